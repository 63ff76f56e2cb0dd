//! The cooling-tower drive train of chapter sections 3.1-3.3, declared once: each part's FMI
//! parameters (name, default, unit, bounds, source) and how to build its `components` element
//! from them. `MotorFan` and the subsystem FMUs (`InductionMotor`, `DriveShaft`, `Fan`,
//! `SpeedController`) declare their parameters through these, so the same name always has the
//! same default, unit, bounds and description. The reasons behind each default are in
//! `models/motor-fan/src/lib.rs` and `docs/motor-fan-spec.md`.

use components::{FanLoad, InductionMachine, Inertia, PiController, Reducer, SecondOrderFilter, SpeedRamp, TorsionSpring};
use fmu_runtime::prelude::*;

/// The induction motor: rotor inertia and equivalent circuit (160 kW, 400 V, 4 poles).
pub struct MotorParameters {
    j_motor: Parameter,
    r_s: Parameter,
    r_r: Parameter,
    l_s_sigma: Parameter,
    l_r_sigma: Parameter,
    l_m: Parameter,
    pole_pairs: Parameter,
    u_supply: Parameter,
    f_supply: Parameter,
}

impl MotorParameters {
    pub fn declare(d: &mut Declarations) -> Self {
        MotorParameters {
            j_motor: d.parameter("J_motor", 1.72, "kg.m2").positive().tunable().describe("Motor rotor inertia (chapter 3.3.3)"),
            r_s: d.parameter("R_s", 0.012, "Ohm").positive().tunable().describe("Stator resistance per phase (chosen, 160 kW 400 V motor)"),
            r_r: d.parameter("R_r", 0.020, "Ohm").positive().tunable().describe("Rotor resistance per phase, referred to the stator (chosen)"),
            l_s_sigma: d.parameter("L_s_sigma", 2.5e-4, "H").positive().tunable().describe("Stator leakage inductance (chosen)"),
            l_r_sigma: d.parameter("L_r_sigma", 2.5e-4, "H").positive().tunable().describe("Rotor leakage inductance, referred to the stator (chosen)"),
            l_m: d.parameter("L_m", 0.01, "H").positive().tunable().describe("Magnetising inductance (chosen)"),
            pole_pairs: d.parameter("pole_pairs", 2.0, "1").positive().describe("Pole pairs: 2 gives 1500 rpm synchronous speed at 50 Hz (chosen)"),
            u_supply: d.parameter("U_supply", 400.0, "V").min(0.0).tunable().describe("Supply voltage, line to line, rms (chosen)"),
            f_supply: d.parameter("f_supply", 50.0, "Hz").positive().tunable().describe("Supply frequency (chapter: 50 Hz network)"),
        }
    }

    pub fn machine(&self, k: &Knowns) -> InductionMachine {
        InductionMachine {
            stator_resistance_ohm: k[self.r_s],
            rotor_resistance_ohm: k[self.r_r],
            stator_leakage_h: k[self.l_s_sigma],
            rotor_leakage_h: k[self.l_r_sigma],
            magnetizing_h: k[self.l_m],
            pole_pairs: k[self.pole_pairs],
            line_voltage_rms_v: k[self.u_supply],
            frequency_hz: k[self.f_supply],
        }
    }

    pub fn rotor(&self, k: &Knowns) -> Inertia {
        Inertia { inertia_kg_m2: k[self.j_motor] }
    }
}

/// The driveshaft: stiffness from the 1.4 Hz resonance (eq. 3.8) and internal damping.
pub struct ShaftParameters {
    k_shaft: Parameter,
    d_shaft: Parameter,
}

impl ShaftParameters {
    pub fn declare(d: &mut Declarations) -> Self {
        ShaftParameters {
            k_shaft: d.parameter("K_shaft", 906.85, "N.m/rad").positive().tunable().describe("Driveshaft torsional stiffness: 11.72 (2 pi 1.4 Hz)^2 (eq. 3.8)"),
            d_shaft: d.parameter("D_shaft", 5.0, "N.m.s/rad").min(0.0).tunable().describe("Driveshaft internal damping (chosen: 2.4 % of critical for the 1.4 Hz mode)"),
        }
    }

    pub fn spring(&self, k: &Knowns) -> TorsionSpring {
        TorsionSpring { stiffness_n_m_per_rad: k[self.k_shaft], damping_n_m_s_per_rad: k[self.d_shaft] }
    }
}

/// The fan with its reducer: inertia on the low-speed side, ratio, efficiency, aerodynamic load.
pub struct FanParameters {
    j_fan: Parameter,
    gear_ratio: Parameter,
    gear_efficiency: Parameter,
    k_fan: Parameter,
}

impl FanParameters {
    pub fn declare(d: &mut Declarations) -> Self {
        FanParameters {
            j_fan: d.parameter("J_fan", 1172.0, "kg.m2").positive().tunable().describe("Fan inertia on the low-speed side: 11.72 kg m2 x N^2 (eqs. 3.4-3.7)"),
            gear_ratio: d.parameter("gear_ratio", 10.0, "1").positive().tunable().describe("Reducer ratio N = motor speed / fan speed (chosen)"),
            gear_efficiency: d
                .parameter("gear_efficiency", 0.97, "1")
                .positive()
                .max(1.0)
                .tunable()
                .describe("Reducer efficiency on the power it transmits (chosen, one gear stage)"),
            k_fan: d.parameter("k_fan", 42.9, "N.m.s2/rad2").min(0.0).tunable().describe("Fan aerodynamic torque coefficient, T = k w_fan^2 (chosen: rated torque at rated speed)"),
        }
    }

    pub fn inertia(&self, k: &Knowns) -> Inertia {
        Inertia { inertia_kg_m2: k[self.j_fan] }
    }

    pub fn reducer(&self, k: &Knowns) -> Reducer {
        Reducer { ratio: k[self.gear_ratio], efficiency: k[self.gear_efficiency] }
    }

    pub fn load(&self, k: &Knowns) -> FanLoad {
        FanLoad { coefficient_n_m_s2_per_rad2: k[self.k_fan] }
    }

    /// The fan inertia seen from the high-speed axis, J_fan / N^2 (eq. 3.6).
    pub fn referred_inertia_kg_m2(&self, k: &Knowns) -> f64 {
        self.reducer(k).referred_inertia_kg_m2(k[self.j_fan])
    }
}

/// The PI's torque limit as a state event: the command and the integral's rate have a corner
/// where the raw command reaches +/- T_limit, and a solver stopped there (rather than stepping
/// across) keeps its accuracy. Declares the mode `pi_limit` and its indicator.
pub struct TorqueLimitEvent {
    mode: Mode,
    indicator: Indicator,
}

impl TorqueLimitEvent {
    pub fn declare(d: &mut Declarations) -> Self {
        TorqueLimitEvent {
            mode: d.mode("pi_limit", 0).range(-1, 1).describe("Side of the PI's torque limit: 0 within, 1 clamped at +T_limit, -1 at -T_limit"),
            indicator: d.event_indicator(
                "pi_torque_limit",
                "within the limit, T_limit - |Kp e + Ki integral|; clamped, how far the raw command is beyond the limit",
            ),
        }
    }

    /// The indicator with the PI driving at this error and integral.
    pub fn indicator(&self, k: &Knowns, pi: &PiController, error: f64, integral: f64, z: &mut EventIndicators) {
        z[self.indicator] = pi.limit_indicator(k[self.mode], error, integral);
    }

    /// The PI not driving (another start mode): never an event.
    pub fn idle(&self, z: &mut EventIndicators) {
        z[self.indicator] = 1.0;
    }

    /// The mode after an event; `error_rate` is de/dt (for the exact-limit case).
    pub fn update(&self, k: &Knowns, next: &mut ModeUpdate, pi: &PiController, error: f64, error_rate: f64, integral: f64) {
        next[self.mode] = pi.next_limit_mode(k[self.mode], error, integral, pi.raw_rate(error, error_rate, integral));
    }
}

/// The variable-speed start: set-point ramp, optional second-order filter, PI controller.
pub struct ControllerParameters {
    pub setpoint_filter: IntegerParameter,
    speed_setpoint: Parameter,
    ramp_time: Parameter,
    kp: Parameter,
    ki: Parameter,
    t_limit: Parameter,
    t_tracking: Parameter,
    filter_below: Parameter,
    filter_above: Parameter,
    filter_damping: Parameter,
}

impl ControllerParameters {
    pub fn declare(d: &mut Declarations) -> Self {
        ControllerParameters {
            setpoint_filter: d
                .integer_parameter("setpoint_filter", 0)
                .range(0, 2)
                .describe("Second-order set-point filter (Figure 3.13): 0 = off, 1 = filter_frequency_below, 2 = filter_frequency_above"),
            speed_setpoint: d.parameter("speed_setpoint", 153.5, "rad/s").min(0.0).tunable().describe("Final motor speed of the variable-speed start (the direct-on-line equilibrium)"),
            ramp_time: d.parameter("ramp_time", 10.0, "s").min(0.0).tunable().describe("Duration of the set-point ramp, 0 = a step (chapter: 10 s)"),
            kp: d.parameter("Kp_speed", 200.0, "N.m.s/rad").min(0.0).tunable().describe("PI speed controller proportional gain (chosen)"),
            ki: d.parameter("Ki_speed", 2000.0, "N.m/rad").min(0.0).tunable().describe("PI speed controller integral gain (chosen)"),
            t_limit: d.parameter("T_limit", 2500.0, "N.m").positive().tunable().describe("Torque limit of the converter-fed motor (chosen, ~2.4x rated)"),
            t_tracking: d
                .parameter("T_tracking", 0.09, "s")
                .positive()
                .tunable()
                .describe("Anti-windup tracking time constant: while the torque is clamped, the PI integral is driven back by (T_clamped - T_raw) / (Ki_speed T_tracking) (chosen: 0.9 Kp_speed/Ki_speed)"),
            filter_below: d.parameter("filter_frequency_below", 0.5, "Hz").positive().tunable().describe("Set-point filter natural frequency below the 1.4 Hz resonance (Figure 3.13)"),
            filter_above: d.parameter("filter_frequency_above", 5.0, "Hz").positive().tunable().describe("Set-point filter natural frequency above the 1.4 Hz resonance (Figure 3.13)"),
            filter_damping: d.parameter("filter_damping", 0.7, "1").positive().tunable().describe("Set-point filter damping ratio"),
        }
    }

    pub fn ramp(&self, k: &Knowns) -> SpeedRamp {
        SpeedRamp { target: k[self.speed_setpoint], duration_s: k[self.ramp_time] }
    }

    pub fn controller(&self, k: &Knowns) -> PiController {
        PiController { proportional_gain: k[self.kp], integral_gain: k[self.ki], output_limit: k[self.t_limit], tracking_time_s: k[self.t_tracking] }
    }

    /// The set-point filter, if one is chosen.
    pub fn filter(&self, k: &Knowns) -> Option<SecondOrderFilter> {
        let natural_frequency_hz = match k[self.setpoint_filter] {
            0 => return None,
            1 => k[self.filter_below],
            _ => k[self.filter_above],
        };
        Some(SecondOrderFilter { natural_frequency_hz, damping: k[self.filter_damping] })
    }

    pub fn ramp_time(&self, k: &Knowns) -> f64 {
        k[self.ramp_time]
    }
}

/// The speed set point and its filter states: w_ref, dw_ref/dt and (filter on) d2w_ref/dt2.
pub struct SetPoint {
    pub reference: f64,
    pub rate: f64,
    pub acceleration: f64,
}

impl SetPoint {
    /// From the ramp, through the filter whose states are (`filtered`, `filtered_rate`).
    pub fn at(params: &ControllerParameters, k: &Knowns, filtered: f64, filtered_rate: f64) -> SetPoint {
        let ramp = params.ramp(k);
        let t = k.time();
        match params.filter(k) {
            None => SetPoint { reference: ramp.value(t), rate: ramp.slope(t), acceleration: 0.0 },
            Some(f) => SetPoint { reference: filtered, rate: filtered_rate, acceleration: f.acceleration(ramp.value(t), filtered, filtered_rate) },
        }
    }
}

/// A converter-fed motor: the power it draws is the mechanical power (an ideal converter and
/// machine) and its current that of the machine at rated flux (constant V/f) giving that
/// torque: the 50 Hz circuit at the slip of that torque. Returns (current rms, power).
pub fn converter_fed(machine: &InductionMachine, torque_n_m: f64, speed_rad_per_s: f64) -> (f64, f64) {
    let slip = machine.stable_slip_for_torque(torque_n_m);
    (machine.steady_state_at_slip(slip).stator_current_rms_a, torque_n_m * speed_rad_per_s)
}

/// What every motor-fan subsystem FMU says about itself: explicit Runge-Kutta, 1 ms default
/// communication step (the shaft's 3.9 Hz mode needs far finer than its period).
pub fn subsystem_info(name: &'static str, description: &'static str, stop_time: f64, documentation: &'static str) -> ModelInfo {
    ModelInfo {
        name,
        description,
        default_experiment: DefaultExperiment { start_time: 0.0, stop_time, step_size: 1e-3 },
        solver: Solver::ExplicitRungeKutta,
        documentation,
    }
}
