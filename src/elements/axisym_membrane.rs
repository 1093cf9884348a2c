//! The 2-node conical (frustum) membrane element of an axisymmetric shell of revolution about
//! the z axis, for the membrane level of the air spring (issue 11, level 2;
//! `shared/reference/seed004-trapezoid-shell-and-air-spring.md` C.7 item 1).
//!
//! Coordinates `q = [r₁, z₁, r₂, z₂]` [m] of the two ring nodes in the meridian plane. The
//! reference (stress-free) meridian has length `L` and ring radii `R₁`, `R₂`.
//!
//! * Shape functions: linear, `N₁ = (1 − ξ)/2`, `N₂ = (1 + ξ)/2`, `ξ ∈ [−1, 1]`.
//! * Strains: meridional stretch `λ_s = ℓ/L` (`ℓ` the current length, constant over the
//!   element), hoop stretch `λ_θ(ξ) = r(ξ)/R(ξ)`.
//! * Energy: `U = ∫ W(λ_s, λ_θ) 2π R dS` with the wall law of [`crate::elements::cord_rubber`],
//!   two-point Gauss rule in `ξ`. Internal force and tangent are its exact first and second
//!   derivatives.
//! * Mass: consistent, `M_ij = ρ_A ∫ 2π R N_i N_j dS` for `r` and `z` alike (mass per reference
//!   area `ρ_A` [kg/m²]), constant.
//!
//! The element is invariant under translations along the axis only (a radial motion changes
//! the hoop stretch), so of the conformance checks it passes all but the rigid-motion ones;
//! `src/elements/tests/axisym_membrane.rs` checks the axial invariance instead.

use super::cord_rubber::CordRubberWall;
use super::element::{Element, ElementState, Layout, Slot};
use nalgebra::{Matrix4, SMatrix, SVector, Vector3, Vector4};
use std::f64::consts::PI;

const LAYOUT: Layout = Layout {
    dim: 2,
    slots: &[Slot::Position, Slot::Position],
};

/// Gauss points `ξ = ∓1/√3` of the two-point rule (weights 1).
const GAUSS: [f64; 2] = [-0.577_350_269_189_625_8, 0.577_350_269_189_625_8];

/// One conical membrane element.
#[derive(Clone, Debug)]
pub struct AxisymMembrane {
    /// Reference meridian length `L` [m].
    pub length: f64,
    /// Reference ring radii `R₁`, `R₂` [m].
    pub radius: [f64; 2],
    /// The wall law.
    pub wall: CordRubberWall,
    mass: SMatrix<f64, 4, 4>,
    /// The cord angle [rad] of `wall` at construction with its `(sin, cos)`: the kernel uses
    /// them while `wall.cord_angle` is unchanged (one `sin_cos` per element instead of one
    /// per integration point and evaluation).
    cord_trig: (f64, (f64, f64)),
    /// The reference `(length, radius)` at construction with its Gauss-point constants
    /// ([`AxisymMembrane::gauss_points`]).
    gauss: ((f64, [f64; 2]), [[f64; 3]; 2]),
}

// ------------------------------------------------------------------------- shape functions

/// `(N₁, N₂)` at `ξ`.
#[inline]
fn shape(xi: f64) -> [f64; 2] {
    [0.5 * (1.0 - xi), 0.5 * (1.0 + xi)]
}

impl AxisymMembrane {
    /// An element of reference length `length` [m] between reference radii `radius` [m], with
    /// the wall `wall` and the mass per reference area `mass_per_area` [kg/m²].
    pub fn new(length: f64, radius: [f64; 2], wall: CordRubberWall, mass_per_area: f64) -> Self {
        // ------------------------------------------------------------------------- mass
        // ∫ R N_i N_j dS over the element with R linear: L/12 [3R₁+R₂, R₁+R₂; R₁+R₂, R₁+3R₂]
        let [r1, r2] = radius;
        let f = 2.0 * PI * mass_per_area * length / 12.0;
        let (m11, m12, m22) = (f * (3.0 * r1 + r2), f * (r1 + r2), f * (r1 + 3.0 * r2));
        let mut mass = SMatrix::<f64, 4, 4>::zeros();
        for c in 0..2 {
            mass[(c, c)] = m11;
            mass[(2 + c, 2 + c)] = m22;
            mass[(c, 2 + c)] = m12;
            mass[(2 + c, c)] = m12;
        }
        Self {
            length,
            radius,
            wall,
            mass,
            cord_trig: (wall.cord_angle, wall.cord_angle.sin_cos()),
            gauss: ((length, radius), gauss_constants(length, radius)),
        }
    }

    /// Stretches `(λ_s, λ_θ)` at `ξ` for coordinates `q`.
    pub fn stretches(&self, q: &SVector<f64, 4>, xi: f64) -> (f64, f64) {
        let n = shape(xi);
        let ell = ((q[2] - q[0]).powi(2) + (q[3] - q[1]).powi(2)).sqrt();
        let r = n[0] * q[0] + n[1] * q[2];
        let rr = n[0] * self.radius[0] + n[1] * self.radius[1];
        (ell / self.length, r / rr)
    }

    // ------------------------------------------------------------------- internal forces

    /// The Gauss-point constants of the current reference (`length`, `radius`): per point
    /// `(N₁/R, N₂/R, w)` with `R` the reference radius there and `w = 2π R L/2` the weight
    /// [1/m, 1/m, m²] (kept from construction while the reference is unchanged).
    #[inline]
    fn gauss_points(&self) -> [[f64; 3]; 2] {
        if self.gauss.0 == (self.length, self.radius) {
            self.gauss.1
        } else {
            gauss_constants(self.length, self.radius)
        }
    }

    /// Energy [J], and if asked the internal force and the tangent stiffness. Inlined into
    /// each caller, so that a call without the tangent (the residual of a modified-Newton
    /// iteration) does not compute the wall law's second derivatives.
    #[inline(always)]
    fn evaluate(
        &self,
        q: &SVector<f64, 4>,
        f: Option<&mut SVector<f64, 4>>,
        k: Option<&mut SMatrix<f64, 4, 4>>,
    ) -> f64 {
        let (dr, dz) = (q[2] - q[0], q[3] - q[1]);
        let ell = (dr * dr + dz * dz).sqrt();
        let inv_len = 1.0 / self.length;
        let ls = ell * inv_len;
        let inv_ell = 1.0 / ell;
        let n = [dr * inv_ell, dz * inv_ell];
        // ∂λ_s/∂q = [−n, n]/L
        let a = Vector4::new(-n[0], -n[1], n[0], n[1]) * inv_len;
        let trig = if self.cord_trig.0 == self.wall.cord_angle {
            self.cord_trig.1
        } else {
            self.wall.cord_angle.sin_cos()
        };
        let gp = self.gauss_points();
        // sums over the points: Σ w W, Σ w ∂W/∂λ_s, Σ w ∂²W/∂λ_s², and per node Σ w ∂W/∂λ_θ b,
        // Σ w ∂²W/∂λ_s∂λ_θ b, Σ w ∂²W/∂λ_θ² b bᵀ (∂λ_θ/∂q = b = (N₁/R, 0, N₂/R, 0))
        let (mut u, mut g_s, mut h_ss) = (0.0, 0.0, 0.0);
        let (mut g_t, mut h_st) = ([0.0; 2], [0.0; 2]);
        let mut h_tt = [0.0; 3];
        for &[b1, b2, w] in &gp {
            let lt = b1 * q[0] + b2 * q[2];
            let e = self.wall.axisym_with(ls, lt, trig);
            u += w * e.w;
            g_s += w * e.grad[0];
            let wg = w * e.grad[1];
            g_t[0] += wg * b1;
            g_t[1] += wg * b2;
            if k.is_some() {
                h_ss += w * e.hess[0][0];
                let wst = w * e.hess[0][1];
                h_st[0] += wst * b1;
                h_st[1] += wst * b2;
                let wtt = w * e.hess[1][1];
                h_tt[0] += wtt * b1 * b1;
                h_tt[1] += wtt * b1 * b2;
                h_tt[2] += wtt * b2 * b2;
            }
        }
        if let Some(f) = f {
            *f = g_s * a;
            f[0] += g_t[0];
            f[2] += g_t[1];
        }
        // ------------------------------------------------------------------------ tangent
        // h_ss a aᵀ + a cᵀ + c aᵀ + B (c = Σ w W_sθ b, B = Σ w W_θθ b bᵀ) plus
        // Σ w W_s ∂²λ_s/∂q², ∂²λ_s/∂q² = (1/(L ℓ)) [P −P; −P P], P = I − n nᵀ
        if let Some(k) = k {
            let c = Vector4::new(h_st[0], 0.0, h_st[1], 0.0);
            let ac = a * c.transpose();
            *k = h_ss * a * a.transpose() + ac + ac.transpose();
            k[(0, 0)] += h_tt[0];
            k[(0, 2)] += h_tt[1];
            k[(2, 0)] += h_tt[1];
            k[(2, 2)] += h_tt[2];
            let cg = g_s * inv_len * inv_ell;
            let p = [
                [1.0 - n[0] * n[0], -n[0] * n[1]],
                [-n[0] * n[1], 1.0 - n[1] * n[1]],
            ];
            for i in 0..2 {
                for j in 0..2 {
                    let v = cg * p[i][j];
                    k[(i, j)] += v;
                    k[(2 + i, 2 + j)] += v;
                    k[(i, 2 + j)] -= v;
                    k[(2 + i, j)] -= v;
                }
            }
        }
        u
    }
}

/// `(N₁/R, N₂/R, 2π R L/2)` at the two Gauss points of an element of reference length
/// `length` [m] between reference radii `radius` [m].
fn gauss_constants(length: f64, radius: [f64; 2]) -> [[f64; 3]; 2] {
    GAUSS.map(|xi| {
        let nn = shape(xi);
        let rr = nn[0] * radius[0] + nn[1] * radius[1];
        [nn[0] / rr, nn[1] / rr, 2.0 * PI * rr * 0.5 * length]
    })
}

impl Element<4> for AxisymMembrane {
    fn layout(&self) -> Layout {
        LAYOUT
    }

    fn constant_mass_matrix(&self) -> Option<&SMatrix<f64, 4, 4>> {
        Some(&self.mass)
    }

    fn mass_into(&self, _s: &ElementState<4>, m: &mut SMatrix<f64, 4, 4>) {
        m.copy_from(&self.mass);
    }

    /// `M u_g` with `u_g = (g.x, g.y)` at both nodes (`g.y` along the axis; the kind passes
    /// no radial component).
    fn gravity_into(&self, _s: &ElementState<4>, g: &Vector3<f64>, f: &mut SVector<f64, 4>) {
        let ug = Vector4::new(g.x, g.y, g.x, g.y);
        f.copy_from(&(self.mass * ug));
    }

    fn strain_energy_at(&self, s: &ElementState<4>) -> f64 {
        self.evaluate(&s.q, None, None)
    }

    fn force_into(&self, s: &ElementState<4>, f: &mut SVector<f64, 4>) -> f64 {
        self.evaluate(&s.q, Some(f), None)
    }

    fn tangent_into(
        &self,
        s: &ElementState<4>,
        f: &mut SVector<f64, 4>,
        k: &mut SMatrix<f64, 4, 4>,
        c: Option<&mut SMatrix<f64, 4, 4>>,
    ) -> f64 {
        if let Some(c) = c {
            c.fill(0.0);
        }
        self.evaluate(&s.q, Some(f), Some(k))
    }
}

/// Volume swept by the meridian segment from `(r₁, z₁)` to `(r₂, z₂)` about the axis,
/// `v = −π (z₂ − z₁)(r₁² + r₁ r₂ + r₂²)/3` [m³] (a frustum, negative while the meridian runs
/// up), with its gradient and Hessian in `q = [r₁, z₁, r₂, z₂]`. Summed over a meridian that
/// runs from the top plate's bead down and around to the piston, it is the exact volume of the
/// polygonal bag between plate, meridian and piston top (`shared/reference/air-spring-physics.md`
/// §1.2).
#[inline]
pub fn frustum_volume(q: &SVector<f64, 4>) -> (f64, Vector4<f64>, Matrix4<f64>) {
    let (r1, z1, r2, z2) = (q[0], q[1], q[2], q[3]);
    let s = r1 * r1 + r1 * r2 + r2 * r2;
    let dz = z2 - z1;
    let c = -PI / 3.0;
    let v = c * dz * s;
    let (s1, s2) = (2.0 * r1 + r2, r1 + 2.0 * r2);
    let g = Vector4::new(c * dz * s1, -c * s, c * dz * s2, c * s);
    let mut h = Matrix4::zeros();
    h[(0, 0)] = c * dz * 2.0;
    h[(0, 2)] = c * dz;
    h[(2, 0)] = c * dz;
    h[(2, 2)] = c * dz * 2.0;
    // ∂²/∂r_i∂z: ∓c s_i
    h[(0, 1)] = -c * s1;
    h[(1, 0)] = -c * s1;
    h[(0, 3)] = c * s1;
    h[(3, 0)] = c * s1;
    h[(2, 1)] = -c * s2;
    h[(1, 2)] = -c * s2;
    h[(2, 3)] = c * s2;
    h[(3, 2)] = c * s2;
    (v, g, h)
}
