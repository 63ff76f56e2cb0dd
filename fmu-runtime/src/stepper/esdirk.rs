//! The tableaus of the implicit method ([`super::implicit`]): explicit first stage, one diagonal
//! gamma, stiffly accurate (the last stage is the step's end, at c = 1), L-stable, with an
//! embedded method for the error estimate.

#[cfg(test)]
use diffsol::Tableau as DiffsolTableau;

/// The most stages a tableau here has.
pub const MAX_STAGES: usize = 7;

/// An ESDIRK tableau in the natural orientation (stage i at row i, 0-based; row 0 is zero).
#[derive(Clone, Debug)]
pub struct Tableau {
    /// Its name in messages and the documentation.
    pub name: &'static str,
    pub stages: usize,
    /// The method's order (diffsol's first-step heuristic is given it).
    pub order: usize,
    /// The embedded method's order: the error estimate is of order h^(embedded_order + 1), and
    /// the step-size controller takes norm^(-1 / (embedded_order + 1)).
    pub embedded_order: usize,
    pub gamma: f64,
    pub a: [[f64; MAX_STAGES]; MAX_STAGES],
    pub c: [f64; MAX_STAGES],
    /// The weights: the last row of `a` (stiffly accurate).
    pub b: [f64; MAX_STAGES],
    /// b - b_hat: the error estimate's weights.
    pub d: [f64; MAX_STAGES],
    /// The dense output ([`Self::dense_weights`]): stage j's weight at theta is
    /// sum_q dense[j][q] theta^(q + 1). Made by [`Self::checked`].
    pub dense: [[f64; DENSE_DEGREE]; MAX_STAGES],
    /// The dense output's order (its error over a step is of order h^(dense_order + 1)).
    pub dense_order: usize,
}

/// The degree of the dense output's weights in theta.
pub const DENSE_DEGREE: usize = 5;

/// Solves the small symmetric positive definite system m x = rhs (Gaussian elimination with
/// partial pivoting), r unknowns.
fn solve_small(mut m: [[f64; 6]; 6], mut rhs: [f64; 6], r: usize) -> [f64; 6] {
    for col in 0..r {
        let p = (col..r).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs())).expect("a row");
        m.swap(col, p);
        rhs.swap(col, p);
        let pivot = m[col];
        for row in col + 1..r {
            let f = m[row][col] / pivot[col];
            for (x, p) in m[row][col..r].iter_mut().zip(&pivot[col..r]) {
                *x -= f * p;
            }
            rhs[row] -= f * rhs[col];
        }
    }
    let mut x = [0.0; 6];
    for row in (0..r).rev() {
        let tail: f64 = (row + 1..r).map(|k| m[row][k] * x[k]).sum();
        x[row] = (rhs[row] - tail) / m[row][row];
    }
    x
}

impl Tableau {
    /// Checks the shape every tableau here has: an explicit first stage at c = 0, one diagonal
    /// gamma, c the row sums, stiffly accurate with its last stage at c = 1.
    fn checked(self) -> Self {
        let s = self.stages;
        assert!((2..=MAX_STAGES).contains(&s));
        assert!(self.c[0] == 0.0 && self.a[0].iter().all(|x| *x == 0.0));
        assert!((1..s).all(|i| self.a[i][i] == self.gamma));
        assert!((0..s).all(|i| (i + 1..MAX_STAGES).all(|j| self.a[i][j] == 0.0)));
        assert!((0..s).all(|i| (self.a[i].iter().sum::<f64>() - self.c[i]).abs() < 1e-14));
        assert!((0..s).all(|j| self.a[s - 1][j] == self.b[j]));
        assert_eq!(self.c[s - 1], 1.0);
        self.with_dense_output()
    }

    /// The stage weights b(theta) of the dense output y(t + theta h) = y + h sum_j b_j(theta) k_j,
    /// theta in [0, 1] (beyond: an extrapolation).
    pub fn dense_weights(&self, theta: f64) -> [f64; MAX_STAGES] {
        let mut w = [0.0; MAX_STAGES];
        for (wj, beta) in w.iter_mut().zip(&self.dense).take(self.stages) {
            // Horner: theta (beta_0 + theta (beta_1 + ...)).
            *wj = theta * beta.iter().rev().fold(0.0, |acc, b| acc * theta + b);
        }
        w
    }

    /// The dense output: weights b(theta), polynomials in theta without constant term, that
    /// satisfy the order conditions of order up to min(order - 1, 4) at every theta
    /// (sum_j b_j(theta) phi_j(tree) = theta^|tree| / gamma(tree)), keep the stability function
    /// bounded at infinity (b(theta) . u = 0, u the [`limit_at_infinity`](Self::limit_at_infinity):
    /// a stiff component is not amplified between the step's ends) and end at the method's
    /// weights, b(1) = b. With stage order 2 (checked) the conditions of order 4 are four
    /// (1, c, c^2 and c^3 being of the bushy trees, A c^2 of the one left; the others follow), so
    /// with u there are at most six on seven stages: b(theta) = C+ g(theta) + theta^5 (b - C+ g(1)),
    /// C the conditions' rows, C+ its pseudo-inverse (the least-norm weights) and g(theta) their
    /// values; b - C+ g(1) lies in C's null space because b itself satisfies every condition.
    /// ESDIRK5(4)7L\[2\]SA\_2 has seven stages: a dense output of order 4, the error estimate's.
    fn with_dense_output(mut self) -> Self {
        let s = self.stages;
        for i in 0..s {
            let ac: f64 = (0..s).map(|j| self.a[i][j] * self.c[j]).sum();
            assert!((ac - self.c[i] * self.c[i] / 2.0).abs() < 1e-14, "{}: stage order below 2 at stage {i}", self.name);
        }
        let order = (self.order - 1).min(4);
        assert!(order >= 2, "{}: too low an order for a dense output", self.name);
        let u = self.limit_at_infinity();
        let power = |p: i32| (0..s).map(|j| self.c[j].powi(p)).collect::<Vec<f64>>();
        // The conditions' rows and the coefficients of theta^1 ..= theta^4 in their values.
        let mut rows: Vec<(Vec<f64>, [f64; 4])> = vec![(power(0), [1.0, 0.0, 0.0, 0.0]), (power(1), [0.0, 0.5, 0.0, 0.0])];
        if order >= 3 {
            rows.push((power(2), [0.0, 0.0, 1.0 / 3.0, 0.0]));
        }
        if order >= 4 {
            rows.push((power(3), [0.0, 0.0, 0.0, 0.25]));
            let c2 = power(2);
            let ac2 = (0..s).map(|i| (0..s).map(|j| self.a[i][j] * c2[j]).sum()).collect();
            rows.push((ac2, [0.0, 0.0, 0.0, 1.0 / 12.0]));
        }
        rows.push((u[..s].to_vec(), [0.0; 4]));
        let r = rows.len();
        let mut gram = [[0.0; 6]; 6];
        for (p, (x, _)) in rows.iter().enumerate() {
            for (q, (y, _)) in rows.iter().enumerate() {
                gram[p][q] = x.iter().zip(y).map(|(a, b)| a * b).sum();
            }
        }
        let mut dense = [[0.0; DENSE_DEGREE]; MAX_STAGES];
        for q in 0..4 {
            let mut rhs = [0.0; 6];
            for (p, (_, g)) in rows.iter().enumerate() {
                rhs[p] = g[q];
            }
            let x = solve_small(gram, rhs, r);
            for (j, beta) in dense.iter_mut().enumerate().take(s) {
                beta[q] = (0..r).map(|p| rows[p].0[j] * x[p]).sum();
            }
        }
        for (j, beta) in dense.iter_mut().enumerate().take(s) {
            beta[4] = self.b[j] - beta[..4].iter().sum::<f64>();
        }
        self.dense = dense;
        self.dense_order = order;
        self
    }

    /// The limit u of (I - z A)^-1 (1, ..., 1) as z -> -infinity: u_0 = 1,
    /// u_i = -(sum_{j < i} a_ij u_j) / gamma. A stiffly accurate method's stability function
    /// at infinity is u's last entry; an embedded method b_hat's stays bounded there when
    /// b_hat . u = 0.
    pub fn limit_at_infinity(&self) -> [f64; MAX_STAGES] {
        let mut u = [0.0; MAX_STAGES];
        u[0] = 1.0;
        for i in 1..self.stages {
            u[i] = -(0..i).map(|j| self.a[i][j] * u[j]).sum::<f64>() / self.gamma;
        }
        u
    }

    /// ESDIRK3(2): the four stages of diffsol's `Tableau::esdirk34` (L-stable, stiffly
    /// accurate, third order) with an embedded L-stable second-order method of our own
    /// (`second_order_estimate`) in place of diffsol's. The implicit method's until it
    /// became [`Self::esdirk547`]; kept for its tests and to compare against.
    #[cfg(test)]
    pub fn esdirk32() -> Self {
        let t = DiffsolTableau::<f64>::esdirk34();
        let s = t.s();
        assert_eq!(s, 4);
        let mut k = Tableau {
            name: "ESDIRK3(2)",
            stages: s,
            order: t.order(),
            embedded_order: 2,
            gamma: t.a(1, 1),
            a: [[0.0; MAX_STAGES]; MAX_STAGES],
            c: [0.0; MAX_STAGES],
            b: [0.0; MAX_STAGES],
            d: [0.0; MAX_STAGES],
            dense: [[0.0; DENSE_DEGREE]; MAX_STAGES],
            dense_order: 0,
        };
        assert_eq!(k.order, 3);
        for i in 0..s {
            for j in 0..s {
                k.a[i][j] = t.a(i, j);
            }
            k.c[i] = t.c().as_slice()[i];
            k.b[i] = t.b().as_slice()[i];
        }
        k.d = k.second_order_estimate(ESDIRK32_ERROR_SCALE);
        k.checked()
    }

    /// The error estimate's weights d = b - b_hat of an embedded second-order method b_hat whose
    /// stability function stays bounded (and vanishes) at infinity, for diffsol's esdirk34 in
    /// place of diffsol's d.
    ///
    /// diffsol's b_hat is of order 4 but its stability function grows like |h lambda|, so its
    /// estimate of a stiff component is meaningless (the filter (I - h gamma J)^-1 only brings it
    /// back to the component's size); and where the solution's stiff components are excited (a
    /// torque step on the stiff chain) the method's local error is of order h^3 (its stages are
    /// of order 2), which an estimate of order h^4 underrates more the tighter the tolerance: the
    /// stiff chain's error was 3.4, 16 and 108 times the tolerance at rtol 1e-6, 1e-8 and 1e-11.
    /// Here d is orthogonal to (1, ..., 1), to c (b_hat is of order 2, as b is) and to the
    /// limit u of (I - z A)^-1 (1, ..., 1) as z -> -infinity (so b_hat's stability function
    /// 1 + z b_hat' (I - z A)^-1 1 stays bounded, and, as b's, vanishes there): an estimate of
    /// order h^3, `scale` times a unit vector.
    #[cfg(test)]
    fn second_order_estimate(&self, scale: f64) -> [f64; MAX_STAGES] {
        const S: usize = 4;
        assert_eq!(self.stages, S);
        let u = self.limit_at_infinity();
        let rows: [[f64; S]; 3] = [[1.0; S], [self.c[0], self.c[1], self.c[2], self.c[3]], [u[0], u[1], u[2], u[3]]];
        // The vector orthogonal to three rows of four: the signed 3 x 3 minors.
        let minor = |skip: usize| {
            let m: Vec<[f64; 3]> = rows
                .iter()
                .map(|r| {
                    let mut v = [0.0; 3];
                    let mut k = 0;
                    for (j, x) in r.iter().enumerate() {
                        if j != skip {
                            v[k] = *x;
                            k += 1;
                        }
                    }
                    v
                })
                .collect();
            m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
        };
        let mut d = [0.0; MAX_STAGES];
        for (j, dj) in d.iter_mut().take(S).enumerate() {
            *dj = if j % 2 == 0 { minor(j) } else { -minor(j) };
        }
        let norm = d.iter().map(|x| x * x).sum::<f64>().sqrt();
        d.map(|x| scale * x / norm)
    }

    /// ESDIRK4(3)6L\[2\]SA: the implicit part of Kennedy and Carpenter's additive Runge-Kutta
    /// method ARK4(3)6L\[2\]SA (C. A. Kennedy, M. H. Carpenter, "Additive Runge-Kutta schemes for
    /// convection-diffusion-reaction equations", Applied Numerical Mathematics 44 (2003)
    /// 139-181, table of ARK4(3)6L\[2\]SA): six stages (five implicit), gamma = 1/4, fourth order,
    /// stage order 2, L-stable and stiffly accurate, with an embedded third-order method whose
    /// stability function stays bounded at infinity. The published rational coefficients.
    /// Measured against [`Self::esdirk547`] on the stiff chain (issue 25): about its cost, ten
    /// times its error; kept for its tests.
    #[cfg(test)]
    pub fn esdirk436() -> Self {
        const G: f64 = 1.0 / 4.0;
        let rows: [&[f64]; 6] = [
            &[],
            &[1.0 / 4.0],
            &[8611.0 / 62500.0, -1743.0 / 31250.0],
            &[5012029.0 / 34652500.0, -654441.0 / 2922500.0, 174375.0 / 388108.0],
            &[15267082809.0 / 155376265600.0, -71443401.0 / 120774400.0, 730878875.0 / 902184768.0, 2285395.0 / 8070912.0],
            &[82889.0 / 524892.0, 0.0, 15625.0 / 83664.0, 69875.0 / 102672.0, -2260.0 / 8211.0],
        ];
        let c = [0.0, 1.0 / 2.0, 83.0 / 250.0, 31.0 / 50.0, 17.0 / 20.0, 1.0];
        let b_hat = [
            4586570599.0 / 29645900160.0,
            0.0,
            178811875.0 / 945068544.0,
            814220225.0 / 1159782912.0,
            -3700637.0 / 11593932.0,
            61727.0 / 225920.0,
        ];
        let mut k = Tableau {
            name: "ESDIRK4(3)6L[2]SA",
            stages: 6,
            order: 4,
            embedded_order: 3,
            gamma: G,
            a: [[0.0; MAX_STAGES]; MAX_STAGES],
            c: [0.0; MAX_STAGES],
            b: [0.0; MAX_STAGES],
            d: [0.0; MAX_STAGES],
            dense: [[0.0; DENSE_DEGREE]; MAX_STAGES],
            dense_order: 0,
        };
        for (i, row) in rows.iter().enumerate() {
            k.a[i][..row.len()].copy_from_slice(row);
            if i > 0 {
                k.a[i][i] = G;
            }
            k.c[i] = c[i];
        }
        k.b = k.a[5];
        for ((d, b), b_hat) in k.d.iter_mut().zip(&k.b).zip(&b_hat) {
            *d = b - b_hat;
        }
        k.checked()
    }
}

impl Tableau {
    /// ESDIRK5(4)7L\[2\]SA\_2 (C. A. Kennedy, M. H. Carpenter, "Diagonally implicit Runge-Kutta
    /// methods for stiff ODEs", Applied Numerical Mathematics 146 (2019) 221-244): seven stages
    /// (six implicit), gamma = 0.184, fifth order, stage order 2, L-stable and stiffly accurate,
    /// with an embedded fourth-order method. The published coefficients (to double precision).
    pub fn esdirk547() -> Self {
        const G: f64 = 0.184;
        let rows: [&[f64]; 7] = [
            &[],
            &[0.184],
            &[0.22210764773832475, 0.22210764773832475],
            &[-0.014049475381926283, -0.014049475381926283, -0.01709085093586415],
            &[-0.40838859254931464, -0.40838859254931464, 0.16646399821362964, 1.1662718062895745],
            &[-0.5392907235588114, -0.5392907235588114, -0.242234428845425, 1.4888806111225146, 0.5563122281913184],
            &[-0.03946606910974026, -0.03946606910974026, 0.27263649025024267, 0.4321651725202882, 0.3524160862328891, -0.16228561078393952],
        ];
        let d = [
            0.041223397456907174,
            0.041223397456907174,
            0.08973680563680714,
            -0.08484870124594279,
            -0.07418364506956521,
            -0.05795875281680454,
            0.04480749858169103,
        ];
        let mut k = Tableau {
            name: "ESDIRK5(4)7L[2]SA_2",
            stages: 7,
            order: 5,
            embedded_order: 4,
            gamma: G,
            a: [[0.0; MAX_STAGES]; MAX_STAGES],
            c: [0.0; MAX_STAGES],
            b: [0.0; MAX_STAGES],
            d,
            dense: [[0.0; DENSE_DEGREE]; MAX_STAGES],
            dense_order: 0,
        };
        for (i, row) in rows.iter().enumerate() {
            k.a[i][..row.len()].copy_from_slice(row);
            if i > 0 {
                k.a[i][i] = G;
            }
            k.c[i] = k.a[i].iter().sum();
        }
        k.c[6] = 1.0;
        k.b = k.a[6];
        k.checked()
    }
}

/// The ESDIRK3(2) error estimate's weights are this multiple of a unit vector (see
/// [`Tableau::second_order_estimate`]); measured on the stiff torsional chain (N = 10, a torque
/// step, against the matrix exponential): the largest error of any speed in the run, in units of
/// the tolerance times the largest speed, at rtol 1e-6 / 1e-8 / 1e-11: 4.6 / 5.8 / 7.4 with 0.1,
/// 1.4 / 2.1 / 2.6 with 0.3, 0.5 / 0.7 / 0.8 with 1.0 (diffsol's own weights: 3.4 / 16 / 108).
#[cfg(test)]
const ESDIRK32_ERROR_SCALE: f64 = 0.3;

#[cfg(test)]
mod tests {
    use super::*;

    /// The order conditions of a Runge-Kutta method (A, c) with weights w, for the rooted trees
    /// up to order 5: (order, the condition's value w . phi, its required value 1 / gamma(tree)).
    fn order_conditions(k: &Tableau, w: &[f64]) -> Vec<(usize, f64, f64)> {
        let s = k.stages;
        let dot = |x: &[f64], y: &[f64]| (0..s).map(|i| x[i] * y[i]).sum::<f64>();
        let times = |x: &[f64], y: &[f64]| (0..s).map(|i| x[i] * y[i]).collect::<Vec<f64>>();
        let apply = |x: &[f64]| (0..s).map(|i| (0..s).map(|j| k.a[i][j] * x[j]).sum::<f64>()).collect::<Vec<f64>>();
        let one = vec![1.0; s];
        let c = k.c[..s].to_vec();
        let c2 = times(&c, &c);
        let c3 = times(&c2, &c);
        let c4 = times(&c3, &c);
        let ac = apply(&c);
        let ac2 = apply(&c2);
        let ac3 = apply(&c3);
        let aac = apply(&ac);
        let aac2 = apply(&ac2);
        let aaac = apply(&aac);
        let cac = times(&c, &ac);
        let acac = apply(&cac);
        vec![
            (1, dot(w, &one), 1.0),
            (2, dot(w, &c), 1.0 / 2.0),
            (3, dot(w, &c2), 1.0 / 3.0),
            (3, dot(w, &ac), 1.0 / 6.0),
            (4, dot(w, &c3), 1.0 / 4.0),
            (4, dot(w, &cac), 1.0 / 8.0),
            (4, dot(w, &ac2), 1.0 / 12.0),
            (4, dot(w, &aac), 1.0 / 24.0),
            (5, dot(w, &c4), 1.0 / 5.0),
            (5, dot(w, &times(&c2, &ac)), 1.0 / 10.0),
            (5, dot(w, &times(&c, &ac2)), 1.0 / 15.0),
            (5, dot(w, &times(&c, &aac)), 1.0 / 30.0),
            (5, dot(w, &times(&ac, &ac)), 1.0 / 20.0),
            (5, dot(w, &ac3), 1.0 / 20.0),
            (5, dot(w, &acac), 1.0 / 40.0),
            (5, dot(w, &aac2), 1.0 / 60.0),
            (5, dot(w, &aaac), 1.0 / 120.0),
        ]
    }

    /// The highest order p such that every condition up to p holds to `tol`.
    fn order_of(k: &Tableau, w: &[f64], tol: f64) -> usize {
        let conditions = order_conditions(k, w);
        let mut p = 0;
        for order in 1..=5 {
            if conditions.iter().filter(|(o, _, _)| *o == order).all(|(_, got, want)| (got - want).abs() <= tol) {
                p = order;
            } else {
                break;
            }
        }
        p
    }

    /// R(z) = 1 + z w' (I - z A)^-1 (1, ..., 1) at a complex z = (re, im).
    fn stability(k: &Tableau, w: &[f64], z: (f64, f64)) -> (f64, f64) {
        let mul = |a: (f64, f64), b: (f64, f64)| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
        let div = |a: (f64, f64), b: (f64, f64)| {
            let m = b.0 * b.0 + b.1 * b.1;
            ((a.0 * b.0 + a.1 * b.1) / m, (a.1 * b.0 - a.0 * b.1) / m)
        };
        // (I - z A) v = 1, A lower triangular: forward substitution.
        let mut v = vec![(0.0, 0.0); k.stages];
        for i in 0..k.stages {
            let mut rhs = (1.0, 0.0);
            for j in 0..i {
                let t = mul(z, (k.a[i][j] * v[j].0, k.a[i][j] * v[j].1));
                rhs = (rhs.0 + t.0, rhs.1 + t.1);
            }
            let diagonal = (1.0 - z.0 * k.a[i][i], -z.1 * k.a[i][i]);
            v[i] = div(rhs, diagonal);
        }
        let mut sum = (0.0, 0.0);
        for i in 0..k.stages {
            sum = (sum.0 + w[i] * v[i].0, sum.1 + w[i] * v[i].1);
        }
        let t = mul(z, sum);
        (1.0 + t.0, t.1)
    }

    fn b_hat(k: &Tableau) -> Vec<f64> {
        (0..k.stages).map(|j| k.b[j] - k.d[j]).collect()
    }

    /// Order, embedded order, stiffly accurate (checked when made), L-stable: |R| <= 1 on the
    /// imaginary axis (A-stable: R has no pole in the left half-plane, its only pole is at
    /// 1 / gamma > 0) and R(infinity) = 0 (from the tableau, and R at a large negative z);
    /// the embedded method's stability function bounded at infinity.
    fn check(k: &Tableau) {
        let s = k.stages;
        assert_eq!(order_of(k, &k.b[..s], 1e-14), k.order, "{}: order", k.name);
        assert_eq!(order_of(k, &b_hat(k), 1e-14), k.embedded_order, "{}: embedded order", k.name);
        assert!(k.gamma > 0.0);
        for m in 0..=4000 {
            let y = if m == 0 { 0.0 } else { 10f64.powf(-3.0 + 9.0 * m as f64 / 4000.0) };
            let r = stability(k, &k.b[..s], (0.0, y));
            let modulus = (r.0 * r.0 + r.1 * r.1).sqrt();
            assert!(modulus <= 1.0 + 1e-13, "{}: |R(i {y})| = {modulus}", k.name);
        }
        let u = k.limit_at_infinity();
        assert!(u[s - 1].abs() < 1e-14, "{}: R(infinity) = {}", k.name, u[s - 1]);
        let far = stability(k, &k.b[..s], (-1e9, 0.0));
        assert!(far.0.abs() < 1e-7 && far.1 == 0.0, "{}: R(-1e9) = {far:?}", k.name);
        let hat: f64 = b_hat(k).iter().zip(&u).map(|(x, y)| x * y).sum();
        assert!(hat.abs() < 1e-14, "{}: the embedded method's R grows at infinity (b_hat . u = {hat})", k.name);
        let far_hat = stability(k, &b_hat(k), (-1e9, 0.0));
        assert!(far_hat.0.abs() < 1.0, "{}: embedded R(-1e9) = {far_hat:?}", k.name);
    }

    /// The dense output (conditions to 1e-12: the least-norm weights come from normal equations):
    /// b(0) = 0, b(1) = b, the order conditions up to its order at every theta
    /// (theta^|tree| / gamma(tree)), b(theta) . u = 0; on y' = lambda y against exp(theta z)
    /// (z = h lambda): an error of order z^(dense_order + 1) (halving z divides it by about
    /// 2^(dense_order + 1)), and bounded by 1 in modulus for stiff z down to -1e9.
    fn check_dense(k: &Tableau, dense_order: usize) {
        assert_eq!(k.dense_order, dense_order, "{}", k.name);
        let s = k.stages;
        assert!(k.dense_weights(0.0).iter().all(|w| *w == 0.0));
        for (w, b) in k.dense_weights(1.0).iter().zip(&k.b) {
            assert!((w - b).abs() < 1e-14, "{}: b(1) = {w}, b = {b}", k.name);
        }
        let u = k.limit_at_infinity();
        for m in 0..=20 {
            let theta = m as f64 / 20.0;
            let w = k.dense_weights(theta);
            for (order, got, want) in order_conditions(k, &w[..s]) {
                if order <= dense_order {
                    let want = want * theta.powi(order as i32);
                    assert!((got - want).abs() < 1e-12, "{}: theta {theta}, order {order}: {got} against {want}", k.name);
                }
            }
            let bounded: f64 = w.iter().zip(&u).map(|(x, y)| x * y).sum();
            assert!(bounded.abs() < 1e-13, "{}: theta {theta}: b(theta) . u = {bounded}", k.name);
            let error = |z: f64| (stability(k, &w[..s], (z, 0.0)).0 - (theta * z).exp()).abs();
            if (0.2..=0.8).contains(&theta) {
                let ratio = error(-0.02) / error(-0.01);
                let expected = 2f64.powi(dense_order as i32 + 1);
                assert!(ratio > 0.8 * expected && ratio < 1.25 * expected, "{}: theta {theta}: error ratio {ratio} (expected {expected})", k.name);
            }
            for z in [-1.0, -3.0, -10.0, -30.0, -1e2, -1e3, -1e5, -1e7, -1e9] {
                let r = stability(k, &w[..s], (z, 0.0)).0;
                assert!(r.abs() <= 1.0, "{}: theta {theta}: R({z}, theta) = {r}", k.name);
            }
        }
    }

    /// (ESDIRK4(3)6L\[2\]SA's, of order 3, is not bounded by 1: |R(-1000, 0.65)| = 1.25; it is
    /// not used.)
    #[test]
    fn the_dense_output_is_of_order_4_and_bounded_for_stiff_components() {
        check_dense(&Tableau::esdirk547(), 4);
    }

    #[test]
    fn esdirk436_is_fourth_order_with_a_third_order_estimate_stiffly_accurate_and_l_stable() {
        let k = Tableau::esdirk436();
        check(&k);
        // Its stage order is 2: each stage's sum_j a_ij c_j = c_i^2 / 2.
        for i in 0..k.stages {
            let ac: f64 = (0..k.stages).map(|j| k.a[i][j] * k.c[j]).sum();
            assert!((ac - k.c[i] * k.c[i] / 2.0).abs() < 1e-14, "stage {i}");
        }
    }

    #[test]
    fn esdirk547_is_fifth_order_with_a_fourth_order_estimate_stiffly_accurate_and_l_stable() {
        check(&Tableau::esdirk547());
    }

    #[test]
    fn esdirk32_is_third_order_with_a_second_order_estimate_stiffly_accurate_and_l_stable() {
        check(&Tableau::esdirk32());
    }
}
