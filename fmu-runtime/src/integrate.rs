//! How a model's ODE advances over one communication step: diffsol underneath.
//!
//! The `OdeSolverProblem` is built once per instance (at the end of initialization). Its
//! parameter vector is the instance's store of known reals (parameters, inputs, state start
//! values) followed by each known's first and second time derivative and the time they refer
//! to, refreshed before each step: inputs set by the master are held constant over the step
//! (zero-order hold) unless the master gave their derivatives (fmi2SetRealInputDerivatives),
//! then they follow u + u' (t - t_k) + u'' (t - t_k)^2 / 2. Each `advance` makes the solver from our own
//! `(t, x, h)` — the communication point, the state and the step size the solver reached last —
//! so that an FMU state saved and restored (or serialized) continues bit-identically: nothing
//! else carries over between steps. The instance keeps its own exact time; the solver's time
//! after `TstopReached` is never trusted over it.
//!
//! State events: a model with event indicators gets them evaluated after every accepted internal
//! step (with the modes of this segment, which hold over it). Where one changes sign — from > 0
//! to <= 0 or from < 0 to >= 0; a zero at the start of a segment is no crossing, its sign is taken
//! from the next step — the crossing is located by the Illinois method on the solver's dense
//! output of that step, to `ROOT_TIME_TOLERANCE`, and `advance` stops there, on the far side
//! of the crossing (the side where the indicator has changed sign), so the instance updates the
//! modes and restarts the solver from that point. The equations stay smooth inside a segment
//! (the modes only change between segments), so the dense output past the crossing is accurate.

use std::sync::Arc;

use diffsol::{
    Closure, ConstantClosure, NalgebraLU, NalgebraMat, NalgebraVec, OdeBuilder, OdeSolverEquations,
    OdeEquations, OdeSolverMethod, OdeSolverProblem, OdeSolverState, OdeSolverStopReason, RkState,
    UnitCallable, Vector,
};
use diffsol::ode_solver::state::StateCommon;

use crate::model::{Model, Solver};
use crate::values::{Derivatives, EventIndicators, Knowns};

type Mat = NalgebraMat<f64>;
type Vect = NalgebraVec<f64>;
type RhsFn = Box<dyn Fn(&[f64], &[f64], f64, &mut [f64]) + Send + Sync>;
type JacFn = Box<dyn Fn(&[f64], &[f64], f64, &[f64], &mut [f64]) + Send + Sync>;
type InitFn = Box<dyn Fn(&[f64], f64, &mut [f64]) + Send + Sync>;
type IndicatorDyn = dyn Fn(&[f64], &[f64], f64, &mut [f64]) + Send + Sync;
type IndicatorFn = Box<IndicatorDyn>;
type Unit = UnitCallable<Mat>;
type Equations = OdeSolverEquations<Mat, Closure<Mat, RhsFn, JacFn>, ConstantClosure<Mat, InitFn>, Unit, Unit, Unit, Unit>;

/// Internal solver steps allowed in one communication step before it is abandoned: a bound
/// that turns a runaway (a model that became too stiff for an explicit method, a state blowing
/// up) into an error message instead of a hang.
pub const MAX_INTERNAL_STEPS: usize = 200_000;

/// An interval too short for a solver's stop time at time `t` (diffsol refuses a stop time
/// within its own rounding of the current time): 1000 ulp of t.
pub fn negligible_interval(t: f64) -> f64 {
    1e3 * f64::EPSILON * t.abs().max(1.0)
}

/// A zero crossing is located to within this fraction of max(|t|, 1 s) (about 2e-13 s at 1 s,
/// 9e-11 s at 400 s): far below any physical time scale, above the rounding of t.
pub const ROOT_TIME_TOLERANCE: f64 = 1e3 * f64::EPSILON;

/// Relative tolerance when the master gives none in fmi2SetupExperiment.
pub const DEFAULT_RELATIVE_TOLERANCE: f64 = 1e-7;

/// Absolute tolerance of state i = `ABSOLUTE_PER_RELATIVE * rtol * nominal_i`.
pub const ABSOLUTE_PER_RELATIVE: f64 = 1e-3;

/// How the knowns move over a step: each known's first and second time derivative (zero but
/// for inputs whose derivatives the master set) and the time they refer to.
pub struct InputMotion<'a> {
    pub slopes: &'a [f64],
    pub curvatures: &'a [f64],
    pub since: f64,
}

/// The solver's parameter vector: [known (n), slopes (n), curvatures (n), since, moving].
fn parameters(known: &[f64], motion: &InputMotion) -> Vec<f64> {
    let moving = motion.slopes.iter().chain(motion.curvatures).any(|v| *v != 0.0);
    let mut p = Vec::with_capacity(3 * known.len() + 2);
    p.extend_from_slice(known);
    p.extend_from_slice(motion.slopes);
    p.extend_from_slice(motion.curvatures);
    p.push(motion.since);
    p.push(if moving { 1.0 } else { 0.0 });
    p
}

/// Calls `f` with the knowns at t from the parameter vector of `parameters`: extrapolated to t
/// only when some input moves.
fn knowns_at<R>(p: &[f64], n_known: usize, t: f64, f: impl FnOnce(&[f64]) -> R) -> R {
    let known = &p[..n_known];
    if p[3 * n_known + 1] == 0.0 {
        return f(known);
    }
    let tau = t - p[3 * n_known];
    let (slopes, curvatures) = (&p[n_known..2 * n_known], &p[2 * n_known..3 * n_known]);
    let moved: Vec<f64> = (0..n_known).map(|i| known[i] + slopes[i] * tau + 0.5 * curvatures[i] * tau * tau).collect();
    f(&moved)
}

/// The right-hand side f(t, x) of a model, as diffsol calls it, with the parameter vector of
/// `parameters`.
fn rhs_of<M: Model>(model: Arc<M>, integers: Arc<[i32]>, booleans: Arc<[bool]>, n_known: usize) -> impl Fn(&[f64], &[f64], f64, &mut [f64]) + Clone {
    move |x: &[f64], p: &[f64], t: f64, dx: &mut [f64]| {
        dx.fill(0.0);
        knowns_at(p, n_known, t, |known| {
            model.derivatives(&Knowns::new(t, known, x, &integers, &booleans), &mut Derivatives::new(dx))
        })
    }
}

/// The event indicators z(t, x) of a model, with the parameter vector of `parameters`.
fn indicators_of<M: Model>(model: Arc<M>, integers: Arc<[i32]>, booleans: Arc<[bool]>, n_known: usize) -> impl Fn(&[f64], &[f64], f64, &mut [f64]) {
    move |x: &[f64], p: &[f64], t: f64, z: &mut [f64]| {
        z.fill(0.0);
        knowns_at(p, n_known, t, |known| {
            model.event_indicators(&Knowns::new(t, known, x, &integers, &booleans), &mut EventIndicators::new(z))
        })
    }
}

/// How `advance` ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Advanced {
    /// The end of the interval was reached.
    Reached,
    /// Event indicator `indicator` changed sign; the state is that just past the crossing at `time`.
    Crossing { time: f64, indicator: usize },
}

/// Whether an indicator going from `a` to `b` crossed zero (a zero at `a` is no crossing).
pub fn crossed(a: f64, b: f64) -> bool {
    (a > 0.0 && b <= 0.0) || (a < 0.0 && b >= 0.0)
}

/// One instance's ODE integrator.
pub struct Integrator {
    problem: OdeSolverProblem<Equations>,
    rhs: RhsFn,
    /// The model's event indicators, with the modes fixed when this integrator was made.
    indicators: Option<IndicatorFn>,
    n_indicators: usize,
    method: Solver,
    rtol: f64,
    atol: Vec<f64>,
    /// The step size the solver reached at the end of the last communication step
    /// (None before the first step: diffsol's starting-step heuristic then chooses).
    pub step_size: Option<f64>,
}

impl Integrator {
    /// Builds the problem for a model whose integer and boolean parameters are fixed from now on.
    pub fn new<M: Model>(
        model: Arc<M>,
        known: &[f64],
        integers: &[i32],
        booleans: &[bool],
        n_states: usize,
        n_indicators: usize,
        method: Solver,
        rtol: f64,
        nominals: &[f64],
    ) -> Result<Self, String> {
        let integers: Arc<[i32]> = integers.into();
        let booleans: Arc<[bool]> = booleans.into();
        let indicators = (n_indicators > 0)
            .then(|| Box::new(indicators_of(model.clone(), integers.clone(), booleans.clone(), known.len())) as IndicatorFn);
        let f = rhs_of(model, integers, booleans, known.len());
        let f_jac = f.clone();
        // Jacobian-vector product by a forward difference along v (exact Jacobians come with
        // the Model Exchange issue); only the implicit method calls it.
        let jac: JacFn = Box::new(move |x: &[f64], p: &[f64], t: f64, v: &[f64], jv: &mut [f64]| {
            let norm_v = v.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            if norm_v == 0.0 {
                jv.fill(0.0);
                return;
            }
            let norm_x = x.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            let eps = f64::EPSILON.sqrt() * (1.0 + norm_x) / norm_v;
            let shifted: Vec<f64> = x.iter().zip(v).map(|(xi, vi)| xi + eps * vi).collect();
            let mut f0 = vec![0.0; x.len()];
            f_jac(x, p, t, &mut f0);
            f_jac(&shifted, p, t, jv);
            for (j, f0i) in jv.iter_mut().zip(&f0) {
                *j = (*j - f0i) / eps;
            }
        });
        let rhs: RhsFn = Box::new(f.clone());
        let init: InitFn = Box::new(move |_p: &[f64], _t: f64, y: &mut [f64]| y.fill(0.0));
        let atol: Vec<f64> = nominals.iter().map(|n| ABSOLUTE_PER_RELATIVE * rtol * n.abs().max(f64::MIN_POSITIVE)).collect();
        let problem = OdeBuilder::<Mat>::new()
            .rtol(rtol)
            .atol(atol.clone())
            .p(parameters(known, &InputMotion { slopes: &vec![0.0; known.len()], curvatures: &vec![0.0; known.len()], since: 0.0 }))
            .rhs_implicit(Box::new(f) as RhsFn, jac)
            .init(init, n_states)
            .build()
            .map_err(|e| format!("could not set up the ODE solver: {e}"))?;
        Ok(Integrator { problem, rhs, indicators, n_indicators, method, rtol, atol, step_size: None })
    }

    /// Advances `x` from `t0` to `t1` with the knowns at `known` moving as `motion` says, or
    /// to the first zero crossing of an event indicator before `t1`. On error `x` is left
    /// unchanged and the message says why (reported through the FMI logger).
    pub fn advance(&mut self, known: &[f64], motion: &InputMotion, t0: f64, x: &mut [f64], t1: f64) -> Result<Advanced, String> {
        let p = parameters(known, motion);
        if x.is_empty() {
            return Ok(Advanced::Reached);
        }
        // A step so short that t0 + h rounds to t0 (relative to t0) cannot be resolved by a
        // solver's stop time; one explicit Euler step is exact to O(h^2) there.
        if t1 - t0 <= negligible_interval(t0) {
            let mut dx = vec![0.0; x.len()];
            (self.rhs)(x, &p, t0, &mut dx);
            for (xi, d) in x.iter_mut().zip(&dx) {
                *xi += (t1 - t0) * d;
            }
            return check_finite(x, t1).map(|_| Advanced::Reached);
        }
        let ctx = *self.problem.context();
        self.problem.eqn_mut().set_params(&Vect::from_slice(&p, ctx));
        let y = Vect::from_slice(x, ctx);
        let mut dx = vec![0.0; x.len()];
        (self.rhs)(x, &p, t0, &mut dx);
        let dy = Vect::from_vec(dx, ctx);
        let empty = || Vect::zeros(0, ctx);
        let mut state = RkState::new_from_common(StateCommon {
            y,
            dy,
            g: empty(),
            dg: empty(),
            s: empty(),
            ds: empty(),
            sg: empty(),
            dsg: empty(),
            t: t0,
            h: self.step_size.unwrap_or(self.problem.h0),
        });
        let order = match self.method {
            Solver::ExplicitRungeKutta => 4,
            Solver::ImplicitRungeKutta => 3,
        };
        if self.step_size.is_none() {
            let atol = Vect::from_slice(&self.atol, ctx);
            state.as_mut().set_step_size(self.problem.h0, &atol, self.rtol, &self.problem.eqn, order);
        }
        let events = self.indicators.as_ref().map(|g| Events { g: &**g, p: &p, n: self.n_indicators });
        let (y, h, how) = match self.method {
            Solver::ExplicitRungeKutta => {
                let solver = self.problem.tsit45_solver(state).map_err(|e| e.to_string())?;
                run_to(solver, t0, x, t1, events)?
            }
            Solver::ImplicitRungeKutta => {
                let solver = self.problem.esdirk34_solver::<NalgebraLU<f64>>(state).map_err(|e| e.to_string())?;
                run_to(solver, t0, x, t1, events)?
            }
        };
        let t_reached = match how {
            Advanced::Reached => t1,
            Advanced::Crossing { time, .. } => time,
        };
        check_finite(&y, t_reached)?;
        x.copy_from_slice(&y);
        self.step_size = Some(h);
        Ok(how)
    }
}

fn check_finite(x: &[f64], t: f64) -> Result<(), String> {
    match x.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(format!("state {i} became {} at t = {t} s", x[i])),
        None => Ok(()),
    }
}

/// The event indicators of one advance: g(x, p, t, z) with its parameter vector.
struct Events<'a> {
    g: &'a IndicatorDyn,
    p: &'a [f64],
    n: usize,
}

impl Events<'_> {
    fn at(&self, t: f64, y: &[f64]) -> Vec<f64> {
        let mut z = vec![0.0; self.n];
        (self.g)(y, self.p, t, &mut z);
        z
    }
}

/// Steps a solver from (t0, x0) until its stop time `t1` or the first zero crossing of an event
/// indicator; returns the state there, the step size reached and how it ended.
fn run_to<'a, S>(mut solver: S, t0: f64, x0: &[f64], t1: f64, events: Option<Events>) -> Result<(Vec<f64>, f64, Advanced), String>
where
    S: OdeSolverMethod<'a, Equations>,
{
    solver.set_stop_time(t1).map_err(|e| format!("could not set the stop time {t1} s: {e}"))?;
    // The indicators at the last accepted point; a zero takes its sign from the next point.
    let mut z_prev = events.as_ref().map(|e| e.at(t0, x0)).unwrap_or_default();
    let mut t_prev = t0;
    for _ in 0..MAX_INTERNAL_STEPS {
        match solver.step() {
            Ok(reason) => {
                let stopped = matches!(reason, OdeSolverStopReason::TstopReached);
                let state = solver.state();
                let h = state.h;
                // Trust our own t1, not the solver's rounding of it.
                let (t, y) = if !stopped {
                    (state.t, state.y.clone_as_vec())
                } else if state.t == t1 {
                    (t1, state.y.clone_as_vec())
                } else {
                    (t1, solver.interpolate(t1).map(|v| v.clone_as_vec()).unwrap_or_else(|_| state.y.clone_as_vec()))
                };
                if let Some(ev) = &events {
                    let z = ev.at(t, &y);
                    if let Some((time, indicator, y_root)) = first_crossing(&solver, ev, t_prev, &z_prev, t, &z, &y)? {
                        return Ok((y_root, h, Advanced::Crossing { time, indicator }));
                    }
                    for (zp, zi) in z_prev.iter_mut().zip(&z) {
                        if *zi != 0.0 || *zp == 0.0 {
                            *zp = *zi;
                        }
                    }
                }
                t_prev = t;
                if stopped {
                    return Ok((y, h, Advanced::Reached));
                }
            }
            Err(e) => {
                return Err(format!("the ODE solver failed at t = {} s: {e}", solver.state().t));
            }
        }
    }
    Err(format!(
        "the ODE solver needed more than {MAX_INTERNAL_STEPS} internal steps to reach t = {t1} s \
         (stopped at t = {} s); the model may be too stiff for its solver or unstable",
        solver.state().t
    ))
}

/// The earliest zero crossing within the last step [ta, tb] (indicators za at ta, zb at tb, state
/// yb at tb), located by the Illinois method on the solver's dense output: (time just past the
/// crossing, indicator, state there), or None.
#[allow(clippy::too_many_arguments)]
fn first_crossing<'a, S>(solver: &S, ev: &Events, ta: f64, za: &[f64], tb: f64, zb: &[f64], yb: &[f64]) -> Result<Option<(f64, usize, Vec<f64>)>, String>
where
    S: OdeSolverMethod<'a, Equations>,
{
    let mut best: Option<(f64, usize, Vec<f64>)> = None;
    let state_at = |t: f64| -> Result<Vec<f64>, String> {
        if t == tb {
            return Ok(yb.to_vec());
        }
        solver.interpolate(t).map(|v| v.clone_as_vec()).map_err(|e| format!("could not interpolate the state at t = {t} s: {e}"))
    };
    for j in 0..ev.n {
        if !crossed(za[j], zb[j]) {
            continue;
        }
        // Bracket: g(lo) on the start side (za's sign), g(hi) crossed.
        let (mut lo, mut g_lo) = (ta, za[j]);
        let (mut hi, mut g_hi, mut y_hi) = (tb, zb[j], yb.to_vec());
        let tol = ROOT_TIME_TOLERANCE * tb.abs().max(1.0);
        let mut side = 0i8;
        for _ in 0..200 {
            if hi - lo <= tol {
                break;
            }
            let secant = if g_lo != g_hi { hi - g_hi * (hi - lo) / (g_hi - g_lo) } else { 0.5 * (lo + hi) };
            // Keep the trial point strictly inside, off the ends by a little.
            let margin = 0.5 * tol;
            let t = if secant.is_finite() { secant.clamp(lo + margin, hi - margin) } else { 0.5 * (lo + hi) };
            let y = state_at(t)?;
            let g = ev.at(t, &y)[j];
            if crossed(za[j], g) {
                hi = t;
                g_hi = g;
                y_hi = y;
                if side == 1 {
                    g_lo *= 0.5; // Illinois: the same end twice, halve the other's weight
                }
                side = 1;
            } else {
                lo = t;
                g_lo = g;
                if side == -1 {
                    g_hi *= 0.5;
                }
                side = -1;
            }
        }
        let earlier = match &best {
            Some((t, _, _)) => hi < *t,
            None => true,
        };
        if earlier {
            best = Some((hi, j, y_hi));
        }
    }
    Ok(best)
}
