"""Model Exchange against Co-Simulation: the same equations, integrated by two different solvers.

Every dist/*.fmu offers both interfaces from one binary. Each FMU is simulated with fmpy
  * as ModelExchange, fmpy's CVode (BDF) at relative_tolerance=1e-8 (the reference), and
  * as CoSimulation, the FMU's own solver at its default tolerance (no relative_tolerance passed),
over its DefaultExperiment (stop time; output_interval = its stepSize, which is also the CS
communication step), and every Real output (causality="output") must agree at every output point:

    |y_ME(t) - y_CS(t)| <= REL_TOL * max(max(y_CS) - min(y_CS), ABS_FLOOR)   for every t

A second test runs every FMU in ME (CVode) and CS at the same tolerance, 1e-4, 1e-6 and 1e-8, with a
bound that scales with the tolerance (see "ME and CS at the same tolerance" below). fmpy's ME loop
re-initializes CVode after every event, so an FMU that leaves an event indicator at zero after an
event passes here; tests/tests/model_exchange_strict.rs runs a strict master that does not.

MotorFan is also run in configurations its default experiment does not reach (level d
direct-on-line, level c with the PI start and with inverse simulation, level a), over 0-15 s.

fmpy quirks handled here (TOOLS.md and fmpy's simulateME):
  * ME records at events too unless record_events=False; with it, both runs have one row per
    output point start + k * output_interval, which the test asserts before comparing.
  * For CS, output_interval is the communication step.

Each test puts its table (worst error per output, and the time where it occurs) into its assertion
message; all tables and the wall-clock time of every simulation are printed at the end of the
module by the terminal reporter, with or without `pytest -s`.
"""

from __future__ import annotations

import time

import numpy as np
import pytest
from fmpy import simulate_fmu

from conftest import print_past_capture, DIST_DIR, fmu_key as _fmu_key, model_description as _model_description, require_fmu, unzipdir as _unzipdir

REL_TOL = 1e-4  # of each output's range over the CS run
ABS_FLOOR = 1e-12  # the "range" of an output that is constant
ME_RELATIVE_TOLERANCE = 1e-8  # CVode, for the reference run

MOTOR_FAN_STOP_TIME = 15.0
MOTOR_FAN_CONFIGURATIONS = {
    # id: start values (all other parameters at their defaults)
    "level_d_direct_on_line": {"level": 4, "start_mode": 1},
    "level_c_PI": {"level": 3, "start_mode": 2},
    "level_c_inverse_simulation": {"level": 3, "start_mode": 3},
    "level_a": {"level": 1},  # direct-on-line at level a is quasi-static: every output is constant
    "level_a_PI": {"level": 1, "start_mode": 2},
}

# Tables and timings of every comparison in this module, printed at its end.
REPORT: list[str] = []


@pytest.fixture(scope="module", autouse=True)
def _print_report(request):
    """Prints every table at the end of the module, past pytest's output capture (so with or
    without `-s`)."""
    yield
    print_past_capture(request, "== Model Exchange (CVode) vs Co-Simulation: worst errors", REPORT)


def real_outputs(md) -> list[str]:
    """The Real outputs two runs are compared on: not the energy balance (power_balance_*), zero up
    to rounding by construction (test_energy_balance.py bounds it against the largest element power)."""
    return [v.name for v in md.modelVariables if v.causality == "output" and v.type == "Real"
            and not v.name.startswith("power_balance_")]


def start_time(md) -> float:
    de = md.defaultExperiment
    return float(de.startTime) if de is not None and de.startTime is not None else 0.0


def simulate(fmu, fmi_type: str, stop_time: float, output_interval: float, start_values: dict,
             me_tolerance: float = ME_RELATIVE_TOLERANCE, cs_tolerance: float | None = None,
             calls: dict | None = None):
    """(fmpy result, wall-clock seconds) of one run: ME with CVode at me_tolerance, CS at
    cs_tolerance (None: the FMU's default). `calls`: counts each fmi2 function called (ME)."""
    key = _fmu_key(fmu)
    md = _model_description(key)
    if fmi_type == "ModelExchange":
        extra = {"solver": "CVode", "relative_tolerance": me_tolerance, "record_events": False}
        if calls is not None:
            def count(message, calls=calls):
                name = message.split("(", 1)[0].strip()
                calls[name] = calls.get(name, 0) + 1
            extra["fmi_call_logger"] = count
    else:
        extra = {} if cs_tolerance is None else {"relative_tolerance": cs_tolerance}
    t0 = time.perf_counter()
    res = simulate_fmu(
        _unzipdir(key),
        validate=False,  # test_validate.py validates every dist/*.fmu
        model_description=md,
        fmi_type=fmi_type,
        start_time=start_time(md),
        stop_time=stop_time,
        output_interval=output_interval,
        start_values=dict(start_values),
        output=real_outputs(md),
        **extra,
    )
    return res, time.perf_counter() - t0


def compare(fmu, label: str, stop_time: float, output_interval: float, start_values: dict,
            tolerance: float | None = None, rel_tol: float = REL_TOL, activity_rel_tol=None):
    """Simulates ME and CS, returns (table text, list of failures). tolerance None: ME at
    ME_RELATIVE_TOLERANCE, CS at its default; else both at `tolerance`. An output fails where
    |ME - CS| > rel_tol x its range; an activity output (description says "activity") where it
    exceeds activity_rel_tol(ME calls) x its range, if given."""
    md = _model_description(_fmu_key(fmu))
    assert md.coSimulation is not None, f"{fmu.name} has no <CoSimulation> element"
    assert md.modelExchange is not None, (
        f"{fmu.name} has no <ModelExchange> element: every FMU must offer Model Exchange"
    )
    assert md.modelExchange.modelIdentifier == md.coSimulation.modelIdentifier, (
        "one binary serves both interfaces: the modelIdentifiers must be equal"
    )
    names = real_outputs(md)
    assert names, f"{fmu.name} has no Real output"

    me_tol = ME_RELATIVE_TOLERANCE if tolerance is None else tolerance
    cs, cs_seconds = simulate(fmu, "CoSimulation", stop_time, output_interval, start_values, cs_tolerance=tolerance)
    calls: dict = {}
    me, me_seconds = simulate(fmu, "ModelExchange", stop_time, output_interval, start_values, me_tolerance=me_tol,
                              calls=calls if activity_rel_tol is not None else None)
    descriptions = {v.name: (v.description or "") for v in md.modelVariables}

    start = start_time(md)
    n_expected = int(round((stop_time - start) / output_interval)) + 1
    t_cs, t_me = np.asarray(cs["time"]), np.asarray(me["time"])
    assert len(t_cs) == n_expected, f"CS run has {len(t_cs)} rows, expected {n_expected}"
    assert len(t_me) == len(t_cs), f"ME run has {len(t_me)} rows, CS run {len(t_cs)}: different time grids"
    grid = start + output_interval * np.arange(n_expected)
    assert np.allclose(t_cs, grid, rtol=0, atol=1e-9 * output_interval), "CS rows are not on the output grid"
    assert np.allclose(t_me, t_cs, rtol=0, atol=1e-9 * output_interval), (
        f"ME and CS time grids differ (max |dt| = {np.max(np.abs(t_me - t_cs)):.3g} s)"
    )

    tol_text = "ME rtol 1e-8, CS default" if tolerance is None else f"ME and CS rtol {tolerance:g}"
    header = (
        f"{fmu.stem} [{label}; {tol_text}]: 0..{stop_time:g} s, {len(t_cs)} points every {output_interval:g} s; "
        f"CS {cs_seconds:.2f} s, ME {me_seconds:.2f} s"
    )
    rows = [header, f"  {'output':<28} {'range (CS)':>12} {'max |ME-CS|':>12} {'rel. error':>10} {'at t':>9}"]
    failures = []
    units = {v.name: v.unit for v in md.modelVariables}

    def limit_of(name):
        if activity_rel_tol is not None and "activity" in descriptions.get(name, "").lower():
            return max(rel_tol, activity_rel_tol(calls))
        return rel_tol

    def span_of(name):
        y = np.asarray(cs[name], dtype=float)
        return float(np.max(y) - np.min(y))

    def derived_bound(name):
        """The per-point bound an output inherits from the outputs it is computed from, or None
        (tests/tests/model_exchange_strict.rs, derived_bounds): a share of the total activity,
        s_i = 100 A_i / sum A, is off by up to 200 sum bound(A) / sum A(t), unbounded while the
        activities are near zero at the start; an algebraic function y = f(x) of another output
        (FUNCTIONS_OF_AN_OUTPUT) by up to |f'(x)| bound(x), f' the CS run's slope."""
        description = descriptions.get(name, "").lower()
        if units.get(name) == "%" and "share" in description and "activity" in description:
            activities = [n for n in names if units.get(n) == "J" and descriptions.get(n, "").startswith("Activity of")]
            if not activities:
                return None
            total_bound = sum(limit_of(a) * span_of(a) for a in activities)
            total = np.sum([np.asarray(cs[a], dtype=float) for a in activities], axis=0)
            with np.errstate(divide="ignore"):
                return np.where(total > 0.0, 200.0 * total_bound / np.where(total > 0.0, total, 1.0), np.inf)
        of = FUNCTIONS_OF_AN_OUTPUT.get((fmu.stem, name))
        if of is None:
            return None
        x, y = np.asarray(cs[of], dtype=float), np.asarray(cs[name], dtype=float)
        dx, dy = np.gradient(x), np.gradient(y)
        moving = np.abs(dx) > 1e-9 * span_of(of)
        slope = np.where(moving, np.abs(dy) / np.where(moving, np.abs(dx), 1.0), 0.0)
        return slope * limit_of(of) * span_of(of)

    for name in names:
        y_cs = np.asarray(cs[name], dtype=float)
        y_me = np.asarray(me[name], dtype=float)
        if not (np.all(np.isfinite(y_cs)) and np.all(np.isfinite(y_me))):
            failures.append(f"{name}: non-finite values (CS {np.sum(~np.isfinite(y_cs))}, ME {np.sum(~np.isfinite(y_me))})")
            rows.append(f"  {name:<28} non-finite values")
            continue
        span = float(np.max(y_cs) - np.min(y_cs))
        scale = max(span, ABS_FLOOR)
        diff = np.abs(y_me - y_cs)
        # Per point: the output's own bound, or the one it inherits where that is larger; the
        # worst point is the one nearest its bound. The limit is reported relative to the range.
        allowed = np.full(len(diff), limit_of(name) * scale)
        inherited = derived_bound(name)
        if inherited is not None:
            allowed = np.maximum(allowed, inherited)
        k = int(np.argmax(diff / allowed))
        rel = float(diff[k] / scale)
        limit = float(allowed[k] / scale)
        flag = "" if rel <= limit else "  <-- FAIL"
        rows.append(f"  {name:<28} {span:12.5g} {diff[k]:12.4g} {rel:10.2e} {t_cs[k]:9.4f} (limit {limit:.2e}){flag}")
        if rel > limit:
            failures.append(
                f"{name}: |ME - CS| = {diff[k]:.4g} at t = {t_cs[k]:.6g} s (ME {y_me[k]:.10g}, CS {y_cs[k]:.10g}), "
                f"{rel:.3g} of its range {span:.5g} > {limit:g}"
            )
    table = "\n".join(rows)
    REPORT.append(table)
    return table, failures


def test_model_exchange_matches_co_simulation_over_the_default_experiment(fmu_path):
    md = _model_description(_fmu_key(fmu_path))
    de = md.defaultExperiment
    assert de is not None and de.stopTime is not None and de.stepSize is not None, (
        f"{fmu_path.name}: the DefaultExperiment needs stopTime and stepSize"
    )
    table, failures = compare(fmu_path, "default experiment", float(de.stopTime), float(de.stepSize), {})
    assert not failures, "ME and CS disagree:\n" + "\n".join(failures) + "\n" + table


@pytest.mark.parametrize("config", list(MOTOR_FAN_CONFIGURATIONS), ids=list(MOTOR_FAN_CONFIGURATIONS))
def test_motor_fan_model_exchange_matches_co_simulation(config):
    fmu = require_fmu(DIST_DIR / "MotorFan.fmu")
    md = _model_description(_fmu_key(fmu))
    step = float(md.defaultExperiment.stepSize)
    start_values = MOTOR_FAN_CONFIGURATIONS[config]
    table, failures = compare(fmu, f"{config} {start_values}", MOTOR_FAN_STOP_TIME, step, start_values)
    assert not failures, "ME and CS disagree:\n" + "\n".join(failures) + "\n" + table


# ---- ME and CS at the same tolerance: 1e-4, 1e-6, 1e-8 ----------------------------------------
#
# Both runs get the same relative tolerance (CVode's, with fmpy's absolute tolerance rtol x the
# states' nominals; the FMU's own solver through fmi2SetupExperiment). Bound, per Real output:
#
#     max_t |y_ME(t) - y_CS(t)| <= K * rtol * range_CS(y)
#
# K = SWEEP_K = 1000 for an output of the dynamics: the argument of
# tests/tests/model_exchange_strict.rs (each solver's error forgotten over the slowest time
# constant, ~10-50 rtol of a state's range; x2 for two solvers; x10 for outputs that balance large
# terms). For an activity output (its description says "activity": an integral of |power| or a
# share of such integrals) K = max(SWEEP_K, 8 N): an integral does not contract, its global error
# is up to the sum of the local errors, N rtol |y|, as much again from the other solver, x2 for the
# kinks of |P| that no event marks (the native master's 4 N), and x2 more for CVode's BDF, whose
# error estimate comes from a polynomial through past steps that a kink has already spoiled. N:
# the number of fmi2GetDerivatives calls of the ME run (~ CVode's steps), counted through fmpy's
# call logger.
#
# Cost: the output grid is coarsened to at most SWEEP_POINTS points (a multiple of stepSize;
# events are located by CVode and the FMU regardless of the grid), so the sweep adds little to CI.

# Outputs computed from another output (the bound they inherit: `derived_bound` in `compare`):
# (model, output) -> the output it is an algebraic function of. MotorFan's motor torque at levels
# a-c is the torque-speed table at the motor speed (slope down to -21 N m per rad/s between 280
# and 300 rad/s: the speed's error, amplified 8.5 times against the torque's range), its current
# and power the circuit's at that speed.
FUNCTIONS_OF_AN_OUTPUT = {
    ("MotorFan", "motor_torque"): "motor_speed",
    ("MotorFan", "electrical_power"): "motor_speed",
    ("MotorFan", "stator_current_rms"): "motor_speed",
}

SWEEP_TOLERANCES = (1e-4, 1e-6, 1e-8)
SWEEP_K = 1000.0
SWEEP_POINTS = 2000


def sweep_interval(start: float, stop: float, step: float) -> float:
    """stepSize times the smallest divisor k of the number of steps that keeps the grid at
    <= SWEEP_POINTS intervals (so the grid still ends at the stop time)."""
    n = int(round((stop - start) / step))
    k = next(k for k in range(1, n + 1) if n % k == 0 and n // k <= SWEEP_POINTS)
    return step * k


# Known cases where the master's integrator, not the FMU, misses the bound (strict: each must keep
# failing, so a change that makes it pass is noticed), with what was measured.
MASTER_LIMITS = {
    # Both below crossed their bound when the models declared their elements (issue 21): the
    # activity states (MotorFan 3 -> 10 of its 22 states, ShaftLine 9 -> 10 of 14, at the
    # runtime's 1 mJ nominal) join CVode's WRMS error norm, where they count as states and add
    # next to nothing to the error, and so change its steps. Our Co-Simulation solver keeps
    # activities out of its norm (fmu-runtime/src/rk.rs); an ME master cannot be told to. In both,
    # the FMU's Co-Simulation agrees with an independent solution to far better than the bound.
    # Measured 2026-12-03.
    ("MotorFan", 1e-8): (
        "fmpy's CVode at rtol 1e-8 misses the independent solution (tests/python/motor_fan_book.py, DOP853 at rtol "
        "1e-10) by 0.0758 N m of shaft_torque at 5.46 s, 1.002e-5 of its 7538 N m range against the 1e-5 bound "
        "(9.96e-6 before the activity states); Co-Simulation at the same tolerance is within 3.4e-4 N m of it "
        "(4.4e-8 of the range, test_motor_fan_book.py checks it)"
    ),
    ("ShaftLine", 1e-6): (
        "fmpy's CVode at rtol 1e-6 misses the independent Radau solution (shaft_line_reference.py) by 20.6 N m of "
        "the held seal torque at 145.12 s, 25 s after the final stick (the phase of the shaft's ringing), 1.14e-3 "
        "of its 18 000 N m range against the 1e-3 bound (6.6e-4 before the activity states); Co-Simulation at the "
        "same tolerance is within 4.4e-6 N m of Radau there (test_shaft_line.py checks the held torque)"
    ),
    ("ShaftLine", 1e-8): (
        "fmpy's CVode at rtol 1e-8 places the seal's final stick (t = 120.206 s, book file's case) about 1e-5 s off: "
        "the propeller stops with a deceleration of ~0.06 rad/s2, so its 6e-7 rad/s speed error (3.4e-8 of the range) "
        "moves the stick by 1e-5 s and the phase of the 7.5 Hz ringing it excites; the held seal torque, that "
        "ringing (~250 N m out of a shaft torque range of 1.9e6 N m), then differs by 0.21 N m at 120.48 s, 1.15e-5 "
        "of the seal torque's own 18 000 N m range against the 1e-5 bound. Co-Simulation (floor 1e-11) agrees with "
        "the independent Radau solution to 3e-7 N m there (test_shaft_line.py checks the held torque)"
    ),
}


@pytest.mark.parametrize("tolerance", SWEEP_TOLERANCES, ids=[f"rtol{t:g}" for t in SWEEP_TOLERANCES])
def test_model_exchange_matches_co_simulation_at_the_same_tolerance(fmu_path, tolerance, request):
    reason = MASTER_LIMITS.get((fmu_path.stem, tolerance))
    if reason:
        request.applymarker(pytest.mark.xfail(strict=True, reason=reason))
    md = _model_description(_fmu_key(fmu_path))
    de = md.defaultExperiment
    assert de is not None and de.stopTime is not None and de.stepSize is not None
    stop = float(de.stopTime)
    interval = sweep_interval(start_time(md), stop, float(de.stepSize))
    table, failures = compare(
        fmu_path, f"default experiment, grid {interval:g} s", stop, interval, {},
        tolerance=tolerance, rel_tol=SWEEP_K * tolerance,
        activity_rel_tol=lambda calls: 8.0 * calls.get("fmi2GetDerivatives", 0) * tolerance,
    )
    assert not failures, "ME and CS disagree:\n" + "\n".join(failures) + "\n" + table


def test_derivatives_and_nominals_are_served_in_initialization_mode(fmu_path):
    # FMI 2.0.5, section 3.2.3's table: fmi2GetDerivatives may be called in Initialization Mode
    # (since 2.0.1), fmi2GetNominalsOfContinuousStates too (since 2.0.3); a strict master may
    # ask for them there. They are the equations at the start values: finite derivatives,
    # positive nominals, and the nominals are those read after initialization.
    from ctypes import c_double

    from fmpy.fmi2 import FMU2Model

    key = _fmu_key(fmu_path)
    md = _model_description(key)
    n = len(md.derivatives)
    m = FMU2Model(guid=md.guid, unzipDirectory=_unzipdir(key), modelIdentifier=md.modelExchange.modelIdentifier,
                  instanceName="init")
    m.instantiate()
    try:
        m.setupExperiment(startTime=0.0)
        m.enterInitializationMode()
        dx, nominals = (c_double * n)(), (c_double * n)()
        m.getDerivatives(dx, n)
        m.getNominalsOfContinuousStates(nominals, n)
        assert np.all(np.isfinite(np.array(dx))), fmu_path.stem
        assert np.all(np.array(nominals) > 0), fmu_path.stem
        m.exitInitializationMode()
        after = (c_double * n)()
        m.getNominalsOfContinuousStates(after, n)
        assert np.array_equal(np.array(nominals), np.array(after)), fmu_path.stem
        m.terminate()
    finally:
        m.freeInstance()
