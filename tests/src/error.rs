//! The one error type of the host: everything that can go wrong *before* an fmi2/fmi3 function
//! returns a status (loading, parsing, symbol lookup, instantiation, name lookup).
//!
//! Statuses returned by the FMU itself are not errors of this type: they are [`crate::Status`]
//! values handed back unchanged, because the tests need to see exactly what the FMU said.

use std::fmt;
use std::path::PathBuf;

use crate::logger::LogRecord;

/// Result alias of this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Why loading an FMU, looking something up in it or instantiating it failed.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// The `.fmu` file (or another file we had to read) does not exist or cannot be read.
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The `.fmu` file is not a readable ZIP archive.
    Zip {
        path: PathBuf,
        source: zip::result::ZipError,
    },
    /// A file the standard requires is missing from the unpacked FMU
    /// (`modelDescription.xml`, `binaries/<platform>/<modelIdentifier>.<ext>`).
    MissingFile { path: PathBuf },
    /// `modelDescription.xml` is not well-formed XML.
    Xml { position: u64, message: String },
    /// `modelDescription.xml` is well-formed but does not describe a usable FMI 2.0 or 3.0 model
    /// (missing or malformed attribute, duplicate variable, ...).
    ModelDescription(String),
    /// The FMU does not provide the Co-Simulation interface.
    NotCoSimulation,
    /// The shared library could not be opened (`dlopen` failed).
    Library {
        path: PathBuf,
        source: libloading::Error,
    },
    /// A required `fmi2...` (FMI 2.0) or `fmi3...` (FMI 3.0) function is not exported by the
    /// shared library.
    MissingSymbol {
        name: &'static str,
        source: libloading::Error,
    },
    /// An optional function (Model Exchange) was called but the FMU does not export it.
    FunctionNotProvided(&'static str),
    /// The function does not exist in the FMU's FMI version (e.g. `fmi2CancelStep` or
    /// `fmi2GetStatus` for an FMI 3.0 FMU, `fmi3GetAdjointDerivative` for an FMI 2.0 one).
    NotInVersion {
        function: &'static str,
        version: crate::ffi::FmiVersion,
    },
    /// No variable with this name in `modelDescription.xml`.
    UnknownVariable(String),
    /// A string handed to the FMU contains an interior NUL byte.
    InvalidArgument(String),
    /// `fmi2Instantiate` (or `fmi3Instantiate...`) returned NULL. `log` holds every message the
    /// FMU logged meanwhile.
    InstantiationFailed {
        instance_name: String,
        log: Vec<LogRecord>,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Io { path, source } => write!(f, "cannot read {}: {source}", path.display()),
            Error::Zip { path, source } => {
                write!(f, "{} is not a valid FMU archive: {source}", path.display())
            }
            Error::MissingFile { path } => {
                write!(
                    f,
                    "the FMU does not contain the required file {}",
                    path.display()
                )
            }
            Error::Xml { position, message } => {
                write!(
                    f,
                    "modelDescription.xml is not well-formed (byte {position}): {message}"
                )
            }
            Error::ModelDescription(msg) => write!(f, "invalid modelDescription.xml: {msg}"),
            Error::NotCoSimulation => {
                write!(
                    f,
                    "the FMU does not provide the FMI Co-Simulation interface"
                )
            }
            Error::Library { path, source } => {
                write!(
                    f,
                    "cannot load the shared library {}: {source}",
                    path.display()
                )
            }
            Error::MissingSymbol { name, source } => {
                write!(f, "the shared library does not export {name}: {source}")
            }
            Error::FunctionNotProvided(name) => write!(f, "the FMU does not provide {name}"),
            Error::NotInVersion { function, version } => {
                write!(f, "{function} is not available in {version}")
            }
            Error::UnknownVariable(name) => {
                write!(f, "no variable named {name:?} in modelDescription.xml")
            }
            Error::InvalidArgument(msg) => write!(f, "invalid argument: {msg}"),
            Error::InstantiationFailed { instance_name, log } => {
                write!(
                    f,
                    "instantiation returned NULL for instance {instance_name:?}"
                )?;
                for record in log {
                    write!(f, "\n  {record}")?;
                }
                Ok(())
            }
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Io { source, .. } => Some(source),
            Error::Zip { source, .. } => Some(source),
            Error::Library { source, .. } => Some(source),
            Error::MissingSymbol { source, .. } => Some(source),
            _ => None,
        }
    }
}
