"""Figure 3.6: torque and speed on the reducer's high-speed axis at modelling levels a, b and c.

Direct-on-line start of dist/MotorFan.fmu with its defaults (the book authors' file
Chap3_CoolingTowerFan.mo). a: quasi-static (Steady_State); b: + motor and fan inertias
(Transient_Dynamic); c: + driveshaft stiffness (Transient_Resonance); the motor is the book's
torque-speed table at a-c. Level d (the book's induction machine with its electrical dynamics),
which the chapter does not plot, is drawn thin and grey: the README compares its peak with level c's.

    .venv/bin/python examples/fig3_6_levels.py [--short] [--out DIR]
"""

from __future__ import annotations

import sys

import numpy as np

import figures_common as fc

OUTPUTS = ["shaft_torque", "fan_speed", "motor_speed"]
STYLE = {"a": dict(color="tab:green", lw=2), "b": dict(color="tab:blue", lw=1.6),
         "c": dict(color="tab:red", lw=1.2), "d": dict(color="0.55", lw=0.8)}
SHOWN = 12.0  # s of the 30 s run drawn (the run-up takes ~8 s; the rest is the steady state)


def run(short: bool) -> dict:
    return {lv: fc.motor_fan({"level": fc.LEVEL[lv], "start_mode": fc.DIRECT_ON_LINE}, OUTPUTS, short) for lv in "abcd"}


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    runs = run(args.short)
    n = fc.start_value("MotorFan", "gear_ratio")
    fig, (ax_w, ax_t) = fc.plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    for lv, res in runs.items():
        t = res["time"]
        shown = t <= SHOWN + 1e-9
        peak = fc.peak_abs(res, "shaft_torque")
        when = float(t[int(np.argmax(np.abs(res["shaft_torque"])))])
        if lv == "a":  # quasi-static: the steady state throughout
            label = f"level a: {peak:.0f} N m throughout (quasi-static)"
        else:
            label = f"level {lv}: peak {peak:.0f} N m at {when:.2f} s" + ("  (the book's induction machine; not in the chapter's figure)" if lv == "d" else "")
        # speed on the reducer's high-speed axis: its input shaft turns at N w_fan
        ax_w.plot(t[shown], n * np.asarray(res["fan_speed"])[shown], label=label, **STYLE[lv])
        ax_t.plot(t[shown], np.asarray(res["shaft_torque"])[shown], label=label, **STYLE[lv])
        print(f"level {lv}: peak shaft torque {peak:8.1f} N m at {when:.3f} s, at {res['time'][-1]:.0f} s: "
              f"{float(res['shaft_torque'][-1]):7.1f} N m, {n * float(res['fan_speed'][-1]):7.2f} rad/s")
    ax_w.set_ylabel("speed, high-speed axis (rad/s)")
    ax_t.set_ylabel("torque, high-speed axis (N m)")
    ax_t.set_xlabel("time (s)")
    ax_w.legend(fontsize=8, loc="lower right")  # the speed panel's empty corner (the torques fill theirs)
    fc.finish(fig, "Figure 3.6: direct-on-line start at levels a, b, c (dist/MotorFan.fmu, the book file's values)", args.out,
              "MotorFan_fig3_6_levels.png", legend_loc=None)
    return 0


if __name__ == "__main__":
    sys.exit(main())
