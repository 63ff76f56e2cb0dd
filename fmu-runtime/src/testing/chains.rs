//! Two linear drive trains of any size for the runtime's own tests and examples (the implicit
//! method's Newton matrix dense, band or sparse, its accuracy through a time event, restored
//! states, allocations in steady steps): the torsional chain of the size benchmark
//! (bench/torsional-chain, there written with `components`) and a star, whose hub makes the
//! pattern one that no reordering narrows to a band. The equations are written without the
//! components crate, which depends on this one.

use crate::model::{DefaultExperiment, Model, ModelInfo, Solver};
use crate::real::Real;
use crate::values::{Derivatives, Knowns, Outputs};
use crate::variables::{Declarations, Input, Parameter, State};

/// The parameters and the input the chain and the star share.
struct Lumps {
    inertia: Parameter,
    stiffness: Parameter,
    damping: Parameter,
    load_coefficient: Parameter,
    drive_torque: Parameter,
    step_time: Parameter,
    load_torque: Input,
}

impl Lumps {
    fn declare(d: &mut Declarations, load_on: &str) -> Self {
        Lumps {
            inertia: d.parameter("J", 1.0, "kg.m2").positive().describe("inertia of each lump"),
            stiffness: d.parameter("K", 1e4, "N.m/rad").min(0.0).describe("stiffness of each shaft"),
            damping: d.parameter("D", 1.0, "N.m.s/rad").min(0.0).describe("damping of each shaft"),
            load_coefficient: d.parameter("c_load", 1.0, "N.m.s/rad").min(0.0).describe("viscous load"),
            drive_torque: d.parameter("drive_torque", 100.0, "N.m").describe("drive torque after step_time"),
            step_time: d.parameter("step_time", 0.1, "s").describe("time of the torque step"),
            load_torque: d.input("load_torque", 0.0, "N.m").describe(load_on),
        }
    }

    /// The torque step's instant, a time event.
    fn next_time_event(&self, k: &Knowns, after: f64) -> Option<f64> {
        (k[self.step_time] > after).then(|| k[self.step_time])
    }

    /// The drive torque: on at `t >= step_time` (`at_or_after`), else at `t > step_time`.
    fn drive<R: Real>(&self, k: &Knowns<R>, at_or_after: bool) -> R {
        let step_time = k[self.step_time].value();
        let on = if at_or_after { k.time() >= step_time } else { k.time() > step_time };
        if on {
            k[self.drive_torque]
        } else {
            R::from(0.0)
        }
    }
}

fn chain_info(name: &'static str, description: &'static str, implicit: bool) -> ModelInfo {
    ModelInfo {
        name,
        description,
        default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 0.3, step_size: 1e-3 },
        solver: if implicit { Solver::ImplicitRungeKutta } else { Solver::ExplicitRungeKutta },
        documentation: "",
    }
}

/// N inertias, N - 1 spring-dampers, a viscous load on the last one (2N - 1 states: the speeds
/// w_1..w_N, then the twists theta_1..theta_{N-1}), driven by a torque step at `step_time` on
/// the first; `AT_OR_AFTER`: the torque is on at `t >= step_time` (else at `t > step_time`);
/// `IMPLICIT`: the solver. An input `load_torque` on the last inertia (0 by default). Stiff with
/// J = 1e-4 kg m2, K = 1e5 N m/rad, D = 10 N m s/rad.
pub struct Chain<const N: usize, const AT_OR_AFTER: bool, const IMPLICIT: bool> {
    lumps: Lumps,
    speeds: Vec<State>,
    twists: Vec<State>,
}

impl<const N: usize, const AT_OR_AFTER: bool, const IMPLICIT: bool> Model for Chain<N, AT_OR_AFTER, IMPLICIT> {
    fn info() -> ModelInfo {
        chain_info("Chain", "a torsional chain", IMPLICIT)
    }

    fn declare(d: &mut Declarations) -> Self {
        Chain {
            lumps: Lumps::declare(d, "torque on the last inertia"),
            speeds: (1..=N).map(|i| d.state(&format!("w_{i}"), 0.0, "rad/s").describe("speed")).collect(),
            twists: (1..N).map(|i| d.state(&format!("theta_{i}"), 0.0, "rad").describe("twist")).collect(),
        }
    }

    fn next_time_event(&self, k: &Knowns, after: f64) -> Option<f64> {
        self.lumps.next_time_event(k, after)
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let p = &self.lumps;
        let (j, stiffness, damping) = (k[p.inertia], k[p.stiffness], k[p.damping]);
        let mut incoming = p.drive(k, AT_OR_AFTER);
        for i in 0..N {
            let w = k[self.speeds[i]];
            let outgoing = if i + 1 < N {
                let rate = w - k[self.speeds[i + 1]];
                der[self.twists[i]] = rate;
                stiffness * k[self.twists[i]] + damping * rate
            } else {
                k[p.load_coefficient] * w + k[p.load_torque]
            };
            der[self.speeds[i]] = (incoming - outgoing) / j;
            incoming = outgoing;
        }
    }

    fn outputs<R: Real>(&self, _: &Knowns<R>, _: &mut Outputs<R>) {}
}

/// A hub inertia joined to K spoke inertias by spring-dampers (2K + 1 states: the speeds w_0 (the
/// hub, driven by the torque step at `t >= step_time`) .. w_K, then the twists theta_1 ..
/// theta_K), each spoke with a viscous load and the input `load_torque`: the hub's row and column
/// are full, so no reordering makes the pattern a narrow band, and the implicit method
/// factorizes it by the sparse LU. The parameters and input of [`Chain`].
pub struct Star<const K: usize> {
    lumps: Lumps,
    speeds: Vec<State>,
    twists: Vec<State>,
}

impl<const K: usize> Model for Star<K> {
    fn info() -> ModelInfo {
        chain_info("Star", "a star of inertias", true)
    }

    fn declare(d: &mut Declarations) -> Self {
        Star {
            lumps: Lumps::declare(d, "torque on each spoke"),
            speeds: (0..=K).map(|i| d.state(&format!("w_{i}"), 0.0, "rad/s").describe("speed")).collect(),
            twists: (1..=K).map(|i| d.state(&format!("theta_{i}"), 0.0, "rad").describe("twist")).collect(),
        }
    }

    fn next_time_event(&self, k: &Knowns, after: f64) -> Option<f64> {
        self.lumps.next_time_event(k, after)
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let p = &self.lumps;
        let (j, stiffness, damping, load) = (k[p.inertia], k[p.stiffness], k[p.damping], k[p.load_coefficient]);
        let hub_speed = k[self.speeds[0]];
        let mut hub = p.drive(k, true);
        for i in 1..=K {
            let w = k[self.speeds[i]];
            let rate = hub_speed - w;
            let torque = stiffness * k[self.twists[i - 1]] + damping * rate;
            der[self.twists[i - 1]] = rate;
            der[self.speeds[i]] = (torque - load * w - k[p.load_torque]) / j;
            hub = hub - torque;
        }
        der[self.speeds[0]] = hub / j;
    }

    fn outputs<R: Real>(&self, _: &Knowns<R>, _: &mut Outputs<R>) {}
}
