//! Sources: the effort a model imposes from outside.

use std::f64::consts::PI;

/// u(t) = amplitude sin(2 pi f t), the excitation of chapter Figure 3.3.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SineVoltage {
    pub amplitude_v: f64,
    pub frequency_hz: f64,
}

impl SineVoltage {
    pub fn angular_frequency_rad_per_s(&self) -> f64 {
        2.0 * PI * self.frequency_hz
    }

    /// Voltage at time t, V.
    pub fn voltage_v(&self, time_s: f64) -> f64 {
        self.amplitude_v * (self.angular_frequency_rad_per_s() * time_s).sin()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quarter_period_reaches_the_amplitude() {
        let s = SineVoltage { amplitude_v: 10.0, frequency_hz: 50.0 };
        assert!((s.voltage_v(0.005) - 10.0).abs() < 1e-12);
        assert_eq!(s.voltage_v(0.0), 0.0);
    }
}
