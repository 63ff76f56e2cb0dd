//! modelDescription.xml, generated from a model's variable table (never written by hand).
//!
//! The ModelStructure (FMI 2.0, section 2.2.8) lists the outputs, the state derivatives and the
//! initial unknowns with their dependencies. The dependencies are found by evaluating the
//! model's own equations: each known (input, state, and at initialization each parameter) is
//! perturbed in turn at two well-separated operating points at a generic time, for every value of each integer
//! and boolean parameter, and an unknown depends on the known if its value moved. A model whose
//! equations panic at such a point gets no `dependencies` attribute at all, which FMI reads as
//! "depends on every known" — conservative, never wrong.
//!
//! The guid is a hash of the generated XML (with the guid left out), so any change of the
//! variables, units or structure gives a new guid, and the binary computes the same guid from
//! the same code at run time to check the `fmuGUID` a master passes to fmi2Instantiate.

use std::collections::BTreeSet;
use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::model::Model;
use crate::standards::Standard;
use crate::values::Values;
use crate::variables::{Causality, Initial, Slot, Variable, VariableTable};

/// What a model says about itself: its variables, the structure of its equations, its problems,
/// and the modelDescription.xml of each standard written from them.
pub struct ModelDescription {
    /// Each exported standard's XML and token (`standards::ALL` order).
    pub documents: Vec<(Standard, Document)>,
    /// The model crate's version, authors, license and source date (in the XML's header).
    pub package: Package,
    pub table: VariableTable,
    pub structure: Structure,
    /// What is wrong with the model (its declarations, or a computed variable its equations
    /// never write): "file:line: rule. Fix: ...". A model with problems is not exported.
    pub problems: Vec<String>,
}

/// What the model crate's Cargo.toml says about it, and when its source was made. `export_fmu!`
/// fills it in where it expands, in the model crate at compile time (`CARGO_PKG_VERSION`, ...,
/// `SOURCE_DATE_EPOCH`), so the description the binary writes at run time is byte for byte the
/// one build-fmus packaged: same XML, same guid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Package {
    /// `CARGO_PKG_VERSION`: the FMU's `version`.
    pub version: &'static str,
    /// `CARGO_PKG_AUTHORS`, colon-separated as cargo gives them: `author` and `copyright`.
    pub authors: &'static str,
    /// `CARGO_PKG_LICENSE`, an SPDX expression: `license`.
    pub license: &'static str,
    /// `SOURCE_DATE_EPOCH` when the model crate was compiled (seconds since 1970-01-01 UTC; build-fmus
    /// sets it to the date of the source's last commit unless it is set): `generationDateAndTime`.
    pub source_date_epoch: Option<&'static str>,
}

impl Package {
    /// The authors, comma-separated.
    pub fn authors(&self) -> String {
        self.authors.split(':').map(str::trim).filter(|a| !a.is_empty()).collect::<Vec<_>>().join(", ")
    }

    /// The source date as an xs:dateTime ("2026-12-01T21:46:29Z"), if it is a number of seconds.
    pub fn generation_date_and_time(&self) -> Option<String> {
        self.source_date_epoch.and_then(|s| s.trim().parse::<i64>().ok()).map(utc_date_time)
    }

    /// "Copyright (c) <year of the source date> <authors>", if there are authors.
    pub fn copyright(&self) -> Option<String> {
        let authors = self.authors();
        if authors.is_empty() {
            return None;
        }
        Some(match self.generation_date_and_time() {
            Some(date) => format!("Copyright (c) {} {authors}", &date[..4]),
            None => format!("Copyright (c) {authors}"),
        })
    }

    /// The attributes of `fmiModelDescription` it gives, in the schema's order (empty ones left out).
    pub fn attributes(&self) -> Vec<(&'static str, String)> {
        let mut a = Vec::new();
        let authors = self.authors();
        if !authors.is_empty() {
            a.push(("author", authors));
        }
        if !self.version.is_empty() {
            a.push(("version", self.version.to_string()));
        }
        if let Some(c) = self.copyright() {
            a.push(("copyright", c));
        }
        if !self.license.is_empty() {
            a.push(("license", self.license.to_string()));
        }
        a
    }
}

/// Seconds since 1970-01-01 UTC as an xs:dateTime in UTC, "YYYY-MM-DDThh:mm:ssZ" (the proleptic
/// Gregorian calendar, days to civil date as in H. Hinnant's `civil_from_days`).
pub fn utc_date_time(epoch: i64) -> String {
    let (days, secs) = (epoch.div_euclid(86_400), epoch.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z", secs / 3600, secs % 3600 / 60, secs % 60)
}

/// The computed variables (outputs, locals, calculated parameters) that `Model::outputs` leaves
/// unwritten in some configuration of the structural parameters: each would show a stale value.
fn unwritten<M: Model>(model: &M, table: &VariableTable, t: f64) -> Vec<String> {
    // A NaN with a payload no arithmetic produces: still there after `outputs`, never written.
    let sentinel = f64::from_bits(0x7ff8_dead_beef_f00d);
    let mut problems = Vec::new();
    let defaults = table.start_values();
    for config in configurations(table) {
        let Some(values) = probe_points(table, &config).into_iter().next() else { continue };
        let mut calculated = vec![sentinel; table.n_calculated];
        let mut derivatives = vec![0.0; table.n_states];
        let evaluated = catch_unwind(AssertUnwindSafe(|| {
            crate::model::evaluate(model, table, t, &values.known, &values.states, &values.integers, &values.booleans, &mut derivatives, &mut calculated)
        }));
        if evaluated.is_err() {
            continue; // a model that panics here is reported when it runs
        }
        problems.extend(unreported_powers(model, table, t, &values, &config, &defaults, &problems));
        for (pos, var) in table.variables.iter().enumerate() {
            let Slot::Calculated(i) = var.slot else { continue };
            if calculated[i].to_bits() != sentinel.to_bits() || problems.iter().any(|p: &String| p.contains(&format!("'{}'", var.name))) {
                continue;
            }
            let when = configuration_text(table, &config, &defaults);
            let at = table.declared_at[pos];
            problems.push(format!(
                "{}:{}: {} '{}' is never written by Model::outputs{when}. Fix: assign out[self.<handle>] = ... for it in outputs(), in every configuration",
                at.file(),
                at.line(),
                var.causality.as_str(),
                var.name
            ));
        }
    }
    problems
}

/// The structural choices of `config` that differ from the defaults, as " (with level = 2)".
fn configuration_text(table: &VariableTable, config: &Values, defaults: &Values) -> String {
    let changed: Vec<String> = table
        .variables
        .iter()
        .filter_map(|v| match v.slot {
            Slot::Integer(j) if config.integers[j] != defaults.integers[j] => Some(format!("{} = {}", v.name, config.integers[j])),
            Slot::Boolean(j) if config.booleans[j] != defaults.booleans[j] => Some(format!("{} = {}", v.name, config.booleans[j])),
            _ => None,
        })
        .collect();
    if changed.is_empty() {
        String::new()
    } else {
        format!(" (with {})", changed.join(", "))
    }
}

/// The declared elements whose power `Model::derivatives` does not report (`der.power`) at
/// one point of a configuration: their activity would stay 0 and the energy balance would
/// leave them out. `known` lists problems already found (one per element is enough).
fn unreported_powers<M: Model>(model: &M, table: &VariableTable, t: f64, values: &Values, config: &Values, defaults: &Values, known: &[String]) -> Vec<String> {
    if table.elements.is_empty() {
        return Vec::new();
    }
    let (mut rates, mut powers) = (vec![0.0; table.n_states], vec![0.0; table.elements.len()]);
    let run = catch_unwind(AssertUnwindSafe(|| {
        crate::model::evaluate_powers(model, t, &values.known, &values.states, &values.integers, &values.booleans, &mut rates, &mut powers)
    }));
    if run.is_err() {
        return Vec::new();
    }
    let mut problems = Vec::new();
    for (e, p) in table.elements.iter().zip(&powers) {
        let Some(s) = e.activity_state else { continue };
        let tag = format!("element '{}'", e.name);
        if !p.is_nan() || known.iter().any(|k| k.contains(&tag)) {
            continue;
        }
        let at = table.declared_at[table.state_value_reference[s] as usize];
        problems.push(format!(
            "{}:{}: {tag} has no power reported by Model::derivatives{}. Fix: call der.power(self.<element>, p) for it in derivatives(), \
             in every configuration (p = 0 where the configuration leaves it out)",
            at.file(),
            at.line(),
            configuration_text(table, config, defaults)
        ));
    }
    problems
}

/// The outputs that nothing moves while the model runs: no input, no state (their ModelStructure
/// dependencies are empty), not time and not a discrete mode, in any configuration of the
/// structural parameters. Such an output is a constant a master would read as a signal: usually
/// an equation that forgot its state or input.
fn constant_outputs<M: Model>(model: &M, table: &VariableTable, structure: &Structure, t: f64) -> Vec<String> {
    let mut problems = Vec::new();
    let later = t + 0.613 * (t.abs() + 1.0);
    for (vr, deps) in &structure.outputs {
        if !deps.as_ref().is_some_and(|d| d.is_empty()) {
            continue;
        }
        let Some(pos) = table.variables.iter().position(|v| value_reference_of(v) == *vr) else { continue };
        let var = &table.variables[pos];
        let mut moves = false;
        'configs: for config in configurations(table) {
            for values in probe_points(table, &config) {
                let Some(p0) = evaluate(model, table, t, &values, false) else { return problems };
                let value = |p: &Point| unknown_value(var, p);
                // Time, then each integer and boolean slot (modes included), moved in turn.
                let mut trials = vec![evaluate(model, table, later, &values, false)];
                for i in 0..values.integers.len() {
                    let mut v = values.clone();
                    v.integers[i] = if v.integers[i] < i32::MAX { v.integers[i] + 1 } else { v.integers[i] - 1 };
                    trials.push(evaluate(model, table, t, &v, false));
                }
                for i in 0..values.booleans.len() {
                    let mut v = values.clone();
                    v.booleans[i] = !v.booleans[i];
                    trials.push(evaluate(model, table, t, &v, false));
                }
                // A tunable parameter moves an output while the instance steps (a set point echoed
                // to an output is a signal, not a constant).
                for tunable in table.variables.iter().filter(|v| v.is_settable_while_stepping()) {
                    if let Slot::Known(i) = tunable.slot {
                        let mut v = values.clone();
                        v.known[i] = if v.known[i] == 0.0 { 1.0 } else { 2.0 * v.known[i] };
                        trials.push(evaluate(model, table, t, &v, false));
                    }
                }
                if trials.iter().flatten().any(|p1| matches!((value(&p0), value(p1)), (Some(a), Some(b)) if moved(a, b))) {
                    moves = true;
                    break 'configs;
                }
            }
        }
        if !moves {
            let at = table.declared_at[pos];
            problems.push(format!(
                "{}:{}: output '{}' depends on nothing: no input, state, time or mode moves it, it is a constant. Fix: compute it from the states or inputs it stands for in outputs(), or declare it as a parameter",
                at.file(),
                at.line(),
                var.name
            ));
        }
    }
    problems
}

/// Whether two problems name the same variable (the first quoted name in each).
fn same_variable(a: &str, b: &str) -> bool {
    let name = |s: &str| s.split('\'').nth(1).map(str::to_owned);
    name(a).is_some() && name(a) == name(b)
}

/// Dependencies of one unknown: the value references of the knowns it depends on, or `None`
/// for "every known".
pub type Dependencies = Option<BTreeSet<usize>>;

/// The ModelStructure: (value reference of the unknown, its dependencies) for each list. Each
/// standard's writer says it in its own terms (FMI 2.0: 1-based indices).
#[derive(Debug, Default)]
pub struct Structure {
    pub outputs: Vec<(usize, Dependencies)>,
    pub derivatives: Vec<(usize, Dependencies)>,
    pub initial_unknowns: Vec<(usize, Dependencies)>,
}

/// Formats a real for XML: shortest round-trip text, with an exponent for very small or large.
pub fn real_text(v: f64) -> String {
    crate::variables::number(v)
}

fn value_reference_of(var: &Variable) -> usize {
    var.value_reference as usize
}

/// The values of every unknown at one point: calculated reals, derivatives, and the states
/// (which, at initialization, include the model's calculated initial states).
struct Point {
    calculated: Vec<f64>,
    derivatives: Vec<f64>,
    states: Vec<f64>,
}

/// All unknowns evaluated at one point (the knowns and states of `values`). At initialization
/// (`initial`), the calculated states are first computed from the knowns, as the instance does.
fn evaluate<M: Model>(model: &M, table: &VariableTable, t: f64, values: &Values, initial: bool) -> Option<Point> {
    let mut p = Point { calculated: values.calculated.clone(), derivatives: values.derivatives.clone(), states: values.states.clone() };
    catch_unwind(AssertUnwindSafe(|| {
        if initial {
            crate::model::initialize_states(model, table, t, &values.known, &values.integers, &values.booleans, &mut p.states).ok()?;
        }
        crate::model::evaluate(model, table, t, &values.known, &p.states, &values.integers, &values.booleans, &mut p.derivatives, &mut p.calculated);
        Some(())
    }))
    .ok()??;
    Some(p)
}

fn unknown_value(var: &Variable, p: &Point) -> Option<f64> {
    match var.slot {
        Slot::Calculated(i) => Some(p.calculated[i]),
        Slot::Derivative(i) => Some(p.derivatives[i]),
        Slot::State(s) => Some(p.states[s]),
        _ => None,
    }
}

fn moved(a: f64, b: f64) -> bool {
    !(a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()))
}

/// A known that can be perturbed.
#[derive(Clone, Copy)]
enum Known<'a> {
    Real(&'a Variable, usize),
    State(&'a Variable, usize),
    Integer(&'a Variable, usize),
    Boolean(&'a Variable, usize),
}

impl Known<'_> {
    fn variable(&self) -> &Variable {
        match self {
            Known::Real(v, _) | Known::State(v, _) | Known::Integer(v, _) | Known::Boolean(v, _) => v,
        }
    }

    /// Moves a real known (an input, a parameter or a state) to its value in a far point;
    /// false for integers and booleans, which `perturb` already moves by a whole step.
    fn jump(&self, values: &mut Values, far: &Values) -> bool {
        match *self {
            Known::Real(_, i) => values.known[i] = far.known[i],
            Known::State(_, s) => values.states[s] = far.states[s],
            Known::Integer(..) | Known::Boolean(..) => return false,
        }
        true
    }

    fn perturb(&self, values: &mut Values) {
        let step = |x: f64| x + 1e-3 * (x.abs() + 1.0);
        match *self {
            Known::Real(_, i) => values.known[i] = step(values.known[i]),
            Known::State(_, s) => values.states[s] = step(values.states[s]),
            Known::Integer(v, i) => {
                let n = values.integers[i];
                let max = v.max.map(|m| m as i32).unwrap_or(i32::MAX);
                values.integers[i] = if n < max { n + 1 } else { n - 1 };
            }
            Known::Boolean(_, i) => values.booleans[i] = !values.booleans[i],
        }
    }
}

/// The operating points at which dependencies are probed: the start values with states and
/// inputs moved off zero (where a product such as x*u would hide a dependency), once upward,
/// once downward with different offsets.
fn probe_points(table: &VariableTable, base: &Values) -> Vec<Values> {
    let nominals = table.state_nominals();
    [(0.31, 0.17), (-0.53, 0.29)]
        .iter()
        .map(|(offset, spread)| {
            let mut v = base.clone();
            for (s, x) in v.states.iter_mut().enumerate() {
                *x += (offset + spread * s as f64) * nominals[s];
            }
            for (j, var) in table.variables.iter().filter(|v| v.causality == Causality::Input).enumerate() {
                if let Slot::Known(i) = var.slot {
                    v.known[i] += offset + spread * j as f64;
                }
            }
            v
        })
        .collect()
}

/// Operating points far from the start values (states and inputs moved by 1.5 and 2.5 times
/// their magnitude plus nominal, down and up): a threshold, a saturation or a latch in the
/// equations is flat near the start and moves only there. Equations may fail at such a point
/// (a square root of a negative value): the point is then skipped, not held against the model.
fn far_points(table: &VariableTable, base: &Values) -> Vec<Values> {
    let nominals = table.state_nominals();
    [-1.5, 2.5]
        .iter()
        .map(|c| {
            let mut v = base.clone();
            for (s, x) in v.states.iter_mut().enumerate() {
                let x0 = *x;
                *x = x0 + c * (x0.abs() + nominals[s]) * (1.0 + 0.1 * s as f64);
            }
            for (j, var) in table.variables.iter().filter(|v| v.causality == Causality::Input).enumerate() {
                if let Slot::Known(i) = var.slot {
                    let u0 = v.known[i];
                    v.known[i] = u0 + c * (u0.abs() + 1.0) * (1.0 + 0.1 * j as f64);
                }
            }
            v
        })
        .collect()
}

/// Every configuration of the structural (integer and boolean) parameters worth probing:
/// the defaults, then each one moved through its declared range with the others at default.
fn configurations(table: &VariableTable) -> Vec<Values> {
    let base = table.start_values();
    let mut configs = vec![base.clone()];
    for var in &table.variables {
        match var.slot {
            Slot::Integer(i) => {
                if let (Some(min), Some(max)) = (var.min, var.max) {
                    for n in (min as i32..=max as i32).take(16) {
                        if n != base.integers[i] {
                            let mut c = base.clone();
                            c.integers[i] = n;
                            configs.push(c);
                        }
                    }
                }
            }
            Slot::Boolean(i) => {
                let mut c = base.clone();
                c.booleans[i] = !c.booleans[i];
                configs.push(c);
            }
            _ => {}
        }
    }
    configs
}

/// For each unknown (by position in `unknowns`), the knowns it depends on; `initial`: at
/// initialization (the calculated states are unknowns computed from the knowns).
fn dependencies<M: Model>(model: &M, table: &VariableTable, unknowns: &[&Variable], knowns: &[Known], t: f64, initial: bool) -> Vec<Dependencies> {
    let mut deps: Vec<Dependencies> = vec![Some(BTreeSet::new()); unknowns.len()];
    for config in configurations(table) {
        let far = far_points(table, &config);
        for values in probe_points(table, &config) {
            let Some(p0) = evaluate(model, table, t, &values, initial) else {
                return vec![None; unknowns.len()];
            };
            let mut record = |known: &Known, p1: &Point| {
                for (u, dep) in unknowns.iter().zip(deps.iter_mut()) {
                    let (a, b) = (unknown_value(u, &p0), unknown_value(u, p1));
                    if let (Some(a), Some(b), Some(set)) = (a, b, dep.as_mut()) {
                        if moved(a, b) {
                            set.insert(value_reference_of(known.variable()));
                        }
                    }
                }
            };
            for known in knowns {
                let mut v = values.clone();
                known.perturb(&mut v);
                let Some(p1) = evaluate(model, table, t, &v, initial) else {
                    return vec![None; unknowns.len()];
                };
                record(known, &p1);
                // A threshold in the equations is flat under a small perturbation: also jump
                // this one known to each far point (where the equations may fail: skipped).
                for far_values in &far {
                    let mut v = values.clone();
                    if known.jump(&mut v, far_values) && (v.known != values.known || v.states != values.states) {
                        if let Some(p1) = evaluate(model, table, t, &v, initial) {
                            record(known, &p1);
                        }
                    }
                }
            }
        }
    }
    deps
}

/// The ModelStructure of a model, from its equations.
pub fn structure<M: Model>(model: &M, table: &VariableTable, t: f64) -> Structure {
    let vars = &table.variables;
    let calculated_state = |v: &Variable| table.state_index(v).is_some() && v.initial == Some(Initial::Calculated);
    // Knowns while stepping: inputs and states.
    let mut run_knowns = Vec::new();
    // Knowns at initialization: also parameters (and state start values).
    let mut init_knowns = Vec::new();
    for v in vars {
        let k = match v.slot {
            Slot::Known(i) => Known::Real(v, i),
            Slot::State(s) => Known::State(v, s),
            // Discrete modes (Integer locals) are no knowns: they hold between events.
            Slot::Integer(i) if v.causality == Causality::Parameter => Known::Integer(v, i),
            Slot::Boolean(i) => Known::Boolean(v, i),
            _ => continue,
        };
        if matches!(k, Known::State(..)) || v.causality == Causality::Input {
            run_knowns.push(k);
        }
        // A calculated state is an unknown at initialization, not a known.
        if !calculated_state(v) {
            init_knowns.push(k);
        }
    }
    let outputs: Vec<&Variable> = vars.iter().filter(|v| v.causality == Causality::Output).collect();
    let derivatives: Vec<&Variable> = vars.iter().filter(|v| v.derivative_of.is_some()).collect();
    let initial: Vec<&Variable> = vars
        .iter()
        .filter(|v| {
            (v.causality == Causality::Output && v.initial != Some(Initial::Exact))
                || v.causality == Causality::CalculatedParameter
                || (v.derivative_of.is_some() && v.initial == Some(Initial::Calculated))
                || calculated_state(v)
        })
        .collect();
    let zip = |us: &[&Variable], ds: Vec<Dependencies>| us.iter().map(|u| value_reference_of(u)).zip(ds).collect::<Vec<_>>();
    Structure {
        outputs: zip(&outputs, dependencies(model, table, &outputs, &run_knowns, t, false)),
        derivatives: zip(&derivatives, dependencies(model, table, &derivatives, &run_knowns, t, false)),
        initial_unknowns: zip(&initial, dependencies(model, table, &initial, &init_knowns, t, true)),
    }
}

/// One standard's modelDescription.xml and its token (FMI 2.0 `guid`, FMI 3.0
/// `instantiationToken`): a hash of the XML with the token left out.
#[derive(Clone, Debug)]
pub struct Document {
    pub xml: String,
    pub token: String,
}

impl Document {
    /// Stamps a draft written with `xml::TOKEN_PLACEHOLDER` with the hash of its content.
    fn stamped(draft: String) -> Document {
        let token = crate::xml::token_of(&draft);
        Document { xml: draft.replacen(crate::xml::TOKEN_PLACEHOLDER, &token, 1), token }
    }
}

impl ModelDescription {
    /// One standard's XML and token.
    pub fn document(&self, standard: Standard) -> &Document {
        &self.documents.iter().find(|(s, _)| *s == standard).expect("every standard of standards::ALL").1
    }

    /// The description of a model with no package information (the runtime's own tests).
    pub fn of<M: Model>() -> ModelDescription {
        Self::with_package::<M>(&Package::default())
    }

    /// The description of a model crate: `export_fmu!` passes its Cargo metadata and source date.
    pub fn with_package<M: Model>(package: &Package) -> ModelDescription {
        let (model, _, table) = crate::model::declare::<M>();
        // Probe at a generic time inside the default experiment, not at its start, where a
        // sine source would hide its amplitude (sin 0 = 0).
        let e = M::info().default_experiment;
        let probe_time = e.start_time + 0.2371 * (e.stop_time - e.start_time) + 0.0137;
        let structure = structure(&model, &table, probe_time);
        let mut problems = table.problems.clone();
        problems.extend(unwritten(&model, &table, probe_time));
        let constant = constant_outputs(&model, &table, &structure, probe_time);
        // An output never written is constant too: it is reported once, as never written.
        let fresh: Vec<String> = constant.into_iter().filter(|c| !problems.iter().any(|p| same_variable(p, c))).collect();
        problems.extend(fresh);
        let documents = crate::standards::ALL.iter().map(|s| (*s, Document::stamped(s.write_xml::<M>(&table, &structure, package)))).collect();
        ModelDescription { documents, package: *package, table, structure, problems }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_model::Decay;

    #[test]
    fn dependencies_come_from_the_equations() {
        let d = ModelDescription::of::<Decay>();
        // value references: a=0, u=1, x=2, der(x)=3, y=4, w=5
        let s = &d.structure;
        let set = |v: &[usize]| Some(v.iter().copied().collect::<BTreeSet<_>>());
        assert_eq!(s.outputs, vec![(4, set(&[2])), (5, set(&[1]))]);
        assert_eq!(s.derivatives, vec![(3, set(&[1, 2]))]);
        assert_eq!(s.initial_unknowns, vec![(3, set(&[0, 1, 2])), (4, set(&[2])), (5, set(&[0, 1]))]);
        // FMI 2.0 says it in 1-based indices.
        assert!(d.document(Standard::Fmi2).xml.contains(r#"<Unknown index="4" dependencies="2 3"/>"#), "{}", d.document(Standard::Fmi2).xml);
    }

    #[test]
    fn fmi3_lists_the_same_structure_in_value_references_with_time_and_indicators() {
        let d = ModelDescription::of::<Decay>();
        let x = &d.document(Standard::Fmi3).xml;
        assert!(x.contains(r#"fmiVersion="3.0""#) && x.contains(&format!(r#"instantiationToken="{}""#, d.document(Standard::Fmi3).token)), "{x}");
        assert_ne!(d.document(Standard::Fmi3).token, d.document(Standard::Fmi2).token, "each version's token hashes its own XML");
        // Decay has no event indicator: time comes right after its own value references.
        let n = d.table.variables.len();
        assert!(x.contains(&format!(r#"<Float64 name="time" valueReference="{n}" description="Simulation time" causality="independent" variability="continuous" unit="s"/>"#)), "{x}");
        assert!(x.contains(r#"<Output valueReference="4" dependencies="2"/>"#), "{x}");
        assert!(x.contains(r#"<ContinuousStateDerivative valueReference="3" dependencies="1 2"/>"#), "{x}");
        assert!(x.contains(r#"<InitialUnknown valueReference="3" dependencies="0 1 2"/>"#), "{x}");
        assert!(x.contains(r#"derivative="2""#) && x.contains(r#"<Unit name="s">"#), "{x}");
        // An event indicator is a Float64 of FMI 3.0, after the model's own value references.
        let b = ModelDescription::of::<crate::test_model::Block>();
        let n = crate::model::declare::<crate::test_model::Block>().2.variables.len();
        assert!(b.document(Standard::Fmi3).xml.contains(&format!(r#"<EventIndicator valueReference="{n}"/>"#)), "{}", b.document(Standard::Fmi3).xml);
        assert!(b.document(Standard::Fmi3).xml.contains(&format!(r#"valueReference="{n}" description="Event indicator"#)), "{}", b.document(Standard::Fmi3).xml);
    }

    #[test]
    fn structural_choices_are_enumerations_with_their_items_in_both_versions() {
        let d = ModelDescription::of::<crate::test_model::Chooser>();
        assert!(d.problems.is_empty(), "{:?}", d.problems);
        let (x2, x3) = (&d.document(Standard::Fmi2).xml, &d.document(Standard::Fmi3).xml);
        let items = r#"<Item name="single" value="1" description="y = x"/>
      <Item name="double" value="2" description="y = 2 x"/>"#;
        assert!(x2.contains(&format!("<TypeDefinitions>\n    <SimpleType name=\"gain\">\n      <Enumeration>\n        {}", items.replace("\n      ", "\n        "))), "{x2}");
        assert!(x2.contains(r#"<Enumeration declaredType="gain" start="2" min="1" max="2"/>"#), "{x2}");
        assert!(x3.contains(&format!("<TypeDefinitions>\n    <EnumerationType name=\"gain\">\n      {items}")), "{x3}");
        assert!(x3.contains(r#"<Enumeration name="gain" valueReference="0" description="gain of the output" causality="parameter" variability="fixed" min="1" max="2" declaredType="gain" start="2"/>"#), "{x3}");
    }

    #[test]
    fn outputs_never_written_are_problems_naming_them() {
        let d = ModelDescription::of::<crate::test_model::Careless>();
        assert_eq!(d.problems.len(), 2, "{:#?}", d.problems);
        assert!(d.problems[0].contains("output 'forgotten' is never written by Model::outputs. Fix:"), "{}", d.problems[0]);
        assert!(d.problems[1].contains("output 'y' is never written by Model::outputs (with level = 2)"), "{}", d.problems[1]);
        assert!(d.problems.iter().all(|p| p.starts_with("fmu-runtime/src/test_model.rs:")), "{:#?}", d.problems);
        // Every model of the runtime's own tests is clean.
        assert!(ModelDescription::of::<Decay>().problems.is_empty());
        assert!(ModelDescription::of::<crate::test_model::Relax>().problems.is_empty());
    }

    #[test]
    fn unknown_units_are_problems_not_a_panic() {
        let d = ModelDescription::of::<crate::test_model::Furlong>();
        assert_eq!(d.problems.len(), 2, "{:#?}", d.problems);
        assert!(d.problems[0].contains("'length' has the unit 'furlong'"), "{}", d.problems[0]);
        assert!(d.problems[1].contains("'count' has no unit"), "{}", d.problems[1]);
        assert!(!d.document(Standard::Fmi2).xml.contains(r#"<Unit name="furlong">"#));
    }

    #[test]
    fn an_output_nothing_moves_is_a_problem_naming_it() {
        let d = ModelDescription::of::<crate::test_model::Frozen>();
        assert_eq!(d.problems.len(), 1, "{:#?}", d.problems);
        let p = &d.problems[0];
        assert!(p.starts_with("fmu-runtime/src/test_model.rs:"), "{p}");
        assert!(p.contains("output 'stuck' depends on nothing") && p.contains("Fix:"), "{p}");
        // An output only time moves ('clock') is a signal: FMI lists it with no dependencies;
        // so is one only a tunable parameter moves ('echo').
        assert!(d.document(Standard::Fmi2).xml.contains(r#"name="clock""#) && d.document(Standard::Fmi2).xml.contains(r#"name="echo""#));
    }

    #[test]
    fn calculated_states_are_initial_unknowns_without_start() {
        let d = ModelDescription::of::<crate::test_model::Relax>();
        // value references: p=0, g=1, steady=2, u=3, T=4, der(T)=5, y=6
        let set = |v: &[usize]| Some(v.iter().copied().collect::<BTreeSet<_>>());
        let s = &d.structure;
        // At initialization T = u + p/g (or u): it depends on every parameter and the input,
        // and so does y = T. der(T) = p - g (T - u) is 0 or p: the input cancels out.
        assert_eq!(s.initial_unknowns, vec![(4, set(&[0, 1, 2, 3])), (5, set(&[0, 1, 2])), (6, set(&[0, 1, 2, 3]))]);
        // While stepping, T is a known like any state.
        assert_eq!(s.outputs, vec![(6, set(&[4]))]);
        assert_eq!(s.derivatives, vec![(5, set(&[3, 4]))]);
        assert!(d.document(Standard::Fmi2).xml.contains(r#"<ScalarVariable name="T" valueReference="4" description="temperature" causality="local" variability="continuous" initial="calculated">"#), "{}", d.document(Standard::Fmi2).xml);
    }

    #[test]
    fn xml_is_escaped_and_guid_is_a_content_hash() {
        let d = ModelDescription::of::<Decay>();
        assert!(d.document(Standard::Fmi2).xml.contains("test &lt;model&gt; &amp; &quot;quotes&quot;"), "{}", d.document(Standard::Fmi2).xml);
        assert!(d.document(Standard::Fmi2).xml.contains(&format!("guid=\"{}\"", d.document(Standard::Fmi2).token)));
        assert!(!d.document(Standard::Fmi2).xml.contains(crate::xml::TOKEN_PLACEHOLDER));
        assert_eq!(d.document(Standard::Fmi2).token, ModelDescription::of::<Decay>().document(Standard::Fmi2).token, "deterministic");
        assert!(d.document(Standard::Fmi2).xml.contains(r#"<Real unit="Hz/s" derivative="3"/>"#) || d.document(Standard::Fmi2).xml.contains(r#"derivative="3""#));
        assert!(d.document(Standard::Fmi2).xml.contains(r#"<Unit name="Hz">"#));
    }

    #[test]
    fn modes_are_discrete_integer_locals_and_indicators_are_counted() {
        let d = ModelDescription::of::<crate::test_model::Block>();
        assert!(d.document(Standard::Fmi2).xml.contains(r#"numberOfEventIndicators="1""#), "{}", d.document(Standard::Fmi2).xml);
        assert!(
            d.document(Standard::Fmi2).xml.contains(r#"name="friction_mode" valueReference="8" description="-1 slipping backwards, 0 stuck, 1 slipping forwards" causality="local" variability="discrete" initial="calculated">"#),
            "{}",
            d.document(Standard::Fmi2).xml
        );
        assert!(d.document(Standard::Fmi2).xml.contains(r#"<Integer min="-1" max="1"/>"#), "no start for a calculated mode: {}", d.document(Standard::Fmi2).xml);
        assert!(d.document(Standard::Fmi2).xml.contains(r#"name="state_events""#));
        // Variable::is_mode, which the instance uses to skip mode bookkeeping: the modes, not other integers.
        let table = crate::model::declare::<crate::test_model::Block>().2;
        let modes: Vec<&str> = table.variables.iter().filter(|v| v.is_mode()).map(|v| v.name.as_str()).collect();
        assert_eq!(modes, ["friction_mode", "state_events"]);
        assert!(!crate::model::declare::<crate::test_model::Careless>().2.variables.iter().any(|v| v.is_mode()), "an integer parameter is no mode");
        // A mode is no known: no dependency names it (value references x=4, v=6, u=3 are; friction_mode is 8).
        for (_, deps) in d.structure.derivatives.iter().chain(&d.structure.outputs) {
            assert!(!deps.as_ref().is_some_and(|s| s.contains(&8)));
        }
        assert_eq!(ModelDescription::of::<Decay>().document(Standard::Fmi2).xml.contains(r#"numberOfEventIndicators="0""#), true);
    }

    #[test]
    fn the_package_gives_version_author_license_copyright_and_date() {
        let package = Package { version: "1.2.3", authors: "The X contributors:Ada", license: "MIT", source_date_epoch: Some("1764625589") };
        let d = ModelDescription::with_package::<Decay>(&package);
        assert!(
            d.document(Standard::Fmi2).xml.contains(r#"author="The X contributors, Ada" version="1.2.3" copyright="Copyright (c) 2025 The X contributors, Ada" license="MIT" generationTool="fmu-runtime"#),
            "{}",
            d.document(Standard::Fmi2).xml
        );
        assert!(d.document(Standard::Fmi2).xml.contains(r#"generationDateAndTime="2025-12-01T21:46:29Z" numberOfEventIndicators="0""#), "{}", d.document(Standard::Fmi2).xml);
        // The same package gives the same guid; another date another one (the date is in the hashed XML).
        assert_eq!(d.document(Standard::Fmi2).token, ModelDescription::with_package::<Decay>(&package).document(Standard::Fmi2).token);
        let later = Package { source_date_epoch: Some("1764625590"), ..package };
        assert_ne!(d.document(Standard::Fmi2).token, ModelDescription::with_package::<Decay>(&later).document(Standard::Fmi2).token);
        // Without a package (or an unreadable date) the attributes are left out, not made up.
        let bare = ModelDescription::of::<Decay>().document(Standard::Fmi2).xml.clone();
        let header = bare.lines().find(|l| l.starts_with("<fmiModelDescription")).unwrap();
        for attribute in [" author=", " version=", " copyright=", " license=", " generationDateAndTime="] {
            assert!(!header.contains(attribute), "{attribute}: {header}");
        }
        assert_eq!(Package { source_date_epoch: Some("yesterday"), ..package }.generation_date_and_time(), None);
    }

    #[test]
    fn dates_are_utc_xs_date_times() {
        assert_eq!(utc_date_time(0), "1970-01-01T00:00:00Z");
        assert_eq!(utc_date_time(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(utc_date_time(1_700_000_000), "2023-11-14T22:13:20Z");
        assert_eq!(utc_date_time(4_107_542_399), "2100-02-28T23:59:59Z");
        assert_eq!(utc_date_time(-1), "1969-12-31T23:59:59Z");
    }

    #[test]
    fn real_text_round_trips() {
        for v in [0.0, 1e-8, 0.01, 1.0, 11.72, 1.5e5, 6.5e6, -3.25, 1e300, 4.9e-324] {
            assert_eq!(real_text(v).parse::<f64>().unwrap(), v, "{}", real_text(v));
        }
    }
}
