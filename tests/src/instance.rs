//! [`Instance`]: one FMU instance (`fmi2Component` or `fmi3Instance`), with a thin method per
//! FMI function.
//!
//! Every method returns the [`Status`] the FMU returned, unchanged (plus the values it wrote):
//! judging the status is the caller's job. The only checks done here are the ones that keep the
//! calls memory-safe (slice lengths, NUL-free strings, a live component).
//!
//! The same methods drive FMI 2.0 and FMI 3.0 FMUs; the FMU's `fmiVersion` picks the function
//! (`get_real` is `fmi2GetReal` or `fmi3GetFloat64`, `new_discrete_states` is
//! `fmi2NewDiscreteStates` or `fmi3UpdateDiscreteStates`, ...). Where the versions differ:
//! * FMI 3.0 has no `fmi2SetupExperiment`: [`Instance::setup_experiment`] keeps the values
//!   (without calling the FMU) and [`Instance::enter_initialization_mode`] passes them to
//!   `fmi3EnterInitializationMode`;
//! * functions one version lacks (`fmi2SetRealInputDerivatives`, `fmi2CancelStep`,
//!   `fmi2Get*Status` in FMI 3.0; `fmi3GetAdjointDerivative`, `fmi3GetNumberOf*` in FMI 2.0)
//!   return [`Error::NotInVersion`] without calling anything.

use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::ptr::{self, NonNull};
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::ffi::{
    Api, CallbackFunctions, Component, EventInfo, Fmi2Boolean, Fmi2Type, Fmi3Boolean, FmiVersion,
    Status, StatusKind, ValueReference, FMI2_FALSE, FMI2_TRUE, FMI3_FALSE, FMI3_TRUE,
};
use crate::fmu::Fmu;
use crate::model_description::VariableType;
use crate::logger::{log_message_callback, logger_callback, LogCollector, LogSink};

extern "C" {
    // The C library's allocator, handed to the FMU as allocateMemory / freeMemory.
    fn calloc(nobj: usize, size: usize) -> *mut c_void;
    fn free(obj: *mut c_void);
}

fn fmi_bool(b: bool) -> Fmi2Boolean {
    if b {
        FMI2_TRUE
    } else {
        FMI2_FALSE
    }
}

fn fmi3_bool(b: bool) -> Fmi3Boolean {
    if b {
        FMI3_TRUE
    } else {
        FMI3_FALSE
    }
}

/// The `fmuResourceLocation` argument of `fmi2Instantiate` (`resourcePath` of FMI 3.0).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum ResourceLocation {
    /// `file:///.../resources` of the unpacked FMU (FMI 3.0: its absolute path, ending in `/`).
    #[default]
    Unpacked,
    /// A NULL pointer (misuse tests).
    Null,
    /// Any other string.
    Custom(String),
}

/// Arguments of `fmi2Instantiate` (`fmi3Instantiate...`) and host-side options. Build with
/// [`InstantiateOptions::new`] and the chainable setters.
#[derive(Clone, Debug)]
pub struct InstantiateOptions {
    pub instance_name: String,
    /// Co-Simulation or Model Exchange (FMI 3.0: `fmi3InstantiateCoSimulation` or
    /// `fmi3InstantiateModelExchange`).
    pub fmu_type: Fmi2Type,
    /// `None`: the guid (FMI 3.0: instantiationToken) of `modelDescription.xml`; `Some`: this
    /// string instead (misuse tests).
    pub guid: Option<String>,
    pub resource_location: ResourceLocation,
    pub visible: bool,
    pub logging_on: bool,
    /// Pass `calloc`/`free` as allocateMemory/freeMemory (true, the default) or NULL pointers
    /// (allowed for FMUs that declare `canNotUseMemoryManagementFunctions`). FMI 3.0 has no
    /// memory callbacks: ignored.
    pub memory_callbacks: bool,
    /// FMI 3.0 Co-Simulation: `eventModeUsed` (default false).
    pub event_mode_used: bool,
    /// FMI 3.0 Co-Simulation: `earlyReturnAllowed` (default false).
    pub early_return_allowed: bool,
    /// Print every log message to stderr as it arrives. Defaults to true when the environment
    /// variable `FMI_HOST_ECHO_LOG` is set.
    pub echo_log: bool,
}

impl InstantiateOptions {
    pub fn new(instance_name: impl Into<String>) -> InstantiateOptions {
        InstantiateOptions {
            instance_name: instance_name.into(),
            fmu_type: Fmi2Type::CoSimulation,
            guid: None,
            resource_location: ResourceLocation::Unpacked,
            visible: false,
            logging_on: false,
            memory_callbacks: true,
            event_mode_used: false,
            early_return_allowed: false,
            echo_log: std::env::var_os("FMI_HOST_ECHO_LOG").is_some(),
        }
    }
    pub fn fmu_type(mut self, fmu_type: Fmi2Type) -> Self {
        self.fmu_type = fmu_type;
        self
    }
    pub fn guid(mut self, guid: impl Into<String>) -> Self {
        self.guid = Some(guid.into());
        self
    }
    pub fn resource_location(mut self, location: ResourceLocation) -> Self {
        self.resource_location = location;
        self
    }
    pub fn visible(mut self, visible: bool) -> Self {
        self.visible = visible;
        self
    }
    pub fn logging_on(mut self, logging_on: bool) -> Self {
        self.logging_on = logging_on;
        self
    }
    pub fn memory_callbacks(mut self, on: bool) -> Self {
        self.memory_callbacks = on;
        self
    }
    pub fn event_mode_used(mut self, on: bool) -> Self {
        self.event_mode_used = on;
        self
    }
    pub fn early_return_allowed(mut self, on: bool) -> Self {
        self.early_return_allowed = on;
        self
    }
    pub fn echo_log(mut self, on: bool) -> Self {
        self.echo_log = on;
        self
    }
}

fn c_string(what: &str, s: &str) -> Result<CString> {
    CString::new(s)
        .map_err(|_| Error::InvalidArgument(format!("{what} contains a NUL byte: {s:?}")))
}

/// The experiment of `fmi2SetupExperiment`, kept for `fmi3EnterInitializationMode`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Experiment {
    tolerance: Option<f64>,
    start_time: f64,
    stop_time: Option<f64>,
}

/// What `fmi3DoStep` wrote besides its status.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DoStepOutcome {
    pub event_handling_needed: bool,
    pub terminate_simulation: bool,
    pub early_return: bool,
    pub last_successful_time: f64,
}

/// What both versions' instantiation functions take from the options: the instance name, the
/// guid (FMI 2.0) or instantiationToken (FMI 3.0), the resource location (FMI 2.0, a URI) or
/// path (FMI 3.0) as C strings, and the log sink the FMU's logger reaches (its environment).
struct Arguments {
    name: CString,
    token: CString,
    resources: Option<CString>,
    log: LogCollector,
    /// From Box::into_raw: owned by the instance once made (freed in Drop), else by the caller.
    sink: *mut LogSink,
}

impl Arguments {
    fn of(fmu: &Fmu, options: &InstantiateOptions, version: FmiVersion) -> Result<Arguments> {
        let (token_label, resource_label) = match version {
            FmiVersion::Fmi2 => ("guid", "resource location"),
            FmiVersion::Fmi3 => ("instantiationToken", "resource path"),
        };
        let name = c_string("instance name", &options.instance_name)?;
        let token = c_string(token_label, options.guid.as_deref().unwrap_or(&fmu.model_description().guid))?;
        let resources = match &options.resource_location {
            ResourceLocation::Unpacked => {
                let unpacked = match version {
                    FmiVersion::Fmi2 => fmu.resource_uri(),
                    FmiVersion::Fmi3 => fmu.resource_path(),
                };
                Some(c_string(resource_label, &unpacked)?)
            }
            ResourceLocation::Null => None,
            ResourceLocation::Custom(s) => Some(c_string(resource_label, s)?),
        };
        // Made last: nothing fallible follows, so the sink never leaks.
        let log = LogCollector::default();
        let sink = Box::into_raw(Box::new(LogSink {
            collector: log.clone(),
            echo: options.echo_log,
            instance_name: options.instance_name.clone(),
        }));
        Ok(Arguments { name, token, resources, log, sink })
    }
}

/// One FMU instance (`fmi2Component` / `fmi3Instance`), freed with `fmi2FreeInstance` /
/// `fmi3FreeInstance` on drop.
///
/// `Instance` is `Send` (it can be moved to another thread) but not `Sync`: the standard does
/// not require the functions of one instance to be thread-safe, and every call takes
/// `&mut self`.
pub struct Instance {
    component: NonNull<c_void>,
    fmu: Arc<Fmu>,
    name: String,
    log: LogCollector,
    // Owned through raw pointers (from Box::into_raw) because the FMU holds their addresses
    // for the whole life of the component; freed in Drop after fmi2FreeInstance. `callbacks` is
    // NULL for FMI 3.0 (the environment is the sink itself).
    callbacks: *mut CallbackFunctions,
    sink: *mut LogSink,
    /// FMI 3.0: the experiment of the last `setup_experiment`, for `fmi3EnterInitializationMode`.
    experiment: Experiment,
    /// FMI 3.0: what the last `fmi3DoStep` wrote.
    last_do_step: Option<DoStepOutcome>,
    // The strings given to fmi2Instantiate, kept alive in case the FMU did not copy them.
    _strings: Vec<CString>,
}

// SAFETY: the component is only used through `&mut self` (no concurrent calls into one
// instance); FMI 2.0 and 3.0 allow different instances to be used from different threads, and
// the logger sink is a Mutex-protected collector reached only through this instance.
unsafe impl Send for Instance {}

impl std::fmt::Debug for Instance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Instance")
            .field("name", &self.name)
            .field("component", &self.component)
            .finish_non_exhaustive()
    }
}

impl Fmu {
    /// `fmi2Instantiate` (`fmi3InstantiateCoSimulation`) as Co-Simulation with the guid
    /// (instantiationToken) of the model description.
    pub fn instantiate(
        self: &Arc<Self>,
        instance_name: &str,
        visible: bool,
        logging_on: bool,
    ) -> Result<Instance> {
        Instance::new(
            self,
            InstantiateOptions::new(instance_name)
                .visible(visible)
                .logging_on(logging_on),
        )
    }
}

/// The FMI 3.0 instantiation functions.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Fmi3Kind {
    ModelExchange,
    CoSimulation,
    ScheduledExecution,
}

impl Instance {
    /// `fmi2Instantiate` (FMI 3.0: `fmi3InstantiateCoSimulation` or
    /// `fmi3InstantiateModelExchange`) with every option. On NULL, returns
    /// [`Error::InstantiationFailed`] with the messages the FMU logged.
    pub fn new(fmu: &Arc<Fmu>, options: InstantiateOptions) -> Result<Instance> {
        match fmu.api() {
            Api::Fmi2(_) => Self::new_fmi2(fmu, options),
            Api::Fmi3(_) => {
                let kind = match options.fmu_type {
                    Fmi2Type::ModelExchange => Fmi3Kind::ModelExchange,
                    Fmi2Type::CoSimulation => Fmi3Kind::CoSimulation,
                };
                Self::new_fmi3(fmu, options, kind)
            }
        }
    }

    /// FMI 3.0 `fmi3InstantiateScheduledExecution` (no clock callbacks are given; the options'
    /// `fmu_type` is ignored). [`Error::NotInVersion`] for an FMI 2.0 FMU.
    pub fn new_scheduled_execution(fmu: &Arc<Fmu>, options: InstantiateOptions) -> Result<Instance> {
        match fmu.api() {
            Api::Fmi2(_) => Err(Error::NotInVersion {
                function: "fmi3InstantiateScheduledExecution",
                version: FmiVersion::Fmi2,
            }),
            Api::Fmi3(_) => Self::new_fmi3(fmu, options, Fmi3Kind::ScheduledExecution),
        }
    }

    fn new_fmi2(fmu: &Arc<Fmu>, options: InstantiateOptions) -> Result<Instance> {
        let Arguments { name, token: guid, resources, log, sink } = Arguments::of(fmu, &options, FmiVersion::Fmi2)?;
        let callbacks = Box::into_raw(Box::new(CallbackFunctions {
            logger: Some(logger_callback),
            allocate_memory: if options.memory_callbacks {
                Some(calloc)
            } else {
                None
            },
            free_memory: if options.memory_callbacks {
                Some(free)
            } else {
                None
            },
            step_finished: None,
            component_environment: sink.cast(),
        }));
        // SAFETY: every pointer is valid (or NULL where the standard's misuse is intended) for
        // the call; `callbacks` and `sink` stay valid until Drop, after fmi2FreeInstance.
        let component = unsafe {
            (fmu.functions().instantiate)(
                name.as_ptr(),
                options.fmu_type,
                guid.as_ptr(),
                resources.as_ref().map_or(ptr::null(), |r| r.as_ptr()),
                callbacks,
                fmi_bool(options.visible),
                fmi_bool(options.logging_on),
            )
        };
        let mut strings = vec![name, guid];
        strings.extend(resources);
        Self::made(fmu, options, component, callbacks, sink, log, strings)
    }

    fn new_fmi3(fmu: &Arc<Fmu>, options: InstantiateOptions, kind: Fmi3Kind) -> Result<Instance> {
        let f = *fmu.fmi3_functions().expect("an FMI 3.0 FMU");
        let Arguments { name, token, resources, log, sink } = Arguments::of(fmu, &options, FmiVersion::Fmi3)?;
        let resource_ptr = resources.as_ref().map_or(ptr::null(), |r| r.as_ptr());
        let (visible, logging_on) = (fmi3_bool(options.visible), fmi3_bool(options.logging_on));
        let free_sink = |sink: *mut LogSink| {
            // SAFETY: nothing was called with the sink yet; it came from Box::into_raw above.
            unsafe { drop(Box::from_raw(sink)) }
        };
        // SAFETY: every pointer is valid (or NULL where the standard's misuse is intended) for
        // the call; `sink`, the instanceEnvironment, stays valid until Drop, after
        // fmi3FreeInstance.
        let component = unsafe {
            match kind {
                Fmi3Kind::ModelExchange => {
                    let Some(instantiate) = f.instantiate_model_exchange else {
                        free_sink(sink);
                        return Err(Error::FunctionNotProvided("fmi3InstantiateModelExchange"));
                    };
                    instantiate(name.as_ptr(), token.as_ptr(), resource_ptr, visible, logging_on, sink.cast(), Some(log_message_callback))
                }
                Fmi3Kind::CoSimulation => (f.instantiate_co_simulation)(
                    name.as_ptr(),
                    token.as_ptr(),
                    resource_ptr,
                    visible,
                    logging_on,
                    fmi3_bool(options.event_mode_used),
                    fmi3_bool(options.early_return_allowed),
                    ptr::null(),
                    0,
                    sink.cast(),
                    Some(log_message_callback),
                    None,
                ),
                Fmi3Kind::ScheduledExecution => {
                    let Some(instantiate) = f.instantiate_scheduled_execution else {
                        free_sink(sink);
                        return Err(Error::FunctionNotProvided("fmi3InstantiateScheduledExecution"));
                    };
                    instantiate(name.as_ptr(), token.as_ptr(), resource_ptr, visible, logging_on, sink.cast(), Some(log_message_callback), None, None, None)
                }
            }
        };
        let mut strings = vec![name, token];
        strings.extend(resources);
        Self::made(fmu, options, component, ptr::null_mut(), sink, log, strings)
    }

    /// The instance for what an instantiation function returned, or its failure.
    fn made(
        fmu: &Arc<Fmu>,
        options: InstantiateOptions,
        component: Component,
        callbacks: *mut CallbackFunctions,
        sink: *mut LogSink,
        log: LogCollector,
        strings: Vec<CString>,
    ) -> Result<Instance> {
        match NonNull::new(component) {
            Some(component) => Ok(Instance {
                component,
                fmu: Arc::clone(fmu),
                name: options.instance_name,
                log,
                callbacks,
                sink,
                experiment: Experiment::default(),
                last_do_step: None,
                _strings: strings,
            }),
            None => {
                // SAFETY: the FMU returned NULL, so it has no component that could still use
                // the callbacks; both boxes came from Box::into_raw (callbacks may be NULL).
                unsafe {
                    if !callbacks.is_null() {
                        drop(Box::from_raw(callbacks));
                    }
                    drop(Box::from_raw(sink));
                }
                Err(Error::InstantiationFailed {
                    instance_name: options.instance_name,
                    log: log.records(),
                })
            }
        }
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn fmu(&self) -> &Arc<Fmu> {
        &self.fmu
    }

    /// FMI 2.0 or FMI 3.0 (the FMU's).
    pub fn fmi_version(&self) -> FmiVersion {
        self.fmu.fmi_version()
    }

    /// Every message the FMU logged for this instance (a shared handle: it keeps filling).
    pub fn log(&self) -> &LogCollector {
        &self.log
    }

    /// The FMU's function table (both versions).
    pub(crate) fn api(&self) -> &Api {
        self.fmu.api()
    }

    pub(crate) fn c(&self) -> Component {
        self.component.as_ptr()
    }

    /// ESCAPE HATCH: the raw `fmi2Component` (`fmi3Instance`), to call [`Fmu::api`] directly.
    /// Valid until this `Instance` is dropped.
    pub fn raw_component(&self) -> Component {
        self.c()
    }

    /// `fmi2FreeInstance` now (same as dropping).
    pub fn free(self) {
        drop(self);
    }

    fn not_in(&self, function: &'static str) -> Error {
        Error::NotInVersion { function, version: self.fmi_version() }
    }

    // ---- Common functions ------------------------------------------------------------------

    /// `fmi2SetDebugLogging` / `fmi3SetDebugLogging`.
    pub fn set_debug_logging(&mut self, logging_on: bool, categories: &[&CStr]) -> Status {
        let ptrs: Vec<*const c_char> = categories.iter().map(|c| c.as_ptr()).collect();
        // SAFETY: live component; `ptrs` holds `categories.len()` valid strings.
        unsafe {
            match self.api() {
                Api::Fmi2(f) => (f.set_debug_logging)(self.c(), fmi_bool(logging_on), ptrs.len(), ptrs.as_ptr()),
                Api::Fmi3(f) => (f.set_debug_logging)(self.c(), fmi3_bool(logging_on), ptrs.len(), ptrs.as_ptr()),
            }
        }
    }

    /// `fmi2SetupExperiment`: `None` for an undefined tolerance / stop time.
    ///
    /// FMI 3.0 has no such function: the values are kept (nothing is called, fmi2OK is
    /// returned) and given to the next `fmi3EnterInitializationMode`.
    pub fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Status {
        match self.api() {
            // SAFETY: live component, plain values.
            Api::Fmi2(f) => unsafe {
                (f.setup_experiment)(
                    self.c(),
                    fmi_bool(tolerance.is_some()),
                    tolerance.unwrap_or(0.0),
                    start_time,
                    fmi_bool(stop_time.is_some()),
                    stop_time.unwrap_or(0.0),
                )
            },
            Api::Fmi3(_) => {
                self.experiment = Experiment { tolerance, start_time, stop_time };
                Status::OK
            }
        }
    }

    /// `fmi2EnterInitializationMode`, or `fmi3EnterInitializationMode` with the experiment of
    /// the last [`Instance::setup_experiment`] (start time 0, no tolerance, no stop time if
    /// there was none since instantiation or the last reset).
    pub fn enter_initialization_mode(&mut self) -> Status {
        let e = self.experiment;
        // SAFETY: live component, plain values.
        unsafe {
            match self.api() {
                Api::Fmi2(f) => (f.enter_initialization_mode)(self.c()),
                Api::Fmi3(f) => (f.enter_initialization_mode)(
                    self.c(),
                    fmi3_bool(e.tolerance.is_some()),
                    e.tolerance.unwrap_or(0.0),
                    e.start_time,
                    fmi3_bool(e.stop_time.is_some()),
                    e.stop_time.unwrap_or(0.0),
                ),
            }
        }
    }

    /// `fmi2ExitInitializationMode` / `fmi3ExitInitializationMode`.
    pub fn exit_initialization_mode(&mut self) -> Status {
        // SAFETY: live component.
        unsafe {
            match self.api() {
                Api::Fmi2(f) => (f.exit_initialization_mode)(self.c()),
                Api::Fmi3(f) => (f.exit_initialization_mode)(self.c()),
            }
        }
    }

    /// `fmi2Terminate` / `fmi3Terminate`.
    pub fn terminate(&mut self) -> Status {
        // SAFETY: live component.
        unsafe {
            match self.api() {
                Api::Fmi2(f) => (f.terminate)(self.c()),
                Api::Fmi3(f) => (f.terminate)(self.c()),
            }
        }
    }

    /// `fmi2Reset` / `fmi3Reset` (FMI 3.0: the kept experiment is forgotten too, as an FMI 2.0
    /// FMU forgets its `fmi2SetupExperiment`).
    pub fn reset(&mut self) -> Status {
        // SAFETY: live component.
        let status = unsafe {
            match self.api() {
                Api::Fmi2(f) => (f.reset)(self.c()),
                Api::Fmi3(f) => (f.reset)(self.c()),
            }
        };
        if status.is_ok_or_warning() {
            self.experiment = Experiment::default();
            self.last_do_step = None;
        }
        status
    }

    // ---- Getting and setting values ----------------------------------------------------------

    /// `fmi2GetReal` / `fmi3GetFloat64`. Panics if `vr` and `values` differ in length (a host
    /// bug, not an FMU one).
    pub fn get_real(&mut self, vr: &[ValueReference], values: &mut [f64]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "get_real: one value per value reference"
        );
        // SAFETY: both arrays hold vr.len() elements.
        unsafe { self.get_real_raw(vr.as_ptr(), vr.len(), values.as_mut_ptr()) }
    }

    /// `fmi2GetReal` into a new Vec.
    pub fn get_reals(&mut self, vr: &[ValueReference]) -> (Status, Vec<f64>) {
        let mut values = vec![0.0; vr.len()];
        let status = self.get_real(vr, &mut values);
        (status, values)
    }

    /// `fmi2GetInteger` / `fmi3GetInt32`, or `fmi3GetInt64` for the Enumerations (the values of
    /// an Enumeration outside 32 bits read as `i32::MIN`).
    pub fn get_integer(&mut self, vr: &[ValueReference], values: &mut [i32]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "get_integer: one value per value reference"
        );
        let (n, p) = (vr.len(), values.as_mut_ptr());
        let c = self.c();
        match self.api() {
            // SAFETY: both arrays hold vr.len() elements.
            Api::Fmi2(f) => unsafe { (f.get_integer)(c, vr.as_ptr(), n, p) },
            Api::Fmi3(f) => {
                let (get_int32, get_int64) = (f.get_int32, f.get_int64);
                self.by_integer_kind(vr, |enumerations, vrs, at| {
                    let m = vrs.len();
                    if enumerations {
                        let mut wide = vec![0i64; m];
                        // SAFETY: both arrays hold m elements.
                        let status = unsafe { get_int64(c, vrs.as_ptr(), m, wide.as_mut_ptr(), m) };
                        for (&i, w) in at.iter().zip(wide) {
                            values[i] = i32::try_from(w).unwrap_or(i32::MIN);
                        }
                        status
                    } else {
                        let mut narrow = vec![0i32; m];
                        // SAFETY: both arrays hold m elements.
                        let status = unsafe { get_int32(c, vrs.as_ptr(), m, narrow.as_mut_ptr(), m) };
                        for (&i, v) in at.iter().zip(narrow) {
                            values[i] = v;
                        }
                        status
                    }
                })
            }
        }
    }

    /// Calls `call(enumerations, value references, their positions in vr)` once for the
    /// Enumerations among `vr` and once for the others (value references this FMU does not
    /// declare count as others): FMI 3.0 reads and sets an Enumeration with fmi3Get/SetInt64,
    /// an Int32 with fmi3Get/SetInt32. Returns the worse status.
    fn by_integer_kind(
        &self,
        vr: &[ValueReference],
        mut call: impl FnMut(bool, &[ValueReference], &[usize]) -> Status,
    ) -> Status {
        let description = self.fmu.model_description();
        let is_enumeration = |r: &ValueReference| {
            description
                .model_variables
                .iter()
                .any(|v| v.value_reference == *r && v.variable_type == VariableType::Enumeration)
        };
        let (enums, others): (Vec<usize>, Vec<usize>) = (0..vr.len()).partition(|&i| is_enumeration(&vr[i]));
        let mut worst = Status::OK;
        for (enumerations, at) in [(true, enums), (false, others)] {
            if at.is_empty() && (enumerations || !vr.is_empty()) {
                continue;
            }
            let vrs: Vec<ValueReference> = at.iter().map(|&i| vr[i]).collect();
            let status = call(enumerations, &vrs, &at);
            if status.0 > worst.0 {
                worst = status;
            }
        }
        worst
    }

    /// `fmi2GetBoolean` / `fmi3GetBoolean` (any non-zero value reads as `true`).
    pub fn get_boolean(&mut self, vr: &[ValueReference], values: &mut [bool]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "get_boolean: one value per value reference"
        );
        let n = vr.len();
        // SAFETY: both arrays hold vr.len() elements.
        match self.api() {
            Api::Fmi2(f) => {
                let mut raw = vec![FMI2_FALSE; n];
                let status = unsafe { (f.get_boolean)(self.c(), vr.as_ptr(), n, raw.as_mut_ptr()) };
                for (v, r) in values.iter_mut().zip(raw) {
                    *v = r != FMI2_FALSE;
                }
                status
            }
            Api::Fmi3(f) => {
                let mut raw = vec![FMI3_FALSE; n];
                let status = unsafe { (f.get_boolean)(self.c(), vr.as_ptr(), n, raw.as_mut_ptr(), n) };
                for (v, r) in values.iter_mut().zip(raw) {
                    *v = r != FMI3_FALSE;
                }
                status
            }
        }
    }

    /// `fmi2GetString` / `fmi3GetString`; the strings are copied (a NULL string reads as
    /// empty).
    pub fn get_string(&mut self, vr: &[ValueReference], values: &mut [String]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "get_string: one value per value reference"
        );
        let n = vr.len();
        let mut raw: Vec<*const c_char> = vec![ptr::null(); n];
        // SAFETY: both arrays hold vr.len() elements; the FMU's strings are valid until the
        // next call into this instance, and are copied right away.
        unsafe {
            let status = match self.api() {
                Api::Fmi2(f) => (f.get_string)(self.c(), vr.as_ptr(), n, raw.as_mut_ptr()),
                Api::Fmi3(f) => (f.get_string)(self.c(), vr.as_ptr(), n, raw.as_mut_ptr(), n),
            };
            for (v, r) in values.iter_mut().zip(raw) {
                *v = if r.is_null() {
                    String::new()
                } else {
                    CStr::from_ptr(r).to_string_lossy().into_owned()
                };
            }
            status
        }
    }

    /// `fmi2SetReal` / `fmi3SetFloat64`.
    pub fn set_real(&mut self, vr: &[ValueReference], values: &[f64]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "set_real: one value per value reference"
        );
        // SAFETY: both arrays hold vr.len() elements.
        unsafe { self.set_real_raw(vr.as_ptr(), vr.len(), values.as_ptr()) }
    }

    /// `fmi2SetInteger` / `fmi3SetInt32`, or `fmi3SetInt64` for the Enumerations.
    pub fn set_integer(&mut self, vr: &[ValueReference], values: &[i32]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "set_integer: one value per value reference"
        );
        let n = vr.len();
        let c = self.c();
        match self.api() {
            // SAFETY: both arrays hold vr.len() elements.
            Api::Fmi2(f) => unsafe { (f.set_integer)(c, vr.as_ptr(), n, values.as_ptr()) },
            Api::Fmi3(f) => {
                let (set_int32, set_int64) = (f.set_int32, f.set_int64);
                self.by_integer_kind(vr, |enumerations, vrs, at| {
                    let m = vrs.len();
                    if enumerations {
                        let wide: Vec<i64> = at.iter().map(|&i| i64::from(values[i])).collect();
                        // SAFETY: both arrays hold m elements.
                        unsafe { set_int64(c, vrs.as_ptr(), m, wide.as_ptr(), m) }
                    } else {
                        let narrow: Vec<i32> = at.iter().map(|&i| values[i]).collect();
                        // SAFETY: both arrays hold m elements.
                        unsafe { set_int32(c, vrs.as_ptr(), m, narrow.as_ptr(), m) }
                    }
                })
            }
        }
    }

    /// `fmi2SetBoolean` / `fmi3SetBoolean`.
    pub fn set_boolean(&mut self, vr: &[ValueReference], values: &[bool]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "set_boolean: one value per value reference"
        );
        let n = vr.len();
        // SAFETY: both arrays hold vr.len() elements.
        match self.api() {
            Api::Fmi2(f) => {
                let raw: Vec<Fmi2Boolean> = values.iter().map(|&b| fmi_bool(b)).collect();
                unsafe { (f.set_boolean)(self.c(), vr.as_ptr(), n, raw.as_ptr()) }
            }
            Api::Fmi3(f) => {
                let raw: Vec<Fmi3Boolean> = values.iter().map(|&b| fmi3_bool(b)).collect();
                unsafe { (f.set_boolean)(self.c(), vr.as_ptr(), n, raw.as_ptr(), n) }
            }
        }
    }

    /// `fmi2SetString` / `fmi3SetString`.
    pub fn set_string(&mut self, vr: &[ValueReference], values: &[&CStr]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "set_string: one value per value reference"
        );
        let raw: Vec<*const c_char> = values.iter().map(|s| s.as_ptr()).collect();
        let n = vr.len();
        // SAFETY: both arrays hold vr.len() elements, the strings outlive the call.
        unsafe {
            match self.api() {
                Api::Fmi2(f) => (f.set_string)(self.c(), vr.as_ptr(), n, raw.as_ptr()),
                Api::Fmi3(f) => (f.set_string)(self.c(), vr.as_ptr(), n, raw.as_ptr(), n),
            }
        }
    }

    /// ESCAPE HATCH (misuse tests): `fmi2GetReal` (`fmi3GetFloat64`, with `nValues = nvr`) with
    /// caller-chosen raw pointers, e.g. a NULL value-reference array with `nvr > 0`.
    ///
    /// # Safety
    /// Whatever the FMU does with these pointers: if it does not reject invalid ones it may
    /// read or write through them.
    pub unsafe fn get_real_raw(
        &mut self,
        vr: *const ValueReference,
        nvr: usize,
        values: *mut f64,
    ) -> Status {
        match self.api() {
            Api::Fmi2(f) => (f.get_real)(self.c(), vr, nvr, values),
            Api::Fmi3(f) => (f.get_float64)(self.c(), vr, nvr, values, nvr),
        }
    }

    /// ESCAPE HATCH (misuse tests): `fmi2SetReal` (`fmi3SetFloat64`) with caller-chosen raw
    /// pointers.
    ///
    /// # Safety
    /// As for [`Instance::get_real_raw`].
    pub unsafe fn set_real_raw(
        &mut self,
        vr: *const ValueReference,
        nvr: usize,
        values: *const f64,
    ) -> Status {
        match self.api() {
            Api::Fmi2(f) => (f.set_real)(self.c(), vr, nvr, values),
            Api::Fmi3(f) => (f.set_float64)(self.c(), vr, nvr, values, nvr),
        }
    }

    // ---- Partial derivatives -----------------------------------------------------------------

    /// `fmi2GetDirectionalDerivative` / `fmi3GetDirectionalDerivative`.
    pub fn get_directional_derivative(
        &mut self,
        unknown: &[ValueReference],
        known: &[ValueReference],
        dv_known: &[f64],
        dv_unknown: &mut [f64],
    ) -> Status {
        assert_eq!(known.len(), dv_known.len(), "one seed per known");
        assert_eq!(unknown.len(), dv_unknown.len(), "one result per unknown");
        let (nu, nk) = (unknown.len(), known.len());
        // SAFETY: every array holds the length passed with it.
        unsafe {
            match self.api() {
                Api::Fmi2(f) => (f.get_directional_derivative)(
                    self.c(),
                    unknown.as_ptr(),
                    nu,
                    known.as_ptr(),
                    nk,
                    dv_known.as_ptr(),
                    dv_unknown.as_mut_ptr(),
                ),
                Api::Fmi3(f) => (f.get_directional_derivative)(
                    self.c(),
                    unknown.as_ptr(),
                    nu,
                    known.as_ptr(),
                    nk,
                    dv_known.as_ptr(),
                    nk,
                    dv_unknown.as_mut_ptr(),
                    nu,
                ),
            }
        }
    }

    /// `fmi3GetAdjointDerivative`: `sensitivity = seed^T J` (one seed per unknown, one
    /// sensitivity per known). FMI 2.0 has none: [`Error::NotInVersion`].
    pub fn get_adjoint_derivative(
        &mut self,
        unknown: &[ValueReference],
        known: &[ValueReference],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> Result<Status> {
        assert_eq!(unknown.len(), seed.len(), "one seed per unknown");
        assert_eq!(known.len(), sensitivity.len(), "one sensitivity per known");
        match self.api() {
            Api::Fmi2(_) => Err(self.not_in("fmi3GetAdjointDerivative")),
            // SAFETY: every array holds the length passed with it.
            Api::Fmi3(f) => Ok(unsafe {
                (f.get_adjoint_derivative)(
                    self.c(),
                    unknown.as_ptr(),
                    unknown.len(),
                    known.as_ptr(),
                    known.len(),
                    seed.as_ptr(),
                    seed.len(),
                    sensitivity.as_mut_ptr(),
                    sensitivity.len(),
                )
            }),
        }
    }

    // ---- Co-Simulation -----------------------------------------------------------------------

    /// `fmi2SetRealInputDerivatives` (FMI 3.0 has none: [`Error::NotInVersion`]).
    pub fn set_real_input_derivatives(
        &mut self,
        vr: &[ValueReference],
        order: &[i32],
        values: &[f64],
    ) -> Result<Status> {
        assert!(
            order.len() == vr.len() && values.len() == vr.len(),
            "one order and value per vr"
        );
        match self.api() {
            // SAFETY: every array holds vr.len() elements.
            Api::Fmi2(f) => Ok(unsafe {
                (f.set_real_input_derivatives)(
                    self.c(),
                    vr.as_ptr(),
                    vr.len(),
                    order.as_ptr(),
                    values.as_ptr(),
                )
            }),
            Api::Fmi3(_) => Err(self.not_in("fmi2SetRealInputDerivatives")),
        }
    }

    /// `fmi2GetRealOutputDerivatives` / `fmi3GetOutputDerivatives`.
    pub fn get_real_output_derivatives(
        &mut self,
        vr: &[ValueReference],
        order: &[i32],
        values: &mut [f64],
    ) -> Status {
        assert!(
            order.len() == vr.len() && values.len() == vr.len(),
            "one order and value per vr"
        );
        let n = vr.len();
        // SAFETY: every array holds vr.len() elements.
        unsafe {
            match self.api() {
                Api::Fmi2(f) => (f.get_real_output_derivatives)(
                    self.c(),
                    vr.as_ptr(),
                    n,
                    order.as_ptr(),
                    values.as_mut_ptr(),
                ),
                Api::Fmi3(f) => (f.get_output_derivatives)(
                    self.c(),
                    vr.as_ptr(),
                    n,
                    order.as_ptr(),
                    values.as_mut_ptr(),
                    n,
                ),
            }
        }
    }

    /// `fmi2DoStep` / `fmi3DoStep` (FMI 3.0: what it wrote besides the status is kept, see
    /// [`Instance::last_do_step`]).
    pub fn do_step(
        &mut self,
        current_communication_point: f64,
        step_size: f64,
        no_set_fmu_state_prior: bool,
    ) -> Status {
        match self.api() {
            // SAFETY: live component, plain values.
            Api::Fmi2(f) => unsafe {
                (f.do_step)(
                    self.c(),
                    current_communication_point,
                    step_size,
                    fmi_bool(no_set_fmu_state_prior),
                )
            },
            Api::Fmi3(f) => {
                let f = *f;
                let (mut event, mut terminate, mut early, mut last) = (FMI3_FALSE, FMI3_FALSE, FMI3_FALSE, f64::NAN);
                // SAFETY: live component, valid out pointers.
                let status = unsafe {
                    (f.do_step)(
                        self.c(),
                        current_communication_point,
                        step_size,
                        fmi3_bool(no_set_fmu_state_prior),
                        &mut event,
                        &mut terminate,
                        &mut early,
                        &mut last,
                    )
                };
                self.last_do_step = Some(DoStepOutcome {
                    event_handling_needed: event != FMI3_FALSE,
                    terminate_simulation: terminate != FMI3_FALSE,
                    early_return: early != FMI3_FALSE,
                    last_successful_time: last,
                });
                status
            }
        }
    }

    /// FMI 3.0: what the last `fmi3DoStep` wrote (eventHandlingNeeded, terminateSimulation,
    /// earlyReturn, lastSuccessfulTime); `None` before the first step, after a reset, and for
    /// FMI 2.0 (which has `fmi2GetRealStatus(fmi2LastSuccessfulTime)` instead).
    pub fn last_do_step(&self) -> Option<DoStepOutcome> {
        self.last_do_step
    }

    /// `fmi2CancelStep` (FMI 3.0 has none: [`Error::NotInVersion`]).
    pub fn cancel_step(&mut self) -> Result<Status> {
        match self.api() {
            // SAFETY: live component.
            Api::Fmi2(f) => Ok(unsafe { (f.cancel_step)(self.c()) }),
            Api::Fmi3(_) => Err(self.not_in("fmi2CancelStep")),
        }
    }

    /// `fmi2GetStatus`: (returned status, value). FMI 3.0 has none: [`Error::NotInVersion`].
    pub fn get_status(&mut self, kind: StatusKind) -> Result<(Status, Status)> {
        let mut value = Status::OK;
        match self.api() {
            // SAFETY: `value` is a valid out pointer.
            Api::Fmi2(f) => Ok((unsafe { (f.get_status)(self.c(), kind, &mut value) }, value)),
            Api::Fmi3(_) => Err(self.not_in("fmi2GetStatus")),
        }
    }

    /// `fmi2GetRealStatus` (e.g. `fmi2LastSuccessfulTime`; FMI 3.0: [`Error::NotInVersion`],
    /// see [`Instance::last_do_step`]).
    pub fn get_real_status(&mut self, kind: StatusKind) -> Result<(Status, f64)> {
        let mut value = 0.0;
        match self.api() {
            // SAFETY: `value` is a valid out pointer.
            Api::Fmi2(f) => Ok((unsafe { (f.get_real_status)(self.c(), kind, &mut value) }, value)),
            Api::Fmi3(_) => Err(self.not_in("fmi2GetRealStatus")),
        }
    }

    /// `fmi2GetIntegerStatus` (FMI 3.0: [`Error::NotInVersion`]).
    pub fn get_integer_status(&mut self, kind: StatusKind) -> Result<(Status, i32)> {
        let mut value: c_int = 0;
        match self.api() {
            // SAFETY: `value` is a valid out pointer.
            Api::Fmi2(f) => Ok((unsafe { (f.get_integer_status)(self.c(), kind, &mut value) }, value)),
            Api::Fmi3(_) => Err(self.not_in("fmi2GetIntegerStatus")),
        }
    }

    /// `fmi2GetBooleanStatus` (e.g. `fmi2Terminated`; FMI 3.0: [`Error::NotInVersion`]).
    pub fn get_boolean_status(&mut self, kind: StatusKind) -> Result<(Status, bool)> {
        let mut value = FMI2_FALSE;
        match self.api() {
            // SAFETY: `value` is a valid out pointer.
            Api::Fmi2(f) => {
                let status = unsafe { (f.get_boolean_status)(self.c(), kind, &mut value) };
                Ok((status, value != FMI2_FALSE))
            }
            Api::Fmi3(_) => Err(self.not_in("fmi2GetBooleanStatus")),
        }
    }

    /// `fmi2GetStringStatus` (`None` if the FMU left the string NULL; FMI 3.0:
    /// [`Error::NotInVersion`]).
    pub fn get_string_status(&mut self, kind: StatusKind) -> Result<(Status, Option<String>)> {
        let mut value: *const c_char = ptr::null();
        match self.api() {
            // SAFETY: `value` is a valid out pointer; the string is copied right away.
            Api::Fmi2(f) => unsafe {
                let status = (f.get_string_status)(self.c(), kind, &mut value);
                let text =
                    (!value.is_null()).then(|| CStr::from_ptr(value).to_string_lossy().into_owned());
                Ok((status, text))
            },
            Api::Fmi3(_) => Err(self.not_in("fmi2GetStringStatus")),
        }
    }

    // ---- Model Exchange (optional functions: Err if the FMU does not export them) -------------

    fn me<T>(f: Option<T>, name: &'static str) -> Result<T> {
        f.ok_or(Error::FunctionNotProvided(name))
    }

    /// `fmi2EnterEventMode` / `fmi3EnterEventMode`.
    pub fn enter_event_mode(&mut self) -> Result<Status> {
        let f = match self.api() {
            Api::Fmi2(f) => Self::me(f.enter_event_mode, "fmi2EnterEventMode")?,
            Api::Fmi3(f) => f.enter_event_mode,
        };
        // SAFETY: live component.
        Ok(unsafe { f(self.c()) })
    }

    /// `fmi2NewDiscreteStates`, or `fmi3UpdateDiscreteStates` with its flags written into
    /// `event_info` as `fmi2EventInfo` holds them.
    pub fn new_discrete_states(&mut self, event_info: &mut EventInfo) -> Result<Status> {
        match self.api() {
            Api::Fmi2(f) => {
                let f = Self::me(f.new_discrete_states, "fmi2NewDiscreteStates")?;
                // SAFETY: valid out pointer.
                Ok(unsafe { f(self.c(), event_info) })
            }
            Api::Fmi3(f) => {
                let (mut need, mut terminate, mut nominals, mut values, mut defined) =
                    (FMI3_FALSE, FMI3_FALSE, FMI3_FALSE, FMI3_FALSE, FMI3_FALSE);
                let mut next = 0.0;
                // SAFETY: valid out pointers.
                let status = unsafe {
                    (f.update_discrete_states)(self.c(), &mut need, &mut terminate, &mut nominals, &mut values, &mut defined, &mut next)
                };
                let b = |v: Fmi3Boolean| fmi_bool(v != FMI3_FALSE);
                *event_info = EventInfo {
                    new_discrete_states_needed: b(need),
                    terminate_simulation: b(terminate),
                    nominals_of_continuous_states_changed: b(nominals),
                    values_of_continuous_states_changed: b(values),
                    next_event_time_defined: b(defined),
                    next_event_time: next,
                };
                Ok(status)
            }
        }
    }

    /// `fmi2EnterContinuousTimeMode` / `fmi3EnterContinuousTimeMode`.
    pub fn enter_continuous_time_mode(&mut self) -> Result<Status> {
        let f = match self.api() {
            Api::Fmi2(f) => Self::me(f.enter_continuous_time_mode, "fmi2EnterContinuousTimeMode")?,
            Api::Fmi3(f) => Self::me(f.enter_continuous_time_mode, "fmi3EnterContinuousTimeMode")?,
        };
        // SAFETY: live component.
        Ok(unsafe { f(self.c()) })
    }

    /// `fmi2CompletedIntegratorStep` / `fmi3CompletedIntegratorStep`: (status, enterEventMode,
    /// terminateSimulation).
    pub fn completed_integrator_step(
        &mut self,
        no_set_fmu_state_prior: bool,
    ) -> Result<(Status, bool, bool)> {
        match self.api() {
            Api::Fmi2(f) => {
                let f = Self::me(f.completed_integrator_step, "fmi2CompletedIntegratorStep")?;
                let (mut enter, mut terminate) = (FMI2_FALSE, FMI2_FALSE);
                // SAFETY: valid out pointers.
                let status = unsafe {
                    f(
                        self.c(),
                        fmi_bool(no_set_fmu_state_prior),
                        &mut enter,
                        &mut terminate,
                    )
                };
                Ok((status, enter != FMI2_FALSE, terminate != FMI2_FALSE))
            }
            Api::Fmi3(f) => {
                let f = Self::me(f.completed_integrator_step, "fmi3CompletedIntegratorStep")?;
                let (mut enter, mut terminate) = (FMI3_FALSE, FMI3_FALSE);
                // SAFETY: valid out pointers.
                let status = unsafe { f(self.c(), fmi3_bool(no_set_fmu_state_prior), &mut enter, &mut terminate) };
                Ok((status, enter != FMI3_FALSE, terminate != FMI3_FALSE))
            }
        }
    }

    /// `fmi2SetTime` / `fmi3SetTime`.
    pub fn set_time(&mut self, time: f64) -> Result<Status> {
        let f = match self.api() {
            Api::Fmi2(f) => Self::me(f.set_time, "fmi2SetTime")?,
            Api::Fmi3(f) => Self::me(f.set_time, "fmi3SetTime")?,
        };
        // SAFETY: live component.
        Ok(unsafe { f(self.c(), time) })
    }

    /// `fmi2SetContinuousStates` / `fmi3SetContinuousStates`.
    pub fn set_continuous_states(&mut self, x: &[f64]) -> Result<Status> {
        let f = match self.api() {
            Api::Fmi2(f) => Self::me(f.set_continuous_states, "fmi2SetContinuousStates")?,
            Api::Fmi3(f) => Self::me(f.set_continuous_states, "fmi3SetContinuousStates")?,
        };
        // SAFETY: x holds x.len() values.
        Ok(unsafe { f(self.c(), x.as_ptr(), x.len()) })
    }

    /// `fmi2GetDerivatives` / `fmi3GetContinuousStateDerivatives`.
    pub fn get_derivatives(&mut self, dx: &mut [f64]) -> Result<Status> {
        let f = match self.api() {
            Api::Fmi2(f) => Self::me(f.get_derivatives, "fmi2GetDerivatives")?,
            Api::Fmi3(f) => Self::me(f.get_continuous_state_derivatives, "fmi3GetContinuousStateDerivatives")?,
        };
        // SAFETY: dx holds dx.len() values.
        Ok(unsafe { f(self.c(), dx.as_mut_ptr(), dx.len()) })
    }

    /// `fmi2GetEventIndicators` / `fmi3GetEventIndicators`.
    pub fn get_event_indicators(&mut self, z: &mut [f64]) -> Result<Status> {
        let f = match self.api() {
            Api::Fmi2(f) => Self::me(f.get_event_indicators, "fmi2GetEventIndicators")?,
            Api::Fmi3(f) => Self::me(f.get_event_indicators, "fmi3GetEventIndicators")?,
        };
        // SAFETY: z holds z.len() values.
        Ok(unsafe { f(self.c(), z.as_mut_ptr(), z.len()) })
    }

    /// `fmi2GetContinuousStates` / `fmi3GetContinuousStates`.
    pub fn get_continuous_states(&mut self, x: &mut [f64]) -> Result<Status> {
        let f = match self.api() {
            Api::Fmi2(f) => Self::me(f.get_continuous_states, "fmi2GetContinuousStates")?,
            Api::Fmi3(f) => Self::me(f.get_continuous_states, "fmi3GetContinuousStates")?,
        };
        // SAFETY: x holds x.len() values.
        Ok(unsafe { f(self.c(), x.as_mut_ptr(), x.len()) })
    }

    /// `fmi2GetNominalsOfContinuousStates` / `fmi3GetNominalsOfContinuousStates`.
    pub fn get_nominals_of_continuous_states(&mut self, x: &mut [f64]) -> Result<Status> {
        let f = match self.api() {
            Api::Fmi2(f) => Self::me(f.get_nominals_of_continuous_states, "fmi2GetNominalsOfContinuousStates")?,
            Api::Fmi3(f) => Self::me(f.get_nominals_of_continuous_states, "fmi3GetNominalsOfContinuousStates")?,
        };
        // SAFETY: x holds x.len() values.
        Ok(unsafe { f(self.c(), x.as_mut_ptr(), x.len()) })
    }

    /// `fmi3GetNumberOfContinuousStates`: (status, count). FMI 2.0 has none (the description
    /// counts them): [`Error::NotInVersion`].
    pub fn get_number_of_continuous_states(&mut self) -> Result<(Status, usize)> {
        match self.api() {
            Api::Fmi2(_) => Err(self.not_in("fmi3GetNumberOfContinuousStates")),
            Api::Fmi3(f) => {
                let f = Self::me(f.get_number_of_continuous_states, "fmi3GetNumberOfContinuousStates")?;
                let mut n = 0usize;
                // SAFETY: valid out pointer.
                Ok((unsafe { f(self.c(), &mut n) }, n))
            }
        }
    }

    /// `fmi3GetNumberOfEventIndicators`: (status, count). FMI 2.0: [`Error::NotInVersion`].
    pub fn get_number_of_event_indicators(&mut self) -> Result<(Status, usize)> {
        match self.api() {
            Api::Fmi2(_) => Err(self.not_in("fmi3GetNumberOfEventIndicators")),
            Api::Fmi3(f) => {
                let f = Self::me(f.get_number_of_event_indicators, "fmi3GetNumberOfEventIndicators")?;
                let mut n = 0usize;
                // SAFETY: valid out pointer.
                Ok((unsafe { f(self.c(), &mut n) }, n))
            }
        }
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: the component is live and freed exactly once; the FMU may log during
        // fmi2FreeInstance, so the sink and callbacks are freed only afterwards. Both came
        // from Box::into_raw in Instance::new (callbacks is NULL for FMI 3.0).
        unsafe {
            match self.api() {
                Api::Fmi2(f) => (f.free_instance)(self.c()),
                Api::Fmi3(f) => (f.free_instance)(self.c()),
            }
            if !self.callbacks.is_null() {
                drop(Box::from_raw(self.callbacks));
            }
            drop(Box::from_raw(self.sink));
        }
    }
}
