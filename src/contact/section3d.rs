//! Contact of a belt's cross-sections with 3D pulleys ([`Pulley3d`]): the belt lies across
//! the rim, so every node's section (width `2b`, width director `d = R e_w`, `R` the node's
//! rotation, `e_w` the section's width axis in the node frame) touches the rim at points
//! `x_j = r + s_j d` across the width, not only at its centre line.
//!
//! Why: a crowned rim centres a flat belt only through the contact pressure over the width.
//! The pressure's moment about the belt's tangent tilts the section onto the local cone of
//! the crown; a flat belt tilted on a cone is steered up the slope. A single point on the
//! centre line feels the crown only through its normal, which pushes it down the slope.
//!
//! The section conforms to the rim across its width: a thin belt pressed on by its tension
//! follows a crown's barrel (its transverse bending is soft), so a point at `s` sits
//! `κ s²/2` towards the pulley's axis from the straight section, `κ = 2 h_c/h²` the crown's
//! curvature (0 on a flat rim). The point's offset from the node is the body-fixed vector
//! `p = s e_w + σ κ s²/2 e_n` (`e_n` the section's thickness axis, `σ = ±1` so that the
//! offset points towards the axis). Without it a rigid flat section would bridge the
//! barrel, touch at one point and feel no moment.
//!
//! Points: `n` Gauss–Lobatto points across the width, `s_j = b ξ_j`, each standing for the
//! share `ω_j/2` of the section (Lobatto weights `ω_j` on [−1, 1]), i.e. the rim weight
//! `l ω_j/2` for a node standing for the belt length `l`. The edge points (`ξ = ±1`) are the
//! belt's edges: they alone meet the flanges, with the flange weight `l`. `n = 1` is the
//! centre-line contact (one point at `s = 0`, its flange test with the belt's half width:
//! the point contact of [`super::pulley3d`] unchanged).
//!
//! Every point is a [`super::pulley3d`] point contact (penalty, damping, bristle friction
//! with its own history). With `G = −R p̃` (`δx_j = δr + G δW` for a body spin `δW`,
//! `R → R exp(δW̃)`) and `v_j = v + R (Ω × p)` (`Ω` the body angular velocity), the
//! point's force `F` acts on the node as the force `F` and the body moment `Gᵀ F =
//! p × (Rᵀ F)` (conjugate to `δW`, as the co-rotational element's moments,
//! [`crate::elements::corotational3d`]). Derivatives with the point's own `K = ∂F/∂x`,
//! `C = ∂F/∂v` (and the pulley-angle columns and torque rows):
//!
//! * `∂F/∂W = K G + C H`, `H = ∂v_j/∂W = −R (Ω × p)~`;
//! * `∂(Gᵀ F)/∂W = Gᵀ ∂F/∂W + p̃ (Rᵀ F)~` (from `δ(Rᵀ) F = (Rᵀ F)~ δW`);
//! * `∂F/∂Ω = C G`;
//!
//! then the rotation columns chained with `T(θ)` of the incremental rotation vector
//! (`δW = T(θ) δθ`, [`crate::elements::node_frames`]). Checked against central differences
//! in the tests below.
//!
//! **Sections between the nodes.** With only the nodes in contact, each standing for an
//! element length, the belt meets the rim at the node-passing frequency: the polygon action
//! excites the spans, and the loaded drive's span tensions ran up to 1.6/3.8 % above the
//! planar drive's, its creep up to twice the planar creep (issue 13 item 4; the planar belt
//! with one contact point per element shows offsets of the same size, with two it is within
//! 0.05 % of four at 144 elements: `tests/belt_3d.rs` `planar_limit_loaded_table`).
//! A section at `ξ` along an element of nodes `a`, `b` (length `l`) has its centre on the
//! cubic Hermite centre line of the nodes' positions and tangents `t_n = R_n e_t`
//! (tangent length `l`): `c = H₁ r_a + H₃ r_b + R_a (l H₂ e_t) + R_b (l H₄ e_t)`, the
//! co-rotational element's own cubic up to the tangents' length (`l` against the stretched
//! chord: a shift of order strain × sagitta). Its width offsets are blended linearly,
//! `(1 − ξ) R_a p + ξ R_b p`, rather than rotated by an interpolated rotation: on a rim both
//! nodes' width directors lie along the axis, and the blend shortens an offset only by
//! `1 − cos(Δ/2)` for a relative rotation `Δ` of the nodes about the tangent (1e-4 for the
//! quarter-twist drive's 0.03 rad per element), while every point stays the sum of the two
//! nodes' body-fixed offsets `u_n = l H₂ₙ e_t + β_n p` plus weighted positions:
//! `x = w_a r_a + w_b r_b + R_a u_a + R_b u_b`. So each node takes the point's force as
//! `w_n F` and the body moment `u_n × (R_nᵀ F)`, with the derivatives above per node
//! (`G_n = −R_n ũ_n`, `H_n = −R_n (Ω_n × u_n)~`). The node-only contact is the section
//! `w = (1, 0)`, `u = (p, 0)`.

use super::circle_friction::ContactLaw;
use super::obstacle::{Obstacle, ObstacleContact, PointMotion};
use super::point_set::{
    ContactBook, ObstacleLoad, read_histories, read_loads, write_histories, write_loads,
};
use super::pulley3d::{
    Pulley3d, Pulley3dContact, Pulley3dHistory, evaluate_parts, evaluate_parts_into,
};
use crate::assembly::Connectivity;
use crate::elements::element::Frame;
use crate::elements::node_frames::NodeFrames;
use crate::elements::quadrature::lobatto;
use crate::elements::rotation::skew;
use crate::model::JacobianCoeffs;
use crate::snapshot::{StateReader, StateWriter};
use nalgebra::{Matrix3, SMatrix, Vector3};
use std::cell::Cell;

/// Coordinates of one (element, pulley) block: the element's first node's position (3) and
/// rotation vector (3), its second node's (3 + 3), the pulley angle (1).
pub const SECTION_BLOCK: usize = 13;

/// Pulleys whose sections' centres and tests [`SectionContactSet::commit`] keeps per
/// section (more pulleys: computed per point).
const MAX_COMMIT_PULLEYS: usize = 8;

/// One point across the section.
#[derive(Clone, Copy, Debug, PartialEq)]
struct WidthPoint {
    /// Offset along the width director [m].
    s: f64,
    /// Share of the section's rim contact [1] (sums to 1).
    share: f64,
    /// Whether the point is an edge of the belt (meets the flanges).
    edge: bool,
}

/// A section along an element (module docs, "Sections between the nodes"): its centre is
/// `w₀ r_a + w₁ r_b + R_a (λ₀ e_t) + R_b (λ₁ e_t)`, its width offsets are blended as
/// `β₀ R_a p + β₁ R_b p`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Station {
    /// Hermite weights of the nodes' positions [1].
    w: [f64; 2],
    /// Hermite weights of the nodes' tangents [1] (times the element length: [m]).
    t: [f64; 2],
    /// Blend of the width offsets [1].
    b: [f64; 2],
}

impl Station {
    /// The section at the element's first node (the node-only contact).
    const NODE: Self = Self {
        w: [1.0, 0.0],
        t: [0.0, 0.0],
        b: [1.0, 0.0],
    };

    /// The section at `ξ` ∈ (0, 1) along the element: the cubic Hermite centre line of the
    /// nodes' positions and tangents (tangent length: the element length), width offsets
    /// blended linearly.
    fn at(xi: f64) -> Self {
        let (x2, x3) = (xi * xi, xi * xi * xi);
        Self {
            w: [1.0 - 3.0 * x2 + 2.0 * x3, 3.0 * x2 - 2.0 * x3],
            t: [xi - 2.0 * x2 + x3, x3 - x2],
            b: [1.0 - xi, xi],
        }
    }
}

/// The term of the (point, pulley) pair with history index `i` in the signature of the set of
/// pairs in contact ([`SectionContactSet::contacts_as_in_matrix`]): `i + 1` times the 64-bit
/// golden-ratio constant (Fibonacci hashing, Knuth, TAOCP vol. 3 §6.4), wrapping.
#[inline(always)]
fn contact_key(i: usize) -> u64 {
    (i as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15)
}

/// Contact of the sections of a belt against 3D pulleys: at its nodes, or at stations
/// between them.
#[derive(Clone, Debug)]
pub struct SectionContactSet {
    law: ContactLaw,
    /// The pulleys as given (belt half width: the centre-line point's flange test).
    obstacles: Vec<Pulley3d>,
    /// The pulleys as seen by points across the width (belt half width 0: each point is its
    /// own edge).
    across: Vec<Pulley3d>,
    blocks: Connectivity<SECTION_BLOCK>,
    /// Node indices (into the node frames) of every element.
    elements: Vec<[usize; 2]>,
    /// Width axis of the section in the node frame (unit).
    width_axis: Vector3<f64>,
    /// Thickness axis of the section in the node frame (unit).
    normal_axis: Vector3<f64>,
    /// Tangent axis of the section in the node frame (unit): thickness × width.
    tangent_axis: Vector3<f64>,
    points: Vec<WidthPoint>,
    /// Sections along every element.
    stations: Vec<Station>,
    /// Belt length a section stands for [m].
    length: f64,
    /// Element length [m] (the Hermite tangents' length).
    element_length: f64,
    /// Block coordinates the sections move with (the node-only contact: not the second
    /// node's).
    used: [bool; SECTION_BLOCK],
    /// Histories by element, station, point, pulley.
    hist: Vec<Pulley3dHistory>,
    loads: Vec<ObstacleLoad<3>>,
    /// Signature of the set of (point, pulley) pairs in contact at the last evaluation that
    /// built an iteration matrix ([`Self::contacts_as_in_matrix`]).
    built_sig: Cell<u64>,
    /// Signature of the set of (point, pulley) pairs in contact at the last evaluation.
    last_sig: Cell<u64>,
}

/// Point motion of a width point and what its spin maps `G_n = −R_n ũ_n` and
/// `H_n = ∂v/∂W_n = −R_n (Ω_n × u_n)~` are made of, per node of the element (the maps
/// themselves are built only for points in contact, [`PointKinematics::spin_maps`]).
struct PointKinematics {
    motion: PointMotion<3>,
    /// Whether the point moves with each node.
    active: [bool; 2],
    /// Weights of the nodes' positions.
    w: [f64; 2],
    rot: [Matrix3<f64>; 2],
    /// Offsets of the point in the node frames [m].
    u: [Vector3<f64>; 2],
    /// Body angular velocities of the nodes [rad/s].
    om: [Vector3<f64>; 2],
}

impl PointKinematics {
    /// `G_n` and `H_n` of node `n`.
    #[inline(always)]
    fn spin_maps(&self, n: usize) -> (Matrix3<f64>, Matrix3<f64>) {
        let u = &self.u[n];
        (
            -self.rot[n] * skew(u),
            -self.rot[n] * skew(&self.om[n].cross(u)),
        )
    }

    /// The body moment `G_nᵀ F = u_n × (R_nᵀ F)` of the force `f` on node `n`.
    #[inline(always)]
    fn moment(&self, n: usize, f: &Vector3<f64>) -> Vector3<f64> {
        self.u[n].cross(&(self.rot[n].transpose() * f))
    }
}

impl SectionContactSet {
    /// Sections of the belt against `obstacles`: `blocks` row `e · n_pulleys + p` holds
    /// element `e`'s nodes' positions and rotation vectors, then pulley `p`'s angle;
    /// `elements[e]` the element's node indices (into the node frames). Each section has its
    /// width axis `width_axis` and thickness axis `normal_axis` in the node frame, `n_width`
    /// Lobatto points across the width (1: the centre line only). `per_element` sections per
    /// element at `(i + 0.5)/per_element` of its length, each standing for
    /// `length/per_element`; 0: one section at each element's first node, standing for
    /// `length` (the node-only contact). `length` [m] is the element length. The belt's half
    /// width is the pulleys' `belt_half_width`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        law: ContactLaw,
        obstacles: Vec<Pulley3d>,
        blocks: Connectivity<SECTION_BLOCK>,
        elements: Vec<[usize; 2]>,
        width_axis: Vector3<f64>,
        normal_axis: Vector3<f64>,
        n_width: usize,
        per_element: usize,
        length: f64,
    ) -> Self {
        let b = obstacles.first().map_or(0.0, |o| o.belt_half_width);
        let points: Vec<WidthPoint> = lobatto(n_width)
            .iter()
            .map(|&(xi, w)| WidthPoint {
                s: b * xi,
                share: 0.5 * w,
                edge: n_width > 1 && xi.abs() == 1.0,
            })
            .collect();
        let stations: Vec<Station> = if per_element == 0 {
            vec![Station::NODE]
        } else {
            (0..per_element)
                .map(|i| Station::at((i as f64 + 0.5) / per_element as f64))
                .collect()
        };
        let across = obstacles
            .iter()
            .map(|o| {
                let mut p = *o;
                p.belt_half_width = 0.0;
                p
            })
            .collect();
        let (width_axis, normal_axis) = (width_axis.normalize(), normal_axis.normalize());
        let used = std::array::from_fn(|i| {
            i == 12
                || stations
                    .iter()
                    .any(|st| st.w[i / 6] != 0.0 || st.b[i / 6] != 0.0)
        });
        let mut me = Self {
            built_sig: Default::default(),
            last_sig: Default::default(),
            law,
            loads: vec![ObstacleLoad::default(); obstacles.len()],
            hist: vec![
                Pulley3dHistory::default();
                elements.len() * stations.len() * points.len() * obstacles.len()
            ],
            obstacles,
            across,
            blocks,
            elements,
            width_axis,
            normal_axis,
            tangent_axis: normal_axis.cross(&width_axis),
            points,
            stations,
            used,
            length: 0.0,
            element_length: 0.0,
        };
        me.set_length(length);
        me
    }

    /// Sets the element length [m] (histories kept).
    pub fn set_length(&mut self, length: f64) {
        self.element_length = length;
        self.length = length / self.stations.len() as f64;
    }

    /// Points across the width of every section.
    pub fn points_per_section(&self) -> usize {
        self.points.len()
    }

    /// Sections per element (1 for the node-only contact).
    pub fn sections_per_element(&self) -> usize {
        self.stations.len()
    }

    /// The pulleys.
    pub fn obstacles(&self) -> &[Pulley3d] {
        &self.obstacles
    }

    /// Loads on every pulley in the committed state.
    pub fn loads(&self) -> &[ObstacleLoad<3>] {
        &self.loads
    }

    /// Contact constants.
    pub fn law(&self) -> &ContactLaw {
        &self.law
    }

    /// Replaces the contact constants (the pre-load's frictionless solve).
    pub fn set_law(&mut self, law: ContactLaw) {
        self.law = law;
    }

    /// The pulley point `j` of a section meets, its rim and flange weights [m].
    #[inline(always)]
    fn pulley_for(&self, j: usize, k: usize) -> (&Pulley3d, f64, f64) {
        let p = &self.points[j];
        if self.points.len() == 1 {
            (&self.obstacles[k], self.length, self.length)
        } else {
            let flange = if p.edge { self.length } else { 0.0 };
            (&self.across[k], self.length * p.share, flange)
        }
    }

    /// Centre `c` and width director `d` of the section at station `st` of block `b` with
    /// node rotations `rot`.
    #[inline(always)]
    fn centre(
        &self,
        b: usize,
        st: &Station,
        rot: &[Matrix3<f64>; 2],
        q: &[f64],
    ) -> (Vector3<f64>, Vector3<f64>) {
        let dofs = self.blocks.dofs(b);
        let (mut c, mut d) = (Vector3::zeros(), Vector3::zeros());
        for n in 0..2 {
            if st.w[n] == 0.0 && st.b[n] == 0.0 {
                continue;
            }
            let o = 6 * n;
            let r = Vector3::new(q[dofs[o]], q[dofs[o + 1]], q[dofs[o + 2]]);
            c += st.w[n] * r + rot[n] * ((st.t[n] * self.element_length) * self.tangent_axis);
            d += st.b[n] * (rot[n] * self.width_axis);
        }
        (c, d)
    }

    /// Whether a section (centre `c`, width director `d`) can touch pulley `k`.
    #[inline(always)]
    fn near(&self, k: usize, c: &Vector3<f64>, d: &Vector3<f64>) -> bool {
        let b = self.obstacles[k].belt_half_width;
        self.obstacles[k].near(&(c - b * d), &(c + b * d))
    }

    /// Sign `σ` and crown curvature `κ` [1/m] of the section's conforming offset on pulley
    /// `k` for a section at `c` with node rotations `rot` blended by `st` (module docs).
    #[inline(always)]
    fn conform(
        &self,
        k: usize,
        c: &Vector3<f64>,
        st: &Station,
        rot: &[Matrix3<f64>; 2],
    ) -> (f64, f64) {
        let ob = &self.obstacles[k];
        if self.points.len() == 1 || ob.crown == 0.0 || ob.half_width <= 0.0 {
            return (0.0, 0.0);
        }
        let d = c - ob.center;
        let radial = d - ob.axis.dot(&d) * ob.axis;
        let mut normal = st.b[0] * (rot[0] * self.normal_axis);
        if st.b[1] != 0.0 {
            normal += st.b[1] * (rot[1] * self.normal_axis);
        }
        let sigma = if radial.dot(&normal) > 0.0 { -1.0 } else { 1.0 };
        (sigma, 2.0 * ob.crown / (ob.half_width * ob.half_width))
    }

    /// Motion of width point `j` of the section at station `st` of block `b` with node
    /// rotations `rot`, conforming offset `(σ, κ)` of [`Self::conform`].
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn kinematics(
        &self,
        b: usize,
        st: &Station,
        j: usize,
        rot: &[Matrix3<f64>; 2],
        (sigma, kappa): (f64, f64),
        q: &[f64],
        v: &[f64],
    ) -> PointKinematics {
        let dofs = self.blocks.dofs(b);
        let s = self.points[j].s;
        let p = s * self.width_axis + (0.5 * sigma * kappa * s * s) * self.normal_axis;
        let (mut x, mut xv) = (Vector3::zeros(), Vector3::zeros());
        let (mut u, mut oms) = ([Vector3::zeros(); 2], [Vector3::zeros(); 2]);
        let mut active = [false; 2];
        for n in 0..2 {
            if st.w[n] == 0.0 && st.b[n] == 0.0 {
                continue;
            }
            active[n] = true;
            let o = 6 * n;
            let r = Vector3::new(q[dofs[o]], q[dofs[o + 1]], q[dofs[o + 2]]);
            let vel = Vector3::new(v[dofs[o]], v[dofs[o + 1]], v[dofs[o + 2]]);
            let om = Vector3::new(v[dofs[o + 3]], v[dofs[o + 4]], v[dofs[o + 5]]);
            let un = (st.t[n] * self.element_length) * self.tangent_axis + st.b[n] * p;
            x += st.w[n] * r + rot[n] * un;
            xv += st.w[n] * vel + rot[n] * om.cross(&un);
            u[n] = un;
            oms[n] = om;
        }
        PointKinematics {
            motion: PointMotion { r: x, v: xv },
            active,
            w: st.w,
            rot: *rot,
            u,
            om: oms,
        }
    }

    /// Subtracts the contact forces at full coordinates `q`, velocities `v` (node frames
    /// `frames` of `q`, indexed by node) from the full residual `f` and, with `jac`, adds
    /// `−∂F/∂(q, v)` (weighted by the coefficients) into the values of the iteration matrix.
    pub fn add_residual(
        &self,
        q: &[f64],
        v: &[f64],
        frames: &[Frame],
        f: &mut [f64],
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) {
        let no = self.obstacles.len();
        let (np, ns) = (self.points.len(), self.stations.len());
        let (cs, cd) = jac
            .as_ref()
            .map_or((0.0, 0.0), |(c, _)| (c.stiffness, c.damping));
        let mut mb = Block::zeros();
        let mut res = Pulley3dContact::default();
        let mut sig = 0u64;
        for (e, nodes) in self.elements.iter().enumerate() {
            if !(0..no).any(|k| self.element_near(e * no + k, k, q)) {
                continue;
            }
            let fr = [&frames[nodes[0]], &frames[nodes[1]]];
            let rot = [fr[0].rot, fr[1].rot];
            let tangents = [fr[0].tangent, fr[1].tangent];
            for k in 0..no {
                let b = e * no + k;
                if !self.element_near(b, k, q) {
                    continue;
                }
                let dofs = self.blocks.dofs(b);
                let (theta, omega) = (q[dofs[12]], v[dofs[12]]);
                let mut any = false;
                for (i, st) in self.stations.iter().enumerate() {
                    let (c, d) = self.centre(b, st, &rot, q);
                    if !self.near(k, &c, &d) {
                        continue;
                    }
                    let conform = self.conform(k, &c, st, &rot);
                    for j in 0..np {
                        let kin = self.kinematics(b, st, j, &rot, conform, q, v);
                        let (ob, w_rim, w_fl) = self.pulley_for(j, k);
                        let h = &self.hist[((e * ns + i) * np + j) * no + k];
                        if !evaluate_parts_into(
                            ob,
                            &self.law,
                            w_rim,
                            w_fl,
                            &kin.motion,
                            theta,
                            omega,
                            h,
                            jac.is_some(),
                            &mut res,
                        ) {
                            continue;
                        }
                        sig = sig.wrapping_add(contact_key(((e * ns + i) * np + j) * no + k));
                        if !any && jac.is_some() {
                            mb.fill(0.0);
                        }
                        any = true;
                        for n in 0..2 {
                            if !kin.active[n] {
                                continue;
                            }
                            let moment = kin.moment(n, &res.force);
                            for c in 0..3 {
                                f[dofs[6 * n + c]] -= kin.w[n] * res.force[c];
                                f[dofs[6 * n + 3 + c]] -= moment[c];
                            }
                        }
                        f[dofs[12]] -= res.torque;
                        if jac.is_some() {
                            point_block(&kin, &res, &tangents, (cs, cd), &mut mb);
                        }
                    }
                }
                if any && let Some((_, vals)) = jac.as_mut() {
                    self.blocks.add_matrix_used(b, &mb, -1.0, &self.used, vals);
                }
            }
        }
        self.last_sig.set(sig);
        if jac.is_some() {
            self.built_sig.set(sig);
        }
    }

    /// Whether the (point, pulley) pairs in contact (rim or flange) at the last evaluation
    /// ([`Self::add_residual`]) are those of the last evaluation that built an iteration
    /// matrix: the contact blocks of a kept matrix belong to those pairs, and a pair that came
    /// into contact since (a section landing on a rim) has none. Compared by a signature,
    /// the wrapping sum of a multiplicative hash of every pair's index ([`contact_key`]): no
    /// allocation, two different sets agree only by a 64-bit collision.
    pub fn contacts_as_in_matrix(&self) -> bool {
        self.last_sig.get() == self.built_sig.get()
    }

    /// Broad phase of block `b` against pulley `k`: whether a section of the element can be
    /// [`Self::near`] the pulley, from its first node alone. Every end `c ± b d` of a section
    /// lies within `|r_b − r_a| + (8/27) l + b` of the first node (the Hermite weights: `w₁ ∈
    /// [0, 1]`, `|H₂| + |H₄| ≤ 8/27`; `|d| ≤ 1`), and the section test widens by at most
    /// `1.1 b + 10⁻³ R`; distance to the axis and axial position change by at most the
    /// distance moved, so the node tested with the sum of both margins (rounded up) rejects
    /// only elements whose sections all fail the section test.
    #[inline(always)]
    fn element_near(&self, b: usize, k: usize, q: &[f64]) -> bool {
        let dofs = self.blocks.dofs(b);
        let ob = &self.obstacles[k];
        let ra = Vector3::new(q[dofs[0]], q[dofs[1]], q[dofs[2]]);
        let chord = if self.used[6] {
            (Vector3::new(q[dofs[6]], q[dofs[7]], q[dofs[8]]) - ra).norm()
        } else {
            0.0
        };
        let margin =
            chord + 0.5 * self.element_length + 2.5 * ob.belt_half_width + 2e-3 * ob.radius + 1e-9;
        let d = ra - ob.center;
        let zeta = ob.axis.dot(&d);
        let rho = (d - zeta * ob.axis).norm();
        rho - margin < ob.radius.max(ob.flange_top)
            && zeta.abs() - margin < ob.half_width + ob.belt_half_width
    }

    /// Commits the state at full coordinates `q`, velocities `v` with the node orientations
    /// of `frames` (at `q`): new histories, the loads on the pulleys ([`Self::loads`]) and the
    /// energy terms. `initial`: no contact is evaluated (histories at rest).
    pub fn commit(
        &mut self,
        q: &[f64],
        v: &[f64],
        frames: &NodeFrames,
        initial: bool,
    ) -> ContactBook {
        let no = self.obstacles.len();
        let (np, ns) = (self.points.len(), self.stations.len());
        self.loads.fill(ObstacleLoad::default());
        let mut book = ContactBook::default();
        if no == 0 {
            return book;
        }
        // (at most MAX_COMMIT_PULLEYS pulleys share a point's kinematics: a fixed array)
        let mut near = [false; MAX_COMMIT_PULLEYS];
        let mut conform = [(0.0, 0.0); MAX_COMMIT_PULLEYS];
        for e in 0..self.elements.len() {
            let nodes = self.elements[e];
            let rot = [frames.rotation(nodes[0], q), frames.rotation(nodes[1], q)];
            for i in 0..ns {
                let st = self.stations[i];
                // the section's centre and the point kinematics move with the element's
                // nodes only (the same for every pulley's block): computed once per section
                // and point, again only for a pulley whose conforming offset differs
                let b0 = e * no;
                let (c, d) = self.centre(b0, &st, &rot, q);
                for k in 0..no.min(MAX_COMMIT_PULLEYS) {
                    near[k] = self.near(k, &c, &d);
                    conform[k] = self.conform(k, &c, &st, &rot);
                }
                for j in 0..np {
                    let shared = self.kinematics(b0, &st, j, &rot, conform[0], q, v);
                    for k in 0..no {
                        let b = e * no + k;
                        let dofs = self.blocks.dofs(b);
                        let x = [q[dofs[12]]];
                        let (cf, nr) = if k < MAX_COMMIT_PULLEYS {
                            (conform[k], near[k])
                        } else {
                            (self.conform(k, &c, &st, &rot), self.near(k, &c, &d))
                        };
                        let own;
                        let kin = if cf == conform[0] {
                            &shared
                        } else {
                            own = self.kinematics(b, &st, j, &rot, cf, q, v);
                            &own
                        };
                        let idx = ((e * ns + i) * np + j) * no + k;
                        let h = self.hist[idx];
                        let (ob, w_rim, w_fl) = self.pulley_for(j, k);
                        let ob = *ob;
                        let res = if nr && !initial {
                            evaluate_parts(
                                &ob,
                                &self.law,
                                w_rim,
                                w_fl,
                                &kin.motion,
                                x[0],
                                v[dofs[12]],
                                &h,
                                false,
                            )
                        } else {
                            None
                        };
                        if let Some(r) = &res {
                            let load = &mut self.loads[k];
                            load.generalized[0] += r.generalized_force(0);
                            load.force -= r.force;
                            load.moment += r.moment;
                            load.side_force += r.side_force();
                            book.slipping += r.slipping as usize;
                            book.normal_energy += r.normal_energy;
                            book.dissipation += r.dissipation;
                            book.friction_work += Pulley3d::friction_work(w_rim, &h, r);
                        }
                        self.hist[idx] = ob.committed(&kin.motion, &x, res.as_ref());
                    }
                }
            }
        }
        book
    }

    /// Writes the histories into a snapshot.
    pub fn save(&self, w: &mut StateWriter) {
        write_histories(&self.hist, w);
    }

    /// Reads histories written by [`Self::save`].
    pub fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        read_histories(&mut self.hist, r)
    }

    /// Writes the committed loads on the pulleys ([`Self::loads`]).
    pub fn save_loads(&self, w: &mut StateWriter) {
        write_loads(&self.loads, w);
    }

    /// Reads loads written by [`Self::save_loads`].
    pub fn restore_loads(&mut self, r: &mut StateReader) -> Result<(), String> {
        read_loads(&mut self.loads, r)
    }
}

/// Block matrix of the generalized forces of a section.
type Block = SMatrix<f64, SECTION_BLOCK, SECTION_BLOCK>;

/// The iteration matrix `c_K K + c_C C` of the generalized forces `Q` = (force `w_n F` and
/// body moment `G_nᵀ F` on each node, torque on the pulley) of one width point of `kin`
/// (module docs), added into `m`: `K = ∂Q/∂(r_a, θ_a, r_b, θ_b, θ_p)` in the incremental
/// rotation vectors (`δW_n = T_n δθ_n`, `T_n` = `tangents[n]`), `C = ∂Q/∂(v_a, Ω_a, v_b,
/// Ω_b, ω)`. With `δx = Σ_n (w_n δr_n + G_n δW_n)` and `∂v/∂W_n = H_n`: `∂F/∂r_n = w_n K`,
/// `∂F/∂θ_n = (K G_n + C H_n) T_n`, `∂F/∂v_n = w_n C`, `∂F/∂Ω_n = C G_n`, plus
/// `ũ_n (R_nᵀ F)~ T_n` on the `(W_n, θ_n)` block. Both coefficients are combined per point,
/// so every row block is multiplied once: `D_n = c_K (K G_n + C H_n) T_n + c_C C G_n`, the
/// moment rows `G_mᵀ (c_K K + c_C C) w_n` and `G_mᵀ D_n`. Only the nodes the point moves with
/// ([`PointKinematics::active`]) are visited: the node-only section costs what one node does.
fn point_block(
    kin: &PointKinematics,
    res: &Pulley3dContact,
    tangents: &[Matrix3<f64>; 2],
    (cs, cd): (f64, f64),
    m: &mut Block,
) {
    let kxx = res.k.fixed_view::<3, 3>(0, 0).into_owned();
    let kxt = res.k.fixed_view::<3, 1>(0, 3).into_owned();
    let ktx = res.k.fixed_view::<1, 3>(3, 0).into_owned();
    let cxx = res.c.fixed_view::<3, 3>(0, 0).into_owned();
    let cxt = res.c.fixed_view::<3, 1>(0, 3).into_owned();
    let ctx = res.c.fixed_view::<1, 3>(3, 0).into_owned();
    let add = |m: &mut Block, i: usize, j: usize, a: &Matrix3<f64>| {
        let mut v = m.fixed_view_mut::<3, 3>(i, j);
        v += a;
    };
    let add_col = |m: &mut Block, i: usize, a: &Vector3<f64>| {
        let mut v = m.fixed_view_mut::<3, 1>(i, 12);
        v += a;
    };
    let add_row = |m: &mut Block, j: usize, a: &nalgebra::RowVector3<f64>| {
        let mut v = m.fixed_view_mut::<1, 3>(12, j);
        v += a;
    };
    // ∂F/∂(r, v) and ∂F/∂(θ_p, ω), ∂τ/∂(r, v), weighted
    let a = cs * kxx + cd * cxx;
    let a_p = cs * kxt + cd * cxt;
    let a_row = cs * ktx + cd * ctx;
    let mut g = [Matrix3::zeros(); 2];
    let mut d = [Matrix3::zeros(); 2];
    for n in 0..2 {
        if !kin.active[n] {
            continue;
        }
        let (gn, hn) = kin.spin_maps(n);
        let tn = &tangents[n];
        d[n] = (cs * (kxx * gn + cxx * hn)) * tn + cd * (cxx * gn);
        // torque row: ∂τ/∂θ_n, ∂τ/∂Ω_n
        add_row(m, 6 * n, &(a_row * kin.w[n]));
        add_row(
            m,
            6 * n + 3,
            &((cs * (ktx * gn + ctx * hn)) * tn + cd * (ctx * gn)),
        );
        // the moment's own rotation: δ(R_nᵀ) F = (R_nᵀ F)~ δW_n, with ũ f̃ = f uᵀ − (u·f) I
        let fb = kin.rot[n].transpose() * res.force;
        let u = &kin.u[n];
        add(
            m,
            6 * n + 3,
            6 * n + 3,
            &(cs * (fb * (tn.transpose() * u).transpose() - u.dot(&fb) * tn)),
        );
        g[n] = gn;
    }
    for r in 0..2 {
        if !kin.active[r] {
            continue;
        }
        let (wr, grt) = (kin.w[r], g[r].transpose());
        let ga = grt * a;
        let (rr, rm) = (6 * r, 6 * r + 3);
        for n in 0..2 {
            if !kin.active[n] {
                continue;
            }
            let wn = kin.w[n];
            add(m, rr, 6 * n, &(a * (wr * wn)));
            add(m, rr, 6 * n + 3, &(d[n] * wr));
            add(m, rm, 6 * n, &(ga * wn));
            add(m, rm, 6 * n + 3, &(grt * d[n]));
        }
        add_col(m, rr, &(a_p * wr));
        add_col(m, rm, &(grt * a_p));
    }
    m[(12, 12)] += cs * res.k[(3, 3)] + cd * res.c[(3, 3)];
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assembly::{Assembly, DofMap};
    use crate::elements::finite_difference as fd;
    use nalgebra::{DMatrix, UnitQuaternion};

    use crate::contact::test_laws::belt as law;

    /// A crowned pulley (radius 0.1 m, rim half width 15 mm, crown 0.5 mm, flanges 5 mm
    /// high) with a skew axis off the origin, belt half width `b`.
    fn pulley(b: f64, flange_top: f64) -> Pulley3d {
        Pulley3d::new(
            Vector3::new(0.2, -0.1, 0.05),
            Vector3::new(0.1, -0.2, 1.0),
            0.1,
            0.015,
            5e-4,
            flange_top,
            b,
        )
    }

    /// One element of two nodes (coordinates 0..6 and 6..12, length 4 mm) and the pulley
    /// angle (12), `per_element` sections per element (0: at the first node): the set, its
    /// assembly and node frames (references `r_ref`).
    fn set_along(
        p: Pulley3d,
        n_width: usize,
        per_element: usize,
        law: ContactLaw,
        r_ref: [UnitQuaternion<f64>; 2],
    ) -> (SectionContactSet, Assembly, NodeFrames) {
        let dofs: Vec<usize> = (0..N).collect();
        let asm = Assembly::new(DofMap::new(&[false; N]), &[(N, &dofs)], &[]);
        let blocks = Connectivity::new(vec![std::array::from_fn(|i| i)], &asm);
        let s = SectionContactSet::new(
            law,
            vec![p],
            blocks,
            vec![[0, 1]],
            Vector3::z(),
            Vector3::y(),
            n_width,
            per_element,
            4e-3,
        );
        let mut frames = NodeFrames::new(vec![3, 9]);
        frames.set_reference(0, r_ref[0]);
        frames.set_reference(1, r_ref[1]);
        (s, asm, frames)
    }

    /// The node-only set ([`set_along`] with the section at the first node).
    fn set(
        p: Pulley3d,
        n_width: usize,
        law: ContactLaw,
        r_ref: UnitQuaternion<f64>,
    ) -> (SectionContactSet, Assembly, NodeFrames) {
        set_along(p, n_width, 0, law, [r_ref; 2])
    }

    /// Coordinates of the element of [`set_along`].
    const N: usize = SECTION_BLOCK;

    /// The element's coordinates for the node-only set: node `a`'s and the pulley's from
    /// `q7` (node position, rotation vector, pulley angle), node `b` a copy of node `a`
    /// (the node-only contact does not see it).
    fn two(q7: &[f64; 7]) -> Vec<f64> {
        let mut q = vec![0.0; N];
        q[..6].copy_from_slice(&q7[..6]);
        q[6..12].copy_from_slice(&q7[..6]);
        q[12] = q7[6];
        q
    }

    /// Node frame `[t, a × t, a]` of a point at polar angle `phi` on pulley `p`, turned by
    /// `tilt` about `t` (the section tilted against the axis).
    fn frame_at(
        p: &Pulley3d,
        phi: f64,
        tilt: f64,
    ) -> (Vector3<f64>, Vector3<f64>, UnitQuaternion<f64>) {
        let u1 = p.u1();
        let u2 = p.axis.cross(&u1);
        let e = phi.cos() * u1 + phi.sin() * u2;
        let t = p.axis.cross(&e);
        let m = Matrix3::from_columns(&[t, p.axis.cross(&t), p.axis]);
        let r =
            UnitQuaternion::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(m));
        let tilt = UnitQuaternion::from_scaled_axis(t * tilt);
        (e, t, tilt * r)
    }

    fn residual(s: &SectionContactSet, fr: &mut NodeFrames, q: &[f64], v: &[f64]) -> Vec<f64> {
        fr.update(q);
        let mut f = vec![0.0; N];
        s.add_residual(q, v, fr.current(), &mut f, None);
        f
    }

    /// The scattered iteration matrix against central differences of the residual, in the
    /// coordinates (node position, incremental rotation vector θ ≠ 0, pulley angle) and in the
    /// rates (velocity, body angular velocity, pulley speed).
    fn check_jacobian(
        s: &SectionContactSet,
        asm: &Assembly,
        fr: &mut NodeFrames,
        q: &[f64],
        v: &[f64],
    ) {
        let f0 = residual(s, fr, q, v);
        // in contact; across the width the section also feels a moment
        let moment = f0[3..6].iter().any(|m| m.abs() > 0.0);
        assert!(
            f0[12].abs() > 0.0
                && moment == (s.points_per_section() > 1 || s.stations[0] != Station::NODE),
            "in contact: {f0:?}"
        );
        for (ks, kd) in [(1.0, 0.0), (0.0, 1.0)] {
            let coeffs = JacobianCoeffs {
                mass: 0.0,
                damping: kd,
                stiffness: ks,
            };
            let mut vals = vec![0.0; asm.pattern.nnz()];
            let mut f = vec![0.0; N];
            fr.update(q);
            s.add_residual(q, v, fr.current(), &mut f, Some((coeffs, &mut vals)));
            let x0 = if ks > 0.0 { q } else { v };
            let num = fd::jacobian(
                x0,
                N,
                |j| {
                    if ks == 0.0 || j % 6 >= 3 || j == 12 {
                        1e-7
                    } else {
                        1e-10
                    }
                },
                |x, out| {
                    let (qq, vv) = if ks > 0.0 { (x, v) } else { (q, x) };
                    out.copy_from_slice(&residual(s, fr, qq, vv));
                },
            );
            let an = DMatrix::from_fn(N, N, |i, j| {
                asm.pattern.position(i, j).map_or(0.0, |p| vals[p])
            });
            let scale = f0.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            fd::assert_close(&format!("ks {ks} kd {kd}"), &an, &num, 1e-5, 1e-6 * scale);
        }
    }

    /// Three and four points across a section tilted against the crown, pressed in, moving and
    /// spinning, with friction histories that stick (and, with a slipped history, slide).
    #[test]
    fn section_tangent_matches_finite_differences() {
        for (n_width, slip) in [(3, false), (3, true), (4, false), (1, true)] {
            let p = pulley(0.008, 0.0);
            let (phi, zeta) = (0.7, 0.003);
            let (e, t, rref) = frame_at(&p, phi, 0.01);
            let (mut s, asm, mut fr) = set(p, n_width, law(), rref);
            let r = p.center + (p.rim_radius(zeta).0 - 3e-5) * e + zeta * p.axis;
            let theta_p = 0.31;
            let om = Vector3::new(0.3, -0.2, 0.5);
            let vel = 0.4 * t + 0.05 * p.axis - 0.01 * e;
            let q = two(&[r.x, r.y, r.z, 0.002, -0.003, 0.004, theta_p]);
            let v = two(&[vel.x, vel.y, vel.z, om.x, om.y, om.z, 4.0]);
            // histories: every point 1e-5 rad back along the rim (stick) or 2 mm (slip)
            let back = if slip { 0.02 } else { 1e-5 };
            stuck_histories(&mut s, phi - back, zeta, theta_p);
            check_jacobian(&s, &asm, &mut fr, &q, &v);
        }
    }

    /// Every point's history anchored at rim angle `phi`, axial place `zeta` and pulley angle
    /// `theta_p − 1e-5`, with a small bristle deflection.
    fn stuck_histories(s: &mut SectionContactSet, phi: f64, zeta: f64, theta_p: f64) {
        for h in s.hist.iter_mut() {
            *h = Pulley3dHistory {
                phi,
                zeta,
                theta: theta_p - 1e-5,
                z: [1e-7, -2e-8],
                f: [0.0; 2],
            };
        }
    }

    /// The belt's edge points on the flange (the section pushed 10 mm off the middle of the
    /// rim: its edge at 18 mm, the flange face at 15 mm): the flange's push, its tangent, and
    /// only the edge points touch it.
    #[test]
    fn edge_points_meet_the_flange() {
        let p = pulley(0.008, 0.105);
        let (phi, zeta) = (-0.4, 0.010);
        let (e, t, rref) = frame_at(&p, phi, -0.02);
        let (mut s, asm, mut fr) = set(p, 3, law(), rref);
        let r = p.center + (p.rim_radius(zeta).0 - 2e-5) * e + zeta * p.axis;
        let q = two(&[r.x, r.y, r.z, 0.0, 0.0, 0.0, 0.0]);
        let vel = 0.2 * t;
        let v = two(&[vel.x, vel.y, vel.z, 0.1, 0.0, 0.0, 2.0]);
        check_jacobian(&s, &asm, &mut fr, &q, &v);
        fr.update(&q);
        s.commit(&q, &v, &fr, false);
        assert!(
            s.loads()[0].side_force > 0.0,
            "the belt pushes the flange at +h outwards: {}",
            s.loads()[0].side_force
        );
    }

    /// A flat section lying on the crown's slope (width director along the axis, all three
    /// points in contact, frictionless, at rest) feels the moment about the belt's tangent
    /// `k_n l R'(ζ) b²/3` (the section conforms to the barrel, so the penetration varies as
    /// `δ₀ + R' s` across the width: `Σ w_j s_j p_j` with the Lobatto weights; to 1e-3, the
    /// droop's own lever `κ s²/2` adds a second-order term), which turns the
    /// section onto the cone (towards the larger radius: a negative moment about `t` for
    /// `R' < 0`). The centre-line contact (one point) has none.
    #[test]
    fn section_on_the_crown_slope_feels_the_tilting_moment() {
        let b = 0.008;
        let p = pulley(b, 0.0);
        let mut frictionless = law();
        frictionless.mu = 0.0;
        frictionless.d_n = 0.0;
        let (phi, zeta) = (1.2, 0.004);
        let (e, t, rref) = frame_at(&p, phi, 0.0);
        let r = p.center + (p.rim_radius(zeta).0 - 5e-4) * e + zeta * p.axis;
        let q = two(&[r.x, r.y, r.z, 0.0, 0.0, 0.0, 0.0]);
        let v = vec![0.0; N];
        let (s3, _, mut fr) = set(p, 3, frictionless, rref);
        let f = residual(&s3, &mut fr, &q, &v);
        // the residual holds −(body moment); body axis x of the frame is t
        let m_t = -f[3];
        let slope = p.rim_radius(zeta).1;
        let expect = frictionless.k_n * 4e-3 * slope * b * b / 3.0;
        assert!(slope < 0.0);
        assert!(
            (m_t - expect).abs() <= 1e-3 * expect.abs(),
            "moment about t {m_t} vs k_n l R' b²/3 = {expect}"
        );
        let _ = t;
        let (s1, _, mut fr1) = set(p, 1, frictionless, rref);
        let f1 = residual(&s1, &mut fr1, &q, &v);
        assert_eq!(&f1[3..6], &[0.0; 3]);
    }

    /// An element of 4 mm wrapped on the crowned, skewed pulley (nodes on the rim at polar
    /// angles φ and φ + l/R, pressed in, their sections tilted and twisted against each
    /// other, moving and spinning), its sections between the nodes (1, 2, 3 per element;
    /// 1 and 3 points across the width), with friction histories that stick and that slide:
    /// the scattered iteration matrix of both nodes and the pulley against central
    /// differences.
    #[test]
    fn sections_between_the_nodes_match_finite_differences() {
        let p = pulley(0.008, 0.105);
        let (phi, zeta) = (0.7, 0.003);
        let dphi = 4e-3 / p.radius;
        for (n_width, per_element, slip) in [
            (3, 2, false),
            (3, 2, true),
            (1, 1, true),
            (3, 3, false),
            (1, 2, false),
        ] {
            let (ea, ta, ra) = frame_at(&p, phi, 0.01);
            let (eb, tb, rb) = frame_at(&p, phi + dphi, -0.02);
            let (mut s, asm, mut fr) = set_along(p, n_width, per_element, law(), [ra, rb]);
            let xa = p.center + (p.rim_radius(zeta).0 - 3e-5) * ea + zeta * p.axis;
            let xb = p.center + (p.rim_radius(zeta + 1e-4).0 - 2e-5) * eb + (zeta + 1e-4) * p.axis;
            let theta_p = 0.31;
            let (oa, ob) = (Vector3::new(0.3, -0.2, 0.5), Vector3::new(-0.1, 0.4, 0.2));
            let (va, vb) = (
                0.4 * ta + 0.05 * p.axis - 0.01 * ea,
                0.41 * tb - 0.02 * p.axis + 0.02 * eb,
            );
            let q = [
                xa.x, xa.y, xa.z, 0.002, -0.003, 0.004, xb.x, xb.y, xb.z, -0.001, 0.002, 0.003,
                theta_p,
            ];
            let v = [
                va.x, va.y, va.z, oa.x, oa.y, oa.z, vb.x, vb.y, vb.z, ob.x, ob.y, ob.z, 4.0,
            ];
            let back = if slip { 0.02 } else { 1e-5 };
            stuck_histories(&mut s, phi + 0.5 * dphi - back, zeta, theta_p);
            check_jacobian(&s, &asm, &mut fr, &q, &v);
        }
    }

    /// The broad phase per element ([`SectionContactSet::element_near`]) rejects only
    /// elements none of whose sections passes the section test: random elements around the
    /// crowned, flanged, skewed pulley (first node within 0.15 m of its centre per axis, the
    /// second up to 17 mm away, four times the element length, random orientations), 0 to 3
    /// sections per element.
    #[test]
    fn broad_phase_keeps_every_near_section() {
        let p = pulley(0.008, 0.105);
        let mut seed = 0x5eed_u64;
        let mut rnd = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        for per_element in 0..=3 {
            let (s, _, mut fr) =
                set_along(p, 3, per_element, law(), [UnitQuaternion::identity(); 2]);
            let mut count = [0usize; 3];
            for _ in 0..20000 {
                let ra = p.center + 0.15 * Vector3::new(rnd(), rnd(), rnd());
                let rb = ra + 0.01 * Vector3::new(rnd(), rnd(), rnd());
                let q = [
                    ra.x,
                    ra.y,
                    ra.z,
                    rnd(),
                    rnd(),
                    rnd(),
                    rb.x,
                    rb.y,
                    rb.z,
                    rnd(),
                    rnd(),
                    rnd(),
                    0.0,
                ];
                fr.update(&q);
                let rot = [fr.current()[0].rot, fr.current()[1].rot];
                let near = s.stations.iter().any(|st| {
                    let (c, d) = s.centre(0, st, &rot, &q);
                    s.near(0, &c, &d)
                });
                let broad = s.element_near(0, 0, &q);
                assert!(
                    broad || !near,
                    "{per_element} sections: a near section rejected at {q:?}"
                );
                count[usize::from(near) + usize::from(broad)] += 1;
            }
            // some elements are rejected, some pass without a near section, some are near
            assert!(count.iter().all(|&c| c > 100), "{count:?}");
        }
    }

    /// Sections between the nodes lie on the pulley where the belt does: an element wrapped
    /// on a flat rim (both nodes pressed in by δ = 20 µm, tangents along the rim, frictionless,
    /// at rest) presses on it with `k_n l δ` in total (smoothed penalty: `δ − δ₀/2`), along
    /// the bisector of its nodes, with 1 to 4 sections per element (the Hermite centre line
    /// of a circular arc is off the arc by about `R Δφ⁴/2000`, 1e-10 m here, against δ).
    #[test]
    fn sections_of_a_wrapped_element_press_as_the_arc() {
        let p = Pulley3d::new(
            Vector3::new(0.2, -0.1, 0.05),
            Vector3::new(0.1, -0.2, 1.0),
            0.1,
            0.015,
            0.0,
            0.0,
            0.008,
        );
        let mut frictionless = law();
        frictionless.mu = 0.0;
        frictionless.d_n = 0.0;
        let (phi, dphi, delta) = (0.3, 0.04, 2e-5);
        let (ea, _, ra) = frame_at(&p, phi, 0.0);
        let (eb, _, rb) = frame_at(&p, phi + dphi, 0.0);
        let r = p.rim_radius(0.0).0 - delta;
        let (xa, xb) = (p.center + r * ea, p.center + r * eb);
        let l = (p.radius - delta) * dphi;
        let q = [
            xa.x, xa.y, xa.z, 0.0, 0.0, 0.0, xb.x, xb.y, xb.z, 0.0, 0.0, 0.0, 0.0,
        ];
        let v = vec![0.0; N];
        let bisector = (ea + eb).normalize();
        for per_element in 1..=4 {
            for n_width in [1, 3] {
                let (mut s, _, mut fr) = set_along(p, n_width, per_element, frictionless, [ra, rb]);
                s.set_length(l);
                let f = residual(&s, &mut fr, &q, &v);
                // the residual holds −(forces on the nodes)
                let total = -(Vector3::new(f[0], f[1], f[2]) + Vector3::new(f[6], f[7], f[8]));
                // (the law's penalty is smoothed: k_n (δ − δ₀/2) beyond δ₀)
                let expect = frictionless.k_n * l * (delta - 0.5 * frictionless.smoothing);
                let along = total.dot(&bisector);
                assert!(
                    (along - expect).abs() < 1e-4 * expect
                        && (total - along * bisector).norm() < 1e-3 * expect,
                    "{per_element} sections, {n_width} across: force {total:?} ({along} along the bisector) vs k_n l δ = {expect}"
                );
            }
        }
    }
}
