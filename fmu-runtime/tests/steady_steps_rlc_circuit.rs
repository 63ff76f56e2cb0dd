//! fmi2DoStep allocates nothing in steady stepping (the same inputs and parameters step after
//! step, no events): RlcCircuit (a time-varying source), 1000 doSteps counted after 100 of warm-up.

mod counting;

use counting::{allocations_in_steady_steps, initialized};

#[test]
fn rlc_circuit_steps_without_allocating() {
    let mut i = initialized::<rlc_circuit::RlcCircuit>(&[]);
    assert_eq!(allocations_in_steady_steps(&mut i, 1e-4, 100, 1000), 0);
}
