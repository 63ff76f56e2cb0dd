//! What every FMU in dist/ must do, whatever its model: run its default experiment, replay
//! bit-identically from a saved FMU state, continue bit-identically from a serialized state in a
//! fresh instance, and run after fmi2Reset exactly as a fresh instance does. Through the FMI 2.0
//! API (dist/*.fmu) and the FMI 3.0 API (dist/fmi3/*.fmu), the same checks.
//!
//! `FMU_DIST_DIR` overrides the folder (default `<workspace>/dist`), `FMI_VERSIONS` the versions
//! (default `2,3`).

use std::sync::Arc;

use fmi_host::dist::{every_fmu_for, every_fmu_of_every_version as every_fmu};
use fmi_host::{Causality, Fmi2Type, FmiVersion, Fmu, Instance, InstantiateOptions, Status, ValueReference, VariableType};

/// The experiment each FMU is exercised with: its default experiment, cut to at most 400
/// communication steps so the whole suite stays fast.
struct Run {
    start: f64,
    step: f64,
    steps: usize,
    outputs: Vec<ValueReference>,
}

impl Run {
    fn of(fmu: &Fmu) -> Run {
        let md = fmu.model_description();
        let e = md.default_experiment.clone().expect("every FMU has a DefaultExperiment");
        let (start, stop, step) = (e.start_time.unwrap_or(0.0), e.stop_time.unwrap(), e.step_size.unwrap());
        let steps = (((stop - start) / step).round() as usize).min(400);
        let outputs = md
            .model_variables
            .iter()
            .filter(|v| v.causality == Causality::Output && v.variable_type == VariableType::Real)
            .map(|v| v.value_reference)
            .collect();
        Run { start, step, steps, outputs }
    }

    fn time(&self, k: usize) -> f64 {
        self.start + k as f64 * self.step
    }

    fn initialized(&self, fmu: &Arc<Fmu>, name: &str) -> Instance {
        let mut inst = fmu.instantiate(name, false, false).expect("instantiate");
        self.initialize(&mut inst);
        inst
    }

    fn initialize(&self, inst: &mut Instance) {
        assert_eq!(inst.setup_experiment(None, self.start, None), Status::OK);
        assert_eq!(inst.enter_initialization_mode(), Status::OK);
        assert_eq!(inst.exit_initialization_mode(), Status::OK);
    }

    /// Steps k in [from, to) and returns the bits of every output after each step.
    fn steps(&self, inst: &mut Instance, from: usize, to: usize) -> Vec<Vec<u64>> {
        (from..to)
            .map(|k| {
                assert_eq!(inst.do_step(self.time(k), self.step, true), Status::OK, "{} at step {k}", inst.name());
                let (status, y) = inst.get_reals(&self.outputs);
                assert_eq!(status, Status::OK);
                assert!(y.iter().all(|v| v.is_finite()), "{}: non-finite output at step {k}", inst.name());
                y.iter().map(|v| v.to_bits()).collect()
            })
            .collect()
    }
}

#[test]
fn a_saved_state_replays_bit_identically() {
    for fmu in every_fmu() {
        let run = Run::of(&fmu);
        let half = run.steps / 2;
        let mut inst = run.initialized(&fmu, "replay");
        run.steps(&mut inst, 0, half);
        let (status, state) = inst.get_fmu_state();
        assert_eq!(status, Status::OK);
        let state = state.unwrap();
        let first = run.steps(&mut inst, half, run.steps);
        assert_eq!(inst.set_fmu_state(&state), Status::OK);
        let again = run.steps(&mut inst, half, run.steps);
        assert_eq!(first, again, "{} ({}): replay differs", fmu.model_description().model_name, fmu.fmi_version());
        assert_eq!(inst.free_fmu_state(state), Status::OK);
    }
}

#[test]
fn a_serialized_state_continues_bit_identically_in_a_fresh_instance() {
    for fmu in every_fmu() {
        let run = Run::of(&fmu);
        let half = run.steps / 2;
        let mut a = run.initialized(&fmu, "a");
        run.steps(&mut a, 0, half);
        let (_, state) = a.get_fmu_state();
        let state = state.unwrap();
        let (status, bytes) = a.serialize_fmu_state(&state);
        assert_eq!(status, Status::OK);
        let rest_a = run.steps(&mut a, half, run.steps);

        let mut b = run.initialized(&fmu, "b");
        let (status, restored) = b.deserialize_fmu_state(&bytes);
        assert_eq!(status, Status::OK);
        let restored = restored.unwrap();
        assert_eq!(b.set_fmu_state(&restored), Status::OK);
        let rest_b = run.steps(&mut b, half, run.steps);
        assert_eq!(rest_a, rest_b, "{} ({}): deserialized run differs", fmu.model_description().model_name, fmu.fmi_version());
    }
}

#[test]
fn after_reset_an_instance_runs_like_a_fresh_one() {
    for fmu in every_fmu() {
        let run = Run::of(&fmu);
        let mut fresh = run.initialized(&fmu, "fresh");
        let expected = run.steps(&mut fresh, 0, run.steps);
        let mut reused = run.initialized(&fmu, "reused");
        run.steps(&mut reused, 0, run.steps / 3);
        assert_eq!(reused.reset(), Status::OK);
        run.initialize(&mut reused);
        assert_eq!(run.steps(&mut reused, 0, run.steps), expected, "{} ({})", fmu.model_description().model_name, fmu.fmi_version());
    }
}

/// The FMI 3.0 build of each model runs bit-identically to its FMI 2.0 build through the same
/// host calls, and its description declares the same variables (same names, value references,
/// causalities, types, starts), the same outputs and states, plus `time` and one
/// `event_indicator.*` per FMI 2.0 event indicator.
#[test]
fn the_fmi3_build_matches_the_fmi2_build() {
    let versions = fmi_host::dist::versions();
    if !(versions.contains(&FmiVersion::Fmi2) && versions.contains(&FmiVersion::Fmi3)) {
        eprintln!("FMI_VERSIONS={versions:?}: needs both versions, skipped");
        return;
    }
    let (two, three) = (every_fmu_for(FmiVersion::Fmi2), every_fmu_for(FmiVersion::Fmi3));
    let names = |fmus: &[Arc<Fmu>]| fmus.iter().map(|f| f.model_description().model_name.clone()).collect::<Vec<_>>();
    assert_eq!(names(&two), names(&three), "dist/ and dist/fmi3/ hold the same models");
    for (a, b) in two.iter().zip(&three) {
        let (ma, mb) = (a.model_description(), b.model_description());
        let name = &ma.model_name;
        assert_eq!((ma.fmi_version.as_str(), mb.fmi_version.as_str()), ("2.0", "3.0"), "{name}");
        assert_eq!((a.version(), b.version()), ("2.0".to_string(), "3.0".to_string()), "{name}: fmi2GetVersion / fmi3GetVersion");
        let time: Vec<_> = mb.model_variables.iter().filter(|v| v.causality == Causality::Independent).collect();
        assert!(time.len() == 1 && time[0].name == "time" && time[0].variable_type == VariableType::Real, "{name}: one Float64 independent variable `time`");
        let indicators: Vec<_> = mb.model_variables.iter().filter(|v| v.name.starts_with("event_indicator.")).collect();
        assert_eq!(Some(indicators.len() as u32), ma.number_of_event_indicators.or(Some(0)), "{name}: one event_indicator.* per event indicator");
        assert_eq!(mb.number_of_event_indicators, Some(indicators.len() as u32), "{name}: <EventIndicator>s");
        let ei_vrs: Vec<_> = indicators.iter().map(|v| v.value_reference).collect();
        let ms_vrs: Vec<_> = mb.model_structure.event_indicators.iter().map(|u| u.value_reference).collect();
        assert_eq!(ei_vrs, ms_vrs, "{name}: ModelStructure <EventIndicator>s are the event_indicator.* variables");
        // The model's own variables: the same in both, in the same order.
        let own: Vec<_> = mb.model_variables.iter().filter(|v| v.causality != Causality::Independent && !v.name.starts_with("event_indicator.")).collect();
        assert_eq!(own.len(), ma.model_variables.len(), "{name}: variable count");
        for (va, vb) in ma.model_variables.iter().zip(&own) {
            assert_eq!(
                (&va.name, va.value_reference, va.causality, va.variability, va.variable_type, &va.start, va.derivative.map(|i| &ma.model_variables[i as usize - 1].name)),
                (&vb.name, vb.value_reference, vb.causality, vb.variability, vb.variable_type, &vb.start, vb.derivative.map(|i| &mb.model_variables[i as usize - 1].name)),
                "{name}: variable {}",
                va.name
            );
        }
        let vrs = |u: &[fmi_host::Unknown]| u.iter().map(|u| u.value_reference).collect::<Vec<_>>();
        assert_eq!(vrs(&ma.model_structure.outputs), vrs(&mb.model_structure.outputs), "{name}: ModelStructure outputs");
        assert_eq!(vrs(&ma.model_structure.continuous_state_derivatives), vrs(&mb.model_structure.continuous_state_derivatives), "{name}: state derivatives");
        let cs = mb.co_simulation.as_ref().expect("CoSimulation");
        assert!(cs.can_get_and_set_fmu_state && cs.can_serialize_fmu_state && cs.provides_directional_derivative && cs.provides_adjoint_derivatives && cs.has_event_mode, "{name}: {cs:?}");
        // The same run, bit for bit.
        let run = Run::of(a);
        let mut ia = run.initialized(a, "fmi2");
        let mut ib = run.initialized(b, "fmi3");
        assert_eq!(run.steps(&mut ia, 0, run.steps), run.steps(&mut ib, 0, run.steps), "{name}: FMI 3.0 run differs from FMI 2.0 run");
        let outcome = ib.last_do_step().expect("fmi3DoStep's outputs");
        assert!(!outcome.event_handling_needed && !outcome.terminate_simulation && !outcome.early_return, "{name}: {outcome:?}");
        // The last step's end, as the FMU computes it (its communication point plus its size).
        let end = run.time(run.steps - 1) + run.step;
        assert_eq!(outcome.last_successful_time, end, "{name}: lastSuccessfulTime");
        let (s, t) = ib.get_reals(&[time[0].value_reference]);
        assert_eq!((s, t[0]), (Status::OK, end), "{name}: the `time` variable after the run");
        // Model Exchange: the counts the instance reports are the description's.
        let mut me = Instance::new(b, InstantiateOptions::new("me").fmu_type(Fmi2Type::ModelExchange)).expect("instantiate ME");
        let n_states = ma.model_variables.iter().filter(|v| v.derivative.is_some()).count();
        assert_eq!(me.get_number_of_continuous_states().unwrap(), (Status::OK, n_states), "{name}");
        assert_eq!(me.get_number_of_event_indicators().unwrap(), (Status::OK, indicators.len()), "{name}");
        assert!(matches!(ia.get_number_of_continuous_states(), Err(fmi_host::Error::NotInVersion { .. })), "{name}: no fmi3GetNumberOfContinuousStates in FMI 2.0");
        assert!(matches!(ib.cancel_step(), Err(fmi_host::Error::NotInVersion { .. })), "{name}: no fmi2CancelStep in FMI 3.0");
        assert!(matches!(ib.set_real_input_derivatives(&[], &[], &[]), Err(fmi_host::Error::NotInVersion { .. })), "{name}");
        assert!(matches!(ib.get_status(fmi_host::StatusKind::DoStepStatus), Err(fmi_host::Error::NotInVersion { .. })), "{name}");
    }
}

/// FMI 3.0 instantiation refusals: a wrong instantiationToken (Co-Simulation and Model
/// Exchange) and Scheduled Execution, which these FMUs do not provide, return NULL with a
/// logged fmi3Error message (the host turns NULL into `InstantiationFailed` with the log).
#[test]
fn fmi3_instantiation_refusals_return_null_with_a_message() {
    if !fmi_host::dist::versions().contains(&FmiVersion::Fmi3) {
        eprintln!("FMI_VERSIONS without 3: skipped");
        return;
    }
    for fmu in every_fmu_for(FmiVersion::Fmi3) {
        let name = fmu.model_description().model_name.clone();
        let token = fmu.model_description().guid.clone();
        for kind in [Fmi2Type::CoSimulation, Fmi2Type::ModelExchange] {
            let options = InstantiateOptions::new("wrong token").fmu_type(kind).guid(format!("{token}-not-this-one"));
            match Instance::new(&fmu, options) {
                Err(fmi_host::Error::InstantiationFailed { log, .. }) => assert!(
                    log.iter().any(|r| r.status == Status::ERROR && r.message.contains("instantiationToken")),
                    "{name} {kind:?}: NULL but no fmi3Error message about the instantiationToken: {log:?}"
                ),
                other => panic!("{name} {kind:?}: a wrong instantiationToken gave {other:?}"),
            }
        }
        match Instance::new_scheduled_execution(&fmu, InstantiateOptions::new("scheduled")) {
            Err(fmi_host::Error::InstantiationFailed { log, .. }) => assert!(
                log.iter().any(|r| r.status == Status::ERROR && r.message.contains("Scheduled Execution")),
                "{name}: fmi3InstantiateScheduledExecution returned NULL but logged no fmi3Error about it: {log:?}"
            ),
            other => panic!("{name}: fmi3InstantiateScheduledExecution gave {other:?}"),
        }
        // The right token still instantiates (the refusals were about the token).
        assert!(Instance::new(&fmu, InstantiateOptions::new("right token")).is_ok(), "{name}");
    }
    let two = &every_fmu_for(FmiVersion::Fmi2)[0];
    assert!(matches!(Instance::new_scheduled_execution(two, InstantiateOptions::new("x")), Err(fmi_host::Error::NotInVersion { .. })));
}
