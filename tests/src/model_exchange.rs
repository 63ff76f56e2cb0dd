//! A strict Model Exchange master: drives an FMU's ME interface the way FMI 2.0 section 3.2.4's
//! pseudo-code does, with an adaptive Dormand-Prince 5(4) integrator (error control at the
//! experiment's relative tolerance, dense output), root location on the dense output, time
//! events from `nextEventTime` and `fmi2CompletedIntegratorStep`.
//!
//! What makes it strict (fmpy's ME loop is not): the integrator re-initializes — forgets its
//! step size and treats indicators that are zero at the restart point as "not yet decided" —
//! **only** when `fmi2NewDiscreteStates` reported `valuesOfContinuousStatesChanged` or
//! `nominalsOfContinuousStatesChanged`. Otherwise it continues with its history (step size and
//! the dense polynomial of the step it was in) and checks the indicators the way CVODE's
//! `cvRcheck2` does after a root return: an indicator that is exactly zero at the event time and
//! still exactly zero a small time `ttol = 100 eps (|t| + |h|)` later (its state taken from the
//! integrator's history) is the error CVODE reports as "Root found at and very near t"
//! ([`MeError::CloseRoots`]). An indicator zero at the event time but not just after takes its
//! sign from just after.
//!
//! After a (re-)initialization the rule is CVODE's `cvRcheck1`: an indicator zero at the start
//! and at start + ttol (state extrapolated with the fresh derivative) is deactivated, not a
//! crossing, and is reactivated at the first step end where it is non-zero.
//!
//! Crossings: between two step ends an active indicator crosses if its sign changes or it
//! becomes exactly zero. The crossing is located by the Illinois method on the step's dense
//! output to `ttol`; the event is handled at the bracket's far end (where the sign has changed,
//! as CVODE returns it). The part of the step after the crossing is discarded: the integrator
//! continues from the event time with the same step size (a one-step method has no other
//! history), so the results stay accurate whether or not it re-initialized.
//!
//! The model is reached through the [`MeModel`] trait; [`Instance`] implements it over the C ABI,
//! and a test model can implement it in Rust (the unit tests below do).

use std::fmt;

use crate::ffi::{EventInfo, FMI2_FALSE};
use crate::{Causality, Fmi2Type, Fmu, Instance, InstantiateOptions, Status, ValueReference, VariableType};

/// The calls of FMI 2.0 Model Exchange the master makes in continuous-time and event mode.
/// Each returns the FMU's status (the master fails on anything but OK and Warning).
pub trait MeModel {
    fn set_time(&mut self, t: f64) -> Status;
    fn set_continuous_states(&mut self, x: &[f64]) -> Status;
    fn get_continuous_states(&mut self, x: &mut [f64]) -> Status;
    fn get_nominals(&mut self, x: &mut [f64]) -> Status;
    fn get_derivatives(&mut self, dx: &mut [f64]) -> Status;
    fn get_event_indicators(&mut self, z: &mut [f64]) -> Status;
    /// (status, enterEventMode, terminateSimulation)
    fn completed_integrator_step(&mut self) -> (Status, bool, bool);
    fn enter_event_mode(&mut self) -> Status;
    fn new_discrete_states(&mut self, info: &mut EventInfo) -> Status;
    fn enter_continuous_time_mode(&mut self) -> Status;
    /// The values recorded at every output point and event (the FMU's Real outputs).
    fn outputs(&mut self, y: &mut [f64]) -> Status;
}

/// [`Instance`] as an [`MeModel`], recording the Reals `outputs`.
pub struct MeInstance {
    pub inst: Instance,
    pub outputs: Vec<ValueReference>,
}

fn me(r: crate::Result<Status>) -> Status {
    r.expect("the FMU exports every Model Exchange function")
}

impl MeModel for MeInstance {
    fn set_time(&mut self, t: f64) -> Status {
        me(self.inst.set_time(t))
    }
    fn set_continuous_states(&mut self, x: &[f64]) -> Status {
        me(self.inst.set_continuous_states(x))
    }
    fn get_continuous_states(&mut self, x: &mut [f64]) -> Status {
        me(self.inst.get_continuous_states(x))
    }
    fn get_nominals(&mut self, x: &mut [f64]) -> Status {
        me(self.inst.get_nominals_of_continuous_states(x))
    }
    fn get_derivatives(&mut self, dx: &mut [f64]) -> Status {
        me(self.inst.get_derivatives(dx))
    }
    fn get_event_indicators(&mut self, z: &mut [f64]) -> Status {
        me(self.inst.get_event_indicators(z))
    }
    fn completed_integrator_step(&mut self) -> (Status, bool, bool) {
        self.inst.completed_integrator_step(true).expect("fmi2CompletedIntegratorStep is exported")
    }
    fn enter_event_mode(&mut self) -> Status {
        me(self.inst.enter_event_mode())
    }
    fn new_discrete_states(&mut self, info: &mut EventInfo) -> Status {
        me(self.inst.new_discrete_states(info))
    }
    fn enter_continuous_time_mode(&mut self) -> Status {
        me(self.inst.enter_continuous_time_mode())
    }
    fn outputs(&mut self, y: &mut [f64]) -> Status {
        let vr = self.outputs.clone();
        self.inst.get_real(&vr, y)
    }
}

/// Why a strict ME run stopped.
#[derive(Debug, Clone, PartialEq)]
pub enum MeError {
    /// An FMI call returned Discard, Error or Fatal.
    Fmu { call: &'static str, t: f64, status: Status },
    /// CVODE's CV_RTFUNC_FAIL-free twin of CLOSERT: after an event the FMU did not re-initialize
    /// the states, and these event indicators are exactly zero at `t` and at `t + ttol`.
    CloseRoots { t: f64, ttol: f64, indicators: Vec<usize> },
    /// The step size fell below round-off of the time.
    StepSizeTooSmall { t: f64, h: f64 },
    /// More than [`MAX_EVENT_ITERATIONS`] fmi2NewDiscreteStates calls in one event iteration.
    EventIterationDoesNotConverge { t: f64 },
    /// More than [`MAX_EVENTS_AT_ONE_TIME`] events at one instant.
    EventsChatter { t: f64 },
    /// A non-finite derivative, state or indicator.
    NotFinite { what: &'static str, t: f64 },
}

impl fmt::Display for MeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeError::Fmu { call, t, status } => write!(f, "{call} returned {status:?} at t = {t}"),
            MeError::CloseRoots { t, ttol, indicators } => write!(
                f,
                "Root found at and very near t = {t} (event indicator(s) {indicators:?} exactly zero at t and at t + {ttol:.3e} \
                 after an event that did not report valuesOfContinuousStatesChanged)"
            ),
            MeError::StepSizeTooSmall { t, h } => write!(f, "step size {h:e} too small at t = {t}"),
            MeError::EventIterationDoesNotConverge { t } => {
                write!(f, "event iteration does not converge at t = {t}")
            }
            MeError::EventsChatter { t } => write!(f, "more than {MAX_EVENTS_AT_ONE_TIME} events at t = {t}"),
            MeError::NotFinite { what, t } => write!(f, "non-finite {what} at t = {t}"),
        }
    }
}

impl std::error::Error for MeError {}

pub const MAX_EVENT_ITERATIONS: usize = 100;
pub const MAX_EVENTS_AT_ONE_TIME: usize = 100;

/// What caused an event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    /// An event indicator crossed (index of the first that did).
    State(usize),
    /// `nextEventTime` was reached.
    Time,
    /// `fmi2CompletedIntegratorStep` asked for it.
    Step,
}

/// One handled event.
#[derive(Debug, Clone, PartialEq)]
pub struct Event {
    pub time: f64,
    pub kind: EventKind,
    /// `valuesOfContinuousStatesChanged || nominalsOfContinuousStatesChanged`: the integrator
    /// re-initialized.
    pub reinitialized: bool,
}

/// Counters of one run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeStats {
    pub accepted_steps: usize,
    pub rejected_steps: usize,
    pub derivative_evaluations: usize,
    pub reinitializations: usize,
}

/// The outputs of a run: one row per output point (start + k interval, and the stop time), and
/// one row at each event (after it).
#[derive(Debug, Clone, Default)]
pub struct MeResult {
    pub grid_times: Vec<f64>,
    pub grid: Vec<Vec<f64>>,
    pub events: Vec<Event>,
    pub event_rows: Vec<Vec<f64>>,
    pub stats: MeStats,
    /// The end time of every accepted step: the instants at which the master compares the event
    /// indicators' signs (a sign excursion between two of them is invisible to it).
    pub step_ends: Vec<f64>,
}

/// The experiment.
#[derive(Debug, Clone, Copy)]
pub struct MeExperiment {
    pub start: f64,
    pub stop: f64,
    pub output_interval: f64,
    pub rtol: f64,
}

// ---- Dormand-Prince 5(4) ----------------------------------------------------------------------

const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0],
    [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0],
    [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0],
];
/// 5th-order weights minus the embedded 4th-order ones.
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];
/// The dense output's 5th-order coefficients (Hairer, Norsett, Wanner; continuous extension).
const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// The dense output of one step: y(t0 + theta h) = r1 + theta (r2 + (1-theta) (r3 + theta (r4 + (1-theta) r5))).
#[derive(Debug, Clone, Default)]
pub struct Dense {
    pub t0: f64,
    pub h: f64,
    r: [Vec<f64>; 5],
}

impl Dense {
    pub fn eval(&self, t: f64, y: &mut [f64]) {
        let th = (t - self.t0) / self.h;
        let th1 = 1.0 - th;
        for i in 0..y.len() {
            y[i] = self.r[0][i]
                + th * (self.r[1][i] + th1 * (self.r[2][i] + th * (self.r[3][i] + th1 * self.r[4][i])));
        }
    }
}

/// One attempted step: (new state, f(new state), error norm, dense output).
struct Attempt {
    y1: Vec<f64>,
    f1: Vec<f64>,
    err: f64,
    dense: Dense,
}

struct Rhs<'a, M: MeModel> {
    model: &'a mut M,
    evaluations: usize,
}

impl<M: MeModel> Rhs<'_, M> {
    fn eval(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), MeError> {
        self.evaluations += 1;
        check(self.model.set_time(t), "fmi2SetTime", t)?;
        check(self.model.set_continuous_states(x), "fmi2SetContinuousStates", t)?;
        check(self.model.get_derivatives(dx), "fmi2GetDerivatives", t)?;
        if dx.iter().any(|v| !v.is_finite()) {
            return Err(MeError::NotFinite { what: "derivative", t });
        }
        Ok(())
    }
    fn indicators(&mut self, t: f64, x: &[f64], z: &mut [f64]) -> Result<(), MeError> {
        check(self.model.set_time(t), "fmi2SetTime", t)?;
        check(self.model.set_continuous_states(x), "fmi2SetContinuousStates", t)?;
        check(self.model.get_event_indicators(z), "fmi2GetEventIndicators", t)?;
        if z.iter().any(|v| !v.is_finite()) {
            return Err(MeError::NotFinite { what: "event indicator", t });
        }
        Ok(())
    }
}

fn check(status: Status, call: &'static str, t: f64) -> Result<(), MeError> {
    if status.is_ok_or_warning() {
        Ok(())
    } else {
        Err(MeError::Fmu { call, t, status })
    }
}

fn dopri_step<M: MeModel>(
    rhs: &mut Rhs<M>,
    t: f64,
    y0: &[f64],
    f0: &[f64],
    h: f64,
    rtol: f64,
    atol: &[f64],
) -> Result<Attempt, MeError> {
    let n = y0.len();
    let mut k: Vec<Vec<f64>> = vec![f0.to_vec()];
    let mut y = vec![0.0; n];
    for s in 1..7 {
        for i in 0..n {
            let mut acc = 0.0;
            for (j, kj) in k.iter().enumerate() {
                acc += A[s][j] * kj[i];
            }
            y[i] = y0[i] + h * acc;
        }
        let mut ks = vec![0.0; n];
        rhs.eval(t + C[s] * h, &y, &mut ks)?;
        k.push(ks);
    }
    // The 7th stage is evaluated at y1 (FSAL): y holds y1 now.
    let y1 = y;
    let mut sum = 0.0;
    for i in 0..n {
        let mut e = 0.0;
        for j in 0..7 {
            e += E[j] * k[j][i];
        }
        let sc = atol[i] + rtol * y0[i].abs().max(y1[i].abs());
        sum += (h * e / sc).powi(2);
    }
    let err = if n == 0 { 0.0 } else { (sum / n as f64).sqrt() };
    let ydiff: Vec<f64> = (0..n).map(|i| y1[i] - y0[i]).collect();
    let bspl: Vec<f64> = (0..n).map(|i| h * k[0][i] - ydiff[i]).collect();
    let r4: Vec<f64> = (0..n).map(|i| ydiff[i] - h * k[6][i] - bspl[i]).collect();
    let r5: Vec<f64> = (0..n)
        .map(|i| h * (0..7).map(|j| D[j] * k[j][i]).sum::<f64>())
        .collect();
    let f1 = k.pop().expect("seven stages");
    Ok(Attempt { y1, f1, err, dense: Dense { t0: t, h, r: [y0.to_vec(), ydiff, bspl, r4, r5] } })
}

/// CVODE's root-time tolerance at t with step h: 100 unit roundoffs of |t| + |h|.
fn ttol(t: f64, h: f64) -> f64 {
    100.0 * f64::EPSILON * (t.abs() + h.abs())
}

/// The first crossing of the active indicators in (t0, t1] on the dense output, located by the
/// Illinois method to ttol: (tlo, thi) with thi on the crossed side, and the indicator index.
fn locate<M: MeModel>(
    rhs: &mut Rhs<M>,
    dense: &Dense,
    crossing: &[usize],
    glo: &[f64],
    ghi: &[f64],
    t0: f64,
    t1: f64,
) -> Result<(f64, usize), MeError> {
    let n = dense.r[0].len();
    let m = glo.len();
    let mut x = vec![0.0; n];
    let mut z = vec![0.0; m];
    let tol = ttol(t1, dense.h);
    let mut best: Option<(f64, usize)> = None;
    for &i in crossing {
        let (mut a, mut b) = (t0, t1);
        let (mut ga, mut gb) = (glo[i], ghi[i]);
        let mut side = 0i32;
        if gb != 0.0 {
            let mut iterations = 0;
            while b - a > tol && iterations < 200 {
                iterations += 1;
                // Illinois: regula falsi with the retained end's value halved.
                let mut tm = b - gb * (b - a) / (gb - ga);
                if !(tm > a && tm < b) || (tm - a) < 0.5 * tol || (b - tm) < 0.5 * tol {
                    tm = 0.5 * (a + b);
                }
                dense.eval(tm, &mut x);
                rhs.indicators(tm, &x, &mut z)?;
                let gm = z[i];
                // crossed: zero, or the sign opposite to the left end's (which is never zero)
                if gm == 0.0 || gm.signum() != glo[i].signum() {
                    b = tm;
                    gb = gm;
                    if side == 1 {
                        ga *= 0.5;
                    }
                    side = 1;
                    if gm == 0.0 {
                        // exactly on the root: shrink from the left by bisection steps only
                        side = 0;
                    }
                } else {
                    a = tm;
                    ga = gm;
                    if side == -1 {
                        gb *= 0.5;
                    }
                    side = -1;
                }
            }
        }
        if best.is_none_or(|(tb, _)| b < tb) {
            best = Some((b, i));
        }
    }
    Ok(best.expect("at least one crossing"))
}

fn sign_crossed(glo: f64, ghi: f64) -> bool {
    ghi == 0.0 || glo * ghi < 0.0
}

/// Runs `model` (initialized: the caller did fmi2Instantiate(ModelExchange), SetupExperiment with
/// the tolerance, the start values, Enter/ExitInitializationMode) from the start to the stop time.
pub fn simulate_strict<M: MeModel>(
    model: &mut M,
    nx: usize,
    nz: usize,
    ny: usize,
    exp: MeExperiment,
) -> Result<MeResult, MeError> {
    let rtol = exp.rtol;
    let mut result = MeResult::default();
    let mut t = exp.start;
    let mut info = EventInfo::default();

    // Event iteration of the initialization (FMI 2.0 3.2.4: after ExitInitializationMode the
    // FMU is in event mode).
    event_iteration(model, &mut info, t)?;
    if info.terminate_simulation != FMI2_FALSE {
        return Ok(result);
    }
    check(model.enter_continuous_time_mode(), "fmi2EnterContinuousTimeMode", t)?;
    let mut t_next = (info.next_event_time_defined != FMI2_FALSE).then_some(info.next_event_time);

    let mut x = vec![0.0; nx];
    let mut nominal = vec![1.0; nx];
    check(model.get_continuous_states(&mut x), "fmi2GetContinuousStates", t)?;
    check(model.get_nominals(&mut nominal), "fmi2GetNominalsOfContinuousStates", t)?;
    let mut atol: Vec<f64> = nominal.iter().map(|v| rtol * v.abs()).collect();

    let mut y = vec![0.0; ny];
    let mut next_grid = 0usize;
    let grid_time = |k: usize| (exp.start + k as f64 * exp.output_interval).min(exp.stop);
    let n_grid = ((exp.stop - exp.start) / exp.output_interval - 1e-9).ceil() as usize + 1;

    let mut rhs_evals = 0usize;
    let mut f0 = vec![0.0; nx];
    let mut glo = vec![0.0; nz];
    let mut gactive = vec![true; nz];
    let mut h: f64;
    let mut events_here = (t, 0usize);

    // (Re-)initialization at t: derivative, step size, indicators with the cvRcheck1 rule.
    macro_rules! reinit {
        () => {{
            let mut rhs = Rhs { model: &mut *model, evaluations: 0 };
            rhs.eval(t, &x, &mut f0)?;
            let span = exp.stop - t;
            h = initial_step(&x, &f0, &atol, rtol, span);
            rhs.indicators(t, &x, &mut glo)?;
            if glo.iter().any(|g| *g == 0.0) {
                let dt = ttol(t, h);
                let xs: Vec<f64> = (0..nx).map(|i| x[i] + dt * f0[i]).collect();
                let mut ghi = vec![0.0; nz];
                rhs.indicators(t + dt, &xs, &mut ghi)?;
                for i in 0..nz {
                    if glo[i] == 0.0 {
                        if ghi[i] == 0.0 {
                            gactive[i] = false;
                        } else {
                            glo[i] = ghi[i];
                        }
                    }
                }
            }
            rhs_evals += rhs.evaluations;
            result.stats.reinitializations += 1;
        }};
    }
    reinit!();
    result.stats.reinitializations = 0; // the first one is the initialization
    record_grid(model, &mut result, &mut next_grid, n_grid, &grid_time, t, &x, None, true, &mut y)?;

    while t < exp.stop {
        let mut t_end = exp.stop;
        if let Some(te) = t_next {
            if te > t && te < t_end {
                t_end = te;
            }
        }
        // One accepted step (clamped to t_end).
        let mut rhs = Rhs { model: &mut *model, evaluations: 0 };
        let mut rejected_last = false;
        let attempt = loop {
            if t + h >= t_end || t + 1.01 * h >= t_end {
                h = t_end - t;
            }
            if h <= 4.0 * f64::EPSILON * t.abs().max(1e-300) {
                return Err(MeError::StepSizeTooSmall { t, h });
            }
            let a = dopri_step(&mut rhs, t, &x, &f0, h, rtol, &atol)?;
            let factor = (0.9 * a.err.max(1e-10).powf(-0.2)).clamp(0.2, 5.0);
            if a.err <= 1.0 {
                let t1 = if (t + h - t_end).abs() <= ttol(t_end, h) { t_end } else { t + h };
                let hn = h * if rejected_last { factor.min(1.0) } else { factor };
                let h_taken = h;
                h = hn;
                break (a, t1, h_taken);
            }
            result.stats.rejected_steps += 1;
            rejected_last = true;
            h *= factor;
        };
        let (a, t1, h_taken) = attempt;
        result.stats.accepted_steps += 1;
        result.step_ends.push(t1);

        // Indicators at the step end; crossings of active ones.
        let mut ghi = vec![0.0; nz];
        rhs.indicators(t1, &a.y1, &mut ghi)?;
        let crossing: Vec<usize> = (0..nz).filter(|&i| gactive[i] && sign_crossed(glo[i], ghi[i])).collect();
        let (t_ev, state_event) = if crossing.is_empty() {
            (t1, None)
        } else {
            let (tr, i) = locate(&mut rhs, &a.dense, &crossing, &glo, &ghi, t, t1)?;
            (tr, Some(i))
        };
        rhs_evals += rhs.evaluations;
        // The state at the step's (possibly shortened) end.
        let x_ev: Vec<f64> = if t_ev == t1 {
            a.y1.clone()
        } else {
            let mut v = vec![0.0; nx];
            a.dense.eval(t_ev, &mut v);
            v
        };
        // Deactivated indicators come back once non-zero.
        if state_event.is_none() {
            for i in 0..nz {
                if !gactive[i] && ghi[i] != 0.0 {
                    gactive[i] = true;
                }
                glo[i] = ghi[i];
            }
        }
        // The FMU at the accepted point.
        check(model.set_time(t_ev), "fmi2SetTime", t_ev)?;
        check(model.set_continuous_states(&x_ev), "fmi2SetContinuousStates", t_ev)?;
        let (status, enter_event_mode, terminate) = model.completed_integrator_step();
        check(status, "fmi2CompletedIntegratorStep", t_ev)?;
        if terminate {
            break;
        }
        let time_event = t_next.is_some_and(|te| t_ev >= te);
        let event = enter_event_mode || time_event || state_event.is_some();
        // Output points inside the step, from the dense output.
        record_grid(model, &mut result, &mut next_grid, n_grid, &grid_time, t_ev, &x_ev, Some(&a.dense), !event, &mut y)?;
        t = t_ev;
        x = x_ev;
        f0 = if state_event.is_none() { a.f1.clone() } else { f0 };
        if !event {
            continue;
        }
        check(model.set_time(t), "fmi2SetTime", t)?;
        check(model.set_continuous_states(&x), "fmi2SetContinuousStates", t)?;
        if events_here.0 == t {
            events_here.1 += 1;
            if events_here.1 > MAX_EVENTS_AT_ONE_TIME {
                return Err(MeError::EventsChatter { t });
            }
        } else {
            events_here = (t, 1);
        }
        // Event mode.
        check(model.enter_event_mode(), "fmi2EnterEventMode", t)?;
        event_iteration(model, &mut info, t)?;
        if info.terminate_simulation != FMI2_FALSE {
            break;
        }
        check(model.enter_continuous_time_mode(), "fmi2EnterContinuousTimeMode", t)?;
        t_next = (info.next_event_time_defined != FMI2_FALSE).then_some(info.next_event_time);
        let reinitialized = info.values_of_continuous_states_changed != FMI2_FALSE
            || info.nominals_of_continuous_states_changed != FMI2_FALSE;
        result.events.push(Event {
            time: t,
            kind: match state_event {
                Some(i) => EventKind::State(i),
                None if time_event => EventKind::Time,
                None => EventKind::Step,
            },
            reinitialized,
        });
        if reinitialized {
            check(model.get_continuous_states(&mut x), "fmi2GetContinuousStates", t)?;
            if info.nominals_of_continuous_states_changed != FMI2_FALSE {
                check(model.get_nominals(&mut nominal), "fmi2GetNominalsOfContinuousStates", t)?;
                atol = nominal.iter().map(|v| rtol * v.abs()).collect();
            }
            reinit!();
        } else {
            // No re-initialization: the integrator keeps its step size and history. CVODE's
            // cvRcheck2: indicators (of the new modes) at t; any exactly zero is evaluated at
            // t + ttol with the state from the history (the dense output of the step the event
            // was found in); zero at both is the error.
            let mut rhs = Rhs { model: &mut *model, evaluations: 0 };
            rhs.eval(t, &x, &mut f0)?;
            rhs.indicators(t, &x, &mut glo)?;
            let zero: Vec<usize> = (0..nz).filter(|&i| gactive[i] && glo[i] == 0.0).collect();
            if !zero.is_empty() {
                let dt = ttol(t, h_taken);
                let mut xs = vec![0.0; nx];
                if t + dt <= t1 {
                    a.dense.eval(t + dt, &mut xs);
                } else {
                    // past the step's end: the history's slope at its end, as CVODE does
                    for i in 0..nx {
                        xs[i] = x[i] + dt * a.f1[i];
                    }
                }
                let mut gs = vec![0.0; nz];
                rhs.indicators(t + dt, &xs, &mut gs)?;
                let still: Vec<usize> = zero.iter().copied().filter(|&i| gs[i] == 0.0).collect();
                if !still.is_empty() {
                    return Err(MeError::CloseRoots { t, ttol: dt, indicators: still });
                }
                for &i in &zero {
                    glo[i] = gs[i];
                }
            }
            for i in 0..nz {
                if !gactive[i] && glo[i] != 0.0 {
                    gactive[i] = true;
                }
            }
            rhs_evals += rhs.evaluations;
            // A step after an event restarts from the event point with the step size the
            // controller had; its history is the step just taken.
            h = h.min(h_taken.max(ttol(t, h_taken) * 1e3));
        }
        // An output point at the event time, after the event.
        record_grid(model, &mut result, &mut next_grid, n_grid, &grid_time, t, &x, None, true, &mut y)?;
        check(model.set_time(t), "fmi2SetTime", t)?;
        check(model.set_continuous_states(&x), "fmi2SetContinuousStates", t)?;
        check(model.outputs(&mut y), "fmi2GetReal", t)?;
        result.event_rows.push(y.clone());
    }
    result.stats.derivative_evaluations = rhs_evals;
    Ok(result)
}

fn event_iteration<M: MeModel>(model: &mut M, info: &mut EventInfo, t: f64) -> Result<(), MeError> {
    let mut acc = EventInfo::default();
    for _ in 0..MAX_EVENT_ITERATIONS {
        *info = EventInfo::default();
        check(model.new_discrete_states(info), "fmi2NewDiscreteStates", t)?;
        acc.values_of_continuous_states_changed |= info.values_of_continuous_states_changed;
        acc.nominals_of_continuous_states_changed |= info.nominals_of_continuous_states_changed;
        if info.terminate_simulation != FMI2_FALSE {
            break;
        }
        if info.new_discrete_states_needed == FMI2_FALSE {
            info.values_of_continuous_states_changed = acc.values_of_continuous_states_changed;
            info.nominals_of_continuous_states_changed = acc.nominals_of_continuous_states_changed;
            return Ok(());
        }
    }
    if info.terminate_simulation != FMI2_FALSE {
        return Ok(());
    }
    Err(MeError::EventIterationDoesNotConverge { t })
}

/// Hairer's starting step (Solving ODEs I, II.4): h with h^5 ||f''|| ~ 0.01, bounded by 100 h0.
fn initial_step(x: &[f64], f: &[f64], atol: &[f64], rtol: f64, span: f64) -> f64 {
    let n = x.len().max(1) as f64;
    let sc: Vec<f64> = (0..x.len()).map(|i| atol[i] + rtol * x[i].abs()).collect();
    let d0 = ((0..x.len()).map(|i| (x[i] / sc[i]).powi(2)).sum::<f64>() / n).sqrt();
    let d1 = ((0..x.len()).map(|i| (f[i] / sc[i]).powi(2)).sum::<f64>() / n).sqrt();
    let h0 = if d0 < 1e-5 || d1 < 1e-5 { 1e-6 } else { 0.01 * d0 / d1 };
    h0.min(span).max(1e-12 * span.max(1.0))
}

/// Records the output points in (t of the last record, t_end) from the dense output, and the one
/// at t_end if `include_end` (not when an event is handled at t_end: that point is recorded after
/// the event, as CS reports a communication point that coincides with an event).
#[allow(clippy::too_many_arguments)]
fn record_grid<M: MeModel>(
    model: &mut M,
    result: &mut MeResult,
    next: &mut usize,
    n_grid: usize,
    grid_time: &dyn Fn(usize) -> f64,
    t_end: f64,
    x_end: &[f64],
    dense: Option<&Dense>,
    include_end: bool,
    y: &mut [f64],
) -> Result<(), MeError> {
    let mut xs = vec![0.0; x_end.len()];
    while *next < n_grid {
        let tg = grid_time(*next);
        if tg > t_end || (tg == t_end && !include_end) {
            break;
        }
        if tg == t_end {
            xs.copy_from_slice(x_end);
        } else {
            dense.expect("an output point before t_end lies in the step just taken").eval(tg, &mut xs);
        }
        check(model.set_time(tg), "fmi2SetTime", tg)?;
        check(model.set_continuous_states(&xs), "fmi2SetContinuousStates", tg)?;
        check(model.outputs(y), "fmi2GetReal", tg)?;
        result.grid_times.push(tg);
        result.grid.push(y.to_vec());
        *next += 1;
    }
    Ok(())
}

// ---- Running an FMU ----------------------------------------------------------------------------

/// A start value to set before initialization: a Real or an Integer (by the variable's type).
pub type StartValues<'a> = &'a [(&'a str, f64)];

fn set_start_values(inst: &mut Instance, fmu: &Fmu, start_values: StartValues) {
    for (name, value) in start_values {
        let v = fmu.variable(name).unwrap_or_else(|e| panic!("{name}: {e}"));
        let status = match v.variable_type {
            VariableType::Real => inst.set_real(&[v.value_reference], &[*value]),
            VariableType::Integer | VariableType::Enumeration => {
                inst.set_integer(&[v.value_reference], &[*value as i32])
            }
            VariableType::Boolean => inst.set_boolean(&[v.value_reference], &[*value != 0.0]),
            ref other => panic!("{name}: cannot set a {other:?} start value"),
        };
        assert_eq!(status, Status::OK, "setting {name} = {value}");
    }
}

/// Whether an output is zero up to rounding by construction: the energy balance
/// (`power_balance_residual`, `power_balance_relative`). Comparing two runs of it compares their
/// rounding; tests/python/test_energy_balance.py bounds it against the largest element power in
/// Co-Simulation and Model Exchange instead.
pub fn is_rounding_only(name: &str) -> bool {
    name.starts_with("power_balance_")
}

/// The Real outputs (causality="output") of an FMU that two runs can be compared on: names and
/// value references (not the rounding-only energy balance, see [`is_rounding_only`]).
pub fn real_outputs(fmu: &Fmu) -> (Vec<String>, Vec<ValueReference>) {
    fmu.model_description()
        .model_variables
        .iter()
        .filter(|v| v.causality == Causality::Output && v.variable_type == VariableType::Real && !is_rounding_only(&v.name))
        .map(|v| (v.name.clone(), v.value_reference))
        .unzip()
}

/// The number of continuous states (variables with a `derivative` attribute).
pub fn number_of_states(fmu: &Fmu) -> usize {
    fmu.model_description().model_variables.iter().filter(|v| v.derivative.is_some()).count()
}

/// A finished ME run of an FMU: the result, and the instance (to read `state_events` and such).
pub struct FmuRun {
    pub result: Result<MeResult, MeError>,
    pub model: MeInstance,
}

/// Instantiates `fmu` as ModelExchange, sets up the experiment with `exp.rtol`, applies the
/// start values, initializes and runs [`simulate_strict`], recording `outputs`.
pub fn run_fmu_strict(
    fmu: &std::sync::Arc<Fmu>,
    exp: MeExperiment,
    start_values: StartValues,
    outputs: &[ValueReference],
) -> FmuRun {
    let md = fmu.model_description();
    let nz = md.number_of_event_indicators.unwrap_or(0) as usize;
    let nx = number_of_states(fmu);
    let mut inst = Instance::new(
        fmu,
        InstantiateOptions::new(format!("{}-me", md.model_name)).fmu_type(Fmi2Type::ModelExchange),
    )
    .expect("instantiate ModelExchange");
    assert_eq!(inst.setup_experiment(Some(exp.rtol), exp.start, Some(exp.stop)), Status::OK);
    set_start_values(&mut inst, fmu, start_values);
    assert_eq!(inst.enter_initialization_mode(), Status::OK);
    assert_eq!(inst.exit_initialization_mode(), Status::OK);
    let mut model = MeInstance { inst, outputs: outputs.to_vec() };
    let result = simulate_strict(&mut model, nx, nz, outputs.len(), exp);
    FmuRun { result, model }
}

/// The Co-Simulation run of the same experiment: fmi2DoStep over each output interval with the
/// tolerance `exp.rtol`; one row per output point, and `counter` (an Integer, e.g.
/// `state_events`) read at every point.
pub fn run_fmu_co_simulation(
    fmu: &std::sync::Arc<Fmu>,
    exp: MeExperiment,
    start_values: StartValues,
    outputs: &[ValueReference],
    counter: Option<ValueReference>,
) -> (Vec<f64>, Vec<Vec<f64>>, Vec<i32>) {
    let md = fmu.model_description();
    let mut inst = Instance::new(fmu, InstantiateOptions::new(format!("{}-cs", md.model_name)))
        .expect("instantiate CoSimulation");
    assert_eq!(inst.setup_experiment(Some(exp.rtol), exp.start, Some(exp.stop)), Status::OK);
    set_start_values(&mut inst, fmu, start_values);
    assert_eq!(inst.enter_initialization_mode(), Status::OK);
    assert_eq!(inst.exit_initialization_mode(), Status::OK);
    let n = ((exp.stop - exp.start) / exp.output_interval - 1e-9).ceil() as usize;
    let (mut times, mut rows, mut counts) = (Vec::new(), Vec::new(), Vec::new());
    let mut y = vec![0.0; outputs.len()];
    let mut c = [0i32];
    let mut record = |inst: &mut Instance, t: f64| {
        assert_eq!(inst.get_real(outputs, &mut y), Status::OK);
        if let Some(vr) = counter {
            assert_eq!(inst.get_integer(&[vr], &mut c), Status::OK);
        }
        times.push(t);
        rows.push(y.clone());
        counts.push(c[0]);
    };
    record(&mut inst, exp.start);
    let mut t = exp.start;
    for k in 1..=n {
        let t1 = (exp.start + k as f64 * exp.output_interval).min(exp.stop);
        let status = inst.do_step(t, t1 - t, true);
        assert_eq!(status, Status::OK, "{}: fmi2DoStep({t}, {}) at tolerance {}", md.model_name, t1 - t, exp.rtol);
        t = t1;
        record(&mut inst, t);
    }
    (times, rows, counts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffi::FMI2_TRUE;

    /// y' = a y (or an oscillator) with no indicators: the integrator's accuracy and dense output.
    struct Linear {
        t: f64,
        x: Vec<f64>,
        oscillator: bool,
    }

    impl MeModel for Linear {
        fn set_time(&mut self, t: f64) -> Status {
            self.t = t;
            Status::OK
        }
        fn set_continuous_states(&mut self, x: &[f64]) -> Status {
            self.x.copy_from_slice(x);
            Status::OK
        }
        fn get_continuous_states(&mut self, x: &mut [f64]) -> Status {
            x.copy_from_slice(&self.x);
            Status::OK
        }
        fn get_nominals(&mut self, x: &mut [f64]) -> Status {
            x.fill(1.0);
            Status::OK
        }
        fn get_derivatives(&mut self, dx: &mut [f64]) -> Status {
            if self.oscillator {
                dx[0] = self.x[1];
                dx[1] = -self.x[0];
            } else {
                dx[0] = -self.x[0];
            }
            Status::OK
        }
        fn get_event_indicators(&mut self, _z: &mut [f64]) -> Status {
            Status::OK
        }
        fn completed_integrator_step(&mut self) -> (Status, bool, bool) {
            (Status::OK, false, false)
        }
        fn enter_event_mode(&mut self) -> Status {
            Status::OK
        }
        fn new_discrete_states(&mut self, info: &mut EventInfo) -> Status {
            info.new_discrete_states_needed = FMI2_FALSE;
            Status::OK
        }
        fn enter_continuous_time_mode(&mut self) -> Status {
            Status::OK
        }
        fn outputs(&mut self, y: &mut [f64]) -> Status {
            y.copy_from_slice(&self.x);
            Status::OK
        }
    }

    #[test]
    fn dense_output_matches_the_solution_of_an_oscillator() {
        for rtol in [1e-4, 1e-6, 1e-8] {
            let mut m = Linear { t: 0.0, x: vec![1.0, 0.0], oscillator: true };
            let exp = MeExperiment { start: 0.0, stop: 10.0, output_interval: 0.01, rtol };
            let r = simulate_strict(&mut m, 2, 0, 2, exp).unwrap();
            assert_eq!(r.grid_times.len(), 1001);
            let worst = r
                .grid_times
                .iter()
                .zip(&r.grid)
                .map(|(t, y)| (y[0] - t.cos()).abs().max((y[1] + t.sin()).abs()))
                .fold(0.0, f64::max);
            // Global error of a tolerance-controlled method over ~1.6 periods: a few rtol.
            assert!(worst < 20.0 * rtol, "rtol {rtol}: worst error {worst:e}");
            let mut m = Linear { t: 0.0, x: vec![1.0], oscillator: false };
            let r = simulate_strict(&mut m, 1, 0, 1, exp).unwrap();
            let worst =
                r.grid_times.iter().zip(&r.grid).map(|(t, y)| (y[0] - (-t).exp()).abs()).fold(0.0, f64::max);
            assert!(worst < 20.0 * rtol, "decay rtol {rtol}: worst error {worst:e}");
        }
    }

    /// A rotor with Coulomb friction, stuck at w = 0 until a ramped torque exceeds the static
    /// friction at t = 1: stuck, the indicator is the margin 1 - |T(t)|; slipping, it is w times the
    /// direction. At breakaway the slipping indicator is w = 0 exactly. `reinit_at_breakaway`
    /// selects what NewDiscreteStates reports then; `bias` (the fix) starts the slipping
    /// indicator's sign off the right side, as the real fix does: it evaluates to the slip
    /// acceleration's sign while w is exactly 0.
    struct Friction {
        t: f64,
        x: Vec<f64>,
        stuck: bool,
        reinit_at_breakaway: bool,
        fixed: bool,
        events: usize,
    }

    impl Friction {
        fn torque(&self) -> f64 {
            self.t // ramp: T = t, breaks loose at T = 1
        }
        fn indicator(&self) -> f64 {
            if self.stuck {
                1.0 - self.torque().abs()
            } else if self.fixed && self.x[0] == 0.0 {
                self.torque() - 0.8 // w exactly 0: the sign of the acceleration
            } else {
                self.x[0]
            }
        }
    }

    impl MeModel for Friction {
        fn set_time(&mut self, t: f64) -> Status {
            self.t = t;
            Status::OK
        }
        fn set_continuous_states(&mut self, x: &[f64]) -> Status {
            self.x.copy_from_slice(x);
            Status::OK
        }
        fn get_continuous_states(&mut self, x: &mut [f64]) -> Status {
            x.copy_from_slice(&self.x);
            Status::OK
        }
        fn get_nominals(&mut self, x: &mut [f64]) -> Status {
            x.fill(1.0);
            Status::OK
        }
        fn get_derivatives(&mut self, dx: &mut [f64]) -> Status {
            dx[0] = if self.stuck { 0.0 } else { self.torque() - 0.8 };
            Status::OK
        }
        fn get_event_indicators(&mut self, z: &mut [f64]) -> Status {
            z[0] = self.indicator();
            Status::OK
        }
        fn completed_integrator_step(&mut self) -> (Status, bool, bool) {
            (Status::OK, false, false)
        }
        fn enter_event_mode(&mut self) -> Status {
            Status::OK
        }
        fn new_discrete_states(&mut self, info: &mut EventInfo) -> Status {
            *info = EventInfo::default();
            if self.stuck && self.torque().abs() >= 1.0 {
                self.stuck = false;
                self.events += 1;
                if self.reinit_at_breakaway {
                    info.values_of_continuous_states_changed = FMI2_TRUE;
                }
            }
            Status::OK
        }
        fn enter_continuous_time_mode(&mut self) -> Status {
            Status::OK
        }
        fn outputs(&mut self, y: &mut [f64]) -> Status {
            y[0] = self.x[0];
            Status::OK
        }
    }

    fn friction(reinit_at_breakaway: bool, fixed: bool) -> (Result<MeResult, MeError>, Friction) {
        let mut m = Friction { t: 0.0, x: vec![0.0], stuck: true, reinit_at_breakaway, fixed, events: 0 };
        let exp = MeExperiment { start: 0.0, stop: 2.0, output_interval: 0.1, rtol: 1e-6 };
        (simulate_strict(&mut m, 1, 1, 1, exp), m)
    }

    #[test]
    fn an_indicator_left_at_zero_without_reinitialization_is_cvodes_close_root_error() {
        let (r, m) = friction(false, false);
        match &r {
            Err(MeError::CloseRoots { t, indicators, .. }) => {
                assert!((t - 1.0).abs() < 1e-9, "at the breakaway, not {t}");
                assert_eq!(indicators, &vec![0]);
                assert!(format!("{}", r.clone().unwrap_err()).contains("Root found at and very near t"));
            }
            other => panic!("expected CloseRoots, got {other:?}"),
        }
        assert_eq!(m.events, 1);
    }

    #[test]
    fn the_same_zero_after_a_reinitialization_is_not_a_crossing() {
        let (r, m) = friction(true, false);
        let r = r.expect("a re-initialized zero is deactivated, not an error");
        assert_eq!(m.events, 1);
        assert_eq!(r.events.len(), 1);
        assert!(r.events[0].reinitialized && (r.events[0].time - 1.0).abs() < 1e-9);
        // w = (t-0.8)(t) integrated from 1: w(2) = [t^2/2 - 0.8 t]_1^2 = 1.5 - 0.8 = 0.7
        assert!((r.grid.last().unwrap()[0] - 0.7).abs() < 1e-6);
    }

    #[test]
    fn an_indicator_that_is_signed_at_the_switch_passes_without_reinitialization() {
        let (r, m) = friction(false, true);
        let r = r.expect("the fixed model passes the strict rule");
        assert_eq!((m.events, r.events.len()), (1, 1));
        assert!(!r.events[0].reinitialized);
        assert!((r.grid.last().unwrap()[0] - 0.7).abs() < 1e-6, "{:?}", r.grid.last());
    }
}
