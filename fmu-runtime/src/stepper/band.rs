//! LU with partial pivoting of a band matrix, for the implicit method's Newton matrix when a
//! reordering of its states makes it narrow ([`jacobian`](super::jacobian) decides).
//!
//! The factorization is LAPACK's unblocked band LU (`dgbtf2`: Golub and Van Loan, Matrix
//! Computations, 4th ed., section 4.3.5, band Gaussian elimination with partial pivoting) over
//! the same column-major band storage: a matrix of lower bandwidth kl and upper bandwidth ku
//! keeps column j's rows j - kl - ku ..= j + kl contiguous, the kl rows above its band holding
//! the fill that row interchanges bring into U (which then has kl + ku superdiagonals). L stays
//! in product form, its multipliers below the diagonal of their column and the row interchanges
//! in `pivots`, as `dgbtrs` applies them.
//!
//! The solves are latency-bound (each unknown waits for the one before it), so after the
//! factorization the factors are copied into a layout made for them: L's multipliers column by
//! column, U row by row with its diagonal inverted and each row scaled by it
//! (x_i = y_i / u_ii - sum_d (u_i,i+d / u_ii) x_i+d), every row padded to the full width, so
//! that the loops have fixed trip counts and no branch but the interchanges; for small bandwidths
//! L's rows in flight stay in registers and U is solved four rows at a time ([`fast`]).
//!
//! Deterministic: the same matrix gives the same factors and solutions bit for bit (one thread,
//! a fixed order of operations). No allocation after [`BandLu::new`].

/// Whether a band of these bandwidths is solved by the fast loops (L's rows in registers, U in
/// blocks); wider bands are solved row by row through memory.
pub fn fast(kl: usize, ku: usize) -> bool {
    kl <= MAX_WINDOW_L && kl + ku <= MAX_BLOCKED
}

/// L's rows are kept in registers up to this lower bandwidth.
const MAX_WINDOW_L: usize = 4;

/// A band LU factorization and its work space.
pub struct BandLu {
    n: usize,
    kl: usize,
    ku: usize,
    /// The band storage (column-major, `ld()` entries per column), A(i, j) at
    /// `j * ld + kl + ku + i - j`: filled by the caller, factorized in place.
    ab: Vec<f64>,
    /// Row j was interchanged with row `pivots[j]` (>= j) at elimination step j.
    pivots: Vec<usize>,
    /// L's multipliers: column k's rows k + 1 ..= k + kl at `l[k * kl..(k + 1) * kl]`, zero
    /// beyond the matrix.
    l: Vec<f64>,
    /// U's superdiagonals of row i, each divided by u_ii: u_i,i+d / u_ii at
    /// `u[i * (kl + ku) + d - 1]`, d = 1 ..= kl + ku, zero beyond the matrix.
    u: Vec<f64>,
    /// 1 / u_ii.
    inverse_diagonal: Vec<f64>,
    /// U's solve in blocks of [`BLOCK`] rows from the last (the matrix padded with zero rows to
    /// a multiple of it), each block's unknowns written in terms of its right-hand sides and the
    /// `kl + ku` unknowns after it: block b's [`BLOCK`] x [`BLOCK`] matrix H, then its
    /// [`BLOCK`] x (kl + ku) matrix G, x_r = sum_q H_rq y_q - sum_d G_rd x_top+d.
    blocks: Vec<f64>,
    /// A right-hand side in band order, then L's solution; `kl + ku + 1` zeros past its end.
    work: Vec<f64>,
}

impl BandLu {
    /// The factorization of an n x n matrix of lower bandwidth `kl`, upper bandwidth `ku`.
    pub fn new(n: usize, kl: usize, ku: usize) -> BandLu {
        let ld = 2 * kl + ku + 1;
        BandLu {
            n,
            kl,
            ku,
            ab: vec![0.0; n * ld],
            pivots: vec![0; n],
            l: vec![0.0; n * kl],
            u: vec![0.0; n * (kl + ku)],
            inverse_diagonal: vec![0.0; n],
            blocks: vec![0.0; n.div_ceil(BLOCK) * BLOCK * (BLOCK + kl + ku)],
            work: vec![0.0; n.div_ceil(BLOCK) * BLOCK + kl + ku + 1],
        }
    }

    /// Entries per column of the band storage.
    pub fn ld(&self) -> usize {
        2 * self.kl + self.ku + 1
    }

    /// Where A(i, j) sits in [`storage`](Self::storage) (|i - j| within the bandwidths).
    pub fn position(kl: usize, ku: usize, i: usize, j: usize) -> usize {
        j * (2 * kl + ku + 1) + kl + ku + i - j
    }

    /// The band storage, to be filled with the matrix (zero outside its entries) before
    /// [`factor`](Self::factor).
    pub fn storage(&mut self) -> &mut [f64] {
        &mut self.ab
    }

    /// Factorizes the matrix in the storage in place (LAPACK `dgbtf2`). Err when a pivot is zero
    /// or not finite: the matrix is singular (or holds a NaN or an infinity).
    pub fn factor(&mut self) -> Result<(), String> {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        let (ld, kv) = (self.ld(), kl + ku);
        let ab = &mut self.ab;
        // The last column that the interchanges so far reach.
        let mut ju = 0;
        for j in 0..n {
            let km = kl.min(n - 1 - j);
            let diagonal = j * ld + kv;
            let mut p = 0;
            let mut best = ab[diagonal].abs();
            for i in 1..=km {
                let v = ab[diagonal + i].abs();
                if v > best {
                    best = v;
                    p = i;
                }
            }
            if !(best > 0.0 && best.is_finite()) {
                return Err(format!("the Newton matrix is singular (pivot {j} of {n})"));
            }
            self.pivots[j] = j + p;
            ju = ju.max((j + ku + p).min(n - 1));
            if p != 0 {
                for c in j..=ju {
                    ab.swap(c * ld + kv + j - c, c * ld + kv + j + p - c);
                }
            }
            if km > 0 {
                let r = 1.0 / ab[diagonal];
                for v in &mut ab[diagonal + 1..=diagonal + km] {
                    *v *= r;
                }
                for c in j + 1..=ju {
                    // Column c's rows j ..= j + km: split off column j's multipliers.
                    let (left, right) = ab.split_at_mut(c * ld);
                    let multipliers = &left[diagonal + 1..=diagonal + km];
                    let top = kv + j - c;
                    let ajc = right[top];
                    if ajc != 0.0 {
                        for (v, m) in right[top + 1..=top + km].iter_mut().zip(multipliers) {
                            *v -= m * ajc;
                        }
                    }
                }
            }
        }
        // The solves' layout.
        self.l.fill(0.0);
        self.u.fill(0.0);
        for k in 0..n {
            let diagonal = k * ld + kv;
            let km = kl.min(n - 1 - k);
            self.l[k * kl..k * kl + km].copy_from_slice(&ab[diagonal + 1..=diagonal + km]);
            let inverse = 1.0 / ab[diagonal];
            self.inverse_diagonal[k] = inverse;
            for d in 1..=kv.min(n - 1 - k) {
                self.u[k * kv + d - 1] = ab[(k + d) * ld + kv - d] * inverse;
            }
        }
        if (1..=MAX_BLOCKED).contains(&kv) {
            self.block_u();
        }
        Ok(())
    }

    /// [`blocks`](Self::blocks) from `u` and `inverse_diagonal`: each row of a block, from its
    /// last, x_k = y_k / u_kk - sum_d (u_k,k+d / u_kk) x_k+d with the unknowns of the block
    /// after it substituted.
    fn block_u(&mut self) {
        let (n, kv) = (self.n, self.kl + self.ku);
        let size = BLOCK * (BLOCK + kv);
        let n_pad = n.div_ceil(BLOCK) * BLOCK;
        for (b, block) in self.blocks.chunks_exact_mut(size).enumerate() {
            block.fill(0.0);
            let top = n_pad - b * BLOCK - 1;
            let base = top + 1 - BLOCK;
            let (h, g) = block.split_at_mut(BLOCK * BLOCK);
            for r in (0..BLOCK).rev() {
                let k = base + r;
                if k >= n {
                    continue;
                }
                h[r * BLOCK + r] = self.inverse_diagonal[k];
                for d in 1..=kv {
                    let (j, v) = (k + d, self.u[k * kv + d - 1]);
                    if v == 0.0 {
                        continue;
                    }
                    if j <= top {
                        let rj = j - base;
                        for q in 0..BLOCK {
                            h[r * BLOCK + q] -= v * h[rj * BLOCK + q];
                        }
                        for e in 0..kv {
                            g[r * kv + e] -= v * g[rj * kv + e];
                        }
                    } else {
                        g[r * kv + j - top - 1] += v;
                    }
                }
            }
        }
    }

    /// x := A^-1 x with the last factors, x in band order gathered by `gather`
    /// (`x_band[k] = x[gather[k]]`) and scattered back the same way.
    pub fn solve(&mut self, gather: &[usize], x: &mut [f64]) {
        let (n, kl, kv) = (self.n, self.kl, self.kl + self.ku);
        let w = &mut self.work;
        // L y = P b: the interchanges and multipliers step by step (dgbtrs), b gathered from x
        // in band order, y into w.
        let (pivots, l) = (&self.pivots, &self.l);
        match kl {
            1 => forward::<1>(n, pivots, l, gather, x, w),
            2 => forward::<2>(n, pivots, l, gather, x, w),
            3 => forward::<3>(n, pivots, l, gather, x, w),
            4 => forward::<4>(n, pivots, l, gather, x, w),
            _ => {
                for (wk, &g) in w.iter_mut().zip(gather) {
                    *wk = x[g];
                }
                w[n..].fill(0.0);
                forward_any(n, kl, pivots, l, w);
            }
        }
        // U x = y from the last row, in blocks for small bandwidths.
        let (u, d, blocks) = (&self.u, &self.inverse_diagonal, &self.blocks);
        w[n..].fill(0.0);
        match kv {
            1 => backward_blocked::<1>(n, blocks, w, gather, x),
            2 => backward_blocked::<2>(n, blocks, w, gather, x),
            3 => backward_blocked::<3>(n, blocks, w, gather, x),
            4 => backward_blocked::<4>(n, blocks, w, gather, x),
            5 => backward_blocked::<5>(n, blocks, w, gather, x),
            6 => backward_blocked::<6>(n, blocks, w, gather, x),
            7 => backward_blocked::<7>(n, blocks, w, gather, x),
            8 => backward_blocked::<8>(n, blocks, w, gather, x),
            _ => backward_any(n, kv, u, d, w, gather, x),
        }
    }
}

// The solves for small bandwidths keep the rows in flight in registers, so that an unknown
// waits for the one before it through a multiplication and a subtraction only, not through
// memory (L: the window of rows k ..= k + KL; the same operations in the same order as
// [`forward_any`], so the same results bit for bit), and U's unknowns are found four at a time
// from the ones after them ([`backward_blocked`]). At 1 999 states with kl = ku = 2 (the stiff
// chain), a solve took 11.2 ns per unknown row by row through memory, 7.0 ns with the window,
// 5.0 ns with U in blocks (`examples/newton_solve.rs`, with flush-to-zero); faer's sparse LU
// 11.5 ns.

/// L y = P b for lower bandwidth KL (>= 1), b = x gathered in band order (`gather`), read as the
/// elimination reaches its rows; y into w[..n].
fn forward<const KL: usize>(n: usize, pivots: &[usize], l: &[f64], gather: &[usize], x: &[f64], w: &mut [f64]) {
    let b = |k: usize| if k < n { x[gather[k]] } else { 0.0 };
    // Rows k (head) and k + 1 ..= k + KL (rest) as the elimination reaches step k.
    let mut head = b(0);
    let mut rest = [0.0; KL];
    for (i, r) in rest.iter_mut().enumerate() {
        *r = b(i + 1);
    }
    for (k, multipliers) in l.chunks_exact(KL).enumerate().take(n) {
        let d = pivots[k] - k;
        for (i, r) in rest.iter_mut().enumerate() {
            if d == i + 1 {
                std::mem::swap(&mut head, r);
            }
        }
        let y = head;
        w[k] = y;
        head = rest[0] - multipliers[0] * y;
        for i in 1..KL {
            rest[i - 1] = rest[i] - multipliers[i] * y;
        }
        rest[KL - 1] = b(k + KL + 1);
    }
}

fn forward_any(n: usize, kl: usize, pivots: &[usize], l: &[f64], w: &mut [f64]) {
    for k in 0..n {
        let p = pivots[k];
        if p != k {
            w.swap(k, p);
        }
        let y = w[k];
        for (v, m) in w[k + 1..k + 1 + kl].iter_mut().zip(&l[k * kl..(k + 1) * kl]) {
            *v -= m * y;
        }
    }
}

/// Rows per block of the blocked solve with U.
const BLOCK: usize = 4;
/// U is solved in blocks up to this many superdiagonals, row by row beyond.
const MAX_BLOCKED: usize = 8;

/// U x = y in blocks of [`BLOCK`] rows (`blocks`, [`BandLu::block_u`]) for KV superdiagonals, y
/// in w (band order, zero from n to a multiple of [`BLOCK`]), x scattered into `x` through
/// `gather`. A block's unknowns wait for the block after it through one multiplication and a
/// pairwise sum of KV products.
fn backward_blocked<const KV: usize>(n: usize, blocks: &[f64], w: &[f64], gather: &[usize], x: &mut [f64]) {
    let n_pad = n.div_ceil(BLOCK) * BLOCK;
    // x_top+1 ..= x_top+KV of the block about to be solved (zero past n).
    let mut next = [0.0; KV];
    for (b, block) in blocks.chunks_exact(BLOCK * (BLOCK + KV)).enumerate() {
        let base = n_pad - (b + 1) * BLOCK;
        let (h, g) = block.split_at(BLOCK * BLOCK);
        let y = &w[base..base + BLOCK];
        let mut xb = [0.0; BLOCK];
        for r in 0..BLOCK {
            let mut s = 0.0;
            for q in r..BLOCK {
                s += h[r * BLOCK + q] * y[q];
            }
            let mut p = [0.0; KV];
            for (e, pe) in p.iter_mut().enumerate() {
                *pe = g[r * KV + e] * next[e];
            }
            xb[r] = s - pairwise(&mut p);
        }
        for e in (0..KV).rev() {
            next[e] = if e < BLOCK { xb[e] } else { next[e - BLOCK] };
        }
        for (r, v) in xb.iter().enumerate() {
            if base + r < n {
                x[gather[base + r]] = *v;
            }
        }
    }
}

/// The sum of `p` added pairwise (neighbours, then neighbouring sums, ...).
#[inline(always)]
fn pairwise<const K: usize>(p: &mut [f64; K]) -> f64 {
    let mut len = K;
    while len > 1 {
        let half = len / 2;
        for i in 0..half {
            p[i] = p[2 * i] + p[2 * i + 1];
        }
        if len % 2 == 1 {
            p[half] = p[len - 1];
        }
        len = half + len % 2;
    }
    if K == 0 {
        0.0
    } else {
        p[0]
    }
}

fn backward_any(n: usize, kv: usize, u: &[f64], inverse_diagonal: &[f64], w: &mut [f64], gather: &[usize], x: &mut [f64]) {
    for k in (0..n).rev() {
        let row = &u[k * kv..(k + 1) * kv];
        let mut s = w[k] * inverse_diagonal[k];
        for d in (1..=kv).rev() {
            s -= row[d - 1] * w[k + d];
        }
        w[k] = s;
        x[gather[k]] = s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reproducible pseudo-random number in [-1, 1) (a 64-bit LCG, Knuth's MMIX constants).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// A random n x n matrix (row-major) of bandwidths kl, ku whose diagonal is small against the
    /// entries below it, so that partial pivoting interchanges rows at most steps.
    fn random_band(n: usize, kl: usize, ku: usize, rng: &mut Lcg) -> Vec<Vec<f64>> {
        let mut a = vec![vec![0.0; n]; n];
        for i in 0..n {
            for j in i.saturating_sub(kl)..n.min(i + ku + 1) {
                a[i][j] = if i == j { 0.01 * rng.next() } else { rng.next() };
            }
        }
        a
    }

    /// The dense LU of `jacobian.rs` (partial pivoting) solving a x = b: the reference.
    fn dense_solution(a: &[Vec<f64>], b: &[f64]) -> Vec<f64> {
        let n = a.len();
        let mut lu: Vec<f64> = (0..n * n).map(|k| a[k % n][k / n]).collect();
        let mut swaps = vec![0; n];
        super::super::jacobian::dense_lu(n, &mut lu, &mut swaps).unwrap();
        let mut x = b.to_vec();
        super::super::jacobian::dense_solve(n, &lu, &swaps, &mut x);
        x
    }

    fn band_of(a: &[Vec<f64>], kl: usize, ku: usize) -> BandLu {
        let n = a.len();
        let mut lu = BandLu::new(n, kl, ku);
        for i in 0..n {
            for j in i.saturating_sub(kl)..n.min(i + ku + 1) {
                lu.storage()[BandLu::position(kl, ku, i, j)] = a[i][j];
            }
        }
        lu
    }

    #[test]
    fn band_lu_solves_as_the_dense_lu_does_with_rows_interchanged() {
        let mut rng = Lcg(7);
        for (n, kl, ku) in [(1, 0, 0), (5, 1, 1), (12, 2, 2), (30, 3, 1), (30, 1, 4), (40, 0, 3), (40, 3, 0), (25, 5, 5), (8, 7, 7)] {
            let a = random_band(n, kl, ku, &mut rng);
            let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
            let mut lu = band_of(&a, kl, ku);
            lu.factor().unwrap();
            if n > 4 && kl > 0 {
                assert!(lu.pivots.iter().enumerate().filter(|(k, p)| *k != **p).count() > n / 3, "rows interchanged: {:?}", lu.pivots);
            }
            // Identity gather: band order is the matrix's.
            let order: Vec<usize> = (0..n).collect();
            let mut x = b.clone();
            lu.solve(&order, &mut x);
            let reference = dense_solution(&a, &b);
            let scale = reference.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            for i in 0..n {
                assert!((x[i] - reference[i]).abs() < 1e-10 * scale, "n {n} kl {kl} ku {ku} x[{i}] {} against {}", x[i], reference[i]);
                let residual: f64 = (0..n).map(|j| a[i][j] * x[j]).sum::<f64>() - b[i];
                assert!(residual.abs() < 1e-10 * scale, "n {n} kl {kl} ku {ku} row {i}: residual {residual:e}");
            }
        }
    }

    #[test]
    fn band_lu_gathers_and_scatters_through_an_ordering() {
        let (n, kl, ku) = (20, 2, 3);
        let mut rng = Lcg(11);
        let a = random_band(n, kl, ku, &mut rng);
        // The matrix a in band order is p a p^T of some m in its own order: m[g[i]][g[j]] = a[i][j].
        let gather: Vec<usize> = (0..n).map(|k| (7 * k + 3) % n).collect();
        let mut m = vec![vec![0.0; n]; n];
        for i in 0..n {
            for j in 0..n {
                m[gather[i]][gather[j]] = a[i][j];
            }
        }
        let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        let mut lu = band_of(&a, kl, ku);
        lu.factor().unwrap();
        let mut x = b.clone();
        lu.solve(&gather, &mut x);
        let reference = dense_solution(&m, &b);
        for i in 0..n {
            assert!((x[i] - reference[i]).abs() < 1e-10 * (1.0 + reference[i].abs()), "x[{i}] {} against {}", x[i], reference[i]);
        }
    }

    #[test]
    fn band_lu_solves_are_deterministic_and_reuse_the_factors() {
        let (n, kl, ku) = (50, 2, 2);
        let mut rng = Lcg(3);
        let a = random_band(n, kl, ku, &mut rng);
        let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        let order: Vec<usize> = (0..n).collect();
        let solve = |lu: &mut BandLu| {
            let mut x = b.clone();
            lu.solve(&order, &mut x);
            x.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        };
        let mut one = band_of(&a, kl, ku);
        one.factor().unwrap();
        let first = solve(&mut one);
        assert_eq!(first, solve(&mut one), "the same factors solve the same twice");
        let mut other = band_of(&a, kl, ku);
        other.factor().unwrap();
        assert_eq!(first, solve(&mut other), "another factorization of the same matrix");
    }

    #[test]
    fn the_fast_solves_agree_with_the_plain_loops() {
        let mut rng = Lcg(13);
        for (kl, ku) in [(1, 0), (1, 1), (2, 2), (3, 1), (4, 4), (2, 6), (0, 3), (0, 0), (5, 2), (1, 8)] {
            for n in [1, 2, 3, 4, 5, 23, 24] {
                let a = random_band(n, kl, ku, &mut rng);
                let mut lu = band_of(&a, kl, ku);
                lu.factor().unwrap();
                let gather: Vec<usize> = (0..n).map(|k| (2 * n + 1 - k) % n).collect();
                let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
                let mut x = b.clone();
                lu.solve(&gather, &mut x);
                // The plain loops, row by row through memory.
                let kv = kl + ku;
                let mut w = vec![0.0; lu.work.len()];
                for k in 0..n {
                    w[k] = b[gather[k]];
                }
                forward_any(n, kl, &lu.pivots, &lu.l, &mut w);
                // L's window: the same bits.
                let mut window = vec![0.0; lu.work.len()];
                for k in 0..n {
                    window[k] = b[gather[k]];
                }
                match kl {
                    1 => forward::<1>(n, &lu.pivots, &lu.l, &gather, &b, &mut window),
                    2 => forward::<2>(n, &lu.pivots, &lu.l, &gather, &b, &mut window),
                    3 => forward::<3>(n, &lu.pivots, &lu.l, &gather, &b, &mut window),
                    4 => forward::<4>(n, &lu.pivots, &lu.l, &gather, &b, &mut window),
                    _ => forward_any(n, kl, &lu.pivots, &lu.l, &mut window),
                }
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&window[..n]), bits(&w[..n]), "L: n {n} kl {kl} ku {ku}");
                // U in blocks: to rounding.
                w[n..].fill(0.0);
                let mut plain = vec![0.0; n];
                backward_any(n, kv, &lu.u, &lu.inverse_diagonal, &mut w, &gather, &mut plain);
                let scale = plain.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                for i in 0..n {
                    assert!((x[i] - plain[i]).abs() <= 1e-12 * scale, "U: n {n} kl {kl} ku {ku} x[{i}] {} against {}", x[i], plain[i]);
                }
            }
        }
    }

    #[test]
    fn a_singular_band_matrix_is_refused() {
        let (n, kl, ku) = (10, 1, 2);
        let mut rng = Lcg(5);
        // A zero column.
        let mut a = random_band(n, kl, ku, &mut rng);
        for row in a.iter_mut() {
            row[4] = 0.0;
        }
        assert!(band_of(&a, kl, ku).factor().is_err());
        // Singular after an elimination step: the leading block [[1, 2], [2, 4]] (exact in
        // binary: the second pivot is 0 exactly), the rest the identity.
        let mut a = vec![vec![0.0; n]; n];
        for i in 0..n {
            a[i][i] = 1.0;
        }
        (a[0][1], a[1][0], a[1][1], a[0][2]) = (2.0, 2.0, 4.0, 3.0);
        assert!(band_of(&a, kl, ku).factor().is_err());
        // A NaN.
        let mut a = random_band(n, kl, ku, &mut rng);
        a[3][3] = f64::NAN;
        assert!(band_of(&a, kl, ku).factor().is_err());
    }
}
