//! The FMI 3.0 logger callback as a [`LogSink`]: `fmi3LogMessageCallback(instanceEnvironment,
//! status, category, message)`. Unlike FMI 2.0's, the message is plain text, not a format string.

use super::types::{fmi3InstanceEnvironment, fmi3LogMessageCallback, fmi3Status};
use crate::log::{to_c_string, LogSink};
use crate::status::Status;

/// The fmi3Status of a status (FMI 3.0 numbers them as the runtime orders them).
pub fn fmi3_status(status: Status) -> fmi3Status {
    status as fmi3Status
}

pub struct Fmi3Logger {
    callback: fmi3LogMessageCallback,
    environment: fmi3InstanceEnvironment,
}

// SAFETY: the environment pointer belongs to the master, which hands it to us to be passed back
// unchanged to its own logger; FMI 3.0 lets the master call an instance from any thread (not
// concurrently), so the logger moves with the instance.
unsafe impl Send for Fmi3Logger {}

impl Fmi3Logger {
    /// A sink for the master's callback, if it gave one.
    pub fn sink(callback: Option<fmi3LogMessageCallback>, environment: fmi3InstanceEnvironment) -> Option<Box<dyn LogSink>> {
        callback.map(|callback| Box::new(Fmi3Logger { callback, environment }) as Box<dyn LogSink>)
    }
}

impl LogSink for Fmi3Logger {
    fn send(&self, status: Status, category: &str, message: &str) {
        let (text, category) = (to_c_string(message), to_c_string(category));
        // SAFETY: the master gave this callback for exactly this use; both strings are valid,
        // NUL-terminated and outlive the call.
        unsafe { (self.callback)(self.environment, fmi3_status(status), category.as_ptr(), text.as_ptr()) };
    }
}
