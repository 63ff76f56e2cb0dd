//! Signal elements of the variable-speed start (section 3.3.2, Figures 3.7 and 3.13): the speed
//! set-point ramp, its second-order filter and the PI speed controller.

use fmu_runtime::real::Real;
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
pub struct SpeedRamp<R = f64> {
    pub target: R,
    pub duration_s: R,
}

impl<R: Real> SpeedRamp<R> {
    pub fn value(&self, time_s: R) -> R {
        if time_s <= 0.0 && self.duration_s > 0.0 {
            R::from(0.0)
        } else if time_s >= self.duration_s {
            self.target
        } else {
            self.target * time_s / self.duration_s
        }
    }

    /// d(value)/dt: the slope inside the ramp, 0 outside.
    pub fn slope(&self, time_s: R) -> R {
        if self.duration_s > 0.0 && time_s >= 0.0 && time_s < self.duration_s {
            self.target / self.duration_s
        } else {
            R::from(0.0)
        }
    }

    /// The kinks of the ramp after `after`, for the solver to stop at.
    pub fn next_kink(&self, after: R) -> Option<R> {
        [R::from(0.0), self.duration_s].into_iter().find(|t| *t > after)
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
pub struct SecondOrderFilter<R = f64> {
    pub natural_frequency_hz: R,
    pub damping: R,
}

impl<R: Real> SecondOrderFilter<R> {
    /// The filter 1 / (1 + a1 s + a2 s^2) (unit static gain): wn = 1 / sqrt(a2),
    /// zeta = a1 / (2 sqrt(a2)).
    /// ```
    /// use components::SecondOrderFilter;
    /// let f = SecondOrderFilter::from_coefficients(2.0 * 0.7 / 100.0, 1.0 / 100.0f64.powi(2));
    /// assert!((f.natural_frequency_hz - 100.0 / (2.0 * std::f64::consts::PI)).abs() < 1e-9);
    /// assert!((f.damping - 0.7).abs() < 1e-12);
    /// ```
    pub fn from_coefficients(a1_s: R, a2_s2: R) -> Self {
        let root = a2_s2.sqrt();
        SecondOrderFilter { natural_frequency_hz: R::from(1.0) / (root * (2.0 * PI)), damping: a1_s / (root * 2.0) }
    }

    /// The second-order Bessel-type filter that smooths a position (or speed) reference at a
    /// critical frequency f_c: 1 / (1 + (1.3617 / w_c) s + (0.6180 / w_c^2) s^2), w_c = 2 pi f_c,
    /// the smoothing of Modelica's rotational Position source when it is not `exact` (its
    /// default, f_crit = 50 Hz; the book's torque-sensor model drives its torsion bar through
    /// one: book file Chap3_TorqueSensor.mo, component position). wn = 1.272 w_c, zeta = 0.866.
    /// ```
    /// use components::SecondOrderFilter;
    /// let f = SecondOrderFilter::bessel(50.0);
    /// assert!((f.natural_frequency_hz - 50.0 / 0.6180f64.sqrt()).abs() < 1e-9);
    /// assert!((f.damping - 1.3617 / (2.0 * 0.6180f64.sqrt())).abs() < 1e-12);
    /// ```
    pub fn bessel(critical_frequency_hz: R) -> Self {
        const A1: f64 = 1.3617; // s coefficient times w_c
        const A2: f64 = 0.6180; // s^2 coefficient times w_c^2
        let wc = critical_frequency_hz * (2.0 * PI);
        SecondOrderFilter::from_coefficients(R::from(A1) / wc, R::from(A2) / (wc * wc))
    }

    /// The filter w^2 / (s^2 + 2 D w s + w^2) given by its angular frequency w in rad/s (as
    /// Modelica's `SecondOrder` block takes it: the book writes w = 2*3.14*800 for the PI start's
    /// torque actuator, book file Chap3_CoolingTowerFan.mo, component secondOrder).
    /// ```
    /// use components::SecondOrderFilter;
    /// let f = SecondOrderFilter::from_angular_frequency(2.0 * 3.14 * 800.0, 1.0);
    /// assert!((f.natural_frequency_hz - 800.0 * 3.14 / std::f64::consts::PI).abs() < 1e-9);
    /// ```
    pub fn from_angular_frequency(angular_frequency_rad_per_s: R, damping: R) -> Self {
        SecondOrderFilter { natural_frequency_hz: angular_frequency_rad_per_s / (2.0 * PI), damping }
    }

    /// y'' for input `u`, output `y` and its rate `y_rate`.
    pub fn acceleration(&self, u: R, y: R, y_rate: R) -> R {
        let wn = self.natural_frequency_hz * (2.0 * PI);
        wn * wn * (u - y) - self.damping * 2.0 * wn * y_rate
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
pub struct Multiplier<R = f64> {
    pub reference_amplitude: R,
}

impl<R: Real> Multiplier<R> {
    pub fn product(&self, signal: R, reference: R) -> R {
        signal * reference / self.reference_amplitude
    }
}

/// A PI controller with an output limit and anti-windup by back-calculation (tracking): while
/// the command is clamped, the integral is also driven by the clamped part of the command,
/// (u - raw) / (Ki T_t), so the raw command stays within Ki T_t |e| of the limit instead of
/// winding up (Astrom & Hagglund; Modelica's `LimPID` does the same with T_t = Ni Ti).
///
/// The integral's rate is continuous in the error and the integral. Conditional integration
/// (hold the integral while clamped and pushed further in) is not: where the free integral
/// pushes the raw command up to the limit and the held one lets it fall back, the solution
/// slides along the limit, and a variable-step solver chatters across the switch (MotorFan's
/// PI start with the 5 Hz set-point filter needed more than 200 000 steps in one 10 ms
/// communication step at rtol 1e-11).
/// ```
/// use components::PiController;
/// let pi = PiController { proportional_gain: 200.0, integral_gain: 2000.0, output_limit: 2500.0, tracking_time_s: 0.09 };
/// assert_eq!(pi.command(1.0, 0.1), 400.0); // Kp e + Ki integral
/// assert_eq!(pi.command(100.0, 0.0), 2500.0); // clamped
/// // Clamped: the error (100) less the excess (20 000 - 2 500) / (Ki T_t).
/// assert!((pi.integral_rate(100.0, 0.0) - (100.0 - 17_500.0 / (2000.0 * 0.09))).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PiController<R = f64> {
    pub proportional_gain: R,
    pub integral_gain: R,
    /// The limit on |command|, N m; `f64::INFINITY` for none (then nothing is ever clamped).
    pub output_limit: R,
    /// The anti-windup tracking time constant T_t, s (> 0).
    pub tracking_time_s: R,
}

impl<R: Real> PiController<R> {
    /// The raw command Kp e + Ki integral, before the limit.
    fn raw(&self, error: R, integral: R) -> R {
        self.proportional_gain * error + self.integral_gain * integral
    }

    /// The command, clamped to +/- the limit.
    pub fn command(&self, error: R, integral: R) -> R {
        self.raw(error, integral).clamp(-self.output_limit, self.output_limit)
    }

    /// d(integral)/dt: the error plus the tracking term (u - raw) / (Ki T_t), which is zero while
    /// the command is within its limit. Without an integral gain the integral does not act on the
    /// command, and it integrates the error alone.
    pub fn integral_rate(&self, error: R, integral: R) -> R {
        if self.integral_gain == 0.0 {
            return error;
        }
        let raw = self.raw(error, integral);
        let clamped = raw.clamp(-self.output_limit, self.output_limit);
        error + (clamped - raw) / (self.integral_gain * self.tracking_time_s)
    }

    /// The event indicator of the limit's kinks, for a solver to stop at them rather than step
    /// across (the command and the integral's rate have a corner there). Its `mode`: 0 within the
    /// limits (indicator limit - |raw|), 1 clamped at +limit (raw - limit), -1 at -limit
    /// (-limit - raw); a mode holds exactly while its indicator is positive. The equations do
    /// not depend on the mode: it only marks the side.
    pub fn limit_indicator(&self, mode: i32, error: R, integral: R) -> R {
        let raw = self.raw(error, integral);
        match mode {
            1 => raw - self.output_limit,
            -1 => -self.output_limit - raw,
            _ => self.output_limit - raw.abs(),
        }
    }

    /// The limit's mode after an event: the side of the limit the raw command is on; exactly at a
    /// limit, the side it is heading to (`raw_rate`, d(raw)/dt), and where that is zero too the
    /// mode holds. The answer depends on the current mode only there, so a repeated update
    /// settles at once.
    pub fn next_limit_mode(&self, mode: i32, error: R, integral: R, raw_rate: R) -> i32 {
        let (raw, limit) = (self.raw(error, integral), self.output_limit);
        if raw > limit {
            1
        } else if raw < -limit {
            -1
        } else if raw.abs() < limit {
            0
        } else {
            let outwards = raw_rate * raw;
            if outwards > 0.0 {
                raw.value().signum() as i32
            } else if outwards < 0.0 {
                0
            } else {
                mode
            }
        }
    }

    /// d(raw)/dt = Kp de/dt + Ki d(integral)/dt, for [`next_limit_mode`](Self::next_limit_mode).
    pub fn raw_rate(&self, error: R, error_rate: R, integral: R) -> R {
        self.proportional_gain * error_rate + self.integral_gain * self.integral_rate(error, integral)
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
        let pi = PiController { proportional_gain: 10.0, integral_gain: 100.0, output_limit: 50.0, tracking_time_s: 0.05 };
        assert_eq!(pi.command(100.0, 0.0), 50.0);
        assert_eq!(pi.integral_rate(1.0, 0.0), 1.0, "within the limit: the error");
        // A constant error of 10 holds the command clamped (raw 100 + 100 I). Integrated by
        // forward Euler for 2 s (40 T_t), the integral settles where its rate vanishes:
        // raw = limit + Ki T_t e, i.e. I = (50 + 100 * 0.05 * 10 - 100) / 100 = 0 (independent
        // of the start: from I = 3, raw 400, far into the limit).
        let (mut integral, dt) = (3.0, 1e-4);
        for _ in 0..20_000 {
            integral += dt * pi.integral_rate(10.0, integral);
        }
        assert!(integral.abs() < 1e-9, "the integral winds down to 0, not up: {integral}");
        assert_eq!(pi.command(10.0, integral), 50.0, "and the command stays at the limit");
        // Unwinding: a negative error lowers the integral at once.
        assert!(pi.integral_rate(-1.0, 10.0) < -1.0);
    }

    #[test]
    fn pi_integral_rate_is_continuous_across_the_limit() {
        let pi = PiController { proportional_gain: 10.0, integral_gain: 100.0, output_limit: 50.0, tracking_time_s: 0.05 };
        // raw = 10 * 1 + 100 I reaches the limit 50 at I = 0.4.
        for i in [0.4, -0.6] {
            let below = pi.integral_rate(1.0, i - 1e-9);
            let above = pi.integral_rate(1.0, i + 1e-9);
            assert!((below - above).abs() < 1e-6, "at I = {i}: {below} vs {above}");
        }
    }

    #[test]
    fn pi_limit_mode_follows_the_side_of_the_limit() {
        let pi = PiController { proportional_gain: 10.0, integral_gain: 100.0, output_limit: 50.0, tracking_time_s: 0.05 };
        // raw = 10 e + 100 I.
        assert_eq!(pi.next_limit_mode(0, 1.0, 0.5, 0.0), 1, "raw 60 > 50");
        assert_eq!(pi.next_limit_mode(1, 1.0, 0.3, 0.0), 0, "raw 40 within");
        assert_eq!(pi.next_limit_mode(0, -1.0, -0.5, 0.0), -1, "raw -60");
        // Exactly at the limit (raw 50): the way it is heading decides, and a repeat agrees.
        for mode in [0, 1] {
            assert_eq!(pi.next_limit_mode(mode, 1.0, 0.4, 3.0), 1);
            assert_eq!(pi.next_limit_mode(mode, 1.0, 0.4, -3.0), 0);
            assert_eq!(pi.next_limit_mode(mode, 1.0, 0.4, 0.0), mode);
        }
        // Each mode holds exactly while its indicator is positive.
        for (mode, e, i) in [(0, 1.0, 0.3), (1, 1.0, 0.5), (-1, -1.0, -0.5)] {
            assert!(pi.limit_indicator(mode, e, i) > 0.0);
            assert_eq!(pi.next_limit_mode(mode, e, i, 0.0), mode);
        }
        assert!(pi.limit_indicator(0, 1.0, 0.5) < 0.0 && pi.limit_indicator(1, 1.0, 0.3) < 0.0);
    }

    #[test]
    fn pi_without_integral_gain_integrates_the_error() {
        let pi = PiController { proportional_gain: 10.0, integral_gain: 0.0, output_limit: 50.0, tracking_time_s: 0.05 };
        assert_eq!(pi.integral_rate(100.0, 7.0), 100.0);
    }
}
