//! The chapter's vocabulary as plain Rust: lumped elements with their constitutive laws, in SI
//! units, knowing nothing about FMI. Each element can say the power it exchanges (effort times
//! flow), so the activity index of chapter eq. 3.3 (A = integral of |e f| dt) comes for free.
//!
//! Electrical elements use the chapter's effort/flow pair: voltage (V) and current (A).

pub mod electrical;
pub mod sources;

pub use electrical::{Capacitor, Inductor, Resistor};
pub use sources::SineVoltage;
