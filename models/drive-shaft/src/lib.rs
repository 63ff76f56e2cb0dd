//! DriveShaft: the motor-fan's driveshaft as an FMU of its own (docs/motor-fan-system-spec.md).
//! Both speeds in, torque out: d(theta)/dt = speed_a - speed_b, T = K theta + D (speed_a - speed_b).
//! Coupling expected: InductionMotor.speed -> `speed_a`, Fan.speed_high -> `speed_b`,
//! `torque` -> InductionMotor.load_torque and Fan.shaft_torque.

use components::activity::activity_rate;
use drive_train::ShaftParameters;
use fmu_runtime::prelude::*;

pub struct DriveShaft {
    shaft: ShaftParameters,
    speed_a: Input,
    speed_b: Input,
    twist: State,
    activity: State,
    y_torque: Output,
    y_twist: Output,
    y_activity: Output,
}

const DOCUMENTATION: &str = r#"
<p>The driveshaft of the cooling-tower fan (chapter 3, Figure 3.4) as a subsystem: a torsion spring with internal
damping between the motor (speed_a) and the reducer's high-speed shaft (speed_b):
d(theta)/dt = speed_a - speed_b, torque = K_shaft theta + D_shaft (speed_a - speed_b). K_shaft = 906.85 N m/rad
gives the chapter's 1.4 Hz resonance against the fan inertia referred to the high-speed axis (eq. 3.8).</p>
<p>Coupling: speeds in, torque out. The damping term passes the input speeds straight to the torque (direct
feedthrough); the inertias it connects take torque in and give speeds that are states, so no algebraic loop forms.
Input derivatives and first output derivatives are supported for extrapolating masters.</p>
"#;

impl Model for DriveShaft {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "DriveShaft",
            description: "Driveshaft torsion spring with damping, speeds in / torque out: the shaft of the cooling-tower fan (chapter 3, Figure 3.4) as a co-simulation subsystem",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 5.0, step_size: 1e-3 },
            solver: Solver::ExplicitRungeKutta,
            documentation: DOCUMENTATION,
        }
    }

    fn declare(d: &mut Declarations) -> Self {
        DriveShaft {
            shaft: ShaftParameters::declare(d),
            speed_a: d.input("speed_a", 0.0, "rad/s").describe("Motor-side speed (connect InductionMotor.speed)"),
            speed_b: d.input("speed_b", 0.0, "rad/s").describe("Reducer-side speed on the high-speed axis (connect Fan.speed_high)"),
            twist: d.state("theta", 0.0, "rad").describe("Twist angle of the shaft"),
            activity: d.state("A_stiffness", 0.0, "J").nominal(1e-3).describe("Activity of the shaft stiffness (eq. 3.3)"),
            y_torque: d.output("torque", "N.m").describe("Transmitted torque, K theta + D (speed_a - speed_b)"),
            y_twist: d.output("twist", "rad").describe("Twist angle"),
            y_activity: d.output("activity_stiffness", "J").describe("Activity of the shaft stiffness, integral of |K theta dtheta/dt| (eq. 3.3)"),
        }
    }

    fn derivatives(&self, k: &Knowns, der: &mut Derivatives) {
        let rate = k[self.speed_a] - k[self.speed_b];
        der[self.twist] = rate;
        der[self.activity] = activity_rate(self.shaft.spring(k).spring_power_w(k[self.twist], rate));
    }

    fn outputs(&self, k: &Knowns, out: &mut Outputs) {
        out[self.y_torque] = self.shaft.spring(k).torque_n_m(k[self.twist], k[self.speed_a] - k[self.speed_b]);
        out[self.y_twist] = k[self.twist];
        out[self.y_activity] = k[self.activity];
    }
}

fmu_runtime::export_fmu!(DriveShaft);
