//! The implicit method, for stiff models: an ESDIRK (explicit first stage, one diagonal gamma,
//! stiffly accurate, L-stable; [`Tableau`]), Kennedy and Carpenter's ESDIRK5(4)7L\[2\]SA\_2
//! ([`Tableau::esdirk547`]: seven stages, six of them implicit, fifth order with an embedded
//! fourth-order error estimate), stepped by our own loop with a simplified Newton iteration whose
//! Jacobian and factorization are kept from step to step and from one advance to the next while
//! Newton converges ([`jacobian`]: dense for small models, a band LU or faer's sparse LU for large
//! ones).
//! Until issue 25's second part it was ESDIRK3(2) (the four stages of diffsol's `esdirk34` with
//! an error estimate of our own, `Tableau::esdirk32`, now only in the tests): on the stiff
//! torsional chain at the default tolerance the fifth-order method takes about 1.7 steps per
//! 1 ms doStep at N = 1 000 where ESDIRK3(2) took 11, costs about 0.3 of its time, and its error
//! is about 10 times smaller (BENCHMARKS.md); it was nowhere measured worse (N = 3 to 1 000,
//! rtol 1e-8 and 1e-6).
//!
//! Each stage z_i = y + h sum_j a_ij k_j + h gamma k_i, k_i = f(t + c_i h, z_i) is solved with
//! the Newton matrix I - h' gamma J, J evaluated at some earlier point and h' the step size it
//! was factorized for: it is factorized again when h gamma leaves [1 / 1.05, 1.05] times that
//! one (the step-size controller changes the step by 7 % or more, so a matrix follows each of
//! its changes; a matrix for another h gamma costs Newton a second iteration per stage), and J
//! evaluated again only when Newton fails to converge with a J not evaluated at the
//! step's start (then, with a fresh one, the step is cut). Newton starts from the last step's
//! cubic Hermite interpolant extrapolated to the stage's time, and stops when its predicted
//! remaining error (from its contraction, no better than a matrix made for another h gamma
//! allows) is below 3 % of the tolerance. The error estimate h sum d_j k_j is filtered through
//! the same matrix, (I - h gamma J)^-1 (Shampine's filter), and measured in diffsol's norm (root
//! mean square over atol + rtol max(|y|, |y_new|)).
//!
//! It looks ahead as the explicit method does ([`crate::integrate`]): while no known moves, it
//! steps past the communication point with its own step size (up to the next time event or the
//! stop time, the steps before which are made equal so that the Newton matrix need not change
//! for a last short step), interpolates there on its dense output, and the next advance
//! continues its last step (and Newton's contraction estimate). An advance that cannot continue
//! starts afresh from (t, x, f(t, x)) with the step size reached. The Jacobian and its factors
//! carry over either way; an FMU state carries the last step ([`StepRecord`]: its ends and
//! stages) and the point the Jacobian was made at with the contraction estimate
//! ([`JacobianPoint`]), from which a restored instance makes them again and continues bit for
//! bit. A kept Jacobian is dropped when the solver's parameter vector (the knowns) changes.
//! Stopping at every communication point made the stiff chain (N = 1 000, 1 ms doSteps) take a
//! step per doStep long after its transient: 750 steps from 0.25 s to 1 s, where looking ahead
//! takes 279 (of 0.8 to 10 ms; `examples/stiff_chain.rs`, BENCHMARKS.md).
//!
//! Its dense output (at the communication points and for the event indicators' zero
//! crossings) is of order 4, as its error estimate, and bounded on stiff components
//! ([`Tableau::dense_weights`]); until issue 25's last part it was the cubic Hermite
//! interpolant of the step's ends and their derivatives.

use std::sync::Arc;

use super::esdirk::{self, Tableau};
use crate::rk::{combine_baseline as combine, same_bits, sum_of_squares, Zeros};
use super::jacobian::{self, Factors, Structure, StructureKey, Work};
use super::{JacobianPoint, Method, Ode, Outcome, Registration, Setup, Stepper};
use crate::rk::StepRecord;

/// [`Solver::ImplicitRungeKutta`](crate::model::Solver::ImplicitRungeKutta).
pub static ESDIRK: Registration = Registration {
    description: "singly diagonally implicit Runge-Kutta ESDIRK5(4)7L[2]SA_2 (Kennedy and Carpenter 2019: fifth order, L-stable, \
                  stiffly accurate, an embedded fourth-order error estimate; Newton iteration with a kept exact Jacobian (dual numbers, \
                  by colors), dense, band or sparse LU)",
    make: |s| Box::new(Esdirk::new(s)),
};

/// Newton iterations per stage before it counts as not converging.
const MAX_NEWTON: usize = 7;
/// Newton has converged when its predicted remaining error is below this fraction of the
/// tolerance (the error norm's unit).
const NEWTON_TOLERANCE: f64 = 0.03;
/// The Newton matrix is kept while h gamma stays within this factor of the one it was made for:
/// the small adjustments that reach a limit exactly. Every change the controller makes is larger
/// ([`KEEP_BELOW`], [`SHRINK_TO_MIDDLE`]), so the matrix follows it.
///
/// Until issue 25's last part it was 1.15 and an accepted step shrank by the controller's own
/// factor (0.9 to 1): on the stiff chain the error estimate creeps up while a wave travels along
/// it, and the step size shrank by a fraction of a percent at a time, each such step within the
/// matrix's band. Newton cannot stop after one iteration against a matrix made for another
/// h gamma (its contraction on a stiff component is |1 - h gamma / h' gamma|): at N = 10 000,
/// from 0.15 s to 0.45 s, 5 874 of 6 396 stages took two iterations or more, with three
/// factorizations (`examples/stiff_chain.rs` with counters added for the measurement). Measured
/// over 1 s at N = 10 000 with [`SHRINK_TO_MIDDLE`]: 19 661 Newton iterations and 72
/// factorizations before, 13 224 and 96 after (2 070 and 2 109 steps); at N = 1 000 7 845 and 85
/// before, 7 077 and 113 after. Ratios of 1.02 to 1.08 gave the same within 2 %.
const REFACTOR_RATIO: f64 = 1.05;
/// Step-size factors: at most 5 times larger, 5 times smaller after a rejection; a factor in
/// [1, KEEP_BELOW) keeps the step size (and so the Newton matrix); safety 0.9.
const MAX_FACTOR: f64 = 5.0;
const MIN_FACTOR: f64 = 0.2;
const KEEP_BELOW: f64 = 1.15;
const SAFETY: f64 = 0.9;
/// An accepted step whose error asks for a smaller step (a factor below 1) shrinks it by this
/// much more, so that the next step's predicted factor, 1 / SHRINK_TO_MIDDLE, lies in the middle
/// (geometric) of [1, KEEP_BELOW) where the step size is kept: the step size then stays put for
/// a while and the matrix made for it serves many steps, where shrinking by the factor alone left
/// the next step at the edge of shrinking again.
const SHRINK_TO_MIDDLE: f64 = 0.932_5;
/// A step's size is cut to this after Newton failed with a Jacobian evaluated at its start.
const NEWTON_FAILURE_FACTOR: f64 = 0.25;
const MAX_REJECTIONS: usize = 40;
/// Within this many steps of a limit (a time event, the stop time) the steps are made equal so
/// as to reach it exactly. Equal steps to every limit, whatever its distance, stretched each
/// step by up to 10 % (while the controller shrank it by its safety factor): the step size
/// changed at every step after the stiff chain's torque step, each change within
/// [`REFACTOR_RATIO`] costing Newton iterations against a matrix made for another h gamma
/// (issue 25, measured with `examples/stiff_chain.rs`: 7 845 iterations against 8 043).
const EQUAL_STEPS_TO_LIMIT: f64 = 3.0;
const MIN_STEP: f64 = 1e-13;


/// The tableau, made once per process.
fn tableau() -> &'static Tableau {
    static MADE: std::sync::OnceLock<Tableau> = std::sync::OnceLock::new();
    MADE.get_or_init(Tableau::esdirk547)
}

/// Per instance: the Jacobian and its factors (kept between advances), the step size, the
/// current point and last step, and the work vectors (sized once).
struct Esdirk {
    n: usize,
    k: &'static Tableau,
    rtol: f64,
    atol: Vec<f64>,
    key: StructureKey,
    /// Made at the first Jacobian.
    structure: Option<Arc<Structure>>,
    jac: Vec<f64>,
    factors: Option<Factors>,
    jac_work: Work,
    /// Where `jac` was evaluated (its `h_gamma`: that of `factors`, NaN before they are made);
    /// None: no Jacobian.
    jac_point: Option<JacobianPoint>,
    /// A restored state's Jacobian point, made again at the next start.
    pending: Option<JacobianPoint>,
    /// The Jacobian was evaluated at the current step's start (a Newton failure then cuts the step).
    fresh: bool,
    /// Newton's estimate of its contraction, carried from stage to stage (reset at each start).
    eta: f64,
    /// The size of the next step.
    h: f64,
    /// The last step [t_start, t_end] (t_start = t_end before the first since a start) with its
    /// ends and their derivatives; the next step starts at (t_end, y_end, f_end).
    t_start: f64,
    t_end: f64,
    y_start: Vec<f64>,
    y_end: Vec<f64>,
    f_start: Vec<f64>,
    f_end: Vec<f64>,
    has_step: bool,
    /// Work: the stages' derivatives (stage i at [i n, (i + 1) n)), a stage's explicit part and
    /// value, a residual, the error estimate, f, Newton's weights.
    stages: Vec<f64>,
    psi: Vec<f64>,
    z: Vec<f64>,
    r: Vec<f64>,
    err: Vec<f64>,
    f: Vec<f64>,
    weights: Vec<f64>,
}

impl Esdirk {
    fn new(s: &Setup) -> Self {
        let n = s.n_states;
        let v = || vec![0.0; n];
        Esdirk {
            n,
            k: tableau(),
            rtol: s.rtol,
            atol: s.atol.to_vec(),
            key: s.structure.clone(),
            structure: None,
            jac: Vec::new(),
            factors: None,
            jac_work: Work::default(),
            jac_point: None,
            pending: None,
            fresh: false,
            eta: 1.0,
            h: 0.0,
            t_start: 0.0,
            t_end: 0.0,
            y_start: v(),
            y_end: v(),
            f_start: v(),
            f_end: v(),
            has_step: false,
            stages: vec![0.0; tableau().stages * n],
            psi: v(),
            z: v(),
            r: v(),
            err: v(),
            f: v(),
            weights: v(),
        }
    }

    /// Evaluates the Jacobian at (t, y) with the advance's parameters (its structure made on
    /// the first call); the factors are stale until [`factor`](Self::factor).
    fn evaluate_jacobian(&mut self, ode: &Ode, t: f64, y: &[f64]) -> Result<(), String> {
        if self.structure.is_none() {
            let s = jacobian::structure(&self.key, || ode.exact.columns(y, ode.p, t))?;
            self.jac = vec![0.0; s.nnz()];
            self.factors = Some(Factors::new(&s));
            self.structure = Some(s);
        }
        let s = self.structure.as_ref().expect("made above");
        let rhs = |x: &[crate::real::Dual], t: f64, dx: &mut [crate::real::Dual]| ode.exact.dual(x, ode.p, t, dx);
        jacobian::evaluate(s, &rhs, t, y, &mut self.jac, &mut self.jac_work);
        match &mut self.jac_point {
            Some(p) => {
                p.t = t;
                p.x.clear();
                p.x.extend_from_slice(y);
                p.parameters.clear();
                p.parameters.extend_from_slice(ode.p);
                p.h_gamma = f64::NAN;
            }
            None => self.jac_point = Some(JacobianPoint { t, x: y.to_vec(), parameters: ode.p.to_vec(), h_gamma: f64::NAN, contraction: 1.0 }),
        }
        Ok(())
    }

    /// Makes a restored state's Jacobian and Newton matrix again, and takes its contraction
    /// estimate, when the knowns are those it was saved with; drops a kept Jacobian made with
    /// other knowns.
    fn restore_pending(&mut self, ode: &Ode) -> Result<(), String> {
        if let Some(p) = self.pending.take() {
            if same_bits(&p.parameters, ode.p) && p.h_gamma.is_finite() {
                self.evaluate_jacobian(ode, p.t, &p.x)?;
                self.factor(p.h_gamma)?;
                self.eta = p.contraction;
            } else {
                self.jac_point = None;
            }
        } else if self.jac_point.as_ref().is_some_and(|p| !same_bits(&p.parameters, ode.p)) {
            self.jac_point = None;
        }
        Ok(())
    }

    /// Factorizes I - `hg` J.
    fn factor(&mut self, hg: f64) -> Result<(), String> {
        let (Some(s), Some(f), Some(p)) = (self.structure.as_ref(), self.factors.as_mut(), self.jac_point.as_mut()) else {
            return Err("no Jacobian to factorize".into());
        };
        p.h_gamma = f64::NAN;
        f.factor(s, &self.jac, hg)?;
        p.h_gamma = hg;
        Ok(())
    }

    /// Whether the factors are those of I - h' gamma J with h' gamma within
    /// [`REFACTOR_RATIO`] of `hg`.
    fn factors_fit(&self, hg: f64) -> bool {
        self.jac_point.as_ref().is_some_and(|p| {
            let ratio = hg / p.h_gamma;
            ratio <= REFACTOR_RATIO && ratio >= 1.0 / REFACTOR_RATIO
        })
    }

    /// Solves the stages of a step of size `h` from (t_end, y_end, f_end) to `t_new` (its last
    /// stage's time, exactly); Err(()) when Newton does not converge. On success `z` holds the
    /// new state.
    fn stages(&mut self, ode: &Ode, h: f64, t_new: f64) -> Result<(), ()> {
        let n = self.n;
        let (t, hg) = (self.t_end, h * self.k.gamma);
        self.stages[..n].copy_from_slice(&self.f_end);
        let last = self.k.stages - 1;
        // The contraction measured in earlier steps, made less optimistic once per step (as
        // Hairer and Wanner's RADAU5 does once per step of all its stages: theta^0.8).
        self.eta = self.eta.max(f64::EPSILON).powf(0.8);
        for i in 1..=last {
            // psi = y + h sum_{j < i} a_ij k_j, in one pass (`rk::combine`: the same bits as one
            // stage at a time)
            let mut w = [0.0; esdirk::MAX_STAGES];
            for (wj, a) in w.iter_mut().zip(&self.k.a[i][..i]) {
                *wj = h * a;
            }
            combine(&mut self.psi, Some(&self.y_end), &w[..i], &self.stages[..i * n], Zeros::Skipped);
            let ti = if i == last { t_new } else { t + self.k.c[i] * h };
            if self.has_step {
                // Start from the last step's interpolant, extrapolated.
                hermite(self.t_start, self.t_end, &self.y_start, &self.y_end, &self.f_start, &self.f_end, ti, &mut self.z);
            } else {
                // Start from k_i = k_{i-1}.
                for ((z, p), k) in self.z.iter_mut().zip(&self.psi).zip(&self.stages[(i - 1) * n..i * n]) {
                    *z = p + hg * k;
                }
            }
            self.newton(ode, ti, hg)?;
            let inv = 1.0 / hg;
            for ((k, z), p) in self.stages[i * n..(i + 1) * n].iter_mut().zip(&self.z).zip(&self.psi) {
                *k = (z - p) * inv;
            }
        }
        Ok(())
    }

    /// Solves z = psi + hg f(ti, z) from the guess in `z` (simplified Newton with the kept
    /// factors), to NEWTON_TOLERANCE of the error norm.
    fn newton(&mut self, ode: &Ode, ti: f64, hg: f64) -> Result<(), ()> {
        let (s, factors) = match (self.structure.as_ref(), self.factors.as_mut()) {
            (Some(s), Some(f)) => (s, f),
            _ => return Err(()),
        };
        // The contraction expected from the last stages (made less optimistic once per step,
        // [`Esdirk::stages`]), but no better than a matrix made for another h gamma allows
        // (|1 - hg / hg'| on a stiff linear component).
        let mismatch = self.jac_point.as_ref().map_or(1.0, |p| (1.0 - hg / p.h_gamma).abs());
        let mut eta = self.eta.max(mismatch / (1.0 - mismatch).max(f64::EPSILON));
        let mut previous = f64::NAN;
        for m in 0..MAX_NEWTON {
            ode.rhs(&self.z, ti, &mut self.f);
            for (((r, p), f), z) in self.r.iter_mut().zip(&self.psi).zip(&self.f).zip(&self.z) {
                *r = p + hg * f - z;
            }
            factors.solve(s, &mut self.r);
            for (z, d) in self.z.iter_mut().zip(&self.r) {
                *z += d;
            }
            let norm = (sum_of_squares(&self.r, |m, d| d * self.weights[m]) / self.n as f64).sqrt();
            if !norm.is_finite() {
                return Err(());
            }
            if m > 0 {
                let theta = norm / previous;
                if theta >= 1.0 {
                    return Err(());
                }
                eta = theta / (1.0 - theta);
                // Would not converge within the iterations left.
                if theta.powi((MAX_NEWTON - 1 - m) as i32) * eta * norm > NEWTON_TOLERANCE {
                    return Err(());
                }
            }
            if eta * norm <= NEWTON_TOLERANCE || norm == 0.0 {
                self.eta = eta;
                return Ok(());
            }
            previous = norm;
        }
        Err(())
    }

    /// The filtered error estimate's norm of the step of size `h` in `stages`, new state in `z`.
    fn error_norm(&mut self, h: f64) -> f64 {
        let n = self.n;
        let mut w = [0.0; esdirk::MAX_STAGES];
        for (wj, d) in w.iter_mut().zip(&self.k.d[..self.k.stages]) {
            *wj = h * d;
        }
        combine(&mut self.err, None, &w[..self.k.stages], &self.stages[..self.k.stages * n], Zeros::Added);
        if let (Some(s), Some(f)) = (self.structure.as_ref(), self.factors.as_mut()) {
            f.solve(s, &mut self.err);
        }
        let sum = sum_of_squares(&self.err, |m, e| e / (self.atol[m] + self.rtol * self.y_end[m].abs().max(self.z[m].abs())));
        (sum / n as f64).sqrt()
    }

    /// One accepted step from (t_end, y_end), ending at `limit` at the latest (exactly at it
    /// when it reaches it).
    fn step(&mut self, ode: &Ode, limit: f64) -> Result<(), String> {
        let t = self.t_end;
        let remaining = limit - t;
        if !(remaining > 0.0) {
            return Err(format!("no step possible at t = {t} s (limit {limit} s)"));
        }
        // Newton's weights: the error norm's, at the step's start.
        for m in 0..self.n {
            self.weights[m] = 1.0 / (self.atol[m] + self.rtol * self.y_end[m].abs());
        }
        let mut h = self.h;
        let mut rejections = 0;
        loop {
            // A step within 10 % of the limit ends at it; within EQUAL_STEPS_TO_LIMIT steps of
            // it, the first attempt is one of equal steps (each at most 10 % longer than h) that
            // reach it. Further away the step size is the controller's, which stays the same
            // while it would grow by less than KEEP_BELOW (so the Newton matrix stays too).
            let reaches = h * 1.1 >= remaining;
            if reaches {
                h = remaining;
            } else if rejections == 0 && remaining.is_finite() {
                let count = (remaining / (1.1 * h)).ceil();
                if count <= EQUAL_STEPS_TO_LIMIT {
                    h = remaining / count;
                }
            }
            let t_new = if reaches { limit } else { t + h };
            if h < MIN_STEP || t_new <= t {
                return Err(format!("the step size fell to {h:e} s at t = {t} s"));
            }
            if self.jac_point.is_none() {
                let y = std::mem::take(&mut self.y_end);
                let made = self.evaluate_jacobian(ode, t, &y);
                self.y_end = y;
                made?;
                self.fresh = true;
            }
            let hg = h * self.k.gamma;
            let mut solved = self.factors_fit(hg) || self.factor(hg).is_ok();
            if solved {
                solved = self.stages(ode, h, t_new).is_ok();
            }
            if !solved {
                if !self.fresh {
                    // A Jacobian of an earlier point: evaluate it here and try again.
                    let y = std::mem::take(&mut self.y_end);
                    let made = self.evaluate_jacobian(ode, t, &y);
                    self.y_end = y;
                    made?;
                    self.fresh = true;
                    continue;
                }
                h *= NEWTON_FAILURE_FACTOR;
                rejections += 1;
                if rejections >= MAX_REJECTIONS {
                    return Err(format!("Newton's iteration did not converge at t = {t} s ({rejections} attempts, down to step size {h:e} s)"));
                }
                continue;
            }
            let norm = self.error_norm(h);
            let factor = if norm.is_finite() { SAFETY * norm.powf(-1.0 / (self.k.embedded_order + 1) as f64) } else { MIN_FACTOR };
            if norm <= 1.0 {
                let factor = factor.min(MAX_FACTOR);
                let factor = match factor {
                    f if f < 1.0 => f * SHRINK_TO_MIDDLE,
                    f if f < KEEP_BELOW => 1.0,
                    f => f,
                };
                self.accept(t, t_new);
                self.h = h * factor;
                return Ok(());
            }
            h *= factor.clamp(MIN_FACTOR, 1.0);
            rejections += 1;
            if rejections >= MAX_REJECTIONS {
                return Err(format!("{rejections} rejected step attempts at t = {t} s (step size {h:e} s)"));
            }
        }
    }

    /// Makes the solved step [t, t_new] (new state in `z`, stages in `stages`) the last one.
    fn accept(&mut self, t: f64, t_new: f64) {
        let n = self.n;
        std::mem::swap(&mut self.y_start, &mut self.y_end);
        self.y_end.copy_from_slice(&self.z);
        std::mem::swap(&mut self.f_start, &mut self.f_end);
        self.f_end.copy_from_slice(&self.stages[(self.k.stages - 1) * n..]);
        self.t_start = t;
        self.t_end = t_new;
        self.has_step = true;
        self.fresh = false;
    }
}

impl Method for Esdirk {
    fn integrates_activities(&self) -> bool {
        false
    }

    fn with_stepper(&mut self, ode: Ode<'_>, advance: &mut dyn FnMut(&mut dyn Stepper) -> Outcome) -> Outcome {
        advance(&mut Advancing { m: self, ode })
    }

    /// The last step, with its stages (the dense output's), while the next advance would
    /// continue it.
    fn saved_step(&self) -> Option<StepRecord> {
        self.has_step.then(|| StepRecord {
            t_start: self.t_start,
            t_end: self.t_end,
            y_start: self.y_start.clone(),
            y_end: self.y_end.clone(),
            stages: self.stages.clone(),
        })
    }

    /// Continues from a saved step: its ends, their derivatives (the first and the last stage:
    /// the method is stiffly accurate) and its stages, with step size `h`.
    fn resume(&mut self, step: &StepRecord, h: f64) -> bool {
        let n = self.n;
        if step.y_start.len() != n || step.y_end.len() != n || step.stages.len() != self.stages.len() {
            return false;
        }
        self.t_start = step.t_start;
        self.t_end = step.t_end;
        self.y_start.copy_from_slice(&step.y_start);
        self.y_end.copy_from_slice(&step.y_end);
        self.stages.copy_from_slice(&step.stages);
        self.f_start.copy_from_slice(&step.stages[..n]);
        self.f_end.copy_from_slice(&step.stages[(self.k.stages - 1) * n..]);
        self.has_step = true;
        self.fresh = false;
        self.h = h;
        true
    }

    /// With Newton's contraction estimate, which the next advance starts from when it continues
    /// the last step.
    fn saved_jacobian(&self) -> Option<JacobianPoint> {
        self.pending.clone().or_else(|| {
            let mut p = self.jac_point.clone().filter(|p| p.h_gamma.is_finite())?;
            p.contraction = self.eta;
            Some(p)
        })
    }

    /// A point of another size (not this model's) is ignored: the next advance evaluates afresh.
    fn restore_jacobian(&mut self, point: &JacobianPoint) {
        if point.x.len() == self.n {
            self.pending = Some(point.clone());
        }
    }
}

/// The cubic Hermite interpolant at `t` of a step [t0, t1] from its ends y0, y1 and their
/// derivatives f0, f1 (also outside the step: an extrapolation).
#[allow(clippy::too_many_arguments)]
fn hermite(t0: f64, t1: f64, y0: &[f64], y1: &[f64], f0: &[f64], f1: &[f64], t: f64, out: &mut [f64]) {
    let dt = t1 - t0;
    let theta = (t - t0) / dt;
    let (a, b, c) = (1.0 - 2.0 * theta, dt * (theta - 1.0), dt * theta);
    let q = theta * (theta - 1.0);
    for i in 0..out.len() {
        let (u0, u1) = (y0[i], y1[i]);
        out[i] = (1.0 - theta) * u0 + theta * u1 + q * (a * (u1 - u0) + b * f0[i] + c * f1[i]);
    }
}

/// The method over one advance's ODE.
struct Advancing<'a> {
    m: &'a mut Esdirk,
    ode: Ode<'a>,
}

impl Stepper for Advancing<'_> {
    fn looks_ahead(&self) -> bool {
        true
    }

    fn start(&mut self, t: f64, x: &[f64], h: Option<f64>, _limit: f64) -> Result<(), String> {
        let (m, ode) = (&mut *self.m, &self.ode);
        m.restore_pending(ode)?;
        m.fresh = false;
        m.eta = 1.0;
        m.t_start = t;
        m.t_end = t;
        m.y_end.copy_from_slice(x);
        ode.rhs(x, t, &mut m.f_end);
        m.has_step = false;
        m.h = match h {
            Some(h) => h,
            None => ode.first_step_size(t, x, &m.f_end, m.k.order),
        };
        Ok(())
    }

    fn step(&mut self, limit: f64) -> Result<(), String> {
        if self.m.pending.is_some() {
            // A restored state continuing its step: no start.
            self.m.restore_pending(&self.ode)?;
        }
        self.m.step(&self.ode, limit).map_err(|e| format!("the ODE solver failed: {e}"))
    }

    fn has_step(&self) -> bool {
        self.m.has_step
    }

    fn last_step(&self) -> (f64, f64, &[f64]) {
        (self.m.t_start, self.m.t_end, &self.m.y_end)
    }

    /// The dense output of the last step ([`Tableau::dense_weights`]), exact at its ends.
    fn interpolate(&self, t: f64, out: &mut [f64]) -> Result<(), String> {
        let m = &*self.m;
        if t == m.t_end {
            out.copy_from_slice(&m.y_end);
            return Ok(());
        }
        if t == m.t_start {
            out.copy_from_slice(&m.y_start);
            return Ok(());
        }
        let (h, s) = (m.t_end - m.t_start, m.k.stages);
        let mut w = m.k.dense_weights((t - m.t_start) / h);
        for wj in &mut w[..s] {
            *wj *= h;
        }
        combine(out, Some(&m.y_start), &w[..s], &m.stages[..s * m.n], Zeros::Skipped);
        Ok(())
    }

    fn step_size(&self) -> f64 {
        self.m.h
    }

    /// A failed step leaves the step size as it was before the advance's last accepted step.
    fn keeps_step_size_on_failure(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An FMU state holds a continued step's stages as `rk::STAGES` vectors, whichever method
    /// made it (`state.rs`): the implicit method's tableau has as many.
    #[test]
    fn a_saved_step_has_as_many_stages_as_an_fmu_state_holds() {
        assert_eq!(tableau().stages, crate::rk::STAGES);
    }

    /// The controller's changes and the Newton matrix's band fit together: a shrunk step's next
    /// predicted factor lies in the geometric middle of the band where the step size is kept, and
    /// every change the controller makes (at least 1 / SHRINK_TO_MIDDLE down, KEEP_BELOW up)
    /// leaves the matrix's band, so a new matrix follows it.
    #[test]
    fn every_change_of_the_controller_is_followed_by_a_new_newton_matrix() {
        assert!((SHRINK_TO_MIDDLE - KEEP_BELOW.powf(-0.5)).abs() < 1e-5);
        let smallest_shrink = 1.0 / SHRINK_TO_MIDDLE;
        assert!(smallest_shrink > REFACTOR_RATIO && KEEP_BELOW > REFACTOR_RATIO);
    }
}
