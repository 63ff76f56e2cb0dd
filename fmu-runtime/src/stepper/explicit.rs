//! The explicit method: Tsitouras 5(4), our own stepper ([`Tsit`], diffsol's tsit45
//! coefficients). It looks ahead: while no known moves it takes its natural step past the
//! communication point (not past the advance's limit) and the state there is interpolated on
//! the step's continuous extension; the next advance continues that step when it starts from
//! exactly the point the last one reached with the same parameter vector, and an FMU state
//! carries the step ([`Method::saved_step`]) so that a restored instance does the same.

use crate::rk::{StepRecord, Tsit};

use super::{Method, Ode, Outcome, Registration, Stepper};

/// [`Solver::ExplicitRungeKutta`](crate::model::Solver::ExplicitRungeKutta).
pub static TSITOURAS_54: Registration = Registration {
    description: "explicit Runge-Kutta, Tsitouras 5(4) (diffsol <code>tsit45</code>)",
    make: |s| Box::new(Tsitouras54 { tsit: Tsit::new(s.n_states, s.rtol, s.atol).with_quadratures(s.activities) }),
};

/// The order diffsol's first-step heuristic is given for this method.
const ORDER: usize = 4;

/// Per instance: the stepper, whose last step and step size outlive an advance.
struct Tsitouras54 {
    tsit: Tsit,
}

impl Method for Tsitouras54 {
    fn integrates_activities(&self) -> bool {
        true
    }

    fn with_stepper(&mut self, ode: Ode<'_>, advance: &mut dyn FnMut(&mut dyn Stepper) -> Outcome) -> Outcome {
        advance(&mut Advancing { tsit: &mut self.tsit, ode })
    }

    fn saved_step(&self) -> Option<StepRecord> {
        Some(self.tsit.last.clone())
    }

    fn resume(&mut self, step: &StepRecord, h: f64) -> bool {
        self.tsit.resume(step, h);
        true
    }
}

/// The stepper over one advance's ODE.
struct Advancing<'a> {
    tsit: &'a mut Tsit,
    ode: Ode<'a>,
}

impl Stepper for Advancing<'_> {
    fn looks_ahead(&self) -> bool {
        true
    }

    /// Restarts from (t, x, f(t, x)); the limit is each step's.
    fn start(&mut self, t: f64, x: &[f64], h: Option<f64>, _limit: f64) -> Result<(), String> {
        let ode = &self.ode;
        self.tsit.restart(t, x, |y, t, dy| ode.rhs(y, t, dy), h.unwrap_or(ode.problem.h0));
        if h.is_none() {
            self.tsit.h = ode.first_step_size(t, x, self.tsit.current_derivative(), ORDER);
        }
        Ok(())
    }

    fn step(&mut self, limit: f64) -> Result<(), String> {
        let ode = &self.ode;
        self.tsit.step(limit, &mut |y: &[f64], t: f64, dy: &mut [f64]| ode.rhs(y, t, dy)).map_err(|e| format!("the ODE solver failed: {e}"))
    }

    fn has_step(&self) -> bool {
        self.tsit.has_step
    }

    fn last_step(&self) -> (f64, f64, &[f64]) {
        let last = &self.tsit.last;
        (last.t_start, last.t_end, &last.y_end)
    }

    fn interpolate(&self, t: f64, out: &mut [f64]) -> Result<(), String> {
        self.tsit.interpolate(t, out);
        Ok(())
    }

    fn step_size(&self) -> f64 {
        self.tsit.h
    }

    /// A failed step leaves the stepper, and its step size, as it was.
    fn keeps_step_size_on_failure(&self) -> bool {
        true
    }
}
