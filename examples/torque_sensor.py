"""Section 3.5.2: the magnetic torque sensor, with the book's model as defaults (Chap3_TorqueSensor.mo).

dist/TorqueSensor.fmu. Left: the book's own experiment (its defaults: 0.1 s, the input shaft stepped by
0.01 rad = 1 N m at 50 ms through the position source's 50 Hz smoothing): the demodulated voltage and the
conditioned torque. Middle: the raw demodulated voltage under a slow ramp of the input shaft's angle
through +-8 N m (question 9: offset and curvature), for the book's sensor, the book's circuits made
differential (arrangement 2) and this project's first set (sensor_data = bridge_topology = twist_drive = 2
and its values). Right: torque_measured - applied torque during the ramp (the low-pass filter's lag
included).

    .venv/bin/python examples/torque_sensor.py [--short] [--out DIR]
"""

from __future__ import annotations

import math
import sys

import numpy as np

import figures_common as fc

OUTPUTS = ["torque_applied", "u_demodulated", "torque_measured"]
SETTLE = 0.03  # s at -full scale before the ramp (the filter settles)
# This project's first set (docs/torque-sensor-spec.md, "The first set"): a torque-driven bar.
FIRST_SET = {"sensor_data": 2, "bridge_topology": 2, "twist_drive": 2, "K_torsion_bar": 360.0 / math.pi, "twist_stop": math.radians(5.0),
             "filter_w": 2 * math.pi * 200.0, "filter_damping": math.sqrt(0.5), "U_multiplier_reference": 5.0}
CASES = {"book (Chap3_TorqueSensor.mo)": {}, "book circuits, differential": {"arrangement": 2}, "first set": FIRST_SET}


def ramp_start(fs: float, k: float, case: dict, ramp: float) -> dict:
    """A ramp of the driven quantity from -full scale to +full scale after SETTLE."""
    if case.get("twist_drive", 1) == 2:
        return {"torque_in": -fs, "torque_profile": 2, "torque_profile_height": 2 * fs,
                "torque_profile_start": SETTLE, "torque_profile_duration": ramp}
    return {"twist_in": -fs / k, "twist_profile": 2, "twist_profile_height": 2 * fs / k,
            "twist_profile_start": SETTLE, "twist_profile_duration": ramp}


def run(short: bool) -> tuple:
    fs = fc.start_value("TorqueSensor", "torque_full_scale")
    stop = fc.start_value("TorqueSensor", "twist_profile_start") * 2  # the book's 0.1 s
    book = fc.simulate_checked("TorqueSensor", stop, 1e-5, {}, OUTPUTS)
    ramp = 0.05 if short else 1.0
    h = 1e-4
    ramps = {}
    for name, case in CASES.items():
        k = case.get("K_torsion_bar", fc.start_value("TorqueSensor", "K_torsion_bar"))
        stop_ramp = h * round((SETTLE + ramp) / h)
        ramps[name] = fc.simulate_checked("TorqueSensor", stop_ramp, h, {**case, **ramp_start(fs, k, case, ramp)}, OUTPUTS)
    return book, ramps


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    book, ramps = run(args.short)
    fs = fc.start_value("TorqueSensor", "torque_full_scale")
    fig, (ax_t, ax_u, ax_e) = fc.plt.subplots(1, 3, figsize=(16, 4.8))
    t = np.asarray(book["time"])
    ax_t.plot(t * 1e3, book["u_demodulated"], color="tab:blue", lw=1.2, label="u_demodulated (V)")
    ax_t.set_xlabel("time (ms)")
    ax_t.set_ylabel("u_demodulated (V; the book's product of two voltages)")
    ax_t.set_title("the book's experiment: 0.01 rad (1 N m) at 50 ms", fontsize=10)
    ax_tt = ax_t.twinx()
    ax_tt.plot(t * 1e3, book["torque_applied"], "k:", lw=1, label="torque_applied (N m)")
    ax_tt.plot(t * 1e3, np.clip(book["torque_measured"], -0.5, 1.5), color="tab:red", lw=1, label="torque_measured (N m)")
    ax_tt.set_ylim(-0.5, 1.5)
    ax_tt.set_ylabel("torque (N m)")
    before = float(np.mean(np.asarray(book["u_demodulated"])[(t > 0.049) & (t <= 0.05 - 1e-6)]))
    after = float(np.mean(np.asarray(book["u_demodulated"])[t > 0.099]))
    print(f"book's experiment: u_demodulated {before:+.5f} V before the step, {after:+.5f} V at 100 ms "
          f"(step {after - before:+.5f} V); torque_measured at the end {float(book['torque_measured'][-1]):.4f} N m")
    for name, res in ramps.items():
        ramping = np.asarray(res["time"]) >= SETTLE
        torque = np.asarray(res["torque_applied"])[ramping]
        u = np.asarray(res["u_demodulated"])[ramping]
        measured = np.asarray(res["torque_measured"])[ramping]
        ax_u.plot(torque, u, lw=1.5, label=name)
        steady = np.asarray(res["time"])[ramping] >= SETTLE + 0.005  # past the filter's response to the ramp's start
        err = 100 * np.max(np.abs(measured - torque)[steady]) / fs
        ax_e.plot(torque[steady], 100 * (measured - torque)[steady] / fs, lw=1.2, label=f"{name}: largest {err:.2f} % of full scale")
        print(f"{name}: u_demodulated from {u[0]:+.4f} V to {u[-1]:+.4f} V; "
              f"|torque_measured - torque| up to {err:.2f} % of full scale during the ramp (includes the filter's lag)")
    ax_u.axhline(0.0, color="k", lw=0.5)
    ax_u.set_xlabel("applied torque (N m)")
    ax_u.set_ylabel("raw demodulated voltage (V)")
    ax_u.set_title("raw output (u_demodulated): offset and curvature", fontsize=10)
    ax_e.set_xlabel("applied torque (N m)")
    ax_e.set_ylabel("error (% of full scale)")
    ax_e.set_title("conditioned - applied torque (filter lag included)", fontsize=10)
    lines = ax_t.get_lines() + ax_tt.get_lines()
    for ax in (ax_u, ax_e):
        ax.legend(fontsize=8, loc="best")
    ax_t.legend(lines, [ln.get_label() for ln in lines], loc="center right", fontsize=8)
    fc.finish(fig, f"Section 3.5.2: torque sensor, the book's model; ramps over +-{fs:g} N m in "
              f"{'a short' if args.short else '1 s'} (dist/TorqueSensor.fmu)", args.out, "TorqueSensor_characteristic.png",
              legend_loc=None)
    return 0


if __name__ == "__main__":
    sys.exit(main())
