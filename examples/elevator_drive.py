"""Figure 3.16.b: the elevator drive (chopper, DC motor, cable drum) going up and down.

A 1200 kg cabin against a 1000 kg counterweight: the duty cycle steps to +0.5 (up) or -0.5 (down)
at t = 0 from rest. Going up the DC bus delivers the power that lifts the 200 kg of unbalance and
heats the armature; going down the unbalance drives the motor, which returns power to the bus
through the chopper (its supply current reverses). The steady states agree with the hand balance
I = r (m_cabin - m_cw) g / k and v = r (alpha U_dc - R I) / k. dist/ElevatorDrive.fmu, the model the
README's tutorial writes.

    .venv/bin/python examples/elevator_drive.py [--short] [--out DIR]
"""

from __future__ import annotations

import sys

import numpy as np

import figures_common as fc

OUTPUTS = ["v", "height", "motor_current", "supply_current", "activity_dc_bus", "activity_unbalance", "activity_armature_resistance"]
CASES = [("up, duty cycle +0.5", 0.5, "tab:blue"), ("down, duty cycle -0.5", -0.5, "tab:red")]


def steady_by_hand(duty: float) -> tuple[float, float]:
    """(motor current A, cabin speed m/s) at steady speed, from the FMU's declared defaults."""
    s = {n: fc.start_value("ElevatorDrive", n) for n in ("supply_voltage", "R", "k", "drum_radius", "m_cabin", "m_counterweight")}
    current = s["drum_radius"] * (s["m_cabin"] - s["m_counterweight"]) * 9.80665 / s["k"]
    return current, s["drum_radius"] * (duty * s["supply_voltage"] - s["R"] * current) / s["k"]


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    stop, h = (0.5, 0.01) if args.short else (1.5, 0.002)
    u_dc = fc.start_value("ElevatorDrive", "supply_voltage")
    fig, axes = fc.plt.subplots(3, 1, figsize=(9, 9), sharex=True)
    for label, duty, color in CASES:
        res = fc.simulate("ElevatorDrive", stop, h, {"duty_cycle": duty}, OUTPUTS)
        t = res["time"]
        axes[0].plot(t, res["v"], color=color, label=label)
        axes[1].plot(t, res["motor_current"], color=color)
        axes[2].plot(t, 1e-3 * u_dc * np.asarray(res["supply_current"]), color=color)
        i_hand, v_hand = steady_by_hand(duty)
        print(f"{label}: at {t[-1]:g} s v = {res['v'][-1]:.6f} m/s (hand {v_hand:.6f}), I = {res['motor_current'][-1]:.6f} A (hand {i_hand:.6f}); "
              f"bus delivered {1e-3 * res['activity_dc_bus'][-1]:.2f} kJ of activity, unbalance {1e-3 * res['activity_unbalance'][-1]:.2f} kJ, "
              f"armature R {1e-3 * res['activity_armature_resistance'][-1]:.2f} kJ")
    axes[0].set_ylabel("cabin speed (m/s)")
    axes[1].set_ylabel("motor current (A)")
    axes[2].set_ylabel("DC bus power (kW)")
    axes[2].set_xlabel("time (s)")
    for ax in axes:
        ax.axhline(0.0, color="0.6", lw=0.8)
    fc.finish(fig, "Figure 3.16.b: elevator drive, 1200 kg cabin against 1000 kg (dist/ElevatorDrive.fmu)",
              args.out, "ElevatorDrive_ride.png", legend_loc="center right")
    return 0


if __name__ == "__main__":
    sys.exit(main())
