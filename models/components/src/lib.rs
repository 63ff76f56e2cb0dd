//! The chapter's vocabulary as plain Rust: lumped elements with their constitutive laws, in SI
//! units, knowing nothing about FMI. Each element can say the power it exchanges (effort times
//! flow), so the activity index of chapter eq. 3.3 (A = integral of |e f| dt) comes for free.

pub mod activity;
pub mod complex;
pub mod control;
pub mod dc;
pub mod electrical;
pub mod induction;
pub mod mechanical;
pub mod sources;

pub use control::{PiController, SecondOrderFilter, SpeedRamp};
pub use dc::DcMachine;
pub use electrical::{Capacitor, Inductor, Resistor};
pub use induction::{Fluxes, InductionMachine};
pub use mechanical::{CoulombFriction, FanLoad, Inertia, PropellerLoad, Reducer, TorsionSpring};
pub use sources::SineVoltage;
