//! What the two derivative tests (directional_derivatives.rs, derivatives_against_high_order_differences.rs)
//! share: status checks, value reads, stderr reports and moving a Model Exchange instance along time
//! through its events.

use std::io::Write;

use fmi_host::ffi::EventInfo;
use fmi_host::{Instance, Status, ValueReference};

/// Writes to the process's stderr, bypassing the test harness's output capture.
pub fn report(text: &str) {
    let stderr = std::io::stderr();
    let mut lock = stderr.lock();
    let _ = lock.write_all(text.as_bytes());
    let _ = lock.flush();
}

pub fn ok(status: Status, what: &str, inst: &Instance) {
    if status != Status::OK {
        let log: Vec<String> = inst.log().records().iter().map(|r| format!("  [{:?}] {}", r.status, r.message)).collect();
        panic!("{}: {what} returned {status:?}; FMU log:\n{}", inst.name(), log.join("\n"));
    }
}

pub fn get(inst: &mut Instance, vr: &[ValueReference], what: &str) -> Vec<f64> {
    let (status, values) = inst.get_reals(vr);
    ok(status, what, inst);
    values
}

/// ME: from Event Mode after fmi2ExitInitializationMode (or an event) to Continuous-Time Mode.
/// Returns the next time event, if the FMU announced one.
pub fn me_event_iteration(inst: &mut Instance) -> Option<f64> {
    let mut info = EventInfo::default();
    for _ in 0..100 {
        info = EventInfo::default();
        let status = inst.new_discrete_states(&mut info).expect("fmi2NewDiscreteStates is exported");
        ok(status, "fmi2NewDiscreteStates", inst);
        assert_eq!(info.terminate_simulation, 0, "{}: terminateSimulation at an event", inst.name());
        if info.new_discrete_states_needed == 0 {
            break;
        }
    }
    assert_eq!(info.new_discrete_states_needed, 0, "{}: event iteration does not converge", inst.name());
    let status = inst.enter_continuous_time_mode().expect("fmi2EnterContinuousTimeMode is exported");
    ok(status, "fmi2EnterContinuousTimeMode", inst);
    (info.next_event_time_defined != 0).then_some(info.next_event_time)
}

/// ME, in Continuous-Time Mode: move to time `t`, handling every time event up to it as a
/// master would (fmi2SetTime(te), fmi2EnterEventMode, event iteration).
pub fn me_move_to(inst: &mut Instance, t: f64, next_event: &mut Option<f64>) {
    while let Some(te) = *next_event {
        if te > t {
            break;
        }
        ok(inst.set_time(te).unwrap(), &format!("fmi2SetTime({te})"), inst);
        ok(inst.enter_event_mode().unwrap(), "fmi2EnterEventMode", inst);
        let next = me_event_iteration(inst);
        assert!(!matches!(next, Some(n) if n <= te), "{}: next time event {next:?} not after {te}", inst.name());
        *next_event = next;
    }
    ok(inst.set_time(t).unwrap(), &format!("fmi2SetTime({t})"), inst);
}

pub fn ratio(diff: f64, denom: f64) -> f64 {
    if diff == 0.0 {
        0.0
    } else if denom > 0.0 {
        diff / denom
    } else {
        f64::INFINITY
    }
}
