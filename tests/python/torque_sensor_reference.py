"""Hand computations for the TorqueSensor model (docs/torque-sensor-spec.md; chapter 3, section 3.5.2).

Everything here is computed with numpy/scipy from the spec's formulas and the FMU's own parameter values
(the start values of modelDescription.xml, possibly overridden by a test); nothing comes from a run of
the FMU or from the Rust code.

The book's circuits (sensor_data = 1; book file Chap3_TorqueSensor.mo): each part is a chain of flux tubes
in series, each tube's permeance the textbook one:
  * axial flux through a hollow cylinder (radii r_i..r_o, length l):   G = mu0 mu_r pi (r_o^2 - r_i^2) / l
  * radial flux through a hollow cylinder (radii r_i..r_o, width w):   G = 2 pi mu0 mu_r w / ln(r_o / r_i)
  part A: the yoke's shell (axial), two poles (radial), two air gaps r1..r2 over b (radial, mu_r = 1), ring A
  (axial); part B: the same yoke, two air gaps r1_B..r2_B over b_B, ring B (axial, ring_B_length) and the
  toothed axial gap of the book, area pi (r_o^2 - r_i^2) (1/4 + N theta / (2 pi)) over teeth_gap, where theta
  is the book's relative angle (output flange minus input flange): theta = -twist.
The first set (sensor_data = 2): two air gaps r1..r2 over b and an iron path (iron_path_length, section
2 pi r1 b, mu_r_iron_path) for both parts; B adds teeth * (rest_overlap + twist) * tooth_radius * tooth_length
over tooth_gap.
  * Question 4 (iron of infinite permeability): L_q4 = pi mu0 b N^2 / ln(r2/r1),   mu0 = 4 pi 1e-7 (chapter).
  * L = N^2 / (sum of the reluctances).
Bridges (phasors, the supply U sin(wt) = Im(U e^{jwt}) as the phase reference; Z = R_winding + j w L):
  * bridge_topology = 1 (the book's): Vout = U (R2 / (R1 + R2) - Z_B / (Z_A + Z_B));
  * bridge_topology = 2 (first set): B = R_bridge U (1 / (R_bridge + Z_B) - 1 / (R_bridge + Z_A)).
  The multiplier's product u_s u_bridge / U_ref has the mean U Re(B) / (2 U_ref); the filter passes it with
  its static gain k: u(twist) = k U Re(B) / (2 U_ref).
Voltage step U on a winding alone (R_bridge = 0, question 5): i(t) = U/R (1 - exp(-t R / L)).

`book_experiment` integrates the book's experiment in the time domain with scipy (the current i as the
state, the time-varying inductances by the chain rule), written from the circuit's equations, not from the
FMU's state choice (the FMU integrates the flux linkage).
"""

from __future__ import annotations

import math

import numpy as np

MU0 = 4e-7 * math.pi  # the chapter's value, question 4

# The book's position source smooths its reference by 1 / (1 + (A1 / wc) s + (A2 / wc^2) s^2), wc = 2 pi f_crit
# (Modelica.Mechanics.Rotational.Sources.Position with exact = false: its documented Bessel coefficients).
POSITION_A1, POSITION_A2 = 1.3617, 0.6180


def axial_tube(l, r_i, r_o, mu_r):
    """Reluctance of a hollow cylinder crossed axially, 1/H."""
    return l / (MU0 * mu_r * math.pi * (r_o**2 - r_i**2))


def radial_tube(w, r_i, r_o, mu_r):
    """Reluctance of a hollow cylinder crossed radially, 1/H."""
    return math.log(r_o / r_i) / (2 * math.pi * MU0 * mu_r * w)


def question4_inductance(N: float, r1: float, r2: float, b: float) -> float:
    return math.pi * MU0 * b * N**2 / math.log(r2 / r1)


# ---- the book's circuits (sensor_data = 1) ----------------------------------------------------------------

def book_yoke(p):
    mu = p["mu_r_iron"]
    return (axial_tube(p["yoke_length"], p["yoke_r_inner"], p["yoke_r_outer"], mu)
            + 2 * radial_tube(p["pole_width"], p["pole_r_inner"], p["pole_r_outer"], mu))


def book_reluctance_a(p):
    return (book_yoke(p) + 2 * radial_tube(p["b"], p["r1"], p["r2"], 1.0)
            + axial_tube(p["ring_A_length"], p["ring_r_inner"], p["ring_r_outer"], p["mu_r_iron"]))


def book_reluctance_b_fixed(p):
    return (book_yoke(p) + 2 * radial_tube(p["b_B"], p["r1_B"], p["r2_B"], 1.0)
            + axial_tube(p["ring_B_length"], p["ring_r_inner"], p["ring_r_outer"], p["mu_r_iron"]))


def book_teeth_reluctance(p, theta):
    """The book's toothed axial gap at the relative angle theta (output minus input flange)."""
    area = math.pi * (p["teeth_r_outer"] ** 2 - p["teeth_r_inner"] ** 2) * (0.25 + p["teeth_poles"] * np.asarray(theta) / (2 * math.pi))
    return p["teeth_gap"] / (MU0 * area)


# ---- the first set's circuits (sensor_data = 2) -----------------------------------------------------------

def gap_reluctance(p: dict) -> float:
    return math.log(p["r2"] / p["r1"]) / (2 * math.pi * MU0 * p["b"])


def first_set_reluctance_a(p: dict) -> float:
    iron = p["iron_path_length"] / (MU0 * p["mu_r_iron_path"] * 2 * math.pi * p["r1"] * p["b"])
    return 2 * gap_reluctance(p) + iron


def first_set_teeth_reluctance(p: dict, twist_rad):
    section = p["teeth"] * (p["rest_overlap"] + np.asarray(twist_rad)) * p["tooth_radius"] * p["tooth_length"]
    return p["tooth_gap"] / (MU0 * section)


# ---- both ------------------------------------------------------------------------------------------------

def twist(p: dict, torque):
    """twist_drive = 2: T / K within the stops."""
    return np.clip(np.asarray(torque, dtype=float) / p["K_torsion_bar"], -p["twist_stop"], p["twist_stop"])


def inductances(p: dict, twist_rad, sensor_data: int = 1, arrangement: int = 1):
    """(L_A, L_B) at the twist of the input shaft against the output shaft, H."""
    tw = np.asarray(twist_rad, dtype=float)
    if sensor_data == 1:
        teeth = lambda x: book_teeth_reluctance(p, -x)  # noqa: E731 (the book's relative angle is -twist)
        r_a, r_b = book_reluctance_a(p), book_reluctance_b_fixed(p) + teeth(tw)
    else:
        teeth = lambda x: first_set_teeth_reluctance(p, x)  # noqa: E731
        r_a = first_set_reluctance_a(p)
        r_b = r_a + teeth(tw)
    if arrangement == 2:
        r_a = r_a + teeth(-tw)
    n2 = p["N"] ** 2
    return n2 / r_a + 0 * tw, n2 / r_b


def bridge_phasor(p: dict, twist_rad, sensor_data: int = 1, topology: int = 1, arrangement: int = 1):
    w = 2 * math.pi * p["f_supply"]
    l_a, l_b = inductances(p, twist_rad, sensor_data, arrangement)
    z_a, z_b = p["R_winding"] + 1j * w * l_a, p["R_winding"] + 1j * w * l_b
    U = p["U_supply"]
    if topology == 1:
        return U * (p["R2_bridge"] / (p["R1_bridge"] + p["R2_bridge"]) - z_b / (z_a + z_b))
    rb = p["R_bridge"]
    return rb * (U / (rb + z_b) - U / (rb + z_a))


def steady_demodulated(p: dict, twist_rad, sensor_data: int = 1, topology: int = 1, arrangement: int = 1):
    """u(twist) = k U Re(B) / (2 U_ref) (phasors), V."""
    b = bridge_phasor(p, twist_rad, sensor_data, topology, arrangement)
    return p["filter_gain"] * p["U_supply"] * np.real(b) / (2 * p["U_multiplier_reference"])


def step_current(U: float, R: float, L: float, t):
    return U / R * (1 - np.exp(-np.asarray(t) * R / L))


def line_fit(x, y):
    """Least-squares straight line: (slope, intercept, largest |deviation|)."""
    slope, intercept = np.polyfit(x, y, 1)
    return float(slope), float(intercept), float(np.max(np.abs(y - (slope * x + intercept))))


def invert(p: dict, u_offset_removed: float, lo: float, hi: float, **kw) -> float:
    """Question 9's conditioning re-derived: the twist whose u(twist) - u(0) equals the reading (scipy's brentq
    on the phasor characteristic), times the stiffness: the torque, N m."""
    from scipy.optimize import brentq

    u0 = float(steady_demodulated(p, 0.0, **kw))
    g = lambda x: float(steady_demodulated(p, x, **kw)) - u0 - u_offset_removed  # noqa: E731
    return p["K_torsion_bar"] * brentq(g, lo, hi, xtol=1e-15, rtol=1e-15)


def book_experiment(p: dict, t_eval, rtol: float = 1e-10):
    """The book's experiment in the time domain (bridge_topology 1, twist_drive 1, the built-in step):
    the input shaft's angle steps by twist_profile_height at twist_profile_start through the position
    source's smoothing; the windings A and B carry one current i:
        (L_A + L_B) di/dt = u_s - 2 R_w i - (dL_A/dt + dL_B/dt) i,
        windings' midpoint v_m = R_w i + L_B di/dt + (dL_B/dt) i,   Vout = u_s R2 / (R1 + R2) - v_m,
        product = u_s Vout / U_ref,   y'' = w^2 (k product - y) - 2 D w y'.
    dL/dt = dL/dtwist x dtwist/dt, dL/dtwist by central differences of `inductances`.
    Returns a dict of arrays on t_eval: u_demodulated, u_bridge, i, twist."""
    from scipy.integrate import solve_ivp

    U, f, R = p["U_supply"], p["f_supply"], p["R_winding"]
    w = 2 * math.pi * f
    divider = p["R2_bridge"] / (p["R1_bridge"] + p["R2_bridge"])
    wf, D, k, uref = p["filter_w"], p["filter_damping"], p["filter_gain"], p["U_multiplier_reference"]
    wc = 2 * math.pi * p["position_f_crit"]
    h = 1e-7

    def lab(tw):
        l_a, l_b = inductances(p, tw)
        return float(l_a), float(l_b)

    def parts(t, x, ref):
        i, y, yd, phi, phid = x
        u_s = U * math.sin(w * t)
        l_a, l_b = lab(phi)
        (la1, lb1), (la0, lb0) = lab(phi + h), lab(phi - h)
        dla, dlb = (la1 - la0) / (2 * h) * phid, (lb1 - lb0) / (2 * h) * phid
        di = (u_s - 2 * R * i - (dla + dlb) * i) / (l_a + l_b)
        v_m = R * i + l_b * di + dlb * i
        vout = u_s * divider - v_m
        product = u_s * vout / uref
        ydd = wf * wf * (k * product - y) - 2 * D * wf * yd
        phidd = (wc * wc / POSITION_A2) * (ref - phi) - (POSITION_A1 * wc / POSITION_A2) * phid
        return np.array([di, yd, ydd, phid, phidd]), vout

    t_eval = np.asarray(t_eval, dtype=float)
    t_step = p["twist_profile_start"]
    out = {name: np.empty_like(t_eval) for name in ("u_demodulated", "u_bridge", "i", "twist")}
    x0 = np.zeros(5)
    for t0, t1, ref in ((0.0, t_step, 0.0), (t_step, t_eval[-1], p["twist_profile_height"])):
        sel = (t_eval >= t0) & (t_eval < t1) if t1 < t_eval[-1] else (t_eval >= t0)
        ts = t_eval[sel]
        extra = not (len(ts) and ts[-1] == t1)  # the segment's end, for the next one's start
        sol = solve_ivp(lambda t, x: parts(t, x, ref)[0], (t0, t1), x0, method="DOP853", rtol=rtol, atol=1e-14,
                        t_eval=np.append(ts, t1) if extra else ts)
        assert sol.success, sol.message
        y = sol.y[:, : len(ts)]
        out["i"][sel], out["u_demodulated"][sel], out["twist"][sel] = y[0], y[1], y[3]
        out["u_bridge"][sel] = [parts(t, x, ref)[1] for t, x in zip(ts, y.T)]
        x0 = sol.y[:, -1]
    return out
