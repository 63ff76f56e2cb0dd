//! The FMI 2.0 state machines (FMI 2.0.4, sections 3.2.3 for Model Exchange and 4.2.4 for
//! Co-Simulation) over the runtime's [`Phase`]s: which fmi2 function may be called in which
//! phase, in one table, and the standard's names of the phases. Every fmi2 function consults
//! this table once, before doing anything. A Co-Simulation instance never enters the Event or
//! ContinuousTime phases, a Model Exchange instance never steps, so one table serves both.
//! FMI 2.0's StepInProgress and StepCanceled are never entered (fmi2DoStep is synchronous and
//! never returns fmi2Pending), so no phase stands for them.

use crate::boundary::CallTable;
use crate::phase::Phase;

/// The FMI 2.0 name of a phase, for messages.
pub fn mode_name(phase: Phase) -> &'static str {
    match phase {
        Phase::Instantiated => "Instantiated",
        Phase::Initialization => "InitializationMode",
        Phase::Stepping => "StepComplete",
        Phase::StepFailed => "StepFailed",
        Phase::Event => "EventMode",
        Phase::ContinuousTime => "ContinuousTimeMode",
        Phase::Terminated => "Terminated",
        Phase::Error => "Error",
        Phase::Fatal => "Fatal",
    }
}

use crate::phase::bits::{CONTINUOUS, ERROR, EVENT, FAILED, FATAL, INIT, INSTANTIATED, STEPPING as COMPLETE, TERMINATED};

/// After the slave is initialized, in any outcome of the last step.
const INITIALIZED: u16 = COMPLETE | FAILED;
/// A Model Exchange instance after initialization.
const SIMULATING: u16 = EVENT | CONTINUOUS;
/// Every phase but Fatal: where an instance can be reset, freed, saved.
const ALIVE: u16 = INSTANTIATED | INIT | INITIALIZED | SIMULATING | TERMINATED | ERROR;
/// Where variables can be read.
const READABLE: u16 = INIT | INITIALIZED | SIMULATING | TERMINATED | ERROR;

/// The fmi2 functions whose legality depends on the phase.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Function {
    SetDebugLogging,
    FreeInstance,
    SetupExperiment,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    Get,
    /// fmi2SetReal.
    Set,
    /// fmi2SetInteger, fmi2SetBoolean, fmi2SetString: as fmi2SetReal, but not in
    /// Continuous-Time Mode (FMI 2.0.5, table of section 3.2.3: there only continuous Real
    /// inputs may change).
    SetDiscrete,
    FmuState,
    GetDirectionalDerivative,
    SetRealInputDerivatives,
    GetRealOutputDerivatives,
    DoStep,
    CancelStep,
    GetStatus,
    // Model Exchange only.
    EnterEventMode,
    NewDiscreteStates,
    EnterContinuousTimeMode,
    CompletedIntegratorStep,
    SetTime,
    SetContinuousStates,
    GetDerivatives,
    GetEventIndicators,
    GetContinuousStates,
    GetNominalsOfContinuousStates,
}

impl CallTable for Function {
    /// The phases in which the function may be called (FMI 2.0.4, table in section 4.2.4).
    fn allowed(self) -> u16 {
        match self {
            Function::SetDebugLogging => ALIVE,
            // Freeing is always allowed, so that no instance ever leaks (also from Fatal).
            Function::FreeInstance => ALIVE | FATAL,
            Function::SetupExperiment | Function::EnterInitializationMode => INSTANTIATED,
            Function::ExitInitializationMode => INIT,
            Function::Terminate => COMPLETE | FAILED | SIMULATING,
            Function::Reset => ALIVE,
            Function::Get => READABLE,
            Function::Set => INSTANTIATED | INIT | COMPLETE | SIMULATING,
            Function::SetDiscrete => INSTANTIATED | INIT | COMPLETE | EVENT,
            Function::FmuState => ALIVE,
            Function::GetDirectionalDerivative => READABLE,
            Function::SetRealInputDerivatives => INSTANTIATED | INIT | COMPLETE,
            Function::GetRealOutputDerivatives => INITIALIZED | TERMINATED | ERROR,
            Function::DoStep => COMPLETE,
            // Only in StepInProgress, which is never entered.
            Function::CancelStep => 0,
            Function::GetStatus => COMPLETE | FAILED | TERMINATED,
            Function::EnterEventMode => SIMULATING,
            Function::NewDiscreteStates | Function::EnterContinuousTimeMode => EVENT,
            Function::CompletedIntegratorStep | Function::SetContinuousStates => CONTINUOUS,
            Function::SetTime => SIMULATING,
            // In Initialization Mode too since FMI 2.0.1 (section 3.2.3), the nominals since 2.0.3.
            Function::GetDerivatives => INIT | SIMULATING | TERMINATED | ERROR,
            Function::GetEventIndicators | Function::GetContinuousStates => INIT | SIMULATING | TERMINATED | ERROR,
            Function::GetNominalsOfContinuousStates => INSTANTIATED | INIT | SIMULATING | TERMINATED | ERROR,
        }
    }

    /// Functions of the Model Exchange interface only (refused for a Co-Simulation instance).
    fn is_model_exchange_only(self) -> bool {
        matches!(
            self,
            Function::EnterEventMode
                | Function::NewDiscreteStates
                | Function::EnterContinuousTimeMode
                | Function::CompletedIntegratorStep
                | Function::SetTime
                | Function::SetContinuousStates
                | Function::GetDerivatives
                | Function::GetEventIndicators
                | Function::GetContinuousStates
                | Function::GetNominalsOfContinuousStates
        )
    }

    /// Functions of the Co-Simulation interface only (refused for a Model Exchange instance).
    fn is_co_simulation_only(self) -> bool {
        matches!(
            self,
            Function::DoStep | Function::CancelStep | Function::GetStatus | Function::SetRealInputDerivatives | Function::GetRealOutputDerivatives
        )
    }

    fn phase_name(phase: Phase) -> &'static str {
        mode_name(phase)
    }

    const IN: &'static str = "in mode ";
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn do_step_only_after_initialization() {
        assert!(Function::DoStep.is_allowed_in(Phase::Stepping));
        for m in [Phase::Instantiated, Phase::Initialization, Phase::Terminated, Phase::Error, Phase::StepFailed] {
            assert!(!Function::DoStep.is_allowed_in(m), "{m:?}");
        }
    }

    #[test]
    fn model_exchange_cells_of_fmi_2_0_5() {
        // Section 3.2.3's table: only Reals may be set in Continuous-Time Mode; the derivatives
        // and the nominals may be read in Initialization Mode.
        assert!(Function::Set.is_allowed_in(Phase::ContinuousTime));
        assert!(!Function::SetDiscrete.is_allowed_in(Phase::ContinuousTime));
        assert!(Function::SetDiscrete.is_allowed_in(Phase::Event) && Function::SetDiscrete.is_allowed_in(Phase::Stepping));
        assert!(Function::GetDerivatives.is_allowed_in(Phase::Initialization));
        assert!(Function::GetNominalsOfContinuousStates.is_allowed_in(Phase::Initialization));
    }

    #[test]
    fn variables_are_not_readable_before_initialization() {
        assert!(!Function::Get.is_allowed_in(Phase::Instantiated));
        assert!(Function::Get.is_allowed_in(Phase::Initialization));
        assert!(Function::Get.is_allowed_in(Phase::Error));
    }

    #[test]
    fn a_fatal_instance_can_only_be_freed() {
        for f in [Function::Reset, Function::Get, Function::Set, Function::FmuState, Function::DoStep] {
            assert!(!f.is_allowed_in(Phase::Fatal), "{f:?}");
        }
        assert!(Function::FreeInstance.is_allowed_in(Phase::Fatal));
    }

    #[test]
    fn model_exchange_modes() {
        assert!(Function::SetContinuousStates.is_allowed_in(Phase::ContinuousTime));
        assert!(!Function::SetContinuousStates.is_allowed_in(Phase::Event));
        assert!(Function::NewDiscreteStates.is_allowed_in(Phase::Event));
        assert!(Function::Get.is_allowed_in(Phase::ContinuousTime));
        assert!(!Function::DoStep.is_allowed_in(Phase::ContinuousTime));
        assert!(Function::DoStep.is_co_simulation_only() && Function::SetTime.is_model_exchange_only());
    }

    #[test]
    fn allowed_names_read_well() {
        assert_eq!(Function::ExitInitializationMode.allowed_names(), "InitializationMode");
        assert!(Function::CancelStep.allowed_names().contains("never"));
    }
}
