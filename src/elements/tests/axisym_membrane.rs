//! The conical membrane element: energy gradient, tangent and iteration matrix against finite
//! differences, mass and gravity (the conformance checks that apply to an axisymmetric
//! element), invariance under axial translation, the frustum volume, and the membrane forces
//! of a cylinder under pressure.

use crate::elements::axisym_membrane::{AxisymMembrane, frustum_volume};
use crate::elements::conformance::{self as c, Case, Config};
use crate::elements::cord_rubber::CordRubberWall;
use crate::elements::element::{Element, ElementState};
use nalgebra::{SVector, Vector4};

fn wall() -> CordRubberWall {
    CordRubberWall {
        cord_stiffness: 1.5e6,
        n_plies: 2,
        cord_angle: 54f64.to_radians(),
        matrix_stiffness: 2.0e4,
        tension_only: false,
    }
}

fn case(tension_only: bool) -> Case<AxisymMembrane, 4> {
    let w = CordRubberWall {
        tension_only,
        ..wall()
    };
    let el = AxisymMembrane::new(0.01, [0.125, 0.125], w, 4.4);
    let q = |a: [f64; 4]| SVector::<f64, 4>::from_column_slice(&a);
    Case {
        element: el,
        states: vec![
            // slightly off the stress-free state: the tension-only law has its kink there
            Config::at("near reference", q([0.1251, 0.2, 0.1252, 0.18995])),
            Config::at("lobe", q([0.14, 0.1, 0.132, 0.093])),
            Config::at("on piston", q([0.1, 0.05, 0.1, 0.063])),
            Config::at("compressed", q([0.12, 0.0, 0.121, -0.008]))
                .moving(q([0.1, -0.3, 0.2, 0.5]), q([1.0, 2.0, -3.0, 0.5])),
        ],
    }
}

#[test]
fn mass_is_symmetric_positive_definite() {
    c::check_mass(&case(false));
}

#[test]
fn gravity_is_mass_times_translation() {
    c::check_gravity(&case(false));
}

#[test]
fn force_is_energy_gradient() {
    c::check_energy_gradient(&case(false));
    c::check_energy_gradient(&case(true));
}

#[test]
fn tangent_matches_finite_differences() {
    c::check_tangent(&case(false));
    c::check_tangent(&case(true));
}

#[test]
fn iteration_matrix_matches_finite_differences() {
    c::check_iteration_matrix(&case(false));
}

/// An axial translation leaves energy and force unchanged; a radial one does not.
#[test]
fn axial_translation_is_invariant_radial_is_not() {
    let k = case(false);
    for st in &k.states {
        let s0 = ElementState::new(st.q, st.v);
        let mut f0 = SVector::<f64, 4>::zeros();
        let u0 = k.element.force_into(&s0, &mut f0);
        let mut qa = st.q;
        qa[1] += 0.37;
        qa[3] += 0.37;
        let mut fa = SVector::<f64, 4>::zeros();
        let ua = k.element.force_into(&ElementState::new(qa, st.v), &mut fa);
        assert!((ua - u0).abs() <= 1e-8 * u0.abs().max(1e-9), "{}", st.label);
        assert!(
            (fa - f0).norm() <= 1e-8 * f0.norm().max(1e-9),
            "{}",
            st.label
        );
        let mut qr = st.q;
        qr[0] += 0.01;
        qr[2] += 0.01;
        let ur = k.element.strain_energy_at(&ElementState::new(qr, st.v));
        assert!((ur - u0).abs() > 1e-6 * u0.abs().max(1e-3), "{}", st.label);
        // no axial self-equilibrium defect: the axial forces cancel
        assert!((f0[1] + f0[3]).abs() <= 1e-10 * f0.norm().max(1e-9));
    }
}

/// Mass: total `ρ_A 2π R̄ L` in each direction.
#[test]
fn mass_is_the_frustum_mass() {
    let el = AxisymMembrane::new(0.02, [0.1, 0.14], wall(), 3.0);
    let s = ElementState::new(SVector::zeros(), SVector::zeros());
    let mut m = nalgebra::SMatrix::<f64, 4, 4>::zeros();
    el.mass_into(&s, &mut m);
    let total = m[(1, 1)] + m[(1, 3)] + m[(3, 1)] + m[(3, 3)];
    let exact = 3.0 * 2.0 * std::f64::consts::PI * 0.12 * 0.02;
    assert!((total - exact).abs() < 1e-14 * exact);
}

/// Frustum volume: exact for a cylinder and a cone, derivatives against finite differences.
#[test]
fn frustum_volume_and_derivatives() {
    let pi = std::f64::consts::PI;
    let (v, _, _) = frustum_volume(&Vector4::new(0.1, 0.3, 0.1, 0.0));
    assert!((v - pi * 0.01 * 0.3).abs() < 1e-15);
    let (v, _, _) = frustum_volume(&Vector4::new(0.0, 0.2, 0.3, 0.0));
    assert!((v - pi * 0.09 * 0.2 / 3.0).abs() < 1e-15);
    let q = Vector4::new(0.13, 0.21, 0.11, 0.02);
    let (_, g, h) = frustum_volume(&q);
    let e = 1e-6;
    for i in 0..4 {
        let mut qp = q;
        qp[i] += e;
        let mut qm = q;
        qm[i] -= e;
        let (vp, gp, _) = frustum_volume(&qp);
        let (vm, gm, _) = frustum_volume(&qm);
        assert!(((vp - vm) / (2.0 * e) - g[i]).abs() < 1e-9);
        for j in 0..4 {
            assert!(((gp[j] - gm[j]) / (2.0 * e) - h[(j, i)]).abs() < 1e-8);
            assert_eq!(h[(i, j)], h[(j, i)]);
        }
    }
}

/// A stretched cylinder: `N_s = (∂W/∂λ_s)/λ_θ`, `N_θ = (∂W/∂λ_θ)/λ_s`, and the nodal forces of
/// the element are the resultants `2π r N_s` along the meridian and `N_θ` times the area over
/// the radius in the radial direction (the hoop force that the pressure `p = N_θ/r`
/// balances).
#[test]
fn cylinder_forces_are_the_membrane_resultants() {
    let el = AxisymMembrane::new(0.01, [0.125, 0.125], wall(), 0.0);
    let (ls, lt) = (1.08, 1.1);
    let r = 0.125 * lt;
    let q = SVector::<f64, 4>::from_column_slice(&[r, 0.0, r, -0.01 * ls]);
    let mut f = SVector::<f64, 4>::zeros();
    el.force_into(&ElementState::new(q, SVector::zeros()), &mut f);
    let [ns, nt] = el.wall.axisym_forces(ls, lt);
    let pi2 = 2.0 * std::f64::consts::PI;
    // meridional resultant at each end
    assert!((f[1] - pi2 * r * ns).abs() < 1e-9 * pi2 * r * ns);
    assert!((f[3] + pi2 * r * ns).abs() < 1e-9 * pi2 * r * ns);
    // hoop: total radial force = N_θ · 2π ℓ
    let hoop = nt * pi2 * 0.01 * ls;
    assert!((f[0] + f[2] - hoop).abs() < 1e-9 * hoop);
}
