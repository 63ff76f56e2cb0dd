//! The model's page in documentation/index.html (the runtime adds the variable tables).

pub const HTML: &str = r#"
<p>The guideline example of chapter 3 (sections 3.1-3.3): the start-up of the electric fan at the top of a
cooling tower (Figure 3.2). An induction motor drives, through a driveshaft on the high-speed side, a reducer
and the fan blades. The question is the torque the reducer sees during the start.</p>
<h3>Equations</h3>
<ul>
<li>Motor inertia: J_motor dw_m/dt = T_m - T_shaft.</li>
<li>Driveshaft: d(theta)/dt = w_m - N w_fan; T_shaft = K_shaft theta + D_shaft (w_m - N w_fan).</li>
<li>Reducer (ratio N, efficiency eta): T_low = N eta T_shaft when the power flows to the fan, N T_shaft / eta when it flows back. With an elastic shaft the direction is the discrete mode <code>reducer_power_flow</code>, switched at the state event where the power T_shaft N w_fan crosses zero (indicator <code>reducer_power_reversal</code>; 4 such events in the direct start's run-up), so the solver never steps across the efficiency's kink.</li>
<li>Fan: J_fan dw_fan/dt = T_low - k_fan w_fan |w_fan|. Seen from the motor: J_fan / N<sup>2</sup> = 11.72 kg m<sup>2</sup> (eqs. 3.4-3.7).</li>
<li>Motor torque, levels a-c: the steady-state T-equivalent circuit (R_s, L_s_sigma, L_m, L_r_sigma, R_r/s);
level d: the dq model, stator and rotor fluxes in the synchronous frame, T = 3/2 p (psi_sd i_sq - psi_sq i_sd).
Its steady state is the circuit's, so all levels settle to the same speed and torque.</li>
</ul>
<h3>Structural parameters</h3>
<ul>
<li><code>level</code>: 1 = a (quasi-static: torque balance only), 2 = b (+ motor and fan inertias), 3 = c (+ driveshaft
elasticity), 4 = d (+ electrical dynamics). Unused states stay frozen at their start values.</li>
<li><code>start_mode</code>: 1 = direct on line; 2 = PI speed control through a converter (the torque follows the
PI command, limited to T_limit, with anti-windup by back-calculation: while clamped, the integral is driven by the
clamped excess over Ki_speed T_tracking; where the raw command reaches the limit, the state event of
indicator <code>pi_torque_limit</code> switches the mode <code>pi_limit</code>, so the solver stops at the corner); 3 = inverse simulation (the motor speed is the set point, the
torque is what that takes). The set point ramps from 0 to speed_setpoint in ramp_time (10 s), optionally through a
second-order filter (<code>setpoint_filter</code>: 0 off, 1 below, 2 above the 1.4 Hz resonance, Figure 3.13).
In controlled starts the motor is converter-fed: level d's electrical dynamics are not used, the power drawn is
the mechanical power and the current that of the machine at rated flux giving that torque.</li>
<li><code>keep_shaft_stiffness</code> = false: a rigid shaft at levels c and d (the reduced model, Figure 3.10).</li>
</ul>
<h3>Values and their sources</h3>
<ul>
<li>From the chapter: J_motor = 1.72 kg m<sup>2</sup>; fan inertia on the high-speed axis 11.72 kg m<sup>2</sup>;
shaft resonance with the motor speed imposed sqrt(K/J_eq)/2&pi; = 1.4 Hz (eq. 3.8), hence K_shaft = 906.85 N m/rad;
50 Hz network; 10 s ramp.</li>
<li>Chosen (the chapter gives no motor data): a 160 kW, 400 V, 4-pole motor, R_s = 12 m&Omega;, R_r = 20 m&Omega;,
L_s_sigma = L_r_sigma = 0.25 mH, L_m = 10 mH: 160 kW at 2.3 % slip (1042 N m at 153.5 rad/s, 265 A), breakdown torque
2.8 times rated at 12.9 % slip, locked-rotor torque 0.74 and current 5.5 times rated. (A single-cage circuit cannot
give both a catalogue motor's 1 % slip and its 2x locked-rotor torque, which deep rotor bars provide; R_r trades one for
the other.) Reducer N = 10, eta = 0.97, so J_fan = 1172 kg m<sup>2</sup>. k_fan = 42.9 N m s<sup>2</sup>/rad<sup>2</sup>:
the fan takes the rated torque at the rated speed. D_shaft = 5 N m s/rad.
PI: Kp = 200 N m s/rad, Ki = 2000 N m/rad, T_limit = 2500 N m.</li>
<li>The 1.4 Hz resonance makes a soft driveshaft: about 1.1 rad of twist at rated torque.</li>
</ul>
<h3>Activity index</h3>
<p>A_i = &int; |e_i f_i| dt (eq. 3.3) for the motor inertia (J dw/dt w), the shaft stiffness (K theta dtheta/dt) and the fan
inertia, and each one's share of their sum in percent (Table 3.3): a small share marks an element the model can drop.</p>
"#;
