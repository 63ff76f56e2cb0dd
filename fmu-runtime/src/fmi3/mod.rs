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

pub use xml::write as write_xml;

/// FMI 3.0 FMUs go into `fmi3/` of the output directory.
pub const FOLDER: &str = "fmi3";

/// FMI 3.0's name of the platform this library was built for (FMI 3.0, section 2.5.1.1: the
/// architecture and the operating system), if it names one.
pub fn platform() -> Option<&'static str> {
    match (std::env::consts::OS, std::env::consts::ARCH) {
        ("linux", "x86_64") => Some("x86_64-linux"),
        ("linux", "x86") => Some("x86-linux"),
        ("linux", "aarch64") => Some("aarch64-linux"),
        ("macos", "x86_64") => Some("x86_64-darwin"),
        ("macos", "aarch64") => Some("aarch64-darwin"),
        ("windows", "x86_64") => Some("x86_64-windows"),
        ("windows", "x86") => Some("x86-windows"),
        _ => None,
    }
}
