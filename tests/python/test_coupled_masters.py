"""MotorFanSystem coupled by external co-simulation masters against the monolithic MotorFan.

Acceptance (docs/motor-fan-system-spec.md, the SSP issue): the direct-on-line start, 0-30 s at a
communication step of 1 ms, run by fmpy's `simulate_ssp` on dist/MotorFanSystem.ssp, by ecospy and by
libcosimpy on the same .ssp, and by the subsystem FMUs packed into one container FMU by fmucontainer
and run in fmpy, agrees with dist/MotorFan.fmu (level=3, start_mode=1, same step): the fan speed
within 0.5 % of the rated speed (the monolithic final fan speed) at every common output point, and
the peak |shaft torque| within 3 % of the monolithic peak. The criteria are not loosened here: a
master that misses them fails with its figures (`pytest -s` prints them for every master).

How each master's rows are put on the grid of communication points (fmpy's SSP rows are stamped
with the step's start, ecospy's time drifts in floats, libcosim counts in nanoseconds, ...) is in
coupled_masters.py; `test_the_masters_agree_once_aligned` checks it: masters that run the same
(Jacobi) algorithm must then give the same fan speed to round-off.

Cost: each master runs once per session (cached), 30000 steps each: about 2.5 s for fmpy's SSP
runner (a Python loop), under 1 s for each of the others.
"""

from __future__ import annotations

import functools
import zipfile

import numpy as np
import pytest

import coupled_masters as cm
from conftest import DIST_DIR, require_fmu

STEP = 1e-3
STOP_TIME = 30.0
FAN_TOLERANCE_PCT = 0.5  # of the rated fan speed, at every output point
PEAK_TOLERANCE_PCT = 3.0  # of the monolithic peak |shaft torque|

SSP = DIST_DIR / "MotorFanSystem.ssp"
SUBSYSTEMS = ("InductionMotor", "DriveShaft", "Fan")
# docs/motor-fan-system-spec.md, "Connections", direct on line
CONNECTIONS = {
    ("InductionMotor", "angle", "DriveShaft", "angle_a"),
    ("Fan", "angle_high", "DriveShaft", "angle_b"),
    ("InductionMotor", "speed", "DriveShaft", "speed_a"),
    ("Fan", "speed_high", "DriveShaft", "speed_b"),
    ("DriveShaft", "torque", "InductionMotor", "load_torque"),
    ("DriveShaft", "torque", "Fan", "shaft_torque"),
}


def require_ssp():
    require_fmu(SSP)
    return SSP


@functools.cache
def reference() -> cm.Run:
    """MotorFan.fmu, level=3, start_mode=1, keyed like the coupled runs (cm.MOTOR_FAN_OUTPUTS)."""
    return cm.motor_fan_reference(require_fmu(DIST_DIR / "MotorFan.fmu"), STEP, STOP_TIME)


@functools.cache
def coupled(master: str) -> cm.Run:
    """The fan speed and the shaft torque (cm.MOTOR_FAN_SIGNALS) from one master; the sequential
    container steps the components in cm.MOTOR_FAN_ORDER."""
    if master == "ecospy":
        try:
            import ecospy  # noqa: F401
        except OSError as e:  # libtbb.so.12 missing
            pytest.fail(f"ecospy cannot load its library ({e}): ./test.sh installs Debian's libtbb12", pytrace=False)
    return cm.motor_fan_coupled(master, require_ssp(), STEP, STOP_TIME)


def test_the_ssp_is_ssp_1_0_with_the_spec_connections():
    from fmpy.ssp.ssd import read_ssd

    ssp = require_ssp()
    with zipfile.ZipFile(ssp) as z:
        names = z.namelist()
        assert names[0] == "SystemStructure.ssd", names
        assert sorted(names[1:]) == sorted(f"resources/{s}.fmu" for s in SUBSYSTEMS), names
        for s in SUBSYSTEMS:  # the very FMUs of dist/
            assert z.read(f"resources/{s}.fmu") == require_fmu(DIST_DIR / f"{s}.fmu").read_bytes(), s
    ssd = read_ssd(str(ssp))  # validates against fmpy's copy of the SSP 1.0 schema
    assert ssd.version == "1.0" and ssd.name == "MotorFanSystem"
    components = {c.name: c for c in ssd.system.elements}
    assert set(components) == set(SUBSYSTEMS)
    for name, c in components.items():
        assert c.type == "application/x-fmu-sharedlibrary" and c.source == f"resources/{name}.fmu"
    got = {(c.startElement, c.startConnector, c.endElement, c.endConnector) for c in ssd.system.connections}
    assert got == CONNECTIONS
    kinds = {(c.name, k.name): k.kind for c in components.values() for k in c.connectors}
    for a, y, b, u in CONNECTIONS:
        assert kinds[(a, y)] == "output" and kinds[(b, u)] == "input"
    assert kinds[("Fan", "fan_speed")] == "output"  # recorded by fmpy's runner
    units = {u.name for u in ssd.units}
    assert {"rad/s", "N.m"} <= units, units
    # Direct on line, stated (the declaration names the item "direct_on_line"): written as the
    # item's value, an ssv:Integer, which every master here reads (ecos and libcosim stop at an
    # ssv:Enumeration).
    assert cm.ssp_bindings(ssp) == {"InductionMotor.drive": ("Integer", "1")}
    assert cm.ssp_parameters(ssp) == {"InductionMotor.drive": "1"}


# The masters (fmpy simulate_ssp, ecospy, libcosimpy, the default container) are Jacobi
# masters holding inputs over a step; they meet the criteria because the subsystem FMUs extrapolate
# their inputs themselves (`extrapolate_inputs`, docs/DESIGN.md). The extra Gauss-Seidel container
# hands the later FMUs inputs of the END of the step, which that extrapolation pushes further still:
# measured 12.28 % of rated fan speed at 1 ms, peak torque -54.0 % (the book's defaults; 2.83 % / -3.03 % with the first set). Strict: if it ever passes, the
# mark must go.
SEQUENTIAL_XFAIL = pytest.mark.xfail(
    strict=True,
    reason="Gauss-Seidel container: FMU-side input extrapolation over-extrapolates inputs that are already "
    "from the end of the step (12.28 % fan speed, -54.0 % peak torque at 1 ms with the book's defaults); see docs/DESIGN.md",
)


@pytest.mark.parametrize(
    "master", [pytest.param(m, marks=SEQUENTIAL_XFAIL) if "sequential" in m else m for m in cm.MASTERS]
)
def test_coupled_direct_on_line_start_matches_the_monolithic_model(master):
    run, ref = coupled(master), reference()
    c = cm.compare(run, ref)
    figures = (
        f"{cm.SCHEMES[master]}, h = {STEP * 1e3:g} ms, 0-{STOP_TIME:g} s ({c.points} points, {run.seconds:.2f} s wall): "
        f"fan speed error max {c.fan_error_pct:.3f} % of rated ({c.rated:.4f} rad/s) at t = {c.worst_time:.3f} s "
        f"[limit {FAN_TOLERANCE_PCT} %]; peak |shaft torque| {c.peak:.1f} N m vs {c.peak_reference:.1f} N m "
        f"monolithic, {c.peak_error_pct:+.2f} % [limit {PEAK_TOLERANCE_PCT} %]"
    )
    print("\n" + figures)
    assert c.points >= int(round(STOP_TIME / STEP)), figures
    assert abs(c.peak_error_pct) <= PEAK_TOLERANCE_PCT, figures
    assert c.fan_error_pct <= FAN_TOLERANCE_PCT, figures


def test_the_masters_agree_once_aligned():
    """fmpy's SSP runner, libcosim and the (parallel) container all run the Jacobi scheme, so once
    their rows are put on the grid as coupled_masters.py says they give the same fan speed to the
    subsystems' solver accuracy; ecospy too, to its CSV's 6 decimals. Shifting any of them by one
    step would leave differences of ~0.03 rad/s: the check has the power to catch a wrong alignment.

    The same FMUs under two masters do not take bit-identical solver steps (a master that sets an
    unchanged input again makes the explicit solver restart at the communication point instead of
    stepping past it), so the runs differ by the solvers' error: each subsystem integrates at its
    1e-11 floor, and two solutions of the same equations may drift apart by up to K = 1000 x rtol of
    a state's range (the argument of tests/tests/model_exchange_strict.rs): 1000 x 1e-11 x 18.8
    rad/s (the book's rated fan speed) = 1.9e-7 rad/s. Measured: libcosim 2.4e-9 rad/s off fmpy's
    runner with the book's defaults (below 1e-9 with the first set, whose run-up rings less)."""
    solver_agreement = 1000 * 1e-11 * 18.8
    base = coupled("fmpy simulate_ssp")
    for master, tolerance in [("libcosimpy", solver_agreement), ("fmucontainer (fmpy)", solver_agreement), ("ecospy", 1e-6)]:
        run = coupled(master)
        common, i, j = np.intersect1d(run.k, base.k, return_indices=True)
        assert len(common) >= len(base.k) - 1, master
        diff = np.max(np.abs(run.fan_speed[i] - base.fan_speed[j]))
        assert diff <= tolerance, f"{master} differs from fmpy simulate_ssp by {diff} rad/s"
        # the same comparison one step off
        _, i1, j1 = np.intersect1d(run.k, base.k + 1, return_indices=True)
        assert np.max(np.abs(run.fan_speed[i1] - base.fan_speed[j1])) > 1e-3


def test_the_ecos_command_line_runs_the_ssp(tmp_path):
    """ecospy's bundled `ecos` executable (made executable by ./test.sh) runs the same .ssp and
    writes <system>.csv into its working directory, with the same fan speed as ecospy's API. Its
    time is a float sum of the steps: asked for 2 s at 1 ms, it stops after 1999 steps."""
    import subprocess
    from pathlib import Path

    try:
        import ecospy
    except OSError as e:
        pytest.fail(f"ecospy cannot load its library ({e}): ./test.sh installs Debian's libtbb12", pytrace=False)
    ecos = Path(ecospy.__file__).parent / "binaries" / "ecos"
    proc = subprocess.run([str(ecos), "simulate", "--path", str(require_ssp()), "--stepSize", "0.001", "--stopTime", "2",
                           "--parameterSet", cm.ECOS_PARAMETER_SET, "-l", "warn"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr[-2000:]
    with open(tmp_path / "MotorFanSystem.csv") as f:
        header = [h.strip().split("[")[0] for h in f.readline().split(",")]
        rows = np.array([[float(x) for x in line.split(",") if x.strip()] for line in f if line.strip()])
    k, fan = rows[:, header.index("iterations")], rows[:, header.index("Fan::fan_speed")]
    assert int(k[-1]) in (1999, 2000)
    api = coupled("ecospy")
    common, i, j = np.intersect1d(k.astype(np.int64), api.k, return_indices=True)
    assert len(common) == len(k)
    assert np.max(np.abs(fan[i] - api.fan_speed[j])) <= 1e-6
