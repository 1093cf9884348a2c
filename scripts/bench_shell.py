"""Benchmark of the seed-004 trapezoidal shell: runs the Rust example `bench_shell` (release,
library level, no FMI overhead), which prints the tables and writes CSV, then plots
  - error against wall time per simulated second on the strip's free vibration, one curve per
    integrator and mesh over the internal step, Pareto-optimal runs ringed (docs/shell_pareto.png),
  - cost per element per Newton iteration against the plate mesh, and the closed cylinder's
    static solve and dynamic step against the number of rings (build/bench/shell_bench.png).

usage: python scripts/bench_shell.py [out-dir]   (default build/bench; the Pareto plot goes to docs/)
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


def pareto(rows, path):
    fig, ax = plt.subplots(figsize=(7.5, 5.2))
    markers = {"5": "o", "10": "s", "20": "^"}
    colors = {"1": "C0", "2": "C1", "3": "C2"}
    for code in ("1", "2", "3"):
        for n_x, marker in markers.items():
            sel = [r for r in rows if r["code"] == code and r["n_x"] == n_x]
            x = [1e3 * float(r["wall_per_simulated_s"]) for r in sel]
            y = [float(r["error"]) for r in sel]
            ax.loglog(x, y, marker + "-", color=colors[code], alpha=0.8, ms=5,
                      label=f"{sel[0]['integrator']}, n_x = {n_x}")
    best = sorted((r for r in rows if r["pareto"] == "1"), key=lambda r: float(r["wall_per_simulated_s"]))
    ax.loglog([1e3 * float(r["wall_per_simulated_s"]) for r in best], [float(r["error"]) for r in best],
              "k:", lw=1.2, label="Pareto front")
    for r in best:
        ax.annotate(f"dt={r['dt']}", (1e3 * float(r["wall_per_simulated_s"]), float(r["error"])),
                    textcoords="offset points", xytext=(4, 4), fontsize=6)
    ax.set_xlabel("wall time per simulated second [ms]")
    ax.set_ylabel("max |tip.z - reference| / amplitude")
    ax.set_title("Shell strip, free vibration: error vs wall time\n(meshes n_x x 2, integrators, steps dt)")
    ax.grid(which="both", alpha=0.3)
    ax.legend(fontsize=6, ncol=3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"plot: {path}")


def costs(cost, cyl, path):
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.6))
    for variant, marker in (("V2", "o-"), ("V1", "s--"), ("V2 + geometric", "^:")):
        sel = [r for r in cost if r["variant"] == variant]
        ax1.semilogx([int(r["elements"]) for r in sel], [float(r["assemble_us_per_element"]) for r in sel],
                     marker, label=f"{variant}: force + tangent + assembly")
    sel = [r for r in cost if r["factor_auto_us_per_element"]]
    ax1.semilogx([int(r["elements"]) for r in sel], [float(r["factor_auto_us_per_element"]) for r in sel],
                 "kx-", alpha=0.5, label="factor + solve (auto)")
    ax1.semilogx([int(r["elements"]) for r in sel], [float(r["factor_sparse_us_per_element"]) for r in sel],
                 "k+--", alpha=0.5, label="factor + solve (sparse LU)")
    ax1.axhline(10.0, color="r", lw=0.8, label="target 10 us")
    ax1.set_xlabel("plate elements")
    ax1.set_ylabel("us per element per Newton iteration")
    ax1.set_yscale("log")
    ax1.grid(which="both", alpha=0.3)
    ax1.legend(fontsize=7)
    ax1.set_title("Cost per element per Newton iteration (plate)")
    rings = [int(r["rings"]) for r in cyl]
    ax2.plot(rings, [1e3 * float(r["static_s"]) for r in cyl], "o-", label="static solve [ms]")
    ax2.plot(rings, [1e4 * float(r["step_s"]) for r in cyl], "s-", label="dynamic step [0.1 ms]")
    ax2.set_xlabel("rings (n_meridional), n_circumferential = 16")
    ax2.set_ylabel("wall time")
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=7)
    ax2.set_title("Closed cylinder: cost against the rings")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"plot: {path}")


def main(out):
    out.mkdir(parents=True, exist_ok=True)
    subprocess.run(["cargo", "run", "--release", "--quiet", "--example", "bench_shell", "--", str(out)],
                   cwd=ROOT, check=True)
    pareto(read(out / "shell_pareto.csv"), ROOT / "docs" / "shell_pareto.png")
    costs(read(out / "shell_cost.csv"), read(out / "shell_cylinder.csv"), out / "shell_bench.png")


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "build" / "bench")
