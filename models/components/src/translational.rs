//! Translational mechanics (the rack of the power steering, section 3.4.2, Figures 3.17-3.19; the
//! actuator rod and control-surface horn of the EHA, Figure 3.16.a): effort = force (N), flow =
//! velocity (m/s). The laws are rotation's with a force for a torque and a velocity for an
//! angular speed, so each element here runs on its rotational twin in [`crate::mechanical`]
//! (one law, written once); the rack and pinion and the lever convert between the two domains.

use fmu_runtime::real::Real;
use crate::mechanical::{CableDrum, CoulombFriction, Inertia, TorsionSpring};
use fmu_runtime::elements::{Domain, Effect, Kind};

/// A rigid body in translation: m dv/dt = net force (inertial storage; the twin of [`Inertia`],
/// m for eq. 3.1's J).
/// ```
/// use components::Mass;
/// // A 3 kg steering rack under a net 60 N accelerates at 20 m/s2.
/// let rack = Mass { mass_kg: 3.0 };
/// assert!((rack.acceleration_m_per_s2(60.0) - 20.0).abs() < 1e-12);
/// assert!((rack.energy_j(0.4) - 0.24).abs() < 1e-12); // m v^2 / 2 at 0.4 m/s
/// assert!((rack.power_w(20.0, 0.4) - 24.0).abs() < 1e-12); // m a v = d/dt (m v^2 / 2)
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mass<R = f64> {
    pub mass_kg: R,
}

impl Mass {
    /// Its effect (Table 3.1): inertial storage in translation.
    pub const MASS: Effect = Effect { domains: &[Domain::Translational], kind: Kind::StorageI, what: "mass" };
}

impl<R: Real> Mass<R> {
    fn rotational_twin(&self) -> Inertia<R> {
        Inertia { inertia_kg_m2: self.mass_kg }
    }

    /// dv/dt under a net force, m/s2.
    pub fn acceleration_m_per_s2(&self, net_force_n: R) -> R {
        self.rotational_twin().acceleration_rad_per_s2(net_force_n)
    }

    /// Power stored per second, m dv/dt v, W (positive while speeding up).
    pub fn power_w(&self, acceleration_m_per_s2: R, velocity_m_per_s: R) -> R {
        self.rotational_twin().power_w(acceleration_m_per_s2, velocity_m_per_s)
    }

    /// Kinetic energy m v^2 / 2, J.
    pub fn energy_j(&self, velocity_m_per_s: R) -> R {
        self.rotational_twin().energy_j(velocity_m_per_s)
    }
}

/// A spring with internal damping between two points: F = k x + d dx/dt, x the elongation (a tie
/// rod, Figure 3.19; a hydraulic column's stiffness, Table 3.2: k = A^2 B / V, see
/// [`geometry`](crate::geometry)). The twin of [`TorsionSpring`].
/// ```
/// use components::TranslationalSpring;
/// let rod = TranslationalSpring { stiffness_n_per_m: 4e4, damping_n_s_per_m: 50.0 };
/// assert_eq!(rod.force_n(0.01, 0.1), 405.0); // k x + d v = 400 + 5
/// assert_eq!(rod.damper_power_w(0.1), 0.5); // d v^2
/// assert!((rod.energy_j(0.01) - 2.0).abs() < 1e-12); // k x^2 / 2
/// // 10 kg on a fixed base: sqrt(k/m) / 2 pi = sqrt(4000) / 2 pi = 10.066 Hz.
/// assert!((rod.natural_frequency_hz(10.0, f64::INFINITY) - 10.066).abs() < 1e-3);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TranslationalSpring<R = f64> {
    pub stiffness_n_per_m: R,
    pub damping_n_s_per_m: R,
}

impl TranslationalSpring {
    /// Its effects (Table 3.1): the stiffness (capacitive storage) ...
    pub const STIFFNESS: Effect = Effect { domains: &[Domain::Translational], kind: Kind::StorageC, what: "stiffness" };
    /// ... and its internal damping (dissipation).
    pub const DAMPING: Effect = Effect { domains: &[Domain::Translational], kind: Kind::Dissipation, what: "internal damping" };
}

impl<R: Real> TranslationalSpring<R> {
    fn rotational_twin(&self) -> TorsionSpring<R> {
        TorsionSpring { stiffness_n_m_per_rad: self.stiffness_n_per_m, damping_n_m_s_per_rad: self.damping_n_s_per_m }
    }

    /// Transmitted force at an elongation and elongation rate, N (positive: tension).
    pub fn force_n(&self, elongation_m: R, elongation_rate_m_per_s: R) -> R {
        self.rotational_twin().torque_n_m(elongation_m, elongation_rate_m_per_s)
    }

    /// Power into the elastic part, k x dx/dt, W.
    pub fn spring_power_w(&self, elongation_m: R, elongation_rate_m_per_s: R) -> R {
        self.rotational_twin().spring_power_w(elongation_m, elongation_rate_m_per_s)
    }

    /// Power dissipated by the internal damping, d (dx/dt)^2, W (never negative).
    pub fn damper_power_w(&self, elongation_rate_m_per_s: R) -> R {
        self.rotational_twin().damper_power_w(elongation_rate_m_per_s)
    }

    /// Elastic energy k x^2 / 2, J (its rate is [`spring_power_w`](Self::spring_power_w)).
    pub fn energy_j(&self, elongation_m: R) -> R {
        self.stiffness_n_per_m * 0.5 * elongation_m * elongation_m
    }

    /// Natural frequency of this spring between two masses, sqrt(k (1/m1 + 1/m2)) / 2 pi, Hz
    /// (`m2_kg` infinite: one end fixed).
    pub fn natural_frequency_hz(&self, m1_kg: R, m2_kg: R) -> R {
        self.rotational_twin().natural_frequency_hz(m1_kg, m2_kg)
    }
}

/// A viscous damper: F = d v, v the relative velocity of its ends (a dissipation; the tire's
/// damping against the road, Figure 3.19, once referred to translation).
/// ```
/// use components::TranslationalDamper;
/// let damper = TranslationalDamper { damping_n_s_per_m: 2000.0 };
/// assert_eq!(damper.force_n(0.05), 100.0); // d v
/// assert_eq!(damper.power_w(-0.05), 5.0); // d v^2 = F v, never negative
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TranslationalDamper<R = f64> {
    pub damping_n_s_per_m: R,
}

impl TranslationalDamper {
    /// Its effect (Table 3.1): a dissipation.
    pub const DAMPING: Effect = Effect { domains: &[Domain::Translational], kind: Kind::Dissipation, what: "viscous damping" };
}

impl<R: Real> TranslationalDamper<R> {
    /// The damper as a spring-damper with no spring: its laws are that one's.
    fn spring_damper(&self) -> TranslationalSpring<R> {
        TranslationalSpring { stiffness_n_per_m: R::from(0.0), damping_n_s_per_m: self.damping_n_s_per_m }
    }

    /// Force at a relative velocity, N.
    pub fn force_n(&self, velocity_m_per_s: R) -> R {
        self.spring_damper().force_n(R::from(0.0), velocity_m_per_s)
    }

    /// Power dissipated, d v^2, W (never negative).
    pub fn power_w(&self, velocity_m_per_s: R) -> R {
        self.spring_damper().damper_power_w(velocity_m_per_s)
    }
}

/// Coulomb friction with sticking in translation (the rack in its housing, a cylinder's seals):
/// slipping, the friction force is -F_c in the direction of slip; stuck, the body stands still and
/// the friction takes whatever force holding it requires, up to F_s. The direction is a discrete
/// mode (1 forwards, 0 stuck, -1 backwards) with the API and the logic of [`CoulombFriction`],
/// which it runs on (its mode logic knows no units).
/// ```
/// use components::SlidingFriction;
/// let rack = SlidingFriction { coulomb_n: 200.0, static_n: 250.0 };
/// assert_eq!(rack.next_mode(0, 0.0, 220.0), (0, false)); // held: 220 N < F_s
/// assert_eq!(rack.next_mode(0, 0.0, 300.0), (1, false)); // breaks loose forwards
/// assert_eq!(rack.slip_force_n(1), -200.0);
/// assert_eq!(rack.power_w(1, 0.1), 20.0); // F_c |v|
/// assert_eq!(rack.next_mode(1, -1e-12, 100.0), (0, true)); // stopped, held: speed set to 0
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlidingFriction<R = f64> {
    /// F_c, N: the force while slipping.
    pub coulomb_n: R,
    /// F_s >= F_c, N: the largest force it holds while stuck.
    pub static_n: R,
}

impl SlidingFriction {
    /// Its effect (Table 3.1): a dissipation.
    pub const FRICTION: Effect = Effect { domains: &[Domain::Translational], kind: Kind::Dissipation, what: "sliding friction" };

    /// Below this velocity a body in the stuck mode stands still: 1e-9 m/s (a millimetre in 12
    /// days), the number [`CoulombFriction::STANDSTILL_RAD_PER_S`] that its mode logic uses.
    pub const STANDSTILL_M_PER_S: f64 = CoulombFriction::<f64>::STANDSTILL_RAD_PER_S;
}

impl<R: Real> SlidingFriction<R> {
    fn rotational_twin(&self) -> CoulombFriction<R> {
        CoulombFriction { coulomb_n_m: self.coulomb_n, static_n_m: self.static_n }
    }

    /// The friction force on a body slipping in `direction` (+-1; 0 when stuck), N.
    pub fn slip_force_n(&self, direction: i32) -> R {
        self.rotational_twin().slip_torque_n_m(direction)
    }

    /// The event indicator (as [`CoulombFriction::indicator`]): slipping, the velocity in the
    /// direction of slip; stuck, the margin F_s - |F_required|, `required_n` the sum of every other
    /// force on the body.
    pub fn indicator(&self, mode: i32, velocity_m_per_s: R, required_n: R) -> R {
        self.rotational_twin().indicator(mode, velocity_m_per_s, required_n)
    }

    /// The mode after an event and whether the velocity must be set to exactly 0 (as
    /// [`CoulombFriction::next_mode`]).
    pub fn next_mode(&self, mode: i32, velocity_m_per_s: R, required_n: R) -> (i32, bool) {
        self.rotational_twin().next_mode(mode, velocity_m_per_s, required_n)
    }

    /// Power dissipated while slipping, |F_c v|, W (zero while stuck).
    pub fn power_w(&self, mode: i32, velocity_m_per_s: R) -> R {
        self.rotational_twin().power_w(mode, velocity_m_per_s)
    }
}

/// A rack and pinion of pinion (pitch) radius r, an ideal rotation-to-translation transformer
/// (the steering gear, section 3.4.2, Figure 3.18): v = r w and T = r F, so T w = F v (Table 3.5:
/// two equations, no loss, no storage). A mass on the rack is seen on the pinion's shaft as an
/// inertia m r^2, an inertia on the shaft as a mass J / r^2 on the rack (eq. 3.7). Steering data
/// sheets give the rack travel per pinion turn 2 pi r (the "C-factor", some 40-60 mm).
/// ```
/// use components::RackAndPinion;
/// let gear = RackAndPinion { pinion_radius_m: 0.0075 };
/// assert!((gear.travel_per_turn_m() - 0.0471239).abs() < 1e-7); // 2 pi r = 47.1 mm per turn
/// assert!((RackAndPinion::from_travel_per_turn(0.0471239).pinion_radius_m - 0.0075).abs() < 1e-8);
/// assert!((gear.rack_velocity_m_per_s(10.0) - 0.075).abs() < 1e-15); // r w
/// assert!((gear.pinion_torque_n_m(5000.0) - 37.5).abs() < 1e-12); // r F
/// assert!((gear.rack_force_n(37.5) - 5000.0).abs() < 1e-9); // T / r
/// assert!((gear.referred_inertia_kg_m2(3.0) - 1.6875e-4).abs() < 1e-15); // m r^2
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RackAndPinion<R = f64> {
    pub pinion_radius_m: R,
}

impl RackAndPinion {
    /// Its effect (Table 3.1): a lossless transformer between rotation and translation.
    pub const TRANSFORMER: Effect =
        Effect { domains: &[Domain::Rotational, Domain::Translational], kind: Kind::Transformer, what: "rack and pinion (rotation to translation)" };
}

impl<R: Real> RackAndPinion<R> {
    /// The rack and pinion whose rack travels `travel_per_turn_m` per pinion turn: r = c / 2 pi.
    pub fn from_travel_per_turn(travel_per_turn_m: R) -> Self {
        RackAndPinion { pinion_radius_m: travel_per_turn_m / (2.0 * std::f64::consts::PI) }
    }

    /// Rack travel per pinion turn, 2 pi r, m.
    pub fn travel_per_turn_m(&self) -> R {
        self.pinion_radius_m * (2.0 * std::f64::consts::PI)
    }

    /// The same transformer as a cable drum of the pinion's radius (v = r w, T = r F).
    fn drum(&self) -> CableDrum<R> {
        CableDrum { radius_m: self.pinion_radius_m }
    }

    /// Rack velocity for a pinion speed, r w, m/s (and rack travel r theta for a pinion angle).
    pub fn rack_velocity_m_per_s(&self, pinion_speed_rad_per_s: R) -> R {
        self.drum().cable_speed_m_per_s(pinion_speed_rad_per_s)
    }

    /// Pinion speed for a rack velocity, v / r, rad/s (and pinion angle x / r for a rack travel).
    pub fn pinion_speed_rad_per_s(&self, rack_velocity_m_per_s: R) -> R {
        rack_velocity_m_per_s / self.pinion_radius_m
    }

    /// Torque on the pinion's shaft from a force on the rack, r F, N m.
    pub fn pinion_torque_n_m(&self, rack_force_n: R) -> R {
        self.drum().torque_n_m(rack_force_n)
    }

    /// Force on the rack from a torque on the pinion's shaft, T / r, N.
    pub fn rack_force_n(&self, pinion_torque_n_m: R) -> R {
        pinion_torque_n_m / self.pinion_radius_m
    }

    /// A mass moving with the rack, seen as an inertia on the pinion's shaft, m r^2, kg m2.
    pub fn referred_inertia_kg_m2(&self, rack_mass_kg: R) -> R {
        self.drum().referred_inertia_kg_m2(rack_mass_kg)
    }

    /// An inertia turning with the pinion, seen as a mass on the rack, J / r^2, kg.
    pub fn referred_mass_kg(&self, pinion_inertia_kg_m2: R) -> R {
        pinion_inertia_kg_m2 / (self.pinion_radius_m * self.pinion_radius_m)
    }
}

/// A lever arm between translation and rotation: the horn of a control surface on which the
/// actuator's rod pushes (the EHA, Figure 3.16.a). With the rod perpendicular to the arm a, the
/// hinge moment is T = a F and the surface turns at w = v / a (F = T / a, v = a w: the transformer
/// of a rack and pinion of radius a, whose laws it uses). Away from perpendicular the effective arm
/// is a cos(angle) (the nonlinear kinematics of chapter 6); take `arm_m` at the position studied.
/// ```
/// use components::Lever;
/// let horn = Lever { arm_m: 0.1 };
/// assert!((horn.hinge_moment_n_m(20_000.0) - 2000.0).abs() < 1e-9); // a F
/// assert!((horn.rod_force_n(2000.0) - 20_000.0).abs() < 1e-9); // T / a
/// assert!((horn.angular_speed_rad_per_s(0.05) - 0.5).abs() < 1e-12); // v / a
/// // A 5 kg m2 surface is a 500 kg mass on the rod: 1/2 J w^2 = 1/2 (J / a^2) v^2.
/// assert!((horn.referred_mass_kg(5.0) - 500.0).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lever<R = f64> {
    pub arm_m: R,
}

impl Lever {
    /// Its effect (Table 3.1): a lossless transformer between translation and rotation.
    pub const TRANSFORMER: Effect =
        Effect { domains: &[Domain::Translational, Domain::Rotational], kind: Kind::Transformer, what: "lever arm (translation to rotation)" };
}

impl<R: Real> Lever<R> {
    fn pinion(&self) -> RackAndPinion<R> {
        RackAndPinion { pinion_radius_m: self.arm_m }
    }

    /// Rod velocity for a surface angular speed, a w, m/s.
    pub fn rod_velocity_m_per_s(&self, angular_speed_rad_per_s: R) -> R {
        self.pinion().rack_velocity_m_per_s(angular_speed_rad_per_s)
    }

    /// Surface angular speed for a rod velocity, v / a, rad/s (and deflection x / a for a rod
    /// travel, small angles).
    pub fn angular_speed_rad_per_s(&self, rod_velocity_m_per_s: R) -> R {
        self.pinion().pinion_speed_rad_per_s(rod_velocity_m_per_s)
    }

    /// Hinge moment from the rod's force, a F, N m.
    pub fn hinge_moment_n_m(&self, rod_force_n: R) -> R {
        self.pinion().pinion_torque_n_m(rod_force_n)
    }

    /// Rod force that balances a hinge moment, T / a, N.
    pub fn rod_force_n(&self, hinge_moment_n_m: R) -> R {
        self.pinion().rack_force_n(hinge_moment_n_m)
    }

    /// The surface's inertia seen as a mass on the rod, J / a^2, kg.
    pub fn referred_mass_kg(&self, surface_inertia_kg_m2: R) -> R {
        self.pinion().referred_mass_kg(surface_inertia_kg_m2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Simpson's rule over [0, t] with n (even) intervals.
    fn simpson(f: impl Fn(f64) -> f64, t: f64, n: usize) -> f64 {
        let h = t / n as f64;
        let inner: f64 = (1..n).map(|i| f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 }).sum();
        (f(0.0) + inner + f(t)) * h / 3.0
    }

    #[test]
    fn stored_energy_is_the_integral_of_the_reported_power() {
        // A mass under a constant force: v = v0 + a t, power m a v linear in t (Simpson exact).
        let m = Mass { mass_kg: 3.0 };
        let (v0, a, t) = (-0.2, m.acceleration_m_per_s2(60.0), 0.05);
        let integral = simpson(|s| m.power_w(a, v0 + a * s), t, 2);
        assert!((integral - (m.energy_j(v0 + a * t) - m.energy_j(v0))).abs() < 1e-13, "{integral}");
        // A spring stretched along x = X sin(w t): the integral of k x x' is k x(t)^2 / 2.
        let s = TranslationalSpring { stiffness_n_per_m: 4e4, damping_n_s_per_m: 50.0 };
        let (amp, w, t) = (0.01, 30.0, 0.04);
        let integral = simpson(|u| s.spring_power_w(amp * (w * u).sin(), amp * w * (w * u).cos()), t, 2000);
        assert!((integral - s.energy_j(amp * (w * t).sin())).abs() < 1e-10, "{integral}");
        // The damper's share is what the damping force takes, F v, never negative.
        assert_eq!(s.force_n(0.0, -0.3) * -0.3, s.damper_power_w(-0.3));
        let d = TranslationalDamper { damping_n_s_per_m: 2000.0 };
        assert_eq!(d.force_n(-0.3) * -0.3, d.power_w(-0.3));
        assert!(d.power_w(-0.3) > 0.0);
    }

    #[test]
    fn a_spring_between_two_masses_oscillates_at_sqrt_k_over_the_reduced_mass() {
        let s = TranslationalSpring { stiffness_n_per_m: 4e4, damping_n_s_per_m: 0.0 };
        // m1 = m2 = 10 kg: reduced mass 5 kg, sqrt(8000) / 2 pi = 14.235 Hz.
        assert!((s.natural_frequency_hz(10.0, 10.0) - 14.2353).abs() < 1e-4);
        assert!((s.natural_frequency_hz(5.0, f64::INFINITY) - s.natural_frequency_hz(10.0, 10.0)).abs() < 1e-12);
    }

    #[test]
    fn the_transformers_conserve_power_and_kinetic_energy() {
        let gear = RackAndPinion { pinion_radius_m: 0.0075 };
        let horn = Lever { arm_m: 0.1 };
        for (w, f) in [(10.0, 5000.0), (-3.0, 800.0), (0.7, -12_000.0)] {
            // T w on the shaft = F v on the rack, and back.
            let (v, t) = (gear.rack_velocity_m_per_s(w), gear.pinion_torque_n_m(f));
            assert!((t * w - f * v).abs() < 1e-9 * (f * v).abs());
            assert!((gear.pinion_speed_rad_per_s(v) - w).abs() < 1e-12 && (gear.rack_force_n(t) - f).abs() < 1e-9);
            let (v, t) = (horn.rod_velocity_m_per_s(w), horn.hinge_moment_n_m(f));
            assert!((t * w - f * v).abs() < 1e-9 * (f * v).abs());
            assert!((horn.angular_speed_rad_per_s(v) - w).abs() < 1e-12 && (horn.rod_force_n(t) - f).abs() < 1e-9);
            // A 3 kg rack seen on the pinion, a 5 kg m2 surface seen on the rod: same energy.
            let rack = Mass { mass_kg: 3.0 };
            let on_shaft = Inertia { inertia_kg_m2: gear.referred_inertia_kg_m2(3.0) };
            assert!((rack.energy_j(gear.rack_velocity_m_per_s(w)) - on_shaft.energy_j(w)).abs() < 1e-15);
            let surface = Inertia { inertia_kg_m2: 5.0 };
            let on_rod = Mass { mass_kg: horn.referred_mass_kg(5.0) };
            assert!((surface.energy_j(w) - on_rod.energy_j(horn.rod_velocity_m_per_s(w))).abs() < 1e-9);
        }
        // One pinion turn moves the rack 2 pi r; a pinion inertia on the rack is J / r^2.
        assert!((gear.travel_per_turn_m() - gear.rack_velocity_m_per_s(2.0 * std::f64::consts::PI)).abs() < 1e-15);
        assert!((RackAndPinion::from_travel_per_turn(gear.travel_per_turn_m()).pinion_radius_m - 0.0075).abs() < 1e-15);
        assert!((gear.referred_mass_kg(gear.referred_inertia_kg_m2(3.0)) - 3.0).abs() < 1e-12);
    }

    #[test]
    fn sliding_friction_follows_the_rotational_stick_slip_logic() {
        let (f_c, f_s) = (200.0, 250.0);
        let slide = SlidingFriction { coulomb_n: f_c, static_n: f_s };
        let turn = CoulombFriction { coulomb_n_m: f_c, static_n_m: f_s };
        for mode in [-1, 0, 1] {
            for v in [-0.5, -1e-12, 0.0, 1e-12, 0.5] {
                for required in [-300.0, -250.0, -100.0, 0.0, 220.0, 250.0, 400.0] {
                    assert_eq!(slide.next_mode(mode, v, required), turn.next_mode(mode, v, required));
                    assert_eq!(slide.indicator(mode, v, required), turn.indicator(mode, v, required));
                }
                assert_eq!(slide.power_w(mode, v), (slide.slip_force_n(mode) * v).abs());
            }
        }
        // Slipping, the friction opposes the motion and dissipates F_c |v|.
        assert_eq!(slide.slip_force_n(-1), f_c);
        assert_eq!(slide.power_w(-1, -0.5), 100.0);
        assert_eq!(slide.power_w(0, 0.0), 0.0);
        assert_eq!(slide.next_mode(-1, 1e-12, -100.0), (0, true), "stopped, held");
        assert_eq!(slide.next_mode(0, 0.0, -251.0), (-1, false), "breaks loose backwards");
    }
}
