//! Sources: the effort a model imposes from outside.

use fmu_runtime::real::Real;
use fmu_runtime::elements::{Domain, Effect, Kind};
use std::f64::consts::PI;

/// u(t) = amplitude sin(2 pi f t), the excitation of chapter Figure 3.3.
/// ```
/// use components::SineVoltage;
/// let u = SineVoltage { amplitude_v: 10.0, frequency_hz: 50.0 };
/// assert!((u.voltage_v(0.005) - 10.0).abs() < 1e-12); // a quarter period
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SineVoltage<R = f64> {
    pub amplitude_v: R,
    pub frequency_hz: R,
}

impl SineVoltage {
    /// Its effect (Table 3.1): an electrical source.
    pub const SOURCE: Effect = Effect { domains: &[Domain::Electrical], kind: Kind::Source, what: "voltage source" };
}

impl<R: Real> SineVoltage<R> {
    pub fn angular_frequency_rad_per_s(&self) -> R {
        self.frequency_hz * (2.0 * PI)
    }

    /// Voltage at time t, V.
    pub fn voltage_v(&self, time_s: R) -> R {
        self.amplitude_v * (self.angular_frequency_rad_per_s() * time_s).sin()
    }
}

/// The weight of a mass in standard gravity: a constant force m g pointing down, a source in
/// translation (the elevator's cabin against its counterweight, Figure 3.16.b: the difference of
/// their masses hangs on the drum). It delivers power while the mass goes down and takes it while
/// the mass is lifted (its potential energy, counted here as the source's negative power).
/// ```
/// use components::Weight;
/// let unbalance = Weight { mass_kg: 200.0 }; // a 1200 kg cabin against a 1000 kg counterweight
/// assert!((unbalance.force_n() - 1961.33).abs() < 1e-9); // m g, g = 9.80665 m/s2
/// assert!((unbalance.power_w(0.5) + 980.665).abs() < 1e-9); // lifting at 0.5 m/s takes m g v
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Weight<R = f64> {
    pub mass_kg: R,
}

impl Weight {
    /// Standard gravity g_n (the conventional value, ISO 80000-3), m/s2.
    pub const STANDARD_GRAVITY_M_PER_S2: f64 = 9.80665;
    /// Its effect (Table 3.1): a source in translation (gravity).
    pub const GRAVITY: Effect = Effect { domains: &[Domain::Translational], kind: Kind::Source, what: "weight (gravity)" };
}

impl<R: Real> Weight<R> {
    /// The downward force m g, N.
    pub fn force_n(&self) -> R {
        self.mass_kg * Weight::<f64>::STANDARD_GRAVITY_M_PER_S2
    }

    /// Power the weight delivers while the mass moves up at `upward_speed_m_per_s`, -m g v, W.
    pub fn power_w(&self, upward_speed_m_per_s: R) -> R {
        -self.force_n() * upward_speed_m_per_s
    }
}

/// A ramp of `height` starting at `start_s` and lasting `duration_s` (a step when the duration
/// is 0): the built-in test signals of the models (a torque step or ramp).
/// ```
/// use components::Ramp;
/// let torque = Ramp { start_s: 0.01, duration_s: 0.02, height: 4.0 };
/// assert_eq!(torque.value(0.0), 0.0);
/// assert_eq!(torque.value(0.02), 2.0);
/// assert_eq!(torque.value(1.0), 4.0);
/// assert_eq!(torque.next_kink(0.0), Some(0.01)); // where a solver must stop
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ramp<R = f64> {
    pub start_s: R,
    pub duration_s: R,
    pub height: R,
}

impl<R: Real> Ramp<R> {
    pub fn value(&self, time_s: R) -> R {
        if time_s < self.start_s {
            R::from(0.0)
        } else if time_s >= self.start_s + self.duration_s {
            self.height
        } else {
            self.height * (time_s - self.start_s) / self.duration_s
        }
    }

    /// d(value)/dt: height / duration inside the ramp, 0 outside (and for a step).
    /// ```
    /// use components::Ramp;
    /// let r = Ramp { start_s: 1.0, duration_s: 2.0, height: 4.0 };
    /// assert_eq!((r.slope(0.5), r.slope(2.0), r.slope(3.5)), (0.0, 2.0, 0.0));
    /// ```
    pub fn slope(&self, time_s: R) -> R {
        if self.duration_s > 0.0 && time_s >= self.start_s && time_s < self.start_s + self.duration_s {
            self.height / self.duration_s
        } else {
            R::from(0.0)
        }
    }

    /// The kinks (or the step) after `after`, for the solver to stop at.
    pub fn next_kink(&self, after: R) -> Option<R> {
        [self.start_s, self.start_s + self.duration_s].into_iter().find(|t| *t > after)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_starts_late_and_reports_its_kinks() {
        let r = Ramp { start_s: 1.0, duration_s: 2.0, height: 4.0 };
        assert_eq!((r.value(0.5), r.value(2.0), r.value(3.0), r.value(9.0)), (0.0, 2.0, 4.0, 4.0));
        assert_eq!((r.next_kink(0.0), r.next_kink(1.0), r.next_kink(3.0)), (Some(1.0), Some(3.0), None));
        let step = Ramp { start_s: 1.0, duration_s: 0.0, height: 4.0 };
        assert_eq!((step.value(0.999), step.value(1.0)), (0.0, 4.0));
        assert_eq!((step.next_kink(0.0), step.next_kink(1.0)), (Some(1.0), None));
    }

    #[test]
    fn a_quarter_period_reaches_the_amplitude() {
        let s = SineVoltage { amplitude_v: 10.0, frequency_hz: 50.0 };
        assert!((s.voltage_v(0.005) - 10.0).abs() < 1e-12);
        assert_eq!(s.voltage_v(0.0), 0.0);
    }
}
