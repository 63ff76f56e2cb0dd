"""Figure 3.13: a set point filtered below or above the 1.4 Hz shaft resonance.

dist/MotorFan.fmu at level c under PI control (the FMU's defaults: the book authors' values, their
Transient_SpeedControler) with the speed set point through the second-order filter (D = 1):
setpoint_filter 1 (filter_frequency_below, the book's 2*3.14*0.5 rad/s = 0.4997 Hz) or 2
(filter_frequency_above, 5 Hz). Each is also run with a rigid shaft (keep_shaft_stiffness = false,
dashed): the difference is what the shaft's elasticity adds. The chapter: below 1.4 Hz the resonance
is not excited and the elasticity can be neglected when sizing the reducer.

Two set points go into the filter (the chapter does not say which its figure used; the book file
has no model for it):
* a step to 300 rad/s (ramp_time = 0; the top two rows: speed and torque), this project's reading
  since its first parameter set: the filter alone shapes the set point;
* the book's own 10 s ramp to 300 rad/s (the default ramp_time; bottom row), the set point of
  Transient_SpeedControler, whose filter secondOrder1 is the one the chapter's text describes.

    .venv/bin/python examples/fig3_13_setpoint_filter.py [--short] [--out DIR]
"""

from __future__ import annotations

import sys

import numpy as np

import figures_common as fc

OUTPUTS = ["shaft_torque", "motor_speed", "speed_reference"]
FILTERS = {1: "filter_frequency_below", 2: "filter_frequency_above"}
# set point -> (the start values it sets besides the filter, s drawn)
SET_POINTS = {"step": ({"ramp_time": 0.0}, 8.0), "ramp": ({}, 15.0)}


def run(short: bool, set_point: str = "step") -> dict:
    """{(setpoint_filter, elastic shaft?): result} for the step (default) or the book's 10 s ramp."""
    extra, _ = SET_POINTS[set_point]
    return {
        (f, stiff): fc.motor_fan({"level": fc.LEVEL["c"], "start_mode": fc.PI_CONTROL, **extra,
                                  "setpoint_filter": f, "keep_shaft_stiffness": stiff}, OUTPUTS, short)
        for f in FILTERS for stiff in (True, False)
    }


def elasticity_torque(runs: dict, f: int) -> float:
    """Largest |shaft torque, elastic - rigid| (N m): the torque the shaft's elasticity adds."""
    return float(np.max(np.abs(np.asarray(runs[(f, True)]["shaft_torque"]) - np.asarray(runs[(f, False)]["shaft_torque"]))))


def peaks(runs: dict, f: int) -> tuple[float, float]:
    """(elastic, rigid) peak |shaft torque| (N m) with filter f."""
    return fc.peak_abs(runs[(f, True)], "shaft_torque"), fc.peak_abs(runs[(f, False)], "shaft_torque")


def _torque_panel(ax, runs: dict, f: int, shown_s: float) -> None:
    for stiff, style in fc.SHAFT_STYLE.items():
        res = runs[(f, stiff)]
        shown = res["time"] <= shown_s + 1e-9
        label = ("elastic" if stiff else "rigid") + f" shaft: peak {fc.peak_abs(res, 'shaft_torque'):.0f} N m"
        ax.plot(res["time"][shown], np.asarray(res["shaft_torque"])[shown], label=label, **style)


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    runs = {sp: run(args.short, sp) for sp in SET_POINTS}
    ramp_time = fc.start_value("MotorFan", "ramp_time")
    fig, axes = fc.plt.subplots(3, 2, figsize=(12, 10))
    for col, (f, name) in enumerate(FILTERS.items()):
        hz = fc.start_value("MotorFan", name)
        where = "below" if f == 1 else "above"
        step, ramp = runs["step"], runs["ramp"]
        shown_step, shown_ramp = SET_POINTS["step"][1], SET_POINTS["ramp"][1]
        for stiff, style in fc.SHAFT_STYLE.items():
            res = step[(f, stiff)]
            shown = res["time"] <= shown_step + 1e-9
            axes[0, col].plot(res["time"][shown], np.asarray(res["motor_speed"])[shown],
                              label=f"motor speed, {'elastic' if stiff else 'rigid'} shaft", **style)
        res = step[(f, True)]
        shown = res["time"] <= shown_step + 1e-9
        axes[0, col].plot(res["time"][shown], np.asarray(res["speed_reference"])[shown], "k:", lw=1, label="filtered set point")
        axes[0, col].set_title(f"step set point filtered at {hz:.4g} Hz ({where} 1.4 Hz)", fontsize=10)
        axes[0, col].set_ylabel("speed (rad/s)")
        _torque_panel(axes[1, col], step, f, shown_step)
        axes[1, col].set_title(f"step: elasticity adds up to {elasticity_torque(step, f):.0f} N m", fontsize=10)
        _torque_panel(axes[2, col], ramp, f, shown_ramp)
        axes[2, col].set_title(f"the book's {ramp_time:g} s ramp, same filter: elasticity adds up to "
                               f"{elasticity_torque(ramp, f):.0f} N m", fontsize=10)
        for row in (1, 2):
            axes[row, col].set_ylabel("torque, high-speed axis (N m)")
        for row in range(3):
            axes[row, col].set_xlabel("time (s)")
        for sp, r in runs.items():
            el, rg = peaks(r, f)
            print(f"{sp:>4}, filter {hz:.4g} Hz: peak shaft torque elastic {el:8.1f} N m, rigid {rg:8.1f} N m "
                  f"({100 * (el / rg - 1):+.1f} %); largest |elastic - rigid| {elasticity_torque(r, f):8.1f} N m")
    fc.finish(fig, "Figure 3.13: spectral content of the speed set point (dist/MotorFan.fmu, level c, PI)",
              args.out, "MotorFan_fig3_13_setpoint_filter.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
