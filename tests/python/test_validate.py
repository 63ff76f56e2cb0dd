"""Generic checks for EVERY dist/*.fmu (parametrized by conftest.py).

References: the FMI 2.0 standard as implemented by two independent checkers (fmpy's validate_fmu and
fmu_manipulation_toolbox's `fmutool -check`), plus a load-and-instantiate run because neither
checker loads the binary (TOOLS.md).
"""

from __future__ import annotations

import re
import zipfile
from ctypes import byref
from pathlib import Path

import pytest
from fmpy import read_model_description
from fmpy.fmi2 import fmi2CoSimulation
from fmpy.validation import validate_fmu

from conftest import DIST_DIR, EXPECTED_FMUS, assert_fmutool_clean
from fmi_host import Slave

def test_expected_fmus_are_built():
    missing = [name for name in EXPECTED_FMUS if not (DIST_DIR / f"{name}.fmu").is_file()]
    assert not missing, (
        f"missing in {DIST_DIR}: {', '.join(m + '.fmu' for m in missing)}; "
        "run `cargo run --release -p build-fmus` to build them"
    )


def test_metadata_and_icon(fmu_path):
    # version, author, license from the model crate's Cargo metadata; a reproducible source date
    md = read_model_description(str(fmu_path))
    assert md.version and md.author and md.license == "MIT", (md.version, md.author, md.license)
    assert md.copyright == f"Copyright (c) {md.generationDateAndTime[:4]} {md.author}", md.copyright
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ", md.generationDateAndTime), md.generationDateAndTime
    icon = zipfile.ZipFile(fmu_path).read("model.png")
    assert icon.startswith(b"\x89PNG\r\n\x1a\n")


def test_fmpy_validate(fmu_path):
    problems = validate_fmu(str(fmu_path))
    assert problems == [], f"fmpy.validation.validate_fmu({fmu_path.name}) found {len(problems)} problem(s):\n" + "\n".join(
        f"  - {p}" for p in problems
    )


def test_fmutool_check(fmu_path):
    assert_fmutool_clean(fmu_path)


def test_is_fmi2_cosimulation(fmu_path):
    md = read_model_description(str(fmu_path))
    assert md.fmiVersion == "2.0"
    assert md.coSimulation is not None, "the project builds Co-Simulation FMUs"
    names = zipfile.ZipFile(fmu_path).namelist()
    lib = f"binaries/linux64/{md.coSimulation.modelIdentifier}.so"
    assert lib in names, f"{lib} not in {fmu_path.name} (modelIdentifier must match the library name)"


def _step_size(md) -> float:
    de = md.defaultExperiment
    if de is not None and de.stepSize is not None:
        return float(de.stepSize)
    return 1e-3


def test_load_instantiate_step(fmu_path):
    """Loads the binary and runs the minimal CS life cycle; every call must return fmi2OK/fmi2Warning
    (fmpy raises FMICallException otherwise). Reference: the FMI 2.0 CS state machine."""
    with Slave(fmu_path) as s:
        s.instantiate()
        assert s.fmu.getVersion() == "2.0"
        assert s.fmu.getTypesPlatform() == "default"
        s.initialize(start_time=0.0)
        h = _step_size(s.md)
        s.do_step(0.0, h)
        reals = [v.name for v in s.md.modelVariables if v.type == "Real"]
        values = s.get(*reals)
        assert len(values) == len(reals)
    errors = [r for r in s.log.records if r[0] >= 3]
    assert not errors, f"the FMU logged errors: {errors}"


def test_host_without_memory_callbacks_and_resource_location(fmu_path):
    """Some masters (fmusim) give no allocateMemory/freeMemory when the FMU declares
    canNotUseMemoryManagementFunctions="true", and fmuResourceLocation = NULL when the FMU has no
    resources/ folder; both must work (TOOLS.md)."""
    md = read_model_description(str(fmu_path))
    if not md.coSimulation.canNotUseMemoryManagementFunctions:
        pytest.skip("the FMU may use the memory callbacks")
    has_resources = any(n.startswith("resources/") for n in zipfile.ZipFile(fmu_path).namelist())
    with Slave(fmu_path) as s:
        cb = s.log.callbacks(memory_functions=False)
        s.fmu.callbacks = cb
        resource = None if not has_resources else Path(s.unzipdir, "resources").as_uri().encode()
        comp = s.fmu.fmi2Instantiate(b"no_callbacks", fmi2CoSimulation, md.guid.encode(), resource, byref(cb), 0, 0)
        assert comp, "fmi2Instantiate returned NULL without memory callbacks / with NULL fmuResourceLocation"
        s.fmu.component = comp
        s.instantiated = True
        s.initialize(start_time=0.0)
        s.do_step(0.0, _step_size(md))
