"""FMU state, serialization, directional derivatives, input and output derivatives through fmpy,
and the two example masters under scripts/."""
import pathlib
import subprocess
import sys

import fmpy
import numpy as np
import pytest

from helpers import Session

ROOT = pathlib.Path(__file__).resolve().parents[1]


def init(s, **reals):
    s.slave.setupExperiment(startTime=0.0)
    for k, v in reals.items():
        s.slave.setReal([s.vr[k]], [v])
    s.slave.enterInitializationMode()
    s.slave.exitInitializationMode()


def outputs(s, names):
    return s.slave.getReal([s.vr[n] for n in names])


def run(s, t0, n, h):
    for k in range(n):
        s.slave.doStep(t0 + k * h, h)
    return t0 + n * h


def test_capability_flags(fmus):
    for name in ("cantilever", "cantilever_motion", "simply_supported", "pendulum"):
        cs = fmpy.read_model_description(fmus[name]).coSimulation
        assert cs.canGetAndSetFMUstate and cs.canSerializeFMUstate and cs.providesDirectionalDerivative
        assert cs.canInterpolateInputs and cs.maxOutputDerivativeOrder == 1
        assert cs.canHandleVariableCommunicationStepSize


def test_rollback_is_bit_exact(fmus):
    names = ["tip.x", "tip.y", "energy.total"]
    s = Session(fmus["pendulum"])
    try:
        init(s)
        t = run(s, 0.0, 20, 0.01)
        state = s.slave.getFMUstate()
        run(s, t, 20, 0.01)
        first = outputs(s, names)
        s.slave.setFMUstate(state)
        run(s, t, 20, 0.01)
        assert outputs(s, names) == first  # bit for bit
        s.slave.freeFMUstate(state)
    finally:
        s.close()


def test_serialized_state_continues_in_another_instance(fmus):
    names = ["tip.x", "tip.y"]
    a, b = Session(fmus["pendulum"], instance_name="a"), Session(fmus["pendulum"], instance_name="b")
    try:
        init(a)
        t = run(a, 0.0, 10, 0.01)
        state = a.slave.getFMUstate()
        data = a.slave.serializeFMUstate(state)
        a.slave.freeFMUstate(state)
        run(a, t, 10, 0.01)
        expected = outputs(a, names)
        restored = b.slave.deSerializeFMUstate(data)
        b.slave.setFMUstate(restored)
        b.slave.freeFMUstate(restored)
        run(b, t, 10, 0.01)
        assert outputs(b, names) == expected
        # truncated and corrupted buffers are rejected with a message
        with pytest.raises(Exception):
            b.slave.deSerializeFMUstate(data[: len(data) // 2])
        assert any("truncated" in m for m in b.errors())
    finally:
        a.close()
        b.close()


def test_directional_derivative_of_the_motion_port(fmus):
    s = Session(fmus["cantilever_motion"])
    try:
        init(s)
        s.slave.setReal([s.vr["tip.vy"]], [-1.0])
        run(s, 0.0, 5, 1e-3)
        d = s.slave.getDirectionalDerivative([s.vr["tip.fx"], s.vr["tip.fy"]], [s.vr["tip.y"]], [1.0])
        assert d[1] < -1e6  # the beam resists a displacement of its tip (stiffer than statically)
        # no direct feedthrough from a load-free quantity: the mid probe does not depend on inputs
        dm = s.slave.getDirectionalDerivative([s.vr["mid.y"]], [s.vr["tip.y"]], [1.0])
        assert dm == [0.0]
    finally:
        s.close()


def test_output_derivatives(fmus):
    s = Session(fmus["pendulum"])
    try:
        init(s)
        run(s, 0.0, 30, 0.01)
        vrs = [s.vr["tip.y"], s.vr["energy.total"], s.vr["energy.kinetic"]]
        d = s.slave.getRealOutputDerivatives(vrs, [1, 1, 1])
        y0 = outputs(s, ["tip.y"])[0]
        state = s.slave.getFMUstate()
        s.slave.doStep(0.3, 1e-4)
        y1 = outputs(s, ["tip.y"])[0]
        s.slave.setFMUstate(state)
        assert abs(d[0] - (y1 - y0) / 1e-4) < 0.02 * abs(d[0])
        assert abs(d[1]) < 1e-6 * abs(d[2])  # conservative: dE/dt = 0 while energy moves
    finally:
        s.close()


def test_input_derivatives_improve_a_coarse_coupling(fmus):
    """A master that hands the slope of a ramped load to the FMU (fmi2SetRealInputDerivatives)
    gets at a coarse communication step what a fine step gives without it. (fmpy's own
    set_input_derivatives=True cannot be used: fmpy 0.3.32 sizes its derivative buffer for
    exactly 9 inputs.)"""

    def load(t):
        return -2e5 * min(t / 0.004, 1.0)

    def slope(t):
        return -2e5 / 0.004 if t < 0.004 - 1e-12 else 0.0

    def sim(h, derivatives):
        s = Session(fmus["cantilever"])
        try:
            s.slave.setupExperiment(startTime=0.0)
            s.slave.setReal([s.vr["solver.max_step"]], [1e-4])
            s.slave.enterInitializationMode()
            s.slave.exitInitializationMode()
            n = int(round(0.01 / h))
            for k in range(n):
                t = k * h
                s.slave.setReal([s.vr["load.fy"]], [load(t)])
                if derivatives:
                    s.slave.setRealInputDerivatives([s.vr["load.fy"]], [1], [slope(t)])
                s.slave.doStep(t, h)
            return s.slave.getReal([s.vr["tip.y"]])[0]
        finally:
            s.close()

    fine = sim(1e-4, True)
    with_d = sim(1e-3, True)
    without = sim(1e-3, False)
    assert abs(with_d - fine) < 0.2 * abs(without - fine), (fine, with_d, without)


def test_implicit_coupling_example():
    r = subprocess.run([sys.executable, str(ROOT / "scripts" / "implicit_coupling.py"), "--t-end", "0.4"],
                       capture_output=True, text=True, check=True)
    lines = {line.split(":")[0]: line for line in r.stdout.splitlines()}
    assert "DIVERGED" in lines["explicit, h = 1 ms"]
    imp = lines["implicit, h = 1 ms"]
    assert "completed" in imp
    deviation = float(imp.split("reference = ")[1].split(" %")[0])
    assert deviation < 3.0, imp


def test_variable_step_master_example():
    r = subprocess.run([sys.executable, str(ROOT / "scripts" / "variable_step_master.py"), "--tol", "1e-4"],
                       capture_output=True, text=True, check=True)
    first = r.stdout.splitlines()[0]
    rejected = int(first.split(" rejected")[0].split(", ")[-1])
    assert rejected > 0, first  # the example exercises rollback
    diff = float(r.stdout.split("difference ")[1].split(" m")[0])
    assert diff < 5e-3, r.stdout
