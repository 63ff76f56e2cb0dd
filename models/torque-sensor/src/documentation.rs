//! The model's page in documentation/index.html (the runtime adds the variable tables).

pub const HTML: &str = r#"
<p>The magnetic torque sensor of an electric power steering (chapter 3, section 3.5.2, Figures 3.24-3.27):
the driver's torque twists a torsion bar between the input (steering wheel) and output shafts; detection
rings A and B sit on the two ends of the bar, so their relative angle is the twist; two windings and a
5 kHz bridge turn the twist into a voltage, and a conditioning stage (question 9) turns the voltage into
torque. The contract: <code>docs/torque-sensor-spec.md</code> in the source repository.</p>

<h3>Equations</h3>
<ul>
<li>Torque: T = torque_in + the built-in profile (torque_profile: 0 none, 1 a step of torque_profile_height at
torque_profile_start, 2 a ramp to it over torque_profile_duration).</li>
<li>Torsion bar (question 6): twist = T / K_torsion_bar, limited to &plusmn;twist_stop by the mechanical stops.</li>
<li>Magnetic analogy (questions 1-2): mmf (A) is the effort, flux (Wb) the flow; flux conservation plays
Kirchhoff's current law, Amp&egrave;re's law (sum of mmfs = N i) his voltage law; reluctance = length / (&mu;<sub>0</sub>
&mu;<sub>r</sub> section). &mu;<sub>0</sub> = 4&pi;&middot;10<sup>-7</sup> H/m, the chapter's value.</li>
<li>Part A (Figure 3.26, question 3): the winding (T, N turns, R_winding) in a yoke whose two poles face ring A
across two radial air gaps (a and c) from r1 to r2 over the width b, each of reluctance
R_gap = ln(r2/r1) / (2&pi; &mu;<sub>0</sub> b), in series with the iron of yoke and ring (b and d):
R_iron = iron_path_length / (&mu;<sub>0</sub> mu_r_iron 2&pi; r1 b). R_A = 2 R_gap + R_iron.</li>
<li>Question 4 (iron infinitely permeable): L = N<sup>2</sup> / (2 R_gap) = &pi; &mu;<sub>0</sub> b N<sup>2</sup> / ln(r2/r1)
= 82.84 mH (calculated parameter <code>L_question4</code>); with the iron, <code>L_A</code> = 82.41 mH (0.52 % less).</li>
<li>Part B (question 7): part A's circuit plus a new component, the toothed air gap between the teeth of ring B
and those of ring A. Each of the <code>teeth</code> tooth pairs overlaps by rest_overlap + twist, so the gap's
section is teeth (rest_overlap + twist) tooth_radius tooth_length and its reluctance
R_teeth = tooth_gap / (&mu;<sub>0</sub> section): R_B(twist) = R_A + R_teeth(twist). Fringing is neglected.</li>
<li><code>arrangement</code> = 2 (differential): part A's circuit crosses the same toothed gap at the opposite twist,
R_A(twist) = 2 R_gap + R_iron + R_teeth(-twist), so L_A(T) = L_B(-T): balanced at zero torque, output odd in the torque.
The default, 1, follows question 7 (only part B gets a new component).</li>
<li>Windings (Amp&egrave;re and Lenz): N i = R_X &phi;<sub>X</sub>, N d&phi;<sub>X</sub>/dt = u<sub>X</sub> - R_winding i.
The flux is the state, so ring B's time-varying reluctance is exact (the motional voltage included).</li>
<li>Question 5: beside winding A, an R-L impedance with L_question4 and R_winding, driven like it:
L di_rl/dt = u<sub>A</sub> - R_winding i_rl (output <code>i_rl_A</code>).</li>
<li>Bridge (question 8): a resistor R_bridge above each winding, both arms across the supply
u_s = U_supply sin(2&pi; f_supply t) (supply_mode 1; supply_mode 2: u_s = U_supply from t = 0, the voltage
step of question 5); u<sub>X</sub> = u_s - R_bridge i<sub>X</sub>; u_bridge = u<sub>A</sub> - u<sub>B</sub> = R_bridge (i_B - i_A).</li>
<li>Multiplier: u_product = u_bridge u_s / U_supply. For u_bridge = |B| sin(&omega;t + &beta;) it is
(|B|/2)(cos &beta; - cos(2&omega;t + &beta;)): the mean is the bridge voltage's in-phase part.</li>
<li>Low-pass: second order, y'' = &omega;<sub>n</sub><sup>2</sup> (u_product - y) - 2 &zeta; &omega;<sub>n</sub> y',
&omega;<sub>n</sub> = 2&pi; f_filter; <code>u_demodulated</code> = y (the raw output).</li>
<li>Steady state (phasors): I<sub>X</sub> = U / (R_bridge + R_winding + j&omega;L<sub>X</sub>), L<sub>X</sub> = N<sup>2</sup>/R<sub>X</sub>;
u_demodulated settles at u(twist) = Re(R_bridge (I<sub>B</sub> - I<sub>A</sub>)) / 2 plus a ripple at 2 f_supply.</li>
<li>Conditioning (question 9): offset removal, u_offset_removed = u_demodulated - u(0)
(calculated parameter <code>u_demodulated_zero_torque</code>), then calibration: the twist whose u(twist) - u(0)
equals it (bisection between the stops; the characteristic is monotonic there), times K_torsion_bar:
<code>torque_measured</code>. The calibration is the model's own characteristic, computed from the parameters:
change a parameter and it follows. Outside the characteristic's range (the filter's start-up from 0 V) the
measurement saturates at the stop torque.</li>
</ul>

<h3>Parameter values</h3>
<ul>
<li>From the chapter: r1 = 15 mm, r2 = 16.5 mm, b = 2 mm, N = 1000, &mu;<sub>0</sub> = 4&pi;&middot;10<sup>-7</sup>
(question 4), R_winding = 30 &Omega; (question 5), f_supply = 5 kHz (question 8).</li>
<li>K_torsion_bar = 2 N m/deg = 114.59 N m/rad, usual for EPS torsion bars (a steel bar, G = 80 GPa, 4.6 mm in
diameter and 30.7 mm long); torque_full_scale = 8 N m (&plusmn;4 deg), a usual EPS measuring range;
twist_stop = 5 deg (10 N m), 1.25 times the full-scale twist.</li>
<li>mu_r_iron = 2000 (a MnZn ferrite: no eddy currents at 5 kHz), iron_path_length = 30 mm (two yoke legs and the
back around the coil, and the ring): the iron adds 0.52 % to the gaps' reluctance, so question 4's assumption
holds to half a percent.</li>
<li>Ring B's teeth: 8 tooth pairs, 22.5 deg wide (half the 45 deg pitch), half overlapping at rest (11.25 deg) so
the overlap stays inside the teeth between the stops (&plusmn;5 deg); radius 12 mm, axial length 5 mm, radial gap
0.3 mm. R_teeth(0) = 2.53&middot;10<sup>6</sup> H<sup>-1</sup> beside 2 R_gap = 12.07&middot;10<sup>6</sup> H<sup>-1</sup>,
so L_B(0) = 68.18 mH. Chosen as a plausible geometry, not tuned to make the raw output linear.</li>
<li>U_supply = 5 V (5 V sensor electronics); R_bridge = 2.2 k&Omega;, the E12 value nearest
&omega; L_B(0) - R_winding = 2.11 k&Omega;: the in-phase part R_bridge Re(I<sub>B</sub>) is most sensitive to L_B when the
arm's resistance equals its reactance.</li>
<li>f_filter = 200 Hz, Butterworth (filter_damping = 0.707): the 10 kHz ripple is attenuated 2500 times
(275 &mu;V peak to peak remain), the response settles in about 5 ms, far above a steering torque's bandwidth.</li>
</ul>

<h3>What comes out (the tests' figures)</h3>
<ul>
<li>Raw characteristic u_demodulated(T): offset 0.2324 V at 0 N m (the bridge is unbalanced: L_B(0) &lt; L_A),
least-squares slope -10.23 mV/(N m) (the output falls as the torque rises), 168 mV span over &plusmn;8 N m, and a
largest deviation from the straight line of 11 % of the span: a two-point linear calibration would err by a
third of full scale. The conditioning by the model's own characteristic meets 0.16 % of full scale, ripple
included, with the torque's sign.</li>
<li>Differential arrangement (arrangement = 2): no offset, slope -20.47 mV/(N m) (twice), 1.4 % of the span from a
straight line (a two-point line would err by 4 % of full scale); conditioned within 0.033 % of full scale.</li>
<li>Question 5: a 5 V step on winding A alone (R_bridge = 0): the winding model and the R-L model differ by at most
0.19 % of the final current U/R = 167 mA (time constants 2.747 and 2.761 ms: the iron's reluctance).</li>
<li>The FMU integrates the 5 kHz carrier with its adaptive explicit Runge-Kutta solver inside each communication
step: 1 ms communication steps give the same filtered output as 10 &mu;s steps (to 1e-8).</li>
</ul>
"#;
