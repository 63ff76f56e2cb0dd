//! `fmi2GetDirectionalDerivative` of every FMU in dist/ and `fmi3GetDirectionalDerivative` of
//! every FMU in dist/fmi3/, checked against central finite differences that this test computes
//! itself through the ordinary FMI calls (the fmi2 calls named below, or their FMI 3.0
//! counterparts: fmi3SetTime, fmi3SetContinuousStates, fmi3SetFloat64, fmi3GetFloat64, ...).
//! Both versions by default; `FMI_VERSIONS=2` or `=3` restricts. The same checks and tolerances
//! for both.
//!
//! FMI 2.0.4, 2.1.9: with v_unknown = h(v_known, v_rest), the FMU returns
//! dv_unknown = (dh/dv_known) dv_known. After initialization the unknowns are the state
//! derivatives and the outputs, the knowns the continuous states and the inputs; in
//! Initialization Mode the knowns also include the parameters (and the states' start values).
//! The test seeds one known at a time (dv_known = e_j: column j of the Jacobian), and all
//! knowns at once (dv_known = v, a mix of every column), for both interfaces:
//!
//! * Model Exchange: the instance is put on an operating point with `fmi2SetTime`,
//!   `fmi2SetContinuousStates` and `fmi2SetReal` (inputs); a state column's reference is
//!   (f(x + h e_j) - f(x - h e_j)) / 2h with f read by `fmi2GetReal` after
//!   `fmi2SetContinuousStates`; an input column's the same with `fmi2SetReal` on the input; the
//!   all-knowns product's is the central difference of f(x + t v) in t.
//! * Co-Simulation: an input column's reference is the finite difference taken in the CS
//!   instance itself (`fmi2SetReal` on an input is allowed at a communication point). A CS master
//!   cannot set the continuous states after initialization (no `fmi2SetContinuousStates`, and a
//!   state is not settable by `fmi2SetReal` then; an FMU state save/restore brings back the same
//!   state, it cannot move it), so a state column of the CS instance, and its all-knowns product,
//!   are compared with the finite differences taken in a Model Exchange instance of the same FMU
//!   put on exactly the CS instance's (time, states, inputs); the test first checks that both
//!   instances then report the same unknowns (to 1e-12; an FMU with event indicators gets an
//!   event iteration there first, so its discrete modes follow the states) and that the ME state vector is in the
//!   order of ModelStructure/Derivatives. In Initialization Mode the knowns are the Real
//!   parameters, the states with initial="exact" and the inputs, all settable by `fmi2SetReal`
//!   in both interfaces, so every column is checked within its own instance.
//!
//! Operating points: right after initialization, after 5 communication steps of the default
//! experiment, and at 1/3 and 2/3 of it (MotorFan's extra configurations: of a 15 s run). The ME
//! instance takes the CS run's states at those instants.
//!
//! Accuracy: h_j = 1e-6 * s_j with s_j = max(|x_j|, nominal_j or 1). Entry (i, j) passes when
//!     |dd - fd| <= 1e-6 * max(|fd|, |dd|, S_i / s_j)
//! where S_i is the scale of unknown i: the largest of its range over the CS run, its magnitude at
//! the operating point and its declared nominal (FMI's default nominal 1 for an unknown that is 0
//! throughout the run and declares none). S_i / s_j is the size of a derivative that moves
//! the unknown by its own scale when the known moves by its own; the round-off of the central
//! difference is ~1e-10 of it, far below the tolerance.
//!
//! The reference must be the derivative at the point, so the test checks that its difference
//! has converged: the forward and backward differences agree to 1e-3 of the entry's scale and the
//! central difference at h/10 equals the one at h to 1e-7. Where not (a kink of f within h, e.g.
//! an activity |J w dw/dt| with w a few 1e-6 of its nominal from 0; curvature on a scale below h;
//! a function like w|w| at w = 0, whose central difference is O(h)), it retries at h/10, h/100,
//! h/1000 and takes the first converged central difference ("refined" in the report). If they
//! never agree but each settles, f has a kink at the point itself (e.g. w = 0 exactly after a
//! start from rest): there is no derivative, and dd must lie between the one-sided differences
//! ("at kinks"). If not even the one-sided differences settle (a jump, or variation on a scale
//! below h/10^4), there is no reference: such entries are counted and the first ones printed
//! ("without reference"), not judged.
//! The all-knowns product J v has a reference only where the finite differences are linear in
//! the seed: its own central difference must equal sum_j v_j times column j's (to REL_TOL of its
//! scale, the tolerance a derivative is judged by). Where not, f has no derivative at the point (a product of two quantities both
//! exactly 0, whose branch the second-order term decides), and the entry is counted and shown
//! ("not linear in the seed"), not judged.
//!
//! FMI 3.0 only: `fmi3GetAdjointDerivative` (sensitivity = seed^T J) at every operating point
//! after initialization, in both instances, with all unknowns seeded (seed_i = c_i / S_i, the
//! c_i alternating in sign and size) and all knowns asked: each sensitivity must equal
//! sum_i seed_i J_ij computed here from the directional-derivative columns (which are checked
//! against the finite differences above), to 1e-12 of sum_i |seed_i J_ij| (rounding of the sum)
//! or, if that is 0, of sum_i |seed_i| S_i / s_j.
//!
//! The worst error of each FMU, interface and configuration is printed to stderr directly (not
//! through the captured `eprintln!`), so it shows in every `cargo test` run.
//!
//! `FMU_DIST_DIR` overrides the folder (default `<workspace>/dist`).

mod derivative_checks;
use derivative_checks::{get, me_event_iteration, me_move_to, ok, ratio, report};

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

use fmi_host::dist::{dist_dir_for, every_fmu_path_for, versions};
use fmi_host::{
    Causality, Fmi2Type, FmiVersion, Fmu, Initial, Instance, InstantiateOptions, ValueReference,
    Variability, VariableType,
};
use quick_xml::events::Event;
use quick_xml::{Reader, XmlVersion};

/// Relative accuracy required of every Jacobian entry (see the module documentation).
const REL_TOL: f64 = 1e-6;
/// Finite-difference step, relative to the known's scale.
const FD_REL_STEP: f64 = 1e-6;
/// Forward and backward differences further apart than this (relative to the entry's scale)
/// mark a kink (or unresolved curvature) of f within the step.
const KINK: f64 = 1e-3;
/// A central difference is converged when the next smaller step changes it by less than this
/// (relative to the entry's scale).
const CONVERGED: f64 = 1e-7;
/// fmi3GetAdjointDerivative against seed^T J from the directional derivatives: rounding of the
/// sum only (see the module documentation).
const ADJOINT_TOL: f64 = 1e-12;


// ---- What the host's parser does not read: <ModelExchange> flags and ModelStructure ---------

struct Structure {
    cs_provides_dd: bool,
    me_present: bool,
    me_provides_dd: bool,
    me_model_identifier: Option<String>,
    /// 1-based indices of ModelStructure/Derivatives/Unknown (FMI 3.0:
    /// ModelStructure/ContinuousStateDerivative, by value reference), in document order: the
    /// order of the continuous-state vector (FMI 2.0.4, 2.2.8; FMI 3.0, 2.4.8).
    derivative_indices: Vec<usize>,
}

fn read_structure(fmu: &Fmu) -> Structure {
    let path = fmu.unpacked_dir().join("modelDescription.xml");
    let xml = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let mut reader = Reader::from_str(&xml);
    let mut stack: Vec<String> = Vec::new();
    let mut s = Structure {
        cs_provides_dd: false,
        me_present: false,
        me_provides_dd: false,
        me_model_identifier: None,
        derivative_indices: Vec::new(),
    };
    loop {
        let event = reader.read_event().expect("modelDescription.xml parses");
        let (e, empty) = match event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(_) => {
                stack.pop();
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let name: String = e.name().as_ref().to_owned();
        let mut attrs: HashMap<String, String> = HashMap::new();
        for a in e.attributes() {
            let a = a.expect("attribute");
            let value = a.normalized_value(XmlVersion::Implicit1_0).expect("attribute value").into_owned();
            attrs.insert(a.key.as_ref().to_owned(), value);
        }
        let flag = |k: &str| matches!(attrs.get(k).map(|v| v.trim()), Some("true" | "1"));
        // FMI 3.0 spells it providesDirectionalDerivatives.
        let provides_dd = flag("providesDirectionalDerivative") || flag("providesDirectionalDerivatives");
        let parent = stack.last().map(String::as_str);
        match (parent, name.as_str()) {
            (Some("fmiModelDescription"), "CoSimulation") => {
                s.cs_provides_dd = provides_dd
            }
            (Some("fmiModelDescription"), "ModelExchange") => {
                s.me_present = true;
                s.me_provides_dd = provides_dd;
                s.me_model_identifier = attrs.get("modelIdentifier").cloned();
            }
            (Some("Derivatives"), "Unknown") => s.derivative_indices.push(
                attrs["index"].trim().parse().expect("Derivatives/Unknown index"),
            ),
            (Some("ModelStructure"), "ContinuousStateDerivative") => {
                let vr: ValueReference = attrs["valueReference"].trim().parse().expect("ContinuousStateDerivative valueReference");
                let variables = &fmu.model_description().model_variables;
                let i = variables.iter().position(|v| v.value_reference == vr).unwrap_or_else(|| {
                    panic!("ContinuousStateDerivative valueReference {vr} is no variable's")
                });
                s.derivative_indices.push(i + 1);
            }
            _ => {}
        }
        if !empty {
            stack.push(name);
        }
    }
    s
}

// ---- The model's variables, by role ---------------------------------------------------------

#[derive(Clone, Debug)]
struct Var {
    name: String,
    vr: ValueReference,
    nominal: Option<f64>,
    min: Option<f64>,
    max: Option<f64>,
}

struct Model {
    fmu: Arc<Fmu>,
    /// "<model name> (FMI x.0)".
    name: String,
    version: FmiVersion,
    structure: Structure,
    /// Continuous states, in the order of the state vector.
    states: Vec<Var>,
    /// `derivatives[i]` is der(`states[i]`).
    derivatives: Vec<Var>,
    inputs: Vec<Var>,
    outputs: Vec<Var>,
    /// Real parameters (fixed or tunable): knowns in Initialization Mode.
    parameters: Vec<Var>,
    /// States with initial="exact": knowns in Initialization Mode.
    exact_states: Vec<Var>,
    start: f64,
    stop: f64,
    step: f64,
}

impl Model {
    fn load(path: &PathBuf) -> Model {
        let fmu = Fmu::load(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
        let structure = read_structure(&fmu);
        let md = fmu.model_description();
        let var = |i: usize| {
            let v = &md.model_variables[i];
            Var { name: v.name.clone(), vr: v.value_reference, nominal: v.nominal, min: v.min, max: v.max }
        };
        let with_derivative = md.model_variables.iter().filter(|v| v.derivative.is_some()).count();
        assert_eq!(
            structure.derivative_indices.len(),
            with_derivative,
            "{}: ModelStructure/Derivatives lists {} unknowns, {} variables have a derivative attribute",
            md.model_name,
            structure.derivative_indices.len(),
            with_derivative
        );
        let mut states = Vec::new();
        let mut derivatives = Vec::new();
        for &i in &structure.derivative_indices {
            let d = &md.model_variables[i - 1];
            let x = d.derivative.unwrap_or_else(|| panic!("{}: Derivatives lists {:?}, which has no derivative attribute", md.model_name, d.name));
            derivatives.push(var(i - 1));
            states.push(var(x as usize - 1));
        }
        let real = |v: &&fmi_host::ScalarVariable| v.variable_type == VariableType::Real;
        let pick = |f: &dyn Fn(&fmi_host::ScalarVariable) -> bool| -> Vec<Var> {
            md.model_variables
                .iter()
                .enumerate()
                .filter(|(_, v)| real(v) && f(v))
                .map(|(i, _)| var(i))
                .collect()
        };
        let inputs = pick(&|v| v.causality == Causality::Input);
        let outputs = pick(&|v| v.causality == Causality::Output);
        let parameters = pick(&|v| {
            v.causality == Causality::Parameter && v.variability != Variability::Constant
        });
        let state_vrs: Vec<ValueReference> = states.iter().map(|s| s.vr).collect();
        let exact_states = pick(&|v| state_vrs.contains(&v.value_reference) && v.initial == Some(Initial::Exact));
        let e = md.default_experiment.expect("every FMU has a DefaultExperiment");
        Model {
            name: format!("{} ({})", md.model_name, fmu.fmi_version()),
            version: fmu.fmi_version(),
            states,
            derivatives,
            inputs,
            outputs,
            parameters,
            exact_states,
            start: e.start_time.unwrap_or(0.0),
            stop: e.stop_time.expect("DefaultExperiment stopTime"),
            step: e.step_size.expect("DefaultExperiment stepSize"),
            structure,
            fmu,
        }
    }

    /// The unknowns after initialization: state derivatives, then Real outputs, but not the energy
    /// balance (`power_balance_residual`, `power_balance_relative`): it is zero at every state of a
    /// consistent model, so its exact derivatives are zero and both the directional derivative
    /// and the finite difference see rounding only (test_energy_balance.py checks its value).
    fn unknowns(&self) -> Vec<Var> {
        self.derivatives.iter().chain(&self.outputs).filter(|v| !v.name.starts_with("power_balance_")).cloned().collect()
    }
}

fn vrs(vars: &[Var]) -> Vec<ValueReference> {
    vars.iter().map(|v| v.vr).collect()
}

/// Integer/Boolean start values of a configuration (set in Instantiated mode).
#[derive(Clone, Debug, Default)]
struct Config {
    label: String,
    integers: Vec<(&'static str, i32)>,
    booleans: Vec<(&'static str, bool)>,
    /// None: the default experiment's stop time.
    stop: Option<f64>,
}



fn instantiate(model: &Model, fmu_type: Fmi2Type, config: &Config, label: &str) -> Instance {
    let label = format!("{label} {}", model.version);
    let mut inst = Instance::new(&model.fmu, InstantiateOptions::new(label).fmu_type(fmu_type))
        .unwrap_or_else(|e| panic!("{}: fmi2Instantiate({fmu_type:?}): {e}", model.name));
    let stop = config.stop.unwrap_or(model.stop);
    let status = inst.setup_experiment(None, model.start, Some(stop));
    ok(status, "fmi2SetupExperiment", &inst);
    apply_config(model, &mut inst, config);
    inst
}

fn apply_config(model: &Model, inst: &mut Instance, config: &Config) {
    for (name, value) in &config.integers {
        let vr = model.fmu.vr(name).unwrap();
        let status = inst.set_integer(&[vr], &[*value]);
        ok(status, &format!("fmi2SetInteger({name} = {value})"), inst);
    }
    for (name, value) in &config.booleans {
        let vr = model.fmu.vr(name).unwrap();
        let status = inst.set_boolean(&[vr], &[*value]);
        ok(status, &format!("fmi2SetBoolean({name} = {value})"), inst);
    }
}



// ---- Comparison -----------------------------------------------------------------------------

#[derive(Default)]
struct Tally {
    entries: usize,
    /// Entries where f has a kink at the operating point (no derivative).
    kinks: usize,
    /// Entries whose reference needed a smaller step than h (a kink or strong curvature within h).
    refined: usize,
    /// Entries without a reference (see `column`), and a few of them.
    unresolved: usize,
    unresolved_examples: Vec<String>,
    /// All-knowns entries whose finite difference is not the seed's combination of the columns'
    /// (no derivative linear in the seed at the point: no reference), and a few of them.
    not_linear: usize,
    not_linear_examples: Vec<String>,
    worst: f64,
    worst_at: String,
    failures: Vec<String>,
}

impl Tally {
    /// Compares one Jacobian column (all unknowns) with its finite differences.
    #[allow(clippy::too_many_arguments)]
    ///
    /// `linear`: for the all-knowns product, sum_j v_j times column j's finite difference. Where
    /// the product's own finite difference differs from it by more than the tolerance (REL_TOL of
    /// the entry's scale: the finite differences disagree with themselves by more than a
    /// derivative is allowed to differ from them), f has no derivative linear in the seed at the point (e.g. a product of two
    /// quantities both exactly 0 whose branch its second-order term decides: MotorFan's rigid
    /// reducer at rest, with both its torque and its speed moving): there is no Jacobian for any
    /// directional derivative to match, so the entry has no reference (counted, shown).
    #[allow(clippy::too_many_arguments)]
    fn column(&mut self, at: &str, known: &str, unknowns: &[Var], scale_u: &[f64], scale_k: f64, dd: &[f64], fd: &Fd, linear: Option<&[f64]>) {
        for (i, u) in unknowns.iter().enumerate() {
            let natural = scale_u[i] / scale_k;
            self.entries += 1;
            let where_ = format!("{at}: d {} / d {known}", u.name);
            if !dd[i].is_finite() {
                self.failures.push(format!("{where_}: directional derivative {} is not finite", dd[i]));
                self.note(f64::INFINITY, &where_);
                continue;
            }
            if let Some(linear) = linear {
                let product = fd.central(0, i);
                if (product - linear[i]).abs() > REL_TOL * product.abs().max(linear[i].abs()).max(natural) {
                    self.not_linear += 1;
                    if self.not_linear_examples.len() < 3 {
                        self.not_linear_examples.push(format!(
                            "{where_}: dd {:.6e}; the product's finite difference {product:.6e}, the columns' combination {:.6e}",
                            dd[i], linear[i]
                        ));
                    }
                    continue;
                }
            }
            // The largest step at which the difference has converged (see `Fd`): the forward and
            // backward differences agree, and the central difference equals the next smaller
            // step's to 1e-7 (so its own error is far below REL_TOL).
            let smooth = (0..fd.levels.len() - 1).find(|&m| {
                let (fwd, bwd, c) = (fd.forward(m, i), fd.backward(m, i), fd.central(m, i));
                (fwd - bwd).abs() <= KINK * fwd.abs().max(bwd.abs()).max(natural)
                    && (c - fd.central(m + 1, i)).abs() <= CONVERGED * c.abs().max(natural)
            });
            let (err, detail) = match smooth {
                Some(m) => {
                    let central = fd.central(m, i);
                    let refined = if m > 0 {
                        self.refined += 1;
                        format!(
                            " (refined: the difference at h = {:.1e}, {:.12e}, had not converged: a kink or strong curvature within h)",
                            fd.levels[0].0,
                            fd.central(0, i)
                        )
                    } else {
                        String::new()
                    };
                    let denom = central.abs().max(dd[i].abs()).max(natural);
                    (ratio((dd[i] - central).abs(), denom), format!("central difference {central:.12e} at h = {:.1e}{refined}", fd.levels[m].0))
                }
                None => {
                    let last = fd.levels.len() - 1;
                    let (fwd, bwd) = (fd.forward(last, i), fd.backward(last, i));
                    let sc = fwd.abs().max(bwd.abs()).max(natural);
                    let settled = (fwd - fd.forward(last - 1, i)).abs() <= KINK * sc
                        && (bwd - fd.backward(last - 1, i)).abs() <= KINK * sc;
                    if !settled || (fwd - bwd).abs() <= KINK * sc {
                        // Not even the one-sided differences converge down to h/10^4: f varies
                        // on a scale below the test's resolution. No reference: counted, shown.
                        self.unresolved += 1;
                        if self.unresolved_examples.len() < 3 {
                            self.unresolved_examples.push(format!(
                                "{where_}: dd {:.6e}; one-sided differences {:.6e} / {:.6e} at h = {:.1e}, {:.6e} / {:.6e} at h = {:.1e}",
                                dd[i],
                                fd.backward(last - 1, i),
                                fd.forward(last - 1, i),
                                fd.levels[last - 1].0,
                                bwd,
                                fwd,
                                fd.levels[last].0
                            ));
                        }
                        continue;
                    }
                    // A kink at the point itself (the one-sided differences settle but differ):
                    // there is no derivative, and dd must lie between them.
                    self.kinks += 1;
                    let (lo, hi) = (fwd.min(bwd), fwd.max(bwd));
                    let denom = sc.max(dd[i].abs());
                    let outside = if dd[i] < lo { lo - dd[i] } else if dd[i] > hi { dd[i] - hi } else { 0.0 };
                    (ratio(outside, denom), format!("kink at the point: one-sided differences {bwd:.9e} (backward), {fwd:.9e} (forward)"))
                }
            };
            if err > REL_TOL {
                self.failures.push(format!(
                    "{where_}: directional derivative {:.12e}, {detail}; error {err:.3e} of max(|fd|, |dd|, scale {natural:.3e})",
                    dd[i]
                ));
            }
            self.note(err, &where_);
        }
    }

    /// The first failures (prefixed), and how many more there are: every configuration gets a
    /// say in the panic message.
    fn first_failures(&self, prefix: &str) -> Vec<String> {
        const SHOWN: usize = 8;
        let mut lines: Vec<String> = self.failures.iter().take(SHOWN).map(|f| format!("{prefix} {f}")).collect();
        if self.failures.len() > SHOWN {
            lines.push(format!("{prefix}: ... and {} more", self.failures.len() - SHOWN));
        }
        lines
    }

    fn note(&mut self, err: f64, where_: &str) {
        if err > self.worst || self.worst_at.is_empty() {
            self.worst = err;
            self.worst_at = where_.to_owned();
        }
    }

    fn line(&self, what: &str) -> String {
        let mut notes = Vec::new();
        if self.kinks > 0 {
            notes.push(format!("{} at kinks", self.kinks));
        }
        if self.refined > 0 {
            notes.push(format!("{} refined", self.refined));
        }
        if self.unresolved > 0 {
            notes.push(format!("{} without reference", self.unresolved));
        }
        if self.not_linear > 0 {
            notes.push(format!("{} not linear in the seed", self.not_linear));
        }
        let mut text = format!(
            "  {what:<58} {:>5} entries, worst {:.2e} ({}){}{}\n",
            self.entries,
            self.worst,
            self.worst_at,
            if notes.is_empty() { String::new() } else { format!("; {}", notes.join(", ")) },
            if self.failures.is_empty() { String::new() } else { format!("  <-- {} FAIL", self.failures.len()) }
        );
        for e in &self.unresolved_examples {
            text += &format!("      no reference: {e}\n");
        }
        for e in &self.not_linear_examples {
            text += &format!("      not linear in the seed: {e}\n");
        }
        text
    }
}


/// Scale of each unknown: max(range over the CS run, |value now|, declared nominal); an unknown
/// that stays 0 over the whole run and declares no nominal gets FMI's default nominal, 1.
fn unknown_scales(unknowns: &[Var], range: &[f64], now: &[f64]) -> Vec<f64> {
    unknowns
        .iter()
        .enumerate()
        .map(|(i, u)| {
            let s = range[i].max(now[i].abs()).max(u.nominal.unwrap_or(0.0).abs());
            if s == 0.0 { 1.0 } else { s }
        })
        .collect()
}

/// Scale and finite-difference step of a known at value x.
fn known_scale(k: &Var, x: f64) -> (f64, f64) {
    let s = x.abs().max(k.nominal.map_or(1.0, f64::abs));
    (s, FD_REL_STEP * s)
}

fn dd_column(inst: &mut Instance, unknown: &[ValueReference], known: &[ValueReference], seed: &[f64], what: &str) -> Vec<f64> {
    let mut out = vec![f64::NAN; unknown.len()];
    let status = inst.get_directional_derivative(unknown, known, seed, &mut out);
    ok(status, &format!("fmi2GetDirectionalDerivative({what})"), inst);
    out
}

/// Finite differences of the unknowns along one known, at the step h and at h/10, h/100, h/1000,
/// h/10^4 (how `Tally::column` picks the reference: see the module documentation).
struct Fd {
    f0: Vec<f64>,
    /// (h, f(x + h), f(x - h)), h decreasing.
    levels: Vec<(f64, Vec<f64>, Vec<f64>)>,
}

impl Fd {
    fn central(&self, m: usize, i: usize) -> f64 {
        let (h, p, n) = &self.levels[m];
        (p[i] - n[i]) / (2.0 * h)
    }
    fn forward(&self, m: usize, i: usize) -> f64 {
        let (h, p, _) = &self.levels[m];
        (p[i] - self.f0[i]) / h
    }
    fn backward(&self, m: usize, i: usize) -> f64 {
        let (h, _, n) = &self.levels[m];
        (self.f0[i] - n[i]) / h
    }
}

/// The unknowns with one known set by `set` to x0 and x0 +- h 10^-m; the known is restored.
fn fd_by<F: FnMut(&mut Instance, f64)>(inst: &mut Instance, unknown: &[ValueReference], x0: f64, h: f64, mut set: F) -> Fd {
    set(inst, x0);
    let f0 = get(inst, unknown, "fmi2GetReal(unknowns)");
    let mut levels = Vec::new();
    for m in 0..5 {
        let hm = h / 10f64.powi(m);
        set(inst, x0 + hm);
        let plus = get(inst, unknown, "fmi2GetReal(unknowns) at x + h");
        set(inst, x0 - hm);
        let minus = get(inst, unknown, "fmi2GetReal(unknowns) at x - h");
        levels.push((hm, plus, minus));
    }
    set(inst, x0);
    let back = get(inst, unknown, "fmi2GetReal(unknowns) after restoring x");
    assert_eq!(
        back.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        f0.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        "{}: the unknowns differ after the known was restored",
        inst.name()
    );
    Fd { f0, levels }
}

// ---- The three operating points after initialization ----------------------------------------

/// Minimum and maximum of every unknown over a CS run of the configuration (and the step count).
fn cs_ranges(model: &Model, config: &Config) -> (Vec<f64>, usize) {
    let unknowns = vrs(&model.unknowns());
    let stop = config.stop.unwrap_or(model.stop);
    let steps = ((stop - model.start) / model.step).round() as usize;
    let mut cs = instantiate(model, Fmi2Type::CoSimulation, config, "ranges");
    ok(cs.enter_initialization_mode(), "fmi2EnterInitializationMode", &cs);
    ok(cs.exit_initialization_mode(), "fmi2ExitInitializationMode", &cs);
    let first = get(&mut cs, &unknowns, "fmi2GetReal");
    let (mut lo, mut hi) = (first.clone(), first);
    for k in 0..steps {
        let t = model.start + k as f64 * model.step;
        ok(cs.do_step(t, model.step, true), &format!("fmi2DoStep({t})"), &cs);
        let y = get(&mut cs, &unknowns, "fmi2GetReal");
        for i in 0..y.len() {
            lo[i] = lo[i].min(y[i]);
            hi[i] = hi[i].max(y[i]);
        }
    }
    (lo.iter().zip(&hi).map(|(a, b)| b - a).collect(), steps)
}

/// Checks both interfaces at the operating points of one configuration; returns the report
/// lines and the failures.
fn check_after_initialization(model: &Model, config: &Config) -> (String, Vec<String>) {
    let s = &model.structure;
    let mut text = String::new();
    let mut failures = Vec::new();
    if !s.cs_provides_dd {
        failures.push(format!("{}: <CoSimulation> does not declare providesDirectionalDerivative=\"true\"", model.name));
    }
    if !s.me_present {
        failures.push(format!("{}: no <ModelExchange> element (the state columns of the CS Jacobian need an ME instance)", model.name));
        return (text, failures);
    }
    if !s.me_provides_dd {
        failures.push(format!("{}: <ModelExchange> does not declare providesDirectionalDerivative=\"true\"", model.name));
    }
    let cs_id = &model.fmu.model_description().co_simulation.as_ref().unwrap().model_identifier;
    if s.me_model_identifier.as_ref() != Some(cs_id) {
        failures.push(format!("{}: ME modelIdentifier {:?} differs from CS {cs_id:?}", model.name, s.me_model_identifier));
    }

    let unknowns = model.unknowns();
    let u_vr = vrs(&unknowns);
    let x_vr = vrs(&model.states);
    let in_vr = vrs(&model.inputs);
    let nx = model.states.len();
    let (range, steps) = cs_ranges(model, config);
    let mut points: Vec<usize> = vec![0, 5.min(steps), steps / 3, 2 * steps / 3];
    points.dedup();

    let mut cs = instantiate(model, Fmi2Type::CoSimulation, config, "cs");
    ok(cs.enter_initialization_mode(), "fmi2EnterInitializationMode", &cs);
    ok(cs.exit_initialization_mode(), "fmi2ExitInitializationMode", &cs);
    let mut me = instantiate(model, Fmi2Type::ModelExchange, config, "me");
    ok(me.enter_initialization_mode(), "fmi2EnterInitializationMode", &me);
    ok(me.exit_initialization_mode(), "fmi2ExitInitializationMode", &me);
    let mut next_event = me_event_iteration(&mut me);

    let (mut t_cs, mut t_me) = (Tally::default(), Tally::default());
    // fmi3GetAdjointDerivative: (sensitivities checked, worst error) per instance.
    let (mut a_cs, mut a_me) = ((0usize, 0.0f64), (0usize, 0.0f64));
    let mut done = 0;
    for &k in &points {
        for j in done..k {
            let t = model.start + j as f64 * model.step;
            ok(cs.do_step(t, model.step, true), &format!("fmi2DoStep({t})"), &cs);
        }
        done = k;
        let t = model.start + k as f64 * model.step;
        let at = format!("t = {t:.6} (step {k})");

        // The CS instance's operating point, copied into the ME instance.
        let x = get(&mut cs, &x_vr, "fmi2GetReal(states)");
        let u = get(&mut cs, &in_vr, "fmi2GetReal(inputs)");
        let y_cs = get(&mut cs, &u_vr, "fmi2GetReal(unknowns)");
        me_move_to(&mut me, t, &mut next_event);
        ok(me.set_continuous_states(&x).unwrap(), "fmi2SetContinuousStates", &me);
        if !in_vr.is_empty() {
            ok(me.set_real(&in_vr, &u), "fmi2SetReal(inputs)", &me);
        }
        if model.fmu.model_description().number_of_event_indicators.unwrap_or(0) > 0 {
            // States moved by hand may leave the FMU's discrete modes behind (a seal the ME
            // instance saw stuck at t = 0 slips at the CS instance's speed): a master handles an
            // event there, and the modes follow the states.
            ok(me.enter_event_mode().unwrap(), "fmi2EnterEventMode", &me);
            next_event = me_event_iteration(&mut me);
        }
        let mut x_me = vec![f64::NAN; nx];
        ok(me.get_continuous_states(&mut x_me).unwrap(), "fmi2GetContinuousStates", &me);
        assert_eq!(x_me, x, "{} {at}: fmi2GetContinuousStates after fmi2SetContinuousStates", model.name);
        let x_by_vr = get(&mut me, &x_vr, "fmi2GetReal(states)");
        assert_eq!(
            x_by_vr, x,
            "{} {at}: the state vector is not in the order of ModelStructure/Derivatives (fmi2GetReal of the states after fmi2SetContinuousStates)",
            model.name
        );
        let y_me = get(&mut me, &u_vr, "fmi2GetReal(unknowns)");
        let mut dx = vec![f64::NAN; nx];
        ok(me.get_derivatives(&mut dx).unwrap(), "fmi2GetDerivatives", &me);
        let scale = unknown_scales(&unknowns, &range, &y_cs);
        for i in 0..unknowns.len() {
            if (y_me[i] - y_cs[i]).abs() > 1e-12 * scale[i].max(y_cs[i].abs()) {
                failures.push(format!(
                    "{} {at}: {} is {:.15e} in the ME instance at the CS instance's (t, x, u), {:.15e} in the CS instance",
                    model.name, unknowns[i].name, y_me[i], y_cs[i]
                ));
            }
            if i < nx && dx[i].to_bits() != y_me[i].to_bits() {
                failures.push(format!(
                    "{} {at}: fmi2GetDerivatives gives {:.15e} for {}, fmi2GetReal {:.15e}",
                    model.name, dx[i], unknowns[i].name, y_me[i]
                ));
            }
        }

        // Columns: states, then inputs.
        let knowns: Vec<(Var, f64, bool)> = model
            .states
            .iter()
            .cloned()
            .zip(x.iter().copied())
            .map(|(v, x)| (v, x, true))
            .chain(model.inputs.iter().cloned().zip(u.iter().copied()).map(|(v, u)| (v, u, false)))
            .collect();
        let mut seeds: Vec<f64> = Vec::new();
        let mut natural_sum = vec![0.0; unknowns.len()];
        // sum_j v_j (column j's central difference, in the ME instance): what the all-knowns
        // product's difference is where f has a derivative at the point.
        let mut combination = vec![0.0; unknowns.len()];
        for (j, (known, x0, is_state)) in knowns.iter().enumerate() {
            let (s_k, h) = known_scale(known, *x0);
            let dd_me = dd_column(&mut me, &u_vr, &[known.vr], &[1.0], &known.name);
            let dd_cs = dd_column(&mut cs, &u_vr, &[known.vr], &[1.0], &known.name);
            let fd = if *is_state {
                let mut xs = x.clone();
                fd_by(&mut me, &u_vr, *x0, h, |inst, v| {
                    xs[j] = v;
                    ok(inst.set_continuous_states(&xs).unwrap(), "fmi2SetContinuousStates", inst);
                })
            } else {
                fd_by(&mut me, &u_vr, *x0, h, |inst, v| ok(inst.set_real(&[known.vr], &[v]), "fmi2SetReal(input)", inst))
            };
            t_me.column(&at, &known.name, &unknowns, &scale, s_k, &dd_me, &fd, None);
            if *is_state {
                // CS cannot set its states: the reference is the ME instance at the same point.
                let at_cs = format!("{at} [states: ME finite differences]");
                t_cs.column(&at_cs, &known.name, &unknowns, &scale, s_k, &dd_cs, &fd, None);
            } else {
                let fd = fd_by(&mut cs, &u_vr, *x0, h, |inst, v| ok(inst.set_real(&[known.vr], &[v]), "fmi2SetReal(input)", inst));
                t_cs.column(&at, &known.name, &unknowns, &scale, s_k, &dd_cs, &fd, None);
            }
            // A seed of the known's own scale, varied so that no two columns can cancel.
            let seed = s_k * (1.0 + 0.37 * j as f64) * if j % 2 == 0 { 1.0 } else { -1.0 };
            seeds.push(seed);
            for (i, c) in combination.iter_mut().enumerate() {
                *c += seed * fd.central(0, i);
            }
            for i in 0..unknowns.len() {
                natural_sum[i] += seed.abs() * scale[i] / s_k;
            }
        }
        if !knowns.is_empty() {
            // All knowns seeded at once: J v, against the central difference of f(x + t v) in t,
            // taken in the ME instance (the only one that can move states and inputs together).
            // With v_j = c_j s_j, t = 1e-6 / max c_j moves each known by at most 1e-6 of its scale.
            let known_vr: Vec<ValueReference> = knowns.iter().map(|(v, _, _)| v.vr).collect();
            let dt = FD_REL_STEP / seeds.iter().zip(&knowns).map(|(v, (k, x0, _))| v.abs() / known_scale(k, *x0).0).fold(0.0, f64::max);
            let fd = fd_by(&mut me, &u_vr, 0.0, dt, |inst, t| {
                let xs: Vec<f64> = (0..nx).map(|j| x[j] + t * seeds[j]).collect();
                ok(inst.set_continuous_states(&xs).unwrap(), "fmi2SetContinuousStates", inst);
                if !in_vr.is_empty() {
                    let us: Vec<f64> = (0..in_vr.len()).map(|j| u[j] + t * seeds[nx + j]).collect();
                    ok(inst.set_real(&in_vr, &us), "fmi2SetReal(inputs)", inst);
                }
            });
            let dd = dd_column(&mut me, &u_vr, &known_vr, &seeds, "all knowns");
            t_me.column(&at, "all knowns at once", &unknowns, &natural_sum, 1.0, &dd, &fd, Some(&combination));
            let dd = dd_column(&mut cs, &u_vr, &known_vr, &seeds, "all knowns");
            t_cs.column(&format!("{at} [ME finite differences]"), "all knowns at once", &unknowns, &natural_sum, 1.0, &dd, &fd, Some(&combination));
            if model.version == FmiVersion::Fmi3 {
                let scale_k: Vec<f64> = knowns.iter().map(|(k, x0, _)| known_scale(k, *x0).0).collect();
                for (inst, tally, what) in [(&mut me, &mut a_me, "ME"), (&mut cs, &mut a_cs, "CS")] {
                    failures.extend(check_adjoint(inst, tally, &u_vr, &known_vr, &scale, &scale_k, &format!("{} {at} {what}", model.name)));
                }
            }
        }
    }
    let head = format!("{} [{}], {} points", model.name, config.label, points.len());
    text += &t_cs.line(&format!("{head}, Co-Simulation"));
    text += &t_me.line(&format!("{head}, Model Exchange"));
    if model.version == FmiVersion::Fmi3 {
        text += &format!(
            "  {:<58} {:>5} sensitivities, worst {:.2e} (CS), {:>5}, worst {:.2e} (ME) of sum |seed_i J_ij|\n",
            format!("{head}, fmi3GetAdjointDerivative vs seed^T J"),
            a_cs.0,
            a_cs.1,
            a_me.0,
            a_me.1
        );
    }
    failures.extend(t_cs.first_failures(&format!("{} [{}] CS", model.name, config.label)));
    failures.extend(t_me.first_failures(&format!("{} [{}] ME", model.name, config.label)));
    (text, failures)
}

/// fmi3GetAdjointDerivative with every unknown seeded and every known asked, against
/// seed^T J built here from the instance's own directional-derivative columns (one known at a
/// time, seed 1), which the caller has just checked against finite differences. Returns the
/// failures; `tally` counts the sensitivities and keeps the worst relative error.
fn check_adjoint(
    inst: &mut Instance,
    tally: &mut (usize, f64),
    unknowns: &[ValueReference],
    knowns: &[ValueReference],
    scale_u: &[f64],
    scale_k: &[f64],
    at: &str,
) -> Vec<String> {
    // Seeds of the size 1 / (the unknown's scale), alternating in sign and varied in size, so
    // that every unknown weighs alike and no two can cancel.
    let seed: Vec<f64> = (0..unknowns.len())
        .map(|i| (1.0 + 0.29 * i as f64) * if i % 2 == 0 { 1.0 } else { -1.0 } / scale_u[i])
        .collect();
    let mut expected = vec![0.0; knowns.len()];
    let mut magnitude = vec![0.0; knowns.len()];
    for (j, k) in knowns.iter().enumerate() {
        let column = dd_column(inst, unknowns, &[*k], &[1.0], "adjoint reference");
        for i in 0..unknowns.len() {
            expected[j] += seed[i] * column[i];
            magnitude[j] += (seed[i] * column[i]).abs();
        }
    }
    let mut sensitivity = vec![f64::NAN; knowns.len()];
    let status = inst
        .get_adjoint_derivative(unknowns, knowns, &seed, &mut sensitivity)
        .expect("an FMI 3.0 instance has fmi3GetAdjointDerivative");
    ok(status, "fmi3GetAdjointDerivative", inst);
    let mut failures = Vec::new();
    for j in 0..knowns.len() {
        // Where seed^T J_j is 0 term by term, the natural size of a sensitivity instead.
        let natural: f64 = seed.iter().zip(scale_u).map(|(w, s)| w.abs() * s).sum::<f64>() / scale_k[j];
        let denom = if magnitude[j] > 0.0 { magnitude[j] } else { natural };
        let err = ratio((sensitivity[j] - expected[j]).abs(), denom);
        let err = if sensitivity[j].is_finite() { err } else { f64::INFINITY };
        tally.0 += 1;
        tally.1 = tally.1.max(err);
        if err > ADJOINT_TOL {
            failures.push(format!(
                "{at}: fmi3GetAdjointDerivative for known vr {} is {:.15e}, seed^T J from the directional derivatives {:.15e} (error {err:.3e} of {denom:.3e})",
                knowns[j], sensitivity[j], expected[j]
            ));
        }
    }
    failures
}

// ---- Initialization Mode: parameters, state start values and inputs are knowns -------------

fn check_initialization_mode(model: &Model, config: &Config, fmu_type: Fmi2Type, range: &[f64]) -> (String, Vec<String>) {
    let unknowns = model.unknowns();
    let u_vr = vrs(&unknowns);
    let mut inst = instantiate(model, fmu_type, config, "init");
    ok(inst.enter_initialization_mode(), "fmi2EnterInitializationMode", &inst);
    let mut tally = Tally::default();
    let mut skipped = Vec::new();
    let knowns: Vec<Var> = model.parameters.iter().chain(&model.exact_states).chain(&model.inputs).cloned().collect();
    for known in &knowns {
        let x0 = get(&mut inst, &[known.vr], "fmi2GetReal(known)")[0];
        let (s_k, h) = known_scale(known, x0);
        if known.min.is_some_and(|m| x0 - h < m) || known.max.is_some_and(|m| x0 + h > m) || (known.min == Some(0.0) && x0 - h <= 0.0) {
            skipped.push(known.name.clone());
            continue;
        }
        let dd = dd_column(&mut inst, &u_vr, &[known.vr], &[1.0], &known.name);
        let fd = fd_by(&mut inst, &u_vr, x0, h, |i, v| ok(i.set_real(&[known.vr], &[v]), &format!("fmi2SetReal({})", known.name), i));
        let scale = unknown_scales(&unknowns, range, &fd.f0);
        tally.column("Initialization Mode", &known.name, &unknowns, &scale, s_k, &dd, &fd, None);
    }
    let what = format!("{} [{}], initialization, {fmu_type:?}", model.name, config.label);
    let mut text = tally.line(&what);
    if !skipped.is_empty() {
        text += &format!("    (at a bound, not perturbed: {})\n", skipped.join(", "));
    }
    let failures = tally.first_failures(&what);
    (text, failures)
}

// ---- Tests ----------------------------------------------------------------------------------

fn finish(title: &str, text: String, failures: Vec<String>) {
    report(&format!("\n== {title}\n{text}"));
    if !failures.is_empty() {
        panic!(
            "Jacobian entries disagree with finite differences (the first ones of each FMU, configuration and interface):\n{}\n{text}",
            failures.join("\n")
        );
    }
}

fn default_config() -> Config {
    Config { label: "default experiment".into(), ..Config::default() }
}

/// The FMUs of every FMI version tested (`FMI_VERSIONS`; FMI 2.0's first).
fn every_fmu_path_of_every_version() -> Vec<PathBuf> {
    versions().into_iter().flat_map(every_fmu_path_for).collect()
}

#[test]
fn directional_derivatives_match_finite_differences_after_initialization() {
    let (mut text, mut failures) = (String::new(), Vec::new());
    for path in every_fmu_path_of_every_version() {
        let model = Model::load(&path);
        let (t, f) = check_after_initialization(&model, &default_config());
        text += &t;
        failures.extend(f);
    }
    finish("directional derivatives vs central differences, every FMU, default experiment", text, failures);
}

#[test]
fn directional_derivatives_match_finite_differences_in_initialization_mode() {
    let (mut text, mut failures) = (String::new(), Vec::new());
    for path in every_fmu_path_of_every_version() {
        let model = Model::load(&path);
        let config = default_config();
        let (range, _) = cs_ranges(&model, &config);
        let mut types = vec![Fmi2Type::CoSimulation];
        if model.structure.me_present {
            types.push(Fmi2Type::ModelExchange);
        }
        for fmu_type in types {
            let (t, f) = check_initialization_mode(&model, &config, fmu_type, &range);
            text += &t;
            failures.extend(f);
        }
    }
    finish("directional derivatives in Initialization Mode (parameters, state start values, inputs)", text, failures);
}

/// MotorFan's configurations beyond the default experiment (level c, direct-on-line): every
/// level with every start mode, the set-point filters and the rigid shaft, over 15 s.
#[test]
fn motor_fan_directional_derivatives_at_every_level_and_start_mode() {
    let (mut text, mut failures) = (String::new(), Vec::new());
    for version in versions() {
        let path = dist_dir_for(version).join("MotorFan.fmu");
        if !path.is_file() {
            report(&format!("\nMotorFan.fmu is not in {:?}: {version} skipped\n", dist_dir_for(version)));
            continue;
        }
        let model = Model::load(&path);
        for config in &motor_fan_configs() {
            let (t, f) = check_after_initialization(&model, config);
            text += &t;
            failures.extend(f);
        }
    }
    finish("MotorFan: directional derivatives vs central differences, every level and start mode (0-15 s)", text, failures);
}

fn motor_fan_configs() -> Vec<Config> {
    let mut configs = Vec::new();
    for level in 1..=4 {
        for start_mode in 1..=3 {
            configs.push(Config {
                label: format!("level {level}, start_mode {start_mode}"),
                integers: vec![("level", level), ("start_mode", start_mode)],
                booleans: vec![],
                stop: Some(15.0),
            });
        }
    }
    for filter in 1..=2 {
        configs.push(Config {
            label: format!("level 3, start_mode 2, setpoint_filter {filter}"),
            integers: vec![("level", 3), ("start_mode", 2), ("setpoint_filter", filter)],
            booleans: vec![],
            stop: Some(15.0),
        });
    }
    configs.push(Config {
        label: "level 4, start_mode 1, rigid shaft".into(),
        integers: vec![("level", 4), ("start_mode", 1)],
        booleans: vec![("keep_shaft_stiffness", false)],
        stop: Some(15.0),
    });
    configs
}
