"""Belt-drive benchmark (issue 12 item 2): real-time factor (simulated time / wall time, one
core, release build) of the belt-drive FMUs through fmpy over element counts, and of Exudyn's own
belt-drive test model measured in the same run, with a plot.

Cases (FMUs stepped with fmpy's FMU2Slave, inputs set and outputs read every 1 ms communication
step, as a master does):
  * belt_drive: scenes/belt_drive.toml, pulley 1 driven (ramp to 60 rad/s in 0.3 s), pulley 2
    free with a load torque ramped to 4 N m, over --elements (default 16 ... 400);
  * soft: the same drive with the soft belt of issue 12 (EA 8000 N, pre-tension 400 N, mu 0.5)
    at --soft-elements (default 120);
  * serpentine: scenes/serpentine.toml at 120 elements, crank from rest to 800 rpm in 0.1 s, held
    until 0.2 s, ramped to 3000 rpm until 0.2 + 0.6 t_end, A/C compressor's 5 N m engaged over
    50 ms at 0.4 t_end (the protocol of examples/bench_belt_predictor.rs), --serpentine-t-end.

Exudyn's test model (`main/pythonDev/TestModels/ANCFbeltDrive.py` of github:jgerstmayr/EXUDYN,
Exudyn 1.13.6 from PyPI, fast module): rebuilt here from that file's parameters with Exudyn's API
(no code copied): two wheels of 0.5 m 2 m apart and a measuring roll, a closed belt of 4 x 32 =
128 ANCFCable2D elements (E 1e10 Pa, 2 x 2 mm, 1000 kg/m3, pre-strain -0.002, axial damping),
GeneralContact (contact stiffness 1e5, damping 1e2, mu 0.5, 8 segments per cable, search tree
16 x 8 x 1), wheel 0 speed-driven by min(0.5 t, 10) rad/s, wheel 1 on a damper of 1 N m s,
gravity; its default settings: generalized-alpha, modified Newton, EigenSparse, h = 0.5 ms,
except numberOfThreads = 1 (one core, as the FMUs; the file asks for 6) and no solution file;
its own end time of 10 s (the wall time per simulated second falls from about 30 s over the
first 0.2 s, while the belt settles on the wheels, to 9-13 s over 2-10 s).
Its wall time per simulated second is the peer figure of issue 12 ("at most 1/10 of Exudyn's
wall time per simulated second"): the table gives each case's wall time per simulated second
divided by Exudyn's, from the same run. The ratio is the result; absolute times vary with the
machine and its load.

Iterations and factorizations per step are not visible through FMI: the in-process benchmark
`cargo run --release --example bench_belt_predictor` counts them.

An older Exudyn model of the flexfmu drive's layout (ANCFCable2D with
ObjectContactFrictionCircleCable2D) runs with --exudyn-layout. Until session 26 its driver was
held at rest (a velocity-level CoordinateConstraint takes `offsetUserFunction_t`, not
`offsetUserFunction`, which it ignores); now pulley 2 follows (40.25 rad/s at 0.4 s, 50 elements,
driver at 60 rad/s). The like-for-like comparison of the two models is
scripts/validate_belt_exudyn.py.

The 3D belt of the same drive (`belt_drive_3d`, co-rotational elements, contact across the
width) runs the same protocol at --elements-3d (issue 13 item 5: real time at 120 elements).
The drive and the soft belt as axially moving (ALE) belts (`belt.formulation` = 2: the mesh
fixed to the loop's shape, the material flowing through it) run it at --ale-elements, the serpentine
as an ALE belt at --serpentine-ale-elements (alternated with the Lagrangian serpentine of the same
count, --serpentine-repeat times). With --input-derivatives the master also gives the driver speed's
slope at every communication step (fmi2SetRealInputDerivatives, as a master that uses the FMUs'
canInterpolateInputs does); the angle and speed then follow the master's ramp inside each step.

Usage: python scripts/bench_belt.py [--elements 16 25 50 100 120 200 400] [--t-end 1.0]
       [--soft-elements 120] [--ale-elements 60 120 240] [--elements-3d 60 120 240] [--serpentine-t-end 0.5]
       [--serpentine-ale-elements 60 120] [--serpentine-repeat 3]
       [--exudyn-t-end 10] [--no-exudyn] [--input-derivatives]
       [--exudyn-layout]
Writes build/bench/belt.csv and build/bench/belt.png.
"""
import argparse
import csv
import pathlib
import sys
import time
import warnings

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
from cosim_mujoco import Fmu  # noqa: E402

# the drive of scenes/belt_drive.toml
R1, R2, CENTER = 0.08, 0.12, 0.5
EA, EI, MASS, THICK, T0, MU = 5.0e4, 0.05, 0.15, 0.004, 300.0, 0.4
J2, C2 = 0.01, 0.2
W_MAX, T_RAMP, LOAD = 60.0, 0.3, 4.0


def drive(t):
    """Driver speed [rad/s] and angle [rad] at time t (linear ramp, then constant)."""
    if t < T_RAMP:
        return W_MAX * t / T_RAMP, 0.5 * W_MAX * t * t / T_RAMP
    return W_MAX, 0.5 * W_MAX * T_RAMP + W_MAX * (t - T_RAMP)


SOFT = {"belt.EA": 8000.0, "belt.pretension": 400.0, "contact.mu": 0.5}
# the axially moving (ALE) formulation of the same drive (`belt.formulation` = 2, "ale")
ALE = {"belt.formulation": 2}
# `--input-derivatives`: give the driver speed's slope over every communication step with
# fmi2SetRealInputDerivatives, as a master with canInterpolateInputs does (fmpy's
# `simulate_fmu(..., set_input_derivatives=True)`); without it the FMU extrapolates the angle
# with the constant speed and the master's next angle lands off that line by alpha h^2 / 2
INPUT_DERIVATIVES = False


def set_speed_slope(fmu, name, w0, w1, h):
    """The speed input's derivative over the coming step (only with --input-derivatives)."""
    if INPUT_DERIVATIVES:
        fmu.slave.setRealInputDerivatives([fmu.vr[name]], [1], [(w1 - w0) / h])


def run_flexfmu(n_el, t_end, h=1e-3, case="belt_drive"):
    """The shipped drive (case `belt_drive`), the soft belt (`soft`), either as an ALE belt
    (`belt_drive ALE`, `soft ALE`) or the 3D belt of the same drive (`belt_drive_3d`, issue 13
    item 5) over the drive's protocol."""
    start = time.perf_counter()
    params = {"belt.n_elements": n_el, **(SOFT if case.startswith("soft") else {}),
              **(ALE if case.endswith(" ALE") else {})}
    scene = "belt_drive_3d" if case == "belt_drive_3d" else "belt_drive"
    fmu = Fmu(ROOT / "build" / "fmus" / f"{scene}.fmu", params)
    init = time.perf_counter() - start
    try:
        t0 = time.perf_counter()
        n = int(round(t_end / h))
        for i in range(n):
            t = i * h
            w, a = drive(t)
            fmu.set(pulley1__angle=a, pulley1__omega=w, pulley2__torque_in=-LOAD * min(t / T_RAMP, 1.0))
            set_speed_slope(fmu, "pulley1.omega", w, drive(t + h)[0], h)
            if not fmu.step(t, h):
                raise RuntimeError(f"FMU step failed at t = {t}")
            w2, tight, slack = fmu.get("pulley2.omega", "belt.tension_tight", "belt.tension_slack")
        wall = time.perf_counter() - t0
    finally:
        fmu.close()
    return {"tool": "flexfmu", "case": case, "elements": n_el, "t_end": t_end, "step_s": h, "wall_s": wall,
            "init_s": init, "rtf": t_end / wall, "omega2": w2, "tight": tight, "slack": slack}


def run_exudyn_layout(n_el, t_end, h=1e-3):
    """An Exudyn model of the flexfmu drive's layout (written for this benchmark from Exudyn's
    documented items): timing of the same layout (the physics comparison is
    scripts/validate_belt_exudyn.py)."""
    import exudyn as exu
    from exudyn.beams import CreateReevingCurve, PointsAndSlopes2ANCFCable2D
    from exudyn.itemInterface import (Cable2D, CoordinateConstraint, CoordinateSpringDamper,
                                      LoadCoordinate, MarkerBodyCable2DShape, MarkerBodyRigid,
                                      MarkerNodeCoordinate, MarkerNodeRigid, NodeGenericData,
                                      NodePointGround, NodeRigidBody2D, ObjectContactFrictionCircleCable2D,
                                      ObjectGround, ObjectRigidBody2D, RevoluteJoint2D, SensorNode)

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    rp1, rp2 = R1 + THICK / 2, R2 + THICK / 2
    circles = [[[0, 0], rp1, "L"], [[CENTER, 0], rp2, "L"], [[0, 0], rp1, "L"], [[CENTER, 0], rp2, "L"]]
    reeving = CreateReevingCurve(circles, removeLastLine=True, numberOfANCFnodes=n_el, graphicsNodeSize=0)
    template = Cable2D(physicsMassPerLength=MASS, physicsBendingStiffness=EI, physicsAxialStiffness=EA,
                       physicsAxialDamping=20.0, physicsReferenceAxialStrain=-T0 / EA,
                       useReducedOrderIntegration=2)
    ancf = PointsAndSlopes2ANCFCable2D(mbs, reeving["ancfPointsSlopes"], reeving["elementLengths"], template,
                                       firstNodeIsLastNode=True)
    ground = mbs.AddObject(ObjectGround())
    n_ground = mbs.AddNode(NodePointGround())
    m_ground = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=n_ground, coordinate=0))
    k_n = EA / (THICK * rp1)  # the automatic penalty of flexfmu, per unit length
    seg = 4
    for i, (p, r, j) in enumerate(((0.0, rp1, 0.005), (CENTER, rp2, J2))):
        node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[p, 0, 0]))
        mbs.AddObject(ObjectRigidBody2D(mass=1.0, inertia=j, nodeNumber=node))
        if i == 1:
            sensor = mbs.AddSensor(SensorNode(nodeNumber=node, storeInternal=True,
                                              outputVariableType=exu.OutputVariableType.AngularVelocity))
        m_node = mbs.AddMarker(MarkerNodeRigid(nodeNumber=node))
        m_g = mbs.AddMarker(MarkerBodyRigid(bodyNumber=ground, localPosition=[p, 0, 0]))
        mbs.AddObject(RevoluteJoint2D(markerNumbers=[m_g, m_node]))
        m_rot = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=2))
        if i == 0:
            def vel(mbs, t, item, offset):
                return drive(t)[0]
            mbs.AddObject(CoordinateConstraint(markerNumbers=[m_ground, m_rot], velocityLevel=True,
                                               offsetUserFunction_t=vel))
        else:
            mbs.AddObject(CoordinateSpringDamper(markerNumbers=[m_ground, m_rot], stiffness=0, damping=C2))
            mbs.AddLoad(LoadCoordinate(markerNumber=m_rot, load=-LOAD))
        for el in ancf[1]:
            m_cable = mbs.AddMarker(MarkerBodyCable2DShape(bodyNumber=el, numberOfSegments=seg))
            data = mbs.AddNode(NodeGenericData(initialCoordinates=[0.1] * seg + [-2] * seg + [0.0] * seg,
                                               numberOfDataCoordinates=3 * seg))
            mbs.AddObject(ObjectContactFrictionCircleCable2D(
                markerNumbers=[m_node, m_cable], nodeNumber=data, numberOfContactSegments=seg,
                contactStiffness=k_n * reeving["elementLengths"][0] / seg,
                contactDamping=np.sqrt(k_n * MASS) * reeving["elementLengths"][0] / seg,
                frictionVelocityPenalty=1e3, frictionStiffness=0.01 * k_n * reeving["elementLengths"][0] / seg,
                frictionCoefficient=MU, circleRadius=r))
    mbs.Assemble()
    s = exu.SimulationSettings()
    s.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    s.parallel.numberOfThreads = 1
    s.solution.file.write = False
    s.timeIntegration.endTime = t_end
    s.timeIntegration.numberOfSteps = int(round(t_end / h))
    s.timeIntegration.verboseMode = 0
    s.timeIntegration.newton.useModifiedNewton = True
    s.timeIntegration.generalizedAlpha.spectralRadius = 0.8
    s.timeIntegration.discontinuous.maxIterations = 7
    t0 = time.perf_counter()
    ok = mbs.SolveDynamic(s)
    wall = time.perf_counter() - t0
    w2 = float(mbs.GetSensorStoredData(sensor)[-1, 3])
    return {"tool": "exudyn", "case": "layout (indicative)", "elements": n_el, "t_end": t_end, "step_s": h,
            "wall_s": wall, "init_s": float("nan"), "rtf": t_end / wall if ok else float("nan"), "omega2": w2,
            "tight": float("nan"), "slack": float("nan")}


def serpentine_inputs(t, t_end):
    """Crank speed [rad/s] and the A/C compressor's load torque [N m] at time t (the protocol of
    examples/bench_belt_predictor.rs)."""
    t2 = 0.2 + 0.6 * t_end
    rpm = 800.0 if t < 0.2 else (800.0 + 2200.0 * (t - 0.2) / (t2 - 0.2) if t < t2 else 3000.0)
    omega = rpm * min(t / 0.1, 1.0) * np.pi / 30.0
    load = -5.0 * min(max((t - 0.4 * t_end) / 0.05, 0.0), 1.0)
    return omega, load


def run_serpentine(n_el, t_end, h=1e-3, ale=False):
    start = time.perf_counter()
    # the shipped serpentine is an ALE belt (session 38): the Lagrangian one is asked for by name
    params = {"belt.n_elements": n_el, "belt.formulation": 2 if ale else 1}
    fmu = Fmu(ROOT / "build" / "fmus" / "serpentine.fmu", params)
    init = time.perf_counter() - start
    try:
        t0 = time.perf_counter()
        angle = 0.0
        for i in range(int(round(t_end / h))):
            t = i * h
            w, load = serpentine_inputs(t, t_end)
            fmu.set(pulley1__angle=angle, pulley1__omega=w, pulley7__torque_in=load)
            set_speed_slope(fmu, "pulley1.omega", w, serpentine_inputs(t + h, t_end)[0], h)
            if not fmu.step(t, h):
                raise RuntimeError(f"FMU step failed at t = {t}")
            angle += 0.5 * (w + serpentine_inputs(t + h, t_end)[0]) * h
            w2, tight, slack = fmu.get("pulley2.omega", "belt.tension_tight", "belt.tension_slack")
        wall = time.perf_counter() - t0
    finally:
        fmu.close()
    return {"tool": "flexfmu", "case": "serpentine ALE" if ale else "serpentine", "elements": n_el, "t_end": t_end,
            "step_s": h, "wall_s": wall, "init_s": init, "rtf": t_end / wall, "omega2": w2, "tight": tight,
            "slack": slack}


def run_exudyn_test_model(t_end, h=0.5e-3, per_section=32):
    """Exudyn's belt-drive test model (TestModels/ANCFbeltDrive.py), rebuilt from its parameters
    (see the module docstring); one thread, no solution file."""
    sys.exudynFast = True
    warnings.filterwarnings("ignore", category=DeprecationWarning, module="exudyn")
    warnings.filterwarnings("ignore", category=DeprecationWarning, message=".*deprecated.*")
    import exudyn as exu
    from exudyn.beams import GenerateCircularArcANCFCable2D, GenerateStraightLineANCFCable2D
    from exudyn.itemInterface import (Cable2D, CoordinateConstraint, CoordinateSpringDamper, MarkerBodyRigid,
                                      MarkerNodeCoordinate, MarkerNodeRigid, NodePointGround, NodeRigidBody2D,
                                      ObjectGround, ObjectRigidBody2D, RevoluteJoint2D, SensorNode)
    from exudyn.utilities import InertiaCylinder

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    m_ground = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()), coordinate=0))
    contact = mbs.AddGeneralContact()
    contact.frictionProportionalZone = 1
    contact.ancfCableUseExactMethod = False
    contact.ancfCableNumberOfContactSegments = 8
    contact.SetSearchTreeCellSize(numberOfCells=[16, 8, 1])
    k_c, d_c, mu, width = 1e5, 1e2, 0.5, 0.002
    young, rho, area, inertia = 1e10, 1000.0, 0.002 * 0.002, 0.002 * 0.002**3 / 12
    cable = Cable2D(physicsMassPerLength=rho * area, physicsBendingStiffness=young * inertia,
                    physicsAxialStiffness=young * area, physicsBendingDamping=0.0,
                    physicsAxialDamping=1e-2 * young * area, physicsReferenceAxialStrain=-0.002)
    c0, c1, r, gravity = np.array([0.0, 0, 0]), np.array([2.0, 0, 0]), 0.5, [0, -9.81, 0]
    e_y = np.array([0.0, 1, 0])
    arc1 = GenerateCircularArcANCFCable2D(mbs, c0 - r * e_y, r, -np.pi, -np.pi, per_section, cable,
                                          massProportionalLoad=gravity, setCurvedReferenceConfiguration=False)
    top = GenerateStraightLineANCFCable2D(mbs, arc1[3][-1], c1 + r * e_y, per_section, cable,
                                          massProportionalLoad=gravity, nodeNumber0=arc1[0][-1])
    arc2 = GenerateCircularArcANCFCable2D(mbs, top[3][-1], r, 0.0, -np.pi, per_section, cable,
                                          massProportionalLoad=gravity, setCurvedReferenceConfiguration=False,
                                          nodeNumber0=top[0][-1])
    bottom = GenerateStraightLineANCFCable2D(mbs, arc2[3][-1], arc1[3][0], per_section, cable,
                                             massProportionalLoad=gravity, nodeNumber0=arc2[0][-1],
                                             nodeNumber1=arc1[0][0])
    sensors = []
    # wheel 0 (speed-driven), wheel 1 (damper), measuring roll (vertical spring, no friction)
    for i, (p, rad, mass) in enumerate(((c0, r, 4.0), (c1, r, 4.0), (np.array([1.0, -r + 0.1, 0]), 0.1, 1e-6))):
        cyl = InertiaCylinder(mass / (rad**2 * np.pi * width), width, rad, axis=2)
        node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[p[0], p[1], 0.0]))
        mbs.AddObject(ObjectRigidBody2D(mass=cyl.mass, inertia=cyl.GetInertia6D()[2], nodeNumber=node))
        m_node = mbs.AddMarker(MarkerNodeRigid(nodeNumber=node))
        m_rot = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=2))
        material = 0
        if i < 2:
            m_g = mbs.AddMarker(MarkerBodyRigid(bodyNumber=ground, localPosition=list(p)))
            mbs.AddObject(RevoluteJoint2D(markerNumbers=[m_g, m_node]))
        else:
            material, k_roll = 1, 1e-2
            m_x = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=0))
            m_y = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=1))
            mbs.AddObject(CoordinateConstraint(markerNumbers=[m_ground, m_x]))
            mbs.AddObject(CoordinateSpringDamper(markerNumbers=[m_ground, m_y], stiffness=k_roll,
                                                 damping=0.005 * 2 * np.sqrt(k_roll * mass), offset=-0.01 / k_roll))
        if i == 0:
            mbs.AddObject(CoordinateConstraint(markerNumbers=[m_ground, m_rot], velocityLevel=True,
                                               offsetUserFunction_t=lambda mbs, t, item, off: min(0.5 * t, 10.0)))
        elif i == 1:
            mbs.AddObject(CoordinateSpringDamper(markerNumbers=[m_ground, m_rot], damping=1.0))
        contact.AddSphereWithMarker(m_node, radius=rad, contactStiffness=k_c, contactDamping=d_c,
                                    frictionMaterialIndex=material)
        sensors.append(mbs.AddSensor(SensorNode(nodeNumber=node, storeInternal=True,
                                                outputVariableType=exu.OutputVariableType.AngularVelocity)))
    for section in (arc1, top, arc2, bottom):
        for obj in section[1]:
            contact.AddANCFCable(objectIndex=obj, halfHeight=0.0, contactStiffness=k_c, contactDamping=d_c,
                                 frictionMaterialIndex=0)
    contact.SetFrictionPairings(np.array([[mu, 0.0], [0.0, 0.0]]))
    mbs.Assemble()
    s = exu.SimulationSettings()
    s.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    s.solution.file.write = False
    s.parallel.numberOfThreads = 1
    s.timeIntegration.endTime = t_end
    s.timeIntegration.numberOfSteps = int(round(t_end / h))
    s.timeIntegration.verboseMode = 0
    s.timeIntegration.newton.useModifiedNewton = True
    t0 = time.perf_counter()
    ok = mbs.SolveDynamic(s)
    wall = time.perf_counter() - t0
    w0, w1 = (float(mbs.GetSensorStoredData(k)[-1, 3]) for k in sensors[:2])
    return {"tool": "exudyn", "case": "test model ANCFbeltDrive", "elements": 4 * per_section, "t_end": t_end,
            "step_s": h, "wall_s": wall, "init_s": float("nan"), "rtf": t_end / wall if ok else float("nan"),
            "omega2": w1, "tight": float("nan"), "slack": float("nan"), "omega_driver": w0}


def plot(rows, path):
    import matplotlib
    import matplotlib.ticker
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    drive = sorted((r["elements"], r["rtf"]) for r in rows if r["case"] == "belt_drive")
    if drive:
        ax.loglog(*zip(*drive), "o-", label="belt_drive (fmpy, 1 ms)")
    for case, marker in (("soft", "s"), ("serpentine", "^"), ("belt_drive_3d", "D-"),
                         ("belt_drive ALE", "o--"), ("soft ALE", "s--")):
        pts = [(r["elements"], r["rtf"]) for r in rows if r["case"] == case]
        if pts:
            ax.loglog(*zip(*pts), marker, markersize=8, label=f"{case} (fmpy, 1 ms)")
    exu_rows = [r for r in rows if r["case"].startswith("test model")]
    ax.axhline(2.0, color="k", ls=":", label="target: 2x real time")
    if exu_rows:
        e = exu_rows[0]
        ax.axhline(e["rtf"], color="C3", ls="--", label=f"Exudyn test model ({e['elements']} el, 0.5 ms)")
        ax.axhline(10 * e["rtf"], color="C3", ls=":", label="10x Exudyn")
    ticks = sorted({r["elements"] for r in rows if r["tool"] == "flexfmu"})
    ax.set_xticks(ticks)
    ax.xaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
    ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    ax.set_xlabel("belt elements")
    ax.set_ylabel("real-time factor (simulated / wall time)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    ap = argparse.ArgumentParser(description="belt-drive real-time factor against Exudyn's test model")
    ap.add_argument("--elements", type=int, nargs="*", default=[16, 25, 50, 100, 120, 200, 400])
    ap.add_argument("--t-end", type=float, default=1.0, help="simulated time of the belt_drive and soft runs [s]")
    ap.add_argument("--soft-elements", type=int, nargs="*", default=[120])
    ap.add_argument("--serpentine-elements", type=int, nargs="*", default=[120])
    ap.add_argument("--elements-3d", type=int, nargs="*", default=[60, 120, 240],
                    help="element counts of the 3D belt (belt_drive_3d, same drive and protocol)")
    ap.add_argument("--ale-elements", type=int, nargs="*", default=[60, 120, 240],
                    help="element counts of the drive and the soft belt as ALE belts (belt.formulation = 2)")
    ap.add_argument("--serpentine-t-end", type=float, default=0.5)
    ap.add_argument("--serpentine-ale-elements", type=int, nargs="*", default=[],
                    help="element counts of the serpentine as an ALE belt (belt.formulation = 2), each run "
                         "right after the Lagrangian serpentine of the same count when that is in the list")
    ap.add_argument("--serpentine-repeat", type=int, default=1,
                    help="run the serpentine cases this many times, alternating Lagrangian and ALE")
    ap.add_argument("--exudyn-t-end", type=float, default=10.0,
                    help="simulated time of Exudyn's test model [s] (its own end time: 10 s)")
    ap.add_argument("--no-exudyn", action="store_true", help="skip Exudyn's test model")
    ap.add_argument("--input-derivatives", action="store_true",
                    help="set the driver speed's derivative at every communication step (canInterpolateInputs)")
    ap.add_argument("--exudyn-layout", action="store_true", help="also run the indicative Exudyn layout model")
    args = ap.parse_args()
    global INPUT_DERIVATIVES
    INPUT_DERIVATIVES = args.input_derivatives
    if INPUT_DERIVATIVES:
        print("input derivatives: the driver speed's slope is set at every communication step", flush=True)

    def fmt(r):
        return (f"{r['tool']:8s} {r['case']:26s} {r['elements']:8d} {1e3 * r['step_s']:6.2f} {r['t_end']:6.2f} "
                f"{r['wall_s']:9.3f} {r['wall_s'] / r['t_end']:12.3f} {r['rtf']:9.3f} {r['omega2']:10.3f}")

    header = (f"{'tool':8s} {'case':26s} {'elements':>8s} {'h [ms]':>6s} {'t [s]':>6s} {'wall [s]':>9s} "
              f"{'wall/sim s':>12s} {'RT factor':>9s} {'omega2':>10s}")
    print(header, flush=True)
    runs = [("belt_drive", n) for n in args.elements] + [("soft", n) for n in args.soft_elements]
    runs += [(c, n) for c in ("belt_drive ALE", "soft ALE") for n in args.ale_elements]
    for _ in range(args.serpentine_repeat):
        for n in sorted(set(args.serpentine_elements) | set(args.serpentine_ale_elements)):
            if n in args.serpentine_elements:
                runs.append(("serpentine", n))
            if n in args.serpentine_ale_elements:
                runs.append(("serpentine ALE", n))
    runs += [("belt_drive_3d", n) for n in args.elements_3d]
    if not args.no_exudyn:
        runs.append(("exudyn", 128))
    if args.exudyn_layout:
        runs += [("layout", n) for n in args.elements]
    rows = []
    for case, n in runs:
        try:
            if case in ("belt_drive", "soft", "belt_drive_3d", "belt_drive ALE", "soft ALE"):
                r = run_flexfmu(n, args.t_end, case=case)
            elif case in ("serpentine", "serpentine ALE"):
                r = run_serpentine(n, args.serpentine_t_end, ale=case == "serpentine ALE")
            elif case == "exudyn":
                r = run_exudyn_test_model(args.exudyn_t_end)
            else:
                r = run_exudyn_layout(n, args.t_end)
        except Exception as e:  # report, do not hide
            print(f"{case}, {n} elements: failed: {e}", flush=True)
            continue
        rows.append(r)
        print(fmt(r), flush=True)
    exu_rows = [r for r in rows if r["case"].startswith("test model")]
    if exu_rows:
        e = exu_rows[0]
        per_s = e["wall_s"] / e["t_end"]
        print(f"\nExudyn test model: {per_s:.3f} s wall per simulated second (driver {e['omega_driver']:.3f}, "
              f"driven {e['omega2']:.3f} rad/s at {e['t_end']} s). Wall time per simulated second against it "
              f"(issue 12 target: <= 0.1 at 120 elements):")
        for r in rows:
            if r["tool"] == "flexfmu":
                ratio = (r["wall_s"] / r["t_end"]) / per_s
                print(f"  {r['case']:12s} {r['elements']:5d} el: {ratio:.4f}  ({1 / ratio:.1f}x faster)")
                r["ratio_to_exudyn"] = ratio
    out = ROOT / "build" / "bench"
    out.mkdir(parents=True, exist_ok=True)
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with open(out / "belt.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    plot(rows, out / "belt.png")
    print(f"csv: {out / 'belt.csv'}, plot: {out / 'belt.png'}")


if __name__ == "__main__":
    main()
