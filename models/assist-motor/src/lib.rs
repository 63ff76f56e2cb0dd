//! AssistMotor: the assistance of the electric power steering (chapter section 3.4.2, Figure
//! 3.18) as a subsystem FMU (docs/steering-system-spec.md): the assistance law (gain, active
//! damping, saturation), the PI current loop within the battery's voltage and the motor's
//! armature (eq. 3.9: R, L, the back-emf k N w_column). The measured torque and the column's
//! speed in, the electromagnetic torque k i out (a state: no direct feedthrough).
//! Coupling expected: SteeringColumn.torsion_bar_torque -> `measured_torque`,
//! SteeringRack.column_speed -> `column_speed`, `motor_torque` -> SteeringRack.motor_torque.
//! The rotor's inertia and friction turn with the column behind the worm: SteeringRack has them.

use fmu_runtime::prelude::*;
use steering::{subsystem_info, Assist, Worm, PORT};

pub struct AssistMotor {
    worm: Worm,
    assist: Assist,
    measured_torque: Input,
    column_speed: Input,
    port: Element,
    motor_torque: Output,
    motor_current: Output,
    current_command: Output,
    motor_voltage: Output,
}

const DOCUMENTATION: &str = r#"
<p>The assistance of the Twingo's column-type electric power steering (chapter 3, section 3.4.2, Figures 3.17-3.19) as a
co-simulation subsystem: the controller's law i_ref = clamp((assist_gain T_measured - assist_damping w_column) / (N eta_f k),
+/- I_max), the PI current loop u = clamp(Kp e + Ki integral, +/- U_battery) with anti-windup by tracking, and the
motor's armature L di/dt = u - R i - k N w_column (eq. 3.9). The equations, parameters and defaults are PowerSteering's
(one declaration, the crate <code>steering</code>).</p>
<p>Coupling: the measured torque (SteeringColumn.torsion_bar_torque) and the lower column's speed (SteeringRack.column_speed)
in, the electromagnetic torque k i on the motor's shaft out (SteeringRack.motor_torque), which follows the current, a
state: no algebraic loop. The rotor's inertia and viscous friction move with the column through the worm and belong to
SteeringRack. Inputs are extrapolated by default (extrapolate_inputs) for masters that hold them over a step.</p>
"#;

impl Model for AssistMotor {
    fn info() -> ModelInfo {
        subsystem_info(
            "AssistMotor",
            "Electric power steering, assistance (chapter 3, section 3.4.2): assistance law, PI current loop and the DC motor's armature; measured torque and column speed in, motor torque out",
            DOCUMENTATION,
        )
    }

    /// Physical couplings (speeds, torques) are smooth: extrapolate them by default.
    fn extrapolates_inputs() -> bool {
        true
    }

    fn declare(d: &mut Declarations) -> Self {
        let model = AssistMotor {
            worm: Worm::declare_motor_side(d),
            assist: Assist::declare(d),
            measured_torque: d.input("measured_torque", 0.0, "N.m").describe("The torque sensor's torque (connect SteeringColumn.torsion_bar_torque)"),
            column_speed: d.input("column_speed", 0.0, "rad/s").describe("Lower column's speed; the motor turns worm_ratio times faster (connect SteeringRack.column_speed)"),
            port: d.element("worm_port", "Worm gear", PORT).describe("the motor's shaft at the worm, power -k i N column_speed (the motor delivers k i N column_speed)"),
            motor_torque: d.output("motor_torque", "N.m").describe("Electromagnetic torque k i on the motor's shaft"),
            motor_current: d.output("motor_current", "A").describe("Assistance motor current"),
            current_command: d.output("current_command", "A").describe("The assistance law's current command"),
            motor_voltage: d.output("motor_voltage", "V").describe("The current loop's voltage on the motor"),
        };
        Assist::declare_transformer(d);
        model
    }

    /// The saturations' modes: the inputs' rates are not known here, so at an exact tie with a
    /// limit the mode holds (PowerSteering breaks such ties with the column's rates).
    fn update_modes(&self, k: &Knowns, next: &mut ModeUpdate) {
        self.assist.update_modes(k, &self.worm, k[self.measured_torque], k[self.column_speed], 0.0, 0.0, next);
    }

    fn event_indicators(&self, k: &Knowns, z: &mut EventIndicators) {
        self.assist.event_indicators(k, &self.worm, k[self.measured_torque], k[self.column_speed], z);
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let (torque, w_column) = (k[self.measured_torque], k[self.column_speed]);
        self.assist.derivatives(k, &self.worm, torque, w_column, der);
        let motor_torque = self.assist.motor(k).torque_n_m(self.assist.current(k));
        der.power(self.port, -motor_torque * self.worm.ratio(k) * w_column);
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        let op = self.assist.operate(k, &self.worm, k[self.measured_torque], k[self.column_speed]);
        out[self.motor_torque] = op.motor_torque;
        out[self.motor_current] = self.assist.current(k);
        out[self.current_command] = op.current_command;
        out[self.motor_voltage] = op.voltage;
    }
}

fmu_runtime::export_fmu!(AssistMotor);
