//! The elevator drive of chapter section 3.4.1.2 (Figure 3.16.b): a chopper, an ideal transformer
//! of duty cycle alpha, feeds a DC motor (eq. 3.9, with its armature's R and L) that turns a cable
//! drum lifting the cabin against its counterweight (both seen by the drum as m r^2, eq. 3.7).
//! Its elements (Table 3.1; the three transformers are Table 3.5's) give the activities and the
//! energy balance. Values argued in docs/elevator-drive-spec.md.

use components::{CableDrum, Chopper, DcMachine, Inertia, Weight};
use fmu_runtime::prelude::*;

pub struct ElevatorDrive {
    supply: Parameter, resistance: Parameter, inductance: Parameter, k: Parameter,
    inertia: Parameter, radius: Parameter, cabin: Parameter, counterweight: Parameter,
    duty: Input, current: State, speed: State, height: State,
    cabin_speed: Output, cabin_height: Output, motor_current: Output, supply_current: Output,
    bus: Element, armature_r: Element, armature_l: Element, rotation: Element, unbalance: Element,
}

impl Model for ElevatorDrive {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "ElevatorDrive",
            description: "DC motor and chopper elevator drive (chapter 3, section 3.4.1.2)",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 5.0, step_size: 0.01 },
            solver: Solver::ExplicitRungeKutta,
            documentation: "<p>Table 3.5: chopper U = alpha U_dc, I_dc = alpha I; DC motor (eq. 3.9) E = k w, C = k I; drum v = r w, C = r F. Cabin and counterweight seen as (m_cabin + m_cw) r^2. Values argued in docs/elevator-drive-spec.md.</p>",
        }
    }

    fn declare(d: &mut Declarations) -> Self {
        d.element("chopper", "Chopper", Chopper::TRANSFORMER).describe("the chopper, U = alpha U_dc and I_dc = alpha I");
        d.element("electromechanical_transformer", "Motor", DcMachine::TRANSFORMER).describe("the motor's E = k w and C = k I (eq. 3.9)");
        d.element("drum", "Drum", CableDrum::TRANSFORMER).describe("the drum's v = r w and C = r F");
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
            bus: d.element("dc_bus", "Chopper", Chopper::SUPPLY).describe("the DC bus, power U_dc alpha i"),
            armature_r: d.element("armature_resistance", "Motor", DcMachine::RESISTANCE).describe("the armature resistance, R i^2"),
            armature_l: d.element("armature_inductance", "Motor", DcMachine::INDUCTANCE).describe("the armature inductance, L i di/dt"),
            rotation: d.element("inertia", "Motor, drum and masses", Inertia::INERTIA).describe("J + (m_cabin + m_cw) r^2, J w dw/dt"),
            unbalance: d.element("unbalance", "Cabin and counterweight", Weight::GRAVITY).describe("the unbalanced weight, -(m_cabin - m_cw) g v"),
        }
    }

    /// At steady speed the explicit solver steps at its stability limit (the armature-inertia mode,
    /// -25 +/- 33j 1/s), and the step-size controller's cycling leaves a ripple of the order of the
    /// tolerance in i and w, whose |J w dw/dt| the inertia's activity integrates: 13-24 x rtol of
    /// its range at 5 s for rtol 1e-3 to 1e-8. At 1e-9 it is within 2e-8 (under 10 x 1e-8).
    fn tolerance_floor(&self, _k: &Knowns) -> Option<f64> {
        Some(1e-9)
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let chopper = Chopper { supply_voltage_v: k[self.supply] };
        let motor = DcMachine { resistance_ohm: k[self.resistance], inductance_h: k[self.inductance], constant_v_s_per_rad: k[self.k] };
        let drum = CableDrum { radius_m: k[self.radius] };
        let inertia = Inertia { inertia_kg_m2: k[self.inertia] + drum.referred_inertia_kg_m2(k[self.cabin] + k[self.counterweight]) };
        let unbalance = Weight { mass_kg: k[self.cabin] - k[self.counterweight] };
        der[self.current] = motor.current_rate_a_per_s(chopper.output_voltage_v(k[self.duty]), k[self.current], k[self.speed]);
        der[self.speed] = inertia.acceleration_rad_per_s2(motor.torque_n_m(k[self.current]) - drum.torque_n_m(unbalance.force_n()));
        der[self.height] = drum.cable_speed_m_per_s(k[self.speed]);
        der.power(self.bus, chopper.supply_power_w(k[self.duty], k[self.current]));
        der.power(self.armature_r, motor.resistance_power_w(k[self.current]));
        der.power(self.armature_l, motor.inductance_power_w(der[self.current], k[self.current]));
        der.power(self.rotation, inertia.power_w(der[self.speed], k[self.speed]));
        der.power(self.unbalance, unbalance.power_w(der[self.height]));
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        out[self.cabin_speed] = k[self.radius] * k[self.speed];
        out[self.cabin_height] = k[self.height];
        out[self.motor_current] = k[self.current];
        out[self.supply_current] = k[self.duty] * k[self.current];
    }
}

fmu_runtime::export_fmu!(ElevatorDrive);
