//! A motor given by its steady-state torque-speed characteristic rather than by an equivalent
//! circuit: the book's cooling-tower models at levels a-c (book file Chap3_CoolingTowerFan.mo,
//! component TorqueSpeed, a CombiTable1D read at the motor speed, Figure 3.5).

use crate::roots::{bisect, with_derivatives};
use fmu_runtime::elements::{Domain, Effect, Kind};
use fmu_runtime::real::Real;

/// How a table is read between its points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// Straight segments between the points (a CombiTable1D's default, `LinearSegments`).
    Linear,
    /// Akima's cubic (H. Akima, J. ACM 17, 1970): at each point the slope is the mean of the
    /// neighbouring segments' slopes weighted by how much the slopes on the far side change, so a
    /// single outlier does not ring; continuous first derivative (CombiTable1D's
    /// `ContinuousDerivative`). At the ends the segment slopes are extended linearly,
    /// m(-1) = 2 m(0) - m(1) and m(-2) = 3 m(0) - 2 m(1), as Akima does.
    Akima,
}

/// A torque-speed characteristic T(w) through `N` >= 3 points of increasing speed. Outside its
/// speeds it continues along a straight line: through the last two points (linear) or along the
/// curve's tangent at the end point (Akima), the "last two points" extrapolation of CombiTable1D.
/// The points are of any scalar (`f64` by default: a model's parameters); the segment is chosen
/// by the speed's value and its polynomial evaluated in the scalar, so that the torque carries
/// the derivatives of the speed and of the points.
/// ```
/// use components::{Interpolation, TorqueSpeedTable};
/// let motor = TorqueSpeedTable { speed_rad_per_s: [0.0, 100.0, 200.0], torque_n_m: [500.0, 800.0, 0.0], interpolation: Interpolation::Linear };
/// assert_eq!(motor.torque_n_m(50.0), 650.0);
/// assert_eq!(motor.torque_n_m(250.0), -400.0); // beyond the last point, on its segment's line
/// // Under a load of 100 N m + 1 N m per rad/s, the drive settles where 800 - 8 (w - 100) = 100 + w.
/// let w = motor.stable_speed_rad_per_s(|w| 100.0 + w).unwrap();
/// assert!((w - 1500.0 / 9.0).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorqueSpeedTable<const N: usize, R = f64> {
    pub speed_rad_per_s: [R; N],
    pub torque_n_m: [R; N],
    pub interpolation: Interpolation,
}

impl<const N: usize> TorqueSpeedTable<N> {
    /// Its effect: the motor seen by its steady torque-speed characteristic, a source of
    /// torque on the shaft (the supply, the windings and the transformer of Table 3.1 lumped).
    pub const SOURCE: Effect = Effect { domains: &[Domain::Rotational], kind: Kind::Source, what: "motor torque-speed characteristic" };
}

/// Akima's slope at a point from the slopes of the two segments on either side of it
/// `[m_-2, m_-1, m_0, m_1]`: the mean of the two nearest weighted by how much the far ones
/// differ from them (their plain mean where both weights vanish).
fn akima_slope<R: Real>([m_2, m_1, m0, m1]: [R; 4]) -> R {
    let (w_left, w_right) = ((m1 - m0).abs(), (m_1 - m_2).abs());
    if w_left + w_right == 0.0 {
        (m_1 + m0) * 0.5
    } else {
        (w_left * m_1 + w_right * m0) / (w_left + w_right)
    }
}

impl<const N: usize, R: Real> TorqueSpeedTable<N, R> {
    /// The slope of segment `i` (between points i and i + 1); beyond the ends, Akima's linear
    /// extension of the segment slopes.
    fn segment_slope(&self, i: isize) -> R {
        let (x, y) = (&self.speed_rad_per_s, &self.torque_n_m);
        let last = N as isize - 2;
        let slope = |j: usize| (y[j + 1] - y[j]) / (x[j + 1] - x[j]);
        if i < 0 {
            let (m0, m1) = (slope(0), slope(1.min(N - 2)));
            m0 + (m0 - m1) * (-i) as f64
        } else if i > last {
            let (m0, m1) = (slope(N - 2), slope((N - 3).min(N - 2)));
            m0 + (m0 - m1) * (i - last) as f64
        } else {
            slope(i as usize)
        }
    }

    /// The curve's slope at point `i`, dT/dw in N m per rad/s.
    fn point_slope(&self, i: usize) -> R {
        match self.interpolation {
            Interpolation::Linear => self.segment_slope(i.min(N - 2) as isize),
            Interpolation::Akima => {
                let i = i as isize;
                akima_slope([self.segment_slope(i - 2), self.segment_slope(i - 1), self.segment_slope(i), self.segment_slope(i + 1)])
            }
        }
    }

    /// T(w), N m.
    pub fn torque_n_m(&self, speed_rad_per_s: R) -> R {
        let (x, y) = (&self.speed_rad_per_s, &self.torque_n_m);
        let w = speed_rad_per_s;
        if w <= x[0] || w >= x[N - 1] {
            let (i, j) = if w <= x[0] { (0, 0) } else { (N - 1, N - 2) };
            let slope = match self.interpolation {
                Interpolation::Linear => self.segment_slope(j as isize),
                Interpolation::Akima => self.point_slope(i),
            };
            return y[i] + slope * (w - x[i]);
        }
        // w is strictly inside (x[0], x[N-1]) here; the clamp keeps a NaN speed (which fails
        // every comparison above) on a segment instead of indexing out of bounds.
        let i = x.partition_point(|xi| *xi <= w).saturating_sub(1).min(N - 2);
        let h = x[i + 1] - x[i];
        match self.interpolation {
            Interpolation::Linear => y[i] + (y[i + 1] - y[i]) * (w - x[i]) / h,
            Interpolation::Akima => {
                // Cubic Hermite on the segment with the Akima slopes at its ends.
                let s = (w - x[i]) / h;
                let one = R::from(1.0);
                // The Akima slopes at both ends share three of their four segment slopes.
                let m: [R; 5] = std::array::from_fn(|j| self.segment_slope(i as isize - 2 + j as isize));
                let (d0, d1) = (akima_slope([m[0], m[1], m[2], m[3]]) * h, akima_slope([m[1], m[2], m[3], m[4]]) * h);
                let (h00, h10, h01, h11) = (
                    (one + s * 2.0) * (one - s) * (one - s),
                    s * (one - s) * (one - s),
                    s * s * (R::from(3.0) - s * 2.0),
                    s * s * (s - 1.0),
                );
                h00 * y[i] + h10 * d0 + h01 * y[i + 1] + h11 * d1
            }
        }
    }

    /// The stable operating speed under a load torque curve: the balance between the table's
    /// point of largest torque and the speed beyond its last point where the motor torque falls
    /// below the load (where the excess torque falls through zero, so a small slow-down raises
    /// the motor's torque above the load's). None if the load exceeds the largest torque (the
    /// motor stalls).
    ///
    /// The speed is found on values (bisection); its derivatives, where the scalar carries
    /// them (the load's, the table's), are those of the balance's implicit function
    /// ([`with_derivatives`]).
    pub fn stable_speed_rad_per_s(&self, load_torque_n_m: impl Fn(R) -> R) -> Option<R> {
        let excess = |w: R| self.torque_n_m(w) - load_torque_n_m(w);
        let peak = (0..N).max_by(|&a, &b| self.torque_n_m[a].value().total_cmp(&self.torque_n_m[b].value())).unwrap_or(0);
        let lo = self.speed_rad_per_s[peak];
        if excess(lo) < 0.0 {
            return None;
        }
        let span = (self.speed_rad_per_s[N - 1] - lo).max(R::from(1.0));
        let mut hi = self.speed_rad_per_s[N - 1];
        let mut widenings = 0;
        while excess(hi) >= 0.0 {
            hi += span;
            widenings += 1;
            if widenings > 60 {
                return None;
            }
        }
        let root = bisect(lo.value(), hi.value(), 80, |w| excess(R::from(w)) >= 0.0);
        Some(with_derivatives(root, (hi - lo).value(), excess))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The book's table (Chap3_CoolingTowerFan.mo, TorqueSpeed).
    const BOOK: TorqueSpeedTable<10> = TorqueSpeedTable {
        speed_rad_per_s: [0.0, 80.0, 160.0, 220.0, 240.0, 250.0, 260.0, 280.0, 300.0, 314.0],
        torque_n_m: [454.0, 579.0, 784.0, 997.0, 1057.0, 1071.0, 1060.0, 919.0, 500.0, 0.0],
        interpolation: Interpolation::Akima,
    };

    #[test]
    fn both_interpolations_pass_through_every_point() {
        for interpolation in [Interpolation::Linear, Interpolation::Akima] {
            let t = TorqueSpeedTable { interpolation, ..BOOK };
            for (w, torque) in t.speed_rad_per_s.iter().zip(t.torque_n_m) {
                assert!((t.torque_n_m(*w) - torque).abs() < 1e-9, "{interpolation:?} at {w}");
            }
        }
    }

    #[test]
    fn akima_has_a_continuous_slope_and_reproduces_a_straight_line() {
        for w in [80.0, 160.0, 250.0, 300.0] {
            let slope = |a: f64, b: f64| (BOOK.torque_n_m(b) - BOOK.torque_n_m(a)) / (b - a);
            let (left, right) = (slope(w - 2e-4, w - 1e-4), slope(w + 1e-4, w + 2e-4));
            assert!((left - right).abs() < 1e-3 * left.abs().max(1.0), "kink at {w}: {left} vs {right}");
        }
        let line = TorqueSpeedTable { speed_rad_per_s: [0.0, 1.0, 3.0, 4.0], torque_n_m: [1.0, 3.0, 7.0, 9.0], interpolation: Interpolation::Akima };
        for w in [-1.0, 0.5, 2.0, 3.7, 5.0] {
            assert!((line.torque_n_m(w) - (1.0 + 2.0 * w)).abs() < 1e-12);
        }
    }

    /// Akima's slope at an interior point (point 5, 250 rad/s, of the book's table) against the
    /// definition written out from the four neighbouring segment slopes.
    #[test]
    fn akima_point_slope_follows_the_definition() {
        let m = |i: usize| (BOOK.torque_n_m[i + 1] - BOOK.torque_n_m[i]) / (BOOK.speed_rad_per_s[i + 1] - BOOK.speed_rad_per_s[i]);
        let (m3, m4, m5, m6) = (m(3), m(4), m(5), m(6));
        let expected = ((m6 - m5).abs() * m4 + (m4 - m3).abs() * m5) / ((m6 - m5).abs() + (m4 - m3).abs());
        assert!((BOOK.point_slope(5) - expected).abs() < 1e-12);
    }
}
