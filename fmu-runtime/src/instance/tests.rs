//! The instance's own tests, on the runtime's test models.

use super::*;
use crate::test_model::Decay;

// Decay's value references: a=0, u=1, x=2, der(x)=3, y=4, w=5.
fn initialized() -> Instance<Decay> {
    let mut i = Instance::<Decay>::new("{test}", Logger::silent());
    i.setup_experiment(Some(1e-8), 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    i
}

fn get(i: &mut Instance<Decay>, vr: u32) -> f64 {
    let mut v = [0.0];
    i.get(&[vr], &mut v).unwrap();
    v[0]
}

#[test]
fn steps_follow_the_exponential() {
    // x' = -a x with x(0) = 1, a = 2: x(t) = exp(-2 t).
    let mut i = initialized();
    for n in 0..100 {
        i.do_step(n as f64 * 0.01, 0.01).unwrap();
    }
    let x = get(&mut i, 2);
    assert!((x - (-2.0f64).exp()).abs() < 1e-7, "{x}");
    assert_eq!(get(&mut i, 4), 2.0 * x);
    assert!((get(&mut i, 3) + 2.0 * x).abs() < 1e-12);
}

#[test]
fn a_set_is_all_or_nothing() {
    let mut i = initialized();
    let err = i.set(&[1, 0], &[3.0, 5.0]).unwrap_err();
    assert!(err.message.contains("'a'") && err.message.contains("fixed parameter"), "{}", err.message);
    assert_eq!(get(&mut i, 1), 0.0, "u must not be written when a later value is refused");
    i.set(&[1], &[3.0]).unwrap();
    assert_eq!(get(&mut i, 5), 6.0, "w = a u is recomputed after the input changes");
}

#[test]
fn out_of_range_parameters_are_refused_and_named() {
    let mut i = Instance::<Decay>::new("{test}", Logger::silent());
    let err = i.set(&[0], &[-1.0]).unwrap_err();
    assert!(err.message.contains("a = -1") && err.message.contains("minimum"), "{}", err.message);
    assert!(i.set(&[1], &[f64::NAN]).is_err());
    assert!(i.set(&[3], &[1.0]).unwrap_err().message.contains("derivative"));
    assert!(i.set(&[99], &[1.0]).unwrap_err().message.contains("unknown value reference 99"));
}

#[test]
fn communication_points_must_match_the_instance_time() {
    let mut i = initialized();
    i.do_step(0.0, 0.1).unwrap();
    let err = i.do_step(0.2, 0.1).unwrap_err();
    assert!(err.message.contains("does not match"), "{}", err.message);
    // Rounding of a master's own time keeping is accepted: 0.1 vs 0.1 + 1 ulp.
    i.do_step(0.1 + f64::EPSILON * 0.1, 0.1).unwrap();
    assert!(i.do_step(0.2, 0.0).is_err() && i.do_step(0.2, -0.1).is_err());
}

#[test]
fn a_defined_stop_time_cannot_be_passed() {
    let mut i = Instance::<Decay>::new("{test}", Logger::silent());
    i.setup_experiment(None, 0.0, Some(0.3)).unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    for n in 0..3 {
        i.do_step(n as f64 * 0.1, 0.1).unwrap();
    }
    let err = i.do_step(0.30000000000000004, 0.1).unwrap_err();
    assert!(err.message.contains("stop time"), "{}", err.message);
    assert_eq!(get(&mut i, 0), 2.0, "the instance keeps working");
}

#[test]
fn a_restored_state_continues_bit_identically() {
    let mut i = initialized();
    i.do_step(0.0, 0.25).unwrap();
    let saved = i.get_fmu_state(None).unwrap();
    i.do_step(0.25, 0.25).unwrap();
    let first = get(&mut i, 2);
    i.set_fmu_state(saved).unwrap();
    assert_eq!(i.time(), 0.25);
    i.do_step(0.25, 0.25).unwrap();
    assert_eq!(get(&mut i, 2).to_bits(), first.to_bits());
    i.free_fmu_state(saved).unwrap();
    assert!(i.free_fmu_state(saved).is_err());
}

#[test]
fn time_events_stop_the_solver_at_the_kink() {
    // x' = 0 before t_on = 0.35 s, 1 after: x(1) = 0.65 s, although the communication step
    // 0.5 s straddles the switch. The segment ending at t_on still sees the new slope in its
    // last stage (the equations have no discrete mode), which costs ~1e-9 s here.
    let mut i = Instance::<crate::test_model::Switch>::new("{test}", Logger::silent());
    i.setup_experiment(None, 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    i.do_step(0.0, 0.5).unwrap();
    i.do_step(0.5, 0.5).unwrap();
    let mut x = [0.0];
    i.get(&[1], &mut x).unwrap();
    assert!((x[0] - 0.65).abs() < 1e-8, "{}", x[0]);
}

#[test]
fn model_exchange_hands_the_states_to_the_master() {
    let mut i = Instance::<Decay>::for_interface(Interface::ModelExchange, "{test}", Logger::silent());
    i.setup_experiment(None, 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    let mut x = [0.0];
    i.get_continuous_states(&mut x).unwrap();
    assert_eq!(x, [1.0], "the start value");
    i.exit_initialization_mode().unwrap();
    assert_eq!(i.phase(), Phase::Event);
    assert_eq!(i.new_discrete_states().unwrap().next_event_time, None);
    i.enter_continuous_time_mode().unwrap();
    i.set_time(0.5).unwrap();
    i.set_continuous_states(&[3.0]).unwrap();
    let mut dx = [0.0];
    i.get_derivatives(&mut dx).unwrap();
    assert_eq!(dx, [-6.0], "x' = -a x with a = 2");
    assert_eq!(get(&mut i, 2), 3.0, "the state variable follows fmi2SetContinuousStates");
    assert!(i.set_continuous_states(&[1.0, 2.0]).is_err());
    assert!(i.set_continuous_states(&[f64::NAN]).is_err());
}

#[test]
fn a_state_s_value_reference_reads_and_sets_the_state_vector_itself() {
    // Decay's x (vr 2): one home for its value, whichever way it is reached.
    let mut i = Instance::<Decay>::for_interface(Interface::ModelExchange, "{test}", Logger::silent());
    i.setup_experiment(None, 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    i.set(&[2], &[4.0]).unwrap();
    let mut x = [0.0];
    i.get_continuous_states(&mut x).unwrap();
    assert_eq!(x, [4.0], "a start value set by value reference is the state");
    i.exit_initialization_mode().unwrap();
    assert!(i.set(&[2], &[5.0]).is_err(), "a state is not settable after initialization");
    i.enter_continuous_time_mode().unwrap();
    i.set_continuous_states(&[-0.5]).unwrap();
    assert_eq!(get(&mut i, 2).to_bits(), (-0.5f64).to_bits());
    assert_eq!(get(&mut i, 4), -1.0, "and the equations read it: y = 2 x");
    // Co-Simulation: after each step the value reference reads the state the solver reached.
    let mut c = initialized();
    for n in 0..10 {
        c.do_step(n as f64 * 0.1, 0.1).unwrap();
        let mut x = [0.0];
        c.get_continuous_states(&mut x).unwrap();
        assert_eq!(get(&mut c, 2).to_bits(), x[0].to_bits(), "after the step to {} s", (n + 1) as f64 * 0.1);
    }
}

#[test]
fn directional_derivatives_match_the_equations() {
    // x' = -a x + u, y = 2 x, w = a u (a = 2): d(x')/dx = -2, dy/dx = 2, dw/du = 2, d(x')/du = 1
    // (central differences with a 1e-7 relative step: exact up to rounding, ~1e-9).
    let mut i = initialized();
    i.set(&[1], &[0.7]).unwrap();
    let mut out = [0.0; 3];
    i.directional_derivative(&[3, 4, 5], &[2], &[1.0], &mut out).unwrap();
    for (got, want) in out.iter().zip([-2.0, 2.0, 0.0]) {
        assert!((got - want).abs() < 1e-8, "{out:?}");
    }
    i.directional_derivative(&[3, 4, 5], &[1], &[1.0], &mut out).unwrap();
    for (got, want) in out.iter().zip([1.0, 0.0, 2.0]) {
        assert!((got - want).abs() < 1e-8, "{out:?}");
    }
    assert!(i.directional_derivative(&[0], &[1], &[1.0], &mut [0.0]).is_err(), "a parameter is no unknown");
    assert!(i.directional_derivative(&[3], &[4], &[1.0], &mut [0.0]).is_err(), "an output is no known");
}

#[test]
fn input_derivatives_move_the_input_over_one_step() {
    // x' = -a x + u with u = u0 + s (t - t0) over [0, 1]: compare with a held input shifted
    // by the exact solution's difference: x(1) - x_held(1) = s * (1 - (1 - e^-a)/a) / a.
    let (a, s) = (2.0f64, 0.8);
    let run = |slope: Option<f64>| {
        let mut i = initialized();
        if let Some(sl) = slope {
            i.set_input_derivatives(&[1], &[1], &[sl]).unwrap();
        }
        i.do_step(0.0, 1.0).unwrap();
        get(&mut i, 2)
    };
    let exact = s * (1.0 - (1.0 - (-a).exp()) / a) / a;
    assert!(((run(Some(s)) - run(None)) - exact).abs() < 1e-6, "{} vs {exact}", run(Some(s)) - run(None));
    let mut i = initialized();
    assert!(i.set_input_derivatives(&[0], &[1], &[1.0]).is_err(), "a parameter is not an input");
    assert!(i.set_input_derivatives(&[1], &[3], &[1.0]).is_err(), "order 3");
}

#[test]
fn extrapolated_inputs_follow_the_last_two_communication_points() {
    // x' = -a x + u. Step 1 from t = 0 with u = 0, step 2 from t = 1 with u = 1: with
    // extrapolation u(t) = 1 + (t - 1) over step 2, without it u = 1. The difference at t = 2
    // is the response to a unit ramp: (1 - (1 - e^-a)/a)/a (a = 2).
    let run = |extrapolate: bool| {
        let mut i = Instance::<Decay>::new("{test}", Logger::silent());
        let flag = i.table().by_name("extrapolate_inputs").expect("declared for models with inputs").value_reference;
        i.set(&[flag], &[extrapolate]).unwrap();
        i.setup_experiment(Some(1e-10), 0.0, None).unwrap();
        i.enter_initialization_mode().unwrap();
        i.exit_initialization_mode().unwrap();
        i.do_step(0.0, 1.0).unwrap();
        i.set(&[1], &[1.0]).unwrap();
        i.do_step(1.0, 1.0).unwrap();
        get(&mut i, 2)
    };
    let a = 2.0f64;
    let exact = (1.0 - (1.0 - (-a).exp()) / a) / a;
    assert!(((run(true) - run(false)) - exact).abs() < 1e-7, "{} vs {exact}", run(true) - run(false));
}

#[test]
fn output_derivatives_follow_the_motion() {
    // y = 2 x, x' = -a x + u: dy/dt = 2 (-2 x + u); w = a u: dw/dt = a du/dt = 2 s.
    let mut i = initialized();
    i.set(&[1], &[0.5]).unwrap();
    i.do_step(0.0, 0.1).unwrap();
    i.set_input_derivatives(&[1], &[1], &[0.3]).unwrap();
    let x = get(&mut i, 2);
    let mut d = [0.0; 2];
    i.output_derivatives(&[4, 5], &[1, 1], &mut d).unwrap();
    assert!((d[0] - 2.0 * (-2.0 * x + 0.5)).abs() < 1e-7, "{d:?}");
    assert!((d[1] - 0.6).abs() < 1e-7, "{d:?}");
    assert!(i.output_derivatives(&[4], &[2], &mut [0.0]).is_err());
}

#[test]
fn an_event_a_rounding_away_from_the_step_end_does_not_fail_the_step() {
    // A master's float time: 1 ms summed 10 000 times lands ~1e-13 s off 10 s, where the
    // event sits; the step must not ask the solver for a 1e-13 s segment (diffsol refuses).
    let mut i = Instance::<crate::test_model::Switch>::new("{test}", Logger::silent());
    let t_on = i.table().by_name("t_on").unwrap().value_reference;
    i.set(&[t_on], &[10.0]).unwrap();
    i.setup_experiment(None, 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    let mut t = 0.0;
    for _ in 0..10_050 {
        i.do_step(t, 1e-3).unwrap();
        t += 1e-3;
    }
    let mut x = [0.0];
    i.get(&[1], &mut x).unwrap();
    assert!((x[0] - 0.05).abs() < 1e-9, "{}", x[0]);
}

fn block(interface: Interface) -> Instance<crate::test_model::Block> {
    block_of(interface)
}

fn block_of<M: Model>(interface: Interface) -> Instance<M> {
    let mut i = Instance::<M>::for_interface(interface, "{test}", Logger::silent());
    i.setup_experiment(Some(1e-8), 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    i
}

fn named<M: Model>(i: &mut Instance<M>, name: &str) -> f64 {
    let var = i.table().by_name(name).unwrap_or_else(|| panic!("{name}"));
    let vr = var.value_reference;
    if var.base_type() == BaseType::Integer {
        let mut n = [0];
        i.get(&[vr], &mut n).unwrap();
        n[0] as f64
    } else {
        let mut x = [0.0];
        i.get(&[vr], &mut x).unwrap();
        x[0]
    }
}

#[test]
fn a_sliding_block_sticks_once_and_stays_stuck() {
    // m = 1 kg, v0 = 3 m/s, F_c = 1.5 N: v = 3 - 1.5 t until t = 2 s, x = 3 - 0.75 t^2 ... = 3 m
    // at rest (x = v0^2 m / (2 F_c)). With sign(v) friction the block would chatter about
    // v = 0; with modes it sticks at one located event and v is exactly 0 afterwards.
    let mut i = block(Interface::CoSimulation);
    assert_eq!(named(&mut i, "friction_mode"), 1.0, "v0 > 0: slipping forwards from the start");
    for n in 0..7 {
        i.do_step(n as f64 * 0.5, 0.5).unwrap();
    }
    assert!((named(&mut i, "x") - 3.0).abs() < 1e-9, "{}", named(&mut i, "x"));
    assert_eq!(named(&mut i, "v"), 0.0);
    assert_eq!(named(&mut i, "friction_mode"), 0.0);
    assert_eq!(named(&mut i, "state_events"), 1.0, "one event: slip -> stick");
    // A force below the static friction (2 N) does not move it: no event, x holds.
    let u = i.table().by_name("u").unwrap().value_reference;
    i.set(&[u], &[1.9]).unwrap();
    i.do_step(3.5, 1.0).unwrap();
    assert!((named(&mut i, "x") - 3.0).abs() < 1e-9);
    assert_eq!(named(&mut i, "state_events"), 1.0);
    // Above it, it breaks loose at the communication point: a = (2.5 - 1.5) / 1 m/s2.
    i.set(&[u], &[2.5]).unwrap();
    i.do_step(4.5, 1.0).unwrap();
    assert_eq!(named(&mut i, "friction_mode"), 1.0);
    assert!((named(&mut i, "v") - 1.0).abs() < 1e-9);
    assert!((named(&mut i, "x") - 3.5).abs() < 1e-9);
    // Pushed back with 1 N (< F_s but > 0): decelerates at (1 + 1.5) m/s2, sticks at 5.9 s.
    i.set(&[u], &[-1.0]).unwrap();
    i.do_step(5.5, 1.0).unwrap();
    assert_eq!(named(&mut i, "friction_mode"), 0.0);
    assert_eq!(named(&mut i, "state_events"), 2.0);
    assert!((named(&mut i, "x") - (3.5 + 1.0 / (2.0 * 2.5))).abs() < 1e-9, "{}", named(&mut i, "x"));
}

#[test]
fn the_crossing_is_located_inside_the_step() {
    // The stick event of a 3 m/s block with F_c = 1.5 N is at 2 s; a step [1.5, 2.5] s ends
    // there with v = 0 and x = 3 m, whatever the step; the indicator read after the step is the
    // static margin F_s - |u| = 2 N.
    let mut i = block(Interface::CoSimulation);
    i.do_step(0.0, 1.5).unwrap();
    assert!((named(&mut i, "v") - 0.75).abs() < 1e-9);
    i.do_step(1.5, 1.0).unwrap();
    assert_eq!(named(&mut i, "v"), 0.0);
    assert!((named(&mut i, "x") - 3.0).abs() < 1e-9);
}

#[test]
fn the_solver_steps_past_communication_points_but_not_past_a_time_event_or_the_stop_time() {
    // x' = 0 until t_on = 0.35 s: the error estimate is zero, the steps double each time,
    // so they reach far past 10 ms communication steps; none passes t_on or the stop time.
    let mut i = Instance::<crate::test_model::Switch>::new("{test}", Logger::silent());
    i.setup_experiment(None, 0.0, Some(1.0)).unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    let (mut t, mut ahead) = (0.0, 0);
    for _ in 0..100 {
        i.do_step(t, 0.01).unwrap();
        t += 0.01;
        if let Some(la) = i.integrator.as_ref().and_then(|g| g.lookahead()) {
            // (The last communication point, 100 x 0.01 = 1.0000000000000007 s, passes the
            // stop time by rounding: accepted, and the bound there.)
            let bound = if t < 0.35 { 0.35 } else { t.max(1.0) };
            assert!(la.step.t_end <= bound, "a step to {} s from t = {t} s", la.step.t_end);
            assert!(la.step.t_start < t && t <= la.step.t_end);
            ahead += (la.step.t_end > t + 0.01) as usize;
        }
    }
    assert!(ahead > 50, "{ahead} doSteps ended inside a step reaching past the next communication point");
    assert!((named(&mut i, "x") - 0.65).abs() < 1e-9, "{}", named(&mut i, "x"));
}

#[test]
fn a_crossing_past_the_communication_point_waits_for_the_step_that_reaches_it() {
    // The 3 m/s block sticks at 2 s (v = 3 - 1.5 t); with 10 ms communication steps the solver's
    // steps reach past 2 s before the doStep that contains it, which alone sees the event.
    let mut i = block(Interface::CoSimulation);
    let mut t = 0.0;
    for _ in 0..250 {
        i.do_step(t, 0.01).unwrap();
        t += 0.01;
        if t < 2.0 - 1e-9 {
            assert_eq!(named(&mut i, "state_events"), 0.0, "at {t} s");
            assert!((named(&mut i, "v") - (3.0 - 1.5 * t)).abs() < 1e-9, "at {t} s: {}", named(&mut i, "v"));
        } else {
            assert_eq!(named(&mut i, "state_events"), 1.0, "at {t} s");
            assert_eq!(named(&mut i, "v"), 0.0);
            assert!((named(&mut i, "x") - 3.0).abs() < 1e-9);
        }
    }
}

#[test]
fn the_implicit_solver_locates_the_same_event() {
    let mut i = block_of::<crate::test_model::ImplicitBlock>(Interface::CoSimulation);
    i.do_step(0.0, 1.5).unwrap();
    i.do_step(1.5, 1.0).unwrap();
    assert_eq!(named(&mut i, "v"), 0.0);
    assert!((named(&mut i, "x") - 3.0).abs() < 1e-8, "{}", named(&mut i, "x"));
    assert_eq!((named(&mut i, "friction_mode"), named(&mut i, "state_events")), (0.0, 1.0));
}

#[test]
fn modes_are_part_of_fmu_states_and_reset() {
    let mut i = block(Interface::CoSimulation);
    i.do_step(0.0, 1.0).unwrap();
    let saved = i.get_fmu_state(None).unwrap();
    let bytes = i.serialize_fmu_state(saved).unwrap();
    i.do_step(1.0, 2.0).unwrap();
    let (x_end, events_end) = (named(&mut i, "x"), named(&mut i, "state_events"));
    assert_eq!((named(&mut i, "friction_mode"), events_end), (0.0, 1.0));
    i.set_fmu_state(saved).unwrap();
    assert_eq!((named(&mut i, "friction_mode"), named(&mut i, "state_events")), (1.0, 0.0));
    i.do_step(1.0, 2.0).unwrap();
    assert_eq!(named(&mut i, "x").to_bits(), x_end.to_bits());
    let restored = i.deserialize_fmu_state(&bytes, None).unwrap();
    i.set_fmu_state(restored).unwrap();
    assert_eq!(named(&mut i, "friction_mode"), 1.0, "deserialized");
    i.reset().unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    assert_eq!((named(&mut i, "friction_mode"), named(&mut i, "state_events")), (1.0, 0.0));
}

#[test]
fn model_exchange_reports_indicators_and_updates_modes() {
    let mut i = block(Interface::ModelExchange);
    let mut z = [0.0];
    i.get_event_indicators(&mut z).unwrap();
    assert_eq!(z, [3.0], "slipping forwards: z = v");
    assert!(i.get_event_indicators(&mut [0.0, 0.0]).is_err());
    assert!(!i.new_discrete_states().unwrap().values_changed, "the modes were settled at initialization");
    i.enter_continuous_time_mode().unwrap();
    i.set_time(2.0 + 1e-12).unwrap();
    i.set_continuous_states(&[3.0, -1.5e-12]).unwrap();
    i.get_event_indicators(&mut z).unwrap();
    assert!(z[0] < 0.0, "the master sees the crossing");
    i.enter_event_mode().unwrap();
    let info = i.new_discrete_states().unwrap();
    assert!(info.values_changed && !info.new_discrete_states_needed, "{info:?}");
    let mut x = [0.0; 2];
    i.get_continuous_states(&mut x).unwrap();
    assert_eq!(x, [3.0, 0.0], "stuck: v re-initialized to 0");
    assert_eq!((named(&mut i, "friction_mode"), named(&mut i, "state_events")), (0.0, 1.0));
    i.get_event_indicators(&mut z).unwrap();
    assert_eq!(z, [2.0], "stuck: the static margin F_s - |u|");
    let mut dx = [1.0; 2];
    i.get_derivatives(&mut dx).unwrap();
    assert_eq!(dx, [0.0, 0.0]);
}

/// The Model Exchange rule (docs/DESIGN.md, "Model Exchange events any integrator survives"):
/// after an event that changed a mode, either the FMU says the continuous states changed (the
/// master restarts its integrator) or no indicator sits at zero. A block stuck at rest that an
/// applied force breaks loose slips from v = 0: its new indicator, mode x v, is exactly 0.
#[test]
fn a_mode_switch_whose_indicator_starts_at_zero_tells_the_master_to_restart() {
    let mut i = Instance::<crate::test_model::Block>::for_interface(Interface::ModelExchange, "{test}", Logger::silent());
    i.setup_experiment(Some(1e-4), 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    let v = i.table().by_name("v").unwrap().value_reference;
    i.set(&[v], &[0.0]).unwrap();
    i.exit_initialization_mode().unwrap();
    assert_eq!(named(&mut i, "friction_mode"), 0.0, "at rest with no force: stuck");
    assert!(!i.new_discrete_states().unwrap().values_changed, "nothing changed");
    i.enter_continuous_time_mode().unwrap();
    // The force rises past the static friction (F_s = 2 N m): the stuck margin crosses zero.
    let u = i.table().by_name("u").unwrap().value_reference;
    i.set_time(0.5).unwrap();
    i.set(&[u], &[2.5]).unwrap();
    let mut z = [0.0];
    i.get_event_indicators(&mut z).unwrap();
    assert!(z[0] < 0.0, "the master sees the crossing: {z:?}");
    i.enter_event_mode().unwrap();
    let info = i.new_discrete_states().unwrap();
    assert_eq!(named(&mut i, "friction_mode"), 1.0, "slipping forwards");
    i.get_event_indicators(&mut z).unwrap();
    assert_eq!(z, [0.0], "the slipping mode's indicator, v = 0, starts exactly at zero");
    assert!(info.values_changed, "so the master must be told to restart its integrator: {info:?}");
    // And no mode change, no restart: a second event iteration changes nothing.
    assert!(!i.new_discrete_states().unwrap().values_changed);
}

/// Steps `a` from `*t` by `h`, and again a twin restored from `a`'s serialized state of
/// before the step: `a` keeps its solver alive, the twin makes one afresh. Their states,
/// knowns, modes and step sizes must agree bit for bit.
fn step_twice<M: Model>(a: &mut Instance<M>, twin: &mut Instance<M>, t: &mut f64, h: f64) {
    let saved = a.get_fmu_state(None).unwrap();
    let bytes = a.serialize_fmu_state(saved).unwrap();
    a.free_fmu_state(saved).unwrap();
    let restored = twin.deserialize_fmu_state(&bytes, None).unwrap();
    twin.set_fmu_state(restored).unwrap();
    twin.free_fmu_state(restored).unwrap();
    a.do_step(*t, h).unwrap();
    twin.do_step(*t, h).unwrap();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.now.values.states), bits(&twin.now.values.states), "states after the step from {t}");
    assert_eq!(bits(&a.now.values.known), bits(&twin.now.values.known), "knowns after the step from {t}");
    assert_eq!(a.now.values.integers, twin.now.values.integers, "modes after the step from {t}");
    let step_size = |i: &Instance<M>| i.integrator.as_ref().and_then(|g| g.step_size).map(f64::to_bits);
    assert_eq!(step_size(a), step_size(twin), "step size after the step from {t}");
    *t += h;
}

#[test]
fn a_kept_solver_steps_as_one_made_afresh_from_a_saved_state() {
    // The sliding block: slips, sticks at 2 s (a state event), is pushed loose, sticks again.
    let (mut a, mut twin) = (block(Interface::CoSimulation), block(Interface::CoSimulation));
    let u = a.table().by_name("u").unwrap().value_reference;
    let mut t = 0.0;
    for k in 0..120 {
        match k {
            60 => a.set(&[u], &[2.5]).unwrap(),
            80 => a.set(&[u], &[-1.0]).unwrap(),
            _ => {}
        }
        step_twice(&mut a, &mut twin, &mut t, 0.05);
    }
    assert_eq!(named(&mut a, "state_events"), 2.0, "both events were crossed");
    // Decay with inputs: held, ramped by input derivatives, changed, held again; with and
    // without input extrapolation.
    for extrapolate in [false, true] {
        let decay = || {
            let mut i = Instance::<Decay>::new("{test}", Logger::silent());
            let flag = i.table().by_name("extrapolate_inputs").unwrap().value_reference;
            i.set(&[flag], &[extrapolate]).unwrap();
            i.setup_experiment(Some(1e-8), 0.0, None).unwrap();
            i.enter_initialization_mode().unwrap();
            i.exit_initialization_mode().unwrap();
            i
        };
        let (mut a, mut twin) = (decay(), decay());
        let mut t = 0.0;
        for k in 0..60 {
            match k {
                10..=19 => {
                    a.set(&[1], &[0.1 * k as f64]).unwrap();
                    a.set_input_derivatives(&[1], &[1], &[0.3]).unwrap();
                }
                20..=39 => a.set(&[1], &[(k as f64).sin()]).unwrap(),
                _ => {}
            }
            step_twice(&mut a, &mut twin, &mut t, 0.01);
        }
    }
    // Through a time event, with steps reaching far past the communication points.
    let switch = || {
        let mut i = Instance::<crate::test_model::Switch>::new("{test}", Logger::silent());
        i.setup_experiment(None, 0.0, None).unwrap();
        i.enter_initialization_mode().unwrap();
        i.exit_initialization_mode().unwrap();
        i
    };
    let (mut a, mut twin) = (switch(), switch());
    let mut t = 0.0;
    for _ in 0..60 {
        step_twice(&mut a, &mut twin, &mut t, 0.01);
    }
    // The block with short communication steps: the stick event at 2 s is seen from steps
    // reaching past it.
    let (mut a, mut twin) = (block(Interface::CoSimulation), block(Interface::CoSimulation));
    let mut t = 1.8;
    a.do_step(0.0, 1.8).unwrap();
    for _ in 0..40 {
        step_twice(&mut a, &mut twin, &mut t, 0.01);
    }
    assert_eq!(named(&mut a, "state_events"), 1.0);
    // The implicit solver (re-made every step anyway).
    let (mut a, mut twin) = (block_of::<crate::test_model::ImplicitBlock>(Interface::CoSimulation), block_of::<crate::test_model::ImplicitBlock>(Interface::CoSimulation));
    let mut t = 0.0;
    for _ in 0..60 {
        step_twice(&mut a, &mut twin, &mut t, 0.05);
    }
}

#[test]
fn reset_returns_to_the_start_values() {
    let mut i = initialized();
    i.do_step(0.0, 0.5).unwrap();
    i.reset().unwrap();
    assert_eq!(i.phase(), Phase::Instantiated);
    i.enter_initialization_mode().unwrap();
    assert_eq!(get(&mut i, 2), 1.0);
}

fn relax_value(i: &mut Instance<crate::test_model::Relax>, vr: u32) -> f64 {
    let mut v = [0.0];
    i.get(&[vr], &mut v).unwrap();
    v[0]
}

#[test]
fn calculated_states_start_where_the_model_says() {
    use crate::test_model::Relax;
    // vrs: p=0, g=1, steady=2, u=3, T=4, der(T)=5, y=6
    let mut i: Instance<Relax> = Instance::new("{test}", Logger::silent());
    i.setup_experiment(None, 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    i.set(&[3], &[20.0]).unwrap();
    // Readable during initialization: the steady state u + p/g = 20 + 3/2.
    assert_eq!(relax_value(&mut i, 4), 21.5);
    assert!(i.set(&[4], &[5.0]).is_err(), "a calculated state has no settable start");
    // d y / d u at initialization goes through the calculated state: T = u + p/g, y = T.
    let mut dy = [0.0, 0.0];
    i.directional_derivative(&[6, 4], &[3], &[1.0], &mut dy).unwrap();
    assert!((dy[0] - 1.0).abs() < 1e-6 && (dy[1] - 1.0).abs() < 1e-6, "{dy:?}");
    i.exit_initialization_mode().unwrap();
    i.do_step(0.0, 0.5).unwrap();
    assert!((relax_value(&mut i, 4) - 21.5).abs() < 1e-9, "the steady state stays put");
    // The cold start: T(0) = u, then T = u + p/g (1 - e^{-g t}).
    i.reset().unwrap();
    i.set(&[2], &[false]).unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    assert_eq!(relax_value(&mut i, 6), 10.0);
    i.do_step(0.0, 0.5).unwrap();
    let exact = 10.0 + 1.5 * (1.0 - (-1.0f64).exp());
    assert!((relax_value(&mut i, 4) - exact).abs() < 1e-6, "{}", relax_value(&mut i, 4));
}

#[test]
fn a_calculated_state_without_a_finite_value_fails_initialization_by_name() {
    use crate::test_model::Relax;
    let mut i: Instance<Relax> = Instance::new("{test}", Logger::silent());
    i.enter_initialization_mode().unwrap();
    i.set(&[1], &[0.0]).unwrap(); // g = 0: no steady state (p/0)
    let e = i.exit_initialization_mode().unwrap_err();
    assert!(e.message.contains("'T'") && e.message.contains("initial value"), "{}", e.message);
    assert_eq!(i.phase(), Phase::Error);
}

/// A Block whose master handles its events (FMI 3.0 Co-Simulation with eventModeUsed and
/// earlyReturnAllowed), initialized: it starts in the event phase.
fn block_handing_events_to_master() -> Instance<crate::test_model::Block> {
    let mut i = Instance::<crate::test_model::Block>::for_interface(Interface::CoSimulation, "{test}", Logger::silent());
    i.hand_events_to_master(true, true);
    i.setup_experiment(Some(1e-8), 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    assert_eq!(i.phase(), Phase::Event, "eventModeUsed: initialization ends in event mode");
    i.new_discrete_states().unwrap();
    i.enter_step_mode().unwrap();
    i
}

#[test]
fn a_master_handling_events_gets_the_step_back_at_the_crossing() {
    // The 3 m/s block with F_c = 1.5 N sticks at t = 2 s (v = 3 - 1.5 t): the step [1.5, 2.5] s
    // returns at 2 s (to ROOT_TIME_TOLERANCE) with the event for the master, the mode still
    // "slipping"; the master's event mode makes it stuck, and the rest of the step ends where
    // a step handling the event itself ends (x = v0^2 / (2 F_c) = 3 m, v = 0).
    let mut i = block_handing_events_to_master();
    let end = i.do_step(0.0, 1.5).unwrap();
    assert_eq!(end, StepEnd { time: 1.5, event: false });
    let end = i.do_step(1.5, 1.0).unwrap();
    assert!(end.event && (end.time - 2.0).abs() < 1e-9, "{end:?}");
    assert_eq!(named(&mut i, "friction_mode"), 1.0, "the modes change in the master's event mode, not before");
    assert_eq!(named(&mut i, "state_events"), 1.0, "counted where the step stopped, as a step handling it would");
    assert!(i.do_step(end.time, 2.5 - end.time).is_ok(), "a master may step on; the next step settles the modes first");
    let mut i = block_handing_events_to_master();
    i.do_step(0.0, 1.5).unwrap();
    let end = i.do_step(1.5, 1.0).unwrap();
    i.enter_event_mode().unwrap();
    let info = i.new_discrete_states().unwrap();
    assert!(info.values_changed, "stuck: v re-initialized to 0");
    assert_eq!(named(&mut i, "friction_mode"), 0.0);
    assert_eq!(named(&mut i, "state_events"), 1.0, "not counted twice");
    i.enter_step_mode().unwrap();
    let end = i.do_step(end.time, 2.5 - end.time).unwrap();
    assert_eq!(end, StepEnd { time: 2.5, event: false });
    assert_eq!(named(&mut i, "v"), 0.0);
    assert!((named(&mut i, "x") - 3.0).abs() < 1e-9, "{}", named(&mut i, "x"));
}

#[test]
fn a_time_event_ends_the_step_early_for_a_master_handling_events() {
    // Switch: x' = 0 before t_on = 0.35 s, 1 after. The step [0, 0.5] s returns at 0.35 s; the
    // rest gives x(1) = 0.65 s as a step handling the event itself does.
    let mut i = Instance::<crate::test_model::Switch>::new("{test}", Logger::silent());
    i.hand_events_to_master(true, true);
    i.setup_experiment(None, 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    i.enter_step_mode().unwrap();
    let end = i.do_step(0.0, 0.5).unwrap();
    assert_eq!(end, StepEnd { time: 0.35, event: true });
    i.enter_event_mode().unwrap();
    assert_eq!(i.new_discrete_states().unwrap().next_event_time, None, "t_on is passed");
    i.enter_step_mode().unwrap();
    assert_eq!(i.do_step(0.35, 0.15).unwrap(), StepEnd { time: 0.5, event: false });
    i.do_step(0.5, 0.5).unwrap();
    let mut x = [0.0];
    i.get(&[1], &mut x).unwrap();
    assert!((x[0] - 0.65).abs() < 1e-8, "{}", x[0]);
}

#[test]
fn without_early_return_or_event_mode_the_step_handles_its_events() {
    // eventModeUsed without earlyReturnAllowed: the step goes through the event; without
    // eventModeUsed the instance refuses to enter event mode.
    let mut i = Instance::<crate::test_model::Block>::for_interface(Interface::CoSimulation, "{test}", Logger::silent());
    i.hand_events_to_master(true, false);
    i.setup_experiment(Some(1e-8), 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    i.enter_step_mode().unwrap();
    assert_eq!(i.do_step(0.0, 2.5).unwrap(), StepEnd { time: 2.5, event: false });
    assert_eq!(named(&mut i, "friction_mode"), 0.0);
    let mut i = block(Interface::CoSimulation);
    let refused = i.enter_event_mode().unwrap_err();
    assert!(refused.message.contains("eventModeUsed = false"), "{}", refused.message);
    assert_eq!(i.phase(), Phase::Stepping);
}

/// Records what an instance logs.
#[derive(Clone, Default)]
struct Recorded(std::sync::Arc<std::sync::Mutex<Vec<(Status, String)>>>);

impl crate::log::LogSink for Recorded {
    fn send(&self, status: Status, _category: &str, message: &str) {
        self.0.lock().unwrap().push((status, message.to_string()));
    }
}

impl Recorded {
    fn warnings(&self) -> Vec<String> {
        self.0.lock().unwrap().iter().filter(|(s, _)| *s == Status::Warning).map(|(_, m)| m.clone()).collect()
    }
}

/// A FlooredDecay set up with the master's tolerance and `ringing`, initialized: the
/// tolerance its solver integrates at, and what it logged.
fn floored(tolerance: Option<f64>, ringing: bool) -> (f64, Recorded) {
    use crate::test_model::FlooredDecay;
    let log = Recorded::default();
    let mut i = Instance::<FlooredDecay>::new("{test}", Logger::new(Some(Box::new(log.clone())), false));
    let vr = i.table.variables.iter().position(|v| v.name == "ringing").unwrap() as u32;
    i.setup_experiment(tolerance, 0.0, None).unwrap();
    assert!(log.warnings().is_empty(), "no warning before the parameters are final: {:?}", log.warnings());
    i.enter_initialization_mode().unwrap();
    i.set(&[vr], &[ringing]).unwrap();
    i.exit_initialization_mode().unwrap();
    i.do_step(0.0, 0.01).unwrap();
    (i.solver_tolerance(), log)
}

#[test]
fn the_tolerance_floor_follows_the_parameters() {
    // Ringing (the default): the master's 1e-6 is tightened to the floor, with a warning naming both.
    let (rtol, log) = floored(Some(1e-6), true);
    assert_eq!(rtol, 1e-10);
    let w = log.warnings();
    assert!(w.len() == 1 && w[0].contains("1e-6") && w[0].contains("floor 1e-10"), "{w:?}");
    // Not ringing: the master's tolerance as given, and no warning.
    let (rtol, log) = floored(Some(1e-6), false);
    assert_eq!(rtol, 1e-6);
    assert!(log.warnings().is_empty(), "{:?}", log.warnings());
    // No tolerance given: the default for the parameters, the floor or DEFAULT_RELATIVE_TOLERANCE.
    assert_eq!(floored(None, true).0, 1e-10);
    assert_eq!(floored(None, false).0, crate::integrate::DEFAULT_RELATIVE_TOLERANCE);
    // A tighter tolerance than the floor is kept.
    assert_eq!(floored(Some(1e-12), true).0, 1e-12);
    // The DefaultExperiment declares the floor at the default parameters.
    let d = crate::description::ModelDescription::of::<crate::test_model::FlooredDecay>();
    for s in crate::standards::ALL {
        assert!(d.document(*s).xml.contains(r#"tolerance="1e-10""#), "{s:?}: {}", d.document(*s).xml);
    }
    assert_eq!(d.default_floor, Some(1e-10));
}
