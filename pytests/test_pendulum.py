"""Seed-000 flexible pendulum (Problem 4 of the paper): energy balance and convergence in
element count. The paper publishes plots only; the checks are the ones it states: total energy
constant, and 8 and 16 elements almost identical."""
import fmpy
import numpy as np


def run(fmu, **start):
    return fmpy.simulate_fmu(fmu, stop_time=1.0, output_interval=1e-3, start_values=start)


def test_starts_horizontal_at_rest_and_falls(fmus):
    r = run(fmus["pendulum"])
    assert r["tip.x"][0] == 2.0 and r["tip.y"][0] == 0.0
    assert r["energy.kinetic"][0] == 0.0
    assert r["tip.y"][-1] < -0.5


def test_energy_is_conserved_within_1e_3_of_the_exchanged_energy(fmus):
    r = run(fmus["pendulum"])
    drop = -r["energy.potential"].min()
    drift = np.abs(r["energy.total"] - r["energy.total"][0]).max()
    assert drop > 1000.0
    assert drift <= 1e-3 * drop, (drift, drop)
    # the parts add up
    s = r["energy.kinetic"] + r["energy.potential"] + r["energy.strain"]
    assert np.allclose(s, r["energy.total"], rtol=0, atol=1e-9 * drop)


def test_energy_conserving_midpoint_rule(fmus):
    r = run(fmus["pendulum"], **{"solver.integrator": 3})
    drop = -r["energy.potential"].min()
    assert np.abs(r["energy.total"] - r["energy.total"][0]).max() <= 1e-8 * drop


def test_8_and_16_elements_agree_within_1_percent(fmus):
    a = run(fmus["pendulum"], **{"mesh.n_elements": 8})
    b = run(fmus["pendulum"], **{"mesh.n_elements": 16})
    L = 2.0
    # tip vertical displacement history (the paper's Fig. 6 comparison), relative to its range
    assert np.abs(a["tip.y"] - b["tip.y"]).max() <= 0.01 * np.abs(b["tip.y"]).max()
    # final tip positions, relative to the length
    assert abs(a["tip.x"][-1] - b["tip.x"][-1]) <= 0.01 * L
    assert abs(a["tip.y"][-1] - b["tip.y"][-1]) <= 0.01 * L
