//! `export_fmu!(MyModel)`: the one line a model crate writes to become an FMU.

/// Exports every function of FMI 2.0 `fmi2Functions.h` (Co-Simulation and Model Exchange)
/// for a type implementing
/// [`Model`](crate::Model), and four functions `build-fmus` reads:
/// `fmu_runtime_model_identifier`, `fmu_runtime_model_description`, `fmu_runtime_documentation`
/// and `fmu_runtime_model_problems`.
///
/// Use it once, at the root of a `cdylib` crate: `fmu_runtime::export_fmu!(RlcCircuit);`
#[macro_export]
macro_rules! export_fmu {
    ($model:ty) => {
        #[allow(non_snake_case, clippy::missing_safety_doc)]
        mod __fmu_exports {
            use super::*;
            use $crate::fmi2::functions as f;
            use $crate::fmi2::types::*;
            use std::os::raw::c_char;
            type M = $model;

            static EXPORTED: $crate::fmi2::ExportedCell = $crate::fmi2::ExportedCell::new();

            /// The model crate's Cargo metadata and source date, read here, in the model crate, at
            /// compile time: the XML the binary writes at run time is the one build-fmus packaged.
            const PACKAGE: $crate::description::Package = $crate::description::Package {
                version: env!("CARGO_PKG_VERSION"),
                authors: env!("CARGO_PKG_AUTHORS"),
                license: env!("CARGO_PKG_LICENSE"),
                source_date_epoch: option_env!("SOURCE_DATE_EPOCH"),
            };

            fn make() -> $crate::fmi2::Exported {
                $crate::fmi2::Exported::with_package::<M>(&PACKAGE)
            }

            fn exported() -> &'static $crate::fmi2::Exported {
                EXPORTED.get_or_init(make)
            }

            /// Frees the description when the library is unloaded (or the process exits).
            #[cfg(target_os = "linux")]
            #[used]
            #[link_section = ".fini_array"]
            static RELEASE_AT_UNLOAD: extern "C" fn() = {
                extern "C" fn release() {
                    // SAFETY: .fini_array runs when nothing of this library can be called again.
                    unsafe { EXPORTED.release() }
                }
                release
            };

            fn guarded_text(pick: fn(&$crate::fmi2::Exported) -> *const c_char) -> *const c_char {
                std::panic::catch_unwind(|| pick(exported())).unwrap_or(std::ptr::null())
            }

            #[no_mangle]
            pub extern "C" fn fmu_runtime_model_identifier() -> *const c_char {
                guarded_text(|e| e.model_identifier.as_ptr())
            }
            #[no_mangle]
            pub extern "C" fn fmu_runtime_model_description() -> *const c_char {
                guarded_text(|e| e.model_description.as_ptr())
            }
            #[no_mangle]
            pub extern "C" fn fmu_runtime_documentation() -> *const c_char {
                guarded_text(|e| e.documentation.as_ptr())
            }
            /// The model's problems (one per line: "file:line: rule. Fix: ..."), or NULL if none.
            #[no_mangle]
            pub extern "C" fn fmu_runtime_model_problems() -> *const c_char {
                guarded_text(|e| e.problems.as_ref().map_or(std::ptr::null(), |p| p.as_ptr()))
            }

            /// The effects of the model and their activities over its default experiment (run
            /// on the first call): (HTML for documentation/index.html, plain text).
            fn effects() -> &'static (std::ffi::CString, std::ffi::CString) {
                static EFFECTS: std::sync::OnceLock<(std::ffi::CString, std::ffi::CString)> = std::sync::OnceLock::new();
                EFFECTS.get_or_init(|| {
                    let (html, text) = $crate::activity_report::report::<M>();
                    ($crate::log::to_c_string(&html), $crate::log::to_c_string(&text))
                })
            }
            /// Table 3.1 and the activity table, as HTML (build-fmus puts it in the documentation).
            #[no_mangle]
            pub extern "C" fn fmu_runtime_effects_html() -> *const c_char {
                std::panic::catch_unwind(|| effects().0.as_ptr()).unwrap_or(std::ptr::null())
            }
            /// Table 3.1 and the activity table, as text (`build-fmus effects <model>`).
            #[no_mangle]
            pub extern "C" fn fmu_runtime_effects_text() -> *const c_char {
                std::panic::catch_unwind(|| effects().1.as_ptr()).unwrap_or(std::ptr::null())
            }

            #[no_mangle]
            pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
                f::get_types_platform()
            }
            #[no_mangle]
            pub extern "C" fn fmi2GetVersion() -> *const c_char {
                f::get_version()
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetDebugLogging(c: fmi2Component, on: fmi2Boolean, n: usize, cats: *const fmi2String) -> fmi2Status {
                f::set_debug_logging::<M>(c, on, n, cats)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Instantiate(
                name: fmi2String,
                kind: fmi2Type,
                guid: fmi2String,
                resources: fmi2String,
                callbacks: *const fmi2CallbackFunctions,
                visible: fmi2Boolean,
                logging_on: fmi2Boolean,
            ) -> fmi2Component {
                match std::panic::catch_unwind(exported) {
                    Ok(e) => f::instantiate::<M>(e, name, kind, guid, resources, callbacks, visible, logging_on),
                    Err(_) => std::ptr::null_mut(),
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
                f::free_instance::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetupExperiment(c: fmi2Component, tol_defined: fmi2Boolean, tol: fmi2Real, start: fmi2Real, stop_defined: fmi2Boolean, stop: fmi2Real) -> fmi2Status {
                f::setup_experiment::<M>(c, tol_defined, tol, start, stop_defined, stop)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
                f::enter_initialization_mode::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
                f::exit_initialization_mode::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
                f::terminate::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
                f::reset::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetReal(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, v: *mut fmi2Real) -> fmi2Status {
                f::get_real::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetInteger(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, v: *mut fmi2Integer) -> fmi2Status {
                f::get_integer::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetBoolean(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, v: *mut fmi2Boolean) -> fmi2Status {
                f::get_boolean::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetString(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, v: *mut fmi2String) -> fmi2Status {
                f::get_string::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetReal(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, v: *const fmi2Real) -> fmi2Status {
                f::set_real::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetInteger(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, v: *const fmi2Integer) -> fmi2Status {
                f::set_integer::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetBoolean(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, v: *const fmi2Boolean) -> fmi2Status {
                f::set_boolean::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetString(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, v: *const fmi2String) -> fmi2Status {
                f::set_string::<M>(c, vr, n, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetFMUstate(c: fmi2Component, s: *mut fmi2FMUstate) -> fmi2Status {
                f::get_fmu_state::<M>(c, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, s: fmi2FMUstate) -> fmi2Status {
                f::set_fmu_state::<M>(c, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2FreeFMUstate(c: fmi2Component, s: *mut fmi2FMUstate) -> fmi2Status {
                f::free_fmu_state::<M>(c, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SerializedFMUstateSize(c: fmi2Component, s: fmi2FMUstate, size: *mut usize) -> fmi2Status {
                f::serialized_fmu_state_size::<M>(c, s, size)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SerializeFMUstate(c: fmi2Component, s: fmi2FMUstate, bytes: *mut fmi2Byte, size: usize) -> fmi2Status {
                f::serialize_fmu_state::<M>(c, s, bytes, size)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2DeSerializeFMUstate(c: fmi2Component, bytes: *const fmi2Byte, size: usize, s: *mut fmi2FMUstate) -> fmi2Status {
                f::deserialize_fmu_state::<M>(c, bytes, size, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
                c: fmi2Component,
                unknowns: *const fmi2ValueReference,
                n_unknowns: usize,
                knowns: *const fmi2ValueReference,
                n_knowns: usize,
                dv_known: *const fmi2Real,
                dv_unknown: *mut fmi2Real,
            ) -> fmi2Status {
                f::get_directional_derivative::<M>(c, unknowns, n_unknowns, knowns, n_knowns, dv_known, dv_unknown)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetRealInputDerivatives(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, order: *const fmi2Integer, v: *const fmi2Real) -> fmi2Status {
                f::set_real_input_derivatives::<M>(c, vr, n, order, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(c: fmi2Component, vr: *const fmi2ValueReference, n: usize, order: *const fmi2Integer, v: *mut fmi2Real) -> fmi2Status {
                f::get_real_output_derivatives::<M>(c, vr, n, order, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2DoStep(c: fmi2Component, t: fmi2Real, h: fmi2Real, no_prior: fmi2Boolean) -> fmi2Status {
                f::do_step::<M>(c, t, h, no_prior)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
                f::cancel_step::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetStatus(c: fmi2Component, k: fmi2StatusKind, v: *mut fmi2Status) -> fmi2Status {
                f::get_status::<M>(c, k, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetRealStatus(c: fmi2Component, k: fmi2StatusKind, v: *mut fmi2Real) -> fmi2Status {
                f::get_real_status::<M>(c, k, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetIntegerStatus(c: fmi2Component, k: fmi2StatusKind, v: *mut fmi2Integer) -> fmi2Status {
                f::get_integer_status::<M>(c, k, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetBooleanStatus(c: fmi2Component, k: fmi2StatusKind, v: *mut fmi2Boolean) -> fmi2Status {
                f::get_boolean_status::<M>(c, k, v)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetStringStatus(c: fmi2Component, k: fmi2StatusKind, v: *mut fmi2String) -> fmi2Status {
                f::get_string_status::<M>(c, k, v)
            }

            // Model Exchange.
            #[no_mangle]
            pub unsafe extern "C" fn fmi2EnterEventMode(c: fmi2Component) -> fmi2Status {
                f::enter_event_mode::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2NewDiscreteStates(c: fmi2Component, info: *mut fmi2EventInfo) -> fmi2Status {
                f::new_discrete_states::<M>(c, info)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2EnterContinuousTimeMode(c: fmi2Component) -> fmi2Status {
                f::enter_continuous_time_mode::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2CompletedIntegratorStep(c: fmi2Component, no_prior: fmi2Boolean, enter: *mut fmi2Boolean, terminate: *mut fmi2Boolean) -> fmi2Status {
                f::completed_integrator_step::<M>(c, no_prior, enter, terminate)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetTime(c: fmi2Component, t: fmi2Real) -> fmi2Status {
                f::set_time::<M>(c, t)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetContinuousStates(c: fmi2Component, x: *const fmi2Real, n: usize) -> fmi2Status {
                f::set_continuous_states::<M>(c, x, n)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetDerivatives(c: fmi2Component, dx: *mut fmi2Real, n: usize) -> fmi2Status {
                f::get_derivatives::<M>(c, dx, n)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetEventIndicators(c: fmi2Component, z: *mut fmi2Real, n: usize) -> fmi2Status {
                f::get_event_indicators::<M>(c, z, n)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetContinuousStates(c: fmi2Component, x: *mut fmi2Real, n: usize) -> fmi2Status {
                f::get_continuous_states::<M>(c, x, n)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetNominalsOfContinuousStates(c: fmi2Component, x: *mut fmi2Real, n: usize) -> fmi2Status {
                f::get_nominals_of_continuous_states::<M>(c, x, n)
            }
        }
    };
}
