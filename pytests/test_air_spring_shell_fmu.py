"""The air spring's shell level (issue 11, level 1: scenes/air_spring.toml) end to end through
fmpy: validation, agreement with the membrane level at the design state, the 5 x 5 port block of
fmi2GetDirectionalDerivative against differences of static re-initializations, symmetry, a
vertical sine run with its energy balance, a tilt, state round trips and bad inputs.

Conventions: the plate pose (top.x, top.y, top.z [m], top.rx, top.ry [rad], the tilt as the
rotation vector (rx, ry, 0) about the plate centre); forces and moments of the spring on the plate
(top.fx, top.fy, top.fz [N], top.mx, top.my [N m] about the plate centre)."""
import math

import numpy as np
import pytest
from fmpy.validation import validate_fmu

from helpers import Session
from test_air_spring_fmu import DESIGN_HEIGHT, STEP, get, start

NAME = "air_spring"
POSE = ["top.x", "top.y", "top.z", "top.rx", "top.ry"]
RATES = ["top.vx", "top.vy", "top.vz", "top.wx", "top.wy"]
LOADS = ["top.fx", "top.fy", "top.fz", "top.mx", "top.my"]
ENERGIES = ["energy.gas", "energy.strain", "energy.kinetic", "energy.plate_work", "energy.dissipated"]


def test_fmpy_validate(fmus):
    assert validate_fmu(fmus[NAME]) == []


def static_loads(fmu, pose):
    s = Session(fmu)
    try:
        start(s, dict(zip(POSE, pose)))
        return np.array(get(s, LOADS))
    finally:
        s.close()


def test_design_state_agrees_with_the_membrane_level(fmus):
    """Issue 11: levels 1 and 2 agree on vertical force within 1 % (here at the design height,
    the shipped scenes: 16 x 40 shell elements against 60 membrane elements); no lateral force or
    moment on the symmetric spring."""
    f1 = static_loads(fmus[NAME], [0.0, 0.0, DESIGN_HEIGHT, 0.0, 0.0])
    s = Session(fmus["air_spring_axisym"])
    try:
        start(s)
        f2 = get(s, ["top.fz"])[0]
    finally:
        s.close()
    assert abs(f1[2] / f2 - 1.0) < 0.01, (f1, f2)
    assert np.abs(f1[[0, 1]]).max() < 1e-6 * f2
    assert np.abs(f1[[3, 4]]).max() < 1e-6 * f2 * 0.14


@pytest.mark.parametrize("pose", [[0.0, 0.0, DESIGN_HEIGHT, 0.0, 0.0], [0.003, 0.0, 0.24, 0.0, 0.01]])
def test_port_block_is_the_static_stiffness(fmus, pose):
    """fmi2GetDirectionalDerivative of (fx, fy, fz, mx, my) with respect to (x, y, z, rx, ry) at
    rest = central differences over static re-initializations (closed gas), column by column."""
    fmu = fmus[NAME]
    s = Session(fmu)
    try:
        start(s, dict(zip(POSE, pose)))
        block = np.array([
            s.slave.getDirectionalDerivative([s.vr[o] for o in LOADS], [s.vr[i]], [1.0]) for i in POSE
        ]).T
        stiffness = get(s, ["spring.stiffness"])[0]
    finally:
        s.close()
    steps = [2e-5, 2e-5, 2e-5, 2e-4, 2e-4]
    for j, h in enumerate(steps):
        plus, minus = list(pose), list(pose)
        plus[j] += h
        minus[j] -= h
        fd = (static_loads(fmu, plus) - static_loads(fmu, minus)) / (2 * h)
        scale = np.abs(block[:, j]).max()
        assert np.abs(fd - block[:, j]).max() < 2e-3 * scale, (POSE[j], fd, block[:, j])
    assert stiffness == -block[2, 2]
    assert block[2, 2] < 0.0 and block[0, 0] < 0.0 and block[3, 3] < 0.0  # restoring


def test_tilt_responses_are_symmetric(fmus):
    """Turning the tilt from about x to about y turns the loads with it (the mesh has a
    16-fold symmetry: a quarter turn maps it onto itself)."""
    a = static_loads(fmus[NAME], [0.0, 0.0, DESIGN_HEIGHT, 0.01, 0.0])
    b = static_loads(fmus[NAME], [0.0, 0.0, DESIGN_HEIGHT, 0.0, 0.01])
    scale = abs(a[3])
    assert scale > 10.0
    # (fx, fy, mx, my) of a -> (-fy, fx, -my, mx) of b under the quarter turn about z
    assert abs(a[2] - b[2]) < 1e-8 * abs(a[2])
    assert abs(a[3] - b[4]) < 1e-6 * scale and abs(a[4] + b[3]) < 1e-6 * scale
    assert abs(a[1] + b[0]) < 1e-6 * abs(a[1]) + 1e-9 and abs(a[0] - b[1]) < 1e-6 * abs(a[1]) + 1e-9


# 5 mm at 5 Hz over a tenth of a second: a half stroke of 10 mm
AMP, FREQ, N_STEPS = 0.005, 5.0, 100


def sine(t):
    return DESIGN_HEIGHT + AMP * math.sin(2 * math.pi * FREQ * t)


def drive(s, k0, k1, names, tilt=0.0):
    rows = []
    for k in range(k0, k1):
        t = k * STEP
        z0, z1 = sine(t), sine(t + STEP)
        r0, r1 = tilt * math.sin(2 * math.pi * FREQ * t), tilt * math.sin(2 * math.pi * FREQ * (t + STEP))
        s.slave.setReal([s.vr["top.z"], s.vr["top.vz"], s.vr["top.rx"], s.vr["top.wx"]],
                        [z0, (z1 - z0) / STEP, r0, (r1 - r0) / STEP])
        s.slave.doStep(currentCommunicationPoint=t, communicationStepSize=STEP)
        rows.append(get(s, names))
    return np.array(rows)


@pytest.fixture(scope="module")
def sine_run(fmus):
    s = Session(fmus[NAME])
    names = LOADS + ENERGIES + ["spring.height", "gas.pressure_gauge", "spring.effective_area"]
    try:
        start(s)
        first = np.array(get(s, names))
        rows = drive(s, 0, N_STEPS, names, tilt=0.005)
    finally:
        s.close()
    return {o: np.concatenate([[first[i]], rows[:, i]]) for i, o in enumerate(names)}


def test_sine_run_follows_the_input(sine_run):
    d = sine_run
    t = np.arange(N_STEPS + 1) * STEP
    assert np.abs(d["spring.height"] - np.array([sine(x) for x in t])).max() < 1e-12
    assert np.all(np.isfinite(np.array(list(d.values()))))
    # compression (the first quarter period: the plate rises) lowers the force
    assert d["top.fz"][50] < d["top.fz"][0] - 500.0
    # the tilt about x brings a restoring moment about x
    k = np.argmax(np.abs(d["top.mx"]))
    assert abs(d["top.mx"][k]) > 10.0


# Numerical part of the energy balance relative to the largest plate work over the run (measured
# with the shipped scene, 16 x 40 elements, 1 ms: 9.1e-3 J of 105 J, 8.6e-5).
ENERGY_TOLERANCE = 3e-4


def test_energy_balance(sine_run):
    """plate work (force and moment) = change of (gas + strain + kinetic) + dissipated + numerical."""
    d = sine_run
    stored = d["energy.gas"] + d["energy.strain"] + d["energy.kinetic"]
    numerical = d["energy.plate_work"] - (stored - stored[0]) - d["energy.dissipated"]
    scale = np.abs(d["energy.plate_work"]).max()
    print(f"shell: plate work up to {scale:.3f} J, numerical part up to {np.abs(numerical).max():.3e} J "
          f"({np.abs(numerical).max() / scale:.2e} of it)")
    assert scale > 10.0
    assert np.abs(numerical).max() < ENERGY_TOLERANCE * scale


def test_fmu_state_round_trip_continues_exactly(fmus):
    a, b = Session(fmus[NAME], instance_name="a"), Session(fmus[NAME], instance_name="b")
    try:
        start(a)
        start(b)
        drive(a, 0, 10, LOADS, tilt=0.005)
        state = a.slave.getFMUstate()
        data = a.slave.serializeFMUstate(state)
        expected = drive(a, 10, 20, LOADS, tilt=0.005)
        a.slave.setFMUstate(state)
        a.slave.freeFMUstate(state)
        again = drive(a, 10, 20, LOADS, tilt=0.005)
        restored = b.slave.deSerializeFMUstate(data)
        b.slave.setFMUstate(restored)
        b.slave.freeFMUstate(restored)
        other = drive(b, 10, 20, LOADS, tilt=0.005)
    finally:
        a.close()
        b.close()
    assert np.array_equal(again, expected)
    assert np.array_equal(other, expected)
    assert np.ptp(expected[:, 2]) > 10.0


@pytest.mark.parametrize("var", POSE + RATES)
def test_nan_input_is_an_error(fmus, var):
    s = Session(fmus[NAME])
    try:
        start(s)
        with pytest.raises(Exception):
            s.slave.setReal([s.vr[var]], [float("nan")])
        assert any(var in m for m in s.errors()), s.messages
    finally:
        s.close()
