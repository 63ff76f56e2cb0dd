//! The C boundary: FMI 2.0 types, the generic implementation of every fmi2 function, and the
//! `export_fmu!` macro that gives a model its `extern "C"` symbols.

pub mod export;
pub mod functions;
pub mod log;
pub mod states;
pub mod types;
pub mod xml;

use std::ffi::CString;
use std::ptr;
use std::sync::atomic::{AtomicPtr, Ordering};

use crate::model::Model;

/// The documentation page's words for FMI 2.0.
pub const DOCUMENTATION: crate::documentation::Standard = crate::documentation::Standard {
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

/// What a model's library says about itself, computed once per library load: the generated
/// modelDescription.xml, its guid (a hash of its content), and the documentation page.
pub struct Exported {
    pub model_identifier: CString,
    pub guid: String,
    pub model_description: CString,
    pub documentation: CString,
    /// The model's problems, one per line ("file:line: rule. Fix: ..."), if it has any: such
    /// a model cannot be instantiated, and build-fmus refuses to package it.
    pub problems: Option<CString>,
}

impl Exported {
    /// A model's description without package information (the runtime's own tests).
    pub fn of<M: Model>() -> Exported {
        Self::with_package::<M>(&crate::description::Package::default())
    }

    /// A model crate's description with its Cargo metadata and source date (`export_fmu!`).
    pub fn with_package<M: Model>(package: &crate::description::Package) -> Exported {
        let description = crate::description::ModelDescription::with_package::<M>(package);
        Exported {
            model_identifier: crate::log::to_c_string(M::info().name),
            guid: description.fmi2.token.clone(),
            model_description: crate::log::to_c_string(&description.fmi2.xml),
            documentation: crate::log::to_c_string(&crate::documentation::html::<M>(&description, &description.fmi2, &DOCUMENTATION)),
            problems: (!description.problems.is_empty()).then(|| crate::log::to_c_string(&description.problems.join("\n"))),
        }
    }
}

/// Where a model library keeps its [`Exported`] description: made on first use, and freed when
/// the library is unloaded (`dlclose`), so a master that loads and unloads an FMU many times
/// loses no memory. (A `OnceLock` static would never be freed: statics have no destructor.)
pub struct ExportedCell {
    ptr: AtomicPtr<Exported>,
}

impl ExportedCell {
    pub const fn new() -> Self {
        ExportedCell { ptr: AtomicPtr::new(ptr::null_mut()) }
    }

    /// The description, made by `make` on the first call (if two threads race, one result is
    /// kept and the other dropped).
    pub fn get_or_init(&self, make: fn() -> Exported) -> &Exported {
        let current = self.ptr.load(Ordering::Acquire);
        if !current.is_null() {
            // SAFETY: a non-null pointer came from Box::into_raw below and is freed only by
            // `release`, after which no code of this library runs.
            return unsafe { &*current };
        }
        let fresh = Box::into_raw(Box::new(make()));
        match self.ptr.compare_exchange(ptr::null_mut(), fresh, Ordering::AcqRel, Ordering::Acquire) {
            // SAFETY: as above; `fresh` is now the stored pointer.
            Ok(_) => unsafe { &*fresh },
            Err(existing) => {
                // SAFETY: `fresh` was never shared; `existing` is the stored pointer.
                unsafe {
                    drop(Box::from_raw(fresh));
                    &*existing
                }
            }
        }
    }

    /// Frees the description.
    ///
    /// # Safety
    /// Only from the library's unload hook (`.fini_array`), when no function of the library
    /// can run any more: references handed out by `get_or_init` dangle afterwards.
    pub unsafe fn release(&self) {
        let p = self.ptr.swap(ptr::null_mut(), Ordering::AcqRel);
        if !p.is_null() {
            drop(Box::from_raw(p));
        }
    }
}

impl Default for ExportedCell {
    fn default() -> Self {
        Self::new()
    }
}
