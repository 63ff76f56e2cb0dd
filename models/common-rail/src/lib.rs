//! CommonRailInjection: the common-rail direct injection system of chapter section 3.4.3
//! (Figure 3.20, Table 3.7). A low-pressure (boost) pump feeds a radial-piston high-pressure pump
//! driven by the engine, whose three plungers deliver through their check valves into the rail, a
//! hydraulic accumulator (C = V / B(p), the fuel's bulk modulus rising with pressure); a
//! spring-loaded pressure-control valve, its poppet a mass on a spring with a damper and an
//! electromagnet set from the pressure set point, returns the excess to the tank through an orifice
//! that opens with its lift; one injector per cylinder, fired in the engine's order (1-3-4-2 for
//! four cylinders) at a crank angle before each firing top dead centre, lifts its needle for the
//! energizing time and sprays through its seat and holes into the cylinder. The chapter's question:
//! how stable is the rail pressure? The contract: `docs/common-rail-spec.md`.
//!
//! Events: the start of each injection is a state event on the crank angle (the `firing_slot`
//! mode), the needle's trapezoid kinks are time events from that start (lift-off, stop, closing,
//! seated), each plunger's check valves switch at its dead centres (state events), and the valve's
//! poppet lands on and lifts off its seat (state events). The chapter gives no values: each
//! default is argued from public data in `documentation.rs` (the FMU's page) and the spec.

use std::f64::consts::PI;

use components::injection::{InjectorNozzle, LinearBulkModulus, NeedleLift, PoppetValve, RadialPistonPump, DIESEL_DENSITY_KG_PER_M3};
use components::{LaminarLeakage, Mass, Ramp, Reducer, TranslationalSpring};
use fmu_runtime::prelude::*;

mod documentation;

/// Plungers of the high-pressure pump (CP1/CP3 layout).
const PLUNGERS: usize = 3;
/// Longest energizing time the injector driver gives, s (the command is clamped to it).
pub const ENERGIZING_TIME_MAX_S: f64 = 3e-3;
/// Highest engine speed the input accepts, rad/s (5000 rpm).
pub const ENGINE_SPEED_MAX_RAD_PER_S: f64 = 5000.0 * 2.0 * PI / 60.0;
/// The firing orders of inline engines of 4 to 6 cylinders (cylinder numbers, from the one whose
/// firing top dead centre is at crank angle 0).
pub const FIRING_ORDERS: [&[i32]; 3] = [&[1, 3, 4, 2], &[1, 2, 4, 5, 3], &[1, 5, 3, 6, 2, 4]];
/// The `firing_slot` mode before it is synchronized with the crank angle (initialization).
const NOT_SYNCHRONIZED: i32 = -1;
/// A needle kink closer than this ahead of the shot's timer is the one just reached, s.
const TIMER_ROUNDING_S: f64 = 1e-12;
/// The run starts this crank angle after cylinder 1's start of injection (1 degree: the injector's
/// timer runs, its needle has not lifted yet), rad.
const START_PAST_INJECTION_RAD: f64 = PI / 180.0;
/// The shot timer's start when the engine stands still at the start: no shot in progress, s.
const NO_SHOT_TIMER_S: f64 = 1.0;

/// The defaults, argued in documentation.rs.
mod defaults {
    use std::f64::consts::PI;
    /// 2000 rpm.
    pub const ENGINE_SPEED: f64 = 2000.0 * 2.0 * PI / 60.0;
    /// 145 MPa.
    pub const SET_POINT: f64 = 145e6;
    /// Spring alone: 10 MPa on the 0.6 mm seat.
    pub fn spring_preload(seat_diameter_m: f64) -> f64 {
        components::geometry::circle_area_m2(seat_diameter_m) * 10e6
    }
    /// 0.5 cm3/s at 145 MPa.
    pub fn leakage() -> f64 {
        145e6 / 0.5e-6
    }
}

pub struct CommonRailInjection {
    cylinders: IntegerParameter,
    advance: Parameter,
    pump_ratio: Parameter,
    pump_phase: Parameter,
    p_feed: Parameter,
    plunger_diameter: Parameter,
    eccentricity: Parameter,
    v_rail: Parameter,
    b_fuel_0: Parameter,
    db_dp: Parameter,
    r_leakage: Parameter,
    seat_diameter: Parameter,
    cd_valve: Parameter,
    m_valve: Parameter,
    k_valve: Parameter,
    c_valve: Parameter,
    f_preload: Parameter,
    holes: IntegerParameter,
    hole_diameter: Parameter,
    cd_nozzle: Parameter,
    needle_seat_diameter: Parameter,
    needle_seat_angle: Parameter,
    lift_max: Parameter,
    opening_speed: Parameter,
    closing_speed: Parameter,
    opening_delay: Parameter,
    closing_delay: Parameter,
    p_cylinder: Parameter,
    step_time: Parameter,
    set_point_step: Parameter,
    energizing_step: Parameter,
    speed_in: Input,
    set_point_in: Input,
    energizing_in: Input,
    crank: State,
    pressure: State,
    lift: State,
    speed: State,
    since_start: State,
    shot_energizing: State,
    shot_volume: State,
    last_shot: State,
    slot: Mode,
    plunger_modes: [Mode; PLUNGERS],
    valve_mode: Mode,
    soi: Indicator,
    check_valves: [Indicator; PLUNGERS],
    seat: Indicator,
    powers: Powers,
    y_pressure: Output,
    y_set_point: Output,
    y_opening: Output,
    y_pump_flow: Output,
    y_injection_flow: Output,
    y_relief_flow: Output,
    y_leakage_flow: Output,
    y_valve_lift: Output,
    y_needle_lift: Output,
    y_shot: Output,
    y_last_shot: Output,
    y_cylinder: Output,
    y_torque: Output,
    y_bulk: Output,
    displacement: Local,
    hole_area: Local,
    valve_seat_area: Local,
    firing_interval: Local,
}

/// The elements whose power the equations report (Table 3.7's sources, storages and dissipations).
struct Powers {
    engine: Element,
    feed: Element,
    rail: Element,
    leakage: Element,
    relief: Element,
    valve_mass: Element,
    valve_spring: Element,
    valve_damping: Element,
    solenoid: Element,
    needle_seats: Element,
    nozzle_holes: Element,
    cylinders: Element,
}

/// The system's parts at the current parameter values.
struct Parts<R = f64> {
    pump: RadialPistonPump<R>,
    fuel: LinearBulkModulus<R>,
    leakage: LaminarLeakage<R>,
    valve: PoppetValve<R>,
    poppet: Mass<R>,
    /// The valve's spring (elongation = lift + preload / k) with the poppet's damping.
    spring: TranslationalSpring<R>,
    nozzle: InjectorNozzle<R>,
    needle: NeedleLift<R>,
}

/// Everything the equations give at one instant.
#[derive(Default)]
struct Operating<R = f64> {
    set_point: R,
    solenoid_force: R,
    closing_force: R,
    net_opening_force: R,
    bulk_modulus: R,
    pressure_rate: R,
    valve_acceleration: R,
    pump_flow: R,
    filling_flow: R,
    pump_torque: R,
    needle_lift: R,
    injection_flow: R,
    relief_flow: R,
    leakage_flow: R,
    displaced_flow: R,
    p_engine: R,
    p_feed: R,
    p_rail: R,
    p_leakage: R,
    p_relief: R,
    p_valve_mass: R,
    p_valve_spring: R,
    p_valve_damping: R,
    p_solenoid: R,
    p_needle_seats: R,
    p_nozzle_holes: R,
    p_cylinders: R,
}

impl CommonRailInjection {
    fn parts<R: Real>(&self, k: &Knowns<R>) -> Parts<R> {
        let k_valve = k[self.k_valve];
        Parts {
            pump: RadialPistonPump::three_plungers(k[self.plunger_diameter], k[self.eccentricity]),
            fuel: LinearBulkModulus { at_zero_pa: k[self.b_fuel_0], slope: k[self.db_dp] },
            leakage: LaminarLeakage { resistance_pa_s_per_m3: k[self.r_leakage] },
            valve: PoppetValve { seat_diameter_m: k[self.seat_diameter], discharge_coefficient: k[self.cd_valve], density_kg_per_m3: R::from(DIESEL_DENSITY_KG_PER_M3) },
            poppet: Mass { mass_kg: k[self.m_valve] },
            spring: TranslationalSpring { stiffness_n_per_m: k_valve, damping_n_s_per_m: k[self.c_valve] },
            nozzle: InjectorNozzle {
                hole_count: R::from(f64::from(k[self.holes])),
                hole_diameter_m: k[self.hole_diameter],
                seat_diameter_m: k[self.needle_seat_diameter],
                seat_half_angle_rad: k[self.needle_seat_angle],
                discharge_coefficient: k[self.cd_nozzle],
                density_kg_per_m3: R::from(DIESEL_DENSITY_KG_PER_M3),
            },
            needle: NeedleLift {
                opening_delay_s: k[self.opening_delay],
                closing_delay_s: k[self.closing_delay],
                opening_speed_m_per_s: k[self.opening_speed],
                closing_speed_m_per_s: k[self.closing_speed],
                max_lift_m: k[self.lift_max],
            },
        }
    }

    fn cylinder_count<R: Real>(&self, k: &Knowns<R>) -> i32 {
        k[self.cylinders].clamp(4, 6)
    }

    /// Crank angle between two firings, 4 pi / n, rad.
    fn firing_interval_rad<R: Real>(&self, k: &Knowns<R>) -> f64 {
        4.0 * PI / f64::from(self.cylinder_count(k))
    }

    /// The built-in profile: at `step_time` the set point and the energizing time step by their steps.
    fn profile<R: Real>(&self, k: &Knowns<R>) -> [Ramp<R>; 2] {
        let start_s = k[self.step_time];
        [Ramp { start_s, duration_s: R::from(0.0), height: k[self.set_point_step] }, Ramp { start_s, duration_s: R::from(0.0), height: k[self.energizing_step] }]
    }

    /// The rail pressure set point, Pa: the input plus the profile's step.
    fn set_point<R: Real>(&self, k: &Knowns<R>) -> R {
        k[self.set_point_in] + self.profile(k)[0].value(R::from(k.time()))
    }

    /// The energizing time commanded now, s: the input plus the profile's step, within the driver's
    /// 0 .. 3 ms.
    fn energizing_time<R: Real>(&self, k: &Knowns<R>) -> R {
        (k[self.energizing_in] + self.profile(k)[1].value(R::from(k.time()))).clamp(R::from(0.0), R::from(ENERGIZING_TIME_MAX_S))
    }

    /// The pump shaft's angle, r theta + phase, rad.
    fn pump_angle<R: Real>(&self, k: &Knowns<R>) -> R {
        k[self.pump_ratio] * k[self.crank] + k[self.pump_phase]
    }

    fn delivering<R: Real>(&self, k: &Knowns<R>) -> [bool; PLUNGERS] {
        self.plunger_modes.map(|m| k[m] == 1)
    }

    /// Crank angle past the start of injection of firing slot `slot`, in [-2 pi, 2 pi) rad: the
    /// start of injection of slot j is at j 4 pi / n - advance (mod 4 pi).
    fn past_start_rad(&self, k: &Knowns, slot: i32) -> f64 {
        let psi = k[self.crank] + k[self.advance] - f64::from(slot) * self.firing_interval_rad(k);
        (psi + 2.0 * PI).rem_euclid(4.0 * PI) - 2.0 * PI
    }

    /// The firing slot whose start of injection the crank angle has passed last.
    fn slot_of_crank(&self, k: &Knowns) -> i32 {
        let n = self.cylinder_count(k);
        let sectors = ((k[self.crank] + k[self.advance]) / self.firing_interval_rad(k)).floor();
        (sectors.rem_euclid(f64::from(n))) as i32
    }

    /// The net force opening the valve's ball, A p - (F_0 + k x + c v) - F_sol, N.
    fn net_opening_force<R: Real>(&self, k: &Knowns<R>, p: &Parts<R>) -> R {
        let preload = k[self.f_preload];
        let solenoid = (p.valve.force_n(self.set_point(k)) - preload).max(R::from(0.0));
        let spring = p.spring.force_n(k[self.lift] + preload / p.spring.stiffness_n_per_m, k[self.speed]);
        p.valve.force_n(k[self.pressure]) - spring - solenoid
    }

    fn operate<R: Real>(&self, k: &Knowns<R>) -> Operating<R> {
        let p = self.parts(k);
        let pressure = k[self.pressure];
        let (x, v) = (k[self.lift], k[self.speed]);
        let open = k[self.valve_mode] == PoppetValve::OPEN;
        let mut op = Operating { set_point: self.set_point(k), ..Operating::default() };
        // The pressure-control valve: spring preload, the solenoid's force from the set point, the
        // spring's rise with the lift and the damping; the rail's pressure pushes on the seat area.
        let preload = k[self.f_preload];
        op.solenoid_force = (p.valve.force_n(op.set_point) - preload).max(R::from(0.0));
        op.closing_force = preload + op.solenoid_force;
        let preload_elongation = preload / p.spring.stiffness_n_per_m;
        op.net_opening_force = self.net_opening_force(k, &p);
        if open {
            op.valve_acceleration = p.poppet.acceleration_m_per_s2(op.net_opening_force);
            op.relief_flow = p.valve.flow_m3_per_s(pressure, x);
            op.displaced_flow = p.valve.displaced_flow_m3_per_s(v);
        }
        // The high-pressure pump.
        let (angle, w_pump) = (self.pump_angle(k), k[self.pump_ratio] * k[self.speed_in]);
        let delivering = self.delivering(k);
        op.pump_flow = p.pump.delivery_flow_m3_per_s(angle, w_pump, &delivering);
        op.filling_flow = p.pump.filling_flow_m3_per_s(angle, w_pump, &delivering);
        op.pump_torque = p.pump.torque_n_m(angle, &delivering, pressure, k[self.p_feed]);
        // The injector of the current shot.
        op.needle_lift = p.needle.lift_m(k[self.since_start], k[self.shot_energizing]);
        let across = pressure - k[self.p_cylinder];
        op.injection_flow = p.nozzle.flow_m3_per_s(across, op.needle_lift);
        let (seat_drop, holes_drop) = p.nozzle.pressure_drops_pa(across, op.needle_lift);
        // The rail.
        op.leakage_flow = p.leakage.flow_m3_per_s(pressure);
        let rail = p.fuel.volume(k[self.v_rail], pressure);
        op.bulk_modulus = rail.bulk_modulus_pa;
        let net_inflow = op.pump_flow - op.injection_flow - op.relief_flow - op.leakage_flow - op.displaced_flow;
        op.pressure_rate = rail.pressure_rate_pa_per_s(net_inflow);
        // Powers (Table 3.1's signs: sources deliver, storages store, dissipations take out).
        op.p_engine = op.pump_torque * w_pump;
        op.p_feed = k[self.p_feed] * op.filling_flow;
        op.p_rail = rail.power_w(pressure, op.pressure_rate);
        op.p_leakage = p.leakage.power_w(pressure);
        op.p_relief = pressure * op.relief_flow;
        if open {
            op.p_valve_mass = p.poppet.power_w(op.valve_acceleration, v);
            op.p_valve_spring = p.spring.spring_power_w(x + preload_elongation, v);
            op.p_valve_damping = p.spring.damper_power_w(v);
            op.p_solenoid = -op.solenoid_force * v;
        }
        op.p_needle_seats = seat_drop * op.injection_flow;
        op.p_nozzle_holes = holes_drop * op.injection_flow;
        op.p_cylinders = -k[self.p_cylinder] * op.injection_flow;
        op
    }
}

impl Model for CommonRailInjection {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "CommonRailInjection",
            description: "Common-rail direct injection system (chapter 3, section 3.4.3, Figure 3.20, Table 3.7): boost pump, engine-driven three-plunger \
                          high-pressure pump with check valves, rail accumulator (fuel bulk modulus rising with pressure), spring-loaded \
                          pressure-control valve with its poppet's mass, spring and damper, and one injector per cylinder (needle, seat and nozzle \
                          holes) fired in the engine's order; the rail pressure, its ripple, the injected quantity per shot and the relief flow",
            // Two engine cycles at 2000 rpm.
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 0.12, step_size: 2e-4 },
            // Fastest modes: the poppet on its spring (about 800 Hz, damping ratio 0.5) and the
            // rail's regulation by the valve (about 2.6 ms); not stiff.
            solver: Solver::ExplicitRungeKutta,
            documentation: documentation::HTML,
        }
    }

    /// Measured (tests/python/accuracy_table.py, against rtol 1e-10): the needle seats' activity, a
    /// quadrature of their power riding on the steps the states' error control takes, is off by
    /// 6.8e-3 of its range at rtol 1e-4 and 2.9e-4 at 1e-5 (the seat's power is a hump at small
    /// lift inside each 0.2 ms ramp of the needle, which the rail pressure and the shot volume
    /// let the solver step across); at 1e-6 every output is within 6.6e-6 of its range.
    fn tolerance_floor(&self, _k: &Knowns) -> Option<f64> {
        Some(1e-6)
    }

    fn declare(d: &mut Declarations) -> Self {
        let seat = 0.6e-3;
        CommonRailInjection {
            cylinders: d.integer_parameter("cylinders", 4).range(4, 6).describe(
                "Number of cylinders, one injector each, fired in the inline engine's order (4: 1-3-4-2, 5: 1-2-4-5-3, 6: 1-5-3-6-2-4), \
                 one firing every 720 / n degrees of crank angle",
            ),
            advance: d.parameter("injection_advance", 4f64.to_radians(), "rad").nominal(0.1).min(-PI / 2.0).max(PI / 2.0).describe(
                "Start of injection before each cylinder's firing top dead centre (crank angle; 4 degrees: a main injection at 2000 rpm, part load)",
            ),
            pump_ratio: d.parameter("pump_ratio", 2.0 / 3.0, "1").positive().max(2.0).describe(
                "Pump shaft speed over engine speed (2/3: the pump's three plungers deliver one stroke per injection of a four-cylinder engine; \
                 a Mercedes OM647's CP3 turns at 1.3 times the camshaft's speed)",
            ),
            pump_phase: d.parameter("pump_phase", 0.0, "rad").min(-PI).max(PI).describe("Pump shaft angle when the crank angle is 0 (plunger 1 at its bottom dead centre)"),
            p_feed: d.parameter("p_feed", 0.3e6, "Pa").min(0.0).describe(
                "Delivery pressure of the low-pressure (boost) pump at the high-pressure pump's inlet (gauge; an electric in-tank or gear pump, some 3 bar)",
            ),
            plunger_diameter: d.parameter("plunger_diameter", 6.5e-3, "m").positive().nominal(6.5e-3).describe("Diameter of each of the three plungers (6.5 mm)"),
            eccentricity: d.parameter("eccentricity", 3.5e-3, "m").positive().nominal(3.5e-3).describe(
                "Eccentricity of the pump shaft's cam (stroke 2 e = 7 mm): 0.697 cm3 per pump revolution with the three plungers, a CP1-class pump",
            ),
            v_rail: d.parameter("V_rail", 20e-6, "m3").positive().nominal(20e-6).describe("Fuel volume of the rail with its lines to the pump and the injectors (20 cm3)"),
            b_fuel_0: d.parameter("B_fuel_0", 1.5e9, "Pa").positive().describe("Bulk modulus of diesel fuel at 0 Pa (gauge), about 1.5 GPa near 40 degrees C"),
            db_dp: d.parameter("dB_fuel_dp", 7.5, "1").min(0.0).max(20.0).describe(
                "Rise of the fuel's bulk modulus with pressure, B = B_fuel_0 + dB_fuel_dp p (2.6 GPa at 145 MPa, 2.85 GPa at 180 MPa)",
            ),
            r_leakage: d.parameter("R_leakage", defaults::leakage(), "Pa.s/m3").positive().describe(
                "Laminar leakage resistance from the rail to the return: the injectors' guides and the pump's plungers, 0.5 cm3/s at 145 MPa",
            ),
            seat_diameter: d.parameter("valve_seat_diameter", seat, "m").positive().nominal(seat).describe("Seat diameter of the pressure-control valve's ball (0.6 mm: 0.283 mm2)"),
            cd_valve: d.parameter("Cd_valve", 0.7, "1").positive().max(1.0).describe("Discharge coefficient of the valve's curtain orifice pi d x (sharp seat)"),
            m_valve: d.parameter("m_valve", 3e-3, "kg").positive().nominal(3e-3).describe("Moving mass of the valve: ball, armature and a third of the spring (3 g)"),
            k_valve: d.parameter("k_valve", 7.5e4, "N/m").positive().describe(
                "Stiffness of the valve's spring (75 N/mm: with the seat it sets the regulation's droop, 2.65 MPa per 10 um of lift)",
            ),
            c_valve: d.parameter("c_valve", 15.0, "N.s/m").min(0.0).describe("Viscous damping of the valve's armature in its fuel-filled chamber (damping ratio 0.5 on its spring)"),
            f_preload: d.parameter("F_spring_preload", defaults::spring_preload(seat), "N").min(0.0).describe(
                "Preload of the valve's spring with the valve seated: alone it holds 10 MPa (Bosch's pressure-control valve: about 100 bar without current)",
            ),
            holes: d.integer_parameter("nozzle_holes", 7).describe("Number of spray holes of each injector's nozzle (7; at least 1)"),
            hole_diameter: d.parameter("hole_diameter", 0.13e-3, "m").positive().nominal(0.13e-3).describe("Diameter of each spray hole (0.13 mm)"),
            cd_nozzle: d.parameter("Cd_nozzle", 0.75, "1").positive().max(1.0).describe("Discharge coefficient of the needle seat and the spray holes (hydro-eroded holes)"),
            needle_seat_diameter: d.parameter("needle_seat_diameter", 1.5e-3, "m").positive().nominal(1.5e-3).describe("Diameter of the needle's seat line on the nozzle cone (1.5 mm)"),
            needle_seat_angle: d.parameter("needle_seat_half_angle", 30f64.to_radians(), "rad").positive().max(PI / 2.0).describe(
                "Half angle of the nozzle's seat cone (30 degrees): the seat gap is lift x sin(angle)",
            ),
            lift_max: d.parameter("needle_lift_max", 0.2e-3, "m").positive().nominal(0.2e-3).describe("Full needle lift, at its stop (0.2 mm)"),
            opening_speed: d.parameter("needle_opening_speed", 1.0, "m/s").positive().describe(
                "Needle speed while opening, set by the control chamber's outlet throttle (1 m/s: 0.2 ms to full lift)",
            ),
            closing_speed: d.parameter("needle_closing_speed", 1.2, "m/s").positive().describe("Needle speed while closing, set by the control chamber's inlet throttle (1.2 m/s)"),
            opening_delay: d.parameter("opening_delay", 0.3e-3, "s").min(0.0).nominal(0.3e-3).describe(
                "Delay from the start of energizing to the needle's lift-off: the solenoid's current rise, the control valve's opening and the control chamber's pressure drop (0.3 ms)",
            ),
            closing_delay: d.parameter("closing_delay", 0.3e-3, "s").min(0.0).nominal(0.3e-3).describe(
                "Delay from the end of energizing to the needle's start of closing: the armature's fall and the control chamber's refilling (0.3 ms)",
            ),
            p_cylinder: d.parameter("p_cylinder", 6e6, "Pa").min(0.0).describe(
                "Pressure in the combustion chamber during injection, the back pressure of the spray (gauge; about 6 MPa of compression near top dead centre)",
            ),
            step_time: d.parameter("step_time", 1.0, "s").min(0.0).describe(
                "Built-in profile: time at which the set point and the energizing time step by set_point_step and energizing_time_step (beyond the stop time: none)",
            ),
            set_point_step: d.parameter("set_point_step", 0.0, "Pa").min(-150e6).max(100e6).describe("Built-in profile: step of the rail pressure set point at step_time"),
            energizing_step: d.parameter("energizing_time_step", 0.0, "s").min(-ENERGIZING_TIME_MAX_S).max(ENERGIZING_TIME_MAX_S).nominal(1e-3).describe(
                "Built-in profile: step of the energizing time at step_time (a load step)",
            ),
            speed_in: d.input("engine_speed", defaults::ENGINE_SPEED, "rad/s").min(0.0).max(ENGINE_SPEED_MAX_RAD_PER_S).describe(
                "Engine (crankshaft) speed, 0 to 5000 rpm (2000 rpm = 209.44 rad/s)",
            ),
            set_point_in: d.input("rail_pressure_set_point", defaults::SET_POINT, "Pa").min(0.0).max(250e6).describe(
                "Rail pressure set point: the pressure-control valve's solenoid adds the force that makes its opening pressure this (145 MPa), above what its spring holds alone",
            ),
            energizing_in: d.input("energizing_time", 0.5e-3, "s").min(0.0).nominal(0.5e-3).describe(
                "Injection command: the injectors' energizing time per shot (0.5 ms: about 24 mm3 at 149 MPa), latched at each start of injection; the driver gives at most 3 ms",
            ),
            crank: d.calculated_state("crank_angle", "rad").nominal(1.0).describe(
                "Crank angle from cylinder 1's firing top dead centre; the engine cycle is 4 pi. Starts 1 degree after cylinder 1's start of injection, \
                 1 degree - injection_advance",
            ),
            pressure: d.state("p_rail", 149e6, "Pa").nominal(1e8).describe("Rail pressure (gauge); starts near its mean with the defaults"),
            lift: d.calculated_state("x_valve", "m").nominal(1e-5).describe(
                "Lift of the pressure-control valve's ball off its seat (starts where the spring balances the rail pressure)",
            ),
            speed: d.state("v_valve", 0.0, "m/s").nominal(1e-2).describe("Speed of the valve's ball, opening"),
            since_start: d.calculated_state("t_since_injection_start", "s").nominal(1e-3).describe(
                "Time since the last start of injection (energizing): a timer set to 0 at each start; starts at the time the engine takes to turn 1 degree",
            ),
            shot_energizing: d.calculated_state("shot_energizing_time", "s").nominal(1e-3).describe(
                "Energizing time of the current (or last) shot, latched at its start from the command; held between (der = 0)",
            ),
            shot_volume: d.state("shot_volume", 0.0, "m3").nominal(1e-8).describe(
                "Volume injected since the last start of injection: the current shot, then its whole quantity until the next start",
            ),
            last_shot: d.state("last_shot_volume", 0.0, "m3").nominal(1e-8).describe(
                "Volume of the last complete shot, latched at each start of injection; held between (der = 0)",
            ),
            slot: d.mode("firing_slot", NOT_SYNCHRONIZED).range(NOT_SYNCHRONIZED, 5).describe(
                "Place in the firing order of the last start of injection (0 .. cylinders - 1; -1 until synchronized with the crank angle at initialization)",
            ),
            plunger_modes: [1, 2, 3].map(|j| {
                d.mode(&format!("plunger_{j}_delivering"), 0).range(0, 1).describe(&format!(
                    "Check valves of plunger {j}: 1 while it rises and delivers into the rail, 0 while it falls and fills from the boost pump"
                ))
            }),
            valve_mode: d.mode("valve_open", PoppetValve::SEATED).range(0, 1).describe("Pressure-control valve: 1 lifted off its seat, 0 seated"),
            soi: d.event_indicator("start_of_injection", "crank angle left to the next start of injection in the firing order"),
            check_valves: [1, 2, 3].map(|j| {
                d.event_indicator(&format!("plunger_{j}_dead_centre"), &format!("plunger {j}'s velocity factor sin(phi), signed to be positive while its check valves hold"))
            }),
            seat: d.event_indicator("valve_seat", "open: the valve's lift; seated: the closing force's margin over the rail pressure's force"),
            powers: declare_elements(d),
            y_pressure: {
                declare_neglected(d);
                d.output("rail_pressure", "Pa").describe("Rail pressure (gauge): its mean, ripple and dips at each shot")
            },
            y_set_point: d.output("set_point", "Pa").describe("Rail pressure set point: rail_pressure_set_point plus the built-in profile"),
            y_opening: d.output("valve_opening_pressure", "Pa").describe(
                "Opening pressure of the pressure-control valve, (F_spring_preload + F_solenoid) / seat area: the set point, or the spring's alone below it",
            ),
            y_pump_flow: d.output("pump_flow", "m3/s").describe("Flow the high-pressure pump delivers into the rail (the rising plungers)"),
            y_injection_flow: d.output("injection_flow", "m3/s").describe("Flow through the injector that is spraying (injection rate)"),
            y_relief_flow: d.output("relief_flow", "m3/s").describe("Flow the pressure-control valve returns to the tank"),
            y_leakage_flow: d.output("leakage_flow", "m3/s").describe("Leakage from the rail to the return, p / R_leakage"),
            y_valve_lift: d.output("valve_lift", "m").describe("Lift of the pressure-control valve"),
            y_needle_lift: d.output("needle_lift", "m").describe("Needle lift of the injector that is spraying (0 between shots)"),
            y_shot: d.output("injected_volume", "m3").describe("Volume injected since the last start of injection (the shot in progress, then the whole shot)"),
            y_last_shot: d.output("injected_volume_last_shot", "m3").describe("Volume of the last complete shot (changes at each start of injection)"),
            y_cylinder: d.output("firing_cylinder", "1").discrete().describe("Cylinder whose injector fired last (the run starts at cylinder 1's start of injection)"),
            y_torque: d.output("pump_torque", "N.m").describe("Torque the high-pressure pump takes from the crankshaft (its shaft's torque times the drive ratio)"),
            y_bulk: d.output("bulk_modulus", "Pa").describe("Bulk modulus of the fuel at the rail pressure, B_fuel_0 + dB_fuel_dp p"),
            displacement: d.calculated_parameter("pump_displacement", "m3").describe("Volume the pump displaces per revolution of its shaft, 3 x 2 e pi d^2 / 4"),
            hole_area: d.calculated_parameter("nozzle_hole_area", "m2").describe("Total area of each nozzle's spray holes, n pi d^2 / 4"),
            valve_seat_area: d.calculated_parameter("valve_seat_area", "m2").describe("Area the rail pressure pushes on the valve's ball, pi d^2 / 4"),
            firing_interval: d.calculated_parameter("firing_interval", "rad").describe("Crank angle between two injections, 4 pi / cylinders"),
        }
    }

    fn check(&self, k: &Knowns) -> Result<(), String> {
        if k[self.holes] < 1 {
            return Err(format!("nozzle_holes = {} must be at least 1", k[self.holes]));
        }
        // One shot at a time: the longest one must end before the next cylinder's start of
        // injection at the highest engine speed.
        let p = self.parts(k);
        let longest = p.needle.end_s(ENERGIZING_TIME_MAX_S);
        let shortest_interval = self.firing_interval_rad(k) / ENGINE_SPEED_MAX_RAD_PER_S;
        if longest.is_nan() || longest >= shortest_interval {
            return Err(format!(
                "the longest shot ({longest:.4e} s: energizing {ENERGIZING_TIME_MAX_S} s, opening_delay, closing_delay and the closing at \
                 needle_closing_speed) must end before the next start of injection at 5000 rpm ({shortest_interval:.4e} s with {} cylinders): \
                 shorten opening_delay or closing_delay, or raise needle_opening_speed or needle_closing_speed",
                self.cylinder_count(k)
            ));
        }
        Ok(())
    }

    fn initial_states<R: Real>(&self, k: &Knowns<R>, x0: &mut InitialStates<R>) {
        // The valve starts where its spring balances the rail pressure (seated below the opening pressure).
        let p = self.parts(k);
        let preload = k[self.f_preload];
        let solenoid = (p.valve.force_n(self.set_point(k)) - preload).max(R::from(0.0));
        x0[self.lift] = ((p.valve.force_n(k[self.pressure]) - preload - solenoid) / p.spring.stiffness_n_per_m).max(R::from(0.0));
        // The run starts 1 degree after cylinder 1's start of injection, its shot latched (its
        // needle not lifted yet at any speed up to 5000 rpm with the default opening delay).
        x0[self.crank] = R::from(START_PAST_INJECTION_RAD) - k[self.advance];
        let w = k[self.speed_in];
        x0[self.since_start] = if w > 0.0 { R::from(START_PAST_INJECTION_RAD) / w } else { R::from(NO_SHOT_TIMER_S) };
        x0[self.shot_energizing] = self.energizing_time(k);
    }

    fn next_time_event(&self, k: &Knowns, after: f64) -> Option<f64> {
        // The needle's kinks ahead of the shot's timer (one within rounding of it is the one just
        // reached), and the profile's step.
        let needle = self.parts(k).needle;
        let since = k[self.since_start];
        let kinks = needle.kinks_s(k[self.shot_energizing]).into_iter().filter(|s| s - since > TIMER_ROUNDING_S).map(|s| k.time() + (s - since));
        let steps = self.profile(k).into_iter().filter(|r| r.height != 0.0).filter_map(|r| r.next_kink(after));
        kinks.chain(steps).filter(|t| *t > after).min_by(f64::total_cmp)
    }

    fn event_indicators(&self, k: &Knowns, z: &mut EventIndicators) {
        let slot = k[self.slot];
        z[self.soi] = if (0..self.cylinder_count(k)).contains(&slot) { self.firing_interval_rad(k) - self.past_start_rad(k, slot) } else { 1.0 };
        let pump = RadialPistonPump::three_plungers(k[self.plunger_diameter], k[self.eccentricity]);
        let angle = self.pump_angle(k);
        for (j, (indicator, mode)) in self.check_valves.iter().zip(self.plunger_modes).enumerate() {
            z[*indicator] = pump.check_valve_indicator(j, k[mode] == 1, angle);
        }
        let p = self.parts(k);
        z[self.seat] = p.valve.seat_indicator(k[self.valve_mode], k[self.lift], self.net_opening_force(k, &p));
    }

    fn update_modes(&self, k: &Knowns, next: &mut ModeUpdate) {
        // The firing slot: a start of injection where the crank angle reaches the next slot's.
        let n = self.cylinder_count(k);
        let slot = k[self.slot];
        let interval = self.firing_interval_rad(k);
        if !(0..n).contains(&slot) {
            // Initialization (or a cylinder count changed): synchronize, no shot.
            next[self.slot] = self.slot_of_crank(k);
        } else {
            let past = self.past_start_rad(k, slot);
            if past >= interval && past < 1.5 * interval {
                // The next cylinder's start of injection: a new shot from now, the last one latched.
                next[self.slot] = (slot + 1) % n;
                next.reinit(self.since_start, 0.0);
                next.reinit(self.shot_energizing, self.energizing_time(k));
                next.reinit(self.last_shot, k[self.shot_volume]);
                next.reinit(self.shot_volume, 0.0);
            } else if !(-0.25 * interval..1.5 * interval).contains(&past) {
                // The crank angle was set elsewhere (not the rounding of a start just handled):
                // synchronize, no shot.
                next[self.slot] = self.slot_of_crank(k);
            }
        }
        // The plungers' check valves: delivering while rising.
        let p = self.parts(k);
        let angle = self.pump_angle(k);
        for (j, mode) in self.plunger_modes.iter().enumerate() {
            next[*mode] = i32::from(p.pump.delivers(j, angle));
        }
        // The valve's seat.
        let (mode, lands) = p.valve.next_mode(k[self.valve_mode], k[self.lift], k[self.speed], self.net_opening_force(k, &p));
        next[self.valve_mode] = mode;
        if lands {
            next.reinit(self.lift, 0.0);
            next.reinit(self.speed, 0.0);
        }
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let op = self.operate(k);
        der[self.crank] = k[self.speed_in];
        der[self.since_start] = R::from(1.0);
        der[self.pressure] = op.pressure_rate;
        if k[self.valve_mode] == PoppetValve::OPEN {
            der[self.lift] = k[self.speed];
            der[self.speed] = op.valve_acceleration;
        }
        der[self.shot_volume] = op.injection_flow;
        let p = &self.powers;
        der.power(p.engine, op.p_engine);
        der.power(p.feed, op.p_feed);
        der.power(p.rail, op.p_rail);
        der.power(p.leakage, op.p_leakage);
        der.power(p.relief, op.p_relief);
        der.power(p.valve_mass, op.p_valve_mass);
        der.power(p.valve_spring, op.p_valve_spring);
        der.power(p.valve_damping, op.p_valve_damping);
        der.power(p.solenoid, op.p_solenoid);
        der.power(p.needle_seats, op.p_needle_seats);
        der.power(p.nozzle_holes, op.p_nozzle_holes);
        der.power(p.cylinders, op.p_cylinders);
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        let op = self.operate(k);
        let p = self.parts(k);
        out[self.y_pressure] = k[self.pressure];
        out[self.y_set_point] = op.set_point;
        out[self.y_opening] = p.valve.opening_pressure_pa(op.closing_force);
        out[self.y_pump_flow] = op.pump_flow;
        out[self.y_injection_flow] = op.injection_flow;
        out[self.y_relief_flow] = op.relief_flow;
        out[self.y_leakage_flow] = op.leakage_flow;
        out[self.y_valve_lift] = k[self.lift];
        out[self.y_needle_lift] = op.needle_lift;
        out[self.y_shot] = k[self.shot_volume];
        out[self.y_last_shot] = k[self.last_shot];
        let slot = k[self.slot];
        let order = FIRING_ORDERS[(self.cylinder_count(k) - 4) as usize];
        out[self.y_cylinder] = if (0..order.len() as i32).contains(&slot) { R::from(f64::from(order[slot as usize])) } else { R::from(0.0) };
        out[self.y_torque] = op.pump_torque * k[self.pump_ratio];
        out[self.y_bulk] = op.bulk_modulus;
        out[self.displacement] = p.pump.displacement_m3_per_rev();
        out[self.hole_area] = p.nozzle.hole_area_m2();
        out[self.valve_seat_area] = p.valve.seat_area_m2();
        out[self.firing_interval] = R::from(self.firing_interval_rad(k));
    }
}

/// Table 3.7: the elements the model keeps, component by component.
fn declare_elements(d: &mut Declarations) -> Powers {
    let engine_effect = Effect { domains: &[Domain::Rotational], kind: Kind::Source, what: "crankshaft driving the pump (speed source, input engine_speed)" };
    let engine = d.element("engine", "Engine", engine_effect).describe("the engine's crankshaft, which drives the high-pressure pump: power T_pump w_pump");
    d.element("pump_drive", "High-pressure pump", Effect { what: "pump drive (gear or belt, ratio pump_ratio)", ..Reducer::RATIO })
        .describe("the drive from the crankshaft to the pump's shaft, w_pump = pump_ratio w_engine");
    d.element("plungers", "High-pressure pump", RadialPistonPump::PUMP)
        .describe("the three plungers on the pump's eccentric with their inlet and outlet check valves (ideal): Q = A e w sin(phi) while rising");
    let feed_effect = Effect { domains: &[Domain::Hydraulic], kind: Kind::Source, what: "feed pressure (pressure source p_feed)" };
    let feed = d.element("feed_pump", "Low-pressure (boost) pump", feed_effect).describe("the boost pump filling the falling plungers at p_feed: power p_feed Q_fill");
    let rail_effect = Effect { what: "fuel compressibility (C = V / B(p))", ..components::FluidVolume::COMPRESSIBILITY };
    let rail = d.element("rail", "Rail", rail_effect).describe("the fuel in the rail and its lines, C = V_rail / B(p): power p Q_net");
    let leakage = d
        .element("leakage", "Injectors", Effect { what: "static leakage of the injectors and the pump (Q = p / R)", ..LaminarLeakage::LEAKAGE })
        .describe("the leakage from the rail to the return: power p^2 / R_leakage");
    d.element("valve_seat", "Pressure-control valve", PoppetValve::SEAT).describe("the ball on its seat: F = A p on the ball, Q = A v displaced as it lifts");
    let relief = d.element("relief_orifice", "Pressure-control valve", PoppetValve::ORIFICE).describe("the valve's opening to the return: power p Q_relief");
    let valve_mass = d.element("valve_mass", "Pressure-control valve", Effect { what: "ball and armature mass", ..Mass::MASS }).describe("the valve's moving mass: power m v dv/dt");
    let valve_spring = d
        .element("valve_spring", "Pressure-control valve", Effect { what: "spring (with its preload)", ..TranslationalSpring::STIFFNESS })
        .describe("the valve's spring: power (F_spring_preload + k x) v");
    let valve_damping = d
        .element("valve_damping", "Pressure-control valve", Effect { what: "armature damping", ..TranslationalSpring::DAMPING })
        .describe("the damping of the ball and armature: power c v^2");
    let solenoid_effect = Effect { domains: &[Domain::Translational], kind: Kind::Source, what: "solenoid force (from the set point)" };
    let solenoid = d.element("valve_solenoid", "Pressure-control valve", solenoid_effect).describe("the solenoid's closing force on the armature: power -F_solenoid v");
    let needle_seats = d.element("needle_seats", "Injectors", InjectorNozzle::SEAT).describe("the needle seats of the injectors: power dp_seat Q_injection");
    let nozzle_holes = d.element("nozzle_holes", "Injectors", InjectorNozzle::HOLES).describe("the spray holes of the injectors: power dp_holes Q_injection");
    let charge_effect = Effect { domains: &[Domain::Hydraulic], kind: Kind::Source, what: "cylinder back pressure (p_cylinder)" };
    let cylinders = d.element("cylinder_charge", "Combustion chambers", charge_effect).describe("the compressed charge the fuel is sprayed into: power -p_cylinder Q_injection");
    Powers { engine, feed, rail, leakage, relief, valve_mass, valve_spring, valve_damping, solenoid, needle_seats, nozzle_holes, cylinders }
}

/// The effects Table 3.7 could list but the model leaves out, each with the reason.
fn declare_neglected(d: &mut Declarations) {
    use components::{CoulombFriction, Inductor, Resistor};
    let pump_friction = Effect { what: "friction of the pump's eccentric, tappets and plungers", ..CoulombFriction::FRICTION };
    d.neglected("High-pressure pump", pump_friction, "a mechanical loss on the engine's side: it changes the engine's torque, not the fuel's pressure");
    let dead_volume = Effect { what: "compressibility of the plungers' dead volume", ..components::FluidVolume::COMPRESSIBILITY };
    d.neglected(
        "High-pressure pump",
        dead_volume,
        "each stroke first compresses its dead volume to the rail pressure (a few degrees of lost delivery); the check valves are ideal",
    );
    let check_valves = Effect { what: "check valves' throttling and inertia", ..PoppetValve::ORIFICE };
    d.neglected("High-pressure pump", check_valves, "taken as ideal: open without a pressure drop while the plunger delivers or fills");
    let line_inertia = Effect { domains: &[Domain::Hydraulic], kind: Kind::StorageI, what: "fuel inertia in the lines (pressure waves)" };
    d.neglected(
        "Rail",
        line_inertia,
        "the lines' waves (some 1.3 km/s over 0.2-0.5 m: 0.6-1.6 kHz) are above the injection and pump harmonics the rail pressure's stability is about",
    );
    let flow_force = Effect { domains: &[Domain::Hydraulic, Domain::Translational], kind: Kind::Source, what: "flow force of the jet on the ball" };
    d.neglected("Pressure-control valve", flow_force, "it lowers the effective closing force by a fraction; lumped into the droop of the spring");
    let coil_resistance = Effect { what: "solenoid windings' resistance (valve and injectors)", ..Resistor::RESISTANCE };
    d.neglected("Injectors", coil_resistance, "the drivers set the currents: the electrical side is a command, its timing kept as the delays");
    let coil_inductance = Effect { what: "solenoid windings' inductance", ..Inductor::INDUCTANCE };
    d.neglected("Injectors", coil_inductance, "its current rise is part of the opening delay");
    let needle_mass = Effect { what: "needle and control piston mass and spring", ..Mass::MASS };
    d.neglected(
        "Injectors",
        needle_mass,
        "the needle moves at the speed the control chamber's throttles let it (a servo-hydraulic injector): its lift is the trapezoid",
    );
    let control_flow = Effect { what: "control-chamber (servo) flow to the return", ..LaminarLeakage::LEAKAGE };
    d.neglected("Injectors", control_flow, "a few mm3 per shot of control quantity, lumped with the static leakage");
    let heating = Effect { domains: &[Domain::Thermal], kind: Kind::Dissipation, what: "heating of the fuel by throttling" };
    d.neglected("Rail", heating, "the fuel's temperature (and with it B and rho) taken constant over a few engine cycles");
}

fmu_runtime::export_fmu!(CommonRailInjection);
