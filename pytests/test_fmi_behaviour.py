"""FMI behaviour through fmpy: start values, errors with messages, calling sequence, instances."""
import fmpy
import numpy as np
import pytest
from fmpy.fmi2 import fmi2Error

from helpers import Session, static_outputs


def test_user_example_from_the_issue(fmus):
    r = fmpy.simulate_fmu(
        fmus["cantilever"], start_values={"mesh.n_elements": 32, "load.fy": -5e5, "solver.static_equilibrium": True}
    )
    # 1x2 rule (default) close to the paper's Table 3 at 32 elements: (1.85497, -0.68100)
    assert abs(r["tip.x"][0] - 1.85497) < 1e-3 and abs(r["tip.y"][0] + 0.68100) < 1e-3
    # in equilibrium it stays there
    assert np.ptp(r["tip.y"]) < 1e-8


def test_start_values_override_parameters(fmus):
    base = {"load.fy": -1000.0}
    (y1,) = static_outputs(fmus["simply_supported"], base, ["mid.y"])
    (y2,) = static_outputs(fmus["simply_supported"], {**base, "material.E": 2.07e11 / 2}, ["mid.y"])
    assert abs(y2 / y1 - 2.0) < 1e-6
    (y3,) = static_outputs(fmus["simply_supported"], {**base, "geometry.length": 1.0}, ["mid.y"])
    assert abs(y3 / y1) < 0.2


def _init(s, **reals):
    s.slave.setupExperiment(startTime=0.0)
    for k, v in reals.items():
        s.slave.setReal([s.vr[k]], [v])
    s.slave.enterInitializationMode()
    s.slave.exitInitializationMode()


@pytest.mark.parametrize(
    "setter,name,value,needle",
    [
        ("setReal", "material.E", -1.0, "material.E"),
        ("setReal", "material.nu", 0.5, "material.nu"),
        ("setInteger", "mesh.n_elements", 0, "mesh.n_elements"),
    ],
)
def test_bad_parameters_give_error_and_message(fmus, setter, name, value, needle):
    s = Session(fmus["cantilever"])
    try:
        getattr(s.slave, setter)([s.vr[name]], [value])
        with pytest.raises(Exception):
            _init(s)
        assert any(needle in m for m in s.errors()), s.messages
    finally:
        s.close()


def test_nan_input_is_an_error(fmus):
    s = Session(fmus["cantilever"])
    try:
        _init(s)
        with pytest.raises(Exception):
            s.slave.setReal([s.vr["load.fy"]], [float("nan")])
        assert any("load.fy" in m for m in s.errors())
    finally:
        s.close()


def test_unknown_value_reference_is_an_error(fmus):
    s = Session(fmus["cantilever"])
    try:
        _init(s)
        with pytest.raises(Exception):
            s.slave.getReal([123456])
        assert any("unknown value reference 123456" in m for m in s.errors())
    finally:
        s.close()


def test_wrong_call_order_is_an_error(fmus):
    s = Session(fmus["pendulum"])
    try:
        with pytest.raises(Exception) as e:
            s.slave.doStep(0.0, 1e-3)
        assert getattr(e.value, "status", fmi2Error) == fmi2Error
        assert any("fmi2DoStep is not allowed" in m for m in s.errors())
        # the instance survives and can be reset
        s.slave.reset()
        _init(s)
        s.slave.doStep(0.0, 1e-3)
    finally:
        s.close()


def test_wrong_guid_fails_instantiation(fmus):
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    md = read_model_description(fmus["pendulum"])
    d = extract(fmus["pendulum"])
    sl = FMU2Slave(guid="{00000000-0000-0000-0000-000000000000}", unzipDirectory=d, modelIdentifier="pendulum")
    with pytest.raises(Exception):
        sl.instantiate()
    assert md.guid != "{00000000-0000-0000-0000-000000000000}"


def test_debug_logging_categories(fmus):
    s = Session(fmus["cantilever"], logging_on=True)
    try:
        s.slave.setDebugLogging(True, ["logEvents"])
        _init(s)
        assert any(c == "logEvents" for (_, c, _) in s.messages)
    finally:
        s.close()


def test_two_instances_are_independent(fmus):
    a, b = Session(fmus["simply_supported"], instance_name="a"), Session(fmus["simply_supported"], instance_name="b")
    try:
        for s, e in [(a, 2.07e11), (b, 1.035e11)]:
            s.slave.setReal([s.vr["material.E"], s.vr["load.fy"]], [e, -1000.0])
            s.slave.setBoolean([s.vr["solver.static_equilibrium"]], [True])
            s.slave.setupExperiment(startTime=0.0)
            s.slave.enterInitializationMode()
        for s in (a, b):
            s.slave.exitInitializationMode()
        ya, yb = a.slave.getReal([a.vr["mid.y"]])[0], b.slave.getReal([b.vr["mid.y"]])[0]
        assert abs(yb / ya - 2.0) < 1e-6
    finally:
        a.close()
        b.close()
