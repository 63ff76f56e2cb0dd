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
//!    then, on the same instance, the sparse Jacobian as a master that reads the ModelStructure
//!    assembles it: the columns of df/dx (the states) colored greedily, in state order, by the
//!    Derivatives' `dependencies` (no two states of a color reach the same derivative), one
//!    `fmi2GetDirectionalDerivative` per color (all derivatives as unknowns, all states as knowns,
//!    seed 1 on the states of the color), each declared entry (i, j) read from row i of the
//!    result of j's color into a fixed compressed-column pattern; the whole assembly timed (CPU
//!    time of the thread, median of up to `--repeats`, within `--jacobian-budget`; the coloring,
//!    done once, timed apart). A derivative without `dependencies` (it depends on every state)
//!    makes the coloring dense: one color per state, every row of each result read (the nonzeros
//!    kept), and said so. Its entries are checked against the per-column Jacobian's over the
//!    columns that one computed: entries that differ, and nonzeros outside the declared
//!    structure, are counted and the first printed;
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

use std::collections::{HashMap, HashSet};
use std::ffi::{c_char, CStr};
use std::sync::Arc;
use std::time::Instant;

use fmi_host::{Fmu, Instance, Status, ValueReference, VariableType};

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
    // Each column's nonzeros (row, value), for the check of the sparse Jacobian below: kept
    // aside, their CPU time (`aside`) left out of the figure and of the budget.
    let mut columns: Vec<Vec<(u32, f64)>> = Vec::new();
    let mut aside = 0.0;
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
        let began = thread_cpu_seconds();
        columns.push(column.iter().enumerate().filter(|(_, v)| **v != 0.0).map(|(i, v)| (i as u32, *v)).collect());
        aside += thread_cpu_seconds() - began;
        if thread_cpu_seconds() - cpu - aside > opts.jacobian_budget {
            break;
        }
    }
    let (jac_cpu, jac_wall) = (thread_cpu_seconds() - cpu - aside, wall.elapsed().as_secs_f64());
    report.num("jacobian_columns_done", done as f64);
    report.num("jacobian_cpu_s", jac_cpu);
    report.num("jacobian_wall_s", jac_wall);
    report.num("jacobian_cpu_s_per_column", jac_cpu / done as f64);
    report.num("jacobian_cpu_s_full", jac_cpu / done as f64 * n as f64);
    if let Some(file) = &opts.jacobian_out {
        in_phase("jacobian", std::fs::write(file, &triplets).map_err(|e| format!("{file}: {e}")))?;
    }
    eprintln!("fmu-bench chain: Jacobian, {done} of {n} columns in {jac_cpu:.3} s");

    // 4b: the sparse Jacobian by colored directional derivatives, on the same instance.
    let sparse = in_phase("sparse jacobian", sparse_jacobian(&fmu, &lay, &mut inst, &opts, &columns));
    inst.free();
    sparse?.put(report);

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

/// df/dx's sparsity as the ModelStructure declares it: for each state (column, in the order of
/// `Layout::states`), the derivatives (rows, in the order of `Layout::derivatives`) whose
/// `dependencies` list it, ascending.
struct Structure {
    columns: Vec<Vec<u32>>,
    /// Derivatives without `dependencies` (each depends on every state: dense coloring).
    undeclared: usize,
    /// Dependencies that are no state (inputs): not columns of df/dx.
    non_state: usize,
    /// Dependencies whose value reference a state shares with a variable of another type (FMI
    /// 2.0's value references are unique per type only; the reader turned the indices into value
    /// references): kept, which can only add a dependency.
    ambiguous: usize,
}

fn structure(fmu: &Fmu, lay: &Layout) -> Structure {
    let md = fmu.model_description();
    let position: HashMap<ValueReference, usize> = lay.states.iter().enumerate().map(|(j, vr)| (*vr, j)).collect();
    let other_types: HashSet<ValueReference> =
        md.model_variables.iter().filter(|v| v.variable_type != VariableType::Real).map(|v| v.value_reference).collect();
    let mut s = Structure { columns: vec![Vec::new(); lay.states.len()], undeclared: 0, non_state: 0, ambiguous: 0 };
    // `layout` takes the derivatives from this list in its order: row i is its i-th entry.
    for (i, unknown) in md.model_structure.continuous_state_derivatives.iter().enumerate() {
        let Some(dependencies) = &unknown.dependencies else {
            s.undeclared += 1;
            continue;
        };
        for d in dependencies {
            match position.get(d) {
                Some(&j) => {
                    s.ambiguous += other_types.contains(d) as usize;
                    s.columns[j].push(i as u32);
                }
                None => s.non_state += 1,
            }
        }
    }
    for rows in &mut s.columns {
        rows.sort_unstable();
        rows.dedup();
    }
    s
}

/// Greedy coloring of the columns in their order: a column takes the smallest color that no
/// column sharing a row with it has. The colors' columns, ascending, color by color.
fn color_columns(columns: &[Vec<u32>], rows: usize) -> Vec<Vec<usize>> {
    let mut row_columns: Vec<Vec<usize>> = vec![Vec::new(); rows];
    for (j, col) in columns.iter().enumerate() {
        for &i in col {
            row_columns[i as usize].push(j);
        }
    }
    let mut color = vec![usize::MAX; columns.len()];
    // taken[c] == j: color c is taken by a neighbour of column j.
    let mut taken = vec![usize::MAX; columns.len() + 1];
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for j in 0..columns.len() {
        for &i in &columns[j] {
            for &k in &row_columns[i as usize] {
                if color[k] != usize::MAX {
                    taken[color[k]] = j;
                }
            }
        }
        let c = (0..).find(|&c| taken[c] != j).expect("at most one color per column");
        color[j] = c;
        if c == groups.len() {
            groups.push(Vec::new());
        }
        groups[c].push(j);
    }
    groups
}

/// The sparse Jacobian's figures and check.
struct Sparse {
    structure: String,
    colors: usize,
    colors_done: usize,
    nonzeros: usize,
    runs: Vec<f64>,
    extrapolated: bool,
    coloring_s: f64,
    non_state: usize,
    ambiguous: usize,
    compared_columns: usize,
    compared_entries: usize,
    mismatches: usize,
    outside_structure: usize,
    max_abs_diff: f64,
}

impl Sparse {
    fn put(self, report: &mut Report) {
        report.str("sparse_jacobian_structure", &self.structure);
        report.num("sparse_jacobian_colors", self.colors as f64);
        report.num("sparse_jacobian_nonzeros", self.nonzeros as f64);
        report.nums("sparse_jacobian_s_all", &self.runs);
        report.num("sparse_jacobian_s", median(self.runs));
        report.str("sparse_jacobian_extrapolated", if self.extrapolated { "yes" } else { "no" });
        if self.extrapolated {
            report.num("sparse_jacobian_colors_done", self.colors_done as f64);
        }
        report.num("sparse_jacobian_coloring_s", self.coloring_s);
        report.num("sparse_jacobian_non_state_dependencies", self.non_state as f64);
        report.num("sparse_jacobian_ambiguous_dependencies", self.ambiguous as f64);
        report.num("sparse_jacobian_compared_columns", self.compared_columns as f64);
        report.num("sparse_jacobian_compared_entries", self.compared_entries as f64);
        report.num("sparse_jacobian_mismatches", self.mismatches as f64);
        report.num("sparse_jacobian_outside_structure", self.outside_structure as f64);
        report.num("sparse_jacobian_max_abs_diff", self.max_abs_diff);
    }
}

/// Phase 4b (see the module's documentation); `per_column`: the nonzeros of the per-column
/// Jacobian's columns, the first `per_column.len()` states'.
fn sparse_jacobian(fmu: &Fmu, lay: &Layout, inst: &mut Instance, opts: &Options, per_column: &[Vec<(u32, f64)>]) -> Result<Sparse, String> {
    let n = lay.states.len();
    let rows = lay.derivatives.len();
    // The structure and its coloring: once, as a master does at setup.
    let began = thread_cpu_seconds();
    let s = structure(fmu, lay);
    let dense = s.undeclared > 0;
    let groups: Vec<Vec<usize>> = if dense { (0..n).map(|j| vec![j]).collect() } else { color_columns(&s.columns, rows) };
    // Compressed columns: column j's entries are at pointer[j]..pointer[j + 1] of row/value.
    let mut pointer = vec![0usize; n + 1];
    let mut row: Vec<u32> = Vec::new();
    if !dense {
        for (j, col) in s.columns.iter().enumerate() {
            row.extend_from_slice(col);
            pointer[j + 1] = row.len();
        }
    }
    let coloring_s = thread_cpu_seconds() - began;
    let structure = if dense {
        format!("dense: {} of {rows} derivatives list no dependencies (each depends on every state), one color per state", s.undeclared)
    } else {
        "sparse".to_string()
    };
    eprintln!(
        "fmu-bench chain: sparse Jacobian: {} colors for {n} states ({structure}; {:.3} ms to color){}",
        groups.len(),
        coloring_s * 1e3,
        if s.non_state + s.ambiguous > 0 { format!("; {} non-state and {} ambiguous dependencies", s.non_state, s.ambiguous) } else { String::new() }
    );
    if dense {
        // Every row of each result is an entry: the nonzeros are kept, column after column.
        row = Vec::with_capacity(per_column.iter().map(Vec::len).sum::<usize>().max(n));
    }
    let mut value = vec![0.0; row.len()];
    let mut seed = vec![0.0; n];
    let mut result = vec![0.0; rows];

    // The assembly, timed whole, repeated.
    let mut runs = Vec::new();
    let mut spent = 0.0;
    let mut colors_done = groups.len();
    for _ in 0..opts.repeats.max(1) {
        if dense {
            row.clear();
            value.clear();
        }
        let cpu = thread_cpu_seconds();
        for (c, group) in groups.iter().enumerate() {
            for &j in group {
                seed[j] = 1.0;
            }
            let status = inst.get_directional_derivative(&lay.derivatives, &lay.states, &seed, &mut result);
            if status != Status::OK {
                return Err(format!("fmi2GetDirectionalDerivative of color {c} ({} states) returned {status:?}: {}", group.len(), messages(inst)));
            }
            for &j in group {
                seed[j] = 0.0;
                if dense {
                    for (i, v) in result.iter().enumerate().filter(|(_, v)| **v != 0.0) {
                        row.push(i as u32);
                        value.push(*v);
                    }
                    pointer[j + 1] = row.len();
                } else {
                    for k in pointer[j]..pointer[j + 1] {
                        value[k] = result[row[k] as usize];
                    }
                }
            }
            if thread_cpu_seconds() - cpu > opts.jacobian_budget && c + 1 < groups.len() {
                colors_done = c + 1;
                break;
            }
        }
        let used = thread_cpu_seconds() - cpu;
        if colors_done < groups.len() {
            runs.push(used / colors_done as f64 * groups.len() as f64);
            break;
        }
        runs.push(used);
        spent += used;
        if spent + used > opts.jacobian_budget {
            break;
        }
    }
    let nonzeros = row.len();

    // The check against the per-column Jacobian, over the columns both computed.
    let mut done = vec![false; n];
    for group in &groups[..colors_done] {
        for &j in group {
            done[j] = true;
        }
    }
    let (mut compared_columns, mut compared_entries, mut mismatches, mut outside_structure, mut max_abs_diff) = (0, 0, 0, 0, 0.0f64);
    let mut shown = 0;
    for (j, expected) in per_column.iter().enumerate().filter(|(j, _)| done[*j]) {
        compared_columns += 1;
        let colored: HashMap<u32, f64> = (pointer[j]..pointer[j + 1]).map(|k| (row[k], value[k])).collect();
        let by_column: HashMap<u32, f64> = expected.iter().copied().collect();
        let mut at: Vec<u32> = colored.keys().chain(by_column.keys()).copied().collect::<HashSet<_>>().into_iter().collect();
        at.sort_unstable();
        for i in at {
            compared_entries += 1;
            let (a, b) = (colored.get(&i).copied(), by_column.get(&i).copied().unwrap_or(0.0));
            let diff = (a.unwrap_or(0.0) - b).abs();
            max_abs_diff = max_abs_diff.max(diff);
            let outside = a.is_none() && !dense;
            if outside {
                outside_structure += 1;
            }
            // Forward-mode derivatives: the same up to round-off.
            if outside || diff > 1e-12 * a.unwrap_or(0.0).abs().max(b.abs()) {
                mismatches += 1;
                if shown < 10 {
                    shown += 1;
                    eprintln!(
                        "fmu-bench chain: sparse Jacobian entry ({i}, {j}): colored {}, per column {b:e}",
                        a.map_or("not declared".to_string(), |a| format!("{a:e}"))
                    );
                }
            }
        }
    }
    let median_s = median(runs.clone());
    eprintln!(
        "fmu-bench chain: sparse Jacobian: {} colors, {nonzeros} entries in {:.3} ms{} (median of {}); against the per-column Jacobian \
         over {compared_columns} columns: {mismatches} of {compared_entries} entries differ ({outside_structure} outside the declared structure), \
         max |difference| {max_abs_diff:e}",
        groups.len(),
        median_s * 1e3,
        if colors_done < groups.len() { format!(" (extrapolated from {colors_done} colors)") } else { String::new() },
        runs.len()
    );
    Ok(Sparse {
        structure,
        colors: groups.len(),
        colors_done,
        nonzeros,
        runs,
        extrapolated: colors_done < groups.len(),
        coloring_s,
        non_state: s.non_state,
        ambiguous: s.ambiguous,
        compared_columns,
        compared_entries,
        mismatches,
        outside_structure,
        max_abs_diff,
    })
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
