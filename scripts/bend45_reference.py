"""Independent reference for the Bathe-Bolourchi 45-degree bend (scenes/bend45.toml): the static
Simo-Reissner (geometrically exact, shear-deformable) rod equations solved by shooting, without
finite elements.

Rod: arc of radius R = 100 over 45 degrees from the origin along +x, turning about +z (initial
body curvature K0 = [0, 0, 1/R]); clamped at s = 0; dead tip force F = (0, 0, 600).
Equilibrium with a tip force only: spatial section force n(s) = F, moment m(s) = (x(L) - x(s)) x F.
Constitutive: Gamma = e1 + C_N^-1 Lam^T n, K = K0 + C_M^-1 Lam^T m, C_N = diag(EA, kGA, kGA),
C_M = diag(GJ, EI, EI). Kinematics: x' = Lam Gamma, Lam' = Lam K~ (RK4 along s).
The unknown tip position x(L) is found by Newton iterations on x(L; guess) = guess, with the load
applied in a few increments.

usage: python scripts/bend45_reference.py   (about half a minute)
"""
import numpy as np

R = 100.0
L = R * np.pi / 4
EA, GA, EI, GJ = 1.0e7, 4.16667e6, 8.33333e5, 8.33333e5
CN_INV = 1.0 / np.array([EA, GA, GA])
CM_INV = 1.0 / np.array([GJ, EI, EI])
K0 = np.array([0.0, 0.0, 1.0 / R])


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def tip(guess, force, steps=400):
    """x(L) from integrating the rod from the clamp with the moment of `force` about `guess`."""
    h = L / steps
    x, lam = np.zeros(3), np.eye(3)

    def rhs(x, lam):
        m = np.cross(guess - x, force)
        gamma = np.array([1.0, 0.0, 0.0]) + CN_INV * (lam.T @ force)
        kappa = K0 + CM_INV * (lam.T @ m)
        return lam @ gamma, lam @ skew(kappa)

    for _ in range(steps):
        k1 = rhs(x, lam)
        k2 = rhs(x + h / 2 * k1[0], lam + h / 2 * k1[1])
        k3 = rhs(x + h / 2 * k2[0], lam + h / 2 * k2[1])
        k4 = rhs(x + h * k3[0], lam + h * k3[1])
        x = x + h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        lam = lam + h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        u, _, vt = np.linalg.svd(lam)
        lam = u @ vt
    return x


def solve(force=np.array([0.0, 0.0, 600.0]), increments=5, steps=400):
    x0 = np.array([R * np.sin(np.pi / 4), R * (1 - np.cos(np.pi / 4)), 0.0])
    guess = x0.copy()
    for lam in np.linspace(1.0 / increments, 1.0, increments):
        f = force * lam
        for _ in range(30):
            r = tip(guess, f, steps) - guess
            if np.linalg.norm(r) < 1e-10:
                break
            jac = np.empty((3, 3))
            for j in range(3):
                d = np.zeros(3)
                d[j] = 1e-6
                jac[:, j] = (tip(guess + d, f, steps) - guess - d - r) / 1e-6
            guess = guess - np.linalg.solve(jac, r)
    return guess - x0


if __name__ == "__main__":
    for steps in (200, 400):
        u = solve(steps=steps)
        print(f"RK4 with {steps} steps: tip displacement ({u[0]:.5f}, {u[1]:.5f}, {u[2]:.5f})")
