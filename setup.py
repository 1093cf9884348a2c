"""Build step of the Python package (metadata in pyproject.toml): compiles the Rust crate
once (`cargo build --release`, reusing CARGO_TARGET_DIR or ./target) and puts the `flexfmu`
executable and the runtime library into the package (`flexfmu/bin/`, `flexfmu/lib/`). The
wheel is platform-specific (it carries native binaries) but not tied to a Python version."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py
from setuptools.dist import Distribution

try:
    from setuptools.command.bdist_wheel import bdist_wheel
except ImportError:  # setuptools < 70.1
    from wheel.bdist_wheel import bdist_wheel

ROOT = Path(__file__).resolve().parent
EXE = "flexfmu.exe" if os.name == "nt" else "flexfmu"
LIB = {"win32": "flexfmu.dll", "darwin": "libflexfmu.dylib"}.get(sys.platform, "libflexfmu.so")


class BuildWithCargo(build_py):
    def run(self):
        super().run()
        target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")) / "release"
        subprocess.run(
            ["cargo", "build", "--release", "--manifest-path", str(ROOT / "Cargo.toml")],
            check=True,
        )
        pkg = Path(self.build_lib) / "flexfmu"
        for sub, name in (("bin", EXE), ("lib", LIB)):
            (pkg / sub).mkdir(parents=True, exist_ok=True)
            shutil.copy2(target / name, pkg / sub / name)
            # the release profile keeps line tables (debug = 1): 22 MB of wheel instead of 6
            if sys.platform.startswith("linux") and shutil.which("objcopy"):
                subprocess.run(["objcopy", "--strip-debug", str(pkg / sub / name)], check=True)


class NativeDistribution(Distribution):
    def has_ext_modules(self):
        return True


class PlatformWheel(bdist_wheel):
    def finalize_options(self):
        super().finalize_options()
        self.root_is_pure = False

    def get_tag(self):
        _, _, plat = super().get_tag()
        return "py3", "none", plat


setup(
    cmdclass={"build_py": BuildWithCargo, "bdist_wheel": PlatformWheel},
    distclass=NativeDistribution,
)
