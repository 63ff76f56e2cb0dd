//! The FMI 3.0 state machine (FMI 3.0, sections 3.2 for Model Exchange and 4.2 for
//! Co-Simulation) over the runtime's [`Phase`]s: which fmi3 function may be called in which
//! phase, in one table, and the standard's names of the phases. This FMU has no clocks, no
//! structural parameters and no intermediate updates, so ConfigurationMode,
//! ReconfigurationMode, ClockActivationMode and IntermediateUpdateMode are never entered.
//! Co-Simulation enters EventMode only when the master instantiated it with eventModeUsed (the
//! instance refuses fmi3EnterEventMode otherwise).

use crate::boundary::CallTable;
use crate::phase::Phase;

/// The FMI 3.0 name of a phase, for messages.
pub fn state_name(phase: Phase) -> &'static str {
    match phase {
        Phase::Instantiated => "Instantiated",
        Phase::Initialization => "InitializationMode",
        Phase::Stepping => "StepMode",
        Phase::StepFailed => "StepMode after a discarded step",
        Phase::Event => "EventMode",
        Phase::ContinuousTime => "ContinuousTimeMode",
        Phase::Terminated => "Terminated",
        Phase::Error => "the state after an error",
        Phase::Fatal => "the state after a fatal error",
    }
}

use crate::phase::bits::{CONTINUOUS, ERROR, EVENT, FAILED, FATAL, INIT, INSTANTIATED, STEPPING as STEP, TERMINATED};

/// Every phase but Fatal.
const ALIVE: u16 = INSTANTIATED | INIT | STEP | FAILED | EVENT | CONTINUOUS | TERMINATED | ERROR;
/// Where variables can be read.
const READABLE: u16 = INIT | STEP | FAILED | EVENT | CONTINUOUS | TERMINATED | ERROR;

/// The fmi3 functions whose legality depends on the phase.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Function {
    SetDebugLogging,
    FreeInstance,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    Get,
    Set,
    FmuState,
    /// fmi3GetDirectionalDerivative, fmi3GetAdjointDerivative.
    PartialDerivatives,
    /// fmi3GetNumberOfContinuousStates, fmi3GetNumberOfEventIndicators.
    Counts,
    // Model Exchange, and Co-Simulation with eventModeUsed.
    EnterEventMode,
    UpdateDiscreteStates,
    // Model Exchange only.
    EnterContinuousTimeMode,
    CompletedIntegratorStep,
    SetTime,
    SetContinuousStates,
    GetContinuousStateDerivatives,
    GetEventIndicators,
    GetContinuousStates,
    GetNominalsOfContinuousStates,
    // Co-Simulation only.
    GetOutputDerivatives,
    DoStep,
    EnterStepMode,
}

impl CallTable for Function {
    /// The phases in which the function may be called.
    fn allowed(self) -> u16 {
        match self {
            Function::SetDebugLogging | Function::Reset | Function::FmuState | Function::Counts => ALIVE,
            // Freeing is always allowed, so that no instance ever leaks (also from Fatal).
            Function::FreeInstance => ALIVE | FATAL,
            Function::EnterInitializationMode => INSTANTIATED,
            Function::ExitInitializationMode => INIT,
            Function::Terminate => STEP | FAILED | EVENT | CONTINUOUS,
            Function::Get | Function::PartialDerivatives => READABLE,
            Function::Set => INSTANTIATED | INIT | STEP | EVENT | CONTINUOUS,
            // From ContinuousTimeMode (Model Exchange) or StepMode (Co-Simulation).
            Function::EnterEventMode => CONTINUOUS | STEP,
            Function::UpdateDiscreteStates | Function::EnterContinuousTimeMode => EVENT,
            Function::CompletedIntegratorStep | Function::SetContinuousStates => CONTINUOUS,
            Function::SetTime => EVENT | CONTINUOUS,
            Function::GetContinuousStateDerivatives | Function::GetEventIndicators | Function::GetContinuousStates => INIT | EVENT | CONTINUOUS | TERMINATED | ERROR,
            // Initialization Mode and the Initialized states (FMI 3.0.2, "State: Initialization Mode"); in
            // Instantiated too, which the standard does not list and a master cannot be hurt by.
            Function::GetNominalsOfContinuousStates => INSTANTIATED | INIT | EVENT | CONTINUOUS | TERMINATED | ERROR,
            Function::GetOutputDerivatives => STEP | FAILED | TERMINATED | ERROR,
            Function::DoStep => STEP,
            Function::EnterStepMode => EVENT,
        }
    }

    fn is_model_exchange_only(self) -> bool {
        matches!(
            self,
            Function::EnterContinuousTimeMode
                | Function::CompletedIntegratorStep
                | Function::SetTime
                | Function::SetContinuousStates
                | Function::GetContinuousStateDerivatives
                | Function::GetEventIndicators
                | Function::GetContinuousStates
                | Function::GetNominalsOfContinuousStates
        )
    }

    fn is_co_simulation_only(self) -> bool {
        matches!(self, Function::GetOutputDerivatives | Function::DoStep | Function::EnterStepMode)
    }

    fn phase_name(phase: Phase) -> &'static str {
        state_name(phase)
    }

    const IN: &'static str = "in ";
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_follows_the_standard() {
        assert!(Function::DoStep.is_allowed_in(Phase::Stepping));
        assert!(!Function::DoStep.is_allowed_in(Phase::StepFailed));
        assert!(Function::EnterInitializationMode.is_allowed_in(Phase::Instantiated));
        assert!(!Function::Get.is_allowed_in(Phase::Instantiated));
        assert!(Function::UpdateDiscreteStates.is_allowed_in(Phase::Event));
        assert!(!Function::UpdateDiscreteStates.is_allowed_in(Phase::ContinuousTime));
        assert!(Function::FreeInstance.is_allowed_in(Phase::Fatal));
        for f in [Function::Reset, Function::Get, Function::Set, Function::FmuState, Function::DoStep] {
            assert!(!f.is_allowed_in(Phase::Fatal), "{f:?}");
        }
        assert_eq!(Function::ExitInitializationMode.allowed_names(), "InitializationMode");
        // Co-Simulation's event mode: in from StepMode, out with fmi3EnterStepMode.
        assert!(Function::EnterEventMode.is_allowed_in(Phase::Stepping) && !Function::EnterEventMode.is_allowed_in(Phase::StepFailed));
        assert!(Function::EnterStepMode.is_allowed_in(Phase::Event) && !Function::EnterStepMode.is_allowed_in(Phase::Stepping));
        assert!(Function::EnterStepMode.is_co_simulation_only() && !Function::UpdateDiscreteStates.is_model_exchange_only());
        // Model Exchange in Initialization Mode (FMI 3.0.2, "State: Initialization Mode"): derivatives, states,
        // nominals and event indicators may be read.
        for f in [Function::GetContinuousStateDerivatives, Function::GetContinuousStates, Function::GetNominalsOfContinuousStates, Function::GetEventIndicators] {
            assert!(f.is_allowed_in(Phase::Initialization), "{f:?}");
        }
    }
}
