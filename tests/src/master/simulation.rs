//! [`Simulation`]: the instantiated system, stepped macro step by macro step.

use super::algorithm::{Algorithm, ErrorControl, Master, Outcome};
use super::error::{config, MasterError, Result};
use super::results::{ResultTable, Stats};
use super::system::{Component, Link, Port, System};
use crate::ffi::{FmiVersion, Status, ValueReference};
use crate::instance::{Instance, InstantiateOptions};
use crate::model_description::VariableType;
use crate::state::FmuState;

/// How many log records of the failing instance a [`MasterError::Call`] carries.
const LOG_TAIL: usize = 8;
/// Deepest binary division of a communication step (error control).
const MAX_LEVEL: u32 = 30;

/// `status` as a [`Result`]: OK and Warning pass, anything else names the instance and call.
fn check(instance: &Instance, call: &'static str, time: f64, status: Status) -> Result<()> {
    if status.is_ok_or_warning() {
        return Ok(());
    }
    let records = instance.log().records();
    let tail = records[records.len().saturating_sub(LOG_TAIL)..].to_vec();
    Err(MasterError::Call {
        instance: instance.name().to_owned(),
        call: call_name(instance, call),
        time,
        status,
        log: tail,
    })
}

/// The function an instance's call went to: `call` (the master names its calls by their FMI 2.0
/// names), or, for an FMI 3.0 instance, the FMI 3.0 function [`Instance`] calls instead.
fn call_name(instance: &Instance, call: &'static str) -> &'static str {
    if instance.fmi_version() == FmiVersion::Fmi2 {
        return call;
    }
    match call {
        "fmi2GetReal" => "fmi3GetFloat64",
        "fmi2SetReal" => "fmi3SetFloat64",
        "fmi2GetInteger" => "fmi3GetInt32/fmi3GetInt64",
        "fmi2SetInteger" => "fmi3SetInt32/fmi3SetInt64",
        "fmi2GetBoolean" => "fmi3GetBoolean",
        "fmi2SetBoolean" => "fmi3SetBoolean",
        "fmi2GetFMUstate" => "fmi3GetFMUState",
        "fmi2SetFMUstate" => "fmi3SetFMUState",
        "fmi2GetRealOutputDerivatives" => "fmi3GetOutputDerivatives",
        "fmi2DoStep" => "fmi3DoStep",
        "fmi2EnterInitializationMode" => "fmi3EnterInitializationMode",
        "fmi2ExitInitializationMode" => "fmi3ExitInitializationMode",
        "fmi2Terminate" => "fmi3Terminate",
        other => other,
    }
}

/// A recorded variable.
#[derive(Clone, Copy, Debug)]
struct Probe {
    instance: usize,
    vr: ValueReference,
    kind: VariableType,
}

/// The result of one macro step.
enum StepOutcome {
    /// Every FMU completed the step; the largest coupling error estimate.
    Done { error: f64 },
    /// This instance returned `fmi2Discard` from `fmi2DoStep`.
    Discarded { instance: usize },
}

/// An initialized system at its current communication point.
///
/// Made by [`Master::initialize`]; [`Simulation::step`] advances one communication step,
/// [`Simulation::finish`] terminates. Dropping it frees every instance (and saved state).
pub struct Simulation {
    instances: Vec<Instance>,
    links: Vec<Link>,
    /// Connections in feedthrough (topological) order.
    exchange_order: Vec<usize>,
    /// Per connection: the consumer follows the source's output derivative over a step.
    extrapolate: Vec<bool>,
    /// Per connection: the consumer can follow a straight line (Gauss-Seidel interpolation).
    interpolate: Vec<bool>,
    /// Per instance: the connections into it.
    inputs_of: Vec<Vec<usize>>,
    gauss_seidel: bool,
    /// Instance indices in stepping order.
    step_order: Vec<usize>,
    error_control: Option<ErrorControl>,
    /// Error control: current division level of the communication step (h = H / 2^level), and
    /// the deepest one allowed.
    level: u32,
    max_level: u32,
    states: Vec<Option<FmuState>>,
    /// Per connection, at the current time: the source's output and output derivative (0 when
    /// not extrapolated).
    y: Vec<f64>,
    dy: Vec<f64>,
    /// Per connection, for the step being made: the input value and slope given to the consumer.
    applied: Vec<(f64, f64)>,
    start_time: f64,
    communication_step: f64,
    stop_time: f64,
    /// Number of communication steps and the index of the current communication point.
    steps: usize,
    /// The stop time is a whole number of communication steps after the start time.
    whole_steps: bool,
    k: usize,
    time: f64,
    probes: Vec<Probe>,
    table: ResultTable,
    stats: Stats,
}

impl Simulation {
    pub(crate) fn new(master: &Master) -> Result<Simulation> {
        master.check()?;
        let system = &master.system;
        if system.components.is_empty() {
            return Err(config("the system has no component"));
        }
        let links = system.resolve()?;
        let exchange_order = system.exchange_order(&links)?;
        let gauss_seidel = matches!(master.algorithm, Algorithm::GaussSeidel { .. });
        let step_order = step_order(master)?;
        let n = system.components.len();
        let mut inputs_of = vec![Vec::new(); n];
        for (j, link) in links.iter().enumerate() {
            inputs_of[link.to_instance].push(j);
        }
        let extrapolate: Vec<bool> = links
            .iter()
            .map(|l| master.extrapolation && l.consumer_interpolates && l.source_has_derivatives)
            .collect();
        let interpolate: Vec<bool> = links
            .iter()
            .map(|l| master.extrapolation && l.consumer_interpolates)
            .collect();

        let h = master.communication_step;
        let ratio = (master.stop_time - master.start_time) / h;
        let whole_steps = (ratio - ratio.round()).abs() < 1e-6;
        let steps = if whole_steps {
            ratio.round()
        } else {
            ratio.ceil()
        } as usize;
        let max_level = match master.error_control {
            Some(ec) => {
                let min_step = ec.min_step.unwrap_or(h / 1024.0);
                ((h / min_step).log2() - 1e-9)
                    .ceil()
                    .clamp(0.0, f64::from(MAX_LEVEL)) as u32
            }
            None => 0,
        };
        if master.error_control.is_some() {
            check_error_control_support(system, max_level > 0)?;
        }
        let probes = master
            .record
            .iter()
            .map(|port| probe(system, port))
            .collect::<Result<Vec<Probe>>>()?;

        let mut instances = Vec::with_capacity(n);
        for c in &system.components {
            instances.push(instantiate(c, master)?);
        }
        for inst in &mut instances {
            let status = inst.exit_initialization_mode();
            check(
                inst,
                "fmi2ExitInitializationMode",
                master.start_time,
                status,
            )?;
        }

        let m = links.len();
        let mut simulation = Simulation {
            states: (0..n).map(|_| None).collect(),
            instances,
            links,
            exchange_order,
            extrapolate,
            interpolate,
            inputs_of,
            gauss_seidel,
            step_order,
            error_control: master.error_control,
            level: 0,
            max_level,
            y: vec![0.0; m],
            dy: vec![0.0; m],
            applied: vec![(0.0, 0.0); m],
            start_time: master.start_time,
            communication_step: h,
            stop_time: master.stop_time,
            steps,
            whole_steps,
            k: 0,
            time: master.start_time,
            probes,
            table: ResultTable::new(master.record.clone()),
            stats: Stats {
                smallest_step: f64::INFINITY,
                ..Stats::default()
            },
        };
        simulation.exchange(master.start_time)?;
        simulation.record()?;
        Ok(simulation)
    }

    /// The current communication point, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Whether the stop time is reached.
    pub fn is_finished(&self) -> bool {
        self.k >= self.steps
    }

    /// The rows recorded so far.
    pub fn results(&self) -> &ResultTable {
        &self.table
    }

    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// Whether the connection into `input` (`"instance.variable"`) is extrapolated with the
    /// source's output derivative (None: no connection into it).
    pub fn is_extrapolated(&self, input: &str) -> Option<bool> {
        self.links
            .iter()
            .position(|l| l.to == input)
            .map(|j| self.extrapolate[j])
    }

    /// The input derivative given to `input` (`"instance.variable"`) at the current
    /// communication point: the source's output derivative if the connection is extrapolated,
    /// else 0 (None: no connection into it).
    pub fn input_derivative(&self, input: &str) -> Option<f64> {
        self.links
            .iter()
            .position(|l| l.to == input)
            .map(|j| self.dy[j])
    }

    /// The instance called `name` (to read or set variables between steps).
    pub fn instance_mut(&mut self, name: &str) -> Option<&mut Instance> {
        self.instances.iter_mut().find(|i| i.name() == name)
    }

    /// The current value of a Real variable `"instance.variable"`.
    pub fn get_real(&mut self, port: &str) -> Result<f64> {
        let Port { instance, variable } = Port::parse(port).map_err(config)?;
        let time = self.time;
        let inst = self
            .instance_mut(&instance)
            .ok_or_else(|| config(format!("no instance named {instance:?}")))?;
        let vr = inst
            .fmu()
            .vr(&variable)
            .map_err(|source| MasterError::Host {
                instance: instance.clone(),
                source,
            })?;
        let mut value = [0.0];
        let status = inst.get_real(&[vr], &mut value);
        check(inst, "fmi2GetReal", time, status)?;
        Ok(value[0])
    }

    fn communication_point(&self, k: usize) -> f64 {
        if k >= self.steps {
            self.stop_time
        } else {
            self.start_time + k as f64 * self.communication_step
        }
    }

    /// Advances one communication step (divided into smaller macro steps under error control)
    /// and records a row. Returns false, doing nothing, once the stop time is reached.
    pub fn step(&mut self) -> Result<bool> {
        if self.is_finished() {
            return Ok(false);
        }
        let (t0, t1) = (
            self.communication_point(self.k),
            self.communication_point(self.k + 1),
        );
        // The step handed to the FMUs is the communication step itself (not t1 - t0, which
        // differs from it by rounding), except for a shorter last step.
        let h = if self.k + 1 == self.steps && !self.whole_steps {
            self.stop_time - t0
        } else {
            self.communication_step
        };
        match self.error_control {
            None => match self.macro_step(t0, h)? {
                StepOutcome::Done { error } => self.accepted(h, error),
                StepOutcome::Discarded { instance } => return Err(self.discard_error(instance, t0)),
            },
            Some(ec) => self.controlled_steps(t0, h, ec)?,
        }
        self.k += 1;
        self.time = t1;
        self.stats.communication_steps += 1;
        self.record()?;
        Ok(true)
    }

    /// Steps to the stop time.
    pub fn run_to_end(&mut self) -> Result<()> {
        while self.step()? {}
        Ok(())
    }

    /// `fmi2Terminate` on every instance, then frees them; the results and counters.
    pub fn finish(mut self) -> Result<Outcome> {
        let time = self.time;
        for inst in &mut self.instances {
            let status = inst.terminate();
            check(inst, "fmi2Terminate", time, status)?;
        }
        Ok(Outcome {
            results: std::mem::take(&mut self.table),
            stats: std::mem::take(&mut self.stats),
        })
    }

    fn accepted(&mut self, h: f64, error: f64) {
        self.stats.accepted_steps += 1;
        self.stats.smallest_step = self.stats.smallest_step.min(h);
        self.stats.largest_error_estimate = self.stats.largest_error_estimate.max(error);
    }

    fn discard_error(&self, instance: usize, time: f64) -> MasterError {
        check(
            &self.instances[instance],
            "fmi2DoStep",
            time,
            Status::DISCARD,
        )
        .expect_err("fmi2Discard is not OK")
    }

    /// Error control over one communication step [t0, t0 + span]: binary sub-steps, rejected
    /// and halved while the error estimate exceeds the tolerance, doubled back when it is small.
    fn controlled_steps(&mut self, t0: f64, span: f64, ec: ErrorControl) -> Result<()> {
        let total: u64 = 1 << self.max_level;
        // Dividing by a power of two is exact: every sub-step is a whole number of `unit`s.
        let unit = span / total as f64;
        let mut pos: u64 = 0;
        while pos < total {
            let units = 1u64 << (self.max_level - self.level);
            let t = t0 + pos as f64 * unit;
            let h = units as f64 * unit;
            self.save_states(t)?;
            let outcome = self.macro_step(t, h)?;
            let reject = match outcome {
                StepOutcome::Done { error } => error > ec.tolerance,
                StepOutcome::Discarded { .. } => true,
            };
            if reject && self.level < self.max_level {
                self.restore_states(t)?;
                self.stats.rejected_steps += 1;
                self.level += 1;
                continue;
            }
            let error = match outcome {
                StepOutcome::Done { error } => error,
                StepOutcome::Discarded { instance } => return Err(self.discard_error(instance, t)),
            };
            self.accepted(h, error);
            if error > ec.tolerance {
                self.stats.accepted_over_tolerance += 1;
            }
            pos += units;
            if error < 0.25 * ec.tolerance && self.level > 0 && pos & (2 * units - 1) == 0 {
                self.level -= 1;
            }
        }
        Ok(())
    }

    fn save_states(&mut self, time: f64) -> Result<()> {
        for (inst, slot) in self.instances.iter_mut().zip(&mut self.states) {
            match slot {
                Some(state) => {
                    let status = inst.update_fmu_state(state);
                    check(inst, "fmi2GetFMUstate", time, status)?;
                }
                None => {
                    let (status, state) = inst.get_fmu_state();
                    check(inst, "fmi2GetFMUstate", time, status)?;
                    *slot = state;
                }
            }
        }
        Ok(())
    }

    /// Restores the saved states and the inputs of time `time`.
    fn restore_states(&mut self, time: f64) -> Result<()> {
        for (inst, slot) in self.instances.iter_mut().zip(&self.states) {
            let state = slot.as_ref().expect("saved before the step");
            let status = inst.set_fmu_state(state);
            check(inst, "fmi2SetFMUstate", time, status)?;
        }
        self.exchange(time)
    }

    fn get_output(&mut self, j: usize, time: f64) -> Result<f64> {
        let link = &self.links[j];
        let inst = &mut self.instances[link.from_instance];
        let mut value = [0.0];
        let status = inst.get_real(&[link.from_vr], &mut value);
        check(inst, "fmi2GetReal", time, status)?;
        Ok(value[0])
    }

    /// Gives connection `j`'s consumer the input `value` (and, if `slope` is Some, that input
    /// derivative for the coming step; fmi2SetReal alone leaves the input constant).
    fn set_input(&mut self, j: usize, time: f64, value: f64, slope: Option<f64>) -> Result<()> {
        let link = &self.links[j];
        let inst = &mut self.instances[link.to_instance];
        let status = inst.set_real(&[link.to_vr], &[value]);
        check(inst, "fmi2SetReal", time, status)?;
        if let Some(slope) = slope {
            let status = inst
                .set_real_input_derivatives(&[link.to_vr], &[1], &[slope])
                .map_err(|source| MasterError::Host { instance: inst.name().to_owned(), source })?;
            check(inst, "fmi2SetRealInputDerivatives", time, status)?;
        }
        Ok(())
    }

    /// Copies every connection at `time`, in feedthrough order, then gives the extrapolated
    /// connections their output derivatives; updates `y` and `dy`.
    ///
    /// Two passes: the derivative of an output can depend on inputs its value does not depend
    /// on (a speed's derivative depends on the torque input), so derivatives are read only
    /// once every input holds its new value; their pass is in feedthrough order too, so that a
    /// direct-feedthrough output's derivative sees the derivatives of its inputs.
    fn exchange(&mut self, time: f64) -> Result<()> {
        for idx in 0..self.exchange_order.len() {
            let j = self.exchange_order[idx];
            let value = self.get_output(j, time)?;
            self.set_input(j, time, value, None)?;
            self.y[j] = value;
            self.dy[j] = 0.0;
        }
        for idx in 0..self.exchange_order.len() {
            let j = self.exchange_order[idx];
            if !self.extrapolate[j] {
                continue;
            }
            let link = &self.links[j];
            let inst = &mut self.instances[link.from_instance];
            let mut d = [0.0];
            let status = inst.get_real_output_derivatives(&[link.from_vr], &[1], &mut d);
            check(inst, "fmi2GetRealOutputDerivatives", time, status)?;
            let inst = &mut self.instances[link.to_instance];
            let status = inst
                .set_real_input_derivatives(&[link.to_vr], &[1], &d)
                .map_err(|source| MasterError::Host { instance: inst.name().to_owned(), source })?;
            check(inst, "fmi2SetRealInputDerivatives", time, status)?;
            self.dy[j] = d[0];
        }
        Ok(())
    }

    fn do_step(&mut self, i: usize, t: f64, h: f64) -> Result<bool> {
        let no_set_prior = self.error_control.is_none();
        let inst = &mut self.instances[i];
        let status = inst.do_step(t, h, no_set_prior);
        self.stats.do_step_calls += 1;
        if status == Status::DISCARD {
            return Ok(false);
        }
        check(inst, "fmi2DoStep", t, status)?;
        Ok(true)
    }

    /// One macro step [t, t + h] of every FMU, then the exchange at t + h.
    fn macro_step(&mut self, t: f64, h: f64) -> Result<StepOutcome> {
        // Inputs as set by the exchange at t: the source's value, with its slope if extrapolated.
        for j in 0..self.links.len() {
            self.applied[j] = (self.y[j], self.dy[j]);
        }
        let mut stepped = vec![false; self.instances.len()];
        for idx in 0..self.step_order.len() {
            let i = self.step_order[idx];
            if self.gauss_seidel {
                for jdx in 0..self.inputs_of[i].len() {
                    let j = self.inputs_of[i][jdx];
                    if !stepped[self.links[j].from_instance] {
                        continue;
                    }
                    // Gauss-Seidel: the source is already at t + h.
                    let fresh = self.get_output(j, t + h)?;
                    if self.interpolate[j] {
                        let slope = (fresh - self.y[j]) / h;
                        self.set_input(j, t, self.y[j], Some(slope))?;
                        self.applied[j] = (self.y[j], slope);
                    } else {
                        self.set_input(j, t, fresh, None)?;
                        self.applied[j] = (fresh, 0.0);
                    }
                }
            }
            if !self.do_step(i, t, h)? {
                return Ok(StepOutcome::Discarded { instance: i });
            }
            stepped[i] = true;
            if self.gauss_seidel {
                // The outputs read from this FMU by those stepping after it must be those of
                // t + h: an input that followed a line over the step is set to the line's end
                // value (an FMU may hold it at the value set at t, and a direct-feedthrough
                // output would then mix t + h states with t inputs).
                for jdx in 0..self.inputs_of[i].len() {
                    let j = self.inputs_of[i][jdx];
                    let (u, slope) = self.applied[j];
                    if slope != 0.0 {
                        self.set_input(j, t + h, u + slope * h, None)?;
                    }
                }
            }
        }
        let before = self.y.clone();
        self.exchange(t + h)?;
        let error = self
            .links
            .iter()
            .enumerate()
            .map(|(j, link)| {
                let (y0, y1) = (before[j], self.y[j]);
                let (u, slope) = self.applied[j];
                let scale = y0.abs().max(y1.abs()).max(link.nominal);
                (u - y0).abs().max((u + slope * h - y1).abs()) / scale
            })
            .fold(0.0, f64::max);
        Ok(StepOutcome::Done { error })
    }

    fn record(&mut self) -> Result<()> {
        let time = self.time;
        let mut row = Vec::with_capacity(self.probes.len());
        for probe in &self.probes {
            let inst = &mut self.instances[probe.instance];
            let value = match probe.kind {
                VariableType::Real => {
                    let mut v = [0.0];
                    let status = inst.get_real(&[probe.vr], &mut v);
                    check(inst, "fmi2GetReal", time, status)?;
                    v[0]
                }
                VariableType::Boolean => {
                    let mut v = [false];
                    let status = inst.get_boolean(&[probe.vr], &mut v);
                    check(inst, "fmi2GetBoolean", time, status)?;
                    f64::from(u8::from(v[0]))
                }
                _ => {
                    let mut v = [0];
                    let status = inst.get_integer(&[probe.vr], &mut v);
                    check(inst, "fmi2GetInteger", time, status)?;
                    f64::from(v[0])
                }
            };
            row.push(value);
        }
        self.table.push(time, &row);
        Ok(())
    }
}

/// Instance indices in stepping order: the Gauss-Seidel order if one is given (checked to name
/// every instance once), else as listed.
fn step_order(master: &Master) -> Result<Vec<usize>> {
    let system = &master.system;
    match &master.algorithm {
        Algorithm::GaussSeidel { order } if !order.is_empty() => {
            let indices = order
                .iter()
                .map(|name| system.index_of(name))
                .collect::<Result<Vec<usize>>>()?;
            let mut sorted = indices.clone();
            sorted.sort_unstable();
            sorted.dedup();
            if sorted.len() != system.components.len() || indices.len() != sorted.len() {
                return Err(config(format!(
                    "the Gauss-Seidel order {order:?} must name every instance exactly once"
                )));
            }
            Ok(indices)
        }
        _ => Ok((0..system.components.len()).collect()),
    }
}

/// Error control saves and restores FMU states, and divides steps when `divides`.
fn check_error_control_support(system: &System, divides: bool) -> Result<()> {
    for c in &system.components {
        let cs = c
            .fmu
            .model_description()
            .co_simulation
            .clone()
            .unwrap_or_default();
        let missing = if !cs.can_get_and_set_fmu_state {
            "canGetAndSetFMUstate"
        } else if divides && !cs.can_handle_variable_communication_step_size {
            "canHandleVariableCommunicationStepSize"
        } else {
            continue;
        };
        return Err(MasterError::Unsupported {
            instance: c.name.clone(),
            capability: missing,
        });
    }
    Ok(())
}

/// The recorded variable `port` (`"instance.variable"`).
fn probe(system: &System, port: &str) -> Result<Probe> {
    let (instance, var) = system.lookup(port)?;
    let kind = match var.variable_type {
        VariableType::Enumeration => VariableType::Integer,
        VariableType::String => {
            return Err(config(format!("{port} is a String: it cannot be recorded")))
        }
        other => other,
    };
    Ok(Probe {
        instance,
        vr: var.value_reference,
        kind,
    })
}

/// `fmi2Instantiate`, the start values, `fmi2SetupExperiment` and
/// `fmi2EnterInitializationMode` for one component.
fn instantiate(c: &Component, master: &Master) -> Result<Instance> {
    let t0 = master.start_time;
    let mut inst = Instance::new(&c.fmu, InstantiateOptions::new(&c.name)).map_err(|source| {
        MasterError::Host {
            instance: c.name.clone(),
            source,
        }
    })?;
    for (name, value) in &c.reals {
        let vr = start_variable(c, name, VariableType::Real)?;
        let status = inst.set_real(&[vr], &[*value]);
        check(&inst, "fmi2SetReal", t0, status)?;
    }
    for (name, value) in &c.integers {
        let vr = start_variable(c, name, VariableType::Integer)?;
        let status = inst.set_integer(&[vr], &[*value]);
        check(&inst, "fmi2SetInteger", t0, status)?;
    }
    for (name, value) in &c.booleans {
        let vr = start_variable(c, name, VariableType::Boolean)?;
        let status = inst.set_boolean(&[vr], &[*value]);
        check(&inst, "fmi2SetBoolean", t0, status)?;
    }
    let status = inst.setup_experiment(master.tolerance, t0, Some(master.stop_time));
    check(&inst, "fmi2SetupExperiment", t0, status)?;
    let status = inst.enter_initialization_mode();
    check(&inst, "fmi2EnterInitializationMode", t0, status)?;
    Ok(inst)
}

/// The value reference of start variable `name` of component `c`, checked to be of `kind`.
fn start_variable(c: &Component, name: &str, kind: VariableType) -> Result<ValueReference> {
    let var = c.fmu.variable(name).map_err(|source| MasterError::Host {
        instance: c.name.clone(),
        source,
    })?;
    let matches = var.variable_type == kind
        || (kind == VariableType::Integer && var.variable_type == VariableType::Enumeration);
    if !matches {
        return Err(config(format!(
            "{}.{name} is {:?}, not {kind:?}",
            c.name, var.variable_type
        )));
    }
    Ok(var.value_reference)
}

impl Drop for Simulation {
    fn drop(&mut self) {
        for (inst, slot) in self.instances.iter_mut().zip(&mut self.states) {
            if let Some(state) = slot.take() {
                let _ = inst.free_fmu_state(state);
            }
        }
    }
}
