//! A small model for the runtime's own unit tests: dx/dt = -a x + u, y = 2 x, w = a u.
use crate::model::{DefaultExperiment, Model, ModelInfo, Solver};
use crate::real::Real;
use crate::values::{Derivatives, Knowns, Outputs};
use crate::variables::{Declarations, Input, Output, Parameter, State};

/// dx/dt = -a x + u; y = 2 x; w = a u.
pub struct Decay {
    a: Parameter,
    u: Input,
    x: State,
    y: Output,
    w: Output,
}

impl Model for Decay {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "Decay",
            description: "test <model> & \"quotes\"",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 1.0, step_size: 0.01 },
            solver: Solver::ExplicitRungeKutta,
            documentation: "",
        }
    }
    fn declare(d: &mut Declarations) -> Self {
        Decay {
            a: d.parameter("a", 2.0, "Hz").min(0.0).describe("rate"),
            u: d.input("u", 0.0, "1").describe("input"),
            x: d.state("x", 1.0, "1").describe("state"),
            y: d.output("y", "1").describe("twice the state"),
            w: d.output("w", "1").describe("the input times a"),
        }
    }
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        der[self.x] = -k[self.a] * k[self.x] + k[self.u];
    }
    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        out[self.y] = k[self.x] * 2.0;
        out[self.w] = k[self.a] * k[self.u];
    }
}


/// dx/dt = 0 before `t_on`, 1 after: a step the solver must not step across blindly.
pub struct Switch {
    t_on: Parameter,
    x: State,
}

impl Model for Switch {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "Switch",
            description: "a time event",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 1.0, step_size: 0.1 },
            solver: Solver::ExplicitRungeKutta,
            documentation: "",
        }
    }
    fn declare(d: &mut Declarations) -> Self {
        Switch { t_on: d.parameter("t_on", 0.35, "s").describe("switch time"), x: d.state("x", 0.0, "s").describe("time since the switch") }
    }
    fn next_time_event(&self, k: &Knowns, after: f64) -> Option<f64> {
        (k[self.t_on] > after).then_some(k[self.t_on])
    }
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        der[self.x] = R::from(if k.time() >= k[self.t_on].value() { 1.0 } else { 0.0 });
    }
    fn outputs<R: Real>(&self, _: &Knowns<R>, _: &mut Outputs<R>) {}
}

/// A body relaxing to `u + p/g`: C dT/dt = p - g (T - u). Its temperature T starts either at the
/// input u (`steady` false) or at the steady value u + p/g (`steady` true): a calculated state.
pub struct Relax {
    p: Parameter,
    g: Parameter,
    steady: crate::variables::BooleanParameter,
    u: Input,
    t: State,
    y: Output,
}

impl Model for Relax {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "Relax",
            description: "a calculated initial state",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 1.0, step_size: 0.1 },
            solver: Solver::ExplicitRungeKutta,
            documentation: "",
        }
    }
    fn declare(d: &mut Declarations) -> Self {
        Relax {
            p: d.parameter("p", 3.0, "W").describe("heat flow"),
            g: d.parameter("g", 2.0, "W/K").min(0.0).describe("conductance (0 makes the steady start impossible)"),
            steady: d.boolean_parameter("steady", true).describe("start at the steady state"),
            u: d.input("u", 10.0, "K").describe("ambient"),
            t: d.calculated_state("T", "K").describe("temperature"),
            y: d.output("y", "K").describe("the temperature"),
        }
    }
    fn initial_states<R: Real>(&self, k: &Knowns<R>, x0: &mut crate::values::InitialStates<R>) {
        x0[self.t] = if k[self.steady] { k[self.u] + k[self.p] / k[self.g] } else { k[self.u] };
    }
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        der[self.t] = k[self.p] - k[self.g] * (k[self.t] - k[self.u]);
    }
    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        out[self.y] = k[self.t];
    }
}

/// A block with Coulomb friction, pushed by a force input: stick/slip with discrete modes (in
/// rotational units, a rotor: x in rad, v in rad/s, forces in N m, mass in kg m2).
/// m dv/dt = u - F_c mode while slipping (mode = +-1), v = 0 while stuck (mode = 0, |u| <= F_s).
pub struct Block {
    mass: Parameter,
    f_coulomb: Parameter,
    f_static: Parameter,
    force: Input,
    x: State,
    v: State,
    mode: crate::variables::Mode,
    z: crate::variables::Indicator,
}

impl Model for Block {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "Block",
            description: "stick/slip",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 4.0, step_size: 0.1 },
            solver: Solver::ExplicitRungeKutta,
            documentation: "",
        }
    }
    fn declare(d: &mut Declarations) -> Self {
        Block {
            mass: d.parameter("m", 1.0, "kg.m2").positive().describe("mass"),
            f_coulomb: d.parameter("F_c", 1.5, "N.m").min(0.0).describe("Coulomb friction"),
            f_static: d.parameter("F_s", 2.0, "N.m").min(0.0).describe("static friction"),
            force: d.input("u", 0.0, "N.m").describe("applied force"),
            x: d.state("x", 0.0, "rad").describe("position"),
            v: d.state("v", 3.0, "rad/s").describe("velocity"),
            mode: d.mode("friction_mode", 0).range(-1, 1).describe("-1 slipping backwards, 0 stuck, 1 slipping forwards"),
            z: d.event_indicator("friction", "velocity while slipping, static margin while stuck"),
        }
    }
    fn event_indicators(&self, k: &Knowns, z: &mut crate::values::EventIndicators) {
        let mode = k[self.mode] as f64;
        z[self.z] = if mode == 0.0 { k[self.f_static] - k[self.force].abs() } else { mode * k[self.v] };
    }
    fn update_modes(&self, k: &Knowns, next: &mut crate::values::ModeUpdate) {
        let (v, u, mode) = (k[self.v], k[self.force], k[self.mode]);
        let at_rest = |next: &mut crate::values::ModeUpdate| {
            next.reinit(self.v, 0.0);
            // Stuck while its indicator F_s - |u| is > 0 (a mode holds while its indicator is > 0).
            next[self.mode] = if k[self.f_static] - u.abs() > 0.0 { 0 } else { u.signum() as i32 };
        };
        match mode {
            0 if v != 0.0 => next[self.mode] = v.signum() as i32,
            0 => at_rest(next),
            m if (m as f64) * v <= 0.0 => at_rest(next),
            _ => {}
        }
    }
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let mode = k[self.mode] as f64;
        der[self.x] = k[self.v];
        der[self.v] = if mode == 0.0 { R::from(0.0) } else { (k[self.force] - k[self.f_coulomb] * mode) / k[self.mass] };
    }
    fn outputs<R: Real>(&self, _: &Knowns<R>, _: &mut Outputs<R>) {}
}

/// `Block` integrated by the implicit solver: the same events, located on its dense output.
pub struct ImplicitBlock(Block);

impl Model for ImplicitBlock {
    fn info() -> ModelInfo {
        ModelInfo { solver: Solver::ImplicitRungeKutta, ..Block::info() }
    }
    fn declare(d: &mut Declarations) -> Self {
        ImplicitBlock(Block::declare(d))
    }
    fn event_indicators(&self, k: &Knowns, z: &mut crate::values::EventIndicators) {
        self.0.event_indicators(k, z)
    }
    fn update_modes(&self, k: &Knowns, next: &mut crate::values::ModeUpdate) {
        self.0.update_modes(k, next)
    }
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        self.0.derivatives(k, der)
    }
    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        self.0.outputs(k, out)
    }
}

/// A model with mistakes a user can make: `forgotten` is declared but never written, and
/// `level` 2 leaves `y` unwritten too.
pub struct Careless {
    level: crate::variables::IntegerParameter,
    x: State,
    y: Output,
    forgotten: Output,
}

impl Model for Careless {
    fn info() -> ModelInfo {
        ModelInfo { name: "Careless", ..Decay::info() }
    }
    fn declare(d: &mut Declarations) -> Self {
        Careless {
            level: d.integer_parameter("level", 1).range(1, 2).describe("1 writes y, 2 forgets it"),
            x: d.state("x", 1.0, "1").describe("state"),
            y: d.output("y", "1").describe("the state"),
            forgotten: d.output("forgotten", "1").describe("never computed"),
        }
    }
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        der[self.x] = -k[self.x];
    }
    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        if k[self.level] == 1 {
            out[self.y] = k[self.x];
        }
        let _ = self.forgotten;
    }
}

/// An output that nothing moves (a parameter copied out), beside outputs that time or a
/// state move: only the first is a problem.
pub struct Frozen {
    gain: Parameter,
    set_point: Parameter,
    x: State,
    stuck: Output,
    clock: Output,
    echo: Output,
    y: Output,
}

impl Model for Frozen {
    fn info() -> ModelInfo {
        ModelInfo { name: "Frozen", ..Decay::info() }
    }
    fn declare(d: &mut Declarations) -> Self {
        Frozen {
            gain: d.parameter("gain", 2.0, "1").describe("a gain"),
            set_point: d.parameter("set_point", 3.0, "1").tunable().describe("a set point the master may change while stepping"),
            x: d.state("x", 1.0, "1").describe("state"),
            stuck: d.output("stuck", "1").describe("twice the gain, whatever happens"),
            clock: d.output("clock", "s").describe("the time"),
            echo: d.output("echo", "1").describe("the set point"),
            y: d.output("y", "1").describe("the state"),
        }
    }
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        der[self.x] = -k[self.x];
    }
    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        out[self.stuck] = k[self.gain] * 2.0;
        out[self.clock] = R::from(k.time());
        out[self.echo] = k[self.set_point];
        out[self.y] = k[self.x];
    }
}

/// A unit the runtime does not know, and none at all: problems, not a panic while the
/// description is written.
pub struct Furlong {
    x: State,
    y: Output,
}

impl Model for Furlong {
    fn info() -> ModelInfo {
        ModelInfo { name: "Furlong", ..Decay::info() }
    }
    fn declare(d: &mut Declarations) -> Self {
        d.parameter("length", 1.0, "furlong").describe("an old unit");
        d.parameter("count", 1.0, "").describe("no unit");
        Furlong { x: d.state("x", 1.0, "m").describe("state"), y: d.output("y", "m").describe("the state") }
    }
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        der[self.x] = -k[self.x];
    }
    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        out[self.y] = k[self.x];
    }
}

/// A model whose equations panic when its input is negative.
pub struct Panicky {
    u: Input,
    x: State,
}

impl Model for Panicky {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "Panicky",
            description: "panics on a negative input",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 1.0, step_size: 0.1 },
            solver: Solver::ExplicitRungeKutta,
            documentation: "",
        }
    }
    fn declare(d: &mut Declarations) -> Self {
        Panicky { u: d.input("u", 1.0, "1").describe("input"), x: d.state("x", 0.0, "1").describe("state") }
    }
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        assert!(k[self.u] >= 0.0, "negative input");
        der[self.x] = k[self.u];
    }
    fn outputs<R: Real>(&self, _: &Knowns<R>, _: &mut Outputs<R>) {}
}


/// dx/dt = -x; y = gain x, with the gain a structural choice among named items (an FMI
/// Enumeration).
pub struct Chooser {
    gain: crate::variables::IntegerParameter,
    x: State,
    y: Output,
}

impl Model for Chooser {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "Chooser",
            description: "a structural choice with named items",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 1.0, step_size: 0.1 },
            solver: Solver::ExplicitRungeKutta,
            documentation: "",
        }
    }
    fn declare(d: &mut Declarations) -> Self {
        Chooser {
            gain: d.integer_parameter("gain", 2).choices(1, &[("single", "y = x"), ("double", "y = 2 x")]).describe("gain of the output"),
            x: d.state("x", 1.0, "1").describe("state"),
            y: d.output("y", "1").describe("gain times the state"),
        }
    }
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        der[self.x] = -k[self.x];
    }
    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        out[self.y] = k[self.x] * (k[self.gain] as f64);
    }
}

/// Three inertias in a row with structured names (`w[1]` .. `w[3]`, `theta[1]`, `theta[2]`, the
/// torsional chain in small), whose declarations and evaluations of the derivatives are counted
/// (`ARRAY_DECLARED`, `ARRAY_EVALUATED`): what instantiation costs shows in the counts.
pub struct Array {
    w: Vec<State>,
    theta: Vec<State>,
    first: Output,
}

/// How many times `Array::declare` ran.
pub static ARRAY_DECLARED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
/// How many times `Array::derivatives` ran.
pub static ARRAY_EVALUATED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

impl Model for Array {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "Array",
            description: "arrays with structured names",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 1.0, step_size: 0.1 },
            solver: Solver::ExplicitRungeKutta,
            documentation: "",
        }
    }
    fn declare(d: &mut Declarations) -> Self {
        ARRAY_DECLARED.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        Array {
            w: (1..=3).map(|i| d.state(&format!("w[{i}]"), 0.0, "rad/s").describe("speed of an inertia")).collect(),
            theta: (1..3).map(|i| d.state(&format!("theta[{i}]"), 0.0, "rad").describe("twist of a shaft")).collect(),
            first: d.output("w_first", "rad/s").describe("speed of the first inertia"),
        }
    }
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        ARRAY_EVALUATED.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        let mut incoming = R::from(1.0);
        for i in 0..3 {
            let outgoing = if i < 2 {
                der[self.theta[i]] = k[self.w[i]] - k[self.w[i + 1]];
                k[self.theta[i]]
            } else {
                k[self.w[i]]
            };
            der[self.w[i]] = incoming - outgoing;
            incoming = outgoing;
        }
    }
    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        out[self.first] = k[self.w[0]];
    }
}

/// `Decay` with a tolerance floor that depends on a parameter: 1e-10 while `ringing` is on
/// (the default), none when it is off.
pub struct FlooredDecay {
    decay: Decay,
    ringing: crate::variables::BooleanParameter,
}

impl Model for FlooredDecay {
    fn info() -> ModelInfo {
        ModelInfo { name: "FlooredDecay", ..Decay::info() }
    }
    fn declare(d: &mut Declarations) -> Self {
        FlooredDecay { decay: Decay::declare(d), ringing: d.boolean_parameter("ringing", true).describe("whether the floor applies") }
    }
    fn tolerance_floor(&self, k: &Knowns) -> Option<f64> {
        k[self.ringing].then_some(1e-10)
    }
    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        self.decay.derivatives(k, der)
    }
    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        self.decay.outputs(k, out)
    }
}
