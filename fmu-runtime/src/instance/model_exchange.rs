//! Model Exchange: the master integrates the states; the instance evaluates and reports events.

use super::*;

impl<M: Model> Instance<M> {
    /// Model Exchange, and Co-Simulation when the master handles events (after a step that
    /// returned at an event, or to change inputs discretely at a communication point).
    pub fn enter_event_mode(&mut self) -> CallResult {
        if self.interface == Interface::CoSimulation && !self.event_mode_used {
            return Err(Failure::error(
                "the master did not ask to handle events (eventModeUsed = false at instantiation), so this instance handles them inside its steps and never enters event mode",
            ));
        }
        self.now.phase = Phase::Event;
        Ok(())
    }

    /// Co-Simulation: back from the event phase to stepping.
    pub fn enter_step_mode(&mut self) -> CallResult {
        self.now.phase = Phase::Stepping;
        Ok(())
    }

    /// fmi2NewDiscreteStates: the model's modes are updated until they settle (so one call
    /// suffices: newDiscreteStatesNeeded is false); the next time event is the model's next kink
    /// after now.
    ///
    /// valuesOfContinuousStatesChanged is reported whenever a mode or a state changed, not only
    /// when a state was re-initialized (docs/DESIGN.md, "Model Exchange events any integrator
    /// survives"): a new mode changes the right-hand side, and its indicator may start exactly
    /// at zero (a stuck body breaking loose has speed 0, the indicator of its slipping mode). A
    /// master that keeps its integrator's history would then find a root at its restart point
    /// (CVODE: "root found at and very near t"); told that the states changed, it restarts, and
    /// a zero at the start of an integration is no crossing.
    pub fn new_discrete_states(&mut self) -> CallResult<EventInfo> {
        let (known, mut x) = (self.now.values.known.clone(), self.now.values.states.clone());
        let (modes_changed, states_changed) = self.settle_modes(self.now.time, &known, &mut x).map_err(Failure::error)?;
        if states_changed {
            self.now.values.states = x;
        }
        if modes_changed || states_changed {
            // Co-Simulation counted the event where its step stopped, as a step handling its
            // events itself does.
            if let (Some(counter), Interface::ModelExchange) = (self.runtime.state_events, self.interface) {
                self.now.values.integers[counter.0] = self.now.values.integers[counter.0].saturating_add(1);
            }
            // Co-Simulation's solver goes on with the new modes (and its step size).
            if let Some(step_size) = self.integrator.as_ref().map(|i| i.step_size) {
                self.integrator = Some(self.remade_integrator(step_size).map_err(Failure::error)?);
            }
            self.stale = true;
            self.debug(&format!("event at t = {} s: modes or states changed", self.now.time));
        }
        let v = &self.now.values;
        let k = Knowns::new(self.now.time, &v.known, &v.states, &v.integers, &v.booleans);
        let next_event_time = self.model.next_time_event(&k, self.now.time);
        Ok(EventInfo { next_event_time, values_changed: modes_changed || states_changed, ..EventInfo::default() })
    }

    pub fn enter_continuous_time_mode(&mut self) -> CallResult {
        self.now.phase = Phase::ContinuousTime;
        Ok(())
    }

    pub fn set_time(&mut self, t: f64) -> CallResult {
        if !t.is_finite() {
            return Err(Failure::error(format!("time {t} is not finite")));
        }
        self.now.time = t;
        self.stale = true;
        Ok(())
    }

    pub(super) fn check_length(&self, n: usize, what: &str, expected: usize) -> CallResult {
        if n != expected {
            return Err(Failure::error(format!("{n} {what} given, this FMU has {expected}")));
        }
        Ok(())
    }

    pub fn set_continuous_states(&mut self, x: &[f64]) -> CallResult {
        self.check_length(x.len(), "continuous states", self.table.n_states)?;
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            let name = &self.table.variables[self.table.state_value_reference[i] as usize].name;
            return Err(Failure::error(format!("state {name} = {} is not finite", x[i])));
        }
        self.now.values.states.copy_from_slice(x);
        self.stale = true;
        Ok(())
    }

    pub fn get_continuous_states(&mut self, x: &mut [f64]) -> CallResult {
        self.check_length(x.len(), "continuous states", self.table.n_states)?;
        self.refresh_only(Fresh::default());
        x.copy_from_slice(&self.now.values.states);
        Ok(())
    }

    pub fn get_derivatives(&mut self, dx: &mut [f64]) -> CallResult {
        self.check_length(dx.len(), "derivatives", self.table.n_states)?;
        self.refresh_only(Fresh { derivatives: true, ..Fresh::default() });
        dx.copy_from_slice(&self.now.values.derivatives);
        Ok(())
    }

    pub fn get_nominals(&mut self, nominals: &mut [f64]) -> CallResult {
        self.check_length(nominals.len(), "nominals", self.table.n_states)?;
        nominals.copy_from_slice(&self.table.state_nominals());
        Ok(())
    }

    /// fmi2GetEventIndicators: the model's indicators at the current time, states and modes.
    pub fn get_event_indicators(&mut self, z: &mut [f64]) -> CallResult {
        self.check_length(z.len(), "event indicators", self.table.indicators.len())?;
        self.refresh();
        let v = &self.now.values;
        let k = Knowns::new(self.now.time, &v.known, &v.states, &v.integers, &v.booleans);
        z.fill(0.0);
        self.model.event_indicators(&k, &mut EventIndicators::new(z));
        Ok(())
    }

    /// fmi2CompletedIntegratorStep: (enter event mode, terminate): never needed here.
    pub fn completed_integrator_step(&mut self) -> CallResult<(bool, bool)> {
        Ok((false, false))
    }
}
