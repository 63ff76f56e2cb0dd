//! Reading some outputs computes only what they need (the energy balance takes an evaluation of
//! the derivatives, the other outputs do not): whatever a master reads, and in whatever order,
//! every value it gets is the one a master reading everything at once gets. MotorFan at level c
//! over its run-up (the reducer's power-flow events from 0.25 s on), two instances in lockstep:
//! one reads every Real output after each step, the other only the motor speed, and the balance
//! outputs every seventh step (before or after the speed).

mod counting;

use counting::initialized;
use fmu_runtime::variables::{BaseType, Causality};

#[test]
fn outputs_read_in_parts_equal_outputs_read_at_once() {
    let mut everything = initialized::<motor_fan::MotorFan>(&[("level", 3)]);
    let mut parts = initialized::<motor_fan::MotorFan>(&[("level", 3)]);
    let vr = |name: &str| everything.table().by_name(name).unwrap_or_else(|| panic!("{name}")).value_reference;
    let (speed, residual, relative) = (vr("motor_speed"), vr("power_balance_residual"), vr("power_balance_relative"));
    let outputs: Vec<u32> = everything
        .table()
        .variables
        .iter()
        .filter(|v| v.causality == Causality::Output && v.base_type() == BaseType::Real)
        .map(|v| v.value_reference)
        .collect();
    let at = |vr: u32| outputs.iter().position(|o| *o == vr).expect("an output");
    let (h, mut t) = (1e-3, 0.0);
    let (mut all, mut one, mut balance) = (vec![0.0; outputs.len()], [0.0], [0.0; 2]);
    let mut compared = 0;
    let mut residuals = std::collections::BTreeSet::new();
    for step in 0..3000 {
        everything.do_step(t, h).unwrap();
        parts.do_step(t, h).unwrap();
        t += h;
        everything.get(&outputs, &mut all).unwrap();
        let balance_first = step % 14 == 0;
        if step % 7 == 0 && balance_first {
            parts.get(&[residual, relative], &mut balance).unwrap();
        }
        parts.get(&[speed], &mut one).unwrap();
        assert_eq!(one[0].to_bits(), all[at(speed)].to_bits(), "motor_speed at t = {t} s");
        if step % 7 == 0 && !balance_first {
            parts.get(&[residual, relative], &mut balance).unwrap();
        }
        if step % 7 == 0 {
            assert_eq!(balance[0].to_bits(), all[at(residual)].to_bits(), "power_balance_residual at t = {t} s");
            assert_eq!(balance[1].to_bits(), all[at(relative)].to_bits(), "power_balance_relative at t = {t} s");
            compared += 1;
            residuals.insert(balance[0].to_bits());
        }
    }
    assert_eq!(compared, 429);
    // The residual (rounding-sized) differs from one compared step to the next, so a value
    // left over from an earlier step would show.
    assert!(residuals.len() > 100, "only {} distinct residuals", residuals.len());
}
