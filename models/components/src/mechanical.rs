//! Rotational mechanics (chapter sections 3.2-3.3, Figures 3.4 and 3.5): effort = torque (N m),
//! flow = angular speed (rad/s).

use fmu_runtime::real::Real;
use fmu_runtime::elements::{Domain, Effect, Kind};

/// The effect of a shaft end where a subsystem FMU meets the FMU it is coupled to: the power
/// that crosses it, T w, counts as a source of the subsystem (negative where power leaves it).
pub const SHAFT_PORT: Effect = Effect { domains: &[Domain::Rotational], kind: Kind::Source, what: "coupling port (power from the connected FMU)" };

/// A rigid rotating body: J dw/dt = net torque (inertial storage, eq. 3.1).
/// ```
/// use components::Inertia;
/// // The chapter's motor: J = 1.72 kg m2 under a net 172 N m accelerates at 100 rad/s2.
/// let motor = Inertia { inertia_kg_m2: 1.72 };
/// assert!((motor.acceleration_rad_per_s2(172.0) - 100.0).abs() < 1e-12);
/// assert!((motor.energy_j(10.0) - 86.0).abs() < 1e-12); // J w^2 / 2
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inertia<R = f64> {
    pub inertia_kg_m2: R,
}

impl Inertia {
    /// Its effect (Table 3.1): inertial storage in rotation.
    pub const INERTIA: Effect = Effect { domains: &[Domain::Rotational], kind: Kind::StorageI, what: "inertia" };
}

impl<R: Real> Inertia<R> {
    /// dw/dt under a net torque, rad/s2.
    pub fn acceleration_rad_per_s2(&self, net_torque_n_m: R) -> R {
        net_torque_n_m / self.inertia_kg_m2
    }

    /// Power stored per second, J dw/dt w, W (positive while speeding up).
    pub fn power_w(&self, acceleration_rad_per_s2: R, speed_rad_per_s: R) -> R {
        self.inertia_kg_m2 * acceleration_rad_per_s2 * speed_rad_per_s
    }

    /// Kinetic energy J w^2 / 2, J.
    pub fn energy_j(&self, speed_rad_per_s: R) -> R {
        self.inertia_kg_m2 * 0.5 * speed_rad_per_s * speed_rad_per_s
    }
}

/// A shaft in torsion with internal damping: T = K theta + D dtheta/dt (eq. 3.2 gives K from
/// the geometry).
/// ```
/// use components::TorsionSpring;
/// // The motor-fan driveshaft: 1.4 Hz with the fan's 11.72 kg m2 on a fixed motor (eq. 3.8).
/// let shaft = TorsionSpring { stiffness_n_m_per_rad: 906.85, damping_n_m_s_per_rad: 5.0 };
/// assert!((shaft.natural_frequency_hz(11.72, f64::INFINITY) - 1.4).abs() < 1e-3);
/// assert_eq!(shaft.torque_n_m(0.1, 0.0), 90.685); // K theta
/// assert_eq!(shaft.damper_power_w(2.0), 20.0); // D (dtheta/dt)^2
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorsionSpring<R = f64> {
    pub stiffness_n_m_per_rad: R,
    pub damping_n_m_s_per_rad: R,
}

impl TorsionSpring {
    /// Its effects (Table 3.1): the shaft's stiffness (capacitive storage) ...
    pub const STIFFNESS: Effect = Effect { domains: &[Domain::Rotational], kind: Kind::StorageC, what: "shaft stiffness" };
    /// ... and its internal damping (dissipation).
    pub const DAMPING: Effect = Effect { domains: &[Domain::Rotational], kind: Kind::Dissipation, what: "internal damping" };
}

impl<R: Real> TorsionSpring<R> {
    /// Transmitted torque at a twist and twist rate, N m.
    pub fn torque_n_m(&self, twist_rad: R, twist_rate_rad_per_s: R) -> R {
        self.stiffness_n_m_per_rad * twist_rad + self.damping_n_m_s_per_rad * twist_rate_rad_per_s
    }

    /// Power into the elastic part, K theta dtheta/dt, W.
    pub fn spring_power_w(&self, twist_rad: R, twist_rate_rad_per_s: R) -> R {
        self.stiffness_n_m_per_rad * twist_rad * twist_rate_rad_per_s
    }

    /// Power dissipated by the internal damping, W (never negative).
    pub fn damper_power_w(&self, twist_rate_rad_per_s: R) -> R {
        self.damping_n_m_s_per_rad * twist_rate_rad_per_s * twist_rate_rad_per_s
    }

    /// Natural frequency of this spring between two inertias, Hz: sqrt(K (1/J1 + 1/J2)) / 2 pi.
    /// With `j2` infinite (an imposed speed on one side) it is sqrt(K/J1) / 2 pi (eq. 3.8).
    pub fn natural_frequency_hz(&self, j1_kg_m2: R, j2_kg_m2: R) -> R {
        (self.stiffness_n_m_per_rad * (R::from(1.0) / j1_kg_m2 + R::from(1.0) / j2_kg_m2)).sqrt() / (2.0 * std::f64::consts::PI)
    }
}

/// The torsion bar of a steering torque sensor (section 3.5.2, Figure 3.24a; question 6): a
/// massless spring between the input (steering wheel) and output shafts whose twist is
/// proportional to the driver's torque, theta = T / K, up to the mechanical end stops at
/// +/- `stop_angle_rad` beyond which the stops carry the extra torque.
/// ```
/// use components::TorsionBar;
/// // 2 N m per degree, stops at 5 degrees.
/// let bar = TorsionBar { stiffness_n_m_per_rad: 2.0 * 180.0 / std::f64::consts::PI, stop_angle_rad: 5f64.to_radians() };
/// assert!((bar.twist_rad(4.0) - 2f64.to_radians()).abs() < 1e-12);
/// assert!((bar.stop_torque_n_m() - 10.0).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorsionBar<R = f64> {
    pub stiffness_n_m_per_rad: R,
    pub stop_angle_rad: R,
}

impl TorsionBar {
    /// Its effect (Table 3.1): capacitive storage in rotation (massless).
    pub const STIFFNESS: Effect = Effect { domains: &[Domain::Rotational], kind: Kind::StorageC, what: "torsion bar stiffness" };
}

impl<R: Real> TorsionBar<R> {
    /// Stiffness of a round bar of a shear modulus, diameter and length: K = G pi d^4 / (32 l)
    /// (polar moment of area pi d^4 / 32), N m/rad: eq. 3.2 with no bore, computed by
    /// [`geometry::shaft_torsional_stiffness_n_m_per_rad`](crate::geometry::shaft_torsional_stiffness_n_m_per_rad).
    pub fn round_bar_stiffness_n_m_per_rad(shear_modulus_pa: R, diameter_m: R, length_m: R) -> R {
        crate::geometry::shaft_torsional_stiffness_n_m_per_rad(shear_modulus_pa, diameter_m, length_m)
    }

    /// Twist angle of the input shaft with respect to the output shaft under a torque, rad.
    pub fn twist_rad(&self, torque_n_m: R) -> R {
        (torque_n_m / self.stiffness_n_m_per_rad).clamp(-self.stop_angle_rad, self.stop_angle_rad)
    }

    /// The torque at which the bar reaches its stops, N m.
    pub fn stop_torque_n_m(&self) -> R {
        self.stiffness_n_m_per_rad * self.stop_angle_rad
    }
}

/// A cable drum of radius r, an ideal rotation-to-translation transformer (section 3.4.1.2, the
/// elevator of Figure 3.16.b): v = r w and C = r F. Masses hanging on the cable are seen by the
/// drum's shaft as an inertia m r^2, by equality of kinetic energy (eq. 3.7).
/// ```
/// use components::CableDrum;
/// let drum = CableDrum { radius_m: 0.25 };
/// assert_eq!(drum.cable_speed_m_per_s(4.0), 1.0);
/// assert_eq!(drum.torque_n_m(1962.0), 490.5); // 200 kg of unbalance at g = 9.81 m/s2
/// assert_eq!(drum.referred_inertia_kg_m2(1800.0), 112.5); // 1/2 m v^2 = 1/2 (m r^2) w^2
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CableDrum<R = f64> {
    pub radius_m: R,
}

impl CableDrum {
    /// Its effect (Table 3.1): a lossless transformer between rotation and translation.
    pub const TRANSFORMER: Effect =
        Effect { domains: &[Domain::Rotational, Domain::Translational], kind: Kind::Transformer, what: "drum radius (rotation to translation)" };
}

impl<R: Real> CableDrum<R> {
    /// Cable (cabin) speed for a drum speed, m/s.
    pub fn cable_speed_m_per_s(&self, drum_speed_rad_per_s: R) -> R {
        self.radius_m * drum_speed_rad_per_s
    }

    /// Torque on the drum's shaft from a cable force, N m.
    pub fn torque_n_m(&self, cable_force_n: R) -> R {
        self.radius_m * cable_force_n
    }

    /// A mass moving with the cable, seen as an inertia on the drum's shaft, kg m2.
    pub fn referred_inertia_kg_m2(&self, mass_kg: R) -> R {
        mass_kg * self.radius_m * self.radius_m
    }
}

/// A massless reducer: ratio N = w_high / w_low, efficiency eta on the power flowing through it
/// (section 3.3.1, level a: "the reducer with its transformation ratio and its efficiency").
/// ```
/// use components::Reducer;
/// let gear = Reducer { ratio: 10.0, efficiency: 0.97 };
/// assert_eq!(gear.low_speed(150.0), 15.0);
/// // Driving (T w > 0): the low side receives N eta T; braking back: N T / eta.
/// assert!((gear.low_side_torque_n_m(100.0, 150.0) - 970.0).abs() < 1e-9);
/// assert!((gear.low_side_torque_n_m(-100.0, 150.0) + 1000.0 / 0.97).abs() < 1e-9);
/// assert!((gear.referred_inertia_kg_m2(1172.0) - 11.72).abs() < 1e-12); // J / N^2 (eq. 3.6)
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reducer<R = f64> {
    pub ratio: R,
    pub efficiency: R,
}

impl Reducer {
    /// Its effects (Table 3.1): the reduction ratio (a lossless transformer) ...
    pub const RATIO: Effect = Effect { domains: &[Domain::Rotational], kind: Kind::Transformer, what: "reduction ratio" };
    /// ... and its efficiency (the loss, a dissipation; see [`loss_flowing_w`](Self::loss_flowing_w)).
    pub const EFFICIENCY: Effect = Effect { domains: &[Domain::Rotational], kind: Kind::Dissipation, what: "reducer efficiency" };
}

impl<R: Real> Reducer<R> {
    // Every law below is the worm gear's with one efficiency both ways: [`WormGear`] holds it.

    /// Low-side speed for a high-side speed, rad/s.
    pub fn low_speed(&self, high_speed_rad_per_s: R) -> R {
        WormGear::from(*self).low_speed(high_speed_rad_per_s)
    }

    /// Low-side torque delivered for a high-side torque, N m: the losses always reduce the
    /// torque on the receiving side, so eta multiplies when power flows from the high side
    /// (T w >= 0) and divides when it flows back.
    pub fn low_side_torque_n_m(&self, high_torque_n_m: R, high_speed_rad_per_s: R) -> R {
        WormGear::from(*self).low_side_torque_n_m(high_torque_n_m, high_speed_rad_per_s)
    }

    /// Low-side torque for a high-side torque with the direction of the power given (`forward`:
    /// from the high side to the low side), N m. The efficiency switches from eta to 1/eta where
    /// the power reverses, a kink in the equations: a model that holds the direction as a
    /// discrete mode (see [`next_power_flow`](Self::next_power_flow)) lets the solver stop there
    /// instead of stepping across it.
    pub fn low_side_torque_flowing_n_m(&self, high_torque_n_m: R, forward: bool) -> R {
        WormGear::from(*self).low_side_torque_flowing_n_m(high_torque_n_m, forward)
    }

    /// The event indicator of a power-flow mode (1: the power flows from the high side, -1: back):
    /// the power through the reducer, T w on the high side, signed to be positive while the
    /// mode holds.
    pub fn power_flow_indicator(&self, mode: i32, high_torque_n_m: R, high_speed_rad_per_s: R) -> R {
        WormGear::from(*self).power_flow_indicator(mode, high_torque_n_m, high_speed_rad_per_s)
    }

    /// The power-flow mode after an event: the sign of the power P; where P is exactly zero, the
    /// sign of dP/dt (where it is heading), and where that is zero too (a drive at rest) the mode
    /// holds. The answer does not depend on the current mode when P != 0, so a repeated update
    /// settles at once.
    pub fn next_power_flow(&self, mode: i32, power_w: R, power_rate_w_per_s: R) -> i32 {
        WormGear::from(*self).next_power_flow(mode, power_w, power_rate_w_per_s)
    }

    /// High-side torque that delivers a given low-side torque, N m (the inverse of
    /// `low_side_torque_n_m` at the same speed).
    pub fn high_side_torque_n_m(&self, low_torque_n_m: R, high_speed_rad_per_s: R) -> R {
        WormGear::from(*self).high_side_torque_n_m(low_torque_n_m, high_speed_rad_per_s)
    }

    /// A low-side inertia seen from the high side, J / N^2 (eqs. 3.4-3.7).
    pub fn referred_inertia_kg_m2(&self, low_side_inertia_kg_m2: R) -> R {
        WormGear::from(*self).referred_inertia_kg_m2(low_side_inertia_kg_m2)
    }

    /// Power lost in the gears, W (never negative).
    pub fn loss_w(&self, high_torque_n_m: R, high_speed_rad_per_s: R) -> R {
        WormGear::from(*self).loss_w(high_torque_n_m, high_speed_rad_per_s)
    }

    /// Power lost in the gears with the direction of the power given (as in
    /// [`low_side_torque_flowing_n_m`](Self::low_side_torque_flowing_n_m)), W: the high side's
    /// power minus the low side's. Never negative while `forward` agrees with the sign of the
    /// power; a model holding the direction as a mode reports this one, which is what its
    /// equations transmit.
    pub fn loss_flowing_w(&self, high_torque_n_m: R, high_speed_rad_per_s: R, forward: bool) -> R {
        WormGear::from(*self).loss_flowing_w(high_torque_n_m, high_speed_rad_per_s, forward)
    }
}

/// A worm gear (the column-type power steering's reducer, section 3.4.2, Figure 3.17: the
/// assistance motor turns the worm, the wheel is keyed on the steering column): ratio
/// N = worm speed / wheel speed (wheel teeth over worm starts), and an efficiency that depends on
/// which side drives. `forward_efficiency` eta_f applies while the power flows from the worm
/// (the high side, the motor) to the wheel (the low side, the column); `backward_efficiency` eta_b
/// while the wheel drives the worm (the road's feedback turning the motor back). Sliding
/// friction on the worm's thread makes eta_b < eta_f (see
/// [`from_lead_and_friction_angle`](Self::from_lead_and_friction_angle)).
///
/// A [`Reducer`] is the case eta_f = eta_b, and uses these laws. The API is the reducer's: the
/// direction of the power is a discrete mode (1 forward, -1 backward) with its
/// [`power_flow_indicator`](Self::power_flow_indicator) and
/// [`next_power_flow`](Self::next_power_flow), the torque and the loss given the direction.
///
/// **Self-locking.** Where eta_b <= 0 (a lead angle at or below the friction angle) the wheel
/// cannot drive the worm at all: pushed from the wheel, the gear locks and holds any torque at
/// rest, like a stuck [`CoulombFriction`], instead of passing a power on. That is not a power-flow
/// direction, and the law T_low = N T_high / eta_b would create energy there, so
/// [`new`](Self::new) and `from_lead_and_friction_angle` refuse such a gear
/// ([`WormGearError::SelfLocking`]); a power steering's worm is made reversible on purpose (the
/// wheels must self-centre and the driver steer with the motor off). The fields stay public,
/// as in every component, so a struct literal is not checked.
/// ```
/// use components::WormGear;
/// // 20 degrees of lead angle, steel on bronze at mu = 0.05: phi = atan(0.05) = 2.862 degrees,
/// // eta_f = tan 20 / tan 22.862 = 0.8632, eta_b = tan 17.138 / tan 20 = 0.8472.
/// let worm = WormGear::from_lead_and_friction_angle(16.5, 20f64.to_radians(), 0.05f64.atan()).unwrap();
/// assert!((worm.forward_efficiency - 0.8632).abs() < 1e-4 && (worm.backward_efficiency - 0.8472).abs() < 1e-4);
/// // The motor drives (T w > 0 on the worm): the column receives N eta_f T.
/// assert!((worm.low_side_torque_n_m(2.0, 100.0) - 16.5 * 0.8632 * 2.0).abs() < 1e-3);
/// // The road drives back (T w < 0 on the worm): the wheel's torque is N T / eta_b, so the worm
/// // (the motor) receives eta_b of the wheel's power.
/// assert!((worm.low_side_torque_n_m(-2.0, 100.0) + 16.5 * 2.0 / 0.8472).abs() < 1e-2);
/// // A 5 degree lead at mu = 0.1 (phi = 5.71 degrees) is self-locking: refused.
/// assert!(WormGear::from_lead_and_friction_angle(30.0, 5f64.to_radians(), 0.1f64.atan()).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WormGear<R = f64> {
    /// N = worm (high side) speed / wheel (low side) speed.
    pub ratio: R,
    /// eta_f, power flowing from the worm to the wheel, in (0, 1].
    pub forward_efficiency: R,
    /// eta_b, power flowing from the wheel back to the worm, in (0, 1] (<= 0: self-locking).
    pub backward_efficiency: R,
}

/// Why [`WormGear::new`] refuses a gear.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WormGearError {
    /// eta_b <= 0: the wheel cannot drive the worm (see [`WormGear`]).
    SelfLocking { backward_efficiency: f64 },
    /// A ratio that is not positive and finite, or an efficiency outside (0, 1].
    OutOfRange { what: &'static str, value: f64 },
}

/// The discrete state of a lossy gear with dry friction (a [`WormGear`] or a [`Reducer`] whose
/// shafts also rub): 0 at rest, held by its friction; otherwise the sign is the direction of
/// motion of the high side and the magnitude says which way the power flows, 1 forwards (from the
/// high side), 2 backwards. As long as the gear moves, its torque ratio follows the power's
/// direction; at rest it holds every torque ratio between its two efficiencies (and the dry
/// friction on top), like a stuck [`CoulombFriction`], which is what keeps a lossy gear from
/// chattering between its two directions where its speed reverses (Modelica's `LossyGear` has
/// the same modes).
/// ```
/// use components::GearMode;
/// assert_eq!(GearMode::of(-1.0, false), -2);
/// assert_eq!((GearMode::direction(-2), GearMode::forward(-2)), (-1.0, false));
/// // Moving forwards with the power forwards: the mode holds while both stay so.
/// assert!(GearMode::moving_margin(1, 3.0, 0.5) > 0.0);
/// assert!(GearMode::moving_margin(1, 3.0, -0.5) < 0.0); // the torque reversed: the power flows back
/// assert!(GearMode::moving_margin(1, -1e-3, 0.5) < 0.0); // the motion reversed
/// ```
pub struct GearMode;

impl GearMode {
    /// At rest, held by the friction.
    pub const STUCK: i32 = 0;
    /// The four moving modes, in the order a breakaway tries them.
    pub const MOVING: [i32; 4] = [1, -1, 2, -2];

    /// The mode moving in `direction` (its sign) with the power flowing forwards or back.
    pub fn of<R: Real>(direction: R, forward: bool) -> i32 {
        let magnitude = if forward { 1 } else { 2 };
        if direction < 0.0 {
            -magnitude
        } else {
            magnitude
        }
    }

    /// The direction of motion: 1, -1, or 0 at rest.
    pub fn direction(mode: i32) -> f64 {
        f64::from(mode.signum())
    }

    /// Whether the power flows forwards (from the high side) in a moving mode.
    pub fn forward(mode: i32) -> bool {
        mode.abs() != 2
    }

    /// The event indicator of a moving mode: positive while the high side's speed keeps the
    /// mode's direction and its torque the power's direction (the smaller of the two margins,
    /// each in its own unit: only its sign and its zero matter).
    pub fn moving_margin<R: Real>(mode: i32, high_speed: R, high_torque: R) -> R {
        let s = Self::direction(mode);
        let d = if Self::forward(mode) { 1.0 } else { -1.0 };
        (high_speed * s).min(high_torque * (d * s))
    }

    /// At rest, how consistently a moving mode would start: positive when its own equations
    /// accelerate the high side in its direction with the power in its direction.
    pub fn breakaway_margin<R: Real>(mode: i32, high_acceleration: R, high_torque: R) -> R {
        Self::moving_margin(mode, high_acceleration, high_torque)
    }

    /// The mode after an event. Moving (|speed| above `standstill`, in the mode's direction): the direction of the speed
    /// and the power's direction from the torque's sign (held where the torque is exactly 0).
    /// At rest: stuck exactly while its indicator [`stuck_margin`](Self::stuck_margin) is
    /// positive (every moving mode's [`breakaway_margin`](Self::breakaway_margin) negative;
    /// `start(mode)` gives that mode's high-side acceleration and torque), else the moving mode
    /// with the largest margin, so the update always agrees with the crossing that triggered it,
    /// even where the located point has the indicator at 0. Returns the mode and whether the
    /// speed must be set to exactly 0.
    pub fn next<R: Real>(mode: i32, high_speed: R, high_torque: R, standstill: f64, start: impl Fn(i32) -> (R, R)) -> (i32, bool) {
        // A moving mode whose speed has reversed passed through rest: decided as at rest, however
        // far past the zero the event was located (a Model Exchange master's root finder may
        // stop further past it than `standstill`, and must see the same stop as Co-Simulation).
        let reversed = mode != Self::STUCK && high_speed * Self::direction(mode) <= 0.0;
        if !reversed && high_speed.abs() > standstill {
            let s = high_speed.signum();
            let forward = if high_torque == 0.0 && mode != Self::STUCK { Self::forward(mode) } else { s * high_torque >= 0.0 };
            return (Self::of(s, forward), false);
        }
        let (best, margin) = Self::best_breakaway(start);
        if margin < 0.0 {
            (Self::STUCK, high_speed != 0.0)
        } else {
            (best, false)
        }
    }

    /// The moving mode that would start most consistently from rest, and its margin.
    fn best_breakaway<R: Real>(start: impl Fn(i32) -> (R, R)) -> (i32, R) {
        Self::MOVING
            .into_iter()
            .map(|m| {
                let (acceleration, torque) = start(m);
                (m, Self::breakaway_margin(m, acceleration, torque))
            })
            .fold((Self::STUCK, R::from(f64::NEG_INFINITY)), |best, candidate| if candidate.1 > best.1 { candidate } else { best })
    }

    /// The event indicator at rest: positive while no moving mode would start consistently.
    pub fn stuck_margin<R: Real>(start: impl Fn(i32) -> (R, R)) -> R {
        -Self::best_breakaway(start).1
    }
}

impl std::fmt::Display for WormGearError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            WormGearError::SelfLocking { backward_efficiency } => write!(
                f,
                "self-locking worm gear (backward efficiency {backward_efficiency} <= 0): the wheel cannot drive the worm, which the power-flow modes do not model"
            ),
            WormGearError::OutOfRange { what, value } => write!(f, "worm gear {what} {value} out of range"),
        }
    }
}

impl std::error::Error for WormGearError {}

impl<R: Real> From<Reducer<R>> for WormGear<R> {
    /// A reducer is a worm gear with one efficiency both ways.
    fn from(reducer: Reducer<R>) -> Self {
        WormGear { ratio: reducer.ratio, forward_efficiency: reducer.efficiency, backward_efficiency: reducer.efficiency }
    }
}

impl WormGear {
    /// Its effects (Table 3.1): the ratio (a lossless transformer) ...
    pub const RATIO: Effect = Effect { domains: &[Domain::Rotational], kind: Kind::Transformer, what: "worm gear ratio" };
    /// ... and its efficiencies (the loss, a dissipation; see [`loss_flowing_w`](Self::loss_flowing_w)).
    pub const EFFICIENCY: Effect = Effect { domains: &[Domain::Rotational], kind: Kind::Dissipation, what: "worm gear efficiency (by power direction)" };
}

impl<R: Real> WormGear<R> {
    /// A checked worm gear: the ratio positive and finite, both efficiencies in (0, 1]; a
    /// backward efficiency <= 0 is [`WormGearError::SelfLocking`].
    pub fn new(ratio: R, forward_efficiency: R, backward_efficiency: R) -> Result<Self, WormGearError> {
        let in_unit = |e: R| e > 0.0 && e <= 1.0;
        if !(ratio > 0.0 && ratio.is_finite()) {
            Err(WormGearError::OutOfRange { what: "ratio", value: ratio.value() })
        } else if !in_unit(forward_efficiency) {
            Err(WormGearError::OutOfRange { what: "forward efficiency", value: forward_efficiency.value() })
        } else if backward_efficiency <= 0.0 {
            Err(WormGearError::SelfLocking { backward_efficiency: backward_efficiency.value() })
        } else if !in_unit(backward_efficiency) {
            Err(WormGearError::OutOfRange { what: "backward efficiency", value: backward_efficiency.value() })
        } else {
            Ok(WormGear { ratio, forward_efficiency, backward_efficiency })
        }
    }

    /// The classical efficiencies of a worm from its lead angle lambda (of the thread on the
    /// worm's pitch cylinder) and the friction angle phi of the flanks (see
    /// [`friction_angle_rad`](Self::friction_angle_rad)), as for a screw: the worm driving,
    /// eta_f = tan(lambda) / tan(lambda + phi); the wheel driving, eta_b = tan(lambda - phi) /
    /// tan(lambda), negative (self-locking, refused) when lambda < phi. With phi = 0 both are 1.
    /// ```
    /// use components::WormGear;
    /// // lambda = 30 degrees, phi = 5 degrees: eta_f = 0.57735 / 0.70021 = 0.82454,
    /// // eta_b = 0.46631 / 0.57735 = 0.80767.
    /// let worm = WormGear::from_lead_and_friction_angle(20.0, 30f64.to_radians(), 5f64.to_radians()).unwrap();
    /// assert!((worm.forward_efficiency - 0.82454).abs() < 1e-5);
    /// assert!((worm.backward_efficiency - 0.80767).abs() < 1e-5);
    /// ```
    pub fn from_lead_and_friction_angle(ratio: R, lead_angle_rad: R, friction_angle_rad: R) -> Result<Self, WormGearError> {
        let forward = lead_angle_rad.tan() / (lead_angle_rad + friction_angle_rad).tan();
        let backward = (lead_angle_rad - friction_angle_rad).tan() / lead_angle_rad.tan();
        Self::new(ratio, forward, backward)
    }

    /// The friction angle of the flanks for a friction coefficient mu and the thread's normal
    /// pressure angle alpha_n: phi = atan(mu / cos alpha_n), rad (the wedge of the thread raises
    /// the normal force; alpha_n = 0 gives atan(mu)). Data sheets give mu (0.02-0.1 for steel on
    /// bronze, falling with the sliding speed) and alpha_n (typically 20 degrees).
    /// ```
    /// use components::WormGear;
    /// assert!((WormGear::friction_angle_rad(0.05, 0.0) - 0.05f64.atan()).abs() < 1e-15);
    /// // mu = 0.05, alpha_n = 20 degrees: atan(0.05 / 0.93969) = 3.046 degrees.
    /// assert!((WormGear::friction_angle_rad(0.05, 20f64.to_radians()).to_degrees() - 3.046).abs() < 1e-3);
    /// ```
    pub fn friction_angle_rad(friction_coefficient: R, normal_pressure_angle_rad: R) -> R {
        (friction_coefficient / normal_pressure_angle_rad.cos()).atan()
    }

    /// Wheel (low-side) speed for a worm (high-side) speed, rad/s.
    pub fn low_speed(&self, high_speed_rad_per_s: R) -> R {
        high_speed_rad_per_s / self.ratio
    }

    /// Wheel torque delivered for a worm torque, N m, the direction of the power from the sign
    /// of T w on the worm (as [`Reducer::low_side_torque_n_m`]).
    pub fn low_side_torque_n_m(&self, high_torque_n_m: R, high_speed_rad_per_s: R) -> R {
        self.low_side_torque_flowing_n_m(high_torque_n_m, high_torque_n_m * high_speed_rad_per_s >= 0.0)
    }

    /// Wheel torque for a worm torque with the direction of the power given, N m: N eta_f T
    /// forward (`forward`: from the worm to the wheel), N T / eta_b backward (the worm then
    /// receives eta_b of the wheel's power).
    pub fn low_side_torque_flowing_n_m(&self, high_torque_n_m: R, forward: bool) -> R {
        if forward {
            self.ratio * self.forward_efficiency * high_torque_n_m
        } else {
            self.ratio * high_torque_n_m / self.backward_efficiency
        }
    }

    /// The event indicator of a power-flow mode (1: the power flows from the worm, -1: back):
    /// T w on the worm, signed to be positive while the mode holds.
    pub fn power_flow_indicator(&self, mode: i32, high_torque_n_m: R, high_speed_rad_per_s: R) -> R {
        high_torque_n_m * f64::from(mode.signum()) * high_speed_rad_per_s
    }

    /// The power-flow mode after an event: the sign of the power P; where P is exactly zero, the
    /// sign of dP/dt, and where that is zero too the mode holds (as
    /// [`Reducer::next_power_flow`]).
    pub fn next_power_flow(&self, mode: i32, power_w: R, power_rate_w_per_s: R) -> i32 {
        if power_w != 0.0 {
            power_w.value().signum() as i32
        } else if power_rate_w_per_s != 0.0 {
            power_rate_w_per_s.value().signum() as i32
        } else {
            mode
        }
    }

    /// Worm torque that delivers a given wheel torque at a worm speed, N m (the inverse of
    /// `low_side_torque_n_m` at the same speed).
    pub fn high_side_torque_n_m(&self, low_torque_n_m: R, high_speed_rad_per_s: R) -> R {
        if low_torque_n_m * high_speed_rad_per_s >= 0.0 {
            low_torque_n_m / (self.ratio * self.forward_efficiency)
        } else {
            low_torque_n_m * self.backward_efficiency / self.ratio
        }
    }

    /// A wheel-side inertia seen from the worm, J / N^2 (eqs. 3.4-3.7).
    pub fn referred_inertia_kg_m2(&self, low_side_inertia_kg_m2: R) -> R {
        low_side_inertia_kg_m2 / (self.ratio * self.ratio)
    }

    /// Power lost in the gear, W (never negative).
    pub fn loss_w(&self, high_torque_n_m: R, high_speed_rad_per_s: R) -> R {
        let p_high = high_torque_n_m * high_speed_rad_per_s;
        let p_low = self.low_side_torque_n_m(high_torque_n_m, high_speed_rad_per_s) * self.low_speed(high_speed_rad_per_s);
        (p_high - p_low).abs()
    }

    /// Power lost with the direction of the power given, the worm's power minus the wheel's, W:
    /// (1 - eta_f) T w forward, (1 - 1/eta_b) T w backward (T w < 0 there). Never negative while
    /// `forward` agrees with the sign of the power (as [`Reducer::loss_flowing_w`]).
    pub fn loss_flowing_w(&self, high_torque_n_m: R, high_speed_rad_per_s: R, forward: bool) -> R {
        high_torque_n_m * high_speed_rad_per_s - self.low_side_torque_flowing_n_m(high_torque_n_m, forward) * self.low_speed(high_speed_rad_per_s)
    }
}

/// Aerodynamic torque of fan blades, T = k w |w| (opposes the rotation; Table 3.1).
/// ```
/// use components::FanLoad;
/// let fan = FanLoad { coefficient_n_m_s2_per_rad2: 42.9 };
/// assert_eq!(fan.torque_n_m(10.0), 4290.0);
/// assert_eq!(fan.torque_n_m(-10.0), -4290.0); // always against the rotation
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FanLoad<R = f64> {
    pub coefficient_n_m_s2_per_rad2: R,
}

impl FanLoad {
    /// Its effect (Table 3.1: "source of aerodynamic forces (function of rotational speed)"):
    /// it takes the power T w out of the drive, a dissipation.
    pub const LOAD: Effect = Effect { domains: &[Domain::Rotational], kind: Kind::Dissipation, what: "aerodynamic load" };
}

impl<R: Real> FanLoad<R> {
    /// The load that absorbs `nominal_torque_n_m` at `nominal_speed_rad_per_s`: k = T_n / w_n^2.
    /// ```
    /// use components::FanLoad;
    /// let load = FanLoad::from_nominal(1.75e5, 12.56);
    /// assert!((load.torque_n_m(12.56) - 1.75e5).abs() < 1e-9);
    /// ```
    pub fn from_nominal(nominal_torque_n_m: R, nominal_speed_rad_per_s: R) -> Self {
        FanLoad { coefficient_n_m_s2_per_rad2: nominal_torque_n_m / (nominal_speed_rad_per_s * nominal_speed_rad_per_s) }
    }

    /// T = k w |w|: against the rotation in both directions.
    pub fn torque_n_m(&self, speed_rad_per_s: R) -> R {
        self.coefficient_n_m_s2_per_rad2 * speed_rad_per_s * speed_rad_per_s.abs()
    }

    /// T = k w^2: the same direction whatever the rotation's, a braking torque turning forwards
    /// and a driving one turning backwards. Not physical for blades in a fluid (they brake both
    /// ways), but the way some models write the law; it differs from `torque_n_m` only for w < 0.
    /// ```
    /// use components::FanLoad;
    /// let load = FanLoad { coefficient_n_m_s2_per_rad2: 2.0 };
    /// assert_eq!(load.unidirectional_torque_n_m(3.0), load.torque_n_m(3.0));
    /// assert_eq!(load.unidirectional_torque_n_m(-3.0), 18.0);
    /// ```
    pub fn unidirectional_torque_n_m(&self, speed_rad_per_s: R) -> R {
        self.coefficient_n_m_s2_per_rad2 * speed_rad_per_s * speed_rad_per_s
    }
}

/// A propeller's hydrodynamic torque follows the same quadratic law as a fan's, T = a w |w|
/// (chapter 3.5.3: "T = alpha w^2", the coupling with the submarine's forward speed ignored).
pub type PropellerLoad<R = f64> = FanLoad<R>;

/// Coulomb friction with sticking (a seal on a shaft): while the body slips the friction torque is
/// -T_c in the direction of slip; while it sticks the body stands still and the friction takes
/// whatever torque holding it requires, up to T_s. The direction is a discrete mode (1 forwards,
/// 0 stuck, -1 backwards), so the equations stay smooth between events and never chatter on
/// sign(w). The mode logic knows no units (an effort and a flow): the translational
/// [`SlidingFriction`](crate::translational::SlidingFriction) runs on it with forces and velocities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoulombFriction<R = f64> {
    /// T_c, N m: the torque while slipping.
    pub coulomb_n_m: R,
    /// T_s >= T_c, N m: the largest torque it holds while stuck.
    pub static_n_m: R,
}

impl CoulombFriction {
    /// Its effect (Table 3.1): a dissipation.
    pub const FRICTION: Effect = Effect { domains: &[Domain::Rotational], kind: Kind::Dissipation, what: "friction" };

    /// Below this speed a body in the stuck mode stands still (1e-9 rad/s: a turn in 200 years).
    pub const STANDSTILL_RAD_PER_S: f64 = 1e-9;
}

impl<R: Real> CoulombFriction<R> {
    /// The friction torque on a body slipping in `direction` (+-1; 0 when stuck), N m.
    pub fn slip_torque_n_m(&self, direction: i32) -> R {
        -self.coulomb_n_m * direction as f64
    }

    /// The event indicator: slipping, the speed in the direction of slip (it reaches zero when the
    /// body stops); stuck, the margin T_s - |T_required| (it reaches zero when the body breaks
    /// loose). `required_n_m` is the torque the friction must take to hold the body still: the sum
    /// of every other torque on it.
    pub fn indicator(&self, mode: i32, speed_rad_per_s: R, required_n_m: R) -> R {
        if mode == 0 {
            self.static_n_m - required_n_m.abs()
        } else {
            speed_rad_per_s * mode as f64
        }
    }

    /// The mode after an event and whether the speed must be set to exactly 0: a slipping body
    /// that stopped sticks if the friction can hold it, else slips the way it is pushed; a stuck
    /// body breaks loose in the direction of the required torque; a "stuck" body that moves (start
    /// values) slips in its direction of motion. A mode holds exactly while its `indicator` is
    /// positive (the FMI convention for an indicator's two domains), so the update always agrees
    /// with the crossing that triggered it, even where the located point has the indicator at 0.
    ///
    /// A stuck body counts as moving only above [`CoulombFriction::STANDSTILL_RAD_PER_S`]: its speed
    /// has a zero derivative, but a Model Exchange master's integrator may leave round-off on it
    /// (fmpy's CVode: -1.9e-22 rad/s at ShaftLine's breakaway), which must not pick the direction.
    pub fn next_mode(&self, mode: i32, speed_rad_per_s: R, required_n_m: R) -> (i32, bool) {
        let pushed = if required_n_m > 0.0 { 1 } else { -1 };
        let holds = self.indicator(0, R::from(0.0), required_n_m) > 0.0;
        match mode {
            0 if speed_rad_per_s.abs() > CoulombFriction::<f64>::STANDSTILL_RAD_PER_S => (if speed_rad_per_s > 0.0 { 1 } else { -1 }, false),
            0 if !holds => (pushed, false),
            0 => (0, false),
            d if self.indicator(d, speed_rad_per_s, required_n_m) <= 0.0 => {
                if holds {
                    (0, true)
                } else {
                    (pushed, true)
                }
            }
            d => (d, false),
        }
    }

    /// Power dissipated while slipping, W (zero while stuck: the body does not move).
    pub fn power_w(&self, mode: i32, speed_rad_per_s: R) -> R {
        (self.slip_torque_n_m(mode) * speed_rad_per_s).abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lossy gear at rest between a driving torque and a load, both at the high side: the
    /// column of a power steering, J dw/dt = e T_drive - T_load in each moving mode (e = eta_f
    /// forwards, 1/eta_b backwards; T_drive is also the worm's torque here, no rotor inertia).
    fn lossy_start(drive: f64, load: f64, friction: f64) -> impl Fn(i32) -> (f64, f64) {
        let (eta_f, eta_b) = (0.8, 0.5);
        move |mode| {
            let e = if GearMode::forward(mode) { eta_f } else { 1.0 / eta_b };
            (e * drive - load - GearMode::direction(mode) * friction, drive)
        }
    }

    #[test]
    fn a_lossy_gear_holds_between_its_efficiencies_and_breaks_away_the_consistent_way() {
        let standstill = 1e-9;
        // Driving 10 against a load between eta_f 10 = 8 and 10 / eta_b = 20: it holds.
        let held = lossy_start(10.0, 12.0, 0.0);
        assert_eq!(GearMode::next(GearMode::STUCK, 0.0, 10.0, standstill, &held), (GearMode::STUCK, false));
        assert!(GearMode::stuck_margin(&held) > 0.0);
        // A load below 8: the motor drives forwards (mode 1); above 20: the load drives it back
        // against the motor (mode -2: moving backwards, the power flowing back into the motor).
        assert_eq!(GearMode::next(GearMode::STUCK, 0.0, 10.0, standstill, lossy_start(10.0, 5.0, 0.0)).0, 1);
        assert_eq!(GearMode::next(GearMode::STUCK, 0.0, 10.0, standstill, lossy_start(10.0, 25.0, 0.0)).0, -2);
        assert!(GearMode::stuck_margin(lossy_start(10.0, 25.0, 0.0)) < 0.0);
        // No torque at all: without dry friction the band is empty (margin 0, it may start); with
        // it, the gear holds with a positive margin (an indicator that starts positive).
        assert_eq!(GearMode::stuck_margin(lossy_start(0.0, 0.0, 0.0)), 0.0);
        assert!(GearMode::stuck_margin(lossy_start(0.0, 0.0, 0.5)) > 0.0);
        // A moving gear that reaches rest where it holds is stuck, its speed reset to exactly 0.
        assert_eq!(GearMode::next(1, 1e-12, 10.0, standstill, &held), (GearMode::STUCK, true));
        // Moving: the direction of the speed, the power's from the torque's sign.
        assert_eq!(GearMode::next(2, 0.3, 10.0, standstill, &held).0, 1);
        assert_eq!(GearMode::next(-1, -0.3, 10.0, standstill, &held).0, -2);
        assert_eq!(GearMode::next(GearMode::STUCK, -0.3, 10.0, standstill, &held).0, -2); // a start value
        // A speed that reversed in its mode went through rest: held there, it sticks (speed reset),
        // however far past the zero the event was located.
        assert_eq!(GearMode::next(1, -0.3, 10.0, standstill, &held), (GearMode::STUCK, true));
        assert_eq!(GearMode::next(1, -0.3, 10.0, standstill, lossy_start(10.0, 25.0, 0.0)).0, -2);
        // Each moving mode holds exactly while its indicator is positive.
        for mode in GearMode::MOVING {
            let (s, d) = (GearMode::direction(mode), if GearMode::forward(mode) { 1.0 } else { -1.0 });
            assert!(GearMode::moving_margin(mode, s * 0.3, d * s * 10.0) > 0.0);
            assert_eq!(GearMode::next(mode, s * 0.3, d * s * 10.0, standstill, &held).0, mode);
        }
    }

    #[test]
    fn a_stuck_body_breaks_loose_the_way_it_is_pushed_whatever_round_off_its_speed_carries() {
        let seal = CoulombFriction { coulomb_n_m: 9000.0, static_n_m: 9000.0 };
        // Breakaway: pushed forwards, with an ME integrator's round-off on the speed either way.
        for speed in [0.0, -1.9e-22, 1.9e-22, -1e-10] {
            assert_eq!(seal.next_mode(0, speed, 9000.5), (1, false), "{speed}");
            assert_eq!(seal.next_mode(0, speed, -9000.5), (-1, false), "{speed}");
            assert_eq!(seal.next_mode(0, speed, 100.0), (0, false), "{speed}");
        }
        // A body that really moves (start values) slips the way it moves.
        assert_eq!(seal.next_mode(0, -0.5, 100.0), (-1, false));
        assert_eq!(seal.next_mode(0, 0.5, -9500.0), (1, false));
    }

    #[test]
    fn torsion_bar_twists_in_proportion_up_to_its_stops() {
        let bar = TorsionBar { stiffness_n_m_per_rad: 100.0, stop_angle_rad: 0.1 };
        assert_eq!(bar.twist_rad(5.0), 0.05);
        assert_eq!(bar.twist_rad(-5.0), -0.05);
        assert_eq!((bar.twist_rad(50.0), bar.twist_rad(-50.0)), (0.1, -0.1));
        assert_eq!(bar.stop_torque_n_m(), 10.0);
        // K = G J / l with J = pi d^4 / 32: a 5 mm steel bar (G = 80 GPa) 40 mm long
        let j = std::f64::consts::PI * 0.005f64.powi(4) / 32.0;
        let k = TorsionBar::round_bar_stiffness_n_m_per_rad(80e9, 0.005, 0.04);
        assert!((k - 80e9 * j / 0.04).abs() < 1e-9 * k);
    }

    #[test]
    fn chapter_numbers_come_out() {
        // Section 3.3.3: fan inertia referred to the high-speed axis 11.72 kg m2, and eq. 3.8
        // sqrt(K/J_eq)/2pi = 1.4 Hz with the motor speed imposed; ~3.9 Hz with the motor free.
        let reducer = Reducer { ratio: 10.0, efficiency: 0.97 };
        let j_eq = reducer.referred_inertia_kg_m2(1172.0);
        assert!((j_eq - 11.72).abs() < 1e-12);
        let k = j_eq * (2.0 * std::f64::consts::PI * 1.4f64).powi(2);
        let shaft = TorsionSpring { stiffness_n_m_per_rad: k, damping_n_m_s_per_rad: 0.0 };
        assert!((shaft.natural_frequency_hz(j_eq, f64::INFINITY) - 1.4).abs() < 1e-12);
        let free = shaft.natural_frequency_hz(j_eq, 1.72);
        assert!((free - 3.91).abs() < 0.01, "{free}");
    }

    #[test]
    fn reducer_losses_are_never_negative_and_inverse_is_exact() {
        let r = Reducer { ratio: 10.0, efficiency: 0.97 };
        for (t, w) in [(100.0, 150.0), (-100.0, 150.0), (100.0, -150.0), (-50.0, -10.0)] {
            assert!(r.loss_w(t, w) >= 0.0);
            let t_low = r.low_side_torque_n_m(t, w);
            assert!((r.high_side_torque_n_m(t_low, w) - t).abs() < 1e-12);
        }
        // Forward: 3 % of the power is lost.
        assert!((r.loss_w(100.0, 150.0) - 0.03 * 15000.0).abs() < 1e-9);
    }

    #[test]
    fn the_power_flow_mode_follows_the_power_and_settles_at_zero() {
        let r = Reducer { ratio: 10.0, efficiency: 0.97 };
        // The held branch agrees with the sign test wherever the mode is right.
        for (t, w) in [(100.0, 150.0), (-100.0, 150.0), (100.0, -150.0), (-50.0, -10.0)] {
            let mode = r.next_power_flow(1, t * w, 0.0);
            assert_eq!(r.low_side_torque_flowing_n_m(t, mode > 0), r.low_side_torque_n_m(t, w));
            assert!(r.power_flow_indicator(mode, t, w) > 0.0, "the mode holds while its indicator is positive");
        }
        // At P = 0 the update follows dP/dt, whatever the mode, so it settles in one update
        // (a flip on the indicator's sign alone would chatter between the modes at P = 0).
        for mode in [1, -1] {
            assert_eq!(r.next_power_flow(mode, 0.0, -3.0), -1);
            assert_eq!(r.next_power_flow(mode, 0.0, 2.0), 1);
            assert_eq!(r.next_power_flow(mode, 0.0, 0.0), mode, "at rest the mode holds");
        }
    }

    #[test]
    fn a_reducer_is_a_worm_gear_with_one_efficiency_both_ways() {
        let r = Reducer { ratio: 16.0, efficiency: 0.94 };
        let w = WormGear::from(r);
        for (t, s) in [(100.0, 150.0), (-100.0, 150.0), (100.0, -150.0), (-50.0, -10.0), (0.0, 3.0)] {
            assert_eq!(r.low_side_torque_n_m(t, s), w.low_side_torque_n_m(t, s));
            assert_eq!(r.high_side_torque_n_m(t, s), w.high_side_torque_n_m(t, s));
            assert_eq!(r.loss_w(t, s), w.loss_w(t, s));
            assert_eq!(r.loss_flowing_w(t, s, false), w.loss_flowing_w(t, s, false));
            assert_eq!(r.power_flow_indicator(-1, t, s), w.power_flow_indicator(-1, t, s));
            // The reducer's own formulas, as they stood before the worm gear held them.
            assert_eq!(r.low_side_torque_flowing_n_m(t, true), r.ratio * r.efficiency * t);
            assert_eq!(r.low_side_torque_flowing_n_m(t, false), r.ratio * t / r.efficiency);
        }
        assert_eq!(r.referred_inertia_kg_m2(3000.0), 3000.0 / 256.0);
    }

    #[test]
    fn a_worm_gear_loses_power_both_ways_and_passes_eta_of_it() {
        let worm = WormGear::new(16.5, 0.86, 0.72).unwrap();
        for (t, s) in [(2.0, 100.0), (-2.0, 100.0), (2.0, -100.0), (-3.0, -40.0)] {
            let forward = t * s >= 0.0;
            let mode = worm.next_power_flow(-1, t * s, 0.0);
            assert_eq!(mode > 0, forward);
            assert!(worm.power_flow_indicator(mode, t, s) > 0.0);
            let loss = worm.loss_flowing_w(t, s, forward);
            assert!(loss > 0.0 && (loss - worm.loss_w(t, s)).abs() < 1e-12);
            // Power on each side: the receiving side gets eta of what the driving side gives.
            let (p_worm, p_wheel) = (t * s, worm.low_side_torque_n_m(t, s) * worm.low_speed(s));
            if forward {
                assert!((p_wheel - 0.86 * p_worm).abs() < 1e-12);
            } else {
                assert!((p_worm - 0.72 * p_wheel).abs() < 1e-12);
            }
            let t_low = worm.low_side_torque_n_m(t, s);
            assert!((worm.high_side_torque_n_m(t_low, s) - t).abs() < 1e-12);
        }
        // Forward: 14 % of 200 W lost; backward, the wheel gives 200 / 0.72 W for the worm's 200 W.
        assert!((worm.loss_w(2.0, 100.0) - 28.0).abs() < 1e-12);
        assert!((worm.loss_w(-2.0, 100.0) - (200.0 / 0.72 - 200.0)).abs() < 1e-12);
        assert_eq!(worm.referred_inertia_kg_m2(16.5 * 16.5), 1.0);
    }

    #[test]
    fn the_lead_angle_formula_has_the_right_limits() {
        use std::f64::consts::FRAC_PI_4;
        // No friction: a perfect gear both ways, whatever the lead.
        for lead in [5f64, 20.0, 40.0] {
            let w = WormGear::from_lead_and_friction_angle(10.0, lead.to_radians(), 0.0).unwrap();
            assert!((w.forward_efficiency - 1.0).abs() < 1e-15 && (w.backward_efficiency - 1.0).abs() < 1e-15);
        }
        // With friction the wheel drives back less well than the worm drives forward, and both
        // improve with the lead angle up to the forward optimum at lambda = 45 deg - phi / 2.
        let phi = 0.06f64.atan();
        let eta = |lead: f64| WormGear::from_lead_and_friction_angle(10.0, lead, phi).unwrap();
        for lead in [10f64, 20.0, 30.0] {
            let w = eta(lead.to_radians());
            assert!(w.backward_efficiency < w.forward_efficiency && w.forward_efficiency < 1.0);
            assert!(eta((lead + 1.0).to_radians()).backward_efficiency > w.backward_efficiency);
        }
        let best = FRAC_PI_4 - phi / 2.0;
        let at = |lead: f64| eta(lead).forward_efficiency;
        assert!(at(best) > at(best - 1e-3) && at(best) > at(best + 1e-3));
        // At the optimum eta_f = (1 - sin phi) / (1 + sin phi) (tan^2 of best).
        assert!((at(best) - (1.0 - phi.sin()) / (1.0 + phi.sin())).abs() < 1e-12);
        // Self-locking where lambda <= phi: eta_b <= 0, refused.
        match WormGear::from_lead_and_friction_angle(40.0, phi, phi) {
            Err(WormGearError::SelfLocking { backward_efficiency }) => assert!(backward_efficiency.abs() < 1e-15),
            other => panic!("{other:?}"),
        }
        assert!(matches!(WormGear::from_lead_and_friction_angle(40.0, phi / 2.0, phi), Err(WormGearError::SelfLocking { .. })));
        assert!(matches!(WormGear::new(0.0, 0.9, 0.8), Err(WormGearError::OutOfRange { what: "ratio", .. })));
        assert!(matches!(WormGear::new(10.0, 1.2, 0.8), Err(WormGearError::OutOfRange { what: "forward efficiency", .. })));
        assert!(matches!(WormGear::new(10.0, 0.9, 1.5), Err(WormGearError::OutOfRange { what: "backward efficiency", .. })));
        assert!(WormGear::new(10.0, 0.9, -0.1).unwrap_err().to_string().contains("self-locking"));
    }

    #[test]
    fn storage_powers_are_rates_of_energy() {
        let j = Inertia { inertia_kg_m2: 2.0 };
        let (w, a) = (3.0, 0.5);
        assert!((j.power_w(a, w) - j.inertia_kg_m2 * w * a).abs() < 1e-15);
        assert_eq!(j.acceleration_rad_per_s2(4.0), 2.0);
        assert_eq!(j.energy_j(3.0), 9.0);
        let s = TorsionSpring { stiffness_n_m_per_rad: 10.0, damping_n_m_s_per_rad: 1.0 };
        assert_eq!(s.torque_n_m(0.1, 2.0), 3.0);
        assert_eq!(s.spring_power_w(0.1, 2.0), 2.0);
        assert_eq!(s.damper_power_w(-2.0), 4.0);
        assert_eq!(FanLoad { coefficient_n_m_s2_per_rad2: 2.0 }.torque_n_m(-3.0), -18.0);
    }

    #[test]
    fn coulomb_friction_sticks_when_it_can_hold_and_slips_the_way_it_is_pushed() {
        let f = CoulombFriction { coulomb_n_m: 9000.0, static_n_m: 9000.0 };
        assert_eq!(f.slip_torque_n_m(1), -9000.0);
        assert_eq!(f.indicator(1, 2.0, 0.0), 2.0);
        assert_eq!(f.indicator(-1, 2.0, 0.0), -2.0, "slipping backwards but moving forwards: crossed");
        assert_eq!(f.indicator(0, 0.0, -8000.0), 1000.0);
        assert_eq!(f.next_mode(1, -1e-12, 5000.0), (0, true), "stopped, held");
        assert_eq!(f.next_mode(1, -1e-12, -2e5), (-1, true), "stopped, pushed back through");
        assert_eq!(f.next_mode(0, 0.0, 9500.0), (1, false), "breaks loose forwards");
        assert_eq!(f.next_mode(0, 0.0, -9000.0), (-1, false), "at the limit the indicator is 0: broken loose");
        assert_eq!(f.next_mode(1, 0.0, 9000.0), (1, true), "stopped at the limit: slips on");
        assert_eq!(f.next_mode(0, 0.0, -8000.0), (0, false));
        assert_eq!(f.next_mode(0, -3.0, 0.0), (-1, false), "moving at the start");
        assert_eq!(f.next_mode(-1, -3.0, 0.0), (-1, false));
        assert_eq!(f.power_w(0, 0.0), 0.0);
        assert_eq!(f.power_w(-1, -2.0), 18000.0);
    }
}
