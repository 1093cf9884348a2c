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
