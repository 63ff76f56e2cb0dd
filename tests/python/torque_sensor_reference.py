"""Hand computations for the TorqueSensor model (docs/torque-sensor-spec.md; chapter 3, section 3.5.2).

Everything here is computed with numpy from the spec's formulas and the FMU's own parameter values
(the start values of modelDescription.xml, possibly overridden by a test); nothing comes from a run of
the FMU.

* Question 4 (iron of infinite permeability): a flux crossing the cylindrical air gap between r1 and
  r2 over the width b sees H(r) = flux / (mu0 2 pi r b), so the gap's mmf is flux ln(r2/r1) / (2 pi mu0 b);
  the flux crosses two such gaps (into the ring and back to the yoke), so
      L_q4 = N^2 / (2 ln(r2/r1) / (2 pi mu0 b)) = pi mu0 b N^2 / ln(r2/r1),   mu0 = 4 pi 1e-7 (chapter).
* With the iron (mu_r_iron over iron_path_length, section 2 pi r1 b) in series:
      L_A = N^2 / (2 R_gap + l_iron / (mu0 mu_r 2 pi r1 b)).
* Ring B adds the toothed gap: section teeth * (rest_overlap + twist) * tooth_radius * tooth_length,
  length tooth_gap: L_B(twist) = N^2 / (R_A + tooth_gap / (mu0 section)). Twist = torque / K (within the stops).
  With arrangement = 2 (differential) ring A's circuit crosses the same toothed gap at the opposite twist.
* Voltage step U on a winding alone (R_bridge = 0, question 5): i(t) = U/R (1 - exp(-t R / L)).
* Steady state under the carrier U sin(w t) (phasors, the supply as the phase reference):
      I_X = U / (R_bridge + R_winding + j w L_X),   B = R_bridge (I_B - I_A)   (bridge voltage),
  the multiplier's product B sin(wt + arg B) sin(wt) has the mean Re(B)/2, and the filter has unit
  gain at DC, so the demodulated voltage settles (up to its 2w ripple) at u(T) = Re(B(T)) / 2.
"""

from __future__ import annotations

import math

import numpy as np

MU0 = 4e-7 * math.pi  # the chapter's value, question 4


def question4_inductance(N: float, r1: float, r2: float, b: float) -> float:
    return math.pi * MU0 * b * N**2 / math.log(r2 / r1)


def gap_reluctance(p: dict) -> float:
    return math.log(p["r2"] / p["r1"]) / (2 * math.pi * MU0 * p["b"])


def reluctance_a(p: dict) -> float:
    iron = p["iron_path_length"] / (MU0 * p["mu_r_iron"] * 2 * math.pi * p["r1"] * p["b"])
    return 2 * gap_reluctance(p) + iron


def inductance_a(p: dict, torque=0.0, arrangement: int = 1):
    if arrangement == 2:
        return p["N"] ** 2 / (reluctance_a(p) + teeth_reluctance(p, -twist(p, torque)))
    return p["N"] ** 2 / reluctance_a(p)


def twist(p: dict, torque):
    return np.clip(np.asarray(torque, dtype=float) / p["K_torsion_bar"], -p["twist_stop"], p["twist_stop"])


def teeth_reluctance(p: dict, twist_rad):
    section = p["teeth"] * (p["rest_overlap"] + twist_rad) * p["tooth_radius"] * p["tooth_length"]
    return p["tooth_gap"] / (MU0 * section)


def inductance_b(p: dict, torque):
    return p["N"] ** 2 / (reluctance_a(p) + teeth_reluctance(p, twist(p, torque)))


def step_current(U: float, R: float, L: float, t):
    return U / R * (1 - np.exp(-np.asarray(t) * R / L))


def steady_demodulated(p: dict, torque, arrangement: int = 1):
    """u(T) = Re(R_bridge (I_B - I_A)) / 2 (phasors), V."""
    w = 2 * math.pi * p["f_supply"]
    r = p["R_bridge"] + p["R_winding"]
    i_a = p["U_supply"] / (r + 1j * w * inductance_a(p, torque, arrangement))
    i_b = p["U_supply"] / (r + 1j * w * inductance_b(p, torque))
    return 0.5 * np.real(p["R_bridge"] * (i_b - i_a))


def line_fit(x, y):
    """Least-squares straight line: (slope, intercept, largest |deviation|)."""
    slope, intercept = np.polyfit(x, y, 1)
    return float(slope), float(intercept), float(np.max(np.abs(y - (slope * x + intercept))))
