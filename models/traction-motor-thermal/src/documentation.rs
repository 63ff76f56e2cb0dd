//! The model's page in documentation/index.html (the runtime adds the variable tables).

pub const HTML: &str = r#"
<p>Chapter 3, section 3.5.1: the AGV motor cars of the V150 record train (574.8 km/h, 3 April 2007) have
permanent-magnet synchronous traction motors of 700 kW nominal, overloaded to 1 MW for the record. How long
can the winding insulation take it? Nominal point (chapter): C_nom = 1400 N m at 4800 rpm, Joule losses
P_J,nom = 5 kW, winding 140 K above a 40 &deg;C ambient.</p>
<h3>Hand figures (questions 1 and 2)</h3>
<ul>
<li>Overload torque at the same maximal speed: C = 1 MW / (4800 &times; 2&pi;/60 rad/s) = 1989.4 N m.</li>
<li>Torque is proportional to current, Joule losses to its square: P_J = 5 kW &times; (1989.4/1400)<sup>2</sup> = 10.10 kW.</li>
<li>Motor-to-air conductance from the nominal point: G = 5 kW / 140 K = 35.71 W/K (the book file: 1 / 0.0279 K/W =
35.84 W/K). Steady overload rise: 10.10 kW / 35.71 W/K = 282.7 K, a winding at 322.7 &deg;C if the overload lasted
(the book file's 10 kW: 279 K).</li>
</ul>
<h3>Equations (question 3)</h3>
<ul>
<li>One node (<code>nodes</code> = 1): C_total dT/dt = P_J - G_total (T - T_ambient).</li>
<li>Two nodes (<code>nodes</code> = 2, Figure 3.23): C_winding dT_w/dt = P_J - G_wi (T_w - T_iron);
C_iron dT_iron/dt = G_wi (T_w - T_iron) - G_ia (T_iron - T_ambient). The Joule losses heat the copper; the slot
insulation (G_wi) separates it from the iron core, which the cooling air (G_ia) cools.</li>
<li>Both levels share C_total = C_winding + C_iron; with <code>thermal_data</code> = 2 also 1/G_total = 1/G_wi + 1/G_ia,
hence the same steady states (with the book file's values, 0.13 % apart: see below). They differ in how fast the
winding heats.</li>
</ul>
<h3>Parameter values (question 4): the book's own file</h3>
<p>The defaults are the values of the authors' Modelica file behind this problem,
<code>Chap3_TGV_Modelisation_Thermique.mo</code> (repository marcbudinger/MultiphysicsModelingTechSys, <code>files/</code>;
parameter values only, no code carried over), and the default experiment is that file's: a cold motor (40 &deg;C),
a step of the Joule losses at t = 0, 10 000 s, results every 20 s.</p>
<ul>
<li>Two nodes (model ModeleTGV_2): copper <code>m_winding</code> = 50 kg &times; <code>c_winding</code> = 385 J/(kg K)
(heatCapacitor, C_winding = 19 250 J/K); iron <code>m_iron</code> = 170 kg &times; <code>c_iron</code> = 444 J/(kg K)
(heatCapacitor1, C_iron = 75 480 J/K); the slot insulation as a layer, R = e / (&lambda; A) with
<code>e_insulation</code> = 0.6 mm, <code>lambda_insulation</code> = 0.14 W/(m K), <code>A_insulation</code> = 0.54 m<sup>2</sup>
(RthCuivre, R = 7.937 mK/W, G_wi = 126.0 W/K); convection to the air R = 1 / (1 &times; 50), read as
<code>A_cooling</code> = 1 m<sup>2</sup> and <code>h_cooling</code> = 50 W/(m<sup>2</sup> K) (RthFer, G_ia = 50 W/K).</li>
<li>One node (model ModeleTGV_1): the same total capacity, 94 730 J/K (CapaThEq), and its own resistance
<code>R_one_node</code> = 0.0279 K/W (ResistanceThEq). The two-node path in series is 0.027937 K/W: the file's two models
differ by 0.13 % there, and each level here uses its own model's value. The chapter's nominal point (140 K at 5 kW)
would be 0.0280 K/W; the file's 0.0279 gives 139.5 K.</li>
<li>The loss step: <code>heat_source</code> = 4 with <code>P_joule_step</code> = 10 000 W, the file's record run
("Fonctionnement record du monde"); its normal-service run steps 5 000 W. The text's route (questions 1-2: 1 MW at
4800 rpm, hence 1989.4 N m and 10.10 kW) is <code>heat_source</code> = 1; the file rounds it to 10 kW, and its curves
are the default.</li>
<li>Time constants: one node C/G = 2643 s (44 min); two nodes: the winding behind its insulation C_winding/G_wi =
153 s, the iron C_iron/G_ia = 1510 s.</li>
<li>Easy to get wrong by hand: the cooling written 1 / (1 &times; 50) is h A = 50 W/K, not 1 W/K; the one-node R is
0.0279, not the two-node sum.</li>
<li>This project's first set (before the book file was read) stays reachable: <code>thermal_data</code> = 2 derives the
conductances from the nominal point, G = P_J,nom / <code>dT_winding_nominal</code> (140 K), split by
<code>dT_winding_iron_nominal</code> = 60 K across the insulation; with <code>m_winding</code> = 80 kg,
<code>m_iron</code> = 620 kg, <code>c_iron</code> = 460 J/(kg K) (a 700 kg motor, about 1 kg per kW) and
<code>heat_source</code> = 1 it gives 6049 s (one node) and 1407 s (two nodes) to the limit. It shows how much the
answer rests on the mass counted as heating with the winding: the book's 220 kg reach the limit 3.3 times sooner
(one node) than a whole 700 kg motor.</li>
</ul>
<h3>What the models answer (questions 5 and 6)</h3>
<p>From cold, the time for the winding to reach the insulation limit (default 180 &deg;C, the chapter's nominal winding
temperature, 40 &deg;C + 140 K) is the output <code>time_to_limit</code>:</p>
<ul>
<li>10 kW record, one node: closed form t = -&tau; ln(1 - 140 K / 279 K) = 1841.5 s (30.7 min);</li>
<li>10 kW record, two nodes: 979.2 s (16.3 min): the copper's small heat capacity heats quickly behind the insulation
before the iron has moved. The one-node model is the least conservative: it promises 1.9 times the time the winding
really has.</li>
<li>5 kW in normal service: both stay below the limit (176.33 &deg;C and 179.04 &deg;C at 10 000 s, tending to 179.50
and 179.68 &deg;C).</li>
</ul>
<p>These curves match the book's own result files (ModeleTGV_1.mat, ModeleTGV_2.mat) within 0.6 mK at 100, 1000,
2000, 5000 and 10 000 s (tests/python/test_traction_motor_thermal.py). Starting from the nominal steady state
(<code>initial_state</code> = 2) the winding sits at 179.5 &deg;C (one node) or 179.68 &deg;C (two nodes), just below
the limit: that start answers "how hot after t seconds of overload from service", not "how long until the limit".</p>
<h3>Outputs</h3>
<ul>
<li><code>T_winding</code>, <code>T_iron</code> (K; equal in the one-node model), <code>margin_to_limit</code> =
T_insulation_limit - T_winding.</li>
<li><code>time_to_limit</code>: the time from the start of the simulation at which the winding first reached the
limit, latched (it does not move if the winding cools again); while <code>limit_reached</code> = 0 it is the time
elapsed so far, a lower bound. The limit is a state event: the event indicator T_insulation_limit - T_winding
crosses zero there, located inside <code>fmi2DoStep</code> in Co-Simulation and by the master's root finder in
Model Exchange, and the discrete mode <code>limit_latch</code> is set at that instant. <code>time_to_limit</code>
is a state growing at 1 s/s until the latch is set (a constant rate, integrated exactly), so it stops at the
event time itself, whatever the communication step.</li>
<li><code>limit_reached</code>: the latch (0 or 1), a discrete output: it changes only at the event, never before
the winding reaches the limit.</li>
<li><code>torque</code> and <code>P_joule</code>: the load. <code>heat_source</code> = 2 takes the torque from the
input <code>torque_in</code> (another FMU's torque output, P_J = P_J,nom (C/C_nom)<sup>2</sup>, both signs heat),
3 takes the losses directly from <code>P_joule_in</code>, 4 (the default) steps them to <code>P_joule_step</code> at
<code>t_step</code> (the output <code>torque</code> is then the torque that gives them, C_nom (P_J / P_J,nom)<sup>1/2</sup>).</li>
</ul>
"#;
