//! Concurrency: 16 instances of every FMU in dist/ (FMI 2.0) and dist/fmi3/ (FMI 3.0), each on its own thread with its own
//! parameter value, run the FMU's default experiment (at most 10 s of simulated time) at the same
//! time, and each result is bit-identical to the same instance run alone on the main thread. Instances share nothing (no global state,
//! no shared solver), so threads cannot disturb one another.

use std::sync::{Arc, Barrier};
use std::thread;

use fmi_host::dist::every_fmu_of_every_version as every_fmu;
use fmi_host::{Causality, Fmu, ScalarVariable, Status, ValueReference, VariableType};

const THREADS: usize = 16;
/// At most this much simulated time per run. An FMU whose default experiment is shorter runs
/// that experiment's length: TorqueSensor's is 0.1 s (its bridge supply is 5 kHz, at rtol 1e-9),
/// and 10 s of it, 100 x its experiment, took 190 of this test's 200 s.
const MAX_SIMULATED_SECONDS: f64 = 10.0;

/// The simulated time of each run: the default experiment's length, at most MAX_SIMULATED_SECONDS.
fn simulated_seconds(fmu: &Fmu) -> f64 {
    let e = fmu.model_description().default_experiment.clone().expect("a DefaultExperiment");
    let length = e.stop_time.map_or(MAX_SIMULATED_SECONDS, |stop| stop - e.start_time.unwrap_or(0.0));
    length.min(MAX_SIMULATED_SECONDS)
}

/// The Real parameters with a non-zero default for which every thread's value
/// default x (1 + 0.01 k), k = 0..16, is inside the declared range.
fn candidate_parameters(fmu: &Fmu) -> Vec<&ScalarVariable> {
    fmu.model_description()
        .model_variables
        .iter()
        .filter(|v| {
            let start = v.start.as_ref().and_then(|s| s.as_f64()).unwrap_or(0.0);
            v.causality == Causality::Parameter
                && v.variable_type == VariableType::Real
                && start != 0.0
                && (0..THREADS).all(|k| {
                    let x = start * (1.0 + 0.01 * k as f64);
                    v.min.is_none_or(|m| x > m) && v.max.is_none_or(|m| x < m)
                })
        })
        .collect()
}

/// Runs one instance for `simulated_seconds` with thread k's parameter value; returns the bits of
/// every output after every communication step.
fn run(fmu: &Arc<Fmu>, parameter: Option<&ScalarVariable>, k: usize) -> Vec<u64> {
    let md = fmu.model_description();
    let e = md.default_experiment.clone().expect("a DefaultExperiment");
    let start = e.start_time.unwrap_or(0.0);
    // The default step, but at least 1 ms, so the fastest models do not take 10^5 steps.
    let step = e.step_size.unwrap().max(1e-3);
    let outputs: Vec<ValueReference> = md
        .model_variables
        .iter()
        .filter(|v| v.causality == Causality::Output && v.variable_type == VariableType::Real)
        .map(|v| v.value_reference)
        .collect();
    let mut inst = fmu.instantiate(&format!("thread{k}"), false, false).expect("instantiate");
    assert_eq!(inst.setup_experiment(None, start, None), Status::OK);
    if let Some(p) = parameter {
        let x = p.start.as_ref().and_then(|s| s.as_f64()).unwrap() * (1.0 + 0.01 * k as f64);
        assert_eq!(inst.set_real(&[p.value_reference], &[x]), Status::OK, "{} = {x}", p.name);
    }
    // Every Real input moved off its default, each by another amount (the same on every thread), so a subsystem driven
    // only through its inputs (DriveShaft) moves at all.
    let inputs = md.model_variables.iter().filter(|v| v.causality == Causality::Input && v.variable_type == VariableType::Real);
    for (j, v) in inputs.enumerate() {
        let x = v.start.as_ref().and_then(|s| s.as_f64()).unwrap_or(0.0) + 0.5 * (j + 1) as f64;
        assert_eq!(inst.set_real(&[v.value_reference], &[x]), Status::OK, "{} = {x}", v.name);
    }
    assert_eq!(inst.enter_initialization_mode(), Status::OK);
    assert_eq!(inst.exit_initialization_mode(), Status::OK);
    let n = (simulated_seconds(fmu) / step).round() as usize;
    let mut bits = Vec::with_capacity(n * outputs.len());
    for i in 0..n {
        assert_eq!(inst.do_step(start + i as f64 * step, step, true), Status::OK, "{} thread {k} step {i}", md.model_name);
        let (status, y) = inst.get_reals(&outputs);
        assert_eq!(status, Status::OK);
        bits.extend(y.iter().map(|v| v.to_bits()));
    }
    bits
}

#[test]
fn sixteen_threads_per_fmu_match_the_single_threaded_runs() {
    for fmu in every_fmu() {
        let name = format!("{} {}", fmu.model_description().model_name, fmu.fmi_version().text());
        // The parameter the threads vary: the first candidate that changes the outputs (so a
        // mix-up between threads would show).
        let first = run(&fmu, None, 0);
        let candidates = candidate_parameters(&fmu);
        let parameter = candidates.into_iter().find(|p| run(&fmu, Some(p), THREADS - 1) != first);
        let alone: Vec<Vec<u64>> = (0..THREADS).map(|k| run(&fmu, parameter, k)).collect();
        let barrier = Arc::new(Barrier::new(THREADS));
        let together: Vec<Vec<u64>> = thread::scope(|s| {
            let handles: Vec<_> = (0..THREADS)
                .map(|k| {
                    let (fmu, barrier) = (fmu.clone(), barrier.clone());
                    s.spawn(move || {
                        barrier.wait(); // all start at once
                        run(&fmu, parameter, k)
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().expect("a thread panicked")).collect()
        });
        for k in 0..THREADS {
            assert!(together[k] == alone[k], "{name}: thread {k} differs from its single-threaded run");
        }
        assert!(parameter.is_some(), "{name}: no parameter changes the outputs over {} s", simulated_seconds(&fmu));
        println!(
            "  {name:<26} {THREADS} threads x {} s, {} output values each, varying {}: identical",
            simulated_seconds(&fmu),
            alone[0].len(),
            parameter.map_or("nothing", |p| p.name.as_str())
        );
    }
}
