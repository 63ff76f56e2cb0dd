//! The elevator drive of chapter section 3.4.1.2 (Figure 3.16.b): a chopper, an ideal transformer
//! of duty cycle alpha, feeds a DC motor (eq. 3.9, with its armature's R and L) that turns a cable
//! drum lifting the cabin against its counterweight (both seen by the drum as m r^2, eq. 3.7).

use components::{CableDrum, Chopper, DcMachine};
use fmu_runtime::prelude::*;

const G: f64 = 9.81; // standard gravity, m/s2

pub struct ElevatorDrive {
    supply: Parameter, resistance: Parameter, inductance: Parameter, k: Parameter,
    inertia: Parameter, radius: Parameter, cabin: Parameter, counterweight: Parameter,
    duty: Input, current: State, speed: State, height: State,
    cabin_speed: Output, cabin_height: Output, motor_current: Output, supply_current: Output,
}

impl Model for ElevatorDrive {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "ElevatorDrive",
            description: "DC motor and chopper elevator drive (chapter 3, section 3.4.1.2)",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 5.0, step_size: 0.01 },
            solver: Solver::ExplicitRungeKutta,
            documentation: "<p>Chopper U = alpha U_dc, DC motor eq. 3.9, drum v = r w, cabin and counterweight.</p>",
        }
    }

    fn declare(d: &mut Declarations) -> Self {
        ElevatorDrive {
            supply: d.parameter("supply_voltage", 400.0, "V").positive().describe("DC bus voltage feeding the chopper"),
            resistance: d.parameter("R", 0.5, "Ohm").positive().describe("Armature resistance"),
            inductance: d.parameter("L", 0.01, "H").positive().describe("Armature inductance"),
            k: d.parameter("k", 60.0, "V.s/rad").positive().describe("Machine constant k_C = k_E (eq. 3.9)"),
            inertia: d.parameter("J", 10.0, "kg.m2").positive().describe("Inertia of the motor and the drum"),
            radius: d.parameter("drum_radius", 0.3, "m").positive().describe("Cable drum radius"),
            cabin: d.parameter("m_cabin", 1200.0, "kg").positive().describe("Cabin with its load"),
            counterweight: d.parameter("m_counterweight", 1000.0, "kg").positive().describe("Counterweight"),
            duty: d.input("duty_cycle", 0.5, "1").min(-1.0).max(1.0).describe("Chopper duty cycle alpha"),
            current: d.state("i", 0.0, "A").describe("Armature current"),
            speed: d.state("w", 0.0, "rad/s").describe("Motor and drum speed"),
            height: d.state("z", 0.0, "m").describe("Cabin height"),
            cabin_speed: d.output("v", "m/s").describe("Cabin speed, upwards"),
            cabin_height: d.output("height", "m").describe("Cabin height"),
            motor_current: d.output("motor_current", "A").describe("Armature current"),
            supply_current: d.output("supply_current", "A").describe("Current drawn from the DC bus"),
        }
    }

    fn derivatives(&self, k: &Knowns, der: &mut Derivatives) {
        let chopper = Chopper { supply_voltage_v: k[self.supply] };
        let motor = DcMachine { resistance_ohm: k[self.resistance], inductance_h: k[self.inductance], constant_v_s_per_rad: k[self.k] };
        let drum = CableDrum { radius_m: k[self.radius] };
        let inertia = k[self.inertia] + drum.referred_inertia_kg_m2(k[self.cabin] + k[self.counterweight]);
        let load = drum.torque_n_m((k[self.cabin] - k[self.counterweight]) * G);
        der[self.current] = motor.current_rate_a_per_s(chopper.output_voltage_v(k[self.duty]), k[self.current], k[self.speed]);
        der[self.speed] = (motor.torque_n_m(k[self.current]) - load) / inertia;
        der[self.height] = drum.cable_speed_m_per_s(k[self.speed]);
    }

    fn outputs(&self, k: &Knowns, out: &mut Outputs) {
        out[self.cabin_speed] = k[self.radius] * k[self.speed];
        out[self.cabin_height] = k[self.height];
        out[self.motor_current] = k[self.current];
        out[self.supply_current] = k[self.duty] * k[self.current];
    }
}

fmu_runtime::export_fmu!(ElevatorDrive);
