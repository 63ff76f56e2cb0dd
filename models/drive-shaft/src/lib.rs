//! DriveShaft: the motor-fan's driveshaft as an FMU of its own (docs/motor-fan-system-spec.md).
//! Both ends' angles and speeds in, torque out: theta = angle_a - angle_b,
//! T = K theta + D (speed_a - speed_b).
//! Coupling expected: InductionMotor.angle/speed -> `angle_a`/`speed_a`, Fan.angle_high/speed_high
//! -> `angle_b`/`speed_b`, `torque` -> InductionMotor.load_torque and Fan.shaft_torque.
//!
//! Why angles and not a twist state integrating the speeds: a master holding its inputs over a
//! communication step would make such a state integrate stale speeds, an error that accumulates
//! into the twist; the inertias integrate their own angles accurately, so the twist taken from
//! them is exact at every communication point.

use components::{TorsionSpring, SHAFT_PORT};
use drive_train::{subsystem_info, ShaftParameters};
use fmu_runtime::prelude::*;

pub struct DriveShaft {
    shaft: ShaftParameters,
    angle_a: Input,
    angle_b: Input,
    speed_a: Input,
    speed_b: Input,
    stiffness: Element,
    damping: Element,
    port_a: Element,
    port_b: Element,
    y_torque: Output,
    y_twist: Output,
}

const DOCUMENTATION: &str = r#"
<p>The driveshaft of the cooling-tower fan (chapter 3, Figure 3.4) as a subsystem: a torsion spring with internal
damping between the motor (angle_a, speed_a) and the reducer's high-speed shaft (angle_b, speed_b):
theta = angle_a - angle_b, torque = K_shaft theta + D_shaft (speed_a - speed_b). K_shaft = 866 N m/rad and
D_shaft = 866/100/sqrt(886/1.7) (the book's, Chap3_CoolingTowerFan.mo, component spring) give the chapter's 1.4 Hz
(1.37 Hz) resonance against the fan inertia referred to the high-speed axis (eq. 3.8).</p>
<p>Coupling: angles and speeds in, torque out (direct feedthrough); the inertias it connects take torque in and give
angles and speeds that are states, so no algebraic loop forms. The twist comes from the two angles rather than
from integrating the speeds inside the shaft, so a master that holds inputs over a step does not accumulate a
twist error. Input derivatives and first output derivatives are supported for extrapolating masters.</p>
"#;

impl Model for DriveShaft {
    fn info() -> ModelInfo {
        subsystem_info(
            "DriveShaft",
            "Driveshaft torsion spring with damping, speeds in / torque out: the shaft of the cooling-tower fan (chapter 3, Figure 3.4) as a co-simulation subsystem",
            5.0,
            DOCUMENTATION,
        )
    }

    /// Physical couplings (speeds, angles, torques) are smooth: extrapolate them by default, so
    /// masters that hold inputs over a step couple accurately (docs/motor-fan-system-spec.md).
    fn extrapolates_inputs() -> bool {
        true
    }

    fn declare(d: &mut Declarations) -> Self {
        DriveShaft {
            shaft: ShaftParameters::declare(d),
            angle_a: d.input("angle_a", 0.0, "rad").describe("Motor-side angle (connect InductionMotor.angle)"),
            angle_b: d.input("angle_b", 0.0, "rad").describe("Reducer-side angle on the high-speed axis (connect Fan.angle_high)"),
            speed_a: d.input("speed_a", 0.0, "rad/s").describe("Motor-side speed (connect InductionMotor.speed)"),
            speed_b: d.input("speed_b", 0.0, "rad/s").describe("Reducer-side speed on the high-speed axis (connect Fan.speed_high)"),
            y_torque: d.output("torque", "N.m").describe("Transmitted torque, K theta + D (speed_a - speed_b)"),
            y_twist: d.output("twist", "rad").describe("Twist angle, angle_a - angle_b"),
            stiffness: d.element("stiffness", "Driveshaft", TorsionSpring::STIFFNESS).describe("the shaft stiffness, power K theta dtheta/dt"),
            damping: d.element("damping", "Driveshaft", TorsionSpring::DAMPING).describe("the shaft's internal damping, power D (dtheta/dt)^2"),
            port_a: d.element("port_a", "Motor side", SHAFT_PORT).describe("the motor-side end, power T speed_a delivered into the shaft"),
            port_b: d.element("port_b", "Reducer side", SHAFT_PORT).describe("the reducer-side end, power -T speed_b (the shaft delivers T speed_b to the fan)"),
        }
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let (twist, rate) = (k[self.angle_a] - k[self.angle_b], k[self.speed_a] - k[self.speed_b]);
        let spring = self.shaft.spring(k);
        let torque = spring.torque_n_m(twist, rate);
        der.power(self.stiffness, spring.spring_power_w(twist, rate));
        der.power(self.damping, spring.damper_power_w(rate));
        der.power(self.port_a, torque * k[self.speed_a]);
        der.power(self.port_b, -torque * k[self.speed_b]);
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        let twist = k[self.angle_a] - k[self.angle_b];
        out[self.y_torque] = self.shaft.spring(k).torque_n_m(twist, k[self.speed_a] - k[self.speed_b]);
        out[self.y_twist] = twist;
    }
}

fmu_runtime::export_fmu!(DriveShaft);
