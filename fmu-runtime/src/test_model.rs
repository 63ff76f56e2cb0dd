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
