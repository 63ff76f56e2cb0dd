//! The README table of the Rust master: the motor-fan start-up coupled from the subsystem FMUs
//! (InductionMotor, DriveShaft, Fan) against the monolithic MotorFan level c, direct on line,
//! for each master set-up and communication step (10 ms, 1 ms, 0.1 ms).
//!
//! ```sh
//! cargo run --release -p fmi-host --example coupling_table                 # the README rows
//! cargo run --release -p fmi-host --example coupling_table -- --lossless   # + gear_efficiency = 1
//! ```
//!
//! Each cell: largest |fan speed - monolithic| over every output point, % of the rated speed
//! (the monolithic final fan speed) / |peak |shaft torque| - monolithic peak|, % of the
//! monolithic peak. Both runs are sampled on the same grid (the communication step).
//! `FMU_DIST_DIR` overrides the folder holding the FMUs.

#[path = "../tests/coupling/mod.rs"]
mod coupling;

use coupling::{compare, Fmus, Scenario, Setup};

const STEPS: [(f64, &str); 3] = [(1e-2, "10 ms"), (1e-3, "1 ms"), (1e-4, "0.1 ms")];

fn setups() -> Vec<Setup> {
    vec![
        Setup::jacobi(),
        Setup::gauss_seidel(),
        Setup::jacobi().held(),
        Setup::gauss_seidel().held(),
        Setup::jacobi().error_control(1e-3),
        Setup::gauss_seidel().error_control(1e-3),
    ]
}

/// A percentage with three significant digits (at least three decimals).
fn pct(x: f64) -> String {
    if x >= 0.01 || x == 0.0 {
        format!("{x:.3}")
    } else {
        format!("{x:.2e}")
    }
}

fn table(fmus: &Fmus, scenario: Scenario) {
    let monolithic: Vec<_> = STEPS.iter().map(|&(h, _)| fmus.monolithic(scenario, h)).collect();
    println!(
        "| master | {} |",
        STEPS.iter().map(|(_, n)| *n).collect::<Vec<_>>().join(" | ")
    );
    println!("|---|{}", "---|".repeat(STEPS.len()));
    for setup in setups() {
        let mut cells = Vec::new();
        for (&(h, _), reference) in STEPS.iter().zip(&monolithic) {
            let started = std::time::Instant::now();
            let coupled = fmus.coupled(scenario, &setup, h);
            let f = compare(&coupled, reference);
            eprintln!(
                "{} at {h} s: {:.2?}, {} accepted / {} rejected steps",
                setup.name,
                started.elapsed(),
                coupled.stats.accepted_steps,
                coupled.stats.rejected_steps
            );
            cells.push(format!("{} / {}", pct(f.max_fan_speed_error_pct), pct(f.peak_torque_error_pct)));
        }
        println!("| Rust master, {} | {} |", setup.name, cells.join(" | "));
    }
}

fn main() {
    let lossless = std::env::args().any(|a| a == "--lossless");
    let fmus = Fmus::load();
    println!("Direct-on-line start, 30 s, against MotorFan level c: max fan speed error (% of rated) / peak shaft torque error (%)");
    println!();
    table(&fmus, Scenario::DIRECT_ON_LINE);
    if lossless {
        println!();
        println!("The same with gear_efficiency = 1 in MotorFan and Fan (the pure coupling error):");
        println!();
        table(&fmus, Scenario { gear_efficiency: Some(1.0), ..Scenario::DIRECT_ON_LINE });
    }
}
