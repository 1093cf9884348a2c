"""Benchmark of the seed-003 co-rotational 3D beam: runs the Rust example `bench_beam_3d` (release,
library level, no FMI overhead), which prints the tables and writes CSV, then plots
  - error against wall time on the Simo & Vu-Quoc right-angle cantilever, one curve per inertia
    model over element counts (2..64) and one over internal steps (20 elements),
  - cost per element per Newton iteration against the element count.

usage: python scripts/bench_beam_3d.py [out-dir]   (default build/bench; writes corot_bench.png)
"""
import csv
import pathlib
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main(out):
    out.mkdir(parents=True, exist_ok=True)
    subprocess.run(["cargo", "run", "--release", "--quiet", "--example", "bench_beam_3d", "--", str(out)],
                   cwd=ROOT, check=True)
    cost = read(out / "corot_cost.csv")
    trade = read(out / "corot_tradeoff.csv")
    names = {"1": "lumped (3 masses)", "2": "consistent"}
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
    colors = {"1": "C0", "2": "C1"}
    for mass, marker in (("1", "o-"), ("2", "s--")):
        rows = [r for r in trade if r["study"] == "elements" and r["mass"] == mass]
        x = [float(r["wall_s"]) for r in rows]
        y = [float(r["error"]) for r in rows]
        ax1.loglog(x, y, marker, color=colors[mass], label=f"{names[mass]}, 2..64 elements, dt = 0.05 s")
        for r, xi, yi in zip(rows, x, y):
            ax1.annotate(r["n_elements"], (xi, yi), textcoords="offset points", xytext=(4, 4), fontsize=7)
    rows = [r for r in trade if r["study"] == "step"]
    ax1.loglog([float(r["wall_s"]) for r in rows], [float(r["error"]) for r in rows], "^:", color="C2",
               label="lumped, 20 elements, dt = 0.05..0.00625 s (time error)")
    ax1.set_xlabel("wall time for 30 s [s]")
    ax1.set_ylabel("max deviation of tip/elbow z / amplitude")
    ax1.set_title("Right-angle cantilever: error vs wall time")
    ax1.grid(which="both", alpha=0.3)
    ax1.legend(fontsize=7)
    for mass, marker in (("1", "o-"), ("2", "s--")):
        rows = [r for r in cost if r["mass"] == mass]
        n = [int(r["n_elements"]) for r in rows]
        ax2.semilogx(n, [float(r["assemble_us_per_element"]) + float(r["factor_solve_us_per_element"]) for r in rows],
                     marker, color=colors[mass], label=f"{names[mass]}: total")
        ax2.semilogx(n, [float(r["assemble_us_per_element"]) for r in rows], marker, color=colors[mass], alpha=0.4,
                     label=f"{names[mass]}: force + tangent + assembly")
    ax2.set_xlabel("elements")
    ax2.set_ylabel("us per element per Newton iteration")
    ax2.set_ylim(bottom=0)
    ax2.set_title("Cost per element per Newton iteration (cantilever3d)")
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "corot_bench.png", dpi=110)
    print(f"plot: {out / 'corot_bench.png'}")


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "build" / "bench")
