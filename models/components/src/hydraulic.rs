//! Hydraulics (chapter section 3.4.1: Table 3.2's hydraulic capacitance and resistance, Table 3.5's
//! transformers of the EHA of Figure 3.16.a): effort = pressure (Pa), flow = volume flow (m3/s),
//! so that effort times flow is a power, p Q in W.
//!
//! Transformers (lossless, two equations each, Table 3.5): the fixed-displacement pump or motor
//! between rotation and hydraulics (Q = D w, T = D dp), the double-acting cylinder between
//! hydraulics and translation (F = A dp, Q = A v). Storage: a volume of oil, compressible through
//! its bulk modulus B (a C element of capacitance V/B). Dissipation: a laminar leakage (Q = dp/R)
//! and a turbulent orifice (Q = Cd A sqrt(2 |dp| / rho)).

use fmu_runtime::real::Real;
use crate::geometry;
use fmu_runtime::elements::{Domain, Effect, Kind};
use std::f64::consts::PI;

/// A flow in litres per minute (the unit of pump and leakage data sheets) in m3/s.
/// ```
/// use components::hydraulic::flow_from_l_per_min;
/// assert!((flow_from_l_per_min(60.0) - 1e-3).abs() < 1e-18); // 60 L/min = 1 L/s
/// ```
pub fn flow_from_l_per_min<R: Real>(litres_per_minute: R) -> R {
    litres_per_minute * 1e-3 / 60.0
}

/// A fixed-displacement pump: an ideal transformer between the shaft's rotation and the oil's flow
/// (Table 3.5): it delivers Q = D w and takes the torque T = D dp from its shaft, dp the pressure
/// rise from its inlet to its outlet, D the displacement per radian. Lossless: T w = dp Q. Its
/// leaks and friction are other elements (a [`LaminarLeakage`] across its ports, a friction on its
/// shaft). Turned the other way (oil driving the shaft) the same two equations are a hydraulic
/// motor: see [`FixedDisplacementMotor`].
/// ```
/// use components::FixedDisplacementPump;
/// let pump = FixedDisplacementPump::from_cm3_per_rev(1.5); // 1.5 cm3 per revolution
/// assert!((pump.displacement_m3_per_rad - 1.5e-6 / (2.0 * std::f64::consts::PI)).abs() < 1e-20);
/// // 6000 rpm deliver 9 L/min ...
/// let w = 6000.0 * 2.0 * std::f64::consts::PI / 60.0;
/// assert!((pump.flow_m3_per_s(w) - 9e-3 / 60.0).abs() < 1e-15);
/// // ... and 20.7 MPa (3000 psi) take 4.94 N m from the shaft: T w = dp Q.
/// let t = pump.torque_n_m(20.7e6);
/// assert!((t - 4.9418).abs() < 1e-4);
/// assert!((t * w - 20.7e6 * pump.flow_m3_per_s(w)).abs() < 1e-9 * t * w);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedDisplacementPump<R = f64> {
    /// D, m3/rad (the data sheets' cm3/rev divided by 2 pi, times 1e-6).
    pub displacement_m3_per_rad: R,
}

/// A fixed-displacement hydraulic motor: the pump's two equations with the power flowing the other
/// way (T = D dp on its shaft from the pressure drop dp across it, Q = D w through it).
pub type FixedDisplacementMotor<R = f64> = FixedDisplacementPump<R>;

impl FixedDisplacementPump {
    /// Its effect as a pump (Table 3.5): a lossless transformer from rotation to hydraulics.
    pub const PUMP: Effect =
        Effect { domains: &[Domain::Rotational, Domain::Hydraulic], kind: Kind::Transformer, what: "fixed-displacement pump (Q = D w, T = D dp)" };
    /// Its effect as a hydraulic motor: the same transformer, from hydraulics to rotation.
    pub const MOTOR: Effect =
        Effect { domains: &[Domain::Hydraulic, Domain::Rotational], kind: Kind::Transformer, what: "fixed-displacement motor (T = D dp, Q = D w)" };
}

impl<R: Real> FixedDisplacementPump<R> {
    /// The machine of a displacement given in cm3 per revolution (data sheets).
    pub fn from_cm3_per_rev(displacement_cm3_per_rev: R) -> Self {
        FixedDisplacementPump { displacement_m3_per_rad: displacement_cm3_per_rev * 1e-6 / (2.0 * PI) }
    }

    /// The displacement in cm3 per revolution.
    pub fn displacement_cm3_per_rev(&self) -> R {
        self.displacement_m3_per_rad * 2.0 * PI * 1e6
    }

    /// Q = D w, m3/s.
    pub fn flow_m3_per_s(&self, speed_rad_per_s: R) -> R {
        self.displacement_m3_per_rad * speed_rad_per_s
    }

    /// T = D dp, N m: the torque the pump takes from its shaft (a motor gives it).
    pub fn torque_n_m(&self, pressure_difference_pa: R) -> R {
        self.displacement_m3_per_rad * pressure_difference_pa
    }

    /// w = Q / D, rad/s: the speed that passes a flow.
    pub fn speed_rad_per_s(&self, flow_m3_per_s: R) -> R {
        flow_m3_per_s / self.displacement_m3_per_rad
    }

    /// dp = T / D, Pa: the pressure difference that balances a shaft torque.
    pub fn pressure_difference_pa(&self, torque_n_m: R) -> R {
        torque_n_m / self.displacement_m3_per_rad
    }
}

/// A double-acting cylinder with a through rod (equal areas on both sides of the piston): an
/// ideal transformer between the oil and the rod's translation (Table 3.5), F = A dp and
/// Q = A v, dp = p_a - p_b the pressure difference across the piston, A its annular area. The
/// flow Q enters chamber a and leaves chamber b. Lossless: F v = dp Q.
/// ```
/// use components::DoubleActingCylinder;
/// // A 50 mm bore with a 28 mm through rod: A = pi/4 (50^2 - 28^2) mm2 = 13.48 cm2.
/// let jack = DoubleActingCylinder::through_rod(0.050, 0.028);
/// assert!((jack.piston_area_m2 - 13.477e-4).abs() < 1e-7);
/// assert!((jack.force_n(34.5e6) - 46_497.1).abs() < 0.1); // its stall force at 5000 psi
/// let (dp, v) = (10e6, 0.05);
/// assert!((jack.force_n(dp) * v - dp * jack.flow_m3_per_s(v)).abs() < 1e-9); // F v = dp Q
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DoubleActingCylinder<R = f64> {
    /// A, m2: the piston's area on either side.
    pub piston_area_m2: R,
}

impl DoubleActingCylinder {
    /// Its effect (Table 3.5): a lossless transformer from hydraulics to translation.
    pub const TRANSFORMER: Effect =
        Effect { domains: &[Domain::Hydraulic, Domain::Translational], kind: Kind::Transformer, what: "double-acting cylinder (F = A dp, Q = A v)" };
}

impl<R: Real> DoubleActingCylinder<R> {
    /// The cylinder of a bore and a through rod of these diameters: A = pi/4 (d_bore^2 - d_rod^2).
    pub fn through_rod(bore_m: R, rod_m: R) -> Self {
        DoubleActingCylinder { piston_area_m2: geometry::annulus_area_m2(bore_m, rod_m) }
    }

    /// F = A dp, N.
    pub fn force_n(&self, pressure_difference_pa: R) -> R {
        self.piston_area_m2 * pressure_difference_pa
    }

    /// Q = A v, m3/s: the flow the piston displaces at a speed.
    pub fn flow_m3_per_s(&self, speed_m_per_s: R) -> R {
        self.piston_area_m2 * speed_m_per_s
    }

    /// v = Q / A, m/s.
    pub fn speed_m_per_s(&self, flow_m3_per_s: R) -> R {
        flow_m3_per_s / self.piston_area_m2
    }

    /// dp = F / A, Pa: the pressure difference that holds a force.
    pub fn pressure_difference_pa(&self, force_n: R) -> R {
        force_n / self.piston_area_m2
    }

    /// The hydraulic stiffness of the piston on its two oil columns, chambers a and b held closed
    /// (no flow in or out): k = A^2 (1/C_a + 1/C_b), N/m, C = V/B each (Table 3.2). Two equal
    /// chambers of volume V (mid stroke) give 2 A^2 B / V.
    /// ```
    /// use components::{DoubleActingCylinder, FluidVolume};
    /// let jack = DoubleActingCylinder { piston_area_m2: 1e-3 };
    /// let chamber = FluidVolume { volume_m3: 1e-4, bulk_modulus_pa: 1.5e9 };
    /// let k = jack.hydraulic_stiffness_n_per_m(&chamber, &chamber);
    /// assert!((k - 2.0 * 1e-6 * 1.5e9 / 1e-4).abs() < 1e-6 * k); // 3e7 N/m
    /// ```
    pub fn hydraulic_stiffness_n_per_m(&self, chamber_a: &FluidVolume<R>, chamber_b: &FluidVolume<R>) -> R {
        let column = |c: &FluidVolume<R>| geometry::hydraulic_stiffness_n_per_m(self.piston_area_m2, c.bulk_modulus_pa, c.volume_m3);
        column(chamber_a) + column(chamber_b)
    }
}

/// A volume of oil V of bulk modulus B (Table 3.2: the hydraulic capacitance C = V/B): the C
/// element of hydraulics. The net flow into it raises its pressure, dp/dt = (B/V) Q_net; it stores
/// E = C p^2 / 2 (the elastic energy of the compressed oil, from p = 0), at the rate C p dp/dt = p Q_net.
/// ```
/// use components::FluidVolume;
/// // 80 cm3 of oil at B = 1.5 GPa: C = 5.33e-14 m3/Pa.
/// let chamber = FluidVolume { volume_m3: 80e-6, bulk_modulus_pa: 1.5e9 };
/// assert!((chamber.capacitance_m3_per_pa() - 80e-6 / 1.5e9).abs() < 1e-27);
/// // 1 L/min into it raises the pressure at 312.5 MPa/s ...
/// let q = 1e-3 / 60.0;
/// assert!((chamber.pressure_rate_pa_per_s(q) - 312.5e6).abs() < 1e-3);
/// // ... and at 20 MPa it stores 10.7 J, taking p Q = C p dp/dt.
/// assert!((chamber.energy_j(20e6) - 10.6667).abs() < 1e-4);
/// let p = 20e6;
/// assert!((chamber.power_w(p, chamber.pressure_rate_pa_per_s(q)) - p * q).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FluidVolume<R = f64> {
    pub volume_m3: R,
    pub bulk_modulus_pa: R,
}

impl FluidVolume {
    /// Its effect (Table 3.1): capacitive storage in hydraulics, the oil's compressibility.
    pub const COMPRESSIBILITY: Effect = Effect { domains: &[Domain::Hydraulic], kind: Kind::StorageC, what: "oil compressibility (C = V/B)" };
}

impl<R: Real> FluidVolume<R> {
    /// C = V / B, m3/Pa.
    pub fn capacitance_m3_per_pa(&self) -> R {
        geometry::fluid_capacitance_m3_per_pa(self.volume_m3, self.bulk_modulus_pa)
    }

    /// dp/dt = Q_net / C, Pa/s, under a net inflow.
    pub fn pressure_rate_pa_per_s(&self, net_inflow_m3_per_s: R) -> R {
        net_inflow_m3_per_s / self.capacitance_m3_per_pa()
    }

    /// Stored energy C p^2 / 2, J (from p = 0).
    pub fn energy_j(&self, pressure_pa: R) -> R {
        self.capacitance_m3_per_pa() * 0.5 * pressure_pa * pressure_pa
    }

    /// Power stored per second, C p dp/dt, W.
    pub fn power_w(&self, pressure_pa: R, pressure_rate_pa_per_s: R) -> R {
        self.capacitance_m3_per_pa() * pressure_pa * pressure_rate_pa_per_s
    }

    /// Two volumes that exchange a flow (the two chambers of a cylinder fed by a pump between them,
    /// a flow Q into one out of the other) seen from their pressure difference: d(p_a - p_b)/dt =
    /// Q (1/C_a + 1/C_b), one capacitance C_a C_b / (C_a + C_b), given as the volume of this
    /// one's bulk modulus that has it. Its energy C (p_a - p_b)^2 / 2 is the two volumes' less
    /// what their common pressure stores, which the exchange does not change.
    /// ```
    /// use components::FluidVolume;
    /// let chamber = FluidVolume { volume_m3: 80e-6, bulk_modulus_pa: 1.5e9 };
    /// let load = chamber.in_series(&chamber); // two equal chambers: half the volume
    /// assert!((load.volume_m3 - 40e-6).abs() < 1e-18);
    /// // The exchange moves p_a up and p_b down by the same amount: energy check from 5 MPa each.
    /// let (p0, dp) = (5e6, 2e6);
    /// let stored = chamber.energy_j(p0 + dp / 2.0) + chamber.energy_j(p0 - dp / 2.0) - 2.0 * chamber.energy_j(p0);
    /// assert!((stored - load.energy_j(dp)).abs() < 1e-12);
    /// ```
    pub fn in_series(&self, other: &FluidVolume<R>) -> FluidVolume<R> {
        let (ca, cb) = (self.capacitance_m3_per_pa(), other.capacitance_m3_per_pa());
        FluidVolume { volume_m3: ca * cb / (ca + cb) * self.bulk_modulus_pa, bulk_modulus_pa: self.bulk_modulus_pa }
    }
}

/// A laminar leakage (Table 3.2's hydraulic resistance; the clearance of a piston's seals, a
/// pump's internal cross-port leak): Q = dp / R, dissipating dp Q = dp^2 / R.
/// ```
/// use components::hydraulic::{flow_from_l_per_min, LaminarLeakage};
/// // 0.5 L/min at 20.7 MPa (3000 psi): R = 2.48e12 Pa s/m3.
/// let leak = LaminarLeakage::from_flow_at(flow_from_l_per_min(0.5), 20.7e6);
/// assert!((leak.resistance_pa_s_per_m3 - 2.484e12).abs() < 1e8);
/// assert!((leak.flow_m3_per_s(10.35e6) - flow_from_l_per_min(0.25)).abs() < 1e-18); // linear
/// assert!((leak.power_w(20.7e6) - 20.7e6 * flow_from_l_per_min(0.5)).abs() < 1e-9); // 172.5 W
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaminarLeakage<R = f64> {
    /// R = dp / Q, Pa s/m3.
    pub resistance_pa_s_per_m3: R,
}

impl LaminarLeakage {
    /// Its effect (Table 3.1): a hydraulic dissipation.
    pub const LEAKAGE: Effect = Effect { domains: &[Domain::Hydraulic], kind: Kind::Dissipation, what: "laminar leakage (Q = dp/R)" };
}

impl<R: Real> LaminarLeakage<R> {
    /// The leakage that passes `flow_m3_per_s` under `pressure_difference_pa` (a data sheet's point).
    pub fn from_flow_at(flow_m3_per_s: R, pressure_difference_pa: R) -> Self {
        LaminarLeakage { resistance_pa_s_per_m3: pressure_difference_pa / flow_m3_per_s }
    }

    /// Q = dp / R, m3/s, from the high to the low pressure.
    pub fn flow_m3_per_s(&self, pressure_difference_pa: R) -> R {
        pressure_difference_pa / self.resistance_pa_s_per_m3
    }

    /// Power dissipated, dp^2 / R, W (never negative).
    pub fn power_w(&self, pressure_difference_pa: R) -> R {
        pressure_difference_pa * pressure_difference_pa / self.resistance_pa_s_per_m3
    }
}

/// A sharp-edged (turbulent) orifice: Q = Cd A sqrt(2 |dp| / rho) sign(dp), the flow of Bernoulli's
/// jet through the area A with the discharge coefficient Cd; it dissipates dp Q >= 0.
/// ```
/// use components::Orifice;
/// // A 1 mm orifice, Cd = 0.61, in oil of 850 kg/m3: 20 bar pass 1.972 L/min.
/// let orifice = Orifice { discharge_coefficient: 0.61, area_m2: std::f64::consts::PI / 4.0 * 1e-6, density_kg_per_m3: 850.0 };
/// let q = orifice.flow_m3_per_s(2e6);
/// assert!((q * 60e3 - 1.97193).abs() < 1e-5);
/// assert_eq!(orifice.flow_m3_per_s(-2e6), -q); // odd in dp
/// assert!((orifice.pressure_drop_pa(q) - 2e6).abs() < 1e-6); // the inverse
/// assert!((orifice.power_w(2e6) - 2e6 * q).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orifice<R = f64> {
    pub discharge_coefficient: R,
    pub area_m2: R,
    pub density_kg_per_m3: R,
}

impl Orifice {
    /// Its effect (Table 3.1): a hydraulic dissipation, quadratic in the flow.
    pub const RESTRICTION: Effect =
        Effect { domains: &[Domain::Hydraulic], kind: Kind::Dissipation, what: "turbulent orifice (Q = Cd A sqrt(2 |dp| / rho))" };
}

impl<R: Real> Orifice<R> {
    /// Q = Cd A sqrt(2 |dp| / rho) sign(dp), m3/s.
    pub fn flow_m3_per_s(&self, pressure_difference_pa: R) -> R {
        let dp = pressure_difference_pa;
        self.discharge_coefficient * self.area_m2 * (dp.abs() * 2.0 / self.density_kg_per_m3).sqrt() * dp.signum()
    }

    /// The pressure drop that passes a flow, rho/2 (Q / (Cd A))^2 sign(Q), Pa.
    pub fn pressure_drop_pa(&self, flow_m3_per_s: R) -> R {
        let jet = flow_m3_per_s / (self.discharge_coefficient * self.area_m2);
        self.density_kg_per_m3 * 0.5 * jet * jet.abs()
    }

    /// Power dissipated, dp Q, W (never negative).
    pub fn power_w(&self, pressure_difference_pa: R) -> R {
        pressure_difference_pa * self.flow_m3_per_s(pressure_difference_pa)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transformers_conserve_power_both_ways() {
        let pump = FixedDisplacementPump::from_cm3_per_rev(2.0);
        assert!((pump.displacement_cm3_per_rev() - 2.0).abs() < 1e-12);
        let jack = DoubleActingCylinder::through_rod(0.05, 0.028);
        for (w, dp, v) in [(500.0, 20e6, 0.08), (-300.0, 5e6, -0.02), (120.0, -3e6, 0.01)] {
            // pump: mechanical power in = hydraulic power out, T w = dp Q
            let (t, q) = (pump.torque_n_m(dp), pump.flow_m3_per_s(w));
            assert!((t * w - dp * q).abs() <= 1e-12 * (t * w).abs());
            assert!((pump.speed_rad_per_s(q) - w).abs() < 1e-9 && (pump.pressure_difference_pa(t) - dp).abs() < 1e-6);
            // cylinder: hydraulic power in = mechanical power out, dp Q = F v
            let (f, q) = (jack.force_n(dp), jack.flow_m3_per_s(v));
            assert!((f * v - dp * q).abs() <= 1e-12 * (f * v).abs());
            assert!((jack.speed_m_per_s(q) - v).abs() < 1e-15 && (jack.pressure_difference_pa(f) - dp).abs() < 1e-6);
        }
        // Pump into cylinder with rigid oil: the piston moves at D w / A and the shaft feels F D / A.
        let w = 400.0;
        let v = jack.speed_m_per_s(pump.flow_m3_per_s(w));
        let f = 10e3;
        let t = pump.torque_n_m(jack.pressure_difference_pa(f));
        assert!((t * w - f * v).abs() < 1e-9 * f * v);
    }

    #[test]
    fn the_volumes_energy_is_the_integral_of_its_power() {
        // A pressure trajectory p(t) = 10 MPa (1 - cos(40 t)) + 3 MPa t driven by whatever flow makes
        // it: integrate the reported power C p dp/dt (Simpson, 2000 intervals) and compare with the
        // change of the stored energy C p^2 / 2.
        let v = FluidVolume { volume_m3: 80e-6, bulk_modulus_pa: 1.5e9 };
        let p = |t: f64| 10e6 * (1.0 - (40.0 * t).cos()) + 3e6 * t;
        let dp = |t: f64| 10e6 * 40.0 * (40.0 * t).sin() + 3e6;
        let (t1, n) = (0.37, 2000);
        let h = t1 / n as f64;
        let mut integral = 0.0;
        for j in 0..=n {
            let t = j as f64 * h;
            let weight = if j == 0 || j == n { 1.0 } else if j % 2 == 1 { 4.0 } else { 2.0 };
            // The power through the flow view: the net inflow C dp/dt times p.
            let q = v.capacitance_m3_per_pa() * dp(t);
            assert!((v.pressure_rate_pa_per_s(q) - dp(t)).abs() <= 1e-9 * dp(t).abs().max(1.0));
            integral += weight * v.power_w(p(t), dp(t));
        }
        integral *= h / 3.0;
        let stored = v.energy_j(p(t1)) - v.energy_j(p(0.0));
        assert!((integral - stored).abs() < 1e-9 * stored.abs(), "{integral} vs {stored}");
    }

    #[test]
    fn two_chambers_in_series_and_the_stiffness_they_give() {
        let a = FluidVolume { volume_m3: 60e-6, bulk_modulus_pa: 1.5e9 };
        let b = FluidVolume { volume_m3: 100e-6, bulk_modulus_pa: 1.5e9 };
        let s = a.in_series(&b);
        // 1/C = 1/C_a + 1/C_b
        let c = 1.0 / (1.0 / a.capacitance_m3_per_pa() + 1.0 / b.capacitance_m3_per_pa());
        assert!((s.capacitance_m3_per_pa() - c).abs() < 1e-12 * c);
        // A piston on the two columns: k = A^2 / C_series.
        let jack = DoubleActingCylinder { piston_area_m2: 1.35e-3 };
        let k = jack.hydraulic_stiffness_n_per_m(&a, &b);
        assert!((k - jack.piston_area_m2.powi(2) / c).abs() < 1e-9 * k);
        // A displacement x of the closed piston compresses a by A x and expands b by A x:
        // the force back is A (dp_a - dp_b) = A^2 x (B/V_a + B/V_b) = k x.
        let x = 1e-4;
        let force = jack.force_n(a.pressure_rate_pa_per_s(jack.flow_m3_per_s(x)) + b.pressure_rate_pa_per_s(jack.flow_m3_per_s(x)));
        assert!((force - k * x).abs() < 1e-9 * k * x);
    }

    #[test]
    fn dissipations_never_give_power() {
        let leak = LaminarLeakage { resistance_pa_s_per_m3: 2.5e12 };
        let orifice = Orifice { discharge_coefficient: 0.7, area_m2: 1e-6, density_kg_per_m3: 870.0 };
        for dp in [-30e6, -1.0, 0.0, 1e-3, 4e6] {
            assert!(leak.power_w(dp) >= 0.0 && orifice.power_w(dp) >= 0.0, "{dp}");
            assert!((leak.power_w(dp) - dp * leak.flow_m3_per_s(dp)).abs() <= 1e-12 * leak.power_w(dp).max(1e-300));
            let q = orifice.flow_m3_per_s(dp);
            assert!((orifice.pressure_drop_pa(q) - dp).abs() <= 1e-9 * dp.abs().max(1.0));
        }
        assert_eq!(orifice.flow_m3_per_s(0.0), 0.0);
        // Quadrupling the pressure drop doubles the orifice's flow; the leakage's quadruples.
        assert!((orifice.flow_m3_per_s(8e6) / orifice.flow_m3_per_s(2e6) - 2.0).abs() < 1e-12);
        assert!((leak.flow_m3_per_s(8e6) / leak.flow_m3_per_s(2e6) - 4.0).abs() < 1e-12);
    }
}
