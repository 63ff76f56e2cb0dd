//! `fmi_host`: a small native FMI 2.0 and FMI 3.0 Co-Simulation (and Model Exchange) host.
//!
//! It loads an FMU the way a co-simulation master does and exposes every fmi2 function as a
//! thin method returning the FMU's raw [`Status`]. The FMU's `fmiVersion` picks the function
//! table ([`Api`]): the same [`Instance`] methods call `fmi2*` or `fmi3*` functions (see
//! [`instance`] for where the versions differ; [`dist::dist_dirs`] names the FMI 3.0 builds). It is used by the integration tests of the
//! project's FMUs, by the co-simulation master and by the benchmarks.
//!
//! ```no_run
//! use fmi_host::{Fmu, Status};
//! let fmu = Fmu::load("dist/RlcCircuit.fmu")?;
//! let i_absorbed = fmu.vr("i_absorbed")?;
//! let mut inst = fmu.instantiate("rlc", false, false)?;
//! assert_eq!(inst.setup_experiment(None, 0.0, Some(0.1)), Status::OK);
//! assert_eq!(inst.enter_initialization_mode(), Status::OK);
//! assert_eq!(inst.exit_initialization_mode(), Status::OK);
//! assert_eq!(inst.do_step(0.0, 1e-4, true), Status::OK);
//! let (status, values) = inst.get_reals(&[i_absorbed]);
//! # Ok::<(), fmi_host::Error>(())
//! ```
//!
//! Modules, one job each:
//! - [`fmu`]: unpack, parse, `dlopen`, resolve symbols ([`Fmu`]);
//! - [`model_description`]: the `modelDescription.xml` parser (build-fmus reads with it too);
//! - [`instance`]: one `fmi2Component` / `fmi3Instance` ([`Instance`]);
//! - [`state`]: FMU state get/set/free/serialize ([`FmuState`]);
//! - [`logger`]: the logger callback and per-instance [`LogRecord`]s;
//! - [`ffi`]: the raw C types and function tables (FMI 2.0 and FMI 3.0);
//! - [`tempdir`]: the unique temporary directory an FMU is unpacked into;
//! - [`model_exchange`]: a strict Model Exchange master (its own Dormand-Prince integrator,
//!   CVODE's rules for indicators at zero after an event);
//! - [`master`]: a co-simulation master (Jacobi / Gauss-Seidel, input extrapolation, step
//!   rejection with FMU states) coupling several instances, and the systems declared in
//!   `models/systems/*.toml` ([`master::declaration`], which build-fmus writes as SSP files).
//!
//! Limitation: the logger callback is declared non-variadic (stable Rust cannot define a
//! C-variadic function); see [`ffi::LoggerFn`].

pub mod dist;
pub mod error;
pub mod ffi;
pub mod fmu;
pub mod instance;
pub mod logger;
pub mod master;
pub mod model_description;
pub mod model_exchange;
pub mod state;
pub mod tempdir;

pub use error::{Error, Result};
pub use ffi::{Api, Fmi2Type, FmiVersion, Status, StatusKind, ValueReference};
pub use fmu::Fmu;
pub use instance::{DoStepOutcome, Instance, InstantiateOptions, ResourceLocation};
pub use logger::{LogCollector, LogRecord};
pub use model_description::{
    Causality, CoSimulation, DefaultExperiment, Initial, ModelDescription, ModelStructure,
    ScalarVariable, StartValue, UnitDefinition, Unknown, Variability, VariableType,
};
pub use state::FmuState;

// Compile-time checks of the thread-safety promises.
const _: () = {
    const fn send<T: Send>() {}
    const fn send_sync<T: Send + Sync>() {}
    send::<Instance>();
    send::<FmuState>();
    send_sync::<Fmu>();
};
