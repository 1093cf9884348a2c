//! The meridional bending hinge: energy gradient and tangent against finite differences (the
//! conformance checks that apply to a massless axisymmetric element: its iteration matrix is
//! `c_K K` alone, which the tangent check covers), the hinge angle, and invariance under axial
//! translation.

use crate::elements::axisym_bending::AxisymHinge;
use crate::elements::conformance::{self as c, Case, Config};
use crate::elements::element::{Element, ElementState};
use nalgebra::SVector;

fn case() -> Case<AxisymHinge, 6> {
    let q = |a: [f64; 6]| SVector::<f64, 6>::from_column_slice(&a);
    Case {
        element: AxisymHinge::new(2.7e-5, 0.125, [0.005, 0.005]),
        states: vec![
            Config::at("kinked", q([0.14, 0.1, 0.142, 0.095, 0.141, 0.09])),
            Config::at("lobe bottom", q([0.13, 0.08, 0.12, 0.075, 0.11, 0.078])),
            Config::at("reversed", q([0.1, 0.05, 0.1, 0.045, 0.103, 0.049])).moving(
                q([0.1, -0.3, 0.2, 0.5, 0.0, 0.1]),
                q([1.0, 2.0, -3.0, 0.5, 0.2, 0.1]),
            ),
        ],
    }
}

#[test]
fn force_is_energy_gradient() {
    c::check_energy_gradient(&case());
}

#[test]
fn tangent_matches_finite_differences() {
    c::check_tangent(&case());
}

/// The angle of a right-angle turn is ±π/2 by its sense; a straight meridian has none and no
/// energy; an axial translation changes nothing.
#[test]
fn hinge_angle_and_translation() {
    let q = |a: [f64; 6]| SVector::<f64, 6>::from_column_slice(&a);
    let turn_left = q([0.0, 0.0, 1.0, 0.0, 1.0, 1.0]);
    assert!((AxisymHinge::angle(&turn_left) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    let turn_right = q([0.0, 0.0, 1.0, 0.0, 1.0, -1.0]);
    assert!((AxisymHinge::angle(&turn_right) + std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    let h = AxisymHinge::new(1.0, 0.1, [0.01, 0.01]);
    let straight = q([0.1, 0.3, 0.1, 0.2, 0.1, 0.1]);
    let s = ElementState::new(straight, SVector::zeros());
    assert_eq!(h.strain_energy_at(&s), 0.0);
    for st in case().states {
        let mut moved = st.q;
        for i in [1, 3, 5] {
            moved[i] += 0.3;
        }
        let u0 = h.strain_energy_at(&ElementState::new(st.q, st.v));
        let u1 = h.strain_energy_at(&ElementState::new(moved, st.v));
        assert!((u1 - u0).abs() <= 1e-10 * u0.abs().max(1e-12));
    }
}
