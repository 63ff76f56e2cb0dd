//! RlcCircuit: the small electric circuit of chapter 3, Figure 3.3, as an FMU.
//!
//! "The objective is to simulate the current absorbed by the load depending on the applied
//! voltage. For low- or high-frequency voltages, the diagram can be simplified while the absorbed
//! current is accurately represented" (section 3.1.3). The chapter does not print the circuit's
//! values, so we choose one whose behaviour shows exactly that and whose response has a closed
//! form:
//!
//! ```text
//!   u(t) --R_series--L_series--+-- i_L
//!                              |
//!                         C_load || R_load      (load: capacitor in parallel with a resistor)
//!                              |
//!   ---------------------------+
//! ```
//!
//! * full model:  L di_L/dt = u - R_series i_L - u_C,   C du_C/dt = i_L - u_C / R_load
//! * low frequency (L a short, C open, quasi-static): i = u / (R_series + R_load)
//! * high frequency (C a short): the R-L circuit  L di_rl/dt = u - R_series i_rl
//!
//! Default values: R_series = 1 Ohm, L_series = 10 mH, C_load = 100 uF, R_load = 10 Ohm, so the
//! LC resonance is at 1/(2 pi sqrt(L C)) = 159 Hz and the eigenvalues of the full model are
//! -550 +/- 893j 1/s: at 5 Hz the quasi-static model holds, at 5 kHz the R-L one does, and at
//! the default 50 Hz neither is exact — the chapter's point. The source is
//! u = U_amplitude sin(2 pi frequency t) + u_in, where the input u_in (0 V unless a master drives
//! it) lets another FMU impose any voltage (set U_amplitude = 0 to use the input alone).
//!
//! The closed form the tests check against: with x = (i_L, u_C), x' = A x + b u, the response
//! to U sin(w t) from x0 is Im(X e^{jwt}) + e^{At}(x0 - Im X) with X = (jwI - A)^{-1} b U.

use components::{Capacitor, Inductor, Resistor, SineVoltage};
use fmu_runtime::prelude::*;

pub struct RlcCircuit {
    amplitude: Parameter,
    frequency: Parameter,
    r_series: Parameter,
    l_series: Parameter,
    c_load: Parameter,
    r_load: Parameter,
    u_in: Input,
    i_l: State,
    u_c: State,
    i_rl: State,
    u_source: Output,
    i_absorbed: Output,
    u_capacitor: Output,
    i_low_frequency: Output,
    i_high_frequency: Output,
    powers: Powers,
}

/// The full circuit's elements (Figure 3.3), whose powers the runtime integrates and balances
/// (the two simplified circuits beside it are not part of the balance).
struct Powers {
    source: Element,
    line_resistance: Element,
    line_inductance: Element,
    load_capacitance: Element,
    load_resistance: Element,
}

/// The circuit's elements at the current parameter values.
struct Elements<R = f64> {
    source: SineVoltage<R>,
    line_resistance: Resistor<R>,
    line_inductance: Inductor<R>,
    load_capacitance: Capacitor<R>,
    load_resistance: Resistor<R>,
}

impl RlcCircuit {
    fn elements<R: Real>(&self, k: &Knowns<R>) -> Elements<R> {
        Elements {
            source: SineVoltage { amplitude_v: k[self.amplitude], frequency_hz: k[self.frequency] },
            line_resistance: Resistor { resistance_ohm: k[self.r_series] },
            line_inductance: Inductor { inductance_h: k[self.l_series] },
            load_capacitance: Capacitor { capacitance_f: k[self.c_load] },
            load_resistance: Resistor { resistance_ohm: k[self.r_load] },
        }
    }

    /// Source voltage: the sine plus the input, V.
    fn voltage<R: Real>(&self, e: &Elements<R>, k: &Knowns<R>) -> R {
        e.source.voltage_v(R::from(k.time())) + k[self.u_in]
    }
}

const DOCUMENTATION: &str = r#"
<p>The circuit of chapter 3, Figure 3.3: a voltage source feeds a line (resistance R_series, inductance
L_series) and a load made of a capacitor C_load in parallel with a resistor R_load. The FMU integrates the
full circuit and, beside it, the two simplifications the chapter compares it with.</p>
<ul>
<li>Source: u(t) = U_amplitude sin(2&pi; frequency t) + u_in.</li>
<li>Full circuit: L di_L/dt = u - R_series i_L - u_C; C du_C/dt = i_L - u_C/R_load. Output i_absorbed = i_L.</li>
<li>Low-frequency model (L short, C open): i_low_frequency = u/(R_series + R_load).</li>
<li>High-frequency model (C short): L di_rl/dt = u - R_series i_rl. Output i_high_frequency = i_rl.</li>
</ul>
<p>Default values (chosen: the chapter prints none): R_series = 1 &Omega;, L_series = 10 mH, C_load = 100 &mu;F,
R_load = 10 &Omega;; LC resonance 159 Hz; eigenvalues -550 &plusmn; 893j s<sup>-1</sup>. Try frequency = 5 Hz
(the quasi-static model matches), 5000 Hz (the R-L model matches) and 50 Hz (neither does).</p>
<p>Closed form: with x = (i_L, u_C), x' = A x + b u, A = [[-R_series/L, -1/L], [1/C, -1/(R_load C)]], b = (1/L, 0);
for u = U sin(&omega;t), x(t) = Im(X e<sup>j&omega;t</sup>) + e<sup>At</sup>(x(0) - Im X), X = (j&omega;I - A)<sup>-1</sup> b U.</p>
"#;

impl Model for RlcCircuit {
    fn info() -> ModelInfo {
        ModelInfo {
            name: "RlcCircuit",
            description: "Current absorbed by an R-L line feeding an R||C load under a sinusoidal voltage, with its low- and high-frequency simplifications (chapter 3, Figure 3.3)",
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 0.1, step_size: 1e-4 },
            solver: Solver::ExplicitRungeKutta,
            documentation: DOCUMENTATION,
        }
    }

    fn declare(d: &mut Declarations) -> Self {
        RlcCircuit {
            amplitude: d.parameter("U_amplitude", 10.0, "V").min(0.0).describe("Amplitude of the sinusoidal source voltage (Figure 3.3)"),
            frequency: d.parameter("frequency", 50.0, "Hz").min(0.0).describe("Frequency of the source voltage (Figure 3.3 compares several)"),
            r_series: d.parameter("R_series", 1.0, "Ohm").min(0.0).describe("Line resistance (chosen value)"),
            l_series: d.parameter("L_series", 0.01, "H").positive().describe("Line inductance (chosen value)"),
            c_load: d.parameter("C_load", 1e-4, "F").positive().describe("Load capacitance (chosen value)"),
            r_load: d.parameter("R_load", 10.0, "Ohm").positive().describe("Load resistance in parallel with C_load (chosen value)"),
            u_in: d.input("u_in", 0.0, "V").describe("Voltage added to the sine: lets a master impose any source voltage"),
            i_l: d.state("i_L", 0.0, "A").nominal(1.0).describe("Line current of the full circuit (inductor current)"),
            u_c: d.state("u_C", 0.0, "V").nominal(10.0).describe("Load capacitor voltage of the full circuit"),
            i_rl: d.state("i_rl", 0.0, "A").nominal(1.0).describe("Current of the high-frequency model (R-L circuit, C short)"),
            u_source: d.output("u_source", "V").describe("Source voltage u(t)"),
            i_absorbed: d.output("i_absorbed", "A").describe("Current absorbed by the full circuit"),
            u_capacitor: d.output("u_capacitor", "V").describe("Load voltage of the full circuit"),
            i_low_frequency: d.output("i_low_frequency", "A").describe("Current of the quasi-static model u/(R_series + R_load)"),
            i_high_frequency: d.output("i_high_frequency", "A").describe("Current of the high-frequency model (R-L circuit)"),
            powers: Powers {
                source: d.element("voltage_source", "Source", SineVoltage::SOURCE).describe("the voltage source, power u i_L"),
                line_resistance: d.element("line_resistance", "Line", Resistor::RESISTANCE).describe("the line resistance, power R_series i_L^2"),
                line_inductance: d.element("line_inductance", "Line", Inductor::INDUCTANCE).describe("the line inductance, power L_series i_L di_L/dt"),
                load_capacitance: d.element("load_capacitance", "Load", Capacitor::CAPACITANCE).describe("the load capacitor, power C_load u_C du_C/dt"),
                load_resistance: d.element("load_resistance", "Load", Resistor::RESISTANCE).describe("the load resistance, power u_C^2 / R_load"),
            },
        }
    }

    fn derivatives<R: Real>(&self, k: &Knowns<R>, der: &mut Derivatives<R>) {
        let e = self.elements(k);
        let u = self.voltage(&e, k);
        let (i_l, u_c, i_rl) = (k[self.i_l], k[self.u_c], k[self.i_rl]);
        let di_l = e.line_inductance.current_rate_a_per_s(u - e.line_resistance.voltage_v(i_l) - u_c);
        let du_c = e.load_capacitance.voltage_rate_v_per_s(i_l - e.load_resistance.current_a(u_c));
        der[self.i_l] = di_l;
        der[self.u_c] = du_c;
        let p = &self.powers;
        der.power(p.source, u * i_l);
        der.power(p.line_resistance, e.line_resistance.power_w(i_l));
        der.power(p.line_inductance, e.line_inductance.power_w(i_l, di_l));
        der.power(p.load_capacitance, e.load_capacitance.power_w(u_c, du_c));
        der.power(p.load_resistance, u_c * e.load_resistance.current_a(u_c));
        der[self.i_rl] = e.line_inductance.current_rate_a_per_s(u - e.line_resistance.voltage_v(i_rl));
    }

    fn outputs<R: Real>(&self, k: &Knowns<R>, out: &mut Outputs<R>) {
        let e = self.elements(k);
        let u = self.voltage(&e, k);
        out[self.u_source] = u;
        out[self.i_absorbed] = k[self.i_l];
        out[self.u_capacitor] = k[self.u_c];
        out[self.i_low_frequency] = u / (e.line_resistance.resistance_ohm + e.load_resistance.resistance_ohm);
        out[self.i_high_frequency] = k[self.i_rl];
    }
}

fmu_runtime::export_fmu!(RlcCircuit);
