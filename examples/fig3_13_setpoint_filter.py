"""Figure 3.13: a set point filtered below or above the 1.4 Hz shaft resonance.

dist/MotorFan.fmu at level c under PI control with a step set point (ramp_time = 0) through the
second-order filter: setpoint_filter 1 (filter_frequency_below, 0.5 Hz) or 2 (filter_frequency_above,
5 Hz). Each is also run with a rigid shaft (keep_shaft_stiffness = false, dashed): the difference
is what the shaft's elasticity adds. The chapter: below 1.4 Hz the resonance is not excited and the
elasticity can be neglected when sizing the reducer.

    .venv/bin/python examples/fig3_13_setpoint_filter.py [--short] [--out DIR]
"""

from __future__ import annotations

import sys

import numpy as np

import figures_common as fc

OUTPUTS = ["shaft_torque", "motor_speed", "speed_reference"]
FILTERS = {1: "filter_frequency_below", 2: "filter_frequency_above"}
SHOWN = 8.0


def run(short: bool) -> dict:
    return {
        (f, stiff): fc.motor_fan({"level": fc.LEVEL["c"], "start_mode": fc.PI_CONTROL, "ramp_time": 0.0,
                                  "setpoint_filter": f, "keep_shaft_stiffness": stiff}, OUTPUTS, short)
        for f in FILTERS for stiff in (True, False)
    }


def elasticity_torque(runs: dict, f: int) -> float:
    """Largest |shaft torque, elastic - rigid| (N m): the torque the shaft's elasticity adds."""
    return float(np.max(np.abs(np.asarray(runs[(f, True)]["shaft_torque"]) - np.asarray(runs[(f, False)]["shaft_torque"]))))


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    runs = run(args.short)
    fig, axes = fc.plt.subplots(2, 2, figsize=(12, 7), sharex=True)
    for col, (f, name) in enumerate(FILTERS.items()):
        hz = fc.start_value("MotorFan", name)
        el = elasticity_torque(runs, f)
        for stiff, style in fc.SHAFT_STYLE.items():
            res = runs[(f, stiff)]
            t = res["time"]
            shown = t <= SHOWN + 1e-9
            label = ("elastic" if stiff else "rigid") + f" shaft: peak {fc.peak_abs(res, 'shaft_torque'):.0f} N m"
            axes[0, col].plot(t[shown], np.asarray(res["motor_speed"])[shown], label="motor speed, " + label, **style)
            axes[1, col].plot(t[shown], np.asarray(res["shaft_torque"])[shown], label=label, **style)
        res = runs[(f, True)]
        shown = res["time"] <= SHOWN + 1e-9
        axes[0, col].plot(res["time"][shown], np.asarray(res["speed_reference"])[shown], "k:", lw=1, label="filtered set point")
        axes[0, col].set_title(f"set point filtered at {hz:g} Hz ({'below' if f == 1 else 'above'} 1.4 Hz): "
                               f"elasticity adds up to {el:.0f} N m", fontsize=10)
        print(f"filter {hz:g} Hz: peak shaft torque elastic {fc.peak_abs(runs[(f, True)], 'shaft_torque'):7.1f} N m, rigid "
              f"{fc.peak_abs(runs[(f, False)], 'shaft_torque'):7.1f} N m; largest |elastic - rigid| {el:7.1f} N m")
        axes[1, col].set_xlabel("time (s)")
    axes[0, 0].set_ylabel("speed (rad/s)")
    axes[1, 0].set_ylabel("torque, high-speed axis (N m)")
    fc.finish(fig, "Figure 3.13: spectral content of the speed set point (dist/MotorFan.fmu, level c, PI)",
              args.out, "MotorFan_fig3_13_setpoint_filter.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
