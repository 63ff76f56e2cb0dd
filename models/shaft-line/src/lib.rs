//! ShaftLine: the short circuit of a submarine's DC propulsion motor (chapter section 3.5.3,
//! Figures 3.29-3.30, Table 3.8). The motor drives the propeller through a hollow shaft; a seal
//! where the shaft leaves the hull rubs on it (Coulomb friction that sticks and slips); bearings
//! lose a little viscously. The supply ramps 0 -> U_max in 200 s, holds 200 s, and is
//! short-circuited (0 V) at t = 400 s: the question is the maximal transient shaft torque and its
//! ratio to the rated torque, then which elements make it (activity, eq. 3.3). The contract:
//! `docs/shaft-line-spec.md`.
//!
//! Table 3.8 gives values without names; our reading (the spec explains each):
//! * 1.75e5 N m, 120 rpm, 700 V: the motor's rated torque, speed and armature voltage (= U_max).
//! * 8 mOhm, 20 mH: armature resistance and inductance (eq. 3.9's circuit; L/R = 2.5 s).
//! * 3e3 kg m2 and 10 N m/(rad/s): motor rotor inertia and its bearings' viscous friction.
//! * 150e3 kg m2: propeller inertia (with entrained water).
//! * 6.5e6 N m/rad, 20 kg m2, 25 000 N m/(rad/s): the hollow shaft's torsional stiffness, inertia
//!   (half lumped on each end) and internal damping (9 % of critical for its 7.5 Hz mode; as a
//!   bearing loss it would absorb 3.1e5 N m at 120 rpm, 1.8x the rated torque: impossible).
//! * 9000 N m: the seal's friction torque (Coulomb and static alike).
//! * 45 t, 6 m, 41 t, 25 cm, 4.5 m: masses and dimensions (motor and propeller masses, propeller
//!   diameter, shaft diameter and length) that the torsional model does not use; the shaft's
//!   stiffness and inertia agree with a steel shaft of that size (J = rho L^2 K / G = 13-23 kg m2).
//!
//! Derived: k from the rated point (eq. 3.9, E = U - R I, k = E/w = C/I: 53.63 V s/rad, 3263 A),
//! propeller a = T_rated / w_rated^2 = 1108 N m s2/rad2.

use components::activity::activity_rate;
use components::{CoulombFriction, DcMachine, Inertia, PropellerLoad, SpeedRamp, TorsionSpring};
use fmu_runtime::prelude::*;
use fmu_runtime::variables::number;

mod documentation;

/// The elements whose activity (eq. 3.3) the FMU integrates, in output order.
const ELEMENTS: [&str; 9] = [
    "armature_resistance",
    "armature_inductance",
    "motor_inertia",
    "motor_bearings",
    "shaft_stiffness",
    "shaft_damping",
    "propeller_inertia",
    "seal_friction",
    "propeller_load",
];

pub struct ShaftLine {
    model_reduction: IntegerParameter,
    voltage_from_input: BooleanParameter,
    t_rated: Parameter,
    speed_rated: Parameter,
    u_rated: Parameter,
    u_max: Parameter,
    r_armature: Parameter,
    l_armature: Parameter,
    j_motor: Parameter,
    b_bearings: Parameter,
    j_propeller: Parameter,
    k_shaft: Parameter,
    j_shaft: Parameter,
    d_shaft: Parameter,
    t_seal_coulomb: Parameter,
    t_seal_static: Parameter,
    ramp_time: Parameter,
    plateau_time: Parameter,
    u_in: Input,
    current: State,
    w_motor: State,
    twist: State,
    w_propeller: State,
    activities: [State; 9],
    seal_mode: Mode,
    seal: Indicator,
    y_voltage: Output,
    y_current: Output,
    y_motor_torque: Output,
    y_motor_speed: Output,
    y_propeller_speed: Output,
    y_shaft_torque: Output,
    y_shaft_torque_ratio: Output,
    y_propeller_torque: Output,
    y_seal_torque: Output,
    y_activities: [Output; 9],
    k_machine: Local,
    a_propeller: Local,
    i_rated: Local,
    j_motor_side: Local,
    j_propeller_side: Local,
    f_shaft: Local,
}

/// The elements at the current parameter values.
struct Line {
    machine: DcMachine,
    motor: Inertia,
    bearings_n_m_s_per_rad: f64,
    shaft: TorsionSpring,
    propeller: Inertia,
    load: PropellerLoad,
    seal: CoulombFriction,
}

/// Everything the equations give at one instant.
#[derive(Default)]
struct Operating {
    voltage: f64,
    current_rate: f64,
    motor_torque: f64,
    motor_speed: f64,
    motor_acceleration: f64,
    twist_rate: f64,
    shaft_torque: f64,
    propeller_speed: f64,
    propeller_acceleration: f64,
    propeller_torque: f64,
    seal_torque: f64,
    /// |power| of each element of `ELEMENTS`, W.
    powers: [f64; 9],
}

impl ShaftLine {
    fn reduced(&self, k: &Knowns) -> bool {
        k[self.model_reduction] == 1
    }

    fn machine_constant(&self, k: &Knowns) -> f64 {
        // check() refuses an impossible rating at initialization; NaN only while probing.
        DcMachine::constant_from_rated_point(k[self.u_rated], k[self.t_rated], k[self.speed_rated], k[self.r_armature]).unwrap_or(f64::NAN)
    }

    fn line(&self, k: &Knowns) -> Line {
        let half_shaft = 0.5 * k[self.j_shaft];
        Line {
            machine: DcMachine {
                resistance_ohm: k[self.r_armature],
                inductance_h: k[self.l_armature],
                constant_v_s_per_rad: self.machine_constant(k),
            },
            motor: Inertia { inertia_kg_m2: k[self.j_motor] + half_shaft },
            bearings_n_m_s_per_rad: k[self.b_bearings],
            shaft: TorsionSpring { stiffness_n_m_per_rad: k[self.k_shaft], damping_n_m_s_per_rad: k[self.d_shaft] },
            propeller: Inertia { inertia_kg_m2: k[self.j_propeller] + half_shaft },
            load: PropellerLoad { coefficient_n_m_s2_per_rad2: k[self.t_rated] / (k[self.speed_rated] * k[self.speed_rated]) },
            seal: CoulombFriction { coulomb_n_m: k[self.t_seal_coulomb], static_n_m: k[self.t_seal_static] },
        }
    }

    /// The supply: 0 -> U_max over ramp_time, U_max for plateau_time, then short-circuited.
    fn voltage(&self, k: &Knowns) -> f64 {
        if k[self.voltage_from_input] {
            return k[self.u_in];
        }
        if k.time() >= self.short_circuit_time(k) {
            0.0
        } else {
            SpeedRamp { target: k[self.u_max], duration_s: k[self.ramp_time] }.value(k.time())
        }
    }

    fn short_circuit_time(&self, k: &Knowns) -> f64 {
        k[self.ramp_time] + k[self.plateau_time]
    }

    /// The torque the seal must take to hold the propeller still: every other torque on it.
    fn seal_required(&self, line: &Line, k: &Knowns) -> f64 {
        let w_p = k[self.w_propeller];
        line.shaft.torque_n_m(k[self.twist], k[self.w_motor] - w_p) - line.load.torque_n_m(w_p)
    }

    fn operate(&self, k: &Knowns) -> Operating {
        let line = self.line(k);
        let m = &line.machine;
        let voltage = self.voltage(k);
        let i = k[self.current];
        let motor_torque = m.torque_n_m(i);
        let mut op = Operating { voltage, motor_torque, ..Operating::default() };
        if self.reduced(k) {
            // Rigid shaft, massless motor rotor, no bearings, no seal: L di/dt = U - R i - k w,
            // J_p dw/dt = k i - a w |w|; the shaft carries the motor torque.
            let w = k[self.w_propeller];
            let current_rate = m.current_rate_a_per_s(voltage, i, w);
            op.current_rate = current_rate;
            op.motor_speed = w;
            op.propeller_speed = w;
            op.propeller_torque = line.load.torque_n_m(w);
            op.shaft_torque = motor_torque;
            op.propeller_acceleration = line.propeller.acceleration_rad_per_s2(motor_torque - op.propeller_torque);
            op.motor_acceleration = op.propeller_acceleration;
            op.powers[0] = m.resistance_power_w(i);
            op.powers[1] = m.inductance_power_w(current_rate, i);
            op.powers[6] = line.propeller.power_w(op.propeller_acceleration, w);
            op.powers[8] = op.propeller_torque * w;
            return op;
        }
        let (w_m, w_p, twist) = (k[self.w_motor], k[self.w_propeller], k[self.twist]);
        op.current_rate = m.current_rate_a_per_s(voltage, i, w_m);
        op.motor_speed = w_m;
        op.propeller_speed = w_p;
        op.twist_rate = w_m - w_p;
        op.shaft_torque = line.shaft.torque_n_m(twist, op.twist_rate);
        let bearings = line.bearings_n_m_s_per_rad * w_m;
        op.motor_acceleration = line.motor.acceleration_rad_per_s2(motor_torque - bearings - op.shaft_torque);
        op.propeller_torque = line.load.torque_n_m(w_p);
        let mode = k[self.seal_mode];
        if mode == 0 {
            // Stuck: the propeller stands still, the seal takes what holding it requires.
            op.seal_torque = -self.seal_required(&line, k);
            op.propeller_acceleration = 0.0;
        } else {
            op.seal_torque = line.seal.slip_torque_n_m(mode);
            op.propeller_acceleration = line.propeller.acceleration_rad_per_s2(op.shaft_torque - op.propeller_torque + op.seal_torque);
        }
        op.powers = [
            m.resistance_power_w(i),
            m.inductance_power_w(op.current_rate, i),
            line.motor.power_w(op.motor_acceleration, w_m),
            bearings * w_m,
            line.shaft.spring_power_w(twist, op.twist_rate),
            line.shaft.damper_power_w(op.twist_rate),
            line.propeller.power_w(op.propeller_acceleration, w_p),
            line.seal.power_w(mode, w_p),
            op.propeller_torque * w_p,
        ];
        op
    }
}

impl Model for ShaftLine {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "ShaftLine",
            description: "Short circuit of a submarine's DC propulsion motor (chapter 3, section 3.5.3, Table 3.8): DC machine, hollow shaft, seal with stick/slip friction, bearings and propeller, with activity indices for model reduction",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 600.0, step_size: 0.01 },
            // The fastest mode is the shaft's 7.5 Hz (47 rad/s), the electrical L/R = 2.5 s: not
            // stiff, and the ringing after the short circuit needs steps of a few ms for accuracy
            // anyway, so the explicit method is cheaper than an implicit one.
            solver: Solver::ExplicitRungeKutta,
            documentation: documentation::HTML,
        }
    }

    /// Measured (tests/python/accuracy_table.py): the shaft mode -4.2 +/- 46.8i /s holds the
    /// explicit solver near its stability limit along that ray (steps of 56.6 ms against 58 ms)
    /// in the 700 V plateau, errors 1600-1900 x rtol of the activities' ranges; at 1e-11 within
    /// 1.5e-8 (17 988 solver steps against 11 972 at 1e-8).
    fn tolerance_floor() -> Option<f64> {
        Some(1e-11)
    }

    fn declare(d: &mut Declarations) -> Self {
        let activity_state = |d: &mut Declarations, name: &str| {
            d.state(&format!("A_{name}"), 0.0, "J").describe(&format!("Activity of the {} (eq. 3.3), integral of |power| dt", name.replace('_', " ")))
        };
        let activity_output = |d: &mut Declarations, name: &str| {
            d.output(&format!("activity_{name}"), "J").describe(&format!("Activity of the {} since t = 0 (eq. 3.3, integral of |power| dt)", name.replace('_', " ")))
        };
        ShaftLine {
            model_reduction: d.integer_parameter("model_reduction", 0).range(0, 1).describe(
                "0 = the full model; 1 = the reduced model keeping only the elements with at least 95 % of the short-circuit activity \
                 (armature R and L, propeller inertia and load: rigid shaft, massless motor rotor, no bearings, no seal)",
            ),
            voltage_from_input: d.boolean_parameter("voltage_from_input", false).describe(
                "false: the built-in supply profile (ramp, plateau, short circuit); true: the supply voltage is the input U_supply_in",
            ),
            t_rated: d.parameter("T_rated", 1.75e5, "N.m").positive().describe("Rated motor torque (Table 3.8: 1.75e5 N m)"),
            speed_rated: d.parameter("speed_rated", 4.0 * std::f64::consts::PI, "rad/s").positive().describe("Rated speed (Table 3.8: 120 rpm)"),
            u_rated: d.parameter("U_rated", 700.0, "V").positive().describe("Rated armature voltage (Table 3.8: 700 V)"),
            u_max: d.parameter("U_max", 700.0, "V").min(0.0).describe("Supply voltage of the plateau, U_max (section 3.5.3; the rated 700 V of Table 3.8)"),
            r_armature: d.parameter("R_armature", 0.008, "Ohm").positive().describe("Armature resistance (Table 3.8: 8 mOhm)"),
            l_armature: d.parameter("L_armature", 0.02, "H").positive().describe("Armature inductance (Table 3.8: 20 mH)"),
            j_motor: d.parameter("J_motor", 3.0e3, "kg.m2").positive().describe("Motor rotor inertia (Table 3.8: 3e3 kg m2)"),
            b_bearings: d.parameter("b_motor_bearings", 10.0, "N.m.s/rad").min(0.0).describe("Viscous friction of the motor bearings (Table 3.8: 10 N m/(rad/s))"),
            j_propeller: d.parameter("J_propeller", 150.0e3, "kg.m2").positive().describe("Propeller inertia, entrained water included (Table 3.8: 150e3 kg m2)"),
            k_shaft: d.parameter("K_shaft", 6.5e6, "N.m/rad").positive().describe("Torsional stiffness of the hollow shaft (Table 3.8: 6.5e6 N m/rad)"),
            j_shaft: d.parameter("J_shaft", 20.0, "kg.m2").min(0.0).describe("Shaft inertia, half lumped on each end (Table 3.8: 20 kg m2)"),
            d_shaft: d.parameter("D_shaft", 25.0e3, "N.m.s/rad").min(0.0).describe("Internal damping of the shaft, on its twist rate (Table 3.8: 25 000 N m/(rad/s))"),
            t_seal_coulomb: d.parameter("T_seal_coulomb", 9.0e3, "N.m").min(0.0).describe("Friction torque of the seal while slipping (Table 3.8: 9000 N m)"),
            t_seal_static: d.parameter("T_seal_static", 9.0e3, "N.m").min(0.0).describe("Largest torque the stuck seal holds (Table 3.8 gives one value, 9000 N m; >= T_seal_coulomb)"),
            ramp_time: d.parameter("ramp_time", 200.0, "s").positive().describe("Supply ramp 0 -> U_max (section 3.5.3: 200 s)"),
            plateau_time: d.parameter("plateau_time", 200.0, "s").min(0.0).describe("Plateau at U_max before the short circuit (section 3.5.3: 200 s, so the short circuit is at 400 s)"),
            u_in: d.input("U_supply_in", 0.0, "V").describe("Supply voltage when voltage_from_input is true"),
            current: d.state("i_armature", 0.0, "A").nominal(1e3).describe("Armature current"),
            w_motor: d.state("w_motor", 0.0, "rad/s").nominal(10.0).describe("Motor speed (frozen in the reduced model)"),
            twist: d.state("shaft_twist", 0.0, "rad").nominal(0.03).describe("Shaft twist, motor angle minus propeller angle (frozen in the reduced model)"),
            w_propeller: d.state("w_propeller", 0.0, "rad/s").nominal(10.0).describe("Propeller speed (the line's speed in the reduced model)"),
            activities: ELEMENTS.map(|name| activity_state(d, name)),
            seal_mode: d.mode("seal_mode", 0).range(-1, 1).describe("Seal: 1 slipping forwards, 0 stuck (propeller held), -1 slipping backwards"),
            seal: d.event_indicator("seal", "slipping: the propeller speed in the direction of slip; stuck: T_seal_static - |required torque|"),
            y_voltage: d.output("supply_voltage", "V").describe("Armature supply voltage"),
            y_current: d.output("armature_current", "A").describe("Armature current"),
            y_motor_torque: d.output("motor_torque", "N.m").describe("Electromagnetic torque k I (eq. 3.9)"),
            y_motor_speed: d.output("motor_speed", "rad/s").describe("Motor speed"),
            y_propeller_speed: d.output("propeller_speed", "rad/s").describe("Propeller speed"),
            y_shaft_torque: d.output("shaft_torque", "N.m").describe("Torque in the shaft, K theta + D dtheta/dt (reduced model: the motor torque)"),
            y_shaft_torque_ratio: d.output("shaft_torque_ratio", "1").describe("Shaft torque / rated torque"),
            y_propeller_torque: d.output("propeller_torque", "N.m").describe("Hydrodynamic torque of the propeller, a w |w|"),
            y_seal_torque: d.output("seal_torque", "N.m").describe("Friction torque of the seal on the propeller side (stuck: what holding it takes)"),
            y_activities: ELEMENTS.map(|name| activity_output(d, name)),
            k_machine: d.calculated_parameter("k_machine", "V.s/rad").describe("Machine constant k = E/w = C/I (eq. 3.9), from the rated point: U_rated = R I + k w_rated, T_rated = k I"),
            a_propeller: d.calculated_parameter("a_propeller", "N.m.s2/rad2").describe("Propeller coefficient a = T_rated / speed_rated^2 (T = a w^2 absorbs the rated torque at the rated speed)"),
            i_rated: d.calculated_parameter("I_rated", "A").describe("Rated armature current T_rated / k"),
            j_motor_side: d.calculated_parameter("J_motor_side", "kg.m2").describe("Inertia on the motor end: J_motor + J_shaft / 2"),
            j_propeller_side: d.calculated_parameter("J_propeller_side", "kg.m2").describe("Inertia on the propeller end: J_propeller + J_shaft / 2"),
            f_shaft: d.calculated_parameter("f_shaft", "Hz").describe("Natural frequency of the shaft between the two ends, sqrt(K (1/J_m + 1/J_p)) / 2 pi"),
        }
    }

    fn check(&self, k: &Knowns) -> Result<(), String> {
        if k[self.t_seal_static] < k[self.t_seal_coulomb] {
            return Err(format!(
                "T_seal_static = {} N m must not be below T_seal_coulomb = {} N m (a stuck seal holds at least the sliding friction)",
                number(k[self.t_seal_static]),
                number(k[self.t_seal_coulomb])
            ));
        }
        if !self.machine_constant(k).is_finite() {
            return Err(format!(
                "no DC machine gives T_rated = {} N m at speed_rated = {} rad/s from U_rated = {} V through R_armature = {} Ohm \
                 (needs U_rated^2 >= 4 speed_rated R_armature T_rated)",
                number(k[self.t_rated]),
                number(k[self.speed_rated]),
                number(k[self.u_rated]),
                number(k[self.r_armature])
            ));
        }
        Ok(())
    }

    /// The ends of the ramp and the short circuit (built-in supply only).
    fn next_time_event(&self, k: &Knowns, after: f64) -> Option<f64> {
        if k[self.voltage_from_input] {
            return None;
        }
        [k[self.ramp_time], self.short_circuit_time(k)].into_iter().find(|t| *t > after)
    }

    fn event_indicators(&self, k: &Knowns, z: &mut EventIndicators) {
        if self.reduced(k) {
            z[self.seal] = 1.0; // no seal in the reduced model: never an event
            return;
        }
        let line = self.line(k);
        z[self.seal] = line.seal.indicator(k[self.seal_mode], k[self.w_propeller], self.seal_required(&line, k));
    }

    fn update_modes(&self, k: &Knowns, next: &mut ModeUpdate) {
        if self.reduced(k) {
            return;
        }
        let line = self.line(k);
        let (mode, stop) = line.seal.next_mode(k[self.seal_mode], k[self.w_propeller], self.seal_required(&line, k));
        next[self.seal_mode] = mode;
        if stop {
            next.reinit(self.w_propeller, 0.0);
        }
    }

    fn derivatives(&self, k: &Knowns, der: &mut Derivatives) {
        let op = self.operate(k);
        der[self.current] = op.current_rate;
        der[self.w_propeller] = op.propeller_acceleration;
        if !self.reduced(k) {
            der[self.w_motor] = op.motor_acceleration;
            der[self.twist] = op.twist_rate;
        }
        for (a, p) in self.activities.iter().zip(op.powers) {
            der[*a] = activity_rate(p);
        }
    }

    fn outputs(&self, k: &Knowns, out: &mut Outputs) {
        let op = self.operate(k);
        let line = self.line(k);
        out[self.y_voltage] = op.voltage;
        out[self.y_current] = k[self.current];
        out[self.y_motor_torque] = op.motor_torque;
        out[self.y_motor_speed] = op.motor_speed;
        out[self.y_propeller_speed] = op.propeller_speed;
        out[self.y_shaft_torque] = op.shaft_torque;
        out[self.y_shaft_torque_ratio] = op.shaft_torque / k[self.t_rated];
        out[self.y_propeller_torque] = op.propeller_torque;
        out[self.y_seal_torque] = op.seal_torque;
        for (y, a) in self.y_activities.iter().zip(self.activities) {
            out[*y] = k[a];
        }
        out[self.k_machine] = line.machine.constant_v_s_per_rad;
        out[self.a_propeller] = line.load.coefficient_n_m_s2_per_rad2;
        out[self.i_rated] = k[self.t_rated] / line.machine.constant_v_s_per_rad;
        out[self.j_motor_side] = line.motor.inertia_kg_m2;
        out[self.j_propeller_side] = line.propeller.inertia_kg_m2;
        out[self.f_shaft] = line.shaft.natural_frequency_hz(line.motor.inertia_kg_m2, line.propeller.inertia_kg_m2);
    }
}

fmu_runtime::export_fmu!(ShaftLine);
