//! Seed-000 element: conformance, closed-form mass and gravity, average-stress force, energy of
//! a stretch.

use crate::element_conformance;
use crate::elements::Element;
use crate::elements::ancf_shear2d::*;
use crate::elements::conformance::{Case, Config, rigid_motion};
use crate::elements::finite_difference as fd;
use crate::elements::material::PlaneElasticity;
use crate::elements::material::StrainEnergy;
use nalgebra::{Matrix3, Rotation2, Vector2, Vector3};

fn column(f: &ElemVec) -> nalgebra::DMatrix<f64> {
    nalgebra::DMatrix::from_column_slice(8, 1, f.as_slice())
}

fn square(k: &ElemMat) -> nalgebra::DMatrix<f64> {
    nalgebra::DMatrix::from_column_slice(8, 8, k.as_slice())
}

const E: f64 = 2.07e11;
const NU: f64 = 0.3;
const RHO: f64 = 7850.0;

fn section() -> Section {
    Section {
        width: 0.1,
        height: 0.1,
    }
}

fn element(rule: ShearRule) -> (AncfShear2d, ElemVec) {
    let e0 = AncfShear2d::straight_reference(Vector2::new(0.0, 0.0), Vector2::new(0.25, 0.0));
    (AncfShear2d::new(&e0, 0.25, section(), rule).unwrap(), e0)
}

fn laws() -> [PlaneElasticity; 2] {
    [
        PlaneElasticity::new(E, NU, 5.0 / 6.0, StrainEnergy::Decoupled),
        PlaneElasticity::new(E, NU, 5.0 / 6.0, StrainEnergy::Lame),
    ]
}

/// A deformed configuration: stretch, bend, shear and a rotated gradient.
fn deformed(e0: &ElemVec) -> ElemVec {
    e0 + ElemVec::from_column_slice(&[1e-3, -2e-3, 0.05, -0.02, 4e-3, 0.03, -0.04, 0.06])
}

fn rigid(e0: &ElemVec, angle: f64, t: Vector2<f64>) -> ElemVec {
    let r = Rotation2::new(angle);
    let mut e = ElemVec::zeros();
    for a in 0..4 {
        let v = r * Vector2::new(e0[2 * a], e0[2 * a + 1]);
        // positions translate, gradients only rotate
        let v = if a % 2 == 0 { v + t } else { v };
        e[2 * a] = v.x;
        e[2 * a + 1] = v.y;
    }
    e
}

/// Closed-form mass matrix of reference A.6: M = M4 ⊗ I2 with m/3, m/6, m h²/36, m h²/72.
#[test]
fn mass_matches_closed_form() {
    let (el, e0) = element(ShearRule::Fixed1x2);
    let (l, h, b) = (0.25, 0.1, 0.1);
    let m = RHO * b * h * l;
    let m4 = nalgebra::Matrix4::new(
        m / 3.0,
        0.0,
        m / 6.0,
        0.0,
        0.0,
        m * h * h / 36.0,
        0.0,
        m * h * h / 72.0,
        m / 6.0,
        0.0,
        m / 3.0,
        0.0,
        0.0,
        m * h * h / 72.0,
        0.0,
        m * h * h / 36.0,
    );
    let mass = el.mass(&e0, RHO);
    for a in 0..4 {
        for bb in 0..4 {
            for i in 0..2 {
                for j in 0..2 {
                    let expect = if i == j { m4[(a, bb)] } else { 0.0 };
                    let got = mass[(2 * a + i, 2 * bb + j)];
                    assert!((got - expect).abs() <= 1e-12 * m, "M[{a}{i},{bb}{j}]");
                }
            }
        }
    }
}

/// Gravity of reference A.6: Q_g = [m g/2, 0, m g/2, 0].
#[test]
fn gravity_matches_closed_form() {
    let (el, e0) = element(ShearRule::Fixed1x2);
    let m = RHO * 0.1 * 0.1 * 0.25;
    let g = Vector2::new(0.3, -9.81);
    let q = el.gravity(&e0, RHO, g);
    let expect = [
        0.5 * m * g.x,
        0.5 * m * g.y,
        0.0,
        0.0,
        0.5 * m * g.x,
        0.5 * m * g.y,
        0.0,
        0.0,
    ];
    for i in 0..8 {
        assert!((q[i] - expect[i]).abs() < 1e-12 * m * 10.0, "Q_g[{i}]");
    }
}

/// Zero strain energy and zero force in the reference configuration and under any rigid
/// rotation and translation.
#[test]
fn rigid_motion_is_strain_free() {
    for rule in [ShearRule::Original1x1, ShearRule::Fixed1x2] {
        let (el, e0) = element(rule);
        for law in laws() {
            for (angle, t) in [
                (0.0, Vector2::zeros()),
                (0.7, Vector2::new(3.0, -1.0)),
                (std::f64::consts::PI, Vector2::new(-2.0, 5.0)),
                (-2.5, Vector2::new(0.1, 0.2)),
                (7.0, Vector2::new(100.0, 0.0)),
            ] {
                let e = rigid(&e0, angle, t);
                let mut f = ElemVec::zeros();
                let u = el.internal_force(&e, &law, &mut f);
                assert!(u.abs() < 1e-12, "U = {u} for angle {angle}");
                assert!(f.norm() < 1e-2, "|Q_e| = {} for angle {angle}", f.norm());
            }
        }
    }
}

/// A rotated reference element has the same stiffness as the one along x.
#[test]
fn rotated_reference_gives_same_energy() {
    let (el, e0) = element(ShearRule::Fixed1x2);
    let e = deformed(&e0);
    let law = laws()[0];
    let u0 = el.strain_energy(&e, &law);
    let e0r = rigid(&e0, 1.1, Vector2::new(1.0, 2.0));
    let er = rigid(&e, 1.1, Vector2::new(1.0, 2.0));
    let elr = AncfShear2d::new(&e0r, 0.25, section(), ShearRule::Fixed1x2).unwrap();
    let ur = elr.strain_energy(&er, &law);
    assert!((u0 - ur).abs() <= 1e-10 * u0.abs(), "{u0} vs {ur}");
}

/// Force is the gradient of the energy: central differences of U.
#[test]
fn force_matches_energy_gradient() {
    for rule in [ShearRule::Original1x1, ShearRule::Fixed1x2] {
        let (el, e0) = element(rule);
        for law in laws() {
            let e = deformed(&e0);
            let mut f = ElemVec::zeros();
            el.internal_force(&e, &law, &mut f);
            let fd = fd::gradient(
                e.as_slice(),
                |_| 1e-6,
                |x| el.strain_energy(&ElemVec::from_column_slice(x), &law),
            );
            fd::assert_close(
                &format!("rule {rule:?}: force vs energy gradient"),
                &column(&f),
                &column(&ElemVec::from_column_slice(&fd)),
                1e-6,
                0.0,
            );
        }
    }
}

/// Tangent against central finite differences of the force.
#[test]
fn tangent_matches_finite_differences() {
    for rule in [ShearRule::Original1x1, ShearRule::Fixed1x2] {
        let (el, e0) = element(rule);
        for law in laws() {
            let e = deformed(&e0);
            let mut f = ElemVec::zeros();
            let mut k = ElemMat::zeros();
            el.internal_force_tangent(&e, &law, &mut f, &mut k);
            fd::assert_jacobian(
                &format!("rule {rule:?}: tangent"),
                &square(&k),
                e.as_slice(),
                1e-7,
                1e-7,
                |x, out| {
                    let mut fx = ElemVec::zeros();
                    el.internal_force(&ElemVec::from_column_slice(x), &law, &mut fx);
                    out.copy_from_slice(fx.as_slice());
                },
            );
            assert!(
                (k - k.transpose()).norm() <= 1e-12 * k.norm(),
                "tangent not symmetric"
            );
        }
    }
}

/// Average-stress force: exact energy difference, consistent with Q_e when e_a = e_b, and
/// its derivative against finite differences.
#[test]
fn average_stress_force_is_a_discrete_gradient() {
    let (el, e0) = element(ShearRule::Fixed1x2);
    let law = laws()[0];
    let ea = deformed(&e0);
    let eb = rigid(&ea, 0.3, Vector2::new(0.01, -0.02)) + ElemVec::from_element(1e-3);
    let mut f = ElemVec::zeros();
    let mut k = ElemMat::zeros();
    el.average_stress_force(&ea, &eb, &law, &mut f, Some(&mut k));
    let du = el.strain_energy(&eb, &law) - el.strain_energy(&ea, &law);
    assert!(
        (f.dot(&(eb - ea)) - du).abs() <= 1e-10 * du.abs().max(1.0),
        "not exact"
    );

    let mut fe = ElemVec::zeros();
    el.internal_force(&ea, &law, &mut fe);
    el.average_stress_force(&ea, &ea, &law, &mut f, None);
    assert!((f - fe).norm() <= 1e-10 * fe.norm());

    el.average_stress_force(&ea, &eb, &law, &mut f, Some(&mut k));
    fd::assert_jacobian(
        "average-stress tangent",
        &square(&k),
        eb.as_slice(),
        1e-7,
        1e-7,
        |x, out| {
            let mut fx = ElemVec::zeros();
            el.average_stress_force(&ea, &ElemVec::from_column_slice(x), &law, &mut fx, None);
            out.copy_from_slice(fx.as_slice());
        },
    );
}

/// Pure axial stretch: ε11 = ½(λ² − 1) integrated over the volume.
#[test]
fn uniaxial_stretch_energy() {
    let (el, e0) = element(ShearRule::Fixed1x2);
    let law = laws()[0];
    let stretch = 1.01;
    let mut e = e0;
    e[4] = 0.25 * stretch;
    let eps = 0.5 * (stretch * stretch - 1.0);
    let expect = 0.5 * E * eps * eps * 0.25 * 0.1 * 0.1;
    let u = el.strain_energy(&e, &law);
    assert!((u - expect).abs() <= 1e-12 * expect);
}

/// The element with its material in the states of the conformance checks: reference, bent
/// (stretch, bending, shear, rotated gradient), the bent state turned by 1.1 rad and moved,
/// and a 1 % axial stretch; moving, so that damping and inertia terms are exercised.
fn case(rule: ShearRule, law: PlaneElasticity) -> Case<Shear2dElement, ELEMENT_COORDS> {
    let (_, e0) = element(rule);
    let el = Shear2dElement::new(&e0, 0.25, section(), rule, law, RHO).unwrap();
    let v = ElemVec::from_column_slice(&[0.3, -0.2, 0.5, 1.0, -0.4, 0.1, 0.7, -0.3]);
    let a = ElemVec::from_column_slice(&[1.0, 0.5, -0.3, -2.0, 0.6, 0.9, 0.2, -0.8]);
    let bent = Config::at("bent", deformed(&e0)).moving(v, a);
    let q = Matrix3::from(nalgebra::Rotation3::from_axis_angle(
        &Vector3::z_axis(),
        1.1,
    ));
    let mut turned = rigid_motion(&el.layout(), &bent, &q, &Vector3::new(1.0, 2.0, 0.0));
    turned.label = "bent, turned by 1.1 rad";
    let mut stretched = e0;
    stretched[4] *= 1.01;
    Case {
        states: vec![
            Config::at("reference", e0).moving(v, a),
            bent,
            turned,
            Config::at("stretched", stretched),
        ],
        element: el,
    }
}

element_conformance!(conformance_fixed_decoupled, || case(
    ShearRule::Fixed1x2,
    laws()[0]
));
element_conformance!(conformance_original_lame, || case(
    ShearRule::Original1x1,
    laws()[1]
));
