//! Seed-000 element: linear shear-deformable 2D ANCF beam with selective integration.
//!
//! Kerkkänen, Sopanen, Mikkola 2003 ("A linear beam finite element based on the absolute nodal
//! coordinate formulation"), decoded in `shared/reference/seed000-ancf-shear-beam.md`.
//! Nodal coordinates (Eq. 5): `e_I = [r_I ; ∂r/∂y|_I]` (4 per node, 8 per element), ordered
//! `[r_I, r_I,y, r_J, r_J,y]`, each a 2-vector.
//!
//! The file follows the fixed order of every element: shape functions, mass, internal forces,
//! tangent; then the element trait ([`Shear2dElement`]).

use super::element::{Element, ElementState, Layout, Slot};
use super::material::PlaneElasticity;
use super::quadrature::gauss_legendre;
use nalgebra::{Matrix2, Matrix3, SMatrix, SVector, Vector2, Vector3};

/// Coordinates per node (position and transverse gradient, both 2-vectors).
pub const NODE_COORDS: usize = 4;
/// Coordinates per element.
pub const ELEMENT_COORDS: usize = 8;
/// Element coordinate vector `e` (Eq. 5).
pub type ElemVec = SVector<f64, ELEMENT_COORDS>;
/// Element matrix (mass, tangent).
pub type ElemMat = SMatrix<f64, ELEMENT_COORDS, ELEMENT_COORDS>;

/// Integration rule for the shear-strain energy term (seed 000, sections 5 and 7).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShearRule {
    /// One point along the axis, one through the height: the paper's original rule
    /// (Tables 1–4); has a spurious zero-energy mode for deep beams.
    Original1x1,
    /// One point along the axis, two through the height: the fix of section 7 (Table 5).
    Fixed1x2,
}

/// Cross-section of a rectangular beam [m].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Section {
    /// Out-of-plane width `b` [m] (enters as a factor only).
    pub width: f64,
    /// Height `h` [m], the extent of the local `y` coordinate.
    pub height: f64,
}

/// Precomputed data of one integration point: weight times volume scale, and the material
/// gradients `d_a = R0ᵀ J0⁻ᵀ ∇S_a` of the four shape functions, so that `D = Σ_a e_a d_aᵀ` is
/// the deformation gradient in the local frame `R0` of the reference axis.
#[derive(Clone, Copy, Debug)]
struct Point {
    w: f64,
    d: [Vector2<f64>; 4],
}

/// One seed-000 element: reference data for integration, independent of the current coordinates.
#[derive(Clone, Debug)]
pub struct AncfShear2d {
    length: f64,
    section: Section,
    normal: [Point; 4],
    shear: [Point; 2],
    n_shear: usize,
}

// ---------------------------------------------------------------------------------------------
// Shape functions (Eq. 6)
// ---------------------------------------------------------------------------------------------

/// Shape functions `[S1, S2, S3, S4]` at local `(x, y)`, `x ∈ [0, l]`, `y ∈ [-h/2, h/2]` (Eq. 6):
/// `S1 = 1 − ξ`, `S2 = y(1 − ξ)`, `S3 = ξ`, `S4 = xy/l`, `ξ = x/l`.
pub fn shape_functions(l: f64, x: f64, y: f64) -> [f64; 4] {
    let xi = x / l;
    [1.0 - xi, y * (1.0 - xi), xi, y * xi]
}

/// Local gradients `[∂S_a/∂x, ∂S_a/∂y]` of the four shape functions at `(x, y)`.
pub fn shape_gradients(l: f64, x: f64, y: f64) -> [Vector2<f64>; 4] {
    let xi = x / l;
    [
        Vector2::new(-1.0 / l, 0.0),
        Vector2::new(-y / l, 1.0 - xi),
        Vector2::new(1.0 / l, 0.0),
        Vector2::new(y / l, xi),
    ]
}

/// Position `r(x, y) = S(x, y) e` of a material point.
pub fn position(e: &ElemVec, l: f64, x: f64, y: f64) -> Vector2<f64> {
    let s = shape_functions(l, x, y);
    let mut r = Vector2::zeros();
    for (a, sa) in s.iter().enumerate() {
        r += *sa * Vector2::new(e[2 * a], e[2 * a + 1]);
    }
    r
}

/// Jacobian `J = [∂r/∂x | ∂r/∂y]` of the map from local coordinates to positions (Eq. 7).
fn jacobian(e: &ElemVec, grads: &[Vector2<f64>; 4]) -> Matrix2<f64> {
    let mut j = Matrix2::zeros();
    for (a, g) in grads.iter().enumerate() {
        j += Vector2::new(e[2 * a], e[2 * a + 1]) * g.transpose();
    }
    j
}

impl AncfShear2d {
    /// Element of reference length `length` [m] whose reference (stress-free) configuration is
    /// `e0`. A straight element along `x` has `e0 = [x_I, 0, 0, 1, x_J, 0, 0, 1]`; any rigid
    /// rotation or translation of it gives the same element.
    ///
    /// Returns `None` when the reference Jacobian `J0` is singular at an integration point.
    pub fn new(e0: &ElemVec, length: f64, section: Section, rule: ShearRule) -> Option<Self> {
        let l = length;
        let (h, b) = (section.height, section.width);
        let point = |xi01: f64, y: f64, w: f64| -> Option<Point> {
            let x = xi01 * l;
            let grads = shape_gradients(l, x, y);
            let j0 = jacobian(e0, &grads);
            let det = j0.determinant();
            let j0_inv_t = j0.try_inverse()?.transpose();
            if det.is_nan() || det <= 0.0 {
                return None;
            }
            // Strains are measured in the local frame R0 = [t, n] of the reference axis
            // (t along ∂r0/∂x), so that E11 is axial and E22 transverse for any orientation:
            // d_a = R0ᵀ J0⁻ᵀ ∇S_a, i.e. D = J J0⁻¹ R0.
            let t = j0.column(0).normalize();
            let r0 = Matrix2::new(t.x, -t.y, t.y, t.x);
            let mut d = [Vector2::zeros(); 4];
            for a in 0..4 {
                d[a] = r0.transpose() * (j0_inv_t * grads[a]);
            }
            Some(Point {
                w: w * 0.5 * l * 0.5 * h * b * det,
                d,
            })
        };
        let g2 = gauss_legendre(2);
        let mut normal = [Point {
            w: 0.0,
            d: [Vector2::zeros(); 4],
        }; 4];
        let mut k = 0;
        for &(px, wx) in g2 {
            for &(py, wy) in g2 {
                normal[k] = point(0.5 * (px + 1.0), 0.5 * h * py, wx * wy)?;
                k += 1;
            }
        }
        let mut shear = [normal[0]; 2];
        let n_shear = match rule {
            ShearRule::Original1x1 => {
                shear[0] = point(0.5, 0.0, 4.0)?;
                1
            }
            ShearRule::Fixed1x2 => {
                for (i, &(py, wy)) in g2.iter().enumerate() {
                    shear[i] = point(0.5, 0.5 * h * py, 2.0 * wy)?;
                }
                2
            }
        };
        Some(Self {
            length: l,
            section,
            normal,
            shear,
            n_shear,
        })
    }

    /// Reference coordinates of a straight element from `p_i` to `p_j` with the cross-section
    /// gradient perpendicular to the axis (unit length).
    pub fn straight_reference(p_i: Vector2<f64>, p_j: Vector2<f64>) -> ElemVec {
        let t = (p_j - p_i).normalize();
        let n = Vector2::new(-t.y, t.x);
        ElemVec::from_column_slice(&[p_i.x, p_i.y, n.x, n.y, p_j.x, p_j.y, n.x, n.y])
    }

    /// Reference length `l` [m].
    pub fn length(&self) -> f64 {
        self.length
    }

    // -----------------------------------------------------------------------------------------
    // Mass (Eq. 14) and gravity
    // -----------------------------------------------------------------------------------------

    /// Constant mass matrix `M = ∫ ρ Sᵀ S dV` (Eq. 14) for a reference configuration `e0`,
    /// integrated with 3×3 Gauss points (exact for a straight element). Units: kg (position
    /// rows), kg m (mixed), kg m² (gradient rows).
    pub fn mass(&self, e0: &ElemVec, rho: f64) -> ElemMat {
        let mut m4 = nalgebra::Matrix4::<f64>::zeros();
        self.integrate_reference(e0, |s, dv| {
            let sv = nalgebra::Vector4::from(s);
            m4 += rho * dv * sv * sv.transpose();
        });
        let mut m = ElemMat::zeros();
        for a in 0..4 {
            for b in 0..4 {
                m[(2 * a, 2 * b)] = m4[(a, b)];
                m[(2 * a + 1, 2 * b + 1)] = m4[(a, b)];
            }
        }
        m
    }

    /// Generalized gravity force `Q_g = ∫ ρ Sᵀ g dV` [N] for acceleration `g` [m/s²].
    pub fn gravity(&self, e0: &ElemVec, rho: f64, g: Vector2<f64>) -> ElemVec {
        let mut q = ElemVec::zeros();
        self.integrate_reference(e0, |s, dv| {
            for a in 0..4 {
                q[2 * a] += rho * dv * s[a] * g.x;
                q[2 * a + 1] += rho * dv * s[a] * g.y;
            }
        });
        q
    }

    /// Integrates `f(S, dV)` over the reference volume with 3×3 Gauss points.
    fn integrate_reference(&self, e0: &ElemVec, mut f: impl FnMut([f64; 4], f64)) {
        let (l, h, b) = (self.length, self.section.height, self.section.width);
        let g3 = gauss_legendre(3);
        for &(px, wx) in g3 {
            for &(py, wy) in g3 {
                let x = 0.5 * (px + 1.0) * l;
                let y = 0.5 * h * py;
                let det = jacobian(e0, &shape_gradients(l, x, y)).determinant();
                f(
                    shape_functions(l, x, y),
                    wx * wy * 0.5 * l * 0.5 * h * b * det,
                );
            }
        }
    }

    // -----------------------------------------------------------------------------------------
    // Internal forces (Eqs. 7–13) and tangent
    // -----------------------------------------------------------------------------------------

    /// Strain energy `U(e)` [J] with the selective integration of section 5/7.
    pub fn strain_energy(&self, e: &ElemVec, law: &PlaneElasticity) -> f64 {
        let mut u = 0.0;
        for p in &self.normal {
            let (_, eps) = strain(p, e);
            u += 0.5 * p.w * eps.dot(&(law.normal * eps));
        }
        for p in &self.shear[..self.n_shear] {
            let (_, eps) = strain(p, e);
            u += 0.5 * p.w * eps.dot(&(law.shear * eps));
        }
        u
    }

    /// Elastic force `Q_e = (∂U/∂e)ᵀ` [N] (Eq. 13), written into `f`; returns `U` [J].
    pub fn internal_force(&self, e: &ElemVec, law: &PlaneElasticity, f: &mut ElemVec) -> f64 {
        *f = ElemVec::zeros();
        let mut u = 0.0;
        for p in &self.normal {
            u += accumulate(p, e, &law.normal, f, None);
        }
        for p in &self.shear[..self.n_shear] {
            u += accumulate(p, e, &law.shear, f, None);
        }
        u
    }

    /// Elastic force and exact tangent `K = ∂Q_e/∂e` [N/m]; returns `U` [J].
    pub fn internal_force_tangent(
        &self,
        e: &ElemVec,
        law: &PlaneElasticity,
        f: &mut ElemVec,
        k: &mut ElemMat,
    ) -> f64 {
        *f = ElemVec::zeros();
        *k = ElemMat::zeros();
        let mut u = 0.0;
        for p in &self.normal {
            u += accumulate(p, e, &law.normal, f, Some(k));
        }
        for p in &self.shear[..self.n_shear] {
            u += accumulate(p, e, &law.shear, f, Some(k));
        }
        u
    }

    /// Energy-conserving "average stress" force of the midpoint rule (reference F.4):
    /// `Q = ∫ B(e_m)ᵀ C ½(ε(e_a) + ε(e_b)) dV` with `e_m = ½(e_a + e_b)`. Because ε is quadratic
    /// in `e`, `Qᵀ (e_b − e_a) = U(e_b) − U(e_a)` exactly. With `k`, also returns `∂Q/∂e_b`.
    pub fn average_stress_force(
        &self,
        e_a: &ElemVec,
        e_b: &ElemVec,
        law: &PlaneElasticity,
        f: &mut ElemVec,
        mut k: Option<&mut ElemMat>,
    ) {
        *f = ElemVec::zeros();
        if let Some(k) = k.as_deref_mut() {
            *k = ElemMat::zeros();
        }
        let e_m = 0.5 * (e_a + e_b);
        let rules: [(&[Point], &Matrix3<f64>); 2] = [
            (&self.normal, &law.normal),
            (&self.shear[..self.n_shear], &law.shear),
        ];
        for (points, c) in rules {
            for p in points {
                let (_, eps_a) = strain(p, e_a);
                let (f_b, eps_b) = strain(p, e_b);
                let (f_m, _) = strain(p, &e_m);
                let s = c * (0.5 * (eps_a + eps_b));
                let b_m = strain_matrix(p, &f_m);
                *f += p.w * b_m.transpose() * s;
                if let Some(k) = k.as_deref_mut() {
                    // d/de_b: B(e_m) depends on e_m = (e_a + e_b)/2, the stress on ε(e_b)/2.
                    let b_b = strain_matrix(p, &f_b);
                    *k += (0.5 * p.w) * b_m.transpose() * (c * b_b);
                    add_geometric(p, &s, 0.5 * p.w, k);
                }
            }
        }
    }
}

/// Deformation gradient `D = Σ_a e_a d_aᵀ` (Eq. 8) and Green–Lagrange strain in Voigt form
/// `[ε11, ε22, 2ε12]` (Eq. 9).
#[inline]
fn strain(p: &Point, e: &ElemVec) -> (Matrix2<f64>, Vector3<f64>) {
    let mut d = Matrix2::zeros();
    for a in 0..4 {
        d += Vector2::new(e[2 * a], e[2 * a + 1]) * p.d[a].transpose();
    }
    let c = d.transpose() * d;
    (
        d,
        Vector3::new(0.5 * (c[(0, 0)] - 1.0), 0.5 * (c[(1, 1)] - 1.0), c[(0, 1)]),
    )
}

/// Strain–displacement matrix `B = ∂ε/∂e` (3×8) at a point with deformation gradient `d`:
/// `∂ε_ij/∂e_a = ½(d_ai F_j + d_aj F_i)`, `F_j` = column j of `D`.
#[inline]
fn strain_matrix(p: &Point, d: &Matrix2<f64>) -> SMatrix<f64, 3, 8> {
    let mut b = SMatrix::<f64, 3, 8>::zeros();
    for a in 0..4 {
        let g = p.d[a];
        for i in 0..2 {
            b[(0, 2 * a + i)] = g.x * d[(i, 0)];
            b[(1, 2 * a + i)] = g.y * d[(i, 1)];
            b[(2, 2 * a + i)] = g.x * d[(i, 1)] + g.y * d[(i, 0)];
        }
    }
    b
}

/// Geometric stiffness `Σ_ij S_ij ∂²ε_ij/∂e_a∂e_b = (d_aᵀ S d_b) I₂`, scaled by `w`.
#[inline]
fn add_geometric(p: &Point, s: &Vector3<f64>, w: f64, k: &mut ElemMat) {
    let smat = Matrix2::new(s[0], s[2], s[2], s[1]);
    for a in 0..4 {
        let sd = smat * p.d[a];
        for b in 0..4 {
            let g = w * sd.dot(&p.d[b]);
            k[(2 * a, 2 * b)] += g;
            k[(2 * a + 1, 2 * b + 1)] += g;
        }
    }
}

/// Adds one integration point's force (and tangent) and returns its energy.
#[inline]
fn accumulate(
    p: &Point,
    e: &ElemVec,
    c: &Matrix3<f64>,
    f: &mut ElemVec,
    k: Option<&mut ElemMat>,
) -> f64 {
    let (d, eps) = strain(p, e);
    let s = c * eps;
    let b = strain_matrix(p, &d);
    *f += p.w * b.transpose() * s;
    if let Some(k) = k {
        *k += p.w * b.transpose() * (c * b);
        add_geometric(p, &s, p.w, k);
    }
    0.5 * p.w * eps.dot(&s)
}

// ---------------------------------------------------------------------------------------------
// The element trait
// ---------------------------------------------------------------------------------------------

/// A seed-000 element with its material: the kernel, the elastic law, the density and the
/// reference configuration, with the constant mass matrix computed once.
#[derive(Clone, Debug)]
pub struct Shear2dElement {
    /// Integration data of the element.
    pub kernel: AncfShear2d,
    /// Elastic law.
    pub law: PlaneElasticity,
    /// Density [kg/m³].
    pub rho: f64,
    /// Reference (stress-free) coordinates.
    pub e0: ElemVec,
    mass: ElemMat,
}

impl Shear2dElement {
    /// The element of reference coordinates `e0` and length `length` [m] (see
    /// [`AncfShear2d::new`]) with law `law` and density `rho` [kg/m³]; `None` if the reference
    /// geometry is degenerate.
    pub fn new(
        e0: &ElemVec,
        length: f64,
        section: Section,
        rule: ShearRule,
        law: PlaneElasticity,
        rho: f64,
    ) -> Option<Self> {
        let kernel = AncfShear2d::new(e0, length, section, rule)?;
        let mass = kernel.mass(e0, rho);
        Some(Self {
            kernel,
            law,
            rho,
            e0: *e0,
            mass,
        })
    }

    /// Constant mass matrix (Eq. 14).
    pub fn mass(&self) -> &ElemMat {
        &self.mass
    }
}

/// Slots `[r_I, r_I,y, r_J, r_J,y]` (Eq. 5).
const SHEAR_SLOTS: &[Slot] = &[
    Slot::Position,
    Slot::Direction,
    Slot::Position,
    Slot::Direction,
];

impl Element<ELEMENT_COORDS> for Shear2dElement {
    fn layout(&self) -> Layout {
        Layout {
            dim: 2,
            slots: SHEAR_SLOTS,
        }
    }

    fn constant_mass_matrix(&self) -> Option<&ElemMat> {
        Some(&self.mass)
    }

    fn mass_into(&self, _s: &ElementState<ELEMENT_COORDS>, m: &mut ElemMat) {
        *m = self.mass;
    }

    fn gravity_into(&self, _s: &ElementState<ELEMENT_COORDS>, g: &Vector3<f64>, f: &mut ElemVec) {
        *f = self
            .kernel
            .gravity(&self.e0, self.rho, Vector2::new(g.x, g.y));
    }

    fn strain_energy_at(&self, s: &ElementState<ELEMENT_COORDS>) -> f64 {
        self.kernel.strain_energy(&s.q, &self.law)
    }

    fn force_into(&self, s: &ElementState<ELEMENT_COORDS>, f: &mut ElemVec) -> f64 {
        self.kernel.internal_force(&s.q, &self.law, f)
    }

    /// No material damping: `C = 0`.
    fn tangent_into(
        &self,
        s: &ElementState<ELEMENT_COORDS>,
        f: &mut ElemVec,
        k: &mut ElemMat,
        c: Option<&mut ElemMat>,
    ) -> f64 {
        if let Some(c) = c {
            *c = ElemMat::zeros();
        }
        self.kernel.internal_force_tangent(&s.q, &self.law, f, k)
    }

    fn average_force_into(
        &self,
        a: &ElementState<ELEMENT_COORDS>,
        b: &ElementState<ELEMENT_COORDS>,
        f: &mut ElemVec,
        k: Option<&mut ElemMat>,
    ) -> bool {
        self.kernel
            .average_stress_force(&a.q, &b.q, &self.law, f, k);
        true
    }
}
