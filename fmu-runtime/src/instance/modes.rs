//! The model's discrete modes, updated at an event until they settle.

use super::*;

impl<M: Model> Instance<M> {
    /// Runs `Model::update_modes` at (time, known, x) until neither a mode nor a state changes;
    /// returns (modes changed, states changed). Only the model's modes can change: the handles
    /// of `ModeUpdate` are the modes it declared.
    pub(super) fn settle_modes(&mut self, time: f64, known: &[f64], x: &mut [f64]) -> Result<(bool, bool), String> {
        let mut modes = std::mem::take(&mut self.buffers.trial_modes);
        let mut states = std::mem::take(&mut self.buffers.trial_states);
        let result = self.settle_modes_with(time, known, x, &mut modes, &mut states);
        (self.buffers.trial_modes, self.buffers.trial_states) = (modes, states);
        result
    }

    pub(super) fn settle_modes_with(&mut self, time: f64, known: &[f64], x: &mut [f64], modes: &mut Vec<i32>, states: &mut Vec<f64>) -> Result<(bool, bool), String> {
        let (mut modes_changed, mut states_changed) = (false, false);
        for _ in 0..MAX_MODE_ITERATIONS {
            modes.clone_from(&self.now.values.integers);
            states.clear();
            states.extend_from_slice(x);
            let reinitialized = {
                let k = Knowns::new(time, known, x, &self.now.values.integers, &self.now.values.booleans);
                let mut next = ModeUpdate::new(modes, states);
                self.model.update_modes(&k, &mut next);
                next.reinitialized()
            };
            let changed = *modes != self.now.values.integers;
            if !changed && !reinitialized {
                return Ok((modes_changed, states_changed));
            }
            if let Some(i) = states.iter().position(|v| !v.is_finite()) {
                return Err(format!("the mode update at t = {time} s set state {i} to {}", states[i]));
            }
            self.now.values.integers.copy_from_slice(modes);
            x.copy_from_slice(states);
            modes_changed |= changed;
            states_changed |= reinitialized;
            self.stale = true;
        }
        Err(format!("the discrete modes did not settle after {MAX_MODE_ITERATIONS} updates at t = {time} s"))
    }

    /// At the end of initialization: the modes that fit the start values (e.g. a body at rest
    /// sticks). A failure moves the instance to the Error mode.
    pub(super) fn settle_initial_modes(&mut self) -> CallResult {
        let (known, mut x) = (self.now.values.known.clone(), self.now.values.states.clone());
        if let Err(message) = self.settle_modes(self.now.time, &known, &mut x) {
            self.now.phase = Phase::Error;
            return Err(Failure::error(format!("initialization failed: {message}")));
        }
        self.now.values.states = x;
        Ok(())
    }
}
