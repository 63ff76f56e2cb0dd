//! How the master steps: [`Algorithm`] (Jacobi or Gauss-Seidel), [`ErrorControl`] (optional
//! step rejection) and the [`Master`] that holds a system with its options.

use std::fmt;

use super::error::{config, Result};
use super::results::{ResultTable, Stats};
use super::simulation::Simulation;
use super::system::System;

/// The order of the FMUs within a macro step.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Algorithm {
    /// Every FMU steps from the inputs of the same communication point; the outputs are
    /// exchanged afterwards. (The FMUs are called one after the other, in the order listed.)
    Jacobi,
    /// The FMUs step one after the other in `order` (instance names, every instance once; empty:
    /// as listed in the [`System`]); each gets, before its step, the outputs of those already
    /// stepped at the end of the macro step.
    GaussSeidel { order: Vec<String> },
}

impl Algorithm {
    /// Gauss-Seidel in the order the components are listed.
    pub fn gauss_seidel() -> Algorithm {
        Algorithm::GaussSeidel { order: Vec::new() }
    }

    /// Gauss-Seidel in this order of instance names.
    pub fn gauss_seidel_in<S: Into<String>>(order: impl IntoIterator<Item = S>) -> Algorithm {
        Algorithm::GaussSeidel {
            order: order.into_iter().map(Into::into).collect(),
        }
    }
}

impl fmt::Display for Algorithm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Algorithm::Jacobi => f.write_str("Jacobi"),
            Algorithm::GaussSeidel { .. } => f.write_str("Gauss-Seidel"),
        }
    }
}

/// Step rejection on the coupling error.
///
/// Before each macro step the master saves every FMU's state (`fmi2GetFMUstate`). After it, it
/// compares, for each connection, the input signal the consumer was given over the step (a
/// constant, or a straight line with input derivatives) with the source's output at both ends
/// of the step:
///
/// `e = max(|u(t) - y(t)|, |u(t+h) - y(t+h)|) / max(|y(t)|, |y(t+h)|, nominal)`
///
/// (`nominal` of the source output, default 1). If the largest `e` exceeds `tolerance`, every
/// state is restored (`fmi2SetFMUstate`) and the step is retried with half the size, down to
/// `min_step`; a step at `min_step` is accepted and counted in
/// [`Stats::accepted_over_tolerance`]. After a step with `e < tolerance / 4` the step doubles
/// again (never beyond the communication step). Sub-steps are binary divisions of the
/// communication step, so every communication point is still hit and recorded.
///
/// For Gauss-Seidel with interpolated inputs, a connection whose source stepped first is
/// matched at both ends by construction and contributes 0: the estimate then sees only the
/// connections against the stepping order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorControl {
    pub tolerance: f64,
    /// Smallest macro step, s; `None`: the communication step / 1024.
    pub min_step: Option<f64>,
}

impl ErrorControl {
    pub fn new(tolerance: f64) -> ErrorControl {
        ErrorControl {
            tolerance,
            min_step: None,
        }
    }

    pub fn min_step(mut self, min_step: f64) -> ErrorControl {
        self.min_step = Some(min_step);
        self
    }
}

/// A co-simulation master: a [`System`] and how to run it.
///
/// ```no_run
/// use fmi_host::master::{Algorithm, Component, Master, System};
/// use fmi_host::Fmu;
/// let rlc = Fmu::load("dist/RlcCircuit.fmu")?;
/// let system = System::new()
///     .with(Component::new("source", &rlc))
///     .with(Component::new("load", &rlc).real("U_amplitude", 0.0))
///     .connect("source.u_capacitor", "load.u_in");
/// let outcome = Master::new(system, 1e-4, 0.05)
///     .algorithm(Algorithm::gauss_seidel())
///     .record(["source.u_capacitor", "load.i_absorbed"])
///     .run()?;
/// println!("{}", outcome.results.to_csv());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct Master {
    pub(crate) system: System,
    pub(crate) algorithm: Algorithm,
    pub(crate) start_time: f64,
    pub(crate) stop_time: f64,
    pub(crate) communication_step: f64,
    pub(crate) extrapolation: bool,
    pub(crate) error_control: Option<ErrorControl>,
    pub(crate) tolerance: Option<f64>,
    pub(crate) record: Vec<String>,
}

impl Master {
    /// A master stepping `system` from 0 to `stop_time` with `communication_step`, Jacobi,
    /// input extrapolation where the FMUs support it, no error control, the FMUs' default
    /// tolerance, nothing recorded.
    pub fn new(system: System, communication_step: f64, stop_time: f64) -> Master {
        Master {
            system,
            algorithm: Algorithm::Jacobi,
            start_time: 0.0,
            stop_time,
            communication_step,
            extrapolation: true,
            error_control: None,
            tolerance: None,
            record: Vec::new(),
        }
    }

    pub fn algorithm(mut self, algorithm: Algorithm) -> Master {
        self.algorithm = algorithm;
        self
    }

    pub fn start_time(mut self, start_time: f64) -> Master {
        self.start_time = start_time;
        self
    }

    /// First-order input extrapolation (default true): where the consumer declares
    /// `canInterpolateInputs` and the source `maxOutputDerivativeOrder >= 1`, the consumer gets
    /// the source's output derivative (`fmi2GetRealOutputDerivatives`) as input derivative
    /// (`fmi2SetRealInputDerivatives`), so its input follows y + dy/dt (t - t_k) over the step;
    /// with Gauss-Seidel, a consumer whose source already stepped gets the straight line between
    /// the source's outputs at both ends of the step (interpolation). Elsewhere, and with
    /// `false`, inputs are held constant over a step.
    pub fn extrapolation(mut self, on: bool) -> Master {
        self.extrapolation = on;
        self
    }

    pub fn error_control(mut self, error_control: Option<ErrorControl>) -> Master {
        self.error_control = error_control;
        self
    }

    /// Relative tolerance handed to every FMU in `fmi2SetupExperiment` (`None`: the FMU's own).
    pub fn tolerance(mut self, tolerance: Option<f64>) -> Master {
        self.tolerance = tolerance;
        self
    }

    /// Variables to record at every communication point, as `"instance.variable"`.
    pub fn record<S: Into<String>>(mut self, variables: impl IntoIterator<Item = S>) -> Master {
        self.record.extend(variables.into_iter().map(Into::into));
        self
    }

    pub fn system(&self) -> &System {
        &self.system
    }

    pub(crate) fn check(&self) -> Result<()> {
        let (t0, t1, h) = (self.start_time, self.stop_time, self.communication_step);
        if !(t0.is_finite() && t1.is_finite() && t1 > t0) {
            return Err(config(format!(
                "stop time {t1} must be finite and after the start time {t0}"
            )));
        }
        if !(h.is_finite() && h > 0.0) {
            return Err(config(format!("communication step {h} must be positive")));
        }
        if let Some(ec) = &self.error_control {
            if !(ec.tolerance.is_finite() && ec.tolerance > 0.0) {
                return Err(config(format!(
                    "error-control tolerance {} must be positive",
                    ec.tolerance
                )));
            }
            if let Some(m) = ec.min_step {
                if !(m.is_finite() && m > 0.0 && m <= h) {
                    return Err(config(format!(
                        "minimum step {m} must be positive and at most the communication step {h}"
                    )));
                }
            }
        }
        if let Some(tol) = self.tolerance {
            if !(tol.is_finite() && tol > 0.0) {
                return Err(config(format!("tolerance {tol} must be positive")));
            }
        }
        Ok(())
    }

    /// Instantiates and initializes every FMU and exchanges the initial outputs: a
    /// [`Simulation`] at the start time, to step by hand.
    pub fn initialize(&self) -> Result<Simulation> {
        Simulation::new(self)
    }

    /// Initializes, steps to the stop time, terminates.
    pub fn run(&self) -> Result<Outcome> {
        let mut simulation = self.initialize()?;
        simulation.run_to_end()?;
        simulation.finish()
    }
}

/// What [`Master::run`] returns.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub results: ResultTable,
    pub stats: Stats,
}
