//! Systems: several FMUs coupled, declared in `models/systems/<Name>.toml` and checked
//! against the FMUs' variables before [`crate::ssp`] writes them as `<Name>.ssp`.
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

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

use crate::interface::{Interface, UnitDefinition, VarType};

/// Where the declarations live, relative to the workspace root.
pub const SYSTEMS_DIR: &str = "models/systems";

/// `instance.variable`.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Endpoint {
    pub element: String,
    pub variable: String,
}

impl std::fmt::Display for Endpoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}.{}", self.element, self.variable)
    }
}

impl Endpoint {
    /// Splits at the first `.`: instance names have none, variable names may.
    fn parse(text: &str) -> Result<Endpoint, String> {
        let text = text.trim();
        match text.split_once('.') {
            Some((e, v)) if !e.is_empty() && !v.is_empty() => Ok(Endpoint {
                element: e.to_owned(),
                variable: v.to_owned(),
            }),
            _ => Err(format!("{text:?} is not \"instance.variable\"")),
        }
    }
}

/// A parameter value as declared (its FMI type is known only from the FMU).
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Real(f64),
    Integer(i64),
    Boolean(bool),
    String(String),
}

/// One `[[components]]` entry.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ComponentDecl {
    pub name: String,
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
    pub connections: Vec<(Endpoint, Endpoint)>,
    pub parameters: Vec<(Endpoint, Value)>,
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

/// Input or output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Input,
    Output,
}

impl Kind {
    pub fn name(self) -> &'static str {
        match self {
            Kind::Input => "input",
            Kind::Output => "output",
        }
    }
}

/// A connector of a component in the SSD.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Connector {
    pub name: String,
    pub kind: Kind,
    pub var_type: VarType,
    /// Only units that the FMU defines (and so the SSD can define too).
    pub unit: Option<String>,
}

/// A component of a checked system.
#[derive(Debug, Clone, PartialEq)]
pub struct Component {
    pub name: String,
    /// The FMU's modelIdentifier; the SSP holds it as `resources/<fmu>.fmu`.
    pub fmu: String,
    pub connectors: Vec<Connector>,
    /// Parameter name, its FMI type and value.
    pub parameters: Vec<(String, VarType, Value)>,
}

impl Component {
    pub fn source(&self) -> String {
        format!("resources/{}.fmu", self.fmu)
    }
}

/// A system checked against its FMUs: what the SSD says.
#[derive(Debug, Clone, PartialEq)]
pub struct System {
    pub name: String,
    pub description: Option<String>,
    pub start_time: Option<f64>,
    pub stop_time: Option<f64>,
    pub components: Vec<Component>,
    /// (start = an output, end = an input)
    pub connections: Vec<(Endpoint, Endpoint)>,
    /// Every unit a connector names, sorted by name.
    pub units: Vec<UnitDefinition>,
}

/// Reads every `models/systems/*.toml` under `root`, sorted by name; none is no error.
pub fn discover(root: &Path) -> Result<Vec<(PathBuf, Declaration)>, String> {
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
        .map(|path| {
            let text = fs::read_to_string(&path)
                .map_err(|e| format!("could not read {}: {e}", path.display()))?;
            let name = path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            let decl = parse(&name, &text).map_err(|e| format!("{}: {e}", path.display()))?;
            Ok((path, decl))
        })
        .collect()
}

/// Parses one declaration; `name` (the file's stem) names the system and its `.ssp`.
pub fn parse(name: &str, text: &str) -> Result<Declaration, String> {
    crate::extract::validate_identifier(name).map_err(|_| {
        format!("the system name {name:?} (the file name) must be a C identifier, like an FMU's")
    })?;
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
    let time = |key: &str| -> Result<Option<f64>, String> {
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
            let pair = (Endpoint::parse(from), Endpoint::parse(to));
            match pair {
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
            let target = Endpoint::parse(key).map_err(|e| format!("parameter {e}"))?;
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

/// Checks a declaration against the FMUs (modelIdentifier -> interface) and resolves it into
/// what the SSD says. Every problem is reported, one per line.
///
/// A component lists as connectors all outputs of its FMU (so that a master records them)
/// and the inputs that a connection feeds. Unconnected inputs are left out: fmpy's SSP runner
/// (0.3.32) fails on an unconnected input connector, or silently feeds it the previous
/// connector's source.
pub fn resolve(decl: &Declaration, fmus: &BTreeMap<String, Interface>) -> Result<System, String> {
    let mut errors: Vec<String> = Vec::new();
    let instances: BTreeMap<&str, &str> = decl
        .components
        .iter()
        .map(|c| (c.name.as_str(), c.fmu.as_str()))
        .collect();
    for c in &decl.components {
        if !fmus.contains_key(&c.fmu) {
            let known: Vec<&str> = fmus.keys().map(String::as_str).collect();
            errors.push(format!(
                "component {}: no FMU {:?} was built (FMUs: {})",
                c.name,
                c.fmu,
                known.join(", ")
            ));
        }
    }
    // The variable an endpoint names, or an error message.
    let lookup = |end: &Endpoint| -> Result<&crate::interface::Variable, String> {
        let fmu = instances
            .get(end.element.as_str())
            .ok_or(format!("no component is named {:?}", end.element))?;
        let interface = fmus
            .get(*fmu)
            .ok_or(format!("the FMU of {} is missing", end.element))?;
        interface.variable(&end.variable).ok_or_else(|| {
            format!(
                "{} ({fmu}) has no variable {:?} (inputs: {}; outputs: {}; parameters: {})",
                end.element,
                end.variable,
                interface.names_of("input").join(", "),
                interface.names_of("output").join(", "),
                interface.names_of("parameter").join(", ")
            )
        })
    };

    let mut fed: BTreeMap<&Endpoint, &Endpoint> = BTreeMap::new();
    for (from, to) in &decl.connections {
        let what = format!("connection {from} -> {to}");
        let (a, b) = match (lookup(from), lookup(to)) {
            (Ok(a), Ok(b)) => (a, b),
            (a, b) => {
                errors.extend(
                    [a.err(), b.err()]
                        .into_iter()
                        .flatten()
                        .map(|e| format!("{what}: {e}")),
                );
                continue;
            }
        };
        if a.causality != "output" {
            errors.push(format!(
                "{what}: {from} is {} {}, not an output (a connection goes from an output to an input)",
                article(&a.causality),
                a.causality
            ));
        }
        if b.causality != "input" {
            errors.push(format!(
                "{what}: {to} is {} {}, not an input (a connection goes from an output to an input)",
                article(&b.causality),
                b.causality
            ));
        }
        if a.var_type != b.var_type {
            errors.push(format!(
                "{what}: {from} is {} but {to} is {}",
                a.var_type.name(),
                b.var_type.name()
            ));
        } else if let (Some(ua), Some(ub)) = (&a.unit, &b.unit) {
            if ua != ub {
                errors.push(format!("{what}: {from} is in {ua} but {to} is in {ub}"));
            }
        }
        if let Some(other) = fed.insert(to, from) {
            errors.push(format!("{to} is fed twice: by {other} and by {from}"));
        }
    }

    let mut parameters: BTreeMap<&str, Vec<(String, VarType, Value)>> = BTreeMap::new();
    for (target, value) in &decl.parameters {
        let what = format!("parameter {target}");
        let var = match lookup(target) {
            Ok(v) => v,
            Err(e) => {
                errors.push(format!("{what}: {e}"));
                continue;
            }
        };
        if var.causality != "parameter" {
            errors.push(format!(
                "{what}: is {} {}, not a parameter",
                article(&var.causality),
                var.causality
            ));
            continue;
        }
        let typed = match (var.var_type, value) {
            (VarType::Real, Value::Real(x)) => Some(Value::Real(*x)),
            (VarType::Real, Value::Integer(i)) => Some(Value::Real(*i as f64)),
            // (Enumerations are left out: SSP gives their values by item name.)
            (VarType::Integer, Value::Integer(i)) if i32::try_from(*i).is_ok() => {
                Some(Value::Integer(*i))
            }
            (VarType::Boolean, Value::Boolean(b)) => Some(Value::Boolean(*b)),
            (VarType::String, Value::String(s)) => Some(Value::String(s.clone())),
            _ => None,
        };
        match typed {
            Some(v) => parameters
                .entry(target.element.as_str())
                .or_default()
                .push((target.variable.clone(), var.var_type, v)),
            None => errors.push(format!(
                "{what}: {value:?} does not fit its type {}",
                var.var_type.name()
            )),
        }
    }
    if !errors.is_empty() {
        return Err(format!(
            "system {} (models/systems/{}.toml):\n  {}",
            decl.name,
            decl.name,
            errors.join("\n  ")
        ));
    }

    let mut units: BTreeMap<String, (UnitDefinition, &str)> = BTreeMap::new();
    let mut components = Vec::new();
    for c in &decl.components {
        let interface = &fmus[&c.fmu];
        let mut connectors = Vec::new();
        for v in &interface.variables {
            let end = Endpoint {
                element: c.name.clone(),
                variable: v.name.clone(),
            };
            let kind = match v.causality.as_str() {
                "output" => Kind::Output,
                "input" if fed.contains_key(&end) => Kind::Input,
                _ => continue,
            };
            let unit = v.unit.as_ref().and_then(|u| interface.unit(u));
            if let Some(def) = unit {
                let mut mine = def.base_unit.clone();
                mine.sort();
                match units.get(&def.name) {
                    Some((known, by)) => {
                        let mut theirs = known.base_unit.clone();
                        theirs.sort();
                        if theirs != mine {
                            errors.push(format!(
                                "unit {:?} is defined differently by {by} and {}",
                                def.name, c.fmu
                            ));
                        }
                    }
                    None => {
                        units.insert(def.name.clone(), (def.clone(), c.fmu.as_str()));
                    }
                }
            }
            connectors.push(Connector {
                name: v.name.clone(),
                kind,
                var_type: v.var_type,
                unit: unit.map(|u| u.name.clone()),
            });
        }
        if connectors
            .iter()
            .any(|k| k.var_type == VarType::Enumeration)
        {
            errors.push(format!(
                "component {}: Enumeration connectors are not supported",
                c.name
            ));
        }
        components.push(Component {
            name: c.name.clone(),
            fmu: c.fmu.clone(),
            connectors,
            parameters: parameters.remove(c.name.as_str()).unwrap_or_default(),
        });
    }
    if !errors.is_empty() {
        return Err(format!("system {}:\n  {}", decl.name, errors.join("\n  ")));
    }
    Ok(System {
        name: decl.name.clone(),
        description: decl.description.clone(),
        start_time: decl.start_time,
        stop_time: decl.stop_time,
        components,
        connections: decl.connections.clone(),
        units: units.into_values().map(|(u, _)| u).collect(),
    })
}

fn article(word: &str) -> &'static str {
    if word.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::interface;

    pub const TOML: &str = r#"
description = "Two inertias & a shaft"
start_time = 0
stop_time = 30.0
connections = [
    "motor.speed -> shaft.speed_a",
    "fan.speed -> shaft.speed_b",
    "shaft.torque -> motor.load",
    "shaft.torque -> fan.load",
]

[parameters]
"shaft.K" = 900
"motor.drive" = 1

[[components]]
name = "motor"
fmu = "Inertia"

[[components]]
name = "shaft"
fmu = "Shaft"

[[components]]
name = "fan"
fmu = "Inertia"
"#;

    fn md(id: &str, vars: &[(&str, &str, &str, &str)]) -> String {
        let mut xml = format!(
            "<fmiModelDescription modelName=\"{id}\"><UnitDefinitions>\
             <Unit name=\"rad/s\"><BaseUnit s=\"-1\" rad=\"1\"/></Unit>\
             <Unit name=\"N.m\"><BaseUnit kg=\"1\" m=\"2\" s=\"-2\"/></Unit>\
             </UnitDefinitions><ModelVariables>"
        );
        for (i, (name, causality, ty, unit)) in vars.iter().enumerate() {
            let unit = if unit.is_empty() {
                String::new()
            } else {
                format!(" unit=\"{unit}\"")
            };
            xml += &format!(
                "<ScalarVariable name=\"{name}\" valueReference=\"{i}\" causality=\"{causality}\"><{ty}{unit}/></ScalarVariable>"
            );
        }
        xml + "</ModelVariables></fmiModelDescription>"
    }

    pub fn fmus() -> BTreeMap<String, Interface> {
        let inertia = md(
            "Inertia",
            &[
                ("J", "parameter", "Real", "kg.m2"),
                ("drive", "parameter", "Integer", ""),
                ("load", "input", "Real", "N.m"),
                ("command", "input", "Real", "N.m"),
                ("speed", "output", "Real", "rad/s"),
                ("angle", "output", "Real", "rad"),
            ],
        );
        let shaft = md(
            "Shaft",
            &[
                ("K", "parameter", "Real", "N.m/rad"),
                ("speed_a", "input", "Real", "rad/s"),
                ("speed_b", "input", "Real", "rad/s"),
                ("torque", "output", "Real", "N.m"),
                ("twist", "local", "Real", "rad"),
                ("on", "output", "Boolean", ""),
            ],
        );
        [("Inertia", inertia), ("Shaft", shaft)]
            .into_iter()
            .map(|(id, xml)| (id.to_owned(), interface::parse(&xml).unwrap()))
            .collect()
    }

    pub fn system() -> System {
        resolve(&parse("Demo", TOML).unwrap(), &fmus()).unwrap()
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
                (Endpoint::parse("motor.drive").unwrap(), Value::Integer(1)),
                (Endpoint::parse("shaft.K").unwrap(), Value::Integer(900)),
            ]
        );
        // A variable name may contain dots; the instance name is before the first.
        assert_eq!(
            Endpoint::parse(" a.b.c ").unwrap(),
            Endpoint {
                element: "a".into(),
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
    fn resolves_connectors_units_and_parameters() {
        let s = system();
        let motor = &s.components[0];
        assert_eq!(motor.source(), "resources/Inertia.fmu");
        // all outputs, and the inputs that are fed (`command` is not), in FMU order
        let conn: Vec<_> = motor
            .connectors
            .iter()
            .map(|c| (c.name.as_str(), c.kind, c.unit.as_deref()))
            .collect();
        assert_eq!(
            conn,
            [
                ("load", Kind::Input, Some("N.m")),
                ("speed", Kind::Output, Some("rad/s")),
                // "rad" is not defined by the FMU: no unit in the SSD
                ("angle", Kind::Output, None),
            ]
        );
        assert_eq!(
            motor.parameters,
            [("drive".to_owned(), VarType::Integer, Value::Integer(1))]
        );
        // an Integer literal for a Real parameter becomes a Real
        assert_eq!(
            s.components[1].parameters,
            [("K".to_owned(), VarType::Real, Value::Real(900.0))]
        );
        assert!(s.components[2].parameters.is_empty());
        let shaft: Vec<_> = s.components[1]
            .connectors
            .iter()
            .map(|c| c.name.as_str())
            .collect();
        assert_eq!(shaft, ["speed_a", "speed_b", "torque", "on"]);
        let units: Vec<_> = s.units.iter().map(|u| u.name.as_str()).collect();
        assert_eq!(units, ["N.m", "rad/s"]);
    }

    fn error_for(toml_text: &str) -> String {
        let decl = parse("Demo", toml_text).unwrap();
        resolve(&decl, &fmus()).unwrap_err()
    }

    fn with(connections: &str, parameters: &str) -> String {
        format!(
            "connections = [{connections}]\n[parameters]\n{parameters}\n\
             [[components]]\nname = \"motor\"\nfmu = \"Inertia\"\n\
             [[components]]\nname = \"shaft\"\nfmu = \"Shaft\"\n"
        )
    }

    #[test]
    fn validation_names_every_problem() {
        let cases = [
            (with("\"motor.speed -> shaft.speed_a\"", ""), None),
            (with("\"motor.sped -> shaft.speed_a\"", ""), Some("motor (Inertia) has no variable \"sped\" (inputs: load, command; outputs: speed, angle; parameters: J, drive)")),
            (with("\"pump.speed -> shaft.speed_a\"", ""), Some("no component is named \"pump\"")),
            (with("\"shaft.speed_a -> motor.load\"", ""), Some("shaft.speed_a is an input, not an output")),
            (with("\"motor.speed -> shaft.torque\"", ""), Some("shaft.torque is an output, not an input")),
            (with("\"motor.speed -> motor.J\"", ""), Some("motor.J is a parameter, not an input")),
            (with("\"shaft.on -> motor.load\"", ""), Some("shaft.on is Boolean but motor.load is Real")),
            (with("\"motor.speed -> motor.load\"", ""), Some("motor.speed is in rad/s but motor.load is in N.m")),
            (with("\"motor.speed -> shaft.speed_a\", \"motor.angle -> shaft.speed_a\"", ""), Some("shaft.speed_a is fed twice: by motor.speed and by motor.angle")),
            (with("", "\"motor.speed\" = 1.0"), Some("parameter motor.speed: is an output, not a parameter")),
            (with("", "\"motor.drive\" = 1.5"), Some("parameter motor.drive: Real(1.5) does not fit its type Integer")),
            (with("", "\"motor.J\" = true"), Some("does not fit its type Real")),
            (with("", "\"motor.mass\" = 1.0"), Some("has no variable \"mass\"")),
        ];
        for (text, want) in cases {
            let got = resolve(&parse("Demo", &text).unwrap(), &fmus());
            match want {
                None => assert!(got.is_ok(), "{got:?}"),
                Some(w) => {
                    let err = got.unwrap_err();
                    assert!(err.contains(w), "want {w:?} in:\n{err}");
                    assert!(err.starts_with("system Demo"), "{err}");
                }
            }
        }
        // Several problems: all of them, one per line after the header (here an unknown
        // variable; an output as the end, in another unit).
        let err = error_for(&with(
            "\"motor.sped -> shaft.speed_a\", \"shaft.torque -> motor.speed\"",
            "",
        ));
        assert_eq!(err.lines().count(), 1 + 3, "{err}");
    }

    #[test]
    fn a_missing_fmu_is_named() {
        let text = "[[components]]\nname = \"motor\"\nfmu = \"InductionMotor\"\n";
        let err = error_for(text);
        assert!(
            err.contains(
                "component motor: no FMU \"InductionMotor\" was built (FMUs: Inertia, Shaft)"
            ),
            "{err}"
        );
    }

    #[test]
    fn conflicting_unit_definitions_are_errors() {
        let mut fmus = fmus();
        let shaft = fmus.get_mut("Shaft").unwrap();
        shaft
            .units
            .iter_mut()
            .find(|u| u.name == "N.m")
            .unwrap()
            .base_unit = vec![("kg".into(), "1".into())];
        let err = resolve(&parse("Demo", TOML).unwrap(), &fmus).unwrap_err();
        assert!(
            err.contains("unit \"N.m\" is defined differently by Inertia and Shaft"),
            "{err}"
        );
    }

    #[test]
    fn discovers_the_toml_files() {
        let tmp = crate::testutil::TempDir::new("systems");
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
}
