//! Tests of the co-simulation master (`fmi_host::master`) with `RlcCircuit.fmu` only: the
//! FMI 2.0 build (dist/) and the FMI 3.0 build (dist/fmi3/), the same scenarios and references
//! for both (`FMI_VERSIONS=2` or `=3` restricts; default both).
//!
//! FMI 3.0 has no fmi2SetRealInputDerivatives and no canInterpolateInputs: the master gives an
//! FMI 3.0 consumer no input slopes, so input interpolation (Gauss-Seidel) and extrapolation
//! (Jacobi) are FMI 2.0 only. The scenarios that test them run with the FMI 2.0 build; with the
//! FMI 3.0 build, where they run at all, they check that the master falls back to inputs held
//! over the step.
//!
//! The coupled system is a chain: a `source` circuit driven by its own sine feeds, through its
//! capacitor voltage, the input u_in of a `load` circuit whose sine is off (U_amplitude = 0).
//! The load's high-frequency branch obeys L di/dt = u_in - R i, whose exact response to an
//! input held constant, or following a straight line, over a step is written below: the
//! references of the ordering tests are computed from it, never from another run of the master.
//!
//! `FMU_DIST_DIR` overrides the folder holding the FMUs (default `<workspace>/dist`).

use std::sync::Arc;

use fmi_host::master::{
    Algorithm, Component, ErrorControl, Master, MasterError, Outcome, System,
};
use fmi_host::dist::{dist_dir_for, versions};
use fmi_host::{FmiVersion, Fmu, Status};

fn rlc_of(version: FmiVersion) -> Arc<Fmu> {
    let path = dist_dir_for(version).join("RlcCircuit.fmu");
    let fmu = Fmu::load(&path).unwrap_or_else(|e| {
        panic!("{path:?}: {e} (run `cargo run --release -p build-fmus` first)")
    });
    assert_eq!(fmu.fmi_version(), version, "{path:?}");
    fmu
}

/// RlcCircuit.fmu of every FMI version tested (`FMI_VERSIONS`), FMI 2.0's first.
fn rlc_of_every_version() -> Vec<Arc<Fmu>> {
    versions().into_iter().map(rlc_of).collect()
}

/// The FMI 2.0 RlcCircuit.fmu, for the scenarios FMI 3.0 cannot run (input derivatives), or
/// None when `FMI_VERSIONS` leaves FMI 2.0 out.
fn rlc_fmi2_only() -> Option<Arc<Fmu>> {
    if versions().contains(&FmiVersion::Fmi2) {
        Some(rlc_of(FmiVersion::Fmi2))
    } else {
        eprintln!("FMI_VERSIONS without 2: this FMI 2.0-only scenario is skipped");
        None
    }
}

/// The RlcCircuit's defaults (docs/rlc-circuit-spec.md).
const R_SERIES: f64 = 1.0;
const L_SERIES: f64 = 0.01;

/// source (10 V, 50 Hz) --u_capacitor--> load.u_in (sine off).
fn chain(fmu: &Arc<Fmu>) -> System {
    System::new()
        .with(Component::new("source", fmu))
        .with(Component::new("load", fmu).real("U_amplitude", 0.0))
        .connect("source.u_capacitor", "load.u_in")
}

const RECORD: [&str; 4] = [
    "source.i_absorbed",
    "source.u_capacitor",
    "load.u_in",
    "load.i_high_frequency",
];

fn run(master: Master) -> Outcome {
    master.run().unwrap_or_else(|e| panic!("{e}"))
}

fn column<'a>(outcome: &'a Outcome, name: &str) -> &'a [f64] {
    outcome.results.column(name).unwrap_or_else(|| panic!("no column {name}"))
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// One step of L di/dt = u0 + s (t - t0) - R i over h, exactly.
fn rl_step(i0: f64, u0: f64, s: f64, h: f64) -> f64 {
    let a = R_SERIES / L_SERIES;
    let b = s / R_SERIES;
    let c = u0 / R_SERIES - s * L_SERIES / (R_SERIES * R_SERIES);
    c + b * h + (i0 - c) * (-a * h).exp()
}

/// The load's high-frequency current when its input is held at `u[k + shift]` over step k.
fn rl_held(u: &[f64], h: f64, shift: usize) -> Vec<f64> {
    let mut i = vec![0.0];
    for k in 0..u.len() - 1 {
        let held = u[(k + shift).min(u.len() - 1)];
        i.push(rl_step(i[k], held, 0.0, h));
    }
    i
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

#[test]
fn table_has_a_row_per_communication_point() {
    for fmu in rlc_of_every_version() {
        eprintln!("RlcCircuit {}", fmu.fmi_version());
        let out = run(Master::new(chain(&fmu), 1e-3, 0.0105).record(RECORD));
        // 0.0105 / 1e-3 is not whole: ten full steps and a last one of 0.5 ms.
        assert_eq!(out.results.len(), 12);
        assert_eq!(out.stats.communication_steps, 11);
        assert_eq!(out.stats.accepted_steps, 11);
        assert_eq!(out.stats.rejected_steps, 0);
        assert_eq!(out.stats.do_step_calls, 22);
        assert_eq!(out.results.columns(), RECORD);
        let t = out.results.time();
        assert_eq!(t[0], 0.0);
        assert!((t[5] - 5e-3).abs() < 1e-15);
        assert_eq!(*t.last().unwrap(), 0.0105);
        let csv = out.results.to_csv();
        assert!(csv.starts_with("time,source.i_absorbed,source.u_capacitor,load.u_in,"));
        assert_eq!(csv.lines().count(), 13);
    }
}

/// The first stage of the chain has no input: coupled, it runs exactly as alone.
#[test]
fn the_chain_first_stage_equals_an_uncoupled_run() {
    for fmu in rlc_of_every_version() {
        eprintln!("RlcCircuit {}", fmu.fmi_version());
        let (h, n) = (1e-4, 500);
        let mut alone = fmu.instantiate("alone", false, false).unwrap();
        let i_absorbed = fmu.vr("i_absorbed").unwrap();
        assert_eq!(alone.setup_experiment(None, 0.0, Some(h * n as f64)), Status::OK);
        assert_eq!(alone.enter_initialization_mode(), Status::OK);
        assert_eq!(alone.exit_initialization_mode(), Status::OK);
        let mut expected = vec![alone.get_reals(&[i_absorbed]).1[0]];
        for k in 0..n {
            assert_eq!(alone.do_step(k as f64 * h, h, true), Status::OK);
            expected.push(alone.get_reals(&[i_absorbed]).1[0]);
        }
        for algorithm in [Algorithm::Jacobi, Algorithm::gauss_seidel()] {
            let out = run(Master::new(chain(&fmu), h, h * n as f64).algorithm(algorithm.clone()).record(RECORD));
            assert_eq!(column(&out, "source.i_absorbed"), expected.as_slice(), "{algorithm}");
            // After every exchange the load's input is the source's output of the same instant.
            assert_eq!(column(&out, "load.u_in"), column(&out, "source.u_capacitor"), "{algorithm}");
        }
    }
}

/// Jacobi: the load steps from the source's output at the start of the macro step.
/// Gauss-Seidel (source first): from the source's output at the end of the same macro step.
/// Gauss-Seidel with the load first is Jacobi again.
#[test]
fn jacobi_and_gauss_seidel_ordering_semantics() {
    for fmu in rlc_of_every_version() {
        eprintln!("RlcCircuit {}", fmu.fmi_version());
        let h = 2e-4;
        let master = || {
            Master::new(chain(&fmu), h, 0.04)
                .extrapolation(false)
                .tolerance(Some(1e-10))
                .record(RECORD)
        };
        let jacobi = run(master().algorithm(Algorithm::Jacobi));
        let gs = run(master().algorithm(Algorithm::gauss_seidel()));
        let gs_reversed = run(master().algorithm(Algorithm::gauss_seidel_in(["load", "source"])));

        let u = column(&jacobi, "source.u_capacitor");
        assert_eq!(u, column(&gs, "source.u_capacitor"), "the source does not see the coupling");
        let scale = max_abs(column(&jacobi, "load.i_high_frequency"));
        let tol = 1e-7 * scale;

        let e_jacobi = max_diff(column(&jacobi, "load.i_high_frequency"), &rl_held(u, h, 0));
        let e_gs = max_diff(column(&gs, "load.i_high_frequency"), &rl_held(u, h, 1));
        let e_reversed = max_diff(column(&gs_reversed, "load.i_high_frequency"), &rl_held(u, h, 0));
        let gap = max_diff(&rl_held(u, h, 0), &rl_held(u, h, 1));
        eprintln!("max |i - reference|: Jacobi {e_jacobi:.2e}, GS {e_gs:.2e}, GS reversed {e_reversed:.2e}; Jacobi-GS gap {gap:.2e} A");
        assert!(gap > 1000.0 * tol, "the test must tell the two apart: gap {gap}");
        assert!(e_jacobi < tol, "Jacobi holds u(t_k): {e_jacobi}");
        assert!(e_gs < tol, "Gauss-Seidel holds u(t_k+1): {e_gs}");
        assert!(e_reversed < tol, "Gauss-Seidel load-first is Jacobi: {e_reversed}");
    }
}

/// Where the FMU declares canInterpolateInputs, Gauss-Seidel gives a consumer stepping after
/// its source the straight line between the source's outputs at both ends of the step.
#[test]
fn gauss_seidel_interpolates_fresh_outputs_when_supported() {
    for fmu in rlc_of_every_version() {
        eprintln!("RlcCircuit {}", fmu.fmi_version());
        let cs = fmu.model_description().co_simulation.clone().unwrap();
        let h = 2e-4;
        let master = Master::new(chain(&fmu), h, 0.04)
            .algorithm(Algorithm::gauss_seidel())
            .tolerance(Some(1e-10))
            .record(RECORD);
        if !cs.can_interpolate_inputs {
            // FMI 3.0 has no canInterpolateInputs (nor fmi2SetRealInputDerivatives): the
            // consumer's input is held.
            eprintln!("RlcCircuit {} does not declare canInterpolateInputs: interpolation not tested", fmu.fmi_version());
            let sim = master.initialize().unwrap();
            assert_eq!(sim.is_extrapolated("load.u_in"), Some(false));
            continue;
        }
        let out = run(master);
        let u = column(&out, "source.u_capacitor");
        let mut expected = vec![0.0];
        for k in 0..u.len() - 1 {
            expected.push(rl_step(expected[k], u[k], (u[k + 1] - u[k]) / h, h));
        }
        let i = column(&out, "load.i_high_frequency");
        let e = max_diff(i, &expected);
        eprintln!("interpolated Gauss-Seidel: max |i - reference| = {e:.2e} A");
        assert!(e < 1e-7 * max_abs(i), "{e}");
    }
}

/// Gauss-Seidel through a direct-feedthrough stage: a -> b.u_in, b.u_source (= u_in, its sine
/// off) -> c.u_in. What c gets is b's output at the end of the step, i.e. with b's input at the
/// end of its interpolated line: c's input follows the straight line between a's outputs.
#[test]
fn gauss_seidel_reads_feedthrough_outputs_at_the_end_of_the_step() {
    // FMI 2.0 only: needs fmi2SetRealInputDerivatives (module comment).
    let Some(fmu) = rlc_fmi2_only() else { return };
    let cs = fmu.model_description().co_simulation.clone().unwrap();
    if !cs.can_interpolate_inputs {
        eprintln!("RlcCircuit does not declare canInterpolateInputs: not tested");
        return;
    }
    let h = 2e-4;
    let system = System::new()
        .with(Component::new("a", &fmu))
        .with(Component::new("b", &fmu).real("U_amplitude", 0.0))
        .with(Component::new("c", &fmu).real("U_amplitude", 0.0))
        .connect("a.u_capacitor", "b.u_in")
        .connect("b.u_source", "c.u_in");
    let out = run(
        Master::new(system, h, 0.04)
            .algorithm(Algorithm::gauss_seidel())
            .tolerance(Some(1e-10))
            .record(["a.u_capacitor", "c.i_high_frequency"]),
    );
    let u = column(&out, "a.u_capacitor");
    let mut expected = vec![0.0];
    for k in 0..u.len() - 1 {
        expected.push(rl_step(expected[k], u[k], (u[k + 1] - u[k]) / h, h));
    }
    let i = column(&out, "c.i_high_frequency");
    let e = max_diff(i, &expected);
    assert!(e < 1e-7 * max_abs(i), "{e}");
}

/// With extrapolation (where supported), Jacobi is closer to a fine-step reference than with
/// inputs held constant. FMI 3.0 (no input derivatives): the switch changes nothing.
#[test]
fn extrapolation_improves_jacobi_when_supported() {
    for fmu in rlc_of_every_version() {
        eprintln!("RlcCircuit {}", fmu.fmi_version());
        let cs = fmu.model_description().co_simulation.clone().unwrap();
        let supported = cs.can_interpolate_inputs && cs.max_output_derivative_order >= 1;
        let reference = run(Master::new(chain(&fmu), 1e-6, 0.02).record(RECORD));
        let coarse = |extrapolation: bool| {
            let master = Master::new(chain(&fmu), 1e-4, 0.02).extrapolation(extrapolation).record(RECORD);
            assert_eq!(master.initialize().unwrap().is_extrapolated("load.u_in"), Some(extrapolation && supported));
            run(master)
        };
        let error = |out: &Outcome| {
            let fine = column(&reference, "load.i_high_frequency");
            let coarse = column(out, "load.i_high_frequency");
            coarse.iter().enumerate().fold(0.0f64, |m, (k, x)| m.max((x - fine[100 * k]).abs()))
        };
        let (held, extrapolated) = (error(&coarse(false)), error(&coarse(true)));
        eprintln!("Jacobi at 0.1 ms vs 1 us: held {held:.3e} A, extrapolated {extrapolated:.3e} A (supported: {supported})");
        if supported {
            assert!(extrapolated < 0.2 * held, "{extrapolated} vs {held}");
        } else {
            assert_eq!(held, extrapolated);
        }
    }
}

/// Error control: steps are rejected at a coarse communication step, the states restored (the
/// first stage still follows its uncoupled trajectory), the stop time reached, every
/// communication point recorded, and the coupled result is closer to a fine reference.
#[test]
fn step_rejection_restores_states_and_reaches_the_end() {
    for fmu in rlc_of_every_version() {
        eprintln!("RlcCircuit {}", fmu.fmi_version());
        let (h, stop) = (1e-3, 0.03);
        let reference = run(Master::new(chain(&fmu), 1e-6, stop).extrapolation(false).record(RECORD));
        let master = |ec: Option<ErrorControl>| {
            Master::new(chain(&fmu), h, stop).extrapolation(false).error_control(ec).record(RECORD)
        };
        let plain = run(master(None));
        let controlled = run(master(Some(ErrorControl::new(0.05).min_step(h / 128.0))));
        let s = &controlled.stats;
        eprintln!("{s:?}");
        assert!(s.rejected_steps > 0, "a 1 ms step on a 159 Hz circuit must be rejected");
        assert!(s.accepted_steps > s.communication_steps, "{s:?}");
        assert_eq!(s.communication_steps, 30);
        assert!(s.smallest_step >= h / 128.0 && s.smallest_step < h, "{s:?}");
        assert_eq!(s.accepted_over_tolerance, 0, "{s:?}");
        assert!(s.largest_error_estimate <= 0.05);
        assert_eq!(controlled.results.len(), 31);
        assert_eq!(*controlled.results.time().last().unwrap(), stop);
        assert_eq!(controlled.results.time(), plain.results.time());

        let at_grid = |out: &Outcome, name: &str| -> f64 {
            let fine = column(&reference, name);
            let v = column(out, name);
            v.iter().enumerate().fold(0.0f64, |m, (k, x)| m.max((x - fine[1000 * k]).abs()))
        };
        // A restored state: the input-free source is still on its own trajectory.
        let source_error = at_grid(&controlled, "source.i_absorbed");
        assert!(source_error < 1e-5 * max_abs(column(&reference, "source.i_absorbed")), "{source_error}");
        let (e_plain, e_controlled) = (at_grid(&plain, "load.i_high_frequency"), at_grid(&controlled, "load.i_high_frequency"));
        eprintln!("load current error vs 1 us: plain {e_plain:.3e} A, controlled {e_controlled:.3e} A");
        assert!(e_controlled < 0.25 * e_plain);
    }
}

/// Error control that never rejects changes nothing: saving states does not disturb a run.
#[test]
fn error_control_without_rejection_equals_the_plain_run() {
    for fmu in rlc_of_every_version() {
        eprintln!("RlcCircuit {}", fmu.fmi_version());
        let master = |ec| Master::new(chain(&fmu), 1e-4, 0.01).error_control(ec).record(RECORD);
        let plain = run(master(None));
        let loose = run(master(Some(ErrorControl::new(1e9))));
        assert_eq!(loose.stats.rejected_steps, 0);
        assert_eq!(plain.results, loose.results);
    }
}

/// Connections are exchanged in feedthrough order whatever the order they are declared in:
/// u_source = sine + u_in is direct feedthrough, so c.u_in = b.u_source = a.u_source.
#[test]
fn feedthrough_chains_are_exchanged_in_dependency_order() {
    for fmu in rlc_of_every_version() {
        eprintln!("RlcCircuit {}", fmu.fmi_version());
        let system = System::new()
            .with(Component::new("a", &fmu).real("frequency", 120.0))
            .with(Component::new("b", &fmu).real("U_amplitude", 0.0))
            .with(Component::new("c", &fmu).real("U_amplitude", 0.0))
            .connect("b.u_source", "c.u_in")
            .connect("a.u_source", "b.u_in");
        let out = run(Master::new(system, 1e-3, 0.02).record(["a.u_source", "c.u_in", "c.u_source"]));
        let a = column(&out, "a.u_source");
        assert!(max_abs(a) > 1.0);
        assert_eq!(column(&out, "c.u_in"), a);
        assert_eq!(column(&out, "c.u_source"), a);
    }
}

/// The derivative of an output can depend on an input its value does not depend on: here
/// d(i_absorbed)/dt = (u_source - R_series i_absorbed - u_capacitor) / L_series, with u_source
/// = sine + u_in. The derivative handed to the consumer must be that of the new u_in, even
/// though the connection feeding u_in comes later in the list.
#[test]
fn output_derivatives_are_read_after_every_input_is_set() {
    // FMI 2.0 only: needs fmi2SetRealInputDerivatives (module comment).
    let Some(fmu) = rlc_fmi2_only() else { return };
    let cs = fmu.model_description().co_simulation.clone().unwrap();
    if !(cs.can_interpolate_inputs && cs.max_output_derivative_order >= 1) {
        eprintln!("RlcCircuit has no input/output derivatives: not tested");
        return;
    }
    let system = System::new()
        .with(Component::new("a", &fmu))
        .with(Component::new("b", &fmu).real("frequency", 170.0))
        .connect("a.i_absorbed", "b.u_in")
        .connect("b.u_capacitor", "a.u_in");
    let mut sim = Master::new(system, 2e-4, 0.01).initialize().unwrap();
    let mut checked = 0;
    while sim.step().unwrap() {
        let get = |sim: &mut fmi_host::master::Simulation, p: &str| sim.get_real(p).unwrap();
        let (u, i, uc) = (get(&mut sim, "a.u_source"), get(&mut sim, "a.i_absorbed"), get(&mut sim, "a.u_capacitor"));
        assert_eq!(get(&mut sim, "a.u_in"), get(&mut sim, "b.u_capacitor"));
        let expected = (u - R_SERIES * i - uc) / L_SERIES;
        let given = sim.input_derivative("b.u_in").unwrap();
        assert!((given - expected).abs() <= 1e-5 * expected.abs().max(1.0), "t = {}: {given} vs {expected}", sim.time());
        checked += 1;
    }
    assert_eq!(checked, 50);
    assert_eq!(sim.input_derivative("a.u_source"), None);
}

#[test]
fn an_algebraic_loop_is_refused() {
    for fmu in rlc_of_every_version() {
        eprintln!("RlcCircuit {}", fmu.fmi_version());
        let system = System::new()
            .with(Component::new("a", &fmu))
            .with(Component::new("b", &fmu))
            .connect("a.u_source", "b.u_in")
            .connect("b.u_source", "a.u_in");
        match Master::new(system, 1e-3, 0.01).initialize() {
            Err(MasterError::AlgebraicLoop(links)) => assert_eq!(links.len(), 2, "{links:?}"),
            other => panic!("expected an algebraic loop, got {:?}", other.err()),
        }
        // Through a state (no feedthrough) the same ring is fine.
        let system = System::new()
            .with(Component::new("a", &fmu))
            .with(Component::new("b", &fmu))
            .connect("a.u_capacitor", "b.u_in")
            .connect("b.u_capacitor", "a.u_in");
        run(Master::new(system, 1e-3, 0.01));
    }
}

#[test]
fn configuration_errors_are_reported() {
    for fmu in rlc_of_every_version() {
        eprintln!("RlcCircuit {}", fmu.fmi_version());
        let err = |system: System, algorithm: Algorithm| -> String {
            match Master::new(system, 1e-3, 0.01).algorithm(algorithm).initialize() {
                Ok(_) => panic!("accepted"),
                Err(e) => e.to_string(),
            }
        };
        let two = || System::new().with(Component::new("a", &fmu)).with(Component::new("b", &fmu));
        let e = err(two().connect("a.u_source", "x.u_in"), Algorithm::Jacobi);
        assert!(e.contains("no instance named \"x\""), "{e}");
        let e = err(two().connect("a.u_in", "b.u_in"), Algorithm::Jacobi);
        assert!(e.contains("a.u_in is not an output"), "{e}");
        let e = err(two().connect("a.u_source", "b.i_absorbed"), Algorithm::Jacobi);
        assert!(e.contains("b.i_absorbed is not an input"), "{e}");
        let e = err(two().connect("a.nope", "b.u_in"), Algorithm::Jacobi);
        assert!(e.contains("\"nope\""), "{e}");
        let e = err(two().connect("a.u_source", "b.u_in").connect("a.u_capacitor", "b.u_in"), Algorithm::Jacobi);
        assert!(e.contains("connected twice"), "{e}");
        let e = err(two().connect("au_source", "b.u_in"), Algorithm::Jacobi);
        assert!(e.contains("instance.variable"), "{e}");
        let e = err(two(), Algorithm::gauss_seidel_in(["a"]));
        assert!(e.contains("every instance exactly once"), "{e}");
        let e = err(two().with(Component::new("a", &fmu)), Algorithm::Jacobi);
        assert!(e.contains("two instances are named \"a\""), "{e}");
        let e = err(System::new().with(Component::new("a", &fmu).integer("R_load", 3)), Algorithm::Jacobi);
        assert!(e.contains("a.R_load is Real, not Integer"), "{e}");
        assert!(Master::new(two(), 0.0, 1.0).initialize().is_err());
        assert!(Master::new(two(), 1e-3, 0.0).initialize().is_err());
    }
}

/// An FMU refusing a call is an error naming the instance and the function (fmi2SetReal,
/// FMI 3.0 fmi3SetFloat64), with the FMU's message, not a panic.
#[test]
fn an_fmu_error_names_the_instance_and_the_call() {
    for fmu in rlc_of_every_version() {
        eprintln!("RlcCircuit {}", fmu.fmi_version());
        let system = chain(&fmu);
        let mut system = system;
        system.components[1] = Component::new("load", &fmu).real("R_load", -1.0);
        match Master::new(system, 1e-3, 0.01).initialize() {
            Err(MasterError::Call { instance, call, status, log, .. }) => {
                assert_eq!(instance, "load");
                let expected = match fmu.fmi_version() {
                    FmiVersion::Fmi2 => "fmi2SetReal",
                    FmiVersion::Fmi3 => "fmi3SetFloat64",
                };
                assert_eq!(call, expected);
                assert_eq!(status, Status::ERROR);
                assert!(log.iter().any(|r| r.message.contains("R_load")), "{log:?}");
            }
            other => panic!("expected an fmi2SetReal / fmi3SetFloat64 error, got {:?}", other.err()),
        }
    }
}

/// Step by step: the simulation can be read between steps and ends at the stop time.
#[test]
fn stepping_by_hand() {
    for fmu in rlc_of_every_version() {
        eprintln!("RlcCircuit {}", fmu.fmi_version());
        let mut sim = Master::new(chain(&fmu), 1e-3, 0.005).initialize().unwrap();
        assert_eq!(sim.time(), 0.0);
        let mut steps = 0;
        while sim.step().unwrap() {
            steps += 1;
            let (u, v) = (sim.get_real("source.u_capacitor").unwrap(), sim.get_real("load.u_in").unwrap());
            assert_eq!(u, v);
        }
        assert_eq!(steps, 5);
        assert!(sim.is_finished());
        assert_eq!(sim.time(), 0.005);
        assert!(!sim.step().unwrap());
        assert!(sim.get_real("load.nope").is_err());
        let outcome = sim.finish().unwrap();
        assert_eq!(outcome.results.len(), 6);
    }
}
