//! The model's page in documentation/index.html (the runtime adds the variable tables, Table 3.1
//! of the declared elements and the activities of the default experiment).

pub const HTML: &str = r#"
<p>Chapter 3, section 3.4.1.1, Figure 3.15: the launcher booster nozzle, which "has two rotational degrees of freedom for
the control of thrust direction of propellant gases". Question 2 asks for the dominant effect of each part. The FMU
models a large solid booster's movable nozzle (Vega P80 class, the values below) about its pivot on a flexible bearing,
steered in pitch and in yaw by one hydraulic servo-actuator each: a servo-valve feeds a double-acting cylinder whose rod
pushes on the nozzle at the lever arm r and whose body is held by its anchoring on the motor case. The gases load the
nozzle with a thrust-offset torque, the air with an aerodynamic torque (inputs). A position loop per axis is closed
inside the FMU. The answers: the actuator-nozzle resonance, and the dominant effect of each part, measured by the
activity of its elements (eq. 3.3, Table 3.3).</p>

<h3>Question 2: the dominant effect of each part</h3>
<p>Shares of the activity (eq. 3.3) of the pitch axis's storage elements, and of its dissipative ones, in three motions
(tests/python/test_booster_nozzle.py checks them against an independent computation and asserts the claims below):
the default 0.5 deg step; a 0.5 deg sine at 2 Hz (profile 2); a 5.7 deg sine at 0.3 Hz (the first cycle of the P80
actuator's endurance profile). Which part dominates depends on the motion, the chapter's point.</p>
<table>
<tr><th>part</th><th>domain</th><th>dominant effect</th><th>step</th><th>2 Hz</th><th>0.3 Hz, 5.7 deg</th><th>why</th></tr>
<tr><td>nozzle (the swivelling cone)</td><td>rotation</td><td>inertia I (1400 kg m<sup>2</sup>, 768 kg on the rod)</td><td><b>52.3 %</b></td><td>21.4 %</td><td>0.7 %</td>
<td>the mass of the actuator-nozzle resonance; dominant in fast moves</td></tr>
<tr><td>flexible bearing (laminated elastomer and steel shims)</td><td>rotation</td><td>stiffness C (15 200 N m/deg); its damping R second</td><td>6.9 %</td><td><b>72.7 %</b></td><td><b>98.4 %</b></td>
<td>the actuator's static load: 86.6 kN m at 5.7 deg, 64.2 kN on the rod ("the force is mainly proportional to the position"); its damping takes 8-40 % of the dissipation</td></tr>
<tr><td>actuator: oil in the two chambers</td><td>hydraulic</td><td>compressibility C (k = 2 A<sup>2</sup> B / V = 1.04e8 N/m)</td><td>18.8 %</td><td>2.8 %</td><td>0.5 %</td>
<td>with the anchoring in series, the spring of the 41 Hz resonance</td></tr>
<tr><td>actuator: cylinder and lever arm</td><td>hydraulic, translation, rotation</td><td>transformers (F = A dp, Q = A dy/dt; M = r F, v = r w)</td><td>-</td><td>-</td><td>-</td><td>no power of their own (Table 3.5)</td></tr>
<tr><td>anchoring of the actuator (backup structure)</td><td>translation</td><td>stiffness C (1e8 N/m)</td><td>20.3 %</td><td>3.0 %</td><td>0.5 %</td>
<td>as much as the oil: it lowers the resonance from 58.7 Hz (rigid anchoring) to 41.0 Hz, and the stroke loop does not see it</td></tr>
<tr><td>actuator body</td><td>translation</td><td>inertia I (30 kg): negligible</td><td>1.6 %</td><td>0.0 %</td><td>0.0 %</td><td>its own mode is at 417 Hz, ten times the resonance</td></tr>
<tr><td>servo-valve</td><td>hydraulic</td><td>source (modulated flow), with its flow-pressure coefficient R</td><td>77.1 % of the dissipation</td><td>59.6 %</td><td>92.2 %</td>
<td>the main damping of the resonance; it sets the loop's gain limit</td></tr>
<tr><td>gases</td><td>rotation</td><td>source: thrust-offset torque (11.3 kN m)</td><td colspan="3">0.0116 deg of static deflection</td><td>a load the loop holds</td></tr>
<tr><td>air</td><td>rotation</td><td>source: aerodynamic torque (input)</td><td colspan="3">-</td><td>a load the loop holds</td></tr>
</table>
<p>The chapter's figure labels its parts a) to e); the text (and so this page) has only the caption, so the table names
the parts by what they are.</p>

<h3>Equations (per axis; pitch and yaw are identical and uncoupled)</h3>
<p>Small angles: the axisymmetric nozzle has the same inertia and the bearing the same stiffness about both transverse
axes, each actuator acts in its own plane, and the geometric coupling between them is second order in the angles. A pitch
command leaves yaw exactly at rest (tested).</p>
<ul>
<li>Command: the built-in profile (<code>profile</code> 1: a step of <code>command_amplitude</code> at <code>step_time</code>;
2: a sine of it at <code>sine_frequency</code> from <code>step_time</code>; 0: none) times cos <code>command_azimuth</code> for
pitch, sin for yaw, plus the input <code>theta_command_pitch</code> / <code>theta_command_yaw</code>. The start of the profile
is a time event.</li>
<li>Stroke (rod end less body): y = r theta - x_b; servo-valve and position loop: Q_v = A K_v (r theta_cmd - y), the flow that
moves the rod at K_v times the stroke error (the actuator's transducer measures the stroke, not the nozzle angle).</li>
<li>Oil: C d(dp)/dt = Q_v - A (r w - v_b) - dp / R_leakage, with C = V_chamber / (2 B_oil): each chamber a C element
V_chamber / B_oil (Table 3.2), the two in series seen from the pressure difference.</li>
<li>Nozzle: J dw/dt = r A dp - K_bearing theta - D_bearing w + M_offset (cos or sin <code>offset_azimuth</code>) + M_aero,
dtheta/dt = w.</li>
<li>Actuator body on its anchoring: m_a dv_b/dt = -A dp - K_anchor x_b - D_anchor v_b, dx_b/dt = v_b. (The FMU keeps the
body's displacement and velocity referred to the nozzle angle, x_b / r and v_b / r, in rad and rad/s.)</li>
</ul>
<p><b>The actuator-nozzle resonance.</b> With the valve closed the axis is a two-degree-of-freedom chain: the nozzle (theta)
on its bearing, the oil column k = 2 A<sup>2</sup> B / V acting at the arm r, the actuator body (x_b) on its anchoring.
M = diag(J, m_a), K = [[K_bearing + k r<sup>2</sup>, -k r], [-k r, k + K_anchor]]; det(K - w<sup>2</sup> M) = 0 gives
<b>f_actuator_nozzle = 40.992 Hz</b> and f_actuator_body = 417.24 Hz (calculated parameters, components::TwoDegreesOfFreedom).
The body's mass barely matters: the nozzle on the oil and the anchoring in series (5.10e7 N/m, massless body) gives
41.20 Hz, with a rigid anchoring 58.72 Hz; the nozzle on its bearing alone 3.97 Hz (<code>f_bearing</code>).
The default actuator, loop closed, keeps it at 40.68 Hz (-0.76 %), damping 7.0 %.</p>
<p><b>Static deflection under a constant load.</b> A torque M and a held command theta_cmd: the rod holds F = (K_bearing theta - M) / r,
the anchoring gives F / K_anchor, the valve must make up the leakage dp / R_leakage, so the stroke lags the command by
F / (A<sup>2</sup> R_leakage K_v); hence theta = (K_s theta_cmd + M) / (K_s + K_bearing) with the servo's static stiffness
K_s = r<sup>2</sup> / (1/K_anchor + 1/(A<sup>2</sup> R_leakage K_v)) = 5.51e7 N m/rad (<code>K_servo_static</code>). The thrust
offset's 11.3 kN m deflect the nozzle by 0.0116 deg; 50 kN m by 0.0512 deg (36.5 kN on the rod, 0.36 mm at the anchoring).
Loop open (K_v = 0) the leakage relieves the oil and theta = M / K_bearing.</p>

<h3>Every value and its source</h3>
<p>The chapter gives none. The nozzle's values are the Vega P80's of M. Budinger's Vega thrust-vector-control course
(INSA Toulouse, github.com/SizingLab/sizing_course, laboratories/Lab-vega; its P80 endurance profile is G. Vanthuyne's, ESMATS 2009,
on the P80's electromechanical TVC); the actuator is a hydraulic servo-actuator of the Ariane 5 booster's kind sized for that load
(<code>docs/booster-nozzle-spec.md</code> has the same table).</p>
<table>
<tr><th>parameter</th><th>default</th><th>argument</th></tr>
<tr><td>J_nozzle</td><td>1400 kg m<sup>2</sup></td><td>the P80 nozzle about its pivot (Budinger's course)</td></tr>
<tr><td>K_bearing</td><td>15 200 N m/deg = 8.709e5 N m/rad</td><td>the P80 flexible bearing (same source); 3.97 Hz with the nozzle alone</td></tr>
<tr><td>D_bearing</td><td>174 N m s/deg = 9969 N m s/rad</td><td>its viscous damping (same source)</td></tr>
<tr><td>r_arm</td><td>1.35 m</td><td>the actuator's lever arm about the pivot (same source); +-6 deg is +-141 mm of stroke</td></tr>
<tr><td>A_piston</td><td>58.90 cm<sup>2</sup></td><td>a 100 mm bore on a 50 mm through rod: 121.9 kN at 20.7 MPa (3000 psi, the class of the Shuttle booster's
TVC supply) against the bearing's 64.2 kN at 5.7 deg, the nozzle's 14.7 kN at the P80 step's 811 deg/s<sup>2</sup> and the offset's 8.4 kN</td></tr>
<tr><td>V_chamber</td><td>1.0e-3 m<sup>3</sup></td><td>the half stroke's 58.9 cm<sup>2</sup> x 145 mm = 854 cm<sup>3</sup> plus 146 cm<sup>3</sup> of end clearance and
manifold passages to the servo-valve</td></tr>
<tr><td>B_oil</td><td>1.5 GPa</td><td>air-free hydraulic oil (MIL-PRF-5606 and kin: 1.4-1.8 GPa; components::geometry::HYDRAULIC_OIL_BULK_MODULUS_PA)</td></tr>
<tr><td>R_leakage</td><td>3.0e10 Pa s/m<sup>3</sup></td><td>the servo-valve's flow-pressure coefficient linearised by Merritt's K_c = Q0 / (2 Ps) at the flow of a
10 deg/s nozzle rate (Q0 = A r 10 deg/s = 1.39e-3 m<sup>3</sup>/s, about the P80 step's 9.24 deg/s) and Ps = 20.7 MPa: 1/K_c = 2.98e10; the piston's own leak
is negligible beside it</td></tr>
<tr><td>m_actuator</td><td>30 kg</td><td>the actuator's body between its oil and its anchoring: a 0.6 m steel tube of 100 mm bore and 8 mm wall (13 kg), end caps,
manifold, servo-valve and transducer</td></tr>
<tr><td>K_anchor</td><td>1e8 N/m</td><td>the anchoring (bracket on the motor case, rod ends, the body's own stiffness): 100 kN/mm, 1.2 mm under the stall force;
chosen of the order of the oil column's 1.04e8 N/m (a much softer structure would waste the actuator's stiffness)</td></tr>
<tr><td>D_anchor</td><td>5477 N s/m</td><td>its structural damping: 5 % of critical for the body alone on it, 2 x 0.05 sqrt(K_anchor m_actuator) (bolted steel
structures: 2-5 %)</td></tr>
<tr><td>K_v</td><td>41.67 /s</td><td>3 / 72 ms: the rigid first-order loop's 5 % response time is the P80's requirement (a 0.5 deg step, 5.2 to 5.7 deg, in 72 ms)</td></tr>
<tr><td>M_offset, offset_azimuth</td><td>11 300 N m, 0</td><td>the P80's mean thrust, 88 t of propellant in about 107 s at 280 s of vacuum Isp = 2.26 MN, passing 5 mm
(manufacturing and thermal tolerances) from the pivot; all in pitch</td></tr>
<tr><td>command_amplitude, step_time, command_azimuth</td><td>0.5 deg, 0.1 s, 0</td><td>the P80's dynamic sizing step; pitch only</td></tr>
<tr><td>sine_frequency</td><td>2 Hz</td><td>a cycle of the P80 actuator's endurance profile (0.3-5 Hz)</td></tr>
</table>

<h3>Results with the defaults (tests/python/test_booster_nozzle.py)</h3>
<ul>
<li><b>Resonance</b>: under the chain's conditions (valve closed and sealed, no damping) the eigenvalues of the FMU's Jacobian,
from its directional derivatives, are +-i 2 pi 40.991683 Hz and +-i 2 pi 417.244 Hz, the chain's to 1e-15. A free oscillation
simulated by the FMU from the chain's low mode shape, the dampings kept, gives 40.9926 Hz (+0.002 %). The default actuator:
40.68 Hz (-0.76 %), damping 7.0 %; the body mode 417.3 Hz, 4.0 %; the loop's real pole -42.6 /s.</li>
<li><b>The default step</b> (0.5 deg at 0.1 s, the offset torque from t = 0): 5 % response time 83.6 ms (the rigid loop's 72 ms),
overshoot 1.3 %; the first-order loop asks the rod for 0.49 m/s at once, so the nozzle rings at the resonance and the
pressure difference swings over about -13.6 .. +12.5 MPa (below the 20.7 MPa supply); the nozzle peaks at 30 deg/s. Every output agrees
with the closed-form solution of the linear equations within 3.5e-11 of its range.</li>
<li><b>The loop's gain limit</b>: K_v = 122.7 /s (2.95 x the default), past which the resonance goes unstable; without the
anchoring's damping 100.1 /s, Merritt's K_v &lt; 2 zeta_h w_h = 1 / (R_leakage C) = 100 /s (+0.14 %).</li>
<li><b>Static deflection</b>: the FMU agrees with the hand formula within 1.3e-12 (50 kN m, loop closed), 2.7e-11 (3 deg with the
offset) and 4.7e-10 (loop open).</li>
</ul>
<p>Neglected, each with its reason in Table 3.1 below: the restoring torque of the nozzle's weight under acceleration, the
variation of the arm with the angle and the pitch-yaw geometric coupling, the elastomer's hysteresis and its stiffness's pressure
dependence, the rod's mass, the seals' friction, the oil's inertia, the cylinder walls' compliance, the spool's dynamics, the
valve's flow saturation and supply limit (the model is linear), the supply's dynamics.</p>

<h3>Structural parameter</h3>
<p><code>profile</code> (0, 1, 2): none, step (default), sine. Solver: explicit Runge-Kutta (the fastest mode, the body's at
417 Hz, is not stiff beside the steps the accuracy asks for); tolerance floor 1e-5 (at a master's 1e-3 the body's activity,
which rectifies its 417 Hz ringing, was 38 x rtol of its range off). Contract: docs/booster-nozzle-spec.md.</p>
"#;
