//! The FMI 2.0 logger callback as a [`LogSink`]: `fmi2CallbackLogger(componentEnvironment,
//! instanceName, status, category, message, ...)`.

use std::ffi::CString;

use super::types::{fmi2CallbackLogger, fmi2ComponentEnvironment, fmi2Status};
use crate::log::{to_c_string, LogSink};
use crate::status::Status;

/// The fmi2Status of a status (FMI 2.0 numbers them as the runtime orders them).
pub fn fmi2_status(status: Status) -> fmi2Status {
    status as fmi2Status
}

pub struct Fmi2Logger {
    callback: fmi2CallbackLogger,
    environment: fmi2ComponentEnvironment,
    instance_name: CString,
}

// SAFETY: the environment pointer belongs to the master, which hands it to us to be passed back
// unchanged to its own logger; FMI 2.0 lets the master call an instance from any thread (not
// concurrently), so the logger moves with the instance.
unsafe impl Send for Fmi2Logger {}

impl Fmi2Logger {
    /// A sink for the master's callback, if it gave one.
    pub fn sink(callback: Option<fmi2CallbackLogger>, environment: fmi2ComponentEnvironment, instance_name: &str) -> Option<Box<dyn LogSink>> {
        callback.map(|callback| Box::new(Fmi2Logger { callback, environment, instance_name: to_c_string(instance_name) }) as Box<dyn LogSink>)
    }
}

impl LogSink for Fmi2Logger {
    fn send(&self, status: Status, category: &str, message: &str) {
        // The message is the format string: double every '%' so that a printf-style logger
        // prints it verbatim; no variadic arguments follow.
        let text = to_c_string(&message.replace('%', "%%"));
        let category = to_c_string(category);
        // SAFETY: the master gave this callback for exactly this use; all strings are valid,
        // NUL-terminated and outlive the call.
        unsafe { (self.callback)(self.environment, self.instance_name.as_ptr(), fmi2_status(status), category.as_ptr(), text.as_ptr()) };
    }
}
