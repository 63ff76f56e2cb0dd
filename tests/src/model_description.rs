//! `modelDescription.xml` of an FMI 2.0 FMU: the subset a co-simulation host needs, parsed with
//! quick-xml.
//!
//! Unknown elements and attributes are ignored (vendor annotations, `TypeDefinitions`,
//! `ModelStructure`, ...); what is read is validated (required attributes present, numbers
//! parse, exactly one type element per `ScalarVariable`, unique names).

use std::collections::HashMap;

use quick_xml::events::{BytesStart, Event};
use quick_xml::{Reader, XmlVersion};

use crate::error::{Error, Result};
use crate::ffi::ValueReference;

/// `fmiModelDescription` (the parts this host uses).
#[derive(Clone, Debug, PartialEq)]
pub struct ModelDescription {
    pub fmi_version: String,
    pub model_name: String,
    pub guid: String,
    pub description: Option<String>,
    pub author: Option<String>,
    pub version: Option<String>,
    pub copyright: Option<String>,
    pub license: Option<String>,
    pub generation_tool: Option<String>,
    /// `generationDateAndTime`, as written (an xs:dateTime).
    pub generation_date_and_time: Option<String>,
    pub number_of_event_indicators: Option<u32>,
    pub co_simulation: Option<CoSimulation>,
    /// Only the `modelIdentifier` matters to this host.
    pub model_exchange: Option<ModelExchange>,
    pub default_experiment: Option<DefaultExperiment>,
    /// In document order; the index of a variable is its 1-based position minus one, as
    /// `ModelStructure` counts them.
    pub model_variables: Vec<ScalarVariable>,
    by_name: HashMap<String, usize>,
}

/// `<CoSimulation>`: the model identifier and the capability flags (absent flags are `false`,
/// an absent `maxOutputDerivativeOrder` is 0, as the schema defaults them).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CoSimulation {
    pub model_identifier: String,
    pub needs_execution_tool: bool,
    pub can_handle_variable_communication_step_size: bool,
    pub can_interpolate_inputs: bool,
    pub max_output_derivative_order: u32,
    pub can_run_asynchronuously: bool,
    pub can_be_instantiated_only_once_per_process: bool,
    pub can_not_use_memory_management_functions: bool,
    pub can_get_and_set_fmu_state: bool,
    pub can_serialize_fmu_state: bool,
    pub provides_directional_derivative: bool,
}

/// `<ModelExchange>`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ModelExchange {
    pub model_identifier: String,
}

/// `<DefaultExperiment>`: every attribute is optional.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DefaultExperiment {
    pub start_time: Option<f64>,
    pub stop_time: Option<f64>,
    pub tolerance: Option<f64>,
    pub step_size: Option<f64>,
}

/// The base type of a variable (the element inside `<ScalarVariable>`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VariableType {
    Real,
    Integer,
    Boolean,
    String,
    Enumeration,
}

/// The `start` attribute, typed after the variable type (an `Enumeration` start is an
/// `Integer`).
#[derive(Clone, Debug, PartialEq)]
pub enum StartValue {
    Real(f64),
    Integer(i32),
    Boolean(bool),
    String(String),
}

impl StartValue {
    /// The value as `f64` for Real, Integer and Enumeration starts.
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            StartValue::Real(v) => Some(*v),
            StartValue::Integer(v) => Some(f64::from(*v)),
            _ => None,
        }
    }
}

/// `causality` (default `local`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Causality {
    Parameter,
    CalculatedParameter,
    Input,
    Output,
    #[default]
    Local,
    Independent,
}

/// `variability` (default `continuous`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Variability {
    Constant,
    Fixed,
    Tunable,
    Discrete,
    #[default]
    Continuous,
}

/// `initial` (no default here: `None` means the attribute is absent, the standard then derives
/// it from causality and variability).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Initial {
    Exact,
    Approx,
    Calculated,
}

/// One `<ScalarVariable>`.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalarVariable {
    pub name: String,
    pub value_reference: ValueReference,
    pub description: Option<String>,
    pub causality: Causality,
    pub variability: Variability,
    pub initial: Option<Initial>,
    pub variable_type: VariableType,
    pub declared_type: Option<String>,
    pub start: Option<StartValue>,
    pub unit: Option<String>,
    /// `min` of a Real, Integer or Enumeration variable.
    pub min: Option<f64>,
    /// `max` of a Real, Integer or Enumeration variable.
    pub max: Option<f64>,
    pub nominal: Option<f64>,
    /// `derivative`: 1-based index of the variable this one is the derivative of.
    pub derivative: Option<u32>,
}

impl ModelDescription {
    /// Parses the text of a `modelDescription.xml`.
    pub fn parse(xml: &str) -> Result<ModelDescription> {
        Parser::default().run(xml.strip_prefix('\u{feff}').unwrap_or(xml))
    }

    /// The variable called `name`.
    pub fn variable(&self, name: &str) -> Result<&ScalarVariable> {
        self.by_name
            .get(name)
            .map(|&i| &self.model_variables[i])
            .ok_or_else(|| Error::UnknownVariable(name.to_owned()))
    }
}

fn invalid(msg: impl Into<String>) -> Error {
    Error::ModelDescription(msg.into())
}

/// The attributes of one element, unescaped, as (name, value) pairs.
struct Attributes {
    element: String,
    pairs: Vec<(String, String)>,
}

impl Attributes {
    fn read(e: &BytesStart<'_>, reader_pos: u64) -> Result<Attributes> {
        let element = e.name().as_ref().to_owned();
        let mut pairs = Vec::new();
        for attr in e.attributes() {
            let attr = attr.map_err(|err| Error::Xml {
                position: reader_pos,
                message: err.to_string(),
            })?;
            let key = attr.key.as_ref().to_owned();
            let value = attr
                .normalized_value(XmlVersion::Implicit1_0)
                .map_err(|err| Error::Xml {
                    position: reader_pos,
                    message: err.to_string(),
                })?
                .into_owned();
            pairs.push((key, value));
        }
        Ok(Attributes { element, pairs })
    }

    fn get(&self, key: &str) -> Option<&str> {
        self.pairs
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    fn string(&self, key: &str) -> Option<String> {
        self.get(key).map(str::to_owned)
    }

    fn required(&self, key: &str) -> Result<String> {
        self.string(key)
            .ok_or_else(|| invalid(format!("<{}> has no attribute {key}", self.element)))
    }

    fn parsed<T: std::str::FromStr>(&self, key: &str) -> Result<Option<T>> {
        match self.get(key) {
            None => Ok(None),
            Some(text) => text.trim().parse::<T>().map(Some).map_err(|_| {
                invalid(format!(
                    "<{}> attribute {key}={text:?} is not a valid number",
                    self.element
                ))
            }),
        }
    }

    /// xs:boolean: `true`/`false`/`1`/`0`; absent is `false`.
    fn flag(&self, key: &str) -> Result<bool> {
        match self.get(key).map(str::trim) {
            None | Some("false") | Some("0") => Ok(false),
            Some("true") | Some("1") => Ok(true),
            Some(other) => Err(invalid(format!(
                "<{}> attribute {key}={other:?} is not a boolean",
                self.element
            ))),
        }
    }
}

fn parse_causality(text: &str) -> Result<Causality> {
    Ok(match text {
        "parameter" => Causality::Parameter,
        "calculatedParameter" => Causality::CalculatedParameter,
        "input" => Causality::Input,
        "output" => Causality::Output,
        "local" => Causality::Local,
        "independent" => Causality::Independent,
        other => return Err(invalid(format!("unknown causality {other:?}"))),
    })
}

fn parse_variability(text: &str) -> Result<Variability> {
    Ok(match text {
        "constant" => Variability::Constant,
        "fixed" => Variability::Fixed,
        "tunable" => Variability::Tunable,
        "discrete" => Variability::Discrete,
        "continuous" => Variability::Continuous,
        other => return Err(invalid(format!("unknown variability {other:?}"))),
    })
}

fn parse_initial(text: &str) -> Result<Initial> {
    Ok(match text {
        "exact" => Initial::Exact,
        "approx" => Initial::Approx,
        "calculated" => Initial::Calculated,
        other => return Err(invalid(format!("unknown initial {other:?}"))),
    })
}

/// A `<ScalarVariable>` whose type element has not been seen yet.
struct PendingVariable {
    attrs: Attributes,
    typed: Option<(VariableType, Attributes)>,
}

impl PendingVariable {
    fn finish(self) -> Result<ScalarVariable> {
        let a = &self.attrs;
        let name = a.required("name")?;
        let value_reference = a
            .parsed::<ValueReference>("valueReference")?
            .ok_or_else(|| invalid(format!("variable {name:?} has no valueReference")))?;
        let (variable_type, t) = self
            .typed
            .ok_or_else(|| invalid(format!("variable {name:?} has no type element")))?;
        let start = match t.get("start") {
            None => None,
            Some(text) => Some(match variable_type {
                VariableType::Real => StartValue::Real(t.parsed("start")?.unwrap_or_default()),
                VariableType::Integer | VariableType::Enumeration => {
                    StartValue::Integer(t.parsed("start")?.unwrap_or_default())
                }
                VariableType::Boolean => StartValue::Boolean(t.flag("start")?),
                VariableType::String => StartValue::String(text.to_owned()),
            }),
        };
        let numeric = !matches!(variable_type, VariableType::Boolean | VariableType::String);
        Ok(ScalarVariable {
            value_reference,
            description: a.string("description"),
            causality: a
                .get("causality")
                .map(parse_causality)
                .transpose()?
                .unwrap_or_default(),
            variability: a
                .get("variability")
                .map(parse_variability)
                .transpose()?
                .unwrap_or_default(),
            initial: a.get("initial").map(parse_initial).transpose()?,
            variable_type,
            declared_type: t.string("declaredType"),
            start,
            unit: t.string("unit"),
            min: if numeric { t.parsed("min")? } else { None },
            max: if numeric { t.parsed("max")? } else { None },
            nominal: t.parsed("nominal")?,
            derivative: t.parsed("derivative")?,
            name,
        })
    }
}

#[derive(Default)]
struct Parser {
    /// Names of the open elements, outermost first.
    stack: Vec<String>,
    root: Option<Attributes>,
    co_simulation: Option<CoSimulation>,
    model_exchange: Option<ModelExchange>,
    default_experiment: Option<DefaultExperiment>,
    variables: Vec<ScalarVariable>,
    pending: Option<PendingVariable>,
}

impl Parser {
    fn run(mut self, xml: &str) -> Result<ModelDescription> {
        let mut reader = Reader::from_str(xml);
        loop {
            let position = reader.buffer_position();
            let event = reader.read_event().map_err(|err| Error::Xml {
                position: reader.error_position(),
                message: err.to_string(),
            })?;
            match event {
                Event::Start(e) => {
                    let attrs = Attributes::read(&e, position)?;
                    self.open(attrs)?;
                }
                Event::Empty(e) => {
                    let attrs = Attributes::read(&e, position)?;
                    let name = attrs.element.clone();
                    self.open(attrs)?;
                    self.close(&name)?;
                }
                Event::End(e) => {
                    let name = e.name().as_ref().to_owned();
                    self.close(&name)?;
                }
                Event::Eof => break,
                _ => {}
            }
        }
        self.finish()
    }

    fn parent(&self) -> Option<&str> {
        self.stack.last().map(String::as_str)
    }

    fn open(&mut self, attrs: Attributes) -> Result<()> {
        let element = attrs.element.clone();
        let parent = self.parent().map(str::to_owned);
        match (parent.as_deref(), element.as_str()) {
            (None, "fmiModelDescription") => self.root = Some(attrs),
            (None, other) => {
                return Err(invalid(format!(
                    "root element is <{other}>, not <fmiModelDescription>"
                )))
            }
            (Some("fmiModelDescription"), "CoSimulation") => {
                self.co_simulation = Some(CoSimulation {
                    model_identifier: attrs.required("modelIdentifier")?,
                    needs_execution_tool: attrs.flag("needsExecutionTool")?,
                    can_handle_variable_communication_step_size: attrs
                        .flag("canHandleVariableCommunicationStepSize")?,
                    can_interpolate_inputs: attrs.flag("canInterpolateInputs")?,
                    max_output_derivative_order: attrs
                        .parsed("maxOutputDerivativeOrder")?
                        .unwrap_or(0),
                    can_run_asynchronuously: attrs.flag("canRunAsynchronuously")?,
                    can_be_instantiated_only_once_per_process: attrs
                        .flag("canBeInstantiatedOnlyOncePerProcess")?,
                    can_not_use_memory_management_functions: attrs
                        .flag("canNotUseMemoryManagementFunctions")?,
                    can_get_and_set_fmu_state: attrs.flag("canGetAndSetFMUstate")?,
                    can_serialize_fmu_state: attrs.flag("canSerializeFMUstate")?,
                    provides_directional_derivative: attrs.flag("providesDirectionalDerivative")?,
                });
            }
            (Some("fmiModelDescription"), "ModelExchange") => {
                self.model_exchange = Some(ModelExchange {
                    model_identifier: attrs.required("modelIdentifier")?,
                });
            }
            (Some("fmiModelDescription"), "DefaultExperiment") => {
                self.default_experiment = Some(DefaultExperiment {
                    start_time: attrs.parsed("startTime")?,
                    stop_time: attrs.parsed("stopTime")?,
                    tolerance: attrs.parsed("tolerance")?,
                    step_size: attrs.parsed("stepSize")?,
                });
            }
            (Some("ModelVariables"), "ScalarVariable") => {
                self.pending = Some(PendingVariable { attrs, typed: None });
            }
            (
                Some("ScalarVariable"),
                kind @ ("Real" | "Integer" | "Boolean" | "String" | "Enumeration"),
            ) => {
                let variable_type = match kind {
                    "Real" => VariableType::Real,
                    "Integer" => VariableType::Integer,
                    "Boolean" => VariableType::Boolean,
                    "String" => VariableType::String,
                    _ => VariableType::Enumeration,
                };
                // Only a ScalarVariable directly under ModelVariables is pending; a type element
                // elsewhere (there is none in the schema) is ignored.
                if let Some(pending) = self.pending.as_mut() {
                    if pending.typed.is_some() {
                        return Err(invalid("a <ScalarVariable> has more than one type element"));
                    }
                    pending.typed = Some((variable_type, attrs));
                }
            }
            _ => {}
        }
        self.stack.push(element);
        Ok(())
    }

    fn close(&mut self, name: &str) -> Result<()> {
        // quick-xml already checks that end tags match start tags.
        self.stack.pop();
        if name == "ScalarVariable" && self.parent() == Some("ModelVariables") {
            if let Some(pending) = self.pending.take() {
                self.variables.push(pending.finish()?);
            }
        }
        Ok(())
    }

    fn finish(self) -> Result<ModelDescription> {
        if !self.stack.is_empty() {
            return Err(invalid(format!(
                "unexpected end of document inside <{}>",
                self.stack.join("><")
            )));
        }
        let root = self
            .root
            .ok_or_else(|| invalid("no <fmiModelDescription> element"))?;
        let fmi_version = root.required("fmiVersion")?;
        if !fmi_version.starts_with("2.") {
            return Err(invalid(format!(
                "fmiVersion {fmi_version:?} is not FMI 2.0"
            )));
        }
        let mut by_name = HashMap::with_capacity(self.variables.len());
        for (i, v) in self.variables.iter().enumerate() {
            if by_name.insert(v.name.clone(), i).is_some() {
                return Err(invalid(format!("two variables are named {:?}", v.name)));
            }
        }
        Ok(ModelDescription {
            model_name: root.required("modelName")?,
            guid: root.required("guid")?,
            description: root.string("description"),
            author: root.string("author"),
            version: root.string("version"),
            copyright: root.string("copyright"),
            license: root.string("license"),
            generation_tool: root.string("generationTool"),
            generation_date_and_time: root.string("generationDateAndTime"),
            number_of_event_indicators: root.parsed("numberOfEventIndicators")?,
            fmi_version,
            co_simulation: self.co_simulation,
            model_exchange: self.model_exchange,
            default_experiment: self.default_experiment,
            model_variables: self.variables,
            by_name,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const XML: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="Demo" guid="{01234567-89ab-cdef-0123-456789abcdef}"
    description="A &lt;demo&gt; model" generationTool="hand" numberOfEventIndicators="0">
  <CoSimulation modelIdentifier="Demo" canHandleVariableCommunicationStepSize="true"
      canGetAndSetFMUstate="true" canSerializeFMUstate="1" canNotUseMemoryManagementFunctions="true"
      maxOutputDerivativeOrder="0" canInterpolateInputs="false">
    <SourceFiles><File name="ignored.c"/></SourceFiles>
  </CoSimulation>
  <UnitDefinitions><Unit name="V"><BaseUnit kg="1" m="2" s="-3" A="-1"/></Unit></UnitDefinitions>
  <TypeDefinitions>
    <SimpleType name="Voltage"><Real quantity="ElectricPotential" unit="V"/></SimpleType>
  </TypeDefinitions>
  <DefaultExperiment startTime="0" stopTime="0.1" stepSize="1e-4"/>
  <ModelVariables>
    <ScalarVariable name="R" valueReference="0" causality="parameter" variability="fixed"
        initial="exact" description="resistance">
      <Real unit="Ohm" start="1" min="1e-9" max="1e9"/>
    </ScalarVariable>
    <ScalarVariable name="u" valueReference="1" causality="input">
      <Real declaredType="Voltage" start="0"/>
    </ScalarVariable>
    <ScalarVariable name="x" valueReference="2" initial="exact"><Real start="-2.5"/></ScalarVariable>
    <ScalarVariable name="der(x)" valueReference="3"><Real derivative="3"/></ScalarVariable>
    <ScalarVariable name="n" valueReference="0" causality="output" variability="discrete">
      <Integer min="-3" max="7"/>
      <Annotations><Tool name="t"><Real start="99"/></Tool></Annotations>
    </ScalarVariable>
    <ScalarVariable name="on" valueReference="0" causality="parameter" variability="tunable">
      <Boolean start="true"/>
    </ScalarVariable>
    <ScalarVariable name="label" valueReference="0" causality="parameter" variability="fixed">
      <String start="a &amp; b"/>
    </ScalarVariable>
    <ScalarVariable name="mode" valueReference="1" causality="parameter" variability="fixed">
      <Enumeration declaredType="Modes" start="2" min="1" max="3"/>
    </ScalarVariable>
  </ModelVariables>
  <ModelStructure><Outputs><Unknown index="5"/></Outputs></ModelStructure>
</fmiModelDescription>"#;

    #[test]
    fn parses_header_capabilities_and_experiment() {
        let md = ModelDescription::parse(XML).unwrap();
        assert_eq!(md.fmi_version, "2.0");
        assert_eq!(md.model_name, "Demo");
        assert_eq!(md.guid, "{01234567-89ab-cdef-0123-456789abcdef}");
        assert_eq!(md.description.as_deref(), Some("A <demo> model"));
        assert_eq!(md.number_of_event_indicators, Some(0));
        let cs = md.co_simulation.as_ref().unwrap();
        assert_eq!(cs.model_identifier, "Demo");
        assert!(cs.can_handle_variable_communication_step_size);
        assert!(cs.can_get_and_set_fmu_state);
        assert!(cs.can_serialize_fmu_state);
        assert!(cs.can_not_use_memory_management_functions);
        assert!(!cs.can_interpolate_inputs);
        assert!(!cs.provides_directional_derivative);
        assert_eq!(cs.max_output_derivative_order, 0);
        assert!(md.model_exchange.is_none());
        let de = md.default_experiment.unwrap();
        assert_eq!(de.start_time, Some(0.0));
        assert_eq!(de.stop_time, Some(0.1));
        assert_eq!(de.step_size, Some(1e-4));
        assert_eq!(de.tolerance, None);
    }

    #[test]
    fn parses_every_variable_kind() {
        let md = ModelDescription::parse(XML).unwrap();
        assert_eq!(md.model_variables.len(), 8);

        let r = md.variable("R").unwrap();
        assert_eq!(r.value_reference, 0);
        assert_eq!(r.causality, Causality::Parameter);
        assert_eq!(r.variability, Variability::Fixed);
        assert_eq!(r.initial, Some(Initial::Exact));
        assert_eq!(r.variable_type, VariableType::Real);
        assert_eq!(r.start, Some(StartValue::Real(1.0)));
        assert_eq!(r.unit.as_deref(), Some("Ohm"));
        assert_eq!((r.min, r.max), (Some(1e-9), Some(1e9)));
        assert_eq!(r.description.as_deref(), Some("resistance"));

        let u = md.variable("u").unwrap();
        assert_eq!(u.causality, Causality::Input);
        assert_eq!(
            u.variability,
            Variability::Continuous,
            "default variability"
        );
        assert_eq!(u.initial, None);
        assert_eq!(u.declared_type.as_deref(), Some("Voltage"));
        assert_eq!(u.unit, None, "the unit of a declared type is not copied");

        let x = md.variable("x").unwrap();
        assert_eq!(x.causality, Causality::Local, "default causality");
        assert_eq!(x.start, Some(StartValue::Real(-2.5)));
        assert_eq!(md.variable("der(x)").unwrap().derivative, Some(3));

        let n = md.variable("n").unwrap();
        assert_eq!(n.variable_type, VariableType::Integer);
        assert_eq!((n.min, n.max), (Some(-3.0), Some(7.0)));
        assert_eq!(
            n.start, None,
            "a <Real> inside <Annotations> is not the type element"
        );

        assert_eq!(
            md.variable("on").unwrap().start,
            Some(StartValue::Boolean(true))
        );
        assert_eq!(
            md.variable("label").unwrap().start,
            Some(StartValue::String("a & b".into()))
        );
        let mode = md.variable("mode").unwrap();
        assert_eq!(mode.variable_type, VariableType::Enumeration);
        assert_eq!(mode.start, Some(StartValue::Integer(2)));
        assert_eq!(mode.start.as_ref().unwrap().as_f64(), Some(2.0));
    }

    #[test]
    fn unknown_variable_is_an_error() {
        let md = ModelDescription::parse(XML).unwrap();
        assert!(matches!(md.variable("nope"), Err(Error::UnknownVariable(n)) if n == "nope"));
    }

    #[test]
    fn malformed_xml_is_an_error() {
        let broken = XML.replace("</ModelVariables>", "</ModelVariablez>");
        assert!(matches!(
            ModelDescription::parse(&broken),
            Err(Error::Xml { .. })
        ));
        assert!(matches!(
            ModelDescription::parse("<fmiModelDescription"),
            Err(Error::Xml { .. })
        ));
        assert!(ModelDescription::parse("").is_err());
    }

    #[test]
    fn invalid_content_is_an_error() {
        let cases = [
            XML.replace(r#"valueReference="2""#, r#"valueReference="two""#),
            XML.replace(r#"guid="{01234567-89ab-cdef-0123-456789abcdef}""#, ""),
            XML.replace(r#"fmiVersion="2.0""#, r#"fmiVersion="3.0""#),
            XML.replace(r#"name="x""#, r#"name="R""#),
            XML.replace(r#"<Real start="-2.5"/>"#, ""),
            XML.replace(r#"<Real start="-2.5"/>"#, r#"<Real start="-2.5"/><Real/>"#),
            XML.replace(r#"causality="input""#, r#"causality="sideways""#),
            XML.replace(
                r#"canSerializeFMUstate="1""#,
                r#"canSerializeFMUstate="yes""#,
            ),
            XML.replace(r#"start="-2.5""#, r#"start="minus two""#),
            XML.replace("fmiModelDescription", "somethingElse"),
        ];
        for (i, xml) in cases.iter().enumerate() {
            match ModelDescription::parse(xml) {
                Err(Error::ModelDescription(_)) => {}
                other => panic!("case {i}: expected a ModelDescription error, got {other:?}"),
            }
        }
    }
}
