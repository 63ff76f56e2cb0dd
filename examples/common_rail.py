"""Figure 3.20: the common-rail direct injection system at 2000 rpm, and the chapter's question: how stable is
the rail pressure?

dist/CommonRailInjection.fmu with its defaults (four cylinders fired 1-3-4-2, 24 mm3 per shot, set point 1450 bar)
and with the rail's volume halved and doubled. Top left: the rail pressure over two engine cycles; top right:
the flows into and out of the rail over one firing interval (the pump's three plungers, the injector, the
pressure-control valve); bottom left: one shot (needle lift, injection rate, injected volume); bottom right: the
ripple (peak to peak, settled) against the rail's volume.

    .venv/bin/python examples/common_rail.py [--short] [--out DIR]
"""

from __future__ import annotations

import sys

import numpy as np

import figures_common as fc

MODEL = "CommonRailInjection"
OUTPUTS = ["rail_pressure", "pump_flow", "injection_flow", "relief_flow", "needle_lift", "injected_volume", "firing_cylinder",
           "valve_opening_pressure"]
VOLUMES = {10e-6: dict(color="tab:orange", lw=1.0), 20e-6: dict(color="tab:blue", lw=1.6), 40e-6: dict(color="tab:green", lw=1.0)}
DEFAULT_VOLUME = 20e-6
FIRING_INTERVAL = 0.015  # s at 2000 rpm, four cylinders


def ripple(res, settle: float) -> float:
    t, p = np.asarray(res["time"]), np.asarray(res["rail_pressure"])
    return float(np.ptp(p[t >= settle]))


def main(argv=None) -> int:
    args = fc.parser(__doc__.splitlines()[0]).parse_args(argv)
    stop, h = (0.06, 1e-4) if args.short else (0.12, 1e-5)
    sweep = [10e-6, 20e-6, 40e-6] if args.short else [5e-6, 7.5e-6, 10e-6, 15e-6, 20e-6, 30e-6, 40e-6, 60e-6, 80e-6]
    runs = {v: fc.simulate_checked(MODEL, stop, h, {"V_rail": v}, OUTPUTS) for v in sorted(set(sweep) | set(VOLUMES))}
    fig, axes = fc.plt.subplots(2, 2, figsize=(13, 8.5))
    (ax_p, ax_q), (ax_shot, ax_ripple) = axes

    for v, style in VOLUMES.items():
        res = runs[v]
        t = np.asarray(res["time"])
        p = np.asarray(res["rail_pressure"]) / 1e5
        ax_p.plot(t * 1e3, p, label=f"V_rail = {v * 1e6:.0f} cm3: {p[t >= 0.5 * stop].min():.0f} .. {p[t >= 0.5 * stop].max():.0f} bar", **style)
    base = runs[DEFAULT_VOLUME]
    t = np.asarray(base["time"])
    ax_p.axhline(base["valve_opening_pressure"][0] / 1e5, color="k", ls=":", lw=0.8, label="valve opening pressure (set point)")
    ax_p.set_xlabel("time (ms)")
    ax_p.set_ylabel("rail pressure (bar)")
    ax_p.set_title("rail pressure: a dip at each shot, refilled by the pump through the valve", fontsize=10)

    # One firing interval of the settled default run, from a start of injection.
    changes = np.flatnonzero(np.diff(base["firing_cylinder"]) != 0)
    start = t[changes[-2] + 1] - h  # the output point just before the second-to-last start of injection
    window = (t >= start) & (t <= start + FIRING_INTERVAL)
    tw = (t[window] - start) * 1e3
    for name, label, color in (("pump_flow", "pump (three plungers)", "tab:blue"), ("injection_flow", "injector", "tab:red"),
                               ("relief_flow", "pressure-control valve", "tab:green")):
        ax_q.plot(tw, np.asarray(base[name])[window] * 1e6, color=color, label=label)
    ax_q.set_xlabel("time after a start of injection (ms)")
    ax_q.set_ylabel("flow (cm3/s)")
    ax_q.set_title("flows over one firing interval (15 ms)", fontsize=10)

    shot = (t >= start) & (t <= start + 1.5e-3)
    ts = (t[shot] - start) * 1e3
    ax_shot.plot(ts, np.asarray(base["needle_lift"])[shot] * 1e3 * 100, color="k", label="needle lift (x 100, mm)")
    ax_shot.plot(ts, np.asarray(base["injection_flow"])[shot] * 1e6, color="tab:red", label="injection rate (mm3/ms)")
    ax_shot.plot(ts, np.asarray(base["injected_volume"])[shot] * 1e9, color="tab:purple",
                 label=f"injected volume (mm3): {np.max(np.asarray(base['injected_volume'])[shot]) * 1e9:.1f}")
    ax_shot.set_xlabel("time after the start of energizing (ms)")
    ax_shot.set_title("one shot: 0.5 ms of energizing, 0.3 ms delays", fontsize=10)

    volumes = np.array(sorted(runs))
    ripples = np.array([ripple(runs[v], 0.5 * stop) for v in volumes]) / 1e5
    ax_ripple.loglog(volumes * 1e6, ripples, "o-", color="tab:blue", label="FMU, settled peak to peak")
    ax_ripple.loglog(volumes * 1e6, ripples[volumes == DEFAULT_VOLUME][0] * DEFAULT_VOLUME / volumes, color="gray", ls="--", lw=0.8,
                     label="1 / V (a shot drawn from C = V / B alone)")
    ax_ripple.set_xlabel("rail volume (cm3)")
    ax_ripple.set_ylabel("rail pressure ripple, peak to peak (bar)")
    ax_ripple.set_title("the rail's volume against the ripple (the valve refills it)", fontsize=10)
    for v, r in zip(volumes, ripples):
        print(f"V_rail {v * 1e6:5.1f} cm3: ripple {r:7.2f} bar peak to peak")
    fc.finish(fig, "Figure 3.20: common-rail injection at 2000 rpm, 4 cylinders (dist/CommonRailInjection.fmu)", args.out,
              "CommonRailInjection_rail_pressure.png", legend_loc="best")
    return 0


if __name__ == "__main__":
    sys.exit(main())
