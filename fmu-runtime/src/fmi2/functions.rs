//! Every fmi2 function of `fmi2Functions.h`, once, generic over the model. `export_fmu!` wraps
//! each in an `extern "C"` symbol. Each function:
//! 1. turns the component pointer into an instance (null -> fmi2Error),
//! 2. checks the call against FMI 2.0's state table (`states`) -> fmi2Error with the allowed modes,
//! 3. turns C arrays into slices (null with n > 0 -> fmi2Error),
//! 4. runs the safe body inside `catch_unwind`: a panic becomes fmi2Fatal and a logger message,
//!    never an unwind across the C boundary,
//! 5. reports a failure's message through the logger and returns its status.
#![allow(clippy::missing_safety_doc, clippy::too_many_arguments, non_upper_case_globals)]

use std::os::raw::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};

use super::log::{fmi2_status, Fmi2Logger};
use super::states::Function;
use super::types::*;
use crate::boundary::{c_str, checked, handle, no_string, null, panic_message, slice, slice_mut, Component};
use crate::exported::Exported;
use crate::instance::{FmiValue, Instance, Interface};
use crate::log::Logger;
use crate::model::Model;
use crate::status::{CallResult, Failure, Status};

/// Runs `body` on the instance behind `c` if `function` is legal in its phase.
unsafe fn with<M: Model>(c: fmi2Component, function: Function, name: &str, body: impl FnOnce(&mut Component<M>) -> CallResult) -> fmi2Status {
    checked::<M, Function>(c, function, name, body).map_or(fmi2Error, fmi2_status)
}

pub fn get_types_platform() -> *const c_char {
    TYPES_PLATFORM.as_ptr()
}

pub fn get_version() -> *const c_char {
    VERSION.as_ptr()
}

pub unsafe fn instantiate<M: Model>(
    exported: &'static Exported<M>,
    instance_name: fmi2String,
    fmu_type: fmi2Type,
    guid: fmi2String,
    _resource_location: fmi2String,
    callbacks: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    logging_on: fmi2Boolean,
) -> fmi2Component {
    let Some(callbacks) = callbacks.as_ref() else {
        return std::ptr::null_mut();
    };
    let name = c_str(instance_name).unwrap_or("");
    let sink = || Fmi2Logger::sink(callbacks.logger, callbacks.componentEnvironment, if name.is_empty() { "?" } else { name });
    let logger = Logger::new(sink(), logging_on != 0);
    let fail = |msg: String| {
        logger.log(Status::Error, &format!("fmi2Instantiate: {msg}"));
        std::ptr::null_mut()
    };
    if name.is_empty() {
        return fail("the instance name is null or empty".into());
    }
    if let Some(problems) = &exported.instantiation_problems {
        return fail(format!("the model is not valid: {problems}"));
    }
    let interface = match fmu_type {
        fmi2CoSimulation => Interface::CoSimulation,
        fmi2ModelExchange => Interface::ModelExchange,
        other => return fail(format!("fmuType {other} is neither fmi2ModelExchange (0) nor fmi2CoSimulation (1)")),
    };
    // The guid's first half, the hash of the description without its dependency lists: the
    // binary knows it without probing its equations (docs/DESIGN.md).
    let Ok(check) = catch_unwind(AssertUnwindSafe(|| exported.token_check(crate::standards::Standard::Fmi2))) else {
        return fail("internal error (panic) writing the description to check the token".into());
    };
    match c_str(guid) {
        Some(g) if check.accepts(g) => {}
        Some(g) => return fail(format!("guid {g} does not match this FMU's guid {}: modelDescription.xml and binary differ", check.shown())),
        None => return fail("guid is null or not UTF-8".into()),
    }
    match catch_unwind(AssertUnwindSafe(|| Instance::<M>::shared(interface, check.shown(), logger, &exported.declared))) {
        Ok(instance) => Component::into_raw(instance),
        Err(payload) => {
            // The logger moved into the closure; build a fresh one to report.
            let logger = Logger::new(sink(), true);
            logger.log(Status::Fatal, &format!("fmi2Instantiate: internal error (panic): {}", panic_message(&*payload)));
            std::ptr::null_mut()
        }
    }
}

pub unsafe fn free_instance<M: Model>(c: fmi2Component) {
    Component::<M>::free(c)
}

pub unsafe fn set_debug_logging<M: Model>(c: fmi2Component, on: fmi2Boolean, n: usize, categories: *const fmi2String) -> fmi2Status {
    with::<M>(c, Function::SetDebugLogging, "fmi2SetDebugLogging", |comp| {
        let cats = slice(categories, n).ok_or_else(|| null("categories"))?;
        let mut names = Vec::with_capacity(n);
        for p in cats {
            names.push(c_str(*p).ok_or_else(|| Failure::error("a category name is null or not UTF-8"))?.to_string());
        }
        comp.instance.set_debug_logging(on != 0, &names)
    })
}

pub unsafe fn setup_experiment<M: Model>(
    c: fmi2Component,
    tolerance_defined: fmi2Boolean,
    tolerance: fmi2Real,
    start_time: fmi2Real,
    stop_time_defined: fmi2Boolean,
    stop_time: fmi2Real,
) -> fmi2Status {
    with::<M>(c, Function::SetupExperiment, "fmi2SetupExperiment", |comp| {
        comp.instance.setup_experiment(
            (tolerance_defined != 0).then_some(tolerance),
            start_time,
            (stop_time_defined != 0).then_some(stop_time),
        )
    })
}

pub unsafe fn enter_initialization_mode<M: Model>(c: fmi2Component) -> fmi2Status {
    with::<M>(c, Function::EnterInitializationMode, "fmi2EnterInitializationMode", |comp| comp.instance.enter_initialization_mode())
}

pub unsafe fn exit_initialization_mode<M: Model>(c: fmi2Component) -> fmi2Status {
    with::<M>(c, Function::ExitInitializationMode, "fmi2ExitInitializationMode", |comp| comp.instance.exit_initialization_mode())
}

pub unsafe fn terminate<M: Model>(c: fmi2Component) -> fmi2Status {
    with::<M>(c, Function::Terminate, "fmi2Terminate", |comp| comp.instance.terminate())
}

pub unsafe fn reset<M: Model>(c: fmi2Component) -> fmi2Status {
    with::<M>(c, Function::Reset, "fmi2Reset", |comp| comp.instance.reset())
}

unsafe fn get_values<M: Model, T: FmiValue>(c: fmi2Component, name: &str, vr: *const fmi2ValueReference, n: usize, out: *mut T) -> fmi2Status {
    with::<M>(c, Function::Get, name, |comp| {
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        let out = slice_mut(out, n).ok_or_else(|| null("the value array"))?;
        comp.instance.get(vrs, out)
    })
}

unsafe fn set_values<M: Model, T: FmiValue>(c: fmi2Component, function: Function, name: &str, vr: *const fmi2ValueReference, n: usize, vals: &[T]) -> fmi2Status {
    with::<M>(c, function, name, |comp| {
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        comp.instance.set(vrs, vals)
    })
}

pub unsafe fn get_real<M: Model>(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, value: *mut fmi2Real) -> fmi2Status {
    get_values::<M, f64>(c, "fmi2GetReal", vr, n, value)
}

pub unsafe fn get_integer<M: Model>(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, value: *mut fmi2Integer) -> fmi2Status {
    get_values::<M, i32>(c, "fmi2GetInteger", vr, n, value)
}

pub unsafe fn get_boolean<M: Model>(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, value: *mut fmi2Boolean) -> fmi2Status {
    let mut bools = vec![false; if value.is_null() { 0 } else { n }];
    let status = get_values::<M, bool>(c, "fmi2GetBoolean", vr, n, if value.is_null() { std::ptr::null_mut() } else { bools.as_mut_ptr() });
    if status == fmi2OK {
        if let Some(out) = slice_mut(value, n) {
            out.iter_mut().zip(&bools).for_each(|(o, b)| *o = *b as fmi2Boolean);
        }
    }
    status
}

pub unsafe fn get_string<M: Model>(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, value: *mut fmi2String) -> fmi2Status {
    with::<M>(c, Function::Get, "fmi2GetString", |comp| {
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        slice_mut(value, n).ok_or_else(|| null("the value array"))?;
        match vrs.first() {
            None => Ok(()),
            Some(vr) => Err(Failure::error(no_string(comp.instance.table(), *vr))),
        }
    })
}


pub unsafe fn set_real<M: Model>(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, value: *const fmi2Real) -> fmi2Status {
    match slice(value, n) {
        Some(vals) => set_values::<M, f64>(c, Function::Set, "fmi2SetReal", vr, n, vals),
        None => with::<M>(c, Function::Set, "fmi2SetReal", |_| Err(null("the value array"))),
    }
}

pub unsafe fn set_integer<M: Model>(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, value: *const fmi2Integer) -> fmi2Status {
    match slice(value, n) {
        Some(vals) => set_values::<M, i32>(c, Function::SetDiscrete, "fmi2SetInteger", vr, n, vals),
        None => with::<M>(c, Function::SetDiscrete, "fmi2SetInteger", |_| Err(null("the value array"))),
    }
}

pub unsafe fn set_boolean<M: Model>(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, value: *const fmi2Boolean) -> fmi2Status {
    match slice(value, n) {
        Some(vals) => {
            let bools: Vec<bool> = vals.iter().map(|b| *b != 0).collect();
            set_values::<M, bool>(c, Function::SetDiscrete, "fmi2SetBoolean", vr, n, &bools)
        }
        None => with::<M>(c, Function::SetDiscrete, "fmi2SetBoolean", |_| Err(null("the value array"))),
    }
}

pub unsafe fn set_string<M: Model>(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, value: *const fmi2String) -> fmi2Status {
    with::<M>(c, Function::SetDiscrete, "fmi2SetString", |comp| {
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        slice(value, n).ok_or_else(|| null("the value array"))?;
        match vrs.first() {
            None => Ok(()),
            Some(vr) => Err(Failure::error(no_string(comp.instance.table(), *vr))),
        }
    })
}

pub unsafe fn get_fmu_state<M: Model>(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    with::<M>(c, Function::FmuState, "fmi2GetFMUstate", |comp| {
        let state = state.as_mut().ok_or_else(|| null("the FMUstate pointer"))?;
        let h = comp.get_fmu_state(handle(*state))?;
        *state = h as fmi2FMUstate;
        Ok(())
    })
}

pub unsafe fn set_fmu_state<M: Model>(c: fmi2Component, state: fmi2FMUstate) -> fmi2Status {
    with::<M>(c, Function::FmuState, "fmi2SetFMUstate", |comp| {
        let h = handle(state).ok_or_else(|| null("the FMUstate"))?;
        comp.instance.set_fmu_state(h)
    })
}

pub unsafe fn free_fmu_state<M: Model>(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    with::<M>(c, Function::FmuState, "fmi2FreeFMUstate", |comp| {
        let Some(state) = state.as_mut() else {
            return Err(null("the FMUstate pointer"));
        };
        // FMI 2.0: freeing a null FMUstate is ignored.
        let Some(h) = handle(*state) else { return Ok(()) };
        comp.instance.free_fmu_state(h)?;
        *state = std::ptr::null_mut();
        Ok(())
    })
}

pub unsafe fn serialized_fmu_state_size<M: Model>(c: fmi2Component, state: fmi2FMUstate, size: *mut usize) -> fmi2Status {
    with::<M>(c, Function::FmuState, "fmi2SerializedFMUstateSize", |comp| {
        let size = size.as_mut().ok_or_else(|| null("the size pointer"))?;
        let h = handle(state).ok_or_else(|| null("the FMUstate"))?;
        *size = comp.serialized_size(h)?;
        Ok(())
    })
}

pub unsafe fn serialize_fmu_state<M: Model>(c: fmi2Component, state: fmi2FMUstate, out: *mut fmi2Byte, size: usize) -> fmi2Status {
    with::<M>(c, Function::FmuState, "fmi2SerializeFMUstate", |comp| {
        let h = handle(state).ok_or_else(|| null("the FMUstate"))?;
        comp.serialize_into(h, slice_mut(out as *mut u8, size), size)
    })
}

pub unsafe fn deserialize_fmu_state<M: Model>(c: fmi2Component, bytes: *const fmi2Byte, size: usize, state: *mut fmi2FMUstate) -> fmi2Status {
    with::<M>(c, Function::FmuState, "fmi2DeSerializeFMUstate", |comp| {
        let bytes = slice(bytes as *const u8, size).ok_or_else(|| null("the byte buffer"))?;
        let state = state.as_mut().ok_or_else(|| null("the FMUstate pointer"))?;
        let h = comp.instance.deserialize_fmu_state(bytes, handle(*state))?;
        *state = h as fmi2FMUstate;
        Ok(())
    })
}

pub unsafe fn get_directional_derivative<M: Model>(
    c: fmi2Component,
    unknowns: *const fmi2ValueReference,
    n_unknowns: usize,
    knowns: *const fmi2ValueReference,
    n_knowns: usize,
    dv_known: *const fmi2Real,
    dv_unknown: *mut fmi2Real,
) -> fmi2Status {
    with::<M>(c, Function::GetDirectionalDerivative, "fmi2GetDirectionalDerivative", |comp| {
        let unknowns = slice(unknowns, n_unknowns).ok_or_else(|| null("the unknowns' value references"))?;
        let knowns = slice(knowns, n_knowns).ok_or_else(|| null("the knowns' value references"))?;
        let dv_known = slice(dv_known, n_knowns).ok_or_else(|| null("the knowns' seed"))?;
        let dv_unknown = slice_mut(dv_unknown, n_unknowns).ok_or_else(|| null("the unknowns' array"))?;
        comp.instance.directional_derivative(unknowns, knowns, dv_known, dv_unknown)
    })
}

pub unsafe fn set_real_input_derivatives<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    order: *const fmi2Integer,
    value: *const fmi2Real,
) -> fmi2Status {
    with::<M>(c, Function::SetRealInputDerivatives, "fmi2SetRealInputDerivatives", |comp| {
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        let orders = slice(order, n).ok_or_else(|| null("the order array"))?;
        let values = slice(value, n).ok_or_else(|| null("the value array"))?;
        comp.instance.set_input_derivatives(vrs, orders, values)
    })
}

pub unsafe fn get_real_output_derivatives<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    order: *const fmi2Integer,
    value: *mut fmi2Real,
) -> fmi2Status {
    with::<M>(c, Function::GetRealOutputDerivatives, "fmi2GetRealOutputDerivatives", |comp| {
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        let orders = slice(order, n).ok_or_else(|| null("the order array"))?;
        let out = slice_mut(value, n).ok_or_else(|| null("the value array"))?;
        comp.instance.output_derivatives(vrs, orders, out)
    })
}

pub unsafe fn do_step<M: Model>(c: fmi2Component, t: fmi2Real, h: fmi2Real, _no_set_prior: fmi2Boolean) -> fmi2Status {
    // FMI 2.0 has no event mode in Co-Simulation: every step reaches its end.
    with::<M>(c, Function::DoStep, "fmi2DoStep", |comp| comp.instance.do_step(t, h).map(|_| ()))
}

pub unsafe fn cancel_step<M: Model>(c: fmi2Component) -> fmi2Status {
    // fmi2DoStep never returns fmi2Pending, so the state table refuses this in every mode.
    with::<M>(c, Function::CancelStep, "fmi2CancelStep", |_| Ok(()))
}

unsafe fn status_of<M: Model, T>(
    c: fmi2Component,
    name: &str,
    kind: fmi2StatusKind,
    value: *mut T,
    read: impl FnOnce(&Instance<M>, fmi2StatusKind) -> CallResult<T>,
) -> fmi2Status {
    with::<M>(c, Function::GetStatus, name, |comp| {
        let out = value.as_mut().ok_or_else(|| null("the value pointer"))?;
        *out = read(&comp.instance, kind)?;
        Ok(())
    })
}

/// FMI 2.0, section 2.1.3: a co-simulation slave that cannot provide a status returns fmi2Discard.
fn no_status(kind: fmi2StatusKind, ty: &str) -> Failure {
    let what = match kind {
        fmi2DoStepStatus | fmi2PendingStatus => "there is never an asynchronous step in progress (fmi2DoStep never returns fmi2Pending)",
        _ => "this status kind has no value of this type",
    };
    Failure::discard(format!("status kind {kind} as {ty} is not available: {what}"))
}

pub unsafe fn get_status<M: Model>(c: fmi2Component, kind: fmi2StatusKind, value: *mut fmi2Status) -> fmi2Status {
    status_of::<M, fmi2Status>(c, "fmi2GetStatus", kind, value, |_, k| Err(no_status(k, "fmi2Status")))
}

pub unsafe fn get_real_status<M: Model>(c: fmi2Component, kind: fmi2StatusKind, value: *mut fmi2Real) -> fmi2Status {
    status_of::<M, fmi2Real>(c, "fmi2GetRealStatus", kind, value, |inst, k| match k {
        fmi2LastSuccessfulTime => Ok(inst.last_successful_time()),
        _ => Err(no_status(k, "Real")),
    })
}

pub unsafe fn get_integer_status<M: Model>(c: fmi2Component, kind: fmi2StatusKind, value: *mut fmi2Integer) -> fmi2Status {
    status_of::<M, fmi2Integer>(c, "fmi2GetIntegerStatus", kind, value, |_, k| Err(no_status(k, "Integer")))
}

pub unsafe fn get_boolean_status<M: Model>(c: fmi2Component, kind: fmi2StatusKind, value: *mut fmi2Boolean) -> fmi2Status {
    status_of::<M, fmi2Boolean>(c, "fmi2GetBooleanStatus", kind, value, |_, k| match k {
        // The slave never asks to end the simulation on its own.
        fmi2Terminated => Ok(fmi2False),
        _ => Err(no_status(k, "Boolean")),
    })
}

pub unsafe fn get_string_status<M: Model>(c: fmi2Component, kind: fmi2StatusKind, value: *mut fmi2String) -> fmi2Status {
    status_of::<M, fmi2String>(c, "fmi2GetStringStatus", kind, value, |_, k| Err(no_status(k, "String")))
}

// ---- Model Exchange ----------------------------------------------------------------------

pub unsafe fn enter_event_mode<M: Model>(c: fmi2Component) -> fmi2Status {
    with::<M>(c, Function::EnterEventMode, "fmi2EnterEventMode", |comp| comp.instance.enter_event_mode())
}

pub unsafe fn new_discrete_states<M: Model>(c: fmi2Component, info: *mut fmi2EventInfo) -> fmi2Status {
    with::<M>(c, Function::NewDiscreteStates, "fmi2NewDiscreteStates", |comp| {
        let info = info.as_mut().ok_or_else(|| null("the event info pointer"))?;
        let e = comp.instance.new_discrete_states()?;
        *info = fmi2EventInfo {
            newDiscreteStatesNeeded: e.new_discrete_states_needed as fmi2Boolean,
            terminateSimulation: e.terminate_simulation as fmi2Boolean,
            nominalsOfContinuousStatesChanged: e.nominals_changed as fmi2Boolean,
            valuesOfContinuousStatesChanged: e.values_changed as fmi2Boolean,
            nextEventTimeDefined: e.next_event_time.is_some() as fmi2Boolean,
            nextEventTime: e.next_event_time.unwrap_or(0.0),
        };
        Ok(())
    })
}

pub unsafe fn enter_continuous_time_mode<M: Model>(c: fmi2Component) -> fmi2Status {
    with::<M>(c, Function::EnterContinuousTimeMode, "fmi2EnterContinuousTimeMode", |comp| comp.instance.enter_continuous_time_mode())
}

pub unsafe fn completed_integrator_step<M: Model>(c: fmi2Component, _no_prior: fmi2Boolean, enter: *mut fmi2Boolean, terminate: *mut fmi2Boolean) -> fmi2Status {
    with::<M>(c, Function::CompletedIntegratorStep, "fmi2CompletedIntegratorStep", |comp| {
        let enter = enter.as_mut().ok_or_else(|| null("enterEventMode"))?;
        let terminate = terminate.as_mut().ok_or_else(|| null("terminateSimulation"))?;
        let (e, t) = comp.instance.completed_integrator_step()?;
        *enter = e as fmi2Boolean;
        *terminate = t as fmi2Boolean;
        Ok(())
    })
}

pub unsafe fn set_time<M: Model>(c: fmi2Component, t: fmi2Real) -> fmi2Status {
    with::<M>(c, Function::SetTime, "fmi2SetTime", |comp| comp.instance.set_time(t))
}

pub unsafe fn set_continuous_states<M: Model>(c: fmi2Component, x: *const fmi2Real, n: usize) -> fmi2Status {
    with::<M>(c, Function::SetContinuousStates, "fmi2SetContinuousStates", |comp| {
        let x = slice(x, n).ok_or_else(|| null("the states array"))?;
        comp.instance.set_continuous_states(x)
    })
}

/// The fmi2Get* functions of Model Exchange that fill an array of n reals.
unsafe fn get_array<M: Model>(
    c: fmi2Component,
    function: Function,
    name: &str,
    out: *mut fmi2Real,
    n: usize,
    get: impl FnOnce(&mut Instance<M>, &mut [f64]) -> CallResult,
) -> fmi2Status {
    with::<M>(c, function, name, |comp| {
        let out = slice_mut(out, n).ok_or_else(|| null("the value array"))?;
        get(&mut comp.instance, out)
    })
}

pub unsafe fn get_derivatives<M: Model>(c: fmi2Component, dx: *mut fmi2Real, n: usize) -> fmi2Status {
    get_array::<M>(c, Function::GetDerivatives, "fmi2GetDerivatives", dx, n, |i, out| i.get_derivatives(out))
}

pub unsafe fn get_event_indicators<M: Model>(c: fmi2Component, z: *mut fmi2Real, n: usize) -> fmi2Status {
    get_array::<M>(c, Function::GetEventIndicators, "fmi2GetEventIndicators", z, n, |i, out| i.get_event_indicators(out))
}

pub unsafe fn get_continuous_states<M: Model>(c: fmi2Component, x: *mut fmi2Real, n: usize) -> fmi2Status {
    get_array::<M>(c, Function::GetContinuousStates, "fmi2GetContinuousStates", x, n, |i, out| i.get_continuous_states(out))
}

pub unsafe fn get_nominals_of_continuous_states<M: Model>(c: fmi2Component, x: *mut fmi2Real, n: usize) -> fmi2Status {
    get_array::<M>(c, Function::GetNominalsOfContinuousStates, "fmi2GetNominalsOfContinuousStates", x, n, |i, out| i.get_nominals(out))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_model::Panicky;
    use std::sync::Mutex;

    static LOG: Mutex<Vec<(i32, String)>> = Mutex::new(Vec::new());

    unsafe extern "C" fn record(_: fmi2ComponentEnvironment, _: fmi2String, status: fmi2Status, _: fmi2String, msg: fmi2String) {
        LOG.lock().unwrap().push((status, std::ffi::CStr::from_ptr(msg).to_string_lossy().into_owned()));
    }

    #[test]
    fn a_panic_in_the_model_becomes_fmi2_fatal_and_a_message() {
        let exported: &'static Exported<Panicky> = Box::leak(Box::new(Exported::of()));
        // SAFETY: on x86_64 SysV a non-variadic callee reads the same registers as the variadic
        // type declares; the runtime passes no variadic arguments.
        let logger: fmi2CallbackLogger = unsafe { std::mem::transmute(record as unsafe extern "C" fn(_, _, _, _, _)) };
        let callbacks = fmi2CallbackFunctions {
            logger: Some(logger),
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: std::ptr::null_mut(),
        };
        let guid = std::ffi::CString::new(exported.of_standard(crate::standards::Standard::Fmi2).token.clone()).unwrap();
        unsafe {
            let c = instantiate::<Panicky>(exported, c"p".as_ptr(), fmi2CoSimulation, guid.as_ptr(), std::ptr::null(), &callbacks, 0, 0);
            assert!(!c.is_null());
            assert_eq!(setup_experiment::<Panicky>(c, 0, 0.0, 0.0, 0, 0.0), fmi2OK);
            assert_eq!(enter_initialization_mode::<Panicky>(c), fmi2OK);
            assert_eq!(exit_initialization_mode::<Panicky>(c), fmi2OK);
            assert_eq!(do_step::<Panicky>(c, 0.0, 0.1, 1), fmi2OK);
            let (vr, u) = ([0u32], [-1.0]);
            assert_eq!(set_real::<Panicky>(c, vr.as_ptr(), 1, u.as_ptr()), fmi2OK);
            assert_eq!(do_step::<Panicky>(c, 0.1, 0.1, 1), fmi2Fatal);
            assert!(LOG.lock().unwrap().iter().any(|(s, m)| *s == fmi2Fatal && m.contains("negative input")));
            assert_eq!(do_step::<Panicky>(c, 0.1, 0.1, 1), fmi2Fatal, "a fatal instance stays fatal");
            free_instance::<Panicky>(c);
        }
    }
}
