//! Time of one solve with the implicit method's Newton matrix I - h gamma J of the stiff
//! torsional chain (J = 1e-4 kg m2, K = 1e5 N m/rad, D = 10 N m s/rad, states ordered as the
//! model declares them: the speeds, then the twists), factorized each way the runtime can
//! (`stepper::jacobian`): a microbenchmark for choosing between them.
//!
//! `cargo run --release -p fmu-runtime --example newton_solve -- N [h_gamma]` (N inertias).

use fmu_runtime::real::{Dual, Real};
use fmu_runtime::stepper::jacobian::{evaluate, probe, Factors, Forced, Structure, Work};

/// The chain's derivatives (speeds, then twists), no drive torque, a viscous load of 1 N m s/rad.
fn chain<R: Real>(n: usize, x: &[R], dx: &mut [R]) {
    let (j, k, d) = (1e-4, 1e5, 10.0);
    let mut incoming = R::from(0.0);
    for i in 0..n {
        let w = x[i];
        let outgoing = if i + 1 < n {
            let rate = w - x[i + 1];
            dx[n + i] = rate;
            x[n + i] * k + rate * d
        } else {
            w * 1.0
        };
        dx[i] = (incoming - outgoing) / j;
        incoming = outgoing;
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map_or(1000, |a| a.parse().expect("N"));
    let hg: f64 = args.get(2).map_or(1.5e-4, |a| a.parse().expect("h gamma"));
    let m = 2 * n - 1;
    let rhs = |x: &[f64], _t: f64, dx: &mut [f64]| chain(n, x, dx);
    let dual = |x: &[Dual], _t: f64, dx: &mut [Dual]| chain(n, x, dx);
    let x: Vec<f64> = (0..m).map(|i| 1.0 + (i as f64 * 0.37).sin()).collect();
    let columns = probe(&rhs, 0.0, &x, &vec![1.0; m]);
    let b: Vec<f64> = (0..m).map(|i| (i as f64 * 0.11).cos()).collect();
    let mut reference: Option<Vec<f64>> = None;
    for force in [None, Some(Forced::Sparse), Some(Forced::Band)] {
        let s = Structure::choose(m, columns.clone(), force).unwrap();
        let mut jac = vec![0.0; s.nnz()];
        evaluate(&s, &dual, 0.0, &x, &mut jac, &mut Work::default());
        let mut f = Factors::new(&s);
        let factor_start = std::time::Instant::now();
        let factorizations = 50;
        for _ in 0..factorizations {
            f.factor(&s, &jac, hg).unwrap();
        }
        let factor_us = factor_start.elapsed().as_secs_f64() * 1e6 / factorizations as f64;
        let mut z = b.clone();
        let solves = 20_000_000 / m;
        let start = std::time::Instant::now();
        for _ in 0..solves {
            z.copy_from_slice(&b);
            f.solve(&s, &mut z);
        }
        let solve_us = start.elapsed().as_secs_f64() * 1e6 / solves as f64;
        let difference = reference.as_ref().map_or(0.0, |r| r.iter().zip(&z).map(|(a, c)| (a - c).abs() / (1.0 + a.abs())).fold(0.0, f64::max));
        reference.get_or_insert(z);
        println!(
            "{m} states, {:?} -> {} {:?}: solve {solve_us:.2} us ({:.2} ns per state), factorization {factor_us:.1} us, largest difference {difference:.1e}",
            force,
            s.kind(),
            s.band(),
            solve_us * 1e3 / m as f64
        );
    }
}
