//! One FMU instance, in neither standard's words: its phase, its values, its solver, its saved
//! states, and every check a call must pass. The adapters (`fmi2`, `fmi3`) have already checked
//! pointers and that the call is legal in the current phase; everything here is safe Rust.
//!
//! This file holds the instance's data and what every job shares (lazy recomputation, value
//! lookup); each job is a file of its own: `access` (get/set), `lifecycle` (set-up,
//! initialization, termination, reset), `stepping` (Co-Simulation's communication step and its
//! events), `modes` (the discrete modes at an event), `io_derivatives` (input and output
//! derivatives), `model_exchange`, `partial_derivatives` (directional derivatives) and
//! `fmu_states` (snapshots, serialization).
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
use crate::state::{Experiment, Shape, Situation, Snapshot, SnapshotStore};
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
            Slot::State(s) => values.states[s],
            Slot::Calculated(i) => values.calculated[i],
            Slot::Derivative(i) => values.derivatives[i],
            _ => unreachable!("checked by type"),
        }
    }
    fn write(values: &mut Values, slot: Slot, v: f64) {
        match slot {
            Slot::Known(i) => values.known[i] = v,
            // Before initialization only (a state is not settable after it): its start value.
            Slot::State(s) => values.states[s] = v,
            _ => {}
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
    /// The calculated values but the energy-balance outputs.
    calculated: bool,
    /// The energy-balance outputs (they take an evaluation of the derivatives).
    balance: bool,
    derivatives: bool,
}

impl Fresh {
    const ALL: Fresh = Fresh { calculated: true, balance: true, derivatives: true };
}

pub struct Instance<M: Model> {
    pub interface: Interface,
    /// Co-Simulation with the master handling events (FMI 3.0's eventModeUsed): the instance
    /// enters the event phase after initialization and the master may enter it at any
    /// communication point.
    event_mode_used: bool,
    /// And the master allows the step to end early (earlyReturnAllowed): the step stops at
    /// each event, before the modes change, and leaves the event to the master.
    stops_at_events: bool,
    runtime: RuntimeVariables,
    model: Arc<M>,
    table: Arc<VariableTable>,
    info: ModelInfo,
    guid: &'static str,
    pub logger: Logger,
    /// What an FMU state saves and restores: the phase, time, experiment, every value (the
    /// continuous states among them, in their one home `now.values.states`) and the input
    /// derivatives and previous inputs.
    now: Situation,
    /// Outputs and derivatives are recomputed lazily, when read after a change: `stale` says
    /// that something changed, `fresh` which of the three (calculated values, the energy
    /// balance, derivatives) have been recomputed since (a master reading outputs after each
    /// step never pays for the derivatives, nor for the balance unless it reads it).
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

impl Situation {
    /// Right after instantiation (and fmi2Reset): no experiment, time 0, the declared start
    /// values (a calculated state's is computed by the instance), no input derivatives.
    fn at_instantiation(table: &VariableTable) -> Situation {
        Situation {
            phase: Phase::Instantiated,
            time: 0.0,
            experiment: Experiment::default(),
            values: table.start_values(),
            input_slopes: vec![0.0; table.n_known],
            input_curvatures: vec![0.0; table.n_known],
            previous_inputs: None,
        }
    }
}

impl<M: Model> Instance<M> {
    pub fn new(guid: &'static str, logger: Logger) -> Self {
        Self::for_interface(Interface::CoSimulation, guid, logger)
    }

    /// An instance with declarations of its own (`Model::declare` runs): the runtime's tests
    /// and tools. An FMU's instances share their library's (`shared`).
    pub fn for_interface(interface: Interface, guid: &'static str, logger: Logger) -> Self {
        Self::shared(interface, guid, logger, &crate::exported::Declared::new())
    }

    /// An instance of the library's one declaration of the model (`export_fmu!`'s, made once
    /// per library): instantiating costs the instance's own values, O(variables), and never
    /// runs `Model::declare` again.
    pub fn shared(interface: Interface, guid: &'static str, logger: Logger, declared: &crate::exported::Declared<M>) -> Self {
        let (model, runtime, table) = (Arc::clone(&declared.model), declared.runtime, Arc::clone(&declared.table));
        let now = Situation::at_instantiation(&table);
        let mut inst = Instance {
            interface,
            event_mode_used: false,
            stops_at_events: false,
            runtime,
            model,
            table,
            info: M::info(),
            guid,
            logger,
            now,
            stale: true,
            fresh: Fresh::default(),
            knowns_set: true,
            has_inputs: false,
            has_modes: false,
            integrator: None,
            snapshots: SnapshotStore::default(),
            buffers: Buffers::default(),
        };
        inst.buffers.slopes = vec![0.0; inst.table.n_known];
        inst.buffers.balance = vec![0.0; inst.table.n_states + inst.table.elements.len()];
        inst.has_inputs = inst.table.variables.iter().any(|v| v.causality == crate::variables::Causality::Input);
        inst.has_modes = inst.table.variables.iter().any(|v| v.is_mode());
        // A model whose initial states fail at the defaults says so at initialization.
        let _ = inst.compute_initial_states();
        inst
    }

    pub fn table(&self) -> &VariableTable {
        &self.table
    }

    pub fn time(&self) -> f64 {
        self.now.time
    }

    /// The phase the instance is in (the adapters check each call against it).
    pub fn phase(&self) -> Phase {
        self.now.phase
    }

    /// After a panic inside a call: only freeing the instance is accepted from now on.
    pub fn enter_fatal(&mut self) {
        self.now.phase = Phase::Fatal;
    }

    /// Sends a debug message (only with debug logging on).
    pub fn debug(&self, message: &str) {
        self.logger.log(Status::Ok, message);
    }

    /// Before initialization: the model's own initial values of its calculated states, from
    /// the knowns, written into the state vector beside the other states' start values (so
    /// fmi2GetReal and the equations read them).
    fn compute_initial_states(&mut self) -> Result<(), String> {
        let v = &mut self.now.values;
        crate::model::initialize_states(&*self.model, &self.table, self.now.time, &v.known, &v.integers, &v.booleans, &mut v.states)
    }

    /// Recomputes outputs, locals and derivatives from the knowns if anything changed.
    fn refresh(&mut self) {
        self.refresh_only(Fresh::ALL);
    }

    /// Recomputes what `need` asks for (calculated values, derivatives) if anything changed
    /// since it was last computed.
    fn refresh_only(&mut self, need: Fresh) {
        if self.stale {
            if self.now.phase.is_before_initialization_end() {
                // A failure leaves NaN in the calculated states; exiting initialization reports it.
                let _ = self.compute_initial_states();
            }
            self.fresh = Fresh::default();
            self.stale = false;
        }
        let (time, v) = (self.now.time, &mut self.now.values);
        if need.calculated && !self.fresh.calculated {
            crate::model::evaluate_outputs_but_balance(&*self.model, &self.table, time, &v.known, &v.states, &v.integers, &v.booleans, &mut v.calculated);
            self.fresh.calculated = true;
        }
        if need.balance && !self.fresh.balance {
            crate::model::evaluate_balance(&*self.model, &self.table, time, &v.known, &v.states, &v.integers, &v.booleans, &mut v.calculated, &mut self.buffers.balance);
            self.fresh.balance = true;
        }
        if need.derivatives && !self.fresh.derivatives {
            crate::model::evaluate_derivatives(&*self.model, time, &v.known, &v.states, &v.integers, &v.booleans, &mut v.derivatives);
            self.fresh.derivatives = true;
        }
    }

    fn variable(&self, vr: u32, expected: BaseType) -> CallResult<&Variable> {
        let var = self.table.get(vr).ok_or_else(|| {
            Failure::error(format!("unknown value reference {vr} (this FMU has 0..{})", self.table.variables.len()))
        })?;
        if var.base_type() != expected {
            return Err(Failure::error(format!(
                "value reference {vr} is the {} variable '{}', not {}",
                var.base_type().name(),
                var.name,
                expected.with_article()
            )));
        }
        Ok(var)
    }

    /// Sends the message of a failed call to the master's logger.
    pub fn report(&self, failure: &Failure) {
        let status = if failure.status == Status::Ok { Status::Warning } else { failure.status };
        self.logger.log(status, &failure.message);
    }
}

mod access;
mod fmu_states;
mod io_derivatives;
mod lifecycle;
mod model_exchange;
mod modes;
mod partial_derivatives;
mod stepping;
pub use stepping::StepEnd;

#[cfg(test)]
mod tests;

#[cfg(test)]
mod send {
    /// A master may call an instance from any thread (never concurrently): it must be Send.
    #[test]
    fn instances_can_move_between_threads() {
        fn assert_send<T: Send>() {}
        assert_send::<super::Instance<crate::test_model::Decay>>();
    }
}
