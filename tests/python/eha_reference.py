"""An independent reference for EhaFlightControl (docs/eha-flight-control-spec.md): the spec's
equations written out here with numpy and scipy, never values from a run of the FMU.

States: level 1 x = (i, w_m, theta); level 2 x = (i, w_m, dp, theta, w_s).

    U      = clip(Kp (theta_cmd - theta), -U_bus, U_bus)                   position law
    L di/dt = U - R i - k w_m                                               armature (eq. 3.9)
    M      = K_hinge theta - M_external                                     the moment the actuator holds
  level 1 (rigid oil, N = A r / D):
    (J_m + J_s / N^2) dw_m/dt = k i - M / N,  dtheta/dt = w_m / N
    dp = (J_s dw_s/dt + M) / (A r)
  level 2 (C = V / (2 B), two chambers of V at mid stroke in series):
    J_m dw_m/dt = k i - D dp
    C d(dp)/dt  = D w_m - A r w_s - dp / R_leak
    J_s dw_s/dt = A r dp - M,  dtheta/dt = w_s

The command is `step_angle` from `step_time` to `return_time` (0 elsewhere) plus `angle_command_in`.
`simulate` integrates segment by segment: the command's steps and the voltage limit's corners are
located (solve_ivp terminal events) and the integration restarts there, so every segment is smooth.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.integrate import solve_ivp

FIELDS = ("level", "U_bus", "R_motor", "L_motor", "k_motor", "J_motor", "D_pump", "A_piston", "r_horn", "J_surface",
          "K_hinge", "V_chamber", "B_oil", "R_leakage", "Kp", "step_angle", "step_time", "return_time")


@dataclasses.dataclass(frozen=True)
class EhaParams:
    level: int
    U_bus: float
    R_motor: float
    L_motor: float
    k_motor: float
    J_motor: float
    D_pump: float
    A_piston: float
    r_horn: float
    J_surface: float
    K_hinge: float
    V_chamber: float
    B_oil: float
    R_leakage: float
    Kp: float
    step_angle: float
    step_time: float
    return_time: float

    @classmethod
    def from_values(cls, values: dict) -> "EhaParams":
        return cls(**{f: (int(values[f]) if f == "level" else float(values[f])) for f in FIELDS})

    def with_(self, **changes) -> "EhaParams":
        return dataclasses.replace(self, **changes)

    @property
    def N(self) -> float:
        """Motor radians per surface radian with rigid oil."""
        return self.A_piston * self.r_horn / self.D_pump

    @property
    def C(self) -> float:
        """The two chambers' capacitance seen from the pressure difference, m3/Pa."""
        return self.V_chamber / (2.0 * self.B_oil)

    @property
    def k_oil(self) -> float:
        """Hydraulic stiffness of the piston on its two closed oil columns, 2 A^2 B / V, N/m."""
        return 2.0 * self.A_piston**2 * self.B_oil / self.V_chamber

    @property
    def m_surface(self) -> float:
        """The surface inertia as a mass on the rod, J_s / r^2, kg."""
        return self.J_surface / self.r_horn**2

    @property
    def f_hydraulic_hz(self) -> float:
        """sqrt(k_oil / m_surface) / 2 pi: the surface on its oil columns, the pump held."""
        return math.sqrt(self.k_oil / self.m_surface) / (2 * math.pi)

    @property
    def f_hydraulic_with_hinge_hz(self) -> float:
        """The same with the hinge's stiffness seen at the rod, K_hinge / r^2, beside the oil's."""
        return math.sqrt((self.k_oil + self.K_hinge / self.r_horn**2) / self.m_surface) / (2 * math.pi)

    def n_states(self) -> int:
        return 3 if self.level == 1 else 5


def command(p: EhaParams, t: float, angle_in: float = 0.0) -> float:
    on = p.step_time <= t < p.return_time
    return (p.step_angle if on else 0.0) + angle_in


def _theta(p, x):
    return x[2] if p.level == 1 else x[3]


def rhs(p: EhaParams, x, theta_cmd: float, m_ext: float = 0.0):
    """dx/dt at the command theta_cmd (held over a segment)."""
    i, w = x[0], x[1]
    theta = _theta(p, x)
    u = min(max(p.Kp * (theta_cmd - theta), -p.U_bus), p.U_bus)
    di = (u - p.R_motor * i - p.k_motor * w) / p.L_motor
    moment = p.K_hinge * theta - m_ext
    if p.level == 1:
        j_line = p.J_motor + p.J_surface / p.N**2
        dw = (p.k_motor * i - moment / p.N) / j_line
        return np.array([di, dw, w / p.N])
    dp, ws = x[2], x[4]
    dw = (p.k_motor * i - p.D_pump * dp) / p.J_motor
    ddp = (p.D_pump * w - p.A_piston * p.r_horn * ws - dp / p.R_leakage) / p.C
    dws = (p.A_piston * p.r_horn * dp - moment) / p.J_surface
    return np.array([di, dw, ddp, ws, dws])


def jacobian(p: EhaParams) -> np.ndarray:
    """The linear system matrix about rest, the voltage within its limit (analytic)."""
    a, L, J, k, R = p.A_piston * p.r_horn, p.L_motor, p.J_motor, p.k_motor, p.R_motor
    if p.level == 1:
        j_line = J + p.J_surface / p.N**2
        return np.array([
            [-R / L, -k / L, -p.Kp / L],
            [k / j_line, 0.0, -p.K_hinge / p.N / j_line],
            [0.0, 1.0 / p.N, 0.0],
        ])
    return np.array([
        [-R / L, -k / L, 0.0, -p.Kp / L, 0.0],
        [k / J, 0.0, -p.D_pump / J, 0.0, 0.0],
        [0.0, p.D_pump / p.C, -1.0 / (p.R_leakage * p.C), 0.0, -a / p.C],
        [0.0, 0.0, 0.0, 0.0, 1.0],
        [0.0, 0.0, a / p.J_surface, -p.K_hinge / p.J_surface, 0.0],
    ])


def hydraulic_mode(eigenvalues: np.ndarray, near_rad_per_s: float) -> complex:
    """The eigenvalue (positive imaginary part) whose modulus is nearest `near_rad_per_s`."""
    upper = [lam for lam in eigenvalues if lam.imag > 0]
    return min(upper, key=lambda lam: abs(abs(lam) - near_rad_per_s))


def stability_limit_kp(p: EhaParams, lo: float, hi: float) -> float:
    """The position gain at which the linearised loop goes unstable (its largest eigenvalue real
    part crosses zero; bisection on the analytic matrix, `lo` stable and `hi` unstable)."""

    def growth(kp):
        return float(np.max(np.linalg.eigvals(jacobian(p.with_(Kp=kp))).real))

    assert growth(lo) < 0 < growth(hi), (growth(lo), growth(hi))
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if growth(mid) < 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def outputs(p: EhaParams, x: np.ndarray, theta_cmd: float, m_ext: float = 0.0) -> dict:
    """The FMU's outputs from a state (columns of x) at the command theta_cmd."""
    i, w = x[0], x[1]
    theta = _theta(p, x)
    u = np.clip(p.Kp * (theta_cmd - theta), -p.U_bus, p.U_bus)
    moment = p.K_hinge * theta - m_ext
    if p.level == 1:
        ws = w / p.N
        dws = rhs_columns(p, x, theta_cmd, m_ext)[1] / p.N
        dp = (p.J_surface * dws + moment) / (p.A_piston * p.r_horn)
        leak = np.zeros_like(i)
    else:
        dp, ws = x[2], x[4]
        leak = dp / p.R_leakage
    return {
        "surface_angle": theta, "surface_rate": ws, "motor_voltage": u, "motor_current": i, "motor_speed": w,
        "motor_torque": p.k_motor * i, "pump_pressure": dp, "pump_flow": p.D_pump * w, "piston_position": p.r_horn * theta,
        "piston_force": p.A_piston * dp, "hinge_moment": moment, "leakage_flow": leak, "bus_current": u / p.U_bus * i,
    }


def rhs_columns(p, x, theta_cmd, m_ext):
    return np.column_stack([rhs(p, x[:, j], theta_cmd, m_ext) for j in range(x.shape[1])])


def simulate(p: EhaParams, t_eval: np.ndarray, m_ext: float = 0.0, angle_in: float = 0.0, rtol: float = 1e-11) -> dict:
    """Outputs on t_eval (from rest at t = 0), integrated by DOP853 segment by segment: between the
    command's steps, and within them between the corners of the voltage limit (terminal events,
    then a restart past the corner). An output at a command step's instant takes the new command
    (the state is continuous there), as the FMU's row at that communication point does."""
    t_end = float(t_eval[-1])
    breaks = sorted({b for b in (p.step_time, p.return_time) if 0.0 < b < t_end})
    scale = [10.0, 100.0, 1e7, 0.1, 1.0] if p.level == 2 else [10.0, 100.0, 0.1]
    atol = rtol * np.array(scale)
    x, t, covered = np.zeros(p.n_states()), 0.0, -math.inf
    columns = np.empty((p.n_states(), len(t_eval)))
    for stop in breaks + [t_end]:
        theta_cmd = command(p, t, angle_in)
        f = lambda tt, xx, c=theta_cmd: rhs(p, xx, c, m_ext)  # noqa: E731
        while t < stop:
            events = []
            for side in (1.0, -1.0):
                ev = lambda tt, xx, s=side, c=theta_cmd: p.Kp * (c - _theta(p, xx)) - s * p.U_bus  # noqa: E731
                ev.terminal = True
                events.append(ev)
            sol = solve_ivp(f, (t, stop), x, method="DOP853", rtol=rtol, atol=atol, events=events, dense_output=True)
            assert sol.success, sol.message
            t_stop = float(sol.t[-1])
            inside = (t_eval > covered) & (t_eval <= t_stop)
            if np.any(inside):
                columns[:, inside] = sol.sol(t_eval[inside])
            covered = max(covered, t_stop)
            x, t = sol.y[:, -1], t_stop
            if sol.status == 1 and t < stop:
                # A corner of the limit: go a hair past it, where its event function has its new sign.
                hair = min(1e-9, stop - t)
                past = solve_ivp(f, (t, t + hair), x, method="DOP853", rtol=rtol, atol=atol, dense_output=True)
                inside = (t_eval > covered) & (t_eval <= t + hair)
                if np.any(inside):
                    columns[:, inside] = past.sol(t_eval[inside])
                covered = t + hair
                x, t = past.y[:, -1], t + hair
    assert covered >= t_end
    commands = np.array([command(p, tk, angle_in) for tk in t_eval])
    out = {name: np.empty(len(t_eval)) for name in outputs(p, columns[:, :1], commands[0], m_ext)}
    for c in np.unique(commands):
        sel = commands == c
        for name, v in outputs(p, columns[:, sel], c, m_ext).items():
            out[name][sel] = v
    out["time"] = np.asarray(t_eval)
    return out


def steady_state(p: EhaParams, theta_cmd: float, m_ext: float = 0.0) -> dict:
    """The surface at rest, by hand. It holds M = K_hinge theta - M_external through the piston:
    dp = M / (A r); the pump's shaft torque D dp is the motor's k i; level 2 leaks Q = dp / R_leak
    across the piston, which the pump makes up turning at w = Q / D, against the back EMF k w. The
    voltage R i + k w is the law's Kp (theta_cmd - theta), so with g = (R D / k + [k / (R_leak D)]) / (A r Kp):
    theta = (theta_cmd + g M_external) / (1 + g K_hinge)."""
    a = p.A_piston * p.r_horn
    leak_term = p.k_motor / (p.R_leakage * p.D_pump) if p.level == 2 else 0.0
    g = (p.R_motor * p.D_pump / p.k_motor + leak_term) / (a * p.Kp)
    theta = (theta_cmd + g * m_ext) / (1.0 + g * p.K_hinge)
    moment = p.K_hinge * theta - m_ext
    dp = moment / a
    i = p.D_pump * dp / p.k_motor
    w = dp / p.R_leakage / p.D_pump if p.level == 2 else 0.0
    u = p.R_motor * i + p.k_motor * w
    assert abs(u) < p.U_bus, "the steady state must be within the voltage limit"
    return {"surface_angle": theta, "hinge_moment": moment, "pump_pressure": dp, "piston_force": p.A_piston * dp,
            "motor_current": i, "motor_torque": p.k_motor * i, "motor_speed": w, "motor_voltage": u,
            "leakage_flow": dp / p.R_leakage if p.level == 2 else 0.0, "surface_rate": 0.0}
