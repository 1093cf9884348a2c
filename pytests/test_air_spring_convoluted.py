"""The double-convoluted air spring (issue 11 item 2, second geometry; scenes/air_spring_convoluted.toml):
self-checks of its shooting reference (scripts/air_spring_reference.py, convoluted part) and the
FMU end to end through fmpy. `top.z` is the plate-to-plate height, `top.fz` > 0 pushes the top
plate up."""
import math
import pathlib
import sys
import tomllib

import numpy as np
import pytest
from fmpy.validation import validate_fmu

from helpers import Session

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import air_spring_reference as ref  # noqa: E402

NAME = "air_spring_convoluted"
DESIGN_HEIGHT = 0.20  # m
STEP = 1e-3  # s
DATA = tomllib.loads((ROOT / "tests" / "data" / "air_spring_convoluted_reference.toml").read_text())


def test_reference_data_is_regenerated():
    # the shipped curves are what the script computes now (two heights, to keep it short)
    c = DATA["constant_pressure"]
    for i in (0, 3):
        res = ref.solve_convoluted(c["h"][i], c["p_gauge"][i])
        assert res["F"] == pytest.approx(c["F"][i], rel=1e-9)
        assert res["V"] == pytest.approx(c["V"][i], rel=1e-9)


def test_reference_first_integral_is_constant_along_the_meridian():
    # F from the departure radius (p pi r_h^2) and from r N_s sin(phi) + p r^2/2 at the girdle's
    # upper side agree: the integration is accurate and the girdle carries no axial load
    res = ref.solve_convoluted(DESIGN_HEIGHT, 5e5)
    assert res["contact"] and res["r_h"] > ref.CONVOLUTED.r_b
    assert abs(res["F_end"] / res["F"] - 1.0) < 1e-9


def test_reference_virtual_work():
    # F = p A_v - dU/dh (energy balance of the membrane at constant pressure): an independent
    # check of the force (first integral) against the volume and strain energy (integrals)
    c = DATA["constant_pressure"]
    p = c["p_gauge"][0]
    for f, a_v, du in zip(c["F"], c["A_v"], c["dU_dh"]):
        assert abs((p * a_v - du) / f - 1.0) < 1e-6


def test_fmpy_validate(fmus):
    assert validate_fmu(fmus[NAME]) == []


OUTPUTS = ["top.fz", "gas.pressure_gauge", "gas.volume", "spring.height", "energy.strain", "energy.kinetic",
           "energy.gas", "energy.plate_work", "energy.dissipated"]


def test_energy_balance_over_a_sine(fmus):
    """plate work = change of (gas + strain + kinetic) + dissipated + numerical, 10 mm at 2 Hz."""
    s = Session(fmus[NAME])
    rows = []
    try:
        s.slave.setupExperiment(startTime=0.0)
        s.slave.enterInitializationMode()
        s.slave.exitInitializationMode()
        rows.append(s.slave.getReal([s.vr[n] for n in OUTPUTS]))
        z = lambda t: DESIGN_HEIGHT + 0.01 * math.sin(2 * math.pi * 2.0 * t)  # noqa: E731
        for k in range(500):
            t = k * STEP
            s.slave.setReal([s.vr["top.z"], s.vr["top.vz"]], [z(t), (z(t + STEP) - z(t)) / STEP])
            s.slave.doStep(currentCommunicationPoint=t, communicationStepSize=STEP)
            rows.append(s.slave.getReal([s.vr[n] for n in OUTPUTS]))
    finally:
        s.close()
    d = {o: np.array([r[i] for r in rows]) for i, o in enumerate(OUTPUTS)}
    assert np.all(np.isfinite(np.array(list(d.values()))))
    stored = d["energy.gas"] + d["energy.strain"] + d["energy.kinetic"]
    numerical = d["energy.plate_work"] - (stored - stored[0]) - d["energy.dissipated"]
    scale = np.abs(d["energy.plate_work"]).max()
    print(f"plate work up to {scale:.3f} J, numerical part up to {np.abs(numerical).max():.3e} J")
    assert scale > 10.0
    assert np.abs(numerical).max() < 1e-4 * scale
    # compression raises the force (stiffening spring)
    assert d["top.fz"][375] > d["top.fz"][0] > d["top.fz"][125]
