//! Electrical storage and dissipation elements (chapter section 3.2, Table 3.2): a resistor
//! dissipates, an inductor stores magnetic energy (current is its state), a capacitor stores
//! electric energy (voltage is its state).

use fmu_runtime::real::Real;
use fmu_runtime::elements::{Domain, Effect, Kind};

/// A linear resistor: u = R i (dissipation).
/// ```
/// use components::Resistor;
/// let r = Resistor { resistance_ohm: 10.0 };
/// assert_eq!(r.voltage_v(2.0), 20.0); // u = R i
/// assert_eq!(r.current_a(5.0), 0.5);
/// assert_eq!(r.power_w(2.0), 40.0); // R i^2, dissipated
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resistor<R = f64> {
    pub resistance_ohm: R,
}

impl Resistor {
    /// Its effect (Table 3.1): an electrical dissipation.
    pub const RESISTANCE: Effect = Effect { domains: &[Domain::Electrical], kind: Kind::Dissipation, what: "resistance" };
}

impl<R: Real> Resistor<R> {
    /// Voltage drop across the resistor, V.
    pub fn voltage_v(&self, current_a: R) -> R {
        self.resistance_ohm * current_a
    }

    /// Current through the resistor under a voltage, A.
    pub fn current_a(&self, voltage_v: R) -> R {
        voltage_v / self.resistance_ohm
    }

    /// Power dissipated, W (never negative).
    pub fn power_w(&self, current_a: R) -> R {
        self.resistance_ohm * current_a * current_a
    }
}

/// A linear inductor: u = L di/dt (magnetic energy storage).
/// ```
/// use components::Inductor;
/// // Figure 3.3's line: 10 mH under 1 V rises its current at 100 A/s.
/// let l = Inductor { inductance_h: 0.01 };
/// assert!((l.current_rate_a_per_s(1.0) - 100.0).abs() < 1e-12);
/// assert!((l.energy_j(2.0) - 0.02).abs() < 1e-15); // L i^2 / 2
/// assert!((l.reactance_ohm(2.0 * std::f64::consts::PI * 50.0) - 3.14159).abs() < 1e-5);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inductor<R = f64> {
    pub inductance_h: R,
}

impl Inductor {
    /// Its effect (Table 3.1): inductive storage, the current its state.
    pub const INDUCTANCE: Effect = Effect { domains: &[Domain::Electrical], kind: Kind::StorageI, what: "inductance" };
}

impl<R: Real> Inductor<R> {
    /// di/dt under a voltage across the inductor, A/s.
    pub fn current_rate_a_per_s(&self, voltage_v: R) -> R {
        voltage_v / self.inductance_h
    }

    /// Stored energy L i^2 / 2, J.
    /// Power stored per second, L i di/dt, W.
    pub fn power_w(&self, current_a: R, current_rate_a_per_s: R) -> R {
        self.inductance_h * current_a * current_rate_a_per_s
    }

    pub fn energy_j(&self, current_a: R) -> R {
        self.inductance_h * 0.5 * current_a * current_a
    }

    /// Impedance magnitude at an angular frequency, Ohm.
    pub fn reactance_ohm(&self, angular_frequency_rad_per_s: R) -> R {
        self.inductance_h * angular_frequency_rad_per_s
    }
}

/// A linear capacitor: i = C du/dt (electric energy storage).
/// ```
/// use components::Capacitor;
/// let c = Capacitor { capacitance_f: 1e-4 };
/// assert!((c.voltage_rate_v_per_s(0.5) - 5000.0).abs() < 1e-9); // du/dt = i / C
/// assert!((c.energy_j(10.0) - 5e-3).abs() < 1e-15); // C u^2 / 2
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Capacitor<R = f64> {
    pub capacitance_f: R,
}

impl Capacitor {
    /// Its effect (Table 3.1): capacitive storage, the voltage its state.
    pub const CAPACITANCE: Effect = Effect { domains: &[Domain::Electrical], kind: Kind::StorageC, what: "capacitance" };
}

impl<R: Real> Capacitor<R> {
    /// du/dt under a current into the capacitor, V/s.
    pub fn voltage_rate_v_per_s(&self, current_a: R) -> R {
        current_a / self.capacitance_f
    }

    /// Stored energy C u^2 / 2, J.
    /// Power stored per second, C u du/dt, W.
    pub fn power_w(&self, voltage_v: R, voltage_rate_v_per_s: R) -> R {
        self.capacitance_f * voltage_v * voltage_rate_v_per_s
    }

    pub fn energy_j(&self, voltage_v: R) -> R {
        self.capacitance_f * 0.5 * voltage_v * voltage_v
    }

    /// Impedance magnitude at an angular frequency, Ohm.
    pub fn reactance_ohm(&self, angular_frequency_rad_per_s: R) -> R {
        R::from(1.0) / (self.capacitance_f * angular_frequency_rad_per_s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resistor_is_ohms_law_and_dissipates() {
        let r = Resistor { resistance_ohm: 4.0 };
        assert_eq!(r.voltage_v(2.0), 8.0);
        assert_eq!(r.current_a(8.0), 2.0);
        assert_eq!(r.power_w(-2.0), 16.0);
    }

    #[test]
    fn storage_power_is_the_rate_of_its_energy() {
        // d/dt (L i^2/2) = L i di/dt = i u: the power u i flows into the inductor.
        let l = Inductor { inductance_h: 0.01 };
        let (i, u) = (3.0, 5.0);
        let di = l.current_rate_a_per_s(u);
        assert!((l.inductance_h * i * di - u * i).abs() < 1e-12);
        let c = Capacitor { capacitance_f: 1e-4 };
        let du = c.voltage_rate_v_per_s(i);
        assert!((c.capacitance_f * u * du - u * i).abs() < 1e-12);
        assert_eq!(l.energy_j(2.0), 0.02);
        assert!((c.energy_j(10.0) - 5e-3).abs() < 1e-15);
    }

    #[test]
    fn reactances_cross_at_resonance() {
        let (l, c) = (Inductor { inductance_h: 0.01 }, Capacitor { capacitance_f: 1e-4 });
        let w0 = 1.0 / (l.inductance_h * c.capacitance_f).sqrt();
        assert!((l.reactance_ohm(w0) - c.reactance_ohm(w0)).abs() < 1e-9);
    }
}
