//! The model's page in documentation/index.html (the runtime adds the variable tables).

pub const HTML: &str = r#"
<p>Chapter 3, section 3.5.3: the short circuit of a diesel-electric submarine's DC propulsion motor, the sizing
case of its shaft line (Figures 3.29-3.30, Table 3.8). The motor drives the propeller directly through a hollow
shaft; a seal rubs on the shaft where it leaves the hull; bearings lose a little. The supply ramps from 0 to
U_max in 200 s, holds 200 s and is short-circuited (0 V) at t = 400 s. The question: the maximal transient
shaft torque, against the rated torque, and which elements make it.</p>
<h3>Equations</h3>
<ul>
<li>Armature (eq. 3.9, E = k w, C = k I): L di/dt = U(t) - R i - k w_m.</li>
<li>Motor end: J_m dw_m/dt = k i - b w_m - T_shaft, with J_m = J_motor + J_shaft/2.</li>
<li>Hollow shaft: d(theta)/dt = w_m - w_p; T_shaft = K_shaft theta + D_shaft (w_m - w_p).</li>
<li>Propeller end (propeller, seal): J_p dw_p/dt = T_shaft - a w_p |w_p| + T_seal, with J_p = J_propeller + J_shaft/2.</li>
<li>Seal (Coulomb friction with sticking, a discrete mode m): slipping (m = +-1), T_seal = -T_c m; stuck (m = 0),
w_p = 0 and the seal takes T_req = T_shaft - a w_p |w_p| while |T_req| &lt;= T_s. Events: a slipping propeller that
stops sticks if the seal holds it, else slips the way it is pushed; a stuck one breaks loose when |T_req| reaches
T_s. The seal acts on the propeller end: it closes the hull aft, outboard of the shaft's compliant length.</li>
<li>Activity of each element (eq. 3.3): A = integral of |power| dt from t = 0.</li>
</ul>
<h3>The two ratios of eq. 3.9 are one</h3>
<p>An ideal machine neither stores nor dissipates energy: E I = C w at every instant. With E = k_E w and C = k_C I,
k_E w I = k_C I w for every w and I, so k_E = k_C = k.</p>
<h3>Table 3.8, value by value</h3>
<ul>
<li>1.75e5 N m, 120 rpm, 700 V: rated torque, speed and armature voltage; U_max = 700 V.</li>
<li>8 mOhm, 20 mH: armature resistance and inductance (L/R = 2.5 s).</li>
<li>3e3 kg m<sup>2</sup>: motor rotor inertia; 10 N m/(rad/s): its bearings' viscous friction (0.07 % of the rated torque at 120 rpm).</li>
<li>150e3 kg m<sup>2</sup>: propeller inertia with entrained water.</li>
<li>6.5e6 N m/rad, 20 kg m<sup>2</sup>, 25 000 N m/(rad/s): the hollow shaft's torsional stiffness, inertia (half on each
end) and internal damping (9 % of critical for its 7.47 Hz mode; as a bearing loss it would absorb 1.8x the rated torque).</li>
<li>9000 N m: the seal's friction torque, sliding and static alike.</li>
<li>45 t, 6 m, 41 t, 25 cm, 4.5 m: motor mass, propeller diameter, propeller mass, shaft diameter and length; not used by
the torsional model (they agree with the stiffness and inertia: a steel shaft of 25 cm, 4.5 m with a 12 cm bore has
K = 6.5e6 N m/rad).</li>
<li>Derived: k = (U + sqrt(U<sup>2</sup> - 4 w R T)) / (2 w) = 53.63 V s/rad from the rated point (U = R I + k w, T = k I),
I_rated = 3263 A; a = T_rated / w_rated<sup>2</sup> = 1108 N m s<sup>2</sup>/rad<sup>2</sup> (the propeller absorbs the rated torque
at the rated speed; with the seal and bearings the steady state at 700 V is 12.543 rad/s, 3421 A).</li>
</ul>
<h3>Results with the defaults</h3>
<ul>
<li>Maximal transient shaft torque: -1.2667e6 N m at 401.51 s, 7.24x the rated torque (an independent Radau solution agrees to 2e-12).</li>
<li>The propeller reverses (-5.9 rad/s), the seal slips both ways and sticks for good at 420.6 s: 8 seal events in 600 s.</li>
<li>Activity over 400-600 s: propeller inertia 39.7 %, armature inductance 32.7 %, armature resistance 21.2 %, propeller
load 4.2 % (together 97.7 %); motor inertia, seal, shaft stiffness, shaft damping and bearings below 1 % each. The
transient is an electromechanical oscillation between the inductance and the propeller inertia (0.98 rad/s, 20 % damped).</li>
</ul>
<h3>Structural parameters</h3>
<ul>
<li><code>model_reduction</code> = 1: only the elements covering 95 % of the short-circuit activity (R, L, propeller inertia
and load): L di/dt = U - R i - k w, J_p dw/dt = k i - a w |w|, the shaft carries k i. Peak -1.3014e6 N m (+2.7 %).</li>
<li><code>voltage_from_input</code> = true: the supply is the input <code>U_supply_in</code> instead of the built-in profile.</li>
</ul>
<p>Integer locals: <code>seal_mode</code> (1 slipping forwards, 0 stuck, -1 backwards) and <code>state_events</code> (zero crossings handled).
Solver: explicit Runge-Kutta (the fastest mode, the shaft's 47 rad/s, is not stiff). Contract: docs/shaft-line-spec.md.</p>
"#;
