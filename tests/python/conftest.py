"""Shared pytest setup for the Python FMI tests.

The FMUs under test are the ones built into dist/ by `cargo run --release -p build-fmus`
(or the directory named by the environment variable FMU_DIST_DIR).

* `fmu_path` is parametrized over every dist/*.fmu plus every FMU listed in EXPECTED_FMUS, so a new
  model is covered by the generic tests as soon as build-fmus puts it into dist/, and a missing
  expected FMU makes the tests fail (not skip) with the command to build it.
* `rlc_fmu` is the path of dist/RlcCircuit.fmu (fails the same way if it is missing).
"""

from __future__ import annotations

import atexit
import functools
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest
from fmpy import extract, read_model_description

REPO_ROOT = Path(__file__).resolve().parents[2]
DIST_DIR = Path(os.environ["FMU_DIST_DIR"]).resolve() if os.environ.get("FMU_DIST_DIR") else REPO_ROOT / "dist"

# FMUs that build-fmus must produce; any other dist/*.fmu is tested by the generic tests too.
EXPECTED_FMUS = ("RlcCircuit", "MotorFan", "TractionMotorThermal", "TorqueSensor", "ShaftLine", "ElevatorDrive", "EhaFlightControl", "PowerSteering",
                 "SteeringColumn", "AssistMotor", "SteeringRack", "MemsAccelerometer", "BoosterNozzle", "CommonRailInjection")

BUILD_HINT = "run `cargo run --release -p build-fmus` (from the repository root) to build the FMUs into dist/"

# The CI build's build-fmus and its cargo target directory, which a model crate built outside the
# workspace shares (test_generator.py, test_chain.py): only the crate itself is compiled there.
TARGET_DIR = Path(os.environ["CARGO_TARGET_DIR"]).resolve() if os.environ.get("CARGO_TARGET_DIR") else REPO_ROOT / "target"
BUILD_FMUS = TARGET_DIR / "release" / "build-fmus"


def build_fmus(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    """Runs the CI build's `build-fmus` with these arguments, sharing its target directory."""
    assert BUILD_FMUS.is_file(), f"{BUILD_FMUS} not found: run `cargo run --release -p build-fmus` first"
    env = dict(os.environ, CARGO_TARGET_DIR=str(TARGET_DIR))
    return subprocess.run([str(BUILD_FMUS), *args], cwd=cwd, env=env, capture_output=True, text=True, timeout=900)


def require_fmu(path: Path) -> Path:
    """Fail the calling test clearly if an FMU is not there."""
    if not path.is_file():
        where = "FMU_DIST_DIR" if os.environ.get("FMU_DIST_DIR") else "<repo>/dist"
        pytest.fail(f"{path} is missing ({where} = {DIST_DIR}): {BUILD_HINT}", pytrace=False)
    return path


def all_fmu_paths() -> list[Path]:
    """Every FMU in dist/ plus the expected ones (which may be missing: the tests then fail)."""
    found = set(DIST_DIR.glob("*.fmu")) if DIST_DIR.is_dir() else set()
    found |= {DIST_DIR / f"{name}.fmu" for name in EXPECTED_FMUS}
    return sorted(found)


def fmu_key(fmu: Path) -> tuple[str, float]:
    """The FMU's path and modification time: a rebuilt FMU is never served from the caches below."""
    return str(fmu), fmu.stat().st_mtime


@functools.lru_cache(maxsize=None)
def model_description(key: tuple[str, float]):
    """The FMU's model description, read once per session (key: `fmu_key(path)`)."""
    return read_model_description(key[0])


@functools.lru_cache(maxsize=None)
def unzipdir(key: tuple[str, float]) -> str:
    """Extract each FMU once per session (fmpy would extract it again for every simulation)."""
    d = extract(key[0])
    atexit.register(shutil.rmtree, d, ignore_errors=True)
    return d


@functools.lru_cache(maxsize=None)
def simulate_cs(key: tuple[str, float], start_items: tuple, stop_time: float, output_interval: float, outputs: tuple):
    """(fmpy result, wall-clock seconds) of one Co-Simulation run from t = 0 with these start values
    (a sorted tuple of (name, value)), simulated once per session and then served from the cache."""
    from fmpy import simulate_fmu

    t0 = time.perf_counter()
    res = simulate_fmu(
        unzipdir(key),
        validate=False,  # test_validate.py validates every dist/*.fmu
        model_description=model_description(key),
        fmi_type="CoSimulation",
        start_time=0.0,
        stop_time=stop_time,
        output_interval=output_interval,
        start_values=dict(start_items),
        output=list(outputs),
    )
    return res, time.perf_counter() - t0


FMUTOOL = Path(sys.executable).with_name("fmutool")

# `fmutool -input X.fmu -check` (fmu_manipulation_toolbox 2.0) logs one record per line to stdout as
#     "<LEVEL padded to 8> | <message>"
# e.g.
#     INFO     | This FMU seems to be compliant with FMI-2.0.
#     INFO     | No semantic error against the FMI-2 standard.
#     ERROR    | Name 'R_series' is used by several variables (FMI-2 §2.2.7).
#     ERROR    | -check: 6 error(s) found.
# (colour codes only on a terminal; stripped below anyway). A finding is any WARNING, ERROR or
# CRITICAL record; exit status 7 means the check failed. Only the FMU's own records can appear here:
# the container's false "[ERROR] Solver configure" (TOOLS.md) is an fmucontainer message, not ours.
FMUTOOL_FINDING = re.compile(r"^(WARNING|ERROR|CRITICAL)\s*\|")
ANSI = re.compile(r"\x1b\[[0-9;]*[A-Za-z]")


def assert_fmutool_clean(fmu_path: Path) -> None:
    """`fmutool -check` on one FMU: exit 0, no finding, and both checkers' positive verdicts."""
    assert FMUTOOL.is_file(), f"{FMUTOOL} not found: install tests/requirements.txt into this venv"
    proc = subprocess.run(
        [str(FMUTOOL), "-input", str(fmu_path), "-check"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    out = ANSI.sub("", proc.stdout + proc.stderr)
    findings = [line for line in out.splitlines() if FMUTOOL_FINDING.match(line.strip())]
    assert proc.returncode == 0 and not findings, (
        f"fmutool -check {fmu_path.name}: exit {proc.returncode}, {len(findings)} finding(s):\n"
        + "\n".join(findings)
        + f"\n--- full output ---\n{out}"
    )
    # the positive verdicts of both built-in checkers must be there (guards against a silent no-op)
    assert "This FMU seems to be compliant with FMI-2.0." in out, out
    assert "No semantic error against the FMI-2 standard." in out, out


def pytest_generate_tests(metafunc):
    if "fmu_path" in metafunc.fixturenames:
        paths = all_fmu_paths()
        metafunc.parametrize("fmu_path", paths, ids=[p.stem for p in paths], indirect=True)


@pytest.fixture
def fmu_path(request) -> Path:
    return require_fmu(request.param)


@pytest.fixture
def rlc_fmu() -> Path:
    return require_fmu(DIST_DIR / "RlcCircuit.fmu")


def pytest_report_header(config):
    return [f"FMU dist dir: {DIST_DIR}", f"FMUs: {', '.join(p.name for p in all_fmu_paths())}"]


def print_past_capture(request, title: str, lines: list[str]) -> None:
    """Prints a module's report (title, then lines) past pytest's output capture, so it shows with or
    without `-s`; nothing when there are no lines."""
    if not lines:
        return
    text = "\n".join(["", title, *lines, ""])
    capman = request.config.pluginmanager.getplugin("capturemanager")
    if capman is not None:
        with capman.global_and_fixture_disabled():
            print(text, flush=True)
    else:  # pragma: no cover (capture plugin disabled)
        print(text, flush=True)
