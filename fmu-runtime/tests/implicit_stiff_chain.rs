//! The implicit method on a stiff model, through a discontinuity at a declared time event, at
//! the default tolerance: the torsional chain of the size benchmark (bench/torsional-chain) made
//! stiff (J = 1e-4 kg m2, K = 1e5 N m/rad, D = 10 N m s/rad), at rest until a 100 N m torque
//! steps on at `step_time`, written either `t >= step_time` or `t > step_time` (the model's
//! choice of side), checked against the exact solution (the matrix exponential of the linear
//! chain, computed here). Also: the explicit method through the same event, both sides; and an
//! FMU state restored (serialized, into another instance) continues bit for bit with the
//! implicit method's kept Jacobian, dense, band and sparse. The models: `fmu_runtime::testing::chains`.

use fmu_runtime::instance::Instance;
use fmu_runtime::log::Logger;
use fmu_runtime::prelude::*;

use fmu_runtime::testing::chains::{Chain, Star};

const STIFF: [(&str, f64); 3] = [("J", 1e-4), ("K", 1e5), ("D", 10.0)];
const STEP: f64 = 1e-3;

fn vr<M: Model>(i: &Instance<M>, name: &str) -> u32 {
    i.table().by_name(name).unwrap_or_else(|| panic!("{name}")).value_reference
}

/// An initialized instance with these real parameters, at the default tolerance.
fn chain<M: Model>(parameters: &[(&str, f64)]) -> Instance<M> {
    fmu_runtime::testing::initialized_with(&[], parameters)
}

/// The states (speeds, then twists) after each 1 ms doStep up to `stop`.
fn run<M: Model>(i: &mut Instance<M>, n: usize, stop: f64) -> Vec<Vec<f64>> {
    let vrs: Vec<u32> = (1..=n).map(|k| vr(i, &format!("w_{k}"))).chain((1..n).map(|k| vr(i, &format!("theta_{k}")))).collect();
    let steps = (stop / STEP).round() as usize;
    let mut out = Vec::with_capacity(steps);
    for s in 0..steps {
        let t = s as f64 * STEP;
        i.do_step(t, STEP).unwrap_or_else(|e| panic!("doStep from {t} s: {}", e.message));
        let mut x = vec![0.0; vrs.len()];
        i.get(&vrs, &mut x).unwrap();
        out.push(x);
    }
    out
}

/// The chain's x' = A x + b T (T the drive torque), dense, row-major, the states as the model orders them.
fn system(n: usize, j: f64, k: f64, d: f64, c: f64) -> (Vec<Vec<f64>>, Vec<f64>) {
    let m = 2 * n - 1;
    let mut a = vec![vec![0.0; m]; m];
    let theta = |i: usize| n + i;
    for i in 0..n {
        if i + 1 < n {
            // T_i = K theta_i + D (w_i - w_{i+1}) leaves inertia i, enters inertia i + 1.
            for (row, sign) in [(i, -1.0), (i + 1, 1.0)] {
                a[row][theta(i)] += sign * k / j;
                a[row][i] += sign * d / j;
                a[row][i + 1] -= sign * d / j;
            }
            a[theta(i)][i] = 1.0;
            a[theta(i)][i + 1] = -1.0;
        } else {
            a[i][i] -= c / j;
        }
    }
    let mut b = vec![0.0; m];
    b[0] = 1.0 / j;
    (a, b)
}

fn matmul(a: &[Vec<f64>], b: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let m = a.len();
    let mut c = vec![vec![0.0; m]; m];
    for i in 0..m {
        for k in 0..m {
            let aik = a[i][k];
            if aik != 0.0 {
                for j in 0..m {
                    c[i][j] += aik * b[k][j];
                }
            }
        }
    }
    c
}

/// exp(M) by scaling and squaring of its Taylor series.
fn expm(m: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let size = m.len();
    let norm = m.iter().map(|r| r.iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max);
    let squarings = (norm / 0.25).log2().ceil().max(0.0) as i32;
    let scale = 0.5f64.powi(squarings);
    let scaled: Vec<Vec<f64>> = m.iter().map(|r| r.iter().map(|v| v * scale).collect()).collect();
    let identity = |s: usize| (0..s).map(|i| (0..s).map(|j| if i == j { 1.0 } else { 0.0 }).collect()).collect::<Vec<Vec<f64>>>();
    // Horner: I + M (I + M/2 (I + M/3 (...)))
    let mut e = identity(size);
    for k in (1..=20).rev() {
        let mut p = matmul(&scaled, &e);
        for (i, row) in p.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = *v / k as f64 + if i == j { 1.0 } else { 0.0 };
            }
        }
        e = p;
    }
    for _ in 0..squarings {
        e = matmul(&e, &e);
    }
    e
}

/// The exact states after each 1 ms doStep up to `stop`: at rest until `step_time`, then the
/// response to the torque `torque` (the exponential of the system augmented by the constant
/// input: exp([[A, b T], [0, 0]] tau) holds the forced response in its last column).
fn exact(n: usize, p: (f64, f64, f64, f64), torque: f64, step_time: f64, stop: f64) -> Vec<Vec<f64>> {
    let (a, b) = system(n, p.0, p.1, p.2, p.3);
    let m = a.len();
    let augmented = |tau: f64| {
        let mut g = vec![vec![0.0; m + 1]; m + 1];
        for i in 0..m {
            for j in 0..m {
                g[i][j] = a[i][j] * tau;
            }
            g[i][m] = b[i] * torque * tau;
        }
        expm(&g)
    };
    let steps = (stop / STEP).round() as usize;
    let first = (0..steps).find(|s| (s + 1) as f64 * STEP >= step_time).unwrap();
    // Propagate by exp(G h) from the first point after the step (computed on its own).
    let e_step = augmented(STEP);
    let mut z = vec![0.0; m + 1];
    let mut out = Vec::with_capacity(steps);
    for s in 0..steps {
        let t = (s + 1) as f64 * STEP;
        if s < first {
            out.push(vec![0.0; m]);
            continue;
        }
        if s == first {
            let e = augmented(t - step_time);
            z = (0..=m).map(|i| e[i][m]).collect();
        } else {
            z = (0..=m).map(|i| (0..=m).map(|j| e_step[i][j] * z[j]).sum()).collect();
        }
        out.push(z[..m].to_vec());
    }
    out
}

/// The largest error of any speed over the run, in units of the largest speed.
fn speed_error(got: &[Vec<f64>], exact: &[Vec<f64>], n: usize) -> f64 {
    let largest = exact.iter().flat_map(|x| x[..n].iter()).fold(0.0f64, |a, v| a.max(v.abs()));
    let worst = got.iter().zip(exact).flat_map(|(g, e)| g[..n].iter().zip(&e[..n]).map(|(a, b)| (a - b).abs())).fold(0.0f64, f64::max);
    worst / largest
}

const DEFAULT_RTOL: f64 = fmu_runtime::integrate::DEFAULT_RELATIVE_TOLERANCE;

/// The stiff chain of 20 inertias (39 states: the dense Newton matrix) at the default
/// tolerance, the torque step on a communication point (0.1 s) and inside a doStep (0.1005 s),
/// on either side of its instant: every speed within 10 x rtol of the largest one at every
/// communication point. diffsol's esdirk34 failed every one of these ("step size is too
/// small": the jump fell inside a step's stage) and, without the jump, was 16 x rtol off.
#[test]
fn the_stiff_chain_at_the_default_tolerance_through_a_torque_step_on_either_side() {
    const N: usize = 20;
    let stop = 0.3;
    for step_time in [0.1, 0.1005] {
        let reference = exact(N, (1e-4, 1e5, 10.0, 1.0), 100.0, step_time, stop);
        let parameters = [STIFF[0], STIFF[1], STIFF[2], ("step_time", step_time)];
        let at_or_after = run(&mut chain::<Chain<N, true, true>>(&parameters), N, stop);
        let after = run(&mut chain::<Chain<N, false, true>>(&parameters), N, stop);
        for (form, got) in [("t >= step_time", &at_or_after), ("t > step_time", &after)] {
            let error = speed_error(got, &reference, N);
            eprintln!("stiff chain N = {N}, step at {step_time} s, {form}: error {:.2} x rtol", error / DEFAULT_RTOL);
            assert!(error < 10.0 * DEFAULT_RTOL, "{form}, step at {step_time} s: {error:e} of the largest speed");
        }
    }
}

/// The same at 60 inertias (119 states: the Newton matrix not dense; a band since the band LU,
/// faer's sparse LU before), the torque step inside a
/// doStep, written `t >= step_time`: every speed within 10 x rtol of the largest one at every
/// communication point.
#[test]
fn the_sparse_stiff_chain_at_the_default_tolerance_through_a_torque_step() {
    const N: usize = 60;
    assert!(2 * N - 1 >= fmu_runtime::stepper::jacobian::DENSE_BELOW);
    let (stop, step_time) = (0.2, 0.1005);
    let reference = exact(N, (1e-4, 1e5, 10.0, 1.0), 100.0, step_time, stop);
    let parameters = [STIFF[0], STIFF[1], STIFF[2], ("step_time", step_time)];
    let got = run(&mut chain::<Chain<N, true, true>>(&parameters), N, stop);
    let error = speed_error(&got, &reference, N);
    eprintln!("stiff chain N = {N}, step at {step_time} s: error {:.2} x rtol", error / DEFAULT_RTOL);
    assert!(error < 10.0 * DEFAULT_RTOL, "{error:e} of the largest speed");
}

/// The same steps with the explicit method (the non-stiff chain: the model's defaults).
#[test]
fn the_explicit_method_through_the_same_torque_step_on_either_side() {
    const N: usize = 5;
    let stop = 0.3;
    for step_time in [0.1, 0.1005] {
        let reference = exact(N, (1.0, 1e4, 1.0, 1.0), 100.0, step_time, stop);
        let parameters = [("step_time", step_time)];
        let at_or_after = run(&mut chain::<Chain<N, true, false>>(&parameters), N, stop);
        let after = run(&mut chain::<Chain<N, false, false>>(&parameters), N, stop);
        for (form, got) in [("t >= step_time", &at_or_after), ("t > step_time", &after)] {
            let error = speed_error(got, &reference, N);
            eprintln!("explicit chain N = {N}, step at {step_time} s, {form}: error {:.2} x rtol", error / DEFAULT_RTOL);
            assert!(error < 10.0 * DEFAULT_RTOL, "{form}, step at {step_time} s: {error:e} of the largest speed");
        }
    }
}

/// Steps `a` and a twin restored from `a`'s serialized state of before each step, with an
/// input change halfway: their states agree bit for bit after every step.
fn restored_twins_agree<M: Model>(n_states: usize) {
    let parameters = [STIFF[0], STIFF[1], STIFF[2], ("step_time", 0.01)];
    let (mut a, mut twin) = (chain::<M>(&parameters), chain::<M>(&parameters));
    let load = vr(&a, "load_torque");
    let state_vrs: Vec<u32> = a.table().variables.iter().filter(|v| v.name.starts_with("w_") || v.name.starts_with("theta_")).map(|v| v.value_reference).collect();
    assert_eq!(state_vrs.len(), n_states);
    let mut t = 0.0;
    for k in 0..40 {
        if k == 25 {
            a.set(&[load], &[-20.0]).unwrap();
        }
        let saved = a.get_fmu_state(None).unwrap();
        let bytes = a.serialize_fmu_state(saved).unwrap();
        a.free_fmu_state(saved).unwrap();
        let restored = twin.deserialize_fmu_state(&bytes, None).unwrap();
        twin.set_fmu_state(restored).unwrap();
        twin.free_fmu_state(restored).unwrap();
        a.do_step(t, STEP).unwrap();
        twin.do_step(t, STEP).unwrap();
        let (mut xa, mut xb) = (vec![0.0; n_states], vec![0.0; n_states]);
        a.get(&state_vrs, &mut xa).unwrap();
        twin.get(&state_vrs, &mut xb).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&xa), bits(&xb), "states after the step from {t} s");
        t += STEP;
    }
}

#[test]
fn a_restored_state_continues_bit_for_bit_with_the_kept_jacobian_dense_and_sparse() {
    // 2 x 3 - 1 = 5 states: dense (the band's rows, 7 entries, wider than the matrix); 2 x 10
    // - 1 = 19: below DENSE_BELOW, a band; 79: a band (and below, sparse).
    assert!(19 < fmu_runtime::stepper::jacobian::DENSE_BELOW && 79 >= fmu_runtime::stepper::jacobian::DENSE_BELOW);
    restored_twins_agree::<Chain<3, true, true>>(5);
    restored_twins_agree::<Chain<10, true, true>>(19);
    restored_twins_agree::<Chain<40, true, true>>(79);
}

/// The same twins on the band LU (the chain of 40 inertias) and on faer's sparse LU (the star of
/// 20 spokes), each structure checked to be the one factorized that way.
#[test]
fn a_restored_state_continues_bit_for_bit_with_the_kept_jacobian_band_and_sparse() {
    use fmu_runtime::stepper::jacobian::{probe, Structure};
    let chain_pattern = |n: usize| {
        let (a, _) = system(n, 1e-4, 1e5, 10.0, 1.0);
        let m = 2 * n - 1;
        let rhs = |x: &[f64], _t: f64, y: &mut [f64]| {
            for (i, row) in a.iter().enumerate() {
                y[i] = row.iter().zip(x).map(|(r, v)| r * v).sum();
            }
        };
        probe(&rhs, 0.0, &vec![0.0; m], &vec![1.0; m])
    };
    assert_eq!(Structure::sparse(79, chain_pattern(40)).unwrap().kind(), "band");
    restored_twins_agree::<Chain<40, true, true>>(79);
    const K: usize = 20;
    let (star, _, table) = fmu_runtime::model::declare::<Star<K>>();
    let v = table.start_values();
    let rhs = |x: &[f64], t: f64, y: &mut [f64]| fmu_runtime::model::evaluate_derivatives(&star, t, &v.known, x, &v.integers, &v.booleans, y);
    let pattern = probe(&rhs, 0.0, &vec![0.0; 2 * K + 1], &vec![1.0; 2 * K + 1]);
    assert_eq!(Structure::sparse(2 * K + 1, pattern).unwrap().kind(), "sparse");
    restored_twins_agree::<Star<K>>(2 * K + 1);
}

/// The chain's probed structure is its band: each speed's derivative depends on at most five
/// states, each twist's on two; a handful of colors, whatever N.
#[test]
fn the_chain_structure_is_banded_and_takes_a_few_colors() {
    use fmu_runtime::stepper::jacobian::{probe, Structure};
    for n in [50, 400] {
        let m = 2 * n - 1;
        let (a, _) = system(n, 1e-4, 1e5, 10.0, 1.0);
        let rhs = |x: &[f64], _t: f64, y: &mut [f64]| {
            for (i, row) in a.iter().enumerate() {
                y[i] = row.iter().zip(x).map(|(r, v)| r * v).sum();
            }
        };
        let x = vec![0.0; m];
        let s = Structure::sparse(m, probe(&rhs, 0.0, &x, &vec![1.0; m])).unwrap();
        assert!(!s.is_dense());
        // Rows of speeds: 5 entries (3 at the ends); rows of twists: 2 and the diagonal.
        assert_eq!(s.nnz(), 5 * n - 4 + 3 * (n - 1), "entries at N = {n}");
        assert!(s.colors() <= 7, "{} colors at N = {n}", s.colors());
    }
}

/// x' = m, the mode m = 1 once a command c(t) has stepped from 0 to 1 at `t_on` (written
/// `t >= t_on` or `t > t_on`: `AT_OR_AFTER`), an event indicator c - 1/2 that jumps at the time
/// event: whichever side, whichever method, one state event, and x = t - t_on after it.
struct Gate<const AT_OR_AFTER: bool, const IMPLICIT: bool> {
    t_on: Parameter,
    x: State,
    mode: Mode,
    z: Indicator,
}

impl<const AT_OR_AFTER: bool, const IMPLICIT: bool> Gate<AT_OR_AFTER, IMPLICIT> {
    fn command(&self, k: &Knowns) -> f64 {
        let on = if AT_OR_AFTER { k.time() >= k[self.t_on] } else { k.time() > k[self.t_on] };
        if on {
            1.0
        } else {
            0.0
        }
    }
}

impl<const AT_OR_AFTER: bool, const IMPLICIT: bool> Model for Gate<AT_OR_AFTER, IMPLICIT> {
    fn info() -> ModelInfo {
        ModelInfo { solver: if IMPLICIT { Solver::ImplicitRungeKutta } else { Solver::ExplicitRungeKutta }, ..Chain::<2, true, true>::info() }
    }
    fn declare(d: &mut Declarations) -> Self {
        Gate {
            t_on: d.parameter("t_on", 0.1, "s").describe("time of the command's step"),
            x: d.state("x", 0.0, "s").describe("time since the gate opened"),
            mode: d.mode("open", 0).range(0, 1).describe("1 once the command is on"),
            z: d.event_indicator("command", "the command minus one half"),
        }
    }
    fn next_time_event(&self, k: &Knowns, after: f64) -> Option<f64> {
        (k[self.t_on] > after).then(|| k[self.t_on])
    }
    fn event_indicators(&self, k: &Knowns, z: &mut EventIndicators) {
        z[self.z] = self.command(k) - 0.5;
    }
    fn update_modes(&self, k: &Knowns, next: &mut ModeUpdate) {
        next[self.mode] = (self.command(k) > 0.5) as i32;
    }
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        der[self.x] = R::from(k[self.mode] as f64);
    }
    fn outputs<R: Real>(&self, _: &Knowns<R>, _: &mut Outputs<R>) {}
}

fn gate_run<M: Model>(t_on: f64) -> (f64, i32) {
    let mut i = chain::<M>(&[("t_on", t_on)]);
    let mut t = 0.0;
    for _ in 0..20 {
        i.do_step(t, 0.01).unwrap();
        t += 0.01;
    }
    let (x, events) = (vr(&i, "x"), vr(&i, "state_events"));
    let (mut xv, mut ev) = ([0.0], [0]);
    i.get(&[x], &mut xv).unwrap();
    i.get(&[events], &mut ev).unwrap();
    (xv[0], ev[0])
}

#[test]
fn an_indicator_that_jumps_at_a_time_event_is_one_state_event_on_either_side() {
    // On a communication point (0.1 = 10 x 0.01) and inside a doStep; t = 0.2 at the end.
    for t_on in [0.1, 0.1037] {
        for (label, (x, events)) in [
            ("explicit, t >= t_on", gate_run::<Gate<true, false>>(t_on)),
            ("explicit, t > t_on", gate_run::<Gate<false, false>>(t_on)),
            ("implicit, t >= t_on", gate_run::<Gate<true, true>>(t_on)),
            ("implicit, t > t_on", gate_run::<Gate<false, true>>(t_on)),
        ] {
            assert_eq!(events, 1, "{label}, t_on = {t_on}");
            assert!((x - (0.2 - t_on)).abs() < 1e-9, "{label}, t_on = {t_on}: x = {x}");
        }
    }
}

/// A master handling the events (FMI 3.0 event mode, early return) gets the step back at the
/// time event, updates the modes and steps on: the same solver path, bit for bit, as a step
/// handling the event itself (the integrator knows it ended at the event, whatever the model
/// names after its modes changed there).
fn event_mode_as_inside<M: Model>(t_on: f64) {
    let plain = || chain::<M>(&[("t_on", t_on)]);
    let mut handing = Instance::<M>::new("{chain}", Logger::silent());
    // black_box: with the constants inlined, rustc 1.95 at opt-level >= 2 stores
    // event_mode_used = false (and enter_event_mode then refuses); seen in an external crate
    // calling these two functions, not through the C ABI (see the report of this change).
    handing.hand_events_to_master(std::hint::black_box(true), std::hint::black_box(true));
    let r = vr(&handing, "t_on");
    handing.set(&[r], &[t_on]).unwrap();
    handing.setup_experiment(None, 0.0, None).unwrap();
    handing.enter_initialization_mode().unwrap();
    handing.exit_initialization_mode().unwrap();
    handing.new_discrete_states().unwrap();
    handing.enter_step_mode().unwrap();
    let mut inside = plain();
    let x = vr(&inside, "x");
    let (mut returns, mut t) = (0, 0.0);
    for _ in 0..20 {
        let t_end = t + 0.01;
        inside.do_step(t, 0.01).unwrap();
        let mut at = t;
        loop {
            let end = handing.do_step(at, if at == t { 0.01 } else { t_end - at }).unwrap();
            at = end.time;
            if end.event {
                returns += 1;
                handing.enter_event_mode().unwrap();
                handing.new_discrete_states().unwrap();
                handing.enter_step_mode().unwrap();
            }
            if at >= t_end {
                break;
            }
        }
        let (mut a, mut b) = ([0.0], [0.0]);
        inside.get(&[x], &mut a).unwrap();
        handing.get(&[x], &mut b).unwrap();
        assert_eq!(a[0].to_bits(), b[0].to_bits(), "x at {t_end} s, t_on = {t_on}: {} against {}", a[0], b[0]);
        t = t_end;
    }
    assert!(returns >= 1, "the step returned early at the event");
}

#[test]
fn a_master_handling_the_time_event_steps_as_a_step_handling_it_inside() {
    for t_on in [0.1, 0.1037] {
        event_mode_as_inside::<Gate<true, false>>(t_on);
        event_mode_as_inside::<Gate<false, false>>(t_on);
        event_mode_as_inside::<Gate<true, true>>(t_on);
        event_mode_as_inside::<Gate<false, true>>(t_on);
    }
}
