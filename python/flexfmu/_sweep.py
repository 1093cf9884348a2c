"""``flexfmu.sweep``: a sweep file run on dask, one FMU instance per partition (fmpy's
FMU2Slave, reused through fmi2Reset), with the same calls, inputs and reductions as
``flexfmu sweep`` so that both give identical numbers."""

from __future__ import annotations

import bisect
import json
import math
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

from . import _cli


def _input_value(times: list[float], ys: list[float], t: float) -> float:
    """Linear interpolation, held constant outside the table: the expression and order of
    ``InputTable::value`` in ``src/sweep/spec.rs``."""
    n = len(times)
    if n == 1 or t <= times[0]:
        return ys[0]
    if t >= times[-1]:
        return ys[-1]
    i = bisect.bisect_right(times, t) - 1
    t0, t1 = times[i], times[i + 1]
    return ys[i] + (ys[i + 1] - ys[i]) * ((t - t0) / (t1 - t0))


class _Reducer:
    """Running reductions of one output: ``Reducer`` in ``src/sweep/run.rs``, the same
    comparisons and sums in the same order."""

    def __init__(self) -> None:
        self.count = 0
        self.last = self.max = self.min = self.max_abs = math.nan
        self.sum = 0.0
        self.sum_sq = 0.0

    def push(self, y: float) -> None:
        if self.count == 0:
            self.max, self.min, self.max_abs = y, y, abs(y)
        else:
            if y > self.max:
                self.max = y
            if y < self.min:
                self.min = y
            if abs(y) > self.max_abs:
                self.max_abs = abs(y)
        self.last = y
        self.sum += y
        self.sum_sq += y * y
        self.count += 1

    def get(self, r: str) -> float:
        n = float(self.count)
        return {
            "final": lambda: self.last,
            "max": lambda: self.max,
            "min": lambda: self.min,
            "max_abs": lambda: self.max_abs,
            "mean": lambda: self.sum / n,
            "rms": lambda: math.sqrt(self.sum_sq / n),
        }[r]()


def run_partition(fmu_bytes: bytes, plan: dict, points: list) -> list:
    """Runs ``points`` ([index, values] pairs of the plan) with one FMU instance, reset
    between points. Returns ``(point, reductions, status, series)`` per point."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    tmp = tempfile.mkdtemp(prefix="flexfmu_sweep_")
    try:
        path = os.path.join(tmp, "model.fmu")
        with open(path, "wb") as f:
            f.write(fmu_bytes)
        md = read_model_description(path)
        unzipdir = extract(path, os.path.join(tmp, "x"))
        fmu = FMU2Slave(
            guid=md.guid,
            unzipDirectory=unzipdir,
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName="sweep",
        )
        fmu.instantiate(loggingOn=False)
        try:
            return [_run_point(fmu, plan, p, values, i > 0) for i, (p, values) in enumerate(points)]
        finally:
            fmu.freeInstance()
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _run_point(fmu, plan: dict, p: int, values: list, reset: bool):
    outputs = plan["outputs"]
    series_spec = plan["series"]
    keep = series_spec is not None and p in series_spec["points"]
    read = [o["vr"] for o in outputs]
    if series_spec is not None:
        read += [o["vr"] for o in series_spec["outputs"]]
    reducers = [_Reducer() for _ in outputs]
    series: list = []
    inputs = plan["inputs"]
    start, step, steps = plan["start_time"], plan["step"], plan["steps"]

    def set_inputs(t: float) -> None:
        if inputs is not None:
            cols = inputs["columns"]
            fmu.setReal(
                [c["vr"] for c in cols],
                [_input_value(inputs["time"], c["values"], t) for c in cols],
            )

    def record(t: float) -> None:
        y = fmu.getReal(read)
        for r, v in zip(reducers, y):
            r.push(v)
        if keep:
            series.append([t, *y[len(reducers):]])

    what = "fmi2Reset"
    try:
        if reset:
            fmu.reset()
        what = "fmi2SetupExperiment"
        fmu.setupExperiment(startTime=start, stopTime=plan["stop_time"])
        for s, v in zip(plan["settings"], values):
            what = f"setting {s['name']}"
            {"Real": fmu.setReal, "Integer": fmu.setInteger, "Boolean": fmu.setBoolean}[s["type"]](
                [s["vr"]], [v]
            )
        what = "fmi2EnterInitializationMode"
        fmu.enterInitializationMode()
        set_inputs(start)
        what = "fmi2ExitInitializationMode"
        fmu.exitInitializationMode()
        record(start)
        for k in range(steps):
            t = start + k * step
            if k > 0:
                set_inputs(t)
            what = f"fmi2DoStep at t = {t} s"
            fmu.doStep(currentCommunicationPoint=t, communicationStepSize=step)
            record(start + (k + 1) * step)
        what = "fmi2Terminate"
        fmu.terminate()
        status = "ok"
    except Exception as e:  # an FMI call failed: the point's reductions are NaN
        status = f"{what}: {e}".replace(",", ";").replace("\n", " ")
        reducers = [_Reducer() for _ in outputs]
    vals = [r.get(red) for o, r in zip(outputs, reducers) for red in o["reduce"]]
    return p, vals, status, series


def _fmt(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return v
    return repr(v)


def plan(sweep_file: str | os.PathLike, chunk: str | None = None) -> dict:
    """The expanded sweep (``flexfmu sweep SWEEP --plan``) as a dict: points, value
    references, run, outputs."""
    with tempfile.TemporaryDirectory() as d:
        out = Path(d) / "plan.json"
        args = ["sweep", str(sweep_file), "--plan", str(out)]
        if chunk:
            args += ["--chunk", chunk]
        _cli.run(*args, quiet=True)
        return json.loads(out.read_text())


def sweep(
    sweep_file: str | os.PathLike,
    client=None,
    output: str | os.PathLike | None = None,
    partitions: int | None = None,
    progress: bool = True,
    plot: bool = True,
):
    """Runs a sweep file (the format of ``flexfmu sweep``, see the README) on dask.

    ``client``: ``None`` starts a ``dask.distributed.LocalCluster`` (one single-threaded
    worker process per core) for this call; a ``dask.distributed.Client`` or a scheduler
    address (``"tcp://host:8786"``) runs on that cluster. The FMU (the sweep's ``fmu``, or
    built from its ``scene``) is sent to the workers once; each partition of points runs on
    one FMU instance reused through fmi2Reset. ``partitions``: default twice the workers'
    threads. ``output``: ``.csv`` or ``.parquet`` to write (the series, if any, go to
    ``<stem>_series.csv``; with ``plot`` a 1-D or 2-D sweep is drawn into ``<stem>.png``).
    Returns a pandas DataFrame, one row per point, columns as the CLI's CSV; the series,
    if kept, in ``df.attrs["series"]`` (a DataFrame ``point, time, <outputs>``).
    """
    import pandas as pd
    from dask.distributed import Client, LocalCluster, as_completed

    pl = plan(sweep_file)
    tmp = tempfile.mkdtemp(prefix="flexfmu_sweep_")
    own = []
    try:
        if "fmu" in pl:
            fmu_path = Path(pl["fmu"])
        else:
            from ._api import build

            fmu_path = build(pl["scene"], Path(tmp) / "model.fmu")
        fmu_bytes = fmu_path.read_bytes()
        if client is None:
            cluster = LocalCluster(
                n_workers=os.cpu_count() or 1, threads_per_worker=1, processes=True
            )
            client = Client(cluster)
            own = [client, cluster]
        elif isinstance(client, str):
            client = Client(client)
            own = [client]
        threads = sum(client.nthreads().values()) or 1
        points = pl["points"]
        nparts = max(1, min(len(points), partitions or 2 * threads))
        bounds = [i * len(points) // nparts for i in range(nparts + 1)]
        parts = [points[bounds[i] : bounds[i + 1]] for i in range(nparts)]
        [fut_fmu] = client.scatter([fmu_bytes], broadcast=True)
        # the run description without the points (each task carries only its own points)
        [fut_plan] = client.scatter([{k: v for k, v in pl.items() if k != "points"}],
                                    broadcast=True)
        futures = [client.submit(run_partition, fut_fmu, fut_plan, part, pure=False)
                   for part in parts]
        results = []
        t0 = time.perf_counter()
        for done, fut in enumerate(as_completed(futures), 1):
            results.extend(fut.result())
            if progress:
                print(
                    f"\rsweep: {len(results)}/{len(points)} points, {done}/{nparts} partitions,"
                    f" {time.perf_counter() - t0:.1f} s",
                    end="",
                    file=sys.stderr,
                    flush=True,
                )
        if progress:
            print(file=sys.stderr)
    finally:
        for o in own:
            o.close()
        shutil.rmtree(tmp, ignore_errors=True)
    results.sort(key=lambda r: r[0])
    by_point = {p: v for p, v in points}
    rows = [[p, *by_point[p], *vals, status] for p, vals, status, _ in results]
    df = pd.DataFrame(rows, columns=pl["header"])
    if pl["series"] is not None:
        srows = [[p, *row] for p, _, _, series in results for row in series]
        names = ["point", "time", *[o["name"] for o in pl["series"]["outputs"]]]
        df.attrs["series"] = pd.DataFrame(srows, columns=names)
    if output is not None:
        _write(df, rows, pl, Path(output), plot)
    return df


def _write(df, rows, pl: dict, out: Path, plot: bool) -> None:
    if out.suffix == ".parquet":
        df.to_parquet(out)
    else:
        # the CLI's format: reals in their shortest round-trip form
        with open(out, "w") as f:
            f.write(",".join(pl["header"]) + "\n")
            for r in rows:
                f.write(",".join(_fmt(v) for v in r) + "\n")
    if "series" in df.attrs:
        df.attrs["series"].to_csv(out.with_name(out.stem + "_series.csv"), index=False)
    if plot:
        plot_sweep(df, out.with_suffix(".png"), pl)


def plot_sweep(df, path: str | os.PathLike, pl: dict | None = None) -> Path | None:
    """Draws a 1-D or 2-D sweep (the reductions against the first varying setting; one curve
    per value of a second one with few values, else a scatter coloured by the result) into
    ``path``; returns ``None`` for other sweeps."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    settings = [c for c in df.columns[1:] if ":" not in c and c != "status"]
    vary = [c for c in settings if df[c].nunique() > 1]
    reds = [c for c in df.columns if ":" in c][:6]
    if not vary or len(vary) > 2 or not reds:
        return None
    ncol = min(2, len(reds))
    nrow = -(-len(reds) // ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(5 * ncol, 3.4 * nrow), squeeze=False)
    x = vary[0]
    for ax, r in zip(axes.flat, reds):
        if len(vary) == 2 and df[vary[1]].nunique() > 8:
            sc = ax.scatter(df[x], df[vary[1]], c=df[r], cmap="coolwarm", s=12)
            fig.colorbar(sc, ax=ax, label=r)
            ax.set_ylabel(vary[1])
        else:
            groups = df.groupby(vary[1]) if len(vary) == 2 else [(None, df)]
            for key, g in groups:
                g = g.sort_values(x)
                ax.plot(g[x], g[r], "o-", ms=3, label=None if key is None else f"{vary[1]} = {key}")
            if len(vary) == 2:
                ax.legend(fontsize=7)
            ax.set_ylabel(r)
        ax.set_xlabel(x)
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(reds):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)
