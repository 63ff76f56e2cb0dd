//! The model's page in documentation/index.html (the runtime adds the variable tables and
//! Table 3.1 of its elements).

pub const HTML: &str = r#"
<p>Chapter 3, section 3.4.2: the column-type electric power steering of a Renault Twingo (Figures 3.17-3.19,
Table 3.6). The driver turns the steering wheel; the torsion bar of the torque sensor twists in proportion to the
driver's torque; the assistance law turns that measured torque into a current command; a PI current loop drives the
assistance DC motor within the battery voltage; the motor turns the column through a worm gear; the pinion moves the
rack, which pulls the wheels about their pivots through the tie rods and the steering levers against the tires.</p>
<p><b>Defaults.</b> The mechanical part is the book authors' own steering model, Chap6_Steering.mo of their repository
(marcbudinger/MultiphysicsModelingTechSys): the driver's angle through a second-order filter (w = 10 rad/s, D = 1) and
a 10 000 N m/rad arm stiffness, the 0.023 kg m2 steering wheel, the pinion ratio 1/0.01 rad/m, the 0.1 m lever, the
tire of Figure 3.19 (rim 1 kg m2, tire 3000 N m/rad and 28 N m s/rad, tread 0.1 kg m2, 80 N m of friction on the
ground, a 7.95 N m/rad kingpin return), the mission (one steering-wheel turn each way at 1/16 Hz, a parking
manoeuvre). The torsion bar is the book's torque sensor (Chap3_TorqueSensor.mo, 100 N m/rad). The assistance has no
book file: its values are argued in docs/power-steering-spec.md.</p>
<h3>Equations</h3>
<ul>
<li>Driver (driver_input = 1): T_d = K_arm (theta_ref - theta_sw), theta_ref'' = w^2 (profile - theta_ref) - 2 D w theta_ref';
(driver_input = 2): T_d = torque_in.</li>
<li>Steering wheel: J_sw theta_sw'' = T_d - T_bar, T_bar = K_torsion_bar (theta_sw - theta_c), the measured torque.</li>
<li>Assistance law: i_ref = clamp(assist_gain T_bar / (N eta_f k), +/- I_max). Current loop: u = clamp(Kp e + Ki integral,
+/- U_battery), e = i_ref - i, anti-windup by tracking.</li>
<li>Motor (eq. 3.9): L di/dt = u - R i - k N w_c; its rotor turns at N w_c (worm ratio N).</li>
<li>Column, worm wheel, pinion, rack and the motor's rotor move as one: with e = eta_f while the motor drives the column,
1/eta_b while the column drives the motor, (J_c + m_r r^2 + e N^2 J_m) w_c' = T_bar - r F + N e (k i - b N w_c).</li>
<li>Tie rods (both): F = 2 K_rod (r theta_c - b delta). Wheels: 2 J_rim delta'' = b F - T_tire - 2 K_gr delta,
T_tire = 2 K_tire (delta - delta_t) + 2 D_tire (delta' - delta_t').</li>
<li>Treads: stuck (delta_t' = 0) while |T_tire| &lt;= 2 T_friction, else 2 J_tread delta_t'' = T_tire - 2 T_friction sign.
The worm's power direction, the treads' sticking and both saturations are modes with state events.</li>
</ul>
<h3>Table 3.6: the Modelica diagram's components, here</h3>
<table>
<tr><th>physical component</th><th>here</th></tr>
<tr><td>steering wheel</td><td>inertia J_steering_wheel, driven by the driver's angle through K_arm (or a torque)</td></tr>
<tr><td>torque sensor</td><td>torsion bar K_torsion_bar; its torque is the measured one</td></tr>
<tr><td>assistance motor (c)</td><td>DC motor: R, L, k (eq. 3.9), J_motor, b_motor; PI current loop</td></tr>
<tr><td>reducer</td><td>worm gear N, eta_f, eta_b (a transformer and a dissipation)</td></tr>
<tr><td>rack and pinion</td><td>transformer r_pinion, rack mass m_rack</td></tr>
<tr><td>tie rod, wheel pivot, tire (h, Figure 3.19)</td><td>tie-rod stiffness, lever b, rim inertia, tire stiffness and damping, tread inertia and ground friction, kingpin return</td></tr>
</table>
"#;
