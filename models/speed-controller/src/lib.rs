//! SpeedController: the variable-speed start's set point and PI controller as an FMU of its own
//! (docs/motor-fan-system-spec.md). Measured speed in, torque command out.
//! Coupling expected: InductionMotor.speed -> `measured_speed`, `torque_command` ->
//! InductionMotor.torque_command (with InductionMotor.drive = 2).

use drive_train::{ControllerParameters, SetPoint, TorqueLimitEvent, subsystem_info};
use fmu_runtime::prelude::*;

pub struct SpeedController {
    control: ControllerParameters,
    measured_speed: Input,
    integral: State,
    torque_limit: TorqueLimitEvent,
    filtered: State,
    filtered_rate: State,
    y_torque_command: Output,
    y_reference: Output,
}

const DOCUMENTATION: &str = r#"
<p>The speed control of the variable-speed start (chapter 3, section 3.3.2, Figures 3.7 and 3.13) as a subsystem:
a set point ramping from 0 to speed_setpoint in ramp_time, optionally through a second-order filter, and a PI
controller with a torque limit and anti-windup by back-calculation: torque_command = clamp(Kp e + Ki I), e = w_ref - measured_speed,
dI/dt = e + (torque_command - (Kp e + Ki I)) / (Ki T_tracking).</p>
<p>Coupling: speed in, torque out (direct feedthrough through Kp). The motor it drives takes torque in and gives its
speed as a state, so no algebraic loop forms. The ramp's corners are announced as time events.</p>
<p>Defaults: the book's (Chap3_CoolingTowerFan.mo, Transient_SpeedControler: Kp_speed 10000, Ki_speed 100000, no limit,
300 rad/s in 10 s through the 2*3.14*0.5 rad/s filter). Those gains close a 5800 rad/s loop on the motor's 1.72 kg m<sup>2</sup>,
which a master sampling the speed every 1 ms cannot hold (5.8 rad per step): coupled at such steps, use gains like
Kp_speed 200, Ki_speed 2000 (the project's first set, what the coupled tests use) or a communication step far below 1 ms. The book's torque actuator lag
is MotorFan's (<code>actuator_angular_frequency</code>), not this controller's.</p>
"#;

impl SpeedController {
    fn set_point<R: Real>(&self, k: &Knowns<R>) -> SetPoint<R> {
        SetPoint::at(&self.control, k, k[self.filtered], k[self.filtered_rate])
    }
}

impl Model for SpeedController {
    fn info() -> ModelInfo {
        subsystem_info(
            "SpeedController",
            "Speed set-point ramp, second-order filter and PI speed controller with torque limit: the variable-speed start of the cooling-tower fan (chapter 3, Figure 3.7) as a co-simulation subsystem",
            15.0,
            DOCUMENTATION,
        )
    }

    /// Physical couplings (speeds, angles, torques) are smooth: extrapolate them by default, so
    /// masters that hold inputs over a step couple accurately (docs/motor-fan-system-spec.md).
    fn extrapolates_inputs() -> bool {
        true
    }

    fn declare(d: &mut Declarations) -> Self {
        SpeedController {
            control: ControllerParameters::declare(d),
            measured_speed: d.input("measured_speed", 0.0, "rad/s").describe("Measured motor speed (connect InductionMotor.speed)"),
            integral: d.state("pi_integral", 0.0, "rad").nominal(10.0).describe("Integral of the speed error"),
            torque_limit: TorqueLimitEvent::declare(d),
            filtered: d.state("reference_filtered", 0.0, "rad/s").nominal(100.0).describe("Filtered speed set point (filter on; frozen otherwise)"),
            filtered_rate: d.state("reference_filtered_rate", 0.0, "rad/s2").nominal(10.0).describe("Rate of the filtered speed set point"),
            y_torque_command: d.output("torque_command", "N.m").describe("Torque command, clamped to +/- T_limit"),
            y_reference: d.output("speed_reference", "rad/s").describe("Speed set point after the filter"),
        }
    }

    fn next_time_event(&self, k: &Knowns, after: f64) -> Option<f64> {
        self.control.ramp(k).next_kink(after)
    }

    fn event_indicators(&self, k: &Knowns, z: &mut EventIndicators) {
        let error = self.set_point(k).reference - k[self.measured_speed];
        self.torque_limit.indicator(k, &self.control.controller(k), error, k[self.integral], z);
    }

    /// Exactly at the limit, the measured speed is taken as steady (its rate is not known here).
    fn update_modes(&self, k: &Knowns, next: &mut ModeUpdate) {
        let sp = self.set_point(k);
        self.torque_limit.update(k, next, &self.control.controller(k), sp.reference - k[self.measured_speed], sp.rate, k[self.integral]);
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let sp = self.set_point(k);
        if self.control.filter(k).is_some() {
            der[self.filtered] = sp.rate;
            der[self.filtered_rate] = sp.acceleration;
        }
        der[self.integral] = self.control.controller(k).integral_rate(sp.reference - k[self.measured_speed], k[self.integral]);
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        let sp = self.set_point(k);
        out[self.y_torque_command] = self.control.controller(k).command(sp.reference - k[self.measured_speed], k[self.integral]);
        out[self.y_reference] = sp.reference;
    }
}

fmu_runtime::export_fmu!(SpeedController);
