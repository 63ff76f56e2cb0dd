"""Closed-form reference for the RlcCircuit model (docs/rlc-circuit-spec.md, "Closed form").

Everything here is physics, computed with numpy from the spec's equations; nothing comes from a
previous run of the FMU.

    x = (i_L, u_C),  x' = A x + b u(t),  u(t) = U sin(w t) + u_in,  w = 2 pi f
    A = [[-R/L, -1/L], [1/C, -1/(R_load C)]],  b = [1/L, 0]

Because the system is linear, the response to U sin(w t) + u0 (u0 constant on a segment that starts
at t0 with state x(t0)) is the superposition

    x(t) = x_p(t) + x_inf + e^{A (t - t0)} (x(t0) - x_p(t0) - x_inf)

with the sinusoidal steady state x_p(t) = Im(X e^{j w t}), X = (j w I - A)^-1 b U (complex phasor)
and the DC steady state x_inf = -A^-1 b u0. e^{A t} comes from the eigen-decomposition of the 2x2 A
(A = V diag(lambda) V^-1, e^{A t} = V diag(e^{lambda t}) V^-1). The R-L branch is the same with a
scalar "matrix" -R/L: i_rl(t) = Im(I e^{j w t}) + u0/R + (i_rl(t0) - Im(I e^{j w t0}) - u0/R)
e^{-(t - t0)/tau}, tau = L/R, I = U / (R + j w L).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

# The full circuit's elements (spec, "Energy"): each has an activity, the storage and dissipative
# ones a share; the runtime adds the energy balance.
ELEMENTS = ("voltage_source", "line_resistance", "line_inductance", "load_capacitance", "load_resistance")
# The circuit's outputs, each with its closed form below.
OUTPUTS = ("u_source", "i_absorbed", "u_capacitor", "i_low_frequency", "i_high_frequency")
# Every output the modelDescription lists.
ALL_OUTPUTS = (
    OUTPUTS
    + tuple(f"activity_{e}" for e in ELEMENTS)
    + tuple(f"share_{e}" for e in ELEMENTS if e != "voltage_source")
    + ("power_balance_residual", "power_balance_relative")
)


@dataclass(frozen=True)
class RlcParams:
    """Parameters, the (constant) input and the initial states; defaults are the spec's start values."""

    U_amplitude: float = 10.0
    frequency: float = 50.0
    R_series: float = 1.0
    L_series: float = 0.01
    C_load: float = 1e-4
    R_load: float = 10.0
    u_in: float = 0.0
    i_L: float = 0.0
    u_C: float = 0.0
    i_rl: float = 0.0

    def with_(self, **changes) -> "RlcParams":
        return replace(self, **changes)

    @property
    def omega(self) -> float:
        return 2.0 * np.pi * self.frequency

    @property
    def A(self) -> np.ndarray:
        R, L, C, Rl = self.R_series, self.L_series, self.C_load, self.R_load
        return np.array([[-R / L, -1.0 / L], [1.0 / C, -1.0 / (Rl * C)]])

    @property
    def b(self) -> np.ndarray:
        return np.array([1.0 / self.L_series, 0.0])

    # ---- phasors (sinusoidal steady state of the U sin(w t) part) ----
    @property
    def X(self) -> np.ndarray:
        """Complex phasor of (i_L, u_C): X = (j w I - A)^-1 b U."""
        return np.linalg.solve(1j * self.omega * np.eye(2) - self.A, self.b * self.U_amplitude)

    @property
    def I_rl(self) -> complex:
        """Complex phasor of the R-L branch current: U / (R + j w L)."""
        return self.U_amplitude / (self.R_series + 1j * self.omega * self.L_series)

    @property
    def I_low(self) -> complex:
        """Complex phasor of the quasi-static current u / (R_series + R_load) (a real multiple of U)."""
        return self.U_amplitude / (self.R_series + self.R_load)

    # ---- DC steady state of the u_in part ----
    @property
    def x_inf(self) -> np.ndarray:
        return -np.linalg.solve(self.A, self.b * self.u_in)

    @property
    def eig(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        lam, V = np.linalg.eig(self.A)
        return lam, V, np.linalg.inv(V)


def expm_At(p: RlcParams, t: np.ndarray) -> np.ndarray:
    """e^{A t} for every t (shape (n, 2, 2)), from the eigen-decomposition of A."""
    lam, V, Vinv = p.eig
    t = np.asarray(t, dtype=float)
    E = np.exp(np.multiply.outer(t, lam))  # (n, 2)
    M = np.einsum("ik,nk,kj->nij", V, E, Vinv)
    return M.real


def sinusoid_xp(p: RlcParams, t: np.ndarray) -> np.ndarray:
    """x_p(t) = Im(X e^{j w t}), shape (n, 2)."""
    t = np.asarray(t, dtype=float)
    return np.imag(np.multiply.outer(np.exp(1j * p.omega * t), p.X))


def _irl_p(p: RlcParams, t: np.ndarray) -> np.ndarray:
    return np.imag(p.I_rl * np.exp(1j * p.omega * np.asarray(t, dtype=float)))


def source(p: RlcParams, t: np.ndarray) -> np.ndarray:
    return p.U_amplitude * np.sin(p.omega * np.asarray(t, dtype=float)) + p.u_in


def segment(p: RlcParams, t: np.ndarray, t0: float = 0.0) -> dict[str, np.ndarray]:
    """States and outputs for t >= t0, with u_in = p.u_in constant on the segment and the states at t0
    given by p.i_L, p.u_C, p.i_rl."""
    t = np.asarray(t, dtype=float)
    x0 = np.array([p.i_L, p.u_C])
    xp0 = sinusoid_xp(p, np.array([t0]))[0]
    x = sinusoid_xp(p, t) + p.x_inf + np.einsum("nij,j->ni", expm_At(p, t - t0), x0 - xp0 - p.x_inf)

    tau = p.L_series / p.R_series
    irl_inf = p.u_in / p.R_series
    irl = _irl_p(p, t) + irl_inf + (p.i_rl - _irl_p(p, np.array([t0]))[0] - irl_inf) * np.exp(-(t - t0) / tau)

    u = source(p, t)
    return {
        "i_L": x[:, 0],
        "u_C": x[:, 1],
        "i_rl": irl,
        "u_source": u,
        "i_absorbed": x[:, 0],
        "u_capacitor": x[:, 1],
        "i_low_frequency": u / (p.R_series + p.R_load),
        "i_high_frequency": irl,
    }


def step_response(p: RlcParams, t: np.ndarray, t_step: float, u_after: float) -> dict[str, np.ndarray]:
    """u_in = p.u_in for t < t_step and u_after from t_step on (the states are continuous at t_step).

    At t == t_step itself the direct-feedthrough outputs (u_source, i_low_frequency) take the value
    BEFORE the step: fmpy samples the outputs at a communication point before it applies the input
    for the next step (TOOLS.md: rows are stamped at communication points)."""
    t = np.asarray(t, dtype=float)
    at_step = np.isclose(t, t_step, rtol=0, atol=1e-12)
    before = (t < t_step) | at_step
    after = ~before
    s0 = segment(p, t)
    at = segment(p, np.array([t_step]))
    p1 = p.with_(u_in=u_after, i_L=at["i_L"][0], u_C=at["u_C"][0], i_rl=at["i_rl"][0])
    s1 = segment(p1, t, t0=t_step)
    out = {k: np.where(after, s1[k], s0[k]) for k in s0}
    # continuous states: at t_step both segments agree; take segment 0 (identical up to round-off)
    return out


def transient_envelope_iL(p: RlcParams, t: float, t0: float = 0.0) -> float:
    """Upper bound of |i_L(t) - i_L steady state| for the segment starting at t0: the i_L component
    of e^{A (t - t0)} (x0 - x_p(t0) - x_inf), bounded mode by mode (sum over eigenmodes of
    |V[0,k] c_k| e^{Re(lambda_k) (t - t0)})."""
    lam, V, Vinv = p.eig
    x0 = np.array([p.i_L, p.u_C])
    c = Vinv @ (x0 - sinusoid_xp(p, np.array([t0]))[0] - p.x_inf)
    return float(np.sum(np.abs(V[0, :] * c) * np.exp(lam.real * (t - t0))))


def transient_envelope_irl(p: RlcParams, t: float, t0: float = 0.0) -> float:
    """|i_rl(t) - i_rl steady state| for the segment starting at t0 (a single decaying exponential)."""
    tau = p.L_series / p.R_series
    c = p.i_rl - _irl_p(p, np.array([t0]))[0] - p.u_in / p.R_series
    return float(abs(c) * np.exp(-(t - t0) / tau))
