"""Serpentine accessory drive demo (scenes/serpentine.toml, issue 12 item 3) through fmpy.

The crankshaft (pulley 1) is driven through an engine speed ramp (idle 800 rpm, up to 3000 rpm
and held); the accessories load the belt by their speed-proportional bearing damping, the
air-conditioning compressor's clutch engages (a load torque step on pulley7.torque_in). Plots
of span tensions, pulley speeds, slip per pulley, the tensioner's angle and torque, and a picture
of the layout (pulleys, belt, tensioner arm) go to build/demo/. Prints the real-time factor and
the Newton iterations per step the FMU reports in its log.

Usage: scripts/build_fmus.sh (or flexfmu build scenes/serpentine.toml -o build/fmus/serpentine.fmu),
then python scripts/serpentine_demo.py [--t-end 2.0]
"""
import argparse
import pathlib
import time
import tomllib

import fmpy
import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
FMU = ROOT / "build" / "fmus" / "serpentine.fmu"
OUT = ROOT / "build" / "demo"
NAMES = {1: "crankshaft", 2: "tensioner idler", 3: "power steering", 4: "water pump",
         5: "back-side idler", 6: "alternator", 7: "A/C compressor"}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--t-end", type=float, default=2.0)
    ap.add_argument("--step", type=float, default=1e-3)
    args = ap.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    scene = tomllib.loads((ROOT / "scenes" / "serpentine.toml").read_text())
    n_p = len(scene["pulley"])
    h, t_end = args.step, args.t_end
    t = np.arange(0.0, t_end + h / 2, h)
    rpm = np.interp(t, [0.0, 0.2, 0.2 + 0.6 * t_end, t_end], [800.0, 800.0, 3000.0, 3000.0])
    # start from idle: the crank speed ramps from 0 to idle in the first 0.1 s
    rpm *= np.minimum(t / 0.1, 1.0)
    omega = rpm * 2 * np.pi / 60
    angle = np.concatenate([[0.0], np.cumsum(0.5 * (omega[1:] + omega[:-1]) * h)])
    # A/C clutch engages at 40 % of the run: 5 N m more load on pulley 7 over 50 ms
    ac = -5.0 * np.clip((t - 0.4 * t_end) / 0.05, 0.0, 1.0)
    signals = np.array(list(zip(t, angle, omega, ac)),
                       dtype=[("time", float), ("pulley1.angle", float), ("pulley1.omega", float),
                              ("pulley7.torque_in", float)])
    outs = ([f"span{i}.tension" for i in range(1, n_p + 1)]
            + [f"pulley{i}.omega" for i in range(2, n_p + 1)]
            + [f"pulley{i}.slip" for i in range(2, n_p + 1)]
            + ["pulley1.torque", "tensioner.angle", "tensioner.torque",
               "energy.input_work", "energy.dissipated", "energy.total"])
    md = fmpy.read_model_description(str(FMU))
    points = sorted({v.name for v in md.modelVariables if v.name.startswith("belt.point[")},
                    key=lambda n: int(n.split("[")[1].split("]")[0]))
    outs += points
    logs = []

    def logger(*a):
        logs.append(a[-1].decode() if isinstance(a[-1], bytes) else str(a[-1]))

    wall = time.perf_counter()
    r = fmpy.simulate_fmu(str(FMU), stop_time=t_end, output_interval=h, input=signals,
                          output=outs, debug_logging=True, logger=logger)
    wall = time.perf_counter() - wall
    print(f"serpentine drive: {t_end} s simulated in {wall:.2f} s wall: "
          f"real-time factor {t_end / wall:.2f} (incl. instantiation and pre-load)")
    stats = [line for line in logs if "iterations" in line.lower()]
    if stats:
        print("  solver:", stats[-1][:300])
    last = r[-1]
    for i in range(1, n_p + 1):
        print(f"  span{i} ({NAMES[i]} -> {NAMES[i % n_p + 1]}): {last[f'span{i}.tension']:.1f} N")
    print(f"  tensioner angle {1e3 * last['tensioner.angle']:.2f} mrad, torque {last['tensioner.torque']:.2f} N m, "
          f"crank torque {last['pulley1.torque']:.2f} N m")
    w = last["energy.input_work"]
    bal = w - (last["energy.total"] - r[0]["energy.total"]) - last["energy.dissipated"]
    print(f"  energy: input {w:.1f} J, mismatch {bal:.3f} J ({100 * abs(bal) / max(abs(w), 1e-9):.2f} %)")

    fig, ax = plt.subplots(2, 2, figsize=(13, 8), sharex=True)
    for i in range(1, n_p + 1):
        ax[0, 0].plot(r["time"], r[f"span{i}.tension"], label=f"span {i}: {NAMES[i]} → {NAMES[i % n_p + 1]}")
    ax[0, 0].set_ylabel("span tension [N]")
    ax[0, 0].legend(fontsize=7)
    ax[0, 1].plot(t, omega * 60 / (2 * np.pi), "k--", label="crankshaft (input)")
    for i in range(2, n_p + 1):
        ax[0, 1].plot(r["time"], r[f"pulley{i}.omega"] * 60 / (2 * np.pi), label=NAMES[i])
    ax[0, 1].set_ylabel("pulley speed [rpm] (back side negative)")
    ax[0, 1].legend(fontsize=7)
    for i in range(2, n_p + 1):
        ax[1, 0].plot(r["time"], 100 * r[f"pulley{i}.slip"], label=NAMES[i])
    ax[1, 0].set_ylabel("slip against the crankshaft [%]")
    ax[1, 0].set_ylim(-2, 5)
    ax[1, 0].legend(fontsize=7)
    ax[1, 0].set_xlabel("time [s]")
    a2 = ax[1, 1].twinx()
    ax[1, 1].plot(r["time"], 1e3 * r["tensioner.angle"], "C0")
    a2.plot(r["time"], r["tensioner.torque"], "C3")
    ax[1, 1].set_ylabel("tensioner angle [mrad]", color="C0")
    a2.set_ylabel("tensioner torque [N m]", color="C3")
    ax[1, 1].set_xlabel("time [s]")
    fig.suptitle("Serpentine drive: engine ramp 800 → 3000 rpm, A/C clutch at "
                 f"{0.4 * t_end:.1f} s")
    fig.tight_layout()
    fig.savefig(OUT / "serpentine.png", dpi=120)

    fig, ax = plt.subplots(figsize=(7, 8))
    xs = [last[f"belt.point[{k}].x"] for k in range(1, len(points) // 2 + 1)]
    ys = [last[f"belt.point[{k}].y"] for k in range(1, len(points) // 2 + 1)]
    ax.plot(xs + xs[:1], ys + ys[:1], "k-", lw=1.5, label=f"belt centre line (t = {t_end} s)")
    ten = scene["tensioner"]
    for i, p in enumerate(scene["pulley"], start=1):
        c = np.array(p["center"], float)
        if i == ten["pulley"]:
            piv = np.array(ten["pivot"], float)
            arm = c - piv
            psi = np.arctan2(arm[1], arm[0]) + last["tensioner.angle"]
            c = piv + np.linalg.norm(arm) * np.array([np.cos(psi), np.sin(psi)])
            ax.plot([piv[0], c[0]], [piv[1], c[1]], "C3-", lw=4, alpha=0.6, label="tensioner arm")
            ax.plot(*piv, "C3s")
        style = "--" if p.get("side", "front") == "back" else "-"
        ax.add_patch(plt.Circle(c, p["radius"], fill=False, ls=style, color=f"C{i % 10}"))
        ax.annotate(f"{i}: {NAMES[i]}", c, ha="center", va="center", fontsize=7)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.legend(loc="lower left", fontsize=7)
    ax.set_title("Serpentine layout (dashed: back side of the belt)")
    fig.savefig(OUT / "serpentine_layout.png", dpi=120)
    print(f"plots: {OUT / 'serpentine.png'}, {OUT / 'serpentine_layout.png'}")


if __name__ == "__main__":
    main()
