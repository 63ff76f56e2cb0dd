//! `export_fmi3!()`: the `extern "C"` symbols of FMI 3.0 `fmi3Functions.h` (Model Exchange and
//! Co-Simulation; Scheduled Execution refused), each a line that calls its generic
//! implementation in `fmi3::functions`.

/// Exports every fmi3 function. Used by `export_fmu!`, inside the module where it defines `M`
/// (the model) and `exported()` (its description).
#[doc(hidden)]
#[macro_export]
macro_rules! export_fmi3 {
    () => {
        #[allow(non_snake_case, clippy::missing_safety_doc, clippy::too_many_arguments)]
        mod __fmi3 {
            use super::{exported, M};
            use $crate::fmi3::functions as f;
            use $crate::fmi3::functions::{NO_CLOCKS, NO_EVALUATE, NO_PARTITIONS, NO_PER_ELEMENT, NO_STRUCTURAL_PARAMETERS};
            use $crate::fmi3::types::*;
            use $crate::instance::Interface;
            use std::os::raw::c_char;

            #[no_mangle]
            pub extern "C" fn fmi3GetVersion() -> *const c_char {
                f::get_version()
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetDebugLogging(c: fmi3Instance, on: fmi3BooleanIn, n: usize, cats: *const fmi3String) -> fmi3Status {
                f::set_debug_logging::<M>(c, on, n, cats)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3InstantiateModelExchange(
                name: fmi3String,
                token: fmi3String,
                _resources: fmi3String,
                _visible: fmi3BooleanIn,
                logging_on: fmi3BooleanIn,
                environment: fmi3InstanceEnvironment,
                log_message: Option<fmi3LogMessageCallback>,
            ) -> fmi3Instance {
                match std::panic::catch_unwind(exported) {
                    Ok(e) => f::instantiate::<M>(e, Interface::ModelExchange, name, token, environment, logging_on != 0, log_message, (false, false)),
                    Err(_) => std::ptr::null_mut(),
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
                name: fmi3String,
                token: fmi3String,
                _resources: fmi3String,
                _visible: fmi3BooleanIn,
                logging_on: fmi3BooleanIn,
                event_mode_used: fmi3BooleanIn,
                early_return_allowed: fmi3BooleanIn,
                _required_intermediate: *const fmi3ValueReference,
                _n_required_intermediate: usize,
                environment: fmi3InstanceEnvironment,
                log_message: Option<fmi3LogMessageCallback>,
                _intermediate_update: Option<fmi3IntermediateUpdateCallback>,
            ) -> fmi3Instance {
                match std::panic::catch_unwind(exported) {
                    Ok(e) => f::instantiate::<M>(e, Interface::CoSimulation, name, token, environment, logging_on != 0, log_message, (event_mode_used != 0, early_return_allowed != 0)),
                    Err(_) => std::ptr::null_mut(),
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
                _name: fmi3String,
                _token: fmi3String,
                _resources: fmi3String,
                _visible: fmi3BooleanIn,
                _logging_on: fmi3BooleanIn,
                environment: fmi3InstanceEnvironment,
                log_message: Option<fmi3LogMessageCallback>,
                _clock_update: Option<fmi3ClockUpdateCallback>,
                _lock: Option<fmi3LockPreemptionCallback>,
                _unlock: Option<fmi3UnlockPreemptionCallback>,
            ) -> fmi3Instance {
                f::instantiate_scheduled_execution(environment, log_message)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3FreeInstance(c: fmi3Instance) {
                f::free_instance::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3EnterInitializationMode(c: fmi3Instance, tol_defined: fmi3BooleanIn, tol: fmi3Float64, start: fmi3Float64, stop_defined: fmi3BooleanIn, stop: fmi3Float64) -> fmi3Status {
                f::enter_initialization_mode::<M>(c, tol_defined, tol, start, stop_defined, stop)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3ExitInitializationMode(c: fmi3Instance) -> fmi3Status {
                f::exit_initialization_mode::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3EnterEventMode(c: fmi3Instance) -> fmi3Status {
                f::enter_event_mode::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3Terminate(c: fmi3Instance) -> fmi3Status {
                f::terminate::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3Reset(c: fmi3Instance) -> fmi3Status {
                f::reset::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetFloat64(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, v: *mut fmi3Float64, nv: usize) -> fmi3Status {
                f::get_float64::<M>(c, vr, n, v, nv)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetInt32(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, v: *mut fmi3Int32, nv: usize) -> fmi3Status {
                f::get_int32::<M>(c, vr, n, v, nv)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetBoolean(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, v: *mut fmi3Boolean, nv: usize) -> fmi3Status {
                f::get_boolean::<M>(c, vr, n, v, nv)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetInt64(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, v: *mut fmi3Int64, nv: usize) -> fmi3Status {
                f::get_int64::<M>(c, vr, n, v, nv)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetInt64(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, v: *const fmi3Int64, nv: usize) -> fmi3Status {
                f::set_int64::<M>(c, vr, n, v, nv)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetFloat64(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, v: *const fmi3Float64, nv: usize) -> fmi3Status {
                f::set_float64::<M>(c, vr, n, v, nv)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetInt32(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, v: *const fmi3Int32, nv: usize) -> fmi3Status {
                f::set_int32::<M>(c, vr, n, v, nv)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetBoolean(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, v: *const fmi3BooleanIn, nv: usize) -> fmi3Status {
                f::set_boolean::<M>(c, vr, n, v, nv)
            }

            // Types this FMU has no variables of: nothing to do for no value references, else an error.
            macro_rules! none_of_type {
                ($get:ident, $set:ident, $type_name:literal) => {
                    #[no_mangle]
                    pub unsafe extern "C" fn $get(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, _v: *mut Opaque, _nv: usize) -> fmi3Status {
                        f::no_such_type::<M>(c, stringify!($get), $type_name, false, vr, n)
                    }
                    #[no_mangle]
                    pub unsafe extern "C" fn $set(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, _v: *const Opaque, _nv: usize) -> fmi3Status {
                        f::no_such_type::<M>(c, stringify!($set), $type_name, true, vr, n)
                    }
                };
            }
            none_of_type!(fmi3GetFloat32, fmi3SetFloat32, "Float32");
            none_of_type!(fmi3GetInt8, fmi3SetInt8, "Int8");
            none_of_type!(fmi3GetUInt8, fmi3SetUInt8, "UInt8");
            none_of_type!(fmi3GetInt16, fmi3SetInt16, "Int16");
            none_of_type!(fmi3GetUInt16, fmi3SetUInt16, "UInt16");
            none_of_type!(fmi3GetUInt32, fmi3SetUInt32, "UInt32");
            none_of_type!(fmi3GetUInt64, fmi3SetUInt64, "UInt64");
            none_of_type!(fmi3GetString, fmi3SetString, "String");
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetBinary(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, _sizes: *mut usize, _v: *mut fmi3Binary, _nv: usize) -> fmi3Status {
                f::no_such_type::<M>(c, "fmi3GetBinary", "Binary", false, vr, n)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetBinary(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, _sizes: *const usize, _v: *const fmi3Binary, _nv: usize) -> fmi3Status {
                f::no_such_type::<M>(c, "fmi3SetBinary", "Binary", true, vr, n)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetClock(c: fmi3Instance, _vr: *const fmi3ValueReference, _n: usize, _v: *mut fmi3Clock) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3GetClock", NO_CLOCKS)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetClock(c: fmi3Instance, _vr: *const fmi3ValueReference, _n: usize, _v: *const fmi3BooleanIn) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3SetClock", NO_CLOCKS)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetNumberOfVariableDependencies(c: fmi3Instance, _vr: fmi3ValueReference, _n: *mut usize) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3GetNumberOfVariableDependencies", NO_PER_ELEMENT)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetVariableDependencies(
                c: fmi3Instance,
                _dependent: fmi3ValueReference,
                _element_indices: *mut usize,
                _independents: *mut fmi3ValueReference,
                _independent_indices: *mut usize,
                _kinds: *mut fmi3DependencyKind,
                _n: usize,
            ) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3GetVariableDependencies", NO_PER_ELEMENT)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetFMUState(c: fmi3Instance, s: *mut fmi3FMUState) -> fmi3Status {
                f::get_fmu_state::<M>(c, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetFMUState(c: fmi3Instance, s: fmi3FMUState) -> fmi3Status {
                f::set_fmu_state::<M>(c, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3FreeFMUState(c: fmi3Instance, s: *mut fmi3FMUState) -> fmi3Status {
                f::free_fmu_state::<M>(c, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SerializedFMUStateSize(c: fmi3Instance, s: fmi3FMUState, size: *mut usize) -> fmi3Status {
                f::serialized_fmu_state_size::<M>(c, s, size)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SerializeFMUState(c: fmi3Instance, s: fmi3FMUState, bytes: *mut fmi3Byte, size: usize) -> fmi3Status {
                f::serialize_fmu_state::<M>(c, s, bytes, size)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3DeserializeFMUState(c: fmi3Instance, bytes: *const fmi3Byte, size: usize, s: *mut fmi3FMUState) -> fmi3Status {
                f::deserialize_fmu_state::<M>(c, bytes, size, s)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetDirectionalDerivative(
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
                f::get_directional_derivative::<M>(c, unknowns, n_unknowns, knowns, n_knowns, seed, n_seed, sensitivity, n_sensitivity)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetAdjointDerivative(
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
                f::get_adjoint_derivative::<M>(c, unknowns, n_unknowns, knowns, n_knowns, seed, n_seed, sensitivity, n_sensitivity)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3EnterConfigurationMode(c: fmi3Instance) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3EnterConfigurationMode", NO_STRUCTURAL_PARAMETERS)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3ExitConfigurationMode(c: fmi3Instance) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3ExitConfigurationMode", NO_STRUCTURAL_PARAMETERS)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetIntervalDecimal(c: fmi3Instance, _vr: *const fmi3ValueReference, _n: usize, _i: *mut fmi3Float64, _q: *mut fmi3IntervalQualifier) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3GetIntervalDecimal", NO_CLOCKS)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetIntervalFraction(c: fmi3Instance, _vr: *const fmi3ValueReference, _n: usize, _c: *mut fmi3UInt64, _r: *mut fmi3UInt64, _q: *mut fmi3IntervalQualifier) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3GetIntervalFraction", NO_CLOCKS)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetShiftDecimal(c: fmi3Instance, _vr: *const fmi3ValueReference, _n: usize, _s: *mut fmi3Float64) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3GetShiftDecimal", NO_CLOCKS)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetShiftFraction(c: fmi3Instance, _vr: *const fmi3ValueReference, _n: usize, _c: *mut fmi3UInt64, _r: *mut fmi3UInt64) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3GetShiftFraction", NO_CLOCKS)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetIntervalDecimal(c: fmi3Instance, _vr: *const fmi3ValueReference, _n: usize, _i: *const fmi3Float64) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3SetIntervalDecimal", NO_CLOCKS)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetIntervalFraction(c: fmi3Instance, _vr: *const fmi3ValueReference, _n: usize, _c: *const fmi3UInt64, _r: *const fmi3UInt64) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3SetIntervalFraction", NO_CLOCKS)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetShiftDecimal(c: fmi3Instance, _vr: *const fmi3ValueReference, _n: usize, _s: *const fmi3Float64) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3SetShiftDecimal", NO_CLOCKS)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetShiftFraction(c: fmi3Instance, _vr: *const fmi3ValueReference, _n: usize, _c: *const fmi3UInt64, _r: *const fmi3UInt64) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3SetShiftFraction", NO_CLOCKS)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3EvaluateDiscreteStates(c: fmi3Instance) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3EvaluateDiscreteStates", NO_EVALUATE)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3UpdateDiscreteStates(
                c: fmi3Instance,
                need: *mut fmi3Boolean,
                terminate: *mut fmi3Boolean,
                nominals: *mut fmi3Boolean,
                values: *mut fmi3Boolean,
                defined: *mut fmi3Boolean,
                next: *mut fmi3Float64,
            ) -> fmi3Status {
                f::update_discrete_states::<M>(c, need, terminate, nominals, values, defined, next)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3EnterContinuousTimeMode(c: fmi3Instance) -> fmi3Status {
                f::enter_continuous_time_mode::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3CompletedIntegratorStep(c: fmi3Instance, no_prior: fmi3BooleanIn, enter: *mut fmi3Boolean, terminate: *mut fmi3Boolean) -> fmi3Status {
                f::completed_integrator_step::<M>(c, no_prior, enter, terminate)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetTime(c: fmi3Instance, t: fmi3Float64) -> fmi3Status {
                f::set_time::<M>(c, t)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3SetContinuousStates(c: fmi3Instance, x: *const fmi3Float64, n: usize) -> fmi3Status {
                f::set_continuous_states::<M>(c, x, n)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetContinuousStateDerivatives(c: fmi3Instance, dx: *mut fmi3Float64, n: usize) -> fmi3Status {
                f::get_continuous_state_derivatives::<M>(c, dx, n)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetEventIndicators(c: fmi3Instance, z: *mut fmi3Float64, n: usize) -> fmi3Status {
                f::get_event_indicators::<M>(c, z, n)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetContinuousStates(c: fmi3Instance, x: *mut fmi3Float64, n: usize) -> fmi3Status {
                f::get_continuous_states::<M>(c, x, n)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetNominalsOfContinuousStates(c: fmi3Instance, x: *mut fmi3Float64, n: usize) -> fmi3Status {
                f::get_nominals_of_continuous_states::<M>(c, x, n)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetNumberOfEventIndicators(c: fmi3Instance, n: *mut usize) -> fmi3Status {
                f::get_number_of_event_indicators::<M>(c, n)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetNumberOfContinuousStates(c: fmi3Instance, n: *mut usize) -> fmi3Status {
                f::get_number_of_continuous_states::<M>(c, n)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3EnterStepMode(c: fmi3Instance) -> fmi3Status {
                f::enter_step_mode::<M>(c)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3GetOutputDerivatives(c: fmi3Instance, vr: *const fmi3ValueReference, n: usize, orders: *const fmi3Int32, v: *mut fmi3Float64, nv: usize) -> fmi3Status {
                f::get_output_derivatives::<M>(c, vr, n, orders, v, nv)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3DoStep(
                c: fmi3Instance,
                t: fmi3Float64,
                h: fmi3Float64,
                no_prior: fmi3BooleanIn,
                event: *mut fmi3Boolean,
                terminate: *mut fmi3Boolean,
                early: *mut fmi3Boolean,
                last: *mut fmi3Float64,
            ) -> fmi3Status {
                f::do_step::<M>(c, t, h, no_prior, event, terminate, early, last)
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi3ActivateModelPartition(c: fmi3Instance, _clock: fmi3ValueReference, _t: fmi3Float64) -> fmi3Status {
                f::not_provided::<M>(c, "fmi3ActivateModelPartition", NO_PARTITIONS)
            }
        }
    };
}
