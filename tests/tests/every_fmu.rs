//! What every FMU in dist/ must do, whatever its model: run its default experiment, replay
//! bit-identically from a saved FMU state, continue bit-identically from a serialized state in a
//! fresh instance, and run after fmi2Reset exactly as a fresh instance does.
//!
//! `FMU_DIST_DIR` overrides the folder (default `<workspace>/dist`).

use std::sync::Arc;

use fmi_host::dist::every_fmu;
use fmi_host::{Causality, Fmu, Instance, Status, ValueReference, VariableType};

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
        assert_eq!(first, again, "{}: replay differs", fmu.model_description().model_name);
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
        assert_eq!(rest_a, rest_b, "{}: deserialized run differs", fmu.model_description().model_name);
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
        assert_eq!(run.steps(&mut reused, 0, run.steps), expected, "{}", fmu.model_description().model_name);
    }
}
