"""flexfmu from Python: flexible bodies as FMI 2.0 Co-Simulation FMUs.

- :func:`build`, :func:`check`: the ``flexfmu`` command line (installed with this package);
- :func:`simulate`: an FMU or a scene through fmpy;
- :func:`sweep`: a sweep file on dask (a local cluster by default, or any
  ``dask.distributed.Client``), results as a pandas DataFrame, CSV or Parquet;
- :func:`advise`: the fidelity advisor (``flexfmu advise``).
"""

from ._api import advise, build, check, simulate
from ._cli import FlexfmuError, cli_path, library_path
from ._sweep import plan, plot_sweep, sweep

__all__ = [
    "FlexfmuError",
    "advise",
    "build",
    "check",
    "cli_path",
    "library_path",
    "plan",
    "plot_sweep",
    "simulate",
    "sweep",
]
