//! modelDescription.xml, generated from a model's variable table (never written by hand).
//!
//! The ModelStructure (FMI 2.0, section 2.2.8) lists the outputs, the state derivatives and the
//! initial unknowns with their dependencies. The dependencies are found by evaluating the
//! model's own equations: each known (input, state, and at initialization each parameter) is
//! perturbed in turn at two well-separated operating points at a generic time, and at a third
//! where neighbouring states differ irregularly, for every value of each integer
//! and boolean parameter, and an unknown depends on the known if its value moved. A model whose
//! equations panic at such a point gets no `dependencies` attribute at all, which FMI reads as
//! "depends on every known" — conservative, never wrong.
//!
//! The token (FMI 2.0 `guid`, FMI 3.0 `instantiationToken`) is two hashes of the generated XML
//! (with the token left out): the first of the XML written without the ModelStructure's
//! dependency lists, the second of the whole XML. Any change of the variables, units, structure
//! or dependencies gives a new token, and the binary computes the first half from the same code
//! at run time, without probing the equations, to check the token a master passes to
//! fmi2Instantiate or fmi3Instantiate* (docs/DESIGN.md, "The token is checked without the
//! dependency probe").

use std::collections::{BTreeSet, HashSet};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Arc;

use crate::model::Model;
use crate::real::Real;
use crate::standards::Standard;
use crate::real::Dual;
use crate::trace::Tracing;
use crate::values::Values;
use crate::variables::{Causality, Initial, Slot, Variable, VariableTable};

/// What a model says about itself: its variables, the structure of its equations, its problems,
/// and the modelDescription.xml of each standard written from them.
pub struct ModelDescription {
    /// Each exported standard's XML and token (`standards::ALL` order).
    pub documents: Vec<(Standard, Document)>,
    /// The model crate's version, authors, license and source date (in the XML's header).
    pub package: Package,
    /// The variable table, shared with the library's instances.
    pub table: Arc<VariableTable>,
    pub structure: Structure,
    /// What is wrong with the model (its declarations, or a computed variable its equations
    /// never write): "file:line: rule. Fix: ...". A model with problems is not exported.
    pub problems: Vec<String>,
    /// The model's tolerance floor at its default parameters (`Model::tolerance_floor`), which
    /// sets the DefaultExperiment's tolerance.
    pub default_floor: Option<f64>,
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
    // The variables already reported (once each, in the first configuration that leaves them out).
    let mut reported = HashSet::new();
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
            if calculated[i].to_bits() != sentinel.to_bits() || !reported.insert(var.value_reference) {
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
        let Some(var) = table.get(*vr as u32) else { continue };
        let pos = *vr;
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

/// The variable a problem names (its first quoted name).
fn quoted_name(problem: &str) -> Option<String> {
    problem.split('\'').nth(1).map(str::to_owned)
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

impl Structure {
    /// The ModelStructure's lists of unknowns without their dependency lists (every one `None`):
    /// what the table alone says, in O(variables), without probing the equations. The first
    /// half of the token hashes the XML written with it.
    pub fn skeleton(table: &VariableTable) -> Structure {
        let lists = Unknowns::of(table);
        let none = |us: &[&Variable]| us.iter().map(|u| (value_reference_of(u), None)).collect();
        Structure { outputs: none(&lists.outputs), derivatives: none(&lists.derivatives), initial_unknowns: none(&lists.initial) }
    }
}

/// The unknowns of the ModelStructure's three lists, from the table.
struct Unknowns<'a> {
    outputs: Vec<&'a Variable>,
    derivatives: Vec<&'a Variable>,
    initial: Vec<&'a Variable>,
}

impl<'a> Unknowns<'a> {
    fn of(table: &'a VariableTable) -> Self {
        let vars = &table.variables;
        let calculated_state = |v: &Variable| table.state_index(v).is_some() && v.initial == Some(Initial::Calculated);
        Unknowns {
            outputs: vars.iter().filter(|v| v.causality == Causality::Output).collect(),
            derivatives: vars.iter().filter(|v| v.derivative_of.is_some()).collect(),
            initial: vars
                .iter()
                .filter(|v| {
                    (v.causality == Causality::Output && v.initial != Some(Initial::Exact))
                        || v.causality == Causality::CalculatedParameter
                        || (v.derivative_of.is_some() && v.initial == Some(Initial::Calculated))
                        || calculated_state(v)
                })
                .collect(),
        }
    }
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

/// `evaluate` into buffers `p` made by an earlier evaluation at the same configuration: the
/// probe evaluates the equations O(knowns) times per point, and making three state-sized vectors
/// each time cost it more than the equations. False where `evaluate` gives None.
fn evaluate_into<M: Model>(model: &M, table: &VariableTable, t: f64, values: &Values, initial: bool, p: &mut Point) -> bool {
    // Calculated values the equations leave unwritten keep the point's, as in `evaluate`.
    p.calculated.copy_from_slice(&values.calculated);
    catch_unwind(AssertUnwindSafe(|| {
        // The states are unknowns only at initialization (the calculated ones): else the
        // equations read the point's own, and `p.states` is not looked at.
        let states = if initial {
            p.states.copy_from_slice(&values.states);
            crate::model::initialize_states(model, table, t, &values.known, &values.integers, &values.booleans, &mut p.states).ok()?;
            &p.states
        } else {
            &values.states
        };
        crate::model::evaluate(model, table, t, &values.known, states, &values.integers, &values.booleans, &mut p.derivatives, &mut p.calculated);
        Some(())
    }))
    .ok()
    .flatten()
    .is_some()
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

    /// Puts the known back to its value in `base` (after `perturb`, `jump` or `perturb_real`).
    fn restore(&self, values: &mut Values, base: &Values) {
        match *self {
            Known::Real(_, i) => values.known[i] = base.known[i],
            Known::State(_, s) => values.states[s] = base.states[s],
            Known::Integer(_, i) => values.integers[i] = base.integers[i],
            Known::Boolean(_, i) => values.booleans[i] = base.booleans[i],
        }
    }

    /// Whether the known's value in `values` differs from its value in `base`.
    fn differs(&self, values: &Values, base: &Values) -> bool {
        match *self {
            Known::Real(_, i) => values.known[i] != base.known[i],
            Known::State(_, s) => values.states[s] != base.states[s],
            Known::Integer(_, i) => values.integers[i] != base.integers[i],
            Known::Boolean(_, i) => values.booleans[i] != base.booleans[i],
        }
    }

    /// Moves a real known (an input, a parameter or a state) by `scale` times the perturbation's
    /// step; false for integers and booleans.
    fn perturb_real(&self, values: &mut Values, scale: f64) -> bool {
        let step = |x: f64| x + scale * 1e-3 * (x.abs() + 1.0);
        match *self {
            Known::Real(_, i) => values.known[i] = step(values.known[i]),
            Known::State(_, s) => values.states[s] = step(values.states[s]),
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

/// A point where the states and inputs are moved off their start values irregularly (by
/// 0.23 to 0.64 of their nominal, pseudo-random in the index): at the regular points
/// neighbouring states differ by the same step (a ramp in the state index), where differences of
/// differences vanish, as the damping torques of a chain of shafts do in der(w[i]) (the torsional
/// chain's `D`, missed at initialization before this point was added). (A multiple of the golden
/// ratio's fractional part would not do: it is a ramp too, between its wraps.)
fn irregular_point(table: &VariableTable, base: &Values) -> Values {
    let nominals = table.state_nominals();
    // splitmix64 of the index, its top 53 bits as a fraction in [0, 1).
    let fraction = |k: usize| {
        let mut z = (k as u64).wrapping_add(1).wrapping_mul(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        (z ^ (z >> 31)) as f64 / 2f64.powi(64)
    };
    let step = |k: usize| 0.23 + 0.41 * fraction(k);
    let mut v = base.clone();
    for (s, x) in v.states.iter_mut().enumerate() {
        *x += step(s) * nominals[s];
    }
    for (j, var) in table.variables.iter().filter(|v| v.causality == Causality::Input).enumerate() {
        if let Slot::Known(i) = var.slot {
            v.known[i] += step(j);
        }
    }
    v
}

/// Adds `known` to the dependencies of each unknown that moves smoothly with it at the irregular
/// point: `p` holds the unknowns with the known moved by a step, 1/16 and 1/256 of it, and the
/// change must shrink at least 8 times with each (a linear dependency's shrinks 16 times). A change
/// of the last bits only (a sum that cancels, such as the energy balance's residual) does not
/// shrink with the step, and is not taken for a dependency there.
fn record_smooth(unknowns: &[&Variable], deps: &mut [Dependencies], known: &Known, p0: &Point, p: &[Point; 3]) {
    for (u, dep) in unknowns.iter().zip(deps.iter_mut()) {
        let change = |p: &Point| Some((unknown_value(u, p)? - unknown_value(u, p0)?).abs());
        if let (Some(d1), Some(d2), Some(d3), Some(set)) = (change(&p[0]), change(&p[1]), change(&p[2]), dep.as_mut()) {
            if d1.is_finite() && d2 > 0.0 && d1 >= 8.0 * d2 && d2 >= 8.0 * d3 {
                set.insert(value_reference_of(known.variable()));
            }
        }
    }
}

/// Adds `known` to the dependencies of each unknown whose value moved from `p0` to `p1`.
fn record(unknowns: &[&Variable], deps: &mut [Dependencies], known: &Known, p0: &Point, p1: &Point) {
    for (u, dep) in unknowns.iter().zip(deps.iter_mut()) {
        let (a, b) = (unknown_value(u, p0), unknown_value(u, p1));
        if let (Some(a), Some(b), Some(set)) = (a, b, dep.as_mut()) {
            if moved(a, b) {
                set.insert(value_reference_of(known.variable()));
            }
        }
    }
}

/// What one evaluation of the equations over [`Trace`](crate::trace::Trace) says at one point: for each unknown, the
/// knowns (by position in `knowns`) its value flowed from; and the knowns that may decide a branch
/// there (they reached a comparison, `min`, `abs`, ..., or left the trace through `value()`).
struct Traced {
    sets: Vec<Option<Vec<u32>>>,
    branching: Vec<u32>,
}

/// Every unknown evaluated over a scalar `R` at `values`, each known `seed(j, known)` (by
/// position in `knowns`; every other real a constant): the equations' reals (calculated,
/// derivatives, states) and a reader of one unknown's value. None where they panic or fail.
fn evaluate_over<M: Model, R: Real>(model: &M, table: &VariableTable, knowns: &[Known], t: f64, values: &Values, initial: bool, seed: impl Fn(usize, f64) -> Option<R>) -> Option<impl Fn(&Variable) -> Option<R>> {
    let mut known: Vec<R> = values.known.iter().map(|&x| R::from(x)).collect();
    let mut states: Vec<R> = values.states.iter().map(|&x| R::from(x)).collect();
    for (j, k) in knowns.iter().enumerate() {
        match *k {
            Known::Real(_, i) => known[i] = seed(j, values.known[i]).unwrap_or(known[i]),
            Known::State(_, s) => states[s] = seed(j, values.states[s]).unwrap_or(states[s]),
            // Integer and boolean knowns are in no trace: they are probed by value.
            Known::Integer(..) | Known::Boolean(..) => {}
        }
    }
    let mut derivatives: Vec<R> = values.derivatives.iter().map(|&x| R::from(x)).collect();
    let mut calculated: Vec<R> = values.calculated.iter().map(|&x| R::from(x)).collect();
    catch_unwind(AssertUnwindSafe(|| {
        if initial {
            crate::model::initialize_states(model, table, t, &known, &values.integers, &values.booleans, &mut states).ok()?;
        }
        crate::model::evaluate(model, table, t, &known, &states, &values.integers, &values.booleans, &mut derivatives, &mut calculated);
        Some(())
    }))
    .ok()??;
    Some(move |u: &Variable| match u.slot {
        Slot::Calculated(i) => Some(calculated[i]),
        Slot::Derivative(i) => Some(derivatives[i]),
        Slot::State(s) => Some(states[s]),
        _ => None,
    })
}

/// The equations evaluated once over [`Trace`](crate::trace::Trace) at `values`, each known seeded with its position
/// in `knowns` (every other real is a constant): None where they panic or fail there.
fn traced<M: Model>(model: &M, table: &VariableTable, unknowns: &[&Variable], knowns: &[Known], t: f64, values: &Values, initial: bool) -> Option<Traced> {
    let tracing = Tracing::start();
    let unknown = evaluate_over(model, table, knowns, t, values, initial, |j, x| Some(tracing.known(j as u32, x)))?;
    let sets = unknowns.iter().map(|u| unknown(u).map(|v| tracing.dependencies(v))).collect();
    Some(Traced { sets, branching: tracing.compared() })
}

/// Colors the knowns (by position in `knowns`) so that no two of one color reach the same
/// unknown in `sets` (greedy, in order): one evaluation over [`Dual`] seeded along all the knowns
/// of a color gives each unknown's derivative by each of its knowns of that color apart.
fn colors(n_knowns: usize, sets: &[Option<Vec<u32>>]) -> Vec<usize> {
    let mut rows_of: Vec<Vec<usize>> = vec![Vec::new(); n_knowns];
    for (r, set) in sets.iter().enumerate() {
        for &j in set.iter().flatten() {
            rows_of[j as usize].push(r);
        }
    }
    let mut color = vec![usize::MAX; n_knowns];
    let mut taken: Vec<usize> = Vec::new();
    for j in 0..n_knowns {
        taken.clear();
        for &r in &rows_of[j] {
            taken.extend(sets[r].iter().flatten().map(|&i| color[i as usize]).filter(|&c| c != usize::MAX));
        }
        taken.sort_unstable();
        taken.dedup();
        color[j] = taken.iter().enumerate().find(|(c, t)| *c != **t).map_or(taken.len(), |(c, _)| c);
    }
    color
}

/// Of each unknown's traced knowns (`sets`, at `values`), those the unknown's derivative by is
/// not exactly 0 there: the equations evaluated over [`Dual`] once per color of the knowns
/// (`colors`). A known that flows into an unknown only to cancel out (der(T) = p - g (T - u) with
/// T = u + p/g at initialization: the input u) has the exact derivative 0. None where the
/// equations fail.
#[allow(clippy::too_many_arguments)]
fn nonzero<M: Model>(model: &M, table: &VariableTable, unknowns: &[&Variable], knowns: &[Known], t: f64, values: &Values, initial: bool, sets: &[Option<Vec<u32>>]) -> Option<Vec<Vec<u32>>> {
    let color = colors(knowns.len(), sets);
    let n_colors = color.iter().filter(|&&c| c != usize::MAX).map(|c| c + 1).max().unwrap_or(0);
    let mut found: Vec<Vec<u32>> = vec![Vec::new(); unknowns.len()];
    for c in 0..n_colors {
        let unknown = evaluate_over(model, table, knowns, t, values, initial, |j, x| (color[j] == c).then_some(Dual { re: x, eps: 1.0 }))?;
        for ((u, set), found) in unknowns.iter().zip(sets).zip(found.iter_mut()) {
            if unknown(u).is_some_and(|v| v.eps != 0.0) {
                found.extend(set.iter().flatten().filter(|&&j| color[j as usize] == c));
            }
        }
    }
    Some(found)
}

/// For each unknown (by position in `unknowns`), the knowns it depends on; `initial`: at
/// initialization (the calculated states are unknowns computed from the knowns).
///
/// The equations are evaluated once over [`Trace`](crate::trace::Trace) at each probe point (two regular ones and
/// the irregular one) of each configuration of the structural parameters: an unknown depends on
/// the knowns its value flowed from and its derivative by which is not exactly 0 (`nonzero`:
/// one evaluation over dual numbers per color of the knowns), at any of them. That sees every
/// dependency through arithmetic, at a cost linear in a sparse model's size. What it cannot see is a known that
/// decides a branch (`if w > w_max`, a relay, a step at `t >= t_step.value()`) without flowing into
/// the value at these points: the knowns that reached a comparison or left the trace there, and
/// the integer and boolean parameters, are probed by value as well (`probe_by_value`), one at a
/// time, moved a little and far.
fn dependencies<M: Model>(model: &M, table: &VariableTable, unknowns: &[&Variable], knowns: &[Known], t: f64, initial: bool) -> Vec<Dependencies> {
    let mut deps: Vec<Dependencies> = vec![Some(BTreeSet::new()); unknowns.len()];
    for config in configurations(table) {
        let mut branching = vec![false; knowns.len()];
        let regular = probe_points(table, &config);
        let irregular = irregular_point(table, &config);
        for (n, values) in regular.iter().chain(std::iter::once(&irregular)).enumerate() {
            let evaluated = traced(model, table, unknowns, knowns, t, values, initial).and_then(|traced| Some((nonzero(model, table, unknowns, knowns, t, values, initial, &traced.sets)?, traced.branching)));
            match evaluated {
                Some((sets, compared)) => {
                    for (dep, set) in deps.iter_mut().zip(&sets) {
                        if let Some(dep) = dep.as_mut() {
                            dep.extend(set.iter().map(|&j| value_reference_of(knowns[j as usize].variable())));
                        }
                    }
                    for j in compared {
                        branching[j as usize] = true;
                    }
                }
                // The equations fail at a regular point: no dependency list is safe.
                None if n < regular.len() => return vec![None; unknowns.len()],
                // The irregular point may be outside the equations' domain: skipped.
                None => {}
            }
        }
        let by_value: Vec<Known> = knowns
            .iter()
            .zip(&branching)
            .filter(|(k, branches)| **branches || matches!(k, Known::Integer(..) | Known::Boolean(..)))
            .map(|(k, _)| *k)
            .collect();
        if !probe_by_value(model, table, unknowns, &by_value, t, initial, &config, &mut deps) {
            return vec![None; unknowns.len()];
        }
    }
    deps
}

/// Adds to `deps` the knowns of `knowns` that move an unknown when moved one at a time at the
/// probe points of configuration `config`: a little, and to each far point (a threshold in the
/// equations is flat under a small step); and at the irregular point by three shrinking steps,
/// where only a change that shrinks with the step counts (`record_smooth`). False where the
/// equations fail at a regular probe point (then no dependency list is safe).
///
/// Each known is moved in place in one copy of the point and put back after each evaluation,
/// which writes into buffers made once per point (`evaluate_into`): a known costs its
/// evaluations and the comparison of every unknown, O(states + unknowns), and nothing is copied
/// or allocated per known.
#[allow(clippy::too_many_arguments)]
fn probe_by_value<M: Model>(model: &M, table: &VariableTable, unknowns: &[&Variable], knowns: &[Known], t: f64, initial: bool, config: &Values, deps: &mut [Dependencies]) -> bool {
    if knowns.is_empty() {
        return true;
    }
    let far = far_points(table, config);
    for values in probe_points(table, config) {
        let Some(p0) = evaluate(model, table, t, &values, initial) else {
            return false;
        };
        let (mut v, mut p1) = (values.clone(), Point { calculated: p0.calculated.clone(), derivatives: p0.derivatives.clone(), states: p0.states.clone() });
        for known in knowns {
            known.perturb(&mut v);
            let evaluated = evaluate_into(model, table, t, &v, initial, &mut p1);
            known.restore(&mut v, &values);
            if !evaluated {
                return false;
            }
            record(unknowns, deps, known, &p0, &p1);
            // A threshold in the equations is flat under a small perturbation: also jump
            // this one known to each far point (where the equations may fail: skipped).
            for far_values in &far {
                if known.jump(&mut v, far_values) && known.differs(&v, &values) && evaluate_into(model, table, t, &v, initial, &mut p1) {
                    record(unknowns, deps, known, &p0, &p1);
                }
                known.restore(&mut v, &values);
            }
        }
    }
    // Each real known perturbed at the irregular point too, by three steps, where only a
    // change that shrinks with the step counts (`record_smooth`); the equations may fail
    // there: the point, or the perturbed known, is then skipped, as at the far points.
    let values = irregular_point(table, config);
    if let Some(p0) = evaluate(model, table, t, &values, initial) {
        let mut v = values.clone();
        let fresh = || Point { calculated: p0.calculated.clone(), derivatives: p0.derivatives.clone(), states: p0.states.clone() };
        let mut p = [fresh(), fresh(), fresh()];
        for known in knowns {
            let mut evaluated = true;
            for (scale, p) in [1.0, 1.0 / 16.0, 1.0 / 256.0].into_iter().zip(p.iter_mut()) {
                evaluated &= known.perturb_real(&mut v, scale) && evaluate_into(model, table, t, &v, initial, p);
                known.restore(&mut v, &values);
                if !evaluated {
                    break;
                }
            }
            if evaluated {
                record_smooth(unknowns, deps, known, &p0, &p);
            }
        }
    }
    true
}

/// The ModelStructure found by probing every known by value, one at a time (`probe_by_value`),
/// without the trace: the reference the traced structure is checked against in the tests (it
/// must hold every dependency this finds). Cost: O(knowns x evaluation), quadratic in size.
#[doc(hidden)]
pub fn structure_by_values<M: Model>(model: &M, table: &VariableTable, t: f64) -> Structure {
    structure_with(table, |unknowns, knowns, initial| {
        let mut deps: Vec<Dependencies> = vec![Some(BTreeSet::new()); unknowns.len()];
        for config in configurations(table) {
            if !probe_by_value(model, table, unknowns, knowns, t, initial, &config, &mut deps) {
                return vec![None; unknowns.len()];
            }
        }
        deps
    })
}

/// The ModelStructure of a model, from its equations.
pub fn structure<M: Model>(model: &M, table: &VariableTable, t: f64) -> Structure {
    structure_with(table, |unknowns, knowns, initial| dependencies(model, table, unknowns, knowns, t, initial))
}

/// The ModelStructure with each list's dependencies found by `find(unknowns, knowns, initial)`.
fn structure_with(table: &VariableTable, find: impl Fn(&[&Variable], &[Known], bool) -> Vec<Dependencies>) -> Structure {
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
    let Unknowns { outputs, derivatives, initial } = Unknowns::of(table);
    let zip = |us: &[&Variable], ds: Vec<Dependencies>| us.iter().map(|u| value_reference_of(u)).zip(ds).collect::<Vec<_>>();
    Structure {
        outputs: zip(&outputs, find(&outputs, &run_knowns, false)),
        derivatives: zip(&derivatives, find(&derivatives, &run_knowns, false)),
        initial_unknowns: zip(&initial, find(&initial, &init_knowns, true)),
    }
}

/// One standard's modelDescription.xml and its token (FMI 2.0 `guid`, FMI 3.0
/// `instantiationToken`): two hashes of the XML with the token left out (`xml::token`).
#[derive(Clone, Debug)]
pub struct Document {
    pub xml: String,
    pub token: String,
}

impl Document {
    /// Stamps a draft written with `xml::TOKEN_PLACEHOLDER` with its token: the hash of the
    /// `skeleton` (the same description without dependency lists), then that of the draft.
    fn stamped(draft: String, skeleton: &str) -> Document {
        let token = crate::xml::token(crate::xml::interface_hash(skeleton), &draft);
        Document { xml: draft.replacen(crate::xml::TOKEN_PLACEHOLDER, &token, 1), token }
    }
}

/// What `fmi2Instantiate`/`fmi3Instantiate*` check a master's token against, for one standard:
/// the first half of the token, the hash of the description written without its dependency
/// lists. O(variables): it needs the table, not the dependency probe.
pub fn token_check<M: Model>(standard: Standard, model: &M, table: &VariableTable, package: &Package) -> crate::xml::TokenCheck {
    let floor = crate::model::default_tolerance_floor(model, table);
    crate::xml::TokenCheck::new(crate::xml::interface_hash(&standard.write_xml::<M>(table, &Structure::skeleton(table), package, floor)))
}

/// The problems a model's library finds without probing its equations' dependencies: its
/// declarations', and the computed variables its equations leave unwritten or the elements whose
/// power they do not report (one evaluation per configuration of the structural parameters).
/// An instance refuses to be made for a model that has any; build-fmus also refuses the outputs
/// the probe finds constant (`ModelDescription::problems`).
pub fn problems_without_probe<M: Model>(model: &M, table: &VariableTable) -> Vec<String> {
    let mut problems = table.problems.clone();
    problems.extend(unwritten(model, table, probe_time::<M>()));
    problems
}

/// A generic time inside the default experiment, not at its start, where a sine source would
/// hide its amplitude (sin 0 = 0): where the equations are probed.
fn probe_time<M: Model>() -> f64 {
    let e = M::info().default_experiment;
    e.start_time + 0.2371 * (e.stop_time - e.start_time) + 0.0137
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
        Self::of_declared(&model, Arc::new(table), package)
    }

    /// The description of a model already declared (the library's one declaration): probes the
    /// equations for the ModelStructure and writes each standard's XML.
    pub fn of_declared<M: Model>(model: &M, table: Arc<VariableTable>, package: &Package) -> ModelDescription {
        let probe_time = probe_time::<M>();
        let structure = structure(model, &table, probe_time);
        let mut problems = problems_without_probe(model, &table);
        let constant = constant_outputs(model, &table, &structure, probe_time);
        // An output never written is constant too: it is reported once, as never written.
        let named: HashSet<String> = problems.iter().filter_map(|p| quoted_name(p)).collect();
        let fresh: Vec<String> = constant.into_iter().filter(|c| quoted_name(c).is_none_or(|n| !named.contains(&n))).collect();
        problems.extend(fresh);
        let skeleton = Structure::skeleton(&table);
        let default_floor = crate::model::default_tolerance_floor(model, &table);
        let documents = crate::standards::ALL
            .iter()
            .map(|s| (*s, Document::stamped(s.write_xml::<M>(&table, &structure, package, default_floor), &s.write_xml::<M>(&table, &skeleton, package, default_floor))))
            .collect();
        ModelDescription { documents, package: *package, table, structure, problems, default_floor }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_model::Decay;

    /// der(x) = -1 above the input u, +1 below (a relay: u decides the branch and flows into
    /// no value); y = x once t >= t_on (compared after leaving the trace through `value()`).
    struct Relay {
        t_on: crate::variables::Parameter,
        u: crate::variables::Input,
        x: crate::variables::State,
        y: crate::variables::Output,
    }

    impl Model for Relay {
        fn info() -> crate::model::ModelInfo {
            crate::model::ModelInfo { name: "Relay", ..Decay::info() }
        }
        fn declare(d: &mut crate::variables::Declarations) -> Self {
            Relay {
                t_on: d.parameter("t_on", 0.1, "s").describe("when y follows x"),
                u: d.input("u", 0.5, "1").describe("threshold"),
                x: d.state("x", 0.0, "1").describe("state"),
                y: d.output("y", "1").describe("x once t >= t_on"),
            }
        }
        fn derivatives<R: Real>(&self, k: &crate::values::Knowns<R>, der: &mut crate::values::Derivatives<R>) {
            der[self.x] = R::from(if k[self.x] > k[self.u] { -1.0 } else { 1.0 });
        }
        fn outputs<R: Real>(&self, k: &crate::values::Knowns<R>, out: &mut crate::values::Outputs<R>) {
            out[self.y] = if k.time() >= k[self.t_on].value() { k[self.x] } else { R::from(0.0) };
        }
    }

    /// Every dependency the value probe (each known moved alone, the quadratic reference) finds,
    /// the traced probe finds too; the value reference of one differing entry where they differ.
    fn traced_holds_every_dependency_by_value<M: Model>() {
        let (model, _, table) = crate::model::declare::<M>();
        let t = probe_time::<M>();
        let (traced, by_value) = (structure(&model, &table, t), structure_by_values(&model, &table, t));
        for (list, a, b) in [("outputs", &traced.outputs, &by_value.outputs), ("derivatives", &traced.derivatives, &by_value.derivatives), ("initial unknowns", &traced.initial_unknowns, &by_value.initial_unknowns)] {
            assert_eq!(a.len(), b.len());
            for ((vr, traced), (_, by_value)) in a.iter().zip(b) {
                if let (Some(traced), Some(by_value)) = (traced, by_value) {
                    assert!(traced.is_superset(by_value), "{}: {list} {vr}: traced {traced:?}, by value {by_value:?}", M::info().name);
                } else {
                    assert!(traced.is_none(), "{}: {list} {vr}: by value every known, traced {traced:?}", M::info().name);
                }
            }
        }
    }

    #[test]
    fn the_traced_probe_finds_what_moving_each_known_alone_finds() {
        use crate::test_model::*;
        traced_holds_every_dependency_by_value::<Decay>();
        traced_holds_every_dependency_by_value::<Switch>();
        traced_holds_every_dependency_by_value::<Relax>();
        traced_holds_every_dependency_by_value::<Block>();
        traced_holds_every_dependency_by_value::<ImplicitBlock>();
        traced_holds_every_dependency_by_value::<Careless>();
        traced_holds_every_dependency_by_value::<Frozen>();
        traced_holds_every_dependency_by_value::<Chooser>();
        traced_holds_every_dependency_by_value::<Array>();
        traced_holds_every_dependency_by_value::<Relay>();
        // The relay's threshold decides a branch only, and flows into no value: found by value.
        // (The switch-on time is before the probe time, where y = x: no probe moves it past.)
        let s = ModelDescription::of::<Relay>().structure;
        let set = |v: &[usize]| Some(v.iter().copied().collect::<BTreeSet<_>>());
        // value references: t_on=0, u=1, x=2, der(x)=3, y=4
        assert_eq!(s.derivatives, vec![(3, set(&[1, 2]))]);
        assert_eq!(s.outputs, vec![(4, set(&[2]))]);
    }

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
    fn the_token_s_first_half_needs_no_probe_and_the_second_covers_the_dependencies() {
        let d = ModelDescription::of::<Decay>();
        for s in crate::standards::ALL {
            let (table, package) = (&d.table, &Package::default());
            let check = token_check::<Decay>(*s, &crate::model::declare::<Decay>().0, table, package);
            let document = d.document(*s);
            assert!(check.accepts(&document.token), "{s:?}: {} against {}", document.token, check.shown());
            // The same description with other dependency lists: same first half, another token.
            let mut other = Structure::skeleton(table);
            other.derivatives[0].1 = Some(BTreeSet::from([2]));
            let relisted = Document::stamped(s.write_xml::<Decay>(table, &other, package, None), &s.write_xml::<Decay>(table, &Structure::skeleton(table), package, None));
            assert_eq!(relisted.token[..20], document.token[..20], "{s:?}");
            assert_ne!(relisted.token, document.token, "{s:?}");
            // Flat names: FMI's default convention, not said.
            assert!(!document.xml.contains("variableNamingConvention"), "{}", document.xml);
        }
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
