"""A system .ssp (an SSP 1.0 file whose subsystem FMUs are under resources/) run by external
co-simulation masters, and compared with the system's monolithic FMU. Shared by
test_coupled_masters.py and coupling_table.py, which run dist/MotorFanSystem.ssp (the subsystem FMUs
coupled for the direct-on-line start) against dist/MotorFan.fmu (level=3, start_mode=1): the
MotorFan section at the end holds what they record and compare.

Every master runner takes the signals to record, `signals` = [(component, variable), ...], and
returns a `Run`: their values, keyed "Component.variable" (`key`), on the grid of communication
points t_k = k h, as an integer index k (not a float time: masters disagree on time stamps, see
below), so that two runs are compared point by point on the indices they share. `monolithic` runs
the monolithic FMU into a `Run` with the same keys, and `deviation` compares one signal of two runs.
The quirks of each master that decide which k a value belongs to (all checked in
test_coupled_masters.py, where the four Jacobi masters agree with each other to round-off once
aligned this way):

* fmpy 0.3.32 `simulate_ssp`: a Jacobi master in Python. Each row is stamped with the START of the
  step but holds the outputs read AFTER `doStep` (its loop records `time` before `time += h`), so row
  j is k = j + 1; there is no row for t = 0. Its time is a float sum of h, so the row count may be
  one more than T/h: rows past k = N are dropped. Its connectors start at 0.0 whatever the FMUs'
  start values (harmless for MotorFanSystem: every coupled output is 0 at t = 0 for the start from
  rest), and it reads the SSD's ParameterBindings without applying them: they are passed as its
  `parameter_set`. It records the SSD's connectors only (a signal must be one).
* fmpy `simulate_fmu` (the monolithic FMU and the container FMU): row k is the communication point
  k h, holding the outputs after the step that ends there; row 0 is the initial point.
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
  (SIGABRT), so it runs in a child process (given the signals as JSON, it saves one array each).
* fmucontainer (fmu_manipulation_toolbox 2.0): the FMUs packed into one native container FMU,
  <system>Container.fmu, from a CSV derived from the .ssp (FMU, LINK, START rows; explicit OUTPUT
  rows name the container's ports after the recorded signals, `container_ports`: Fan.fan_speed is
  `Fan_fan_speed`; auto-exposed ports take the bare port name, or a lower-cased `fmu.port` on a
  clash), run by fmpy `simulate_fmu`. By default it steps the embedded FMUs in parallel from the
  same inputs (Jacobi); `-sequential` steps them one after the other in the CSV's order (the
  caller's `order`, else the SSD's) with fresh outputs (Gauss-Seidel). It logs a false
  "[ERROR] Solver configure".
"""

from __future__ import annotations

import csv
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import zipfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

Signal = tuple[str, str]  # (component, variable) of the .ssp
ECOS_PARAMETER_SET = "initialValues"  # the name build-fmus gives every component's parameter set


class MasterFailed(RuntimeError):
    """A master stopped the simulation (an FMU refused a step, the execution failed)."""


def key(signal: Signal) -> str:
    """A signal's key in `Run.values`: "Component.variable"."""
    component, variable = signal
    return f"{component}.{variable}"


def keys(signals: Sequence[Signal]) -> list[str]:
    """The signals' keys, checked: at least one signal, none twice."""
    out = [key(s) for s in signals]
    if not out:
        raise ValueError("no signals to record")
    if len(set(out)) != len(out):
        raise ValueError(f"a signal is recorded twice: {out}")
    return out


@dataclass
class Run:
    master: str
    step: float
    stop_time: float
    k: np.ndarray  # communication point indices, t = k * step
    values: dict[str, np.ndarray]  # "Component.variable" -> its values at k
    seconds: float  # wall-clock time of the simulation (without building or loading results)

    @property
    def t(self) -> np.ndarray:
        return self.k * self.step

    # MotorFanSystem's signals (FAN, TORQUE below), for its tests and table
    @property
    def fan_speed(self) -> np.ndarray:  # rad/s
        return self.values[key(FAN)]

    @property
    def shaft_torque(self) -> np.ndarray:  # N m, high-speed side
        return self.values[key(TORQUE)]


def steps(step: float, stop_time: float) -> int:
    n = int(round(stop_time / step))
    if abs(n * step - stop_time) > 1e-9 * max(1.0, stop_time):
        raise ValueError(f"stop time {stop_time} s is not a whole number of steps of {step} s")
    return n


def _run(master, step, stop_time, k, values: Mapping[str, np.ndarray], seconds) -> Run:
    k = np.asarray(k, dtype=np.int64)
    keep = (k >= 0) & (k <= steps(step, stop_time))
    return Run(master, step, stop_time, k[keep], {name: np.asarray(v, float)[keep] for name, v in values.items()},
               seconds)


@dataclass
class Deviation:
    key: str  # the signal compared
    error: float  # max |run - reference| over the common points, divided by the caller's scale
    worst_time: float  # where it is reached, s
    points: int  # common output points compared


def common_points(run: Run, reference: Run) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(k, indices into run, indices into reference) of the points both runs have."""
    if abs(run.step - reference.step) > 1e-15:
        raise ValueError("compare runs made with the same communication step")
    common, i_run, i_ref = np.intersect1d(run.k, reference.k, return_indices=True)
    if len(common) < 0.99 * min(len(run.k), len(reference.k)):
        raise ValueError(f"{run.master}: only {len(common)} of {len(run.k)} points on the reference grid")
    return common, i_run, i_ref


def deviation(run: Run, reference: Run, signal: str, scale: float) -> Deviation:
    """The largest |run - reference| of one signal (its key) over the common output points, divided
    by `scale` (e.g. the signal's rated value), and where it is reached."""
    common, i_run, i_ref = common_points(run, reference)
    err = np.abs(run.values[signal][i_run] - reference.values[signal][i_ref]) / scale
    worst = int(np.argmax(err))
    return Deviation(signal, float(err[worst]), float(common[worst] * run.step), len(common))


def peak(run: Run, signal: str) -> float:
    """max |value| of one signal (its key) over all the run's points."""
    return float(np.max(np.abs(run.values[signal])))


# ---------------------------------------------------------------------------------------------
# The monolithic reference

def monolithic(fmu: Path, step: float, stop_time: float, start_values: Mapping[str, object],
               outputs: Mapping[str, str]) -> Run:
    """The monolithic FMU run by fmpy `simulate_fmu` with these start values; `outputs` maps the
    key each value is stored under (the coupled run's "Component.variable") to the FMU's output
    name, so that the two runs are compared signal by signal."""
    from fmpy import simulate_fmu

    t0 = time.perf_counter()
    r = simulate_fmu(str(fmu), stop_time=stop_time, output_interval=step, start_values=dict(start_values),
                     output=list(outputs.values()))
    seconds = time.perf_counter() - t0
    return _run(f"{Path(fmu).name} (monolithic, fmpy)", step, stop_time, np.rint(r["time"] / step),
                {name: r[output] for name, output in outputs.items()}, seconds)


# ---------------------------------------------------------------------------------------------
# The .ssp as the masters read it

def ssp_bindings(ssp: Path) -> dict[str, tuple[str, str]]:
    """{"Component.variable": (ssv type, value text)} from the ParameterBindings of the SSD's
    components, as written."""
    from fmpy.ssp.ssd import read_ssd

    values = {}
    for component in read_ssd(str(ssp)).system.elements:
        for binding in component.parameterBindings:
            for parameter_set in binding.parameterValues:
                for p in parameter_set.parameters:
                    values[f"{component.name}.{p.name}"] = (p.type, p.value)
    return values


def ssp_parameters(ssp: Path) -> dict[str, str]:
    """{"Component.variable": value text} from the ParameterBindings of the SSD's components."""
    return {name: text for name, (_, text) in ssp_bindings(ssp).items()}


def fmpy_ssp(ssp: Path, step: float, stop_time: float, signals: Sequence[Signal]) -> Run:
    from fmpy.fmi1 import FMICallException
    from fmpy.ssp.simulation import simulate_ssp
    from fmpy.ssp.ssd import Parameter, ParameterSet, read_ssd

    names = keys(signals)
    connectors = {f"{c.name}.{k.name}" for c in read_ssd(str(ssp)).system.elements for k in c.connectors}
    missing = [name for name in names if name not in connectors]
    if missing:
        raise ValueError(f"fmpy simulate_ssp records the SSD's connectors only; not among them: {missing}")
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
    return _run("fmpy simulate_ssp", step, stop_time, k, {name: r[name] for name in names}, seconds)


def ecospy_ssp(ssp: Path, step: float, stop_time: float, signals: Sequence[Signal]) -> Run:
    from ecospy import EcosLib, EcosSimulation

    EcosLib.set_log_level("warn")
    names = keys(signals)
    n = steps(step, stop_time)
    with tempfile.TemporaryDirectory(prefix="ecospy-") as tmp:
        result = Path(tmp) / "result.csv"
        sim = EcosSimulation(ssp_path=str(ssp), step_size=step)
        try:
            ids = [f"{c}::{v}" for c, v in signals]
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
    missing = [i for i in ids if i not in col]
    if missing:
        raise RuntimeError(f"ecospy's CSV has no column {missing} (header: {header})")
    return _run("ecospy", step, stop_time, rows[:, col["iterations"]],
                {name: rows[:, col[i]] for name, i in zip(names, ids)}, seconds)


def libcosim_ssp(ssp: Path, step: float, stop_time: float, signals: Sequence[Signal]) -> Run:
    """libcosimpy from the .ssp, in a child process (an fmi2Error aborts the process)."""
    names = keys(signals)
    with tempfile.TemporaryDirectory(prefix="libcosim-") as tmp:
        out = Path(tmp) / "run.npz"
        proc = subprocess.run([sys.executable, __file__, "libcosim", str(ssp), repr(step), repr(stop_time),
                               json.dumps([list(s) for s in signals]), str(out)],
                              capture_output=True, text=True, timeout=3600)
        if proc.returncode != 0 or not out.exists():
            last = (proc.stderr.strip().splitlines() or ["(no message)"])[-1]
            if last.startswith(MasterFailed.__name__ + ": "):
                raise MasterFailed(last.split(": ", 1)[1])
            raise RuntimeError(f"libcosimpy child exited with {proc.returncode}:\n{proc.stdout[-2000:]}\n{proc.stderr[-4000:]}")
        d = np.load(out)
        return _run("libcosimpy", step, stop_time, d["k"], {name: d[f"signal{i}"] for i, name in enumerate(names)},
                    float(d["seconds"]))


def _libcosim_child(ssp: str, step: float, stop_time: float, signals: Sequence[Signal], out: str) -> None:
    """Saves k, seconds and signal0, signal1, ... (in the order of `signals`) to `out` (.npz)."""
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
        found = [v.reference for v in ex.slave_variables(index[component]) if v.name.decode() == variable]
        if not found:
            raise RuntimeError(f"libcosim: {component} has no variable {variable}")
        return found[0]

    observer = CosimObserver.create_time_series(buffer_size=n + 16)
    ex.add_observer(observer)
    variables = [(index[c], reference(c, v)) for c, v in signals]
    for slave, vr in variables:
        observer.start_time_series(slave, vr, CosimVariableType.REAL)
    t0 = time.perf_counter()
    if not ex.simulate_until(target_time=n * h_ns):
        status = ex.status()
        raise MasterFailed(f"stops at t = {status.current_time / 1e9:g} s ({CosimExecutionState(status.state).name}): "
                           f"{get_last_error_message().strip()}")
    seconds = time.perf_counter() - t0
    series = []
    for slave, vr in variables:
        times, step_numbers, values = observer.time_series_real_samples(slave, vr, from_step=1, sample_count=n)
        if len(values) != n or step_numbers[-1] != n or times[-1] != n * h_ns:
            raise RuntimeError(f"libcosim observer returned {len(values)} samples, last step {step_numbers[-1:]}")
        series.append((np.asarray(step_numbers), np.asarray(values)))
    if any(not np.array_equal(k, series[0][0]) for k, _ in series):
        raise RuntimeError("libcosim observer returned different step numbers for the signals")
    np.savez(out, k=series[0][0], seconds=seconds, **{f"signal{i}": v for i, (_, v) in enumerate(series)})


def container_ports(signals: Sequence[Signal]) -> dict[str, str]:
    """{key: name of the container's OUTPUT port}: "Component_variable" (characters other than
    letters, digits and "_" made "_"), unique per signal."""
    ports = {key(s): re.sub(r"\W", "_", f"{s[0]}_{s[1]}") for s in signals}
    if len(set(ports.values())) != len(ports):
        raise ValueError(f"two signals would give the same container port: {ports}")
    return ports


def _container_csv(ssp: Path, signals: Sequence[Signal], order: Sequence[str] | None = None) -> tuple[str, list[str]]:
    """The fmucontainer CSV for the system of the .ssp: its components (FMU rows, in `order` if
    given), connections (LINK), parameter bindings (START) and the signals recorded (OUTPUT rows,
    ports named by `container_ports`)."""
    from fmpy.ssp.ssd import read_ssd

    system = read_ssd(str(ssp)).system
    components = {c.name: Path(c.source).name for c in system.elements}
    if len(set(components.values())) != len(components):
        raise ValueError("fmucontainer needs one file per instance; copy the FMU under another name")
    names = list(order) if order else list(components)
    if sorted(names) != sorted(components):
        raise ValueError(f"order {names} is not a permutation of the system's components {list(components)}")
    rows = ["rule;from_fmu;from_port;to_fmu;to_port"]
    rows += [f"FMU;{components[n]};;;" for n in names]
    rows += [f"LINK;{components[c.startElement]};{c.startConnector};{components[c.endElement]};{c.endConnector}"
             for c in system.connections]
    for name, value in ssp_parameters(ssp).items():
        component, variable = name.split(".", 1)
        rows.append(f"START;{components[component]};{variable};{value};")
    ports = container_ports(signals)
    for component, variable in signals:
        rows.append(f"OUTPUT;{components[component]};{variable};;{ports[key((component, variable))]}")
    return "\n".join(rows) + "\n", [components[n] for n in names]


def fmucontainer_command() -> list[str]:
    exe = Path(sys.executable).with_name("fmucontainer")
    return [str(exe)] if exe.exists() else [shutil.which("fmucontainer") or "fmucontainer"]


def build_container(ssp: Path, step: float, workdir: Path, signals: Sequence[Signal], sequential: bool = False,
                    order: Sequence[str] | None = None) -> Path:
    """Builds `workdir/<system>Container.fmu` (<system>: the SSD's name) from the FMUs inside the
    .ssp, its outputs the signals under the names `container_ports` gives them."""
    from fmpy.ssp.ssd import read_ssd

    text, files = _container_csv(ssp, signals, order)
    name = re.sub(r"\W", "_", read_ssd(str(ssp)).name) + "Container"
    with zipfile.ZipFile(ssp) as z:
        for f in files:
            (workdir / f).write_bytes(z.read(f"resources/{f}"))
    (workdir / f"{name}.csv").write_text(text)
    cmd = fmucontainer_command() + ["-container", f"{name}.csv:{step!r}", "-fmu-directory", str(workdir),
                                    "-no-auto-input", "-no-auto-output"]
    if sequential:
        cmd.append("-sequential")
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=workdir, timeout=600)
    fmu = workdir / f"{name}.fmu"
    if proc.returncode != 0 or not fmu.exists():
        raise RuntimeError(f"fmucontainer failed ({proc.returncode}):\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    return fmu


def fmucontainer_fmpy(ssp: Path, step: float, stop_time: float, signals: Sequence[Signal], sequential: bool = False,
                      order: Sequence[str] | None = None) -> Run:
    """The container FMU in fmpy. `order`: the order of the FMU rows, in which `-sequential` steps
    the components (default: the SSD's)."""
    from fmpy import simulate_fmu
    from fmpy.fmi1 import FMICallException

    ports = container_ports(signals)
    with tempfile.TemporaryDirectory(prefix="fmucontainer-") as tmp:
        fmu = build_container(ssp, step, Path(tmp), signals, sequential, order)
        t0 = time.perf_counter()
        try:
            r = simulate_fmu(str(fmu), stop_time=stop_time, output_interval=step, output=list(ports.values()))
        except FMICallException as e:  # an embedded FMU refused a step
            raise MasterFailed(f"stops: {str(e).rstrip('.')}") from e
        seconds = time.perf_counter() - t0
    name = "fmucontainer -sequential (fmpy)" if sequential else "fmucontainer (fmpy)"
    return _run(name, step, stop_time, np.rint(r["time"] / step), {k: r[port] for k, port in ports.items()}, seconds)


# How each master couples the FMUs (all hold an input constant over a step: none of them uses the
# FMUs' input derivatives).
SCHEMES = {
    "fmpy simulate_ssp": "fmpy 0.3.32 `simulate_ssp` on the .ssp (Jacobi)",
    "ecospy": "ecospy 0.7.2 on the .ssp (Jacobi)",
    "libcosimpy": "libcosimpy 0.0.6 on the .ssp (Jacobi)",
    "fmucontainer (fmpy)": "fmucontainer 2.0 container FMU in fmpy (parallel = Jacobi)",
    "fmucontainer -sequential (fmpy)": "fmucontainer 2.0 `-sequential` in fmpy (Gauss-Seidel)",
}

# master -> (ssp, step, stop_time, signals, order=None) -> Run. `order` (component names) is the
# order in which a sequential (Gauss-Seidel) master steps the components (default: the SSD's); the
# Jacobi masters step them all from the same inputs and ignore it.
MASTERS = {
    "fmpy simulate_ssp": lambda ssp, step, stop, signals, order=None: fmpy_ssp(ssp, step, stop, signals),
    "ecospy": lambda ssp, step, stop, signals, order=None: ecospy_ssp(ssp, step, stop, signals),
    "libcosimpy": lambda ssp, step, stop, signals, order=None: libcosim_ssp(ssp, step, stop, signals),
    "fmucontainer (fmpy)": lambda ssp, step, stop, signals, order=None: fmucontainer_fmpy(ssp, step, stop, signals),
    "fmucontainer -sequential (fmpy)": lambda ssp, step, stop, signals, order=None: fmucontainer_fmpy(
        ssp, step, stop, signals, sequential=True, order=order),
}


# ---------------------------------------------------------------------------------------------
# MotorFanSystem (dist/MotorFanSystem.ssp) against MotorFan.fmu: what test_coupled_masters.py and
# coupling_table.py record and compare

FAN = ("Fan", "fan_speed")  # rad/s
TORQUE = ("DriveShaft", "torque")  # N m, high-speed side
MOTOR_FAN_SIGNALS = (FAN, TORQUE)
MOTOR_FAN_START = {"level": 3, "start_mode": 1}  # MotorFan.fmu: level c, direct on line
MOTOR_FAN_OUTPUTS = {key(FAN): "fan_speed", key(TORQUE): "shaft_torque"}  # MotorFan.fmu's names
# Sequential: the shaft first (it needs both speeds), then both inertias with its fresh torque.
MOTOR_FAN_ORDER = ("DriveShaft", "InductionMotor", "Fan")


def motor_fan_reference(motor_fan_fmu: Path, step: float, stop_time: float) -> Run:
    """MotorFan.fmu (level=3, start_mode=1) with the keys of MotorFanSystem's signals."""
    return monolithic(motor_fan_fmu, step, stop_time, MOTOR_FAN_START, MOTOR_FAN_OUTPUTS)


def motor_fan_coupled(master: str, ssp: Path, step: float, stop_time: float) -> Run:
    """MotorFanSystem's fan speed and shaft torque from one of MASTERS (Gauss-Seidel in MOTOR_FAN_ORDER)."""
    return MASTERS[master](ssp, step, stop_time, MOTOR_FAN_SIGNALS, order=MOTOR_FAN_ORDER)


@dataclass
class Comparison:
    fan_error_pct: float  # max |coupled - monolithic| fan speed over the common points, % of rated
    worst_time: float  # where it is reached, s
    peak: float  # max |shaft torque| of the coupled run, N m
    peak_reference: float  # same for the monolithic run
    peak_error_pct: float  # (peak - peak_reference) / peak_reference, %
    points: int  # common output points compared
    rated: float  # rated fan speed: the monolithic final fan speed, rad/s


def compare(run: Run, reference: Run) -> Comparison:
    """MotorFanSystem: the fan speed error at every common output point (% of the rated speed, taken
    as the monolithic final fan speed) and the peak |shaft torque| of each run over its points."""
    fan, torque = key(FAN), key(TORQUE)
    rated = float(reference.values[fan][np.argmax(reference.k)])
    d = deviation(run, reference, fan, rated)
    p, p_ref = peak(run, torque), peak(reference, torque)
    return Comparison(d.error * 100.0, d.worst_time, p, p_ref, (p - p_ref) / p_ref * 100.0, d.points, rated)


if __name__ == "__main__":
    if len(sys.argv) == 7 and sys.argv[1] == "libcosim":
        signals = [tuple(s) for s in json.loads(sys.argv[5])]
        _libcosim_child(sys.argv[2], float(sys.argv[3]), float(sys.argv[4]), signals, sys.argv[6])
    else:
        sys.exit(f"usage: {os.path.basename(__file__)} libcosim SSP STEP STOP_TIME SIGNALS_JSON OUT.npz (internal)")
