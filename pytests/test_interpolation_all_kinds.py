"""canInterpolateInputs and output derivatives for every kind (issue 9, item 6): the 3D beam and
the belt drives take input derivatives (fmi2SetRealInputDerivatives) and give first output
derivatives (fmi2GetRealOutputDerivatives), checked against fine piecewise-constant coupling and
against finite differences of the outputs over a small step."""
import fmpy
import pytest

from conftest import SCENES
from helpers import Session


def init(s, **reals):
    s.slave.setupExperiment(startTime=0.0)
    for k, v in reals.items():
        s.slave.setReal([s.vr[k]], [v])
    s.slave.enterInitializationMode()
    s.slave.exitInitializationMode()


def get(s, names):
    return s.slave.getReal([s.vr[n] for n in names])


@pytest.mark.parametrize("name", SCENES)
def test_every_kind_interpolates_and_gives_output_derivatives(fmus, name):
    cs = fmpy.read_model_description(fmus[name]).coSimulation
    assert cs.canInterpolateInputs and cs.maxOutputDerivativeOrder == 1


def ramp_run(fmu, h, derivatives, name, ramp, slope, t_end, out, start=None):
    """Drives input `name` with ramp(t), optionally with slope(t) as its derivative, at
    communication step h; returns the outputs `out` at t_end."""
    s = Session(fmu)
    try:
        init(s, **(start or {}))
        for k in range(int(round(t_end / h))):
            t = k * h
            s.slave.setReal([s.vr[name]], [ramp(t)])
            if derivatives:
                s.slave.setRealInputDerivatives([s.vr[name]], [1], [slope(t)])
            s.slave.doStep(t, h)
        return get(s, out)
    finally:
        s.close()


def test_3d_beam_ramped_load_with_derivatives(fmus):
    """A tip load rising linearly over 20 ms: with its slope a 5 ms coupling step gives the
    response of a 0.25 ms step; without it the 5 ms zero-order hold lags."""
    f_end, t_ramp = 200.0, 0.02

    def load(t):
        return f_end * min(t / t_ramp, 1.0)

    def slope(t):
        return f_end / t_ramp if t < t_ramp - 1e-12 else 0.0

    out = ["tip.z"]
    args = ("load.fz", load, slope, 0.03, out)
    fine = ramp_run(fmus["cantilever3d"], 2.5e-4, True, *args)[0]
    fine_zoh = ramp_run(fmus["cantilever3d"], 2.5e-4, False, *args)[0]
    with_d = ramp_run(fmus["cantilever3d"], 5e-3, True, *args)[0]
    without = ramp_run(fmus["cantilever3d"], 5e-3, False, *args)[0]
    assert abs(fine) > 1e-5, fine
    # piecewise-constant inputs converge to the interpolated signal as the step shrinks
    assert abs(fine_zoh - fine) < 0.1 * abs(without - fine), (fine, fine_zoh, without)
    assert abs(with_d - fine) < 0.2 * abs(without - fine), (fine, with_d, without)


def test_belt_drive_ramped_torque_with_derivatives(fmus):
    """A drive torque on a free pulley of the belt drive rising linearly: the pulley speed
    after a coarse coupling with the slope matches a fine coupling better than without."""
    t_end = 0.04

    def torque(t):
        return 2000.0 * t

    def slope(t):
        return 2000.0

    out = ["pulley1.omega", "pulley2.omega"]
    args = ("pulley1.torque_in", torque, slope, t_end, out)
    fmu = fmus["belt_drive_inertia"]
    fine = ramp_run(fmu, 1e-3, True, *args)
    with_d = ramp_run(fmu, 1e-2, True, *args)
    without = ramp_run(fmu, 1e-2, False, *args)
    assert abs(fine[0]) > 0.1, fine
    assert abs(with_d[0] - fine[0]) < 0.2 * abs(without[0] - fine[0]), (fine, with_d, without)


def test_driven_pulley_angle_with_derivatives(fmus):
    """A driven pulley accelerating uniformly, angle = a t²/2: with the angle's first and second
    derivatives the FMU follows the parabola inside a 10 ms step (its belt speed then matches a
    1 ms coupling); with angle and speed only it extrapolates linearly."""
    alpha, t_end = 400.0, 0.03

    def run(h, derivatives):
        s = Session(fmus["belt_drive"])
        try:
            init(s)
            for k in range(int(round(t_end / h))):
                t = k * h
                vrs = [s.vr["pulley1.angle"], s.vr["pulley1.omega"]]
                s.slave.setReal(vrs, [0.5 * alpha * t * t, alpha * t])
                if derivatives:
                    s.slave.setRealInputDerivatives(
                        [s.vr["pulley1.angle"], s.vr["pulley1.angle"], s.vr["pulley1.omega"]],
                        [1, 2, 1], [alpha * t, alpha, alpha])
                s.slave.doStep(t, h)
            return get(s, ["belt.speed", "pulley1.torque"])
        finally:
            s.close()

    fine = run(1e-3, True)
    with_d = run(1e-2, True)
    without = run(1e-2, False)
    assert fine[0] > 0.5, fine
    assert abs(with_d[0] - fine[0]) < 0.2 * abs(without[0] - fine[0]), (fine, with_d, without)


def derivative_vs_difference(fmu, names, t_run, h_run, dt, start=None):
    """Output derivatives at t_run + dt against the central difference of the outputs at t_run
    and t_run + 2 dt."""
    s = Session(fmu)
    try:
        init(s, **(start or {}))
        t = 0.0
        for k in range(int(round(t_run / h_run))):
            s.slave.doStep(t, h_run)
            t += h_run
        vrs = [s.vr[n] for n in names]
        ym = get(s, names)
        s.slave.doStep(t, dt)
        d = s.slave.getRealOutputDerivatives(vrs, [1] * len(names))
        s.slave.doStep(t + dt, dt)
        yp = get(s, names)
        return {n: (d[i], (yp[i] - ym[i]) / (2 * dt)) for i, n in enumerate(names)}
    finally:
        s.close()


def test_3d_beam_output_derivatives_match_differences(fmus):
    names = ["tip.x", "tip.z", "tip.ry", "tip.tz"]
    r = derivative_vs_difference(fmus["cantilever3d"], names, 0.01, 1e-3, 1e-5,
                                 start={"load.fz": 500.0, "load.mx": 20.0,
                                        "solver.max_step": 1e-5})
    for n, (d, fd) in r.items():
        assert abs(fd) > 0.0, (n, d, fd)
        assert abs(d - fd) < 0.02 * abs(fd), (n, d, fd)


def test_belt_output_derivatives_match_differences(fmus):
    names = ["pulley2.angle", "pulley2.omega", "belt.point[1].x", "belt.point[7].y",
             "belt.speed", "pulley1.omega", "energy.kinetic", "energy.input_work"]
    r = derivative_vs_difference(fmus["belt_drive_inertia"], names, 0.02, 1e-3, 1e-4,
                                 start={"pulley1.torque_in": 20.0, "solver.max_step": 1e-4})
    for n, (d, fd) in r.items():
        assert abs(fd) > 0.0, (n, d, fd)
        assert abs(d - fd) < 0.05 * abs(fd), (n, d, fd)
