"""The chapter's figures (examples/): every script runs on a short horizon and writes its files,
and the chapter's reduction findings are checked on the full-length FMU runs.

* Every example script runs alone, as a user would (`python examples/<script>.py --short --out DIR`),
  all at once in subprocesses; each must exit 0 and write its PNG (and Table 3.3's markdown), non-empty.
* examples/make_figures.py (the one command) lists every script.
* Table 3.3 (chapter 3.3.2): the shaft stiffness' share of the activity falls by >= 10x with the PI
  controller (level c, 30 s runs of dist/MotorFan.fmu), and the script's table rounds to the digits the
  chapter prints.
* Figure 3.11 (chapter 3.3.3): under speed control the one-at-a-time +-10 % sweep finds fan inertia the
  most influential parameter on the peak shaft torque (30 s runs, in the script's process pool).
* Figure 3.13 (chapter 3.3.3): with the set point filtered below 1.4 Hz the shaft's elasticity is
  negligible for the peak torque: holds on the book's 10 s ramp through the filter, not on a step
  through it (a strict xfail).
* The Dask path of the sweep: the script with `--scheduler ADDRESS` against an in-process
  dask.distributed LocalCluster on tcp (worker threads in this process: the client, the upload of the
  modules and the scattered FMU bytes are exercised, separate worker machines are not); its results
  equal the process pool's.
The MotorFan checks run with its defaults, the book authors' values (book file Chap3_CoolingTowerFan.mo).
The figures are written to pytest's temporary directory, never to docs/figures.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import DIST_DIR, REPO_ROOT, require_fmu

EXAMPLES = REPO_ROOT / "examples"
sys.path.insert(0, str(EXAMPLES))

# script -> the files it writes
OUTPUTS = {
    "fig3_3_rlc": ["RlcCircuit_fig3_3.png"],
    "fig3_6_levels": ["MotorFan_fig3_6_levels.png"],
    "fig3_8_variable_speed": ["MotorFan_fig3_8_variable_speed.png"],
    "fig3_10_shaft_stiffness": ["MotorFan_fig3_10_shaft_stiffness.png"],
    "fig3_11_oat": ["MotorFan_fig3_11_oat.png"],
    "fig3_13_setpoint_filter": ["MotorFan_fig3_13_setpoint_filter.png"],
    "table3_3_activity": ["MotorFan_table3_3.md", "MotorFan_table3_3.png"],
    "tgv_thermal": ["TractionMotorThermal_heating.png"],
    "torque_sensor": ["TorqueSensor_characteristic.png"],
    "shaft_line_short_circuit": ["ShaftLine_short_circuit.png"],
    "elevator_drive": ["ElevatorDrive_ride.png"],
    "power_steering": ["PowerSteering_parking.png"],
    "eha_flight_control": ["EhaFlightControl_levels.png"],
    "booster_nozzle": ["BoosterNozzle_resonance_and_effects.png"],
    "mems_accelerometer": ["MemsAccelerometer_response.png"],
    "common_rail": ["CommonRailInjection_rail_pressure.png"],
}
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def fmus():
    for name in ("RlcCircuit", "MotorFan", "TractionMotorThermal", "TorqueSensor"):
        require_fmu(DIST_DIR / f"{name}.fmu")


@pytest.fixture(scope="module")
def short_runs(fmus, tmp_path_factory):
    """Every script with --short, all started at once; {script: (out dir, returncode, output)}."""
    env = {**os.environ, "MPLBACKEND": "Agg", "FMU_DIST_DIR": str(DIST_DIR)}
    procs = {}
    for script in OUTPUTS:
        out = tmp_path_factory.mktemp(script)
        procs[script] = (out, subprocess.Popen(
            [sys.executable, str(EXAMPLES / f"{script}.py"), "--short", "--out", str(out)],
            cwd=tmp_path_factory.getbasetemp(), env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True))
    results = {}
    for script, (out, p) in procs.items():
        text, _ = p.communicate(timeout=300)
        results[script] = (out, p.returncode, text)
    return results


def test_every_example_script_is_tested_and_in_make_figures():
    import make_figures

    scripts = {p.stem for p in EXAMPLES.glob("*.py")} - {"figures_common", "make_figures"}
    assert scripts == set(OUTPUTS), "a script in examples/ is missing from this test's OUTPUTS (or the other way round)"
    assert set(make_figures.SCRIPTS) == scripts, "examples/make_figures.py must run every script"


@pytest.mark.parametrize("script", list(OUTPUTS))
def test_script_writes_its_figures(short_runs, script):
    out, rc, text = short_runs[script]
    assert rc == 0, f"examples/{script}.py --short exited {rc}:\n{text}"
    for name in OUTPUTS[script]:
        path = out / name
        assert path.is_file() and path.stat().st_size > 0, f"{script} did not write {name}:\n{text}"
        if name.endswith(".png"):
            assert path.read_bytes()[:8] == PNG_MAGIC, f"{name} is not a PNG"
    assert sorted(p.name for p in out.iterdir()) == sorted(OUTPUTS[script]), "unexpected files written"


def test_table_3_3_controller_removes_the_shaft_stiffness_activity(fmus, tmp_path):
    # reference: chapter 3.3.2, Table 3.3: the driveshaft stiffness' share of the activity falls from 9 %
    # without a controller to 0.3 % with one (30x). Criterion (issue 12): at least 10x with the PI controller.
    import table3_3_activity as table

    s = table.shares(short=False)
    md = table.markdown(s, 30.0)
    print("\n" + md)
    starts = list(table.STARTS)
    dol, pi = s[starts[0]]["share_shaft_stiffness"], s[starts[1]]["share_shaft_stiffness"]
    for start in starts:
        assert abs(sum(s[start].values()) - 100.0) < 1e-6, f"{start}: shares do not sum to 100 %"
    assert dol > 0 and pi > 0
    assert dol / pi >= 10.0, f"shaft stiffness share {dol:.3f} % without controller, {pi:.3f} % with PI: only {dol / pi:.1f}x"
    assert "shaft stiffness" in md and f"{pi:.3f}" in md
    # The chapter's printed digits (its Table 3.3, read as table.CHAPTER: motor / shaft / fan): with the
    # book file's values each share of the script's direct-on-line and PI columns rounds to the decimals
    # the chapter prints (44.3 / 9 / 46.7 and 12 / 0.3 / 87.7; the same check against an independent
    # integration is in test_motor_fan_book.py). The references are the chapter's numbers, not a run.
    decimals = {"share_motor_inertia": (1, 0), "share_shaft_stiffness": (0, 1), "share_fan_inertia": (1, 1)}
    for col, start in enumerate(starts[:2]):
        for name, chapter in table.CHAPTER.items():
            d = decimals[name][col]
            got = s[start][name]
            assert round(got, d) == chapter[col], (
                f"{start}, {table.ELEMENTS[name]}: {got:.4f} % rounds to {round(got, d)}, the chapter prints {chapter[col]}")


def test_figure_3_11_fan_inertia_is_the_most_influential(fmus):
    # reference: chapter 3.3.3 (Figure 3.11): "For this problem, the most influential parameter is fan
    # inertia. [...] motor inertia has a small influence on the reducer torque [...] stiffness variation has
    # a very small effect on maximal torque." Response: the peak high-speed shaft torque, level c, PI.
    import fig3_11_oat as oat

    results = oat.sweep(short=False, workers=2)
    sw = oat.swings(results)
    order = oat.ranking(results)
    print(f"\nOAT, PI, nominal peak {sw['nominal']:.1f} N m: " + ", ".join(
        f"{p} {sw['effects'][p]['minus']:+.2f} / {sw['effects'][p]['plus']:+.2f} N m" for p in order))
    assert len(results) == 7
    assert order[0] == "J_fan", f"most influential: {order} ({sw['effects']})"
    # +10 % fan inertia needs more torque to accelerate it along the same ramp: the peak rises
    assert sw["effects"]["J_fan"]["plus"] > 0 > sw["effects"]["J_fan"]["minus"]


def test_figure_3_11_runs_on_a_dask_cluster(fmus, tmp_path):
    distributed = pytest.importorskip("distributed")
    import fig3_11_oat as oat

    # One worker thread (processes=False puts every worker in this process): fmpy changes the
    # process's working directory while it loads an FMU's library and changes back afterwards, so two
    # simulations in threads of one process race (one thread went back into the other's extracted FMU
    # directory, which was then deleted: every later os.getcwd() in this pytest process failed). The
    # example's docstring says the same for real workers (one thread each).
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, protocol="tcp",
                                  dashboard_address=None) as cluster:
        address = cluster.scheduler_address
        assert address.startswith("tcp://")
        assert oat.main(["--short", "--out", str(tmp_path), "--scheduler", address]) == 0
        with oat.dask_client(address) as client:
            on_dask = oat.sweep(short=True, client=client)
    png = tmp_path / "MotorFan_fig3_11_oat.png"
    assert png.is_file() and png.read_bytes()[:8] == PNG_MAGIC
    in_pool = oat.sweep(short=True, workers=2)
    assert [r["name"] for r in on_dask] == [r["name"] for r in in_pool]
    assert [r["peak"] for r in on_dask] == [r["peak"] for r in in_pool], "the Dask and pool sweeps differ"


def test_each_fmu_documentation_shows_its_figures(fmus):
    # build-fmus puts docs/figures/<ModelIdentifier>_*.png into the FMU as documentation/<file> and links
    # each from documentation/index.html (issue 12: "Each FMU's documentation/index.html includes its figure").
    import zipfile

    figures = sorted((REPO_ROOT / "docs" / "figures").glob("*.png"))
    assert figures, "no committed figures in docs/figures (run examples/make_figures.py)"
    models = {p.name.split("_", 1)[0] for p in figures}
    for model in sorted(models):
        fmu = require_fmu(DIST_DIR / f"{model}.fmu")
        with zipfile.ZipFile(fmu) as z:
            names = set(z.namelist())
            html = z.read("documentation/index.html").decode()
        for png in (p.name for p in figures if p.name.startswith(model + "_")):
            assert f"documentation/{png}" in names, f"{fmu.name} lacks documentation/{png}: rebuild with build-fmus"
            assert f'<img src="{png}"' in html, f"{fmu.name}'s index.html does not show {png}"


# Figure 3.13 (chapter 3.3.3): "Figure 3.13 illustrates two different cases, below and above 1.4 Hz, and
# shows the advantage of using a filtered speed set point to avoid resonance mode excitation. In this
# latter case, the effect of the driveshaft elasticity can be neglected when sizing the reducer."
# Criterion for "negligible when sizing": with the set point filtered below 1.4 Hz, the elastic shaft's
# peak torque within 10 % of the rigid shaft's, either way (the first set's test asked only "not more
# than 10 % over"; a rigid model that overstates the peak by far does not size the reducer either, so
# now both ways: this is stricter, and the verdicts are those of the one-sided form, the step fails
# and the ramp holds); and the filter below must excite the shaft less than the one above (largest
# |elastic - rigid|). The chapter does not say
# what went into the filter and the book file has no model of the figure, so both readings are tested:
# a step (this project's since its first set) and the book's own 10 s ramp (Transient_SpeedControler,
# whose filter secondOrder1 the text describes). Neither replaces the other.


def _figure_3_13_verdict(set_point: str):
    import fig3_13_setpoint_filter as fig

    runs = fig.run(short=False, set_point=set_point)
    (elastic, rigid), (elastic_above, rigid_above) = fig.peaks(runs, 1), fig.peaks(runs, 2)
    below, above = fig.elasticity_torque(runs, 1), fig.elasticity_torque(runs, 2)
    print(f"\n{set_point}, filter below: elastic {elastic:.1f} N m, rigid {rigid:.1f} N m ({elastic / rigid - 1:+.1%}); "
          f"elasticity adds {below:.1f} N m; filter above: elastic {elastic_above:.1f} N m, rigid {rigid_above:.1f} N m "
          f"({elastic_above / rigid_above - 1:+.1%}); elasticity adds {above:.1f} N m")
    return elastic, rigid, elastic_above, rigid_above, below, above


def test_figure_3_13_elasticity_negligible_below_resonance_on_the_books_ramp(fmus):
    elastic, rigid, elastic_above, rigid_above, below, above = _figure_3_13_verdict("ramp")
    assert below < above, "the filter below 1.4 Hz must excite the shaft less than the one above"
    assert abs(elastic / rigid - 1) <= 0.10, f"elastic peak {elastic:.0f} N m is {elastic / rigid - 1:+.0%} from the rigid {rigid:.0f} N m"
    # The criterion must tell the two cases apart, or a ramp too slow to excite anything would pass it
    # whatever the filter: above 1.4 Hz the elasticity is not negligible by the same 10 %.
    assert abs(elastic_above / rigid_above - 1) > 0.10, (
        f"filter above 1.4 Hz: elastic {elastic_above:.0f} N m within 10 % of rigid {rigid_above:.0f} N m: "
        "the experiment does not discriminate")


@pytest.mark.xfail(strict=True, reason=(
    "Chapter 3.3.3 / Figure 3.13 with a step set point through the filter (the book's values: PI Kp 10000, "
    "Ki 100000, no torque limit, 800 Hz actuator, 300 rad/s): with the 0.4997 Hz (2*3.14*0.5 rad/s) D = 1 "
    "filter the elastic shaft peaks at 7923 N m against the rigid shaft's 4363 N m (+82 %), the elasticity "
    "adds up to 3858 N m; with the 5 Hz filter 29020 against 43734 N m (-34 %), up to 42817 N m. The filter "
    "below does excite the shaft 11x less, but its step response starts with a step of jerk: the "
    "acceleration rises to 347 rad/s2 within 0.32 s, under half the 0.75 s period of the 1.33 Hz shaft mode "
    "(motor speed imposed), which rings (the set point does it, not the 800 Hz actuator: without it the "
    "elastic peak is the same to 0.1 N m). On the book's 10 s ramp the claim holds (the test above). "
    "Strict: if it ever holds, this XPASS fails and the README must be updated."))
def test_figure_3_13_elasticity_negligible_below_resonance_on_a_step(fmus):
    elastic, rigid, _, _, below, above = _figure_3_13_verdict("step")
    assert below < above, "the filter below 1.4 Hz must excite the shaft less than the one above"
    assert abs(elastic / rigid - 1) <= 0.10, f"elastic peak {elastic:.0f} N m is {elastic / rigid - 1:+.0%} from the rigid {rigid:.0f} N m"
