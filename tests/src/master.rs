//! A small co-simulation master for Co-Simulation FMUs, FMI 2.0 and FMI 3.0 (through
//! [`crate::Instance`], which calls either version; the function names below are FMI 2.0's).
//!
//! A [`System`] lists named FMU instances ([`Component`]: an FMU, an instance name and start
//! values by variable name) and [`Connection`]s from outputs to inputs (`"instance.variable"`,
//! Real). A [`Master`] runs it:
//!
//! - initialization: `fmi2Instantiate`, start values, `fmi2SetupExperiment`, enter and exit
//!   initialization mode, then one exchange of every connection in feedthrough order (read
//!   from the FMUs' `ModelStructure` outputs; an algebraic loop is refused);
//! - stepping ([`Algorithm`]): Jacobi (all FMUs step from the inputs of the same communication
//!   point, then exchange) or Gauss-Seidel (FMUs step in a given order, each with the freshest
//!   outputs of those before it);
//! - input extrapolation (on by default where the FMUs declare `canInterpolateInputs` and
//!   `maxOutputDerivativeOrder >= 1`): first-order, from `fmi2GetRealOutputDerivatives` to
//!   `fmi2SetRealInputDerivatives` (FMI 2.0 only: FMI 3.0 has no input derivatives, its inputs
//!   are held); Gauss-Seidel interpolates fresh outputs instead;
//! - optional step rejection ([`ErrorControl`]): FMU states saved before each macro step,
//!   restored and the step halved when the coupling error estimate exceeds the tolerance;
//! - recording: a [`ResultTable`] of chosen variables at every communication point, and
//!   [`Stats`] (accepted and rejected steps, ...).
//!
//! Every FMU failure is a [`MasterError`] naming the instance and the call (fmi2 or fmi3), with the
//! FMU's last log messages; nothing panics on an FMU error.
//!
//! Modules: [`system`] (what is coupled), [`declaration`] (a system declared in
//! `models/systems/<Name>.toml`, the file build-fmus writes as an SSP), [`algorithm`] (how it is stepped: the options),
//! [`simulation`] (the running system), [`results`], [`error`].

pub mod algorithm;
pub mod declaration;
pub mod error;
pub mod results;
pub mod simulation;
pub mod system;

pub use algorithm::{Algorithm, ErrorControl, Master, Outcome};
pub use error::{MasterError, Result};
pub use results::{ResultTable, Stats};
pub use simulation::Simulation;
pub use system::{Component, Connection, Port, System};
