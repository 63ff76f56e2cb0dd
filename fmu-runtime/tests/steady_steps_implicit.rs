//! fmi2DoStep allocates nothing in steady stepping with the implicit method, whichever way it
//! factorizes its kept Newton matrix: dense (the stiff chain of 3 inertias, 5 states), band
//! (10 inertias, 19 states, below `DENSE_BELOW`; 40 inertias, 79 states) and faer's sparse LU
//! (the star of 20 spokes, 41 states), each checked to be factorized that way. 300 doSteps of
//! 1 ms are counted after 3 of warm-up that take the torque step at 2 ms (no event after it):
//! the counted steps follow the transient and refactorize the Newton matrix as the step size
//! changes (the chains of 3, 10 and 40 inertias and the star: 16, 23, 37 and 9 times, counted
//! once since the method looks ahead; an allocation put in the factorization made the test fail
//! with those counts).

mod counting;

use counting::{allocations_in_steady_steps, initialized_with};
use fmu_runtime::stepper::jacobian::{chosen, probe, DENSE_BELOW};
use fmu_runtime::testing::chains::{Chain, Star};
use fmu_runtime::Model;

/// The stiff parameters (J = 1e-4 kg m2, K = 1e5 N m/rad, D = 10 N m s/rad) and the torque step early.
const STIFF: [(&str, f64); 4] = [("J", 1e-4), ("K", 1e5), ("D", 10.0), ("step_time", 0.002)];

/// How the implicit method factorizes the model's Newton matrix ("dense", "band" or "sparse"),
/// and its number of states, from its probed pattern.
fn factorization<M: Model>() -> (&'static str, usize) {
    let (model, _, table) = fmu_runtime::model::declare::<M>();
    let v = table.start_values();
    let n = v.states.len();
    let rhs = |x: &[f64], t: f64, y: &mut [f64]| fmu_runtime::model::evaluate_derivatives(&model, t, &v.known, x, &v.integers, &v.booleans, y);
    (chosen(n, probe(&rhs, 0.0, &vec![0.0; n], &vec![1.0; n])).unwrap().kind(), n)
}

fn allocations<M: Model>() -> usize {
    let mut i = initialized_with::<M>(&[], &STIFF);
    allocations_in_steady_steps(&mut i, 1e-3, 3, 300)
}

#[test]
fn implicit_steps_allocate_nothing_dense_band_or_sparse() {
    assert_eq!(factorization::<Chain<3, true, true>>(), ("dense", 5));
    assert_eq!(factorization::<Chain<10, true, true>>(), ("band", 19));
    assert!(19 < DENSE_BELOW);
    assert_eq!(factorization::<Chain<40, true, true>>(), ("band", 79));
    assert_eq!(factorization::<Star<20>>(), ("sparse", 41));
    let counts = [
        allocations::<Chain<3, true, true>>(),
        allocations::<Chain<10, true, true>>(),
        allocations::<Chain<40, true, true>>(),
        allocations::<Star<20>>(),
    ];
    assert_eq!(counts, [0, 0, 0, 0], "allocations in 300 steady doSteps: dense, small band, band, sparse");
}
