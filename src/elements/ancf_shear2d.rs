//! Seed-000 element: linear shear-deformable 2D ANCF beam with selective integration.
//!
//! Kerkkänen, Sopanen, Mikkola 2003 ("A linear beam finite element based on the absolute nodal
//! coordinate formulation"), decoded in `shared/reference/seed000-ancf-shear-beam.md`.
//! Nodal coordinates (Eq. 5): `e_I = [r_I ; ∂r/∂y|_I]` (4 per node, 8 per element), ordered
//! `[r_I, r_I,y, r_J, r_J,y]`, each a 2-vector.
//!
//! The file follows the fixed order of every element: shape functions, mass, internal forces,
//! tangent.

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::material::StrainEnergy;
    use nalgebra::Rotation2;

    const E: f64 = 2.07e11;
    const NU: f64 = 0.3;
    const RHO: f64 = 7850.0;

    fn section() -> Section {
        Section {
            width: 0.1,
            height: 0.1,
        }
    }

    fn element(rule: ShearRule) -> (AncfShear2d, ElemVec) {
        let e0 = AncfShear2d::straight_reference(Vector2::new(0.0, 0.0), Vector2::new(0.25, 0.0));
        (AncfShear2d::new(&e0, 0.25, section(), rule).unwrap(), e0)
    }

    fn laws() -> [PlaneElasticity; 2] {
        [
            PlaneElasticity::new(E, NU, 5.0 / 6.0, StrainEnergy::Decoupled),
            PlaneElasticity::new(E, NU, 5.0 / 6.0, StrainEnergy::Lame),
        ]
    }

    /// A deformed configuration: stretch, bend, shear and a rotated gradient.
    fn deformed(e0: &ElemVec) -> ElemVec {
        e0 + ElemVec::from_column_slice(&[1e-3, -2e-3, 0.05, -0.02, 4e-3, 0.03, -0.04, 0.06])
    }

    fn rigid(e0: &ElemVec, angle: f64, t: Vector2<f64>) -> ElemVec {
        let r = Rotation2::new(angle);
        let mut e = ElemVec::zeros();
        for a in 0..4 {
            let v = r * Vector2::new(e0[2 * a], e0[2 * a + 1]);
            // positions translate, gradients only rotate
            let v = if a % 2 == 0 { v + t } else { v };
            e[2 * a] = v.x;
            e[2 * a + 1] = v.y;
        }
        e
    }

    /// Closed-form mass matrix of reference A.6: M = M4 ⊗ I2 with m/3, m/6, m h²/36, m h²/72.
    #[test]
    fn mass_matches_closed_form() {
        let (el, e0) = element(ShearRule::Fixed1x2);
        let (l, h, b) = (0.25, 0.1, 0.1);
        let m = RHO * b * h * l;
        let m4 = nalgebra::Matrix4::new(
            m / 3.0,
            0.0,
            m / 6.0,
            0.0,
            0.0,
            m * h * h / 36.0,
            0.0,
            m * h * h / 72.0,
            m / 6.0,
            0.0,
            m / 3.0,
            0.0,
            0.0,
            m * h * h / 72.0,
            0.0,
            m * h * h / 36.0,
        );
        let mass = el.mass(&e0, RHO);
        for a in 0..4 {
            for bb in 0..4 {
                for i in 0..2 {
                    for j in 0..2 {
                        let expect = if i == j { m4[(a, bb)] } else { 0.0 };
                        let got = mass[(2 * a + i, 2 * bb + j)];
                        assert!((got - expect).abs() <= 1e-12 * m, "M[{a}{i},{bb}{j}]");
                    }
                }
            }
        }
    }

    /// Gravity of reference A.6: Q_g = [m g/2, 0, m g/2, 0].
    #[test]
    fn gravity_matches_closed_form() {
        let (el, e0) = element(ShearRule::Fixed1x2);
        let m = RHO * 0.1 * 0.1 * 0.25;
        let g = Vector2::new(0.3, -9.81);
        let q = el.gravity(&e0, RHO, g);
        let expect = [
            0.5 * m * g.x,
            0.5 * m * g.y,
            0.0,
            0.0,
            0.5 * m * g.x,
            0.5 * m * g.y,
            0.0,
            0.0,
        ];
        for i in 0..8 {
            assert!((q[i] - expect[i]).abs() < 1e-12 * m * 10.0, "Q_g[{i}]");
        }
    }

    /// Zero strain energy and zero force in the reference configuration and under any rigid
    /// rotation and translation.
    #[test]
    fn rigid_motion_is_strain_free() {
        for rule in [ShearRule::Original1x1, ShearRule::Fixed1x2] {
            let (el, e0) = element(rule);
            for law in laws() {
                for (angle, t) in [
                    (0.0, Vector2::zeros()),
                    (0.7, Vector2::new(3.0, -1.0)),
                    (std::f64::consts::PI, Vector2::new(-2.0, 5.0)),
                    (-2.5, Vector2::new(0.1, 0.2)),
                    (7.0, Vector2::new(100.0, 0.0)),
                ] {
                    let e = rigid(&e0, angle, t);
                    let mut f = ElemVec::zeros();
                    let u = el.internal_force(&e, &law, &mut f);
                    assert!(u.abs() < 1e-12, "U = {u} for angle {angle}");
                    assert!(f.norm() < 1e-2, "|Q_e| = {} for angle {angle}", f.norm());
                }
            }
        }
    }

    /// A rotated reference element has the same stiffness as the one along x.
    #[test]
    fn rotated_reference_gives_same_energy() {
        let (el, e0) = element(ShearRule::Fixed1x2);
        let e = deformed(&e0);
        let law = laws()[0];
        let u0 = el.strain_energy(&e, &law);
        let e0r = rigid(&e0, 1.1, Vector2::new(1.0, 2.0));
        let er = rigid(&e, 1.1, Vector2::new(1.0, 2.0));
        let elr = AncfShear2d::new(&e0r, 0.25, section(), ShearRule::Fixed1x2).unwrap();
        let ur = elr.strain_energy(&er, &law);
        assert!((u0 - ur).abs() <= 1e-10 * u0.abs(), "{u0} vs {ur}");
    }

    /// Force is the gradient of the energy: central differences of U.
    #[test]
    fn force_matches_energy_gradient() {
        for rule in [ShearRule::Original1x1, ShearRule::Fixed1x2] {
            let (el, e0) = element(rule);
            for law in laws() {
                let e = deformed(&e0);
                let mut f = ElemVec::zeros();
                el.internal_force(&e, &law, &mut f);
                let hstep = 1e-6;
                for i in 0..8 {
                    let mut ep = e;
                    let mut em = e;
                    ep[i] += hstep;
                    em[i] -= hstep;
                    let fd =
                        (el.strain_energy(&ep, &law) - el.strain_energy(&em, &law)) / (2.0 * hstep);
                    assert!(
                        (fd - f[i]).abs() <= 1e-6 * f.norm(),
                        "rule {rule:?} dof {i}: {fd} vs {}",
                        f[i]
                    );
                }
            }
        }
    }

    /// Tangent against central finite differences of the force.
    #[test]
    fn tangent_matches_finite_differences() {
        for rule in [ShearRule::Original1x1, ShearRule::Fixed1x2] {
            let (el, e0) = element(rule);
            for law in laws() {
                let e = deformed(&e0);
                let mut f = ElemVec::zeros();
                let mut k = ElemMat::zeros();
                el.internal_force_tangent(&e, &law, &mut f, &mut k);
                let hstep = 1e-7;
                let mut fd = ElemMat::zeros();
                for j in 0..8 {
                    let (mut ep, mut em) = (e, e);
                    ep[j] += hstep;
                    em[j] -= hstep;
                    let (mut fp, mut fm) = (ElemVec::zeros(), ElemVec::zeros());
                    el.internal_force(&ep, &law, &mut fp);
                    el.internal_force(&em, &law, &mut fm);
                    fd.set_column(j, &((fp - fm) / (2.0 * hstep)));
                }
                let err = (fd - k).norm() / k.norm();
                assert!(err < 1e-7, "rule {rule:?}: relative tangent error {err}");
                assert!(
                    (k - k.transpose()).norm() <= 1e-12 * k.norm(),
                    "tangent not symmetric"
                );
            }
        }
    }

    /// Average-stress force: exact energy difference, consistent with Q_e when e_a = e_b, and
    /// its derivative against finite differences.
    #[test]
    fn average_stress_force_is_a_discrete_gradient() {
        let (el, e0) = element(ShearRule::Fixed1x2);
        let law = laws()[0];
        let ea = deformed(&e0);
        let eb = rigid(&ea, 0.3, Vector2::new(0.01, -0.02)) + ElemVec::from_element(1e-3);
        let mut f = ElemVec::zeros();
        let mut k = ElemMat::zeros();
        el.average_stress_force(&ea, &eb, &law, &mut f, Some(&mut k));
        let du = el.strain_energy(&eb, &law) - el.strain_energy(&ea, &law);
        assert!(
            (f.dot(&(eb - ea)) - du).abs() <= 1e-10 * du.abs().max(1.0),
            "not exact"
        );

        let mut fe = ElemVec::zeros();
        el.internal_force(&ea, &law, &mut fe);
        el.average_stress_force(&ea, &ea, &law, &mut f, None);
        assert!((f - fe).norm() <= 1e-10 * fe.norm());

        let hstep = 1e-7;
        let mut fd = ElemMat::zeros();
        for j in 0..8 {
            let (mut ep, mut em) = (eb, eb);
            ep[j] += hstep;
            em[j] -= hstep;
            let (mut fp, mut fm) = (ElemVec::zeros(), ElemVec::zeros());
            el.average_stress_force(&ea, &ep, &law, &mut fp, None);
            el.average_stress_force(&ea, &em, &law, &mut fm, None);
            fd.set_column(j, &((fp - fm) / (2.0 * hstep)));
        }
        el.average_stress_force(&ea, &eb, &law, &mut f, Some(&mut k));
        let err = (fd - k).norm() / k.norm();
        assert!(err < 1e-7, "average-stress tangent error {err}");
    }

    /// Pure axial stretch: ε11 = ½(λ² − 1) integrated over the volume.
    #[test]
    fn uniaxial_stretch_energy() {
        let (el, e0) = element(ShearRule::Fixed1x2);
        let law = laws()[0];
        let stretch = 1.01;
        let mut e = e0;
        e[4] = 0.25 * stretch;
        let eps = 0.5 * (stretch * stretch - 1.0);
        let expect = 0.5 * E * eps * eps * 0.25 * 0.1 * 0.1;
        let u = el.strain_energy(&e, &law);
        assert!((u - expect).abs() <= 1e-12 * expect);
    }
}
