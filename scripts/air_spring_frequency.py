"""Dynamic stiffness and loss angle of the air spring with a reservoir (scenes/air_spring_reservoir.toml)
against the linear two-volume model (issue 11 item 8; air-spring-physics.md 1.5).

The FMU is driven through fmpy: `top.z` = z0 + a env(t) sin(wt) (env ramps up smoothly over the
first second, so the lightly damped pipe mode is not kicked), `top.vz` the secant slope over each
1 ms communication step (the derivative of the path the FMU follows). The first harmonic of
`top.fz` is fitted by least squares over whole periods after the run-in; the dynamic stiffness
is K = -F^/z^ (compression positive) and the loss angle arg K.

The sleeve has mass (bellows.density): its share moving with the plate, m_w, subtracts m_w w^2
(0.4 % at 10 Hz, 6 % at 20 Hz). The linear models carry -m_w w^2 with m_w measured on the closed
bag (scenes/air_spring_axisym.toml, same wall, no reservoir) at 20 Hz.

Linear model, everything read from the FMU at its design state (static initialization), in
volume-flow units (air-spring-physics.md 1.5; src/gas/linear.rs writes the same in mass flow):

    K(w) = A_e A_v / (C_b + C_r / (1 + i w R_f C_r - w^2 I C_r)) + k_wall

with A_e = `spring.effective_area`, A_v = `spring.volumetric_area`, C_b = V_b/(n p), V_b =
`gas.volume`, p = `gas.pressure`, C_r = V_r/(n p_r), V_r = `reservoir.volume`, p_r =
`reservoir.pressure`, n = `gas.polytropic_exponent`; R_f = 128 mu l/(pi D^4) the laminar
(Hagen-Poiseuille) resistance of the pipe (mu = 1.81e-5 Pa s; the orifice drop is quadratic in
the flow and adds nothing at zero flow), I = rho l / A_pipe the pipe inertance (rho = gas.mass/V_b).
k_wall = `spring.stiffness` - n p A_e A_v / V_b: the FMU's quasi-static stiffness of the closed
bag minus its gas term, i.e. the wall/geometry term p_g dA_e/dz.

This form takes A_v and the wall term of the closed bag; with a reservoir the pressure swings less,
the bag swells less and A_v and the wall term change (the A_e A_v form is 5 % soft at low
frequency). The consistent linearization of the quasi-static wall V(h, p), F(h, p) is

    K(w) = F_p V_h / (C_b + V_p + C_r / (1 + i w R_f C_r - w^2 I C_r)) - F_h

(V_h = dV/dh, F_h = dF/dh at constant p, V_p = dV/dp, F_p = dF/dp at constant h), which the script
derives from the FMU's spring.volumetric_area and spring.stiffness of the closed bag at two
polytropic exponents (`wall_derivatives`); it reduces to the first form for V_p = 0.

The orifice is not linear: its drop rho Q|Q|/(2 C_d^2 A_o^2) dominates the laminar pipe drop for
all but tiny flows. The script therefore also runs smaller amplitudes (the FMU should approach the
linear model as a -> 0) and gives the describing-function model: the linear model with
R = R_f + 8 c |Q^|/(3 pi), c = rho/(2 C_d^2 A_o^2), |Q^| the pipe flow amplitude of that same
model (solved by fixed-point iteration): the equivalent linear resistance of a quadratic loss under
a sinusoidal flow.

Run: python scripts/air_spring_frequency.py [--amplitudes 5e-4 5e-5 5e-6] [--plot docs/air_spring_reservoir.png]
"""
import argparse
import math
import pathlib
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
from cosim_mujoco import Fmu  # noqa: E402

FMU = ROOT / "build" / "fmus" / "air_spring_reservoir.fmu"
MU_AIR = 1.81e-5  # Pa s, as src/gas/params.rs
STEP = 1e-3  # s
# whole numbers of 1 ms steps per period
FREQUENCIES = [0.1, 0.2, 0.5, 1.0, 2.0, 4.0, 5.0, 8.0, 10.0, 12.5, 20.0]
RAMP = 1.0  # s, smooth run-in of the amplitude


def design_state(fmu_path=FMU, start_values=None):
    """The linear-model ingredients at the FMU's design state (static initialization)."""
    f = Fmu(fmu_path, start_values)
    try:
        names = ["spring.effective_area", "spring.volumetric_area", "gas.volume", "gas.pressure",
                 "gas.pressure_gauge", "gas.mass", "reservoir.pressure", "spring.stiffness", "top.fz",
                 "reservoir.volume", "gas.polytropic_exponent", "pipe.length", "pipe.diameter",
                 "orifice.diameter", "orifice.cd", "spring.design_height"]
        return dict(zip(names, f.get(*names)))
    finally:
        f.close()


class LinearModel:
    """The linear two-volume model of the module documentation (volume-flow units):
    K(w) = gain / (c_bag + C_r / (1 + i w R C_r - w^2 I C_r)) + k_wall.

    `compliance=None`: the form of air-spring-physics.md 1.5, gain = A_e A_v, c_bag = C_b,
    k_wall = spring.stiffness - n p A_e A_v / V_b, with A_v and spring.stiffness those of the
    closed bag. `compliance=(V_h, V_p, F_h, F_p)`: the linearization of the quasi-static wall
    V(h, p), F(h, p) (see `wall_derivatives`), gain = F_p V_h, c_bag = C_b + V_p, k_wall = -F_h:
    the bag swells with the pressure (V_p), and a reservoir changes how much, which the first form,
    with A_v and dA_e/dz of the closed bag, does not follow."""

    def __init__(self, d, compliance=None, wall_mass=0.0):
        self.d = d
        self.wall_mass = wall_mass  # kg, see `wall_mass`
        n = d["gas.polytropic_exponent"]
        self.n = n
        self.a_e, self.a_v = d["spring.effective_area"], d["spring.volumetric_area"]
        self.c_b = d["gas.volume"] / (n * d["gas.pressure"])  # m3/Pa
        self.c_r = d["reservoir.volume"] / (n * d["reservoir.pressure"])
        self.rho = d["gas.mass"] / d["gas.volume"]
        a_pipe = math.pi * d["pipe.diameter"] ** 2 / 4
        self.r_f = 128 * MU_AIR * d["pipe.length"] / (math.pi * d["pipe.diameter"] ** 4)  # Pa s/m3
        self.inertance = self.rho * d["pipe.length"] / a_pipe  # kg/m4 = Pa s2/m3
        a_o = math.pi * d["orifice.diameter"] ** 2 / 4
        self.c_orifice = self.rho / (2 * d["orifice.cd"] ** 2 * a_o ** 2)  # Pa s2/m6
        self.k_gas_bag = self.a_e * self.a_v / self.c_b
        if compliance is None:
            self.gain, self.v_h, self.c_bag = self.a_e * self.a_v, self.a_v, self.c_b
            self.k_wall = d["spring.stiffness"] - self.k_gas_bag
        else:
            v_h, v_p, f_h, f_p = compliance
            self.gain, self.v_h, self.c_bag, self.k_wall = f_p * v_h, v_h, self.c_b + v_p, -f_h

    def branch(self, w, r):
        return 1 + 1j * w * r * self.c_r - w * w * self.inertance * self.c_r

    def stiffness(self, w, r=None):
        r = self.r_f if r is None else r
        return self.gain / (self.c_bag + self.c_r / self.branch(w, r)) + self.k_wall - self.wall_mass * w * w

    def pipe_flow(self, w, amp, r):
        """Pipe volume-flow amplitude [m3/s] for a plate amplitude amp: the bag's volume change
        V_h amp splits into the bag's compression and the flow Q,
        dp_b c_bag = -(V_h amp + Q/(iw)), dp_r = Q/(iw C_r), (R + iw I) Q = dp_b - dp_r."""
        z = r + 1j * w * self.inertance
        q = -self.v_h * amp / self.c_bag / (z + 1 / (1j * w * self.c_bag) + 1 / (1j * w * self.c_r))
        return abs(q)

    def describing_function_stiffness(self, w, amp):
        """Linear model with R = R_f + 8 c |Q|/(3 pi) at the flow amplitude it gives."""
        r = self.r_f
        for _ in range(200):
            r_new = self.r_f + 8 * self.c_orifice * self.pipe_flow(w, amp, r) / (3 * math.pi)
            if abs(r_new - r) <= 1e-10 * r_new:
                break
            r = 0.5 * (r + r_new)
        return self.stiffness(w, r)


def wall_derivatives(fmu_path=FMU, factor=0.7, start_values=None):
    """(V_h, V_p, F_h, F_p) of the quasi-static wall at the design state, from what the FMU
    reports for the closed bag at two polytropic exponents n and factor n (the design state does
    not depend on n). With dp = -(V_h dh + V_p dp)/C_b, C_b = V/(n p):
    1/A_v = 1/V_h + (V_p/V_h) n p/V and k = -F_h + F_p A_v n p/V, both linear in n: two
    exponents give the four derivatives. (Maxwell: F_p = V_h for a wall with a potential.)"""
    d1 = design_state(fmu_path, start_values)
    n1 = d1["gas.polytropic_exponent"]
    d2 = design_state(fmu_path, dict(start_values or {}, **{"gas.polytropic_exponent": factor * n1}))
    x = [n * d["gas.pressure"] / d["gas.volume"] for n, d in ((n1, d1), (factor * n1, d2))]
    inv = [1 / d["spring.volumetric_area"] for d in (d1, d2)]
    slope = (inv[0] - inv[1]) / (x[0] - x[1])
    v_h = 1 / (inv[0] - slope * x[0])
    v_p = slope * v_h
    y = [d["spring.volumetric_area"] * xi for d, xi in zip((d1, d2), x)]
    f_p = (d1["spring.stiffness"] - d2["spring.stiffness"]) / (y[0] - y[1])
    f_h = f_p * y[0] - d1["spring.stiffness"]
    return v_h, v_p, f_h, f_p


def wall_mass(freq=20.0, amp=5e-4, start_values=None, freq_low=2.0):
    """Effective mass [kg] of the sleeve moving with the plate: the two-volume model has none, an
    FMU whose wall has inertia has (bellows.density, with solver.integrator = 1); the shipped
    membrane-level scenes step quasi-statically (no wall inertia, m_w = 0). Measured on the closed
    bag (scenes/air_spring_axisym.toml, same wall, no reservoir, same integrator) as the drop of
    the real part of K(w) = K_wall - m_w w^2 between two frequencies at the same amplitude: the
    discrete characteristic has a slope sawtooth (nodes leaving the piston), so the secant stiffness
    of a finite stroke differs from the pointwise spring.stiffness at the design height."""
    closed = ROOT / "build" / "fmus" / "air_spring_axisym.fmu"
    k_high, _, _ = measure(freq, amp, closed, start_values)
    k_low, _, _ = measure(freq_low, amp, closed, start_values)
    return (k_low.real - k_high.real) / ((2 * math.pi * freq) ** 2 - (2 * math.pi * freq_low) ** 2)


def design_state_closed(path):
    f = Fmu(path)
    try:
        return f.get("spring.stiffness")[0]
    finally:
        f.close()


def measure(freq, amp, fmu_path=FMU, start_values=None, periods=None):
    """Runs the sine drive and returns (complex K, wall time, simulated time)."""
    f = Fmu(fmu_path, start_values)
    try:
        z0 = f.get("spring.design_height")[0]
        w = 2 * math.pi * freq
        n_period = int(round(1 / (freq * STEP)))
        n_fit = n_period * (periods or max(1, math.ceil(1.0 * freq)))  # at least a period and ~1 s
        n_run = int(round(RAMP / STEP)) + max(n_period, int(round(1.0 / STEP)))  # run-in and settling
        n_total = n_run + n_fit

        def z(k):
            t = k * STEP
            env = 0.5 * (1 - math.cos(math.pi * min(t / RAMP, 1.0)))
            return z0 + amp * env * math.sin(w * t)

        fz = np.empty(n_total)
        tic = time.perf_counter()
        for k in range(n_total):
            za, zb = z(k), z(k + 1)
            f.set(top__z=za, top__vz=(zb - za) / STEP)
            if not f.step(k * STEP, STEP):
                raise RuntimeError(f"FMU step failed at t = {k * STEP} s, f = {freq} Hz, a = {amp} m")
            # read top.fz with top.z at the committed height: right after fmi2DoStep the FMU
            # extrapolates top.fz to the top.z last set, ignoring top.vz (reported FMU bug)
            f.set(top__z=zb)
            fz[k] = f.get("top.fz")[0]
        wall = time.perf_counter() - tic
    finally:
        f.close()
    t = (np.arange(n_run, n_total) + 1) * STEP
    basis = np.column_stack([np.ones_like(t), t - t.mean(), np.cos(w * t), np.sin(w * t)])
    coef, *_ = np.linalg.lstsq(basis, fz[n_run:], rcond=None)
    f_hat = coef[3] + 1j * coef[2]  # F = Im(F^ e^{iwt}), z = Im(a e^{iwt})
    return -f_hat / amp, wall, n_total * STEP


def table(amplitudes, freqs=FREQUENCIES, fmu_path=FMU, verbose=True):
    """Runs every (amplitude, frequency); returns the two linear models and the rows."""
    d = design_state(fmu_path)
    m_w = wall_mass()
    simple = LinearModel(d, wall_mass=m_w)
    wall = wall_derivatives(fmu_path)
    lin = LinearModel(d, wall, wall_mass=m_w)
    if verbose:
        v_h, v_p, f_h, f_p = wall
        print(f"design state: F = {d['top.fz']:.2f} N, A_e = {lin.a_e:.6f} m2, A_v = {lin.a_v:.6f} m2, "
              f"V_b = {d['gas.volume'] * 1e3:.4f} L, V_r = {d['reservoir.volume'] * 1e3:.1f} L, n = {lin.n}")
        print(f"  k (closed bag, FMU) = {d['spring.stiffness']:.1f} N/m = gas n p A_e A_v/V_b {simple.k_gas_bag:.1f} "
              f"+ wall {simple.k_wall:.1f} N/m")
        print(f"  wall at constant p: V_h = dV/dh = {v_h:.6f} m2, F_p = dF/dp = {f_p:.6f} m2, "
              f"-F_h = {-f_h:.1f} N/m; at constant h: V_p = dV/dp = {v_p:.4e} m3/Pa (C_b = {lin.c_b:.4e} m3/Pa)")
        print(f"  pipe: R_f = {lin.r_f:.4g} Pa s/m3, I = {lin.inertance:.4g} kg/m4, orifice c = {lin.c_orifice:.4g} Pa s2/m6, "
              f"pipe resonance {math.sqrt((lin.c_bag + lin.c_r) / (lin.inertance * lin.c_bag * lin.c_r)) / (2 * math.pi):.2f} Hz")
        print(f"  wall inertia: m_w = {m_w:.4f} kg (closed bag at 20 Hz; the sleeve weighs "
              f"{2 * math.pi * 0.125 * 0.3 * 0.004 * 1100:.3f} kg), -m_w w^2 added to both models")
        print(f"  K(0): A_e A_v form {simple.stiffness(0.0).real:.1f} N/m, with wall compliance {lin.stiffness(0.0).real:.1f} N/m")
        print(f"{'a [mm]':>7} {'f [Hz]':>6} | {'|K| FMU':>9} {'lin. A':>9} {'lin. B':>9} {'B desc.':>9} | "
              f"{'dev A':>7} {'dev B':>7} {'dev Bd':>7} | {'loss FMU':>8} {'A':>6} {'B':>6} {'B desc.':>7} | {'RTF':>4}")
    rows = []
    for amp in amplitudes:
        for fr in freqs:
            k, wall_time, sim = measure(fr, amp, fmu_path)
            w = 2 * math.pi * fr
            ka, kb, kd = simple.stiffness(w), lin.stiffness(w), lin.describing_function_stiffness(w, amp)
            rows.append(dict(amp=amp, f=fr, K=k, K_a=ka, K_b=kb, K_df=kd, rtf=sim / wall_time))
            if verbose:
                dev = [100 * (abs(k) / abs(x) - 1) for x in (ka, kb, kd)]
                deg = [math.degrees(np.angle(x)) for x in (k, ka, kb, kd)]
                print(f"{amp * 1e3:7.4f} {fr:6.1f} | {abs(k):9.0f} {abs(ka):9.0f} {abs(kb):9.0f} {abs(kd):9.0f} | "
                      f"{dev[0]:+6.2f}% {dev[1]:+6.2f}% {dev[2]:+6.2f}% | {deg[0]:8.2f} {deg[1]:6.2f} {deg[2]:6.2f} {deg[3]:7.2f} | "
                      f"{sim / wall_time:4.1f}", flush=True)
    return simple, lin, rows


def plot(simple, lin, rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7.5, 7), sharex=True)
    fw = np.logspace(-1.1, 1.35, 300)
    w = 2 * np.pi * fw
    for model, ls, label in ((simple, "k:", "linear, A_e A_v / C + k_wall (laminar pipe)"),
                             (lin, "k-", "linear with wall compliance (laminar pipe)")):
        k = np.array([model.stiffness(x) for x in w])
        ax1.semilogx(fw, np.abs(k) / 1e3, ls, lw=1.2, label=label)
        ax2.semilogx(fw, np.degrees(np.angle(k)), ls, lw=1.2)
    markers = "os^dv"
    for i, amp in enumerate(sorted({r["amp"] for r in rows}, reverse=True)):
        sel = [r for r in rows if r["amp"] == amp]
        fr = np.array([r["f"] for r in sel])
        k = np.array([r["K"] for r in sel])
        kd = np.array([lin.describing_function_stiffness(x, amp) for x in w])
        line, = ax1.semilogx(fr, np.abs(k) / 1e3, markers[i % 5], ms=5, label=f"FMU, a = {amp * 1e3:g} mm")
        ax1.semilogx(fw, np.abs(kd) / 1e3, "--", lw=0.8, color=line.get_color(),
                     label=f"with orifice (describing function), a = {amp * 1e3:g} mm")
        ax2.semilogx(fr, np.degrees(np.angle(k)), markers[i % 5], ms=5, color=line.get_color())
        ax2.semilogx(fw, np.degrees(np.angle(kd)), "--", lw=0.8, color=line.get_color())
    ax1.set_yscale("log")
    ax1.set_ylabel("|K| [kN/m]")
    ax1.legend(fontsize=6)
    ax1.set_title("Air spring + 20 L reservoir (level 2): dynamic stiffness")
    ax2.set_ylabel("loss angle [deg]")
    ax2.set_xlabel("frequency [Hz]")
    for ax in (ax1, ax2):
        ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    print(f"plot: {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--amplitudes", type=float, nargs="+", default=[5e-4, 5e-5, 5e-6])
    ap.add_argument("--freqs", type=float, nargs="+", default=FREQUENCIES)
    ap.add_argument("--plot", default=str(ROOT / "docs" / "air_spring_reservoir.png"))
    args = ap.parse_args()
    simple, lin, rows = table(args.amplitudes, args.freqs)
    if args.plot:
        plot(simple, lin, rows, args.plot)


if __name__ == "__main__":
    main()
