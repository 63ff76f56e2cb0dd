//! The induction machine of the chapter's guideline example (section 3.1.2, Figure 3.2; levels
//! a-d of Figure 3.5), from one set of parameters:
//! * the steady-state T-equivalent circuit (per phase: R_s, L_s_sigma, then L_m in parallel with
//!   R_r/s + L_r_sigma), which gives the torque-speed curve used by levels a-c;
//! * the dq model with stator and rotor fluxes in the synchronous frame (level d), whose steady
//!   state is exactly the equivalent circuit's.

use crate::complex::Complex;
use crate::roots::{bisect, with_derivatives, with_derivatives_of};
use fmu_runtime::elements::{Domain, Effect, Kind};
use fmu_runtime::real::Real;
use std::cell::Cell;
use std::f64::consts::{PI, SQRT_2};

/// Parameters of a three-phase, star-connected induction machine.
/// ```
/// use components::InductionMachine;
/// let motor = InductionMachine {
///     stator_resistance_ohm: 0.012, rotor_resistance_ohm: 0.020, stator_leakage_h: 2.5e-4,
///     rotor_leakage_h: 2.5e-4, magnetizing_h: 0.01, pole_pairs: 2.0,
///     line_voltage_rms_v: 400.0, frequency_hz: 50.0,
/// };
/// let w_sync = motor.synchronous_speed_rad_per_s(); // 2 pi 50 / 2 = 157.08 rad/s
/// assert!((w_sync - 157.0796).abs() < 1e-4);
/// assert_eq!(motor.steady_state(w_sync).torque_n_m, 0.0); // no slip, no torque
/// let breakdown = motor.steady_state_at_slip(motor.breakdown_slip()).torque_n_m;
/// assert!(breakdown > motor.steady_state_at_slip(1.0).torque_n_m); // above the locked-rotor torque
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InductionMachine<R = f64> {
    pub stator_resistance_ohm: R,
    pub rotor_resistance_ohm: R,
    pub stator_leakage_h: R,
    pub rotor_leakage_h: R,
    pub magnetizing_h: R,
    pub pole_pairs: R,
    /// Supply voltage, line to line, rms.
    pub line_voltage_rms_v: R,
    pub frequency_hz: R,
}

/// The machine at one speed in steady state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SteadyState<R = f64> {
    pub slip: R,
    pub torque_n_m: R,
    pub stator_current_rms_a: R,
    /// Active power drawn from the supply, W.
    pub electrical_power_w: R,
}

/// Stator and rotor flux linkages in the synchronous frame (d along the stator voltage), Wb,
/// peak-value (amplitude-invariant) scaling.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Fluxes<R = f64> {
    pub stator_d: R,
    pub stator_q: R,
    pub rotor_d: R,
    pub rotor_q: R,
}

/// What the dq model gives at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DqResponse<R = f64> {
    pub flux_rates: Fluxes<R>,
    pub torque_n_m: R,
    pub stator_current_rms_a: R,
    pub electrical_power_w: R,
    /// Power the stator and rotor resistances dissipate, 3/2 (R_s |i_s|^2 + R_r |i_r|^2), W.
    pub winding_loss_w: R,
    /// Rate of the magnetic energy of the windings, 3/2 (i_s . dpsi_s/dt + i_r . dpsi_r/dt), W:
    /// the electrical power minus the losses minus the mechanical power T w.
    pub magnetic_power_w: R,
}

impl InductionMachine {
    /// Its effects (Table 3.1, the motor's row): the electromechanical transformer (lossless) ...
    pub const TRANSFORMER: Effect =
        Effect { domains: &[Domain::Electrical, Domain::Rotational], kind: Kind::Transformer, what: "electromechanical transformer" };
    /// ... the winding inductances (the magnetic energy of the stator and rotor fluxes) ...
    pub const WINDING_INDUCTANCE: Effect = Effect { domains: &[Domain::Electrical], kind: Kind::StorageI, what: "winding inductance" };
    /// ... and the winding resistances (stator and rotor).
    pub const WINDING_RESISTANCE: Effect = Effect { domains: &[Domain::Electrical], kind: Kind::Dissipation, what: "winding resistance" };
    /// The grid's voltage source that feeds it.
    pub const SUPPLY: Effect = Effect { domains: &[Domain::Electrical], kind: Kind::Source, what: "voltage source" };
}

impl<R: Real> InductionMachine<R> {
    /// Electrical angular frequency of the supply, rad/s.
    pub fn supply_angular_frequency(&self) -> R {
        self.frequency_hz * (2.0 * PI)
    }

    /// Synchronous mechanical speed, rad/s.
    pub fn synchronous_speed_rad_per_s(&self) -> R {
        self.supply_angular_frequency() / self.pole_pairs
    }

    pub fn phase_voltage_rms_v(&self) -> R {
        self.line_voltage_rms_v / 3f64.sqrt()
    }

    pub fn slip(&self, speed_rad_per_s: R) -> R {
        R::from(1.0) - speed_rad_per_s / self.synchronous_speed_rad_per_s()
    }

    /// Steady state at a mechanical speed, from the T-equivalent circuit.
    pub fn steady_state(&self, speed_rad_per_s: R) -> SteadyState<R> {
        self.steady_state_at_slip(self.slip(speed_rad_per_s))
    }

    /// Steady state at a slip: torque = air-gap power / synchronous speed, 3 |I_r|^2 R_r/s / W_s.
    ///
    /// The circuit solved with one complex division: with D = Z_m + Z_r and
    /// E = Z_s D + Z_m Z_r, I_s = V / (Z_s + Z_m Z_r / D) = V D / E and the rotor branch's share
    /// I_r = I_s Z_m / D = V Z_m / E (the same algebra as Z_s + Z_m || Z_r, three divisions
    /// fewer: this runs at every evaluation of levels a-c).
    pub fn steady_state_at_slip(&self, slip: R) -> SteadyState<R> {
        let zero = R::from(0.0);
        let w = self.supply_angular_frequency();
        let v = Complex::new(self.phase_voltage_rms_v(), zero);
        let z_s = Complex::new(self.stator_resistance_ohm, w * self.stator_leakage_h);
        let z_m = Complex::new(zero, w * self.magnetizing_h);
        if slip == 0.0 {
            let i_s = v / (z_s + z_m);
            return SteadyState { slip, torque_n_m: zero, stator_current_rms_a: i_s.abs(), electrical_power_w: (v * i_s.conj()).re * 3.0 };
        }
        let z_r = Complex::new(self.rotor_resistance_ohm / slip, w * self.rotor_leakage_h);
        let e = z_s * (z_m + z_r) + z_m * z_r;
        let v_over_e = v / e;
        let i_s = v_over_e * (z_m + z_r);
        let i_r = v_over_e * z_m;
        let air_gap_power = i_r.norm_sqr() * 3.0 * self.rotor_resistance_ohm / slip;
        SteadyState {
            slip,
            torque_n_m: air_gap_power / self.synchronous_speed_rad_per_s(),
            stator_current_rms_a: i_s.abs(),
            electrical_power_w: (v * i_s.conj()).re * 3.0,
        }
    }

    /// The slip of maximum (breakdown) torque. Seen from the rotor branch, the stator and the
    /// magnetising branch are a Thevenin source of impedance R_th + j X_th (exactly, the circuit
    /// being linear), so the air-gap power peaks where R_r/s = |R_th + j (X_th + X_r)|.
    pub fn breakdown_slip(&self) -> R {
        let w = self.supply_angular_frequency();
        let z_s = Complex::new(self.stator_resistance_ohm, w * self.stator_leakage_h);
        let z_m = Complex::new(R::from(0.0), w * self.magnetizing_h);
        let z_th = z_s.parallel(z_m);
        self.rotor_resistance_ohm / Complex::new(z_th.re, z_th.im + w * self.rotor_leakage_h).abs()
    }

    /// The stable operating speed under a load torque curve (the speed between breakdown and
    /// synchronism where motor and load torques balance), or None if the load exceeds the
    /// breakdown torque there (the motor stalls).
    ///
    /// The speed is found on values (bisection); its derivatives, where the scalar carries
    /// them, are those of the balance's implicit function ([`with_derivatives`]).
    pub fn stable_speed_rad_per_s(&self, load_torque_n_m: impl Fn(R) -> R) -> Option<R> {
        let w_sync = self.synchronous_speed_rad_per_s();
        let excess = |w: R| self.steady_state(w).torque_n_m - load_torque_n_m(w);
        let (lo, hi) = (w_sync * (R::from(1.0) - self.breakdown_slip()), w_sync);
        if excess(lo) < 0.0 {
            return None;
        }
        if excess(hi) >= 0.0 {
            return Some(hi);
        }
        let root = bisect(lo.value(), hi.value(), 80, |w| excess(R::from(w)) >= 0.0);
        Some(with_derivatives(root, (hi - lo).value(), excess))
    }

    /// The slip, on the stable branch, at which the machine gives `torque` (clamped to the
    /// breakdown torque): how a converter at rated flux (constant V/f) runs it.
    ///
    /// Found on values (bisection); its derivatives, where the scalar carries them (the torque's,
    /// the machine's), are those of the implicit function T(s) = |torque|
    /// ([`with_derivatives`]), and beyond the breakdown torque, where the slip stays at the
    /// breakdown slip, those of the breakdown slip.
    pub fn stable_slip_for_torque(&self, torque_n_m: R) -> R {
        let s_bd = self.breakdown_slip();
        let target = torque_n_m.abs();
        let clamped = Cell::new(true);
        let root = bisect(0.0, s_bd.value(), 60, |s| {
            let below = self.steady_state_at_slip(R::from(s)).torque_n_m < target;
            clamped.set(clamped.get() && below);
            below
        });
        let slip = if clamped.get() {
            with_derivatives_of(root, s_bd)
        } else {
            with_derivatives(root, s_bd.value(), |s: R| self.steady_state_at_slip(s).torque_n_m - target)
        };
        slip * torque_n_m.signum()
    }

    /// Self inductances and the determinant of the flux-current relation.
    fn inductances(&self) -> (R, R, R) {
        let l_s = self.stator_leakage_h + self.magnetizing_h;
        let l_r = self.rotor_leakage_h + self.magnetizing_h;
        (l_s, l_r, l_s * l_r - self.magnetizing_h * self.magnetizing_h)
    }

    /// The dq model at a rotor speed: flux derivatives, torque, current and power.
    /// d psi_s/dt = v_s - R_s i_s - j w_s psi_s;  d psi_r/dt = -R_r i_r - j (w_s - p w_m) psi_r;
    /// T = 3/2 p (psi_sd i_sq - psi_sq i_sd), with the stator voltage on the d axis at its peak value.
    pub fn dq_response(&self, psi: Fluxes<R>, speed_rad_per_s: R) -> DqResponse<R> {
        let (l_s, l_r, det) = self.inductances();
        let l_m = self.magnetizing_h;
        let i_sd = (l_r * psi.stator_d - l_m * psi.rotor_d) / det;
        let i_sq = (l_r * psi.stator_q - l_m * psi.rotor_q) / det;
        let i_rd = (l_s * psi.rotor_d - l_m * psi.stator_d) / det;
        let i_rq = (l_s * psi.rotor_q - l_m * psi.stator_q) / det;
        let w_s = self.supply_angular_frequency();
        let w_slip = w_s - self.pole_pairs * speed_rad_per_s;
        let v_sd = self.phase_voltage_rms_v() * SQRT_2;
        let rates = Fluxes {
            stator_d: v_sd - self.stator_resistance_ohm * i_sd + w_s * psi.stator_q,
            stator_q: -self.stator_resistance_ohm * i_sq - w_s * psi.stator_d,
            rotor_d: -self.rotor_resistance_ohm * i_rd + w_slip * psi.rotor_q,
            rotor_q: -self.rotor_resistance_ohm * i_rq - w_slip * psi.rotor_d,
        };
        DqResponse {
            flux_rates: rates,
            torque_n_m: self.pole_pairs * 1.5 * (psi.stator_d * i_sq - psi.stator_q * i_sd),
            stator_current_rms_a: i_sd.hypot(i_sq) / SQRT_2,
            electrical_power_w: v_sd * 1.5 * i_sd,
            winding_loss_w: (self.stator_resistance_ohm * (i_sd * i_sd + i_sq * i_sq) + self.rotor_resistance_ohm * (i_rd * i_rd + i_rq * i_rq)) * 1.5,
            magnetic_power_w: (i_sd * rates.stator_d + i_sq * rates.stator_q + i_rd * rates.rotor_d + i_rq * rates.rotor_q) * 1.5,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The dq model conserves energy: the supply's power is the winding losses plus the rate of
    /// the magnetic energy plus the mechanical power T w, at any fluxes and speed (the powers
    /// each from its own formula; eq. 3.3's powers of Table 3.1's motor row).
    #[test]
    fn the_dq_powers_add_up() {
        let m = machine();
        for (i, w) in [0.0, 40.0, 150.0, 157.0, 170.0].into_iter().enumerate() {
            let f = i as f64;
            let psi = Fluxes { stator_d: 0.3 + 0.1 * f, stator_q: -0.9 + 0.2 * f, rotor_d: 0.25 - 0.05 * f, rotor_q: -0.8 + 0.15 * f };
            let r = m.dq_response(psi, w);
            let residual = r.electrical_power_w - r.winding_loss_w - r.magnetic_power_w - r.torque_n_m * w;
            let scale = [r.electrical_power_w, r.winding_loss_w, r.magnetic_power_w, r.torque_n_m * w].iter().fold(0.0f64, |a, p| a.max(p.abs()));
            assert!(residual.abs() <= 1e-12 * scale, "w = {w}: residual {residual} of {scale}");
        }
    }

    /// The 160 kW, 400 V, 4-pole machine of the MotorFan model.
    pub fn machine() -> InductionMachine {
        InductionMachine {
            stator_resistance_ohm: 0.012,
            rotor_resistance_ohm: 0.010,
            stator_leakage_h: 2.5e-4,
            rotor_leakage_h: 2.5e-4,
            magnetizing_h: 0.01,
            pole_pairs: 2.0,
            line_voltage_rms_v: 400.0,
            frequency_hz: 50.0,
        }
    }

    #[test]
    fn torque_speed_curve_has_the_usual_shape() {
        let m = machine();
        assert_eq!(m.steady_state(m.synchronous_speed_rad_per_s()).torque_n_m, 0.0);
        let s_bd = m.breakdown_slip();
        let t_bd = m.steady_state_at_slip(s_bd).torque_n_m;
        assert!(t_bd > m.steady_state_at_slip(1.0).torque_n_m && t_bd > m.steady_state_at_slip(0.01).torque_n_m);
        assert!(m.steady_state_at_slip(-0.01).torque_n_m < 0.0, "a generator above synchronism");
        // The closed-form breakdown slip is the maximum of the curve (checked by sampling).
        let sampled = (1..100_000).map(|i| i as f64 * 1e-5).max_by(|a, b| {
            m.steady_state_at_slip(*a).torque_n_m.total_cmp(&m.steady_state_at_slip(*b).torque_n_m)
        });
        assert!((sampled.unwrap() - s_bd).abs() < 2e-5, "{sampled:?} vs {s_bd}");
        // Power balance: electrical power = air-gap power + stator copper losses.
        let st = m.steady_state_at_slip(0.02);
        let p_air = st.torque_n_m * m.synchronous_speed_rad_per_s();
        let p_cu_s = 3.0 * st.stator_current_rms_a.powi(2) * m.stator_resistance_ohm;
        assert!((st.electrical_power_w - p_air - p_cu_s).abs() < 1e-6 * st.electrical_power_w);
    }

    #[test]
    fn the_one_division_circuit_solution_is_the_series_parallel_one() {
        // I_s = V / (Z_s + Z_m || Z_r), I_r = I_s Z_m / (Z_m + Z_r), written out the textbook way.
        let m = machine();
        let w = m.supply_angular_frequency();
        let v = Complex::new(m.phase_voltage_rms_v(), 0.0);
        let (z_s, z_m) = (Complex::new(m.stator_resistance_ohm, w * m.stator_leakage_h), Complex::new(0.0, w * m.magnetizing_h));
        for slip in [1.0, 0.3, 0.05, 0.023, 1e-4, -0.02] {
            let z_r = Complex::new(m.rotor_resistance_ohm / slip, w * m.rotor_leakage_h);
            let i_s = v / (z_s + z_m.parallel(z_r));
            let i_r = i_s * z_m / (z_m + z_r);
            let torque = 3.0 * i_r.norm_sqr() * m.rotor_resistance_ohm / slip / m.synchronous_speed_rad_per_s();
            let st = m.steady_state_at_slip(slip);
            assert!((st.torque_n_m - torque).abs() <= 1e-12 * torque.abs(), "slip {slip}: {} vs {torque}", st.torque_n_m);
            assert!((st.stator_current_rms_a - i_s.abs()).abs() <= 1e-12 * i_s.abs());
            let p = 3.0 * (v * i_s.conj()).re;
            assert!((st.electrical_power_w - p).abs() <= 1e-12 * p.abs());
        }
    }

    #[test]
    fn stable_speed_balances_the_load() {
        let m = machine();
        let load = |w: f64| 1000.0 * (w / 155.0).powi(2);
        let w = m.stable_speed_rad_per_s(load).unwrap();
        assert!((m.steady_state(w).torque_n_m - load(w)).abs() < 1e-6);
        assert!(m.slip(w) < m.breakdown_slip());
        assert!(m.stable_speed_rad_per_s(|_| 1e6).is_none(), "overload stalls");
        let s = m.stable_slip_for_torque(1000.0);
        assert!((m.steady_state_at_slip(s).torque_n_m - 1000.0).abs() < 1e-6);
    }

    #[test]
    fn dq_model_settles_on_the_equivalent_circuit() {
        // Integrate the dq fluxes at a fixed speed (RK4, 2e-5 s, 4 s: ~4 rotor time constants
        // of the short-circuited machine) and compare with the circuit.
        let m = machine();
        let w = m.synchronous_speed_rad_per_s() * (1.0 - 0.02);
        let f = |p: Fluxes| m.dq_response(p, w).flux_rates;
        let add = |p: Fluxes, d: Fluxes, h: f64| Fluxes {
            stator_d: p.stator_d + h * d.stator_d,
            stator_q: p.stator_q + h * d.stator_q,
            rotor_d: p.rotor_d + h * d.rotor_d,
            rotor_q: p.rotor_q + h * d.rotor_q,
        };
        let (mut p, h) = (Fluxes::default(), 2e-5);
        for _ in 0..200_000 {
            let k1 = f(p);
            let k2 = f(add(p, k1, h / 2.0));
            let k3 = f(add(p, k2, h / 2.0));
            let k4 = f(add(p, k3, h));
            p = Fluxes {
                stator_d: p.stator_d + h / 6.0 * (k1.stator_d + 2.0 * k2.stator_d + 2.0 * k3.stator_d + k4.stator_d),
                stator_q: p.stator_q + h / 6.0 * (k1.stator_q + 2.0 * k2.stator_q + 2.0 * k3.stator_q + k4.stator_q),
                rotor_d: p.rotor_d + h / 6.0 * (k1.rotor_d + 2.0 * k2.rotor_d + 2.0 * k3.rotor_d + k4.rotor_d),
                rotor_q: p.rotor_q + h / 6.0 * (k1.rotor_q + 2.0 * k2.rotor_q + 2.0 * k3.rotor_q + k4.rotor_q),
            };
        }
        let dq = m.dq_response(p, w);
        let ss = m.steady_state(w);
        assert!((dq.torque_n_m - ss.torque_n_m).abs() < 1e-6 * ss.torque_n_m, "{} vs {}", dq.torque_n_m, ss.torque_n_m);
        assert!((dq.stator_current_rms_a - ss.stator_current_rms_a).abs() < 1e-6 * ss.stator_current_rms_a);
        assert!((dq.electrical_power_w - ss.electrical_power_w).abs() < 1e-6 * ss.electrical_power_w);
    }
}
