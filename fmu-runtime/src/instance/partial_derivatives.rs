//! Directional derivatives of the unknowns with respect to the knowns, from the equations.

use super::*;
use crate::real::Dual;

impl<M: Model> Instance<M> {
    /// fmi2GetDirectionalDerivative: d(unknowns) = J d(knowns) along the direction `dv_known`,
    /// exact: the model's equations evaluated once over [`Dual`] numbers (forward-mode automatic
    /// differentiation). Knowns: states, inputs, parameters; unknowns: state derivatives,
    /// outputs, locals and calculated parameters (and the calculated states during
    /// initialization). Where the equations branch, the derivative is that of the branch taken.
    pub fn directional_derivative(&mut self, unknowns: &[u32], knowns: &[u32], dv_known: &[f64], dv_unknown: &mut [f64]) -> CallResult {
        // Each seeded known: where it lives (`Slot::Known` or `Slot::State`) and its nominal.
        let mut slots = Vec::with_capacity(knowns.len());
        for vr in knowns {
            let var = self.variable(*vr, BaseType::Real)?;
            if !matches!(var.slot, Slot::Known(_) | Slot::State(_)) {
                return Err(Failure::error(format!("'{}' is not a known (a state, an input or a parameter)", var.name)));
            }
            slots.push((var.slot, var.nominal.unwrap_or(1.0).abs()));
        }
        // During initialization the calculated states are unknowns too, computed from the knowns.
        let initializing = self.now.phase.is_before_initialization_end();
        for vr in unknowns {
            let var = self.variable(*vr, BaseType::Real)?;
            let calculated_state = initializing && var.initial == Some(crate::variables::Initial::Calculated) && self.table.state_index(var).is_some();
            if !(matches!(var.slot, Slot::Calculated(_) | Slot::Derivative(_)) || calculated_state) {
                return Err(Failure::error(format!("'{}' is not an unknown (a derivative or a computed value)", var.name)));
            }
        }
        if let Some(j) = dv_known.iter().position(|v| !v.is_finite()) {
            return Err(Failure::error(format!("the seed of known {} is not finite", knowns[j])));
        }
        self.refresh();
        if dv_known.iter().all(|v| *v == 0.0) {
            dv_unknown.fill(0.0);
            return Ok(());
        }
        // One evaluation of the equations over dual numbers, the knowns moving along the seed:
        // the derivative part of every unknown is its directional derivative, exact to
        // round-off (docs/DESIGN.md, "Exact derivatives").
        let v = &self.now.values;
        let mut known: Vec<Dual> = v.known.iter().map(|&x| Dual::from(x)).collect();
        let mut states: Vec<Dual> = v.states.iter().map(|&x| Dual::from(x)).collect();
        for (j, (slot, _)) in slots.iter().enumerate() {
            match *slot {
                Slot::State(s) => states[s].eps += dv_known[j],
                Slot::Known(i) => known[i].eps += dv_known[j],
                _ => unreachable!("checked above: a known"),
            }
        }
        if initializing {
            // A failure leaves NaN in the calculated states, and so in the derivatives.
            let _ = crate::model::initialize_states(&*self.model, &self.table, self.now.time, &known, &v.integers, &v.booleans, &mut states);
        }
        let mut der: Vec<Dual> = v.derivatives.iter().map(|&x| Dual::from(x)).collect();
        let mut calc: Vec<Dual> = v.calculated.iter().map(|&x| Dual::from(x)).collect();
        evaluate(&*self.model, &self.table, self.now.time, &known, &states, &v.integers, &v.booleans, &mut der, &mut calc);
        for (out, vr) in dv_unknown.iter_mut().zip(unknowns) {
            *out = match self.table.variables[*vr as usize].slot {
                Slot::Derivative(i) => der[i].eps,
                Slot::Calculated(i) => calc[i].eps,
                Slot::State(s) => states[s].eps,
                _ => unreachable!("checked above: an unknown"),
            };
        }
        Ok(())
    }
}
