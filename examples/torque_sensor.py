"""Section 3.5.2: the magnetic torque sensor's output against the applied torque.

dist/TorqueSensor.fmu under a slow torque ramp from -full scale to +full scale (torque_in = -8 N m
plus the built-in ramp of 16 N m), for both arrangements (1: ring A is the bridge's reference arm;
2: differential). Left: the raw demodulated voltage (question 9: offset and curvature); right: the
conditioned output torque_measured against the applied torque, and its error.

    .venv/bin/python examples/torque_sensor.py [--short] [--out DIR]
"""

from __future__ import annotations

import sys

import numpy as np

import figures_common as fc

OUTPUTS = ["torque_applied", "u_demodulated", "torque_measured"]
ARRANGEMENTS = {1: "reference arm A", 2: "differential"}
SETTLE = 0.02  # s at -full scale before the ramp (the 200 Hz filter settles)


def run(short: bool) -> dict:
    fs = fc.start_value("TorqueSensor", "torque_full_scale")
    ramp = 0.05 if short else 1.0
    h = 1e-4
    stop = h * round((SETTLE + ramp) / h)
    start = {"torque_in": -fs, "torque_profile": 2, "torque_profile_height": 2 * fs,
             "torque_profile_start": SETTLE, "torque_profile_duration": ramp}
    return {a: fc.simulate_checked("TorqueSensor", stop, h, {**start, "arrangement": a}, OUTPUTS) for a in ARRANGEMENTS}


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    runs = run(args.short)
    fs = fc.start_value("TorqueSensor", "torque_full_scale")
    fig, (ax_u, ax_m, ax_e) = fc.plt.subplots(1, 3, figsize=(15, 4.8))
    for a, name in ARRANGEMENTS.items():
        res = runs[a]
        ramping = np.asarray(res["time"]) >= SETTLE
        torque = np.asarray(res["torque_applied"])[ramping]
        u = np.asarray(res["u_demodulated"])[ramping]
        measured = np.asarray(res["torque_measured"])[ramping]
        ax_u.plot(torque, u, lw=1.5, label=f"arrangement {a}: {name}")
        ax_m.plot(torque, measured, lw=1.5, label=f"arrangement {a}: {name}")
        steady = np.asarray(res["time"])[ramping] >= SETTLE + 0.005  # past the filter's response to the ramp's start
        err = 100 * np.max(np.abs(measured - torque)[steady]) / fs
        ax_e.plot(torque[steady], 100 * (measured - torque)[steady] / fs, lw=1.2, label=f"arrangement {a}: largest {err:.2f} % of full scale")
        print(f"arrangement {a} ({name}): u_demodulated from {u[0]:+.4f} V to {u[-1]:+.4f} V; "
              f"|torque_measured - torque| up to {err:.2f} % of full scale during the ramp (includes the 200 Hz filter's lag)")
    ax_m.plot([-fs, fs], [-fs, fs], "k:", lw=1, label="ideal")
    ax_u.set_xlabel("applied torque (N m)")
    ax_u.set_ylabel("raw demodulated voltage (V)")
    ax_u.set_title("raw output (u_demodulated)", fontsize=10)
    ax_m.set_xlabel("applied torque (N m)")
    ax_m.set_ylabel("torque_measured (N m)")
    ax_m.set_title("conditioned output", fontsize=10)
    ax_e.set_xlabel("applied torque (N m)")
    ax_e.set_ylabel("error (% of full scale)")
    ax_e.set_title("conditioned - applied torque (filter lag included)", fontsize=10)
    fc.finish(fig, f"Section 3.5.2: torque sensor under a {'short' if args.short else '1 s'} ramp over +-{fs:g} N m "
              "(dist/TorqueSensor.fmu)", args.out, "TorqueSensor_characteristic.png", legend_loc="best")
    return 0


if __name__ == "__main__":
    sys.exit(main())
