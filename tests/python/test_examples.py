"""The chapter's figures (examples/): every script runs on a short horizon and writes its files,
and the chapter's two reduction findings are checked on the full-length FMU runs.

* Every example script runs alone, as a user would (`python examples/<script>.py --short --out DIR`),
  all at once in subprocesses; each must exit 0 and write its PNG (and Table 3.3's markdown), non-empty.
* examples/make_figures.py (the one command) lists every script.
* Table 3.3 (chapter 3.3.2): the shaft stiffness' share of the activity falls by >= 10x with the PI
  controller (level c, 30 s runs of dist/MotorFan.fmu).
* Figure 3.11 (chapter 3.3.3): under speed control the one-at-a-time +-10 % sweep finds fan inertia the
  most influential parameter on the peak shaft torque (30 s runs, in the script's process pool).
* The Dask path of the sweep: the script with `--scheduler ADDRESS` against an in-process
  dask.distributed LocalCluster on tcp (worker threads in this process: the client, the upload of the
  modules and the scattered FMU bytes are exercised, separate worker machines are not); its results
  equal the process pool's.
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
    assert "shaft stiffness" in md and f"{pi:.2f}" in md


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


@pytest.mark.xfail(strict=True, reason=(
    "Chapter 3.3.3 / Figure 3.13: with the set point filtered below 1.4 Hz 'the effect of the driveshaft "
    "elasticity can be neglected when sizing the reducer'. Measured (level c, PI, step set point through the "
    "0.5 Hz filter, 30 s): elastic shaft peak 2756 N m vs rigid 2324 N m (+19 %), elasticity adds up to 1211 N m; "
    "with the 5 Hz filter 3959 vs 2316 N m (+71 %), up to 2138 N m. The 0.5 Hz filter does cut the shaft's "
    "part by 43 %, but the PI controller's torque still rises within ~0.2 s (and saturates at T_limit), a "
    "torque step that excites the 3.9 Hz two-inertia mode: the filter only shapes the set point. We report this "
    "rather than retune the controller."))
def test_figure_3_13_elasticity_negligible_below_resonance(fmus):
    # reference: chapter 3.3.3 (Figure 3.13). Criterion for "negligible when sizing": the elastic shaft's
    # peak torque within 10 % of the rigid shaft's, with the set point filtered below 1.4 Hz.
    import fig3_13_setpoint_filter as fig

    runs = fig.run(short=False)
    elastic = float(max(abs(runs[(1, True)]["shaft_torque"])))
    rigid = float(max(abs(runs[(1, False)]["shaft_torque"])))
    below, above = fig.elasticity_torque(runs, 1), fig.elasticity_torque(runs, 2)
    print(f"\nfilter below: elastic {elastic:.0f} N m, rigid {rigid:.0f} N m; elasticity adds {below:.0f} N m "
          f"(above: {above:.0f} N m)")
    assert below < above, "the filter below 1.4 Hz must excite the shaft less than the one above"
    assert elastic <= 1.10 * rigid, f"elastic peak {elastic:.0f} N m is {elastic / rigid - 1:+.0%} over the rigid {rigid:.0f} N m"
