//! The chapter's vocabulary as plain Rust: lumped elements with their constitutive laws, in SI
//! units, knowing nothing about FMI. Each element can say the power it exchanges (effort times
//! flow), so the activity index of chapter eq. 3.3 (A = integral of |e f| dt) comes for free.

pub mod activity;
pub mod complex;
pub mod control;
pub mod electrical;
pub mod induction;
pub mod magnetic;
pub mod mechanical;
pub mod sources;
pub mod thermal;

pub use control::{Multiplier, PiController, SecondOrderFilter, SpeedRamp};
pub use electrical::{Capacitor, Inductor, Resistor};
pub use induction::{Fluxes, InductionMachine};
pub use magnetic::{Reluctance, RlWinding, ToothedAirGap, Winding, MU_0_H_PER_M};
pub use mechanical::{FanLoad, Inertia, Reducer, TorsionBar, TorsionSpring};
pub use sources::{Ramp, SineVoltage};
pub use thermal::{ThermalConductance, ThermalNode};
