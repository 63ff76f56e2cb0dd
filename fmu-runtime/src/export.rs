//! `export_fmu!(MyModel)`: the one line a model crate writes to become an FMU, of both standards.

/// Exports, for a type implementing [`Model`](crate::Model), every function of FMI 2.0
/// `fmi2Functions.h` and of FMI 3.0 `fmi3Functions.h` (Co-Simulation and Model Exchange; one
/// binary serves both standards' FMUs), and the functions `build-fmus` reads:
/// `fmu_runtime_model_identifier`, `fmu_runtime_model_description` and
/// `fmu_runtime_documentation` (FMI 2.0), `fmu_runtime_standards` with each standard's
/// `fmu_runtime_model_description_of(n)` and `fmu_runtime_documentation_of(n)`,
/// `fmu_runtime_model_problems` and `fmu_runtime_effects_html`/`_text`.
///
/// Use it once, at the root of a `cdylib` crate: `fmu_runtime::export_fmu!(RlcCircuit);`
#[macro_export]
macro_rules! export_fmu {
    ($model:ty) => {
        #[allow(non_snake_case, clippy::missing_safety_doc)]
        mod __fmu_exports {
            use super::*;
            use std::os::raw::c_char;
            type M = $model;

            /// The library's declarations and descriptions, made once per library load and
            /// shared by every instance (the descriptions only when build-fmus asks for them).
            static EXPORTED: $crate::exported::ExportedCell<$crate::exported::Exported<M>> = $crate::exported::ExportedCell::new();

            /// The model crate's Cargo metadata and source date, read here, in the model crate, at
            /// compile time: the XML the binary writes at run time is the one build-fmus packaged.
            const PACKAGE: $crate::description::Package = $crate::description::Package {
                version: env!("CARGO_PKG_VERSION"),
                authors: env!("CARGO_PKG_AUTHORS"),
                license: env!("CARGO_PKG_LICENSE"),
                source_date_epoch: option_env!("SOURCE_DATE_EPOCH"),
            };

            fn make() -> $crate::exported::Exported<M> {
                $crate::exported::Exported::<M>::with_package(&PACKAGE)
            }

            fn exported() -> &'static $crate::exported::Exported<M> {
                EXPORTED.get_or_init(make)
            }

            /// Frees the description when the library is unloaded (or the process exits).
            #[cfg(target_os = "linux")]
            #[used]
            #[link_section = ".fini_array"]
            static RELEASE_AT_UNLOAD: extern "C" fn() = {
                extern "C" fn release() {
                    // SAFETY: .fini_array runs when nothing of this library can be called again.
                    unsafe { EXPORTED.release() }
                }
                release
            };

            fn guarded_text(pick: fn(&$crate::exported::Exported<M>) -> *const c_char) -> *const c_char {
                std::panic::catch_unwind(|| pick(exported())).unwrap_or(std::ptr::null())
            }

            #[no_mangle]
            pub extern "C" fn fmu_runtime_model_identifier() -> *const c_char {
                guarded_text(|e| e.model_identifier.as_ptr())
            }
            /// The first standard's (FMI 2.0's) modelDescription.xml and documentation page.
            #[no_mangle]
            pub extern "C" fn fmu_runtime_model_description() -> *const c_char {
                guarded_text(|e| e.described().standards[0].model_description.as_ptr())
            }
            #[no_mangle]
            pub extern "C" fn fmu_runtime_documentation() -> *const c_char {
                guarded_text(|e| e.described().standards[0].documentation.as_ptr())
            }
            /// The exported standards, one line each: version, output folder, binaries folder
            /// (tab-separated); the n-th line's description and page are `..._of(n)`.
            #[no_mangle]
            pub extern "C" fn fmu_runtime_standards() -> *const c_char {
                guarded_text(|e| e.listing.as_ptr())
            }
            #[no_mangle]
            pub extern "C" fn fmu_runtime_model_description_of(n: usize) -> *const c_char {
                std::panic::catch_unwind(|| exported().described().standards.get(n).map_or(std::ptr::null(), |s| s.model_description.as_ptr())).unwrap_or(std::ptr::null())
            }
            #[no_mangle]
            pub extern "C" fn fmu_runtime_documentation_of(n: usize) -> *const c_char {
                std::panic::catch_unwind(|| exported().described().standards.get(n).map_or(std::ptr::null(), |s| s.documentation.as_ptr())).unwrap_or(std::ptr::null())
            }
            /// The model's problems (one per line: "file:line: rule. Fix: ..."), or NULL if none.
            #[no_mangle]
            pub extern "C" fn fmu_runtime_model_problems() -> *const c_char {
                guarded_text(|e| e.described().problems.as_ref().map_or(std::ptr::null(), |p| p.as_ptr()))
            }

            /// The effects of the model and their activities over its default experiment (run
            /// on the first call): (HTML for documentation/index.html, plain text).
            fn effects() -> &'static (std::ffi::CString, std::ffi::CString) {
                static EFFECTS: std::sync::OnceLock<(std::ffi::CString, std::ffi::CString)> = std::sync::OnceLock::new();
                EFFECTS.get_or_init(|| {
                    let (html, text) = $crate::activity_report::report::<M>();
                    ($crate::log::to_c_string(&html), $crate::log::to_c_string(&text))
                })
            }
            /// Table 3.1 and the activity table, as HTML (build-fmus puts it in the documentation).
            #[no_mangle]
            pub extern "C" fn fmu_runtime_effects_html() -> *const c_char {
                std::panic::catch_unwind(|| effects().0.as_ptr()).unwrap_or(std::ptr::null())
            }
            /// Table 3.1 and the activity table, as text (`build-fmus effects <model>`).
            #[no_mangle]
            pub extern "C" fn fmu_runtime_effects_text() -> *const c_char {
                std::panic::catch_unwind(|| effects().1.as_ptr()).unwrap_or(std::ptr::null())
            }

            $crate::export_fmi2!();
            $crate::export_fmi3!();
        }
    };
}
