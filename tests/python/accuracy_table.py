"""Accuracy against the tolerance: every Real output of every dist/*.fmu (issue 19).

    .venv/bin/python tests/python/accuracy_table.py [--only MotorFan,ShaftLine]
                                                    [--tolerances 1e-3,1e-4,...] [--reference 1e-10]
                                                    [--workers N] [--no-cache] [--all-outputs]

For each FMU (discovered in dist/, or FMU_DIST_DIR) and each relative tolerance, one Co-Simulation run
in fmpy over the FMU's DefaultExperiment (start and stop time; output_interval = its stepSize, so one
doStep per output row), the tolerance passed to fmi2SetupExperiment. Every Real output with
causality="output" is compared with the same FMU's run at the reference tolerance (1e-10) on the same
rows: the error of an output is max_t |y(t) - y_ref(t)| / scale, where scale is the output's range
over the reference run (max - min; max |y_ref| if that range is 0, 1 if both are 0), reported with the
time where it occurs. The issue's rule is error <= 10 x tol; where the FMU logs that it raised the
tolerance to its documented floor (a message containing "tolerance" and "floor"), the rule is
error <= 10 x max(tol, floor) (test_accuracy.py asserts it).

Runs go to a process pool (fmpy changes the working directory while it loads an FMU, so processes,
not threads) and are cached on disk under target/accuracy-cache/, keyed by the SHA-256 of the FMU file,
the tolerance and the experiment: a rebuilt FMU is simulated again, an unchanged one is not. Wall times
of every run (its own, not from the cache) are printed.

Importable: `sweep`, `simulate`, `compare`, `fmu_paths`, `floor_from_log`.
"""

from __future__ import annotations

import argparse
import hashlib
import math
import multiprocessing
import os
import pickle
import re
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
DIST_DIR = Path(os.environ["FMU_DIST_DIR"]).resolve() if os.environ.get("FMU_DIST_DIR") else REPO / "dist"
CACHE_DIR = REPO / "target" / "accuracy-cache"
# Bump when what a cached run holds changes.
CACHE_FORMAT = 1

TOLERANCES = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
REFERENCE_TOLERANCE = 1e-10
# The rule: error <= RULE_FACTOR x tolerance, as a fraction of the output's range.
RULE_FACTOR = 10.0

# A message saying the FMU raised the master's tolerance to its floor names both values, e.g.
# "tolerance 0.001 is looser than this FMU's floor 1e-06: using 1e-06" (wording not fixed yet).
FLOAT = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
FLOOR_NUMBER = re.compile(r"floor\D{0,40}?(" + FLOAT + ")", re.IGNORECASE)
ANY_NUMBER = re.compile(FLOAT)


@dataclass
class Experiment:
    start: float
    stop: float
    step: float
    tolerance: float | None  # DefaultExperiment's tolerance attribute, if any


@dataclass
class Run:
    fmu: str  # model name (file stem)
    tolerance: float
    time: np.ndarray | None = None
    values: dict[str, np.ndarray] = field(default_factory=dict)
    wall: float = 0.0  # seconds of the simulation itself (when it was run, not read from the cache)
    messages: list[tuple[int, str, str]] = field(default_factory=list)  # (status, category, message)
    failure: str | None = None  # the exception, when the run failed
    cached: bool = False


@dataclass
class OutputError:
    name: str
    error: float  # max |y - y_ref| / scale
    at: float  # time of the worst error
    scale: float
    scale_kind: str  # "range", "max|y|" or "1"


def fmu_paths() -> list[Path]:
    return sorted(DIST_DIR.glob("*.fmu")) if DIST_DIR.is_dir() else []


def experiment_of(md) -> Experiment:
    de = md.defaultExperiment
    if de is None or de.stopTime is None or de.stepSize is None:
        raise ValueError(f"{md.modelName}: no DefaultExperiment with stopTime and stepSize")
    start = float(de.startTime) if de.startTime is not None else 0.0
    tol = float(de.tolerance) if de.tolerance is not None else None
    return Experiment(start, float(de.stopTime), float(de.stepSize), tol)


def real_outputs(md) -> list[str]:
    """The Real outputs two runs are compared on: not the energy balance (power_balance_*), zero up
    to rounding by construction (test_energy_balance.py bounds it against the largest element power)."""
    return [v.name for v in md.modelVariables if v.causality == "output" and v.type == "Real"
            and not v.name.startswith("power_balance_")]


def file_hash(path: Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def floor_messages(messages) -> list[tuple[int, str, str]]:
    """The log records saying a tolerance floor applied: their text names "tolerance" and "floor"."""
    return [m for m in messages if "tolerance" in m[2].lower() and "floor" in m[2].lower()]


def floor_from_log(messages, master_tolerance: float | None = None) -> float | None:
    """The tolerance floor an FMU says it applied, from the first message naming "tolerance" and
    "floor": the number right after the word "floor", else the one number of the message that is
    not the master's tolerance. None when no such message was logged; NaN when one was but its
    floor cannot be told from it."""
    for _status, _category, text in floor_messages(messages):
        m = FLOOR_NUMBER.search(text)
        if m:
            return float(m.group(1))
        numbers = [float(x) for x in ANY_NUMBER.findall(text) if _is_number(x)]
        if master_tolerance is not None:
            numbers = [x for x in numbers if not math.isclose(x, master_tolerance, rel_tol=1e-6)]
        return numbers[0] if len(numbers) == 1 else math.nan
    return None


def _is_number(s: str) -> bool:
    try:
        float(s)
        return True
    except ValueError:
        return False


def _cache_file(digest: str, name: str, tol: float, exp: Experiment) -> Path:
    key = f"{CACHE_FORMAT}|{digest}|{tol!r}|{exp.start!r}|{exp.stop!r}|{exp.step!r}"
    return CACHE_DIR / f"{name}-{hashlib.sha256(key.encode()).hexdigest()[:20]}.pkl"


def simulate(fmu_path: str | Path, tolerance: float, use_cache: bool = True, digest: str | None = None) -> Run:
    """One Co-Simulation run of the FMU's DefaultExperiment at `tolerance`, every Real output
    recorded at each communication point, the FMU's log messages collected."""
    from fmpy import read_model_description, simulate_fmu
    from fmpy.fmi2 import fmi2CallbackLoggerTYPE  # noqa: F401  (fmpy's logger signature)

    fmu_path = Path(fmu_path)
    md = read_model_description(str(fmu_path))
    exp = experiment_of(md)
    names = real_outputs(md)
    run = Run(fmu=fmu_path.stem, tolerance=tolerance)
    cache = None
    if use_cache:
        cache = _cache_file(digest or file_hash(fmu_path), fmu_path.stem, tolerance, exp)
        if cache.is_file():
            try:
                cached = pickle.loads(cache.read_bytes())
                cached.cached = True
                return cached
            except Exception:
                pass
    messages: list[tuple[int, str, str]] = []

    def logger(env, instance_name, status, category, message):
        messages.append((int(status), (category or b"").decode("utf-8", "replace"), (message or b"").decode("utf-8", "replace")))

    t0 = time.perf_counter()
    try:
        result = simulate_fmu(
            str(fmu_path),
            fmi_type="CoSimulation",
            start_time=exp.start,
            stop_time=exp.stop,
            output_interval=exp.step,
            relative_tolerance=tolerance,
            output=names,
            logger=logger,
        )
        run.time = np.asarray(result["time"], dtype=float)
        run.values = {n: np.asarray(result[n], dtype=float) for n in names}
    except Exception as e:  # a failed run is a finding, reported in the table
        run.failure = f"{type(e).__name__}: {e}"
    run.wall = time.perf_counter() - t0
    run.messages = messages
    if cache is not None and run.failure is None:
        CACHE_DIR.mkdir(parents=True, exist_ok=True)
        tmp = cache.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_bytes(pickle.dumps(run))
        tmp.replace(cache)
    return run


def share_classes(md) -> dict[str, tuple[str, ...]]:
    """share_<element> -> the activity outputs of its class, for the runtime's share outputs: a
    storage element's share is 100 A_i / sum of the storage elements' activities, a dissipative
    one's among the dissipative elements (the share's description says which)."""
    outputs = {v.name: v for v in md.modelVariables if v.causality == "output"}
    classes: dict[str, list[str]] = {}
    for name, v in outputs.items():
        if not name.startswith("share_") or f"activity_{name[len('share_'):]}" not in outputs:
            continue
        description = (v.description or "").lower()
        kind = "storage" if "storage elements" in description else "dissipative" if "dissipative elements" in description else None
        if kind is not None:
            classes.setdefault(kind, []).append(name)
    return {share: tuple(f"activity_{s[len('share_'):]}" for s in members) for members in classes.values() for share in members}


def compare(run: Run, reference: Run, bound: float | None = None, shares: dict[str, tuple[str, ...]] | None = None) -> list[OutputError]:
    """Each output's worst error against the reference, as a fraction of its scale.

    With `bound` (the allowed error, a fraction of each output's scale) and `shares`
    (share_classes): a share s_i = 100 A_i / sum A is a ratio of activities, so where the sum is
    still small (just after the start, the states near zero and within their absolute tolerance)
    it inherits its activities' bound, 200 sum_j(bound range(A_j)) / sum_j A_j(t), where that is
    larger than its own (the rule of test_model_exchange.py's derived_bound and
    tests/tests/model_exchange_strict.rs). Its error is then reported scaled to its own bound:
    <= bound exactly where the difference is within the larger of the two at every point."""
    errors = []
    if run.failure or reference.failure:
        return errors
    n = min(len(run.time), len(reference.time))
    t = reference.time[:n]
    for name, ref in reference.values.items():
        y = run.values[name][:n]
        ref = ref[:n]
        span = float(np.max(ref) - np.min(ref))
        if span > 0:
            scale, kind = span, "range"
        elif np.max(np.abs(ref)) > 0:
            scale, kind = float(np.max(np.abs(ref))), "max|y|"
        else:
            scale, kind = 1.0, "1"
        diff = np.abs(y - ref)
        if not np.all(np.isfinite(diff)):
            j = int(np.argmax(~np.isfinite(diff)))
            errors.append(OutputError(name, math.inf, float(t[j]), scale, kind))
            continue
        activities = (shares or {}).get(name)
        if bound is not None and activities and all(a in reference.values for a in activities):
            own = bound * scale
            total = np.sum([reference.values[a][:n] for a in activities], axis=0)
            total_bound = sum(bound * float(np.ptp(reference.values[a][:n])) for a in activities)
            with np.errstate(divide="ignore", invalid="ignore"):
                inherited = np.where(total > 0.0, 200.0 * total_bound / np.where(total > 0.0, total, 1.0), np.inf)
            allowed = np.maximum(own, inherited)
            j = int(np.argmax(diff / allowed))
            if allowed[j] > own:
                kind += f" (bound inherited from its activities there: {allowed[j] / scale:.3g})"
            errors.append(OutputError(name, float(diff[j] / allowed[j]) * bound, float(t[j]), scale, kind))
            continue
        j = int(np.argmax(diff))
        errors.append(OutputError(name, float(diff[j]) / scale, float(t[j]), scale, kind))
    return errors


def _task(args):
    path, tol, use_cache, digest = args
    return simulate(path, tol, use_cache=use_cache, digest=digest)


def sweep(paths=None, tolerances=TOLERANCES, reference=REFERENCE_TOLERANCE, workers: int | None = None, use_cache: bool = True) -> dict[str, dict[float, Run]]:
    """{model: {tolerance: Run}} for every FMU and every tolerance plus the reference. The
    reference runs (the slowest) are submitted first."""
    paths = [Path(p) for p in (fmu_paths() if paths is None else paths)]
    digests = {str(p): file_hash(p) for p in paths}
    tols = [reference] + [t for t in tolerances if t != reference]
    tasks = [(str(p), tol, use_cache, digests[str(p)]) for tol in tols for p in paths]
    workers = workers or min(len(tasks), os.cpu_count() or 1)
    runs: dict[str, dict[float, Run]] = {p.stem: {} for p in paths}

    def reference_reruns():
        # An FMU that tightens the master's tolerance to a floor near (or past) the reference's own
        # tolerance would be compared with itself: its reference is run 100 x tighter than the
        # floor (and kept under the key `reference`; its Run.tolerance says which it is).
        for p in paths:
            by_tol = runs[p.stem]
            floors = [f for t, r in by_tol.items() if (f := floor_from_log(r.messages, t)) is not None and f > 0]
            if floors and min(floors) < 100 * reference:
                yield (str(p), min(floors) / 100, use_cache, digests[str(p)])

    def run_all(mapper):
        for r in mapper(_task, tasks):
            runs[r.fmu][r.tolerance] = r
        for r in mapper(_task, list(reference_reruns())):
            runs[r.fmu][reference] = r

    if workers <= 1:
        run_all(map)
    else:
        # Spawned, not forked: a fork of a process that has FMU libraries loaded (and fmpy's or
        # pytest's threads) copies their state mid-flight; a worker starts clean instead. Every
        # simulation runs in a worker, none in the calling process: fmpy 0.3.32's variadic-logger
        # shim (fmpy/logging/linux64/logging.so, logMessage) appears to keep the last Python logger callback
        # it was given in a global, so after simulate_fmu(..., logger=f) had returned and f was
        # collected, the next FMU that logs through the shim without a logger of its own (the
        # fmucontainer FMU of test_coupled_masters.py, in fmi2Instantiate) jumped to the freed
        # callback: SIGSEGV (gdb: logMessage <- logger_message <- container_configure; with FMUs
        # of any build of ours).
        with ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn")) as pool:
            run_all(pool.map)
    return runs


def allowed(tol: float, floor: float | None) -> float:
    """The issue's bound on an output's error (fraction of its range) at master tolerance `tol`:
    10 x tol, or 10 x max(tol, floor) where the FMU logged that its floor applied (a floor that
    cannot be read from the message leaves the bound at 10 x tol)."""
    effective = tol if floor is None or not (floor > 0) else max(tol, floor)
    return RULE_FACTOR * effective


def fmt(x: float) -> str:
    if x is None:
        return "-"
    if not math.isfinite(x):
        return str(x)
    return f"{x:.2g}" if x != 0 else "0"


def report(runs: dict[str, dict[float, Run]], tolerances, reference: float, all_outputs: bool = True) -> str:
    from fmpy import read_model_description

    lines = []
    # Wall times.
    lines.append("### Wall time of each run (s; 'c' = from the cache, its original time)\n")
    header = ["FMU", f"ref {reference:g}"] + [f"{t:g}" for t in tolerances]
    lines.append("| " + " | ".join(header) + " |")
    lines.append("|" + "---|" * len(header))
    for model, by_tol in runs.items():
        cells = [model]
        for t in [reference, *tolerances]:
            r = by_tol.get(t)
            cells.append("-" if r is None else (f"FAILED" if r.failure else f"{r.wall:.1f}{' c' if r.cached else ''}"))
        lines.append("| " + " | ".join(cells) + " |")
    lines.append("")
    # Failures and floors.
    notes = []
    for model, by_tol in runs.items():
        if reference in by_tol and by_tol[reference].tolerance != reference:
            notes.append(f"- {model}: reference at rtol {by_tol[reference].tolerance:g} (100 x tighter than the tolerance floor it logs)")
        for t, r in by_tol.items():
            if r.failure:
                notes.append(f"- {model} at {t:g}: run failed: {r.failure}")
            fl = floor_from_log(r.messages, t)
            if fl is not None:
                notes.append(f"- {model} at {t:g}: tolerance floor {fl:g} logged")
            warnings = [m for m in r.messages if m[0] >= 1]
            if warnings:
                notes.append(f"- {model} at {t:g}: {len(warnings)} warning(s) logged, first: {warnings[0][2]!r}")
    # Worst output per FMU per tolerance.
    lines.append(f"### Worst output per FMU: max |y - y_ref| / range(y_ref), y_ref at rtol {reference:g} (rule: <= {RULE_FACTOR:g} x tol)\n")
    header = ["FMU"] + [f"{t:g}" for t in tolerances]
    lines.append("| " + " | ".join(header) + " |")
    lines.append("|" + "---|" * len(header))
    per_output: dict[str, dict[str, dict[float, OutputError]]] = {}
    for model, by_tol in runs.items():
        ref = by_tol.get(reference)
        cells = [model]
        per_output[model] = {}
        for t in tolerances:
            r = by_tol.get(t)
            if r is None or ref is None or r.failure or ref.failure:
                cells.append("FAILED" if (r and r.failure) or (ref and ref.failure) else "-")
                continue
            bound = allowed(t, floor_from_log(r.messages, t))
            # Shares are judged as test_accuracy.py judges them: against the bound they inherit
            # from their activities where that is larger (compare).
            errs = compare(r, ref, bound, share_classes(read_model_description(str(DIST_DIR / f"{model}.fmu"))))
            for e in errs:
                per_output[model].setdefault(e.name, {})[t] = e
            if not errs:
                cells.append("no Real output")
                continue
            w = max(errs, key=lambda e: e.error)
            mark = "" if w.error <= bound else " **x**"
            cells.append(f"{fmt(w.error)} {w.name} @{w.at:g}s{mark}")
        lines.append("| " + " | ".join(cells) + " |")
    lines.append("")
    lines.append("**x**: above the rule's bound.\n")
    if all_outputs:
        lines.append("### Every output (error as a fraction of its range, time of the worst error)\n")
        header = ["FMU", "output", "range"] + [f"{t:g}" for t in tolerances]
        lines.append("| " + " | ".join(header) + " |")
        lines.append("|" + "---|" * len(header))
        for model, outs in per_output.items():
            for name, by_tol in outs.items():
                any_e = next(iter(by_tol.values()))
                scale = f"{any_e.scale:.3g}" + ("" if any_e.scale_kind == "range" else f" ({any_e.scale_kind})")
                cells = [model, name, scale]
                for t in tolerances:
                    e = by_tol.get(t)
                    if e is None:
                        cells.append("-")
                        continue
                    bound = allowed(t, floor_from_log(runs[model][t].messages, t))
                    cells.append(f"{fmt(e.error)} @{e.at:g}" + ("" if e.error <= bound else " **x**"))
                lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
    still = [m for m, outs in per_output.items() if outs and all(next(iter(v.values())).scale_kind != "range" for v in outs.values())]
    if still:
        notes.insert(0, f"- every output constant over the reference run (nothing to measure in the default experiment): {', '.join(still)}")
    if notes:
        lines.append("### Notes\n")
        lines.extend(notes)
        lines.append("")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", help="comma-separated model names (file stems in dist/)")
    ap.add_argument("--tolerances", default=",".join(f"{t:g}" for t in TOLERANCES))
    ap.add_argument("--reference", type=float, default=REFERENCE_TOLERANCE)
    ap.add_argument("--workers", type=int, default=None, help="processes (default: the CPU count)")
    ap.add_argument("--no-cache", action="store_true", help=f"simulate everything again (cache: {CACHE_DIR})")
    ap.add_argument("--worst-only", action="store_true", help="only the worst output per FMU, not every output")
    a = ap.parse_args(argv)
    paths = fmu_paths()
    if a.only:
        wanted = set(a.only.split(","))
        paths = [p for p in paths if p.stem in wanted]
    if not paths:
        print(f"no FMU found in {DIST_DIR}: run `cargo run --release -p build-fmus`", file=sys.stderr)
        return 2
    tolerances = tuple(float(x) for x in a.tolerances.split(","))
    t0 = time.perf_counter()
    runs = sweep(paths, tolerances, a.reference, workers=a.workers, use_cache=not a.no_cache)
    wall = time.perf_counter() - t0
    print(report(runs, tolerances, a.reference, all_outputs=not a.worst_only))
    simulated = sum(r.wall for by in runs.values() for r in by.values() if not r.cached)
    print(f"Total wall time {wall:.1f} s ({simulated:.1f} s of simulation in this invocation, "
          f"{sum(r.cached for by in runs.values() for r in by.values())} runs from the cache).")
    return 0


if __name__ == "__main__":
    sys.exit(main())
