//! One FMU instance, in neither standard's words: its phase, its values, its solver, its saved
//! states, and every check a call must pass. The adapters (`fmi2`, `fmi3`) have already checked
//! pointers and that the call is legal in the current phase; everything here is safe Rust.
//!
//! Errors from misuse (a wrong value reference, a NaN, a parameter set after initialization)
//! refuse the call and leave the instance as it was, so a master can go on. Errors of the model
//! itself (a parameter out of its physical range at initialization) move the instance to the
//! Error phase; a step the solver cannot complete returns Status::Discard and leaves the instance
//! at the last communication point.

use std::sync::Arc;

use crate::integrate::{declared_tolerance, negligible_interval, Advanced, InputMotion, Integrator};
use crate::log::Logger;
use crate::model::{evaluate, Model, ModelInfo, RuntimeVariables};
use crate::phase::Phase;
pub use crate::status::{CallResult, Failure};
use crate::status::Status;
use crate::state::{Experiment, Shape, Snapshot, SnapshotStore};
use crate::values::{EventIndicators, Knowns, ModeUpdate, Values};
use crate::variables::{BaseType, Slot, Variable, VariableTable};

/// Time events one communication step may hold before the step is refused (a model announcing
/// events that do not advance would otherwise loop forever).
pub const MAX_EVENTS_PER_STEP: usize = 10_000;

/// Passes of `Model::update_modes` at one event before the modes are declared unsettled (a
/// model whose update rules contradict each other would otherwise loop forever).
pub const MAX_MODE_ITERATIONS: usize = 50;

/// State events at one instant (within rounding) before a step is refused as chattering.
pub const MAX_EVENTS_AT_ONE_INSTANT: usize = 100;

/// The rounding error of one evaluation of a model's unknown, in ulps of its value, that a
/// directional derivative's central difference allows for (a few dozen operations each
/// rounding by half an ulp, some of them cancelling).
const ROUNDING_ULPS: f64 = 16.0;

/// A value a master can get or set, typed as FMI types it.
pub trait FmiValue: Copy {
    const TYPE: BaseType;
    fn read(values: &Values, slot: Slot) -> Self;
    fn write(values: &mut Values, slot: Slot, v: Self);
    fn check(var: &Variable, v: Self) -> Result<(), String>;
}

impl FmiValue for f64 {
    const TYPE: BaseType = BaseType::Real;
    fn read(values: &Values, slot: Slot) -> f64 {
        match slot {
            Slot::Known(i) => values.known[i],
            Slot::Calculated(i) => values.calculated[i],
            Slot::Derivative(i) => values.derivatives[i],
            _ => unreachable!("checked by type"),
        }
    }
    fn write(values: &mut Values, slot: Slot, v: f64) {
        if let Slot::Known(i) = slot {
            values.known[i] = v;
        }
    }
    fn check(var: &Variable, v: f64) -> Result<(), String> {
        var.check_range(v)
    }
}

impl FmiValue for i32 {
    const TYPE: BaseType = BaseType::Integer;
    fn read(values: &Values, slot: Slot) -> i32 {
        match slot {
            Slot::Integer(i) => values.integers[i],
            _ => unreachable!("checked by type"),
        }
    }
    fn write(values: &mut Values, slot: Slot, v: i32) {
        if let Slot::Integer(i) = slot {
            values.integers[i] = v;
        }
    }
    fn check(var: &Variable, v: i32) -> Result<(), String> {
        var.check_range(v as f64)
    }
}

impl FmiValue for bool {
    const TYPE: BaseType = BaseType::Boolean;
    fn read(values: &Values, slot: Slot) -> bool {
        match slot {
            Slot::Boolean(i) => values.booleans[i],
            _ => unreachable!("checked by type"),
        }
    }
    fn write(values: &mut Values, slot: Slot, v: bool) {
        if let Slot::Boolean(i) = slot {
            values.booleans[i] = v;
        }
    }
    fn check(_: &Variable, _: bool) -> Result<(), String> {
        Ok(())
    }
}

/// The interface an instance was made for (fmi2Instantiate's fmuType).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interface {
    CoSimulation,
    ModelExchange,
}

/// What fmi2NewDiscreteStates reports (fmi2EventInfo).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EventInfo {
    pub new_discrete_states_needed: bool,
    pub terminate_simulation: bool,
    pub nominals_changed: bool,
    /// valuesOfContinuousStatesChanged: a mode update changed a mode or re-initialized a state
    /// (the master must restart its integrator).
    pub values_changed: bool,
    pub next_event_time: Option<f64>,
}

/// Which lazily computed values are up to date (see `Instance::refresh_only`).
#[derive(Clone, Copy, Default)]
struct Fresh {
    calculated: bool,
    derivatives: bool,
}

pub struct Instance<M: Model> {
    pub interface: Interface,
    runtime: RuntimeVariables,
    /// The known reals at the previous communication point and its time, for input
    /// extrapolation.
    previous_inputs: Option<(f64, Vec<f64>)>,
    model: Arc<M>,
    table: Arc<VariableTable>,
    info: ModelInfo,
    guid: &'static str,
    pub logger: Logger,
    pub phase: Phase,
    experiment: Experiment,
    values: Values,
    /// The continuous states at `time` (after initialization; before it, the start values).
    states: Vec<f64>,
    time: f64,
    /// Outputs and derivatives are recomputed lazily, when read after a change: `stale` says
    /// that something changed, `fresh` which of the two (calculated values, derivatives) have
    /// been recomputed since (a master reading outputs after each step never pays for the
    /// derivatives).
    stale: bool,
    fresh: Fresh,
    /// A known may have changed since the solver last advanced (set by the master, moved along
    /// its derivatives, restored): the solver's parameter vector is rebuilt and compared.
    knowns_set: bool,
    /// The model has inputs (else no input bookkeeping runs in a step), and discrete modes
    /// (else no mode update runs at communication points).
    has_inputs: bool,
    has_modes: bool,
    /// Boxed: `do_step` takes it out and puts it back, which moves only the pointer.
    integrator: Option<Box<Integrator>>,
    snapshots: SnapshotStore,
    /// First and second time derivatives of the inputs for the next step (by known index;
    /// fmi2SetRealInputDerivatives), cleared after each step and when the input is set.
    input_slopes: Vec<f64>,
    input_curvatures: Vec<f64>,
    /// Buffers reused by every doStep, so that steady stepping allocates nothing.
    buffers: Buffers,
}

/// Work vectors of `do_step` and `settle_modes`, kept between calls (their contents carry
/// nothing from one call to the next).
#[derive(Default)]
struct Buffers {
    /// The states being advanced over a step.
    x: Vec<f64>,
    /// The input slopes of a step.
    slopes: Vec<f64>,
    /// The modes at the start of a step (restored when it fails).
    modes: Vec<i32>,
    /// A mode update's trial modes and states.
    trial_modes: Vec<i32>,
    trial_states: Vec<f64>,
    /// The derivatives and element powers of the energy balance, at each output refresh.
    balance: Vec<f64>,
}

impl<M: Model> Instance<M> {
    pub fn new(guid: &'static str, logger: Logger) -> Self {
        Self::for_interface(Interface::CoSimulation, guid, logger)
    }

    pub fn for_interface(interface: Interface, guid: &'static str, logger: Logger) -> Self {
        let (model, runtime, table) = crate::model::declare::<M>();
        let (model, table) = (Arc::new(model), Arc::new(table));
        let values = table.start_values();
        let n_states = table.n_states;
        let mut inst = Instance {
            interface,
            runtime,
            previous_inputs: None,
            model,
            table,
            info: M::info(),
            guid,
            logger,
            phase: Phase::Instantiated,
            experiment: Experiment::default(),
            values,
            states: vec![0.0; n_states],
            time: 0.0,
            stale: true,
            fresh: Fresh::default(),
            knowns_set: true,
            has_inputs: false,
            has_modes: false,
            integrator: None,
            snapshots: SnapshotStore::default(),
            input_slopes: Vec::new(),
            input_curvatures: Vec::new(),
            buffers: Buffers::default(),
        };
        inst.input_slopes = vec![0.0; inst.table.n_known];
        inst.input_curvatures = vec![0.0; inst.table.n_known];
        inst.buffers.slopes = vec![0.0; inst.table.n_known];
        inst.buffers.balance = vec![0.0; inst.table.n_states + inst.table.elements.len()];
        inst.has_inputs = inst.table.variables.iter().any(|v| v.causality == crate::variables::Causality::Input);
        inst.has_modes = inst.table.variables.iter().any(|v| v.is_mode());
        // A model whose initial states fail at the defaults says so at initialization.
        let _ = inst.load_state_starts();
        inst
    }

    pub fn table(&self) -> &VariableTable {
        &self.table
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    /// Sends a debug message (only with debug logging on).
    pub fn debug(&self, message: &str) {
        self.logger.log(Status::Ok, message);
    }

    /// The states at initialization: the start values, and the model's own initial values of
    /// its calculated states (also written back, so fmi2GetReal reads them).
    fn load_state_starts(&mut self) -> Result<(), String> {
        for (x, k) in self.states.iter_mut().zip(&self.table.state_known_index) {
            *x = self.values.known[*k];
        }
        let v = &self.values;
        let result = crate::model::initialize_states(&*self.model, &self.table, self.time, &v.known, &v.integers, &v.booleans, &mut self.states);
        self.store_states();
        result
    }

    fn store_states(&mut self) {
        for (x, k) in self.states.iter().zip(&self.table.state_known_index) {
            self.values.known[*k] = *x;
        }
    }

    /// Recomputes outputs, locals and derivatives from the knowns if anything changed.
    fn refresh(&mut self) {
        self.refresh_only(Fresh { calculated: true, derivatives: true });
    }

    /// Recomputes what `need` asks for (calculated values, derivatives) if anything changed
    /// since it was last computed.
    fn refresh_only(&mut self, need: Fresh) {
        if self.stale {
            if self.phase.is_before_initialization_end() {
                // A failure leaves NaN in the calculated states; exiting initialization reports it.
                let _ = self.load_state_starts();
            }
            self.fresh = Fresh::default();
            self.stale = false;
        }
        let v = &mut self.values;
        if need.calculated && !self.fresh.calculated {
            crate::model::evaluate_outputs(&*self.model, &self.table, self.time, &v.known, &self.states, &v.integers, &v.booleans, &mut v.calculated, &mut self.buffers.balance);
            self.fresh.calculated = true;
        }
        if need.derivatives && !self.fresh.derivatives {
            crate::model::evaluate_derivatives(&*self.model, self.time, &v.known, &self.states, &v.integers, &v.booleans, &mut v.derivatives);
            self.fresh.derivatives = true;
        }
    }

    fn variable(&self, vr: u32, expected: BaseType) -> CallResult<&Variable> {
        let var = self.table.get(vr).ok_or_else(|| {
            Failure::error(format!("unknown value reference {vr} (this FMU has 0..{})", self.table.variables.len()))
        })?;
        if var.base_type() != expected {
            return Err(Failure::error(format!(
                "value reference {vr} is the {:?} variable '{}', not {}",
                var.base_type(),
                var.name,
                expected.with_article()
            )));
        }
        Ok(var)
    }

    /// fmi2GetReal/Integer/Boolean.
    pub fn get<T: FmiValue>(&mut self, vrs: &[u32], out: &mut [T]) -> CallResult {
        let mut need = Fresh::default();
        for vr in vrs {
            match self.variable(*vr, T::TYPE)?.slot {
                Slot::Calculated(_) => need.calculated = true,
                Slot::Derivative(_) => need.derivatives = true,
                _ => {}
            }
        }
        // Reading only knowns (states, parameters, inputs) evaluates nothing, but a pending
        // initialization still fills in the calculated states.
        self.refresh_only(need);
        for (vr, o) in vrs.iter().zip(out.iter_mut()) {
            *o = T::read(&self.values, self.table.variables[*vr as usize].slot);
        }
        Ok(())
    }

    /// fmi2SetReal/Integer/Boolean: all values are checked before any is written.
    pub fn set<T: FmiValue>(&mut self, vrs: &[u32], vals: &[T]) -> CallResult {
        let before_init = self.phase.is_before_initialization_end();
        for (vr, v) in vrs.iter().zip(vals) {
            let var = self.variable(*vr, T::TYPE)?;
            let settable = if before_init { var.is_settable_before_initialization() } else { var.is_settable_while_stepping() };
            if !settable {
                let why = match (var.causality, before_init) {
                    (crate::variables::Causality::Parameter, false) => "a fixed parameter cannot change after initialization",
                    (crate::variables::Causality::Output, _) => "an output is computed by the FMU",
                    _ if var.derivative_of.is_some() => "a derivative is computed by the FMU",
                    _ if !before_init => "only inputs and tunable parameters can be set while stepping",
                    _ => "it is computed by the FMU",
                };
                return Err(Failure::error(format!("cannot set '{}' {}: {why}", var.name, self.phase.words())));
            }
            T::check(var, *v).map_err(|e| Failure::error(format!("refused: {e}")))?;
        }
        for (vr, v) in vrs.iter().zip(vals) {
            let slot = self.table.variables[*vr as usize].slot;
            T::write(&mut self.values, slot, *v);
            if let Slot::Known(i) = slot {
                // A new input value without derivatives is held over the next step.
                self.input_slopes[i] = 0.0;
                self.input_curvatures[i] = 0.0;
            }
        }
        self.stale = true;
        self.knowns_set = true;
        Ok(())
    }

    pub fn setup_experiment(&mut self, tolerance: Option<f64>, start_time: f64, stop_time: Option<f64>) -> CallResult {
        if let Some(tol) = tolerance {
            if !(tol.is_finite() && tol > 0.0 && tol < 1.0) {
                return Err(Failure::error(format!("tolerance {tol} must be a number in (0, 1)")));
            }
        }
        if !start_time.is_finite() {
            return Err(Failure::error(format!("start time {start_time} is not finite")));
        }
        if let Some(stop) = stop_time {
            if !(stop.is_finite() && stop >= start_time) {
                return Err(Failure::error(format!("stop time {stop} must be finite and not before the start time {start_time}")));
            }
        }
        self.experiment = Experiment { tolerance, start_time, stop_time };
        self.time = start_time;
        self.stale = true;
        let stop = stop_time.map_or("no stop time".to_string(), |s| format!("stop {s} s"));
        let asked = tolerance.map_or(format!("no tolerance given (the default {})", declared_tolerance(M::tolerance_floor())), |t| format!("tolerance {t}"));
        self.debug(&format!("experiment: start {start_time} s, {stop}, {asked}"));
        if let (Interface::CoSimulation, Some(asked), Some(floor)) = (self.interface, tolerance, M::tolerance_floor()) {
            if asked > floor {
                self.logger.log(
                    Status::Warning,
                    &format!(
                        "tolerance {asked} set by the master is looser than this FMU's floor {floor}: its solver integrates at {floor} \
                         (at looser tolerances its errors grow far beyond the tolerance; see the FMU's documentation)"
                    ),
                );
            }
        }
        Ok(())
    }

    /// The relative tolerance the Co-Simulation solver integrates at: the master's (else the
    /// declared default), tightened to the model's floor.
    fn solver_tolerance(&self) -> f64 {
        let floor = M::tolerance_floor();
        let asked = self.experiment.tolerance.unwrap_or(declared_tolerance(floor));
        floor.map_or(asked, |floor| asked.min(floor))
    }

    pub fn enter_initialization_mode(&mut self) -> CallResult {
        self.phase = Phase::Initialization;
        self.time = self.experiment.start_time;
        self.stale = true;
        self.debug("entered initialization mode");
        Ok(())
    }

    /// Checks every parameter against its physical range and the model's own relations, then that
    /// every value at the start is finite; a violation moves the instance to the Error mode with a
    /// message naming the parameter.
    pub fn exit_initialization_mode(&mut self) -> CallResult {
        if let Err(message) = self.check_parameters() {
            self.phase = Phase::Error;
            return Err(Failure::error(format!("initialization failed: {message}")));
        }
        if let Err(message) = self.load_state_starts() {
            self.phase = Phase::Error;
            return Err(Failure::error(format!("initialization failed: {message}")));
        }
        self.settle_initial_modes()?;
        if let Err(message) = crate::model::check_finite_start(&*self.model, &self.table, self.time, &self.values, &self.states) {
            self.phase = Phase::Error;
            return Err(Failure::error(format!("initialization failed: {message}")));
        }
        if self.interface == Interface::ModelExchange {
            self.phase = Phase::Event;
            self.stale = true;
            self.debug("initialization done, event mode");
            return Ok(());
        }
        match self.make_integrator() {
            Ok(integrator) => self.integrator = Some(integrator),
            Err(message) => {
                self.phase = Phase::Error;
                return Err(Failure::error(message));
            }
        }
        self.phase = Phase::Stepping;
        self.stale = true;
        self.debug("initialization done");
        Ok(())
    }

    fn check_parameters(&self) -> Result<(), String> {
        for var in &self.table.variables {
            match var.slot {
                Slot::Known(i) => var.check_range(self.values.known[i])?,
                Slot::Integer(i) => var.check_range(self.values.integers[i] as f64)?,
                _ => {}
            }
        }
        let v = &self.values;
        let k = Knowns::new(self.time, &v.known, &self.states, &v.integers, &v.booleans);
        self.model.check(&k)
    }

    fn make_integrator(&self) -> Result<Box<Integrator>, String> {
        Integrator::new(
            self.model.clone(),
            &self.values.known,
            &self.values.integers,
            &self.values.booleans,
            self.table.n_states,
            self.table.indicators.len(),
            self.info.solver,
            self.solver_tolerance(),
            &self.table.state_nominals(),
            &self.table.state_known_index,
            &self.table.activity_states(),
        )
        .map(Box::new)
    }

    /// fmi2DoStep: integrate from the communication point to the next one.
    pub fn do_step(&mut self, t: f64, h: f64) -> CallResult {
        if !(h.is_finite() && h > 0.0) {
            return Err(Failure::error(format!("communication step size {h} must be a finite number > 0")));
        }
        if !t.is_finite() {
            return Err(Failure::error(format!("communication point {t} is not finite")));
        }
        let tolerance = 64.0 * f64::EPSILON * self.time.abs().max(t.abs()) + 1e-6 * h;
        if let Some(stop) = self.experiment.stop_time {
            // FMI 2.0 and 3.0: computing past a defined stop time is an error.
            if t + h > stop + tolerance {
                return Err(Failure::error(format!(
                    "the step to {} s would pass the experiment's stop time {stop} s",
                    t + h
                )));
            }
        }
        if (t - self.time).abs() > tolerance {
            return Err(Failure::error(format!(
                "communication point {t} s does not match this instance's time {} s (restore a saved FMU state to go back)",
                self.time
            )));
        }
        let t_end = t + h;
        let mut x = std::mem::take(&mut self.buffers.x);
        x.clone_from(&self.states);
        let mut slopes = std::mem::take(&mut self.buffers.slopes);
        if self.has_inputs {
            self.extrapolated_slopes(t, &mut slopes);
        }
        let result = self.integrate(t, &mut x, t_end, &slopes);
        if let Err(message) = result {
            (self.buffers.x, self.buffers.slopes) = (x, slopes);
            self.phase = Phase::StepFailed;
            return Err(Failure {
                status: Status::Discard,
                message: format!("step from {t} s to {t_end} s discarded, the instance stays at {t} s: {message}"),
            });
        }
        if self.has_inputs {
            match &mut self.previous_inputs {
                Some((t_prev, previous)) => {
                    *t_prev = t;
                    previous.clone_from(&self.values.known);
                }
                None => self.previous_inputs = Some((t, self.values.known.clone())),
            }
            // At the end of the step the inputs are where their motion took them, so outputs
            // that depend on inputs directly (a shaft's torque) are those of t_end, not of t.
            for (i, (slope, curvature)) in slopes.iter().zip(&self.input_curvatures).enumerate() {
                // Only moving inputs are written: `+= 0.0` would turn an input's -0.0 into +0.0.
                if *slope != 0.0 || *curvature != 0.0 {
                    self.values.known[i] += slope * h + 0.5 * curvature * h * h;
                    self.knowns_set = true;
                }
            }
            // Input derivatives describe one step; the master sets new values (and derivatives)
            // at the next communication point.
            self.input_slopes.fill(0.0);
            self.input_curvatures.fill(0.0);
        }
        std::mem::swap(&mut self.states, &mut x);
        (self.buffers.x, self.buffers.slopes) = (x, slopes);
        self.time = t_end;
        self.store_states();
        self.stale = true;
        Ok(())
    }

    /// The input slopes for a step from `t`: the master's input derivatives where it gave them;
    /// with `extrapolate_inputs` on, the line through the previous and the current communication
    /// point for the other inputs.
    fn extrapolated_slopes(&self, t: f64, slopes: &mut Vec<f64>) {
        slopes.clone_from(&self.input_slopes);
        let on = self.runtime.extrapolate_inputs.is_some_and(|b| self.values.booleans[b.index()]);
        if let (true, Some((t_prev, previous))) = (on, &self.previous_inputs) {
            if t > *t_prev {
                for var in self.table.variables.iter().filter(|v| v.causality == crate::variables::Causality::Input) {
                    if let Slot::Known(i) = var.slot {
                        if self.input_slopes[i] == 0.0 && self.input_curvatures[i] == 0.0 {
                            slopes[i] = (self.values.known[i] - previous[i]) / (t - t_prev);
                        }
                    }
                }
            }
        }
    }

    /// Integrates from `t` to `t_end`, stopping at every time event the model announces and at
    /// every zero crossing of an event indicator, where the modes are updated and the solver
    /// restarts. On failure the modes are those of `t` again (the step is discarded).
    fn integrate(&mut self, t: f64, x: &mut [f64], t_end: f64, slopes: &[f64]) -> Result<(), String> {
        let mut integrator = self.integrator.take().ok_or("the instance has no ODE solver (initialization did not finish)")?;
        let step_size = integrator.step_size;
        // Without modes, no integer changes in a step.
        let mut modes = std::mem::take(&mut self.buffers.modes);
        if self.has_modes {
            modes.clone_from(&self.values.integers);
        }
        let curvatures = std::mem::take(&mut self.input_curvatures);
        let mut result = self.integrate_with(&mut integrator, t, x, t_end, slopes, &curvatures);
        self.input_curvatures = curvatures;
        if result.is_err() && self.has_modes && self.values.integers != modes {
            self.values.integers.copy_from_slice(&modes);
            match self.make_integrator() {
                Ok(made) => {
                    integrator = made;
                    integrator.step_size = step_size;
                }
                Err(message) => result = Err(message),
            }
        }
        self.buffers.modes = modes;
        self.integrator = Some(integrator);
        result
    }

    fn integrate_with(&mut self, integrator: &mut Integrator, t: f64, x: &mut [f64], t_end: f64, slopes: &[f64], curvatures: &[f64]) -> Result<(), String> {
        // Inputs or tunable parameters set at this communication point may change the modes
        // (a force above the static friction breaks a stuck body loose) without any indicator
        // crossing zero during integration. When nothing was set since the last step, the modes
        // are those the last step left consistent (it stopped at every crossing up to here).
        let known = std::mem::take(&mut self.values.known);
        let settled = if self.has_modes && self.knowns_set { self.settle_modes(t, &known, x) } else { Ok((false, false)) };
        self.values.known = known;
        if settled?.0 {
            let step_size = integrator.step_size;
            *integrator = *self.make_integrator()?;
            integrator.step_size = step_size;
        }
        let mut now = t;
        let (mut last_event, mut at_one_instant) = (f64::NEG_INFINITY, 0usize);
        // One budget of internal steps for the whole communication step, across its events.
        let mut budget = crate::integrate::MAX_INTERNAL_STEPS;
        // Without inputs nothing moves (the slopes are zero): no need to look.
        let motion = if self.has_inputs { InputMotion::new(slopes, curvatures, t) } else { InputMotion::still(slopes) };
        for _ in 0..MAX_EVENTS_PER_STEP {
            let v = &self.values;
            let k = Knowns::new(now, &v.known, x, &v.integers, &v.booleans);
            // An event within rounding of the step's end is taken as the end (a master's
            // float time 9.999999999999897 s for an event at 10 s).
            let tiny = negligible_interval(t_end);
            let event = self.model.next_time_event(&k, now).filter(|e| *e > now);
            let next = match event {
                Some(event) if event < t_end - tiny => event,
                _ => t_end,
            };
            // How far the explicit solver may step past `next` (it interpolates back): not past
            // the next time event, nor past a defined stop time (the model may be invalid there).
            let limit = match event {
                Some(event) if next == t_end => event.max(t_end),
                Some(_) => next,
                None => f64::INFINITY,
            };
            let limit = self.experiment.stop_time.map_or(limit, |stop| limit.min(stop)).max(next);
            let knowns_set = std::mem::replace(&mut self.knowns_set, false);
            let how = integrator.advance(&v.known, &motion, knowns_set, now, x, next, limit, &mut budget)?;
            match how {
                Advanced::Reached if next == t_end => return Ok(()),
                Advanced::Reached => {
                    self.logger.log(Status::Ok, &format!("time event at t = {next} s"));
                    now = next;
                }
                Advanced::Crossing { time, indicator } => {
                    if time - last_event <= negligible_interval(time) {
                        at_one_instant += 1;
                        if at_one_instant >= MAX_EVENTS_AT_ONE_INSTANT {
                            return Err(format!(
                                "{MAX_EVENTS_AT_ONE_INSTANT} state events at t = {time} s without time advancing \
                                 (the modes chatter: event indicator '{}')",
                                self.table.indicators[indicator].0
                            ));
                        }
                    } else {
                        at_one_instant = 0;
                    }
                    last_event = time;
                    self.logger.log(Status::Ok, &format!("state event at t = {time} s: '{}' crossed zero", self.table.indicators[indicator].0));
                    if let Some(counter) = self.runtime.state_events {
                        self.values.integers[counter.0] = self.values.integers[counter.0].saturating_add(1);
                    }
                    now = time;
                }
            }
            // The modes after the event (a time event may change them too: a voltage step can
            // break a stuck body loose). The solver is re-made with the new modes.
            let known = self.knowns_moved_to(now, t, slopes, curvatures);
            let (modes_changed, _) = self.settle_modes(now, &known, x)?;
            if modes_changed {
                let step_size = integrator.step_size;
                *integrator = *self.make_integrator()?;
                integrator.step_size = step_size;
            }
        }
        Err(format!("more than {MAX_EVENTS_PER_STEP} events in one communication step"))
    }

    /// The known reals at `now` with the inputs moved along their derivatives since `since`.
    fn knowns_moved_to(&self, now: f64, since: f64, slopes: &[f64], curvatures: &[f64]) -> Vec<f64> {
        let tau = now - since;
        (0..self.values.known.len())
            .map(|i| self.values.known[i] + slopes[i] * tau + 0.5 * curvatures[i] * tau * tau)
            .collect()
    }

    /// Runs `Model::update_modes` at (time, known, x) until neither a mode nor a state changes;
    /// returns (modes changed, states changed). Only the model's modes can change: the handles
    /// of `ModeUpdate` are the modes it declared.
    fn settle_modes(&mut self, time: f64, known: &[f64], x: &mut [f64]) -> Result<(bool, bool), String> {
        let mut modes = std::mem::take(&mut self.buffers.trial_modes);
        let mut states = std::mem::take(&mut self.buffers.trial_states);
        let result = self.settle_modes_with(time, known, x, &mut modes, &mut states);
        (self.buffers.trial_modes, self.buffers.trial_states) = (modes, states);
        result
    }

    fn settle_modes_with(&mut self, time: f64, known: &[f64], x: &mut [f64], modes: &mut Vec<i32>, states: &mut Vec<f64>) -> Result<(bool, bool), String> {
        let (mut modes_changed, mut states_changed) = (false, false);
        for _ in 0..MAX_MODE_ITERATIONS {
            modes.clone_from(&self.values.integers);
            states.clear();
            states.extend_from_slice(x);
            let reinitialized = {
                let k = Knowns::new(time, known, x, &self.values.integers, &self.values.booleans);
                let mut next = ModeUpdate::new(modes, states);
                self.model.update_modes(&k, &mut next);
                next.reinitialized()
            };
            let changed = *modes != self.values.integers;
            if !changed && !reinitialized {
                return Ok((modes_changed, states_changed));
            }
            if let Some(i) = states.iter().position(|v| !v.is_finite()) {
                return Err(format!("the mode update at t = {time} s set state {i} to {}", states[i]));
            }
            self.values.integers.copy_from_slice(modes);
            x.copy_from_slice(states);
            modes_changed |= changed;
            states_changed |= reinitialized;
            self.stale = true;
        }
        Err(format!("the discrete modes did not settle after {MAX_MODE_ITERATIONS} updates at t = {time} s"))
    }

    /// At the end of initialization: the modes that fit the start values (e.g. a body at rest
    /// sticks). A failure moves the instance to the Error mode.
    fn settle_initial_modes(&mut self) -> CallResult {
        let (known, mut x) = (self.values.known.clone(), self.states.clone());
        if let Err(message) = self.settle_modes(self.time, &known, &mut x) {
            self.phase = Phase::Error;
            return Err(Failure::error(format!("initialization failed: {message}")));
        }
        self.states = x;
        self.store_states();
        Ok(())
    }

    pub fn terminate(&mut self) -> CallResult {
        self.phase = Phase::Terminated;
        self.debug("terminated");
        Ok(())
    }

    /// fmi2Reset: back to the state right after fmi2Instantiate (saved FMU states stay valid).
    pub fn reset(&mut self) -> CallResult {
        self.values = self.table.start_values();
        self.experiment = Experiment::default();
        self.time = 0.0;
        self.integrator = None;
        self.previous_inputs = None;
        self.input_slopes.fill(0.0);
        self.input_curvatures.fill(0.0);
        self.phase = Phase::Instantiated;
        let _ = self.load_state_starts();
        self.stale = true;
        self.knowns_set = true;
        self.debug("reset");
        Ok(())
    }

    pub fn set_debug_logging(&mut self, on: bool, categories: &[String]) -> CallResult {
        self.logger.set_debug_logging(on, categories).map_err(Failure::error)
    }

    /// fmi2GetRealStatus(fmi2LastSuccessfulTime).
    pub fn last_successful_time(&self) -> f64 {
        self.time
    }

    // ---- Input and output derivatives (Co-Simulation) ----------------------------------------

    /// fmi2SetRealInputDerivatives: first and second derivatives of inputs, used over the next
    /// step (canInterpolateInputs).
    pub fn set_input_derivatives(&mut self, vrs: &[u32], orders: &[i32], values: &[f64]) -> CallResult {
        let mut updates = Vec::with_capacity(vrs.len());
        for ((vr, order), value) in vrs.iter().zip(orders).zip(values) {
            let var = self.variable(*vr, BaseType::Real)?;
            let (Slot::Known(i), crate::variables::Causality::Input) = (var.slot, var.causality) else {
                return Err(Failure::error(format!("'{}' is not an input", var.name)));
            };
            if !(1..=2).contains(order) {
                return Err(Failure::error(format!("derivative order {order} of '{}': this FMU takes orders 1 and 2", var.name)));
            }
            if !value.is_finite() {
                return Err(Failure::error(format!("derivative of '{}' = {value} is not finite", var.name)));
            }
            updates.push((i, *order, *value));
        }
        self.knowns_set = true;
        for (i, order, value) in updates {
            if order == 1 {
                self.input_slopes[i] = value;
            } else {
                self.input_curvatures[i] = value;
            }
        }
        Ok(())
    }

    /// fmi2GetRealOutputDerivatives, order 1: dy/dt along the current motion (states moving with
    /// their derivatives, inputs with the derivatives set for the next step, time), by central
    /// differences over a time step h = 1e-6 of the fastest state's time scale (|x| / |dx/dt|).
    pub fn output_derivatives(&mut self, vrs: &[u32], orders: &[i32], out: &mut [f64]) -> CallResult {
        for (vr, order) in vrs.iter().zip(orders) {
            let var = self.variable(*vr, BaseType::Real)?;
            if var.causality != crate::variables::Causality::Output {
                return Err(Failure::error(format!("'{}' is not an output", var.name)));
            }
            if *order != 1 {
                return Err(Failure::error(format!("derivative order {order} of '{}': maxOutputDerivativeOrder is 1", var.name)));
            }
        }
        self.refresh();
        let nominals = self.table.state_nominals();
        let time_scale = self
            .states
            .iter()
            .zip(&self.values.derivatives)
            .zip(&nominals)
            .filter(|(( _, d), _)| **d != 0.0)
            .map(|((x, d), n)| x.abs().max(n.abs()) / d.abs())
            .fold(1.0f64, f64::min);
        let h = 1e-6 * time_scale;
        let v = &self.values;
        let at = |sign: f64| {
            let x: Vec<f64> = self.states.iter().zip(&v.derivatives).map(|(x, d)| x + sign * h * d).collect();
            let k: Vec<f64> = (0..v.known.len())
                .map(|i| v.known[i] + sign * h * self.input_slopes[i] + 0.5 * h * h * self.input_curvatures[i])
                .collect();
            let (mut der, mut calc) = (v.derivatives.clone(), v.calculated.clone());
            evaluate(&*self.model, &self.table, self.time + sign * h, &k, &x, &v.integers, &v.booleans, &mut der, &mut calc);
            calc
        };
        let (plus, minus) = (at(1.0), at(-1.0));
        for (o, vr) in out.iter_mut().zip(vrs) {
            let Slot::Calculated(i) = self.table.variables[*vr as usize].slot else { unreachable!("an output") };
            *o = (plus[i] - minus[i]) / (2.0 * h);
        }
        Ok(())
    }

    // ---- Model Exchange -------------------------------------------------------------------

    pub fn enter_event_mode(&mut self) -> CallResult {
        self.phase = Phase::Event;
        Ok(())
    }

    /// fmi2NewDiscreteStates: the model's modes are updated until they settle (so one call
    /// suffices: newDiscreteStatesNeeded is false); the next time event is the model's next kink
    /// after now.
    ///
    /// valuesOfContinuousStatesChanged is reported whenever a mode or a state changed, not only
    /// when a state was re-initialized (docs/DESIGN.md, "Model Exchange events any integrator
    /// survives"): a new mode changes the right-hand side, and its indicator may start exactly
    /// at zero (a stuck body breaking loose has speed 0, the indicator of its slipping mode). A
    /// master that keeps its integrator's history would then find a root at its restart point
    /// (CVODE: "root found at and very near t"); told that the states changed, it restarts, and
    /// a zero at the start of an integration is no crossing.
    pub fn new_discrete_states(&mut self) -> CallResult<EventInfo> {
        let (known, mut x) = (self.values.known.clone(), self.states.clone());
        let (modes_changed, states_changed) = self.settle_modes(self.time, &known, &mut x).map_err(Failure::error)?;
        if states_changed {
            self.states = x;
            self.store_states();
        }
        if modes_changed || states_changed {
            if let Some(counter) = self.runtime.state_events {
                self.values.integers[counter.0] = self.values.integers[counter.0].saturating_add(1);
            }
            self.stale = true;
            self.debug(&format!("event at t = {} s: modes or states changed", self.time));
        }
        let v = &self.values;
        let k = Knowns::new(self.time, &v.known, &self.states, &v.integers, &v.booleans);
        let next_event_time = self.model.next_time_event(&k, self.time);
        Ok(EventInfo { next_event_time, values_changed: modes_changed || states_changed, ..EventInfo::default() })
    }

    pub fn enter_continuous_time_mode(&mut self) -> CallResult {
        self.phase = Phase::ContinuousTime;
        Ok(())
    }

    pub fn set_time(&mut self, t: f64) -> CallResult {
        if !t.is_finite() {
            return Err(Failure::error(format!("time {t} is not finite")));
        }
        self.time = t;
        self.stale = true;
        Ok(())
    }

    fn check_length(&self, n: usize, what: &str, expected: usize) -> CallResult {
        if n != expected {
            return Err(Failure::error(format!("{n} {what} given, this FMU has {expected}")));
        }
        Ok(())
    }

    pub fn set_continuous_states(&mut self, x: &[f64]) -> CallResult {
        self.check_length(x.len(), "continuous states", self.table.n_states)?;
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            let name = &self.table.variables[self.table.state_value_reference[i] as usize].name;
            return Err(Failure::error(format!("state {name} = {} is not finite", x[i])));
        }
        self.states.copy_from_slice(x);
        self.store_states();
        self.stale = true;
        Ok(())
    }

    pub fn get_continuous_states(&mut self, x: &mut [f64]) -> CallResult {
        self.check_length(x.len(), "continuous states", self.table.n_states)?;
        self.refresh_only(Fresh::default());
        x.copy_from_slice(&self.states);
        Ok(())
    }

    pub fn get_derivatives(&mut self, dx: &mut [f64]) -> CallResult {
        self.check_length(dx.len(), "derivatives", self.table.n_states)?;
        self.refresh_only(Fresh { calculated: false, derivatives: true });
        dx.copy_from_slice(&self.values.derivatives);
        Ok(())
    }

    pub fn get_nominals(&mut self, nominals: &mut [f64]) -> CallResult {
        self.check_length(nominals.len(), "nominals", self.table.n_states)?;
        nominals.copy_from_slice(&self.table.state_nominals());
        Ok(())
    }

    /// fmi2GetEventIndicators: the model's indicators at the current time, states and modes.
    pub fn get_event_indicators(&mut self, z: &mut [f64]) -> CallResult {
        self.check_length(z.len(), "event indicators", self.table.indicators.len())?;
        self.refresh();
        let v = &self.values;
        let k = Knowns::new(self.time, &v.known, &self.states, &v.integers, &v.booleans);
        z.fill(0.0);
        self.model.event_indicators(&k, &mut EventIndicators::new(z));
        Ok(())
    }

    /// fmi2CompletedIntegratorStep: (enter event mode, terminate): never needed here.
    pub fn completed_integrator_step(&mut self) -> CallResult<(bool, bool)> {
        Ok((false, false))
    }

    // ---- Directional derivatives -------------------------------------------------------------

    /// fmi2GetDirectionalDerivative: d(unknowns) = J d(knowns), by central differences of the
    /// model's equations along the direction `dv_known` (step 1e-7 of the knowns' scale, refined
    /// near kinks; about 1e-9 relative accuracy on smooth equations). Knowns: states, inputs, parameters;
    /// unknowns: state derivatives, outputs, locals and calculated parameters.
    pub fn directional_derivative(&mut self, unknowns: &[u32], knowns: &[u32], dv_known: &[f64], dv_unknown: &mut [f64]) -> CallResult {
        let mut slots = Vec::with_capacity(knowns.len());
        for vr in knowns {
            let var = self.variable(*vr, BaseType::Real)?;
            let Slot::Known(i) = var.slot else {
                return Err(Failure::error(format!("'{}' is not a known (a state, an input or a parameter)", var.name)));
            };
            let state = self.table.state_known_index.iter().position(|k| *k == i);
            slots.push((i, state, var.nominal.unwrap_or(1.0).abs()));
        }
        // During initialization the calculated states are unknowns too, computed from the knowns.
        let initializing = self.phase.is_before_initialization_end();
        for vr in unknowns {
            let var = self.variable(*vr, BaseType::Real)?;
            let calculated_state = initializing && var.initial == Some(crate::variables::Initial::Calculated) && self.table.state_index(var).is_some();
            if !(matches!(var.slot, Slot::Calculated(_) | Slot::Derivative(_)) || calculated_state) {
                return Err(Failure::error(format!("'{}' is not an unknown (a derivative or a computed value)", var.name)));
            }
        }
        if let Some(j) = dv_known.iter().position(|v| !v.is_finite()) {
            return Err(Failure::error(format!("the seed of known {} is not finite", knowns[j])));
        }
        self.refresh();
        let (known, states) = (&self.values.known, &self.states);
        let value = |j: usize| match slots[j].1 {
            Some(s) => states[s],
            None => known[slots[j].0],
        };
        if dv_known.iter().all(|v| *v == 0.0) {
            dv_unknown.fill(0.0);
            return Ok(());
        }
        // Step: 1e-7 of each seeded known's scale max(|value|, nominal) (nominal 1 where
        // undeclared), the smallest over the seed. Then up to four refinements by 10: for each
        // unknown the first estimate that agrees with the next finer one (to 1e-4: far above
        // rounding, far below the jump of a straddled kink) is kept, so a kink near the point
        // (an activity's |power|) is not straddled, while smooth equations keep the first
        // step's small rounding error. Agreement is judged against the largest of the five
        // estimates: where the first step straddles a kink and the function is flat on the
        // near side (MotorFan's rigid reducer 6e-6 rad/s after standstill, whose efficiency
        // switches with the sign of the speed), the finer estimates are rounding noise around
        // zero, which never agree with each other by their own size; by the jump's they do.
        // Where none agree, the finer of the two neighbouring estimates that differ least
        // stands (an estimate that shrinks with the step, the zero slope of the fan's w |w| at
        // w = 0, ends on its finest).
        let h0 = (0..slots.len())
            .filter(|j| dv_known[*j] != 0.0)
            .map(|j| 1e-7 * value(j).abs().max(slots[j].2) / dv_known[j].abs())
            .fold(f64::INFINITY, f64::min);
        let central = |h: f64| {
            let at = |sign: f64| {
                let (mut k, mut x) = (known.clone(), states.clone());
                for (j, (i, state, _)) in slots.iter().enumerate() {
                    match state {
                        Some(s) => x[*s] += sign * h * dv_known[j],
                        None => k[*i] += sign * h * dv_known[j],
                    }
                }
                let (mut der, mut calc) = (self.values.derivatives.clone(), self.values.calculated.clone());
                let v = &self.values;
                if initializing {
                    // A failure leaves NaN in the calculated states, and so in the derivative.
                    let _ = crate::model::initialize_states(&*self.model, &self.table, self.time, &k, &v.integers, &v.booleans, &mut x);
                }
                evaluate(&*self.model, &self.table, self.time, &k, &x, &v.integers, &v.booleans, &mut der, &mut calc);
                (der, calc, x)
            };
            let ((der_plus, calc_plus, x_plus), (der_minus, calc_minus, x_minus)) = (at(1.0), at(-1.0));
            // Each estimate with its rounding noise: ROUNDING_ULPS ulps of the larger of the two
            // values, over 2h.
            let estimate = |plus: f64, minus: f64| ((plus - minus) / (2.0 * h), ROUNDING_ULPS * f64::EPSILON * plus.abs().max(minus.abs()) / (2.0 * h));
            unknowns
                .iter()
                .map(|vr| {
                    let var = &self.table.variables[*vr as usize];
                    match var.slot {
                        Slot::Derivative(i) => estimate(der_plus[i], der_minus[i]),
                        Slot::Calculated(i) => estimate(calc_plus[i], calc_minus[i]),
                        _ => {
                            let s = self.table.state_index(var).expect("checked above: a calculated state");
                            estimate(x_plus[s], x_minus[s])
                        }
                    }
                })
                .collect::<Vec<(f64, f64)>>()
        };
        let estimates: Vec<Vec<(f64, f64)>> = (0..5).map(|r| central(h0 / 10f64.powi(r))).collect();
        for (u, out) in dv_unknown.iter_mut().enumerate() {
            let e = |r: usize| estimates[r][u].0;
            let noise = |r: usize| estimates[r][u].1;
            let scale = (0..5).map(|r| e(r).abs()).fold(f64::MIN_POSITIVE, f64::max);
            // Two neighbouring estimates agree within 1e-4 of the scale, or within their
            // rounding noise: where the unknown barely moves against its own size (PowerSteering's
            // 35 W worm loss moves by 0.02 W per radian of the arm's stretch), the finer steps'
            // estimates are rounding noise, and two of them that both come out exactly 0 must
            // not outvote the first, sound one.
            let agree = |r: usize| (e(r) - e(r + 1)).abs() <= (1e-4 * scale).max(noise(r) + noise(r + 1));
            let differs = |r: usize| (e(r) - e(r + 1)).abs();
            let steadiest = || (0..4).min_by(|a, b| differs(*a).total_cmp(&differs(*b))).map_or(0, |r| r + 1);
            *out = match (0..4).find(|r| agree(*r)) {
                Some(r) => e(r),
                None => e(steadiest()),
            };
        }
        // The activity and share outputs the runtime itself writes: exactly.
        if !self.table.elements.is_empty() {
            let mut d_states = vec![0.0; self.table.n_states];
            for (j, (_, state, _)) in slots.iter().enumerate() {
                if let Some(s) = state {
                    d_states[*s] += dv_known[j];
                }
            }
            for (out, vr) in dv_unknown.iter_mut().zip(unknowns) {
                if let Slot::Calculated(y) = self.table.variables[*vr as usize].slot {
                    if let Some(d) = crate::elements::output_derivative(&self.table.elements, &self.states, &d_states, y) {
                        *out = d;
                    }
                }
            }
        }
        Ok(())
    }

    fn snapshot(&self) -> Snapshot {
        Snapshot {
            phase: self.phase,
            time: self.time,
            experiment: self.experiment,
            values: self.values.clone(),
            states: self.states.clone(),
            step_size: self.integrator.as_ref().and_then(|i| i.step_size),
            lookahead: self.integrator.as_ref().and_then(|i| i.lookahead()),
            input_slopes: self.input_slopes.clone(),
            input_curvatures: self.input_curvatures.clone(),
            previous_inputs: self.previous_inputs.clone(),
        }
    }

    fn restore(&mut self, s: Snapshot) -> CallResult {
        let initialized = !s.phase.is_before_initialization_end();
        self.phase = s.phase;
        self.time = s.time;
        self.experiment = s.experiment;
        self.values = s.values;
        self.states = s.states;
        self.input_slopes = s.input_slopes;
        self.input_curvatures = s.input_curvatures;
        self.previous_inputs = s.previous_inputs;
        self.stale = true;
        self.knowns_set = true;
        self.integrator = None;
        if initialized && self.interface == Interface::CoSimulation {
            let mut integrator = self.make_integrator().map_err(Failure::error)?;
            integrator.step_size = s.step_size;
            if let Some(lookahead) = &s.lookahead {
                integrator.resume_lookahead(lookahead, self.time, &self.states);
            }
            self.integrator = Some(integrator);
        }
        Ok(())
    }

    /// fmi2GetFMUstate: a new handle (`existing` = None) or overwrite a live one.
    pub fn get_fmu_state(&mut self, existing: Option<usize>) -> CallResult<usize> {
        let s = self.snapshot();
        match existing {
            None => self.snapshots.insert(s).map_err(Failure::error),
            Some(h) if self.snapshots.replace(h, s) => Ok(h),
            Some(h) => Err(Failure::error(format!("FMU state {h:#x} is not a live state of this instance (freed or never made here)"))),
        }
    }

    pub fn set_fmu_state(&mut self, handle: usize) -> CallResult {
        let s = self
            .snapshots
            .get(handle)
            .cloned()
            .ok_or_else(|| Failure::error(format!("FMU state {handle:#x} is not a live state of this instance (freed or never made here)")))?;
        self.restore(s)?;
        self.debug(&format!("restored the FMU state of t = {} s", self.time));
        Ok(())
    }

    pub fn free_fmu_state(&mut self, handle: usize) -> CallResult {
        if self.snapshots.remove(handle) {
            Ok(())
        } else {
            Err(Failure::error(format!("FMU state {handle:#x} was already freed or was never made by this instance")))
        }
    }

    pub fn serialize_fmu_state(&self, handle: usize) -> CallResult<Vec<u8>> {
        self.snapshots
            .get(handle)
            .map(|s| s.serialize(self.guid))
            .ok_or_else(|| Failure::error(format!("FMU state {handle:#x} is not a live state of this instance")))
    }

    pub fn deserialize_fmu_state(&mut self, bytes: &[u8], existing: Option<usize>) -> CallResult<usize> {
        let t = &self.table;
        let shape = Shape { known: t.n_known, calculated: t.n_calculated, states: t.n_states, integers: t.n_integers, booleans: t.n_booleans };
        let s = Snapshot::deserialize(bytes, self.guid, &shape).map_err(Failure::error)?;
        match existing {
            None => self.snapshots.insert(s).map_err(Failure::error),
            Some(h) if self.snapshots.replace(h, s) => Ok(h),
            Some(h) => Err(Failure::error(format!("FMU state {h:#x} is not a live state of this instance"))),
        }
    }

    /// Sends the message of a failed call to the master's logger.
    pub fn report(&self, failure: &Failure) {
        let status = if failure.status == Status::Ok { Status::Warning } else { failure.status };
        self.logger.log(status, &failure.message);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_model::Decay;

    // Decay's value references: a=0, u=1, x=2, der(x)=3, y=4, w=5.
    fn initialized() -> Instance<Decay> {
        let mut i = Instance::<Decay>::new("{test}", Logger::silent());
        i.setup_experiment(Some(1e-8), 0.0, None).unwrap();
        i.enter_initialization_mode().unwrap();
        i.exit_initialization_mode().unwrap();
        i
    }

    fn get(i: &mut Instance<Decay>, vr: u32) -> f64 {
        let mut v = [0.0];
        i.get(&[vr], &mut v).unwrap();
        v[0]
    }

    #[test]
    fn steps_follow_the_exponential() {
        // x' = -a x with x(0) = 1, a = 2: x(t) = exp(-2 t).
        let mut i = initialized();
        for n in 0..100 {
            i.do_step(n as f64 * 0.01, 0.01).unwrap();
        }
        let x = get(&mut i, 2);
        assert!((x - (-2.0f64).exp()).abs() < 1e-7, "{x}");
        assert_eq!(get(&mut i, 4), 2.0 * x);
        assert!((get(&mut i, 3) + 2.0 * x).abs() < 1e-12);
    }

    #[test]
    fn a_set_is_all_or_nothing() {
        let mut i = initialized();
        let err = i.set(&[1, 0], &[3.0, 5.0]).unwrap_err();
        assert!(err.message.contains("'a'") && err.message.contains("fixed parameter"), "{}", err.message);
        assert_eq!(get(&mut i, 1), 0.0, "u must not be written when a later value is refused");
        i.set(&[1], &[3.0]).unwrap();
        assert_eq!(get(&mut i, 5), 6.0, "w = a u is recomputed after the input changes");
    }

    #[test]
    fn out_of_range_parameters_are_refused_and_named() {
        let mut i = Instance::<Decay>::new("{test}", Logger::silent());
        let err = i.set(&[0], &[-1.0]).unwrap_err();
        assert!(err.message.contains("a = -1") && err.message.contains("minimum"), "{}", err.message);
        assert!(i.set(&[1], &[f64::NAN]).is_err());
        assert!(i.set(&[3], &[1.0]).unwrap_err().message.contains("derivative"));
        assert!(i.set(&[99], &[1.0]).unwrap_err().message.contains("unknown value reference 99"));
    }

    #[test]
    fn communication_points_must_match_the_instance_time() {
        let mut i = initialized();
        i.do_step(0.0, 0.1).unwrap();
        let err = i.do_step(0.2, 0.1).unwrap_err();
        assert!(err.message.contains("does not match"), "{}", err.message);
        // Rounding of a master's own time keeping is accepted: 0.1 vs 0.1 + 1 ulp.
        i.do_step(0.1 + f64::EPSILON * 0.1, 0.1).unwrap();
        assert!(i.do_step(0.2, 0.0).is_err() && i.do_step(0.2, -0.1).is_err());
    }

    #[test]
    fn a_defined_stop_time_cannot_be_passed() {
        let mut i = Instance::<Decay>::new("{test}", Logger::silent());
        i.setup_experiment(None, 0.0, Some(0.3)).unwrap();
        i.enter_initialization_mode().unwrap();
        i.exit_initialization_mode().unwrap();
        for n in 0..3 {
            i.do_step(n as f64 * 0.1, 0.1).unwrap();
        }
        let err = i.do_step(0.30000000000000004, 0.1).unwrap_err();
        assert!(err.message.contains("stop time"), "{}", err.message);
        assert_eq!(get(&mut i, 0), 2.0, "the instance keeps working");
    }

    #[test]
    fn a_restored_state_continues_bit_identically() {
        let mut i = initialized();
        i.do_step(0.0, 0.25).unwrap();
        let saved = i.get_fmu_state(None).unwrap();
        i.do_step(0.25, 0.25).unwrap();
        let first = get(&mut i, 2);
        i.set_fmu_state(saved).unwrap();
        assert_eq!(i.time(), 0.25);
        i.do_step(0.25, 0.25).unwrap();
        assert_eq!(get(&mut i, 2).to_bits(), first.to_bits());
        i.free_fmu_state(saved).unwrap();
        assert!(i.free_fmu_state(saved).is_err());
    }

    #[test]
    fn time_events_stop_the_solver_at_the_kink() {
        // x' = 0 before t_on = 0.35 s, 1 after: x(1) = 0.65 s, although the communication step
        // 0.5 s straddles the switch. The segment ending at t_on still sees the new slope in its
        // last stage (the equations have no discrete mode), which costs ~1e-9 s here.
        let mut i = Instance::<crate::test_model::Switch>::new("{test}", Logger::silent());
        i.setup_experiment(None, 0.0, None).unwrap();
        i.enter_initialization_mode().unwrap();
        i.exit_initialization_mode().unwrap();
        i.do_step(0.0, 0.5).unwrap();
        i.do_step(0.5, 0.5).unwrap();
        let mut x = [0.0];
        i.get(&[1], &mut x).unwrap();
        assert!((x[0] - 0.65).abs() < 1e-8, "{}", x[0]);
    }

    #[test]
    fn model_exchange_hands_the_states_to_the_master() {
        let mut i = Instance::<Decay>::for_interface(Interface::ModelExchange, "{test}", Logger::silent());
        i.setup_experiment(None, 0.0, None).unwrap();
        i.enter_initialization_mode().unwrap();
        let mut x = [0.0];
        i.get_continuous_states(&mut x).unwrap();
        assert_eq!(x, [1.0], "the start value");
        i.exit_initialization_mode().unwrap();
        assert_eq!(i.phase, Phase::Event);
        assert_eq!(i.new_discrete_states().unwrap().next_event_time, None);
        i.enter_continuous_time_mode().unwrap();
        i.set_time(0.5).unwrap();
        i.set_continuous_states(&[3.0]).unwrap();
        let mut dx = [0.0];
        i.get_derivatives(&mut dx).unwrap();
        assert_eq!(dx, [-6.0], "x' = -a x with a = 2");
        assert_eq!(get(&mut i, 2), 3.0, "the state variable follows fmi2SetContinuousStates");
        assert!(i.set_continuous_states(&[1.0, 2.0]).is_err());
        assert!(i.set_continuous_states(&[f64::NAN]).is_err());
    }

    #[test]
    fn directional_derivatives_match_the_equations() {
        // x' = -a x + u, y = 2 x, w = a u (a = 2): d(x')/dx = -2, dy/dx = 2, dw/du = 2, d(x')/du = 1
        // (central differences with a 1e-7 relative step: exact up to rounding, ~1e-9).
        let mut i = initialized();
        i.set(&[1], &[0.7]).unwrap();
        let mut out = [0.0; 3];
        i.directional_derivative(&[3, 4, 5], &[2], &[1.0], &mut out).unwrap();
        for (got, want) in out.iter().zip([-2.0, 2.0, 0.0]) {
            assert!((got - want).abs() < 1e-8, "{out:?}");
        }
        i.directional_derivative(&[3, 4, 5], &[1], &[1.0], &mut out).unwrap();
        for (got, want) in out.iter().zip([1.0, 0.0, 2.0]) {
            assert!((got - want).abs() < 1e-8, "{out:?}");
        }
        assert!(i.directional_derivative(&[0], &[1], &[1.0], &mut [0.0]).is_err(), "a parameter is no unknown");
        assert!(i.directional_derivative(&[3], &[4], &[1.0], &mut [0.0]).is_err(), "an output is no known");
    }

    #[test]
    fn input_derivatives_move_the_input_over_one_step() {
        // x' = -a x + u with u = u0 + s (t - t0) over [0, 1]: compare with a held input shifted
        // by the exact solution's difference: x(1) - x_held(1) = s * (1 - (1 - e^-a)/a) / a.
        let (a, s) = (2.0f64, 0.8);
        let run = |slope: Option<f64>| {
            let mut i = initialized();
            if let Some(sl) = slope {
                i.set_input_derivatives(&[1], &[1], &[sl]).unwrap();
            }
            i.do_step(0.0, 1.0).unwrap();
            get(&mut i, 2)
        };
        let exact = s * (1.0 - (1.0 - (-a).exp()) / a) / a;
        assert!(((run(Some(s)) - run(None)) - exact).abs() < 1e-6, "{} vs {exact}", run(Some(s)) - run(None));
        let mut i = initialized();
        assert!(i.set_input_derivatives(&[0], &[1], &[1.0]).is_err(), "a parameter is not an input");
        assert!(i.set_input_derivatives(&[1], &[3], &[1.0]).is_err(), "order 3");
    }

    #[test]
    fn extrapolated_inputs_follow_the_last_two_communication_points() {
        // x' = -a x + u. Step 1 from t = 0 with u = 0, step 2 from t = 1 with u = 1: with
        // extrapolation u(t) = 1 + (t - 1) over step 2, without it u = 1. The difference at t = 2
        // is the response to a unit ramp: (1 - (1 - e^-a)/a)/a (a = 2).
        let run = |extrapolate: bool| {
            let mut i = Instance::<Decay>::new("{test}", Logger::silent());
            let flag = i.table().by_name("extrapolate_inputs").expect("declared for models with inputs").value_reference;
            i.set(&[flag], &[extrapolate]).unwrap();
            i.setup_experiment(Some(1e-10), 0.0, None).unwrap();
            i.enter_initialization_mode().unwrap();
            i.exit_initialization_mode().unwrap();
            i.do_step(0.0, 1.0).unwrap();
            i.set(&[1], &[1.0]).unwrap();
            i.do_step(1.0, 1.0).unwrap();
            get(&mut i, 2)
        };
        let a = 2.0f64;
        let exact = (1.0 - (1.0 - (-a).exp()) / a) / a;
        assert!(((run(true) - run(false)) - exact).abs() < 1e-7, "{} vs {exact}", run(true) - run(false));
    }

    #[test]
    fn output_derivatives_follow_the_motion() {
        // y = 2 x, x' = -a x + u: dy/dt = 2 (-2 x + u); w = a u: dw/dt = a du/dt = 2 s.
        let mut i = initialized();
        i.set(&[1], &[0.5]).unwrap();
        i.do_step(0.0, 0.1).unwrap();
        i.set_input_derivatives(&[1], &[1], &[0.3]).unwrap();
        let x = get(&mut i, 2);
        let mut d = [0.0; 2];
        i.output_derivatives(&[4, 5], &[1, 1], &mut d).unwrap();
        assert!((d[0] - 2.0 * (-2.0 * x + 0.5)).abs() < 1e-7, "{d:?}");
        assert!((d[1] - 0.6).abs() < 1e-7, "{d:?}");
        assert!(i.output_derivatives(&[4], &[2], &mut [0.0]).is_err());
    }

    #[test]
    fn an_event_a_rounding_away_from_the_step_end_does_not_fail_the_step() {
        // A master's float time: 1 ms summed 10 000 times lands ~1e-13 s off 10 s, where the
        // event sits; the step must not ask the solver for a 1e-13 s segment (diffsol refuses).
        let mut i = Instance::<crate::test_model::Switch>::new("{test}", Logger::silent());
        let t_on = i.table().by_name("t_on").unwrap().value_reference;
        i.set(&[t_on], &[10.0]).unwrap();
        i.setup_experiment(None, 0.0, None).unwrap();
        i.enter_initialization_mode().unwrap();
        i.exit_initialization_mode().unwrap();
        let mut t = 0.0;
        for _ in 0..10_050 {
            i.do_step(t, 1e-3).unwrap();
            t += 1e-3;
        }
        let mut x = [0.0];
        i.get(&[1], &mut x).unwrap();
        assert!((x[0] - 0.05).abs() < 1e-9, "{}", x[0]);
    }

    fn block(interface: Interface) -> Instance<crate::test_model::Block> {
        block_of(interface)
    }

    fn block_of<M: Model>(interface: Interface) -> Instance<M> {
        let mut i = Instance::<M>::for_interface(interface, "{test}", Logger::silent());
        i.setup_experiment(Some(1e-8), 0.0, None).unwrap();
        i.enter_initialization_mode().unwrap();
        i.exit_initialization_mode().unwrap();
        i
    }

    fn named<M: Model>(i: &mut Instance<M>, name: &str) -> f64 {
        let var = i.table().by_name(name).unwrap_or_else(|| panic!("{name}"));
        let vr = var.value_reference;
        if var.base_type() == BaseType::Integer {
            let mut n = [0];
            i.get(&[vr], &mut n).unwrap();
            n[0] as f64
        } else {
            let mut x = [0.0];
            i.get(&[vr], &mut x).unwrap();
            x[0]
        }
    }

    #[test]
    fn a_sliding_block_sticks_once_and_stays_stuck() {
        // m = 1 kg, v0 = 3 m/s, F_c = 1.5 N: v = 3 - 1.5 t until t = 2 s, x = 3 - 0.75 t^2 ... = 3 m
        // at rest (x = v0^2 m / (2 F_c)). With sign(v) friction the block would chatter about
        // v = 0; with modes it sticks at one located event and v is exactly 0 afterwards.
        let mut i = block(Interface::CoSimulation);
        assert_eq!(named(&mut i, "friction_mode"), 1.0, "v0 > 0: slipping forwards from the start");
        for n in 0..7 {
            i.do_step(n as f64 * 0.5, 0.5).unwrap();
        }
        assert!((named(&mut i, "x") - 3.0).abs() < 1e-9, "{}", named(&mut i, "x"));
        assert_eq!(named(&mut i, "v"), 0.0);
        assert_eq!(named(&mut i, "friction_mode"), 0.0);
        assert_eq!(named(&mut i, "state_events"), 1.0, "one event: slip -> stick");
        // A force below the static friction (2 N) does not move it: no event, x holds.
        let u = i.table().by_name("u").unwrap().value_reference;
        i.set(&[u], &[1.9]).unwrap();
        i.do_step(3.5, 1.0).unwrap();
        assert!((named(&mut i, "x") - 3.0).abs() < 1e-9);
        assert_eq!(named(&mut i, "state_events"), 1.0);
        // Above it, it breaks loose at the communication point: a = (2.5 - 1.5) / 1 m/s2.
        i.set(&[u], &[2.5]).unwrap();
        i.do_step(4.5, 1.0).unwrap();
        assert_eq!(named(&mut i, "friction_mode"), 1.0);
        assert!((named(&mut i, "v") - 1.0).abs() < 1e-9);
        assert!((named(&mut i, "x") - 3.5).abs() < 1e-9);
        // Pushed back with 1 N (< F_s but > 0): decelerates at (1 + 1.5) m/s2, sticks at 5.9 s.
        i.set(&[u], &[-1.0]).unwrap();
        i.do_step(5.5, 1.0).unwrap();
        assert_eq!(named(&mut i, "friction_mode"), 0.0);
        assert_eq!(named(&mut i, "state_events"), 2.0);
        assert!((named(&mut i, "x") - (3.5 + 1.0 / (2.0 * 2.5))).abs() < 1e-9, "{}", named(&mut i, "x"));
    }

    #[test]
    fn the_crossing_is_located_inside_the_step() {
        // The stick event of a 3 m/s block with F_c = 1.5 N is at 2 s; a step [1.5, 2.5] s ends
        // there with v = 0 and x = 3 m, whatever the step; the indicator read after the step is the
        // static margin F_s - |u| = 2 N.
        let mut i = block(Interface::CoSimulation);
        i.do_step(0.0, 1.5).unwrap();
        assert!((named(&mut i, "v") - 0.75).abs() < 1e-9);
        i.do_step(1.5, 1.0).unwrap();
        assert_eq!(named(&mut i, "v"), 0.0);
        assert!((named(&mut i, "x") - 3.0).abs() < 1e-9);
    }

    #[test]
    fn the_solver_steps_past_communication_points_but_not_past_a_time_event_or_the_stop_time() {
        // x' = 0 until t_on = 0.35 s: the error estimate is zero, the steps double each time,
        // so they reach far past 10 ms communication steps; none passes t_on or the stop time.
        let mut i = Instance::<crate::test_model::Switch>::new("{test}", Logger::silent());
        i.setup_experiment(None, 0.0, Some(1.0)).unwrap();
        i.enter_initialization_mode().unwrap();
        i.exit_initialization_mode().unwrap();
        let (mut t, mut ahead) = (0.0, 0);
        for _ in 0..100 {
            i.do_step(t, 0.01).unwrap();
            t += 0.01;
            if let Some(la) = i.integrator.as_ref().and_then(|g| g.lookahead()) {
                // (The last communication point, 100 x 0.01 = 1.0000000000000007 s, passes the
                // stop time by rounding: accepted, and the bound there.)
                let bound = if t < 0.35 { 0.35 } else { t.max(1.0) };
                assert!(la.step.t_end <= bound, "a step to {} s from t = {t} s", la.step.t_end);
                assert!(la.step.t_start < t && t <= la.step.t_end);
                ahead += (la.step.t_end > t + 0.01) as usize;
            }
        }
        assert!(ahead > 50, "{ahead} doSteps ended inside a step reaching past the next communication point");
        assert!((named(&mut i, "x") - 0.65).abs() < 1e-9, "{}", named(&mut i, "x"));
    }

    #[test]
    fn a_crossing_past_the_communication_point_waits_for_the_step_that_reaches_it() {
        // The 3 m/s block sticks at 2 s (v = 3 - 1.5 t); with 10 ms communication steps the solver's
        // steps reach past 2 s before the doStep that contains it, which alone sees the event.
        let mut i = block(Interface::CoSimulation);
        let mut t = 0.0;
        for _ in 0..250 {
            i.do_step(t, 0.01).unwrap();
            t += 0.01;
            if t < 2.0 - 1e-9 {
                assert_eq!(named(&mut i, "state_events"), 0.0, "at {t} s");
                assert!((named(&mut i, "v") - (3.0 - 1.5 * t)).abs() < 1e-9, "at {t} s: {}", named(&mut i, "v"));
            } else {
                assert_eq!(named(&mut i, "state_events"), 1.0, "at {t} s");
                assert_eq!(named(&mut i, "v"), 0.0);
                assert!((named(&mut i, "x") - 3.0).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn the_implicit_solver_locates_the_same_event() {
        let mut i = block_of::<crate::test_model::ImplicitBlock>(Interface::CoSimulation);
        i.do_step(0.0, 1.5).unwrap();
        i.do_step(1.5, 1.0).unwrap();
        assert_eq!(named(&mut i, "v"), 0.0);
        assert!((named(&mut i, "x") - 3.0).abs() < 1e-8, "{}", named(&mut i, "x"));
        assert_eq!((named(&mut i, "friction_mode"), named(&mut i, "state_events")), (0.0, 1.0));
    }

    #[test]
    fn modes_are_part_of_fmu_states_and_reset() {
        let mut i = block(Interface::CoSimulation);
        i.do_step(0.0, 1.0).unwrap();
        let saved = i.get_fmu_state(None).unwrap();
        let bytes = i.serialize_fmu_state(saved).unwrap();
        i.do_step(1.0, 2.0).unwrap();
        let (x_end, events_end) = (named(&mut i, "x"), named(&mut i, "state_events"));
        assert_eq!((named(&mut i, "friction_mode"), events_end), (0.0, 1.0));
        i.set_fmu_state(saved).unwrap();
        assert_eq!((named(&mut i, "friction_mode"), named(&mut i, "state_events")), (1.0, 0.0));
        i.do_step(1.0, 2.0).unwrap();
        assert_eq!(named(&mut i, "x").to_bits(), x_end.to_bits());
        let restored = i.deserialize_fmu_state(&bytes, None).unwrap();
        i.set_fmu_state(restored).unwrap();
        assert_eq!(named(&mut i, "friction_mode"), 1.0, "deserialized");
        i.reset().unwrap();
        i.enter_initialization_mode().unwrap();
        i.exit_initialization_mode().unwrap();
        assert_eq!((named(&mut i, "friction_mode"), named(&mut i, "state_events")), (1.0, 0.0));
    }

    #[test]
    fn model_exchange_reports_indicators_and_updates_modes() {
        let mut i = block(Interface::ModelExchange);
        let mut z = [0.0];
        i.get_event_indicators(&mut z).unwrap();
        assert_eq!(z, [3.0], "slipping forwards: z = v");
        assert!(i.get_event_indicators(&mut [0.0, 0.0]).is_err());
        assert!(!i.new_discrete_states().unwrap().values_changed, "the modes were settled at initialization");
        i.enter_continuous_time_mode().unwrap();
        i.set_time(2.0 + 1e-12).unwrap();
        i.set_continuous_states(&[3.0, -1.5e-12]).unwrap();
        i.get_event_indicators(&mut z).unwrap();
        assert!(z[0] < 0.0, "the master sees the crossing");
        i.enter_event_mode().unwrap();
        let info = i.new_discrete_states().unwrap();
        assert!(info.values_changed && !info.new_discrete_states_needed, "{info:?}");
        let mut x = [0.0; 2];
        i.get_continuous_states(&mut x).unwrap();
        assert_eq!(x, [3.0, 0.0], "stuck: v re-initialized to 0");
        assert_eq!((named(&mut i, "friction_mode"), named(&mut i, "state_events")), (0.0, 1.0));
        i.get_event_indicators(&mut z).unwrap();
        assert_eq!(z, [2.0], "stuck: the static margin F_s - |u|");
        let mut dx = [1.0; 2];
        i.get_derivatives(&mut dx).unwrap();
        assert_eq!(dx, [0.0, 0.0]);
    }

    /// The Model Exchange rule (docs/DESIGN.md, "Model Exchange events any integrator survives"):
    /// after an event that changed a mode, either the FMU says the continuous states changed (the
    /// master restarts its integrator) or no indicator sits at zero. A block stuck at rest that an
    /// applied force breaks loose slips from v = 0: its new indicator, mode x v, is exactly 0.
    #[test]
    fn a_mode_switch_whose_indicator_starts_at_zero_tells_the_master_to_restart() {
        let mut i = Instance::<crate::test_model::Block>::for_interface(Interface::ModelExchange, "{test}", Logger::silent());
        i.setup_experiment(Some(1e-4), 0.0, None).unwrap();
        i.enter_initialization_mode().unwrap();
        let v = i.table().by_name("v").unwrap().value_reference;
        i.set(&[v], &[0.0]).unwrap();
        i.exit_initialization_mode().unwrap();
        assert_eq!(named(&mut i, "friction_mode"), 0.0, "at rest with no force: stuck");
        assert!(!i.new_discrete_states().unwrap().values_changed, "nothing changed");
        i.enter_continuous_time_mode().unwrap();
        // The force rises past the static friction (F_s = 2 N m): the stuck margin crosses zero.
        let u = i.table().by_name("u").unwrap().value_reference;
        i.set_time(0.5).unwrap();
        i.set(&[u], &[2.5]).unwrap();
        let mut z = [0.0];
        i.get_event_indicators(&mut z).unwrap();
        assert!(z[0] < 0.0, "the master sees the crossing: {z:?}");
        i.enter_event_mode().unwrap();
        let info = i.new_discrete_states().unwrap();
        assert_eq!(named(&mut i, "friction_mode"), 1.0, "slipping forwards");
        i.get_event_indicators(&mut z).unwrap();
        assert_eq!(z, [0.0], "the slipping mode's indicator, v = 0, starts exactly at zero");
        assert!(info.values_changed, "so the master must be told to restart its integrator: {info:?}");
        // And no mode change, no restart: a second event iteration changes nothing.
        assert!(!i.new_discrete_states().unwrap().values_changed);
    }

    /// Steps `a` from `*t` by `h`, and again a twin restored from `a`'s serialized state of
    /// before the step: `a` keeps its solver alive, the twin makes one afresh. Their states,
    /// knowns, modes and step sizes must agree bit for bit.
    fn step_twice<M: Model>(a: &mut Instance<M>, twin: &mut Instance<M>, t: &mut f64, h: f64) {
        let saved = a.get_fmu_state(None).unwrap();
        let bytes = a.serialize_fmu_state(saved).unwrap();
        a.free_fmu_state(saved).unwrap();
        let restored = twin.deserialize_fmu_state(&bytes, None).unwrap();
        twin.set_fmu_state(restored).unwrap();
        twin.free_fmu_state(restored).unwrap();
        a.do_step(*t, h).unwrap();
        twin.do_step(*t, h).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a.states), bits(&twin.states), "states after the step from {t}");
        assert_eq!(bits(&a.values.known), bits(&twin.values.known), "knowns after the step from {t}");
        assert_eq!(a.values.integers, twin.values.integers, "modes after the step from {t}");
        let step_size = |i: &Instance<M>| i.integrator.as_ref().and_then(|g| g.step_size).map(f64::to_bits);
        assert_eq!(step_size(a), step_size(twin), "step size after the step from {t}");
        *t += h;
    }

    #[test]
    fn a_kept_solver_steps_as_one_made_afresh_from_a_saved_state() {
        // The sliding block: slips, sticks at 2 s (a state event), is pushed loose, sticks again.
        let (mut a, mut twin) = (block(Interface::CoSimulation), block(Interface::CoSimulation));
        let u = a.table().by_name("u").unwrap().value_reference;
        let mut t = 0.0;
        for k in 0..120 {
            match k {
                60 => a.set(&[u], &[2.5]).unwrap(),
                80 => a.set(&[u], &[-1.0]).unwrap(),
                _ => {}
            }
            step_twice(&mut a, &mut twin, &mut t, 0.05);
        }
        assert_eq!(named(&mut a, "state_events"), 2.0, "both events were crossed");
        // Decay with inputs: held, ramped by input derivatives, changed, held again; with and
        // without input extrapolation.
        for extrapolate in [false, true] {
            let decay = || {
                let mut i = Instance::<Decay>::new("{test}", Logger::silent());
                let flag = i.table().by_name("extrapolate_inputs").unwrap().value_reference;
                i.set(&[flag], &[extrapolate]).unwrap();
                i.setup_experiment(Some(1e-8), 0.0, None).unwrap();
                i.enter_initialization_mode().unwrap();
                i.exit_initialization_mode().unwrap();
                i
            };
            let (mut a, mut twin) = (decay(), decay());
            let mut t = 0.0;
            for k in 0..60 {
                match k {
                    10..=19 => {
                        a.set(&[1], &[0.1 * k as f64]).unwrap();
                        a.set_input_derivatives(&[1], &[1], &[0.3]).unwrap();
                    }
                    20..=39 => a.set(&[1], &[(k as f64).sin()]).unwrap(),
                    _ => {}
                }
                step_twice(&mut a, &mut twin, &mut t, 0.01);
            }
        }
        // Through a time event, with steps reaching far past the communication points.
        let switch = || {
            let mut i = Instance::<crate::test_model::Switch>::new("{test}", Logger::silent());
            i.setup_experiment(None, 0.0, None).unwrap();
            i.enter_initialization_mode().unwrap();
            i.exit_initialization_mode().unwrap();
            i
        };
        let (mut a, mut twin) = (switch(), switch());
        let mut t = 0.0;
        for _ in 0..60 {
            step_twice(&mut a, &mut twin, &mut t, 0.01);
        }
        // The block with short communication steps: the stick event at 2 s is seen from steps
        // reaching past it.
        let (mut a, mut twin) = (block(Interface::CoSimulation), block(Interface::CoSimulation));
        let mut t = 1.8;
        a.do_step(0.0, 1.8).unwrap();
        for _ in 0..40 {
            step_twice(&mut a, &mut twin, &mut t, 0.01);
        }
        assert_eq!(named(&mut a, "state_events"), 1.0);
        // The implicit solver (re-made every step anyway).
        let (mut a, mut twin) = (block_of::<crate::test_model::ImplicitBlock>(Interface::CoSimulation), block_of::<crate::test_model::ImplicitBlock>(Interface::CoSimulation));
        let mut t = 0.0;
        for _ in 0..60 {
            step_twice(&mut a, &mut twin, &mut t, 0.05);
        }
    }

    #[test]
    fn reset_returns_to_the_start_values() {
        let mut i = initialized();
        i.do_step(0.0, 0.5).unwrap();
        i.reset().unwrap();
        assert_eq!(i.phase, Phase::Instantiated);
        i.enter_initialization_mode().unwrap();
        assert_eq!(get(&mut i, 2), 1.0);
    }

    fn relax_value(i: &mut Instance<crate::test_model::Relax>, vr: u32) -> f64 {
        let mut v = [0.0];
        i.get(&[vr], &mut v).unwrap();
        v[0]
    }

    #[test]
    fn calculated_states_start_where_the_model_says() {
        use crate::test_model::Relax;
        // vrs: p=0, g=1, steady=2, u=3, T=4, der(T)=5, y=6
        let mut i: Instance<Relax> = Instance::new("{test}", Logger::silent());
        i.setup_experiment(None, 0.0, None).unwrap();
        i.enter_initialization_mode().unwrap();
        i.set(&[3], &[20.0]).unwrap();
        // Readable during initialization: the steady state u + p/g = 20 + 3/2.
        assert_eq!(relax_value(&mut i, 4), 21.5);
        assert!(i.set(&[4], &[5.0]).is_err(), "a calculated state has no settable start");
        // d y / d u at initialization goes through the calculated state: T = u + p/g, y = T.
        let mut dy = [0.0, 0.0];
        i.directional_derivative(&[6, 4], &[3], &[1.0], &mut dy).unwrap();
        assert!((dy[0] - 1.0).abs() < 1e-6 && (dy[1] - 1.0).abs() < 1e-6, "{dy:?}");
        i.exit_initialization_mode().unwrap();
        i.do_step(0.0, 0.5).unwrap();
        assert!((relax_value(&mut i, 4) - 21.5).abs() < 1e-9, "the steady state stays put");
        // The cold start: T(0) = u, then T = u + p/g (1 - e^{-g t}).
        i.reset().unwrap();
        i.set(&[2], &[false]).unwrap();
        i.enter_initialization_mode().unwrap();
        i.exit_initialization_mode().unwrap();
        assert_eq!(relax_value(&mut i, 6), 10.0);
        i.do_step(0.0, 0.5).unwrap();
        let exact = 10.0 + 1.5 * (1.0 - (-1.0f64).exp());
        assert!((relax_value(&mut i, 4) - exact).abs() < 1e-6, "{}", relax_value(&mut i, 4));
    }

    #[test]
    fn a_calculated_state_without_a_finite_value_fails_initialization_by_name() {
        use crate::test_model::Relax;
        let mut i: Instance<Relax> = Instance::new("{test}", Logger::silent());
        i.enter_initialization_mode().unwrap();
        i.set(&[1], &[0.0]).unwrap(); // g = 0: no steady state (p/0)
        let e = i.exit_initialization_mode().unwrap_err();
        assert!(e.message.contains("'T'") && e.message.contains("initial value"), "{}", e.message);
        assert_eq!(i.phase, Phase::Error);
    }
}

#[cfg(test)]
mod send {
    /// A master may call an instance from any thread (never concurrently): it must be Send.
    #[test]
    fn instances_can_move_between_threads() {
        fn assert_send<T: Send>() {}
        assert_send::<super::Instance<crate::test_model::Decay>>();
    }
}
