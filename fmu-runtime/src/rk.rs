//! The explicit Runge-Kutta method of Co-Simulation, stepped by our own loop: Tsitouras 5(4)
//! with its free 4th-order continuous extension (the coefficients of diffsol's
//! `Tableau::tsit45`, read from diffsol), an integral step-size controller and diffsol's error
//! norm. Everything it carries from one step to the next — the last accepted step's ends and
//! stages (its dense output), and the next step size — is plain data here, so that an FMU state
//! can save it and a restored instance continue bit for bit from it, also in the middle of a
//! step that reaches past the communication point (diffsol keeps its dense output private).
//!
//! Activities (chapter eq. 3.3, A = integral of |p| dt) are integrated as quadratures: the
//! right-hand side gives their signed power p, which is smooth where |p| has a kink at every
//! sign change; the stepper keeps them out of its error norm (their step is the physical
//! states'), and an accepted step adds the total variation of the continuous extension's
//! integral of p, split at the zeros of p inside the step ([`Tsit::with_quadratures`]). So an
//! activity is as accurate as the states it is computed from, adds no kink error, and does not
//! change a single bit of the physical states' steps.
//!
//! No heap allocation after [`Tsit::new`].

use diffsol::Tableau;

/// Whether [`combine`] skips the terms of zero weight (as the stages' arguments always did: a
/// zero weight then leaves even an infinite stage value out) or adds them (the error estimate).
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Zeros {
    Skipped,
    Added,
}

/// States combined per block in [`combine`]: eight SSE2 registers of partial sums (x86_64's
/// baseline; 16 took 9 % fewer instructions per explicit doStep than 8 on the chain of 1 999 states).
const BLOCK: usize = 16;

/// States per block where the processor has AVX: eight 256-bit registers of partial sums.
#[cfg(target_arch = "x86_64")]
const AVX_BLOCK: usize = 32;

/// [`combine`] sums block by block from this many states on, one stage at a time below: MotorFan
/// (22 states, mostly in the blocks' scalar remainder) took 0.73 us per level c doStep summed by
/// blocks against 0.67 us one stage at a time (`step_cost`, quiet machine).
const FUSED_FROM: usize = 64;

/// out = base + sum_j weights[j] k_j (base 0 where None; k_j = `stages[j n..(j + 1) n]`, n =
/// out's length), each element summed in the order j = 0, 1, ..., so bit for bit what adding
/// one stage at a time over the whole vector gives, in one pass over memory: each block of
/// states is read once from each stage and written once. From [`FUSED_FROM`] states on in AVX
/// where the processor has it (the explicit method's sums; [`combine_baseline`] for the
/// implicit method's).
pub(crate) fn combine(out: &mut [f64], base: Option<&[f64]>, weights: &[f64], stages: &[f64], zeros: Zeros) {
    #[cfg(target_arch = "x86_64")]
    if out.len() >= FUSED_FROM && crate::simd::avx() {
        // SAFETY: the processor and the operating system support AVX (checked just above).
        unsafe { combine_blocks_avx(out, base, weights, stages, zeros) };
        return;
    }
    combine_baseline(out, base, weights, stages, zeros);
}

/// [`combine`] in x86_64's baseline only, whatever the processor: the implicit method's sums.
/// Its doStep goes mostly to the band solves, one unknown after another; with its stage loops in
/// AVX as well, the stiff chain took 155.0 against 156.2 us per doStep at N = 1 000 and 3 542
/// against 3 519 us at N = 10 000 (`examples/stiff_chain.rs`, AVX and baseline alternating in one
/// process), and in-process builds of the code with and without AVX in its sums alone took
/// 3 564-3 618 against 3 418-3 457 us at N = 10 000 (issue 25, BENCHMARKS.md).
pub(crate) fn combine_baseline(out: &mut [f64], base: Option<&[f64]>, weights: &[f64], stages: &[f64], zeros: Zeros) {
    let n = out.len();
    if n < FUSED_FROM {
        // One pass per stage over a vector that stays in registers and L1 anyway.
        match base {
            Some(base) => out.copy_from_slice(base),
            None => out.fill(0.0),
        }
        for (j, &w) in weights.iter().enumerate() {
            if w == 0.0 && zeros == Zeros::Skipped {
                continue;
            }
            for (o, k) in out.iter_mut().zip(&stages[j * n..(j + 1) * n]) {
                *o += w * k;
            }
        }
        return;
    }
    combine_blocks::<BLOCK>(out, base, weights, stages, zeros);
}

/// [`combine_blocks`] compiled for AVX: a block of 32 states in eight 256-bit registers, twice
/// the states per instruction of x86_64's baseline. The same multiplications and additions in
/// the same order (AVX has no fused multiply-add), so the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn combine_blocks_avx(out: &mut [f64], base: Option<&[f64]>, weights: &[f64], stages: &[f64], zeros: Zeros) {
    combine_blocks::<AVX_BLOCK>(out, base, weights, stages, zeros);
}

/// The block-by-block sum of [`combine`], `B` states per block.
#[inline(always)]
fn combine_blocks<const B: usize>(out: &mut [f64], base: Option<&[f64]>, weights: &[f64], stages: &[f64], zeros: Zeros) {
    let n = out.len();
    let full = n - n % B;
    for start in (0..full).step_by(B) {
        let mut acc = [0.0; B];
        if let Some(base) = base {
            acc.copy_from_slice(&base[start..start + B]);
        }
        for (j, &w) in weights.iter().enumerate() {
            if w == 0.0 && zeros == Zeros::Skipped {
                continue;
            }
            let k: &[f64; B] = stages[j * n + start..j * n + start + B].try_into().expect("a block");
            for (a, kl) in acc.iter_mut().zip(k) {
                *a += w * kl;
            }
        }
        out[start..start + B].copy_from_slice(&acc);
    }
    for m in full..n {
        let mut acc = base.map_or(0.0, |b| b[m]);
        for (j, &w) in weights.iter().enumerate() {
            if w == 0.0 && zeros == Zeros::Skipped {
                continue;
            }
            acc += w * stages[j * n + m];
        }
        out[m] = acc;
    }
}

/// Stages of the method. The last one is f at the step's end (first same as last).
pub const STAGES: usize = 7;
/// Degree of the continuous extension's polynomials (in theta, without the constant).
const POLY: usize = 4;
/// diffsol's defaults: step-size factor within [0.5, 2], safety 0.9, at most 40 rejected
/// attempts per step, no step shorter than 1e-13 s.
const MIN_FACTOR: f64 = 0.5;
const MAX_FACTOR: f64 = 2.0;
const SAFETY: f64 = 0.9;
const MAX_REJECTIONS: usize = 40;
const MIN_STEP: f64 = 1e-13;

/// The last accepted step [t_start, t_end]: enough to interpolate anywhere inside it and to
/// continue after it.
#[derive(Clone, Debug, PartialEq)]
pub struct StepRecord {
    pub t_start: f64,
    pub t_end: f64,
    pub y_start: Vec<f64>,
    pub y_end: Vec<f64>,
    /// The stages' derivatives, stage i at `[i n, (i + 1) n)`; the last is f(t_end, y_end).
    pub stages: Vec<f64>,
}

/// The method's coefficients in the natural orientation.
struct Coefficients {
    a: [[f64; STAGES]; STAGES],
    c: [f64; STAGES],
    d: [f64; STAGES],
    beta: [[f64; POLY]; STAGES],
    /// -(integral gain) / (order + 1), the exponent of the squared error norm.
    exponent: f64,
}

impl Coefficients {
    fn tsit45() -> Self {
        let t = Tableau::<f64>::tsit45();
        assert_eq!(t.s(), STAGES);
        let beta_t = t.beta_t().expect("tsit45 has a continuous extension");
        assert_eq!(beta_t.nrows(), POLY);
        let mut k = Coefficients { a: [[0.0; STAGES]; STAGES], c: [0.0; STAGES], d: [0.0; STAGES], beta: [[0.0; POLY]; STAGES], exponent: 0.0 };
        for i in 0..STAGES {
            for j in 0..STAGES {
                k.a[i][j] = t.a(i, j);
            }
            k.c[i] = t.c().as_slice()[i];
            k.d[i] = t.d().as_slice()[i];
            k.beta[i].copy_from_slice(beta_t.as_col_slice(i));
        }
        // First same as last: the last stage is evaluated at the step's end, y + h sum b_j k_j.
        assert_eq!(k.c[STAGES - 1], 1.0);
        assert!((0..STAGES - 1).all(|j| k.a[STAGES - 1][j] == t.b().as_slice()[j]) && t.b().as_slice()[STAGES - 1] == 0.0);
        // diffsol's error norm is the mean of squares: its integral controller takes
        // norm^(-0.5 / (order + 1)).
        k.exponent = -0.5 / (t.order() + 1) as f64;
        k
    }
}

/// The stepper of one instance (one right-hand side, one size).
pub struct Tsit {
    n: usize,
    k: Coefficients,
    rtol: f64,
    atol: Vec<f64>,
    /// The last accepted step; before the first one after a restart only the current point is
    /// set: `t_end`, `y_end` and the last stage (f there).
    pub last: StepRecord,
    /// Whether `last` is an accepted step (its dense output is valid).
    pub has_step: bool,
    /// The size of the next step.
    pub h: f64,
    trial: Vec<f64>,
    y_stage: Vec<f64>,
    /// The error estimate's sums sum_j d_j k_j, one per state (scratch).
    error: Vec<f64>,
    /// The quadrature states (activities): their rate is a signed power, integrated as the
    /// total variation of its integral; out of the error norm.
    quadrature: Vec<bool>,
    /// How many states the error norm averages over (the others).
    n_norm: usize,
    /// Per quadrature state, over the last step: its index, the continuous extension's integral
    /// of p as S(theta) = sum_j c[j] theta^(j + 1), and the zeros of p inside (0, 1), ascending.
    quadratures: Vec<Quadrature>,
}

/// One quadrature state's integral of p over the last step, and where p changes sign in it.
#[derive(Clone, Copy, Debug, Default)]
struct Quadrature {
    state: usize,
    c: [f64; POLY],
    zeros: [f64; 3],
    n_zeros: usize,
}

impl Quadrature {
    /// S(theta), the integral of p from the step's start.
    fn integral(&self, x: f64) -> f64 {
        self.c.iter().rev().fold(0.0, |acc, cj| (acc + cj) * x)
    }

    /// p(theta) (per unit of theta: dS/dtheta).
    fn rate(&self, x: f64) -> f64 {
        self.c.iter().enumerate().rev().fold(0.0, |acc, (j, cj)| acc * x + (j + 1) as f64 * cj)
    }

    /// The integral of |p| over [0, theta]: the total variation of S, split at the zeros.
    fn variation(&self, theta: f64) -> f64 {
        let (mut total, mut from) = (0.0, 0.0);
        for &z in &self.zeros[..self.n_zeros] {
            if z >= theta {
                break;
            }
            total += (self.integral(z) - self.integral(from)).abs();
            from = z;
        }
        total + (self.integral(theta) - self.integral(from)).abs()
    }

    /// The zeros of p inside (0, 1): p is monotone between the zeros of its derivative
    /// 2 c1 + 6 c2 x + 12 c3 x^2; a piece whose ends differ in sign holds one, found by bisection
    /// to rounding. The stages' signs alone do not tell: a lobe of p of the other sign can fit
    /// between two stages (RlcCircuit's source power, u i, between the zeros of u and of i).
    fn find_zeros(&mut self) {
        self.n_zeros = 0;
        if self.c.iter().all(|c| *c == 0.0) {
            return;
        }
        let mut cuts = [0.0, 1.0, 1.0, 1.0];
        let mut k = 1;
        let (a, b, cc) = (12.0 * self.c[3], 6.0 * self.c[2], 2.0 * self.c[1]);
        let mut critical = |x: f64| {
            if x > 0.0 && x < 1.0 {
                cuts[k] = x;
                k += 1;
            }
        };
        if a == 0.0 {
            if b != 0.0 {
                critical(-cc / b);
            }
        } else {
            let disc = b * b - 4.0 * a * cc;
            if disc >= 0.0 {
                let q = -0.5 * (b + b.signum() * disc.sqrt());
                critical(q / a);
                if q != 0.0 {
                    critical(cc / q);
                }
            }
        }
        if k == 3 && cuts[1] > cuts[2] {
            cuts.swap(1, 2);
        }
        let mut p_lo = self.rate(0.0);
        for w in 1..=k {
            let (mut lo, mut hi) = (cuts[w - 1], cuts[w]);
            let p_hi = self.rate(hi);
            if (p_lo < 0.0 && p_hi > 0.0) || (p_lo > 0.0 && p_hi < 0.0) {
                let negative_at_lo = p_lo < 0.0;
                for _ in 0..64 {
                    let mid = 0.5 * (lo + hi);
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    if (self.rate(mid) < 0.0) == negative_at_lo {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                self.zeros[self.n_zeros] = lo;
                self.n_zeros += 1;
            }
            p_lo = p_hi;
        }
    }
}

impl Tsit {
    pub fn new(n: usize, rtol: f64, atol: &[f64]) -> Self {
        Tsit {
            n,
            k: Coefficients::tsit45(),
            rtol,
            atol: atol.to_vec(),
            last: StepRecord { t_start: 0.0, t_end: 0.0, y_start: vec![0.0; n], y_end: vec![0.0; n], stages: vec![0.0; STAGES * n] },
            has_step: false,
            h: 0.0,
            trial: vec![0.0; STAGES * n],
            y_stage: vec![0.0; n],
            error: vec![0.0; n],
            quadrature: vec![false; n],
            n_norm: n,
            quadratures: Vec::new(),
        }
    }

    /// Marks the states `quadratures` (indices) as quadratures of a signed rate p whose
    /// absolute value is integrated: the state advances by the integral of |p| over each step,
    /// computed from the stages of p, and is left out of the error norm.
    pub fn with_quadratures(mut self, quadratures: &[usize]) -> Self {
        for &q in quadratures {
            self.quadrature[q] = true;
        }
        self.n_norm = self.quadrature.iter().filter(|q| !**q).count();
        self.quadratures = (0..self.n).filter(|&m| self.quadrature[m]).map(|state| Quadrature { state, ..Quadrature::default() }).collect();
        self
    }

    /// Each quadrature's integral of p and the zeros of p over the last step (from its stages).
    fn prepare_quadratures(&mut self) {
        let (n, r) = (self.n, &self.last);
        let dt = r.t_end - r.t_start;
        for q in &mut self.quadratures {
            q.c = [0.0; POLY];
            for (i, beta) in self.k.beta.iter().enumerate() {
                let k = r.stages[i * n + q.state];
                if k != 0.0 {
                    for (cj, b) in q.c.iter_mut().zip(beta) {
                        *cj += dt * b * k;
                    }
                }
            }
            q.find_zeros();
        }
    }

    /// Starts afresh at (t, y) with f(t, y) = `dy` and step size `h`: no step to interpolate in.
    pub fn restart(&mut self, t: f64, y: &[f64], rhs: impl FnOnce(&[f64], f64, &mut [f64]), h: f64) {
        let n = self.n;
        self.last.t_start = t;
        self.last.t_end = t;
        self.last.y_start.copy_from_slice(y);
        self.last.y_end.copy_from_slice(y);
        rhs(y, t, &mut self.last.stages[(STAGES - 1) * n..]);
        self.has_step = false;
        self.h = h;
    }

    /// Continues from a saved step (its end is the current point) with step size `h`.
    pub fn resume(&mut self, record: &StepRecord, h: f64) {
        self.last.clone_from(record);
        self.has_step = true;
        self.h = h;
        self.prepare_quadratures();
    }

    /// f at the current point (the end of the last step).
    pub fn current_derivative(&self) -> &[f64] {
        &self.last.stages[(STAGES - 1) * self.n..]
    }

    /// Takes one accepted step from the current point, not past `limit` (a step that would end
    /// within rounding of it, or beyond, ends exactly at it). On error the stepper is unchanged.
    pub fn step(&mut self, limit: f64, rhs: &mut impl FnMut(&[f64], f64, &mut [f64])) -> Result<(), String> {
        let n = self.n;
        let t = self.last.t_end;
        let remaining = limit - t;
        if limit.is_finite() && remaining > 0.0 && remaining <= crate::integrate::negligible_interval(limit) {
            // Within rounding of the limit (where the equations may jump: a time event), no
            // error estimate can be trusted: one explicit Euler step, exact to O(remaining^2),
            // every stage but the last (f at the limit) the derivative here. The step size is kept.
            let (y, trial, y_stage) = (&self.last.y_end, &mut self.trial, &mut self.y_stage);
            let f0 = &self.last.stages[(STAGES - 1) * n..];
            for i in 0..STAGES - 1 {
                trial[i * n..(i + 1) * n].copy_from_slice(f0);
            }
            for ((ys, yi), fi) in y_stage.iter_mut().zip(y).zip(f0) {
                *ys = yi + remaining * fi;
            }
            rhs(y_stage, limit, &mut trial[(STAGES - 1) * n..]);
            self.accept(t, limit);
            return Ok(());
        }
        let mut h = self.h;
        let mut rejections = 0;
        loop {
            let mut t_new = t + h;
            // A step passing the limit ends at it; so does one ending within rounding of it, on
            // the first attempt only: stretched again after a rejection, a step could never
            // shrink below that rounding (the equations may jump at the limit: a time event).
            let stretch = rejections == 0 && t_new >= limit - crate::integrate::negligible_interval(limit);
            if limit.is_finite() && (t_new >= limit || stretch) {
                h = limit - t;
                t_new = limit;
            }
            if !(h > 0.0) {
                return Err(format!("no step possible at t = {t} s (step size {h} s, limit {limit} s)"));
            }
            let (y, trial, y_stage, k) = (&self.last.y_end, &mut self.trial, &mut self.y_stage, &self.k);
            trial[..n].copy_from_slice(&self.last.stages[(STAGES - 1) * n..]);
            for i in 1..STAGES {
                let mut w = [0.0; STAGES];
                for (wj, a) in w.iter_mut().zip(&k.a[i][..i]) {
                    *wj = h * a;
                }
                let (done, next) = trial.split_at_mut(i * n);
                combine(y_stage, Some(y), &w[..i], done, Zeros::Skipped);
                let ti = if k.c[i] == 1.0 { t_new } else { t + k.c[i] * h };
                rhs(y_stage, ti, &mut next[..n]);
            }
            // The error estimate h sum d_j k_j, in diffsol's norm: the mean of squares of each
            // component over rtol |y| + atol at the step's start (the sums sum_j d_j k_j into
            // `error`, a stage's worth of scratch, then the norm: [`error_sum_of_squares`]).
            let error = &mut self.error;
            combine(error, None, &k.d, trial, Zeros::Added);
            let norm = error_sum_of_squares(h, self.rtol, error, y, &self.atol, &self.quadrature);
            let norm = norm / self.n_norm.max(1) as f64;
            let factor = if norm.is_finite() { (SAFETY * norm.powf(k.exponent)).clamp(MIN_FACTOR, MAX_FACTOR) } else { MIN_FACTOR };
            if norm < 1.0 {
                // y_stage holds the last stage's argument: y + h sum b_j k_j, the new state.
                self.accept(t, t_new);
                self.h = h * factor;
                return Ok(());
            }
            h *= factor;
            rejections += 1;
            if rejections >= MAX_REJECTIONS {
                return Err(format!("{rejections} rejected step attempts at t = {t} s"));
            }
            if h.abs() < MIN_STEP {
                return Err(format!("the step size fell below {MIN_STEP} s at t = {t} s"));
            }
        }
    }

    /// Makes the attempt in `trial` and `y_stage` (its new state) the last step, [t, t_new].
    fn accept(&mut self, t: f64, t_new: f64) {
        // The new state is the last stage's argument, y_stage, whose old contents no one reads:
        // every step writes it whole before its first use.
        std::mem::swap(&mut self.last.y_start, &mut self.last.y_end);
        std::mem::swap(&mut self.last.y_end, &mut self.y_stage);
        std::mem::swap(&mut self.last.stages, &mut self.trial);
        self.last.t_start = t;
        self.last.t_end = t_new;
        self.has_step = true;
        self.prepare_quadratures();
        for q in &self.quadratures {
            self.last.y_end[q.state] = self.last.y_start[q.state] + q.variation(1.0);
        }
    }

    /// The state at `t` within the last step, from its continuous extension (the step's ends
    /// exactly at its ends).
    pub fn interpolate(&self, t: f64, out: &mut [f64]) {
        let r = &self.last;
        if t == r.t_end {
            out.copy_from_slice(&r.y_end);
            return;
        }
        if t == r.t_start {
            out.copy_from_slice(&r.y_start);
            return;
        }
        let dt = r.t_end - r.t_start;
        let theta = (t - r.t_start) / dt;
        let mut weights = [0.0; STAGES];
        for (w, beta) in weights.iter_mut().zip(&self.k.beta) {
            let mut sum = 0.0;
            let mut power = theta;
            for b in beta {
                sum += b * power;
                power *= theta;
            }
            *w = dt * sum;
        }
        combine(out, Some(&r.y_start), &weights, &r.stages, Zeros::Skipped);
        for q in &self.quadratures {
            out[q.state] = r.y_start[q.state] + q.variation(theta);
        }
    }
}

/// The sum of the squares of `term(m, v[m])`, in four interleaved partial sums added pairwise at
/// the end: one running sum makes each term wait for the addition before it (at 1 999 states that
/// chain was 15 % of the stiff chain's doStep). The implicit method's norms; the explicit one
/// keeps its running sum ([`Tsit::step`]). Deterministic: the same order for the same length.
#[inline(always)]
pub(crate) fn sum_of_squares(v: &[f64], term: impl Fn(usize, f64) -> f64) -> f64 {
    let mut partial = [0.0; 4];
    let whole = v.len() / 4 * 4;
    for (c, chunk) in v[..whole].chunks_exact(4).enumerate() {
        for (i, (p, x)) in partial.iter_mut().zip(chunk).enumerate() {
            let e = term(4 * c + i, *x);
            *p += e * e;
        }
    }
    for (i, x) in v[whole..].iter().enumerate() {
        let e = term(whole + i, *x);
        partial[i] += e * e;
    }
    (partial[0] + partial[1]) + (partial[2] + partial[3])
}

/// The sum over the states (quadratures left out) of (h e_m / (rtol |y_m| + atol_m))^2, the
/// explicit method's squared error norm before its mean.
///
/// Below [`FUSED_FROM`] states one running sum in the states' order, as the chapter's FMUs have
/// always been summed: SteeringColumn's activity at rtol 1e-6 (a quadrature, outside the error
/// control) sits at 9.3e-6 of its range against the accuracy test's bound of 1e-5, and four
/// partial sums moved it to 1.07e-5 (issue 25, BENCHMARKS.md). From [`FUSED_FROM`] states on,
/// the four partial sums of [`sum_of_squares`] (the implicit method's), with the divisions in
/// vector registers (AVX where the processor has it: the same bits as without): one running sum
/// makes each term wait for the addition before it.
fn error_sum_of_squares(h: f64, rtol: f64, error: &[f64], y: &[f64], atol: &[f64], quadrature: &[bool]) -> f64 {
    let n = error.len();
    if n < FUSED_FROM {
        let mut sum = 0.0;
        for m in 0..n {
            if quadrature[m] {
                continue;
            }
            let term = (h * error[m]) / (y[m].abs() * rtol + atol[m]);
            sum += term * term;
        }
        return sum;
    }
    #[cfg(target_arch = "x86_64")]
    if crate::simd::avx() {
        // SAFETY: the processor and the operating system support AVX (checked just above).
        return unsafe { error_sum_of_squares_avx(h, rtol, error, y, atol, quadrature) };
    }
    error_sum_in_four(h, rtol, error, y, atol, quadrature)
}

/// [`error_sum_in_four`] compiled for AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn error_sum_of_squares_avx(h: f64, rtol: f64, error: &[f64], y: &[f64], atol: &[f64], quadrature: &[bool]) -> f64 {
    error_sum_in_four(h, rtol, error, y, atol, quadrature)
}

/// The error's sum of squares in the four partial sums of [`sum_of_squares`] (the same order);
/// a quadrature adds 0. Written four states at a time, so that the divisions go in one vector
/// instruction.
#[inline(always)]
fn error_sum_in_four(h: f64, rtol: f64, error: &[f64], y: &[f64], atol: &[f64], quadrature: &[bool]) -> f64 {
    let n = error.len();
    let whole = n / 4 * 4;
    let (y, atol, quadrature) = (&y[..n], &atol[..n], &quadrature[..n]);
    let square = |m: usize| {
        let term = (h * error[m]) / (y[m].abs() * rtol + atol[m]);
        if quadrature[m] {
            0.0
        } else {
            term * term
        }
    };
    let mut partial = [0.0; 4];
    for (((e, yc), ac), qc) in error[..whole].chunks_exact(4).zip(y[..whole].chunks_exact(4)).zip(atol[..whole].chunks_exact(4)).zip(quadrature[..whole].chunks_exact(4)) {
        let mut terms = [0.0; 4];
        for i in 0..4 {
            terms[i] = (h * e[i]) / (yc[i].abs() * rtol + ac[i]);
        }
        for i in 0..4 {
            partial[i] += if qc[i] { 0.0 } else { terms[i] * terms[i] };
        }
    }
    for m in whole..n {
        partial[m - whole] += square(m);
    }
    (partial[0] + partial[1]) + (partial[2] + partial[3])
}

/// Whether `a` and `b` hold the same numbers bit for bit (a NaN equal to itself, 0 not to -0),
/// without an early exit, so that it compiles to vector compares.
pub(crate) fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0u64, |differ, (x, y)| differ | (x.to_bits() ^ y.to_bits())) == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bit for bit: a NaN equals itself, 0 does not equal -0, lengths must agree.
    #[test]
    fn same_bits_compares_the_bits() {
        assert!(same_bits(&[1.0, f64::NAN, -0.0], &[1.0, f64::NAN, -0.0]));
        assert!(!same_bits(&[1.0, 0.0], &[1.0, -0.0]));
        assert!(!same_bits(&[1.0, 2.0], &[1.0, 2.0 + f64::EPSILON * 2.0]));
        assert!(!same_bits(&[1.0], &[1.0, 1.0]));
        assert!(same_bits(&[], &[]));
    }

    /// The sum one stage at a time over the whole vector, the order [`combine`] promises.
    fn combine_one_stage_at_a_time(base: Option<&[f64]>, weights: &[f64], stages: &[f64], zeros: Zeros, n: usize) -> Vec<f64> {
        let mut out = base.map_or(vec![0.0; n], |b| b.to_vec());
        for (j, &w) in weights.iter().enumerate() {
            if w == 0.0 && zeros == Zeros::Skipped {
                continue;
            }
            for (o, k) in out.iter_mut().zip(&stages[j * n..(j + 1) * n]) {
                *o += w * k;
            }
        }
        out
    }

    /// Every way of summing (one stage at a time, blocks of 16, AVX's blocks of 32 where the
    /// processor has it) gives the bits of one stage at a time, at every size around the blocks'
    /// edges. The numbers span 30 orders of magnitude, so that any other order of the additions
    /// (or a fused multiply-add) rounds differently; a zero weight leaves an infinite stage out
    /// when zeros are skipped.
    #[test]
    fn combine_gives_the_bits_of_one_stage_at_a_time() {
        let weights = [0.31, -1.7e-3, 0.0, 2.9e5, -0.77, 1.3e-9, 0.11];
        let value = |i: usize| ((i * 7919 % 1013) as f64 - 506.0) * 10f64.powi((i % 31) as i32 - 15) / 3.0;
        for n in [0, 1, 15, 16, 17, 31, 32, 33, 63, 64, 65, 95, 96, 97, 1000, 1999] {
            let mut stages: Vec<f64> = (0..7 * n).map(value).collect();
            if n > 0 {
                stages[2 * n + n / 2] = f64::INFINITY; // in the stage of zero weight
            }
            let base: Vec<f64> = (0..n).map(|i| value(i + 99_991)).collect();
            for zeros in [Zeros::Skipped, Zeros::Added] {
                for base in [Some(&base[..]), None] {
                    let expected = combine_one_stage_at_a_time(base, &weights, &stages, zeros, n);
                    let mut out = vec![f64::NAN; n];
                    combine(&mut out, base, &weights, &stages, zeros);
                    assert!(same_bits(&out, &expected), "combine, n = {n}");
                    combine_blocks::<BLOCK>(&mut out, base, &weights, &stages, zeros);
                    assert!(same_bits(&out, &expected), "blocks of {BLOCK}, n = {n}");
                    #[cfg(target_arch = "x86_64")]
                    if std::arch::is_x86_feature_detected!("avx") {
                        // SAFETY: the processor has AVX.
                        unsafe { combine_blocks_avx(&mut out, base, &weights, &stages, zeros) };
                        assert!(same_bits(&out, &expected), "AVX blocks, n = {n}");
                    }
                }
            }
        }
    }

    /// The explicit norm's sum: exact on integers at every size (quadratures left out even where
    /// their term is not finite), and from 64 states on the same bits with AVX as without.
    #[test]
    fn the_explicit_error_sum_leaves_quadratures_out_and_is_the_same_with_avx() {
        for n in [1, 5, 63, 64, 65, 66, 67, 1000, 1999] {
            // h = 1, rtol 0, atol 1: each term is the error itself, an integer.
            let error: Vec<f64> = (0..n).map(|m| (m % 17) as f64 - 8.0).collect();
            let quadrature: Vec<bool> = (0..n).map(|m| m % 5 == 3).collect();
            let mut with_infinite = error.clone();
            for (e, q) in with_infinite.iter_mut().zip(&quadrature) {
                if *q {
                    *e = f64::INFINITY;
                }
            }
            let exact: f64 = error.iter().zip(&quadrature).filter(|(_, q)| !**q).map(|(e, _)| e * e).sum();
            let (y, atol) = (vec![3.0; n], vec![1.0; n]);
            assert_eq!(error_sum_of_squares(1.0, 0.0, &with_infinite, &y, &atol, &quadrature), exact, "n = {n}");
            // Numbers whose sum rounds: AVX and the baseline agree bit for bit.
            let error: Vec<f64> = (0..n).map(|m| ((m * 7919 % 1013) as f64 - 506.0) * 10f64.powi((m % 23) as i32 - 11)).collect();
            let y: Vec<f64> = (0..n).map(|m| (m as f64 * 0.37).sin() * 50.0).collect();
            let atol: Vec<f64> = (0..n).map(|m| 1e-9 * (1.0 + (m % 3) as f64)).collect();
            let baseline = error_sum_in_four(1e-3, 1e-8, &error, &y, &atol, &quadrature);
            if n >= FUSED_FROM {
                assert_eq!(error_sum_of_squares(1e-3, 1e-8, &error, &y, &atol, &quadrature).to_bits(), baseline.to_bits(), "n = {n}");
            }
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx") {
                // SAFETY: the processor has AVX.
                let avx = unsafe { error_sum_of_squares_avx(1e-3, 1e-8, &error, &y, &atol, &quadrature) };
                assert_eq!(avx.to_bits(), baseline.to_bits(), "n = {n}");
            }
        }
    }

    /// Integers: every partial sum is exact, so any order gives the exact sum of squares
    /// (lengths 0 to 9 cover the remainders of the four partial sums).
    #[test]
    fn sum_of_squares_is_the_exact_sum_on_integers() {
        for len in 0..10 {
            let v: Vec<f64> = (0..len).map(|m| m as f64 - 3.0).collect();
            let exact: f64 = (0..len).map(|m| ((m as f64 - 3.0) * 2.0).powi(2)).sum();
            assert_eq!(sum_of_squares(&v, |_, x| 2.0 * x), exact, "length {len}");
        }
    }

    fn oscillator(y: &[f64], _t: f64, dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = -y[0];
    }

    #[test]
    fn steps_and_interpolates_a_harmonic_oscillator() {
        let rtol = 1e-9;
        let mut s = Tsit::new(2, rtol, &[1e-12, 1e-12]);
        s.restart(0.0, &[1.0, 0.0], oscillator, 1e-3);
        let mut rhs = oscillator;
        let mut y = [0.0; 2];
        let mut steps = 0;
        while s.last.t_end < 10.0 {
            s.step(10.0, &mut rhs).unwrap();
            steps += 1;
            let (a, b) = (s.last.t_start, s.last.t_end);
            for q in 1..4 {
                let t = a + (b - a) * q as f64 / 4.0;
                s.interpolate(t, &mut y);
                assert!((y[0] - t.cos()).abs() < 1e-7 && (y[1] + t.sin()).abs() < 1e-7, "at {t}: {y:?}");
            }
        }
        assert_eq!(s.last.t_end, 10.0, "the last step ends exactly at the limit");
        assert!((s.last.y_end[0] - 10f64.cos()).abs() < 1e-7);
        assert!(steps < 400, "{steps} steps: the step size grows");
    }

    /// The oscillator with a third state, the activity of p = y1 = -sin t: its rate is the
    /// signed p, integrated as a quadrature of |p|.
    fn oscillator_with_activity(y: &[f64], t: f64, dy: &mut [f64]) {
        oscillator(&y[..2], t, &mut dy[..2]);
        dy[2] = y[1];
    }

    /// The integral of |sin t| from 0 to t, in closed form: |cos a - cos b| summed over the
    /// pieces between the zeros k pi.
    fn activity_of_sine(t: f64) -> f64 {
        let (mut total, mut a) = (0.0, 0.0);
        while a < t {
            let b = (a + std::f64::consts::PI).min(t);
            total += (a.cos() - b.cos()).abs();
            a += std::f64::consts::PI;
        }
        total
    }

    #[test]
    fn an_activity_is_the_integral_of_the_absolute_power_and_leaves_the_states_bit_for_bit() {
        let rtol = 1e-9;
        let mut plain = Tsit::new(2, rtol, &[1e-12, 1e-12]);
        let mut with = Tsit::new(3, rtol, &[1e-12, 1e-12, 1e-12]).with_quadratures(&[2]);
        plain.restart(0.0, &[1.0, 0.0], oscillator, 1e-3);
        with.restart(0.0, &[1.0, 0.0, 0.0], oscillator_with_activity, 1e-3);
        let (mut rhs, mut rhs3) = (oscillator, oscillator_with_activity);
        let mut y = [0.0; 3];
        let mut worst = 0.0f64;
        while with.last.t_end < 20.0 {
            plain.step(20.0, &mut rhs).unwrap();
            with.step(20.0, &mut rhs3).unwrap();
            assert_eq!((plain.last.t_end.to_bits(), plain.h.to_bits()), (with.last.t_end.to_bits(), with.h.to_bits()));
            assert_eq!(plain.last.y_end[..], with.last.y_end[..2], "the activity changes no bit of the states");
            let (a, b) = (with.last.t_start, with.last.t_end);
            for q in 1..=4 {
                let t = a + (b - a) * q as f64 / 4.0;
                with.interpolate(t, &mut y);
                worst = worst.max((y[2] - activity_of_sine(t)).abs());
            }
        }
        // 6 zeros of sin in 20 s: each a kink of |p|, located inside its step.
        eprintln!("activity of sin over 20 s at rtol 1e-9: worst error {worst:e}");
        assert!(worst < 1e-8, "activity off by {worst:e} (exact {})", activity_of_sine(20.0));
    }

    #[test]
    fn an_activity_rate_that_changes_sign_inside_one_step_is_split_at_its_zero() {
        // One step over [0, 1] of p = t - 0.3 (y' = p): |p| integrates to 0.3^2/2 + 0.7^2/2 = 0.29,
        // where the integral of p is 0.2 (to the rounding of the tableau's coefficients, 1.6e-14).
        let mut s = Tsit::new(1, 1e-6, &[1.0]).with_quadratures(&[0]);
        let mut rhs = |_: &[f64], t: f64, dy: &mut [f64]| dy[0] = t - 0.3;
        s.restart(0.0, &[0.0], |_: &[f64], t: f64, dy: &mut [f64]| dy[0] = t - 0.3, 1.0);
        s.step(1.0, &mut rhs).unwrap();
        assert_eq!(s.last.t_end, 1.0, "one step");
        assert!((s.last.y_end[0] - 0.29).abs() < 1e-13, "{}", s.last.y_end[0]);
        let mut y = [0.0];
        s.interpolate(0.5, &mut y);
        assert!((y[0] - (0.045 + 0.02)).abs() < 1e-13, "{}", y[0]);
        s.interpolate(0.2, &mut y);
        assert!((y[0] - (0.3 * 0.3 - 0.1 * 0.1) / 2.0).abs() < 1e-13, "{}", y[0]);
    }

    #[test]
    fn a_lobe_of_the_other_sign_between_two_stages_is_counted() {
        // p = (t - 0.45)(t - 0.55) over one step [0, 1]: every stage (c = 0, 0.161, 0.327, 0.9,
        // 0.98, 1) sees p > 0; the lobe between 0.45 and 0.55 is negative, of area 0.1^3 / 6.
        // Integral of |p| = integral of p + 2 x lobe = (1/3 - 1/2 + 0.2475) + 0.1^3 / 3.
        let p = |t: f64| (t - 0.45) * (t - 0.55);
        let mut s = Tsit::new(1, 1e-6, &[1.0]).with_quadratures(&[0]);
        let mut rhs = |_: &[f64], t: f64, dy: &mut [f64]| dy[0] = p(t);
        s.restart(0.0, &[0.0], |_: &[f64], t: f64, dy: &mut [f64]| dy[0] = p(t), 1.0);
        s.step(1.0, &mut rhs).unwrap();
        assert_eq!(s.last.t_end, 1.0, "one step");
        let exact = (1.0 / 3.0 - 0.5 + 0.2475) + 1e-3 / 3.0;
        assert!((s.last.y_end[0] - exact).abs() < 1e-13, "{} against {exact}", s.last.y_end[0]);
        let mut y = [0.0];
        s.interpolate(0.5, &mut y);
        let before = 0.125 / 3.0 - 0.125 + 0.2475 * 0.5; // integral of p over [0, 0.5]
        let lobe_half = 1e-3 / 12.0; // |integral of p| over [0.45, 0.5]
        assert!((y[0] - (before + 2.0 * lobe_half)).abs() < 1e-13, "{} against {}", y[0], before + 2.0 * lobe_half);
    }

    #[test]
    fn a_jump_of_the_equations_at_the_limit_is_approached_not_looped_on() {
        // y' = 0 before 1 s, 1e6 after: the last stages of a step ending at the limit see the
        // jump; the stepper shrinks its steps towards the limit and reaches it.
        let mut rhs = |_: &[f64], t: f64, dy: &mut [f64]| dy[0] = if t >= 1.0 { 1e6 } else { 0.0 };
        let mut s = Tsit::new(1, 1e-8, &[1e-11]);
        s.restart(0.0, &[0.0], |_: &[f64], _: f64, dy: &mut [f64]| dy[0] = 0.0, 0.1);
        let mut steps = 0;
        while s.last.t_end < 1.0 {
            s.step(1.0, &mut rhs).unwrap();
            steps += 1;
            assert!(steps < 1000);
        }
        assert_eq!(s.last.t_end, 1.0);
        assert!(s.last.y_end[0].abs() < 1e-3, "{}", s.last.y_end[0]);
    }

    #[test]
    fn a_resumed_record_steps_bit_for_bit_as_the_original() {
        let mut s = Tsit::new(2, 1e-7, &[1e-10, 1e-10]);
        s.restart(0.0, &[1.0, 0.0], oscillator, 1e-2);
        let mut rhs = oscillator;
        for _ in 0..5 {
            s.step(f64::INFINITY, &mut rhs).unwrap();
        }
        let mut twin = Tsit::new(2, 1e-7, &[1e-10, 1e-10]);
        twin.resume(&s.last.clone(), s.h);
        for _ in 0..5 {
            s.step(f64::INFINITY, &mut rhs).unwrap();
            twin.step(f64::INFINITY, &mut rhs).unwrap();
            assert_eq!(s.last, twin.last);
            assert_eq!(s.h.to_bits(), twin.h.to_bits());
        }
    }
}
