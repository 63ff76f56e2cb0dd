//! What is coupled: [`Component`]s (named FMU instances with their start values) and
//! [`Connection`]s (output -> input), and their resolution into value references and an
//! exchange order that respects direct feedthrough.

use std::fmt;
use std::sync::Arc;

use super::error::{config, MasterError, Result};
use crate::ffi::ValueReference;
use crate::fmu::Fmu;
use crate::model_description::{Causality, ScalarVariable, VariableType};

/// One FMU instance of the system: the FMU, the instance name, and the values set after
/// `fmi2Instantiate` and before `fmi2EnterInitializationMode` (parameters, input starts), by
/// variable name.
#[derive(Clone, Debug)]
pub struct Component {
    pub name: String,
    pub fmu: Arc<Fmu>,
    pub reals: Vec<(String, f64)>,
    pub integers: Vec<(String, i32)>,
    pub booleans: Vec<(String, bool)>,
}

impl Component {
    pub fn new(name: impl Into<String>, fmu: &Arc<Fmu>) -> Component {
        Component {
            name: name.into(),
            fmu: Arc::clone(fmu),
            reals: Vec::new(),
            integers: Vec::new(),
            booleans: Vec::new(),
        }
    }

    /// A Real start value (builder style; see [`Component::set_real`]).
    pub fn real(mut self, variable: impl Into<String>, value: f64) -> Component {
        self.set_real(variable, value);
        self
    }

    /// An Integer (or Enumeration) start value (builder style).
    pub fn integer(mut self, variable: impl Into<String>, value: i32) -> Component {
        self.set_integer(variable, value);
        self
    }

    /// A Boolean start value (builder style).
    pub fn boolean(mut self, variable: impl Into<String>, value: bool) -> Component {
        self.set_boolean(variable, value);
        self
    }

    /// A Real start value; it replaces one given before for the same variable.
    pub fn set_real(&mut self, variable: impl Into<String>, value: f64) {
        set(&mut self.reals, variable.into(), value);
    }

    /// An Integer (or Enumeration) start value, replacing an earlier one.
    pub fn set_integer(&mut self, variable: impl Into<String>, value: i32) {
        set(&mut self.integers, variable.into(), value);
    }

    /// A Boolean start value, replacing an earlier one.
    pub fn set_boolean(&mut self, variable: impl Into<String>, value: bool) {
        set(&mut self.booleans, variable.into(), value);
    }
}

/// Sets `name` in a list of start values: in place if it is there, else at the end.
fn set<T>(values: &mut Vec<(String, T)>, name: String, value: T) {
    match values.iter_mut().find(|(n, _)| *n == name) {
        Some(slot) => slot.1 = value,
        None => values.push((name, value)),
    }
}

/// `instance.variable`: a variable of one instance. The instance name ends at the first dot,
/// so variable names may contain dots.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Port {
    pub instance: String,
    pub variable: String,
}

impl Port {
    /// Splits `text` (spaces around it ignored) at its first dot.
    pub fn parse(text: &str) -> std::result::Result<Port, String> {
        let text = text.trim();
        match text.split_once('.') {
            Some((instance, variable)) if !instance.is_empty() && !variable.is_empty() => {
                Ok(Port {
                    instance: instance.to_owned(),
                    variable: variable.to_owned(),
                })
            }
            _ => Err(format!("{text:?} is not \"instance.variable\"")),
        }
    }
}

impl fmt::Display for Port {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{}", self.instance, self.variable)
    }
}

/// A connection: the value of output `from` is given to input `to` (both `"instance.variable"`,
/// both Real).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Connection {
    pub from: String,
    pub to: String,
}

impl fmt::Display for Connection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} -> {}", self.from, self.to)
    }
}

/// The coupled system: components in a chosen order (the default Gauss-Seidel order) and the
/// connections between them.
#[derive(Clone, Debug, Default)]
pub struct System {
    pub components: Vec<Component>,
    pub connections: Vec<Connection>,
}

impl System {
    pub fn new() -> System {
        System::default()
    }

    /// Adds a component (builder style).
    pub fn with(mut self, component: Component) -> System {
        self.components.push(component);
        self
    }

    /// Connects output `from` to input `to`, both `"instance.variable"` (builder style; checked
    /// when the master starts).
    pub fn connect(mut self, from: impl Into<String>, to: impl Into<String>) -> System {
        self.connections.push(Connection {
            from: from.into(),
            to: to.into(),
        });
        self
    }

    /// The component called `name` (to change its start values).
    pub fn component_mut(&mut self, name: &str) -> Result<&mut Component> {
        let i = self.index_of(name)?;
        Ok(&mut self.components[i])
    }

    /// Index of the component called `name`.
    pub fn index_of(&self, name: &str) -> Result<usize> {
        self.components
            .iter()
            .position(|c| c.name == name)
            .ok_or_else(|| config(format!("no instance named {name:?} in the system")))
    }

    /// The variable `port` (instance index, variable).
    pub(crate) fn lookup(&self, port: &str) -> Result<(usize, &ScalarVariable)> {
        let port = Port::parse(port).map_err(config)?;
        let instance = self.index_of(&port.instance)?;
        let variable = self.components[instance]
            .fmu
            .variable(&port.variable)
            .map_err(|source| MasterError::Host {
                instance: port.instance.clone(),
                source,
            })?;
        Ok((instance, variable))
    }

    /// Checks the system and resolves every connection.
    pub(crate) fn resolve(&self) -> Result<Vec<Link>> {
        for (i, c) in self.components.iter().enumerate() {
            if c.name.is_empty() || c.name.contains('.') {
                return Err(config(format!(
                    "instance name {:?} must be non-empty and without a dot",
                    c.name
                )));
            }
            if self.components[..i].iter().any(|o| o.name == c.name) {
                return Err(config(format!("two instances are named {:?}", c.name)));
            }
        }
        let mut links: Vec<Link> = Vec::with_capacity(self.connections.len());
        for connection in &self.connections {
            let (from_instance, from) = self.lookup(&connection.from)?;
            let (to_instance, to) = self.lookup(&connection.to)?;
            if from.causality != Causality::Output {
                return Err(config(format!(
                    "{connection}: {} is not an output",
                    connection.from
                )));
            }
            if to.causality != Causality::Input {
                return Err(config(format!(
                    "{connection}: {} is not an input",
                    connection.to
                )));
            }
            if from.variable_type != VariableType::Real || to.variable_type != VariableType::Real {
                return Err(config(format!(
                    "{connection}: only Real variables can be connected"
                )));
            }
            if let Some(other) = links
                .iter()
                .find(|l| l.to_instance == to_instance && l.to_vr == to.value_reference)
            {
                return Err(config(format!(
                    "{} is connected twice ({} and {connection})",
                    connection.to, other.name
                )));
            }
            let from_cs = self.components[from_instance]
                .fmu
                .model_description()
                .co_simulation
                .clone()
                .unwrap_or_default();
            let to_cs = self.components[to_instance]
                .fmu
                .model_description()
                .co_simulation
                .clone()
                .unwrap_or_default();
            links.push(Link {
                name: connection.to_string(),
                to: connection.to.clone(),
                from_instance,
                from_vr: from.value_reference,
                to_instance,
                to_vr: to.value_reference,
                nominal: from.nominal.unwrap_or(1.0).abs().max(f64::MIN_POSITIVE),
                source_has_derivatives: from_cs.max_output_derivative_order >= 1,
                consumer_interpolates: to_cs.can_interpolate_inputs,
            });
        }
        Ok(links)
    }

    /// The order in which to copy the connections so that every output is read after all the
    /// inputs it depends on directly have been set (a topological order of the feedthrough
    /// graph, read from each FMU's `ModelStructure`). [`MasterError::AlgebraicLoop`] when there
    /// is none.
    pub(crate) fn exchange_order(&self, links: &[Link]) -> Result<Vec<usize>> {
        let structure = |instance: usize| &self.components[instance].fmu.model_description().model_structure;
        // before[j]: the links whose input the source output of link j depends on.
        let before: Vec<Vec<usize>> = links
            .iter()
            .map(|lj| {
                links
                    .iter()
                    .enumerate()
                    .filter(|(_, li)| {
                        li.to_instance == lj.from_instance
                            && structure(lj.from_instance).output_depends_on(lj.from_vr, li.to_vr)
                    })
                    .map(|(i, _)| i)
                    .collect()
            })
            .collect();
        let mut order = Vec::with_capacity(links.len());
        let mut done = vec![false; links.len()];
        while order.len() < links.len() {
            // The first ready link in declaration order: deterministic.
            let ready = (0..links.len()).find(|&j| !done[j] && before[j].iter().all(|&i| done[i]));
            match ready {
                Some(j) => {
                    done[j] = true;
                    order.push(j);
                }
                None => {
                    return Err(MasterError::AlgebraicLoop(
                        (0..links.len())
                            .filter(|&j| !done[j])
                            .map(|j| links[j].name.clone())
                            .collect(),
                    ))
                }
            }
        }
        Ok(order)
    }
}

/// A resolved connection.
#[derive(Clone, Debug)]
pub(crate) struct Link {
    /// `"a.y -> b.u"`.
    pub name: String,
    /// The input, `"instance.variable"`.
    pub to: String,
    pub from_instance: usize,
    pub from_vr: ValueReference,
    pub to_instance: usize,
    pub to_vr: ValueReference,
    /// Scale below which differences count as absolute (the output's `nominal`, default 1).
    pub nominal: f64,
    /// The source declares `maxOutputDerivativeOrder >= 1`.
    pub source_has_derivatives: bool,
    /// The consumer declares `canInterpolateInputs`.
    pub consumer_interpolates: bool,
}
