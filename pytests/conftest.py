"""Shared fixtures: the FMUs are (re)built once per session by scripts/build_fmus.sh."""
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
FMU_DIR = ROOT / "build" / "fmus"
SCENES = sorted(p.stem for p in (ROOT / "scenes").glob("*.toml"))


@pytest.fixture(scope="session")
def fmus():
    subprocess.run([str(ROOT / "scripts" / "build_fmus.sh")], check=True, stdout=subprocess.DEVNULL)
    return {name: str(FMU_DIR / f"{name}.fmu") for name in SCENES}
