//! A small model for the runtime's own unit tests: dx/dt = -a x + u, y = 2 x, w = a u.
use crate::model::{DefaultExperiment, Model, ModelInfo, Solver};
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
    fn derivatives(&self, k: &Knowns, der: &mut Derivatives) {
        der[self.x] = -k[self.a] * k[self.x] + k[self.u];
    }
    fn outputs(&self, k: &Knowns, out: &mut Outputs) {
        out[self.y] = 2.0 * k[self.x];
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
    fn derivatives(&self, k: &Knowns, der: &mut Derivatives) {
        der[self.x] = if k.time() >= k[self.t_on] { 1.0 } else { 0.0 };
    }
    fn outputs(&self, _: &Knowns, _: &mut Outputs) {}
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
    fn initial_states(&self, k: &Knowns, x0: &mut crate::values::InitialStates) {
        x0[self.t] = if k[self.steady] { k[self.u] + k[self.p] / k[self.g] } else { k[self.u] };
    }
    fn derivatives(&self, k: &Knowns, der: &mut Derivatives) {
        der[self.t] = k[self.p] - k[self.g] * (k[self.t] - k[self.u]);
    }
    fn outputs(&self, k: &Knowns, out: &mut Outputs) {
        out[self.y] = k[self.t];
    }
}
