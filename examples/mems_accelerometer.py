"""Figure 3.14: the MEMS accelerometer, its response, its bandwidth, its pull-in and the dominant effect
of each part (question 2).

dist/MemsAccelerometer.fmu with its defaults (an ADXL-class sensor: a 0.29 ug polysilicon proof mass on
folded beams at 24 kHz, 1 um sense gaps, a charge amplifier, a 1 kHz two-pole filter, 19 mV/g).
Top left: a 10 g step, the proof mass's displacement and the output voltage. Top right: the frequency
response, simulated sines against the linearised transfer function, the mechanics alone and with the
read-out filter; the bandwidth marked. Bottom left: pull-in, the bias on one electrode ramped slowly
past V_pi = sqrt(8 k g^3 / (27 eps A)) with the carrier off, against the static balance. Bottom right:
each element's share of the activity (eq. 3.3) in the measurement band and in the step's ringing.

    .venv/bin/python examples/mems_accelerometer.py [--short] [--out DIR]
"""

from __future__ import annotations

import math
import sys

import numpy as np

import figures_common as fc

MODEL = "MemsAccelerometer"
EPS0 = 8.8541878128e-12
G_N = 9.80665
CALCULATED = ["k_suspension", "b_squeeze", "b_slide", "k_electrostatic", "V_pull_in", "V_out_per_g", "bandwidth", "f_natural_carrier"]
ELEMENTS = ["proof_mass", "folded_beams", "sense_capacitors", "squeeze_film", "slide_film"]


def sine_amplitude(f: float, output: str, cycles: int) -> float:
    """Steady amplitude of `output` under a 1 g sine at f (least squares over the last half of the run)."""
    stop = cycles / f
    res = fc.simulate_checked(MODEL, stop, 1 / (40 * f), {"profile": 2, "a_sine": G_N, "f_sine": f, "t_start": 0.0}, [output])
    t, y = np.asarray(res["time"]), np.asarray(res[output])
    sel = t >= stop / 2
    w = 2 * math.pi * f
    basis = np.column_stack([np.sin(w * t[sel]), np.cos(w * t[sel]), np.ones(np.count_nonzero(sel))])
    (a, b, _), *_ = np.linalg.lstsq(basis, y[sel], rcond=None)
    return math.hypot(a, b)


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    start = {name: fc.start_value(MODEL, name) for name in ("m_proof", "f_filter", "gap", "A_electrode", "x_stop")}
    step = fc.simulate_checked(MODEL, 3e-3, 1e-6 if not args.short else 1e-5, {}, ["displacement", "V_out"] + CALCULATED)
    c = {name: float(step[name][-1]) for name in CALCULATED}
    m, k_eff = start["m_proof"], c["k_suspension"] - c["k_electrostatic"]
    b = c["b_squeeze"] + c["b_slide"]

    fig, axes = fc.plt.subplots(2, 2, figsize=(14, 9))
    (ax_step, ax_freq), (ax_pull, ax_share) = axes

    # Step response.
    t = np.asarray(step["time"]) * 1e3
    ax_step.plot(t, np.asarray(step["displacement"]) * 1e9, color="tab:blue", lw=1.0, label="proof-mass displacement x (nm)")
    ax_v = ax_step.twinx()
    ax_v.plot(t, np.asarray(step["V_out"]) * 1e3, color="tab:red", lw=2.0, label="output voltage V_out (mV)")
    ax_step.set_xlabel("time (ms)")
    ax_step.set_ylabel("displacement (nm)", color="tab:blue")
    ax_v.set_ylabel("V_out (mV)", color="tab:red")
    ax_step.set_title(f"10 g step: the mass rings at {c['f_natural_carrier'] / 1e3:.1f} kHz (Q = {math.sqrt(m * k_eff) / b:.0f}), "
                      f"the 1 kHz filter smooths it", fontsize=10)
    lines = ax_step.get_lines() + ax_v.get_lines()
    ax_v.legend(lines, [line.get_label() for line in lines], fontsize=8, loc="center right")
    print(f"step: x = {1e9 * float(step['displacement'][-1]):.3f} nm, V_out = {1e3 * float(step['V_out'][-1]):.2f} mV "
          f"({1e3 * c['V_out_per_g']:.3f} mV/g x 10)")

    # Frequency response: closed form of the linearised sensor, and simulated sines.
    f = np.geomspace(10.0, 1e5, 600)
    s = 2j * np.pi * f
    wn = 2 * np.pi * start["f_filter"]
    mech = k_eff / (m * s**2 + b * s + k_eff)
    filt = wn**2 / (s**2 + math.sqrt(2) * wn * s + wn**2)
    ax_freq.loglog(f, np.abs(mech), color="tab:blue", lw=1.0, label="mechanics x / (m a / k_eff), linearised")
    ax_freq.loglog(f, np.abs(mech * filt), color="tab:red", lw=1.0, label="sensor V_out / (S a), linearised")
    points = [100.0, 1000.0, 3000.0] if args.short else [100.0, 300.0, 1000.0, 2000.0, 5000.0, 10000.0, 20000.0, 24000.0, 30000.0, 50000.0]
    x_static = m * G_N / k_eff
    sim_mech = [sine_amplitude(fp, "displacement", 30 if fp > 3000 else 6) / x_static for fp in points]
    sim_out = [sine_amplitude(fp, "V_out", 8) / c["V_out_per_g"] for fp in points if fp <= 5000.0]
    ax_freq.loglog(points, sim_mech, "o", color="tab:blue", ms=5, label="FMU, simulated 1 g sines: displacement")
    ax_freq.loglog([fp for fp in points if fp <= 5000.0], sim_out, "s", color="tab:red", ms=5, label="FMU, simulated 1 g sines: V_out")
    ax_freq.axvline(c["bandwidth"], color="k", ls=":", lw=1.0, label=f"bandwidth {c['bandwidth']:.0f} Hz (-3 dB)")
    ax_freq.axhline(1 / math.sqrt(2), color="grey", ls="--", lw=0.8)
    ax_freq.set_ylim(1e-3, 50)
    ax_freq.set_xlabel("frequency (Hz)")
    ax_freq.set_ylabel("amplitude / static amplitude")
    ax_freq.set_title("frequency response: the filter sets the bandwidth, far below the resonance", fontsize=10)
    ax_freq.legend(fontsize=8, loc="lower left")

    # Pull-in: the bias on electrode 1 ramped slowly, the carrier off.
    v_pi = c["V_pull_in"]
    ramp = 4e-3 if args.short else 20e-3
    pull = fc.simulate_checked(MODEL, ramp, 1e-5, {"V_carrier": 0.0, "a_step": 0.0, "V_bias": 1.15 * v_pi, "t_bias_ramp": ramp},
                               ["V_bias_applied", "displacement", "at_stop"])
    vb = np.asarray(pull["V_bias_applied"])
    ax_pull.plot(vb, np.asarray(pull["displacement"]) * 1e6, color="tab:red", lw=1.5, label="FMU: V_bias ramped to 1.15 V_pi")
    u = np.linspace(0.0, 1.0 / 3.0, 400)  # x / g along the stable branch: k x (g - x)^2 = eps A V^2 / 2
    k = c["k_suspension"]
    v_static = np.sqrt(2 * k * u * start["gap"] ** 3 * (1 - u) ** 2 / (EPS0 * start["A_electrode"]))
    ax_pull.plot(v_static, u * start["gap"] * 1e6, color="k", ls="--", lw=1.0, label="static balance (stable branch, to g/3)")
    ax_pull.axvline(v_pi, color="tab:purple", ls=":", label=f"V_pi = sqrt(8 k g^3 / 27 eps A) = {v_pi:.3f} V")
    ax_pull.axhline(start["x_stop"] * 1e6, color="grey", lw=0.8, label="travel stop")
    snap = vb[np.argmax(np.asarray(pull["at_stop"]) == 1.0)] if np.any(np.asarray(pull["at_stop"]) == 1.0) else float("nan")
    print(f"pull-in: the mass reaches the stop at V_bias = {snap:.4f} V (ramp {1e3 * ramp:g} ms); V_pi = {v_pi:.4f} V")
    ax_pull.set_xlabel("bias voltage on electrode 1 (V)")
    ax_pull.set_ylabel("displacement (um)")
    ax_pull.set_title(f"pull-in (carrier off): the mass snaps onto the stop at {snap:.3f} V", fontsize=10)
    ax_pull.legend(fontsize=8, loc="upper left")

    # Question 2: shares of activity.
    shares = {}
    for label, sv in (("1 kHz sine (in band)", {"profile": 2}), ("10 g step (ringing)", {})):
        res = fc.simulate_checked(MODEL, 3e-3, 1e-5, sv, [f"share_{e}" for e in ELEMENTS])
        shares[label] = [float(res[f"share_{e}"][-1]) for e in ELEMENTS]
        print(f"shares, {label}: " + ", ".join(f"{e} {v:.2f} %" for e, v in zip(ELEMENTS, shares[label])))
    y = np.arange(len(ELEMENTS))
    for i, (label, values) in enumerate(shares.items()):
        ax_share.barh(y + (0.2 if i else -0.2), values, height=0.38, label=label, color=("tab:green", "tab:orange")[i])
    ax_share.set_yticks(y, ["proof mass (I)", "folded beams (C)", "sense capacitors (C, 2 domains)", "squeeze film (R)", "slide film (R)"])
    ax_share.set_xlabel("share of the storage (C, I) or of the dissipative (R) elements' activity (%)")
    ax_share.set_title("question 2: the dominant effect of each part", fontsize=10)
    ax_share.invert_yaxis()
    ax_share.legend(fontsize=8, loc="lower right")

    fc.finish(fig, "Figure 3.14: MEMS accelerometer (dist/MemsAccelerometer.fmu)", args.out, "MemsAccelerometer_response.png", legend_loc=None)
    return 0


if __name__ == "__main__":
    sys.exit(main())
