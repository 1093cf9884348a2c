#!/usr/bin/env python3
"""The SSP example (issue 14, item 6): a flexible link hanging from the tip of a steel boom, two
flexfmu FMUs coupled through a motion port and a force port (ssp/boom_link/: the two scenes,
SystemStructure.ssd, boom_link.ssv). This script builds both FMUs, packs
build/ssp/boom_link.ssp (SystemStructure.ssd + resources/boom.fmu, link.fmu, boom_link.ssv;
SSP 1.0, chapter 4: an .ssp is a zip with the .ssd at its root) and runs the system

- in libcosim (libcosimpy: CosimExecution.from_ssp_file on the unpacked archive, fixed step),
- in Ecos (ecospy: EcosSimulation(ssp_path=...) on the .ssp itself, fixed step),
- in libcosim from its own format (ssp/boom_link/OspSystemStructure.xml with the FMUs' OSP side
  files: one VariableGroupConnection of the ports instead of six connections),
- in a plain fmpy master written here (FMU2Slave, connections and parameter values read from the
  same .ssd and .ssv): explicit Jacobi coupling with the step of the other two: every
  communication step, each connection's output at t_k is written to its input, then both FMUs
  step from t_k to t_k+1 (the fixed-step algorithms of libcosim and Ecos do the same; before the
  first step, the outputs after initialization are passed on).

Coupling: the boom's tip position and velocity go to the link's pivot (the link extrapolates the
pivot inside a step with the velocity), the force the link exerts on its pivot goes back to the
boom's tip. Explicit coupling of a force-driven and a motion-driven body is stable when the
motion-driven side's stiffness over the force-driven node's mass, times h^2, stays well below 1:
k = EA/l_e = 1.035e8 x 0.01 / 0.25 = 4.1e6 N/m of the link's first element against the boom's tip
node (about 10 kg) gives k h^2 / (2 m) = 0.2 at h = 1 ms.

Usage: ssp_example.py [--fmu-dir DIR] [--plot FILE]; prints the largest deviations between the
three runs. Results: the boom's tip (x, y) and the link's pivot force (fx, fy) and tip (x, y).
"""
import argparse
import pathlib
import shutil
import subprocess
import sys
import tempfile
import zipfile

import numpy as np
from lxml import etree

ROOT = pathlib.Path(__file__).resolve().parents[1]
SOURCE = ROOT / "ssp" / "boom_link"
OUT = ROOT / "build" / "ssp"
NS = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
      "ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues"}
STEP = 1e-3  # communication step [s]
STOP = 1.0  # [s]: the link swings down through its lowest point (about 0.75 s)
RESULTS = [("boom", "tip.x"), ("boom", "tip.y"), ("link", "pivot.fx"), ("link", "pivot.fy"),
           ("link", "tip.x"), ("link", "tip.y")]


def build(fmu_dir=None):
    """Builds boom.fmu and link.fmu (or copies them from fmu_dir) and writes boom_link.ssp."""
    OUT.mkdir(parents=True, exist_ok=True)
    for name in ("boom", "link"):
        if fmu_dir is None:
            subprocess.run([str(ROOT / "target" / "release" / "flexfmu"), "build", str(SOURCE / f"{name}.toml"),
                            "-o", str(OUT / f"{name}.fmu")], check=True, capture_output=True)
        elif pathlib.Path(fmu_dir) != OUT:
            for f in (f"{name}.fmu", f"{name}_OspModelDescription.xml"):
                shutil.copy(pathlib.Path(fmu_dir) / f, OUT / f)
    ssp = OUT / "boom_link.ssp"
    with zipfile.ZipFile(ssp, "w", zipfile.ZIP_DEFLATED) as z:
        z.write(SOURCE / "SystemStructure.ssd", "SystemStructure.ssd")
        z.write(SOURCE / "boom_link.ssv", "resources/boom_link.ssv")
        for name in ("boom", "link"):
            z.write(OUT / f"{name}.fmu", f"resources/{name}.fmu")
    return ssp


def read_system(ssd_dir):
    """Components {name: fmu path}, connections [(from, output, to, input)] and parameter values
    {component: {name: value}} of an unpacked SSP, read from its .ssd and the .ssv it binds."""
    ssd = etree.parse(str(pathlib.Path(ssd_dir) / "SystemStructure.ssd"))
    components, params = {}, {}
    for c in ssd.iterfind(".//ssd:Component", NS):
        components[c.get("name")] = pathlib.Path(ssd_dir) / c.get("source")
        for b in c.iterfind("ssd:ParameterBindings/ssd:ParameterBinding", NS):
            ssv = etree.parse(str(pathlib.Path(ssd_dir) / b.get("source")))
            for p in ssv.iterfind(".//ssv:Parameter", NS):
                params.setdefault(c.get("name"), {})[p.get("name")] = float(p.find("ssv:Real", NS).get("value"))
    connections = [(c.get("startElement"), c.get("startConnector"), c.get("endElement"), c.get("endConnector"))
                   for c in ssd.iterfind(".//ssd:Connection", NS)]
    return components, connections, params


def run_fmpy(ssp, apply_parameters=True, read_after_transfer=False):
    """The plain fmpy master (Jacobi, fixed step). Rows [t, RESULTS...] at t = h..STOP, read
    right after the step or, with read_after_transfer, after the new outputs have been passed
    on to the inputs (as Ecos reads them: the link's pivot force depends directly on its pivot
    inputs, so it changes when they are set)."""
    import fmpy
    from fmpy.fmi2 import FMU2Slave

    with tempfile.TemporaryDirectory() as d:
        with zipfile.ZipFile(ssp) as z:
            z.extractall(d)
        components, connections, params = read_system(d)
        slaves, unzipped = {}, []
        try:
            for name, path in components.items():
                md = fmpy.read_model_description(str(path))
                unzipped.append(fmpy.extract(str(path)))
                s = FMU2Slave(guid=md.guid, unzipDirectory=unzipped[-1],
                              modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
                s.vr = {v.name: v.valueReference for v in md.modelVariables}
                s.instantiate()
                s.setupExperiment(startTime=0.0, stopTime=STOP)
                for p, value in (params.get(name, {}) if apply_parameters else {}).items():
                    s.setReal([s.vr[p]], [value])
                slaves[name] = s
            for s in slaves.values():
                s.enterInitializationMode()
            for s in slaves.values():
                s.exitInitializationMode()

            def transfer():
                values = [slaves[a].getReal([slaves[a].vr[o]])[0] for a, o, _, _ in connections]
                for (_, _, b, i), v in zip(connections, values):
                    slaves[b].setReal([slaves[b].vr[i]], [v])

            rows = []
            transfer()  # the outputs after initialization go to the inputs of the first step
            for k in range(int(round(STOP / STEP))):
                t = k * STEP
                for s in slaves.values():
                    s.doStep(currentCommunicationPoint=t, communicationStepSize=(k + 1) * STEP - t)
                if read_after_transfer:
                    transfer()
                rows.append([(k + 1) * STEP] + [slaves[c].getReal([slaves[c].vr[v]])[0] for c, v in RESULTS])
                if not read_after_transfer:
                    transfer()
            for s in slaves.values():
                s.terminate()
        finally:
            for s in slaves.values():
                s.freeInstance()
            for u in unzipped:
                shutil.rmtree(u, ignore_errors=True)
    return np.array(rows)


def _libcosim_rows(ex):
    """Steps a libcosim execution to STOP, the RESULTS after every step."""
    from libcosimpy.CosimObserver import CosimObserver

    step_ns = int(round(STEP * 1e9))
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    index = {}
    for info in ex.slave_infos():
        i = info.index
        index[info.name.decode()] = (i, {v.name.decode(): v.reference for v in ex.slave_variables(i)})
    rows = []
    for k in range(int(round(STOP / STEP))):
        assert ex.step(), f"libcosim step {k}"
        rows.append([(k + 1) * step_ns * 1e-9] + [
            obs.last_real_values(slave_index=index[c][0], variable_references=[index[c][1][v]])[0]
            for c, v in RESULTS])
    return np.array(rows)


def run_libcosim(ssp):
    """libcosim: the unpacked .ssp (libcosim reads a directory with SystemStructure.ssd), its
    fixed-step algorithm at STEP (integer nanoseconds)."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level

    log_output_level(CosimLogLevel.ERROR)
    with tempfile.TemporaryDirectory() as d:
        with zipfile.ZipFile(ssp) as z:
            z.extractall(d)
        ex = CosimExecution.from_ssp_file(ssp_path=d, step_size=int(round(STEP * 1e9)))
        return _libcosim_rows(ex)


def run_libcosim_osp(fmu_dir=OUT):
    """libcosim from its own configuration: ssp/boom_link/OspSystemStructure.xml next to the two
    FMUs and their <model>_OspModelDescription.xml side files (written by flexfmu build), the
    six connections as one VariableGroupConnection of the tip and pivot ports."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level

    log_output_level(CosimLogLevel.ERROR)
    with tempfile.TemporaryDirectory() as d:
        shutil.copy(SOURCE / "OspSystemStructure.xml", d)
        for name in ("boom", "link"):
            for f in (f"{name}.fmu", f"{name}_OspModelDescription.xml"):
                shutil.copy(pathlib.Path(fmu_dir) / f, d)
        ex = CosimExecution.from_osp_config_file(d)
        assert ex, "libcosim could not load OspSystemStructure.xml"
        return _libcosim_rows(ex)


def run_ecos(ssp):
    """Ecos: the .ssp archive itself, fixed step STEP, the parameter set of the .ssv by name."""
    from ecospy import EcosSimulation
    from ecospy.lib import EcosLib

    EcosLib.set_log_level("warn")
    rows = []
    with EcosSimulation(step_size=STEP, ssp_path=str(ssp)) as sim:
        sim.init(parameter_set="soft_link")
        for _ in range(int(round(STOP / STEP))):
            sim.step()
            rows.append([sim.get_time()] + [sim.get_real(f"{c}::{v}") for c, v in RESULTS])
    return np.array(rows)


def deviation(a, b):
    """Largest |a - b| per result, over the largest |b| of that result."""
    return np.abs(a[:, 1:] - b[:, 1:]).max(axis=0) / np.abs(b[:, 1:]).max(axis=0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fmu-dir", help="take boom.fmu and link.fmu from here instead of building them")
    ap.add_argument("--plot", help="write a plot of the three runs to this file")
    args = ap.parse_args()
    ssp = build(args.fmu_dir)
    runs = {"fmpy": run_fmpy(ssp), "libcosim": run_libcosim(ssp), "Ecos": run_ecos(ssp),
            "libcosim (OSP)": run_libcosim_osp()}
    names = [f"{c}.{v}" for c, v in RESULTS]
    for importer in ("libcosim", "Ecos", "libcosim (OSP)"):
        print(importer, "vs fmpy:", " ".join(f"{n} {d:.1e}" for n, d in zip(names, deviation(runs[importer], runs["fmpy"]))))
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
        for importer, r in runs.items():
            axes[0].plot(r[:, 0], r[:, 2] * 1e3, label=importer)
            axes[1].plot(r[:, 0], r[:, 4], label=importer)
        axes[0].set_ylabel("boom tip y [mm]")
        axes[1].set_ylabel("force on the boom tip, y [N]")
        axes[1].set_xlabel("t [s]")
        axes[0].legend()
        fig.savefig(args.plot, dpi=100)
    return 0


if __name__ == "__main__":
    sys.exit(main())
