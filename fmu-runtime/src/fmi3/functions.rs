//! Every fmi3 function of `fmi3Functions.h`, once, generic over the model. `export_fmi3!` wraps
//! each in an `extern "C"` symbol. Each function turns the instance pointer into an instance
//! (null -> fmi3Error), checks the call against FMI 3.0's state table (`states`), turns C arrays
//! into slices, runs the safe body inside `catch_unwind` (`boundary::guarded`: a panic becomes
//! fmi3Fatal and a logger message), and reports a failure's message through the logger.
//!
//! The FMI 3.0 description adds two kinds of variables to the model's table, after its value
//! references: one Float64 per event indicator (ModelStructure `EventIndicator` names a
//! variable in FMI 3.0), and the independent variable `time`. fmi3GetFloat64 reads them here.
#![allow(clippy::missing_safety_doc, clippy::too_many_arguments)]

use std::panic::{catch_unwind, AssertUnwindSafe};

use super::log::{fmi3_status, Fmi3Logger};
use super::states::Function;
use super::types::*;
use crate::boundary::{c_str, checked, guarded, handle, no_string, null, panic_message, slice, slice_mut, Component, Refusal};
use crate::exported::Exported;
use crate::instance::{FmiValue, Instance, Interface};
use crate::log::Logger;
use crate::model::Model;
use crate::status::{CallResult, Failure, Status};
use crate::variables::VariableTable;

/// Runs `body` on the instance behind `c` if `function` is legal in its phase.
unsafe fn with<M: Model>(c: fmi3Instance, function: Function, name: &str, body: impl FnOnce(&mut Component<M>) -> CallResult) -> fmi3Status {
    checked::<M, Function>(c, function, name, body).map_or(fmi3Error, fmi3_status)
}

/// A function this FMU does not provide (no clocks, no configuration mode, no scheduled
/// execution, no per-element dependencies): fmi3Error with a message saying why.
unsafe fn unsupported<M: Model>(c: fmi3Instance, name: &str, why: &str) -> fmi3Status {
    let refuse = |_: &Instance<M>| Err(Refusal { status: Status::Error, message: format!("is not supported: {why}") });
    guarded::<M>(c, name, refuse, |_| Ok(())).map_or(fmi3Error, fmi3_status)
}

/// The variables the FMI 3.0 description adds after the model's table.
pub struct Extra {
    /// The first event indicator's value reference (one per indicator, in declaration order).
    pub first_indicator: u32,
    /// The independent variable `time`.
    pub time: u32,
}

impl Extra {
    pub fn of(table: &VariableTable) -> Extra {
        let first_indicator = table.variables.len() as u32;
        Extra { first_indicator, time: first_indicator + table.indicators.len() as u32 }
    }

    /// The name of an added variable, if `vr` is one.
    pub fn name(&self, table: &VariableTable, vr: u32) -> Option<String> {
        match vr {
            v if v == self.time => Some("time".into()),
            v if (self.first_indicator..self.time).contains(&v) => {
                Some(format!("event_indicator.{}", table.indicators[(v - self.first_indicator) as usize].0))
            }
            _ => None,
        }
    }
}

/// Refuses the description's added variables (time, the event indicators) where only the
/// model's own variables can go, naming them: they are read with fmi3GetFloat64 only (time is
/// set with fmi3SetTime or by stepping; this FMU gives no partial derivatives of event
/// indicators).
fn model_variables_only(table: &VariableTable, vrs: &[u32], what: &str) -> CallResult {
    let extra = Extra::of(table);
    match vrs.iter().find_map(|vr| extra.name(table, *vr)) {
        Some(name) => Err(Failure::error(format!(
            "'{name}' cannot be {what}: the FMI 3.0 description adds it to read it with fmi3GetFloat64 only"
        ))),
        None => Ok(()),
    }
}

pub fn get_version() -> *const std::os::raw::c_char {
    VERSION.as_ptr()
}

/// fmi3InstantiateModelExchange and fmi3InstantiateCoSimulation.
pub unsafe fn instantiate<M: Model>(
    exported: &'static Exported<M>,
    interface: Interface,
    instance_name: fmi3String,
    token: fmi3String,
    environment: fmi3InstanceEnvironment,
    logging_on: bool,
    log_message: Option<fmi3LogMessageCallback>,
    (event_mode_used, early_return_allowed): (bool, bool),
) -> fmi3Instance {
    let name = c_str(instance_name).unwrap_or("");
    let logger = Logger::new(Fmi3Logger::sink(log_message, environment), logging_on);
    let function = match interface {
        Interface::CoSimulation => "fmi3InstantiateCoSimulation",
        Interface::ModelExchange => "fmi3InstantiateModelExchange",
    };
    let fail = |msg: String| {
        logger.log(Status::Error, &format!("{function}: {msg}"));
        std::ptr::null_mut()
    };
    if name.is_empty() {
        return fail("the instance name is null or empty".into());
    }
    if let Some(problems) = &exported.instantiation_problems {
        return fail(format!("the model is not valid: {problems}"));
    }
    // The token's first half, the hash of the description without its dependency lists: the
    // binary knows it without probing its equations (docs/DESIGN.md).
    let Ok(check) = catch_unwind(AssertUnwindSafe(|| exported.token_check(crate::standards::Standard::Fmi3))) else {
        return fail("internal error (panic) writing the description to check the token".into());
    };
    match c_str(token) {
        Some(t) if check.accepts(t) => {}
        Some(t) => {
            return fail(format!("instantiationToken {t} does not match this FMU's {}: modelDescription.xml and binary differ", check.shown()))
        }
        None => return fail("instantiationToken is null or not UTF-8".into()),
    }
    let made = || {
        let mut instance = Instance::<M>::shared(interface, check.shown(), logger, &exported.declared);
        instance.hand_events_to_master(event_mode_used, early_return_allowed);
        instance
    };
    match catch_unwind(AssertUnwindSafe(made)) {
        Ok(instance) => Component::into_raw(instance),
        Err(payload) => {
            let logger = Logger::new(Fmi3Logger::sink(log_message, environment), true);
            logger.log(Status::Fatal, &format!("{function}: internal error (panic): {}", panic_message(&*payload)));
            std::ptr::null_mut()
        }
    }
}

/// fmi3InstantiateScheduledExecution: this FMU has no clocks, so no Scheduled Execution.
pub unsafe fn instantiate_scheduled_execution(environment: fmi3InstanceEnvironment, log_message: Option<fmi3LogMessageCallback>) -> fmi3Instance {
    let logger = Logger::new(Fmi3Logger::sink(log_message, environment), false);
    logger.log(Status::Error, "fmi3InstantiateScheduledExecution: this FMU provides Model Exchange and Co-Simulation, not Scheduled Execution");
    std::ptr::null_mut()
}

pub unsafe fn free_instance<M: Model>(c: fmi3Instance) {
    Component::<M>::free(c)
}

pub unsafe fn set_debug_logging<M: Model>(c: fmi3Instance, on: fmi3BooleanIn, n: usize, categories: *const fmi3String) -> fmi3Status {
    with::<M>(c, Function::SetDebugLogging, "fmi3SetDebugLogging", |comp| {
        let cats = slice(categories, n).ok_or_else(|| null("categories"))?;
        let mut names = Vec::with_capacity(n);
        for p in cats {
            names.push(c_str(*p).ok_or_else(|| Failure::error("a category name is null or not UTF-8"))?.to_string());
        }
        comp.instance.set_debug_logging(on != 0, &names)
    })
}

pub unsafe fn enter_initialization_mode<M: Model>(
    c: fmi3Instance,
    tolerance_defined: fmi3BooleanIn,
    tolerance: fmi3Float64,
    start_time: fmi3Float64,
    stop_time_defined: fmi3BooleanIn,
    stop_time: fmi3Float64,
) -> fmi3Status {
    with::<M>(c, Function::EnterInitializationMode, "fmi3EnterInitializationMode", |comp| {
        comp.instance.setup_experiment((tolerance_defined != 0).then_some(tolerance), start_time, (stop_time_defined != 0).then_some(stop_time))?;
        comp.instance.enter_initialization_mode()
    })
}

pub unsafe fn exit_initialization_mode<M: Model>(c: fmi3Instance) -> fmi3Status {
    with::<M>(c, Function::ExitInitializationMode, "fmi3ExitInitializationMode", |comp| comp.instance.exit_initialization_mode())
}

pub unsafe fn terminate<M: Model>(c: fmi3Instance) -> fmi3Status {
    with::<M>(c, Function::Terminate, "fmi3Terminate", |comp| comp.instance.terminate())
}

pub unsafe fn reset<M: Model>(c: fmi3Instance) -> fmi3Status {
    with::<M>(c, Function::Reset, "fmi3Reset", |comp| comp.instance.reset())
}

/// The value references and the values array of a get or set: FMI 3.0 passes both lengths,
/// which must agree for scalar variables (this FMU has no arrays).
fn scalar_count(n_vrs: usize, n_values: usize) -> CallResult {
    if n_vrs != n_values {
        return Err(Failure::error(format!("{n_vrs} value references but {n_values} values: this FMU's variables are all scalars")));
    }
    Ok(())
}

unsafe fn get_values<M: Model, T: FmiValue>(c: fmi3Instance, name: &str, vr: *const fmi3ValueReference, n: usize, out: *mut T, n_values: usize) -> fmi3Status {
    with::<M>(c, Function::Get, name, |comp| {
        scalar_count(n, n_values)?;
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        let out = slice_mut(out, n).ok_or_else(|| null("the value array"))?;
        comp.instance.get(vrs, out)
    })
}

unsafe fn set_values<M: Model, T: FmiValue>(c: fmi3Instance, name: &str, vr: *const fmi3ValueReference, n: usize, vals: Option<&[T]>, n_values: usize) -> fmi3Status {
    with::<M>(c, Function::Set, name, |comp| {
        scalar_count(n, n_values)?;
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        model_variables_only(comp.instance.table(), vrs, "set")?;
        comp.instance.set(vrs, vals.ok_or_else(|| null("the value array"))?)
    })
}

/// fmi3GetFloat64: the model's reals, and the description's event indicators and time.
pub unsafe fn get_float64<M: Model>(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, value: *mut fmi3Float64, n_values: usize) -> fmi3Status {
    with::<M>(c, Function::Get, "fmi3GetFloat64", |comp| {
        scalar_count(n, n_values)?;
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        let out = slice_mut(value, n).ok_or_else(|| null("the value array"))?;
        let extra = Extra::of(comp.instance.table());
        if vrs.iter().all(|v| *v < extra.first_indicator) {
            return comp.instance.get(vrs, out);
        }
        let mut indicators = vec![0.0; comp.instance.table().indicators.len()];
        if vrs.iter().any(|v| (extra.first_indicator..extra.time).contains(v)) {
            comp.instance.get_event_indicators(&mut indicators)?;
        }
        for (v, o) in vrs.iter().zip(out.iter_mut()) {
            *o = match *v {
                v if v < extra.first_indicator => {
                    let mut one = [0.0];
                    comp.instance.get(&[v], &mut one)?;
                    one[0]
                }
                v if v < extra.time => indicators[(v - extra.first_indicator) as usize],
                v if v == extra.time => comp.instance.time(),
                v => return Err(Failure::error(format!("unknown value reference {v} (this FMU's FMI 3.0 description has 0..={})", extra.time))),
            };
        }
        Ok(())
    })
}

/// FMI 3.0 reads and sets an Enumeration with fmi3Get/SetInt64 and an Int32 with fmi3Get/SetInt32;
/// both are Integer values in the core. Refuses a value reference of the other kind.
fn integer_kind(table: &VariableTable, vrs: &[u32], enumeration: bool) -> CallResult {
    model_variables_only(table, vrs, if enumeration { "read or set as an Enumeration" } else { "read or set as an Int32" })?;
    for vr in vrs {
        if let Some(v) = table.get(*vr).filter(|v| v.base_type() == crate::variables::BaseType::Integer) {
            match (v.items.is_empty(), enumeration) {
                (false, false) => return Err(Failure::error(format!("'{}' is an Enumeration: FMI 3.0 reads and sets it with fmi3GetInt64/fmi3SetInt64", v.name))),
                (true, true) => return Err(Failure::error(format!("'{}' is an Int32, not an Enumeration (use fmi3GetInt32/fmi3SetInt32)", v.name))),
                _ => {}
            }
        } else if enumeration {
            return Err(Failure::error(match table.get(*vr) {
                Some(v) => format!("value reference {vr} is the {} variable '{}', not an Enumeration", v.base_type().name(), v.name),
                None => format!("unknown value reference {vr}"),
            }));
        }
    }
    Ok(())
}

pub unsafe fn get_int32<M: Model>(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, value: *mut fmi3Int32, n_values: usize) -> fmi3Status {
    with::<M>(c, Function::Get, "fmi3GetInt32", |comp| {
        scalar_count(n, n_values)?;
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        integer_kind(comp.instance.table(), vrs, false)?;
        comp.instance.get(vrs, slice_mut(value, n).ok_or_else(|| null("the value array"))?)
    })
}

/// fmi3GetInt64: the Enumerations (the model's structural choices).
pub unsafe fn get_int64<M: Model>(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, value: *mut fmi3Int64, n_values: usize) -> fmi3Status {
    with::<M>(c, Function::Get, "fmi3GetInt64", |comp| {
        scalar_count(n, n_values)?;
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        let out = slice_mut(value, n).ok_or_else(|| null("the value array"))?;
        integer_kind(comp.instance.table(), vrs, true)?;
        let mut values = vec![0i32; n];
        comp.instance.get(vrs, &mut values)?;
        out.iter_mut().zip(values).for_each(|(o, v)| *o = v as i64);
        Ok(())
    })
}

/// fmi3SetInt64: the Enumerations; a value outside 32 bits is outside every item's range.
pub unsafe fn set_int64<M: Model>(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, value: *const fmi3Int64, n_values: usize) -> fmi3Status {
    with::<M>(c, Function::Set, "fmi3SetInt64", |comp| {
        scalar_count(n, n_values)?;
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        let values = slice(value, n).ok_or_else(|| null("the value array"))?;
        integer_kind(comp.instance.table(), vrs, true)?;
        let narrow: Vec<i32> = values.iter().map(|v| i32::try_from(*v).unwrap_or(if *v < 0 { i32::MIN } else { i32::MAX })).collect();
        comp.instance.set(vrs, &narrow)
    })
}

pub unsafe fn get_boolean<M: Model>(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, value: *mut fmi3Boolean, n_values: usize) -> fmi3Status {
    get_values::<M, bool>(c, "fmi3GetBoolean", vr, n, value, n_values)
}

pub unsafe fn set_float64<M: Model>(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, value: *const fmi3Float64, n_values: usize) -> fmi3Status {
    set_values::<M, f64>(c, "fmi3SetFloat64", vr, n, slice(value, n), n_values)
}

pub unsafe fn set_int32<M: Model>(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, value: *const fmi3Int32, n_values: usize) -> fmi3Status {
    with::<M>(c, Function::Set, "fmi3SetInt32", |comp| {
        scalar_count(n, n_values)?;
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        integer_kind(comp.instance.table(), vrs, false)?;
        comp.instance.set(vrs, slice(value, n).ok_or_else(|| null("the value array"))?)
    })
}

pub unsafe fn set_boolean<M: Model>(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, value: *const fmi3BooleanIn, n_values: usize) -> fmi3Status {
    let bools: Option<Vec<bool>> = slice(value, n).map(|v| v.iter().map(|b| *b != 0).collect());
    set_values::<M, bool>(c, "fmi3SetBoolean", vr, n, bools.as_deref(), n_values)
}

/// Gets and sets of a type this FMU has no variable of (Float32, the other integer widths,
/// String, Binary, Clock): nothing to do for no value references, else an error naming the
/// variable's real type.
pub unsafe fn no_such_type<M: Model>(c: fmi3Instance, name: &str, type_name: &str, set: bool, vr: *const fmi3ValueReference, n: usize) -> fmi3Status {
    with::<M>(c, if set { Function::Set } else { Function::Get }, name, |comp| {
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        model_variables_only(comp.instance.table(), vrs, &format!("read or set as a {type_name}"))?;
        match vrs.first() {
            None => Ok(()),
            Some(vr) if type_name == "String" => Err(Failure::error(no_string(comp.instance.table(), *vr))),
            Some(vr) => Err(Failure::error(match comp.instance.table().get(*vr) {
                Some(v) => format!("value reference {vr} is the {} variable '{}', not a {type_name} (this FMU has no {type_name} variables)", v.base_type().name(), v.name),
                None => format!("unknown value reference {vr} (this FMU has no {type_name} variables)"),
            })),
        }
    })
}

pub unsafe fn get_fmu_state<M: Model>(c: fmi3Instance, state: *mut fmi3FMUState) -> fmi3Status {
    with::<M>(c, Function::FmuState, "fmi3GetFMUState", |comp| {
        let state = state.as_mut().ok_or_else(|| null("the FMUState pointer"))?;
        *state = comp.get_fmu_state(handle(*state))? as fmi3FMUState;
        Ok(())
    })
}

pub unsafe fn set_fmu_state<M: Model>(c: fmi3Instance, state: fmi3FMUState) -> fmi3Status {
    with::<M>(c, Function::FmuState, "fmi3SetFMUState", |comp| {
        let h = handle(state).ok_or_else(|| null("the FMUState"))?;
        comp.instance.set_fmu_state(h)
    })
}

pub unsafe fn free_fmu_state<M: Model>(c: fmi3Instance, state: *mut fmi3FMUState) -> fmi3Status {
    with::<M>(c, Function::FmuState, "fmi3FreeFMUState", |comp| {
        let state = state.as_mut().ok_or_else(|| null("the FMUState pointer"))?;
        // Freeing a null FMUState is ignored.
        let Some(h) = handle(*state) else { return Ok(()) };
        comp.instance.free_fmu_state(h)?;
        *state = std::ptr::null_mut();
        Ok(())
    })
}

pub unsafe fn serialized_fmu_state_size<M: Model>(c: fmi3Instance, state: fmi3FMUState, size: *mut usize) -> fmi3Status {
    with::<M>(c, Function::FmuState, "fmi3SerializedFMUStateSize", |comp| {
        let size = size.as_mut().ok_or_else(|| null("the size pointer"))?;
        *size = comp.serialized_size(handle(state).ok_or_else(|| null("the FMUState"))?)?;
        Ok(())
    })
}

pub unsafe fn serialize_fmu_state<M: Model>(c: fmi3Instance, state: fmi3FMUState, out: *mut fmi3Byte, size: usize) -> fmi3Status {
    with::<M>(c, Function::FmuState, "fmi3SerializeFMUState", |comp| {
        let h = handle(state).ok_or_else(|| null("the FMUState"))?;
        comp.serialize_into(h, slice_mut(out, size), size)
    })
}

pub unsafe fn deserialize_fmu_state<M: Model>(c: fmi3Instance, bytes: *const fmi3Byte, size: usize, state: *mut fmi3FMUState) -> fmi3Status {
    with::<M>(c, Function::FmuState, "fmi3DeserializeFMUState", |comp| {
        let bytes = slice(bytes, size).ok_or_else(|| null("the byte buffer"))?;
        let state = state.as_mut().ok_or_else(|| null("the FMUState pointer"))?;
        *state = comp.instance.deserialize_fmu_state(bytes, handle(*state))? as fmi3FMUState;
        Ok(())
    })
}

/// What the seed of a partial derivative runs along: the knowns (fmi3GetDirectionalDerivative,
/// sensitivities of the unknowns) or the unknowns (fmi3GetAdjointDerivative, sensitivities of
/// the knowns).
#[derive(Clone, Copy)]
enum Seeded {
    Knowns,
    Unknowns,
}

/// The arrays of a partial-derivative call, checked: the counts agree with what the seed runs
/// along, no pointer is null, and every value reference is one of the model's own variables.
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
unsafe fn derivative_arrays<'a>(
    table: &VariableTable,
    seeded: Seeded,
    unknowns: *const fmi3ValueReference,
    n_unknowns: usize,
    knowns: *const fmi3ValueReference,
    n_knowns: usize,
    seed: *const fmi3Float64,
    n_seed: usize,
    sensitivity: *mut fmi3Float64,
    n_sensitivity: usize,
) -> CallResult<(&'a [u32], &'a [u32], &'a [f64], &'a mut [f64])> {
    let ((n_along, along), (n_sensed, sensed)) = match seeded {
        Seeded::Knowns => ((n_knowns, "knowns"), (n_unknowns, "unknowns")),
        Seeded::Unknowns => ((n_unknowns, "unknowns"), (n_knowns, "knowns")),
    };
    if n_seed != n_along || n_sensitivity != n_sensed {
        return Err(Failure::error(format!(
            "{n_seed} seed values for {n_along} {along} and {n_sensitivity} sensitivities for {n_sensed} {sensed}: they must agree (scalar variables)"
        )));
    }
    let u = slice(unknowns, n_unknowns).ok_or_else(|| null("the unknowns' value references"))?;
    let k = slice(knowns, n_knowns).ok_or_else(|| null("the knowns' value references"))?;
    let s = slice(seed, n_seed).ok_or_else(|| null("the seed"))?;
    let out = slice_mut(sensitivity, n_sensitivity).ok_or_else(|| null("the sensitivity array"))?;
    model_variables_only(table, u, "an unknown of a partial derivative")?;
    model_variables_only(table, k, "a known of a partial derivative")?;
    Ok((u, k, s, out))
}

pub unsafe fn get_directional_derivative<M: Model>(
    c: fmi3Instance,
    unknowns: *const fmi3ValueReference,
    n_unknowns: usize,
    knowns: *const fmi3ValueReference,
    n_knowns: usize,
    seed: *const fmi3Float64,
    n_seed: usize,
    sensitivity: *mut fmi3Float64,
    n_sensitivity: usize,
) -> fmi3Status {
    with::<M>(c, Function::PartialDerivatives, "fmi3GetDirectionalDerivative", |comp| {
        let table = comp.instance.table();
        let (u, k, s, out) = derivative_arrays(table, Seeded::Knowns, unknowns, n_unknowns, knowns, n_knowns, seed, n_seed, sensitivity, n_sensitivity)?;
        comp.instance.directional_derivative(u, k, s, out)
    })
}

/// fmi3GetAdjointDerivative: sensitivity = seed^T J, from the same Jacobian as the directional
/// derivative, one column (one known) at a time.
pub unsafe fn get_adjoint_derivative<M: Model>(
    c: fmi3Instance,
    unknowns: *const fmi3ValueReference,
    n_unknowns: usize,
    knowns: *const fmi3ValueReference,
    n_knowns: usize,
    seed: *const fmi3Float64,
    n_seed: usize,
    sensitivity: *mut fmi3Float64,
    n_sensitivity: usize,
) -> fmi3Status {
    with::<M>(c, Function::PartialDerivatives, "fmi3GetAdjointDerivative", |comp| {
        let table = comp.instance.table();
        let (u, k, s, out) = derivative_arrays(table, Seeded::Unknowns, unknowns, n_unknowns, knowns, n_knowns, seed, n_seed, sensitivity, n_sensitivity)?;
        let (mut direction, mut column) = (vec![0.0; k.len()], vec![0.0; u.len()]);
        for j in 0..k.len() {
            direction.fill(0.0);
            direction[j] = 1.0;
            comp.instance.directional_derivative(u, k, &direction, &mut column)?;
            out[j] = s.iter().zip(&column).map(|(a, b)| a * b).sum();
        }
        Ok(())
    })
}

// ---- Model Exchange ----------------------------------------------------------------------

pub unsafe fn enter_event_mode<M: Model>(c: fmi3Instance) -> fmi3Status {
    with::<M>(c, Function::EnterEventMode, "fmi3EnterEventMode", |comp| comp.instance.enter_event_mode())
}

pub unsafe fn update_discrete_states<M: Model>(
    c: fmi3Instance,
    discrete_states_need_update: *mut fmi3Boolean,
    terminate_simulation: *mut fmi3Boolean,
    nominals_changed: *mut fmi3Boolean,
    values_changed: *mut fmi3Boolean,
    next_event_time_defined: *mut fmi3Boolean,
    next_event_time: *mut fmi3Float64,
) -> fmi3Status {
    with::<M>(c, Function::UpdateDiscreteStates, "fmi3UpdateDiscreteStates", |comp| {
        let need = discrete_states_need_update.as_mut().ok_or_else(|| null("discreteStatesNeedUpdate"))?;
        let terminate = terminate_simulation.as_mut().ok_or_else(|| null("terminateSimulation"))?;
        let nominals = nominals_changed.as_mut().ok_or_else(|| null("nominalsOfContinuousStatesChanged"))?;
        let values = values_changed.as_mut().ok_or_else(|| null("valuesOfContinuousStatesChanged"))?;
        let defined = next_event_time_defined.as_mut().ok_or_else(|| null("nextEventTimeDefined"))?;
        let next = next_event_time.as_mut().ok_or_else(|| null("nextEventTime"))?;
        let e = comp.instance.new_discrete_states()?;
        *need = e.new_discrete_states_needed;
        *terminate = e.terminate_simulation;
        *nominals = e.nominals_changed;
        *values = e.values_changed;
        *defined = e.next_event_time.is_some();
        *next = e.next_event_time.unwrap_or(0.0);
        Ok(())
    })
}

pub unsafe fn enter_continuous_time_mode<M: Model>(c: fmi3Instance) -> fmi3Status {
    with::<M>(c, Function::EnterContinuousTimeMode, "fmi3EnterContinuousTimeMode", |comp| comp.instance.enter_continuous_time_mode())
}

pub unsafe fn completed_integrator_step<M: Model>(c: fmi3Instance, _no_prior: fmi3BooleanIn, enter: *mut fmi3Boolean, terminate: *mut fmi3Boolean) -> fmi3Status {
    with::<M>(c, Function::CompletedIntegratorStep, "fmi3CompletedIntegratorStep", |comp| {
        let enter = enter.as_mut().ok_or_else(|| null("enterEventMode"))?;
        let terminate = terminate.as_mut().ok_or_else(|| null("terminateSimulation"))?;
        (*enter, *terminate) = comp.instance.completed_integrator_step()?;
        Ok(())
    })
}

pub unsafe fn set_time<M: Model>(c: fmi3Instance, t: fmi3Float64) -> fmi3Status {
    with::<M>(c, Function::SetTime, "fmi3SetTime", |comp| comp.instance.set_time(t))
}

pub unsafe fn set_continuous_states<M: Model>(c: fmi3Instance, x: *const fmi3Float64, n: usize) -> fmi3Status {
    with::<M>(c, Function::SetContinuousStates, "fmi3SetContinuousStates", |comp| {
        comp.instance.set_continuous_states(slice(x, n).ok_or_else(|| null("the states array"))?)
    })
}

/// The fmi3Get* functions of Model Exchange that fill an array of n reals.
unsafe fn get_array<M: Model>(
    c: fmi3Instance,
    function: Function,
    name: &str,
    out: *mut fmi3Float64,
    n: usize,
    get: impl FnOnce(&mut Instance<M>, &mut [f64]) -> CallResult,
) -> fmi3Status {
    with::<M>(c, function, name, |comp| get(&mut comp.instance, slice_mut(out, n).ok_or_else(|| null("the value array"))?))
}

pub unsafe fn get_continuous_state_derivatives<M: Model>(c: fmi3Instance, dx: *mut fmi3Float64, n: usize) -> fmi3Status {
    get_array::<M>(c, Function::GetContinuousStateDerivatives, "fmi3GetContinuousStateDerivatives", dx, n, |i, out| i.get_derivatives(out))
}

pub unsafe fn get_event_indicators<M: Model>(c: fmi3Instance, z: *mut fmi3Float64, n: usize) -> fmi3Status {
    get_array::<M>(c, Function::GetEventIndicators, "fmi3GetEventIndicators", z, n, |i, out| i.get_event_indicators(out))
}

pub unsafe fn get_continuous_states<M: Model>(c: fmi3Instance, x: *mut fmi3Float64, n: usize) -> fmi3Status {
    get_array::<M>(c, Function::GetContinuousStates, "fmi3GetContinuousStates", x, n, |i, out| i.get_continuous_states(out))
}

pub unsafe fn get_nominals_of_continuous_states<M: Model>(c: fmi3Instance, x: *mut fmi3Float64, n: usize) -> fmi3Status {
    get_array::<M>(c, Function::GetNominalsOfContinuousStates, "fmi3GetNominalsOfContinuousStates", x, n, |i, out| i.get_nominals(out))
}

unsafe fn count<M: Model>(c: fmi3Instance, name: &str, n: *mut usize, of: fn(&VariableTable) -> usize) -> fmi3Status {
    with::<M>(c, Function::Counts, name, |comp| {
        *n.as_mut().ok_or_else(|| null("the count pointer"))? = of(comp.instance.table());
        Ok(())
    })
}

pub unsafe fn get_number_of_event_indicators<M: Model>(c: fmi3Instance, n: *mut usize) -> fmi3Status {
    count::<M>(c, "fmi3GetNumberOfEventIndicators", n, |t| t.indicators.len())
}

pub unsafe fn get_number_of_continuous_states<M: Model>(c: fmi3Instance, n: *mut usize) -> fmi3Status {
    count::<M>(c, "fmi3GetNumberOfContinuousStates", n, |t| t.n_states)
}

// ---- Co-Simulation -------------------------------------------------------------------------

pub unsafe fn get_output_derivatives<M: Model>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    n: usize,
    orders: *const fmi3Int32,
    values: *mut fmi3Float64,
    n_values: usize,
) -> fmi3Status {
    with::<M>(c, Function::GetOutputDerivatives, "fmi3GetOutputDerivatives", |comp| {
        scalar_count(n, n_values)?;
        let vrs = slice(vr, n).ok_or_else(|| null("the value reference array"))?;
        let orders = slice(orders, n).ok_or_else(|| null("the order array"))?;
        let out = slice_mut(values, n).ok_or_else(|| null("the value array"))?;
        comp.instance.output_derivatives(vrs, orders, out)
    })
}

/// fmi3DoStep. With eventModeUsed and earlyReturnAllowed the step returns early at the first
/// event inside it (eventHandlingNeeded, earlyReturn, lastSuccessfulTime the event's time), or
/// asks for event handling at its end when a time event falls there; otherwise the events are
/// handled inside the step. It never ends the simulation; lastSuccessfulTime is the time
/// reached, or the step's start when the step is discarded.
pub unsafe fn do_step<M: Model>(
    c: fmi3Instance,
    t: fmi3Float64,
    h: fmi3Float64,
    _no_prior: fmi3BooleanIn,
    event_handling_needed: *mut fmi3Boolean,
    terminate_simulation: *mut fmi3Boolean,
    early_return: *mut fmi3Boolean,
    last_successful_time: *mut fmi3Float64,
) -> fmi3Status {
    with::<M>(c, Function::DoStep, "fmi3DoStep", |comp| {
        let event = event_handling_needed.as_mut().ok_or_else(|| null("eventHandlingNeeded"))?;
        let terminate = terminate_simulation.as_mut().ok_or_else(|| null("terminateSimulation"))?;
        let early = early_return.as_mut().ok_or_else(|| null("earlyReturn"))?;
        let last = last_successful_time.as_mut().ok_or_else(|| null("lastSuccessfulTime"))?;
        (*event, *terminate, *early) = (false, false, false);
        let result = comp.instance.do_step(t, h);
        *last = comp.instance.time();
        let end = result?;
        *event = end.event;
        *early = end.time < t + h;
        Ok(())
    })
}

/// fmi3EnterStepMode: from Event Mode back to stepping (Co-Simulation with eventModeUsed).
pub unsafe fn enter_step_mode<M: Model>(c: fmi3Instance) -> fmi3Status {
    with::<M>(c, Function::EnterStepMode, "fmi3EnterStepMode", |comp| comp.instance.enter_step_mode())
}

// ---- What this FMU does not provide ----------------------------------------------------------

pub const NO_CLOCKS: &str = "this FMU has no clocks";
pub const NO_STRUCTURAL_PARAMETERS: &str = "this FMU has no structural parameters (providing them is left to its parameters before initialization)";
pub const NO_EVALUATE: &str = "providesEvaluateDiscreteStates = false";
pub const NO_PER_ELEMENT: &str = "providesPerElementDependencies = false: read the dependencies from modelDescription.xml's ModelStructure";
pub const NO_PARTITIONS: &str = "this FMU provides no Scheduled Execution";

pub unsafe fn not_provided<M: Model>(c: fmi3Instance, name: &str, why: &str) -> fmi3Status {
    unsupported::<M>(c, name, why)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_model::{Decay, Panicky};
    use std::ffi::CString;
    use std::sync::Mutex;

    static LOG: Mutex<Vec<(i32, String)>> = Mutex::new(Vec::new());

    unsafe extern "C" fn record(_: fmi3InstanceEnvironment, status: fmi3Status, _: fmi3String, msg: fmi3String) {
        LOG.lock().unwrap().push((status, std::ffi::CStr::from_ptr(msg).to_string_lossy().into_owned()));
    }

    fn exported<M: Model>() -> &'static Exported<M> {
        Box::leak(Box::new(Exported::of()))
    }

    unsafe fn co_simulation<M: Model>(exported: &'static Exported<M>, token: &str) -> fmi3Instance {
        let token = CString::new(token).unwrap();
        instantiate::<M>(exported, Interface::CoSimulation, c"i".as_ptr(), token.as_ptr(), std::ptr::null_mut(), false, Some(record), (false, false))
    }

    unsafe fn step(c: fmi3Instance, t: f64, h: f64) -> (fmi3Status, f64) {
        let (mut event, mut terminate, mut early, mut last) = (true, true, true, f64::NAN);
        let status = do_step::<Decay>(c, t, h, 1, &mut event, &mut terminate, &mut early, &mut last);
        assert!(!event && !terminate && !early, "events are handled inside fmi3DoStep");
        (status, last)
    }

    #[test]
    fn a_wrong_token_is_refused_and_a_panic_is_fatal() {
        let e = exported::<Panicky>();
        unsafe {
            assert!(co_simulation::<Panicky>(e, "{not-this-one}").is_null());
            assert!(LOG.lock().unwrap().iter().any(|(s, m)| *s == fmi3Error && m.contains("instantiationToken {not-this-one} does not match")));
            let c = co_simulation::<Panicky>(e, &e.of_standard(crate::standards::Standard::Fmi3).token);
            assert!(!c.is_null());
            assert_eq!(enter_initialization_mode::<Panicky>(c, 0, 0.0, 0.0, 0, 0.0), fmi3OK);
            assert_eq!(exit_initialization_mode::<Panicky>(c), fmi3OK);
            let (vr, u) = ([0u32], [-1.0]);
            assert_eq!(set_float64::<Panicky>(c, vr.as_ptr(), 1, u.as_ptr(), 1), fmi3OK);
            let (mut a, mut b, mut d, mut last) = (false, false, false, 0.0);
            assert_eq!(do_step::<Panicky>(c, 0.0, 0.1, 1, &mut a, &mut b, &mut d, &mut last), fmi3Fatal);
            assert!(LOG.lock().unwrap().iter().any(|(s, m)| *s == fmi3Fatal && m.contains("negative input")));
            free_instance::<Panicky>(c);
        }
    }

    #[test]
    fn an_enumeration_is_read_and_set_as_int64_only() {
        use crate::test_model::Chooser;
        let e = exported::<Chooser>();
        unsafe {
            let token = CString::new(e.of_standard(crate::standards::Standard::Fmi3).token.clone()).unwrap();
            let c = instantiate::<Chooser>(e, Interface::CoSimulation, c"i".as_ptr(), token.as_ptr(), std::ptr::null_mut(), false, Some(record), (false, false));
            let vr = [0u32];
            assert_eq!(set_int64::<Chooser>(c, vr.as_ptr(), 1, [1i64].as_ptr(), 1), fmi3OK);
            assert_eq!(set_int64::<Chooser>(c, vr.as_ptr(), 1, [3i64].as_ptr(), 1), fmi3Error, "no third item");
            assert_eq!(set_int64::<Chooser>(c, vr.as_ptr(), 1, [1i64 << 40].as_ptr(), 1), fmi3Error);
            assert_eq!(set_int32::<Chooser>(c, vr.as_ptr(), 1, [2i32].as_ptr(), 1), fmi3Error);
            assert!(LOG.lock().unwrap().iter().any(|(_, m)| m.contains("'gain' is an Enumeration")));
            assert_eq!(enter_initialization_mode::<Chooser>(c, 0, 0.0, 0.0, 0, 0.0), fmi3OK);
            let mut v = [0i64];
            assert_eq!(get_int64::<Chooser>(c, vr.as_ptr(), 1, v.as_mut_ptr(), 1), fmi3OK);
            assert_eq!(v[0], 1);
            let mut y = [0.0];
            assert_eq!(get_float64::<Chooser>(c, [3u32].as_ptr(), 1, y.as_mut_ptr(), 1), fmi3OK);
            assert_eq!(y[0], 1.0, "y = x with the first item");
            free_instance::<Chooser>(c);
        }
    }

    #[test]
    fn steps_read_time_and_give_adjoints_from_the_same_jacobian() {
        let e = exported::<Decay>();
        unsafe {
            let c = co_simulation::<Decay>(e, &e.of_standard(crate::standards::Standard::Fmi3).token);
            // Before initialization nothing can be read; the table says where it can.
            let mut v = [0.0];
            assert_eq!(get_float64::<Decay>(c, [2u32].as_ptr(), 1, v.as_mut_ptr(), 1), fmi3Error);
            assert_eq!(enter_initialization_mode::<Decay>(c, 1, 1e-8, 0.0, 1, 1.0), fmi3OK);
            assert_eq!(exit_initialization_mode::<Decay>(c), fmi3OK);
            let (status, last) = step(c, 0.0, 0.25);
            assert_eq!((status, last), (fmi3OK, 0.25));
            let time = Extra::of(&crate::model::declare::<Decay>().2).time;
            assert_eq!(get_float64::<Decay>(c, [time].as_ptr(), 1, v.as_mut_ptr(), 1), fmi3OK);
            assert_eq!(v[0], 0.25);
            // More values than value references: refused (every variable is a scalar).
            assert_eq!(get_float64::<Decay>(c, [2u32].as_ptr(), 1, v.as_mut_ptr(), 2), fmi3Error);
            // A step past the stop time set at initialization is refused.
            assert_eq!(step(c, 0.25, 1.0).0, fmi3Error);
            // d(der(x), y)/d(x, u): [[-a, 1], [2, 0]] with a = 2; the adjoint with seed (1, 1)
            // is the columns' sums: (-2 + 2, 1 + 0).
            let (unknowns, knowns) = ([3u32, 4], [2u32, 1]);
            let (seed, mut sensitivity) = ([1.0, 1.0], [0.0; 2]);
            let status = get_adjoint_derivative::<Decay>(c, unknowns.as_ptr(), 2, knowns.as_ptr(), 2, seed.as_ptr(), 2, sensitivity.as_mut_ptr(), 2);
            assert_eq!(status, fmi3OK);
            assert!((sensitivity[0] - 0.0).abs() < 1e-8 && (sensitivity[1] - 1.0).abs() < 1e-8, "{sensitivity:?}");
            let mut column = [0.0; 2];
            let status = get_directional_derivative::<Decay>(c, unknowns.as_ptr(), 2, knowns.as_ptr(), 2, [1.0, 0.0].as_ptr(), 2, column.as_mut_ptr(), 2);
            assert_eq!(status, fmi3OK);
            assert!((column[0] + 2.0).abs() < 1e-8 && (column[1] - 2.0).abs() < 1e-8, "{column:?}");
            assert_eq!(not_provided::<Decay>(c, "fmi3GetClock", NO_CLOCKS), fmi3Error);
            // time is the description's own: read only, and named when refused.
            assert_eq!(set_float64::<Decay>(c, [time].as_ptr(), 1, [1.0].as_ptr(), 1), fmi3Error);
            assert!(LOG.lock().unwrap().iter().any(|(_, m)| m.contains("'time' cannot be set")));
            free_instance::<Decay>(c);
        }
    }
}
