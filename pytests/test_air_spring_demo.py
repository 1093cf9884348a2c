"""Short runs of the air-spring scripts: the reservoir frequency response against the linear
two-volume model (scripts/air_spring_frequency.py) and the MuJoCo quarter car
(scripts/air_spring_quarter_car.py)."""
import math
import pathlib
import sys

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import air_spring_frequency as fr  # noqa: E402
import air_spring_quarter_car as qc  # noqa: E402


# The linear models take the wall's derivatives from spring.stiffness and
# spring.volumetric_area at the design height: pointwise slopes of the discrete characteristic,
# which has a slope sawtooth as nodes leave the piston (README, level-2 validation: up to 6 % at
# the shipped 60 elements, 2.8 % at 120). The strokes below average over it, so the comparisons
# run at 120 elements.
MESH = {"mesh.n_meridional": 120}


@pytest.fixture(scope="module")
def models(fmus):
    d = fr.design_state(fmus["air_spring_reservoir"], MESH)
    wall = fr.wall_derivatives(fmus["air_spring_reservoir"], start_values=MESH)
    m_w = fr.wall_mass(start_values=MESH)
    return d, wall, fr.LinearModel(d, wall_mass=m_w), fr.LinearModel(d, wall, wall_mass=m_w)


def test_wall_derivatives_are_reciprocal(models):
    # a wall with a potential has dF/dp = dV/dh (Maxwell); the two come from different outputs
    # (spring.stiffness and spring.volumetric_area at two exponents)
    _, (v_h, v_p, f_h, f_p), _, _ = models
    assert abs(f_p / v_h - 1.0) < 1e-3
    assert v_p > 0.0  # the bag swells with the pressure


def test_wall_mass_is_part_of_the_sleeve(models):
    # the shipped scenes step quasi-statically: no wall inertia in the response (measured 1.0 g
    # of 1.04 kg: the fit's noise); with generalized-alpha the wall's inertia is part of the sleeve
    sleeve = 2 * math.pi * 0.125 * 0.3 * 0.004 * 1100.0  # kg, scene: radius, length, thickness, density
    assert abs(models[2].wall_mass) < 0.01 * sleeve
    m_w = fr.wall_mass(start_values=dict(MESH, **{"solver.integrator": 1}))
    assert 0.3 * sleeve < m_w < sleeve


def test_small_amplitude_follows_the_linear_model(models):
    # 5 micrometres at 1 Hz: the orifice's quadratic loss is negligible, the laminar model holds
    # (measured +0.02 % in |K|)
    _, _, simple, lin = models
    k, _, _ = fr.measure(1.0, 5e-6, start_values=MESH)
    kl = lin.stiffness(2 * math.pi)
    assert abs(abs(k) / abs(kl) - 1.0) < 1e-3, (k, kl)
    assert abs(math.degrees(np.angle(k) - np.angle(kl))) < 0.05
    # the A_e A_v form, which ignores how the bag's swelling changes with a reservoir, is 5 % soft
    assert abs(k) / abs(simple.stiffness(2 * math.pi)) > 1.04


def test_orifice_at_half_a_millimetre(models):
    # 0.5 mm at 10 Hz, just above the pipe resonance: the orifice dominates (the laminar model is
    # 33 % stiffer and nearly lossless); the describing-function model matches (measured +0.33 %,
    # 19.9 vs 20.3 deg)
    _, _, _, lin = models
    w = 2 * math.pi * 10.0
    k, _, _ = fr.measure(10.0, 5e-4, start_values=MESH)
    kd = lin.describing_function_stiffness(w, 5e-4)
    assert abs(abs(k) / abs(kd) - 1.0) < 0.01, (k, kd)
    assert abs(math.degrees(np.angle(k) - np.angle(kd))) < 1.5
    assert math.degrees(np.angle(k)) > 10.0
    assert abs(lin.stiffness(w)) > 1.3 * abs(k)


def test_quarter_car_drop(fmus, monkeypatch):
    """Body released from +2 cm: explicit and implicit coupling agree, and the body swings at
    the frequency of the linear two-mass model with k = spring.stiffness."""
    monkeypatch.setattr(qc, "FMU_START", MESH)
    runs = {}
    for implicit in (False, True):
        s, _, its, car = qc.simulate(fmus["air_spring_axisym"], "drop", implicit, t_end=0.6)
        runs[implicit] = s
        assert its.max() <= (20 if implicit else 1)
    exp, imp = runs[False], runs[True]
    assert np.abs(exp[:, 1] - imp[:, 1]).max() < 1e-3 * 0.02
    # first minimum of the body displacement at half the period of the lower mode
    k, m_s, m_u, k_t = car.k_static, car.sprung, qc.UNSPRUNG, qc.K_TYRE
    a, b, c = m_s * m_u, -(k * (m_s + m_u) + k_t * m_s), k * k_t
    w2 = (-b - math.sqrt(b * b - 4 * a * c)) / (2 * a)
    t_min = imp[np.argmin(imp[:, 1]), 0]
    assert abs(t_min / (math.pi / math.sqrt(w2)) - 1.0) < 0.03, (t_min, math.pi / math.sqrt(w2))
    assert imp[:, 1].min() < -0.015  # it swings through the equilibrium
