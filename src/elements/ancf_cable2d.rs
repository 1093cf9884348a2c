//! Gradient-deficient ANCF cable element in 2D (belts, ropes, thin beams).
//!
//! Formulation as documented for Exudyn's `ObjectANCFCable2D` (interpolation after Berzeri &
//! Shabana 2000, elastic forces after Gerstmayr & Irschik 2008), summarised in
//! `shared/reference/belt-drive.md` E.1:
//! * coordinates per node: position `r` and axial slope `r' = ∂r/∂x` (2-vectors); element
//!   `q = [r0, r0', r1, r1']` (8 coordinates), `x ∈ [0, L]` the arc length of the stress-free
//!   reference configuration (so `L` is the *unstretched* element length: a belt mounted with
//!   pre-tension has elements shorter than their mounted length);
//! * cubic Hermite shape functions `S1 = 1 − 3ξ² + 2ξ³`, `S2 = L(ξ − 2ξ² + ξ³)`,
//!   `S3 = 3ξ² − 2ξ³`, `S4 = L(−ξ² + ξ³)`, `ξ = x/L`;
//! * axial (engineering) strain `ε = |r'| − 1`, material curvature
//!   `K = (r' × r'')/|r'|²` (the rate of the tangent angle per unit reference length);
//! * `δW_int = ∫ (N δε + M δK) dx` with `N = EA(ε − ε0) + d_ε ε̇` and `M = EI(K − K0) + d_K K̇`;
//!   axial stiffness `EA` and bending stiffness `EI` are independent (a cord-reinforced belt is
//!   not a homogeneous beam); `ε0` is an optional prescribed pre-strain, `K0 = 0` (straight
//!   reference).
//!
//! The file follows the fixed order of every element: shape functions, mass, internal forces,
//! tangent; then the element trait.

use super::element::{Element, ElementState, Layout, Slot};
use super::quadrature::{gauss_legendre, lobatto3};
use nalgebra::{Matrix2, SMatrix, SVector, Vector2, Vector3};

/// Coordinates per node (position and axial slope, both 2-vectors).
pub const NODE_COORDS: usize = 4;
/// Coordinates per element.
pub const ELEMENT_COORDS: usize = 8;
/// Element coordinate vector `q = [r0, r0', r1, r1']`.
pub type ElemVec = SVector<f64, ELEMENT_COORDS>;
/// Element matrix (mass, tangent, damping).
pub type ElemMat = SMatrix<f64, ELEMENT_COORDS, ELEMENT_COORDS>;

/// Section data of a cable as belt datasheets give them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CableSection {
    /// Axial stiffness `EA` [N].
    pub ea: f64,
    /// Bending stiffness `EI` [N m²].
    pub ei: f64,
    /// Mass per unit reference (unstretched) length `ρA` [kg/m].
    pub mass_per_length: f64,
    /// Axial material damping `d_ε` [N s]: `N_d = d_ε ε̇`.
    pub damping_axial: f64,
    /// Bending material damping `d_K` [N m² s]: `M_d = d_K K̇`.
    pub damping_bending: f64,
    /// Prescribed pre-strain `ε0` [1] (stress-free axial strain; negative pre-strain tensions a
    /// cable mounted at its reference length).
    pub prestrain: f64,
}

/// Integration rule of the elastic forces (options of reference E.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CableRule {
    /// 5 Gauss points for the axial terms, 3 for the bending terms.
    Full,
    /// 4 Gauss points for the axial terms, 2 for the bending terms.
    Reduced,
    /// Lobatto 3 points `{0, L/2, L}` for the axial terms, 2 Gauss points for bending: decouples
    /// axial from bending strain and gives smooth axial forces in belts.
    Mixed,
}

/// One integration point: weight [m] and the first and second derivatives of the four shape
/// functions with respect to `x` (`S2`, `S4` carry the length factor).
#[derive(Clone, Copy, Debug, Default)]
struct Point {
    w: f64,
    d1: [f64; 4],
    d2: [f64; 4],
}

/// One cable element: reference length, section and integration points.
#[derive(Clone, Debug)]
pub struct AncfCable2d {
    length: f64,
    section: CableSection,
    axial: [Point; 5],
    n_axial: usize,
    bending: [Point; 3],
    n_bending: usize,
    mass: ElemMat,
}

// ---------------------------------------------------------------------------------------------
// Shape functions
// ---------------------------------------------------------------------------------------------

/// Shape functions `[S1, S2, S3, S4]` at `x ∈ [0, l]` (cubic Hermite; `S2`, `S4` multiply the
/// slopes and carry the length).
pub fn shape_functions(l: f64, x: f64) -> [f64; 4] {
    let xi = x / l;
    let (x2, x3) = (xi * xi, xi * xi * xi);
    [
        1.0 - 3.0 * x2 + 2.0 * x3,
        l * (xi - 2.0 * x2 + x3),
        3.0 * x2 - 2.0 * x3,
        l * (-x2 + x3),
    ]
}

/// First derivatives `∂S_a/∂x` [1/m for S1, S3; 1 for S2, S4].
pub fn shape_d1(l: f64, x: f64) -> [f64; 4] {
    let xi = x / l;
    [
        (-6.0 * xi + 6.0 * xi * xi) / l,
        1.0 - 4.0 * xi + 3.0 * xi * xi,
        (6.0 * xi - 6.0 * xi * xi) / l,
        -2.0 * xi + 3.0 * xi * xi,
    ]
}

/// Second derivatives `∂²S_a/∂x²`.
pub fn shape_d2(l: f64, x: f64) -> [f64; 4] {
    let xi = x / l;
    [
        (-6.0 + 12.0 * xi) / (l * l),
        (-4.0 + 6.0 * xi) / l,
        (6.0 - 12.0 * xi) / (l * l),
        (-2.0 + 6.0 * xi) / l,
    ]
}

/// `Σ_a s_a q_a`: a field (position, slope or curvature vector) from the coordinates.
#[inline]
fn combine(s: &[f64; 4], q: &ElemVec) -> Vector2<f64> {
    let mut v = Vector2::zeros();
    for a in 0..4 {
        v.x += s[a] * q[2 * a];
        v.y += s[a] * q[2 * a + 1];
    }
    v
}

/// Position `r(x) = S(x) q` [m].
pub fn position(q: &ElemVec, l: f64, x: f64) -> Vector2<f64> {
    combine(&shape_functions(l, x), q)
}

/// Reference coordinates of a straight element from `p0` to `p1` (slopes = unit tangent
/// times `stretch`, the ratio of mounted to reference length).
pub fn straight_coordinates(p0: Vector2<f64>, p1: Vector2<f64>, stretch: f64) -> ElemVec {
    let t = (p1 - p0).normalize() * stretch;
    ElemVec::from_column_slice(&[p0.x, p0.y, t.x, t.y, p1.x, p1.y, t.x, t.y])
}

/// Strain quantities at one point: the first-derivative vectors and the strains.
struct Kinematics {
    /// `∂ε/∂q` (8)
    de: ElemVec,
    /// `∂K/∂q` (8)
    dk: ElemVec,
    eps: f64,
    curv: f64,
}

// ---------------------------------------------------------------------------------------------
// Mass (the constant matrix, computed once per element)
// ---------------------------------------------------------------------------------------------

/// Consistent mass matrix `M = ∫ ρA Sᵀ S dx` [kg, kg m, kg m²] of an element of length `l`
/// [m] and mass per length `rho_a` [kg/m], integrated with 4 Gauss points (exact for the cubic
/// shape functions).
pub fn consistent_mass(l: f64, rho_a: f64) -> ElemMat {
    let mut m4 = nalgebra::Matrix4::<f64>::zeros();
    for &(p, w) in gauss_legendre(4) {
        let s = nalgebra::Vector4::from(shape_functions(l, 0.5 * (p + 1.0) * l));
        m4 += (rho_a * w * 0.5 * l) * s * s.transpose();
    }
    let mut m = ElemMat::zeros();
    for a in 0..4 {
        for b in 0..4 {
            m[(2 * a, 2 * b)] = m4[(a, b)];
            m[(2 * a + 1, 2 * b + 1)] = m4[(a, b)];
        }
    }
    m
}

impl AncfCable2d {
    /// Element of reference (stress-free) length `length` [m].
    pub fn new(length: f64, section: CableSection, rule: CableRule) -> Self {
        let mk = |xi01: f64, w: f64| {
            let x = xi01 * length;
            Point {
                w: w * 0.5 * length,
                d1: shape_d1(length, x),
                d2: shape_d2(length, x),
            }
        };
        let mut axial = [Point::default(); 5];
        let mut bending = [Point::default(); 3];
        type Rule = &'static [(f64, f64)];
        let (ra, rb): (Rule, Rule) = match rule {
            CableRule::Full => (gauss_legendre(5), gauss_legendre(3)),
            CableRule::Reduced => (gauss_legendre(4), gauss_legendre(2)),
            CableRule::Mixed => (lobatto3(), gauss_legendre(2)),
        };
        for (i, &(p, w)) in ra.iter().enumerate() {
            axial[i] = mk(0.5 * (p + 1.0), w);
        }
        for (i, &(p, w)) in rb.iter().enumerate() {
            bending[i] = mk(0.5 * (p + 1.0), w);
        }
        Self {
            length,
            section,
            axial,
            n_axial: ra.len(),
            bending,
            n_bending: rb.len(),
            mass: consistent_mass(length, section.mass_per_length),
        }
    }

    /// Reference length `L` [m].
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Section data.
    pub fn section(&self) -> &CableSection {
        &self.section
    }

    // -----------------------------------------------------------------------------------------
    // Mass and gravity
    // -----------------------------------------------------------------------------------------

    /// Constant mass matrix `M = ∫ ρA Sᵀ S dx` [kg, kg m, kg m²] (computed once, see
    /// [`consistent_mass`]).
    pub fn mass(&self) -> ElemMat {
        self.mass
    }

    /// Generalized gravity force `Q_g = ∫ ρA Sᵀ g dx` [N] for acceleration `g` [m/s²]:
    /// `ρA L [g/2, L g/12, g/2, −L g/12]`.
    pub fn gravity(&self, g: Vector2<f64>) -> ElemVec {
        let (l, m) = (self.length, self.section.mass_per_length);
        let f = [0.5 * l, l * l / 12.0, 0.5 * l, -l * l / 12.0];
        let mut q = ElemVec::zeros();
        for a in 0..4 {
            q[2 * a] = m * f[a] * g.x;
            q[2 * a + 1] = m * f[a] * g.y;
        }
        q
    }

    // -----------------------------------------------------------------------------------------
    // Internal forces
    // -----------------------------------------------------------------------------------------

    /// Axial strain `ε = |r'| − 1` and its gradient at a point.
    #[inline]
    fn axial_kin(p: &Point, q: &ElemVec) -> (Vector2<f64>, f64, f64, ElemVec) {
        let rp = combine(&p.d1, q);
        let len = rp.norm();
        let u = rp / len;
        let mut de = ElemVec::zeros();
        for a in 0..4 {
            de[2 * a] = p.d1[a] * u.x;
            de[2 * a + 1] = p.d1[a] * u.y;
        }
        (u, len, len - 1.0, de)
    }

    /// Curvature `K = c/g` (`c = r' × r''`, `g = r'·r'`) and the gradients of `c`, `g`, `K`.
    #[inline]
    fn bending_kin(p: &Point, q: &ElemVec) -> (f64, f64, f64, ElemVec, ElemVec, ElemVec) {
        let rp = combine(&p.d1, q);
        let rpp = combine(&p.d2, q);
        let c = rp.x * rpp.y - rp.y * rpp.x;
        let g = rp.dot(&rp);
        let k = c / g;
        let (mut dc, mut dg) = (ElemVec::zeros(), ElemVec::zeros());
        for a in 0..4 {
            // ∂c/∂r' = (r''_y, −r''_x), ∂c/∂r'' = (−r'_y, r'_x)
            dc[2 * a] = p.d1[a] * rpp.y - p.d2[a] * rp.y;
            dc[2 * a + 1] = -p.d1[a] * rpp.x + p.d2[a] * rp.x;
            dg[2 * a] = 2.0 * p.d1[a] * rp.x;
            dg[2 * a + 1] = 2.0 * p.d1[a] * rp.y;
        }
        let dk = dc / g - dg * (c / (g * g));
        (c, g, k, dc, dg, dk)
    }

    /// Strain energy `U = ∫ ½EA(ε − ε0)² + ½EI K² dx` [J].
    pub fn strain_energy(&self, q: &ElemVec) -> f64 {
        let s = &self.section;
        let mut u = 0.0;
        for p in &self.axial[..self.n_axial] {
            let (_, _, eps, _) = Self::axial_kin(p, q);
            u += 0.5 * p.w * s.ea * (eps - s.prestrain).powi(2);
        }
        for p in &self.bending[..self.n_bending] {
            let (_, _, k, _, _, _) = Self::bending_kin(p, q);
            u += 0.5 * p.w * s.ei * k * k;
        }
        u
    }

    /// Axial force `N = EA(ε − ε0)` [N] at `x` (elastic part).
    pub fn axial_force(&self, q: &ElemVec, x: f64) -> f64 {
        let rp = combine(&shape_d1(self.length, x), q);
        self.section.ea * (rp.norm() - 1.0 - self.section.prestrain)
    }

    /// Dissipated power of the material damping `∫ d_ε ε̇² + d_K K̇² dx` [W].
    pub fn damping_power(&self, q: &ElemVec, qd: &ElemVec) -> f64 {
        let s = &self.section;
        let mut pw = 0.0;
        if s.damping_axial != 0.0 {
            // ε̇ = u·ṙ' (`∂ε/∂q = s' ⊗ u`), without forming the 8-vector
            for p in &self.axial[..self.n_axial] {
                let rp = combine(&p.d1, q);
                let eps_dot = rp.dot(&combine(&p.d1, qd)) / rp.norm();
                pw += p.w * s.damping_axial * eps_dot * eps_dot;
            }
        }
        if s.damping_bending != 0.0 {
            for p in &self.bending[..self.n_bending] {
                let (_, _, _, _, _, dk) = Self::bending_kin(p, q);
                pw += p.w * s.damping_bending * dk.dot(qd).powi(2);
            }
        }
        pw
    }

    /// Internal force `Q = ∫ N ∂ε/∂q + M ∂K/∂q dx` [N] (elastic plus material damping at the
    /// velocities `qd`), written into `f`; returns the strain energy [J].
    ///
    /// The gradients are never formed as 8-vectors: with `∂ε/∂r'_a = s'_a u`
    /// (`u = r'/|r'|`) and `∂K/∂q_a = s'_a ∂K/∂r' + s''_a ∂K/∂r''`, where
    /// `∂K/∂r' = (r''_y, −r''_x)/g − 2c r'/g²` and `∂K/∂r'' = (−r'_y, r'_x)/g`
    /// (`c = r' × r''`, `g = r'·r'`), every point adds `s'_a A + s''_a B` to node block `a`
    /// with two 2-vectors `A`, `B` (the same sums as [`Self::axial_kin`] and
    /// [`Self::bending_kin`]; checked against them and against ∇U in the element tests).
    pub fn internal_force(&self, q: &ElemVec, qd: &ElemVec, f: &mut ElemVec) -> f64 {
        let s = &self.section;
        let mut u = 0.0;
        let mut fa = [Vector2::<f64>::zeros(); 4];
        for p in &self.axial[..self.n_axial] {
            let rp = combine(&p.d1, q);
            let len = rp.norm();
            let uvec = rp / len;
            let strain = len - 1.0 - s.prestrain;
            let mut n = s.ea * strain;
            if s.damping_axial != 0.0 {
                n += s.damping_axial * uvec.dot(&combine(&p.d1, qd));
            }
            let a = (p.w * n) * uvec;
            for (block, d1) in fa.iter_mut().zip(&p.d1) {
                *block += *d1 * a;
            }
            u += 0.5 * p.w * s.ea * strain * strain;
        }
        for p in &self.bending[..self.n_bending] {
            let rp = combine(&p.d1, q);
            let rpp = combine(&p.d2, q);
            let c = rp.x * rpp.y - rp.y * rpp.x;
            let inv_g = 1.0 / rp.dot(&rp);
            let k = c * inv_g;
            let dk1 = Vector2::new(rpp.y, -rpp.x) * inv_g - (2.0 * k * inv_g) * rp;
            let dk2 = Vector2::new(-rp.y, rp.x) * inv_g;
            let mut m = s.ei * k;
            if s.damping_bending != 0.0 {
                m += s.damping_bending
                    * (dk1.dot(&combine(&p.d1, qd)) + dk2.dot(&combine(&p.d2, qd)));
            }
            let (a, b) = ((p.w * m) * dk1, (p.w * m) * dk2);
            for (block, (d1, d2)) in fa.iter_mut().zip(p.d1.iter().zip(&p.d2)) {
                *block += *d1 * a + *d2 * b;
            }
            u += 0.5 * p.w * s.ei * k * k;
        }
        for (i, block) in fa.iter().enumerate() {
            f[2 * i] = block.x;
            f[2 * i + 1] = block.y;
        }
        u
    }

    // -----------------------------------------------------------------------------------------
    // Tangent
    // -----------------------------------------------------------------------------------------

    /// Internal force, tangent stiffness `K = ∂Q/∂q` [N/m] and damping matrix `C = ∂Q/∂q̇`
    /// [N s/m] (exact derivatives, including the geometric and velocity-dependent terms);
    /// returns the strain energy [J].
    ///
    /// Every term is accumulated in 2×2 node blocks (issue 12 item 2, session 29): the
    /// coordinates of node vector `a` enter `r'` with `s'_a` and `r''` with `s''_a`, so
    /// * axial: `∂ε/∂q_a = s'_a u`, and every axial matrix is `(s' s'ᵀ) ⊗ B` for a 2×2 block
    ///   `B` per point (blocks `(j, i)` equal blocks `(i, j)`);
    /// * bending (`K = c/g`, `c = r' × r''`, `g = r'·r'`): `∂K/∂q_a = s'_a P + s''_a Q` with
    ///   `P = ∂K/∂r' = J r''/g − 2c r'/g²`, `Q = ∂K/∂r'' = Jᵀ r'/g` (`J = [[0, 1], [−1, 0]]`),
    ///   and the Hessian of `½ EI K²` has the blocks
    ///   `s'_a s'_b M11 + s'_a s''_b M12 + s''_a s'_b M12ᵀ + s''_a s''_b M22` with
    ///   `M11 = EI P Pᵀ + M H11`, `M12 = EI P Qᵀ + M H12`, `M22 = EI Q Qᵀ` (`M = EI K`),
    ///   `H11 = ∂²K/∂r'² = −2 (J r'' r'ᵀ + r' (J r'')ᵀ)/g² − 2c I/g² + 8c r' r'ᵀ/g³`,
    ///   `H12 = ∂²K/∂r'∂r'' = J/g − 2 r' (Jᵀ r')ᵀ/g²` (`∂²K/∂r''² = 0`); `M11`, `M22` are
    ///   symmetric, so blocks `(j, i)` are the transposes of blocks `(i, j)`.
    ///
    /// Only blocks `j ≥ i` are accumulated. With bending damping the bending terms take the
    /// 8×8 path ([`Self::add_curvature_hessian`]).
    pub fn internal_force_tangent(
        &self,
        q: &ElemVec,
        qd: &ElemVec,
        f: &mut ElemVec,
        k: &mut ElemMat,
        c: &mut ElemMat,
    ) -> f64 {
        let s = &self.section;
        let mut u = 0.0;
        let damped_axial = s.damping_axial != 0.0;
        let damped_bending = s.damping_bending != 0.0;
        let mut fa = [Vector2::<f64>::zeros(); 4];
        // axial blocks (mirrored as they are) and bending blocks (mirrored transposed)
        let (mut kb, mut cb) = ([[Matrix2::zeros(); 4]; 4], [[Matrix2::zeros(); 4]; 4]);
        let mut kbb = [[Matrix2::zeros(); 4]; 4];
        for p in &self.axial[..self.n_axial] {
            let rp = combine(&p.d1, q);
            let len = rp.norm();
            let uvec = rp / len;
            let strain = len - 1.0 - s.prestrain;
            let mut n = s.ea * strain;
            let rpd = if damped_axial {
                let rpd = combine(&p.d1, qd);
                n += s.damping_axial * uvec.dot(&rpd);
                rpd
            } else {
                Vector2::zeros()
            };
            let a = (p.w * n) * uvec;
            for (block, d1) in fa.iter_mut().zip(&p.d1) {
                *block += *d1 * a;
            }
            u += 0.5 * p.w * s.ea * strain * strain;
            // ∂²ε/∂q_a∂q_b = s'_a s'_b (I − u uᵀ)/|r'|
            let uu = uvec * uvec.transpose();
            let proj = (Matrix2::identity() - uu) / len;
            let mut b = (p.w * s.ea) * uu + (p.w * n) * proj;
            if damped_axial {
                // ∂ε̇/∂q = q̇ᵀ ∂²ε = s' ⊗ (P ṙ')
                b += (p.w * s.damping_axial) * uvec * (proj * rpd).transpose();
                let bc = (p.w * s.damping_axial) * uu;
                for i in 0..4 {
                    for j in i..4 {
                        cb[i][j] += (p.d1[i] * p.d1[j]) * bc;
                    }
                }
            }
            for i in 0..4 {
                for j in i..4 {
                    kb[i][j] += (p.d1[i] * p.d1[j]) * b;
                }
            }
        }
        if !damped_bending {
            for p in &self.bending[..self.n_bending] {
                let rp = combine(&p.d1, q);
                let rpp = combine(&p.d2, q);
                let cv = rp.x * rpp.y - rp.y * rpp.x;
                let inv_g = 1.0 / rp.dot(&rp);
                let kv = cv * inv_g;
                let jrpp = Vector2::new(rpp.y, -rpp.x);
                let jtrp = Vector2::new(-rp.y, rp.x);
                let pv = jrpp * inv_g - (2.0 * kv * inv_g) * rp;
                let qv = jtrp * inv_g;
                let m = s.ei * kv;
                let (a, b) = ((p.w * m) * pv, (p.w * m) * qv);
                for (block, (d1, d2)) in fa.iter_mut().zip(p.d1.iter().zip(&p.d2)) {
                    *block += *d1 * a + *d2 * b;
                }
                u += 0.5 * p.w * s.ei * kv * kv;
                let (outer, scale) = (p.w * s.ei, p.w * m);
                let inv_g2 = inv_g * inv_g;
                let h11 = (-2.0 * inv_g2) * (jrpp * rp.transpose() + rp * jrpp.transpose())
                    + (8.0 * cv * inv_g2 * inv_g) * rp * rp.transpose()
                    - Matrix2::from_diagonal_element(2.0 * cv * inv_g2);
                let h12 =
                    Matrix2::new(0.0, inv_g, -inv_g, 0.0) - (2.0 * inv_g2) * rp * jtrp.transpose();
                let m11 = outer * pv * pv.transpose() + scale * h11;
                let m12 = outer * pv * qv.transpose() + scale * h12;
                let m21 = m12.transpose();
                let m22 = outer * qv * qv.transpose();
                for i in 0..4 {
                    let (d1i, d2i) = (p.d1[i], p.d2[i]);
                    let (r1, r2) = (d1i * m11 + d2i * m21, d1i * m12 + d2i * m22);
                    for j in i..4 {
                        kbb[i][j] += p.d1[j] * r1 + p.d2[j] * r2;
                    }
                }
            }
        }
        for (i, block) in fa.iter().enumerate() {
            f[2 * i] = block.x;
            f[2 * i + 1] = block.y;
        }
        for i in 0..4 {
            for j in i..4 {
                let kij = kb[i][j] + kbb[i][j];
                k.fixed_view_mut::<2, 2>(2 * i, 2 * j).copy_from(&kij);
                c.fixed_view_mut::<2, 2>(2 * i, 2 * j).copy_from(&cb[i][j]);
                if j > i {
                    let kji = kb[i][j] + kbb[i][j].transpose();
                    k.fixed_view_mut::<2, 2>(2 * j, 2 * i).copy_from(&kji);
                    c.fixed_view_mut::<2, 2>(2 * j, 2 * i).copy_from(&cb[i][j]);
                }
            }
        }
        if damped_bending {
            for p in &self.bending[..self.n_bending] {
                let (cv, g, kv, dc, dg, dk) = Self::bending_kin(p, q);
                let k_dot = dk.dot(qd);
                let m = s.ei * kv + s.damping_bending * k_dot;
                *f += (p.w * m) * dk;
                u += 0.5 * p.w * s.ei * kv * kv;
                Self::add_curvature_hessian(p, cv, g, &dc, &dg, p.w * s.ei, p.w * m, k);
                let mut h = ElemMat::zeros();
                Self::add_curvature_hessian(p, cv, g, &dc, &dg, 0.0, 1.0, &mut h);
                let dk_dot = h * qd;
                k.ger(p.w * s.damping_bending, &dk, &dk_dot, 1.0);
                c.ger(p.w * s.damping_bending, &dk, &dk, 1.0);
            }
        }
        u
    }

    /// Adds `outer · ∂K ∂Kᵀ + scale · ∂²K/∂q²` to `out`, for `K = c/g`:
    /// `∂²K = ∂²c/g − (∂c ∂gᵀ + ∂g ∂cᵀ)/g² − c ∂²g/g² + 2c ∂g ∂gᵀ/g³`, with
    /// `∂²c_ab = s'_a s''_b J + s''_a s'_b Jᵀ` (`J = [[0, 1], [−1, 0]]`) and `∂²g_ab = 2 s'_a s'_b I`.
    /// With `∂K = ∂c/g − c ∂g/g²` every rank-one term is `A ∂c ∂cᵀ + B (∂c ∂gᵀ + ∂g ∂cᵀ) +
    /// C ∂g ∂gᵀ = ∂c ⊗ (A ∂c + B ∂g) + ∂g ⊗ (B ∂c + C ∂g)`: two rank-one updates instead of four.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn add_curvature_hessian(
        p: &Point,
        c: f64,
        g: f64,
        dc: &ElemVec,
        dg: &ElemVec,
        outer: f64,
        scale: f64,
        out: &mut ElemMat,
    ) {
        let inv_g = 1.0 / g;
        let inv_g2 = inv_g * inv_g;
        for b in 0..4 {
            for a in 0..4 {
                // s'_a s''_b J + s''_a s'_b Jᵀ: off-diagonal entries of the 2×2 block
                let x = scale * inv_g * (p.d1[a] * p.d2[b] - p.d2[a] * p.d1[b]);
                let diag = -2.0 * scale * c * inv_g2 * p.d1[a] * p.d1[b];
                out[(2 * a, 2 * b)] += diag;
                out[(2 * a + 1, 2 * b + 1)] += diag;
                out[(2 * a, 2 * b + 1)] += x;
                out[(2 * a + 1, 2 * b)] -= x;
            }
        }
        let inv_g3 = inv_g2 * inv_g;
        let ca = outer * inv_g2;
        let cb = -outer * c * inv_g3 - scale * inv_g2;
        let cc = outer * c * c * inv_g2 * inv_g2 + 2.0 * scale * c * inv_g3;
        out.ger(1.0, dc, &(ca * dc + cb * dg), 1.0);
        out.ger(1.0, dg, &(cb * dc + cc * dg), 1.0);
    }

    /// Strain quantities at a point (for tests and outputs): `(ε, K)`.
    pub fn strains_at(&self, q: &ElemVec, x: f64) -> (f64, f64) {
        let p = Point {
            w: 0.0,
            d1: shape_d1(self.length, x),
            d2: shape_d2(self.length, x),
        };
        let kin = self.kinematics(&p, q);
        (kin.eps, kin.curv)
    }

    fn kinematics(&self, p: &Point, q: &ElemVec) -> Kinematics {
        let (_, _, eps, de) = Self::axial_kin(p, q);
        let (_, _, curv, _, _, dk) = Self::bending_kin(p, q);
        Kinematics { de, dk, eps, curv }
    }

    /// `(∂ε/∂q, ∂K/∂q)` at `x` (for tests).
    pub fn strain_gradients_at(&self, q: &ElemVec, x: f64) -> (ElemVec, ElemVec) {
        let p = Point {
            w: 0.0,
            d1: shape_d1(self.length, x),
            d2: shape_d2(self.length, x),
        };
        let kin = self.kinematics(&p, q);
        (kin.de, kin.dk)
    }
}

// ---------------------------------------------------------------------------------------------
// Axially moving (ALE) terms
// ---------------------------------------------------------------------------------------------
//
// Pechstein & Gerstmayr, "A Lagrange-Eulerian formulation of an axially moving beam based on
// the absolute nodal coordinate formulation", Multibody Syst. Dyn. 30 (2013) 343-358 (design
// note "ale", prototype `scripts/ale_prototype.py`): the mesh coordinate `x` is the reference
// arc length shifted by the belt travel `s(t)` (the material point `X` sits at `x = X + s`,
// `v = ṡ`), `r(x, t) = S(x) q(t)`. Material velocity `S q̇ + v r'`, material acceleration
// `S q̈ + v̇ r' + 2 v S' q̇ + v² r''`, material strain rate `ε̇ + v ε'`.

/// The constant band matrices of the axially moving cable, for elements of length `l`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AleBand {
    /// Transport matrix `G = ρA ∫ Sᵀ S' dx` [kg/m · m] (8×8): `G q` is `ρA ∫ Sᵀ r' dx`. Not
    /// symmetric: `G + Gᵀ = ρA [Sᵀ S]₀ᴸ`, which cancels between neighbours round a closed
    /// loop (the assembled `G` is skew).
    pub g: ElemMat,
    /// Convective stiffness `H = ρA ∫ S'ᵀ S' dx` [kg/m] (8×8, symmetric): the centripetal term
    /// `ρA ∫ Sᵀ r'' dx v²` integrated by parts, `−v² H q` (the boundary terms `[Sᵀ r']₀ᴸ`
    /// cancel between neighbours of a C¹ field round a closed loop).
    pub h: ElemMat,
}

/// [`AleBand`] of elements of length `l` [m] and mass per length `rho_a` [kg/m], integrated
/// with 4 Gauss points (exact: the integrands are polynomials of degree 5 and 4).
pub fn ale_band(l: f64, rho_a: f64) -> AleBand {
    let (mut g4, mut h4) = (
        nalgebra::Matrix4::<f64>::zeros(),
        nalgebra::Matrix4::zeros(),
    );
    for &(p, w) in gauss_legendre(4) {
        let x = 0.5 * (p + 1.0) * l;
        let s = nalgebra::Vector4::from(shape_functions(l, x));
        let d = nalgebra::Vector4::from(shape_d1(l, x));
        let wt = rho_a * w * 0.5 * l;
        g4 += wt * s * d.transpose();
        h4 += wt * d * d.transpose();
    }
    let (mut g, mut h) = (ElemMat::zeros(), ElemMat::zeros());
    for a in 0..4 {
        for b in 0..4 {
            for i in 0..2 {
                g[(2 * a + i, 2 * b + i)] = g4[(a, b)];
                h[(2 * a + i, 2 * b + i)] = h4[(a, b)];
            }
        }
    }
    AleBand { g, h }
}

/// Belt travel rates of the axially moving cable: `v = ṡ` [m/s of reference length] and its
/// rate `v̇` [m/s²].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AleRates {
    /// Belt speed `v` [m/s] (reference length per second).
    pub v: f64,
    /// Belt acceleration `v̇` [m/s²].
    pub v_dot: f64,
}

/// Partial derivatives of the ALE inertia force of one element, written by
/// [`ale_inertia_into`]; the mass part `∂f/∂q̈ = M` is the element's constant mass.
#[derive(Clone, Debug, PartialEq)]
pub struct AleInertiaTangent {
    /// `∂f/∂q = v̇ G − v² H` [N/m].
    pub k: ElemMat,
    /// `∂f/∂q̇ = 2 v G` [N s/m].
    pub c: ElemMat,
    /// `∂f/∂v = 2 G q̇ − 2 v H q` [N s/m].
    pub dv: ElemVec,
    /// `∂f/∂v̇ = G q` [kg].
    pub dv_dot: ElemVec,
}

impl Default for AleInertiaTangent {
    fn default() -> Self {
        Self {
            k: ElemMat::zeros(),
            c: ElemMat::zeros(),
            dv: ElemVec::zeros(),
            dv_dot: ElemVec::zeros(),
        }
    }
}

/// Inertia force of an element of the axially moving cable,
/// `f = ρA ∫ Sᵀ (S q̈ + v̇ r' + 2 v S' q̇ + v² r'') dx = M q̈ + v̇ G q + 2 v G q̇ − v² H q` [N]
/// (the last term by parts, see [`AleBand::h`]), written into `f`; with `tangent`, its partial
/// derivatives. `m` is the element's mass matrix ([`consistent_mass`]).
#[allow(clippy::too_many_arguments)]
pub fn ale_inertia_into(
    m: &ElemMat,
    band: &AleBand,
    q: &ElemVec,
    qd: &ElemVec,
    qdd: &ElemVec,
    rates: AleRates,
    f: &mut ElemVec,
    tangent: Option<&mut AleInertiaTangent>,
) {
    let AleRates { v, v_dot } = rates;
    let gq = band.g * q;
    let gqd = band.g * qd;
    let hq = band.h * q;
    *f = m * qdd + v_dot * gq + (2.0 * v) * gqd - (v * v) * hq;
    if let Some(t) = tangent {
        t.k = v_dot * band.g - (v * v) * band.h;
        t.c = (2.0 * v) * band.g;
        t.dv = 2.0 * gqd - (2.0 * v) * hq;
        t.dv_dot = gq;
    }
}

impl AncfCable2d {
    /// Convective part of the axial material damping of the axially moving cable: the material
    /// strain rate is `ε̇ + v ε'` with `ε' = u·r''` (`u = r'/|r'|`), so the damping force
    /// `∫ d_ε (ε̇ + v ε') ∂ε/∂q dx` of the moving belt is [`Self::internal_force`]'s plus
    /// `f_v = ∫ d_ε v (u·r'') ∂ε/∂q dx` [N], which this adds to `f` (same axial points).
    ///
    /// With `k`, `dv`: adds `∂f_v/∂q` [N/m] to `k` and writes `∂f_v/∂v` [N s/m] into `dv`
    /// (`f_v` does not depend on `q̇`: the damping matrix is [`Self::internal_force_tangent`]'s).
    /// Per axial point, with `∂ε/∂q_a = s'_a u`, `P = (I − u uᵀ)/|r'|`, `∂u/∂r' = P`,
    /// `∂(u·r'')/∂r' = P r''` and `∂(u·r'')/∂r'' = u`, node block `(a, b)` gains
    /// `w d_ε v [s'_a s'_b (u (P r'')ᵀ + (u·r'') P) + s'_a s''_b u uᵀ]` (not symmetric).
    ///
    /// The bending damping's convective rate `v K'` is not included: the ALE belt refuses
    /// bending damping.
    pub fn convective_damping_into(
        &self,
        q: &ElemVec,
        v: f64,
        f: &mut ElemVec,
        tangent: Option<(&mut ElemMat, &mut ElemVec)>,
    ) {
        self.convective_kernel(q, v, f, tangent, (true, false));
    }

    /// Coefficient `c(v)` [N s² · m/s … = N m] of [`Self::convective_upwinding_into`] and its
    /// derivative `dc/dv`: `c = d_ε v α` with the streamline length
    /// `α = sign(v) λ L / (L + 2λ)`, `λ = d_ε |v| / EA` (the stabilisation parameter
    /// `τ = 1 / (2|λ|/L + 1)` of the reaction–transport equation `ε + λ ε' = N/EA`), so
    /// `c = (d_ε v)² L / (EA L + 2 d_ε |v|)` and
    /// `dc/dv = 2 d_ε² L v (EA L + d_ε |v|) / (EA L + 2 d_ε |v|)²`. Zero without damping.
    pub fn upwinding_coefficient(&self, v: f64) -> (f64, f64) {
        let (d, ea, l) = (self.section.damping_axial, self.section.ea, self.length);
        let den = ea * l + 2.0 * d * v.abs();
        if d == 0.0 || den <= 0.0 {
            return (0.0, 0.0);
        }
        let c = (d * v).powi(2) * l / den;
        let dc = 2.0 * d * d * l * v * (ea * l + d * v.abs()) / (den * den);
        (c, dc)
    }

    /// Streamline-upwind (Petrov–Galerkin) weighting of the convective damping of the axially
    /// moving cable. On the fixed mesh the steady axial force `EA ε + d_ε v ε'` makes the
    /// strain obey the transport `ε + λ ε' = N/EA` (`λ = d_ε v/EA`); plain Galerkin (test
    /// `δε`) carries a spurious mode upstream from every sharp change (the wrap entries), which
    /// grows by about 1.8 per element toward it at `EA L/(d_ε v) ≈ 3` and reads as a zero-mean
    /// strain variation inside the elements. Testing the convective damping term with
    /// `δε + α δε'` instead adds `f_u = ∫ c ε' ∂ε'/∂q dx` [N] (`c` from
    /// [`Self::upwinding_coefficient`], `ε' = u·r''`), which this adds to `f` (same axial
    /// points). It vanishes where the strain is uniform (a free span in steady running).
    ///
    /// With `k`, `dv`: adds `∂f_u/∂q` [N/m] to `k` and writes `∂f_u/∂v` [N s/m] into `dv` (`f_u` does not
    /// depend on `q̇`). With `∂ε'/∂r' = P r''`, `∂ε'/∂r'' = u` (`P = (I − u uᵀ)/|r'|`) and
    /// `∂²ε'/∂r'² = −(r'' uᵀ + u r''ᵀ + ε' I)/|r'|² + 3 ε' u uᵀ/|r'|²`,
    /// `∂²ε'/∂r'∂r'' = P`, `∂²ε'/∂r''² = 0`.
    pub fn convective_upwinding_into(
        &self,
        q: &ElemVec,
        v: f64,
        f: &mut ElemVec,
        tangent: Option<(&mut ElemMat, &mut ElemVec)>,
    ) {
        self.convective_kernel(q, v, f, tangent, (false, true));
    }

    /// [`Self::convective_damping_into`] and [`Self::convective_upwinding_into`] together (one
    /// pass over the axial points; the ALE belt's residual and tangent): the convective damping
    /// with the streamline-upwind test `δε + α δε'`. `dv` is written, `f` and `k` added to.
    pub fn convective_damping_upwinded_into(
        &self,
        q: &ElemVec,
        v: f64,
        f: &mut ElemVec,
        tangent: Option<(&mut ElemMat, &mut ElemVec)>,
    ) {
        self.convective_kernel(q, v, f, tangent, (true, true));
    }

    /// The convective damping's Galerkin part (`parts.0`) and its upwinding (`parts.1`): adds
    /// the force to `f` and `∂f/∂q` to `k`, writes `∂f/∂v` into `dv`.
    fn convective_kernel(
        &self,
        q: &ElemVec,
        v: f64,
        f: &mut ElemVec,
        tangent: Option<(&mut ElemMat, &mut ElemVec)>,
        (galerkin, upwind): (bool, bool),
    ) {
        let d = self.section.damping_axial;
        let (c, dc) = if upwind {
            self.upwinding_coefficient(v)
        } else {
            (0.0, 0.0)
        };
        let galerkin = galerkin && d != 0.0;
        let upwind = upwind && (c != 0.0 || dc != 0.0);
        let (mut fa, mut fv) = ([Vector2::<f64>::zeros(); 4], [Vector2::<f64>::zeros(); 4]);
        let mut kb = [[Matrix2::zeros(); 4]; 4];
        let want_tangent = tangent.is_some();
        if galerkin || upwind {
            for p in &self.axial[..self.n_axial] {
                let rp = combine(&p.d1, q);
                let rpp = combine(&p.d2, q);
                let len = rp.norm();
                let u = rp / len;
                let eps_x = u.dot(&rpp);
                let proj = (Matrix2::identity() - u * u.transpose()) / len;
                let g1 = proj * rpp;
                if galerkin {
                    let a = (p.w * d * v * eps_x) * u;
                    let av = (p.w * d * eps_x) * u;
                    for ((block, bv), d1) in fa.iter_mut().zip(fv.iter_mut()).zip(&p.d1) {
                        *block += *d1 * a;
                        *bv += *d1 * av;
                    }
                    if want_tangent {
                        let wv = p.w * d * v;
                        let b1 = wv * (u * g1.transpose() + eps_x * proj);
                        let b2 = wv * (u * u.transpose());
                        for (i, row) in kb.iter_mut().enumerate() {
                            for (j, blk) in row.iter_mut().enumerate() {
                                *blk += (p.d1[i] * p.d1[j]) * b1 + (p.d1[i] * p.d2[j]) * b2;
                            }
                        }
                    }
                }
                if upwind {
                    // ∂ε'/∂q_a = s'_a P r'' + s''_a u
                    let g: [Vector2<f64>; 4] = std::array::from_fn(|a| p.d1[a] * g1 + p.d2[a] * u);
                    let (wc, wd) = (p.w * c * eps_x, p.w * dc * eps_x);
                    for a in 0..4 {
                        fa[a] += wc * g[a];
                        fv[a] += wd * g[a];
                    }
                    if want_tangent {
                        let inv2 = 1.0 / (len * len);
                        let h11 = (-(rpp * u.transpose() + u * rpp.transpose())
                            - eps_x * Matrix2::identity()
                            + (3.0 * eps_x) * (u * u.transpose()))
                            * inv2;
                        let (wh, wp) = (wc * h11, wc * proj);
                        let wcc = p.w * c;
                        for (i, row) in kb.iter_mut().enumerate() {
                            let gi = wcc * g[i];
                            for (j, blk) in row.iter_mut().enumerate() {
                                *blk += gi * g[j].transpose()
                                    + (p.d1[i] * p.d1[j]) * wh
                                    + (p.d1[i] * p.d2[j] + p.d2[i] * p.d1[j]) * wp;
                            }
                        }
                    }
                }
            }
        }
        for (i, block) in fa.iter().enumerate() {
            f[2 * i] += block.x;
            f[2 * i + 1] += block.y;
        }
        if let Some((k, dv)) = tangent {
            for (i, block) in fv.iter().enumerate() {
                dv[2 * i] = block.x;
                dv[2 * i + 1] = block.y;
            }
            for (i, row) in kb.iter().enumerate() {
                for (j, blk) in row.iter().enumerate() {
                    let mut view = k.fixed_view_mut::<2, 2>(2 * i, 2 * j);
                    view += blk;
                }
            }
        }
    }

    /// Power of [`Self::convective_upwinding_into`]'s force at the rates `qd`,
    /// `q̇·f_u = ∫ c ε' ε̇' dx` [W] (booked with the material damping: zero in steady running on
    /// the fixed mesh).
    pub fn upwinding_power(&self, q: &ElemVec, qd: &ElemVec, v: f64) -> f64 {
        let (c, _) = self.upwinding_coefficient(v);
        if c == 0.0 {
            return 0.0;
        }
        let mut pw = 0.0;
        for p in &self.axial[..self.n_axial] {
            let rp = combine(&p.d1, q);
            let rpp = combine(&p.d2, q);
            let len = rp.norm();
            let u = rp / len;
            let eps_x = u.dot(&rpp);
            let proj = (Matrix2::identity() - u * u.transpose()) / len;
            let rate = (proj * rpp).dot(&combine(&p.d1, qd)) + u.dot(&combine(&p.d2, qd));
            pw += p.w * c * eps_x * rate;
        }
        pw
    }

    /// The axial material damping of the axially moving cable as [`Self::ale_damping_power`]
    /// (first) and its generalized force on the belt travel `s`, `−∫ d_ε (ε̇ + v ε') ε' dx` [N]
    /// (second; the part of the dissipated power that flows through the belt speed is `v` times
    /// minus it).
    pub fn ale_damping_terms(&self, q: &ElemVec, qd: &ElemVec, v: f64) -> (f64, f64) {
        let d = self.section.damping_axial;
        if d == 0.0 {
            return (0.0, 0.0);
        }
        let (mut pw, mut fs) = (0.0, 0.0);
        for p in &self.axial[..self.n_axial] {
            let rp = combine(&p.d1, q);
            let rpp = combine(&p.d2, q);
            let len = rp.norm();
            let eps_x = rp.dot(&rpp) / len;
            let rate = rp.dot(&combine(&p.d1, qd)) / len + v * eps_x;
            pw += p.w * d * rate * rate;
            fs -= p.w * d * rate * eps_x;
        }
        (pw, fs)
    }

    /// Dissipated power of the axial material damping of the axially moving cable,
    /// `∫ d_ε (ε̇ + v ε')² dx` [W] (bending damping excluded, see
    /// [`Self::convective_damping_into`]).
    pub fn ale_damping_power(&self, q: &ElemVec, qd: &ElemVec, v: f64) -> f64 {
        let d = self.section.damping_axial;
        if d == 0.0 {
            return 0.0;
        }
        let mut pw = 0.0;
        for p in &self.axial[..self.n_axial] {
            let rp = combine(&p.d1, q);
            let rate = rp.dot(&(combine(&p.d1, qd) + v * combine(&p.d2, q))) / rp.norm();
            pw += p.w * d * rate * rate;
        }
        pw
    }
}

// ---------------------------------------------------------------------------------------------
// The element trait
// ---------------------------------------------------------------------------------------------

/// Slots `[r0, r0', r1, r1']`.
const CABLE_SLOTS: &[Slot] = &[
    Slot::Position,
    Slot::Direction,
    Slot::Position,
    Slot::Direction,
];

impl Element<ELEMENT_COORDS> for AncfCable2d {
    fn layout(&self) -> Layout {
        Layout {
            dim: 2,
            slots: CABLE_SLOTS,
        }
    }

    fn constant_mass_matrix(&self) -> Option<&ElemMat> {
        Some(&self.mass)
    }

    fn mass_into(&self, _s: &ElementState<ELEMENT_COORDS>, m: &mut ElemMat) {
        *m = self.mass;
    }

    fn gravity_into(&self, _s: &ElementState<ELEMENT_COORDS>, g: &Vector3<f64>, f: &mut ElemVec) {
        *f = self.gravity(Vector2::new(g.x, g.y));
    }

    fn strain_energy_at(&self, s: &ElementState<ELEMENT_COORDS>) -> f64 {
        self.strain_energy(&s.q)
    }

    fn force_into(&self, s: &ElementState<ELEMENT_COORDS>, f: &mut ElemVec) -> f64 {
        self.internal_force(&s.q, &s.v, f)
    }

    fn tangent_into(
        &self,
        s: &ElementState<ELEMENT_COORDS>,
        f: &mut ElemVec,
        k: &mut ElemMat,
        c: Option<&mut ElemMat>,
    ) -> f64 {
        match c {
            Some(c) => self.internal_force_tangent(&s.q, &s.v, f, k, c),
            None => self.internal_force_tangent(&s.q, &s.v, f, k, &mut ElemMat::zeros()),
        }
    }

    fn damping_power_at(&self, s: &ElementState<ELEMENT_COORDS>) -> f64 {
        self.damping_power(&s.q, &s.v)
    }
}
