//! SteeringRack: the lower part of the electric power steering (chapter section 3.4.2, Figures
//! 3.18-3.19) as a subsystem FMU (docs/steering-system-spec.md): the lower column with the worm
//! wheel and the pinion, the worm gear with the motor's rotor behind it (a lossy gear that sticks
//! at rest), the column's dry friction, the rack, the tie rods, the steering levers, the wheels
//! about their pivots and the tires of Figure 3.19. The torsion bar's torque and the motor's
//! electromagnetic torque in; the column's angle and speed (states) out.
//! Coupling expected: SteeringColumn.torsion_bar_torque -> `torsion_bar_torque`,
//! AssistMotor.motor_torque -> `motor_torque`, `column_angle`/`column_speed` ->
//! SteeringColumn.column_angle/column_speed, `column_speed` -> AssistMotor.column_speed.

use fmu_runtime::prelude::*;
use steering::{subsystem_info, Rack, PORT};

pub struct SteeringRack {
    rack: Rack,
    torsion_bar_torque: Input,
    motor_torque: Input,
    column_angle: State,
    column_port: Element,
    motor_port: Element,
    y_column_angle: Output,
    y_column_speed: Output,
    rack_position: Output,
    rack_force: Output,
    wheel_angle: Output,
    assist_torque: Output,
}

const DOCUMENTATION: &str = r#"
<p>The lower part of the Twingo's column-type electric power steering (chapter 3, section 3.4.2, Figures 3.17-3.19) as a
co-simulation subsystem: the lower column, worm wheel and pinion, the assistance motor's rotor and viscous friction behind
the worm gear (ratio N, efficiency eta_f while the motor drives, eta_b while the column drives the motor; at rest the gear
sticks), the column's dry friction, the rack, the tie rods (rigid by default, as the book's), the steering levers, the
two wheels about their pivots and the tires of Figure 3.19 with their treads' friction on the ground and the kingpin's
gravity return. With e the worm's torque factor for the power's direction,
(J_c + m_r r^2 + e N^2 J_m) w_c' = T_bar - r F - s T_friction + N e (T_motor - b N w_c). The equations, parameters and
defaults are PowerSteering's (one declaration, the crate <code>steering</code>).</p>
<p>Coupling: the torsion bar's torque (SteeringColumn) and the motor's electromagnetic torque (AssistMotor) in; the
lower column's angle and speed out, both states (no direct feedthrough). Inputs are extrapolated by default
(extrapolate_inputs) for masters that hold them over a step.</p>
"#;

impl Model for SteeringRack {
    fn info() -> ModelInfo {
        subsystem_info(
            "SteeringRack",
            "Electric power steering, lower column to the road (chapter 3, section 3.4.2): worm gear and motor rotor, rack and pinion, tie rods, wheels and tires; torsion-bar and motor torques in, column angle and speed out",
            DOCUMENTATION,
        )
    }

    /// Physical couplings (torques) are smooth: extrapolate them by default.
    fn extrapolates_inputs() -> bool {
        true
    }

    fn declare(d: &mut Declarations) -> Self {
        let model = SteeringRack {
            rack: Rack::declare(d),
            torsion_bar_torque: d.input("torsion_bar_torque", 0.0, "N.m").describe("The torsion bar's torque on the lower column (connect SteeringColumn.torsion_bar_torque)"),
            motor_torque: d.input("motor_torque", 0.0, "N.m").describe("The assistance motor's electromagnetic torque on its shaft, before the worm (connect AssistMotor.motor_torque)"),
            column_angle: d.state("theta_column", 0.0, "rad").nominal(1.0).describe("Lower column's angle"),
            column_port: d.element("column_port", "Torsion bar", PORT).describe("the torsion bar's lower end, power T_bar w_column"),
            motor_port: d.element("motor_port", "Motor", PORT).describe("the motor's electromagnetic torque on the rotor, power T_motor N w_column"),
            y_column_angle: d.output("column_angle", "rad").describe("Lower column's angle (connect to SteeringColumn.column_angle)"),
            y_column_speed: d.output("column_speed", "rad/s").describe("Lower column's speed (connect to SteeringColumn.column_speed and AssistMotor.column_speed)"),
            rack_position: d.output("rack_position", "m").describe("Rack position, r_pinion x column angle"),
            rack_force: d.output("rack_force", "N").describe("Force the rack pushes the tie rods with (both rods; the tie rods' tension)"),
            wheel_angle: d.output("wheel_angle", "rad").describe("The wheels' steering angle"),
            assist_torque: d.output("assist_torque", "N.m").describe("Torque of the worm wheel on the column"),
        };
        Rack::declare_transformers_and_neglected(d);
        model
    }

    fn check(&self, k: &Knowns) -> Result<(), String> {
        self.rack.worm.check(k)
    }

    fn event_indicators(&self, k: &Knowns, z: &mut EventIndicators) {
        self.rack.event_indicators(k, k[self.column_angle], k[self.torsion_bar_torque], k[self.motor_torque], z);
    }

    fn update_modes(&self, k: &Knowns, next: &mut ModeUpdate) {
        self.rack.update_modes(k, k[self.column_angle], k[self.torsion_bar_torque], k[self.motor_torque], next);
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let (bar_torque, motor_torque, w_column) = (k[self.torsion_bar_torque], k[self.motor_torque], self.rack.column_speed(k));
        der[self.column_angle] = w_column;
        self.rack.derivatives(k, k[self.column_angle], bar_torque, motor_torque, der);
        der.power(self.column_port, bar_torque * w_column);
        der.power(self.motor_port, motor_torque * self.rack.worm.ratio(k) * w_column);
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        let column_angle = k[self.column_angle];
        let op = self.rack.operating(k, column_angle, k[self.torsion_bar_torque], k[self.motor_torque]);
        out[self.y_column_angle] = column_angle;
        out[self.y_column_speed] = self.rack.column_speed(k);
        out[self.rack_position] = self.rack.rack_position(k, column_angle);
        out[self.rack_force] = op.rack_force;
        out[self.wheel_angle] = self.rack.wheel_angle(k, column_angle);
        out[self.assist_torque] = op.assist_torque;
    }
}

fmu_runtime::export_fmu!(SteeringRack);
