//! fmi2DoStep and fmi3DoStep allocate nothing in steady stepping when called through the C
//! adapters, as a master calls them (the adapters' guard, state table and status mapping on top
//! of the instance's step): MotorFan at level c, 1000 doSteps counted after 8 s of warm-up past
//! the run-up's events (see steady_steps_motor_fan.rs), through each standard's entry points.

mod counting;

use counting::allocations;
use fmu_runtime::exported::Exported;
use fmu_runtime::standards::Standard;
use motor_fan::MotorFan;

const H: f64 = 1e-3;

fn exported() -> &'static Exported<MotorFan> {
    Box::leak(Box::new(Exported::of()))
}

/// Allocations in `steps` calls of `step(t)` after `warm_up` of them; `step` returns true on OK.
fn counted(mut step: impl FnMut(f64) -> bool, warm_up: usize, steps: usize) -> usize {
    let mut t = 0.0;
    for _ in 0..warm_up {
        assert!(step(t), "warm-up step at t = {t} s");
        t += H;
    }
    let before = allocations();
    for _ in 0..steps {
        assert!(step(t), "step at t = {t} s");
        t += H;
    }
    allocations() - before
}

#[test]
fn fmi2_do_step_allocates_nothing_in_steady_steps() {
    use fmu_runtime::fmi2::functions as f;
    use fmu_runtime::fmi2::types::*;
    let e = exported();
    let guid = std::ffi::CString::new(e.of_standard(Standard::Fmi2).token.clone()).unwrap();
    let callbacks = fmi2CallbackFunctions { logger: None, allocateMemory: None, freeMemory: None, stepFinished: None, componentEnvironment: std::ptr::null_mut() };
    unsafe {
        let c = f::instantiate::<MotorFan>(e, c"mf".as_ptr(), fmi2CoSimulation, guid.as_ptr(), std::ptr::null(), &callbacks, 0, 0);
        assert!(!c.is_null());
        assert_eq!(f::setup_experiment::<MotorFan>(c, 0, 0.0, 0.0, 0, 0.0), fmi2OK);
        assert_eq!(f::enter_initialization_mode::<MotorFan>(c), fmi2OK);
        assert_eq!(f::exit_initialization_mode::<MotorFan>(c), fmi2OK);
        let n = counted(|t| f::do_step::<MotorFan>(c, t, H, 1) == fmi2OK, 8000, 1000);
        f::free_instance::<MotorFan>(c);
        assert_eq!(n, 0);
    }
}

#[test]
fn fmi3_do_step_allocates_nothing_in_steady_steps() {
    use fmu_runtime::fmi3::functions as f;
    use fmu_runtime::fmi3::types::*;
    use fmu_runtime::instance::Interface;
    let e = exported();
    let token = std::ffi::CString::new(e.of_standard(Standard::Fmi3).token.clone()).unwrap();
    unsafe {
        let c = f::instantiate::<MotorFan>(e, Interface::CoSimulation, c"mf".as_ptr(), token.as_ptr(), std::ptr::null_mut(), false, None, (false, false));
        assert!(!c.is_null());
        assert_eq!(f::enter_initialization_mode::<MotorFan>(c, 0, 0.0, 0.0, 0, 0.0), fmi3OK);
        assert_eq!(f::exit_initialization_mode::<MotorFan>(c), fmi3OK);
        let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
        let n = counted(|t| f::do_step::<MotorFan>(c, t, H, 1, &mut event, &mut terminate, &mut early, &mut last) == fmi3OK, 8000, 1000);
        f::free_instance::<MotorFan>(c);
        assert_eq!(n, 0);
    }
}
