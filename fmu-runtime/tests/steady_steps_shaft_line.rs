//! fmi2DoStep allocates nothing in steady stepping (the same inputs and parameters step after
//! step, no events): ShaftLine, whose event indicators are evaluated after every internal step, 500 doSteps of 1 ms counted after 100 of warm-up (0.1-0.6 s: before the seal breaks loose at 0.72 s).

mod counting;

use counting::{allocations_in_steady_steps, initialized, integer};

#[test]
fn event_indicators_between_events_allocate_nothing() {
    let mut i = initialized::<shaft_line::ShaftLine>(&[]);
    let before = integer(&mut i, "state_events");
    let n = allocations_in_steady_steps(&mut i, 1e-3, 100, 500);
    assert_eq!(integer(&mut i, "state_events"), before, "no state event in the steps counted (else pick another interval)");
    assert_eq!(n, 0);
}
