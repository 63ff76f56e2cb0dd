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


pub use xml::write as write_xml;

/// FMI 2.0 FMUs go into the output directory itself.
pub const FOLDER: &str = "";

/// FMI 2.0's name of the platform this library was built for (FMI 2.0.4, section 2.4: the
/// binaries folder), if it names one.
pub fn platform() -> Option<&'static str> {
    match (std::env::consts::OS, std::env::consts::ARCH) {
        ("linux", "x86_64") => Some("linux64"),
        ("linux", "x86") => Some("linux32"),
        ("macos", "x86_64" | "aarch64") => Some("darwin64"),
        ("windows", "x86_64") => Some("win64"),
        ("windows", "x86") => Some("win32"),
        _ => None,
    }
}
