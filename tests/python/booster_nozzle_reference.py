"""An independent reference for BoosterNozzle (docs/booster-nozzle-spec.md): the spec's equations
written out here with numpy and scipy in the physical coordinates (the body's displacement in
metres, where the FMU keeps it referred to the nozzle angle), never values from a run of the FMU.

One axis, states x = (theta, w, dp, x_b, v_b):

    y      = r theta - x_b                       stroke (rod end less body)
    Q_v    = A K_v (r theta_cmd - y)             servo-valve flow (position loop on the stroke)
    C d(dp)/dt = Q_v - A (r w - v_b) - dp / R    C = V / (2 B): the two chambers in series
    J dw/dt    = r A dp - K_b theta - D_b w + M  M = the offset torque's share + M_aero
    m_a dv_b/dt = -A dp - K_a x_b - D_a v_b      the actuator's body on its anchoring

The axis is linear: dx/dt = F x + G (theta_cmd, M). The built-in command (profile 1: a step of
`command_amplitude` at `step_time`; 2: a sine of it at `sine_frequency` from `step_time`) is
split into pitch (cos command_azimuth) and yaw (sin); the offset torque likewise by `offset_azimuth`.
`simulate` solves it in closed form on [0, step_time] and [step_time, end] (the command's kink):
a particular solution (constant and sinusoidal inputs) plus F's matrix exponential through its
eigenvectors; checked while writing it against scipy's DOP853 at rtol 1e-12 (within 5e-11 of each
state's range over the default step, the 2 Hz sine and an input-driven run).

The two-degree-of-freedom chain (valve closed, undamped), coordinates (theta, x_b):
    M = diag(J, m_a),  K = [[K_b + k r^2, -k r], [-k r, k + K_a]],  k = 2 A^2 B / V.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

FIELDS = ("profile", "J_nozzle", "K_bearing", "D_bearing", "r_arm", "A_piston", "V_chamber", "B_oil", "R_leakage", "m_actuator",
          "K_anchor", "D_anchor", "K_v", "M_offset", "offset_azimuth", "command_amplitude", "command_azimuth", "step_time", "sine_frequency")
STATES = ("theta", "w", "dp", "x_b", "v_b")
# Storage and dissipative elements of one axis, as the FMU names them (without the axis suffix).
STORAGE = ("nozzle_inertia", "bearing_stiffness", "oil", "actuator_body", "anchoring")
DISSIPATION = ("bearing_damping", "leakage", "anchoring_damping")


@dataclasses.dataclass(frozen=True)
class NozzleParams:
    profile: int
    J_nozzle: float
    K_bearing: float
    D_bearing: float
    r_arm: float
    A_piston: float
    V_chamber: float
    B_oil: float
    R_leakage: float
    m_actuator: float
    K_anchor: float
    D_anchor: float
    K_v: float
    M_offset: float
    offset_azimuth: float
    command_amplitude: float
    command_azimuth: float
    step_time: float
    sine_frequency: float

    @classmethod
    def from_values(cls, values: dict) -> "NozzleParams":
        return cls(**{f: (int(values[f]) if f == "profile" else float(values[f])) for f in FIELDS})

    def with_(self, **changes) -> "NozzleParams":
        return dataclasses.replace(self, **changes)

    @property
    def C(self) -> float:
        """The two chambers seen from dp, m3/Pa."""
        return self.V_chamber / (2.0 * self.B_oil)

    @property
    def k_oil(self) -> float:
        """The piston on its two closed oil columns, 2 A^2 B / V, N/m."""
        return 2.0 * self.A_piston**2 * self.B_oil / self.V_chamber

    @property
    def servo_static_stiffness(self) -> float:
        """r^2 / (1/K_a + 1/(A^2 R K_v)), N m/rad (0 with the loop open)."""
        if self.K_v == 0.0:
            return 0.0
        return self.r_arm**2 / (1.0 / self.K_anchor + 1.0 / (self.A_piston**2 * self.R_leakage * self.K_v))


def two_dof_matrices(p: NozzleParams) -> tuple[np.ndarray, np.ndarray]:
    """(M, K) of the undamped chain, coordinates (theta, x_b): from the kinetic energy
    (J theta'^2 + m_a x_b'^2) / 2 and the elastic one (K_b theta^2 + k (r theta - x_b)^2 + K_a x_b^2) / 2."""
    k, r = p.k_oil, p.r_arm
    mass = np.diag([p.J_nozzle, p.m_actuator])
    stiffness = np.array([[p.K_bearing + k * r * r, -k * r], [-k * r, k + p.K_anchor]])
    return mass, stiffness


def two_dof_modes(p: NozzleParams) -> tuple[np.ndarray, np.ndarray]:
    """(natural angular frequencies ascending, mode shapes as columns) from scipy's generalized
    symmetric eigenproblem K phi = w^2 M phi."""
    from scipy.linalg import eigh

    mass, stiffness = two_dof_matrices(p)
    w2, phi = eigh(stiffness, mass)
    return np.sqrt(w2), phi


def system_matrix(p: NozzleParams) -> tuple[np.ndarray, np.ndarray]:
    """(F, G) of one axis: dx/dt = F x + G @ (theta_cmd, M), x = (theta, w, dp, x_b, v_b)."""
    J, r, A, C = p.J_nozzle, p.r_arm, p.A_piston, p.C
    F = np.zeros((5, 5))
    F[0, 1] = 1.0
    F[1, 0], F[1, 1], F[1, 2] = -p.K_bearing / J, -p.D_bearing / J, r * A / J
    # C d(dp)/dt = A K_v (r theta_cmd - r theta + x_b) - A (r w - v_b) - dp / R
    F[2, 0], F[2, 1], F[2, 2], F[2, 3], F[2, 4] = -A * p.K_v * r / C, -A * r / C, -1.0 / (p.R_leakage * C), A * p.K_v / C, A / C
    F[3, 4] = 1.0
    F[4, 2], F[4, 3], F[4, 4] = -A / p.m_actuator, -p.K_anchor / p.m_actuator, -p.D_anchor / p.m_actuator
    G = np.zeros((5, 2))
    G[2, 0] = A * p.K_v * r / C
    G[1, 1] = 1.0 / J
    return F, G


def profile(p: NozzleParams, t: np.ndarray) -> np.ndarray:
    t = np.asarray(t, dtype=float)
    on = t >= p.step_time
    if p.profile == 1:
        return np.where(on, p.command_amplitude, 0.0)
    if p.profile == 2:
        return np.where(on, p.command_amplitude * np.sin(2 * math.pi * p.sine_frequency * (t - p.step_time)), 0.0)
    return np.zeros_like(t)


def axis_inputs(p: NozzleParams, axis: str, t, command_in: float = 0.0, m_aero: float = 0.0):
    """(theta_cmd(t), M(t)) of one axis."""
    share = math.cos if axis == "pitch" else math.sin
    theta_cmd = profile(p, t) * share(p.command_azimuth) + command_in
    moment = p.M_offset * share(p.offset_azimuth) + m_aero + 0.0 * np.asarray(t, dtype=float)
    return theta_cmd, moment


def powers(p: NozzleParams, x: np.ndarray, theta_cmd, moment) -> dict:
    """Each element's power (columns of x): sources deliver, storage dE/dt, dissipation takes."""
    F, G = system_matrix(p)
    dx = F @ x + G @ np.vstack([np.broadcast_to(theta_cmd, x.shape[1]), np.broadcast_to(moment, x.shape[1])])
    theta, w, dp, x_b, v_b = x
    y = p.r_arm * theta - x_b
    q_v = p.A_piston * p.K_v * (p.r_arm * theta_cmd - y)
    return {
        "nozzle_inertia": p.J_nozzle * w * dx[1],
        "bearing_stiffness": p.K_bearing * theta * w,
        "oil": p.C * dp * dx[2],
        "actuator_body": p.m_actuator * v_b * dx[4],
        "anchoring": p.K_anchor * x_b * v_b,
        "bearing_damping": p.D_bearing * w * w,
        "leakage": dp * dp / p.R_leakage,
        "anchoring_damping": p.D_anchor * v_b * v_b,
        "servo_valve": dp * q_v,
        "external_moment": moment * w,
    }


def _states(p: NozzleParams, axis: str, t_eval: np.ndarray, command_in: float, m_aero: float, x0) -> np.ndarray:
    """The axis's states (rows) on t_eval from x0 (default rest), in closed form: the axis is linear,
    dx/dt = F x + g_c u_c + g_s sin(w (t - t0)) on each stretch between the command's kinks, so
    x(t) = x_p(t) + exp(F (t - t_a)) (x(t_a) - x_p(t_a)) with the particular solution
    x_p = -F^-1 g_c u_c + Im((i w I - F)^-1 g_s e^(i w (t - t0))), the exponential through F's
    eigenvectors (of F scaled by the states' magnitudes, so that they are well conditioned)."""
    F, G = system_matrix(p)
    share = math.cos if axis == "pitch" else math.sin
    command_share = share(p.command_azimuth)
    g_moment = G[:, 1] * (p.M_offset * share(p.offset_azimuth) + m_aero)
    w_sine = 2 * math.pi * p.sine_frequency
    scale = np.array([0.01, 0.1, 1e6, 1e-4, 1e-2])
    Fs = F * (1.0 / scale)[:, None] * scale[None, :]  # D^-1 F D
    lam, V = np.linalg.eig(Fs)
    V_inv = np.linalg.inv(V)

    def stretch(t_a, t_b):
        """(constant input vector, sine input vector) on [t_a, t_b)."""
        on = p.profile != 0 and t_a >= p.step_time
        step = p.command_amplitude if (on and p.profile == 1) else 0.0
        sine = p.command_amplitude if (on and p.profile == 2) else 0.0
        return G[:, 0] * (step * command_share + command_in) + g_moment, G[:, 0] * sine * command_share

    def particular(t, g_c, g_s):
        x = np.linalg.solve(F, -g_c)[:, None] * np.ones_like(t)[None, :]
        if np.any(g_s):
            amp = np.linalg.solve(1j * w_sine * np.eye(5) - F, g_s.astype(complex))
            x = x + np.imag(amp[:, None] * np.exp(1j * w_sine * (t - p.step_time))[None, :])
        return x

    t_eval = np.asarray(t_eval, dtype=float)
    t_end = float(t_eval[-1])
    breaks = [b for b in (p.step_time,) if p.profile != 0 and 0.0 < b < t_end]
    x = np.zeros(5) if x0 is None else np.asarray(x0, dtype=float)
    columns = np.empty((5, len(t_eval)))
    t_a = 0.0
    for t_b in breaks + [t_end]:
        g_c, g_s = stretch(t_a, t_b)
        d = (x - particular(np.array([t_a]), g_c, g_s)[:, 0]) / scale
        c = V_inv @ d
        inside = (t_eval >= t_a) & ((t_eval < t_b) | (t_b == t_end))
        tt = t_eval[inside]
        homogeneous = scale[:, None] * np.real(V @ (c[:, None] * np.exp(lam[:, None] * (tt - t_a)[None, :])))
        columns[:, inside] = particular(tt, g_c, g_s) + homogeneous
        end = scale * np.real(V @ (c * np.exp(lam * (t_b - t_a))))
        x = particular(np.array([t_b]), g_c, g_s)[:, 0] + end
        t_a = t_b
    return columns


def simulate(p: NozzleParams, axis: str, t_eval: np.ndarray, command_in: float = 0.0, m_aero: float = 0.0, x0=None) -> dict:
    """The FMU's outputs of one axis on t_eval (from x0, default rest)."""
    theta, w, dp, x_b, v_b = _states(p, axis, t_eval, command_in, m_aero, x0)
    theta_cmd, _ = axis_inputs(p, axis, t_eval, command_in, m_aero)
    y = p.r_arm * theta - x_b
    return {
        f"nozzle_angle_{axis}": theta,
        f"nozzle_rate_{axis}": w,
        f"nozzle_command_{axis}": theta_cmd,
        f"pressure_difference_{axis}": dp,
        f"actuator_force_{axis}": p.A_piston * dp,
        f"hinge_moment_{axis}": p.r_arm * p.A_piston * dp,
        f"actuator_stroke_{axis}": y,
        f"anchoring_deflection_{axis}": x_b,
        f"valve_flow_{axis}": p.A_piston * p.K_v * (p.r_arm * theta_cmd - y),
        "time": np.asarray(t_eval),
    }


def activities(p: NozzleParams, axis: str, t_end: float, dt: float = 5e-6) -> dict:
    """Eq. 3.3's activity, the integral of |power| over [0, t_end], of each storage and dissipative
    element of one axis (no input): the reference's states on a grid of dt (closed form), each
    element's power from `powers`, |p| integrated by the trapezoid rule. Accuracy ~ (w dt)^2 / 12
    of the fastest ringing (the body's 417 Hz: 1.4e-5 at dt = 5e-6)."""
    n = int(round(t_end / dt))
    t = np.linspace(0.0, t_end, n + 1)
    x = _states(p, axis, t, 0.0, 0.0, None)
    theta_cmd, moment = axis_inputs(p, axis, t)
    pw = powers(p, x, theta_cmd, moment)
    return {name: float(np.trapezoid(np.abs(pw[name]), t)) for name in STORAGE + DISSIPATION}


def static_deflection(p: NozzleParams, moment: float, theta_cmd: float = 0.0) -> dict:
    """The axis at rest under a constant torque M and a held command, by hand. The nozzle holds
    r F = K_b theta - M through the rod's force F = A dp; the anchoring gives x_b = -F / K_a; the
    leakage dp / R must be made up by the valve, A K_v (r theta_cmd - y) = dp / R, so the stroke
    lags the command by y_err = F / (A^2 R K_v); theta = (y + x_b) / r. With
    K_s = r^2 / (1/K_a + 1/(A^2 R K_v)): theta = (K_s theta_cmd + M) / (K_s + K_b). Loop open
    (K_v = 0): the leakage relieves the oil, dp = 0 and theta = M / K_b."""
    ks = p.servo_static_stiffness
    theta = (ks * theta_cmd + moment) / (ks + p.K_bearing)
    force = (p.K_bearing * theta - moment) / p.r_arm
    dp = force / p.A_piston
    x_b = -force / p.K_anchor
    return {"nozzle_angle": theta, "actuator_force": force, "pressure_difference": dp, "hinge_moment": p.r_arm * force,
            "anchoring_deflection": x_b, "actuator_stroke": p.r_arm * theta - x_b, "valve_flow": dp / p.R_leakage}
