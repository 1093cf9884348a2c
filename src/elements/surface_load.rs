//! Follower pressure on a bilinear quadrilateral surface patch and the patch's part of the
//! volume enclosed by a closed surface (seed-004 air spring, Pogorelov & Rodikov 2021: the
//! pressure of the enclosed gas acts on the deformed shell and the gas volume follows it).
//!
//! The patch is `x(ξ, η) = Σ N_i(ξ, η) x_i` on `[0, 1]²` with the bilinear functions
//! `N_1 = (1−ξ)(1−η)`, `N_2 = ξ(1−η)`, `N_3 = ξη`, `N_4 = (1−ξ)η` (corners 1: (0,0), 2: (1,0),
//! 3: (1,1), 4: (0,1)). Its area vector density is `x_ξ × x_η` [m2]: the normal points to the
//! side from which the corners run counter-clockwise. Every integrand below is at most
//! quadratic in each of ξ and η, so the 2 × 2 Gauss rule is exact; nothing allocates.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Gauss points of the 2-point rule on [0, 1]: `(1 ∓ 1/√3) / 2` (weights 1/2 each).
const G: [f64; 2] = [0.211_324_865_405_187_1, 0.788_675_134_594_812_9];

/// Shape functions and their derivatives `(N, N_ξ, N_η)` at `(ξ, η)`.
#[inline]
const fn shape(xi: f64, eta: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    (
        [
            (1.0 - xi) * (1.0 - eta),
            xi * (1.0 - eta),
            xi * eta,
            (1.0 - xi) * eta,
        ],
        [-(1.0 - eta), 1.0 - eta, eta, -eta],
        [-(1.0 - xi), -xi, xi, 1.0 - xi],
    )
}

/// `(x, x_ξ, x_η)` of the patch [m] for the shape values `(n, dxi, deta)`.
#[inline]
fn interpolate(
    x: &[Vector3<f64>; 4],
    n: &[f64; 4],
    dxi: &[f64; 4],
    deta: &[f64; 4],
) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let mut p = Vector3::zeros();
    for i in 0..4 {
        p += x[i] * n[i];
    }
    let (a, b) = tangents(x, dxi, deta);
    (p, a, b)
}

/// [`shape`] at the 2 × 2 Gauss points `(G[i], G[j])`, `i` outer, evaluated once at
/// compile time (the same values as at run time: IEEE arithmetic either way).
const SHAPES: [([f64; 4], [f64; 4], [f64; 4]); 4] = [
    shape(G[0], G[0]),
    shape(G[0], G[1]),
    shape(G[1], G[0]),
    shape(G[1], G[1]),
];

/// `(x_ξ, x_η)` of the patch [m] (the two last of [`interpolate`], in the same order of
/// operations).
#[inline]
fn tangents(
    x: &[Vector3<f64>; 4],
    dxi: &[f64; 4],
    deta: &[f64; 4],
) -> (Vector3<f64>, Vector3<f64>) {
    let (mut a, mut b) = (Vector3::zeros(), Vector3::zeros());
    for i in 0..4 {
        a += x[i] * dxi[i];
        b += x[i] * deta[i];
    }
    (a, b)
}

/// The 2 × 2 Gauss points on [0, 1]² with weight 1/4 each (the tests' independent rule; the
/// kernels take [`SHAPES`]).
#[cfg(test)]
fn gauss_points() -> impl Iterator<Item = (f64, f64)> {
    G.iter().flat_map(|&xi| G.iter().map(move |&eta| (xi, eta)))
}

/// Pressure force on the corners of a bilinear patch and its tangent.
///
/// `x`: corner positions [m] in the order above; `p`: pressure [Pa] acting along
/// `+n = x_ξ × x_η` (for a closed surface whose corners run counter-clockwise seen from
/// outside, `p > 0` is an internal gauge pressure that inflates it). Writes (overwriting)
/// `f = [f_1, f_2, f_3, f_4]` [N] with `f_i = p ∫ N_i (x_ξ × x_η) dξ dη`, whose sum is `p` times
/// the vector area `½ (x_3 − x_1) × (x_4 − x_2)`, and, if asked, the follower tangent
/// `k = ∂f/∂x` [N/m] (12 × 12, not symmetric for a single patch):
/// `∂f_i/∂x_j = p ∫ N_i (N_j,η [x_ξ]× − N_j,ξ [x_η]×) dξ dη`. Exact (2 × 2 Gauss).
pub fn pressure_into(
    x: &[Vector3<f64>; 4],
    p: f64,
    f: &mut SVector<f64, 12>,
    mut k: Option<&mut SMatrix<f64, 12, 12>>,
) {
    f.fill(0.0);
    if let Some(k) = k.as_deref_mut() {
        k.fill(0.0);
    }
    let w = 0.25 * p;
    for (n, dxi, deta) in &SHAPES {
        let (a, b) = tangents(x, dxi, deta);
        let nrm = a.cross(&b) * w;
        for i in 0..4 {
            let mut fi = f.fixed_rows_mut::<3>(3 * i);
            fi += nrm * n[i];
        }
        if let Some(k) = k.as_deref_mut() {
            let (sa, sb) = (a.cross_matrix() * w, b.cross_matrix() * w);
            for j in 0..4 {
                let dj: Matrix3<f64> = sa * deta[j] - sb * dxi[j];
                for i in 0..4 {
                    let mut kij = k.fixed_view_mut::<3, 3>(3 * i, 3 * j);
                    kij += dj * n[i];
                }
            }
        }
    }
}

/// The patch's part `(1/3) ∫ x · (x_ξ × x_η) dξ dη` [m3] of the volume enclosed by a closed
/// surface whose corners run counter-clockwise seen from outside (divergence theorem with
/// `div x = 3`); exact for the bilinear patch. The parts of a closed surface sum to its volume
/// whatever the origin; a single part depends on it.
///
/// In closed form: the integrand is a polynomial, and the integral is the mean of the cones
/// from the origin over the two triangulations of the patch,
/// `(1/12) [x₁·(x₂×x₃) + x₁·(x₃×x₄) + x₁·(x₂×x₄) + x₂·(x₃×x₄)]` (four triple products
/// instead of four quadrature points; checked against the 2 × 2 Gauss rule in the tests).
pub fn volume_part(x: &[Vector3<f64>; 4]) -> f64 {
    let [a, b, c, d] = x;
    let cd = c.cross(d);
    (a.dot(&(b.cross(c) + cd + b.cross(d))) + b.dot(&cd)) / 12.0
}

/// Gradient of [`volume_part`] with respect to the corners `[x_1, x_2, x_3, x_4]` [m2] (12):
/// `∂V/∂x_j = (1/3) ∫ N_j (x_ξ × x_η) + N_j,ξ (x_η × x) + N_j,η (x × x_ξ) dξ dη`. Summed over a
/// closed surface the last two terms cancel and it equals the pressure force per unit pressure
/// of [`pressure_into`] (the volume grows along the outward normal); for one patch it does not.
pub fn volume_part_gradient(x: &[Vector3<f64>; 4]) -> SVector<f64, 12> {
    let mut g = SVector::<f64, 12>::zeros();
    for (n, dxi, deta) in &SHAPES {
        let (p, a, b) = interpolate(x, n, dxi, deta);
        let (ab, bp, pa) = (a.cross(&b), b.cross(&p), p.cross(&a));
        for j in 0..4 {
            let mut gj = g.fixed_rows_mut::<3>(3 * j);
            gj += (ab * n[j] + bp * dxi[j] + pa * deta[j]) * (0.25 / 3.0);
        }
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::finite_difference::{assert_jacobian, gradient};
    use nalgebra::DMatrix;

    fn corners(q: &[f64]) -> [Vector3<f64>; 4] {
        std::array::from_fn(|i| Vector3::new(q[3 * i], q[3 * i + 1], q[3 * i + 2]))
    }

    /// A warped (non-planar), skewed patch away from the origin.
    fn warped() -> [Vector3<f64>; 4] {
        [
            Vector3::new(0.11, -0.05, 0.31),
            Vector3::new(0.52, 0.03, 0.27),
            Vector3::new(0.61, 0.44, 0.42),
            Vector3::new(0.07, 0.38, 0.22),
        ]
    }

    /// The six faces of the axis-aligned box `[x0, x0 + lx] × [y0, y0 + ly] × [z0, z0 + lz]`,
    /// corners counter-clockwise seen from outside.
    fn box_faces(o: Vector3<f64>, l: Vector3<f64>) -> (Vec<Vector3<f64>>, Vec<[usize; 4]>) {
        let nodes: Vec<Vector3<f64>> = (0..8)
            .map(|c| {
                o + Vector3::new(
                    l.x * (c & 1) as f64,
                    l.y * ((c >> 1) & 1) as f64,
                    l.z * ((c >> 2) & 1) as f64,
                )
            })
            .collect();
        // corner c = x + 2 y + 4 z
        let faces = vec![
            [0, 2, 3, 1], // z = 0, normal -z
            [4, 5, 7, 6], // z = lz, normal +z
            [0, 1, 5, 4], // y = 0, normal -y
            [2, 6, 7, 3], // y = ly, normal +y
            [0, 4, 6, 2], // x = 0, normal -x
            [1, 3, 7, 5], // x = lx, normal +x
        ];
        (nodes, faces)
    }

    fn gather(nodes: &[Vector3<f64>], el: &[usize; 4]) -> [Vector3<f64>; 4] {
        el.map(|k| nodes[k])
    }

    /// The tangent is the derivative of the force (finite differences on a warped patch).
    #[test]
    fn pressure_tangent_matches_finite_differences() {
        let x = warped();
        let p = 2.5e5;
        let (mut f, mut k) = (SVector::<f64, 12>::zeros(), SMatrix::<f64, 12, 12>::zeros());
        pressure_into(&x, p, &mut f, Some(&mut k));
        let q: Vec<f64> = x.iter().flat_map(|v| v.iter().copied()).collect();
        let analytic = DMatrix::from_column_slice(12, 12, k.as_slice());
        assert_jacobian("pressure tangent", &analytic, &q, 1e-6, 1e-8, |q, out| {
            let mut fq = SVector::<f64, 12>::zeros();
            pressure_into(&corners(q), p, &mut fq, None);
            out.copy_from_slice(fq.as_slice());
        });
        // the force without the tangent is the same
        let mut f2 = SVector::<f64, 12>::zeros();
        pressure_into(&x, p, &mut f2, None);
        assert_eq!(f, f2);
    }

    /// The resultant is p times the vector area `½ (x3 − x1) × (x4 − x2)`; on a flat rectangle
    /// every corner carries a quarter of it along the normal.
    #[test]
    fn resultant_is_pressure_times_vector_area() {
        let x = warped();
        let p = -1.7e3;
        let mut f = SVector::<f64, 12>::zeros();
        pressure_into(&x, p, &mut f, None);
        let sum: Vector3<f64> = (0..4).map(|i| f.fixed_rows::<3>(3 * i).into_owned()).sum();
        let area = 0.5 * (x[2] - x[0]).cross(&(x[3] - x[1]));
        assert!(
            (sum - area * p).norm() < 1e-12 * (area * p).norm(),
            "{sum} {area}"
        );
        // a 0.3 × 0.2 rectangle in the plane z = 1, counter-clockwise seen from +z
        let r = [
            Vector3::new(0.0, 0.0, 1.0),
            Vector3::new(0.3, 0.0, 1.0),
            Vector3::new(0.3, 0.2, 1.0),
            Vector3::new(0.0, 0.2, 1.0),
        ];
        pressure_into(&r, 1e5, &mut f, None);
        for i in 0..4 {
            let fi = f.fixed_rows::<3>(3 * i);
            let expect = Vector3::new(0.0, 0.0, 1e5 * 0.06 / 4.0);
            assert!((fi - expect).norm() < 1e-9, "corner {i}: {fi}");
        }
    }

    /// The closed form of the volume part is the exact 2 × 2 Gauss rule of its integral, on
    /// a warped patch and on a stretched, shifted one.
    #[test]
    fn volume_part_is_the_gauss_rule() {
        for x in [
            warped(),
            warped().map(|p| p * 3.0 - Vector3::new(0.2, -1.0, 0.7)),
        ] {
            let mut v = 0.0;
            for (xi, eta) in gauss_points() {
                let (n, dxi, deta) = shape(xi, eta);
                let (p, a, b) = interpolate(&x, &n, &dxi, &deta);
                v += p.dot(&a.cross(&b));
            }
            v *= 0.25 / 3.0;
            let closed = volume_part(&x);
            assert!(
                (closed - v).abs() <= 1e-14 * v.abs().max(1.0),
                "{closed} vs {v}"
            );
        }
    }

    /// The volume gradient is the derivative of the volume part (finite differences).
    #[test]
    fn volume_gradient_matches_finite_differences() {
        let x = warped();
        let q: Vec<f64> = x.iter().flat_map(|v| v.iter().copied()).collect();
        let fd = gradient(&q, |_| 1e-6, |q| volume_part(&corners(q)));
        let g = volume_part_gradient(&x);
        let analytic = DMatrix::from_column_slice(12, 1, g.as_slice());
        let fd = DMatrix::from_column_slice(12, 1, &fd);
        crate::elements::finite_difference::assert_close(
            "volume gradient",
            &analytic,
            &fd,
            1e-8,
            0.0,
        );
    }

    /// A box with warped faces (its corners moved): the parts sum to the same volume wherever
    /// the origin is, an axis-aligned box gives `lx ly lz` exactly, and the summed volume
    /// gradient equals the summed pressure force per unit pressure at every node.
    #[test]
    fn closed_box_volume_translation_invariance_and_gradient() {
        let (o, l) = (Vector3::new(0.3, -0.2, 0.7), Vector3::new(0.4, 0.25, 0.15));
        let (mut nodes, faces) = box_faces(o, l);
        let total = |nodes: &[Vector3<f64>]| -> f64 {
            faces.iter().map(|el| volume_part(&gather(nodes, el))).sum()
        };
        let exact = l.x * l.y * l.z;
        assert!((total(&nodes) - exact).abs() < 1e-14, "{}", total(&nodes));
        // warp: move every corner, faces become non-planar
        for (c, x) in nodes.iter_mut().enumerate() {
            let c = c as f64;
            *x += Vector3::new(
                0.03 * (1.3 * c).sin(),
                0.02 * (0.7 * c).cos(),
                0.025 * (2.1 * c).sin(),
            );
        }
        let v0 = total(&nodes);
        let shift = Vector3::new(-3.1, 4.7, 12.5);
        let moved: Vec<Vector3<f64>> = nodes.iter().map(|x| x + shift).collect();
        let v1 = total(&moved);
        assert!((v1 - v0).abs() < 1e-12, "{v0} vs {v1}");
        assert!(
            (v0 - exact).abs() > 1e-4,
            "the warp changes the volume: {v0}"
        );
        let mut grad = vec![Vector3::zeros(); nodes.len()];
        let mut force = vec![Vector3::zeros(); nodes.len()];
        let mut f = SVector::<f64, 12>::zeros();
        for el in &faces {
            let x = gather(&moved, el);
            let g = volume_part_gradient(&x);
            pressure_into(&x, 1.0, &mut f, None);
            for (i, &k) in el.iter().enumerate() {
                grad[k] += g.fixed_rows::<3>(3 * i);
                force[k] += f.fixed_rows::<3>(3 * i);
            }
        }
        for k in 0..nodes.len() {
            assert!(
                (grad[k] - force[k]).norm() < 1e-12,
                "node {k}: {} vs {}",
                grad[k],
                force[k]
            );
            assert!(grad[k].norm() > 1e-3, "node {k}");
        }
        // a single face's gradient is not its force (the cancellation needs a closed surface)
        let x = gather(&moved, &faces[0]);
        pressure_into(&x, 1.0, &mut f, None);
        assert!((volume_part_gradient(&x) - f).norm() > 1e-3);
    }

    /// The summed pressure tangent of a closed surface is the Hessian of `p V`: symmetric.
    #[test]
    fn closed_surface_pressure_tangent_is_symmetric() {
        let (nodes, faces) = box_faces(Vector3::new(0.1, 0.2, 0.3), Vector3::new(0.5, 0.3, 0.2));
        let n = 3 * nodes.len();
        let mut kt = DMatrix::<f64>::zeros(n, n);
        let (mut f, mut k) = (SVector::<f64, 12>::zeros(), SMatrix::<f64, 12, 12>::zeros());
        for el in &faces {
            pressure_into(&gather(&nodes, el), 3e4, &mut f, Some(&mut k));
            for (i, &a) in el.iter().enumerate() {
                for (j, &b) in el.iter().enumerate() {
                    let mut blk = kt.view_mut((3 * a, 3 * b), (3, 3));
                    blk += k.fixed_view::<3, 3>(3 * i, 3 * j);
                }
            }
        }
        let asym = (&kt - kt.transpose()).norm();
        assert!(kt.norm() > 1e3, "{}", kt.norm());
        assert!(asym < 1e-10 * kt.norm(), "asymmetry {asym}");
    }
}
