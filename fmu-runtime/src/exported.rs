//! What a model's library says about itself, made once per library load and freed at unload:
//! its identifier, its problems, and for each standard its modelDescription.xml, token and
//! documentation page.

use std::ffi::CString;
use std::ptr;
use std::sync::atomic::{AtomicPtr, Ordering};

use crate::description::{ModelDescription, Package};
use crate::log::to_c_string;
use crate::model::Model;
use crate::standards::{Standard, ALL};

/// What a model's library says about itself, computed once per library load: the generated
/// modelDescription.xml, its guid (a hash of its content), and the documentation page.
pub struct Exported {
    pub model_identifier: CString,
    /// The model's problems, one per line ("file:line: rule. Fix: ..."), if it has any: such
    /// a model cannot be instantiated, and build-fmus refuses to package it.
    pub problems: Option<CString>,
    /// Each exported standard's description (`standards::ALL` order).
    pub standards: Vec<ForStandard>,
    /// `fmu_runtime_standards`: one line per standard that names a platform (version, output
    /// folder, binaries folder), for build-fmus.
    pub listing: CString,
}

/// One standard's description of the model, as the library hands it out.
pub struct ForStandard {
    pub standard: Standard,
    /// FMI 2.0 `guid`, FMI 3.0 `instantiationToken`: what instantiation checks.
    pub token: String,
    pub model_description: CString,
    pub documentation: CString,
}

impl ForStandard {
    fn of<M: Model>(description: &ModelDescription, standard: Standard) -> ForStandard {
        let (document, words) = (description.document(standard), standard.words());
        ForStandard {
            standard,
            token: document.token.clone(),
            model_description: to_c_string(&document.xml),
            documentation: to_c_string(&crate::documentation::html::<M>(description, document, words)),
        }
    }
}

impl Exported {
    /// One standard's description.
    pub fn of_standard(&self, standard: Standard) -> &ForStandard {
        self.standards.iter().find(|s| s.standard == standard).expect("every standard of standards::ALL")
    }

    /// A model's description without package information (the runtime's own tests).
    pub fn of<M: Model>() -> Exported {
        Self::with_package::<M>(&Package::default())
    }

    /// A model crate's description with its Cargo metadata and source date (`export_fmu!`).
    pub fn with_package<M: Model>(package: &Package) -> Exported {
        let d = ModelDescription::with_package::<M>(package);
        Exported {
            model_identifier: to_c_string(M::info().name),
            problems: (!d.problems.is_empty()).then(|| to_c_string(&d.problems.join("\n"))),
            standards: ALL.iter().map(|s| ForStandard::of::<M>(&d, *s)).collect(),
            listing: to_c_string(&ALL.iter().filter_map(|s| s.listing()).collect::<Vec<_>>().join("\n")),
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
