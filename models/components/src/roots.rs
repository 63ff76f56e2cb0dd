//! Root bracketing shared by the elements that solve a balance on a monotone stretch of a curve
//! (an induction motor's stable speed under a load, the slip for a torque, a torque-speed
//! table's operating point).
//!
//! The root is found on values ([`bisect`]); its derivatives, where the scalar carries them
//! ([`Real`]), are those of the implicit function residual(x) = 0, added by
//! [`with_derivatives`]: dx = -(d residual at fixed x) / (d residual / dx).

use fmu_runtime::real::Real;
use std::any::TypeId;

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

/// The root `root` of `residual`, found on values (by [`bisect`]), as an `R` that carries the
/// derivatives of the root: those of the implicit function residual(x, knowns) = 0,
/// dx = -(d residual / d knowns) / (d residual / dx). With `f64` it is `root`, bit for bit (no
/// derivative to carry, and `residual` is not evaluated).
///
/// How: the value stays `root`; the derivatives are iterated to their fixed point,
/// x <- x - r(x) / s with only the derivative part of the residual r (its value is set to
/// exactly 0), s the slope of the residual at the root from a fourth-order central difference
/// of its values over `scale` 1e-4 (`scale`: the width of the bracket the root was found in).
/// The derivative part converges whatever the accuracy of s (each iteration multiplies its error
/// by 1 - r'/s, about 1e-10 here): the converged derivative is r's own, exact to round-off.
/// Where the slope is zero or not finite (a double root, a kink) the root comes back without
/// derivatives.
/// ```
/// use components::roots::{bisect, with_derivatives};
/// use fmu_runtime::real::Dual;
/// // x^2 = a at a = 2 moving at rate 1: dx/da = 1 / (2 sqrt(a)).
/// let a = Dual::new(2.0, 1.0);
/// let root = bisect(0.0, 2.0, 80, |x| x * x <= a.re);
/// let x = with_derivatives(root, 2.0, |x: Dual| x * x - a);
/// assert_eq!(x.re, root);
/// assert!((x.eps - 0.5 / 2f64.sqrt()).abs() < 1e-15);
/// assert_eq!(with_derivatives(root, 2.0, |x: f64| x * x - 2.0), root);
/// ```
pub fn with_derivatives<R: Real>(root: f64, scale: f64, residual: impl Fn(R) -> R) -> R {
    if is_f64::<R>() {
        return R::from(root);
    }
    let h = 1e-4 * scale.abs().max(root.abs() * 1e-3).max(f64::MIN_POSITIVE);
    let r = |x: f64| residual(R::from(x)).value();
    let slope = (8.0 * (r(root + h) - r(root - h)) - (r(root + 2.0 * h) - r(root - 2.0 * h))) / (12.0 * h);
    let mut x = R::from(root);
    if !(slope != 0.0 && slope.is_finite()) {
        return x;
    }
    for _ in 0..4 {
        let at = residual(x);
        if !at.value().is_finite() {
            return R::from(root);
        }
        // Only the derivatives: the value of `at - at.value()` is exactly +0, and `+ 0.0` keeps
        // the correction's value +0 (so that x keeps its value, also a -0).
        x = x - ((at - at.value()) / slope + 0.0);
    }
    x
}

/// `value` carrying the derivatives of `like` (a root found at the end of its bracket, where it
/// is that end): `value` bit for bit with `f64`.
/// ```
/// use components::roots::with_derivatives_of;
/// use fmu_runtime::real::Dual;
/// let x = with_derivatives_of(0.25, Dual::new(0.2500001, 3.0));
/// assert_eq!((x.re, x.eps), (0.25, 3.0));
/// assert_eq!(with_derivatives_of(0.25, 0.2500001), 0.25);
/// ```
pub fn with_derivatives_of<R: Real>(value: f64, like: R) -> R {
    if is_f64::<R>() {
        return R::from(value);
    }
    R::from(value) + ((like - like.value()) + 0.0)
}

/// Whether the scalar is plain `f64` (no derivatives to carry: the roots skip the work).
fn is_f64<R: Real>() -> bool {
    TypeId::of::<R>() == TypeId::of::<f64>()
}
