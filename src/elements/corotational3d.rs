//! Seed-003 element: two-node co-rotational 3D beam with Euler–Bernoulli or Timoshenko local
//! stiffness and three-point lumped inertia.
//!
//! Seed: Wang, Qi & Xu 2020, "A high-precision co-rotational formulation of 3D beam elements
//! for dynamic analysis of flexible multibody systems", CMAME 360:112701 (abstract only). The
//! formulation is that of `shared/reference/seed003-corotational-beam.md`: element frame and
//! local deformations after Crisfield 1990 / Battini & Pacoste 2002 (B.1), the small-deformation
//! stiffness used unchanged in the co-rotated frame (B.3), and inertia from three lumped masses
//! at the ends and the mid-point with Simpson weights 1/6, 2/3, 1/6 (B.4).
//!
//! **Nodes and coordinates.** A node carries a position `x` [m] and an orientation `R ∈ SO(3)`,
//! the rotation from the reference configuration (`R = I` there). The kernels take `R` as a
//! matrix; how it is stored (the model keeps unit quaternions and incremental rotation vectors)
//! is not their business. Element force vectors are ordered `[x1, θ1, x2, θ2]` (3 each): forces
//! on the positions (global components) and moments conjugate to a *body* spin `δW_i`
//! (`R_i → R_i exp(δW̃_i)`), i.e. `R_iᵀ` times the spatial moment. Tangents are derivatives with
//! respect to `[δx1, δW1, δx2, δW2]`; the model chains them with the tangent of its rotation
//! parameters ([`super::rotation::tangent_body`]). Velocities are `ẋ_i` and the body angular
//! velocities `Ω_i` (`Ṙ_i = R_i Ω̃_i`), accelerations `ẍ_i`, `Ω̇_i`.
//!
//! **Element frame** (B.1.1–3). `R0 = [e1⁰ e2⁰ e3⁰]`: reference chord and section axes. Current
//! chord `e1 = (x2 − x1)/l`; `q_i = R_i e2⁰`, `q = (q1 + q2)/2`, `e3 = e1 × q/|e1 × q|`,
//! `e2 = e3 × e1`, `Rr = [e1 e2 e3]`. Local deformations: `ū = l − l0` and
//! `θ̄_i = log(Rrᵀ R_i R0)` (torsion `θ̄_2x − θ̄_1x`, bending `θ̄_iy`, `θ̄_iz`). A rigid motion of
//! any size leaves all seven unchanged, so it produces neither strain nor force.
//!
//! The file follows the fixed order of every element: shape functions (and kinematics), mass,
//! internal forces, tangent; then the element trait (node frames from
//! [`super::node_frames`]).

use super::element::{Element, ElementState, Layout, Slot};
use super::quadrature::gauss_legendre;
use super::rotation::{
    log_so3, skew, tangent_spatial_inv, tangent_spatial_inv_t, tangent_spatial_inv_t_apply,
};
use nalgebra::{Matrix2, Matrix3, SMatrix, SVector, Vector2, Vector3};

/// Coordinates per node (position and rotation).
pub const NODE_DOFS: usize = 6;
/// Coordinates per element.
pub const ELEMENT_DOFS: usize = 12;
/// Element vector `[x1, θ1, x2, θ2]`.
pub type Vec12 = SVector<f64, ELEMENT_DOFS>;
/// Element matrix.
pub type Mat12 = SMatrix<f64, ELEMENT_DOFS, ELEMENT_DOFS>;
/// Derivatives by the reduced columns `[δx2, δw1, δw2]` (the δx1 columns are their negation).
type M3x9 = SMatrix<f64, 3, 9>;
type R9 = SMatrix<f64, 1, 9>;
type M9 = SMatrix<f64, 9, 9>;

/// Most inertia points of one element (consistent variant: 4 centre-line points and 2 × 3
/// section directors).
const MAX_POINTS: usize = 10;

/// Local small-deformation beam theory in the co-rotated frame (B.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Theory {
    /// Bending block `(2EI/l0) [[2, 1], [1, 2]]`.
    EulerBernoulli,
    /// Bending block `(EI/((1 + Φ) l0)) [[4 + Φ, 2 − Φ], [2 − Φ, 4 + Φ]]`,
    /// `Φ = 12 EI/(GA l0²)` (shear-deformable, statically condensed).
    Timoshenko,
}

/// How the kinetic energy of an element is integrated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MassModel {
    /// Three lumped masses (B.4): the end nodes and the mid-point, Simpson weights
    /// 1/6, 2/3, 1/6 of the element's mass and rotary inertia.
    Lumped,
    /// Consistent: the same kinematics integrated by Gauss–Legendre quadrature (4 points on the
    /// centre line, exact for a straight element; 2 points for the section rotary inertia).
    Consistent,
}

/// Section properties of a beam, as beam users give them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamSection {
    /// Axial stiffness `EA` [N].
    pub ea: f64,
    /// Shear stiffness for deflection along local y, including the shear coefficient [N].
    pub ga_y: f64,
    /// Shear stiffness for deflection along local z [N].
    pub ga_z: f64,
    /// Torsional stiffness `GJ` [N m²].
    pub gj: f64,
    /// Bending stiffness about local y (deflection along z) [N m²].
    pub ei_y: f64,
    /// Bending stiffness about local z (deflection along y) [N m²].
    pub ei_z: f64,
    /// Mass per length `ρA` [kg/m].
    pub rho_a: f64,
    /// Polar rotary inertia per length `ρJ_x` [kg m].
    pub rho_jx: f64,
    /// Rotary inertia per length about local y [kg m].
    pub rho_iy: f64,
    /// Rotary inertia per length about local z [kg m].
    pub rho_iz: f64,
}

impl BeamSection {
    /// Second moments of the section mass per length `E_kk = ∫ X_k² dm` along the section axes
    /// (the Euler tensor, `E = ½ tr(J) I − J`): `[½(Iy + Iz − Jx), ½(Jx + Iz − Iy),
    /// ½(Jx + Iy − Iz)]` [kg m]. The rotational kinetic energy of a section with directors
    /// `d_k` is `½ Σ E_kk |ḋ_k|²`, which equals `½ ωᵀ J ω`. A physical section has
    /// `E_kk ≥ 0` (`J_x = I_y + I_z` for a thin section gives `E_11 = 0`); the element clips
    /// negative values from rounded data at zero.
    pub fn euler_tensor(&self) -> Vector3<f64> {
        let (jx, iy, iz) = (self.rho_jx, self.rho_iy, self.rho_iz);
        Vector3::new(
            0.5 * (iy + iz - jx),
            0.5 * (jx + iz - iy),
            0.5 * (jx + iy - iz),
        )
    }
}

/// Configuration of an element's two nodes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nodes {
    /// Positions [m].
    pub x: [Vector3<f64>; 2],
    /// Rotations from the reference configuration.
    pub r: [Matrix3<f64>; 2],
}

/// Rates of an element's two nodes: `ẋ_i` [m/s] and `Ω_i` [rad/s] (or their time derivatives).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rates {
    /// Translational rates.
    pub x: [Vector3<f64>; 2],
    /// Body angular rates.
    pub w: [Vector3<f64>; 2],
}

impl Rates {
    /// From an element vector `[ẋ1, Ω1, ẋ2, Ω2]`.
    pub fn from_vec(v: &Vec12) -> Self {
        let b = |k: usize| Vector3::new(v[k], v[k + 1], v[k + 2]);
        Self {
            x: [b(0), b(6)],
            w: [b(3), b(9)],
        }
    }
}

/// A point of the kinetic-energy quadrature: `y = Σ_i α_i x_i + Σ_i R_i c_i` with weight `μ`.
/// Centre-line points carry mass (`μ` [kg], gravity acts on them); director points carry the
/// section's rotary inertia (`y` is a director, `μ` = a second moment `E_kk` times length
/// [kg m²]).
#[derive(Clone, Copy, Debug, PartialEq)]
struct InertiaPoint {
    alpha: [f64; 2],
    c: [Vector3<f64>; 2],
    mu: f64,
    mass: bool,
}

/// One element: reference geometry, local stiffness and inertia data.
#[derive(Clone, Debug)]
pub struct Corot3d {
    l0: f64,
    r0: Matrix3<f64>,
    k_axial: f64,
    k_torsion: f64,
    k_bend_y: Matrix2<f64>,
    k_bend_z: Matrix2<f64>,
    points: [InertiaPoint; MAX_POINTS],
    n_points: usize,
    end_mass: f64,
    end_inertia: Matrix3<f64>,
    bowing: bool,
}

/// Bowing (shallow-arch) factor of one bending plane: the mean axial strain that the cubic
/// Hermite centre line with local end rotations `θ1`, `θ2` adds to the chord strain,
/// `b = (2θ1² − θ1θ2 + 2θ2²)/30` [1] (Crisfield 1991, *Non-linear finite element analysis of
/// solids and structures* vol. 1, §7 shallow-arch strain `∫ ½ w'² dx / L` of the cubic), its
/// gradient `[∂b/∂θ1, ∂b/∂θ2]` and (constant) Hessian `[[4, −1], [−1, 4]]/30`. For a circular
/// arc of angle `Δφ` (`θ1 = −θ2 = Δφ/2`) `b = Δφ²/24`, which cancels the chord's
/// `chord/arc − 1 ≈ −Δφ²/24`.
pub fn bowing(t1: f64, t2: f64) -> (f64, Vector2<f64>) {
    (
        (2.0 * t1 * t1 - t1 * t2 + 2.0 * t2 * t2) / 30.0,
        Vector2::new(4.0 * t1 - t2, 4.0 * t2 - t1) / 30.0,
    )
}

/// Hessian of [`bowing`] with respect to `(θ1, θ2)` (constant).
const BOWING_HESSIAN: [[f64; 2]; 2] = [[4.0 / 30.0, -1.0 / 30.0], [-1.0 / 30.0, 4.0 / 30.0]];

/// Reference section frame `R0 = [e1 e2 e3]` of a chord from `x1` to `x2`: `e1` along the
/// chord, `e2 = z_hint × e1/|…|`, `e3 = e1 × e2` (the local z axis is the hint made
/// perpendicular to the chord). `None` if the chord is degenerate or parallel to the hint.
pub fn reference_frame(
    x1: &Vector3<f64>,
    x2: &Vector3<f64>,
    z_hint: &Vector3<f64>,
) -> Option<Matrix3<f64>> {
    let d = x2 - x1;
    let l = d.norm();
    if !l.is_finite() || l <= 0.0 {
        return None;
    }
    let e1 = d / l;
    let y = z_hint.cross(&e1);
    let n = y.norm();
    if n < 1e-8 * z_hint.norm().max(f64::MIN_POSITIVE) {
        return None;
    }
    let e2 = y / n;
    Some(Matrix3::from_columns(&[e1, e2, e1.cross(&e2)]))
}

// ---------------------------------------------------------------------------------------------
// Shape functions and kinematics
// ---------------------------------------------------------------------------------------------

/// Cubic Hermite basis on `ξ ∈ [0, 1]`: `[h00, h10, h01, h11]`, so that a curve with end points
/// `x1`, `x2` and end tangents `l0 t1`, `l0 t2` is
/// `y(ξ) = h00 x1 + h01 x2 + l0 (h10 t1 + h11 t2)`. At ξ = ½: `[½, 1/8, ½, −1/8]`.
pub fn hermite(xi: f64) -> [f64; 4] {
    let (x2, x3) = (xi * xi, xi * xi * xi);
    [
        1.0 - 3.0 * x2 + 2.0 * x3,
        xi - 2.0 * x2 + x3,
        3.0 * x2 - 2.0 * x3,
        x3 - x2,
    ]
}

/// Derivatives `dh/dξ` of the Hermite basis [`hermite`] (same order), e.g. the tangent of a
/// predicted centre line: `y'(ξ) = h00' x1 + h01' x2 + l0 (h10' t1 + h11' t2)`.
pub fn hermite_d1(xi: f64) -> [f64; 4] {
    [
        6.0 * xi * (xi - 1.0),
        1.0 - 4.0 * xi + 3.0 * xi * xi,
        6.0 * xi * (1.0 - xi),
        xi * (3.0 * xi - 2.0),
    ]
}

/// The co-rotated frame and the local deformations of a configuration.
#[derive(Clone, Copy, Debug)]
pub struct Local {
    /// Chord length [m].
    pub l: f64,
    /// Element frame `Rr = [e1 e2 e3]`.
    pub rr: Matrix3<f64>,
    /// `q_i = R_i e2⁰` (global).
    pub q: [Vector3<f64>; 2],
    /// Local components `(q·e1, q·e2)` of `q = (q1 + q2)/2` (`q·e3 = 0`).
    pub qm: Vector2<f64>,
    /// Elongation `ū = l − l0` [m].
    pub u: f64,
    /// Local rotations `θ̄_i = log(Rrᵀ R_i R0)` [rad].
    pub theta: [Vector3<f64>; 2],
}

impl Corot3d {
    /// An element of reference length `l0` [m] and reference section frame `r0` (columns: chord
    /// direction, local y, local z; see [`reference_frame`]).
    pub fn new(
        l0: f64,
        r0: Matrix3<f64>,
        s: &BeamSection,
        theory: Theory,
        mass: MassModel,
    ) -> Self {
        let bend = |ei: f64, ga: f64| -> Matrix2<f64> {
            match theory {
                Theory::EulerBernoulli => Matrix2::new(2.0, 1.0, 1.0, 2.0) * (2.0 * ei / l0),
                Theory::Timoshenko => {
                    let phi = 12.0 * ei / (ga * l0 * l0);
                    Matrix2::new(4.0 + phi, 2.0 - phi, 2.0 - phi, 4.0 + phi)
                        * (ei / ((1.0 + phi) * l0))
                }
            }
        };
        let t0 = r0.column(0).into_owned();
        let jsec = Matrix3::from_diagonal(&Vector3::new(s.rho_jx, s.rho_iy, s.rho_iz));
        let euler = s.euler_tensor();
        let m = s.rho_a * l0;
        let zero = InertiaPoint {
            alpha: [0.0; 2],
            c: [Vector3::zeros(); 2],
            mu: 0.0,
            mass: false,
        };
        let mut points = [zero; MAX_POINTS];
        let mut n = 0;
        let mut push = |p: InertiaPoint| {
            if p.mu != 0.0 {
                points[n] = p;
                n += 1;
            }
        };
        // A centre-line point at ξ with weight w (fraction of the element).
        let centre = |xi: f64, w: f64| {
            let h = hermite(xi);
            InertiaPoint {
                alpha: [h[0], h[2]],
                c: [t0 * (l0 * h[1]), t0 * (l0 * h[3])],
                mu: w * m,
                mass: true,
            }
        };
        // Director k of the section at ξ (linear interpolation of the nodal directors).
        let director = |xi: f64, w: f64, k: usize| {
            let d = r0.column(k).into_owned();
            InertiaPoint {
                alpha: [0.0; 2],
                c: [d * (1.0 - xi), d * xi],
                mu: w * l0 * euler[k].max(0.0),
                mass: false,
            }
        };
        let (end_mass, end_inertia) = match mass {
            MassModel::Lumped => {
                push(centre(0.5, 2.0 / 3.0));
                for k in 0..3 {
                    push(director(0.5, 2.0 / 3.0, k));
                }
                (m / 6.0, r0 * jsec * r0.transpose() * (l0 / 6.0))
            }
            MassModel::Consistent => {
                for &(g, w) in gauss_legendre(4) {
                    push(centre(0.5 * (g + 1.0), 0.5 * w));
                }
                for &(g, w) in gauss_legendre(2) {
                    for k in 0..3 {
                        push(director(0.5 * (g + 1.0), 0.5 * w, k));
                    }
                }
                (0.0, Matrix3::zeros())
            }
        };
        Self {
            l0,
            r0,
            k_axial: s.ea / l0,
            k_torsion: s.gj / l0,
            k_bend_y: bend(s.ei_y, s.ga_z),
            k_bend_z: bend(s.ei_z, s.ga_y),
            points,
            n_points: n,
            end_mass,
            end_inertia,
            bowing: false,
        }
    }

    /// The same element with (`true`) or without (`false`, the default and the seed's
    /// formulation) the bowing term in the axial strain: `ε = ū/l0 + b(θ̄_1y, θ̄_2y) +
    /// b(θ̄_1z, θ̄_2z)` with `b` of [`bowing`]. The chord measures the elongation of a straight
    /// element; a belt wrapped on a pulley is an arc between its nodes, whose chord is short by
    /// `Δφ²/24` of its length, which the term restores (issue 13: 36 elements on a drive of
    /// EA = 5e4 N lost 170 N of a 200 N tension without it).
    pub fn with_bowing(mut self, on: bool) -> Self {
        self.bowing = on;
        self
    }

    /// Whether the bowing term is on (see [`Corot3d::with_bowing`]).
    pub fn has_bowing(&self) -> bool {
        self.bowing
    }

    /// Effective elongation `ū + l0 (b_y + b_z)` [m] of a configuration's local deformations
    /// (`ū` alone without the bowing term).
    pub fn effective_elongation(&self, loc: &Local) -> f64 {
        if !self.bowing {
            return loc.u;
        }
        let [t1, t2] = loc.theta;
        loc.u + self.l0 * (bowing(t1.y, t2.y).0 + bowing(t1.z, t2.z).0)
    }

    /// Axial force `N = EA ε` [N] of a configuration (with the bowing term if it is on).
    pub fn axial_force(&self, n: &Nodes) -> f64 {
        self.k_axial * self.effective_elongation(&self.local(n))
    }

    /// Reference length [m].
    pub fn length(&self) -> f64 {
        self.l0
    }

    /// Reference section frame `R0`.
    pub fn reference_frame(&self) -> &Matrix3<f64> {
        &self.r0
    }

    /// Element frame and local deformations (B.1.2–4).
    pub fn local(&self, n: &Nodes) -> Local {
        let d = n.x[1] - n.x[0];
        let l = d.norm();
        let e1 = d / l;
        let y0 = self.r0.column(1).into_owned();
        let q = [n.r[0] * y0, n.r[1] * y0];
        let qmean = 0.5 * (q[0] + q[1]);
        let e3u = e1.cross(&qmean);
        let e3 = e3u / e3u.norm();
        let e2 = e3.cross(&e1);
        let rr = Matrix3::from_columns(&[e1, e2, e3]);
        let theta = [
            log_so3(&(rr.transpose() * n.r[0] * self.r0)),
            log_so3(&(rr.transpose() * n.r[1] * self.r0)),
        ];
        Local {
            l,
            rr,
            q,
            qm: Vector2::new(qmean.dot(&e1), qmean.dot(&e2)),
            u: l - self.l0,
            theta,
        }
    }

    /// Position of the centre line at `ξ ∈ [0, 1]` from the cubic Hermite interpolation of the
    /// nodal positions and tangents `R_i e1⁰` (the kinematics of the inertia points).
    pub fn centre_line(&self, n: &Nodes, xi: f64) -> Vector3<f64> {
        let h = hermite(xi);
        let t0 = self.r0.column(0).into_owned();
        n.x[0] * h[0] + n.x[1] * h[2] + (n.r[0] * t0 * h[1] + n.r[1] * t0 * h[3]) * self.l0
    }

    // -----------------------------------------------------------------------------------------
    // Mass
    // -----------------------------------------------------------------------------------------

    /// Kinetic energy [J]: `Σ_p ½ μ_p |ẏ_p|²` over the inertia points plus, for the lumped
    /// model, `½ m_e |ẋ_i|² + ½ Ω_iᵀ J_e Ω_i` of the end nodes (`m_e = ρA l0/6`,
    /// `J_e = (l0/6) R0 diag(ρJx, ρIy, ρIz) R0ᵀ`).
    pub fn kinetic_energy(&self, n: &Nodes, v: &Rates) -> f64 {
        let mut t = 0.0;
        for p in &self.points[..self.n_points] {
            let yd = v.x[0] * p.alpha[0]
                + v.x[1] * p.alpha[1]
                + n.r[0] * v.w[0].cross(&p.c[0])
                + n.r[1] * v.w[1].cross(&p.c[1]);
            t += 0.5 * p.mu * yd.norm_squared();
        }
        for i in 0..2 {
            t += 0.5 * self.end_mass * v.x[i].norm_squared()
                + 0.5 * v.w[i].dot(&(self.end_inertia * v.w[i]));
        }
        t
    }

    /// Gravity potential `−Σ m g·y` [J] of the mass points (gravity `g` [m/s²]).
    pub fn gravity_potential(&self, n: &Nodes, g: &Vector3<f64>) -> f64 {
        let mut v = -self.end_mass * g.dot(&(n.x[0] + n.x[1]));
        for p in self.points[..self.n_points].iter().filter(|p| p.mass) {
            let y = n.x[0] * p.alpha[0] + n.x[1] * p.alpha[1] + n.r[0] * p.c[0] + n.r[1] * p.c[1];
            v -= p.mu * g.dot(&y);
        }
        v
    }

    /// Inertia and gravity force in residual form, added to `f`:
    /// `Σ_p B_pᵀ μ_p (ÿ_p − g)` (g on mass points only) with
    /// `ÿ_p = Σ α_i ẍ_i + Σ R_i (Ω̇_i × c_i + Ω_i × (Ω_i × c_i))` and
    /// `B_p = [α_1 I, −R_1 c̃_1, α_2 I, −R_2 c̃_2]` (so the moment on node i is
    /// `c_i × R_iᵀ F_p`), plus the end-node rigid bodies `m_e (ẍ_i − g)`,
    /// `J_e Ω̇_i + Ω_i × J_e Ω_i`. All in closed form, no Gauss integration for the lumped model.
    ///
    /// If `mats = Some((cm, cd, mc, k))`, adds `cm·M + cd·C` to `mc` (mass `∂f/∂(ẍ, Ω̇)`,
    /// gyroscopic `∂f/∂(ẋ, Ω)`) and the configuration derivative `∂f/∂(x, W)` (body spins) to
    /// `k`.
    pub fn inertia_force(
        &self,
        n: &Nodes,
        v: &Rates,
        a: &Rates,
        g: &Vector3<f64>,
        f: &mut Vec12,
        mats: Option<(f64, f64, &mut Mat12, &mut Mat12)>,
    ) {
        let mut mats = mats;
        for p in &self.points[..self.n_points] {
            let mut ydd = a.x[0] * p.alpha[0] + a.x[1] * p.alpha[1];
            let mut z = [Vector3::zeros(); 2];
            for i in 0..2 {
                z[i] = a.w[i].cross(&p.c[i]) + v.w[i].cross(&v.w[i].cross(&p.c[i]));
                ydd += n.r[i] * z[i];
            }
            let force = if p.mass { (ydd - g) * p.mu } else { ydd * p.mu };
            // B_p = [α_1 I, G_1, α_2 I, G_2] with G_i = −R_i c̃_i; rows of Bᵀ F.
            let gm = [-n.r[0] * skew(&p.c[0]), -n.r[1] * skew(&p.c[1])];
            for i in 0..2 {
                let fx = force * p.alpha[i];
                let mx = gm[i].transpose() * force;
                for c in 0..3 {
                    f[6 * i + c] += fx[c];
                    f[6 * i + 3 + c] += mx[c];
                }
            }
            if let Some((cm, cd, mc, k)) = mats.as_mut() {
                let (cm, cd, mu) = (*cm, *cd, p.mu);
                // Columns of the rotation rates: mass (G_j), gyroscopic (R_j Γ_j, Γ = ∂z/∂Ω)
                // and configuration (−R_j z̃_j) parts of ∂ÿ/∂(·)_j.
                let mut w = [Matrix3::zeros(); 2];
                let mut zc = [Matrix3::zeros(); 2];
                for j in 0..2 {
                    let (om, c) = (&v.w[j], &p.c[j]);
                    let gamma = Matrix3::identity() * om.dot(c) + om * c.transpose()
                        - 2.0 * c * om.transpose();
                    w[j] = gm[j] * (cm * mu) + n.r[j] * gamma * (cd * mu);
                    zc[j] = -n.r[j] * skew(&z[j]) * mu;
                }
                for i in 0..2 {
                    let gt = gm[i].transpose();
                    for j in 0..2 {
                        let (ai, aj) = (p.alpha[i], p.alpha[j]);
                        if ai != 0.0 {
                            let mut xx = mc.fixed_view_mut::<3, 3>(6 * i, 6 * j);
                            if aj != 0.0 {
                                for d in 0..3 {
                                    xx[(d, d)] += cm * mu * ai * aj;
                                }
                            }
                            let mut xt = mc.fixed_view_mut::<3, 3>(6 * i, 6 * j + 3);
                            xt += w[j] * ai;
                            let mut kxt = k.fixed_view_mut::<3, 3>(6 * i, 6 * j + 3);
                            kxt += zc[j] * ai;
                        }
                        if aj != 0.0 {
                            let mut tx = mc.fixed_view_mut::<3, 3>(6 * i + 3, 6 * j);
                            tx += gt * (cm * mu * aj);
                        }
                        let mut tt = mc.fixed_view_mut::<3, 3>(6 * i + 3, 6 * j + 3);
                        tt += gt * w[j];
                        let mut ktt = k.fixed_view_mut::<3, 3>(6 * i + 3, 6 * j + 3);
                        ktt += gt * zc[j];
                    }
                    // c̃ f̃ = f cᵀ − (c·f) I
                    let fb = n.r[i].transpose() * force;
                    let blk = fb * p.c[i].transpose() - Matrix3::identity() * p.c[i].dot(&fb);
                    let mut view = k.fixed_view_mut::<3, 3>(6 * i + 3, 6 * i + 3);
                    view += blk;
                }
            }
        }
        if self.end_mass != 0.0 {
            let (m, j) = (self.end_mass, &self.end_inertia);
            for i in 0..2 {
                let fx = (a.x[i] - g) * m;
                let jw = j * v.w[i];
                let mw = j * a.w[i] + v.w[i].cross(&jw);
                for c in 0..3 {
                    f[6 * i + c] += fx[c];
                    f[6 * i + 3 + c] += mw[c];
                }
                if let Some((cm, cd, mc, _)) = mats.as_mut() {
                    let mut tv = mc.fixed_view_mut::<3, 3>(6 * i, 6 * i);
                    tv += Matrix3::identity() * (*cm * m);
                    let mut rv = mc.fixed_view_mut::<3, 3>(6 * i + 3, 6 * i + 3);
                    rv += j * *cm + (skew(&v.w[i]) * j - skew(&jw)) * *cd;
                }
            }
        }
    }

    /// Mass matrix `∂f/∂(ẍ, Ω̇)` of a configuration (symmetric, `Σ μ_p B_pᵀ B_p` plus the end
    /// nodes).
    pub fn mass_matrix(&self, n: &Nodes) -> Mat12 {
        let mut mc = Mat12::zeros();
        let mut k = Mat12::zeros();
        let mut f = Vec12::zeros();
        let zero = Rates::default();
        self.inertia_force(
            n,
            &zero,
            &zero,
            &Vector3::zeros(),
            &mut f,
            Some((1.0, 0.0, &mut mc, &mut k)),
        );
        mc
    }

    // -----------------------------------------------------------------------------------------
    // Internal forces
    // -----------------------------------------------------------------------------------------

    /// Local forces of the small-deformation beam (B.3): axial force `N = EA ū/l0` [N], local
    /// end moments `n_i` [N m] (torsion `∓GJ (θ̄_2x − θ̄_1x)/l0`, bending blocks per plane), and
    /// the strain energy `U = ½ pᵀ K_l p` [J].
    /// With the bowing term the axial force `N = EA (ū/l0 + b)` also loads the end rotations:
    /// `n_i += N l0 ∂b/∂θ̄_i` per bending plane.
    fn local_forces(&self, loc: &Local) -> (f64, [Vector3<f64>; 2], f64) {
        let [t1, t2] = loc.theta;
        let ue = self.effective_elongation(loc);
        let nax = self.k_axial * ue;
        let tor = self.k_torsion * (t2.x - t1.x);
        let mut by = self.k_bend_y * Vector2::new(t1.y, t2.y);
        let mut bz = self.k_bend_z * Vector2::new(t1.z, t2.z);
        let energy = 0.5
            * (nax * ue
                + tor * (t2.x - t1.x)
                + by.dot(&Vector2::new(t1.y, t2.y))
                + bz.dot(&Vector2::new(t1.z, t2.z)));
        if self.bowing {
            by += bowing(t1.y, t2.y).1 * (nax * self.l0);
            bz += bowing(t1.z, t2.z).1 * (nax * self.l0);
        }
        (
            nax,
            [
                Vector3::new(-tor, by.x, bz.x),
                Vector3::new(tor, by.y, bz.y),
            ],
            energy,
        )
    }

    /// Strain energy [J] of a configuration.
    pub fn strain_energy(&self, n: &Nodes) -> f64 {
        self.local_forces(&self.local(n)).2
    }

    /// Internal force `[f_1, M_1, f_2, M_2]` (forces global, moments conjugate to body spins),
    /// written into `f`; returns the strain energy [J]. With `v_i = T_s⁻ᵀ(θ̄_i) n_i`,
    /// `μ̄ = v_1 + v_2`, `ρ = q·e1/q·e2`:
    /// `f_2 = −f_1 = N e1 + ((μ̄_2 + ρ μ̄_1) e3 − μ̄_3 e2)/l`,
    /// `m_i = Rr v_i − (μ̄_1/(2 q·e2)) (q_i × e3)` (spatial), `M_i = R_iᵀ m_i`.
    /// This is `Bᵀ f_l` of Battini & Pacoste 2002 written out; moment equilibrium
    /// `m_1 + m_2 + (x2 − x1) × f_2 = 0` holds identically.
    pub fn internal_force(&self, n: &Nodes, f: &mut Vec12) -> f64 {
        self.internal(n, f, None)
    }

    // -----------------------------------------------------------------------------------------
    // Tangent
    // -----------------------------------------------------------------------------------------

    /// Internal force and its exact derivative with respect to `[δx1, δW1, δx2, δW2]` (body
    /// spins): material part `Bᵀ K_l B` and every geometric term (variation of the frame, of
    /// `T_s⁻ᵀ`, of `q`, of the body-moment transformation), unsymmetrised. Returns the strain
    /// energy.
    pub fn internal_force_tangent(&self, n: &Nodes, f: &mut Vec12, k: &mut Mat12) -> f64 {
        self.internal(n, f, Some(k))
    }

    fn internal(&self, n: &Nodes, f: &mut Vec12, k: Option<&mut Mat12>) -> f64 {
        let loc = self.local(n);
        let (nax, nl, energy) = self.local_forces(&loc);
        let l = loc.l;
        let e = [
            loc.rr.column(0).into_owned(),
            loc.rr.column(1).into_owned(),
            loc.rr.column(2).into_owned(),
        ];
        let (q1, q2) = (loc.qm.x, loc.qm.y);
        let rho = q1 / q2;
        // the derivatives of `T_s⁻ᵀ n` only for the tangent
        let (v0, v1, lam) = if k.is_some() {
            let (v0, lam0) = tangent_spatial_inv_t_apply(&loc.theta[0], &nl[0]);
            let (v1, lam1) = tangent_spatial_inv_t_apply(&loc.theta[1], &nl[1]);
            (v0, v1, [lam0, lam1])
        } else {
            (
                tangent_spatial_inv_t(&loc.theta[0], &nl[0]),
                tangent_spatial_inv_t(&loc.theta[1], &nl[1]),
                [Matrix3::zeros(); 2],
            )
        };
        let v = [v0, v1];
        let mu = v0 + v1;
        let h = e[2] * (mu.y + mu.x * rho) - e[1] * mu.z;
        let f2 = e[0] * nax + h / l;
        let qxe3 = [loc.q[0].cross(&e[2]), loc.q[1].cross(&e[2])];
        let ms = [
            loc.rr * v[0] - qxe3[0] * (mu.x / (2.0 * q2)),
            loc.rr * v[1] - qxe3[1] * (mu.x / (2.0 * q2)),
        ];
        let mb = [n.r[0].transpose() * ms[0], n.r[1].transpose() * ms[1]];
        for c in 0..3 {
            f[c] = -f2[c];
            f[3 + c] = mb[0][c];
            f[6 + c] = f2[c];
            f[9 + c] = mb[1][c];
        }
        let Some(k) = k else {
            return energy;
        };

        // Derivatives with respect to δd = [δx1, δw1, δx2, δw2] (spatial spins). Everything
        // depends on the positions through the chord `x2 − x1` only, so the δx1 columns are
        // the negated δx2 columns: a derivative is kept as 3×9 (or 1×9) with the columns
        // [δx2, δw1, δw2] and expanded into the 12 columns at the end.
        let put = |m: &mut M3x9, col: usize, blk: &Matrix3<f64>| {
            m.fixed_view_mut::<3, 3>(0, col).copy_from(blk);
        };
        let row = |a: &Vector3<f64>, b: &Vector3<f64>, c: &Vector3<f64>| {
            let mut r = R9::zeros();
            for j in 0..3 {
                r[j] = a[j];
                r[3 + j] = b[j];
                r[6 + j] = c[j];
            }
            r
        };
        let z3 = Vector3::zeros();
        let dl = row(&e[0], &z3, &z3);
        let proj = (Matrix3::identity() - e[0] * e[0].transpose()) / l;
        let mut de1 = M3x9::zeros();
        put(&mut de1, 0, &proj);
        // Local components of the frame spin δw_r (Battini's Gᵀ).
        let mut gloc = M3x9::zeros();
        gloc.set_row(
            0,
            &(row(&(e[2] * (-q1 / l)), &(qxe3[0] * 0.5), &(qxe3[1] * 0.5)) / q2),
        );
        gloc.set_row(1, &row(&(-e[2] / l), &z3, &z3));
        gloc.set_row(2, &row(&(e[1] / l), &z3, &z3));
        // Frame spins δe_k = δw_r × e_k with δw_r = R_r gloc: for the frame's own axes
        // e_k × (R_r g) = R_r (ê_k × g), outer products instead of 3×3 by 3×9 products.
        let de2 = e[2] * gloc.row(0) - e[0] * gloc.row(2);
        let de3 = e[0] * gloc.row(1) - e[1] * gloc.row(0);
        let mut dqi = [M3x9::zeros(); 2];
        put(&mut dqi[0], 3, &-skew(&loc.q[0]));
        put(&mut dqi[1], 6, &-skew(&loc.q[1]));
        let dq = (dqi[0] + dqi[1]) * 0.5;
        let qmean = 0.5 * (loc.q[0] + loc.q[1]);
        let dq1 = e[0].transpose() * dq + qmean.transpose() * de1;
        let dq2 = e[1].transpose() * dq + qmean.transpose() * de2;
        let drho = (dq1 - dq2 * rho) / q2;
        let rrt = loc.rr.transpose();
        let tinv = [
            tangent_spatial_inv(&loc.theta[0]),
            tangent_spatial_inv(&loc.theta[1]),
        ];
        let mut dth = [M3x9::zeros(); 2];
        for i in 0..2 {
            let mut sel = -gloc;
            let mut blk = sel.fixed_view_mut::<3, 3>(0, 3 * i + 3);
            blk += rrt;
            dth[i] = tinv[i] * sel;
        }
        // Local forces' derivatives.
        let mut dnax = dl * self.k_axial;
        let th = &loc.theta;
        if self.bowing {
            for axis in 1..3 {
                let g = bowing(th[0][axis], th[1][axis]).1;
                dnax +=
                    (dth[0].row(axis) * g.x + dth[1].row(axis) * g.y) * (self.k_axial * self.l0);
            }
        }
        let dtor = (dth[1].row(0) - dth[0].row(0)) * self.k_torsion;
        let mut dn = [M3x9::zeros(); 2];
        dn[0].set_row(0, &-dtor);
        dn[1].set_row(0, &dtor);
        for (axis, kb) in [(1usize, &self.k_bend_y), (2usize, &self.k_bend_z)] {
            let (a, b) = (dth[0].row(axis), dth[1].row(axis));
            let mut r0 = a * kb[(0, 0)] + b * kb[(0, 1)];
            let mut r1 = a * kb[(1, 0)] + b * kb[(1, 1)];
            if self.bowing {
                // n_i += N l0 ∂b/∂θ_i: derivative of N and of the gradient
                let g = bowing(th[0][axis], th[1][axis]).1 * self.l0;
                let hs = &BOWING_HESSIAN;
                let nl0 = nax * self.l0;
                r0 += dnax * g.x + (a * hs[0][0] + b * hs[0][1]) * nl0;
                r1 += dnax * g.y + (a * hs[1][0] + b * hs[1][1]) * nl0;
            }
            dn[0].set_row(axis, &r0);
            dn[1].set_row(axis, &r1);
        }
        let mut dv = [M3x9::zeros(); 2];
        for i in 0..2 {
            dv[i] = lam[i] * dth[i] + tinv[i].transpose() * dn[i];
        }
        let dmu = dv[0] + dv[1];
        let dh = e[2] * (dmu.row(1) + dmu.row(0) * rho + drho * mu.x) + de3 * (mu.y + mu.x * rho)
            - e[1] * dmu.row(2)
            - de2 * mu.z;
        let df2 = e[0] * dnax + de1 * nax - h * dl / (l * l) + dh / l;
        // Rows [f2, R1ᵀ m1, R2ᵀ m2] of the reduced columns; the force on node 1 is −f2.
        let mut kr = M9::zeros();
        kr.fixed_rows_mut::<3>(0).copy_from(&df2);
        // R_iᵀ δm_i with δm_i = δ(R_r v_i) − q_i × e3 δ(μ̄_1/(2 q·e2)) − δ(q_i × e3) μ̄_1/(2 q·e2):
        // δ(R_r v_i) = R_r (δv_i − ṽ_i gloc) (the frame spin R_r gloc), δe3 of the outer
        // products above, δq_i = −q̃_i δw_i (the node's own spin block only).
        let cq = mu.x / (2.0 * q2);
        let dc = dq2 * (mu.x / (2.0 * q2 * q2)) - dmu.row(0) / (2.0 * q2);
        for i in 0..2 {
            let rt = n.r[i].transpose();
            let a = rt * qxe3[i];
            let b0 = rt * loc.q[i].cross(&e[0]) * cq;
            let b1 = rt * loc.q[i].cross(&e[1]) * cq;
            let mut rows = (rt * loc.rr) * (dv[i] - skew(&v[i]) * gloc) + a * dc - b0 * gloc.row(1)
                + b1 * gloc.row(0);
            let mut blk = rows.fixed_view_mut::<3, 3>(0, 3 * i + 3);
            // ẽ₃ q̃ = q e₃ᵀ − (e₃·q) I
            blk -=
                rt * (loc.q[i] * e[2].transpose() - Matrix3::identity() * e[2].dot(&loc.q[i])) * cq;
            kr.fixed_rows_mut::<3>(3 * i + 3).copy_from(&rows);
        }
        // columns: spatial spins → body spins (× R_j)
        for j in 0..2 {
            let cols = kr.fixed_columns::<3>(3 * j + 3) * n.r[j];
            kr.fixed_columns_mut::<3>(3 * j + 3).copy_from(&cols);
        }
        for i in 0..2 {
            let mut blk = kr.fixed_view_mut::<3, 3>(3 * i + 3, 3 * i + 3);
            blk += skew(&mb[i]);
        }
        // expand: full row/column block b ↔ reduced block and sign
        const EXPAND: [(usize, bool); 4] = [(0, true), (3, false), (0, false), (6, false)];
        for (bc, &(rc, nc)) in EXPAND.iter().enumerate() {
            for (br, &(rr, nr)) in EXPAND.iter().enumerate() {
                let src = kr.fixed_view::<3, 3>(rr, rc);
                let mut dst = k.fixed_view_mut::<3, 3>(3 * br, 3 * bc);
                if nr != nc {
                    dst.copy_from(&-src);
                } else {
                    dst.copy_from(&src);
                }
            }
        }
        energy
    }
}

// ---------------------------------------------------------------------------------------------
// The element trait
// ---------------------------------------------------------------------------------------------

/// Slots `[x1, θ1, x2, θ2]`: rotation slots are incremental rotation vectors of node frames.
const COROT_SLOTS: &[Slot] = &[
    Slot::Position,
    Slot::Rotation,
    Slot::Position,
    Slot::Rotation,
];

impl Corot3d {
    /// Nodes of an element state (positions from the coordinates, orientations from the node
    /// frames).
    #[inline]
    pub fn nodes_of(s: &ElementState<ELEMENT_DOFS>) -> Nodes {
        Nodes {
            x: [
                s.q.fixed_rows::<3>(0).into_owned(),
                s.q.fixed_rows::<3>(6).into_owned(),
            ],
            r: [s.frames[0].rot, s.frames[1].rot],
        }
    }

    /// Chains the rotation columns of a body-spin derivative with the tangents `T(θ_i)`.
    #[inline]
    fn chain_rotations(s: &ElementState<ELEMENT_DOFS>, k: &mut Mat12) {
        for slot in 0..2 {
            let cols = k.fixed_view::<12, 3>(0, 6 * slot + 3) * s.frames[slot].tangent;
            k.fixed_view_mut::<12, 3>(0, 6 * slot + 3).copy_from(&cols);
        }
    }
}

impl Element<ELEMENT_DOFS> for Corot3d {
    fn layout(&self) -> Layout {
        Layout {
            dim: 3,
            slots: COROT_SLOTS,
        }
    }

    fn constant_mass_matrix(&self) -> Option<&Mat12> {
        None
    }

    fn mass_into(&self, s: &ElementState<ELEMENT_DOFS>, m: &mut Mat12) {
        *m = self.mass_matrix(&Self::nodes_of(s));
    }

    /// `Q_g = Σ_p B_pᵀ μ_p g` over the mass points (and the end masses of the lumped model).
    fn gravity_into(&self, s: &ElementState<ELEMENT_DOFS>, g: &Vector3<f64>, f: &mut Vec12) {
        let zero = Rates::default();
        *f = Vec12::zeros();
        self.inertia_force(&Self::nodes_of(s), &zero, &zero, g, f, None);
        f.neg_mut();
    }

    fn strain_energy_at(&self, s: &ElementState<ELEMENT_DOFS>) -> f64 {
        self.strain_energy(&Self::nodes_of(s))
    }

    fn force_into(&self, s: &ElementState<ELEMENT_DOFS>, f: &mut Vec12) -> f64 {
        self.internal_force(&Self::nodes_of(s), f)
    }

    /// Exact tangent, rotation columns chained with `T(θ)`; no material damping (`C = 0`).
    fn tangent_into(
        &self,
        s: &ElementState<ELEMENT_DOFS>,
        f: &mut Vec12,
        k: &mut Mat12,
        c: Option<&mut Mat12>,
    ) -> f64 {
        if let Some(c) = c {
            *c = Mat12::zeros();
        }
        let u = self.internal_force_tangent(&Self::nodes_of(s), f, k);
        Self::chain_rotations(s, k);
        u
    }

    fn kinetic_energy_at(&self, s: &ElementState<ELEMENT_DOFS>) -> f64 {
        self.kinetic_energy(&Self::nodes_of(s), &Rates::from_vec(&s.v))
    }

    /// Inertia (mass, gyroscopic and configuration terms, gravity on the mass points) plus
    /// internal force; the configuration derivatives of both are chained with `T(θ)`.
    fn residual_into(
        &self,
        s: &ElementState<ELEMENT_DOFS>,
        a: &Vec12,
        g: &Vector3<f64>,
        f: &mut Vec12,
        mat: Option<(crate::model::JacobianCoeffs, &mut Mat12)>,
    ) -> f64 {
        let nodes = Self::nodes_of(s);
        let v = Rates::from_vec(&s.v);
        let a = Rates::from_vec(a);
        match mat {
            Some((c, out)) => {
                let mut k = Mat12::zeros();
                *out = Mat12::zeros();
                if c.stiffness == 0.0 {
                    // a mass (and gyroscopic) matrix only, e.g. for consistent accelerations:
                    // the tangent would be multiplied by zero
                    let u = self.internal_force(&nodes, f);
                    self.inertia_force(
                        &nodes,
                        &v,
                        &a,
                        g,
                        f,
                        Some((c.mass, c.damping, out, &mut k)),
                    );
                    return u;
                }
                let u = self.internal_force_tangent(&nodes, f, &mut k);
                self.inertia_force(&nodes, &v, &a, g, f, Some((c.mass, c.damping, out, &mut k)));
                Self::chain_rotations(s, &mut k);
                *out += k * c.stiffness;
                u
            }
            None => {
                let u = self.internal_force(&nodes, f);
                self.inertia_force(&nodes, &v, &a, g, f, None);
                u
            }
        }
    }
}
