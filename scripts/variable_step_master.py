"""A variable-step co-simulation master with step rejection through FMU state rollback.

The flexible pendulum FMU (scenes/pendulum.toml) is stepped with one internal step per
communication step (solver.max_step set large), so the communication step size sets the
accuracy. Each step is taken twice from a saved FMU state (fmi2GetFMUstate): once with H, once
as two steps of H/2; the difference of the tip positions estimates the error. A step whose
error exceeds the tolerance is rejected: the FMU is rolled back (fmi2SetFMUstate) and retried
with a smaller step; accepted steps let H grow. The result is compared with a fixed-step run at
a step 10x smaller than the smallest one the master used.

Run: python scripts/variable_step_master.py [--tol 1e-4] [--plot out.png]
"""
import argparse
import pathlib
import shutil
import tempfile

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

ROOT = pathlib.Path(__file__).resolve().parents[1]
FMU = ROOT / "build" / "fmus" / "pendulum.fmu"


class Pendulum:
    def __init__(self, fmu=FMU, instance="pendulum"):
        md = read_model_description(str(fmu))
        self.dir = extract(str(fmu), unzipdir=tempfile.mkdtemp())
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.s = FMU2Slave(guid=md.guid, unzipDirectory=self.dir,
                           modelIdentifier=md.coSimulation.modelIdentifier, instanceName=instance)
        self.s.instantiate()
        self.s.setupExperiment(startTime=0.0)
        self.s.setReal([self.vr["solver.max_step"]], [1.0])  # one internal step per DoStep
        self.s.enterInitializationMode()
        self.s.exitInitializationMode()

    def tip(self):
        return np.array(self.s.getReal([self.vr["tip.x"], self.vr["tip.y"]]))

    def close(self):
        self.s.terminate()
        self.s.freeInstance()
        shutil.rmtree(self.dir, ignore_errors=True)


def adaptive(t_end, tol, h0=1e-2, h_min=1e-6):
    p = Pendulum()
    t, h = 0.0, h0
    times, tips, steps = [0.0], [p.tip()], []
    accepted = rejected = 0
    while t < t_end - 1e-12:
        h = min(h, t_end - t)
        state = p.s.getFMUstate()
        p.s.doStep(t, h)
        coarse = p.tip()
        p.s.setFMUstate(state)
        p.s.doStep(t, h / 2)
        p.s.doStep(t + h / 2, h / 2)
        fine = p.tip()
        err = np.abs(fine - coarse).max()
        if err > tol and h > h_min:
            rejected += 1
            p.s.setFMUstate(state)  # roll back and retry with a smaller step
            p.s.freeFMUstate(state)
            h *= max(0.2, 0.9 * (tol / err) ** (1 / 3))
            continue
        p.s.freeFMUstate(state)
        accepted += 1
        t += h
        times.append(t)
        tips.append(fine)
        steps.append(h)
        # second-order scheme: error ~ h^3 per step
        h *= min(2.0, 0.9 * (tol / max(err, 1e-300)) ** (1 / 3))
    p.close()
    return np.array(times), np.array(tips), np.array(steps), accepted, rejected


def fixed(t_end, h):
    p = Pendulum(instance="reference")
    n = int(round(t_end / h))
    for k in range(n):
        p.s.doStep(k * h, h)
    tip = p.tip()
    p.close()
    return tip


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tol", type=float, default=1e-4, help="error per step [m]")
    ap.add_argument("--t-end", type=float, default=1.0)
    ap.add_argument("--plot")
    args = ap.parse_args()
    t, tips, steps, acc, rej = adaptive(args.t_end, args.tol)
    h_ref = steps.min() / 10
    ref = fixed(args.t_end, h_ref)
    err = np.abs(tips[-1] - ref).max()
    print(f"adaptive master: {acc} steps accepted, {rej} rejected (rolled back), "
          f"step size {steps.min():.2e} .. {steps.max():.2e} s")
    print(f"tip at t = {args.t_end} s: ({tips[-1][0]:.6f}, {tips[-1][1]:.6f}) m; fixed step {h_ref:.1e} s: "
          f"({ref[0]:.6f}, {ref[1]:.6f}) m; difference {err:.2e} m")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7, 3.5))
        ax.semilogy(t[1:], steps, ".-")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("communication step [s]")
        ax.set_title(f"pendulum, tolerance {args.tol} m: {acc} accepted, {rej} rejected")
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"plot: {args.plot}")


if __name__ == "__main__":
    main()
