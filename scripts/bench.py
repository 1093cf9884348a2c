"""flexfmu speed/accuracy benchmark (release build, one core).

Measures, for the seed-000 flexible pendulum (Kerkkanen et al. 2003, Problem 4; scenes/pendulum.toml)
simulated for 1 s:
  * over element counts (2..256), integrators and internal steps (1e-5..2e-2 s): wall time per
    simulated second, Newton iterations, and the tip error against a converged reference
    (256 elements, 1e-4 s steps, energy-conserving midpoint rule); error = largest distance of
    the tip from the reference over the run, sampled every millisecond or, for longer internal
    steps, at every step (so no interpolation enters, and the sampling does not shorten steps);
  * the same pendulum in Exudyn (PyPI exudyn, fast module): its ANCFCable2D and
    ObjectBeamGeometricallyExact2D elements, generalized-alpha, dense and sparse linear solvers,
    full and modified Newton; its error against the same reference and against its own converged
    solution, its wall time; the speed ratio at equal error;
  * the cost of communication steps (fmpy FMU2Slave loop) for 1e-4..1e-2 s;
  * the Rust kernel benchmark (examples/bench_kernels.rs).
Writes build/bench/results.csv, build/bench/exudyn.csv, build/bench/pareto.png and
build/bench/report.md, and prints the tables.

Run: python scripts/bench.py [--quick]
"""
import argparse
import csv
import datetime
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
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

ROOT = pathlib.Path(__file__).resolve().parents[1]
FMU = ROOT / "build" / "fmus" / "pendulum.fmu"
OUT = ROOT / "build" / "bench"
T_END = 1.0
SAMPLE = 1e-3
INTEGRATORS = {1: "generalized-alpha (0.9)", 2: "Newmark", 3: "midpoint (energy-conserving)", 4: "central difference"}

# seed-000 pendulum data (Kerkkanen et al. 2003, Problem 4)
E, NU, RHO, L, B, H, G = 2.07e7, 0.3, 7850.0, 2.0, 0.1, 0.1, 9.81


class Pendulum:
    """The pendulum FMU in fmpy's FMU2Slave, with the solver statistics from the log."""

    def __init__(self, **params):
        md = read_model_description(str(FMU))
        self.dir = extract(str(FMU), unzipdir=tempfile.mkdtemp())
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.types = {v.name: v.type for v in md.modelVariables}
        self.s = FMU2Slave(guid=md.guid, unzipDirectory=self.dir,
                           modelIdentifier=md.coSimulation.modelIdentifier, instanceName="bench")
        self.log = []
        from ctypes import byref
        from fmpy.fmi1 import calloc, free
        from fmpy.fmi2 import (fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                               fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
        from fmpy.logging import addLoggerProxy
        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(lambda env, name, status, cat, msg: self.log.append(msg.decode()))
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        addLoggerProxy(byref(cb))
        self._cb = cb
        self.s.instantiate(callbacks=cb, loggingOn=True)
        self.s.setupExperiment(startTime=0.0)
        for k, v in params.items():
            if self.types[k] == "Integer":
                self.s.setInteger([self.vr[k]], [int(v)])
            elif self.types[k] == "Boolean":
                self.s.setBoolean([self.vr[k]], [bool(v)])
            else:
                self.s.setReal([self.vr[k]], [float(v)])
        self.s.enterInitializationMode()
        self.s.exitInitializationMode()

    def tip(self):
        return self.s.getReal([self.vr["tip.x"], self.vr["tip.y"]])

    def stats(self):
        self.s.terminate()
        for m in self.log:
            g = re.search(r"(\d+) steps, (\d+) rejected, (\d+) Newton iterations, (\d+) factorizations", m)
            if g:
                return tuple(int(x) for x in g.groups())
        return (0, 0, 0, 0)

    def close(self):
        self.s.freeInstance()
        shutil.rmtree(self.dir, ignore_errors=True)


def flexfmu_run(n, integrator, max_step, newton=2):
    params = {"mesh.n_elements": n, "solver.integrator": integrator, "solver.max_step": max_step,
              "solver.newton": newton}
    # timing: one communication step over the whole second (pure FMU work)
    p = Pendulum(**params)
    t0 = time.perf_counter()
    p.s.doStep(0.0, T_END)
    wall = time.perf_counter() - t0
    steps, rejected, iterations, factorizations = p.stats()
    p.close()
    # trajectory: the same internal steps, sampled at every internal step or millisecond (a shorter
    # communication step would shorten the internal steps)
    p = Pendulum(**params)
    comm = max(SAMPLE, max_step)
    k = int(round(T_END / comm))
    traj = np.empty((k + 1, 2))
    traj[0] = p.tip()
    for i in range(k):
        p.s.doStep(i * comm, comm)
        traj[i + 1] = p.tip()
    p.close()
    return dict(wall=wall, steps=steps, rejected=rejected, iterations=iterations,
                factorizations=factorizations, traj=traj)


def error(traj, ref):
    """Largest tip distance [m] at the sample times of `traj` (every internal step or
    millisecond; `ref` is sampled every millisecond)."""
    stride = (len(ref) - 1) // (len(traj) - 1)
    return float(np.hypot(*(traj - ref[::stride]).T).max())


# ----------------------------------------------------------------------------------------------
# Exudyn
# ----------------------------------------------------------------------------------------------

def exudyn_run(kind, n, dt, sparse, modified, record=True, rho_inf=0.9):
    sys.exudynFast = True
    import exudyn as exu
    from exudyn.beams import GenerateBeamElementsAlongLine
    from exudyn.itemInterface import ObjectANCFCable2D, ObjectBeamGeometricallyExact2D, SensorNode

    A, I = B * H, B * H ** 3 / 12
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    if kind == "ANCFCable2D":
        tmpl = ObjectANCFCable2D(physicsMassPerLength=RHO * A, physicsBendingStiffness=E * I, physicsAxialStiffness=E * A)
        ground = [1, 1, 0, 0]
    else:
        tmpl = ObjectBeamGeometricallyExact2D(
            physicsMassPerLength=RHO * A, physicsCrossSectionInertia=RHO * I, physicsBendingStiffness=E * I,
            physicsAxialStiffness=E * A, physicsShearStiffness=5 / 6 * E / (2 * (1 + NU)) * A)
        ground = [1, 1, 0]
    d = GenerateBeamElementsAlongLine(mbs, [0, 0, 0], [L, 0, 0], n, tmpl, gravity=[0, -G, 0],
                                      groundConstraintsStart=ground)
    sensor = None
    if record:
        sensor = mbs.AddSensor(SensorNode(nodeNumber=d["nodes"][-1], storeInternal=True,
                                          outputVariableType=exu.OutputVariableType.Position))
    mbs.Assemble()
    ss = exu.SimulationSettings()
    ss.timeIntegration.numberOfSteps = int(round(T_END / dt))
    ss.timeIntegration.endTime = T_END
    ss.timeIntegration.verboseMode = 0
    ss.timeIntegration.generalizedAlpha.spectralRadius = rho_inf
    ss.timeIntegration.newton.useModifiedNewton = modified
    ss.solutionSettings.writeSolutionToFile = False
    ss.solutionSettings.sensorsWritePeriod = SAMPLE
    ss.linearSolver.solverType = exu.LinearSolverType.EigenSparse if sparse else exu.LinearSolverType.EXUdense
    t0 = time.perf_counter()
    exu.SolveDynamic(mbs, ss)
    wall = time.perf_counter() - t0
    traj = None
    if record:
        data = mbs.GetSensorStoredData(sensor)
        t = data[:, 0]
        period = max(SAMPLE, dt)  # at the step times: no interpolation error in the comparison
        grid = np.arange(0, int(round(T_END / period)) + 1) * period
        traj = np.stack([np.interp(grid, t, data[:, 1]), np.interp(grid, t, data[:, 2])], axis=1)
    return wall, traj


def best_under(rows, key_err, threshold):
    ok = [r for r in rows if r[key_err] <= threshold]
    return min(ok, key=lambda r: r["wall"]) if ok else None


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
    ap.add_argument("--quick", action="store_true", help="a smaller grid (for a smoke run)")
    args = ap.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    lines = []

    def say(s=""):
        print(s, flush=True)
        lines.append(s)

    say(f"# flexfmu benchmark — {datetime.date.today().isoformat()}")
    say(f"Machine: {machine()}; one core per run (the FMU is sequential).")

    ref_run = flexfmu_run(256, 3, 1e-4)
    ref = ref_run["traj"]
    say(f"\nReference: 256 elements, 1e-4 s, midpoint rule; tip at 1 s = ({ref[-1][0]:.6f}, {ref[-1][1]:.6f}) m")

    counts = [2, 8, 32, 128] if args.quick else [2, 4, 8, 16, 32, 64, 128, 256]
    steps = [1e-3, 1e-2] if args.quick else [1e-5, 1e-4, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2]
    rows = []
    for integrator in (1, 2, 3, 4):
        for n in counts:
            for h in steps:
                if integrator == 4 and h != 1e-2:
                    continue  # the explicit scheme chooses its own (stability-limited) step
                if h == 1e-5 and n > 32:
                    continue  # 1e5 steps of large meshes: minutes for nothing new
                r = flexfmu_run(n, integrator, h)
                err = error(r["traj"], ref)
                rows.append(dict(program="flexfmu", element="seed-000", integrator=INTEGRATORS[integrator],
                                 n=n, h=h, wall=r["wall"], steps=r["steps"], iterations=r["iterations"],
                                 factorizations=r["factorizations"], error=err))
                print(f"  flexfmu {INTEGRATORS[integrator]:30s} n={n:4d} h={h:.0e}: {r['wall'] * 1e3:9.2f} ms  "
                      f"error {err:.2e} m  ({r['steps']} steps, {r['iterations']} Newton it.)", flush=True)
    with open(OUT / "results.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)

    # Exudyn
    exu_rows = []
    exu_ref = {}
    for kind in ("ANCFCable2D", "BeamGeometricallyExact2D"):
        _, exu_ref[kind] = exudyn_run(kind, 128, 1e-4, sparse=True, modified=False)
        for n in ([4, 16, 64] if args.quick else [2, 4, 8, 16, 32, 64]):
            for dt in ([1e-3] if args.quick else [1e-4, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2]):
                for sparse in (True, False):
                    for modified in (False, True):
                        try:
                            wall, _ = exudyn_run(kind, n, dt, sparse, modified, record=False)
                            _, traj = exudyn_run(kind, n, dt, sparse, modified, record=True)
                            err = error(traj, ref)
                            self_err = error(traj, exu_ref[kind])
                        except Exception as e:  # Exudyn reports failed solves as exceptions
                            print(f"  exudyn {kind} n={n} dt={dt}: failed ({e})")
                            continue
                        exu_rows.append(dict(program="exudyn", element=kind, n=n, h=dt,
                                             solver=("EigenSparse" if sparse else "EXUdense"),
                                             newton=("modified" if modified else "full"),
                                             wall=wall, error=err, self_error=self_err))
                        print(f"  exudyn {kind:25s} n={n:3d} dt={dt:.0e} {'sparse' if sparse else 'dense '} "
                              f"{'modified' if modified else 'full    '}: {wall * 1e3:9.2f} ms  error {err:.2e} m  "
                              f"(own converged solution: {self_err:.2e} m)", flush=True)
    with open(OUT / "exudyn.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(exu_rows[0].keys()))
        w.writeheader()
        w.writerows(exu_rows)
    floors = {k: error(v, ref) for k, v in exu_ref.items()}

    # flexfmu's own self-convergence is the error against the reference (same model)
    for r in rows:
        r["self_error"] = r["error"]

    say("\n## Speed/accuracy: fastest configuration under each error level (1 s of the pendulum)")
    say("Error: largest tip distance from the reference over the run [m]. Exudyn's elements converge to")
    say("a slightly different solution than the seed-000 continuum element (Euler-Bernoulli cable; Reissner")
    say("beam with Biot strain instead of Green-Lagrange strain): converged, they stay "
        + ", ".join(f"{k} {v * 1e3:.2f} mm" for k, v in floors.items())
        + " from the seed-000 reference. So the comparison is made twice: against the seed-000 reference,")
    say("and with each program against its own converged solution (how fast each reaches a given accuracy).")
    say("")
    say("| error level | flexfmu fastest | wall [ms] | Exudyn fastest (vs seed-000 ref.) | wall [ms] | ratio | Exudyn fastest (vs own converged) | wall [ms] | ratio |")
    say("|---|---|---|---|---|---|---|---|---|")
    for level in (3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4):
        f = best_under(rows, "error", level)
        e1 = best_under(exu_rows, "error", level)
        e2 = best_under(exu_rows, "self_error", level)

        def desc(r):
            if r is None:
                return "none reaches it", "—"
            if r["program"] == "flexfmu":
                return f"{r['integrator']}, {r['n']} el., h={r['h']:.0e}", f"{r['wall'] * 1e3:.1f}"
            return f"{r['element']}, {r['n']} el., h={r['h']:.0e}, {r['solver']}, {r['newton']}", f"{r['wall'] * 1e3:.1f}"

        fd, fw = desc(f)
        d1, w1 = desc(e1)
        d2, w2 = desc(e2)
        r1 = f"{e1['wall'] / f['wall']:.1f}x" if (f and e1) else "—"
        r2 = f"{e2['wall'] / f['wall']:.1f}x" if (f and e2) else "—"
        say(f"| {level:.0e} m | {fd} | {fw} | {d1} | {w1} | {r1} | {d2} | {w2} | {r2} |")

    # cost at equal mesh and step (the same work on both sides: elements x steps)
    say("\n## Cost at equal mesh and step (1 s of the pendulum; Exudyn: its fastest solver setting)")
    say("| elements | step [s] | flexfmu generalized-alpha [ms] | Exudyn ANCFCable2D [ms] | ratio | Exudyn BeamGeometricallyExact2D [ms] | ratio |")
    say("|---|---|---|---|---|---|---|")
    for n in (16, 64):
        for h in (1e-3, 1e-2):
            f = next((r for r in rows if r["n"] == n and r["h"] == h and r["integrator"] == INTEGRATORS[1]), None)
            cells = []
            for kind in ("ANCFCable2D", "BeamGeometricallyExact2D"):
                ex = [r for r in exu_rows if r["element"] == kind and r["n"] == n and r["h"] == h]
                e = min(ex, key=lambda r: r["wall"]) if ex else None
                cells += [f"{e['wall'] * 1e3:.1f}", f"{e['wall'] / f['wall']:.1f}x"] if (e and f) else ["—", "—"]
            if f:
                say(f"| {n} | {h:.0e} | {f['wall'] * 1e3:.1f} | " + " | ".join(cells) + " |")

    # communication-step cost (fmpy loop, Python included)
    say("\n## Communication steps (fmpy FMU2Slave loop from Python, 16 elements, generalized-alpha, h = 1 ms)")
    say("| communication step [s] | wall per simulated second [ms] | of which FMU work [ms] |")
    say("|---|---|---|")
    base = flexfmu_run(16, 1, 1e-3)["wall"]
    for comm in (1e-4, 1e-3, 1e-2):
        p = Pendulum(**{"mesh.n_elements": 16, "solver.integrator": 1, "solver.max_step": min(1e-3, comm)})
        k = int(round(T_END / comm))
        t0 = time.perf_counter()
        for i in range(k):
            p.s.doStep(i * comm, comm)
            p.tip()
        wall = time.perf_counter() - t0
        p.close()
        work = base if comm >= 1e-3 else flexfmu_run(16, 1, comm)["wall"]
        say(f"| {comm:.0e} | {wall * 1e3:.1f} | {work * 1e3:.1f} |")

    # kernels
    say("\n## Kernels (examples/bench_kernels.rs)")
    subprocess.run(["cargo", "build", "--release", "--quiet", "--example", "bench_kernels"], cwd=ROOT, check=True)
    k = subprocess.run([str(ROOT / "target" / "release" / "examples" / "bench_kernels"), "--csv", str(OUT / "kernels.csv")],
                       cwd=ROOT, capture_output=True, text=True, check=True)
    say("```")
    for line in k.stdout.splitlines():
        if not line.startswith("csv:"):
            say(line)
    say("```")

    # Pareto plot
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

    fig, ax = plt.subplots(figsize=(8, 5.5))
    for name in INTEGRATORS.values():
        # (the reference configuration itself has error 0 and no place on a log axis)
        pts = [(r["wall"], r["error"]) for r in rows if r["integrator"] == name and r["error"] > 0]
        if pts:
            ax.scatter(*zip(*pts), s=10, alpha=0.35)
            fr = front(pts)
            ax.plot(*zip(*fr), "-o", ms=3, label=f"flexfmu, {name}")
    for kind, style in (("ANCFCable2D", "k--s"), ("BeamGeometricallyExact2D", "k:^")):
        pts = [(r["wall"], r["error"]) for r in exu_rows if r["element"] == kind]
        if pts:
            ax.plot(*zip(*front(pts)), style, ms=4, label=f"Exudyn {kind} (vs seed-000 reference)")
        pts = [(r["wall"], r["self_error"]) for r in exu_rows if r["element"] == kind]
        if pts:
            ax.plot(*zip(*front(pts)), style, ms=4, alpha=0.4, label=f"Exudyn {kind} (vs own converged)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.axhline(1e-3, color="grey", lw=0.8)
    ax.set_xlabel("wall time for 1 s of simulation [s]")
    ax.set_ylabel("max tip error over 1 s [m]")
    ax.set_title("Seed-000 flexible pendulum: error vs wall time (Pareto fronts)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(OUT / "pareto.png", dpi=120)
    say(f"\nFiles: {OUT / 'results.csv'}, {OUT / 'exudyn.csv'}, {OUT / 'kernels.csv'}, {OUT / 'pareto.png'}")
    (OUT / "report.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
