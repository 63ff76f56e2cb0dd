//! `fmu-bench`: the native side of the benchmark (issue 11; `bench/run.sh` runs it, BENCHMARKS.md
//! explains the figures). Subcommands:
//!
//! ```text
//! fmu-bench package-floors --empty-step LIB --null-step LIB --out DIR
//!     zips the two floor libraries into DIR/EmptyStep.fmu and DIR/NullStep.fmu
//! fmu-bench run --dist DIR --floors DIR [--pythonfmu FMU] [--repeats N] --out DIR
//!     times every contender from this native host and writes DIR/rust.json and, for each
//!     MotorFan-like run, DIR/traj_<label>.csv (t, motor_speed, shaft_torque on the 1 ms grid)
//! fmu-bench memory --fmu FMU
//!     memory per instance of one FMU (`run` starts it in a child process for each FMU)
//! fmu-bench chain --fmu FMU --out JSON [--real NAME=VALUE]... [--tolerance RTOL] [...]
//! fmu-bench chain-describe --lib LIB --out JSON
//!     the size benchmark of issue 25 (`bench/chain.py` runs them; see src/chain.rs)
//! ```
//!
//! Timing: each repeat instantiates a fresh instance, initializes it, then times the stepping
//! loop alone (`fmi2DoStep` followed by `fmi2GetReal` of the recorded outputs, into preallocated
//! buffers) in CPU time of the thread and in wall time; the figure is the median over the
//! repeats, which run in rounds over all contenders. The communication points are `i * h`, never
//! a running sum.
//!
//! The pythonfmu FMU needs libpython preloaded in a native host (`LD_PRELOAD`, see
//! /work/shared/TOOLS.md) and the venv's site-packages on `PYTHONPATH`; `bench/run.sh` sets both.

mod chain;
mod floors;
mod json;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Instant;

use fmi_host::{Fmu, Instance, Status};
use json::Json;

/// Communication step and stop time of the MotorFan runs (the issue's 30 s at 1 ms).
const H: f64 = 1e-3;
const STOP: f64 = 30.0;

/// Relative tolerances our MotorFan is run at (`None` = the FMU's default, 1e-8; 1e-7 was the
/// default before the solver stepped past communication points).
const TOLERANCES: [Option<f64>; 3] = [None, Some(1e-7), Some(1e-9)];

/// RK4 substeps per doStep the pythonfmu FMU is run with.
const PY_SUBSTEPS: [i32; 4] = [1, 2, 4, 8];

/// Instances made at once for the memory figure.
const MEMORY_INSTANCES: usize = 1000;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("package-floors") => floors::package(&Args(args[1..].to_vec())),
        Some("run") => run(&Args(args[1..].to_vec())),
        Some("memory") => memory(&Args(args[1..].to_vec())),
        Some("chain") => chain::chain(&Args(args[1..].to_vec())),
        Some("chain-describe") => chain::describe(&Args(args[1..].to_vec())),
        _ => Err("usage: fmu-bench package-floors --empty-step LIB --null-step LIB --out DIR\n       fmu-bench run --dist DIR --floors DIR [--pythonfmu FMU] [--repeats N] --out DIR\n       fmu-bench memory --fmu FMU\n       fmu-bench chain --fmu FMU --out JSON [--real NAME=VALUE]... [--tolerance RTOL] [--repeats N] [--step-budget S] [--jacobian-budget S] [--memory-budget S] [--jacobian-out FILE] [--record VRFILE --record-out BIN]\n       fmu-bench chain-describe --lib LIB --out JSON".into()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("fmu-bench: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `--name value` pairs.
pub struct Args(Vec<String>);

impl Args {
    pub fn get(&self, name: &str) -> Option<&str> {
        self.0.iter().position(|a| a == name).and_then(|i| self.0.get(i + 1)).map(String::as_str)
    }

    pub fn path(&self, name: &str) -> Result<PathBuf, String> {
        self.get(name).map(PathBuf::from).ok_or_else(|| format!("missing {name}"))
    }
}

fn check(status: Status, what: &str) -> Result<(), String> {
    if status == Status::OK {
        Ok(())
    } else {
        Err(format!("{what} returned {status:?}"))
    }
}

fn load(path: &Path) -> Result<Arc<Fmu>, String> {
    Fmu::load(path).map_err(|e| format!("{}: {e}", path.display()))
}

/// How one run is set up: parameters to set before initialization, the tolerance, the grid.
#[derive(Clone)]
struct Setup {
    integers: Vec<(String, i32)>,
    tolerance: Option<f64>,
    stop: f64,
    step: f64,
    /// Outputs read after each step (recorded on the grid).
    outputs: Vec<String>,
}

/// A fresh, initialized instance.
fn start(fmu: &Arc<Fmu>, setup: &Setup, name: &str) -> Result<Instance, String> {
    let mut inst = fmu.instantiate(name, false, false).map_err(|e| e.to_string())?;
    for (var, value) in &setup.integers {
        let vr = fmu.vr(var).map_err(|e| e.to_string())?;
        check(inst.set_integer(&[vr], &[*value]), &format!("fmi2SetInteger {var}"))?;
    }
    check(inst.setup_experiment(setup.tolerance, 0.0, Some(setup.stop)), "fmi2SetupExperiment")?;
    check(inst.enter_initialization_mode(), "fmi2EnterInitializationMode")?;
    check(inst.exit_initialization_mode(), "fmi2ExitInitializationMode")?;
    Ok(inst)
}

#[repr(C)]
struct Timespec {
    sec: i64,
    nsec: i64,
}

extern "C" {
    fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
}

/// CPU time consumed by the calling thread, s (CLOCK_THREAD_CPUTIME_ID): unlike the wall
/// clock, it does not count the time other processes held the core, which on a shared
/// machine is most of the noise. Everything a run does (the FMU's code, the embedded Python
/// interpreter of a pythonfmu FMU) runs on this thread.
fn thread_cpu_seconds() -> f64 {
    const CLOCK_THREAD_CPUTIME_ID: i32 = 3;
    let mut ts = Timespec { sec: 0, nsec: 0 };
    // SAFETY: a valid clock id and a pointer to a live timespec.
    unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.sec as f64 + ts.nsec as f64 * 1e-9
}

/// One run's times.
#[derive(Clone, Copy)]
struct Times {
    cpu: f64,
    wall: f64,
}

/// One timed run: CPU and wall seconds spent in the stepping loop, and the recorded outputs
/// (row-major, one row per communication point after the first step).
fn timed_run(fmu: &Arc<Fmu>, setup: &Setup) -> Result<(Times, Vec<f64>), String> {
    let vrs = fmu.vrs(&setup.outputs.iter().map(String::as_str).collect::<Vec<_>>()).map_err(|e| e.to_string())?;
    let n = (setup.stop / setup.step).round() as usize;
    let mut inst = start(fmu, setup, "bench")?;
    let mut row = vec![0.0; vrs.len()];
    let mut record = Vec::with_capacity(n * vrs.len());
    let (began, cpu_began) = (Instant::now(), thread_cpu_seconds());
    for i in 0..n {
        let status = inst.do_step(i as f64 * setup.step, setup.step, true);
        if status != Status::OK {
            return Err(format!("fmi2DoStep at t = {} s returned {status:?}: {:?}", i as f64 * setup.step, inst.log().records()));
        }
        inst.get_real(&vrs, &mut row);
        record.extend_from_slice(&row);
    }
    let times = Times { cpu: thread_cpu_seconds() - cpu_began, wall: began.elapsed().as_secs_f64() };
    inst.free();
    Ok((times, record))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

/// One contender of the native host: what to run and how to label it.
struct Job {
    label: String,
    group: &'static str,
    fmu: Arc<Fmu>,
    setup: Setup,
    /// Write the last run's outputs to traj_<label>.csv.
    trajectory: bool,
    extra: Vec<(&'static str, f64)>,
}

/// Runs every job `repeats` times in rounds (each round runs every job once, so that a burst
/// of load from other processes spreads over all of them); the JSON record of each.
fn measure_all(jobs: &[Job], repeats: usize, out: &Path) -> Result<Vec<Json>, String> {
    let mut times: Vec<Vec<Times>> = vec![Vec::new(); jobs.len()];
    for round in 0..repeats {
        for (job, t) in jobs.iter().zip(times.iter_mut()) {
            let (run_times, record) = timed_run(&job.fmu, &job.setup)?;
            t.push(run_times);
            if job.trajectory && round + 1 == repeats {
                write_trajectory(out, &job.label, &job.setup, &record)?;
            }
        }
        eprintln!("round {} of {repeats} done", round + 1);
    }
    let mut records = Vec::new();
    for (job, t) in jobs.iter().zip(times) {
        let steps = (job.setup.stop / job.setup.step).round();
        let cpu: Vec<f64> = t.iter().map(|x| x.cpu).collect();
        let wall: Vec<f64> = t.iter().map(|x| x.wall).collect();
        let (cpu_med, wall_med) = (median(cpu.clone()), median(wall.clone()));
        let cpu_min = cpu.iter().copied().fold(f64::INFINITY, f64::min);
        eprintln!(
            "{:<36} CPU {:>9.4} s (min {:.4})  {:>9.3} us/doStep   wall {:>9.4} s",
            job.label,
            cpu_med,
            cpu_min,
            cpu_med / steps * 1e6,
            wall_med
        );
        let mut json = Json::object()
            .str("label", &job.label)
            .str("group", job.group)
            .num("cpu_seconds_median", cpu_med)
            .num("cpu_seconds_min", cpu_min)
            .num("wall_seconds_median", wall_med)
            .num("us_per_step", cpu_med / steps * 1e6)
            .num("steps", steps)
            .num("step_size", job.setup.step)
            .num("stop_time", job.setup.stop)
            .nums("cpu_seconds_all", &cpu)
            .nums("wall_seconds_all", &wall)
            .opt_num("tolerance", job.setup.tolerance);
        for (k, v) in &job.extra {
            json = json.num(k, *v);
        }
        records.push(json);
    }
    Ok(records)
}

fn write_trajectory(out: &Path, label: &str, setup: &Setup, record: &[f64]) -> Result<(), String> {
    let width = setup.outputs.len();
    let mut text = format!("t,{}\n", setup.outputs.join(","));
    for (i, row) in record.chunks(width).enumerate() {
        let cells: Vec<String> = row.iter().map(|v| format!("{v:.17e}")).collect();
        text.push_str(&format!("{:.17e},{}\n", (i + 1) as f64 * setup.step, cells.join(",")));
    }
    let path = out.join(format!("traj_{label}.csv"));
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Resident set size of this process, kB (VmRSS of /proc/self/status).
fn rss_kb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap_or(f64::NAN)
}

/// glibc's `struct mallinfo2` (malloc.h): every field a size_t.
#[repr(C)]
#[derive(Default)]
struct MallInfo2 {
    arena: usize,
    ordblks: usize,
    smblks: usize,
    hblks: usize,
    hblkhd: usize,
    usmblks: usize,
    fsmblks: usize,
    uordblks: usize,
    fordblks: usize,
    keepcost: usize,
}

extern "C" {
    fn mallinfo2() -> MallInfo2;
}

/// Bytes the process holds from malloc right now (in use, from the main arena and mmap):
/// every library in the process, the FMUs' included, allocates through the same malloc.
fn heap_in_use_bytes() -> f64 {
    // SAFETY: a glibc function without arguments returning a plain struct.
    let m = unsafe { mallinfo2() };
    (m.uordblks + m.hblkhd) as f64
}

/// `memory --fmu PATH [--integer NAME=VALUE]`: in a process of its own (so that no memory
/// freed by an earlier measurement is reused), the growth of RSS (kB) and of the malloc heap
/// in use (bytes) while `MEMORY_INSTANCES` instantiated and initialized instances are alive,
/// each scaled to 1000 instances, printed as one JSON object.
fn memory(args: &Args) -> Result<(), String> {
    let fmu = load(&args.path("--fmu")?)?;
    let setup = Setup { integers: vec![], tolerance: None, stop: 1.0, step: 1e-3, outputs: vec![] };
    // Warm up: the first instances pay for lazily made tables and the allocator's arenas.
    for _ in 0..10 {
        start(&fmu, &setup, "warm")?.free();
    }
    let (rss0, heap0) = (rss_kb(), heap_in_use_bytes());
    let mut alive = Vec::with_capacity(MEMORY_INSTANCES);
    for i in 0..MEMORY_INSTANCES {
        alive.push(start(&fmu, &setup, &format!("m{i}"))?);
    }
    let (rss1, heap1) = (rss_kb(), heap_in_use_bytes());
    for inst in alive {
        inst.free();
    }
    let scale = 1000.0 / MEMORY_INSTANCES as f64;
    let json = Json::object()
        .str("fmu", &fmu.model_description().model_name)
        .num("rss_kb_per_1000", (rss1 - rss0) * scale)
        .num("heap_kb_per_1000", (heap1 - heap0) / 1024.0 * scale)
        .num("library_bytes", library_size(&fmu));
    println!("{}", json.render());
    Ok(())
}

/// Runs `memory` for one FMU in a child process of this program; its JSON line.
fn memory_in_child(fmu: &Path) -> Result<String, String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let out = std::process::Command::new(exe).arg("memory").arg("--fmu").arg(fmu).output().map_err(|e| e.to_string())?;
    if !out.status.success() {
        return Err(format!("memory --fmu {}: {}", fmu.display(), String::from_utf8_lossy(&out.stderr)));
    }
    let line = String::from_utf8_lossy(&out.stdout).trim().to_string();
    eprintln!("memory: {line}");
    Ok(line)
}

fn motor_fan_setup(level: i32, tolerance: Option<f64>) -> Setup {
    Setup {
        integers: vec![("level".into(), level), ("start_mode".into(), 1)],
        tolerance,
        stop: STOP,
        step: H,
        outputs: vec!["motor_speed".into(), "shaft_torque".into()],
    }
}

/// An FMU at its DefaultExperiment (stop time and step size), recording its first output.
fn default_setup(fmu: &Fmu) -> Setup {
    let md = fmu.model_description();
    let de = md.default_experiment.unwrap_or_default();
    let first_output = md
        .model_variables
        .iter()
        .find(|v| v.causality == fmi_host::Causality::Output)
        .map(|v| v.name.clone());
    Setup {
        integers: vec![],
        tolerance: None,
        stop: de.stop_time.unwrap_or(1.0),
        step: de.step_size.unwrap_or(1e-3),
        outputs: first_output.into_iter().collect(),
    }
}

fn library_size(fmu: &Fmu) -> f64 {
    std::fs::metadata(fmu.library_path()).map(|m| m.len() as f64).unwrap_or(f64::NAN)
}

fn run(args: &Args) -> Result<(), String> {
    let dist = args.path("--dist")?;
    let floors = args.path("--floors")?;
    let out = args.path("--out")?;
    let repeats: usize = args.get("--repeats").unwrap_or("5").parse().map_err(|e| format!("--repeats: {e}"))?;
    std::fs::create_dir_all(&out).map_err(|e| e.to_string())?;
    let mut jobs = Vec::new();
    let mut memory = Vec::new();
    let job = |label: String, group, fmu: &Arc<Fmu>, setup: Setup, trajectory, extra| Job { label, group, fmu: fmu.clone(), setup, trajectory, extra };

    // 1. Our MotorFan, level c, direct start, 30 s at 1 ms, at several tolerances.
    let motor_fan = load(&dist.join("MotorFan.fmu"))?;
    for tol in TOLERANCES {
        let label = match tol {
            None => "MotorFan_c_default".to_string(),
            Some(t) => format!("MotorFan_c_rtol{t:e}"),
        };
        jobs.push(job(label, "motor_fan_c", &motor_fan, motor_fan_setup(3, tol), true, vec![]));
    }

    // 2. The floors: our runtime with no state, and no runtime at all.
    for name in ["EmptyStep", "NullStep"] {
        let path = floors.join(format!("{name}.fmu"));
        let setup = Setup { integers: vec![], tolerance: None, stop: STOP, step: H, outputs: vec!["y".into()] };
        jobs.push(job(name.into(), "floor", &load(&path)?, setup, false, vec![]));
        memory.push(memory_in_child(&path)?);
    }

    // 3. The pythonfmu FMU, from this native host.
    if let Some(py) = args.get("--pythonfmu") {
        let fmu = load(Path::new(py))?;
        for substeps in PY_SUBSTEPS {
            let setup = Setup {
                integers: vec![("substeps".into(), substeps)],
                tolerance: None,
                stop: STOP,
                step: H,
                outputs: vec!["motor_speed".into(), "shaft_torque".into()],
            };
            jobs.push(job(format!("MotorFanPy_rk4x{substeps}_rust_host"), "pythonfmu", &fmu, setup, true, vec![("substeps", substeps as f64)]));
        }
        memory.push(memory_in_child(Path::new(py))?);
    }

    // 4. The other models at their defaults (the stiff ones included), and level d.
    jobs.push(job("MotorFan_d_default".into(), "defaults", &motor_fan, motor_fan_setup(4, None), false, vec![]));
    // (The chapter FMUs added later are skipped in an older dist, so that a dist from before them
    // can still be measured against.)
    let later = ["ElevatorDrive", "EhaFlightControl", "PowerSteering", "MemsAccelerometer", "BoosterNozzle", "CommonRailInjection"];
    for name in ["RlcCircuit", "TractionMotorThermal", "TorqueSensor", "ShaftLine"].into_iter().chain(later) {
        let path = dist.join(format!("{name}.fmu"));
        if !path.is_file() && later.contains(&name) {
            continue;
        }
        let fmu = load(&path)?;
        let setup = default_setup(&fmu);
        jobs.push(job(name.into(), "defaults", &fmu, setup, false, vec![]));
    }
    let runs = measure_all(&jobs, repeats, &out)?;

    // 5. Memory per instance and library size of every FMU in dist/.
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dist)
        .map_err(|e| format!("{}: {e}", dist.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "fmu"))
        .collect();
    paths.sort();
    for path in paths {
        memory.push(memory_in_child(&path)?);
    }

    let doc = Json::object().num("repeats", repeats as f64).list("runs", runs).raw_list("memory", memory);
    let path = out.join("rust.json");
    std::fs::write(&path, doc.render()).map_err(|e| format!("{}: {e}", path.display()))?;
    eprintln!("wrote {}", path.display());
    Ok(())
}
