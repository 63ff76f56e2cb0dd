//! The implicit method's Jacobian df/dx and its linear solves: the Jacobian's structure (which
//! derivative depends on which state), its assembly, and the factorization of the Newton matrix
//! I - h gamma J: dense for small models; for large ones a band LU when reordering the states
//! makes the matrix a narrow band (chains, lines, discretized shafts), else faer's sparse LU.
//!
//! Structure: the states-only dependencies of the derivatives, from one evaluation of the
//! equations over traces (`integrate::ExactRhs::columns`), once per library and configuration of
//! the integer and boolean values ([`structure`]); [`probe`] finds the same by perturbing each
//! state alone (n + 1 evaluations: the tests' reference). Its columns are grouped by a greedy
//! coloring (no two columns of a group share a row), so that the Jacobian costs one evaluation
//! per color, not one per state.
//!
//! Assembly ([`evaluate`]): exact, the equations evaluated over dual numbers once per color.
//!
//! Dense, band or sparse: below [`DENSE_BELOW`] states the Newton matrix is a dense n x n matrix
//! (every column perturbed on its own, LU with partial pivoting) unless its pattern reordered is
//! a band narrower than the matrix that the band LU's fast loops solve ([`Structure::small`]);
//! from there on, the probed pattern in compressed columns and no states x states matrix
//! anywhere. A pattern denser
//! than [`DENSE_ABOVE_FILL`] falls back to dense. Otherwise the states are reordered by reverse
//! Cuthill-McKee, and when the band that makes is narrow against what faer's sparse LU fills
//! ([`BAND_BELOW_FILL_FAST`], [`BAND_BELOW_FILL`]), the matrix is factorized as a band
//! ([`band`]: LAPACK's band LU with partial pivoting, its solves made for latency); else by
//! faer's sparse LU (fill-reducing column ordering and symbolic analysis once per structure, a
//! numeric factorization each time the matrix changes). The stiff chain at 1 999 states is a
//! band of width 2 either side: a solve costs 4.5-5 ns per state there against 11.5 ns with
//! faer's LU, and the Newton solves were about 80 % of its doStep.
//!
//! Everything is deterministic: the same (t, x, parameters, h gamma) give the same factors bit for
//! bit (faer runs sequentially here; the band LU is sequential code with a fixed order), which an FMU state's restore relies on
//! (`stepper::JacobianPoint`).

use std::any::TypeId;
use std::sync::{Arc, Mutex};

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::perm::PermRef;
use faer::sparse::linalg::lu::simplicial::{self, SimplicialLu};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuSymbolicParams};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par};

use super::band;
use crate::real::Dual;

/// Dense or band below this many states ([`Structure::small`]), faer's sparse LU allowed from it
/// on. Measured on the stiff torsional chain (bench/torsional-chain, J = 1e-4, K = 1e5, D = 10,
/// a 100 N m torque step at 0.1 s; us per 1 ms doStep over 1 s at rtol 1e-8, through the C ABI):
/// see [`DENSE_BELOW_MEASURED`]. Sparse costs 0.95-1.01 of dense up to 19 states, 0.80 at 29
/// and 0.41 at 99; the band 0.79 of dense at 9 states, 0.62 at 19 (1.12 at 5, where the band,
/// 7 entries a row, is wider than the matrix).
pub const DENSE_BELOW: usize = 20;

/// A factorization forced for every size by the environment's `FMU_RUNTIME_JACOBIAN`, for the
/// benchmarks that measure [`DENSE_BELOW`] and [`BAND_BELOW_FILL`] (bench/chain.py
/// `--dense-or-sparse`): `dense` (every size dense), `sparse` (every size from 2 states faer's
/// sparse LU, never the band) or `band` (every size from 2 states the band LU), read once per
/// process. Not meant for users: the results are the same to the tolerance either way, only the
/// cost differs.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Forced {
    Dense,
    Sparse,
    Band,
}

pub fn forced() -> Option<Forced> {
    static CHOSEN: std::sync::OnceLock<Option<Forced>> = std::sync::OnceLock::new();
    *CHOSEN.get_or_init(|| match std::env::var("FMU_RUNTIME_JACOBIAN").as_deref() {
        Ok("dense") => Some(Forced::Dense),
        Ok("sparse") => Some(Forced::Sparse),
        Ok("band") => Some(Forced::Band),
        _ => None,
    })
}

/// [`DENSE_BELOW`], or what [`forced`] makes of it.
pub fn dense_below() -> usize {
    match forced() {
        Some(Forced::Dense) => usize::MAX,
        Some(_) => 2,
        None => DENSE_BELOW,
    }
}

/// The measurement behind [`DENSE_BELOW`] and [`Structure::small`]: (states, us per doStep
/// dense, band, sparse), `bench/run.sh --chain --dense-or-sparse 3,5,8,10,15,25,50` at commit
/// a7e3f0f on a quiet machine (BENCHMARKS.md). Up to 15 states the chain's pattern fills more
/// than [`DENSE_ABOVE_FILL`] of the matrix, so "sparse" is dense there.
pub const DENSE_BELOW_MEASURED: &[(usize, f64, f64, f64)] = &[
    (5, 1.2, 1.3, 1.1),
    (9, 2.0, 1.6, 2.0),
    (15, 3.2, 2.0, 3.2),
    (19, 4.0, 2.5, 3.8),
    (29, 6.2, 3.0, 5.0),
    (49, 12.4, 4.8, 7.9),
    (99, 40.2, 9.2, 16.7),
];

/// A pattern is factorized as a band (reordered by reverse Cuthill-McKee) when the band LU's
/// storage, n (2 kl + ku + 1) entries, is less than this many times the entries of faer's
/// sparse factors of a trial matrix (`Structure::trial_fill`), and its bandwidths are those of
/// the band LU's fast solves ([`band::fast`]); else by faer's sparse LU. Measured with
/// `examples/newton_solve.rs` (one solve, with flush-to-zero, on the shared 2-core machine): the
/// stiff chain at 1 999 states (kl = ku = 2: 7 band entries per state against 5.0 in the sparse
/// factors) solves in 4.5-5.0 ns per state as a band, 11.5 ns sparse (0.7 ns per band entry,
/// 2.3 per sparse one: even at 3 times the entries the band would be faster; 2 leaves a margin).
pub const BAND_BELOW_FILL_FAST: f64 = 2.0;

/// The same for bandwidths beyond the band LU's fast solves (row by row through memory): a stiff
/// M x M grid (5-point Laplacian, `newton_solve grid M`: kl = ku = M) costs about the same per
/// entry either way, 0.8-0.9 ns (band: 29, 53, 81, 108 ns per state for M = 10, 20, 30, 45 with
/// 31, 61, 91, 136 entries; sparse: 15, 23, 30, 36 ns with 15.6, 25.3, 33.9, 44.2), so the band
/// only when it holds fewer entries.
pub const BAND_BELOW_FILL: f64 = 1.0;

/// A probed pattern with more than this fraction of its n^2 entries set is factorized dense.
pub const DENSE_ABOVE_FILL: f64 = 0.25;

/// What a Jacobian's structure is cached under, within one library: the model (type), its
/// integer and boolean values (parameters and discrete modes: they may change the equations'
/// dependencies), the number of states.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StructureKey {
    pub model: TypeId,
    pub integers: Vec<i32>,
    pub booleans: Vec<bool>,
    pub n: usize,
}

/// The Jacobian's structure: its pattern in compressed sparse columns (the diagonal always in
/// it, rows ascending in each column), its columns grouped by color, and how the Newton matrix
/// is factorized.
pub struct Structure {
    pub n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// The columns of color c: `color_cols[color_ptr[c]..color_ptr[c + 1]]`.
    color_ptr: Vec<usize>,
    color_cols: Vec<usize>,
    /// Where the diagonal entry of each column sits in `row_idx`.
    diagonal: Vec<usize>,
    layout: Layout,
    /// The entries of faer's sparse factors of the trial matrix with the better ordering (None:
    /// not tried).
    sparse_fill: Option<usize>,
}

/// How the Newton matrix is factorized.
enum Layout {
    /// Dense LU (the pattern is full, column-major).
    Dense,
    /// The band LU of the matrix reordered by reverse Cuthill-McKee ([`band`]): state
    /// `order[k]` is the band's row and column k, the band has bandwidths `kl`, `ku`, and the
    /// pattern's entry e sits at `positions[e]` of the band storage.
    Band { order: Vec<usize>, kl: usize, ku: usize, positions: Vec<usize> },
    /// faer's sparse LU with this column ordering (forward, inverse).
    Sparse { ordering: (Vec<usize>, Vec<usize>) },
}

impl Structure {
    /// The full n x n pattern, each column its own color: dense.
    pub fn dense(n: usize) -> Structure {
        let col_ptr = (0..=n).map(|j| j * n).collect();
        let row_idx = (0..n * n).map(|k| k % n).collect();
        let color_ptr = (0..=n).collect();
        let color_cols = (0..n).collect();
        let diagonal = (0..n).map(|j| j * n + j).collect();
        Structure { n, col_ptr, row_idx, color_ptr, color_cols, diagonal, layout: Layout::Dense, sparse_fill: None }
    }

    /// The structure of a model below [`DENSE_BELOW`] states from each column's rows: a band
    /// where reverse Cuthill-McKee makes one that the band LU's fast loops solve ([`band::fast`])
    /// and that is narrower than the matrix (2 kl + ku + 1 < n entries a row), else dense (also
    /// when [`forced`] dense). Measured ([`DENSE_BELOW_MEASURED`]): the chain's band (kl = ku = 2)
    /// costs 0.79 of dense at 9 states and 0.62 at 19, 1.12 at 5 states (a row of 7 > 5).
    pub fn small(n: usize, columns: Vec<Vec<usize>>) -> Result<Structure, String> {
        if n < 2 || forced() == Some(Forced::Dense) {
            return Ok(Structure::dense(n));
        }
        let s = Structure::choose(n, columns, Some(Forced::Band))?;
        Ok(match s.layout {
            Layout::Band { kl, ku, .. } if band::fast(kl, ku) && 2 * kl + ku + 1 < n => s,
            _ => Structure::dense(n),
        })
    }

    /// A sparse structure from each column's rows (any order, the diagonal added): colored, and
    /// factorized dense when the pattern fills more than [`DENSE_ABOVE_FILL`], as a band when
    /// its reverse Cuthill-McKee band holds fewer than [`BAND_BELOW_FILL_FAST`] (bandwidths of
    /// the band LU's fast solves) or [`BAND_BELOW_FILL`] (wider) times the entries of faer's
    /// sparse factors, else by faer's sparse LU ([`forced`] may force either).
    pub fn sparse(n: usize, columns: Vec<Vec<usize>>) -> Result<Structure, String> {
        Structure::choose(n, columns, forced())
    }

    /// [`sparse`](Self::sparse), the choice between band and sparse LU forced or not.
    pub fn choose(n: usize, mut columns: Vec<Vec<usize>>, force: Option<Forced>) -> Result<Structure, String> {
        for (j, rows) in columns.iter_mut().enumerate() {
            rows.push(j);
            rows.sort_unstable();
            rows.dedup();
        }
        let nnz: usize = columns.iter().map(Vec::len).sum();
        if force != Some(Forced::Band) && nnz as f64 > DENSE_ABOVE_FILL * (n * n) as f64 {
            return Ok(Structure::dense(n));
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(nnz);
        let mut diagonal = Vec::with_capacity(n);
        col_ptr.push(0);
        for (j, rows) in columns.iter().enumerate() {
            let at = rows.binary_search(&j).expect("the diagonal was added");
            diagonal.push(row_idx.len() + at);
            row_idx.extend_from_slice(rows);
            col_ptr.push(row_idx.len());
        }
        drop(columns);
        let (color_ptr, color_cols) = color(n, &col_ptr, &row_idx);
        let mut s = Structure { n, col_ptr, row_idx, color_ptr, color_cols, diagonal, layout: Layout::Dense, sparse_fill: None };
        let rcm = reverse_cuthill_mckee(n, &s.col_ptr, &s.row_idx);
        let (kl, ku) = s.bandwidths(&rcm.1);
        if force == Some(Forced::Band) {
            s.layout = s.band_layout(rcm.0, kl, ku);
            return Ok(s);
        }
        // The sparse LU's column ordering: faer's COLAMD, or the reverse Cuthill-McKee ordering
        // of the symmetrized pattern where that fills strictly less in a trial factorization (a
        // band numbered across, which COLAMD may not narrow). On the stiff chain both fill the
        // same (5n in the trial, 7n in the Newton matrix's factors), and COLAMD's solves are 3.4
        // times faster: RCM's order runs them through subnormal numbers (the chain's end at
        // rest; with flush-to-zero both take the same time).
        let colamd = {
            let a = SymbolicSparseColMatRef::new_checked(n, n, &s.col_ptr, None, &s.row_idx);
            let symbolic = factorize_symbolic_lu(a, LuSymbolicParams::default()).map_err(|e| format!("the sparse LU's ordering failed: {e:?}"))?;
            let (fwd, inv) = symbolic.col_perm().arrays();
            (fwd.to_vec(), inv.to_vec())
        };
        let mut best: Option<((Vec<usize>, Vec<usize>), usize)> = None;
        for ordering in [colamd, rcm.clone()] {
            let fill = s.trial_fill(&ordering)?;
            if best.as_ref().map_or(true, |(_, f)| fill < *f) {
                best = Some((ordering, fill));
            }
        }
        let (ordering, fill) = best.expect("two orderings tried");
        s.sparse_fill = Some(fill);
        let band_entries = n * (2 * kl + ku + 1);
        let ratio = if band::fast(kl, ku) { BAND_BELOW_FILL_FAST } else { BAND_BELOW_FILL };
        s.layout = if force != Some(Forced::Sparse) && (band_entries as f64) < ratio * fill as f64 {
            s.band_layout(rcm.0, kl, ku)
        } else {
            Layout::Sparse { ordering }
        };
        Ok(s)
    }

    /// The lower and upper bandwidths of the pattern in the order whose inverse is `inverse`
    /// (state j is row and column `inverse[j]`).
    fn bandwidths(&self, inverse: &[usize]) -> (usize, usize) {
        let (mut kl, mut ku) = (0, 0);
        for j in 0..self.n {
            for &i in &self.row_idx[self.col_ptr[j]..self.col_ptr[j + 1]] {
                let (r, c) = (inverse[i], inverse[j]);
                kl = kl.max(r.saturating_sub(c));
                ku = ku.max(c.saturating_sub(r));
            }
        }
        (kl, ku)
    }

    fn band_layout(&self, order: Vec<usize>, kl: usize, ku: usize) -> Layout {
        let mut inverse = vec![0; self.n];
        for (k, &v) in order.iter().enumerate() {
            inverse[v] = k;
        }
        let mut positions = vec![0; self.row_idx.len()];
        for j in 0..self.n {
            for e in self.col_ptr[j]..self.col_ptr[j + 1] {
                positions[e] = band::BandLu::position(kl, ku, inverse[self.row_idx[e]], inverse[j]);
            }
        }
        Layout::Band { order, kl, ku, positions }
    }

    /// Entries of L and U of a matrix with this pattern whose diagonal dominates, factorized
    /// by faer's sparse LU with this column ordering.
    fn trial_fill(&self, ordering: &(Vec<usize>, Vec<usize>)) -> Result<usize, String> {
        let values: Vec<f64> = (0..self.n)
            .flat_map(|j| (self.col_ptr[j]..self.col_ptr[j + 1]).map(move |k| (j, k)))
            .map(|(j, k)| if self.row_idx[k] == j { 4.0 } else { 0.1 + 0.01 * (k % 7) as f64 })
            .collect();
        let mut f = Factors::sparse(self.n, self.nnz());
        f.factor_sparse(self, ordering, &values)?;
        match f {
            Factors::Sparse { lu, .. } => Ok(lu.l_factor_unsorted().row_idx().len() + lu.u_factor_unsorted().row_idx().len()),
            _ => unreachable!("made sparse"),
        }
    }

    /// How the Newton matrix is factorized: "dense", "band" or "sparse".
    pub fn kind(&self) -> &'static str {
        match self.layout {
            Layout::Dense => "dense",
            Layout::Band { .. } => "band",
            Layout::Sparse { .. } => "sparse",
        }
    }

    /// The entries of faer's sparse factors of the trial matrix (`trial_fill`), when tried.
    pub fn sparse_fill(&self) -> Option<usize> {
        self.sparse_fill
    }

    /// The band's lower and upper bandwidths, when the Newton matrix is factorized as a band.
    pub fn band(&self) -> Option<(usize, usize)> {
        match self.layout {
            Layout::Band { kl, ku, .. } => Some((kl, ku)),
            _ => None,
        }
    }

    /// Entries of the pattern (n^2 when dense).
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Evaluations of the right-hand side one Jacobian costs (besides f(t, x) itself).
    pub fn colors(&self) -> usize {
        self.color_ptr.len() - 1
    }

    pub fn is_dense(&self) -> bool {
        matches!(self.layout, Layout::Dense)
    }
}

/// Greedy coloring of the columns in their order: a column takes the smallest color no column
/// sharing a row with it has. Returns the columns grouped by color (CSR-like).
fn color(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> (Vec<usize>, Vec<usize>) {
    // The pattern by rows: the columns of each row.
    let mut row_ptr = vec![0usize; n + 1];
    for &i in row_idx {
        row_ptr[i + 1] += 1;
    }
    for i in 0..n {
        row_ptr[i + 1] += row_ptr[i];
    }
    let mut fill = row_ptr.clone();
    let mut row_cols = vec![0usize; row_idx.len()];
    for j in 0..n {
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            row_cols[fill[i]] = j;
            fill[i] += 1;
        }
    }
    let mut color_of = vec![usize::MAX; n];
    // forbidden[c] == j: color c is taken by a neighbour of column j.
    let mut forbidden: Vec<usize> = Vec::new();
    let mut n_colors = 0;
    for j in 0..n {
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            for &k in &row_cols[row_ptr[i]..row_ptr[i + 1]] {
                let c = color_of[k];
                if c != usize::MAX {
                    forbidden[c] = j;
                }
            }
        }
        let c = (0..n_colors).find(|c| forbidden[*c] != j).unwrap_or_else(|| {
            n_colors += 1;
            forbidden.push(usize::MAX);
            n_colors - 1
        });
        color_of[j] = c;
    }
    let mut color_ptr = vec![0usize; n_colors + 1];
    for &c in &color_of {
        color_ptr[c + 1] += 1;
    }
    for c in 0..n_colors {
        color_ptr[c + 1] += color_ptr[c];
    }
    let mut fill = color_ptr.clone();
    let mut color_cols = vec![0usize; n];
    for (j, &c) in color_of.iter().enumerate() {
        color_cols[fill[c]] = j;
        fill[c] += 1;
    }
    (color_ptr, color_cols)
}

/// The reverse Cuthill-McKee ordering of the symmetrized pattern (forward, inverse): a
/// breadth-first search from a vertex of least degree in each connected part, the neighbours
/// of each vertex visited by increasing degree, reversed.
fn reverse_cuthill_mckee(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); n];
    for j in 0..n {
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            if i != j {
                neighbours[i].push(j);
                neighbours[j].push(i);
            }
        }
    }
    for v in &mut neighbours {
        v.sort_unstable();
        v.dedup();
    }
    let degree: Vec<usize> = neighbours.iter().map(Vec::len).collect();
    let mut by_degree: Vec<usize> = (0..n).collect();
    by_degree.sort_by_key(|v| (degree[*v], *v));
    let mut order = Vec::with_capacity(n);
    let mut seen = vec![false; n];
    for &root in &by_degree {
        if seen[root] {
            continue;
        }
        seen[root] = true;
        let mut head = order.len();
        order.push(root);
        while head < order.len() {
            let v = order[head];
            head += 1;
            let mut next: Vec<usize> = neighbours[v].iter().copied().filter(|u| !seen[*u]).collect();
            next.sort_by_key(|u| (degree[*u], *u));
            for u in next {
                seen[u] = true;
                order.push(u);
            }
        }
    }
    order.reverse();
    let mut inverse = vec![0; n];
    for (k, &v) in order.iter().enumerate() {
        inverse[v] = k;
    }
    (order, inverse)
}

/// The right-hand side as the Jacobian sees it: f(y, t) into dy, with the advance's parameters.
pub type Rhs<'a> = &'a dyn Fn(&[f64], f64, &mut [f64]);

/// The states-only dependencies of the derivatives, by probing: at a point moved off (t, x) (so
/// that a product of two states at zero hides nothing), each state perturbed alone; a derivative
/// whose value changes (bit for bit) depends on it. n + 1 evaluations of the right-hand side.
/// A derivative that is not finite at the probe point depends on every state.
pub fn probe(rhs: Rhs, t: f64, x: &[f64], scale: &[f64]) -> Vec<Vec<usize>> {
    let n = x.len();
    let mut x0: Vec<f64> = (0..n).map(|j| x[j] + 0.0173 * (1.0 + 0.1 * (j % 7) as f64) * (x[j].abs() + scale[j])).collect();
    let mut f0 = vec![0.0; n];
    rhs(&x0, t, &mut f0);
    let mut f1 = vec![0.0; n];
    let mut columns = vec![Vec::new(); n];
    let unknown: Vec<usize> = (0..n).filter(|i| !f0[*i].is_finite()).collect();
    for j in 0..n {
        let xj = x0[j];
        x0[j] = xj + 1e-3 * (xj.abs() + scale[j]);
        rhs(&x0, t, &mut f1);
        x0[j] = xj;
        columns[j].extend((0..n).filter(|i| f1[*i].to_bits() != f0[*i].to_bits() && f0[*i].is_finite()));
        columns[j].extend_from_slice(&unknown);
    }
    columns
}

/// The cached structures of this library (one model per library; a few configurations).
static STRUCTURES: Mutex<Vec<(StructureKey, Arc<Structure>)>> = Mutex::new(Vec::new());

/// The structure the implicit method factorizes for `n` states whose derivatives depend on the
/// states as `columns` say: below [`dense_below`] states [`Structure::small`] (dense or a band),
/// from there on [`Structure::sparse`] (dense, band or sparse).
pub fn chosen(n: usize, columns: Vec<Vec<usize>>) -> Result<Structure, String> {
    if n < dense_below() {
        Structure::small(n, columns)
    } else {
        Structure::sparse(n, columns)
    }
}

/// The Jacobian's structure for `key`: the cached one, or the one [`chosen`] from `columns` (each
/// state's dependent derivatives: [`probe`]) and cached. The one place that says where the
/// dependencies come from.
pub fn structure(key: &StructureKey, columns: impl FnOnce() -> Vec<Vec<usize>>) -> Result<Arc<Structure>, String> {
    if let Some((_, s)) = STRUCTURES.lock().unwrap_or_else(|e| e.into_inner()).iter().find(|(k, _)| k == key) {
        return Ok(Arc::clone(s));
    }
    let made = Arc::new(chosen(key.n, columns())?);
    let mut cache = STRUCTURES.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, s)) = cache.iter().find(|(k, _)| k == key) {
        return Ok(Arc::clone(s));
    }
    cache.push((key.clone(), Arc::clone(&made)));
    Ok(made)
}

/// The right-hand side over dual numbers: f(y, t) into dy, with the advance's parameters.
pub type DualRhs<'a> = &'a dyn Fn(&[Dual], f64, &mut [Dual]);

/// Work vectors of [`evaluate`].
#[derive(Default)]
pub struct Work {
    x: Vec<Dual>,
    f: Vec<Dual>,
}

/// df/dx at (t, x) into `values` (the structure's entries, column by column), exact to
/// round-off: the equations evaluated over dual numbers once per color, every state of the
/// color seeded with derivative 1 (no two of them reach the same derivative, so each entry is
/// the derivative part of its row).
pub fn evaluate(s: &Structure, rhs: DualRhs, t: f64, x: &[f64], values: &mut [f64], work: &mut Work) {
    let n = s.n;
    let Work { x: xd, f } = work;
    xd.clear();
    xd.extend(x.iter().map(|&v| Dual::from(v)));
    f.resize(n, Dual::from(0.0));
    for c in 0..s.colors() {
        let cols = &s.color_cols[s.color_ptr[c]..s.color_ptr[c + 1]];
        for &j in cols {
            xd[j].eps = 1.0;
        }
        rhs(xd, t, f);
        for &j in cols {
            xd[j].eps = 0.0;
            for k in s.col_ptr[j]..s.col_ptr[j + 1] {
                values[k] = f[s.row_idx[k]].eps;
            }
        }
    }
}

/// The factors of the Newton matrix I - h gamma J, for solving with it.
pub enum Factors {
    /// LU with partial pivoting of the dense matrix (column-major) and the row swaps.
    Dense { lu: Vec<f64>, swaps: Vec<usize> },
    /// The band LU of the matrix in the structure's band order.
    Band { lu: band::BandLu },
    /// faer's simplicial LU (left-looking, partial pivoting) with the structure's column
    /// ordering, its row pivoting (forward, inverse), the matrix's values and the work space.
    Sparse { lu: SimplicialLu<usize, f64>, rows: (Vec<usize>, Vec<usize>), values: Vec<f64>, mem: MemBuffer },
}

impl Factors {
    pub fn new(s: &Structure) -> Factors {
        match &s.layout {
            Layout::Dense => Factors::Dense { lu: vec![0.0; s.n * s.n], swaps: vec![0; s.n] },
            Layout::Band { kl, ku, .. } => Factors::Band { lu: band::BandLu::new(s.n, *kl, *ku) },
            Layout::Sparse { .. } => Factors::sparse(s.n, s.nnz()),
        }
    }

    fn sparse(n: usize, nnz: usize) -> Factors {
        let req = StackReq::any_of(&[
            simplicial::factorize_simplicial_numeric_lu_scratch::<usize, f64>(n, n),
            simplicial::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq),
        ]);
        Factors::Sparse { lu: SimplicialLu::new(), rows: (vec![0; n], vec![0; n]), values: vec![0.0; nnz], mem: MemBuffer::new(req) }
    }

    /// Factorizes I - `hg` J, J's entries in `jac` (the structure's order). Err when singular.
    pub fn factor(&mut self, s: &Structure, jac: &[f64], hg: f64) -> Result<(), String> {
        match (self, &s.layout) {
            (Factors::Dense { lu, swaps }, _) => {
                let n = s.n;
                for (m, j) in lu.iter_mut().zip(jac) {
                    *m = -hg * j;
                }
                for k in 0..n {
                    lu[k * n + k] += 1.0;
                }
                dense_lu(n, lu, swaps)
            }
            (Factors::Band { lu }, Layout::Band { positions, .. }) => {
                let band = lu.storage();
                band.fill(0.0);
                for (&at, j) in positions.iter().zip(jac) {
                    band[at] = -hg * j;
                }
                for &k in &s.diagonal {
                    band[positions[k]] += 1.0;
                }
                lu.factor()
            }
            (f @ Factors::Sparse { .. }, Layout::Sparse { ordering }) => {
                let Factors::Sparse { values, .. } = &mut *f else { unreachable!() };
                for (m, j) in values.iter_mut().zip(jac) {
                    *m = -hg * j;
                }
                for &k in &s.diagonal {
                    values[k] += 1.0;
                }
                f.factor_own_values(s, ordering)
            }
            _ => Err("factors of another structure".into()),
        }
    }

    /// Factorizes the matrix of these entries (the structure's order) by faer's sparse LU with
    /// this column ordering.
    fn factor_sparse(&mut self, s: &Structure, ordering: &(Vec<usize>, Vec<usize>), matrix: &[f64]) -> Result<(), String> {
        if let Factors::Sparse { values, .. } = self {
            values.copy_from_slice(matrix);
        }
        self.factor_own_values(s, ordering)
    }

    fn factor_own_values(&mut self, s: &Structure, (fwd, inv): &(Vec<usize>, Vec<usize>)) -> Result<(), String> {
        let Factors::Sparse { lu, rows, values, mem } = self else {
            return Err("not a sparse factorization".into());
        };
        let a = SparseColMatRef::new(SymbolicSparseColMatRef::new_checked(s.n, s.n, &s.col_ptr, None, &s.row_idx), values);
        simplicial::factorize_simplicial_numeric_lu(&mut rows.0, &mut rows.1, lu, a, PermRef::new_checked(fwd, inv, s.n), MemStack::new(mem))
            .map_err(|e| format!("the Newton matrix is singular ({e:?})"))
    }

    /// b := (I - h gamma J)^-1 b with the last factors.
    pub fn solve(&mut self, s: &Structure, b: &mut [f64]) {
        match (self, &s.layout) {
            (Factors::Dense { lu, swaps }, _) => dense_solve(s.n, lu, swaps, b),
            (Factors::Band { lu }, Layout::Band { order, .. }) => lu.solve(order, b),
            (Factors::Sparse { lu, rows, mem, .. }, Layout::Sparse { ordering: (fwd, inv) }) => {
                let n = b.len();
                lu.solve_in_place_with_conj(
                    PermRef::new_checked(&rows.0, &rows.1, n),
                    PermRef::new_checked(fwd, inv, n),
                    Conj::No,
                    MatMut::from_column_major_slice_mut(b, n, 1),
                    Par::Seq,
                    MemStack::new(mem),
                );
            }
            _ => unreachable!("factors are made for their structure"),
        }
    }
}

/// LU with partial pivoting, in place (column-major n x n), the row swapped with each row k in
/// `swaps[k]`. Err when a pivot is zero or not finite.
pub(super) fn dense_lu(n: usize, a: &mut [f64], swaps: &mut [usize]) -> Result<(), String> {
    for k in 0..n {
        let col = &a[k * n..(k + 1) * n];
        let mut p = k;
        let mut best = col[k].abs();
        for (i, v) in col.iter().enumerate().skip(k + 1) {
            if v.abs() > best {
                best = v.abs();
                p = i;
            }
        }
        if !(best > 0.0 && best.is_finite()) {
            return Err(format!("the Newton matrix is singular (pivot {k} of {n})"));
        }
        swaps[k] = p;
        if p != k {
            for j in 0..n {
                a.swap(j * n + k, j * n + p);
            }
        }
        let inv = 1.0 / a[k * n + k];
        for v in &mut a[k * n + k + 1..(k + 1) * n] {
            *v *= inv;
        }
        let (left, right) = a.split_at_mut((k + 1) * n);
        let lk = &left[k * n + k + 1..(k + 1) * n];
        for j in k + 1..n {
            let cj = &mut right[(j - k - 1) * n..(j - k) * n];
            let ukj = cj[k];
            if ukj != 0.0 {
                for (v, l) in cj[k + 1..].iter_mut().zip(lk) {
                    *v -= l * ukj;
                }
            }
        }
    }
    Ok(())
}

pub(super) fn dense_solve(n: usize, lu: &[f64], swaps: &[usize], b: &mut [f64]) {
    for k in 0..n {
        b.swap(k, swaps[k]);
    }
    // L y = b (unit lower), column by column.
    for k in 0..n {
        let bk = b[k];
        if bk != 0.0 {
            for (v, l) in b[k + 1..].iter_mut().zip(&lu[k * n + k + 1..(k + 1) * n]) {
                *v -= l * bk;
            }
        }
    }
    // U x = y, column by column from the last.
    for k in (0..n).rev() {
        b[k] /= lu[k * n + k];
        let bk = b[k];
        if bk != 0.0 {
            for (v, u) in b[..k].iter_mut().zip(&lu[k * n..k * n + k]) {
                *v -= u * bk;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f = A x for a fixed banded-with-a-corner A; its Jacobian is A.
    fn matrix(n: usize) -> Vec<Vec<f64>> {
        let mut a = vec![vec![0.0; n]; n];
        for i in 0..n {
            a[i][i] = -3.0 - i as f64;
            if i + 1 < n {
                a[i][i + 1] = 1.5;
                a[i + 1][i] = 0.5 * (i as f64 + 1.0);
            }
        }
        a[n - 1][0] = 2.0;
        a
    }

    fn apply<R: crate::real::Real>(a: &[Vec<f64>], x: &[R], y: &mut [R]) {
        for (i, row) in a.iter().enumerate() {
            y[i] = row.iter().zip(x).fold(R::from(0.0), |sum, (r, v)| sum + *v * *r);
        }
    }

    #[test]
    fn colored_dual_columns_and_the_three_factorizations_solve_the_newton_system() {
        let n = 40;
        let a = matrix(n);
        let rhs = |x: &[f64], _t: f64, y: &mut [f64]| apply(&a, x, y);
        let dual = |x: &[Dual], _t: f64, y: &mut [Dual]| apply(&a, x, y);
        let x: Vec<f64> = (0..n).map(|i| 0.3 + i as f64).collect();
        let scale = vec![1.0; n];
        let columns = probe(&rhs, 0.0, &x, &scale);
        // A ring (the corner): reverse Cuthill-McKee makes it a band of width 2 either side.
        let chosen = Structure::sparse(n, columns.clone()).unwrap();
        assert_eq!((chosen.kind(), chosen.band()), ("band", Some((2, 2))));
        assert_eq!(chosen.nnz(), 3 * n - 2 + 1);
        assert!(chosen.colors() <= 4, "{} colors", chosen.colors());
        let sparse = Structure::choose(n, columns.clone(), Some(Forced::Sparse)).unwrap();
        assert_eq!(sparse.kind(), "sparse");
        let band = Structure::choose(n, columns, Some(Forced::Band)).unwrap();
        assert_eq!(band.kind(), "band");
        let dense = Structure::dense(n);
        let b: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let hg = 0.37;
        let mut solutions = Vec::new();
        for s in [&sparse, &band, &dense] {
            let mut jac = vec![0.0; s.nnz()];
            evaluate(s, &dual, 0.0, &x, &mut jac, &mut Work::default());
            for j in 0..n {
                for k in s.col_ptr[j]..s.col_ptr[j + 1] {
                    let i = s.row_idx[k];
                    // Exact: a linear f's dual derivative is its matrix entry, bit for bit.
                    assert_eq!(jac[k], a[i][j], "J[{i}][{j}]");
                }
            }
            let mut f = Factors::new(s);
            f.factor(s, &jac, hg).unwrap();
            let mut z = b.clone();
            f.solve(s, &mut z);
            // (I - hg J) z = b, J as assembled
            let mut jz = vec![0.0; n];
            for j in 0..n {
                for k in s.col_ptr[j]..s.col_ptr[j + 1] {
                    jz[s.row_idx[k]] += jac[k] * z[j];
                }
            }
            for i in 0..n {
                assert!((z[i] - hg * jz[i] - b[i]).abs() < 1e-12, "row {i}: {}", z[i] - hg * jz[i] - b[i]);
            }
            solutions.push(z);
        }
        for other in &solutions[..2] {
            for (s, d) in other.iter().zip(&solutions[2]) {
                assert!((s - d).abs() < 1e-12 * (1.0 + d.abs()), "{s} {d}");
            }
        }
    }

    /// The switch between band and sparse LU on the two patterns that measured it
    /// ([`BAND_BELOW_FILL_FAST`], [`BAND_BELOW_FILL`]): the chain (speeds, then twists, as the
    /// model declares them) is a band of width 2 either side after reverse Cuthill-McKee; a
    /// 10 x 10 grid's band (10 either side, 31 entries per row) holds twice the sparse factors'
    /// entries, and its solve measured twice as slow as a band.
    #[test]
    fn a_narrow_band_is_factorized_as_a_band_a_wide_one_sparse() {
        let n = 200;
        let m = 2 * n - 1;
        let mut chain = vec![Vec::new(); m];
        for i in 0..n {
            // d w_i / dt: the speeds i - 1, i, i + 1 and the twists i - 1, i; d theta_i / dt: w_i, w_i+1.
            for j in [i.wrapping_sub(1), i, i + 1] {
                if j < n {
                    chain[j].push(i);
                }
            }
            for t in [i.wrapping_sub(1), i] {
                if t < n - 1 {
                    chain[n + t].push(i);
                }
            }
            if i < n - 1 {
                chain[i].push(n + i);
                chain[i + 1].push(n + i);
            }
        }
        let s = Structure::sparse(m, chain).unwrap();
        assert_eq!((s.kind(), s.band()), ("band", Some((2, 2))));
        let side = 10;
        let mut grid = vec![Vec::new(); side * side];
        for i in 0..side {
            for j in 0..side {
                let k = i * side + j;
                for (di, dj) in [(0, 1), (1, 0)] {
                    if i + di < side && j + dj < side {
                        let other = (i + di) * side + j + dj;
                        grid[k].push(other);
                        grid[other].push(k);
                    }
                }
            }
        }
        let s = Structure::sparse(side * side, grid).unwrap();
        assert_eq!(s.kind(), "sparse");
    }

    #[test]
    fn a_dense_pattern_is_factorized_dense() {
        let n = 6;
        let columns = vec![(0..n).collect::<Vec<_>>(); n];
        assert!(Structure::sparse(n, columns).unwrap().is_dense());
    }
}
