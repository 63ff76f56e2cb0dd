//! `alloc-count`: heap allocations made inside `fmi2DoStep` in steady stepping (issue 11's
//! "no allocation inside doStep", measured rather than asserted).
//!
//! An FMU's Rust code allocates through its own shared library's allocator, which a host-side
//! `#[global_allocator]` never sees. So this program links the MotorFan model as an rlib and
//! drives `fmu_runtime::instance::Instance<MotorFan>` directly (the same code the C functions
//! of the .so call, minus the pointer checks and `catch_unwind` of the C boundary), with a
//! counting global allocator around the system one. After a warm-up of 1000 steps it counts
//! the allocations (alloc, alloc_zeroed and realloc calls) and the bytes requested during the
//! next 10 000 doSteps (`--steps N`), and separately during an fmi2GetReal of the outputs after each step.
//!
//! ```sh
//! cargo run --release -p fmu-bench --bin alloc-count
//! ```
//!
//! Prints one JSON object per case on stdout, with the doSteps that handled a state event (the
//! reducer's power reversal at levels c and d: the solver is re-made with the new mode, which
//! allocates) counted apart from the others (steady stepping, which must not allocate).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::Relaxed};

use fmu_runtime::instance::Instance;
use fmu_runtime::log::Logger;
use motor_fan::MotorFan;

/// The system allocator, counting calls and bytes while `ON` is set.
struct Counting;

static ON: AtomicBool = AtomicBool::new(false);
static CALLS: AtomicU64 = AtomicU64::new(0);
static BYTES: AtomicU64 = AtomicU64::new(0);

fn count(size: usize) {
    if ON.load(Relaxed) {
        CALLS.fetch_add(1, Relaxed);
        BYTES.fetch_add(size as u64, Relaxed);
    }
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count(layout.size());
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count(layout.size());
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count(new_size);
        System.realloc(ptr, layout, new_size)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

const WARM_UP: usize = 1000;
const H: f64 = 1e-3;

/// (calls, bytes) counted while `f` runs.
fn counted(f: impl FnOnce()) -> (u64, u64) {
    CALLS.store(0, Relaxed);
    BYTES.store(0, Relaxed);
    ON.store(true, Relaxed);
    f();
    ON.store(false, Relaxed);
    (CALLS.load(Relaxed), BYTES.load(Relaxed))
}

fn case(level: i32, steps: usize) -> Result<String, String> {
    let e = |f: fmu_runtime::instance::Failure| f.message;
    let mut inst = Instance::<MotorFan>::new("alloc-count", Logger::silent());
    let vr = |name: &str| inst.table().variables.iter().position(|v| v.name == name).map(|i| i as u32).ok_or(format!("no variable {name}"));
    let (level_vr, speed_vr, torque_vr, events_vr) = (vr("level")?, vr("motor_speed")?, vr("shaft_torque")?, vr("state_events")?);
    inst.set::<i32>(&[level_vr], &[level]).map_err(e)?;
    inst.setup_experiment(None, 0.0, Some(30.0)).map_err(e)?;
    inst.enter_initialization_mode().map_err(e)?;
    inst.exit_initialization_mode().map_err(e)?;
    let outputs = [speed_vr, torque_vr];
    let mut values = [0.0; 2];
    for i in 0..WARM_UP {
        inst.do_step(i as f64 * H, H).map_err(e)?;
        inst.get::<f64>(&outputs, &mut values).map_err(e)?;
    }
    let (mut step_calls, mut step_bytes, mut get_calls, mut get_bytes) = (0, 0, 0, 0);
    // doSteps with a state event: how many, and their allocations.
    let (mut event_steps, mut event_calls) = (0u64, 0u64);
    let mut events = [0i32];
    let mut failure = None;
    for i in WARM_UP..WARM_UP + steps {
        inst.get::<i32>(&[events_vr], &mut events).map_err(e)?;
        let events_before = events[0];
        let (c, b) = counted(|| {
            if let Err(f) = inst.do_step(i as f64 * H, H) {
                failure = Some(f.message);
            }
        });
        (step_calls, step_bytes) = (step_calls + c, step_bytes + b);
        inst.get::<i32>(&[events_vr], &mut events).map_err(e)?;
        if events[0] != events_before {
            (event_steps, event_calls) = (event_steps + 1, event_calls + c);
        }
        let (c, b) = counted(|| {
            let _ = inst.get::<f64>(&outputs, &mut values);
        });
        (get_calls, get_bytes) = (get_calls + c, get_bytes + b);
    }
    if let Some(message) = failure {
        return Err(message);
    }
    let n = steps as f64;
    Ok(format!(
        "{{\"case\": \"MotorFan level {level}, 1 ms, default tolerance, t = {} .. {} s\", \"allocations_per_do_step\": {}, \"bytes_per_do_step\": {}, \"allocations_per_get_real\": {}, \"bytes_per_get_real\": {}, \"steps\": {steps}, \"steps_with_event\": {event_steps}, \"allocations_in_event_steps\": {event_calls}, \"allocations_in_other_steps\": {}}}",
        WARM_UP as f64 * H,
        (WARM_UP + steps) as f64 * H,
        step_calls as f64 / n,
        step_bytes as f64 / n,
        get_calls as f64 / n,
        get_bytes as f64 / n,
        step_calls - event_calls
    ))
}

/// `alloc-count [--level L] [--steps N]`: MotorFan levels 3 and 4 (or only L), N counted
/// steps after the warm-up (default 10 000; at most 29 000, the run ends at 30 s).
fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let value = |name: &str| args.iter().position(|a| a == name).and_then(|i| args.get(i + 1)).and_then(|v| v.parse::<usize>().ok());
    let levels: Vec<i32> = value("--level").map_or(vec![3, 4], |l| vec![l as i32]);
    let steps = value("--steps").unwrap_or(10_000).min(29_000);
    for level in levels {
        match case(level, steps) {
            Ok(line) => println!("{line}"),
            Err(message) => {
                eprintln!("alloc-count: level {level}: {message}");
                return std::process::ExitCode::FAILURE;
            }
        }
    }
    std::process::ExitCode::SUCCESS
}
