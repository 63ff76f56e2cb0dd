//! [`Instance`]: one `fmi2Component`, with a thin method per fmi2 function.
//!
//! Every method returns the [`Status`] the FMU returned, unchanged (plus the values it wrote):
//! judging the status is the caller's job. The only checks done here are the ones that keep the
//! calls memory-safe (slice lengths, NUL-free strings, a live component).

use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::ptr::{self, NonNull};
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::ffi::{
    CallbackFunctions, Component, EventInfo, Fmi2Boolean, Fmi2Type, Functions, Status, StatusKind,
    ValueReference, FMI2_FALSE, FMI2_TRUE,
};
use crate::fmu::Fmu;
use crate::logger::{logger_callback, LogCollector, LogSink};

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

/// The `fmuResourceLocation` argument of `fmi2Instantiate`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum ResourceLocation {
    /// `file:///.../resources` of the unpacked FMU.
    #[default]
    Unpacked,
    /// A NULL pointer (misuse tests).
    Null,
    /// Any other string.
    Custom(String),
}

/// Arguments of `fmi2Instantiate` and host-side options. Build with [`InstantiateOptions::new`]
/// and the chainable setters.
#[derive(Clone, Debug)]
pub struct InstantiateOptions {
    pub instance_name: String,
    pub fmu_type: Fmi2Type,
    /// `None`: the guid of `modelDescription.xml`; `Some`: this string instead (misuse tests).
    pub guid: Option<String>,
    pub resource_location: ResourceLocation,
    pub visible: bool,
    pub logging_on: bool,
    /// Pass `calloc`/`free` as allocateMemory/freeMemory (true, the default) or NULL pointers
    /// (allowed for FMUs that declare `canNotUseMemoryManagementFunctions`).
    pub memory_callbacks: bool,
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
    pub fn echo_log(mut self, on: bool) -> Self {
        self.echo_log = on;
        self
    }
}

fn c_string(what: &str, s: &str) -> Result<CString> {
    CString::new(s)
        .map_err(|_| Error::InvalidArgument(format!("{what} contains a NUL byte: {s:?}")))
}

/// One FMU instance (`fmi2Component`), freed with `fmi2FreeInstance` on drop.
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
    // for the whole life of the component; freed in Drop after fmi2FreeInstance.
    callbacks: *mut CallbackFunctions,
    sink: *mut LogSink,
    // The strings given to fmi2Instantiate, kept alive in case the FMU did not copy them.
    _strings: Vec<CString>,
}

// SAFETY: the component is only used through `&mut self` (no concurrent calls into one
// instance); FMI 2.0 allows different instances to be used from different threads, and the
// logger sink is a Mutex-protected collector reached only through this instance.
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
    /// `fmi2Instantiate` as Co-Simulation with the guid of the model description.
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

impl Instance {
    /// `fmi2Instantiate` with every option. On NULL, returns
    /// [`Error::InstantiationFailed`] with the messages the FMU logged.
    pub fn new(fmu: &Arc<Fmu>, options: InstantiateOptions) -> Result<Instance> {
        let name = c_string("instance name", &options.instance_name)?;
        let guid = c_string(
            "guid",
            options
                .guid
                .as_deref()
                .unwrap_or(&fmu.model_description().guid),
        )?;
        let resources = match &options.resource_location {
            ResourceLocation::Unpacked => Some(c_string("resource location", &fmu.resource_uri())?),
            ResourceLocation::Null => None,
            ResourceLocation::Custom(s) => Some(c_string("resource location", s)?),
        };
        let log = LogCollector::default();
        let sink = Box::into_raw(Box::new(LogSink {
            collector: log.clone(),
            echo: options.echo_log,
        }));
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
        match NonNull::new(component) {
            Some(component) => {
                let mut strings = vec![name, guid];
                strings.extend(resources);
                Ok(Instance {
                    component,
                    fmu: Arc::clone(fmu),
                    name: options.instance_name,
                    log,
                    callbacks,
                    sink,
                    _strings: strings,
                })
            }
            None => {
                // SAFETY: the FMU returned NULL, so it has no component that could still use
                // the callbacks; both boxes came from Box::into_raw above.
                unsafe {
                    drop(Box::from_raw(callbacks));
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

    /// Every message the FMU logged for this instance (a shared handle: it keeps filling).
    pub fn log(&self) -> &LogCollector {
        &self.log
    }

    pub(crate) fn f(&self) -> &Functions {
        self.fmu.functions()
    }

    pub(crate) fn c(&self) -> Component {
        self.component.as_ptr()
    }

    /// ESCAPE HATCH: the raw `fmi2Component`, to call [`Fmu::functions`] directly. Valid until
    /// this `Instance` is dropped.
    pub fn raw_component(&self) -> Component {
        self.c()
    }

    /// `fmi2FreeInstance` now (same as dropping).
    pub fn free(self) {
        drop(self);
    }

    // ---- Common functions ------------------------------------------------------------------

    /// `fmi2SetDebugLogging`.
    pub fn set_debug_logging(&mut self, logging_on: bool, categories: &[&CStr]) -> Status {
        let ptrs: Vec<*const c_char> = categories.iter().map(|c| c.as_ptr()).collect();
        // SAFETY: live component; `ptrs` holds `categories.len()` valid strings.
        unsafe {
            (self.f().set_debug_logging)(self.c(), fmi_bool(logging_on), ptrs.len(), ptrs.as_ptr())
        }
    }

    /// `fmi2SetupExperiment`: `None` for an undefined tolerance / stop time.
    pub fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Status {
        // SAFETY: live component, plain values.
        unsafe {
            (self.f().setup_experiment)(
                self.c(),
                fmi_bool(tolerance.is_some()),
                tolerance.unwrap_or(0.0),
                start_time,
                fmi_bool(stop_time.is_some()),
                stop_time.unwrap_or(0.0),
            )
        }
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization_mode(&mut self) -> Status {
        // SAFETY: live component.
        unsafe { (self.f().enter_initialization_mode)(self.c()) }
    }

    /// `fmi2ExitInitializationMode`.
    pub fn exit_initialization_mode(&mut self) -> Status {
        // SAFETY: live component.
        unsafe { (self.f().exit_initialization_mode)(self.c()) }
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self) -> Status {
        // SAFETY: live component.
        unsafe { (self.f().terminate)(self.c()) }
    }

    /// `fmi2Reset`.
    pub fn reset(&mut self) -> Status {
        // SAFETY: live component.
        unsafe { (self.f().reset)(self.c()) }
    }

    // ---- Getting and setting values ----------------------------------------------------------

    /// `fmi2GetReal`. Panics if `vr` and `values` differ in length (a host bug, not an FMU one).
    pub fn get_real(&mut self, vr: &[ValueReference], values: &mut [f64]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "get_real: one value per value reference"
        );
        // SAFETY: both arrays hold vr.len() elements.
        unsafe { (self.f().get_real)(self.c(), vr.as_ptr(), vr.len(), values.as_mut_ptr()) }
    }

    /// `fmi2GetReal` into a new Vec.
    pub fn get_reals(&mut self, vr: &[ValueReference]) -> (Status, Vec<f64>) {
        let mut values = vec![0.0; vr.len()];
        let status = self.get_real(vr, &mut values);
        (status, values)
    }

    /// `fmi2GetInteger`.
    pub fn get_integer(&mut self, vr: &[ValueReference], values: &mut [i32]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "get_integer: one value per value reference"
        );
        // SAFETY: both arrays hold vr.len() elements.
        unsafe { (self.f().get_integer)(self.c(), vr.as_ptr(), vr.len(), values.as_mut_ptr()) }
    }

    /// `fmi2GetBoolean` (any non-zero fmi2Boolean reads as `true`).
    pub fn get_boolean(&mut self, vr: &[ValueReference], values: &mut [bool]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "get_boolean: one value per value reference"
        );
        let mut raw = vec![FMI2_FALSE; vr.len()];
        // SAFETY: both arrays hold vr.len() elements.
        let status =
            unsafe { (self.f().get_boolean)(self.c(), vr.as_ptr(), vr.len(), raw.as_mut_ptr()) };
        for (v, r) in values.iter_mut().zip(raw) {
            *v = r != FMI2_FALSE;
        }
        status
    }

    /// `fmi2GetString`; the strings are copied (a NULL string reads as empty).
    pub fn get_string(&mut self, vr: &[ValueReference], values: &mut [String]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "get_string: one value per value reference"
        );
        let mut raw: Vec<*const c_char> = vec![ptr::null(); vr.len()];
        // SAFETY: both arrays hold vr.len() elements; the FMU's strings are valid until the
        // next call into this instance, and are copied right away.
        unsafe {
            let status = (self.f().get_string)(self.c(), vr.as_ptr(), vr.len(), raw.as_mut_ptr());
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

    /// `fmi2SetReal`.
    pub fn set_real(&mut self, vr: &[ValueReference], values: &[f64]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "set_real: one value per value reference"
        );
        // SAFETY: both arrays hold vr.len() elements.
        unsafe { (self.f().set_real)(self.c(), vr.as_ptr(), vr.len(), values.as_ptr()) }
    }

    /// `fmi2SetInteger`.
    pub fn set_integer(&mut self, vr: &[ValueReference], values: &[i32]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "set_integer: one value per value reference"
        );
        // SAFETY: both arrays hold vr.len() elements.
        unsafe { (self.f().set_integer)(self.c(), vr.as_ptr(), vr.len(), values.as_ptr()) }
    }

    /// `fmi2SetBoolean`.
    pub fn set_boolean(&mut self, vr: &[ValueReference], values: &[bool]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "set_boolean: one value per value reference"
        );
        let raw: Vec<Fmi2Boolean> = values.iter().map(|&b| fmi_bool(b)).collect();
        // SAFETY: both arrays hold vr.len() elements.
        unsafe { (self.f().set_boolean)(self.c(), vr.as_ptr(), vr.len(), raw.as_ptr()) }
    }

    /// `fmi2SetString`.
    pub fn set_string(&mut self, vr: &[ValueReference], values: &[&CStr]) -> Status {
        assert_eq!(
            vr.len(),
            values.len(),
            "set_string: one value per value reference"
        );
        let raw: Vec<*const c_char> = values.iter().map(|s| s.as_ptr()).collect();
        // SAFETY: both arrays hold vr.len() elements, the strings outlive the call.
        unsafe { (self.f().set_string)(self.c(), vr.as_ptr(), vr.len(), raw.as_ptr()) }
    }

    /// ESCAPE HATCH (misuse tests): `fmi2GetReal` with caller-chosen raw pointers, e.g. a NULL
    /// value-reference array with `nvr > 0`.
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
        (self.f().get_real)(self.c(), vr, nvr, values)
    }

    /// ESCAPE HATCH (misuse tests): `fmi2SetReal` with caller-chosen raw pointers.
    ///
    /// # Safety
    /// As for [`Instance::get_real_raw`].
    pub unsafe fn set_real_raw(
        &mut self,
        vr: *const ValueReference,
        nvr: usize,
        values: *const f64,
    ) -> Status {
        (self.f().set_real)(self.c(), vr, nvr, values)
    }

    // ---- Partial derivatives -----------------------------------------------------------------

    /// `fmi2GetDirectionalDerivative`.
    pub fn get_directional_derivative(
        &mut self,
        unknown: &[ValueReference],
        known: &[ValueReference],
        dv_known: &[f64],
        dv_unknown: &mut [f64],
    ) -> Status {
        assert_eq!(known.len(), dv_known.len(), "one seed per known");
        assert_eq!(unknown.len(), dv_unknown.len(), "one result per unknown");
        // SAFETY: every array holds the length passed with it.
        unsafe {
            (self.f().get_directional_derivative)(
                self.c(),
                unknown.as_ptr(),
                unknown.len(),
                known.as_ptr(),
                known.len(),
                dv_known.as_ptr(),
                dv_unknown.as_mut_ptr(),
            )
        }
    }

    // ---- Co-Simulation -----------------------------------------------------------------------

    /// `fmi2SetRealInputDerivatives`.
    pub fn set_real_input_derivatives(
        &mut self,
        vr: &[ValueReference],
        order: &[i32],
        values: &[f64],
    ) -> Status {
        assert!(
            order.len() == vr.len() && values.len() == vr.len(),
            "one order and value per vr"
        );
        // SAFETY: every array holds vr.len() elements.
        unsafe {
            (self.f().set_real_input_derivatives)(
                self.c(),
                vr.as_ptr(),
                vr.len(),
                order.as_ptr(),
                values.as_ptr(),
            )
        }
    }

    /// `fmi2GetRealOutputDerivatives`.
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
        // SAFETY: every array holds vr.len() elements.
        unsafe {
            (self.f().get_real_output_derivatives)(
                self.c(),
                vr.as_ptr(),
                vr.len(),
                order.as_ptr(),
                values.as_mut_ptr(),
            )
        }
    }

    /// `fmi2DoStep`.
    pub fn do_step(
        &mut self,
        current_communication_point: f64,
        step_size: f64,
        no_set_fmu_state_prior: bool,
    ) -> Status {
        // SAFETY: live component, plain values.
        unsafe {
            (self.f().do_step)(
                self.c(),
                current_communication_point,
                step_size,
                fmi_bool(no_set_fmu_state_prior),
            )
        }
    }

    /// `fmi2CancelStep`.
    pub fn cancel_step(&mut self) -> Status {
        // SAFETY: live component.
        unsafe { (self.f().cancel_step)(self.c()) }
    }

    /// `fmi2GetStatus`: (returned status, value).
    pub fn get_status(&mut self, kind: StatusKind) -> (Status, Status) {
        let mut value = Status::OK;
        // SAFETY: `value` is a valid out pointer.
        let status = unsafe { (self.f().get_status)(self.c(), kind, &mut value) };
        (status, value)
    }

    /// `fmi2GetRealStatus` (e.g. `fmi2LastSuccessfulTime`).
    pub fn get_real_status(&mut self, kind: StatusKind) -> (Status, f64) {
        let mut value = 0.0;
        // SAFETY: `value` is a valid out pointer.
        let status = unsafe { (self.f().get_real_status)(self.c(), kind, &mut value) };
        (status, value)
    }

    /// `fmi2GetIntegerStatus`.
    pub fn get_integer_status(&mut self, kind: StatusKind) -> (Status, i32) {
        let mut value: c_int = 0;
        // SAFETY: `value` is a valid out pointer.
        let status = unsafe { (self.f().get_integer_status)(self.c(), kind, &mut value) };
        (status, value)
    }

    /// `fmi2GetBooleanStatus` (e.g. `fmi2Terminated`).
    pub fn get_boolean_status(&mut self, kind: StatusKind) -> (Status, bool) {
        let mut value = FMI2_FALSE;
        // SAFETY: `value` is a valid out pointer.
        let status = unsafe { (self.f().get_boolean_status)(self.c(), kind, &mut value) };
        (status, value != FMI2_FALSE)
    }

    /// `fmi2GetStringStatus` (`None` if the FMU left the string NULL).
    pub fn get_string_status(&mut self, kind: StatusKind) -> (Status, Option<String>) {
        let mut value: *const c_char = ptr::null();
        // SAFETY: `value` is a valid out pointer; the string is copied right away.
        unsafe {
            let status = (self.f().get_string_status)(self.c(), kind, &mut value);
            let text =
                (!value.is_null()).then(|| CStr::from_ptr(value).to_string_lossy().into_owned());
            (status, text)
        }
    }

    // ---- Model Exchange (optional functions: Err if the FMU does not export them) -------------

    fn me<T>(f: Option<T>, name: &'static str) -> Result<T> {
        f.ok_or(Error::FunctionNotProvided(name))
    }

    /// `fmi2EnterEventMode`.
    pub fn enter_event_mode(&mut self) -> Result<Status> {
        let f = Self::me(self.f().enter_event_mode, "fmi2EnterEventMode")?;
        // SAFETY: live component.
        Ok(unsafe { f(self.c()) })
    }

    /// `fmi2NewDiscreteStates`.
    pub fn new_discrete_states(&mut self, event_info: &mut EventInfo) -> Result<Status> {
        let f = Self::me(self.f().new_discrete_states, "fmi2NewDiscreteStates")?;
        // SAFETY: valid out pointer.
        Ok(unsafe { f(self.c(), event_info) })
    }

    /// `fmi2EnterContinuousTimeMode`.
    pub fn enter_continuous_time_mode(&mut self) -> Result<Status> {
        let f = Self::me(
            self.f().enter_continuous_time_mode,
            "fmi2EnterContinuousTimeMode",
        )?;
        // SAFETY: live component.
        Ok(unsafe { f(self.c()) })
    }

    /// `fmi2CompletedIntegratorStep`: (status, enterEventMode, terminateSimulation).
    pub fn completed_integrator_step(
        &mut self,
        no_set_fmu_state_prior: bool,
    ) -> Result<(Status, bool, bool)> {
        let f = Self::me(
            self.f().completed_integrator_step,
            "fmi2CompletedIntegratorStep",
        )?;
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

    /// `fmi2SetTime`.
    pub fn set_time(&mut self, time: f64) -> Result<Status> {
        let f = Self::me(self.f().set_time, "fmi2SetTime")?;
        // SAFETY: live component.
        Ok(unsafe { f(self.c(), time) })
    }

    /// `fmi2SetContinuousStates`.
    pub fn set_continuous_states(&mut self, x: &[f64]) -> Result<Status> {
        let f = Self::me(self.f().set_continuous_states, "fmi2SetContinuousStates")?;
        // SAFETY: x holds x.len() values.
        Ok(unsafe { f(self.c(), x.as_ptr(), x.len()) })
    }

    /// `fmi2GetDerivatives`.
    pub fn get_derivatives(&mut self, dx: &mut [f64]) -> Result<Status> {
        let f = Self::me(self.f().get_derivatives, "fmi2GetDerivatives")?;
        // SAFETY: dx holds dx.len() values.
        Ok(unsafe { f(self.c(), dx.as_mut_ptr(), dx.len()) })
    }

    /// `fmi2GetEventIndicators`.
    pub fn get_event_indicators(&mut self, z: &mut [f64]) -> Result<Status> {
        let f = Self::me(self.f().get_event_indicators, "fmi2GetEventIndicators")?;
        // SAFETY: z holds z.len() values.
        Ok(unsafe { f(self.c(), z.as_mut_ptr(), z.len()) })
    }

    /// `fmi2GetContinuousStates`.
    pub fn get_continuous_states(&mut self, x: &mut [f64]) -> Result<Status> {
        let f = Self::me(self.f().get_continuous_states, "fmi2GetContinuousStates")?;
        // SAFETY: x holds x.len() values.
        Ok(unsafe { f(self.c(), x.as_mut_ptr(), x.len()) })
    }

    /// `fmi2GetNominalsOfContinuousStates`.
    pub fn get_nominals_of_continuous_states(&mut self, x: &mut [f64]) -> Result<Status> {
        let f = Self::me(
            self.f().get_nominals_of_continuous_states,
            "fmi2GetNominalsOfContinuousStates",
        )?;
        // SAFETY: x holds x.len() values.
        Ok(unsafe { f(self.c(), x.as_mut_ptr(), x.len()) })
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: the component is live and freed exactly once; the FMU may log during
        // fmi2FreeInstance, so the sink and callbacks are freed only afterwards. Both came
        // from Box::into_raw in Instance::new.
        unsafe {
            (self.f().free_instance)(self.c());
            drop(Box::from_raw(self.callbacks));
            drop(Box::from_raw(self.sink));
        }
    }
}
