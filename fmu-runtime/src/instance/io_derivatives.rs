//! Input derivatives given by the master and output derivatives computed for it (Co-Simulation).

use super::*;

impl<M: Model> Instance<M> {
    /// fmi2SetRealInputDerivatives: first and second derivatives of inputs, used over the next
    /// step (canInterpolateInputs).
    pub fn set_input_derivatives(&mut self, vrs: &[u32], orders: &[i32], values: &[f64]) -> CallResult {
        let mut updates = Vec::with_capacity(vrs.len());
        for ((vr, order), value) in vrs.iter().zip(orders).zip(values) {
            let var = self.variable(*vr, BaseType::Real)?;
            let (Slot::Known(i), crate::variables::Causality::Input) = (var.slot, var.causality) else {
                return Err(Failure::error(format!("'{}' is not an input", var.name)));
            };
            if !(1..=2).contains(order) {
                return Err(Failure::error(format!("derivative order {order} of '{}': this FMU takes orders 1 and 2", var.name)));
            }
            if !value.is_finite() {
                return Err(Failure::error(format!("derivative of '{}' = {value} is not finite", var.name)));
            }
            updates.push((i, *order, *value));
        }
        self.knowns_set = true;
        for (i, order, value) in updates {
            if order == 1 {
                self.now.input_slopes[i] = value;
            } else {
                self.now.input_curvatures[i] = value;
            }
        }
        Ok(())
    }

    /// fmi2GetRealOutputDerivatives, order 1: dy/dt along the current motion (states moving with
    /// their derivatives, inputs with the derivatives set for the next step, time), by central
    /// differences over a time step h = 1e-6 of the fastest state's time scale (|x| / |dx/dt|).
    pub fn output_derivatives(&mut self, vrs: &[u32], orders: &[i32], out: &mut [f64]) -> CallResult {
        for (vr, order) in vrs.iter().zip(orders) {
            let var = self.variable(*vr, BaseType::Real)?;
            if var.causality != crate::variables::Causality::Output {
                return Err(Failure::error(format!("'{}' is not an output", var.name)));
            }
            if *order != 1 {
                return Err(Failure::error(format!("derivative order {order} of '{}': maxOutputDerivativeOrder is 1", var.name)));
            }
        }
        self.refresh();
        let nominals = self.table.state_nominals();
        let v = &self.now.values;
        let time_scale = v
            .states
            .iter()
            .zip(&v.derivatives)
            .zip(&nominals)
            .filter(|(( _, d), _)| **d != 0.0)
            .map(|((x, d), n)| x.abs().max(n.abs()) / d.abs())
            .fold(1.0f64, f64::min);
        let h = 1e-6 * time_scale;
        let at = |sign: f64| {
            let x: Vec<f64> = v.states.iter().zip(&v.derivatives).map(|(x, d)| x + sign * h * d).collect();
            let k: Vec<f64> = (0..v.known.len())
                .map(|i| v.known[i] + sign * h * self.now.input_slopes[i] + 0.5 * h * h * self.now.input_curvatures[i])
                .collect();
            let (mut der, mut calc) = (v.derivatives.clone(), v.calculated.clone());
            evaluate(&*self.model, &self.table, self.now.time + sign * h, &k, &x, &v.integers, &v.booleans, &mut der, &mut calc);
            calc
        };
        let (plus, minus) = (at(1.0), at(-1.0));
        for (o, vr) in out.iter_mut().zip(vrs) {
            let Slot::Calculated(i) = self.table.variables[*vr as usize].slot else { unreachable!("an output") };
            *o = (plus[i] - minus[i]) / (2.0 * h);
        }
        Ok(())
    }
}
