//! The little complex arithmetic an equivalent circuit needs (phasors).

use fmu_runtime::real::Real;
use std::ops::{Add, Div, Mul, Sub};

/// A complex number over any real scalar (`f64` by default).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Complex<R = f64> {
    pub re: R,
    pub im: R,
}

impl<R: Real> Complex<R> {
    pub const fn new(re: R, im: R) -> Self {
        Complex { re, im }
    }

    pub fn norm_sqr(self) -> R {
        self.re * self.re + self.im * self.im
    }

    pub fn abs(self) -> R {
        self.re.hypot(self.im)
    }

    pub fn conj(self) -> Self {
        Complex::new(self.re, -self.im)
    }

    /// Two impedances in parallel.
    pub fn parallel(self, other: Complex<R>) -> Complex<R> {
        self * other / (self + other)
    }
}

impl<R: Real> Add for Complex<R> {
    type Output = Complex<R>;
    fn add(self, o: Complex<R>) -> Complex<R> {
        Complex::new(self.re + o.re, self.im + o.im)
    }
}

impl<R: Real> Sub for Complex<R> {
    type Output = Complex<R>;
    fn sub(self, o: Complex<R>) -> Complex<R> {
        Complex::new(self.re - o.re, self.im - o.im)
    }
}

impl<R: Real> Mul for Complex<R> {
    type Output = Complex<R>;
    fn mul(self, o: Complex<R>) -> Complex<R> {
        Complex::new(self.re * o.re - self.im * o.im, self.re * o.im + self.im * o.re)
    }
}

impl<R: Real> Div for Complex<R> {
    type Output = Complex<R>;
    fn div(self, o: Complex<R>) -> Complex<R> {
        let d = o.norm_sqr();
        Complex::new((self.re * o.re + self.im * o.im) / d, (self.im * o.re - self.re * o.im) / d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn division_inverts_multiplication() {
        let (a, b) = (Complex::new(1.5, -2.0), Complex::new(0.3, 4.0));
        let c = a * b / b;
        assert!((c - a).abs() < 1e-15);
        assert!((Complex::new(2.0, 0.0).parallel(Complex::new(2.0, 0.0)).re - 1.0).abs() < 1e-15);
    }
}
