"""flexfmu demo: drives the built FMUs with fmpy.

1. Belt drive (scenes/belt_drive.toml): pulley 1 driven up to 60 rad/s, pulley 2 free with a load
   torque; span tensions, pulley speeds and slip over time, and the belt shape.
2. Cantilever (seed 000, Problem 2): static large deflection at 2..64 elements vs the paper's Table 3.
3. Flexible pendulum (Problem 4): 1 s of free fall at 8 and 16 elements; tip path and energy balance.
4. Seed-003 co-rotational 3D beam: the Simo & Vu-Quoc right-angle cantilever against the published
   curves (scripts/plot_right_angle.py).
5. Seed-004 shell: the strip rolled up by an end moment against the exact arc, and the plate under
   a pressure step (centre deflection over time against the static Navier value).
6. Air spring (issue 11, level 2): design state against the shooting reference, and a short MuJoCo
   quarter car (scripts/air_spring_quarter_car.py) hit by a road bump.
Plots go to build/demo/.
"""
import pathlib

import fmpy
import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
FMUS = ROOT / "build" / "fmus"
OUT = ROOT / "build" / "demo"
OUT.mkdir(parents=True, exist_ok=True)

# --- 1. Belt drive -------------------------------------------------------------------------
print("Belt drive: pulley 1 driven (ramp to 60 rad/s in 0.3 s), pulley 2 free, load torque 4 N m")
h, t_end = 1e-3, 1.0
t = np.arange(0.0, t_end + h / 2, h)
omega = 60.0 * np.minimum(t / 0.3, 1.0)
angle = np.concatenate([[0.0], np.cumsum(0.5 * (omega[1:] + omega[:-1]) * h)])
load = -4.0 * np.minimum(t / 0.3, 1.0)
signals = np.array(list(zip(t, angle, omega, load)),
                   dtype=[("time", float), ("pulley1.angle", float), ("pulley1.omega", float),
                          ("pulley2.torque_in", float)])
belt_fmu = str(FMUS / "belt_drive.fmu")
md = fmpy.read_model_description(belt_fmu)
points = sorted({v.name for v in md.modelVariables if v.name.startswith("belt.point[")},
                key=lambda n: (int(n.split("[")[1].split("]")[0]), n))
outs = ["belt.tension_tight", "belt.tension_slack", "pulley1.torque", "pulley2.omega", "belt.slip",
        "belt.speed", "energy.input_work", "energy.dissipated", "energy.total"] + points
belt = fmpy.simulate_fmu(belt_fmu, stop_time=t_end, output_interval=h, input=signals, output=outs)
last = belt[-1]
print(f"  t = {t_end} s: T_tight = {last['belt.tension_tight']:.1f} N, T_slack = {last['belt.tension_slack']:.1f} N, "
      f"torque on pulley 1 = {last['pulley1.torque']:.3f} N m, omega2 = {last['pulley2.omega']:.3f} rad/s, "
      f"slip = {100 * last['belt.slip']:.3f} %, belt speed = {last['belt.speed']:.3f} m/s")
print(f"  energy: input work {last['energy.input_work']:.2f} J = stored {last['energy.total'] - belt[0]['energy.total']:.2f} J"
      f" + dissipated {last['energy.dissipated']:.2f} J")
fig, (ax1, ax2, ax3) = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
ax1.plot(belt["time"], belt["belt.tension_tight"], label="tight span")
ax1.plot(belt["time"], belt["belt.tension_slack"], label="slack span")
ax1.set_ylabel("span tension [N]"); ax1.legend(); ax1.set_title("Belt drive (100 ANCF cable elements)")
ax2.plot(belt["time"], omega[: len(belt)], label="pulley 1 (driven, input)")
ax2.plot(belt["time"], belt["pulley2.omega"], label="pulley 2 (free)")
ax2.set_ylabel("angular velocity [rad/s]"); ax2.legend()
ax3.plot(belt["time"], 100 * belt["belt.slip"])
ax3.set_ylabel("slip 1 - w2 r2/(w1 r1) [%]"); ax3.set_xlabel("time [s]"); ax3.set_ylim(-2, 2)
fig.tight_layout()
fig.savefig(OUT / "belt_drive.png", dpi=120)
fig, ax = plt.subplots(figsize=(8, 4))
xs = [last[n] for n in points if n.endswith(".x")]
ys = [last[n] for n in points if n.endswith(".y")]
ax.plot(xs + xs[:1], ys + ys[:1], "o-", ms=2, lw=1, label="belt centre line (t = 1 s)")
for (cx, r) in ((0.0, 0.08), (0.5, 0.12)):
    ax.add_patch(plt.Circle((cx, 0.0), r, color="0.8"))
ax.set_aspect("equal"); ax.set_ylim(-0.22, 0.22); ax.set_xlabel("x [m]"); ax.set_ylabel("y [m]"); ax.legend(loc="upper center")
ax.set_title("Belt shape")
fig.tight_layout()
fig.savefig(OUT / "belt_shape.png", dpi=120)
print(f"  plots: {OUT / 'belt_drive.png'}, {OUT / 'belt_shape.png'}\n")

# --- 2. and 3. Seed-000 beam ------------------------------------------------------------------
TABLE_3 = {2: (1.93097, -0.47477), 4: (1.86837, -0.64974), 8: (1.85667, -0.67758),
           16: (1.85526, -0.68046), 32: (1.85497, -0.68100), 64: (1.85489, -0.68114)}

print("Cantilever, tip force -5e5 N (Kerkkanen et al. 2003, Table 3, original 1x1 shear rule)")
print(f"{'n':>4} {'tip.x':>9} {'tip.y':>9}   {'paper x':>9} {'paper y':>9}")
for n, (px, py) in TABLE_3.items():
    r = fmpy.simulate_fmu(str(FMUS / "cantilever.fmu"), stop_time=1e-4, output_interval=1e-4,
                          start_values={"mesh.n_elements": n, "element.shear_rule": 1, "load.fy": -5e5,
                                        "solver.static_equilibrium": True})
    print(f"{n:4d} {r['tip.x'][0]:9.5f} {r['tip.y'][0]:9.5f}   {px:9.5f} {py:9.5f}")

print("\nFlexible pendulum, 1 s (E = 2.07e7 Pa)")
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
for n in (8, 16):
    r = fmpy.simulate_fmu(str(FMUS / "pendulum.fmu"), stop_time=1.0, output_interval=1e-3,
                          start_values={"mesh.n_elements": n})
    drift = abs(r["energy.total"] - r["energy.total"][0]).max()
    print(f"  {n:2d} elements: tip at t = 1 s ({r['tip.x'][-1]:.4f}, {r['tip.y'][-1]:.4f}) m, "
          f"energy drift {drift:.2e} J of {-r['energy.potential'].min():.1f} J exchanged")
    ax1.plot(r["tip.x"], r["tip.y"], label=f"{n} elements")
    if n == 16:
        for key in ("kinetic", "potential", "strain", "total"):
            ax2.plot(r["time"], r[f"energy.{key}"], label=key)
ax1.set_xlabel("tip x [m]"); ax1.set_ylabel("tip y [m]"); ax1.set_aspect("equal"); ax1.legend()
ax1.set_title("Pendulum tip path")
ax2.set_xlabel("time [s]"); ax2.set_ylabel("energy [J]"); ax2.legend(); ax2.set_title("Energy balance (16 elements)")
fig.tight_layout()
fig.savefig(OUT / "pendulum.png", dpi=120)
print(f"\nplots: {OUT / 'pendulum.png'}")

print()
import plot_right_angle  # noqa: E402  (scripts/ is on sys.path when this script runs)

plot_right_angle.main(OUT / "right_angle_cantilever.png")

# --- 5. Seed-004 shell ------------------------------------------------------------------------
print("\nSeed-004 shell strip (scenes/strip.toml): roll-up by an end moment, tip vs the exact arc")
L, EI = 10.0, 100.0
for frac in (0.25, 0.5, 1.0):
    m = frac * 2.0 * np.pi * EI / L
    r = fmpy.simulate_fmu(str(FMUS / "strip.fmu"), stop_time=1e-2, output_interval=1e-2,
                          start_values={"load.my": -m, "solver.load_steps": int(40 * frac)})
    th = m * L / EI
    print(f"  M = {frac:4.2f} x 2 pi EI/L: tip ({r['tip.x'][0]:9.5f}, {r['tip.z'][0]:9.5f}) m, "
          f"exact ({L * np.sin(th) / th:9.5f}, {L * (1 - np.cos(th)) / th:9.5f}) m")

q = 1000.0
D = 210e9 * 0.01 ** 3 / (12 * (1 - 0.3 ** 2))
w_static = 0.00406235 * q / D  # Navier, simply supported square plate, a = 1 m
r = fmpy.simulate_fmu(str(FMUS / "plate.fmu"), stop_time=0.1, output_interval=5e-4,
                      start_values={"load.pressure": q, "solver.static_equilibrium": False})
print(f"Plate, pressure step {q:.0f} Pa: centre deflection swings about {r['centre.z'][len(r) // 2:].mean():.3e} m "
      f"(static Navier {w_static:.3e} m), peak {r['centre.z'].max():.3e} m")
fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(r["time"], 1e3 * r["centre.z"], label="centre deflection (FMU, 10 x 10 elements)")
ax.axhline(1e3 * w_static, color="k", ls="--", label="static, Navier series")
ax.set_xlabel("time [s]"); ax.set_ylabel("centre z [mm]"); ax.legend()
ax.set_title("Seed-004 shell: simply supported steel plate, 1 kPa pressure step")
fig.tight_layout()
fig.savefig(OUT / "plate_step.png", dpi=120)
print(f"plots: {OUT / 'plate_step.png'}")

# --- 6. Air spring ----------------------------------------------------------------------------
import json  # noqa: E402

import air_spring_quarter_car as quarter_car  # noqa: E402

print("\nAir spring, level 2 (scenes/air_spring_axisym.toml): rolling-lobe membrane, 5 bar gauge at 0.25 m")
ref = json.loads((ROOT / "tests" / "data" / "air_spring_reference.json").read_text())["design"]
r = fmpy.simulate_fmu(str(FMUS / "air_spring_axisym.fmu"), stop_time=1e-3, output_interval=1e-3,
                      output=["top.fz", "gas.volume", "spring.effective_area", "spring.stiffness"])
print(f"  design state: F = {r['top.fz'][0]:.1f} N (shooting reference {ref['F']:.1f} N), "
      f"V = {1e3 * r['gas.volume'][0]:.4f} L ({1e3 * ref['V']:.4f} L), "
      f"A_e = {r['spring.effective_area'][0]:.5f} m2 ({ref['A_e']:.5f} m2), k = {r['spring.stiffness'][0]:.0f} N/m")
s_bump, wall, _, car = quarter_car.simulate(FMUS / "air_spring_axisym.fmu", "bump", implicit=False, t_end=1.0)
print(f"  quarter car ({car.sprung:.0f} kg on the spring, {quarter_car.UNSPRUNG:.0f} kg axle, tyre "
      f"{quarter_car.K_TYRE:.0e} N/m) over a 5 cm bump at 10 m/s: body rises {1e3 * s_bump[:, 1].max():.1f} mm, "
      f"peak body acceleration {np.abs(s_bump[:, 3]).max():.2f} m/s2, {s_bump[-1, 0] / wall:.1f}x real time")
fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(s_bump[:, 0], 1e3 * s_bump[:, 5], "k--", label="road")
ax.plot(s_bump[:, 0], 1e3 * s_bump[:, 1], label="body")
ax.plot(s_bump[:, 0], 1e3 * s_bump[:, 2], label="axle")
ax.set_xlabel("time [s]"); ax.set_ylabel("displacement [mm]"); ax.legend()
ax.set_title("Quarter car in MuJoCo with the air-spring FMU: road bump")
fig.tight_layout()
fig.savefig(OUT / "air_spring_bump.png", dpi=120)
print(f"  plot: {OUT / 'air_spring_bump.png'}")
