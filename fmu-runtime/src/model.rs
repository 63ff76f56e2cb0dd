//! The `Model` trait: what a model author writes. Plain physics — declarations, derivatives,
//! outputs — with no FMI, no XML and no unsafe code. The runtime derives the rest.

use crate::real::Real;
use crate::values::{Derivatives, EventIndicators, InitialStates, Knowns, ModeUpdate, Outputs};
use crate::variables::{Declarations, VariableTable};

/// How `fmi2DoStep` integrates the model's ODE (see `integrate.rs`). Each variant is a file in
/// `stepper/`, registered in `stepper::registered` (docs/DESIGN.md, "Adding a solver method").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// Explicit Runge-Kutta (Tsitouras 5(4), diffsol `tsit45`): non-stiff models.
    ExplicitRungeKutta,
    /// Singly diagonally implicit Runge-Kutta (Kennedy and Carpenter's ESDIRK5(4)7L[2]SA_2, fifth
    /// order, L-stable; Newton with a kept exact Jacobian, dense, band or sparse LU): stiff models, of any size,
    /// e.g. electrical time constants beside seconds of mechanics. A single-step method, so a
    /// communication point costs it no history (unlike BDF).
    ImplicitRungeKutta,
}

/// The experiment a model suggests (FMI `DefaultExperiment`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DefaultExperiment {
    pub start_time: f64,
    pub stop_time: f64,
    /// Communication step a master should use to see the dynamics, s.
    pub step_size: f64,
}

/// What a model says about itself.
#[derive(Clone, Debug)]
pub struct ModelInfo {
    /// FMI model name, modelIdentifier and the name of the `.fmu`: a C identifier.
    pub name: &'static str,
    /// One sentence: what the model is and where it comes from.
    pub description: &'static str,
    pub default_experiment: DefaultExperiment,
    pub solver: Solver,
    /// An HTML fragment for documentation/index.html: the equations and the reasoning behind
    /// the chosen parameter values. The runtime adds the variable tables.
    pub documentation: &'static str,
}

/// A lumped-parameter model: an ODE dx/dt = f(t, x, p, u) with outputs y = g(t, x, p, u).
///
/// The struct implementing it holds only the handles returned by its declarations; every
/// value lives in the instance, so the same equations serve Co-Simulation (and later Model
/// Exchange), FMU state save/restore and the generated modelDescription.xml.
pub trait Model: Sized + Send + Sync + 'static {
    /// Name, description, default experiment, solver choice, documentation.
    fn info() -> ModelInfo;

    /// Declares every variable once (name, start, unit, bounds, description) and keeps the
    /// handles. Value references follow declaration order.
    fn declare(d: &mut Declarations) -> Self;

    /// Whether the FMU extrapolates its inputs by default (the FMI Boolean parameter
    /// `extrapolate_inputs`, declared by the runtime for every model with inputs): over a
    /// Co-Simulation step with no input derivatives from the master, each input follows the line
    /// through its values at the last two communication points instead of being held. Right for
    /// physical couplings (speeds, torques) with masters that hold inputs; wrong for inputs that
    /// jump (a switched voltage), so off unless a model says otherwise.
    fn extrapolates_inputs() -> bool {
        false
    }

    /// The loosest relative tolerance the model's Co-Simulation solver runs at with the
    /// parameters in `k` (FMI's `fmi2SetupExperiment` tolerance, or the default, is tightened to
    /// it, with a logged warning that names both): for a model whose errors grow far beyond the
    /// tolerance asked for, e.g. an explicit method riding its stability limit on a stiff mode
    /// (docs/DESIGN.md, "Accuracy that follows the tolerance"). It may depend on the parameters
    /// (a configuration that does not ring needs none, and a floor below what round-off allows
    /// only costs steps); the one at the default parameters is the DefaultExperiment's tolerance.
    /// Read when initialization ends. Model Exchange is unaffected: the master's own solver
    /// integrates. None: any tolerance the master asks for is used as given.
    fn tolerance_floor(&self, _k: &Knowns) -> Option<f64> {
        None
    }

    /// Checks relations between parameters that per-variable min/max cannot express; called
    /// when initialization ends. The message names the offending parameter.
    fn check(&self, _k: &Knowns) -> Result<(), String> {
        Ok(())
    }

    /// The first instant strictly after `after` at which the equations change non-smoothly
    /// (the end of a ramp, a voltage step, a short circuit). `fmi2DoStep` stops the solver
    /// there and restarts it, instead of stepping across the kink. None: no more events.
    fn next_time_event(&self, _k: &Knowns, _after: f64) -> Option<f64> {
        None
    }

    /// The initial values of the states declared with `Declarations::calculated_state`, from
    /// the parameters and the inputs at the start time (`k` holds them; the calculated states
    /// themselves read NaN there). Called during initialization; every calculated state must be
    /// given a finite value, or initialization fails naming it. Other states keep their start.
    fn initial_states<R: Real>(&self, _k: &Knowns<R>, _x0: &mut InitialStates<R>) {}

    /// The event indicators z at the knowns `k` (which include the current discrete modes,
    /// `k[mode]`), one per `Declarations::event_indicator`. An event happens where an indicator
    /// changes sign; a model makes each indicator continuous in time while its modes hold (e.g.
    /// the speed of a slipping body, or the margin T_static - |T_required| of a stuck one).
    fn event_indicators(&self, _k: &Knowns, _z: &mut EventIndicators) {}

    /// At an event (and at the end of initialization): the discrete modes after it, from the
    /// knowns `k` at the event. Write the new modes into `next` (it starts as the current ones);
    /// `next.reinit(state, value)` sets a state where the physics says so. The runtime calls this
    /// again until nothing changes (at most `MAX_MODE_ITERATIONS` times). Let a mode hold exactly
    /// while its indicator is > 0: the point the runtime (or an ME master) stops at has the
    /// indicator <= 0, possibly exactly 0, and the update must then leave the mode. For a model
    /// that declares no mode it runs only at events and at initialization, not at every
    /// communication point.
    fn update_modes(&self, _k: &Knowns, _next: &mut ModeUpdate) {}

    /// The state derivatives dx/dt at the knowns `k`. Written over any scalar `R` ([`Real`]):
    /// the runtime evaluates them with `f64` for values and with [`crate::real::Dual`] for exact
    /// directional derivatives (docs/DESIGN.md, "Exact derivatives").
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>);

    /// The outputs, locals and calculated parameters at the knowns `k` (over any scalar, as
    /// `derivatives`).
    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>);
}

/// Evaluates a model's equations at one point: the derivatives and the calculated values
/// (outputs, locals, calculated parameters, the runtime's activity, share and balance outputs),
/// written into `derivatives` and `calculated`. Over any scalar: `f64` for values, [`Dual`]
/// for exact directional derivatives.
///
/// [`Dual`]: crate::real::Dual
#[allow(clippy::too_many_arguments)]
pub fn evaluate<M: Model, R: Real>(
    model: &M,
    table: &VariableTable,
    time: f64,
    known: &[R],
    states: &[R],
    integers: &[i32],
    booleans: &[bool],
    derivatives: &mut [R],
    calculated: &mut [R],
) {
    evaluate_derivatives(model, time, known, states, integers, booleans, derivatives);
    evaluate_outputs_but_balance(model, table, time, known, states, integers, booleans, calculated);
    evaluate_balance(model, table, time, known, states, integers, booleans, calculated, &mut Vec::new());
}

/// The derivatives alone (see [`evaluate`]).
pub fn evaluate_derivatives<M: Model, R: Real>(model: &M, time: f64, known: &[R], states: &[R], integers: &[i32], booleans: &[bool], derivatives: &mut [R]) {
    derivatives.fill(R::from(0.0));
    model.derivatives(&Knowns::new(time, known, states, integers, booleans), &mut Derivatives::new(derivatives));
}

/// The derivatives with each declared element's reported power (`der.power`) recorded in
/// `powers` (one per element of `table.elements`; NaN where the model reported none).
#[allow(clippy::too_many_arguments)]
pub fn evaluate_powers<M: Model, R: Real>(model: &M, time: f64, known: &[R], states: &[R], integers: &[i32], booleans: &[bool], derivatives: &mut [R], powers: &mut [R]) {
    derivatives.fill(R::from(0.0));
    powers.fill(R::from(f64::NAN));
    model.derivatives(&Knowns::new(time, known, states, integers, booleans), &mut Derivatives::with_powers(derivatives, powers));
}

/// The calculated values but the energy-balance outputs: the model's outputs, locals and
/// calculated parameters, and the activity and share outputs (from the states alone).
#[allow(clippy::too_many_arguments)]
pub fn evaluate_outputs_but_balance<M: Model, R: Real>(
    model: &M,
    table: &VariableTable,
    time: f64,
    known: &[R],
    states: &[R],
    integers: &[i32],
    booleans: &[bool],
    calculated: &mut [R],
) {
    model.outputs(&Knowns::new(time, known, states, integers, booleans), &mut Outputs::new(calculated));
    crate::elements::write_activity_outputs(&table.elements, states, calculated);
}

/// The energy-balance outputs (`power_balance_residual`, `power_balance_relative`), which take
/// an evaluation of the derivatives for the elements' powers; nothing for a model without them.
/// `work` is scratch space (it grows once, then is reused).
#[allow(clippy::too_many_arguments)]
pub fn evaluate_balance<M: Model, R: Real>(
    model: &M,
    table: &VariableTable,
    time: f64,
    known: &[R],
    states: &[R],
    integers: &[i32],
    booleans: &[bool],
    calculated: &mut [R],
    work: &mut Vec<R>,
) {
    let Some(outputs) = table.balance else { return };
    work.resize(table.n_states + table.elements.len(), R::from(0.0));
    let (rates, powers) = work.split_at_mut(table.n_states);
    evaluate_powers(model, time, known, states, integers, booleans, rates, powers);
    crate::elements::write_balance(&table.elements, outputs, powers, calculated);
}

/// Fills in the calculated states of `states` (which holds the start values of the others)
/// through `Model::initial_states`; the message names a state left without a finite value.
pub fn initialize_states<M: Model, R: Real>(
    model: &M,
    table: &crate::variables::VariableTable,
    time: f64,
    known: &[R],
    integers: &[i32],
    booleans: &[bool],
    states: &mut [R],
) -> Result<(), String> {
    let calculated: Vec<usize> = table.calculated_states().collect();
    if calculated.is_empty() {
        return Ok(());
    }
    for &s in &calculated {
        states[s] = R::from(f64::NAN);
    }
    let starts = states.to_vec();
    let k = Knowns::new(time, known, &starts, integers, booleans);
    model.initial_states(&k, &mut InitialStates::new(states));
    for &s in &calculated {
        if !states[s].is_finite() {
            let name = &table.variables[table.state_value_reference[s] as usize].name;
            return Err(format!("the model computed no finite initial value for the state '{name}' (got {})", states[s].value()));
        }
    }
    Ok(())
}

/// The model's tolerance floor at its default parameters and start values, at the default
/// experiment's start (`Model::tolerance_floor`): what its DefaultExperiment declares.
pub fn default_tolerance_floor<M: Model>(model: &M, table: &VariableTable) -> Option<f64> {
    let v = table.start_values();
    model.tolerance_floor(&Knowns::new(M::info().default_experiment.start_time, &v.known, &v.states, &v.integers, &v.booleans))
}

/// What the runtime itself declares beside a model's own variables.
#[derive(Clone, Copy, Debug)]
pub struct RuntimeVariables {
    /// `extrapolate_inputs`, for models with inputs.
    pub extrapolate_inputs: Option<crate::variables::BooleanParameter>,
    /// `state_events`, for models with event indicators: how many state events were handled.
    pub state_events: Option<crate::variables::Mode>,
}

/// Declares a model's variables, then the runtime's (after them, so the model's value
/// references do not depend on the runtime's).
pub fn declare<M: Model>() -> (M, RuntimeVariables, crate::variables::VariableTable) {
    let mut d = crate::variables::Declarations::new();
    let model = M::declare(&mut d);
    let extrapolate_inputs = d.has_inputs().then(|| {
        d.boolean_parameter("extrapolate_inputs", M::extrapolates_inputs()).describe(
            "Co-Simulation: over a step without input derivatives from the master, extrapolate each input \
             linearly through its values at the last two communication points (instead of holding it)",
        )
    });
    let state_events = d.has_event_indicators().then(|| {
        d.mode("state_events", 0).describe(
            "Number of state events handled: in Co-Simulation each zero crossing of an event indicator located \
             inside fmi2DoStep, in Model Exchange each event iteration in which a discrete mode or a state changed",
        )
    });
    d.declare_power_balance();
    (model, RuntimeVariables { extrapolate_inputs, state_events }, d.into_table())
}

/// The first derivative, calculated value (output, local, calculated parameter) or event
/// indicator that is not finite at one point, or what the equations panicked with. The states
/// are those of `values`, with the calculated ones computed afresh when `initial`.
fn first_non_finite<M: Model>(model: &M, table: &crate::variables::VariableTable, time: f64, values: &crate::values::Values, initial: bool) -> Option<String> {
    use crate::variables::Slot;
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let mut states = values.states.clone();
        if initial {
            if let Err(message) = initialize_states(model, table, time, &values.known, &values.integers, &values.booleans, &mut states) {
                return Some(message);
            }
        }
        let mut derivatives = vec![0.0; table.n_states];
        let mut calculated = values.calculated.clone();
        evaluate(model, table, time, &values.known, &states, &values.integers, &values.booleans, &mut derivatives, &mut calculated);
        let mut z = vec![0.0; table.indicators.len()];
        let k = Knowns::new(time, &values.known, &states, &values.integers, &values.booleans);
        model.event_indicators(&k, &mut crate::values::EventIndicators::new(&mut z));
        let bad = |x: f64| !x.is_finite();
        for var in &table.variables {
            let x = match var.slot {
                Slot::Derivative(i) => derivatives[i],
                Slot::Calculated(i) => calculated[i],
                _ => continue,
            };
            if bad(x) {
                return Some(format!("{} = {} is not finite", var.name, crate::variables::number(x)));
            }
        }
        z.iter().position(|x| bad(*x)).map(|i| format!("event indicator '{}' = {} is not finite", table.indicators[i].0, z[i]))
    }));
    run.unwrap_or_else(|payload| {
        let text = payload.downcast_ref::<&str>().map(|s| s.to_string()).or_else(|| payload.downcast_ref::<String>().cloned());
        Some(format!("the equations panicked ({})", text.unwrap_or_else(|| "no message".into())))
    })
}

/// At the end of initialization: every derivative, output, local, calculated parameter and event
/// indicator at the start must be finite, so that a master never reads a silent NaN. A value
/// inside its declared range can still be outside what the equations take (an inductance at its
/// declared minimum, 2.2e-308 H, makes di/dt infinite); the message then names the parameters (or
/// inputs, or state start values) responsible: those set away from their defaults whose default
/// alone makes every value finite again. The states are those of `values`.
pub fn check_finite_start<M: Model>(model: &M, table: &crate::variables::VariableTable, time: f64, values: &crate::values::Values) -> Result<(), String> {
    use crate::variables::{number, Slot, Start};
    let Some(what) = first_non_finite(model, table, time, values, false) else { return Ok(()) };
    let defaults = table.start_values();
    let mut moved = Vec::new();
    let mut culprits = Vec::new();
    for var in table.variables.iter().filter(|v| v.is_settable_before_initialization()) {
        let mut trial = values.clone();
        let (now, default) = match (var.slot, var.start) {
            (Slot::Known(i), Some(Start::Real(d))) if values.known[i].to_bits() != d.to_bits() => {
                trial.known[i] = d;
                (number(values.known[i]), number(d))
            }
            (Slot::State(s), Some(Start::Real(d))) if values.states[s].to_bits() != d.to_bits() => {
                trial.states[s] = d;
                (number(values.states[s]), number(d))
            }
            (Slot::Integer(i), _) if values.integers[i] != defaults.integers[i] => {
                trial.integers[i] = defaults.integers[i];
                (values.integers[i].to_string(), defaults.integers[i].to_string())
            }
            (Slot::Boolean(i), _) if values.booleans[i] != defaults.booleans[i] => {
                trial.booleans[i] = defaults.booleans[i];
                (values.booleans[i].to_string(), defaults.booleans[i].to_string())
            }
            _ => continue,
        };
        let text = format!("{} = {now}", var.name);
        if first_non_finite(model, table, time, &trial, true).is_none() {
            culprits.push(format!("{text} (finite with its default {default})"));
        }
        moved.push(text);
    }
    Err(if !culprits.is_empty() {
        format!("at the start {what} with {}. Fix: give it a value the physics takes, inside its range", culprits.join(", "))
    } else if !moved.is_empty() {
        format!("at the start {what} with these values set away from their defaults: {}. Fix: choose values the physics takes", moved.join(", "))
    } else {
        format!("at the start {what} with the default values. Fix: the model's equations must give finite values at its defaults")
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_model::Block;
    use crate::variables::Slot;

    #[test]
    fn a_value_the_equations_cannot_take_is_named_at_initialization() {
        let (model, _, table) = declare::<Block>();
        let mut values = table.start_values();
        values.integers[0] = 1; // slipping forwards: der(v) = (u - F_c) / m
        assert_eq!(check_finite_start(&model, &table, 0.0, &values), Ok(()));
        let known = |name: &str| match table.by_name(name).unwrap().slot {
            Slot::Known(i) => i,
            _ => unreachable!(),
        };
        // m at its declared minimum alone is fine here: -1.5 / 2.2e-308 is still finite.
        values.known[known("m")] = f64::MIN_POSITIVE;
        assert_eq!(check_finite_start(&model, &table, 0.0, &values), Ok(()));
        // With a large force it is not: both values are named, each finite with its default.
        values.known[known("u")] = 1e300;
        let err = check_finite_start(&model, &table, 0.0, &values).unwrap_err();
        assert!(err.starts_with("at the start der(v) = inf is not finite with "), "{err}");
        assert!(err.contains("m = 2.2250738585072014e-308 (finite with its default 1)") && err.contains("u = 1e300 (finite with its default 0)"), "{err}");
    }
}
