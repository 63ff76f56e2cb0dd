"""MotorFanSystem (dist/MotorFanSystem.ssp, the subsystem FMUs coupled for the direct-on-line start)
run by external co-simulation masters, and compared with the monolithic dist/MotorFan.fmu (level=3,
start_mode=1). Shared by test_coupled_masters.py and coupling_table.py.

Every runner returns a `Run`: the fan speed and the shaft torque on the grid of communication points
t_k = k h, as an integer index k (not a float time: masters disagree on time stamps, see below), so
that two runs are compared point by point on the indices they share. The quirks of each master that
decide which k a value belongs to (all checked in test_coupled_masters.py, where the four Jacobi
masters agree with each other to round-off once aligned this way):

* fmpy 0.3.32 `simulate_ssp`: a Jacobi master in Python. Each row is stamped with the START of the
  step but holds the outputs read AFTER `doStep` (its loop records `time` before `time += h`), so row
  j is k = j + 1; there is no row for t = 0. Its time is a float sum of h, so the row count may be
  one more than T/h: rows past k = N are dropped. Its connectors start at 0.0 whatever the FMUs'
  start values (harmless here: every coupled output is 0 at t = 0 for the start from rest), and it
  reads the SSD's ParameterBindings without applying them: they are passed as its `parameter_set`.
* fmpy `simulate_fmu` (MotorFan.fmu and the container FMU): row k is the communication point k h,
  holding the outputs after the step that ends there; row 0 is the initial point.
* ecospy 0.7.2: a Jacobi master (C++, TBB). It ignores an FMU's fmi2Discard: the FMU stays at
  the time it refused and the others go on (at h = 10 ms, where the Jacobi coupling is unstable,
  it reports values of 1e16 instead of stopping). Time accumulates in floats (`step_until(T)` may
  stop a step short), so the runner steps an exact count, `step(N)`, and uses the CSV writer's
  iteration number as k; the CSV holds 6 decimals. It reads outputs after the new inputs are set, so a direct
  feedthrough output (DriveShaft.torque = K theta + D (speed_a - speed_b)) shows the damping term of
  the next step's inputs: the recorded torque differs from the other masters' by D x one step's
  change of the speed difference (up to ~13 N m at h = 1 ms), the dynamics do not. It applies the
  SSD's parameter sets only on request: `init(parameter_set="initialValues")`.
* libcosimpy 0.0.6 (DNV libcosim): a Jacobi master with integer nanosecond time. A buffered
  time-series observer records every step; sample n is the value after step n (k = n, read from
  step 1 on: the wrapper trims its buffer by counting zero step numbers, so a sample of step 0
  would drop the last one). With an observer attached an fmi2Error aborts the whole process
  (SIGABRT), so it runs in a child process.
* fmucontainer (fmu_manipulation_toolbox 2.0): the FMUs packed into one native container FMU from a
  CSV derived from the .ssp (FMU, LINK, START rows; explicit OUTPUT rows name the container's ports
  `fan_speed` and `shaft_torque`: auto-exposed ports take the bare port name, or a lower-cased
  `fmu.port` on a clash), run by fmpy `simulate_fmu`. By default it steps the embedded FMUs in
  parallel from the same inputs (Jacobi); `-sequential` steps them one after the other in the CSV's
  order with fresh outputs (Gauss-Seidel). It logs a false "[ERROR] Solver configure".
"""

from __future__ import annotations

import csv
import os
import shutil
import subprocess
import sys
import tempfile
import time
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

FAN = ("Fan", "fan_speed")
TORQUE = ("DriveShaft", "torque")
ECOS_PARAMETER_SET = "initialValues"  # the name build-fmus gives every component's parameter set


class MasterFailed(RuntimeError):
    """A master stopped the simulation (an FMU refused a step, the execution failed)."""


@dataclass
class Run:
    master: str
    step: float
    stop_time: float
    k: np.ndarray  # communication point indices, t = k * step
    fan_speed: np.ndarray  # rad/s
    shaft_torque: np.ndarray  # N m, high-speed side
    seconds: float  # wall-clock time of the simulation (without building or loading results)

    @property
    def t(self) -> np.ndarray:
        return self.k * self.step


@dataclass
class Comparison:
    fan_error_pct: float  # max |coupled - monolithic| fan speed over the common points, % of rated
    worst_time: float  # where it is reached, s
    peak: float  # max |shaft torque| of the coupled run, N m
    peak_reference: float  # same for the monolithic run
    peak_error_pct: float  # (peak - peak_reference) / peak_reference, %
    points: int  # common output points compared
    rated: float  # rated fan speed: the monolithic final fan speed, rad/s


def steps(step: float, stop_time: float) -> int:
    n = int(round(stop_time / step))
    if abs(n * step - stop_time) > 1e-9 * max(1.0, stop_time):
        raise ValueError(f"stop time {stop_time} s is not a whole number of steps of {step} s")
    return n


def _run(master, step, stop_time, k, fan, torque, seconds) -> Run:
    k = np.asarray(k, dtype=np.int64)
    keep = (k >= 0) & (k <= steps(step, stop_time))
    return Run(master, step, stop_time, k[keep], np.asarray(fan, float)[keep], np.asarray(torque, float)[keep], seconds)


def compare(run: Run, reference: Run) -> Comparison:
    """Fan speed error at every common output point (% of the rated speed, taken as the monolithic
    final fan speed) and the peak |shaft torque| of each run over its points."""
    if abs(run.step - reference.step) > 1e-15:
        raise ValueError("compare runs made with the same communication step")
    common, i_run, i_ref = np.intersect1d(run.k, reference.k, return_indices=True)
    if len(common) < 0.99 * min(len(run.k), len(reference.k)):
        raise ValueError(f"{run.master}: only {len(common)} of {len(run.k)} points on the reference grid")
    rated = float(reference.fan_speed[np.argmax(reference.k)])
    err = np.abs(run.fan_speed[i_run] - reference.fan_speed[i_ref]) / rated * 100.0
    worst = int(np.argmax(err))
    peak, peak_ref = float(np.max(np.abs(run.shaft_torque))), float(np.max(np.abs(reference.shaft_torque)))
    return Comparison(float(err[worst]), float(common[worst] * run.step), peak, peak_ref,
                      (peak - peak_ref) / peak_ref * 100.0, len(common), rated)


# ---------------------------------------------------------------------------------------------
# The monolithic reference

def monolithic(motor_fan_fmu: Path, step: float, stop_time: float) -> Run:
    from fmpy import simulate_fmu

    t0 = time.perf_counter()
    r = simulate_fmu(str(motor_fan_fmu), stop_time=stop_time, output_interval=step,
                     start_values={"level": 3, "start_mode": 1}, output=["fan_speed", "shaft_torque"])
    seconds = time.perf_counter() - t0
    return _run("MotorFan.fmu (monolithic, fmpy)", step, stop_time, np.rint(r["time"] / step), r["fan_speed"],
                r["shaft_torque"], seconds)


# ---------------------------------------------------------------------------------------------
# The .ssp as the masters read it

def ssp_parameters(ssp: Path) -> dict[str, str]:
    """{"Component.variable": value text} from the ParameterBindings of the SSD's components."""
    from fmpy.ssp.ssd import read_ssd

    values = {}
    for component in read_ssd(str(ssp)).system.elements:
        for binding in component.parameterBindings:
            for parameter_set in binding.parameterValues:
                for p in parameter_set.parameters:
                    values[f"{component.name}.{p.name}"] = p.value
    return values


def fmpy_ssp(ssp: Path, step: float, stop_time: float) -> Run:
    from fmpy.fmi1 import FMICallException
    from fmpy.ssp.simulation import simulate_ssp
    from fmpy.ssp.ssd import Parameter, ParameterSet

    n = steps(step, stop_time)
    # fmpy ignores the SSD's bindings; its own parameter_set takes "Component.variable" names.
    parameters = ParameterSet(parameters=[Parameter(name=k, value=v) for k, v in ssp_parameters(ssp).items()])
    t0 = time.perf_counter()
    try:
        r = simulate_ssp(str(ssp), stop_time=stop_time, step_size=step, parameter_set=parameters)
    except FMICallException as e:  # the time is only in the FMU's log message, printed by fmpy
        raise MasterFailed(f"stops: {str(e).rstrip('.')}") from e
    seconds = time.perf_counter() - t0
    k = np.rint(r["time"] / step).astype(np.int64) + 1  # stamped with the step's start, values after it
    if len(k) < n:
        raise RuntimeError(f"fmpy simulate_ssp returned {len(k)} rows for {n} steps")
    return _run("fmpy simulate_ssp", step, stop_time, k, r[".".join(FAN)], r[".".join(TORQUE)], seconds)


def ecospy_ssp(ssp: Path, step: float, stop_time: float) -> Run:
    from ecospy import EcosLib, EcosSimulation

    EcosLib.set_log_level("warn")
    n = steps(step, stop_time)
    with tempfile.TemporaryDirectory(prefix="ecospy-") as tmp:
        result = Path(tmp) / "result.csv"
        sim = EcosSimulation(ssp_path=str(ssp), step_size=step)
        try:
            ids = [f"{c}::{v}" for c, v in (FAN, TORQUE)]
            sim.add_csv_writer(str(result), identifiers=ids)
            if not sim.init(parameter_set=ECOS_PARAMETER_SET if ssp_parameters(ssp) else None):
                raise RuntimeError(f"ecospy: init failed: {EcosLib.get_last_error()}")
            t0 = time.perf_counter()
            sim.step(n)  # an exact number of steps: step_until(T) may stop one short
            seconds = time.perf_counter() - t0
            sim.terminate()
        finally:
            sim.free()  # also closes the CSV file
        with open(result, newline="") as f:
            reader = csv.reader(f)
            header = [h.strip() for h in next(reader)]
            rows = np.array([[float(x) for x in row] for row in reader if row])
    col = {name.split("[")[0]: i for i, name in enumerate(header)}
    return _run("ecospy", step, stop_time, rows[:, col["iterations"]], rows[:, col[ids[0]]], rows[:, col[ids[1]]],
                seconds)


def libcosim_ssp(ssp: Path, step: float, stop_time: float) -> Run:
    """libcosimpy from the .ssp, in a child process (an fmi2Error aborts the process)."""
    with tempfile.TemporaryDirectory(prefix="libcosim-") as tmp:
        out = Path(tmp) / "run.npz"
        proc = subprocess.run([sys.executable, __file__, "libcosim", str(ssp), repr(step), repr(stop_time), str(out)],
                              capture_output=True, text=True, timeout=3600)
        if proc.returncode != 0 or not out.exists():
            last = (proc.stderr.strip().splitlines() or ["(no message)"])[-1]
            if last.startswith(MasterFailed.__name__ + ": "):
                raise MasterFailed(last.split(": ", 1)[1])
            raise RuntimeError(f"libcosimpy child exited with {proc.returncode}:\n{proc.stdout[-2000:]}\n{proc.stderr[-4000:]}")
        d = np.load(out)
        return _run("libcosimpy", step, stop_time, d["k"], d["fan"], d["torque"], float(d["seconds"]))


def _libcosim_child(ssp: str, step: float, stop_time: float, out: str) -> None:
    from libcosimpy._internal import get_last_error_message
    from libcosimpy.CosimEnums import CosimExecutionState, CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.WARNING)  # debug by default
    n = steps(step, stop_time)
    h_ns = int(round(step * 1e9))
    ex = CosimExecution.from_ssp_file(ssp, step_size=h_ns)
    index = {s.name.decode(): s.index for s in ex.slave_infos()}

    def reference(component, variable):
        return next(v.reference for v in ex.slave_variables(index[component]) if v.name.decode() == variable)

    observer = CosimObserver.create_time_series(buffer_size=n + 16)
    ex.add_observer(observer)
    signals = [(index[c], reference(c, v)) for c, v in (FAN, TORQUE)]
    for slave, vr in signals:
        observer.start_time_series(slave, vr, CosimVariableType.REAL)
    t0 = time.perf_counter()
    if not ex.simulate_until(target_time=n * h_ns):
        status = ex.status()
        raise MasterFailed(f"stops at t = {status.current_time / 1e9:g} s ({CosimExecutionState(status.state).name}): "
                           f"{get_last_error_message().strip()}")
    seconds = time.perf_counter() - t0
    series = []
    for slave, vr in signals:
        times, step_numbers, values = observer.time_series_real_samples(slave, vr, from_step=1, sample_count=n)
        if len(values) != n or step_numbers[-1] != n or times[-1] != n * h_ns:
            raise RuntimeError(f"libcosim observer returned {len(values)} samples, last step {step_numbers[-1:]}")
        series.append((np.asarray(step_numbers), np.asarray(values)))
    np.savez(out, k=series[0][0], fan=series[0][1], torque=series[1][1], seconds=seconds)


def _container_csv(ssp: Path, order: list[str] | None = None) -> tuple[str, list[str]]:
    """The fmucontainer CSV for the system of the .ssp: its components (FMU rows, in `order` if
    given), connections (LINK), parameter bindings (START) and the two outputs compared."""
    from fmpy.ssp.ssd import read_ssd

    system = read_ssd(str(ssp)).system
    components = {c.name: Path(c.source).name for c in system.elements}
    if len(set(components.values())) != len(components):
        raise ValueError("fmucontainer needs one file per instance; copy the FMU under another name")
    names = order or list(components)
    rows = ["rule;from_fmu;from_port;to_fmu;to_port"]
    rows += [f"FMU;{components[n]};;;" for n in names]
    rows += [f"LINK;{components[c.startElement]};{c.startConnector};{components[c.endElement]};{c.endConnector}"
             for c in system.connections]
    for name, value in ssp_parameters(ssp).items():
        component, variable = name.split(".", 1)
        rows.append(f"START;{components[component]};{variable};{value};")
    rows.append(f"OUTPUT;{components[FAN[0]]};{FAN[1]};;fan_speed")
    rows.append(f"OUTPUT;{components[TORQUE[0]]};{TORQUE[1]};;shaft_torque")
    return "\n".join(rows) + "\n", [components[n] for n in names]


def fmucontainer_command() -> list[str]:
    exe = Path(sys.executable).with_name("fmucontainer")
    return [str(exe)] if exe.exists() else [shutil.which("fmucontainer") or "fmucontainer"]


def build_container(ssp: Path, step: float, workdir: Path, sequential: bool = False,
                    order: list[str] | None = None) -> Path:
    """Builds `workdir/MotorFanContainer.fmu` from the FMUs inside the .ssp."""
    text, files = _container_csv(ssp, order)
    with zipfile.ZipFile(ssp) as z:
        for f in files:
            (workdir / f).write_bytes(z.read(f"resources/{f}"))
    (workdir / "MotorFanContainer.csv").write_text(text)
    cmd = fmucontainer_command() + ["-container", f"MotorFanContainer.csv:{step!r}", "-fmu-directory", str(workdir),
                                    "-no-auto-input", "-no-auto-output"]
    if sequential:
        cmd.append("-sequential")
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=workdir, timeout=600)
    fmu = workdir / "MotorFanContainer.fmu"
    if proc.returncode != 0 or not fmu.exists():
        raise RuntimeError(f"fmucontainer failed ({proc.returncode}):\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    return fmu


def fmucontainer_fmpy(ssp: Path, step: float, stop_time: float, sequential: bool = False) -> Run:
    from fmpy import simulate_fmu
    from fmpy.fmi1 import FMICallException

    with tempfile.TemporaryDirectory(prefix="fmucontainer-") as tmp:
        # Sequential: the shaft first (it needs both speeds), then both inertias with its fresh torque.
        order = ["DriveShaft", "InductionMotor", "Fan"] if sequential else None
        fmu = build_container(ssp, step, Path(tmp), sequential, order)
        t0 = time.perf_counter()
        try:
            r = simulate_fmu(str(fmu), stop_time=stop_time, output_interval=step, output=["fan_speed", "shaft_torque"])
        except FMICallException as e:  # an embedded FMU refused a step
            raise MasterFailed(f"stops: {str(e).rstrip('.')}") from e
        seconds = time.perf_counter() - t0
    name = "fmucontainer -sequential (fmpy)" if sequential else "fmucontainer (fmpy)"
    return _run(name, step, stop_time, np.rint(r["time"] / step), r["fan_speed"], r["shaft_torque"], seconds)


# How each master couples the FMUs (all hold an input constant over a step: none of them uses the
# FMUs' input derivatives).
SCHEMES = {
    "fmpy simulate_ssp": "fmpy 0.3.32 `simulate_ssp` on the .ssp (Jacobi)",
    "ecospy": "ecospy 0.7.2 on the .ssp (Jacobi)",
    "libcosimpy": "libcosimpy 0.0.6 on the .ssp (Jacobi)",
    "fmucontainer (fmpy)": "fmucontainer 2.0 container FMU in fmpy (parallel = Jacobi)",
    "fmucontainer -sequential (fmpy)": "fmucontainer 2.0 `-sequential` in fmpy (Gauss-Seidel)",
}

MASTERS = {
    "fmpy simulate_ssp": fmpy_ssp,
    "ecospy": ecospy_ssp,
    "libcosimpy": libcosim_ssp,
    "fmucontainer (fmpy)": fmucontainer_fmpy,
    "fmucontainer -sequential (fmpy)": lambda ssp, step, stop: fmucontainer_fmpy(ssp, step, stop, sequential=True),
}


if __name__ == "__main__":
    if len(sys.argv) == 6 and sys.argv[1] == "libcosim":
        _libcosim_child(sys.argv[2], float(sys.argv[3]), float(sys.argv[4]), sys.argv[5])
    else:
        sys.exit(f"usage: {os.path.basename(__file__)} libcosim SSP STEP STOP_TIME OUT.npz (internal)")
