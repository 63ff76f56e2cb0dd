//! The size benchmark of issue 25 ("Models of any size"), the native side: `bench/chain.py`
//! builds the torsional chain (`bench/torsional-chain`) at each size and runs, for each FMU, one
//! fresh process of
//!
//! ```text
//! fmu-bench chain --fmu FMU --out JSON [--real NAME=VALUE]... [--tolerance RTOL] [--repeats N]
//!     [--step-budget S] [--jacobian-budget S] [--memory-budget S] [--record VRFILE --record-out BIN]
//! fmu-bench chain-describe --lib LIB --out JSON
//! ```
//!
//! `chain`, in this order, in one process (the first instantiation in a process is the one that
//! pays for what the library makes once):
//! 1. the first instantiation: `fmi2Instantiate`, the parameters (`--real`),
//!    `fmi2SetupExperiment`, `fmi2EnterInitializationMode`, `fmi2ExitInitializationMode`, each
//!    timed (wall and CPU time of the process), and the peak RSS after it; freed;
//! 2. a second instantiation, timed the same way; freed;
//! 3. memory: as many instances as `--memory-budget` seconds allow at the second's cost (2 to
//!    100), instantiated and initialized, alive at once: the growth of RSS and of the malloc heap
//!    in use, per instance (the method of `fmu-bench memory`);
//! 4. the full Jacobian of the state derivatives by directional derivatives after
//!    initialization: one `fmi2GetDirectionalDerivative` per state (all derivatives as unknowns,
//!    that state as the known, seed 1), until `--jacobian-budget` seconds of CPU are spent (the
//!    rest extrapolated from the mean per column, and said so); the nonzeros are written to
//!    `--jacobian-out` if given;
//! 5. the doStep cost: `--repeats` runs over the DefaultExperiment (1 s at 1 ms), each on a fresh
//!    instance, the loop alone timed (`fmi2DoStep` + `fmi2GetReal` of the outputs, CPU time of
//!    the thread), median; the runs stop when `--step-budget` seconds of stepping are spent (a run
//!    cut short is extrapolated from its mean per doStep, and said so);
//! 6. with `--record`: one more run on a fresh instance (not timed) that writes the value
//!    references listed in VRFILE (one a line) after every doStep to BIN, little-endian f64, one
//!    row per communication point.
//!
//! The states and their derivatives are found from the ModelStructure (`<Derivatives>` and each
//! derivative's `derivative` attribute), never by name. Any failure is written to the JSON as
//! `"error"` (with the phase it stopped in) and the figures measured until then; the exit status
//! is 0 so that the caller reads it.
//!
//! `chain-describe` loads a model library in a fresh process and calls what `build-fmus`
//! calls to package it, in its order (problems, identifier, effects, standards, each
//! standard's description and documentation), each timed: the description and dependency
//! probe's share of `build-fmus build`.

use std::ffi::{c_char, CStr};
use std::sync::Arc;
use std::time::Instant;

use fmi_host::{Fmu, Instance, Status, ValueReference};

use crate::json::Json;
use crate::{check, heap_in_use_bytes, load, median, rss_kb, thread_cpu_seconds, Args};

/// CPU time of the whole process, s (CLOCK_PROCESS_CPUTIME_ID): an instantiation may use
/// other threads.
fn process_cpu_seconds() -> f64 {
    const CLOCK_PROCESS_CPUTIME_ID: i32 = 2;
    let mut ts = crate::Timespec { sec: 0, nsec: 0 };
    // SAFETY: a valid clock id and a pointer to a live timespec.
    unsafe { crate::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    ts.sec as f64 + ts.nsec as f64 * 1e-9
}

/// Peak resident set size of this process so far, kB (VmHWM).
fn peak_rss_kb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap_or(f64::NAN)
}

/// Wall and process-CPU seconds of `f`.
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64, f64) {
    let (wall, cpu) = (Instant::now(), process_cpu_seconds());
    let value = f();
    (value, wall.elapsed().as_secs_f64(), process_cpu_seconds() - cpu)
}

/// What `chain` was asked to do.
struct Options {
    reals: Vec<(String, f64)>,
    tolerance: Option<f64>,
    repeats: usize,
    step_budget: f64,
    jacobian_budget: f64,
    memory_budget: f64,
    jacobian_out: Option<String>,
    record: Option<(String, String)>,
}

impl Options {
    fn parse(args: &Args) -> Result<Options, String> {
        let number = |name: &str, default: f64| -> Result<f64, String> {
            args.get(name).map_or(Ok(default), |v| v.parse().map_err(|e| format!("{name} {v}: {e}")))
        };
        let mut reals = Vec::new();
        for (i, a) in args.0.iter().enumerate() {
            if a == "--real" {
                let pair = args.0.get(i + 1).ok_or("--real needs NAME=VALUE")?;
                let (name, value) = pair.split_once('=').ok_or_else(|| format!("--real {pair}: not NAME=VALUE"))?;
                reals.push((name.to_string(), value.parse().map_err(|e| format!("--real {pair}: {e}"))?));
            }
        }
        let record = match (args.get("--record"), args.get("--record-out")) {
            (Some(a), Some(b)) => Some((a.to_string(), b.to_string())),
            (None, None) => None,
            _ => return Err("--record and --record-out go together".into()),
        };
        Ok(Options {
            reals,
            tolerance: args.get("--tolerance").map(|v| v.parse().map_err(|e| format!("--tolerance {v}: {e}"))).transpose()?,
            repeats: number("--repeats", 5.0)? as usize,
            step_budget: number("--step-budget", 60.0)?,
            jacobian_budget: number("--jacobian-budget", 30.0)?,
            memory_budget: number("--memory-budget", 10.0)?,
            jacobian_out: args.get("--jacobian-out").map(str::to_string),
            record,
        })
    }
}

/// The model's states and derivatives (value references, in the order of `<Derivatives>`),
/// its outputs, and its DefaultExperiment.
struct Layout {
    states: Vec<ValueReference>,
    derivatives: Vec<ValueReference>,
    outputs: Vec<ValueReference>,
    stop: f64,
    step: f64,
}

fn layout(fmu: &Fmu) -> Result<Layout, String> {
    let md = fmu.model_description();
    let mut states = Vec::new();
    let mut derivatives = Vec::new();
    for unknown in &md.model_structure.continuous_state_derivatives {
        // FMI 2.0 value references are unique per type only: the derivative is the Real with a
        // `derivative` attribute.
        let var = md
            .model_variables
            .iter()
            .find(|v| v.value_reference == unknown.value_reference && v.derivative.is_some())
            .ok_or_else(|| format!("no derivative variable with vr {}", unknown.value_reference))?;
        let index = var.derivative.expect("filtered") as usize;
        let state = md.model_variables.get(index.wrapping_sub(1)).ok_or_else(|| format!("{}: derivative index {index} out of range", var.name))?;
        states.push(state.value_reference);
        derivatives.push(unknown.value_reference);
    }
    let outputs = md.model_structure.outputs.iter().map(|u| u.value_reference).collect();
    let de = md.default_experiment.unwrap_or_default();
    Ok(Layout { states, derivatives, outputs, stop: de.stop_time.unwrap_or(1.0), step: de.step_size.unwrap_or(1e-3) })
}

/// What the instance logged, one message after the other.
fn messages(inst: &Instance) -> String {
    inst.log().records().iter().map(|r| r.message.as_str()).collect::<Vec<_>>().join("; ")
}

/// The figures gathered so far (written even when a later phase fails).
struct Report {
    json: Json,
}

impl Report {
    fn num(&mut self, key: &str, value: f64) {
        let json = std::mem::replace(&mut self.json, Json::object());
        self.json = json.num(key, value);
    }
    fn str(&mut self, key: &str, value: &str) {
        let json = std::mem::replace(&mut self.json, Json::object());
        self.json = json.str(key, value);
    }
    fn nums(&mut self, key: &str, values: &[f64]) {
        let json = std::mem::replace(&mut self.json, Json::object());
        self.json = json.nums(key, values);
    }
}

/// `chain`: see the module's documentation.
pub fn chain(args: &Args) -> Result<(), String> {
    let out = args.path("--out")?;
    let mut report = Report { json: Json::object() };
    let result = chain_into(args, &mut report);
    if let Err((phase, e)) = &result {
        report.str("error", e);
        report.str("error_phase", phase);
        eprintln!("fmu-bench chain: {phase}: {e}");
    }
    report.num("peak_rss_kb_end", peak_rss_kb());
    std::fs::write(&out, report.json.render()).map_err(|e| format!("{}: {e}", out.display()))
}

type PhaseResult<T> = Result<T, (&'static str, String)>;

fn in_phase<T>(phase: &'static str, r: Result<T, String>) -> PhaseResult<T> {
    r.map_err(|e| (phase, e))
}

/// Instantiates and initializes, timing each call; (instance, [instantiate, parameters, setup,
/// enter, exit] as (wall, cpu) pairs).
fn start_timed(fmu: &Arc<Fmu>, opts: &Options, stop: f64, name: &str) -> Result<(Instance, [(f64, f64); 5]), String> {
    let (inst, w0, c0) = timed(|| fmu.instantiate(name, false, false));
    let mut inst = inst.map_err(|e| format!("fmi2Instantiate: {e}"))?;
    let vrs: Vec<ValueReference> = opts.reals.iter().map(|(n, _)| fmu.vr(n).map_err(|e| e.to_string())).collect::<Result<_, _>>()?;
    let values: Vec<f64> = opts.reals.iter().map(|(_, v)| *v).collect();
    let (s, w1, c1) = timed(|| inst.set_real(&vrs, &values));
    check(s, "fmi2SetReal of the parameters")?;
    let (s, w2, c2) = timed(|| inst.setup_experiment(opts.tolerance, 0.0, Some(stop)));
    check(s, "fmi2SetupExperiment")?;
    let (s, w3, c3) = timed(|| inst.enter_initialization_mode());
    check(s, "fmi2EnterInitializationMode")?;
    let (s, w4, c4) = timed(|| inst.exit_initialization_mode());
    check(s, "fmi2ExitInitializationMode")?;
    Ok((inst, [(w0, c0), (w1, c1), (w2, c2), (w3, c3), (w4, c4)]))
}

fn put_start_times(report: &mut Report, prefix: &str, t: &[(f64, f64); 5]) {
    for (i, part) in ["instantiate", "parameters", "setup", "enter_init", "exit_init"].iter().enumerate() {
        report.num(&format!("{prefix}_{part}_wall_s"), t[i].0);
        report.num(&format!("{prefix}_{part}_cpu_s"), t[i].1);
    }
    report.num(&format!("{prefix}_total_wall_s"), t.iter().map(|x| x.0).sum());
    report.num(&format!("{prefix}_total_cpu_s"), t.iter().map(|x| x.1).sum());
}

fn chain_into(args: &Args, report: &mut Report) -> PhaseResult<()> {
    let opts = in_phase("arguments", Options::parse(args))?;
    let path = in_phase("arguments", args.path("--fmu"))?;
    report.num("rss_kb_start", rss_kb());
    let (fmu, wall, cpu) = timed(|| load(&path));
    let fmu = in_phase("load", fmu)?;
    report.num("load_wall_s", wall);
    report.num("load_cpu_s", cpu);
    let lay = in_phase("load", layout(&fmu))?;
    let n = lay.states.len();
    report.num("states", n as f64);
    report.num("rss_kb_loaded", rss_kb());

    // 1 and 2: the first and the second instantiation.
    let (first, t) = in_phase("first instantiate", start_timed(&fmu, &opts, lay.stop, "first"))?;
    put_start_times(report, "first", &t);
    report.num("peak_rss_kb_after_first", peak_rss_kb());
    report.num("rss_kb_first_alive", rss_kb());
    first.free();
    let (second, t) = in_phase("second instantiate", start_timed(&fmu, &opts, lay.stop, "second"))?;
    put_start_times(report, "second", &t);
    let second_cost = t.iter().map(|x| x.0).sum::<f64>();
    second.free();
    eprintln!("fmu-bench chain: {n} states; instantiated twice");

    // 3: memory per instance.
    let count = ((opts.memory_budget / second_cost.max(1e-9)) as usize).clamp(2, 100);
    let (rss0, heap0) = (rss_kb(), heap_in_use_bytes());
    let mut alive = Vec::with_capacity(count);
    for i in 0..count {
        alive.push(in_phase("memory", start_timed(&fmu, &opts, lay.stop, &format!("m{i}")).map(|x| x.0))?);
    }
    let (rss1, heap1) = (rss_kb(), heap_in_use_bytes());
    for inst in alive {
        inst.free();
    }
    report.num("memory_instances", count as f64);
    report.num("rss_kb_per_instance", (rss1 - rss0) / count as f64);
    report.num("heap_kb_per_instance", (heap1 - heap0) / 1024.0 / count as f64);
    eprintln!("fmu-bench chain: memory of {count} instances measured");

    // 4: the Jacobian, one directional derivative per state.
    let (mut inst, _) = in_phase("jacobian", start_timed(&fmu, &opts, lay.stop, "jacobian"))?;
    let mut column = vec![0.0; n];
    let mut triplets = String::new();
    let (wall, cpu) = (Instant::now(), thread_cpu_seconds());
    let mut done = 0;
    for j in 0..n {
        let status = inst.get_directional_derivative(&lay.derivatives, &lay.states[j..j + 1], &[1.0], &mut column);
        if status != Status::OK {
            return Err(("jacobian", format!("fmi2GetDirectionalDerivative column {j} returned {status:?}: {}", messages(&inst))));
        }
        done += 1;
        if opts.jacobian_out.is_some() {
            for (i, v) in column.iter().enumerate().filter(|(_, v)| **v != 0.0) {
                triplets.push_str(&format!("{i} {j} {v:.17e}\n"));
            }
        }
        if thread_cpu_seconds() - cpu > opts.jacobian_budget {
            break;
        }
    }
    let (jac_cpu, jac_wall) = (thread_cpu_seconds() - cpu, wall.elapsed().as_secs_f64());
    inst.free();
    report.num("jacobian_columns_done", done as f64);
    report.num("jacobian_cpu_s", jac_cpu);
    report.num("jacobian_wall_s", jac_wall);
    report.num("jacobian_cpu_s_per_column", jac_cpu / done as f64);
    report.num("jacobian_cpu_s_full", jac_cpu / done as f64 * n as f64);
    if let Some(file) = &opts.jacobian_out {
        in_phase("jacobian", std::fs::write(file, &triplets).map_err(|e| format!("{file}: {e}")))?;
    }
    eprintln!("fmu-bench chain: Jacobian, {done} of {n} columns in {jac_cpu:.3} s");

    // 5: the doStep cost.
    let steps = (lay.stop / lay.step).round() as usize;
    let mut row = vec![0.0; lay.outputs.len()];
    let mut runs = Vec::new();
    let mut spent = 0.0;
    let mut cut: Option<(usize, f64)> = None;
    // (doSteps done, CPU s) of the first run, read at doSteps 1, 2, 3, ... while a doStep costs
    // more than 1 ms, then at doubling strides up to 64: how the cost spreads over the run, and
    // the budget's check, at a negligible cost to the loop.
    let mut checkpoints = Vec::new();
    for repeat in 0..opts.repeats.max(1) {
        let (mut inst, _) = in_phase("doStep", start_timed(&fmu, &opts, lay.stop, "steps"))?;
        let cpu = thread_cpu_seconds();
        let (mut next_check, mut stride, mut last) = (1, 1, 0.0);
        for i in 0..steps {
            let status = inst.do_step(i as f64 * lay.step, lay.step, true);
            if status != Status::OK {
                return Err(("doStep", format!("fmi2DoStep at t = {} s returned {status:?}: {}", i as f64 * lay.step, messages(&inst))));
            }
            inst.get_real(&lay.outputs, &mut row);
            if repeat == 0 && i + 1 == next_check {
                let now = thread_cpu_seconds() - cpu;
                checkpoints.push((i + 1) as f64);
                checkpoints.push(now);
                if now - last < 1e-3 * stride as f64 && stride < 64 {
                    stride *= 2;
                }
                last = now;
                next_check += stride;
                if now > opts.step_budget && i + 1 < steps {
                    cut = Some((i + 1, now));
                    break;
                }
            }
        }
        let used = thread_cpu_seconds() - cpu;
        inst.free();
        if let Some((done, t)) = cut {
            report.num("steps_done", done as f64);
            report.num("step_cpu_s_done", t);
            runs.push(t / done as f64 * steps as f64);
            break;
        }
        runs.push(used);
        spent += used;
        eprintln!("fmu-bench chain: doStep run {} of {}: {used:.4} s", repeat + 1, opts.repeats);
        if spent + used > opts.step_budget {
            break;
        }
    }
    report.num("steps", steps as f64);
    report.num("step_size", lay.step);
    report.num("step_runs", runs.len() as f64);
    report.str("step_extrapolated", if cut.is_some() { "yes" } else { "no" });
    report.nums("step_cpu_s_all", &runs);
    report.nums("step_checkpoints_steps_cpu_s", &checkpoints);
    let med = median(runs);
    report.num("step_cpu_s_median", med);
    report.num("us_per_step", med / steps as f64 * 1e6);
    eprintln!("fmu-bench chain: {:.3} us per doStep{}", med / steps as f64 * 1e6, if cut.is_some() { " (extrapolated)" } else { "" });

    // 6: the recorded run.
    if let (Some((vr_file, bin)), None) = (&opts.record, cut) {
        let text = in_phase("record", std::fs::read_to_string(vr_file).map_err(|e| format!("{vr_file}: {e}")))?;
        let vrs: Vec<ValueReference> =
            in_phase("record", text.split_whitespace().map(|s| s.parse().map_err(|e| format!("{vr_file}: {s}: {e}"))).collect())?;
        let (mut inst, _) = in_phase("record", start_timed(&fmu, &opts, lay.stop, "record"))?;
        let mut values = vec![0.0; vrs.len()];
        let mut bytes = Vec::with_capacity(steps * vrs.len() * 8);
        for i in 0..steps {
            let status = inst.do_step(i as f64 * lay.step, lay.step, true);
            if status != Status::OK {
                return Err(("record", format!("fmi2DoStep at t = {} s returned {status:?}", i as f64 * lay.step)));
            }
            in_phase("record", check(inst.get_real(&vrs, &mut values), "fmi2GetReal"))?;
            for v in &values {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        inst.free();
        in_phase("record", std::fs::write(bin, bytes).map_err(|e| format!("{bin}: {e}")))?;
        report.str("recorded", bin);
    }
    Ok(())
}

/// `chain-describe --lib LIB --out JSON`: see the module's documentation.
pub fn describe(args: &Args) -> Result<(), String> {
    let lib_path = args.path("--lib")?;
    let out = args.path("--out")?;
    let mut json = Json::object();
    let began = (Instant::now(), process_cpu_seconds());
    let (lib, wall, cpu) = timed(|| unsafe { libloading::Library::new(&lib_path) });
    let lib = lib.map_err(|e| format!("{}: {e}", lib_path.display()))?;
    json = json.num("load_wall_s", wall).num("load_cpu_s", cpu);
    let text = |lib: &libloading::Library, symbol: &str| -> Result<Option<String>, String> {
        // SAFETY: export_fmu! defines these symbols as extern "C" fn() -> *const c_char.
        let f = unsafe { lib.get::<unsafe extern "C" fn() -> *const c_char>(symbol.as_bytes()) }.map_err(|e| format!("{symbol}: {e}"))?;
        let p = unsafe { f() };
        Ok((!p.is_null()).then(|| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()))
    };
    let indexed = |lib: &libloading::Library, symbol: &str, n: usize| -> Result<Option<String>, String> {
        // SAFETY: as above, with one usize argument.
        let f = unsafe { lib.get::<unsafe extern "C" fn(usize) -> *const c_char>(symbol.as_bytes()) }.map_err(|e| format!("{symbol}: {e}"))?;
        let p = unsafe { f(n) };
        Ok((!p.is_null()).then(|| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()))
    };
    let mut calls: Vec<(String, f64, f64, usize)> = Vec::new();
    for symbol in ["fmu_runtime_model_problems", "fmu_runtime_model_identifier", "fmu_runtime_effects_html"] {
        let (r, w, c) = timed(|| text(&lib, symbol));
        let len = r?.map_or(0, |s| s.len());
        calls.push((symbol.to_string(), w, c, len));
    }
    let (standards, w, c) = timed(|| text(&lib, "fmu_runtime_standards"));
    let standards = standards?.unwrap_or_default();
    calls.push(("fmu_runtime_standards".into(), w, c, standards.len()));
    for n in 0..standards.lines().count() {
        for symbol in ["fmu_runtime_model_description_of", "fmu_runtime_documentation_of"] {
            let (r, w, c) = timed(|| indexed(&lib, symbol, n));
            let len = r?.map_or(0, |s| s.len());
            calls.push((format!("{symbol}({n})"), w, c, len));
        }
    }
    let (r, w, c) = timed(|| text(&lib, "fmu_runtime_effects_text"));
    calls.push(("fmu_runtime_effects_text".into(), w, c, r?.map_or(0, |s| s.len())));
    let total_wall = began.0.elapsed().as_secs_f64();
    let total_cpu = process_cpu_seconds() - began.1;
    let rendered: Vec<String> = calls
        .iter()
        .map(|(s, w, c, len)| Json::object().str("call", s).num("wall_s", *w).num("cpu_s", *c).num("bytes", *len as f64).render())
        .collect();
    json = json.num("total_wall_s", total_wall).num("total_cpu_s", total_cpu).num("peak_rss_kb", peak_rss_kb()).raw_list("calls", rendered);
    drop(lib);
    std::fs::write(&out, json.render()).map_err(|e| format!("{}: {e}", out.display()))?;
    eprintln!("fmu-bench chain-describe: {total_wall:.3} s wall");
    Ok(())
}
