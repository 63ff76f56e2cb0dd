//! The model's page in documentation/index.html (the runtime adds the variable tables, Table 3.1
//! of the declared elements, which is the chapter's Table 3.7 here, and the activities of the
//! default experiment).

pub const HTML: &str = r#"
<p>Chapter 3, section 3.4.3, Figure 3.20: the common-rail direct injection system of a four-cylinder passenger-car
diesel engine. A low-pressure (boost) pump feeds a high-pressure radial-piston pump driven by the engine; the pump
fills the rail, a hydraulic accumulator that is the high-pressure fuel reserve of the injectors; a spring-loaded
pressure-control valve returns the excess to the tank; one electrically commanded injector per cylinder sprays into
the combustion chamber, fired in the engine's order. The chapter asks for Table 3.7, the domains and effects of each
component, for a model that answers one question: <b>how stable is the rail pressure?</b> Table 3.7 is the table of
elements below, generated from the model's declarations (with the effects it leaves out and why).</p>

<h3>Equations</h3>
<ul>
<li><b>Crank and firing order.</b> d theta/dt = w_engine (input <code>engine_speed</code>). Slot j of the firing order
(cylinders 1-3-4-2 for four; 1-2-4-5-3 for five, 1-5-3-6-2-4 for six) fires at theta = j 4 pi / n; its injector starts
energizing <code>injection_advance</code> before, a state event on the crank angle (Integer local <code>firing_slot</code>).
At each start the shot's timer restarts, the energizing time is latched from <code>energizing_time</code> (0 .. 3 ms)
and the last shot's volume is latched. The run starts 1 degree after cylinder 1's start of injection.</li>
<li><b>High-pressure pump</b> (three plungers on an eccentric e, area A_p, shaft at r theta + phase): plunger k sits
at e (1 - cos phi_k), phi_k = r theta + phase - 2 pi k / 3, and with ideal check valves delivers A_p e r w sin phi_k into
the rail while it rises (a state event at each dead centre: Integer locals <code>plunger_k_delivering</code>) and fills
from the boost pump at p_feed while it falls. Mean delivery 6 e A_p r w / 2 pi; torque on the crankshaft
r A_p e sum_k p_k sin phi_k.</li>
<li><b>Rail</b>: C(p) dp/dt = Q_pump - Q_injection - Q_relief - p / R_leakage - A_seat v, with C(p) = V_rail / B(p) and
B(p) = B_fuel_0 + dB_fuel_dp p (Table 3.2's hydraulic capacitance with a pressure-dependent bulk modulus); it stores
E(p) = V / K' (p - B0 / K' ln(1 + K' p / B0)) at the rate p Q_net.</li>
<li><b>Pressure-control valve</b> (a ball of mass m on a seat of area A = pi d^2 / 4, a spring k with preload F_0, a damper
c, a solenoid): m dv/dt = A p - F_0 - k x - c v - F_sol, dx/dt = v, lifted (Integer local <code>valve_open</code>); seated,
x = v = 0 until A p reaches F_0 + F_sol (a state event), and it lands (an inelastic impact, a state event) when its lift
returns to 0 under a closing net force. The solenoid adds F_sol = max(A p_set - F_0, 0), so that the
<b>opening pressure (F_0 + F_sol) / A</b> is the set point (input <code>rail_pressure_set_point</code>), or the spring's
own F_0 / A below it. Flow to the tank Q_relief = Cd pi d x sqrt(2 p / rho) (the curtain area follows the lift).</li>
<li><b>Injector</b> (servo-hydraulic, its actuator reduced to its timing): the needle leaves its seat
<code>opening_delay</code> after the start of energizing, rises at <code>needle_opening_speed</code> to its stop at
<code>needle_lift_max</code>, starts closing <code>closing_delay</code> after the end of energizing and lands at
<code>needle_closing_speed</code>: a trapezoid whose four kinks are <b>time events</b> located inside fmi2DoStep. The
nozzle is the needle's seat gap (pi d_seat h sin(alpha)) in series with the spray holes (n pi d_h^2 / 4), one sharp-edged
orifice law: Q = Cd A_eff sqrt(2 (p - p_cylinder) / rho), 1 / A_eff^2 = 1 / A_seat^2 + 1 / A_holes^2; the pressure drop
splits between seat and holes in the ratio of the inverse squared areas. dV_shot/dt = Q.</li>
</ul>
<p>Energy: the engine delivers r T w through the pump (p Q_pump - p_feed Q_fill), the boost pump p_feed Q_fill, the
solenoid -F_sol v; the rail stores p Q_net, the ball m v dv/dt and the spring (F_0 + k x) v; the valve's orifice takes
p Q_relief, its damper c v^2, the leakage p^2 / R, the needle seats and the holes their pressure drops times Q, and the
cylinder's charge takes p_cylinder Q (a source of negative power). <code>power_balance_relative</code> stays below 1e-15.</p>

<h3>Every value and its source</h3>
<p>The chapter gives none. A passenger-car system of the Bosch CP1/CP3 class at 2000 rpm, each value argued
(<code>docs/common-rail-spec.md</code> has the same table).</p>
<table>
<tr><th>parameter</th><th>default</th><th>argument</th></tr>
<tr><td>engine_speed</td><td>209.44 rad/s</td><td>2000 rpm, part load: the firing interval is 15 ms</td></tr>
<tr><td>cylinders</td><td>4</td><td>the four injectors of Figure 3.20; 5 and 6 (inline orders) are offered</td></tr>
<tr><td>injection_advance</td><td>4 degrees</td><td>start of the main injection a few degrees before firing TDC at part load</td></tr>
<tr><td>pump_ratio</td><td>2/3</td><td>three plungers and four cylinders: one delivery stroke per injection, the pump synchronous with
the injections; Mercedes' OM647 (Sprinter) drives its three-piston pump at about 1.3 times camshaft speed, 0.65 engine speed</td></tr>
<tr><td>plunger_diameter, eccentricity</td><td>6.5 mm, 3.5 mm</td><td>0.697 cm<sup>3</sup> per pump revolution: at 4000 rpm
(2667 pump rpm) 31 cm<sup>3</sup>/s, three times the 8 cm<sup>3</sup>/s of four 60 mm<sup>3</sup> full-load shots per
engine cycle, the margin a full-delivery (CP1-type) pump keeps for starting and leakage; at 2000 rpm it delivers
15.5 cm<sup>3</sup>/s</td></tr>
<tr><td>p_feed</td><td>0.3 MPa</td><td>the low-pressure circuit's few bar (an electric in-tank or a gear pump)</td></tr>
<tr><td>V_rail</td><td>20 cm<sup>3</sup></td><td>a forged rail with a 9 mm bore (BMW M57's) over 250 mm is 15.9 cm<sup>3</sup>, its four
injector lines (2.4 mm bore, 250 mm) 4.5 cm<sup>3</sup> more: the compromise between damping the pulsations and building
pressure fast at the start</td></tr>
<tr><td>B_fuel_0, dB_fuel_dp</td><td>1.5 GPa, 7.5</td><td>isentropic bulk modulus of diesel fuel: about 1.5 GPa near atmospheric
pressure at 20-40 degrees C (Tat and Van Gerpen, JAOCS 80, 2003, to 32 MPa; Boehman et al., Energy and Fuels 18, 2004),
rising with pressure, rho c<sup>2</sup> near 2.8 GPa at 180 MPa (speed of sound in diesel fuel to 180 MPa, Payri et al.,
Fuel 90, 2011); the line gives 2.61 GPa at the mean 149.5 MPa</td></tr>
<tr><td>rho (constant)</td><td>830 kg/m<sup>3</sup></td><td>EN 590: 820-845 kg/m<sup>3</sup> at 15 degrees C (the orifice laws' density;
a constant of the model, not a parameter)</td></tr>
<tr><td>R_leakage</td><td>2.9e14 Pa s/m<sup>3</sup></td><td>0.5 cm<sup>3</sup>/s at 145 MPa: the static leakage of four injectors'
guides and the pump's plungers, a few per cent of the pump's delivery</td></tr>
<tr><td>valve_seat_diameter, Cd_valve</td><td>0.6 mm, 0.7</td><td>the pressure-control valve's ball seat: 41 N hold 145 MPa, a
force a small solenoid gives; a sharp seat's discharge coefficient</td></tr>
<tr><td>F_spring_preload</td><td>2.83 N</td><td>the spring alone holds 10 MPa (Bosch's pressure-control valve: about 100 bar
without current)</td></tr>
<tr><td>k_valve, m_valve, c_valve</td><td>75 N/mm, 3 g, 15 N s/m</td><td>the ball, its armature and a third of the spring;
sqrt(k/m) / 2 pi = 796 Hz, damping ratio c / 2 sqrt(k m) = 0.5 (the armature in its fuel-filled chamber). k sets the
regulation's droop: 2.65 MPa per 10 um of lift</td></tr>
<tr><td>rail_pressure_set_point</td><td>145 MPa</td><td>rail pressures of 135-160 MPa at part and full load for CP1/CP3 systems;
the open-loop valve settles 4.5 MPa above it (its droop)</td></tr>
<tr><td>nozzle_holes, hole_diameter, Cd_nozzle</td><td>7, 0.13 mm, 0.75</td><td>passenger-car nozzles of 6-8 holes of 0.12-0.15 mm;
hydro-eroded holes: 39.7 mm<sup>3</sup>/ms at 140 MPa, full lift</td></tr>
<tr><td>needle_seat_diameter, needle_seat_half_angle</td><td>1.5 mm, 30 degrees</td><td>the seat gap equals the holes' area at
39 um of lift: the seat throttles only while the needle opens and closes</td></tr>
<tr><td>needle_lift_max, speeds</td><td>0.2 mm, 1.0 and 1.2 m/s</td><td>full lift in 0.2 ms, closing in 0.17 ms, set by the
control chamber's throttles</td></tr>
<tr><td>opening_delay, closing_delay</td><td>0.3 ms, 0.3 ms</td><td>the solenoid's current rise, the control valve's stroke and the
control chamber's pressure change</td></tr>
<tr><td>energizing_time</td><td>0.5 ms</td><td>24.3 mm<sup>3</sup> per shot at the rail's pressure: 20-30 mm<sup>3</sup> is a
part-load main injection of a 2 L engine</td></tr>
<tr><td>p_cylinder</td><td>6 MPa</td><td>the charge compressed near TDC at part load: 0.15 MPa (absolute) of boost times
17<sup>1.35</sup> is 6.9 MPa before injection; constant over the shot (its rise with combustion left out)</td></tr>
</table>

<h3>Results with the defaults (tests/python/test_common_rail.py)</h3>
<ul>
<li><b>Mean rail pressure</b>: the flow balance by hand (pump 15.485 cm<sup>3</sup>/s = injected 1.627 + relief 13.343 +
leakage 0.515 cm<sup>3</sup>/s at the valve's static lift) gives 1494.695 bar; the FMU's mean over a settled firing
interval is 1494.696 bar (5e-7). The valve regulates with a droop of 44.7 bar above the 1450 bar set point.</li>
<li><b>Ripple</b>: 32.6 bar peak to peak (2.2 % of the mean), each shot a 30 bar dip the valve and the pump refill in
about 2.5 ms (C / G = 7.63e-15 m<sup>3</sup>/Pa over 3.0e-12 m<sup>3</sup>/(s Pa)). Against the linearised accumulator
(closed form per harmonic) the first harmonic, 7.67 bar at 66.7 Hz, agrees to 6e-4 in amplitude and 3e-3 rad in phase;
the pump's own pulsation (three plungers: its first harmonic at 6 r w = 133 Hz, 0.88 cm<sup>3</sup>/s) is a quarter of
the injections' (3.2 cm<sup>3</sup>/s per harmonic). The injections make the ripple, the rail's C and the valve's
conductance set it: the corner frequency G / 2 pi C = 63 Hz is the injection frequency.</li>
<li><b>Shot</b>: 24.31 mm<sup>3</sup> (the nozzle law over the needle's trapezoid at the FMU's own pressure agrees to 2e-11);
0.4 % less than at the mean pressure, since each shot sprays into its own dip.</li>
<li><b>Valve opening</b>: the ball lifts between 99.9996 and 100.0007 bar with the spring alone (preload / area 100 bar)
and between 1499.9998 and 1500.0010 bar with a 1500 bar set point.</li>
<li>The whole trajectory agrees with scipy's DOP853 (rtol 1e-12, integrated from kink to kink) to 4e-10 of each output's
range.</li>
<li>The pump's hydraulic power is 2.3 kW at 2000 rpm, 86 % of it throttled by the valve: the reason later pumps (CP3)
meter their inlet instead.</li>
<li><b>Activities</b> (table below, the chapter's eq. 3.3 over the default experiment): among the storage elements the
rail's fuel takes 99.999 %; the valve's ball, spring and damper together less than 0.01 %: a reduced model may take the
valve as quasi-static (a pressure-dependent orifice whose lift follows (A p - F_0 - F_sol) / k), its 796 Hz mode being
far above the 66.7 Hz injections. Among the dissipations the valve's orifice takes 87 %, the nozzle holes 9 %, the needle
seats 1.2 %, the leakage 3.4 %.</li>
</ul>

<h3>Structural parameter, modes and solver</h3>
<p><code>cylinders</code> = 4 (default), 5 or 6. Integer locals: <code>firing_slot</code>, <code>plunger_1..3_delivering</code>,
<code>valve_open</code>, <code>state_events</code>. Shots may not overlap: the longest (3 ms of energizing with the delays and
the closing) must end before the next start of injection at 5000 rpm, checked at initialization. Solver: explicit
Runge-Kutta (the fastest mode, the ball on its spring at 796 Hz, is not stiff); tolerance floor 1e-6 (at looser
tolerances the needle seats' activity, a hump of power in each 0.2 ms ramp of the needle that the states' error control
steps across, was 68 x rtol of its range off at 1e-4). Contract: docs/common-rail-spec.md.</p>
"#;
