"""Every FMU exists as FMI 2.0 (dist/<Model>.fmu) and FMI 3.0 (dist/fmi3/<Model>.fmu), made by
build-fmus from the same model declaration and the same binary; the FMI 3.0 twin must be a valid
FMI 3.0 FMU and simulate exactly as the FMI 2.0 one.

References (independent of our code): fmpy's validate_fmu, which checks an FMI 3.0 description
against the standard's XML schema and its rules (one independent variable, unique value
references, legal causality/variability/initial, start values, units); fmpy's own FMI 3.0
Co-Simulation and Model Exchange loops (fmpy.fmi3 and CVode), against its FMI 2.0 loops on the
FMI 2.0 twin.

Equality: every output of the default experiment, at every output point, within 1e-12 of the
output's range over the FMI 2.0 run (the issue's bound; the two versions share every line of the
model and the solver, so the runs are expected to agree to the bit).
"""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.validation import validate_fmu

from conftest import DIST_DIR, fmu_key, model_description, require_fmu, unzipdir

FMI3_DIR = DIST_DIR / "fmi3"
REL_TOL = 1e-12  # of each output's range
ME_RELATIVE_TOLERANCE = 1e-8  # CVode, as in test_model_exchange.py


def twin(fmu_path: Path) -> Path:
    return require_fmu(FMI3_DIR / fmu_path.name)


def test_fmi3_twin_is_a_valid_fmi3_fmu(fmu_path):
    fmu3 = twin(fmu_path)
    problems = validate_fmu(str(fmu3))
    assert problems == [], f"fmpy validate {fmu3} found {len(problems)} problem(s):\n" + "\n".join(f"  - {p}" for p in problems)
    md2, md3 = read_model_description(str(fmu_path)), read_model_description(str(fmu3))
    assert md3.fmiVersion == "3.0"
    assert md3.coSimulation is not None and md3.modelExchange is not None
    identifier = md3.coSimulation.modelIdentifier
    assert identifier == md3.modelExchange.modelIdentifier == md2.coSimulation.modelIdentifier
    assert f"binaries/x86_64-linux/{identifier}.so" in zipfile.ZipFile(fmu3).namelist()
    # The model's own variables are the same, with the same value references, causalities and
    # units; FMI 3.0 adds the independent variable time and one Float64 per event indicator.
    fmi3_type = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean", "Enumeration": "Enumeration"}
    by_name = {v.name: v for v in md3.modelVariables}
    for v in md2.modelVariables:
        w = by_name.get(v.name)
        assert w is not None, f"{v.name} is missing in the FMI 3.0 description"
        assert (w.valueReference, w.causality, w.variability, w.unit, w.type) == (
            v.valueReference, v.causality, v.variability, v.unit, fmi3_type[v.type]), v.name
    extra = sorted(set(by_name) - {v.name for v in md2.modelVariables})
    indicators = [n for n in extra if n.startswith("event_indicator.")]
    assert [n for n in extra if n not in indicators] == ["time"]
    assert by_name["time"].causality == "independent" and by_name["time"].unit == "s"
    assert len(indicators) == md2.numberOfEventIndicators == len(md3.eventIndicators)
    # The same ModelStructure, in value references.
    def structure(unknowns):
        return sorted((u.variable.valueReference, tuple(sorted(d.valueReference for d in u.dependencies)) if u.dependencies is not None else None)
                      for u in unknowns)
    assert structure(md3.outputs) == structure(md2.outputs)
    assert structure(md3.derivatives) == structure(md2.derivatives)
    assert structure(md3.initialUnknowns) == structure(md2.initialUnknowns)


def run(path: Path, fmi_type: str):
    md = model_description(fmu_key(path))
    de = md.defaultExperiment
    extra = {"relative_tolerance": ME_RELATIVE_TOLERANCE, "record_events": False} if fmi_type == "ModelExchange" else {}
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    return simulate_fmu(unzipdir(fmu_key(path)), validate=False, model_description=md, fmi_type=fmi_type,
                        start_time=float(de.startTime or 0.0), stop_time=float(de.stopTime), output_interval=float(de.stepSize),
                        output=outputs, **extra), outputs


@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
def test_fmi3_simulates_as_fmi2(fmu_path, fmi_type):
    fmu3 = twin(fmu_path)
    (r2, outputs), (r3, _) = run(fmu_path, fmi_type), run(fmu3, fmi_type)
    assert len(r2) == len(r3) and np.array_equal(r2["time"], r3["time"]), (len(r2), len(r3))
    worst = []
    for name in outputs:
        a, b = np.asarray(r2[name], dtype=float), np.asarray(r3[name], dtype=float)
        span = max(float(np.ptp(a)), np.finfo(float).tiny)
        error = float(np.max(np.abs(a - b))) / span
        worst.append((error, name))
    error, name = max(worst)
    assert error <= REL_TOL, f"{fmu_path.stem} {fmi_type}: FMI 3.0 differs from FMI 2.0 by {error:.3g} of the range of {name}"


# ---------------------------------------------------------------------------------------------
# Co-Simulation with event mode and early return (FMI 3.0 only)

EVENT_MODE_STEPS = 3000  # output intervals of each default experiment (enough to meet events in 9 of 18 models)


def run_event_mode(path: Path, event_mode: bool):
    md = model_description(fmu_key(path))
    de = md.defaultExperiment
    start, h = float(de.startTime or 0.0), float(de.stepSize)
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    extra = {"use_event_mode": True, "early_return_allowed": True} if event_mode else {}
    return simulate_fmu(unzipdir(fmu_key(path)), validate=False, model_description=md, fmi_type="CoSimulation",
                        start_time=start, stop_time=min(float(de.stopTime), start + EVENT_MODE_STEPS * h),
                        output_interval=h, output=outputs, **extra), outputs


def event_mode_against_plain(fmu3: Path):
    """fmpy's FMI 3.0 Co-Simulation loop with eventModeUsed and earlyReturnAllowed (it enters
    Event Mode after every early return, updates the discrete states and steps on to the next
    regular point) against the same loop without: the outputs at the regular points, and how many
    rows the early returns added."""
    (plain, outputs), (evented, _) = run_event_mode(fmu3, False), run_event_mode(fmu3, True)
    # The last row at each regular time (fmpy records after the step and after the event).
    rows = [int(np.flatnonzero(np.isclose(evented["time"], t, rtol=0.0, atol=1e-12 * max(1.0, abs(t))))[-1]) for t in plain["time"]]
    worst = max((float(np.max(np.abs(plain[n] - evented[n][rows]))) / max(float(np.ptp(plain[n])), np.finfo(float).tiny), n)
                for n in outputs)
    return worst, len(evented) - len(plain)


def test_fmi3_event_mode_steps_as_events_handled_inside(fmu_path):
    # A step that returns at an event and is finished after the master's event mode takes the
    # same solver path as a step that handles the event itself (the modes are updated at the
    # same point and the solver re-made with the same step size), so the outputs agree to the
    # same 1e-12 of range as the two FMI versions.
    (error, name), _ = event_mode_against_plain(twin(fmu_path))
    assert error <= REL_TOL, f"{fmu_path.stem}: event mode differs by {error:.3g} of the range of {name}"


def test_fmi3_event_mode_returns_early_at_the_injections():
    # CommonRailInjection: the starts of injection in the firing order, the pump plungers' dead
    # centres and the valve seating are state events, several of each in the 0.12 s of the
    # default experiment: fmpy sees early returns.
    fmu3 = twin(require_fmu(DIST_DIR / "CommonRailInjection.fmu"))
    (error, name), early_rows = event_mode_against_plain(fmu3)
    assert early_rows > 0, "no early return at the injection events"
    assert error <= REL_TOL, f"event mode differs by {error:.3g} of the range of {name}"
