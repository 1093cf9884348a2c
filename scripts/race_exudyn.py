"""The race with Exudyn (issue 15, item 5): the soft pendulum with the ANCF cable element in
flexfmu (scenes/pendulum.toml with element.type = 2, through fmpy) against Exudyn's
ObjectANCFCable2D (PyPI exudyn, fast module, one thread) on the same physics, side by side in
one run.

Physics (both programs): the seed-000 pendulum of Kerkkanen et al. 2003, Problem 4: L = 2 m,
0.1 m x 0.1 m, E = 2.07e7 Pa, rho = 7850 kg/m3, pinned at x = 0, released horizontally at rest
under g = 9.81 m/s2, 1 s; Euler-Bernoulli cable with EA = E b h, EI = E b h^3/12,
rhoA = rho b h, axial strain |r'| - 1, curvature (r' x r'')/|r'|^2, full Gauss integration
(5 points axial, 3 bending: Exudyn's default, flexfmu's CableRule::Full), consistent mass and
gravity.

Reference: the converged Euler-Bernoulli solution, Richardson-extrapolated from flexfmu's
finest runs (generalized-alpha, full Newton, tight tolerance): in space from 32, 64 and 128
elements at h = 1e-4 s (order estimated from the three), in time from h = 2e-4 and 1e-4 s at
128 elements (order 2). Exudyn's finest run is compared with it too (the same physics must
converge to the same answer).

Error: the largest distance of the tip from the reference over the run, sampled every 20 ms
(every step size of the grid divides 20 ms: no interpolation enters). Wall time: the solver
only, the best of repeated runs until they together took 0.2 s, at most seven (a run over 0.2 s
runs once; the same rule for both programs: short runs are the noisy ones) (flexfmu: one
fmi2DoStep over the whole second;
Exudyn: SolveDynamic with the sensor off; setup, assembly and initialization excluded for both).
Each (elements, step) cell runs both programs one after the other, so machine load affects
both alike.

Settings tried (each program's fastest configuration at each error level wins):
  flexfmu: generalized-alpha (rho_inf 0.9) and Newmark (trapezoidal); modified and full Newton;
           solver.newton_tolerance 1e-10 (default), 1e-7 and 1e-5 (on the increment, relative
           to L);
  Exudyn:  GeneralizedAlpha (spectralRadius 0.9) and TrapezoidalIndex2; modified and full Newton;
           newton.relativeTolerance 1e-8 (default), 1e-6 and 1e-4; EXUdense, EigenDense and
           EigenSparse (reuseAnalyzedPattern) linear solvers; full and reduced-order integration of the element (useReducedOrderIntegration
           0 and 1; reduced integration is a slightly different discretization, measured against
           the same reference);
  both:    elements 2..32, steps 2e-2..2.5e-4 s.

Also: the cost per element per Newton iteration of the cable (examples/bench_cable.rs) against
Exudyn's residual and Jacobian (MainSolverImplicitSecondOrder.ComputeNewtonResidual /
ComputeNewtonJacobian, timed from Python on 16 and 256 elements, the difference per element).

Writes docs/race_exudyn.png (Pareto fronts), docs/race_exudyn.csv (every run) and prints the
tables (markdown). Run: python scripts/race_exudyn.py [--quick | --fine] [--fresh]   (about 40 min on a
loaded 2-core machine; --quick: 3 min; --fine: the three finest error levels only, about 15 min,
written to build/race/ instead of docs/; the reference runs are cached in build/race/)
"""
import argparse
import csv
import math
import os
import pathlib
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
FMU = ROOT / "build" / "fmus" / "pendulum.fmu"
DOCS = ROOT / "docs"
T_END = 1.0
SAMPLE = 2e-2
E, RHO, L, B, H, G = 2.07e7, 7850.0, 2.0, 0.1, 0.1, 9.81
A, I = B * H, B * H ** 3 / 12
LEVELS = [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5]


# ----------------------------------------------------------------------------------------------
# flexfmu through fmpy
# ----------------------------------------------------------------------------------------------

REPS = 7  # at most this many timed runs per configuration


def enough(spent):
    """Stop repeating once the timed runs together took 0.2 s (a run over 0.2 s runs once)."""
    return spent > 0.2


class Flexfmu:
    """The pendulum FMU, extracted once; one FMU2Slave per run."""

    def __init__(self):
        from fmpy import extract, read_model_description
        self.md = read_model_description(str(FMU))
        self.dir = extract(str(FMU), unzipdir=tempfile.mkdtemp())
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.types = {v.name: v.type for v in self.md.modelVariables}

    def instance(self, params):
        from fmpy.fmi2 import FMU2Slave
        s = FMU2Slave(guid=self.md.guid, unzipDirectory=self.dir,
                      modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName="race")
        s.instantiate()
        s.setupExperiment(startTime=0.0)
        for k, v in params.items():
            if self.types[k] == "Integer":
                s.setInteger([self.vr[k]], [int(v)])
            else:
                s.setReal([self.vr[k]], [float(v)])
        s.enterInitializationMode()
        s.exitInitializationMode()
        return s

    def run(self, n, h, integrator, newton, tol, record=True, reps=REPS):
        params = {"element.type": 2, "mesh.n_elements": n, "solver.integrator": integrator,
                  "solver.max_step": h, "solver.newton": newton, "solver.newton_tolerance": tol}
        wall, spent = math.inf, 0.0
        for _ in range(reps):
            s = self.instance(params)
            t0 = time.perf_counter()
            s.doStep(0.0, T_END)
            dt = time.perf_counter() - t0
            s.terminate()
            s.freeInstance()
            wall, spent = min(wall, dt), spent + dt
            if enough(spent):
                break
        traj = None
        if record:
            s = self.instance(params)
            k = int(round(T_END / SAMPLE))
            traj = np.empty((k + 1, 2))
            tip = [self.vr["tip.x"], self.vr["tip.y"]]
            traj[0] = s.getReal(tip)
            for i in range(k):
                s.doStep(i * SAMPLE, SAMPLE)
                traj[i + 1] = s.getReal(tip)
            s.terminate()
            s.freeInstance()
        return wall, traj

    def close(self):
        shutil.rmtree(self.dir, ignore_errors=True)


# ----------------------------------------------------------------------------------------------
# Exudyn
# ----------------------------------------------------------------------------------------------

def exudyn_system(n, reduced):
    sys.exudynFast = True
    import exudyn as exu
    from exudyn.beams import GenerateBeamElementsAlongLine
    from exudyn.itemInterface import ObjectANCFCable2D
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    tmpl = ObjectANCFCable2D(physicsMassPerLength=RHO * A, physicsBendingStiffness=E * I,
                             physicsAxialStiffness=E * A, useReducedOrderIntegration=int(reduced))
    d = GenerateBeamElementsAlongLine(mbs, [0, 0, 0], [L, 0, 0], n, tmpl, gravity=[0, -G, 0],
                                      groundConstraintsStart=[1, 1, 0, 0])
    return exu, sc, mbs, d


def exudyn_settings(exu, h, solver, modified, tol, linear):
    ss = exu.SimulationSettings()
    ss.timeIntegration.numberOfSteps = int(round(T_END / h))
    ss.timeIntegration.endTime = T_END
    ss.timeIntegration.verboseMode = 0
    ss.timeIntegration.generalizedAlpha.spectralRadius = 0.9
    ss.timeIntegration.newton.useModifiedNewton = modified
    ss.timeIntegration.newton.relativeTolerance = tol
    if hasattr(ss, "solution"):  # Exudyn >= 1.13 (the old names are deprecated)
        ss.solution.file.write = False
    else:
        ss.solutionSettings.writeSolutionToFile = False
    if hasattr(ss, "solution"):  # Exudyn >= 1.13 (the old name is deprecated)
        ss.solution.sensors.writePeriod = SAMPLE
    else:
        ss.solutionSettings.sensorsWritePeriod = SAMPLE
    ss.parallel.numberOfThreads = 1
    ss.linearSolver.reuseAnalyzedPattern = True
    ss.linearSolver.solverType = getattr(exu.LinearSolverType, linear)
    return ss, (exu.DynamicSolverType.TrapezoidalIndex2 if solver == "trapezoidal"
                else exu.DynamicSolverType.GeneralizedAlpha)


def exudyn_run(n, h, solver, modified, tol, linear, reduced, record=True, reps=REPS):
    from exudyn.itemInterface import SensorNode
    wall, spent = math.inf, 0.0
    for _ in range(reps):
        exu, sc, mbs, d = exudyn_system(n, reduced)
        mbs.Assemble()
        ss, st = exudyn_settings(exu, h, solver, modified, tol, linear)
        t0 = time.perf_counter()
        exu.SolveDynamic(mbs, ss, solverType=st)
        dt = time.perf_counter() - t0
        wall, spent = min(wall, dt), spent + dt
        if enough(spent):
            break
    traj = None
    if record:
        exu, sc, mbs, d = exudyn_system(n, reduced)
        sensor = mbs.AddSensor(SensorNode(nodeNumber=d["nodes"][-1], storeInternal=True,
                                          outputVariableType=exu.OutputVariableType.Position))
        mbs.Assemble()
        ss, st = exudyn_settings(exu, h, solver, modified, tol, linear)
        exu.SolveDynamic(mbs, ss, solverType=st)
        data = mbs.GetSensorStoredData(sensor)
        grid = np.arange(0, int(round(T_END / SAMPLE)) + 1) * SAMPLE
        traj = np.stack([np.interp(grid, data[:, 0], data[:, 1]),
                         np.interp(grid, data[:, 0], data[:, 2])], axis=1)
    return wall, traj


def exudyn_costs():
    """Exudyn's residual and Jacobian per element [us]: (t(256) - t(16)) / 240 per call."""
    out = {}
    for n in (16, 256):
        exu, sc, mbs, d = exudyn_system(n, False)
        mbs.Assemble()
        ss, _ = exudyn_settings(exu, 1e-3, "alpha", True, 1e-8, "EigenSparse")
        solver = exu.MainSolverImplicitSecondOrder()
        solver.InitializeSolver(mbs, ss)
        res, jac = [], []
        for _ in range(5):
            k = 2000 if n == 16 else 400
            t0 = time.perf_counter()
            for _ in range(k):
                solver.ComputeNewtonResidual(mbs, ss)
            res.append((time.perf_counter() - t0) / k)
            t0 = time.perf_counter()
            for _ in range(k // 4):
                solver.ComputeNewtonJacobian(mbs, ss)
            jac.append((time.perf_counter() - t0) / (k // 4))
        out[n] = (min(res), min(jac))
    per = lambda i: (out[256][i] - out[16][i]) / 240 * 1e6
    return per(0), per(1)


# ----------------------------------------------------------------------------------------------

def error(traj, ref):
    return float(np.hypot(*(traj - ref).T).max())


def machine():
    model = platform.processor() or ""
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{model}, {os.cpu_count()} cores, Linux {platform.release()}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="a small grid (smoke run)")
    ap.add_argument("--fine", action="store_true",
                    help="only the cells that decide the three finest error levels (1e-4, 3e-5, 1e-5 m): "
                         "8, 16 and 32 elements at steps 2e-3 to 2.5e-4 s; full reference; writes build/race/")
    ap.add_argument("--fresh", action="store_true", help="recompute the cached reference runs")
    args = ap.parse_args()
    subprocess.run([str(ROOT / "scripts" / "build_fmus.sh")], check=True, stdout=subprocess.DEVNULL)
    import exudyn
    DOCS.mkdir(exist_ok=True)
    print(f"# Race: flexfmu ANCF cable vs Exudyn {exudyn.__version__} ANCFCable2D, soft pendulum, 1 s")
    print(f"Machine: {machine()}; one core per run.\n")
    fx = Flexfmu()
    cache = ROOT / "build" / "race" / ("reference_quick.npz" if args.quick else "reference.npz")
    cache.parent.mkdir(parents=True, exist_ok=True)
    # reference: Richardson in space (32, 64, 128 elements at 1e-4 s) and time (128 el., 2e-4, 1e-4 s)
    fine_h = 2e-4 if args.quick else 1e-4
    ns = (16, 32, 64) if args.quick else (32, 64, 128)
    if cache.exists() and not args.fresh:
        z = np.load(cache)
        runs, coarse_t = {n: z[f"n{n}"] for n in ns}, z["coarse_t"]
        print(f"(reference runs read from {cache}; --fresh recomputes them)")
    else:
        runs = {n: fx.run(n, fine_h, 1, 1, 1e-12, reps=1)[1] for n in ns}
        coarse_t = fx.run(ns[-1], 2 * fine_h, 1, 1, 1e-12, reps=1)[1]
        np.savez(cache, coarse_t=coarse_t, **{f"n{n}": runs[n] for n in ns})
    d1, d2 = error(runs[ns[0]], runs[ns[1]]), error(runs[ns[1]], runs[ns[2]])
    p = math.log2(d1 / d2)
    f = runs[ns[2]]
    space = (f - runs[ns[1]]) / (2 ** p - 1)
    tcorr = (f - coarse_t) / 3.0
    ref = f + space + tcorr
    print(f"Reference: {ns[-1]} elements, h = {fine_h:g} s, generalized-alpha, full Newton; spatial order "
          f"estimated {p:.2f} ({ns[0]}/{ns[1]}/{ns[2]} el.: differences {d1:.2e}, {d2:.2e} m); Richardson "
          f"corrections: space {np.hypot(*space.T).max():.2e} m, time {np.hypot(*tcorr.T).max():.2e} m; "
          f"tip at 1 s = ({ref[-1][0]:.6f}, {ref[-1][1]:.6f}) m")
    _, exu_fine = exudyn_run(ns[-1], fine_h, "alpha", False, 1e-8, "EigenSparse", False, reps=1)
    print(f"Exudyn at the same mesh and step ({ns[-1]} el., {fine_h:g} s, full integration): "
          f"{error(exu_fine, f):.2e} m from flexfmu's run, {error(exu_fine, ref):.2e} m from the reference\n")

    counts = [2, 4, 8, 16] if args.quick else [2, 4, 8, 16, 32]
    steps = [2e-2, 5e-3, 1e-3] if args.quick else [2e-2, 1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2.5e-4]
    levels = LEVELS
    out_dir = DOCS
    if args.fine:
        counts, steps, levels = [8, 16, 32], [2e-3, 1e-3, 5e-4, 2.5e-4], LEVELS[-3:]
        out_dir = ROOT / "build" / "race"
        print(f"--fine: only {counts} elements x {steps} s steps, error levels {levels} m "
              f"(a subset: the table and plot in docs/ are not touched)\n")
    fx_cfgs = [(i, nw, tol) for i in (1, 2) for nw in (2, 1) for tol in (1e-10, 1e-7, 1e-5)]
    ex_cfgs = [(s, m, tol, red) for s in ("alpha", "trapezoidal") for m in (True, False)
               for tol in (1e-8, 1e-6, 1e-4) for red in (False, True)]
    rows = []
    for n in counts:
        for h in steps:
            for integ, newton, tol in fx_cfgs:
                wall, traj = fx.run(n, h, integ, newton, tol)
                rows.append(dict(program="flexfmu", n=n, h=h,
                                 setting=f"{'generalized-alpha' if integ == 1 else 'Newmark'}, "
                                         f"{'modified' if newton == 2 else 'full'} Newton, tol {tol:g}",
                                 wall=wall, error=error(traj, ref)))
            for solver, modified, tol, red in ex_cfgs:
                trajs = None
                for linear in ("EXUdense", "EigenDense", "EigenSparse"):
                    try:
                        wall, traj = exudyn_run(n, h, solver, modified, tol, linear, red, record=trajs is None)
                    except Exception as e:  # Exudyn reports failed solves as exceptions
                        print(f"  exudyn n={n} h={h:g} {solver} failed: {e}")
                        continue
                    trajs = traj if trajs is None else trajs
                    rows.append(dict(program="exudyn", n=n, h=h,
                                     setting=f"{'generalized-alpha' if solver == 'alpha' else 'trapezoidal'}, "
                                             f"{'modified' if modified else 'full'} Newton, rel. tol {tol:g}, "
                                             f"{linear}, "
                                             f"{'reduced' if red else 'full'} integration",
                                     wall=wall, error=error(trajs, ref)))
            best = {prog: min((r for r in rows if r["program"] == prog and r["n"] == n and r["h"] == h),
                              key=lambda r: r["wall"]) for prog in ("flexfmu", "exudyn")}
            print(f"  n={n:3d} h={h:7.1e}: flexfmu {best['flexfmu']['wall'] * 1e3:8.2f} ms "
                  f"(err {best['flexfmu']['error']:.1e}), exudyn {best['exudyn']['wall'] * 1e3:8.2f} ms "
                  f"(err {best['exudyn']['error']:.1e})", flush=True)
    fx.close()
    csv_path = out_dir / "race_exudyn.csv"
    with open(csv_path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)

    print("\n| tip error ≤ | flexfmu fastest | wall [ms] | Exudyn fastest | wall [ms] | Exudyn / flexfmu |")
    print("|---|---|---|---|---|---|")
    ratios = []
    for lev in levels:
        b = {}
        for prog in ("flexfmu", "exudyn"):
            ok = [r for r in rows if r["program"] == prog and r["error"] <= lev]
            b[prog] = min(ok, key=lambda r: r["wall"]) if ok else None
        cell = lambda r: f"{r['n']} el., h = {r['h']:g} s, {r['setting']}" if r else "none in the grid"
        wall = lambda r: f"{r['wall'] * 1e3:.2f}" if r else "—"
        ratio = b["exudyn"]["wall"] / b["flexfmu"]["wall"] if b["flexfmu"] and b["exudyn"] else None
        ratios.append(ratio)
        print(f"| {lev:g} m | {cell(b['flexfmu'])} | {wall(b['flexfmu'])} | {cell(b['exudyn'])} | "
              f"{wall(b['exudyn'])} | {f'{ratio:.1f}×' if ratio else '—'} |")
    met = [r for r in ratios if r]
    if met:
        print(f"\nRatio Exudyn/flexfmu at the error levels both reach: {min(met):.1f}× to {max(met):.1f}× "
              f"(target ≥ 3×: {'met' if min(met) >= 3 else 'not met'} at every level)")

    # cost per element per Newton iteration
    out = subprocess.run(["cargo", "run", "--release", "--quiet", "--example", "bench_cable"],
                         cwd=ROOT, check=True, capture_output=True, text=True).stdout
    fk = {int(m[0]): (float(m[1]), float(m[2])) for m in
          re.findall(r"^\s*(\d+)\s+\d+\s+([\d.]+)\s+([\d.]+)", out, re.M)}
    ex_res, ex_jac = exudyn_costs()
    print("\n| per element and Newton iteration | flexfmu cable [us] | Exudyn ANCFCable2D [us] |")
    print("|---|---|---|")
    print(f"| residual (internal force + mass + gravity) | {fk[256][0]:.2f} | {ex_res:.2f} |")
    print(f"| residual + iteration matrix (assembled) | {fk[256][1]:.2f} | {ex_res + ex_jac:.2f} "
          f"(Jacobian alone {ex_jac:.2f}) |")
    print("(flexfmu: 256 elements, examples/bench_cable.rs; Exudyn: (t(256 el.) - t(16 el.)) / 240 of "
          "ComputeNewtonResidual and ComputeNewtonJacobian from Python)")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def front(pts):
        pts = sorted(pts)
        out, best = [], math.inf
        for w, e in pts:
            if e < best:
                out.append((w, e))
                best = e
        return out

    fig, ax = plt.subplots(figsize=(7, 5))
    for prog, style, label in (("flexfmu", "o-", "flexfmu ANCF cable (fmpy)"),
                               ("exudyn", "s-", f"Exudyn {exudyn.__version__} ANCFCable2D")):
        pts = [(r["wall"] * 1e3, r["error"]) for r in rows if r["program"] == prog]
        ax.plot(*zip(*pts), style[0], ms=2, alpha=0.25, color="C0" if prog == "flexfmu" else "C1")
        ax.plot(*zip(*front(pts)), style, ms=4, label=label, color="C0" if prog == "flexfmu" else "C1")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time for 1 s of simulated time [ms]")
    ax.set_ylabel("largest tip error over the run [m]")
    ax.set_title("Soft pendulum, Euler-Bernoulli cable: error vs wall time")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out_dir / "race_exudyn.png", dpi=120)
    print(f"\nFiles: {csv_path}, {out_dir / 'race_exudyn.png'}")


if __name__ == "__main__":
    main()
