//! fmi2Get*/fmi2Set* (fmi3Get*/fmi3Set*): reading a variable recomputes only what it needs;
//! a set is checked in full before any value is written.

use super::*;

impl<M: Model> Instance<M> {
    /// fmi2GetReal/Integer/Boolean.
    pub fn get<T: FmiValue>(&mut self, vrs: &[u32], out: &mut [T]) -> CallResult {
        let mut need = Fresh::default();
        for vr in vrs {
            match self.variable(*vr, T::TYPE)?.slot {
                Slot::Calculated(i) if self.table.balance.is_some_and(|b| i == b.residual || i == b.relative) => need.balance = true,
                Slot::Calculated(_) => need.calculated = true,
                Slot::Derivative(_) => need.derivatives = true,
                _ => {}
            }
        }
        // Reading only knowns (states, parameters, inputs) evaluates nothing, but a pending
        // initialization still fills in the calculated states.
        self.refresh_only(need);
        for (vr, o) in vrs.iter().zip(out.iter_mut()) {
            *o = T::read(&self.now.values, self.table.variables[*vr as usize].slot);
        }
        Ok(())
    }

    /// fmi2SetReal/Integer/Boolean: all values are checked before any is written.
    pub fn set<T: FmiValue>(&mut self, vrs: &[u32], vals: &[T]) -> CallResult {
        let before_init = self.now.phase.is_before_initialization_end();
        for (vr, v) in vrs.iter().zip(vals) {
            let var = self.variable(*vr, T::TYPE)?;
            let settable = if before_init { var.is_settable_before_initialization() } else { var.is_settable_while_stepping() };
            if !settable {
                let why = match (var.causality, before_init) {
                    (crate::variables::Causality::Parameter, false) => "a fixed parameter cannot change after initialization",
                    (crate::variables::Causality::Output, _) => "an output is computed by the FMU",
                    _ if var.derivative_of.is_some() => "a derivative is computed by the FMU",
                    _ if !before_init => "only inputs and tunable parameters can be set while stepping",
                    _ => "it is computed by the FMU",
                };
                return Err(Failure::error(format!("cannot set '{}' {}: {why}", var.name, self.now.phase.words())));
            }
            T::check(var, *v).map_err(|e| Failure::error(format!("refused: {e}")))?;
        }
        for (vr, v) in vrs.iter().zip(vals) {
            let slot = self.table.variables[*vr as usize].slot;
            T::write(&mut self.now.values, slot, *v);
            if let Slot::Known(i) = slot {
                // A new input value without derivatives is held over the next step.
                self.now.input_slopes[i] = 0.0;
                self.now.input_curvatures[i] = 0.0;
            }
        }
        self.stale = true;
        self.knowns_set = true;
        Ok(())
    }
}
