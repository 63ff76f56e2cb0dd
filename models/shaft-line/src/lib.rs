//! ShaftLine: the short circuit of a submarine's DC propulsion motor (chapter section 3.5.3,
//! Figures 3.29-3.30, Table 3.8). The motor drives the propeller through a hollow shaft; a seal
//! where the shaft leaves the hull rubs on it (Coulomb friction that sticks and slips); bearings
//! lose a little viscously. The supply ramps 0 -> U_max, holds, and is short-circuited (0 V): the
//! question is the maximal transient shaft torque and its ratio to the rated torque, then which
//! elements make it (activity, eq. 3.3). The contract: `docs/shaft-line-spec.md`.
//!
//! Defaults from the book's own file, Chap3_Submarine.mo (models FullModel, FullModel_AI,
//! ReducedModel), where it gives a value; Table 3.8 otherwise (they agree but for three values):
//! * EMF constant k = 700 / (120 2 3.14 / 60) = 55.73 V s/rad given directly (component emf; pi
//!   written 3.14). `emf_constant` = 2 derives it from the rated point instead (53.63 V s/rad).
//! * Propeller T = a w |w| with a = 1.75e5 N m / (120 2 3.14 / 60 rad/s)^2 (component
//!   Propeler_quadratic_torque of FullModel_AI and ReducedModel; FullModel has 1.75e5 - 9e3).
//! * Supply: 0 -> 700 V in 50 s, 700 V to 100 s, short circuit at 100 s, 150 s in all (component
//!   tableVoltage); the chapter's text says 200 s, 200 s, 400 s, 600 s (ramp_time, plateau_time).
//! * No shaft inertia (the file has none; Table 3.8's 20 kg m2 is `J_shaft`, default 0).
//! * 8 mOhm, 20 mH, 3e3 kg m2, 10 N m/(rad/s), 6.5e6 N m/rad, 25 000 N m/(rad/s), 150e3 kg m2,
//!   9000 N m: as Table 3.8.

use components::{CoulombFriction, DcMachine, Inertia, PropellerLoad, SineVoltage, SpeedRamp, TorsionSpring};
use fmu_runtime::prelude::*;
use fmu_runtime::variables::number;

mod documentation;

/// The elements whose activity (eq. 3.3) the FMU integrates, in the order of `Operating::powers`:
/// name, component (Table 3.8's rows), effect, and what it is.
const ELEMENTS: [(&str, &str, Effect, &str); 9] = [
    ("armature_resistance", "Motor", DcMachine::RESISTANCE, "the armature resistance, power R i^2"),
    ("armature_inductance", "Motor", DcMachine::INDUCTANCE, "the armature inductance, power L i di/dt"),
    ("motor_inertia", "Motor", Effect { what: "rotor inertia", ..Inertia::INERTIA }, "the motor rotor's inertia, power J_m dw/dt w (full model only)"),
    ("motor_bearings", "Motor", Effect { what: "bearing friction (viscous)", ..CoulombFriction::FRICTION }, "the motor bearings' viscous friction, power b w^2"),
    ("shaft_stiffness", "Shaft", TorsionSpring::STIFFNESS, "the shaft stiffness, power K theta dtheta/dt (full model only)"),
    ("shaft_damping", "Shaft", TorsionSpring::DAMPING, "the shaft's internal damping, power D (dtheta/dt)^2 (full model only)"),
    ("propeller_inertia", "Propeller", Effect { what: "propeller inertia (entrained water included)", ..Inertia::INERTIA }, "the propeller inertia, power J_p dw/dt w"),
    ("seal_friction", "Seal", Effect { what: "seal friction (stick/slip)", ..CoulombFriction::FRICTION }, "the seal's friction, power |T_seal w| while slipping"),
    ("propeller_load", "Propeller", Effect { what: "hydrodynamic load", ..components::FanLoad::LOAD }, "the propeller's hydrodynamic load, power a w |w| w"),
];

/// pi as the book's file writes it in every speed (120 rpm = 120 2 3.14 / 60 rad/s).
const BOOK_PI: f64 = 3.14;
/// The book file's EMF constant, k = 700 V / 120 rpm (component emf of Chap3_Submarine.mo).
const BOOK_K_EMF: f64 = 700.0 / (120.0 * 2.0 * BOOK_PI / 60.0);
/// The book file's nominal propeller speed, 120 rpm with pi = 3.14 (Propeler_quadratic_torque).
const BOOK_PROPELLER_SPEED: f64 = 120.0 * 2.0 * BOOK_PI / 60.0;

/// Which equations the FMU integrates (`model_reduction`).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Structure {
    /// 0: motor rotor, elastic shaft, propeller, bearings and seal.
    Full,
    /// 1: the book's ReducedModel: no motor inertia, a rigid shaft; bearings and seal kept.
    BookReduced,
    /// 2: only the elements with 95 % of the short-circuit activity: R, L, propeller inertia and load.
    ActivityReduced,
}

pub struct ShaftLine {
    model_reduction: IntegerParameter,
    voltage_from_input: BooleanParameter,
    emf_constant: IntegerParameter,
    k_emf: Parameter,
    t_rated: Parameter,
    speed_rated: Parameter,
    u_rated: Parameter,
    u_max: Parameter,
    r_armature: Parameter,
    l_armature: Parameter,
    j_motor: Parameter,
    b_bearings: Parameter,
    j_propeller: Parameter,
    t_propeller_nominal: Parameter,
    speed_propeller_nominal: Parameter,
    propeller_law: IntegerParameter,
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
    elements: [Element; 9],
    supply: Element,
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
    k_machine: Local,
    a_propeller: Local,
    i_rated: Local,
    j_motor_side: Local,
    j_propeller_side: Local,
    f_shaft: Local,
}

/// The elements at the current parameter values.
struct Line<R = f64> {
    machine: DcMachine<R>,
    motor: Inertia<R>,
    bearings_n_m_s_per_rad: R,
    shaft: TorsionSpring<R>,
    propeller: Inertia<R>,
    load: PropellerLoad<R>,
    /// `propeller_law` = 2: T = a w^2 in both directions of rotation.
    load_unidirectional: bool,
    seal: CoulombFriction<R>,
}

impl<R: Real> Line<R> {
    /// The propeller's hydrodynamic torque, N m (against a forward rotation).
    fn propeller_torque_n_m(&self, w: R) -> R {
        if self.load_unidirectional {
            self.load.unidirectional_torque_n_m(w)
        } else {
            self.load.torque_n_m(w)
        }
    }
}

/// Everything the equations give at one instant.
#[derive(Default)]
struct Operating<R = f64> {
    voltage: R,
    current_rate: R,
    motor_torque: R,
    motor_speed: R,
    motor_acceleration: R,
    twist_rate: R,
    shaft_torque: R,
    propeller_speed: R,
    propeller_acceleration: R,
    propeller_torque: R,
    seal_torque: R,
    /// The power of each element of `ELEMENTS`, W (what it stores per second or dissipates).
    powers: [R; 9],
    /// The supply's power U i, W.
    supply_power: R,
}

impl ShaftLine {
    fn structure<R: Real>(&self, k: &Knowns<R>) -> Structure {
        match k[self.model_reduction] {
            1 => Structure::BookReduced,
            2 => Structure::ActivityReduced,
            _ => Structure::Full,
        }
    }

    fn machine_constant<R: Real>(&self, k: &Knowns<R>) -> R {
        if k[self.emf_constant] == 1 {
            return k[self.k_emf];
        }
        // check() refuses an impossible rating at initialization; NaN only while probing.
        DcMachine::constant_from_rated_point(k[self.u_rated], k[self.t_rated], k[self.speed_rated], k[self.r_armature]).unwrap_or(R::from(f64::NAN))
    }

    fn line<R: Real>(&self, k: &Knowns<R>) -> Line<R> {
        let half_shaft = k[self.j_shaft] * 0.5;
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
            load: PropellerLoad::from_nominal(k[self.t_propeller_nominal], k[self.speed_propeller_nominal]),
            load_unidirectional: k[self.propeller_law] == 2,
            seal: CoulombFriction { coulomb_n_m: k[self.t_seal_coulomb], static_n_m: k[self.t_seal_static] },
        }
    }

    /// The supply: 0 -> U_max over ramp_time, U_max for plateau_time, then short-circuited.
    fn voltage<R: Real>(&self, k: &Knowns<R>) -> R {
        if k[self.voltage_from_input] {
            return k[self.u_in];
        }
        if k.time() >= self.short_circuit_time(k).value() {
            R::from(0.0)
        } else {
            SpeedRamp { target: k[self.u_max], duration_s: k[self.ramp_time] }.value(R::from(k.time()))
        }
    }

    fn short_circuit_time<R: Real>(&self, k: &Knowns<R>) -> R {
        k[self.ramp_time] + k[self.plateau_time]
    }

    /// The torque the seal must take to hold the propeller still: every other torque on the body
    /// it rubs on (the propeller end; in the book's reduced model the whole rigid line).
    fn seal_required<R: Real>(&self, line: &Line<R>, k: &Knowns<R>) -> R {
        let w_p = k[self.w_propeller];
        let drive = match self.structure(k) {
            Structure::BookReduced => line.machine.torque_n_m(k[self.current]) - line.bearings_n_m_s_per_rad * w_p,
            _ => line.shaft.torque_n_m(k[self.twist], k[self.w_motor] - w_p),
        };
        drive - line.propeller_torque_n_m(w_p)
    }

    /// The seal's torque and the propeller end's acceleration under the `drive` torque.
    fn propeller_end<R: Real>(&self, line: &Line<R>, k: &Knowns<R>, drive: R, op: &mut Operating<R>) {
        let mode = k[self.seal_mode];
        if mode == 0 {
            // Stuck: the propeller stands still, the seal takes what holding it requires.
            op.seal_torque = -self.seal_required(line, k);
            op.propeller_acceleration = R::from(0.0);
        } else {
            op.seal_torque = line.seal.slip_torque_n_m(mode);
            op.propeller_acceleration = line.propeller.acceleration_rad_per_s2(drive - op.propeller_torque + op.seal_torque);
        }
    }

    fn operate<R: Real>(&self, k: &Knowns<R>) -> Operating<R> {
        let line = self.line(k);
        let m = &line.machine;
        let voltage = self.voltage(k);
        let i = k[self.current];
        let motor_torque = m.torque_n_m(i);
        let mut op = Operating { voltage, motor_torque, supply_power: voltage * i, ..Operating::default() };
        let structure = self.structure(k);
        if structure != Structure::Full {
            // A rigid massless shaft and motor rotor: L di/dt = U - R i - k w, J_p dw/dt = k i - b w
            // - a w |w| + T_seal (the book's reduced model), or without b and the seal (activity).
            let w = k[self.w_propeller];
            op.current_rate = m.current_rate_a_per_s(voltage, i, w);
            op.motor_speed = w;
            op.propeller_speed = w;
            op.propeller_torque = line.propeller_torque_n_m(w);
            op.powers[0] = m.resistance_power_w(i);
            op.powers[1] = m.inductance_power_w(op.current_rate, i);
            op.powers[8] = op.propeller_torque * w;
            if structure == Structure::BookReduced {
                let bearings = line.bearings_n_m_s_per_rad * w;
                op.shaft_torque = motor_torque - bearings;
                self.propeller_end(&line, k, op.shaft_torque, &mut op);
                op.powers[3] = bearings * w;
                op.powers[7] = line.seal.power_w(k[self.seal_mode], w);
            } else {
                op.shaft_torque = motor_torque;
                op.propeller_acceleration = line.propeller.acceleration_rad_per_s2(motor_torque - op.propeller_torque);
            }
            op.motor_acceleration = op.propeller_acceleration;
            op.powers[6] = line.propeller.power_w(op.propeller_acceleration, w);
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
        op.propeller_torque = line.propeller_torque_n_m(w_p);
        self.propeller_end(&line, k, op.shaft_torque, &mut op);
        op.powers = [
            m.resistance_power_w(i),
            m.inductance_power_w(op.current_rate, i),
            line.motor.power_w(op.motor_acceleration, w_m),
            bearings * w_m,
            line.shaft.spring_power_w(twist, op.twist_rate),
            line.shaft.damper_power_w(op.twist_rate),
            line.propeller.power_w(op.propeller_acceleration, w_p),
            line.seal.power_w(k[self.seal_mode], w_p),
            op.propeller_torque * w_p,
        ];
        op
    }
}

impl Model for ShaftLine {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "ShaftLine",
            description: "Short circuit of a submarine's DC propulsion motor (chapter 3, section 3.5.3, Table 3.8; defaults from the book's file Chap3_Submarine.mo): DC machine, hollow shaft, seal with stick/slip friction, bearings and propeller, with activity indices for model reduction",
            // The book file's supply table ends at 150 s (the file has no experiment annotation).
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 150.0, step_size: 0.01 },
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
    /// 1.5e-8 (the chapter text's 600 s run: 17 988 solver steps against 11 972 at 1e-8), 2.6e-9
    /// on the book file's 150 s run.
    fn tolerance_floor(&self, _k: &Knowns) -> Option<f64> {
        Some(1e-11)
    }

    fn declare(d: &mut Declarations) -> Self {
        ShaftLine {
            model_reduction: d.integer_parameter("model_reduction", 0).choices(0, &[("full", "the full model"), ("book_reduced", "the book's reduced model"), ("activity_reduced", "the elements with at least 95 % of the short-circuit activity")]).describe(
                "0 = the full model; 1 = the book's reduced model (file Chap3_Submarine.mo, ReducedModel: no motor inertia, a rigid shaft; \
                 the motor bearings and the seal kept); 2 = only the elements with at least 95 % of the short-circuit activity \
                 (armature R and L, propeller inertia and load: no bearings, no seal either)",
            ),
            voltage_from_input: d.boolean_parameter("voltage_from_input", false).describe(
                "false: the built-in supply profile (ramp, plateau, short circuit); true: the supply voltage is the input U_supply_in",
            ),
            emf_constant: d.integer_parameter("emf_constant", 1).choices(1, &[("k_emf", "the machine constant is k_emf (book file)"), ("rated_point", "derived from the rated point (eq. 3.9)")]).describe(
                "1 = the machine constant is k_emf (book file Chap3_Submarine.mo, component emf); \
                 2 = derived from the rated point U_rated, T_rated, speed_rated through R_armature (eq. 3.9)",
            ),
            k_emf: d.parameter("k_emf", BOOK_K_EMF, "V.s/rad").positive().describe(
                "EMF constant k = E/w = C/I when emf_constant = 1 (book file Chap3_Submarine.mo, component emf: k = 700/(120*2*3.14/60), pi written 3.14)",
            ),
            t_rated: d.parameter("T_rated", 1.75e5, "N.m").positive().describe("Rated motor torque (Table 3.8: 1.75e5 N m), the reference of shaft_torque_ratio"),
            speed_rated: d.parameter("speed_rated", 4.0 * std::f64::consts::PI, "rad/s").positive().describe("Rated speed (Table 3.8: 120 rpm); used when emf_constant = 2"),
            u_rated: d.parameter("U_rated", 700.0, "V").positive().describe("Rated armature voltage (Table 3.8: 700 V); used when emf_constant = 2"),
            u_max: d.parameter("U_max", 700.0, "V").min(0.0).describe("Supply voltage of the plateau, U_max (book file, component tableVoltage: 700 V)"),
            r_armature: d.parameter("R_armature", 0.008, "Ohm").positive().describe("Armature resistance (Table 3.8 and book file, component resistor: 8 mOhm)"),
            l_armature: d.parameter("L_armature", 0.02, "H").positive().describe("Armature inductance (Table 3.8 and book file, component inductor: 20 mH)"),
            j_motor: d.parameter("J_motor", 3.0e3, "kg.m2").positive().describe("Motor rotor inertia (Table 3.8 and book file, component inertia_motor: 3e3 kg m2)"),
            b_bearings: d.parameter("b_motor_bearings", 10.0, "N.m.s/rad").min(0.0).describe("Viscous friction of the motor bearings (Table 3.8 and book file, component friction_motor: 10 N m/(rad/s))"),
            j_propeller: d.parameter("J_propeller", 150.0e3, "kg.m2").positive().describe("Propeller inertia, entrained water included (Table 3.8 and book file, component Propeler_Inertia: 150e3 kg m2)"),
            t_propeller_nominal: d.parameter("T_propeller_nominal", 1.75e5, "N.m").positive().describe(
                "Propeller torque at speed_propeller_nominal, a = T/w^2 (book file, Propeler_quadratic_torque of FullModel_AI and ReducedModel: 1.75e5 N m; FullModel: 1.75e5 - 9e3 = 1.66e5)",
            ),
            speed_propeller_nominal: d.parameter("speed_propeller_nominal", BOOK_PROPELLER_SPEED, "rad/s").positive().describe(
                "Speed at which the propeller absorbs T_propeller_nominal (book file: 120*2*3.14/60 = 12.56 rad/s, pi written 3.14)",
            ),
            propeller_law: d.integer_parameter("propeller_law", 1).choices(1, &[("against_rotation", "T = a w |w| (book file, FullModel)"), ("squared", "T = a w^2 in both directions (book file, ReducedModel)")]).describe(
                "1 = T = a w |w|, against the rotation both ways (book file, FullModel: TorqueDirection = false); \
                 2 = T = a w^2 in both directions, driving a backwards rotation (book file, ReducedModel: TorqueDirection = true)",
            ),
            k_shaft: d.parameter("K_shaft", 6.5e6, "N.m/rad").positive().describe("Torsional stiffness of the hollow shaft (Table 3.8 and book file, shaft_stiffness_loss: 6.5e6 N m/rad)"),
            j_shaft: d.parameter("J_shaft", 0.0, "kg.m2").min(0.0).describe("Shaft inertia, half lumped on each end (the book file has none: 0; Table 3.8 lists 20 kg m2)"),
            d_shaft: d.parameter("D_shaft", 25.0e3, "N.m.s/rad").min(0.0).describe("Internal damping of the shaft, on its twist rate (Table 3.8 and book file, shaft_stiffness_loss: 25 000 N m/(rad/s))"),
            t_seal_coulomb: d.parameter("T_seal_coulomb", 9.0e3, "N.m").min(0.0).describe("Friction torque of the seal while slipping (Table 3.8 and book file, Propeler_friction: 9000 N m)"),
            t_seal_static: d.parameter("T_seal_static", 9.0e3, "N.m").min(0.0).describe("Largest torque the stuck seal holds (one value, 9000 N m, in Table 3.8 and the book file; >= T_seal_coulomb)"),
            ramp_time: d.parameter("ramp_time", 50.0, "s").positive().describe("Supply ramp 0 -> U_max (book file, tableVoltage: 50 s; the chapter's text: 200 s)"),
            plateau_time: d.parameter("plateau_time", 50.0, "s").min(0.0).describe(
                "Plateau at U_max before the short circuit (book file, tableVoltage: 50 s, short circuit at 100 s; the chapter's text: 200 s, at 400 s)",
            ),
            u_in: d.input("U_supply_in", 0.0, "V").describe("Supply voltage when voltage_from_input is true"),
            current: d.state("i_armature", 0.0, "A").nominal(1e3).describe("Armature current"),
            w_motor: d.state("w_motor", 0.0, "rad/s").nominal(10.0).describe("Motor speed (frozen in the reduced models)"),
            twist: d.state("shaft_twist", 0.0, "rad").nominal(0.03).describe("Shaft twist, motor angle minus propeller angle (frozen in the reduced models)"),
            w_propeller: d.state("w_propeller", 0.0, "rad/s").nominal(10.0).describe("Propeller speed (the line's speed in the reduced models)"),
            seal_mode: d.mode("seal_mode", 0).range(-1, 1).describe("Seal: 1 slipping forwards, 0 stuck (propeller held), -1 slipping backwards"),
            seal: d.event_indicator("seal", "slipping: the propeller speed in the direction of slip; stuck: T_seal_static - |required torque|"),
            y_voltage: d.output("supply_voltage", "V").describe("Armature supply voltage"),
            y_current: d.output("armature_current", "A").describe("Armature current"),
            y_motor_torque: d.output("motor_torque", "N.m").describe("Electromagnetic torque k I (eq. 3.9)"),
            y_motor_speed: d.output("motor_speed", "rad/s").describe("Motor speed"),
            y_propeller_speed: d.output("propeller_speed", "rad/s").describe("Propeller speed"),
            y_shaft_torque: d.output("shaft_torque", "N.m").describe(
                "Torque in the shaft, K theta + D dtheta/dt (reduced models: what the motor passes on, k I - b w, or k I without bearings)",
            ),
            y_shaft_torque_ratio: d.output("shaft_torque_ratio", "1").describe("Shaft torque / rated torque T_rated"),
            y_propeller_torque: d.output("propeller_torque", "N.m").describe("Hydrodynamic torque of the propeller, a w |w| (propeller_law 2: a w^2)"),
            y_seal_torque: d.output("seal_torque", "N.m").describe("Friction torque of the seal on the propeller side (stuck: what holding it takes)"),
            elements: ELEMENTS.map(|(name, component, effect, what)| d.element(name, component, effect).describe(what)),
            supply: {
                d.element("electromechanical_transformer", "Motor", DcMachine::TRANSFORMER).describe("the DC machine's conversion, E = k w, C = k I (eq. 3.9)");
                d.element("supply", "Power supply", Effect { what: "DC voltage source", ..SineVoltage::SOURCE })
                    .describe("the armature supply, power U i (the ramp, plateau and short circuit, or the input U_supply_in)")
            },
            k_machine: d.calculated_parameter("k_machine", "V.s/rad").describe(
                "Machine constant k = E/w = C/I (eq. 3.9): k_emf, or from the rated point U_rated = R I + k w_rated, T_rated = k I (emf_constant = 2)",
            ),
            a_propeller: d.calculated_parameter("a_propeller", "N.m.s2/rad2").describe("Propeller coefficient a = T_propeller_nominal / speed_propeller_nominal^2"),
            i_rated: d.calculated_parameter("I_rated", "A").describe("Armature current at the rated torque, T_rated / k"),
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
                "emf_constant = 2: no DC machine gives T_rated = {} N m at speed_rated = {} rad/s from U_rated = {} V through R_armature = {} Ohm \
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
        if self.structure(k) == Structure::ActivityReduced {
            z[self.seal] = 1.0; // no seal in this model: never an event
            return;
        }
        let line = self.line(k);
        z[self.seal] = line.seal.indicator(k[self.seal_mode], k[self.w_propeller], self.seal_required(&line, k));
    }

    fn update_modes(&self, k: &Knowns, next: &mut ModeUpdate) {
        if self.structure(k) == Structure::ActivityReduced {
            return;
        }
        let line = self.line(k);
        let (mode, stop) = line.seal.next_mode(k[self.seal_mode], k[self.w_propeller], self.seal_required(&line, k));
        next[self.seal_mode] = mode;
        if stop {
            next.reinit(self.w_propeller, 0.0);
        }
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let op = self.operate(k);
        der[self.current] = op.current_rate;
        der[self.w_propeller] = op.propeller_acceleration;
        if self.structure(k) == Structure::Full {
            der[self.w_motor] = op.motor_acceleration;
            der[self.twist] = op.twist_rate;
        }
        for (e, p) in self.elements.iter().zip(op.powers) {
            der.power(*e, p);
        }
        der.power(self.supply, op.supply_power);
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
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
        out[self.k_machine] = line.machine.constant_v_s_per_rad;
        out[self.a_propeller] = line.load.coefficient_n_m_s2_per_rad2;
        out[self.i_rated] = k[self.t_rated] / line.machine.constant_v_s_per_rad;
        out[self.j_motor_side] = line.motor.inertia_kg_m2;
        out[self.j_propeller_side] = line.propeller.inertia_kg_m2;
        out[self.f_shaft] = line.shaft.natural_frequency_hz(line.motor.inertia_kg_m2, line.propeller.inertia_kg_m2);
    }
}

fmu_runtime::export_fmu!(ShaftLine);
