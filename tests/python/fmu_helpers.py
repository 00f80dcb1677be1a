"""Helpers to drive the FMU through fmpy: a log capture and a thin FMU2Slave wrapper."""

import math
from ctypes import byref

import numpy as np
from fmpy import calloc, free
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2Real,
    fmi2ValueReference,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
    fmi2LastSuccessfulTime,
)

FMI2_STATUS = ["OK", "Warning", "Discard", "Error", "Fatal", "Pending"]
INPUTS = ("Fz", "alpha", "kappa", "gamma")
OUTPUTS = ("Fx", "Fy", "Mz")


class LogCapture:
    """Collects every message the FMU sends to its logger, tagged with the instance name.

    fmpy formats the FMU's printf-style message in a native proxy (fmpy.logging) that keeps
    ONE process-wide pointer to the Python callback, set by the last addLoggerProxy call.
    So there is one capture for the whole test session, with a ctypes thunk that lives as
    long as the process, and fmpy's default callbacks (used by simulate_fmu) end up here too.
    Never pass `logger=` to simulate_fmu in the tests: its thunk dies with the call and
    would leave the proxy pointing at freed memory.
    """

    def __init__(self):
        self.records = []  # (instance, status, category, message)
        self._thunk = fmi2CallbackLoggerTYPE(self._log)
        self.callbacks = fmi2CallbackFunctions()
        self.callbacks.logger = self._thunk
        self.callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        self.callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        from fmpy.logging import addLoggerProxy

        addLoggerProxy(byref(self.callbacks))

    def _log(self, env, instance, status, category, message):
        decode = lambda b: b.decode("utf-8", "replace") if b else ""
        self.records.append((decode(instance), status, decode(category), decode(message)))

    def of(self, instance, min_status=0):
        """(status, category, message) logged by `instance` with status >= min_status."""
        return [(s, c, m) for i, s, c, m in self.records if i == instance and s >= min_status]


LOG = LogCapture()


class Tire:
    """One FMU2Slave instance of the tire, addressed by variable names."""

    def __init__(self, unzipdir, model_description, name, logging_on=True):
        self.name = name
        self.md = model_description
        self.vars = {v.name: v for v in model_description.modelVariables}
        self.fmu = FMU2Slave(
            guid=model_description.guid,
            unzipDirectory=unzipdir,
            modelIdentifier=model_description.coSimulation.modelIdentifier,
            instanceName=name,
        )
        self.fmu.instantiate(callbacks=LOG.callbacks, loggingOn=logging_on)
        self.time = 0.0

    def vr(self, name):
        return self.vars[name].valueReference

    def set(self, **values):
        """Set variables by name; the setter follows the variable's type."""
        for name, value in values.items():
            kind = self.vars[name].type
            if kind == "Real":
                self.fmu.setReal([self.vr(name)], [float(value)])
            elif kind == "Boolean":
                self.fmu.setBoolean([self.vr(name)], [bool(value)])
            elif kind == "String":
                self.fmu.setString([self.vr(name)], [str(value)])
            else:
                raise TypeError(f"{name}: {kind}")

    def get(self, *names):
        return tuple(self.fmu.getReal([self.vr(n) for n in names]))

    def initialize(self, start_time=0.0, **parameters):
        """setupExperiment, parameters, enter and exit initialization mode."""
        self.fmu.setupExperiment(startTime=start_time)
        self.time = start_time
        self.set(**parameters)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()

    def step(self, h=0.01, **inputs):
        """Set `inputs`, then fmi2DoStep(time, h): the outputs after it belong to these inputs."""
        self.set(**inputs)
        self.fmu.doStep(currentCommunicationPoint=self.time, communicationStepSize=h)
        self.time += h
        return self.outputs()

    def set_real_status(self, vr, value):
        """fmi2SetReal of one value by value reference; returns the FMI status."""
        vrs, values = (fmi2ValueReference * 1)(vr), (fmi2Real * 1)(value)
        return call_status(self.fmu.fmi2SetReal, self.fmu.component, vrs, 1, values)

    def get_real_status(self, vr):
        """fmi2GetReal of one value by value reference; returns the FMI status."""
        vrs, values = (fmi2ValueReference * 1)(vr), (fmi2Real * 1)()
        return call_status(self.fmu.fmi2GetReal, self.fmu.component, vrs, 1, values)

    def outputs(self):
        return self.get(*OUTPUTS)

    def inputs(self):
        return self.get(*INPUTS)

    def last_successful_time(self):
        return self.fmu.getRealStatus(fmi2LastSuccessfulTime)

    def messages(self, min_status=0):
        return LOG.of(self.name, min_status)

    def free(self):
        self.fmu.freeInstance()


def call_status(function, *args):
    """Calls one of fmpy's raw fmi2* functions; returns the FMI status it gave.

    (fmpy returns OK and Warning and raises FMICallException for Discard and worse.)
    """
    try:
        return function(*args)
    except FMICallException as e:
        return e.status


def deg(x):
    return math.radians(x)


def applied_inputs(result, signals):
    """The inputs behind each recorded row of an fmpy co-simulation result.

    fmpy's co-simulation loop, at each communication point t_k: set the inputs
    interpolated at t_k, call fmi2DoStep(t_k, h), record the outputs at t_{k+1}. So row
    k >= 1 (time t_k) holds the outputs for the inputs applied at t_{k-1}, one step of
    delay, and row 0 the outputs computed in initialization from the inputs at t_0.
    """
    t = result["time"]
    t_applied = np.concatenate(([t[0]], t[:-1]))
    return {n: np.interp(t_applied, signals["time"], signals[n]) for n in INPUTS}


def input_signals(time, **columns):
    """A structured array with 'time' and the four inputs (constants are broadcast)."""
    time = np.asarray(time, dtype=float)
    dtype = [("time", float)] + [(n, float) for n in INPUTS]
    signals = np.zeros(time.shape, dtype=dtype)
    signals["time"] = time
    for n in INPUTS:
        signals[n] = columns[n]
    return signals
