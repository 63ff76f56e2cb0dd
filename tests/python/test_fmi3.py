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
    fmi3_type = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean"}
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
