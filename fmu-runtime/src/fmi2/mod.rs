//! The FMI 2.0 adapter: its C types, its state table, its logger callback, its
//! modelDescription.xml, the generic implementation of every fmi2 function, and the
//! `export_fmi2!` macro that gives a model its `extern "C"` fmi2 symbols.

pub mod export;
pub mod functions;
pub mod log;
pub mod states;
pub mod types;
pub mod xml;

/// The documentation page's words for FMI 2.0.
pub const DOCUMENTATION: crate::documentation::Words = crate::documentation::Words {
    version: "2.0",
    token_name: "guid",
    error: "fmi2Error",
    discard: "fmi2Discard",
    do_step: "fmi2DoStep",
    setup: "fmi2SetupExperiment",
    input_derivatives: Some("fmi2SetRealInputDerivatives"),
    new_discrete_states: "fmi2NewDiscreteStates",
    event_indicators: "fmi2GetEventIndicators",
};

