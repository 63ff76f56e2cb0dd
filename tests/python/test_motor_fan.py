"""MotorFan against its contract (docs/motor-fan-spec.md) and the claims of chapter 3, sections 3.1-3.3.

Every reference value is computed here from the FMU's own parameter values (the start values of its
modelDescription.xml, plus a test's overrides) with the hand formulas of motor_fan_reference.py (the
spec's equivalent circuit, eqs. 3.4-3.8, linear two-inertia theory); nothing comes from a previous
run of the FMU. Where a test checks a claim of the chapter, the measured figures are printed
(`pytest -s`) and stated in the failure message; such a test is not loosened when the physics
disagrees with the chapter, the disagreement is discussed instead.

Simulations: fmpy, Co-Simulation, 0..30 s, communication step (= output_interval, TOOLS.md) 1e-3 s.
Each configuration (a set of start values) is simulated once per session and cached (`run`), so the
physics tests share the 12 level x start_mode runs plus a few variants (~20 runs in all).

fmpy quirk (TOOLS.md): each result row is stamped with a communication point and holds the values
after the step that ends there; at 1e-3 s this shifts nothing measurable here.
"""

from __future__ import annotations

import functools
import math
import time

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException

import motor_fan_reference as ref
from conftest import DIST_DIR, fmu_key as _fmu_key, model_description as _model_description, require_fmu, unzipdir as _unzipdir
from fmi_host import Slave

STOP_TIME = 30.0
OUTPUT_INTERVAL = 1e-3
# The FMUs' relative tolerance when the master gives none (fmu-runtime's DEFAULT_RELATIVE_TOLERANCE,
# stated in each FMU's documentation): the runs below give none.
FMU_RTOL = 1e-8

LEVELS = {1: "a", 2: "b", 3: "c", 4: "d"}
START_MODES = {1: "direct-on-line", 2: "PI", 3: "inverse"}

OUTPUTS = {
    # name: unit (spec, "Outputs")
    "motor_speed": "rad/s",
    "fan_speed": "rad/s",
    "shaft_torque": "N.m",
    "motor_torque": "N.m",
    "stator_current_rms": "A",
    "electrical_power": "W",
    "speed_reference": "rad/s",
    "activity_motor_inertia": "J",
    "activity_shaft_stiffness": "J",
    "activity_fan_inertia": "J",
    "share_motor_inertia": "%",
    "share_shaft_stiffness": "%",
    "share_fan_inertia": "%",
}
ACTIVITIES = ("activity_motor_inertia", "activity_shaft_stiffness", "activity_fan_inertia")
SHARES = ("share_motor_inertia", "share_shaft_stiffness", "share_fan_inertia")

# Spec, "Parameters": name -> (type, unit, variability, default). unit None: Integer/Boolean (no unit).
SPEC_PARAMETERS = {
    "level": ("Integer", None, "fixed", 3),
    "start_mode": ("Integer", None, "fixed", 1),
    "setpoint_filter": ("Integer", None, "fixed", 0),
    "keep_shaft_stiffness": ("Boolean", None, "fixed", True),
    "J_motor": ("Real", "kg.m2", "tunable", 1.72),
    "J_fan": ("Real", "kg.m2", "tunable", 1172.0),
    "gear_ratio": ("Real", "1", "tunable", 10.0),
    "gear_efficiency": ("Real", "1", "tunable", 0.97),
    "K_shaft": ("Real", "N.m/rad", "tunable", 906.85),
    "D_shaft": ("Real", "N.m.s/rad", "tunable", 5.0),
    "k_fan": ("Real", "N.m.s2/rad2", "tunable", 42.9),
    "R_s": ("Real", "Ohm", "tunable", 0.012),
    "R_r": ("Real", "Ohm", "tunable", 0.020),
    "L_s_sigma": ("Real", "H", "tunable", 2.5e-4),
    "L_r_sigma": ("Real", "H", "tunable", 2.5e-4),
    "L_m": ("Real", "H", "tunable", 0.01),
    "pole_pairs": ("Real", "1", "fixed", 2.0),
    "U_supply": ("Real", "V", "tunable", 400.0),
    "f_supply": ("Real", "Hz", "tunable", 50.0),
    "speed_setpoint": ("Real", "rad/s", "tunable", 153.5),
    "ramp_time": ("Real", "s", "tunable", 10.0),
    "Kp_speed": ("Real", "N.m.s/rad", "tunable", 200.0),
    "Ki_speed": ("Real", "N.m/rad", "tunable", 2000.0),
    "T_limit": ("Real", "N.m", "tunable", 2500.0),
    "T_tracking": ("Real", "s", "tunable", 0.09),
    "filter_frequency_below": ("Real", "Hz", "tunable", 0.5),
    "filter_frequency_above": ("Real", "Hz", "tunable", 5.0),
    "filter_damping": ("Real", "1", "tunable", 0.7),
}


# --------------------------------------------------------------------------------------------------
# Fixtures, cached simulations, signal helpers
# --------------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def motor_fan_fmu():
    return require_fmu(DIST_DIR / "MotorFan.fmu")


def _start_value(v):
    if v.start is None:
        return None
    if v.type == "Real":
        return float(v.start)
    if v.type in ("Integer", "Enumeration"):
        return int(v.start)
    if v.type == "Boolean":
        return str(v.start).lower() in ("true", "1")
    return v.start


def start_values(fmu) -> dict:
    """{name: start value} of every variable that has one (modelDescription.xml)."""
    md = _model_description(_fmu_key(fmu))
    return {v.name: _start_value(v) for v in md.modelVariables if v.start is not None}


def params(fmu, **overrides) -> ref.MotorFanParams:
    """The physical parameters the FMU simulates with: its start values updated by `overrides`."""
    return ref.MotorFanParams.from_values({**start_values(fmu), **overrides})


@functools.lru_cache(maxsize=None)
def _simulate(key: tuple[str, float], start_items: tuple):
    t0 = time.perf_counter()
    res = simulate_fmu(
        _unzipdir(key),
        validate=False,  # test_validate.py validates every dist/*.fmu
        model_description=_model_description(key),
        fmi_type="CoSimulation",
        start_time=0.0,
        stop_time=STOP_TIME,
        output_interval=OUTPUT_INTERVAL,
        start_values=dict(start_items),
        output=list(OUTPUTS),
    )
    return res, time.perf_counter() - t0


def run(fmu, **start):
    """fmpy result of a 30 s run with these start values (simulated once per session, then cached)."""
    res, _ = _simulate(_fmu_key(fmu), tuple(sorted(start.items())))
    return res


def run_seconds(fmu, **start) -> float:
    """Wall-clock time of the (cached) simulation."""
    return _simulate(_fmu_key(fmu), tuple(sorted(start.items())))[1]


def base(fmu, level: int, start_mode: int):
    """One of the 12 level x start_mode runs (all other parameters at their defaults)."""
    return run(fmu, level=level, start_mode=start_mode)


def last_second(res, name: str) -> np.ndarray:
    t = res["time"]
    return np.asarray(res[name])[t >= t[-1] - 1.0 - 1e-9]


def peak_abs(res, name: str = "shaft_torque") -> float:
    return float(np.max(np.abs(res[name])))


def zero_crossings(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Times where y changes sign, linearly interpolated between output points."""
    k = np.where(np.sign(y[:-1]) * np.sign(y[1:]) < 0)[0]
    return t[k] - y[k] * (t[k + 1] - t[k]) / (y[k + 1] - y[k])


def ringing_frequency(t: np.ndarray, d: np.ndarray, rel_floor: float = 0.02, min_crossings: int = 6) -> tuple[float, int]:
    """Frequency (Hz) of the oscillation of a zero-mean (detrended) signal d(t) from its zero
    crossings: f = (number of half periods) / (2 * their span). Crossings are used while the
    oscillation is clearly above numerical noise: up to the last half period whose peak |d| is at
    least rel_floor of the largest one. Returns (f, number of crossings used)."""
    c = zero_crossings(t, d)
    assert len(c) >= min_crossings, f"only {len(c)} zero crossings of the detrended signal"
    peaks = np.array([np.max(np.abs(d[(t >= a) & (t <= b)]), initial=0.0) for a, b in zip(c[:-1], c[1:])])
    keep = np.where(peaks >= rel_floor * peaks.max())[0]
    c = c[: keep[-1] + 2]
    assert len(c) >= min_crossings, f"only {len(c)} zero crossings above {rel_floor:.0%} of the oscillation"
    return float((len(c) - 1) / (2.0 * (c[-1] - c[0]))), len(c)


def moving_average(t: np.ndarray, y: np.ndarray, period: float) -> np.ndarray:
    """Centred moving average of y over `period` seconds, on the points t[h:-h] where the whole window
    fits (h = half the window, in samples)."""
    n = max(3, int(round(period / (t[1] - t[0]))) | 1)  # odd, so that the window is centred
    return np.convolve(y, np.ones(n) / n, mode="valid")


def detrend_moving_average(t: np.ndarray, y: np.ndarray, period: float) -> tuple[np.ndarray, np.ndarray]:
    """(t, y minus its centred moving average over `period` seconds) on the points where the whole
    window fits. A moving average over T has zeros at 1/T, 2/T, ...: with T = the theoretical period
    the trend keeps none of an oscillation at that frequency, and only ~10 % of one 10 % away from it,
    so the zero crossings of the residual (hence the measured frequency) are those of the signal, not
    forced to the theory."""
    trend = moving_average(t, y, period)
    h = (len(y) - len(trend)) // 2
    return t[h : len(t) - h], y[h : len(y) - h] - trend


# --------------------------------------------------------------------------------------------------
# Interface: every physical value is a parameter with a unit
# --------------------------------------------------------------------------------------------------

def test_model_description_parameters_and_outputs(motor_fan_fmu):
    # reference: the spec's tables "Parameters" and "Outputs", and "DefaultExperiment: 0 to 30 s, step 1e-3 s"
    md = read_model_description(str(motor_fan_fmu))
    variables = {v.name: v for v in md.modelVariables}
    problems = []
    assert md.coSimulation is not None, "MotorFan must be a Co-Simulation FMU"
    for name, (vtype, unit, variability, default) in SPEC_PARAMETERS.items():
        v = variables.get(name)
        if v is None:
            problems.append(f"parameter {name!r} missing")
            continue
        if (v.type, v.causality, v.variability) != (vtype, "parameter", variability):
            problems.append(f"{name}: (type, causality, variability) = {(v.type, v.causality, v.variability)}, "
                            f"spec {(vtype, 'parameter', variability)}")
        if vtype == "Real" and v.unit != unit:
            problems.append(f"{name}: unit {v.unit!r}, spec {unit!r}")
        if v.start is None:
            problems.append(f"{name}: no start value")
        elif default is not None:
            got = _start_value(v)
            if (isinstance(default, float) and not math.isclose(got, default, rel_tol=1e-12)) or (
                not isinstance(default, float) and got != default
            ):
                problems.append(f"{name}: start {v.start!r}, spec {default!r}")
    # "every physical value is a parameter with a unit": no Real parameter without a unit
    for v in md.modelVariables:
        if v.causality == "parameter" and v.type == "Real" and not v.unit:
            problems.append(f"Real parameter {v.name!r} has no unit")
    for name, unit in OUTPUTS.items():
        v = variables.get(name)
        if v is None:
            problems.append(f"output {name!r} missing")
        elif (v.type, v.causality, v.unit) != ("Real", "output", unit):
            problems.append(f"{name}: (type, causality, unit) = {(v.type, v.causality, v.unit)}, spec ('Real', 'output', {unit!r})")
    listed = {u.variable.name for u in md.outputs}
    if not set(OUTPUTS) <= listed:
        problems.append(f"<Outputs> misses {sorted(set(OUTPUTS) - listed)}")
    de = md.defaultExperiment
    got_de = None if de is None else tuple(None if x is None else float(x) for x in (de.startTime or 0.0, de.stopTime, de.stepSize))
    if got_de != (0.0, 30.0, 1e-3):
        problems.append(f"DefaultExperiment (startTime, stopTime, stepSize) = {got_de}, spec (0, 30, 1e-3)")
    assert not problems, "modelDescription.xml vs docs/motor-fan-spec.md:\n" + "\n".join(problems)

    # the spec's derived figures hold for the default parameters (eqs. 3.6 and 3.8)
    p = params(motor_fan_fmu)
    assert p.J_eq == pytest.approx(11.72, rel=1e-9)
    assert ref.frequency_motor_imposed(p, p.J_eq) == pytest.approx(1.4, rel=1e-3)
    assert ref.frequency_two_inertia(p, p.J_eq) == pytest.approx(3.9, rel=0.01)


# --------------------------------------------------------------------------------------------------
# Every level and start mode simulates
# --------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("start_mode", list(START_MODES), ids=list(START_MODES.values()))
@pytest.mark.parametrize("level", list(LEVELS), ids=[f"level-{c}" for c in LEVELS.values()])
def test_simulation_succeeds(motor_fan_fmu, level, start_mode):
    # reference: spec "DefaultExperiment: 0 to 30 s, step 1e-3 s"; fmpy's CS loop gives one row per
    # communication point k * output_interval
    res = base(motor_fan_fmu, level, start_mode)
    n = int(round(STOP_TIME / OUTPUT_INTERVAL))
    assert len(res) == n + 1, f"expected {n + 1} rows, got {len(res)}"
    np.testing.assert_allclose(res["time"], np.arange(n + 1) * OUTPUT_INTERVAL, rtol=0, atol=1e-9)
    bad = [name for name in OUTPUTS if not np.all(np.isfinite(res[name]))]
    assert not bad, f"non-finite values in {bad}"
    print(f"level {LEVELS[level]}, {START_MODES[start_mode]}: {run_seconds(motor_fan_fmu, level=level, start_mode=start_mode):.2f} s wall clock")


def test_inverse_simulation_refuses_an_unfiltered_step(motor_fan_fmu):
    # reference: spec "Inverse simulation needs a finite acceleration: ramp_time = 0 with the filter off
    # is refused at initialization"
    with Slave(motor_fan_fmu) as s:
        s.instantiate()
        s.fmu.setupExperiment(startTime=0.0, stopTime=STOP_TIME)
        s.fmu.setInteger([s.vr["start_mode"], s.vr["setpoint_filter"]], [3, 0])
        s.set(ramp_time=0.0)
        with pytest.raises(FMICallException):
            s.fmu.enterInitializationMode()
            s.fmu.exitInitializationMode()


# --------------------------------------------------------------------------------------------------
# Steady state after the start (Figure 3.6: "similar for all modeling levels")
# --------------------------------------------------------------------------------------------------

STEADY_TOL = 0.005  # issue: within 0.5 %


def test_steady_state_direct_on_line_all_levels(motor_fan_fmu):
    # reference: spec "Steady state by hand": root of T_m(w) = k (w/N)^2 / (N eta) on the stable branch
    # of the equivalent-circuit curve; the shaft torque is that torque. Every output point of the last
    # second must be within 0.5 % of it (so the run has settled), and the levels within 0.5 % of each other.
    p = params(motor_fan_fmu)
    w_eq, T_eq = ref.equilibrium(p)
    print(f"hand equilibrium: w_m = {w_eq:.4f} rad/s, T_shaft = {T_eq:.2f} N.m "
          f"(breakdown {ref.breakdown(p)[0]:.2f} rad/s, {ref.breakdown(p)[1]:.1f} N.m)")
    problems, finals = [], {}
    for level, letter in LEVELS.items():
        res = base(motor_fan_fmu, level, 1)
        w, T = last_second(res, "motor_speed"), last_second(res, "shaft_torque")
        finals[letter] = (float(w[-1]), float(T[-1]))
        print(f"  level {letter}: w_m(30 s) = {w[-1]:.4f} rad/s ({w[-1] / w_eq - 1:+.3%}), "
              f"T_shaft(30 s) = {T[-1]:.2f} N.m ({T[-1] / T_eq - 1:+.3%})")
        for name, sig, ref_value in (("motor_speed", w, w_eq), ("shaft_torque", T, T_eq)):
            err = float(np.max(np.abs(sig / ref_value - 1.0)))
            if err > STEADY_TOL:
                problems.append(f"level {letter}: {name} over the last second is up to {err:.3%} from {ref_value:.4f}")
    for i, name in enumerate(("motor speed", "shaft torque")):
        values = [v[i] for v in finals.values()]
        spread = (max(values) - min(values)) / abs(np.mean(values))
        if spread > STEADY_TOL:
            problems.append(f"{name} differs by {spread:.3%} across levels: {finals}")
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("start_mode", [2, 3], ids=["PI", "inverse"])
def test_steady_state_controlled_all_levels(motor_fan_fmu, start_mode):
    # reference: the controlled drive settles at the set point (PI with integral action; inverse
    # simulation imposes it), where the shaft carries the fan's torque k (w_set/N)^2 / (N eta).
    p = params(motor_fan_fmu)
    w_set = p.speed_setpoint
    T_set = float(ref.load_torque(p, w_set))
    problems = []
    for level, letter in LEVELS.items():
        res = base(motor_fan_fmu, level, start_mode)
        for name, ref_value in (("motor_speed", w_set), ("shaft_torque", T_set)):
            sig = last_second(res, name)
            err = float(np.max(np.abs(sig / ref_value - 1.0)))
            if err > STEADY_TOL:
                problems.append(f"level {letter}: {name} over the last second is up to {err:.3%} from {ref_value:.4f}")
    assert not problems, f"{START_MODES[start_mode]} (w_set = {w_set}, T = {T_set:.2f} N.m):\n" + "\n".join(problems)


def test_load_parameter_moves_the_equilibrium(motor_fan_fmu):
    # reference: same hand equilibrium with k_fan set to 1.2x its default at run time (no rebuild):
    # a heavier fan load gives a lower speed and a higher torque, exactly as the equivalent circuit says.
    # Level a (quasi-static, the algebraic model) and level c (after 30 s of dynamics).
    p0 = params(motor_fan_fmu)
    k_fan = 1.2 * p0.k_fan
    w0, T0 = ref.equilibrium(p0)
    w1, T1 = ref.equilibrium(p0.with_(k_fan=k_fan))
    assert w1 < w0 and T1 > T0
    for level in (1, 3):
        res = run(motor_fan_fmu, level=level, start_mode=1, k_fan=k_fan)
        w, T = float(res["motor_speed"][-1]), float(res["shaft_torque"][-1])
        print(f"level {LEVELS[level]}, k_fan = {k_fan:.2f}: w = {w:.4f} (hand {w1:.4f}), T = {T:.2f} (hand {T1:.2f})")
        assert w == pytest.approx(w1, rel=STEADY_TOL)
        assert T == pytest.approx(T1, rel=STEADY_TOL)


# --------------------------------------------------------------------------------------------------
# Direct-on-line start: peak torque by modeling level (Figure 3.6)
# --------------------------------------------------------------------------------------------------

def _dol_peaks(fmu) -> dict[str, float]:
    return {letter: peak_abs(base(fmu, level, 1)) for level, letter in LEVELS.items()}


def test_direct_on_line_peak_torque_grows_with_level(motor_fan_fmu):
    # reference: chapter 3.3.1, Figure 3.6: inertias add a starting torque surge (b above the steady
    # torque), the driveshaft elasticity an even stronger transient torque (c above b).
    # Peak = max |T_shaft| over the 30 s run (the reducer must carry either sign).
    _, T_eq = ref.equilibrium(params(motor_fan_fmu))
    peaks = _dol_peaks(motor_fan_fmu)
    print("direct-on-line peak |T_shaft| (N.m): " + ", ".join(f"{k}: {v:.1f}" for k, v in peaks.items())
          + f"; steady {T_eq:.1f}; c/b = {peaks['c'] / peaks['b']:.3f}, b/steady = {peaks['b'] / T_eq:.3f}")
    assert peaks["b"] > T_eq, f"level b peak {peaks['b']:.1f} N.m does not exceed the steady torque {T_eq:.1f} N.m"
    assert peaks["c"] > peaks["b"], f"level c peak {peaks['c']:.1f} N.m does not exceed level b's {peaks['b']:.1f} N.m"


@pytest.mark.xfail(
    strict=True,
    reason="physics disagrees with the chapter (README, 'Where the physics disagrees'): direct-on-line peak "
    "shaft torque level c 4167 N.m, level d 2633 N.m (-37 %), level b 2644 N.m. Level c's quasi-static "
    "torque-speed curve rises with speed below breakdown (negative damping) and the 3.9 Hz shaft mode grows "
    "during the run-up; in level d's dq model the torque lags speed changes through the rotor transient time "
    "constant and the mode does not grow. Strict: if the claim ever holds, this XPASS fails and the README "
    "must be updated.",
)
def test_level_d_adds_nothing_to_the_peak_torque(motor_fan_fmu):
    # reference: chapter 3.3.1: "The last level d) ... provides no additional information for this
    # maximal torque" -- taken as: level d's peak |T_shaft| within 20 % of level c's (the issue).
    peaks = _dol_peaks(motor_fan_fmu)
    ratio = peaks["d"] / peaks["c"]
    print(f"direct-on-line peak |T_shaft|: level b {peaks['b']:.1f}, level c {peaks['c']:.1f}, "
          f"level d {peaks['d']:.1f} N.m, d/c = {ratio:.3f}")
    assert abs(ratio - 1.0) <= 0.20, (
        f"level d's peak shaft torque {peaks['d']:.1f} N.m is {ratio - 1:+.1%} from level c's {peaks['c']:.1f} N.m "
        f"(chapter: d adds nothing for this maximum; issue: within 20 %)"
    )


# --------------------------------------------------------------------------------------------------
# Driveshaft mode: frequencies from the linear two-inertia theory
# --------------------------------------------------------------------------------------------------
# Which J_eq: while power flows from the motor to the fan (T_shaft > 0, w_m > 0: the whole run-up and
# the ramps here), the spec's reducer transmits T_ls = N eta T_shaft, so the fan equation referred to
# the high-speed axis reads T_shaft = J_fan/(N^2 eta) dw_m/dt + ...: the shaft's spring works against
# J_eq_forward = J_fan/(N^2 eta) = 12.08 kg.m2, not J_fan/N^2 = 11.72 kg.m2 (eq. 3.6 ignores the
# efficiency). The theory below uses J_eq_forward; the efficiency-free figures (1.400 Hz, 3.913 Hz) are
# printed beside it and are within 1.6 % of it, far inside the 5 % tolerance. The damping (D_shaft,
# the fan's load slope, the motor curve's slope during the run-up) lowers the frequency by
# 1 - sqrt(1 - zeta^2): < 0.5 % after the ramp (zeta < 0.1), <= 1.1 % in the run-up window (|zeta| <= 0.15).

FREQ_TOL = 0.05  # issue: within 5 %


def test_direct_on_line_runup_rings_at_two_inertia_frequency(motor_fan_fmu):
    # reference: free motor inertia, f = sqrt(K (1/J_m + 1/J_eq_forward)) / (2 pi) ~ 3.9 Hz.
    # Measured on level c's direct-on-line run-up: T_shaft minus its moving average over one theoretical
    # period, zero crossings, from t = 0 until the motor's mean speed (the same moving average of w_m:
    # the point the oscillation is linearised about; w_m itself swings by tens of rad/s) first reaches
    # the speed above which the motor curve's slope (negative damping, steep towards breakdown) makes
    # the linearised mode's |damping ratio| exceed 0.15 (ref.runup_linear_limit, hand computation).
    p = params(motor_fan_fmu)
    f_theory = ref.frequency_two_inertia(p)
    w_lim = ref.runup_linear_limit(p)
    res = base(motor_fan_fmu, 3, 1)
    t, w, T = res["time"], np.asarray(res["motor_speed"]), np.asarray(res["shaft_torque"])
    td, d = detrend_moving_average(t, T, 1.0 / f_theory)
    w_mean = moving_average(t, w, 1.0 / f_theory)
    assert np.any(w_mean >= w_lim), f"the motor's mean speed never reaches {w_lim:.1f} rad/s"
    t_end = float(td[np.argmax(w_mean >= w_lim)])
    window = td <= t_end
    f, n = ringing_frequency(td[window], d[window])
    print(f"run-up ringing (level c, t <= {t_end:.3f} s, mean w_m < {w_lim:.1f} rad/s): {f:.4f} Hz from {n} zero crossings; "
          f"theory {f_theory:.4f} Hz with J_fan/(N^2 eta), {ref.frequency_two_inertia(p, p.J_eq):.4f} Hz with J_fan/N^2; "
          f"error {f / f_theory - 1:+.2%}")
    assert f == pytest.approx(f_theory, rel=FREQ_TOL)


def _inverse_ringing(fmu, **overrides) -> tuple[float, int, float]:
    """Frequency of the shaft-torque ringing after the end of the set-point ramp under inverse
    simulation at level c: the motor speed is imposed and constant from t = ramp_time on, so T_shaft
    rings about its final (constant) value; window ramp_time .. ramp_time + 8 s."""
    p = params(fmu, **overrides)
    res = run(fmu, level=3, start_mode=3, **overrides)
    t, T = res["time"], np.asarray(res["shaft_torque"])
    window = (t >= p.ramp_time) & (t <= p.ramp_time + 8.0)
    assert p.ramp_time + 8.0 < STOP_TIME - 1.0
    d = T[window] - float(np.mean(last_second(res, "shaft_torque")))
    f, n = ringing_frequency(t[window], d)
    return f, n, float(np.max(np.abs(d)))


def test_inverse_simulation_rings_at_motor_imposed_frequency(motor_fan_fmu):
    # reference: eq. 3.8, motor inertia neutralised: f = sqrt(K / J_eq_forward) / (2 pi) (1.4 Hz with J_eq).
    p = params(motor_fan_fmu)
    f_theory = ref.frequency_motor_imposed(p)
    f, n, amp = _inverse_ringing(motor_fan_fmu)
    print(f"inverse simulation ringing after the ramp (level c): {f:.4f} Hz from {n} zero crossings "
          f"(first amplitude {amp:.1f} N.m); theory {f_theory:.4f} Hz with J_fan/(N^2 eta), "
          f"{ref.frequency_motor_imposed(p, p.J_eq):.4f} Hz with J_fan/N^2 (eq. 3.8); error {f / f_theory - 1:+.2%}")
    assert f == pytest.approx(f_theory, rel=FREQ_TOL)


def _measured_J_eq(fmu, **overrides) -> float:
    """Inertia seen by the shaft, from the inverse-simulation ramp at level c: with the motor speed
    imposed on a ramp of constant acceleration a = speed_setpoint / ramp_time, the shaft carries the
    fan's torque plus J a: J = mean(T_shaft - k w_fan^2 / (N eta)) / a over the ramp (1 s after its
    start to 0.5 s before its end; the ringing about that mean averages out to ~1-2 %)."""
    p = params(fmu, **overrides)
    res = run(fmu, level=3, start_mode=3, **overrides)
    t = res["time"]
    window = (t >= 1.0) & (t <= p.ramp_time - 0.5)
    load = p.k_fan * np.asarray(res["fan_speed"]) ** 2 / (p.gear_ratio * p.gear_efficiency)
    a = p.speed_setpoint / p.ramp_time
    return float(np.mean((np.asarray(res["shaft_torque"]) - load)[window]) / a)


def test_fan_inertia_parameter_changes_the_physics(motor_fan_fmu):
    # reference: eqs. 3.6 and 3.8, applied to J_fan set to twice its default at run time (no rebuild):
    # J_eq doubles (measured from the ramp torque), so the inverse-simulation ringing frequency drops by
    # sqrt(2). Both J_eq figures are checked against J_fan/(N^2 eta).
    p = params(motor_fan_fmu)
    J_fan2 = 2.0 * p.J_fan
    p2 = params(motor_fan_fmu, J_fan=J_fan2)
    J1, J2 = _measured_J_eq(motor_fan_fmu), _measured_J_eq(motor_fan_fmu, J_fan=J_fan2)
    f1, _, _ = _inverse_ringing(motor_fan_fmu)
    f2, n2, _ = _inverse_ringing(motor_fan_fmu, J_fan=J_fan2)
    print(f"J_eq measured {J1:.3f} -> {J2:.3f} kg.m2 (ratio {J2 / J1:.4f}; hand {p.J_eq_forward:.3f} -> {p2.J_eq_forward:.3f}); "
          f"ringing {f1:.4f} -> {f2:.4f} Hz (ratio {f1 / f2:.4f}, sqrt(2) = {math.sqrt(2):.4f}; "
          f"hand {ref.frequency_motor_imposed(p2):.4f} Hz)")
    assert J1 == pytest.approx(p.J_eq_forward, rel=FREQ_TOL)
    assert J2 == pytest.approx(p2.J_eq_forward, rel=FREQ_TOL)
    assert J2 / J1 == pytest.approx(2.0, rel=FREQ_TOL)
    assert f2 == pytest.approx(ref.frequency_motor_imposed(p2), rel=FREQ_TOL)
    assert f1 / f2 == pytest.approx(math.sqrt(2.0), rel=FREQ_TOL)


# --------------------------------------------------------------------------------------------------
# Variable-speed start (section 3.3.2, Figures 3.7-3.8)
# --------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("start_mode", [2, 3], ids=["PI", "inverse"])
def test_variable_speed_start_cuts_the_peak_torque(motor_fan_fmu, start_mode):
    # reference: chapter 3.3.2 / Figure 3.8: with a 10 s speed ramp the maximal reducer torque is "much
    # lower"; issue: at least 3x lower than direct-on-line (level c, the model that is just sufficient).
    # Hand figure: a start that follows the ramp carries, just before the ramp ends, the quasi-static
    # torque T_load(w_set) + J_eq_forward * w_set / ramp_time (steady torque plus the fan's acceleration
    # torque; any ringing comes on top). No controller that follows the ramp can go much below it, so the
    # factor 3 needs a direct-on-line peak of about 3x that figure; the message says how far off it is.
    p = params(motor_fan_fmu)
    dol = peak_abs(base(motor_fan_fmu, 3, 1))
    ctrl = peak_abs(base(motor_fan_fmu, 3, start_mode))
    quasi_static = float(ref.load_torque(p, p.speed_setpoint)) + p.J_eq_forward * p.speed_setpoint / p.ramp_time
    print(f"level c peak |T_shaft|: direct-on-line {dol:.1f} N.m, {START_MODES[start_mode]} {ctrl:.1f} N.m, "
          f"ratio {dol / ctrl:.3f}; quasi-static torque at the end of the ramp {quasi_static:.1f} N.m "
          f"(direct-on-line peak / it = {dol / quasi_static:.3f})")
    assert dol >= 3.0 * ctrl, (
        f"direct-on-line peak {dol:.1f} N.m is only {dol / ctrl:.2f}x the {START_MODES[start_mode]} peak {ctrl:.1f} N.m "
        f"(issue: >= 3x); a start following the {p.ramp_time:g} s ramp carries ~{quasi_static:.1f} N.m at its end "
        f"(steady torque + J_eq a), i.e. the direct-on-line peak is only {dol / quasi_static:.2f}x that with these parameters"
    )


@pytest.mark.parametrize("level", list(LEVELS), ids=[f"level-{c}" for c in LEVELS.values()])
def test_pi_and_inverse_simulation_give_the_same_speed(motor_fan_fmu, level):
    # reference: chapter 3.3.2: "The two models produce the same results" (Figure 3.8); issue: speeds
    # within 1 % of the set point speed at every output point.
    p = params(motor_fan_fmu)
    w_pi = np.asarray(base(motor_fan_fmu, level, 2)["motor_speed"])
    w_inv = np.asarray(base(motor_fan_fmu, level, 3)["motor_speed"])
    dev = np.abs(w_pi - w_inv)
    k = int(np.argmax(dev))
    t = base(motor_fan_fmu, level, 2)["time"]
    print(f"level {LEVELS[level]}: max |w_PI - w_inverse| = {dev[k]:.4f} rad/s ({dev[k] / p.speed_setpoint:.3%} of "
          f"the set point) at t = {t[k]:.3f} s")
    assert dev[k] <= 0.01 * p.speed_setpoint, (
        f"level {LEVELS[level]}: PI and inverse simulation differ by {dev[k]:.4f} rad/s at t = {t[k]:.3f} s "
        f"(PI {w_pi[k]:.4f}, inverse {w_inv[k]:.4f}); allowed 1 % of {p.speed_setpoint}"
    )


# --------------------------------------------------------------------------------------------------
# Activity index (eq. 3.3, Table 3.3)
# --------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("start_mode", list(START_MODES), ids=list(START_MODES.values()))
@pytest.mark.parametrize("level", list(LEVELS), ids=[f"level-{c}" for c in LEVELS.values()])
def test_activity_shares_are_consistent(motor_fan_fmu, level, start_mode):
    # reference: spec: activity = integral of |power| (eq. 3.3), so it starts at 0 and never decreases;
    # share_i = 100 activity_i / sum (0 while the sum is 0), so the shares sum to 100 % when the sum > 0.
    # Level b has a rigid shaft (theta stays 0): no stiffness activity.
    # "Never decreases" holds up to the integration error of the activity, which follows the FMU's
    # tolerance (FMU_RTOL): near the steady state |power| is a small difference of large torques, so
    # the speeds' error allowance (rtol of 153 rad/s) times the torque slope enters the integral, and
    # the solver's steps reach tens of ms (up to 2.5 rtol of the activity between 1 ms samples was
    # measured). While every doStep was one solver step of at most 1 ms, this was below 1e-9.
    res = base(motor_fan_fmu, level, start_mode)
    A = np.column_stack([np.asarray(res[n]) for n in ACTIVITIES])
    S = np.column_stack([np.asarray(res[n]) for n in SHARES])
    total = A.sum(axis=1)
    assert np.all(A >= 0.0), "negative activity"
    assert np.all(np.diff(A, axis=0) >= -10 * FMU_RTOL * np.maximum(A[1:], 1.0)), "an activity decreases"
    assert np.all(A[0] == 0.0), f"activities at t = 0: {A[0]}"
    pos = total > 0.0
    np.testing.assert_allclose(S[pos].sum(axis=1), 100.0, rtol=0, atol=1e-6, err_msg="shares do not sum to 100 %")
    np.testing.assert_allclose(S[pos], 100.0 * A[pos] / total[pos, None], rtol=0, atol=1e-6,
                               err_msg="share != 100 activity / total")
    assert np.all(S[~pos] == 0.0), "shares must be 0 while the total activity is 0"
    if level == 2:
        assert np.all(A[:, 1] == 0.0), "level b (rigid shaft) has stiffness activity"
    if level >= 2:
        assert pos[-1], f"level {LEVELS[level]}: no activity at all after {STOP_TIME} s"
    print(f"level {LEVELS[level]}, {START_MODES[start_mode]}: shares at 30 s (motor inertia, shaft stiffness, fan inertia) = "
          + ", ".join(f"{s:.2f} %" for s in S[-1]))


def _stiffness_shares(fmu, start_mode: int) -> tuple[float, float]:
    """Shaft stiffness share (%) at 30 s, level c: direct-on-line and `start_mode`."""
    shares = {m: [float(base(fmu, 3, m)[n][-1]) for n in SHARES] for m in (1, start_mode)}
    activities = {m: [float(base(fmu, 3, m)[n][-1]) for n in ACTIVITIES] for m in (1, start_mode)}
    for m, sh in shares.items():
        print(f"level c, {START_MODES[m]:>14}: motor inertia {sh[0]:6.2f} %, shaft stiffness {sh[1]:6.3f} %, "
              f"fan inertia {sh[2]:6.2f} % (activities " + ", ".join(f"{a:.0f}" for a in activities[m]) + " J)")
    dol, ctrl = shares[1][1], shares[start_mode][1]
    assert dol > 0.0, "no stiffness activity in the direct-on-line start at level c"
    assert ctrl > 0.0, f"{START_MODES[start_mode]}: no stiffness activity at level c (the shaft is twisted by the load)"
    return dol, ctrl


def test_controller_removes_the_shaft_stiffness_activity(motor_fan_fmu):
    # reference: chapter 3.3.2, Table 3.3 (9 % -> 0.3 % for the stiffness): with the speed controller
    # (the PI of Figure 3.7) the driveshaft stiffness' share of the activity falls by at least 10x
    # against the direct start (level c) -- the criterion.
    dol, ctrl = _stiffness_shares(motor_fan_fmu, 2)
    assert dol >= 10.0 * ctrl, (
        f"shaft stiffness share: direct-on-line {dol:.3f} %, PI {ctrl:.3f} % "
        f"(ratio {dol / ctrl:.2f}, issue: >= 10; chapter Table 3.3: 9 % -> 0.3 %)"
    )


def test_inverse_simulation_reduces_the_shaft_stiffness_activity(motor_fan_fmu):
    # Inverse simulation is the controller's ideal stand-in, not a controller: it imposes the ramp's
    # corners (an acceleration step of w_set/ramp_time at t = 0 and t = ramp_time), each of which sets
    # the lightly damped 1.4 Hz mode ringing with amplitude ~J_eq a (~180 N.m); the PI's finite
    # bandwidth rounds them. Measured here: 15.0 % -> 1.6 % (9.3x), against 14.7x with the PI. The
    # check: the share still falls by more than 5x, and the stiffness activity is at least the energy
    # finally stored in the twisted shaft, K theta^2 / 2 (activity integrates |power| >= its net sum).
    dol, ctrl = _stiffness_shares(motor_fan_fmu, 3)
    assert dol >= 5.0 * ctrl, f"direct-on-line {dol:.3f} %, inverse simulation {ctrl:.3f} % (ratio {dol / ctrl:.2f})"
    p = params(motor_fan_fmu)
    res = base(motor_fan_fmu, 3, 3)
    theta_end = float(res["shaft_torque"][-1]) / p.K_shaft
    stored = 0.5 * p.K_shaft * theta_end**2
    assert float(res["activity_shaft_stiffness"][-1]) >= stored * (1 - 1e-6), (stored, float(res["activity_shaft_stiffness"][-1]))


# --------------------------------------------------------------------------------------------------
# Spectral content of the set point (section 3.3.3, Figure 3.13)
# --------------------------------------------------------------------------------------------------
# "Oscillation" = the shaft torque the driveshaft's elasticity adds: max over the run of
# |T_shaft(elastic shaft) - T_shaft(rigid shaft)|, both runs at level c under the same PI controller
# and the same set point, the rigid one with keep_shaft_stiffness = false (the reduced model of
# Figure 3.10, the quasi-static J_eq-based torque of the same motion). The chapter's conclusion for the
# filtered case is precisely that "the effect of the driveshaft elasticity can be neglected when sizing
# the reducer", i.e. that this difference is small. (A detrended peak-to-peak of T_shaft alone would
# count the slow 0.5 Hz torque swing of the filtered start, only ~3x below 1.4 Hz, as oscillation.)

def _elasticity_torque(fmu, setpoint_filter: int) -> tuple[float, float, float]:
    start = dict(level=3, start_mode=2, ramp_time=0.0, setpoint_filter=setpoint_filter)
    elastic = run(fmu, **start)
    rigid = run(fmu, keep_shaft_stiffness=False, **start)
    diff = float(np.max(np.abs(np.asarray(elastic["shaft_torque"]) - np.asarray(rigid["shaft_torque"]))))
    return diff, peak_abs(elastic), peak_abs(rigid)


def test_filtered_setpoint_avoids_exciting_the_shaft(motor_fan_fmu):
    # reference: chapter 3.3.3, Figure 3.13: a set point filtered below the 1.4 Hz resonance (setpoint_filter
    # 1) excites a smaller shaft-torque oscillation than an unfiltered step (ramp_time = 0, setpoint_filter 0),
    # and than a set point filtered above it (setpoint_filter 2), all under PI control.
    p_md = start_values(motor_fan_fmu)
    figures = {f: _elasticity_torque(motor_fan_fmu, f) for f in (0, 1, 2)}
    names = {0: "unfiltered step", 1: f"filter {p_md['filter_frequency_below']} Hz",
             2: f"filter {p_md['filter_frequency_above']} Hz"}
    for f, (diff, pk, pk_rigid) in figures.items():
        print(f"PI, level c, {names[f]:>16}: elasticity torque {diff:8.1f} N.m, peak |T_shaft| {pk:8.1f} N.m "
              f"(rigid shaft {pk_rigid:8.1f} N.m)")
    below, step, above = figures[1][0], figures[0][0], figures[2][0]
    assert below < step, f"filtered below 1.4 Hz: {below:.1f} N.m, not below the unfiltered step's {step:.1f} N.m"
    assert below < above, f"filtered below 1.4 Hz: {below:.1f} N.m, not below the filter above 1.4 Hz: {above:.1f} N.m"
