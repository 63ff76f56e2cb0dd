//! Signal elements of the variable-speed start (section 3.3.2, Figures 3.7 and 3.13): the speed
//! set-point ramp, its second-order filter and the PI speed controller.

use std::f64::consts::PI;

/// A ramp from 0 to `target` over `duration_s` starting at t = 0 (a step when the duration is 0).
/// ```
/// use components::SpeedRamp;
/// // The chapter's 10 s ramp to the fan's rated speed.
/// let set_point = SpeedRamp { target: 153.5, duration_s: 10.0 };
/// assert_eq!(set_point.value(5.0), 76.75);
/// assert_eq!(set_point.slope(5.0), 15.35);
/// assert_eq!(set_point.value(12.0), 153.5);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedRamp {
    pub target: f64,
    pub duration_s: f64,
}

impl SpeedRamp {
    pub fn value(&self, time_s: f64) -> f64 {
        if time_s <= 0.0 && self.duration_s > 0.0 {
            0.0
        } else if time_s >= self.duration_s {
            self.target
        } else {
            self.target * time_s / self.duration_s
        }
    }

    /// d(value)/dt: the slope inside the ramp, 0 outside.
    pub fn slope(&self, time_s: f64) -> f64 {
        if self.duration_s > 0.0 && time_s >= 0.0 && time_s < self.duration_s {
            self.target / self.duration_s
        } else {
            0.0
        }
    }

    /// The kinks of the ramp after `after`, for the solver to stop at.
    pub fn next_kink(&self, after: f64) -> Option<f64> {
        [0.0, self.duration_s].into_iter().find(|t| *t > after)
    }
}

/// y'' = wn^2 (u - y) - 2 zeta wn y': a second-order low-pass filter (unit static gain).
/// ```
/// use components::SecondOrderFilter;
/// // At rest on its input, a filter does not move; below it, it accelerates upward.
/// let filter = SecondOrderFilter { natural_frequency_hz: 1.0, damping: 0.7 };
/// assert_eq!(filter.acceleration(2.0, 2.0, 0.0), 0.0);
/// assert!(filter.acceleration(2.0, 0.0, 0.0) > 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SecondOrderFilter {
    pub natural_frequency_hz: f64,
    pub damping: f64,
}

impl SecondOrderFilter {
    /// y'' for input `u`, output `y` and its rate `y_rate`.
    pub fn acceleration(&self, u: f64, y: f64, y_rate: f64) -> f64 {
        let wn = 2.0 * PI * self.natural_frequency_hz;
        wn * wn * (u - y) - 2.0 * self.damping * wn * y_rate
    }
}

/// The multiplier of a synchronous demodulator (section 3.5.2, Figure 3.27, question 8): the
/// signal times the carrier reference divided by the reference's amplitude, so the product is in
/// the signal's unit. For a signal A sin(wt + phi) and the reference R sin(wt), the product is
/// (A/2) (cos phi - cos(2wt + phi)): a low-pass filter keeps the in-phase part A cos(phi) / 2.
/// ```
/// use components::Multiplier;
/// // An in-phase signal 2 sin(wt) times the reference 5 sin(wt) / 5 averages to 2 / 2 = 1.
/// let m = Multiplier { reference_amplitude: 5.0 };
/// let w = 2.0 * std::f64::consts::PI;
/// let mean: f64 = (0..1000).map(|i| { let t = i as f64 / 1000.0; m.product(2.0 * (w * t).sin(), 5.0 * (w * t).sin()) }).sum::<f64>() / 1000.0;
/// assert!((mean - 1.0).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Multiplier {
    pub reference_amplitude: f64,
}

impl Multiplier {
    pub fn product(&self, signal: f64, reference: f64) -> f64 {
        signal * reference / self.reference_amplitude
    }
}

/// A PI controller with an output limit and anti-windup by conditional integration.
/// ```
/// use components::PiController;
/// let pi = PiController { proportional_gain: 200.0, integral_gain: 2000.0, output_limit: 2500.0 };
/// assert_eq!(pi.command(1.0, 0.1), 400.0); // Kp e + Ki integral
/// assert_eq!(pi.command(100.0, 0.0), 2500.0); // clamped
/// assert_eq!(pi.integral_rate(100.0, 0.0), 0.0); // no wind-up while clamped
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PiController {
    pub proportional_gain: f64,
    pub integral_gain: f64,
    pub output_limit: f64,
}

impl PiController {
    /// The command, clamped to +/- the limit.
    pub fn command(&self, error: f64, integral: f64) -> f64 {
        (self.proportional_gain * error + self.integral_gain * integral).clamp(-self.output_limit, self.output_limit)
    }

    /// d(integral)/dt: the error, except while the command is clamped and the error would push
    /// it further into the limit (so the integral does not wind up).
    pub fn integral_rate(&self, error: f64, integral: f64) -> f64 {
        let raw = self.proportional_gain * error + self.integral_gain * integral;
        if (raw >= self.output_limit && error > 0.0) || (raw <= -self.output_limit && error < 0.0) {
            0.0
        } else {
            error
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_reaches_its_target_and_reports_its_kinks() {
        let r = SpeedRamp { target: 150.0, duration_s: 10.0 };
        assert_eq!((r.value(-1.0), r.value(5.0), r.value(12.0)), (0.0, 75.0, 150.0));
        assert_eq!((r.slope(5.0), r.slope(10.0)), (15.0, 0.0));
        assert_eq!((r.next_kink(-1.0), r.next_kink(0.0), r.next_kink(10.0)), (Some(0.0), Some(10.0), None));
        let step = SpeedRamp { target: 150.0, duration_s: 0.0 };
        assert_eq!((step.value(0.0), step.slope(0.0)), (150.0, 0.0));
    }

    #[test]
    fn filter_rests_at_its_input() {
        let f = SecondOrderFilter { natural_frequency_hz: 0.5, damping: 0.7 };
        assert_eq!(f.acceleration(3.0, 3.0, 0.0), 0.0);
        assert!(f.acceleration(3.0, 0.0, 0.0) > 0.0);
    }

    #[test]
    fn multiplier_mean_is_half_the_in_phase_amplitude() {
        // mean over one period of A sin(wt + phi) R sin(wt) / R = A cos(phi) / 2
        let m = Multiplier { reference_amplitude: 5.0 };
        let (a, phi, n) = (0.3, 0.7, 10_000);
        let mean: f64 = (0..n)
            .map(|k| {
                let x = 2.0 * PI * (k as f64 + 0.5) / n as f64;
                m.product(a * (x + phi).sin(), 5.0 * x.sin())
            })
            .sum::<f64>()
            / n as f64;
        assert!((mean - a * phi.cos() / 2.0).abs() < 1e-12);
    }

    #[test]
    fn pi_does_not_wind_up_in_saturation() {
        let pi = PiController { proportional_gain: 10.0, integral_gain: 100.0, output_limit: 50.0 };
        assert_eq!(pi.command(100.0, 0.0), 50.0);
        assert_eq!(pi.integral_rate(100.0, 0.0), 0.0, "clamped high, error positive: hold");
        assert_eq!(pi.integral_rate(-1.0, 10.0), -1.0, "clamped high, error negative: unwind");
        assert_eq!(pi.integral_rate(1.0, 0.0), 1.0);
    }
}
