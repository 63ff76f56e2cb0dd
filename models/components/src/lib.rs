//! The chapter's vocabulary as plain Rust: lumped elements with their constitutive laws, in SI
//! units, knowing nothing about FMI. Each element can say the power it exchanges (effort times
//! flow), so the activity index of chapter eq. 3.3 (A = integral of |e f| dt) comes for free.
//!
//! A model composes them in its `derivatives`: here the right-hand side of the motor-fan's
//! level c (Figure 3.5c) at one instant, with a constant motor torque.
//!
//! ```
//! use components::{FanLoad, Inertia, Reducer, TorsionSpring};
//! let motor = Inertia { inertia_kg_m2: 1.72 };
//! let shaft = TorsionSpring { stiffness_n_m_per_rad: 906.85, damping_n_m_s_per_rad: 5.0 };
//! let gear = Reducer { ratio: 10.0, efficiency: 0.97 };
//! let fan = Inertia { inertia_kg_m2: 1172.0 };
//! let blades = FanLoad { coefficient_n_m_s2_per_rad2: 42.9 };
//! let (w_motor, twist, w_fan, torque_motor) = (100.0, 0.5, 9.9, 1000.0);
//!
//! let w_high = w_fan * gear.ratio; // the reducer's input speed
//! let t_shaft = shaft.torque_n_m(twist, w_motor - w_high);
//! let dw_motor = motor.acceleration_rad_per_s2(torque_motor - t_shaft);
//! let dtwist = w_motor - w_high;
//! let dw_fan = fan.acceleration_rad_per_s2(gear.low_side_torque_n_m(t_shaft, w_high) - blades.torque_n_m(w_fan));
//! assert!(dw_motor > 0.0 && dtwist > 0.0 && dw_fan > 0.0);
//! ```
//!
//! Modules: [`electrical`] (R, L, C), [`mechanical`] (inertia, torsion spring and bar, reducer, worm gear, cable drum,
//! fan load), [`translational`] (mass, spring, damper, sliding friction, rack and pinion, lever), [`geometry`] (Table 3.2: parameters
//! from dimensions and materials, eqs. 3.1-3.2), [`hydraulic`] (pump and motor, cylinder, oil volume, leakage, orifice), [`dc`] (the DC machine of eq. 3.9, the chopper), [`induction`] (the induction machine, circuit and dq), [`control`] (ramps, filter,
//! multiplier, PI), [`sources`], [`thermal`] (nodes and conductances), [`magnetic`] (reluctances
//! and windings), [`activity`] (eq. 3.3), [`table`] (a motor's torque-speed table), [`roots`] (bisection, and the derivatives of a root). Every element has an example in its documentation
//! (`cargo doc -p components --open`).
//!
//! Every element is written once over the scalar `R:` [`fmu_runtime::real::Real`], `f64` by
//! default (`Inertia` is `Inertia<f64>`, and `Inertia { inertia_kg_m2: 1.72 }` infers it): over
//! `f64` the laws compute exactly what they computed written over `f64` (the same operations in
//! the same order), over [`fmu_runtime::real::Dual`] they also give the exact directional
//! derivative of every result (docs/DESIGN.md, "Exact derivatives: equations over any scalar"; the test
//! `tests/dual_derivatives.rs` checks them against sixth-order differences). Integers, modes,
//! flags and enum choices stay as they are; an element's [`Effect`](fmu_runtime::elements::Effect)
//! constants are on its `f64` form (`Inertia::INERTIA`).

pub mod activity;
pub mod complex;
pub mod control;
pub mod dc;
pub mod electrical;
pub mod geometry;
pub mod hydraulic;
pub mod induction;
pub mod injection;
pub mod magnetic;
pub mod mechanical;
pub mod mems;
pub mod modal;
pub mod roots;
pub mod sources;
pub mod table;
pub mod thermal;
pub mod translational;

pub use control::{Multiplier, PiController, SecondOrderFilter, SpeedRamp};
pub use dc::{Chopper, DcMachine};
pub use electrical::{Capacitor, Inductor, Resistor};
pub use hydraulic::{DoubleActingCylinder, FixedDisplacementMotor, FixedDisplacementPump, FluidVolume, LaminarLeakage, Orifice};
pub use induction::{Fluxes, InductionMachine};
pub use magnetic::{Reluctance, RlWinding, ToothFaces, ToothedAirGap, Winding, MU_0_H_PER_M};
pub use mechanical::{SHAFT_PORT, CableDrum, CoulombFriction, FanLoad, GearMode, Inertia, PropellerLoad, Reducer, TorsionBar, TorsionSpring, WormGear, WormGearError};
pub use modal::TwoDegreesOfFreedom;
pub use sources::{Ramp, SineVoltage, Weight};
pub use table::{Interpolation, TorqueSpeedTable};
pub use thermal::{ThermalConductance, ThermalNode};
pub use translational::{Lever, Mass, RackAndPinion, SlidingFriction, TranslationalDamper, TranslationalSpring};
