"""flexfmu demo: drives the built FMUs with fmpy.

1. Cantilever (seed 000, Problem 2): static large deflection at 2..64 elements vs the paper's Table 3.
2. Flexible pendulum (Problem 4): 1 s of free fall at 8 and 16 elements; tip path and energy balance.
3. Seed-003 co-rotational 3D beam: the Simo & Vu-Quoc right-angle cantilever against the published
   curves (scripts/plot_right_angle.py).
Plots go to build/demo/.
"""
import pathlib

import fmpy
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
FMUS = ROOT / "build" / "fmus"
OUT = ROOT / "build" / "demo"
OUT.mkdir(parents=True, exist_ok=True)

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
