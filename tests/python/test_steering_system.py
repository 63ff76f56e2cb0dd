"""SteeringSystem coupled by external co-simulation masters against the monolithic PowerSteering.

Acceptance (docs/steering-system-spec.md, issue 22 part 1): the parking manoeuvre, 0-16 s at a
communication step of 1 ms, run by fmpy's `simulate_ssp`, ecospy and libcosimpy on
dist/SteeringSystem.ssp and by the three FMUs packed into one container FMU by fmucontainer and run
in fmpy, agrees with dist/PowerSteering.fmu at its defaults (same step): the driver's torque, the
rack's force and position and the motor's current each within 1 % of the monolith's peak |value| at
every common communication point. A master that misses it fails with its figures (`pytest -s`
prints them for every master). The README's table comes from `steering_system.py`.

Cost: each master runs once, 16 000 steps: about 2.5 s for fmpy's SSP runner (a Python loop), 1.3 s
for libcosimpy, under 0.3 s for the others.
"""

from __future__ import annotations

import functools
import zipfile

import pytest

import coupled_masters as cm
import steering_system as ss
from conftest import DIST_DIR, require_fmu

STEP = 1e-3
SSP = DIST_DIR / "SteeringSystem.ssp"
# docs/steering-system-spec.md, "Connections"
CONNECTIONS = {
    ("SteeringRack", "column_angle", "SteeringColumn", "column_angle"),
    ("SteeringRack", "column_speed", "SteeringColumn", "column_speed"),
    ("SteeringRack", "column_speed", "AssistMotor", "column_speed"),
    ("SteeringColumn", "torsion_bar_torque", "SteeringRack", "torsion_bar_torque"),
    ("SteeringColumn", "torsion_bar_torque", "AssistMotor", "measured_torque"),
    ("AssistMotor", "motor_torque", "SteeringRack", "motor_torque"),
}


@functools.cache
def reference() -> cm.Run:
    return ss.reference(DIST_DIR, STEP)


@functools.cache
def coupled(master: str) -> cm.Run:
    require_fmu(SSP)
    if master == "ecospy":
        try:
            import ecospy  # noqa: F401
        except OSError as e:  # libtbb.so.12 missing
            pytest.fail(f"ecospy cannot load its library ({e}): ./test.sh installs Debian's libtbb12", pytrace=False)
    return ss.coupled(master, DIST_DIR, STEP)


def test_the_ssp_couples_the_three_subsystems_as_the_spec_says():
    from fmpy.ssp.ssd import read_ssd

    require_fmu(SSP)
    with zipfile.ZipFile(SSP) as z:
        names = z.namelist()
        assert names[0] == "SystemStructure.ssd", names
        assert sorted(names[1:]) == sorted(f"resources/{s}.fmu" for s in ss.SUBSYSTEMS), names
        for s in ss.SUBSYSTEMS:  # the very FMUs of dist/
            assert z.read(f"resources/{s}.fmu") == require_fmu(DIST_DIR / f"{s}.fmu").read_bytes(), s
    ssd = read_ssd(str(SSP))  # validates against fmpy's copy of the SSP 1.0 schema
    assert ssd.version == "1.0" and ssd.name == "SteeringSystem"
    components = {c.name: c for c in ssd.system.elements}
    assert set(components) == set(ss.SUBSYSTEMS)
    got = {(c.startElement, c.startConnector, c.endElement, c.endConnector) for c in ssd.system.connections}
    assert got == CONNECTIONS
    kinds = {(c.name, k.name): k.kind for c in components.values() for k in c.connectors}
    for a, y, b, u in CONNECTIONS:
        assert kinds[(a, y)] == "output" and kinds[(b, u)] == "input"
    # every input of the three is connected: nothing is left at its start value
    inputs = {key for key, kind in kinds.items() if kind == "input"}
    assert inputs == {(b, u) for _, _, b, u in CONNECTIONS}, inputs
    for component, variable in ss.SIGNALS:  # recorded by the masters
        assert kinds[(component, variable)] == "output"
    assert {"rad", "rad/s", "N.m"} <= {u.name for u in ssd.units}
    assert cm.ssp_parameters(SSP) == {}  # every default is the monolith's


@pytest.mark.parametrize("master", ss.MASTERS)
def test_coupled_parking_manoeuvre_matches_the_monolithic_power_steering(master):
    run, ref = coupled(master), reference()
    e = ss.errors(run, ref)
    figures = f"{cm.SCHEMES[master]}, h = {STEP * 1e3:g} ms, 0-{ss.STOP_TIME:g} s ({run.seconds:.2f} s wall): " + "; ".join(
        f"{k} {d.error:.3f} % of peak {cm.peak(ref, k):.4g} at t = {d.worst_time:.3f} s" for k, d in e.worst.items()
    ) + f" [limit {ss.TOLERANCE_PCT} %]"
    print("\n" + figures)
    for d in e.worst.values():
        assert d.points >= int(round(ss.STOP_TIME / STEP)), figures
        assert d.error <= ss.TOLERANCE_PCT, figures
