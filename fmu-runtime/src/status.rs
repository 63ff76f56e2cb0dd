//! The outcome of a call, in the runtime's own words. Each standard's adapter (`fmi2`, `fmi3`)
//! turns a [`Status`] into its own status code; nothing below the adapters knows either.

/// How a call ended, from best to worst (both FMI 2.0 and FMI 3.0 number their statuses in
/// this order, 0 to 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    Ok,
    /// Something was adjusted or ignored; the call did its job.
    Warning,
    /// A step could not be completed; the instance stays at the last communication point.
    Discard,
    /// The call was refused or the model failed; the message says why.
    Error,
    /// The instance can only be freed.
    Fatal,
}

/// Why a call did not end with [`Status::Ok`]: the status and the message for the logger.
#[derive(Debug)]
pub struct Failure {
    pub status: Status,
    pub message: String,
}

impl Failure {
    pub fn error(message: impl Into<String>) -> Self {
        Failure { status: Status::Error, message: message.into() }
    }

    pub fn discard(message: impl Into<String>) -> Self {
        Failure { status: Status::Discard, message: message.into() }
    }
}

pub type CallResult<T = ()> = Result<T, Failure>;
