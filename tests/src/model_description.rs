//! `modelDescription.xml` of an FMI 2.0 or FMI 3.0 FMU: the subset a co-simulation host needs,
//! parsed with quick-xml.
//!
//! FMI 2.0 declares a variable as `<ScalarVariable ...><Real .../></ScalarVariable>`, FMI 3.0
//! as one typed element (`<Float64 .../>`, `<Int32/>`, `<Boolean/>`, `<String><Start/></String>`,
//! `<Enumeration/>`); both become a [`ScalarVariable`] with the FMI 2.0 names of the base types
//! (Float64 is `Real`, Int32 is `Integer`). FMI 3.0's other types (Float32, the 8-, 16- and
//! 64-bit and unsigned integers, Binary, Clock) and array variables (`<Dimension>`) are refused
//! with [`Error::ModelDescription`]: this host has no methods for them. The `ModelStructure` of
//! both versions is read into value references ([`ModelStructure`]).
//!
//! Unknown elements and attributes are ignored (vendor annotations, `TypeDefinitions`, ...);
//! what is read is validated (required attributes present, numbers parse, exactly one type
//! element per `ScalarVariable`, unique names).
//!
//! This is the workspace's one reader of the descriptions the runtime writes: build-fmus reads
//! the built libraries' descriptions with it too (a system's variables and `UnitDefinitions`,
//! checked and written into the SSP files).

use std::collections::HashMap;

use quick_xml::events::{BytesStart, Event};
use quick_xml::{Reader, XmlVersion};

use crate::error::{Error, Result};
use crate::ffi::{FmiVersion, ValueReference};

/// `fmiModelDescription` (the parts this host uses).
#[derive(Clone, Debug, PartialEq)]
pub struct ModelDescription {
    pub fmi_version: String,
    pub model_name: String,
    /// FMI 2.0's `guid`, or FMI 3.0's `instantiationToken` (what instantiation is given).
    pub guid: String,
    pub description: Option<String>,
    pub author: Option<String>,
    pub version: Option<String>,
    pub copyright: Option<String>,
    pub license: Option<String>,
    pub generation_tool: Option<String>,
    /// `generationDateAndTime`, as written (an xs:dateTime).
    pub generation_date_and_time: Option<String>,
    /// FMI 2.0's `numberOfEventIndicators`; for FMI 3.0 the number of `<EventIndicator>`s of
    /// the ModelStructure.
    pub number_of_event_indicators: Option<u32>,
    pub co_simulation: Option<CoSimulation>,
    /// Only the `modelIdentifier` matters to this host.
    pub model_exchange: Option<ModelExchange>,
    pub default_experiment: Option<DefaultExperiment>,
    /// In document order; the index of a variable is its 1-based position minus one, as
    /// FMI 2.0's `ModelStructure` counts them. FMI 3.0 descriptions also list their independent
    /// variable (`time`) here.
    pub model_variables: Vec<ScalarVariable>,
    /// The outputs, state derivatives, initial unknowns and (FMI 3.0) event indicators.
    pub model_structure: ModelStructure,
    /// `<UnitDefinitions>`, in document order.
    pub unit_definitions: Vec<UnitDefinition>,
    /// The enumeration types of `<TypeDefinitions>` (FMI 2.0 `<SimpleType>` with an
    /// `<Enumeration>`, FMI 3.0 `<EnumerationType>`), in document order.
    pub enumeration_types: Vec<EnumerationType>,
    by_name: HashMap<String, usize>,
}

/// An enumeration type: its name and its items (name, value), in document order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EnumerationType {
    pub name: String,
    pub items: Vec<(String, i64)>,
}

/// One `<Unit>` of `<UnitDefinitions>`: its name and the attributes of its `<BaseUnit>`
/// (kg, m, s, A, K, mol, cd, rad, factor, offset) as written, in their order (empty without a
/// `<BaseUnit>`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnitDefinition {
    pub name: String,
    pub base_unit: Vec<(String, String)>,
}

/// One unknown of the `ModelStructure`, in value references (FMI 2.0's indices are turned into
/// the value references of the variables they count).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Unknown {
    pub value_reference: ValueReference,
    /// `None`: the attribute is absent (depends on every known); `Some(empty)`: on none.
    pub dependencies: Option<Vec<ValueReference>>,
}

/// `<ModelStructure>`: FMI 2.0's `<Outputs>`, `<Derivatives>`, `<InitialUnknowns>` (of
/// `<Unknown index=...>`), FMI 3.0's `<Output>`, `<ContinuousStateDerivative>`,
/// `<InitialUnknown>` and `<EventIndicator>` (of `valueReference`s).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ModelStructure {
    pub outputs: Vec<Unknown>,
    pub continuous_state_derivatives: Vec<Unknown>,
    pub initial_unknowns: Vec<Unknown>,
    /// FMI 3.0 only (FMI 2.0 only counts them: `numberOfEventIndicators`).
    pub event_indicators: Vec<Unknown>,
}

impl ModelStructure {
    /// Whether output `output` depends directly on the variable `known` (value references).
    /// An output the structure does not list, or lists without `dependencies`, is taken to
    /// depend on everything (the safe answer); so is one whose value reference FMI 2.0 gives
    /// to outputs of two types and one of them does.
    pub fn output_depends_on(&self, output: ValueReference, known: ValueReference) -> bool {
        let mut listed = false;
        for unknown in self.outputs.iter().filter(|u| u.value_reference == output) {
            listed = true;
            match &unknown.dependencies {
                Some(list) if !list.contains(&known) => {}
                _ => return true,
            }
        }
        !listed
    }
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
    /// FMI 2.0's `providesDirectionalDerivative`, FMI 3.0's `providesDirectionalDerivatives`.
    pub provides_directional_derivative: bool,
    /// FMI 3.0's `providesAdjointDerivatives` (false for FMI 2.0).
    pub provides_adjoint_derivatives: bool,
    /// FMI 3.0's `hasEventMode` (false for FMI 2.0).
    pub has_event_mode: bool,
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

impl VariableType {
    /// The element name, as FMI 2.0 and SSP 1.0 (`ssc:`/`ssv:`) both spell it.
    pub fn name(self) -> &'static str {
        match self {
            VariableType::Real => "Real",
            VariableType::Integer => "Integer",
            VariableType::Boolean => "Boolean",
            VariableType::String => "String",
            VariableType::Enumeration => "Enumeration",
        }
    }
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

impl Causality {
    /// The attribute value, as the standard spells it.
    pub fn name(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::CalculatedParameter => "calculatedParameter",
            Causality::Input => "input",
            Causality::Output => "output",
            Causality::Local => "local",
            Causality::Independent => "independent",
        }
    }
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
    /// `derivative`: 1-based index of the variable this one is the derivative of (FMI 3.0's
    /// attribute, a value reference, is turned into that index).
    pub derivative: Option<u32>,
}

impl ModelDescription {
    /// Parses the text of a `modelDescription.xml`.
    pub fn parse(xml: &str) -> Result<ModelDescription> {
        Parser::default().run(xml.strip_prefix('\u{feff}').unwrap_or(xml))
    }

    /// FMI 2.0 or FMI 3.0 (the parser accepts no other `fmiVersion`).
    pub fn version(&self) -> FmiVersion {
        FmiVersion::of(&self.fmi_version).expect("checked by the parser")
    }

    /// The variable called `name`.
    pub fn variable(&self, name: &str) -> Result<&ScalarVariable> {
        self.by_name
            .get(name)
            .map(|&i| &self.model_variables[i])
            .ok_or_else(|| Error::UnknownVariable(name.to_owned()))
    }

    /// The names of the variables of one causality, in declaration order.
    pub fn names_of(&self, causality: Causality) -> Vec<&str> {
        self.model_variables
            .iter()
            .filter(|v| v.causality == causality)
            .map(|v| v.name.as_str())
            .collect()
    }

    /// The items (name, value) of an Enumeration variable's declared type; None for another
    /// variable or a type the description does not define.
    pub fn items_of(&self, variable: &ScalarVariable) -> Option<&[(String, i64)]> {
        let declared = variable.declared_type.as_deref().filter(|_| variable.variable_type == VariableType::Enumeration)?;
        self.enumeration_types.iter().find(|t| t.name == declared).map(|t| t.items.as_slice())
    }

    /// The `<Unit>` called `name`.
    pub fn unit(&self, name: &str) -> Option<&UnitDefinition> {
        self.unit_definitions.iter().find(|u| u.name == name)
    }
}

fn invalid(msg: impl Into<String>) -> Error {
    Error::ModelDescription(msg.into())
}

/// The attributes of one element, unescaped, as (name, value) pairs.
#[derive(Clone)]
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

/// The FMI 3.0 variable elements and the base type this host reads them as.
fn fmi3_variable_type(element: &str) -> Option<VariableType> {
    Some(match element {
        "Float64" => VariableType::Real,
        "Int32" => VariableType::Integer,
        "Boolean" => VariableType::Boolean,
        "String" => VariableType::String,
        "Enumeration" => VariableType::Enumeration,
        _ => return None,
    })
}

/// FMI 3.0 variable elements this host cannot read or write.
const FMI3_UNSUPPORTED_TYPES: [&str; 10] =
    ["Float32", "Int8", "UInt8", "Int16", "UInt16", "UInt32", "Int64", "UInt64", "Binary", "Clock"];

/// The ModelStructure lists, while parsing: (list, value reference or FMI 2.0 index, dependencies
/// as written).
type RawUnknown = (&'static str, u64, Option<Vec<u64>>);

#[derive(Default)]
struct Parser {
    /// Names of the open elements, outermost first.
    stack: Vec<String>,
    root: Option<Attributes>,
    version: Option<FmiVersion>,
    unknowns: Vec<RawUnknown>,
    co_simulation: Option<CoSimulation>,
    model_exchange: Option<ModelExchange>,
    default_experiment: Option<DefaultExperiment>,
    variables: Vec<ScalarVariable>,
    pending: Option<PendingVariable>,
    units: Vec<UnitDefinition>,
    enumeration_types: Vec<EnumerationType>,
    /// The name of the `<SimpleType>` being read (FMI 2.0).
    simple_type: Option<String>,
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
            (None, "fmiModelDescription") => {
                let text = attrs.required("fmiVersion")?;
                self.version = Some(FmiVersion::of(&text).ok_or_else(|| {
                    invalid(format!("fmiVersion {text:?} is neither FMI 2.0 nor FMI 3.0"))
                })?);
                self.root = Some(attrs);
            }
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
                    // FMI 3.0 spells these FMUState and Derivatives.
                    can_get_and_set_fmu_state: attrs.flag("canGetAndSetFMUstate")?
                        || attrs.flag("canGetAndSetFMUState")?,
                    can_serialize_fmu_state: attrs.flag("canSerializeFMUstate")?
                        || attrs.flag("canSerializeFMUState")?,
                    provides_directional_derivative: attrs.flag("providesDirectionalDerivative")?
                        || attrs.flag("providesDirectionalDerivatives")?,
                    provides_adjoint_derivatives: attrs.flag("providesAdjointDerivatives")?,
                    has_event_mode: attrs.flag("hasEventMode")?,
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
            (Some("UnitDefinitions"), "Unit") => {
                self.units.push(UnitDefinition { name: attrs.required("name")?, base_unit: Vec::new() });
            }
            // FMI 2.0: <SimpleType name><Enumeration><Item/>; FMI 3.0: <EnumerationType name><Item/>.
            (Some("SimpleType"), "Enumeration") if self.version == Some(FmiVersion::Fmi2) => {
                let name = self.simple_type.clone().unwrap_or_default();
                self.enumeration_types.push(EnumerationType { name, items: Vec::new() });
            }
            (Some("TypeDefinitions"), "SimpleType") => {
                self.simple_type = attrs.get("name").map(str::to_owned);
            }
            (Some("TypeDefinitions"), "EnumerationType") if self.version == Some(FmiVersion::Fmi3) => {
                self.enumeration_types.push(EnumerationType { name: attrs.required("name")?, items: Vec::new() });
            }
            (Some("Enumeration" | "EnumerationType"), "Item") => {
                let item = (attrs.required("name")?, attrs.parsed("value")?.ok_or_else(|| invalid("an enumeration <Item> has no value"))?);
                if let Some(t) = self.enumeration_types.last_mut() {
                    t.items.push(item);
                }
            }
            (Some("Unit"), "BaseUnit") => {
                if let Some(unit) = self.units.last_mut() {
                    unit.base_unit = attrs.pairs.clone();
                }
            }
            (Some("ModelVariables"), "ScalarVariable") if self.version == Some(FmiVersion::Fmi2) => {
                self.pending = Some(PendingVariable { attrs, typed: None });
            }
            (Some("ModelVariables"), kind) if self.version == Some(FmiVersion::Fmi3) => {
                if let Some(variable_type) = fmi3_variable_type(kind) {
                    self.pending = Some(PendingVariable { typed: Some((variable_type, attrs.clone())), attrs });
                } else if FMI3_UNSUPPORTED_TYPES.contains(&kind) {
                    return Err(invalid(format!(
                        "variable {:?} is a {kind}: this host reads Float64, Int32, Boolean, String and Enumeration variables only",
                        attrs.get("name").unwrap_or("?")
                    )));
                }
            }
            (Some("String"), "Start") if self.version == Some(FmiVersion::Fmi3) => {
                // FMI 3.0 gives a String's start value as a child element.
                if let Some((_, typed)) = self.pending.as_mut().and_then(|p| p.typed.as_mut()) {
                    let value = attrs.required("value")?;
                    typed.pairs.retain(|(k, _)| k != "start");
                    typed.pairs.push(("start".into(), value));
                }
            }
            (Some(parent), "Dimension") if self.version == Some(FmiVersion::Fmi3) && self.pending.is_some() => {
                return Err(invalid(format!("variable {:?} of <{parent}> is an array: this host reads scalar variables only",
                    self.pending.as_ref().and_then(|p| p.attrs.get("name")).unwrap_or("?"))));
            }
            (Some("ModelStructure"), list @ ("Output" | "ContinuousStateDerivative" | "InitialUnknown" | "EventIndicator"))
                if self.version == Some(FmiVersion::Fmi3) =>
            {
                let list: &'static str = match list {
                    "Output" => "Outputs",
                    "ContinuousStateDerivative" => "Derivatives",
                    "InitialUnknown" => "InitialUnknowns",
                    _ => "EventIndicators",
                };
                self.unknowns.push(Self::unknown(list, &attrs, "valueReference")?);
            }
            (Some(list @ ("Outputs" | "Derivatives" | "InitialUnknowns")), "Unknown")
                if self.version == Some(FmiVersion::Fmi2) && self.stack.iter().rev().nth(1).map(String::as_str) == Some("ModelStructure") =>
            {
                let list: &'static str = match list {
                    "Outputs" => "Outputs",
                    "Derivatives" => "Derivatives",
                    _ => "InitialUnknowns",
                };
                self.unknowns.push(Self::unknown(list, &attrs, "index")?);
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

    /// One ModelStructure entry: its value reference (FMI 3.0) or index (FMI 2.0) and its
    /// dependencies as written.
    fn unknown(list: &'static str, attrs: &Attributes, key: &str) -> Result<RawUnknown> {
        let at = attrs.parsed::<u64>(key)?.ok_or_else(|| invalid(format!("<{}> has no attribute {key}", attrs.element)))?;
        let dependencies = match attrs.get("dependencies") {
            None => None,
            Some(text) => Some(
                text.split_whitespace()
                    .map(|d| d.parse::<u64>().map_err(|_| invalid(format!("<{}> dependency {d:?} is not a number", attrs.element))))
                    .collect::<Result<Vec<u64>>>()?,
            ),
        };
        Ok((list, at, dependencies))
    }

    fn close(&mut self, name: &str) -> Result<()> {
        // quick-xml already checks that end tags match start tags.
        self.stack.pop();
        let variable_element = match self.version {
            Some(FmiVersion::Fmi3) => fmi3_variable_type(name).is_some(),
            _ => name == "ScalarVariable",
        };
        if variable_element && self.parent() == Some("ModelVariables") {
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
        let version = self.version.expect("set with the root");
        let mut variables = self.variables;
        let mut by_name = HashMap::with_capacity(variables.len());
        for (i, v) in variables.iter().enumerate() {
            if by_name.insert(v.name.clone(), i).is_some() {
                return Err(invalid(format!("two variables are named {:?}", v.name)));
            }
        }
        // What a ModelStructure number names: FMI 2.0 a 1-based index, FMI 3.0 a value reference.
        let vr_of = |n: u64| -> Result<ValueReference> {
            match version {
                FmiVersion::Fmi2 => n
                    .checked_sub(1)
                    .and_then(|i| variables.get(i as usize))
                    .map(|v| v.value_reference)
                    .ok_or_else(|| invalid(format!("ModelStructure index {n} is not a variable (1..={})", variables.len()))),
                FmiVersion::Fmi3 => ValueReference::try_from(n)
                    .ok()
                    .filter(|vr| variables.iter().any(|v| v.value_reference == *vr))
                    .ok_or_else(|| invalid(format!("ModelStructure value reference {n} is not a variable's"))),
            }
        };
        let mut model_structure = ModelStructure::default();
        for (list, at, dependencies) in &self.unknowns {
            let unknown = Unknown {
                value_reference: vr_of(*at)?,
                dependencies: dependencies.as_ref().map(|d| d.iter().map(|n| vr_of(*n)).collect::<Result<Vec<_>>>()).transpose()?,
            };
            match *list {
                "Outputs" => model_structure.outputs.push(unknown),
                "Derivatives" => model_structure.continuous_state_derivatives.push(unknown),
                "InitialUnknowns" => model_structure.initial_unknowns.push(unknown),
                _ => model_structure.event_indicators.push(unknown),
            }
        }
        let (guid, number_of_event_indicators) = match version {
            FmiVersion::Fmi2 => (root.required("guid")?, root.parsed("numberOfEventIndicators")?),
            FmiVersion::Fmi3 => {
                // FMI 3.0's `derivative` is the state's value reference: keep FMI 2.0's meaning
                // (its 1-based index) in `ScalarVariable::derivative`.
                let index_of: HashMap<ValueReference, usize> =
                    variables.iter().enumerate().map(|(i, v)| (v.value_reference, i)).collect();
                for v in variables.iter_mut() {
                    if let Some(state) = v.derivative {
                        let i = index_of.get(&state).ok_or_else(|| {
                            invalid(format!("{:?} is the derivative of value reference {state}, which no variable has", v.name))
                        })?;
                        v.derivative = Some(*i as u32 + 1);
                    }
                }
                (root.required("instantiationToken")?, Some(model_structure.event_indicators.len() as u32))
            }
        };
        Ok(ModelDescription {
            model_name: root.required("modelName")?,
            guid,
            description: root.string("description"),
            author: root.string("author"),
            version: root.string("version"),
            copyright: root.string("copyright"),
            license: root.string("license"),
            generation_tool: root.string("generationTool"),
            generation_date_and_time: root.string("generationDateAndTime"),
            number_of_event_indicators,
            fmi_version,
            co_simulation: self.co_simulation,
            model_exchange: self.model_exchange,
            default_experiment: self.default_experiment,
            model_variables: variables,
            model_structure,
            unit_definitions: self.units,
            enumeration_types: self.enumeration_types,
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

    const XML3: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" modelName="Demo3" instantiationToken="{token-3}" numberOfEventIndicators="99">
  <ModelExchange modelIdentifier="Demo3" canGetAndSetFMUState="true"/>
  <CoSimulation modelIdentifier="Demo3" canGetAndSetFMUState="true" canSerializeFMUState="true"
      providesDirectionalDerivatives="true" providesAdjointDerivatives="true" hasEventMode="false"
      maxOutputDerivativeOrder="1"/>
  <UnitDefinitions><Unit name="V"><BaseUnit kg="1" m="2" s="-3" A="-1"/></Unit></UnitDefinitions>
  <TypeDefinitions><Float64Type name="Voltage" unit="V"/></TypeDefinitions>
  <DefaultExperiment startTime="0" stopTime="1" stepSize="0.01"/>
  <ModelVariables>
    <Float64 name="time" valueReference="7" causality="independent" variability="continuous"/>
    <Float64 name="x" valueReference="0" initial="exact" start="-2.5" nominal="2"/>
    <Float64 name="der(x)" valueReference="1" derivative="0"/>
    <Float64 name="u" valueReference="2" causality="input" declaredType="Voltage" start="0"/>
    <Int32 name="n" valueReference="3" causality="output" variability="discrete" min="-3" max="7"/>
    <Boolean name="on" valueReference="4" causality="parameter" variability="tunable" start="true"/>
    <String name="label" valueReference="5" causality="parameter" variability="fixed"><Start value="a &amp; b"/></String>
    <Float64 name="event_indicator.z" valueReference="6" initial="calculated"/>
  </ModelVariables>
  <ModelStructure>
    <Output valueReference="3" dependencies="0 2"/>
    <ContinuousStateDerivative valueReference="1"/>
    <InitialUnknown valueReference="3" dependencies=""/>
    <EventIndicator valueReference="6"/>
  </ModelStructure>
</fmiModelDescription>"#;

    #[test]
    fn parses_an_fmi3_description() {
        let md = ModelDescription::parse(XML3).unwrap();
        assert_eq!(md.version(), FmiVersion::Fmi3);
        assert_eq!(md.guid, "{token-3}", "the instantiationToken");
        assert_eq!(md.number_of_event_indicators, Some(1), "counted from the ModelStructure, not the (FMI 2.0) attribute");
        let cs = md.co_simulation.as_ref().unwrap();
        assert!(cs.can_get_and_set_fmu_state && cs.can_serialize_fmu_state && cs.provides_directional_derivative && cs.provides_adjoint_derivatives);
        assert!(!cs.has_event_mode);
        assert_eq!(cs.max_output_derivative_order, 1);
        assert_eq!(md.model_exchange.as_ref().unwrap().model_identifier, "Demo3");
        assert_eq!(md.model_variables.len(), 8);
        let time = md.variable("time").unwrap();
        assert_eq!((time.causality, time.variable_type, time.value_reference), (Causality::Independent, VariableType::Real, 7));
        let x = md.variable("x").unwrap();
        assert_eq!((x.start.clone(), x.nominal, x.initial), (Some(StartValue::Real(-2.5)), Some(2.0), Some(Initial::Exact)));
        // FMI 3.0's derivative="0" names x by value reference; the host keeps FMI 2.0's 1-based index.
        assert_eq!(md.variable("der(x)").unwrap().derivative, Some(2));
        assert_eq!(md.variable("u").unwrap().declared_type.as_deref(), Some("Voltage"));
        let n = md.variable("n").unwrap();
        assert_eq!((n.variable_type, n.min, n.max, n.variability), (VariableType::Integer, Some(-3.0), Some(7.0), Variability::Discrete));
        assert_eq!(md.variable("on").unwrap().start, Some(StartValue::Boolean(true)));
        assert_eq!(md.variable("label").unwrap().start, Some(StartValue::String("a & b".into())));
        let ms = &md.model_structure;
        assert_eq!(ms.outputs, vec![Unknown { value_reference: 3, dependencies: Some(vec![0, 2]) }]);
        assert_eq!(ms.continuous_state_derivatives, vec![Unknown { value_reference: 1, dependencies: None }]);
        assert_eq!(ms.initial_unknowns, vec![Unknown { value_reference: 3, dependencies: Some(vec![]) }]);
        assert_eq!(ms.event_indicators, vec![Unknown { value_reference: 6, dependencies: None }]);
    }

    #[test]
    fn reads_the_unit_definitions_of_both_versions() {
        let base = |pairs: &[(&str, &str)]| pairs.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect::<Vec<_>>();
        for xml in [XML, XML3] {
            let md = ModelDescription::parse(xml).unwrap();
            assert_eq!(md.unit_definitions, vec![UnitDefinition { name: "V".into(), base_unit: base(&[("kg", "1"), ("m", "2"), ("s", "-3"), ("A", "-1")]) }]);
            assert_eq!(md.unit("V"), md.unit_definitions.first());
            assert!(md.unit("Ohm").is_none());
        }
    }

    #[test]
    fn reads_enumeration_items_of_both_versions() {
        let fmi2 = r#"<fmiModelDescription fmiVersion="2.0" modelName="m" guid="{g}">
  <TypeDefinitions>
    <SimpleType name="level"><Enumeration><Item name="a" value="1" description="quasi-static"/><Item name="b" value="2"/></Enumeration></SimpleType>
  </TypeDefinitions>
  <ModelVariables>
    <ScalarVariable name="level" valueReference="0" causality="parameter" variability="fixed"><Enumeration declaredType="level" start="2"/></ScalarVariable>
    <ScalarVariable name="n" valueReference="1" causality="parameter" variability="fixed"><Integer start="2"/></ScalarVariable>
  </ModelVariables>
  <ModelStructure/>
</fmiModelDescription>"#;
        let fmi3 = r#"<fmiModelDescription fmiVersion="3.0" modelName="m" instantiationToken="{g}">
  <TypeDefinitions>
    <EnumerationType name="level"><Item name="a" value="1"/><Item name="b" value="2"/></EnumerationType>
  </TypeDefinitions>
  <ModelVariables>
    <Enumeration name="level" valueReference="0" causality="parameter" variability="fixed" declaredType="level" start="2"/>
    <Int32 name="n" valueReference="1" causality="parameter" variability="fixed" start="2"/>
  </ModelVariables>
  <ModelStructure/>
</fmiModelDescription>"#;
        for xml in [fmi2, fmi3] {
            let md = ModelDescription::parse(xml).unwrap();
            let items: &[(String, i64)] = &[("a".into(), 1), ("b".into(), 2)];
            assert_eq!(md.items_of(md.variable("level").unwrap()), Some(items));
            assert_eq!(md.items_of(md.variable("n").unwrap()), None);
        }
    }

    /// A small description in the shape fmu-runtime writes, as build-fmus reads it for a system.
    const INTERFACE: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
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
    fn reads_what_a_system_needs_variables_and_units() {
        let md = ModelDescription::parse(INTERFACE).unwrap();
        let names: Vec<_> = md.model_variables.iter().map(|v| v.name.as_str()).collect();
        assert_eq!(names, ["K", "mode", "w_in", "T & more", "x", "on"]);
        let w = md.variable("w_in").unwrap();
        assert_eq!((w.causality, w.variable_type, w.unit.as_deref()), (Causality::Input, VariableType::Real, Some("rad/s")));
        assert_eq!((w.causality.name(), w.variable_type.name()), ("input", "Real"));
        assert_eq!(md.variable("x").unwrap().causality.name(), "local");
        assert_eq!(md.variable("mode").unwrap().variable_type, VariableType::Integer);
        assert_eq!(md.variable("on").unwrap().variable_type, VariableType::Boolean);
        assert_eq!(md.names_of(Causality::Output), ["T & more", "on"]);
        let units: Vec<_> = md.unit_definitions.iter().map(|u| u.name.as_str()).collect();
        assert_eq!(units, ["N.m", "rad/s", "1"]);
        assert_eq!(md.unit("rad/s").unwrap().base_unit, [("s".to_owned(), "-1".to_owned()), ("rad".to_owned(), "1".to_owned())]);
        assert!(md.unit("1").unwrap().base_unit.is_empty());
        // A variable without its type element, closed or self-closing.
        for broken in [
            r#"<ScalarVariable name="x" valueReference="4"></ScalarVariable>"#,
            r#"<ScalarVariable name="x" valueReference="4"/>"#,
        ] {
            let xml = INTERFACE.replace(r#"<ScalarVariable name="x" valueReference="4"><Real/></ScalarVariable>"#, broken);
            match ModelDescription::parse(&xml) {
                Err(Error::ModelDescription(m)) => assert!(m.contains("\"x\" has no type element"), "{m}"),
                other => panic!("{broken}: {other:?}"),
            }
        }
        let not_well_formed = INTERFACE.replace("</UnitDefinitions>", "</UnitDefinitionz>");
        assert!(matches!(ModelDescription::parse(&not_well_formed), Err(Error::Xml { .. })));
    }

    #[test]
    fn reads_output_dependencies() {
        // Seven variables; FMI 2.0 counts them from 1, the structure is kept in value references
        // (index - 1 here).
        let variables: String = (1..=7)
            .map(|i| format!(r#"<ScalarVariable name="v{i}" valueReference="{}"><Real/></ScalarVariable>"#, i - 1))
            .collect();
        let xml = format!(
            r#"<fmiModelDescription fmiVersion="2.0" modelName="D" guid="{{g}}"><ModelVariables>{variables}</ModelVariables><ModelStructure>
            <Outputs><Unknown index="3" dependencies="1 2"/><Unknown index="4" dependencies=""/>
            <Unknown index="5"/></Outputs>
            <Derivatives><Unknown index="7" dependencies="1"/></Derivatives>
            </ModelStructure></fmiModelDescription>"#
        );
        let d = ModelDescription::parse(&xml).unwrap().model_structure;
        assert!(d.output_depends_on(2, 0) && d.output_depends_on(2, 1) && !d.output_depends_on(2, 5));
        assert!(!d.output_depends_on(3, 0), "empty list: no dependency");
        assert!(d.output_depends_on(4, 0), "no attribute: depends on everything");
        assert!(d.output_depends_on(6, 1), "a derivative is not an output: conservative answer");
    }

    #[test]
    fn reads_the_fmi2_model_structure_in_value_references() {
        let md = ModelDescription::parse(XML).unwrap();
        assert_eq!(md.version(), FmiVersion::Fmi2);
        // <Unknown index="5"/> is the fifth variable, n (value reference 0).
        assert_eq!(md.model_structure.outputs, vec![Unknown { value_reference: 0, dependencies: None }]);
        let bad = XML.replace(r#"<Unknown index="5"/>"#, r#"<Unknown index="9"/>"#);
        assert!(matches!(ModelDescription::parse(&bad), Err(Error::ModelDescription(_))));
    }

    #[test]
    fn invalid_fmi3_content_is_an_error() {
        let cases = [
            XML3.replace(r#"instantiationToken="{token-3}""#, ""),
            XML3.replace(r#"fmiVersion="3.0""#, r#"fmiVersion="4.0""#),
            XML3.replace(r#"<Int32 name="n""#, r#"<UInt8 name="n""#),
            XML3.replace(r#"<Float64 name="u" valueReference="2" causality="input" declaredType="Voltage" start="0"/>"#, r#"<Float64 name="u" valueReference="2" causality="input"><Dimension start="2"/></Float64>"#),
            XML3.replace(r#"derivative="0""#, r#"derivative="42""#),
            XML3.replace(r#"<EventIndicator valueReference="6"/>"#, r#"<EventIndicator valueReference="60"/>"#),
            XML3.replace(r#"dependencies="0 2""#, r#"dependencies="0 two""#),
            XML3.replace(r#"name="u""#, r#"name="x""#),
        ];
        for (i, xml) in cases.iter().enumerate() {
            match ModelDescription::parse(xml) {
                Err(Error::ModelDescription(_)) => {}
                other => panic!("case {i}: expected a ModelDescription error, got {other:?}"),
            }
        }
    }
}
