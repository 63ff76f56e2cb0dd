//! The sensor's parts assembled (Figure 3.27), with its steady-state characteristic computed from
//! the parameters by phasors and the conditioning of question 9 that inverts it.

use components::complex::Complex;
use components::{Multiplier, Reluctance, RlWinding, SecondOrderFilter, SineVoltage, ToothedAirGap, TorsionBar, Winding};

/// Every element of Figure 3.27 at the current parameter values.
#[derive(Clone, Copy, Debug)]
pub struct Sensor {
    /// Mechanical part: torque -> twist (question 6).
    pub torsion_bar: TorsionBar,
    /// Windings A and B are identical (N turns, R_winding).
    pub winding: Winding,
    /// One radial air gap between a detection ring and its yoke (Figure 3.26, a and c).
    pub ring_gap: Reluctance,
    /// The soft-iron path of yoke and ring (Figure 3.26, b and d).
    pub iron: Reluctance,
    /// Ring B's twist-dependent air gap (question 7).
    pub teeth: ToothedAirGap,
    /// Whether part A's circuit crosses a toothed gap too, whose overlap shrinks as ring B's
    /// grows (a differential sensor); false: part A is Figure 3.26 as is, the reference arm.
    pub differential: bool,
    /// The two resistors of the bridge (one above each winding), Ohm.
    pub bridge_resistance_ohm: f64,
    /// The 5 kHz bridge supply (question 8).
    pub supply: SineVoltage,
    pub multiplier: Multiplier,
    pub filter: SecondOrderFilter,
}

impl Sensor {
    /// Figure 3.26's circuit: two ring gaps and the iron, in series.
    pub fn fixed_circuit(&self) -> Reluctance {
        self.ring_gap.series(self.ring_gap).series(self.iron)
    }

    /// Magnetic circuit of part A: Figure 3.26's (differential: plus the toothed gap at the
    /// opposite twist).
    pub fn circuit_a(&self, twist_rad: f64) -> Reluctance {
        if self.differential {
            self.fixed_circuit().series(self.teeth.reluctance(-twist_rad))
        } else {
            self.fixed_circuit()
        }
    }

    /// Magnetic circuit of part B (question 7): Figure 3.26's plus the toothed gap.
    pub fn circuit_b(&self, twist_rad: f64) -> Reluctance {
        self.fixed_circuit().series(self.teeth.reluctance(twist_rad))
    }

    /// Question 4: the inductance with soft iron of infinite permeability, N^2 / (2 R_gap)
    /// = pi mu0 b N^2 / ln(r2/r1).
    pub fn question4_inductance_h(&self) -> f64 {
        self.winding.inductance_h(self.ring_gap.series(self.ring_gap))
    }

    /// Question 5's R-L model of winding A: the inductance of question 4 and R_winding.
    pub fn rl_winding(&self) -> RlWinding {
        RlWinding { inductance_h: self.question4_inductance_h(), resistance_ohm: self.winding.resistance_ohm }
    }

    /// Current phasor of a bridge arm (bridge resistor over a winding of inductance L) under the
    /// supply phasor U (the supply is U sin(wt) = Im(U e^{jwt})), A.
    fn arm_current(&self, inductance_h: f64) -> Complex {
        let w = self.supply.angular_frequency_rad_per_s();
        let z = Complex::new(self.bridge_resistance_ohm + self.winding.resistance_ohm, w * inductance_h);
        Complex::new(self.supply.amplitude_v, 0.0) / z
    }

    /// The steady-state demodulated voltage at a constant twist, V: the bridge voltage
    /// u_bridge = R_bridge (i_B - i_A) has the phasor B = R_bridge (I_B - I_A); the multiplier's
    /// product B sin(wt + arg B) sin(wt) has the mean Re(B) / 2, which the filter (unit DC gain)
    /// passes. Exact once the electrical and filter transients have died out.
    pub fn steady_demodulated_v(&self, twist_rad: f64) -> f64 {
        let l_a = self.winding.inductance_h(self.circuit_a(twist_rad));
        let l_b = self.winding.inductance_h(self.circuit_b(twist_rad));
        let bridge = (self.arm_current(l_b) - self.arm_current(l_a)) * Complex::new(self.bridge_resistance_ohm, 0.0);
        0.5 * bridge.re
    }

    /// The offset of question 9's conditioning: the steady output at zero torque, V.
    pub fn zero_torque_demodulated_v(&self) -> f64 {
        self.steady_demodulated_v(0.0)
    }

    /// Question 9's conditioning: remove the zero-torque offset, then invert the characteristic
    /// u(twist) - u(0) (monotonic between the stops) by bisection and scale by the stiffness.
    /// Outside the characteristic's range (during start-up) the result saturates at the stop
    /// torque. Returns the measured torque, N m.
    pub fn measured_torque_n_m(&self, offset_removed_v: f64) -> f64 {
        let stop = self.torsion_bar.stop_angle_rad;
        let offset = self.zero_torque_demodulated_v();
        let g = |twist: f64| self.steady_demodulated_v(twist) - offset;
        let (mut lo, mut hi) = (-stop, stop);
        let increasing = g(hi) > g(lo);
        // invariant: the twist sought lies in [lo, hi] (or at a bound, when out of range)
        while hi - lo > f64::EPSILON * stop {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if (g(mid) < offset_removed_v) == increasing {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        self.torsion_bar.stiffness_n_m_per_rad * 0.5 * (lo + hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn sensor() -> Sensor {
        Sensor {
            torsion_bar: TorsionBar { stiffness_n_m_per_rad: 360.0 / PI, stop_angle_rad: 5f64.to_radians() },
            winding: Winding { turns: 1000.0, resistance_ohm: 30.0 },
            ring_gap: Reluctance::radial_air_gap(0.015, 0.0165, 0.002),
            iron: Reluctance::uniform(0.03, 2.0 * PI * 0.015 * 0.002, 2000.0),
            teeth: ToothedAirGap {
                teeth: 8.0,
                radius_m: 0.012,
                axial_length_m: 0.005,
                gap_length_m: 3e-4,
                tooth_width_rad: PI / 8.0,
                rest_overlap_rad: PI / 16.0,
            },
            differential: false,
            bridge_resistance_ohm: 2200.0,
            supply: SineVoltage { amplitude_v: 5.0, frequency_hz: 5000.0 },
            multiplier: Multiplier { reference_amplitude: 5.0 },
            filter: SecondOrderFilter { natural_frequency_hz: 200.0, damping: 0.5f64.sqrt() },
        }
    }

    #[test]
    fn calibration_inverts_the_characteristic() {
        let s = sensor();
        let offset = s.zero_torque_demodulated_v();
        for torque in [-8.0, -3.0, -0.5, 0.0, 0.5, 3.0, 8.0] {
            let u = s.steady_demodulated_v(s.torsion_bar.twist_rad(torque)) - offset;
            let measured = s.measured_torque_n_m(u);
            assert!((measured - torque).abs() < 1e-9, "{torque} -> {measured}");
        }
        let differential = Sensor { differential: true, ..s };
        for torque in [-8.0, -0.5, 3.0] {
            let u = differential.steady_demodulated_v(differential.torsion_bar.twist_rad(torque));
            assert!((differential.measured_torque_n_m(u) - torque).abs() < 1e-9);
        }
        // out of range: saturates at a stop torque
        assert!((s.measured_torque_n_m(1e3).abs() - s.torsion_bar.stop_torque_n_m()).abs() < 1e-9);
    }

    #[test]
    fn bridge_is_balanced_when_both_circuits_are_equal() {
        // an infinitely wide toothed gap (vanishing reluctance) makes L_B = L_A: no bridge voltage
        let mut s = sensor();
        s.teeth.axial_length_m = 1e30;
        assert!(s.zero_torque_demodulated_v().abs() < 1e-15);
    }

    #[test]
    fn differential_arrangement_is_balanced_and_odd() {
        // both arms cross the toothed gap, at opposite twists: L_A(t) = L_B(-t), so u(-t) = -u(t)
        let s = Sensor { differential: true, ..sensor() };
        assert!(s.zero_torque_demodulated_v().abs() < 1e-15);
        for twist in [0.01, 0.05] {
            let (up, down) = (s.steady_demodulated_v(twist), s.steady_demodulated_v(-twist));
            assert!((up + down).abs() < 1e-12 * up.abs(), "{up} {down}");
        }
    }

    #[test]
    fn question4_inductance_ignores_the_iron() {
        let s = sensor();
        let mu0 = 4e-7 * PI;
        let closed_form = PI * mu0 * 0.002 * 1e6 / (0.0165f64 / 0.015).ln();
        assert!((s.question4_inductance_h() / closed_form - 1.0).abs() < 1e-12);
        let l_a = s.winding.inductance_h(s.circuit_a(0.0));
        assert!(l_a < s.question4_inductance_h() && l_a > 0.99 * s.question4_inductance_h());
    }
}
