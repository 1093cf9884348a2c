#!/usr/bin/env python3
"""Prototype of the axially moving (ALE) belt, steady state (issue 12 item 2, design note "ale",
step 1; session 35, helper ale35). numpy only; not part of the product.

The two-pulley drive of `scenes/belt_drive.toml` (pulleys of 80 and 120 mm at 0.5 m, belt 4 mm
thick, pitch radii r + t/2), pulley 1 driven at a given speed, pulley 2 free with a load torque
and bearing damping, as the creep harness `src/kinds/belt_drive/creep.rs` builds it.

Formulation (Pechstein & Gerstmayr 2013, written from the design note):
* mesh coordinate x in [0, L) round the closed loop, L = N l the unstretched loop length; the
  material point X sits at x = X + s(t), v = ds/dt (reference length per second);
* r(x) = S(x) q, the planar ANCF cable of `src/elements/ancf_cable2d.rs` (nodes: position and
  slope; cubic Hermite; eps = |r'| - 1, K = r' x r'' / |r'|^2; N = EA eps + d_eps eps_dot,
  M = EI K; 5 Gauss points axial, 3 bending: the "full" rule);
* steady state (q_dot = 0, v_dot = 0): the material derivative of any field is v d/dx, so the
  material velocity is v r', the strain rate v eps' and the acceleration v^2 r''.

Unknowns: q (4 N), v, omega2. Equations:
* q-equations: Q_int(q, v) - v^2 rhoA int S'^T S' dx q - Q_contact(q, v, omega) = 0
  (the convective inertia by parts; the axial damping with eps_dot = v eps');
* gauge: node 0 (middle of the slack span) does not move along its tangent. The steady problem
  does not depend on s: shifting the mesh along the loop's shape is a shift of s, an (up to the
  discretization) zero mode of the q-equations. Its left partner, the projection of the
  q-equations on the mode, is the s-equation "the friction forces sum to zero round the loop",
  which v satisfies; it is reported as a check, not imposed a second time;
* pulley 2: sum of the contact torques - load - c omega2 = 0.

Contact: the penalty and the bristle of `src/contact/circle_friction.rs` at fixed mesh points
(points_per_element per element at (i + 1/2)/n of each element, weight w = l/n). The bristle
deflection z belongs to the material and is transported: steady, v dz/dx = slip rate (stick)
with the cap mu p. Discretization: the product's return mapping with the history taken from the
upstream contact point (upwind, first order) and the "step" the material needs to get there,
h_c = w / v:
    ds_c = rho_c dphi_c - R omega h_c      (dphi_c: angle from the upstream point to this one)
    f*_c = k_t (z_{c-1} + ds_c) + d_t sdot_c,   sdot_c = v r'_c . t_c - omega R
    f_c  = mu p_c phi(f*_c / (mu p_c))         (the C1 stick/slip blend of the product)
    z_c  = |f_c| / |f*_c| (z_{c-1} + ds_c)     (Kelvin-Voigt bristle), z = 0 out of contact,
swept once round the loop from the middle of a span (where z = 0). It is the product's law with
the upstream point as the committed history and h_c as the step.

Solved by Newton with a finite-difference Jacobian (dense), backtracking on the residual norm;
load continuation 0 -> 4 -> 10 -> 20 N m. The mount: the belt laid on the pitch circles at the
stretch 1 + T0/EA, then the reference length corrected until the frictionless static span
tension is T0 (as `preload.rs`).

Run: .venv/bin/python scripts/ale_prototype.py [--belt stiff|soft|both] [--n 30,60,120]
     [--omega 60] [--loads 4,10,20] [--ppe 4] [--bearing c] [--closure q|s|s2]
     [--transient [--h 1e-3] [--t-end 1] [--tol 1e-5 --product-scales]]

Results (session 35; driver 60 rad/s; the Lagrangian figures from `cargo run --release
--example bench_creep w=60` and `bench_belt`, same parameters):
* steady, bearing 0.01 N m s (the creep harness), ALE at the harness' element counts (stiff 100,
  soft 120) against the Lagrangian drive: span tensions within 0.08 % (-0.02 .. -0.08 %), creep
  error against Grashof -5.5 / -0.6 / +4.4 % (stiff, 4 / 10 / 20 N m; Lagrangian -6.4 / -0.8 /
  +3.4 %) and -1.7 / +2.0 / +4.0 % (soft; Lagrangian -3.5 / +1.2 / +3.1 %); torque balance
  (T1 - T2) rho2 against load + bearing within 0.4 %. Tensions at 60 elements within 0.15 % of
  those at 120 (30: up to +0.65 %), the creep error settles from 100 elements (30: up to +30 %,
  60: up to 8 %); 8 contact points per element instead of 4 move it by 0.5-2 % of the creep.
* closure: the discrete s-equation imposed (with the gauge's reaction, --closure s or s2) leaves
  a spurious drag of 0.8 N at 60 elements (torque balance +0.75 %): the point quadrature of the
  penalty and of the convective axial damping (int d v eps'^2 dx = 0.58 N, mostly the cable's
  intra-element strain oscillation) does not vanish round the loop; closure q (default) does
  not have it (-0.05 %).
* transient, the bench protocol (ramp to 60 rad/s and 4 N m in 0.3 s, bearing 0.2 N m s, 1 ms,
  backward Euler, full Newton, the belt kind's scaled test at 1e-5): steady running takes 1.00
  Newton iteration per step (the predictor is the solution) against the Lagrangian drive's 3.20
  (60 elements) / 2.23 (100) with full Newton at the same tolerance; the ramp 2.62 against 2.59 /
  2.16; the soft belt (60 elements) 1.00 against 2.46 running, 2.07 against 2.25 in the ramp.
  Final state against the Lagrangian drive (generalized-alpha, same N): tensions -0.03 ..
  -0.13 %, creep error -0.8 % (stiff, 100 elements; Lagrangian -0.1 %) and +1.3 % (soft, 60;
  Lagrangian +1.4 %). 2 ms steps run (tensions
  +0.12 %, 1.89 iterations per step); 3 and 5 ms steps fail (without line search on the first
  step from rest; with it, 3 ms at 10 iterations per step up to v = 3.8 m/s, 5 ms with spans
  +2.3 / +3.3 % off at 0.5 s, then Newton diverges): not diagnosed.
"""

import argparse
import math
import os
import sys
import time

# one BLAS thread: the dense solves are small, and threads on a shared machine slow them 100x
for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import numpy as np  # noqa: E402

# ---------------------------------------------------------------------------------------------
# cases (CreepCase::stiff / soft of src/kinds/belt_drive/creep.rs)


def case(belt, n, omega, ppe, bearing=0.01):
    c = dict(
        ea=5e4, ei=0.05, mass=0.15, damping_axial=20.0, thickness=0.004, pretension=300.0,
        mu=0.4, radii=(0.08, 0.12), distance=0.5, bearing_damping=bearing, n=n, ppe=ppe,
        omega=omega,
    )
    if belt == "soft":
        c.update(ea=8000.0, pretension=400.0, mu=0.5)
    return c


def default_contact(c):
    """`default_contact` of src/kinds/belt_drive/model.rs."""
    rp = [r + 0.5 * c["thickness"] for r in c["radii"]]
    r_min, r_max = min(rp), max(rp)
    t = max(c["thickness"], 0.01 * r_min)
    k_n = c["ea"] / (t * r_min)
    d_n = math.sqrt(k_n * c["mass"])
    k_t = 0.1 * k_n
    return dict(k_n=k_n, d_n=d_n, k_t=k_t, d_t=d_n * math.sqrt(k_t / k_n), mu=c["mu"],
                smoothing=0.25 * c["pretension"] / (r_max * k_n), blend=0.05)


# ---------------------------------------------------------------------------------------------
# cubic Hermite (S2, S4 carry the length)


def hermite(l, x):
    xi = x / l
    s = np.array([1 - 3 * xi**2 + 2 * xi**3, l * (xi - 2 * xi**2 + xi**3), 3 * xi**2 - 2 * xi**3,
                  l * (-xi**2 + xi**3)])
    d1 = np.array([(-6 * xi + 6 * xi**2) / l, 1 - 4 * xi + 3 * xi**2, (6 * xi - 6 * xi**2) / l,
                   -2 * xi + 3 * xi**2])
    d2 = np.array([(-6 + 12 * xi) / l**2, (-4 + 6 * xi) / l, (6 - 12 * xi) / l**2,
                   (-2 + 6 * xi) / l])
    return s, d1, d2


def gauss(n):
    p, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (p + 1), 0.5 * w


def stick_slip(x, eps):
    """`stick_slip` of circle_friction.rs (x >= 0)."""
    if x <= 1 - eps:
        return x
    if x >= 1 + eps:
        return 1.0
    u = 1 + eps - x
    return 1 - u * u / (4 * eps)


def smoothed_penalty(law, delta):
    d0 = law["smoothing"]
    if delta < d0:
        return law["k_n"] * delta * delta / (2 * d0), delta / d0
    return law["k_n"] * (delta - 0.5 * d0), 1.0


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


# ---------------------------------------------------------------------------------------------
# the loop: open belt over two circles, counter-clockwise (belt from pulley 1 to pulley 2 along
# the lower span), arc length from the middle of the lower span


class Path:
    def __init__(self, centers, radii):
        self.c = [np.asarray(centers[0], float), np.asarray(centers[1], float)]
        self.R = radii
        d = np.linalg.norm(self.c[1] - self.c[0])
        beta = math.asin((radii[1] - radii[0]) / d)
        self.beta = beta
        nl = np.array([-math.sin(beta), -math.cos(beta)])  # normal of the lower span
        nu = np.array([-math.sin(beta), math.cos(beta)])
        self.p1l, self.p2l = self.c[0] + radii[0] * nl, self.c[1] + radii[1] * nl
        self.p2u, self.p1u = self.c[1] + radii[1] * nu, self.c[0] + radii[0] * nu
        span = np.linalg.norm(self.p2l - self.p1l)
        self.span = span
        self.a_l = math.atan2(nl[1], nl[0])
        self.a_u = math.atan2(nu[1], nu[0])
        self.arc2 = radii[1] * (math.pi + 2 * beta)
        self.arc1 = radii[0] * (math.pi - 2 * beta)
        # segments from the middle of the lower span
        self.seg = [0.5 * span, self.arc2, span, self.arc1, 0.5 * span]
        self.length = 2 * span + self.arc1 + self.arc2
        # mesh positions (arc length from the start) of the two span middles
        self.mid_lower = 0.0
        self.mid_upper = 0.5 * span + self.arc2 + 0.5 * span

    def at(self, s):
        s = s % self.length
        lo_dir = (self.p2l - self.p1l) / self.span
        up_dir = (self.p1u - self.p2u) / self.span
        if s < self.seg[0]:
            return 0.5 * (self.p1l + self.p2l) + s * lo_dir, lo_dir
        s -= self.seg[0]
        if s < self.seg[1]:
            a = self.a_l + s / self.R[1]
            n = np.array([math.cos(a), math.sin(a)])
            return self.c[1] + self.R[1] * n, np.array([-n[1], n[0]])
        s -= self.seg[1]
        if s < self.seg[2]:
            return self.p2u + s * up_dir, up_dir
        s -= self.seg[2]
        if s < self.seg[3]:
            a = self.a_u + s / self.R[0]
            n = np.array([math.cos(a), math.sin(a)])
            return self.c[0] + self.R[0] * n, np.array([-n[1], n[0]])
        s -= self.seg[3]
        return self.p1l + s * lo_dir, lo_dir


# ---------------------------------------------------------------------------------------------
# the model


class AleBelt:
    def __init__(self, c, law=None):
        self.c = c
        self.law = law or default_contact(c)
        self.n = c["n"]
        self.rp = [r + 0.5 * c["thickness"] for r in c["radii"]]
        self.centers = [np.zeros(2), np.array([c["distance"], 0.0])]
        self.path = Path(self.centers, self.rp)
        stretch = 1 + c["pretension"] / c["ea"]
        n = self.n
        q = np.zeros((n, 4))
        for k in range(n):
            p, t = self.path.at(self.path.length * k / n)
            q[k, :2], q[k, 2:] = p, stretch * t
        self.q0 = q.reshape(-1)
        self.t0 = q[0, 2:] / np.linalg.norm(q[0, 2:])
        self.set_length(self.path.length / n / stretch)
        self.omega1 = c["omega"]
        self.load = 0.0
        self.mu_on = True
        self.closure = "q"

    def set_mode(self, q):
        """The shift mode of the mesh along the loop's shape at q: nodal r' and the mean of
        r'' from both sides (reaction: lam r' per node, a distributed tangential load)."""
        n = self.n
        qe = self.elem(q)
        _, d1, d2 = hermite(self.l, 0.0)
        _, e1, e2 = hermite(self.l, self.l)
        rpp = 0.5 * (self.field(qe, d2) + np.roll(self.field(qe, e2), 1, axis=0))
        m = np.zeros((n, 4))
        m[:, :2] = q.reshape(n, 4)[:, 2:]
        m[:, 2:] = rpp
        m /= math.sqrt(n)
        self.mode = m.reshape(-1)

    def set_length(self, l):
        self.l = l
        n, ppe = self.n, self.c["ppe"]
        ga, wa = gauss(5)
        gb, wb = gauss(3)
        self.Ha = [hermite(l, x * l) for x in ga]
        self.wa = wa * l
        self.Hb = [hermite(l, x * l) for x in gb]
        self.wb = wb * l
        self.Hc = [hermite(l, (i + 0.5) / ppe * l) for i in range(ppe)]
        self.w = l / ppe
        # span middles in mesh coordinates: element and local coordinate (mesh fixed to the
        # mount, whose nodes are equally spaced along the path)
        self.mids = []
        for s in (self.path.mid_lower, self.path.mid_upper):
            u = s / self.path.length * n
            e = int(math.floor(u)) % n
            self.mids.append((e, (u - math.floor(u)) * l))

    # element coordinates (n, 8)
    def elem(self, q):
        qn = q.reshape(self.n, 4)
        return np.hstack([qn, np.roll(qn, -1, axis=0)])

    @staticmethod
    def field(qe, s):
        """sum_a s_a q_a for all elements: (n, 2)."""
        return (s[0] * qe[:, 0:2] + s[1] * qe[:, 2:4] + s[2] * qe[:, 4:6] + s[3] * qe[:, 6:8])

    @staticmethod
    def scatter(f, s, vec):
        """adds s_a vec to the element force f (n, 8)."""
        for a in range(4):
            f[:, 2 * a:2 * a + 2] += s[a] * vec

    def internal(self, q, v):
        """Q_int (elastic + convective damping) - v^2 rhoA int S'^T r' dx, element forces."""
        c = self.c
        qe = self.elem(q)
        f = np.zeros((self.n, 8))
        for (s, d1, d2), w in zip(self.Ha, self.wa):
            rp = self.field(qe, d1)
            rpp = self.field(qe, d2)
            nr = np.linalg.norm(rp, axis=1)
            eps = nr - 1
            deps = np.sum(rp * rpp, axis=1) / nr
            nf = c["ea"] * eps + c["damping_axial"] * v * deps
            self.scatter(f, d1, (w * nf / nr)[:, None] * rp - (w * c["mass"] * v * v) * rp)
        for (s, d1, d2), w in zip(self.Hb, self.wb):
            rp = self.field(qe, d1)
            rpp = self.field(qe, d2)
            n2 = np.sum(rp * rp, axis=1)
            cr = rp[:, 0] * rpp[:, 1] - rp[:, 1] * rpp[:, 0]
            k = cr / n2
            m = w * c["ei"] * k
            dk_drp = (np.stack([rpp[:, 1], -rpp[:, 0]], 1) - 2 * cr[:, None] * rp / n2[:, None]
                      ) / n2[:, None]
            dk_drpp = np.stack([-rp[:, 1], rp[:, 0]], 1) / n2[:, None]
            self.scatter(f, d1, m[:, None] * dk_drp)
            self.scatter(f, d2, m[:, None] * dk_drpp)
        return f

    def assemble(self, fe):
        g = np.zeros((self.n, 4))
        g += fe[:, 0:4]
        g += np.roll(fe[:, 4:8], 1, axis=0)
        return g.reshape(-1)

    def contact(self, q, v, omegas, detail=False):
        """Element forces of the contact, torques on the pulleys, details per point."""
        law, ppe, n = self.law, self.c["ppe"], self.n
        qe = self.elem(q)
        pos = np.zeros((n, ppe, 2))
        slope = np.zeros((n, ppe, 2))
        for i, (s, d1, _) in enumerate(self.Hc):
            pos[:, i] = self.field(qe, s)
            slope[:, i] = self.field(qe, d1)
        pos = pos.reshape(-1, 2)
        slope = slope.reshape(-1, 2)
        m = n * ppe
        force = np.zeros((m, 2))
        torque = np.zeros(2)
        w = self.w
        h = w / v if v > 0 else 0.0
        z_up, k_up = 0.0, -1
        info = np.zeros((m, 6))  # pulley, p, f, z, slip rate, sliding
        info[:, 0] = -1
        s_eq = 0.0
        # sweep from the middle of the lower span (point 0 sits at the start of element 0)
        for c in range(m):
            r = pos[c]
            hit = None
            for k in range(2):
                d = r - self.centers[k]
                rho2 = d @ d
                if rho2 < self.rp[k] ** 2:
                    hit = k
                    break
            if hit is None:
                z_up, k_up = 0.0, -1
                continue
            k = hit
            big_r = self.rp[k]
            rho = math.sqrt(rho2)
            nn = d / rho
            t = np.array([-nn[1], nn[0]])
            delta = big_r - rho
            u = v * slope[c]
            pe, ramp = smoothed_penalty(law, delta)
            p = pe - law["d_n"] * (u @ nn) * ramp
            if p <= 0:
                z_up, k_up = 0.0, -1
                continue
            # upstream point: angle from it to this one about this pulley's centre
            du = pos[c - 1] - self.centers[k]
            dphi = math.atan2(du[0] * d[1] - du[1] * d[0], du @ d)
            om = omegas[k]
            ds = rho * dphi - big_r * om * h
            sdot = u @ t - om * big_r
            z_prev = z_up if k_up == k else 0.0
            z_trial = z_prev + ds
            f_trial = law["k_t"] * z_trial + law["d_t"] * sdot
            cap = law["mu"] * p if self.mu_on else 0.0
            if cap > 0:
                x = f_trial / cap
                f = cap * math.copysign(stick_slip(abs(x), law["blend"]), x)
            else:
                f = 0.0
            z = (abs(f) / abs(f_trial) if f_trial != 0 else 1.0) * z_trial
            force[c] = w * p * nn - w * f * t
            torque[k] += big_r * w * f
            s_eq += -w * f * (t @ slope[c])
            info[c] = (k, p, f, z, sdot, float(cap <= 0 or abs(f_trial) >= cap))
            z_up, k_up = z, k
        fe = np.zeros((n, 8))
        fr = force.reshape(n, ppe, 2)
        for i, (s, _, _) in enumerate(self.Hc):
            self.scatter(fe, s, fr[:, i])
        if detail:
            return fe, torque, dict(info=info, pos=pos, slope=slope, s_eq=s_eq, force=force)
        return fe, torque

    def unpack(self, x):
        return x[:4 * self.n], x[4 * self.n], x[4 * self.n + 1]

    def residual(self, x):
        q, v, om2 = self.unpack(x)
        fi = self.internal(q, v)
        if self.closure in ("s", "s2"):
            fc, tq, det = self.contact(q, v, (self.omega1, om2), detail=True)
        else:
            fc, tq = self.contact(q, v, (self.omega1, om2))
        rq = self.assemble(fi - fc)
        if self.closure == "s2":
            # distributed gauge: the mesh's shift mode, reaction lam * mode
            gauge = self.mode @ (q - self.q0) * self.c["ea"]
        else:
            gauge = self.t0 @ (q[0:2] - self.q0[0:2]) * self.c["ea"]
        torque = (tq[1] - self.load - self.c["bearing_damping"] * om2) * 1e3
        if self.closure == "s2":
            lam = x[4 * self.n + 2]
            rq = rq + lam * self.mode
            return np.concatenate([rq, [gauge, torque, self.s_residual(q, v, det)]])
        if self.closure == "s":
            # the gauge's reaction lam (a force along node 0's tangent) and the s-equation
            lam = x[4 * self.n + 2]
            rq = rq.copy()
            rq[0:2] += lam * self.t0
            return np.concatenate([rq, [gauge, torque, self.s_residual(q, v, det)]])
        return np.concatenate([rq, [gauge, torque]])

    def s_residual(self, q, v, det):
        """Virtual work of the steady forces under dr = r' ds (material points moved along
        the belt): sum_c F_c . r'_c - int N_d eps' dx (the elastic part is a total
        derivative round the loop, the convective inertia v^2 int r'.r'' too)."""
        fc = det["force"]
        work = np.sum(fc * det["slope"])
        qe = self.elem(q)
        for (s, d1, d2), w in zip(self.Ha, self.wa):
            rp = self.field(qe, d1)
            rpp = self.field(qe, d2)
            nr = np.linalg.norm(rp, axis=1)
            deps = np.sum(rp * rpp, axis=1) / nr
            work -= np.sum(w * self.c["damping_axial"] * v * deps * deps)
        return work

    def tension(self, q, e, x):
        qe = self.elem(q)[e:e + 1]
        _, d1, _ = hermite(self.l, x)
        rp = self.field(qe, d1)[0]
        return self.c["ea"] * (np.linalg.norm(rp) - 1)


# ---------------------------------------------------------------------------------------------
# Newton with a finite-difference Jacobian


def jacobian(res, x, r0, scales):
    m = len(x)
    jac = np.empty((len(r0), m))
    for j in range(m):
        hj = 1e-7 * scales[j]
        xp = x.copy()
        xp[j] += hj
        jac[:, j] = (res(xp) - r0) / hj
    return jac


def newton(res, x, scales, tol=1e-10, max_it=40, verbose=False, stats=None):
    r = res(x)
    jac = None
    for it in range(max_it):
        jac = jacobian(res, x, r, scales)
        if stats is not None:
            stats["jac"] = stats.get("jac", 0) + 1
        dx = -np.linalg.solve(jac, r)
        nrm = np.linalg.norm(r)
        lam = 1.0
        while True:
            xn = x + lam * dx
            rn = res(xn)
            if np.linalg.norm(rn) < (1 - 1e-4 * lam) * nrm or lam < 1e-3:
                break
            lam *= 0.5
        x, r = xn, rn
        step = np.max(np.abs(lam * dx) / scales)
        if stats is not None:
            stats["it"] = stats.get("it", 0) + 1
        if verbose:
            print(f"    it {it}: |r| {np.linalg.norm(r):.3e}, step {step:.3e}, lam {lam}")
        if step < tol:
            return x, it + 1
    raise RuntimeError(f"Newton did not converge: |r| {np.linalg.norm(r):.3e}")


def scales_of(model):
    n = model.n
    s = np.ones(4 * n + 2)
    s[:4 * n] = 0.1  # positions [m]; slopes ~1 (0.1 is fine for both at this step)
    s[4 * n] = 5.0
    s[4 * n + 1] = 40.0
    if model.closure in ("s", "s2"):
        s = np.concatenate([s, [1.0]])
    return s


def preload(model, verbose=False):
    """Frictionless static equilibrium at rest (v -> 0), reference length corrected until the
    mean span tension is the pre-tension (preload.rs)."""
    c = model.c
    n = model.n
    q = model.q0.copy()
    model.mu_on = False
    scales = scales_of(model)[:4 * n]
    for _ in range(5):
        def res(qq):
            fi = model.internal(qq, 0.0)
            fc, _ = model.contact(qq, 0.0, (0.0, 0.0))
            rq = model.assemble(fi - fc)
            # the frictionless loop slides round the pulleys: the gauge replaces node 0's
            # equation along the tangent (its force along the tangent is zero anyway)
            g = model.t0 @ (qq[0:2] - model.q0[0:2]) * c["ea"]
            rq = rq.copy()
            rq[0:2] = rq[0:2] - (model.t0 @ rq[0:2]) * model.t0 + g * model.t0
            return rq
        q, _ = newton(res, q, scales, verbose=verbose)
        tm = 0.5 * sum(model.tension(q, e, x) for e, x in model.mids)
        if abs(tm - c["pretension"]) < 1e-4 * c["pretension"]:
            break
        model.set_length(model.l * (1 + (tm - c["pretension"]) / c["ea"]))
    model.mu_on = True
    return q, tm


def solve_steady(model, x, load, verbose=False, stats=None, depth=0):
    """Newton at the load `load` from the state x (of the load model.load); on failure
    through the middle load first (the stick/slip blend can make Newton cycle on a large
    change of the sliding arcs)."""
    start = model.load
    model.load = load
    try:
        return newton(model.residual, x, scales_of(model), verbose=verbose, stats=stats)
    except (RuntimeError, np.linalg.LinAlgError):
        if depth >= 4:
            raise
        if verbose:
            print(f"    load {start} -> {load} failed: through {0.5 * (start + load)}")
        model.load = start
        xm, i1 = solve_steady(model, x, 0.5 * (start + load), verbose, stats, depth + 1)
        xe, i2 = solve_steady(model, xm, load, verbose, stats, depth + 1)
        return xe, i1 + i2


def report(model, x):
    q, v, om2 = model.unpack(x)
    c = model.c
    fc, tq, det = model.contact(q, v, (model.omega1, om2), detail=True)
    t_lo, t_up = (model.tension(q, e, xx) for e, xx in model.mids)
    t1, t2 = max(t_lo, t_up), min(t_lo, t_up)
    rp = model.rp
    creep = 1 - om2 * rp[1] / (model.omega1 * rp[0])
    theory = (t1 - t2) / (c["ea"] + t1)
    info = det["info"]
    sliding = [int(np.sum((info[:, 0] == k) & (info[:, 5] > 0))) for k in range(2)]
    contact = [int(np.sum(info[:, 0] == k)) for k in range(2)]
    # s-equation residual: sum of the friction forces along the belt's tangent
    ftot = np.sum(np.abs(info[:, 2])) * model.w
    if model.closure == "s":
        s_react = x[4 * model.n + 2]
    elif model.closure == "s2":
        s_react = x[4 * model.n + 2] * np.sum(model.mode.reshape(-1, 4)[:, :2]**2)**0.5
    else:
        s_react = float("nan")
    load = model.load + c["bearing_damping"] * om2
    return dict(t1=t1, t2=t2, omega2=om2, s_react=s_react,
                balance=((t1 - t2) * rp[1] - load) / load, v=v, creep=creep, theory=theory,
                err=(creep - theory) / theory, driver_torque=-tq[0], torque2=tq[1],
                sliding=sliding, contact=contact, s_eq=det["s_eq"], s_eq_rel=det["s_eq"] / ftot,
                length=model.l * model.n)


def run(belt, n, omega, loads, ppe, verbose=False, closure="q", bearing=0.01):
    c = case(belt, n, omega, ppe, bearing)
    model = AleBelt(c)
    t0 = time.time()
    q, tm = preload(model, verbose=verbose)
    rows = []
    # start: material speed from the driver's pitch speed, free pulley at the ratio
    stretch = 1 + c["pretension"] / c["ea"]
    x = np.concatenate([q, [omega * model.rp[0] / stretch, omega * model.rp[0] / model.rp[1]]])
    model.closure = closure
    if closure in ("s", "s2"):
        x = np.concatenate([x, [0.0]])
    if closure == "s2":
        model.set_mode(q)
    for load in [0.0] + list(loads):
        stats = {}
        x, its = solve_steady(model, x, load, verbose=verbose, stats=stats)
        if load in loads:
            rr = report(model, x)
            rr.update(belt=belt, n=n, load=load, its=its, preload=tm, wall=time.time() - t0)
            rows.append(rr)
            print(f"{belt:5} N={n:4} M={load:5.1f}: T1 {rr['t1']:8.3f} T2 {rr['t2']:8.3f} N, "
                  f"omega2 {rr['omega2']:.5f}, v {rr['v']:.5f}, creep {100 * rr['creep']:.4f} % "
                  f"vs Grashof {100 * rr['theory']:.4f} % (error {100 * rr['err']:+.1f} %), "
                  f"driver {rr['driver_torque']:.4f} N m, sliding pts {rr['sliding']} of "
                  f"{rr['contact']}, s-eq {rr['s_eq']:.2e} N ({rr['s_eq_rel']:.1e} of sum|f|), "
                  f"gauge reaction {rr['s_react']:.2e} N, torque balance {100 * rr['balance']:+.2f} %, "
                  f"{its} Newton its, {time.time() - t0:.0f} s", flush=True)
    return rows


# ---------------------------------------------------------------------------------------------
# transient (step 2 of the note, first cut): backward Euler, closure "q" (all q-equations, the
# gauge, v unknown: the q-equations' projection on the shift mode is the s-equation, with the
# mode's inertia rhoA int S^T r' dx v_dot), semi-Lagrangian bristle transport


class AleTransient:
    def __init__(self, model, h, inertia, bearing_damping, tol):
        self.m = model
        self.h = h
        self.inertia = inertia
        self.bearing = bearing_damping
        self.tol = tol
        self.product_scales = False
        self.line_search = False
        n, ppe = model.n, model.c["ppe"]
        self.np = n * ppe
        self.z = np.zeros(self.np)
        self.k = -np.ones(self.np, dtype=int)
        self.theta = np.zeros(2)
        self.omega = np.zeros(2)
        self.v = 0.0
        self.q = None
        self.qd = None
        self.load = 0.0
        self.omega1 = 0.0
        # colouring of the node columns: nodes k and k + p never share a row
        self.period = next(p for p in range(3, n + 1) if n % p == 0)

    def fields(self, qe, x_local):
        s, d1, _ = hermite(self.m.l, x_local)
        return s, d1

    def residual(self, xu, detail=False):
        mo, h = self.m, self.h
        c, law = mo.c, mo.law
        n, ppe = mo.n, c["ppe"]
        q, v, th2 = xu[:4 * n], xu[4 * n], xu[4 * n + 1]
        qd = (q - self.q) / h
        qdd = (qd - self.qd) / h
        vd = (v - self.v) / h
        th = np.array([self.theta[0] + h * self.omega1, th2])
        om = np.array([self.omega1, (th2 - self.theta[1]) / h])
        qe, qde, qdde = mo.elem(q), mo.elem(qd), mo.elem(qdd)
        f = np.zeros((n, 8))
        for (sa, d1, d2), w in zip(mo.Ha, mo.wa):
            rp, rpp = mo.field(qe, d1), mo.field(qe, d2)
            rpd = mo.field(qde, d1)
            acc = mo.field(qdde, sa) + vd * rp + 2 * v * rpd
            nr = np.linalg.norm(rp, axis=1)
            eps_rate = np.sum(rp * rpd, axis=1) / nr + v * np.sum(rp * rpp, axis=1) / nr
            nf = c["ea"] * (nr - 1) + c["damping_axial"] * eps_rate
            mo.scatter(f, d1, (w * nf / nr)[:, None] * rp - (w * c["mass"] * v * v) * rp)
            mo.scatter(f, sa, (w * c["mass"]) * acc)
        for (sa, d1, d2), w in zip(mo.Hb, mo.wb):
            rp, rpp = mo.field(qe, d1), mo.field(qe, d2)
            n2 = np.sum(rp * rp, axis=1)
            cr = rp[:, 0] * rpp[:, 1] - rp[:, 1] * rpp[:, 0]
            m = w * c["ei"] * cr / n2
            dk_drp = (np.stack([rpp[:, 1], -rpp[:, 0]], 1) - 2 * cr[:, None] * rp / n2[:, None]
                      ) / n2[:, None]
            dk_drpp = np.stack([-rp[:, 1], rp[:, 0]], 1) / n2[:, None]
            mo.scatter(f, d1, m[:, None] * dk_drp)
            mo.scatter(f, d2, m[:, None] * dk_drpp)
        # contact points
        pos = np.zeros((n, ppe, 2))
        slope = np.zeros((n, ppe, 2))
        vel = np.zeros((n, ppe, 2))
        for i, (sa, d1, _) in enumerate(mo.Hc):
            pos[:, i], slope[:, i], vel[:, i] = (mo.field(qe, sa), mo.field(qe, d1),
                                                 mo.field(qde, sa))
        pos, slope, vel = pos.reshape(-1, 2), slope.reshape(-1, 2), vel.reshape(-1, 2)
        npt = self.np
        w = mo.w
        force = np.zeros((npt, 2))
        tau = np.zeros(npt)
        znew = np.zeros(npt)
        knew = -np.ones(npt, dtype=int)
        # upstream material points at the last step (mesh x_j - h v), vectorized
        xs = ((np.arange(npt) + 0.5) * w - h * v) % (npt * w)
        e_up = (xs // mo.l).astype(int) % n
        s_up, _, _ = hermite(mo.l, xs - e_up * mo.l)
        qn = mo.elem(self.q)[e_up]
        r_up = (s_up[0][:, None] * qn[:, 0:2] + s_up[1][:, None] * qn[:, 2:4]
                + s_up[2][:, None] * qn[:, 4:6] + s_up[3][:, None] * qn[:, 6:8])
        a = (np.arange(npt) - h * v / w) % npt
        j0 = np.floor(a).astype(int) % npt
        al = a - np.floor(a)
        j1 = (j0 + 1) % npt
        u = vel + v * slope
        for kk in range(2):
            d = pos - mo.centers[kk]
            rho = np.linalg.norm(d, axis=1)
            big_r = mo.rp[kk]
            inside = (rho < big_r) & (knew < 0)
            if not np.any(inside):
                continue
            idx = np.nonzero(inside)[0]
            d, rho = d[idx], rho[idx]
            nn = d / rho[:, None]
            t = np.stack([-nn[:, 1], nn[:, 0]], 1)
            delta = big_r - rho
            d0 = law["smoothing"]
            lin = delta >= d0
            pe = np.where(lin, law["k_n"] * (delta - 0.5 * d0), law["k_n"] * delta**2 / (2 * d0))
            ramp = np.where(lin, 1.0, delta / d0)
            uu = u[idx]
            p = pe - law["d_n"] * np.sum(uu * nn, axis=1) * ramp
            ok = p > 0
            idx, d, rho, nn, t, p, uu = idx[ok], d[ok], rho[ok], nn[ok], t[ok], p[ok], uu[ok]
            z_up = ((1 - al[idx]) * np.where(self.k[j0[idx]] == kk, self.z[j0[idx]], 0.0)
                    + al[idx] * np.where(self.k[j1[idx]] == kk, self.z[j1[idx]], 0.0))
            du = r_up[idx] - mo.centers[kk]
            dphi = np.arctan2(du[:, 0] * d[:, 1] - du[:, 1] * d[:, 0], np.sum(du * d, axis=1))
            ds = rho * dphi - big_r * (th[kk] - self.theta[kk])
            sdot = np.sum(uu * t, axis=1) - om[kk] * big_r
            z_trial = z_up + ds
            f_trial = law["k_t"] * z_trial + law["d_t"] * sdot
            cap = law["mu"] * p
            x = np.abs(f_trial) / cap
            eps = law["blend"]
            uq = 1 + eps - x
            phi = np.where(x <= 1 - eps, x, np.where(x >= 1 + eps, 1.0, 1 - uq * uq / (4 * eps)))
            ff = cap * phi * np.sign(f_trial)
            with np.errstate(invalid="ignore", divide="ignore"):
                fac = np.where(f_trial != 0, np.abs(ff) / np.abs(f_trial), 1.0)
            znew[idx] = fac * z_trial
            knew[idx] = kk
            force[idx] = (w * p)[:, None] * nn - (w * ff)[:, None] * t
            if kk == 1:
                tau[idx] = big_r * w * ff
            else:
                self.tau1 = big_r * w * np.sum(ff)
        fe = np.zeros((n, 8))
        fr = force.reshape(n, ppe, 2)
        for i, (sa, _, _) in enumerate(mo.Hc):
            mo.scatter(fe, sa, fr[:, i])
        rq = mo.assemble(f - fe)
        gauge = mo.t0 @ (q[0:2] - mo.q0[0:2]) * c["ea"]
        torque = (np.sum(tau) - self.load - self.bearing * om[1]
                  - self.inertia * (om[1] - self.omega[1]) / h) * 1e3
        res = np.concatenate([rq, [gauge, torque]])
        if detail:
            return res, tau, dict(z=znew, k=knew, force=force, pos=pos, om=om, th=th)
        return res, tau

    def jacobian(self, xu, r0, tau0):
        mo = self.m
        n, ppe = mo.n, mo.c["ppe"]
        dim = 4 * n + 2
        jac = np.zeros((dim, dim))
        p = self.period
        for start in range(p):
            nodes = np.arange(start, n, p)
            for dof in range(4):
                hs = 1e-7 * (0.1 if dof < 2 else 1.0)
                xp = xu.copy()
                xp[4 * nodes + dof] += hs
                r1, tau1 = self.residual(xp)
                dr = (r1 - r0) / hs
                dtau = (tau1 - tau0) / hs
                for k in nodes:
                    col = 4 * k + dof
                    for kk in (k - 1, k, k + 1):
                        kk %= n
                        jac[4 * kk:4 * kk + 4, col] = dr[4 * kk:4 * kk + 4]
                    if k == 0:
                        jac[4 * n, col] = dr[4 * n]
                    els = [(k - 1) % n, k]
                    jac[4 * n + 1, col] = 1e3 * sum(np.sum(dtau[e * ppe:(e + 1) * ppe])
                                                    for e in els)
        for col, hs in ((4 * n, 1e-7 * 5), (4 * n + 1, 1e-7)):
            xp = xu.copy()
            xp[col] += hs
            r1, _ = self.residual(xp)
            jac[:, col] = (r1 - r0) / hs
        return jac

    def step(self, stats):
        """One backward-Euler step; full Newton (a Jacobian per iteration)."""
        n = self.m.n
        xu = np.concatenate([self.q + self.h * self.qd, [self.v, self.theta[1]
                                                          + self.h * self.omega[1]]])
        scales = np.ones(4 * n + 2)
        if self.product_scales:
            # the belt kind's convergence test: positions against the loop length L, slopes
            # against L / (4 l_e); v [m/s] and the pulley angle [rad] against 1
            length = self.m.l * n
            scales[:4 * n] = np.tile([length, length, n / 4.0, n / 4.0], n)
        else:
            scales[:4 * n] = 0.1
            scales[4 * n] = 5.0
        r0, tau0 = self.residual(xu)
        for it in range(30):
            jac = self.jacobian(xu, r0, tau0)
            dx = -np.linalg.solve(jac, r0)
            # optional backtracking on the residual norm (at most 5 halvings)
            lam, nrm = 1.0, np.linalg.norm(r0)
            for _ in range(6 if self.line_search else 1):
                r1, tau1 = self.residual(xu + lam * dx)
                if not self.line_search or np.linalg.norm(r1) < nrm or lam < 0.05:
                    break
                lam *= 0.5
                stats["halvings"] = stats.get("halvings", 0) + 1
            xu, r0, tau0 = xu + lam * dx, r1, tau1
            stats["it"] += 1
            if lam == 1.0 and np.max(np.abs(dx) / scales) < self.tol:
                break
        else:
            raise RuntimeError(f"transient Newton did not converge (v {self.v:.4f} m/s)")
        _, tau, det = self.residual(xu, detail=True)
        q = xu[:4 * n]
        self.qd = (q - self.q) / self.h
        self.q = q
        self.v = xu[4 * n]
        self.omega = det["om"]
        self.theta = det["th"]
        self.z, self.k = det["z"], det["k"]
        self.tau2 = np.sum(tau)
        return det


def transient(belt, n, ppe, h, t_end, tol, bearing, inertia, log_every, product_scales=False,
              line_search=False):
    c = case(belt, n, 60.0, ppe, bearing)
    model = AleBelt(c)
    q, tm = preload(model)
    tr = AleTransient(model, h, inertia, bearing, tol)
    tr.product_scales = product_scales
    tr.line_search = line_search
    tr.q, tr.qd = q.copy(), np.zeros_like(q)
    w_max, t_ramp, load = 60.0, 0.3, 4.0
    stats = dict(it=0)
    steps = int(round(t_end / h))
    t0 = time.time()
    window = []
    for i in range(steps):
        t = (i + 1) * h
        tm_ = i * h
        # mean driver speed over the step (the bench's angle input)
        a0 = 0.5 * w_max * min(tm_, t_ramp) ** 2 / t_ramp + w_max * max(0.0, tm_ - t_ramp)
        a1 = 0.5 * w_max * min(t, t_ramp) ** 2 / t_ramp + w_max * max(0.0, t - t_ramp)
        tr.omega1 = (a1 - a0) / h
        tr.load = load * min(t / t_ramp, 1.0)
        it0 = stats["it"]
        tr.step(stats)
        its = stats["it"] - it0
        if t > 0.8 * t_end:
            window.append(its)
        if (i + 1) % log_every == 0:
            qq = tr.q
            t_lo, t_up = (model.tension(qq, e, xx) for e, xx in model.mids)
            print(f"  t {t:.3f}: omega1 {tr.omega1:.3f}, omega2 {tr.omega[1]:.4f}, v {tr.v:.4f}, "
                  f"T {max(t_lo, t_up):.2f} / {min(t_lo, t_up):.2f} N, {its} its, "
                  f"mean {stats['it'] / (i + 1):.2f} its/step, {time.time() - t0:.0f} s",
                  flush=True)
    print(f"{belt} N={n} h={h}: {stats['it'] / steps:.2f} Newton its per step overall, "
          f"{np.mean(window):.2f} in the last 20 %, {stats.get('halvings', 0)} step halvings "
          "of the line search")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--belt", default="both")
    ap.add_argument("--n", default="30,60,120")
    ap.add_argument("--omega", type=float, default=60.0)
    ap.add_argument("--loads", default="4,10,20")
    ap.add_argument("--ppe", type=int, default=4)
    ap.add_argument("--verbose", action="store_true")
    ap.add_argument("--closure", default="q", help="q: the q-equations with the gauge close "
                    "the system (v from their projection on the mode); s: the s-equation "
                    "imposed, the gauge with a reaction force")
    ap.add_argument("--transient", action="store_true")
    ap.add_argument("--line-search", action="store_true", help="transient: backtracking on "
                    "the residual norm (did not rescue 3 and 5 ms steps)")
    ap.add_argument("--h", type=float, default=1e-3)
    ap.add_argument("--t-end", type=float, default=1.0)
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--product-scales", action="store_true", help="the belt kind's Newton "
                    "scales (positions against the loop length, slopes against L/(4 l_e)); "
                    "with --tol 1e-5 the scene's test")
    ap.add_argument("--bearing", type=float, default=None, help="bearing damping of pulley 2 "
                    "[N m s] (default: the scene's 0.2 for --transient, the creep harness' 0.01 "
                    "for the steady cases)")
    a = ap.parse_args()
    if a.transient:
        for n in [int(s) for s in a.n.split(",")]:
            transient("stiff" if a.belt == "both" else a.belt, n, a.ppe, a.h, a.t_end, a.tol,
                      0.2 if a.bearing is None else a.bearing, 0.01, 50, a.product_scales,
                      a.line_search)
        return
    belts = ["stiff", "soft"] if a.belt == "both" else [a.belt]
    loads = [float(s) for s in a.loads.split(",")]
    for belt in belts:
        for n in [int(s) for s in a.n.split(",")]:
            run(belt, n, a.omega, loads, a.ppe, verbose=a.verbose, closure=a.closure,
                bearing=0.01 if a.bearing is None else a.bearing)


if __name__ == "__main__":
    sys.exit(main())
