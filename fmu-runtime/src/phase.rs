//! Where an instance is in its life, in the runtime's own words: the phases both FMI 2.0 and
//! FMI 3.0 pass through, under the names neither uses. Each adapter keeps its standard's table
//! of which function may be called in which phase (`fmi2::states`, `fmi3::states`) and its own
//! names for the phases in messages.
//!
//! (A model's discrete *modes*, such as a clutch slipping or sticking, are something else:
//! `variables::Mode`.)

/// The phase of one instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Phase {
    /// Made; parameters and start values may be set.
    Instantiated = 0,
    /// Between entering and exiting initialization.
    Initialization = 1,
    /// Co-Simulation: at a communication point, ready for the next step.
    Stepping = 2,
    /// Co-Simulation: the last step was discarded; the instance is at its start.
    StepFailed = 3,
    /// Discrete changes are computed (Model Exchange; the event mode of FMI 3.0 Co-Simulation).
    Event = 4,
    /// Model Exchange: the master integrates the continuous states.
    ContinuousTime = 5,
    Terminated = 6,
    /// The model failed (a parameter out of range at initialization): values can be read,
    /// the instance reset or freed.
    Error = 7,
    /// Only freeing is left.
    Fatal = 8,
}

impl Phase {
    pub const ALL: [Phase; 9] = [
        Phase::Instantiated,
        Phase::Initialization,
        Phase::Stepping,
        Phase::StepFailed,
        Phase::Event,
        Phase::ContinuousTime,
        Phase::Terminated,
        Phase::Error,
        Phase::Fatal,
    ];

    /// The phase as one bit, so that an adapter's set of phases is a mask.
    pub const fn bit(self) -> u16 {
        1 << self as u8
    }

    /// The phase with this number (`self as u8`), as a saved FMU state stores it.
    pub fn from_number(n: u32) -> Option<Phase> {
        Phase::ALL.into_iter().find(|p| *p as u32 == n)
    }

    /// The phase in words, for messages of the core ("cannot set 'x' while stepping").
    pub fn words(self) -> &'static str {
        match self {
            Phase::Instantiated => "before initialization",
            Phase::Initialization => "during initialization",
            Phase::Stepping => "while stepping",
            Phase::StepFailed => "after a discarded step",
            Phase::Event => "in event mode",
            Phase::ContinuousTime => "in continuous-time mode",
            Phase::Terminated => "after termination",
            Phase::Error => "after an error",
            Phase::Fatal => "after a fatal error",
        }
    }

    /// Before initialization ends: the calculated states are computed from the start values.
    pub fn is_before_initialization_end(self) -> bool {
        matches!(self, Phase::Instantiated | Phase::Initialization)
    }
}

/// The phases as bits, for the adapters' state tables.
pub mod bits {
    use super::Phase;
    pub const INSTANTIATED: u16 = Phase::Instantiated.bit();
    pub const INIT: u16 = Phase::Initialization.bit();
    pub const STEPPING: u16 = Phase::Stepping.bit();
    pub const FAILED: u16 = Phase::StepFailed.bit();
    pub const TERMINATED: u16 = Phase::Terminated.bit();
    pub const ERROR: u16 = Phase::Error.bit();
    pub const FATAL: u16 = Phase::Fatal.bit();
    pub const EVENT: u16 = Phase::Event.bit();
    pub const CONTINUOUS: u16 = Phase::ContinuousTime.bit();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_round_trip_and_bits_are_distinct() {
        let mut mask = 0u16;
        for p in Phase::ALL {
            assert_eq!(Phase::from_number(p as u32), Some(p));
            assert_eq!(mask & p.bit(), 0);
            mask |= p.bit();
        }
        assert_eq!(Phase::from_number(9), None);
    }
}
