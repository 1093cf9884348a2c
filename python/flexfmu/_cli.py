"""Locating and calling the ``flexfmu`` command line and its runtime library."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

_HERE = Path(__file__).resolve().parent
_EXE = "flexfmu.exe" if os.name == "nt" else "flexfmu"
_LIB = {"win32": "flexfmu.dll", "darwin": "libflexfmu.dylib"}.get(sys.platform, "libflexfmu.so")


class FlexfmuError(RuntimeError):
    """A ``flexfmu`` command failed; the message is the command's error output."""


def _repository_target() -> Path | None:
    """``target/release`` of a source checkout this module sits in (``python/flexfmu``)."""
    root = _HERE.parent.parent
    if (root / "Cargo.toml").is_file():
        return Path(os.environ.get("CARGO_TARGET_DIR", root / "target")) / "release"
    return None


def cli_path() -> Path:
    """The ``flexfmu`` executable: ``$FLEXFMU_CLI``, the one inside this package
    (``flexfmu/bin/``, from the wheel) or ``target/release`` of a source checkout (not
    ``PATH``: there the wheel's console script, which calls this, is found)."""
    env = os.environ.get("FLEXFMU_CLI")
    if env:
        return Path(env)
    candidates = [_HERE / "bin" / _EXE]
    target = _repository_target()
    if target is not None:
        candidates.append(target / _EXE)
    for c in candidates:
        if c.is_file():
            return c
    raise FlexfmuError(
        "cannot find the flexfmu executable: install the package (pip install .), build it "
        "(cargo build --release) or set FLEXFMU_CLI"
    )


def library_path() -> Path | None:
    """The runtime library packaged into FMUs: ``$FLEXFMU_LIBRARY``, the one inside this
    package (``flexfmu/lib/``, from the wheel), or ``None`` (the CLI then looks next to its
    executable)."""
    env = os.environ.get("FLEXFMU_LIBRARY")
    if env:
        return Path(env)
    packaged = _HERE / "lib" / _LIB
    if packaged.is_file():
        return packaged
    return None


def run(*args: str | os.PathLike, quiet: bool = False) -> str:
    """Runs ``flexfmu ARGS`` and returns its standard output; raises :class:`FlexfmuError`
    with the command's message when it fails. Progress (stderr) is passed through unless
    ``quiet``."""
    cmd = [str(cli_path()), *map(str, args)]
    env = dict(os.environ)
    lib = library_path()
    if lib is not None:
        env["FLEXFMU_LIBRARY"] = str(lib)
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
    err = bytearray()

    def pump() -> None:
        # stderr carries progress (passed through) and, on failure, the error message (kept)
        assert proc.stderr is not None
        while chunk := os.read(proc.stderr.fileno(), 4096):
            err.extend(chunk)
            if not quiet:
                sys.stderr.write(chunk.decode(errors="replace"))
                sys.stderr.flush()

    import threading

    t = threading.Thread(target=pump, daemon=True)
    t.start()
    out = proc.stdout.read().decode() if proc.stdout is not None else ""
    proc.wait()
    t.join()
    if proc.returncode != 0:
        lines = [ln for ln in err.decode(errors="replace").replace("\r", "\n").splitlines() if ln.strip()]
        msg = lines[-1] if lines else f"{' '.join(cmd)} failed with exit code {proc.returncode}"
        raise FlexfmuError(msg)
    return out


def main() -> None:
    """The ``flexfmu`` console script of the wheel: runs the packaged executable."""
    exe = str(cli_path())
    env = dict(os.environ)
    lib = library_path()
    if lib is not None:
        env.setdefault("FLEXFMU_LIBRARY", str(lib))
    if os.name == "nt":
        sys.exit(subprocess.call([exe, *sys.argv[1:]], env=env))
    os.execve(exe, [exe, *sys.argv[1:]], env)
