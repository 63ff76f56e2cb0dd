//! FMU states: snapshots of values, kept behind handles, serialized and restored bit-identically.

use super::*;

impl<M: Model> Instance<M> {
    /// The instance's situation and the solver's own bits (step size, the step it would continue,
    /// where its kept Jacobian was evaluated, the time event it last ended at).
    pub(super) fn snapshot(&self) -> Snapshot {
        Snapshot {
            situation: self.now.clone(),
            step_size: self.integrator.as_ref().and_then(|i| i.step_size),
            lookahead: self.integrator.as_ref().and_then(|i| i.lookahead()),
            jacobian: self.integrator.as_ref().and_then(|i| i.jacobian_point()),
            after_time_event: self.integrator.as_ref().and_then(|i| i.after_time_event),
        }
    }

    /// Back to a saved situation; the caches are stale, and a Co-Simulation solver is made
    /// afresh with the saved step size (continuing the saved step, if any; making the saved
    /// Jacobian again, if any).
    pub(super) fn restore(&mut self, s: Snapshot) -> CallResult {
        self.now = s.situation;
        self.stale = true;
        self.knowns_set = true;
        self.integrator = None;
        if !self.now.phase.is_before_initialization_end() && self.interface == Interface::CoSimulation {
            let mut integrator = self.remade_integrator(s.step_size).map_err(Failure::error)?;
            if let Some(lookahead) = &s.lookahead {
                integrator.resume_lookahead(lookahead, self.now.time, &self.now.values.states);
            }
            if let Some(point) = &s.jacobian {
                integrator.restore_jacobian(point);
            }
            integrator.after_time_event = s.after_time_event;
            self.integrator = Some(integrator);
        }
        Ok(())
    }

    /// fmi2GetFMUstate: a new handle (`existing` = None) or overwrite a live one.
    pub fn get_fmu_state(&mut self, existing: Option<usize>) -> CallResult<usize> {
        let s = self.snapshot();
        match existing {
            None => self.snapshots.insert(s).map_err(Failure::error),
            Some(h) if self.snapshots.replace(h, s) => Ok(h),
            Some(h) => Err(Failure::error(format!("FMU state {h:#x} is not a live state of this instance (freed or never made here)"))),
        }
    }

    pub fn set_fmu_state(&mut self, handle: usize) -> CallResult {
        let s = self
            .snapshots
            .get(handle)
            .cloned()
            .ok_or_else(|| Failure::error(format!("FMU state {handle:#x} is not a live state of this instance (freed or never made here)")))?;
        self.restore(s)?;
        self.debug(&format!("restored the FMU state of t = {} s", self.now.time));
        Ok(())
    }

    pub fn free_fmu_state(&mut self, handle: usize) -> CallResult {
        if self.snapshots.remove(handle) {
            Ok(())
        } else {
            Err(Failure::error(format!("FMU state {handle:#x} was already freed or was never made by this instance")))
        }
    }

    pub fn serialize_fmu_state(&self, handle: usize) -> CallResult<Vec<u8>> {
        self.snapshots
            .get(handle)
            .map(|s| s.serialize(self.guid))
            .ok_or_else(|| Failure::error(format!("FMU state {handle:#x} is not a live state of this instance")))
    }

    pub fn deserialize_fmu_state(&mut self, bytes: &[u8], existing: Option<usize>) -> CallResult<usize> {
        let t = &self.table;
        let shape = Shape { known: t.n_known, calculated: t.n_calculated, states: t.n_states, integers: t.n_integers, booleans: t.n_booleans };
        let s = Snapshot::deserialize(bytes, self.guid, &shape).map_err(Failure::error)?;
        match existing {
            None => self.snapshots.insert(s).map_err(Failure::error),
            Some(h) if self.snapshots.replace(h, s) => Ok(h),
            Some(h) => Err(Failure::error(format!("FMU state {h:#x} is not a live state of this instance"))),
        }
    }
}
