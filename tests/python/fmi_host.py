"""A thin wrapper around fmpy.fmi2.FMU2Slave for the tests that drive the FMI API directly.

Value references are always looked up by variable NAME in modelDescription.xml (never hard-coded).
The FMU's log messages are collected with a non-variadic host logger (the spec promises that
messages arrive pre-formatted, with every '%' doubled, and no variadic arguments).
"""

from __future__ import annotations

import shutil
from ctypes import byref, c_void_p
from pathlib import Path

from fmpy import extract, read_model_description
from fmpy import calloc, free
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)


class LogCollector:
    """Host logger that records (status, category, message) without interpreting '%' sequences."""

    def __init__(self):
        self.records: list[tuple[int, str, str]] = []
        self._cb = fmi2CallbackLoggerTYPE(self._log)  # keep the ctypes thunk alive

    def _log(self, env, instance_name, status, category, message):
        self.records.append((
            int(status),
            (category or b"").decode("utf-8", "replace"),
            (message or b"").decode("utf-8", "replace"),
        ))

    def callbacks(self, memory_functions: bool = True) -> fmi2CallbackFunctions:
        cb = fmi2CallbackFunctions()
        cb.logger = self._cb
        if memory_functions:
            # libc calloc/free, as fmpy's default callbacks (the struct keeps the thunks alive)
            cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
            cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        else:
            cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE()  # NULL function pointer
            cb.freeMemory = fmi2CallbackFreeMemoryTYPE()
        # stepFinished and componentEnvironment stay NULL
        return cb


class Slave:
    """One co-simulation instance of an FMU (extracted to its own temporary directory unless
    `unzipdir` is given, e.g. to share one extraction between several instances)."""

    def __init__(self, fmu_path: Path, instance_name: str = "instance", unzipdir: str | None = None):
        self.md = read_model_description(str(fmu_path))
        assert self.md.coSimulation is not None, f"{fmu_path.name} has no CoSimulation element"
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.var = {v.name: v for v in self.md.modelVariables}
        self._own_dir = unzipdir is None
        self.unzipdir = extract(str(fmu_path)) if unzipdir is None else unzipdir
        self.log = LogCollector()
        self.fmu = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=self.unzipdir,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=instance_name,
        )
        self.instantiated = False
        self.initialized = False

    # ---- lifecycle ----
    def instantiate(self, logging_on: bool = False):
        self.fmu.instantiate(callbacks=self.log.callbacks(), loggingOn=logging_on)
        self.instantiated = True
        return self

    def initialize(self, start_time: float = 0.0, stop_time: float | None = None, start_values: dict | None = None):
        """setupExperiment, set start values (by name), enter/exit initialization mode."""
        self.fmu.setupExperiment(startTime=start_time, stopTime=stop_time)
        if start_values:
            self.set(**start_values)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        self.initialized = True
        return self

    def close(self):
        if self.instantiated:
            try:
                if self.initialized:  # fmi2Terminate is not allowed in the Instantiated state
                    self.initialized = False
                    self.fmu.terminate()
            finally:
                self.fmu.freeInstance()  # also unloads (dlclose) the shared library
                self.instantiated = False
        if self._own_dir:
            shutil.rmtree(self.unzipdir, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # ---- values by name ----
    def get(self, *names: str) -> list[float]:
        return self.fmu.getReal([self.vr[n] for n in names])

    def set(self, **values: float):
        names = list(values)
        self.fmu.setReal([self.vr[n] for n in names], [float(values[n]) for n in names])

    def do_step(self, t: float, h: float):
        self.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)

    def get_state_into(self, state: c_void_p) -> c_void_p:
        """fmi2GetFMUstate with an existing (non-NULL) state: the FMU must copy into it (FMI 2.0 §2.1.8)."""
        self.fmu.fmi2GetFMUstate(self.fmu.component, byref(state))
        return state


def state_jacobian(fmu_path, states, overrides: dict | None = None, relative_step: float = 1e-6):
    """The FMU's Jacobian d(der(x))/dx of the named states at the initial point (Model Exchange,
    after initialization and event iteration), by central differences of fmi2GetDerivatives with
    steps of `relative_step` times each state's nominal (1 where undeclared). `overrides`: start
    values set before initialization (Integer or Real by the variable's type). Rows and columns
    follow `states`. An independent check of the FMU's own equations, not of its directional
    derivatives."""
    from ctypes import c_double

    import numpy as np
    from fmpy.fmi2 import FMU2Model

    md = read_model_description(str(fmu_path))
    unzipped = extract(str(fmu_path))
    m = FMU2Model(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.modelExchange.modelIdentifier, instanceName="lin")
    variables = {v.name: v for v in md.modelVariables}
    m.instantiate()
    try:
        m.setupExperiment(startTime=0.0)
        for name, value in (overrides or {}).items():
            v = variables[name]
            if v.type in ("Integer", "Enumeration"):
                m.setInteger([v.valueReference], [int(value)])
            else:
                m.setReal([v.valueReference], [float(value)])
        m.enterInitializationMode()
        m.exitInitializationMode()
        while m.newDiscreteStates()[0]:
            pass
        m.enterContinuousTimeMode()
        order = [d.variable.derivative.name for d in md.derivatives]
        n = len(order)
        x0 = (c_double * n)()
        m.getContinuousStates(x0, n)
        rows = [order.index(s) for s in states]
        jac = np.zeros((len(states), len(states)))
        for j, s in enumerate(states):
            h = relative_step * float(variables[s].nominal or 1.0)
            cols = []
            for sign in (1.0, -1.0):
                x = (c_double * n)(*x0)
                x[rows[j]] += sign * h
                m.setContinuousStates(x, n)
                dx = (c_double * n)()
                m.getDerivatives(dx, n)
                cols.append(np.array([dx[r] for r in rows]))
            jac[:, j] = (cols[0] - cols[1]) / (2 * h)
        return jac
    finally:
        m.terminate()
        m.freeInstance()
        shutil.rmtree(unzipped, ignore_errors=True)
