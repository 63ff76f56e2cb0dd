//! MotorFan: the start-up of the cooling-tower electric fan, the chapter's guideline example
//! (sections 3.1-3.3, Figures 3.2-3.13), at the four modelling levels of Figure 3.5, started
//! direct-on-line or at variable speed (PI controller or inverse simulation, Figure 3.7) with an
//! optional second-order set-point filter (Figure 3.13), with the activity index of each storage
//! element (eq. 3.3, Table 3.3). The contract: `docs/motor-fan-spec.md`.
//!
//! Chain: induction motor (inertia J_motor) -> driveshaft on the high-speed side (K_shaft,
//! D_shaft) -> reducer (gear_ratio N, gear_efficiency) -> fan (J_fan, torque k_fan w^2).
//!
//! Defaults: the book authors' own values (book file Chap3_CoolingTowerFan.mo; each parameter's
//! description names its component, `docs/motor-fan-spec.md` tabulates them):
//! * Motor at levels a-c: the torque-speed table TorqueSpeed (454 N m at standstill, 1071 N m at
//!   250 rad/s, 0 at 314 rad/s), read linearly at levels a and b (Steady_State,
//!   Transient_Dynamic) and by Akima's spline at level c (Transient_Resonance); J_motor 1.72.
//! * Motor at level d (and the current drawn at every level): the book's induction machine
//!   (result file Transient_InductionMachine_graphic.mat): R_s = R_r = 0.038 Ohm, leakages 0.2
//!   and 0.4 mH, L_m 12 mH, one pole pair, 230 V per phase. Its steady-state torque matches the
//!   table within 1.3 % (6.5 N m at 314 rad/s).
//! * Reducer N = 16, efficiency 0.94 both ways (lossyGear); J_fan 3000 kg m2 (11.72 on the
//!   high-speed axis, the chapter's eq. 3.6); fan torque 7742.6 N m at 19.373 rad/s.
//! * Shaft: c = 866 N m/rad, d = 866/100/sqrt(886/1.7) (the file's 886).
//! * Variable-speed start (Transient_SpeedControler): 0 -> 300 rad/s in 10 s through a
//!   second-order filter (2*3.14*0.5 rad/s, D = 1), PI k = 10000, T = 0.1 (Kp 10000, Ki 100000),
//!   no torque limit, and a 2*3.14*800 rad/s, D = 1 torque actuator between the PI and the motor.
//!
//! The earlier chosen set (a 160 kW 4-pole motor by its circuit, N = 10, eta 0.97, J_fan 1172,
//! K 906.85, D 5, k_fan 42.9 i.e. T_fan_nominal 42.9 x speed_fan_nominal^2, Kp 200, Ki 2000,
//! T_limit 2500, no actuator lag, no filter, 153.5 rad/s) stays reachable through parameters:
//! motor_model = 2 with its circuit values, and the rest by value (docs/motor-fan-spec.md).

use components::{FanLoad, Fluxes, InductionMachine, Inertia, Reducer, TorqueSpeedTable, TorsionSpring};
use drive_train::{converter_fed, ControllerParameters, FanParameters, MotorCurve, MotorParameters, SetPoint, ShaftParameters, TorqueActuatorParameters, TorqueLimitEvent};
use fmu_runtime::prelude::*;

mod documentation;

/// Modelling level (Figure 3.5), in increasing detail.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Level {
    QuasiStatic,
    Inertias,
    Elastic,
    Electrical,
}

/// How the motor is started (sections 3.3.1-3.3.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Start {
    DirectOnLine,
    PiControl,
    InverseSimulation,
}

pub struct MotorFan {
    level: IntegerParameter,
    start_mode: IntegerParameter,
    keep_shaft_stiffness: BooleanParameter,
    motor: MotorParameters,
    shaft: ShaftParameters,
    fan: FanParameters,
    control: ControllerParameters,
    actuator: TorqueActuatorParameters,
    w_motor: State,
    twist: State,
    w_fan: State,
    psi_sd: State,
    psi_sq: State,
    psi_rd: State,
    psi_rq: State,
    pi_integral: State,
    reference: State,
    reference_rate: State,
    actuator_torque: State,
    actuator_torque_rate: State,
    power_flow: Mode,
    power_reversal: Indicator,
    torque_limit: TorqueLimitEvent,
    y_motor_speed: Output,
    y_fan_speed: Output,
    y_shaft_torque: Output,
    y_motor_torque: Output,
    y_current: Output,
    y_power: Output,
    y_reference: Output,
    j_equivalent: Local,
    elements: Elements,
}

/// The drive's elements (Table 3.1) whose powers the equations report; the runtime integrates
/// their activities (eq. 3.3, Table 3.3) and checks that the powers add up.
struct Elements {
    supply: Element,
    winding_inductance: Element,
    winding_resistance: Element,
    motor_torque: Element,
    motor_inertia: Element,
    shaft_stiffness: Element,
    shaft_damping: Element,
    reducer_efficiency: Element,
    fan_inertia: Element,
    aerodynamic_load: Element,
}

impl Elements {
    /// Table 3.1's rows for the cooling-tower fan, in the chapter's order (power supply, motor,
    /// driveshaft, reducer, fan), with the effects the book's models leave out.
    fn declare(d: &mut Declarations) -> Self {
        let table = TorqueSpeedTable::<3>::SOURCE;
        let elements = Elements {
            supply: d.element("voltage_source", "Power supply", InductionMachine::SUPPLY).describe(
                "the grid's voltage source, 3/2 u_sd i_sd (level d, direct start; 0 otherwise: the torque-speed table stands for the motor)",
            ),
            winding_inductance: d.element("winding_inductance", "Motor", InductionMachine::WINDING_INDUCTANCE).describe(
                "the winding inductances, rate of the stator and rotor fluxes' magnetic energy (level d, direct start)",
            ),
            winding_resistance: d.element("winding_resistance", "Motor", InductionMachine::WINDING_RESISTANCE).describe(
                "the stator and rotor winding resistances, 3/2 (R_s |i_s|^2 + R_r |i_r|^2) (level d, direct start)",
            ),
            motor_torque: d.element("motor_torque", "Motor", Effect { what: "motor torque (table or converter)", ..table }).describe(
                "the motor's torque on its shaft, T_m w_m: from the torque-speed table (levels a-c, direct start) or the converter (controlled starts)",
            ),
            motor_inertia: d.element("motor_inertia", "Motor", Effect { what: "rotor inertia", ..Inertia::INERTIA }).describe(
                "the motor inertia, power J_m dw/dt w",
            ),
            shaft_stiffness: d.element("shaft_stiffness", "Driveshaft", TorsionSpring::STIFFNESS).describe(
                "the driveshaft stiffness, power K theta dtheta/dt (elastic shaft)",
            ),
            shaft_damping: d.element("shaft_damping", "Driveshaft", TorsionSpring::DAMPING).describe(
                "the driveshaft's internal damping, power D (dtheta/dt)^2 (elastic shaft)",
            ),
            reducer_efficiency: d.element("reducer_efficiency", "Reducer", Reducer::EFFICIENCY).describe(
                "the reducer's loss, the power in at the high-speed side minus the power out at the fan",
            ),
            fan_inertia: d.element("fan_inertia", "Fan", Effect { what: "blade inertia", ..Inertia::INERTIA }).describe(
                "the fan inertia, power J_fan dw/dt w (low-speed side)",
            ),
            aerodynamic_load: d.element("aerodynamic_load", "Fan", FanLoad::LOAD).describe("the fan's aerodynamic load, power T_fan w_fan"),
        };
        d.element("electromechanical_transformer", "Motor", InductionMachine::TRANSFORMER).describe("the motor's conversion of electrical into mechanical power");
        d.neglected("Motor", Effect { what: "bearing friction", ..components::CoulombFriction::FRICTION }, "the book's torque-speed table is the torque at the shaft, friction included; Chap3_CoolingTowerFan.mo has none");
        d.element("reduction_ratio", "Reducer", Reducer::RATIO).describe("the reducer's ratio N, w_high = N w_low");
        d.neglected("Reducer", Effect { what: "pinion inertia", ..Inertia::INERTIA }, "negligible beside the motor inertia (Figure 3.4)");
        d.neglected("Reducer", Effect { what: "tooth stiffness", ..TorsionSpring::STIFFNESS }, "far stiffer than the driveshaft (Figure 3.4)");
        elements
    }
}

/// The drive train's elements at the current parameter values.
struct Train<R = f64> {
    motor: InductionMachine<R>,
    curve: MotorCurve<R>,
    motor_inertia: Inertia<R>,
    shaft: TorsionSpring<R>,
    reducer: Reducer<R>,
    fan_inertia: Inertia<R>,
    fan: FanLoad<R>,
}

/// Everything the equations give at one instant; derivatives and outputs both read it.
#[derive(Default)]
struct Operating<R = f64> {
    motor_speed: R,
    fan_speed: R,
    shaft_torque: R,
    motor_torque: R,
    current_rms: R,
    electrical_power: R,
    /// The speed set point; 0 for a direct start unless the outputs are computed.
    reference: R,
    motor_acceleration: R,
    fan_acceleration: R,
    twist_rate: R,
    integral_rate: R,
    actuator_rate: R,
    actuator_acceleration: R,
    flux_rates: Fluxes<R>,
    power_motor_inertia: R,
    power_shaft_spring: R,
    power_fan_inertia: R,
    power_supply: R,
    power_winding_inductance: R,
    power_winding_resistance: R,
    power_motor_torque: R,
    power_shaft_damping: R,
    power_reducer_loss: R,
    power_fan_load: R,
}

impl MotorFan {
    fn level<R: Real>(&self, k: &Knowns<R>) -> Level {
        match k[self.level] {
            1 => Level::QuasiStatic,
            2 => Level::Inertias,
            3 => Level::Elastic,
            _ => Level::Electrical,
        }
    }

    fn start<R: Real>(&self, k: &Knowns<R>) -> Start {
        match k[self.start_mode] {
            1 => Start::DirectOnLine,
            2 => Start::PiControl,
            _ => Start::InverseSimulation,
        }
    }

    fn train<R: Real>(&self, k: &Knowns<R>) -> Train<R> {
        Train {
            motor: self.motor.machine(k),
            // Interpolation 0 reads the table as the book's file for the level: Akima at level c
            // (Transient_Resonance), linear at a and b (Steady_State, Transient_Dynamic).
            curve: self.motor.curve(k, self.level(k) >= Level::Elastic),
            motor_inertia: self.motor.rotor(k),
            shaft: self.shaft.spring(k),
            reducer: self.fan.reducer(k),
            fan_inertia: self.fan.inertia(k),
            fan: self.fan.load(k),
        }
    }

    /// The PI's speed error, w_ref - w_m, while the PI drives (controlled start, level b or above).
    fn pi_error<R: Real>(&self, k: &Knowns<R>) -> Option<R> {
        (self.start(k) == Start::PiControl && self.level(k) != Level::QuasiStatic).then(|| self.reference(k).reference - k[self.w_motor])
    }

    /// The speed set point after the optional filter.
    fn reference<R: Real>(&self, k: &Knowns<R>) -> SetPoint<R> {
        SetPoint::at(&self.control, k, k[self.reference], k[self.reference_rate])
    }

    fn fluxes<R: Real>(&self, k: &Knowns<R>) -> Fluxes<R> {
        Fluxes { stator_d: k[self.psi_sd], stator_q: k[self.psi_sq], rotor_d: k[self.psi_rd], rotor_q: k[self.psi_rq] }
    }

    /// The whole drive at the knowns `k`. The converter-fed current (a root search on the
    /// torque curve), and a direct start's set point, only when `with_electrical`: the
    /// derivatives do not need them.
    fn operate<R: Real>(&self, k: &Knowns<R>, with_electrical: bool) -> Operating<R> {
        let train = self.train(k);
        let (level, start) = (self.level(k), self.start(k));
        // The set point drives the PI and the inverse simulation; a direct start only shows
        // it among the outputs.
        let (reference, reference_rate) = if start != Start::DirectOnLine || with_electrical {
            let set_point = self.reference(k);
            (set_point.reference, set_point.rate)
        } else {
            (R::from(0.0), R::from(0.0))
        };
        let mut op = Operating { reference, ..Operating::default() };
        if level == Level::QuasiStatic {
            self.quasi_static(&train, start, &mut op);
            return op;
        }
        let n = train.reducer.ratio;
        let elastic = level >= Level::Elastic && k[self.keep_shaft_stiffness];
        let w_m = if start == Start::InverseSimulation { reference } else { k[self.w_motor] };
        let w_fan = if elastic { k[self.w_fan] } else { w_m / n };
        let fan_torque = train.fan.torque_n_m(w_fan);

        // Motor torque, unless the motor speed is imposed (then it follows from the rest).
        let mut motor_torque = R::from(0.0);
        match start {
            Start::DirectOnLine if level == Level::Electrical => {
                let dq = train.motor.dq_response(self.fluxes(k), w_m);
                motor_torque = dq.torque_n_m;
                op.flux_rates = dq.flux_rates;
                op.power_supply = dq.electrical_power_w;
                op.power_winding_inductance = dq.magnetic_power_w;
                op.power_winding_resistance = dq.winding_loss_w;
                op.current_rms = dq.stator_current_rms_a;
                op.electrical_power = dq.electrical_power_w;
            }
            Start::DirectOnLine if with_electrical => {
                let st = train.curve.steady_state(&train.motor, w_m);
                motor_torque = st.torque_n_m;
                op.current_rms = st.current_rms_a;
                op.electrical_power = st.electrical_power_w;
            }
            Start::DirectOnLine => motor_torque = train.curve.torque_n_m(&train.motor, w_m),
            Start::PiControl => {
                let error = reference - w_m;
                let controller = self.control.controller(k);
                let command = controller.command(error, k[self.pi_integral]);
                op.integral_rate = controller.integral_rate(error, k[self.pi_integral]);
                motor_torque = match self.actuator.lag(k) {
                    // The converter's torque follows the command through its lag.
                    Some(lag) => {
                        let (torque, rate) = (k[self.actuator_torque], k[self.actuator_torque_rate]);
                        op.actuator_rate = rate;
                        op.actuator_acceleration = lag.acceleration(command, torque, rate);
                        torque
                    }
                    None => command,
                };
            }
            Start::InverseSimulation => {}
        }

        if elastic {
            op.twist_rate = w_m - n * w_fan;
            op.shaft_torque = train.shaft.torque_n_m(k[self.twist], op.twist_rate);
            // The power through the reducer is the shaft torque times the reducer's own input
            // speed N w_fan (the motor side swings apart from it by the twist rate).
            let low_torque = train.reducer.low_side_torque_flowing_n_m(op.shaft_torque, k[self.power_flow] >= 0);
            op.fan_acceleration = train.fan_inertia.acceleration_rad_per_s2(low_torque - fan_torque);
            if start == Start::InverseSimulation {
                op.motor_acceleration = reference_rate;
                motor_torque = train.motor_inertia.inertia_kg_m2 * reference_rate + op.shaft_torque;
            } else {
                op.motor_acceleration = train.motor_inertia.acceleration_rad_per_s2(motor_torque - op.shaft_torque);
            }
            op.power_shaft_spring = train.shaft.spring_power_w(k[self.twist], op.twist_rate);
            op.power_shaft_damping = train.shaft.damper_power_w(op.twist_rate);
            op.power_reducer_loss = train.reducer.loss_flowing_w(op.shaft_torque, n * w_fan, k[self.power_flow] >= 0);
        } else {
            // Rigid shaft: motor and fan accelerate together (w_fan = w_m / N).
            let acceleration = if start == Start::InverseSimulation {
                reference_rate
            } else {
                rigid_acceleration(&train, motor_torque, w_m, fan_torque)
            };
            let low_torque = train.fan_inertia.inertia_kg_m2 * acceleration / n + fan_torque;
            op.shaft_torque = train.reducer.high_side_torque_n_m(low_torque, w_m);
            if start == Start::InverseSimulation {
                motor_torque = train.motor_inertia.inertia_kg_m2 * acceleration + op.shaft_torque;
            }
            op.motor_acceleration = acceleration;
            op.fan_acceleration = acceleration / n;
            op.power_reducer_loss = train.reducer.loss_w(op.shaft_torque, w_m);
        }
        if start != Start::DirectOnLine && with_electrical {
            self.converter_fed(&train, motor_torque, w_m, &mut op);
        }
        op.motor_speed = w_m;
        op.fan_speed = w_fan;
        op.motor_torque = motor_torque;
        op.power_motor_inertia = train.motor_inertia.power_w(op.motor_acceleration, w_m);
        op.power_fan_inertia = train.fan_inertia.power_w(op.fan_acceleration, w_fan);
        op.power_fan_load = fan_torque * w_fan;
        // The motor's torque is the source unless the dq model's supply is (level d, direct start).
        if !(start == Start::DirectOnLine && level == Level::Electrical) {
            op.power_motor_torque = motor_torque * w_m;
        }
        op
    }

    /// Each element's power at this instant (the runtime integrates the activities and sums the
    /// balance: supply + motor torque = stored + dissipated).
    fn report_powers<R: Real>(&self, op: &Operating<R>, der: &mut Derivatives<R>) {
        let e = &self.elements;
        der.power(e.supply, op.power_supply);
        der.power(e.winding_inductance, op.power_winding_inductance);
        der.power(e.winding_resistance, op.power_winding_resistance);
        der.power(e.motor_torque, op.power_motor_torque);
        der.power(e.motor_inertia, op.power_motor_inertia);
        der.power(e.shaft_stiffness, op.power_shaft_spring);
        der.power(e.shaft_damping, op.power_shaft_damping);
        der.power(e.reducer_efficiency, op.power_reducer_loss);
        der.power(e.fan_inertia, op.power_fan_inertia);
        der.power(e.aerodynamic_load, op.power_fan_load);
    }

    /// Level a: no storage; the speed is the torque balance (direct start) or the set point.
    fn quasi_static<R: Real>(&self, train: &Train<R>, start: Start, op: &mut Operating<R>) {
        let load_on_motor = |w: R| train.reducer.high_side_torque_n_m(train.fan.torque_n_m(train.reducer.low_speed(w)), w);
        let w_m = match start {
            Start::DirectOnLine => train.curve.stable_speed_rad_per_s(&train.motor, load_on_motor).unwrap_or(R::from(0.0)),
            _ => op.reference,
        };
        op.motor_speed = w_m;
        op.fan_speed = train.reducer.low_speed(w_m);
        op.shaft_torque = load_on_motor(w_m);
        op.motor_torque = op.shaft_torque;
        op.power_motor_torque = op.motor_torque * w_m;
        op.power_reducer_loss = train.reducer.loss_w(op.shaft_torque, w_m);
        op.power_fan_load = train.fan.torque_n_m(op.fan_speed) * op.fan_speed;
        if start == Start::DirectOnLine {
            let st = train.curve.steady_state(&train.motor, w_m);
            op.current_rms = st.current_rms_a;
            op.electrical_power = st.electrical_power_w;
        } else {
            self.converter_fed(train, op.motor_torque, w_m, op);
        }
    }

    /// With an elastic shaft (levels c and d): the power into the reducer, P = T_shaft N w_fan,
    /// and its rate dP/dt = (K dtheta/dt + D d2theta/dt2) N w_fan + T_shaft N dw_fan/dt. None
    /// otherwise.
    fn reducer_power(&self, k: &Knowns) -> Option<(f64, f64)> {
        if self.level(k) < Level::Elastic || !k[self.keep_shaft_stiffness] {
            return None;
        }
        let op = self.operate(k, false);
        let (spring, n) = (self.shaft.spring(k), self.fan.reducer(k).ratio);
        let speed = n * op.fan_speed;
        let twist_acceleration = op.motor_acceleration - n * op.fan_acceleration;
        let torque_rate = spring.stiffness_n_m_per_rad * op.twist_rate + spring.damping_n_m_s_per_rad * twist_acceleration;
        Some((op.shaft_torque * speed, torque_rate * speed + op.shaft_torque * n * op.fan_acceleration))
    }

    fn converter_fed<R: Real>(&self, train: &Train<R>, torque: R, speed: R, op: &mut Operating<R>) {
        (op.current_rms, op.electrical_power) = converter_fed(&train.motor, torque, speed);
    }
}

/// Rigid coupling: J_m a + T_shaft = T_m and T_shaft delivers J_fan a / N + T_fan through the
/// reducer, whose efficiency depends on the direction of the power.
fn rigid_acceleration<R: Real>(train: &Train<R>, motor_torque: R, w_m: R, fan_torque: R) -> R {
    let (n, eta, j_m, j_fan) = (train.reducer.ratio, train.reducer.efficiency, train.motor_inertia.inertia_kg_m2, train.fan_inertia.inertia_kg_m2);
    let forward = (motor_torque - fan_torque / (n * eta)) / (j_m + j_fan / (n * n * eta));
    if (j_fan * forward / n + fan_torque) * w_m >= 0.0 {
        forward
    } else {
        (motor_torque - fan_torque * eta / n) / (j_m + j_fan * eta / (n * n))
    }
}

impl Model for MotorFan {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "MotorFan",
            description: "Start-up of a cooling-tower fan: induction motor, driveshaft, reducer and fan at the modelling levels a-d of chapter 3 (Figure 3.5), direct-on-line or at variable speed (PI or inverse simulation), with activity indices",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 30.0, step_size: 1e-3 },
            solver: Solver::ExplicitRungeKutta,
            documentation: documentation::HTML,
        }
    }

    /// Measured (tests/python/accuracy_table.py, rtol 1e-3..1e-8 against 1e-10): the explicit
    /// solver's steps in the settled run are limited by the motor's stiff slip mode (eigenvalue
    /// -155 /s at 20 s, h = 22.6 ms: h lambda = -3.50 against the method's stability boundary
    /// -3.507), and the step-size controller's cycling leaves a speed ripple proportional to the
    /// tolerance, which the activities integrate: errors about 2600 x rtol of their range
    /// (2.6e-3 at 1e-6). At 1e-11 every output is within 2.7e-8 of its range (against 1e-13),
    /// under 10 x 1e-8, for about twice the solver steps of 1e-8 (3555 against 1849 in 30 s).
    /// (The PI start with a step set point chattered at this tolerance while its anti-windup
    /// switched the integral's rate on and off; it now tracks: `components::PiController`.)
    /// Those figures are the first set's. With the book's defaults the elastic shaft rings
    /// through 54 sign changes of its torque in the run-up, and the shaft activity, an integral
    /// of |K theta dtheta/dt| whose kinks no event marks, kept 1.35e-7 of its range at 1e-11
    /// (beyond 10 x 1e-8); at 1e-12 every output is within 7.2e-9 of its range (against 1e-14).
    /// The default experiment's wall time in fmpy is the same to 0.05 s (1.5 s, fmpy's own cost).
    ///
    /// The PI start through the torque actuator's lag needs no floor, and is hurt by one (a
    /// build without a floor, every level and shaft, with and without the set-point filter and
    /// the torque limit, fmpy at 1 ms, 30 s, 2026-12-04): against a run at 1e-11, every output
    /// of the runs at 1e-4 to 1e-10 is within 0.006-1.4 x rtol of its range (the rule is 10 x),
    /// and runs at 1e-7 to 1e-11 agree within 7.2e-10 of it. Tighter, round-off decides: the
    /// actuator's acceleration is its 5024 rad/s lag squared times the PI's command, itself the
    /// gain times a speed difference of near-equal numbers, and at 1e-12 the rate's absolute
    /// tolerance (5e-9 N m/s) is below that noise times a step, so the steps shrink to
    /// microseconds: 16 s for the 30 s run at 1e-12 (553 us a doStep) against 0.6 s at 1e-10,
    /// and the shaft activity drifts 1.2e-9 of its range from the looser runs (1.2e-8 at 1e-13).
    /// Without the lag (`actuator_angular_frequency` = 0) the motor torque is the PI's gain
    /// times the speed's integration error: 6.4e-5 of its range at 1e-8, linear in rtol, so
    /// that start keeps the floor, as do the direct start and the imposed speed (the elastic
    /// shaft's activity 150-450 x rtol at every rtol).
    fn tolerance_floor(&self, k: &Knowns) -> Option<f64> {
        let through_actuator_lag = self.start(k) == Start::PiControl && self.actuator.lag(k).is_some();
        (!through_actuator_lag).then_some(1e-12)
    }

    fn declare(d: &mut Declarations) -> Self {
        MotorFan {
            level: d.integer_parameter("level", 3).choices(1, &[("a", "quasi-static"), ("b", "a + inertias"), ("c", "b + driveshaft elasticity"), ("d", "c + electrical dynamics")]).describe("Modelling level (Figure 3.5): 1 = a quasi-static, 2 = b + inertias, 3 = c + driveshaft elasticity, 4 = d + electrical dynamics"),
            start_mode: d.integer_parameter("start_mode", 1).choices(1, &[("direct_on_line", "direct on line"), ("speed_control", "PI speed control"), ("imposed_speed", "inverse simulation (imposed speed)")]).describe("1 = direct on line, 2 = PI speed control, 3 = inverse simulation (imposed speed), Figure 3.7"),
            keep_shaft_stiffness: d.boolean_parameter("keep_shaft_stiffness", true).describe("false: rigid driveshaft at levels c and d (the reduced model of Figure 3.10)"),
            motor: MotorParameters::declare(d),
            shaft: ShaftParameters::declare(d),
            fan: FanParameters::declare(d),
            control: ControllerParameters::declare(d),
            actuator: TorqueActuatorParameters::declare(d),
            w_motor: d.state("w_motor", 0.0, "rad/s").nominal(100.0).describe("Motor speed (frozen at level a)"),
            twist: d.state("shaft_twist", 0.0, "rad").describe("Driveshaft twist (frozen unless the shaft is elastic)"),
            w_fan: d.state("w_fan", 0.0, "rad/s").nominal(10.0).describe("Fan speed, low-speed side (follows w_motor/N when the shaft is rigid)"),
            psi_sd: d.state("psi_sd", 0.0, "Wb").describe("Stator flux, d axis (level d, direct start; frozen otherwise)"),
            psi_sq: d.state("psi_sq", 0.0, "Wb").describe("Stator flux, q axis (level d, direct start; frozen otherwise)"),
            psi_rd: d.state("psi_rd", 0.0, "Wb").describe("Rotor flux, d axis (level d, direct start; frozen otherwise)"),
            psi_rq: d.state("psi_rq", 0.0, "Wb").describe("Rotor flux, q axis (level d, direct start; frozen otherwise)"),
            pi_integral: d.state("pi_integral", 0.0, "rad").nominal(10.0).describe("Integral of the speed error (PI start; frozen otherwise)"),
            reference: d.state("reference_filtered", 0.0, "rad/s").nominal(100.0).describe("Filtered speed set point (filter on; frozen otherwise)"),
            reference_rate: d.state("reference_filtered_rate", 0.0, "rad/s2").nominal(10.0).describe("Rate of the filtered speed set point"),
            actuator_torque: d.state("actuator_torque", 0.0, "N.m").nominal(1000.0).describe("Torque actuator output, the motor torque of the PI start (actuator lag on; frozen otherwise)"),
            actuator_torque_rate: d.state("actuator_torque_rate", 0.0, "N.m/s").nominal(5e6).describe("Rate of the torque actuator output (nominal: the rate a 1000 N m command step starts through the 5024 rad/s lag; a smaller one made its absolute tolerance so tight that the solver steps shrank to microseconds)"),
            power_flow: d.mode("reducer_power_flow", 1).range(-1, 1).describe(
                "Direction of the power through the reducer with an elastic shaft: 1 towards the fan (efficiency eta), -1 back (1/eta)",
            ),
            power_reversal: d.event_indicator(
                "reducer_power_reversal",
                "the power through the reducer, T_shaft N w_fan, signed positive while reducer_power_flow holds (elastic shaft only)",
            ),
            torque_limit: TorqueLimitEvent::declare(d),
            y_motor_speed: d.output("motor_speed", "rad/s").describe("Motor speed (high-speed axis)"),
            y_fan_speed: d.output("fan_speed", "rad/s").describe("Fan speed (low-speed axis)"),
            y_shaft_torque: d.output("shaft_torque", "N.m").describe("Driveshaft torque on the high-speed axis of the reducer (Figure 3.6)"),
            y_motor_torque: d.output("motor_torque", "N.m").describe("Electromagnetic torque of the motor"),
            y_current: d.output("stator_current_rms", "A").describe("Stator phase current, rms"),
            y_power: d.output("electrical_power", "W").describe("Active power drawn (controlled starts: mechanical power through an ideal converter)"),
            y_reference: d.output("speed_reference", "rad/s").describe("Speed set point after the filter"),
            j_equivalent: d.calculated_parameter("J_fan_equivalent", "kg.m2").describe("Fan inertia referred to the high-speed axis, J_fan / N^2 (eq. 3.6; 11.72 in the chapter)"),
            elements: Elements::declare(d),
        }
    }

    fn check(&self, k: &Knowns) -> Result<(), String> {
        self.motor.check(k)?;
        if self.start(k) == Start::InverseSimulation && self.control.ramp_time(k) == 0.0 && self.control.filter(k).is_none() {
            return Err("inverse simulation imposes the motor speed, so the set point must have a finite acceleration: \
                        set ramp_time > 0 or a setpoint_filter"
                .into());
        }
        Ok(())
    }

    /// The set-point ramp's kinks, when a controlled start follows it.
    fn next_time_event(&self, k: &Knowns, after: f64) -> Option<f64> {
        if self.start(k) == Start::DirectOnLine {
            return None;
        }
        self.control.ramp(k).next_kink(after)
    }

    /// The reducer's efficiency switches where the power through it reverses: with an elastic
    /// shaft that is where the shaft torque changes sign (4 times in the direct start's run-up),
    /// a state event, so that the solver never steps across the kink.
    fn event_indicators(&self, k: &Knowns, z: &mut EventIndicators) {
        z[self.power_reversal] = match self.reducer_power(k) {
            Some((power, _)) => f64::from(k[self.power_flow].signum()) * power,
            None => 1.0, // rigid shaft or level a: the power's direction is solved for, no event
        };
        match self.pi_error(k) {
            Some(error) => self.torque_limit.indicator(k, &self.control.controller(k), error, k[self.pi_integral], z),
            None => self.torque_limit.idle(z),
        }
    }

    fn update_modes(&self, k: &Knowns, next: &mut ModeUpdate) {
        if let Some((power, rate)) = self.reducer_power(k) {
            next[self.power_flow] = self.fan.reducer(k).next_power_flow(k[self.power_flow], power, rate);
        }
        if let Some(error) = self.pi_error(k) {
            let error_rate = self.reference(k).rate - self.operate(k, false).motor_acceleration;
            self.torque_limit.update(k, next, &self.control.controller(k), error, error_rate, k[self.pi_integral]);
        }
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        if self.control.filter(k).is_some() {
            let set_point = self.reference(k);
            der[self.reference] = set_point.rate;
            der[self.reference_rate] = set_point.acceleration;
        }
        let op = self.operate(k, false);
        self.report_powers(&op, der);
        if self.level(k) == Level::QuasiStatic {
            return;
        }
        der[self.w_motor] = op.motor_acceleration;
        der[self.twist] = op.twist_rate;
        der[self.w_fan] = op.fan_acceleration;
        der[self.psi_sd] = op.flux_rates.stator_d;
        der[self.psi_sq] = op.flux_rates.stator_q;
        der[self.psi_rd] = op.flux_rates.rotor_d;
        der[self.psi_rq] = op.flux_rates.rotor_q;
        der[self.pi_integral] = op.integral_rate;
        der[self.actuator_torque] = op.actuator_rate;
        der[self.actuator_torque_rate] = op.actuator_acceleration;
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        let op = self.operate(k, true);
        out[self.y_motor_speed] = op.motor_speed;
        out[self.y_fan_speed] = op.fan_speed;
        out[self.y_shaft_torque] = op.shaft_torque;
        out[self.y_motor_torque] = op.motor_torque;
        out[self.y_current] = op.current_rms;
        out[self.y_power] = op.electrical_power;
        out[self.y_reference] = op.reference;
        out[self.j_equivalent] = self.fan.referred_inertia_kg_m2(k);
    }
}

fmu_runtime::export_fmu!(MotorFan);

/// The drive train's powers add up (the chapter's eq. 3.3 powers, summed over the elements of
/// Table 3.1): at any state, the motor's power T_m w_m equals the rates of the stored energies
/// (motor inertia J_m a_m w_m, shaft spring K theta theta', fan inertia J_fan a_fan w_fan) plus
/// the dissipated powers (shaft damper D theta'^2, the reducer's loss from `Reducer::loss_w`, the
/// fan's aerodynamic load T_fan w_fan). Each power is taken from its own element, not from the
/// equations being checked, so a sign slip or a torque left out of one equation shows here.
#[cfg(test)]
mod power_balance {
    use super::*;
    use fmu_runtime::values::Values;
    use fmu_runtime::variables::VariableTable;
    use fmu_runtime::testing::{calculated, set, spread};

    /// (source - storage - dissipation, the largest of the terms) at one state. `damper`: whether
    /// the damper's power is counted (false: the deliberately broken balance).
    fn balance(model: &MotorFan, values: &Values, states: &[f64], t: f64, damper: bool) -> (f64, f64) {
        let k = Knowns::new(t, &values.known, states, &values.integers, &values.booleans);
        let op = model.operate(&k, false);
        let train = model.train(&k);
        let n = train.reducer.ratio;
        let source = op.motor_torque * op.motor_speed;
        let stored = [op.power_motor_inertia, op.power_shaft_spring, op.power_fan_inertia];
        let mut dissipated = vec![train.reducer.loss_w(op.shaft_torque, n * op.fan_speed), train.fan.torque_n_m(op.fan_speed) * op.fan_speed];
        if damper {
            dissipated.push(train.shaft.damper_power_w(op.twist_rate));
        }
        let residual = source - stored.iter().sum::<f64>() - dissipated.iter().sum::<f64>();
        let scale = std::iter::once(source).chain(stored).chain(dissipated).fold(0.0f64, |m, p| m.max(p.abs()));
        (residual, scale)
    }

    /// Random states (speeds forward, as in every start) at levels b and c, each start mode;
    /// with an elastic shaft the power-flow mode is set to the direction of the power there.
    #[test]
    fn the_powers_of_levels_b_and_c_add_up_and_a_missing_damper_shows() {
        let (model, _, table) = fmu_runtime::model::declare::<MotorFan>();
        let mut worst = 0.0f64;
        let mut missing_damper_seen = 0.0f64;
        let mut r = spread(100_000);
        let mut next = move || r.next().unwrap();
        for level in [2.0, 3.0] {
            for start in [1.0, 2.0, 3.0] {
                for _ in 0..200 {
                    let mut values = table.start_values();
                    set(&table, &mut values, "level", level);
                    set(&table, &mut values, "start_mode", start);
                    let mut states = vec![0.0; table.n_states];
                    let mut state = |name: &str, v: f64| {
                        let var = table.by_name(name).unwrap();
                        states[table.state_index(var).unwrap()] = v;
                    };
                    let w_m = 320.0 * next();
                    state("w_motor", w_m);
                    state("w_fan", w_m / 16.0 * (0.9 + 0.2 * next()));
                    state("shaft_twist", 10.0 * (next() - 0.5));
                    state("pi_integral", 0.02 * (next() - 0.5));
                    state("reference_filtered", 300.0 * next());
                    state("reference_filtered_rate", 60.0 * (next() - 0.5));
                    state("actuator_torque", 2000.0 * next());
                    state("actuator_torque_rate", 1e5 * (next() - 0.5));
                    let t = 30.0 * next();
                    // The elastic shaft's power-flow mode: the direction of T_shaft N w_fan here.
                    let (k_shaft, d_shaft) = (values.known[slot(&table, "K_shaft")], values.known[slot(&table, "D_shaft")]);
                    let get = |name: &str| states[table.state_index(table.by_name(name).unwrap()).unwrap()];
                    let torque = k_shaft * get("shaft_twist") + d_shaft * (get("w_motor") - 16.0 * get("w_fan"));
                    set(&table, &mut values, "reducer_power_flow", if torque * get("w_fan") >= 0.0 { 1.0 } else { -1.0 });
                    let (residual, scale) = balance(&model, &values, &states, t, true);
                    worst = worst.max(residual.abs() / scale);
                    if level == 3.0 {
                        let (broken, scale) = balance(&model, &values, &states, t, false);
                        missing_damper_seen = missing_damper_seen.max(broken.abs() / scale);
                    }
                }
            }
        }
        println!("1200 states at levels b and c, every start mode: worst residual {worst:.3e} of the largest power; without the damper's power up to {missing_damper_seen:.3e}");
        assert!(worst <= 1e-12, "the powers do not add up: worst residual {worst:.3e} of the largest power");
        assert!(missing_damper_seen > 1e-6, "leaving the damper out went unseen ({missing_damper_seen:.3e})");
    }

    /// The runtime's own balance output (`power_balance_relative`, from every element's reported
    /// power) at random states of every level, start mode and shaft choice: rounding only. At
    /// level d the direct start runs the dq model (supply, windings, transformer).
    #[test]
    fn the_runtime_balance_holds_at_every_level_and_start() {
        let (model, _, table) = fmu_runtime::model::declare::<MotorFan>();
        let relative = calculated(&table, "power_balance_relative");
        let mut r = spread(100_000);
        let mut next = move || r.next().unwrap();
        let mut worst = 0.0f64;
        for level in [1.0, 2.0, 3.0, 4.0] {
            for start in [1.0, 2.0, 3.0] {
                for keep in [1.0, 0.0] {
                    for _ in 0..50 {
                        let mut values = table.start_values();
                        set(&table, &mut values, "level", level);
                        set(&table, &mut values, "start_mode", start);
                        set(&table, &mut values, "keep_shaft_stiffness", keep);
                        let mut states = vec![0.0; table.n_states];
                        for (name, v) in [
                            ("w_motor", 320.0 * next()),
                            ("shaft_twist", 10.0 * (next() - 0.5)),
                            ("psi_sd", 2.0 * (next() - 0.5)),
                            ("psi_sq", 2.0 * (next() - 0.5)),
                            ("psi_rd", 2.0 * (next() - 0.5)),
                            ("psi_rq", 2.0 * (next() - 0.5)),
                            ("pi_integral", 0.02 * (next() - 0.5)),
                            ("reference_filtered", 300.0 * next()),
                            ("reference_filtered_rate", 60.0 * (next() - 0.5)),
                            ("actuator_torque", 2000.0 * next()),
                            ("actuator_torque_rate", 1e5 * (next() - 0.5)),
                        ] {
                            states[table.state_index(table.by_name(name).unwrap()).unwrap()] = v;
                        }
                        let w_m = states[table.state_index(table.by_name("w_motor").unwrap()).unwrap()];
                        states[table.state_index(table.by_name("w_fan").unwrap()).unwrap()] = w_m / 16.0 * (0.9 + 0.2 * next());
                        // The power-flow mode as the event update would leave it: the direction of the
                        // power into the reducer at this state.
                        let (k, d) = (values.known[slot(&table, "K_shaft")], values.known[slot(&table, "D_shaft")]);
                        let get = |name: &str| states[table.state_index(table.by_name(name).unwrap()).unwrap()];
                        let torque = k * get("shaft_twist") + d * (get("w_motor") - 16.0 * get("w_fan"));
                        set(&table, &mut values, "reducer_power_flow", if torque * get("w_fan") >= 0.0 { 1.0 } else { -1.0 });
                        let (mut der, mut calc) = (vec![0.0; table.n_states], values.calculated.clone());
                        fmu_runtime::model::evaluate(&model, &table, 30.0 * next(), &values.known, &states, &values.integers, &values.booleans, &mut der, &mut calc);
                        worst = worst.max(calc[relative].abs());
                    }
                }
            }
        }
        println!("1200 states at levels a-d, every start and shaft: worst power_balance_relative {worst:.3e}");
        assert!(worst <= 1e-12, "worst power_balance_relative {worst:.3e}");
    }

    fn slot(table: &VariableTable, name: &str) -> usize {
        match table.by_name(name).unwrap().slot {
            fmu_runtime::variables::Slot::Known(i) => i,
            other => panic!("{name}: {other:?}"),
        }
    }
}
