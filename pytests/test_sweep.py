"""Sweeps (issue 15, items 3 and 4): the 200-point pendulum sweep gives identical numbers from
the CLI run serially (one thread), on worker threads, in chunks merged, and through the Python
package on a dask local cluster (fmpy's FMU2Slave, one instance per partition); a sweep with
an input CSV likewise; the wheel installs in a fresh virtual environment and drives a sweep."""

import math
import os
import subprocess
import sys
import sysconfig
import time
import venv

import pandas as pd
import pytest

from conftest import ROOT

sys.path.insert(0, str(ROOT / "python"))
import flexfmu  # noqa: E402

CLI = ROOT / "target" / "release" / "flexfmu"
SWEEPS = ROOT / "examples" / "sweeps"


@pytest.fixture(scope="module")
def built(fmus):
    """The CLI and library of this checkout (scripts/build_fmus.sh builds them)."""
    return CLI


def cli_sweep(sweep, out, *args):
    subprocess.run(
        [str(CLI), "sweep", str(sweep), "-o", str(out), "-q", *args],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    return pd.read_csv(out)


def assert_identical(a: pd.DataFrame, b: pd.DataFrame, what: str):
    assert list(a.columns) == list(b.columns), what
    assert len(a) == len(b), what
    assert (a["status"] == "ok").all() and (b["status"] == "ok").all(), what
    for c in a.columns:
        if c == "status":
            continue
        for i, (x, y) in enumerate(zip(a[c], b[c])):
            same = x == y or (isinstance(x, float) and math.isnan(x) and math.isnan(y))
            assert same, f"{what}: row {i}, {c}: {x!r} != {y!r}"


def test_200_point_pendulum_sweep_is_identical_on_cli_threads_chunks_and_dask(built, tmp_path):
    sweep = SWEEPS / "pendulum_lhs.toml"
    t0 = time.perf_counter()
    serial = cli_sweep(sweep, tmp_path / "serial.csv", "--threads", "1")
    t_serial = time.perf_counter() - t0
    assert len(serial) == 200
    # the points differ: the Latin hypercube moved every run
    assert serial["tip.y:final"].nunique() == 200
    threads = cli_sweep(sweep, tmp_path / "threads.csv", "--threads", "2")
    assert_identical(serial, threads, "CLI 1 thread vs 2 threads")
    for k in (1, 2, 3):
        cli_sweep(sweep, tmp_path / f"c{k}.csv", "--chunk", f"{k}/3")
    subprocess.run(
        [str(CLI), "sweep", "--merge", *[str(tmp_path / f"c{k}.csv") for k in (3, 1, 2)],
         "-o", str(tmp_path / "merged.csv")],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    assert_identical(serial, pd.read_csv(tmp_path / "merged.csv"), "CLI vs chunks merged")
    t0 = time.perf_counter()
    df = flexfmu.sweep(sweep, output=tmp_path / "dask.csv", progress=False)
    t_dask = time.perf_counter() - t0
    assert_identical(serial, df, "CLI vs dask (DataFrame)")
    assert_identical(serial, pd.read_csv(tmp_path / "dask.csv"), "CLI vs dask (CSV)")
    series = df.attrs["series"]
    assert sorted(series["point"].unique()) == [0, 199]
    cli_series = pd.read_csv(tmp_path / "serial_series.csv")
    assert (series["tip.y"].to_numpy() == cli_series["tip.y"].to_numpy()).all()
    print(f"\n200-point pendulum sweep: CLI 1 thread {t_serial:.2f} s, dask local cluster "
          f"(start-up included) {t_dask:.2f} s")


def test_a_2d_sweep_with_an_input_csv_on_a_given_client(built, tmp_path):
    from dask.distributed import Client, LocalCluster

    sweep = SWEEPS / "cantilever_load.toml"
    cli = cli_sweep(sweep, tmp_path / "cli.csv")
    assert (tmp_path / "cli.svg").is_file()
    # the load ramps in: the tip goes down, more for the softer and thinner beams
    assert (cli["tip.y:final"] < 0).all()
    assert cli["tip.y:final"].iloc[0] < cli["tip.y:final"].iloc[-1]
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True) as cluster, \
            Client(cluster) as client:
        df = flexfmu.sweep(sweep, client=client, output=tmp_path / "d.parquet", partitions=3,
                           progress=False)
    assert_identical(cli, df, "CLI vs dask with an input CSV")
    assert_identical(cli, pd.read_parquet(tmp_path / "d.parquet"), "Parquet")
    assert (tmp_path / "d.png").stat().st_size > 10_000


def test_bad_sweep_file_names_the_key_from_python(built, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text((SWEEPS / "pendulum.toml").read_text().replace(
        '"../../scenes/pendulum.toml"', str(ROOT / "scenes" / "pendulum.toml").join('""')
    ).replace('reduce = ["final", "min", "mean"]', 'reduce = ["median"]'))
    with pytest.raises(flexfmu.FlexfmuError, match=r"outputs\[0\]\.reduce"):
        flexfmu.sweep(bad)


def test_wheel_installs_in_a_fresh_venv_and_drives_a_sweep(built, tmp_path):
    """`pip wheel .` (setup.py: cargo build --release reusing ./target, both binaries copied
    into the package), installed without an index into a new virtual environment whose
    dependencies come from this one (a .pth file), then a sweep and a build from there."""
    try:
        import setuptools  # noqa: F401
        import wheel  # noqa: F401
    except ImportError as e:
        pytest.skip(f"building the wheel without an index needs setuptools and wheel: {e}")
    t0 = time.perf_counter()
    dist = tmp_path / "dist"
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-build-isolation", "--no-deps", "-q",
         "-w", str(dist), str(ROOT)],
        check=True,
        cwd=tmp_path,
    )
    (whl,) = dist.glob("flexfmu-*.whl")
    t_wheel = time.perf_counter() - t0
    env_dir = tmp_path / "venv"
    venv.EnvBuilder(with_pip=False).create(env_dir)
    py = env_dir / "bin" / "python"
    site = subprocess.run(
        [str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        check=True, capture_output=True, text=True,
    ).stdout.strip()
    # the dependencies (fmpy, dask, pandas, ...) of the test environment, after the venv's own
    with open(os.path.join(site, "zz_test_deps.pth"), "w") as f:
        f.write(sysconfig.get_paths()["purelib"] + "\n")
    # this environment's pip installs into the new one (pip --python): no pip bootstrap there
    subprocess.run([sys.executable, "-m", "pip", "--python", str(py), "install", "-q", "--no-deps",
                    "--no-index", str(whl)], check=True)
    script = f"""
import flexfmu, pathlib, pandas as pd
assert 'site-packages' in flexfmu.__file__, flexfmu.__file__
assert flexfmu.cli_path().parent.parent == pathlib.Path(flexfmu.__file__).parent
print(flexfmu.check(r"{ROOT / 'scenes' / 'pendulum.toml'}")[0])
fmu = flexfmu.build(r"{ROOT / 'scenes' / 'pendulum.toml'}", "p.fmu")
from dask.distributed import Client
with Client(processes=False, n_workers=1, threads_per_worker=2) as client:  # quick to start
    df = flexfmu.sweep(r"{SWEEPS / 'cantilever_load.toml'}", client=client, output="w.csv",
                       progress=False)
cli = pd.read_csv(r"{tmp_path / 'cli.csv'}")
assert (df["tip.y:final"].to_numpy() == cli["tip.y:final"].to_numpy()).all()
r = flexfmu.simulate(fmu, stop_time=0.01, output_interval=0.005)
print(len(df), "points;", r["tip.y"][-1])
"""
    cli_sweep(SWEEPS / "cantilever_load.toml", tmp_path / "cli.csv")
    env = {k: v for k, v in os.environ.items() if k not in ("FLEXFMU_CLI", "FLEXFMU_LIBRARY",
                                                             "PYTHONPATH")}
    out = subprocess.run([str(py), "-c", script], cwd=tmp_path, env=env, capture_output=True,
                         text=True)
    assert out.returncode == 0, out.stderr[-3000:]
    assert "pendulum" in out.stdout and "10 points" in out.stdout, out.stdout
    # the console script runs the packaged executable
    check = subprocess.run([str(env_dir / "bin" / "flexfmu"), "check",
                            str(ROOT / "scenes" / "pendulum.toml")],
                           capture_output=True, text=True, env=env)
    assert check.returncode == 0 and "ok" in check.stdout, check.stderr
    print(f"\nwheel: built in {t_wheel:.1f} s ({whl.stat().st_size / 1e6:.1f} MB), whole test "
          f"{time.perf_counter() - t0:.1f} s")
