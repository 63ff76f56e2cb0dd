//! The sensor's parts assembled (Figure 3.27), with its steady-state characteristic computed from
//! the parameters by phasors and the conditioning of question 9 that inverts it.

use components::complex::Complex;
use components::roots::{with_derivatives, with_derivatives_of};
use components::{Multiplier, Reluctance, RlWinding, SecondOrderFilter, SineVoltage, ToothedAirGap, TorsionBar, Winding};
use fmu_runtime::real::Real;

/// How the two windings and the bridge resistors are connected across the supply (question 8).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Topology {
    /// The book's (book file Chap3_TorqueSensor.mo, InductiveSensor1/2): windings A and B in
    /// series in one arm (A from the supply to the midpoint, B from the midpoint to ground),
    /// resistors R1 over R2 in the other; the bridge voltage is the resistors' midpoint minus
    /// the windings' midpoint.
    WindingsInOneArm,
    /// This project's first set: a resistor R_bridge above each winding, each arm across the
    /// supply; the bridge voltage is u_A - u_B = R_bridge (i_B - i_A).
    ResistorAboveEachWinding,
}

/// Every element of Figure 3.27 at the current parameter values.
#[derive(Clone, Copy, Debug)]
pub struct Sensor<R = f64> {
    /// Mechanical part: torque -> twist (question 6).
    pub torsion_bar: TorsionBar<R>,
    /// Windings A and B are identical (N turns, R_winding).
    pub winding: Winding<R>,
    /// Part A's magnetic circuit without the toothed gap (Figure 3.26: the yoke, two air gaps,
    /// the ring).
    pub fixed_a: Reluctance<R>,
    /// Part B's magnetic circuit without the toothed gap.
    pub fixed_b: Reluctance<R>,
    /// The iron flux tubes of `fixed_a` (the book's yoke shell, its two poles and ring A; the first
    /// set's iron path); the rest of `fixed_a` is its two radial air gaps, `air_gaps_a`. For the
    /// power of each part only (`magnetic_powers_w`).
    pub iron_a: Reluctance<R>,
    /// Part A's two radial air gaps.
    pub air_gaps_a: Reluctance<R>,
    /// The iron flux tubes of `fixed_b`.
    pub iron_b: Reluctance<R>,
    /// Part B's two radial air gaps.
    pub air_gaps_b: Reluctance<R>,
    /// One of part A's two air gaps (question 4 takes the iron as infinitely permeable).
    pub question4_gap: Reluctance<R>,
    /// The twist-dependent air gap (question 7).
    pub teeth: ToothedAirGap<R>,
    /// The toothed gap sees teeth_sign x twist: -1 in the book's model (its relative-angle sensor
    /// measures the output flange against the input one, so the overlap shrinks as the input
    /// shaft turns forward), +1 in the first set.
    pub teeth_sign: R,
    /// Whether part A's circuit crosses a toothed gap too, at the opposite twist (a differential
    /// sensor); false: part A is the reference arm.
    pub differential: bool,
    pub topology: Topology,
    /// R1, from the supply to the resistors' midpoint (WindingsInOneArm), Ohm.
    pub r_upper_ohm: R,
    /// R2, from the resistors' midpoint to ground (WindingsInOneArm), Ohm.
    pub r_lower_ohm: R,
    /// R_bridge, above each winding (ResistorAboveEachWinding), Ohm.
    pub r_arm_ohm: R,
    /// The 5 kHz bridge supply (question 8).
    pub supply: SineVoltage<R>,
    pub multiplier: Multiplier<R>,
    pub filter: SecondOrderFilter<R>,
    /// Static gain of the low-pass filter.
    pub filter_gain: R,
}

/// The power mmf x dflux/dt flowing into each reluctance of the two magnetic circuits, W (the
/// magnetic module's convention; for the toothed gaps, whose reluctance changes with the twist,
/// that is the rate of their energy R flux^2 / 2 less the work of the reluctance torque, which
/// the model leaves out).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MagneticPowers<R = f64> {
    pub iron_a: R,
    pub air_gaps_a: R,
    /// 0 unless the arrangement is differential.
    pub toothed_gap_a: R,
    pub iron_b: R,
    pub air_gaps_b: R,
    pub toothed_gap_b: R,
}

impl<R: Real> Sensor<R> {
    /// Each reluctance's power mmf x dflux/dt at a twist, for the fluxes through the two
    /// circuits and their rates (the sum over a circuit is N i dflux/dt, the winding's
    /// magnetic-side power).
    pub fn magnetic_powers_w(&self, twist_rad: R, flux_a_wb: R, flux_a_rate: R, flux_b_wb: R, flux_b_rate: R) -> MagneticPowers<R> {
        // No flux, no power: also through a toothed gap whose teeth no longer face each other (an
        // infinite reluctance, whose mmf R flux would be infinity x 0).
        let power = |r: Reluctance<R>, flux: R, rate: R| if flux == 0.0 { R::from(0.0) } else { r.mmf_a(flux) * rate };
        let toothed_gap_a = if self.differential { power(self.teeth.reluctance(-self.teeth_sign * twist_rad), flux_a_wb, flux_a_rate) } else { R::from(0.0) };
        MagneticPowers {
            iron_a: power(self.iron_a, flux_a_wb, flux_a_rate),
            air_gaps_a: power(self.air_gaps_a, flux_a_wb, flux_a_rate),
            toothed_gap_a,
            iron_b: power(self.iron_b, flux_b_wb, flux_b_rate),
            air_gaps_b: power(self.air_gaps_b, flux_b_wb, flux_b_rate),
            toothed_gap_b: power(self.teeth.reluctance(self.teeth_sign * twist_rad), flux_b_wb, flux_b_rate),
        }
    }

    /// Magnetic circuit of part A at a twist (differential: plus the toothed gap at the opposite
    /// twist).
    pub fn circuit_a(&self, twist_rad: R) -> Reluctance<R> {
        if self.differential {
            self.fixed_a.series(self.teeth.reluctance(-self.teeth_sign * twist_rad))
        } else {
            self.fixed_a
        }
    }

    /// Magnetic circuit of part B (question 7): its fixed part plus the toothed gap.
    pub fn circuit_b(&self, twist_rad: R) -> Reluctance<R> {
        self.fixed_b.series(self.teeth.reluctance(self.teeth_sign * twist_rad))
    }

    /// (L_A, L_B) at a twist, H.
    pub fn inductances_h(&self, twist_rad: R) -> (R, R) {
        (self.winding.inductance_h(self.circuit_a(twist_rad)), self.winding.inductance_h(self.circuit_b(twist_rad)))
    }

    /// (dL_A/dtwist, dL_B/dtwist), H/rad: L = N^2 / R, so dL/dtwist = -L^2 / N^2 dR/dtwist.
    pub fn inductance_rates_h_per_rad(&self, twist_rad: R) -> (R, R) {
        let (l_a, l_b) = self.inductances_h(twist_rad);
        let n2 = self.winding.turns * self.winding.turns;
        let s = self.teeth_sign;
        let dr_b = s * self.teeth.reluctance_rate_per_h_per_rad(s * twist_rad);
        let dr_a = if self.differential { -s * self.teeth.reluctance_rate_per_h_per_rad(-s * twist_rad) } else { R::from(0.0) };
        (-l_a * l_a / n2 * dr_a, -l_b * l_b / n2 * dr_b)
    }

    /// Question 4: the inductance of part A with soft iron of infinite permeability, N^2 / (2 R_gap)
    /// = pi mu0 b N^2 / ln(r2/r1).
    pub fn question4_inductance_h(&self) -> R {
        self.winding.inductance_h(self.question4_gap.series(self.question4_gap))
    }

    /// Question 5's R-L model of winding A: the inductance of question 4 and R_winding.
    pub fn rl_winding(&self) -> RlWinding<R> {
        RlWinding { inductance_h: self.question4_inductance_h(), resistance_ohm: self.winding.resistance_ohm }
    }

    /// The bridge voltage's phasor at a constant twist (the supply U sin(wt) = Im(U e^{jwt}) is the
    /// phase reference), V.
    pub fn bridge_phasor_v(&self, twist_rad: R) -> Complex<R> {
        let w = self.supply.angular_frequency_rad_per_s();
        let (l_a, l_b) = self.inductances_h(twist_rad);
        let r = self.winding.resistance_ohm;
        let (z_a, z_b) = (Complex::new(r, w * l_a), Complex::new(r, w * l_b));
        let u = Complex::new(self.supply.amplitude_v, R::from(0.0));
        match self.topology {
            Topology::WindingsInOneArm => {
                // resistors' midpoint U R2 / (R1 + R2) minus the windings' midpoint U Z_B / (Z_A + Z_B)
                let divider = self.r_lower_ohm / (self.r_upper_ohm + self.r_lower_ohm);
                u * Complex::new(divider, R::from(0.0)) - u * z_b / (z_a + z_b)
            }
            Topology::ResistorAboveEachWinding => {
                let rb = Complex::new(self.r_arm_ohm, R::from(0.0));
                (u / (rb + z_b) - u / (rb + z_a)) * rb
            }
        }
    }

    /// The steady-state demodulated voltage at a constant twist, V: the multiplier's product
    /// |B| sin(wt + arg B) U sin(wt) / U_ref has the mean U Re(B) / (2 U_ref), which the filter
    /// passes with its static gain. Exact once the electrical and filter transients have died out.
    pub fn steady_demodulated_v(&self, twist_rad: R) -> R {
        let b = self.bridge_phasor_v(twist_rad);
        self.filter_gain * self.supply.amplitude_v * b.re / (self.multiplier.reference_amplitude * 2.0)
    }

    /// The offset of question 9's conditioning: the steady output at zero torque, V.
    pub fn zero_torque_demodulated_v(&self) -> R {
        self.steady_demodulated_v(R::from(0.0))
    }

    /// Question 9's conditioning: remove the zero-torque offset, then invert the characteristic
    /// u(twist) - u(0) (monotonic between the stops) by bisection and scale by the stiffness.
    /// Outside the characteristic's range (during start-up) the result saturates at the stop
    /// torque. Returns the measured torque, N m.
    ///
    /// The bisection runs on values; the result carries the derivatives of the implicit
    /// function u(twist) - u(0) = offset_removed_v (`roots::with_derivatives`), or those of the
    /// stop where it saturates there.
    pub fn measured_torque_n_m(&self, offset_removed_v: R) -> R {
        let stop = self.torsion_bar.stop_angle_rad.value();
        let offset = self.zero_torque_demodulated_v();
        let g = |twist: f64| (self.steady_demodulated_v(R::from(twist)) - offset).value();
        let target = offset_removed_v.value();
        let (mut lo, mut hi) = (-stop, stop);
        let increasing = g(hi) > g(lo);
        // invariant: the twist sought lies in [lo, hi] (or at a bound, when out of range)
        while hi - lo > f64::EPSILON * stop {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if (g(mid) < target) == increasing {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        // lo + hi (twice the twist), with its derivatives: those of +/- twice the stop where the
        // bisection stayed at a bound (out of range), else the characteristic's implicit ones
        let sum = lo + hi;
        let sum = if hi == stop {
            with_derivatives_of(sum, self.torsion_bar.stop_angle_rad * 2.0)
        } else if lo == -stop {
            with_derivatives_of(sum, -self.torsion_bar.stop_angle_rad * 2.0)
        } else {
            with_derivatives(sum, stop, |sum: R| self.steady_demodulated_v(sum * 0.5) - offset - offset_removed_v)
        };
        self.torsion_bar.stiffness_n_m_per_rad * 0.5 * sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use components::ToothFaces;
    use std::f64::consts::PI;

    /// The first set (ring geometry, a resistor above each winding).
    fn first_set() -> Sensor {
        let gap = Reluctance::radial_air_gap(0.015, 0.0165, 0.002);
        let fixed = gap.series(gap).series(Reluctance::uniform(0.03, 2.0 * PI * 0.015 * 0.002, 2000.0));
        Sensor {
            torsion_bar: TorsionBar { stiffness_n_m_per_rad: 360.0 / PI, stop_angle_rad: 5f64.to_radians() },
            winding: Winding { turns: 1000.0, resistance_ohm: 30.0 },
            fixed_a: fixed,
            fixed_b: fixed,
            iron_a: Reluctance::uniform(0.03, 2.0 * PI * 0.015 * 0.002, 2000.0),
            air_gaps_a: gap.series(gap),
            iron_b: Reluctance::uniform(0.03, 2.0 * PI * 0.015 * 0.002, 2000.0),
            air_gaps_b: gap.series(gap),
            question4_gap: gap,
            teeth: ToothedAirGap {
                teeth: 8.0,
                faces: ToothFaces::Radial { radius_m: 0.012, axial_length_m: 0.005 },
                gap_length_m: 3e-4,
                tooth_width_rad: PI / 8.0,
                rest_overlap_rad: PI / 16.0,
            },
            teeth_sign: 1.0,
            differential: false,
            topology: Topology::ResistorAboveEachWinding,
            r_upper_ohm: 10e3,
            r_lower_ohm: 10e3,
            r_arm_ohm: 2200.0,
            supply: SineVoltage { amplitude_v: 5.0, frequency_hz: 5000.0 },
            multiplier: Multiplier { reference_amplitude: 5.0 },
            filter: SecondOrderFilter { natural_frequency_hz: 200.0, damping: 0.5f64.sqrt() },
            filter_gain: 1.0,
        }
    }

    #[test]
    fn calibration_inverts_the_characteristic() {
        for s in [first_set(), Sensor { topology: Topology::WindingsInOneArm, ..first_set() }] {
            let offset = s.zero_torque_demodulated_v();
            for torque in [-8.0, -3.0, -0.5, 0.0, 0.5, 3.0, 8.0] {
                let u = s.steady_demodulated_v(s.torsion_bar.twist_rad(torque)) - offset;
                let measured = s.measured_torque_n_m(u);
                assert!((measured - torque).abs() < 1e-9, "{torque} -> {measured}");
            }
            // out of range: saturates at a stop torque
            assert!((s.measured_torque_n_m(1e3).abs() - s.torsion_bar.stop_torque_n_m()).abs() < 1e-9);
        }
        let differential = Sensor { differential: true, ..first_set() };
        for torque in [-8.0, -0.5, 3.0] {
            let u = differential.steady_demodulated_v(differential.torsion_bar.twist_rad(torque));
            assert!((differential.measured_torque_n_m(u) - torque).abs() < 1e-9);
        }
    }

    #[test]
    fn bridge_is_balanced_when_both_circuits_are_equal() {
        // an infinitely wide toothed gap (vanishing reluctance) makes L_B = L_A: no bridge voltage,
        // in either topology (with R1 = R2 in the book's)
        for topology in [Topology::ResistorAboveEachWinding, Topology::WindingsInOneArm] {
            let mut s = Sensor { topology, ..first_set() };
            s.teeth.faces = ToothFaces::Radial { radius_m: 0.012, axial_length_m: 1e30 };
            assert!(s.zero_torque_demodulated_v().abs() < 1e-15, "{topology:?}");
        }
    }

    #[test]
    fn differential_arrangement_is_balanced_and_odd() {
        // both arms cross the toothed gap, at opposite twists: L_A(t) = L_B(-t), so u(-t) = -u(t)
        for topology in [Topology::ResistorAboveEachWinding, Topology::WindingsInOneArm] {
            let s = Sensor { differential: true, topology, ..first_set() };
            assert!(s.zero_torque_demodulated_v().abs() < 1e-15);
            for twist in [0.01, 0.05] {
                let (up, down) = (s.steady_demodulated_v(twist), s.steady_demodulated_v(-twist));
                assert!((up + down).abs() < 1e-12 * up.abs(), "{up} {down}");
            }
        }
    }

    #[test]
    fn inductance_rates_are_the_derivatives() {
        for (differential, sign) in [(false, 1.0), (true, 1.0), (false, -1.0), (true, -1.0)] {
            let s = Sensor { differential, teeth_sign: sign, ..first_set() };
            let (h, t) = (1e-7, 0.03);
            let (a1, b1) = s.inductances_h(t + h);
            let (a0, b0) = s.inductances_h(t - h);
            let (da, db) = s.inductance_rates_h_per_rad(t);
            assert!((db - (b1 - b0) / (2.0 * h)).abs() < 1e-6 * db.abs());
            if differential {
                assert!((da - (a1 - a0) / (2.0 * h)).abs() < 1e-6 * da.abs());
            } else {
                assert_eq!(da, 0.0);
            }
        }
    }

    #[test]
    fn question4_inductance_ignores_the_iron() {
        let s = first_set();
        let mu0 = 4e-7 * PI;
        let closed_form = PI * mu0 * 0.002 * 1e6 / (0.0165f64 / 0.015).ln();
        assert!((s.question4_inductance_h() / closed_form - 1.0).abs() < 1e-12);
        let l_a = s.winding.inductance_h(s.circuit_a(0.0));
        assert!(l_a < s.question4_inductance_h() && l_a > 0.99 * s.question4_inductance_h());
    }
}
