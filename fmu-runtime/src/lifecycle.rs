//! The FMI 2.0 state machines (FMI 2.0.4, sections 3.2.3 for Model Exchange and 4.2.4 for
//! Co-Simulation): the modes an instance passes through and, in one table, which function may be
//! called in which mode. Every fmi2 function consults this table once, before doing anything.
//! A Co-Simulation instance never enters EventMode or ContinuousTimeMode, a Model Exchange
//! instance never enters the Step* modes, so one table serves both.

/// The mode of one instance. The discriminants are bits so that a set of modes is a mask.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u16)]
pub enum Mode {
    Instantiated = 1 << 0,
    InitializationMode = 1 << 1,
    StepComplete = 1 << 2,
    /// Never entered: fmi2DoStep is synchronous and never returns fmi2Pending.
    StepInProgress = 1 << 3,
    StepFailed = 1 << 4,
    StepCanceled = 1 << 5,
    Terminated = 1 << 6,
    Error = 1 << 7,
    Fatal = 1 << 8,
    /// Model Exchange: discrete changes are computed.
    EventMode = 1 << 9,
    /// Model Exchange: the master integrates the continuous states.
    ContinuousTimeMode = 1 << 10,
}

impl Mode {
    pub fn name(self) -> &'static str {
        match self {
            Mode::Instantiated => "Instantiated",
            Mode::InitializationMode => "InitializationMode",
            Mode::StepComplete => "StepComplete",
            Mode::StepInProgress => "StepInProgress",
            Mode::StepFailed => "StepFailed",
            Mode::StepCanceled => "StepCanceled",
            Mode::Terminated => "Terminated",
            Mode::Error => "Error",
            Mode::Fatal => "Fatal",
            Mode::EventMode => "EventMode",
            Mode::ContinuousTimeMode => "ContinuousTimeMode",
        }
    }

    pub fn from_bits(bits: u16) -> Option<Mode> {
        [
            Mode::Instantiated,
            Mode::InitializationMode,
            Mode::StepComplete,
            Mode::StepInProgress,
            Mode::StepFailed,
            Mode::StepCanceled,
            Mode::Terminated,
            Mode::Error,
            Mode::Fatal,
            Mode::EventMode,
            Mode::ContinuousTimeMode,
        ]
        .into_iter()
        .find(|m| *m as u16 == bits)
    }
}

const INSTANTIATED: u16 = Mode::Instantiated as u16;
const INIT: u16 = Mode::InitializationMode as u16;
const COMPLETE: u16 = Mode::StepComplete as u16;
const IN_PROGRESS: u16 = Mode::StepInProgress as u16;
const FAILED: u16 = Mode::StepFailed as u16;
const CANCELED: u16 = Mode::StepCanceled as u16;
const TERMINATED: u16 = Mode::Terminated as u16;
const ERROR: u16 = Mode::Error as u16;
const FATAL: u16 = Mode::Fatal as u16;
const EVENT: u16 = Mode::EventMode as u16;
const CONTINUOUS: u16 = Mode::ContinuousTimeMode as u16;

/// After the slave is initialized, in any outcome of the last step.
const INITIALIZED: u16 = COMPLETE | FAILED | CANCELED;
/// A Model Exchange instance after initialization.
const SIMULATING: u16 = EVENT | CONTINUOUS;
/// Every mode but Fatal and StepInProgress: where an instance can be reset, freed, saved.
const ALIVE: u16 = INSTANTIATED | INIT | INITIALIZED | SIMULATING | TERMINATED | ERROR;
/// Where variables can be read.
const READABLE: u16 = INIT | INITIALIZED | SIMULATING | TERMINATED | ERROR;

/// The FMI functions whose legality depends on the mode.
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
    Set,
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

impl Function {
    /// The modes in which the function may be called (FMI 2.0.4, table in section 4.2.4).
    pub fn allowed(self) -> u16 {
        match self {
            Function::SetDebugLogging => ALIVE | IN_PROGRESS,
            // Freeing is always allowed, so that no instance ever leaks (also from Fatal).
            Function::FreeInstance => ALIVE | FATAL,
            Function::SetupExperiment | Function::EnterInitializationMode => INSTANTIATED,
            Function::ExitInitializationMode => INIT,
            Function::Terminate => COMPLETE | FAILED | SIMULATING,
            Function::Reset => ALIVE,
            Function::Get => READABLE,
            Function::Set => INSTANTIATED | INIT | COMPLETE | SIMULATING,
            Function::FmuState => ALIVE,
            Function::GetDirectionalDerivative => READABLE,
            Function::SetRealInputDerivatives => INSTANTIATED | INIT | COMPLETE,
            Function::GetRealOutputDerivatives => INITIALIZED | TERMINATED | ERROR,
            Function::DoStep => COMPLETE,
            Function::CancelStep => IN_PROGRESS,
            Function::GetStatus => COMPLETE | IN_PROGRESS | FAILED | TERMINATED,
            Function::EnterEventMode => SIMULATING,
            Function::NewDiscreteStates | Function::EnterContinuousTimeMode => EVENT,
            Function::CompletedIntegratorStep | Function::SetContinuousStates => CONTINUOUS,
            Function::SetTime => SIMULATING,
            Function::GetDerivatives => SIMULATING | TERMINATED | ERROR,
            Function::GetEventIndicators | Function::GetContinuousStates => INIT | SIMULATING | TERMINATED | ERROR,
            Function::GetNominalsOfContinuousStates => INSTANTIATED | SIMULATING | TERMINATED | ERROR,
        }
    }

    /// Functions of the Model Exchange interface only (refused for a Co-Simulation instance).
    pub fn is_model_exchange_only(self) -> bool {
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
    pub fn is_co_simulation_only(self) -> bool {
        matches!(
            self,
            Function::DoStep | Function::CancelStep | Function::GetStatus | Function::SetRealInputDerivatives | Function::GetRealOutputDerivatives
        )
    }

    pub fn is_allowed_in(self, mode: Mode) -> bool {
        self.allowed() & mode as u16 != 0
    }

    /// The modes in which the function may be called, for an error message.
    pub fn allowed_mode_names(self) -> String {
        let mask = self.allowed();
        (0..11)
            .filter_map(|b| Mode::from_bits(1 << b))
            .filter(|m| mask & *m as u16 != 0)
            .map(Mode::name)
            .collect::<Vec<_>>()
            .join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn do_step_only_after_initialization() {
        assert!(Function::DoStep.is_allowed_in(Mode::StepComplete));
        for m in [Mode::Instantiated, Mode::InitializationMode, Mode::Terminated, Mode::Error, Mode::StepFailed] {
            assert!(!Function::DoStep.is_allowed_in(m), "{m:?}");
        }
    }

    #[test]
    fn variables_are_not_readable_before_initialization() {
        assert!(!Function::Get.is_allowed_in(Mode::Instantiated));
        assert!(Function::Get.is_allowed_in(Mode::InitializationMode));
        assert!(Function::Get.is_allowed_in(Mode::Error));
    }

    #[test]
    fn a_fatal_instance_can_only_be_freed() {
        for f in [Function::Reset, Function::Get, Function::Set, Function::FmuState, Function::DoStep] {
            assert!(!f.is_allowed_in(Mode::Fatal), "{f:?}");
        }
        assert!(Function::FreeInstance.is_allowed_in(Mode::Fatal));
    }

    #[test]
    fn model_exchange_modes() {
        assert!(Function::SetContinuousStates.is_allowed_in(Mode::ContinuousTimeMode));
        assert!(!Function::SetContinuousStates.is_allowed_in(Mode::EventMode));
        assert!(Function::NewDiscreteStates.is_allowed_in(Mode::EventMode));
        assert!(Function::Get.is_allowed_in(Mode::ContinuousTimeMode));
        assert!(!Function::DoStep.is_allowed_in(Mode::ContinuousTimeMode));
        assert!(Function::DoStep.is_co_simulation_only() && Function::SetTime.is_model_exchange_only());
    }

    #[test]
    fn allowed_names_read_well() {
        assert_eq!(Function::ExitInitializationMode.allowed_mode_names(), "InitializationMode");
    }
}
