//! The model's page in documentation/index.html (the runtime adds the variable tables).

pub const HTML: &str = r#"
<p>The magnetic torque sensor of an electric power steering (chapter 3, section 3.5.2, Figures 3.24-3.27):
the driver's torque twists a torsion bar between the input (steering wheel) and output shafts; detection
rings A and B sit on the two ends of the bar, so their relative angle is the twist; two windings and a
5 kHz bridge turn the twist into a voltage, and a conditioning stage (question 9) turns the voltage into
torque. <b>The defaults are the book's own model</b>: the authors' file <code>Chap3_TorqueSensor.mo</code>
(marcbudinger/MultiphysicsModelingTechSys, <code>files/</code>; its models InductiveSensor2, InductiveSensorRef,
InductiveSensorVar, HollowCylinderAxialFluxVariable), each value named below with its component. The contract:
<code>docs/torque-sensor-spec.md</code> in the source repository.</p>

<h3>Structure (integer parameters; 1 is the book's)</h3>
<ul>
<li><code>sensor_data</code>: 1 = the book's magnetic circuits (flux tubes, below); 2 = this project's first set
(identical rings: two gaps r1-r2 over b and an iron path, a radial toothed gap of <code>teeth</code> teeth).</li>
<li><code>bridge_topology</code>: 1 = the book's bridge: windings A (from the supply to the midpoint) and B (from the
midpoint to ground) in one arm, R1_bridge over R2_bridge in the other, u_bridge = resistors' midpoint minus windings'
midpoint (the book's Vout); 2 = a resistor R_bridge above each winding, u_bridge = R_bridge (i_B - i_A).</li>
<li><code>twist_drive</code>: 1 = the input shaft's angle is imposed (the book's <code>position</code> source on the
torsion bar's input flange): twist = twist_in + the twist profile (0 none, 1 step, 2 ramp), smoothed by the position
source's filter at position_f_crit; torque_applied = K_torsion_bar twist (the book's spring). 2 = a torque is applied:
torque_in + the torque profile; twist = T / K_torsion_bar within &plusmn;twist_stop.</li>
<li><code>arrangement</code>: 1 = part A is the reference arm (question 7: only B gets the toothed gap); 2 = differential:
part A's circuit crosses a toothed gap too, at the opposite twist.</li>
<li><code>supply_mode</code>: 1 = U_supply sin(2&pi; f_supply t) (the book's sineVoltage); 2 = a U_supply step at t = 0
(question 5).</li>
</ul>

<h3>Equations</h3>
<ul>
<li>Magnetic analogy (questions 1-2): mmf (A) is the effort, flux (Wb) the flow; flux conservation plays Kirchhoff's
current law, Amp&egrave;re's law (sum of mmfs = N i) his voltage law. &mu;<sub>0</sub> = 4&pi;&middot;10<sup>-7</sup> H/m,
the chapter's value. Flux tubes: axial flux through a hollow cylinder, R = l / (&mu;<sub>0</sub> &mu;<sub>r</sub> &pi;
(r<sub>o</sub><sup>2</sup> - r<sub>i</sub><sup>2</sup>)); radial flux, R = ln(r<sub>o</sub>/r<sub>i</sub>) / (2&pi;
&mu;<sub>0</sub> &mu;<sub>r</sub> w).</li>
<li>Part A (sensor_data 1; Figure 3.26, question 3): the yoke's outer shell (axial, yoke_length, yoke_r_inner..yoke_r_outer),
its two poles (radial, pole_width, pole_r_inner..pole_r_outer), the two air gaps a and c (radial, b, r1..r2, &mu;<sub>r</sub> = 1)
and ring A (axial, ring_A_length, ring_r_inner..ring_r_outer), all iron at mu_r_iron, in series.</li>
<li>Part B (question 7): the same yoke, its own air gaps (b_B, r1_B..r2_B), ring B (ring_B_length) and the new component,
the toothed axial gap of <code>teeth_poles</code> poles: facing area &pi; (teeth_r_outer<sup>2</sup> - teeth_r_inner<sup>2</sup>)
(1/4 + N &theta; / (2&pi;)) over teeth_gap, with &theta; = -twist (the book's relative-angle sensor measures the output
flange against the input one): the overlap shrinks as the torque rises. Teeth half the pitch wide, half overlapping at rest;
the formula holds for |twist| &lt; &pi; / (2 N) = 9 deg (the area is clamped beyond).</li>
<li>Question 4 (iron infinitely permeable): L = N<sup>2</sup> / (2 R_gap) = &pi; &mu;<sub>0</sub> b N<sup>2</sup> / ln(r2/r1)
= 82.84 mH (calculated parameter <code>L_question4</code>); with the book's iron, <code>L_A</code> = 82.21 mH (0.76 % less);
<code>L_B0</code> = 111.38 mH.</li>
<li>Windings (Amp&egrave;re and Lenz): N i = R_X &phi;<sub>X</sub>, N d&phi;<sub>X</sub>/dt = u<sub>X</sub> - R_winding i.
Book topology: A and B carry one current, so the state is the flux linkage &lambda; = N (&phi;<sub>A</sub> + &phi;<sub>B</sub>)
= (L_A + L_B) i, d&lambda;/dt = u_s - 2 R_winding i; the windings' midpoint is R_winding i + d(L_B i)/dt, the motional
term (dL_B/dtwist x dtwist/dt) included; the resistors' midpoint is u_s R2 / (R1 + R2). Topology 2: one flux state per
winding, u<sub>X</sub> = u_s - R_bridge i<sub>X</sub>.</li>
<li>Question 5: an R-L impedance with L_question4 and R_winding behind R_bridge across the supply (both topologies):
L di_rl/dt = u_s - (R_bridge + R_winding) i_rl (output <code>i_rl_A</code>).</li>
<li>Multiplier (question 8): u_product = u_bridge u_s / U_multiplier_reference. The book multiplies the two voltages
(U_multiplier_reference = 1 V: its product and filtered output read in V<sup>2</sup>, numerically); the first set
divided by U_supply.</li>
<li>Low-pass: y'' = w<sup>2</sup> (filter_gain u_product - y) - 2 filter_damping w y', w = filter_w; <code>u_demodulated</code> = y.</li>
<li>Position smoothing (twist_drive 1, position_f_crit &gt; 0): 1 / (1 + (1.3617/w<sub>c</sub>) s + (0.6180/w<sub>c</sub><sup>2</sup>) s<sup>2</sup>),
w<sub>c</sub> = 2&pi; position_f_crit: the filter of the Modelica Position source the book uses with its defaults
(exact = false, f_crit = 50 Hz). 0 = the angle is imposed exactly.</li>
<li>Steady state (phasors, the supply as phase reference): book topology B = U (R2/(R1+R2) - Z_B/(Z_A+Z_B)); topology 2
B = R_bridge U (1/(R_bridge + Z_B) - 1/(R_bridge + Z_A)); Z_X = R_winding + j&omega;L_X; u(twist) = filter_gain U Re(B) /
(2 U_multiplier_reference), plus a ripple at 2 f_supply.</li>
<li>Conditioning (question 9): offset removal, u_offset_removed = u_demodulated - u(0) (calculated parameter
<code>u_demodulated_zero_torque</code>), then calibration: the twist whose u(twist) - u(0) equals it (bisection over
&plusmn;twist_stop; the characteristic is monotonic there), times K_torsion_bar: <code>torque_measured</code>. The
calibration is the model's own characteristic, computed from the parameters: change a parameter and it follows.
<code>sensitivity_zero_torque</code> is du/dT at 0. During the filter's start-up from 0 the measurement saturates at the
stop torque.</li>
</ul>

<h3>Parameter values and their source</h3>
<p>"Book" = book file Chap3_TorqueSensor.mo, component named.</p>
<ul>
<li>Supply: U_supply = 5 V, f_supply = 5 kHz (book, sineVoltage: V, freqHz; the chapter's question 8 gives the 5 kHz).</li>
<li>Bridge: R1_bridge = R2_bridge = 10 k&Omega; (book, R1 and R2), topology 1 (book, InductiveSensor2: inductiveSensor1 = A
from the supply, inductiveSensorVar = B to ground, Vout between the two midpoints).</li>
<li>Windings: N = 1000 (book, converter; chapter, question 4), R_winding = 30 &Omega; (book, resistor; chapter, question 5).</li>
<li>Iron: mu_r_iron = 1000 (book, mu_rConst of every iron tube). Yoke shell: 10 mm long, 21.5-23.5 mm (book, AxialIron1).
Poles: 2 mm wide, 16.5-21.5 mm (book, RadialIron1 and RadialIron2).</li>
<li>Air gaps: part A r1 = 15 mm, r2 = 16.5 mm, b = 2 mm (book, InductiveSensorRef.AirGap1/2; the chapter's question 4
values); part B r1_B = 16 mm, r2_B = 16.5 mm, b_B = 2 mm (book, InductiveSensorVar.AirGap1/2: the chapter gives none).</li>
<li>Rings: 12-15 mm (book, AxialIron2), ring A 10 mm long, ring B 5 mm (book, InductiveSensorRef/Var.AxialIron2).</li>
<li>Toothed gap: teeth_poles = 10, 12-15 mm, teeth_gap = 0.4 mm, &mu;<sub>r</sub> = 1 (book, AxialTorqueSensor and
HollowCylinderAxialFluxVariable).</li>
<li>Torsion bar: K_torsion_bar = 100 N m/rad (book, spring: c). Drive: a 0.01 rad step at 50 ms (book, step: height,
startTime) on the input flange (book, position), smoothed at 50 Hz (book, position: the library's defaults).</li>
<li>Filter: filter_gain = 1 (book, LowPassFilter: k, its default), filter_damping = 0.7 (D), filter_w = 2*3.14*300 =
1884.0 rad/s (w). <b>The book writes &pi; as 3.14</b>: its filter is at 299.85 Hz, not 300 Hz (2&pi;300 = 1885.0 rad/s);
the default keeps the book's number.</li>
<li>Multiplier: U_multiplier_reference = 1 V (book, product: the plain product of u_supply and Vout).</li>
<li>DefaultExperiment: 0.1 s, 2 &mu;s (book, experiment: StopTime, Interval). The book's tolerance 1e-6 is looser than this
FMU's floor (1e-9, for the first set's bridge): a master's 1e-6 is raised to it, and the FMU says so.</li>
<li>Not in the book (chosen): torque_full_scale = 8 N m (an EPS range; the measuring range of the figures), twist_stop =
0.1 rad = 5.7 deg (the conditioning's inversion range and, under a torque, the stops: 10 N m, 1.25 x full scale; below the
teeth's 9 deg).</li>
</ul>
<p><b>Values easy to get wrong when setting a case by hand.</b> Question 5 (a voltage step straight on a winding) needs
bridge_topology = 2 with <b>R_bridge = 0</b> and supply_mode = 2: the book's topology has no resistor above a winding.
filter_w is in rad/s with the book's 3.14. The book's demodulated output is in V<sup>2</sup> (U_multiplier_reference =
1 V), so it is 5 times the first set's for the same bridge voltage. The book's relative angle is output minus input:
&theta; = -twist. The angle step is smoothed (position_f_crit = 50 Hz), so the twist follows the step in about 12 ms.</p>
<p><b>The first set</b> (this project's parameters before the book file was read) stays reachable: sensor_data = 2,
bridge_topology = 2, twist_drive = 2, K_torsion_bar = 114.59 (2 N m/deg), twist_stop = 0.087266 (5 deg), filter_w = 1256.6 (200 Hz),
filter_damping = 0.7071, U_multiplier_reference = 5; the other first-set values are the defaults of the parameters
only it uses (R_bridge 2.2 k&Omega;, mu_r_iron_path 2000, iron_path_length 30 mm, 8 teeth of 22.5 deg half overlapping,
12 mm radius, 5 mm long, 0.3 mm gap; the torque step of 4 N m at 10 ms). It teaches what the book's does not: a bridge
resistor matched to the arm's impedance, and with arrangement = 2 an offset-free, odd output.</p>

<h3>What comes out (the tests' figures, references by phasors and by a scipy integration)</h3>
<ul>
<li>The book's experiment (defaults, 0.1 s): u_demodulated settles at -0.94175 V before the step and at -0.82787 V after
it (+0.11388 V for 0.01 rad = 1 N m), within 2 % 12.1 ms after the step; ripple 1.5 mV peak to peak; the FMU follows a
scipy integration of the book's circuit to 3.7e-10 of the output's range; torque_measured reads 1.00000 N m (mean).</li>
<li>Raw characteristic over &plusmn;8 N m: offset -0.94175 V at 0 N m (L_B(0) = 111.4 mH against L_A = 82.2 mH: the book's
bridge is balanced only near +6.1 N m); slope at zero torque 108.35 mV/(N m) (least-squares over &plusmn;8 N m: 122.25);
largest deviation from the least-squares line 13.8 % of the 2.04 V span (1.6 % over the book's &plusmn;1 N m); an
end-point line would err by 42 % of full scale. Conditioned: within 0.31 % of full scale at every sample, ripple
included.</li>
<li>Book circuits with arrangement = 2: still offset (-1.957 V; the parts differ beyond the teeth), 152.3 mV/(N m), 7.0 %.</li>
<li>The first set: offset 0.2324 V, least-squares slope -10.23 mV/(N m), 11.0 % of its span; differential: no offset,
-20.47 mV/(N m), 1.4 %.</li>
<li>Question 5 (book circuits, R_bridge = 0, a 5 V step): winding and R-L models within 0.28 % of U/R (time constants
2.740 and 2.761 ms: the iron's reluctance).</li>
<li>The FMU integrates the 5 kHz carrier with its adaptive explicit Runge-Kutta solver inside each communication step:
1 ms communication steps give the same filtered output as 10 &mu;s steps.</li>
</ul>
"#;
