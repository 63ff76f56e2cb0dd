//! BoosterNozzle: the launcher booster nozzle of chapter section 3.4.1.1, Figure 3.15 (question 2:
//! the dominant effect of each part). The nozzle swivels about a pivot on its flexible bearing
//! (laminated elastomer and steel shims) in two rotational degrees of freedom, pitch and yaw; each
//! is driven by a hydraulic servo-actuator: a servo-valve feeds a double-acting cylinder whose rod
//! pushes on the nozzle at the lever arm r, whose body is held by its anchoring on the motor case.
//! The gases load the nozzle with a thrust-offset torque, the air with an aerodynamic torque
//! (inputs). A position loop per axis (the servo-valve's flow proportional to the stroke error)
//! is closed inside the FMU. The contract: `docs/booster-nozzle-spec.md`.
//!
//! Per axis (small angles; pitch and yaw are identical and uncoupled):
//! * nozzle: J dw/dt = r A dp - K_b theta - D_b w + M_offset + M_aero, dtheta/dt = w;
//! * actuator body on its anchoring: m_a dv_b/dt = -A dp - K_a x_b - D_a v_b, dx_b/dt = v_b;
//! * oil (two chambers at mid stroke in series, C = V / (2 B)): C d(dp)/dt = Q_v - A (r w - v_b) - dp / R;
//! * servo-valve and loop: Q_v = A K_v (r theta_cmd - y), y = r theta - x_b the stroke.
//!
//! The chapter gives no values: each default is argued from public data in `documentation.rs`
//! (the FMU's page) and the spec.

use components::{DoubleActingCylinder, FluidVolume, Inertia, LaminarLeakage, Lever, Mass, Ramp, TorsionSpring, TranslationalSpring, TwoDegreesOfFreedom};
use fmu_runtime::prelude::*;
use std::f64::consts::PI;

mod documentation;

/// The defaults, argued in documentation.rs and docs/booster-nozzle-spec.md.
mod defaults {
    use components::DoubleActingCylinder;
    use std::f64::consts::PI;

    /// Degrees to radians.
    pub fn deg(x: f64) -> f64 {
        x * PI / 180.0
    }
    /// The Vega P80 nozzle about its pivot (M. Budinger's Vega TVC course, SizingLab/sizing_course).
    pub const J_NOZZLE_KG_M2: f64 = 1.40e3;
    /// 15 200 N m/deg.
    pub fn k_bearing() -> f64 {
        15_200.0 * 180.0 / PI
    }
    /// 174 N m s/deg.
    pub fn d_bearing() -> f64 {
        174.0 * 180.0 / PI
    }
    /// The actuator's lever arm about the pivot.
    pub const ARM_M: f64 = 1.35;
    /// A 100 mm bore on a 50 mm through rod: 58.9 cm2, 122 kN at 20.7 MPa.
    pub fn cylinder() -> DoubleActingCylinder {
        DoubleActingCylinder::through_rod(0.100, 0.050)
    }
    /// K_v = 3 / 72 ms: the rigid loop's 5 % response time is the P80's 72 ms.
    pub const K_V_PER_S: f64 = 3.0 / 0.072;
    /// The anchoring's structural damping: 5 % of critical for the body alone on it, 2 zeta sqrt(K m).
    pub fn d_anchor(k_anchor: f64, m_actuator: f64) -> f64 {
        2.0 * 0.05 * (k_anchor * m_actuator).sqrt()
    }
    /// 2.26 MN (88 t in 107 s at 280 s of Isp) passing 5 mm from the pivot.
    pub const M_OFFSET_N_M: f64 = 2.26e6 * 5e-3;
}

/// One axis's handles: its states, inputs, outputs and elements.
struct Axis {
    /// Pitch takes the cos share of the built-in command and of the offset torque, yaw the sin share.
    is_pitch: bool,
    command_in: Input,
    m_aero: Input,
    theta: State,
    w: State,
    dp: State,
    phi_body: State,
    w_body: State,
    y_angle: Output,
    y_rate: Output,
    y_command: Output,
    y_force: Output,
    y_pressure: Output,
    y_hinge: Output,
    y_stroke: Output,
    y_anchoring: Output,
    y_valve_flow: Output,
    e_inertia: Element,
    e_bearing_stiffness: Element,
    e_bearing_damping: Element,
    e_oil: Element,
    e_leakage: Element,
    e_body: Element,
    e_anchoring: Element,
    e_anchoring_damping: Element,
    e_valve: Element,
    e_offset: Element,
    e_aero: Element,
}

pub struct BoosterNozzle {
    profile: IntegerParameter,
    j_nozzle: Parameter,
    k_bearing: Parameter,
    d_bearing: Parameter,
    r_arm: Parameter,
    a_piston: Parameter,
    v_chamber: Parameter,
    b_oil: Parameter,
    r_leakage: Parameter,
    m_actuator: Parameter,
    k_anchor: Parameter,
    d_anchor: Parameter,
    k_v: Parameter,
    m_offset: Parameter,
    offset_azimuth: Parameter,
    amplitude: Parameter,
    command_azimuth: Parameter,
    step_time: Parameter,
    sine_frequency: Parameter,
    pitch: Axis,
    yaw: Axis,
    k_oil: Local,
    f_actuator_nozzle: Local,
    f_actuator_body: Local,
    f_bearing: Local,
    k_servo_static: Local,
    m_nozzle_rod: Local,
}

/// The parts of one axis at the current parameter values (both axes are made of the same parts).
struct Parts<R = f64> {
    nozzle: Inertia<R>,
    bearing: TorsionSpring<R>,
    lever: Lever<R>,
    cylinder: DoubleActingCylinder<R>,
    /// One chamber at mid stroke.
    chamber: FluidVolume<R>,
    leakage: LaminarLeakage<R>,
    body: Mass<R>,
    anchoring: TranslationalSpring<R>,
    /// The loop's velocity gain: the valve's flow moves the rod at K_v times the stroke error.
    k_v: R,
}

impl<R: Real> Parts<R> {
    /// The two chambers seen from the pressure difference across the piston: C = V / (2 B).
    fn oil(&self) -> FluidVolume<R> {
        self.chamber.in_series(&self.chamber)
    }

    /// The piston on its two closed oil columns, k = 2 A^2 B / V.
    fn oil_stiffness_n_per_m(&self) -> R {
        self.cylinder.hydraulic_stiffness_n_per_m(&self.chamber, &self.chamber)
    }

    /// The undamped two-degree-of-freedom chain with the valve closed: the nozzle (theta) on its
    /// bearing, the oil column at the arm r, the actuator body (x_b) on its anchoring.
    fn chain(&self) -> TwoDegreesOfFreedom<R> {
        TwoDegreesOfFreedom::chain(
            self.nozzle.inertia_kg_m2,
            self.body.mass_kg,
            self.bearing.stiffness_n_m_per_rad,
            self.anchoring.stiffness_n_per_m,
            self.oil_stiffness_n_per_m(),
            self.lever.arm_m,
        )
    }

    /// The servo-actuator's static stiffness seen by the nozzle, N m/rad: a steady load F on the rod
    /// deflects the anchoring by F / K_a and, through the leakage the valve must make up
    /// (dp / R = A K_v (stroke error)), the stroke by F / (A^2 R K_v); the nozzle turns by their
    /// sum over r. Written r^2 K_a A^2 R K_v / (K_a + A^2 R K_v): 0 without the loop (K_v = 0).
    fn servo_static_stiffness_n_m_per_rad(&self) -> R {
        let loop_stiffness = self.cylinder.piston_area_m2.powi(2) * self.leakage.resistance_pa_s_per_m3 * self.k_v;
        let ka = self.anchoring.stiffness_n_per_m;
        self.lever.arm_m.powi(2) * ka * loop_stiffness / (ka + loop_stiffness)
    }
}

/// One axis at one instant.
#[derive(Default)]
struct Operating<R = f64> {
    command: R,
    stroke: R,
    valve_flow: R,
    pressure_rate: R,
    acceleration: R,
    body_acceleration: R,
    force: R,
    hinge_moment: R,
    p_inertia: R,
    p_bearing_stiffness: R,
    p_bearing_damping: R,
    p_oil: R,
    p_leakage: R,
    p_body: R,
    p_anchoring: R,
    p_anchoring_damping: R,
    p_valve: R,
    p_offset: R,
    p_aero: R,
}

/// The servo-valve as Table 3.1 sees it: a modulated flow source fed by the hydraulic supply.
const SERVO_VALVE: Effect = Effect { domains: &[Domain::Hydraulic], kind: Kind::Source, what: "servo-valve (flow source Q = A K_v (y_cmd - y))" };
/// The gases' torque on the nozzle: thrust passing off the pivot.
const OFFSET_TORQUE: Effect = Effect { domains: &[Domain::Rotational], kind: Kind::Source, what: "thrust offset torque (gases)" };
/// The air's torque on the nozzle (input).
const AERO_TORQUE: Effect = Effect { domains: &[Domain::Rotational], kind: Kind::Source, what: "aerodynamic torque (input)" };

impl BoosterNozzle {
    fn parts<R: Real>(&self, k: &Knowns<R>) -> Parts<R> {
        Parts {
            nozzle: Inertia { inertia_kg_m2: k[self.j_nozzle] },
            bearing: TorsionSpring { stiffness_n_m_per_rad: k[self.k_bearing], damping_n_m_s_per_rad: k[self.d_bearing] },
            lever: Lever { arm_m: k[self.r_arm] },
            cylinder: DoubleActingCylinder { piston_area_m2: k[self.a_piston] },
            chamber: FluidVolume { volume_m3: k[self.v_chamber], bulk_modulus_pa: k[self.b_oil] },
            leakage: LaminarLeakage { resistance_pa_s_per_m3: k[self.r_leakage] },
            body: Mass { mass_kg: k[self.m_actuator] },
            anchoring: TranslationalSpring { stiffness_n_per_m: k[self.k_anchor], damping_n_s_per_m: k[self.d_anchor] },
            k_v: k[self.k_v],
        }
    }

    /// The built-in profile's deflection (before it is split into pitch and yaw), rad.
    fn profile_value<R: Real>(&self, k: &Knowns<R>) -> R {
        let (a, t0, t) = (k[self.amplitude], k[self.step_time], k.time());
        match k[self.profile] {
            1 => Ramp { start_s: t0, duration_s: R::from(0.0), height: a }.value(R::from(t)),
            2 if t >= t0.value() => a * (k[self.sine_frequency] * (2.0 * PI) * (R::from(t) - t0)).sin(),
            _ => R::from(0.0),
        }
    }

    /// The axis's share of a vector of magnitude 1 at an azimuth (pitch cos, yaw sin).
    fn share<R: Real>(axis: &Axis, azimuth: R) -> R {
        if axis.is_pitch {
            azimuth.cos()
        } else {
            azimuth.sin()
        }
    }

    fn operate<R: Real>(&self, axis: &Axis, p: &Parts<R>, k: &Knowns<R>) -> Operating<R> {
        let (theta, w, dp) = (k[axis.theta], k[axis.w], k[axis.dp]);
        // The body's states are its displacement and velocity referred to the nozzle angle (x / r).
        let (x_b, v_b) = (p.lever.rod_velocity_m_per_s(k[axis.phi_body]), p.lever.rod_velocity_m_per_s(k[axis.w_body]));
        let command = self.profile_value(k) * Self::share(axis, k[self.command_azimuth]) + k[axis.command_in];
        let m_offset = k[self.m_offset] * Self::share(axis, k[self.offset_azimuth]);
        let m_aero = k[axis.m_aero];
        // The stroke y = r theta - x_b (rod end less body) and its rate.
        let stroke = p.lever.rod_velocity_m_per_s(theta) - x_b;
        let stroke_rate = p.lever.rod_velocity_m_per_s(w) - v_b;
        let stroke_command = p.lever.rod_velocity_m_per_s(command);
        let valve_flow = p.cylinder.flow_m3_per_s(p.k_v * (stroke_command - stroke));
        let oil = p.oil();
        let pressure_rate = oil.pressure_rate_pa_per_s(valve_flow - p.cylinder.flow_m3_per_s(stroke_rate) - p.leakage.flow_m3_per_s(dp));
        let force = p.cylinder.force_n(dp);
        let hinge_moment = p.lever.hinge_moment_n_m(force);
        let acceleration = p.nozzle.acceleration_rad_per_s2(hinge_moment - p.bearing.torque_n_m(theta, w) + m_offset + m_aero);
        let body_acceleration = p.body.acceleration_m_per_s2(-force - p.anchoring.force_n(x_b, v_b));
        Operating {
            command,
            stroke,
            valve_flow,
            pressure_rate,
            acceleration,
            body_acceleration,
            force,
            hinge_moment,
            p_inertia: p.nozzle.power_w(acceleration, w),
            p_bearing_stiffness: p.bearing.spring_power_w(theta, w),
            p_bearing_damping: p.bearing.damper_power_w(w),
            p_oil: oil.power_w(dp, pressure_rate),
            p_leakage: p.leakage.power_w(dp),
            p_body: p.body.power_w(body_acceleration, v_b),
            p_anchoring: p.anchoring.spring_power_w(x_b, v_b),
            p_anchoring_damping: p.anchoring.damper_power_w(v_b),
            p_valve: dp * valve_flow,
            p_offset: m_offset * w,
            p_aero: m_aero * w,
        }
    }
}

/// The declarations of one axis (`pitch` or `yaw`).
fn declare_axis(d: &mut Declarations, name: &str) -> Axis {
    let n = |what: &str| format!("{what}_{name}");
    let actuator = "Actuator";
    Axis {
        is_pitch: name == "pitch",
        command_in: d.input(&n("theta_command"), 0.0, "rad").describe(&format!("Nozzle {name} angle command added to the built-in profile's {name} share")),
        m_aero: d
            .input(&n("M_aero"), 0.0, "N.m")
            .describe(&format!("Aerodynamic torque on the nozzle about its {name} axis (a side load times its arm from the pivot), positive in the direction of positive deflection")),
        theta: d.state(&n("theta"), 0.0, "rad").nominal(0.01).describe(&format!("Nozzle {name} deflection about the pivot")),
        w: d.state(&n("w"), 0.0, "rad/s").nominal(0.1).describe(&format!("Nozzle {name} angular speed")),
        dp: d.state(&n("dp"), 0.0, "Pa").nominal(1e6).describe(&format!("Pressure difference across the {name} actuator's piston (extending chamber less retracting one)")),
        phi_body: d.state(&n("phi_body"), 0.0, "rad").nominal(1e-4).describe(&format!(
            "Displacement of the {name} actuator's body on its anchoring along the actuator (toward the nozzle), referred to the nozzle angle: x_body / r_arm"
        )),
        w_body: d.state(&n("w_body"), 0.0, "rad/s").nominal(1e-2).describe(&format!("Velocity of the {name} actuator's body referred to the nozzle angle, v_body / r_arm")),
        y_angle: d.output(&n("nozzle_angle"), "rad").describe(&format!("Nozzle {name} deflection theta")),
        y_rate: d.output(&n("nozzle_rate"), "rad/s").describe(&format!("Nozzle {name} angular speed")),
        y_command: d.output(&n("nozzle_command"), "rad").describe(&format!("Nozzle {name} angle command: the profile's {name} share plus theta_command_{name}")),
        y_force: d.output(&n("actuator_force"), "N").describe(&format!("Force of the {name} actuator's rod on the nozzle, A dp")),
        y_pressure: d.output(&n("pressure_difference"), "Pa").describe(&format!("Chamber pressure difference of the {name} actuator, dp")),
        y_hinge: d.output(&n("hinge_moment"), "N.m").describe(&format!("Moment of the {name} actuator on the nozzle about the pivot, r A dp")),
        y_stroke: d.output(&n("actuator_stroke"), "m").describe(&format!("Stroke of the {name} actuator from mid stroke, y = r theta - x_body (what its transducer measures)")),
        y_anchoring: d.output(&n("anchoring_deflection"), "m").describe(&format!("Deflection of the {name} actuator's anchoring, x_body")),
        y_valve_flow: d.output(&n("valve_flow"), "m3/s").describe(&format!("Flow of the {name} servo-valve into the extending chamber, A K_v (r theta_cmd - y)")),
        e_inertia: d
            .element(&n("nozzle_inertia"), "Nozzle", Effect { what: "nozzle inertia about the pivot", ..Inertia::INERTIA })
            .describe(&format!("the nozzle's inertia J_nozzle about its {name} axis, power J w dw/dt")),
        e_bearing_stiffness: d
            .element(&n("bearing_stiffness"), "Flexible bearing", Effect { what: "flexible bearing stiffness (elastomer in shear)", ..TorsionSpring::STIFFNESS })
            .describe(&format!("the flexible bearing's stiffness K_bearing about the {name} axis, power K theta dtheta/dt")),
        e_bearing_damping: d
            .element(&n("bearing_damping"), "Flexible bearing", Effect { what: "flexible bearing damping (elastomer)", ..TorsionSpring::DAMPING })
            .describe(&format!("the flexible bearing's viscous damping D_bearing about the {name} axis, power D w^2")),
        e_oil: {
            d.element(&n("lever"), actuator, Lever::TRANSFORMER).describe("the actuator's arm about the pivot, M = r F, v = r w (Table 3.5)");
            d.element(&n("cylinder"), actuator, DoubleActingCylinder::TRANSFORMER).describe("the cylinder, F = A dp, Q = A dy/dt (Table 3.5)");
            d.element(&n("oil"), actuator, FluidVolume::COMPRESSIBILITY)
                .describe(&format!("the oil of the {name} actuator's two chambers, C = V_chamber / (2 B_oil), power C dp d(dp)/dt"))
        },
        e_leakage: d
            .element(&n("leakage"), actuator, Effect { what: "servo-valve flow-pressure coefficient and cross-port leakage (Q = dp/R)", ..LaminarLeakage::LEAKAGE })
            .describe(&format!("the laminar path across the {name} actuator's piston (the valve's K_c and the piston's leak), power dp^2 / R_leakage")),
        e_body: d
            .element(&n("actuator_body"), actuator, Effect { what: "actuator body mass", ..Mass::MASS })
            .describe(&format!("the {name} actuator's body (cylinder, manifold, valve), power m v dv/dt")),
        e_anchoring: d
            .element(&n("anchoring"), "Anchoring", Effect { what: "anchoring (backup structure) stiffness", ..TranslationalSpring::STIFFNESS })
            .describe(&format!("the anchoring of the {name} actuator on the motor case, power K_anchor x dx/dt")),
        e_anchoring_damping: d
            .element(&n("anchoring_damping"), "Anchoring", Effect { what: "anchoring structural damping", ..TranslationalSpring::DAMPING })
            .describe(&format!("the structural damping of the {name} actuator's anchoring, power D_anchor v^2")),
        e_valve: d.element(&n("servo_valve"), "Servo-valve", SERVO_VALVE).describe(&format!("the {name} servo-valve fed by the hydraulic supply, power dp Q_v")),
        e_offset: d.element(&n("offset_torque"), "Gases", OFFSET_TORQUE).describe(&format!("the thrust-offset torque's {name} share, power M w")),
        e_aero: d.element(&n("aero_torque"), "Air", AERO_TORQUE).describe(&format!("the aerodynamic torque about the {name} axis (input M_aero_{name}), power M w")),
    }
}

impl Model for BoosterNozzle {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "BoosterNozzle",
            description: "Launcher booster nozzle (chapter 3, section 3.4.1.1, Figure 3.15): two rotational degrees of freedom (pitch, yaw) of a Vega P80-class nozzle on its flexible bearing, each steered by a servo-valve controlled hydraulic actuator on a compliant anchoring, with thrust-offset and aerodynamic torques; position loops inside",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 1.0, step_size: 1e-3 },
            // Fastest mode: the actuator body on its anchoring (~417 Hz, |lambda| ~ 2600 /s), lightly
            // damped, not stiff beside the step sizes the accuracy asks for.
            solver: Solver::ExplicitRungeKutta,
            documentation: documentation::HTML,
        }
    }

    /// Measured (tests/python/test_accuracy.py against rtol 1e-10): at rtol 1e-3 the actuator body's
    /// activity was 0.038 of its range off (38 x rtol; it rectifies the body's 417 Hz ringing after
    /// each step of the valve's flow), at 1e-4 0.0018 (18 x); from 1e-5 on every output is within
    /// 10 x rtol of its range. The default tolerance, 1e-8, is unaffected.
    fn tolerance_floor(&self, _k: &Knowns) -> Option<f64> {
        Some(1e-5)
    }

    fn declare(d: &mut Declarations) -> Self {
        let cylinder = defaults::cylinder();
        let deg = defaults::deg;
        let profile = d.integer_parameter("profile", 1).choices(0, &[("none", "the inputs only"), ("step", "a step of command_amplitude at step_time"), ("sine", "a sine of command_amplitude at sine_frequency from step_time")]).describe(
            "Built-in command: 0 = none (the inputs only), 1 = a step of command_amplitude at step_time, 2 = a sine of command_amplitude at sine_frequency from step_time; \
             split into pitch (cos command_azimuth) and yaw (sin command_azimuth)",
        );
        BoosterNozzle {
            profile,
            j_nozzle: d.parameter("J_nozzle", defaults::J_NOZZLE_KG_M2, "kg.m2").positive().describe(
                "Nozzle inertia about the pivot (either transverse axis): 1400 kg m2, the Vega P80 nozzle of M. Budinger's Vega TVC course (github.com/SizingLab/sizing_course, Lab-vega)",
            ),
            k_bearing: d.parameter("K_bearing", defaults::k_bearing(), "N.m/rad").min(0.0).describe(
                "Flexible bearing rotational stiffness: 15 200 N m/deg (Vega P80, same source); at 5.7 deg it holds 86.6 kN m",
            ),
            d_bearing: d.parameter("D_bearing", defaults::d_bearing(), "N.m.s/rad").min(0.0).describe("Flexible bearing viscous damping: 174 N m s/deg (Vega P80, same source)"),
            r_arm: d.parameter("r_arm", defaults::ARM_M, "m").positive().describe("Actuator lever arm about the pivot: 1.35 m (Vega P80 nozzle geometry, same source); +-6 deg is +-141 mm of stroke"),
            a_piston: d.parameter("A_piston", cylinder.piston_area_m2, "m2").positive().describe(
                "Piston area of the through-rod cylinder: 100 mm bore, 50 mm rod, 58.9 cm2; 122 kN at 20.7 MPa against 64 kN for the bearing at 5.7 deg plus inertia and offset loads",
            ),
            v_chamber: d.parameter("V_chamber", 1.0e-3, "m3").positive().describe(
                "Oil volume of each chamber at mid stroke: the half stroke's 58.9 cm2 x 145 mm = 854 cm3 plus 146 cm3 of end clearance and manifold passages to the servo-valve",
            ),
            b_oil: d
                .parameter("B_oil", components::geometry::HYDRAULIC_OIL_BULK_MODULUS_PA, "Pa")
                .positive()
                .describe("Bulk modulus of the oil: 1.5 GPa, air-free hydraulic oil (MIL-PRF-5606 and kin: 1.4-1.8 GPa)"),
            r_leakage: d.parameter("R_leakage", 3.0e10, "Pa.s/m3").positive().describe(
                "Laminar path across the piston, Q = dp / R: the servo-valve's flow-pressure coefficient K_c = Q0 / (2 Ps) (Merritt's linearisation) at Q0 = 1.39e-3 m3/s \
                 (the nozzle at 10 deg/s) and Ps = 20.7 MPa, 1 / K_c = 2.98e10; the piston's own leak is negligible beside it",
            ),
            m_actuator: d.parameter("m_actuator", 30.0, "kg").positive().describe(
                "Mass of the actuator's body between its oil and its anchoring: a 0.6 m steel tube of 100 mm bore and 8 mm wall (13 kg), end caps, manifold, servo-valve and transducer",
            ),
            k_anchor: d.parameter("K_anchor", 1e8, "N/m").positive().describe(
                "Stiffness of the actuator's anchoring on the motor case (bracket, rod ends, body): 100 kN/mm, 1.2 mm under the 122 kN stall force; chosen of the order of the oil column's 1.04e8 N/m",
            ),
            d_anchor: d.parameter("D_anchor", defaults::d_anchor(1e8, 30.0), "N.s/m").min(0.0).describe(
                "Structural damping of the anchoring (bolted bracket, rod ends): 5 % of critical for the actuator body alone on it, 2 x 0.05 sqrt(K_anchor m_actuator) = 5477 N s/m",
            ),
            k_v: d.parameter("K_v", defaults::K_V_PER_S, "1/s").min(0.0).describe(
                "Position loop velocity gain: the servo-valve's flow moves the rod at K_v times the stroke error; 3 / 72 ms, so that the rigid loop's 5 % response time is the P80's 72 ms (0 opens the loop: valve closed)",
            ),
            m_offset: d
                .parameter("M_offset", defaults::M_OFFSET_N_M, "N.m")
                .describe("Thrust-offset torque on the nozzle: the P80's mean thrust 2.26 MN (88 t in 107 s at 280 s of Isp) passing 5 mm from the pivot, 11.3 kN m"),
            offset_azimuth: d.parameter("offset_azimuth", 0.0, "rad").describe("Direction of the offset torque: pitch share cos, yaw share sin (0: all in pitch)"),
            amplitude: d
                .parameter("command_amplitude", deg(0.5), "rad")
                .min(-deg(6.0))
                .max(deg(6.0))
                .describe("Amplitude of the built-in command: 0.5 deg, the P80's dynamic sizing step (5.2 to 5.7 deg in 72 ms); at most the +-6 deg deflection range"),
            command_azimuth: d.parameter("command_azimuth", 0.0, "rad").describe("Direction of the built-in command: pitch share cos, yaw share sin (0: pitch only)"),
            step_time: d.parameter("step_time", 0.1, "s").min(0.0).describe("Start of the built-in command (the step, or the sine from 0)"),
            sine_frequency: d
                .parameter("sine_frequency", 2.0, "Hz")
                .min(0.0)
                .describe("Frequency of the built-in sine (profile 2): 2 Hz, a cycle of the P80 actuator's endurance profile"),
            pitch: declare_axis(d, "pitch"),
            yaw: declare_axis(d, "yaw"),
            k_oil: {
                declare_neglected(d);
                d.calculated_parameter("k_oil", "N/m").describe("Hydraulic stiffness of the piston on its two closed oil columns, 2 A_piston^2 B_oil / V_chamber")
            },
            f_actuator_nozzle: d.calculated_parameter("f_actuator_nozzle", "Hz").describe(
                "Actuator-nozzle resonance: the lower natural frequency of the undamped two-degree-of-freedom chain (valve closed): nozzle J_nozzle on K_bearing, \
                 oil column k_oil at r_arm, actuator body m_actuator on K_anchor",
            ),
            f_actuator_body: d.calculated_parameter("f_actuator_body", "Hz").describe("The chain's upper natural frequency: the actuator body between its oil column and its anchoring"),
            f_bearing: d.calculated_parameter("f_bearing", "Hz").describe("The nozzle on its flexible bearing alone (actuator disconnected), sqrt(K_bearing / J_nozzle) / 2 pi"),
            k_servo_static: d.calculated_parameter("K_servo_static", "N.m/rad").describe(
                "Static stiffness of the servo-actuator seen by the nozzle, r^2 / (1/K_anchor + 1/(A^2 R_leakage K_v)): a steady torque M deflects the nozzle by M / (K_bearing + K_servo_static)",
            ),
            m_nozzle_rod: d.calculated_parameter("m_nozzle_rod", "kg").describe("The nozzle's inertia seen as a mass on the actuator's rod, J_nozzle / r_arm^2"),
        }
    }

    fn next_time_event(&self, k: &Knowns, after: f64) -> Option<f64> {
        let t0 = k[self.step_time];
        (k[self.profile] != 0 && t0 > after).then_some(t0)
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let p = self.parts(k);
        for axis in [&self.pitch, &self.yaw] {
            let op = self.operate(axis, &p, k);
            der[axis.theta] = k[axis.w];
            der[axis.w] = op.acceleration;
            der[axis.dp] = op.pressure_rate;
            der[axis.phi_body] = k[axis.w_body];
            der[axis.w_body] = p.lever.angular_speed_rad_per_s(op.body_acceleration);
            der.power(axis.e_inertia, op.p_inertia);
            der.power(axis.e_bearing_stiffness, op.p_bearing_stiffness);
            der.power(axis.e_bearing_damping, op.p_bearing_damping);
            der.power(axis.e_oil, op.p_oil);
            der.power(axis.e_leakage, op.p_leakage);
            der.power(axis.e_body, op.p_body);
            der.power(axis.e_anchoring, op.p_anchoring);
            der.power(axis.e_anchoring_damping, op.p_anchoring_damping);
            der.power(axis.e_valve, op.p_valve);
            der.power(axis.e_offset, op.p_offset);
            der.power(axis.e_aero, op.p_aero);
        }
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        let p = self.parts(k);
        for axis in [&self.pitch, &self.yaw] {
            let op = self.operate(axis, &p, k);
            out[axis.y_angle] = k[axis.theta];
            out[axis.y_rate] = k[axis.w];
            out[axis.y_command] = op.command;
            out[axis.y_force] = op.force;
            out[axis.y_pressure] = k[axis.dp];
            out[axis.y_hinge] = op.hinge_moment;
            out[axis.y_stroke] = op.stroke;
            out[axis.y_anchoring] = p.lever.rod_velocity_m_per_s(k[axis.phi_body]);
            out[axis.y_valve_flow] = op.valve_flow;
        }
        let (f_low, f_high) = p.chain().natural_frequencies_hz();
        out[self.k_oil] = p.oil_stiffness_n_per_m();
        out[self.f_actuator_nozzle] = f_low;
        out[self.f_actuator_body] = f_high;
        out[self.f_bearing] = p.bearing.natural_frequency_hz(p.nozzle.inertia_kg_m2, R::from(f64::INFINITY));
        out[self.k_servo_static] = p.servo_static_stiffness_n_m_per_rad();
        out[self.m_nozzle_rod] = p.lever.referred_mass_kg(p.nozzle.inertia_kg_m2);
    }
}

/// The effects the model leaves out (Table 3.1), each with the reason.
fn declare_neglected(d: &mut Declarations) {
    use components::{SlidingFriction, TranslationalSpring as Spring};
    let pendulum = Effect { domains: &[Domain::Rotational], kind: Kind::StorageC, what: "restoring torque of the nozzle's weight under the launcher's acceleration" };
    d.neglected(
        "Nozzle",
        pendulum,
        "a ~1.2 t nozzle with its centre of mass ~1 m aft of the pivot at 3 g adds m n g d ~ 35 kN m/rad, 4 % of K_bearing",
    );
    let hysteresis = Effect { domains: &[Domain::Rotational], kind: Kind::Dissipation, what: "hysteresis (friction-like) torque of the elastomer" };
    d.neglected("Flexible bearing", hysteresis, "lumped into the equivalent viscous damping D_bearing of the source; a dry-friction term would add stick/slip events");
    let pressure = Effect { domains: &[Domain::Rotational], kind: Kind::StorageC, what: "dependence of the bearing's stiffness on the chamber pressure" };
    d.neglected("Flexible bearing", pressure, "K_bearing is the equivalent stiffness of the source, taken constant over the burn");
    let rod = Effect { domains: &[Domain::Translational], kind: Kind::StorageI, what: "mass of the piston and rod" };
    d.neglected("Actuator", rod, "about 10 kg at r = 1.35 m: 18 kg m2, 1.3 % of J_nozzle");
    let seals = Effect { what: "piston and rod seal friction", ..SlidingFriction::FRICTION };
    d.neglected("Actuator", seals, "a few hundred N against tens of kN (a stick/slip mode would add events)");
    let oil_inertia = Effect { domains: &[Domain::Hydraulic], kind: Kind::StorageI, what: "oil inertia in the manifold passages" };
    d.neglected("Actuator", oil_inertia, "the valve sits on the cylinder: short passages, their mode far above the 417 Hz body mode");
    let wall = Effect { what: "compliance of the cylinder's walls", ..Spring::STIFFNESS };
    d.neglected("Actuator", wall, "a few % of the oil's compliance; an effective bulk modulus would lump it into B_oil");
    let spool = Effect { domains: &[Domain::Translational], kind: Kind::StorageI, what: "servo-valve spool and torque-motor dynamics" };
    d.neglected("Servo-valve", spool, "a two-stage valve's bandwidth (~100 Hz and more) lies well above the 6.7 Hz position loop");
    let saturation = Effect { domains: &[Domain::Hydraulic], kind: Kind::Dissipation, what: "valve orifices' pressure drop, flow saturation and supply-pressure limit" };
    d.neglected(
        "Servo-valve",
        saturation,
        "linearised about the null (Merritt): the model stays linear for closed forms; it does not cap the flow or dp at the supply's 20.7 MPa (the default step peaks at 13.6 MPa)",
    );
    let supply = Effect { domains: &[Domain::Hydraulic], kind: Kind::StorageC, what: "hydraulic supply (accumulator, blow-down or pump) dynamics" };
    d.neglected("Servo-valve", supply, "the supply pressure is taken constant; it only enters the valve's K_c");
    let kinematics = Effect { domains: &[Domain::Rotational], kind: Kind::Transformer, what: "variation of the lever arm with the angle and pitch-yaw geometric coupling" };
    d.neglected("Nozzle", kinematics, "second order in the angle: under 1 % of the arm at 5.7 deg (the source's remark); pitch and yaw stay uncoupled");
}

fmu_runtime::export_fmu!(BoosterNozzle);
