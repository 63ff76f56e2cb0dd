//! FMI runtime: everything that is the same for every FMU, and nothing about motors.
//!
//! A model author implements [`Model`] in plain Rust — declarations, derivatives, outputs —
//! and writes `fmu_runtime::export_fmu!(MyModel);`. The runtime supplies the rest: every
//! fmi2 and fmi3 function with its standard's state machine enforced ([`fmi2::states`],
//! [`fmi3::states`]) over a version-neutral core ([`phase`], [`status`]), the variable stores and their
//! checks ([`instance`]), the ODE solver ([`integrate`]), FMU state save/restore/serialize
//! ([`state`]), and the generated modelDescription.xml ([`description`]) and documentation.
//!
//! ```
//! use fmu_runtime::prelude::*;
//!
//! /// dx/dt = -rate x: a first-order decay.
//! pub struct Decay { rate: Parameter, x: State, y: Output }
//!
//! impl Model for Decay {
//!     fn info() -> ModelInfo {
//!         ModelInfo {
//!             name: "Decay",
//!             description: "First-order decay",
//!             default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 5.0, step_size: 0.01 },
//!             solver: Solver::ExplicitRungeKutta,
//!             documentation: "<p>dx/dt = -rate x</p>",
//!         }
//!     }
//!     fn declare(d: &mut Declarations) -> Self {
//!         Decay {
//!             rate: d.parameter("rate", 2.0, "Hz").positive().describe("decay rate"),
//!             x: d.state("x", 1.0, "1").describe("amount"),
//!             y: d.output("y", "1").describe("amount, observed"),
//!         }
//!     }
//!     fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) { der[self.x] = -k[self.rate] * k[self.x]; }
//!     fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) { out[self.y] = k[self.x]; }
//! }
//!
//! // In a cdylib crate this one line makes the FMU: fmu_runtime::export_fmu!(Decay);
//! let description = fmu_runtime::description::ModelDescription::of::<Decay>();
//! assert!(description.document(fmu_runtime::standards::Standard::Fmi2).xml.contains(r#"<ScalarVariable name="rate" valueReference="0""#));
//! // y depends on the state x (index 2), der(x) on x; at initialization also on rate (index 1).
//! assert!(description.document(fmu_runtime::standards::Standard::Fmi2).xml.contains(r#"<Unknown index="4" dependencies="2"/>"#));
//! ```
pub mod activity_report;
pub mod boundary;
pub mod description;
pub mod documentation;
pub mod elements;
pub mod export;
pub mod exported;
pub mod float_mode;
pub mod fmi2;
pub mod fmi3;
pub mod instance;
pub mod integrate;
pub mod rk;
pub mod simd;
pub mod log;
pub mod model;
pub mod phase;
pub mod real;
pub mod trace;
pub mod standards;
pub mod state;
pub mod status;
pub mod stepper;
pub mod testing;
pub mod units;
pub mod values;
pub mod variables;
pub mod xml;

#[cfg(test)]
mod test_model;

pub use model::{DefaultExperiment, Model, ModelInfo, Solver};

/// Everything a model crate needs, in one import.
pub mod prelude {
    pub use crate::elements::{Domain, Effect, Element, Kind};
    pub use crate::model::{DefaultExperiment, Model, ModelInfo, Solver};
    pub use crate::real::Real;
    pub use crate::values::{Derivatives, EventIndicators, InitialStates, Knowns, ModeUpdate, Outputs};
    pub use crate::variables::{BooleanParameter, Declarations, Indicator, Input, IntegerParameter, Local, Mode, Output, Parameter, State};
}
