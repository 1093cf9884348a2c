"""Seed-004 shell FMUs (kind "shell") under fmpy: the three shipped scenes pass fmpy's validation,
take their parameters as start values and answer their inputs in the static solve at
initialization (small loads, so the linear formulas hold). The validation tables of the element
are the Rust tests'."""
import math

from fmpy.validation import validate_fmu
import pytest

from helpers import static_outputs


@pytest.mark.parametrize("name", ["plate", "cylinder", "strip"])
def test_shell_scene_passes_fmpy_validation(fmus, name):
    assert validate_fmu(fmus[name]) == []


def test_strip_small_end_force_matches_beam_theory(fmus):
    ei = 1.2e6 * 1.0 * 0.1**3 / 12  # E b h^3 / 12, nu = 0
    f = 1e-4 * ei / 100.0
    (z,) = static_outputs(fmus["strip"], {"load.fz": f}, ["tip.z"])
    assert abs(z / (f * 1000.0 / (3 * ei)) - 1.0) < 1e-6


def test_plate_support_parameters_change_the_deflection(fmus):
    (ss,) = static_outputs(fmus["plate"], {"load.fz": 100.0}, ["centre.z"])
    clamped = {f"support.{e}": 2 for e in ("x0", "x1", "y0", "y1")}
    (cl,) = static_outputs(fmus["plate"], {"load.fz": 100.0, **clamped}, ["centre.z"])
    assert ss > cl > 0.0


def test_cylinder_grows_under_internal_pressure(fmus):
    names = ["shell.volume", "mid.radius", "shell.length"]
    v0, r0, l0 = static_outputs(fmus["cylinder"], {}, names)
    assert abs(v0 - 8 * 0.1**2 * math.sin(2 * math.pi / 16) * 0.5) < 1e-12
    assert abs(r0 - 0.1) < 1e-12 and abs(l0 - 0.5) < 1e-12
    v1, r1, l1 = static_outputs(fmus["cylinder"], {"load.pressure": 1e5}, names)
    assert v1 > v0 and r1 > r0 and l1 > l0
