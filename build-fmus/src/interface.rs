//! An FMU's interface as a system sees it: its variables (name, causality, type, unit) and
//! its unit definitions, read from its modelDescription.xml with quick-xml.

use quick_xml::events::{BytesStart, Event};
use quick_xml::{Reader, XmlVersion};

/// The FMI 2.0 type element of a variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VarType {
    Real,
    Integer,
    Boolean,
    String,
    Enumeration,
}

impl VarType {
    /// The element name, as FMI 2.0 and SSP 1.0 (`ssc:`/`ssv:`) both spell it.
    pub fn name(self) -> &'static str {
        match self {
            VarType::Real => "Real",
            VarType::Integer => "Integer",
            VarType::Boolean => "Boolean",
            VarType::String => "String",
            VarType::Enumeration => "Enumeration",
        }
    }
}

/// One `<ScalarVariable>`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Variable {
    pub name: String,
    /// FMI 2.0 causality; `local` when the attribute is absent.
    pub causality: String,
    pub var_type: VarType,
    /// The `unit` attribute of a Real (or Integer) type element.
    pub unit: Option<String>,
}

/// One `<Unit>` of `<UnitDefinitions>`: its name and the attributes of its `<BaseUnit>`
/// (kg, m, s, A, K, mol, cd, rad, factor, offset), as written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnitDefinition {
    pub name: String,
    pub base_unit: Vec<(String, String)>,
}

/// What a system needs to know about one FMU.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Interface {
    pub variables: Vec<Variable>,
    pub units: Vec<UnitDefinition>,
}

impl Interface {
    pub fn variable(&self, name: &str) -> Option<&Variable> {
        self.variables.iter().find(|v| v.name == name)
    }

    pub fn unit(&self, name: &str) -> Option<&UnitDefinition> {
        self.units.iter().find(|u| u.name == name)
    }

    /// The names of the variables of one causality, in declaration order.
    pub fn names_of(&self, causality: &str) -> Vec<&str> {
        self.variables
            .iter()
            .filter(|v| v.causality == causality)
            .map(|v| v.name.as_str())
            .collect()
    }
}

fn attributes(e: &BytesStart<'_>) -> Result<Vec<(String, String)>, String> {
    e.attributes()
        .map(|a| {
            let a = a.map_err(|err| format!("bad attribute: {err}"))?;
            let value = a
                .normalized_value(XmlVersion::Implicit1_0)
                .map_err(|err| format!("bad attribute value: {err}"))?;
            Ok((a.key.as_ref().to_owned(), value.into_owned()))
        })
        .collect()
}

fn get<'a>(attrs: &'a [(String, String)], key: &str) -> Option<&'a str> {
    attrs
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
}

/// Reads the variables and unit definitions of a modelDescription.xml.
pub fn parse(xml: &str) -> Result<Interface, String> {
    let mut reader = Reader::from_str(xml);
    let mut stack: Vec<String> = Vec::new();
    let mut interface = Interface::default();
    // The open <ScalarVariable>'s attributes, until its type element is seen.
    let mut pending: Option<Vec<(String, String)>> = None;
    loop {
        let event = reader.read_event().map_err(|e| {
            format!(
                "modelDescription.xml is not well-formed at byte {}: {e}",
                reader.error_position()
            )
        })?;
        let (e, is_empty) = match event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(_) => {
                if stack.pop().as_deref() == Some("ScalarVariable") {
                    if let Some(attrs) = pending.take() {
                        let name = get(&attrs, "name").unwrap_or("?");
                        return Err(format!("variable {name:?} has no type element"));
                    }
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let name = e.name().as_ref().to_owned();
        let attrs = attributes(&e)?;
        match (stack.last().map(String::as_str), name.as_str()) {
            (Some("ModelVariables"), "ScalarVariable") => {
                if get(&attrs, "name").is_none() {
                    return Err("a <ScalarVariable> has no name".into());
                }
                pending = Some(attrs);
            }
            (
                Some("ScalarVariable"),
                t @ ("Real" | "Integer" | "Boolean" | "String" | "Enumeration"),
            ) => {
                if let Some(sv) = pending.take() {
                    let var_type = match t {
                        "Real" => VarType::Real,
                        "Integer" => VarType::Integer,
                        "Boolean" => VarType::Boolean,
                        "String" => VarType::String,
                        _ => VarType::Enumeration,
                    };
                    interface.variables.push(Variable {
                        name: get(&sv, "name").unwrap_or_default().to_owned(),
                        causality: get(&sv, "causality").unwrap_or("local").to_owned(),
                        var_type,
                        unit: get(&attrs, "unit").map(str::to_owned),
                    });
                }
            }
            (Some("UnitDefinitions"), "Unit") => {
                let unit = get(&attrs, "name").ok_or("a <Unit> has no name")?;
                interface.units.push(UnitDefinition {
                    name: unit.to_owned(),
                    base_unit: Vec::new(),
                });
            }
            (Some("Unit"), "BaseUnit") => {
                if let Some(unit) = interface.units.last_mut() {
                    unit.base_unit = attrs;
                }
            }
            _ => {}
        }
        if !is_empty {
            stack.push(name);
        } else if name == "ScalarVariable" && pending.is_some() {
            return Err(format!(
                "variable {:?} has no type element",
                get(pending.as_deref().unwrap_or_default(), "name").unwrap_or("?")
            ));
        }
    }
    if interface.variables.is_empty() {
        return Err("modelDescription.xml declares no variables".into());
    }
    Ok(interface)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A small description in the shape fmu-runtime writes.
    pub const XML: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="Shaft" guid="{x}">
  <CoSimulation modelIdentifier="Shaft"/>
  <UnitDefinitions>
    <Unit name="N.m"><BaseUnit kg="1" m="2" s="-2"/></Unit>
    <Unit name="rad/s">
      <BaseUnit s="-1" rad="1"/>
    </Unit>
    <Unit name="1"><BaseUnit/></Unit>
  </UnitDefinitions>
  <ModelVariables>
    <ScalarVariable name="K" valueReference="0" causality="parameter" variability="fixed">
      <Real start="900" unit="N.m/rad"/>
    </ScalarVariable>
    <ScalarVariable name="mode" valueReference="1" causality="parameter" variability="fixed"><Integer start="1"/></ScalarVariable>
    <ScalarVariable name="w_in" valueReference="2" causality="input"><Real start="0" unit="rad/s"/></ScalarVariable>
    <ScalarVariable name="T &amp; more" valueReference="3" causality="output"><Real unit="N.m"/></ScalarVariable>
    <ScalarVariable name="x" valueReference="4"><Real/></ScalarVariable>
    <ScalarVariable name="on" valueReference="5" causality="output"><Boolean/></ScalarVariable>
  </ModelVariables>
</fmiModelDescription>"#;

    #[test]
    fn reads_variables_and_units() {
        let i = parse(XML).unwrap();
        let names: Vec<_> = i.variables.iter().map(|v| v.name.as_str()).collect();
        assert_eq!(names, ["K", "mode", "w_in", "T & more", "x", "on"]);
        let w = i.variable("w_in").unwrap();
        assert_eq!(
            (w.causality.as_str(), w.var_type, w.unit.as_deref()),
            ("input", VarType::Real, Some("rad/s"))
        );
        assert_eq!(i.variable("x").unwrap().causality, "local");
        assert_eq!(i.variable("mode").unwrap().var_type, VarType::Integer);
        assert_eq!(i.variable("on").unwrap().var_type, VarType::Boolean);
        assert_eq!(i.names_of("output"), ["T & more", "on"]);
        let units: Vec<_> = i.units.iter().map(|u| u.name.as_str()).collect();
        assert_eq!(units, ["N.m", "rad/s", "1"]);
        assert_eq!(
            i.unit("rad/s").unwrap().base_unit,
            [
                ("s".to_owned(), "-1".to_owned()),
                ("rad".to_owned(), "1".to_owned())
            ]
        );
        assert!(i.unit("1").unwrap().base_unit.is_empty());
    }

    #[test]
    fn rejects_broken_descriptions() {
        assert!(parse(
            "<fmiModelDescription><ModelVariables></ModelVariables></fmiModelDescription>"
        )
        .unwrap_err()
        .contains("no variables"));
        assert!(parse("<fmiModelDescription><ModelVariables><ScalarVariable name=\"a\"></ScalarVariable></ModelVariables></fmiModelDescription>")
            .unwrap_err()
            .contains("\"a\" has no type element"));
        assert!(parse("<fmiModelDescription><ModelVariables><ScalarVariable name=\"a\"/></ModelVariables></fmiModelDescription>")
            .unwrap_err()
            .contains("\"a\" has no type element"));
        assert!(parse("<a><b></a>").unwrap_err().contains("not well-formed"));
    }
}
