//! TorqueSensor: the magnetic torque sensor of an electric power steering (chapter section 3.5.2,
//! Figures 3.24-3.27, questions 1-9), as an FMU. The contract: `docs/torque-sensor-spec.md`.
//!
//! Chain (Figure 3.27): the driver's torque twists the torsion bar (mechanical part); the twist
//! changes the reluctance of ring B's magnetic circuit (magnetic part: windings A and B, rings A
//! and B); a Wheatstone-like bridge supplied at 5 kHz turns the inductance difference into a
//! 5 kHz bridge voltage, a multiplier demodulates it synchronously and a low-pass filter keeps
//! the mean (electronic part); the conditioning of question 9 turns that voltage into torque.
//!
//! * Magnetic part (questions 3, 4, 7): each winding (N turns, R_winding; the transformer T of
//!   Figure 3.26) sits in a yoke whose two poles face its detection ring across two radial air
//!   gaps, r1 (ring) to r2 (yoke bore) over the ring width b (Figure 3.26's a and c), with the
//!   iron of yoke and ring (b and d) in series. With infinitely permeable iron (question 4)
//!   L = N^2 / (2 ln(r2/r1) / (2 pi mu0 b)) = pi mu0 b N^2 / ln(r2/r1) = 82.84 mH for the
//!   chapter's r1 = 15 mm, r2 = 16.5 mm, b = 2 mm, N = 1000. Part A is Figure 3.26 as is: the
//!   reference arm. Part B (question 7) adds the new component, a toothed air gap between the
//!   teeth of ring B and those of ring A; the rings sit on the two ends of the torsion bar, so
//!   the teeth's overlap (the gap's section) follows the twist, the rings' relative angle.
//! * `arrangement` = 2 makes the sensor differential, the other reading of "a variable air gap for
//!   rings A and B": part A's circuit crosses the toothed gap too, at the opposite twist, so
//!   L_A(T) = L_B(-T). The bridge is then balanced at zero torque (no offset) and its output odd
//!   in the torque (1.4 % of its span from a straight line instead of 11 %). The default (1)
//!   follows question 7, where only part B gets a new component.
//! * The windings are modelled with their flux as state (Ampere and Lenz, question 1), so ring
//!   B's time-varying reluctance is handled exactly. Beside winding A, an R-L impedance with the
//!   inductance of question 4 (question 5) is driven the same way, for comparison.
//! * Electronics (question 8): each winding has a resistor R_bridge above it, both arms across
//!   the supply U sin(2 pi f t); the bridge voltage is R_bridge (i_B - i_A); the multiplier
//!   forms u_bridge x supply / U; a second-order Butterworth low-pass gives u_demodulated.
//! * Conditioning (question 9): the model computes its own steady-state characteristic
//!   u(twist) from the parameters by phasors (`Sensor::steady_demodulated_v`), removes the
//!   zero-torque offset u(0), and inverts u(twist) - u(0) to the twist, times the stiffness:
//!   `torque_measured`. No number is fitted: change a parameter and the calibration follows.
//!
//! Chosen values (the chapter gives r1, r2, b, N, R_winding = 30 Ohm, the 5 kHz supply, mu0):
//! * Torsion bar 2 N m/deg = 114.59 N m/rad, full scale +/- 8 N m (+/- 4 deg), stops at +/- 5 deg:
//!   usual for EPS torque sensors (a steel bar, G = 80 GPa, 4.6 mm in diameter and 30.7 mm long).
//! * Soft iron: a ferrite (mu_r = 2000, no eddy currents at 5 kHz) over a 30 mm path of section
//!   2 pi r1 b: 0.52 % of the gaps' reluctance, so question 4's "infinite permeability" holds to
//!   half a percent.
//! * Ring B's teeth: 8 teeth of half the 45 deg pitch (22.5 deg) at 12 mm radius, 5 mm long,
//!   0.3 mm radial gap, half-overlapping at rest (11.25 deg), so the overlap stays inside the
//!   teeth over the +/- 5 deg of the stops. Not tuned for linearity: the raw output is what it is
//!   (offset 0.232 V, slope -10.2 mV/(N m), 11 % of its span away from a straight line), which is
//!   why the conditioning inverts the characteristic rather than fitting a line.
//! * Supply 5 V amplitude at 5 kHz; R_bridge = 2.2 kOhm, the E12 value nearest the arm
//!   impedance w L_B(0) - R_winding = 2.11 kOhm that maximizes the in-phase sensitivity.
//! * Low-pass: second-order Butterworth at 200 Hz (the 10 kHz ripple is attenuated 2500x; the
//!   step response settles in ~5 ms, well above steering bandwidths of ~10 Hz).

use components::{Multiplier, Ramp, Reluctance, SecondOrderFilter, SineVoltage, ToothedAirGap, TorsionBar, Winding};
use fmu_runtime::prelude::*;

mod documentation;
pub mod sensor;

pub use sensor::Sensor;

pub struct TorqueSensor {
    torque_full_scale: Parameter,
    k_torsion_bar: Parameter,
    twist_stop: Parameter,
    turns: Parameter,
    r_winding: Parameter,
    r1: Parameter,
    r2: Parameter,
    b: Parameter,
    mu_r_iron: Parameter,
    iron_path_length: Parameter,
    teeth: Parameter,
    tooth_radius: Parameter,
    tooth_length: Parameter,
    tooth_gap: Parameter,
    tooth_width: Parameter,
    rest_overlap: Parameter,
    arrangement: IntegerParameter,
    supply_mode: IntegerParameter,
    u_supply_amplitude: Parameter,
    f_supply: Parameter,
    r_bridge: Parameter,
    f_filter: Parameter,
    filter_damping: Parameter,
    torque_profile: IntegerParameter,
    profile_height: Parameter,
    profile_start: Parameter,
    profile_duration: Parameter,
    torque_in: Input,
    flux_a: State,
    flux_b: State,
    i_rl: State,
    filter_y: State,
    filter_z: State,
    y_torque: Output,
    y_twist: Output,
    y_supply: Output,
    y_i_a: Output,
    y_i_b: Output,
    y_i_rl: Output,
    y_flux_a: Output,
    y_flux_b: Output,
    y_l_a: Output,
    y_l_b: Output,
    y_bridge: Output,
    y_product: Output,
    y_demodulated: Output,
    y_measured: Output,
    offset_removed: Local,
    l_question4: Local,
    l_a: Local,
    offset: Local,
}

/// Supply of the bridge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Supply {
    /// U sin(2 pi f t): the sensor (question 8).
    Carrier,
    /// U from t = 0: a voltage step (question 5).
    Step,
}

/// Everything the equations give at one instant; derivatives and outputs both read it.
struct Operating {
    torque: f64,
    twist: f64,
    supply: f64,
    i_a: f64,
    i_b: f64,
    l_a: f64,
    l_b: f64,
    bridge: f64,
    product: f64,
}

impl TorqueSensor {
    fn sensor(&self, k: &Knowns) -> Sensor {
        let u = k[self.u_supply_amplitude];
        Sensor {
            torsion_bar: TorsionBar { stiffness_n_m_per_rad: k[self.k_torsion_bar], stop_angle_rad: k[self.twist_stop] },
            winding: Winding { turns: k[self.turns], resistance_ohm: k[self.r_winding] },
            ring_gap: Reluctance::radial_air_gap(k[self.r1], k[self.r2], k[self.b]),
            iron: Reluctance::uniform(
                k[self.iron_path_length],
                2.0 * std::f64::consts::PI * k[self.r1] * k[self.b],
                k[self.mu_r_iron],
            ),
            teeth: ToothedAirGap {
                teeth: k[self.teeth],
                radius_m: k[self.tooth_radius],
                axial_length_m: k[self.tooth_length],
                gap_length_m: k[self.tooth_gap],
                tooth_width_rad: k[self.tooth_width],
                rest_overlap_rad: k[self.rest_overlap],
            },
            differential: k[self.arrangement] == 2,
            bridge_resistance_ohm: k[self.r_bridge],
            supply: SineVoltage { amplitude_v: u, frequency_hz: k[self.f_supply] },
            multiplier: Multiplier { reference_amplitude: u },
            filter: SecondOrderFilter { natural_frequency_hz: k[self.f_filter], damping: k[self.filter_damping] },
        }
    }

    fn supply_mode(&self, k: &Knowns) -> Supply {
        if k[self.supply_mode] == 2 {
            Supply::Step
        } else {
            Supply::Carrier
        }
    }

    /// The built-in torque test signal, if any (0: none, 1: step, 2: ramp).
    fn profile(&self, k: &Knowns) -> Option<Ramp> {
        let duration = match k[self.torque_profile] {
            1 => 0.0,
            2 => k[self.profile_duration],
            _ => return None,
        };
        Some(Ramp { start_s: k[self.profile_start], duration_s: duration, height: k[self.profile_height] })
    }

    fn operating(&self, s: &Sensor, k: &Knowns) -> Operating {
        let t = k.time();
        let torque = k[self.torque_in] + self.profile(k).map_or(0.0, |p| p.value(t));
        let twist = s.torsion_bar.twist_rad(torque);
        let supply = match self.supply_mode(k) {
            Supply::Carrier => s.supply.voltage_v(t),
            Supply::Step => s.supply.amplitude_v,
        };
        let (circuit_a, circuit_b) = (s.circuit_a(twist), s.circuit_b(twist));
        let i_a = s.winding.current_a(k[self.flux_a], circuit_a);
        let i_b = s.winding.current_a(k[self.flux_b], circuit_b);
        let bridge = s.bridge_resistance_ohm * (i_b - i_a);
        Operating {
            torque,
            twist,
            supply,
            i_a,
            i_b,
            l_a: s.winding.inductance_h(circuit_a),
            l_b: s.winding.inductance_h(circuit_b),
            bridge,
            product: s.multiplier.product(bridge, supply),
        }
    }

    /// The filter's natural angular frequency: its second state is y' / wn (in V, like y).
    fn filter_wn(s: &Sensor) -> f64 {
        2.0 * std::f64::consts::PI * s.filter.natural_frequency_hz
    }
}

impl Model for TorqueSensor {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "TorqueSensor",
            description: "Magnetic torque sensor of an electric power steering: torsion bar, windings A and B on their rings, 5 kHz bridge, synchronous demodulation, low-pass filter and calibration (chapter 3, section 3.5.2, Figures 3.24-3.27)",
            // 10 us: 20 points per carrier period, so the bridge signals are seen; the torque
            // step at 10 ms has settled by 40 ms.
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 0.04, step_size: 1e-5 },
            solver: Solver::ExplicitRungeKutta,
            documentation: documentation::HTML,
        }
    }

    fn declare(d: &mut Declarations) -> Self {
        use std::f64::consts::PI;
        TorqueSensor {
            torque_full_scale: d.parameter("torque_full_scale", 8.0, "N.m").positive().describe("Measuring range +/- torque_full_scale (chosen: usual for EPS torque sensors)"),
            k_torsion_bar: d.parameter("K_torsion_bar", 360.0 / PI, "N.m/rad").positive().describe("Torsion bar stiffness, 2 N m/deg (chosen; question 6: the rotational stiffness of Figure 3.27)"),
            twist_stop: d.parameter("twist_stop", 5f64.to_radians(), "rad").positive().describe("Mechanical stops of the twist, +/- 5 deg (chosen: 1.25 x the full-scale twist)"),
            turns: d.parameter("N", 1000.0, "1").positive().describe("Turns of each winding (chapter, question 4)"),
            r_winding: d.parameter("R_winding", 30.0, "Ohm").min(0.0).describe("Resistance of each winding (chapter, question 5)"),
            r1: d.parameter("r1", 0.015, "m").positive().describe("Outer radius of a detection ring, inner radius of its air gaps (chapter, question 4)"),
            r2: d.parameter("r2", 0.0165, "m").positive().describe("Bore radius of the yoke, outer radius of the air gaps (chapter, question 4)"),
            b: d.parameter("b", 0.002, "m").positive().describe("Axial width of the air gaps (chapter, question 4)"),
            mu_r_iron: d.parameter("mu_r_iron", 2000.0, "1").positive().describe("Relative permeability of yokes and rings (chosen: ferrite; question 4 takes it infinite)"),
            iron_path_length: d.parameter("iron_path_length", 0.03, "m").min(0.0).describe("Length of the flux path in the iron of yoke and ring, section 2 pi r1 b (chosen)"),
            teeth: d.parameter("teeth", 8.0, "1").positive().describe("Number of tooth pairs of ring B's variable air gap (chosen; question 7)"),
            tooth_radius: d.parameter("tooth_radius", 0.012, "m").positive().describe("Radius of ring B's toothed air gap (chosen)"),
            tooth_length: d.parameter("tooth_length", 0.005, "m").positive().describe("Axial length of ring B's teeth (chosen)"),
            tooth_gap: d.parameter("tooth_gap", 3e-4, "m").positive().describe("Radial length of ring B's toothed air gap (chosen)"),
            tooth_width: d.parameter("tooth_width", PI / 8.0, "rad").positive().describe("Angular width of a tooth, half the 45 deg pitch (chosen)"),
            rest_overlap: d.parameter("rest_overlap", PI / 16.0, "rad").positive().describe("Angular overlap of a tooth pair at zero twist, half a tooth (chosen)"),
            arrangement: d.integer_parameter("arrangement", 1).range(1, 2).describe("1 = part A is Figure 3.26 as is, the bridge's reference arm (question 7: only B gets the toothed gap); 2 = differential: ring A's circuit crosses a toothed gap too, whose overlap shrinks as B's grows"),
            supply_mode: d.integer_parameter("supply_mode", 1).range(1, 2).describe("Bridge supply: 1 = U_supply sin(2 pi f_supply t) (question 8), 2 = a U_supply step at t = 0 (question 5)"),
            u_supply_amplitude: d.parameter("U_supply", 5.0, "V").positive().describe("Amplitude of the bridge supply (chosen: 5 V sensor electronics)"),
            f_supply: d.parameter("f_supply", 5000.0, "Hz").min(0.0).describe("Frequency of the bridge supply (chapter, question 8)"),
            r_bridge: d.parameter("R_bridge", 2200.0, "Ohm").min(0.0).describe("Bridge resistor above each winding (chosen: ~ w L_B(0) - R_winding, the most sensitive)"),
            f_filter: d.parameter("f_filter", 200.0, "Hz").positive().describe("Natural frequency of the second-order low-pass filter (chosen)"),
            filter_damping: d.parameter("filter_damping", 0.5f64.sqrt(), "1").positive().describe("Damping ratio of the low-pass filter (Butterworth)"),
            torque_profile: d.integer_parameter("torque_profile", 1).range(0, 2).describe("Built-in torque added to torque_in: 0 = none, 1 = step, 2 = ramp"),
            profile_height: d.parameter("torque_profile_height", 4.0, "N.m").describe("Height of the built-in torque step or ramp"),
            profile_start: d.parameter("torque_profile_start", 0.01, "s").min(0.0).describe("Instant of the built-in torque step, or start of the ramp"),
            profile_duration: d.parameter("torque_profile_duration", 0.02, "s").min(0.0).describe("Duration of the built-in torque ramp"),
            torque_in: d.input("torque_in", 0.0, "N.m").describe("Steering torque applied by the driver (from a master), added to the built-in profile"),
            flux_a: d.state("flux_A", 0.0, "Wb").nominal(1e-7).describe("Flux through winding A (Lenz: N dflux/dt = u - R i)"),
            flux_b: d.state("flux_B", 0.0, "Wb").nominal(1e-7).describe("Flux through winding B"),
            i_rl: d.state("i_rl", 0.0, "A").nominal(1e-3).describe("Current of the R-L model of winding A (question 5)"),
            filter_y: d.state("filter_y", 0.0, "V").nominal(0.1).describe("Low-pass filter output"),
            filter_z: d.state("filter_z", 0.0, "V").nominal(0.1).describe("Low-pass filter rate divided by its natural angular frequency"),
            y_torque: d.output("torque_applied", "N.m").describe("Torque on the torsion bar: torque_in plus the built-in profile"),
            y_twist: d.output("twist_angle", "rad").describe("Twist of the input shaft against the output shaft (torque / K_torsion_bar, within the stops)"),
            y_supply: d.output("u_supply", "V").describe("Bridge supply voltage"),
            y_i_a: d.output("i_winding_A", "A").describe("Current of winding A (winding model, Figure 3.26)"),
            y_i_b: d.output("i_winding_B", "A").describe("Current of winding B"),
            y_i_rl: d.output("i_rl_A", "A").describe("Current of the R-L model of winding A with the inductance of question 4 (question 5)"),
            y_flux_a: d.output("flux_winding_A", "Wb").describe("Flux through winding A"),
            y_flux_b: d.output("flux_winding_B", "Wb").describe("Flux through winding B"),
            y_l_a: d.output("inductance_A", "H").describe("Inductance of winding A at the present twist (constant unless arrangement = 2)"),
            y_l_b: d.output("inductance_B", "H").describe("Inductance of winding B at the present twist, N^2 / reluctance"),
            y_bridge: d.output("u_bridge", "V").describe("Bridge voltage R_bridge (i_B - i_A)"),
            y_product: d.output("u_product", "V").describe("Multiplier output u_bridge u_supply / U_supply (question 8)"),
            y_demodulated: d.output("u_demodulated", "V").describe("Raw demodulated voltage: the low-pass filter's output"),
            y_measured: d.output("torque_measured", "N.m").describe("Conditioned torque measurement (question 9): offset removed, the model's characteristic inverted"),
            offset_removed: d.local("u_offset_removed", "V").describe("u_demodulated minus the zero-torque offset"),
            l_question4: d.calculated_parameter("L_question4", "H").describe("Inductance of question 4: pi mu0 b N^2 / ln(r2/r1) (infinitely permeable iron)"),
            l_a: d.calculated_parameter("L_A", "H").describe("Inductance of winding A at zero twist with the iron's reluctance, N^2 / reluctance"),
            offset: d.calculated_parameter("u_demodulated_zero_torque", "V").describe("Steady demodulated voltage at zero torque (phasors): the offset removed by the conditioning"),
        }
    }

    fn check(&self, k: &Knowns) -> Result<(), String> {
        if k[self.r2] <= k[self.r1] {
            return Err("r2 must exceed r1 (the air gap runs from the ring at r1 to the yoke at r2)".into());
        }
        if k[self.teeth] * k[self.tooth_width] > 2.0 * std::f64::consts::PI {
            return Err("teeth x tooth_width exceeds a full turn".into());
        }
        let (stop, overlap) = (k[self.twist_stop], k[self.rest_overlap]);
        if overlap <= stop || overlap + stop >= k[self.tooth_width] {
            return Err("the tooth overlap must stay strictly between 0 and tooth_width over the twists between the \
                        stops: rest_overlap > twist_stop and rest_overlap + twist_stop < tooth_width"
                .into());
        }
        if k[self.k_torsion_bar] * stop < k[self.torque_full_scale] {
            return Err("the stops (K_torsion_bar x twist_stop) must not be reached below torque_full_scale".into());
        }
        Ok(())
    }

    /// Measured (tests/python/accuracy_table.py, against rtol 1e-12): the bridge output
    /// R (i_B - i_A) is a small difference of two large winding currents, so it carries the
    /// flux states' relative error amplified: after the torque step at 10 ms, u_bridge is
    /// 2.8e-7 of its range off at rtol 1e-8 (28 x the tolerance) and 1.1e-3 at 1e-4, while the
    /// fluxes are within 4e-9. At 1e-9 it is within 3.5e-9 (1.2e-9 at 1e-10).
    fn tolerance_floor() -> Option<f64> {
        Some(1e-9)
    }

    fn next_time_event(&self, k: &Knowns, after: f64) -> Option<f64> {
        self.profile(k)?.next_kink(after)
    }

    fn derivatives(&self, k: &Knowns, der: &mut Derivatives) {
        let s = self.sensor(k);
        let op = self.operating(&s, k);
        let r_b = s.bridge_resistance_ohm;
        der[self.flux_a] = s.winding.flux_rate_wb_per_s(op.supply - r_b * op.i_a, op.i_a);
        der[self.flux_b] = s.winding.flux_rate_wb_per_s(op.supply - r_b * op.i_b, op.i_b);
        let i_rl = k[self.i_rl];
        der[self.i_rl] = s.rl_winding().current_rate_a_per_s(op.supply - r_b * i_rl, i_rl);
        let wn = Self::filter_wn(&s);
        let (y, z) = (k[self.filter_y], k[self.filter_z]);
        der[self.filter_y] = wn * z;
        der[self.filter_z] = s.filter.acceleration(op.product, y, wn * z) / wn;
    }

    fn outputs(&self, k: &Knowns, out: &mut Outputs) {
        let s = self.sensor(k);
        let op = self.operating(&s, k);
        let offset = s.zero_torque_demodulated_v();
        let demodulated = k[self.filter_y];
        out[self.y_torque] = op.torque;
        out[self.y_twist] = op.twist;
        out[self.y_supply] = op.supply;
        out[self.y_i_a] = op.i_a;
        out[self.y_i_b] = op.i_b;
        out[self.y_i_rl] = k[self.i_rl];
        out[self.y_flux_a] = k[self.flux_a];
        out[self.y_flux_b] = k[self.flux_b];
        out[self.y_l_a] = op.l_a;
        out[self.y_l_b] = op.l_b;
        out[self.y_bridge] = op.bridge;
        out[self.y_product] = op.product;
        out[self.y_demodulated] = demodulated;
        out[self.offset_removed] = demodulated - offset;
        out[self.y_measured] = s.measured_torque_n_m(demodulated - offset);
        out[self.l_question4] = s.question4_inductance_h();
        out[self.l_a] = s.winding.inductance_h(s.circuit_a(0.0));
        out[self.offset] = offset;
    }
}

fmu_runtime::export_fmu!(TorqueSensor);
