"""Belt-drive FMUs under fmpy: static pre-load, parameters, the seed-000 belt element, errors,
and the co-simulation with MuJoCo against the pulley inertias inside the FMU."""
import pathlib
import sys

import fmpy
import numpy as np
import pytest

from helpers import Session

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "scripts"))

# fmpy's C logger proxy (addLoggerProxy, used by helpers.Session) keeps the last registered Python
# logger in a global; a Session whose callback is garbage-collected leaves it dangling and a later
# FMU that logs through the proxy crashes. Sessions of this module stay referenced.
_KEEP_ALIVE = []

OUT = ["belt.tension_tight", "belt.tension_slack", "pulley1.force_x", "pulley1.force_y", "pulley1.torque"]


def at_rest(fmu, start_values=None):
    r = fmpy.simulate_fmu(fmu, stop_time=2e-3, output_interval=1e-3, start_values=start_values or {}, output=OUT)
    return {n: float(r[n][0]) for n in OUT}


def test_static_preload_has_the_pretension(fmus):
    r = at_rest(fmus["belt_drive"])
    for n in ("belt.tension_tight", "belt.tension_slack"):
        assert abs(r[n] - 300.0) < 0.3, (n, r[n])
    # the belt pulls pulley 1 towards pulley 2 with both spans: about 2 T0 along +x
    assert abs(r["pulley1.force_x"] - 600.0) < 6.0, r
    assert abs(r["pulley1.force_y"]) < 3.0 and abs(r["pulley1.torque"]) < 0.05, r


def test_start_values_change_pretension_and_geometry(fmus):
    r = at_rest(fmus["belt_drive"], {"belt.pretension": 200.0, "pulleys.center_distance": 0.6,
                                      "belt.n_elements": 80})
    for n in ("belt.tension_tight", "belt.tension_slack"):
        assert abs(r[n] - 200.0) < 0.2, (n, r[n])


def test_seed000_element_is_selectable_as_belt(fmus):
    r = at_rest(fmus["belt_drive"], {"belt.element": 2})
    for n in ("belt.tension_tight", "belt.tension_slack"):
        assert abs(r[n] - 300.0) < 3.0, (n, r[n])
    # and it runs: driver at 10 rad/s for 50 ms
    sv = {"belt.element": 2}
    inp = np.array([(0.0, 0.0, 0.0), (0.05, 0.5, 10.0)],
                   dtype=[("time", float), ("pulley1.angle", float), ("pulley1.omega", float)])
    res = fmpy.simulate_fmu(fmus["belt_drive"], stop_time=0.05, output_interval=1e-3, start_values=sv,
                            input=inp, output=["pulley2.omega"])
    assert res["pulley2.omega"][-1] > 1.0


def test_impossible_layout_is_an_error_with_a_message(fmus):
    s = Session(fmus["belt_drive"], logging_on=True)
    _KEEP_ALIVE.append(s)
    try:
        sl = s.slave
        sl.setupExperiment(startTime=0.0)
        sl.enterInitializationMode()
        sl.setReal([s.vr["pulleys.center_distance"]], [0.03])
        with pytest.raises(Exception):
            sl.exitInitializationMode()
        assert any("centre distance" in m for m in s.errors()), s.messages
    finally:
        s.close()


def test_mujoco_cosimulation_agrees_with_internal_inertias(fmus):
    """Item 6: explicit exchange at 0.25 ms; steady speeds and torques within 1 % (measured 5e-5).
    Since the bristle is k_n/10 (issue 12, creep) the pulley-on-belt frequency is higher and the
    explicit exchange at 1 ms goes unstable (speeds off by a factor 3; 0.5 ms: 12 %)."""
    import cosim_mujoco

    a, b, rel = cosim_mujoco.compare(t_end=0.8, h=2.5e-4)
    assert b[1] > 5.0 and b[3] > 1.0, b  # the drive runs and transmits torque
    assert (rel < 0.01).all(), (a, b, rel)


@pytest.mark.parametrize("name,tension,free", [("belt_drive", "belt.tension_tight", "pulley2.omega"),
                                                ("serpentine", "span1.tension", "pulley6.omega"),
                                                ("belt_drive_3d", "belt.tension_tight", "pulley2.omega")])
def test_driven_pulley_started_at_speed_initializes(fmus, name, tension, free):
    """A master that starts the driven pulley at speed (start value `pulley1.omega` = 20 rad/s;
    planar, serpentine and 3D drives)
    with the scene's `solver.static_equilibrium = true`: the static solve is the belt at rest
    (before the fix it made the friction slide at the pulley's speed and
    `fmi2ExitInitializationMode` failed with "static equilibrium not found"). At t = 0 the
    tension is the pre-load's (started at rest); then the belt carries the pulley's start."""
    rest = fmpy.simulate_fmu(fmus[name], stop_time=1e-3, output_interval=1e-3, output=[tension])
    r = fmpy.simulate_fmu(fmus[name], stop_time=0.03, output_interval=1e-3,
                          start_values={"pulley1.omega": 20.0}, output=[tension, free])
    assert abs(r[tension][0] - rest[tension][0]) <= 1e-3 * abs(rest[tension][0]), (r[tension][0], rest[tension][0])
    # the free pulley is dragged along (its sense depends on the wrap side: front pulleys turn
    # with the crank)
    assert r[free][-1] > 1.0, r[free][-1]
