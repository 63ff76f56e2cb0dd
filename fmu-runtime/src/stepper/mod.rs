//! The solver methods of Co-Simulation, each in its own file, behind one interface.
//!
//! A method is two things. Its per-instance part ([`Method`]: what it keeps from one advance to
//! the next, such as the explicit method's last step) lives as long as the instance's
//! [`Integrator`](crate::integrate::Integrator). For each advance it opens a [`Stepper`] on the
//! model's ODE ([`Ode`]: diffsol's problem, the right-hand side with this advance's parameter
//! vector, the tolerances), which takes accepted steps and offers their dense output. Everything
//! else — whether the last step is continued, the tiny-interval Euler step, the search for event
//! indicator zero crossings on the dense output, the budget of internal steps — is the same for
//! every method and written once ([`events::step_until`], `Integrator::advance`).
//!
//! Adding a method: one file here implementing both traits and a [`Registration`]; here its
//! `pub mod` line and its line in `registered`; its variant in [`Solver`] (docs/DESIGN.md,
//! "Adding a solver method").

pub mod band;
pub mod esdirk;
pub mod events;
pub mod explicit;
pub mod implicit;
pub mod jacobian;

use diffsol::ode_solver::state::StateCommon;
use diffsol::{OdeSolverProblem, OdeSolverState, RkState, Vector};

use crate::integrate::{Advanced, Equations, ExactRhs, RhsDyn, Vect};
use crate::model::Solver;
use crate::rk::StepRecord;

/// The one place a method is registered: each [`Solver`] variant to its file's [`Registration`].
fn registered(solver: Solver) -> &'static Registration {
    match solver {
        Solver::ExplicitRungeKutta => &explicit::TSITOURAS_54,
        Solver::ImplicitRungeKutta => &implicit::ESDIRK,
    }
}

/// What the runtime knows of a method before any instance uses it.
pub struct Registration {
    /// The method in an FMU's documentation, an HTML phrase ("each doStep integrates with an
    /// adaptive {description} with error control").
    pub description: &'static str,
    /// Makes its per-instance part.
    pub make: fn(&Setup) -> Box<dyn Method>,
}

/// The method's phrase in an FMU's documentation.
pub fn description(solver: Solver) -> &'static str {
    registered(solver).description
}

/// The per-instance part of the method `solver`.
pub fn make(solver: Solver, setup: &Setup) -> Box<dyn Method> {
    (registered(solver).make)(setup)
}

/// What a method is made for: the model's size, the tolerances, the activity states.
pub struct Setup<'a> {
    pub n_states: usize,
    pub rtol: f64,
    /// Per state.
    pub atol: &'a [f64],
    /// The indices of the activity states (integrals of |power| dt).
    pub activities: &'a [usize],
    /// What the structure of the model's Jacobian is cached under
    /// ([`jacobian::structure`]).
    pub structure: &'a jacobian::StructureKey,
}

/// Where a method's kept Jacobian was evaluated, and the h gamma its Newton matrix
/// I - h gamma J was factorized with: what an FMU state carries so that a restored instance
/// makes the same matrix again (bit for bit: the Jacobian is a deterministic function of the
/// point) and continues as the live one does.
#[derive(Clone, Debug, PartialEq)]
pub struct JacobianPoint {
    pub t: f64,
    pub x: Vec<f64>,
    /// The solver's parameter vector (knowns and their motion) it was evaluated with.
    pub parameters: Vec<f64>,
    pub h_gamma: f64,
    /// Newton's contraction estimate when the point was saved (the method iterates with it
    /// when it continues its last step).
    pub contraction: f64,
}

/// How an advance ended: how (reached or stopped at a crossing), and whether the next advance may
/// continue the stepper's last step; or why it failed.
pub type Outcome = Result<(Advanced, bool), String>;

/// The per-instance part of a solver method: what it keeps between advances.
pub trait Method: Send + Sync {
    /// Whether the method integrates activities itself, as quadratures of their element's signed
    /// power ([`crate::rk::Tsit::with_quadratures`]); the right-hand side then gives the signed
    /// power, else |power|.
    fn integrates_activities(&self) -> bool;

    /// Opens a stepper on `ode` for one advance and hands it to `advance`.
    fn with_stepper(&mut self, ode: Ode<'_>, advance: &mut dyn FnMut(&mut dyn Stepper) -> Outcome) -> Outcome;

    /// The last step, for an FMU state to carry while the next advance would continue it (see
    /// [`crate::integrate::Lookahead`]); None for a method that never continues a step.
    fn saved_step(&self) -> Option<StepRecord> {
        None
    }

    /// Continues from a saved step (its end is the current point) with step size `h`; false (and
    /// nothing done) for a method that never continues a step.
    fn resume(&mut self, _step: &StepRecord, _h: f64) -> bool {
        false
    }

    /// Where the Jacobian the next advance would use was evaluated, for an FMU state to carry;
    /// None for a method that keeps none between advances.
    fn saved_jacobian(&self) -> Option<JacobianPoint> {
        None
    }

    /// Makes the Jacobian of a saved point again before the next advance (a restored state).
    fn restore_jacobian(&mut self, _point: &JacobianPoint) {}
}

/// One method's stepping over one advance, as [`events::step_until`] drives it.
pub trait Stepper {
    /// Whether it may step past the communication point (up to the advance's limit: the next
    /// time event, a defined stop time), interpolate the state there, and have the next advance
    /// continue that step (lookahead). Otherwise every step ends at the communication point at
    /// the latest.
    fn looks_ahead(&self) -> bool;

    /// Starts afresh at (t, x) with step size `h`, or diffsol's first-step heuristic's where
    /// None. No step of this advance will end past `limit` (the same for every [`step`](Self::step)).
    fn start(&mut self, t: f64, x: &[f64], h: Option<f64>, limit: f64) -> Result<(), String>;

    /// Takes one accepted step from the current point, ending at `limit` at the latest. On
    /// error the message says why (reported through the FMI logger).
    fn step(&mut self, limit: f64) -> Result<(), String>;

    /// Whether a step has been accepted since it started (its dense output is valid).
    fn has_step(&self) -> bool;

    /// The last accepted step [t_start, t_end] and the state at its end; before the first step
    /// since a start, the start point (t_start = t_end).
    fn last_step(&self) -> (f64, f64, &[f64]);

    /// The state at `t` within the last accepted step, on its dense output; at t_end exactly the
    /// step's end state.
    fn interpolate(&self, t: f64, out: &mut [f64]) -> Result<(), String>;

    /// The size of its next step.
    fn step_size(&self) -> f64;

    /// Whether [`step_size`](Self::step_size) is kept when the advance fails (a failed step
    /// leaves it as it was), rather than the step size the advance started with.
    fn keeps_step_size_on_failure(&self) -> bool;
}

/// The model's ODE for one advance: x' = f(t, x; p) with this advance's parameter vector, diffsol's
/// problem (for the first step size and for diffsol's own solvers), the tolerances.
pub struct Ode<'a> {
    pub problem: &'a OdeSolverProblem<Equations>,
    pub rhs: &'a RhsDyn,
    /// The same equations over dual numbers and traces (the implicit method's Jacobian).
    pub exact: &'a dyn ExactRhs,
    pub p: &'a [f64],
    /// Per state.
    pub atol: &'a [f64],
    pub rtol: f64,
}

impl Ode<'_> {
    /// dy = f(t, y).
    pub fn rhs(&self, y: &[f64], t: f64, dy: &mut [f64]) {
        (self.rhs)(y, self.p, t, dy)
    }

    /// diffsol's first step size from (t, y, dy = f(t, y)) for a method of `order`: the one its
    /// own solvers start with.
    pub fn first_step_size(&self, t: f64, y: &[f64], dy: &[f64], order: usize) -> f64 {
        let ctx = *self.problem.context();
        let mut state = rk_state(Vect::from_slice(y, ctx), Vect::from_slice(dy, ctx), t, self.problem.h0);
        state.set_step_size(self.problem.h0, &Vect::from_slice(self.atol, ctx), self.rtol, &self.problem.eqn, order);
        state.as_ref().h
    }
}

/// A Runge-Kutta solver's state (y, dy = f(t, y), t, h), without outputs or sensitivities.
pub fn rk_state(y: Vect, dy: Vect, t: f64, h: f64) -> RkState<Vect> {
    let ctx = *y.context();
    let empty = || Vect::zeros(0, ctx);
    RkState::new_from_common(StateCommon { y, dy, g: empty(), dg: empty(), s: empty(), ds: empty(), sg: empty(), dsg: empty(), t, h })
}
