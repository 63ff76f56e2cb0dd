//! The logger of one instance: messages reach the master through a [`LogSink`] (its standard's
//! callback, set by the adapter), with a status and a category declared in modelDescription.xml
//! `LogCategories`.

use crate::float_mode::MasterMode;
use std::ffi::CString;

use crate::status::Status;

/// The log categories every FMU declares (name, description), in modelDescription order.
pub const CATEGORIES: &[(&str, &str)] = &[
    ("logStatusWarning", "Warnings: something was adjusted or ignored"),
    ("logStatusDiscard", "A step could not be completed; the instance stays at the last communication point"),
    ("logStatusError", "Errors: a call was refused or the model failed; the message says why"),
    ("logStatusFatal", "Fatal errors: the instance can only be freed"),
    ("logEvents", "Mode changes, experiment set-up, state save/restore (debug logging)"),
];

/// The category of messages with a given status.
pub fn category_of(status: Status) -> &'static str {
    match status {
        Status::Warning => "logStatusWarning",
        Status::Discard => "logStatusDiscard",
        Status::Error => "logStatusError",
        Status::Fatal => "logStatusFatal",
        Status::Ok => "logEvents",
    }
}

/// Where an instance's messages go: the master's logger callback, in its standard's form.
/// FMI lets the master call an instance from any thread (not concurrently), so the sink moves
/// with the instance.
pub trait LogSink: Send {
    fn send(&self, status: Status, category: &str, message: &str);
}

pub struct Logger {
    sink: Option<Box<dyn LogSink>>,
    /// Debug logging (fmi2SetDebugLogging, fmi3SetDebugLogging): debug messages (category
    /// logEvents) are sent only when on. Warnings, discards, errors and fatal errors are always sent.
    debug_on: bool,
    enabled: Vec<bool>,
    /// Inside a call of the master's: its floating-point mode, in which its callback runs
    /// ([`crate::float_mode`]).
    master_mode: std::cell::Cell<Option<MasterMode>>,
}

impl Logger {
    pub fn new(sink: Option<Box<dyn LogSink>>, debug_on: bool) -> Self {
        Logger { sink, debug_on, enabled: vec![true; CATEGORIES.len()], master_mode: std::cell::Cell::new(None) }
    }

    /// The master's floating-point mode while inside one of its calls, None outside.
    pub fn set_master_mode(&self, mode: Option<MasterMode>) {
        self.master_mode.set(mode);
    }

    /// A logger that sends nothing (the runtime's own tools and tests).
    pub fn silent() -> Self {
        Self::new(None, false)
    }

    /// Switches debug logging, for all categories (empty list) or the named ones.
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

    /// Sends a message with a status. Debug (`Status::Ok`) messages go out only with debug
    /// logging on.
    pub fn log(&self, status: Status, message: &str) {
        let category = category_of(status);
        let enabled = CATEGORIES.iter().position(|(n, _)| *n == category).map(|i| self.enabled[i]).unwrap_or(true);
        if status == Status::Ok && !(self.debug_on && enabled) {
            return;
        }
        if let Some(sink) = &self.sink {
            match self.master_mode.get() {
                Some(mode) => mode.run(|| sink.send(status, category, message)),
                None => sink.send(status, category, message),
            }
        }
    }
}

/// A C string from text that may contain NUL bytes (they become spaces).
pub fn to_c_string(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).expect("no NUL bytes left")
}
