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
<li>Motor-to-air conductance from the nominal point: G = 5 kW / 140 K = 35.71 W/K. Steady overload rise:
10.10 kW / 35.71 W/K = 282.7 K, i.e. a winding at 322.7 &deg;C if the overload lasted.</li>
</ul>
<h3>Equations (question 3)</h3>
<ul>
<li>One node (<code>nodes</code> = 1): C_total dT/dt = P_J - G_total (T - T_ambient).</li>
<li>Two nodes (<code>nodes</code> = 2, Figure 3.23): C_winding dT_w/dt = P_J - G_wi (T_w - T_iron);
C_iron dT_iron/dt = G_wi (T_w - T_iron) - G_ia (T_iron - T_ambient). The Joule losses heat the copper; the slot
insulation (G_wi) separates it from the iron core, which the cooling air (G_ia) cools.</li>
<li>Both levels share C_total = C_winding + C_iron and 1/G_total = 1/G_wi + 1/G_ia, hence the same steady states:
they differ only in how fast the winding heats.</li>
</ul>
<h3>Parameter values (question 4) and their reasoning</h3>
<ul>
<li>Conductances come from the nominal point: G_total = 5 kW / 140 K. The two-node split needs one more figure,
the part of the 140 K that drops across the slot insulation; we take <code>dT_winding_iron_nominal</code> = 60 K
(G_wi = 83.3 W/K) and 80 K from iron to air (G_ia = 62.5 W/K). In forced-ventilated machines with class-H
insulation the drop across the slot liner and impregnation is typically a third to a half of the winding rise;
60 K of 140 K sits in that range. It is a parameter so a user with better data can change it.</li>
<li>Masses: a forced-ventilated traction motor of this class weighs about 1 kg per kW, so we take 700 kg in all.
The copper winding is about 11 % of it, <code>m_winding</code> = 80 kg (specific heat 385 J/(kg K)): C_winding =
30.8 kJ/K. The rest, <code>m_iron</code> = 620 kg of stator laminations, rotor with magnets, shaft and frame, is
counted as steel (460 J/(kg K)): C_iron = 285.2 kJ/K. C_total = 316 kJ/K.</li>
<li>Time constants: one node C_total/G_total = 8848 s (2.46 h); two nodes: the winding alone behind its insulation
C_winding/G_wi = 370 s, the iron C_iron/G_ia = 4563 s.</li>
</ul>
<h3>What the models answer (questions 5 and 6)</h3>
<p>The overload step is applied at t_step (default 0) to a cold motor (<code>initial_state</code> = 1: winding and
iron at the ambient temperature). The time for the winding to reach the insulation limit (default 180 &deg;C,
the nominal steady winding temperature) is the output <code>time_to_limit</code>:</p>
<ul>
<li>one node: closed form t = -&tau; ln(1 - 140 K / 282.7 K) = 0.684 &tau; = 6049 s (101 min);</li>
<li>two nodes: about 1407 s (23 min): the copper's small heat capacity heats quickly behind the insulation
before the iron has moved. The one-node model is the least conservative: it promises four times the time the
winding really has.</li>
</ul>
<p>Starting from the nominal steady state (<code>initial_state</code> = 2) the winding already sits at 180 &deg;C,
the default limit, so <code>time_to_limit</code> is 0 there: that start answers "how hot after t seconds of
overload from service", not "how long until the limit". Which initial state each output assumes is the one the
parameter selects; the outputs themselves do not change meaning.</p>
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
3 takes the losses directly from <code>P_joule_in</code>.</li>
</ul>
"#;
