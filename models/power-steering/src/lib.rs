//! PowerSteering: the column-type electric power steering of chapter section 3.4.2 (the Renault
//! Twingo's, Figures 3.17-3.19, Table 3.6) as an FMU.
//!
//! Chain, from the driver to the road: the driver's hands (an imposed steering-wheel angle
//! through the arm's stiffness, or an imposed torque), the steering wheel's inertia, the torsion
//! bar of the torque sensor (its twist is the measured torque, section 3.5.2), the lower column
//! with the worm wheel and the pinion, the assistance DC motor (eq. 3.9 with R, L, rotor inertia
//! and friction) driving the worm, the rack (a rotation-translation transformer), the tie rods
//! (stiffness), the steering levers and the wheels about their pivots with the tire of
//! Figure 3.19 (rim inertia, the tire's torsional stiffness and damping, the tread's inertia and
//! its friction on the ground, the kingpin's gravity return). The assistance law turns the
//! measured torque into a current command (gain, saturation) that a PI current loop follows
//! within the battery voltage.
//!
//! Defaults: the mechanical part is the book authors' own steering model (Chap6_Steering.mo of
//! marcbudinger/MultiphysicsModelingTechSys: steering wheel, pinion ratio, lever, tire), the
//! torsion bar the book's torque sensor (Chap3_TorqueSensor.mo); the assistance (motor, worm,
//! controller) has no book file and its values are argued in `docs/power-steering-spec.md`.
//!
//! The parts (driver and steering wheel, torsion bar, worm, assistance, rack side) are declared
//! once in the crate `steering`, with their equations; this crate couples them rigidly where the
//! subsystem FMUs SteeringColumn, AssistMotor and SteeringRack couple them through a master
//! (docs/steering-system-spec.md). Its states are the springs' deflections: the column's angle is
//! the steering wheel's less the torsion bar's twist.
//!
//! Both front wheels move alike: the book's lever is linear (Bielette_init) and the two wheels
//! have the same parameters, so one equivalent wheel carries twice each per-wheel value (exact,
//! not an approximation, as long as both tires stick or slip together, which identical tires
//! under identical loads do).

mod documentation;

use fmu_runtime::prelude::*;
use steering::{Assist, Driver, Rack, Sensor};

pub struct PowerSteering {
    driver: Driver,
    sensor: Sensor,
    assist: Assist,
    rack: Rack,
    bar_twist: State,
    driver_torque: Output,
    torsion_bar_torque: Output,
    steering_wheel_angle: Output,
    rack_position: Output,
    rack_force: Output,
    wheel_angle: Output,
    motor_current: Output,
    current_command: Output,
    motor_torque: Output,
    motor_voltage: Output,
    assist_torque: Output,
}

impl PowerSteering {
    /// The lower column's angle, rad: the steering wheel's less the torsion bar's twist (the
    /// states are the springs' deflections, each under error control at its own scale).
    fn column_angle<R: Real>(&self, k: &Knowns<R>) -> R {
        self.driver.wheel_angle(k) - k[self.bar_twist]
    }

    /// The torsion bar's torque and the motor's electromagnetic torque, the couplings between the
    /// three parts.
    fn couplings<R: Real>(&self, k: &Knowns<R>) -> (R, R) {
        let bar_torque = self.sensor.torque_n_m(k, k[self.bar_twist]);
        let w_column = self.rack.column_speed(k);
        (bar_torque, self.assist.operate(k, &self.rack.worm, bar_torque, w_column).motor_torque)
    }
}

impl Model for PowerSteering {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "PowerSteering",
            description: "Column-type electric power steering (Renault Twingo, chapter 3, section 3.4.2, Figures 3.17-3.19): steering wheel, torsion-bar torque sensor, assistance DC motor and worm gear, rack and pinion, tie rods, wheels and tires; mechanical defaults from the book's steering file",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 16.0, step_size: 0.01 },
            solver: Solver::ExplicitRungeKutta,
            documentation: documentation::HTML,
        }
    }

    fn declare(d: &mut Declarations) -> Self {
        let model = PowerSteering {
            driver: Driver::declare(d),
            sensor: Sensor::declare(d),
            assist: Assist::declare(d),
            rack: Rack::declare(d),
            bar_twist: d.state("torsion_bar_twist", 0.0, "rad").nominal(0.05).describe("Torsion bar twist, steering-wheel angle minus column angle"),
            driver_torque: d.output("driver_torque", "N.m").describe("The driver's torque on the steering wheel"),
            torsion_bar_torque: d.output("torsion_bar_torque", "N.m").describe("The torque the sensor measures, K_torsion_bar x twist"),
            steering_wheel_angle: d.output("steering_wheel_angle", "rad").describe("Steering-wheel angle"),
            rack_position: d.output("rack_position", "m").describe("Rack position, r_pinion x column angle"),
            rack_force: d.output("rack_force", "N").describe("Force the rack pushes the tie rods with (both rods; the tie rods' tension)"),
            wheel_angle: d.output("wheel_angle", "rad").describe("The wheels' steering angle"),
            motor_current: d.output("motor_current", "A").describe("Assistance motor current"),
            current_command: d.output("current_command", "A").describe("The assistance law's current command"),
            motor_torque: d.output("motor_torque", "N.m").describe("Electromagnetic torque k i"),
            motor_voltage: d.output("motor_voltage", "V").describe("The current loop's voltage on the motor"),
            assist_torque: d.output("assist_torque", "N.m").describe("Torque of the worm wheel on the column"),
        };
        Assist::declare_transformer(d);
        Rack::declare_transformers_and_neglected(d);
        Sensor::neglect_stops(d);
        model
    }

    /// Measured (tests/python/accuracy_table.py's rule, the parking manoeuvre against rtol 1e-13,
    /// this FMU built without its floor): the 300 Hz current loop holds the explicit solver at its
    /// stability limit, and the armature inductance's activity integrates the ripple that leaves:
    /// 2e4 x rtol of its range at 1e-3, 1.6e4 x at 1e-4, 226 x at 1e-6, 10 x at 1e-8. At 1e-9
    /// every output is within 1.7e-8 of its range (17 x, under 10 x 1e-8); the 16 s run takes
    /// 0.05 s in fmpy.
    fn tolerance_floor(&self, _k: &Knowns) -> Option<f64> {
        Some(1e-9)
    }

    fn check(&self, k: &Knowns) -> Result<(), String> {
        self.rack.worm.check(k)
    }

    fn event_indicators(&self, k: &Knowns, z: &mut EventIndicators) {
        let (bar_torque, motor_torque) = self.couplings(k);
        self.rack.event_indicators(k, self.column_angle(k), bar_torque, motor_torque, z);
        self.assist.event_indicators(k, &self.rack.worm, bar_torque, self.rack.column_speed(k), z);
    }

    fn update_modes(&self, k: &Knowns, next: &mut ModeUpdate) {
        let (bar_torque, motor_torque) = self.couplings(k);
        let column_angle = self.column_angle(k);
        // The assistance's tie-breaking rates, from the modes before the update (as the rack's).
        let column_acceleration = self.rack.column_acceleration(k, column_angle, bar_torque, motor_torque);
        let torque_rate = self.sensor.torque_n_m(k, self.driver.wheel_speed(k) - self.rack.column_speed(k));
        self.rack.update_modes(k, column_angle, bar_torque, motor_torque, next);
        self.assist.update_modes(k, &self.rack.worm, bar_torque, self.rack.column_speed(k), torque_rate, column_acceleration, next);
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let (bar_torque, motor_torque) = self.couplings(k);
        let (w_wheel, w_column) = (self.driver.wheel_speed(k), self.rack.column_speed(k));
        self.driver.derivatives(k, bar_torque, der);
        der[self.bar_twist] = w_wheel - w_column;
        self.sensor.report(k, k[self.bar_twist], w_wheel - w_column, der);
        self.assist.derivatives(k, &self.rack.worm, bar_torque, w_column, der);
        self.rack.derivatives(k, self.column_angle(k), bar_torque, motor_torque, der);
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        let (bar_torque, _) = self.couplings(k);
        let w_column = self.rack.column_speed(k);
        let assist = self.assist.operate(k, &self.rack.worm, bar_torque, w_column);
        let column_angle = self.column_angle(k);
        let rack = self.rack.operating(k, column_angle, bar_torque, assist.motor_torque);
        out[self.driver_torque] = self.driver.forces(k).driver_torque;
        out[self.torsion_bar_torque] = bar_torque;
        out[self.steering_wheel_angle] = self.driver.wheel_angle(k);
        out[self.rack_position] = self.rack.rack_position(k, column_angle);
        out[self.rack_force] = rack.rack_force;
        out[self.wheel_angle] = self.rack.wheel_angle(k, column_angle);
        out[self.motor_current] = self.assist.current(k);
        out[self.current_command] = assist.current_command;
        out[self.motor_torque] = assist.motor_torque;
        out[self.motor_voltage] = assist.voltage;
        out[self.assist_torque] = rack.assist_torque;
    }
}

fmu_runtime::export_fmu!(PowerSteering);
