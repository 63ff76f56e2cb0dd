//! Co-Simulation: one communication step, stopping at every time event and state event inside
//! it, with the inputs held, moved along their derivatives, or extrapolated.

use super::*;
use crate::integrate::{just_above, just_below};

/// How a communication step ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepEnd {
    /// The time reached: the step's end, or the event it stopped at.
    pub time: f64,
    /// The step met an event at `time` that the master is to handle (only when it handles
    /// events: `Instance::hand_events_to_master`).
    pub event: bool,
}

impl<M: Model> Instance<M> {
    pub(super) fn make_integrator(&self) -> Result<Box<Integrator>, String> {
        Integrator::new(
            self.model.clone(),
            &self.now.values.known,
            &self.now.values.integers,
            &self.now.values.booleans,
            self.table.n_states,
            self.table.indicators.len(),
            self.info.solver,
            self.solver_tolerance(),
            &self.table.state_nominals(),
            &self.table.activity_states(),
        )
        .map(Box::new)
    }

    /// The solver made afresh for the current modes and values, continuing with `step_size` (the
    /// step size the previous one had reached: after an event, a mode switch or a restored state
    /// the solver does not start over from a cautious first step), and knowing the time event
    /// the instance's solver last ended at (when it has one: not while a step has it out).
    pub(super) fn remade_integrator(&self, step_size: Option<f64>) -> Result<Box<Integrator>, String> {
        let mut integrator = self.make_integrator()?;
        integrator.step_size = step_size;
        integrator.after_time_event = self.integrator.as_ref().and_then(|i| i.after_time_event);
        Ok(integrator)
    }

    /// The solver made afresh for the current modes, continuing from `old`'s step size and
    /// time event.
    fn remade_from(&self, old: &Integrator) -> Result<Box<Integrator>, String> {
        let mut integrator = self.remade_integrator(old.step_size)?;
        integrator.after_time_event = old.after_time_event;
        Ok(integrator)
    }

    /// fmi2DoStep, fmi3DoStep: integrate from the communication point to the next one, or,
    /// when the master handles events and allows it, to the first event inside the step
    /// (before the modes change: the master enters the event phase there).
    pub fn do_step(&mut self, t: f64, h: f64) -> CallResult<StepEnd> {
        if !(h.is_finite() && h > 0.0) {
            return Err(Failure::error(format!("communication step size {h} must be a finite number > 0")));
        }
        if !t.is_finite() {
            return Err(Failure::error(format!("communication point {t} is not finite")));
        }
        let tolerance = 64.0 * f64::EPSILON * self.now.time.abs().max(t.abs()) + 1e-6 * h;
        if let Some(stop) = self.now.experiment.stop_time {
            // FMI 2.0 and 3.0: computing past a defined stop time is an error.
            if t + h > stop + tolerance {
                return Err(Failure::error(format!(
                    "the step to {} s would pass the experiment's stop time {stop} s",
                    t + h
                )));
            }
        }
        if (t - self.now.time).abs() > tolerance {
            return Err(Failure::error(format!(
                "communication point {t} s does not match this instance's time {} s (restore a saved FMU state to go back)",
                self.now.time
            )));
        }
        let t_end = t + h;
        let mut x = std::mem::take(&mut self.buffers.x);
        x.clone_from(&self.now.values.states);
        let mut slopes = std::mem::take(&mut self.buffers.slopes);
        if self.has_inputs {
            self.extrapolated_slopes(t, &mut slopes);
        }
        let event = match self.integrate(t, &mut x, t_end, &slopes) {
            Ok(event) => event,
            Err(message) => {
                (self.buffers.x, self.buffers.slopes) = (x, slopes);
                self.now.phase = Phase::StepFailed;
                return Err(Failure {
                    status: Status::Discard,
                    message: format!("step from {t} s to {t_end} s discarded, the instance stays at {t} s: {message}"),
                });
            }
        };
        // Where the step ended: its end, or the event it stopped at.
        let (reached, tau) = match event {
            Some(at) if at < t_end => (at, at - t),
            _ => (t_end, h),
        };
        if self.has_inputs {
            match &mut self.now.previous_inputs {
                Some((t_prev, previous)) => {
                    *t_prev = t;
                    previous.clone_from(&self.now.values.known);
                }
                None => self.now.previous_inputs = Some((t, self.now.values.known.clone())),
            }
            // At the end of the step the inputs are where their motion took them, so outputs
            // that depend on inputs directly (a shaft's torque) are those of t_end, not of t.
            for (i, (slope, curvature)) in slopes.iter().zip(&self.now.input_curvatures).enumerate() {
                // Only moving inputs are written: `+= 0.0` would turn an input's -0.0 into +0.0.
                if *slope != 0.0 || *curvature != 0.0 {
                    self.now.values.known[i] += slope * tau + 0.5 * curvature * tau * tau;
                    self.knowns_set = true;
                }
            }
            // Input derivatives describe one step; the master sets new values (and derivatives)
            // at the next communication point.
            self.now.input_slopes.fill(0.0);
            self.now.input_curvatures.fill(0.0);
        }
        std::mem::swap(&mut self.now.values.states, &mut x);
        (self.buffers.x, self.buffers.slopes) = (x, slopes);
        self.now.time = reached;
        self.stale = true;
        if event.is_some() {
            // Should the master step on without handling the event, the next step settles the
            // modes at its start.
            self.knowns_set = true;
        }
        Ok(StepEnd { time: reached, event: event.is_some() })
    }

    /// The input slopes for a step from `t`: the master's input derivatives where it gave them;
    /// with `extrapolate_inputs` on, the line through the previous and the current communication
    /// point for the other inputs.
    pub(super) fn extrapolated_slopes(&self, t: f64, slopes: &mut Vec<f64>) {
        slopes.clone_from(&self.now.input_slopes);
        let on = self.runtime.extrapolate_inputs.is_some_and(|b| self.now.values.booleans[b.index()]);
        if let (true, Some((t_prev, previous))) = (on, &self.now.previous_inputs) {
            if t > *t_prev {
                for var in self.table.variables.iter().filter(|v| v.causality == crate::variables::Causality::Input) {
                    if let Slot::Known(i) = var.slot {
                        if self.now.input_slopes[i] == 0.0 && self.now.input_curvatures[i] == 0.0 {
                            slopes[i] = (self.now.values.known[i] - previous[i]) / (t - t_prev);
                        }
                    }
                }
            }
        }
    }

    /// Integrates from `t` to `t_end`, stopping at every time event the model announces and at
    /// every zero crossing of an event indicator, where the modes are updated and the solver
    /// restarts; or, when the step stops at events (`stops_at_events`), returns the time of the
    /// first one, the modes unchanged (an event at `t_end` is returned as `t_end`). On failure
    /// the modes are those of `t` again (the step is discarded).
    pub(super) fn integrate(&mut self, t: f64, x: &mut [f64], t_end: f64, slopes: &[f64]) -> Result<Option<f64>, String> {
        let mut integrator = self.integrator.take().ok_or("the instance has no ODE solver (initialization did not finish)")?;
        let (step_size, after_time_event) = (integrator.step_size, integrator.after_time_event);
        // Without modes, no integer changes in a step.
        let mut modes = std::mem::take(&mut self.buffers.modes);
        if self.has_modes {
            modes.clone_from(&self.now.values.integers);
        }
        let curvatures = std::mem::take(&mut self.now.input_curvatures);
        let mut result = self.integrate_with(&mut integrator, t, x, t_end, slopes, &curvatures);
        self.now.input_curvatures = curvatures;
        if result.is_err() {
            // The instance stays at t: so does what the solver knows of a time event there.
            integrator.after_time_event = after_time_event;
        }
        if result.is_err() && self.has_modes && self.now.values.integers != modes {
            self.now.values.integers.copy_from_slice(&modes);
            match self.remade_integrator(step_size) {
                Ok(mut made) => {
                    made.after_time_event = after_time_event;
                    integrator = made
                }
                Err(message) => result = Err(message),
            }
        }
        self.buffers.modes = modes;
        self.integrator = Some(integrator);
        result
    }

    pub(super) fn integrate_with(&mut self, integrator: &mut Integrator, t: f64, x: &mut [f64], t_end: f64, slopes: &[f64], curvatures: &[f64]) -> Result<Option<f64>, String> {
        // Inputs or tunable parameters set at this communication point may change the modes
        // (a force above the static friction breaks a stuck body loose) without any indicator
        // crossing zero during integration. When nothing was set since the last step, the modes
        // are those the last step left consistent (it stopped at every crossing up to here).
        let known = std::mem::take(&mut self.now.values.known);
        let settled = if self.has_modes && self.knowns_set { self.settle_modes(t, &known, x) } else { Ok((false, false)) };
        self.now.values.known = known;
        if settled?.0 {
            *integrator = *self.remade_from(integrator)?;
        }
        let mut now = t;
        // Whether `now` is a time event: the solver then starts just above it (see below).
        let mut at_time_event = false;
        let mut first = true;
        let (mut last_event, mut at_one_instant) = (f64::NEG_INFINITY, 0usize);
        // One budget of internal steps for the whole communication step, across its events.
        let mut budget = crate::integrate::MAX_INTERNAL_STEPS;
        // Without inputs nothing moves (the slopes are zero): no need to look.
        let motion = if self.has_inputs { InputMotion::new(slopes, curvatures, t) } else { InputMotion::still(slopes) };
        for _ in 0..MAX_EVENTS_PER_STEP {
            let v = &self.now.values;
            let k = Knowns::new(now, &v.known, x, &v.integers, &v.booleans);
            // An event within rounding of the step's end is taken as the end (a master's
            // float time 9.999999999999897 s for an event at 10 s).
            let tiny = negligible_interval(t_end);
            if first {
                // A step that starts at the time event the last one ended at (or returned at to
                // a master handling events) starts past it: the integrator knows (the model may
                // no longer name that instant once its modes were updated there).
                first = false;
                at_time_event = integrator.after_time_event.is_some_and(|e| e <= now && now - e <= negligible_interval(now));
            }
            let event = self.model.next_time_event(&k, now).filter(|e| *e > now);
            let next = match event {
                Some(event) if event < t_end - tiny => event,
                _ => t_end,
            };
            // How far the explicit solver may step past `next` (it interpolates back): not past
            // the next time event, nor past a defined stop time (the model may be invalid there).
            let limit = match event {
                Some(event) if next == t_end => event.max(t_end),
                Some(_) => next,
                None => f64::INFINITY,
            };
            let limit = self.now.experiment.stop_time.map_or(limit, |stop| limit.min(stop)).max(next);
            // The solver never evaluates the equations at a time event that starts or ends its
            // segment, where they jump (whichever side the model puts the jump on, `t >= t_e` or
            // `t > t_e`): a segment ending at one ends at the float just below it, one starting
            // at one starts at the float just above it (x is continuous there; only f jumps).
            // No step straddles the jump, and none has it in a stage.
            let solver_end = match event {
                Some(e) if e <= next => just_below(e),
                _ => next,
            };
            let limit = if event == Some(limit) { just_below(limit) } else { limit }.max(solver_end);
            let solver_start = if at_time_event { just_above(now) } else { now };
            if at_time_event {
                integrator.start_after_time_event(now);
            }
            let knowns_set = std::mem::replace(&mut self.knowns_set, false);
            let how = if solver_end > solver_start {
                let how = integrator.advance(&v.known, &motion, knowns_set, solver_start, x, solver_end, limit, &mut budget)?;
                integrator.after_time_event = match (&how, event) {
                    (Advanced::Reached, Some(e)) if solver_end != next => Some(e),
                    _ => None,
                };
                how
            } else {
                // Nothing to integrate: the step ends at the time event it started at (it stays
                // the one the solver last ended at), or the next one is a float away.
                self.knowns_set |= knowns_set;
                integrator.restart();
                if solver_end != next {
                    integrator.after_time_event = event;
                }
                Advanced::Reached
            };
            let how = match how {
                Advanced::Reached if solver_end != next => {
                    // It ended just below a time event: what follows starts afresh past it (the
                    // stepper's last step, ending below the event, is not continued), and an
                    // event indicator the model makes jump there is a state event at the
                    // event (the solver, stopping short of it, saw none).
                    integrator.restart();
                    let e = event.expect("a segment ends below a time event only when there is one");
                    match integrator.jump_at(solver_end, e, x) {
                        Some(indicator) => Advanced::Crossing { time: e, indicator },
                        None => how,
                    }
                }
                how => how,
            };
            match how {
                Advanced::Reached if next == t_end => {
                    // A time event at the step's end is the master's to handle, when it does.
                    let at_end = self.stops_at_events && event.is_some_and(|e| e <= t_end + tiny);
                    return Ok(at_end.then_some(t_end));
                }
                Advanced::Reached => {
                    self.logger.log(Status::Ok, &format!("time event at t = {next} s"));
                    if self.stops_at_events {
                        return Ok(Some(next));
                    }
                    now = next;
                    at_time_event = true;
                }
                Advanced::Crossing { time, indicator } => {
                    if time - last_event <= negligible_interval(time) {
                        at_one_instant += 1;
                        if at_one_instant >= MAX_EVENTS_AT_ONE_INSTANT {
                            return Err(format!(
                                "{MAX_EVENTS_AT_ONE_INSTANT} state events at t = {time} s without time advancing \
                                 (the modes chatter: event indicator '{}')",
                                self.table.indicators[indicator].0
                            ));
                        }
                    } else {
                        at_one_instant = 0;
                    }
                    last_event = time;
                    // At a time event (an indicator that jumps there): what follows starts past it.
                    at_time_event = event == Some(time);
                    self.logger.log(Status::Ok, &format!("state event at t = {time} s: '{}' crossed zero", self.table.indicators[indicator].0));
                    if let Some(counter) = self.runtime.state_events {
                        self.now.values.integers[counter.0] = self.now.values.integers[counter.0].saturating_add(1);
                    }
                    if self.stops_at_events {
                        return Ok(Some(time));
                    }
                    now = time;
                }
            }
            // The modes after the event (a time event may change them too: a voltage step can
            // break a stuck body loose). The solver is re-made with the new modes.
            let known = self.knowns_moved_to(now, t, slopes, curvatures);
            let (modes_changed, _) = self.settle_modes(now, &known, x)?;
            if modes_changed {
                *integrator = *self.remade_from(integrator)?;
            }
        }
        Err(format!("more than {MAX_EVENTS_PER_STEP} events in one communication step"))
    }

    /// The known reals at `now` with the inputs moved along their derivatives since `since`.
    pub(super) fn knowns_moved_to(&self, now: f64, since: f64, slopes: &[f64], curvatures: &[f64]) -> Vec<f64> {
        let tau = now - since;
        (0..self.now.values.known.len())
            .map(|i| self.now.values.known[i] + slopes[i] * tau + 0.5 * curvatures[i] * tau * tau)
            .collect()
    }
}
