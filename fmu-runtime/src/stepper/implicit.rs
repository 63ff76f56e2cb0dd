//! The implicit method: diffsol's esdirk34 (ESDIRK3(4)), for stiff models. Made afresh from
//! (t, x, f(t, x), step size) for every advance, with its stop time at the communication point.
//! Kept alive, its Newton iteration and Jacobian would carry over from the previous step, so a
//! restored FMU state would not continue bit-identically (and the shared design saw a kept
//! esdirk34 fail at a stop time).

use diffsol::{NalgebraLU, OdeSolverMethod, OdeSolverStopReason, Sdirk, Vector, VectorCommon};

use crate::integrate::{Equations, Vect};

use super::{rk_state, Method, Ode, Outcome, Registration, Stepper};

/// [`Solver::ImplicitRungeKutta`](crate::model::Solver::ImplicitRungeKutta).
pub static ESDIRK_34: Registration = Registration {
    description: "singly diagonally implicit Runge-Kutta ESDIRK3(4) (diffsol <code>esdirk34</code>)",
    make: |s| Box::new(Esdirk34 { y_end: Vect::zeros(s.n_states, Default::default()) }),
};

/// The order diffsol's first-step heuristic is given for this method.
const ORDER: usize = 3;

/// Per instance: nothing but a buffer (the solver is made for each advance).
struct Esdirk34 {
    /// The state at the last step's end.
    y_end: Vect,
}

impl Method for Esdirk34 {
    fn integrates_activities(&self) -> bool {
        false
    }

    fn with_stepper(&mut self, ode: Ode<'_>, advance: &mut dyn FnMut(&mut dyn Stepper) -> Outcome) -> Outcome {
        advance(&mut Advancing { ode, solver: None, stop: f64::NAN, t_start: f64::NAN, t_end: f64::NAN, y_end: &mut self.y_end, has_step: false, h: f64::NAN })
    }
}

/// diffsol's esdirk34 over one advance.
struct Advancing<'a> {
    ode: Ode<'a>,
    /// Made by `start`.
    solver: Option<Sdirk<'a, Equations, NalgebraLU<f64>>>,
    /// The solver's stop time: the advance's limit.
    stop: f64,
    /// The last step, [t_start, t_end], ending at the stop time exactly when it reached it (our
    /// own time, not diffsol's rounding of it), and the state at its end.
    t_start: f64,
    t_end: f64,
    y_end: &'a mut Vect,
    has_step: bool,
    /// The solver's step size after the last accepted step.
    h: f64,
}

impl Stepper for Advancing<'_> {
    fn looks_ahead(&self) -> bool {
        false
    }

    fn start(&mut self, t: f64, x: &[f64], h: Option<f64>, limit: f64) -> Result<(), String> {
        let ode = &self.ode;
        let ctx = *ode.problem.context();
        let mut dx = vec![0.0; x.len()];
        ode.rhs(x, t, &mut dx);
        let h = h.unwrap_or_else(|| ode.first_step_size(t, x, &dx, ORDER));
        let state = rk_state(Vect::from_slice(x, ctx), Vect::from_vec(dx, ctx), t, h);
        let mut solver = ode.problem.esdirk34_solver::<NalgebraLU<f64>>(state).map_err(|e| e.to_string())?;
        solver.set_stop_time(limit).map_err(|e| format!("could not set the stop time {limit} s: {e}"))?;
        self.solver = Some(solver);
        self.stop = limit;
        (self.t_start, self.t_end) = (t, t);
        self.y_end.inner_mut().as_mut_slice().copy_from_slice(x);
        self.has_step = false;
        self.h = h;
        Ok(())
    }

    fn step(&mut self, _limit: f64) -> Result<(), String> {
        let solver = self.solver.as_mut().ok_or("the implicit solver was not started")?;
        match solver.step() {
            Ok(reason) => {
                let stopped = matches!(reason, OdeSolverStopReason::TstopReached);
                let (h, t_solver) = {
                    let state = solver.state();
                    (state.h, state.t)
                };
                // Trust our own stop time, not the solver's rounding of it.
                let interpolated = stopped && t_solver != self.stop;
                if !interpolated || solver.interpolate_inplace(self.stop, self.y_end).is_err() {
                    self.y_end.copy_from(solver.state().y);
                }
                self.t_start = self.t_end;
                self.t_end = if stopped { self.stop } else { t_solver };
                self.has_step = true;
                self.h = h;
                Ok(())
            }
            Err(e) => Err(format!("the ODE solver failed at t = {} s: {e}", solver.state().t)),
        }
    }

    fn has_step(&self) -> bool {
        self.has_step
    }

    fn last_step(&self) -> (f64, f64, &[f64]) {
        (self.t_start, self.t_end, self.y_end.inner().as_slice())
    }

    fn interpolate(&self, t: f64, out: &mut [f64]) -> Result<(), String> {
        if t == self.t_end {
            out.copy_from_slice(self.y_end.inner().as_slice());
            return Ok(());
        }
        let solver = self.solver.as_ref().ok_or("the implicit solver was not started")?;
        let v = solver.interpolate(t).map_err(|e| format!("could not interpolate the state at t = {t} s: {e}"))?;
        out.copy_from_slice(v.inner().as_slice());
        Ok(())
    }

    fn step_size(&self) -> f64 {
        self.h
    }

    /// A failed advance keeps the step size it started with: diffsol's state after a failure is
    /// no point to continue from.
    fn keeps_step_size_on_failure(&self) -> bool {
        false
    }
}
