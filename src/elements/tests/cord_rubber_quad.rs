//! The cord–rubber membrane quadrilateral: every conformance check (its energy depends on the
//! surface metric only), in tension, compression and shear, and its energy on a stretched
//! cylinder facet against the axisymmetric law.

use crate::element_conformance;
use crate::elements::conformance::{Case, Config};
use crate::elements::cord_rubber::CordRubberWall;
use crate::elements::cord_rubber_quad::{CordRubberQuad, QUAD_DOFS};
use crate::elements::element::{Element, ElementState};
use nalgebra::{SVector, Vector3};

fn wall(tension_only: bool) -> CordRubberWall {
    CordRubberWall {
        cord_stiffness: 1.5e6,
        n_plies: 2,
        cord_angle: 54f64.to_radians(),
        matrix_stiffness: 2.0e4,
        tension_only,
    }
}

/// A facet of a cylinder of radius `r` between the angles `±h/2` and heights `0`, `−l`
/// (the meridian runs down), counter-clockwise about the outward normal.
fn facet(r: f64, h: f64, l: f64, ls: f64, lt: f64) -> [Vector3<f64>; 4] {
    let p = |phi: f64, z: f64| Vector3::new(lt * r * phi.cos(), lt * r * phi.sin(), ls * z);
    [
        p(-h / 2.0, 0.0),
        p(-h / 2.0, -l),
        p(h / 2.0, -l),
        p(h / 2.0, 0.0),
    ]
}

fn flat(x: &[Vector3<f64>; 4]) -> SVector<f64, QUAD_DOFS> {
    SVector::from_fn(|i, _| x[i / 3][i % 3])
}

fn case(tension_only: bool) -> Case<CordRubberQuad, QUAD_DOFS> {
    let x0 = facet(0.125, 0.2, 0.01, 1.0, 1.0);
    let el =
        CordRubberQuad::new(x0, Vector3::new(0.0, 0.0, -1.0), wall(tension_only), 4.4).unwrap();
    let mut sheared = facet(0.125, 0.2, 0.01, 1.2, 0.85);
    sheared[0] += Vector3::new(0.0, 0.002, 0.0005);
    sheared[2] += Vector3::new(0.001, -0.001, 0.0003);
    let v = SVector::from_fn(|i, _| 0.1 * (i as f64 - 5.0));
    Case {
        element: el,
        states: vec![
            Config::at("stretched", flat(&facet(0.125, 0.2, 0.01, 1.3, 1.1))),
            Config::at(
                "hoop compression",
                flat(&facet(0.125, 0.2, 0.01, 1.28, 0.8)),
            ),
            Config::at("sheared and warped", flat(&sheared)).moving(v, v * 3.0),
        ],
    }
}

element_conformance!(conformance_linear_cords, || case(false));
element_conformance!(conformance_tension_only, || case(true));

/// A facet of the stress-free cylinder scaled by `λ_s` along the axis and `λ_θ` about it has the
/// energy of the axisymmetric law times its reference area (the chord scales exactly with the
/// radius), and none unstretched.
#[test]
fn stretched_facet_has_the_axisymmetric_energy() {
    for to in [false, true] {
        let w = wall(to);
        let x0 = facet(0.125, 0.2, 0.01, 1.0, 1.0);
        let el = CordRubberQuad::new(x0, Vector3::new(0.0, 0.0, -1.0), w, 0.0).unwrap();
        let u0 = el.strain_energy_at(&ElementState::new(flat(&x0), SVector::zeros()));
        assert!(u0.abs() < 1e-18, "unstretched: {u0}");
        for &(ls, lt) in &[(1.3, 0.8), (1.05, 1.12), (0.9, 0.95)] {
            let x = facet(0.125, 0.2, 0.01, ls, lt);
            let u = el.strain_energy_at(&ElementState::new(flat(&x), SVector::zeros()));
            let expect = w.axisym(ls, lt).w * el.area();
            assert!(
                (u - expect).abs() <= 1e-12 * expect,
                "{ls}, {lt}: {u} vs {expect}"
            );
        }
    }
}

/// The node-by-node internal force (force and tangent paths) is the force of the column
/// formulation (`∂C_p/∂q` as 12-vectors, `axpy`) to the bit: in every state of the conformance
/// cases and in 100 states scattered about each (a reordered sum differs in the last bit in
/// some of those).
#[test]
fn force_is_the_column_formulations_to_the_bit() {
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut rand = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for to in [false, true] {
        let c = case(to);
        for cfg in &c.states {
            for n in 0..=100 {
                // scatter of 2 mm about the state (the facet is 25 mm × 10 mm)
                let q = if n == 0 {
                    cfg.q
                } else {
                    cfg.q + SVector::<f64, QUAD_DOFS>::from_fn(|_, _| 0.002 * rand())
                };
                let s = ElementState::new(q, SVector::zeros());
                let (mut f, mut ft) = (SVector::zeros(), SVector::zeros());
                let mut k = nalgebra::SMatrix::<f64, QUAD_DOFS, QUAD_DOFS>::zeros();
                c.element.force_into(&s, &mut f);
                c.element.tangent_into(&s, &mut ft, &mut k, None);
                let reference = c.element.force_by_columns(&q);
                for i in 0..QUAD_DOFS {
                    let r = reference[i].to_bits();
                    assert_eq!(f[i].to_bits(), r, "{} #{n} row {i}", cfg.label);
                    assert_eq!(ft[i].to_bits(), r, "{} #{n} row {i}", cfg.label);
                }
            }
        }
    }
}
