//! The logger callback and the per-instance record of everything an FMU logged.
//!
//! Each [`crate::Instance`] owns a boxed [`LogSink`] whose address is the
//! `componentEnvironment` given to `fmi2Instantiate` (the `instanceEnvironment` of
//! `fmi3Instantiate...`); the C callbacks [`logger_callback`] (FMI 2.0) and
//! [`log_message_callback`] (FMI 3.0) find their sink through that pointer, so messages of
//! different instances never mix, even on different threads.
//!
//! Limitation (see [`crate::ffi::LoggerFn`]): the callback is declared non-variadic, so variadic
//! `printf` arguments are ignored; `%%` in the message is turned into `%`.

use std::ffi::{c_char, CStr};
use std::fmt;
use std::sync::{Arc, Mutex, MutexGuard};

use crate::ffi::{ComponentEnvironment, Status};

/// One call of the logger.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LogRecord {
    pub instance_name: String,
    pub status: Status,
    pub category: String,
    pub message: String,
}

impl fmt::Display for LogRecord {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "[{}] {} ({}): {}",
            self.instance_name, self.status, self.category, self.message
        )
    }
}

/// A shared, growing list of [`LogRecord`]s (cheap to clone: it is an `Arc`).
#[derive(Clone, Debug, Default)]
pub struct LogCollector {
    records: Arc<Mutex<Vec<LogRecord>>>,
}

impl LogCollector {
    fn lock(&self) -> MutexGuard<'_, Vec<LogRecord>> {
        // A panic while holding the lock cannot leave the Vec inconsistent: ignore poisoning.
        self.records
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    pub fn push(&self, record: LogRecord) {
        self.lock().push(record);
    }

    /// A copy of every record so far.
    pub fn records(&self) -> Vec<LogRecord> {
        self.lock().clone()
    }

    /// A copy of the records from index `start` on (use [`LogCollector::len`] as a mark).
    pub fn since(&self, start: usize) -> Vec<LogRecord> {
        self.lock()
            .get(start..)
            .map(<[LogRecord]>::to_vec)
            .unwrap_or_default()
    }

    pub fn len(&self) -> usize {
        self.lock().len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn clear(&self) {
        self.lock().clear();
    }

    /// Whether a record with this status was logged from index `start` on.
    pub fn has_status_since(&self, start: usize, status: Status) -> bool {
        self.lock()
            .get(start..)
            .is_some_and(|r| r.iter().any(|rec| rec.status == status))
    }
}

/// What `componentEnvironment` (FMI 3.0: `instanceEnvironment`) points to.
#[derive(Debug)]
pub struct LogSink {
    pub collector: LogCollector,
    /// Also print every message to stderr as it arrives.
    pub echo: bool,
    /// The instance's name, for the records of FMI 3.0's callback (which does not pass it).
    pub instance_name: String,
}

impl LogSink {
    fn record(&self, record: LogRecord) {
        if self.echo {
            eprintln!("{record}");
        }
        self.collector.push(record);
    }
}

/// Copies a C string that may be NULL or not UTF-8.
///
/// # Safety
/// `ptr` is NULL or points to a NUL-terminated string.
unsafe fn lossy(ptr: *const c_char) -> String {
    if ptr.is_null() {
        String::new()
    } else {
        CStr::from_ptr(ptr).to_string_lossy().into_owned()
    }
}

/// The callback given to every instance (non-variadic: see the module documentation).
///
/// # Safety
/// Called by the FMU with `env` = the `componentEnvironment` it was given (a live `LogSink`)
/// or NULL, and NUL-terminated (or NULL) strings.
pub unsafe extern "C" fn logger_callback(
    env: ComponentEnvironment,
    instance_name: *const c_char,
    status: Status,
    category: *const c_char,
    message: *const c_char,
) {
    let record = LogRecord {
        instance_name: lossy(instance_name),
        status,
        category: lossy(category),
        message: lossy(message).replace("%%", "%"),
    };
    if env.is_null() {
        // The FMU lost its environment pointer: still show the message somewhere.
        eprintln!("fmi-host: log without componentEnvironment: {record}");
        return;
    }
    let sink = &*(env as *const LogSink);
    sink.record(record);
}

/// The `fmi3LogMessageCallback` given to every FMI 3.0 instance: the message is plain text (not
/// a format string, so `%%` stays as it is), the instance name is the sink's.
///
/// # Safety
/// Called by the FMU with `env` = the `instanceEnvironment` it was given (a live `LogSink`) or
/// NULL, and NUL-terminated (or NULL) strings.
pub unsafe extern "C" fn log_message_callback(
    env: ComponentEnvironment,
    status: Status,
    category: *const c_char,
    message: *const c_char,
) {
    if env.is_null() {
        eprintln!("fmi-host: log without instanceEnvironment: {status} ({}): {}", lossy(category), lossy(message));
        return;
    }
    let sink = &*(env as *const LogSink);
    sink.record(LogRecord {
        instance_name: sink.instance_name.clone(),
        status,
        category: lossy(category),
        message: lossy(message),
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::CString;

    #[test]
    fn callback_records_and_unescapes_percent() {
        let sink = Box::new(LogSink {
            collector: LogCollector::default(),
            echo: false,
            instance_name: String::new(),
        });
        let name = CString::new("inst").unwrap();
        let cat = CString::new("logStatusError").unwrap();
        let msg = CString::new("100%% sure").unwrap();
        unsafe {
            logger_callback(
                &*sink as *const LogSink as ComponentEnvironment,
                name.as_ptr(),
                Status::ERROR,
                cat.as_ptr(),
                msg.as_ptr(),
            );
            logger_callback(
                &*sink as *const LogSink as ComponentEnvironment,
                std::ptr::null(),
                Status::OK,
                std::ptr::null(),
                std::ptr::null(),
            );
        }
        let records = sink.collector.records();
        assert_eq!(records.len(), 2);
        assert_eq!(records[0].message, "100% sure");
        assert_eq!(records[0].status, Status::ERROR);
        assert_eq!(records[0].instance_name, "inst");
        assert!(sink.collector.has_status_since(0, Status::ERROR));
        assert!(!sink.collector.has_status_since(1, Status::ERROR));
        assert_eq!(sink.collector.since(1)[0].message, "");
    }
}
