"""compat/ (issue 14, item 5): scripts/compat.py regenerates the whole folder in a temporary
directory (FMUs included) and the result agrees with the committed files: options, inputs and
readmes identical, the reference results within the stated tolerance (compat.AGREEMENT: about
ten times the spread between importers, which is the FMU's Newton tolerance acting on round-off),
every importer (FMPy, libcosim, Ecos) passed and within the same tolerance; each model folder
passes fmpy's cross-check vendor-repository validator (FMU size, modelDescription, _ref.opt,
CSV names); and each FMU re-run through fmpy.simulate_fmu from nothing but its _in.csv and
_ref.opt (read with fmpy's own readers) reproduces the committed _ref.csv."""
import importlib.util
import pathlib
import re
import subprocess
import sys

import fmpy
import numpy as np
import pytest
from fmpy.cross_check.validate_vendor_repo import validate_test_fmu
from fmpy.util import read_csv as fmpy_read_csv
from fmpy.util import read_ref_opt_file

ROOT = pathlib.Path(__file__).resolve().parents[1]
COMMITTED = ROOT / "compat"
_spec = importlib.util.spec_from_file_location("compat", ROOT / "scripts" / "compat.py")
compat = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(compat)


@pytest.fixture(scope="module")
def regenerated(fmus, tmp_path_factory):
    """The folder written afresh by the command (the fmus fixture has built the release CLI and
    library)."""
    out = tmp_path_factory.mktemp("compat")
    r = subprocess.run([sys.executable, str(ROOT / "scripts" / "compat.py"), "--out", str(out)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    return out


def model_dirs(root):
    dirs = sorted(p for p in (root / "fmus").glob("2.0/cs/linux64/flexfmu/*/*") if p.is_dir())
    assert [d.name for d in dirs] == sorted(compat.MODELS), dirs
    return dirs


def relative_deviation(a, b):
    """max |a - b| per column over max |b| of that column; time columns must agree."""
    assert a.shape == b.shape
    assert np.allclose(a[:, 0], b[:, 0], rtol=0, atol=1e-12)
    scale = np.maximum(np.abs(b[:, 1:]).max(axis=0), 1e-300)
    return float((np.abs(a[:, 1:] - b[:, 1:]) / scale).max())


def test_regenerated_folder_agrees_with_the_committed_one(regenerated):
    new_dirs = model_dirs(regenerated)
    for old, new in zip(model_dirs(COMMITTED), new_dirs):
        m = old.name
        listing = [sorted(p.name for p in d.iterdir() if p.suffix != ".fmu") for d in (old, new)]
        assert listing[0] == listing[1], m
        assert (new / f"{m}.fmu").is_file()
        for f in [f"{m}_ref.opt", f"{m}_in.csv", "README.md"]:
            if (old / f).exists():
                assert (old / f).read_text() == (new / f).read_text(), (m, f)
        h_old, ref_old = compat.read_csv(old / f"{m}_ref.csv")
        h_new, ref_new = compat.read_csv(new / f"{m}_ref.csv")
        assert h_old == h_new
        assert relative_deviation(ref_new, ref_old) <= compat.AGREEMENT[m], m
    # the same importers passed the same models (the deviations in brackets vary by machine)
    verdicts = [sorted(str(p.relative_to(root)) for p in (root / "results").rglob("*") if p.is_file())
                for root in (COMMITTED, regenerated)]
    assert verdicts[0] == verdicts[1]
    assert len([v for v in verdicts[1] if v.endswith("/passed")]) == 3 * len(compat.MODELS)
    strip = lambda text: re.sub(r"\(\d\.\de[+-]\d\d\)", "", text)
    assert strip((COMMITTED / "README.md").read_text()) == strip((regenerated / "README.md").read_text())


def test_every_importer_passed_within_the_tolerance(regenerated):
    table = re.findall(r"^\| `(\w+)` \| (.*) \|$", (regenerated / "README.md").read_text(), flags=re.M)
    assert sorted(m for m, _ in table) == sorted(compat.MODELS)
    for model, cells in table:
        cells = cells.split(" | ")
        assert len(cells) == len(compat.IMPORTERS)
        for importer, cell in zip(compat.IMPORTERS, cells):
            verdict, dev = re.fullmatch(r"(\w+) \((\S+)\)", cell).groups()
            assert verdict == "passed", (model, importer)
            assert float(dev) <= compat.AGREEMENT[model], (model, importer, dev)


def test_model_folders_pass_the_cross_check_validator(regenerated):
    for d in model_dirs(regenerated):
        assert validate_test_fmu(str(d)) == [], d.name


def test_fmpy_rerun_from_the_files_reproduces_the_reference(regenerated):
    for d in model_dirs(regenerated):
        m = d.name
        opts = read_ref_opt_file(str(d / f"{m}_ref.opt"))
        signals = fmpy_read_csv(str(d / f"{m}_in.csv")) if (d / f"{m}_in.csv").exists() else None
        names, ref = compat.read_csv(COMMITTED / d.relative_to(regenerated) / f"{m}_ref.csv")
        r = fmpy.simulate_fmu(str(d / f"{m}.fmu"), start_time=opts["StartTime"], stop_time=opts["StopTime"],
                              step_size=opts["StepSize"], output_interval=opts["StepSize"], input=signals,
                              output=names[1:])
        res = np.column_stack([r[n] for n in names])
        assert res[-1, 0] == pytest.approx(opts["StopTime"])
        assert relative_deviation(res, ref) <= compat.AGREEMENT[m], m
