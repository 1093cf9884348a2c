//! Seed-004 trapezoidal shell: conformance (both bending variants, with and without the
//! geometric stiffness, rectangle, trapezoid and a general convex quadrilateral), free–free
//! modes, shape-function properties.

use crate::element_conformance;
use crate::elements::Element;
use crate::elements::conformance::{Case, Config, rigid_motion};
use crate::elements::rotation::exp_so3;
use crate::elements::trapezoid_shell::*;
use nalgebra::{Matrix3, SMatrix, Vector3};

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
        membrane: true,
        ..ShellOptions::default()
    }
}

// bending only (the air spring's wall: its membrane is the cord-rubber quadrilateral)
element_conformance!(conformance_general_v2_bending_only, || case(
    Shape::General,
    ShellOptions {
        membrane: false,
        ..opts(Bending::V2, true)
    }
));
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

/// Dense global stiffness (6 per node) of flat quadrilaterals in the x-y plane at their
/// reference state.
fn assemble(
    nodes: &[(f64, f64)],
    quads: &[[usize; 4]],
    bending: Bending,
) -> nalgebra::DMatrix<f64> {
    let mat = ShellMaterial {
        e: 1.0e6,
        nu: 0.25,
        rho: 1.0,
        thickness: 0.01,
    };
    assemble_with(nodes, quads, bending, &mat)
}

fn assemble_with(
    nodes: &[(f64, f64)],
    quads: &[[usize; 4]],
    bending: Bending,
    mat: &ShellMaterial,
) -> nalgebra::DMatrix<f64> {
    let n = nodes.len() * 6;
    let mut k = nalgebra::DMatrix::zeros(n, n);
    for q in quads {
        let x = q.map(|i| Vector3::new(nodes[i].0, nodes[i].1, 0.0));
        let el = TrapezoidShell::new(x, mat, &opts(bending, false)).unwrap();
        let (mut f, mut ke) = (Vec24::zeros(), Mat24::zeros());
        el.internal(&x, &[Matrix3::identity(); 4], &mut f, Some(&mut ke));
        for a in 0..4 {
            for b in 0..4 {
                for i in 0..6 {
                    for j in 0..6 {
                        k[(6 * q[a] + i, 6 * q[b] + j)] += ke[(6 * a + i, 6 * b + j)];
                    }
                }
            }
        }
    }
    k
}

/// Solves `K d = 0` for the free nodes with the boundary nodes' coordinates from `exact`
/// (6 per node) and returns the largest error of the free nodes' coordinates against `exact`,
/// relative to the largest exact value.
fn patch_error(
    nodes: &[(f64, f64)],
    quads: &[[usize; 4]],
    boundary: &[usize],
    bending: Bending,
    exact: &dyn Fn(f64, f64) -> [f64; 6],
) -> f64 {
    let k = assemble(nodes, quads, bending);
    let n = nodes.len() * 6;
    let d_exact: Vec<f64> = nodes.iter().flat_map(|&(x, y)| exact(x, y)).collect();
    let free: Vec<usize> = (0..n).filter(|i| !boundary.contains(&(i / 6))).collect();
    let fixed: Vec<usize> = (0..n).filter(|i| boundary.contains(&(i / 6))).collect();
    let kff = nalgebra::DMatrix::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
    let rhs = nalgebra::DVector::from_fn(free.len(), |i, _| {
        -fixed
            .iter()
            .map(|&j| k[(free[i], j)] * d_exact[j])
            .sum::<f64>()
    });
    let d = kff.lu().solve(&rhs).expect("regular");
    let scale = d_exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    free.iter()
        .enumerate()
        .map(|(i, &g)| (d[i] - d_exact[g]).abs())
        .fold(0.0, f64::max)
        / scale
}

/// The patch of MacNeal & Harder 1985 (0.24 × 0.12 with five distorted elements; 4 interior
/// nodes).
/// Nodes, quadrilaterals and boundary nodes of a patch.
type Patch = (Vec<(f64, f64)>, Vec<[usize; 4]>, Vec<usize>);

fn macneal_patch() -> Patch {
    let nodes = vec![
        (0.0, 0.0),
        (0.24, 0.0),
        (0.24, 0.12),
        (0.0, 0.12),
        (0.04, 0.02),
        (0.18, 0.03),
        (0.16, 0.08),
        (0.08, 0.08),
    ];
    let quads = vec![
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
        [4, 5, 6, 7],
    ];
    (nodes, quads, vec![0, 1, 2, 3])
}

/// A patch of isosceles trapezoids: two rows of a trapezoidal plate whose width shrinks with
/// y (the mesh of a surface-of-revolution ring, flattened); interior nodes on the middle row.
fn trapezoid_patch(n: usize) -> Patch {
    let width = |y: f64| 0.3 - 0.5 * y;
    let rows = 2 * n;
    let mut nodes = Vec::new();
    for j in 0..=rows {
        let y = 0.2 * j as f64 / rows as f64;
        for i in 0..=n {
            nodes.push((width(y) * (i as f64 / n as f64 - 0.5), y));
        }
    }
    let mut quads = Vec::new();
    for j in 0..rows {
        for i in 0..n {
            let a = j * (n + 1) + i;
            quads.push([a, a + 1, a + n + 2, a + n + 1]);
        }
    }
    let boundary = (0..nodes.len())
        .filter(|&k| {
            let (i, j) = (k % (n + 1), k / (n + 1));
            i == 0 || i == n || j == 0 || j == rows
        })
        .collect();
    (nodes, quads, boundary)
}

/// Membrane patch test: a linear displacement field (constant strain, with the drilling
/// rotation following the in-plane rotation) is reproduced exactly on distorted
/// quadrilaterals and on trapezoids, for both bending variants (the membrane is the same).
#[test]
fn membrane_patch_test() {
    let field = |x: f64, y: f64| {
        let (u, v) = (
            1e-3 * (1.0 + 2.0 * x + 3.0 * y),
            1e-3 * (-0.5 + 1.5 * x - 2.5 * y),
        );
        let omega = 0.5 * 1e-3 * (1.5 - 3.0);
        [u, v, 0.0, 0.0, 0.0, omega]
    };
    for (name, (nodes, quads, boundary)) in [
        ("MacNeal-Harder", macneal_patch()),
        ("trapezoids", trapezoid_patch(3)),
    ] {
        for bending in [Bending::V1, Bending::V2] {
            let e = patch_error(&nodes, &quads, &boundary, bending, &field);
            assert!(e < 1e-9, "{name} {bending:?}: {e}");
        }
    }
}

/// The constant-curvature (bending patch) field `w = ½ kx x² + ½ ky y² + kxy x y` with
/// `α = ∂w/∂y`, `β = −∂w/∂x`.
fn curvature_field(kx: f64, ky: f64, kxy: f64) -> impl Fn(f64, f64) -> [f64; 6] {
    move |x, y| {
        let w = 0.5 * kx * x * x + 0.5 * ky * y * y + kxy * x * y;
        [0.0, 0.0, w, ky * y + kxy * x, -(kx * x + kxy * y), 0.0]
    }
}

/// Bending patch test on rectangles: both variants reproduce constant curvatures and a constant
/// twist at the nodes exactly (V2 is the ACM rectangle; V1's products of Hermite cubics lack
/// the `θ(ξ)θ(η)` twist function inside the element, but its nodal solution is still exact).
#[test]
fn bending_patch_test_on_rectangles() {
    let (nodes, quads, boundary) = {
        // 3 × 3 rectangles, 4 interior nodes
        let mut nodes = Vec::new();
        for j in 0..4 {
            for i in 0..4 {
                nodes.push((0.1 * i as f64, 0.07 * j as f64));
            }
        }
        let mut quads = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                let a = 4 * j + i;
                quads.push([a, a + 1, a + 5, a + 4]);
            }
        }
        let boundary: Vec<usize> = (0..16).filter(|k| ![5, 6, 9, 10].contains(k)).collect();
        (nodes, quads, boundary)
    };
    for bending in [Bending::V1, Bending::V2] {
        let e = patch_error(
            &nodes,
            &quads,
            &boundary,
            bending,
            &curvature_field(0.3, -0.2, 0.0),
        );
        assert!(e < 1e-9, "{bending:?} curvature: {e}");
        let e = patch_error(
            &nodes,
            &quads,
            &boundary,
            bending,
            &curvature_field(0.0, 0.0, 0.25),
        );
        assert!(e < 1e-9, "{bending:?} twist: {e}");
    }
}

/// Bending patch test on isosceles trapezoids and on the distorted patch: neither variant is
/// exact (the functions are the rectangle's composed with a non-affine map); both errors fall
/// at about second order with the element size, V2's about 1e3 times smaller than V1's
/// (printed table: `cargo test --release --lib bending_patch -- --nocapture`). On the
/// strongly distorted MacNeal–Harder patch V2 is 10 % off: meshes should stay close to
/// trapezoids.
#[test]
fn bending_patch_test_on_trapezoids_converges_for_v2() {
    let f = curvature_field(0.3, -0.2, 0.25);
    let mut errs = Vec::new();
    for n in [2, 4, 8] {
        let (nodes, quads, boundary) = trapezoid_patch(n);
        let e2 = patch_error(&nodes, &quads, &boundary, Bending::V2, &f);
        let e1 = patch_error(&nodes, &quads, &boundary, Bending::V1, &f);
        println!("trapezoid patch n = {n}: V2 error {e2:.3e}, V1 error {e1:.3e}");
        errs.push((e2, e1));
    }
    let (nodes, quads, boundary) = macneal_patch();
    let e = patch_error(&nodes, &quads, &boundary, Bending::V2, &f);
    println!("MacNeal-Harder patch: V2 error {e:.3e}");
    for k in 0..2 {
        let (r2, r1) = (errs[k].0 / errs[k + 1].0, errs[k].1 / errs[k + 1].1);
        assert!(
            r2 > 1.5 && r1 > 3.0,
            "no convergence on trapezoids: {errs:?}"
        );
    }
    assert!(errs[2].0 < 1e-5 && errs[2].1 < 1e-2, "{errs:?}");
    assert!(e < 0.2, "distorted patch: {e}");
}

/// The closed-form first derivatives of the element frame agree with the dual-number ones.
#[test]
fn frame_derivatives_closed_form_and_dual_agree() {
    let (x, r) = deformed(&corners(Shape::General));
    let el = TrapezoidShell::new(
        corners(Shape::General),
        &steel(0.01),
        &ShellOptions::default(),
    )
    .unwrap();
    // The force (closed-form frame derivatives) equals the force computed along with the
    // tangent (dual-number frame derivatives).
    let (mut f1, mut f2, mut k) = (Vec24::zeros(), Vec24::zeros(), Mat24::zeros());
    el.internal(&x, &r, &mut f1, None);
    el.internal(&x, &r, &mut f2, Some(&mut k));
    assert!(
        (f1 - f2).norm() <= 1e-12 * f1.norm(),
        "{}",
        (f1 - f2).norm() / f1.norm()
    );
}

/// A cantilever strip (L = 1, b = 0.1, h = 0.01, ν = 0) of `n × 1` rectangles under a tip
/// force P (two nodal forces): the linear tip deflection against Euler–Bernoulli
/// `P L³/(3 E I)`. V2 (ACM) holds the cubic deflection of a beam exactly: round-off at any `n`.
/// V1 is within 1e-4 but not exact (measured 5.6e-6 at n = 1 to 3.9e-5 at n = 16, more
/// flexible; its rigid modes are exact on rectangles, the cause was not traced further).
#[test]
fn cantilever_strip_matches_beam_theory() {
    let mat = ShellMaterial {
        e: 2.0e11,
        nu: 0.0,
        rho: 7800.0,
        thickness: 0.01,
    };
    let (l, b, p) = (1.0, 0.1, 10.0);
    let ei = mat.e * b * mat.thickness.powi(3) / 12.0;
    for bending in [Bending::V1, Bending::V2] {
        for n in [1, 4, 16] {
            let mut nodes = Vec::new();
            for i in 0..=n {
                let x = l * i as f64 / n as f64;
                nodes.push((x, 0.0));
                nodes.push((x, b));
            }
            let quads: Vec<[usize; 4]> = (0..n)
                .map(|i| [2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1])
                .collect();
            let k = assemble_with(&nodes, &quads, bending, &mat);
            let free: Vec<usize> = (12..k.nrows()).collect();
            let kff =
                nalgebra::DMatrix::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
            let mut f = nalgebra::DVector::zeros(free.len());
            let tip = [6 * (2 * n) + 2 - 12, 6 * (2 * n + 1) + 2 - 12];
            for t in tip {
                f[t] = 0.5 * p;
            }
            let d = kff.lu().solve(&f).unwrap();
            let w = 0.5 * (d[tip[0]] + d[tip[1]]);
            let exact = p * l.powi(3) / (3.0 * ei);
            let tol = if bending == Bending::V2 { 1e-9 } else { 1e-4 };
            assert!(
                (w / exact - 1.0).abs() < tol,
                "{bending:?} n = {n}: {w} vs {exact}"
            );
        }
    }
}

/// The paper's modal form (Eqs. 5–10): with the linear local energy, the strain energy of a
/// large deformed state equals `½ Δqᵀ Ω Δq` of the elastic coordinates `Δq = Hᵀ M ΔX` in the
/// mass-normalised free–free modes.
#[test]
fn strain_energy_is_the_modal_energy() {
    for shape in [Shape::Rectangle, Shape::Trapezoid, Shape::General] {
        let c = case(shape, opts(Bending::V2, false));
        let el = &c.element;
        let (omega, h) = el.free_free_modes();
        let mh = el.local_mass() * h;
        let ortho = h.transpose() * mh;
        assert!(
            (ortho - SMatrix::<f64, 18, 18>::identity()).norm() < 1e-9,
            "HᵀMH"
        );
        for state in &c.states[1..] {
            let frames: Vec<crate::elements::Frame> = state
                .r_ref
                .iter()
                .enumerate()
                .map(|(i, r)| crate::elements::Frame {
                    rot: r * exp_so3(&state.q.fixed_rows::<3>(6 * i + 3).into_owned()),
                    tangent: Matrix3::identity(),
                })
                .collect();
            let s = crate::elements::ElementState {
                q: state.q,
                v: state.v,
                frames: &frames,
            };
            let dq = el.elastic_coordinates(&s, &h);
            let modal = 0.5 * dq.dot(&omega.component_mul(&dq));
            let u = el.strain_energy_at(&s);
            assert!(
                (modal - u).abs() < 1e-9 * u,
                "{shape:?} {}: {modal} vs {u}",
                state.label
            );
        }
    }
}
