//! The chapter's systematic analysis of effects (section 3.2.1, Table 3.1) and its activity
//! index (eq. 3.3), as the runtime keeps them for every model.
//!
//! A model declares the elements it is made of once: a name, the component (subset) it belongs
//! to, and the effect (domain and kind: source, transformer, storage C or I, dissipation R),
//! usually a constant of the component in `models/components` (`TorsionSpring::STIFFNESS`). Its
//! equations then report each element's power once, `der.power(element, p)`, from the values
//! they already compute. The runtime derives the rest:
//!
//! - the activity of every source, storage and dissipative element, A = integral of |P| dt
//!   (eq. 3.3), as a continuous state `A_<name>` under the solver's error control, with an
//!   output `activity_<name>`;
//! - each storage element's share of the storage elements' total activity and each dissipative
//!   element's share of the dissipative elements' total, `share_<name>` in % (Table 3.3 ranks
//!   the storage elements);
//! - the energy balance, `power_balance_residual` = sum of source powers - sum of stored powers
//!   - sum of dissipated powers, in W, and `power_balance_relative`, that residual over the
//!   largest element power: zero up to rounding when every power is reported and the equations
//!   are consistent, so an element left out of an equation, or a sign slip, shows;
//! - Table 3.1 in the FMU's documentation.
//!
//! Signs: a source reports the power it delivers into the model, a storage element the rate of
//! its stored energy dE/dt, a dissipative element the power it takes out of the model (>= 0 for
//! a passive one). Transformers and gyrators are lossless (a lossy one is a transformer plus an
//! R) and report nothing. A thermal resistance reports the heat flow through it, for its
//! activity; it passes that heat on (it produces entropy, it loses no energy), so the balance
//! leaves it out: a thermal network's balance is its heat sources and sinks against its heat
//! capacities.

use crate::real::Real;

/// The physical domain of an effect (Table 3.1, second column).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Domain {
    Electrical,
    Magnetic,
    Rotational,
    Translational,
    Hydraulic,
    Thermal,
    /// A signal (a set point, a controller): no power of its own.
    Signal,
}

impl Domain {
    pub fn as_str(self) -> &'static str {
        match self {
            Domain::Electrical => "electrical",
            Domain::Magnetic => "magnetic",
            Domain::Rotational => "mechanical (rotation)",
            Domain::Translational => "mechanical (translation)",
            Domain::Hydraulic => "hydraulic",
            Domain::Thermal => "thermal",
            Domain::Signal => "signal",
        }
    }
}

/// The kind of an effect (Table 3.1, third column).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Delivers power into the model (a voltage source, a motor's torque characteristic, a
    /// heat source); a sink is a source whose power is negative.
    Source,
    /// Converts power between two domains or two scales without loss (eq. 3.9's k, a gear ratio).
    Transformer,
    /// Converts power with the effort of one side set by the flow of the other (a gyrator).
    Gyrator,
    /// Stores energy as a function of its effort-side variable: a spring, a capacitor, a heat capacity.
    StorageC,
    /// Stores energy as a function of its flow-side variable: an inertia, an inductance.
    StorageI,
    /// Takes power out of the model: a resistance, a friction, a damper, a load.
    Dissipation,
}

impl Kind {
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Source => "source",
            Kind::Transformer => "transformer",
            Kind::Gyrator => "gyrator",
            Kind::StorageC => "storage (C)",
            Kind::StorageI => "storage (I)",
            Kind::Dissipation => "dissipation (R)",
        }
    }

    /// Whether the runtime integrates the element's activity (every kind that reports a power).
    pub fn has_activity(self) -> bool {
        !matches!(self, Kind::Transformer | Kind::Gyrator)
    }

    /// Whether the element is ranked among the storage elements (true) or the dissipative ones.
    pub fn is_storage(self) -> bool {
        matches!(self, Kind::StorageC | Kind::StorageI)
    }
}

/// One effect of a component, as the component states it (`TorsionSpring::STIFFNESS`): its
/// domains (two for a transformer between domains), its kind and what it is, in the chapter's words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Effect {
    pub domains: &'static [Domain],
    pub kind: Kind,
    /// The effect as Table 3.1 names it: "shaft stiffness", "winding resistance".
    pub what: &'static str,
}

impl Effect {
    /// The domains as Table 3.1 writes them: "electrical and mechanical (rotation)".
    pub fn domain_text(&self) -> String {
        self.domains.iter().map(|d| d.as_str()).collect::<Vec<_>>().join(" and ")
    }

    /// Whether the element's power enters the energy balance.
    pub fn in_balance(&self) -> bool {
        self.kind.has_activity() && !(self.kind == Kind::Dissipation && self.domains == [Domain::Thermal])
    }
}

/// A declared element whose power the equations report: `der.power(element, p)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Element {
    /// Position in `VariableTable::elements`.
    pub(crate) index: usize,
    /// The state index of its activity `A_<name>`, for elements with an activity.
    pub(crate) activity: Option<usize>,
}

/// What the runtime keeps of one element: Table 3.1's row and where its values live.
#[derive(Clone, Debug, PartialEq)]
pub struct ElementInfo {
    /// The element's name, the suffix of its variables: "shaft_stiffness".
    pub name: String,
    /// The component (subset) it belongs to, Table 3.1's first column: "Driveshaft".
    pub component: String,
    pub effect: Effect,
    /// What the model says about it (its law, its parameter).
    pub description: String,
    /// Why the model leaves it out, for an effect listed in Table 3.1 but not modelled.
    pub neglected: Option<String>,
    /// State index of `A_<name>`.
    pub activity_state: Option<usize>,
    /// Calculated-store index of `activity_<name>`.
    pub activity_output: Option<usize>,
    /// Calculated-store index of `share_<name>`.
    pub share_output: Option<usize>,
}

/// Calculated-store indices of the balance outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BalanceOutputs {
    pub residual: usize,
    pub relative: usize,
}

/// The energy balance at one instant from the reported powers (one per element, NaN where an
/// element with no power has none): (residual in W, residual over the largest power).
pub fn balance<R: Real>(elements: &[ElementInfo], powers: &[R]) -> (R, R) {
    let (mut residual, mut largest) = (R::from(0.0), R::from(0.0));
    for (e, &p) in elements.iter().zip(powers) {
        if !e.effect.in_balance() || e.neglected.is_some() {
            continue;
        }
        largest = largest.max(p.abs());
        residual += if e.effect.kind == Kind::Source { p } else { -p };
    }
    let relative = if largest > 0.0 { residual / largest } else { R::from(0.0) };
    (residual, relative)
}

/// Fills in `activity_<name>` and `share_<name>` from the activity states.
pub(crate) fn write_activity_outputs<R: Real>(elements: &[ElementInfo], states: &[R], calculated: &mut [R]) {
    // The activities the shares are of: storage and dissipation apart.
    let (mut storage_total, mut dissipation_total) = (R::from(0.0), R::from(0.0));
    for e in elements.iter().filter(|e| e.share_output.is_some()) {
        if let Some(s) = e.activity_state {
            *(if e.effect.kind.is_storage() { &mut storage_total } else { &mut dissipation_total }) += states[s];
        }
    }
    for e in elements {
        let Some(s) = e.activity_state else { continue };
        if let Some(y) = e.activity_output {
            calculated[y] = states[s];
        }
        if let Some(y) = e.share_output {
            let sum = if e.effect.kind.is_storage() { storage_total } else { dissipation_total };
            calculated[y] = if sum > 0.0 { states[s] * 100.0 / sum } else { R::from(0.0) };
        }
    }
}

/// Fills in the balance outputs from the reported powers.
pub(crate) fn write_balance<R: Real>(elements: &[ElementInfo], outputs: BalanceOutputs, powers: &[R], calculated: &mut [R]) {
    let (residual, relative) = balance(elements, powers);
    calculated[outputs.residual] = residual;
    calculated[outputs.relative] = relative;
}

/// Table 3.1 for the documentation: one row per component, its domains and its effects, in
/// declaration order; neglected effects are listed with the reason.
pub fn effects_table_html(elements: &[ElementInfo]) -> String {
    use crate::documentation::escape;
    if elements.is_empty() {
        return String::new();
    }
    let mut components: Vec<&str> = Vec::new();
    for e in elements {
        if !components.contains(&e.component.as_str()) {
            components.push(&e.component);
        }
    }
    let mut s = String::from(
        "<h3>Systematic analysis of effects (the chapter's Table 3.1)</h3>\n<table>\n<tr><th>component</th><th>domain</th><th>effects</th></tr>\n",
    );
    for c in components {
        let of: Vec<&ElementInfo> = elements.iter().filter(|e| e.component == c).collect();
        let mut domains: Vec<String> = Vec::new();
        for e in &of {
            let d = e.effect.domain_text();
            if !domains.contains(&d) {
                domains.push(d);
            }
        }
        let effects: Vec<String> = of
            .iter()
            .map(|e| match &e.neglected {
                None => format!("{} (<code>{}</code>): {}", escape(e.effect.what), escape(&e.name), e.effect.kind.as_str()),
                Some(why) => format!("{}: {}, neglected ({})", escape(e.effect.what), e.effect.kind.as_str(), escape(why)),
            })
            .collect();
        s += &format!("<tr><td>{}</td><td>{}</td><td>{}</td></tr>\n", escape(c), escape(&domains.join("; ")), effects.join("<br>"));
    }
    s + "</table>\n"
}

/// Table 3.1 as plain text, one line per effect: component, domain, kind, effect, element.
pub fn effects_table_text(elements: &[ElementInfo]) -> String {
    let mut s = format!("{:<22} {:<40} {:<16} {:<34} {}\n", "component", "domain", "kind", "effect", "element");
    let mut components: Vec<&str> = Vec::new();
    for e in elements {
        if !components.contains(&e.component.as_str()) {
            components.push(&e.component);
        }
    }
    for e in components.iter().flat_map(|c| elements.iter().filter(move |e| e.component == *c)) {
        let element = match &e.neglected {
            None => e.name.clone(),
            Some(why) => format!("(neglected: {why})"),
        };
        s += &format!("{:<22} {:<40} {:<16} {:<34} {}\n", e.component, e.effect.domain_text(), e.effect.kind.as_str(), e.effect.what, element);
    }
    s
}

#[cfg(test)]
pub(crate) mod tests {
    use crate::prelude::*;

    const FORCE: Effect = Effect { domains: &[Domain::Translational], kind: Kind::Source, what: "applied force" };
    const MASS: Effect = Effect { domains: &[Domain::Translational], kind: Kind::StorageI, what: "mass" };
    const SPRING: Effect = Effect { domains: &[Domain::Translational], kind: Kind::StorageC, what: "spring" };
    const DAMPER: Effect = Effect { domains: &[Domain::Translational], kind: Kind::Dissipation, what: "damper" };

    /// m dv/dt = F - k x - b v, dx/dt = v; `broken` leaves the damper's force out of the
    /// equation of motion (the slip the balance must show); `silent` reports no damper power.
    pub struct Oscillator<const BROKEN: bool, const SILENT: bool> {
        x: State,
        v: State,
        force: Element,
        mass: Element,
        spring: Element,
        damper: Element,
    }

    impl<const BROKEN: bool, const SILENT: bool> Model for Oscillator<BROKEN, SILENT> {
        fn info() -> ModelInfo {
            ModelInfo {
                name: "Oscillator",
                description: "a forced mass-spring-damper",
                default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 2.0, step_size: 0.01 },
                solver: Solver::ExplicitRungeKutta,
                documentation: "",
            }
        }
        fn declare(d: &mut Declarations) -> Self {
            d.neglected("Spring", MASS, "the spring's own mass is small");
            Oscillator {
                x: d.state("x", 0.1, "m").describe("extension"),
                v: d.state("v", 0.0, "m/s").describe("speed"),
                force: d.element("force", "Actuator", FORCE).describe("the force 3 sin(2 t) N"),
                mass: d.element("mass", "Body", MASS).nominal(1e-3).describe("the 2 kg mass"),
                spring: d.element("spring", "Spring", SPRING).describe("the 50 N/m spring"),
                damper: d.element("damper", "Damper", DAMPER).describe("the 0.8 N s/m damper"),
            }
        }
        fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
            let (x, v, f) = (k[self.x], k[self.v], 3.0 * (2.0 * k.time()).sin());
            let damping = if BROKEN { R::from(0.0) } else { v * 0.8 };
            let a = (R::from(f) - x * 50.0 - damping) / 2.0;
            der[self.x] = v;
            der[self.v] = a;
            der.power(self.force, v * f);
            der.power(self.mass, a * 2.0 * v);
            der.power(self.spring, x * 50.0 * v);
            if !SILENT {
                der.power(self.damper, v * 0.8 * v);
            }
        }
        fn outputs<R: Real>(&self, _: &Knowns<R>, _: &mut Outputs<R>) {}
    }

    fn run<M: Model>(steps: usize) -> (crate::variables::VariableTable, Vec<f64>) {
        let (model, _, table) = crate::model::declare::<M>();
        let values = table.start_values();
        let mut x = values.states.clone();
        let (mut der, mut calc) = (vec![0.0; table.n_states], vec![0.0; table.n_calculated]);
        let h = 1e-4;
        let mut worst = 0.0f64;
        for n in 0..steps {
            let t = n as f64 * h;
            crate::model::evaluate(&model, &table, t, &values.known, &x, &values.integers, &values.booleans, &mut der, &mut calc);
            worst = worst.max(calc[table.balance.unwrap().relative].abs());
            for (xi, di) in x.iter_mut().zip(&der) {
                *xi += h * di; // explicit Euler: enough to move the activities
            }
        }
        calc.push(worst);
        (table, calc)
    }

    fn output(table: &crate::variables::VariableTable, calc: &[f64], name: &str) -> f64 {
        match table.by_name(name).unwrap_or_else(|| panic!("no {name}")).slot {
            crate::variables::Slot::Calculated(i) => calc[i],
            other => panic!("{name}: {other:?}"),
        }
    }

    #[test]
    fn activities_shares_and_the_balance_come_from_the_reported_powers() {
        let (table, calc) = run::<Oscillator<false, false>>(20_000);
        let worst = *calc.last().unwrap();
        assert!(worst < 1e-12, "the oscillator's powers add up to rounding: worst {worst:e}");
        for name in ["A_force", "A_mass", "A_spring", "A_damper", "activity_mass", "share_mass", "share_spring", "share_damper"] {
            assert!(table.by_name(name).is_some(), "{name} declared");
        }
        assert!(table.by_name("share_force").is_none(), "a source has no share");
        let (m, s, d) = (output(&table, &calc, "share_mass"), output(&table, &calc, "share_spring"), output(&table, &calc, "share_damper"));
        assert!((m + s - 100.0).abs() < 1e-9 && m > 0.0 && s > 0.0, "storage shares sum to 100: {m} + {s}");
        assert_eq!(d, 100.0, "the only dissipative element has all of their activity");
        assert_eq!(table.variables.iter().find(|v| v.name == "A_mass").unwrap().nominal, Some(1e-3));
        let html = super::effects_table_html(&table.elements);
        assert!(html.contains("<td>Spring</td>") && html.contains("mass: storage (I), neglected (the spring's own mass is small)"), "{html}");
    }

    #[test]
    fn a_force_left_out_of_an_equation_breaks_the_balance() {
        let (_, calc) = run::<Oscillator<true, false>>(20_000);
        let worst = *calc.last().unwrap();
        assert!(worst > 0.1, "the damper's force missing from m dv/dt shows in the balance: worst {worst:e}");
    }

    #[test]
    fn an_element_without_a_reported_power_is_a_declaration_problem() {
        let d = crate::description::ModelDescription::of::<Oscillator<false, true>>();
        let problems = d.table.problems.iter().chain(&d.problems).filter(|p| p.contains("element 'damper' has no power reported")).count();
        assert_eq!(problems, 1, "{:?}", d.problems);
        let ok = crate::description::ModelDescription::of::<Oscillator<false, false>>();
        assert!(!ok.problems.iter().any(|p| p.contains("no power reported")), "{:?}", ok.problems);
    }
}
