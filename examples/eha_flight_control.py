"""Figure 3.16.a: the EHA of an aileron, level 1 (ideal transformers, rigid oil) against level 2 (the
oil's compressibility and the leakage across the piston).

dist/EhaFlightControl.fmu with its defaults: a 10 degree step of the surface command at 0.1 s, back
at 0.6 s, the position loop saturating the motor at the 270 V bus. The chapter's question: what does
the hydraulic stiffness mode (the surface on its oil columns, ~58 Hz) do to the surface's position
response? Top: the surface angle, and level 2 less level 1; bottom: the pump's differential
pressure, and a zoom on its ringing after the step.

    .venv/bin/python examples/eha_flight_control.py [--short] [--out DIR]
"""

from __future__ import annotations

import sys

import numpy as np

import figures_common as fc

OUTPUTS = ["surface_angle", "surface_angle_command", "pump_pressure", "motor_current"]
LEVELS = {
    1: ("level 1: ideal transformers, rigid oil", dict(color="tab:blue", lw=2.2)),
    2: ("level 2: oil compressibility and leakage", dict(color="tab:red", lw=1.0)),
}
ZOOM = (0.095, 0.25)  # s: the step's slew and the ringing after it


def run(short: bool) -> dict:
    stop, h = (0.3, 1e-3) if short else (1.0, 1e-4)
    return {level: fc.simulate_checked("EhaFlightControl", stop, h, {"level": level}, OUTPUTS) for level in LEVELS}


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    runs = run(args.short)
    fig, axes = fc.plt.subplots(2, 2, figsize=(13, 8))
    (ax_angle, ax_diff), (ax_dp, ax_zoom) = axes
    t1 = np.asarray(runs[1]["time"])
    ax_angle.plot(t1, np.degrees(runs[1]["surface_angle_command"]), color="k", lw=0.8, ls=":", label="command")
    for level, (label, style) in LEVELS.items():
        res = runs[level]
        t = np.asarray(res["time"])
        theta = np.degrees(np.asarray(res["surface_angle"]))
        dp = np.asarray(res["pump_pressure"]) / 1e6
        ax_angle.plot(t, theta, label=label, **style)
        ax_dp.plot(t, dp, label=f"{label}: {dp.min():.1f} .. {dp.max():.1f} MPa", **style)
        ax_zoom.plot(t, dp, label=label, **style)
        print(f"level {level}: surface {theta.max():.3f} deg at most, pump pressure {dp.min():.2f} .. {dp.max():.2f} MPa, "
              f"|i| <= {np.max(np.abs(res['motor_current'])):.1f} A")
    diff = np.degrees(np.asarray(runs[2]["surface_angle"]) - np.asarray(runs[1]["surface_angle"]))
    ax_diff.plot(t1, diff, color="tab:purple", lw=1.0, label="level 2 - level 1")
    ax_zoom.set_xlim(*ZOOM)
    ax_angle.set_ylabel("surface angle (deg)")
    ax_diff.set_ylabel("surface angle difference (deg)")
    ax_dp.set_ylabel("pump differential pressure (MPa)")
    ax_zoom.set_ylabel("pump differential pressure (MPa)")
    ax_angle.set_title("surface response: the levels agree to a fraction of the step", fontsize=10)
    ax_diff.set_title("the difference: the leakage's steady error, a ripple at the mode", fontsize=10)
    ax_dp.set_title("pressure: level 2 rings at the hydraulic mode", fontsize=10)
    ax_zoom.set_title("zoom on the step: the ~58 Hz oil-column mode", fontsize=10)
    for ax in axes.flat:
        ax.set_xlabel("time (s)")
    fc.finish(fig, "Figure 3.16.a: EHA of an aileron, 10 deg step and return (dist/EhaFlightControl.fmu)", args.out,
              "EhaFlightControl_levels.png", legend_loc="best")
    return 0


if __name__ == "__main__":
    sys.exit(main())
