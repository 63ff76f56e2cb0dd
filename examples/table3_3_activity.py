"""Table 3.3: activity index shares of the storage elements, with and without a speed controller.

dist/MotorFan.fmu at level c (elastic shaft): the activity of each storage element (eq. 3.3, the
integral of |power| through it) over the run, as a share of their sum (`share_*` outputs at the end
of the run), with the FMU's defaults (the book authors' values): direct-on-line (no controller; the
book file's Activity_Index_direct), PI controller and inverse simulation (the 10 s ramp of
Transient_SpeedControler), and the PI controller on the 20 s ramp of the book file's
Activity_Index_controller. Printed, written as markdown (MotorFan_table3_3.md) and drawn as bars
(MotorFan_table3_3.png).

    .venv/bin/python examples/table3_3_activity.py [--short] [--out DIR]
"""

from __future__ import annotations

import sys

import numpy as np

import figures_common as fc

ELEMENTS = {"share_motor_inertia": "motor inertia", "share_shaft_stiffness": "shaft stiffness",
            "share_fan_inertia": "fan inertia"}
# column -> the start values it sets (besides level c); the first three are the chapter's comparison
STARTS = {"without controller (direct-on-line)": {"start_mode": fc.DIRECT_ON_LINE},
          "PI controller": {"start_mode": fc.PI_CONTROL},
          "inverse simulation": {"start_mode": fc.INVERSE},
          "PI controller, 20 s ramp (Activity_Index_controller)": {"start_mode": fc.PI_CONTROL, "ramp_time": 20.0}}
# The chapter's Table 3.3 (without / with controller). Its rows carry no labels in the text we have;
# this reading puts the fan inertia first and the motor inertia last (with the controller the fan's
# share grows, the motor's falls) and the shaft stiffness in the middle (the text: its share "decreases
# particularly starting with an electronic speed controller"). With the book file's values the FMU gives
# these digits in this order (direct start and the 10 s PI start), which confirms the reading.
CHAPTER = {"share_motor_inertia": (44.3, 12.0), "share_shaft_stiffness": (9.0, 0.3), "share_fan_inertia": (46.7, 87.7)}


def shares(short: bool) -> dict:
    """{start: {share name: % at the end of the run}}"""
    out = {}
    for start, values in STARTS.items():
        res = fc.motor_fan({"level": fc.LEVEL["c"], **values}, list(ELEMENTS), short)
        out[start] = {name: float(res[name][-1]) for name in ELEMENTS}
    return out


def _pct(v: float) -> str:
    """A share in %: two decimals, three below 1 % (the chapter's 0.3 % against ours)."""
    return f"{v:.3f}" if abs(v) < 1 else f"{v:.2f}"


def markdown(s: dict, horizon: float) -> str:
    starts = list(s)
    lines = [f"Activity shares (%), dist/MotorFan.fmu level c, {horizon:g} s "
             "(examples/table3_3_activity.py); last column: the chapter's Table 3.3", "",
             "| element | " + " | ".join(starts) + " | chapter: without / with controller |",
             "|---|" + "---|" * (len(starts) + 1)]
    for name, label in ELEMENTS.items():
        lines.append(f"| {label} | " + " | ".join(_pct(s[st][name]) for st in starts)
                     + f" | {CHAPTER[name][0]} / {CHAPTER[name][1]} |")
    dol, pi = s[starts[0]]["share_shaft_stiffness"], s[starts[1]]["share_shaft_stiffness"]
    inv, pi20 = s[starts[2]]["share_shaft_stiffness"], s[starts[3]]["share_shaft_stiffness"]
    lines += ["", f"Shaft stiffness share: {dol:.2f} % without controller, {pi:.3f} % with the PI controller "
              f"({dol / pi:.1f}x lower), {inv:.3f} % with inverse simulation ({dol / inv:.1f}x lower), "
              f"{pi20:.3f} % with the PI controller on the 20 s ramp ({dol / pi20:.1f}x lower); "
              f"chapter: 9 % -> 0.3 % (30x)."]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    s = shares(args.short)
    horizon = 3.0 if args.short else fc.MOTOR_FAN_HORIZON
    md = markdown(s, horizon)
    print(md)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "MotorFan_table3_3.md").write_text(md)
    print(f"wrote {args.out / 'MotorFan_table3_3.md'}")

    fig, ax = fc.plt.subplots(figsize=(11, 5))
    columns = list(s) + ["chapter, without controller", "chapter, with controller"]
    values = [[s[st][n] for n in ELEMENTS] for st in s] + [[CHAPTER[n][k] for n in ELEMENTS] for k in (0, 1)]
    x = np.arange(len(ELEMENTS))
    width = 0.8 / len(columns)
    for i, (col, vals) in enumerate(zip(columns, values)):
        bars = ax.bar(x + (i - (len(columns) - 1) / 2) * width, vals, width, label=col,
                      hatch="//" if col.startswith("chapter") else None, alpha=0.6 if col.startswith("chapter") else 1)
        ax.bar_label(bars, fmt="%.3g", fontsize=7)
    ax.set_xticks(x, list(ELEMENTS.values()))
    ax.set_ylabel("share of the total activity (%)")
    fc.finish(fig, f"Table 3.3: activity index shares, level c, {horizon:g} s (dist/MotorFan.fmu; hatched: the chapter)",
              args.out, "MotorFan_table3_3.png", legend_loc="upper left")
    return 0


if __name__ == "__main__":
    sys.exit(main())
