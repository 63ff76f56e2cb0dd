//! What a model's library says about itself, made once per library load and freed at unload:
//! its declarations (the model's handles and variable table, shared by every instance), its
//! identifier, what instantiation checks (the problems found without probing, the first half of
//! each standard's token), and, made on first use (by build-fmus, or a test), each standard's
//! modelDescription.xml, token and documentation page, with the dependency probe they need.

use std::ffi::CString;
use std::ptr;
use std::sync::atomic::{AtomicPtr, Ordering};
use std::sync::{Arc, OnceLock};

use crate::description::{ModelDescription, Package};
use crate::log::to_c_string;
use crate::model::{Model, RuntimeVariables};
use crate::standards::{Standard, ALL};
use crate::variables::VariableTable;
use crate::xml::TokenCheck;

/// A model's declarations, made once per library: its handles (the model struct), the
/// runtime's own variables and the variable table. Every instance shares them.
pub struct Declared<M> {
    pub model: Arc<M>,
    pub runtime: RuntimeVariables,
    pub table: Arc<VariableTable>,
}

impl<M: Model> Declared<M> {
    /// Runs the model's `declare` (O(variables)).
    pub fn new() -> Self {
        let (model, runtime, table) = crate::model::declare::<M>();
        Declared { model: Arc::new(model), runtime, table: Arc::new(table) }
    }
}

impl<M: Model> Default for Declared<M> {
    fn default() -> Self {
        Self::new()
    }
}

/// What a model's library says about itself. Made once per library load, in O(variables): the
/// declarations, the problems found without probing, each standard's token check and the
/// standards' listing; the descriptions (`described`), which probe the equations for the
/// ModelStructure, only when first asked for: instantiation never needs them.
pub struct Exported<M> {
    pub model_identifier: CString,
    pub declared: Declared<M>,
    /// The problems found without probing the equations (`description::problems_without_probe`),
    /// one per line, if there are any: such a model cannot be instantiated.
    pub instantiation_problems: Option<String>,
    /// Each standard's token check (`standards::ALL` order), made at its first instantiation
    /// (one XML written: an FMI 2.0 master never pays for FMI 3.0's).
    checks: Vec<OnceLock<TokenCheck>>,
    /// `fmu_runtime_standards`: one line per standard that names a platform (version, output
    /// folder, binaries folder), for build-fmus.
    pub listing: CString,
    package: Package,
    described: OnceLock<Described>,
}

/// The descriptions of a model, with the ModelStructure its equations give.
pub struct Described {
    /// The model's problems, one per line ("file:line: rule. Fix: ..."), if it has any:
    /// build-fmus refuses to package such a model. Beside `Exported::instantiation_problems`,
    /// the outputs the probe finds constant.
    pub problems: Option<CString>,
    /// Each exported standard's description (`standards::ALL` order).
    pub standards: Vec<ForStandard>,
}

/// One standard's description of the model, as the library hands it out.
pub struct ForStandard {
    pub standard: Standard,
    /// FMI 2.0 `guid`, FMI 3.0 `instantiationToken`: what the modelDescription.xml says.
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

impl<M: Model> Exported<M> {
    /// A model's library without package information (the runtime's own tests).
    pub fn of() -> Self {
        Self::with_package(&Package::default())
    }

    /// A model crate's library with its Cargo metadata and source date (`export_fmu!`).
    pub fn with_package(package: &Package) -> Self {
        let declared = Declared::<M>::new();
        let problems = crate::description::problems_without_probe(&*declared.model, &declared.table);
        Exported {
            model_identifier: to_c_string(M::info().name),
            instantiation_problems: (!problems.is_empty()).then(|| problems.join("\n")),
            checks: ALL.iter().map(|_| OnceLock::new()).collect(),
            listing: to_c_string(&ALL.iter().filter_map(|s| s.listing()).collect::<Vec<_>>().join("\n")),
            package: *package,
            declared,
            described: OnceLock::new(),
        }
    }

    /// What one standard's instantiation checks a master's token against (made on the first
    /// call: O(variables), no probe).
    pub fn token_check(&self, standard: Standard) -> &TokenCheck {
        self.checks[ALL.iter().position(|s| *s == standard).expect("every standard of standards::ALL")]
            .get_or_init(|| crate::description::token_check::<M>(standard, &*self.declared.model, &self.declared.table, &self.package))
    }

    /// The descriptions, made on the first call (the dependency probe runs then, once).
    pub fn described(&self) -> &Described {
        self.described.get_or_init(|| {
            let d = ModelDescription::of_declared(&*self.declared.model, Arc::clone(&self.declared.table), &self.package);
            Described {
                problems: (!d.problems.is_empty()).then(|| to_c_string(&d.problems.join("\n"))),
                standards: ALL.iter().map(|s| ForStandard::of::<M>(&d, *s)).collect(),
            }
        })
    }

    /// One standard's description (made on first use, see `described`).
    pub fn of_standard(&self, standard: Standard) -> &ForStandard {
        self.described().standards.iter().find(|s| s.standard == standard).expect("every standard of standards::ALL")
    }
}

/// Where a model library keeps its [`Exported`] description: made on first use, and freed when
/// the library is unloaded (`dlclose`), so a master that loads and unloads an FMU many times
/// loses no memory. (A `OnceLock` static would never be freed: statics have no destructor.)
pub struct ExportedCell<T> {
    ptr: AtomicPtr<T>,
}

impl<T: Send + Sync> ExportedCell<T> {
    pub const fn new() -> Self {
        ExportedCell { ptr: AtomicPtr::new(ptr::null_mut()) }
    }

    /// The description, made by `make` on the first call (if two threads race, one result is
    /// kept and the other dropped).
    pub fn get_or_init(&self, make: fn() -> T) -> &T {
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

impl<T: Send + Sync> Default for ExportedCell<T> {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::instance::Interface;
    use crate::test_model::{Array, ARRAY_DECLARED, ARRAY_EVALUATED};
    use std::sync::atomic::Ordering::SeqCst;

    /// The only test of `Array`: its counters are the library's and its instances' costs.
    #[test]
    fn instances_share_the_library_s_one_declaration_and_instantiation_never_probes() {
        // The tokens a master reads from the packaged descriptions (another load of the library).
        let packaged = Exported::<Array>::of();
        let tokens = [Standard::Fmi2, Standard::Fmi3].map(|s| CString::new(packaged.of_standard(s).token.clone()).unwrap());
        let (declared, evaluated) = (ARRAY_DECLARED.load(SeqCst), ARRAY_EVALUATED.load(SeqCst));
        let e: &'static Exported<Array> = Box::leak(Box::new(Exported::of()));
        let callbacks = crate::fmi2::types::fmi2CallbackFunctions {
            logger: None,
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: ptr::null_mut(),
        };
        // SAFETY: valid strings and callbacks; each instance is freed once below.
        unsafe {
            let fmi2: Vec<_> = (0..3)
                .map(|_| crate::fmi2::functions::instantiate::<Array>(e, c"a".as_ptr(), crate::fmi2::types::fmi2CoSimulation, tokens[0].as_ptr(), ptr::null(), &callbacks, 0, 0))
                .collect();
            let fmi3: Vec<_> = [Interface::CoSimulation, Interface::ModelExchange]
                .into_iter()
                .map(|i| crate::fmi3::functions::instantiate::<Array>(e, i, c"b".as_ptr(), tokens[1].as_ptr(), ptr::null_mut(), false, None, (false, false)))
                .collect();
            assert!(fmi2.iter().all(|c| !c.is_null()) && fmi3.iter().all(|c| !c.is_null()), "the packaged tokens are accepted");
            assert_eq!(ARRAY_DECLARED.load(SeqCst) - declared, 1, "one declaration for the library and its five instances");
            // Without the probe: the unwritten-output check's one evaluation (one configuration).
            assert_eq!(ARRAY_EVALUATED.load(SeqCst) - evaluated, 1, "instantiation evaluated the equations beyond the problems' check");
            assert!(e.described.get().is_none(), "instantiation made the descriptions");
            // A token of another description is refused: another first half, or not a token.
            let other = format!("{{0{}", &tokens[0].to_str().unwrap()[2..]);
            for wrong in [other.as_str(), &tokens[0].to_str().unwrap()[..37], "{not-this-one}"] {
                let wrong = CString::new(wrong).unwrap();
                let c = crate::fmi2::functions::instantiate::<Array>(e, c"a".as_ptr(), crate::fmi2::types::fmi2CoSimulation, wrong.as_ptr(), ptr::null(), &callbacks, 0, 0);
                assert!(c.is_null(), "{wrong:?} accepted");
            }
            for c in fmi2 {
                crate::fmi2::functions::free_instance::<Array>(c);
            }
            for c in fmi3 {
                crate::fmi3::functions::free_instance::<Array>(c);
            }
        }
        // The descriptions, when asked for, probe the equations (once) and give the same tokens.
        assert_eq!(e.of_standard(Standard::Fmi3).token.as_str(), tokens[1].to_str().unwrap());
        assert!(ARRAY_EVALUATED.load(SeqCst) - evaluated > 20, "the probe ran");
        assert_eq!(ARRAY_DECLARED.load(SeqCst) - declared, 1, "on the library's declaration");
        // Structured names: accepted, and said in both descriptions (FMI 2.0 section 2.2.9, FMI 3.0 2.4.7.5).
        assert!(e.described().problems.is_none(), "{:?}", e.described().problems);
        for s in [Standard::Fmi2, Standard::Fmi3] {
            let xml = e.of_standard(s).model_description.to_str().unwrap();
            assert!(xml.contains(r#" variableNamingConvention="structured""#), "{xml}");
            assert!(xml.contains(r#"name="der(theta[2])""#), "{xml}");
        }
    }
}
