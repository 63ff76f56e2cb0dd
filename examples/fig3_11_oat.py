"""Figure 3.11: one-at-a-time design of experiments, +-10 % on motor inertia, fan inertia and shaft stiffness.

dist/MotorFan.fmu at level c under speed control (default: the PI controller of Figure 3.7,
`--start-mode 3` for inverse simulation), with the FMU's defaults (the book authors' values: the 10 s
ramp to 300 rad/s through the 0.5 Hz filter). Each parameter is moved by -10 % and +10 % from its
default, one at a time; the response is the peak torque on the reducer's high-speed axis.
The parameter with the largest peak-torque swing is the most influential (the chapter: fan inertia).

The 7 cases run in parallel: in a process pool on this machine by default, or on a Dask cluster
with `--scheduler tcp://host:port` (dask.distributed). The FMU's bytes are sent to the workers, so
they need only the Python packages of tests/requirements.txt, not this repository or dist/. Start
workers with one thread each (`dask worker --nthreads 1 ADDRESS`; add processes with `--nworkers`):
fmpy changes the process's working directory while it loads an FMU, so two simulations in threads
of one process can leave it in a deleted directory.

    .venv/bin/python examples/fig3_11_oat.py [--short] [--out DIR] [--workers N] [--scheduler ADDRESS]
"""

from __future__ import annotations

import hashlib
import os
import sys
import tempfile
import threading
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

import figures_common as fc

PARAMETERS = {"J_motor": "motor inertia", "J_fan": "fan inertia", "K_shaft": "shaft stiffness"}
VARIATION = 0.10
OUTPUTS = ["shaft_torque"]


def cases(defaults: dict[str, float], base: dict) -> list[dict]:
    """The nominal case and, for each parameter, -10 % and +10 % (one at a time)."""
    out = [{"name": "nominal", "parameter": None, "factor": 1.0, "start_values": dict(base)}]
    for p in PARAMETERS:
        for factor in (1 - VARIATION, 1 + VARIATION):
            out.append({"name": f"{p} x {factor:.2f}", "parameter": p, "factor": factor,
                        "start_values": {**base, p: defaults[p] * factor}})
    return out


def _fmu_file(fmu: str | bytes) -> str:
    """A path to the FMU: `fmu` itself, or (bytes sent to a remote worker) a file written once per
    worker process, named by the content's hash."""
    if isinstance(fmu, str):
        return fmu
    path = Path(tempfile.gettempdir()) / f"oat-{hashlib.sha256(fmu).hexdigest()[:16]}-{os.getpid()}.fmu"
    if not path.is_file():
        tmp = path.with_suffix(f".{threading.get_ident()}.tmp")
        tmp.write_bytes(fmu)
        tmp.replace(path)
    return str(path)


def run_case(fmu: str | bytes, case: dict, stop_time: float, output_interval: float) -> dict:
    """One experiment (runs in a pool process or on a Dask worker): the case with its peak shaft torque
    and the torque's time history."""
    from fmpy import simulate_fmu

    res = simulate_fmu(_fmu_file(fmu), fmi_type="CoSimulation", start_time=0.0, stop_time=stop_time,
                       output_interval=output_interval, start_values=case["start_values"], output=OUTPUTS)
    torque = np.asarray(res["shaft_torque"], dtype=float)
    if not np.all(np.isfinite(torque)):
        raise RuntimeError(f"{case['name']}: the shaft torque is not finite")
    return {**case, "peak": float(np.max(np.abs(torque))), "time": np.asarray(res["time"], dtype=float), "torque": torque}


def run_pool(fmu: Path, all_cases: list[dict], stop: float, h: float, workers: int | None) -> list[dict]:
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = [pool.submit(run_case, str(fmu), c, stop, h) for c in all_cases]
        return [f.result() for f in futures]


def dask_client(address: str):
    """A dask.distributed client of the scheduler at `address` (e.g. tcp://host:8786)."""
    from dask.distributed import Client

    return Client(address)


def run_dask(client, fmu: Path, all_cases: list[dict], stop: float, h: float) -> list[dict]:
    """The cases as Dask tasks; the FMU's bytes are scattered to every worker once. run_case travels by
    value (cloudpickle), so the workers need fmpy and numpy but not this repository."""
    import cloudpickle

    cloudpickle.register_pickle_by_value(sys.modules[run_case.__module__])
    fmu_bytes = client.scatter(fmu.read_bytes(), broadcast=True)
    futures = [client.submit(run_case, fmu_bytes, c, stop, h, pure=False) for c in all_cases]
    return client.gather(futures)


def swings(results: list[dict]) -> dict[str, dict]:
    """Per parameter: peak torque at -10 % and +10 %, and the swing (largest |change| of the peak from nominal)."""
    nominal = next(r["peak"] for r in results if r["parameter"] is None)
    out = {}
    for p in PARAMETERS:
        lo = next(r["peak"] for r in results if r["parameter"] == p and r["factor"] < 1)
        hi = next(r["peak"] for r in results if r["parameter"] == p and r["factor"] > 1)
        out[p] = {"minus": lo - nominal, "plus": hi - nominal, "swing": max(abs(lo - nominal), abs(hi - nominal))}
    return {"nominal": nominal, "effects": out}


def ranking(results: list[dict]) -> list[str]:
    """Parameters from the most to the least influential on the peak shaft torque."""
    eff = swings(results)["effects"]
    return sorted(eff, key=lambda p: eff[p]["swing"], reverse=True)


def sweep(short: bool, start_mode: int = fc.PI_CONTROL, scheduler: str | None = None, workers: int | None = None,
          client=None) -> list[dict]:
    from fmpy import read_model_description

    fmu = fc.fmu("MotorFan")
    md = read_model_description(str(fmu))
    defaults = {v.name: float(v.start) for v in md.modelVariables if v.name in PARAMETERS}
    stop, h = (3.0, 1e-2) if short else (fc.MOTOR_FAN_HORIZON, fc.MOTOR_FAN_STEP)
    all_cases = cases(defaults, {"level": fc.LEVEL["c"], "start_mode": start_mode})
    if client is not None:
        return run_dask(client, fmu, all_cases, stop, h)
    if scheduler:
        with dask_client(scheduler) as c:
            return run_dask(c, fmu, all_cases, stop, h)
    return run_pool(fmu, all_cases, stop, h, workers)


def main(argv=None, client=None) -> int:
    p = fc.parser(__doc__.splitlines()[0])
    p.add_argument("--start-mode", type=int, default=fc.PI_CONTROL, choices=(fc.PI_CONTROL, fc.INVERSE),
                   help="speed control: 2 = PI controller (default), 3 = inverse simulation")
    p.add_argument("--scheduler", help="run the cases on the Dask cluster whose scheduler is at this address (tcp://host:port)")
    p.add_argument("--workers", type=int, help="process pool size (default: the number of CPUs)")
    args = p.parse_args(argv)
    results = sweep(args.short, args.start_mode, args.scheduler, args.workers, client)
    sw = swings(results)
    order = ranking(results)
    mode = "PI controller" if args.start_mode == fc.PI_CONTROL else "inverse simulation"
    print(f"nominal peak shaft torque ({mode}): {sw['nominal']:.1f} N m")
    for p_ in order:
        e = sw["effects"][p_]
        print(f"{PARAMETERS[p_]:>16}: -10 % -> {e['minus']:+9.3f} N m, +10 % -> {e['plus']:+9.3f} N m "
              f"({100 * e['swing'] / sw['nominal']:.2f} % of the nominal peak)")
    print("most influential on the peak shaft torque: " + " > ".join(PARAMETERS[p_] for p_ in order))

    fig, (ax_t, ax_b) = fc.plt.subplots(1, 2, figsize=(13, 5), gridspec_kw={"width_ratios": [2, 1]})
    colors = {None: "k", "J_motor": "tab:green", "J_fan": "tab:blue", "K_shaft": "tab:red"}
    for r in results:
        ls = "-" if r["factor"] >= 1 else "--"
        label = "nominal" if r["parameter"] is None else f"{PARAMETERS[r['parameter']]} {100 * (r['factor'] - 1):+.0f} %"
        ax_t.plot(r["time"], r["torque"], color=colors[r["parameter"]], ls=ls, lw=1.0 if r["parameter"] else 1.8, label=label)
    ax_t.set_xlim(0, min(15.0, float(results[0]["time"][-1])))  # the ramp and its settling; then steady
    ax_t.set_xlabel("time (s)")
    ax_t.set_ylabel("torque, high-speed axis (N m)")
    ax_t.legend(fontsize=8, loc="lower right")
    ax_t.set_title(f"level c, {mode}, 10 s ramp through the 0.5 Hz filter", fontsize=10)
    y = np.arange(len(PARAMETERS))
    names = list(PARAMETERS)
    ax_b.barh(y - 0.2, [sw["effects"][n]["minus"] for n in names], 0.4, label="-10 %", color="tab:gray")
    ax_b.barh(y + 0.2, [sw["effects"][n]["plus"] for n in names], 0.4, label="+10 %", color="tab:orange")
    ax_b.set_yticks(y, [PARAMETERS[n] for n in names])
    ax_b.axvline(0, color="k", lw=0.8)
    ax_b.set_xlabel("change of the peak shaft torque (N m)")
    ax_b.set_title(f"nominal peak {sw['nominal']:.0f} N m; most influential: {PARAMETERS[order[0]]}", fontsize=10)
    ax_b.legend(fontsize=8)
    suffix = "" if args.start_mode == fc.PI_CONTROL else "_inverse"
    fc.finish(fig, "Figure 3.11: one-at-a-time +-10 % (dist/MotorFan.fmu)", args.out, f"MotorFan_fig3_11_oat{suffix}.png",
              legend_loc=None)
    return 0


if __name__ == "__main__":
    sys.exit(main())
