//! Seed-003 co-rotational 3D beam: conformance, Hermite basis, linear response of one
//! element, rigid-body inertia, inertia force against Lagrange's equations, chain to rotation
//! vectors.

use crate::element_conformance;
use crate::elements::Element;
use crate::elements::conformance::{Case, Config, rigid_motion};
use crate::elements::corotational3d::*;
use crate::elements::finite_difference as fd;
use crate::elements::rotation::{exp_so3, tangent_body};
use nalgebra::{Matrix3, Vector3};

fn section() -> BeamSection {
    BeamSection {
        ea: 2.0e6,
        ga_y: 8.0e5,
        ga_z: 6.0e5,
        gj: 3.0e3,
        ei_y: 5.0e3,
        ei_z: 8.0e3,
        rho_a: 7.0,
        rho_jx: 0.03,
        rho_iy: 0.01,
        rho_iz: 0.02,
    }
}

/// An element of length 0.7 along a skew direction.
fn element(theory: Theory, mass: MassModel) -> (Corot3d, Nodes) {
    let x1 = Vector3::new(0.2, -0.1, 0.3);
    let x2 = x1 + Vector3::new(0.4, 0.5, 0.3).normalize() * 0.7;
    let r0 = reference_frame(&x1, &x2, &Vector3::new(0.1, 0.2, 1.0)).unwrap();
    let el = Corot3d::new(0.7, r0, &section(), theory, mass);
    (
        el,
        Nodes {
            x: [x1, x2],
            r: [Matrix3::identity(); 2],
        },
    )
}

/// A large deformed configuration (local rotations of a few tenths of a radian, on top
/// of a large rigid rotation).
fn deformed(n0: &Nodes) -> Nodes {
    let q = exp_so3(&Vector3::new(1.3, -2.1, 0.8));
    let t = Vector3::new(0.3, 1.0, -2.0);
    Nodes {
        x: [
            q * n0.x[0] + t,
            q * (n0.x[1] + Vector3::new(0.01, -0.03, 0.02)) + t,
        ],
        r: [
            q * exp_so3(&Vector3::new(0.1, -0.2, 0.15)),
            q * exp_so3(&Vector3::new(-0.12, 0.25, 0.05)),
        ],
    }
}

fn perturbed(n: &Nodes, j: usize, eps: f64) -> Nodes {
    let mut p = *n;
    let node = j / 6;
    let comp = j % 6;
    if comp < 3 {
        p.x[node][comp] += eps;
    } else {
        let mut w = Vector3::zeros();
        w[comp - 3] = eps;
        p.r[node] = n.r[node] * exp_so3(&w);
    }
    p
}

/// Nodes moved by `d = [δx1, δW1, δx2, δW2]` (positions added, body spins applied).
fn spun(n: &Nodes, d: &[f64]) -> Nodes {
    let mut p = *n;
    for i in 0..2 {
        p.x[i] += Vector3::from_column_slice(&d[6 * i..6 * i + 3]);
        p.r[i] = n.r[i] * exp_so3(&Vector3::from_column_slice(&d[6 * i + 3..6 * i + 6]));
    }
    p
}

fn dmat(r: usize, c: usize, x: &[f64]) -> nalgebra::DMatrix<f64> {
    nalgebra::DMatrix::from_column_slice(r, c, x)
}

fn theories() -> [Theory; 2] {
    [Theory::EulerBernoulli, Theory::Timoshenko]
}

/// Hermite basis: partition of unity, end values and the mid-point weights.
#[test]
fn hermite_basis() {
    let h0 = hermite(0.0);
    let h1 = hermite(1.0);
    assert_eq!(h0, [1.0, 0.0, 0.0, 0.0]);
    assert_eq!(h1, [0.0, 0.0, 1.0, 0.0]);
    assert_eq!(hermite(0.5), [0.5, 0.125, 0.5, -0.125]);
    for xi in [0.1, 0.37, 0.8] {
        let h = hermite(xi);
        assert!((h[0] + h[2] - 1.0).abs() < 1e-15);
        // reproduces a straight line: y = ξ when x1 = 0, x2 = 1, t = 1
        assert!((h[2] + h[1] + h[3] - xi).abs() < 1e-15);
    }
}

/// The Hermite basis' derivatives against central differences of the basis.
#[test]
fn hermite_d1_matches_finite_differences() {
    for xi in [0.0, 0.1, 0.37, 0.5, 0.8, 1.0] {
        let g: Vec<f64> = (0..4)
            .map(|k| fd::gradient(&[xi], |_| 1e-6, |x| hermite(x[0])[k])[0])
            .collect();
        let d = hermite_d1(xi);
        for k in 0..4 {
            assert!(
                (d[k] - g[k]).abs() < 1e-8,
                "xi {xi}, h{k}': {} against {}",
                d[k],
                g[k]
            );
        }
    }
}

/// Zero strain and zero internal force in the reference configuration and under rigid
/// motions of any size: rotation angles beyond 2π included (a rotation of 2π + 1 rad is
/// the same matrix as 1 rad, so the element cannot tell them apart).
#[test]
fn rigid_motion_is_strain_free() {
    for th in theories() {
        let (el, n0) = element(th, MassModel::Lumped);
        for (axis, angle) in [
            (Vector3::new(0.0, 0.0, 1.0), 0.0),
            (Vector3::new(1.0, 2.0, -0.5), 1.0),
            (Vector3::new(0.3, -0.4, 0.8), std::f64::consts::PI),
            (
                Vector3::new(-1.0, 0.2, 0.1),
                2.0 * std::f64::consts::PI + 1.0,
            ),
            (Vector3::new(0.5, 0.5, -0.7), 7.5 * std::f64::consts::PI),
        ] {
            let q = exp_so3(&(axis.normalize() * angle));
            let t = Vector3::new(10.0, -3.0, 2.0);
            let n = Nodes {
                x: [q * n0.x[0] + t, q * n0.x[1] + t],
                r: [q, q],
            };
            let mut f = Vec12::zeros();
            let u = el.internal_force(&n, &mut f);
            assert!(u.abs() < 1e-18, "U = {u} at angle {angle}");
            assert!(f.norm() < 1e-8, "|f| = {} at angle {angle}", f.norm());
            let loc = el.local(&n);
            assert!(loc.u.abs() < 1e-14);
            assert!(loc.theta[0].norm() < 1e-12 && loc.theta[1].norm() < 1e-12);
        }
    }
}

/// The force is the gradient of the strain energy along position perturbations and body
/// spins.
#[test]
fn force_matches_energy_gradient() {
    for th in theories() {
        let (el, n0) = element(th, MassModel::Lumped);
        let n = deformed(&n0);
        let mut f = Vec12::zeros();
        el.internal_force(&n, &mut f);
        let g = fd::gradient(&[0.0; 12], |_| 1e-6, |d| el.strain_energy(&spun(&n, d)));
        fd::assert_close(
            &format!("{th:?}: force vs energy gradient"),
            &dmat(12, 1, f.as_slice()),
            &dmat(12, 1, &g),
            1e-6,
            0.0,
        );
    }
}

/// Force and moment balance of the internal force for any configuration.
#[test]
fn internal_force_is_self_equilibrated() {
    let (el, n0) = element(Theory::Timoshenko, MassModel::Lumped);
    let n = deformed(&n0);
    let mut f = Vec12::zeros();
    el.internal_force(&n, &mut f);
    let f1 = Vector3::new(f[0], f[1], f[2]);
    let f2 = Vector3::new(f[6], f[7], f[8]);
    let m1 = n.r[0] * Vector3::new(f[3], f[4], f[5]);
    let m2 = n.r[1] * Vector3::new(f[9], f[10], f[11]);
    assert!((f1 + f2).norm() < 1e-10 * f.norm());
    let mom = m1 + m2 + n.x[0].cross(&f1) + n.x[1].cross(&f2);
    assert!(mom.norm() < 1e-9 * f.norm(), "{mom:?}");
}

/// The tangent against central differences of the force (positions and body spins), at
/// the reference and at a large deformed configuration.
#[test]
fn tangent_matches_finite_differences() {
    for th in theories() {
        let (el, n0) = element(th, MassModel::Lumped);
        for n in [n0, deformed(&n0)] {
            let mut f = Vec12::zeros();
            let mut k = Mat12::zeros();
            el.internal_force_tangent(&n, &mut f, &mut k);
            fd::assert_jacobian(
                &format!("{th:?}: tangent"),
                &dmat(12, 12, k.as_slice()),
                &[0.0; 12],
                1e-7,
                1e-7,
                |d, out| {
                    let mut fx = Vec12::zeros();
                    el.internal_force(&spun(&n, d), &mut fx);
                    out.copy_from_slice(fx.as_slice());
                },
            );
        }
    }
}

/// Small deflections of a single element equal the classical beam element: tip force P on
/// a cantilever gives `P L³/(3EI) (+ P L/GA for Timoshenko)`, tip moment `M L²/(2EI)`,
/// axial `P L/EA`, torsion `T L/GJ`.
#[test]
fn linear_response_of_one_element() {
    let s = section();
    let l0 = 0.7;
    for th in theories() {
        let el = Corot3d::new(l0, Matrix3::identity(), &s, th, MassModel::Lumped);
        let n = Nodes {
            x: [Vector3::zeros(), Vector3::new(l0, 0.0, 0.0)],
            r: [Matrix3::identity(); 2],
        };
        let mut f = Vec12::zeros();
        let mut k = Mat12::zeros();
        el.internal_force_tangent(&n, &mut f, &mut k);
        let kff = k.fixed_view::<6, 6>(6, 6).into_owned();
        let c = kff.try_inverse().unwrap();
        let shear = |ga: f64| {
            if th == Theory::Timoshenko {
                l0 / ga
            } else {
                0.0
            }
        };
        let l3 = l0 * l0 * l0;
        let expect = [
            (0, 0, l0 / s.ea),
            (1, 1, l3 / (3.0 * s.ei_z) + shear(s.ga_y)),
            (2, 2, l3 / (3.0 * s.ei_y) + shear(s.ga_z)),
            (3, 3, l0 / s.gj),
            (1, 5, l0 * l0 / (2.0 * s.ei_z)),
            (2, 4, -l0 * l0 / (2.0 * s.ei_y)),
            (5, 5, l0 / s.ei_z),
        ];
        for (i, j, v) in expect {
            assert!(
                (c[(i, j)] - v).abs() < 1e-9 * v.abs(),
                "{th:?} flexibility ({i},{j}) = {} vs {v}",
                c[(i, j)]
            );
        }
    }
}

/// Total mass and the rigid-body inertia of a straight element are exact for both mass
/// models: the kinetic energy of any rigid motion (v, ω) about any current orientation is
/// `½ m |v_c|² + ½ ωᵀ J ω` with `J = m l²/12 (I − t tᵀ) + l Q R0 J_sec R0ᵀ Qᵀ`.
#[test]
fn rigid_body_inertia_is_exact() {
    let s = section();
    for mass in [MassModel::Lumped, MassModel::Consistent] {
        let (el, n0) = element(Theory::Timoshenko, mass);
        let l = el.length();
        let m = s.rho_a * l;
        let q = exp_so3(&Vector3::new(-0.4, 2.2, 1.9));
        let n = Nodes {
            x: [q * n0.x[0], q * n0.x[1]],
            r: [q, q],
        };
        let mm = el.mass_matrix(&n);
        let mut total = 0.0;
        for i in [0, 6] {
            for j in [0, 6] {
                total += mm[(i, j)];
            }
        }
        assert!(
            (total - m).abs() < 1e-13 * m,
            "{mass:?}: total mass {total}"
        );
        let xc = 0.5 * (n.x[0] + n.x[1]);
        let t = (n.x[1] - n.x[0]) / l;
        let js = Matrix3::from_diagonal(&Vector3::new(s.rho_jx, s.rho_iy, s.rho_iz));
        let jrig = (Matrix3::identity() - t * t.transpose()) * (m * l * l / 12.0)
            + q * el.reference_frame() * js * el.reference_frame().transpose() * q.transpose() * l;
        for (vc, w) in [
            (Vector3::new(1.0, -2.0, 0.5), Vector3::zeros()),
            (Vector3::zeros(), Vector3::new(0.3, 1.1, -0.7)),
            (Vector3::new(0.2, 0.1, -0.3), Vector3::new(-2.0, 0.4, 0.9)),
        ] {
            let v = Rates {
                x: [vc + w.cross(&(n.x[0] - xc)), vc + w.cross(&(n.x[1] - xc))],
                w: [q.transpose() * w, q.transpose() * w],
            };
            let ke = el.kinetic_energy(&n, &v);
            let exact = 0.5 * m * vc.norm_squared() + 0.5 * w.dot(&(jrig * w));
            assert!(
                (ke - exact).abs() < 1e-12 * exact,
                "{mass:?}: {ke} vs {exact}"
            );
        }
    }
}

/// Nodal velocities and accelerations `[ẋ₀, W₀, ẋ₁, W₁]` of a general motion, shared by the
/// inertia tests.
fn motion_rates() -> (Vec12, Vec12) {
    (
        Vec12::from_column_slice(&[
            0.3, -0.2, 0.5, 1.5, -0.7, 2.0, -0.1, 0.4, 0.2, -1.0, 0.8, 1.7,
        ]),
        Vec12::from_column_slice(&[
            1.0, 0.5, -0.3, -2.0, 0.6, 0.9, 0.2, -0.8, 0.6, 1.3, -0.4, 0.7,
        ]),
    )
}

/// The kinetic energy is ½ vᵀ M v, and the inertia force is consistent with it: its power
/// equals dT/dt along a motion (checked with central differences in time), which tests
/// the convective terms.
#[test]
fn inertia_force_power_is_kinetic_energy_rate() {
    for mass in [MassModel::Lumped, MassModel::Consistent] {
        let (el, n0) = element(Theory::EulerBernoulli, mass);
        let n = deformed(&n0);
        let (vv, av) = motion_rates();
        let (v, a) = (Rates::from_vec(&vv), Rates::from_vec(&av));
        let mm = el.mass_matrix(&n);
        let t = el.kinetic_energy(&n, &v);
        assert!((t - 0.5 * vv.dot(&(mm * vv))).abs() < 1e-12 * t);
        let mut f = Vec12::zeros();
        el.inertia_force(&n, &v, &a, &Vector3::zeros(), &mut f, None);
        // Motion: x(s) = x + s ẋ + ½ s² ẍ, R(s) = R exp(s Ω + ½ s² Ω̇), v(s) = v + s a.
        let at = |s: f64| {
            let mut p = n;
            let mut r = v;
            for i in 0..2 {
                p.x[i] = n.x[i] + v.x[i] * s + a.x[i] * (0.5 * s * s);
                p.r[i] = n.r[i] * exp_so3(&(v.w[i] * s + a.w[i] * (0.5 * s * s)));
                r.x[i] = v.x[i] + a.x[i] * s;
                r.w[i] = v.w[i] + a.w[i] * s;
            }
            el.kinetic_energy(&p, &r)
        };
        let h = 1e-5;
        let dtdt = (at(h) - at(-h)) / (2.0 * h);
        let power = f.dot(&vv);
        assert!(
            (dtdt - power).abs() < 1e-7 * power.abs().max(1.0),
            "{mass:?}: dT/dt {dtdt} vs power {power}"
        );
    }
}

/// Lagrange's equations in body coordinates: the inertia force equals
/// `d/dt(∂T/∂v) − ∂T/∂(x, W)` (the Euler–Poincaré form), with all derivatives by central
/// differences of the kinetic energy. Checks every convective term individually.
#[test]
fn inertia_force_matches_lagrange_equations() {
    for mass in [MassModel::Lumped, MassModel::Consistent] {
        let (el, n0) = element(Theory::Timoshenko, mass);
        let n = deformed(&n0);
        let (vv, av) = motion_rates();
        let (v, a) = (Rates::from_vec(&vv), Rates::from_vec(&av));
        let mut f = Vec12::zeros();
        el.inertia_force(&n, &v, &a, &Vector3::zeros(), &mut f, None);
        // p = ∂T/∂v = M(q) v; d/dt along the motion; ∂T/∂q along body spins with v fixed.
        let momentum = |nn: &Nodes, vel: &Vec12| el.mass_matrix(nn) * vel;
        let h = 1e-5;
        let step = |s: f64| {
            let mut p = n;
            for i in 0..2 {
                p.x[i] = n.x[i] + v.x[i] * s;
                p.r[i] = n.r[i] * exp_so3(&(v.w[i] * s));
            }
            p
        };
        let pdot =
            (momentum(&step(h), &(vv + av * h)) - momentum(&step(-h), &(vv - av * h))) / (2.0 * h);
        let mut dtdq = Vec12::zeros();
        for j in 0..12 {
            let tp = el.kinetic_energy(&perturbed(&n, j, h), &v);
            let tm = el.kinetic_energy(&perturbed(&n, j, -h), &v);
            dtdq[j] = (tp - tm) / (2.0 * h);
        }
        // Body angular velocities: d/dt(∂T/∂Ω) + Ω × ∂T/∂Ω − ∂T/∂W (Euler–Poincaré).
        let mut lag = pdot - dtdq;
        let p = momentum(&n, &vv);
        for i in 0..2 {
            let pw = Vector3::new(p[6 * i + 3], p[6 * i + 4], p[6 * i + 5]);
            let c = v.w[i].cross(&pw);
            for k in 0..3 {
                lag[6 * i + 3 + k] += c[k];
            }
        }
        let err = (lag - f).norm() / f.norm();
        assert!(err < 1e-7, "{mass:?}: relative error {err}\n{lag}\n{f}");
    }
}

/// Mass, gyroscopic and configuration derivatives of the inertia force (with gravity)
/// against central differences.
#[test]
fn inertia_derivatives_match_finite_differences() {
    let g = Vector3::new(0.5, -9.81, 2.0);
    for mass in [MassModel::Lumped, MassModel::Consistent] {
        let (el, n0) = element(Theory::EulerBernoulli, mass);
        let n = deformed(&n0);
        let vv = Vec12::from_column_slice(&[
            0.3, -0.2, 0.5, 1.5, -0.7, 2.0, -0.1, 0.4, 0.2, -1.0, 0.8, 1.7,
        ]);
        let av = Vec12::from_column_slice(&[
            1.0, 0.5, -0.3, -2.0, 0.6, 0.9, 0.2, -0.8, 0.6, 1.3, -0.4, 0.7,
        ]);
        let force = |nn: &Nodes, v: &Vec12, a: &Vec12| {
            let mut f = Vec12::zeros();
            el.inertia_force(
                nn,
                &Rates::from_vec(v),
                &Rates::from_vec(a),
                &g,
                &mut f,
                None,
            );
            f
        };
        let mut mm = Mat12::zeros();
        let mut cc = Mat12::zeros();
        let mut kk = Mat12::zeros();
        let mut f = Vec12::zeros();
        let mut dummy = Mat12::zeros();
        let (v, a) = (Rates::from_vec(&vv), Rates::from_vec(&av));
        el.inertia_force(&n, &v, &a, &g, &mut f, Some((1.0, 0.0, &mut mm, &mut kk)));
        el.inertia_force(
            &n,
            &v,
            &a,
            &g,
            &mut f,
            Some((0.0, 1.0, &mut cc, &mut dummy)),
        );
        let v12 = Vec12::from_column_slice;
        let put = |f: Vec12, out: &mut [f64]| out.copy_from_slice(f.as_slice());
        let h = 1e-6;
        fd::assert_jacobian(
            &format!("{mass:?} M"),
            &dmat(12, 12, mm.as_slice()),
            av.as_slice(),
            h,
            1e-7,
            |x, out| put(force(&n, &vv, &v12(x)), out),
        );
        fd::assert_jacobian(
            &format!("{mass:?} C"),
            &dmat(12, 12, cc.as_slice()),
            vv.as_slice(),
            h,
            1e-7,
            |x, out| put(force(&n, &v12(x), &av), out),
        );
        fd::assert_jacobian(
            &format!("{mass:?} K"),
            &dmat(12, 12, kk.as_slice()),
            &[0.0; 12],
            h,
            1e-7,
            |d, out| put(force(&spun(&n, d), &vv, &av), out),
        );
        assert!((mm - mm.transpose()).norm() < 1e-14 * mm.norm());
    }
}

/// The lumped mid-point is the centre-line point of the Hermite interpolation at ξ = ½,
/// which to first order is the co-rotated cubic: `x_mid = ½(x1 + x2) + Rr (l0/8)
/// [0, θ̄_1z − θ̄_2z, −(θ̄_1y − θ̄_2y)]` (reference B.4).
#[test]
fn mid_point_matches_corotated_cubic() {
    let (el, n0) = element(Theory::EulerBernoulli, MassModel::Lumped);
    let q = exp_so3(&Vector3::new(0.4, 0.9, -1.2));
    for eps in [1e-2, 1e-3, 1e-4] {
        let n = Nodes {
            x: [q * n0.x[0], q * n0.x[1]],
            r: [
                q * exp_so3(&(Vector3::new(0.2, -0.5, 0.7) * eps)),
                q * exp_so3(&(Vector3::new(-0.3, 0.4, 0.1) * eps)),
            ],
        };
        let loc = el.local(&n);
        let [t1, t2] = loc.theta;
        let cubic = 0.5 * (n.x[0] + n.x[1])
            + loc.rr * Vector3::new(0.0, t1.z - t2.z, -(t1.y - t2.y)) * (el.length() / 8.0);
        let offset = (cubic - 0.5 * (n.x[0] + n.x[1])).norm();
        let err = (cubic - el.centre_line(&n, 0.5)).norm();
        // first-order offset, second-order difference
        assert!(offset > 0.05 * eps * el.length(), "offset {offset}");
        assert!(
            err < eps * offset,
            "eps {eps}: difference {err} vs offset {offset}"
        );
    }
}

/// Chain to incremental rotation vectors: with `R = R_ref exp(θ̃)`, the derivative with
/// respect to θ is the body-spin tangent times `T(θ)`.
#[test]
fn chain_to_rotation_vectors() {
    let (el, n0) = element(Theory::Timoshenko, MassModel::Lumped);
    let n = deformed(&n0);
    let theta = [Vector3::new(0.5, -1.2, 2.0), Vector3::new(-0.1, 0.3, 0.2)];
    let at = |th: [Vector3<f64>; 2]| Nodes {
        x: n.x,
        r: [n.r[0] * exp_so3(&th[0]), n.r[1] * exp_so3(&th[1])],
    };
    let cur = at(theta);
    let mut f = Vec12::zeros();
    let mut k = Mat12::zeros();
    el.internal_force_tangent(&cur, &mut f, &mut k);
    let h = 1e-7;
    for node in 0..2 {
        let t = tangent_body(&theta[node]);
        let chained = k.fixed_view::<12, 3>(0, 6 * node + 3) * t;
        for c in 0..3 {
            let (mut tp, mut tm) = (theta, theta);
            tp[node][c] += h;
            tm[node][c] -= h;
            let (mut fp, mut fm) = (Vec12::zeros(), Vec12::zeros());
            el.internal_force(&at(tp), &mut fp);
            el.internal_force(&at(tm), &mut fm);
            let fd = (fp - fm) / (2.0 * h);
            let err = (fd - chained.column(c)).norm() / k.norm();
            assert!(err < 1e-7, "node {node} component {c}: {err}");
        }
    }
}

/// Element coordinates `[x1, θ1, x2, θ2]` of nodes with stored orientations `r_ref` and
/// incremental rotation vectors `theta`.
fn config(label: &'static str, n: &Nodes, theta: [Vector3<f64>; 2]) -> Config<ELEMENT_DOFS> {
    let mut q = Vec12::zeros();
    for i in 0..2 {
        q.fixed_rows_mut::<3>(6 * i).copy_from(&n.x[i]);
        q.fixed_rows_mut::<3>(6 * i + 3).copy_from(&theta[i]);
    }
    let r_ref = (0..2).map(|i| n.r[i] * exp_so3(&-theta[i])).collect();
    Config::at(label, q).frames(r_ref)
}

/// The element in the states of the conformance checks: reference, the large deformed state
/// (with θ = 0 and with large incremental rotation vectors θ, which exercises the chain with
/// `T(θ)`), the deformed state turned by a rigid rotation and moved, and a 1 % stretch; moving
/// (gyroscopic and configuration terms of the inertia).
fn case(theory: Theory, mass: MassModel) -> Case<Corot3d, ELEMENT_DOFS> {
    let (el, n0) = element(theory, mass);
    let v = Vec12::from_column_slice(&[
        0.3, -0.2, 0.5, 1.5, -0.7, 2.0, -0.1, 0.4, 0.2, -1.0, 0.8, 1.7,
    ]);
    let a = Vec12::from_column_slice(&[
        1.0, 0.5, -0.3, -2.0, 0.6, 0.9, 0.2, -0.8, 0.6, 1.3, -0.4, 0.7,
    ]);
    let zero = [Vector3::zeros(); 2];
    let bent = config("bent", &deformed(&n0), zero).moving(v, a);
    let incremental = config(
        "bent, large incremental rotations",
        &deformed(&n0),
        [Vector3::new(0.5, -1.2, 2.0), Vector3::new(-0.1, 0.3, 0.2)],
    )
    .moving(v, a);
    let q = exp_so3(&Vector3::new(-2.0, 0.7, 1.9));
    let mut turned = rigid_motion(&el.layout(), &bent, &q, &Vector3::new(5.0, -3.0, 1.0));
    turned.label = "bent, turned rigidly";
    let mut stretched = n0;
    stretched.x[1] = n0.x[0] + (n0.x[1] - n0.x[0]) * 1.01;
    Case {
        states: vec![
            config("reference", &n0, zero).moving(v, a),
            bent,
            incremental,
            turned,
            config("stretched", &stretched, zero),
        ],
        element: el,
    }
}

element_conformance!(conformance_timoshenko_lumped, || case(
    Theory::Timoshenko,
    MassModel::Lumped
));
element_conformance!(conformance_euler_bernoulli_consistent, || case(
    Theory::EulerBernoulli,
    MassModel::Consistent
));

/// The conformance case with the bowing term on (issue 13): the bent states have local
/// rotations of a few tenths of a radian, so the term and its tangent are exercised.
fn bowing_case(theory: Theory, mass: MassModel) -> Case<Corot3d, ELEMENT_DOFS> {
    let mut c = case(theory, mass);
    c.element = c.element.with_bowing(true);
    c
}

element_conformance!(conformance_timoshenko_lumped_bowing, || bowing_case(
    Theory::Timoshenko,
    MassModel::Lumped
));
element_conformance!(conformance_euler_bernoulli_consistent_bowing, || {
    bowing_case(Theory::EulerBernoulli, MassModel::Consistent)
});

/// Bowing term: an element whose nodes lie on a circle of radius R, 2π/36 apart, with the
/// node frames along the circle's tangents (a belt mounted on a pulley at its stress-free
/// length = the arc). Reference: the arc length R Δφ is the element's length, so the strain
/// must vanish; the chord alone gives `2 sin(Δφ/2)/Δφ − 1 = −Δφ²/24 + Δφ⁴/1920` (Taylor
/// series), the bowing term cancels the `Δφ²` part (Crisfield vol. 1 §7), leaving `Δφ⁴/1920`.
#[test]
fn bowing_restores_the_arc_length() {
    let s = section();
    let r = 0.1;
    for (plane, axis) in [("z", Vector3::z()), ("y", Vector3::y())] {
        for n_el in [36.0, 72.0] {
            let dphi = 2.0 * std::f64::consts::PI / n_el;
            let l0 = r * dphi;
            // chord along x; the end tangents turned by ∓Δφ/2 about the bending axis
            let half = 0.5 * dphi;
            let chord = 2.0 * r * half.sin();
            let nodes = Nodes {
                x: [Vector3::zeros(), Vector3::new(chord, 0.0, 0.0)],
                r: [exp_so3(&(axis * half)), exp_so3(&(-axis * half))],
            };
            let el = Corot3d::new(
                l0,
                Matrix3::identity(),
                &s,
                Theory::Timoshenko,
                MassModel::Lumped,
            );
            let chord_strain = el.axial_force(&nodes) / s.ea;
            let expect = 2.0 * half.sin() / dphi - 1.0;
            assert!(
                (chord_strain - expect).abs() < 1e-14,
                "{plane}, {n_el}: chord strain {chord_strain:e} vs {expect:e}"
            );
            let bowed = el.with_bowing(true).axial_force(&nodes) / s.ea;
            let residual = dphi.powi(4) / 1920.0;
            assert!(
                (bowed - residual).abs() < 0.05 * residual,
                "{plane}, {n_el}: strain with bowing {bowed:e}, expected {residual:e} \
                 (chord alone {chord_strain:e})"
            );
        }
    }
}
