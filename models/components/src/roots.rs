//! Root bracketing shared by the elements that solve a balance on a monotone stretch of a curve
//! (an induction motor's stable speed under a load, the slip for a torque, a torque-speed
//! table's operating point).

/// Bisection on [`lo`, `hi`] for the point where `holds` stops being true: `holds(lo)` is
/// expected true and `holds(hi)` false, and the answer is the midpoint of the last bracket after
/// `iterations` halvings (80 reach the ulp of any f64 bracket).
/// ```
/// use components::roots::bisect;
/// let root = bisect(0.0, 2.0, 80, |x| x * x <= 2.0);
/// assert!((root - 2f64.sqrt()).abs() < 1e-15);
/// ```
pub fn bisect(mut lo: f64, mut hi: f64, iterations: usize, holds: impl Fn(f64) -> bool) -> f64 {
    for _ in 0..iterations {
        let mid = 0.5 * (lo + hi);
        if holds(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}
