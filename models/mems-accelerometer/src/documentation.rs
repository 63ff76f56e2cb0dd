//! The model's page in documentation/index.html (the runtime adds the variable tables, Table 3.1
//! of the declared elements and the activities of the default experiment).

pub const HTML: &str = r#"
<p>Chapter 3, section 3.4.1.1, Figure 3.14: a MEMS (micro-electro-mechanical system) accelerometer, "made from silicon
by etching a superficial layer through a chemical process to obtain a moving part". Question 2 asks for the dominant
effect of each part. The FMU models an ADXL-class surface-micromachined sensor: a polysilicon proof mass hangs on folded
beams 1.6 um above the substrate; 42 fingers on its sides sit between fixed fingers, 1 um from each neighbour, forming a
differential pair of parallel-plate capacitors; the air in those gaps is squeezed as the mass moves and the air under it is
sheared; overtravel stops limit its travel; a charge amplifier reads the capacitance difference on a square-wave carrier,
a synchronous demodulator and a two-pole low-pass filter make the output voltage. Input: the frame's acceleration
(<code>a_frame</code>, plus a built-in step or sine). Outputs: the proof mass's displacement, the sensed capacitance change,
the output voltage, the electrostatic force.</p>

<h3>Question 2: the dominant effect of each part</h3>
<p>The figure's part letters are not in the chapter's text, so the parts are named. The shares are the FMU's activities
(eq. 3.3) over the default 3 ms, for a 1 kHz, 10 g sine (in the measurement band) and for the default 10 g step (whose
ringing excites the resonance).</p>
<table>
<tr><th>part</th><th>dominant effect</th><th>domain</th><th>what the FMU shows</th></tr>
<tr><td>proof mass (the etched moving plate)</td><td>I: inertia, the mass m whose d'Alembert force m a is what is measured</td><td>mechanical (translation)</td>
<td>0.74 % of the storage activity in band ((f / f0)<sup>2</sup> of the spring's energy), 19.3 % in the step's ringing at 24 kHz</td></tr>
<tr><td>folded beams (suspension, anchored to the substrate)</td><td>C: bending stiffness k = 2 E t w<sup>3</sup> / L<sup>3</sup></td><td>mechanical (translation)</td>
<td>97.0 % of the storage activity in band, 78.9 % in the step: the deflection x = m a / k is the measurement</td></tr>
<tr><td>sense fingers (fixed and moving electrodes)</td><td>C: electrostatic storage coupling the electrical and the mechanical domains (a capacitive transducer)</td><td>electrical and mechanical</td>
<td>2.3 % in band: exactly the carrier's softening k_e / k = 2.35 %; it carries the signal (C_2 - C_1) and, with a bias, the pull-in</td></tr>
<tr><td>air gaps between the fingers</td><td>R: squeeze-film damping</td><td>mechanical (translation), fluid</td>
<td>58 % of the dissipation (b_squeeze / (b_squeeze + b_slide)); Q = 27.4 with the slide film</td></tr>
<tr><td>air gap under the proof mass</td><td>R: slide-film (Couette) damping</td><td>mechanical (translation), fluid</td><td>42 % of the dissipation</td></tr>
<tr><td>substrate, frame, anchors</td><td>the input: a source (the acceleration), rigid</td><td>mechanical (translation)</td><td>the frame's acceleration is the inertial force's source</td></tr>
<tr><td>read-out electronics</td><td>signal processing (no power: a charge amplifier at virtual ground, demodulator, filter)</td><td>electrical, signal</td><td>sets the bandwidth (1 kHz) and the sensitivity (19 mV/g)</td></tr>
</table>
<p>In the band the sensor is a spring balance: the mass makes the force, the beams turn it into a displacement, the
capacitors into a charge; the air and the mass's own kinetic energy matter only near the 24 kHz resonance, which the
read-out filter keeps out of the output (a 10 g step rings the mass at 23.8 kHz with Q = 27, and V_out overshoots only by
the Butterworth filter's 4.3 %).</p>

<h3>Equations</h3>
<ul>
<li>Frame coordinates, x the proof mass's displacement towards electrode 1: m dv/dt = -m a - k x - (b_squeeze(x) + b_slide) v + F_e,
dx/dt = v. The frame's acceleration acts as the inertial force -m a (a source, power -m a v); a static acceleration gives
x = -m a / k_eff.</li>
<li>Folded flexure (Tang, Nguyen and Howe 1989): four folds of two fixed-guided beams (12 E I / L<sup>3</sup> each, I = t w<sup>3</sup>/12)
in series, in parallel: k = 2 E t w<sup>3</sup> / L<sup>3</sup> = 6.575 N/m.</li>
<li>Air (kinetic theory): mean free path lambda = (mu / p) sqrt(pi R T / (2 M)) = 66.9 nm at 1 atm and 25 degrees C. Squeeze film in
the finger gaps: the Reynolds equation across a strip of width t (the fingers' thickness) and length N l (fingers times overlap),
incompressible (squeeze number 12 mu_eff omega t<sup>2</sup> / (p g<sup>2</sup>) = 9.2e-4 at 24 kHz): b = mu_eff N l t<sup>3</sup> / h<sup>3</sup> per side,
with the gap h = g -+ x each side takes, b_squeeze(x) = mu_eff A t<sup>2</sup> (1/(g-x)<sup>3</sup> + 1/(g+x)<sup>3</sup>), 9.107e-7 N s/m at rest;
mu_eff = mu / (1 + 9.638 Kn<sup>1.159</sup>) (Veijola et al. 1995, Kn = lambda / g = 0.067: 70 % of mu). Slide film under the mass:
b_slide = mu_eff' A_plate / d with mu_eff' = mu / (1 + 2 lambda / d) (first-order slip), 6.587e-7 N s/m. Q = sqrt(m k_eff) / b = 27.4.</li>
<li>Capacitors: C_1 = eps0 A / (g - x), C_2 = eps0 A / (g + x), 77.35 fF each at rest. Electrode 1 carries the carrier and the
bias, electrode 2 the carrier; the carrier (a square wave far above the mechanics) acts through its mean square, so the mean
squares are W_1 = V_carrier<sup>2</sup> + V_bias(t)<sup>2</sup>, W_2 = V_carrier<sup>2</sup>. Force F_e = (W_1/2) dC_1/dx + (W_2/2) dC_2/dx =
eps0 A (W_1 / (2 (g-x)<sup>2</sup>) - W_2 / (2 (g+x)<sup>2</sup>)). At rest the carrier's two pulls cancel and leave a negative stiffness
k_e = 2 eps0 A V_carrier<sup>2</sup> / g<sup>3</sup> = 0.155 N/m: k_eff = k - k_e, f = 23.78 kHz instead of 24.06 kHz.</li>
<li>Energy of the C element with two ports: E = (C_1 W_1 + C_2 W_2) / 2, dE/dt = sum (W_i/2) dC_i/dt + (C_i/2) dW_i/dt; the voltage
sources deliver sum W_i dC_i/dt + (C_i/2) dW_i/dt (mean square of V i, i = d(C V)/dt); the difference, sum (W_i/2) dC_i/dt = F_e v, goes
to the mass. <code>power_balance_relative</code> stays at rounding (2e-16 in the default run, 4e-16 through stop contacts).</li>
<li>Read-out: a charge amplifier holds the proof mass at virtual ground; demodulated, its output is V_demodulated = V_carrier (C_2 - C_1) /
C_feedback (positive for a positive acceleration); then u'' = wn<sup>2</sup> (V_demodulated - u) - sqrt(2) wn u' (two-pole Butterworth,
wn = 2 pi f_filter; state <code>w_filter</code> = u' / wn), V_out = G_out u. Static sensitivity G_out V_carrier (2 C_0 / g) (m / k_eff) / C_feedback
= 19.035 mV/g.</li>
<li>Stops at x = +-x_stop: state events (indicator (x_stop<sup>2</sup> - x<sup>2</sup>) / (2 x_stop) while free). The impact is inelastic
(v set to 0: the kinetic energy is lost at the event, not a power); on the stop the mass stands still while the forces press it on
(indicator: that force, -m a - k x + F_e towards the stop), and leaves from rest when they stop doing so. <code>at_stop</code> says
where it is, <code>F_stop</code> what the stop holds.</li>
</ul>

<h3>Acceptance figures (tests/python/test_mems_accelerometer.py)</h3>
<ul>
<li><b>Static sensitivity</b> (1 g step, settled): carrier off, x / a = -4.37566e-11 s<sup>2</sup> against -m / k (1e-7 relative); carrier on,
against -m / (k - k_e) (within 1e-7): the carrier's softening raises the sensitivity by 2.4 %. delta_C = -67.98 aF per g, V_out = 19.035 mV per g.</li>
<li><b>Resonance</b>: the FMU's linearisation gives |lambda| = sqrt(k / m) = 24 060.15 Hz to 1e-10 (carrier off) and sqrt((k - k_e) / m) =
23 775.42 Hz (carrier on), damping ratio 1/(2Q) = 0.0180; a free oscillation from 10 nm rings at 24 056.23 Hz, the damped
sqrt(k/m) sqrt(1 - 1/(4 Q<sup>2</sup>)) to 1e-6 (-0.016 % from sqrt(k / m)).</li>
<li><b>Pull-in</b> (carrier off, bias on electrode 1 alone, ramped over 3 ms and held): bisection finds the snap at 5.0124 V against
sqrt(8 k g<sup>3</sup> / (27 eps0 A)) = 5.0186 V (-0.12 %; the ramp's finite speed lets the mass overshoot its equilibrium: -0.31 % with 1 ms,
-0.07 % with 6 ms). Below it the mass rests on the stable root of k x = eps0 A V<sup>2</sup> / (2 (g - x)<sup>2</sup>) (to 1e-6 at 0.5, 0.9, 0.98 V_pi;
x = 0.259 g at 0.98 V_pi); beyond it, on the stop. A 5 V self-test on the sense electrodes would snap it: real devices have self-test fingers with
wider gaps. With the default 1 V carrier the rest position would lose its stiffness at 6.52 V on both electrodes (<code>V_pull_in_symmetric</code>).</li>
<li><b>Bandwidth</b>, defined as the lowest frequency at which the output per unit acceleration leaves +-3 dB of its static value (a roll-off or a
resonance peak, whichever comes first; linearised at rest, bias off): 1001.77 Hz, the filter's corner with the mechanics adding 0.18 %. A 1 g sine
there gives an amplitude ratio of 0.70711. The mechanics alone would leave the band at 12.9 kHz, by their +3 dB rise towards the resonance.</li>
<li>Transients against scipy (DOP853, rtol 1e-12, the same equations written out in the test): the default step, a 1 kHz sine and a 2.5 V self-test
agree to 3.6e-10 of each output's range.</li>
<li>Shocks: a 2000 g, 200 Hz sine lands the mass on each stop (it engages at 1116 g), it rests there and leaves; outputs finite, balance at 4e-16.</li>
</ul>

<h3>Every value and its source</h3>
<p>The chapter gives none; <code>docs/mems-accelerometer-spec.md</code> has the same table.</p>
<table>
<tr><th>parameter</th><th>default</th><th>argument</th></tr>
<tr><td>t_structure</td><td>2 um</td><td>the ADXL50's sensor: "plates etched from a single 2 um piece of silicon" (polysilicon, Analog Devices' iMEMS process)</td></tr>
<tr><td>m_proof</td><td>2.877e-10 kg</td><td>the layout of COMSOL's public "surface micromachined accelerometer" model (an ADXL-type design): a 448 x 100 um plate with
4 um release holes on an 18 um pitch (4.9 % open) and 42 fingers of 114 x 4 um, 1.235e-13 m<sup>3</sup> of polysilicon at 2330 kg/m<sup>3</sup> (silicon's
density)</td></tr>
<tr><td>E_beam</td><td>160 GPa</td><td>polysilicon's Young's modulus as MEMS design texts take it; tensile tests of MUMPs polysilicon give 158-169 GPa</td></tr>
<tr><td>w_beam, L_beam</td><td>2 um, 92 um</td><td>the layout's 2 um spring width; the length chosen to put the resonance at the ADXL50's 24 kHz (Analog Devices
application note AN-377: "the ADXL50's sensor beam has a resonance at approximately 24 kHz"): 24.06 kHz</td></tr>
<tr><td>gap, A_electrode</td><td>1 um, 8.736e-9 m<sup>2</sup></td><td>the layout's 1 um finger gap; each moving finger faces one fixed finger of each set over 104 um of its 2 um
thickness: 42 x 104 um x 2 um per capacitor, C_0 = 77 fF (the ADXL50's sense capacitance is quoted around 0.1 pF)</td></tr>
<tr><td>A_plate, d_substrate</td><td>6.18e-8 m<sup>2</sup>, 1.6 um</td><td>the proof mass's footprint (plate less holes, plus fingers); the sacrificial oxide's 1.6 um under it</td></tr>
<tr><td>p_gas, T_gas</td><td>101 325 Pa, 298.15 K</td><td>a package sealed with air at atmospheric pressure, at 25 degrees C; air's viscosity 1.85e-5 Pa s (tables; Sutherland's law
gives 1.84e-5), molar mass 28.96 g/mol</td></tr>
<tr><td>x_stop</td><td>0.5 um</td><td>half the gap: beyond the pull-in point g/3 (a bias below V_pi never touches it), short of the fingers' contact; it engages at 1116 g,
below the ADXL50's 2000 g unpowered shock survival</td></tr>
<tr><td>V_carrier</td><td>1 V</td><td>chosen: ADXL-class read-outs excite the sense capacitors with square waves of a few volts from a 3-5 V supply; at 1 V the
electrostatic spring takes 2.35 % of the beams' stiffness (the signal grows as V, the softening as V<sup>2</sup>)</td></tr>
<tr><td>C_feedback</td><td>100 fF</td><td>chosen: of the order of the sense capacitance, the charge amplifier's gain V_carrier / C_feedback = 1e13 V/F</td></tr>
<tr><td>f_filter</td><td>1 kHz</td><td>AN-377: the ADXL series is "specified and tested for operation over the range from dc to 1 kHz typically"; the ADXL50 data sheet
allows one or two poles of filtering: two (Butterworth)</td></tr>
<tr><td>G_out</td><td>28</td><td>trimmed to the ADXL50's factory-trimmed 19 mV/g: 19.035 mV/g</td></tr>
<tr><td>a_step, a_sine, f_sine, t_start</td><td>10 g, 10 g, 1 kHz, 0.1 ms</td><td>the built-in profiles (the ADXL50's range is +-50 g)</td></tr>
<tr><td>V_bias, t_bias_ramp</td><td>0 V, 0 s</td><td>off by default: for self-test and pull-in studies</td></tr>
</table>

<h3>Structural parameter, modes, solver</h3>
<ul>
<li><code>profile</code> = 1: a step of a_step at t_start (default); 2: a sine of a_sine at f_sine from t_start. Set the amplitude to 0 to drive the
FMU by <code>a_frame</code> alone.</li>
<li>Integer locals: <code>stop_contact</code> (0 free, +-1 on a stop) and <code>state_events</code>.</li>
<li>Solver: explicit Runge-Kutta (the fastest mode, the proof mass at 24 kHz with damping ratio 0.018, is not stiff). Tolerance floor 1e-4: at 1e-3
the activities, which rectify the 24 kHz ringing, were 10.5 x rtol of their range off; at 1e-4 8.3e-4. The default experiment (3 ms) takes
about 0.05 s in fmpy Co-Simulation.</li>
<li>Left out (Table 3.1 lists each with its reason): the beams' own mass (2.4 % of m), their material damping, the squeezed air's compressibility,
the fringing fields (parallel plates only, as the pull-in formula takes them: the fringes would add tens of % to C and F and lower V_pull_in), the
electrodes' resistance, the read-out's parasitic capacitances, the open air above the mass, the substrate's compliance. Thermal-mechanical
noise (sqrt(4 k_B T b) / m = 57 ug/sqrt(Hz)) is a fluctuation, not in a deterministic model. The ADXL50 itself closes a force-balance loop
around its sensor; this FMU is the open-loop sensor of the later ADXL parts. The output stage is linear: V_out is not
clipped at a supply rail (a 2000 g shock swings it by tens of volts).</li>
</ul>
"#;
