//! The FMI 2.0 Co-Simulation state machine (FMI 2.0.4, section 4.2.4): the modes an instance
//! passes through and, in one table, which function may be called in which mode. Every fmi2
//! function consults this table once, before doing anything.

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

/// After the slave is initialized, in any outcome of the last step.
const INITIALIZED: u16 = COMPLETE | FAILED | CANCELED;
/// Every mode but Fatal and StepInProgress: where an instance can be reset, freed, saved.
const ALIVE: u16 = INSTANTIATED | INIT | INITIALIZED | TERMINATED | ERROR;
/// Where variables can be read.
const READABLE: u16 = INIT | INITIALIZED | TERMINATED | ERROR;

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
            Function::Terminate => COMPLETE | FAILED,
            Function::Reset => ALIVE,
            Function::Get => READABLE,
            Function::Set => INSTANTIATED | INIT | COMPLETE,
            Function::FmuState => ALIVE,
            Function::GetDirectionalDerivative => READABLE,
            Function::SetRealInputDerivatives => INSTANTIATED | INIT | COMPLETE,
            Function::GetRealOutputDerivatives => INITIALIZED | TERMINATED | ERROR,
            Function::DoStep => COMPLETE,
            Function::CancelStep => IN_PROGRESS,
            Function::GetStatus => COMPLETE | IN_PROGRESS | FAILED | TERMINATED,
        }
    }

    pub fn is_allowed_in(self, mode: Mode) -> bool {
        self.allowed() & mode as u16 != 0
    }

    /// The modes in which the function may be called, for an error message.
    pub fn allowed_mode_names(self) -> String {
        let mask = self.allowed();
        (0..9)
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
    fn allowed_names_read_well() {
        assert_eq!(Function::ExitInitializationMode.allowed_mode_names(), "InitializationMode");
    }
}
