"""``flexfmu.build``, ``check``, ``simulate`` and ``advise``: the command line and fmpy from
Python."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from . import _cli


def build(scene: str | os.PathLike, output: str | os.PathLike | None = None) -> Path:
    """Builds the FMU of a scene file (``flexfmu build SCENE -o OUTPUT``) with the runtime
    library installed with this package; returns the FMU's path (default: ``<model_name>.fmu``
    in the current directory)."""
    args = ["build", str(scene)]
    if output is not None:
        args += ["-o", str(output)]
    out = _cli.run(*args, quiet=True)
    written = [ln.removeprefix("wrote ").strip() for ln in out.splitlines() if ln.startswith("wrote ")]
    return Path(next(w for w in written if w.endswith(".fmu")))


def check(*scenes: str | os.PathLike) -> list[str]:
    """Checks scene files (``flexfmu check``): parse, validate, build the model with the
    default parameters. Returns one summary line per scene; raises ``FlexfmuError`` naming
    the key on the first bad one."""
    out = _cli.run("check", *map(str, scenes), quiet=True)
    return [ln for ln in out.splitlines() if ln.strip()]


def simulate(model: str | os.PathLike, **kwargs):
    """Simulates an FMU, or the FMU of a scene file (built into a temporary directory),
    with ``fmpy.simulate_fmu`` (keyword arguments are fmpy's: ``stop_time``, ``step_size``,
    ``output_interval``, ``start_values``, ``input``, ``output``, ...). Returns fmpy's
    structured array."""
    from fmpy import simulate_fmu

    model = Path(model)
    if model.suffix == ".fmu":
        return simulate_fmu(str(model), **kwargs)
    with tempfile.TemporaryDirectory() as d:
        fmu = build(model, Path(d) / "model.fmu")
        return simulate_fmu(str(fmu), **kwargs)


def advise(
    scene: str | os.PathLike,
    output: str,
    tol: float,
    out: str | os.PathLike,
    stop_time: float | None = None,
    inputs: str | os.PathLike | None = None,
    extra: tuple[str, ...] = (),
) -> Path:
    """The fidelity advisor: ``flexfmu advise SCENE --output OUTPUT --tol TOL [--stop-time T]
    [--inputs CSV] -o OUT`` (a convergence study over the scene kind's knobs; writes the
    cheapest scene whose error on ``output`` stays within ``tol``, with its table and plot).
    ``extra`` passes further options of the command. Progress goes to stderr; returns
    ``out``."""
    args = ["advise", str(scene), "--output", output, "--tol", repr(float(tol))]
    if stop_time is not None:
        args += ["--stop-time", repr(float(stop_time))]
    if inputs is not None:
        args += ["--inputs", str(inputs)]
    args += [*extra, "-o", str(out)]
    _cli.run(*args)
    return Path(out)
