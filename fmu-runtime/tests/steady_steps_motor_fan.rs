//! fmi2DoStep allocates nothing in steady stepping (the same inputs and parameters step after
//! step, no events): MotorFan at levels c and d, 1000 doSteps counted after a warm-up past the
//! run-up's events. With the book's defaults the elastic shaft's torque changes sign 54 times
//! between 0.25 s and 7.12 s at level c (the reducer's power-flow events; tests/tests/
//! model_exchange_strict.rs prints them), 40 times up to 6.89 s at level d, and an event's
//! handling may allocate; from 8 s on the drive runs steady.

mod counting;

use counting::{allocations_in_steady_steps, initialized};

#[test]
fn motor_fan_level_c_steps_without_allocating() {
    let mut i = initialized::<motor_fan::MotorFan>(&[("level", 3)]);
    assert_eq!(allocations_in_steady_steps(&mut i, 1e-3, 8000, 1000), 0);
}

#[test]
fn motor_fan_level_d_steps_without_allocating() {
    let mut i = initialized::<motor_fan::MotorFan>(&[("level", 4)]);
    assert_eq!(allocations_in_steady_steps(&mut i, 1e-3, 8000, 1000), 0);
}
