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

use super::circle_friction::ContactLaw;
use super::obstacle::{Obstacle, ObstacleContact, PointMotion};
use super::point_set::{
    ContactBook, ObstacleLoad, read_histories, read_loads, write_histories, write_loads,
};
use super::pulley3d::{Pulley3d, Pulley3dContact, Pulley3dHistory, evaluate_parts};
use crate::assembly::Connectivity;
use crate::elements::element::Frame;
use crate::elements::node_frames::NodeFrames;
use crate::elements::quadrature::lobatto;
use crate::elements::rotation::skew;
use crate::model::JacobianCoeffs;
use crate::snapshot::{StateReader, StateWriter};
use nalgebra::{Matrix3, SMatrix, Vector3};

/// Coordinates of one (node, pulley) block: node position (3), node rotation vector (3),
/// pulley angle (1).
pub const SECTION_BLOCK: usize = 7;

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

/// Contact of the sections of a belt's nodes against 3D pulleys.
#[derive(Clone, Debug)]
pub struct SectionContactSet {
    law: ContactLaw,
    /// The pulleys as given (belt half width: the centre-line point's flange test).
    obstacles: Vec<Pulley3d>,
    /// The pulleys as seen by points across the width (belt half width 0: each point is its
    /// own edge).
    across: Vec<Pulley3d>,
    blocks: Connectivity<SECTION_BLOCK>,
    n_nodes: usize,
    /// Width axis of the section in the node frame (unit).
    width_axis: Vector3<f64>,
    /// Thickness axis of the section in the node frame (unit).
    normal_axis: Vector3<f64>,
    points: Vec<WidthPoint>,
    /// Belt length a node stands for [m].
    length: f64,
    /// Histories by node, point, pulley.
    hist: Vec<Pulley3dHistory>,
    loads: Vec<ObstacleLoad<3>>,
}

/// Point motion, body spin map `G` and `H = ∂v/∂W` of a width point.
struct PointKinematics {
    motion: PointMotion<3>,
    g: Matrix3<f64>,
    h: Matrix3<f64>,
    rot: Matrix3<f64>,
    /// Offset of the point from the node in the node frame [m].
    p: Vector3<f64>,
}

impl SectionContactSet {
    /// Sections of the nodes in `blocks` (row `k · n_pulleys + p`: node `k`'s position and
    /// rotation vector, then pulley `p`'s angle) against `obstacles`, each node's section
    /// with its width axis `width_axis` and thickness axis `normal_axis` in the node frame,
    /// `n_width` Lobatto points across
    /// the width (1: the centre line only), each node standing for the belt length
    /// `length` [m]. The belt's half width is the pulleys' `belt_half_width`.
    pub fn new(
        law: ContactLaw,
        obstacles: Vec<Pulley3d>,
        blocks: Connectivity<SECTION_BLOCK>,
        width_axis: Vector3<f64>,
        normal_axis: Vector3<f64>,
        n_width: usize,
        length: f64,
    ) -> Self {
        let no = obstacles.len().max(1);
        let n_nodes = blocks.len() / no;
        let b = obstacles.first().map_or(0.0, |o| o.belt_half_width);
        let points: Vec<WidthPoint> = lobatto(n_width)
            .iter()
            .map(|&(xi, w)| WidthPoint {
                s: b * xi,
                share: 0.5 * w,
                edge: n_width > 1 && xi.abs() == 1.0,
            })
            .collect();
        let across = obstacles
            .iter()
            .map(|o| {
                let mut p = *o;
                p.belt_half_width = 0.0;
                p
            })
            .collect();
        Self {
            law,
            loads: vec![ObstacleLoad::default(); obstacles.len()],
            hist: vec![Pulley3dHistory::default(); n_nodes * points.len() * obstacles.len()],
            obstacles,
            across,
            blocks,
            n_nodes,
            width_axis: width_axis.normalize(),
            normal_axis: normal_axis.normalize(),
            points,
            length,
        }
    }

    /// Sets the belt length a node stands for [m] (histories kept).
    pub fn set_length(&mut self, length: f64) {
        self.length = length;
    }

    /// Points across the width of every section.
    pub fn points_per_section(&self) -> usize {
        self.points.len()
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

    /// Whether node block `b` (node position `r`, width director `d`) can touch pulley `k`.
    #[inline(always)]
    fn near(&self, k: usize, r: &Vector3<f64>, d: &Vector3<f64>) -> bool {
        let b = self.obstacles[k].belt_half_width;
        self.obstacles[k].near(&(r - b * d), &(r + b * d))
    }

    /// Sign `σ` and crown curvature `κ` [1/m] of the section's conforming offset on pulley
    /// `k` for a node at `r` with rotation `rot` (module docs).
    #[inline(always)]
    fn conform(&self, k: usize, r: &Vector3<f64>, rot: &Matrix3<f64>) -> (f64, f64) {
        let ob = &self.obstacles[k];
        if self.points.len() == 1 || ob.crown == 0.0 || ob.half_width <= 0.0 {
            return (0.0, 0.0);
        }
        let d = r - ob.center;
        let radial = d - ob.axis.dot(&d) * ob.axis;
        let sigma = if radial.dot(&(rot * self.normal_axis)) > 0.0 {
            -1.0
        } else {
            1.0
        };
        (sigma, 2.0 * ob.crown / (ob.half_width * ob.half_width))
    }

    /// Motion of width point `j` of block `b` with node rotation `rot`, conforming offset
    /// `(σ, κ)` of [`Self::conform`].
    #[inline(always)]
    fn kinematics(
        &self,
        b: usize,
        j: usize,
        rot: &Matrix3<f64>,
        (sigma, kappa): (f64, f64),
        q: &[f64],
        v: &[f64],
    ) -> PointKinematics {
        let dofs = self.blocks.dofs(b);
        let r = Vector3::new(q[dofs[0]], q[dofs[1]], q[dofs[2]]);
        let vel = Vector3::new(v[dofs[0]], v[dofs[1]], v[dofs[2]]);
        let om = Vector3::new(v[dofs[3]], v[dofs[4]], v[dofs[5]]);
        let s = self.points[j].s;
        let p = s * self.width_axis + (0.5 * sigma * kappa * s * s) * self.normal_axis;
        let g = -rot * skew(&p);
        let h = -rot * skew(&om.cross(&p));
        PointKinematics {
            motion: PointMotion {
                r: r + rot * p,
                v: vel + rot * om.cross(&p),
            },
            g,
            h,
            rot: *rot,
            p,
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
        let np = self.points.len();
        let (mut kb, mut cb) = (Block::zeros(), Block::zeros());
        for node in 0..self.n_nodes {
            let fr = &frames[node];
            let d = fr.rot * self.width_axis;
            for k in 0..no {
                let b = node * no + k;
                let dofs = self.blocks.dofs(b);
                let r = Vector3::new(q[dofs[0]], q[dofs[1]], q[dofs[2]]);
                if !self.near(k, &r, &d) {
                    continue;
                }
                let (theta, omega) = (q[dofs[6]], v[dofs[6]]);
                let conform = self.conform(k, &r, &fr.rot);
                let mut any = false;
                kb.fill(0.0);
                cb.fill(0.0);
                for j in 0..np {
                    let kin = self.kinematics(b, j, &fr.rot, conform, q, v);
                    let (ob, w_rim, w_fl) = self.pulley_for(j, k);
                    let h = &self.hist[(node * np + j) * no + k];
                    let Some(res) =
                        evaluate_parts(ob, &self.law, w_rim, w_fl, &kin.motion, theta, omega, h)
                    else {
                        continue;
                    };
                    any = true;
                    let moment = kin.g.transpose() * res.force;
                    for c in 0..3 {
                        f[dofs[c]] -= res.force[c];
                        f[dofs[3 + c]] -= moment[c];
                    }
                    f[dofs[6]] -= res.torque;
                    if jac.is_some() {
                        point_block(&kin, &res, &mut kb, &mut cb);
                    }
                }
                if any && let Some((c, vals)) = jac.as_mut() {
                    // rotation columns of the stiffness: δW = T(θ) δθ
                    let cols = kb.fixed_view::<SECTION_BLOCK, 3>(0, 3) * fr.tangent;
                    kb.fixed_view_mut::<SECTION_BLOCK, 3>(0, 3).copy_from(&cols);
                    let m = kb * c.stiffness + cb * c.damping;
                    self.blocks.add_matrix(b, &m, -1.0, vals);
                }
            }
        }
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
        let np = self.points.len();
        self.loads.fill(ObstacleLoad::default());
        let mut book = ContactBook::default();
        for node in 0..self.n_nodes {
            let rot = frames.rotation(node, q);
            let d = rot * self.width_axis;
            for k in 0..no {
                let b = node * no + k;
                let dofs = self.blocks.dofs(b);
                let r = Vector3::new(q[dofs[0]], q[dofs[1]], q[dofs[2]]);
                let near = self.near(k, &r, &d);
                let x = [q[dofs[6]]];
                let conform = self.conform(k, &r, &rot);
                for j in 0..np {
                    let idx = (node * np + j) * no + k;
                    let kin = self.kinematics(b, j, &rot, conform, q, v);
                    let h = self.hist[idx];
                    let (ob, w_rim, w_fl) = self.pulley_for(j, k);
                    let ob = *ob;
                    let res = if near && !initial {
                        evaluate_parts(
                            &ob,
                            &self.law,
                            w_rim,
                            w_fl,
                            &kin.motion,
                            x[0],
                            v[dofs[6]],
                            &h,
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

/// Derivatives `K = ∂Q/∂(r, W, θ_p)` and `C = ∂Q/∂(v, Ω, ω)` of the generalized forces
/// `Q` = (force on the node, body moment `Gᵀ F`, torque on the pulley) of one width point
/// at the offset `p` of `kin` (module docs), rotation columns with respect to the body spin
/// `W`.
fn point_block(kin: &PointKinematics, res: &Pulley3dContact, kb: &mut Block, cb: &mut Block) {
    let kxx = res.k.fixed_view::<3, 3>(0, 0).into_owned();
    let kxt = res.k.fixed_view::<3, 1>(0, 3).into_owned();
    let ktx = res.k.fixed_view::<1, 3>(3, 0).into_owned();
    let cxx = res.c.fixed_view::<3, 3>(0, 0).into_owned();
    let cxt = res.c.fixed_view::<3, 1>(0, 3).into_owned();
    let ctx = res.c.fixed_view::<1, 3>(3, 0).into_owned();
    let (g, h) = (kin.g, kin.h);
    let gt = g.transpose();
    let f_w = kxx * g + cxx * h;
    let fb = kin.rot.transpose() * res.force;
    let add =
        |m: &mut Block, i: usize, j: usize, a: &dyn Fn(usize, usize) -> f64, r: usize, c: usize| {
            for ii in 0..r {
                for jj in 0..c {
                    m[(i + ii, j + jj)] += a(ii, jj);
                }
            }
        };
    // stiffness: columns r, W, θ_p
    add(kb, 0, 0, &|i, j| kxx[(i, j)], 3, 3);
    add(kb, 0, 3, &|i, j| f_w[(i, j)], 3, 3);
    add(kb, 0, 6, &|i, _| kxt[i], 3, 1);
    let m_r = gt * kxx;
    let m_w = gt * f_w + skew(&kin.p) * skew(&fb);
    let m_t = gt * kxt;
    add(kb, 3, 0, &|i, j| m_r[(i, j)], 3, 3);
    add(kb, 3, 3, &|i, j| m_w[(i, j)], 3, 3);
    add(kb, 3, 6, &|i, _| m_t[i], 3, 1);
    let t_w = ktx * g + ctx * h;
    add(kb, 6, 0, &|_, j| ktx[j], 1, 3);
    add(kb, 6, 3, &|_, j| t_w[j], 1, 3);
    kb[(6, 6)] += res.k[(3, 3)];
    // damping: columns v, Ω, ω
    let f_om = cxx * g;
    let m_v = gt * cxx;
    let m_om = gt * f_om;
    let m_tc = gt * cxt;
    let t_om = ctx * g;
    add(cb, 0, 0, &|i, j| cxx[(i, j)], 3, 3);
    add(cb, 0, 3, &|i, j| f_om[(i, j)], 3, 3);
    add(cb, 0, 6, &|i, _| cxt[i], 3, 1);
    add(cb, 3, 0, &|i, j| m_v[(i, j)], 3, 3);
    add(cb, 3, 3, &|i, j| m_om[(i, j)], 3, 3);
    add(cb, 3, 6, &|i, _| m_tc[i], 3, 1);
    add(cb, 6, 0, &|_, j| ctx[j], 1, 3);
    add(cb, 6, 3, &|_, j| t_om[j], 1, 3);
    cb[(6, 6)] += res.c[(3, 3)];
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

    /// One node (coordinates 0..6) and the pulley angle (6): the set, its assembly and node
    /// frames.
    fn set(
        p: Pulley3d,
        n_width: usize,
        law: ContactLaw,
        r_ref: UnitQuaternion<f64>,
    ) -> (SectionContactSet, Assembly, NodeFrames) {
        let dofs: Vec<usize> = (0..7).collect();
        let asm = Assembly::new(DofMap::new(&[false; 7]), &[(7, &dofs)], &[]);
        let blocks = Connectivity::new(vec![std::array::from_fn(|i| i)], &asm);
        let s = SectionContactSet::new(
            law,
            vec![p],
            blocks,
            Vector3::z(),
            Vector3::y(),
            n_width,
            4e-3,
        );
        let mut frames = NodeFrames::new(vec![3]);
        frames.set_reference(0, r_ref);
        (s, asm, frames)
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
        let mut f = vec![0.0; 7];
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
            f0[6].abs() > 0.0 && moment == (s.points_per_section() > 1),
            "in contact: {f0:?}"
        );
        for (ks, kd) in [(1.0, 0.0), (0.0, 1.0)] {
            let coeffs = JacobianCoeffs {
                mass: 0.0,
                damping: kd,
                stiffness: ks,
            };
            let mut vals = vec![0.0; asm.pattern.nnz()];
            let mut f = vec![0.0; 7];
            fr.update(q);
            s.add_residual(q, v, fr.current(), &mut f, Some((coeffs, &mut vals)));
            let x0 = if ks > 0.0 { q } else { v };
            let num = fd::jacobian(
                x0,
                7,
                |j| if ks == 0.0 || j >= 3 { 1e-7 } else { 1e-10 },
                |x, out| {
                    let (qq, vv) = if ks > 0.0 { (x, v) } else { (q, x) };
                    out.copy_from_slice(&residual(s, fr, qq, vv));
                },
            );
            let an = DMatrix::from_fn(7, 7, |i, j| {
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
            let q = [r.x, r.y, r.z, 0.002, -0.003, 0.004, theta_p];
            let v = [vel.x, vel.y, vel.z, om.x, om.y, om.z, 4.0];
            // histories: every point 1e-5 rad back along the rim (stick) or 2 mm (slip)
            let back = if slip { 0.02 } else { 1e-5 };
            for h in s.hist.iter_mut() {
                *h = Pulley3dHistory {
                    phi: phi - back,
                    zeta,
                    theta: theta_p - 1e-5,
                    z: [1e-7, -2e-8],
                    f: [0.0; 2],
                };
            }
            check_jacobian(&s, &asm, &mut fr, &q, &v);
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
        let q = [r.x, r.y, r.z, 0.0, 0.0, 0.0, 0.0];
        let vel = 0.2 * t;
        let v = [vel.x, vel.y, vel.z, 0.1, 0.0, 0.0, 2.0];
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
        let q = [r.x, r.y, r.z, 0.0, 0.0, 0.0, 0.0];
        let v = [0.0; 7];
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
}
