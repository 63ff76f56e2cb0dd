//! The C boundary: FMI 2.0 types, the generic implementation of every fmi2 function, and the
//! `export_fmu!` macro that gives a model its `extern "C"` symbols.

pub mod export;
pub mod functions;
pub mod types;

use std::ffi::CString;

use crate::model::Model;

/// What a model's library says about itself, computed once per process: the generated
/// modelDescription.xml, its guid (a hash of its content), and the documentation page.
pub struct Exported {
    pub model_identifier: CString,
    pub guid: String,
    pub model_description: CString,
    pub documentation: CString,
}

impl Exported {
    pub fn of<M: Model>() -> Exported {
        let description = crate::description::ModelDescription::of::<M>();
        Exported {
            model_identifier: crate::log::to_c_string(M::info().name),
            guid: description.guid.clone(),
            model_description: crate::log::to_c_string(&description.xml),
            documentation: crate::log::to_c_string(&crate::documentation::html::<M>(&description)),
        }
    }
}
