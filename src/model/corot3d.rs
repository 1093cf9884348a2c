//! A 3D beam meshed with seed-003 co-rotational elements along a centre line of straight and
//! circular pieces: supports, point loads (fixed-direction or follower forces and moments),
//! gravity, probes and energies.
//!
//! **Coordinates.** Per node `[x, y, z, θx, θy, θz]`: the absolute position [m] and an
//! *incremental* rotation vector θ [rad] from the node's stored orientation `R_ref` (a unit
//! quaternion): `R = R_ref exp(θ̃)`. Velocities are `[ẋ, Ω]` with the body angular velocity
//! `Ω` (`Ṙ = R Ω̃`), accelerations `[ẍ, Ω̇]`. After every accepted time step
//! ([`Model::accept`]) and every converged static load increment
//! ([`MechanicalSystem::rebase`]) θ is absorbed into `R_ref` and reset to zero. With the
//! integrators' additive update `θ_{n+1} = h Ω_n + h²(½ − β) a_n + h² β a_{n+1}` from θ_n = 0,
//! every step is then the Lie-group Newmark / generalized-α update `R_{n+1} = R_n exp(θ̃)` of
//! Brüls, Cardona & Arnold 2012 (`shared/reference/time-integration.md` F.1), with velocities
//! and accelerations that need no re-expression. Orientations are never described by a total
//! rotation vector, so the body may turn through any number of revolutions; θ only has to
//! stay below 2π within one step or load increment (the singularity of `T(θ)`).
//!
//! **Residual.** `r = f_inertia(q, v, a) + f_int(q) − λ f_ext(q)`; force rows in global
//! components, moment rows in body components (premultiplying the moment balance by the
//! invertible `T(θ)ᵀ` is unnecessary, so it is not done). The iteration matrix is exact:
//! element tangents with respect to body spins times `T(θ)` on the rotation columns.

use super::system::{JacobianCoeffs, MechanicalSystem, Model, ModelError};
use crate::assembly::{Assembly, DofMap};
use crate::elements::corotational3d::{
    BeamSection, Corot3d, ELEMENT_DOFS, MassModel, Mat12, NODE_DOFS, Nodes, Rates, Theory, Vec12,
    reference_frame,
};
use crate::elements::rotation::{exp_so3, skew, tangent_body};
use crate::integrators::DynState;
use crate::kinds::KindIo;
use crate::kinds::beam_3d::scene::{Input, Output, io, names::*};
use crate::kinds::beam_3d::{Beam3dScene, CentrelineSection};
use crate::kinds::energy::EnergyKind;
use crate::linalg::CscPattern;
use crate::scene::params::{ParamValues, names::*};
use crate::scene::tables::{ProbeQuantity, SupportKind};
use crate::snapshot::{StateReader, StateWriter};
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// Reference nodes of a centre line.
#[derive(Clone, Debug)]
struct Mesh {
    /// Node positions [m].
    x: Vec<Vector3<f64>>,
    /// Arc length of each node along the centre line [m].
    s: Vec<f64>,
    /// Reference section frame of each element.
    frames: Vec<Matrix3<f64>>,
}

fn vec3(a: &[f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

/// Nodes along the centre line: `n_el` elements shared among the pieces in proportion to their
/// lengths (largest remainder, at least one each); piece ends are always nodes.
fn mesh(c: &CentrelineSection, n_el: usize) -> Result<Mesh, String> {
    let n_pieces = c.segments.len();
    if n_el < n_pieces {
        return Err(format!(
            "{MESH_N_ELEMENTS} = {n_el}: the centre line has {n_pieces} pieces and each needs at least one element"
        ));
    }
    // Geometry of every piece: start point, start tangent, length, and a point function.
    enum Piece {
        Line {
            p: Vector3<f64>,
            t: Vector3<f64>,
            len: f64,
        },
        Arc {
            p: Vector3<f64>,
            t: Vector3<f64>,
            n: Vector3<f64>,
            r: f64,
            phi: f64,
        },
    }
    let mut pieces = Vec::with_capacity(n_pieces);
    let mut p = vec3(&c.start);
    let mut t = Vector3::x();
    for (i, seg) in c.segments.iter().enumerate() {
        if let Some(d) = &seg.direction {
            t = vec3(d).normalize();
        }
        match (seg.length, seg.radius, seg.angle_deg, &seg.bend_axis) {
            (Some(len), ..) => {
                pieces.push(Piece::Line { p, t, len });
                p += t * len;
            }
            (None, Some(r), Some(a), Some(b)) => {
                let b = vec3(b);
                let bp = b - t * b.dot(&t);
                if bp.norm() < 1e-8 * b.norm() {
                    return Err(format!(
                        "centreline.segments[{i}].bend_axis: parallel to the tangent {t:?}"
                    ));
                }
                let n = bp.normalize().cross(&t);
                let phi = a.to_radians();
                pieces.push(Piece::Arc { p, t, n, r, phi });
                p += (t * phi.sin() + n * (1.0 - phi.cos())) * r;
                t = t * phi.cos() + n * phi.sin();
            }
            _ => return Err(format!("centreline.segments[{i}]: incomplete piece")),
        }
    }
    let lengths: Vec<f64> = pieces
        .iter()
        .map(|pc| match pc {
            Piece::Line { len, .. } => *len,
            Piece::Arc { r, phi, .. } => r * phi,
        })
        .collect();
    let total: f64 = lengths.iter().sum();
    // Largest-remainder distribution with at least one element per piece.
    let exact: Vec<f64> = lengths.iter().map(|l| n_el as f64 * l / total).collect();
    let mut counts: Vec<usize> = exact.iter().map(|e| (e.floor() as usize).max(1)).collect();
    while counts.iter().sum::<usize>() > n_el {
        let k = (0..n_pieces)
            .filter(|&k| counts[k] > 1)
            .max_by(|&a, &b| {
                (counts[a] as f64 - exact[a]).total_cmp(&(counts[b] as f64 - exact[b]))
            })
            .ok_or("cannot distribute the elements")?;
        counts[k] -= 1;
    }
    while counts.iter().sum::<usize>() < n_el {
        let k = (0..n_pieces)
            .max_by(|&a, &b| {
                (exact[a] - counts[a] as f64).total_cmp(&(exact[b] - counts[b] as f64))
            })
            .ok_or("cannot distribute the elements")?;
        counts[k] += 1;
    }
    let mut x = vec![vec3(&c.start)];
    let mut s = vec![0.0];
    let mut s0 = 0.0;
    for (k, pc) in pieces.iter().enumerate() {
        let m = counts[k];
        for j in 1..=m {
            let u = j as f64 / m as f64;
            let point = match pc {
                Piece::Line { p, t, len } => p + t * (len * u),
                Piece::Arc { p, t, n, r, phi } => {
                    let a = phi * u;
                    p + (t * a.sin() + n * (1.0 - a.cos())) * *r
                }
            };
            x.push(point);
            s.push(s0 + lengths[k] * u);
        }
        s0 += lengths[k];
    }
    let hint = c.section_z.as_ref().map_or(Vector3::z(), vec3);
    let mut frames = Vec::with_capacity(n_el);
    for e in 0..n_el {
        let f = reference_frame(&x[e], &x[e + 1], &hint)
            .or_else(|| reference_frame(&x[e], &x[e + 1], &Vector3::y()))
            .ok_or_else(|| format!("element {e}: degenerate reference geometry"))?;
        frames.push(f);
    }
    Ok(Mesh { x, s, frames })
}

/// A point load at a node.
#[derive(Clone, Copy, Debug)]
struct NodeLoad {
    node: usize,
    /// `[fx, fy, fz, mx, my, mz]` [N, N m].
    values: [f64; 6],
    follower: bool,
}

/// A probe at a node.
#[derive(Clone, Copy, Debug)]
struct NodeProbe {
    node: usize,
    /// Reference direction of the beam axis at the node.
    tangent: Vector3<f64>,
}

/// The seed-003 3D beam model.
#[derive(Clone, Debug)]
pub struct Beam3d {
    length: f64,
    elements: Vec<Corot3d>,
    r_ref: Vec<UnitQuaternion<f64>>,
    asm: Assembly,
    gravity: Vector3<f64>,
    loads: Vec<NodeLoad>,
    probes: Vec<NodeProbe>,
    scales: Vec<f64>,
    // committed state (outputs are computed from it)
    q: Vec<f64>,
    v: Vec<f64>,
    // work buffers
    qw: Vec<f64>,
    vw: Vec<f64>,
    aw: Vec<f64>,
    fw: Vec<f64>,
    qmid: Vec<f64>,
    rot: Vec<Matrix3<f64>>,
    tan: Vec<Matrix3<f64>>,
    /// What each input and output means, by index.
    roles: KindIo<Input, Output>,
}

impl Beam3d {
    /// Builds the model of a scene with the given parameter values (already validated).
    /// Errors name the scene key or parameter at fault.
    pub fn build(scene: &Beam3dScene, p: &ParamValues) -> Result<Self, String> {
        let c = &scene.centreline;
        let n_el = p.integer(MESH_N_ELEMENTS) as usize;
        let section = BeamSection {
            ea: p.real(SECTION_EA),
            ga_y: p.real(SECTION_GAY),
            ga_z: p.real(SECTION_GAZ),
            gj: p.real(SECTION_GJ),
            ei_y: p.real(SECTION_EIY),
            ei_z: p.real(SECTION_EIZ),
            rho_a: p.real(SECTION_RHOA),
            rho_jx: p.real(SECTION_RHOJX),
            rho_iy: p.real(SECTION_RHOIY),
            rho_iz: p.real(SECTION_RHOIZ),
        };
        let e = section.euler_tensor();
        // Rounded data (rhoJx = 2 rhoI to a few digits) are accepted; the element clips the
        // second moments at zero.
        if e.min() < -1e-3 * (section.rho_jx + section.rho_iy + section.rho_iz) {
            return Err(format!(
                "{SECTION_RHOJX} = {}, {SECTION_RHOIY} = {}, {SECTION_RHOIZ} = {}: not the inertia of a cross-section; each must not exceed the sum of the other two (for a thin section rhoJx = rhoIy + rhoIz)",
                section.rho_jx, section.rho_iy, section.rho_iz
            ));
        }
        let theory = match p.integer(ELEMENT_THEORY) {
            1 => Theory::EulerBernoulli,
            _ => Theory::Timoshenko,
        };
        let mass = match p.integer(ELEMENT_MASS) {
            2 => MassModel::Consistent,
            _ => MassModel::Lumped,
        };
        let gravity = Vector3::new(
            p.get(GRAVITY_X).map_or(0.0, |_| p.real(GRAVITY_X)),
            p.get(GRAVITY_Y).map_or(0.0, |_| p.real(GRAVITY_Y)),
            p.get(GRAVITY_Z).map_or(0.0, |_| p.real(GRAVITY_Z)),
        );
        let m = mesh(c, n_el)?;
        let n_nodes = n_el + 1;
        let length = m.s[n_el];
        let node_at = |key: String, at: f64| -> Result<usize, String> {
            let target = at * length;
            let k =
                m.s.iter()
                    .enumerate()
                    .min_by(|a, b| (a.1 - target).abs().total_cmp(&(b.1 - target).abs()))
                    .map(|(k, _)| k)
                    .unwrap_or(0);
            if (m.s[k] - target).abs() > 1e-9 * length {
                let lo =
                    m.s.iter()
                        .rev()
                        .find(|&&s| s <= target)
                        .copied()
                        .unwrap_or(0.0);
                let hi =
                    m.s.iter()
                        .find(|&&s| s >= target)
                        .copied()
                        .unwrap_or(length);
                return Err(format!(
                    "{key}.at = {at}: must fall on a node; with {MESH_N_ELEMENTS} = {n_el} the nearest nodes are at {:.6} and {:.6} of the length",
                    lo / length,
                    hi / length
                ));
            }
            Ok(k)
        };
        let mut constrained = vec![false; n_nodes * NODE_DOFS];
        for (i, s) in scene.supports.iter().enumerate() {
            let k = node_at(format!("supports[{i}]"), s.at)?;
            let n_fixed = match s.kind {
                SupportKind::Clamp => 6,
                _ => 3,
            };
            for c in 0..n_fixed {
                constrained[k * NODE_DOFS + c] = true;
            }
        }
        let dofs = DofMap::new(&constrained);
        if dofs.n_free() == 0 {
            return Err("the supports fix every coordinate: nothing left to simulate".into());
        }
        let element_dofs: Vec<usize> = (0..n_el)
            .flat_map(|e| e * NODE_DOFS..e * NODE_DOFS + ELEMENT_DOFS)
            .collect();
        let asm = Assembly::new(dofs, ELEMENT_DOFS, element_dofs, &[]);
        let elements: Vec<Corot3d> = (0..n_el)
            .map(|e| {
                let l0 = (m.x[e + 1] - m.x[e]).norm();
                Corot3d::new(l0, m.frames[e], &section, theory, mass)
            })
            .collect();
        let mut loads = Vec::with_capacity(scene.loads.len());
        for (i, l) in scene.loads.iter().enumerate() {
            loads.push(NodeLoad {
                node: node_at(format!("loads[{i}]"), l.at)?,
                values: [l.fx, l.fy, l.fz, l.mx, l.my, l.mz],
                follower: l.follower,
            });
        }
        let mut probes = Vec::with_capacity(scene.probes.len());
        for (i, pr) in scene.probes.iter().enumerate() {
            let node = node_at(format!("probes[{i}]"), pr.at)?;
            let e = node.min(n_el - 1);
            probes.push(NodeProbe {
                node,
                tangent: m.frames[e].column(0).into_owned(),
            });
        }
        let mut q0 = vec![0.0; n_nodes * NODE_DOFS];
        for (k, x) in m.x.iter().enumerate() {
            q0[k * NODE_DOFS..k * NODE_DOFS + 3].copy_from_slice(x.as_slice());
        }
        let scales = asm
            .dofs
            .free_to_full()
            .iter()
            .map(|&i| if i % NODE_DOFS < 3 { length } else { 1.0 })
            .collect();
        let n_full = q0.len();
        let n_free = asm.dofs.n_free();
        Ok(Self {
            length,
            elements,
            r_ref: vec![UnitQuaternion::identity(); n_nodes],
            asm,
            gravity,
            loads,
            probes,
            scales,
            q: q0.clone(),
            v: vec![0.0; n_full],
            qw: q0,
            vw: vec![0.0; n_full],
            aw: vec![0.0; n_full],
            fw: vec![0.0; n_full],
            qmid: vec![0.0; n_free],
            rot: vec![Matrix3::identity(); n_nodes],
            tan: vec![Matrix3::identity(); n_nodes],
            roles: io(scene),
        })
    }

    /// Total centre-line length [m].
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.elements.len()
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.r_ref.len()
    }

    /// Position of node `k` in the committed state [m].
    pub fn node_position(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.q[k * NODE_DOFS..k * NODE_DOFS + 3])
    }

    /// Orientation of node `k` in the committed state (rotation from the reference).
    pub fn node_rotation(&self, k: usize) -> Matrix3<f64> {
        let th = Vector3::from_column_slice(&self.q[k * NODE_DOFS + 3..k * NODE_DOFS + 6]);
        self.r_ref[k].to_rotation_matrix().into_inner() * exp_so3(&th)
    }

    /// Body angular velocity of node `k` [rad/s].
    pub fn node_angular_velocity(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.v[k * NODE_DOFS + 3..k * NODE_DOFS + 6])
    }

    fn element_state(&self, e: usize, q: &[f64], v: &[f64]) -> (Nodes, Rates) {
        let nodes = Nodes {
            x: [
                Vector3::from_column_slice(&q[e * NODE_DOFS..e * NODE_DOFS + 3]),
                Vector3::from_column_slice(&q[(e + 1) * NODE_DOFS..(e + 1) * NODE_DOFS + 3]),
            ],
            r: [self.node_rotation_of(e, q), self.node_rotation_of(e + 1, q)],
        };
        let vv: Vec12 = self.asm.gather(e, v);
        (nodes, Rates::from_vec(&vv))
    }

    fn node_rotation_of(&self, k: usize, q: &[f64]) -> Matrix3<f64> {
        let th = Vector3::from_column_slice(&q[k * NODE_DOFS + 3..k * NODE_DOFS + 6]);
        self.r_ref[k].to_rotation_matrix().into_inner() * exp_so3(&th)
    }

    /// Kinetic energy [J] of the committed state.
    pub fn kinetic_energy(&self) -> f64 {
        (0..self.elements.len())
            .map(|e| {
                let (n, v) = self.element_state(e, &self.q, &self.v);
                self.elements[e].kinetic_energy(&n, &v)
            })
            .sum()
    }

    /// Gravity potential [J] of the committed state (relative to the origin).
    pub fn potential_energy(&self) -> f64 {
        (0..self.elements.len())
            .map(|e| {
                let (n, _) = self.element_state(e, &self.q, &self.v);
                self.elements[e].gravity_potential(&n, &self.gravity)
            })
            .sum()
    }

    /// Strain energy [J] of the committed state.
    pub fn strain_energy(&self) -> f64 {
        (0..self.elements.len())
            .map(|e| {
                let (n, _) = self.element_state(e, &self.q, &self.v);
                self.elements[e].strain_energy(&n)
            })
            .sum()
    }

    /// Linear momentum `∂T/∂ẋ` summed over the nodes [kg m/s] of the committed state.
    pub fn linear_momentum(&self) -> Vector3<f64> {
        let mut p = Vector3::zeros();
        for e in 0..self.elements.len() {
            let (n, _) = self.element_state(e, &self.q, &self.v);
            let vv: Vec12 = self.asm.gather(e, &self.v);
            let pe = self.elements[e].mass_matrix(&n) * vv;
            p += Vector3::new(pe[0] + pe[6], pe[1] + pe[7], pe[2] + pe[8]);
        }
        p
    }

    /// Angular momentum about the origin [kg m²/s] of the committed state:
    /// `Σ_i x_i × ∂T/∂ẋ_i + R_i ∂T/∂Ω_i` (the Noether charge of rotation invariance).
    pub fn angular_momentum(&self) -> Vector3<f64> {
        let mut h = Vector3::zeros();
        for e in 0..self.elements.len() {
            let (n, _) = self.element_state(e, &self.q, &self.v);
            let vv: Vec12 = self.asm.gather(e, &self.v);
            let pe = self.elements[e].mass_matrix(&n) * vv;
            for i in 0..2 {
                let px = Vector3::new(pe[6 * i], pe[6 * i + 1], pe[6 * i + 2]);
                let pw = Vector3::new(pe[6 * i + 3], pe[6 * i + 4], pe[6 * i + 5]);
                h += n.x[i].cross(&px) + n.r[i] * pw;
            }
        }
        h
    }

    fn output_of(&self, kind: Output) -> f64 {
        match kind {
            Output::Probe { probe, quantity } => {
                let p = &self.probes[probe];
                let b = p.node * NODE_DOFS;
                let r = || self.node_rotation(p.node);
                use ProbeQuantity::*;
                match quantity {
                    X => self.q[b],
                    Y => self.q[b + 1],
                    Z => self.q[b + 2],
                    Vx => self.v[b],
                    Vy => self.v[b + 1],
                    Vz => self.v[b + 2],
                    Rx | Ry | Rz => {
                        let rv = UnitQuaternion::from_matrix(&r()).scaled_axis();
                        rv[[Rx, Ry, Rz]
                            .iter()
                            .position(|x| *x == quantity)
                            .unwrap_or(0)]
                    }
                    Tx | Ty | Tz => {
                        let t = r() * p.tangent;
                        t[[Tx, Ty, Tz]
                            .iter()
                            .position(|x| *x == quantity)
                            .unwrap_or(0)]
                    }
                    Wx | Wy | Wz => {
                        let w = r() * self.node_angular_velocity(p.node);
                        w[[Wx, Wy, Wz]
                            .iter()
                            .position(|x| *x == quantity)
                            .unwrap_or(0)]
                    }
                }
            }
            Output::Energy(k) => match k {
                EnergyKind::Kinetic => self.kinetic_energy(),
                EnergyKind::Potential => self.potential_energy(),
                EnergyKind::Strain => self.strain_energy(),
                EnergyKind::Total => {
                    self.kinetic_energy() + self.potential_energy() + self.strain_energy()
                }
            },
        }
    }

    /// Absorbs the incremental rotations of a full coordinate vector into the stored nodal
    /// orientations and zeroes them.
    fn absorb_rotations(&mut self, full: &mut [f64]) {
        for (k, r) in self.r_ref.iter_mut().enumerate() {
            let th = Vector3::from_column_slice(&full[k * NODE_DOFS + 3..k * NODE_DOFS + 6]);
            if th != Vector3::zeros() {
                let mut nq = *r * UnitQuaternion::from_scaled_axis(th);
                nq.renormalize();
                *r = nq;
                full[k * NODE_DOFS + 3..k * NODE_DOFS + 6].fill(0.0);
            }
        }
    }

    /// Residual and iteration matrix of the configuration in `self.qw`, rates in `self.vw`,
    /// `self.aw`; the stiffness part of the iteration matrix is scaled by `k_scale`.
    fn assemble(
        &mut self,
        lambda: f64,
        k_scale: f64,
        r: &mut [f64],
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        for k in 0..self.r_ref.len() {
            let th = Vector3::from_column_slice(&self.qw[k * NODE_DOFS + 3..k * NODE_DOFS + 6]);
            self.rot[k] = self.r_ref[k].to_rotation_matrix().into_inner() * exp_so3(&th);
            self.tan[k] = tangent_body(&th);
        }
        let mut fw = std::mem::take(&mut self.fw);
        fw.iter_mut().for_each(|x| *x = 0.0);
        if let Some((_, vals)) = jac.as_mut() {
            vals.iter_mut().for_each(|x| *x = 0.0);
        }
        let g = self.gravity * lambda;
        for e in 0..self.elements.len() {
            let el = &self.elements[e];
            let nodes = Nodes {
                x: [
                    Vector3::from_column_slice(&self.qw[e * NODE_DOFS..e * NODE_DOFS + 3]),
                    Vector3::from_column_slice(
                        &self.qw[(e + 1) * NODE_DOFS..(e + 1) * NODE_DOFS + 3],
                    ),
                ],
                r: [self.rot[e], self.rot[e + 1]],
            };
            let v = Rates::from_vec(&self.asm.gather(e, &self.vw));
            let a = Rates::from_vec(&self.asm.gather(e, &self.aw));
            let mut f = Vec12::zeros();
            match jac.as_mut() {
                Some((c, vals)) => {
                    let mut k = Mat12::zeros();
                    let mut mc = Mat12::zeros();
                    el.internal_force_tangent(&nodes, &mut f, &mut k);
                    el.inertia_force(
                        &nodes,
                        &v,
                        &a,
                        &g,
                        &mut f,
                        Some((c.mass, c.damping, &mut mc, &mut k)),
                    );
                    for (slot, node) in [(0, e), (1, e + 1)] {
                        let cols = k.fixed_view::<12, 3>(0, 6 * slot + 3) * self.tan[node];
                        k.fixed_view_mut::<12, 3>(0, 6 * slot + 3).copy_from(&cols);
                    }
                    mc += k * (c.stiffness * k_scale);
                    self.asm.add_matrix(e, &mc, 1.0, vals);
                }
                None => {
                    el.internal_force(&nodes, &mut f);
                    el.inertia_force(&nodes, &v, &a, &g, &mut f, None);
                }
            }
            self.asm.add_vector(e, &f, 1.0, &mut fw);
        }
        for l in &self.loads {
            let b = l.node * NODE_DOFS;
            let rot = &self.rot[l.node];
            let force = Vector3::new(l.values[0], l.values[1], l.values[2]) * lambda;
            let moment = Vector3::new(l.values[3], l.values[4], l.values[5]) * lambda;
            // Residual −f_ext; `blk` = ∂(−f_ext)/∂W (body spin) for the rows x or θ.
            let (fx, mb, blk, rows) = if l.follower {
                let fx = rot * force;
                (fx, moment, rot * skew(&force), 0)
            } else {
                let mb = rot.transpose() * moment;
                (force, mb, -skew(&mb), 3)
            };
            for c in 0..3 {
                fw[b + c] -= fx[c];
                fw[b + 3 + c] -= mb[c];
            }
            if let Some((c, vals)) = jac.as_mut() {
                if force != Vector3::zeros() && l.follower
                    || moment != Vector3::zeros() && !l.follower
                {
                    let d = blk * self.tan[l.node] * (c.stiffness * k_scale);
                    for i in 0..3 {
                        for j in 0..3 {
                            self.asm.add_entry(b + rows + i, b + 3 + j, d[(i, j)], vals);
                        }
                    }
                }
            }
        }
        self.asm.dofs.restrict(&fw, r);
        self.fw = fw;
        if r.iter().any(|x| !x.is_finite()) {
            return Err(ModelError::NonFinite);
        }
        if let Some((_, vals)) = jac {
            if vals.iter().any(|x| !x.is_finite()) {
                return Err(ModelError::NonFinite);
            }
        }
        Ok(())
    }

    /// The element mass matrices assembled into a dense matrix of the free coordinates at the
    /// committed state (for modal analysis in tests; not used by the solvers).
    pub fn dense_matrices(&mut self) -> (nalgebra::DMatrix<f64>, nalgebra::DMatrix<f64>) {
        let n = self.n_free();
        let mut q = vec![0.0; n];
        let mut v = vec![0.0; n];
        self.free_state(&mut q, &mut v);
        let zeros = vec![0.0; n];
        let mut r = vec![0.0; n];
        let mut dense = |c: JacobianCoeffs, s: &mut Self| {
            let mut vals = vec![0.0; s.asm.pattern.nnz()];
            s.residual(0.0, &q, &zeros, &zeros, 0.0, &mut r, Some((c, &mut vals)))
                .expect("finite");
            let p = &s.asm.pattern;
            let mut m = nalgebra::DMatrix::zeros(n, n);
            for col in 0..n {
                for k in p.col_ptr()[col]..p.col_ptr()[col + 1] {
                    m[(p.row_idx()[k], col)] = vals[k];
                }
            }
            m
        };
        let mm = dense(
            JacobianCoeffs {
                mass: 1.0,
                damping: 0.0,
                stiffness: 0.0,
            },
            self,
        );
        let kk = dense(
            JacobianCoeffs {
                mass: 0.0,
                damping: 0.0,
                stiffness: 1.0,
            },
            self,
        );
        (mm, kk)
    }
}

impl Model for Beam3d {
    fn set_input(&mut self, input: usize, value: f64) {
        match self.roles.inputs[input] {
            Input::Load { load, axis } => self.loads[load].values[axis] = value,
            Input::Moment { load, axis } => self.loads[load].values[3 + axis] = value,
        }
    }

    fn output(&self, output: usize) -> f64 {
        self.output_of(self.roles.outputs[output])
    }

    fn accept(&mut self, state: &mut DynState) {
        let mut q = std::mem::take(&mut self.q);
        self.asm.dofs.expand(&state.q, &mut q);
        self.absorb_rotations(&mut q);
        self.asm.dofs.restrict(&q, &mut state.q);
        self.q = q;
        self.asm.dofs.expand(&state.v, &mut self.v);
    }

    fn free_state(&self, q: &mut [f64], v: &mut [f64]) {
        self.asm.dofs.restrict(&self.q, q);
        self.asm.dofs.restrict(&self.v, v);
    }

    /// Committed coordinates and velocities, nodal orientations (quaternions) and loads.
    fn save(&self, w: &mut StateWriter) -> Result<(), String> {
        w.f64s(&self.q);
        w.f64s(&self.v);
        let quats: Vec<f64> = self
            .r_ref
            .iter()
            .flat_map(|r| {
                let c = r.as_ref().coords;
                [c[0], c[1], c[2], c[3]]
            })
            .collect();
        w.f64s(&quats);
        for l in &self.loads {
            w.f64s(&l.values);
        }
        Ok(())
    }

    fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        r.f64s_into(&mut self.q).map_err(e)?;
        r.f64s_into(&mut self.v).map_err(e)?;
        let quats = r.f64s(Some(4 * self.r_ref.len())).map_err(e)?;
        for (k, c) in quats.chunks(4).enumerate() {
            let q = nalgebra::Quaternion::new(c[3], c[0], c[1], c[2]);
            if !(q.norm() - 1.0).abs().is_finite() || (q.norm() - 1.0).abs() > 1e-9 {
                return Err("a stored orientation is not a unit quaternion".into());
            }
            self.r_ref[k] = UnitQuaternion::new_unchecked(q);
        }
        for l in self.loads.iter_mut() {
            r.f64s_into(&mut l.values).map_err(e)?;
        }
        Ok(())
    }
}

impl MechanicalSystem for Beam3d {
    fn n_free(&self) -> usize {
        self.asm.dofs.n_free()
    }

    fn pattern(&self) -> &CscPattern {
        &self.asm.pattern
    }

    fn scales(&self) -> &[f64] {
        &self.scales
    }

    fn residual(
        &mut self,
        _t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        load_factor: f64,
        r: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        self.asm.dofs.expand(q, &mut self.qw);
        self.asm.dofs.expand(v, &mut self.vw);
        self.asm.dofs.expand(a, &mut self.aw);
        self.assemble(load_factor, 1.0, r, jac)
    }

    /// Implicit midpoint rule: the residual at the mean configuration `(q_a + q_b)/2` (in the
    /// chart of the stored orientations) with the mean velocity and acceleration the
    /// integrator passes. For a free rigid body this conserves the kinetic energy exactly
    /// (`J(Ω₁ − Ω₀)/h + Ω_m × J Ω_m = 0`); for the co-rotational strain energy (not quadratic in
    /// the coordinates) it is second order but not exactly energy conserving.
    fn midpoint_residual(
        &mut self,
        _t_a: f64,
        _t_b: f64,
        q_a: &[f64],
        q_b: &[f64],
        v: &[f64],
        a: &[f64],
        r: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        let mut qm = std::mem::take(&mut self.qmid);
        for i in 0..qm.len() {
            qm[i] = 0.5 * (q_a[i] + q_b[i]);
        }
        self.asm.dofs.expand(&qm, &mut self.qw);
        self.qmid = qm;
        self.asm.dofs.expand(v, &mut self.vw);
        self.asm.dofs.expand(a, &mut self.aw);
        self.assemble(1.0, 0.5, r, jac)
    }

    fn rebase(&mut self, q: &mut [f64]) {
        let mut full = std::mem::take(&mut self.q);
        self.asm.dofs.expand(q, &mut full);
        self.absorb_rotations(&mut full);
        self.asm.dofs.restrict(&full, q);
        self.q = full;
    }
}
