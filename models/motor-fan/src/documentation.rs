//! The model's page in documentation/index.html (the runtime adds the variable tables).

pub const HTML: &str = r#"
<p>The guideline example of chapter 3 (sections 3.1-3.3): the start-up of the electric fan at the top of a
cooling tower (Figure 3.2). An induction motor drives, through a driveshaft on the high-speed side, a reducer
and the fan blades. The question is the torque the reducer sees during the start.</p>
<h3>Equations</h3>
<ul>
<li>Motor inertia: J_motor dw_m/dt = T_m - T_shaft.</li>
<li>Driveshaft: d(theta)/dt = w_m - N w_fan; T_shaft = K_shaft theta + D_shaft (w_m - N w_fan).</li>
<li>Reducer (ratio N, efficiency eta): T_low = N eta T_shaft when the power flows to the fan, N T_shaft / eta when it flows back. With an elastic shaft the direction is the discrete mode <code>reducer_power_flow</code>, switched at the state event where the power T_shaft N w_fan crosses zero (indicator <code>reducer_power_reversal</code>; 54 such events in the direct start's run-up with the book's values), so the solver never steps across the efficiency's kink.</li>
<li>Fan: J_fan dw_fan/dt = T_low - T_fan_nominal (w_fan / speed_fan_nominal)<sup>2</sup>, against the rotation. Seen from the motor: J_fan / N<sup>2</sup> = 11.72 kg m<sup>2</sup> (eqs. 3.4-3.7).</li>
<li>Motor torque, levels a-c: the book's torque-speed table (<code>motor_model</code> = 1: ten points
<code>motor_table_speed_i</code>, <code>motor_table_torque_i</code>, read linearly at levels a and b and by Akima's spline at c
as the book's files do, <code>motor_table_interpolation</code>; beyond its ends a straight line), or the steady-state
T-equivalent circuit (<code>motor_model</code> = 2: R_s, L_s_sigma, L_m, L_r_sigma, R_r/s, per winding, star or delta);
level d: the circuit's dq model, stator and rotor fluxes in the synchronous frame, T = 3/2 p (psi_sd i_sq - psi_sq i_sd).
The book's circuit gives the table's torque within 9 N m, so the levels settle within 0.12 % of each other
(300.46, 300.56, 300.80 rad/s). The current and power are always the circuit's (the winding current).</li>
</ul>
<h3>Structural parameters</h3>
<ul>
<li><code>level</code>: 1 = a (quasi-static: torque balance only), 2 = b (+ motor and fan inertias), 3 = c (+ driveshaft
elasticity), 4 = d (+ electrical dynamics). Unused states stay frozen at their start values.</li>
<li><code>start_mode</code>: 1 = direct on line; 2 = PI speed control through a converter (the torque follows the
PI command through the second-order torque actuator <code>actuator_angular_frequency</code>, <code>actuator_damping</code>
(0 = no lag), limited to T_limit (0 = no limit, the book's), with anti-windup by back-calculation: while clamped, the integral is driven by the
clamped excess over Ki_speed T_tracking; where the raw command reaches the limit, the state event of
indicator <code>pi_torque_limit</code> switches the mode <code>pi_limit</code>, so the solver stops at the corner); 3 = inverse simulation (the motor speed is the set point, the
torque is what that takes). The set point ramps from 0 to speed_setpoint in ramp_time (10 s), through a second-order filter
(<code>setpoint_filter</code>: 0 off, 1 below (the book's, on by default), 2 above the 1.4 Hz resonance, Figure 3.13).
In controlled starts the motor is converter-fed: level d's electrical dynamics are not used, the power drawn is
the mechanical power and the current that of the machine at rated flux giving that torque.
Co-Simulation tolerance floor: 1e-12 for the direct start, the imposed speed and the PI start without the actuator's lag; none for
the PI start through the lag (a tighter tolerance there only lets round-off set the steps: give it the tolerance you want, e.g. 1e-8,
rather than the DefaultExperiment's 1e-12, which is the direct start's).</li>
<li><code>keep_shaft_stiffness</code> = false: a rigid shaft at levels c and d (the reduced model, Figure 3.10). It drops
the element with the least activity among the storage elements of the controlled start: the shaft stiffness, 0.301 % of their
activity with the PI start and 9.01 % direct-on-line (Table 3.3, level c, 30 s). What that costs in the peak shaft torque:
with the PI start 798.0 N m rigid against 795.9 N m elastic (+0.3 %); direct-on-line 983.0 against 4503.1 N m (-78 %), so
the reduction holds for the controlled start only (README, Figure 3.10).</li>
</ul>
<h3>Values and their sources</h3>
<p>The defaults are the book authors' own model, book file Chap3_CoolingTowerFan.mo (repository
marcbudinger/MultiphysicsModelingTechSys), each parameter's description naming its component:</p>
<ul>
<li>Motor (levels a-c): the table TorqueSpeed, 454 N m at standstill, 1071 N m at 250 rad/s, 500 at 300, 0 at 314 rad/s;
J_motor = 1.72 kg m<sup>2</sup> (inertia_motor). Its circuit (level d and the current): the book's induction machine of the
result file Transient_InductionMachine_graphic.mat, R_s = R_r = 0.038 &Omega;, L_s_sigma 0.2 mH, L_r_sigma 0.4 mH,
L_m 12 mH, one pole pair, delta windings on 230 V, 50 Hz.</li>
<li>Reducer N = 16, eta = 0.94 both ways (lossyGear); J_fan = 3000 kg m<sup>2</sup> (inertia_fan); fan 7742.6 N m at
19.373154697137 rad/s (quadraticSpeedDependentTorque); shaft K = 866 N m/rad, D = 866/100/sqrt(886/1.7) = 0.3793 N m s/rad
(spring; the file writes 886).</li>
<li>PI start (Transient_SpeedControler): 0 to 300 rad/s in 10 s (timeTable), filter 2*3.14*0.5 rad/s, D = 1
(secondOrder1: filter_frequency_below = 0.49975 Hz, the file's pi being 3.14), PI k = 10000, T = 0.1
(Kp_speed 10000, Ki_speed 100000), no limit, torque actuator 2*3.14*800 rad/s, D = 1 (secondOrder).</li>
<li>Values easy to get wrong when setting the book's case by hand: filter_frequency_below is 0.5*3.14/pi Hz, not 0.5;
Ki_speed is k/T = 100000, not T; U_supply is the line voltage of delta windings (230 V), not a star's 398 V;
the Activity_Index_controller file ramps over 20 s (ramp_time = 20), while the chapter's Table 3.3 is the 10 s ramp's.</li>
<li>The project's first set (a chosen 160 kW 4-pole motor by its circuit, N = 10, eta 0.97, J_fan 1172, K 906.85,
D 5, k = 42.9 N m s<sup>2</sup>/rad<sup>2</sup>, Kp 200, Ki 2000, T_limit 2500, no lag, no filter, 153.5 rad/s) is reachable
through parameters: docs/motor-fan-spec.md, "The first set".</li>
</ul>
<h3>Activity index</h3>
<p>A_i = &int; |e_i f_i| dt (eq. 3.3) for the motor inertia (J dw/dt w), the shaft stiffness (K theta dtheta/dt) and the fan
inertia, and each one's share of their sum in percent (Table 3.3): a small share marks an element the model can drop.</p>
"#;
