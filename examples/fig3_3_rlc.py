"""Figure 3.3: the current absorbed by the RLC load, full circuit vs its simplifications.

At low frequency the quasi-static model (L short, C open: i = u / (R_series + R_load)) gives the
absorbed current; at high frequency the R-L model (C short) does; near the circuit's resonance
(~160 Hz with the defaults) neither does. dist/RlcCircuit.fmu computes all three currents.

    .venv/bin/python examples/fig3_3_rlc.py [--short] [--out DIR]
"""

from __future__ import annotations

import sys

import numpy as np

import figures_common as fc

OUTPUTS = ["u_source", "i_absorbed", "i_low_frequency", "i_high_frequency"]
# (title, frequency Hz, periods shown, simplified output, its label)
CASES = [
    ("low frequency", 5.0, 3, "i_low_frequency", "quasi-static (L short, C open)"),
    ("near resonance", 160.0, 6, None, None),
    ("high frequency", 5000.0, 10, "i_high_frequency", "R-L (C short)"),
]


SETTLE = 0.06  # s


def run(short: bool):
    """Each case from rest; the figure shows `periods` periods after SETTLE s (the switch-on transient,
    ~10 ms with the defaults, has died out), as the chapter's steady-state comparison."""
    runs = []
    for title, f, periods, simplified, label in CASES:
        settle = 0.0 if short else SETTLE
        if short:
            periods = 1
        window = periods / f
        h = window / 400
        stop = h * round((settle + window) / h)
        res = fc.simulate("RlcCircuit", stop, h, {"frequency": f}, OUTPUTS)
        res = res[res["time"] >= stop - window - 1e-12]
        runs.append((title, f, simplified, label, res))
    return runs


def mismatch(res, name: str, f: float) -> float:
    """Largest |full - simplified| over the last period shown, in % of the full current's amplitude there."""
    t = res["time"]
    last = t >= t[-1] - 1.0 / f - 1e-12
    full = np.asarray(res["i_absorbed"])
    return 100 * float(np.max(np.abs(full[last] - np.asarray(res[name])[last])) / np.max(np.abs(full[last])))


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    runs = run(args.short)
    fig, axes = fc.plt.subplots(2, len(runs), figsize=(13, 6), sharex="col")
    for col, (title, f, simplified, label, res) in enumerate(runs):
        t_ms = 1e3 * res["time"]
        axes[0, col].plot(t_ms, res["u_source"], color="k")
        axes[0, col].set_title(f"{title}: {f:g} Hz")
        axes[1, col].plot(t_ms, res["i_absorbed"], color="tab:blue", lw=2.5, label="full circuit")
        if simplified:
            axes[1, col].plot(t_ms, res[simplified], color="tab:red", lw=1.2, label=label)
        else:
            axes[1, col].plot(t_ms, res["i_low_frequency"], color="tab:red", lw=1, ls="--", label="quasi-static")
            axes[1, col].plot(t_ms, res["i_high_frequency"], color="tab:green", lw=1, ls=":", label="R-L")
        for name in (["i_low_frequency", "i_high_frequency"] if not simplified else [simplified]):
            print(f"{f:7g} Hz: {name} differs from i_absorbed by up to {mismatch(res, name, f):6.2f} % of its amplitude (last period)")
        axes[1, col].set_xlabel("time (ms)")
    axes[0, 0].set_ylabel("source voltage (V)")
    axes[1, 0].set_ylabel("absorbed current (A)")
    fc.finish(fig, "Figure 3.3: absorbed current, full circuit (blue) vs simplified diagrams (dist/RlcCircuit.fmu)",
              args.out, "RlcCircuit_fig3_3.png", legend_loc="lower left")
    return 0


if __name__ == "__main__":
    sys.exit(main())
