//! The cost of one steady fmi2DoStep through the C ABI: loads an FMU from dist/, optionally sets
//! an Integer parameter, initializes and times `steps` doSteps of `h` (median of `runs`).
//!
//! ```sh
//! cargo run --release -p build-fmus -- --only MotorFan
//! cargo run --release -p fmi-host --example step_cost -- MotorFan level=3 [steps] [runs] [h]
//! valgrind --tool=callgrind target/release/examples/step_cost MotorFan level=3 30000 1
//! ```
//! Not the benchmark harness (bench/): a quick check while working on the runtime.

use std::time::Instant;

use fmi_host::dist::dist_dir;
use fmi_host::{Fmu, Instance, InstantiateOptions, Status};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().map(String::as_str).unwrap_or("MotorFan");
    let mut integer: Option<(String, i32)> = None;
    let mut numbers = Vec::new();
    for a in &args[1.min(args.len())..] {
        match a.split_once('=') {
            Some((k, v)) => integer = Some((k.to_string(), v.parse().expect("an integer value"))),
            None => numbers.push(a.clone()),
        }
    }
    let steps: usize = numbers.first().and_then(|a| a.parse().ok()).unwrap_or(30_000);
    let runs: usize = numbers.get(1).and_then(|a| a.parse().ok()).unwrap_or(5);
    let h: f64 = numbers.get(2).and_then(|a| a.parse().ok()).unwrap_or(1e-3);
    let fmu = Fmu::load(dist_dir().join(format!("{name}.fmu"))).expect("the FMU in dist/ (build-fmus)");
    let mut per_step = Vec::new();
    for run in 0..runs {
        let mut inst = Instance::new(&fmu, InstantiateOptions::new(format!("run{run}"))).expect("instantiate");
        if let Some((k, v)) = &integer {
            let vr = fmu.vr(k).expect("the parameter");
            assert_eq!(inst.set_integer(&[vr], &[*v]), Status::OK);
        }
        assert_eq!(inst.setup_experiment(None, 0.0, None), Status::OK);
        assert_eq!(inst.enter_initialization_mode(), Status::OK);
        assert_eq!(inst.exit_initialization_mode(), Status::OK);
        let start = Instant::now();
        for k in 0..steps {
            assert_eq!(inst.do_step(k as f64 * h, h, true), Status::OK);
        }
        per_step.push(start.elapsed().as_secs_f64() / steps as f64 * 1e6);
        inst.free();
    }
    per_step.sort_by(f64::total_cmp);
    println!("{name} {integer:?}: {steps} steps of {h} s, median {:.2} us per doStep (runs: {per_step:.2?})", per_step[per_step.len() / 2]);
}
