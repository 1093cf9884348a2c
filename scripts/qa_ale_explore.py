"""QA of belt.formulation = 2 (session 36, qa36): the case table, ALE against Lagrangian on
belt_drive.fmu (build/fmus, scripts/build_fmus.sh). Usage: .venv/bin/python scripts/qa_ale_explore.py
[case ...]; per case the means of T1, T2, omega2, pulley 1's torque over the last 0.2 s of the
60 rad/s protocol of tests/belt_ale.rs (ramps over 0.3 s, 0.6 s run)."""
import sys
import time

sys.path.insert(0, "pytests")
import numpy as np
from fmpy.fmi1 import FMICallException

from helpers import Session

FMU = "build/fmus/belt_drive.fmu"
OUT = ["belt.tension_tight", "belt.tension_slack", "pulley2.omega", "pulley1.torque"]


def run(fmu, sv, omega=60.0, load=10.0, h=1e-3, t_end=0.6, ramp_t=0.3, load_step=None):
    s = Session(fmu, logging_on=True)
    sl = s.slave
    t0 = time.time()
    try:
        sl.setupExperiment(startTime=0.0)
        sl.enterInitializationMode()
        for k, v in sv.items():
            if isinstance(v, bool):
                sl.setBoolean([s.vr[k]], [v])
            elif isinstance(v, int):
                sl.setInteger([s.vr[k]], [v])
            else:
                sl.setReal([s.vr[k]], [float(v)])
        sl.exitInitializationMode()
        n = int(round(t_end / h))
        angle, acc, k = 0.0, np.zeros(len(OUT)), 0
        ramp = lambda t: min(t / ramp_t, 1.0)
        for i in range(n):
            t = i * h
            w = 0.5 * omega * (ramp(t) + ramp(t + h))
            tl = -load * ramp(t) if load_step is None else (-load if t >= load_step else 0.0)
            sl.setReal([s.vr["pulley1.angle"], s.vr["pulley1.omega"], s.vr["pulley2.torque_in"]], [angle, w, tl])
            sl.doStep(t, h)
            angle += w * h
            o = np.array(sl.getReal([s.vr[x] for x in OUT]))
            if not np.all(np.isfinite(o)):
                return "nonfinite", o, time.time() - t0, s.errors()
            if t + h > t_end - 0.2 + 1e-9:
                acc += o
                k += 1
        return "ok", acc / k, time.time() - t0, []
    except FMICallException as e:
        return f"status {e.status} at t={t if 'i' in dir() else 'init'}", None, time.time() - t0, s.errors()[-2:]
    except Exception as e:
        return f"exc {e}", None, time.time() - t0, s.errors()[-2:]
    finally:
        s.close()


CASES = {
    "base 100 el.": dict(sv={}),
    "16 el.": dict(sv={"belt.n_elements": 16}),
    "60 el.": dict(sv={"belt.n_elements": 60}),
    "200 el.": dict(sv={"belt.n_elements": 200}),
    "soft belt": dict(sv={"belt.EA": 8000.0, "belt.pretension": 400.0, "contact.mu": 0.5, "belt.n_elements": 120}, load=20.0),
    "radii 0.1/0.05": dict(sv={"pulley1.radius": 0.1, "pulley2.radius": 0.05}),
    "radii 0.1/0.15": dict(sv={"pulley1.radius": 0.1, "pulley2.radius": 0.15}),
    "h 0.5 ms": dict(sv={}, h=5e-4),
    "h 2 ms": dict(sv={}, h=2e-3),
    "pulley1 at rest": dict(sv={}, omega=0.0, load=0.0),
    "reversed -60": dict(sv={}, omega=-60.0, load=-10.0),
    "load step 10 at 0.4": dict(sv={}, load_step=0.4),
    "integration reduced": dict(sv={"belt.integration": 2}),
    "integration mixed": dict(sv={"belt.integration": 3}),
    "full Newton": dict(sv={"solver.newton": 1}),
    "sparse LU": dict(sv={"solver.linear_solver": 2}),
    "newmark": dict(sv={"solver.integrator": 2}),
    "no static eq.": dict(sv={"solver.static_equilibrium": False}),
    "centre 0.3": dict(sv={"pulleys.center_distance": 0.3}),
    "1 cp/element": dict(sv={"contact.points_per_element": 1}),
    "omega 200": dict(sv={}, omega=200.0),
    "mu 0.1 slipping": dict(sv={"contact.mu": 0.1}, load=10.0),
    # finding (qa36): the ALE spans' mean tension grows with the internal step
    "max_step 5 ms": dict(sv={"solver.max_step": 5e-3}, h=5e-3),
    "max_step 10 ms": dict(sv={"solver.max_step": 1e-2}, h=1e-2),
}

if __name__ == "__main__":
    sel = sys.argv[1:] or list(CASES)
    for name in sel:
        c = dict(CASES[name])
        sv = c.pop("sv")
        r = {}
        for form in (1, 2):
            r[form] = run(FMU, {**sv, "belt.formulation": form}, **c)
        (sa, oa, ta, ea), (sl_, ol, tl, el) = r[2], r[1]
        line = f"{name:22s} ALE {sa} ({ta:.1f}s) LAG {sl_} ({tl:.1f}s)"
        if oa is not None and ol is not None:
            rel = oa[:3] / ol[:3] - 1
            line += f" | ALE T1 {oa[0]:.2f} T2 {oa[1]:.2f} w2 {oa[2]:.4f} | LAG T1 {ol[0]:.2f} T2 {ol[1]:.2f} w2 {ol[2]:.4f} | rel % {np.round(100*rel, 3)}"
        else:
            line += f" | ALE {oa} {ea} | LAG {ol} {el}"
        print(line, flush=True)
