"""The energy balance of every FMU, in Co-Simulation and in Model Exchange (issue: every element's
effect, power and activity, generated).

Each model declares its elements (the chapter's Table 3.1: sources, storage C and I, dissipation R,
transformers) and reports each element's power from its equations; the runtime exposes

    power_balance_residual = sum(source powers) - sum(dE/dt of the storage elements) - sum(dissipated)
    power_balance_relative = power_balance_residual / max |element power|   (same instant)

Energy conservation makes the residual zero at every state, whatever the solver's accuracy, as long
as every element's power is reported and the equations are consistent with those powers (a torque
left out of an equation of motion, or a sign slip, leaves a residual of the order of that term;
fmu-runtime's unit test `a_force_left_out_of_an_equation_breaks_the_balance` shows one). So the
bound here is rounding, not a tolerance: |power_balance_relative| <= 1e-6 at every output point
(the issue's bound; measured worst is of the order of 1e-15, printed at the end).

Configurations: every combination of each FMU's structural choices (Integer parameters with a
declared range, Boolean parameters) when there are at most MAX_PRODUCT of them; otherwise every
combination of the two choices with the most values (MotorFan: level x start_mode) plus every value
of each other choice with the rest at their defaults. Each runs over the FMU's DefaultExperiment,
recorded at OUTPUT_POINTS points in CS and at the DefaultExperiment's stepSize in ME (the residual is algebraic in the state:
the recording grid does not change what it measures), in CS and in ME (fmpy's CVode at its default
tolerance).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from fmpy import simulate_fmu

from conftest import print_past_capture, all_fmu_paths, fmu_key, model_description, unzipdir

BOUND = 1e-6
MAX_PRODUCT = 24
OUTPUT_POINTS = 300
# Models without physical power: the speed controller is a signal block (a set-point filter and a
# PI law), its outputs are commands; it declares no element and has no balance.
SIGNAL_ONLY = {"SpeedController"}

WORST: list[str] = []


@pytest.fixture(scope="module", autouse=True)
def _print_worst(request):
    yield
    print_past_capture(request, "== energy balance: worst |power_balance_relative| per FMU and interface", WORST)


def structural_choices(md) -> dict[str, list]:
    """name -> its values, for every fixed Integer parameter with a range and every Boolean parameter."""
    choices = {}
    for v in md.modelVariables:
        if v.causality != "parameter":
            continue
        if v.type == "Integer" and v.min is not None and v.max is not None:
            lo, hi = int(v.min), int(v.max)
            if hi - lo <= 5:
                choices[v.name] = list(range(lo, hi + 1))
        elif v.type == "Boolean":
            choices[v.name] = [False, True]
    return choices


def configurations(md) -> list[dict]:
    choices = structural_choices(md)
    names = list(choices)
    product = int(np.prod([len(choices[n]) for n in names])) if names else 1
    if product <= MAX_PRODUCT:
        return [dict(zip(names, values)) for values in itertools.product(*(choices[n] for n in names))]
    main = sorted(names, key=lambda n: -len(choices[n]))[:2]
    configs = [dict(zip(main, values)) for values in itertools.product(*(choices[n] for n in main))]
    for n in names:
        if n in main:
            continue
        for value in choices[n]:
            configs.append({n: value})
    return configs


def fmus_with_balance():
    params = []
    for fmu in all_fmu_paths():
        md = model_description(fmu_key(fmu))
        if "power_balance_relative" not in {v.name for v in md.modelVariables}:
            continue  # a signal block, or NOT_YET: test_every_physical_fmu_has_a_balance_and_activities says which
        for config in configurations(md):
            label = ",".join(f"{k}={v}" for k, v in config.items()) or "defaults"
            params.append(pytest.param(fmu, config, id=f"{fmu.stem}[{label}]"))
    return params


# Models whose elements are not declared yet, with why (the issue stays open until this is empty).
# Each conversion is written and closes its balance to rounding (wip/issue-21/<crate>.patch), but
# lands only once the suites it changes pass; measured on the patched FMUs (2026-12-02):
NOT_YET = {
    "MotorFan": "its 7 new activity states (22 states in all) dilute CVode's error norm: ME at rtol 1e-8 then "
                "misses CS by 1.0002e-5 of shaft_torque's range (bound 1e-5, test_model_exchange.py)",
    "ShaftLine": "ME against CS at rtol 1e-6: seal_torque 1.14e-3 of its range (bound 1e-3; 6.6e-4 before the conversion)",
    "RlcCircuit": "test_accuracy.py: share_load_resistance 6.8e-3 of its range at rtol 1e-5 and 1e-6 (bound 10 rtol), "
                  "shares of activities still near zero just after the start",
    "TorqueSensor": "with the driver's input twist_in = 0.5 rad and 1 ms steps (tests/tests/threads.rs) the solver stalls "
                    "(step below 1e-13 s at t = 2.7 ms) on a jump of the driver's power at the torsion bar's stops",
}


def fmu_params():
    return [pytest.param(f, id=f.stem, marks=[pytest.mark.xfail(strict=True, reason=NOT_YET[f.stem])] if f.stem in NOT_YET else [])
            for f in all_fmu_paths()]


@pytest.mark.parametrize("fmu", fmu_params())
def test_every_physical_fmu_has_a_balance_and_activities(fmu):
    """Every FMU but the signal-only ones exposes the balance, and every storage and dissipative
    element its activity and share (the runtime declares them together)."""
    md = model_description(fmu_key(fmu))
    names = {v.name for v in md.modelVariables}
    if fmu.stem in SIGNAL_ONLY:
        assert "power_balance_residual" not in names
        return
    assert {"power_balance_residual", "power_balance_relative"} <= names, f"{fmu.stem}: no energy balance"
    activities = [n for n in names if n.startswith("activity_")]
    assert activities, f"{fmu.stem}: no activity output"
    for a in activities:
        element = a.removeprefix("activity_")
        assert f"A_{element}" in names, f"{fmu.stem}: {a} without its state A_{element}"


@pytest.mark.parametrize("fmu, config", fmus_with_balance())
@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
def test_energy_balance_holds(fmu, config, fmi_type):
    key = fmu_key(fmu)
    md = model_description(key)
    de = md.defaultExperiment
    start, stop = float(de.startTime or 0.0), float(de.stopTime)
    extra = {"solver": "CVode", "record_events": False} if fmi_type == "ModelExchange" else {}
    interval = (stop - start) / OUTPUT_POINTS
    if fmi_type == "ModelExchange":
        # fmpy caps CVode at 500 steps per output interval (mxstep): the dq models of InductionMotor
        # and MotorFan level d starting up take more in 10 ms, so ME records at the FMU's own step.
        interval = float(de.stepSize)
    res = simulate_fmu(
        unzipdir(key),
        validate=False,
        model_description=md,
        fmi_type=fmi_type,
        start_time=start,
        stop_time=stop,
        output_interval=interval,
        start_values=dict(config),
        output=["power_balance_relative", "power_balance_residual"],
        **extra,
    )
    relative = np.abs(np.asarray(res["power_balance_relative"], dtype=float))
    assert np.all(np.isfinite(relative)), f"{fmu.stem} {config} {fmi_type}: non-finite balance"
    i = int(np.argmax(relative))
    WORST.append(f"{fmu.stem:22s} {fmi_type:14s} {config}: {relative[i]:.2e} at t = {res['time'][i]:.4g} s "
                 f"(residual {res['power_balance_residual'][i]:.2e} W)")
    assert relative[i] <= BOUND, (
        f"{fmu.stem} {config} {fmi_type}: power_balance_relative {relative[i]:.3e} at t = {res['time'][i]:.6g} s "
        f"(residual {res['power_balance_residual'][i]:.3e} W): an element's power is missing or an equation is inconsistent")


# The chapter's Table 3.1 for the cooling-tower fan (section 3.2.1): every effect it lists, by the
# words the chapter uses (the FMU's table may word the motor's torque source its own way).
TABLE_3_1_MOTOR_FAN = (
    "voltage source", "electromechanical transformer", "winding inductance", "winding resistance", "rotor inertia",
    "bearing friction", "shaft stiffness", "internal damping", "reduction ratio", "reducer efficiency", "blade inertia",
    "aerodynamic load",
)


def documentation_page(fmu) -> str:
    import zipfile
    with zipfile.ZipFile(fmu) as z:
        return z.read("documentation/index.html").decode()


@pytest.mark.xfail(strict=True, reason="MotorFan: " + NOT_YET["MotorFan"])
def test_motor_fan_documentation_lists_table_3_1_and_the_activities_of_its_default_experiment():
    from conftest import DIST_DIR, require_fmu
    import re
    fmu = require_fmu(DIST_DIR / "MotorFan.fmu")
    page = documentation_page(fmu)
    start = page.index("Systematic analysis of effects")
    table_3_1 = page[start:page.index("</table>", start)]
    missing = [row for row in TABLE_3_1_MOTOR_FAN if row not in table_3_1]
    assert not missing, f"MotorFan's Table 3.1 lacks {missing}"
    assert "neglected" in table_3_1, "the effects the book's model leaves out are listed as neglected"
    # The activity table is the FMU's own default experiment: its shares are the share outputs
    # at the stop time of a plain fmpy run (both from the same equations; printed to 3 decimals).
    start = page.index("Activity of each element over the default experiment")
    activity = page[start:page.index("</table>", start)]
    md = model_description(fmu_key(fmu))
    shares = [v.name for v in md.modelVariables if v.name.startswith("share_")]
    res = simulate_fmu(unzipdir(fmu_key(fmu)), validate=False, model_description=md, output=shares)
    for name in shares:
        element = name.removeprefix("share_")
        row = re.search(rf"<code>{element}</code></td><td>[^<]*</td><td>[^<]*</td><td>[^<]*</td><td>([0-9.]+)</td>", activity)
        assert row, f"no row for {element} in the activity table"
        assert abs(float(row.group(1)) - float(res[name][-1])) <= 6e-4, f"{element}: documented {row.group(1)} %, run {res[name][-1]:.4f} %"
