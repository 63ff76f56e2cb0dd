"""Section 3.5.3: the submarine shaft line's short circuit, full and reduced models.

dist/ShaftLine.fmu with its defaults, the book file's case (Chap3_Submarine.mo: 0 -> 700 V in
50 s, plateau, short circuit at t = 100 s, 150 s in all): shaft torque over rated torque, armature
current, motor and propeller speeds, for the full model (model_reduction = 0), the book's reduced
model (1: no motor inertia, rigid shaft, seal and bearings kept) and the one that keeps the elements
with 95 % of the short-circuit activity (2). The chapter's question: how large is the transient
shaft torque after the short circuit, and does a reduced model predict it?

    .venv/bin/python examples/shaft_line_short_circuit.py [--short] [--out DIR]
"""

from __future__ import annotations

import sys

import numpy as np

import figures_common as fc

OUTPUTS = ["shaft_torque_ratio", "armature_current", "motor_speed", "propeller_speed", "supply_voltage"]
SHORT_CIRCUIT = 100.0  # s (the FMU's ramp_time + plateau_time defaults, the book file's)
MODELS = {
    0: ("full model", dict(color="tab:red", lw=1.5)),
    1: ("book's reduced model", dict(color="tab:blue", lw=1.5, ls="--")),
    2: ("activity-reduced model", dict(color="tab:green", lw=1.2, ls=":")),
}


def run(short: bool) -> dict:
    # The short run still crosses the short circuit, with a coarse output step.
    stop, h = (120.0, 0.5) if short else (150.0, 0.02)
    return {m: fc.simulate_checked("ShaftLine", stop, h, {"model_reduction": m}, OUTPUTS) for m in MODELS}


ZOOM = (98.0, 130.0)  # s: the transient after the short circuit


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    runs = run(args.short)
    fig, axes = fc.plt.subplots(2, 2, figsize=(13, 8))
    (ax_torque, ax_zoom), (ax_speed, ax_current) = axes
    for m, (label, style) in MODELS.items():
        res = runs[m]
        t = np.asarray(res["time"])
        after = t >= SHORT_CIRCUIT
        ratio = np.asarray(res["shaft_torque_ratio"])
        i_peak = int(np.argmax(np.abs(np.where(after, ratio, 0.0))))
        ax_torque.plot(t, ratio, label=label, **style)
        ax_zoom.plot(t, ratio, label=f"{label}: peak {ratio[i_peak]:.2f} x rated at {t[i_peak]:.1f} s", **style)
        ax_speed.plot(t, np.asarray(res["propeller_speed"]), label=f"{label}: propeller", **style)
        ax_current.plot(t, np.asarray(res["armature_current"]) / 1e3, label=label, **style)
        print(f"{label:>13}: peak shaft torque after the short circuit {ratio[i_peak]:+.3f} x rated at t = {t[i_peak]:.2f} s")
    full = runs[0]
    ax_speed.plot(full["time"], full["motor_speed"], color="tab:orange", lw=0.8, label="full model: motor")
    for ax in (ax_zoom, ax_current):
        ax.set_xlim(*ZOOM)
    ax_torque.set_title("the whole run: ramp, plateau, short circuit", fontsize=10)
    ax_zoom.set_title("the transient after the short circuit", fontsize=10)
    ax_torque.set_ylabel("shaft torque / rated torque")
    ax_zoom.set_ylabel("shaft torque / rated torque")
    ax_speed.set_ylabel("speed (rad/s)")
    ax_current.set_ylabel("armature current (kA)")
    for ax in axes.flat:
        ax.set_xlabel("time (s)")
        ax.axvline(SHORT_CIRCUIT, color="k", lw=0.6, ls=":")
    fc.finish(fig, "Section 3.5.3: shaft line, short circuit at t = 100 s (book file's case; dist/ShaftLine.fmu)", args.out,
              "ShaftLine_short_circuit.png", legend_loc="best")
    return 0


if __name__ == "__main__":
    sys.exit(main())
