//! ANCF cable: conformance, closed-form mass and gravity, strains of a stretch and an arc,
//! damping power.

use crate::element_conformance;
use crate::elements::Element;
use crate::elements::ancf_cable2d::*;
use crate::elements::conformance::{Case, Config, rigid_motion};
use crate::elements::finite_difference as fd;
use nalgebra::{Matrix3, Rotation2, Vector2, Vector3};

fn dmat(r: usize, c: usize, x: &[f64]) -> nalgebra::DMatrix<f64> {
    nalgebra::DMatrix::from_column_slice(r, c, x)
}

const RULES: [CableRule; 3] = [CableRule::Full, CableRule::Reduced, CableRule::Mixed];

fn section() -> CableSection {
    CableSection {
        ea: 5e4,
        ei: 0.8,
        mass_per_length: 0.2,
        damping_axial: 0.0,
        damping_bending: 0.0,
        prestrain: 0.0,
    }
}

fn damped() -> CableSection {
    CableSection {
        damping_axial: 30.0,
        damping_bending: 2e-3,
        prestrain: -0.01,
        ..section()
    }
}

const L: f64 = 0.3;

fn reference() -> ElemVec {
    straight_coordinates(Vector2::new(0.1, -0.2), Vector2::new(0.1 + L, -0.2), 1.0)
}

/// A stretched, bent configuration with rotated slopes.
fn deformed() -> ElemVec {
    reference() + ElemVec::from_column_slice(&[2e-3, -1e-3, 0.02, 0.15, 4e-3, 0.03, -0.05, -0.1])
}

fn rigid(q: &ElemVec, angle: f64, t: Vector2<f64>) -> ElemVec {
    let r = Rotation2::new(angle);
    let mut out = ElemVec::zeros();
    for a in 0..4 {
        let v = r * Vector2::new(q[2 * a], q[2 * a + 1]);
        let v = if a % 2 == 0 { v + t } else { v };
        out[2 * a] = v.x;
        out[2 * a + 1] = v.y;
    }
    out
}

/// Closed-form consistent mass of the Hermite cubic (Przemieniecki; Shabana, Dynamics of
/// Multibody Systems, ANCF cable): `ρA L/420 [[156, 22L, 54, −13L], [22L, 4L², 13L, −3L²],
/// [54, 13L, 156, −22L], [−13L, −3L², −22L, 4L²]] ⊗ I₂`.
#[test]
fn mass_matches_closed_form() {
    let el = AncfCable2d::new(L, section(), CableRule::Full);
    let f = 0.2 * L / 420.0;
    let m4 = nalgebra::Matrix4::new(
        156.0,
        22.0 * L,
        54.0,
        -13.0 * L,
        22.0 * L,
        4.0 * L * L,
        13.0 * L,
        -3.0 * L * L,
        54.0,
        13.0 * L,
        156.0,
        -22.0 * L,
        -13.0 * L,
        -3.0 * L * L,
        -22.0 * L,
        4.0 * L * L,
    ) * f;
    let m = el.mass();
    for a in 0..4 {
        for b in 0..4 {
            for i in 0..2 {
                for j in 0..2 {
                    let expect = if i == j { m4[(a, b)] } else { 0.0 };
                    let got = m[(2 * a + i, 2 * b + j)];
                    assert!(
                        (got - expect).abs() <= 1e-14,
                        "M[{a}{i},{b}{j}] {got} {expect}"
                    );
                }
            }
        }
    }
    // total mass: a rigid translation u gives uᵀ M u = ρA L |u|²
    let mut u = ElemVec::zeros();
    for a in [0, 2] {
        u[2 * a] = 1.0;
    }
    assert!((u.dot(&(m * u)) - 0.2 * L).abs() < 1e-14);
}

/// Gravity against the closed form ρA L [g/2, L g/12, g/2, −L g/12] and against M·(rigid
/// translation by g).
#[test]
fn gravity_matches_mass_times_translation() {
    let el = AncfCable2d::new(L, section(), CableRule::Full);
    let g = Vector2::new(0.5, -9.81);
    let qg = el.gravity(g);
    let mut u = ElemVec::zeros();
    for a in [0, 2] {
        u[2 * a] = g.x;
        u[2 * a + 1] = g.y;
    }
    let mu = el.mass() * u;
    assert!((qg - mu).norm() < 1e-14, "{qg} vs {mu}");
}

/// Zero strains, energy and force in the reference configuration and under rigid motion.
#[test]
fn rigid_motion_is_strain_free() {
    for rule in RULES {
        let el = AncfCable2d::new(L, section(), rule);
        for (angle, t) in [
            (0.0, Vector2::zeros()),
            (0.7, Vector2::new(3.0, -1.0)),
            (std::f64::consts::PI, Vector2::new(-2.0, 5.0)),
            (-2.5, Vector2::new(0.1, 0.2)),
            (7.0, Vector2::new(100.0, 0.0)),
        ] {
            let q = rigid(&reference(), angle, t);
            let mut f = ElemVec::zeros();
            let u = el.internal_force(&q, &ElemVec::zeros(), &mut f);
            assert!(u.abs() < 1e-20, "U = {u}");
            assert!(f.norm() < 1e-12 * 5e4, "|Q| = {}", f.norm());
            for x in [0.0, 0.1, 0.3] {
                let (e, k) = el.strains_at(&q, x);
                assert!(e.abs() < 1e-13 && k.abs() < 1e-10, "{e} {k}");
            }
        }
    }
}

/// Energy and strains are invariant under rigid motion of a deformed configuration.
#[test]
fn deformed_energy_is_invariant_under_rigid_motion() {
    for rule in RULES {
        let el = AncfCable2d::new(L, section(), rule);
        let u0 = el.strain_energy(&deformed());
        let u1 = el.strain_energy(&rigid(&deformed(), 1.3, Vector2::new(-4.0, 2.0)));
        assert!((u0 - u1).abs() <= 1e-11 * u0, "{u0} {u1}");
        assert!(u0 > 0.0);
    }
}

/// Uniform stretch λ: ε = λ − 1, U = ½EA(λ−1)²L. Circular arc of radius R traversed at
/// unit speed: K = 1/R (checked on an element interpolating the arc: Hermite data exact at
/// the nodes).
#[test]
fn strains_of_stretch_and_arc() {
    let el = AncfCable2d::new(L, section(), CableRule::Full);
    let lam = 1.02;
    let q = straight_coordinates(Vector2::zeros(), Vector2::new(L * lam, 0.0), lam);
    let u = el.strain_energy(&q);
    let expect = 0.5 * 5e4 * (lam - 1.0f64).powi(2) * L;
    assert!((u - expect).abs() <= 1e-12 * expect);
    assert!((el.axial_force(&q, 0.13) - 5e4 * 0.02).abs() < 1e-9);
    // arc: r(s) = R(sin(s/R), 1 − cos(s/R)), r' = (cos, sin)
    let r = 0.5;
    let phi = L / r;
    let q = ElemVec::from_column_slice(&[
        0.0,
        0.0,
        1.0,
        0.0,
        r * phi.sin(),
        r * (1.0 - phi.cos()),
        phi.cos(),
        phi.sin(),
    ]);
    for x in [0.0, 0.5 * L, L] {
        let (e, k) = el.strains_at(&q, x);
        // cubic interpolation of an arc of 0.6 rad: errors of a few 1e-3
        assert!(e.abs() < 5e-3, "ε = {e}");
        assert!((k * r - 1.0).abs() < 3e-2, "K R = {}", k * r);
    }
}

/// The internal force is the gradient of the strain energy (no damping).
#[test]
fn force_matches_energy_gradient() {
    for rule in RULES {
        for sec in [
            section(),
            CableSection {
                prestrain: -0.01,
                ..section()
            },
        ] {
            let el = AncfCable2d::new(L, sec, rule);
            let q = deformed();
            let mut f = ElemVec::zeros();
            el.internal_force(&q, &ElemVec::zeros(), &mut f);
            let g = fd::gradient(
                q.as_slice(),
                |_| 1e-6,
                |x| el.strain_energy(&ElemVec::from_column_slice(x)),
            );
            fd::assert_close(
                &format!("{rule:?}: force vs energy gradient"),
                &dmat(8, 1, f.as_slice()),
                &dmat(8, 1, &g),
                1e-6,
                0.0,
            );
        }
    }
}

/// Tangent stiffness and damping matrix against central differences of the force, with
/// material damping and pre-strain.
#[test]
fn tangent_and_damping_match_finite_differences() {
    for rule in RULES {
        for sec in [section(), damped()] {
            let el = AncfCable2d::new(L, sec, rule);
            let q = deformed();
            let qd = ElemVec::from_column_slice(&[0.3, -0.2, 0.5, 1.0, -0.4, 0.1, 0.7, -0.3]);
            let (mut f, mut k, mut c) = (ElemVec::zeros(), ElemMat::zeros(), ElemMat::zeros());
            el.internal_force_tangent(&q, &qd, &mut f, &mut k, &mut c);
            let mut f2 = ElemVec::zeros();
            el.internal_force(&q, &qd, &mut f2);
            assert!((f - f2).norm() <= 1e-12 * f.norm());
            let force = |q: &[f64], v: &[f64], out: &mut [f64]| {
                let mut fx = ElemVec::zeros();
                let (q, v) = (ElemVec::from_column_slice(q), ElemVec::from_column_slice(v));
                el.internal_force(&q, &v, &mut fx);
                out.copy_from_slice(fx.as_slice());
            };
            fd::assert_jacobian(
                &format!("{rule:?}: tangent"),
                &dmat(8, 8, k.as_slice()),
                q.as_slice(),
                1e-7,
                1e-6,
                |x, out| force(x, qd.as_slice(), out),
            );
            if sec.damping_axial > 0.0 {
                fd::assert_jacobian(
                    &format!("{rule:?}: damping matrix"),
                    &dmat(8, 8, c.as_slice()),
                    qd.as_slice(),
                    1e-7,
                    1e-6,
                    |x, out| force(q.as_slice(), x, out),
                );
            } else {
                assert_eq!(c, ElemMat::zeros());
                // without damping the tangent is symmetric (a Hessian)
                assert!((k - k.transpose()).norm() <= 1e-10 * k.norm());
            }
        }
    }
}

/// Damping power equals Q_d·q̇ (the force of the damping stresses times the velocity).
#[test]
fn damping_power_is_force_times_velocity() {
    let el = AncfCable2d::new(L, damped(), CableRule::Full);
    let q = deformed();
    let qd = ElemVec::from_column_slice(&[0.3, -0.2, 0.5, 1.0, -0.4, 0.1, 0.7, -0.3]);
    let (mut f1, mut f0) = (ElemVec::zeros(), ElemVec::zeros());
    el.internal_force(&q, &qd, &mut f1);
    el.internal_force(&q, &ElemVec::zeros(), &mut f0);
    let p = (f1 - f0).dot(&qd);
    let pd = el.damping_power(&q, &qd);
    assert!((p - pd).abs() <= 1e-12 * pd.abs(), "{p} {pd}");
    assert!(pd > 0.0);
}

/// The cable in the states of the conformance checks: reference, bent and stretched with
/// rotated slopes, the bent state turned by 1.3 rad and moved, a 2 % stretch; moving (material
/// damping).
fn case(rule: CableRule, sec: CableSection) -> Case<AncfCable2d, ELEMENT_COORDS> {
    let el = AncfCable2d::new(L, sec, rule);
    let v = ElemVec::from_column_slice(&[0.3, -0.2, 0.5, 1.0, -0.4, 0.1, 0.7, -0.3]);
    let a = ElemVec::from_column_slice(&[1.0, 0.5, -0.3, -2.0, 0.6, 0.9, 0.2, -0.8]);
    let bent = Config::at("bent", deformed()).moving(v, a);
    let q = Matrix3::from(nalgebra::Rotation3::from_axis_angle(
        &Vector3::z_axis(),
        1.3,
    ));
    let mut turned = rigid_motion(&el.layout(), &bent, &q, &Vector3::new(-4.0, 2.0, 0.0));
    turned.label = "bent, turned by 1.3 rad";
    let lam = 1.02;
    let stretched = straight_coordinates(Vector2::zeros(), Vector2::new(L * lam, 0.0), lam);
    Case {
        states: vec![
            Config::at("reference", reference()).moving(v, a),
            bent,
            turned,
            Config::at("stretched", stretched).moving(v, a),
        ],
        element: el,
    }
}

element_conformance!(conformance_full, || case(CableRule::Full, section()));
element_conformance!(conformance_reduced_damped, || case(
    CableRule::Reduced,
    damped()
));
element_conformance!(conformance_mixed_damped, || case(
    CableRule::Mixed,
    damped()
));

// ---------------------------------------------------------------------------------------------
// Axially moving (ALE) terms (design note "ale", Pechstein & Gerstmayr 2013)
// ---------------------------------------------------------------------------------------------

/// `Σ_a s_a q_a` (the test's own copy of the field sum).
fn field(s: &[f64; 4], q: &ElemVec) -> Vector2<f64> {
    (0..4).fold(Vector2::zeros(), |acc, a| {
        acc + s[a] * Vector2::new(q[2 * a], q[2 * a + 1])
    })
}

/// A 4×4 node matrix times I₂ as an 8×8 element matrix.
fn kron2(m4: &nalgebra::Matrix4<f64>) -> ElemMat {
    let mut m = ElemMat::zeros();
    for a in 0..4 {
        for b in 0..4 {
            m[(2 * a, 2 * b)] = m4[(a, b)];
            m[(2 * a + 1, 2 * b + 1)] = m4[(a, b)];
        }
    }
    m
}

/// `H = ρA ∫ S'ᵀ S' dx` is the geometric-stiffness matrix of the Hermite cubic (Przemieniecki,
/// Theory of Matrix Structural Analysis, 1968, §15: `1/(30L) [[36, 3L, −36, 3L], [3L, 4L²,
/// −3L, −L²], [−36, −3L, 36, −3L], [3L, −L², −3L, 4L²]]`); `G + Gᵀ = ρA [Sᵀ S]₀ᴸ` (S(0) and S(L)
/// pick the node positions); a rigid translation has no slope (`G u = H u = 0`); a straight
/// line `r = p + a x` gives `G q = ρA ∫ Sᵀ dx ⊗ a = ρA L [1/2, L/12, 1/2, −L/12] ⊗ a`.
#[test]
fn ale_band_matches_closed_forms() {
    let rho = 0.2;
    let band = ale_band(L, rho);
    let h4 = nalgebra::Matrix4::new(
        36.0,
        3.0 * L,
        -36.0,
        3.0 * L,
        3.0 * L,
        4.0 * L * L,
        -3.0 * L,
        -L * L,
        -36.0,
        -3.0 * L,
        36.0,
        -3.0 * L,
        3.0 * L,
        -L * L,
        -3.0 * L,
        4.0 * L * L,
    ) * (rho / (30.0 * L));
    let h = kron2(&h4);
    assert!(
        (band.h - h).norm() <= 1e-13 * h.norm(),
        "H\n{}\n{h}",
        band.h
    );
    let mut ends = nalgebra::Matrix4::zeros();
    ends[(2, 2)] = rho;
    ends[(0, 0)] = -rho;
    let sym = band.g + band.g.transpose();
    assert!((sym - kron2(&ends)).norm() <= 1e-14, "G + Gᵀ\n{sym}");
    let mut u = ElemVec::zeros();
    for a in [0, 2] {
        u[2 * a] = 0.7;
        u[2 * a + 1] = -1.1;
    }
    assert!((band.g * u).norm() <= 1e-15 && (band.h * u).norm() <= 1e-15);
    let a = Vector2::new(0.6, 0.8) * 1.03;
    let q = straight_coordinates(Vector2::new(0.2, 0.1), Vector2::new(0.2, 0.1) + L * a, 1.03);
    let gq = band.g * q;
    let f = [0.5 * L, L * L / 12.0, 0.5 * L, -L * L / 12.0];
    for k in 0..4 {
        for i in 0..2 {
            let expect = rho * f[k] * a[i];
            assert!((gq[2 * k + i] - expect).abs() <= 1e-15, "G q [{k}{i}]");
        }
    }
}

/// The ALE inertia force equals `ρA ∫ Sᵀ a dx` of the material acceleration
/// `a = S q̈ + v̇ r' + 2 v S' q̇ + v² r''` (5-point Gauss: exact, degree 5) minus the boundary
/// term `ρA v² [Sᵀ r']₀ᴸ` that cancels round a closed loop (the by-parts form of `H`).
#[test]
fn ale_inertia_is_the_material_acceleration() {
    let rho = 0.2;
    let band = ale_band(L, rho);
    let m = consistent_mass(L, rho);
    let q = deformed();
    let qd = ElemVec::from_column_slice(&[0.3, -0.2, 0.5, 1.0, -0.4, 0.1, 0.7, -0.3]);
    let qdd = ElemVec::from_column_slice(&[1.0, 0.5, -0.3, -2.0, 0.6, 0.9, 0.2, -0.8]);
    let rates = AleRates {
        v: 17.0,
        v_dot: -40.0,
    };
    let mut f = ElemVec::zeros();
    ale_inertia_into(&m, &band, &q, &qd, &qdd, rates, &mut f, None);
    let mut expect = ElemVec::zeros();
    for &(p, w) in crate::elements::quadrature::gauss_legendre(5) {
        let x = 0.5 * (p + 1.0) * L;
        let (s, d1, d2) = (shape_functions(L, x), shape_d1(L, x), shape_d2(L, x));
        let acc = field(&s, &qdd)
            + rates.v_dot * field(&d1, &q)
            + 2.0 * rates.v * field(&d1, &qd)
            + rates.v * rates.v * field(&d2, &q);
        for a in 0..4 {
            expect[2 * a] += rho * w * 0.5 * L * s[a] * acc.x;
            expect[2 * a + 1] += rho * w * 0.5 * L * s[a] * acc.y;
        }
    }
    for (x, sign) in [(0.0, -1.0), (L, 1.0)] {
        let (s, rp) = (shape_functions(L, x), field(&shape_d1(L, x), &q));
        for a in 0..4 {
            expect[2 * a] -= sign * rho * rates.v * rates.v * s[a] * rp.x;
            expect[2 * a + 1] -= sign * rho * rates.v * rates.v * s[a] * rp.y;
        }
    }
    assert!(
        (f - expect).norm() <= 1e-12 * expect.norm(),
        "{f}\n{expect}"
    );
}

/// The partial derivatives of the ALE inertia force against central differences in `q`, `q̇`,
/// `v` and `v̇`.
#[test]
fn ale_inertia_tangent_matches_finite_differences() {
    let rho = 0.2;
    let band = ale_band(L, rho);
    let m = consistent_mass(L, rho);
    let q = deformed();
    let qd = ElemVec::from_column_slice(&[0.3, -0.2, 0.5, 1.0, -0.4, 0.1, 0.7, -0.3]);
    let qdd = ElemVec::from_column_slice(&[1.0, 0.5, -0.3, -2.0, 0.6, 0.9, 0.2, -0.8]);
    // x = [q, q̇, v, v̇]
    let mut x0 = q.as_slice().to_vec();
    x0.extend_from_slice(qd.as_slice());
    x0.extend_from_slice(&[17.0, -40.0]);
    let force = |x: &[f64], out: &mut [f64]| {
        let mut f = ElemVec::zeros();
        let rates = AleRates {
            v: x[16],
            v_dot: x[17],
        };
        ale_inertia_into(
            &m,
            &band,
            &ElemVec::from_column_slice(&x[..8]),
            &ElemVec::from_column_slice(&x[8..16]),
            &qdd,
            rates,
            &mut f,
            None,
        );
        out.copy_from_slice(f.as_slice());
    };
    let mut t = AleInertiaTangent::default();
    let mut f = ElemVec::zeros();
    let rates = AleRates {
        v: 17.0,
        v_dot: -40.0,
    };
    ale_inertia_into(&m, &band, &q, &qd, &qdd, rates, &mut f, Some(&mut t));
    let mut analytic = nalgebra::DMatrix::zeros(8, 18);
    analytic.view_mut((0, 0), (8, 8)).copy_from(&t.k);
    analytic.view_mut((0, 8), (8, 8)).copy_from(&t.c);
    analytic.view_mut((0, 16), (8, 1)).copy_from(&t.dv);
    analytic.view_mut((0, 17), (8, 1)).copy_from(&t.dv_dot);
    fd::assert_jacobian("ALE inertia", &analytic, &x0, 1e-5, 1e-8, force);
    // v = v̇ = 0: the Lagrangian inertia M q̈
    let mut f0 = ElemVec::zeros();
    ale_inertia_into(&m, &band, &q, &qd, &qdd, AleRates::default(), &mut f0, None);
    assert_eq!(f0, m * qdd);
}

/// `ε'(x)` by central differences of [`AncfCable2d::strains_at`] along the element.
fn strain_slope(el: &AncfCable2d, q: &ElemVec, x: f64) -> f64 {
    let h = 1e-5 * L;
    (el.strains_at(q, x + h).0 - el.strains_at(q, x - h).0) / (2.0 * h)
}

/// Axial quadrature of a rule on [0, L]: points and weights [m].
fn axial_points(rule: CableRule) -> Vec<(f64, f64)> {
    use crate::elements::quadrature::{gauss_legendre, lobatto3};
    let r = match rule {
        CableRule::Full => gauss_legendre(5),
        CableRule::Reduced => gauss_legendre(4),
        CableRule::Mixed => lobatto3(),
    };
    r.iter()
        .map(|&(p, w)| (0.5 * (p + 1.0) * L, 0.5 * w * L))
        .collect()
}

/// The convective damping force is `∫ d_ε v ε' ∂ε/∂q dx` with `ε'` the slope of the strain
/// along the element (central differences of the strain, not the kernel's `u·r''`) on the
/// rule's axial points; zero at `v = 0` and without damping; its power with the Lagrangian
/// rate is the material rate's `∫ d_ε (ε̇ + v ε')² dx`.
#[test]
fn convective_damping_is_the_material_strain_rate() {
    let v = 13.0;
    let q = deformed();
    let qd = ElemVec::from_column_slice(&[0.3, -0.2, 0.5, 1.0, -0.4, 0.1, 0.7, -0.3]);
    for rule in RULES {
        let el = AncfCable2d::new(L, damped(), rule);
        let mut f = ElemVec::zeros();
        el.convective_damping_into(&q, v, &mut f, None);
        let (mut expect, mut power) = (ElemVec::zeros(), 0.0);
        for (x, w) in axial_points(rule) {
            let (de, _) = el.strain_gradients_at(&q, x);
            let eps_x = strain_slope(&el, &q, x);
            expect += (w * 30.0 * v * eps_x) * de;
            let rate = de.dot(&qd) + v * eps_x;
            power += w * 30.0 * rate * rate;
        }
        assert!(
            (f - expect).norm() <= 1e-7 * expect.norm(),
            "{rule:?}: {f}\n{expect}"
        );
        let p = el.ale_damping_power(&q, &qd, v);
        assert!((p - power).abs() <= 1e-7 * power, "{rule:?}: {p} {power}");
        let pl = el.ale_damping_power(&q, &qd, 0.0);
        let (mut lag, mut lag_bending_free) = (0.0, ElemVec::zeros());
        let el_axial = AncfCable2d::new(
            L,
            CableSection {
                damping_bending: 0.0,
                ..damped()
            },
            rule,
        );
        el_axial.internal_force(&q, &qd, &mut lag_bending_free);
        let mut f0 = ElemVec::zeros();
        el_axial.internal_force(&q, &ElemVec::zeros(), &mut f0);
        lag += (lag_bending_free - f0).dot(&qd);
        assert!((pl - lag).abs() <= 1e-12 * lag, "{rule:?}: {pl} {lag}");
        let mut z = ElemVec::zeros();
        el.convective_damping_into(&q, 0.0, &mut z, None);
        assert_eq!(z, ElemVec::zeros());
        AncfCable2d::new(L, section(), rule).convective_damping_into(&q, v, &mut z, None);
        assert_eq!(z, ElemVec::zeros());
    }
}

/// The tangent of the convective damping force in `q` and its derivative in `v` against
/// central differences; the tangent is added to what the caller's matrix holds.
#[test]
fn convective_damping_tangent_matches_finite_differences() {
    let v = 13.0;
    let q = deformed();
    for rule in RULES {
        let el = AncfCable2d::new(L, damped(), rule);
        let mut x0 = q.as_slice().to_vec();
        x0.push(v);
        let force = |x: &[f64], out: &mut [f64]| {
            let mut f = ElemVec::zeros();
            el.convective_damping_into(&ElemVec::from_column_slice(&x[..8]), x[8], &mut f, None);
            out.copy_from_slice(f.as_slice());
        };
        let mut f = ElemVec::zeros();
        let base = ElemMat::from_element(0.25);
        let (mut k, mut dv) = (base, ElemVec::zeros());
        el.convective_damping_into(&q, v, &mut f, Some((&mut k, &mut dv)));
        let mut analytic = nalgebra::DMatrix::zeros(8, 9);
        analytic.view_mut((0, 0), (8, 8)).copy_from(&(k - base));
        analytic.view_mut((0, 8), (8, 1)).copy_from(&dv);
        fd::assert_jacobian(
            &format!("{rule:?}: convective damping"),
            &analytic,
            &x0,
            1e-7,
            1e-6,
            force,
        );
    }
}

/// The streamline-upwind weighting of the convective damping: its tangent in `q` and its
/// derivative in `v` against central differences (at both signs of `v`), added to what the
/// caller's matrix holds; its power is `q̇·f_u`; its coefficient is `(d v)² L/(EA L + 2 d |v|)`
/// (even in `v`), and it vanishes without damping or for a uniformly strained straight element;
/// the fused kernel is the sum of the Galerkin part and the upwinding.
#[test]
fn convective_upwinding_tangent_matches_finite_differences() {
    let q = deformed();
    let qd = ElemVec::from_column_slice(&[0.3, -0.2, 0.5, 1.0, -0.4, 0.1, 0.7, -0.3]);
    for v in [13.0, -7.0] {
        for rule in RULES {
            let el = AncfCable2d::new(L, damped(), rule);
            let s = damped();
            let (c, _) = el.upwinding_coefficient(v);
            let expect =
                (s.damping_axial * v).powi(2) * L / (s.ea * L + 2.0 * s.damping_axial * v.abs());
            assert!((c - expect).abs() <= 1e-14 * expect, "{c} {expect}");
            let mut x0 = q.as_slice().to_vec();
            x0.push(v);
            let force = |x: &[f64], out: &mut [f64]| {
                let mut f = ElemVec::zeros();
                el.convective_upwinding_into(
                    &ElemVec::from_column_slice(&x[..8]),
                    x[8],
                    &mut f,
                    None,
                );
                out.copy_from_slice(f.as_slice());
            };
            let mut f = ElemVec::zeros();
            let base = ElemMat::from_element(0.25);
            let (mut k, mut dv) = (base, ElemVec::from_element(0.5));
            let (mut k2, mut dv2) = (base, ElemVec::zeros());
            el.convective_upwinding_into(&q, v, &mut f, Some((&mut k, &mut dv)));
            assert!(f.norm() > 0.0);
            let mut analytic = nalgebra::DMatrix::zeros(8, 9);
            analytic.view_mut((0, 0), (8, 8)).copy_from(&(k - base));
            analytic.view_mut((0, 8), (8, 1)).copy_from(&dv);
            // together with the Galerkin part: the sum of the two
            let mut f2 = ElemVec::zeros();
            el.convective_damping_upwinded_into(&q, v, &mut f2, Some((&mut k2, &mut dv2)));
            let (mut f3, mut k3, mut dv3) = (ElemVec::zeros(), ElemMat::zeros(), ElemVec::zeros());
            el.convective_damping_into(&q, v, &mut f3, Some((&mut k3, &mut dv3)));
            assert!((f2 - f3 - f).norm() <= 1e-12 * f2.norm());
            assert!((k2 - base - k3 - (k - base)).norm() <= 1e-12 * k2.norm());
            assert!((dv2 - dv3 - dv).norm() <= 1e-12 * dv2.norm());
            fd::assert_jacobian(
                &format!("{rule:?}, v = {v}: convective upwinding"),
                &analytic,
                &x0,
                1e-7,
                1e-6,
                force,
            );
            let p = el.upwinding_power(&q, &qd, v);
            assert!(
                (p - f.dot(&qd)).abs() <= 1e-10 * f.norm() * qd.norm(),
                "{p}"
            );
            // uniform strain along a straight element: nothing
            let straight = straight_coordinates(
                Vector2::new(0.1, 0.2),
                Vector2::new(0.1 + 0.606 * L, 0.2 + 0.808 * L),
                1.01,
            );
            let mut z = ElemVec::zeros();
            el.convective_upwinding_into(&straight, v, &mut z, None);
            assert!(z.norm() <= 1e-12, "{z}");
            AncfCable2d::new(L, section(), rule).convective_upwinding_into(&q, v, &mut z, None);
            assert!(z.norm() <= 1e-12, "{z}");
        }
    }
}

/// Round a closed loop the boundary terms cancel (the premise of the ALE belt's band matrices):
/// on a ring of 12 elements wrapping an ellipse (C¹ at the nodes), the assembled `G` is skew
/// and the assembled `−H q` equals the assembled `ρA ∫ Sᵀ r'' dx` (5-point Gauss, exact); on
/// one element alone neither holds.
#[test]
fn ale_band_boundary_terms_cancel_round_a_closed_loop() {
    let (n, rho) = (12, 0.2);
    let (a, b) = (0.4, 0.25);
    let l = 0.19;
    let band = ale_band(l, rho);
    // node k at angle 2πk/n, slope the ellipse's tangent scaled to the element
    let node = |k: usize| {
        let t = std::f64::consts::TAU * (k % n) as f64 / n as f64;
        let scale = n as f64 * l / std::f64::consts::TAU;
        [
            a * t.cos(),
            b * t.sin(),
            -a * t.sin() / scale,
            b * t.cos() / scale,
        ]
    };
    let dim = 4 * n;
    let (mut g, mut hq, mut direct) = (
        nalgebra::DMatrix::<f64>::zeros(dim, dim),
        nalgebra::DVector::<f64>::zeros(dim),
        nalgebra::DVector::<f64>::zeros(dim),
    );
    for e in 0..n {
        let (p0, p1) = (node(e), node(e + 1));
        let q =
            ElemVec::from_column_slice(&[p0[0], p0[1], p0[2], p0[3], p1[0], p1[1], p1[2], p1[3]]);
        let dofs: Vec<usize> = (0..8).map(|i| (4 * e + i) % dim).collect();
        let hqe = band.h * q;
        let mut de = ElemVec::zeros();
        for &(p, w) in crate::elements::quadrature::gauss_legendre(5) {
            let x = 0.5 * (p + 1.0) * l;
            let (s, rpp) = (shape_functions(l, x), field(&shape_d2(l, x), &q));
            for k in 0..4 {
                de[2 * k] += rho * w * 0.5 * l * s[k] * rpp.x;
                de[2 * k + 1] += rho * w * 0.5 * l * s[k] * rpp.y;
            }
        }
        if e == 0 {
            assert!(
                (hqe + de).norm() > 1e-3 * de.norm(),
                "one element: by parts needs its ends"
            );
        }
        for i in 0..8 {
            hq[dofs[i]] -= hqe[i];
            direct[dofs[i]] += de[i];
            for j in 0..8 {
                g[(dofs[i], dofs[j])] += band.g[(i, j)];
            }
        }
    }
    let skew = &g + g.transpose();
    assert!(
        skew.norm() <= 1e-15 * g.norm().max(1.0),
        "G + Gᵀ = {}",
        skew.norm()
    );
    assert!((band.g + band.g.transpose()).norm() > 0.1 * rho);
    assert!(
        (&hq - &direct).norm() <= 1e-12 * direct.norm(),
        "−H q {} vs ∫ Sᵀ r'' {}",
        hq.norm(),
        direct.norm()
    );
}
