//! TorsionalChain: N rigid inertias joined by N - 1 elastic, damped shafts, driven by a torque
//! on the first inertia: the benchmark of a model that grows (issue "Models of any size").
//!
//! A drive train cut into N lumps is the chapter's own move (section 3.2: a shaft becomes an
//! inertia-spring-inertia chain when its stiffness matters, eq. 3.2 and Figure 3.5 level c),
//! repeated N - 1 times:
//!
//! ```text
//!   J dw_1/dt = T_drive(t) - T_1
//!   J dw_i/dt = T_{i-1} - T_i                 (1 < i < N)
//!   J dw_N/dt = T_{N-1} - T_load,  T_load = c_load w_N
//!   dtheta_i/dt = w_i - w_{i+1},   T_i = K theta_i + D (w_i - w_{i+1})
//! ```
//!
//! 2N - 1 states, `w[i]` and `theta[i]` (FMI's structured names, 1-based), each derivative
//! depending on at most 5 of them: a banded Jacobian. The drive
//! torque steps from 0 to `drive_torque` at `step_time`, a declared time event. Its defaults
//! are a non-stiff chain (J = 1 kg m2, K = 1e4 N m/rad, D = 1 N m s/rad: the fastest mode near
//! 2 sqrt(K/J) = 200 rad/s, lightly damped); the stiff chain of the benchmark is the same model
//! with small inertias and stiff, strongly damped shafts (set by the master).
//!
//! The number of inertias is `INERTIAS` in src/size.rs: one crate builds one size.

use components::{Inertia, TorsionSpring};
use fmu_runtime::prelude::*;

mod size;
pub use size::INERTIAS;

pub struct TorsionalChain {
    inertia: Parameter,
    stiffness: Parameter,
    damping: Parameter,
    load_coefficient: Parameter,
    drive_torque: Parameter,
    step_time: Parameter,
    speeds: Vec<State>,
    twists: Vec<State>,
    w_first: Output,
    w_last: Output,
}

impl TorsionalChain {
    fn drive_torque_n_m<R: Real>(&self, k: &Knowns<R>) -> R {
        if k.time() >= k[self.step_time].value() {
            k[self.drive_torque]
        } else {
            R::from(0.0)
        }
    }
}

impl Model for TorsionalChain {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "TorsionalChain",
            description: "A chain of N inertias and N - 1 elastic damped shafts under a torque step: the size benchmark",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 1.0, step_size: 1e-3 },
            solver: Solver::ExplicitRungeKutta,
            documentation: "<p>J dw_i/dt = T_{i-1} - T_i; dtheta_i/dt = w_i - w_{i+1}; T_i = K theta_i + D (w_i - w_{i+1}).</p>",
        }
    }

    fn declare(d: &mut Declarations) -> Self {
        let inertia = d.parameter("J", 1.0, "kg.m2").positive().describe("Inertia of each lump");
        let stiffness = d.parameter("K", 1e4, "N.m/rad").min(0.0).describe("Stiffness of each shaft");
        let damping = d.parameter("D", 1.0, "N.m.s/rad").min(0.0).describe("Internal damping of each shaft");
        let load_coefficient = d.parameter("c_load", 1.0, "N.m.s/rad").min(0.0).describe("Viscous load on the last inertia");
        let drive_torque = d.parameter("drive_torque", 100.0, "N.m").describe("Drive torque on the first inertia after step_time");
        let step_time = d.parameter("step_time", 0.1, "s").describe("Time of the drive torque's step (a time event)");
        // Arrays declared in a loop, with FMI's structured names (1-based): w[1] .. w[N], theta[1] .. theta[N - 1].
        let speeds = (1..=INERTIAS).map(|i| d.state(&format!("w[{i}]"), 0.0, "rad/s").describe("Speed of an inertia")).collect();
        let twists = (1..INERTIAS).map(|i| d.state(&format!("theta[{i}]"), 0.0, "rad").describe("Twist of a shaft")).collect();
        TorsionalChain {
            inertia,
            stiffness,
            damping,
            load_coefficient,
            drive_torque,
            step_time,
            speeds,
            twists,
            w_first: d.output("w_first", "rad/s").describe("Speed of the first inertia"),
            w_last: d.output("w_last", "rad/s").describe("Speed of the last inertia"),
        }
    }

    fn next_time_event(&self, k: &Knowns, after: f64) -> Option<f64> {
        (k[self.step_time] > after).then(|| k[self.step_time])
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let body = Inertia { inertia_kg_m2: k[self.inertia] };
        let shaft = TorsionSpring { stiffness_n_m_per_rad: k[self.stiffness], damping_n_m_s_per_rad: k[self.damping] };
        let n = self.speeds.len();
        // Torque the previous shaft passes on to inertia i (the drive torque for the first).
        let mut incoming = self.drive_torque_n_m(k);
        for i in 0..n {
            let w = k[self.speeds[i]];
            let outgoing = if i + 1 < n {
                let rate = w - k[self.speeds[i + 1]];
                der[self.twists[i]] = rate;
                shaft.torque_n_m(k[self.twists[i]], rate)
            } else {
                k[self.load_coefficient] * w
            };
            der[self.speeds[i]] = body.acceleration_rad_per_s2(incoming - outgoing);
            incoming = outgoing;
        }
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        out[self.w_first] = k[self.speeds[0]];
        out[self.w_last] = k[self.speeds[self.speeds.len() - 1]];
    }
}

fmu_runtime::export_fmu!(TorsionalChain);
