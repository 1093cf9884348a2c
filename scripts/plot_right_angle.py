"""Simo & Vu-Quoc 1988 right-angle cantilever through the built FMU (fmpy), against the published
curves (digitised, tests/data/simo_vuquoc_1988_right_angle_*.csv).

The elbow force is the paper's triangular pulse, 0 -> 50 at t = 1 s -> 0 at t = 2 s; fmpy holds an
input over each communication step, so the signal handed to fmpy is the pulse at the middle of
each step. Prints the extremes against the reference and writes a plot.

usage: python scripts/plot_right_angle.py [output.png]   (default build/demo/right_angle_cantilever.png)
"""
import pathlib
import sys

import fmpy
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
FMU = ROOT / "build" / "fmus" / "right_angle_cantilever.fmu"
STEP = 0.05


def pulse(t):
    return np.where(t < 1.0, 50.0 * t, np.where(t < 2.0, 50.0 * (2.0 - t), 0.0))


def reference(name):
    """(t, uz) of the digitised curve for 'tip' or 'elbow'."""
    path = ROOT / "tests" / "data" / f"simo_vuquoc_1988_right_angle_{name}.csv"
    return np.loadtxt(path, delimiter=",", comments="#", skiprows=7).T


def simulate(fmu=FMU, step=STEP, **start):
    t = np.arange(0.0, 30.0 + step, step)
    names = ["load.fx", "load.fy", "load.fz", "load.mx", "load.my", "load.mz"]
    signal = np.zeros(len(t), dtype=[("time", np.float64)] + [(n, np.float64) for n in names])
    signal["time"] = t
    signal["load.fz"] = pulse(t + 0.5 * step)
    return fmpy.simulate_fmu(str(fmu), stop_time=30.0, output_interval=step, input=signal,
                             start_values=start, output=["tip.z", "elbow.z", "tip.x", "tip.y"])


def extremes(t, z):
    i, j = int(np.argmax(z)), int(np.argmin(z))
    return (t[i], z[i]), (t[j], z[j])


def compare(r):
    """Rows (name, ours max, ref max, ours min, ref min, RMS deviation / amplitude)."""
    rows = []
    for name in ("tip", "elbow"):
        rt, rz = reference(name)
        z = r[f"{name}.z"]
        (otm, om), (otn, on) = extremes(r["time"], z)
        (rtm, rm), (rtn, rn) = extremes(rt, rz)
        amp = np.abs(rz).max()
        rms = np.sqrt(np.mean((np.interp(rt, r["time"], z) - rz) ** 2))
        rows.append((name, (otm, om), (rtm, rm), (otn, on), (rtn, rn), rms / amp))
    return rows


def main(out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = {
        "lumped, 10 el./leg": simulate(),
        "consistent, 10 el./leg": simulate(**{"element.mass": 2}),
        "lumped, 2 el./leg": simulate(**{"mesh.n_elements": 4}),
    }
    fig, axes = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    for ax, name in zip(axes, ("tip", "elbow")):
        rt, rz = reference(name)
        ax.plot(rt, rz, "ko", ms=4, label="Simo & Vu-Quoc 1988 (digitised)")
        for (label, r), style in zip(runs.items(), ("-", "--", ":")):
            ax.plot(r["time"], r[f"{name}.z"], style, label=f"flexfmu {label}")
        ax.set_ylabel(f"{name} out-of-plane displacement [m]")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[1].set_xlabel("time [s]")
    fig.suptitle("Right-angle cantilever, elbow force pulse (Newmark, dt = 0.05 s)")
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    print("Right-angle cantilever (Simo & Vu-Quoc 1988), flexfmu vs digitised reference")
    for label, r in runs.items():
        for name, omax, rmax, omin, rmin, rel in compare(r):
            print(f"  {label:24s} {name:5s}: max {omax[1]:6.3f} at {omax[0]:5.2f} s (ref {rmax[1]:6.3f} at {rmax[0]:5.2f} s), "
                  f"min {omin[1]:7.3f} at {omin[0]:5.2f} s (ref {rmin[1]:7.3f} at {rmin[0]:5.2f} s), RMS dev. {100 * rel:4.1f} %")
    print(f"plot: {out}")


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "build" / "demo" / "right_angle_cantilever.png")
