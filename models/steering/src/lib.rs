//! The column-type electric power steering of chapter section 3.4.2 (the Renault Twingo's,
//! Figures 3.17-3.19), declared once: each part's FMI parameters, states, modes and elements, and
//! its equations. `PowerSteering` (the monolith) and the subsystem FMUs cut along the chain of
//! Figure 3.18 (`SteeringColumn`: the driver, the steering wheel and the torque sensor's torsion
//! bar; `AssistMotor`: the assistance law, the current loop and the motor's armature;
//! `SteeringRack`: the lower column with the worm wheel and the motor's rotor, the pinion, the
//! rack, the wheels and the tires) build from the same three parts, so a name always has the same
//! default, unit, bounds and description, and the equations exist once.
//!
//! The parts meet where Figure 3.18 has its couplings: the torsion bar's torque (the measured one)
//! acts on the lower column; the motor's electromagnetic torque k i acts on the lower column
//! through the worm; the lower column's speed drives the motor's back-emf (and the law's active
//! damping). Defaults: the book authors' Chap6_Steering.mo for the mechanics, Chap3_TorqueSensor.mo
//! for the torsion bar, the rest argued in docs/power-steering-spec.md.

use components::{
    CoulombFriction, DcMachine, GearMode, Inertia, Lever, Mass, PiController, RackAndPinion, SecondOrderFilter, TorsionBar, TorsionSpring, TranslationalSpring,
    WormGear, SHAFT_PORT,
};
use fmu_runtime::prelude::*;
use std::f64::consts::PI;

/// Two front wheels, each with its tie rod, lever and tire. Both move alike: the book's lever is
/// linear (Bielette_init) and the two wheels have the same parameters, so one equivalent wheel
/// carries twice each per-wheel value (exact as long as both tires stick or slip together, which
/// identical tires under identical loads do).
pub const WHEELS: f64 = 2.0;

/// Below this speed, at an event, the column (the worm) and the treads count as at rest, rad/s
/// (0.06 degree per second: Karnopp's stick window, D. Karnopp, "Computer simulation of
/// stick-slip friction in mechanical dynamic systems", J. Dyn. Sys. Meas. Control 107, 1985).
/// When the driver reverses, the column and the sliding treads creep to rest together (about
/// 0.1 rad/s2), their speeds' zeros tens of nanoseconds apart (48 ns at 12.2 s of the parking
/// manoeuvre): one stop, which Co-Simulation located as two events and a Model Exchange
/// master, whose root finder does not resolve 48 ns, as one. Whichever zero is located first
/// now stops both, as one event, in every master. The window must exceed the speed errors of
/// a master at its loosest tolerance (a strict master at rtol 1e-4 located the column's stop
/// 3.5 us early and the treads' 24 us after it; with a 1e-5 rad/s window it still saw two).
pub const STANDSTILL_RAD_PER_S: f64 = 1e-3;

/// The worm gear's default geometry: a 16.5 ratio, 20 degrees of lead angle, steel on a
/// lubricated plastic wheel at mu = 0.05 (docs/power-steering-spec.md).
fn default_worm() -> WormGear {
    WormGear::from_lead_and_friction_angle(16.5, 20f64.to_radians(), 0.05f64.atan()).expect("a reversible worm")
}

/// A description naming the book file's component it comes from.
fn book(what: &str, description: &str) -> String {
    format!("{description} (book file Chap6_Steering.mo, {what})")
}

/// Subsystem FMUs: 16 s (the parking manoeuvre) at 1 ms communication steps.
pub fn subsystem_info(name: &'static str, description: &'static str, documentation: &'static str) -> ModelInfo {
    ModelInfo { name, description, default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 16.0, step_size: 1e-3 }, solver: Solver::ExplicitRungeKutta, documentation }
}

// ---------------------------------------------------------------------------------------------
// The driver and the steering wheel

/// How the driver acts (`driver_input`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DriverInput {
    /// The steering-wheel angle is imposed (profile + angle_in) through the arm's stiffness.
    Angle,
    /// The driver's torque is imposed (profile + torque_in).
    Torque,
}

/// The driver's hands and the steering wheel: the profiles, the driver's filter, the arm's
/// stiffness and damping, the steering wheel's inertia; its inputs, states and elements.
pub struct Driver {
    driver_input: IntegerParameter,
    profile: IntegerParameter,
    parking_amplitude: Parameter,
    parking_frequency: Parameter,
    sine_amplitude: Parameter,
    sine_frequency: Parameter,
    torque_amplitude: Parameter,
    filter_frequency: Parameter,
    filter_damping: Parameter,
    k_arm: Parameter,
    d_arm: Parameter,
    j_wheel: Parameter,
    angle_in: Input,
    torque_in: Input,
    reference: State,
    reference_rate: State,
    arm_stretch: State,
    w_wheel: State,
    driver: Element,
    arm: Element,
    arm_damping: Element,
    steering_wheel: Element,
}

/// The driver's side at one instant.
pub struct DriverForces<R = f64> {
    pub reference_acceleration: R,
    pub driver_torque: R,
    pub driver_power: R,
    pub arm_power: R,
    pub arm_damper_power: R,
}

impl Driver {
    pub fn declare(d: &mut Declarations) -> Self {
        Driver {
            driver_input: d
                .integer_parameter("driver_input", 1)
                .choices(1, &[("angle", "the driver imposes the steering-wheel angle"), ("torque", "the driver's torque")])
                .describe("1 = the driver imposes the steering-wheel angle (profile + angle_in) through the arm's stiffness; 2 = the driver's torque torque_in"),
            profile: d
                .integer_parameter("profile", 1)
                .choices(1, &[("parking", "parking manoeuvre (the book's mission)"), ("sine_steer", "sine steer")])
                .describe("The driver's profile, a sine: 1 = parking manoeuvre (the book's mission: one turn each way at 1/16 Hz), 2 = sine steer; an angle (driver_input = 1) or a torque of torque_amplitude (2). Set its amplitude to 0 to drive through angle_in or torque_in alone"),
            parking_amplitude: d.parameter("parking_amplitude", 2.0 * 3.14, "rad").min(0.0).describe(&book("Steering_mission, sine amplitude 2*3.14", "Steering-wheel amplitude of the parking manoeuvre")),
            parking_frequency: d.parameter("parking_frequency", 1.0 / 16.0, "Hz").min(0.0).describe(&book("Steering_mission, sine freqHz 1/16", "Frequency of the parking manoeuvre")),
            sine_amplitude: d.parameter("sine_amplitude", 0.5, "rad").min(0.0).describe("Steering-wheel amplitude of the sine steer (chosen: 29 degrees)"),
            sine_frequency: d.parameter("sine_frequency", 1.0, "Hz").min(0.0).describe("Frequency of the sine steer (chosen: a brisk 1 Hz)"),
            torque_amplitude: d.parameter("torque_amplitude", 5.0, "N.m").min(0.0).describe("Amplitude of the driver's torque (driver_input = 2), with the profile's frequency (chosen: a firm hand on the wheel)"),
            filter_frequency: d.parameter("driver_filter_w", 10.0, "rad/s").positive().describe(&book("Steering_mission, secondOrder w", "Natural frequency of the driver's second-order filter on the angle profile")),
            filter_damping: d.parameter("driver_filter_damping", 1.0, "1").positive().describe(&book("Steering_mission, secondOrder D", "Damping of the driver's filter")),
            k_arm: d.parameter("K_arm", 10000.0, "N.m/rad").positive().describe(&book("SteeringWheel, springDamper c", "Stiffness between the imposed angle and the steering wheel (the driver's hands and arms)")),
            d_arm: d.parameter("D_arm", 15.0, "N.m.s/rad").min(0.0).describe("Damping of the driver's arms between the imposed angle and the steering wheel (chosen; the book's is 0, with which the assistance makes the 105 Hz steering-wheel mode unstable: docs/power-steering-spec.md)"),
            j_wheel: d.parameter("J_steering_wheel", 0.023, "kg.m2").positive().describe(&book("SteeringWheel, inertia J", "Steering-wheel inertia")),
            angle_in: d.input("angle_in", 0.0, "rad").describe("Steering-wheel angle added to the profile before the driver's filter (driver_input = 1)"),
            torque_in: d.input("torque_in", 0.0, "N.m").describe("Driver's torque added to the profile's (driver_input = 2)"),
            reference: d.state("driver_angle", 0.0, "rad").nominal(1.0).describe("The driver's filtered angle (the imposed end of the arm's stiffness)"),
            reference_rate: d.state("driver_angle_rate", 0.0, "rad/s").describe("Its rate"),
            arm_stretch: d.state("arm_stretch", 0.0, "rad").nominal(1e-3).describe("The arm's deflection, driver's angle minus steering-wheel angle (driver_input = 2: minus the steering-wheel angle)"),
            w_wheel: d.state("w_steering_wheel", 0.0, "rad/s").describe("Steering-wheel speed"),
            driver: d.element("driver", "Driver", Effect { domains: &[Domain::Rotational], kind: Kind::Source, what: "the driver's hands" }).describe("the driver, power T_driver x (imposed angle's rate, or steering-wheel speed)"),
            arm: d.element("arm_stiffness", "Driver", Effect { what: "arm stiffness", ..TorsionSpring::STIFFNESS }).describe("the arm's stiffness between the imposed angle and the wheel"),
            arm_damping: d.element("arm_damping", "Driver", Effect { what: "arm damping", ..TorsionSpring::DAMPING }).describe("the arm's damping between the imposed angle and the wheel"),
            steering_wheel: d.element("steering_wheel", "Steering wheel", Effect { what: "steering-wheel inertia", ..Inertia::INERTIA }).describe("the steering wheel's inertia"),
        }
    }

    pub fn input<R: Real>(&self, k: &Knowns<R>) -> DriverInput {
        if k[self.driver_input] == 2 {
            DriverInput::Torque
        } else {
            DriverInput::Angle
        }
    }

    /// The profile's shape, sin(2 pi f t), and its angle amplitude (`profile`: 1 parking, 2 sine
    /// steer).
    fn profile<R: Real>(&self, k: &Knowns<R>) -> (R, R) {
        let (amplitude, frequency) = match k[self.profile] {
            2 => (k[self.sine_amplitude], k[self.sine_frequency]),
            _ => (k[self.parking_amplitude], k[self.parking_frequency]),
        };
        ((frequency * (2.0 * PI) * k.time()).sin(), amplitude)
    }

    /// The steering-wheel angle, rad: the driver's angle less the arm's deflection.
    pub fn wheel_angle<R: Real>(&self, k: &Knowns<R>) -> R {
        k[self.reference] - k[self.arm_stretch]
    }

    pub fn wheel_speed<R: Real>(&self, k: &Knowns<R>) -> R {
        k[self.w_wheel]
    }

    /// The driver's filter, torque and powers.
    pub fn forces<R: Real>(&self, k: &Knowns<R>) -> DriverForces<R> {
        let filter = SecondOrderFilter::from_angular_frequency(k[self.filter_frequency], k[self.filter_damping]);
        let arm = TorsionSpring { stiffness_n_m_per_rad: k[self.k_arm], damping_n_m_s_per_rad: k[self.d_arm] };
        let (reference, reference_rate, w_wheel) = (k[self.reference], k[self.reference_rate], k[self.w_wheel]);
        let (shape, amplitude) = self.profile(k);
        let reference_acceleration = filter.acceleration(amplitude * shape + k[self.angle_in], reference, reference_rate);
        match self.input(k) {
            DriverInput::Angle => {
                let (stretch, stretch_rate) = (k[self.arm_stretch], reference_rate - w_wheel);
                let driver_torque = arm.torque_n_m(stretch, stretch_rate);
                DriverForces {
                    reference_acceleration,
                    driver_torque,
                    driver_power: driver_torque * reference_rate,
                    arm_power: arm.spring_power_w(stretch, stretch_rate),
                    arm_damper_power: arm.damper_power_w(stretch_rate),
                }
            }
            DriverInput::Torque => {
                let driver_torque = k[self.torque_amplitude] * shape + k[self.torque_in];
                DriverForces { reference_acceleration, driver_torque, driver_power: driver_torque * w_wheel, arm_power: R::from(0.0), arm_damper_power: R::from(0.0) }
            }
        }
    }

    /// The steering wheel's angular acceleration under the torsion bar's torque.
    pub fn wheel_acceleration<R: Real>(&self, k: &Knowns<R>, f: &DriverForces<R>, bar_torque_n_m: R) -> R {
        Inertia { inertia_kg_m2: k[self.j_wheel] }.acceleration_rad_per_s2(f.driver_torque - bar_torque_n_m)
    }

    /// The driver's states' derivatives and elements' powers, the torsion bar holding the steering
    /// wheel with `bar_torque_n_m`.
    pub fn derivatives<R: Real>(&self, k: &Knowns<R>, bar_torque_n_m: R, der: &mut Derivatives<R>) {
        let f = self.forces(k);
        let acceleration = self.wheel_acceleration(k, &f, bar_torque_n_m);
        let w_wheel = k[self.w_wheel];
        der[self.reference] = k[self.reference_rate];
        der[self.reference_rate] = f.reference_acceleration;
        der[self.arm_stretch] = k[self.reference_rate] - w_wheel;
        der[self.w_wheel] = acceleration;
        der.power(self.driver, f.driver_power);
        der.power(self.arm, f.arm_power);
        der.power(self.arm_damping, f.arm_damper_power);
        der.power(self.steering_wheel, Inertia { inertia_kg_m2: k[self.j_wheel] }.power_w(acceleration, w_wheel));
    }
}

/// The torque sensor's torsion bar (section 3.5.2): its stiffness and its element.
pub struct Sensor {
    k_torsion_bar: Parameter,
    element: Element,
}

impl Sensor {
    pub fn declare(d: &mut Declarations) -> Self {
        Sensor {
            k_torsion_bar: d.parameter("K_torsion_bar", 100.0, "N.m/rad").positive().describe("Torsion bar stiffness of the torque sensor (book file Chap3_TorqueSensor.mo, spring c; section 3.5.2)"),
            element: d.element("torsion_bar", "Torque sensor", TorsionBar::STIFFNESS).describe("the torsion bar, K twist dtwist/dt"),
        }
    }

    pub fn bar<R: Real>(&self, k: &Knowns<R>) -> TorsionBar<R> {
        TorsionBar { stiffness_n_m_per_rad: k[self.k_torsion_bar], stop_angle_rad: R::from(f64::INFINITY) }
    }

    /// The torque the sensor measures, K x twist.
    pub fn torque_n_m<R: Real>(&self, k: &Knowns<R>, twist_rad: R) -> R {
        self.bar(k).stiffness_n_m_per_rad * twist_rad
    }

    pub fn report<R: Real>(&self, k: &Knowns<R>, twist_rad: R, twist_rate: R, der: &mut Derivatives<R>) {
        der.power(self.element, self.torque_n_m(k, twist_rad) * twist_rate);
    }

    /// Declares the torsion bar's end stops as neglected.
    pub fn neglect_stops(d: &mut Declarations) {
        d.neglected("Torque sensor", TorsionBar::STIFFNESS, "the torsion bar's end stops: the twist stays within a few degrees with the assistance on (docs/power-steering-spec.md)");
    }
}

// ---------------------------------------------------------------------------------------------
// The worm gear

/// The worm gear's ratio and efficiencies. The motor side needs only the ratio and the forward
/// efficiency (the assistance law's gain, the back-emf's speed).
pub struct Worm {
    ratio: Parameter,
    forward: Parameter,
    backward: Option<Parameter>,
}

impl Worm {
    fn declare_with(d: &mut Declarations, backward: bool) -> Self {
        let worm = default_worm();
        Worm {
            ratio: d.parameter("worm_ratio", worm.ratio, "1").positive().describe("Worm gear ratio, motor speed / column speed (chosen: docs/power-steering-spec.md)"),
            forward: d.parameter("worm_efficiency_forward", worm.forward_efficiency, "1").positive().max(1.0).describe("Worm efficiency while the motor drives the column: tan(lambda)/tan(lambda + phi), lead 20 deg, mu 0.05"),
            backward: backward.then(|| {
                d.parameter("worm_efficiency_backward", worm.backward_efficiency, "1").positive().max(1.0).describe("Worm efficiency while the column drives the motor back: tan(lambda - phi)/tan(lambda)")
            }),
        }
    }

    /// Ratio and both efficiencies (the gear itself).
    pub fn declare(d: &mut Declarations) -> Self {
        Self::declare_with(d, true)
    }

    /// Ratio and forward efficiency (the motor's controller).
    pub fn declare_motor_side(d: &mut Declarations) -> Self {
        Self::declare_with(d, false)
    }

    pub fn ratio<R: Real>(&self, k: &Knowns<R>) -> R {
        k[self.ratio]
    }

    pub fn forward_efficiency<R: Real>(&self, k: &Knowns<R>) -> R {
        k[self.forward]
    }

    /// The gear (the motor side's declaration has no backward efficiency: it reads as the forward).
    pub fn gear<R: Real>(&self, k: &Knowns<R>) -> WormGear<R> {
        let backward = self.backward.map_or(k[self.forward], |b| k[b]);
        WormGear { ratio: k[self.ratio], forward_efficiency: k[self.forward], backward_efficiency: backward }
    }

    /// Refuses a self-locking or otherwise impossible gear.
    pub fn check(&self, k: &Knowns) -> Result<(), String> {
        let g = self.gear(k);
        WormGear::new(g.ratio, g.forward_efficiency, g.backward_efficiency).map(|_| ()).map_err(|e| format!("worm gear: {e}"))
    }
}

// ---------------------------------------------------------------------------------------------
// The assistance: law, current loop, armature

/// The assistance law (gain, active damping, saturation), the PI current loop within the
/// battery's voltage and the motor's armature (eq. 3.9's electrical side).
pub struct Assist {
    r_motor: Parameter,
    l_motor: Parameter,
    k_motor: Parameter,
    u_battery: Parameter,
    assist_gain: Parameter,
    assist_damping: Parameter,
    i_max: Parameter,
    kp_current: Parameter,
    ki_current: Parameter,
    tracking_time: Parameter,
    current: State,
    current_integral: State,
    assist_limit: Mode,
    voltage_limit: Mode,
    z_assist: Indicator,
    z_voltage: Indicator,
    battery: Element,
    armature_r: Element,
    armature_l: Element,
}

/// The assistance at one instant.
pub struct AssistOperating<R = f64> {
    pub assist_demand: R,
    pub current_command: R,
    pub current_error: R,
    pub voltage: R,
    pub current_rate: R,
    pub integral_rate: R,
    /// The electromagnetic torque k i on the motor's shaft.
    pub motor_torque: R,
}

impl Assist {
    pub fn declare(d: &mut Declarations) -> Self {
        Assist {
            r_motor: d.parameter("R_motor", 0.06, "Ohm").positive().describe("Assistance motor armature resistance (chosen, 12 V brushed DC)"),
            l_motor: d.parameter("L_motor", 1.0e-4, "H").positive().describe("Assistance motor armature inductance (chosen)"),
            k_motor: d.parameter("k_motor", 0.041, "V.s/rad").positive().describe("Assistance motor constant k_C = k_E (eq. 3.9; chosen for 35 N m of assistance at 60 A)"),
            u_battery: d.parameter("U_battery", 12.0, "V").positive().describe("Battery voltage, the current loop's limit"),
            assist_gain: d.parameter("assist_gain", 4.0, "1").min(0.0).describe("Assistance gain: assistance torque at the column over the measured torque while the motor drives"),
            assist_damping: d.parameter("assist_damping", 1.0, "N.m.s/rad").min(0.0).describe("Active damping of the assistance law: torque demanded at the column against the column's speed (chosen: without it the assisted column oscillates whenever the treads slide, docs/power-steering-spec.md)"),
            i_max: d.parameter("I_max", 60.0, "A").positive().describe("Saturation of the current command"),
            kp_current: d.parameter("Kp_current", 0.1885, "Ohm").positive().describe("Current loop proportional gain, L_motor x 1885 rad/s (a 300 Hz loop)"),
            ki_current: d.parameter("Ki_current", 113.1, "Ohm/s").min(0.0).describe("Current loop integral gain, R_motor x 1885 rad/s"),
            tracking_time: d.parameter("T_tracking_current", 1.0e-3, "s").positive().describe("Current loop anti-windup tracking time"),
            current: d.state("i_motor", 0.0, "A").nominal(10.0).describe("Assistance motor current"),
            current_integral: d.state("current_error_integral", 0.0, "A.s").nominal(1e-3).describe("Current loop's integral of the error"),
            assist_limit: d.mode("assist_limit", 0).range(-1, 1).describe("Current command: 0 within +/- I_max, 1 at +I_max, -1 at -I_max"),
            voltage_limit: d.mode("voltage_limit", 0).range(-1, 1).describe("Current loop's voltage: 0 within +/- U_battery, 1 at +U_battery, -1 at -U_battery"),
            z_assist: d.event_indicator("assist_saturation", "within: I_max - |gain x torque|; saturated: how far beyond"),
            z_voltage: d.event_indicator("voltage_saturation", "within: U_battery - |raw voltage|; saturated: how far beyond"),
            battery: d.element("battery", "Motor", Effect { domains: &[Domain::Electrical], kind: Kind::Source, what: "battery through the current loop's bridge" }).describe("the battery, u i"),
            armature_r: d.element("armature_resistance", "Motor", DcMachine::RESISTANCE).describe("the motor's armature resistance, R i^2"),
            armature_l: d.element("armature_inductance", "Motor", DcMachine::INDUCTANCE).describe("the motor's armature inductance, L i di/dt"),
        }
    }

    /// Declares eq. 3.9's transformer (it has no power of its own).
    pub fn declare_transformer(d: &mut Declarations) {
        d.element("electromechanical_transformer", "Motor", DcMachine::TRANSFORMER).describe("the motor's E = k w, C = k i (eq. 3.9)");
    }

    pub fn motor<R: Real>(&self, k: &Knowns<R>) -> DcMachine<R> {
        DcMachine { resistance_ohm: k[self.r_motor], inductance_h: k[self.l_motor], constant_v_s_per_rad: k[self.k_motor] }
    }

    /// From the assistance torque demanded at the column to the current that gives it while the
    /// motor drives (N eta_f k i), saturated at I_max.
    fn law<R: Real>(&self, k: &Knowns<R>, worm: &Worm) -> PiController<R> {
        PiController {
            proportional_gain: R::from(1.0) / (worm.ratio(k) * worm.forward_efficiency(k) * k[self.k_motor]),
            integral_gain: R::from(0.0),
            output_limit: k[self.i_max],
            tracking_time_s: R::from(1.0),
        }
    }

    fn current_loop<R: Real>(&self, k: &Knowns<R>) -> PiController<R> {
        PiController { proportional_gain: k[self.kp_current], integral_gain: k[self.ki_current], output_limit: k[self.u_battery], tracking_time_s: k[self.tracking_time] }
    }

    pub fn current<R: Real>(&self, k: &Knowns<R>) -> R {
        k[self.current]
    }

    /// The law, the loop and the armature, for the measured torque and the column's speed.
    pub fn operate<R: Real>(&self, k: &Knowns<R>, worm: &Worm, measured_torque_n_m: R, w_column: R) -> AssistOperating<R> {
        let motor = self.motor(k);
        let assist_demand = k[self.assist_gain] * measured_torque_n_m - k[self.assist_damping] * w_column;
        let current_command = self.law(k, worm).command(assist_demand, R::from(0.0));
        let (i, integral) = (k[self.current], k[self.current_integral]);
        let current_error = current_command - i;
        let current_loop = self.current_loop(k);
        let voltage = current_loop.command(current_error, integral);
        AssistOperating {
            assist_demand,
            current_command,
            current_error,
            voltage,
            current_rate: motor.current_rate_a_per_s(voltage, i, worm.ratio(k) * w_column),
            integral_rate: current_loop.integral_rate(current_error, integral),
            motor_torque: motor.torque_n_m(i),
        }
    }

    pub fn event_indicators(&self, k: &Knowns, worm: &Worm, measured_torque_n_m: f64, w_column: f64, z: &mut EventIndicators) {
        let op = self.operate(k, worm, measured_torque_n_m, w_column);
        z[self.z_assist] = self.law(k, worm).limit_indicator(k[self.assist_limit], op.assist_demand, 0.0);
        z[self.z_voltage] = self.current_loop(k).limit_indicator(k[self.voltage_limit], op.current_error, k[self.current_integral]);
    }

    /// The saturations' modes; `torque_rate` and `column_acceleration` (their inputs' rates, 0
    /// where unknown) decide the side only at an exact tie with a limit.
    pub fn update_modes(&self, k: &Knowns, worm: &Worm, measured_torque_n_m: f64, w_column: f64, torque_rate: f64, column_acceleration: f64, next: &mut ModeUpdate) {
        let op = self.operate(k, worm, measured_torque_n_m, w_column);
        let law = self.law(k, worm);
        let demand_rate = k[self.assist_gain] * torque_rate - k[self.assist_damping] * column_acceleration;
        next[self.assist_limit] = law.next_limit_mode(k[self.assist_limit], op.assist_demand, 0.0, law.proportional_gain * demand_rate);
        let command_rate = if op.current_command.abs() < law.output_limit { law.proportional_gain * demand_rate } else { 0.0 };
        let current_loop = self.current_loop(k);
        let raw_rate = current_loop.raw_rate(op.current_error, command_rate - op.current_rate, k[self.current_integral]);
        next[self.voltage_limit] = current_loop.next_limit_mode(k[self.voltage_limit], op.current_error, k[self.current_integral], raw_rate);
    }

    /// The current's and the integral's derivatives and the electrical elements' powers.
    pub fn derivatives<R: Real>(&self, k: &Knowns<R>, worm: &Worm, measured_torque_n_m: R, w_column: R, der: &mut Derivatives<R>) {
        let op = self.operate(k, worm, measured_torque_n_m, w_column);
        let (motor, i) = (self.motor(k), k[self.current]);
        der[self.current] = op.current_rate;
        der[self.current_integral] = op.integral_rate;
        der.power(self.battery, op.voltage * i);
        der.power(self.armature_r, motor.resistance_power_w(i));
        der.power(self.armature_l, motor.inductance_power_w(op.current_rate, i));
    }
}

// ---------------------------------------------------------------------------------------------
// The lower column, the motor's rotor, the rack, the wheels and the tires

/// The lower column with the worm wheel and the pinion, the motor's rotor behind the worm, the
/// rack, the tie rods, the steering levers, the wheels about their pivots and the tires
/// (Figure 3.19): the parameters, the states but the column's angle (PowerSteering takes it from
/// the springs' deflections, SteeringRack integrates it), the modes and the elements.
pub struct Rack {
    pub worm: Worm,
    j_column: Parameter,
    column_friction: Parameter,
    j_motor: Parameter,
    b_motor: Parameter,
    r_pinion: Parameter,
    m_rack: Parameter,
    rigid_tie_rods: BooleanParameter,
    k_tie_rod: Parameter,
    lever_arm: Parameter,
    j_rim: Parameter,
    k_tire: Parameter,
    d_tire: Parameter,
    j_tread: Parameter,
    t_friction: Parameter,
    k_gravity: Parameter,
    w_column: State,
    tie_rod_stretch: State,
    w_rim: State,
    tire_twist: State,
    w_tread: State,
    worm_flow: Mode,
    tread_mode: Mode,
    z_worm: Indicator,
    z_tread: Indicator,
    elements: RackElements,
}

struct RackElements {
    column: Element,
    rotor: Element,
    motor_friction: Element,
    worm_efficiency: Element,
    column_friction: Element,
    rack: Element,
    tie_rods: Element,
    rims: Element,
    tire_stiffness: Element,
    tire_damping: Element,
    treads: Element,
    ground_friction: Element,
    kingpin_gravity: Element,
}

/// The components at the current parameter values (the wheel side counts both wheels).
struct RackParts<R = f64> {
    worm: WormGear<R>,
    column: Inertia<R>,
    rotor: Inertia<R>,
    motor_friction_n_m_s_per_rad: R,
    column_friction_n_m: R,
    pinion: RackAndPinion<R>,
    rack: Mass<R>,
    tie_rods: TranslationalSpring<R>,
    lever: Lever<R>,
    rigid_tie_rods: bool,
    rims: Inertia<R>,
    tire: TorsionSpring<R>,
    treads: Inertia<R>,
    ground: CoulombFriction<R>,
    gravity: TorsionSpring<R>,
}

/// The mechanics at one instant, for one worm mode.
#[derive(Default)]
pub struct RackOperating<R = f64> {
    pub worm_torque: R,
    /// The worm wheel's torque on the column.
    pub assist_torque: R,
    pub column_friction: R,
    pub column_acceleration: R,
    /// The tie rods' tension (both rods).
    pub rack_force: R,
    pub tie_rod_stretch_rate: R,
    pub rim_acceleration: R,
    pub tire_torque: R,
    pub tread_acceleration: R,
    pub ground_torque: R,
}

impl Rack {
    pub fn declare(d: &mut Declarations) -> Self {
        Rack {
            j_column: d.parameter("J_column", 2.0e-4, "kg.m2").positive().describe("Lower column, worm wheel and pinion shaft (chosen, Table 3.2 cylinders: docs/power-steering-spec.md)"),
            worm: Worm::declare(d),
            column_friction: d.parameter("T_column_friction", 0.5, "N.m").min(0.0).describe("Dry friction of the lower column and the worm's bearings, load-independent (chosen: docs/power-steering-spec.md)"),
            j_motor: d.parameter("J_motor", 1.5e-4, "kg.m2").positive().describe("Assistance motor rotor inertia (chosen)"),
            b_motor: d.parameter("b_motor", 2.0e-4, "N.m.s/rad").min(0.0).describe("Assistance motor viscous friction (chosen: 0.02 N m at 100 rad/s)"),
            r_pinion: d.parameter("r_pinion", 0.01, "m").positive().describe(&book("RackPinion2Ports, ratio 1/0.01", "Pinion radius (rack travel 62.8 mm per turn)")),
            m_rack: d.parameter("m_rack", 2.5, "kg").positive().describe("Rack mass (chosen; the book's rack is massless)"),
            rigid_tie_rods: d.boolean_parameter("rigid_tie_rods", true).describe("true: rigid tie rods (the book's Bielette_init); false: their axial stiffness K_tie_rod (a 200 Hz mode whose activity is negligible: docs/power-steering-spec.md)"),
            k_tie_rod: d.parameter("K_tie_rod", 1.08e8, "N/m").positive().describe("Axial stiffness of one tie rod: steel, 14 mm, 0.3 m (Table 3.2, E A / L; the book's rods are rigid)"),
            lever_arm: d.parameter("lever_arm", 0.1, "m").positive().describe(&book("Bielette_init, b_levier", "Steering lever arm, from the tie rod to the wheel's pivot")),
            j_rim: d.parameter("J_rim", 1.0, "kg.m2").positive().describe(&book("Tire_init, J", "Inertia of one wheel (rim) about its pivot")),
            k_tire: d.parameter("K_tire", 3000.0, "N.m/rad").positive().describe(&book("Tire_init, K", "Torsional stiffness of one tire between rim and tread")),
            d_tire: d.parameter("D_tire", 28.0, "N.m.s/rad").min(0.0).describe(&book("Tire_init, f", "Torsional damping of one tire")),
            j_tread: d.parameter("J_tread", 0.1, "kg.m2").positive().describe(&book("Tire_init, Jp", "Inertia of one tire's tread about the pivot")),
            t_friction: d.parameter("T_tire_friction", 80.0, "N.m").min(0.0).describe(&book("Tire_init, T (bearingFriction, peak 1)", "Friction torque of one tread on the ground (static = sliding)")),
            k_gravity: d.parameter("K_kingpin_gravity", 7.95, "N.m/rad").min(0.0).describe(&book("Tire_final, Kgr", "Return stiffness of one wheel from the kingpin's inclination (gravity)")),
            w_column: d.state("w_column", 0.0, "rad/s").describe("Lower column speed (the motor turns N times faster)"),
            tie_rod_stretch: d.state("tie_rod_stretch", 0.0, "m").nominal(1e-5).describe("Tie rods' stretch, rack travel minus the levers' travel"),
            w_rim: d.state("w_rim", 0.0, "rad/s").describe("Wheels' speed about their pivots"),
            tire_twist: d.state("tire_twist", 0.0, "rad").nominal(0.03).describe("Tires' twist, wheel angle minus tread angle"),
            w_tread: d.state("w_tread", 0.0, "rad/s").describe("Treads' speed on the ground"),
            worm_flow: d.mode("worm_mode", 0).range(-2, 2).describe("The worm gear (components::GearMode): 0 at rest, held by its friction; moving, the sign is the column's direction and 1 = the motor drives the column, 2 = the column drives the motor"),
            tread_mode: d.mode("tread_mode", 0).range(-1, 1).describe("Treads on the ground: 1 sliding forwards, 0 stuck, -1 sliding backwards"),
            z_worm: d.event_indicator("worm", "moving: the smaller of the column speed's and the worm torque's margins in the mode's direction; at rest: how far every direction is from breaking away"),
            z_tread: d.event_indicator("tread", "sliding: the treads' speed in the direction of slip; stuck: the friction's margin"),
            elements: RackElements {
                column: d.element("column", "Column", Effect { what: "column inertia", ..Inertia::INERTIA }).describe("the lower column, worm wheel and pinion"),
                rotor: d.element("rotor", "Motor", Effect { what: "rotor inertia", ..Inertia::INERTIA }).describe("the motor's rotor inertia"),
                motor_friction: d.element("motor_friction", "Motor", Effect { domains: &[Domain::Rotational], kind: Kind::Dissipation, what: "viscous friction" }).describe("the motor's viscous friction, b w^2"),
                worm_efficiency: d.element("worm_efficiency", "Worm gear", WormGear::EFFICIENCY).describe("the worm's losses"),
                column_friction: d.element("column_friction", "Column", CoulombFriction::FRICTION).describe("the column's and the worm bearings' dry friction, T |w|"),
                rack: d.element("rack", "Rack", Mass::MASS).describe("the rack's mass"),
                tie_rods: d.element("tie_rods", "Tie rods", TranslationalSpring::STIFFNESS).describe("the tie rods' stiffness"),
                rims: d.element("rims", "Wheels", Effect { what: "wheel inertia about the pivot", ..Inertia::INERTIA }).describe("the wheels' inertia about their pivots"),
                tire_stiffness: d.element("tire_stiffness", "Tires", Effect { what: "tire torsional stiffness", ..TorsionSpring::STIFFNESS }).describe("the tires' torsional stiffness"),
                tire_damping: d.element("tire_damping", "Tires", Effect { what: "tire torsional damping", ..TorsionSpring::DAMPING }).describe("the tires' torsional damping"),
                treads: d.element("treads", "Tires", Effect { what: "tread inertia", ..Inertia::INERTIA }).describe("the treads' inertia"),
                ground_friction: d.element("ground_friction", "Tires", CoulombFriction::FRICTION).describe("the treads' friction on the ground"),
                kingpin_gravity: d.element("kingpin_gravity", "Wheels", Effect { what: "kingpin inclination (gravity return)", ..TorsionSpring::STIFFNESS }).describe("the kingpin's gravity return (the car lifted as the wheels turn)"),
            },
        }
    }

    /// Declares the transformers (no power of their own) and the effects left out.
    pub fn declare_transformers_and_neglected(d: &mut Declarations) {
        d.element("worm_ratio", "Worm gear", WormGear::RATIO).describe("the worm's ratio N");
        d.element("rack_and_pinion", "Rack", RackAndPinion::TRANSFORMER).describe("the pinion, v = r w, T = r F");
        d.element("steering_levers", "Wheels", Lever::TRANSFORMER).describe("the steering levers, v = b w, T = b F");
        d.neglected("Motor", CoulombFriction::FRICTION, "the motor's brushes' and bearings' dry friction: only its viscous part is kept");
        d.neglected("Tie rods", TranslationalSpring::DAMPING, "the steel rods' internal damping (the tires damp the wheels)");
    }

    fn parts<R: Real>(&self, k: &Knowns<R>) -> RackParts<R> {
        RackParts {
            worm: self.worm.gear(k),
            column: Inertia { inertia_kg_m2: k[self.j_column] },
            rotor: Inertia { inertia_kg_m2: k[self.j_motor] },
            motor_friction_n_m_s_per_rad: k[self.b_motor],
            column_friction_n_m: k[self.column_friction],
            pinion: RackAndPinion { pinion_radius_m: k[self.r_pinion] },
            rack: Mass { mass_kg: k[self.m_rack] },
            tie_rods: TranslationalSpring { stiffness_n_per_m: k[self.k_tie_rod] * WHEELS, damping_n_s_per_m: R::from(0.0) },
            lever: Lever { arm_m: k[self.lever_arm] },
            rigid_tie_rods: k[self.rigid_tie_rods],
            rims: Inertia { inertia_kg_m2: k[self.j_rim] * WHEELS },
            tire: TorsionSpring { stiffness_n_m_per_rad: k[self.k_tire] * WHEELS, damping_n_m_s_per_rad: k[self.d_tire] * WHEELS },
            treads: Inertia { inertia_kg_m2: k[self.j_tread] * WHEELS },
            ground: CoulombFriction { coulomb_n_m: k[self.t_friction] * WHEELS, static_n_m: k[self.t_friction] * WHEELS },
            gravity: TorsionSpring { stiffness_n_m_per_rad: k[self.k_gravity] * WHEELS, damping_n_m_s_per_rad: R::from(0.0) },
        }
    }

    pub fn column_speed<R: Real>(&self, k: &Knowns<R>) -> R {
        k[self.w_column]
    }

    /// The wheels' speed about their pivots, rad/s: the state with compliant tie rods, the rack's
    /// through the levers with rigid ones (the state then stays at 0).
    fn rim_speed<R: Real>(&self, k: &Knowns<R>) -> R {
        if k[self.rigid_tie_rods] {
            k[self.r_pinion] / k[self.lever_arm] * k[self.w_column]
        } else {
            k[self.w_rim]
        }
    }

    /// The rack's position from the column's angle, m.
    pub fn rack_position<R: Real>(&self, k: &Knowns<R>, column_angle: R) -> R {
        RackAndPinion { pinion_radius_m: k[self.r_pinion] }.rack_velocity_m_per_s(column_angle)
    }

    /// The wheels' angle from the column's angle and the tie rods' stretch, rad (each under error
    /// control at its own scale: a tie rod stretches by microns while the rack travels
    /// centimetres).
    pub fn wheel_angle<R: Real>(&self, k: &Knowns<R>, column_angle: R) -> R {
        (self.rack_position(k, column_angle) - k[self.tie_rod_stretch]) / k[self.lever_arm]
    }

    /// The mechanics under the torsion bar's torque on the column and the motor's
    /// electromagnetic torque, in worm mode `worm_mode`.
    pub fn operate<R: Real>(&self, k: &Knowns<R>, column_angle: R, bar_torque: R, motor_torque: R, worm_mode: i32) -> RackOperating<R> {
        let p = self.parts(k);
        let mut op = RackOperating::default();
        let (w_column, w_rim, w_tread) = (k[self.w_column], self.rim_speed(k), k[self.w_tread]);

        // Tires and treads.
        let rim_angle = self.wheel_angle(k, column_angle);
        op.tire_torque = p.tire.torque_n_m(k[self.tire_twist], w_rim - w_tread);
        let wheel_load = op.tire_torque + p.gravity.torque_n_m(rim_angle, R::from(0.0));
        if k[self.tread_mode] == 0 {
            op.ground_torque = -op.tire_torque;
            op.tread_acceleration = R::from(0.0);
        } else {
            op.ground_torque = p.ground.slip_torque_n_m(k[self.tread_mode]);
            op.tread_acceleration = p.treads.acceleration_rad_per_s2(op.tire_torque + op.ground_torque);
        }

        // The tie rods: compliant, their force from their stretch; rigid (the book's), the wheels
        // turn with the rack (lever ratio r / b) and their load and inertia act on the column.
        let ratio = p.pinion.pinion_radius_m / p.lever.arm_m;
        let (load, wheels_inertia) = if p.rigid_tie_rods {
            (bar_torque - ratio * wheel_load, ratio * ratio * p.rims.inertia_kg_m2)
        } else {
            op.rack_force = p.tie_rods.force_n(k[self.tie_rod_stretch], R::from(0.0));
            (bar_torque - p.pinion.pinion_torque_n_m(op.rack_force), R::from(0.0))
        };
        op.tie_rod_stretch_rate = if p.rigid_tie_rods { R::from(0.0) } else { p.pinion.rack_velocity_m_per_s(w_column) - p.lever.rod_velocity_m_per_s(w_rim) };

        // The column, the worm and the motor's rotor move as one: with e the worm's torque
        // factor for the power's direction (eta_f, or 1/eta_b) and s the direction of motion,
        // (J_c + m_r r^2 + e N^2 J_m) dw/dt = T_bar - r F - s T_friction + N e (k i - b N w).
        // At rest (GearMode::STUCK) the gear's and the column's friction hold it and take
        // whatever torque that requires.
        let n = p.worm.ratio;
        let w_motor = n * w_column;
        let drive = motor_torque - p.motor_friction_n_m_s_per_rad * w_motor;
        if worm_mode == GearMode::STUCK {
            op.column_acceleration = R::from(0.0);
            op.worm_torque = drive;
            op.assist_torque = -load;
        } else {
            let forward = GearMode::forward(worm_mode);
            op.column_friction = p.column_friction_n_m * -GearMode::direction(worm_mode);
            let e = p.worm.low_side_torque_flowing_n_m(R::from(1.0), forward) / n;
            let inertia = p.column.inertia_kg_m2 + p.pinion.referred_inertia_kg_m2(p.rack.mass_kg) + wheels_inertia + e * n * n * p.rotor.inertia_kg_m2;
            op.column_acceleration = (load + op.column_friction + n * e * drive) / inertia;
            op.worm_torque = drive - p.rotor.inertia_kg_m2 * n * op.column_acceleration;
            op.assist_torque = p.worm.low_side_torque_flowing_n_m(op.worm_torque, forward);
        }
        if p.rigid_tie_rods {
            op.rim_acceleration = ratio * op.column_acceleration;
            op.rack_force = (p.rims.inertia_kg_m2 * op.rim_acceleration + wheel_load) / p.lever.arm_m;
        } else {
            op.rim_acceleration = p.rims.acceleration_rad_per_s2(p.lever.hinge_moment_n_m(op.rack_force) - wheel_load);
        }
        op
    }

    /// The worm's and the treads' event indicators.
    pub fn event_indicators(&self, k: &Knowns, column_angle: f64, bar_torque: f64, motor_torque: f64, z: &mut EventIndicators) {
        let p = self.parts(k);
        let op = self.operate(k, column_angle, bar_torque, motor_torque, k[self.worm_flow]);
        z[self.z_worm] = match k[self.worm_flow] {
            GearMode::STUCK => GearMode::stuck_margin(|m| self.worm_start(k, column_angle, bar_torque, motor_torque, m)),
            mode => GearMode::moving_margin(mode, k[self.w_column], op.worm_torque),
        };
        z[self.z_tread] = p.ground.indicator(k[self.tread_mode], k[self.w_tread], op.tire_torque);
    }

    /// How a moving worm mode would start from rest: the motor side's acceleration and torque.
    fn worm_start(&self, k: &Knowns, column_angle: f64, bar_torque: f64, motor_torque: f64, mode: i32) -> (f64, f64) {
        let op = self.operate(k, column_angle, bar_torque, motor_torque, mode);
        (op.column_acceleration, op.worm_torque)
    }

    /// The worm's and the treads' modes after an event (a stop sets the speed to 0).
    pub fn update_modes(&self, k: &Knowns, column_angle: f64, bar_torque: f64, motor_torque: f64, next: &mut ModeUpdate) {
        let p = self.parts(k);
        let torque = self.operate(k, column_angle, bar_torque, motor_torque, GearMode::of(k[self.w_column], true)).worm_torque;
        let (flow, stop) = GearMode::next(k[self.worm_flow], k[self.w_column], torque, STANDSTILL_RAD_PER_S, |m| self.worm_start(k, column_angle, bar_torque, motor_torque, m));
        next[self.worm_flow] = flow;
        if stop {
            next.reinit(self.w_column, 0.0);
        }
        let op = self.operate(k, column_angle, bar_torque, motor_torque, k[self.worm_flow]);
        // A sliding tread slower than the standstill speed is taken as stopped (see
        // STANDSTILL_RAD_PER_S): its speed is then reset to 0 whatever the mode after.
        let w_tread = k[self.w_tread];
        let creeping = k[self.tread_mode] != 0 && w_tread.abs() < STANDSTILL_RAD_PER_S;
        let (tread, stop) = p.ground.next_mode(k[self.tread_mode], if creeping { 0.0 } else { w_tread }, op.tire_torque);
        next[self.tread_mode] = tread;
        if stop {
            next.reinit(self.w_tread, 0.0);
        }
    }

    /// The column's acceleration in the current worm mode.
    pub fn column_acceleration<R: Real>(&self, k: &Knowns<R>, column_angle: R, bar_torque: R, motor_torque: R) -> R {
        self.operate(k, column_angle, bar_torque, motor_torque, k[self.worm_flow]).column_acceleration
    }

    /// The current mode's mechanics (for outputs).
    pub fn operating<R: Real>(&self, k: &Knowns<R>, column_angle: R, bar_torque: R, motor_torque: R) -> RackOperating<R> {
        self.operate(k, column_angle, bar_torque, motor_torque, k[self.worm_flow])
    }

    /// The states' derivatives (all but the column's angle) and the elements' powers.
    pub fn derivatives<R: Real>(&self, k: &Knowns<R>, column_angle: R, bar_torque: R, motor_torque: R, der: &mut Derivatives<R>) {
        let p = self.parts(k);
        let op = self.operate(k, column_angle, bar_torque, motor_torque, k[self.worm_flow]);
        let (w_column, w_rim, w_tread) = (k[self.w_column], self.rim_speed(k), k[self.w_tread]);
        der[self.w_column] = op.column_acceleration;
        if !p.rigid_tie_rods {
            der[self.tie_rod_stretch] = op.tie_rod_stretch_rate;
            der[self.w_rim] = op.rim_acceleration;
        }
        der[self.tire_twist] = w_rim - w_tread;
        der[self.w_tread] = op.tread_acceleration;

        let e = &self.elements;
        let w_motor = p.worm.ratio * w_column;
        der.power(e.column, p.column.power_w(op.column_acceleration, w_column));
        der.power(e.rotor, p.rotor.power_w(p.worm.ratio * op.column_acceleration, w_motor));
        der.power(e.motor_friction, p.motor_friction_n_m_s_per_rad * w_motor * w_motor);
        der.power(e.worm_efficiency, op.worm_torque * w_motor - op.assist_torque * w_column);
        der.power(e.column_friction, -op.column_friction * w_column);
        let rack_speed = p.pinion.rack_velocity_m_per_s(w_column);
        der.power(e.rack, p.rack.power_w(p.pinion.rack_velocity_m_per_s(op.column_acceleration), rack_speed));
        der.power(e.tie_rods, op.rack_force * op.tie_rod_stretch_rate);
        der.power(e.rims, p.rims.power_w(op.rim_acceleration, w_rim));
        let tire_twist = k[self.tire_twist];
        der.power(e.tire_stiffness, p.tire.spring_power_w(tire_twist, w_rim - w_tread));
        der.power(e.tire_damping, p.tire.damper_power_w(w_rim - w_tread));
        der.power(e.treads, p.treads.power_w(op.tread_acceleration, w_tread));
        der.power(e.ground_friction, -op.ground_torque * w_tread);
        der.power(e.kingpin_gravity, p.gravity.spring_power_w(self.wheel_angle(k, column_angle), w_rim));
    }
}

/// The coupling port of a subsystem: the power a connected FMU delivers through a torque and a
/// speed.
pub const PORT: Effect = SHAFT_PORT;
