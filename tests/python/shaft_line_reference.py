"""An independent solution of the ShaftLine equations (docs/shaft-line-spec.md; chapter 3, section 3.5.3,
Table 3.8, eq. 3.9), written from the spec with numpy/scipy and sharing no code with the FMU.

Equations (spec, "Equations"), states i (armature current), w_m (motor speed), theta (shaft twist),
w_p (propeller speed), seal mode m in {-1 slipping backwards, 0 stuck, +1 slipping forwards}:

    L di/dt       = U(t) - R i - k w_m                                (armature, eq. 3.9: E = k w_m)
    J_m dw_m/dt   = k i - b w_m - T_shaft                             (motor rotor + half the shaft)
    dtheta/dt     = w_m - w_p
    T_shaft       = K theta + D (w_m - w_p)                           (hollow shaft: spring and damper)
    J_p dw_p/dt   = T_shaft - a w_p |w_p| - T_c m        if m = +-1   (propeller + half the shaft; seal slips)
    dw_p/dt       = 0                                    if m = 0     (seal stuck: w_p = 0)

with k = k_emf (emf_constant = 1, the book file's value) or from the rated point (emf_constant = 2:
U_rated = R I + k w_rated, T_rated = k I, the larger root of k^2 w_rated - U_rated k + R T_rated = 0),
and a = T_propeller_nominal / speed_propeller_nominal^2; the propeller torque is a w |w|
(propeller_law = 1) or a w^2 (propeller_law = 2, the book's ReducedModel).

Stick/slip of the seal, segment by segment with solve_ivp (Radau, rtol 1e-10) and terminal events:
  * slipping (m = +-1): the segment ends when w_p crosses 0; there the torque the seal must hold,
    T_req = T_shaft - a w_p |w_p| (= T_shaft at w_p = 0), decides: |T_req| <= T_s -> stuck (w_p = 0),
    else slipping in the direction of T_req;
  * stuck (m = 0): the segment ends when |T_req| reaches T_s; the seal slips in the direction of T_req.
Supply U(t): 0 -> U_max over ramp_time, U_max for plateau_time, 0 V (short circuit) after; the kinks
at ramp_time and ramp_time + plateau_time end segments too.

Reduced models (spec, "Model reduction"): model_reduction = 1, the book's ReducedModel (a rigid line
without the motor inertia; bearings and seal kept), is `simulate` with `structure="book_reduced"`:
the same segment logic on the states (i, w); model_reduction = 2 is `simulate_reduced`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np


@dataclass(frozen=True)
class ShaftLineParams:
    """The physical parameters (names as in modelDescription.xml)."""

    emf_constant: int
    k_emf: float
    T_rated: float
    speed_rated: float
    U_rated: float
    U_max: float
    R_armature: float
    L_armature: float
    J_motor: float
    b_motor_bearings: float
    J_propeller: float
    T_propeller_nominal: float
    speed_propeller_nominal: float
    propeller_law: int
    K_shaft: float
    J_shaft: float
    D_shaft: float
    T_seal_coulomb: float
    T_seal_static: float
    ramp_time: float
    plateau_time: float

    @classmethod
    def from_values(cls, values: dict) -> "ShaftLineParams":
        return cls(**{f.name: int(values[f.name]) if f.type == "int" else float(values[f.name]) for f in fields(cls)})

    # -- derived values (spec, "Derived parameters") ----------------------------------------------
    @property
    def k(self) -> float:
        """Machine constant, V s/rad = N m/A: k_emf, or (emf_constant = 2) the larger root of
        k^2 w - U k + R T = 0 (rated point)."""
        if self.emf_constant == 1:
            return self.k_emf
        w, u, r, t = self.speed_rated, self.U_rated, self.R_armature, self.T_rated
        return (u + math.sqrt(u * u - 4.0 * w * r * t)) / (2.0 * w)

    @property
    def a(self) -> float:
        """Propeller coefficient, T = a w^2 at the propeller's nominal point: N m s2/rad2."""
        return self.T_propeller_nominal / self.speed_propeller_nominal**2

    def propeller_torque(self, w: float) -> float:
        """a w |w| (propeller_law 1), or a w^2 whatever the direction (propeller_law 2)."""
        return self.a * w * (w if self.propeller_law == 2 else abs(w))

    @property
    def J_m(self) -> float:
        return self.J_motor + 0.5 * self.J_shaft

    @property
    def J_p(self) -> float:
        return self.J_propeller + 0.5 * self.J_shaft

    @property
    def short_circuit_time(self) -> float:
        return self.ramp_time + self.plateau_time

    def supply(self, t: float) -> float:
        if t < self.ramp_time:
            return self.U_max * t / self.ramp_time
        if t < self.short_circuit_time:
            return self.U_max
        return 0.0


def steady_state(p: ShaftLineParams) -> dict:
    """The balance at U = U_max with the seal slipping forwards, solved by Newton's method on the
    speed (spec, "Steady state by hand"):
        k I = a w^2 + b w + T_c,   U_max = R I + k w
    -> f(w) = k (U_max - k w) / R - a w^2 - b w - T_c = 0 (one positive root: f decreases in w)."""
    k, a, r, b, tc = p.k, p.a, p.R_armature, p.b_motor_bearings, p.T_seal_coulomb

    def f(w):
        return k * (p.U_max - k * w) / r - a * w * w - b * w - tc

    def df(w):
        return -k * k / r - 2.0 * a * w - b

    w = p.U_max / k
    for _ in range(100):
        step = f(w) / df(w)
        w -= step
        if abs(step) < 1e-15 * abs(w):
            break
    current = (p.U_max - k * w) / r
    return {
        "speed": w,
        "current": current,
        "motor_torque": k * current,
        "shaft_torque": a * w * w + tc,  # the shaft carries the propeller and the seal
        "propeller_torque": a * w * w,
    }


class _Full:
    """States (i, w_m, theta, w_p): motor end, elastic shaft, propeller end with the seal."""

    speed = 3  # index of the speed the seal rubs on
    atol = np.array([1e-6, 1e-9, 1e-12, 1e-9])

    def __init__(self, p: ShaftLineParams):
        self.p = p

    def shaft_torque(self, y):
        p = self.p
        return p.K_shaft * y[2] + p.D_shaft * (y[1] - y[3])

    def required(self, y) -> float:
        """The torque the seal must take to hold the propeller still."""
        return self.shaft_torque(y) - self.p.propeller_torque(y[3])

    def rhs(self, mode: int):
        p = self.p

        def f(t, y):
            i, w_m, theta, w_p = y
            t_shaft = self.shaft_torque(y)
            di = (p.supply(t) - p.R_armature * i - p.k * w_m) / p.L_armature
            dw_m = (p.k * i - p.b_motor_bearings * w_m - t_shaft) / p.J_m
            dw_p = 0.0 if mode == 0 else (t_shaft - p.propeller_torque(w_p) - p.T_seal_coulomb * mode) / p.J_p
            return [di, dw_m, w_m - w_p, dw_p]

        return f

    def jac(self, mode: int):
        p = self.p
        k, r, l, b, kk, d = p.k, p.R_armature, p.L_armature, p.b_motor_bearings, p.K_shaft, p.D_shaft

        def jac(t, y):
            j = np.zeros((4, 4))
            j[0] = [-r / l, -k / l, 0.0, 0.0]
            j[1] = [k / p.J_m, (-b - d) / p.J_m, -kk / p.J_m, d / p.J_m]
            j[2] = [0.0, 1.0, 0.0, -1.0]
            if mode != 0:
                j[3] = [0.0, d / p.J_p, kk / p.J_p, (-d - _load_slope(p, y[3])) / p.J_p]
            return j

        return jac


class _BookReduced:
    """The book's ReducedModel, states (i, w): no motor inertia, a rigid shaft; the motor bearings and
    the seal act on the one body, the propeller inertia. What the motor passes on: k i - b w."""

    speed = 1
    atol = np.array([1e-6, 1e-9])

    def __init__(self, p: ShaftLineParams):
        self.p = p

    def shaft_torque(self, y):
        return self.p.k * y[0] - self.p.b_motor_bearings * y[1]

    def required(self, y) -> float:
        return self.shaft_torque(y) - self.p.propeller_torque(y[1])

    def rhs(self, mode: int):
        p = self.p

        def f(t, y):
            i, w = y
            di = (p.supply(t) - p.R_armature * i - p.k * w) / p.L_armature
            dw = 0.0 if mode == 0 else (self.required(y) - p.T_seal_coulomb * mode) / p.J_p
            return [di, dw]

        return f

    def jac(self, mode: int):
        p = self.p

        def jac(t, y):
            j = np.zeros((2, 2))
            j[0] = [-p.R_armature / p.L_armature, -p.k / p.L_armature]
            if mode != 0:
                j[1] = [p.k / p.J_p, (-p.b_motor_bearings - _load_slope(p, y[1])) / p.J_p]
            return j

        return jac


def _load_slope(p: ShaftLineParams, w: float) -> float:
    """d(propeller torque)/dw: 2 a |w| (a w |w|) or 2 a w (a w^2)."""
    return 2.0 * p.a * (w if p.propeller_law == 2 else abs(w))


STRUCTURES = {"full": _Full, "book_reduced": _BookReduced}


def _mode_after(line, y) -> tuple[int, np.ndarray]:
    """At zero speed (a slip segment ended, or at the start): stuck if the seal can hold the required
    torque, else slipping in its direction. Returns the mode and the state (speed = 0 exactly)."""
    y = np.array(y, dtype=float)
    y[line.speed] = 0.0
    t_req = line.required(y)
    if abs(t_req) <= line.p.T_seal_static:
        return 0, y
    return (1 if t_req > 0 else -1), y


def simulate(p: ShaftLineParams, t_end: float, rtol: float = 1e-10, max_step: float = 0.05, t_eval=None, structure: str = "full"):
    """Segment-by-segment Radau solution from rest (seal stuck). Returns a dict of arrays
    (t, the states by name, mode, shaft_torque, motor_torque, propeller_speed) at the solver's steps,
    or at the times `t_eval` (from the dense output), and the list of mode changes (t, mode before,
    after). `structure`: "full" (model_reduction 0) or "book_reduced" (model_reduction 1)."""
    from scipy.integrate import solve_ivp

    line = STRUCTURES[structure](p)
    names = ("i", "w_m", "theta", "w_p") if structure == "full" else ("i", "w")
    y = np.zeros(len(names))
    mode, y = _mode_after(line, y)
    t = 0.0
    kinks = [p.ramp_time, p.short_circuit_time]
    out = {name: [] for name in ("t", "mode") + names}
    switches = []
    while t < t_end:
        t_stop = min([k for k in kinks if k > t + 1e-12] + [t_end])

        if mode == 0:
            def ev(tt, yy):
                return p.T_seal_static - abs(line.required(yy))
        else:
            def ev(tt, yy, m=mode):
                return m * yy[line.speed]
        ev.direction = -1
        ev.terminal = True

        segment_eval = None
        if t_eval is not None:
            segment_eval = t_eval[(t_eval >= t) & (t_eval <= t_stop)]
        sol = solve_ivp(line.rhs(mode), (t, t_stop), y, method="Radau", rtol=rtol, atol=line.atol,
                        jac=line.jac(mode), events=ev, t_eval=segment_eval, max_step=max_step)
        if sol.status < 0:
            raise RuntimeError(f"Radau failed at t = {t}: {sol.message}")
        for name, row in zip(names, sol.y):
            out[name].append(row)
        out["t"].append(sol.t)
        out["mode"].append(np.full(sol.t.shape, mode))
        if sol.status == 1:  # event
            t = float(sol.t_events[0][0])
            y = np.array(sol.y_events[0][0])
            if mode == 0:
                new_mode = 1 if line.required(y) > 0 else -1
            else:
                new_mode, y = _mode_after(line, y)
            switches.append((t, mode, new_mode))
            mode = new_mode
        else:
            t = t_stop
            y = sol.y[:, -1]
    res = {name: np.concatenate(v) for name, v in out.items()}
    _, first = np.unique(res["t"], return_index=True)  # a time shared by two segments, once
    res = {name: v[first] for name, v in res.items()}
    states = np.vstack([res[n] for n in names])
    res["shaft_torque"] = line.shaft_torque(states)
    res["motor_torque"] = p.k * res["i"]
    res["propeller_speed"] = res[names[line.speed]]
    return res, switches


def simulate_reduced(p: ShaftLineParams, t_end: float, rtol: float = 1e-10, max_step: float = 0.05, t_eval=None):
    """The activity-reduced model (model_reduction = 2; spec, "Model reduction": armature R and L,
    propeller inertia and load; rigid massless shaft and motor rotor, no bearings, no seal):
    L di/dt = U - R i - k w, J_p dw/dt = k i - a w |w|; the shaft carries the motor torque k i. Smooth: one Radau run per
    supply segment. Returns (t, shaft torque)."""
    from scipy.integrate import solve_ivp

    k, r, l = p.k, p.R_armature, p.L_armature

    def f(t, y):
        i, w = y
        return [(p.supply(t) - r * i - k * w) / l, (k * i - p.propeller_torque(w)) / p.J_p]

    y = np.zeros(2)
    ts, torques = [], []
    bounds = [0.0] + [kk for kk in (p.ramp_time, p.short_circuit_time) if kk < t_end] + [t_end]
    for t0, t1 in zip(bounds[:-1], bounds[1:]):
        segment_eval = None
        if t_eval is not None:  # the segment's end too, where the next one starts
            segment_eval = np.append(t_eval[(t_eval >= t0) & (t_eval < t1)], t1)
        sol = solve_ivp(f, (t0, t1), y, method="Radau", rtol=rtol, atol=[1e-6, 1e-9], t_eval=segment_eval, max_step=max_step)
        if sol.status < 0:
            raise RuntimeError(f"Radau failed at t = {t0}: {sol.message}")
        y = sol.y[:, -1]
        ts.append(sol.t)
        torques.append(k * sol.y[0])
    t, idx = np.unique(np.concatenate(ts), return_index=True)
    return t, np.concatenate(torques)[idx]
