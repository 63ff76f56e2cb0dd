//! How a model's ODE advances over one communication step.
//!
//! The `OdeSolverProblem` (diffsol's) is built once per instance (at the end of
//! initialization). Its parameter vector is the instance's store of known reals (parameters,
//! inputs; not the states, which are the ODE's x) followed by each known's first and second time derivative and the
//! time they refer to, refreshed before each step: inputs set by the master are held constant
//! over the step (zero-order hold) unless the master gave their derivatives
//! (fmi2SetRealInputDerivatives), then they follow u + u' (t - t_k) + u'' (t - t_k)^2 / 2.
//!
//! The solver methods are in [`crate::stepper`], one file each behind one interface
//! ([`Stepper`], [`Method`]); what is the same for all of them is here and in
//! [`crate::stepper::events`], written once: `Integrator::advance` decides whether the stepper
//! continues its last step or starts afresh from (t, x, f(t, x)) with the step size reached (a
//! step too short to resolve is one Euler step), and `step_until` steps, looks for zero
//! crossings and interpolates at the communication point.
//!
//! Lookahead (both methods: our explicit stepper [`crate::rk::Tsit`], diffsol's tsit45
//! coefficients, and the implicit one, [`crate::stepper::implicit`]): while no known moves, a
//! method that looks ahead steps past the communication point with its natural step size (not
//! past `limit`: the next time event, a defined stop time) and interpolates the state there on
//! its continuous extension; the next `advance` continues that step — by interpolation alone
//! while its end lies beyond the next communication point — as long as it starts from exactly
//! the point the last one reached and the parameter vector is the same (it is canonical: see
//! `fill_parameters`). Otherwise it restarts. What a continuation depends on — the step and the
//! parameter vector ([`Lookahead`]), the step size — goes into FMU states, so that a restored (or
//! deserialized) state continues bit-identically. What the implicit method keeps from one advance
//! to the next besides (its Jacobian and the factors of its Newton matrix, Newton's contraction
//! estimate) goes into FMU states as the point the Jacobian was evaluated at
//! ([`JacobianPoint`]), from which a restored instance makes it again. The instance keeps its
//! own exact time.
//!
//! State events: a model with event indicators gets them evaluated after every accepted internal
//! step (with the modes of this segment, which hold over it). Where one changes sign — from > 0
//! to <= 0 or from < 0 to >= 0; a zero at the start of a segment is no crossing, its sign is taken
//! from the next step — the crossing is located by the Illinois method on the stepper's dense
//! output of that step, to `ROOT_TIME_TOLERANCE`, and `advance` stops there, on the far side
//! of the crossing (the side where the indicator has changed sign), so the instance updates the
//! modes and restarts the solver from that point. The equations stay smooth inside a segment
//! (the modes only change between segments), so the dense output past the crossing is accurate.
//! A step reaching past the communication point is searched only up to it: a crossing beyond is
//! the next communication step's.

use std::sync::Arc;

use diffsol::{
    ConstantOp, NalgebraContext, NalgebraMat, NalgebraVec, NonLinearOp, NonLinearOpJacobian, OdeBuilder, OdeEquations, OdeEquationsRef,
    OdeSolverProblem, Op, ParameterisedOp, UnitCallable, Vector, VectorCommon,
};

use crate::model::{Model, Solver};
use crate::real::{Dual, Real};
use crate::rk::{same_bits, StepRecord};
use crate::stepper::events::{step_until, Ends, Events, RootScratch};
use crate::stepper::jacobian::StructureKey;
use crate::stepper::{self, JacobianPoint, Method, Ode, Setup, Stepper};
use crate::values::{Derivatives, EventIndicators, Knowns};

type Mat = NalgebraMat<f64>;
/// diffsol's vector type as the solvers use it.
pub(crate) type Vect = NalgebraVec<f64>;
/// A model's right-hand side f(x, p, t) -> dx.
pub(crate) type RhsDyn = dyn Fn(&[f64], &[f64], f64, &mut [f64]) + Send + Sync;
type RhsFn = Box<RhsDyn>;
type JacFn = Box<dyn Fn(&[f64], &[f64], f64, &[f64], &mut [f64]) + Send + Sync>;
/// A model's event indicators g(x, p, t) -> z.
pub(crate) type IndicatorDyn = dyn Fn(&[f64], &[f64], f64, &mut [f64]) + Send + Sync;
type IndicatorFn = Box<IndicatorDyn>;
type Unit = UnitCallable<Mat>;

/// A model's ODE as diffsol sees it: x' = f(t, x; p) and the product of its Jacobian with a
/// vector. Our own operator types rather than diffsol's `Closure`, which counts its calls in a
/// `RefCell`: a problem with interior mutability is not `Sync`, so a solver borrowing it would
/// not be `Send`, and an instance keeping its solver alive could no longer move between
/// threads (FMI lets a master call an instance from any thread, one at a time).
pub struct Equations {
    rhs: RhsFn,
    jac: JacFn,
    p: Vect,
    n_states: usize,
    ctx: NalgebraContext,
}

/// f(t, x; p) of [`Equations`].
pub struct Rhs<'a>(&'a Equations);

/// The initial state of [`Equations`] (never used: every solver starts from a state we give it).
pub struct Init<'a>(&'a Equations);

macro_rules! op_of_equations {
    ($t:ty) => {
        impl Op for $t {
            type T = f64;
            type V = Vect;
            type M = Mat;
            type C = NalgebraContext;
            fn context(&self) -> &NalgebraContext {
                &self.eqn().ctx
            }
            fn nstates(&self) -> usize {
                self.eqn().n_states
            }
            fn nout(&self) -> usize {
                self.eqn().n_states
            }
            fn nparams(&self) -> usize {
                self.eqn().p.len()
            }
        }
    };
}

trait OfEquations {
    fn eqn(&self) -> &Equations;
}
impl OfEquations for Equations {
    fn eqn(&self) -> &Equations {
        self
    }
}
impl OfEquations for Rhs<'_> {
    fn eqn(&self) -> &Equations {
        self.0
    }
}
impl OfEquations for Init<'_> {
    fn eqn(&self) -> &Equations {
        self.0
    }
}
op_of_equations!(Equations);
op_of_equations!(Rhs<'_>);
op_of_equations!(Init<'_>);

impl NonLinearOp for Rhs<'_> {
    fn call_inplace(&self, x: &Vect, t: f64, y: &mut Vect) {
        (self.0.rhs)(x.inner().as_slice(), self.0.p.inner().as_slice(), t, y.inner_mut().as_mut_slice());
    }
}

impl NonLinearOpJacobian for Rhs<'_> {
    fn jac_mul_inplace(&self, x: &Vect, t: f64, v: &Vect, y: &mut Vect) {
        (self.0.jac)(x.inner().as_slice(), self.0.p.inner().as_slice(), t, v.inner().as_slice(), y.inner_mut().as_mut_slice());
    }
}

impl ConstantOp for Init<'_> {
    fn call_inplace(&self, _t: f64, y: &mut Vect) {
        y.fill(0.0);
    }
}

impl<'a> OdeEquationsRef<'a> for Equations {
    type Mass = ParameterisedOp<'a, Unit>;
    type Rhs = Rhs<'a>;
    type Root = ParameterisedOp<'a, Unit>;
    type Init = Init<'a>;
    type Out = ParameterisedOp<'a, Unit>;
    type Reset = ParameterisedOp<'a, Unit>;
}

impl OdeEquations for Equations {
    fn rhs(&self) -> Rhs<'_> {
        Rhs(self)
    }
    fn mass(&self) -> Option<ParameterisedOp<'_, Unit>> {
        None
    }
    fn init(&self) -> Init<'_> {
        Init(self)
    }
    fn set_params(&mut self, p: &Vect) {
        self.p.copy_from(p);
    }
    fn get_params(&self, p: &mut Vect) {
        p.copy_from(&self.p);
    }
}

/// Internal solver steps allowed in one communication step before it is abandoned: a bound
/// that turns a runaway (a model that became too stiff for an explicit method, a state blowing
/// up) into an error message instead of a hang.
pub const MAX_INTERNAL_STEPS: usize = 200_000;

/// An interval too short for a solver's stop time at time `t` (diffsol refuses a stop time
/// within its own rounding of the current time): 1000 ulp of t.
pub fn negligible_interval(t: f64) -> f64 {
    1e3 * f64::EPSILON * t.abs().max(1.0)
}

/// The float just below `t` (toward -infinity).
pub fn just_below(t: f64) -> f64 {
    if t.is_nan() || t == f64::NEG_INFINITY {
        t
    } else if t == 0.0 {
        -f64::from_bits(1)
    } else if t > 0.0 {
        f64::from_bits(t.to_bits() - 1)
    } else {
        f64::from_bits(t.to_bits() + 1)
    }
}

/// The float just above `t` (toward +infinity).
pub fn just_above(t: f64) -> f64 {
    -just_below(-t)
}

/// A zero crossing is located to within this fraction of max(|t|, 1 s) (about 2e-13 s at 1 s,
/// 9e-11 s at 400 s): far below any physical time scale, above the rounding of t.
pub const ROOT_TIME_TOLERANCE: f64 = 1e3 * f64::EPSILON;

/// Relative tolerance when the master gives none in fmi2SetupExperiment.
///
/// 1e-8 since the explicit solver steps past communication points (1e-7 before): cut at every
/// communication point, its steps had been far shorter than the tolerance asked for, and so
/// more accurate than it; with its natural steps its error follows the tolerance, and 1e-8
/// keeps the accuracy the tests ask for (RlcCircuit's 5 kHz case: 4.0e-6 of the capacitor
/// voltage's amplitude at 1e-7, within 1e-6 at 1e-8), at little cost (a doStep served by
/// interpolation costs the same at any tolerance).
pub const DEFAULT_RELATIVE_TOLERANCE: f64 = 1e-8;

/// The tolerance an FMU declares in its DefaultExperiment, the one it is made for: its floor
/// where the model has one (so a master that takes the suggestion is not tightened), else the
/// default.
pub fn declared_tolerance(floor: Option<f64>) -> f64 {
    floor.map_or(DEFAULT_RELATIVE_TOLERANCE, |f| f.min(DEFAULT_RELATIVE_TOLERANCE))
}

/// Absolute tolerance of state i = `ABSOLUTE_PER_RELATIVE * rtol * nominal_i`.
pub const ABSOLUTE_PER_RELATIVE: f64 = 1e-3;

/// How the knowns move over a step: each known's first and second time derivative (zero but
/// for inputs whose derivatives the master set) and the time they refer to.
pub struct InputMotion<'a> {
    pub slopes: &'a [f64],
    pub curvatures: &'a [f64],
    pub since: f64,
    /// Whether some known moves (a slope or a curvature is not zero): see [`InputMotion::new`].
    moving: bool,
}

impl<'a> InputMotion<'a> {
    pub fn new(slopes: &'a [f64], curvatures: &'a [f64], since: f64) -> Self {
        let moving = slopes.iter().chain(curvatures).any(|v| *v != 0.0);
        InputMotion { slopes, curvatures, since, moving }
    }

    /// No known moves (a model without inputs, or a master that gives no input derivatives and
    /// no extrapolation).
    pub fn still(zeros: &'a [f64]) -> Self {
        InputMotion { slopes: zeros, curvatures: zeros, since: 0.0, moving: false }
    }

    pub fn moving(&self) -> bool {
        self.moving
    }
}

/// Writes the solver's parameter vector [known (n), slopes (n), curvatures (n), since, moving]
/// into `p`, canonical: the slopes, curvatures and `since` are zero when no input moves, so
/// that steady stepping sees the same vector step after step, and an instance restored from an
/// FMU state the same vector as the one that saved it. The states are not in it (they are not
/// knowns: the equations read them from x).
fn fill_parameters(p: &mut Vec<f64>, known: &[f64], motion: &InputMotion) {
    let moving = motion.moving();
    p.clear();
    p.extend_from_slice(known);
    if moving {
        p.extend_from_slice(motion.slopes);
        p.extend_from_slice(motion.curvatures);
    } else {
        // Not -0.0 either: a vector made afresh from the knowns alone (a restored FMU state) has +0.0.
        p.resize(3 * known.len(), 0.0);
    }
    p.push(if moving { motion.since } else { 0.0 });
    p.push(if moving { 1.0 } else { 0.0 });
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
/// `parameters`; with `signed_activities`, an activity's rate is its element's signed power (the
/// explicit stepper integrates |p| itself: [`Tsit::with_quadratures`]).
fn rhs_of<M: Model>(model: Arc<M>, integers: Arc<[i32]>, booleans: Arc<[bool]>, n_known: usize, signed_activities: bool) -> impl Fn(&[f64], &[f64], f64, &mut [f64]) + Clone {
    move |x: &[f64], p: &[f64], t: f64, dx: &mut [f64]| {
        dx.fill(0.0);
        knowns_at(p, n_known, t, |known| {
            let mut der = if signed_activities { Derivatives::with_signed_activities(dx) } else { Derivatives::new(dx) };
            model.derivatives(&Knowns::new(t, known, x, &integers, &booleans), &mut der)
        })
    }
}

/// The right-hand side over the scalars the implicit method's Jacobian is made with
/// (docs/DESIGN.md, "Exact derivatives"): dual numbers for its entries, exact to round-off, and
/// traces for its structure, both from the model's own equations.
pub trait ExactRhs: Send + Sync {
    /// dx = f(t, x) over dual numbers, the parameter vector `p` held: with x seeded along a
    /// direction v, the derivative parts of dx are J v.
    fn dual(&self, x: &[Dual], p: &[f64], t: f64, dx: &mut [Dual]);
    /// For each state j, the derivatives that depend on it at (t, x): one evaluation over
    /// [`Trace`](crate::trace::Trace). A derivative that is not finite there depends on every state.
    fn columns(&self, x: &[f64], p: &[f64], t: f64) -> Vec<Vec<usize>>;
}

/// A model's equations as an [`ExactRhs`].
struct ModelRhs<M> {
    model: Arc<M>,
    integers: Arc<[i32]>,
    booleans: Arc<[bool]>,
    n_known: usize,
    signed_activities: bool,
}

impl<M: Model> ModelRhs<M> {
    fn evaluate<R: Real>(&self, x: &[R], p: &[f64], t: f64, dx: &mut [R]) {
        dx.fill(R::from(0.0));
        knowns_at(p, self.n_known, t, |known| {
            let known: Vec<R> = known.iter().map(|&k| R::from(k)).collect();
            let mut der = if self.signed_activities { Derivatives::with_signed_activities(dx) } else { Derivatives::new(dx) };
            self.model.derivatives(&Knowns::new(t, &known, x, &self.integers, &self.booleans), &mut der)
        })
    }
}

impl<M: Model> ExactRhs for ModelRhs<M> {
    fn dual(&self, x: &[Dual], p: &[f64], t: f64, dx: &mut [Dual]) {
        self.evaluate(x, p, t, dx)
    }

    fn columns(&self, x: &[f64], p: &[f64], t: f64) -> Vec<Vec<usize>> {
        let tracing = crate::trace::Tracing::start();
        let traced: Vec<crate::trace::Trace> = x.iter().enumerate().map(|(j, &v)| tracing.known(j as u32, v)).collect();
        let mut dx = vec![crate::trace::Trace::from(0.0); x.len()];
        self.evaluate(&traced, p, t, &mut dx);
        let mut columns = vec![Vec::new(); x.len()];
        for (i, d) in dx.iter().enumerate() {
            if d.value().is_finite() {
                for j in tracing.dependencies(*d) {
                    columns[j as usize].push(i);
                }
            } else {
                columns.iter_mut().for_each(|c| c.push(i));
            }
        }
        columns
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

pub use crate::stepper::events::crossed;

/// The explicit solver's last step, reaching past the communication point, and the parameter
/// vector (knowns, their motion) it was taken with: what an FMU state carries so that a
/// restored instance continues that step exactly when the live one would.
#[derive(Clone, Debug, PartialEq)]
pub struct Lookahead {
    pub step: StepRecord,
    pub parameters: Vec<f64>,
}

/// The length of the solver's parameter vector for `n_known` known reals.
pub fn parameters_len(n_known: usize) -> usize {
    3 * n_known + 2
}

/// One instance's ODE integrator.
pub struct Integrator {
    /// The problem (diffsol's; its parameter vector is kept equal to `p`): diffsol's methods are
    /// made from it, and every method takes its first step size from it.
    problem: OdeSolverProblem<Equations>,
    rhs: RhsFn,
    /// The same equations over dual numbers and traces: the implicit method's Jacobian.
    exact: Arc<dyn ExactRhs>,
    /// The model's event indicators, with the modes fixed when this integrator was made.
    indicators: Option<IndicatorFn>,
    n_indicators: usize,
    n_known: usize,
    /// The solver method's per-instance part ([`crate::stepper`]).
    method: Box<dyn Method>,
    rtol: f64,
    atol: Vec<f64>,
    /// The parameter vector set in the problem, and the next one (a buffer).
    p: Vec<f64>,
    p_next: Vec<f64>,
    /// The states whose rate `rhs` gives as a signed power, to integrate in absolute value.
    quadrature: Vec<bool>,
    /// Whether the next advance may continue the stepper's last step: the last advance ended
    /// inside it or at its end (at `reached`, with the state `y_end` interpolated there), the
    /// method looks ahead, and the parameter vector has not changed since.
    resume: bool,
    /// Where the last advance ended.
    reached: f64,
    /// The instant at which the next advance takes the indicators at its start, when not its
    /// start ([`start_after_time_event`](Self::start_after_time_event)).
    indicators_at: Option<f64>,
    /// Buffers: the state an advance reached, event indicators.
    y_end: Vec<f64>,
    z: Vec<f64>,
    z_prev: Vec<f64>,
    /// `z_prev` holds exactly the indicators at the end of the stepper's last accepted step (none
    /// was zero there) with the current parameter vector: an advance that continues that step
    /// need not evaluate them there again ([`Ends::z_prev_fresh`]).
    z_prev_fresh: bool,
    /// The zero-crossing search's buffers.
    roots: RootScratch,
    /// The size of the solver's next step (None before the first step: diffsol's starting-step
    /// heuristic then chooses).
    pub step_size: Option<f64>,
    /// The time event the last advance ended at (just below it): the next advance, when it
    /// starts there, starts just past it. Kept when the integrator is re-made for new modes
    /// (the master's event mode at that event) and in FMU states, like the step size.
    pub after_time_event: Option<f64>,
}

impl Integrator {
    /// Builds the problem for a model whose integer and boolean parameters are fixed from now on.
    #[allow(clippy::too_many_arguments)]
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
        activities: &[usize],
    ) -> Result<Self, String> {
        let atol: Vec<f64> = nominals.iter().map(|n| ABSOLUTE_PER_RELATIVE * rtol * n.abs().max(f64::MIN_POSITIVE)).collect();
        let structure = StructureKey { model: std::any::TypeId::of::<M>(), integers: integers.to_vec(), booleans: booleans.to_vec(), n: n_states };
        let method = stepper::make(method, &Setup { n_states, rtol, atol: &atol, activities, structure: &structure });
        let integers: Arc<[i32]> = integers.into();
        let booleans: Arc<[bool]> = booleans.into();
        let indicators = (n_indicators > 0)
            .then(|| Box::new(indicators_of(model.clone(), integers.clone(), booleans.clone(), known.len())) as IndicatorFn);
        // A method that integrates activities as quadratures gets their signed power.
        let quadratures = method.integrates_activities();
        let exact: Arc<dyn ExactRhs> = Arc::new(ModelRhs { model: model.clone(), integers: integers.clone(), booleans: booleans.clone(), n_known: known.len(), signed_activities: quadratures });
        let f = rhs_of(model, integers, booleans, known.len(), quadratures);
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
        let zeros = vec![0.0; known.len()];
        let mut p = Vec::with_capacity(3 * known.len() + 2);
        fill_parameters(&mut p, known, &InputMotion::still(&zeros));
        let ctx = NalgebraContext::default();
        let eqn = Equations { rhs: Box::new(f), jac, p: Vect::zeros(p.len(), ctx), n_states, ctx };
        let problem = OdeBuilder::<Mat>::new()
            .rtol(rtol)
            .atol(atol.clone())
            .p(p.clone())
            .build_from_eqn(eqn)
            .map_err(|e| format!("could not set up the ODE solver: {e}"))?;
        let mut quadrature = vec![false; n_states];
        if quadratures {
            activities.iter().for_each(|&a| quadrature[a] = true);
        }
        Ok(Integrator {
            problem,
            rhs,
            exact,
            indicators,
            n_indicators,
            n_known: known.len(),
            method,
            rtol,
            atol,
            p_next: Vec::with_capacity(p.len()),
            p,
            quadrature,
            resume: false,
            reached: f64::NAN,
            indicators_at: None,
            y_end: Vec::with_capacity(n_states),
            z: vec![0.0; n_indicators],
            z_prev: vec![0.0; n_indicators],
            z_prev_fresh: false,
            roots: RootScratch::new(n_states, n_indicators),
            step_size: None,
            after_time_event: None,
        })
    }

    /// The stepper's last step and the parameter vector it was taken with, while the next
    /// advance would continue it (then an FMU state must carry them, for a restored instance to
    /// continue the same way); else None.
    pub fn lookahead(&self) -> Option<Lookahead> {
        if !self.resume {
            return None;
        }
        self.method.saved_step().map(|step| Lookahead { step, parameters: self.p.clone() })
    }

    /// Where the Jacobian the method keeps for the next advance was evaluated (the implicit
    /// method's), for an FMU state to carry; else None.
    pub fn jacobian_point(&self) -> Option<JacobianPoint> {
        self.method.saved_jacobian()
    }

    /// Makes the Jacobian of a saved [`jacobian_point`](Self::jacobian_point) again before the
    /// next advance.
    pub fn restore_jacobian(&mut self, point: &JacobianPoint) {
        self.method.restore_jacobian(point);
    }

    /// The first event indicator that changes sign from (`before`, x) to (`at`, x): an
    /// indicator that jumps at a time event (the segment before it ended at the float below
    /// it, where the solver saw no crossing). None without indicators or crossing.
    pub fn jump_at(&mut self, before: f64, at: f64, x: &[f64]) -> Option<usize> {
        let g = self.indicators.as_ref()?;
        self.z_prev_fresh = false;
        g(x, &self.p, before, &mut self.z_prev);
        g(x, &self.p, at, &mut self.z);
        (0..self.n_indicators).find(|&j| crate::stepper::events::crossed(self.z_prev[j], self.z[j]))
    }

    /// The next advance starts afresh, not continuing the stepper's last step.
    pub fn restart(&mut self) {
        self.resume = false;
    }

    /// The next advance starts afresh just past the time event `t_event` (where the equations
    /// have changed), and takes the event indicators at its start as the model gives them at
    /// `t_event` (the modes were settled there), so that one crossing between the two instants
    /// is a state event just past it, as when the solver started at the event itself.
    pub fn start_after_time_event(&mut self, t_event: f64) {
        self.resume = false;
        self.indicators_at = Some(t_event);
    }

    /// Continues from a saved [`lookahead`](Self::lookahead): the state `x` at `t` was reached
    /// inside its step, and `step_size` is the size of the next one. A lookahead that does not
    /// fit this integrator (another solver, another size) is ignored: the next advance restarts.
    pub fn resume_lookahead(&mut self, lookahead: &Lookahead, t: f64, x: &[f64]) {
        if lookahead.parameters.len() != self.p.len() || lookahead.step.y_end.len() != x.len() {
            return;
        }
        let Some(h) = self.step_size else { return };
        if !self.method.resume(&lookahead.step, h) {
            return;
        }
        if !same_bits(&lookahead.parameters, &self.p) {
            self.p.copy_from_slice(&lookahead.parameters);
            let ctx = *self.problem.context();
            self.problem.eqn_mut().set_params(&Vect::from_slice(&self.p, ctx));
        }
        self.reached = t;
        self.y_end.clear();
        self.y_end.extend_from_slice(x);
        self.resume = true;
        // A restored instance evaluates the indicators at the step's end again, as the live one
        // does unless it knows them: the same values either way.
        self.z_prev_fresh = false;
    }

    /// Advances `x` from `t0` to `t1` with the knowns at `known` moving as `motion` says, or
    /// to the first zero crossing of an event indicator before `t1`. A method that looks ahead
    /// may step past `t1`, up to `limit` (the next time event, a defined stop time), when no
    /// known moves, and interpolates the state at `t1`; a later advance from there continues
    /// that step while nothing changed. On error `x` is left unchanged and the message says why
    /// (reported through the FMI logger).
    ///
    /// `knowns_set`: whether a known may have changed since the last advance (set by the master,
    /// moved along its derivatives). When not, and no input moves now or moved in the last
    /// advance, the parameter vector is that of the last advance and is not rebuilt.
    #[allow(clippy::too_many_arguments)]
    pub fn advance(&mut self, known: &[f64], motion: &InputMotion, knowns_set: bool, t0: f64, x: &mut [f64], t1: f64, limit: f64, budget: &mut usize) -> Result<Advanced, String> {
        if x.is_empty() {
            return Ok(Advanced::Reached);
        }
        let was_moving = self.p[3 * self.n_known + 1] != 0.0;
        if knowns_set || was_moving || motion.moving() {
            let mut p = std::mem::take(&mut self.p_next);
            fill_parameters(&mut p, known, motion);
            if !same_bits(&p, &self.p) {
                let ctx = *self.problem.context();
                self.problem.eqn_mut().set_params(&Vect::from_slice(&p, ctx));
                std::mem::swap(&mut self.p, &mut p);
                self.resume = false;
            }
            self.p_next = p;
        }
        let resume = std::mem::replace(&mut self.resume, false);
        let (how, resume) = self.advance_method(resume, t0, x, t1, limit, budget)?;
        let t_reached = match how {
            Advanced::Reached => t1,
            Advanced::Crossing { time, .. } => time,
        };
        check_finite(&self.y_end, t_reached)?;
        x.copy_from_slice(&self.y_end);
        self.reached = t_reached;
        self.resume = resume;
        Ok(how)
    }

    /// One advance of the method, whichever it is. It continues the stepper's last step when the
    /// method looks ahead, the last advance ended inside that step at exactly (t0, x0), and
    /// nothing changed since; otherwise it starts afresh from (t0, x0, f(t0, x0)) with the step
    /// size reached (a step too short to resolve is one Euler step). Either way everything it
    /// starts from is in the FMU state (the instance's t and x, the step size and, when it
    /// continues, the step: [`lookahead`](Self::lookahead)), so a restored instance continues
    /// bit-identically. Returns how it ended and whether the next advance may continue.
    fn advance_method(&mut self, resume: bool, t0: f64, x0: &[f64], t1: f64, limit: f64, budget: &mut usize) -> Result<(Advanced, bool), String> {
        // A moving input's motion is only the master's word for this communication step.
        let moving = self.p[3 * self.n_known + 1] != 0.0;
        let indicators_at = self.indicators_at.take();
        let Integrator { problem, rhs, exact, indicators, n_indicators, method, rtol, atol, p, quadrature, reached, y_end, z, z_prev, z_prev_fresh, roots, step_size, .. } = self;
        let (rhs, p, reached): (&RhsDyn, &[f64], f64) = (&**rhs, p, *reached);
        let ode = Ode { problem, rhs, exact: &**exact, p, atol, rtol: *rtol };
        let events = indicators.as_ref().map(|g| Events { g: &**g, p, n: *n_indicators, start_at: indicators_at });
        method.with_stepper(ode, &mut |stepper: &mut dyn Stepper| {
            let looks_ahead = stepper.looks_ahead() && !moving;
            let limit = if looks_ahead { limit.max(t1) } else { t1 };
            let resume = resume
                && stepper.has_step()
                && stepper.last_step().1 <= limit
                && (t0 - reached).abs() <= negligible_interval(t0)
                && same_bits(x0, y_end);
            // The indicators at the step's end are known only while that step is continued.
            *z_prev_fresh &= resume;
            if !resume && t1 - t0 <= negligible_interval(t0) {
                euler(rhs, p, quadrature, t0, x0, t1, y_end);
                return Ok((Advanced::Reached, false));
            }
            if !resume {
                stepper.start(t0, x0, *step_size, limit)?;
            }
            let ends = Ends { y_end, z, z_prev, z_prev_fresh, roots };
            let result = step_until(stepper, events.as_ref(), t1, limit, ends, budget);
            if result.is_ok() || stepper.keeps_step_size_on_failure() {
                *step_size = Some(stepper.step_size());
            }
            // With moving inputs the step ends at t1 anyway; the next one restarts with the
            // master's next motion.
            result.map(|(how, resume)| (how, resume && looks_ahead))
        })
    }
}

/// One explicit Euler step into `y_end`: for a step so short that t0 + h rounds to t0
/// (relative to t0), which no solver step can resolve; exact to O(h^2) there.
fn euler(rhs: &RhsDyn, p: &[f64], quadrature: &[bool], t0: f64, x0: &[f64], t1: f64, y_end: &mut Vec<f64>) {
    y_end.clear();
    y_end.resize(x0.len(), 0.0);
    rhs(x0, p, t0, y_end);
    for ((y, x), q) in y_end.iter_mut().zip(x0).zip(quadrature) {
        *y = x + (t1 - t0) * if *q { y.abs() } else { *y };
    }
}

fn check_finite(x: &[f64], t: f64) -> Result<(), String> {
    // Tested without an early exit (vector code), searched only when something is not finite.
    if !x.iter().fold(false, |bad, v| bad | !v.is_finite()) {
        return Ok(());
    }
    match x.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(format!("state {i} became {} at t = {t} s", x[i])),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::check_finite;

    /// The first state that is not finite is named, whichever way it is not.
    #[test]
    fn check_finite_names_the_first_state_that_is_not() {
        assert!(check_finite(&[0.0, -1e308, f64::MIN_POSITIVE], 1.0).is_ok());
        assert!(check_finite(&[], 1.0).is_ok());
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let x = [1.0, 2.0, bad, 3.0, f64::NAN];
            let message = check_finite(&x, 0.5).unwrap_err();
            assert_eq!(message, format!("state 2 became {bad} at t = 0.5 s"));
        }
    }
}
