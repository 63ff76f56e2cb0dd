//! Reading a built model library's identity, modelDescription.xml and documentation.
//!
//! Every model library exports these functions, written by `fmu_runtime::export_fmu!`:
//!
//! ```text
//! extern "C" fn fmu_runtime_model_identifier() -> *const c_char
//! extern "C" fn fmu_runtime_model_description() -> *const c_char  // modelDescription.xml
//! extern "C" fn fmu_runtime_documentation() -> *const c_char      // an HTML page
//! extern "C" fn fmu_runtime_model_problems() -> *const c_char     // NULL, or what is wrong
//! extern "C" fn fmu_runtime_standards() -> *const c_char          // "2.0\t\tlinux64\n3.0\tfmi3\t..."
//! extern "C" fn fmu_runtime_model_description_of(n: usize) -> *const c_char  // the n-th's XML
//! extern "C" fn fmu_runtime_documentation_of(n: usize) -> *const c_char      // and page
//! ```
//!
//! The standards' list says, for each FMI version the library exports, where its FMU goes
//! (a folder of the output directory, empty for the directory itself) and the name of its
//! binaries folder: build-fmus names no FMI version itself.
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

/// The standards' list and each one's description and page (a library built by an older
/// runtime has none: it makes one FMI 2.0 FMU from the plain symbols).
pub const STANDARDS_SYMBOL: &str = "fmu_runtime_standards";
pub const DESCRIPTION_OF_SYMBOL: &str = "fmu_runtime_model_description_of";
pub const DOCUMENTATION_OF_SYMBOL: &str = "fmu_runtime_documentation_of";

/// The problems symbol's name: the model's declaration problems, NULL when there are none.
pub const PROBLEMS_SYMBOL: &str = "fmu_runtime_model_problems";

/// What a model library says about itself, copied out of it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModelInfo {
    /// The FMI modelIdentifier (`RlcCircuit`): names the .fmu and the binary inside it.
    pub identifier: String,
    /// Table 3.1 and the activity table as text (empty for a model without elements).
    pub effects: String,
    /// One FMU per FMI version the library exports, FMI 2.0 first; never empty.
    pub editions: Vec<Edition>,
}

/// The same library as an FMU of one FMI version.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Edition {
    /// "2.0", "3.0".
    pub version: String,
    /// Where its FMU goes, inside the output directory ("" for the directory itself).
    pub folder: String,
    /// Its binaries folder (`linux64`, `x86_64-linux`).
    pub platform: String,
    /// The complete modelDescription.xml.
    pub description: String,
    /// The complete documentation/index.html (with the activity table of the default experiment).
    pub documentation: String,
}

impl ModelInfo {
    /// The FMI 2.0 modelDescription.xml (the first edition's).
    pub fn description(&self) -> &str {
        &self.editions[0].description
    }

    /// How many `<ScalarVariable` elements the FMI 2.0 description declares.
    pub fn variable_count(&self) -> usize {
        count_variables(self.description())
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
    let table = call_optional_string(&lib, EFFECTS_HTML_SYMBOL)?.filter(|t| !t.is_empty());
    let with_table = |page: String| match &table {
        Some(_) if !page.contains(ACTIVITY_TABLE_MARK) => {
            Err(format!("{package}: the documentation page has no place for the activity table ({ACTIVITY_TABLE_MARK:?})"))
        }
        Some(t) => Ok(page.replacen(ACTIVITY_TABLE_MARK, t, 1)),
        None => Ok(page),
    };
    let mut editions = Vec::new();
    for (n, line) in call_optional_string(&lib, STANDARDS_SYMBOL)?.unwrap_or_default().lines().enumerate() {
        let [version, folder, platform] = line.split('\t').collect::<Vec<_>>()[..] else {
            return Err(format!("{package}: `{STANDARDS_SYMBOL}` line {line:?} is not version, folder and platform"));
        };
        if folder.contains(['/', '\\', '.']) {
            return Err(format!("{package}: `{STANDARDS_SYMBOL}` names the folder {folder:?}: one plain name only"));
        }
        editions.push(Edition {
            version: version.to_owned(),
            folder: folder.to_owned(),
            platform: platform.to_owned(),
            description: call_indexed_string(&lib, DESCRIPTION_OF_SYMBOL, n, package)?,
            documentation: with_table(call_indexed_string(&lib, DOCUMENTATION_OF_SYMBOL, n, package)?)?,
        });
    }
    if editions.is_empty() {
        // A library that lists no standards exports FMI 2.0 only, through the plain symbols.
        let platform = crate::package::platform().map(|(dir, _)| dir.to_owned()).ok_or_else(|| {
            format!("{package}: FMI 2.0 defines no binaries/ folder for {}-{}", std::env::consts::OS, std::env::consts::ARCH)
        })?;
        let description = call_string(&lib, DESCRIPTION_SYMBOL, package)?;
        let documentation = with_table(call_string(&lib, DOCUMENTATION_SYMBOL, package)?)?;
        editions.push(Edition { version: "2.0".into(), folder: String::new(), platform, description, documentation });
    }
    let effects = call_optional_string(&lib, EFFECTS_TEXT_SYMBOL)?.unwrap_or_default();
    drop(lib);
    let info = ModelInfo { identifier, effects, editions };
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

/// Calls the exported `extern "C" fn(usize) -> *const c_char` named `symbol` with `n` and copies
/// its string.
fn call_indexed_string(lib: &Library, symbol: &str, n: usize, package: &str) -> Result<String, String> {
    // SAFETY: the export macro defines the symbol with exactly this signature.
    let f = unsafe { lib.get::<unsafe extern "C" fn(usize) -> *const c_char>(symbol) }
        .map_err(|e| format!("{package}: the library lists its standards but does not export `{symbol}`: {}", chain(&e)))?;
    // SAFETY: as in `call_string`; a null result (no n-th standard) is an error below.
    let ptr = unsafe { f(n) };
    if ptr.is_null() {
        return Err(format!("{package}: `{symbol}({n})` returned a null pointer"));
    }
    // SAFETY: non-null and NUL-terminated by contract, valid while the library is loaded.
    let bytes = unsafe { CStr::from_ptr(ptr) }.to_bytes();
    String::from_utf8(bytes.to_vec()).map_err(|e| format!("{package}: `{symbol}({n})` returned text that is not UTF-8: {e}"))
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
    if info.editions.is_empty() {
        return Err(format!("{package}: the library exports no FMI version"));
    }
    for e in &info.editions {
        check_one(&info.identifier, &e.description, &e.documentation, &format!("{DESCRIPTION_OF_SYMBOL} (FMI {})", e.version), package)?;
    }
    Ok(())
}

/// One standard's description and page: a model description naming the library's identifier,
/// and a page that is not empty.
fn check_one(identifier: &str, description: &str, documentation: &str, symbol: &str, package: &str) -> Result<(), String> {
    if !description.contains("<fmiModelDescription") {
        return Err(format!(
            "{package}: `{symbol}` did not return a modelDescription.xml \
             (no <fmiModelDescription element)"
        ));
    }
    let named = attribute_values(description, "modelIdentifier");
    if named.is_empty() {
        return Err(format!(
            "{package}: modelDescription.xml has no modelIdentifier attribute"
        ));
    }
    if let Some(other) = named.iter().find(|n| **n != identifier) {
        return Err(format!(
            "{package}: modelDescription.xml names modelIdentifier \"{other}\" but the library \
             says \"{identifier}\""
        ));
    }
    if documentation.trim().is_empty() {
        return Err(format!(
            "{package}: the documentation page of `{symbol}` is empty"
        ));
    }
    Ok(())
}

/// A modelIdentifier names a file and C symbols: it must be a C identifier
/// (`[A-Za-z_][A-Za-z0-9_]*`), which also keeps it from escaping the output directory.
pub fn validate_identifier(id: &str) -> Result<(), String> {
    if fmi_host::master::declaration::is_c_identifier(id) {
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
        let edition = Edition {
            version: "2.0".into(),
            folder: String::new(),
            platform: "linux64".into(),
            description: xml.into(),
            documentation: "<html></html>".into(),
        };
        ModelInfo { identifier: id.into(), effects: String::new(), editions: vec![edition] }
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
        empty_doc.editions[0].documentation = " \n".into();
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
