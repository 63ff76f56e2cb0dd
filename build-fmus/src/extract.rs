//! Reading a built model library's identity, modelDescription.xml and documentation.
//!
//! Every model library exports these functions, written by `fmu_runtime::export_fmu!`:
//!
//! ```text
//! extern "C" fn fmu_runtime_model_identifier() -> *const c_char
//! extern "C" fn fmu_runtime_model_description() -> *const c_char  // modelDescription.xml
//! extern "C" fn fmu_runtime_documentation() -> *const c_char      // an HTML page
//! extern "C" fn fmu_runtime_model_problems() -> *const c_char     // NULL, or what is wrong
//! extern "C" fn fmu_runtime_model_description_fmi3() -> *const c_char  // FMI 3.0's
//! extern "C" fn fmu_runtime_documentation_fmi3() -> *const c_char      // FMI 3.0's page
//! ```
//!
//! Each returns a NUL-terminated UTF-8 string that stays valid while the library is loaded.
//! The library is loaded, the three strings are copied, and it is unloaded again.

use std::ffi::{c_char, CStr};
use std::path::Path;

use libloading::Library;

/// The identifier symbol's name.
pub const IDENTIFIER_SYMBOL: &str = "fmu_runtime_model_identifier";
/// The model description symbol's name.
pub const DESCRIPTION_SYMBOL: &str = "fmu_runtime_model_description";
/// The documentation symbol's name.
pub const DOCUMENTATION_SYMBOL: &str = "fmu_runtime_documentation";
/// The effects symbols: Table 3.1 and the default experiment's activity table (running the
/// model), as HTML for the documentation and as text for `build-fmus effects`.
pub const EFFECTS_HTML_SYMBOL: &str = "fmu_runtime_effects_html";
pub const EFFECTS_TEXT_SYMBOL: &str = "fmu_runtime_effects_text";
/// Where the documentation page takes the activity table: the comment
/// `fmu_runtime::documentation::ACTIVITY_TABLE_MARK` writes.
pub const ACTIVITY_TABLE_MARK: &str = "<!-- activity table of the default experiment -->\n";

/// The FMI 3.0 twins of the description and documentation symbols (a library built by an older
/// runtime has none: it makes no FMI 3.0 FMU).
pub const DESCRIPTION_FMI3_SYMBOL: &str = "fmu_runtime_model_description_fmi3";
pub const DOCUMENTATION_FMI3_SYMBOL: &str = "fmu_runtime_documentation_fmi3";

/// The problems symbol's name: the model's declaration problems, NULL when there are none.
pub const PROBLEMS_SYMBOL: &str = "fmu_runtime_model_problems";

/// What a model library says about itself, copied out of it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModelInfo {
    /// The FMI modelIdentifier (`RlcCircuit`): names the .fmu and the binary inside it.
    pub identifier: String,
    /// The complete modelDescription.xml.
    pub description: String,
    /// The complete documentation/index.html (with the activity table of the default experiment).
    pub documentation: String,
    /// Table 3.1 and the activity table as text (empty for a model without elements).
    pub effects: String,
    /// The FMI 3.0 modelDescription.xml and documentation page, if the library has them.
    pub fmi3: Option<Fmi3Info>,
}

/// What the same library says about itself as an FMI 3.0 FMU.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fmi3Info {
    pub description: String,
    pub documentation: String,
}

impl ModelInfo {
    /// How many `<ScalarVariable` elements the description declares.
    pub fn variable_count(&self) -> usize {
        count_variables(&self.description)
    }
}

/// Loads the library at `path` (built from package `package`) and copies out its
/// [`ModelInfo`], then checks it: a valid identifier, a description that is a model
/// description naming that identifier, a non-empty documentation page.
pub fn extract(path: &Path, package: &str) -> Result<ModelInfo, String> {
    // SAFETY: the library is a model crate of this workspace, just built by cargo; loading
    // it runs only its (Rust, side-effect free) initializers.
    let lib = unsafe { Library::new(path) }.map_err(|e| {
        format!(
            "{package}: could not load {}: {}",
            path.display(),
            chain(&e)
        )
    })?;
    // A model with problems (a duplicate name, a missing unit, an output never written, ...)
    // says so, each with its source file, line and fix; it is not packaged.
    if let Some(problems) = call_optional_string(&lib, PROBLEMS_SYMBOL)? {
        return Err(format!("{package}: the model is not valid:\n  {}", problems.replace('\n', "\n  ")));
    }
    let identifier = call_string(&lib, IDENTIFIER_SYMBOL, package)?;
    let description = call_string(&lib, DESCRIPTION_SYMBOL, package)?;
    let table = call_optional_string(&lib, EFFECTS_HTML_SYMBOL)?.filter(|t| !t.is_empty());
    let with_table = |page: String| match &table {
        Some(_) if !page.contains(ACTIVITY_TABLE_MARK) => {
            Err(format!("{package}: the documentation page has no place for the activity table ({ACTIVITY_TABLE_MARK:?})"))
        }
        Some(t) => Ok(page.replacen(ACTIVITY_TABLE_MARK, t, 1)),
        None => Ok(page),
    };
    let documentation = with_table(call_string(&lib, DOCUMENTATION_SYMBOL, package)?)?;
    let fmi3 = match (call_optional_string(&lib, DESCRIPTION_FMI3_SYMBOL)?, call_optional_string(&lib, DOCUMENTATION_FMI3_SYMBOL)?) {
        (Some(description), Some(page)) => Some(Fmi3Info { description, documentation: with_table(page)? }),
        _ => None,
    };
    let effects = call_optional_string(&lib, EFFECTS_TEXT_SYMBOL)?.unwrap_or_default();
    drop(lib);
    let info = ModelInfo {
        identifier,
        description,
        documentation,
        effects,
        fmi3,
    };
    check(&info, package)?;
    Ok(info)
}

/// Calls the exported `extern "C" fn() -> *const c_char` named `symbol` and copies its
/// string.
fn call_string(lib: &Library, symbol: &str, package: &str) -> Result<String, String> {
    // SAFETY: the export macro defines the symbol with exactly this signature.
    let f = unsafe { lib.get::<unsafe extern "C" fn() -> *const c_char>(symbol) }.map_err(|e| {
        format!(
            "{package}: the library does not export `{symbol}` (does it call \
             fmu_runtime::export_fmu!?): {}",
            chain(&e)
        )
    })?;
    // SAFETY: a function without arguments; the contract says it returns a NUL-terminated
    // string valid while the library is loaded, which it is until after the copy below.
    let ptr = unsafe { f() };
    if ptr.is_null() {
        return Err(format!("{package}: `{symbol}` returned a null pointer"));
    }
    // SAFETY: non-null and NUL-terminated by contract.
    let bytes = unsafe { CStr::from_ptr(ptr) }.to_bytes();
    String::from_utf8(bytes.to_vec())
        .map_err(|e| format!("{package}: `{symbol}` returned text that is not UTF-8: {e}"))
}

/// Like [`call_string`], for a symbol whose NULL result means "nothing to say".
fn call_optional_string(lib: &Library, symbol: &str) -> Result<Option<String>, String> {
    // SAFETY: the export macro defines the symbol with exactly this signature.
    let Ok(f) = (unsafe { lib.get::<unsafe extern "C" fn() -> *const c_char>(symbol) }) else {
        return Ok(None); // a library built by an older runtime
    };
    // SAFETY: as in `call_string`.
    let ptr = unsafe { f() };
    if ptr.is_null() {
        return Ok(None);
    }
    // SAFETY: non-null and NUL-terminated by contract, valid while the library is loaded.
    let bytes = unsafe { CStr::from_ptr(ptr) }.to_bytes();
    Ok(Some(String::from_utf8_lossy(bytes).into_owned()))
}

/// An error with its sources: libloading's own message ("dlsym failed") says little, the
/// system's (its source) says which symbol or file.
fn chain(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        text.push_str(": ");
        text.push_str(&s.to_string());
        source = s.source();
    }
    text
}

/// The checks that keep a wrong FMU from being written.
fn check(info: &ModelInfo, package: &str) -> Result<(), String> {
    validate_identifier(&info.identifier).map_err(|e| format!("{package}: {e}"))?;
    if !info.description.contains("<fmiModelDescription") {
        return Err(format!(
            "{package}: `{DESCRIPTION_SYMBOL}` did not return a modelDescription.xml \
             (no <fmiModelDescription element)"
        ));
    }
    let named = attribute_values(&info.description, "modelIdentifier");
    if named.is_empty() {
        return Err(format!(
            "{package}: modelDescription.xml has no modelIdentifier attribute"
        ));
    }
    if let Some(other) = named.iter().find(|n| **n != info.identifier) {
        return Err(format!(
            "{package}: modelDescription.xml names modelIdentifier \"{other}\" but the library \
             says \"{}\"",
            info.identifier
        ));
    }
    if info.documentation.trim().is_empty() {
        return Err(format!(
            "{package}: `{DOCUMENTATION_SYMBOL}` returned an empty page"
        ));
    }
    Ok(())
}

/// A modelIdentifier names a file and C symbols: it must be a C identifier
/// (`[A-Za-z_][A-Za-z0-9_]*`), which also keeps it from escaping the output directory.
pub fn validate_identifier(id: &str) -> Result<(), String> {
    let mut chars = id.chars();
    let ok = match chars.next() {
        Some(c) if c.is_ascii_alphabetic() || c == '_' => {
            chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        }
        _ => false,
    };
    if ok {
        Ok(())
    } else {
        Err(format!("modelIdentifier {id:?} is not a C identifier"))
    }
}

/// Counts `<ScalarVariable` start tags (not longer names that begin the same way).
pub fn count_variables(xml: &str) -> usize {
    xml.match_indices("<ScalarVariable")
        .filter(|(i, m)| {
            xml[i + m.len()..]
                .chars()
                .next()
                .is_some_and(|c| c.is_whitespace() || c == '>' || c == '/')
        })
        .count()
}

/// Every value of the attribute `name` in `xml` (either quote style).
fn attribute_values<'a>(xml: &'a str, name: &str) -> Vec<&'a str> {
    let mut values = Vec::new();
    for (i, _) in xml.match_indices(name) {
        // Only a whole attribute name: preceded by whitespace.
        if !xml[..i].ends_with(|c: char| c.is_whitespace()) {
            continue;
        }
        let rest = xml[i + name.len()..].trim_start();
        let Some(rest) = rest.strip_prefix('=') else {
            continue;
        };
        let rest = rest.trim_start();
        let Some(quote) = rest.chars().next().filter(|q| *q == '"' || *q == '\'') else {
            continue;
        };
        if let Some(end) = rest[1..].find(quote) {
            values.push(&rest[1..1 + end]);
        }
    }
    values
}

#[cfg(test)]
mod tests {
    use super::*;

    const XML: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="RlcCircuit" guid="{x}">
  <CoSimulation modelIdentifier="RlcCircuit" canHandleVariableCommunicationStepSize="true"/>
  <ModelVariables>
    <ScalarVariable name="a" valueReference="0"><Real/></ScalarVariable>
    <ScalarVariable
      name="b" valueReference="1"><Real/></ScalarVariable>
    <ScalarVariableX name="not counted"/>
  </ModelVariables>
</fmiModelDescription>"#;

    fn info(id: &str, xml: &str) -> ModelInfo {
        ModelInfo {
            identifier: id.into(),
            description: xml.into(),
            documentation: "<html></html>".into(),
            effects: String::new(),
            fmi3: None,
        }
    }

    #[test]
    fn counts_scalar_variables() {
        assert_eq!(count_variables(XML), 2);
        assert_eq!(count_variables(""), 0);
    }

    #[test]
    fn identifiers_must_be_c_identifiers() {
        for ok in ["RlcCircuit", "_x", "Motor_Fan2"] {
            assert!(validate_identifier(ok).is_ok(), "{ok}");
        }
        for bad in ["", "2x", "../evil", "a b", "Rlc-Circuit", "Ünïcode"] {
            assert!(validate_identifier(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn reads_attribute_values() {
        assert_eq!(attribute_values(XML, "modelIdentifier"), ["RlcCircuit"]);
        assert_eq!(
            attribute_values("<a modelIdentifier = 'X'/>", "modelIdentifier"),
            ["X"]
        );
        assert!(attribute_values("<a xmodelIdentifier=\"X\"/>", "modelIdentifier").is_empty());
    }

    #[test]
    fn checks_catch_a_wrong_description() {
        assert!(check(&info("RlcCircuit", XML), "rlc-circuit").is_ok());
        let err = check(&info("Other", XML), "rlc-circuit").unwrap_err();
        assert!(
            err.contains("\"RlcCircuit\"") && err.contains("\"Other\""),
            "{err}"
        );
        let err = check(&info("RlcCircuit", "<html/>"), "rlc-circuit").unwrap_err();
        assert!(err.contains("fmiModelDescription"), "{err}");
        let no_id = XML.replace("modelIdentifier=\"RlcCircuit\"", "");
        assert!(check(&info("RlcCircuit", &no_id), "p")
            .unwrap_err()
            .contains("no modelIdentifier"));
        let mut empty_doc = info("RlcCircuit", XML);
        empty_doc.documentation = " \n".into();
        assert!(check(&empty_doc, "p").is_err());
    }

    #[test]
    fn a_missing_library_is_an_error_naming_the_crate() {
        let err = extract(Path::new("/nonexistent/librlc_circuit.so"), "rlc-circuit").unwrap_err();
        assert!(err.starts_with("rlc-circuit: could not load"), "{err}");
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_library_without_the_symbols_is_an_error_naming_the_crate() {
        // Any shared library without the symbols will do; libm is on every Linux.
        let Some(libm) = [
            "/lib/x86_64-linux-gnu/libm.so.6",
            "/usr/lib/x86_64-linux-gnu/libm.so.6",
            "/lib64/libm.so.6",
        ]
        .into_iter()
        .map(Path::new)
        .find(|p| p.exists()) else {
            return;
        };
        let err = extract(libm, "rlc-circuit").unwrap_err();
        assert!(
            err.contains("rlc-circuit")
                && err.contains(IDENTIFIER_SYMBOL)
                && err.contains("export_fmu!"),
            "{err}"
        );
    }
}
