//! The scalar the equations compute with, so that one set of equations gives values and exact
//! derivatives (docs/DESIGN.md, "Exact derivatives: equations over any scalar").
//!
//! [`Real`] is what a component or a model's equations need of a number: arithmetic (also with
//! plain `f64` constants on the right, `x * 2.0`, `x - 1.0`), comparisons by value (`x > 0.0`),
//! and the elementary functions. `f64` implements it with its own operations, bit for bit, so
//! equations written over `R: Real` and run with `f64` give exactly what they gave written over
//! `f64`. [`Dual`] implements it with one derivative carried beside the value (forward-mode
//! automatic differentiation): run with the knowns seeded along a direction, the equations give
//! the directional derivative of every unknown, exact to round-off.
//!
//! Writing equations over `R`: a constant goes on the right of an operator (`x * 2.0`, not
//! `2.0 * x`; `R::from(2.0) / x` where it must come first); a branch compares values
//! (`if x > 0.0`), and the derivative is that of the branch taken. Functions whose derivative
//! is zero almost everywhere (`floor`, `signum`) give zero.

use std::fmt::Debug;
use std::iter::Sum;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// A real number the equations compute with: `f64`, or a number that carries derivatives.
pub trait Real:
    Copy
    + Debug
    + Default
    + Send
    + Sync
    + 'static
    + PartialEq
    + PartialOrd
    + PartialEq<f64>
    + PartialOrd<f64>
    + From<f64>
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
    + AddAssign<f64>
    + SubAssign<f64>
    + MulAssign<f64>
    + DivAssign<f64>
    + Sum
{
    /// The value, without derivatives: for decisions and for what needs a plain number.
    fn value(self) -> f64;
    fn abs(self) -> Self;
    /// -1, 0 or 1 as `f64::signum` (1 at +0): a constant, derivative zero.
    fn signum(self) -> Self;
    fn sqrt(self) -> Self;
    fn cbrt(self) -> Self;
    fn exp(self) -> Self;
    fn ln(self) -> Self;
    fn ln_1p(self) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    fn tan(self) -> Self;
    fn asin(self) -> Self;
    fn acos(self) -> Self;
    fn atan(self) -> Self;
    fn atan2(self, other: Self) -> Self;
    fn sinh(self) -> Self;
    fn cosh(self) -> Self;
    fn tanh(self) -> Self;
    fn powi(self, n: i32) -> Self;
    fn powf(self, n: Self) -> Self;
    fn hypot(self, other: Self) -> Self;
    /// The smaller one, as `f64::min` (the other one where one is NaN).
    fn min(self, other: Self) -> Self;
    fn max(self, other: Self) -> Self;
    fn clamp(self, lo: Self, hi: Self) -> Self;
    fn floor(self) -> Self;
    fn ceil(self) -> Self;
    fn rem_euclid(self, rhs: Self) -> Self;
    fn to_radians(self) -> Self;
    fn to_degrees(self) -> Self;
    fn is_finite(self) -> bool {
        self.value().is_finite()
    }
    fn is_nan(self) -> bool {
        self.value().is_nan()
    }
}

impl Real for f64 {
    fn value(self) -> f64 {
        self
    }
    fn abs(self) -> Self {
        f64::abs(self)
    }
    fn signum(self) -> Self {
        f64::signum(self)
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    fn cbrt(self) -> Self {
        f64::cbrt(self)
    }
    fn exp(self) -> Self {
        f64::exp(self)
    }
    fn ln(self) -> Self {
        f64::ln(self)
    }
    fn ln_1p(self) -> Self {
        f64::ln_1p(self)
    }
    fn sin(self) -> Self {
        f64::sin(self)
    }
    fn cos(self) -> Self {
        f64::cos(self)
    }
    fn tan(self) -> Self {
        f64::tan(self)
    }
    fn asin(self) -> Self {
        f64::asin(self)
    }
    fn acos(self) -> Self {
        f64::acos(self)
    }
    fn atan(self) -> Self {
        f64::atan(self)
    }
    fn atan2(self, other: Self) -> Self {
        f64::atan2(self, other)
    }
    fn sinh(self) -> Self {
        f64::sinh(self)
    }
    fn cosh(self) -> Self {
        f64::cosh(self)
    }
    fn tanh(self) -> Self {
        f64::tanh(self)
    }
    fn powi(self, n: i32) -> Self {
        f64::powi(self, n)
    }
    fn powf(self, n: Self) -> Self {
        f64::powf(self, n)
    }
    fn hypot(self, other: Self) -> Self {
        f64::hypot(self, other)
    }
    fn min(self, other: Self) -> Self {
        f64::min(self, other)
    }
    fn max(self, other: Self) -> Self {
        f64::max(self, other)
    }
    fn clamp(self, lo: Self, hi: Self) -> Self {
        f64::clamp(self, lo, hi)
    }
    fn floor(self) -> Self {
        f64::floor(self)
    }
    fn ceil(self) -> Self {
        f64::ceil(self)
    }
    fn rem_euclid(self, rhs: Self) -> Self {
        f64::rem_euclid(self, rhs)
    }
    fn to_radians(self) -> Self {
        f64::to_radians(self)
    }
    fn to_degrees(self) -> Self {
        f64::to_degrees(self)
    }
}

/// A value with one derivative beside it: `re + eps ε`, ε² = 0 (forward-mode automatic
/// differentiation along one direction). Comparisons look at the value alone.
#[derive(Clone, Copy, Debug, Default)]
pub struct Dual {
    pub re: f64,
    pub eps: f64,
}

impl Dual {
    /// A value that moves along the direction at rate `eps`.
    pub fn new(re: f64, eps: f64) -> Dual {
        Dual { re, eps }
    }

    /// `f(re) + f'(re) eps ε`, from the value and the derivative of f at re.
    fn chain(self, value: f64, derivative: f64) -> Dual {
        Dual { re: value, eps: derivative * self.eps }
    }
}

impl From<f64> for Dual {
    fn from(re: f64) -> Dual {
        Dual { re, eps: 0.0 }
    }
}

impl PartialEq for Dual {
    fn eq(&self, other: &Dual) -> bool {
        self.re == other.re
    }
}

impl PartialOrd for Dual {
    fn partial_cmp(&self, other: &Dual) -> Option<std::cmp::Ordering> {
        self.re.partial_cmp(&other.re)
    }
}

impl PartialEq<f64> for Dual {
    fn eq(&self, other: &f64) -> bool {
        self.re == *other
    }
}

impl PartialOrd<f64> for Dual {
    fn partial_cmp(&self, other: &f64) -> Option<std::cmp::Ordering> {
        self.re.partial_cmp(other)
    }
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, b: Dual) -> Dual {
        Dual { re: self.re + b.re, eps: self.eps + b.eps }
    }
}

impl Sub for Dual {
    type Output = Dual;
    fn sub(self, b: Dual) -> Dual {
        Dual { re: self.re - b.re, eps: self.eps - b.eps }
    }
}

impl Mul for Dual {
    type Output = Dual;
    fn mul(self, b: Dual) -> Dual {
        Dual { re: self.re * b.re, eps: self.eps * b.re + self.re * b.eps }
    }
}

impl Div for Dual {
    type Output = Dual;
    fn div(self, b: Dual) -> Dual {
        let re = self.re / b.re;
        Dual { re, eps: (self.eps - re * b.eps) / b.re }
    }
}

impl Neg for Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        Dual { re: -self.re, eps: -self.eps }
    }
}

impl Add<f64> for Dual {
    type Output = Dual;
    fn add(self, b: f64) -> Dual {
        Dual { re: self.re + b, eps: self.eps }
    }
}

impl Sub<f64> for Dual {
    type Output = Dual;
    fn sub(self, b: f64) -> Dual {
        Dual { re: self.re - b, eps: self.eps }
    }
}

impl Mul<f64> for Dual {
    type Output = Dual;
    fn mul(self, b: f64) -> Dual {
        Dual { re: self.re * b, eps: self.eps * b }
    }
}

impl Div<f64> for Dual {
    type Output = Dual;
    fn div(self, b: f64) -> Dual {
        Dual { re: self.re / b, eps: self.eps / b }
    }
}

macro_rules! assign_ops {
    ($($assign:ident $method:ident $op:tt),*) => {$(
        impl $assign for Dual {
            fn $method(&mut self, b: Dual) {
                *self = *self $op b;
            }
        }
        impl $assign<f64> for Dual {
            fn $method(&mut self, b: f64) {
                *self = *self $op b;
            }
        }
    )*};
}
assign_ops!(AddAssign add_assign +, SubAssign sub_assign -, MulAssign mul_assign *, DivAssign div_assign /);

impl Sum for Dual {
    fn sum<I: Iterator<Item = Dual>>(iter: I) -> Dual {
        iter.fold(Dual::from(0.0), |a, b| a + b)
    }
}

impl Real for Dual {
    fn value(self) -> f64 {
        self.re
    }
    /// At exactly 0, a kink: the mean of the one-sided derivatives, 0 (what a central
    /// difference sees there too).
    fn abs(self) -> Self {
        if self.re < 0.0 {
            -self
        } else if self.re > 0.0 {
            self
        } else {
            Dual { re: self.re.abs(), eps: 0.0 }
        }
    }
    fn signum(self) -> Self {
        Dual::from(self.re.signum())
    }
    fn sqrt(self) -> Self {
        let s = self.re.sqrt();
        self.chain(s, 0.5 / s)
    }
    fn cbrt(self) -> Self {
        let c = self.re.cbrt();
        self.chain(c, 1.0 / (3.0 * c * c))
    }
    fn exp(self) -> Self {
        let e = self.re.exp();
        self.chain(e, e)
    }
    fn ln(self) -> Self {
        self.chain(self.re.ln(), 1.0 / self.re)
    }
    fn ln_1p(self) -> Self {
        self.chain(self.re.ln_1p(), 1.0 / (1.0 + self.re))
    }
    fn sin(self) -> Self {
        self.chain(self.re.sin(), self.re.cos())
    }
    fn cos(self) -> Self {
        self.chain(self.re.cos(), -self.re.sin())
    }
    fn tan(self) -> Self {
        let t = self.re.tan();
        self.chain(t, 1.0 + t * t)
    }
    fn asin(self) -> Self {
        self.chain(self.re.asin(), 1.0 / (1.0 - self.re * self.re).sqrt())
    }
    fn acos(self) -> Self {
        self.chain(self.re.acos(), -1.0 / (1.0 - self.re * self.re).sqrt())
    }
    fn atan(self) -> Self {
        self.chain(self.re.atan(), 1.0 / (1.0 + self.re * self.re))
    }
    fn atan2(self, x: Self) -> Self {
        // d atan2(y, x) = (x dy - y dx) / (x^2 + y^2)
        let r2 = self.re * self.re + x.re * x.re;
        Dual { re: self.re.atan2(x.re), eps: (x.re * self.eps - self.re * x.eps) / r2 }
    }
    fn sinh(self) -> Self {
        self.chain(self.re.sinh(), self.re.cosh())
    }
    fn cosh(self) -> Self {
        self.chain(self.re.cosh(), self.re.sinh())
    }
    fn tanh(self) -> Self {
        let t = self.re.tanh();
        self.chain(t, 1.0 - t * t)
    }
    fn powi(self, n: i32) -> Self {
        if n == 0 {
            return Dual::from(1.0);
        }
        self.chain(self.re.powi(n), n as f64 * self.re.powi(n - 1))
    }
    fn powf(self, n: Self) -> Self {
        // d x^n = n x^(n-1) dx + x^n ln(x) dn; the second term only where n moves.
        let p = self.re.powf(n.re);
        let by_base = if self.eps == 0.0 { 0.0 } else { n.re * self.re.powf(n.re - 1.0) * self.eps };
        let by_exponent = if n.eps == 0.0 { 0.0 } else { p * self.re.ln() * n.eps };
        Dual { re: p, eps: by_base + by_exponent }
    }
    fn hypot(self, other: Self) -> Self {
        let h = self.re.hypot(other.re);
        let eps = if h == 0.0 { 0.0 } else { (self.re * self.eps + other.re * other.eps) / h };
        Dual { re: h, eps }
    }
    fn min(self, other: Self) -> Self {
        if other.re < self.re || self.re.is_nan() {
            other
        } else {
            self
        }
    }
    fn max(self, other: Self) -> Self {
        if other.re > self.re || self.re.is_nan() {
            other
        } else {
            self
        }
    }
    fn clamp(self, lo: Self, hi: Self) -> Self {
        assert!(lo.re <= hi.re, "clamp: min > max, or either was NaN. min = {:?}, max = {:?}", lo.re, hi.re);
        if self.re < lo.re {
            lo
        } else if self.re > hi.re {
            hi
        } else {
            self
        }
    }
    fn floor(self) -> Self {
        Dual::from(self.re.floor())
    }
    fn ceil(self) -> Self {
        Dual::from(self.re.ceil())
    }
    fn rem_euclid(self, rhs: Self) -> Self {
        // x - k rhs with the integer k held: derivative dx - k drhs.
        let k = (self.re - self.re.rem_euclid(rhs.re)) / rhs.re;
        Dual { re: self.re.rem_euclid(rhs.re), eps: self.eps - k.round() * rhs.eps }
    }
    fn to_radians(self) -> Self {
        Dual { re: self.re.to_radians(), eps: self.eps.to_radians() }
    }
    fn to_degrees(self) -> Self {
        Dual { re: self.re.to_degrees(), eps: self.eps.to_degrees() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The derivative of `f` at `x` by Dual, and by a sixth-order central difference (an
    /// independent computation: 7 plain f64 evaluations).
    fn both(f: impl Fn(Dual) -> Dual + Copy, g: impl Fn(f64) -> f64, x: f64) -> (f64, f64) {
        let ad = f(Dual::new(x, 1.0)).eps;
        let h = 1e-3 * (1.0 + x.abs());
        let d = |k: f64| g(x + k * h);
        let fd = (45.0 * (d(1.0) - d(-1.0)) - 9.0 * (d(2.0) - d(-2.0)) + (d(3.0) - d(-3.0))) / (60.0 * h);
        (ad, fd)
    }

    /// Equations written once over R, as a component would be.
    fn equation<R: Real>(x: R) -> R {
        let a = x * x * 3.0 - x.sin() * x.exp() + (x * 0.5).atan2(R::from(1.0) + x * x) + x.hypot(R::from(2.0));
        let b = a / (x.cosh() + 2.0) + x.powi(3) - x.abs().sqrt() * x.tanh() + (x * x + 1.0).ln() + x.powf(R::from(1.5)).cbrt();
        let c = if b > 0.0 { b.max(x) } else { b.min(x * 2.0) };
        c + x.to_radians().cos() * x.ln_1p() + (x / 7.0).asin() - (x / 9.0).acos() + x.tan() * 0.1 + x.sinh() * 0.01
    }

    #[test]
    fn dual_derivatives_agree_with_a_sixth_order_difference() {
        for &x in &[0.3, 0.7, 1.1, 1.9, 2.6] {
            let (ad, fd) = both(equation::<Dual>, equation::<f64>, x);
            // The difference's own error (h^6 f^(7), rounding 1e-16 / h): about 1e-9 here.
            assert!((ad - fd).abs() <= 1e-8 * (1.0 + fd.abs()), "x = {x}: AD {ad} against differences {fd}");
        }
    }

    #[test]
    fn dual_values_are_the_f64_values_bit_for_bit() {
        for &x in &[0.3, 0.7, 1.1, 1.9, 2.6] {
            assert_eq!(equation(Dual::new(x, 1.0)).re.to_bits(), equation(x).to_bits(), "x = {x}");
        }
    }

    #[test]
    fn branches_compare_values_and_differentiate_the_branch_taken() {
        let relu = |x: Dual| if x > 0.0 { x * 3.0 } else { x * 0.0 };
        assert_eq!(relu(Dual::new(2.0, 1.0)).eps, 3.0);
        assert_eq!(relu(Dual::new(-2.0, 1.0)).eps, 0.0);
        assert_eq!(Dual::new(-2.0, 1.0).abs().eps, -1.0);
        assert_eq!(Dual::new(0.0, 1.0).abs().eps, 0.0);
        assert_eq!(Dual::new(1.0, 1.0).clamp(Dual::from(0.0), Dual::from(0.5)).eps, 0.0);
        assert_eq!(Dual::new(2.5, 1.0).floor().eps, 0.0);
        assert_eq!(Dual::new(7.0, 1.0).rem_euclid(Dual::new(3.0, 1.0)), 1.0);
        assert_eq!(Dual::new(7.0, 1.0).rem_euclid(Dual::new(3.0, 1.0)).eps, 1.0 - 2.0);
    }
}
