"""CommonRailInjection's equations written out independently of the FMU (docs/common-rail-spec.md),
for tests/python/test_common_rail.py and the benchmark's scipy contender (bench/python/common_rail_scipy.py).

At a constant engine speed every event of the model is known in time beforehand: the crank angle is
theta(t) = theta0 + w t (theta0 = 1 degree - advance: the run starts 1 degree after cylinder 1's start
of injection), slot j's start of injection is at theta = j 4 pi / n - advance, the plungers' dead
centres at r theta + phase = 2 pi k / 3 + m pi, the needle's kinks at fixed delays from each start.
So a reference needs no root finding: it integrates from kink to kink (`kinks`).

What is here:
  * `Params`: the FMU's parameters, from its start values;
  * the parts' laws, each written in its own way: the needle's trapezoid by phases (`lift`), the nozzle
    as two orifices in series (`nozzle_flow`), the pump as three half-wave rectified sines
    (`pump_flow`), the valve's static balance (`valve_static`), the leakage;
  * `hand_balance`: the mean rail pressure from the mean flows (brentq);
  * `linear_ripple`: the rail pressure's harmonics from the net flow's harmonics into C = V / B(p) with
    the valve's linearised conductance and its mass-spring-damper (closed form per harmonic);
  * `Rail`: the whole ODE (rail pressure, valve lift and speed, the shot volume) and `simulate`, DOP853
    from kink to kink (the valve's seat contact is not modelled here: `simulate` asserts that it stays
    open, as it does at the defaults).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq

#: Diesel fuel, kg/m3: EN 590 allows 820-845 kg/m3 at 15 degrees C (the FMU's constant, not a parameter).
RHO = 830.0
#: Inline firing orders (cylinder numbers from the one at crank angle 0).
FIRING_ORDERS = {4: (1, 3, 4, 2), 5: (1, 2, 4, 5, 3), 6: (1, 5, 3, 6, 2, 4)}
#: The run starts this far past cylinder 1's start of injection.
START_PAST = math.radians(1.0)


@dataclass(frozen=True)
class Params:
    cylinders: int = 4
    injection_advance: float = math.radians(4.0)
    pump_ratio: float = 2.0 / 3.0
    pump_phase: float = 0.0
    p_feed: float = 0.3e6
    plunger_diameter: float = 6.5e-3
    eccentricity: float = 3.5e-3
    V_rail: float = 20e-6
    B_fuel_0: float = 1.5e9
    dB_fuel_dp: float = 7.5
    R_leakage: float = 145e6 / 0.5e-6
    valve_seat_diameter: float = 0.6e-3
    Cd_valve: float = 0.7
    m_valve: float = 3e-3
    k_valve: float = 7.5e4
    c_valve: float = 15.0
    F_spring_preload: float = math.pi / 4 * 0.6e-3**2 * 10e6
    nozzle_holes: int = 7
    hole_diameter: float = 0.13e-3
    Cd_nozzle: float = 0.75
    needle_seat_diameter: float = 1.5e-3
    needle_seat_half_angle: float = math.radians(30.0)
    needle_lift_max: float = 0.2e-3
    needle_opening_speed: float = 1.0
    needle_closing_speed: float = 1.2
    opening_delay: float = 0.3e-3
    closing_delay: float = 0.3e-3
    p_cylinder: float = 6e6
    engine_speed: float = 2000.0 * 2 * math.pi / 60
    rail_pressure_set_point: float = 145e6
    energizing_time: float = 0.5e-3
    p_rail: float = 149e6

    @classmethod
    def from_values(cls, values: dict) -> "Params":
        names = {f.name for f in fields(cls)}
        kw = {k: v for k, v in values.items() if k in names}
        for k in ("cylinders", "nozzle_holes"):
            if k in kw:
                kw[k] = int(kw[k])
        return cls(**{k: (v if k in ("cylinders", "nozzle_holes") else float(v)) for k, v in kw.items()})

    def with_(self, **kw) -> "Params":
        return replace(self, **kw)

    # ---- derived
    @property
    def firing_interval(self) -> float:
        return 4 * math.pi / self.cylinders

    @property
    def period(self) -> float:
        """Time between two starts of injection, s."""
        return self.firing_interval / self.engine_speed

    @property
    def theta0(self) -> float:
        return START_PAST - self.injection_advance

    @property
    def plunger_area(self) -> float:
        return math.pi / 4 * self.plunger_diameter**2

    @property
    def displacement(self) -> float:
        """Pump displacement per shaft revolution, m3: three plungers of stroke 2 e."""
        return 3 * self.plunger_area * 2 * self.eccentricity

    @property
    def seat_area(self) -> float:
        return math.pi / 4 * self.valve_seat_diameter**2

    @property
    def solenoid_force(self) -> float:
        return max(self.seat_area * self.rail_pressure_set_point - self.F_spring_preload, 0.0)

    @property
    def opening_pressure(self) -> float:
        """The valve opens where the rail pressure's force on the seat equals spring preload plus solenoid."""
        return (self.F_spring_preload + self.solenoid_force) / self.seat_area

    @property
    def hole_area(self) -> float:
        return self.nozzle_holes * math.pi / 4 * self.hole_diameter**2

    def bulk_modulus(self, p):
        return self.B_fuel_0 + self.dB_fuel_dp * p

    def capacitance(self, p):
        return self.V_rail / self.bulk_modulus(p)

    def start_times(self, t_end: float) -> np.ndarray:
        """Times of the starts of injection in (0, t_end] (the one at the start is before t = 0)."""
        first = (self.firing_interval - START_PAST) / self.engine_speed
        return first + self.period * np.arange(max(0, int(math.floor((t_end - first) / self.period)) + 1))


# ---- the needle and the nozzle ----------------------------------------------------------------------

def needle_phases(p: Params, et: float) -> list[tuple[float, float, float]]:
    """The trapezoid as (start, end, slope) pieces after the start of energizing (lift 0 elsewhere):
    rising from the opening delay at the opening speed until the stop or the closing start, flat at the
    stop, then falling from the closing start (energizing time + closing delay) at the closing speed."""
    t_lift = p.opening_delay
    t_close = et + p.closing_delay
    if t_close <= t_lift:
        return []
    t_top = t_lift + p.needle_lift_max / p.needle_opening_speed
    pieces = []
    if t_top < t_close:
        pieces.append((t_lift, t_top, p.needle_opening_speed))
        pieces.append((t_top, t_close, 0.0))
        h_close = p.needle_lift_max
    else:
        pieces.append((t_lift, t_close, p.needle_opening_speed))
        h_close = p.needle_opening_speed * (t_close - t_lift)
    pieces.append((t_close, t_close + h_close / p.needle_closing_speed, -p.needle_closing_speed))
    return pieces


def lift(p: Params, s: float, et: float) -> float:
    """Needle lift s after the start of energizing, by walking the pieces."""
    h = 0.0
    for a, b, slope in needle_phases(p, et):
        if s <= a:
            break
        h += slope * (min(s, b) - a)
    return max(h, 0.0)


def shot_end(p: Params, et: float) -> float:
    pieces = needle_phases(p, et)
    return pieces[-1][1] if pieces else p.opening_delay


def nozzle_area(p: Params, h: float) -> float:
    """Seat gap pi d h sin(alpha) and holes in series: 1 / A^2 = 1 / A_seat^2 + 1 / A_holes^2."""
    a_seat = math.pi * p.needle_seat_diameter * h * math.sin(p.needle_seat_half_angle)
    if a_seat <= 0.0:
        return 0.0
    return 1.0 / math.sqrt(1.0 / a_seat**2 + 1.0 / p.hole_area**2)


def nozzle_flow(p: Params, h: float, p_rail: float) -> float:
    dp = p_rail - p.p_cylinder
    return p.Cd_nozzle * nozzle_area(p, h) * math.copysign(math.sqrt(2 * abs(dp) / RHO), dp)


def shot_volume(p: Params, p_rail: float, et: float | None = None) -> float:
    """Volume of one shot at a constant rail pressure, m3: Cd sqrt(2 dp / rho) times the integral of
    A(h(s)) ds, by quad on each piece of the trapezoid."""
    et = p.energizing_time if et is None else et
    integral = sum(quad(lambda s: nozzle_area(p, lift(p, s, et)), a, b, epsabs=0.0, epsrel=1e-12, limit=200)[0]
                   for a, b, _ in needle_phases(p, et))
    dp = p_rail - p.p_cylinder
    return p.Cd_nozzle * math.sqrt(2 * dp / RHO) * integral


# ---- the pump -------------------------------------------------------------------------------------

def crank_angle(p: Params, t):
    return p.theta0 + p.engine_speed * t


def pump_flow(p: Params, t):
    """Delivery of three plungers on the eccentric, each A e w_p sin(phi_k) while it rises
    (phi_k = r theta + phase - 2 pi k / 3), nothing while it falls (the check valves)."""
    phi = p.pump_ratio * crank_angle(p, np.asarray(t, dtype=float)) + p.pump_phase
    w_p = p.pump_ratio * p.engine_speed
    return sum(p.plunger_area * p.eccentricity * w_p * np.maximum(np.sin(phi - 2 * math.pi * k / 3), 0.0) for k in range(3))


def pump_mean_flow(p: Params) -> float:
    """Displacement times pump revolutions per second."""
    return p.displacement * p.pump_ratio * p.engine_speed / (2 * math.pi)


# ---- the valve and the leakage -----------------------------------------------------------------------

def valve_static(p: Params, p_rail: float) -> tuple[float, float]:
    """(lift, flow) of the valve in static balance at a rail pressure: k x = A p - preload - solenoid."""
    x = max((p.seat_area * p_rail - p.F_spring_preload - p.solenoid_force) / p.k_valve, 0.0)
    return x, p.Cd_valve * math.pi * p.valve_seat_diameter * x * math.sqrt(2 * p_rail / RHO)


def leakage(p: Params, p_rail: float) -> float:
    return p_rail / p.R_leakage


# ---- the mean: the flow balance by hand --------------------------------------------------------------

def injected_mean_flow(p: Params, p_rail: float) -> float:
    return shot_volume(p, p_rail) / p.period


def hand_balance(p: Params) -> dict:
    """The mean rail pressure where the pump's mean delivery equals the mean injected flow, the valve's
    flow in its static balance and the leakage (all at that pressure), and the flows there."""
    q_pump = pump_mean_flow(p)

    def surplus(pr):
        return q_pump - injected_mean_flow(p, pr) - valve_static(p, pr)[1] - leakage(p, pr)

    pr = brentq(surplus, p.opening_pressure, p.opening_pressure + 100e6, xtol=1e-6, rtol=1e-15)
    x, q_relief = valve_static(p, pr)
    return dict(p=pr, q_pump=q_pump, q_injection=injected_mean_flow(p, pr), q_relief=q_relief, q_leakage=leakage(p, pr),
                lift=x, shot=shot_volume(p, pr))


# ---- the ripple: the linearised accumulator -------------------------------------------------------------

def harmonics(signal: np.ndarray, count: int) -> np.ndarray:
    """Complex amplitudes c_k (k = 1 .. count) of a signal sampled uniformly over exactly one period
    (endpoint excluded): signal ~ mean + sum Re(c_k exp(i k Omega t))."""
    n = len(signal)
    spectrum = np.fft.rfft(signal) / n
    return 2 * spectrum[1:count + 1]


def linear_ripple(p: Params, mean: dict, count: int = 40, samples: int = 20000) -> dict:
    """The rail pressure's harmonics k = 1 .. count of the injection period T (the flows repeat every
    firing interval when 6 pump_ratio / cylinders is an integer: 1 at the defaults), from the
    linearised rail equation

        C dp/dt = Q_pump(t) - Q_inj(t) - G_p p - G_x x - A dx/dt,   m x'' + c x' + k x = A p

    (p, x deviations from the mean; C = V / B(p_mean); G_p = dQ_relief/dp + 1/R + mean dQ_inj/dp,
    G_x = dQ_relief/dx = Cd pi d sqrt(2 p / rho); A dx/dt the flow the ball displaces): per harmonic
    p_k = (Q_pump,k - Q_inj,k) / (i w C + G_p + (G_x + i w A) A / (k - m w^2 + i w c)), w = k 2 pi / T.
    Q_inj(t) is the shot at the mean pressure. Returns the harmonics, the flows' and the waveform."""
    pr = mean["p"]
    T = p.period
    t = np.arange(samples) * (T / samples)
    # One period starting at the first start of injection after t = 0 (any origin works for amplitudes).
    t0 = p.start_times(2 * T)[0]
    q_pump = pump_flow(p, t0 + t)
    q_inj = np.array([nozzle_flow(p, lift(p, s, p.energizing_time), pr) for s in t])
    C = p.capacitance(pr)
    x_mean, q_relief = mean["lift"], mean["q_relief"]
    g_x = p.Cd_valve * math.pi * p.valve_seat_diameter * math.sqrt(2 * pr / RHO)
    g_inj = np.mean(q_inj) / (2 * (pr - p.p_cylinder))
    g_p = q_relief / (2 * pr) + 1 / p.R_leakage + g_inj
    A = p.seat_area
    qp, qi = harmonics(q_pump, count), harmonics(q_inj, count)
    w = 2 * math.pi / T * np.arange(1, count + 1)
    valve = A / (p.k_valve - p.m_valve * w**2 + 1j * w * p.c_valve)
    admittance = 1j * w * C + g_p + (g_x + 1j * w * A) * valve
    pk = (qp - qi) / admittance
    wave = pr + np.real(np.sum(pk[:, None] * np.exp(1j * np.outer(w, t)), axis=0))
    return dict(t=t0 + t, harmonics=pk, pump=qp, injection=qi, g_p=g_p, g_x=g_x, C=C, wave=wave, x_mean=x_mean)


# ---- the whole ODE -----------------------------------------------------------------------------------

class Rail:
    """The FMU's equations at a constant engine speed, states y = (p_rail, x_valve, v_valve, V_shot),
    the valve open throughout (its seat contact left out: `simulate` asserts the lift stays positive).
    The crank angle and every event are functions of time; `shot_start(t)` is the last start of
    injection at or before t (cylinder 1's, 1 degree before t = 0, at the start)."""

    def __init__(self, p: Params):
        self.p = p
        self.A = p.seat_area
        self.F = p.F_spring_preload + p.solenoid_force
        self.gx = p.Cd_valve * math.pi * p.valve_seat_diameter
        self.first = -START_PAST / p.engine_speed

    def shot_start(self, t: float) -> float:
        p = self.p
        k = math.floor((t - self.first) / p.period + 1e-12)
        return self.first + k * p.period

    def rhs(self, t, y, start=None):
        p = self.p
        pr, x, v, _ = y
        start = self.shot_start(t) if start is None else start
        q_inj = nozzle_flow(p, lift(p, t - start, p.energizing_time), pr)
        q_relief = self.gx * x * math.sqrt(2 * pr / RHO) if x > 0 else 0.0
        q_net = float(pump_flow(p, t)) - q_inj - q_relief - pr / p.R_leakage - self.A * v
        dp = q_net / p.capacitance(pr)
        a = (self.A * pr - self.F - p.k_valve * x - p.c_valve * v) / p.m_valve
        return [dp, v, a, q_inj]

    def initial(self) -> list[float]:
        p = self.p
        return [p.p_rail, max((self.A * p.p_rail - self.F) / p.k_valve, 0.0), 0.0, 0.0]

    def kinks(self, t_end: float) -> np.ndarray:
        """Every instant in (0, t_end) where the right-hand side has a kink: the needle's four, the
        starts of injection and the plungers' dead centres."""
        p = self.p
        times = []
        for start in np.concatenate([[self.first], p.start_times(t_end)]):
            times.append(start)
            for a, b, _ in needle_phases(p, p.energizing_time):
                times += [start + a, start + b]
        # dead centres: r theta + phase - 2 pi k / 3 = m pi
        r, w = p.pump_ratio, p.engine_speed
        phi0 = r * p.theta0 + p.pump_phase
        step = math.pi / 3  # every 60 degrees of the pump one plunger is at a dead centre
        m0 = math.ceil(phi0 / step)
        m1 = math.floor((phi0 + r * w * t_end) / step)
        times += [(m * step - phi0) / (r * w) for m in range(m0, m1 + 1)]
        times = np.unique(np.array([t for t in times if 0.0 < t < t_end]))
        return times

    def simulate(self, t_eval: np.ndarray, rtol: float = 1e-12, method: str = "DOP853") -> dict:
        """DOP853 from kink to kink, dense output onto t_eval (an instant on a kink belongs to the
        segment after it). Returns the states and the flows on t_eval."""
        p = self.p
        t_end = float(t_eval[-1])
        edges = np.concatenate([[0.0], self.kinks(t_end), [t_end]])
        scale = np.array([1e8, 1e-5, 1e-2, 1e-8])
        y = np.array(self.initial(), dtype=float)
        out = np.empty((4, len(t_eval)))
        starts = np.empty(len(t_eval))
        steps = 0
        for a, b in zip(edges[:-1], edges[1:]):
            if b <= a:
                continue
            mid_start = self.shot_start(0.5 * (a + b))
            sol = solve_ivp(lambda t, z: self.rhs(t, z, mid_start), (a, b), y, method=method, rtol=rtol,
                            atol=1e-3 * rtol * scale, dense_output=True)
            if not sol.success:
                raise RuntimeError(sol.message)
            steps += len(sol.t) - 1
            inside = (t_eval >= a) & ((t_eval < b) | (b == t_end))
            if inside.any():
                out[:, inside] = sol.sol(t_eval[inside])
                starts[inside] = mid_start
            y = sol.y[:, -1].copy()
            if self.shot_start(b + 1e-12) != mid_start:
                y[3] = 0.0  # the shot volume restarts at each start of injection
        assert np.all(out[1] > 0.0), "the valve landed on its seat: the reference leaves the seat out"
        pr, x, v, vol = out
        q_inj = np.array([nozzle_flow(p, lift(p, t - s, p.energizing_time), q) for t, s, q in zip(t_eval, starts, pr)])
        return dict(t=t_eval, p=pr, x=x, v=v, shot=vol, q_pump=pump_flow(p, t_eval), q_inj=q_inj,
                    q_relief=self.gx * x * np.sqrt(2 * pr / RHO), q_leak=pr / p.R_leakage, steps=steps)
