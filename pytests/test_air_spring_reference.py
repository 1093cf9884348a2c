"""Self-checks of the independent air-spring membrane reference (scripts/air_spring_reference.py,
issue 11 item 8). Sign conventions: h = top plate height (extension positive), F > 0 pushes the
plate up, A_v = dV/dh, k = -dF/dh (= dF/dz with z = compression)."""
import dataclasses
import json
import math
import pathlib
import sys

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import air_spring_reference as ref  # noqa: E402


@pytest.fixture(scope="module")
def design():
    return ref.solve(0.25, 5e5)


def test_design_state_reproduces_the_issue_figures(design):
    # issue 11 item 7: "F = 21533.04 N, V = 8.456949 L, A_e = 0.043066 m2 (computed independently)"
    assert design["wrap"] and design["warnings"] == []
    assert round(design["F"], 2) == 21533.04
    assert round(design["V"] * 1e3, 6) == 8.456949
    assert round(design["A_e"], 6) == 0.043066


def test_effective_area_is_pi_rh_squared(design):
    # F comes from the first integral at the departure point, r_h from locating phi = -pi on the
    # integrated meridian: they agree only if the integration is right.
    for res in (design, ref.solve(0.29, 4e5, ref.SPRING_B)):
        assert abs(res["A_e"] - math.pi * res["r_h"] ** 2) < 1e-8
    # the half-torus rule (r_p + r_o)/2 is not exact: the cords make it about 7 % too high
    mean_rule = math.pi * (0.5 * (ref.DEFAULT.r_p + design["lobe_radius"])) ** 2
    assert 1.05 < mean_rule / design["A_e"] < 1.09


@pytest.mark.parametrize("h, p, spring", [(0.25, 5e5, ref.DEFAULT), (0.21, 3e5, ref.DEFAULT), (0.29, 4e5, ref.SPRING_B)])
def test_virtual_work(h, p, spring):
    # constant pressure: F = p_g dV/dh - dU/dh (potential U - p_g V of the membrane and the gas)
    c = ref.characteristic([h], p, spring, compliance=False)
    f_vw = p * c["A_v"][0] - c["dU_dh"][0]
    assert abs(f_vw - c["F"][0]) < 1e-5 * c["F"][0]
    assert c["wrap"][0] == (spring is ref.DEFAULT)  # spring B at 0.29 m has rolled off the piston wall


def test_closed_gas_stiffness_identity():
    # k = -dF/dh = n p_abs A_e A_v / V - p_g dA_e/dh along the closed-gas path (A_v = dV/dh)
    n = 1.4
    c = ref.closed([0.24], (0.25, 5e5), n)
    d = ref.solve(0.25, 5e5)
    gas = (5e5 + ref.P_AMBIENT) * d["V"] ** n
    assert abs((c["p_gauge"][0] + ref.P_AMBIENT) * c["V"][0] ** n / gas - 1.0) < 1e-9
    assert c["p_gauge"][0] > 5e5  # compressed below the design height
    assert abs(c["k"][0] - c["k_identity"][0]) < 1e-5 * c["k"][0]
    # the A_e^2 form overestimates the extensible bellows (A_v < A_e: the bag swells with p)
    assert c["A_v"][0] < 0.95 * c["A_e"][0]
    assert c["k_Ae2"][0] > 1.05 * c["k"][0]


def test_zero_hoop_stress_lobe_has_the_rms_radius():
    # Meridional cords only (alpha0 = 0) and no matrix: N_theta = 0, so r N_s = Q is constant
    # (tangential equilibrium), lam_s = 1 + Q/(R0 n K_c), and the normal equilibrium
    # dphi/ds = -p r/Q integrates to sin(phi) = 1 - beta (r^2 - r_p^2), beta = p/(2Q), from the
    # departure point (phi = -3 pi/2): r_h^2 = (r_p^2 + r_o^2)/2 with r_o the radius where the outer
    # wall is vertical (air-spring-physics.md 1.2). The spring is built from that profile by an
    # independent Gauss quadrature (ds = dphi/(2 beta r)): r_o = 0.15 m, bead at r_b = 0.128 m,
    # 10 mm of contact on the piston; the solver must find the same lobe.
    p, r_p, r_o, r_b, h_p, l_c, n_k, r0 = 5e5, 0.1, 0.15, 0.128, 0.15, 0.01, 3e6, 0.125
    beta = 2.0 / (r_o**2 - r_p**2)
    lam = 1.0 + p / (2.0 * beta) / (r0 * n_k)
    phi_b = math.asin(1.0 - beta * (r_b**2 - r_p**2))
    xg, wg = np.polynomial.legendre.leggauss(200)
    lo, hi = -1.5 * math.pi, phi_b
    phi, w = 0.5 * (hi - lo) * xg + 0.5 * (hi + lo), 0.5 * (hi - lo) * wg
    r = np.sqrt(r_p**2 + (1.0 - np.sin(phi)) / beta)
    s_free = np.sum(w / (2.0 * beta * r))
    rise = -np.sum(w * np.sin(phi) / (2.0 * beta * r))
    z_d = h_p - l_c
    spring = ref.Spring(r_p=r_p, h_p=h_p, r_b=r_b, R0=r0, L=(s_free + l_c) / lam, alpha0_deg=0.0, K_c=n_k / 2, Et=0.0)
    res = ref.solve(z_d + rise, p, spring)
    assert res["wrap"] and res["warnings"] == []
    assert abs(res["lobe_radius"] - r_o) < 1e-9
    assert abs(res["departure_height"] - z_d) < 1e-9
    assert abs(res["r_h"] ** 2 - 0.5 * (r_p**2 + res["lobe_radius"] ** 2)) < 1e-11
    shape = res["shape"]
    q = shape["r"] * shape["N_s"]
    assert max(abs(q - p / (2.0 * beta))) < 1e-8 * q[0]
    assert max(abs(shape["N_theta"])) == 0.0


def test_integration_converges():
    # halving the steps (tolerance / 2^5 for the 5th-order Dormand-Prince pair) changes F by less
    # than 1e-9 relative
    coarse = ref.solve(0.25, 5e5, tol=1e-10)
    fine = ref.solve(0.25, 5e5, tol=1e-10 / 32, start=coarse)
    assert 1.7 < fine["steps"] / coarse["steps"] < 2.3
    assert abs(fine["F"] - coarse["F"]) < 1e-9 * fine["F"]
    assert abs(fine["V"] - coarse["V"]) < 1e-9 * fine["V"]


def test_committed_data_matches_the_solver(design):
    # tests/data/air_spring_reference.json is written by the script's CLI: it must be current
    data = json.loads((ROOT / "tests" / "data" / "air_spring_reference.json").read_text())
    assert data["design"]["F"] == pytest.approx(design["F"], rel=1e-9)
    assert data["design"]["V"] == pytest.approx(design["V"], rel=1e-9)
    curve = next(c for c in data["constant_pressure"] if c["spring"] == "B")
    i = curve["h"].index(0.29)
    res = ref.solve(0.29, 4e5, ref.SPRING_B)
    assert curve["F"][i] == pytest.approx(res["F"], rel=1e-9)
    assert curve["V"][i] == pytest.approx(res["V"], rel=1e-9)
    assert [c["p_gauge"][0] for c in data["constant_pressure"]] == [3e5, 5e5, 7e5, 4e5]
    assert [(c["spring"], c["n"]) for c in data["closed"]] == [("default", 1.0), ("default", 1.4), ("B", 1.4)]
    assert 40 <= len(data["meridian_design"]["r"]) <= 60


def test_toml_copy_matches_the_json():
    """The Rust tests read the TOML copy of the curves: it must be the JSON's."""
    import json
    import tomllib

    data_dir = pathlib.Path(__file__).resolve().parents[1] / "tests" / "data"
    js = json.loads((data_dir / "air_spring_reference.json").read_text())
    tm = tomllib.loads((data_dir / "air_spring_reference.toml").read_text())
    assert tm["design"]["F"] == js["design"]["F"]
    for key in ("constant_pressure", "closed"):
        assert len(tm[key]) == len(js[key])
        for a, b in zip(tm[key], js[key]):
            for q in ("h", "F", "V", "A_e"):
                assert a[q] == b[q]
