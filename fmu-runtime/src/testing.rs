//! Helpers for a model crate's unit tests that set values and states by name on the runtime's
//! own stores (the energy-balance tests of MotorFan, TorqueSensor and TractionMotorThermal), and
//! the drive trains of any size the runtime's own tests and examples step (`chains`), and an
//! instance set up and initialized by name for the runtime's integration tests.

pub mod chains;

use crate::instance::Instance;
use crate::log::Logger;
use crate::values::Values;
use crate::variables::{Slot, VariableTable};
use crate::Model;

/// A Co-Simulation instance of `M` out of initialization (no logger, start time 0, the default
/// tolerance), with the given integer and real parameters set by name first.
pub fn initialized_with<M: Model>(integers: &[(&str, i32)], reals: &[(&str, f64)]) -> Instance<M> {
    let mut i = Instance::<M>::new("{test}", Logger::silent());
    let vr = |i: &Instance<M>, name: &str| i.table().by_name(name).unwrap_or_else(|| panic!("{name}")).value_reference;
    for (name, value) in integers {
        let r = vr(&i, name);
        i.set(&[r], &[*value]).unwrap();
    }
    for (name, value) in reals {
        let r = vr(&i, name);
        i.set(&[r], &[*value]).unwrap();
    }
    i.setup_experiment(None, 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    i
}

/// Sets a known real, state, integer or boolean by its FMI name (a nonzero `value` is true).
pub fn set(table: &VariableTable, values: &mut Values, name: &str, value: f64) {
    match table.by_name(name).unwrap_or_else(|| panic!("no variable {name}")).slot {
        Slot::Known(i) => values.known[i] = value,
        Slot::State(s) => values.states[s] = value,
        Slot::Integer(i) => values.integers[i] = value as i32,
        Slot::Boolean(i) => values.booleans[i] = value != 0.0,
        other => panic!("{name}: not settable here ({other:?})"),
    }
}

/// Sets the state named `name` in `states`.
pub fn set_state(table: &VariableTable, states: &mut [f64], name: &str, value: f64) {
    let variable = table.by_name(name).unwrap_or_else(|| panic!("no variable {name}"));
    states[table.state_index(variable).unwrap_or_else(|| panic!("{name} is not a state"))] = value;
}

/// The calculated-store index of an output or local.
pub fn calculated(table: &VariableTable, name: &str) -> usize {
    match table.by_name(name).unwrap_or_else(|| panic!("no variable {name}")).slot {
        Slot::Calculated(i) => i,
        other => panic!("{name}: {other:?}"),
    }
}

/// A deterministic spread of `n` numbers in [0, 1) (xorshift; no dependency for a test).
pub fn spread(n: usize) -> impl Iterator<Item = f64> {
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    (0..n).map(move |_| {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64
    })
}

/// At one point (time `t`, the values and states): the runtime's `power_balance_relative`, and
/// for each element in the balance whose power is not zero there, the relative balance with that
/// element's power left out, kept as the largest seen in `missing` (its element marked in
/// `reported`): a balance test asserts the first is rounding and each of the second is not, so
/// that every element's power is known to matter.
pub fn balance_at<M: crate::Model>(model: &M, table: &VariableTable, t: f64, values: &Values, states: &[f64], reported: &mut [bool], missing: &mut [f64]) -> f64 {
    let (mut der, mut calc) = (vec![0.0; table.n_states], values.calculated.clone());
    crate::model::evaluate(model, table, t, &values.known, states, &values.integers, &values.booleans, &mut der, &mut calc);
    let mut powers = vec![0.0; table.elements.len()];
    crate::model::evaluate_powers(model, t, &values.known, states, &values.integers, &values.booleans, &mut der, &mut powers);
    for (j, e) in table.elements.iter().enumerate() {
        if e.neglected.is_some() || !e.effect.in_balance() || powers[j] == 0.0 {
            continue;
        }
        reported[j] = true;
        let mut without = powers.clone();
        without[j] = 0.0;
        missing[j] = missing[j].max(crate::elements::balance(&table.elements, &without).1.abs());
    }
    calc[calculated(table, "power_balance_relative")].abs()
}
