//! InductionMotor: the motor-fan's motor as an FMU of its own (docs/motor-fan-system-spec.md).
//! Torque in (the shaft's load torque), speed and angle out: J dw/dt = T_m - T_load. The
//! electromagnetic torque comes from the steady-state equivalent circuit (MotorFan levels b-c),
//! the dq model (`electrical_dynamics`, level d), or a converter's torque command (`drive` = 2).
//! Coupling expected: `angle`/`speed` -> DriveShaft.angle_a/speed_a, DriveShaft.torque -> `load_torque`;
//! with a converter, SpeedController.torque_command -> `torque_command`.

use components::{Fluxes, InductionMachine, Inertia, TorqueSpeedTable, SHAFT_PORT};
use drive_train::{converter_fed, MotorParameters, subsystem_info};
use fmu_runtime::prelude::*;

pub struct InductionMotor {
    drive: IntegerParameter,
    electrical_dynamics: BooleanParameter,
    motor: MotorParameters,
    load_torque: Input,
    torque_command: Input,
    w: State,
    angle: State,
    psi_sd: State,
    psi_sq: State,
    psi_rd: State,
    psi_rq: State,
    y_speed: Output,
    y_angle: Output,
    y_torque: Output,
    y_current: Output,
    y_power: Output,
    elements: Elements,
}

/// The motor's elements (Table 3.1's motor row and the port to the driveshaft).
struct Elements {
    supply: Element,
    winding_inductance: Element,
    winding_resistance: Element,
    motor_torque: Element,
    inertia: Element,
    port: Element,
}

/// The motor at one instant.
struct Operating<R = f64> {
    torque: R,
    current_rms: R,
    power: R,
    flux_rates: Fluxes<R>,
    /// The dq model's winding losses and magnetic power (0 without electrical dynamics).
    winding_loss: R,
    magnetic_power: R,
    /// Whether the dq model, fed by the supply, makes the torque (else the curve or the converter).
    from_supply: bool,
}

impl InductionMotor {
    fn fluxes<R: Real>(&self, k: &Knowns<R>) -> Fluxes<R> {
        Fluxes { stator_d: k[self.psi_sd], stator_q: k[self.psi_sq], rotor_d: k[self.psi_rd], rotor_q: k[self.psi_rq] }
    }

    fn operate<R: Real>(&self, k: &Knowns<R>, with_electrical: bool) -> Operating<R> {
        let zero = R::from(0.0);
        let machine = self.motor.machine(k);
        let w = k[self.w];
        if k[self.drive] == 2 {
            let torque = k[self.torque_command];
            let (current_rms, power) = if with_electrical { converter_fed(&machine, torque, w) } else { (zero, zero) };
            return Operating { torque, current_rms, power, flux_rates: Fluxes::default(), winding_loss: zero, magnetic_power: zero, from_supply: false };
        }
        if k[self.electrical_dynamics] {
            let dq = machine.dq_response(self.fluxes(k), w);
            return Operating {
                torque: dq.torque_n_m,
                current_rms: dq.stator_current_rms_a,
                power: dq.electrical_power_w,
                flux_rates: dq.flux_rates,
                winding_loss: dq.winding_loss_w,
                magnetic_power: dq.magnetic_power_w,
                from_supply: true,
            };
        }
        // Interpolation 0 reads the table by Akima's spline, as the book's level-c file.
        let curve = self.motor.curve(k, true);
        if !with_electrical {
            return Operating { torque: curve.torque_n_m(&machine, w), current_rms: zero, power: zero, flux_rates: Fluxes::default(), winding_loss: zero, magnetic_power: zero, from_supply: false };
        }
        let st = curve.steady_state(&machine, w);
        Operating { torque: st.torque_n_m, current_rms: st.current_rms_a, power: st.electrical_power_w, flux_rates: Fluxes::default(), winding_loss: zero, magnetic_power: zero, from_supply: false }
    }
}

const DOCUMENTATION: &str = r#"
<p>The induction motor of the cooling-tower fan (chapter 3, sections 3.1-3.3) as a subsystem: rotor inertia
J_motor dw/dt = T_m - load_torque, with T_m from the book's torque-speed table (<code>motor_model</code> = 1, read by
Akima's spline; book file Chap3_CoolingTowerFan.mo, component TorqueSpeed) or the steady-state T-equivalent circuit
(<code>motor_model</code> = 2; the current and power come from the circuit in both cases), from the dq model
(<code>electrical_dynamics</code> = true: stator and rotor fluxes in the synchronous frame), or, with
<code>drive</code> = 2, from a converter that follows <code>torque_command</code>.</p>
<p>Coupling: torque in, angle and speed out. Connect <code>angle</code> and <code>speed</code> to DriveShaft.angle_a
and speed_a, and DriveShaft.torque to
<code>load_torque</code>; with a converter, SpeedController.torque_command to <code>torque_command</code>.
The speed is a state: it does not depend directly on any input, so no algebraic loop forms.
Input derivatives and first output derivatives are supported for extrapolating masters.</p>
"#;

impl Model for InductionMotor {
    fn info() -> ModelInfo {
        subsystem_info(
            "InductionMotor",
            "Induction motor with rotor inertia, torque in / speed out: the motor of the cooling-tower fan (chapter 3, Figure 3.2) as a co-simulation subsystem",
            5.0,
            DOCUMENTATION,
        )
    }

    /// Physical couplings (speeds, angles, torques) are smooth: extrapolate them by default, so
    /// masters that hold inputs over a step couple accurately (docs/motor-fan-system-spec.md).
    fn extrapolates_inputs() -> bool {
        true
    }

    /// Measured as for MotorFan (tests/python/accuracy_table.py): the slip mode's eigenvalue
    /// -179 /s holds the explicit solver at its stability limit (h = 19.5 ms, h lambda = -3.50),
    /// errors about 1400 x rtol of the activity's range; at 1e-11 within 1.4e-8 (472 solver
    /// steps against 307 at 1e-8).
    fn tolerance_floor(&self, _k: &Knowns) -> Option<f64> {
        Some(1e-11)
    }

    fn declare(d: &mut Declarations) -> Self {
        InductionMotor {
            drive: d.integer_parameter("drive", 1).choices(1, &[("direct_on_line", "torque from the machine"), ("converter", "torque = torque_command")]).describe("1 = direct on line (torque from the machine), 2 = converter (torque = torque_command)"),
            electrical_dynamics: d.boolean_parameter("electrical_dynamics", false).describe("true: the dq model with stator and rotor fluxes (MotorFan level d) instead of the steady-state curve"),
            motor: MotorParameters::declare(d),
            load_torque: d.input("load_torque", 0.0, "N.m").describe("Torque the driveshaft exerts on the rotor (connect DriveShaft.torque)"),
            torque_command: d.input("torque_command", 0.0, "N.m").describe("Converter torque command, used when drive = 2 (connect SpeedController.torque_command)"),
            w: d.state("w_motor", 0.0, "rad/s").nominal(100.0).describe("Rotor speed"),
            angle: d.state("phi_motor", 0.0, "rad").nominal(100.0).describe("Rotor angle"),
            psi_sd: d.state("psi_sd", 0.0, "Wb").describe("Stator flux, d axis (electrical_dynamics; frozen otherwise)"),
            psi_sq: d.state("psi_sq", 0.0, "Wb").describe("Stator flux, q axis (electrical_dynamics; frozen otherwise)"),
            psi_rd: d.state("psi_rd", 0.0, "Wb").describe("Rotor flux, d axis (electrical_dynamics; frozen otherwise)"),
            psi_rq: d.state("psi_rq", 0.0, "Wb").describe("Rotor flux, q axis (electrical_dynamics; frozen otherwise)"),
            y_speed: d.output("speed", "rad/s").describe("Rotor speed"),
            y_angle: d.output("angle", "rad").describe("Rotor angle"),
            y_torque: d.output("motor_torque", "N.m").describe("Electromagnetic torque"),
            y_current: d.output("stator_current_rms", "A").describe("Stator phase current, rms"),
            y_power: d.output("electrical_power", "W").describe("Active power drawn (converter: mechanical power through an ideal converter)"),
            elements: Elements {
                supply: d.element("voltage_source", "Power supply", InductionMachine::SUPPLY).describe("the grid's voltage source, 3/2 u_sd i_sd (electrical_dynamics only)"),
                winding_inductance: d
                    .element("winding_inductance", "Motor", InductionMachine::WINDING_INDUCTANCE)
                    .describe("the winding inductances, rate of the fluxes' magnetic energy (electrical_dynamics only)"),
                winding_resistance: d
                    .element("winding_resistance", "Motor", InductionMachine::WINDING_RESISTANCE)
                    .describe("the stator and rotor winding resistances (electrical_dynamics only)"),
                motor_torque: {
                    d.element("electromechanical_transformer", "Motor", InductionMachine::TRANSFORMER).describe("the motor's conversion of electrical into mechanical power");
                    d.element("motor_torque", "Motor", Effect { what: "motor torque (curve or converter)", ..TorqueSpeedTable::<3>::SOURCE })
                        .describe("the motor's torque on its shaft, T_m w, from the steady-state curve or the converter (0 with electrical_dynamics: the supply is the source)")
                },
                inertia: d.element("inertia", "Motor", Effect { what: "rotor inertia", ..Inertia::INERTIA }).describe("the rotor inertia, power J dw/dt w"),
                port: d.element("shaft_port", "Motor", SHAFT_PORT).describe("the shaft end, power -load_torque w (what the motor delivers to the driveshaft)"),
            },
        }
    }

    fn check(&self, k: &Knowns) -> Result<(), String> {
        self.motor.check(k)
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let op = self.operate(k, false);
        let rotor = self.motor.rotor(k);
        let w = k[self.w];
        let acceleration = rotor.acceleration_rad_per_s2(op.torque - k[self.load_torque]);
        der[self.w] = acceleration;
        der[self.angle] = w;
        der[self.psi_sd] = op.flux_rates.stator_d;
        der[self.psi_sq] = op.flux_rates.stator_q;
        der[self.psi_rd] = op.flux_rates.rotor_d;
        der[self.psi_rq] = op.flux_rates.rotor_q;
        let e = &self.elements;
        let supplied = if op.from_supply { op.power } else { R::from(0.0) };
        der.power(e.supply, supplied);
        der.power(e.winding_inductance, op.magnetic_power);
        der.power(e.winding_resistance, op.winding_loss);
        der.power(e.motor_torque, if op.from_supply { R::from(0.0) } else { op.torque * w });
        der.power(e.inertia, rotor.power_w(acceleration, w));
        der.power(e.port, -k[self.load_torque] * w);
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        let op = self.operate(k, true);
        out[self.y_speed] = k[self.w];
        out[self.y_angle] = k[self.angle];
        out[self.y_torque] = op.torque;
        out[self.y_current] = op.current_rms;
        out[self.y_power] = op.power;
    }
}

fmu_runtime::export_fmu!(InductionMotor);
