//! The variable table: a model states each variable once, here, and everything else — value
//! references, the typed stores behind fmi2Get/Set, range checks and `modelDescription.xml` —
//! is derived from that one declaration.
//!
//! ```text
//! let r = d.parameter("R_series", 1.0, "Ohm").min(0.0).describe("Line resistance");
//! let i = d.state("i_L", 0.0, "A").describe("Line current");
//! let y = d.output("i_absorbed", "A").describe("Absorbed current");
//! ```
//! Value references are given in declaration order, one counter for all types (so a value
//! reference names one variable whatever its type). A state also declares its derivative
//! `der(<name>)` right after itself.

use std::collections::{HashMap, HashSet};
use std::hash::{BuildHasherDefault, Hasher};
use std::panic::Location;

use crate::units;

/// FMI 2.0 causality (section 2.2.7).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    CalculatedParameter,
    Input,
    Output,
    Local,
}

impl Causality {
    pub fn as_str(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::CalculatedParameter => "calculatedParameter",
            Causality::Input => "input",
            Causality::Output => "output",
            Causality::Local => "local",
        }
    }
}

/// FMI 2.0 variability (section 2.2.7).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    Fixed,
    Tunable,
    Discrete,
    Continuous,
}

impl Variability {
    pub fn as_str(self) -> &'static str {
        match self {
            Variability::Fixed => "fixed",
            Variability::Tunable => "tunable",
            Variability::Discrete => "discrete",
            Variability::Continuous => "continuous",
        }
    }
}

/// FMI 2.0 `initial` attribute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Initial {
    Exact,
    Calculated,
}

impl Initial {
    pub fn as_str(self) -> &'static str {
        match self {
            Initial::Exact => "exact",
            Initial::Calculated => "calculated",
        }
    }
}

/// Where a variable's value lives inside an instance. Knowns (parameters, inputs) and states
/// are read by the model's equations; calculated values (outputs, locals, calculated
/// parameters) are written by them; derivatives come from `Model::derivatives`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// Index into the known reals: parameters and inputs.
    Known(usize),
    /// Index into the state vector: a continuous state. Its one home holds the start value
    /// before initialization (set by the master, or computed for a calculated state) and the
    /// current value after it.
    State(usize),
    /// Index into the calculated reals: outputs, locals, calculated parameters.
    Calculated(usize),
    /// Index of the state whose derivative this is.
    Derivative(usize),
    /// Index into the integer parameters.
    Integer(usize),
    /// Index into the boolean parameters.
    Boolean(usize),
}

/// The FMI base type of a variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BaseType {
    Real,
    Integer,
    Boolean,
}

impl BaseType {
    /// The type's name in both standards, for messages: FMI 2.0's, then FMI 3.0's where it
    /// differs ("Real/Float64").
    pub fn name(self) -> &'static str {
        match self {
            BaseType::Real => "Real/Float64",
            BaseType::Integer => "Integer/Int32",
            BaseType::Boolean => "Boolean",
        }
    }

    /// "a Real/Float64", "an Integer/Int32", "a Boolean".
    pub fn with_article(self) -> &'static str {
        match self {
            BaseType::Real => "a Real/Float64",
            BaseType::Integer => "an Integer/Int32",
            BaseType::Boolean => "a Boolean",
        }
    }
}

/// Start value of a variable, if it has one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Start {
    Real(f64),
    Integer(i32),
    Boolean(bool),
}

/// One scalar variable, as declared by a model.
#[derive(Clone, Debug)]
pub struct Variable {
    pub name: String,
    pub value_reference: u32,
    pub description: String,
    pub causality: Causality,
    pub variability: Variability,
    pub initial: Option<Initial>,
    pub start: Option<Start>,
    pub unit: Option<String>,
    pub min: Option<f64>,
    pub max: Option<f64>,
    pub nominal: Option<f64>,
    pub slot: Slot,
    /// For a state derivative, the value reference of its state.
    pub derivative_of: Option<u32>,
    /// For a structural choice, its items (name, description), valued min, min + 1, ...: an FMI
    /// Enumeration (FMI 2.0 read and set as Integer, FMI 3.0 as Int64). Empty for an Integer.
    pub items: Vec<(String, String)>,
}

impl Variable {
    pub fn base_type(&self) -> BaseType {
        match self.slot {
            Slot::Known(_) | Slot::State(_) | Slot::Calculated(_) | Slot::Derivative(_) => BaseType::Real,
            Slot::Integer(_) => BaseType::Integer,
            Slot::Boolean(_) => BaseType::Boolean,
        }
    }

    /// A known whose value the master may set before initialization (a parameter or a state
    /// start value) or at any time (an input).
    pub fn is_settable_before_initialization(&self) -> bool {
        matches!(self.causality, Causality::Parameter | Causality::Input)
            || self.initial == Some(Initial::Exact)
    }

    /// A discrete mode (`Declarations::mode`): an Integer local, changed only at events.
    pub fn is_mode(&self) -> bool {
        matches!(self.slot, Slot::Integer(_)) && self.causality == Causality::Local
    }

    /// Settable while the instance steps (FMI 2.0 CS: inputs and tunable parameters).
    pub fn is_settable_while_stepping(&self) -> bool {
        self.causality == Causality::Input
            || (self.causality == Causality::Parameter && self.variability == Variability::Tunable)
    }

    /// Checks a candidate value against the variable's declared range, inclusive at both ends:
    /// exactly the range modelDescription.xml declares.
    pub fn check_range(&self, value: f64) -> Result<(), String> {
        let (name, v) = (&self.name, number(value));
        if !value.is_finite() {
            return Err(format!("{name} = {v} is not a finite number"));
        }
        if let Some(min) = self.min {
            if value < min {
                let positive = if min == SMALLEST_POSITIVE { " (a strictly positive quantity: it must be > 0)" } else { "" };
                return Err(format!("{name} = {v} is below its minimum {}{positive}", number(min)));
            }
        }
        if let Some(max) = self.max {
            if value > max {
                return Err(format!("{name} = {v} is above its maximum {}", number(max)));
            }
        }
        Ok(())
    }
}

/// The `min` of a strictly positive quantity (`RealBuilder::positive`): the smallest positive
/// normal double. FMI 2.0's `min` is inclusive, so a declared `min="0"` would promise that 0 is
/// accepted; this bound is the closest to 0 that an inclusive range can say "above 0" with.
pub const SMALLEST_POSITIVE: f64 = f64::MIN_POSITIVE;

/// A variable name FMI masters and scripting languages can use, and a valid name of FMI's
/// structured naming convention (FMI 2.0 section 2.2.9, FMI 3.0 section 2.4.7.5): parts joined by
/// '.', each a letter, then letters, digits or '_', optionally with array indices
/// (`w[1]`, `T[2,3]`, `pipe[3].T[14]`); `der(x)` for a state's derivative. (FMI's grammar also
/// allows a leading '_' and quoted names, `'motor #234'`; this runtime does not.)
pub fn is_valid_name(name: &str) -> bool {
    match name.strip_prefix("der(").and_then(|n| n.strip_suffix(')')) {
        Some(inner) => is_identifier(inner),
        None => is_identifier(name),
    }
}

/// `part {"." part}`, a part being `letter {letter | digit | "_"} ["[" digits {"," digits} "]"]`.
fn is_identifier(name: &str) -> bool {
    name.split('.').all(|part| {
        let (base, indices) = match part.find('[') {
            Some(open) => (&part[..open], Some(&part[open..])),
            None => (part, None),
        };
        let base_ok = base.chars().next().is_some_and(|c| c.is_ascii_alphabetic()) && base.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        let indices_ok = indices.is_none_or(|i| {
            i.strip_prefix('[')
                .and_then(|i| i.strip_suffix(']'))
                .is_some_and(|list| list.split(',').all(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit())))
        });
        base_ok && indices_ok
    })
}

/// Whether a name uses the structured convention's hierarchy or array indices (`a.b`, `w[1]`):
/// a description with such a name says `variableNamingConvention="structured"`.
pub fn is_structured_name(name: &str) -> bool {
    name.contains(['.', '['])
}

/// A number as people read it: shortest round-trip text, an exponent for tiny or huge values.
pub fn number(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e15).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

macro_rules! handle {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub struct $name(pub(crate) usize);
    };
}

handle!(
    /// A real parameter (causality parameter): read it in the equations as `k[handle]`.
    Parameter
);
handle!(
    /// A real input: read it in the equations as `k[handle]`.
    Input
);
handle!(
    /// A real output: write it in `Model::outputs` as `out[handle] = value`.
    Output
);
handle!(
    /// A real local or calculated parameter: written in `Model::outputs` like an output.
    Local
);
handle!(
    /// An integer parameter (structural choices: modelling level, number of nodes).
    IntegerParameter
);
handle!(
    /// A boolean parameter.
    BooleanParameter
);

impl BooleanParameter {
    /// Index into the boolean store.
    pub fn index(self) -> usize {
        self.0
    }
}

/// A discrete mode (an FMI Integer local, variability `discrete`): read as `k[mode]` in the
/// equations, changed only at events by `Model::update_modes` (stick/slip of a friction,
/// a switch's position). Its value lives in the integer store, so it is part of FMU states.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mode(pub(crate) usize);

/// An event indicator z (FMI 2.0 ME `numberOfEventIndicators`): the model writes it in
/// `Model::event_indicators`; an event happens when it changes sign.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Indicator(pub(crate) usize);

/// A continuous state: read as `k[state]`, its derivative written as `der[state] = value`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct State {
    pub(crate) state: usize,
}

/// Everything a model declared: the variables in value-reference order and the store sizes.
#[derive(Clone, Debug, Default)]
pub struct VariableTable {
    pub variables: Vec<Variable>,
    pub n_known: usize,
    pub n_calculated: usize,
    pub n_states: usize,
    pub n_integers: usize,
    pub n_booleans: usize,
    /// Value reference of each state, in state order.
    pub state_value_reference: Vec<u32>,
    /// Event indicators (name, description), in declaration order.
    pub indicators: Vec<(String, String)>,
    /// Where each variable was declared (the model's source file and line), by value reference.
    pub declared_at: Vec<&'static Location<'static>>,
    /// The model's elements (Table 3.1) with their activity variables, in declaration order.
    pub elements: Vec<crate::elements::ElementInfo>,
    /// The energy balance outputs, for a model with elements whose powers it sums.
    pub balance: Option<crate::elements::BalanceOutputs>,
    /// What is wrong with the declarations, one message per problem: "file:line: the rule
    /// broken. Fix: what to do". A model with problems is not exported (build-fmus prints them).
    pub problems: Vec<String>,
    /// The value reference of each name (the first declared, for a name declared twice): what
    /// `by_name` and the duplicate check look up, so that declaring costs O(variables).
    names: HashMap<String, u32, BuildHasherDefault<NameHasher>>,
}

/// FNV-1a over a name's bytes: the name index's hash (a model's own names, no adversary to
/// guard against; the standard library's SipHash cost a tenth of a declaration).
struct NameHasher(u64);

impl Default for NameHasher {
    fn default() -> Self {
        NameHasher(crate::state::FNV_OFFSET)
    }
}

impl Hasher for NameHasher {
    fn write(&mut self, bytes: &[u8]) {
        self.0 = crate::state::fnv1a64(self.0, bytes);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

impl VariableTable {
    /// The variable with this value reference.
    pub fn get(&self, vr: u32) -> Option<&Variable> {
        self.variables.get(vr as usize)
    }

    /// The variable with this name.
    pub fn by_name(&self, name: &str) -> Option<&Variable> {
        self.names.get(name).and_then(|&vr| self.get(vr)).filter(|v| v.name == name)
    }

    /// Whether the description says `variableNamingConvention="structured"`: some name uses
    /// the structured convention's hierarchy or array indices (every accepted name is a valid
    /// structured name, so a model without such names keeps FMI's default, flat).
    pub fn structured_names(&self) -> bool {
        self.variables.iter().any(|v| is_structured_name(&v.name))
    }

    /// The state indices of the states declared with `Declarations::calculated_state`.
    pub fn calculated_states(&self) -> impl Iterator<Item = usize> + '_ {
        self.state_value_reference
            .iter()
            .enumerate()
            .filter(|(_, vr)| self.variables[**vr as usize].initial == Some(Initial::Calculated))
            .map(|(s, _)| s)
    }

    /// The state index of a variable, if it is a continuous state.
    pub fn state_index(&self, var: &Variable) -> Option<usize> {
        match var.slot {
            Slot::State(s) => Some(s),
            _ => None,
        }
    }

    /// Nominal value of each state (1 where undeclared), used to scale absolute tolerances.
    pub fn state_nominals(&self) -> Vec<f64> {
        self.state_value_reference
            .iter()
            .map(|&vr| self.variables[vr as usize].nominal.unwrap_or(1.0))
            .collect()
    }

    /// The state indices of the elements' activities (`A_<element>`).
    pub fn activity_states(&self) -> Vec<usize> {
        self.elements.iter().filter_map(|e| e.activity_state).collect()
    }

    /// Start values of the known reals, states (0 for a calculated state, which the model
    /// computes), calculated reals, integers and booleans.
    pub fn start_values(&self) -> crate::values::Values {
        let mut v = crate::values::Values {
            known: vec![0.0; self.n_known],
            states: vec![0.0; self.n_states],
            calculated: vec![0.0; self.n_calculated],
            derivatives: vec![0.0; self.n_states],
            integers: vec![0; self.n_integers],
            booleans: vec![false; self.n_booleans],
        };
        for var in &self.variables {
            match (var.slot, var.start) {
                (Slot::Known(i), Some(Start::Real(x))) => v.known[i] = x,
                (Slot::State(s), Some(Start::Real(x))) => v.states[s] = x,
                (Slot::Integer(i), Some(Start::Integer(x))) => v.integers[i] = x,
                (Slot::Boolean(i), Some(Start::Boolean(x))) => v.booleans[i] = x,
                _ => {}
            }
        }
        v
    }
}

/// The builder a model's `declare` receives. Each call adds one variable (two for a state) and
/// hands back a builder whose `describe` finishes the declaration and returns the typed handle:
/// a variable without a description does not compile into a handle.
#[derive(Default)]
pub struct Declarations {
    table: VariableTable,
    /// The event indicators' names, for the duplicate check.
    indicator_names: HashSet<String>,
    /// Whether any input has been declared.
    has_inputs: bool,
}

impl Declarations {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn into_table(self) -> VariableTable {
        self.table
    }

    /// Whether any event indicator has been declared.
    pub fn has_event_indicators(&self) -> bool {
        !self.table.indicators.is_empty()
    }

    /// Whether any input has been declared.
    pub fn has_inputs(&self) -> bool {
        self.has_inputs
    }

    /// Records a problem found in the declaration at `at`.
    fn problem(&mut self, at: &Location, message: String) {
        self.table.problems.push(format!("{}:{}: {message}", at.file(), at.line()));
    }

    #[track_caller]
    fn push(&mut self, mut var: Variable) -> usize {
        let at = Location::caller();
        let name = var.name.clone();
        let vr = self.table.variables.len() as u32;
        if let Some(first) = self.table.by_name(&name).map(|v| self.table.declared_at[v.value_reference as usize]) {
            self.problem(
                at,
                format!("variable '{name}' is declared twice (first at {}:{}). Fix: give each variable its own name", first.file(), first.line()),
            );
        } else {
            self.table.names.insert(name.clone(), vr);
        }
        if !is_valid_name(&name) {
            self.problem(
                at,
                format!(
                    "'{name}' is not a usable variable name. Fix: start with a letter, then letters, digits or '_'; \
                     an array element as name[1] (or name[1,2]), a part of a component as part.name"
                ),
            );
        }
        self.has_inputs |= var.causality == Causality::Input;
        match var.unit.as_deref() {
            Some("") => self.problem(at, format!("'{name}' has no unit. Fix: give its SI unit (\"1\" for a dimensionless quantity)")),
            Some(unit) if units::lookup(unit).is_none() => self.problem(
                at,
                format!("'{name}' has the unit '{unit}', which fmu_runtime::units does not know. Fix: use an SI unit ({}) or add it there", units::examples()),
            ),
            _ => {}
        }
        var.value_reference = vr;
        self.table.variables.push(var);
        self.table.declared_at.push(at);
        self.table.variables.len() - 1
    }

    /// Finishes a declaration: its description, which must say something.
    fn describe_variable(&mut self, pos: usize, description: &str) {
        self.table.variables[pos].description = description.to_string();
        if description.trim().is_empty() {
            let (at, name) = (self.table.declared_at[pos], self.table.variables[pos].name.clone());
            self.problem(at, format!("'{name}' has no description. Fix: say what it is, with the chapter's equation or figure"));
        }
    }

    #[track_caller]
    fn real(
        &mut self,
        name: &str,
        unit: &str,
        causality: Causality,
        variability: Variability,
        initial: Option<Initial>,
        start: Option<f64>,
        slot: Slot,
    ) -> usize {
        self.push(Variable {
            name: name.to_string(),
            value_reference: 0,
            description: String::new(),
            causality,
            variability,
            initial,
            start: start.map(Start::Real),
            unit: Some(unit.to_string()),
            min: None,
            max: None,
            nominal: None,
            slot,
            derivative_of: None,
            items: Vec::new(),
        })
    }

    fn next_known(&mut self) -> usize {
        self.table.n_known += 1;
        self.table.n_known - 1
    }

    fn next_calculated(&mut self) -> usize {
        self.table.n_calculated += 1;
        self.table.n_calculated - 1
    }

    /// A real parameter with its default (the chapter's value) and SI unit; `fixed` unless
    /// `.tunable()`.
    #[track_caller]
    pub fn parameter(&mut self, name: &str, start: f64, unit: &str) -> RealBuilder<'_, Parameter> {
        let k = self.next_known();
        let pos = self.real(name, unit, Causality::Parameter, Variability::Fixed, None, Some(start), Slot::Known(k));
        RealBuilder { decl: self, pos, handle: Parameter(k) }
    }

    /// A real input with the value it holds until the master sets it.
    #[track_caller]
    pub fn input(&mut self, name: &str, start: f64, unit: &str) -> RealBuilder<'_, Input> {
        let k = self.next_known();
        let pos = self.real(name, unit, Causality::Input, Variability::Continuous, None, Some(start), Slot::Known(k));
        RealBuilder { decl: self, pos, handle: Input(k) }
    }

    /// A real output, computed by `Model::outputs`.
    #[track_caller]
    pub fn output(&mut self, name: &str, unit: &str) -> RealBuilder<'_, Output> {
        let c = self.next_calculated();
        let pos = self.real(name, unit, Causality::Output, Variability::Continuous, None, None, Slot::Calculated(c));
        RealBuilder { decl: self, pos, handle: Output(c) }
    }

    /// A real local variable computed by `Model::outputs` (an internal signal worth plotting).
    #[track_caller]
    pub fn local(&mut self, name: &str, unit: &str) -> RealBuilder<'_, Local> {
        let c = self.next_calculated();
        let pos = self.real(name, unit, Causality::Local, Variability::Continuous, None, None, Slot::Calculated(c));
        RealBuilder { decl: self, pos, handle: Local(c) }
    }

    /// A parameter computed from other parameters (e.g. an inertia referred to another axis),
    /// written by `Model::outputs`.
    #[track_caller]
    pub fn calculated_parameter(&mut self, name: &str, unit: &str) -> RealBuilder<'_, Local> {
        let c = self.next_calculated();
        let pos = self.real(
            name,
            unit,
            Causality::CalculatedParameter,
            Variability::Fixed,
            Some(Initial::Calculated),
            None,
            Slot::Calculated(c),
        );
        RealBuilder { decl: self, pos, handle: Local(c) }
    }

    /// A continuous state with its initial value (settable before initialization). Also
    /// declares `der(<name>)`, in the unit of the state per second.
    #[track_caller]
    pub fn state(&mut self, name: &str, start: f64, unit: &str) -> RealBuilder<'_, State> {
        self.state_with(name, Some(start), unit)
    }

    /// A continuous state whose initial value the model computes at initialization, in
    /// `Model::initial_states`, from the parameters and inputs (a steady state, a temperature
    /// equal to the ambient one). FMI `initial="calculated"`: no start value, not settable before
    /// initialization, listed among the InitialUnknowns. Also declares `der(<name>)`.
    #[track_caller]
    pub fn calculated_state(&mut self, name: &str, unit: &str) -> RealBuilder<'_, State> {
        self.state_with(name, None, unit)
    }

    #[track_caller]
    fn state_with(&mut self, name: &str, start: Option<f64>, unit: &str) -> RealBuilder<'_, State> {
        let s = self.table.n_states;
        self.table.n_states += 1;
        let initial = if start.is_some() { Initial::Exact } else { Initial::Calculated };
        let pos = self.real(name, unit, Causality::Local, Variability::Continuous, Some(initial), start, Slot::State(s));
        let vr = self.table.variables[pos].value_reference;
        self.table.state_value_reference.push(vr);
        let der_unit = units::derivative_unit(unit);
        let dpos = self.real(
            &format!("der({name})"),
            &der_unit,
            Causality::Local,
            Variability::Continuous,
            Some(Initial::Calculated),
            None,
            Slot::Derivative(s),
        );
        self.table.variables[dpos].derivative_of = Some(vr);
        self.table.variables[dpos].description = format!("Time derivative of {name}");
        RealBuilder { decl: self, pos, handle: State { state: s } }
    }

    /// A non-real parameter (`fixed`, no unit).
    #[track_caller]
    fn discrete_parameter(&mut self, name: &str, start: Start, slot: Slot) -> usize {
        self.push(Variable {
            name: name.to_string(),
            value_reference: 0,
            description: String::new(),
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            initial: None,
            start: Some(start),
            unit: None,
            min: None,
            max: None,
            nominal: None,
            slot,
            derivative_of: None,
            items: Vec::new(),
        })
    }

    /// An integer parameter (`fixed`): structural choices such as a modelling level.
    #[track_caller]
    pub fn integer_parameter(&mut self, name: &str, start: i32) -> IntegerBuilder<'_> {
        let i = self.table.n_integers;
        self.table.n_integers += 1;
        let pos = self.discrete_parameter(name, Start::Integer(start), Slot::Integer(i));
        IntegerBuilder { decl: self, pos, handle: IntegerParameter(i) }
    }

    /// A boolean parameter (`fixed`).
    #[track_caller]
    pub fn boolean_parameter(&mut self, name: &str, start: bool) -> BooleanBuilder<'_> {
        let b = self.table.n_booleans;
        self.table.n_booleans += 1;
        let pos = self.discrete_parameter(name, Start::Boolean(start), Slot::Boolean(b));
        BooleanBuilder { decl: self, pos, handle: BooleanParameter(b) }
    }

    /// A discrete mode with the value the model starts from before its first mode update
    /// (an Integer local, `discrete`, `initial="calculated"`: the runtime settles it at the end
    /// of initialization by `Model::update_modes`).
    #[track_caller]
    pub fn mode(&mut self, name: &str, start: i32) -> ModeBuilder<'_> {
        let i = self.table.n_integers;
        self.table.n_integers += 1;
        let pos = self.push(Variable {
            name: name.to_string(),
            value_reference: 0,
            description: String::new(),
            causality: Causality::Local,
            variability: Variability::Discrete,
            initial: Some(Initial::Calculated),
            start: Some(Start::Integer(start)),
            unit: None,
            min: None,
            max: None,
            nominal: None,
            slot: Slot::Integer(i),
            derivative_of: None,
            items: Vec::new(),
        });
        ModeBuilder { decl: self, pos, handle: Mode(i) }
    }

    /// An element of the model (Table 3.1): its name (the suffix of the variables the runtime
    /// declares for it), the component or subset it belongs to ("Driveshaft") and its effect,
    /// usually the component's own constant (`TorsionSpring::STIFFNESS`). A source, storage or
    /// dissipative element gets its activity state `A_<name>` and output `activity_<name>`, a
    /// storage or dissipative one also `share_<name>` (see [`crate::elements`]); its equations
    /// report its power with `der.power(element, p)`.
    #[track_caller]
    pub fn element(&mut self, name: &str, component: &str, effect: crate::elements::Effect) -> ElementBuilder<'_> {
        ElementBuilder { decl: self, name: name.to_string(), component: component.to_string(), effect, nominal: None }
    }

    /// An effect Table 3.1 lists for a component but the model leaves out, with the reason
    /// ("negligible beside the motor inertia, Figure 3.4"): documented, no variables.
    #[track_caller]
    pub fn neglected(&mut self, component: &str, effect: crate::elements::Effect, reason: &str) {
        if reason.trim().is_empty() {
            self.problem(Location::caller(), format!("the neglected {} of '{component}' gives no reason. Fix: say why it is left out", effect.what));
        }
        self.table.elements.push(crate::elements::ElementInfo {
            name: String::new(),
            component: component.to_string(),
            effect,
            description: String::new(),
            neglected: Some(reason.to_string()),
            activity_state: None,
            activity_output: None,
            share_output: None,
        });
    }

    /// Declares the balance outputs, once the model's elements are known (by `model::declare`).
    pub(crate) fn declare_power_balance(&mut self) {
        if !self.table.elements.iter().any(|e| e.neglected.is_none() && e.effect.in_balance()) {
            return;
        }
        let residual = self
            .output("power_balance_residual", "W")
            .describe("Energy balance of the elements (Table 3.1): source powers - rates of stored energy - dissipated powers; 0 up to rounding");
        let relative = self
            .output("power_balance_relative", "1")
            .describe("power_balance_residual over the largest element power at the same instant (0 while every power is 0)");
        self.table.balance = Some(crate::elements::BalanceOutputs { residual: residual.0, relative: relative.0 });
    }

    /// An event indicator (not an FMI variable: FMI 2.0 only counts them). The name appears in
    /// the log messages of the events it triggers.
    #[track_caller]
    pub fn event_indicator(&mut self, name: &str, description: &str) -> Indicator {
        if !self.indicator_names.insert(name.to_string()) {
            self.problem(Location::caller(), format!("event indicator '{name}' is declared twice. Fix: give each indicator its own name"));
        }
        self.table.indicators.push((name.to_string(), description.to_string()));
        Indicator(self.table.indicators.len() - 1)
    }
}

/// The nominal of an activity state unless the element gives one, J. An activity starts at 0
/// and grows; its shares are ratios of activities, so a directional derivative stepping an
/// activity by 1e-7 of a 1 J nominal straddles the shares' curvature while the activities are
/// still small (ShaftLine at 0.05 s: 2e-6 of their scale); 1 mJ keeps it below 1e-8 there.
pub const ACTIVITY_NOMINAL_J: f64 = 1e-3;

/// Finishes an element's declaration: the nominal magnitude of its activity, then `describe`.
pub struct ElementBuilder<'a> {
    decl: &'a mut Declarations,
    name: String,
    component: String,
    effect: crate::elements::Effect,
    nominal: Option<f64>,
}

impl ElementBuilder<'_> {
    /// Typical magnitude of the activity state in J (scales its absolute tolerance and the step
    /// of its directional derivatives); [`ACTIVITY_NOMINAL_J`] unless given.
    pub fn nominal(mut self, nominal_j: f64) -> Self {
        self.nominal = Some(nominal_j);
        self
    }

    /// Finishes the declaration with what the element is, as a phrase that reads after "the
    /// activity of" ("the driveshaft stiffness K_shaft, power K theta dtheta/dt"), and declares
    /// its variables.
    #[track_caller]
    pub fn describe(self, description: &str) -> crate::elements::Element {
        let ElementBuilder { decl, name, component, effect, nominal } = self;
        let index = decl.table.elements.len();
        let (mut activity_state, mut activity_output, mut share_output) = (None, None, None);
        if effect.kind.has_activity() {
            let state = decl.state(&format!("A_{name}"), 0.0, "J").nominal(nominal.unwrap_or(ACTIVITY_NOMINAL_J));
            activity_state = Some(state.describe(&format!("Activity of {description} (eq. 3.3): integral of |power| dt since the start")).state);
            activity_output =
                Some(decl.output(&format!("activity_{name}"), "J").describe(&format!("Activity of {description}, integral of |power| dt (eq. 3.3)")).0);
            if effect.kind != crate::elements::Kind::Source {
                let among = if effect.kind.is_storage() { "storage" } else { "dissipative" };
                share_output = Some(
                    decl.output(&format!("share_{name}"), "%")
                        .describe(&format!("Share of {description} in the total activity of the {among} elements (Table 3.3)"))
                        .0,
                );
            }
        }
        if description.trim().is_empty() {
            decl.problem(Location::caller(), format!("element '{name}' has no description. Fix: say what it is, with its law"));
        }
        decl.table.elements.push(crate::elements::ElementInfo {
            name,
            component,
            effect,
            description: description.to_string(),
            neglected: None,
            activity_state,
            activity_output,
            share_output,
        });
        crate::elements::Element { index, activity: activity_state }
    }
}

/// Finishes a discrete mode's declaration.
pub struct ModeBuilder<'a> {
    decl: &'a mut Declarations,
    pos: usize,
    handle: Mode,
}

impl ModeBuilder<'_> {
    /// The values the mode takes, inclusive (also the values at which the runtime probes the
    /// equations for the ModelStructure).
    pub fn range(self, min: i32, max: i32) -> Self {
        let v = &mut self.decl.table.variables[self.pos];
        v.min = Some(min as f64);
        v.max = Some(max as f64);
        self
    }

    pub fn describe(self, description: &str) -> Mode {
        self.decl.describe_variable(self.pos, description);
        self.handle
    }
}

/// Finishes a real variable's declaration: bounds, nominal, tunability, then `describe`.
pub struct RealBuilder<'a, H> {
    decl: &'a mut Declarations,
    pos: usize,
    handle: H,
}

impl<H> RealBuilder<'_, H> {
    fn var(&mut self) -> &mut Variable {
        &mut self.decl.table.variables[self.pos]
    }

    /// Smallest physically meaningful value (inclusive); values below are rejected.
    pub fn min(mut self, min: f64) -> Self {
        self.var().min = Some(min);
        self
    }

    /// Strictly positive (an inertia, an inductance, a capacitance): declares
    /// `min` = [`SMALLEST_POSITIVE`] (inclusive, as FMI reads it), so 0 and below are refused and
    /// the declared range is exactly what `fmi2SetReal` accepts.
    pub fn positive(mut self) -> Self {
        self.var().min = Some(SMALLEST_POSITIVE);
        self
    }

    /// Largest physically meaningful value (inclusive); values above are rejected.
    pub fn max(mut self, max: f64) -> Self {
        self.var().max = Some(max);
        self
    }

    /// Typical magnitude (scales a state's absolute tolerance).
    pub fn nominal(mut self, nominal: f64) -> Self {
        self.var().nominal = Some(nominal);
        self
    }

    /// Finishes the declaration with its description (cite the chapter's equation or figure)
    /// and returns the handle the equations use.
    pub fn describe(self, description: &str) -> H {
        self.decl.describe_variable(self.pos, description);
        let v = &self.decl.table.variables[self.pos];
        if let Some(Start::Real(s)) = v.start {
            if let Err(e) = v.check_range(s) {
                let (at, name) = (self.decl.table.declared_at[self.pos], v.name.clone());
                let what = if s.is_nan() { "no default (NaN)".to_string() } else { format!("an invalid default: {e}") };
                self.decl.problem(at, format!("'{name}' has {what}. Fix: give the chapter's value, or a documented choice, inside its range"));
            }
        }
        self.handle
    }
}

impl RealBuilder<'_, Parameter> {
    /// The master may change this parameter between communication steps.
    pub fn tunable(mut self) -> Self {
        self.var().variability = Variability::Tunable;
        self
    }
}

impl RealBuilder<'_, Output> {
    /// An output that changes only at events (FMI `variability="discrete"`): computed from the
    /// discrete modes alone, such as a latch's state, so that a Model Exchange master may take
    /// it as constant between events.
    pub fn discrete(mut self) -> Self {
        self.var().variability = Variability::Discrete;
        self
    }
}

/// Finishes an integer parameter's declaration.
pub struct IntegerBuilder<'a> {
    decl: &'a mut Declarations,
    pos: usize,
    handle: IntegerParameter,
}

impl IntegerBuilder<'_> {
    /// The allowed range, inclusive.
    pub fn range(self, min: i32, max: i32) -> Self {
        let v = &mut self.decl.table.variables[self.pos];
        v.min = Some(min as f64);
        v.max = Some(max as f64);
        self
    }

    /// A choice among named items (an FMI Enumeration): `first` is the first item's value, each
    /// next item's one more (the range). Each item is (name, description): ("c", "level c:
    /// driveshaft elasticity").
    pub fn choices(self, first: i32, items: &[(&str, &str)]) -> Self {
        let v = &mut self.decl.table.variables[self.pos];
        v.items = items.iter().map(|(n, d)| (n.to_string(), d.to_string())).collect();
        self.range(first, first + items.len().max(1) as i32 - 1)
    }

    pub fn describe(self, description: &str) -> IntegerParameter {
        self.decl.describe_variable(self.pos, description);
        self.handle
    }
}

/// Finishes a boolean parameter's declaration.
pub struct BooleanBuilder<'a> {
    decl: &'a mut Declarations,
    pos: usize,
    handle: BooleanParameter,
}

impl BooleanBuilder<'_> {
    pub fn describe(self, description: &str) -> BooleanParameter {
        self.decl.describe_variable(self.pos, description);
        self.handle
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_references_follow_declaration_order_and_states_bring_derivatives() {
        let mut d = Declarations::new();
        let p = d.parameter("R", 1.0, "Ohm").min(0.0).describe("resistance");
        let x = d.state("i", 0.0, "A").describe("current");
        let y = d.output("y", "A").describe("output");
        let n = d.integer_parameter("level", 1).range(1, 4).describe("level");
        let t = d.into_table();
        assert_eq!((p, x, y, n), (Parameter(0), State { state: 0 }, Output(0), IntegerParameter(0)));
        let names: Vec<_> = t.variables.iter().map(|v| (v.value_reference, v.name.as_str())).collect();
        assert_eq!(names, vec![(0, "R"), (1, "i"), (2, "der(i)"), (3, "y"), (4, "level")]);
        assert_eq!(t.variables[2].derivative_of, Some(1));
        assert_eq!(t.variables[2].unit.as_deref(), Some("A/s"));
        assert_eq!(t.variables[1].slot, Slot::State(0), "a state lives in the state vector");
        assert_eq!(t.n_known, 1, "the known reals are the parameters and inputs");
    }

    #[test]
    fn declaration_problems_name_the_file_the_variable_and_the_fix() {
        let mut d = Declarations::new();
        d.parameter("R", 1.0, "Ohm").describe("a");
        d.parameter("R", 1.0, "Ohm").describe("b");
        d.parameter("x", 1.0, "furlong").describe("c");
        d.parameter("y", 1.0, "").describe("d");
        d.parameter("z", f64::NAN, "m").describe("e");
        d.output("w", "m").describe(" ");
        d.parameter("2x", 1.0, "m").describe("f");
        let t = d.into_table();
        let p = &t.problems;
        assert_eq!(p.len(), 6, "{p:#?}");
        let here = file!();
        assert!(p.iter().all(|m| m.starts_with(here) && m.contains("Fix:")), "{p:#?}");
        assert!(p[0].contains("'R' is declared twice (first at"));
        assert!(p[1].contains("'x' has the unit 'furlong'"));
        assert!(p[2].contains("'y' has no unit"));
        assert!(p[3].contains("'z' has no default (NaN)"));
        assert!(p[4].contains("'w' has no description"));
        assert!(p[5].contains("'2x' is not a usable variable name"));
    }

    #[test]
    fn structured_names_are_accepted_as_fmi_defines_them() {
        // FMI 2.0 section 2.2.9 / FMI 3.0 section 2.4.7.5: '.' between parts, array indices on any part.
        for name in ["w[1]", "theta[12]", "T[1,2,3]", "pipe[3,4].T[14]", "vehicle.engine.speed", "der(w[1])", "der(a.b[2])", "x_1", "R"] {
            assert!(is_valid_name(name), "{name}");
        }
        for name in ["w[]", "w[1", "w[a]", "w[-1]", "w[1,]", "w [1]", "w[1]x", "a..b", ".a", "a.", "a.2b", "2x", "_x", "der(w[1]", "der()", "'quoted'", "w[1][2]", ""] {
            assert!(!is_valid_name(name), "{name}");
        }
        let mut d = Declarations::new();
        d.state("w[1]", 0.0, "rad/s").describe("a");
        d.state("w[2]", 0.0, "rad/s").describe("b");
        d.parameter("w[1]", 1.0, "m").describe("again");
        d.parameter("w[x]", 1.0, "m").describe("c");
        let t = d.into_table();
        assert_eq!(t.problems.len(), 2, "{:#?}", t.problems);
        assert!(t.problems[0].contains("'w[1]' is declared twice"), "{}", t.problems[0]);
        assert!(t.problems[1].contains("'w[x]' is not a usable variable name") && t.problems[1].contains("name[1]"), "{}", t.problems[1]);
        assert_eq!(t.by_name("der(w[2])").map(|v| v.value_reference), Some(3));
        assert_eq!(t.by_name("w[1]").map(|v| v.causality), Some(Causality::Local), "the first of a name declared twice");
        assert!(t.structured_names());
        let mut plain = Declarations::new();
        plain.state("w_1", 0.0, "rad/s").describe("a");
        assert!(!plain.into_table().structured_names(), "flat names keep FMI's default convention");
    }

    #[test]
    fn declaring_costs_the_same_per_variable_at_any_size() {
        // A name index, not a scan: 20 000 states (40 000 variables) in a fraction of a second,
        // where a scan per name took seconds (quadratic). Generous for a loaded debug build.
        let started = std::time::Instant::now();
        let mut d = Declarations::new();
        for i in 1..=20_000 {
            d.state(&format!("x[{i}]"), 0.0, "m").describe("a state");
        }
        let t = d.into_table();
        assert!(t.problems.is_empty() && t.variables.len() == 40_000);
        assert!(started.elapsed().as_secs_f64() < 2.0, "{:?}", started.elapsed());
    }

    #[test]
    fn range_check_names_the_variable() {
        let mut d = Declarations::new();
        d.parameter("J", 1.0, "kg.m2").min(0.0).describe("inertia");
        let t = d.into_table();
        let err = t.variables[0].check_range(-1.0).unwrap_err();
        assert!(err.contains("J = -1") && err.contains("minimum"), "{err}");
        assert!(t.variables[0].check_range(f64::NAN).is_err());
        assert!(t.variables[0].check_range(0.0).is_ok());
    }

    #[test]
    fn positive_quantities_refuse_zero() {
        let mut d = Declarations::new();
        d.parameter("L", 0.01, "H").positive().describe("inductance");
        let t = d.into_table();
        assert_eq!(t.variables[0].min, Some(f64::MIN_POSITIVE));
        let err = t.variables[0].check_range(0.0).unwrap_err();
        assert!(err.contains("L = 0 is below its minimum 2.2250738585072014e-308") && err.contains("must be > 0"), "{err}");
        // The declared bound itself is accepted (FMI's min is inclusive), a subnormal below it is not.
        assert!(t.variables[0].check_range(f64::MIN_POSITIVE).is_ok());
        assert!(t.variables[0].check_range(1e-300).is_ok());
        assert!(t.variables[0].check_range(f64::MIN_POSITIVE / 2.0).is_err());
    }
}
