"""MotorFan against its contract (docs/motor-fan-spec.md) and the claims of chapter 3, sections 3.1-3.3.

The FMU's defaults are the book authors' own values (book file Chap3_CoolingTowerFan.mo,
marcbudinger/MultiphysicsModelingTechSys, files/; each default's component is in the spec and in
SPEC_PARAMETERS below). Every reference value is computed here from the FMU's own parameter values (the
start values of its modelDescription.xml, plus a test's overrides) with the hand formulas of
motor_fan_reference.py (the torque-speed table read linearly or by Akima's spline, the spec's equivalent
circuit, eqs. 3.4-3.8, linear two-inertia theory, the set-point filter by scipy.signal.lsim); nothing
comes from a previous run of the FMU. Where a test checks a claim of the chapter, the measured figures
are printed (`pytest -s`) and stated in the failure message; such a test is not loosened when the
physics disagrees with the chapter, the disagreement is discussed instead.

This project's first parameter set (before the book file was read: a 160 kW 4-pole motor by its
circuit, N = 10, ...) stays reachable through parameters (FIRST_SET); the tests that teach something
about it pass it explicitly and say so.

Simulations: fmpy, Co-Simulation, 0..30 s, communication step (= output_interval, TOOLS.md) 1e-3 s,
at the tolerance the FMU's DefaultExperiment declares (fmpy passes it: `fmu_rtol`). Each configuration
(a set of start values) is simulated once per session and cached (`run`), so the physics tests share
the 12 level x start_mode runs plus a few variants.

fmpy quirk (TOOLS.md): each result row is stamped with a communication point and holds the values
after the step that ends there; at 1e-3 s this shifts nothing measurable here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.fmi1 import FMICallException

import motor_fan_reference as ref
from conftest import DIST_DIR, fmu_key as _fmu_key, model_description as _model_description, require_fmu, simulate_cs
from fmi_host import Slave

STOP_TIME = 30.0
OUTPUT_INTERVAL = 1e-3

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
    "activity_winding_inductance": "J",
    "share_winding_inductance": "%",
}
ACTIVITIES = ("activity_motor_inertia", "activity_shaft_stiffness", "activity_fan_inertia")
SHARES = ("share_motor_inertia", "share_shaft_stiffness", "share_fan_inertia")
# Every storage element (the runtime's shares are among these): Table 3.3's three, and at level d
# (direct start) the windings' magnetic energy.
STORAGE_ACTIVITIES = ACTIVITIES + ("activity_winding_inductance",)
STORAGE_SHARES = SHARES + ("share_winding_inductance",)

BOOK = "book file Chap3_CoolingTowerFan.mo"
# Spec, "Parameters": name -> (type, unit, variability, default, source). unit None: Integer/Boolean
# (no unit). The defaults as the spec (and the book file) writes them.
SPEC_PARAMETERS = {
    "level": ("Enumeration", None, "fixed", 3, "Figure 3.5 a-d"),
    "start_mode": ("Enumeration", None, "fixed", 1, "sections 3.3.1-3.3.2"),
    "setpoint_filter": ("Enumeration", None, "fixed", 1, f"{BOOK}, component secondOrder1 (Transient_SpeedControler)"),
    "keep_shaft_stiffness": ("Boolean", None, "fixed", True, "Figure 3.10"),
    "motor_model": ("Enumeration", None, "fixed", 1, f"{BOOK}: the table TorqueSpeed at levels a-c"),
    "motor_table_interpolation": ("Enumeration", None, "fixed", 0, f"{BOOK}: linear in Steady_State/Transient_Dynamic, Akima in Transient_Resonance"),
    **{f"motor_table_speed_{i + 1}": ("Real", "rad/s", "fixed", w, f"{BOOK}, component TorqueSpeed") for i, (w, _) in enumerate(ref.BOOK_TABLE)},
    **{f"motor_table_torque_{i + 1}": ("Real", "N.m", "tunable", T, f"{BOOK}, component TorqueSpeed") for i, (_, T) in enumerate(ref.BOOK_TABLE)},
    "J_motor": ("Real", "kg.m2", "tunable", 1.72, f"chapter 3.3.3; {BOOK}, component inertia_motor"),
    "J_fan": ("Real", "kg.m2", "tunable", 3000.0, f"{BOOK}, component inertia_fan"),
    "gear_ratio": ("Real", "1", "tunable", 16.0, f"{BOOK}, component lossyGear"),
    "gear_efficiency": ("Real", "1", "tunable", 0.94, f"{BOOK}, component lossyGear (lossTable 0.94, 0.94)"),
    "K_shaft": ("Real", "N.m/rad", "tunable", 866.0, f"{BOOK}, component spring: c"),
    "D_shaft": ("Real", "N.m.s/rad", "tunable", 866.0 / 100.0 / math.sqrt(886.0 / 1.7), f"{BOOK}, component spring: d"),
    "T_fan_nominal": ("Real", "N.m", "tunable", 7742.6, f"{BOOK}, component quadraticSpeedDependentTorque: -tau_nominal"),
    "speed_fan_nominal": ("Real", "rad/s", "tunable", 19.373154697137, f"{BOOK}, component quadraticSpeedDependentTorque: w_nominal"),
    "R_s": ("Real", "Ohm", "tunable", 0.038, "the book's induction machine"),
    "R_r": ("Real", "Ohm", "tunable", 0.038, "the book's induction machine"),
    "L_s_sigma": ("Real", "H", "tunable", 2e-4, "the book's induction machine"),
    "L_r_sigma": ("Real", "H", "tunable", 4e-4, "the book's induction machine"),
    "L_m": ("Real", "H", "tunable", 0.012, "the book's induction machine"),
    "pole_pairs": ("Real", "1", "fixed", 1.0, "the book's induction machine (314 rad/s synchronous, the table's zero)"),
    "winding_connection": ("Enumeration", None, "fixed", 2, "the book's induction machine: delta (terminalBox.delta in its result files)"),
    "U_supply": ("Real", "V", "tunable", 230.0, "the book's induction machine: VNominal = 230 V line to line"),
    "f_supply": ("Real", "Hz", "tunable", 50.0, "chapter: 50 Hz network"),
    "speed_setpoint": ("Real", "rad/s", "tunable", 300.0, f"{BOOK}, component timeTable"),
    "ramp_time": ("Real", "s", "tunable", 10.0, f"chapter; {BOOK}, component timeTable"),
    "Kp_speed": ("Real", "N.m.s/rad", "tunable", 10000.0, f"{BOOK}, component PI: k"),
    "Ki_speed": ("Real", "N.m/rad", "tunable", 100000.0, f"{BOOK}, component PI: k / T"),
    "T_limit": ("Real", "N.m", "tunable", 0.0, f"{BOOK}: the PI has no limit (0 = none)"),
    "T_tracking": ("Real", "s", "tunable", 0.09, "chosen (acts only with a T_limit)"),
    "filter_frequency_below": ("Real", "Hz", "tunable", 0.5 * 3.14 / math.pi, f"{BOOK}, component secondOrder1: w = 2*3.14*0.5"),
    "filter_frequency_above": ("Real", "Hz", "tunable", 5.0, "chosen (Figure 3.13)"),
    "filter_damping": ("Real", "1", "tunable", 1.0, f"{BOOK}, component secondOrder1: D"),
    "actuator_angular_frequency": ("Real", "rad/s", "tunable", 2.0 * 3.14 * 800.0, f"{BOOK}, component secondOrder: w = 2*3.14*800"),
    "actuator_damping": ("Real", "1", "tunable", 1.0, f"{BOOK}, component secondOrder: D"),
}
# Parameters of the first set that the spec no longer has.
REMOVED_PARAMETERS = ("k_fan",)

# This project's first set (the defaults before the book file was read), through parameters (spec,
# "The first set"): the 160 kW 400 V 4-pole motor by its circuit, N = 10, eta 0.97, J_fan 1172,
# K 906.85, D 5, k_fan 42.9 (T_fan_nominal = 42.9 x 15.35^2 at the rated fan speed 15.35 rad/s),
# PI Kp 200, Ki 2000, T_limit 2500, no actuator lag, no filter, set point 153.5 rad/s.
FIRST_SET = dict(
    motor_model=2, R_s=0.012, R_r=0.020, L_s_sigma=2.5e-4, L_r_sigma=2.5e-4, L_m=0.01, pole_pairs=2.0, winding_connection=1, U_supply=400.0,
    gear_ratio=10.0, gear_efficiency=0.97, J_fan=1172.0, K_shaft=906.85, D_shaft=5.0,
    T_fan_nominal=42.9 * 15.35**2, speed_fan_nominal=15.35,
    speed_setpoint=153.5, Kp_speed=200.0, Ki_speed=2000.0, T_limit=2500.0, actuator_angular_frequency=0.0,
    setpoint_filter=0, filter_frequency_below=0.5, filter_damping=0.7,
)


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


def fmu_rtol(fmu) -> float:
    """The relative tolerance the runs use: the DefaultExperiment's, which fmpy passes to
    fmi2SetupExperiment when the caller gives none."""
    return float(_model_description(_fmu_key(fmu)).defaultExperiment.tolerance)


def params(fmu, **overrides) -> ref.MotorFanParams:
    """The physical parameters the FMU simulates with: its start values updated by `overrides`."""
    return ref.MotorFanParams.from_values({**start_values(fmu), **overrides})


def _simulate(key: tuple[str, float], start_items: tuple):
    return simulate_cs(key, start_items, STOP_TIME, OUTPUT_INTERVAL, tuple(OUTPUTS))


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


def setpoint_settled(p: ref.MotorFanParams, t: np.ndarray, rel: float = 1e-4) -> float:
    """First output time at or after the end of the ramp from which the hand set point (ramp through
    the filter) stays within `rel` of speed_setpoint: from then on the controlled motor turns at a
    constant speed."""
    w_ref, _ = ref.setpoint(p, t)
    off = np.abs(w_ref - p.speed_setpoint) > rel * p.speed_setpoint
    late = t >= p.ramp_time
    last_off = np.where(off & late)[0]
    k = (last_off[-1] + 1) if len(last_off) else int(np.argmax(late))
    assert k < len(t) - 1, "the set point does not settle within the run"
    return float(t[k])


# --------------------------------------------------------------------------------------------------
# Interface: every physical value is a parameter with a unit
# --------------------------------------------------------------------------------------------------

def test_model_description_parameters_and_outputs(motor_fan_fmu):
    # reference: the spec's tables "Parameters" and "Outputs", and "DefaultExperiment: 0 to 30 s, step 1e-3 s"
    md = read_model_description(str(motor_fan_fmu))
    variables = {v.name: v for v in md.modelVariables}
    problems = []
    assert md.coSimulation is not None, "MotorFan must be a Co-Simulation FMU"
    for name, (vtype, unit, variability, default, source) in SPEC_PARAMETERS.items():
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
            if (isinstance(default, float) and not math.isclose(got, default, rel_tol=1e-12, abs_tol=1e-300)) or (
                not isinstance(default, float) and got != default
            ):
                problems.append(f"{name}: start {v.start!r}, spec {default!r} ({source})")
    # The item names: the chapter's levels a-d (Figure 3.5), not 1..4.
    items = [(i.name, int(i.value)) for i in variables["level"].declaredType.items] if variables.get("level") else None
    if items != [("a", 1), ("b", 2), ("c", 3), ("d", 4)]:
        problems.append(f"level: Enumeration items {items}, spec a-d valued 1..4")
    for name in REMOVED_PARAMETERS:
        if name in variables:
            problems.append(f"{name}: the spec no longer has this parameter")
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

    # the spec's derived figures hold for the default parameters (eqs. 3.6 and 3.8): the chapter's
    # 11.72 kg m2 (3000 / 16^2 = 11.71875) and its 1.4 Hz, to the chapter's one decimal
    # (sqrt(866 / 11.72) / (2 pi) = 1.368 Hz); the free two-inertia mode 3.8 Hz
    p = params(motor_fan_fmu)
    f_38 = ref.frequency_motor_imposed(p, p.J_eq)
    f_free = ref.frequency_two_inertia(p, p.J_eq)
    print(f"J_eq = {p.J_eq:.5f} kg.m2 (J_eq_forward {p.J_eq_forward:.4f}); eq. 3.8: {f_38:.4f} Hz "
          f"(with J_eq_forward {ref.frequency_motor_imposed(p):.4f} Hz); free mode {f_free:.4f} Hz; "
          f"k = T_fan_nominal / speed_fan_nominal^2 = {p.k_fan:.4f} N.m.s2/rad2")
    assert p.J_eq == pytest.approx(11.72, rel=2e-4)
    assert round(f_38, 1) == 1.4, f"eq. 3.8 with the book's values gives {f_38:.4f} Hz, not the chapter's 1.4 Hz"
    assert round(f_free, 1) == 3.8, f"free two-inertia mode {f_free:.4f} Hz, spec 3.8 Hz"


# --------------------------------------------------------------------------------------------------
# Every level and start mode simulates; what initialization refuses
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


def _refused_at_initialization(fmu, integers: dict, reals: dict, reason: str) -> None:
    """Initialization with these values fails (FMICallException), and the FMU's error message names
    `reason` (so it fails for that reason, not another)."""
    with Slave(fmu) as s:
        s.instantiate(logging_on=True)
        s.fmu.setupExperiment(startTime=0.0, stopTime=STOP_TIME)
        if integers:
            s.fmu.setInteger([s.vr[k] for k in integers], list(integers.values()))
        if reals:
            s.set(**reals)
        with pytest.raises(FMICallException):
            s.fmu.enterInitializationMode()
            s.fmu.exitInitializationMode()
        errors = [m for status, _, m in s.log.records if status >= 3]
        print(f"refused: {errors}")
        assert any(reason in m for m in errors), f"no error message naming {reason!r}: {s.log.records}"


def test_inverse_simulation_refuses_an_unfiltered_step(motor_fan_fmu):
    # reference: spec "Inverse simulation needs a finite acceleration: ramp_time = 0 with the filter off
    # is refused at initialization"
    _refused_at_initialization(motor_fan_fmu, {"start_mode": 3, "setpoint_filter": 0}, {"ramp_time": 0.0}, "ramp_time")


def test_table_speeds_must_increase(motor_fan_fmu):
    # reference: spec "Motor": the table's speeds must increase (the interpolation divides by their
    # differences); a table with two equal speeds is refused at initialization
    w5 = start_values(motor_fan_fmu)["motor_table_speed_5"]
    _refused_at_initialization(motor_fan_fmu, {"level": 1}, {"motor_table_speed_6": w5}, "motor_table_speed_6")


# --------------------------------------------------------------------------------------------------
# The motor curve (spec, "Motor"): the table, read as the level's book file, or the circuit
# --------------------------------------------------------------------------------------------------

def test_motor_curve_follows_the_level_and_the_parameters(motor_fan_fmu):
    # reference: the hand equilibrium of each curve (motor_fan_reference: the table read linearly or by
    # Akima, the equivalent circuit). The three give distinct equilibria (300.457, 300.562, 300.799
    # rad/s with the book's values: 3.5e-4 and 1.1e-3 apart), far more than the 1e-9 (level a, algebraic)
    # and 1e-6 (level c, after 30 s of dynamics) the FMU must meet, so each run shows which curve it used.
    cases = [
        (1, {}, "linear"),  # level a: motor_table_interpolation 0 = linear (book file Steady_State)
        (1, {"motor_table_interpolation": 2}, "akima"),
        (1, {"motor_model": 2}, "circuit"),
        (3, {}, "akima"),  # level c: 0 = Akima (book file Transient_Resonance)
        (3, {"motor_table_interpolation": 1}, "linear"),
    ]
    problems = []
    for level, overrides, curve in cases:
        p = params(motor_fan_fmu, level=level, **overrides)
        assert p.curve == curve, (level, overrides, p.curve)
        w_eq, T_eq = ref.equilibrium(p)
        res = run(motor_fan_fmu, level=level, start_mode=1, **overrides)
        w, T = float(res["motor_speed"][-1]), float(res["shaft_torque"][-1])
        tol = 1e-9 if level == 1 else 1e-6
        print(f"level {LEVELS[level]} {overrides or 'defaults'} ({curve}): w = {w:.9f} rad/s (hand {w_eq:.9f}), "
              f"T = {T:.6f} N.m (hand {T_eq:.6f})")
        for name, got, want in (("speed", w, w_eq), ("torque", T, T_eq)):
            if abs(got / want - 1.0) > tol:
                problems.append(f"level {LEVELS[level]} {overrides}: {name} {got:.9g}, hand ({curve}) {want:.9g} "
                                f"({got / want - 1:+.2e}, allowed {tol:g})")
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("interpolation", [1, 2], ids=["linear", "akima"])
def test_table_extrapolates_beyond_its_last_point(motor_fan_fmu, interpolation):
    # reference: spec "Motor": beyond its last point the table continues along a straight line, the last
    # segment's (linear) or the curve's tangent at the last point (Akima), as CombiTable1D's
    # LastTwoPoints. With the last two torques raised to 700 and 600 N.m the load meets the motor beyond
    # 314 rad/s, so the level-a equilibrium lies on the extrapolation (hand: motor_fan_reference).
    table = {"motor_table_torque_9": 700.0, "motor_table_torque_10": 600.0}
    p = params(motor_fan_fmu, level=1, motor_table_interpolation=interpolation, **table)
    w_eq, T_eq = ref.equilibrium(p)
    assert w_eq > p.table_speed[-1], "the hand equilibrium must lie beyond the table for this test"
    res = run(motor_fan_fmu, level=1, start_mode=1, motor_table_interpolation=interpolation, **table)
    w, T = float(res["motor_speed"][-1]), float(res["shaft_torque"][-1])
    print(f"{p.curve} table raised at its end: w = {w:.9f} rad/s (hand {w_eq:.9f}, {w_eq - p.table_speed[-1]:.3f} rad/s "
          f"beyond the last point, slope there {ref.table_slope(p, w_eq, p.curve):.4f} N.m.s/rad), T = {T:.6f} (hand {T_eq:.6f})")
    assert w == pytest.approx(w_eq, rel=1e-9)
    assert T == pytest.approx(T_eq, rel=1e-9)


def test_current_and_power_come_from_the_circuit(motor_fan_fmu):
    # reference: spec "Outputs": at levels a-c the current and the power are the equivalent circuit's
    # whatever gives the torque: direct-on-line the circuit's steady state at the motor speed; under
    # control (converter-fed) the circuit's current at the stable slip where it gives the motor torque,
    # and the power T_m w_m. Checked at every output point (hand: motor_fan_reference).
    problems = []
    for level, start_mode in ((1, 1), (3, 1), (1, 2), (3, 2), (3, 3)):
        p = params(motor_fan_fmu, level=level)
        res = base(motor_fan_fmu, level, start_mode)
        w, T_m = np.asarray(res["motor_speed"]), np.asarray(res["motor_torque"])
        if start_mode == 1:
            _, current, power = ref.circuit_steady_state(p, w)
        else:
            current, power = ref.converter_fed(p, T_m, w)
        for name, want in (("stator_current_rms", current), ("electrical_power", power)):
            err = float(np.max(np.abs(np.asarray(res[name]) - want)) / np.max(np.abs(want)))
            print(f"level {LEVELS[level]}, {START_MODES[start_mode]}: {name} at 30 s {res[name][-1]:.4f} "
                  f"(hand {want[-1]:.4f}); largest difference {err:.1e} of its range")
            if err > 1e-9:
                problems.append(f"level {LEVELS[level]}, {START_MODES[start_mode]}: {name} up to {err:.2e} of its range from the circuit's")
    assert not problems, "\n".join(problems)


# --------------------------------------------------------------------------------------------------
# Steady state after the start (Figure 3.6: "similar for all modeling levels")
# --------------------------------------------------------------------------------------------------

STEADY_TOL = 0.005  # issue: within 0.5 %


def test_steady_state_direct_on_line_all_levels(motor_fan_fmu):
    # reference: spec "Steady state by hand": the first speed from standstill where the level's motor
    # curve meets T_load = k (w/N)^2 / (N eta) (levels a, b: the table read linearly; c: by Akima; d: the
    # circuit, the dq model's steady state); the shaft torque is that torque. Every output point of the
    # last second must be within 0.5 % of it (so the run has settled), and the levels within 0.5 % of
    # each other (the chapter: "the results in steady state at constant speed are similar for all
    # modeling levels").
    problems, finals = [], {}
    for level, letter in LEVELS.items():
        p = params(motor_fan_fmu, level=level)
        w_eq, T_eq = ref.equilibrium(p)
        res = base(motor_fan_fmu, level, 1)
        w, T = last_second(res, "motor_speed"), last_second(res, "shaft_torque")
        finals[letter] = (float(w[-1]), float(T[-1]))
        print(f"  level {letter} ({p.curve}): hand w_m = {w_eq:.4f} rad/s, T = {T_eq:.3f} N.m; "
              f"w_m(30 s) = {w[-1]:.4f} rad/s ({w[-1] / w_eq - 1:+.3%}), T_shaft(30 s) = {T[-1]:.3f} N.m ({T[-1] / T_eq - 1:+.3%})")
        for name, sig, ref_value in (("motor_speed", w, w_eq), ("shaft_torque", T, T_eq)):
            err = float(np.max(np.abs(sig / ref_value - 1.0)))
            if err > STEADY_TOL:
                problems.append(f"level {letter}: {name} over the last second is up to {err:.3%} from {ref_value:.4f}")
    for i, name in enumerate(("motor speed", "shaft torque")):
        values = [v[i] for v in finals.values()]
        spread = (max(values) - min(values)) / abs(np.mean(values))
        print(f"  {name}: spread across the levels {spread:.3%}")
        if spread > STEADY_TOL:
            problems.append(f"{name} differs by {spread:.3%} across levels: {finals}")
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("start_mode", [2, 3], ids=["PI", "inverse"])
def test_steady_state_controlled_all_levels(motor_fan_fmu, start_mode):
    # reference: the controlled drive settles at the set point (PI with integral action; inverse
    # simulation imposes it), where the shaft carries the fan's torque T_set = k (w_set/N)^2 / (N eta).
    # Motor speed: every output point of the last second within 0.5 % of w_set. Shaft torque: at levels
    # a and b (no shaft mode) every point within 0.5 % of T_set. At levels c and d the book's shaft
    # (D_shaft = 0.38 N m s/rad) leaves the 1.33 Hz mode almost undamped: with the motor speed held,
    # its ringing decays at sigma = (D + c_l) / (2 J_eq_forward) = 0.144 /s (the fan's load slope c_l
    # does most of it; test_shaft_ringing_decays_at_the_linear_rate), so what the set point's end leaves
    # (35 N.m) is still ~3.5 N.m (0.7 %) at 30 s. There the last second's swing must be centred on
    # T_set within 0.5 %, and its half-height no more than that linear decay leaves of the swing in the
    # second after the set point has settled: A_end <= 1.2 A_settled exp(-sigma (t_end - t_settled))
    # (1.2: each window's largest deviation is up to a half period, e^(0.054), from its start, and the
    # PI's finite stiffness only adds damping).
    problems = []
    for level, letter in LEVELS.items():
        p = params(motor_fan_fmu, level=level)
        w_set = p.speed_setpoint
        T_set = float(ref.load_torque(p, w_set))
        res = base(motor_fan_fmu, level, start_mode)
        w = last_second(res, "motor_speed")
        err = float(np.max(np.abs(w / w_set - 1.0)))
        if err > STEADY_TOL:
            problems.append(f"level {letter}: motor_speed over the last second is up to {err:.3%} from {w_set}")
        T = last_second(res, "shaft_torque")
        if level <= 2:
            err = float(np.max(np.abs(T / T_set - 1.0)))
            print(f"  level {letter}: T_shaft over the last second within {err:.2e} of {T_set:.3f} N.m")
            if err > STEADY_TOL:
                problems.append(f"level {letter}: shaft_torque over the last second is up to {err:.3%} from {T_set:.4f}")
            continue
        t = res["time"]
        t_s = setpoint_settled(p, t)
        first = np.asarray(res["shaft_torque"])[(t >= t_s) & (t <= t_s + 1.0)]
        a_settled = float(np.max(np.abs(first - T_set)))
        a_end = float(np.max(np.abs(T - T_set)))
        centre = 0.5 * (float(T.max()) + float(T.min()))
        sigma = ref.motor_imposed_decay_rate(p, w_set)
        bound = 1.2 * a_settled * math.exp(-sigma * (t[-1] - 1.0 - t_s))
        print(f"  level {letter}: T_shaft over the last second {T.min():.3f}..{T.max():.3f} N.m, centre {centre:.3f} "
              f"({centre / T_set - 1:+.3%} from {T_set:.3f}); swing {a_end:.3f} N.m, {a_settled:.2f} N.m after the set point "
              f"settled at {t_s:.3f} s, linear decay at {sigma:.4f} /s leaves <= {bound:.3f} N.m")
        if abs(centre / T_set - 1.0) > STEADY_TOL:
            problems.append(f"level {letter}: shaft torque centred on {centre:.4f}, {centre / T_set - 1:+.3%} from {T_set:.4f}")
        if a_end > bound:
            problems.append(f"level {letter}: shaft torque still swings by {a_end:.3f} N.m at 30 s, more than the "
                            f"{bound:.3f} N.m the shaft mode's linear decay leaves of {a_settled:.3f} N.m at {t_s:.3f} s")
    assert not problems, f"{START_MODES[start_mode]}:\n" + "\n".join(problems)


def test_load_parameter_moves_the_equilibrium(motor_fan_fmu):
    # reference: same hand equilibrium with T_fan_nominal set to 1.2x its default at run time (no
    # rebuild): a heavier fan load gives a lower speed and a higher torque, exactly as the motor curve
    # says. Level a (quasi-static, the algebraic model, linear table) and level c (after 30 s of
    # dynamics, Akima table). The load law is T_fan_nominal (w_fan / speed_fan_nominal)^2: lowering
    # speed_fan_nominal by sqrt(1.2) instead is the same load (level a).
    p0 = params(motor_fan_fmu)
    T_nom = 1.2 * p0.T_fan_nominal
    w_nom = p0.speed_fan_nominal / math.sqrt(1.2)
    results = {}
    for level, overrides in ((1, {"T_fan_nominal": T_nom}), (3, {"T_fan_nominal": T_nom}), (1, {"speed_fan_nominal": w_nom})):
        p = params(motor_fan_fmu, level=level)
        w0, T0 = ref.equilibrium(p)
        w1, T1 = ref.equilibrium(params(motor_fan_fmu, level=level, **overrides))
        assert w1 < w0 and T1 > T0
        res = run(motor_fan_fmu, level=level, start_mode=1, **overrides)
        w, T = float(res["motor_speed"][-1]), float(res["shaft_torque"][-1])
        results[(level, tuple(overrides))] = (w, T)
        print(f"level {LEVELS[level]}, {overrides}: w = {w:.4f} (hand {w1:.4f}; default load {w0:.4f}), "
              f"T = {T:.2f} (hand {T1:.2f}; default load {T0:.2f})")
        assert w == pytest.approx(w1, rel=STEADY_TOL)
        assert T == pytest.approx(T1, rel=STEADY_TOL)
    a_T, a_w = results[(1, ("T_fan_nominal",))], results[(1, ("speed_fan_nominal",))]
    assert a_w == pytest.approx(a_T, rel=1e-9), f"T_fan_nominal x 1.2 gives {a_T}, speed_fan_nominal / sqrt(1.2) gives {a_w}"


def test_imposed_speed_without_elasticity_is_quasi_static(motor_fan_fmu):
    # reference: without the shaft's elasticity the torques follow from the imposed motion alone. Level
    # a (no inertia), PI and inverse: w_m = w_ref and T_shaft = T_load(w_ref). Level b, inverse
    # simulation (w_m = w_ref imposed, rigid shaft, power towards the fan throughout):
    # T_shaft = T_load(w_ref) + J_eq_forward dw_ref/dt and T_m = T_shaft + J_motor dw_ref/dt. The set
    # point w_ref(t) and its rate by hand (the ramp through the filter, scipy.signal.lsim). At every
    # output point within 1e-8 of the peak.
    problems = []
    for level, start_mode in ((1, 2), (1, 3), (2, 3)):
        p = params(motor_fan_fmu, level=level)
        res = base(motor_fan_fmu, level, start_mode)
        w_ref, a_ref = ref.setpoint(p, res["time"])
        T_shaft = ref.load_torque(p, w_ref) + (p.J_eq_forward * a_ref if level == 2 else 0.0)
        T_m = T_shaft + (p.J_motor * a_ref if level == 2 else 0.0)
        for name, want in (("speed_reference", w_ref), ("motor_speed", w_ref), ("shaft_torque", T_shaft), ("motor_torque", T_m)):
            err = float(np.max(np.abs(np.asarray(res[name]) - want)) / np.max(np.abs(want)))
            print(f"level {LEVELS[level]}, {START_MODES[start_mode]}: {name} peak {np.max(np.abs(res[name])):.4f} "
                  f"(hand {np.max(np.abs(want)):.4f}), largest difference {err:.1e} of it")
            if err > 1e-8:
                problems.append(f"level {LEVELS[level]}, {START_MODES[start_mode]}: {name} up to {err:.2e} of its peak from the hand value")
    assert not problems, "\n".join(problems)


# --------------------------------------------------------------------------------------------------
# Direct-on-line start: peak torque by modeling level (Figure 3.6)
# --------------------------------------------------------------------------------------------------

def _dol_peaks(fmu, **overrides) -> dict[str, float]:
    return {letter: peak_abs(run(fmu, level=level, start_mode=1, **overrides)) for level, letter in LEVELS.items() if level >= 2}


def test_direct_on_line_peak_torque_grows_with_level(motor_fan_fmu):
    # reference: chapter 3.3.1, Figure 3.6: inertias add a starting torque surge (b above the steady
    # torque), the driveshaft elasticity an even stronger transient torque (c above b).
    # Peak = max |T_shaft| over the 30 s run (the reducer must carry either sign).
    _, T_eq = ref.equilibrium(params(motor_fan_fmu, level=2))
    peaks = _dol_peaks(motor_fan_fmu)
    print("direct-on-line peak |T_shaft| (N.m): " + ", ".join(f"{k}: {v:.1f}" for k, v in peaks.items())
          + f"; steady (level b) {T_eq:.1f}; c/b = {peaks['c'] / peaks['b']:.3f}, b/steady = {peaks['b'] / T_eq:.3f}")
    assert peaks["b"] > T_eq, f"level b peak {peaks['b']:.1f} N.m does not exceed the steady torque {T_eq:.1f} N.m"
    assert peaks["c"] > peaks["b"], f"level c peak {peaks['c']:.1f} N.m does not exceed level b's {peaks['b']:.1f} N.m"


@pytest.mark.parametrize("parameter_set", [
    "book",
    pytest.param("first-set", marks=pytest.mark.xfail(
        strict=True,
        reason="with the first set (FIRST_SET: the chosen 160 kW 4-pole motor by its circuit at every level) the physics "
        "disagrees with the chapter: direct-on-line peak shaft torque level c 4167 N.m, level d 2633 N.m (-37 %), level b "
        "2644 N.m. That circuit's torque-speed curve rises steeply below breakdown (negative damping) and level c's 3.9 Hz "
        "shaft mode grows during the run-up; in level d's dq model the torque lags speed changes through the rotor transient "
        "time constant and the mode does not grow. Strict: if it ever holds, this XPASS fails and the spec and README must "
        "be updated.",
    )),
])
def test_level_d_adds_nothing_to_the_peak_torque(motor_fan_fmu, parameter_set):
    # reference: chapter 3.3.1: "The last level d) ... provides no additional information for this
    # maximal torque" -- taken as: level d's peak |T_shaft| within 20 % of level c's (the issue).
    # With the book's values (level c the Akima table, level d the book's induction machine, whose
    # steady state is within 9 N m of the table at its points) it holds: level c 4503 N.m at 5.38 s,
    # level d 3876 N.m at 5.66 s (-13.9 %), level b 982 N.m. The first set keeps its earlier
    # disagreement (strict xfail).
    overrides = FIRST_SET if parameter_set == "first-set" else {}
    peaks = _dol_peaks(motor_fan_fmu, **overrides)
    when = {}
    for level in (3, 4):
        res = run(motor_fan_fmu, level=level, start_mode=1, **overrides)
        when[LEVELS[level]] = float(res["time"][int(np.argmax(np.abs(res["shaft_torque"])))])
    ratio = peaks["d"] / peaks["c"]
    print(f"{parameter_set}: direct-on-line peak |T_shaft|: level b {peaks['b']:.1f}, level c {peaks['c']:.1f} "
          f"(at {when['c']:.3f} s), level d {peaks['d']:.1f} N.m (at {when['d']:.3f} s), d/c = {ratio:.3f}")
    assert abs(ratio - 1.0) <= 0.20, (
        f"{parameter_set}: level d's peak shaft torque {peaks['d']:.1f} N.m is {ratio - 1:+.1%} from level c's {peaks['c']:.1f} N.m "
        f"(chapter: d adds nothing for this maximum; issue: within 20 %)"
    )


def test_first_set_settles_at_its_circuit_equilibrium(motor_fan_fmu):
    # reference: the first set (FIRST_SET, through parameters) is still the earlier model: at levels c
    # (motor_model 2: the circuit's steady state) and d (its dq model) the direct-on-line start settles
    # at the circuit's hand equilibrium (153.51 rad/s, 1042.2 N.m then), within 0.5 % at every point of
    # the last second. The runs are those of the first set's case above.
    problems = []
    for level in (3, 4):
        p = params(motor_fan_fmu, level=level, **FIRST_SET)
        assert p.curve == "circuit"
        w_eq, T_eq = ref.equilibrium(p)
        res = run(motor_fan_fmu, level=level, start_mode=1, **FIRST_SET)
        print(f"first set, level {LEVELS[level]}: w(30 s) = {res['motor_speed'][-1]:.4f} rad/s (hand {w_eq:.4f}), "
              f"T(30 s) = {res['shaft_torque'][-1]:.3f} N.m (hand {T_eq:.3f})")
        for name, want in (("motor_speed", w_eq), ("shaft_torque", T_eq)):
            err = float(np.max(np.abs(last_second(res, name) / want - 1.0)))
            if err > STEADY_TOL:
                problems.append(f"first set, level {LEVELS[level]}: {name} up to {err:.3%} from {want:.4f}")
    assert not problems, "\n".join(problems)


# --------------------------------------------------------------------------------------------------
# Driveshaft mode: frequencies and decay from the linear two-inertia theory
# --------------------------------------------------------------------------------------------------
# Which J_eq: while power flows from the motor to the fan (T_shaft > 0, w_m > 0: the whole run-up and
# the ramps here), the spec's reducer transmits T_ls = N eta T_shaft, so the fan equation referred to
# the high-speed axis reads T_shaft = J_fan/(N^2 eta) dw_m/dt + ...: the shaft's spring works against
# J_eq_forward = J_fan/(N^2 eta) = 12.47 kg.m2, not J_fan/N^2 = 11.72 kg.m2 (eq. 3.6 ignores the
# efficiency). The theory below uses J_eq_forward; the efficiency-free figures (eq. 3.8: 1.368 Hz, the
# chapter's "1.4 Hz"; free mode 3.824 Hz) are printed beside it: 3.1 % and 0.4 % above it. The damping
# (D_shaft, the fan's load slope, the motor curve's slope during the run-up) lowers the frequency by
# 1 - sqrt(1 - zeta^2): < 0.1 % after the ramp (zeta < 0.02), <= 1.1 % in the run-up window (|zeta| <= 0.15).

FREQ_TOL = 0.05  # issue: within 5 %


def test_direct_on_line_runup_rings_at_two_inertia_frequency(motor_fan_fmu):
    # reference: free motor inertia, f = sqrt(K (1/J_m + 1/J_eq_forward)) / (2 pi) = 3.81 Hz.
    # Measured on level c's direct-on-line run-up: T_shaft minus its moving average over one theoretical
    # period, zero crossings, from t = 0 until the motor's mean speed (the same moving average of w_m:
    # the point the oscillation is linearised about; w_m itself swings by tens of rad/s) first reaches
    # the speed above which the motor curve's slope would make the linearised mode's |damping ratio|
    # exceed 0.15 (ref.runup_linear_limit, hand computation). For the book's Akima table the rising part
    # (slope up to 3.7 N m s/rad: negative damping, |zeta| <= 0.034 with D_shaft 0.38) stays below it up
    # to the table's maximum (251.6 rad/s), beyond which the falling curve damps the mode (zeta 0.31 at
    # 300 rad/s).
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


def _inverse_ringing(fmu, **overrides) -> tuple[float, int, float, float]:
    """Frequency of the shaft-torque ringing after the set point has settled under inverse simulation
    at level c: the motor speed is imposed and constant from then on (setpoint_settled, by hand: the
    filter's tail after the ramp), so T_shaft rings about its final (constant) value; window 8 s from
    there. Returns (f, crossings, first amplitude, window start)."""
    p = params(fmu, **overrides)
    res = run(fmu, level=3, start_mode=3, **overrides)
    t, T = res["time"], np.asarray(res["shaft_torque"])
    t_s = setpoint_settled(p, t)
    window = (t >= t_s) & (t <= t_s + 8.0)
    assert t_s + 8.0 < STOP_TIME - 1.0
    d = T[window] - float(np.mean(last_second(res, "shaft_torque")))
    f, n = ringing_frequency(t[window], d)
    return f, n, float(np.max(np.abs(d))), t_s


def test_inverse_simulation_rings_at_motor_imposed_frequency(motor_fan_fmu):
    # reference: eq. 3.8, motor inertia neutralised: f = sqrt(K / J_eq_forward) / (2 pi) = 1.326 Hz
    # (the reducer's efficiency counted, see above); and the chapter's eq. 3.8 as it writes it, with
    # J_eq = 11.72 kg m2 (1.368 Hz: its "1.4 Hz"), must predict the ringing within 5 % too.
    p = params(motor_fan_fmu)
    f_theory = ref.frequency_motor_imposed(p)
    f_chapter = ref.frequency_motor_imposed(p, p.J_eq)
    f, n, amp, t_s = _inverse_ringing(motor_fan_fmu)
    print(f"inverse simulation ringing after the set point settled (level c, from {t_s:.3f} s): {f:.4f} Hz from {n} zero "
          f"crossings (first amplitude {amp:.1f} N.m); theory {f_theory:.4f} Hz with J_fan/(N^2 eta) ({f / f_theory - 1:+.2%}), "
          f"{f_chapter:.4f} Hz with J_fan/N^2 (eq. 3.8, {f / f_chapter - 1:+.2%}); the chapter's 1.4 Hz {f / 1.4 - 1:+.2%}")
    assert f == pytest.approx(f_theory, rel=FREQ_TOL)
    assert f == pytest.approx(f_chapter, rel=FREQ_TOL), f"eq. 3.8 with J_eq: {f_chapter:.4f} Hz, measured {f:.4f} Hz"


def test_shaft_ringing_decays_at_the_linear_rate(motor_fan_fmu):
    # reference: with the motor speed imposed (inverse simulation, level c, after the set point has
    # settled at w_set) the linearised fan side J_eq_forward u'' + (D_shaft + c_l) u' + K u = 0, c_l =
    # 2 k w_set / (N^3 eta), decays as exp(-sigma t), sigma = (D_shaft + c_l) / (2 J_eq_forward) =
    # 0.144 /s with the book's values (c_l = 3.21 N m s/rad does 89 % of it). Measured: the peak
    # |T_shaft - T_set| of each half period from the set point's settling to 30 s, a least-squares line
    # through their logarithms; within 5 %.
    p = params(motor_fan_fmu)
    w_set = p.speed_setpoint
    T_set = float(ref.load_torque(p, w_set))
    sigma = ref.motor_imposed_decay_rate(p, w_set)
    res = base(motor_fan_fmu, 3, 3)
    t, T = res["time"], np.asarray(res["shaft_torque"])
    t_s = setpoint_settled(p, t)
    late = t >= t_s
    d = T[late] - T_set
    c = zero_crossings(t[late], d)
    assert len(c) >= 10, f"only {len(c)} zero crossings of T_shaft - T_set after {t_s:.3f} s"
    tl = t[late]
    peaks = np.array([np.max(np.abs(d[(tl >= a) & (tl <= b)])) for a, b in zip(c[:-1], c[1:])])
    mid = 0.5 * (c[:-1] + c[1:])
    rate = -float(np.polyfit(mid, np.log(peaks), 1)[0])
    print(f"shaft ringing under inverse simulation (level c, {t_s:.3f}..30 s, {len(peaks)} half periods, "
          f"{peaks[0]:.2f} -> {peaks[-1]:.2f} N.m): decay {rate:.5f} /s, hand {sigma:.5f} /s "
          f"(D_shaft {p.D_shaft:.4f}, c_l {ref.load_slope(p, w_set):.4f} N.m.s/rad); error {rate / sigma - 1:+.2%}")
    assert rate == pytest.approx(sigma, rel=FREQ_TOL)


def _measured_J_eq(fmu, **overrides) -> float:
    """Inertia seen by the shaft, from the inverse-simulation ramp at level c: with the motor speed
    imposed on the filtered ramp, whose acceleration (by hand) is a = speed_setpoint / ramp_time to
    within 0.1 % from ~2.9 s on, the shaft carries the fan's torque plus J a:
    J = mean(T_shaft - k w_fan^2 / (N eta)) / a over that part of the ramp, up to 0.5 s before its end
    (the ringing about that mean averages out to ~1-2 %)."""
    p = params(fmu, **overrides)
    res = run(fmu, level=3, start_mode=3, **overrides)
    t = res["time"]
    a = p.speed_setpoint / p.ramp_time
    _, a_ref = ref.setpoint(p, t)
    steady = np.abs(a_ref / a - 1.0) <= 1e-3
    window = steady & (t <= p.ramp_time - 0.5) & (t >= t[np.argmax(steady)])
    assert np.count_nonzero(window) > 4000, "the filtered ramp's acceleration is never steady for 4 s"
    load = p.k_fan * np.asarray(res["fan_speed"]) ** 2 / (p.gear_ratio * p.gear_efficiency)
    return float(np.mean((np.asarray(res["shaft_torque"]) - load)[window]) / a)


def test_fan_inertia_parameter_changes_the_physics(motor_fan_fmu):
    # reference: eqs. 3.6 and 3.8, applied to J_fan set to twice its default at run time (no rebuild):
    # J_eq doubles (measured from the ramp torque), so the inverse-simulation ringing frequency drops by
    # sqrt(2). Both J_eq figures are checked against J_fan/(N^2 eta).
    p = params(motor_fan_fmu)
    J_fan2 = 2.0 * p.J_fan
    p2 = params(motor_fan_fmu, J_fan=J_fan2)
    J1, J2 = _measured_J_eq(motor_fan_fmu), _measured_J_eq(motor_fan_fmu, J_fan=J_fan2)
    f1, _, _, _ = _inverse_ringing(motor_fan_fmu)
    f2, n2, _, _ = _inverse_ringing(motor_fan_fmu, J_fan=J_fan2)
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
    # Hand figure: a start that follows the set point exactly carries the quasi-static torque
    # T_load(w_ref) + J_eq_forward dw_ref/dt (steady torque plus the fan's acceleration torque; any
    # ringing comes on top); with the book's filtered ramp its largest value is reached just after the
    # ramp's end. The factor 3 needs a direct-on-line peak of about 3x that figure; the message says how
    # far off it is.
    p = params(motor_fan_fmu)
    dol = peak_abs(base(motor_fan_fmu, 3, 1))
    ctrl = peak_abs(base(motor_fan_fmu, 3, start_mode))
    t = base(motor_fan_fmu, 3, start_mode)["time"]
    w_ref, a_ref = ref.setpoint(p, t)
    quasi = ref.load_torque(p, w_ref) + p.J_eq_forward * a_ref
    k = int(np.argmax(quasi))
    quasi_static = float(quasi[k])
    print(f"level c peak |T_shaft|: direct-on-line {dol:.1f} N.m, {START_MODES[start_mode]} {ctrl:.1f} N.m, "
          f"ratio {dol / ctrl:.3f}; quasi-static torque of the set point at most {quasi_static:.1f} N.m (at {t[k]:.3f} s; "
          f"direct-on-line peak / it = {dol / quasi_static:.3f})")
    assert dol >= 3.0 * ctrl, (
        f"direct-on-line peak {dol:.1f} N.m is only {dol / ctrl:.2f}x the {START_MODES[start_mode]} peak {ctrl:.1f} N.m "
        f"(issue: >= 3x); a start following the {p.ramp_time:g} s set point carries up to ~{quasi_static:.1f} N.m "
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
    # share_i = 100 activity_i / sum over the storage elements (0 while the sum is 0), so the storage
    # elements' shares sum to 100 % when the sum > 0.
    # Level b has a rigid shaft (theta stays 0): no stiffness activity.
    # "Never decreases" holds up to the integration error of the activity, which follows the run's
    # tolerance (fmu_rtol, the DefaultExperiment's): near the steady state |power| is a small difference
    # of large torques, so the speeds' error allowance (rtol of 300 rad/s) times the torque slope enters
    # the integral, and the solver's steps reach tens of ms; allowed: 10 rtol of the activity between
    # 1 ms samples.
    res = base(motor_fan_fmu, level, start_mode)
    A = np.column_stack([np.asarray(res[n]) for n in STORAGE_ACTIVITIES])
    S = np.column_stack([np.asarray(res[n]) for n in STORAGE_SHARES])
    total = A.sum(axis=1)
    assert np.all(A >= 0.0), "negative activity"
    assert np.all(np.diff(A, axis=0) >= -10 * fmu_rtol(motor_fan_fmu) * np.maximum(A[1:], 1.0)), "an activity decreases"
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
    print(f"level {LEVELS[level]}, {START_MODES[start_mode]}: shares at 30 s (motor inertia, shaft stiffness, fan inertia, "
          "winding inductance) = " + ", ".join(f"{s:.2f} %" for s in S[-1]))


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
    # Inverse simulation is the controller's ideal stand-in: it imposes the set point itself. With the
    # first set's unfiltered ramp it imposed the ramp's corners (acceleration steps at t = 0 and
    # t = ramp_time, each setting the lightly damped shaft mode ringing), and the share fell only 9.3x
    # (15.0 % -> 1.6 %), so this test asked for 5x. The book's set point goes through its 0.5 Hz
    # filter (the default now), which rounds the corners: the inverse simulation is held to the same
    # 10x as the PI (measured 9.01 % -> 0.34 %, 26.7x). And the stiffness activity is at least the
    # energy finally stored in the twisted shaft, K theta^2 / 2 (activity integrates |power| >= its net sum).
    dol, ctrl = _stiffness_shares(motor_fan_fmu, 3)
    assert dol >= 10.0 * ctrl, f"direct-on-line {dol:.3f} %, inverse simulation {ctrl:.3f} % (ratio {dol / ctrl:.2f}, >= 10)"
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
# The set point is a step (ramp_time = 0) through the filter, under the book's PI: no torque limit
# (T_limit 0), so the unfiltered step asks Kp w_set = 3e6 N.m at once and the rigid model's shaft
# torque follows (about 2e6 N.m) where the elastic shaft decouples the fan (about 3e4 N.m): the
# elasticity matters most there, as the comparison says.

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
    names = {0: "unfiltered step", 1: f"filter {p_md['filter_frequency_below']:.4f} Hz",
             2: f"filter {p_md['filter_frequency_above']:.4f} Hz"}
    for f, (diff, pk, pk_rigid) in figures.items():
        print(f"PI, level c, {names[f]:>16}: elasticity torque {diff:10.1f} N.m, peak |T_shaft| {pk:10.1f} N.m "
              f"(rigid shaft {pk_rigid:10.1f} N.m)")
    below, step, above = figures[1][0], figures[0][0], figures[2][0]
    assert below < step, f"filtered below 1.4 Hz: {below:.1f} N.m, not below the unfiltered step's {step:.1f} N.m"
    assert below < above, f"filtered below 1.4 Hz: {below:.1f} N.m, not below the filter above 1.4 Hz: {above:.1f} N.m"
