//! The instance's life: experiment set-up, initialization (every parameter checked), termination,
//! reset, debug logging.

use super::*;

impl<M: Model> Instance<M> {
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
        self.now.experiment = Experiment { tolerance, start_time, stop_time };
        self.now.time = start_time;
        self.stale = true;
        let stop = stop_time.map_or("no stop time".to_string(), |s| format!("stop {s} s"));
        let asked = tolerance.map_or("no tolerance given".to_string(), |t| format!("tolerance {t}"));
        self.debug(&format!("experiment: start {start_time} s, {stop}, {asked}"));
        Ok(())
    }

    /// The model's tolerance floor with the parameters as they are now (`Model::tolerance_floor`).
    fn tolerance_floor(&self) -> Option<f64> {
        let v = &self.now.values;
        self.model.tolerance_floor(&Knowns::new(self.now.time, &v.known, &v.states, &v.integers, &v.booleans))
    }

    /// The relative tolerance the Co-Simulation solver integrates at: the master's (else the
    /// default for these parameters, `declared_tolerance`), tightened to the model's floor for
    /// these parameters.
    pub(super) fn solver_tolerance(&self) -> f64 {
        let floor = self.tolerance_floor();
        let asked = self.now.experiment.tolerance.unwrap_or(declared_tolerance(floor));
        floor.map_or(asked, |floor| asked.min(floor))
    }

    /// Co-Simulation, when initialization ends (the parameters final): says through the logger
    /// which tolerance the solver integrates at, with a warning where the model's floor for these
    /// parameters tightens the master's.
    fn report_solver_tolerance(&self) {
        let floor = self.tolerance_floor();
        match (self.now.experiment.tolerance, floor) {
            (Some(asked), Some(floor)) if asked > floor => self.logger.log(
                Status::Warning,
                &format!(
                    "tolerance {asked:e} set by the master is looser than this FMU's floor {floor:e} for its parameters: its solver \
                     integrates at {floor:e} (at looser tolerances its errors grow far beyond the tolerance; see the FMU's documentation)"
                ),
            ),
            (None, _) => self.debug(&format!("no tolerance given: the solver integrates at {:e}", self.solver_tolerance())),
            _ => {}
        }
    }

    pub fn enter_initialization_mode(&mut self) -> CallResult {
        self.now.phase = Phase::Initialization;
        self.now.time = self.now.experiment.start_time;
        self.stale = true;
        self.debug("entered initialization mode");
        Ok(())
    }

    /// Checks every parameter against its physical range and the model's own relations, then that
    /// every value at the start is finite; a violation moves the instance to the Error mode with a
    /// message naming the parameter.
    pub fn exit_initialization_mode(&mut self) -> CallResult {
        if let Err(message) = self.check_parameters() {
            self.now.phase = Phase::Error;
            return Err(Failure::error(format!("initialization failed: {message}")));
        }
        if let Err(message) = self.compute_initial_states() {
            self.now.phase = Phase::Error;
            return Err(Failure::error(format!("initialization failed: {message}")));
        }
        self.settle_initial_modes()?;
        if let Err(message) = crate::model::check_finite_start(&*self.model, &self.table, self.now.time, &self.now.values) {
            self.now.phase = Phase::Error;
            return Err(Failure::error(format!("initialization failed: {message}")));
        }
        if self.interface == Interface::ModelExchange {
            self.now.phase = Phase::Event;
            self.stale = true;
            self.debug("initialization done, event mode");
            return Ok(());
        }
        self.report_solver_tolerance();
        match self.make_integrator() {
            Ok(integrator) => self.integrator = Some(integrator),
            Err(message) => {
                self.now.phase = Phase::Error;
                return Err(Failure::error(message));
            }
        }
        // With the master handling events, Co-Simulation starts in the event phase (FMI 3.0:
        // fmi3ExitInitializationMode enters Event Mode when eventModeUsed).
        self.now.phase = if self.event_mode_used { Phase::Event } else { Phase::Stepping };
        self.stale = true;
        self.debug("initialization done");
        Ok(())
    }

    /// Co-Simulation: whether the master handles the events (`event_mode_used`: it enters the
    /// event phase at communication points) and whether a step stops at each event inside it
    /// and returns early (`stop_at_events`, only with `event_mode_used`). Set at instantiation;
    /// without either the events are handled inside the step.
    pub fn hand_events_to_master(&mut self, event_mode_used: bool, stop_at_events: bool) {
        let used = event_mode_used && self.interface == Interface::CoSimulation;
        self.event_mode_used = used;
        self.stops_at_events = used && stop_at_events;
    }

    pub(super) fn check_parameters(&self) -> Result<(), String> {
        for var in &self.table.variables {
            match var.slot {
                Slot::Known(i) => var.check_range(self.now.values.known[i])?,
                Slot::State(s) => var.check_range(self.now.values.states[s])?,
                Slot::Integer(i) => var.check_range(self.now.values.integers[i] as f64)?,
                _ => {}
            }
        }
        let v = &self.now.values;
        let k = Knowns::new(self.now.time, &v.known, &v.states, &v.integers, &v.booleans);
        self.model.check(&k)
    }

    pub fn terminate(&mut self) -> CallResult {
        self.now.phase = Phase::Terminated;
        self.debug("terminated");
        Ok(())
    }

    /// fmi2Reset: back to the state right after fmi2Instantiate (saved FMU states stay valid).
    pub fn reset(&mut self) -> CallResult {
        self.now = Situation::at_instantiation(&self.table);
        self.integrator = None;
        let _ = self.compute_initial_states();
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
        self.now.time
    }
}
