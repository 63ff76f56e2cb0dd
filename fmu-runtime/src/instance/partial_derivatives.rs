//! Directional derivatives of the unknowns with respect to the knowns, from the equations.

use super::*;

impl<M: Model> Instance<M> {
    /// fmi2GetDirectionalDerivative: d(unknowns) = J d(knowns), by central differences of the
    /// model's equations along the direction `dv_known` (step 1e-7 of the knowns' scale, refined
    /// near kinks; about 1e-9 relative accuracy on smooth equations). Knowns: states, inputs, parameters;
    /// unknowns: state derivatives, outputs, locals and calculated parameters.
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
        let (known, states) = (&self.now.values.known, &self.now.values.states);
        let value = |j: usize| match slots[j].0 {
            Slot::State(s) => states[s],
            Slot::Known(i) => known[i],
            _ => unreachable!("checked above: a known"),
        };
        if dv_known.iter().all(|v| *v == 0.0) {
            dv_unknown.fill(0.0);
            return Ok(());
        }
        // Step: 1e-7 of each seeded known's scale max(|value|, nominal) (nominal 1 where
        // undeclared), the smallest over the seed. Then up to four refinements by 10: for each
        // unknown the first estimate that agrees with the next finer one (to 1e-4: far above
        // rounding, far below the jump of a straddled kink) is kept, so a kink near the point
        // (an activity's |power|) is not straddled, while smooth equations keep the first
        // step's small rounding error. Agreement is judged against the largest of the five
        // estimates: where the first step straddles a kink and the function is flat on the
        // near side (MotorFan's rigid reducer 6e-6 rad/s after standstill, whose efficiency
        // switches with the sign of the speed), the finer estimates are rounding noise around
        // zero, which never agree with each other by their own size; by the jump's they do.
        // Where none agree, the finer of the two neighbouring estimates that differ least
        // stands (an estimate that shrinks with the step, the zero slope of the fan's w |w| at
        // w = 0, ends on its finest).
        let h0 = (0..slots.len())
            .filter(|j| dv_known[*j] != 0.0)
            .map(|j| 1e-7 * value(j).abs().max(slots[j].1) / dv_known[j].abs())
            .fold(f64::INFINITY, f64::min);
        let central = |h: f64| {
            let at = |sign: f64| {
                let (mut k, mut x) = (known.clone(), states.clone());
                for (j, (slot, _)) in slots.iter().enumerate() {
                    match *slot {
                        Slot::State(s) => x[s] += sign * h * dv_known[j],
                        Slot::Known(i) => k[i] += sign * h * dv_known[j],
                        _ => unreachable!("checked above: a known"),
                    }
                }
                let (mut der, mut calc) = (self.now.values.derivatives.clone(), self.now.values.calculated.clone());
                let v = &self.now.values;
                if initializing {
                    // A failure leaves NaN in the calculated states, and so in the derivative.
                    let _ = crate::model::initialize_states(&*self.model, &self.table, self.now.time, &k, &v.integers, &v.booleans, &mut x);
                }
                evaluate(&*self.model, &self.table, self.now.time, &k, &x, &v.integers, &v.booleans, &mut der, &mut calc);
                (der, calc, x)
            };
            let ((der_plus, calc_plus, x_plus), (der_minus, calc_minus, x_minus)) = (at(1.0), at(-1.0));
            // Each estimate with its rounding noise: ROUNDING_ULPS ulps of the larger of the two
            // values, over 2h.
            let estimate = |plus: f64, minus: f64| ((plus - minus) / (2.0 * h), ROUNDING_ULPS * f64::EPSILON * plus.abs().max(minus.abs()) / (2.0 * h));
            unknowns
                .iter()
                .map(|vr| {
                    let var = &self.table.variables[*vr as usize];
                    match var.slot {
                        Slot::Derivative(i) => estimate(der_plus[i], der_minus[i]),
                        Slot::Calculated(i) => estimate(calc_plus[i], calc_minus[i]),
                        Slot::State(s) => estimate(x_plus[s], x_minus[s]),
                        _ => unreachable!("checked above: an unknown"),
                    }
                })
                .collect::<Vec<(f64, f64)>>()
        };
        let estimates: Vec<Vec<(f64, f64)>> = (0..5).map(|r| central(h0 / 10f64.powi(r))).collect();
        for (u, out) in dv_unknown.iter_mut().enumerate() {
            let e = |r: usize| estimates[r][u].0;
            let noise = |r: usize| estimates[r][u].1;
            let scale = (0..5).map(|r| e(r).abs()).fold(f64::MIN_POSITIVE, f64::max);
            // Two neighbouring estimates agree within 1e-4 of the scale, or within their
            // rounding noise: where the unknown barely moves against its own size (PowerSteering's
            // 35 W worm loss moves by 0.02 W per radian of the arm's stretch), the finer steps'
            // estimates are rounding noise, and two of them that both come out exactly 0 must
            // not outvote the first, sound one.
            let agree = |r: usize| (e(r) - e(r + 1)).abs() <= (1e-4 * scale).max(noise(r) + noise(r + 1));
            let differs = |r: usize| (e(r) - e(r + 1)).abs();
            let steadiest = || (0..4).min_by(|a, b| differs(*a).total_cmp(&differs(*b))).map_or(0, |r| r + 1);
            *out = match (0..4).find(|r| agree(*r)) {
                Some(r) => e(r),
                None => e(steadiest()),
            };
        }
        // The activity and share outputs the runtime itself writes: exactly.
        if !self.table.elements.is_empty() {
            let mut d_states = vec![0.0; self.table.n_states];
            for (j, (slot, _)) in slots.iter().enumerate() {
                if let Slot::State(s) = *slot {
                    d_states[s] += dv_known[j];
                }
            }
            for (out, vr) in dv_unknown.iter_mut().zip(unknowns) {
                if let Slot::Calculated(y) = self.table.variables[*vr as usize].slot {
                    if let Some(d) = crate::elements::output_derivative(&self.table.elements, &self.now.values.states, &d_states, y) {
                        *out = d;
                    }
                }
            }
        }
        Ok(())
    }
}
