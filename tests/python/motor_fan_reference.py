"""Hand computations for the MotorFan model (docs/motor-fan-spec.md; chapter 3, sections 3.1-3.3).

Everything here is computed with numpy from the spec's formulas and the FMU's own parameter values
(the start values of modelDescription.xml, possibly overridden by a test); nothing comes from a
previous run of the FMU.

* Motor torque of the steady-state T-equivalent circuit (spec, "Steady state by hand"), per phase,
  V = U_supply / sqrt(3), ws = 2 pi f_supply, slip s = 1 - p w_m / ws:
      Z   = R_s + j ws L_s_sigma + (j ws L_m || (R_r/s + j ws L_r_sigma))
      I_s = V / Z,   I_r = I_s j ws L_m / (j ws L_m + R_r/s + j ws L_r_sigma)
      T_m = 3 |I_r|^2 (R_r / s) / (ws / p)
* Load torque seen on the high-speed shaft with power flowing to the fan (spec, level a):
      T_load(w_m) = k (w_m/N)^2 / (N eta)
* Direct-on-line equilibrium: the root of T_m(w) = T_load(w) on the stable branch of the motor curve
  (between the breakdown speed and the synchronous speed, where dT_m/dw < 0), found by bisection.
* Equivalent fan inertia on the high-speed axis (eqs. 3.4-3.7): J_eq = J_fan / N^2. With the
  reducer's efficiency and power flowing towards the fan (the spec's T_ls = N eta T_shaft), the fan
  equation J_fan dw_fan/dt = N eta T_shaft - ... gives, with w_fan = w_m / N,
      T_shaft = J_fan / (N^2 eta) dw_m/dt + ...,
  i.e. the inertia the shaft actually sees is J_eq_forward = J_fan / (N^2 eta) (3 % above J_eq for
  eta = 0.97).
* Linear two-inertia theory of the driveshaft mode (spring K between J_m and the fan inertia J):
      motor speed imposed (eq. 3.8):  f = sqrt(K / J) / (2 pi)
      motor inertia free:             f = sqrt(K (1/J_m + 1/J)) / (2 pi)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np


@dataclass(frozen=True)
class MotorFanParams:
    """The physical parameters of the spec (names as in modelDescription.xml)."""

    J_motor: float
    J_fan: float
    gear_ratio: float
    gear_efficiency: float
    K_shaft: float
    D_shaft: float
    k_fan: float
    R_s: float
    R_r: float
    L_s_sigma: float
    L_r_sigma: float
    L_m: float
    pole_pairs: float
    U_supply: float
    f_supply: float
    speed_setpoint: float
    ramp_time: float

    @classmethod
    def from_values(cls, values: dict) -> "MotorFanParams":
        """From a {name: value} dict (e.g. modelDescription start values updated by a test's overrides)."""
        return cls(**{f.name: float(values[f.name]) for f in fields(cls)})

    def with_(self, **changes) -> "MotorFanParams":
        return replace(self, **changes)

    # ---- electrical ----
    @property
    def omega_supply(self) -> float:
        return 2.0 * math.pi * self.f_supply

    @property
    def synchronous_speed(self) -> float:
        """Mechanical synchronous speed ws / p (rad/s)."""
        return self.omega_supply / self.pole_pairs

    # ---- inertias ----
    @property
    def J_eq(self) -> float:
        """Fan inertia on the high-speed axis, eq. 3.6/3.7 (no efficiency)."""
        return self.J_fan / self.gear_ratio**2

    @property
    def J_eq_forward(self) -> float:
        """Fan inertia seen by the shaft while power flows towards the fan: J_fan / (N^2 eta)."""
        return self.J_fan / (self.gear_ratio**2 * self.gear_efficiency)


def motor_torque(p: MotorFanParams, w_m) -> np.ndarray:
    """Steady-state equivalent-circuit torque (N.m) at motor speed(s) w_m (rad/s); w_m < ws/p."""
    w_m = np.asarray(w_m, dtype=float)
    ws = p.omega_supply
    s = 1.0 - p.pole_pairs * w_m / ws
    V = p.U_supply / math.sqrt(3.0)
    z_m = 1j * ws * p.L_m
    z_r = p.R_r / s + 1j * ws * p.L_r_sigma
    z = p.R_s + 1j * ws * p.L_s_sigma + z_m * z_r / (z_m + z_r)
    i_s = V / z
    i_r = i_s * z_m / (z_m + z_r)
    return 3.0 * np.abs(i_r) ** 2 * (p.R_r / s) / (ws / p.pole_pairs)


def motor_torque_slope(p: MotorFanParams, w_m: float) -> float:
    """dT_m/dw (N.m.s/rad) of the equivalent-circuit curve, central difference."""
    h = 1e-4 * p.synchronous_speed
    return float((motor_torque(p, w_m + h) - motor_torque(p, w_m - h)) / (2.0 * h))


def load_torque(p: MotorFanParams, w_m) -> np.ndarray:
    """Aerodynamic torque on the high-speed shaft, power towards the fan: k (w_m/N)^2 / (N eta)."""
    w_m = np.asarray(w_m, dtype=float)
    return p.k_fan * (w_m / p.gear_ratio) ** 2 / (p.gear_ratio * p.gear_efficiency)


def breakdown(p: MotorFanParams) -> tuple[float, float]:
    """(speed, torque) of the motor curve's maximum on [0, ws/p): dense grid, then golden section."""
    w_sync = p.synchronous_speed
    grid = np.linspace(0.0, w_sync * (1.0 - 1e-6), 20001)
    k = int(np.argmax(motor_torque(p, grid)))
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    g = (math.sqrt(5.0) - 1.0) / 2.0
    for _ in range(100):
        c, d = b - g * (b - a), a + g * (b - a)
        if motor_torque(p, c) > motor_torque(p, d):
            b = d
        else:
            a = c
    w = 0.5 * (a + b)
    return float(w), float(motor_torque(p, w))


def equilibrium(p: MotorFanParams) -> tuple[float, float]:
    """Direct-on-line steady state (speed rad/s, shaft torque N.m): root of T_m(w) = T_load(w) on the
    stable branch [w_breakdown, w_sync), by bisection (T_m - T_load > 0 at breakdown, < 0 near ws/p)."""
    w_bd, _ = breakdown(p)
    lo, hi = w_bd, p.synchronous_speed * (1.0 - 1e-12)
    f = lambda w: float(motor_torque(p, w) - load_torque(p, w))  # noqa: E731
    if not (f(lo) > 0.0 > f(hi)):
        raise ValueError("no equilibrium on the stable branch: the load exceeds the breakdown torque")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if f(mid) > 0.0:
            lo = mid
        else:
            hi = mid
    w = 0.5 * (lo + hi)
    return w, float(load_torque(p, w))


def frequency_motor_imposed(p: MotorFanParams, J: float | None = None) -> float:
    """Eq. 3.8: driveshaft resonance with the motor speed imposed, sqrt(K / J) / (2 pi) (Hz)."""
    J = p.J_eq_forward if J is None else J
    return math.sqrt(p.K_shaft / J) / (2.0 * math.pi)


def frequency_two_inertia(p: MotorFanParams, J: float | None = None) -> float:
    """Free-free two-inertia resonance, sqrt(K (1/J_m + 1/J)) / (2 pi) (Hz)."""
    J = p.J_eq_forward if J is None else J
    return math.sqrt(p.K_shaft * (1.0 / p.J_motor + 1.0 / J)) / (2.0 * math.pi)


def two_inertia_damping_ratio(p: MotorFanParams, motor_slope: float, w_m: float) -> float:
    """Damping ratio of the free two-inertia shaft mode, linearised at motor speed w_m.

    Linear model on the high-speed axis (J = J_eq_forward, power towards the fan):
        J_m x1' = c_m x1 - T,  J x2' = T - c_l x2,  T = K theta + D (x1 - x2),  theta' = x1 - x2
    with c_m = dT_m/dw (the motor curve's slope; > 0 is negative damping) and
    c_l = dT_load/dw = 2 k w_m / (N^3 eta). Returns -Re(lambda)/|lambda| of the oscillatory pair.
    """
    J = p.J_eq_forward
    c_l = 2.0 * p.k_fan * w_m / (p.gear_ratio**3 * p.gear_efficiency)
    K, D, Jm = p.K_shaft, p.D_shaft, p.J_motor
    # states (x1, x2, theta)
    A = np.array([
        [(motor_slope - D) / Jm, D / Jm, -K / Jm],
        [D / J, (-D - c_l) / J, K / J],
        [1.0, -1.0, 0.0],
    ])
    lam = np.linalg.eigvals(A)
    osc = lam[np.abs(lam.imag) > 1e-9]
    if len(osc) == 0:
        return 1.0
    l0 = osc[0]
    return float(-l0.real / abs(l0))


def runup_linear_limit(p: MotorFanParams, zeta_max: float = 0.15) -> float:
    """Highest motor speed below breakdown up to which the run-up stays a lightly damped linear
    two-inertia oscillator: |damping ratio| <= zeta_max (the damped frequency is then within
    1 - sqrt(1 - zeta_max^2) = 1.1 % of the undamped one). Above it, the steep positive slope of the
    motor curve near breakdown (negative damping) pulls the ringing frequency down."""
    w_bd, _ = breakdown(p)
    for w in np.linspace(0.0, w_bd, 401)[1:]:
        if abs(two_inertia_damping_ratio(p, motor_torque_slope(p, w), w)) > zeta_max:
            return float(w)
    return w_bd
