//! Natural frequencies of two bodies coupled by springs: the resonance frequency of chapter eq. 3.8
//! (one inertia on one stiffness, sqrt(K/J)) generalised to two degrees of freedom, for a chain
//! where neither body is held (the launcher booster nozzle of Figure 3.15 on its flexible bearing,
//! driven through the actuator's oil column by the actuator's body on its anchoring).
//!
//! Generalised coordinates q1, q2 (an angle or a displacement each), the kinetic energy
//! (m1 q1'^2 + m2 q2'^2) / 2 and the elastic energy q^T K q / 2 with K = [[k11, k12], [k12, k22]]
//! give M q'' + K q = 0; the natural angular frequencies w solve det(K - w^2 M) = 0:
//! m1 m2 w^4 - (m1 k22 + m2 k11) w^2 + (k11 k22 - k12^2) = 0.

use fmu_runtime::real::Real;
use std::f64::consts::PI;

/// Two bodies of (generalised) masses m1 and m2 with the symmetric stiffness matrix
/// [[k11, k12], [k12, k22]] (undamped).
/// ```
/// use components::{TorsionSpring, TwoDegreesOfFreedom};
/// // Uncoupled: each body on its own spring (eq. 3.8 twice).
/// let apart = TwoDegreesOfFreedom { m1: 4.0, m2: 1.0, k11: 400.0, k12: 0.0, k22: 900.0 };
/// let (low, high) = apart.natural_angular_frequencies_rad_per_s();
/// assert!((low - 10.0).abs() < 1e-12 && (high - 30.0).abs() < 1e-12);
/// // The chapter's motor and fan (fan referred to the motor's shaft, 11.72 kg m2) on the
/// // 906.85 N m/rad driveshaft, both free: a rigid-body mode at 0 and the shaft mode, which is
/// // the spring between the two inertias.
/// let shaft = TorsionSpring { stiffness_n_m_per_rad: 906.85, damping_n_m_s_per_rad: 0.0 };
/// let drive = TwoDegreesOfFreedom::chain(1.72, 11.72, 0.0, 0.0, shaft.stiffness_n_m_per_rad, 1.0);
/// let (rigid, shaft_mode) = drive.natural_frequencies_hz();
/// assert!(rigid.abs() < 1e-9);
/// assert!((shaft_mode - shaft.natural_frequency_hz(1.72, 11.72)).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoDegreesOfFreedom<R = f64> {
    pub m1: R,
    pub m2: R,
    pub k11: R,
    pub k12: R,
    pub k22: R,
}

impl<R: Real> TwoDegreesOfFreedom<R> {
    /// The chain ground - k1 - body 1 - coupling spring - body 2 - k2 - ground, where the coupling
    /// spring (stiffness kc) stretches by `lever` q1 - q2: body 1 turns (q1 an angle, m1 an inertia)
    /// and meets the spring at the arm `lever`, body 2 translates along it. Its elastic energy
    /// (k1 q1^2 + kc (lever q1 - q2)^2 + k2 q2^2) / 2 gives k11 = k1 + kc lever^2,
    /// k12 = -kc lever, k22 = kc + k2.
    /// ```
    /// use components::TwoDegreesOfFreedom;
    /// // A 1400 kg m2 nozzle on a flexible bearing of 8.7e5 N m/rad, an actuator at 1.35 m whose
    /// // oil column (1.04e8 N/m) meets a 30 kg actuator body on a 1e8 N/m anchoring.
    /// let nozzle = TwoDegreesOfFreedom::chain(1400.0, 30.0, 8.709e5, 1e8, 1.04e8, 1.35);
    /// let (f_low, f_high) = nozzle.natural_frequencies_hz();
    /// assert!((f_low - 40.98).abs() < 0.01 && (f_high - 417.1).abs() < 0.1);
    /// // The body's mass alone changes little: the nozzle on the two springs in series
    /// // (massless body), sqrt((K_b + lever^2 k_s) / J) with k_s = 1 / (1/kc + 1/k2).
    /// let k_s = 1.0 / (1.0 / 1.04e8 + 1.0 / 1e8);
    /// let massless = ((8.709e5 + 1.35f64.powi(2) * k_s) / 1400.0).sqrt() / (2.0 * std::f64::consts::PI);
    /// assert!((f_low / massless - 1.0).abs() < 0.01);
    /// ```
    pub fn chain(m1: R, m2: R, k1: R, k2: R, kc: R, lever: R) -> Self {
        TwoDegreesOfFreedom { m1, m2, k11: k1 + kc * lever * lever, k12: -kc * lever, k22: kc + k2 }
    }

    /// The two natural angular frequencies (low, high), rad/s. The discriminant is written
    /// (m1 k22 - m2 k11)^2 + 4 m1 m2 k12^2 (never negative) and the low root as c / (the high
    /// root's m1 m2 w^2), so neither loses digits to cancellation.
    pub fn natural_angular_frequencies_rad_per_s(&self) -> (R, R) {
        let a = self.m1 * self.m2;
        let b = self.m1 * self.k22 + self.m2 * self.k11;
        let c = self.k11 * self.k22 - self.k12 * self.k12;
        let d = (self.m1 * self.k22 - self.m2 * self.k11).powi(2) + a * 4.0 * self.k12 * self.k12;
        let high_sq = (b + d.sqrt()) / (a * 2.0);
        let low_sq = if high_sq > 0.0 { c / (a * high_sq) } else { R::from(0.0) };
        (low_sq.max(R::from(0.0)).sqrt(), high_sq.max(R::from(0.0)).sqrt())
    }

    /// The two natural frequencies (low, high), Hz.
    pub fn natural_frequencies_hz(&self) -> (R, R) {
        let (low, high) = self.natural_angular_frequencies_rad_per_s();
        (low / (2.0 * PI), high / (2.0 * PI))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// det(K - w^2 M) at each root is 0 (relative to the matrices' scale), and the roots are
    /// ordered, for well- and ill-conditioned pairs (a heavy body on a soft spring beside a light
    /// one on a stiff spring).
    #[test]
    fn the_roots_make_the_determinant_vanish() {
        for sys in [
            TwoDegreesOfFreedom { m1: 1.0, m2: 1.0, k11: 2.0, k12: -1.0, k22: 2.0 },
            TwoDegreesOfFreedom::chain(1400.0, 30.0, 8.7e5, 1e8, 1.04e8, 1.35),
            TwoDegreesOfFreedom::chain(1e6, 1e-3, 1.0, 1e9, 1e3, 0.1),
        ] {
            let (low, high) = sys.natural_angular_frequencies_rad_per_s();
            assert!(low <= high);
            for w in [low, high] {
                let w2 = w * w;
                let det = (sys.k11 - w2 * sys.m1) * (sys.k22 - w2 * sys.m2) - sys.k12 * sys.k12;
                let scale = (sys.k11.abs() + w2 * sys.m1) * (sys.k22.abs() + w2 * sys.m2);
                assert!(det.abs() <= 1e-10 * scale, "{sys:?}: det {det} at w {w}");
            }
        }
        // Two equal masses on three equal springs: sqrt(k/m) and sqrt(3 k/m).
        let (low, high) = TwoDegreesOfFreedom { m1: 1.0, m2: 1.0, k11: 2.0, k12: -1.0, k22: 2.0 }.natural_angular_frequencies_rad_per_s();
        assert!((low - 1.0).abs() < 1e-15 && (high - 3f64.sqrt()).abs() < 1e-15);
    }
}
