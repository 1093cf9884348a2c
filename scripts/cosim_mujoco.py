"""Co-simulation of the belt-drive FMU with a MuJoCo rigid-body model of the two pulleys.

MuJoCo owns the pulleys: two bodies on hinge joints (z axis) with their moments of inertia, a
motor (torque actuator) on the driver, a load torque and viscous damping on the driven pulley.
The FMU (scenes/belt_drive_cosim.toml, both pulleys driven) owns the belt. At every
communication step h the master

1. sends MuJoCo's pulley angles and speeds to the FMU (pulleyN.angle, pulleyN.omega),
2. advances the FMU by h (fmi2DoStep; inside, the angles are extrapolated with the speeds),
3. applies the belt torques (pulleyN.torque) to the hinges and advances MuJoCo by h.

This is an explicit (Gauss-Seidel, FMU first) exchange. The reference is the same drive with the
pulley inertias inside the FMU (scenes/belt_drive_inertia.toml, both pulleys free): same motor
torque, load torque and damping, no exchange of motion.

Stability of the explicit exchange: the belt couples a pulley angle to its torque with the
stiffness k = dtau/dtheta of the belt wrapped on it (both spans plus the stick zone of the
contact), k ~ 2 EA rho^2 / L_span. Held over a step, this torque acts like an explicit spring on
MuJoCo's pulley inertia J, which is stable only for h < 2/omega_c, omega_c = sqrt(k/J) (the
central-difference limit). `--sweep` measures where the exchange diverges.

Usage:
    python scripts/cosim_mujoco.py            # compare MuJoCo co-simulation and FMU-internal pulleys
    python scripts/cosim_mujoco.py --sweep    # stability limit of the explicit exchange
"""
import argparse
import pathlib
import shutil
import sys
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
FMUS = ROOT / "build" / "fmus"

# The drive (must match scenes/belt_drive_inertia.toml).
J1, J2 = 0.005, 0.01  # kg m2
DAMPING2 = 0.2  # N m s/rad
MOTOR = 3.0  # N m on pulley 1
LOAD = 2.0  # N m against the rotation of pulley 2
RAMP = 0.1  # s: torques ramp up linearly


def ramp(t):
    return min(t / RAMP, 1.0)


class Fmu:
    """A thin FMU2Slave session with name-based access."""

    def __init__(self, path, start_values=None, name="belt"):
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave

        self.md = read_model_description(str(path))
        self.dir = extract(str(path), unzipdir=tempfile.mkdtemp())
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        types = {v.name: v.type for v in self.md.modelVariables}
        self.slave = FMU2Slave(guid=self.md.guid, unzipDirectory=self.dir,
                               modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName=name)
        self.slave.instantiate()
        self.slave.setupExperiment(startTime=0.0)
        self.slave.enterInitializationMode()
        for k, v in (start_values or {}).items():
            if types[k] == "Integer":
                self.slave.setInteger([self.vr[k]], [int(v)])
            elif types[k] == "Boolean":
                self.slave.setBoolean([self.vr[k]], [bool(v)])
            else:
                self.slave.setReal([self.vr[k]], [float(v)])
        self.slave.exitInitializationMode()

    def set(self, **values):
        names = [k.replace("__", ".") for k in values]
        self.slave.setReal([self.vr[n] for n in names], list(values.values()))

    def get(self, *names):
        return self.slave.getReal([self.vr[n] for n in names])

    def step(self, t, h):
        """fmi2DoStep; False when the FMU did not complete the step (fmpy raises on a status
        other than fmi2OK)."""
        try:
            self.slave.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        except Exception:
            return False
        return True

    def close(self):
        try:
            self.slave.terminate()
            self.slave.freeInstance()
        finally:
            shutil.rmtree(self.dir, ignore_errors=True)


def mujoco_pulleys(h):
    """MuJoCo model: two pulleys on hinges, motor on the driver, damping on the driven."""
    import mujoco

    xml = f"""
<mujoco>
  <option timestep="{h}" gravity="0 0 0" integrator="Euler"/>
  <worldbody>
    <body name="pulley1" pos="0 0 0">
      <joint name="j1" type="hinge" axis="0 0 1"/>
      <inertial pos="0 0 0" mass="1" diaginertia="{J1} {J1} {J1}"/>
    </body>
    <body name="pulley2" pos="0.5 0 0">
      <joint name="j2" type="hinge" axis="0 0 1" damping="{DAMPING2}"/>
      <inertial pos="0 0 0" mass="1" diaginertia="{J2} {J2} {J2}"/>
    </body>
  </worldbody>
  <actuator>
    <motor name="motor" joint="j1" gear="1"/>
  </actuator>
</mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    return model, mujoco.MjData(model)


def run_mujoco(t_end, h, start_values=None, diverge=1e3):
    """The explicit co-simulation. Returns time series (t, w1, w2, tau1, tau2) and whether it
    stayed bounded."""
    import mujoco

    model, data = mujoco_pulleys(h)
    fmu = Fmu(FMUS / "belt_drive_cosim.fmu", start_values)
    out = []
    ok = True
    try:
        tau1, tau2 = fmu.get("pulley1.torque", "pulley2.torque")
        n = int(round(t_end / h))
        for i in range(n):
            t = i * h
            fmu.set(pulley1__angle=data.qpos[0], pulley1__omega=data.qvel[0],
                    pulley2__angle=data.qpos[1], pulley2__omega=data.qvel[1])
            if not fmu.step(t, h):
                ok = False
                break
            tau1, tau2 = fmu.get("pulley1.torque", "pulley2.torque")
            data.ctrl[0] = MOTOR * ramp(t)
            data.qfrc_applied[0] = tau1
            data.qfrc_applied[1] = tau2 - LOAD * ramp(t)
            mujoco.mj_step(model, data)
            out.append((t + h, data.qvel[0], data.qvel[1], tau1, tau2))
            if not np.all(np.isfinite(data.qvel)) or np.abs(data.qvel).max() > diverge:
                ok = False
                break
    finally:
        fmu.close()
    return np.array(out), ok


def run_internal(t_end, h, start_values=None):
    """The reference: pulley inertias inside the FMU, torques as inputs."""
    fmu = Fmu(FMUS / "belt_drive_inertia.fmu", start_values)
    out = []
    try:
        n = int(round(t_end / h))
        for i in range(n):
            t = i * h
            fmu.set(pulley1__torque_in=MOTOR * ramp(t), pulley2__torque_in=-LOAD * ramp(t))
            if not fmu.step(t, h):
                raise RuntimeError(f"FMU step failed at t = {t}")
            w1, w2, tau1, tau2 = fmu.get("pulley1.omega", "pulley2.omega", "pulley1.torque", "pulley2.torque")
            out.append((t + h, w1, w2, tau1, tau2))
    finally:
        fmu.close()
    return np.array(out)


def steady(series, t_from):
    """Mean of (w1, w2, tau1, tau2) over t >= t_from."""
    sel = series[:, 0] >= t_from
    return series[sel, 1:].mean(axis=0)


def compare(t_end=0.8, h=1e-3, start_values=None, plot=None):
    """Both runs; returns (mujoco steady, internal steady, relative differences)."""
    cos, ok = run_mujoco(t_end, h, start_values)
    if not ok:
        raise RuntimeError("the explicit co-simulation diverged")
    ref = run_internal(t_end, h, start_values)
    a, b = steady(cos, t_end - 0.2), steady(ref, t_end - 0.2)
    rel = np.abs(a - b) / np.abs(b)
    if plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
        for s, lab, ls in ((cos, "MuJoCo + belt FMU", "-"), (ref, "inertias in the FMU", "--")):
            ax1.plot(s[:, 0], s[:, 1], ls, label=f"pulley 1, {lab}")
            ax1.plot(s[:, 0], s[:, 2], ls, label=f"pulley 2, {lab}")
            ax2.plot(s[:, 0], s[:, 3], ls, label=f"pulley 1, {lab}")
            ax2.plot(s[:, 0], s[:, 4], ls, label=f"pulley 2, {lab}")
        ax1.set_xlabel("time [s]"); ax1.set_ylabel("omega [rad/s]"); ax1.legend(fontsize=7)
        ax2.set_xlabel("time [s]"); ax2.set_ylabel("belt torque on pulley [N m]"); ax2.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(plot, dpi=110)
    return a, b, rel


def coupling_frequencies(ea=5e4, rho=(0.082, 0.122), center=0.5, inertia=(J1, J2)):
    """omega_c = sqrt(k/J) per pulley with k = 2 EA rho^2 / L_span (both spans stretched by a
    pulley rotation), L_span = sqrt(C^2 - (rho2 - rho1)^2): the frequency the explicit exchange
    must resolve."""
    span = np.sqrt(center ** 2 - (rho[1] - rho[0]) ** 2)
    return [np.sqrt(2 * ea * r * r / span / j) for r, j in zip(rho, inertia)]


def sweep(t_end=0.4, start_values=None, steps=(1e-3, 1.5e-3, 2e-3, 3e-3, 4e-3)):
    """Explicit exchange at growing communication steps against a run at 0.25 ms: stable when
    the pulley speeds stay within 5 % of the reference (a diverging exchange does not blow up
    to infinity here: belt slip caps the torque, so it shows as a large, growing oscillation)."""
    ref, ok = run_mujoco(t_end, 2.5e-4, start_values)
    assert ok, "reference run diverged"
    scale = np.abs(ref[:, 1:3]).max()
    rows = []
    for h in steps:
        try:
            s, ok = run_mujoco(t_end, h, start_values, diverge=1e4)
        except Exception as e:
            ok, s = False, np.zeros((0, 5))
            print(f"  h = {h:g}: {e}")
        if ok and len(s):
            dev = max(np.abs(s[:, k] - np.interp(s[:, 0], ref[:, 0], ref[:, k])).max() for k in (1, 2)) / scale
        else:
            dev = float("inf")
        stable = dev < 0.05
        rows.append((h, stable, dev))
        print(f"  h = {h * 1e3:4.1f} ms: {'stable  ' if stable else 'UNSTABLE'} (largest speed deviation from the 0.25 ms run: {100 * dev:.1f} %)")
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sweep", action="store_true", help="stability limit of the explicit exchange")
    ap.add_argument("--t-end", type=float, default=0.8)
    args = ap.parse_args()
    if args.sweep:
        wc = coupling_frequencies()
        print("Explicit exchange, MuJoCo pulleys + belt FMU (EA = 5e4 N): omega_c = sqrt(k/J) = "
              + ", ".join(f"{w:.0f}" for w in wc) + " rad/s, 1/omega_c = "
              + ", ".join(f"{1e3 / w:.2f}" for w in wc) + " ms")
        sweep()
        return
    out = ROOT / "build" / "demo"
    out.mkdir(parents=True, exist_ok=True)
    a, b, rel = compare(args.t_end, 1e-3, plot=out / "cosim_mujoco.png")
    names = ("omega1 [rad/s]", "omega2 [rad/s]", "torque1 [N m]", "torque2 [N m]")
    print(f"{'steady (last 0.2 s)':22s} {'MuJoCo+FMU':>12s} {'FMU inertias':>12s} {'rel. diff':>10s}")
    for n, x, y, r in zip(names, a, b, rel):
        print(f"{n:22s} {x:12.5f} {y:12.5f} {100 * r:9.3f} %")
    print(f"plot: {out / 'cosim_mujoco.png'}")
    return 0 if (rel < 0.01).all() else 1


if __name__ == "__main__":
    sys.exit(main())
