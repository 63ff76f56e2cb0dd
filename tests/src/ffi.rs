//! Raw FMI 2.0 and FMI 3.0 C types (`fmi2FunctionTypes.h`, `fmi3FunctionTypes.h`) and the tables of
//! function pointers resolved from an FMU's shared library.
//!
//! Everything here is a plain transcription of the C declarations; the safe layer is
//! [`crate::Instance`].

use std::ffi::{c_char, c_int, c_void};
use std::fmt;

use libloading::Library;

use crate::error::{Error, Result};

/// `fmi2Component`: an opaque pointer to one FMU instance.
pub type Component = *mut c_void;
/// `fmi2ComponentEnvironment`: an opaque pointer handed back to the callbacks.
pub type ComponentEnvironment = *mut c_void;
/// `fmi2FMUstate`: an opaque pointer to a saved FMU state.
pub type FmuStatePtr = *mut c_void;
/// `fmi2ValueReference`.
pub type ValueReference = u32;
/// `fmi2Boolean` (`int`): 0 is `fmi2False`, 1 is `fmi2True`.
pub type Fmi2Boolean = c_int;
/// `fmi2True`.
pub const FMI2_TRUE: Fmi2Boolean = 1;
/// `fmi2False`.
pub const FMI2_FALSE: Fmi2Boolean = 0;

/// `fmi2Status`, kept as the raw `int` the FMU returned (an FMU returning an out-of-range value
/// must not be undefined behaviour on our side, so this is not a Rust enum).
#[repr(transparent)]
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Status(pub c_int);

impl Status {
    pub const OK: Status = Status(0);
    pub const WARNING: Status = Status(1);
    pub const DISCARD: Status = Status(2);
    pub const ERROR: Status = Status(3);
    pub const FATAL: Status = Status(4);
    pub const PENDING: Status = Status(5);

    /// The C name of the status (`"fmi2OK"`, ...), or `None` for an out-of-range value.
    pub fn name(self) -> Option<&'static str> {
        Some(match self.0 {
            0 => "fmi2OK",
            1 => "fmi2Warning",
            2 => "fmi2Discard",
            3 => "fmi2Error",
            4 => "fmi2Fatal",
            5 => "fmi2Pending",
            _ => return None,
        })
    }

    /// `fmi2OK` or `fmi2Warning`: the call did what was asked.
    pub fn is_ok_or_warning(self) -> bool {
        self == Status::OK || self == Status::WARNING
    }
}

impl fmt::Debug for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.name() {
            Some(name) => f.write_str(name),
            None => write!(f, "fmi2Status({})", self.0),
        }
    }
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self, f)
    }
}

/// `fmi2Type`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fmi2Type {
    ModelExchange = 0,
    CoSimulation = 1,
}

/// `fmi2StatusKind`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StatusKind {
    DoStepStatus = 0,
    PendingStatus = 1,
    LastSuccessfulTime = 2,
    Terminated = 3,
}

/// The logger callback **as this host declares it**.
///
/// The standard's `fmi2CallbackLogger` is C-variadic (`..., fmi2String message, ...)`); stable
/// Rust cannot *define* a C-variadic function. On x86_64 System V (and aarch64 Linux) a caller
/// passing the five fixed arguments of a variadic function puts them in the same registers as
/// for a non-variadic one, so a non-variadic callee reads them correctly. The limitation: any
/// variadic arguments the FMU passes are ignored and the message is not run through `printf`.
/// The FMUs of this project pass the message pre-formatted, with every `%` doubled and no
/// variadic arguments; the host turns `%%` back into `%`. A third-party FMU that relies on
/// `printf` formatting would show its raw format string.
pub type LoggerFn = unsafe extern "C" fn(
    env: ComponentEnvironment,
    instance_name: *const c_char,
    status: Status,
    category: *const c_char,
    message: *const c_char,
);
/// `fmi2CallbackAllocateMemory`.
pub type AllocateMemoryFn = unsafe extern "C" fn(nobj: usize, size: usize) -> *mut c_void;
/// `fmi2CallbackFreeMemory`.
pub type FreeMemoryFn = unsafe extern "C" fn(obj: *mut c_void);
/// `fmi2StepFinished`.
pub type StepFinishedFn = unsafe extern "C" fn(env: ComponentEnvironment, status: Status);

/// `fmi2CallbackFunctions` (the header packs it with alignment 8, which is the natural layout
/// of these five pointers anyway).
#[repr(C)]
#[derive(Debug)]
pub struct CallbackFunctions {
    pub logger: Option<LoggerFn>,
    pub allocate_memory: Option<AllocateMemoryFn>,
    pub free_memory: Option<FreeMemoryFn>,
    pub step_finished: Option<StepFinishedFn>,
    pub component_environment: ComponentEnvironment,
}

/// `fmi2EventInfo` (Model Exchange).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EventInfo {
    pub new_discrete_states_needed: Fmi2Boolean,
    pub terminate_simulation: Fmi2Boolean,
    pub nominals_of_continuous_states_changed: Fmi2Boolean,
    pub values_of_continuous_states_changed: Fmi2Boolean,
    pub next_event_time_defined: Fmi2Boolean,
    pub next_event_time: f64,
}

type Vr = *const ValueReference;

// Common functions.
pub type GetTypesPlatformFn = unsafe extern "C" fn() -> *const c_char;
pub type GetVersionFn = unsafe extern "C" fn() -> *const c_char;
pub type SetDebugLoggingFn =
    unsafe extern "C" fn(Component, Fmi2Boolean, usize, *const *const c_char) -> Status;
pub type InstantiateFn = unsafe extern "C" fn(
    *const c_char,
    Fmi2Type,
    *const c_char,
    *const c_char,
    *const CallbackFunctions,
    Fmi2Boolean,
    Fmi2Boolean,
) -> Component;
pub type FreeInstanceFn = unsafe extern "C" fn(Component);
pub type SetupExperimentFn =
    unsafe extern "C" fn(Component, Fmi2Boolean, f64, f64, Fmi2Boolean, f64) -> Status;
pub type ComponentFn = unsafe extern "C" fn(Component) -> Status;
pub type GetRealFn = unsafe extern "C" fn(Component, Vr, usize, *mut f64) -> Status;
pub type GetIntegerFn = unsafe extern "C" fn(Component, Vr, usize, *mut c_int) -> Status;
pub type GetBooleanFn = unsafe extern "C" fn(Component, Vr, usize, *mut Fmi2Boolean) -> Status;
pub type GetStringFn = unsafe extern "C" fn(Component, Vr, usize, *mut *const c_char) -> Status;
pub type SetRealFn = unsafe extern "C" fn(Component, Vr, usize, *const f64) -> Status;
pub type SetIntegerFn = unsafe extern "C" fn(Component, Vr, usize, *const c_int) -> Status;
pub type SetBooleanFn = unsafe extern "C" fn(Component, Vr, usize, *const Fmi2Boolean) -> Status;
pub type SetStringFn = unsafe extern "C" fn(Component, Vr, usize, *const *const c_char) -> Status;
pub type GetFmuStateFn = unsafe extern "C" fn(Component, *mut FmuStatePtr) -> Status;
pub type SetFmuStateFn = unsafe extern "C" fn(Component, FmuStatePtr) -> Status;
pub type FreeFmuStateFn = unsafe extern "C" fn(Component, *mut FmuStatePtr) -> Status;
pub type SerializedFmuStateSizeFn =
    unsafe extern "C" fn(Component, FmuStatePtr, *mut usize) -> Status;
pub type SerializeFmuStateFn =
    unsafe extern "C" fn(Component, FmuStatePtr, *mut c_char, usize) -> Status;
pub type DeSerializeFmuStateFn =
    unsafe extern "C" fn(Component, *const c_char, usize, *mut FmuStatePtr) -> Status;
pub type GetDirectionalDerivativeFn =
    unsafe extern "C" fn(Component, Vr, usize, Vr, usize, *const f64, *mut f64) -> Status;

// Model Exchange functions.
pub type NewDiscreteStatesFn = unsafe extern "C" fn(Component, *mut EventInfo) -> Status;
pub type CompletedIntegratorStepFn =
    unsafe extern "C" fn(Component, Fmi2Boolean, *mut Fmi2Boolean, *mut Fmi2Boolean) -> Status;
pub type SetTimeFn = unsafe extern "C" fn(Component, f64) -> Status;
pub type SetContinuousStatesFn = unsafe extern "C" fn(Component, *const f64, usize) -> Status;
pub type GetRealArrayFn = unsafe extern "C" fn(Component, *mut f64, usize) -> Status;

// Co-Simulation functions.
pub type SetRealInputDerivativesFn =
    unsafe extern "C" fn(Component, Vr, usize, *const c_int, *const f64) -> Status;
pub type GetRealOutputDerivativesFn =
    unsafe extern "C" fn(Component, Vr, usize, *const c_int, *mut f64) -> Status;
pub type DoStepFn = unsafe extern "C" fn(Component, f64, f64, Fmi2Boolean) -> Status;
pub type GetStatusFn = unsafe extern "C" fn(Component, StatusKind, *mut Status) -> Status;
pub type GetRealStatusFn = unsafe extern "C" fn(Component, StatusKind, *mut f64) -> Status;
pub type GetIntegerStatusFn = unsafe extern "C" fn(Component, StatusKind, *mut c_int) -> Status;
pub type GetBooleanStatusFn =
    unsafe extern "C" fn(Component, StatusKind, *mut Fmi2Boolean) -> Status;
pub type GetStringStatusFn =
    unsafe extern "C" fn(Component, StatusKind, *mut *const c_char) -> Status;

/// Every function of `fmi2Functions.h`, resolved from one shared library.
///
/// The common and Co-Simulation functions are required (loading fails without them); the
/// Model Exchange ones are optional. The pointers are only valid while the [`Library`] they
/// came from is loaded: [`crate::Fmu`] owns both and never hands this table out without itself.
#[derive(Clone, Copy, Debug)]
pub struct Functions {
    // Common.
    pub get_types_platform: GetTypesPlatformFn,
    pub get_version: GetVersionFn,
    pub set_debug_logging: SetDebugLoggingFn,
    pub instantiate: InstantiateFn,
    pub free_instance: FreeInstanceFn,
    pub setup_experiment: SetupExperimentFn,
    pub enter_initialization_mode: ComponentFn,
    pub exit_initialization_mode: ComponentFn,
    pub terminate: ComponentFn,
    pub reset: ComponentFn,
    pub get_real: GetRealFn,
    pub get_integer: GetIntegerFn,
    pub get_boolean: GetBooleanFn,
    pub get_string: GetStringFn,
    pub set_real: SetRealFn,
    pub set_integer: SetIntegerFn,
    pub set_boolean: SetBooleanFn,
    pub set_string: SetStringFn,
    pub get_fmu_state: GetFmuStateFn,
    pub set_fmu_state: SetFmuStateFn,
    pub free_fmu_state: FreeFmuStateFn,
    pub serialized_fmu_state_size: SerializedFmuStateSizeFn,
    pub serialize_fmu_state: SerializeFmuStateFn,
    pub de_serialize_fmu_state: DeSerializeFmuStateFn,
    pub get_directional_derivative: GetDirectionalDerivativeFn,
    // Co-Simulation.
    pub set_real_input_derivatives: SetRealInputDerivativesFn,
    pub get_real_output_derivatives: GetRealOutputDerivativesFn,
    pub do_step: DoStepFn,
    pub cancel_step: ComponentFn,
    pub get_status: GetStatusFn,
    pub get_real_status: GetRealStatusFn,
    pub get_integer_status: GetIntegerStatusFn,
    pub get_boolean_status: GetBooleanStatusFn,
    pub get_string_status: GetStringStatusFn,
    // Model Exchange (optional).
    pub enter_event_mode: Option<ComponentFn>,
    pub new_discrete_states: Option<NewDiscreteStatesFn>,
    pub enter_continuous_time_mode: Option<ComponentFn>,
    pub completed_integrator_step: Option<CompletedIntegratorStepFn>,
    pub set_time: Option<SetTimeFn>,
    pub set_continuous_states: Option<SetContinuousStatesFn>,
    pub get_derivatives: Option<GetRealArrayFn>,
    pub get_event_indicators: Option<GetRealArrayFn>,
    pub get_continuous_states: Option<GetRealArrayFn>,
    pub get_nominals_of_continuous_states: Option<GetRealArrayFn>,
}

/// Looks up a required symbol.
///
/// # Safety
/// `T` must be the exact function pointer type of the C function named `name`.
unsafe fn required<T: Copy>(lib: &Library, name: &'static str) -> Result<T> {
    match lib.get::<T>(name) {
        Ok(symbol) => Ok(*symbol),
        Err(source) => Err(Error::MissingSymbol { name, source }),
    }
}

/// Looks up an optional symbol.
///
/// # Safety
/// As for [`required`].
unsafe fn optional<T: Copy>(lib: &Library, name: &'static str) -> Option<T> {
    lib.get::<T>(name).ok().map(|symbol| *symbol)
}

impl Functions {
    /// Resolves every `fmi2` function from `lib`.
    ///
    /// # Safety
    /// `lib` must be an FMI 2.0 binary: the exported `fmi2...` symbols must have the signatures
    /// of `fmi2FunctionTypes.h`. The returned pointers dangle once `lib` is unloaded.
    pub unsafe fn load(lib: &Library) -> Result<Functions> {
        Ok(Functions {
            get_types_platform: required(lib, "fmi2GetTypesPlatform")?,
            get_version: required(lib, "fmi2GetVersion")?,
            set_debug_logging: required(lib, "fmi2SetDebugLogging")?,
            instantiate: required(lib, "fmi2Instantiate")?,
            free_instance: required(lib, "fmi2FreeInstance")?,
            setup_experiment: required(lib, "fmi2SetupExperiment")?,
            enter_initialization_mode: required(lib, "fmi2EnterInitializationMode")?,
            exit_initialization_mode: required(lib, "fmi2ExitInitializationMode")?,
            terminate: required(lib, "fmi2Terminate")?,
            reset: required(lib, "fmi2Reset")?,
            get_real: required(lib, "fmi2GetReal")?,
            get_integer: required(lib, "fmi2GetInteger")?,
            get_boolean: required(lib, "fmi2GetBoolean")?,
            get_string: required(lib, "fmi2GetString")?,
            set_real: required(lib, "fmi2SetReal")?,
            set_integer: required(lib, "fmi2SetInteger")?,
            set_boolean: required(lib, "fmi2SetBoolean")?,
            set_string: required(lib, "fmi2SetString")?,
            get_fmu_state: required(lib, "fmi2GetFMUstate")?,
            set_fmu_state: required(lib, "fmi2SetFMUstate")?,
            free_fmu_state: required(lib, "fmi2FreeFMUstate")?,
            serialized_fmu_state_size: required(lib, "fmi2SerializedFMUstateSize")?,
            serialize_fmu_state: required(lib, "fmi2SerializeFMUstate")?,
            de_serialize_fmu_state: required(lib, "fmi2DeSerializeFMUstate")?,
            get_directional_derivative: required(lib, "fmi2GetDirectionalDerivative")?,
            set_real_input_derivatives: required(lib, "fmi2SetRealInputDerivatives")?,
            get_real_output_derivatives: required(lib, "fmi2GetRealOutputDerivatives")?,
            do_step: required(lib, "fmi2DoStep")?,
            cancel_step: required(lib, "fmi2CancelStep")?,
            get_status: required(lib, "fmi2GetStatus")?,
            get_real_status: required(lib, "fmi2GetRealStatus")?,
            get_integer_status: required(lib, "fmi2GetIntegerStatus")?,
            get_boolean_status: required(lib, "fmi2GetBooleanStatus")?,
            get_string_status: required(lib, "fmi2GetStringStatus")?,
            enter_event_mode: optional(lib, "fmi2EnterEventMode"),
            new_discrete_states: optional(lib, "fmi2NewDiscreteStates"),
            enter_continuous_time_mode: optional(lib, "fmi2EnterContinuousTimeMode"),
            completed_integrator_step: optional(lib, "fmi2CompletedIntegratorStep"),
            set_time: optional(lib, "fmi2SetTime"),
            set_continuous_states: optional(lib, "fmi2SetContinuousStates"),
            get_derivatives: optional(lib, "fmi2GetDerivatives"),
            get_event_indicators: optional(lib, "fmi2GetEventIndicators"),
            get_continuous_states: optional(lib, "fmi2GetContinuousStates"),
            get_nominals_of_continuous_states: optional(lib, "fmi2GetNominalsOfContinuousStates"),
        })
    }
}

// ---- FMI 3.0 -------------------------------------------------------------------------------

/// The FMI version of an FMU (its `fmiVersion`), which picks the function table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FmiVersion {
    /// FMI 2.0: `fmi2*` functions, `binaries/linux64`.
    Fmi2,
    /// FMI 3.0: `fmi3*` functions, `binaries/x86_64-linux`.
    Fmi3,
}

impl FmiVersion {
    /// `"2.0"` or `"3.0"`.
    pub fn text(self) -> &'static str {
        match self {
            FmiVersion::Fmi2 => "2.0",
            FmiVersion::Fmi3 => "3.0",
        }
    }

    /// The version of an `fmiVersion` attribute (`2.x` or `3.x`).
    pub fn of(fmi_version: &str) -> Option<FmiVersion> {
        if fmi_version.starts_with("2.") {
            Some(FmiVersion::Fmi2)
        } else if fmi_version.starts_with("3.") {
            Some(FmiVersion::Fmi3)
        } else {
            None
        }
    }
}

impl fmt::Display for FmiVersion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "FMI {}", self.text())
    }
}

/// `fmi3Instance`.
pub type Fmi3Instance = *mut c_void;
/// `fmi3InstanceEnvironment`.
pub type Fmi3InstanceEnvironment = *mut c_void;
/// `fmi3Boolean` is C `bool` (one byte). The host passes 0 or 1 and reads any non-zero byte the
/// FMU writes as true (a Rust `bool` holding another byte would be undefined behaviour).
pub type Fmi3Boolean = u8;
/// `fmi3True`.
pub const FMI3_TRUE: Fmi3Boolean = 1;
/// `fmi3False`.
pub const FMI3_FALSE: Fmi3Boolean = 0;

/// `fmi3LogMessageCallback(instanceEnvironment, status, category, message)`: not variadic,
/// the message is plain text.
pub type Fmi3LogMessageFn =
    unsafe extern "C" fn(Fmi3InstanceEnvironment, Status, *const c_char, *const c_char);
/// `fmi3IntermediateUpdateCallback` (never passed by this host: no intermediate update).
pub type Fmi3IntermediateUpdateFn = unsafe extern "C" fn(
    Fmi3InstanceEnvironment,
    f64,
    Fmi3Boolean,
    Fmi3Boolean,
    Fmi3Boolean,
    Fmi3Boolean,
    *mut Fmi3Boolean,
    *mut f64,
);
/// `fmi3ClockUpdateCallback`.
pub type Fmi3ClockUpdateFn = unsafe extern "C" fn(Fmi3InstanceEnvironment);
/// `fmi3LockPreemptionCallback` / `fmi3UnlockPreemptionCallback`.
pub type Fmi3PreemptionFn = unsafe extern "C" fn();

pub type Fmi3InstantiateModelExchangeFn = unsafe extern "C" fn(
    *const c_char,
    *const c_char,
    *const c_char,
    Fmi3Boolean,
    Fmi3Boolean,
    Fmi3InstanceEnvironment,
    Option<Fmi3LogMessageFn>,
) -> Fmi3Instance;
pub type Fmi3InstantiateCoSimulationFn = unsafe extern "C" fn(
    *const c_char,
    *const c_char,
    *const c_char,
    Fmi3Boolean,
    Fmi3Boolean,
    Fmi3Boolean,
    Fmi3Boolean,
    *const ValueReference,
    usize,
    Fmi3InstanceEnvironment,
    Option<Fmi3LogMessageFn>,
    Option<Fmi3IntermediateUpdateFn>,
) -> Fmi3Instance;
pub type Fmi3InstantiateScheduledExecutionFn = unsafe extern "C" fn(
    *const c_char,
    *const c_char,
    *const c_char,
    Fmi3Boolean,
    Fmi3Boolean,
    Fmi3InstanceEnvironment,
    Option<Fmi3LogMessageFn>,
    Option<Fmi3ClockUpdateFn>,
    Option<Fmi3PreemptionFn>,
    Option<Fmi3PreemptionFn>,
) -> Fmi3Instance;
pub type Fmi3SetDebugLoggingFn =
    unsafe extern "C" fn(Fmi3Instance, Fmi3Boolean, usize, *const *const c_char) -> Status;
pub type Fmi3FreeInstanceFn = unsafe extern "C" fn(Fmi3Instance);
pub type Fmi3EnterInitializationModeFn =
    unsafe extern "C" fn(Fmi3Instance, Fmi3Boolean, f64, f64, Fmi3Boolean, f64) -> Status;
pub type Fmi3InstanceFn = unsafe extern "C" fn(Fmi3Instance) -> Status;
/// `fmi3Get<Type>(instance, valueReferences, nValueReferences, values, nValues)`.
pub type Fmi3GetFn<T> = unsafe extern "C" fn(Fmi3Instance, Vr, usize, *mut T, usize) -> Status;
/// `fmi3Set<Type>(instance, valueReferences, nValueReferences, values, nValues)`.
pub type Fmi3SetFn<T> = unsafe extern "C" fn(Fmi3Instance, Vr, usize, *const T, usize) -> Status;
pub type Fmi3GetBinaryFn =
    unsafe extern "C" fn(Fmi3Instance, Vr, usize, *mut usize, *mut *const u8, usize) -> Status;
pub type Fmi3SetBinaryFn =
    unsafe extern "C" fn(Fmi3Instance, Vr, usize, *const usize, *const *const u8, usize) -> Status;
pub type Fmi3GetClockFn = unsafe extern "C" fn(Fmi3Instance, Vr, usize, *mut Fmi3Boolean) -> Status;
pub type Fmi3SetClockFn =
    unsafe extern "C" fn(Fmi3Instance, Vr, usize, *const Fmi3Boolean) -> Status;
pub type Fmi3GetIntervalDecimalFn =
    unsafe extern "C" fn(Fmi3Instance, Vr, usize, *mut f64, *mut c_int) -> Status;
pub type Fmi3GetNumberOfVariableDependenciesFn =
    unsafe extern "C" fn(Fmi3Instance, ValueReference, *mut usize) -> Status;
pub type Fmi3GetFmuStateFn = unsafe extern "C" fn(Fmi3Instance, *mut FmuStatePtr) -> Status;
pub type Fmi3SetFmuStateFn = unsafe extern "C" fn(Fmi3Instance, FmuStatePtr) -> Status;
pub type Fmi3SerializedFmuStateSizeFn =
    unsafe extern "C" fn(Fmi3Instance, FmuStatePtr, *mut usize) -> Status;
pub type Fmi3SerializeFmuStateFn =
    unsafe extern "C" fn(Fmi3Instance, FmuStatePtr, *mut u8, usize) -> Status;
pub type Fmi3DeserializeFmuStateFn =
    unsafe extern "C" fn(Fmi3Instance, *const u8, usize, *mut FmuStatePtr) -> Status;
/// `fmi3GetDirectionalDerivative` and `fmi3GetAdjointDerivative` (same signature).
pub type Fmi3DerivativeFn = unsafe extern "C" fn(
    Fmi3Instance,
    Vr,
    usize,
    Vr,
    usize,
    *const f64,
    usize,
    *mut f64,
    usize,
) -> Status;
pub type Fmi3UpdateDiscreteStatesFn = unsafe extern "C" fn(
    Fmi3Instance,
    *mut Fmi3Boolean,
    *mut Fmi3Boolean,
    *mut Fmi3Boolean,
    *mut Fmi3Boolean,
    *mut Fmi3Boolean,
    *mut f64,
) -> Status;
pub type Fmi3CompletedIntegratorStepFn =
    unsafe extern "C" fn(Fmi3Instance, Fmi3Boolean, *mut Fmi3Boolean, *mut Fmi3Boolean) -> Status;
pub type Fmi3SetTimeFn = unsafe extern "C" fn(Fmi3Instance, f64) -> Status;
pub type Fmi3SetContinuousStatesFn = unsafe extern "C" fn(Fmi3Instance, *const f64, usize) -> Status;
pub type Fmi3GetRealArrayFn = unsafe extern "C" fn(Fmi3Instance, *mut f64, usize) -> Status;
pub type Fmi3GetCountFn = unsafe extern "C" fn(Fmi3Instance, *mut usize) -> Status;
pub type Fmi3GetOutputDerivativesFn =
    unsafe extern "C" fn(Fmi3Instance, Vr, usize, *const c_int, *mut f64, usize) -> Status;
pub type Fmi3DoStepFn = unsafe extern "C" fn(
    Fmi3Instance,
    f64,
    f64,
    Fmi3Boolean,
    *mut Fmi3Boolean,
    *mut Fmi3Boolean,
    *mut Fmi3Boolean,
    *mut f64,
) -> Status;
pub type Fmi3ActivateModelPartitionFn =
    unsafe extern "C" fn(Fmi3Instance, ValueReference, f64) -> Status;

/// The functions of `fmi3Functions.h`, resolved from one shared library.
///
/// The common and Co-Simulation functions are required; the Model Exchange and Scheduled
/// Execution ones are optional (an FMU need not provide those interfaces). Same lifetime rule as
/// [`Functions`]. The getters and setters of the types the host has no typed method for
/// (Float32, the 8-, 16- and 64-bit and unsigned integers) are kept as untyped pointers, with
/// their names, for misuse tests.
#[derive(Clone, Copy, Debug)]
pub struct Fmi3Functions {
    // Common.
    pub get_version: GetVersionFn,
    pub set_debug_logging: Fmi3SetDebugLoggingFn,
    pub instantiate_co_simulation: Fmi3InstantiateCoSimulationFn,
    pub free_instance: Fmi3FreeInstanceFn,
    pub enter_initialization_mode: Fmi3EnterInitializationModeFn,
    pub exit_initialization_mode: Fmi3InstanceFn,
    pub terminate: Fmi3InstanceFn,
    pub reset: Fmi3InstanceFn,
    pub get_float64: Fmi3GetFn<f64>,
    pub get_int32: Fmi3GetFn<c_int>,
    /// Enumerations are read and set as Int64 in FMI 3.0.
    pub get_int64: Fmi3GetFn<i64>,
    pub get_boolean: Fmi3GetFn<Fmi3Boolean>,
    pub get_string: Fmi3GetFn<*const c_char>,
    pub get_binary: Fmi3GetBinaryFn,
    pub set_float64: Fmi3SetFn<f64>,
    pub set_int32: Fmi3SetFn<c_int>,
    pub set_int64: Fmi3SetFn<i64>,
    pub set_boolean: Fmi3SetFn<Fmi3Boolean>,
    pub set_string: Fmi3SetFn<*const c_char>,
    pub set_binary: Fmi3SetBinaryFn,
    /// `(name, fmi3Get<Type>, fmi3Set<Type>, size of one value)` of Float32, Int8, UInt8, Int16,
    /// UInt16, UInt32, Int64, UInt64.
    pub other_types: [(&'static str, Fmi3GetFn<c_void>, Fmi3SetFn<c_void>, usize); 8],
    pub get_clock: Fmi3GetClockFn,
    pub set_clock: Fmi3SetClockFn,
    pub get_interval_decimal: Fmi3GetIntervalDecimalFn,
    pub get_number_of_variable_dependencies: Fmi3GetNumberOfVariableDependenciesFn,
    pub get_fmu_state: Fmi3GetFmuStateFn,
    pub set_fmu_state: Fmi3SetFmuStateFn,
    pub free_fmu_state: Fmi3GetFmuStateFn,
    pub serialized_fmu_state_size: Fmi3SerializedFmuStateSizeFn,
    pub serialize_fmu_state: Fmi3SerializeFmuStateFn,
    pub deserialize_fmu_state: Fmi3DeserializeFmuStateFn,
    pub get_directional_derivative: Fmi3DerivativeFn,
    pub get_adjoint_derivative: Fmi3DerivativeFn,
    pub enter_configuration_mode: Fmi3InstanceFn,
    pub exit_configuration_mode: Fmi3InstanceFn,
    pub evaluate_discrete_states: Fmi3InstanceFn,
    pub update_discrete_states: Fmi3UpdateDiscreteStatesFn,
    pub enter_event_mode: Fmi3InstanceFn,
    // Co-Simulation.
    pub enter_step_mode: Fmi3InstanceFn,
    pub get_output_derivatives: Fmi3GetOutputDerivativesFn,
    pub do_step: Fmi3DoStepFn,
    // Model Exchange (optional).
    pub instantiate_model_exchange: Option<Fmi3InstantiateModelExchangeFn>,
    pub enter_continuous_time_mode: Option<Fmi3InstanceFn>,
    pub completed_integrator_step: Option<Fmi3CompletedIntegratorStepFn>,
    pub set_time: Option<Fmi3SetTimeFn>,
    pub set_continuous_states: Option<Fmi3SetContinuousStatesFn>,
    pub get_continuous_state_derivatives: Option<Fmi3GetRealArrayFn>,
    pub get_event_indicators: Option<Fmi3GetRealArrayFn>,
    pub get_continuous_states: Option<Fmi3GetRealArrayFn>,
    pub get_nominals_of_continuous_states: Option<Fmi3GetRealArrayFn>,
    pub get_number_of_event_indicators: Option<Fmi3GetCountFn>,
    pub get_number_of_continuous_states: Option<Fmi3GetCountFn>,
    // Scheduled Execution (optional).
    pub instantiate_scheduled_execution: Option<Fmi3InstantiateScheduledExecutionFn>,
    pub activate_model_partition: Option<Fmi3ActivateModelPartitionFn>,
}

impl Fmi3Functions {
    /// Resolves the `fmi3` functions from `lib`.
    ///
    /// # Safety
    /// `lib` must be an FMI 3.0 binary: the exported `fmi3...` symbols must have the signatures
    /// of `fmi3FunctionTypes.h`. The returned pointers dangle once `lib` is unloaded.
    pub unsafe fn load(lib: &Library) -> Result<Fmi3Functions> {
        macro_rules! typed {
            ($name:literal, $size:expr) => {
                ($name, required(lib, concat!("fmi3Get", $name))?, required(lib, concat!("fmi3Set", $name))?, $size)
            };
        }
        Ok(Fmi3Functions {
            get_version: required(lib, "fmi3GetVersion")?,
            set_debug_logging: required(lib, "fmi3SetDebugLogging")?,
            instantiate_co_simulation: required(lib, "fmi3InstantiateCoSimulation")?,
            free_instance: required(lib, "fmi3FreeInstance")?,
            enter_initialization_mode: required(lib, "fmi3EnterInitializationMode")?,
            exit_initialization_mode: required(lib, "fmi3ExitInitializationMode")?,
            terminate: required(lib, "fmi3Terminate")?,
            reset: required(lib, "fmi3Reset")?,
            get_float64: required(lib, "fmi3GetFloat64")?,
            get_int32: required(lib, "fmi3GetInt32")?,
            get_int64: required(lib, "fmi3GetInt64")?,
            get_boolean: required(lib, "fmi3GetBoolean")?,
            get_string: required(lib, "fmi3GetString")?,
            get_binary: required(lib, "fmi3GetBinary")?,
            set_float64: required(lib, "fmi3SetFloat64")?,
            set_int32: required(lib, "fmi3SetInt32")?,
            set_int64: required(lib, "fmi3SetInt64")?,
            set_boolean: required(lib, "fmi3SetBoolean")?,
            set_string: required(lib, "fmi3SetString")?,
            set_binary: required(lib, "fmi3SetBinary")?,
            other_types: [
                typed!("Float32", 4),
                typed!("Int8", 1),
                typed!("UInt8", 1),
                typed!("Int16", 2),
                typed!("UInt16", 2),
                typed!("UInt32", 4),
                typed!("Int64", 8),
                typed!("UInt64", 8),
            ],
            get_clock: required(lib, "fmi3GetClock")?,
            set_clock: required(lib, "fmi3SetClock")?,
            get_interval_decimal: required(lib, "fmi3GetIntervalDecimal")?,
            get_number_of_variable_dependencies: required(lib, "fmi3GetNumberOfVariableDependencies")?,
            get_fmu_state: required(lib, "fmi3GetFMUState")?,
            set_fmu_state: required(lib, "fmi3SetFMUState")?,
            free_fmu_state: required(lib, "fmi3FreeFMUState")?,
            serialized_fmu_state_size: required(lib, "fmi3SerializedFMUStateSize")?,
            serialize_fmu_state: required(lib, "fmi3SerializeFMUState")?,
            deserialize_fmu_state: required(lib, "fmi3DeserializeFMUState")?,
            get_directional_derivative: required(lib, "fmi3GetDirectionalDerivative")?,
            get_adjoint_derivative: required(lib, "fmi3GetAdjointDerivative")?,
            enter_configuration_mode: required(lib, "fmi3EnterConfigurationMode")?,
            exit_configuration_mode: required(lib, "fmi3ExitConfigurationMode")?,
            evaluate_discrete_states: required(lib, "fmi3EvaluateDiscreteStates")?,
            update_discrete_states: required(lib, "fmi3UpdateDiscreteStates")?,
            enter_event_mode: required(lib, "fmi3EnterEventMode")?,
            enter_step_mode: required(lib, "fmi3EnterStepMode")?,
            get_output_derivatives: required(lib, "fmi3GetOutputDerivatives")?,
            do_step: required(lib, "fmi3DoStep")?,
            instantiate_model_exchange: optional(lib, "fmi3InstantiateModelExchange"),
            enter_continuous_time_mode: optional(lib, "fmi3EnterContinuousTimeMode"),
            completed_integrator_step: optional(lib, "fmi3CompletedIntegratorStep"),
            set_time: optional(lib, "fmi3SetTime"),
            set_continuous_states: optional(lib, "fmi3SetContinuousStates"),
            get_continuous_state_derivatives: optional(lib, "fmi3GetContinuousStateDerivatives"),
            get_event_indicators: optional(lib, "fmi3GetEventIndicators"),
            get_continuous_states: optional(lib, "fmi3GetContinuousStates"),
            get_nominals_of_continuous_states: optional(lib, "fmi3GetNominalsOfContinuousStates"),
            get_number_of_event_indicators: optional(lib, "fmi3GetNumberOfEventIndicators"),
            get_number_of_continuous_states: optional(lib, "fmi3GetNumberOfContinuousStates"),
            instantiate_scheduled_execution: optional(lib, "fmi3InstantiateScheduledExecution"),
            activate_model_partition: optional(lib, "fmi3ActivateModelPartition"),
        })
    }
}

/// The function table of an FMU: FMI 2.0's or FMI 3.0's, after its `fmiVersion`.
#[derive(Clone, Copy, Debug)]
pub enum Api {
    Fmi2(Functions),
    Fmi3(Fmi3Functions),
}

impl Api {
    pub fn version(&self) -> FmiVersion {
        match self {
            Api::Fmi2(_) => FmiVersion::Fmi2,
            Api::Fmi3(_) => FmiVersion::Fmi3,
        }
    }
}
