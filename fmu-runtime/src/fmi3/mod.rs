//! The FMI 3.0 adapter: its C types, its state table, its logger callback, its
//! modelDescription.xml, the generic implementation of every fmi3 function, and the
//! `export_fmi3!` macro that gives a model its `extern "C"` fmi3 symbols.

pub mod export;
pub mod functions;
pub mod log;
pub mod states;
pub mod types;
pub mod xml;

/// The documentation page's words for FMI 3.0.
pub const DOCUMENTATION: crate::documentation::Words = crate::documentation::Words {
    version: "3.0",
    token_name: "instantiationToken",
    error: "fmi3Error",
    discard: "fmi3Discard",
    do_step: "fmi3DoStep",
    setup: "fmi3EnterInitializationMode",
    input_derivatives: None,
    new_discrete_states: "fmi3UpdateDiscreteStates",
    event_indicators: "fmi3GetEventIndicators",
};
