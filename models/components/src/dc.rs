//! The DC machine of chapter eq. 3.9 (section 3.4.1.2, "transformer effects"), with the armature's
//! resistance and inductance around it: the model of the submarine's propulsion motor (3.5.3).
//!
//! Eq. 3.9, the ideal machine: C = k_C I (torque from current) and E = k_E w (back EMF from speed).
//! The two ratios are one: an ideal machine neither stores nor dissipates energy, so the electrical
//! power it takes equals the mechanical power it gives at every instant, E I = C w; substituting,
//! k_E w I = k_C I w for every w and I, hence k_E = k_C = k (in V s/rad = N m/A).
//!
//! Armature circuit (a separately excited machine at constant field): U = R I + L dI/dt + k w.

use fmu_runtime::real::Real;
use fmu_runtime::elements::{Domain, Effect, Kind};

/// A separately excited DC machine at constant field: armature resistance R, inductance L and
/// machine constant k (eq. 3.9).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DcMachine<R = f64> {
    pub resistance_ohm: R,
    pub inductance_h: R,
    /// k = E / w = C / I, V s/rad (= N m/A).
    pub constant_v_s_per_rad: R,
}

impl DcMachine {
    /// Its effects (Table 3.1): the electromechanical transformer of eq. 3.9 (lossless) ...
    pub const TRANSFORMER: Effect =
        Effect { domains: &[Domain::Electrical, Domain::Rotational], kind: Kind::Transformer, what: "electromechanical transformer (eq. 3.9)" };
    /// ... the armature's resistance ...
    pub const RESISTANCE: Effect = Effect { domains: &[Domain::Electrical], kind: Kind::Dissipation, what: "armature resistance" };
    /// ... and its inductance.
    pub const INDUCTANCE: Effect = Effect { domains: &[Domain::Electrical], kind: Kind::StorageI, what: "armature inductance" };
}

impl<R: Real> DcMachine<R> {
    /// The machine constant that makes the machine deliver `rated_torque` at `rated_speed` from
    /// `rated_voltage` in steady state: U = R I + k w and T = k I give k^2 w - U k + R T = 0, whose
    /// larger root is the machine (the smaller one would draw almost the short-circuit current
    /// U / R). None when no real root exists (U^2 < 4 w R T: the rating is impossible).
    pub fn constant_from_rated_point(rated_voltage_v: R, rated_torque_n_m: R, rated_speed_rad_per_s: R, resistance_ohm: R) -> Option<R> {
        let (u, t, w, r) = (rated_voltage_v, rated_torque_n_m, rated_speed_rad_per_s, resistance_ohm);
        let discriminant = u * u - w * 4.0 * r * t;
        (discriminant >= 0.0 && w > 0.0).then(|| (u + discriminant.sqrt()) / (w * 2.0))
    }

    /// Back EMF E = k w, V.
    pub fn back_emf_v(&self, speed_rad_per_s: R) -> R {
        self.constant_v_s_per_rad * speed_rad_per_s
    }

    /// Electromagnetic torque C = k I, N m.
    pub fn torque_n_m(&self, current_a: R) -> R {
        self.constant_v_s_per_rad * current_a
    }

    /// dI/dt = (U - R I - k w) / L, A/s.
    pub fn current_rate_a_per_s(&self, voltage_v: R, current_a: R, speed_rad_per_s: R) -> R {
        (voltage_v - self.resistance_ohm * current_a - self.back_emf_v(speed_rad_per_s)) / self.inductance_h
    }

    /// The armature current with the inductance neglected (steady state at this speed), A.
    pub fn resistive_current_a(&self, voltage_v: R, speed_rad_per_s: R) -> R {
        (voltage_v - self.back_emf_v(speed_rad_per_s)) / self.resistance_ohm
    }

    /// Power dissipated in the armature resistance, W.
    pub fn resistance_power_w(&self, current_a: R) -> R {
        self.resistance_ohm * current_a * current_a
    }

    /// Power into the armature inductance's magnetic energy, L dI/dt I, W.
    pub fn inductance_power_w(&self, current_rate_a_per_s: R, current_a: R) -> R {
        self.inductance_h * current_rate_a_per_s * current_a
    }
}

/// A chopper (DC-DC converter) as an ideal transformer of section 3.4.1.2 (the elevator drive of
/// Figure 3.16.b): averaged over its switching period, it sets the load voltage to a fraction of
/// the supply, U_out = alpha U_in, and draws I_in = alpha I_out, so that U_in I_in = U_out I_out
/// (no loss, no storage). The duty cycle alpha is in [-1, 1] for a four-quadrant chopper.
/// ```
/// use components::dc::Chopper;
/// let chopper = Chopper { supply_voltage_v: 400.0 };
/// assert_eq!(chopper.output_voltage_v(0.6), 240.0);
/// assert_eq!(chopper.supply_current_a(0.6, 50.0), 30.0);
/// // Power in = power out (two equations of an ideal transformer, Table 3.5).
/// assert_eq!(400.0 * chopper.supply_current_a(0.6, 50.0), chopper.output_voltage_v(0.6) * 50.0);
/// assert_eq!(chopper.supply_power_w(0.6, 50.0), 12000.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chopper<R = f64> {
    pub supply_voltage_v: R,
}

impl Chopper {
    /// Its effects (Table 3.5, the elevator of Figure 3.16.b): the DC bus it draws from, a
    /// source ...
    pub const SUPPLY: Effect = Effect { domains: &[Domain::Electrical], kind: Kind::Source, what: "DC bus (supply)" };
    /// ... and the chopper itself, an ideal transformer of ratio alpha (U_out = alpha U_in,
    /// I_in = alpha I_out).
    pub const TRANSFORMER: Effect = Effect { domains: &[Domain::Electrical], kind: Kind::Transformer, what: "chopper (ideal transformer of ratio alpha)" };
}

impl<R: Real> Chopper<R> {
    /// Mean output voltage alpha U_in, V.
    pub fn output_voltage_v(&self, duty_cycle: R) -> R {
        duty_cycle * self.supply_voltage_v
    }

    /// Mean current drawn from the supply, alpha I_out, A.
    pub fn supply_current_a(&self, duty_cycle: R, output_current_a: R) -> R {
        duty_cycle * output_current_a
    }

    /// Power the DC bus delivers, U_in alpha I_out (= U_out I_out: the chopper is lossless), W.
    pub fn supply_power_w(&self, duty_cycle: R, output_current_a: R) -> R {
        self.supply_voltage_v * self.supply_current_a(duty_cycle, output_current_a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rated_point_comes_back_and_power_balances() {
        // Table 3.8: 1.75e5 N m at 120 rpm from 700 V, R = 8 mOhm.
        let w = 120.0 * 2.0 * std::f64::consts::PI / 60.0;
        let k = DcMachine::constant_from_rated_point(700.0, 1.75e5, w, 0.008).unwrap();
        let m = DcMachine { resistance_ohm: 0.008, inductance_h: 0.02, constant_v_s_per_rad: k };
        let i = 1.75e5 / k;
        assert!((m.resistive_current_a(700.0, w) - i).abs() < 1e-9 * i, "steady current at the rated point");
        assert!(m.current_rate_a_per_s(700.0, i, w).abs() < 1e-9);
        // E I = C w (eq. 3.9 with one k), and U I = E I + R I^2.
        assert!((m.back_emf_v(w) * i - m.torque_n_m(i) * w).abs() < 1e-9 * m.torque_n_m(i) * w);
        assert!((700.0 * i - m.back_emf_v(w) * i - m.resistance_power_w(i)).abs() < 1e-6 * 700.0 * i);
        assert!((k - 53.6267508696889).abs() < 1e-9, "{k}");
        assert!(DcMachine::constant_from_rated_point(100.0, 1.75e5, w, 0.008).is_none());
    }
}
