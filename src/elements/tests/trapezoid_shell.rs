//! Seed-004 trapezoidal shell: conformance (both bending variants, with and without the
//! geometric stiffness, rectangle, trapezoid and a general convex quadrilateral), free–free
//! modes, shape-function properties.

use crate::element_conformance;
use crate::elements::Element;
use crate::elements::conformance::{Case, Config, rigid_motion};
use crate::elements::rotation::exp_so3;
use crate::elements::trapezoid_shell::*;
use nalgebra::{Matrix3, Vector3};

pub(crate) fn steel(thickness: f64) -> ShellMaterial {
    ShellMaterial {
        e: 2.1e11,
        nu: 0.3,
        rho: 7850.0,
        thickness,
    }
}

/// Shapes of the checks, in a plane turned out of the global axes.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Shape {
    Rectangle,
    Trapezoid,
    General,
}

pub(crate) fn corners(shape: Shape) -> [Vector3<f64>; 4] {
    let local = match shape {
        Shape::Rectangle => [(0.0, 0.0), (0.4, 0.0), (0.4, 0.25), (0.0, 0.25)],
        Shape::Trapezoid => [(0.0, 0.0), (0.5, 0.0), (0.4, 0.3), (0.1, 0.3)],
        Shape::General => [(0.0, 0.0), (0.45, 0.05), (0.38, 0.33), (0.04, 0.27)],
    };
    let q = exp_so3(&Vector3::new(0.4, -0.3, 0.9));
    let t = Vector3::new(0.2, -0.1, 0.3);
    local.map(|(x, y)| q * Vector3::new(x, y, 0.0) + t)
}

fn config(
    label: &'static str,
    x: &[Vector3<f64>; 4],
    r: &[Matrix3<f64>; 4],
    theta: [Vector3<f64>; 4],
) -> Config<ELEMENT_DOFS> {
    let mut q = Vec24::zeros();
    for i in 0..4 {
        q.fixed_rows_mut::<3>(6 * i).copy_from(&x[i]);
        q.fixed_rows_mut::<3>(6 * i + 3).copy_from(&theta[i]);
    }
    let r_ref = (0..4).map(|i| r[i] * exp_so3(&-theta[i])).collect();
    Config::at(label, q).frames(r_ref)
}

/// A deformed state: in-plane stretch, bending and twist of a few percent of the size on top
/// of a large rigid rotation.
fn deformed(x0: &[Vector3<f64>; 4]) -> ([Vector3<f64>; 4], [Matrix3<f64>; 4]) {
    let q = exp_so3(&Vector3::new(1.3, -2.1, 0.8));
    let t = Vector3::new(0.3, 1.0, -2.0);
    let dx = [
        Vector3::new(0.004, -0.003, 0.01),
        Vector3::new(-0.002, 0.005, -0.006),
        Vector3::new(0.003, 0.001, 0.012),
        Vector3::new(-0.001, -0.004, -0.003),
    ];
    let dr = [
        Vector3::new(0.05, -0.08, 0.02),
        Vector3::new(-0.04, 0.06, -0.03),
        Vector3::new(0.07, 0.02, 0.04),
        Vector3::new(-0.03, -0.05, 0.01),
    ];
    (
        std::array::from_fn(|i| q * (x0[i] + dx[i]) + t),
        std::array::from_fn(|i| q * exp_so3(&dr[i])),
    )
}

fn case(shape: Shape, opt: ShellOptions) -> Case<TrapezoidShell, ELEMENT_DOFS> {
    let x0 = corners(shape);
    let el = TrapezoidShell::new(x0, &steel(0.01), &opt).unwrap();
    let v = Vec24::from_fn(|i, _| ((i * 7 % 11) as f64 - 5.0) * 0.1);
    let a = Vec24::from_fn(|i, _| ((i * 5 % 13) as f64 - 6.0) * 0.2);
    let zero = [Vector3::zeros(); 4];
    let id = [Matrix3::identity(); 4];
    let (x, r) = deformed(&x0);
    let bent = config("bent", &x, &r, zero).moving(v, a);
    let incremental = config(
        "bent, large incremental rotations",
        &x,
        &r,
        [
            Vector3::new(0.5, -1.2, 2.0),
            Vector3::new(-0.1, 0.3, 0.2),
            Vector3::new(0.9, 0.1, -0.4),
            Vector3::new(0.0, -0.6, 0.3),
        ],
    )
    .moving(v, a);
    let q = exp_so3(&Vector3::new(-2.0, 0.7, 1.9));
    let mut turned = rigid_motion(&el.layout(), &bent, &q, &Vector3::new(5.0, -3.0, 1.0));
    turned.label = "bent, turned rigidly";
    Case {
        states: vec![
            config("reference", &x0, &id, zero).moving(v, a),
            bent,
            incremental,
            turned,
        ],
        element: el,
    }
}

fn opts(bending: Bending, geometric_stiffness: bool) -> ShellOptions {
    ShellOptions {
        bending,
        geometric_stiffness,
        ..ShellOptions::default()
    }
}

element_conformance!(conformance_rectangle_v2, || case(
    Shape::Rectangle,
    opts(Bending::V2, false)
));
element_conformance!(conformance_trapezoid_v2, || case(
    Shape::Trapezoid,
    opts(Bending::V2, false)
));
element_conformance!(conformance_trapezoid_v1, || case(
    Shape::Trapezoid,
    opts(Bending::V1, false)
));
element_conformance!(conformance_general_v2_geometric, || case(
    Shape::General,
    opts(Bending::V2, true)
));
element_conformance!(conformance_trapezoid_v1_geometric, || case(
    Shape::Trapezoid,
    opts(Bending::V1, true)
));

/// Six zero-frequency free–free modes and eighteen elastic ones (Eqs. 4–10). V2 holds the
/// rigid motions exactly on every convex quadrilateral; V1 only on rectangles: composed with
/// the trapezoid map its functions no longer reproduce a linear deflection, so a rigid
/// rotation about an in-plane axis costs energy (the paper's V1 is a rectangle element). The
/// projector on the elastic modes removes that energy, so the element's effective stiffness
/// has exactly six zero modes for both.
#[test]
fn six_rigid_free_free_modes() {
    for shape in [Shape::Rectangle, Shape::Trapezoid, Shape::General] {
        for bending in [Bending::V1, Bending::V2] {
            let el =
                TrapezoidShell::new(corners(shape), &steel(0.01), &opts(bending, false)).unwrap();
            let ev = el.free_free_eigenvalues();
            let top = ev[ELEMENT_DOFS - 1];
            let exact = bending == Bending::V2 || matches!(shape, Shape::Rectangle);
            for (i, e) in ev.iter().enumerate() {
                if i < 6 && exact {
                    assert!(
                        e.abs() < 1e-9 * top,
                        "{shape:?} {bending:?}: mode {i} {e} of {top}"
                    );
                } else if i < 6 {
                    assert!(
                        e.abs() < 1e-5 * top,
                        "{shape:?} {bending:?}: mode {i} {e} of {top}"
                    );
                } else {
                    assert!(
                        *e > 1e-9 * top,
                        "{shape:?} {bending:?}: mode {i} {e} of {top}"
                    );
                }
            }
            if !exact {
                assert!(
                    ev[5] > 1e-9 * top,
                    "V1 on a {shape:?} now holds rigid rotations exactly: update the docs"
                );
            }
            let ep = el.projected_eigenvalues();
            for (i, e) in ep.iter().enumerate() {
                assert_eq!(
                    i < 6,
                    e.abs() < 1e-9 * top,
                    "{shape:?} {bending:?}: projected mode {i} {e}"
                );
            }
        }
    }
}
