//! The FMI logger of one instance: messages reach the master through its callback, with the
//! instance name, a status and a category declared in modelDescription.xml `LogCategories`.

#![allow(non_upper_case_globals)]

use std::ffi::CString;

use crate::fmi2::types::{fmi2CallbackLogger, fmi2ComponentEnvironment, fmi2Error, fmi2Fatal, fmi2OK, fmi2Status, fmi2Warning, fmi2Discard};

/// The log categories every FMU declares (name, description), in modelDescription order.
pub const CATEGORIES: &[(&str, &str)] = &[
    ("logStatusWarning", "Warnings: something was adjusted or ignored"),
    ("logStatusDiscard", "A step could not be completed; the instance stays at the last communication point"),
    ("logStatusError", "Errors: a call was refused or the model failed; the message says why"),
    ("logStatusFatal", "Fatal errors: the instance can only be freed"),
    ("logEvents", "Mode changes, experiment set-up, state save/restore (debug logging)"),
];

/// The category of messages with a given status.
pub fn category_of(status: fmi2Status) -> &'static str {
    match status {
        fmi2Warning => "logStatusWarning",
        fmi2Discard => "logStatusDiscard",
        fmi2Error => "logStatusError",
        fmi2Fatal => "logStatusFatal",
        _ => "logEvents",
    }
}

pub struct Logger {
    callback: Option<fmi2CallbackLogger>,
    environment: fmi2ComponentEnvironment,
    instance_name: CString,
    /// fmi2SetDebugLogging: debug messages (category logEvents) are sent only when on.
    /// Warnings, discards, errors and fatal errors are always sent.
    debug_on: bool,
    enabled: Vec<bool>,
}

// SAFETY: the environment pointer belongs to the master, which hands it to us to be passed back
// unchanged to its own logger; FMI 2.0 lets the master call an instance from any thread (not
// concurrently), so the logger moves with the instance.
unsafe impl Send for Logger {}

impl Logger {
    pub fn new(callback: Option<fmi2CallbackLogger>, environment: fmi2ComponentEnvironment, instance_name: &str, debug_on: bool) -> Self {
        Logger {
            callback,
            environment,
            instance_name: to_c_string(instance_name),
            debug_on,
            enabled: vec![true; CATEGORIES.len()],
        }
    }

    pub fn instance_name(&self) -> &str {
        self.instance_name.to_str().unwrap_or("?")
    }

    /// fmi2SetDebugLogging: switch debug logging, for all categories (empty list) or the named ones.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[String]) -> Result<(), String> {
        let mut indices = Vec::new();
        for c in categories {
            match CATEGORIES.iter().position(|(n, _)| n == c) {
                Some(i) => indices.push(i),
                None => {
                    let known: Vec<_> = CATEGORIES.iter().map(|(n, _)| *n).collect();
                    return Err(format!("unknown log category '{c}'; this FMU has {}", known.join(", ")));
                }
            }
        }
        self.debug_on = on;
        if indices.is_empty() {
            self.enabled.iter_mut().for_each(|e| *e = on);
        } else {
            indices.into_iter().for_each(|i| self.enabled[i] = on);
        }
        Ok(())
    }

    /// Sends a message with a status. Debug (fmi2OK) messages go out only with debug logging on.
    pub fn log(&self, status: fmi2Status, message: &str) {
        let category = category_of(status);
        let enabled = CATEGORIES.iter().position(|(n, _)| *n == category).map(|i| self.enabled[i]).unwrap_or(true);
        if status == fmi2OK && !(self.debug_on && enabled) {
            return;
        }
        let Some(callback) = self.callback else { return };
        // The message is the format string: double every '%' so that a printf-style logger
        // prints it verbatim; no variadic arguments follow.
        let text = to_c_string(&message.replace('%', "%%"));
        let category = to_c_string(category);
        // SAFETY: the master gave this callback for exactly this use; all strings are valid,
        // NUL-terminated and outlive the call.
        unsafe { callback(self.environment, self.instance_name.as_ptr(), status, category.as_ptr(), text.as_ptr()) };
    }
}

/// A C string from text that may contain NUL bytes (they become spaces).
pub fn to_c_string(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).expect("no NUL bytes left")
}
