//! Systems: several FMUs coupled, declared in `models/systems/<Name>.toml` (read by
//! [`fmi_host::master::declaration`], which the tests couple too) and checked here against the
//! FMUs' variables before [`crate::ssp`] writes them as `<Name>.ssp`.

use std::collections::BTreeMap;

use fmi_host::{Causality, ModelDescription, ScalarVariable, UnitDefinition, VariableType};

pub use fmi_host::master::declaration::{discover, Declaration, Value};
use fmi_host::master::Port;

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
    pub var_type: VariableType,
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
    pub parameters: Vec<(String, VariableType, Value)>,
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
    pub connections: Vec<(Port, Port)>,
    /// Every unit a connector names, sorted by name.
    pub units: Vec<UnitDefinition>,
}

/// Checks a declaration against the FMUs (modelIdentifier -> interface) and resolves it into
/// what the SSD says. Every problem is reported, one per line.
///
/// A component lists as connectors all outputs of its FMU (so that a master records them)
/// and the inputs that a connection feeds. Unconnected inputs are left out: fmpy's SSP runner
/// (0.3.32) fails on an unconnected input connector, or silently feeds it the previous
/// connector's source.
pub fn resolve(decl: &Declaration, fmus: &BTreeMap<String, ModelDescription>) -> Result<System, String> {
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
    let lookup = |end: &Port| -> Result<&ScalarVariable, String> {
        let fmu = instances
            .get(end.instance.as_str())
            .ok_or(format!("no component is named {:?}", end.instance))?;
        let md = fmus
            .get(*fmu)
            .ok_or(format!("the FMU of {} is missing", end.instance))?;
        md.variable(&end.variable).map_err(|_| {
            format!(
                "{} ({fmu}) has no variable {:?} (inputs: {}; outputs: {}; parameters: {})",
                end.instance,
                end.variable,
                md.names_of(Causality::Input).join(", "),
                md.names_of(Causality::Output).join(", "),
                md.names_of(Causality::Parameter).join(", ")
            )
        })
    };

    let mut fed: BTreeMap<&Port, &Port> = BTreeMap::new();
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
        if a.causality != Causality::Output {
            errors.push(format!(
                "{what}: {from} is {}, not an output (a connection goes from an output to an input)",
                with_article(a.causality)
            ));
        }
        if b.causality != Causality::Input {
            errors.push(format!(
                "{what}: {to} is {}, not an input (a connection goes from an output to an input)",
                with_article(b.causality)
            ));
        }
        if a.variable_type != b.variable_type {
            errors.push(format!(
                "{what}: {from} is {} but {to} is {}",
                a.variable_type.name(),
                b.variable_type.name()
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

    let mut parameters: BTreeMap<&str, Vec<(String, VariableType, Value)>> = BTreeMap::new();
    for (target, value) in &decl.parameters {
        let what = format!("parameter {target}");
        let var = match lookup(target) {
            Ok(v) => v,
            Err(e) => {
                errors.push(format!("{what}: {e}"));
                continue;
            }
        };
        if var.causality != Causality::Parameter {
            errors.push(format!(
                "{what}: is {}, not a parameter",
                with_article(var.causality)
            ));
            continue;
        }
        let items = instances
            .get(target.instance.as_str())
            .and_then(|f| fmus.get(*f))
            .and_then(|md| md.items_of(var))
            .unwrap_or_default();
        // The declaration may name an Enumeration's item or give its value. The SSP gets the
        // value as an ssv:Integer: SSP 1.0's ssv:Enumeration (the item's name) stops ecos 0.7.2
        // ("Unknown XML node in ssv:Parameter") and libcosim 0.0.6, and fmpy's simulate_ssp sets
        // it with int(value); every FMI master sets an Enumeration with fmi2SetInteger.
        let typed = value.typed(var.variable_type, items);
        let ssv_type = match var.variable_type {
            VariableType::Enumeration => VariableType::Integer,
            ty => ty,
        };
        match typed {
            Some(v) => parameters
                .entry(target.instance.as_str())
                .or_default()
                .push((target.variable.clone(), ssv_type, v)),
            None => errors.push(format!(
                "{what}: {value:?} does not fit its type {}",
                var.variable_type.name()
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
        let md = &fmus[&c.fmu];
        let mut connectors = Vec::new();
        for v in &md.model_variables {
            let end = Port {
                instance: c.name.clone(),
                variable: v.name.clone(),
            };
            let kind = match v.causality {
                Causality::Output => Kind::Output,
                Causality::Input if fed.contains_key(&end) => Kind::Input,
                _ => continue,
            };
            let unit = v.unit.as_ref().and_then(|u| md.unit(u));
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
                var_type: v.variable_type,
                unit: unit.map(|u| u.name.clone()),
            });
        }
        if connectors
            .iter()
            .any(|k| k.var_type == VariableType::Enumeration)
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

/// "an output", "a parameter".
fn with_article(causality: Causality) -> String {
    let word = causality.name();
    let article = if word.starts_with(['a', 'e', 'i', 'o', 'u']) { "an" } else { "a" };
    format!("{article} {word}")
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use fmi_host::master::declaration::parse;

    /// Two inertias and a shaft (the fixture of fmi-host's declaration tests).
    const TOML: &str = include_str!("../../tests/src/master/testdata/Demo.toml");

    fn md(id: &str, vars: &[(&str, &str, &str, &str)]) -> String {
        let mut xml = format!(
            "<fmiModelDescription fmiVersion=\"2.0\" modelName=\"{id}\" guid=\"{{{id}}}\"><UnitDefinitions>\
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

    pub fn fmus() -> BTreeMap<String, ModelDescription> {
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
            .map(|(id, xml)| (id.to_owned(), ModelDescription::parse(&xml).unwrap()))
            .collect()
    }

    pub fn system() -> System {
        resolve(&parse("Demo", TOML).unwrap(), &fmus()).unwrap()
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
            [("drive".to_owned(), VariableType::Integer, Value::Integer(1))]
        );
        // an Integer literal for a Real parameter becomes a Real
        assert_eq!(
            s.components[1].parameters,
            [("K".to_owned(), VariableType::Real, Value::Real(900.0))]
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
            .unit_definitions
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
}
