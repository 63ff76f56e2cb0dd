//! Fuel injection hydraulics (chapter section 3.4.3, Figure 3.20, Table 3.7: the common-rail direct
//! injection system): the fuel's bulk modulus rising with pressure (the rail's C of Table 3.2, V / B,
//! with B a function of p), the engine-driven radial-piston pump with its check valves, the
//! spring-loaded poppet of a pressure-control (relief) valve, and the injector's needle and nozzle.
//! Effort = pressure (Pa), flow = volume flow (m3/s), as in [`crate::hydraulic`].

use fmu_runtime::real::Real;
use crate::hydraulic::{FluidVolume, Orifice};
use fmu_runtime::elements::{Domain, Effect, Kind};
use std::f64::consts::PI;

/// Density of diesel fuel, kg/m3: EN 590 allows 820-845 kg/m3 at 15 degrees C; 830 kg/m3 is the
/// middle of the summer grades. (Compressed to 150 MPa it is some 7 % denser; the orifice laws here
/// take the one value, see [`Orifice`].)
pub const DIESEL_DENSITY_KG_PER_M3: f64 = 830.0;

/// A bulk modulus that rises linearly with pressure, B(p) = B0 + K' p (the tangent of a Tait
/// law; for diesel fuel B0 ~ 1.5 GPa and K' ~ 7 over 0-180 MPa). A volume V of such a fluid is the
/// C element of Table 3.2 with a capacitance V / B(p) that falls as the pressure rises: it stores
/// E(p) = integral of p V / B(p) dp, at the rate p Q_net.
/// ```
/// use components::injection::LinearBulkModulus;
/// let fuel = LinearBulkModulus { at_zero_pa: 1.5e9, slope: 7.5 };
/// assert_eq!(fuel.bulk_modulus_pa(150e6), 1.5e9 + 7.5 * 150e6); // 2.625 GPa
/// // A 20 cm3 rail at 150 MPa: C = V / B = 7.62e-15 m3/Pa, and 1 cm3/s raises it 131 MPa/s.
/// let rail = fuel.volume(20e-6, 150e6);
/// assert!((rail.capacitance_m3_per_pa() - 20e-6 / 2.625e9).abs() < 1e-27);
/// assert!((rail.pressure_rate_pa_per_s(1e-6) - 131.25e6).abs() < 1e-3);
/// // The stored energy's slope is p C(p): dE/dp = p V / B(p).
/// let (p, h) = (150e6, 1e3);
/// let slope = (fuel.energy_j(20e-6, p + h) - fuel.energy_j(20e-6, p - h)) / (2.0 * h);
/// assert!((slope - p * rail.capacitance_m3_per_pa()).abs() < 1e-9 * slope);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearBulkModulus<R = f64> {
    /// B0, Pa: the bulk modulus at p = 0 (gauge).
    pub at_zero_pa: R,
    /// K' = dB/dp, dimensionless.
    pub slope: R,
}

impl<R: Real> LinearBulkModulus<R> {
    /// B(p) = B0 + K' p, Pa.
    pub fn bulk_modulus_pa(&self, pressure_pa: R) -> R {
        self.at_zero_pa + self.slope * pressure_pa
    }

    /// The volume `volume_m3` of this fluid seen at `pressure_pa`: a [`FluidVolume`] of the
    /// tangent bulk modulus there (its capacitance V / B(p), its pressure rate Q_net / C, its
    /// power C p dp/dt = p Q_net).
    pub fn volume(&self, volume_m3: R, pressure_pa: R) -> FluidVolume<R> {
        FluidVolume { volume_m3, bulk_modulus_pa: self.bulk_modulus_pa(pressure_pa) }
    }

    /// Energy stored from p = 0 in `volume_m3`, J: integral of p V / (B0 + K' p) dp =
    /// V / K' (p - B0 / K' ln(1 + K' p / B0)); V p^2 / (2 B0) when K' = 0.
    pub fn energy_j(&self, volume_m3: R, pressure_pa: R) -> R {
        let (b0, k, p) = (self.at_zero_pa, self.slope, pressure_pa);
        let u = k * p / b0;
        if u.abs() < 1e-4 {
            // The series of u - ln(1 + u), to keep the digits a difference would lose.
            volume_m3 * p * p / b0 * (R::from(0.5) - u / 3.0 + u * u / 4.0 - u * u * u / 5.0)
        } else {
            volume_m3 / k * (p - b0 / k * u.ln_1p())
        }
    }
}

/// A radial-piston pump (the common rail's high-pressure pump, Bosch CP1/CP3, Denso HP4): `plungers`
/// plungers spaced evenly round an eccentric of eccentricity e on the pump's shaft, each at the
/// shaft angle phi_k = phi - 2 pi k / n. Plunger k sits at x_k = e (1 - cos phi_k) and moves at
/// e w sin phi_k; with ideal check valves it delivers A e w sin phi_k to the outlet while it rises
/// (sin phi_k > 0) and fills from the inlet while it falls. Its transformer (Table 3.5's pump with a
/// pulsating ratio): Q_out = A e w sum over the delivering plungers of sin phi_k, and the torque on
/// the shaft T = A e sum_k p_k sin phi_k (p_k the outlet pressure on a delivering plunger, the
/// inlet pressure on a filling one), so T w = p_out Q_out - p_in Q_in. Displacement 2 e A n per
/// revolution.
/// ```
/// use components::injection::RadialPistonPump;
/// use std::f64::consts::PI;
/// // Three 6.5 mm plungers on a 3.5 mm eccentric: 0.697 cm3 per revolution.
/// let pump = RadialPistonPump::three_plungers(6.5e-3, 3.5e-3);
/// assert!((pump.displacement_m3_per_rev() - 0.6968e-6).abs() < 1e-10);
/// let w = 1333.3 * 2.0 * PI / 60.0;
/// // At 90 degrees plunger 0 rises at full speed e w, plunger 1 (at -30 degrees) fills, plunger 2
/// // (at 210 degrees... -150) fills too.
/// let delivering = [0, 1, 2].map(|k| pump.delivers(k, PI / 2.0));
/// assert_eq!(delivering, [true, false, false]);
/// let q = pump.delivery_flow_m3_per_s(PI / 2.0, w, &delivering);
/// assert!((q - pump.plunger_area_m2 * 3.5e-3 * w).abs() < 1e-15);
/// // Power: T w = p_out Q_out - p_in Q_in.
/// let (p_out, p_in) = (150e6, 0.3e6);
/// let t = pump.torque_n_m(PI / 2.0, &delivering, p_out, p_in);
/// let q_in = pump.filling_flow_m3_per_s(PI / 2.0, w, &delivering);
/// assert!((t * w - (p_out * q - p_in * q_in)).abs() < 1e-9 * t * w);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadialPistonPump<R = f64> {
    pub plunger_area_m2: R,
    pub eccentricity_m: R,
    pub plungers: usize,
}

impl RadialPistonPump {
    /// Its effect (Table 3.5's pump, the ratio pulsating with the shaft angle): a lossless
    /// transformer from rotation to hydraulics.
    pub const PUMP: Effect = Effect {
        domains: &[Domain::Rotational, Domain::Hydraulic],
        kind: Kind::Transformer,
        what: "radial-piston pump (Q = A e w sin phi on each rising plunger, T = A e p sin phi)",
    };
}

impl<R: Real> RadialPistonPump<R> {
    /// The CP1/CP3 layout: three plungers 120 degrees apart, of `plunger_diameter_m`, on an
    /// eccentric of `eccentricity_m` (stroke 2 e).
    pub fn three_plungers(plunger_diameter_m: R, eccentricity_m: R) -> Self {
        RadialPistonPump { plunger_area_m2: crate::geometry::circle_area_m2(plunger_diameter_m), eccentricity_m, plungers: 3 }
    }

    /// Volume displaced per shaft revolution, 2 e A n, m3.
    pub fn displacement_m3_per_rev(&self) -> R {
        self.eccentricity_m * 2.0 * self.plunger_area_m2 * self.plungers as f64
    }

    /// The mean delivery at a shaft speed, 2 e A n w / 2 pi, m3/s.
    pub fn mean_flow_m3_per_s(&self, speed_rad_per_s: R) -> R {
        self.displacement_m3_per_rev() * speed_rad_per_s / (2.0 * PI)
    }

    /// Plunger k's angle on the eccentric, phi - 2 pi k / n, rad.
    pub fn plunger_angle_rad(&self, plunger: usize, shaft_angle_rad: R) -> R {
        shaft_angle_rad - 2.0 * PI * plunger as f64 / self.plungers as f64
    }

    /// Plunger k's velocity outwards (towards the outlet), e w sin phi_k, m/s.
    pub fn plunger_velocity_m_per_s(&self, plunger: usize, shaft_angle_rad: R, speed_rad_per_s: R) -> R {
        self.eccentricity_m * speed_rad_per_s * self.plunger_angle_rad(plunger, shaft_angle_rad).sin()
    }

    /// Whether plunger k delivers at this angle (its outlet check valve open): it rises (sin phi_k
    /// positive), or stands at its bottom dead centre about to rise (sin phi_k = 0, cos phi_k > 0),
    /// for a shaft turning forwards. The check valve's state after an event.
    pub fn delivers(&self, plunger: usize, shaft_angle_rad: R) -> bool {
        let phi = self.plunger_angle_rad(plunger, shaft_angle_rad);
        let s = phi.sin();
        s > 0.0 || (s == 0.0 && phi.cos() > 0.0)
    }

    /// The event indicator of plunger k's check valves: sin phi_k while it delivers, -sin phi_k
    /// while it fills; positive while the state holds, zero at its dead centres.
    pub fn check_valve_indicator(&self, plunger: usize, delivering: bool, shaft_angle_rad: R) -> R {
        let s = self.plunger_angle_rad(plunger, shaft_angle_rad).sin();
        if delivering {
            s
        } else {
            -s
        }
    }

    /// Flow to the outlet, A e w sum over the delivering plungers of sin phi_k, m3/s.
    pub fn delivery_flow_m3_per_s(&self, shaft_angle_rad: R, speed_rad_per_s: R, delivering: &[bool]) -> R {
        (0..self.plungers).filter(|k| delivering[*k]).map(|k| self.plunger_area_m2 * self.plunger_velocity_m_per_s(k, shaft_angle_rad, speed_rad_per_s)).sum()
    }

    /// Flow drawn from the inlet, A e w sum over the filling plungers of -sin phi_k, m3/s.
    pub fn filling_flow_m3_per_s(&self, shaft_angle_rad: R, speed_rad_per_s: R, delivering: &[bool]) -> R {
        (0..self.plungers).filter(|k| !delivering[*k]).map(|k| -self.plunger_area_m2 * self.plunger_velocity_m_per_s(k, shaft_angle_rad, speed_rad_per_s)).sum()
    }

    /// Torque the plungers take from the shaft, A e sum_k p_k sin phi_k, N m (p_k the outlet
    /// pressure on a delivering plunger, the inlet pressure on a filling one).
    pub fn torque_n_m(&self, shaft_angle_rad: R, delivering: &[bool], outlet_pa: R, inlet_pa: R) -> R {
        (0..self.plungers)
            .map(|k| {
                let p = if delivering[k] { outlet_pa } else { inlet_pa };
                self.plunger_area_m2 * self.eccentricity_m * p * self.plunger_angle_rad(k, shaft_angle_rad).sin()
            })
            .sum()
    }
}

/// The poppet (or ball) of a spring-loaded pressure-relief or pressure-control valve on a seat of
/// diameter d: the pressure difference dp across it pushes it open with F = A dp, A = pi d^2 / 4 (a
/// transformer, Table 3.5's cylinder: lifting at v it displaces Q = A v), and lifted by x it opens
/// the curtain area pi d x to a sharp-edged orifice, Q = Cd pi d x sqrt(2 dp / rho). Seated it holds
/// until A dp exceeds the force that closes it (spring preload and any actuator force): the valve's
/// opening pressure is that force over A. The seat is a contact, as a stuck friction: a discrete
/// mode (seated 0, open 1) with its event indicator and update ([`PoppetValve::next_mode`]).
/// ```
/// use components::injection::PoppetValve;
/// let valve = PoppetValve { seat_diameter_m: 0.6e-3, discharge_coefficient: 0.7, density_kg_per_m3: 830.0 };
/// // 0.283 mm2 of seat: 41.0 N hold 145 MPa.
/// assert!((valve.seat_area_m2() - 0.28274e-6).abs() < 1e-10);
/// assert!((valve.opening_pressure_pa(41.0) - 145.0e6).abs() < 0.1e6);
/// // Lifted 17 um under 149 MPa it passes 13.4 cm3/s.
/// let q = valve.flow_m3_per_s(149e6, 17e-6);
/// assert!((q - 13.44e-6).abs() < 0.01e-6, "{q}");
/// // Seated and held: the margin is the indicator; pushed open, the mode switches.
/// assert_eq!(valve.next_mode(0, 0.0, 0.0, -1.0), (0, false));
/// assert_eq!(valve.next_mode(0, 0.0, 0.0, 2.0), (1, false));
/// // Open, back on the seat while the force closes it: seated, lift and speed set to 0.
/// assert_eq!(valve.next_mode(1, -1e-12, -0.3, -1.0), (0, true));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoppetValve<R = f64> {
    pub seat_diameter_m: R,
    pub discharge_coefficient: R,
    pub density_kg_per_m3: R,
}

impl PoppetValve {
    /// Its seat (Table 3.5's transformer between hydraulics and translation): F = A dp, Q = A v.
    pub const SEAT: Effect = Effect {
        domains: &[Domain::Hydraulic, Domain::Translational],
        kind: Kind::Transformer,
        what: "poppet on its seat (F = A dp, Q = A v)",
    };
    /// Its opening (Table 3.1's hydraulic dissipation): the curtain orifice.
    pub const ORIFICE: Effect = Effect {
        domains: &[Domain::Hydraulic],
        kind: Kind::Dissipation,
        what: "valve orifice (Q = Cd pi d x sqrt(2 dp / rho))",
    };
    /// Seated.
    pub const SEATED: i32 = 0;
    /// Lifted off its seat.
    pub const OPEN: i32 = 1;
}

impl<R: Real> PoppetValve<R> {
    /// A = pi d^2 / 4, m2: the area the pressure pushes on, seated or lifted.
    pub fn seat_area_m2(&self) -> R {
        crate::geometry::circle_area_m2(self.seat_diameter_m)
    }

    /// The pressure difference that balances a closing force, F / A, Pa.
    pub fn opening_pressure_pa(&self, closing_force_n: R) -> R {
        closing_force_n / self.seat_area_m2()
    }

    /// The opening force of a pressure difference, A dp, N.
    pub fn force_n(&self, pressure_difference_pa: R) -> R {
        self.seat_area_m2() * pressure_difference_pa
    }

    /// The flow the moving poppet displaces, A v, m3/s.
    pub fn displaced_flow_m3_per_s(&self, velocity_m_per_s: R) -> R {
        self.seat_area_m2() * velocity_m_per_s
    }

    /// The orifice at a lift: the curtain area pi d x (0 when seated), Cd, rho.
    pub fn orifice(&self, lift_m: R) -> Orifice<R> {
        Orifice { discharge_coefficient: self.discharge_coefficient, area_m2: self.seat_diameter_m * PI * lift_m.max(R::from(0.0)), density_kg_per_m3: self.density_kg_per_m3 }
    }

    /// Flow through the opening at a lift, m3/s (0 seated).
    pub fn flow_m3_per_s(&self, pressure_difference_pa: R, lift_m: R) -> R {
        self.orifice(lift_m).flow_m3_per_s(pressure_difference_pa)
    }

    /// The event indicator of the seat: open, the lift (it closes where the lift reaches 0);
    /// seated, the margin by which the closing force exceeds the opening one (-net opening force).
    pub fn seat_indicator(&self, mode: i32, lift_m: R, net_opening_force_n: R) -> R {
        if mode == PoppetValve::<f64>::OPEN {
            lift_m
        } else {
            -net_opening_force_n
        }
    }

    /// The mode after an event and whether the lift and speed must be set to exactly 0 (the poppet
    /// lands on its seat: an inelastic impact). Seated, it lifts when the net opening force (A dp
    /// less every closing force) is no longer negative (and a poppet found off its seat, a start
    /// value, is open); open, it lands when its lift reaches 0, and stays open from the seat when
    /// the net force does not close it. `velocity_m_per_s` is not needed to decide,
    /// but a landing poppet is one moving towards its seat or standing on it.
    pub fn next_mode(&self, mode: i32, lift_m: R, velocity_m_per_s: R, net_opening_force_n: R) -> (i32, bool) {
        let _ = velocity_m_per_s;
        // The seated mode holds while its indicator, -net, is > 0: at an event (the indicator <= 0,
        // possibly exactly 0) it lifts, and a landing with the net force >= 0 stays open, so that the
        // two rules agree where the net force is exactly 0.
        const OPEN: i32 = PoppetValve::<f64>::OPEN;
        const SEATED: i32 = PoppetValve::<f64>::SEATED;
        if mode == OPEN {
            if lift_m > 0.0 {
                (OPEN, false)
            } else if net_opening_force_n >= 0.0 {
                (OPEN, true)
            } else {
                (SEATED, true)
            }
        } else if net_opening_force_n >= 0.0 || lift_m > 0.0 {
            // Pushed off its seat, or found off it (a start value): open.
            (OPEN, false)
        } else {
            (SEATED, false)
        }
    }
}

/// An injector's nozzle: the needle's seat throttle (the conical gap pi d_seat h sin(alpha) at
/// needle lift h) in series with the spray holes (n holes of diameter d), both sharp-edged orifices
/// of one discharge coefficient. Two orifices in series pass Q = Cd A_eff sqrt(2 dp / rho) with
/// 1 / A_eff^2 = 1 / A_seat^2 + 1 / A_holes^2 (the sac between them takes the pressure that makes
/// both flows equal): the seat throttles at small lift, the holes at full lift.
/// ```
/// use components::injection::InjectorNozzle;
/// // 7 holes of 0.13 mm, Cd 0.75, a 1.5 mm seat of 60 degree cone: 39.7 mm3/ms at 140 MPa, full lift.
/// let nozzle = InjectorNozzle { hole_count: 7.0, hole_diameter_m: 0.13e-3, seat_diameter_m: 1.5e-3,
///     seat_half_angle_rad: 30f64.to_radians(), discharge_coefficient: 0.75, density_kg_per_m3: 830.0 };
/// assert!((nozzle.hole_area_m2() - 9.291e-8).abs() < 1e-11);
/// let q = nozzle.flow_m3_per_s(140e6, 0.2e-3);
/// assert!((q - 39.71e-6).abs() < 0.01e-6, "{q}");
/// assert_eq!(nozzle.flow_m3_per_s(140e6, 0.0), 0.0); // seated
/// // The pressure drop splits between seat and holes and adds up to dp.
/// let (seat, holes) = nozzle.pressure_drops_pa(140e6, 0.05e-3);
/// assert!((seat + holes - 140e6).abs() < 1e-6);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InjectorNozzle<R = f64> {
    /// Number of spray holes (a real number: the law only needs their total area).
    pub hole_count: R,
    pub hole_diameter_m: R,
    /// Diameter of the needle's seat line on the nozzle cone.
    pub seat_diameter_m: R,
    /// Half angle of the seat cone (the gap normal to the cone is h sin(alpha)).
    pub seat_half_angle_rad: R,
    pub discharge_coefficient: R,
    pub density_kg_per_m3: R,
}

impl InjectorNozzle {
    /// The needle's seat (Table 3.1's hydraulic dissipation).
    pub const SEAT: Effect = Effect { domains: &[Domain::Hydraulic], kind: Kind::Dissipation, what: "needle seat throttle (A = pi d_seat h sin alpha)" };
    /// The spray holes (Table 3.1's hydraulic dissipation).
    pub const HOLES: Effect = Effect { domains: &[Domain::Hydraulic], kind: Kind::Dissipation, what: "nozzle holes (Q = Cd A sqrt(2 dp / rho))" };
}

impl<R: Real> InjectorNozzle<R> {
    /// Total area of the holes, n pi d^2 / 4, m2.
    pub fn hole_area_m2(&self) -> R {
        self.hole_count * crate::geometry::circle_area_m2(self.hole_diameter_m)
    }

    /// The seat's gap area at needle lift h, pi d_seat h sin(alpha), m2 (0 when seated).
    pub fn seat_area_m2(&self, lift_m: R) -> R {
        self.seat_diameter_m * PI * lift_m.max(R::from(0.0)) * self.seat_half_angle_rad.sin()
    }

    /// A_eff = A_seat A_holes / sqrt(A_seat^2 + A_holes^2), m2.
    pub fn effective_area_m2(&self, lift_m: R) -> R {
        let (s, h) = (self.seat_area_m2(lift_m), self.hole_area_m2());
        if s <= 0.0 {
            R::from(0.0)
        } else {
            s * h / s.hypot(h)
        }
    }

    /// Flow through the nozzle from the rail side to the cylinder, Cd A_eff sqrt(2 |dp| / rho) sign(dp), m3/s.
    pub fn flow_m3_per_s(&self, pressure_difference_pa: R, lift_m: R) -> R {
        Orifice { discharge_coefficient: self.discharge_coefficient, area_m2: self.effective_area_m2(lift_m), density_kg_per_m3: self.density_kg_per_m3 }
            .flow_m3_per_s(pressure_difference_pa)
    }

    /// The pressure drops across the seat and across the holes, Pa: dp (A_eff / A_seat)^2 and
    /// dp (A_eff / A_holes)^2 (they add up to dp); (0, 0) seated (no flow, the holes see none of it).
    pub fn pressure_drops_pa(&self, pressure_difference_pa: R, lift_m: R) -> (R, R) {
        let (s, h) = (self.seat_area_m2(lift_m), self.hole_area_m2());
        if s <= 0.0 {
            return (R::from(0.0), R::from(0.0));
        }
        let sum = s * s + h * h;
        (pressure_difference_pa * h * h / sum, pressure_difference_pa * s * s / sum)
    }
}

/// The needle lift of a servo-hydraulic injector (solenoid or piezo) over one shot, the actuator
/// and the control chamber reduced to their timing: the needle leaves its seat `opening_delay_s`
/// after the start of energizing, rises at `opening_speed_m_per_s` (the control chamber's outlet
/// throttle sets it) to its stop at `max_lift_m`, starts closing `closing_delay_s` after the end of
/// energizing (after an energizing time T_ET) and lands at `closing_speed_m_per_s`. A short
/// energizing closes it before it reaches its stop (ballistic); one shorter than the delays
/// difference does not lift it at all. A trapezoid of four kinks, each an instant a solver must stop at.
/// ```
/// use components::injection::NeedleLift;
/// let needle = NeedleLift { opening_delay_s: 0.3e-3, closing_delay_s: 0.3e-3, opening_speed_m_per_s: 1.0,
///     closing_speed_m_per_s: 1.2, max_lift_m: 0.2e-3 };
/// let et = 0.5e-3;
/// assert_eq!(needle.lift_m(0.2e-3, et), 0.0); // still in the delay
/// assert!((needle.lift_m(0.4e-3, et) - 0.1e-3).abs() < 1e-15); // rising at 1 m/s
/// assert!((needle.lift_m(0.7e-3, et) - 0.2e-3).abs() < 1e-15); // at the stop
/// let expected = [0.3e-3, 0.5e-3, 0.8e-3, 0.8e-3 + 0.2e-3 / 1.2]; // lift-off, stop, closing, seated
/// assert!(needle.kinks_s(et).iter().zip(expected).all(|(k, e)| (k - e).abs() < 1e-15));
/// assert_eq!(needle.lift_m(needle.end_s(et), et), 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NeedleLift<R = f64> {
    pub opening_delay_s: R,
    pub closing_delay_s: R,
    pub opening_speed_m_per_s: R,
    pub closing_speed_m_per_s: R,
    pub max_lift_m: R,
}

impl<R: Real> NeedleLift<R> {
    /// When the needle starts closing after the start of energizing, T_ET + closing delay, s.
    fn closing_start_s(&self, energizing_time_s: R) -> R {
        energizing_time_s + self.closing_delay_s
    }

    /// The lift it has reached when it starts closing, m.
    fn lift_at_closing_m(&self, energizing_time_s: R) -> R {
        (self.opening_speed_m_per_s * (self.closing_start_s(energizing_time_s) - self.opening_delay_s)).clamp(R::from(0.0), self.max_lift_m)
    }

    /// The lift `since_start_s` after the start of energizing, m (0 before and after the shot).
    pub fn lift_m(&self, since_start_s: R, energizing_time_s: R) -> R {
        let rising = self.opening_speed_m_per_s * (since_start_s - self.opening_delay_s);
        let closing = self.lift_at_closing_m(energizing_time_s) - self.closing_speed_m_per_s * (since_start_s - self.closing_start_s(energizing_time_s));
        rising.min(self.max_lift_m).min(closing).max(R::from(0.0))
    }

    /// The four kinks of the trapezoid after the start of energizing, s, in order: lift-off, the
    /// stop reached (lift-off again when it is never reached), closing starts (lift-off when it never
    /// lifts), the needle on its seat (the end of the shot).
    pub fn kinks_s(&self, energizing_time_s: R) -> [R; 4] {
        let lift_off = self.opening_delay_s;
        let closing = self.closing_start_s(energizing_time_s);
        let top = self.lift_at_closing_m(energizing_time_s);
        if top <= 0.0 {
            return [lift_off; 4];
        }
        let stop = (lift_off + self.max_lift_m / self.opening_speed_m_per_s).min(closing);
        [lift_off, stop, closing, closing + top / self.closing_speed_m_per_s]
    }

    /// When the shot is over (the needle back on its seat), after the start of energizing, s.
    pub fn end_s(&self, energizing_time_s: R) -> R {
        self.kinks_s(energizing_time_s)[3]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rails_energy_is_the_integral_of_its_power() {
        // p(t) from 100 to 160 MPa and back: integrate p C(p) dp/dt (Simpson) against E(p1) - E(p0).
        let fuel = LinearBulkModulus { at_zero_pa: 1.5e9, slope: 7.5 };
        let v = 20e-6;
        let p = |t: f64| 130e6 + 30e6 * (3.0 * t).sin() + 5e6 * t;
        let dp = |t: f64| 90e6 * (3.0 * t).cos() + 5e6;
        let (t1, n) = (1.7, 4000);
        let h = t1 / n as f64;
        let mut integral = 0.0;
        for j in 0..=n {
            let t = j as f64 * h;
            let weight = if j == 0 || j == n { 1.0 } else if j % 2 == 1 { 4.0 } else { 2.0 };
            integral += weight * fuel.volume(v, p(t)).power_w(p(t), dp(t));
        }
        integral *= h / 3.0;
        let stored = fuel.energy_j(v, p(t1)) - fuel.energy_j(v, p(0.0));
        assert!((integral - stored).abs() < 1e-9 * stored.abs().max(1.0), "{integral} vs {stored}");
        // Near p = 0 the series branch joins the closed form.
        let (a, b) = (fuel.energy_j(v, 19.9e3), fuel.energy_j(v, 20.1e3));
        let mid = fuel.energy_j(v, 20.0e3);
        assert!(a < mid && mid < b);
        let incompressible = LinearBulkModulus { at_zero_pa: 1.5e9, slope: 0.0 };
        assert!((incompressible.energy_j(v, 1e8) - v * 1e16 / 3e9).abs() < 1e-12);
    }

    #[test]
    fn the_pumps_mean_flow_is_its_displacement_and_its_power_balances() {
        let pump = RadialPistonPump::three_plungers(6.5e-3, 3.5e-3);
        let w = 140.0;
        let n = 3600;
        let (mut q_out, mut q_in) = (0.0, 0.0);
        for j in 0..n {
            let phi = 2.0 * PI * (j as f64 + 0.5) / n as f64;
            let delivering = [0, 1, 2].map(|k| pump.delivers(k, phi));
            let (qo, qi) = (pump.delivery_flow_m3_per_s(phi, w, &delivering), pump.filling_flow_m3_per_s(phi, w, &delivering));
            assert!(qo >= 0.0 && qi >= 0.0);
            let t = pump.torque_n_m(phi, &delivering, 1.4e8, 3e5);
            assert!((t * w - (1.4e8 * qo - 3e5 * qi)).abs() <= 1e-9 * (1.4e8 * qo).max(1.0));
            q_out += qo / n as f64;
            q_in += qi / n as f64;
        }
        assert!((q_out - pump.mean_flow_m3_per_s(w)).abs() < 1e-6 * q_out, "{q_out}");
        assert!((q_in - q_out).abs() < 1e-6 * q_out);
        // The check valve's indicator is positive while its state holds.
        for phi in [0.3, 2.0, 3.5, 5.0] {
            for k in 0..3 {
                let d = pump.delivers(k, phi);
                assert!(pump.check_valve_indicator(k, d, phi) > 0.0);
                assert!(pump.check_valve_indicator(k, !d, phi) < 0.0);
            }
        }
        // At a bottom dead centre the plunger is about to rise: it delivers.
        // (f64 PI is a little short of pi: there the plunger still rises.)
        assert!(pump.delivers(0, 0.0) && pump.delivers(0, PI) && !pump.delivers(0, PI + 1e-12));
    }

    #[test]
    fn two_orifices_in_series_make_the_nozzle() {
        let nozzle = InjectorNozzle { hole_count: 7.0, hole_diameter_m: 0.13e-3, seat_diameter_m: 1.5e-3, seat_half_angle_rad: 0.5, discharge_coefficient: 0.75, density_kg_per_m3: 830.0 };
        for lift in [1e-6, 2e-5, 5e-5, 2e-4] {
            let dp = 1.3e8;
            let q = nozzle.flow_m3_per_s(dp, lift);
            // The same flow through the seat alone under its share, and through the holes under theirs.
            let (seat, holes) = nozzle.pressure_drops_pa(dp, lift);
            let rho = 830.0;
            let q_seat = 0.75 * nozzle.seat_area_m2(lift) * (2.0 * seat / rho).sqrt();
            let q_holes = 0.75 * nozzle.hole_area_m2() * (2.0 * holes / rho).sqrt();
            assert!((q_seat - q).abs() < 1e-12 * q && (q_holes - q).abs() < 1e-12 * q, "{lift}");
            // Power: dp Q splits into the two drops.
            assert!(((seat + holes) * q - dp * q).abs() < 1e-9 * dp * q);
        }
        assert!(nozzle.effective_area_m2(1.0) < nozzle.hole_area_m2());
    }

    #[test]
    fn the_needles_trapezoid_is_continuous_and_ends_on_its_seat() {
        let needle = NeedleLift { opening_delay_s: 0.3e-3, closing_delay_s: 0.25e-3, opening_speed_m_per_s: 1.0, closing_speed_m_per_s: 1.5, max_lift_m: 0.2e-3 };
        for et in [0.0, 0.04e-3, 0.1e-3, 0.2e-3, 0.5e-3, 1.5e-3] {
            let k = needle.kinks_s(et);
            assert!(k.windows(2).all(|w| w[0] <= w[1]), "{et}: {k:?}");
            assert_eq!(needle.lift_m(k[3] + 1e-9, et), 0.0);
            // Continuous: no jump anywhere on a fine grid.
            let mut last = 0.0;
            for j in 0..=3000 {
                let h = needle.lift_m(j as f64 * 1e-6, et);
                assert!((h - last).abs() <= 1.5e-6 + 1e-15 && (0.0..=0.2e-3).contains(&h), "{et} {j}");
                last = h;
            }
        }
        // A short pulse that ends before the delays' difference never lifts it.
        assert_eq!(needle.kinks_s(0.0), [0.3e-3; 4]);
        assert_eq!((0..1000).map(|j| needle.lift_m(j as f64 * 1e-6, 0.0)).fold(0.0, f64::max), 0.0);
    }

    #[test]
    fn the_poppet_lands_and_lifts_by_the_net_force() {
        let valve = PoppetValve { seat_diameter_m: 1e-3, discharge_coefficient: 0.7, density_kg_per_m3: 830.0 };
        assert_eq!(valve.next_mode(PoppetValve::OPEN, 1e-6, -0.1, -5.0), (PoppetValve::OPEN, false));
        assert_eq!(valve.next_mode(PoppetValve::OPEN, 0.0, 0.0, 5.0), (PoppetValve::OPEN, true));
        // Exactly balanced at the seat: open either way (no flip-flop between the two rules).
        assert_eq!(valve.next_mode(PoppetValve::SEATED, 0.0, 0.0, 0.0), (PoppetValve::OPEN, false));
        assert_eq!(valve.next_mode(PoppetValve::OPEN, 0.0, 0.0, 0.0), (PoppetValve::OPEN, true));
        assert_eq!(valve.seat_indicator(PoppetValve::SEATED, 0.0, -3.0), 3.0);
        // Found off its seat (a start value at the spring's balance, net force 0): open.
        assert_eq!(valve.next_mode(PoppetValve::SEATED, 1e-5, 0.0, 0.0), (PoppetValve::OPEN, false));
        assert_eq!(valve.flow_m3_per_s(1e8, -1e-6), 0.0);
        let f = valve.force_n(100e6);
        assert!((valve.opening_pressure_pa(f) - 100e6).abs() < 1e-6);
        assert!((valve.displaced_flow_m3_per_s(0.01) - valve.seat_area_m2() * 0.01).abs() < 1e-20);
    }
}
