"""3D belt drive demo (issue 13): a belt walking onto a flange, and a 3D picture of the drive.

Needs build/fmus/belt_drive_3d.fmu (scripts/build_fmus.sh). Pulley 1 is driven at 10 rad/s
(ramped over 0.1 s), pulley 2 skewed by `pulley2.skew` = 0.03 rad (first argument): the span enters its rim at
that angle and the belt walks sideways at about belt speed x skew until a flange stops it.
Writes build/demo/belt_3d_walk.png (lateral position and flange force against time) and
build/demo/belt_3d_drive.png (the drive in 3D at the end, lateral scale exaggerated).
"""
import pathlib
import sys

import fmpy
import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
FMU = ROOT / "build" / "fmus" / "belt_drive_3d.fmu"
OUT = ROOT / "build" / "demo"
OUT.mkdir(parents=True, exist_ok=True)

skew = float(sys.argv[1]) if len(sys.argv) > 1 else 0.03
h, t_end = 1e-3, 1.2
t = np.arange(0.0, t_end + h / 2, h)
omega = 10.0 * np.minimum(t / 0.1, 1.0)
angle = np.concatenate([[0.0], np.cumsum(0.5 * (omega[1:] + omega[:-1]) * h)])
signals = np.array(list(zip(t, angle, omega)),
                   dtype=[("time", float), ("pulley1.angle", float), ("pulley1.omega", float)])
md = fmpy.read_model_description(str(FMU))
points = [v.name for v in md.modelVariables if v.name.startswith("belt.point[")]
outs = ["belt1.lateral", "belt2.lateral", "pulley2.flange_force", "pulley1.flange_force",
        "belt.speed", "pulley2.force_z", "pulley2.moment_x", "pulley2.moment_y"] + points
res = fmpy.simulate_fmu(str(FMU), stop_time=t_end, output_interval=h, input=signals, output=outs,
                        start_values={"pulley2.skew": skew})
i0, i1 = np.searchsorted(res["time"], [0.2, 0.4])
rate = (res["belt2.lateral"][i1] - res["belt2.lateral"][i0]) / (res["time"][i1] - res["time"][i0])
v = res["belt.speed"][i0:i1].mean()
print(f"skew {skew} rad: lateral speed on pulley 2 {1e3 * rate:.2f} mm/s, belt speed x skew "
      f"{1e3 * v * skew:.2f} mm/s; at {t_end} s belt2.lateral = {1e3 * res['belt2.lateral'][-1]:.2f} mm, "
      f"largest |pulley2.flange_force| = {np.abs(res['pulley2.flange_force']).max():.2f} N")

fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
ax1.plot(res["time"], 1e3 * res["belt2.lateral"], label="on pulley 2 (skewed)")
ax1.plot(res["time"], 1e3 * res["belt1.lateral"], label="on pulley 1")
tt = res["time"][(res["time"] > 0.1) & (res["time"] < 0.6)]
for frac, style in [(1.0, "k:"), (0.5, "k--")]:
    ax1.plot(tt, 1e3 * (res["belt2.lateral"][i0] + np.sign(rate) * frac * v * skew * (tt - res["time"][i0])),
             style, label=f"{frac:g} x belt speed x skew")
ax1.set_ylabel("lateral position [mm]"); ax1.legend()
ax1.set_title(f"belt_drive_3d: pulley 2 skewed by {skew} rad, belt walks onto the flange")
ax2.plot(res["time"], np.abs(res["pulley2.flange_force"]), label="pulley 2")
ax2.plot(res["time"], np.abs(res["pulley1.flange_force"]), label="pulley 1")
ax2.set_ylabel("|flange force| [N]"); ax2.set_xlabel("time [s]"); ax2.legend()
fig.tight_layout(); fig.savefig(OUT / "belt_3d_walk.png", dpi=120)

last = res[-1]
n = len(points) // 3
xyz = np.array([[last[f"belt.point[{k}].{c}"] for c in "xyz"] for k in range(1, n + 1)])
xyz = np.vstack([xyz, xyz[:1]])
fig = plt.figure(figsize=(8, 5))
ax = fig.add_subplot(projection="3d")
ax.plot(xyz[:, 0], xyz[:, 1], 20 * xyz[:, 2], "b.-", label="belt centre line (z x 20)")
for c, r, a in [((0, 0, 0), 0.08, (0, 0, 1)), ((0.5, 0, 0), 0.12, (np.sin(skew), 0, np.cos(skew)))]:
    a = np.array(a) / np.linalg.norm(a)
    u = np.cross(a, [0, 1, 0]); u /= np.linalg.norm(u); w = np.cross(a, u)
    s = np.linspace(0, 2 * np.pi, 100)
    for off in (-0.02, 0.02):
        ring = np.array(c) + off * a + r * (np.outer(np.cos(s), u) + np.outer(np.sin(s), w))
        ax.plot(ring[:, 0], ring[:, 1], 20 * ring[:, 2], "k-", lw=0.8)
ax.set_xlabel("x [m]"); ax.set_ylabel("y [m]"); ax.set_zlabel("20 z [m]"); ax.legend()
ax.set_title(f"belt_drive_3d at t = {t_end} s (rim edges of both pulleys)")
fig.tight_layout(); fig.savefig(OUT / "belt_3d_drive.png", dpi=120)
print(f"plots: {OUT / 'belt_3d_walk.png'}, {OUT / 'belt_3d_drive.png'}")
