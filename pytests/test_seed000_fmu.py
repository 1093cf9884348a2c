"""Kerkkanen, Sopanen & Mikkola 2003 (seed 000), proposed-element columns, through the built
FMUs with fmpy at 2, 16 and 64 elements (values from shared/reference/seed000-ancf-shear-beam.md)."""
import pytest

from helpers import Session, static_outputs

N = [2, 16, 64]


# Tables 1-2: simply supported, 1000 N at mid-span, original 1x1 shear rule, mid deflection [mm]
TABLE_1_2 = {2: (-0.07304348, -0.07321739), 16: (-0.09682065, -0.09699456), 64: (-0.09717448, -0.09734839)}


@pytest.mark.parametrize("n", N)
@pytest.mark.parametrize("column,nu", [(0, 0.0), (1, 0.3)])
def test_tables_1_and_2(fmus, n, column, nu):
    (y,) = static_outputs(
        fmus["simply_supported"],
        {"mesh.n_elements": n, "material.nu": nu, "element.shear_rule": 1, "load.fy": -1000.0},
        ["mid.y"],
    )
    assert round(y * 1e3, 8) == TABLE_1_2[n][column]


# Table 3: cantilever, Model 1, F = -5e5 N, original 1x1 rule, tip (x, y) [m]
TABLE_3 = {2: (1.93097, -0.47477), 16: (1.85526, -0.68046), 64: (1.85489, -0.68114)}


@pytest.mark.parametrize("n", N)
def test_table_3(fmus, n):
    x, y = static_outputs(
        fmus["cantilever"], {"mesh.n_elements": n, "element.shear_rule": 1, "load.fy": -5e5}, ["tip.x", "tip.y"]
    )
    assert (round(x, 5), round(y, 5)) == TABLE_3[n]


# Table 5: deep cantilever (Model 2: h = 0.5 m, nu = 0, F = -6.25e7 N) with the 1x2 fix
TABLE_5 = {2: (1.87066, -0.65601), 16: (1.84228, -0.71066), 64: (1.84191, -0.71133)}


@pytest.mark.parametrize("n", N)
def test_table_5(fmus, n):
    x, y = static_outputs(
        fmus["cantilever"],
        {"mesh.n_elements": n, "geometry.height": 0.5, "material.nu": 0.0, "element.shear_rule": 2, "load.fy": -6.25e7},
        ["tip.x", "tip.y"],
    )
    assert (round(x, 5), round(y, 5)) == TABLE_5[n]


def test_table_4_no_convergence_is_an_error(fmus):
    """Table 4: the original 1x1 rule does not converge for the deep beam with 64 elements;
    the FMU reports an error with a message instead of a result."""
    s = Session(fmus["cantilever"])
    try:
        sl = s.slave
        sl.setupExperiment(startTime=0.0)
        for name, v in [("geometry.height", 0.5), ("material.nu", 0.0), ("load.fy", -6.25e7)]:
            sl.setReal([s.vr[name]], [v])
        sl.setInteger([s.vr["mesh.n_elements"], s.vr["element.shear_rule"]], [64, 1])
        sl.setBoolean([s.vr["solver.static_equilibrium"]], [True])
        sl.enterInitializationMode()
        with pytest.raises(Exception):
            sl.exitInitializationMode()
        assert any("static equilibrium not found" in m for m in s.errors()), s.messages
    finally:
        s.close()


# Table 6: axial elongation 0.048307 mm for any element count, nu = 0 and 0.3
@pytest.mark.parametrize("n", N)
@pytest.mark.parametrize("nu", [0.0, 0.3])
def test_table_6(fmus, n, nu):
    (x,) = static_outputs(fmus["cantilever"], {"mesh.n_elements": n, "material.nu": nu, "load.fx": 5e4}, ["tip.x"])
    assert round((x - 2.0) * 1e3, 6) == 0.048307
