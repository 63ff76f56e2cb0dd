//! The cooling-tower drive train of chapter sections 3.1-3.3, declared once: each part's FMI
//! parameters (name, default, unit, bounds, source) and how to build its `components` element
//! from them. `MotorFan` and the subsystem FMUs (`InductionMotor`, `DriveShaft`, `Fan`,
//! `SpeedController`) declare their parameters through these, so the same name always has the
//! same default, unit, bounds and description. The defaults are the book authors' own values
//! (book file Chap3_CoolingTowerFan.mo, each description names its component); the reasons and
//! the earlier chosen set are in `models/motor-fan/src/lib.rs` and `docs/motor-fan-spec.md`.

use components::complex::Complex;
use components::roots::with_derivatives_of;
use components::{FanLoad, InductionMachine, Inertia, Interpolation, PiController, Reducer, SecondOrderFilter, SpeedRamp, TorqueSpeedTable, TorsionSpring};
use fmu_runtime::prelude::*;

/// Points of the book's torque-speed table (book file Chap3_CoolingTowerFan.mo, component
/// TorqueSpeed): speed rad/s, torque N m.
pub const BOOK_TABLE: [(f64, f64); TABLE_POINTS] =
    [(0.0, 454.0), (80.0, 579.0), (160.0, 784.0), (220.0, 997.0), (240.0, 1057.0), (250.0, 1071.0), (260.0, 1060.0), (280.0, 919.0), (300.0, 500.0), (314.0, 0.0)];
pub const TABLE_POINTS: usize = 10;

/// Where the motor's torque comes from at levels a-c (level d always solves the circuit's dq
/// model).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MotorCurve<R = f64> {
    /// The torque-speed table.
    Table(TorqueSpeedTable<TABLE_POINTS, R>),
    /// The equivalent circuit's steady state.
    Circuit,
}

/// The induction motor: rotor inertia, its torque-speed table (levels a-c, as the book's files)
/// and its equivalent circuit (level d, the current drawn, converter-fed starts).
pub struct MotorParameters {
    j_motor: Parameter,
    motor_model: IntegerParameter,
    table_interpolation: IntegerParameter,
    table_speed: [Parameter; TABLE_POINTS],
    table_torque: [Parameter; TABLE_POINTS],
    r_s: Parameter,
    r_r: Parameter,
    l_s_sigma: Parameter,
    l_r_sigma: Parameter,
    l_m: Parameter,
    pole_pairs: Parameter,
    winding_connection: IntegerParameter,
    u_supply: Parameter,
    f_supply: Parameter,
}

impl MotorParameters {
    pub fn declare(d: &mut Declarations) -> Self {
        let j_motor = d.parameter("J_motor", 1.72, "kg.m2").positive().tunable().describe("Motor rotor inertia (chapter 3.3.3; book file Chap3_CoolingTowerFan.mo, component inertia_motor)");
        let motor_model = d
            .integer_parameter("motor_model", 1)
            .choices(1, &[("torque_table", "the torque-speed table (the book's files)"), ("equivalent_circuit", "the equivalent circuit's steady state")])
            .describe("Motor torque below level d: 1 = the torque-speed table (the book's files), 2 = the equivalent circuit's steady state (R_s ... L_m)");
        let table_interpolation = d.integer_parameter("motor_table_interpolation", 0).choices(0, &[("as_book", "as the book's file for the level"), ("linear", "linear"), ("akima", "Akima (CombiTable1D ContinuousDerivative)")]).describe(
            "Reading of the torque-speed table: 0 = as the book's file for the level (MotorFan: linear at levels a and b as Steady_State and Transient_Dynamic, Akima at c as Transient_Resonance; InductionMotor: Akima), 1 = linear, 2 = Akima (CombiTable1D ContinuousDerivative)",
        );
        let table_speed = std::array::from_fn(|i| {
            d.parameter(&format!("motor_table_speed_{}", i + 1), BOOK_TABLE[i].0, "rad/s")
                .describe(&format!("Torque-speed table, point {} of {TABLE_POINTS}: motor speed (book file Chap3_CoolingTowerFan.mo, component TorqueSpeed; speeds must increase, checked at initialization, so fixed)", i + 1))
        });
        let table_torque = std::array::from_fn(|i| {
            d.parameter(&format!("motor_table_torque_{}", i + 1), BOOK_TABLE[i].1, "N.m")
                .tunable()
                .describe(&format!("Torque-speed table, point {} of {TABLE_POINTS}: motor torque at motor_table_speed_{} (book file Chap3_CoolingTowerFan.mo, component TorqueSpeed)", i + 1, i + 1))
        });
        MotorParameters {
            j_motor,
            motor_model,
            table_interpolation,
            table_speed,
            table_torque,
            r_s: d.parameter("R_s", 0.038, "Ohm").positive().tunable().describe("Stator resistance per phase (the book's induction machine, result file Transient_InductionMachine_graphic.mat)"),
            r_r: d.parameter("R_r", 0.038, "Ohm").positive().tunable().describe("Rotor resistance per phase, referred to the stator (the book's induction machine)"),
            l_s_sigma: d.parameter("L_s_sigma", 2e-4, "H").positive().tunable().describe("Stator leakage inductance (the book's induction machine)"),
            l_r_sigma: d.parameter("L_r_sigma", 4e-4, "H").positive().tunable().describe("Rotor leakage inductance, referred to the stator (the book's induction machine)"),
            l_m: d.parameter("L_m", 0.012, "H").positive().tunable().describe("Magnetising inductance (the book's induction machine)"),
            pole_pairs: d.parameter("pole_pairs", 1.0, "1").positive().describe("Pole pairs: 1 gives 3000 rpm (314 rad/s) synchronous at 50 Hz, where the book's table reaches zero torque"),
            winding_connection: d.integer_parameter("winding_connection", 2).choices(1, &[("star", "each winding sees U_supply / sqrt 3"), ("delta", "each winding sees U_supply (the book's machine)")]).describe(
                "Stator windings: 1 = star (each winding sees U_supply / sqrt 3), 2 = delta (each sees U_supply; the book's machine, terminalBox.delta in its result files). R_s ... L_m are per winding and stator_current_rms is the winding current",
            ),
            u_supply: d.parameter("U_supply", 230.0, "V").min(0.0).tunable().describe("Supply voltage, line to line, rms (the book's induction machine: VNominal = 230 V, 50 Hz)"),
            f_supply: d.parameter("f_supply", 50.0, "Hz").positive().tunable().describe("Supply frequency (chapter: 50 Hz network)"),
        }
    }

    pub fn machine<R: Real>(&self, k: &Knowns<R>) -> InductionMachine<R> {
        InductionMachine {
            stator_resistance_ohm: k[self.r_s],
            rotor_resistance_ohm: k[self.r_r],
            stator_leakage_h: k[self.l_s_sigma],
            rotor_leakage_h: k[self.l_r_sigma],
            magnetizing_h: k[self.l_m],
            pole_pairs: k[self.pole_pairs],
            // The circuit is per winding, solved as the star of the same winding voltage.
            line_voltage_rms_v: if k[self.winding_connection] == 2 { k[self.u_supply] * 3f64.sqrt() } else { k[self.u_supply] },
            frequency_hz: k[self.f_supply],
        }
    }

    /// The steady-state torque curve below level d. `akima_by_default`: how interpolation 0
    /// reads the table (the book's choice for the level).
    pub fn curve<R: Real>(&self, k: &Knowns<R>, akima_by_default: bool) -> MotorCurve<R> {
        if k[self.motor_model] == 2 {
            return MotorCurve::Circuit;
        }
        let interpolation = match k[self.table_interpolation] {
            1 => Interpolation::Linear,
            2 => Interpolation::Akima,
            _ if akima_by_default => Interpolation::Akima,
            _ => Interpolation::Linear,
        };
        MotorCurve::Table(TorqueSpeedTable {
            speed_rad_per_s: std::array::from_fn(|i| k[self.table_speed[i]]),
            torque_n_m: std::array::from_fn(|i| k[self.table_torque[i]]),
            interpolation,
        })
    }

    /// The table's speeds must increase (the interpolation divides by their differences).
    pub fn check(&self, k: &Knowns) -> Result<(), String> {
        for i in 1..TABLE_POINTS {
            let (a, b) = (k[self.table_speed[i - 1]], k[self.table_speed[i]]);
            if !(b > a) {
                return Err(format!("motor_table_speed_{} = {b} rad/s must be above motor_table_speed_{} = {a} rad/s: the table's speeds increase", i + 1, i));
            }
        }
        Ok(())
    }

    pub fn rotor<R: Real>(&self, k: &Knowns<R>) -> Inertia<R> {
        Inertia { inertia_kg_m2: k[self.j_motor] }
    }
}

/// The motor's steady state at one speed, whichever curve gives its torque.
pub struct MotorSteadyState<R = f64> {
    pub torque_n_m: R,
    /// From the equivalent circuit at this speed (a table gives no current).
    pub current_rms_a: R,
    pub electrical_power_w: R,
}

impl<R: Real> MotorCurve<R> {
    /// The torque at `speed`, and the circuit's current and power there.
    pub fn steady_state(&self, machine: &InductionMachine<R>, speed_rad_per_s: R) -> MotorSteadyState<R> {
        let st = machine.steady_state(speed_rad_per_s);
        let torque_n_m = match self {
            MotorCurve::Table(t) => t.torque_n_m(speed_rad_per_s),
            MotorCurve::Circuit => st.torque_n_m,
        };
        MotorSteadyState { torque_n_m, current_rms_a: st.stator_current_rms_a, electrical_power_w: st.electrical_power_w }
    }

    /// The torque alone (the derivatives need no current).
    pub fn torque_n_m(&self, machine: &InductionMachine<R>, speed_rad_per_s: R) -> R {
        match self {
            MotorCurve::Table(t) => t.torque_n_m(speed_rad_per_s),
            MotorCurve::Circuit => machine.steady_state(speed_rad_per_s).torque_n_m,
        }
    }

    /// The stable operating speed under a load torque curve (None: the motor stalls).
    pub fn stable_speed_rad_per_s(&self, machine: &InductionMachine<R>, load_torque_n_m: impl Fn(R) -> R) -> Option<R> {
        match self {
            MotorCurve::Table(t) => t.stable_speed_rad_per_s(load_torque_n_m),
            MotorCurve::Circuit => machine.stable_speed_rad_per_s(load_torque_n_m),
        }
    }
}

/// The driveshaft: stiffness and internal damping (book file Chap3_CoolingTowerFan.mo, component
/// spring of Transient_Resonance; the 1.4 Hz of eq. 3.8 with the referred fan inertia).
pub struct ShaftParameters {
    k_shaft: Parameter,
    d_shaft: Parameter,
}

impl ShaftParameters {
    pub fn declare(d: &mut Declarations) -> Self {
        ShaftParameters {
            k_shaft: d.parameter("K_shaft", 866.0, "N.m/rad").positive().tunable().describe("Driveshaft torsional stiffness (book file Chap3_CoolingTowerFan.mo, component spring: c = 866; 1.37 Hz against the referred fan inertia, eq. 3.8)"),
            d_shaft: d.parameter("D_shaft", 866.0 / 100.0 / (886.0f64 / 1.7).sqrt(), "N.m.s/rad").min(0.0).tunable().describe("Driveshaft internal damping (book file Chap3_CoolingTowerFan.mo, component spring: d = 866/100/sqrt(886/1.7), 886 as the file writes it)"),
        }
    }

    pub fn spring<R: Real>(&self, k: &Knowns<R>) -> TorsionSpring<R> {
        TorsionSpring { stiffness_n_m_per_rad: k[self.k_shaft], damping_n_m_s_per_rad: k[self.d_shaft] }
    }
}

/// The fan with its reducer: inertia on the low-speed side, ratio, efficiency, aerodynamic load.
pub struct FanParameters {
    j_fan: Parameter,
    gear_ratio: Parameter,
    gear_efficiency: Parameter,
    t_fan_nominal: Parameter,
    speed_fan_nominal: Parameter,
}

impl FanParameters {
    pub fn declare(d: &mut Declarations) -> Self {
        FanParameters {
            j_fan: d.parameter("J_fan", 3000.0, "kg.m2").positive().tunable().describe("Fan inertia on the low-speed side (book file Chap3_CoolingTowerFan.mo, component inertia_fan; 11.72 kg m2 on the high-speed axis, eqs. 3.4-3.7)"),
            gear_ratio: d.parameter("gear_ratio", 16.0, "1").positive().tunable().describe("Reducer ratio N = motor speed / fan speed (book file Chap3_CoolingTowerFan.mo, component lossyGear)"),
            gear_efficiency: d
                .parameter("gear_efficiency", 0.94, "1")
                .positive()
                .max(1.0)
                .tunable()
                .describe("Reducer efficiency on the power it transmits, either way (book file Chap3_CoolingTowerFan.mo, component lossyGear: lossTable 0.94, 0.94)"),
            t_fan_nominal: d
                .parameter("T_fan_nominal", 7742.6, "N.m")
                .min(0.0)
                .tunable()
                .describe("Fan torque at speed_fan_nominal; the torque follows T_fan_nominal (w_fan / speed_fan_nominal)^2 against the rotation (book file Chap3_CoolingTowerFan.mo, component quadraticSpeedDependentTorque: tau_nominal = -7742.6)"),
            speed_fan_nominal: d
                .parameter("speed_fan_nominal", 19.373154697137, "rad/s")
                .positive()
                .tunable()
                .describe("Fan speed at which the fan torque is T_fan_nominal (book file Chap3_CoolingTowerFan.mo, component quadraticSpeedDependentTorque: w_nominal = 19.373154697137; 19.37 in Steady_State)"),
        }
    }

    pub fn inertia<R: Real>(&self, k: &Knowns<R>) -> Inertia<R> {
        Inertia { inertia_kg_m2: k[self.j_fan] }
    }

    pub fn reducer<R: Real>(&self, k: &Knowns<R>) -> Reducer<R> {
        Reducer { ratio: k[self.gear_ratio], efficiency: k[self.gear_efficiency] }
    }

    pub fn load<R: Real>(&self, k: &Knowns<R>) -> FanLoad<R> {
        FanLoad::from_nominal(k[self.t_fan_nominal], k[self.speed_fan_nominal])
    }

    /// The fan inertia seen from the high-speed axis, J_fan / N^2 (eq. 3.6).
    pub fn referred_inertia_kg_m2<R: Real>(&self, k: &Knowns<R>) -> R {
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
        z[self.indicator] = if pi.output_limit.is_finite() { pi.limit_indicator(k[self.mode], error, integral) } else { 1.0 };
    }

    /// The PI not driving (another start mode): never an event.
    pub fn idle(&self, z: &mut EventIndicators) {
        z[self.indicator] = 1.0;
    }

    /// The mode after an event; `error_rate` is de/dt (for the exact-limit case).
    pub fn update(&self, k: &Knowns, next: &mut ModeUpdate, pi: &PiController, error: f64, error_rate: f64, integral: f64) {
        if !pi.output_limit.is_finite() {
            return;
        }
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
                .integer_parameter("setpoint_filter", 1)
                .choices(0, &[("off", "no set-point filter"), ("below", "filter_frequency_below (the book's)"), ("above", "filter_frequency_above")])
                .describe("Second-order set-point filter (Figure 3.13): 0 = off, 1 = filter_frequency_below (the book's, component secondOrder1), 2 = filter_frequency_above"),
            speed_setpoint: d.parameter("speed_setpoint", 300.0, "rad/s").min(0.0).tunable().describe("Final motor speed of the variable-speed start (book file Chap3_CoolingTowerFan.mo, component timeTable: 300 rad/s)"),
            ramp_time: d.parameter("ramp_time", 10.0, "s").min(0.0).tunable().describe("Duration of the set-point ramp, 0 = a step (chapter and book file Transient_SpeedControler, component timeTable: 10 s; Activity_Index_controller: 20 s)"),
            kp: d.parameter("Kp_speed", 10000.0, "N.m.s/rad").min(0.0).tunable().describe("PI speed controller proportional gain (book file Chap3_CoolingTowerFan.mo, component PI: k = 10000)"),
            ki: d.parameter("Ki_speed", 100000.0, "N.m/rad").min(0.0).tunable().describe("PI speed controller integral gain (book file Chap3_CoolingTowerFan.mo, component PI: k / T = 10000 / 0.1)"),
            t_limit: d.parameter("T_limit", 0.0, "N.m").min(0.0).tunable().describe("Torque limit of the converter-fed motor, 0 = none (the book's PI has none; the earlier chosen set: 2500)"),
            t_tracking: d
                .parameter("T_tracking", 0.09, "s")
                .positive()
                .tunable()
                .describe("Anti-windup tracking time constant: while the torque is clamped, the PI integral is driven back by (T_clamped - T_raw) / (Ki_speed T_tracking) (chosen: 0.9 Kp_speed/Ki_speed; acts only with a T_limit)"),
            filter_below: d.parameter("filter_frequency_below", 0.5 * 3.14 / std::f64::consts::PI, "Hz").positive().tunable().describe("Set-point filter natural frequency below the 1.4 Hz resonance (Figure 3.13; book file Chap3_CoolingTowerFan.mo, component secondOrder1: w = 2*3.14*0.5 rad/s, so 0.49975 Hz with its pi written 3.14)"),
            filter_above: d.parameter("filter_frequency_above", 5.0, "Hz").positive().tunable().describe("Set-point filter natural frequency above the 1.4 Hz resonance (Figure 3.13)"),
            filter_damping: d.parameter("filter_damping", 1.0, "1").positive().tunable().describe("Set-point filter damping ratio (book file Chap3_CoolingTowerFan.mo, component secondOrder1: D = 1)"),
        }
    }

    pub fn ramp<R: Real>(&self, k: &Knowns<R>) -> SpeedRamp<R> {
        SpeedRamp { target: k[self.speed_setpoint], duration_s: k[self.ramp_time] }
    }

    pub fn controller<R: Real>(&self, k: &Knowns<R>) -> PiController<R> {
        let limit = k[self.t_limit];
        let output_limit = if limit > 0.0 { limit } else { R::from(f64::INFINITY) };
        PiController { proportional_gain: k[self.kp], integral_gain: k[self.ki], output_limit, tracking_time_s: k[self.t_tracking] }
    }

    /// The set-point filter, if one is chosen.
    pub fn filter<R: Real>(&self, k: &Knowns<R>) -> Option<SecondOrderFilter<R>> {
        let natural_frequency_hz = match k[self.setpoint_filter] {
            0 => return None,
            1 => k[self.filter_below],
            _ => k[self.filter_above],
        };
        Some(SecondOrderFilter { natural_frequency_hz, damping: k[self.filter_damping] })
    }

    pub fn ramp_time<R: Real>(&self, k: &Knowns<R>) -> R {
        k[self.ramp_time]
    }
}

/// The torque actuator of the PI start: the converter-fed motor follows the PI's command through
/// a second-order lag (book file Chap3_CoolingTowerFan.mo, component secondOrder: w = 2*3.14*800
/// rad/s, D = 1). Declared by MotorFan only: the SpeedController subsystem sends its command to
/// InductionMotor without a lag.
pub struct TorqueActuatorParameters {
    angular_frequency: Parameter,
    damping: Parameter,
}

impl TorqueActuatorParameters {
    pub fn declare(d: &mut Declarations) -> Self {
        TorqueActuatorParameters {
            angular_frequency: d
                .parameter("actuator_angular_frequency", 2.0 * 3.14 * 800.0, "rad/s")
                .min(0.0)
                .tunable()
                .describe("Torque actuator's natural angular frequency, 0 = no lag (the motor torque is the PI's command; the earlier chosen set) (book file Chap3_CoolingTowerFan.mo, component secondOrder: w = 2*3.14*800, pi written 3.14)"),
            damping: d.parameter("actuator_damping", 1.0, "1").positive().tunable().describe("Torque actuator's damping ratio (book file Chap3_CoolingTowerFan.mo, component secondOrder: D = 1)"),
        }
    }

    /// The lag, or None when the command acts at once.
    pub fn lag<R: Real>(&self, k: &Knowns<R>) -> Option<SecondOrderFilter<R>> {
        (k[self.angular_frequency] > 0.0).then(|| SecondOrderFilter::from_angular_frequency(k[self.angular_frequency], k[self.damping]))
    }
}

/// The speed set point and its filter states: w_ref, dw_ref/dt and (filter on) d2w_ref/dt2.
pub struct SetPoint<R = f64> {
    pub reference: R,
    pub rate: R,
    pub acceleration: R,
}

impl<R: Real> SetPoint<R> {
    /// From the ramp, through the filter whose states are (`filtered`, `filtered_rate`).
    pub fn at(params: &ControllerParameters, k: &Knowns<R>, filtered: R, filtered_rate: R) -> SetPoint<R> {
        let ramp = params.ramp(k);
        let t = R::from(k.time());
        match params.filter(k) {
            None => SetPoint { reference: ramp.value(t), rate: ramp.slope(t), acceleration: R::from(0.0) },
            Some(f) => SetPoint { reference: filtered, rate: filtered_rate, acceleration: f.acceleration(ramp.value(t), filtered, filtered_rate) },
        }
    }
}

/// A converter-fed motor: the power it draws is the mechanical power (an ideal converter and
/// machine) and its current that of the machine at rated flux (constant V/f) giving that
/// torque: the 50 Hz circuit at the slip of that torque. Returns (current rms, power).
///
/// At zero torque exactly (a converter-fed start from rest) the current's derivatives come from
/// [`current_at_zero_torque`]: the slip found there by bisection, about 1e-19, is 0 to the
/// circuit's resolution, and neither the slip's derivative (found through |T|, whose derivative
/// a `Dual` takes as 0 at 0) nor the circuit's derivative at such a slip (R_r / s about 1e18:
/// the forward derivative cancels to nothing) survives. The value is the circuit's, bit for bit.
pub fn converter_fed<R: Real>(machine: &InductionMachine<R>, torque_n_m: R, speed_rad_per_s: R) -> (R, R) {
    let slip = machine.stable_slip_for_torque(torque_n_m);
    let mut current_rms_a = machine.steady_state_at_slip(slip).stator_current_rms_a;
    if torque_n_m == 0.0 {
        current_rms_a = with_derivatives_of(current_rms_a.value(), current_at_zero_torque(machine, torque_n_m));
    }
    (current_rms_a, torque_n_m * speed_rad_per_s)
}

/// The stator current rms at a torque of value 0, carrying its derivatives: those of the
/// machine's parameters at slip 0, and the torque's through the slip, ds = dT / (dT/ds at s = 0).
/// The circuit is written in s Z_r = R_r + j s X_r, smooth through s = 0:
/// I_s = V s (Z_m + Z_r) / (Z_s s (Z_m + Z_r) + Z_m s Z_r); near s = 0 the torque is
/// T = 3 |V Z_m / (Z_s + Z_m)|^2 s / (R_r W_s) (Thevenin's source seen by the rotor branch, whose
/// impedance R_r / s is then all that limits the rotor current).
pub fn current_at_zero_torque<R: Real>(machine: &InductionMachine<R>, torque_n_m: R) -> R {
    let zero = R::from(0.0);
    let w = machine.supply_angular_frequency();
    let v = Complex::new(machine.phase_voltage_rms_v(), zero);
    let z_s = Complex::new(machine.stator_resistance_ohm, w * machine.stator_leakage_h);
    let z_m = Complex::new(zero, w * machine.magnetizing_h);
    // dT/ds at s = 0, a plain number: it multiplies dT, whose value here is 0.
    let thevenin = (v * z_m / (z_s + z_m)).norm_sqr().value();
    let torque_per_slip = thevenin * 3.0 / (machine.rotor_resistance_ohm.value() * machine.synchronous_speed_rad_per_s().value());
    let slip = torque_n_m / torque_per_slip;
    let s_z_r = Complex::new(machine.rotor_resistance_ohm, slip * w * machine.rotor_leakage_h);
    let s_z_mr = Complex::new(slip, zero) * z_m + s_z_r;
    (v * s_z_mr / (z_s * s_z_mr + z_m * s_z_r)).abs()
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
