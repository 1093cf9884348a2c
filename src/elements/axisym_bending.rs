//! Rotation-free meridional bending of an axisymmetric shell: a hinge at every inner node of
//! the meridian with the energy `U = ½ k θ²`, `θ` the signed angle between the two meridian
//! segments at the node (0 on the straight stress-free sleeve), `k = D 2π R / L̄` from the
//! bending stiffness `D` [N m], the node's reference radius `R` and the mean reference length of
//! the two segments `L̄`: the discrete form of `½ D κ_s²` per area with `κ_s ≈ θ / L̄` (the
//! "hinge" of rotation-free shells and discrete elastic rods, Bergou et al. 2008, §4.2). Hoop
//! bending is not included. It regularizes the membrane of the air spring (issue 11, item 2:
//! bending from the thickness, `D = E t³/12`, or a given bending stiffness).
//!
//! Coordinates `q = [r₀, z₀, r₁, z₁, r₂, z₂]` of the three nodes [m]; no mass.

use super::element::{Element, ElementState, Layout, Slot};
use nalgebra::{Matrix2, SMatrix, SVector, Vector2, Vector3};

const LAYOUT: Layout = Layout {
    dim: 2,
    slots: &[Slot::Position, Slot::Position, Slot::Position],
};

/// One hinge between two meridian segments.
#[derive(Clone, Debug)]
pub struct AxisymHinge {
    /// Hinge stiffness `k = D 2π R / L̄` [N m/rad²·rad = N m].
    pub stiffness: f64,
    zero: SMatrix<f64, 6, 6>,
}

/// `∂φ/∂v` and `∂²φ/∂v²` of the direction angle `φ = atan2(v_z, v_r)` of a segment `v`.
fn angle_derivatives(v: &Vector2<f64>) -> (Vector2<f64>, Matrix2<f64>) {
    let s = v.norm_squared();
    let g = Vector2::new(-v.y, v.x) / s;
    let off = (v.y * v.y - v.x * v.x) / (s * s);
    let h = Matrix2::new(
        2.0 * v.x * v.y / (s * s),
        off,
        off,
        -2.0 * v.x * v.y / (s * s),
    );
    (g, h)
}

impl AxisymHinge {
    /// A hinge at a node of reference radius `radius` [m] between segments of reference lengths
    /// `lengths` [m], for the bending stiffness `d` [N m].
    pub fn new(d: f64, radius: f64, lengths: [f64; 2]) -> Self {
        let mean = 0.5 * (lengths[0] + lengths[1]);
        Self {
            stiffness: d * 2.0 * std::f64::consts::PI * radius / mean,
            zero: SMatrix::zeros(),
        }
    }

    /// The hinge angle `θ` [rad] at coordinates `q`.
    pub fn angle(q: &SVector<f64, 6>) -> f64 {
        let a = Vector2::new(q[2] - q[0], q[3] - q[1]);
        let b = Vector2::new(q[4] - q[2], q[5] - q[3]);
        (a.x * b.y - a.y * b.x).atan2(a.dot(&b))
    }

    fn evaluate(
        &self,
        q: &SVector<f64, 6>,
        f: Option<&mut SVector<f64, 6>>,
        k: Option<&mut SMatrix<f64, 6, 6>>,
    ) -> f64 {
        let a = Vector2::new(q[2] - q[0], q[3] - q[1]);
        let b = Vector2::new(q[4] - q[2], q[5] - q[3]);
        let theta = Self::angle(q);
        let (ga, ha) = angle_derivatives(&a);
        let (gb, hb) = angle_derivatives(&b);
        // θ = φ_b − φ_a; a = x₁ − x₀, b = x₂ − x₁
        let mut grad = SVector::<f64, 6>::zeros();
        for c in 0..2 {
            grad[c] = ga[c];
            grad[2 + c] = -ga[c] - gb[c];
            grad[4 + c] = gb[c];
        }
        if let Some(f) = f {
            *f = self.stiffness * theta * grad;
        }
        if let Some(k) = k {
            // ∇²θ = B_bᵀ H_b B_b − B_aᵀ H_a B_a with B_a = [−I I 0], B_b = [0 −I I]
            let mut hess = SMatrix::<f64, 6, 6>::zeros();
            for i in 0..2 {
                for j in 0..2 {
                    let (x, y) = (ha[(i, j)], hb[(i, j)]);
                    hess[(i, j)] -= x;
                    hess[(i, 2 + j)] += x;
                    hess[(2 + i, j)] += x;
                    hess[(2 + i, 2 + j)] -= x;
                    hess[(2 + i, 2 + j)] += y;
                    hess[(2 + i, 4 + j)] -= y;
                    hess[(4 + i, 2 + j)] -= y;
                    hess[(4 + i, 4 + j)] += y;
                }
            }
            *k = self.stiffness * (grad * grad.transpose() + theta * hess);
        }
        0.5 * self.stiffness * theta * theta
    }
}

impl Element<6> for AxisymHinge {
    fn layout(&self) -> Layout {
        LAYOUT
    }

    /// No mass (the membrane elements carry the wall's mass).
    fn constant_mass_matrix(&self) -> Option<&SMatrix<f64, 6, 6>> {
        Some(&self.zero)
    }

    fn mass_into(&self, _s: &ElementState<6>, m: &mut SMatrix<f64, 6, 6>) {
        m.fill(0.0);
    }

    fn gravity_into(&self, _s: &ElementState<6>, _g: &Vector3<f64>, f: &mut SVector<f64, 6>) {
        f.fill(0.0);
    }

    fn strain_energy_at(&self, s: &ElementState<6>) -> f64 {
        self.evaluate(&s.q, None, None)
    }

    fn force_into(&self, s: &ElementState<6>, f: &mut SVector<f64, 6>) -> f64 {
        self.evaluate(&s.q, Some(f), None)
    }

    fn tangent_into(
        &self,
        s: &ElementState<6>,
        f: &mut SVector<f64, 6>,
        k: &mut SMatrix<f64, 6, 6>,
        c: Option<&mut SMatrix<f64, 6, 6>>,
    ) -> f64 {
        if let Some(c) = c {
            c.fill(0.0);
        }
        self.evaluate(&s.q, Some(f), Some(k))
    }
}
