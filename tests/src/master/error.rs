//! [`MasterError`]: what can stop a co-simulation, naming the instance and the call.

use std::fmt;

use crate::ffi::Status;
use crate::logger::LogRecord;

/// Result alias of the master.
pub type Result<T, E = MasterError> = std::result::Result<T, E>;

/// Why setting up or running a coupled simulation failed. FMU errors are values of this type,
/// never panics.
#[derive(Debug)]
#[non_exhaustive]
pub enum MasterError {
    /// Loading, name lookup or `fmi2Instantiate` failed for an instance (the host's error).
    Host {
        instance: String,
        source: crate::Error,
    },
    /// An fmi2 function returned something else than `fmi2OK` / `fmi2Warning`.
    Call {
        instance: String,
        /// The C name of the function, e.g. `"fmi2DoStep"`.
        call: &'static str,
        /// The master's time when the call was made.
        time: f64,
        status: Status,
        /// The last messages the FMU logged for this instance.
        log: Vec<LogRecord>,
    },
    /// The system or the options are inconsistent (unknown instance or variable, an input
    /// connected twice, a connection from an input, a bad step size, ...).
    Config(String),
    /// The connections form an algebraic loop (direct feedthrough all the way round); the
    /// connections involved, as `"a.y -> b.u"`.
    AlgebraicLoop(Vec<String>),
    /// An option needs a capability the FMU does not declare (e.g. error control needs
    /// `canGetAndSetFMUstate`).
    Unsupported {
        instance: String,
        capability: &'static str,
    },
}

impl fmt::Display for MasterError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MasterError::Host { instance, source } => write!(f, "instance {instance:?}: {source}"),
            MasterError::Call {
                instance,
                call,
                time,
                status,
                log,
            } => {
                write!(
                    f,
                    "instance {instance:?}: {call} at t = {time} s returned {status}"
                )?;
                for record in log {
                    write!(f, "\n  {record}")?;
                }
                Ok(())
            }
            MasterError::Config(msg) => write!(f, "invalid co-simulation set-up: {msg}"),
            MasterError::AlgebraicLoop(links) => {
                write!(f, "algebraic loop through the connections {}", links.join(", "))
            }
            MasterError::Unsupported {
                instance,
                capability,
            } => write!(
                f,
                "instance {instance:?}: the FMU does not declare {capability}, which the chosen options need"
            ),
        }
    }
}

impl std::error::Error for MasterError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            MasterError::Host { source, .. } => Some(source),
            _ => None,
        }
    }
}

pub(crate) fn config(msg: impl Into<String>) -> MasterError {
    MasterError::Config(msg.into())
}
