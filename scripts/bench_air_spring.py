"""Benchmark of the air spring: runs the Rust example `bench_air_spring` (release, library level,
no FMI overhead), which prints the tables and writes build/bench/air_spring.csv, then plots the
force error against the wall time per simulated second, one point per level and mesh
(docs/air_spring_pareto.png). The error of a run is the design-state force error against the
shooting solution (the mesh) plus the largest deviation of the sine run from the quasi-static
force (the time integration and Newton tolerance), both relative to the design force. Levels 1
(shell) and 3 (effective-area table) appear once their scenes exist.

usage: python scripts/bench_air_spring.py [out-dir]   (default build/bench; the plot goes to docs/)
"""
import csv
import pathlib
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
NAMES = {"1": "level 1 (shell)", "2": "level 2 (axisymmetric membrane)", "3": "level 3 (table)"}


def main():
    out = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "build" / "bench"
    subprocess.run(["cargo", "run", "--release", "--example", "bench_air_spring", str(out)],
                   cwd=ROOT, check=True)
    with open(out / "air_spring.csv") as f:
        rows = list(csv.DictReader(f))
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for level, name in NAMES.items():
        sel = [r for r in rows if r["level"] == level]
        if not sel:
            continue
        x = [1e3 * float(r["wall_per_s"]) for r in sel]
        y = [float(r["design_error"]) + float(r["run_error"]) for r in sel]
        ax.loglog(x, y, "o-", label=name)
        for r, xi, yi in zip(sel, x, y):
            ax.annotate(r["label"], (xi, yi), textcoords="offset points", xytext=(5, 4), fontsize=8)
    ax.axvline(10.0, color="grey", ls=":", lw=1)
    ax.text(10.0, ax.get_ylim()[0], " 100x real time", color="grey", fontsize=8, va="bottom")
    ax.set_xlabel("wall time per simulated second [ms] (1 ms communication steps)")
    ax.set_ylabel("force error / design force")
    ax.set_title("Air spring: 2 Hz, ±10 mm sine of top.z")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = ROOT / "docs" / "air_spring_pareto.png"
    fig.savefig(path, dpi=90)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
