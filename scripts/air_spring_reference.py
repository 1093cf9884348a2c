"""Independent reference for the rolling-lobe air spring of issue 11 (level-2 membrane checks):
the static axisymmetric membrane equations solved by shooting, without finite elements.

Geometry (issue 11 item 7; heights z above the piston base, radii r from the axis):
  piston: cylinder of radius r_p from z = 0 to its top at z = h_p;
  top plate at z = h; the sleeve's top bead is clamped on it at radius r_b;
  sleeve: stress-free cylinder of radius R0 and length L, material coordinate S from 0 (top bead)
  to L (lower bead, clamped at the piston's top edge (r_p, h_p)). From the top bead the sleeve runs
  down as the outer wall, turns in the rolling lobe and runs up along the piston's cylindrical wall
  (frictionless contact, r = r_p) to the clamp.

Wall (per reference area, no bending): n_plies cord plies at +-alpha0 from the meridian,
  W_c = K_c (lam_c - 1)^2 / 2 per ply,  lam_c^2 = lam_s^2 cos^2 alpha0 + lam_t^2 sin^2 alpha0
(both plies have the same cord stretch in axisymmetry, no twist), linear in tension and compression,
plus an isotropic matrix with nu = 0 written in Biot strains (the chosen form):
  W_m = (E t / 2) [(lam_s - 1)^2 + (lam_t - 1)^2],
lam_s = ds/dS (meridional stretch), lam_t = r/R0 (hoop stretch).

Membrane forces per current length (virtual work dU = int (N_s d eps_s + N_t d eps_t) da with
d eps = d lam / lam and da = lam_s lam_t dA):
  N_s = W_s / lam_t,   N_t = W_t / lam_s     (W_s = dW/dlam_s, W_t = dW/dlam_t).

Equilibrium of a ring ds of the meridian (r(s), z(s)), tangent t = (cos phi, sin phi), gauge
pressure p (follower, acting from the gas side, normal n = (-sin phi, cos phi) for the orientation
used here: S increasing from the top bead, gas on the left of the meridian):
  d(r N_s t)/ds - N_t e_r + r p n = 0, i.e.
  d(r N_s)/ds = N_t cos phi,   r N_s dphi/ds + N_t sin phi + r p = 0                      (1)
(the standard equations of a shell of revolution in membrane state, e.g. Timoshenko &
Woinowsky-Krieger, Theory of Plates and Shells, ch. 14, with the pressure as a follower load).
Axial first integral of (1): r N_s sin phi + p r^2 / 2 = C, the force on the top plate
  F = p pi r_b^2 + 2 pi r_b N_s sin phi (S = 0) = 2 pi C,
so F = p pi r_h^2 at any point where the meridian is horizontal (A_e = pi r_h^2, exact).

Unknowns integrated in S: r, z, phi, lam_s. Since Q = r N_s = R0 W_s(lam_s, lam_t), the first
equation of (1), dQ/dS = W_t cos phi, gives lam_s explicitly:
  dr/dS = lam_s cos phi,  dz/dS = lam_s sin phi,
  dphi/dS = -(p r lam_s + W_t sin phi) / (R0 W_s),
  dlam_s/dS = cos phi (W_t - lam_s W_st) / (R0 W_ss).
Contact part on the piston (r = r_p, phi = -3 pi / 2, frictionless): the tangential equation gives
r N_s = const, with r fixed lam_t = r_p/R0 and hence lam_s are constant too; the contact pressure
is p + N_t / r_p. At the departure point S_d the meridian leaves the piston tangentially (the
departure point is free, so no line load: the string-over-a-pulley condition) with the contact
part's lam_s. The shooting unknowns are S_d and lam_d = lam_s on the contact part: the contact part
gives the departure height z_d = h_p - lam_d (L - S_d); the free part is integrated from the
departure point back to the top bead, where r = r_b, z = h must hold (Newton with a finite-difference
Jacobian). Then F = 2 pi R0 W_s(lam_d, r_p/R0) + p pi r_p^2 (first integral at the departure point).

Integration: Dormand-Prince 5(4) with step control (Hairer, Norsett & Wanner, Solving ODEs I,
sec. II.4 and II.5); the gas volume V = -int pi r^2 dz (S from 0 to L, plate and piston top add
nothing) and the strain energy U = int 2 pi R0 W dS are integrated along.

Sign conventions: h is the height of the top plate above the piston base (extension positive);
F > 0 pushes the top plate up; A_e = F / p_g; A_v = dV/dh (= -dV/dz with z = compression, > 0);
k = -dF/dh (= dF/dz, > 0 for a stiffening spring); dA_e/dz = -dA_e/dh.

usage: python scripts/air_spring_reference.py [--out tests/data/air_spring_reference.json]
                                              [--figure docs/air_spring_reference.png]
"""
import argparse
import dataclasses
import json
import math
import pathlib
import sys

import numpy as np

P_AMBIENT = 101325.0  # [Pa], issue 11 item 7
ROOT = pathlib.Path(__file__).resolve().parents[1]


@dataclasses.dataclass(frozen=True)
class Spring:
    """A rolling-lobe spring: geometry [m], cord angle [deg from the meridian], stiffnesses [N/m]."""

    r_p: float = 0.100  # piston radius
    h_p: float = 0.15  # piston height (its top above its base)
    r_b: float = 0.140  # top bead radius
    R0: float = 0.125  # stress-free sleeve radius
    L: float = 0.300  # sleeve length
    alpha0_deg: float = 54.0  # cord angle from the meridian in the stress-free state
    n_plies: int = 2  # plies at +-alpha0
    K_c: float = 1.5e6  # cord stiffness per ply [N/m]
    Et: float = 2.0e4  # matrix stiffness E t [N/m]


DEFAULT = Spring()
SPRING_B = Spring(r_p=0.09, h_p=0.12, r_b=0.13, R0=0.115, L=0.26, alpha0_deg=50.0, K_c=1.0e6, Et=3.0e4)


class ShotFailure(Exception):
    """The integrated meridian left the range where the wall law is in tension or r > 0."""


def wall_law(spring):
    """Energy per reference area W [J/m^2] and its derivatives as functions of (lam_s, lam_t).

    Returns (W, dW) with dW(ls, lt) = (W_s, W_t, W_ss, W_st) [N/m]:
      W   = n K_c (lc - 1)^2 / 2 + Et/2 [(ls - 1)^2 + (lt - 1)^2],  lc^2 = ls^2 c2 + lt^2 s2,
      W_s = n K_c (1 - 1/lc) ls c2 + Et (ls - 1),   W_t = n K_c (1 - 1/lc) lt s2 + Et (lt - 1),
      W_ss = n K_c [c2 (1 - 1/lc) + ls^2 c2^2 / lc^3] + Et,   W_st = n K_c ls lt c2 s2 / lc^3.
    """
    a = math.radians(spring.alpha0_deg)
    c2, s2 = math.cos(a) ** 2, math.sin(a) ** 2
    nk, et = spring.n_plies * spring.K_c, spring.Et
    sqrt = math.sqrt

    def energy(ls, lt):
        lc = sqrt(ls * ls * c2 + lt * lt * s2)
        return 0.5 * nk * (lc - 1.0) ** 2 + 0.5 * et * ((ls - 1.0) ** 2 + (lt - 1.0) ** 2)

    def derivatives(ls, lt):
        lc = sqrt(ls * ls * c2 + lt * lt * s2)
        f = nk * (1.0 - 1.0 / lc)
        g = nk / (lc * lc * lc)
        return (
            f * ls * c2 + et * (ls - 1.0),
            f * lt * s2 + et * (lt - 1.0),
            f * c2 + g * ls * ls * c2 * c2 + et,
            g * ls * lt * c2 * s2,
        )

    return energy, derivatives


# Dormand-Prince 5(4) tableau (Hairer, Norsett & Wanner, Table 5.2 of ch. II).
_C = (0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0)
_A = (
    (),
    (1 / 5,),
    (3 / 40, 9 / 40),
    (44 / 45, -56 / 15, 32 / 9),
    (19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729),
    (9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656),
    (35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84),
)
_B = (35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0.0)
_E = (  # 5th minus 4th order weights
    35 / 384 - 5179 / 57600,
    0.0,
    500 / 1113 - 7571 / 16695,
    125 / 192 - 393 / 640,
    -2187 / 6784 + 92097 / 339200,
    11 / 84 - 187 / 2100,
    -1 / 40,
)


def _dopri_step(f, y, h, k1):
    """One Dormand-Prince step of size h from y with k1 = f(y): (y_new, k7 = f(y_new), error)."""
    ks = [k1]
    for i in range(1, 7):
        coef = [(h * a, k) for a, k in zip(_A[i], ks) if a != 0.0]
        yi = list(y)
        for ha, k in coef:
            yi = [u + ha * v for u, v in zip(yi, k)]
        ks.append(f(yi))
    err = [0.0] * len(y)
    for e, k in zip(_E, ks):
        if e != 0.0:
            he = h * e
            err = [u + he * v for u, v in zip(err, k)]
    return yi, ks[6], err  # stage 7 is evaluated at the 5th-order solution (FSAL)


def integrate(f, y0, t_end, tol, scale, stations=None, mesh=None):
    """Integrate y' = f(y) (autonomous) from t = 0 to t_end with step control.

    The error of the first len(scale) components, measured in units of tol * scale[i] (absolute),
    is kept below 1 per step; the step follows h_new = 0.9 h err^(-1/5) (Hairer et al. II.4).
    With `stations` (increasing values of t) the steps end on every station as well. With `mesh`
    (increasing fractions of t_end ending with 1) the steps are those, without control: the map
    from y0 and t_end to the result is then smooth (finite-difference Jacobians).
    Returns the list of accepted (t, y), including the start and the end.
    """
    t, y = 0.0, list(y0)
    k1 = f(y)
    out = [(t, y)]
    if mesh is not None:
        for frac in mesh:
            t_new = frac * t_end
            y, k1, _ = _dopri_step(f, y, t_new - t, k1)
            t = t_new
            out.append((t, y))
        return out
    targets = sorted(set([t for t in (stations or []) if 0.0 < t < t_end] + [t_end]))
    h = t_end / 50.0
    m = len(scale)
    for target in targets:
        while t < target:
            last = t + h >= target * (1.0 - 1e-14)
            step = target - t if last else h
            try:
                y_new, k7, err = _dopri_step(f, y, step, k1)
                e = max(abs(err[i]) / (tol * scale[i]) for i in range(m))
            except (ShotFailure, ValueError, ZeroDivisionError, OverflowError):
                e = float("inf")
            if e <= 1.0:
                t = target if last else t + step
                y, k1 = y_new, k7
                out.append((t, y))
                if last:
                    continue  # keep h: the truncated step says nothing about the next one
            if not math.isfinite(e):
                h = 0.25 * step
            else:
                h = step * min(4.0, max(0.2, 0.9 * max(e, 1e-10) ** -0.2))
            if h < 1e-12 * t_end:
                raise ShotFailure("step size underflow")
    return out


class Membrane:
    """The multiple-shooting problem of one spring at one height h [m] and gauge pressure p [Pa].

    wrap=True: the sleeve wraps the piston; the first two unknowns are the departure point S_d
    and the contact part's lam_s. wrap=False (the lobe has rolled up to the piston's top edge,
    no contact part): the free meridian ends at the clamp (r_p, h_p); the first two unknowns are
    the meridian angle phi_c and lam_s there (phi_c >= -3 pi/2, so that the sleeve stays outside
    the piston; phi_c = -3 pi/2 is the limit of the wrapped branch with S_d = L)."""

    def __init__(self, h, p_gauge, spring=DEFAULT, tol=1e-10, wrap=True):
        self.h, self.p, self.spring, self.tol, self.wrap = h, p_gauge, spring, tol, wrap
        self.energy, self.dW = wall_law(spring)
        sp = spring
        self.scale = (sp.L, sp.L, 1.0, 1.0)
        self.lt_contact = sp.r_p / sp.R0
        p, R0, dW, energy = p_gauge, sp.R0, self.dW, self.energy
        cos, sin, pi = math.cos, math.sin, math.pi

        def rhs_t(y):
            # d/dt with t = S_d - S (from the departure point back to the top bead)
            r, z, phi, ls = y[0], y[1], y[2], y[3]
            if r <= 0.0 or ls <= 0.0:
                raise ShotFailure("r or lam_s not positive")
            lt = r / R0
            w_s, w_t, w_ss, w_st = dW(ls, lt)
            if w_s <= 0.0 or w_ss <= 0.0:
                raise ShotFailure("meridional force not positive")
            c, s = cos(phi), sin(phi)
            z_S = ls * s
            return [
                -ls * c,
                -z_S,
                (p * r * ls + w_t * s) / (R0 * w_s),
                -c * (w_t - ls * w_st) / (R0 * w_ss),
                -pi * r * r * z_S,
                2.0 * pi * R0 * energy(ls, lt),
            ]

        self.rhs_t = rhs_t

    def departure_state(self, x0, x1):
        """State (r, z, phi, lam_s, V, U) at the lower end of the free part (t = 0): from the
        contact part's (S_d, lam_d) when wrapped, else at the clamp from (phi_c, lam_c)."""
        sp = self.spring
        if not self.wrap:
            return [sp.r_p, sp.h_p, x0, x1, 0.0, 0.0]
        z_d = sp.h_p - x1 * (sp.L - x0)
        return [sp.r_p, z_d, -1.5 * math.pi, x1, 0.0, 0.0]

    def free_length(self, x):
        """Material length of the free part [m]."""
        return x[0] if self.wrap else self.spring.L

    def segment(self, x, k, stations=None, mesh=None):
        """Accepted steps [(t, y)] of segment k (t from the segment's start) for the
        multiple-shooting unknowns x = (S_d, lam_d, y_1, ..., y_{K-1}), y_k = (r, z, phi, lam_s)
        at t_k = k S_d / K (t = S_d - S, material length from the departure point)."""
        if x[1] <= 0.0 or (self.wrap and not 0.0 < x[0] < self.spring.L):
            raise ShotFailure("departure point outside the sleeve")
        k_seg = (len(x) - 2) // 4 + 1
        length = self.free_length(x) / k_seg
        y0 = self.departure_state(x[0], x[1]) if k == 0 else [float(v) for v in x[4 * k - 2 : 4 * k + 2]] + [0.0, 0.0]
        st = None if stations is None else [t - k * length for t in stations]
        return integrate(self.rhs_t, y0, length, self.tol, self.scale, st, mesh)

    def segments(self, x, stations=None, meshes=None):
        """All segments of the free part (see `segment`), optionally on given meshes."""
        k_seg = (len(x) - 2) // 4 + 1
        return [self.segment(x, k, stations, None if meshes is None else meshes[k]) for k in range(k_seg)]

    def _residual_part(self, x, k, y_end):
        """Residual rows of segment k's end state: continuity with node k+1 or the top bead."""
        L = self.spring.L
        if 4 * k + 6 <= len(x):
            node = x[4 * k + 2 : 4 * k + 6]
            return [(y_end[0] - node[0]) / L, (y_end[1] - node[1]) / L, y_end[2] - node[2], y_end[3] - node[3]]
        return [(y_end[0] - self.spring.r_b) / L, (y_end[1] - self.h) / L]

    def residual(self, x, ends=None):
        """Continuity of (r, z, phi, lam_s) at the interior nodes and (r - r_b, z - h) at the top
        bead; lengths in units of L."""
        if ends is None:
            ends = [seg[-1][1] for seg in self.segments(x)]
        res = []
        for k, y in enumerate(ends):
            res += self._residual_part(x, k, y)
        return np.array(res)

    def jacobian(self, x, segs, fd=1e-7):
        """Forward-difference Jacobian of `residual` at x, whose segments `segs` were integrated
        with step control: the perturbed segments replay the same steps (as fractions of the
        segment length), so that the differences are free of step-selection noise. A node's
        unknowns enter only its own segment and the previous segment's continuity rows (the latter
        exactly: -1/scale on the diagonal)."""
        n = len(x)
        k_seg = (n - 2) // 4 + 1
        meshes = [[t / seg[-1][0] for t, _ in seg[1:]] for seg in segs]
        res0 = self.residual(x, [seg[-1][1] for seg in segs])
        jac = np.zeros((n, n))
        for j in range(n):
            xp = np.array(x, dtype=float)
            dx = fd * max(1.0, abs(x[j]))
            xp[j] += dx
            if j == 0:
                ends = [seg[-1][1] for seg in self.segments(xp, meshes=meshes)]
                jac[:, 0] = (self.residual(xp, ends) - res0) / dx
                continue
            k = 0 if j == 1 else (j - 2) // 4 + 1  # the segment that starts from this unknown
            rows = slice(4 * k, 4 * k + (4 if k < k_seg - 1 else 2))
            y_end = self.segment(xp, k, mesh=meshes[k])[-1][1]
            jac[rows, j] = (np.array(self._residual_part(xp, k, y_end)) - res0[rows]) / dx
            if j >= 2:  # continuity rows of the previous segment: -(node) / scale
                c = (j - 2) % 4
                jac[4 * (k - 1) + c, j] = -1.0 / self.spring.L if c < 2 else -1.0
        return jac

    def newton(self, x0, jac=None, max_iter=60, fd=1e-7, atol=1e-12, accept=1e-11):
        """Damped Newton on the multiple-shooting unknowns, Jacobian by forward differences.

        A Jacobian (given, e.g. from a neighbouring solution, or from an earlier iteration) is
        reused while it reduces the residual at least fivefold per step, and recomputed otherwise.
        Stops when the largest residual is below `atol`, or when it is below `accept` and a fresh
        Newton step no longer reduces it (the floor set by the integration's step selection).
        The last Jacobian is left in `self.jac`; `self.iterations` counts the steps taken."""
        x = np.array(x0, dtype=float)

        def evaluate(x):
            segs = self.segments(x)
            return self.residual(x, [seg[-1][1] for seg in segs]), segs

        res, segs = evaluate(x)
        fresh = jac is None
        if fresh:
            jac = self.jacobian(x, segs, fd)
        self.iterations = 0
        for _ in range(max_iter):
            norm = np.max(np.abs(res))
            if norm < atol:
                break
            self.iterations += 1
            step = -np.linalg.solve(jac, res)
            lam = 1.0
            while True:
                trial = x + lam * step
                try:
                    res_trial, segs_trial = evaluate(trial)
                    ok = np.max(np.abs(res_trial)) < (0.2 * norm if not fresh else norm)
                except ShotFailure:
                    ok = False
                if ok:
                    break
                if not fresh:  # a stale Jacobian: recompute it and try again
                    jac, fresh = self.jacobian(x, segs, fd), True
                    break
                if norm < accept:
                    self.jac = jac
                    return x
                lam *= 0.5
                if lam < 1e-4:
                    raise ShotFailure(f"line search failed at residual {norm:.3e}")
            if ok:
                x, res, segs, fresh = trial, res_trial, segs_trial, False
        else:
            if np.max(np.abs(res)) > accept:
                raise ShotFailure(f"Newton did not converge: residual {np.max(np.abs(res)):.3e}")
        self.jac = jac
        return x


def stretch_for_force(spring, q, lam_t):
    """lam_s with R0 W_s(lam_s, lam_t) = q [N/m] (meridional force times radius), by bisection."""
    _, dW = wall_law(spring)
    lo, hi = 0.2, 5.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if spring.R0 * dW(mid, lam_t)[0] < q:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def initial_guess(h, p_gauge, spring, k_seg=8):
    """(x, wrap): multiple-shooting unknowns of a half-torus lobe of radius a = (r_b - r_p)/2
    between the piston and a vertical outer wall at r_b, with the meridional force of a
    zero-hoop-stress lobe (r_h^2 = (r_p^2 + r_b^2)/2, so r N_s = p (r_b^2 - r_p^2)/4 at both ends)
    and lam_s from the wall law (the sleeve pantographs: lam_s depends strongly on the radius).
    When the lobe would lie above the piston's top, the guess is of the unwrapped branch."""
    q = 0.25 * p_gauge * (spring.r_b**2 - spring.r_p**2)
    lam_d = stretch_for_force(spring, q, spring.r_p / spring.R0)
    lam_o = stretch_for_force(spring, q, spring.r_b / spring.R0)
    lam_m = 0.5 * (lam_d + lam_o)
    a = 0.5 * (spring.r_b - spring.r_p)
    # material length: (h - z_c)/lam_o + pi a/lam_m + (h_p - z_c)/lam_d = L
    z_c = (h / lam_o + math.pi * a / lam_m + spring.h_p / lam_d - spring.L) / (1 / lam_o + 1 / lam_d)
    s_lobe = math.pi * a / lam_m
    wrap = z_c < spring.h_p - 0.002
    if wrap:
        s_free = (h - z_c) / lam_o + s_lobe
        x = [s_free, lam_d]
    else:
        z_c, s_free = spring.h_p, spring.L
        x = [-1.5 * math.pi + 0.02, lam_d]
    for k in range(1, k_seg):
        t = k * s_free / k_seg  # material length from the lower end of the free part
        if t < s_lobe:
            phi = -1.5 * math.pi + math.pi * t / s_lobe
            r = spring.r_p + a + a * math.cos(phi + math.pi / 2)
            x += [r, z_c + a * math.sin(phi + math.pi / 2), phi, stretch_for_force(spring, q, r / spring.R0)]
        else:
            x += [spring.r_b, z_c + (t - s_lobe) * lam_o, -0.5 * math.pi, lam_o]
    return x, wrap


def _locate(f, t0, y0, t1, target):
    """(t, y) where y[2] (the meridian angle) = target inside the accepted step t0 -> t1, by Newton
    on the length of one Dormand-Prince step from (t0, y0) (as accurate as the step itself)."""
    y1 = _dopri_step(f, y0, t1 - t0, f(y0))[0]
    d = (t1 - t0) * (target - y0[2]) / (y1[2] - y0[2])
    for _ in range(30):
        y = _dopri_step(f, y0, d, f(y0))[0] if d != 0.0 else list(y0)
        g = y[2] - target
        d_new = d - g / f(y)[2]
        if abs(d_new - d) < 1e-15 * (t1 - t0) + 1e-300:
            d = d_new
            break
        d = d_new
    y = _dopri_step(f, y0, d, f(y0))[0] if d != 0.0 else list(y0)
    return t0 + d, y


def _crossings(m, x, segs, target):
    """All points of the free part where the meridian angle passes `target`, as (t, y) with t the
    material length from the lower end of the free part."""
    out = []
    length = m.free_length(x) / len(segs)
    for k, seg in enumerate(segs):
        for (t0, y0), (t1, y1) in zip(seg[:-1], seg[1:]):
            if (y0[2] - target) * (y1[2] - target) < 0.0 or (y1[2] == target):
                t, y = _locate(m.rhs_t, t0, y0, t1, target)
                out.append((k * length + t, y))
    return out


def _result(m, x, n_shape=None):
    """The dict of `solve` from a converged Membrane m at unknowns x."""
    sp, p = m.spring, m.p
    segs = m.segments(x)
    k_seg = len(segs)
    s_free = m.free_length(x)
    lt_p = sp.r_p / sp.R0
    lam_low = x[1]
    q_low = sp.R0 * m.dW(lam_low, lt_p)[0]  # r N_s at the lower end of the free part
    sin_low = 1.0 if m.wrap else math.sin(x[0])
    c_int = q_low * sin_low + 0.5 * p * sp.r_p**2  # first integral r N_s sin phi + p r^2/2
    F = 2.0 * math.pi * c_int
    V = sum(seg[-1][1][4] for seg in segs)
    U = sum(seg[-1][1][5] for seg in segs)
    z_low = m.departure_state(x[0], x[1])[1]
    if m.wrap:  # contact part: r = r_p, constant lam_s, from z_d up to h_p
        V -= math.pi * sp.r_p**2 * (sp.h_p - z_low)
        U += 2.0 * math.pi * sp.R0 * m.energy(lam_low, lt_p) * (sp.L - s_free)
    horizontal = _crossings(m, x, segs, -math.pi)
    vertical = _crossings(m, x, segs, -0.5 * math.pi)
    r_h = horizontal[0][1][0] if horizontal else None
    lobe = max([(y[0], y[1]) for _, y in vertical] + [(sp.r_b, m.h)])
    # the meridian: free part at the accepted steps (or at n_shape stations over the sleeve)
    if n_shape:
        s_all = np.linspace(0.0, sp.L, n_shape)
        stations = sorted(s_free - s for s in s_all if s < s_free)
        segs_out = m.segments(x, stations=stations)
        keep = set(round(t, 13) for t in stations) | {0.0, round(s_free, 13)}
    else:
        segs_out, keep = segs, None
    length = s_free / k_seg
    pts = []
    for k, seg in enumerate(segs_out):
        for t, y in seg[(1 if k else 0) :]:
            if keep is None or round(k * length + t, 13) in keep:
                pts.append((s_free - (k * length + t), y[0], y[1], y[2], y[3]))
    pts.sort()
    if m.wrap:
        s_contact = [s for s in np.linspace(0.0, sp.L, n_shape)[1:] if s > s_free] if n_shape else [sp.L]
        for s in s_contact:
            pts.append((s, sp.r_p, z_low + lam_low * (s - s_free), -1.5 * math.pi, lam_low))
    S, r, z, phi, ls = (np.array(c) for c in zip(*pts))
    dW = np.array([m.dW(a, b / sp.R0) for a, b in zip(ls, r)])
    n_s, n_t = dW[:, 0] / (r / sp.R0), dW[:, 1] / ls
    warnings = []
    below = z < sp.h_p - 1e-12
    if np.any(r[below] < sp.r_p - 1e-9):
        warnings.append("the free meridian enters the piston")
    if np.any(z > m.h + 1e-9):
        warnings.append("the free meridian rises above the top plate")
    contact_pressure = p + m.dW(lam_low, lt_p)[1] / lam_low / sp.r_p if m.wrap else None
    if contact_pressure is not None and contact_pressure < 0.0:
        warnings.append("negative contact pressure on the piston")
    if not m.wrap and x[0] < -1.5 * math.pi - 1e-12:
        warnings.append("unwrapped branch with the sleeve entering the piston")
    return {
        "h": m.h,
        "p_gauge": p,
        "F": F,
        "V": V,
        "A_e": F / p if p else None,
        "U": U,
        "r_h": r_h,
        "z_h": horizontal[0][1][1] if horizontal else None,
        "lobe_radius": lobe[0],
        "lobe_height": lobe[1],
        "wrap": m.wrap,
        "departure_height": z_low,  # wrapped: where the sleeve leaves the piston; else h_p
        "departure_S": s_free,
        "lam_s_contact": lam_low if m.wrap else None,
        "lower_angle": -1.5 * math.pi if m.wrap else float(x[0]),
        "contact_pressure": contact_pressure,
        "steps": sum(len(seg) - 1 for seg in segs),
        "warnings": warnings,
        "shape": {"S": S, "r": r, "z": z, "phi": phi, "lam_s": ls, "N_s": n_s, "N_theta": n_t},
        "x": x,
        "jac": m.jac,
    }


def _switch_branch(x, wrap, spring):
    """Unknowns of the other branch near the transition (S_d = L <-> phi_c = -3 pi/2)."""
    x = np.array(x, dtype=float)
    x[0] = -1.5 * math.pi + 1e-6 if wrap else spring.L * (1.0 - 1e-6)
    return x, not wrap


def solve(h, p_gauge, spring=DEFAULT, start=None, tol=1e-10, n_shape=None):
    """Static equilibrium of the membrane at top-plate height h [m] and gauge pressure p_gauge [Pa].

    Returns a dict: F [N] (force on the top plate, > 0 pushes it up), V [m^3] (gas volume between
    top plate, sleeve and piston top), A_e = F/p_g [m^2], U [J] (strain energy of the sleeve),
    r_h, z_h [m] (point where the meridian is horizontal, A_e = pi r_h^2), lobe_radius,
    lobe_height [m] (largest radius of the outer wall), wrap (the sleeve wraps the piston),
    departure_height [m] (where it leaves the piston), departure_S [m] (material coordinate of
    that point), lam_s_contact, contact_pressure [Pa] on the piston, lower_angle [rad],
    warnings (geometric admissibility), shape: arrays S, r, z, phi, lam_s, N_s, N_theta [N/m]
    (S from the top bead); x, jac (the shooting unknowns and Jacobian: pass the dict as `start`
    to a neighbouring solve). n_shape: the meridian at that many equally spaced S instead of at
    the integration steps.
    """
    guesses = []
    if start is not None:
        guesses.append((start["x"], start["wrap"], start.get("jac")))
        guesses.append(_switch_branch(start["x"], start["wrap"], spring) + (None,))
    x0, wrap0 = initial_guess(h, p_gauge, spring)
    guesses.append((x0, wrap0, None))
    guesses.append(_switch_branch(x0, wrap0, spring) + (None,))
    failures = []
    for x0, wrap, jac in guesses:
        m = Membrane(h, p_gauge, spring, tol, wrap)
        try:
            x = m.newton(x0, jac)
        except (ShotFailure, np.linalg.LinAlgError) as e:
            failures.append(str(e))
            continue
        if not wrap and x[0] < -1.5 * math.pi - 1e-9:
            failures.append("unwrapped solution enters the piston")
            continue
        return _result(m, x, n_shape)
    raise ShotFailure(f"no equilibrium found at h = {h}, p = {p_gauge}: {failures}")


def _plain(v):
    """A JSON-friendly scalar (numpy floats to float)."""
    return v if v is None or isinstance(v, (bool, str)) else float(v)


def characteristic(heights, p_gauge, spring=DEFAULT, dh=1e-4, dp_rel=1e-4, tol=1e-10, compliance=True):
    """Constant-pressure characteristic: for each height h [m] at gauge pressure p_gauge [Pa]:
    F [N], V [m^3], p_gauge [Pa], A_e = F/p_g [m^2], A_v = dV/dh [m^2], k = -dF/dh [N/m],
    dV_dp [m^3/Pa] (volume compliance at fixed h), U [J], dU_dh [N], dAe_dh [m], r_h, lobe_radius,
    departure_height [m], wrap. Derivatives by central differences (dh [m], dp = dp_rel p_gauge);
    compliance=False leaves dV_dp out (None)."""
    cols = {key: [] for key in ("h p_gauge F V A_e A_v k dV_dp U dU_dh dAe_dh r_h lobe_radius departure_height wrap").split()}
    prev = None
    dp = dp_rel * p_gauge
    for h in heights:
        res = solve(h, p_gauge, spring, start=prev, tol=tol)
        up, dn = (solve(h + s * dh, p_gauge, spring, start=res, tol=tol) for s in (1, -1))
        if compliance:
            pu, pd = (solve(h, p_gauge + s * dp, spring, start=res, tol=tol) for s in (1, -1))
        row = {
            "h": h,
            "p_gauge": p_gauge,
            "A_v": (up["V"] - dn["V"]) / (2 * dh),
            "k": -(up["F"] - dn["F"]) / (2 * dh),
            "dV_dp": (pu["V"] - pd["V"]) / (2 * dp) if compliance else None,
            "dU_dh": (up["U"] - dn["U"]) / (2 * dh),
            "dAe_dh": (up["A_e"] - dn["A_e"]) / (2 * dh),
        }
        for key in cols:
            cols[key].append(_plain(row[key] if key in row else res[key]))
        prev = res
    return cols


def closed_pressure(h, n, gas_const, spring=DEFAULT, start=None, tol=1e-10):
    """Equilibrium with a fixed gas mass: p_abs V^n = gas_const (polytropic); secant iteration on
    the gauge pressure, each iterate a membrane solution at fixed pressure. Returns solve's dict."""
    p_prev = start["p_gauge"] if start is not None else 5e5
    res = solve(h, p_prev, spring, start=start, tol=tol)

    def g(r):  # log of the gas law residual
        return math.log(r["p_gauge"] + P_AMBIENT) + n * math.log(r["V"]) - math.log(gas_const)

    g_prev = g(res)
    p_new = (gas_const / res["V"] ** n) - P_AMBIENT  # fixed-point step at the current volume
    for _ in range(50):
        new = solve(h, p_new, spring, start=res, tol=tol)
        g_new = g(new)
        if abs(p_new - p_prev) < 1e-10 * (p_new + P_AMBIENT) or g_new == 0.0:
            return new
        p_prev, p_new = p_new, p_new - g_new * (p_new - p_prev) / (g_new - g_prev)
        g_prev, res = g_new, new
    raise ShotFailure(f"closed-gas pressure did not converge at h = {h}")


def closed(heights, design=(0.25, 5e5), n=1.4, spring=DEFAULT, dh=1e-4, tol=1e-10):
    """Closed-gas characteristic: fixed gas mass, polytropic p_abs V^n = const through the design
    state (h [m], gauge pressure [Pa]). For each height: F [N], V [m^3], p_gauge [Pa], A_e [m^2],
    A_v = dV/dh and k = -dF/dh along the closed-gas path, dAe_dh [m] along the path, and the
    stiffness of the exact identity k_identity = n p_abs A_e A_v / V - p_g dA_e/dh and of the
    usual form k_Ae2 = n p_abs A_e^2 / V - p_g dA_e/dh (dA_e/dz = -dA_e/dh)."""
    d = solve(design[0], design[1], spring, tol=tol)
    gas_const = (design[1] + P_AMBIENT) * d["V"] ** n
    keys = "h p_gauge F V A_e A_v k dAe_dh k_identity k_Ae2 r_h lobe_radius departure_height wrap"
    cols = {key: [] for key in keys.split()}
    prev = d
    for h in heights:
        res = closed_pressure(h, n, gas_const, spring, prev, tol)
        up, dn = (closed_pressure(h + s * dh, n, gas_const, spring, res, tol) for s in (1, -1))
        p_abs = res["p_gauge"] + P_AMBIENT
        a_v = (up["V"] - dn["V"]) / (2 * dh)
        dae = (up["A_e"] - dn["A_e"]) / (2 * dh)
        row = {
            "A_v": a_v,
            "k": -(up["F"] - dn["F"]) / (2 * dh),
            "dAe_dh": dae,
            "k_identity": n * p_abs * res["A_e"] * a_v / res["V"] - res["p_gauge"] * dae,
            "k_Ae2": n * p_abs * res["A_e"] ** 2 / res["V"] - res["p_gauge"] * dae,
        }
        for key in cols:
            cols[key].append(_plain(row[key] if key in row else res[key]))
        prev = res
    return cols


# ---------------------------------------------------------------------------------------------
# Convoluted (single or double bellows) spring: the same membrane equations between two bead
# plates, the girdle ring pinning the radius at mid-length (issue 11 item 2, second geometry).
#
# Geometry (heights z above the bottom plate): the sleeve (stress-free cylinder R0, length L) is
# clamped at the top bead (r_b, h) and the bottom bead (r_b, 0) (equal bead radii); with two
# convolutions a rigid girdle ring at S = L/2 pins r = r_g and is free along the axis. Both
# plates are flat frictionless obstacles: where a lobe overhangs its bead it lies on the plate
# (phi = 0 from the top bead outwards), and leaves it tangentially (no line load at a free
# departure point, as on the piston).
#
# Symmetry: with equal bead radii (and the girdle at mid-length) the equilibrium is symmetric
# about z = h/2, so only the upper half S in [0, L/2] is integrated, from the top bead down:
#   dr/dS = lam_s cos phi, dz/dS = lam_s sin phi, dphi/dS = -(p r lam_s + W_t sin phi)/(R0 W_s),
#   dlam_s/dS = cos phi (W_t - lam_s W_st)/(R0 W_ss)                 (equations (1) above),
# on the plate (phi = 0, z = h): dr/dS = lam_s, the same dlam_s/dS, contact pressure = p.
# Unknowns: (phi_0, q_0) at the bead, or (S_d, q_0) (q_0 = r N_s there) when the sleeve lies on the plate up to
# the departure point S_d. Conditions at S = L/2: two convolutions: r = r_g, z = h/2 (the girdle's
# height is free, symmetry puts it at mid-height); one convolution: z = h/2, phi = -pi/2
# (vertical tangent at the crest, the mirror plane).
# Force: the first integral r N_s sin phi + p r^2/2 = C is constant along the free meridian and
# across the axially free girdle (it only takes a radial load), so F = 2 pi C: at the top bead
# without contact, F = p pi r_d^2 at the departure point from the plate (A_e = pi r_h^2 there,
# the horizontal-tangent point nearest the top). Volume V = 2 (-int pi r^2 dz) over the half.
# ---------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Convoluted:
    """A convoluted spring: bead radius (top = bottom), girdle radius [m] (None: one
    convolution), sleeve R0, L [m], cord angle [deg from the meridian], stiffnesses [N/m]."""

    r_b: float = 0.115
    r_g: float = 0.110
    R0: float = 0.150
    L: float = 0.340
    alpha0_deg: float = 54.0
    n_plies: int = 2
    K_c: float = 1.5e6
    Et: float = 2.0e4


CONVOLUTED = Convoluted()


class ConvolutedShot:
    """Shooting problem of the upper half of a convoluted spring at height h [m], gauge p [Pa].
    contact=False: unknowns (phi_0, q_0) at the top bead (q_0 = r N_s [N/m]); contact=True: (S_d, q_0), the sleeve
    on the top plate from the bead out to S_d."""

    def __init__(self, h, p_gauge, spring=CONVOLUTED, tol=1e-11, contact=False):
        self.h, self.p, self.spring, self.tol, self.contact = h, p_gauge, spring, tol, contact
        self.energy, self.dW = wall_law(spring)
        sp = spring
        self.scale = (sp.L, sp.L, 1.0, 1.0)
        R0, dW, energy, p = sp.R0, self.dW, self.energy, p_gauge
        cos, sin, pi = math.cos, math.sin, math.pi

        def free(y):
            r, z, phi, ls = y[0], y[1], y[2], y[3]
            if r <= 0.0 or ls <= 0.0:
                raise ShotFailure("r or lam_s not positive")
            lt = r / R0
            w_s, w_t, w_ss, w_st = dW(ls, lt)
            if w_s <= 0.0 or w_ss <= 0.0:
                raise ShotFailure("meridional force not positive")
            c, s_ = cos(phi), sin(phi)
            z_S = ls * s_
            return [ls * c, z_S, -(p * r * ls + w_t * s_) / (R0 * w_s), c * (w_t - ls * w_st) / (R0 * w_ss),
                    -pi * r * r * z_S, 2.0 * pi * R0 * energy(ls, lt)]

        def flat(y):
            r, ls = y[0], y[3]
            if r <= 0.0 or ls <= 0.0:
                raise ShotFailure("r or lam_s not positive")
            lt = r / R0
            w_s, w_t, w_ss, w_st = dW(ls, lt)
            if w_ss <= 0.0:
                raise ShotFailure("wall law not convex")
            return [ls, 0.0, 0.0, (w_t - ls * w_st) / (R0 * w_ss), 0.0, 2.0 * pi * R0 * energy(ls, lt)]

        self.free, self.flat = free, flat

    def shoot(self, x, meshes=None):
        """Segments [(t, y)] of the flat part (contact) and the free part up to S = L/2."""
        sp, half = self.spring, 0.5 * self.spring.L
        # x[1] is the meridional force r N_s = R0 W_s at the bead [N/m] (lam_0 from the wall law:
        # near the bead the hoop is compressed and lam_0 a poor unknown, W_s being steep there)
        if x[1] <= 0.0:
            raise ShotFailure("no meridional tension at the bead")
        lam0 = stretch_for_force(sp, x[1], sp.r_b / sp.R0)
        y0 = [sp.r_b, self.h, 0.0 if self.contact else x[0], lam0, 0.0, 0.0]
        segs = []
        if self.contact:
            if not 0.0 < x[0] < half:
                raise ShotFailure("departure point outside the half sleeve")
            seg = integrate(self.flat, y0, x[0], self.tol, self.scale, mesh=None if meshes is None else meshes[0])
            segs.append(seg)
            y0 = list(seg[-1][1])
        free_len = half - (x[0] if self.contact else 0.0)
        m = None if meshes is None else meshes[-1]
        segs.append(integrate(self.free, y0, free_len, self.tol, self.scale, mesh=m))
        return segs

    def residual(self, segs):
        sp = self.spring
        y = segs[-1][-1][1]
        if sp.r_g is not None:
            return np.array([(y[0] - sp.r_g) / sp.L, (y[1] - 0.5 * self.h) / sp.L])
        return np.array([(y[1] - 0.5 * self.h) / sp.L, y[2] + 0.5 * math.pi])

    def newton(self, x0, max_iter=60, fd=1e-7, atol=1e-12):
        x = np.array(x0, dtype=float)
        segs = self.shoot(x)
        res = self.residual(segs)
        for _ in range(max_iter):
            norm = np.max(np.abs(res))
            if norm < atol:
                return x, segs
            meshes = [[t / seg[-1][0] for t, _ in seg[1:]] for seg in segs]
            jac = np.zeros((2, 2))
            for j in range(2):
                xp = x.copy()
                dx = fd * max(1.0, abs(x[j]))
                xp[j] += dx
                jac[:, j] = (self.residual(self.shoot(xp, meshes)) - res) / dx
            step = -np.linalg.solve(jac, res)
            lam = 1.0
            while True:
                try:
                    trial = x + lam * step
                    segs_t = self.shoot(trial)
                    res_t = self.residual(segs_t)
                    if np.max(np.abs(res_t)) < norm:
                        break
                except ShotFailure:
                    pass
                lam *= 0.5
                if lam < 1e-6:
                    if norm < 1e-10:
                        return x, segs
                    raise ShotFailure(f"line search failed at residual {norm:.3e}")
            x, segs, res = trial, segs_t, res_t
        if np.max(np.abs(res)) < 1e-10:
            return x, segs
        raise ShotFailure(f"Newton did not converge: {np.max(np.abs(res)):.3e}")


def solve_convoluted(h, p_gauge, spring=CONVOLUTED, start=None, tol=1e-11):
    """Static equilibrium of a convoluted spring at plate-to-plate height h [m] and gauge
    pressure p_gauge [Pa]: dict with F [N] (on the top plate, > 0 pushes it up), V [m^3], A_e,
    U [J] (strain energy), r_h [m] (departure radius from the top plate, or None without
    contact: A_e = pi r_h^2), lobe_radius [m], girdle_angle [rad] (meridian angle arriving at
    the girdle), contact (the sleeve lies on the plates), x (pass the dict as `start`)."""
    guesses = []
    if start is not None:
        guesses.append((start["x"], start["contact"]))
        guesses.append(([0.002, start["x"][1]] if not start["contact"] else [0.0, start["x"][1]], not start["contact"]))
    # the meridional force of a half-torus lobe out to 1.45 r_b: r N_s ~ p (r_o^2 - r_b^2)/4
    q0 = 0.25 * p_gauge * ((1.45 * spring.r_b) ** 2 - spring.r_b**2)
    failures = []

    def tries():
        yield from guesses
        yield from _convoluted_grid(h, p_gauge, spring, q0)  # only when the neighbour fails

    for x0, contact in tries():
        m = ConvolutedShot(h, p_gauge, spring, tol, contact)
        try:
            x, segs = m.newton(x0)
        except (ShotFailure, np.linalg.LinAlgError, ValueError, OverflowError) as e:
            failures.append(str(e))
            continue
        if not contact and math.sin(x[0]) > 1e-9:
            failures.append("the free meridian rises into the top plate")
            continue
        return _convoluted_result(m, x, segs)
    raise ShotFailure(f"no convoluted equilibrium at h = {h}, p = {p_gauge}: {failures}")


def _convoluted_grid(h, p_gauge, spring, q0):
    """Start points for Newton: the best shots of a coarse grid over (S_d, q_0) on the plate and
    (phi_0, q_0) off it (q_0 from 0.4 to 2.2 times the half-torus estimate), best first."""
    found = []
    for contact, firsts in ((True, np.linspace(0.001, 0.4 * spring.L, 16)), (False, np.linspace(-1.5, 0.0, 16))):
        m = ConvolutedShot(h, p_gauge, spring, 1e-7, contact)
        for a in firsts:
            for q in np.linspace(0.4, 2.2, 19) * q0:
                try:
                    found.append((float(np.max(np.abs(m.residual(m.shoot([a, q]))))), [a, q], contact))
                except (ShotFailure, ValueError, OverflowError, ZeroDivisionError):
                    pass
    found.sort(key=lambda f: f[0])
    return [(x, c) for _, x, c in found[:4]]


def _convoluted_result(m, x, segs):
    sp, p = m.spring, m.p
    pts = [y for seg in segs for _, y in seg]
    y_end = pts[-1]
    if m.contact:
        r_d = segs[0][-1][1][0]
        F = p * math.pi * r_d**2
    else:
        r_d = None
        F = 2.0 * math.pi * (x[1] * math.sin(x[0]) + 0.5 * p * sp.r_b**2)
    V = 2.0 * y_end[4]
    U = 2.0 * y_end[5]  # accumulated over the flat and the free part
    # the first integral at the end of the half (the girdle's upper side)
    r, phi, ls = y_end[0], y_end[2], y_end[3]
    c_end = sp.R0 * m.dW(ls, r / sp.R0)[0] * math.sin(phi) + 0.5 * p * r * r
    warnings = []
    if any(y[1] > m.h + 1e-9 for y in pts):
        warnings.append("the free meridian rises above the top plate")
    if any(y[1] < 0.5 * m.h - 1e-9 for y in pts):
        warnings.append("the upper convolution crosses the mirror plane (the lobes overlap)")
    return {
        "h": m.h, "p_gauge": p, "F": F, "V": V, "A_e": F / p if p else None, "U": U,
        "F_end": 2.0 * math.pi * c_end, "r_h": r_d, "lobe_radius": max(y[0] for y in pts),
        "girdle_angle": phi, "contact": m.contact, "x": list(x), "warnings": warnings,
        "shape": {"r": [y[0] for y in pts], "z": [y[1] for y in pts]},
    }


def convoluted_characteristic(heights, p_gauge, spring=CONVOLUTED, dh=1e-4, tol=1e-11):
    """Constant-pressure characteristic of a convoluted spring: per height h [m]: F [N], V [m^3],
    A_e [m^2], A_v = dV/dh [m^2], k = -dF/dh [N/m], dAe_dh [m], U [J], dU_dh [N], r_h, lobe_radius
    [m], contact. Derivatives by central differences (dh [m])."""
    keys = "h p_gauge F V A_e A_v k dAe_dh U dU_dh r_h lobe_radius contact".split()
    cols = {k: [] for k in keys}
    prev = None
    for h in heights:
        res = solve_convoluted(h, p_gauge, spring, prev, tol)
        up, dn = (solve_convoluted(h + s * dh, p_gauge, spring, res, tol) for s in (1, -1))
        row = {"A_v": (up["V"] - dn["V"]) / (2 * dh), "k": -(up["F"] - dn["F"]) / (2 * dh),
               "dAe_dh": (up["A_e"] - dn["A_e"]) / (2 * dh), "dU_dh": (up["U"] - dn["U"]) / (2 * dh)}
        for k in keys:
            v = row[k] if k in row else res[k]
            cols[k].append(-1.0 if v is None else _plain(v))
        prev = res
    return cols


ISSUE_DESIGN = {"F": 21533.04, "V": 8.456949e-3, "A_e": 0.043066}  # issue 11 item 7 [N, m^3, m^2]
HEIGHTS = [round(0.20 + 0.01 * i, 2) for i in range(11)]  # [m]


def _meridian(res):
    """The shape arrays of a solve dict as lists."""
    return {key: [float(v) for v in res["shape"][key]] for key in ("S", "r", "z", "phi", "lam_s", "N_s", "N_theta")}


def _state(res):
    """The scalar entries of a solve dict."""
    skip = ("shape", "x", "jac")
    return {key: (list(v) if isinstance(v, list) else _plain(v)) for key, v in res.items() if key not in skip}


def build_reference(log=print):
    """All data of tests/data/air_spring_reference.json (a few minutes)."""
    data = {
        "description": "Independent axisymmetric membrane reference of the rolling-lobe air spring (issue 11 item 8): "
        "shooting solution of the membrane equations by scripts/air_spring_reference.py",
        "conventions": {
            "h": "top plate height above the piston base [m] (extension positive)",
            "F": "force on the top plate [N], positive pushes it up",
            "p_gauge": "gauge pressure [Pa]; ambient 101325 Pa",
            "V": "gas volume between top plate, sleeve and piston top [m^3] (piston interior excluded)",
            "A_e": "F / p_gauge [m^2]",
            "A_v": "dV/dh [m^2] (= -dV/dz with z = compression), along the curve's path",
            "k": "-dF/dh [N/m] (= dF/dz with z = compression), along the curve's path",
            "dAe_dh": "dA_e/dh [m] along the curve's path (dA_e/dz = -dAe_dh)",
            "dV_dp": "dV/dp at fixed h [m^3/Pa] (volume compliance)",
            "U": "strain energy of the sleeve [J]; dU_dh [N]",
            "k_identity": "n p_abs A_e A_v / V - p_gauge dAe_dh [N/m] (exact for the polytropic gas)",
            "k_Ae2": "n p_abs A_e^2 / V - p_gauge dAe_dh [N/m] (the usual approximation)",
            "r_h": "radius of the horizontal-tangent point [m] (A_e = pi r_h^2)",
            "lobe_radius": "largest radius of the outer wall [m]",
            "departure_height": "height where the sleeve leaves the piston [m] (h_p when wrap is false)",
            "wrap": "true: the sleeve wraps the piston wall; false: the lobe has rolled up to the piston's top edge",
            "derivatives": "central differences, dh = 1e-4 m, dp = 1e-4 p_gauge",
            "meridian": "S material coordinate from the top bead [m]; r, z [m]; phi meridian angle [rad] "
            "(tangent (cos phi, sin phi) in (r, z)); lam_s; N_s, N_theta membrane forces per current length [N/m]",
        },
        "springs": {"default": dataclasses.asdict(DEFAULT), "B": dataclasses.asdict(SPRING_B)},
        "p_ambient": P_AMBIENT,
        "issue_design_figures": ISSUE_DESIGN,
    }
    log("design state")
    design = solve(0.25, 5e5, DEFAULT, n_shape=51)
    data["design"] = dict(spring="default", **_state(design))
    data["meridian_design"] = _meridian(design)
    data["meridians"] = []
    for h in (0.20, 0.30):
        data["meridians"].append(dict(spring="default", h=h, p_gauge=5e5, **_meridian(solve(h, 5e5, n_shape=51))))
    data["constant_pressure"] = []
    for name, spring, pressures in (("default", DEFAULT, (3e5, 5e5, 7e5)), ("B", SPRING_B, (4e5,))):
        for p in pressures:
            log(f"constant pressure: spring {name}, {p / 1e5:g} bar")
            data["constant_pressure"].append(dict(spring=name, **characteristic(HEIGHTS, p, spring)))
    data["closed"] = []
    for name, spring, dsg, ns in (("default", DEFAULT, (0.25, 5e5), (1.0, 1.4)), ("B", SPRING_B, (0.25, 4e5), (1.4,))):
        for n in ns:
            log(f"closed gas: spring {name}, n = {n}")
            cols = closed(HEIGHTS, dsg, n, spring)
            data["closed"].append(dict(spring=name, n=n, design={"h": dsg[0], "p_gauge": dsg[1]}, **cols))
    return data


def figure(data, path):
    """Meridians at three heights and F(h) at three pressures (default spring)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sp = DEFAULT
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.5))
    merid = [dict(h=0.25, **data["meridian_design"])] + data["meridians"]
    for m in sorted(merid, key=lambda m: m["h"]):
        line = ax1.plot(m["r"], m["z"], label=f"h = {m['h']:.2f} m")[0]
        ax1.plot([0, sp.r_b], [m["h"], m["h"]], color=line.get_color(), lw=3, alpha=0.4)
    ax1.fill_between([0, sp.r_p], [0, 0], [sp.h_p, sp.h_p], color="0.85", label="piston")
    ax1.set_aspect("equal")
    ax1.set_xlim(0, 0.17)
    ax1.set_xlabel("r [m]")
    ax1.set_ylabel("z [m]")
    ax1.set_title("meridian at 5 bar (bar: top plate)")
    ax1.legend(fontsize=8, loc="lower right")
    for c in data["constant_pressure"]:
        if c["spring"] == "default":
            ax2.plot(c["h"], np.array(c["F"]) / 1e3, "o-", ms=3, label=f"{c['p_gauge'][0] / 1e5:g} bar, constant")
    for c in data["closed"]:
        if c["spring"] == "default":
            ax2.plot(c["h"], np.array(c["F"]) / 1e3, "--", label=f"closed, n = {c['n']:g} (5 bar at 0.25 m)")
    ax2.set_xlabel("h [m]")
    ax2.set_ylabel("F [kN]")
    ax2.set_title("force on the top plate")
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def curves_toml(data):
    """The scalar curves of the reference as TOML (the Rust tests read it; std has no JSON):
    `[[constant_pressure]]` and `[[closed]]` tables with the spring's name, the gauge pressure
    or design state, and arrays of equal length per quantity, plus `[design]`."""
    def val(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, (int, float)):
            return repr(float(v))
        if isinstance(v, str):
            return '"' + v + '"'
        return "[" + ", ".join(val(x) for x in v) + "]"

    def table(name, d, array):
        lines = [f"[[{name}]]" if array else f"[{name}]"]
        for k, v in d.items():
            if isinstance(v, (dict,)) or v is None:
                continue
            if isinstance(v, list) and v and not isinstance(v[0], (int, float, bool)):
                continue
            lines.append(f"{k} = {val(v)}")
        return "\n".join(lines)

    parts = ["# Generated by scripts/air_spring_reference.py from air_spring_reference.json: do not edit."]
    parts.append(table("design", data["design"], False))
    for c in data["constant_pressure"]:
        parts.append(table("constant_pressure", c, True))
    for c in data["closed"]:
        parts.append(table("closed", c, True))
    return "\n\n".join(parts) + "\n"


CONVOLUTED_HEIGHTS = [round(0.17 + 0.01 * i, 2) for i in range(7)]  # [m]


def convoluted_toml(log=print):
    """tests/data/air_spring_convoluted_reference.toml: the shipped double-convoluted spring
    (scenes/air_spring_convoluted.toml) at 5 bar over CONVOLUTED_HEIGHTS, constant pressure."""
    log("convoluted: constant pressure, 5 bar")
    c = convoluted_characteristic(CONVOLUTED_HEIGHTS, 5e5, CONVOLUTED)
    lines = [
        "# Generated by scripts/air_spring_reference.py --convoluted: do not edit.",
        "# Double-convoluted spring of scenes/air_spring_convoluted.toml (equal beads, girdle at mid-length),",
        "# shooting solution of the membrane equations (upper half, mirror symmetry), constant gauge pressure.",
        "# h [m] plate to plate; F [N] on the top plate; V [m^3]; A_e = F/p [m^2]; A_v = dV/dh [m^2];",
        "# k = -dF/dh [N/m]; r_h [m] departure radius from the top plate (-1: no contact); lobe_radius [m].",
        "[spring]",
    ]
    lines += [f"{k} = {float(v)!r}" for k, v in dataclasses.asdict(CONVOLUTED).items()]
    lines.append("\n[constant_pressure]")
    for k, v in c.items():
        lines.append(f"{k} = [" + ", ".join(("true" if x else "false") if isinstance(x, bool) else repr(float(x)) for x in v) + "]")
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--convoluted", action="store_true",
                    help="write tests/data/air_spring_convoluted_reference.toml only")
    ap.add_argument("--out", default=str(ROOT / "tests" / "data" / "air_spring_reference.json"))
    ap.add_argument("--figure", default=str(ROOT / "docs" / "air_spring_reference.png"))
    args = ap.parse_args(argv)
    if args.convoluted:
        out = ROOT / "tests" / "data" / "air_spring_convoluted_reference.toml"
        out.write_text(convoluted_toml(log=lambda msg: print(msg, file=sys.stderr)))
        print(f"wrote {out}")
        return
    data = build_reference(log=lambda msg: print(msg, file=sys.stderr))
    pathlib.Path(args.out).write_text(json.dumps(data, indent=1) + "\n")
    pathlib.Path(args.out).with_suffix(".toml").write_text(curves_toml(data))
    figure(data, args.figure)
    d = data["design"]
    print(f"design: F = {d['F']:.6f} N, V = {d['V'] * 1e3:.9f} L, A_e = {d['A_e']:.9f} m^2, r_h = {d['r_h']:.9f} m")
    print(f"wrote {args.out} and {args.figure}")


if __name__ == "__main__":
    main()
