//! fmi2DoStep allocates nothing in steady stepping (the same inputs and parameters step after
//! step, no events): MotorFan at levels c and d, 1000 doSteps counted after 100 of warm-up.

mod counting;

use counting::{allocations_in_steady_steps, initialized};

#[test]
fn motor_fan_level_c_steps_without_allocating() {
    let mut i = initialized::<motor_fan::MotorFan>(&[("level", 3)]);
    assert_eq!(allocations_in_steady_steps(&mut i, 1e-3, 100, 1000), 0);
}

#[test]
fn motor_fan_level_d_steps_without_allocating() {
    let mut i = initialized::<motor_fan::MotorFan>(&[("level", 4)]);
    assert_eq!(allocations_in_steady_steps(&mut i, 1e-3, 100, 1000), 0);
}
