"""Accuracy follows the tolerance, every output included (issue 19).

The rule: for every dist/*.fmu, at every relative tolerance from 1e-3 to 1e-8 that a master passes to
fmi2SetupExperiment, every Real output's largest error against the same FMU at rtol 1e-10 is within
10 x tol of the output's range (max - min over the reference run); where the FMU logs that it raised
the tolerance to its documented floor (a message naming "tolerance" and "floor", and both values),
within 10 x max(tol, floor) of its range. (A floor tighter than tol leaves the bound at 10 x tol: a
tightened run must meet the master's tolerance; one looser than tol, i.e. an FMU that cannot be more
accurate than its floor, relaxes it. A run tightened to a floor within 100 x of the reference's
tolerance is compared with a reference 100 x tighter than that floor, not with itself.)

How: accuracy_table.sweep (Co-Simulation in fmpy over each FMU's DefaultExperiment, output_interval =
its stepSize; the same runs as `python tests/python/accuracy_table.py`, which prints the whole table).
All 6 tolerances and the reference of every FMU are run, not a subset: the sweep takes about 15 s of
wall time on 2 cores (63 runs, ShaftLine's 60 000 doSteps the longest at 2-5 s each), once per session,
and a rerun of an unchanged FMU reads its runs from target/accuracy-cache/.

A share of the activities (share_<element>, 100 A_i / sum A) inherits the bound of its activities
where that is larger than its own: just after the start, the activities are integrals of powers of
states still within their absolute tolerance, and their ratio carries that (accuracy_table.compare).

An output that does not move over the default experiment (DriveShaft's and Fan's, whose inputs stay
0) is compared on the scale max |y_ref| (or 1), so that it must not move either.
"""

from __future__ import annotations

import functools
import math
import os
import time

import pytest
from fmpy import read_model_description

import accuracy_table as at
from conftest import DIST_DIR, require_fmu


@functools.lru_cache(maxsize=None)
def sweep() -> tuple[dict, float]:
    """Every FMU of dist/ at every tolerance and the reference, once per session (wall time too)."""
    t0 = time.perf_counter()
    runs = at.sweep(at.fmu_paths(), at.TOLERANCES, at.REFERENCE_TOLERANCE, workers=os.cpu_count())
    wall = time.perf_counter() - t0
    print(f"\naccuracy sweep: {sum(len(v) for v in runs.values())} runs of {len(runs)} FMUs in {wall:.1f} s wall time")
    return runs, wall


def runs_of(fmu_path) -> dict:
    require_fmu(fmu_path)
    runs, _ = sweep()
    assert fmu_path.stem in runs, f"{fmu_path.name} was not in the sweep of {DIST_DIR}"
    return runs[fmu_path.stem]


def declared_tolerance(fmu_path) -> float | None:
    de = read_model_description(str(fmu_path)).defaultExperiment
    return None if de is None or de.tolerance is None else float(de.tolerance)


def test_default_experiment_declares_a_tolerance(fmu_path):
    """Each FMU states the tolerance it is meant to run at (DefaultExperiment tolerance="...")."""
    tol = declared_tolerance(fmu_path)
    assert tol is not None and 0 < tol < 1, f"{fmu_path.name}: DefaultExperiment has no tolerance in (0, 1): {tol}"


@pytest.mark.parametrize("tol", at.TOLERANCES, ids=[f"rtol{t:g}" for t in at.TOLERANCES])
def test_every_output_within_ten_times_the_tolerance(fmu_path, tol):
    by_tol = runs_of(fmu_path)
    ref, run = by_tol[at.REFERENCE_TOLERANCE], by_tol[tol]
    assert ref.failure is None, f"{fmu_path.name}: the reference run at rtol {at.REFERENCE_TOLERANCE:g} failed: {ref.failure}"
    assert run.failure is None, f"{fmu_path.name} at rtol {tol:g}: the run failed: {run.failure}"

    floor = at.floor_from_log(run.messages, tol)
    notes = [f"{fmu_path.name} at rtol {tol:g}: DefaultExperiment tolerance {declared_tolerance(fmu_path)}"]
    if floor is not None:
        record = at.floor_messages(run.messages)[0]
        notes.append(f"floor {floor:g} logged (status {record[0]}): {record[2]!r}")
        # The floor message names both values: the master's tolerance and the floor.
        numbers = [float(x) for x in at.ANY_NUMBER.findall(record[2]) if at._is_number(x)]
        assert math.isfinite(floor) and floor > 0, f"the floor cannot be read from {record[2]!r}"
        assert any(math.isclose(x, tol, rel_tol=1e-6) for x in numbers), f"the floor message does not name the master's tolerance {tol:g}: {record[2]!r}"
        if floor < tol and floor < 100 * at.REFERENCE_TOLERANCE:
            # Tightened to a floor near (or past) the reference's own tolerance, the run would be
            # compared with itself: the reference is then run 100 x tighter than the floor.
            # accuracy_table.sweep has made it so.
            assert ref.tolerance <= floor / 100 * (1 + 1e-9), f"{fmu_path.name}: the reference ran at {ref.tolerance:g}, not 100 x tighter than the floor {floor:g}"
            notes.append(f"reference at rtol {ref.tolerance:g} (100 x tighter than the floor)")
    ref_floor = at.floor_from_log(ref.messages, ref.tolerance)
    if ref_floor is not None:
        notes.append(f"the reference run at rtol {ref.tolerance:g} too logged a floor ({ref_floor:g})")
    bound = at.allowed(tol, floor)

    errors = at.compare(run, ref, bound, at.share_classes(read_model_description(str(fmu_path))))
    assert errors, f"{fmu_path.name}: no Real output compared"
    too_large = [e for e in errors if not e.error <= bound]
    print("; ".join(notes) + f"; worst {max(errors, key=lambda e: e.error).name} {max(e.error for e in errors):.2g} (bound {bound:.2g})")
    if too_large:
        pytest.fail(
            "; ".join(notes)
            + f"\n{len(too_large)} of {len(errors)} outputs beyond {bound:.3g} of their range (10 x {'max(tol, floor)' if floor is not None else 'tol'}):\n"
            + "\n".join(f"  {e.name}: {e.error:.3g} of its {e.scale_kind} {e.scale:.4g}, at t = {e.at:g} s" for e in sorted(too_large, key=lambda e: -e.error)),
            pytrace=False,
        )


def test_floor_parsing():
    """The floor is read from the message whichever way it is worded."""
    rec = lambda text: [(1, "logStatusWarning", text)]  # noqa: E731
    assert at.floor_from_log(rec("tolerance 0.001 is looser than this FMU's floor 1e-06: using 1e-06"), 1e-3) == 1e-6
    assert at.floor_from_log(rec("tolerance floor 2e-7 applies (the master asked for 1e-10)"), 1e-10) == 2e-7
    assert at.floor_from_log(rec("relative tolerance 1e-3 tightened to 1e-5 (documented floor)"), 1e-3) == 1e-5
    assert at.floor_from_log(rec("the tolerance is fine"), 1e-3) is None
    assert math.isnan(at.floor_from_log(rec("tolerance floor applied"), 1e-3))
    assert at.allowed(1e-3, None) == pytest.approx(1e-2)
    assert at.allowed(1e-8, 1e-6) == pytest.approx(1e-5)
    assert at.allowed(1e-3, 1e-6) == pytest.approx(1e-2)
