"""fmpy helpers for the tests: static runs, FMU2Slave sessions with a capturing logger."""
import shutil
import tempfile
from ctypes import byref

import fmpy
from fmpy import extract, read_model_description
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)
from fmpy.logging import addLoggerProxy
from fmpy.fmi1 import calloc, free

LEVELS = ["OK", "WARNING", "DISCARD", "ERROR", "FATAL", "PENDING"]

_CALLBACKS = []


def static_outputs(fmu, start_values, names):
    """Outputs right after initialization (t = 0) with solver.static_equilibrium = True."""
    sv = dict(start_values)
    sv["solver.static_equilibrium"] = True
    res = fmpy.simulate_fmu(fmu, start_values=sv, stop_time=1e-4, output_interval=1e-4, output=names)
    return [float(res[n][0]) for n in names]


class Session:
    """An FMU2Slave with a logger that records (status, category, message)."""

    def __init__(self, fmu, logging_on=False, instance_name="inst"):
        self.md = read_model_description(fmu)
        self.dir = extract(fmu, unzipdir=tempfile.mkdtemp())
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.messages = []
        self.slave = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=self.dir,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=instance_name,
        )
        cb = fmi2CallbackFunctions()

        def log(env, name, status, category, message):
            self.messages.append((LEVELS[status], category.decode(), message.decode()))

        cb.logger = fmi2CallbackLoggerTYPE(log)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        addLoggerProxy(byref(cb))
        # fmpy's logger proxy keeps the last registered callback in a C global: keep every
        # callback alive for the whole test session, not just for this Session.
        _CALLBACKS.append(cb)
        self._cb = cb
        self.slave.instantiate(callbacks=cb, loggingOn=logging_on)

    def errors(self):
        return [m for (s, _, m) in self.messages if s in ("ERROR", "DISCARD", "FATAL")]

    def close(self):
        try:
            self.slave.freeInstance()
        finally:
            shutil.rmtree(self.dir, ignore_errors=True)
