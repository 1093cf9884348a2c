"""What every shipped FMU carries besides the model (issue 14), checked with independent tools:
the terminals against the FMI 3.0 schema fmi3TerminalsAndIcons.xsd that fmpy ships (FMI 2.0.4,
section 2.3, refers to it), the documentation page with lxml's XML parser, the icon with
matplotlib's PNG reader; and a two-platform FMU (this machine's library copied under a second
platform name) through fmpy."""
import pathlib
import shutil
import subprocess
import zipfile

import fmpy
import matplotlib.image
import numpy as np
from fmpy import read_model_description, simulate_fmu
from fmpy.validation import validate_fmu
from lxml import etree

ROOT = pathlib.Path(__file__).resolve().parents[1]
XSD = pathlib.Path(fmpy.__file__).parent / "schema" / "fmi3" / "fmi3TerminalsAndIcons.xsd"


def test_terminals_validate_against_the_fmi3_schema(fmus):
    schema = etree.XMLSchema(etree.parse(str(XSD)))
    terminals = 0
    for name, path in fmus.items():
        with zipfile.ZipFile(path) as z:
            doc = etree.fromstring(z.read("terminalsAndIcons/terminalsAndIcons.xml"))
        assert schema.validate(doc), (name, schema.error_log)
        variables = {v.name for v in read_model_description(path).modelVariables}
        for m in doc.iter("TerminalMemberVariable"):
            assert m.get("variableName") in variables, (name, m.get("variableName"))
        terminals += len(doc.findall("Terminals/Terminal"))
    assert terminals >= 10


def test_documentation_icon_and_licences_are_there(fmus):
    for name, path in fmus.items():
        with zipfile.ZipFile(path) as z:
            html = etree.fromstring(z.read("documentation/index.html"))
            assert html.tag == "{http://www.w3.org/1999/xhtml}html", name
            text = "".join(html.itertext())
            for v in read_model_description(path).modelVariables:
                assert v.name in text, (name, v.name)
            with z.open("model.png") as f:
                img = matplotlib.image.imread(f, format="png")
            assert img.shape[:2] == (256, 256), name
            # the body is drawn: more than the frame and the background
            assert len(np.unique(img.reshape(-1, img.shape[-1]), axis=0)) == 3, name
            lic = z.read("documentation/licenses/license.txt").decode()
            assert "flexfmu 0.1.0 is licensed under MIT" in lic
            assert "nalgebra-" in lic and "faer-" in lic
            assert any(n.startswith("documentation/licenses/nalgebra-") for n in z.namelist())
        side = pathlib.Path(path).with_name(f"{name}_OspModelDescription.xml")
        osp = etree.parse(str(side)).getroot()
        assert osp.tag == "{https://open-simulation-platform.com/OspModelDescription/1.0.0}OspModelDescription"


def test_two_platform_fmu_validates_and_runs(tmp_path):
    lib = ROOT / "target" / "release" / "libflexfmu.so"
    other = tmp_path / "libflexfmu_aarch64.so"
    shutil.copy(lib, other)  # a stand-in for a library built on an ARM machine
    out = tmp_path / "cantilever.fmu"
    exe = ROOT / "target" / "release" / "flexfmu"
    subprocess.run([str(exe), "build", str(ROOT / "scenes" / "cantilever.toml"), "-o", str(out),
                    "--library", f"linux64={lib}", "--library", f"aarch64-linux={other}"],
                   check=True, capture_output=True)
    with zipfile.ZipFile(out) as z:
        names = set(z.namelist())
    assert {"binaries/linux64/cantilever.so", "binaries/aarch64-linux/cantilever.so"} <= names
    assert validate_fmu(str(out)) == []
    res = simulate_fmu(str(out), stop_time=0.01, output_interval=0.005, output=["tip.y"])
    assert np.isfinite(res["tip.y"]).all()
    # re-package: add a win64 folder to the existing FMU
    subprocess.run([str(exe), "add-platforms", str(out), "--library", f"win64={other}"],
                   check=True, capture_output=True)
    with zipfile.ZipFile(out) as z:
        assert "binaries/win64/cantilever.dll" in z.namelist()
        assert len(z.namelist()) == len(names) + 1
    assert validate_fmu(str(out)) == []
