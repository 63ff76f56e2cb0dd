//! The directional derivatives of every FMU (`fmi2GetDirectionalDerivative` of dist/,
//! `fmi3GetDirectionalDerivative` of dist/fmi3/; `FMI_VERSIONS=2` or `=3` restricts, both by
//! default) come from forward-mode automatic differentiation, so they should be exact to
//! round-off. This test holds them to that, a thousand times tighter than
//! tests/tests/directional_derivatives.rs (1e-6 against plain central differences): every entry
//! of the Model Exchange Jacobian must match an eighth-order finite difference to
//! `REL_TOL` = 1e-9 of its scale.
//!
//! Jacobian: a Model Exchange instance put on the operating points of the default experiment
//! that tests/tests/directional_derivatives.rs uses (right after initialization, after 5
//! communication steps, at 1/3 and 2/3): the time, continuous states and inputs of a
//! Co-Simulation run of the same FMU at those instants, set by `fmi2SetTime`,
//! `fmi2SetContinuousStates` and `fmi2SetReal`, then an event iteration if the FMU has event
//! indicators (its discrete modes follow the states). Unknowns: the state derivatives and the
//! Real outputs (not the energy balance `power_balance_*`, zero at every state: its derivatives
//! are round-off on both sides); knowns: the continuous states and the Real inputs. Column j is
//! `fmi2GetDirectionalDerivative` with the seed e_j.
//!
//! Reference: computed here from the FMU's own function values only (not from its derivative
//! code, never hard-coded): f = the unknowns read by `fmi2GetReal` (equal, bit for bit, to
//! `fmi2GetDerivatives` for the state derivatives: checked) with known j alone moved by
//! `fmi2SetContinuousStates` (a state) or `fmi2SetReal` (an input), at x0 + k d, k = -8..8,
//! d = h/2. From these 17 values:
//!
//! * C(d), the 8-point central stencil, of truncation order 8 (below); C(h/2) uses k = +-1..4,
//!   C(h) k = +-2, 4, 6, 8;
//! * F and B, the 9-point one-sided stencils of step d (forward: k = 0..8, backward: k = 0..-8),
//!   of truncation order 8 too (error d^8 f^(9) / 9): they see a kink of f that C cannot (C is
//!   blind to the even part of f about x, so to a kink exactly at x).
//!
//! ```text
//! C(d) = [672 (f(x+d) - f(x-d)) - 168 (f(x+2d) - f(x-2d)) + 32 (f(x+3d) - f(x-3d))
//!         - 3 (f(x+4d) - f(x-4d))] / (840 d)
//!      = f'(x) - d^8 f^(9)(x) / 630 + O(d^10)
//! F    = [-761/280 f(x) + 8 f(x+d) - 14 f(x+2d) + 56/3 f(x+3d) - 35/2 f(x+4d)
//!         + 56/5 f(x+5d) - 14/3 f(x+6d) + 8/7 f(x+7d) - 1/8 f(x+8d)] / d
//!      = f'(x) - d^8 f^(9)(x) / 9 + O(d^9)          (B: the same with -d for d)
//! ```
//!
//! Steps: h = h0 / 4^m, m = 0..3, with h0 the power of two at or below 1e-3 s_j, where
//! s_j = max(|x0|, nominal_j or 1) is the known's scale (as in directional_derivatives.rs): a
//! power of two, so that the offsets k h/2 are exact and x0 + k h/2 is only rounded to x0's
//! ulp (an error of f of the size of eps_f below). Each step costs 16 evaluations of f.
//!
//! Round-off: values of f wrong by eps_f make C(d) wrong by at most
//! eps_f 2 (672 + 168 + 32 + 3) / 840 / d ~ 2.1 eps_f / d, and F, B by 78 eps_f / d (the sum
//! of their coefficients' magnitudes). With eps_f ~ 2e-16 S_i (one ulp of a value the size of
//! the unknown's scale S_i) and d >= h0/2 > 2.5e-4 s_j, C(h/2) is accurate to ~2e-12 of
//! S_i / s_j, the size the tolerance is measured against: a 500th of REL_TOL, room for
//! intermediate terms larger than the unknown cancelling inside the model. At the smallest
//! step (d > 3.9e-6 s_j) C's round-off reaches ~1e-10 = `CONVERGED`, so a noisy entry there
//! fails the self-check below (no reference) rather than being judged with a poor reference.
//! F and B are used as references only at the first two steps (d > 6.2e-5 s_j: round-off
//! below 3e-10 of S_i / s_j).
//!
//! Self-check, for each entry, at the first step m where it holds: C(h) and C(h/2) agree to
//! `CONVERGED` = 1e-10 of the entry's scale (C(h) - C(h/2) is 255/256 of C(h)'s truncation
//! error for a smooth f, so C(h/2)'s own is below 4e-13) and F and B agree to `KINK` = 1e-9 of
//! it (or 4 times their round-off bound, if larger): no kink of f within the stencil, none at
//! x0 either. The reference is then C(h/2) ("refined" when m > 0: a feature of f within the
//! first step's reach 4 h0, e.g. a smoothed |w| near w = 0). Where no step passes:
//!
//! * if F and B each agree between h0 and h0/4 to `CONVERGED` (f smooth on each side of x0):
//!   - they agree with each other to `KINK`: f has a derivative at x0 but is not smooth
//!     enough there for C (e.g. w |w| at w = 0); the reference is their mean ("one-sided");
//!   - they do not: a kink of f at x0 itself (an activity rate |P| at P = 0 to round-off, a
//!     |w| term at w = 0): f has no derivative, and the AD value must be the derivative of the
//!     branch the equations took there, F or B, or their mean (what `Dual::abs` gives at exactly
//!     0), to `REL_TOL` ("at kinks");
//! * if only one side's stencil agrees between h0 and h0/4, and f is continuous at x0 on the
//!   other side (its first difference there shrinks with the step from h0 to h0/64, with a
//!   margin of 4: it does not for a jump at x0, or for a branch of x0 narrower than the last
//!   step), the kink on the other side lies within the stencil but not at x0 (else that side
//!   would have agreed too): x0 is inside the smooth side's branch, whose F or B is the
//!   reference ("one-sided");
//! * otherwise there is no reference at this accuracy: a jump of f at x0 (e.g. the activity
//!   shares `share_*` = 100 A_i / sum A while the activities are all 0 or tiny against the
//!   step: they jump to 0 where the sum crosses 0), or a kink or a feature of f closer to x0
//!   than any step resolves. Such entries are counted and the first ones printed ("without
//!   reference", with every estimate at every step), never judged with a looser tolerance. So
//!   are entries whose stencils could not be evaluated at all (a known's min/max within 4h, a
//!   status not OK, a value not finite).
//!
//! Accuracy: entry (i, j) passes when
//!
//! ```text
//! |dd - ref| <= REL_TOL * max(|ref|, |dd|, S_i / s_j),     REL_TOL = 1e-9
//! ```
//!
//! (at a kink: the smallest of |dd - F|, |dd - B|, |dd - (F + B)/2|, against
//! max(|F|, |B|, |dd|, S_i / s_j)), where S_i is the scale of unknown i: the largest of its range
//! over the Co-Simulation run, its magnitude at the operating point and its declared nominal (1
//! for an unknown that is 0 throughout the run and declares none), as in
//! directional_derivatives.rs.
//!
//! Per FMU, the worst relative error (and where), the entries judged (of them: one-sided, at
//! kinks, refined), those without reference (and which unknowns they are), the number of FMU
//! evaluations and the time are printed to stderr directly (bypassing the harness's capture),
//! so they show in every `cargo test` run. The whole test takes about a second (release build).
//!
//! `FMU_DIST_DIR` overrides the folder (default `<workspace>/dist`).

mod derivative_checks;
use derivative_checks::{get, me_event_iteration, me_move_to, ok, ratio, report};

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use fmi_host::dist::{every_fmu_path_for, versions};
use fmi_host::{Causality, Fmi2Type, Fmu, Instance, InstantiateOptions, Status, ValueReference, VariableType};

/// Relative accuracy required of every Jacobian entry (of max(|ref|, |dd|, S_i / s_j)).
const REL_TOL: f64 = 1e-9;
/// C(h) and C(h/2) agreeing to this (relative to the entry's scale) make C(h/2) the reference.
const CONVERGED: f64 = 1e-10;
/// F and B further apart than this (relative to the entry's scale, or 4 times their round-off
/// if larger) mark a kink of f at or next to the point.
const KINK: f64 = 1e-9;
/// The first step, relative to the known's scale (rounded down to a power of two).
const FIRST_REL_STEP: f64 = 1e-3;
/// Each further step is the previous one divided by this (a power of two).
const REFINE: f64 = 4.0;
/// Steps tried: h, h/4, h/16, h/64.
const LEVELS: usize = 4;
/// The 8-point central stencil: f'(x) ~ sum_m CENTRAL[m] (f(x + (m+1) d) - f(x - (m+1) d)) / d.
const CENTRAL: [f64; 4] = [672.0 / 840.0, -168.0 / 840.0, 32.0 / 840.0, -3.0 / 840.0];
/// The 9-point forward stencil: f'(x) ~ sum_k ONE_SIDED[k] f(x + k d) / d, order 8.
const ONE_SIDED: [f64; 9] = [-761.0 / 280.0, 8.0, -14.0, 56.0 / 3.0, -35.0 / 2.0, 56.0 / 5.0, -14.0 / 3.0, 8.0 / 7.0, -1.0 / 8.0];
/// Entries without reference printed per FMU.
const SHOWN: usize = 3;


#[derive(Clone, Debug)]
struct Var {
    name: String,
    vr: ValueReference,
    nominal: Option<f64>,
    min: Option<f64>,
    max: Option<f64>,
}

struct Model {
    fmu: Arc<Fmu>,
    /// "<model name> (FMI x.0)".
    name: String,
    /// Continuous states, in the order of the state vector (ModelStructure's derivatives).
    states: Vec<Var>,
    /// State derivatives, then the Real outputs but the energy balance.
    unknowns: Vec<Var>,
    inputs: Vec<Var>,
    start: f64,
    stop: f64,
    step: f64,
}

impl Model {
    fn load(path: &Path) -> Model {
        let fmu = Fmu::load(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
        let md = fmu.model_description();
        let var = |v: &fmi_host::ScalarVariable| Var { name: v.name.clone(), vr: v.value_reference, nominal: v.nominal, min: v.min, max: v.max };
        let real_by_vr = |vr: ValueReference| {
            md.model_variables
                .iter()
                .find(|v| v.value_reference == vr && v.variable_type == VariableType::Real)
                .unwrap_or_else(|| panic!("{}: no Real variable has value reference {vr}", md.model_name))
        };
        let mut states = Vec::new();
        let mut derivatives = Vec::new();
        for u in &md.model_structure.continuous_state_derivatives {
            let d = real_by_vr(u.value_reference);
            let x = d.derivative.unwrap_or_else(|| panic!("{}: {:?} is listed as a derivative, has no derivative attribute", md.model_name, d.name));
            derivatives.push(var(d));
            states.push(var(&md.model_variables[x as usize - 1]));
        }
        let pick = |c: Causality| -> Vec<Var> {
            md.model_variables.iter().filter(|v| v.variable_type == VariableType::Real && v.causality == c).map(var).collect()
        };
        let unknowns = derivatives.into_iter().chain(pick(Causality::Output)).filter(|v| !v.name.starts_with("power_balance_")).collect();
        let e = md.default_experiment.expect("every FMU has a DefaultExperiment");
        Model {
            name: format!("{} ({})", md.model_name, fmu.fmi_version()),
            states,
            unknowns,
            inputs: pick(Causality::Input),
            start: e.start_time.unwrap_or(0.0),
            stop: e.stop_time.expect("DefaultExperiment stopTime"),
            step: e.step_size.expect("DefaultExperiment stepSize"),
            fmu,
        }
    }
}

fn vrs(vars: &[Var]) -> Vec<ValueReference> {
    vars.iter().map(|v| v.vr).collect()
}



fn instantiate(model: &Model, fmu_type: Fmi2Type, label: &str) -> Instance {
    let mut inst = Instance::new(&model.fmu, InstantiateOptions::new(label).fmu_type(fmu_type))
        .unwrap_or_else(|e| panic!("{}: instantiate ({fmu_type:?}): {e}", model.name));
    ok(inst.setup_experiment(None, model.start, Some(model.stop)), "fmi2SetupExperiment", &inst);
    ok(inst.enter_initialization_mode(), "fmi2EnterInitializationMode", &inst);
    ok(inst.exit_initialization_mode(), "fmi2ExitInitializationMode", &inst);
    inst
}



/// An operating point of the Co-Simulation run.
struct Point {
    step: usize,
    t: f64,
    x: Vec<f64>,
    u: Vec<f64>,
    y: Vec<f64>,
}

/// One Co-Simulation run of the default experiment: the operating points (after
/// initialization, after 5 steps, at 1/3 and 2/3) and the range of every unknown over the run.
fn cs_run(model: &Model) -> (Vec<Point>, Vec<f64>) {
    let (u_vr, x_vr, in_vr) = (vrs(&model.unknowns), vrs(&model.states), vrs(&model.inputs));
    let steps = ((model.stop - model.start) / model.step).round() as usize;
    let mut wanted = vec![0, 5.min(steps), steps / 3, 2 * steps / 3];
    wanted.dedup();
    let mut cs = instantiate(model, Fmi2Type::CoSimulation, "cs");
    let mut points = Vec::new();
    let first = get(&mut cs, &u_vr, "fmi2GetReal(unknowns)");
    let (mut lo, mut hi) = (first.clone(), first);
    for k in 0..=steps {
        if k > 0 {
            let t = model.start + (k - 1) as f64 * model.step;
            ok(cs.do_step(t, model.step, true), &format!("fmi2DoStep({t})"), &cs);
        }
        let y = get(&mut cs, &u_vr, "fmi2GetReal(unknowns)");
        for i in 0..y.len() {
            lo[i] = lo[i].min(y[i]);
            hi[i] = hi[i].max(y[i]);
        }
        if wanted.contains(&k) {
            let x = get(&mut cs, &x_vr, "fmi2GetReal(states)");
            let u = get(&mut cs, &in_vr, "fmi2GetReal(inputs)");
            points.push(Point { step: k, t: model.start + k as f64 * model.step, x, u, y });
        }
    }
    (points, lo.iter().zip(&hi).map(|(a, b)| b - a).collect())
}

/// Scale of each unknown: max(range over the CS run, |value now|, nominal), 1 if all are 0.
fn unknown_scales(unknowns: &[Var], range: &[f64], now: &[f64]) -> Vec<f64> {
    (0..unknowns.len())
        .map(|i| {
            let s = range[i].max(now[i].abs()).max(unknowns[i].nominal.unwrap_or(0.0).abs());
            if s == 0.0 { 1.0 } else { s }
        })
        .collect()
}


/// The unknowns at x0 + k d, k = -8..8, with one known moved (d = h/2: the points of C(h),
/// C(h/2), F and B of one step h).
struct Level {
    /// The step h (a power of two); the points are h/2 apart.
    h: f64,
    /// `plus[k - 1]` = f(x0 + k h/2), `minus[k - 1]` = f(x0 - k h/2), k = 1..8.
    plus: Vec<Vec<f64>>,
    minus: Vec<Vec<f64>>,
}

impl Level {
    fn f(&self, f0: &[f64], k: i32, i: usize) -> f64 {
        match k {
            0 => f0[i],
            k if k > 0 => self.plus[k as usize - 1][i],
            k => self.minus[(-k) as usize - 1][i],
        }
    }
    /// C(h/2) (`unit` 1: points +-1..4 halves) or C(h) (`unit` 2: +-2, 4, 6, 8 halves).
    fn central(&self, f0: &[f64], i: usize, unit: i32) -> f64 {
        let step = unit as f64 * self.h / 2.0;
        (0..4).map(|m| CENTRAL[m] * (self.f(f0, unit * (m as i32 + 1), i) - self.f(f0, -unit * (m as i32 + 1), i))).sum::<f64>() / step
    }
    /// F (`side` 1) or B (`side` -1): the one-sided 9-point stencil of step h/2.
    fn one_sided(&self, f0: &[f64], i: usize, side: i32) -> f64 {
        side as f64 * (0..9).map(|k| ONE_SIDED[k] * self.f(f0, side * k as i32, i)).sum::<f64>() / (self.h / 2.0)
    }
    /// Round-off bound of F and B: eps sum|c_k| max|f_k| / (h/2).
    fn one_sided_round_off(&self, f0: &[f64], i: usize) -> f64 {
        let big = (-8..=8).map(|k| self.f(f0, k, i).abs()).fold(0.0, f64::max);
        f64::EPSILON * ONE_SIDED.iter().map(|c| c.abs()).sum::<f64>() * big / (self.h / 2.0)
    }
}

/// The values of one step h; `None` where the points leave the known's [min, max], or a call is
/// not OK, or a value is not finite.
/// `evaluations` counts the evaluations of f.
fn level<F: FnMut(&mut Instance, f64) -> Status>(
    inst: &mut Instance,
    unknowns: &[ValueReference],
    known: &Var,
    x0: f64,
    h: f64,
    set: &mut F,
    evaluations: &mut usize,
) -> Option<Level> {
    let reach = 4.0 * h;
    if known.min.is_some_and(|m| x0 - reach < m) || known.max.is_some_and(|m| x0 + reach > m) {
        return None;
    }
    *evaluations += 16;
    let (mut plus, mut minus) = (Vec::new(), Vec::new());
    let mut fine = true;
    for k in 1..=8 {
        for (sign, out) in [(1.0, &mut plus), (-1.0, &mut minus)] {
            let status = set(inst, x0 + sign * k as f64 * (h / 2.0));
            let (s2, f) = inst.get_reals(unknowns);
            fine &= status == Status::OK && s2 == Status::OK && f.iter().all(|v| v.is_finite());
            out.push(f);
        }
    }
    fine.then_some(Level { h, plus, minus })
}

#[derive(Default)]
struct Tally {
    /// Entries judged against C (smooth f), against F and B (the derivative exists, f is not
    /// smooth enough for the central stencil), at a kink (against the branch derivatives).
    central: usize,
    one_sided: usize,
    kinks: usize,
    /// Judged at a level after the first (a feature within the first step's stencil).
    refined: usize,
    without_reference: usize,
    /// The unknowns of the entries without reference (in order of appearance), with counts.
    without_reference_by_unknown: Vec<(String, usize)>,
    examples: Vec<String>,
    worst: f64,
    worst_at: String,
    failures: Vec<String>,
    evaluations: usize,
}

impl Tally {
    fn judged(&self) -> usize {
        self.central + self.one_sided + self.kinks
    }
}

/// The reference of one entry (see the module documentation), with its description.
enum Reference {
    /// C(h/2), where C(h) agrees with it and F with B.
    Central(f64, String),
    /// From F and B (their mean where both converged and agree, else the smooth side's).
    OneSided(f64, String),
    /// A kink at the point: the derivative of either branch (F, B), or their mean.
    Kink(f64, f64),
}

/// Classifies entry i of a column from its levels (see the module documentation).
fn reference(levels: &[Option<Level>], f0: &[f64], i: usize, natural: f64) -> Option<(Reference, usize)> {
    for (m, level) in levels.iter().enumerate() {
        let Some(l) = level else { continue };
        let (coarse, fine) = (l.central(f0, i, 2), l.central(f0, i, 1));
        let (fwd, bwd) = (l.one_sided(f0, i, 1), l.one_sided(f0, i, -1));
        let sc = coarse.abs().max(fine.abs()).max(natural);
        let converged = (coarse - fine).abs() <= CONVERGED * sc;
        let no_kink = (fwd - bwd).abs() <= (KINK * sc).max(4.0 * l.one_sided_round_off(f0, i));
        if converged && no_kink {
            return Some((Reference::Central(fine, format!("C(h/2) = {fine:.15e} at h = {:.3e} (C(h) {coarse:.15e})", l.h)), m));
        }
    }
    // The one-sided stencils of the first two steps (the only ones whose round-off is well
    // below REL_TOL), side by side: a side whose F (or B) is the same at h and h/4 has f smooth
    // over its whole reach [x0, x0 +- 4h].
    let (Some(a), Some(b)) = (levels.first()?, levels.get(1)?) else { return None };
    let side = |s: i32| {
        let (coarse, fine) = (a.one_sided(f0, i, s), b.one_sided(f0, i, s));
        ((coarse - fine).abs() <= CONVERGED * coarse.abs().max(fine.abs()).max(natural)).then_some(fine)
    };
    let h = b.h;
    match (side(1), side(-1)) {
        (Some(fwd), Some(bwd)) if (fwd - bwd).abs() <= KINK * fwd.abs().max(bwd.abs()).max(natural) => {
            let mean = 0.5 * (fwd + bwd);
            Some((Reference::OneSided(mean, format!("one-sided F = {fwd:.15e}, B = {bwd:.15e} at h = {h:.3e} (C not converged)")), 1))
        }
        (Some(fwd), Some(bwd)) => Some((Reference::Kink(fwd, bwd), 1)),
        // One side smooth, and f continuous at x0 on the other, whose difference did not
        // converge: a kink there within the stencil, not at x0 (else that side's difference
        // would have converged too), so x0 is inside the smooth side's branch.
        (Some(fwd), None) if continuous(levels, f0, i, -1) => {
            Some((Reference::OneSided(fwd, format!("one-sided F = {fwd:.15e} at h = {h:.3e} (a kink in x0's backward stencil)")), 1))
        }
        (None, Some(bwd)) if continuous(levels, f0, i, 1) => {
            Some((Reference::OneSided(bwd, format!("one-sided B = {bwd:.15e} at h = {h:.3e} (a kink in x0's forward stencil)")), 1))
        }
        _ => None,
    }
}

/// Whether f is continuous at x0 on side `side` as far as the steps show: its first difference
/// there shrinks at least in proportion to the step from the first step to the last (a jump at
/// x0, or a branch of x0 narrower than the last step, keeps it), with a margin of 4.
fn continuous(levels: &[Option<Level>], f0: &[f64], i: usize, side: i32) -> bool {
    let (Some(Some(first)), Some(last)) = (levels.first(), levels.iter().flatten().last()) else { return false };
    let jump = |l: &Level| (l.f(f0, side, i) - f0[i]).abs();
    jump(last) <= 4.0 * (last.h / first.h) * jump(first)
}

/// Checks one column (known j at x0) against the high-order differences.
#[allow(clippy::too_many_arguments)]
fn check_column<F: FnMut(&mut Instance, f64) -> Status>(
    inst: &mut Instance,
    tally: &mut Tally,
    at: &str,
    unknowns: &[Var],
    scale_u: &[f64],
    known: &Var,
    x0: f64,
    mut set: F,
) {
    let u_vr = vrs(unknowns);
    let mut dd = vec![f64::NAN; unknowns.len()];
    ok(inst.get_directional_derivative(&u_vr, &[known.vr], &[1.0], &mut dd), &format!("fmi2GetDirectionalDerivative({})", known.name), inst);
    ok(set(inst, x0), "set the known", inst);
    let f0 = get(inst, &u_vr, "fmi2GetReal(unknowns)");
    let s_j = x0.abs().max(known.nominal.map_or(1.0, f64::abs));
    let h0 = 2f64.powi((FIRST_REL_STEP * s_j).log2().floor() as i32);
    tally.evaluations += 1;
    let levels: Vec<Option<Level>> =
        (0..LEVELS).map(|m| level(inst, &u_vr, known, x0, h0 / REFINE.powi(m as i32), &mut set, &mut tally.evaluations)).collect();
    // Restore the known; the unknowns must come back bit for bit.
    ok(set(inst, x0), "restore the known", inst);
    let back = get(inst, &u_vr, "fmi2GetReal(unknowns) after restoring the known");
    assert!(back.iter().zip(&f0).all(|(a, b)| a.to_bits() == b.to_bits()), "{} {at}: the unknowns differ after {} was restored", inst.fmu().model_description().model_name, known.name);

    for (i, u) in unknowns.iter().enumerate() {
        let natural = scale_u[i] / s_j;
        let where_ = format!("{at}: d {} / d {}", u.name, known.name);
        if !dd[i].is_finite() {
            tally.failures.push(format!("{where_}: directional derivative {} is not finite", dd[i]));
            tally.worst = f64::INFINITY;
            tally.worst_at = where_;
            continue;
        }
        let Some((reference, m)) = reference(&levels, &f0, i, natural) else {
            tally.without_reference += 1;
            match tally.without_reference_by_unknown.iter_mut().find(|(name, _)| *name == u.name) {
                Some((_, n)) => *n += 1,
                None => tally.without_reference_by_unknown.push((u.name.clone(), 1)),
            }
            if tally.examples.len() < SHOWN {
                let estimates: Vec<String> = levels
                    .iter()
                    .map(|l| match l {
                        Some(l) => format!(
                            "h = {:.2e}: C(h) {:.9e}, C(h/2) {:.9e}, F {:.9e}, B {:.9e}",
                            l.h,
                            l.central(&f0, i, 2),
                            l.central(&f0, i, 1),
                            l.one_sided(&f0, i, 1),
                            l.one_sided(&f0, i, -1)
                        ),
                        None => "not evaluable".to_owned(),
                    })
                    .collect();
                tally.examples.push(format!("{where_} (dd {:.9e}, S_i/s_j {natural:.3e}): {}", dd[i], estimates.join("; ")));
            }
            continue;
        };
        if m > 0 {
            tally.refined += 1;
        }
        match reference {
            Reference::Central(..) => tally.central += 1,
            Reference::OneSided(..) => tally.one_sided += 1,
            Reference::Kink(..) => tally.kinks += 1,
        }
        let (err, detail) = match reference {
            Reference::Central(r, detail) | Reference::OneSided(r, detail) => {
                (ratio((dd[i] - r).abs(), r.abs().max(dd[i].abs()).max(natural)), detail)
            }
            Reference::Kink(fwd, bwd) => {
                let denom = fwd.abs().max(bwd.abs()).max(dd[i].abs()).max(natural);
                let off = [fwd, bwd, 0.5 * (fwd + bwd)].iter().map(|r| (dd[i] - r).abs()).fold(f64::INFINITY, f64::min);
                (ratio(off, denom), format!("kink at the point: one-sided F = {fwd:.15e}, B = {bwd:.15e} (dd must be either or their mean)"))
            }
        };
        if err > tally.worst || tally.worst_at.is_empty() {
            tally.worst = err;
            tally.worst_at = where_.clone();
        }
        if err > REL_TOL {
            tally.failures.push(format!("{where_}: directional derivative {:.15e}, {detail}; error {err:.3e} of max(|ref|, |dd|, S_i/s_j = {natural:.3e})", dd[i]));
        }
    }
}

/// Every entry of the ME Jacobian of one FMU at its operating points.
fn check_fmu(model: &Model) -> (String, Vec<String>) {
    let (u_vr, x_vr, in_vr) = (vrs(&model.unknowns), vrs(&model.states), vrs(&model.inputs));
    let nx = model.states.len();
    let started = Instant::now();
    let (points, range) = cs_run(model);
    let mut me = instantiate(model, Fmi2Type::ModelExchange, "me");
    let mut next_event = me_event_iteration(&mut me);
    let has_indicators = model.fmu.model_description().number_of_event_indicators.unwrap_or(0) > 0;
    let mut tally = Tally::default();
    let mut failures = Vec::new();
    for p in &points {
        let at = format!("t = {:.6} (step {})", p.t, p.step);
        me_move_to(&mut me, p.t, &mut next_event);
        ok(me.set_continuous_states(&p.x).unwrap(), "fmi2SetContinuousStates", &me);
        if !in_vr.is_empty() {
            ok(me.set_real(&in_vr, &p.u), "fmi2SetReal(inputs)", &me);
        }
        if has_indicators {
            // The discrete modes follow the states set by hand (as a master's event handling).
            ok(me.enter_event_mode().unwrap(), "fmi2EnterEventMode", &me);
            next_event = me_event_iteration(&mut me);
        }
        assert_eq!(get(&mut me, &x_vr, "fmi2GetReal(states)"), p.x, "{} {at}: the state vector is not in the order of the ModelStructure's derivatives", model.name);
        let y = get(&mut me, &u_vr, "fmi2GetReal(unknowns)");
        let mut dx = vec![f64::NAN; nx];
        ok(me.get_derivatives(&mut dx).unwrap(), "fmi2GetDerivatives", &me);
        let scale = unknown_scales(&model.unknowns, &range, &y);
        for i in 0..u_vr.len() {
            if (y[i] - p.y[i]).abs() > 1e-12 * scale[i].max(p.y[i].abs()) {
                failures.push(format!("{} {at}: {} is {:.15e} in the ME instance, {:.15e} in the CS instance", model.name, model.unknowns[i].name, y[i], p.y[i]));
            }
            if i < nx && dx[i].to_bits() != y[i].to_bits() {
                failures.push(format!("{} {at}: fmi2GetDerivatives gives {:.15e} for {}, fmi2GetReal {:.15e}", model.name, dx[i], model.unknowns[i].name, y[i]));
            }
        }
        for (j, state) in model.states.iter().enumerate() {
            let mut xs = p.x.clone();
            check_column(&mut me, &mut tally, &at, &model.unknowns, &scale, state, p.x[j], |inst, v| {
                xs[j] = v;
                inst.set_continuous_states(&xs).unwrap()
            });
        }
        for (j, input) in model.inputs.iter().enumerate() {
            check_column(&mut me, &mut tally, &at, &model.unknowns, &scale, input, p.u[j], |inst, v| inst.set_real(&[input.vr], &[v]));
        }
    }
    let mut text = format!(
        "  {:<28} {:>6} judged, worst {:.2e} ({}){}; of them {} one-sided, {} at kinks, {} refined; {} without reference; {} evaluations, {:.2} s\n",
        model.name,
        tally.judged(),
        tally.worst,
        tally.worst_at,
        if tally.failures.is_empty() { String::new() } else { format!("  <-- {} FAIL", tally.failures.len()) },
        tally.one_sided,
        tally.kinks,
        tally.refined,
        tally.without_reference,
        tally.evaluations,
        started.elapsed().as_secs_f64(),
    );
    if !tally.without_reference_by_unknown.is_empty() {
        let list: Vec<String> = tally.without_reference_by_unknown.iter().map(|(name, n)| format!("{name} {n}")).collect();
        text += &format!("      without reference, by unknown: {}\n", list.join(", "));
    }
    for e in &tally.examples {
        text += &format!("      without reference: {e}\n");
    }
    failures.extend(tally.failures.iter().take(8).map(|f| format!("{}: {f}", model.name)));
    if tally.failures.len() > 8 {
        failures.push(format!("{}: ... and {} more", model.name, tally.failures.len() - 8));
    }
    (text, failures)
}

#[test]
fn directional_derivatives_match_eighth_order_differences_to_1e_9() {
    let started = Instant::now();
    let (mut text, mut failures) = (String::new(), Vec::new());
    for version in versions() {
        for path in every_fmu_path_for(version) {
            let model = Model::load(&path);
            let (t, f) = check_fmu(&model);
            report(&t);
            text += &t;
            failures.extend(f);
        }
    }
    report(&format!(
        "== directional derivatives vs 8th-order central differences (tolerance {REL_TOL:e}), every FMU, Model Exchange: {:.1} s\n",
        started.elapsed().as_secs_f64()
    ));
    if !failures.is_empty() {
        panic!("Jacobian entries disagree with the 8th-order differences beyond {REL_TOL:e}:\n{}\n{text}", failures.join("\n"));
    }
}
