//! MemsAccelerometer: the surface-micromachined capacitive accelerometer of chapter section
//! 3.4.1.1, Figure 3.14 (question 2: the dominant effect of each part). A polysilicon proof mass
//! hangs on folded beams above the substrate; its fingers sit between fixed fingers, 1 um away on
//! either side, forming a differential pair of parallel-plate capacitors; the air in those gaps is
//! squeezed as the mass moves, and the air under it is sheared. A charge amplifier reads the
//! capacitance difference on a square-wave carrier, a synchronous demodulator and a two-pole
//! low-pass filter make the output voltage. The contract: `docs/mems-accelerometer-spec.md`.
//!
//! In the frame's coordinates (x the mass's displacement from rest, towards electrode 1):
//! * m dv/dt = -m a - k x - b_squeeze(x) v - b_slide v + F_electrostatic, dx/dt = v;
//! * k = 2 E t w^3 / L^3 (folded flexure), b_squeeze(x) = mu_eff A t^2 (1/(g - x)^3 + 1/(g + x)^3),
//!   b_slide = mu_eff' A_plate / d;
//! * C_1 = eps A / (g - x), C_2 = eps A / (g + x); electrode 1 carries the carrier and the bias
//!   (mean square V_c^2 + V_b^2), electrode 2 the carrier (V_c^2): F = (W_1/2) dC_1/dx + (W_2/2) dC_2/dx;
//! * V_demodulated = V_c (C_2 - C_1) / C_f, a two-pole Butterworth at f_filter, V_out = G_out x its output;
//! * travel stops at +-x_stop (state events: the mass stops there, inelastically, and stays while
//!   the forces press it on).
//!
//! The chapter gives no values: each default is argued in `documentation.rs` (the FMU's page) and
//! the spec, from public data on ADXL-class devices and first principles.

use components::mems::{self, FrameAcceleration, ParallelPlate, SlideFilm, SqueezeFilm};
use components::{Mass, Ramp, SecondOrderFilter, SpeedRamp, TranslationalSpring, Weight};
use fmu_runtime::prelude::*;
use std::f64::consts::{FRAC_1_SQRT_2, PI};

mod documentation;

/// The defaults, argued in documentation.rs: the layout of an ADXL-type sensor (COMSOL's public
/// "surface micromachined accelerometer" model gives these dimensions), in 2 um polysilicon.
mod defaults {
    use components::mems::POLYSILICON_DENSITY_KG_PER_M3;

    /// Structural polysilicon thickness (beams, plate, fingers), m.
    pub const THICKNESS_M: f64 = 2e-6;
    const PLATE_LENGTH_M: f64 = 448e-6;
    const PLATE_WIDTH_M: f64 = 100e-6;
    /// 4 um square release holes on an 18 um pitch: (4/18)^2 of the plate is open.
    const ETCH_HOLE_FRACTION: f64 = (4.0 * 4.0) / (18.0 * 18.0);
    /// 21 sense fingers on each long side of the plate.
    const FINGERS: f64 = 42.0;
    const FINGER_LENGTH_M: f64 = 114e-6;
    const FINGER_WIDTH_M: f64 = 4e-6;
    /// Length over which a moving finger faces its fixed neighbours.
    const FINGER_OVERLAP_M: f64 = 104e-6;

    /// The proof mass's footprint, the plate less its holes plus the fingers, m2.
    pub fn plate_area_m2() -> f64 {
        PLATE_LENGTH_M * PLATE_WIDTH_M * (1.0 - ETCH_HOLE_FRACTION) + FINGERS * FINGER_LENGTH_M * FINGER_WIDTH_M
    }

    /// m = rho t A_plate, kg.
    pub fn proof_mass_kg() -> f64 {
        POLYSILICON_DENSITY_KG_PER_M3 * THICKNESS_M * plate_area_m2()
    }

    /// One side's electrode area: each moving finger faces one fixed finger of each set, A = N l t, m2.
    pub fn electrode_area_m2() -> f64 {
        FINGERS * FINGER_OVERLAP_M * THICKNESS_M
    }
}

/// Standard gravity g_n, m/s2: the unit in which the outputs per g are given.
const G_N: f64 = Weight::STANDARD_GRAVITY_M_PER_S2;

pub struct MemsAccelerometer {
    profile: IntegerParameter,
    a_step: Parameter,
    a_sine: Parameter,
    f_sine: Parameter,
    t_start: Parameter,
    m_proof: Parameter,
    e_beam: Parameter,
    l_beam: Parameter,
    w_beam: Parameter,
    t_structure: Parameter,
    a_electrode: Parameter,
    gap: Parameter,
    a_plate: Parameter,
    d_substrate: Parameter,
    p_gas: Parameter,
    t_gas: Parameter,
    x_stop: Parameter,
    v_carrier: Parameter,
    v_bias: Parameter,
    t_bias_ramp: Parameter,
    c_feedback: Parameter,
    f_filter: Parameter,
    g_out: Parameter,
    a_in: Input,
    x: State,
    v: State,
    u_filter: State,
    w_filter: State,
    contact: Mode,
    stop: Indicator,
    powers: Powers,
    y_displacement: Output,
    y_velocity: Output,
    y_acceleration: Output,
    y_c1: Output,
    y_c2: Output,
    y_delta_c: Output,
    y_demodulated: Output,
    y_v_out: Output,
    y_measured: Output,
    y_force: Output,
    y_stop_force: Output,
    y_at_stop: Output,
    y_bias: Local,
    k_suspension: Local,
    f_natural: Local,
    k_electrostatic: Local,
    f_natural_carrier: Local,
    b_squeeze: Local,
    b_slide: Local,
    q_factor: Local,
    c_0: Local,
    v_pull_in: Local,
    v_pull_in_symmetric: Local,
    x_per_g: Local,
    delta_c_per_g: Local,
    v_out_per_g: Local,
    bandwidth: Local,
    knudsen: Local,
    squeeze_number: Local,
}

/// The elements whose power the equations report (Table 3.1's sources, storages and dissipations).
struct Powers {
    frame: Element,
    mass: Element,
    beams: Element,
    squeeze: Element,
    slide: Element,
    capacitors: Element,
    carrier: Element,
    bias: Element,
}

/// The accelerometer's parts at the current parameter values.
struct Parts<R = f64> {
    mass: Mass<R>,
    inertial: FrameAcceleration<R>,
    beams: TranslationalSpring<R>,
    squeeze: SqueezeFilm<R>,
    slide: SlideFilm<R>,
    /// Electrode 1: x closes its gap.
    plate_1: ParallelPlate<R>,
    /// Electrode 2: -x closes its gap (the same plate seen from the other side).
    plate_2: ParallelPlate<R>,
    filter: SecondOrderFilter<R>,
    carrier_v: R,
    feedback_f: R,
    gain: R,
    stop_m: R,
}

impl<R: Real> Parts<R> {
    /// The electrostatic stiffness of the carrier alone at rest, both sides: 2 eps A V_c^2 / g^3.
    fn carrier_softening(&self) -> R {
        let w = self.carrier_v * self.carrier_v;
        self.plate_1.softening_n_per_m(w, R::from(0.0)) + self.plate_2.softening_n_per_m(w, R::from(0.0))
    }

    /// The suspension less the carrier's softening: the stiffness the mass rests on, N/m.
    fn effective_stiffness(&self) -> R {
        self.beams.stiffness_n_per_m - self.carrier_softening()
    }

    /// dV_demodulated / dx at rest: V_c d(C_2 - C_1)/dx / C_f = -2 V_c (eps A / g^2) / C_f, V/m.
    fn read_out_gain_v_per_m(&self) -> R {
        -(self.plate_1.capacitance_gradient_f_per_m(R::from(0.0)) + self.plate_2.capacitance_gradient_f_per_m(R::from(0.0))) * self.carrier_v / self.feedback_f
    }

    /// The static output per unit of frame acceleration, V/(m/s2): x = -m a / k_eff read out and
    /// amplified (the filter has unit static gain).
    fn sensitivity_v_per_m_s2(&self) -> R {
        -self.gain * self.read_out_gain_v_per_m() * self.mass.mass_kg / self.effective_stiffness()
    }

    /// |H(j w) / H(0)| of the linearised sensor at rest (bias off): the mass on k_eff and
    /// b_squeeze(0) + b_slide, then the filter.
    fn relative_gain(&self, w: R) -> R {
        use components::complex::Complex;
        let k = self.effective_stiffness();
        let b = self.squeeze.damping_n_s_per_m(R::from(0.0)) + self.slide.damper().damping_n_s_per_m;
        let mechanics = Complex::new(k, R::from(0.0)) / Complex::new(k - self.mass.mass_kg * w * w, b * w);
        let wn = self.filter.natural_frequency_hz * (2.0 * PI);
        let filter = Complex::new(wn * wn, R::from(0.0)) / Complex::new(wn * wn - w * w, self.filter.damping * 2.0 * wn * w);
        (mechanics * filter).abs()
    }

    /// The bandwidth, Hz: the lowest frequency at which the output's amplitude per unit of
    /// acceleration leaves the +-3 dB band around its static value ([1/sqrt 2, sqrt 2] of it: a
    /// roll-off or a resonance peak, whichever comes first). A scan in steps of 2 %, then bisection
    /// on values; the derivatives are those of the crossing, |H| = the band's edge
    /// ([`components::roots::with_derivatives`]).
    fn bandwidth_hz(&self) -> R {
        let gain = |w: f64| self.relative_gain(R::from(w)).value();
        let outside = |w: f64| !(FRAC_1_SQRT_2..=std::f64::consts::SQRT_2).contains(&gain(w));
        let w0 = (self.effective_stiffness() / self.mass.mass_kg).sqrt().value();
        let wn = (self.filter.natural_frequency_hz * (2.0 * PI)).value();
        let (mut lo, top) = (1e-3 * w0.min(wn), 1e3 * w0.max(wn));
        while lo < top {
            let hi = lo * 1.02;
            if outside(hi) {
                let root = components::roots::bisect(lo, hi, 60, |w| !outside(w));
                // The edge crossed: the roll-off's 1/sqrt 2, or the peak's sqrt 2.
                let edge = |g: f64| if g < 1.0 { FRAC_1_SQRT_2 } else { std::f64::consts::SQRT_2 };
                let w = components::roots::with_derivatives(root, hi - lo, |w: R| self.relative_gain(w) - edge(gain(root)));
                return w / (2.0 * PI);
            }
            lo = hi;
        }
        R::from(f64::NAN)
    }
}

/// Everything the equations give at one instant.
#[derive(Default)]
struct Operating<R = f64> {
    acceleration: R,
    bias_v: R,
    c_1: R,
    c_2: R,
    electrostatic: R,
    /// The force on the mass at rest (no damping): what presses it on a stop, N.
    static_force: R,
    dv: R,
    dx: R,
    demodulated: R,
    p_frame: R,
    p_mass: R,
    p_beams: R,
    p_squeeze: R,
    p_slide: R,
    p_capacitors: R,
    p_carrier: R,
    p_bias: R,
}

impl MemsAccelerometer {
    fn parts<R: Real>(&self, k: &Knowns<R>) -> Parts<R> {
        let t = k[self.t_structure];
        let m = k[self.m_proof];
        let lambda = mems::mean_free_path_m(R::from(mems::AIR_VISCOSITY_PA_S), k[self.p_gas], k[self.t_gas], R::from(mems::AIR_MOLAR_MASS_KG_PER_MOL));
        let plate = ParallelPlate { permittivity_f_per_m: R::from(mems::VACUUM_PERMITTIVITY_F_PER_M), area_m2: k[self.a_electrode], gap_m: k[self.gap] };
        Parts {
            mass: Mass { mass_kg: m },
            inertial: FrameAcceleration { mass_kg: m },
            beams: TranslationalSpring {
                stiffness_n_per_m: mems::folded_flexure_stiffness_n_per_m(k[self.e_beam], t, k[self.w_beam], k[self.l_beam]),
                damping_n_s_per_m: R::from(0.0),
            },
            squeeze: SqueezeFilm {
                effective_viscosity_pa_s: mems::squeeze_film_effective_viscosity_pa_s(R::from(mems::AIR_VISCOSITY_PA_S), lambda / k[self.gap]),
                area_m2: k[self.a_electrode],
                width_m: t,
                gap_m: k[self.gap],
            },
            slide: SlideFilm {
                effective_viscosity_pa_s: mems::slide_film_effective_viscosity_pa_s(R::from(mems::AIR_VISCOSITY_PA_S), lambda / k[self.d_substrate]),
                area_m2: k[self.a_plate],
                gap_m: k[self.d_substrate],
            },
            plate_1: plate,
            plate_2: plate,
            filter: SecondOrderFilter { natural_frequency_hz: k[self.f_filter], damping: R::from(FRAC_1_SQRT_2) },
            carrier_v: k[self.v_carrier],
            feedback_f: k[self.c_feedback],
            gain: k[self.g_out],
            stop_m: k[self.x_stop],
        }
    }

    /// The built-in acceleration profile, m/s2: 1 (a step at t_start), 2 (a sine from t_start).
    fn profile_value<R: Real>(&self, k: &Knowns<R>) -> R {
        let t = k.time();
        match k[self.profile] {
            1 => Ramp { start_s: k[self.t_start], duration_s: R::from(0.0), height: k[self.a_step] }.value(R::from(t)),
            2 if t >= k[self.t_start].value() => k[self.a_sine] * (k[self.f_sine] * (2.0 * PI) * (R::from(t) - k[self.t_start])).sin(),
            _ => R::from(0.0),
        }
    }

    /// The bias on electrode 1, ramped from 0 over t_bias_ramp (a step at t = 0 when it is 0).
    fn bias_ramp<R: Real>(&self, k: &Knowns<R>) -> SpeedRamp<R> {
        SpeedRamp { target: k[self.v_bias], duration_s: k[self.t_bias_ramp] }
    }

    fn operate<R: Real>(&self, p: &Parts<R>, k: &Knowns<R>) -> Operating<R> {
        let (x, v) = (k[self.x], k[self.v]);
        let t = k.time();
        let acceleration = self.profile_value(k) + k[self.a_in];
        let ramp = self.bias_ramp(k);
        let (bias_v, bias_rate) = (ramp.value(R::from(t)), ramp.slope(R::from(t)));
        let carrier_ms = p.carrier_v * p.carrier_v;
        let (ms_1, ms_2) = (carrier_ms + bias_v * bias_v, carrier_ms);
        let ms_rate_1 = bias_v * 2.0 * bias_rate;
        let (c_1, c_2) = (p.plate_1.capacitance_f(x), p.plate_2.capacitance_f(-x));
        let electrostatic = p.plate_1.force_n(ms_1, x) - p.plate_2.force_n(ms_2, -x);
        let static_force = p.inertial.force_n(acceleration) - p.beams.force_n(x, R::from(0.0)) + electrostatic;
        let mut op = Operating { acceleration, bias_v, c_1, c_2, electrostatic, static_force, ..Operating::default() };
        op.demodulated = p.carrier_v * (c_2 - c_1) / p.feedback_f;
        if k[self.contact] == 0 {
            let squeeze = p.squeeze.force_n(x, v);
            let slide = -p.slide.damper().force_n(v);
            op.dx = v;
            op.dv = p.mass.acceleration_m_per_s2(static_force + squeeze + slide);
        }
        // At a stop v = 0 and nothing moves: every mechanical power is 0, the bias ramp still
        // charges electrode 1.
        let (dx, dv) = (op.dx, op.dv);
        op.p_frame = p.inertial.power_w(acceleration, dx);
        op.p_mass = p.mass.power_w(dv, dx);
        op.p_beams = p.beams.spring_power_w(x, dx);
        op.p_squeeze = p.squeeze.power_w(x, dx);
        op.p_slide = p.slide.damper().power_w(dx);
        op.p_capacitors = p.plate_1.storage_power_w(ms_1, ms_rate_1, x, dx) + p.plate_2.storage_power_w(ms_2, R::from(0.0), -x, -dx);
        op.p_carrier = p.plate_1.source_power_w(carrier_ms, R::from(0.0), x, dx) + p.plate_2.source_power_w(carrier_ms, R::from(0.0), -x, -dx);
        op.p_bias = p.plate_1.source_power_w(bias_v * bias_v, ms_rate_1, x, dx);
        op
    }
}

impl Model for MemsAccelerometer {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "MemsAccelerometer",
            description: "Surface-micromachined capacitive accelerometer (chapter 3, section 3.4.1.1, Figure 3.14): polysilicon proof mass on folded beams, squeeze- and slide-film air damping, differential parallel-plate sense capacitors with their electrostatic force, travel stops, charge-amplifier read-out with demodulator and two-pole low-pass; ADXL-class values",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 3e-3, step_size: 1e-5 },
            // Fastest mode: the proof mass at 24 kHz (|lambda| = 1.5e5 /s, damping ratio 1.8 %); the
            // filter's pair at 1 kHz. Not stiff.
            solver: Solver::ExplicitRungeKutta,
            documentation: documentation::HTML,
        }
    }

    /// Measured (tests/python/accuracy_table.py, against rtol 1e-10): at rtol 1e-3 the activities of
    /// the mass, the beams, the capacitors and the sources are 0.0105 of their range off (10.5 x
    /// rtol: |p| rectifies the 24 kHz ringing after the step, and an error in its phase accumulates);
    /// at 1e-4 at most 8.3e-4, at 1e-5 2.6e-5, at 1e-8 7e-8; the displacement follows rtol within 3.2 x.
    fn tolerance_floor(&self, _k: &Knowns) -> Option<f64> {
        Some(1e-4)
    }

    fn declare(d: &mut Declarations) -> Self {
        MemsAccelerometer {
            profile: d.integer_parameter("profile", 1).choices(1, &[("step", "a step of a_step at t_start"), ("sine", "a sine of a_sine at f_sine from t_start")]).describe(
                "Built-in frame acceleration added to the input a_frame: 1 a step of a_step at t_start, 2 a sine of amplitude a_sine and frequency f_sine from t_start (a_step or a_sine = 0: the input alone)",
            ),
            a_step: d.parameter("a_step", 10.0 * G_N, "m/s2").describe("Height of the built-in acceleration step (10 g_n; the ADXL50's range is +-50 g)"),
            a_sine: d.parameter("a_sine", 10.0 * G_N, "m/s2").describe("Amplitude of the built-in acceleration sine (10 g_n)"),
            f_sine: d.parameter("f_sine", 1000.0, "Hz").min(0.0).describe("Frequency of the built-in acceleration sine (1 kHz, the read-out filter's corner)"),
            t_start: d.parameter("t_start", 1e-4, "s").min(0.0).describe("Time the built-in step or sine starts"),
            m_proof: d.parameter("m_proof", defaults::proof_mass_kg(), "kg").positive().describe(
                "Proof mass: a 448 x 100 um plate (4/18 squared of it open in release holes) with 42 fingers of 114 x 4 um, 2 um of polysilicon at 2330 kg/m3 (COMSOL's ADXL-type layout)",
            ),
            e_beam: d.parameter("E_beam", mems::POLYSILICON_YOUNG_MODULUS_PA, "Pa").positive().describe("Young's modulus of the polysilicon beams (160 GPa; tensile tests of MUMPs polysilicon 158-169 GPa)"),
            l_beam: d.parameter("L_beam", 92e-6, "m").positive().describe(
                "Length of each of the folded flexure's 8 beams (chosen: puts the resonance at the ADXL50's 24 kHz, Analog Devices AN-377)",
            ),
            w_beam: d.parameter("w_beam", 2e-6, "m").positive().describe("Width of the beams in the direction of motion (2 um, the layout's spring width)"),
            t_structure: d.parameter("t_structure", defaults::THICKNESS_M, "m").positive().describe(
                "Thickness of the structural polysilicon: beams, plate and fingers (2 um, the ADXL50's sensor layer)",
            ),
            a_electrode: d.parameter("A_electrode", defaults::electrode_area_m2(), "m2").positive().describe(
                "Electrode area of each sense capacitor: 42 moving fingers, each facing one fixed finger of the set over 104 um x 2 um",
            ),
            gap: d.parameter("gap", 1e-6, "m").positive().describe("Gap between a moving finger and each of its fixed neighbours at rest (1 um, the layout's finger gap)"),
            a_plate: d.parameter("A_plate", defaults::plate_area_m2(), "m2").positive().describe("Area of the proof mass facing the substrate (the slide film's area)"),
            d_substrate: d.parameter("d_substrate", 1.6e-6, "m").positive().describe("Height of the proof mass above the substrate (1.6 um, the sacrificial oxide's thickness)"),
            p_gas: d.parameter("p_gas", 101_325.0, "Pa").positive().describe("Pressure of the air in the package (1 atm: a sensor sealed with air at atmospheric pressure)"),
            t_gas: d.parameter("T_gas", 298.15, "K").positive().describe("Temperature of the air (25 degrees C): sets its mean free path with p_gas"),
            x_stop: d.parameter("x_stop", 0.5e-6, "m").positive().describe(
                "Travel to the overtravel stops on either side (half the gap: beyond the pull-in point gap/3, short of the fingers' contact)",
            ),
            v_carrier: d.parameter("V_carrier", 1.0, "V").min(0.0).describe(
                "Amplitude of the read-out's square-wave excitation on both fixed electrodes (antiphase); the mass sees its mean square on each side (chosen)",
            ),
            v_bias: d.parameter("V_bias", 0.0, "V").min(0.0).describe("DC voltage added on electrode 1 only (self-test, pull-in study)"),
            t_bias_ramp: d.parameter("t_bias_ramp", 0.0, "s").min(0.0).describe("Time over which V_bias rises from 0 (0: applied from the start)"),
            c_feedback: d.parameter("C_feedback", 100e-15, "F").positive().describe("Feedback capacitance of the charge amplifier (chosen: 100 fF, of the order of the sense capacitance)"),
            f_filter: d.parameter("f_filter", 1000.0, "Hz").positive().describe(
                "Corner of the two-pole Butterworth low-pass after the demodulator (1 kHz: ADXL series specified dc to 1 kHz, AN-377)",
            ),
            g_out: d.parameter("G_out", 28.0, "1").describe("Gain after the filter (trimmed: 19.0 mV/g, the ADXL50's factory-trimmed 19 mV/g)"),
            a_in: d.input("a_frame", 0.0, "m/s2").describe("Acceleration of the frame (the package) along the sensitive axis, added to the built-in profile"),
            x: d.state("x_proof", 0.0, "m").nominal(1e-8).describe("Displacement of the proof mass from rest relative to the frame, towards electrode 1"),
            v: d.state("v_proof", 0.0, "m/s").nominal(1e-3).describe("Velocity of the proof mass relative to the frame"),
            u_filter: d.state("u_filter", 0.0, "V").nominal(1e-2).describe("Output of the two-pole low-pass (before G_out)"),
            w_filter: d.state("w_filter", 0.0, "V").nominal(1e-2).describe("Rate of the low-pass output over its angular frequency, (d u_filter/dt) / (2 pi f_filter)"),
            contact: d.mode("stop_contact", 0).range(-1, 1).describe("Travel stop: 0 free, 1 resting on the stop towards electrode 1, -1 on the one towards electrode 2"),
            stop: d.event_indicator(
                "travel_stop",
                "free: (x_stop^2 - x^2) / (2 x_stop), the travel left to the nearer stop; on a stop: the force pressing the mass on it",
            ),
            powers: declare_elements(d),
            y_displacement: d.output("displacement", "m").describe("Proof-mass displacement x relative to the frame (towards electrode 1; a positive acceleration moves it towards electrode 2)"),
            y_velocity: d.output("velocity", "m/s").describe("Proof-mass velocity relative to the frame"),
            y_acceleration: d.output("acceleration_frame", "m/s2").describe("Acceleration of the frame: the built-in profile plus a_frame"),
            y_c1: d.output("C_1", "F").describe("Sense capacitance of electrode 1, eps A / (gap - x)"),
            y_c2: d.output("C_2", "F").describe("Sense capacitance of electrode 2, eps A / (gap + x)"),
            y_delta_c: d.output("delta_C", "F").describe("Sensed capacitance change C_1 - C_2 (negative for a positive acceleration)"),
            y_demodulated: d.output("V_demodulated", "V").describe("Charge amplifier output after synchronous demodulation, V_carrier (C_2 - C_1) / C_feedback"),
            y_v_out: d.output("V_out", "V").describe("Output voltage: G_out times the low-pass output (about the zero-g level)"),
            y_measured: d.output("acceleration_measured", "m/s2").describe("The acceleration the sensor reports, V_out over its static sensitivity (V_out_per_g / g_n); 0 without a carrier"),
            y_force: d.output("F_electrostatic", "N").describe("Net electrostatic force of the two electrodes on the proof mass (positive towards electrode 1)"),
            y_stop_force: d.output("F_stop", "N").describe("Force of the travel stop on the proof mass (0 while free)"),
            y_at_stop: d.output("at_stop", "1").discrete().describe("1 while the proof mass rests on the stop towards electrode 1 (e.g. pulled in), -1 on the other, 0 free"),
            y_bias: d.local("V_bias_applied", "V").describe("Bias voltage on electrode 1 at this instant (the ramp)"),
            k_suspension: d.calculated_parameter("k_suspension", "N/m").describe("Folded-flexure stiffness 2 E_beam t_structure w_beam^3 / L_beam^3 (Tang, Nguyen and Howe 1989)"),
            f_natural: d.calculated_parameter("f_natural", "Hz").describe("Natural frequency of the proof mass on its beams, sqrt(k_suspension / m_proof) / 2 pi (carrier off)"),
            k_electrostatic: d.calculated_parameter("k_electrostatic", "N/m").describe("Electrostatic softening of the carrier at rest, 2 eps0 A_electrode V_carrier^2 / gap^3"),
            f_natural_carrier: d.calculated_parameter("f_natural_carrier", "Hz").describe("Natural frequency with the carrier's softening, sqrt((k_suspension - k_electrostatic) / m_proof) / 2 pi"),
            b_squeeze: d.calculated_parameter("b_squeeze", "N.s/m").describe("Squeeze-film damping of the finger gaps at rest, 2 mu_eff A_electrode t_structure^2 / gap^3"),
            b_slide: d.calculated_parameter("b_slide", "N.s/m").describe("Slide-film damping under the proof mass, mu_eff A_plate / d_substrate"),
            q_factor: d.calculated_parameter("Q_factor", "1").describe("Quality factor of the mechanical mode, sqrt(m_proof k_eff) / (b_squeeze + b_slide)"),
            c_0: d.calculated_parameter("C_0", "F").describe("Sense capacitance of each electrode at rest, eps0 A_electrode / gap"),
            v_pull_in: d.calculated_parameter("V_pull_in", "V").describe(
                "Pull-in voltage of electrode 1 alone (carrier off), sqrt(8 k_suspension gap^3 / (27 eps0 A_electrode)): V_bias beyond it snaps the mass onto the stop",
            ),
            v_pull_in_symmetric: d.calculated_parameter("V_pull_in_symmetric", "V").describe(
                "Carrier amplitude at which the rest position loses its stiffness, sqrt(k_suspension gap^3 / (2 eps0 A_electrode)) (V_carrier must stay below it)",
            ),
            x_per_g: d.calculated_parameter("x_per_g", "m").describe("Static deflection for 1 g_n, m_proof g_n / k_eff (the mass lags: x = -x_per_g a / g_n)"),
            delta_c_per_g: d.calculated_parameter("delta_C_per_g", "F").describe("Capacitance difference C_2 - C_1 for 1 g_n at rest, 2 C_0 x_per_g / gap (linearised)"),
            v_out_per_g: d.calculated_parameter("V_out_per_g", "V").describe("Static output for 1 g_n, G_out V_carrier delta_C_per_g / C_feedback"),
            bandwidth: d.calculated_parameter("bandwidth", "Hz").describe(
                "Lowest frequency at which the output per unit acceleration leaves +-3 dB of its static value (linearised at rest, bias off)",
            ),
            knudsen: d.calculated_parameter("Knudsen_gap", "1").describe("Knudsen number of the finger gap, mean free path / gap (sets the squeeze film's effective viscosity)"),
            squeeze_number: d.calculated_parameter("squeeze_number", "1").describe(
                "Squeeze number 12 mu_eff omega t_structure^2 / (p_gas gap^2) at f_natural_carrier: << 1, the film damps and does not spring",
            ),
        }
    }

    fn check(&self, k: &Knowns) -> Result<(), String> {
        if k[self.x_stop] >= k[self.gap] {
            return Err(format!("x_stop = {:e} m must be below gap = {:e} m: the stops keep the fingers apart", k[self.x_stop], k[self.gap]));
        }
        let p = self.parts(k);
        let plate = p.plate_1;
        let limit = plate.symmetric_pull_in_voltage_v(p.beams.stiffness_n_per_m);
        if k[self.v_carrier] >= limit {
            return Err(format!(
                "V_carrier = {:e} V leaves the proof mass no stable rest: the carrier's softening 2 eps0 A_electrode V_carrier^2 / gap^3 reaches \
                 k_suspension = 2 E_beam t_structure w_beam^3 / L_beam^3 = {:e} N/m at V_pull_in_symmetric = {limit:e} V (gap = {:e} m, A_electrode = {:e} m2)",
                k[self.v_carrier],
                p.beams.stiffness_n_per_m,
                k[self.gap],
                k[self.a_electrode]
            ));
        }
        Ok(())
    }

    fn next_time_event(&self, k: &Knowns, after: f64) -> Option<f64> {
        let start = (k[self.t_start] > after).then_some(k[self.t_start]);
        let ramp = if k[self.t_bias_ramp] > 0.0 { self.bias_ramp(k).next_kink(after) } else { None };
        [start, ramp].into_iter().flatten().min_by(f64::total_cmp)
    }

    fn event_indicators(&self, k: &Knowns, z: &mut EventIndicators) {
        let mode = k[self.contact];
        z[self.stop] = if mode == 0 {
            let (s, x) = (k[self.x_stop], k[self.x]);
            (s * s - x * x) / (2.0 * s)
        } else {
            let p = self.parts(k);
            f64::from(mode) * self.operate(&p, k).static_force
        };
    }

    fn update_modes(&self, k: &Knowns, next: &mut ModeUpdate) {
        let p = self.parts(k);
        let force = self.operate(&p, k).static_force;
        let (x, v) = (k[self.x], k[self.v]);
        let mode = k[self.contact];
        if mode == 0 {
            // A stop is reached moving towards it, or at rest pressed on it; the impact is inelastic.
            for side in [1, -1] {
                let s = f64::from(side);
                if s * x >= p.stop_m && (s * v > 0.0 || (v == 0.0 && s * force > 0.0)) {
                    next[self.contact] = side;
                    next.reinit(self.x, s * p.stop_m);
                    next.reinit(self.v, 0.0);
                }
            }
        } else if f64::from(mode) * force <= 0.0 {
            // The forces no longer press the mass on the stop: it leaves from rest.
            next[self.contact] = 0;
        }
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let p = self.parts(k);
        let op = self.operate(&p, k);
        der[self.x] = op.dx;
        der[self.v] = op.dv;
        // The filter u'' = wn^2 (V_demodulated - u) - 2 zeta wn u' with the scaled rate w = u' / wn as
        // its second state (both states in volts).
        let wn = p.filter.natural_frequency_hz * (2.0 * PI);
        let rate = wn * k[self.w_filter];
        der[self.u_filter] = rate;
        der[self.w_filter] = p.filter.acceleration(op.demodulated, k[self.u_filter], rate) / wn;
        let w = &self.powers;
        der.power(w.frame, op.p_frame);
        der.power(w.mass, op.p_mass);
        der.power(w.beams, op.p_beams);
        der.power(w.squeeze, op.p_squeeze);
        der.power(w.slide, op.p_slide);
        der.power(w.capacitors, op.p_capacitors);
        der.power(w.carrier, op.p_carrier);
        der.power(w.bias, op.p_bias);
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        let p = self.parts(k);
        let op = self.operate(&p, k);
        let sensitivity = p.sensitivity_v_per_m_s2();
        out[self.y_displacement] = k[self.x];
        out[self.y_velocity] = op.dx;
        out[self.y_acceleration] = op.acceleration;
        out[self.y_c1] = op.c_1;
        out[self.y_c2] = op.c_2;
        out[self.y_delta_c] = op.c_1 - op.c_2;
        out[self.y_demodulated] = op.demodulated;
        let v_out = p.gain * k[self.u_filter];
        out[self.y_v_out] = v_out;
        // Without a carrier (or a gain) the read-out measures nothing: it reports 0.
        out[self.y_measured] = if sensitivity == 0.0 { R::from(0.0) } else { v_out / sensitivity };
        out[self.y_force] = op.electrostatic;
        out[self.y_stop_force] = if k[self.contact] == 0 { R::from(0.0) } else { -op.static_force };
        out[self.y_at_stop] = R::from(f64::from(k[self.contact]));
        out[self.y_bias] = op.bias_v;
        let (m, stiffness) = (p.mass.mass_kg, p.beams.stiffness_n_per_m);
        let k_eff = p.effective_stiffness();
        out[self.k_suspension] = stiffness;
        out[self.f_natural] = p.beams.natural_frequency_hz(m, R::from(f64::INFINITY));
        out[self.k_electrostatic] = p.carrier_softening();
        out[self.f_natural_carrier] = (k_eff / m).sqrt() / (2.0 * PI);
        let (b_sq, b_sl) = (p.squeeze.damping_n_s_per_m(R::from(0.0)), p.slide.damper().damping_n_s_per_m);
        out[self.b_squeeze] = b_sq;
        out[self.b_slide] = b_sl;
        out[self.q_factor] = (m * k_eff).sqrt() / (b_sq + b_sl);
        out[self.c_0] = p.plate_1.capacitance_f(R::from(0.0));
        out[self.v_pull_in] = p.plate_1.pull_in_voltage_v(stiffness);
        out[self.v_pull_in_symmetric] = p.plate_1.symmetric_pull_in_voltage_v(stiffness);
        let x_g = m * G_N / k_eff;
        out[self.x_per_g] = x_g;
        out[self.delta_c_per_g] = (p.plate_1.capacitance_gradient_f_per_m(R::from(0.0)) + p.plate_2.capacitance_gradient_f_per_m(R::from(0.0))) * x_g;
        out[self.v_out_per_g] = sensitivity * G_N;
        out[self.bandwidth] = p.bandwidth_hz();
        let lambda = mems::mean_free_path_m(R::from(mems::AIR_VISCOSITY_PA_S), k[self.p_gas], k[self.t_gas], R::from(mems::AIR_MOLAR_MASS_KG_PER_MOL));
        out[self.knudsen] = lambda / k[self.gap];
        let t = k[self.t_structure];
        out[self.squeeze_number] = p.squeeze.effective_viscosity_pa_s * 12.0 * (k_eff / m).sqrt() * t * t / (k[self.p_gas] * k[self.gap] * k[self.gap]);
    }
}

/// The elements (Table 3.1) and the effects the model leaves out, each with the reason.
fn declare_elements(d: &mut Declarations) -> Powers {
    use components::{Resistor, TranslationalDamper};
    const NOMINAL_J: f64 = 1e-14;
    let frame = d
        .element("frame_acceleration", "Frame (package, substrate, anchors)", FrameAcceleration::SOURCE)
        .nominal(NOMINAL_J)
        .describe("the frame's acceleration a seen from the frame, the inertial force -m a on the proof mass, power -m a dx/dt");
    let frame_compliance = Effect { what: "compliance of the substrate and the anchors", ..TranslationalSpring::STIFFNESS };
    d.neglected("Frame (package, substrate, anchors)", frame_compliance, "a die some 0.5 mm thick under anchors of 17 um: its modes lie in the MHz, far above the proof mass's 24 kHz");
    let mass = d
        .element("proof_mass", "Proof mass", Effect { what: "proof mass (inertia)", ..Mass::MASS })
        .nominal(NOMINAL_J)
        .describe("the proof mass m_proof, power m v dv/dt");
    let beams = d
        .element("folded_beams", "Folded-beam suspension", Effect { what: "bending stiffness of the folded beams", ..TranslationalSpring::STIFFNESS })
        .nominal(NOMINAL_J)
        .describe("the folded flexure's stiffness k = 2 E t w^3 / L^3, power k x dx/dt");
    let beam_mass = Effect { what: "mass of the beams and trusses", ..Mass::MASS };
    d.neglected("Folded-beam suspension", beam_mass, "8 beams of 92 x 2 x 2 um weigh 6.9e-12 kg, 2.4 % of the proof mass; the share that moves with it, about a third (Rayleigh), would add 0.9 % to m (-0.4 % on f_natural)");
    let material = Effect { what: "material (thermoelastic) damping of the beams", ..TranslationalSpring::DAMPING };
    d.neglected("Folded-beam suspension", material, "polysilicon flexures in vacuum reach Q of 1e4 and more; the air's Q here is about 28");
    let squeeze = d
        .element("squeeze_film", "Air gaps between the fingers", SqueezeFilm::DAMPING)
        .nominal(NOMINAL_J)
        .describe("the air squeezed out of the 84 finger gaps, b(x) = mu_eff A t^2 (1/(g-x)^3 + 1/(g+x)^3), power b(x) v^2");
    let gas_spring = Effect { domains: &[Domain::Translational], kind: Kind::StorageC, what: "compressibility of the squeezed air (gas spring)" };
    d.neglected("Air gaps between the fingers", gas_spring, "the squeeze number at 24 kHz is 1e-3: the air flows out of the gaps long before it is compressed");
    let slide = d
        .element("slide_film", "Air gap under the proof mass", SlideFilm::DAMPING)
        .nominal(NOMINAL_J)
        .describe("the air sheared between the proof mass and the substrate 1.6 um below (Couette flow), b = mu_eff A_plate / d, power b v^2");
    let open_air = Effect { what: "drag of the open air above the proof mass", ..TranslationalDamper::DAMPING };
    d.neglected("Air gap under the proof mass", open_air, "the shear wave's depth sqrt(2 mu / (rho omega)) is 14 um at 24 kHz (71 um at 1 kHz), against the 1.6 um film below: 12 % of the slide film's drag at the resonance, 2 % in band");
    let capacitors = d
        .element("sense_capacitors", "Sense fingers (differential capacitor)", ParallelPlate::TRANSDUCER)
        .nominal(NOMINAL_J)
        .describe("the two parallel-plate sense capacitors eps A / (g -+ x) at their mean-square voltages, power d/dt (C_1 W_1 + C_2 W_2) / 2, coupling the electrical and mechanical domains");
    let fringing = Effect { domains: &[Domain::Electrical, Domain::Translational], kind: Kind::StorageC, what: "fringing fields of the fingers" };
    d.neglected(
        "Sense fingers (differential capacitor)",
        fringing,
        "parallel plates only, as the pull-in formula takes them; with 2 um thick fingers 1 um apart the fringes add tens of % to C and to the force (they lower V_pull_in)",
    );
    let carrier = d
        .element("carrier_excitation", "Read-out electronics", Effect { what: "square-wave excitation of both electrodes", ..ParallelPlate::DRIVE })
        .nominal(NOMINAL_J)
        .describe("the read-out's square waves of amplitude V_carrier on both fixed electrodes, mean-square power V_c^2 (dC_1/dt + dC_2/dt)");
    let bias = d
        .element("bias_voltage", "Bias / self-test", Effect { what: "DC bias on electrode 1", ..ParallelPlate::DRIVE })
        .nominal(NOMINAL_J)
        .describe("the DC bias V_bias on electrode 1, power V_b^2 dC_1/dt + (C_1/2) d(V_b^2)/dt");
    let electrode_resistance = Effect { what: "resistance of the polysilicon electrodes and leads", ..Resistor::RESISTANCE };
    d.neglected("Sense fingers (differential capacitor)", electrode_resistance, "kilo-ohms against 0.1 pF: time constants of 0.1 ns, 10^4 times faster than the carrier");
    d.element(
        "read_out",
        "Read-out electronics",
        Effect { domains: &[Domain::Electrical, Domain::Signal], kind: Kind::Transformer, what: "charge amplifier, demodulator, two-pole low-pass (a signal block)" },
    )
    .describe("the charge amplifier holds the proof mass at virtual ground and turns the charge V_c (C_2 - C_1) into a voltage over C_feedback; the demodulator and the filter are signals, with no power");
    let parasitics = Effect { what: "parasitic capacitances of the read-out node", ..components::Capacitor::CAPACITANCE };
    d.neglected("Read-out electronics", parasitics, "the charge amplifier's virtual ground keeps no voltage across them: they take no charge from the signal");
    Powers { frame, mass, beams, squeeze, slide, capacitors, carrier, bias }
}

fmu_runtime::export_fmu!(MemsAccelerometer);
