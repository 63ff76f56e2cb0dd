"""Figure 3.10: torque and speed with and without the driveshaft stiffness.

dist/MotorFan.fmu at level c with keep_shaft_stiffness = true (elastic shaft) and false (the
reduced model: a rigid shaft, inertias only), for the direct-on-line start and the PI start, with the
FMU's defaults (the book authors' values; the PI start is their Transient_SpeedControler and its rigid
twin Transient_SpeedControlerRigid: a 10 s ramp to 300 rad/s through the 0.5 Hz filter).
The chapter: speed profiles superimpose; without the stiffness the oscillations disappear.

    .venv/bin/python examples/fig3_10_shaft_stiffness.py [--short] [--out DIR]
"""

from __future__ import annotations

import sys

import numpy as np

import figures_common as fc

OUTPUTS = ["shaft_torque", "fan_speed"]
# start -> (start_mode, s drawn): the direct start's run-up takes ~8 s, the PI start's ramp 10 s
STARTS = {"direct-on-line": (fc.DIRECT_ON_LINE, 12.0), "PI controller, 10 s ramp": (fc.PI_CONTROL, 15.0)}


def run(short: bool) -> dict:
    return {
        (start, stiff): fc.motor_fan({"level": fc.LEVEL["c"], "start_mode": mode, "keep_shaft_stiffness": stiff}, OUTPUTS, short)
        for start, (mode, _) in STARTS.items() for stiff in (True, False)
    }


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    runs = run(args.short)
    n = fc.start_value("MotorFan", "gear_ratio")
    fig, axes = fc.plt.subplots(2, 2, figsize=(12, 7), sharex="col")
    for col, (start, (_, shown_s)) in enumerate(STARTS.items()):
        for stiff, style in fc.SHAFT_STYLE.items():
            res = runs[(start, stiff)]
            t = res["time"]
            shown = t <= shown_s + 1e-9
            label = ("with" if stiff else "without") + f" shaft stiffness: peak {fc.peak_abs(res, 'shaft_torque'):.0f} N m"
            axes[0, col].plot(t[shown], n * np.asarray(res["fan_speed"])[shown], label=label, **style)
            axes[1, col].plot(t[shown], np.asarray(res["shaft_torque"])[shown], label=label, **style)
        a, b = runs[(start, True)], runs[(start, False)]
        gap = n * np.abs(np.asarray(a["fan_speed"]) - np.asarray(b["fan_speed"]))
        dw, when = float(np.max(gap)), float(a["time"][int(np.argmax(gap))])
        print(f"{start:>25}: peak shaft torque with stiffness {fc.peak_abs(a, 'shaft_torque'):7.1f} N m, without "
              f"{fc.peak_abs(b, 'shaft_torque'):7.1f} N m; largest speed difference (high-speed axis, N w_fan) {dw:.2f} rad/s "
              f"at {when:.2f} s")
        axes[0, col].set_title(f"{start} (largest speed difference {dw:.1f} rad/s)", fontsize=10)
        axes[1, col].set_xlabel("time (s)")
    axes[0, 0].set_ylabel("speed, high-speed axis N w_fan (rad/s)")
    axes[1, 0].set_ylabel("torque, high-speed axis (N m)")
    fc.finish(fig, "Figure 3.10: with and without the driveshaft stiffness (dist/MotorFan.fmu, level c)",
              args.out, "MotorFan_fig3_10_shaft_stiffness.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
