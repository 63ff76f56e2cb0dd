"""Prints the README's coupling table: MotorFanSystem's direct-on-line start run by each external
co-simulation master at communication steps of 10 ms, 1 ms and 0.1 ms, against the monolithic
MotorFan.fmu (level=3, start_mode=1) run by fmpy at the same step.

    .venv/bin/python tests/python/coupling_table.py [--steps 1e-2,1e-3,1e-4] [--stop-time 30]
                                                    [--window-0.1ms SECONDS] [--no-rust]

Each cell: the largest fan-speed error over the common output points, in % of the rated fan speed
(the monolithic final fan speed), and the error of the peak |shaft torque|, in % of the monolithic
peak. How each master's output rows are aligned: coupled_masters.py. The Rust master's rows come from
`cargo run --release -p fmi-host --example coupling_table` when that example exists (run from the
repository root; its table rows are merged when they have the same columns, else its output is
printed below). Needs dist/ built (`cargo run --release -p build-fmus`) and, for ecospy, Debian's
libtbb12 (./test.sh installs it).

`measure` and `print_tables` are system-independent (they take the system's coupled and monolithic
runners and how to turn a pair of runs into a cell); `main` is MotorFanSystem's table, the README's.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import coupled_masters as cm  # noqa: E402

REPO = HERE.parents[1]


def label(step: float) -> str:
    return f"{step * 1e3:g} ms"


def cell(c: cm.Comparison) -> str:
    """MotorFanSystem's cell: fan-speed error, % of rated / peak |shaft torque| error, %."""
    if not (c.fan_error_pct <= 100.0):  # also NaN
        return f"diverges ({c.fan_error_pct:.3g} / {c.peak_error_pct:+.3g})"
    return f"{c.fan_error_pct:.2f} / {c.peak_error_pct:+.2f}"


def rust_rows(columns: int) -> tuple[list[str], str]:
    """(rows to merge, text to print below) from the Rust master's example, if it exists."""
    if not (REPO / "tests" / "examples" / "coupling_table.rs").exists():
        return [], ""
    cmd = ["cargo", "run", "--release", "-q", "-p", "fmi-host", "--example", "coupling_table"]
    proc = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True)
    if proc.returncode != 0:
        return [], f"`{' '.join(cmd)}` failed ({proc.returncode}):\n{proc.stderr[-2000:]}"
    rows = []
    for line in proc.stdout.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if not line.lstrip().startswith("|") or set("".join(cells)) <= set("-: "):
            continue
        if cells[0].lower().startswith("master"):
            continue
        rows.append(line.strip())
    if rows and all(r.count("|") == columns + 1 for r in rows):
        return rows, ""
    return [], "Rust master (`" + " ".join(cmd) + "`), as it prints:\n\n" + proc.stdout


# ---------------------------------------------------------------------------------------------
# The system-independent core: run every master at every step against the monolithic reference

@contextlib.contextmanager
def stdout_to_stderr():
    """The FMUs' and the container's log lines go to stdout at the C level: send them to stderr while
    simulating, so that stdout is the table alone."""
    sys.stdout.flush()
    saved_stdout = os.dup(1)
    os.dup2(2, 1)
    try:
        yield
    finally:
        sys.stdout.flush()
        os.dup2(saved_stdout, 1)
        os.close(saved_stdout)


@dataclass
class Measured:
    cells: dict[tuple[str, float], str]  # (master, step) -> the evaluation's cell, or why the master failed
    seconds: dict[tuple[str, float], str]  # (master, step) -> wall time of the simulation, s
    windows: dict[float, float]  # step -> end of the simulated window, s


def measure(masters: Sequence[str], steps: Sequence[float], stop_time: float, short_window: float | None,
            coupled: Callable[[str, float, float], cm.Run], reference: Callable[[float, float], cm.Run],
            evaluate: Callable[[cm.Run, cm.Run], tuple[str, str]]) -> Measured:
    """coupled(master, step, stop) for every master and step (0-`short_window` s only at steps
    below 1 ms, if given) against reference(step, stop); evaluate(run, reference) gives the cell and
    the figures logged to stderr."""
    m = Measured({}, {}, {})
    for step in steps:
        stop = stop_time
        if short_window and step < 1e-3 - 1e-12:
            stop = min(stop, short_window)
        m.windows[step] = stop
        ref = reference(step, stop)
        for master in masters:
            t0 = time.perf_counter()
            try:
                run = coupled(master, step, stop)
            except cm.MasterFailed as e:  # e.g. an FMU refuses a step once the coupling diverges
                m.cells[(master, step)] = str(e).splitlines()[0][:90]
                m.seconds[(master, step)] = f"{time.perf_counter() - t0:.1f}"
                print(f"  {master:32s} {label(step):>7s}: failed: {e}", file=sys.stderr)
                continue
            m.cells[(master, step)], figures = evaluate(run, ref)
            m.seconds[(master, step)] = f"{run.seconds:.1f}"
            print(f"  {master:32s} {label(step):>7s}: {figures}, {run.seconds:6.1f} s", file=sys.stderr)
    return m


def table(steps: Sequence[float], head: Callable[[float], str], rows: Sequence[tuple[str, Sequence[str]]]) -> list[str]:
    """A Markdown table: a column per step, a row per (first cell, cells)."""
    lines = ["| master | " + " | ".join(head(s) for s in steps) + " |", "|---" * (len(steps) + 1) + "|"]
    return lines + [f"| {first} | " + " | ".join(cells) + " |" for first, cells in rows]


def print_tables(m: Measured, masters: Sequence[str], steps: Sequence[float], stop_time: float,
                 extra_rows: Sequence[str] = ()) -> None:
    """The error table (a row per master, named by cm.SCHEMES, then `extra_rows` as they are) and
    the wall-time table."""
    def head(s: float) -> str:
        return label(s) + ("" if m.windows[s] == stop_time else f" (0-{m.windows[s]:g} s)")

    for line in table(steps, head, [(cm.SCHEMES.get(master, master), [m.cells.get((master, s), "-") for s in steps])
                                    for master in masters]):
        print(line)
    for row in extra_rows:
        print(row)
    print("\nWall time of the simulation alone, s:\n")
    for line in table(steps, head, [(master, [m.seconds.get((master, s), "-") for s in steps]) for master in masters]):
        print(line)


# ---------------------------------------------------------------------------------------------
# MotorFanSystem against MotorFan.fmu

def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--steps", default="1e-2,1e-3,1e-4", help="communication steps, s (comma-separated)")
    p.add_argument("--stop-time", type=float, default=30.0, help="end of the simulated window, s")
    p.add_argument("--window-0.1ms", dest="short_window", type=float, default=None,
                   help="simulate only this many seconds at steps below 1 ms (the peak is in the first 3 s)")
    p.add_argument("--masters", default=",".join(cm.MASTERS), help="which masters (comma-separated)")
    p.add_argument("--dist", type=Path, default=REPO / "dist")
    p.add_argument("--no-rust", action="store_true", help="do not run the Rust master's example")
    args = p.parse_args()

    steps = [float(s) for s in args.steps.split(",")]
    masters = [m.strip() for m in args.masters.split(",")]
    ssp, mono_fmu = args.dist / "MotorFanSystem.ssp", args.dist / "MotorFan.fmu"
    for f in (ssp, mono_fmu):
        if not f.exists():
            sys.exit(f"{f} is missing: run `cargo run --release -p build-fmus` first")

    rated = None

    def evaluate(run: cm.Run, ref: cm.Run) -> tuple[str, str]:
        nonlocal rated
        c = cm.compare(run, ref)
        rated = rated or c.rated
        return cell(c), (f"fan {c.fan_error_pct:8.3f} % at {c.worst_time:6.3f} s, "
                         f"peak {c.peak:7.1f} vs {c.peak_reference:7.1f} N m ({c.peak_error_pct:+7.2f} %)")

    with stdout_to_stderr():
        m = measure(masters, steps, args.stop_time, args.short_window,
                    lambda master, step, stop: cm.motor_fan_coupled(master, ssp, step, stop),
                    lambda step, stop: cm.motor_fan_reference(mono_fmu, step, stop), evaluate)

    print(f"MotorFanSystem, direct-on-line start, 0-{args.stop_time:g} s, against MotorFan.fmu (level c) "
          f"at the same communication step.")
    print(f"Each cell: max fan-speed error, % of rated ({rated:.3f} rad/s) / peak |shaft torque| error, %. "
          f"Acceptance at 1 ms: 0.5 % / 3 %.\n")
    merged, below = ([], "") if args.no_rust else rust_rows(len(steps) + 1)
    print_tables(m, masters, steps, args.stop_time, merged)
    if below:
        print("\n" + below)
    return 0


if __name__ == "__main__":
    sys.exit(main())
