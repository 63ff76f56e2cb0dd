"""Section 3.5.1: the TGV V150 traction motor's winding temperature, one- and two-node models.

dist/TractionMotorThermal.fmu with its defaults, the book file's values
(Chap3_TGV_Modelisation_Thermique.mo), from a cold motor (40 C), a step of the Joule losses at t = 0
(P_joule_step): 5 kW in normal service and 10 kW for the record, as the book file's two runs, for
nodes = 1 (the whole motor at one temperature) and nodes = 2 (winding and iron core). The dotted line is the 180 C insulation limit;
the time at which each winding reaches it (the FMU's time_to_limit) is the chapter's question 6.

    .venv/bin/python examples/tgv_thermal.py [--short] [--out DIR]
"""

from __future__ import annotations

import sys

import numpy as np

import figures_common as fc

OUTPUTS = ["T_winding", "T_iron", "time_to_limit", "limit_reached"]
HORIZON = 10000.0  # s, the FMU's DefaultExperiment (the book file's)
POWERS = {"5 kW rated": 5e3, "10 kW record": 1e4}
NODES = {1: "one-node", 2: "two-node"}


def run(short: bool) -> dict:
    stop, h = (600.0, 20.0) if short else (HORIZON, 20.0)
    return {(n, p): fc.simulate_checked("TractionMotorThermal", stop, h, {"nodes": n, "P_joule_step": w}, OUTPUTS)
            for n in NODES for p, w in POWERS.items()}


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    runs = run(args.short)
    limit = fc.start_value("TractionMotorThermal", "T_insulation_limit") - 273.15
    fig, axes = fc.plt.subplots(1, 2, figsize=(13, 5), sharey=True)
    colors = {"5 kW rated": "tab:blue", "10 kW record": "tab:red"}
    for col, (n, title) in enumerate(NODES.items()):
        ax = axes[col]
        for p in POWERS:
            res = runs[(n, p)]
            t_min = np.asarray(res["time"]) / 60
            reached = bool(res["limit_reached"][-1] > 0.5)
            when = f"reaches {limit:.0f} C at {float(res['time_to_limit'][-1]) / 60:.1f} min" if reached else f"stays below {limit:.0f} C"
            ax.plot(t_min, np.asarray(res["T_winding"]) - 273.15, color=colors[p], lw=2, label=f"{p}: winding, {when}")
            if n == 2:
                ax.plot(t_min, np.asarray(res["T_iron"]) - 273.15, color=colors[p], lw=1, ls="--", label=f"{p}: iron core")
            if reached:
                ax.axvline(float(res["time_to_limit"][-1]) / 60, color=colors[p], lw=0.6, ls=":")
            print(f"{title:>9}, {p:>13}: winding at {float(res['time'][-1]):.0f} s {float(res['T_winding'][-1]) - 273.15:7.2f} C, {when}")
        ax.axhline(limit, color="k", ls=":", lw=1, label=f"insulation limit {limit:.0f} C")
        ax.set_title(f"{title} model", fontsize=10)
        ax.set_xlabel("time (min)")
    axes[0].set_ylabel("temperature (C)")
    fc.finish(fig, "Section 3.5.1: V150 traction motor from cold, Joule losses stepped at t = 0 (the book file's values; dist/TractionMotorThermal.fmu)",
              args.out, "TractionMotorThermal_heating.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
