//! The 4-node cord–rubber membrane quadrilateral: the fiber membrane energy of the air spring's
//! wall on the seed-004 shell mesh (issue 11, level 1; the seed leaves cord–rubber layers as
//! future work, `shared/reference/seed004-trapezoid-shell-and-air-spring.md` D). The seed-004
//! element ([`super::trapezoid_shell`]) carries the wall's bending on the same nodes; this one
//! carries its membrane, exactly in finite strain.
//!
//! Coordinates `q = [x₁, x₂, x₃, x₄]` [m], the corner positions, counter-clockwise about the
//! outward normal; reference corners `X_i` (a facet of the stress-free sleeve).
//!
//! * Shape functions: bilinear, `N_i = (1 + ξ ξ_i)(1 + η η_i)/4` on `[−1, 1]²`.
//! * Strains: the surface metric `C_ab = g_a · g_b` with `g_a = Σ N_i,a x_i` against the
//!   reference `G_ab = G_a · G_b` (`G_a = Σ N_i,a X_i`): the surface deformation gradient
//!   `F = g_a ⊗ Gᵃ` gives the cord stretch `|F a₀|² = cᵃ cᵇ C_ab` and the principal stretches.
//! * Energy: `U = ∫ W(C) dA₀` with the wall law [`CordRubberWall::surface`], 2 × 2 Gauss.
//!   Internal force and tangent are its exact first and second derivatives:
//!   `f = Σ ∂W/∂C_p ∂C_p/∂q`, `K = Σ ∂²W/∂C_p∂C_q ∂C_p/∂q ∂C_q/∂qᵀ + Σ ∂W/∂C_p ∂²C_p/∂q²`.
//! * Mass: consistent `ρ_A ∫ N_i N_j dA₀` per direction (mass per reference area `ρ_A`
//!   [kg/m²]), constant; 0 where the seed-004 element on the same nodes carries the inertia.
//!
//! The energy depends on the metric only, so the element is invariant under rigid motions of
//! any size and passes every conformance check (`src/elements/tests/cord_rubber_quad.rs`).

use super::cord_rubber::{CordRubberWall, SurfaceReference};
use super::element::{Element, ElementState, Layout, Slot};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

const LAYOUT: Layout = Layout {
    dim: 3,
    slots: &[
        Slot::Position,
        Slot::Position,
        Slot::Position,
        Slot::Position,
    ],
};

/// Coordinates per element.
pub const QUAD_DOFS: usize = 12;
/// Element vector.
pub type Vec12 = SVector<f64, QUAD_DOFS>;
/// Element matrix.
pub type Mat12 = SMatrix<f64, QUAD_DOFS, QUAD_DOFS>;

/// Corner coordinates `(ξ_i, η_i)`.
const CORNERS: [(f64, f64); 4] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
/// Gauss abscissa of the two-point rule.
const G: f64 = 0.577_350_269_189_625_8;

// ------------------------------------------------------------------------- shape functions

/// `N_i`, `N_i,ξ`, `N_i,η` at `(ξ, η)`.
fn shape(xi: f64, eta: f64) -> ([f64; 4], [[f64; 2]; 4]) {
    let mut n = [0.0; 4];
    let mut d = [[0.0; 2]; 4];
    for (i, &(a, b)) in CORNERS.iter().enumerate() {
        n[i] = 0.25 * (1.0 + a * xi) * (1.0 + b * eta);
        d[i] = [0.25 * a * (1.0 + b * eta), 0.25 * b * (1.0 + a * xi)];
    }
    (n, d)
}

/// One Gauss point: shape derivatives, the wall's reference there and the weight `w √det G`.
#[derive(Clone, Copy, Debug)]
struct Point {
    dn: [[f64; 2]; 4],
    reference: SurfaceReference,
    weight: f64,
}

/// One membrane quadrilateral.
#[derive(Clone, Debug)]
pub struct CordRubberQuad {
    /// The wall law.
    pub wall: CordRubberWall,
    points: [Point; 4],
    area: f64,
    mass: Mat12,
}

impl CordRubberQuad {
    /// An element on the reference corners `x` [m] (counter-clockwise about the outward
    /// normal), with the unit meridian direction `meridian` of the stress-free sleeve (the cords
    /// lie at `±α₀` from it), the wall and the mass per reference area [kg/m²]. Errors for a
    /// degenerate quadrilateral.
    pub fn new(
        x: [Vector3<f64>; 4],
        meridian: Vector3<f64>,
        wall: CordRubberWall,
        mass_per_area: f64,
    ) -> Result<Self, String> {
        let mut points = [Point {
            dn: [[0.0; 2]; 4],
            reference: SurfaceReference {
                g_inv: [0.0; 3],
                det_g: 0.0,
                cords: [[0.0; 3]; 2],
            },
            weight: 0.0,
        }; 4];
        let mut mass = Mat12::zeros();
        let mut area = 0.0;
        for (k, (xi, eta)) in [(-G, -G), (G, -G), (G, G), (-G, G)].into_iter().enumerate() {
            let (n, dn) = shape(xi, eta);
            let (g1, g2) = tangents(&x, &dn);
            let reference = SurfaceReference::new(&g1, &g2, &meridian, wall.cord_angle)
                .ok_or_else(|| format!("degenerate membrane quadrilateral {x:?}"))?;
            let weight = reference.det_g.sqrt();
            area += weight;
            for i in 0..4 {
                for j in 0..4 {
                    let m = mass_per_area * n[i] * n[j] * weight;
                    for c in 0..3 {
                        mass[(3 * i + c, 3 * j + c)] += m;
                    }
                }
            }
            points[k] = Point {
                dn,
                reference,
                weight,
            };
        }
        Ok(Self {
            wall,
            points,
            area,
            mass,
        })
    }

    /// Reference area [m²].
    pub fn area(&self) -> f64 {
        self.area
    }

    // --------------------------------------------------------------------- internal forces

    /// Strain energy [J]; with `f` the internal force, with `k` the tangent (both overwritten).
    fn evaluate(&self, q: &Vec12, mut f: Option<&mut Vec12>, mut k: Option<&mut Mat12>) -> f64 {
        let x: [Vector3<f64>; 4] = std::array::from_fn(|i| q.fixed_rows::<3>(3 * i).into_owned());
        if let Some(f) = f.as_deref_mut() {
            f.fill(0.0);
        }
        if let Some(k) = k.as_deref_mut() {
            k.fill(0.0);
        }
        let mut u = 0.0;
        for p in &self.points {
            let (g1, g2) = tangents(&x, &p.dn);
            let c = [g1.dot(&g1), g2.dot(&g2), g1.dot(&g2)];
            let e = self.wall.surface_with(&c, &p.reference, k.is_some());
            u += e.w * p.weight;
            // ∂C_p/∂x_i: C₁₁ → 2 N_i,ξ g₁, C₂₂ → 2 N_i,η g₂, C₁₂ → N_i,ξ g₂ + N_i,η g₁
            if let Some(f) = f.as_deref_mut() {
                // f += Σ_p (∂W/∂C_p w) ∂C_p/∂q, node by node: each entry takes the three terms
                // in the order p = 1, 2, 3 and the roundings of three whole-vector updates
                let s = [
                    e.grad[0] * p.weight,
                    e.grad[1] * p.weight,
                    e.grad[2] * p.weight,
                ];
                for i in 0..4 {
                    let [a, b] = p.dn[i];
                    let (a2, b2) = (2.0 * a, 2.0 * b);
                    for c in 0..3 {
                        let r = &mut f[3 * i + c];
                        *r += s[0] * (g1[c] * a2);
                        *r += s[1] * (g2[c] * b2);
                        *r += s[2] * (g2[c] * a + g1[c] * b);
                    }
                }
            }
            // ------------------------------------------------------------------- tangent
            if let Some(k) = k.as_deref_mut() {
                let dc = strain_columns(&g1, &g2, &p.dn);
                // B H Bᵀ with B = [∂C₁₁/∂q ∂C₂₂/∂q ∂C₁₂/∂q] (12 × 3)
                let b = SMatrix::<f64, QUAD_DOFS, 3>::from_columns(&dc);
                let bh = b * (e.hess * p.weight);
                k.gemm(1.0, &bh, &b.transpose(), 1.0);
                // Σ ∂W/∂C_p ∂²C_p/∂x_i∂x_j, a multiple of the identity per node pair
                for i in 0..4 {
                    for j in 0..4 {
                        let (ai, bi) = (p.dn[i][0], p.dn[i][1]);
                        let (aj, bj) = (p.dn[j][0], p.dn[j][1]);
                        let s = p.weight
                            * (e.grad[0] * 2.0 * ai * aj
                                + e.grad[1] * 2.0 * bi * bj
                                + e.grad[2] * (ai * bj + bi * aj));
                        let mut blk = k.fixed_view_mut::<3, 3>(3 * i, 3 * j);
                        blk += Matrix3::identity() * s;
                    }
                }
            }
        }
        u
    }
}

/// The three columns `∂C₁₁/∂q`, `∂C₂₂/∂q`, `∂C₁₂/∂q` (12-vectors) of the surface metric
/// `C = [g₁·g₁, g₂·g₂, g₁·g₂]` at a point with tangents `g1`, `g2` and shape-function
/// derivatives `dn` (per node `[∂N/∂ξ, ∂N/∂η]`).
fn strain_columns(g1: &Vector3<f64>, g2: &Vector3<f64>, dn: &[[f64; 2]; 4]) -> [Vec12; 3] {
    let mut dc = [Vec12::zeros(); 3];
    for i in 0..4 {
        let [a, b] = dn[i];
        dc[0]
            .fixed_rows_mut::<3>(3 * i)
            .copy_from(&(g1 * (2.0 * a)));
        dc[1]
            .fixed_rows_mut::<3>(3 * i)
            .copy_from(&(g2 * (2.0 * b)));
        dc[2]
            .fixed_rows_mut::<3>(3 * i)
            .copy_from(&(g2 * a + g1 * b));
    }
    dc
}

#[cfg(test)]
impl CordRubberQuad {
    /// The internal force [N] the way the element formed it before session 39: the three
    /// columns `∂C_p/∂q` built as 12-vectors and added with `axpy`; the reference for the
    /// node-by-node force of [`CordRubberQuad::evaluate`] (which must agree to the bit).
    pub(crate) fn force_by_columns(&self, q: &Vec12) -> Vec12 {
        let x: [Vector3<f64>; 4] = std::array::from_fn(|i| q.fixed_rows::<3>(3 * i).into_owned());
        let mut f = Vec12::zeros();
        for p in &self.points {
            let (g1, g2) = tangents(&x, &p.dn);
            let c = [g1.dot(&g1), g2.dot(&g2), g1.dot(&g2)];
            let e = self.wall.surface_with(&c, &p.reference, false);
            let dc = strain_columns(&g1, &g2, &p.dn);
            for (d, s) in dc.iter().zip(e.grad.iter()) {
                f.axpy(s * p.weight, d, 1.0);
            }
        }
        f
    }
}

/// Tangent vectors `(x_ξ, x_η)` of the bilinear patch through `x`.
fn tangents(x: &[Vector3<f64>; 4], dn: &[[f64; 2]; 4]) -> (Vector3<f64>, Vector3<f64>) {
    let mut a = Vector3::zeros();
    let mut b = Vector3::zeros();
    for i in 0..4 {
        a += x[i] * dn[i][0];
        b += x[i] * dn[i][1];
    }
    (a, b)
}

impl Element<QUAD_DOFS> for CordRubberQuad {
    fn layout(&self) -> Layout {
        LAYOUT
    }

    fn constant_mass_matrix(&self) -> Option<&Mat12> {
        Some(&self.mass)
    }

    fn mass_into(&self, _s: &ElementState<QUAD_DOFS>, m: &mut Mat12) {
        m.copy_from(&self.mass);
    }

    fn gravity_into(&self, _s: &ElementState<QUAD_DOFS>, g: &Vector3<f64>, f: &mut Vec12) {
        let ug = Vec12::from_fn(|i, _| g[i % 3]);
        f.copy_from(&(self.mass * ug));
    }

    fn strain_energy_at(&self, s: &ElementState<QUAD_DOFS>) -> f64 {
        self.evaluate(&s.q, None, None)
    }

    fn force_into(&self, s: &ElementState<QUAD_DOFS>, f: &mut Vec12) -> f64 {
        self.evaluate(&s.q, Some(f), None)
    }

    fn tangent_into(
        &self,
        s: &ElementState<QUAD_DOFS>,
        f: &mut Vec12,
        k: &mut Mat12,
        c: Option<&mut Mat12>,
    ) -> f64 {
        if let Some(c) = c {
            c.fill(0.0);
        }
        self.evaluate(&s.q, Some(f), Some(k))
    }
}
