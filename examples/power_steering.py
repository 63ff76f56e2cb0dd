"""Section 3.4.2: the electric power steering parking, with and without its assistance.

The book's mission (Chap6_Steering.mo: one steering-wheel turn each way at 1/16 Hz, the car at
rest, the treads sliding on the ground) through dist/PowerSteering.fmu: the driver's torque with
the assistance (gain 4, active damping) and without it (the motor's current held at 0, the worm
back-driven), the rack force and the assistance motor's current.

    .venv/bin/python examples/power_steering.py [--short] [--out DIR]
"""

from __future__ import annotations

import sys

import numpy as np

import figures_common as fc

OUTPUTS = ["driver_torque", "rack_force", "wheel_angle", "motor_current"]
CASES = [("assisted (gain 4)", {}, "tab:blue"), ("without assistance", {"assist_gain": 0.0, "assist_damping": 0.0}, "tab:red")]


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    stop, h = (2.0, 0.01) if args.short else (16.0, 0.005)
    fig, axes = fc.plt.subplots(3, 1, figsize=(9, 9), sharex=True)
    for label, start_values, color in CASES:
        res = fc.simulate("PowerSteering", stop, h, start_values, OUTPUTS)
        t = res["time"]
        axes[0].plot(t, res["driver_torque"], color=color, label=label)
        axes[1].plot(t, 1e-3 * np.asarray(res["rack_force"]), color=color)
        axes[2].plot(t, res["motor_current"], color=color)
        print(f"{label}: peak driver torque {fc.peak_abs(res, 'driver_torque'):.3f} N m, peak rack force {fc.peak_abs(res, 'rack_force'):.0f} N, "
              f"peak wheel angle {np.degrees(fc.peak_abs(res, 'wheel_angle')):.1f} deg, peak motor current {fc.peak_abs(res, 'motor_current'):.1f} A")
    axes[0].set_ylabel("driver's torque (N m)")
    axes[1].set_ylabel("rack force (kN)")
    axes[2].set_ylabel("motor current (A)")
    axes[2].set_xlabel("time (s)")
    fc.finish(fig, "Section 3.4.2: parking with the electric power steering (dist/PowerSteering.fmu)", args.out, "PowerSteering_parking.png",
              legend_loc="upper right")
    return 0


if __name__ == "__main__":
    sys.exit(main())
