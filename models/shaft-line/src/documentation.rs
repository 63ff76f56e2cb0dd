//! The model's page in documentation/index.html (the runtime adds the variable tables).

pub const HTML: &str = r#"
<p>Chapter 3, section 3.5.3: the short circuit of a diesel-electric submarine's DC propulsion motor, the sizing
case of its shaft line (Figures 3.29-3.30, Table 3.8). The motor drives the propeller directly through a hollow
shaft; a seal rubs on the shaft where it leaves the hull; bearings lose a little. The question: the maximal
transient shaft torque, against the rated torque, and which elements make it.</p>
<p><b>Defaults: the book's own file</b>, Chap3_Submarine.mo of the authors' repository
(marcbudinger/MultiphysicsModelingTechSys; models FullModel, FullModel_AI, ReducedModel). The supply ramps from 0
to 700 V in 50 s, holds to 100 s and is short-circuited (0 V) at t = 100 s; the run ends at 150 s.</p>
<h3>Equations</h3>
<ul>
<li>Armature (eq. 3.9, E = k w, C = k I): L di/dt = U(t) - R i - k w_m.</li>
<li>Motor end: J_m dw_m/dt = k i - b w_m - T_shaft, with J_m = J_motor + J_shaft/2.</li>
<li>Hollow shaft: d(theta)/dt = w_m - w_p; T_shaft = K_shaft theta + D_shaft (w_m - w_p).</li>
<li>Propeller end (propeller, seal): J_p dw_p/dt = T_shaft - a w_p |w_p| + T_seal, with J_p = J_propeller + J_shaft/2
and a = T_propeller_nominal / speed_propeller_nominal<sup>2</sup> (<code>propeller_law</code> = 2: a w_p<sup>2</sup>).</li>
<li>Seal (Coulomb friction with sticking, a discrete mode m): slipping (m = +-1), T_seal = -T_c m; stuck (m = 0),
w_p = 0 and the seal takes T_req = T_shaft - a w_p |w_p| while |T_req| &lt;= T_s. Events: a slipping propeller that
stops sticks if the seal holds it, else slips the way it is pushed; a stuck one breaks loose when |T_req| reaches
T_s. The seal acts on the propeller end: it closes the hull aft, outboard of the shaft's compliant length.</li>
<li>Activity of each element (eq. 3.3): A = integral of |power| dt from t = 0.</li>
</ul>
<h3>The two ratios of eq. 3.9 are one</h3>
<p>An ideal machine neither stores nor dissipates energy: E I = C w at every instant. With E = k_E w and C = k_C I,
k_E w I = k_C I w for every w and I, so k_E = k_C = k.</p>
<h3>Every value and its source</h3>
<table>
<tr><th>parameter</th><th>default</th><th>book file Chap3_Submarine.mo</th><th>Table 3.8 / text</th></tr>
<tr><td>k_emf (emf_constant = 1)</td><td>55.7325 V s/rad</td><td>emf: k = 700/(120*2*3.14/60)</td><td>not given; emf_constant = 2 derives 53.627 from the rated point</td></tr>
<tr><td>R_armature, L_armature</td><td>8 mOhm, 20 mH</td><td>resistor, inductor</td><td>same</td></tr>
<tr><td>U_max, ramp_time, plateau_time</td><td>700 V, 50 s, 50 s</td><td>tableVoltage [0,0; 50,700; 100,700; 100,0; 150,0]</td><td>200 s ramp, 200 s plateau, short circuit at 400 s, 600 s</td></tr>
<tr><td>J_motor, b_motor_bearings</td><td>3e3 kg m<sup>2</sup>, 10 N m/(rad/s)</td><td>inertia_motor, friction_motor</td><td>same</td></tr>
<tr><td>K_shaft, D_shaft</td><td>6.5e6 N m/rad, 25 000 N m/(rad/s)</td><td>shaft_stiffness_loss (SpringDamper)</td><td>same</td></tr>
<tr><td>J_shaft</td><td><b>0</b></td><td>no shaft inertia</td><td>20 kg m<sup>2</sup></td></tr>
<tr><td>J_propeller</td><td>150e3 kg m<sup>2</sup></td><td>Propeler_Inertia</td><td>same</td></tr>
<tr><td>T_seal_coulomb, T_seal_static</td><td>9000 N m</td><td>Propeler_friction: tau_pos = [0, 9000]</td><td>9000 N m</td></tr>
<tr><td>T_propeller_nominal, speed_propeller_nominal</td><td>1.75e5 N m at 12.56 rad/s</td><td>Propeler_quadratic_torque: tau_nominal -1.75e5 (FullModel_AI, ReducedModel; FullModel: -(1.75e5 - 9e3)) at w_nominal 120*2*3.14/60</td><td>T = a w<sup>2</sup>, 1.75e5 N m and 120 rpm rated</td></tr>
<tr><td>propeller_law</td><td>1 (a w |w|)</td><td>FullModel: TorqueDirection = false; ReducedModel: true (2)</td><td></td></tr>
<tr><td>T_rated, speed_rated, U_rated</td><td>1.75e5 N m, 4 pi rad/s, 700 V</td><td>(700 V and 120 rpm inside k)</td><td>Table 3.8; used by shaft_torque_ratio and emf_constant = 2</td></tr>
</table>
<p><b>Values easy to get wrong by hand</b>: the shaft inertia must be 0 (not Table 3.8's 20 kg m<sup>2</sup>); pi is 3.14 in the
file's k and w_nominal (k = 55.7325, not 700/(4 pi) = 55.7042); the ramp is 50 s, not the text's 200 s; the propeller constant
is 1.75e5 N m in the model the activity question uses (FullModel_AI), 1.66e5 in FullModel.
Default: 1.75e5, the value of the two models the model-reduction question compares. The other values are parameters:
the chapter text's reading is ramp_time = plateau_time = 200 s, J_shaft = 20, emf_constant = 2,
speed_propeller_nominal = 4 pi and a 600 s run.</p>
<p>Table 3.8's 45 t, 6 m, 41 t, 25 cm, 4.5 m (motor mass, propeller diameter, propeller mass, shaft diameter and length) are not
in the torsional model (they agree with the stiffness: a steel shaft of 25 cm, 4.5 m with a 12 cm bore has K = 6.5e6 N m/rad).</p>
<h3>Results with the defaults (tests/python/test_shaft_line.py)</h3>
<ul>
<li>Steady state at 700 V: 12.117 rad/s, 3086 A, 171 995 N m (the hand balance to 1e-7).</li>
<li>Maximal transient shaft torque: -1.2891e6 N m at 101.456 s, 7.37x the rated torque (an independent Radau solution agrees to 1e-11).
The chapter text's reading gives -1.2667e6 N m at 401.514 s, 7.24x.</li>
<li>The propeller reverses (-5.8 rad/s), the seal slips both ways and sticks for good at 120.2 s: 8 seal events.</li>
<li>Activity over 100-150 s: propeller inertia 39.8 %, armature inductance 33.2 %, armature resistance 20.7 %, propeller
load 3.9 % (together 97.7 %); motor inertia, shaft stiffness, seal, shaft damping and bearings below 1 % each. The
transient is an electromechanical oscillation between the inductance and the propeller inertia (0.98 rad/s, 20 % damped).</li>
</ul>
<h3>Structural parameters</h3>
<ul>
<li><code>model_reduction</code> = 1: the book's ReducedModel, no motor inertia and a rigid shaft, the bearings and the seal kept:
L di/dt = U - R i - k w, J_p dw/dt = k i - b w - a w |w| + T_seal; the shaft torque is k i - b w. Peak -1.3165e6 N m (+2.1 %).
The file writes its propeller with TorqueDirection = true (<code>propeller_law</code> = 2), which drives a propeller turning
backwards: the same peak, a backwards swing to -6.17 rad/s instead of -5.83.</li>
<li><code>model_reduction</code> = 2: only the elements covering 95 % of the short-circuit activity (R, L, propeller inertia
and load): J_p dw/dt = k i - a w |w|, the shaft carries k i. Peak -1.3251e6 N m (+2.8 %).</li>
<li><code>voltage_from_input</code> = true: the supply is the input <code>U_supply_in</code> instead of the built-in profile.</li>
</ul>
<p>Integer locals: <code>seal_mode</code> (1 slipping forwards, 0 stuck, -1 backwards) and <code>state_events</code> (zero crossings handled).
Solver: explicit Runge-Kutta (the fastest mode, the shaft's 47 rad/s, is not stiff). Contract: docs/shaft-line-spec.md.</p>
"#;
