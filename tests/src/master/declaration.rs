//! A system as the workspace declares it: `models/systems/<Name>.toml`, the one declaration of
//! what is coupled. build-fmus checks it against the FMUs and writes it as `<Name>.ssp`; the
//! tests couple the same declaration with this master ([`System::declared`]).
//!
//! ```toml
//! description = "What the system is"       # optional
//! start_time = 0.0                          # optional: the SSD's DefaultExperiment
//! stop_time = 30.0
//! connections = [                           # output -> input, "instance.variable"
//!     "motor.speed -> shaft.speed_a",
//! ]
//!
//! [parameters]                              # optional start values of parameters
//! "motor.drive" = 1
//!
//! [[components]]                            # one per instance, in this order
//! name = "motor"                            # instance name (no '.')
//! fmu = "InductionMotor"                    # modelIdentifier of an FMU of this workspace
//! ```
//!
//! Top-level keys (`connections`, the times) go before the first `[...]` or `[[...]]`
//! header: TOML puts every key that follows a header into that header's table.

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::error::{config, MasterError, Result};
use super::system::{Component, Port, System};
use crate::fmu::Fmu;
use crate::model_description::VariableType;

/// Where the declarations live, relative to the workspace root.
pub const SYSTEMS_DIR: &str = "models/systems";

/// A parameter value as declared (its FMI type is known only from the FMU).
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Real(f64),
    Integer(i64),
    Boolean(bool),
    String(String),
}

impl Value {
    /// The value as a variable of type `ty` takes it (an Integer literal for a Real is a
    /// Real; an Enumeration's item, given by name or by value, is its value); `None` when it does
    /// not fit (another type, an Integer beyond 32 bits, no such item). `items` are an
    /// Enumeration's (name, value) pairs (`ModelDescription::items_of`; empty: any 32-bit value).
    pub fn typed(&self, ty: VariableType, items: &[(String, i64)]) -> Option<Value> {
        match (ty, self) {
            (VariableType::Real, Value::Real(x)) => Some(Value::Real(*x)),
            (VariableType::Real, Value::Integer(i)) => Some(Value::Real(*i as f64)),
            (VariableType::Enumeration, Value::Integer(i)) if !items.is_empty() => {
                items.iter().any(|(_, v)| v == i).then_some(Value::Integer(*i))
            }
            (VariableType::Enumeration, Value::String(name)) => {
                items.iter().find(|(n, _)| n == name).map(|(_, v)| Value::Integer(*v))
            }
            (VariableType::Integer | VariableType::Enumeration, Value::Integer(i))
                if i32::try_from(*i).is_ok() =>
            {
                Some(Value::Integer(*i))
            }
            (VariableType::Boolean, Value::Boolean(b)) => Some(Value::Boolean(*b)),
            (VariableType::String, Value::String(s)) => Some(Value::String(s.clone())),
            _ => None,
        }
    }
}

/// One `[[components]]` entry.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ComponentDecl {
    pub name: String,
    /// The modelIdentifier of its FMU.
    pub fmu: String,
}

/// A system as declared in its TOML file, not yet checked against the FMUs.
#[derive(Debug, Clone, PartialEq)]
pub struct Declaration {
    pub name: String,
    pub description: Option<String>,
    pub start_time: Option<f64>,
    pub stop_time: Option<f64>,
    pub components: Vec<ComponentDecl>,
    /// (an output, an input)
    pub connections: Vec<(Port, Port)>,
    /// Sorted by `"instance.variable"` (TOML tables are).
    pub parameters: Vec<(Port, Value)>,
}

impl Declaration {
    /// The modelIdentifiers the system needs, each once, in component order.
    pub fn fmus(&self) -> Vec<&str> {
        let mut seen = Vec::new();
        for c in &self.components {
            if !seen.contains(&c.fmu.as_str()) {
                seen.push(c.fmu.as_str());
            }
        }
        seen
    }
}

/// Whether `name` is a C identifier (`[A-Za-z_][A-Za-z0-9_]*`): a modelIdentifier's and a
/// system's name must be, since they name files (and, for an FMU, C symbols).
pub fn is_c_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    match chars.next() {
        Some(c) if c.is_ascii_alphabetic() || c == '_' => {
            chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        }
        _ => false,
    }
}

/// Reads every `models/systems/*.toml` under `root`, sorted by name; none is no error.
pub fn discover(root: &Path) -> std::result::Result<Vec<(PathBuf, Declaration)>, String> {
    let dir = root.join(SYSTEMS_DIR);
    let Ok(entries) = fs::read_dir(&dir) else {
        return Ok(Vec::new());
    };
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml") && p.is_file())
        .collect();
    paths.sort();
    paths
        .into_iter()
        .map(|path| read(&path).map(|decl| (path, decl)))
        .collect()
}

/// Reads one declaration file; its stem names the system.
pub fn read(path: &Path) -> std::result::Result<Declaration, String> {
    let text =
        fs::read_to_string(path).map_err(|e| format!("could not read {}: {e}", path.display()))?;
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    parse(&name, &text).map_err(|e| format!("{}: {e}", path.display()))
}

/// The declaration `<workspace>/models/systems/<name>.toml` of this checkout (for the tests
/// and examples, which run inside it).
pub fn workspace_system(name: &str) -> std::result::Result<Declaration, String> {
    read(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join(SYSTEMS_DIR)
            .join(format!("{name}.toml")),
    )
}

/// Parses one declaration; `name` (the file's stem) names the system and its `.ssp`.
pub fn parse(name: &str, text: &str) -> std::result::Result<Declaration, String> {
    if !is_c_identifier(name) {
        return Err(format!(
            "the system name {name:?} (the file name) must be a C identifier, like an FMU's"
        ));
    }
    let table: toml::Table = text.parse().map_err(|e| format!("not valid TOML: {e}"))?;
    const KEYS: [&str; 6] = [
        "description",
        "start_time",
        "stop_time",
        "components",
        "connections",
        "parameters",
    ];
    if let Some(k) = table.keys().find(|k| !KEYS.contains(&k.as_str())) {
        return Err(format!("unknown key `{k}` (known: {})", KEYS.join(", ")));
    }
    let time = |key: &str| -> std::result::Result<Option<f64>, String> {
        match table.get(key) {
            None => Ok(None),
            Some(v) => v
                .as_float()
                .or_else(|| v.as_integer().map(|i| i as f64))
                .filter(|t| t.is_finite())
                .map(Some)
                .ok_or_else(|| format!("`{key}` must be a number")),
        }
    };
    let description = match table.get("description") {
        None => None,
        Some(v) => Some(
            v.as_str()
                .ok_or("`description` must be a string")?
                .to_owned(),
        ),
    };

    let mut components = Vec::new();
    let list = table
        .get("components")
        .and_then(|c| c.as_array())
        .filter(|c| !c.is_empty())
        .ok_or("`[[components]]` must list at least one component (name, fmu)")?;
    for (i, c) in list.iter().enumerate() {
        let c = c
            .as_table()
            .ok_or(format!("components[{i}] must be a table with name and fmu"))?;
        if let Some(k) = c.keys().find(|k| *k != "name" && *k != "fmu") {
            return Err(format!(
                "components[{i}]: unknown key `{k}` (known: name, fmu)"
            ));
        }
        let field = |key: &str| {
            c.get(key)
                .and_then(|v| v.as_str())
                .map(str::to_owned)
                .ok_or(format!("components[{i}] needs `{key}` (a string)"))
        };
        let (name, fmu) = (field("name")?, field("fmu")?);
        if name.is_empty() || name.contains(['.', '/', '\\']) || name.trim() != name {
            return Err(format!(
                "components[{i}]: instance name {name:?} must be non-empty, without '.', '/' or spaces around"
            ));
        }
        if components.iter().any(|c: &ComponentDecl| c.name == name) {
            return Err(format!("two components are named {name:?}"));
        }
        components.push(ComponentDecl { name, fmu });
    }

    let mut connections = Vec::new();
    if let Some(v) = table.get("connections") {
        let list = v
            .as_array()
            .ok_or("`connections` must be an array of \"a.y -> b.u\" strings")?;
        for c in list {
            let text = c
                .as_str()
                .ok_or("`connections` must be an array of \"a.y -> b.u\" strings")?;
            let (from, to) = text
                .split_once("->")
                .ok_or(format!("connection {text:?} is not \"a.y -> b.u\""))?;
            match (Port::parse(from), Port::parse(to)) {
                (Ok(from), Ok(to)) => connections.push((from, to)),
                (Err(e), _) | (_, Err(e)) => return Err(format!("connection {text:?}: {e}")),
            }
        }
    }

    let mut parameters = Vec::new();
    if let Some(v) = table.get("parameters") {
        let t = v
            .as_table()
            .ok_or("`[parameters]` must be a table of \"instance.name\" = value")?;
        for (key, v) in t {
            let target = Port::parse(key).map_err(|e| format!("parameter {e}"))?;
            let value = match v {
                toml::Value::Float(f) if f.is_finite() => Value::Real(*f),
                toml::Value::Integer(i) => Value::Integer(*i),
                toml::Value::Boolean(b) => Value::Boolean(*b),
                toml::Value::String(s) => Value::String(s.clone()),
                _ => {
                    return Err(format!(
                        "parameter {key}: the value must be a finite number, a boolean or a string"
                    ))
                }
            };
            parameters.push((target, value));
        }
    }

    Ok(Declaration {
        name: name.to_owned(),
        description,
        start_time: time("start_time")?,
        stop_time: time("stop_time")?,
        components,
        connections,
        parameters,
    })
}

impl System {
    /// The declared system coupled by this master: its components in declaration order (the
    /// default Gauss-Seidel order), each with the FMU `fmu(modelIdentifier)` and the declared
    /// parameter values as start values, and its connections.
    pub fn declared(decl: &Declaration, mut fmu: impl FnMut(&str) -> Arc<Fmu>) -> Result<System> {
        let mut system = System::new();
        for c in &decl.components {
            system = system.with(Component::new(c.name.clone(), &fmu(&c.fmu)));
        }
        for (target, value) in &decl.parameters {
            let component = system.component_mut(&target.instance)?;
            let variable = component.fmu.variable(&target.variable).map_err(|source| {
                MasterError::Host {
                    instance: target.instance.clone(),
                    source,
                }
            })?;
            let items = component.fmu.model_description().items_of(variable).unwrap_or_default();
            match value.typed(variable.variable_type, items) {
                Some(Value::Real(x)) => component.set_real(&target.variable, x),
                Some(Value::Integer(n)) => {
                    component.set_integer(&target.variable, n as i32) // fits: `typed` checked
                }
                Some(Value::Boolean(b)) => component.set_boolean(&target.variable, b),
                _ => {
                    return Err(config(format!(
                        "parameter {target}: {value:?} does not fit its type {} (or is a String, which this master does not set)",
                        variable.variable_type.name()
                    )))
                }
            }
        }
        for (from, to) in &decl.connections {
            system = system.connect(from.to_string(), to.to_string());
        }
        Ok(system)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The demo declaration the unit tests of build-fmus read too.
    const TOML: &str = include_str!("testdata/Demo.toml");

    fn port(text: &str) -> Port {
        Port::parse(text).unwrap()
    }

    #[test]
    fn parses_a_declaration() {
        let d = parse("Demo", TOML).unwrap();
        assert_eq!(d.name, "Demo");
        assert_eq!(d.description.as_deref(), Some("Two inertias & a shaft"));
        assert_eq!((d.start_time, d.stop_time), (Some(0.0), Some(30.0)));
        let names: Vec<_> = d
            .components
            .iter()
            .map(|c| (c.name.as_str(), c.fmu.as_str()))
            .collect();
        assert_eq!(
            names,
            [("motor", "Inertia"), ("shaft", "Shaft"), ("fan", "Inertia")]
        );
        assert_eq!(d.fmus(), ["Inertia", "Shaft"]);
        assert_eq!(d.connections.len(), 4);
        assert_eq!(d.connections[0].0.to_string(), "motor.speed");
        assert_eq!(d.connections[0].1.to_string(), "shaft.speed_a");
        // sorted by key (TOML tables are)
        assert_eq!(
            d.parameters,
            [
                (port("motor.drive"), Value::Integer(1)),
                (port("shaft.K"), Value::Integer(900)),
            ]
        );
        // A variable name may contain dots; the instance name is before the first.
        assert_eq!(
            port(" a.b.c "),
            Port {
                instance: "a".into(),
                variable: "b.c".into()
            }
        );
    }

    #[test]
    fn malformed_declarations_are_errors() {
        let cases = [
            ("stop_time = 1", "at least one component"),
            ("[[components]]\nname = \"a\"", "needs `fmu`"),
            ("[[components]]\nname = \"a.b\"\nfmu = \"X\"", "without '.'"),
            ("[[components]]\nname = \"a\"\nfmu = \"X\"\n[[components]]\nname = \"a\"\nfmu = \"Y\"", "two components are named \"a\""),
            ("connections = [\"a.y b.u\"]\n[[components]]\nname = \"a\"\nfmu = \"X\"", "is not \"a.y -> b.u\""),
            ("connections = [\"a -> b.u\"]\n[[components]]\nname = \"a\"\nfmu = \"X\"", "\"a\" is not \"instance.variable\""),
            ("bogus = 1\n[[components]]\nname = \"a\"\nfmu = \"X\"", "unknown key `bogus`"),
            ("stop_time = \"soon\"\n[[components]]\nname = \"a\"\nfmu = \"X\"", "`stop_time` must be a number"),
            ("[parameters]\n\"a.k\" = [1]\n[[components]]\nname = \"a\"\nfmu = \"X\"", "parameter a.k"),
            ("[[components]\n", "not valid TOML"),
        ];
        for (text, want) in cases {
            let err = parse("S", text).unwrap_err();
            assert!(err.contains(want), "{text:?}: {err}");
        }
        assert!(parse("Bad-Name", TOML)
            .unwrap_err()
            .contains("C identifier"));
    }

    #[test]
    fn identifiers_must_be_c_identifiers() {
        for ok in ["RlcCircuit", "_x", "Motor_Fan2"] {
            assert!(is_c_identifier(ok), "{ok}");
        }
        for bad in ["", "2x", "../evil", "a b", "Rlc-Circuit", "Ünïcode"] {
            assert!(!is_c_identifier(bad), "{bad}");
        }
    }

    #[test]
    fn values_take_their_variables_type() {
        assert_eq!(Value::Integer(900).typed(VariableType::Real, &[]), Some(Value::Real(900.0)));
        assert_eq!(Value::Integer(2).typed(VariableType::Enumeration, &[]), Some(Value::Integer(2)));
        assert_eq!(Value::Integer(1 << 40).typed(VariableType::Integer, &[]), None);
        assert_eq!(Value::Real(1.5).typed(VariableType::Integer, &[]), None);
        assert_eq!(Value::Boolean(true).typed(VariableType::Real, &[]), None);
        assert_eq!(Value::String("a".into()).typed(VariableType::String, &[]), Some(Value::String("a".into())));
        // An Enumeration's item by name or by value; no other.
        let items = [("direct_on_line".to_string(), 1), ("converter".to_string(), 2)];
        assert_eq!(Value::String("converter".into()).typed(VariableType::Enumeration, &items), Some(Value::Integer(2)));
        assert_eq!(Value::Integer(1).typed(VariableType::Enumeration, &items), Some(Value::Integer(1)));
        assert_eq!(Value::Integer(3).typed(VariableType::Enumeration, &items), None);
        assert_eq!(Value::String("dol".into()).typed(VariableType::Enumeration, &items), None);
    }

    #[test]
    fn discovers_the_toml_files() {
        let tmp = crate::tempdir::TempDir::new("systems").unwrap();
        assert!(discover(tmp.path()).unwrap().is_empty());
        let dir = tmp.path().join(SYSTEMS_DIR);
        fs::create_dir_all(&dir).unwrap();
        fs::write(dir.join("B.toml"), TOML).unwrap();
        fs::write(dir.join("A.toml"), TOML).unwrap();
        fs::write(dir.join("notes.md"), "not a system").unwrap();
        let found = discover(tmp.path()).unwrap();
        let names: Vec<_> = found.iter().map(|(_, d)| d.name.as_str()).collect();
        assert_eq!(names, ["A", "B"]);
        fs::write(dir.join("C.toml"), "[[components]]\nname = 1\n").unwrap();
        let err = discover(tmp.path()).unwrap_err();
        assert!(
            err.contains("C.toml") && err.contains("needs `name`"),
            "{err}"
        );
    }

    #[test]
    fn the_workspace_declares_its_systems() {
        let d = workspace_system("MotorFanSystem").unwrap();
        assert_eq!(d.fmus(), ["InductionMotor", "DriveShaft", "Fan"]);
        assert!(workspace_system("NoSuchSystem").unwrap_err().contains("NoSuchSystem.toml"));
    }
}
