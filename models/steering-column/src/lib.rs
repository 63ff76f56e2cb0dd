//! SteeringColumn: the driver, the steering wheel and the torque sensor's torsion bar of the
//! electric power steering (chapter section 3.4.2, Figure 3.18) as a subsystem FMU
//! (docs/steering-system-spec.md). The lower column's angle and speed in, the torsion bar's
//! torque out: T_bar = K_torsion_bar (theta_sw - column_angle), the torque the sensor measures.
//! Coupling expected: SteeringRack.column_angle/column_speed -> `column_angle`/`column_speed`,
//! `torsion_bar_torque` -> SteeringRack.torsion_bar_torque and AssistMotor.measured_torque.
//!
//! Why the column's angle and not a twist state: as DriveShaft's, a twist integrating a held
//! speed input would accumulate the hold's error; the rack side integrates its own angle.

use fmu_runtime::prelude::*;
use steering::{subsystem_info, Driver, Sensor, PORT};

pub struct SteeringColumn {
    driver: Driver,
    sensor: Sensor,
    column_angle: Input,
    column_speed: Input,
    port: Element,
    torsion_bar_torque: Output,
    torsion_bar_twist: Output,
    driver_torque: Output,
    steering_wheel_angle: Output,
}

const DOCUMENTATION: &str = r#"
<p>The upper part of the Twingo's column-type electric power steering (chapter 3, section 3.4.2, Figures 3.17-3.19) as a
co-simulation subsystem: the driver (an imposed steering-wheel angle through the arm's stiffness and damping, or an
imposed torque; the parking manoeuvre and the sine steer built in), the steering wheel's inertia and the torsion bar of
the torque sensor (section 3.5.2). The equations, parameters and defaults are PowerSteering's (one declaration, the
crate <code>steering</code>): T_d = K_arm (theta_ref - theta_sw) + D_arm (theta_ref' - theta_sw'),
J_sw theta_sw'' = T_d - T_bar, T_bar = K_torsion_bar (theta_sw - column_angle).</p>
<p>Coupling: the lower column's angle and speed in (SteeringRack's states), the torsion bar's torque out, with direct
feedthrough from the angle; the rack side takes the torque into its inertia, so no algebraic loop forms. The torque
also goes to AssistMotor as the measured torque. Inputs are extrapolated by default (extrapolate_inputs) for masters
that hold them over a step. dist/SteeringSystem.ssp couples the three subsystems; with them a master reproduces
PowerSteering (docs/steering-system-spec.md gives the errors measured in external masters).</p>
"#;

impl Model for SteeringColumn {
    fn info() -> ModelInfo {
        subsystem_info(
            "SteeringColumn",
            "Electric power steering, upper column (chapter 3, section 3.4.2): driver, steering wheel and the torque sensor's torsion bar; column angle and speed in, torsion-bar torque out",
            DOCUMENTATION,
        )
    }

    /// Physical couplings (angles, speeds, torques) are smooth: extrapolate them by default.
    fn extrapolates_inputs() -> bool {
        true
    }

    /// Measured (tests/python/accuracy_table.py's rule, its default experiment against rtol 1e-13,
    /// built without the floor): the explicit solver rides the stability limit of the arm's
    /// 105 Hz mode, and the steering wheel's activity integrates the ripple: 3.7 x its range at
    /// rtol 1e-3, 0.14 x at 1e-4, 3.5e-4 at 1e-5 (35 x rtol), 9.3e-6 at 1e-6 (within 10 x).
    fn tolerance_floor(&self, _k: &Knowns) -> Option<f64> {
        Some(1e-6)
    }

    fn declare(d: &mut Declarations) -> Self {
        let model = SteeringColumn {
            driver: Driver::declare(d),
            sensor: Sensor::declare(d),
            column_angle: d.input("column_angle", 0.0, "rad").describe("Lower column's angle (connect SteeringRack.column_angle)"),
            column_speed: d.input("column_speed", 0.0, "rad/s").describe("Lower column's speed (connect SteeringRack.column_speed)"),
            port: d.element("column_port", "Lower column", PORT).describe("the lower column's end, power -T_bar column_speed (the bar delivers T_bar column_speed to the column)"),
            torsion_bar_torque: d.output("torsion_bar_torque", "N.m").describe("The torsion bar's torque on the lower column, the measured torque K_torsion_bar x twist"),
            torsion_bar_twist: d.output("torsion_bar_twist", "rad").describe("Torsion bar twist, steering-wheel angle minus column_angle"),
            driver_torque: d.output("driver_torque", "N.m").describe("The driver's torque on the steering wheel"),
            steering_wheel_angle: d.output("steering_wheel_angle", "rad").describe("Steering-wheel angle"),
        };
        Sensor::neglect_stops(d);
        model
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let twist = self.driver.wheel_angle(k) - k[self.column_angle];
        let bar_torque = self.sensor.torque_n_m(k, twist);
        self.driver.derivatives(k, bar_torque, der);
        self.sensor.report(k, twist, self.driver.wheel_speed(k) - k[self.column_speed], der);
        der.power(self.port, -bar_torque * k[self.column_speed]);
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        let twist = self.driver.wheel_angle(k) - k[self.column_angle];
        out[self.torsion_bar_torque] = self.sensor.torque_n_m(k, twist);
        out[self.torsion_bar_twist] = twist;
        out[self.driver_torque] = self.driver.forces(k).driver_torque;
        out[self.steering_wheel_angle] = self.driver.wheel_angle(k);
    }
}

fmu_runtime::export_fmu!(SteeringColumn);
