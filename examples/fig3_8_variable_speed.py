"""Figure 3.8: variable-speed start, a 10 s speed ramp, PI controller vs inverse simulation.

dist/MotorFan.fmu at level c (elastic shaft) with its defaults, the book authors' Transient_SpeedControler
(book file Chap3_CoolingTowerFan.mo): 0 -> 300 rad/s in 10 s through the 0.5 Hz (2*3.14*0.5 rad/s),
D = 1 set-point filter; start_mode 2 (the PI controller, Kp 10000, Ki 100000, drives the motor torque
through the 800 Hz torque actuator) and 3 (inverse simulation: the motor speed is imposed). The direct-on-line start's peak is printed
for comparison (the chapter: "the maximal torque applied to the reducer has a much lower value").

    .venv/bin/python examples/fig3_8_variable_speed.py [--short] [--out DIR]
"""

from __future__ import annotations

import sys

import numpy as np

import figures_common as fc

OUTPUTS = ["shaft_torque", "motor_torque", "motor_speed", "speed_reference"]
SHOWN = 15.0  # s drawn (the 10 s ramp and what follows)


def run(short: bool) -> dict:
    level_c = fc.LEVEL["c"]
    return {
        "PI controller": fc.motor_fan({"level": level_c, "start_mode": fc.PI_CONTROL}, OUTPUTS, short),
        "inverse simulation": fc.motor_fan({"level": level_c, "start_mode": fc.INVERSE}, OUTPUTS, short),
        "direct-on-line": fc.motor_fan({"level": level_c, "start_mode": fc.DIRECT_ON_LINE}, OUTPUTS, short),
    }


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    runs = run(args.short)
    dol_peak = fc.peak_abs(runs.pop("direct-on-line"), "shaft_torque")
    fig, (ax_w, ax_t) = fc.plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    style = {"PI controller": dict(color="tab:blue", lw=2.4), "inverse simulation": dict(color="tab:orange", lw=1.0)}
    for name, res in runs.items():
        t = res["time"]
        shown = t <= SHOWN + 1e-9
        peak = fc.peak_abs(res, "shaft_torque")
        ax_w.plot(t[shown], np.asarray(res["motor_speed"])[shown], label=f"{name}: motor speed", **style[name])
        ax_t.plot(t[shown], np.asarray(res["shaft_torque"])[shown], label=f"{name}: shaft torque, peak {peak:.0f} N m", **style[name])
        print(f"{name:>18}: peak shaft torque {peak:7.1f} N m ({dol_peak / peak:.1f}x below the direct-on-line start's "
              f"{dol_peak:.0f} N m), peak motor torque {fc.peak_abs(res, 'motor_torque'):7.1f} N m")
    res = runs["PI controller"]
    shown = res["time"] <= SHOWN + 1e-9
    ax_w.plot(res["time"][shown], np.asarray(res["speed_reference"])[shown], "k:", lw=1, label="set point (10 s ramp through the 0.5 Hz filter)")
    diff = np.max(np.abs(np.asarray(runs["PI controller"]["shaft_torque"]) - np.asarray(runs["inverse simulation"]["shaft_torque"])))
    print(f"largest shaft-torque difference PI vs inverse simulation: {diff:.1f} N m")
    ax_w.set_ylabel("motor speed (rad/s)")
    ax_t.set_ylabel("torque, high-speed axis (N m)")
    ax_t.set_xlabel("time (s)")
    ax_t.set_title(f"direct-on-line start at the same level c: peak {dol_peak:.0f} N m", fontsize=9)
    fc.finish(fig, "Figure 3.8: progressive start within 10 s, PI vs inverse simulation (dist/MotorFan.fmu, level c)",
              args.out, "MotorFan_fig3_8_variable_speed.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
