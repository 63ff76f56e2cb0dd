//! The one stepping loop of every method: step, evaluate the event indicators at the step's end,
//! locate the earliest zero crossing on the step's dense output (Illinois method), stop just
//! past it; else, once a step reaches the communication point, interpolate the state there.

use crate::integrate::{Advanced, IndicatorDyn, MAX_INTERNAL_STEPS, ROOT_TIME_TOLERANCE};

use super::Stepper;

/// Whether an indicator going from `a` to `b` crossed zero (a zero at `a` is no crossing).
pub fn crossed(a: f64, b: f64) -> bool {
    (a > 0.0 && b <= 0.0) || (a < 0.0 && b >= 0.0)
}

/// The event indicators of one advance: g(x, p, t, z) with its parameter vector.
pub struct Events<'a> {
    pub g: &'a IndicatorDyn,
    pub p: &'a [f64],
    pub n: usize,
    /// The instant at which the indicators at a fresh start are taken, when not the stepper's
    /// start: the time event just below it.
    pub start_at: Option<f64>,
}

impl Events<'_> {
    fn into(&self, t: f64, y: &[f64], z: &mut [f64]) {
        (self.g)(y, self.p, t, z);
    }
}

/// The buffers of [`step_until`], kept in the integrator so that steady stepping allocates
/// nothing: the state reached (its result), the event indicators at the step's end and at the
/// last accepted point, the zero-crossing search's vectors.
pub struct Ends<'a> {
    pub y_end: &'a mut Vec<f64>,
    pub z: &'a mut [f64],
    pub z_prev: &'a mut [f64],
    /// In: `z_prev` holds exactly the indicators at the end of the stepper's last accepted
    /// step (the advance continues it, nothing changed since, none was zero there), so they
    /// are not evaluated there again. Out: whether that holds for the last step taken.
    pub z_prev_fresh: &'a mut bool,
    pub roots: &'a mut RootScratch,
}

/// Steps `stepper` from where it stands until its last step reaches `t1` (a stepper that looks
/// ahead may end past it, not past `limit`), and interpolates the state at `t1` into `y_end`; or
/// stops at the first zero crossing of an event indicator before `t1`, with the state just past
/// it in `y_end`. A step reaching past `t1` whose indicators cross zero only after `t1` is not
/// continued: that event is the next communication step's, which restarts from `t1` and locates
/// it. The indicators at the current point are the reference; a zero there takes its sign from
/// the next point. Returns how it ended and whether the next advance may continue the last
/// step (it may when the advance reached `t1` inside or at the end of a step).
pub fn step_until(stepper: &mut dyn Stepper, events: Option<&Events>, t1: f64, limit: f64, ends: Ends, budget: &mut usize) -> Result<(Advanced, bool), String> {
    let Ends { y_end, z, z_prev, z_prev_fresh, roots } = ends;
    let (_, t_now, y_now) = stepper.last_step();
    y_end.clear();
    y_end.resize(y_now.len(), 0.0);
    if stepper.has_step() && t1 <= t_now {
        // The last step already covers t1 (and was checked for crossings in full).
        stepper.interpolate(t1, y_end)?;
        return Ok((Advanced::Reached, true));
    }
    if let Some(ev) = events {
        if !(*z_prev_fresh && stepper.has_step()) {
            let t_ref = if stepper.has_step() { t_now } else { ev.start_at.unwrap_or(t_now) };
            ev.into(t_ref, y_now, z_prev);
        }
    }
    while *budget > 0 {
        *budget -= 1;
        *z_prev_fresh = false;
        stepper.step(limit)?;
        let stepper: &dyn Stepper = &*stepper;
        let (ta, tb, yb) = stepper.last_step();
        if let Some(ev) = events {
            ev.into(tb, yb, z);
            if let Some(found) = first_crossing(stepper, ev, ta, z_prev, tb, z, yb, roots)? {
                let found = if tb <= t1 {
                    Some(found)
                } else {
                    // Only a crossing before t1 belongs to this communication step: the same
                    // search on [ta, t1], as if the step had stopped at t1.
                    stepper.interpolate(t1, y_end)?;
                    ev.into(t1, y_end, z);
                    first_crossing(stepper, ev, ta, z_prev, t1, z, y_end, roots)?
                };
                return Ok(match found {
                    Some((time, indicator)) => {
                        y_end.copy_from_slice(&roots.y_root);
                        (Advanced::Crossing { time, indicator }, false)
                    }
                    None => (Advanced::Reached, false),
                });
            }
            for (zp, zi) in z_prev.iter_mut().zip(z.iter()) {
                if *zi != 0.0 || *zp == 0.0 {
                    *zp = *zi;
                }
            }
            *z_prev_fresh = z.iter().all(|zi| *zi != 0.0);
        }
        if t1 <= tb {
            stepper.interpolate(t1, y_end)?;
            return Ok((Advanced::Reached, true));
        }
    }
    Err(format!(
        "the ODE solver needed more than {MAX_INTERNAL_STEPS} internal steps in one communication step to reach t = {t1} s \
         (stopped at t = {} s); the model may be too stiff for its solver or unstable",
        stepper.last_step().1
    ))
}

/// Work vectors of the zero-crossing search (`first_crossing`), kept between calls so that the
/// search allocates nothing: a trial state and its indicators, the state at the bracket's crossed
/// end, and the result.
#[derive(Default)]
pub struct RootScratch {
    y_trial: Vec<f64>,
    z_trial: Vec<f64>,
    y_hi: Vec<f64>,
    /// The state just past the crossing found by the last successful search.
    y_root: Vec<f64>,
}

impl RootScratch {
    /// Sized for `n_states` states and `n_indicators` indicators up front, so that the first
    /// search after the integrator is made (at an event) does not allocate either.
    pub fn new(n_states: usize, n_indicators: usize) -> Self {
        let states = || Vec::with_capacity(n_states);
        RootScratch { y_trial: states(), z_trial: Vec::with_capacity(n_indicators), y_hi: states(), y_root: states() }
    }
}

/// The earliest zero crossing within the last step [ta, tb] (indicators za at ta, zb at tb, state
/// yb at tb), located by the Illinois method on the stepper's dense output of that step: (time
/// just past the crossing, indicator), with the state there in `scratch.y_root`; or None.
#[allow(clippy::too_many_arguments)]
fn first_crossing(
    stepper: &dyn Stepper,
    ev: &Events,
    ta: f64,
    za: &[f64],
    tb: f64,
    zb: &[f64],
    yb: &[f64],
    scratch: &mut RootScratch,
) -> Result<Option<(f64, usize)>, String> {
    let RootScratch { y_trial, z_trial, y_hi, y_root } = scratch;
    y_trial.resize(yb.len(), 0.0);
    z_trial.resize(ev.n, 0.0);
    let mut best: Option<(f64, usize)> = None;
    for j in 0..ev.n {
        if !crossed(za[j], zb[j]) {
            continue;
        }
        // Bracket: g(lo) on the start side (za's sign), g(hi) crossed.
        let (mut lo, mut g_lo) = (ta, za[j]);
        let (mut hi, mut g_hi) = (tb, zb[j]);
        y_hi.clear();
        y_hi.extend_from_slice(yb);
        let tol = ROOT_TIME_TOLERANCE * tb.abs().max(1.0);
        let mut side = 0i8;
        for _ in 0..200 {
            if hi - lo <= tol {
                break;
            }
            let secant = if g_lo != g_hi { hi - g_hi * (hi - lo) / (g_hi - g_lo) } else { 0.5 * (lo + hi) };
            // Keep the trial point strictly inside, off the ends by a little.
            let margin = 0.5 * tol;
            let t = if secant.is_finite() { secant.clamp(lo + margin, hi - margin) } else { 0.5 * (lo + hi) };
            if t == tb {
                y_trial.copy_from_slice(yb);
            } else {
                stepper.interpolate(t, y_trial)?;
            }
            ev.into(t, y_trial, z_trial);
            let g = z_trial[j];
            if crossed(za[j], g) {
                hi = t;
                g_hi = g;
                y_hi.copy_from_slice(y_trial);
                if side == 1 {
                    g_lo *= 0.5; // Illinois: the same end twice, halve the other's weight
                }
                side = 1;
            } else {
                lo = t;
                g_lo = g;
                if side == -1 {
                    g_hi *= 0.5;
                }
                side = -1;
            }
        }
        let earlier = match &best {
            Some((t, _)) => hi < *t,
            None => true,
        };
        if earlier {
            best = Some((hi, j));
            y_root.clear();
            y_root.extend_from_slice(y_hi);
        }
    }
    Ok(best)
}
