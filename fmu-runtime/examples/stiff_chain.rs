//! The stiff torsional chain of the size benchmark (bench/torsional-chain with J = 1e-4 kg m2,
//! K = 1e5 N m/rad, D = 10 N m s/rad, a 100 N m torque step at 0.1 s), stepped in-process with
//! the implicit method in 1 ms doSteps over 1 s: a quick loop for profiling the method's linear
//! algebra without building an FMU. Prints the wall-clock time per doStep (median of the repeats).
//!
//! `cargo run --release -p fmu-runtime --example stiff_chain -- N [repeats]`, N one of 100, 1000,
//! 10000 (inertias; 2N - 1 states). It steps with subnormal numbers flushed to zero, as an FMU's
//! calls do (the chain's resting end otherwise decays through subnormal numbers, which dominate
//! the timing: 615 against 180 us per doStep at N = 1 000).

use fmu_runtime::instance::Instance;
use fmu_runtime::log::Logger;
use fmu_runtime::testing::chains::Chain;

/// The chain of bench/torsional-chain (its equations, written without the components crate).
type StiffChain<const N: usize> = Chain<N, true, true>;

/// Wall-clock seconds (std has no CPU clock; the machine's other load shows in the repeats).
fn cpu_seconds() -> f64 {
    std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap().as_secs_f64()
}

/// Seconds per doStep of one run, and the last speed of the first inertia.
fn run<const N: usize>() -> (f64, f64) {
    let _flushed = fmu_runtime::float_mode::FlushSubnormals::enter();
    let mut i = Instance::<StiffChain<N>>::new("{chain}", Logger::silent());
    for (name, value) in [("J", 1e-4), ("K", 1e5), ("D", 10.0)] {
        let r = i.table().by_name(name).unwrap().value_reference;
        i.set(&[r], &[value]).unwrap();
    }
    i.setup_experiment(None, 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    i.exit_initialization_mode().unwrap();
    let w1 = i.table().by_name("w_1").unwrap().value_reference;
    let steps = 1000;
    let start = cpu_seconds();
    for s in 0..steps {
        i.do_step(s as f64 * 1e-3, 1e-3).unwrap_or_else(|e| panic!("doStep {s}: {}", e.message));
    }
    let per_step = (cpu_seconds() - start) / steps as f64;
    let mut w = [0.0];
    i.get(&[w1], &mut w).unwrap();
    (per_step, w[0])
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map_or(1000, |a| a.parse().expect("N"));
    let repeats: usize = args.get(2).map_or(3, |a| a.parse().expect("repeats"));
    let mut times = Vec::new();
    let mut w = 0.0;
    for _ in 0..repeats {
        let (t, last) = match n {
            100 => run::<100>(),
            1000 => run::<1000>(),
            10000 => run::<10000>(),
            _ => panic!("N is one of 100, 1000, 10000"),
        };
        times.push(t);
        w = last;
    }
    times.sort_by(f64::total_cmp);
    println!("N = {n}: {:.1} us per doStep (median of {repeats}: {:?}), w_1(1 s) = {w:.17e}", times[repeats / 2] * 1e6, times.iter().map(|t| (t * 1e7).round() / 10.0).collect::<Vec<_>>());
}
