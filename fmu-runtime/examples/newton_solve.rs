//! Time of one solve with the implicit method's Newton matrix I - h gamma J of the stiff
//! torsional chain (J = 1e-4 kg m2, K = 1e5 N m/rad, D = 10 N m s/rad, states ordered as the
//! model declares them: the speeds, then the twists), factorized each way the runtime can
//! (`stepper::jacobian`): a microbenchmark for choosing between them.
//!
//! `cargo run --release -p fmu-runtime --example newton_solve -- N [h_gamma]` (N inertias), or
//! `-- grid M [h_gamma]`: the same for a stiff M x M grid (x' = -1e5 L x, L the 5-point
//! Laplacian: a band of width about M after reverse Cuthill-McKee, far wider than the sparse
//! LU's fill per row), for the band/sparse switch (`jacobian::BAND_BELOW_FILL`).

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

/// x' = -1e5 L x on an M x M grid (row by row), L the 5-point Laplacian with zero outside.
fn grid<R: Real>(side: usize, x: &[R], dx: &mut [R]) {
    for i in 0..side {
        for j in 0..side {
            let k = i * side + j;
            let mut s = x[k] * -4.0;
            if i > 0 {
                s += x[k - side];
            }
            if i + 1 < side {
                s += x[k + side];
            }
            if j > 0 {
                s += x[k - 1];
            }
            if j + 1 < side {
                s += x[k + 1];
            }
            dx[k] = s * 1e5;
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let is_grid = args.get(1).map(String::as_str) == Some("grid");
    let args: Vec<String> = if is_grid { args[1..].to_vec() } else { args };
    let n: usize = args.get(1).map_or(1000, |a| a.parse().expect("N"));
    let hg: f64 = args.get(2).map_or(1.5e-4, |a| a.parse().expect("h gamma"));
    let m = if is_grid { n * n } else { 2 * n - 1 };
    let rhs = |x: &[f64], _t: f64, dx: &mut [f64]| if is_grid { grid(n, x, dx) } else { chain(n, x, dx) };
    let dual = |x: &[Dual], _t: f64, dx: &mut [Dual]| if is_grid { grid(n, x, dx) } else { chain(n, x, dx) };
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
            "{m} states, {:?} -> {} {:?} (band {} entries per state, sparse trial fill {:.1}): solve {solve_us:.2} us ({:.2} ns per state), factorization {factor_us:.1} us, largest difference {difference:.1e}",
            force,
            s.kind(),
            s.band(),
            s.band().map_or(0, |(kl, ku)| 2 * kl + ku + 1),
            s.sparse_fill().map_or(f64::NAN, |f| f as f64 / m as f64),
            solve_us * 1e3 / m as f64
        );
    }
}
