"""An independent reference for MemsAccelerometer (docs/mems-accelerometer-spec.md): the spec's
equations and closed forms written out here with numpy and scipy, never values from a run of the FMU.

States x = (x, v, u, w): the proof mass's displacement towards electrode 1 and its velocity, relative
to the frame; the read-out filter's output u and its rate over its angular frequency w = u' / wn.

    k        = 2 E t w_b^3 / L^3                         folded flexure (Tang, Nguyen, Howe 1989)
    lambda   = (mu / p) sqrt(pi R T / (2 M))              mean free path of air (kinetic theory)
    mu_sq    = mu / (1 + 9.638 (lambda / g)^1.159)         squeeze film, Veijola et al. 1995
    mu_sl    = mu / (1 + 2 lambda / d)                     slide film, first-order slip
    b_sq(x)  = mu_sq A t^2 (1 / (g - x)^3 + 1 / (g + x)^3) the finger gaps (Reynolds strip, L >> t)
    b_sl     = mu_sl A_plate / d                           under the mass (Couette)
    C_1, C_2 = eps0 A / (g - x), eps0 A / (g + x)
    W_1, W_2 = V_c^2 + V_b(t)^2, V_c^2                     mean squares on the electrodes
    F_e      = W_1 eps0 A / (2 (g - x)^2) - W_2 eps0 A / (2 (g + x)^2)
    m dv/dt  = -m a(t) - k x - (b_sq(x) + b_sl) v + F_e,   dx/dt = v
    V_dem    = V_c (C_2 - C_1) / C_f
    u''      = wn^2 (V_dem - u) - sqrt(2) wn u',           wn = 2 pi f_filter (Butterworth)
    V_out    = G u

The closed forms of the spec's acceptance figures: x / a = -m / k_eff (k_eff = k - 2 eps0 A V_c^2 /
g^3), sqrt(k / m), V_pi = sqrt(8 k g^3 / (27 eps0 A)) (one electrode, carrier off), and the bandwidth
of H(s) = k_eff / (m s^2 + b s + k_eff) x wn^2 / (s^2 + sqrt(2) wn s + wn^2).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

EPS0 = 8.8541878128e-12  # F/m, CODATA 2018
MU_AIR = 1.85e-5  # Pa s, air at 25 degrees C
M_AIR = 0.0289647  # kg/mol
R_GAS = 8.314462618  # J/(mol K)
G_N = 9.80665  # m/s2

FIELDS = ("profile", "a_step", "a_sine", "f_sine", "t_start", "m_proof", "E_beam", "L_beam", "w_beam", "t_structure", "A_electrode",
          "gap", "A_plate", "d_substrate", "p_gas", "T_gas", "x_stop", "V_carrier", "V_bias", "t_bias_ramp", "C_feedback",
          "f_filter", "G_out")


@dataclasses.dataclass(frozen=True)
class MemsParams:
    profile: int
    a_step: float
    a_sine: float
    f_sine: float
    t_start: float
    m_proof: float
    E_beam: float
    L_beam: float
    w_beam: float
    t_structure: float
    A_electrode: float
    gap: float
    A_plate: float
    d_substrate: float
    p_gas: float
    T_gas: float
    x_stop: float
    V_carrier: float
    V_bias: float
    t_bias_ramp: float
    C_feedback: float
    f_filter: float
    G_out: float

    @classmethod
    def from_values(cls, values: dict) -> "MemsParams":
        return cls(**{f: (int(values[f]) if f == "profile" else float(values[f])) for f in FIELDS})

    def with_(self, **changes) -> "MemsParams":
        return dataclasses.replace(self, **changes)

    # ---- the lumped parameters from the dimensions ----
    @property
    def k(self) -> float:
        """Folded flexure: four folds of two fixed-guided beams (12 E I / L^3 each, I = t w^3 / 12) in series."""
        beam = 12.0 * self.E_beam * (self.t_structure * self.w_beam**3 / 12.0) / self.L_beam**3
        return 4.0 * (beam / 2.0)

    @property
    def mean_free_path(self) -> float:
        return MU_AIR / self.p_gas * math.sqrt(math.pi * R_GAS * self.T_gas / (2.0 * M_AIR))

    @property
    def mu_squeeze(self) -> float:
        return MU_AIR / (1.0 + 9.638 * (self.mean_free_path / self.gap) ** 1.159)

    @property
    def mu_slide(self) -> float:
        return MU_AIR / (1.0 + 2.0 * self.mean_free_path / self.d_substrate)

    def b_squeeze(self, x: float = 0.0) -> float:
        # Each side: N fingers of overlap l and thickness t, the strip's mu l t^3 / h^3, with N l = A / t.
        length = self.A_electrode / self.t_structure
        return sum(self.mu_squeeze * length * self.t_structure**3 / h**3 for h in (self.gap - x, self.gap + x))

    @property
    def b_slide(self) -> float:
        return self.mu_slide * self.A_plate / self.d_substrate

    @property
    def C0(self) -> float:
        return EPS0 * self.A_electrode / self.gap

    @property
    def k_e(self) -> float:
        """The carrier's electrostatic softening at rest: d/dx of W eps0 A / (2 (g - x)^2) on both sides."""
        return 2.0 * EPS0 * self.A_electrode * self.V_carrier**2 / self.gap**3

    @property
    def k_eff(self) -> float:
        return self.k - self.k_e

    @property
    def omega0(self) -> float:
        return math.sqrt(self.k / self.m_proof)

    @property
    def omega_eff(self) -> float:
        return math.sqrt(self.k_eff / self.m_proof)

    @property
    def Q(self) -> float:
        return math.sqrt(self.m_proof * self.k_eff) / (self.b_squeeze() + self.b_slide)

    @property
    def V_pull_in(self) -> float:
        """Senturia, Microsystem Design, section 6.4: one electrode, linear spring."""
        return math.sqrt(8.0 * self.k * self.gap**3 / (27.0 * EPS0 * self.A_electrode))

    @property
    def V_pull_in_symmetric(self) -> float:
        return math.sqrt(self.k * self.gap**3 / (2.0 * EPS0 * self.A_electrode))

    @property
    def x_per_g(self) -> float:
        return self.m_proof * G_N / self.k_eff

    @property
    def sensitivity(self) -> float:
        """Static V_out per m/s2: x = -m a / k_eff, C_2 - C_1 = 2 C0 (-x) / g, V_dem = V_c (C_2 - C_1) / C_f."""
        return self.G_out * self.V_carrier * (2.0 * self.C0 / self.gap) * (self.m_proof / self.k_eff) / self.C_feedback

    def relative_response(self, f_hz):
        """|H(j w) / H(0)| of the linearised sensor (bias off), at frequencies f_hz."""
        s = 2j * np.pi * np.asarray(f_hz, dtype=float)
        wn = 2 * np.pi * self.f_filter
        b = self.b_squeeze() + self.b_slide
        h = self.k_eff / (self.m_proof * s**2 + b * s + self.k_eff) * wn**2 / (s**2 + math.sqrt(2.0) * wn * s + wn**2)
        return np.abs(h)

    def bandwidth(self) -> float:
        """The lowest frequency where |H / H(0)| leaves [1/sqrt 2, sqrt 2]: a grid of 0.1 % steps, then brentq."""
        f = np.geomspace(1.0, 1e3 * max(self.omega_eff / (2 * math.pi), self.f_filter), 20000)
        g = self.relative_response(f)
        outside = np.nonzero((g < 1 / math.sqrt(2)) | (g > math.sqrt(2)))[0]
        i = int(outside[0])
        level = 1 / math.sqrt(2) if g[i] < 1 / math.sqrt(2) else math.sqrt(2)
        return brentq(lambda ff: float(self.relative_response(ff)) - level, f[i - 1], f[i], xtol=1e-12, rtol=1e-14)

    # ---- the time functions ----
    def acceleration(self, t: float) -> float:
        if t < self.t_start:
            return 0.0
        if self.profile == 1:
            return self.a_step
        return self.a_sine * math.sin(2 * math.pi * self.f_sine * (t - self.t_start))

    def bias(self, t: float) -> float:
        if self.t_bias_ramp > 0.0 and t < self.t_bias_ramp:
            return self.V_bias * max(t, 0.0) / self.t_bias_ramp
        return self.V_bias

    def electrostatic_force(self, x: float, t: float) -> float:
        w1 = self.V_carrier**2 + self.bias(t) ** 2
        w2 = self.V_carrier**2
        return EPS0 * self.A_electrode * (w1 / (2 * (self.gap - x) ** 2) - w2 / (2 * (self.gap + x) ** 2))

    def rhs(self, t: float, y) -> list:
        x, v, u, w = y
        wn = 2 * math.pi * self.f_filter
        dv = (-self.m_proof * self.acceleration(t) - self.k * x - (self.b_squeeze(x) + self.b_slide) * v + self.electrostatic_force(x, t)) / self.m_proof
        c1, c2 = EPS0 * self.A_electrode / (self.gap - x), EPS0 * self.A_electrode / (self.gap + x)
        v_dem = self.V_carrier * (c2 - c1) / self.C_feedback
        du = wn * w
        dw = (wn**2 * (v_dem - u) - math.sqrt(2.0) * wn * du) / wn
        return [v, dv, du, dw]

    def static_equilibrium(self, v_bias: float) -> float:
        """Carrier off, a = 0: the stable root of k x = eps0 A V^2 / (2 (g - x)^2) below g / 3."""
        f = lambda x: self.k * x - EPS0 * self.A_electrode * v_bias**2 / (2 * (self.gap - x) ** 2)
        return brentq(f, 0.0, self.gap / 3.0, xtol=1e-20, rtol=1e-15)


def simulate(p: MemsParams, t_eval: np.ndarray, x0=(0.0, 0.0, 0.0, 0.0), rtol: float = 1e-12) -> dict:
    """The equations above by DOP853, piecewise between the profile's start and the bias ramp's end
    (no stop contact: the runs compared stay clear of the stops)."""
    breaks = sorted({0.0, float(t_eval[-1])} | {b for b in (p.t_start, p.t_bias_ramp) if 0.0 < b < t_eval[-1]})
    y = np.array(x0, dtype=float)
    rows = np.zeros((len(t_eval), 4))
    for a, b in zip(breaks[:-1], breaks[1:]):
        sel = (t_eval >= a) & ((t_eval < b) if b < breaks[-1] else (t_eval <= b))
        sol = solve_ivp(p.rhs, (a, b), y, method="DOP853", rtol=rtol, atol=[1e-22, 1e-17, 1e-16, 1e-16], dense_output=True)
        assert sol.success, sol.message
        if np.any(sel):
            rows[sel] = sol.sol(t_eval[sel]).T
        y = sol.y[:, -1]
    x, v, u, _ = rows.T
    c1, c2 = EPS0 * p.A_electrode / (p.gap - x), EPS0 * p.A_electrode / (p.gap + x)
    return {
        "displacement": x,
        "velocity": v,
        "C_1": c1,
        "C_2": c2,
        "delta_C": c1 - c2,
        "V_demodulated": p.V_carrier * (c2 - c1) / p.C_feedback,
        "V_out": p.G_out * u,
        "F_electrostatic": np.array([p.electrostatic_force(xi, ti) for xi, ti in zip(x, t_eval)]),
    }
