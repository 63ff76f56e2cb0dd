//! Which knowns each unknown depends on, from one evaluation of the equations: [`Trace`], a
//! [`Real`] that carries the set of knowns its value was computed from (docs/DESIGN.md, "Exact
//! derivatives").
//!
//! Seed each known with its own index ([`Trace::known`]), evaluate the equations once over
//! `Trace`, and each unknown's set ([`Tracing::dependencies`]) is the knowns its value flowed
//! from, at that point: the branch the equations took there, as with [`crate::real::Dual`]. A
//! known that only decides a branch (`if w > 0.0 { a } else { b }`, a relay) moves no value
//! through arithmetic; [`Tracing::compared`] lists every known that reached a comparison, for
//! the caller to probe by value. The cost is that of the equations times the size of the sets
//! they build: linear in the model's size for a sparse model.
//!
//! A `Trace` is a value and an index into the sets of the [`Tracing`] session it was made in;
//! the sets live in a thread-local store for the session's duration (a `Real` must be `Copy`),
//! so a `Trace` must not outlive its session (using one afterwards panics or reads another
//! session's sets: the store checks the session's number).

use std::cell::RefCell;
use std::cmp::Ordering;
use std::iter::Sum;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use crate::real::Real;

/// A value and the knowns it depends on.
#[derive(Clone, Copy, Debug, Default)]
pub struct Trace {
    value: f64,
    /// The set's position in the session's store; 0 is the empty set.
    set: u32,
    /// The session that made it (0: a constant, valid in any session).
    session: u32,
}

/// The store of one session's sets: set i is `items[starts[i]..starts[i + 1]]`, sorted.
struct Store {
    session: u32,
    active: bool,
    starts: Vec<usize>,
    items: Vec<u32>,
    compared: Vec<u32>,
}

thread_local! {
    static STORE: RefCell<Store> = const { RefCell::new(Store { session: 0, active: false, starts: Vec::new(), items: Vec::new(), compared: Vec::new() }) };
}

impl Store {
    fn set(&self, i: u32) -> &[u32] {
        &self.items[self.starts[i as usize]..self.starts[i as usize + 1]]
    }

    fn push(&mut self, items: impl IntoIterator<Item = u32>) -> u32 {
        self.items.extend(items);
        self.starts.push(self.items.len());
        (self.starts.len() - 2) as u32
    }

    fn check(&self, t: &Trace) {
        assert!(t.session == 0 || (self.active && t.session == self.session), "a Trace was used outside the Tracing session that made it");
    }

    /// The union of two sets, as a set of the store (one of them where it holds the other).
    fn union(&mut self, a: u32, b: u32) -> u32 {
        if a == b || b == 0 {
            return a;
        }
        if a == 0 {
            return b;
        }
        let (x, y) = (self.set(a), self.set(b));
        let mut merged = Vec::with_capacity(x.len() + y.len());
        let (mut i, mut j) = (0, 0);
        while i < x.len() || j < y.len() {
            let next = match (x.get(i), y.get(j)) {
                (Some(&p), Some(&q)) if p == q => {
                    i += 1;
                    j += 1;
                    p
                }
                (Some(&p), Some(&q)) if p < q => {
                    i += 1;
                    p
                }
                (Some(&p), None) => {
                    i += 1;
                    p
                }
                (_, Some(&q)) => {
                    j += 1;
                    q
                }
                (None, None) => unreachable!(),
            };
            merged.push(next);
        }
        if merged.len() == x.len() {
            return a;
        }
        if merged.len() == y.len() {
            return b;
        }
        self.push(merged)
    }
}

/// One session of tracing: its knowns, and afterwards the sets of the unknowns.
pub struct Tracing {
    session: u32,
}

impl Tracing {
    /// Starts a session on this thread (ending any earlier one).
    pub fn start() -> Tracing {
        STORE.with(|s| {
            let mut s = s.borrow_mut();
            s.session = s.session.wrapping_add(1).max(1);
            s.active = true;
            s.starts.clear();
            s.items.clear();
            s.compared.clear();
            s.starts.extend([0, 0]); // set 0: empty
            Tracing { session: s.session }
        })
    }

    /// A known at `value`, depending on itself: known number `index` of the caller's numbering.
    pub fn known(&self, index: u32, value: f64) -> Trace {
        STORE.with(|s| {
            let set = s.borrow_mut().push([index]);
            Trace { value, set, session: self.session }
        })
    }

    /// The knowns `t` depends on, ascending.
    pub fn dependencies(&self, t: Trace) -> Vec<u32> {
        STORE.with(|s| {
            let s = s.borrow();
            s.check(&t);
            s.set(t.set).to_vec()
        })
    }

    /// Every known that reached a comparison (`<`, `>`, `min`, `abs`, ...) or left the trace
    /// through `Real::value` since the start:
    /// the knowns that may decide a branch of the equations. Ascending, without repeats.
    pub fn compared(&self) -> Vec<u32> {
        STORE.with(|s| {
            let mut c = s.borrow().compared.clone();
            c.sort_unstable();
            c.dedup();
            c
        })
    }
}

impl Drop for Tracing {
    fn drop(&mut self) {
        STORE.with(|s| {
            let mut s = s.borrow_mut();
            if s.session == self.session {
                s.active = false;
                s.starts = Vec::new();
                s.items = Vec::new();
                s.compared = Vec::new();
            }
        })
    }
}

impl Trace {
    /// The value, without its set.
    pub fn value(self) -> f64 {
        self.value
    }

    fn with(value: f64, set: u32, session: u32) -> Trace {
        Trace { value, set, session }
    }

    /// The result of an operation on `self` and `b`: their union's set.
    fn join(self, b: Trace, value: f64) -> Trace {
        if b.set == 0 {
            return Trace::with(value, self.set, self.session);
        }
        if self.set == 0 {
            return Trace::with(value, b.set, b.session);
        }
        STORE.with(|s| {
            let mut s = s.borrow_mut();
            s.check(&self);
            s.check(&b);
            let set = s.union(self.set, b.set);
            Trace::with(value, set, s.session)
        })
    }

    /// Notes that `self` (and `b`) reached a comparison.
    fn note_compared(self, b: Option<Trace>) {
        for t in [Some(self), b].into_iter().flatten() {
            if t.set != 0 {
                STORE.with(|s| {
                    let mut s = s.borrow_mut();
                    s.check(&t);
                    let set = s.set(t.set).to_vec();
                    s.compared.extend(set);
                });
            }
        }
    }

    /// A unary function of the value: the same set.
    fn map(self, value: f64) -> Trace {
        Trace::with(value, self.set, self.session)
    }
}

impl From<f64> for Trace {
    fn from(value: f64) -> Trace {
        Trace { value, set: 0, session: 0 }
    }
}

impl PartialEq for Trace {
    fn eq(&self, other: &Trace) -> bool {
        self.note_compared(Some(*other));
        self.value == other.value
    }
}

impl PartialOrd for Trace {
    fn partial_cmp(&self, other: &Trace) -> Option<Ordering> {
        self.note_compared(Some(*other));
        self.value.partial_cmp(&other.value)
    }
}

impl PartialEq<f64> for Trace {
    fn eq(&self, other: &f64) -> bool {
        self.note_compared(None);
        self.value == *other
    }
}

impl PartialOrd<f64> for Trace {
    fn partial_cmp(&self, other: &f64) -> Option<Ordering> {
        self.note_compared(None);
        self.value.partial_cmp(other)
    }
}

macro_rules! binary_ops {
    ($($trait:ident $method:ident $assign:ident $assign_method:ident $op:tt),*) => {$(
        impl $trait for Trace {
            type Output = Trace;
            fn $method(self, b: Trace) -> Trace {
                self.join(b, self.value $op b.value)
            }
        }
        impl $trait<f64> for Trace {
            type Output = Trace;
            fn $method(self, b: f64) -> Trace {
                self.map(self.value $op b)
            }
        }
        impl $assign for Trace {
            fn $assign_method(&mut self, b: Trace) {
                *self = *self $op b;
            }
        }
        impl $assign<f64> for Trace {
            fn $assign_method(&mut self, b: f64) {
                *self = *self $op b;
            }
        }
    )*};
}
binary_ops!(Add add AddAssign add_assign +, Sub sub SubAssign sub_assign -, Mul mul MulAssign mul_assign *, Div div DivAssign div_assign /);

impl Neg for Trace {
    type Output = Trace;
    fn neg(self) -> Trace {
        self.map(-self.value)
    }
}

impl Sum for Trace {
    fn sum<I: Iterator<Item = Trace>>(iter: I) -> Trace {
        iter.fold(Trace::from(0.0), |a, b| a + b)
    }
}

impl Real for Trace {
    /// The value, leaving the trace: what the equations compute from it (`if t >= t_step.value()`,
    /// a root found over f64) is not traced, so its knowns count as compared.
    fn value(self) -> f64 {
        self.note_compared(None);
        self.value
    }
    fn is_finite(self) -> bool {
        self.note_compared(None);
        self.value.is_finite()
    }
    fn is_nan(self) -> bool {
        self.note_compared(None);
        self.value.is_nan()
    }
    fn abs(self) -> Self {
        self.note_compared(None);
        self.map(self.value.abs())
    }
    fn signum(self) -> Self {
        self.note_compared(None);
        Trace::from(self.value.signum())
    }
    fn sqrt(self) -> Self {
        self.map(self.value.sqrt())
    }
    fn cbrt(self) -> Self {
        self.map(self.value.cbrt())
    }
    fn exp(self) -> Self {
        self.map(self.value.exp())
    }
    fn ln(self) -> Self {
        self.map(self.value.ln())
    }
    fn ln_1p(self) -> Self {
        self.map(self.value.ln_1p())
    }
    fn sin(self) -> Self {
        self.map(self.value.sin())
    }
    fn cos(self) -> Self {
        self.map(self.value.cos())
    }
    fn tan(self) -> Self {
        self.map(self.value.tan())
    }
    fn asin(self) -> Self {
        self.map(self.value.asin())
    }
    fn acos(self) -> Self {
        self.map(self.value.acos())
    }
    fn atan(self) -> Self {
        self.map(self.value.atan())
    }
    fn atan2(self, other: Self) -> Self {
        self.join(other, self.value.atan2(other.value))
    }
    fn sinh(self) -> Self {
        self.map(self.value.sinh())
    }
    fn cosh(self) -> Self {
        self.map(self.value.cosh())
    }
    fn tanh(self) -> Self {
        self.map(self.value.tanh())
    }
    fn powi(self, n: i32) -> Self {
        if n == 0 {
            return Trace::from(1.0);
        }
        self.map(self.value.powi(n))
    }
    fn powf(self, n: Self) -> Self {
        self.join(n, self.value.powf(n.value))
    }
    fn hypot(self, other: Self) -> Self {
        self.join(other, self.value.hypot(other.value))
    }
    fn min(self, other: Self) -> Self {
        self.note_compared(Some(other));
        if other.value < self.value || self.value.is_nan() {
            other
        } else {
            self
        }
    }
    fn max(self, other: Self) -> Self {
        self.note_compared(Some(other));
        if other.value > self.value || self.value.is_nan() {
            other
        } else {
            self
        }
    }
    fn clamp(self, lo: Self, hi: Self) -> Self {
        self.max(lo).min(hi)
    }
    fn floor(self) -> Self {
        self.note_compared(None);
        Trace::from(self.value.floor())
    }
    fn ceil(self) -> Self {
        self.note_compared(None);
        Trace::from(self.value.ceil())
    }
    fn rem_euclid(self, rhs: Self) -> Self {
        self.note_compared(Some(rhs));
        self.join(rhs, self.value.rem_euclid(rhs.value))
    }
    fn to_radians(self) -> Self {
        self.map(self.value.to_radians())
    }
    fn to_degrees(self) -> Self {
        self.map(self.value.to_degrees())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chain_link<R: Real>(w_prev: R, w: R, w_next: R, twist: R) -> R {
        (twist * 1e4 + (w - w_next) * 2.0) - (w_prev - w) * 0.5
    }

    #[test]
    fn a_value_depends_on_the_knowns_it_was_computed_from() {
        let tracing = Tracing::start();
        let k: Vec<Trace> = (0..6).map(|i| tracing.known(i, 1.0 + i as f64)).collect();
        let y = chain_link(k[1], k[2], k[3], k[5]);
        assert_eq!(tracing.dependencies(y), vec![1, 2, 3, 5]);
        assert_eq!(y.value(), chain_link(2.0, 3.0, 4.0, 6.0));
        // A constant and an operation with constants add nothing.
        assert_eq!(tracing.dependencies((k[4] * 2.0 + 1.0).sin() + Trace::from(3.0)), vec![4]);
        assert!(tracing.dependencies(Trace::from(3.0)).is_empty());
        // The branch taken: the other known only decides it.
        let relay = if k[0] > k[1] { k[2] } else { k[3] };
        assert_eq!(tracing.dependencies(relay), vec![3]);
        assert_eq!(tracing.compared(), vec![0, 1]);
    }

    #[test]
    fn a_long_chain_costs_sets_of_its_own_width() {
        let tracing = Tracing::start();
        let n = 10_000u32;
        let w: Vec<Trace> = (0..n).map(|i| tracing.known(i, i as f64)).collect();
        for i in 1..n as usize - 1 {
            let d = tracing.dependencies(chain_link(w[i - 1], w[i], w[i + 1], w[i]));
            assert_eq!(d, vec![i as u32 - 1, i as u32, i as u32 + 1]);
        }
    }

    #[test]
    #[should_panic(expected = "outside the Tracing session")]
    fn a_trace_from_an_ended_session_is_refused() {
        let stale = {
            let tracing = Tracing::start();
            (tracing.known(0, 1.0), tracing.known(1, 2.0))
        };
        let _tracing = Tracing::start();
        let _ = stale.0 + stale.1;
    }
}
