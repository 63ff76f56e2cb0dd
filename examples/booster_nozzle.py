"""Figure 3.15: the launcher booster nozzle, its actuator-nozzle resonance and the dominant effect of
each part (question 2).

dist/BoosterNozzle.fmu: a Vega P80-class nozzle (1400 kg m2 on a 15 200 N m/deg flexible bearing)
steered in pitch and yaw by two servo-valve controlled hydraulic actuators on a compliant anchoring.
Top left: the default 0.5 deg pitch step (the thrust-offset torque acting from t = 0); yaw stays at
rest. Top right: the pitch actuator's pressure difference rings at the actuator-nozzle resonance
(the two-degree-of-freedom chain's ~41 Hz). Bottom left: a free oscillation, valve closed, against
the chain's period. Bottom right: the storage elements' shares of activity (Table 3.3) in three
motions: which part dominates depends on the motion.

    .venv/bin/python examples/booster_nozzle.py [--short] [--out DIR]
"""

from __future__ import annotations

import math
import sys

import numpy as np

import figures_common as fc

MODEL = "BoosterNozzle"
DEG = math.pi / 180.0
STORAGE = [("nozzle_inertia", "nozzle inertia (I)"), ("bearing_stiffness", "bearing stiffness (C)"), ("oil", "oil (C)"),
           ("anchoring", "anchoring (C)"), ("actuator_body", "actuator body (I)")]
SCENARIOS = {
    "0.5 deg step": ({}, 1.0),
    "2 Hz sine, 0.5 deg": ({"profile": 2}, 1.0),
    "0.3 Hz sine, 5.7 deg": ({"profile": 2, "sine_frequency": 0.3, "command_amplitude": 5.7 * DEG, "step_time": 0.0}, 10 / 3),
}
ZOOM = (0.095, 0.25)  # s: the step and the ringing after it


def chain_modes() -> tuple[float, np.ndarray]:
    """The FMU's own two-DOF resonance (calculated parameter) and the low mode's shape (theta, x_b)
    from the chain's matrices with the FMU's parameter values."""
    v = {n: fc.start_value(MODEL, n) for n in ("J_nozzle", "K_bearing", "r_arm", "A_piston", "B_oil", "V_chamber", "m_actuator", "K_anchor")}
    k = 2 * v["A_piston"] ** 2 * v["B_oil"] / v["V_chamber"]
    r = v["r_arm"]
    mass = np.diag([v["J_nozzle"], v["m_actuator"]])
    stiffness = np.array([[v["K_bearing"] + k * r * r, -k * r], [-k * r, k + v["K_anchor"]]])
    w2, phi = np.linalg.eig(np.linalg.solve(mass, stiffness))
    low = int(np.argmin(w2.real))
    return math.sqrt(w2[low].real) / (2 * math.pi), phi[:, low].real, k, v


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    stop, h = (0.3, 1e-4) if args.short else (1.0, 1e-4)
    outputs = ["nozzle_angle_pitch", "nozzle_command_pitch", "nozzle_angle_yaw", "pressure_difference_pitch", "f_actuator_nozzle"]
    step = fc.simulate_checked(MODEL, stop, h, {}, outputs)
    f_chain = float(step["f_actuator_nozzle"][-1])

    f_low, shape, k_oil, v = chain_modes()
    theta0 = 0.5 * DEG
    x_b0 = theta0 * shape[1] / shape[0]
    free_start = {"K_v": 0.0, "R_leakage": 1e30, "profile": 0, "M_offset": 0.0, "theta_pitch": theta0, "phi_body_pitch": x_b0 / v["r_arm"],
                  "dp_pitch": -(k_oil / v["A_piston"]) * (v["r_arm"] * theta0 - x_b0)}
    free = fc.simulate_checked(MODEL, 0.1 if args.short else 0.2, 2e-5, free_start, ["nozzle_angle_pitch"])

    shares = {}
    for name, (start, t_end) in SCENARIOS.items():
        t_end = min(t_end, 1.0) if args.short else t_end
        res = fc.simulate_checked(MODEL, t_end, t_end / 200, start, [f"share_{e}_pitch" for e, _ in STORAGE])
        shares[name] = [float(res[f"share_{e}_pitch"][-1]) for e, _ in STORAGE]
        print(f"{name}: " + ", ".join(f"{label} {s:.1f} %" for (_, label), s in zip(STORAGE, shares[name])))

    fig, axes = fc.plt.subplots(2, 2, figsize=(13, 8.5))
    (ax_step, ax_dp), (ax_free, ax_share) = axes
    t = np.asarray(step["time"])
    ax_step.plot(t, np.degrees(step["nozzle_command_pitch"]), color="k", lw=0.8, ls=":", label="pitch command")
    ax_step.plot(t, np.degrees(step["nozzle_angle_pitch"]), color="tab:red", lw=1.4, label="pitch angle")
    ax_step.plot(t, np.degrees(step["nozzle_angle_yaw"]), color="tab:blue", lw=1.0, label="yaw angle (at rest)")
    ax_step.set_ylabel("nozzle angle (deg)")
    ax_step.set_title("0.5 deg pitch step; the offset torque deflects the nozzle from t = 0", fontsize=10)

    dp = np.asarray(step["pressure_difference_pitch"]) / 1e6
    ax_dp.plot(t, dp, color="tab:purple", lw=1.0, label=f"pitch actuator dp ({dp.min():.1f} .. {dp.max():.1f} MPa)")
    ax_dp.set_xlim(*ZOOM)
    ax_dp.set_ylabel("pressure difference (MPa)")
    ax_dp.set_title(f"the step rings at the actuator-nozzle resonance (chain: {f_chain:.1f} Hz)", fontsize=10)

    tf = np.asarray(free["time"])
    ax_free.plot(1e3 * tf, np.degrees(free["nozzle_angle_pitch"]), color="tab:green", lw=1.2, label="FMU, valve closed")
    ax_free.plot(1e3 * tf, np.degrees(theta0 * np.cos(2 * math.pi * f_low * tf)), color="k", lw=0.8, ls="--",
                 label=f"undamped two-DOF chain's low mode, {f_low:.2f} Hz")
    ax_free.set_xlabel("time (ms)")
    ax_free.set_ylabel("nozzle angle (deg)")
    ax_free.set_title("free oscillation from the chain's mode shape (dampings kept)", fontsize=10)

    x = np.arange(len(STORAGE))
    width = 0.8 / len(shares)
    for j, (name, values) in enumerate(shares.items()):
        ax_share.bar(x + (j - 1) * width, values, width, label=name)
    ax_share.set_xticks(x, [label for _, label in STORAGE], rotation=15, fontsize=8)
    ax_share.set_ylabel("share of the storage activity (%)")
    ax_share.set_title("dominant storage: inertia in the step, the bearing in slow motion", fontsize=10)

    for ax in (ax_step, ax_dp):
        ax.set_xlabel("time (s)")
    fc.finish(fig, "Figure 3.15: launcher booster nozzle, pitch step, resonance and dominant effects (dist/BoosterNozzle.fmu)", args.out,
              "BoosterNozzle_resonance_and_effects.png", legend_loc="best")
    return 0


if __name__ == "__main__":
    sys.exit(main())
