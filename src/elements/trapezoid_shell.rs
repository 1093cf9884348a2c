//! Seed-004 element: four-node trapezoidal shell in absolute coordinates, with a per-element
//! floating frame and the element's own free–free modes as elastic coordinates.
//!
//! Seed: Pogorelov & Rodikov 2021, Part I (`shared/seeds/004_*.txt`), decoded in
//! `shared/reference/seed004-trapezoid-shell-and-air-spring.md` (section C; equation numbers
//! below are the paper's).
//!
//! **Nodes and coordinates.** Four corner nodes, counter-clockwise about the element normal,
//! each with an absolute position `x_i` [m] and a node-fixed frame `R_i ∈ SO(3)` (the rotation
//! from the reference configuration, stored without singularities by
//! [`super::node_frames`]: the element sees `R_i` and its tangent only). Element vectors are
//! `[x1, θ1, …, x4, θ4]`: forces on positions in global components, moments conjugate to body
//! spins of the node frames (as the seed-003 beam, [`super::corotational3d`]).
//!
//! **Floating frame (Eqs. 12–17).** The element frame SCF has its origin at the centroid of the
//! four nodes and axes `E = [e1 e2 e3]` from the median vector `g1 = (x2 − x1 + x3 − x4)/2`
//! and the height vector `g2 = (x3 + x4 − x1 − x2)/2` (Gram–Schmidt; `e3` is the normal). In
//! SCF the nodes deflect by `ΔX = [Eᵀ(x_i − c) − ρ_i ; θ̄_i]` with the local nodal rotations
//! `θ̄_i = log(Eᵀ R_i E0)`, computed as `ψ(v) = v asin|v|/|v|` of `v = axial(Eᵀ R_i E0)`
//! (`= sin|θ̄| n`, linear in the frames, which keeps the second derivatives simple; valid for
//! local rotations below 90°). With `v` itself as the measure a strip rolled into a ring by
//! 20 elements missed closing by 1.7 % of its length. The paper defines SCF implicitly by
//! `ΔX ∈ range(H)` (Eq. 17), i.e. by `Rᵀ M ΔX = 0` for the six rigid modes `R`; this element
//! uses the explicit frame above and removes what is left of a rigid motion in `ΔX` with the
//! mass-orthogonal projector `P = I − R (Rᵀ M R)⁻¹ Rᵀ M` (`Δq = Hᵀ M ΔX` are the paper's elastic
//! coordinates, `P ΔX = H Δq`). The two frames differ by a rigid motion of the order of the
//! strains, which the strain energy does not see (`K R = 0`), and the explicit frame has
//! closed-form first and second derivatives (a second-order forward-mode dual number on the
//! six components of `g1`, `g2`), so the tangent below is exact.
//!
//! **Element in SCF (Eqs. 22–33).** The quadrilateral is mapped bilinearly on the unit square
//! (for an isosceles trapezoid this is Eq. 22: `x = (ξ − ½) a (1 + ε(η − ½))`, `y = (η − ½) b`);
//! membrane displacements are bilinear (Eq. 25, plane stress, 2 × 2 Gauss); the deflection `w`
//! uses the nodal `w_i`, `α_i = ∂w/∂y` and `β_i = −∂w/∂x` with the rectangle functions of
//! variant V2 (Eq. 28, the 12-DOF Adini–Clough–Melosh rectangle, default) or V1 (Eqs. 26–27,
//! products of Hermite cubics), composed with the map; the rotation functions are corrected at
//! their node (Eqs. 29–31) so that their slopes there are exactly `(0, 1)` and `(−1, 0)`: for an
//! isosceles trapezoid this is the paper's `N_β = d N_β^r + c N_α^r`, for a general convex
//! quadrilateral the same 2 × 2 condition on both. Kirchhoff plate energy (Eq. 33,
//! `D = E h³/(12(1 − ν²))`, 3 × 3 Gauss). The paper gives the drilling rotation `γ` no shape
//! function; here a penalty `½ k_d ∫ (γ − ω)² dA` with the bilinear `γ` and the membrane's
//! in-plane rotation `ω = ½(v,x − u,y)` (Hughes & Brezzi 1989), `k_d = drilling · G h`, keeps
//! folded shells regular without touching rigid rotations.
//!
//! **Geometric stiffness (Eq. 21, default on).** With `geometric_stiffness` the membrane strains
//! in SCF are von Kármán's, `ε = ε_lin + ½ (w,x², w,y², 2 w,x w,y)`: the initial-stress
//! stiffness `Gᵀ N G` and the large-displacement part follow from this energy exactly. Without
//! it the local energy is the linear `½ ΔXᵀ K ΔX` of the paper's Part I (large rotations come
//! from the rotating frames alone). As the paper says, it allows coarser meshes: measured, the
//! strip under an end shear k = 4 at 4 elements is 9.4e-5 instead of 6.7e-3 off the elastica
//! (`tests/shell_validation.rs`, `geometric_stiffness_on_coarse_meshes`).
//!
//! **Mass.** Translational inertia: the consistent mass `ρ h ∫ N_i N_j dA` of the bilinear
//! position field, isotropic and therefore constant in global coordinates (exact for rigid
//! translations and rotations; the bending functions' `O(element size²)` share of the inertia
//! and the paper's rotating `D⁻ᵀ M_f D⁻¹` are left out: both converge to the same kinetic
//! energy). Rotary inertia: `ρ h³/12` per area (Mindlin's), lumped at the nodes about all three
//! axes, so `J Ω̇ + Ω × J Ω = J Ω̇`. The mass matrix is constant.
//!
//! The file follows the fixed order of every element: shape functions (and kinematics), mass,
//! internal forces, tangent; then the element trait.

use super::element::{Element, ElementState, Layout, Slot};
use super::quadrature::gauss_legendre;
use super::rotation::{axial, skew};
use nalgebra::{Matrix2, Matrix3, SMatrix, SVector, Vector2, Vector3};

/// Coordinates per node `[x, y, z, θx, θy, θz]`.
pub const NODE_DOFS: usize = 6;
/// Coordinates per element (4 nodes).
pub const ELEMENT_DOFS: usize = 24;
/// Element vector.
pub type Vec24 = SVector<f64, ELEMENT_DOFS>;
/// Element matrix.
pub type Mat24 = SMatrix<f64, ELEMENT_DOFS, ELEMENT_DOFS>;
type Row24 = SMatrix<f64, 1, ELEMENT_DOFS>;
type M3x24 = SMatrix<f64, 3, ELEMENT_DOFS>;
type M2x24 = SMatrix<f64, 2, ELEMENT_DOFS>;

/// Corner `(ξ, η)` of each node on the unit square (counter-clockwise).
const CORNERS: [(f64, f64); 4] = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
/// Coefficients of the median vector `g1 = Σ C1_i x_i` and the height vector `g2 = Σ C2_i x_i`.
const C1: [f64; 4] = [-0.5, 0.5, 0.5, -0.5];
const C2: [f64; 4] = [-0.5, -0.5, 0.5, 0.5];

/// Bending shape functions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bending {
    /// V1: products of beam Hermite polynomials (Eqs. 26–27). Holds rigid rotations exactly
    /// only on rectangles (on trapezoids the rigid-mode projector removes the spurious energy).
    V1,
    /// V2: the 12-DOF rectangle (Adini–Clough–Melosh) functions (Eq. 28), the default.
    V2,
}

/// Material and thickness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShellMaterial {
    /// Young's modulus [Pa].
    pub e: f64,
    /// Poisson's ratio [1].
    pub nu: f64,
    /// Density [kg/m3].
    pub rho: f64,
    /// Thickness [m].
    pub thickness: f64,
}

impl ShellMaterial {
    /// Plate bending stiffness `D = E h³/(12(1 − ν²))` [N m].
    pub fn bending_stiffness(&self) -> f64 {
        self.e * self.thickness.powi(3) / (12.0 * (1.0 - self.nu * self.nu))
    }

    /// Membrane stiffness `E h/(1 − ν²)` [N/m].
    pub fn membrane_stiffness(&self) -> f64 {
        self.e * self.thickness / (1.0 - self.nu * self.nu)
    }

    /// Plane-stress matrix `[[1, ν, 0], [ν, 1, 0], [0, 0, (1 − ν)/2]]` times `s`.
    fn plane_stress(&self, s: f64) -> Matrix3<f64> {
        let nu = self.nu;
        Matrix3::new(1.0, nu, 0.0, nu, 1.0, 0.0, 0.0, 0.0, 0.5 * (1.0 - nu)) * s
    }
}

/// Element options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShellOptions {
    /// Bending variant.
    pub bending: Bending,
    /// Drilling stiffness `k_d` as a ratio of the membrane shear stiffness `G h` [1].
    pub drilling: f64,
    /// Include the geometric (initial-stress) stiffness of the local von Kármán strains.
    pub geometric_stiffness: bool,
    /// Include the isotropic membrane energy (`E h/(1 − ν²)`). Off for a wall whose membrane is
    /// another element on the same nodes (the air spring's cord–rubber wall,
    /// [`super::cord_rubber_quad`]): the element then carries bending, drilling and inertia.
    pub membrane: bool,
}

impl Default for ShellOptions {
    fn default() -> Self {
        Self {
            bending: Bending::V2,
            drilling: 1e-3,
            geometric_stiffness: true,
            membrane: true,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Shape functions and kinematics
// ---------------------------------------------------------------------------------------------

/// Value and derivatives of a function of `(ξ, η)`: `[f, f_ξ, f_η, f_ξξ, f_ξη, f_ηη]`.
type Jet = [f64; 6];

/// `A(t) = 3t² − 2t³` and derivatives.
fn cubic_a(t: f64) -> [f64; 3] {
    [
        3.0 * t * t - 2.0 * t * t * t,
        6.0 * t - 6.0 * t * t,
        6.0 - 12.0 * t,
    ]
}

/// `B(t) = t(1 − t)²` (Hermite θ) and derivatives.
fn cubic_b(t: f64) -> [f64; 3] {
    [
        t - 2.0 * t * t + t * t * t,
        1.0 - 4.0 * t + 3.0 * t * t,
        -4.0 + 6.0 * t,
    ]
}

/// Hermite `ψ(t) = 1 − 3t² + 2t³` and derivatives.
fn hermite_psi(t: f64) -> [f64; 3] {
    let a = cubic_a(t);
    [1.0 - a[0], -a[1], -a[2]]
}

/// Product `f(ξ) g(η)` of two 1D functions with their derivatives.
fn product(f: [f64; 3], g: [f64; 3]) -> Jet {
    [
        f[0] * g[0],
        f[1] * g[0],
        f[0] * g[1],
        f[2] * g[0],
        f[1] * g[1],
        f[0] * g[2],
    ]
}

/// The three bending functions of node 1 (at `(0, 0)`) in `(ξ, η)`: deflection, rotation
/// about x (slope along η) and about y (slope along −ξ), before the nodal correction. V2 is
/// Eq. 28, V1 Eqs. 26–27 (without the side lengths, which the correction supplies).
fn node1_bending(kind: Bending, x: f64, y: f64) -> [Jet; 3] {
    match kind {
        Bending::V2 => {
            let (ax, ay) = (cubic_a(x), cubic_a(y));
            let (bx, by) = (cubic_b(x), cubic_b(y));
            let f = [
                1.0 - x * y - ax[0] * (1.0 - y) - ay[0] * (1.0 - x),
                -y - ax[1] * (1.0 - y) + ay[0],
                -x + ax[0] - ay[1] * (1.0 - x),
                -ax[2] * (1.0 - y),
                -1.0 + ax[1] + ay[1],
                -ay[2] * (1.0 - x),
            ];
            let g = [
                by[0] * (1.0 - x),
                -by[0],
                by[1] * (1.0 - x),
                0.0,
                -by[1],
                by[2] * (1.0 - x),
            ];
            let h = [
                -bx[0] * (1.0 - y),
                -bx[1] * (1.0 - y),
                bx[0],
                -bx[2] * (1.0 - y),
                bx[1],
                0.0,
            ];
            [f, g, h]
        }
        Bending::V1 => {
            let (px, py) = (hermite_psi(x), hermite_psi(y));
            let (bx, by) = (cubic_b(x), cubic_b(y));
            let f = product(px, py);
            let g = product(px, by);
            let h = product(bx, py).map(|v| -v);
            [f, g, h]
        }
    }
}

/// The bending functions of node `i` at `(ξ, η)`: node 1's mirrored (`ξ → 1 − ξ`, `η → 1 − η`).
fn node_bending(kind: Bending, i: usize, xi: f64, eta: f64) -> [Jet; 3] {
    let (xi_i, eta_i) = CORNERS[i];
    let (sx, sy) = (1.0 - 2.0 * xi_i, 1.0 - 2.0 * eta_i);
    let jets = node1_bending(kind, xi_i + sx * xi, eta_i + sy * eta);
    jets.map(|j| [j[0], sx * j[1], sy * j[2], j[3], sx * sy * j[4], j[5]])
}

/// Bilinear functions `N_i` and their derivatives `(N_ξ, N_η)` at `(ξ, η)`.
fn bilinear(xi: f64, eta: f64) -> ([f64; 4], [Vector2<f64>; 4]) {
    (
        [
            (1.0 - xi) * (1.0 - eta),
            xi * (1.0 - eta),
            xi * eta,
            (1.0 - xi) * eta,
        ],
        [
            Vector2::new(-(1.0 - eta), -(1.0 - xi)),
            Vector2::new(1.0 - eta, -xi),
            Vector2::new(eta, xi),
            Vector2::new(-eta, 1.0 - xi),
        ],
    )
}

/// `N_i,ξη` of the bilinear functions.
const BILINEAR_XI_ETA: [f64; 4] = [1.0, -1.0, 1.0, -1.0];

/// The bilinear map of the local corner coordinates `p` at `(ξ, η)`: the Jacobian
/// `J = ∂(x, y)/∂(ξ, η)` and the mixed derivative `(x_ξη, y_ξη)`.
struct MapPoint {
    n: [f64; 4],
    /// `J⁻ᵀ`: physical gradient = `jit * (f_ξ, f_η)`.
    jit: Matrix2<f64>,
    det: f64,
    x_xieta: Vector2<f64>,
}

impl MapPoint {
    fn new(p: &[Vector2<f64>; 4], xi: f64, eta: f64) -> Option<Self> {
        let (n, dn) = bilinear(xi, eta);
        let mut j = Matrix2::zeros();
        let mut x_xieta = Vector2::zeros();
        for i in 0..4 {
            j[(0, 0)] += dn[i].x * p[i].x;
            j[(0, 1)] += dn[i].y * p[i].x;
            j[(1, 0)] += dn[i].x * p[i].y;
            j[(1, 1)] += dn[i].y * p[i].y;
            x_xieta += BILINEAR_XI_ETA[i] * p[i];
        }
        let det = j.determinant();
        let jit = j.try_inverse()?.transpose();
        Some(Self {
            n,
            jit,
            det,
            x_xieta,
        })
    }

    /// Physical gradient of a function with derivatives `(f_ξ, f_η)`.
    fn grad(&self, jet: &Jet) -> Vector2<f64> {
        self.jit * Vector2::new(jet[1], jet[2])
    }

    /// Physical second derivatives `(f_xx, f_yy, f_xy)`:
    /// `H_x = J⁻ᵀ (H_ξ − (∇f · x_ξη) [[0, 1], [1, 0]]) J⁻¹`.
    fn hessian(&self, jet: &Jet) -> Vector3<f64> {
        let g = self.grad(jet);
        let c = g.dot(&self.x_xieta);
        let h = Matrix2::new(jet[3], jet[4] - c, jet[4] - c, jet[5]);
        let hx = self.jit * h * self.jit.transpose();
        Vector3::new(hx[(0, 0)], hx[(1, 1)], hx[(0, 1)])
    }
}

/// The bending interpolation of one element: per node the 2 × 2 correction of the rotation
/// functions (Eqs. 29–31 generalised): `[N_α, N_β] = [N_α^r, N_β^r] C_i`.
#[derive(Clone, Copy, Debug)]
struct BendingBasis {
    kind: Bending,
    corr: [Matrix2<f64>; 4],
}

impl BendingBasis {
    fn new(kind: Bending, p: &[Vector2<f64>; 4]) -> Option<Self> {
        let mut corr = [Matrix2::zeros(); 4];
        for (i, c) in corr.iter_mut().enumerate() {
            let (xi, eta) = CORNERS[i];
            let m = MapPoint::new(p, xi, eta)?;
            let j = node_bending(kind, i, xi, eta);
            let g = Matrix2::from_columns(&[m.grad(&j[1]), m.grad(&j[2])]);
            // Target slopes: ∇N_α = (0, 1) (α = ∂w/∂y), ∇N_β = (−1, 0) (β = −∂w/∂x).
            let target = Matrix2::new(0.0, -1.0, 1.0, 0.0);
            *c = g.try_inverse()? * target;
        }
        Some(Self { kind, corr })
    }

    /// Deflection `w`, its gradient and second derivatives at a map point as rows over the 24
    /// local coordinates (`w_i`, `α_i`, `β_i` at 6i + 2, 3, 4).
    fn rows(&self, m: &MapPoint, xi: f64, eta: f64) -> (Row24, M2x24, M3x24) {
        let mut w = Row24::zeros();
        let mut g = M2x24::zeros();
        let mut h = M3x24::zeros();
        for i in 0..4 {
            let j = node_bending(self.kind, i, xi, eta);
            let c = &self.corr[i];
            let vals = [j[0][0], j[1][0], j[2][0]];
            let grads = [m.grad(&j[0]), m.grad(&j[1]), m.grad(&j[2])];
            let hess = [m.hessian(&j[0]), m.hessian(&j[1]), m.hessian(&j[2])];
            let b = 6 * i;
            w[b + 2] = vals[0];
            g.set_column(b + 2, &grads[0]);
            h.set_column(b + 2, &hess[0]);
            for k in 0..2 {
                let (ca, cb) = (c[(0, k)], c[(1, k)]);
                w[b + 3 + k] = ca * vals[1] + cb * vals[2];
                g.set_column(b + 3 + k, &(ca * grads[1] + cb * grads[2]));
                h.set_column(b + 3 + k, &(ca * hess[1] + cb * hess[2]));
            }
        }
        (w, g, h)
    }
}

/// Membrane strain rows `[u,x; v,y; u,y + v,x]` and the drilling row `γ − ½(v,x − u,y)` at a
/// map point.
fn membrane_rows(m: &MapPoint, xi: f64, eta: f64) -> (M3x24, Row24) {
    let (n, dn) = bilinear(xi, eta);
    let mut b = M3x24::zeros();
    let mut r = Row24::zeros();
    for i in 0..4 {
        let gx = m.jit * dn[i];
        let c = 6 * i;
        b[(0, c)] = gx.x;
        b[(1, c + 1)] = gx.y;
        b[(2, c)] = gx.y;
        b[(2, c + 1)] = gx.x;
        r[c + 5] = n[i];
        r[c] = 0.5 * gx.y;
        r[c + 1] = -0.5 * gx.x;
    }
    (b, r)
}

/// Gauss points on the unit square: `(ξ, η, weight)`.
fn square_rule(n: usize) -> impl Iterator<Item = (f64, f64, f64)> {
    let g = gauss_legendre(n);
    g.iter().flat_map(move |&(a, wa)| {
        g.iter()
            .map(move |&(b, wb)| (0.5 * (a + 1.0), 0.5 * (b + 1.0), 0.25 * wa * wb))
    })
}

/// Frame `[e1 e2 e3]` from two vectors by Gram–Schmidt (`e1 ∥ g1`, `e2` in the plane of both).
fn gram_schmidt(g1: &Vector3<f64>, g2: &Vector3<f64>) -> Option<Matrix3<f64>> {
    let n1 = g1.norm();
    if n1 == 0.0 {
        return None;
    }
    let e1 = g1 / n1;
    let h = g2 - g2.dot(&e1) * e1;
    let nh = h.norm();
    if nh <= 1e-12 * n1 {
        return None;
    }
    let e2 = h / nh;
    Some(Matrix3::from_columns(&[e1, e2, e1.cross(&e2)]))
}

/// A second-order forward-mode dual number in the six components of `(g1, g2)`: value,
/// gradient and Hessian.
#[derive(Clone, Copy, Debug)]
struct Dual2 {
    v: f64,
    g: [f64; 6],
    h: [[f64; 6]; 6],
}

impl Dual2 {
    fn var(v: f64, k: usize) -> Self {
        let mut g = [0.0; 6];
        g[k] = 1.0;
        Self {
            v,
            g,
            h: [[0.0; 6]; 6],
        }
    }
    fn add(&self, o: &Self) -> Self {
        let mut r = *self;
        r.v += o.v;
        for a in 0..6 {
            r.g[a] += o.g[a];
            for b in 0..6 {
                r.h[a][b] += o.h[a][b];
            }
        }
        r
    }
    fn sub(&self, o: &Self) -> Self {
        self.add(&o.scale(-1.0))
    }
    fn scale(&self, s: f64) -> Self {
        let mut r = *self;
        r.v *= s;
        for a in 0..6 {
            r.g[a] *= s;
            for b in 0..6 {
                r.h[a][b] *= s;
            }
        }
        r
    }
    fn mul(&self, o: &Self) -> Self {
        let mut r = Self {
            v: self.v * o.v,
            g: [0.0; 6],
            h: [[0.0; 6]; 6],
        };
        for a in 0..6 {
            r.g[a] = self.v * o.g[a] + o.v * self.g[a];
            for b in 0..6 {
                r.h[a][b] = self.v * o.h[a][b]
                    + o.v * self.h[a][b]
                    + self.g[a] * o.g[b]
                    + o.g[a] * self.g[b];
            }
        }
        r
    }
    /// `f(self)` for a scalar function with value `f0` and derivatives `f1`, `f2`.
    fn chain(&self, f0: f64, f1: f64, f2: f64) -> Self {
        let mut r = Self {
            v: f0,
            g: [0.0; 6],
            h: [[0.0; 6]; 6],
        };
        for a in 0..6 {
            r.g[a] = f1 * self.g[a];
            for b in 0..6 {
                r.h[a][b] = f1 * self.h[a][b] + f2 * self.g[a] * self.g[b];
            }
        }
        r
    }
    /// `1/√self`.
    fn rsqrt(&self) -> Self {
        let s = self.v.sqrt();
        let f0 = 1.0 / s;
        self.chain(f0, -0.5 * f0 / self.v, 0.75 * f0 / (self.v * self.v))
    }
}

type D3 = [Dual2; 3];

fn dot3(a: &D3, b: &D3) -> Dual2 {
    a[0].mul(&b[0]).add(&a[1].mul(&b[1])).add(&a[2].mul(&b[2]))
}

fn cross3(a: &D3, b: &D3) -> D3 {
    [
        a[1].mul(&b[2]).sub(&a[2].mul(&b[1])),
        a[2].mul(&b[0]).sub(&a[0].mul(&b[2])),
        a[0].mul(&b[1]).sub(&a[1].mul(&b[0])),
    ]
}

/// The frame of [`gram_schmidt`] with its first and second derivatives in `(g1, g2)`:
/// `E[k][l]` is the entry `(k, l)` (row, column).
fn frame_jet(g1: &Vector3<f64>, g2: &Vector3<f64>) -> [[Dual2; 3]; 3] {
    let a: D3 = std::array::from_fn(|k| Dual2::var(g1[k], k));
    let b: D3 = std::array::from_fn(|k| Dual2::var(g2[k], 3 + k));
    let r1 = dot3(&a, &a).rsqrt();
    let e1: D3 = std::array::from_fn(|k| a[k].mul(&r1));
    let d = dot3(&b, &e1);
    let h: D3 = std::array::from_fn(|k| b[k].sub(&d.mul(&e1[k])));
    let rh = dot3(&h, &h).rsqrt();
    let e2: D3 = std::array::from_fn(|k| h[k].mul(&rh));
    let e3 = cross3(&e1, &e2);
    std::array::from_fn(|k| [e1[k], e2[k], e3[k]])
}

/// The current element frame `E`, its derivatives `∂E/∂x_jk` (node j, component k), and, for
/// the tangent, its second derivatives (the frame jet, contracted on demand).
struct CurrentFrame {
    e: Matrix3<f64>,
    /// `∂E/∂g_a`, a = 0..6.
    de_dg: [Matrix3<f64>; 6],
    /// Spin `w_a` of the frame per unit `g_a` (`∂E/∂g_a = w̃_a E`).
    spin: [Vector3<f64>; 6],
    jet: Option<[[Dual2; 3]; 3]>,
    c: Vector3<f64>,
}

impl CurrentFrame {
    /// The frame and its first derivatives in closed form: the spin `ω` of the frame
    /// (`δE = ω̃ E`) is `ω = e1 (e3·δg2 − (g2·e1)/|g1| e3·δg1)/|h| − e2 (e3·δg1)/|g1| +
    /// e3 (e2·δg1)/|g1|` with `h = g2 − (g2·e1) e1`; with `second` also the second derivatives.
    fn new(x: &[Vector3<f64>; 4], second: bool) -> Self {
        let mut g1 = Vector3::zeros();
        let mut g2 = Vector3::zeros();
        let mut c = Vector3::zeros();
        for i in 0..4 {
            g1 += C1[i] * x[i];
            g2 += C2[i] * x[i];
            c += 0.25 * x[i];
        }
        if second {
            let jet = frame_jet(&g1, &g2);
            let e = Matrix3::from_fn(|k, l| jet[k][l].v);
            let de_dg: [Matrix3<f64>; 6] =
                std::array::from_fn(|a| Matrix3::from_fn(|k, l| jet[k][l].g[a]));
            let spin = std::array::from_fn(|a| axial(&(de_dg[a] * e.transpose())));
            return Self {
                e,
                de_dg,
                spin,
                jet: Some(jet),
                c,
            };
        }
        let n1 = g1.norm();
        let e1 = g1 / n1;
        let d = g2.dot(&e1);
        let h = g2 - d * e1;
        let nh = h.norm();
        let e2 = h / nh;
        let e3 = e1.cross(&e2);
        let e = Matrix3::from_columns(&[e1, e2, e3]);
        let spin: [Vector3<f64>; 6] = std::array::from_fn(|a| {
            let (k, second_vector) = (a % 3, a >= 3);
            if second_vector {
                e1 * (e3[k] / nh)
            } else {
                e1 * (-d / n1 * e3[k] / nh) - e2 * (e3[k] / n1) + e3 * (e2[k] / n1)
            }
        });
        let de_dg = std::array::from_fn(|a| skew(&spin[a]) * e);
        Self {
            e,
            de_dg,
            spin,
            jet: None,
            c,
        }
    }

    /// `∂E/∂x_jk`.
    fn de_dx(&self, j: usize, k: usize) -> Matrix3<f64> {
        self.de_dg[k] * C1[j] + self.de_dg[3 + k] * C2[j]
    }

    /// `⟨∂²E/∂g_a ∂g_b, B⟩` (6 × 6); needs the frame built with second derivatives.
    fn contracted_hessian(&self, b: &Matrix3<f64>) -> [[f64; 6]; 6] {
        let mut out = [[0.0; 6]; 6];
        let Some(jet) = &self.jet else {
            return out;
        };
        for k in 0..3 {
            for l in 0..3 {
                let w = b[(k, l)];
                if w == 0.0 {
                    continue;
                }
                let h = &jet[k][l].h;
                for a in 0..6 {
                    for c in 0..6 {
                        out[a][c] += w * h[a][c];
                    }
                }
            }
        }
        out
    }
}

/// For `s² = |v|²`: `g = asin(s)/s`, `h = g'(s)/s` and `k = h'(s)/s`. Below `s = 0.2` from
/// the series `asin s = Σ a_n s^(2n+1)/(2n + 1)`, `s/√(1 − s²) = Σ a_n s^(2n+1)`,
/// `a_n = (2n)!/(4ⁿ n!²)` (16 terms, exact to round-off), above from the closed forms, which
/// lose digits to cancellation at small `s`.
fn arcsine_ratio(s2: f64) -> (f64, f64, f64) {
    if s2 < 0.04 {
        let (mut g, mut h, mut k) = (1.0, 0.0, 0.0);
        let mut a = 1.0;
        let mut p = 1.0; // s^(2n-2)
        for n in 1..16 {
            let nf = n as f64;
            a *= (2.0 * nf - 1.0) / (2.0 * nf);
            let c = a * 2.0 * nf / (2.0 * nf + 1.0);
            g += a / (2.0 * nf + 1.0) * p * s2;
            h += c * p;
            if n >= 2 {
                k += c * (2.0 * nf - 2.0) * p / s2.max(f64::MIN_POSITIVE);
            }
            p *= s2;
        }
        if s2 == 0.0 {
            k = 0.6;
        }
        return (g, h, k);
    }
    let s = s2.sqrt();
    let c2 = 1.0 - s2;
    let c = c2.sqrt();
    let asin = s.asin();
    let g = asin / s;
    let n = s / c - asin;
    let h = n / (s2 * s);
    let k = 1.0 / (c2 * c * s2) - 3.0 * n / (s2 * s2 * s);
    (g, h, k)
}

/// Node positions and rotations of an element state.
fn nodes_of(s: &ElementState<ELEMENT_DOFS>) -> ([Vector3<f64>; 4], [Matrix3<f64>; 4]) {
    let x = std::array::from_fn(|i| s.q.fixed_rows::<3>(6 * i).into_owned());
    let r = std::array::from_fn(|i| s.frames.get(i).map_or(Matrix3::identity(), |f| f.rot));
    (x, r)
}

/// One element: reference geometry, the local linear stiffness in SCF, the rigid-mode
/// projector and the constant mass matrix.
#[derive(Clone, Debug)]
pub struct TrapezoidShell {
    mat: ShellMaterial,
    opt: ShellOptions,
    /// Reference frame `E0` (columns: median direction, height direction, normal).
    e0: Matrix3<f64>,
    /// Reference node positions in SCF, `ρ_i = E0ᵀ(X_i − c0)` [m].
    rho: [Vector3<f64>; 4],
    area: f64,
    /// Local stiffness `Pᵀ K P = M H Ω Hᵀ M` (linear local energy) or, with the geometric
    /// stiffness, the bending and drilling part only.
    k_local: Mat24,
    /// Mass-orthogonal projector on the elastic modes, `P = I − R (Rᵀ M R)⁻¹ Rᵀ M`.
    proj: Mat24,
    /// Its factors: the rigid modes `R` (24 × 6) and `Y = (Rᵀ M R)⁻¹ Rᵀ M` (6 × 24), `P = I − R Y`.
    rigid: SMatrix<f64, ELEMENT_DOFS, 6>,
    rigid_y: SMatrix<f64, 6, ELEMENT_DOFS>,
    /// Membrane strain rows and gradient rows of `w` at the 2 × 2 Gauss points, with weights
    /// `w det J` (geometric stiffness only).
    membrane: [(M3x24, M2x24, f64); 4],
    /// The local linear stiffness before the projection (for the free–free modes).
    k_linear: Mat24,
    /// Constant mass matrix (isotropic in the nodal translations, nodal rotary inertia).
    mass: Mat24,
    /// Nodal area shares `∫ N_i dA` [m2].
    shares: [f64; 4],
}

impl TrapezoidShell {
    /// An element on four reference nodes, counter-clockwise about the element normal.
    /// Errors for degenerate or non-convex quadrilaterals, for nodes far from a plane (warping
    /// more than 1 % of the element size), and for non-physical material data.
    pub fn new(
        x: [Vector3<f64>; 4],
        mat: &ShellMaterial,
        opt: &ShellOptions,
    ) -> Result<Self, String> {
        if !(mat.e > 0.0 && mat.rho > 0.0 && mat.thickness > 0.0 && mat.nu > -1.0 && mat.nu < 0.5) {
            return Err(format!(
                "shell material E = {}, nu = {}, rho = {}, thickness = {}: E, rho and the thickness must be positive and -1 < nu < 0.5",
                mat.e, mat.nu, mat.rho, mat.thickness
            ));
        }
        if opt.drilling.is_nan() || opt.drilling <= 0.0 {
            return Err(format!(
                "element.drilling_stiffness = {}: must be positive (a small ratio of G h, e.g. 1e-3)",
                opt.drilling
            ));
        }
        let frame = CurrentFrame::new(&x, false);
        let g1: Vector3<f64> = (0..4).map(|i| C1[i] * x[i]).sum();
        let g2: Vector3<f64> = (0..4).map(|i| C2[i] * x[i]).sum();
        let e0 = gram_schmidt(&g1, &g2)
            .ok_or_else(|| format!("degenerate quadrilateral {x:?}: its sides are parallel"))?;
        let rho: [Vector3<f64>; 4] = std::array::from_fn(|i| e0.transpose() * (x[i] - frame.c));
        let size = g1.norm().max(g2.norm());
        let p: [Vector2<f64>; 4] = std::array::from_fn(|i| rho[i].xy());
        for i in 0..4 {
            if rho[i].z.abs() > 1e-2 * size {
                return Err(format!(
                    "quadrilateral {x:?} is warped: node {i} lies {:.3e} m off its mean plane",
                    rho[i].z
                ));
            }
            let (a, b, c) = (p[i], p[(i + 1) % 4], p[(i + 2) % 4]);
            let turn = (b - a).perp(&(c - b));
            if turn <= 1e-10 * size * size {
                return Err(format!(
                    "quadrilateral {x:?} is not convex and counter-clockwise about its normal (corner {})",
                    (i + 1) % 4
                ));
            }
        }
        let basis = BendingBasis::new(opt.bending, &p)
            .ok_or_else(|| format!("degenerate quadrilateral {x:?}"))?;
        let cm = mat.plane_stress(mat.membrane_stiffness());
        let cb = mat.plane_stress(mat.bending_stiffness());
        let g_h = mat.e * mat.thickness / (2.0 * (1.0 + mat.nu));
        let kd = opt.drilling * g_h;
        let mut k_mem = Mat24::zeros();
        let mut k_rest = Mat24::zeros();
        let mut mass = Mat24::zeros();
        let mut membrane = [(M3x24::zeros(), M2x24::zeros(), 0.0); 4];
        let mut shares = [0.0; 4];
        let mut area = 0.0;
        let rho_h = mat.rho * mat.thickness;
        for (gp, (xi, eta, w)) in square_rule(2).enumerate() {
            let m = MapPoint::new(&p, xi, eta).ok_or("degenerate quadrilateral")?;
            let wd = w * m.det;
            let (bm, rd) = membrane_rows(&m, xi, eta);
            k_mem += bm.transpose() * cm * bm * wd;
            k_rest += rd.transpose() * rd * (kd * wd);
            area += wd;
            for i in 0..4 {
                shares[i] += m.n[i] * wd;
                for j in 0..4 {
                    let mij = rho_h * m.n[i] * m.n[j] * wd;
                    for k in 0..3 {
                        mass[(6 * i + k, 6 * j + k)] += mij;
                    }
                }
            }
            let (_, gw, _) = basis.rows(&m, xi, eta);
            membrane[gp] = (bm, gw, wd);
        }
        for (xi, eta, w) in square_rule(3) {
            let m = MapPoint::new(&p, xi, eta).ok_or("degenerate quadrilateral")?;
            let (_, _, h) = basis.rows(&m, xi, eta);
            // curvatures (w,xx, w,yy, 2 w,xy)
            let mut kap = h;
            kap.row_mut(2).scale_mut(2.0);
            k_rest += kap.transpose() * cb * kap * (w * m.det);
        }
        let rot_inertia = mat.rho * mat.thickness.powi(3) / 12.0;
        for i in 0..4 {
            for k in 3..6 {
                mass[(6 * i + k, 6 * i + k)] = rot_inertia * shares[i];
            }
        }
        // Rigid modes in SCF (translations; rotations u_i = e_k × ρ_i, θ_i = e_k).
        let mut r = SMatrix::<f64, ELEMENT_DOFS, 6>::zeros();
        for i in 0..4 {
            for k in 0..3 {
                r[(6 * i + k, k)] = 1.0;
                let ek = Vector3::ith(k, 1.0);
                let u = ek.cross(&rho[i]);
                for c in 0..3 {
                    r[(6 * i + c, 3 + k)] = u[c];
                }
                r[(6 * i + 3 + k, 3 + k)] = 1.0;
            }
        }
        let s = (r.transpose() * mass * r)
            .try_inverse()
            .ok_or("singular rigid-mode mass")?;
        let rigid_y = s * r.transpose() * mass;
        let proj = Mat24::identity() - r * rigid_y;
        if !opt.membrane {
            k_mem.fill(0.0);
        }
        let k_lin = k_mem + k_rest;
        let k_local = if opt.geometric_stiffness {
            k_rest
        } else {
            proj.transpose() * k_lin * proj
        };
        Ok(Self {
            mat: *mat,
            opt: *opt,
            e0,
            rho,
            area,
            k_local,
            proj,
            rigid: r,
            rigid_y,
            membrane,
            k_linear: k_lin,
            mass,
            shares,
        })
    }

    /// Reference area [m2].
    pub fn area(&self) -> f64 {
        self.area
    }

    /// Reference frame `E0` (median direction, height direction, normal).
    pub fn reference_frame(&self) -> &Matrix3<f64> {
        &self.e0
    }

    /// Material and thickness.
    pub fn material(&self) -> &ShellMaterial {
        &self.mat
    }

    /// Options.
    pub fn options(&self) -> &ShellOptions {
        &self.opt
    }

    /// Nodal shares `∫ N_i dA` of the reference area [m2].
    pub fn area_shares(&self) -> [f64; 4] {
        self.shares
    }

    /// The local linear stiffness `K` in SCF (membrane, Kirchhoff bending, drilling; no rigid
    /// modes removed) [N/m, N, N m], for the free–free modal analysis.
    pub fn local_linear_stiffness(&self) -> &Mat24 {
        &self.k_linear
    }

    /// The local mass matrix in SCF (equal to the global one: it is isotropic).
    pub fn local_mass(&self) -> &Mat24 {
        &self.mass
    }

    /// Free–free modes of the element (Eqs. 4–10): the squared circular frequencies `ω²`
    /// [rad²/s²] of `(K − ω² M) h = 0`, ascending (six rigid modes first). Computed on
    /// demand (a 24 × 24 symmetric eigenproblem).
    pub fn free_free_eigenvalues(&self) -> [f64; ELEMENT_DOFS] {
        self.eigenvalues(&self.k_linear)
    }

    /// The same for the stiffness with the rigid modes projected out, `Pᵀ K P` (the paper's
    /// `H Ω Hᵀ` in mass-normalised modes), which the element uses: exactly six zeros.
    pub fn projected_eigenvalues(&self) -> [f64; ELEMENT_DOFS] {
        self.eigenvalues(&(self.proj.transpose() * self.k_linear * self.proj))
    }

    fn eigenvalues(&self, k: &Mat24) -> [f64; ELEMENT_DOFS] {
        let l = self.mass.cholesky().expect("mass is positive definite");
        let li = l.l().try_inverse().expect("triangular");
        let a = li * *k * li.transpose();
        let a = 0.5 * (a + a.transpose());
        let mut ev: Vec<f64> = a.symmetric_eigenvalues().iter().copied().collect();
        ev.sort_by(f64::total_cmp);
        std::array::from_fn(|i| ev[i])
    }

    /// The element's free–free elastic modes (Eqs. 4–10): `Ω = diag(ω²)` [rad²/s²] and the
    /// mass-normalised mode shapes `H` (24 × 18, `Hᵀ M H = I`, `Hᵀ (Pᵀ K P) H = Ω`), the six
    /// rigid modes removed. Computed on demand.
    pub fn free_free_modes(&self) -> (SVector<f64, 18>, SMatrix<f64, ELEMENT_DOFS, 18>) {
        let kp = self.proj.transpose() * self.k_linear * self.proj;
        let l = self.mass.cholesky().expect("mass is positive definite");
        let li = l.l().try_inverse().expect("triangular");
        let a = li * kp * li.transpose();
        let eig = (0.5 * (a + a.transpose())).symmetric_eigen();
        let mut order: Vec<usize> = (0..ELEMENT_DOFS).collect();
        order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
        let mut omega = SVector::<f64, 18>::zeros();
        let mut h = SMatrix::<f64, ELEMENT_DOFS, 18>::zeros();
        for (c, &i) in order[6..].iter().enumerate() {
            omega[c] = eig.eigenvalues[i];
            h.set_column(c, &(li.transpose() * eig.eigenvectors.column(i)));
        }
        (omega, h)
    }

    /// The paper's elastic coordinates `Δq = Hᵀ M ΔX` (Eq. 5–6) at a state, for the modes `h`
    /// of [`Self::free_free_modes`]; with the linear local energy the strain energy is
    /// `½ Δqᵀ Ω Δq`.
    pub fn elastic_coordinates(
        &self,
        s: &ElementState<ELEMENT_DOFS>,
        h: &SMatrix<f64, ELEMENT_DOFS, 18>,
    ) -> SVector<f64, 18> {
        let (x, r) = nodes_of(s);
        let f = CurrentFrame::new(&x, false);
        let mut d = self.local_deflection(&f, &x, &r);
        for i in 0..4 {
            let v = d.fixed_rows::<3>(6 * i + 3).into_owned();
            let (g, _, _) = arcsine_ratio(v.norm_squared());
            d.fixed_rows_mut::<3>(6 * i + 3).copy_from(&(v * g));
        }
        h.transpose() * (self.mass * d)
    }

    /// Deflections in SCF `ΔX` (24): `[Eᵀ(x_i − c) − ρ_i ; axial(Eᵀ R_i E0)]`.
    fn local_deflection(
        &self,
        f: &CurrentFrame,
        x: &[Vector3<f64>; 4],
        r: &[Matrix3<f64>; 4],
    ) -> Vec24 {
        let mut d = Vec24::zeros();
        let et = f.e.transpose();
        for i in 0..4 {
            let u = et * (x[i] - f.c) - self.rho[i];
            let th = axial(&(et * r[i] * self.e0));
            d.fixed_rows_mut::<3>(6 * i).copy_from(&u);
            d.fixed_rows_mut::<3>(6 * i + 3).copy_from(&th);
        }
        d
    }

    /// The paper's elastic coordinates in mass-normalised free–free modes are `Δq = Hᵀ M ΔX`;
    /// this returns the elastic part `P ΔX = H Δq` of the deflections in SCF at a state.
    pub fn elastic_deflection(&self, s: &ElementState<ELEMENT_DOFS>) -> Vec24 {
        let (x, r) = nodes_of(s);
        let f = CurrentFrame::new(&x, false);
        self.proj * self.local_deflection(&f, &x, &r)
    }

    // -----------------------------------------------------------------------------------------
    // Mass: constant (see the module notes); `self.mass`.
    // -----------------------------------------------------------------------------------------

    // -----------------------------------------------------------------------------------------
    // Internal forces
    // -----------------------------------------------------------------------------------------

    /// Local energy as a function of the deflections with the nodal rotations measured by
    /// `v = axial(Q)` (= `sin|θ| n`, linear in the frames): maps each `v` to the rotation
    /// vector `θ = ψ(v) = v asin|v|/|v|` (exact for local rotations below 90°; beyond, NaN, and
    /// the step fails) and chains gradient and Hessian.
    fn local_energy(&self, dv: &Vec24, grad: &mut Vec24, hess: Option<&mut Mat24>) -> f64 {
        let mut dx = *dv;
        let mut jacs = [Matrix3::identity(); 4];
        let mut hs = [(0.0, 0.0, 0.0); 4];
        for i in 0..4 {
            let v = dv.fixed_rows::<3>(6 * i + 3).into_owned();
            let (g, h, k) = arcsine_ratio(v.norm_squared());
            dx.fixed_rows_mut::<3>(6 * i + 3).copy_from(&(v * g));
            jacs[i] = Matrix3::identity() * g + v * v.transpose() * h;
            hs[i] = (g, h, k);
        }
        let mut gl = Vec24::zeros();
        let want = hess.is_some();
        let mut hl = Mat24::zeros();
        let e = self.local_energy_log(&dx, &mut gl, want.then_some(&mut hl));
        *grad = gl;
        for i in 0..4 {
            let f = gl.fixed_rows::<3>(6 * i + 3).into_owned();
            grad.fixed_rows_mut::<3>(6 * i + 3)
                .copy_from(&(jacs[i].transpose() * f));
        }
        if let Some(out) = hess {
            // Jψᵀ H Jψ with Jψ block diagonal (identity on positions)
            for i in 0..4 {
                let r = 6 * i + 3;
                let cols = hl.fixed_columns::<3>(r) * jacs[i];
                hl.fixed_columns_mut::<3>(r).copy_from(&cols);
            }
            for i in 0..4 {
                let r = 6 * i + 3;
                let rows = jacs[i].transpose() * hl.fixed_rows::<3>(r);
                hl.fixed_rows_mut::<3>(r).copy_from(&rows);
            }
            // + ∇²(f·ψ)(v) = h (f vᵀ + v fᵀ) + (f·v)(h I + k v vᵀ)
            for i in 0..4 {
                let r = 6 * i + 3;
                let v = dv.fixed_rows::<3>(r).into_owned();
                let f = gl.fixed_rows::<3>(r).into_owned();
                let (_, h, k) = hs[i];
                let fv = f.dot(&v);
                let add = (f * v.transpose() + v * f.transpose()) * h
                    + (Matrix3::identity() * h + v * v.transpose() * k) * fv;
                let mut blk = hl.fixed_view_mut::<3, 3>(r, r);
                blk += add;
            }
            *out = hl;
        }
        e
    }

    /// Local energy `e(d)` of the projected deflection `d = P ΔX` (nodal rotations as rotation
    /// vectors), its gradient and (if asked) Hessian with respect to `ΔX`.
    fn local_energy_log(&self, dx: &Vec24, grad: &mut Vec24, hess: Option<&mut Mat24>) -> f64 {
        if !self.opt.geometric_stiffness {
            *grad = self.k_local * dx;
            if let Some(h) = hess {
                *h = self.k_local;
            }
            return 0.5 * dx.dot(grad);
        }
        let d = dx - self.rigid * (self.rigid_y * dx);
        let mut g = self.k_local * d;
        let mut e = 0.5 * d.dot(&g);
        let cm = self.mat.plane_stress(self.mat.membrane_stiffness());
        let mut h = hess.as_ref().map(|_| self.k_local);
        let membrane: &[_] = if self.opt.membrane {
            &self.membrane
        } else {
            &[]
        };
        for (bm, gw, wd) in membrane {
            let th = gw * d;
            let eps = bm * d + Vector3::new(0.5 * th.x * th.x, 0.5 * th.y * th.y, th.x * th.y);
            let n = cm * eps;
            e += 0.5 * eps.dot(&n) * wd;
            let a = SMatrix::<f64, 3, 2>::new(th.x, 0.0, 0.0, th.y, th.y, th.x);
            let bnl = bm + a * gw;
            g += bnl.transpose() * n * *wd;
            if let Some(h) = h.as_mut() {
                let nm = Matrix2::new(n.x, n.z, n.z, n.y);
                let cb = cm * bnl * *wd;
                let ng = nm * gw * *wd;
                h.gemm_tr(1.0, &bnl, &cb, 1.0);
                h.gemm_tr(1.0, gw, &ng, 1.0);
            }
        }
        // Pᵀ g and Pᵀ H P with P = I − R Y (rank-6 corrections instead of 24³ products)
        *grad = g - self.rigid_y.transpose() * (self.rigid.transpose() * g);
        if let (Some(out), Some(h)) = (hess, h) {
            let hr = h * self.rigid;
            let hry = hr * self.rigid_y;
            let core = self.rigid.transpose() * hr;
            *out = h - hry - hry.transpose() + self.rigid_y.transpose() * (core * self.rigid_y);
        }
        e
    }

    /// Strain energy [J] at nodes `x` and node rotations `r`.
    pub fn strain_energy(&self, x: &[Vector3<f64>; 4], r: &[Matrix3<f64>; 4]) -> f64 {
        let f = CurrentFrame::new(x, false);
        let d = self.local_deflection(&f, x, r);
        let mut g = Vec24::zeros();
        self.local_energy(&d, &mut g, None)
    }

    /// Internal force (positions: global components; rotations: body moments) and, if asked,
    /// the tangent with respect to `[δx_i, δW_i]` (body spins); returns the strain energy [J].
    pub fn internal(
        &self,
        x: &[Vector3<f64>; 4],
        r: &[Matrix3<f64>; 4],
        f: &mut Vec24,
        k: Option<&mut Mat24>,
    ) -> f64 {
        let fr = CurrentFrame::new(x, k.is_some());
        let et = fr.e.transpose();
        let d = self.local_deflection(&fr, x, r);
        let a: [Matrix3<f64>; 4] = std::array::from_fn(|i| r[i] * self.e0);
        // J = ∂ΔX/∂[δx, δW] = Λ + Z Ω: Λ block diagonal (`Eᵀ` for u_i ← x_i, `T_i` for
        // θ_i ← W_i), the frame spin `ω = Ω δx` (3 × 24) acting through `Z` (24 × 3). The
        // centroid's part of J is a local rigid translation, which the projected local force
        // and stiffness do not see (`P R = 0`), so it is left out.
        let de: [[Matrix3<f64>; 3]; 4] =
            std::array::from_fn(|j| std::array::from_fn(|k| fr.de_dx(j, k)));
        let mut lam = [Matrix3::zeros(); 8];
        let mut z = SMatrix::<f64, ELEMENT_DOFS, 3>::zeros();
        let mut om = SMatrix::<f64, 3, ELEMENT_DOFS>::zeros();
        for i in 0..4 {
            lam[2 * i] = et;
            lam[2 * i + 1] = Matrix3::from_fn(|c, kk| {
                axial(&(et * r[i] * skew(&Vector3::ith(kk, 1.0)) * self.e0))[c]
            });
            z.fixed_view_mut::<3, 3>(6 * i, 0)
                .copy_from(&(et * skew(&(x[i] - fr.c))));
            for m in 0..3 {
                let col = -axial(&(et * skew(&Vector3::ith(m, 1.0)) * a[i]));
                z.fixed_view_mut::<3, 1>(6 * i + 3, m).copy_from(&col);
            }
            for kk in 0..3 {
                let w = fr.spin[kk] * C1[i] + fr.spin[3 + kk] * C2[i];
                om.set_column(6 * i + kk, &w);
            }
        }
        let mut fl = Vec24::zeros();
        let mut kl = Mat24::zeros();
        let want_k = k.is_some();
        let u = self.local_energy(&d, &mut fl, want_k.then_some(&mut kl));
        for b in 0..8 {
            f.fixed_rows_mut::<3>(3 * b)
                .copy_from(&(lam[b].transpose() * fl.fixed_rows::<3>(3 * b)));
        }
        f.gemv_tr(1.0, &om, &(z.transpose() * fl), 1.0);
        let Some(k) = k else {
            return u;
        };
        // Jᵀ K J = Λᵀ K Λ + G Ω + Ωᵀ Gᵀ + Ωᵀ (Zᵀ K Z) Ω with G = Λᵀ K Z.
        let mut kla = Mat24::zeros();
        for b in 0..8 {
            let blk = kl.fixed_columns::<3>(3 * b) * lam[b];
            kla.fixed_columns_mut::<3>(3 * b).copy_from(&blk);
        }
        let kz = kl * z;
        let mut g = SMatrix::<f64, ELEMENT_DOFS, 3>::zeros();
        for a in 0..8 {
            let lt = lam[a].transpose();
            g.fixed_rows_mut::<3>(3 * a)
                .copy_from(&(lt * kz.fixed_rows::<3>(3 * a)));
            for b in 0..8 {
                let blk = lt * kla.fixed_view::<3, 3>(3 * a, 3 * b);
                k.fixed_view_mut::<3, 3>(3 * a, 3 * b).copy_from(&blk);
            }
        }
        let c3 = z.transpose() * kz;
        let go = g * om;
        *k += go + go.transpose() + om.transpose() * (c3 * om);
        // Geometric part: the Hessian of s = f̄ᵀ ΔX(y) = ⟨E, B⟩ at fixed f̄,
        // B = Σ (x_i − c) f̄u_iᵀ − ½ Σ R_i E0 f̃θ_i.
        let fu: [Vector3<f64>; 4] = std::array::from_fn(|i| fl.fixed_rows::<3>(6 * i).into_owned());
        let ft: [Matrix3<f64>; 4] =
            std::array::from_fn(|i| skew(&fl.fixed_rows::<3>(6 * i + 3).into_owned()));
        let mean_fu = 0.25 * (fu[0] + fu[1] + fu[2] + fu[3]);
        let phi: [Vector3<f64>; 4] = std::array::from_fn(|i| fu[i] - mean_fu);
        let mut b = Matrix3::zeros();
        for i in 0..4 {
            b += (x[i] - fr.c) * fu[i].transpose() - 0.5 * a[i] * ft[i];
        }
        let hb = fr.contracted_hessian(&b);
        // ∂B/∂W_lb = −½ R_l ẽ_b E0 f̃θ_l
        let db_dw: [[Matrix3<f64>; 3]; 4] = std::array::from_fn(|l| {
            std::array::from_fn(|bb| -0.5 * r[l] * skew(&Vector3::ith(bb, 1.0)) * self.e0 * ft[l])
        });
        for j in 0..4 {
            for aa in 0..3 {
                let row = 6 * j + aa;
                for l in 0..4 {
                    for bb in 0..3 {
                        let col = 6 * l + bb;
                        let mut v = 0.0;
                        for (p, cp) in [C1[j], C2[j]].iter().enumerate() {
                            for (q, cq) in [C1[l], C2[l]].iter().enumerate() {
                                v += cp * cq * hb[3 * p + aa][3 * q + bb];
                            }
                        }
                        v += de[j][aa].row(bb).transpose().dot(&phi[l]);
                        v += de[l][bb].row(aa).transpose().dot(&phi[j]);
                        k[(row, col)] += v;
                        // x–W blocks
                        let m = de[j][aa].component_mul(&db_dw[l][bb]).sum();
                        k[(row, 6 * l + 3 + bb)] += m;
                        k[(6 * l + 3 + bb, row)] += m;
                    }
                }
            }
        }
        // W–W blocks (ordered second derivative of R exp(W̃_m) exp(W̃_k)).
        for l in 0..4 {
            for kk in 0..3 {
                for m in 0..3 {
                    let sk = skew(&Vector3::ith(kk, 1.0));
                    let sm = skew(&Vector3::ith(m, 1.0));
                    let v = (fr
                        .e
                        .component_mul(&(-0.5 * r[l] * sm * sk * self.e0 * ft[l])))
                    .sum();
                    k[(6 * l + 3 + kk, 6 * l + 3 + m)] += v;
                }
            }
        }
        u
    }

    /// Chains the rotation columns of a tangent with respect to body spins with the tangents
    /// `T(θ)` of the incremental rotation vectors.
    fn chain_rotations(s: &ElementState<ELEMENT_DOFS>, k: &mut Mat24) {
        for (i, fr) in s.frames.iter().enumerate().take(4) {
            let mut cols = k.fixed_columns_mut::<3>(6 * i + 3);
            let chained = cols.clone_owned() * fr.tangent;
            cols.copy_from(&chained);
        }
    }
}

impl Element<ELEMENT_DOFS> for TrapezoidShell {
    fn layout(&self) -> Layout {
        Layout {
            dim: 3,
            slots: &[
                Slot::Position,
                Slot::Rotation,
                Slot::Position,
                Slot::Rotation,
                Slot::Position,
                Slot::Rotation,
                Slot::Position,
                Slot::Rotation,
            ],
        }
    }

    fn constant_mass_matrix(&self) -> Option<&Mat24> {
        Some(&self.mass)
    }

    fn mass_into(&self, _s: &ElementState<ELEMENT_DOFS>, m: &mut Mat24) {
        *m = self.mass;
    }

    fn gravity_into(&self, _s: &ElementState<ELEMENT_DOFS>, g: &Vector3<f64>, f: &mut Vec24) {
        f.fill(0.0);
        let rho_h = self.mat.rho * self.mat.thickness;
        for i in 0..4 {
            f.fixed_rows_mut::<3>(6 * i)
                .copy_from(&(g * (rho_h * self.shares[i])));
        }
    }

    fn strain_energy_at(&self, s: &ElementState<ELEMENT_DOFS>) -> f64 {
        let (x, r) = nodes_of(s);
        self.strain_energy(&x, &r)
    }

    fn force_into(&self, s: &ElementState<ELEMENT_DOFS>, f: &mut Vec24) -> f64 {
        let (x, r) = nodes_of(s);
        self.internal(&x, &r, f, None)
    }

    fn tangent_into(
        &self,
        s: &ElementState<ELEMENT_DOFS>,
        f: &mut Vec24,
        k: &mut Mat24,
        c: Option<&mut Mat24>,
    ) -> f64 {
        let (x, r) = nodes_of(s);
        let u = self.internal(&x, &r, f, Some(k));
        Self::chain_rotations(s, k);
        if let Some(c) = c {
            c.fill(0.0);
        }
        u
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::rotation::exp_so3;

    /// `ψ(axial(exp θ̃)) = θ`, and the series and closed forms of `g`, `h`, `k` meet at the
    /// switch and are each other's derivatives (finite differences).
    #[test]
    fn arcsine_map_is_the_logarithm() {
        for th in [1e-6, 1e-3, 0.05, 0.3, 1.0, 1.4] {
            let t = Vector3::new(0.3, -0.5, 0.8).normalize() * th;
            let v = axial(&exp_so3(&t));
            let (g, _, _) = arcsine_ratio(v.norm_squared());
            assert!((v * g - t).norm() < 1e-14 * th.max(1e-3), "{th}");
        }
        let below = arcsine_ratio(0.04 * (1.0 - 1e-12));
        let above = arcsine_ratio(0.04 * (1.0 + 1e-12));
        for (a, b) in [(below.0, above.0), (below.1, above.1), (below.2, above.2)] {
            assert!((a - b).abs() < 1e-9 * a, "{a} {b}");
        }
        for s in [0.2, 0.6, 0.9] {
            let e = 1e-6;
            let (_, h, k) = arcsine_ratio(s * s);
            let gp = (arcsine_ratio((s + e) * (s + e)).0 - arcsine_ratio((s - e) * (s - e)).0)
                / (2.0 * e);
            let hp = (arcsine_ratio((s + e) * (s + e)).1 - arcsine_ratio((s - e) * (s - e)).1)
                / (2.0 * e);
            assert!((gp / s - h).abs() < 1e-7 * h, "h at {s}");
            assert!((hp / s - k).abs() < 1e-6 * k, "k at {s}");
        }
    }
}
