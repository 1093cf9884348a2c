"""Seed-003 co-rotational 3D beam FMUs under fmpy: static beam theory, the 45-degree bend, the
pure-moment roll-up, the right-angle cantilever against the published curves, parameter
overrides and errors."""
import math
import pathlib
import sys

import numpy as np
import pytest

from helpers import Session, static_outputs

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "scripts"))
import plot_right_angle  # noqa: E402

EI = 1649.34  # cantilever3d default, N m2
KGA = 2.28368e7  # N


def test_cantilever3d_small_tip_force_matches_beam_theory(fmus):
    p = 0.01
    y, rz = static_outputs(fmus["cantilever3d"], {"load.fy": p}, ["tip.y", "tip.rz"])
    assert abs(y - (p / (3 * EI) + p / KGA)) < 1e-5 * y
    assert abs(rz - p / (2 * EI)) < 1e-5 * rz


def test_cantilever3d_start_values_override_section(fmus):
    base = {"load.fz": 0.01, "element.theory": 1}
    (z1,) = static_outputs(fmus["cantilever3d"], base, ["tip.z"])
    (z2,) = static_outputs(fmus["cantilever3d"], {**base, "section.EIy": EI / 2}, ["tip.z"])
    assert abs(z2 / z1 - 2.0) < 1e-5


@pytest.mark.parametrize("turns", [1, 2])
def test_cantilever3d_rolls_up_into_closed_circles(fmus, turns):
    m = turns * 2 * math.pi * EI
    out = static_outputs(fmus["cantilever3d"], {"load.mz": m, "solver.load_steps": 4},
                         ["tip.x", "tip.y", "tip.z", "tip.tx"])
    assert math.hypot(out[0], out[1]) < 1e-9 and out[2] == 0.0
    assert abs(out[3] - 1.0) < 1e-9


def test_bend45_default_is_the_bathe_bolourchi_benchmark(fmus):
    # Converged reference (Kynema LSFE, kynema/kynema docs/sphinx/testing/curved.rst):
    # (-23.646, 13.721, 53.578) in magnitude; here the arc turns towards +y, so u_y < 0.
    x, y, z = static_outputs(fmus["bend45"], {}, ["tip.x", "tip.y", "tip.z"])
    u = (x - 100 * math.sin(math.pi / 4), y - 100 * (1 - math.cos(math.pi / 4)), z)
    for got, ref in zip(u, (-23.645972, -13.720801, 53.577645)):
        assert abs(got - ref) < 0.01 * abs(ref), (u, ref)


def test_right_angle_cantilever_matches_published_curves(fmus):
    r = plot_right_angle.simulate(fmus["right_angle_cantilever"])
    for name, omax, rmax, omin, rmin, rel in plot_right_angle.compare(r):
        amp = np.abs(plot_right_angle.reference(name)[1]).max()
        for o, ref in ((omax, rmax), (omin, rmin)):
            assert abs(o[1] - ref[1]) < 0.05 * amp and abs(o[0] - ref[0]) < 0.5, (name, o, ref)
        assert rel < 0.08, (name, rel)


@pytest.mark.parametrize(
    "name,value,needle",
    [("section.rhoJx", 1.0, "section.rhoJx"), ("section.EA", -1.0, "section.EA")],
)
def test_bad_section_gives_error_and_message(fmus, name, value, needle):
    s = Session(fmus["cantilever3d"])
    try:
        s.slave.setReal([s.vr[name]], [value])
        s.slave.setupExperiment(startTime=0.0)
        with pytest.raises(Exception):
            s.slave.enterInitializationMode()
            s.slave.exitInitializationMode()
        assert any(needle in m for m in s.errors()), s.messages
    finally:
        s.close()


def test_nan_moment_input_is_an_error(fmus):
    s = Session(fmus["cantilever3d"])
    try:
        s.slave.setupExperiment(startTime=0.0)
        s.slave.enterInitializationMode()
        s.slave.exitInitializationMode()
        with pytest.raises(Exception):
            s.slave.setReal([s.vr["load.my"]], [float("nan")])
        assert s.errors()
    finally:
        s.close()
