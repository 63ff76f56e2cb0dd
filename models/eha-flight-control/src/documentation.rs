//! The model's page in documentation/index.html (the runtime adds the variable tables, Table 3.1
//! of the declared elements and the activities of the default experiment).

pub const HTML: &str = r#"
<p>Chapter 3, section 3.4.1.2, Figure 3.16.a: the electro-hydrostatic actuator (EHA) of a flight-control surface,
here an aileron. A DC bus feeds, through a converter, an electric motor that turns a fixed-displacement pump; the
pump moves oil between the two chambers of a double-acting cylinder; the cylinder's rod pushes on the surface's horn;
the air holds the surface back with a hinge moment. The position loop is closed inside the FMU. The chapter asks
for Table 3.5 (the components and their two equations as ideal transformers); the FMU adds the storage and
dissipation effects a sizing needs, in two levels, and answers: what is the hydraulic stiffness mode's frequency,
and what does it do to the surface's position response?</p>

<h3>Table 3.5: the EHA's transformers, two equations each</h3>
<table>
<tr><th>component</th><th>ports</th><th>equations</th></tr>
<tr><td>converter (power electronics)</td><td>DC bus (U_bus, I_bus) to motor (U, i)</td><td>U = alpha U_bus, I_bus = alpha i</td></tr>
<tr><td>electric motor (eq. 3.9)</td><td>electrical (E, i) to rotation (C, w_m)</td><td>E = k w_m, C = k i</td></tr>
<tr><td>fixed-displacement pump</td><td>rotation (T, w_m) to hydraulics (dp, Q)</td><td>Q = D w_m, T = D dp</td></tr>
<tr><td>double-acting cylinder</td><td>hydraulics (dp, Q) to translation (F, v)</td><td>F = A dp, Q = A v</td></tr>
<tr><td>horn (lever arm)</td><td>translation (F, v) to rotation (M, w_s)</td><td>v = r w_s, M = r F</td></tr>
</table>
<p>With rigid oil the pump, the cylinder and the horn in a row are one reducer: w_m = N w_s with
N = A r / D = 564.5 motor radians per surface radian, and the surface inertia is seen by the motor as
J_s / N<sup>2</sup> = 1.57e-5 kg m<sup>2</sup> (eq. 3.7), 8 % of the rotor's 2e-4.</p>

<h3>Equations</h3>
<ul>
<li>Command: theta_cmd = step_angle from step_time to return_time (0 elsewhere) + <code>angle_command_in</code>.</li>
<li>Position law (proportional): U = Kp (theta_cmd - theta), clamped to +-U_bus; the corners of the clamp are
state events (Integer local <code>voltage_limit</code>).</li>
<li>Armature (eq. 3.9): L di/dt = U - R i - k w_m.</li>
<li>Hinge moment the actuator holds: M = K_hinge theta - M_external.</li>
<li>Level 1 (ideal transformers, rigid oil): (J_motor + J_surface / N<sup>2</sup>) dw_m/dt = k i - M / N,
dtheta/dt = w_m / N; the pressure follows: dp = (J_surface dw_s/dt + M) / (A r).</li>
<li>Level 2 (with the oil's compressibility and leakage): J_motor dw_m/dt = k i - D dp;
C d(dp)/dt = D w_m - A r w_s - dp / R_leakage with C = V_chamber / (2 B_oil) (each chamber a capacitance
V_chamber / B_oil, Table 3.2; the two seen from the pressure difference are in series);
J_surface dw_s/dt = A r dp - M; dtheta/dt = w_s.</li>
<li>Hydraulic stiffness: k_oil = A<sup>2</sup> (B/V_a + B/V_b) = 2 A<sup>2</sup> B / V_chamber = 6.81e7 N/m at mid
stroke; the surface as a mass on the rod m = J_surface / r<sup>2</sup> = 500 kg; <b>f = sqrt(k_oil / m) / 2 pi =
58.74 Hz</b> (calculated parameter <code>f_hydraulic</code>).</li>
</ul>
<p>Assumptions: the chambers keep their mid-stroke volume. At 10 degrees the piston has displaced
A r theta = 23.5 cm<sup>3</sup>, 29 % of a chamber: V(1 + e) and V(1 - e) stiffen the columns by 1/(1 - e<sup>2</sup>), 9.5 %
(4.6 % on the frequency); towards the stroke's ends the mid-stroke figure is a lower bound. The horn is linear (v = r w_s, the
cos theta of its kinematics, chapter 6, left out); the converter is ideal and has no current limit.</p>

<h3>Every value and its source</h3>
<p>The chapter gives none. Each default is argued from public data or first principles
(<code>docs/eha-flight-control-spec.md</code> has the same table).</p>
<table>
<tr><th>parameter</th><th>default</th><th>argument</th></tr>
<tr><td>U_bus</td><td>270 V</td><td>the HVDC bus of MIL-STD-704; a six-pulse rectifier on the 115/200 V AC network gives 1.35 x 200 = 270 V</td></tr>
<tr><td>A_piston</td><td>13.48 cm<sup>2</sup></td><td>a 50 mm bore on a 28 mm through rod (equal areas). Sized by the A380's 5000 psi class: at 34.5 MPa it
stalls at 46.5 kN, 4.65 kN m on the horn, just above the hinge moment at the full 25 degrees (4.36 kN m)</td></tr>
<tr><td>r_horn</td><td>0.1 m</td><td>horn arm; +-25 degrees is +-42 mm of stroke</td></tr>
<tr><td>D_pump</td><td>1.5 cm<sup>3</sup>/rev (2.387e-7 m<sup>3</sup>/rad)</td><td>published EHA pumps have 1-3 cm<sup>3</sup>/rev; with the motor's
675 rad/s at no load the surface moves at 68 deg/s (aileron rates are some 40-60 deg/s under load)</td></tr>
<tr><td>K_hinge</td><td>1e4 N m/rad</td><td>q S c |C_h,delta|: q = 19.8 kPa (350 kt at sea level), an aileron of S = 1.4 m<sup>2</sup> and chord
c = 0.6 m, C_h,delta = -0.6 /rad (a plain flap without aerodynamic balance; -0.3 to -0.9 in the classical data): 9980 N m/rad</td></tr>
<tr><td>J_surface</td><td>5 kg m<sup>2</sup></td><td>a 60 kg aileron of 0.6 m chord is 7.2 kg m<sup>2</sup> as a uniform plate about its leading edge
(m c<sup>2</sup>/3); its mass balance brings the centre of mass toward the hinge</td></tr>
<tr><td>V_chamber</td><td>80 cm<sup>3</sup></td><td>the half stroke's swept volume, 13.48 cm<sup>2</sup> x 42 mm = 57 cm<sup>3</sup>, plus 23 cm<sup>3</sup> of
end clearance, manifold passages and the pump's ports (the pump and the cylinder share one block)</td></tr>
<tr><td>B_oil</td><td>1.5 GPa</td><td>air-free aviation hydraulic oil (MIL-PRF-5606 and kin, phosphate esters alike): 1.4-1.8 GPa
(components::geometry::HYDRAULIC_OIL_BULK_MODULUS_PA; entrained air would lower it, and the mode with its square root)</td></tr>
<tr><td>R_leakage</td><td>2.484e12 Pa s/m<sup>3</sup></td><td>0.5 L/min across the piston at 20.7 MPa (3000 psi): the piston seals' and the pump's cross-port
leakage lumped, 6 % of the pump's 9 L/min at 6000 rpm (a volumetric efficiency of 94 %)</td></tr>
<tr><td>k_motor, R_motor, L_motor</td><td>0.4 V s/rad, 1 Ohm, 2 mH</td><td>chosen for a 270 V permanent-magnet motor of a few kW: 675 rad/s (6450 rpm) at no load;
the stall pressure's torque D x 34.5 MPa = 8.24 N m takes 20.6 A; L/R = 2 ms</td></tr>
<tr><td>J_motor</td><td>2e-4 kg m<sup>2</sup></td><td>the rotor of such a motor with the pump's rotating group</td></tr>
<tr><td>Kp</td><td>3000 V/rad</td><td>the loop's pole at 13.7 /s (2 % settling in 0.30 s); 41 % of the gain at which level 2's hydraulic
mode goes unstable (7296 V/rad). Level 1 would allow 112 900 V/rad</td></tr>
<tr><td>step_angle, step_time, return_time</td><td>10 deg, 0.1 s, 0.6 s</td><td>the built-in command: the default experiment moves power without input</td></tr>
</table>

<h3>Results with the defaults (tests/python/test_eha_flight_control.py)</h3>
<ul>
<li><b>Steady state</b> (command held): the surface holds M = K_hinge theta through dp = M / (r A), the motor the pump's
D dp with i = D dp / k; the proportional law needs U = R i (+ k w at level 2, where the pump turns at w = Q_leak / D to
make up the leakage), hence an angle error U / Kp. Level 1: 9.8545 deg (error 1.45 % of the step), 1719.9 N m,
12.76 MPa, 7.62 A, 7.62 V; level 2: 9.6951 deg (3.05 %), 12.56 MPa, 7.49 A, 21.2 rad/s, 15.96 V. The FMU agrees with
the hand balance to 1.1e-11.</li>
<li><b>Transients</b> against scipy (DOP853, rtol 1e-12, the limit's corners located): a 2 degree step (linear):
1.2e-8 (level 1) and 3.1e-11 (level 2) of each output's range; the default saturated run: 1.8e-9 and 9.2e-11.</li>
<li><b>The hydraulic mode</b>: with the pump held (J_motor = 1e3 kg m<sup>2</sup>) the FMU's linearisation gives
59.172 Hz, 0.73 % above sqrt(k_oil / m) = 58.743 Hz: the hinge's K_hinge / r<sup>2</sup> = 1e6 N/m adds 1.5 % to the
stiffness (59.173 Hz with it, -0.001 %); a simulated free oscillation gives 59.175 Hz. In the default actuator the
rotor, 6374 kg on the rod (12.7 x the surface's 500 kg), is held by the loop and its armature: 58.27 Hz (-0.81 %),
damping 2.9 %.</li>
<li><b>What the mode does to the response</b> (10 degree step and return): the surface angle barely shows it. Both
levels slew at the voltage limit and settle within 2 % in 0.30 s without overshoot; level 2 less level 1 ripples at the
mode by -0.20 .. +0.17 deg after the step (2 % of the step) and -0.37 deg after the return, and ends 0.16 deg lower,
the leakage's steady error. The pressure shows it fully: level 2 rings at 58.2 Hz (the damped mode) after each corner
of the motor's torque and swings over -15.7 .. 29.2 MPa against level 1's -3.9 .. 16.2 MPa: the compliance nearly
doubles the peak pressure the cylinder and the pump see. And the mode sets the loop's gain: the rigid model would
let Kp rise 37.6 x, the compressible one only 2.43 x before the mode goes unstable.</li>
<li>The voltage-only loop draws up to 132 A at the steps (270 V on a still motor, limited by L and the back EMF): a real
drive's current loop would cap it; it is not modelled.</li>
</ul>

<h3>Structural parameter</h3>
<ul>
<li><code>level</code> = 1: Table 3.5's ideal transformers, rigid oil, the surface inertia referred to the motor; the states
<code>dp_load</code> and <code>w_surface</code> are frozen, the outputs <code>pump_pressure</code> and <code>surface_rate</code>
follow from the motion, the oil and leakage elements report no power.</li>
<li><code>level</code> = 2 (default): the oil's compressibility and the leakage.</li>
</ul>
<p>Integer locals: <code>voltage_limit</code> (0 within the limit, +-1 clamped) and <code>state_events</code>. Solver: explicit
Runge-Kutta (the fastest modes, the motor's electromechanical one at |lambda| = 640 /s and the hydraulic one at 366 /s,
are not stiff); tolerance floor 1e-5 (at 1e-3 the oil's activity, which rectifies the 58 Hz ringing, was 11 x rtol of its
range off). Contract: docs/eha-flight-control-spec.md.</p>
"#;
