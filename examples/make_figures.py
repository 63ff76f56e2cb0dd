"""Every figure and table of the chapter from the FMUs in dist/, into docs/figures/ (or --out DIR).

    cargo run --release -p build-fmus          # the FMUs, into dist/
    .venv/bin/python examples/make_figures.py  # every figure (./test.sh makes .venv)

Each script also runs alone (examples/<script>.py [--short] [--out DIR]); `--short` is a short
horizon, for the tests.
"""

from __future__ import annotations

import importlib
import sys
import time

import figures_common as fc

SCRIPTS = [
    "fig3_3_rlc",
    "fig3_6_levels",
    "fig3_8_variable_speed",
    "fig3_10_shaft_stiffness",
    "fig3_11_oat",
    "fig3_13_setpoint_filter",
    "table3_3_activity",
    "tgv_thermal",
    "torque_sensor",
    "shaft_line_short_circuit",
    "elevator_drive",
    "power_steering",
    "eha_flight_control",
    "booster_nozzle",
    "mems_accelerometer",
    "common_rail",
]


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    passed = (["--short"] if args.short else []) + ["--out", str(args.out)]
    for name in SCRIPTS:
        t0 = time.perf_counter()
        print(f"== {name}")
        rc = importlib.import_module(name).main(passed)
        if rc:
            print(f"{name} failed ({rc})", file=sys.stderr)
            return rc
        print(f"   {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
