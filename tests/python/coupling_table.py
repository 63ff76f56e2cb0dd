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
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import coupled_masters as cm  # noqa: E402

REPO = HERE.parents[1]


def label(step: float) -> str:
    return f"{step * 1e3:g} ms"


def cell(c: cm.Comparison) -> str:
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

    # The FMUs' and the container's log lines go to stdout at the C level: send them to stderr while
    # simulating, so that stdout is the table alone.
    sys.stdout.flush()
    saved_stdout = os.dup(1)
    os.dup2(2, 1)
    cells: dict[tuple[str, float], str] = {}
    seconds: dict[tuple[str, float], str] = {}
    windows: dict[float, float] = {}
    rated = None
    for step in steps:
        stop = args.stop_time
        if args.short_window and step < 1e-3 - 1e-12:
            stop = min(stop, args.short_window)
        windows[step] = stop
        ref = cm.monolithic(mono_fmu, step, stop)
        for master in masters:
            t0 = time.perf_counter()
            try:
                run = cm.MASTERS[master](ssp, step, stop)
            except cm.MasterFailed as e:  # e.g. an FMU refuses a step once the coupling diverges
                cells[(master, step)] = str(e).splitlines()[0][:90]
                seconds[(master, step)] = f"{time.perf_counter() - t0:.1f}"
                print(f"  {master:32s} {label(step):>7s}: failed: {e}", file=sys.stderr)
                continue
            c = cm.compare(run, ref)
            rated = rated or c.rated
            cells[(master, step)] = cell(c)
            seconds[(master, step)] = f"{run.seconds:.1f}"
            print(f"  {master:32s} {label(step):>7s}: fan {c.fan_error_pct:8.3f} % at {c.worst_time:6.3f} s, "
                  f"peak {c.peak:7.1f} vs {c.peak_reference:7.1f} N m ({c.peak_error_pct:+7.2f} %), "
                  f"{run.seconds:6.1f} s", file=sys.stderr)

    sys.stdout.flush()
    os.dup2(saved_stdout, 1)
    os.close(saved_stdout)

    def head(s: float) -> str:
        return label(s) + ("" if windows[s] == args.stop_time else f" (0-{windows[s]:g} s)")

    header = "| master | " + " | ".join(head(s) for s in steps) + " |"
    rule = "|---" * (len(steps) + 1) + "|"
    print(f"MotorFanSystem, direct-on-line start, 0-{args.stop_time:g} s, against MotorFan.fmu (level c) "
          f"at the same communication step.")
    print(f"Each cell: max fan-speed error, % of rated ({rated:.3f} rad/s) / peak |shaft torque| error, %. "
          f"Acceptance at 1 ms: 0.5 % / 3 %.\n")
    print(header)
    print(rule)
    for master in masters:
        print(f"| {cm.SCHEMES.get(master, master)} | " + " | ".join(cells.get((master, s), "-") for s in steps) + " |")
    merged, below = ([], "") if args.no_rust else rust_rows(len(steps) + 1)
    for row in merged:
        print(row)
    print("\nWall time of the simulation alone, s:\n")
    print(header)
    print(rule)
    for master in masters:
        print(f"| {master} | " + " | ".join(seconds.get((master, s), "-") for s in steps) + " |")
    if below:
        print("\n" + below)
    return 0


if __name__ == "__main__":
    sys.exit(main())
