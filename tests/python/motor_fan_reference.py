"""Hand computations for the MotorFan model (docs/motor-fan-spec.md; chapter 3, sections 3.1-3.3).

Everything here is computed with numpy/scipy from the spec's formulas and the FMU's own parameter
values (the start values of modelDescription.xml, possibly overridden by a test); nothing comes from
a previous run of the FMU, and nothing from the FMU's Rust code (the table reading below is written
from Akima's paper and CombiTable1D's documented behaviour, not from models/components/src/table.rs).

* Motor torque below level d from the torque-speed table (book file Chap3_CoolingTowerFan.mo,
  component TorqueSpeed, a CombiTable1D; spec, "Motor"), points (w_i, T_i), i = 1..10, read
      linearly (smoothness LinearSegments): straight segments; beyond the ends the end segment's
          line (extrapolation LastTwoPoints);
      by Akima (smoothness ContinuousDerivative; H. Akima, J. ACM 17(4), 1970): on each segment the
          cubic Hermite polynomial through its two points with Akima's slopes there; beyond the
          ends the straight line along the curve's slope at the end point (CombiTable1D's
          LastTwoPoints: "the derivative at the first/last table points"). Inside the table
          scipy.interpolate.Akima1DInterpolator (Akima's slopes with his end extension of the
          segment slopes, m_-1 = 2 m_0 - m_1, m_-2 = 3 m_0 - 2 m_1, and where both of Akima's
          weights vanish the mean of the two neighbouring segment slopes, as CombiTable1D); its
          derivative gives the end slopes.
  motor_table_interpolation 0 reads linearly at levels a and b, by Akima at level c (the book files
  Steady_State, Transient_Dynamic and Transient_Resonance); 1 linear, 2 Akima. motor_model = 2 and
  level d use the equivalent circuit instead.
* Equivalent-circuit steady state (spec, "Steady state by hand"), per winding, V = U_supply (delta) or U_supply / sqrt(3) (star),
  ws = 2 pi f_supply, slip s = 1 - p w_m / ws:
      Z   = R_s + j ws L_s_sigma + (j ws L_m || (R_r/s + j ws L_r_sigma))
      I_s = V / Z,   I_r = I_s j ws L_m / (j ws L_m + R_r/s + j ws L_r_sigma)
      T_m = 3 |I_r|^2 (R_r / s) / (ws / p),   P = 3 Re(V conj(I_s))
  It gives the level-d torque's steady state, and at every level the current and the power drawn
  (direct-on-line: at the motor speed; converter-fed: the current at the stable slip whose circuit
  torque is the motor torque, the power T_m w_m).
* Fan load (book file, component quadraticSpeedDependentTorque): T_fan = T_fan_nominal
  (w_fan / speed_fan_nominal)^2, i.e. k = T_fan_nominal / speed_fan_nominal^2; seen on the
  high-speed shaft with power flowing to the fan (spec, level a): T_load(w_m) = k (w_m/N)^2 / (N eta).
* Direct-on-line equilibrium: the speed a start from standstill runs up to, i.e. the first speed
  above 0 at which the excess torque T_m(w) - T_load(w) falls through zero (found on a dense grid,
  then by bisection); there dT_m/dw < dT_load/dw, so it is stable.
* Equivalent fan inertia on the high-speed axis (eqs. 3.4-3.7): J_eq = J_fan / N^2. With the
  reducer's efficiency and power flowing towards the fan (the spec's T_ls = N eta T_shaft), the fan
  equation J_fan dw_fan/dt = N eta T_shaft - ... gives, with w_fan = w_m / N,
      T_shaft = J_fan / (N^2 eta) dw_m/dt + ...,
  i.e. the inertia the shaft actually sees is J_eq_forward = J_fan / (N^2 eta) (6.4 % above J_eq for
  eta = 0.94).
* Linear two-inertia theory of the driveshaft mode (spring K between J_m and the fan inertia J):
      motor speed imposed (eq. 3.8):  f = sqrt(K / J) / (2 pi);  decay rate (D + c_l) / (2 J)
      motor inertia free:             f = sqrt(K (1/J_m + 1/J)) / (2 pi)
  with c_l = dT_load/dw the fan's load slope.
* Set point: a ramp 0 -> speed_setpoint in ramp_time through the second-order filter
  wn^2 / (s^2 + 2 zeta wn s + wn^2) (setpoint_filter 1 or 2), simulated with scipy.signal.lsim.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np
from scipy.interpolate import Akima1DInterpolator
from scipy.signal import StateSpace, lsim

TABLE_POINTS = 10

#: The book's table (book file Chap3_CoolingTowerFan.mo, component TorqueSpeed): rad/s, N m.
BOOK_TABLE = ((0.0, 454.0), (80.0, 579.0), (160.0, 784.0), (220.0, 997.0), (240.0, 1057.0),
              (250.0, 1071.0), (260.0, 1060.0), (280.0, 919.0), (300.0, 500.0), (314.0, 0.0))

_INTEGERS = ("level", "motor_model", "motor_table_interpolation", "setpoint_filter", "winding_connection")


@dataclass(frozen=True)
class MotorFanParams:
    """The physical parameters of the spec (names as in modelDescription.xml); the table's points
    as two tuples (motor_table_speed_1..10, motor_table_torque_1..10)."""

    level: int
    motor_model: int
    motor_table_interpolation: int
    table_speed: tuple
    table_torque: tuple
    J_motor: float
    J_fan: float
    gear_ratio: float
    gear_efficiency: float
    K_shaft: float
    D_shaft: float
    T_fan_nominal: float
    speed_fan_nominal: float
    R_s: float
    R_r: float
    L_s_sigma: float
    L_r_sigma: float
    L_m: float
    pole_pairs: float
    U_supply: float
    winding_connection: int
    f_supply: float
    speed_setpoint: float
    ramp_time: float
    setpoint_filter: int
    filter_frequency_below: float
    filter_frequency_above: float
    filter_damping: float

    @classmethod
    def from_values(cls, values: dict) -> "MotorFanParams":
        """From a {name: value} dict (e.g. modelDescription start values updated by a test's overrides)."""
        kw = {}
        for f in fields(cls):
            if f.name == "table_speed":
                kw[f.name] = tuple(float(values[f"motor_table_speed_{i + 1}"]) for i in range(TABLE_POINTS))
            elif f.name == "table_torque":
                kw[f.name] = tuple(float(values[f"motor_table_torque_{i + 1}"]) for i in range(TABLE_POINTS))
            elif f.name in _INTEGERS:
                kw[f.name] = int(values[f.name])
            else:
                kw[f.name] = float(values[f.name])
        return cls(**kw)

    def with_(self, **changes) -> "MotorFanParams":
        return replace(self, **changes)

    # ---- supply ----
    @property
    def winding_voltage(self) -> float:
        """Rms voltage across one stator winding: U_supply in delta (winding_connection 2, the
        book's machine), U_supply / sqrt(3) in star (1)."""
        return self.U_supply if self.winding_connection == 2 else self.U_supply / math.sqrt(3.0)

    # ---- load ----
    @property
    def k_fan(self) -> float:
        """Fan torque coefficient k = T_fan_nominal / speed_fan_nominal^2 (N m s2/rad2)."""
        return self.T_fan_nominal / self.speed_fan_nominal**2

    # ---- electrical ----
    @property
    def omega_supply(self) -> float:
        return 2.0 * math.pi * self.f_supply

    @property
    def synchronous_speed(self) -> float:
        """Mechanical synchronous speed ws / p (rad/s)."""
        return self.omega_supply / self.pole_pairs

    # ---- which curve gives the motor torque ----
    @property
    def curve(self) -> str:
        """'circuit', 'linear' or 'akima': the steady-state motor torque the FMU uses at `level`
        (level d and motor_model 2: the circuit; else the table, read as motor_table_interpolation
        says, 0 = linear at levels a and b and Akima at level c)."""
        if self.level == 4 or self.motor_model == 2:
            return "circuit"
        if self.motor_table_interpolation == 1:
            return "linear"
        if self.motor_table_interpolation == 2:
            return "akima"
        return "akima" if self.level == 3 else "linear"

    # ---- inertias ----
    @property
    def J_eq(self) -> float:
        """Fan inertia on the high-speed axis, eq. 3.6/3.7 (no efficiency)."""
        return self.J_fan / self.gear_ratio**2

    @property
    def J_eq_forward(self) -> float:
        """Fan inertia seen by the shaft while power flows towards the fan: J_fan / (N^2 eta)."""
        return self.J_fan / (self.gear_ratio**2 * self.gear_efficiency)


# --------------------------------------------------------------------------------------------------
# The torque-speed table
# --------------------------------------------------------------------------------------------------

def _table_xy(p: MotorFanParams) -> tuple[np.ndarray, np.ndarray]:
    x, y = np.asarray(p.table_speed, dtype=float), np.asarray(p.table_torque, dtype=float)
    if not np.all(np.diff(x) > 0.0):
        raise ValueError(f"table speeds must increase: {x}")
    return x, y


def table_torque(p: MotorFanParams, w_m, interpolation: str) -> np.ndarray:
    """The table's torque (N.m) at motor speed(s) w_m, read 'linear' or 'akima', extrapolated
    along a straight line beyond the ends (see the module docstring)."""
    x, y = _table_xy(p)
    w = np.asarray(w_m, dtype=float)
    if interpolation == "linear":
        inside = np.interp(w, x, y)
        left_slope = (y[1] - y[0]) / (x[1] - x[0])
        right_slope = (y[-1] - y[-2]) / (x[-1] - x[-2])
    elif interpolation == "akima":
        spline = Akima1DInterpolator(x, y, method="akima")
        inside = spline(np.clip(w, x[0], x[-1]))
        left_slope, right_slope = float(spline(x[0], 1)), float(spline(x[-1], 1))
    else:
        raise ValueError(interpolation)
    return np.where(w < x[0], y[0] + left_slope * (w - x[0]),
                    np.where(w > x[-1], y[-1] + right_slope * (w - x[-1]), inside))


def table_slope(p: MotorFanParams, w_m: float, interpolation: str) -> float:
    """dT/dw (N.m.s/rad) of the table curve at w_m (analytic: segment slope or the spline's
    derivative; beyond the ends the extrapolation's slope)."""
    x, y = _table_xy(p)
    if interpolation == "linear":
        i = int(np.clip(np.searchsorted(x, w_m, side="right") - 1, 0, len(x) - 2))
        return float((y[i + 1] - y[i]) / (x[i + 1] - x[i]))
    spline = Akima1DInterpolator(x, y, method="akima")
    return float(spline(np.clip(w_m, x[0], x[-1]), 1))


# --------------------------------------------------------------------------------------------------
# The equivalent circuit
# --------------------------------------------------------------------------------------------------

def t_equivalent(p, V: float, ws: float, s) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(torque N.m, stator current rms A, power drawn W) of the per-winding T-equivalent circuit of
    any parameter set with R_s, R_r, L_s_sigma, L_r_sigma, L_m, pole_pairs (this module's
    MotorFanParams, motor_fan_book's BookParameters), at winding voltage V rms, supply angular
    frequency ws and slip(s) s != 0: Z = R_s + j ws L_s_sigma + (j ws L_m || (R_r/s + j ws L_r_sigma)),
    T = 3 |I_r|^2 (R_r/s) / (ws/p)."""
    s = np.asarray(s, dtype=float)
    z_m = 1j * ws * p.L_m
    z_r = p.R_r / s + 1j * ws * p.L_r_sigma
    z = p.R_s + 1j * ws * p.L_s_sigma + z_m * z_r / (z_m + z_r)
    i_s = V / z
    i_r = i_s * z_m / (z_m + z_r)
    torque = 3.0 * np.abs(i_r) ** 2 * (p.R_r / s) / (ws / p.pole_pairs)
    return torque, np.abs(i_s), 3.0 * np.real(V * np.conj(i_s))


def circuit_at_slip(p: MotorFanParams, s) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(torque N.m, stator current rms A, power drawn W) of the T-equivalent circuit at slip(s) s != 0."""
    return t_equivalent(p, p.winding_voltage, p.omega_supply, s)


def circuit_steady_state(p: MotorFanParams, w_m):
    """The circuit's (torque, current, power) at motor speed(s) w_m (below synchronism)."""
    return circuit_at_slip(p, 1.0 - p.pole_pairs * np.asarray(w_m, dtype=float) / p.omega_supply)


def circuit_torque(p: MotorFanParams, w_m) -> np.ndarray:
    """Steady-state equivalent-circuit torque (N.m) at motor speed(s) w_m (rad/s); w_m < ws/p."""
    return circuit_steady_state(p, w_m)[0]


def circuit_breakdown_slip(p: MotorFanParams) -> float:
    """The slip of the circuit's largest torque (dense grid on (0, 1], then golden section)."""
    grid = np.geomspace(1e-6, 1.0, 20001)
    k = int(np.argmax(circuit_at_slip(p, grid)[0]))
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    g = (math.sqrt(5.0) - 1.0) / 2.0
    for _ in range(100):
        c, d = b - g * (b - a), a + g * (b - a)
        if circuit_at_slip(p, c)[0] > circuit_at_slip(p, d)[0]:
            b = d
        else:
            a = c
    return 0.5 * (a + b)


def converter_fed(p: MotorFanParams, torque, w_m) -> tuple[np.ndarray, np.ndarray]:
    """(current rms, power) of the converter-fed motor (controlled starts, spec "Outputs"): the circuit's
    current at the stable slip 0 < s <= s_breakdown whose torque is |torque| (by bisection; above the
    breakdown torque s = s_breakdown), taken negative for a negative torque; power = torque w_m."""
    torque = np.asarray(torque, dtype=float)
    target = np.abs(torque)
    s_bd = circuit_breakdown_slip(p)
    lo, hi = np.zeros_like(target), np.full_like(target, s_bd)
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        below = circuit_at_slip(p, np.maximum(mid, 1e-300))[0] < target
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    s = np.maximum(0.5 * (lo + hi), 1e-300) * np.where(torque < 0.0, -1.0, 1.0)
    return circuit_at_slip(p, s)[1], torque * np.asarray(w_m, dtype=float)


# --------------------------------------------------------------------------------------------------
# The motor at the level, the load, the equilibrium
# --------------------------------------------------------------------------------------------------

def motor_torque(p: MotorFanParams, w_m) -> np.ndarray:
    """The steady-state motor torque (N.m) the FMU uses at p.level (see MotorFanParams.curve)."""
    if p.curve == "circuit":
        return circuit_torque(p, w_m)
    return table_torque(p, w_m, p.curve)


def motor_torque_slope(p: MotorFanParams, w_m: float) -> float:
    """dT_m/dw (N.m.s/rad) of that curve: analytic for the table, central difference for the circuit."""
    if p.curve != "circuit":
        return table_slope(p, w_m, p.curve)
    h = 1e-4 * p.synchronous_speed
    return float((circuit_torque(p, w_m + h) - circuit_torque(p, w_m - h)) / (2.0 * h))


def load_torque(p: MotorFanParams, w_m) -> np.ndarray:
    """Aerodynamic torque on the high-speed shaft, power towards the fan: k (w_m/N)^2 / (N eta)."""
    w_m = np.asarray(w_m, dtype=float)
    return p.k_fan * (w_m / p.gear_ratio) ** 2 / (p.gear_ratio * p.gear_efficiency)


def load_slope(p: MotorFanParams, w_m: float) -> float:
    """dT_load/dw on the high-speed shaft: 2 k w_m / (N^3 eta)."""
    return 2.0 * p.k_fan * w_m / (p.gear_ratio**3 * p.gear_efficiency)


def _top_speed(p: MotorFanParams) -> float:
    """A speed above every equilibrium: just below synchronism (circuit), or beyond the table's last
    point where the extrapolated motor torque has fallen below the load."""
    if p.curve == "circuit":
        return p.synchronous_speed * (1.0 - 1e-12)
    x = np.asarray(p.table_speed)
    top, span = x[-1], max(x[-1] - x[0], 1.0)
    for _ in range(60):
        if float(motor_torque(p, top) - load_torque(p, top)) < 0.0:
            return top
        top += span
    raise ValueError("the motor torque never falls below the load")


def breakdown(p: MotorFanParams) -> tuple[float, float]:
    """(speed, torque) of the motor curve's maximum on [0, top speed]: dense grid, then golden section."""
    grid = np.linspace(0.0, _top_speed(p), 20001)
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
    """Direct-on-line steady state (speed rad/s, shaft torque N.m): the first speed above standstill
    where T_m(w) - T_load(w) falls through zero (dense grid, then bisection)."""
    f = lambda w: motor_torque(p, w) - load_torque(p, w)  # noqa: E731
    grid = np.linspace(0.0, _top_speed(p), 200001)
    ex = f(grid)
    if not ex[0] > 0.0:
        raise ValueError("the motor cannot start: its standstill torque does not exceed the load's")
    i = int(np.argmax(ex <= 0.0))
    lo, hi = float(grid[i - 1]), float(grid[i])
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if float(f(mid)) > 0.0:
            lo = mid
        else:
            hi = mid
    w = 0.5 * (lo + hi)
    return w, float(load_torque(p, w))


# --------------------------------------------------------------------------------------------------
# The driveshaft mode
# --------------------------------------------------------------------------------------------------

def frequency_motor_imposed(p: MotorFanParams, J: float | None = None) -> float:
    """Eq. 3.8: driveshaft resonance with the motor speed imposed, sqrt(K / J) / (2 pi) (Hz)."""
    J = p.J_eq_forward if J is None else J
    return math.sqrt(p.K_shaft / J) / (2.0 * math.pi)


def frequency_two_inertia(p: MotorFanParams, J: float | None = None) -> float:
    """Free-free two-inertia resonance, sqrt(K (1/J_m + 1/J)) / (2 pi) (Hz)."""
    J = p.J_eq_forward if J is None else J
    return math.sqrt(p.K_shaft * (1.0 / p.J_motor + 1.0 / J)) / (2.0 * math.pi)


def motor_imposed_decay_rate(p: MotorFanParams, w_m: float) -> float:
    """Decay rate sigma (1/s) of the shaft mode with the motor speed imposed at w_m, linearised:
    fan side on the high-speed axis J u'' + (D + c_l) u' + K u = 0 (J = J_eq_forward, power towards
    the fan, c_l = load_slope), so the ringing's envelope falls as exp(-sigma t), sigma = (D + c_l) / (2 J)."""
    return (p.D_shaft + load_slope(p, w_m)) / (2.0 * p.J_eq_forward)


def two_inertia_damping_ratio(p: MotorFanParams, motor_slope: float, w_m: float) -> float:
    """Damping ratio of the free two-inertia shaft mode, linearised at motor speed w_m.

    Linear model on the high-speed axis (J = J_eq_forward, power towards the fan):
        J_m x1' = c_m x1 - T,  J x2' = T - c_l x2,  T = K theta + D (x1 - x2),  theta' = x1 - x2
    with c_m = dT_m/dw (the motor curve's slope; > 0 is negative damping) and
    c_l = dT_load/dw = 2 k w_m / (N^3 eta). Returns -Re(lambda)/|lambda| of the oscillatory pair.
    """
    J = p.J_eq_forward
    c_l = load_slope(p, w_m)
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
    """Highest motor speed below the motor curve's maximum up to which the run-up stays a lightly
    damped linear two-inertia oscillator: |damping ratio| <= zeta_max (the damped frequency is then
    within 1 - sqrt(1 - zeta_max^2) = 1.1 % of the undamped one). Above it, the motor curve's slope
    (negative damping where it rises steeply, strong damping where it falls) moves the ringing frequency."""
    w_bd, _ = breakdown(p)
    for w in np.linspace(0.0, w_bd, 401)[1:]:
        if abs(two_inertia_damping_ratio(p, motor_torque_slope(p, w), w)) > zeta_max:
            return float(w)
    return w_bd


# --------------------------------------------------------------------------------------------------
# The set point
# --------------------------------------------------------------------------------------------------

def setpoint(p: MotorFanParams, t) -> tuple[np.ndarray, np.ndarray]:
    """(w_ref, dw_ref/dt) at times t (increasing, from 0): the ramp 0 -> speed_setpoint in ramp_time
    (0 = a step), through the second-order filter wn^2 / (s^2 + 2 zeta wn s + wn^2) when
    setpoint_filter is 1 (filter_frequency_below) or 2 (filter_frequency_above), by scipy.signal.lsim
    (exact for the piecewise-linear ramp: lsim's first-order hold)."""
    t = np.asarray(t, dtype=float)
    if p.ramp_time > 0.0:
        ramp = p.speed_setpoint * np.clip(t / p.ramp_time, 0.0, 1.0)
        ramp_rate = np.where((t >= 0.0) & (t < p.ramp_time), p.speed_setpoint / p.ramp_time, 0.0)
    else:
        ramp, ramp_rate = np.full_like(t, p.speed_setpoint), np.zeros_like(t)
    if p.setpoint_filter == 0:
        return ramp, ramp_rate
    hz = p.filter_frequency_below if p.setpoint_filter == 1 else p.filter_frequency_above
    wn, z = 2.0 * math.pi * hz, p.filter_damping
    # states (y, y'); outputs y and y'
    system = StateSpace([[0.0, 1.0], [-wn * wn, -2.0 * z * wn]], [[0.0], [wn * wn]], [[1.0, 0.0], [0.0, 1.0]], [[0.0], [0.0]])
    if p.ramp_time > 0.0 and p.ramp_time not in t:
        # lsim holds the input linear between samples: put the ramp's corner on a sample
        tt = np.union1d(t, [p.ramp_time])
        _, y, _ = lsim(system, p.speed_setpoint * np.clip(tt / p.ramp_time, 0.0, 1.0), tt)
        keep = np.isin(tt, t)
        return y[keep, 0], y[keep, 1]
    _, y, _ = lsim(system, ramp, t)
    return y[:, 0], y[:, 1]
