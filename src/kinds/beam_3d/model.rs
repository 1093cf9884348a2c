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

use crate::assembly::{Assembly, DofMap, ElementSet};
use crate::elements::corotational3d::{
    BeamSection, Corot3d, ELEMENT_DOFS, MassModel, NODE_DOFS, Theory, reference_frame,
};
use crate::elements::node_frames::NodeFrames;
use crate::integrators::DynState;
use crate::kinds::KindIo;
use crate::kinds::beam_3d::scene::{Input, Output, io, names::*};
use crate::kinds::beam_3d::{Beam3dScene, CentrelineSection};
use crate::kinds::energy::EnergyKind;
use crate::linalg::CscPattern;
use crate::meshers::centreline::{Piece, mesh_centreline};
use crate::meshers::stations::Stations;
use crate::model::framed::FramedState;
use crate::model::inputs::InputSignal;
use crate::model::nodes3d::{NodeLoad, NodeMotion};
use crate::model::rates;
use crate::model::{JacobianCoeffs, MechanicalSystem, Model, ModelError};
use crate::scene::params::{ParamValues, names::*};
use crate::scene::tables::SupportKind;
use crate::snapshot::{StateReader, StateWriter};
use nalgebra::{Matrix3, Vector3};

/// Reference nodes of a centre line and the section frame of every element.
#[derive(Clone, Debug)]
struct Mesh {
    /// Node positions [m].
    x: Vec<Vector3<f64>>,
    /// Arc length of each node along the centre line.
    stations: Stations,
    /// Reference section frame of each element.
    frames: Vec<Matrix3<f64>>,
}

fn vec3(a: &[f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

/// Nodes along the centre line ([`mesh_centreline`]) and the element frames: local z as close
/// as possible to `section_z` (default global z; global y where an element is parallel to it).
fn mesh(c: &CentrelineSection, n_el: usize) -> Result<Mesh, String> {
    let pieces: Vec<Piece> = c
        .segments
        .iter()
        .enumerate()
        .map(|(i, seg)| {
            let direction = seg.direction.as_ref().map(vec3);
            match (seg.length, seg.radius, seg.angle_deg, &seg.bend_axis) {
                (Some(length), ..) => Ok(Piece::Line { direction, length }),
                (None, Some(radius), Some(a), Some(b)) => Ok(Piece::Arc {
                    direction,
                    radius,
                    angle: a.to_radians(),
                    bend_axis: vec3(b),
                }),
                _ => Err(format!("centreline.segments[{i}]: incomplete piece")),
            }
        })
        .collect::<Result<_, _>>()?;
    let line = mesh_centreline(
        vec3(&c.start),
        &pieces,
        n_el,
        MESH_N_ELEMENTS,
        "centreline.segments",
    )?;
    let x = line.x;
    let hint = c.section_z.as_ref().map_or(Vector3::z(), vec3);
    let mut frames = Vec::with_capacity(n_el);
    for e in 0..n_el {
        let f = reference_frame(&x[e], &x[e + 1], &hint)
            .or_else(|| reference_frame(&x[e], &x[e + 1], &Vector3::y()))
            .ok_or_else(|| {
                format!(
                    "element {e}: degenerate reference geometry (centreline.start, the length, or radius and angle_deg, of the centreline.segments and {MESH_N_ELEMENTS} = {n_el} give it the ends {:?} and {:?})",
                    x[e], x[e + 1]
                )
            })?;
        frames.push(f);
    }
    Ok(Mesh {
        x,
        stations: line.stations,
        frames,
    })
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
    set: ElementSet<Corot3d, ELEMENT_DOFS>,
    gravity: Vector3<f64>,
    loads: Vec<NodeLoad>,
    probes: Vec<NodeProbe>,
    scales: Vec<f64>,
    /// Assembly, node orientations, committed state (outputs are computed from it) and work
    /// buffers.
    st: FramedState,
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
        let length = m.stations.length();
        let node_at = |key: String, at: f64| {
            m.stations
                .node_at(&key, at, MESH_N_ELEMENTS)
                .map_err(|e| format!("{e} (the nodes follow from {MESH_N_ELEMENTS} and the lengths of the centreline.segments)"))
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
        let connectivity: Vec<[usize; ELEMENT_DOFS]> = (0..n_el)
            .map(|e| std::array::from_fn(|i| e * NODE_DOFS + i))
            .collect();
        let asm = Assembly::new(dofs, &[(ELEMENT_DOFS, connectivity.as_flattened())], &[]);
        let elements: Vec<Corot3d> = (0..n_el)
            .map(|e| {
                let l0 = (m.x[e + 1] - m.x[e]).norm();
                Corot3d::new(l0, m.frames[e], &section, theory, mass)
            })
            .collect();
        let frames = NodeFrames::new((0..n_nodes).map(|k| k * NODE_DOFS + 3).collect());
        let set = ElementSet::new(elements, connectivity, &asm).with_frames(&frames);
        let mut loads = Vec::with_capacity(scene.loads.len());
        for (i, l) in scene.loads.iter().enumerate() {
            loads.push(NodeLoad::at_node(
                node_at(format!("loads[{i}]"), l.at)?,
                [l.fx, l.fy, l.fz, l.mx, l.my, l.mz],
                l.follower,
            ));
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
        Ok(Self {
            length,
            set,
            gravity,
            loads,
            probes,
            scales,
            st: FramedState::new(asm, frames, q0),
            roles: io(scene),
        })
    }

    /// Total centre-line length [m].
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.set.len()
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.st.frames.len()
    }

    /// Position of node `k` in the committed state [m].
    pub fn node_position(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.st.q[k * NODE_DOFS..k * NODE_DOFS + 3])
    }

    /// Orientation of node `k` in the committed state (rotation from the reference).
    pub fn node_rotation(&self, k: usize) -> Matrix3<f64> {
        self.st.frames.rotation(k, &self.st.q)
    }

    /// Body angular velocity of node `k` [rad/s].
    pub fn node_angular_velocity(&self, k: usize) -> Vector3<f64> {
        self.st.frames.angular_velocity(k, &self.st.v)
    }

    /// Kinetic energy [J] of the committed state.
    pub fn kinetic_energy(&self) -> f64 {
        self.kinetic_energy_at(&self.st.q, &self.st.v)
    }

    /// Gravity potential [J] of the committed state (relative to the origin).
    pub fn potential_energy(&self) -> f64 {
        self.potential_energy_at(&self.st.q)
    }

    /// Strain energy [J] of the committed state.
    pub fn strain_energy(&self) -> f64 {
        self.strain_energy_at(&self.st.q)
    }

    /// Kinetic energy [J] at full coordinates `q` (rotation vectors in the chart of the stored
    /// orientations) and rates `v` (body angular velocities).
    fn kinetic_energy_at(&self, q: &[f64], v: &[f64]) -> f64 {
        self.set.kinetic_energy(q, v, Some(&self.st.frames))
    }

    /// Gravity potential [J] at full coordinates `q`.
    fn potential_energy_at(&self, q: &[f64]) -> f64 {
        let mut v = 0.0;
        self.set
            .for_each_state(q, &self.st.v, Some(&self.st.frames), |_, el, s| {
                v += el.gravity_potential(&Corot3d::nodes_of(s), &self.gravity);
            });
        v
    }

    /// Strain energy [J] at full coordinates `q`.
    fn strain_energy_at(&self, q: &[f64]) -> f64 {
        self.set.strain_energy(q, Some(&self.st.frames))
    }

    /// Time derivative of an output of the committed state: positions, velocities, angular
    /// velocities and direction cosines analytically (`ẋ`, `ẍ`, `R Ẇ`, `ω × t`); the rotation
    /// vector φ by `φ̇ = T_s(φ)⁻¹ ω` (not defined within 1e-6 rad of |φ| = π, where the
    /// principal value jumps: `None`); energies along the motion ([`rates::along_motion`]).
    fn output_rate(&self, kind: Output) -> Option<f64> {
        let energy = |f: &dyn Fn(&[f64], &[f64]) -> f64| {
            let mut work = [Vec::new(), Vec::new()];
            rates::along_motion(&self.st.q, &self.st.v, &self.st.acc, &mut work, f)
        };
        match kind {
            Output::Probe { probe, quantity } => {
                let p = &self.probes[probe];
                self.motion().probe_rate(p.node, quantity, Some(&p.tangent))
            }
            Output::Energy(k) => Some(match k {
                EnergyKind::Kinetic => energy(&|q, v| self.kinetic_energy_at(q, v)),
                EnergyKind::Potential => energy(&|q, _| self.potential_energy_at(q)),
                EnergyKind::Strain => energy(&|q, _| self.strain_energy_at(q)),
                EnergyKind::Total => energy(&|q, v| {
                    self.kinetic_energy_at(q, v)
                        + self.potential_energy_at(q)
                        + self.strain_energy_at(q)
                }),
            }),
        }
    }

    /// The committed motion of the nodes (for probes).
    fn motion(&self) -> NodeMotion<'_> {
        NodeMotion {
            q: &self.st.q,
            v: &self.st.v,
            acc: &self.st.acc,
            frames: &self.st.frames,
        }
    }

    /// The signal of a load or moment input.
    fn input_signal(&mut self, input: usize) -> &mut InputSignal {
        match self.roles.inputs[input] {
            Input::Load { load, axis } => &mut self.loads[load].values[axis],
            Input::Moment { load, axis } => &mut self.loads[load].values[3 + axis],
        }
    }

    /// Linear momentum `∂T/∂ẋ` summed over the nodes [kg m/s] of the committed state.
    pub fn linear_momentum(&self) -> Vector3<f64> {
        let mut p = Vector3::zeros();
        self.set
            .for_each_state(&self.st.q, &self.st.v, Some(&self.st.frames), |_, el, s| {
                let pe = el.mass_matrix(&Corot3d::nodes_of(s)) * s.v;
                p += Vector3::new(pe[0] + pe[6], pe[1] + pe[7], pe[2] + pe[8]);
            });
        p
    }

    /// Angular momentum about the origin [kg m²/s] of the committed state:
    /// `Σ_i x_i × ∂T/∂ẋ_i + R_i ∂T/∂Ω_i` (the Noether charge of rotation invariance).
    pub fn angular_momentum(&self) -> Vector3<f64> {
        let mut h = Vector3::zeros();
        self.set
            .for_each_state(&self.st.q, &self.st.v, Some(&self.st.frames), |_, el, s| {
                let n = Corot3d::nodes_of(s);
                let pe = el.mass_matrix(&n) * s.v;
                for i in 0..2 {
                    let px = Vector3::new(pe[6 * i], pe[6 * i + 1], pe[6 * i + 2]);
                    let pw = Vector3::new(pe[6 * i + 3], pe[6 * i + 4], pe[6 * i + 5]);
                    h += n.x[i].cross(&px) + n.r[i] * pw;
                }
            });
        h
    }

    fn output_of(&self, kind: Output) -> f64 {
        match kind {
            Output::Probe { probe, quantity } => {
                let p = &self.probes[probe];
                self.motion().probe(p.node, quantity, Some(&p.tangent))
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

    /// Residual and iteration matrix at time `t` [s] (load signals) of the configuration in
    /// `self.st.qw`, rates in `self.st.vw`, `self.st.aw`; the stiffness part of the iteration matrix is scaled by `k_scale`.
    fn assemble(
        &mut self,
        t: f64,
        lambda: f64,
        k_scale: f64,
        r: &mut [f64],
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        let fw = self.st.assemble_elements(
            &self.set,
            &self.loads,
            self.gravity * lambda,
            t,
            lambda,
            k_scale,
            &mut jac,
        );
        self.st
            .finish_assembly(fw, r, jac.as_ref().map(|(_, vals)| &**vals))
    }

    /// The mass and stiffness matrices of the free coordinates at the committed state, dense
    /// (for modal analysis in tests; not used by the solvers).
    pub fn dense_matrices(&mut self) -> (nalgebra::DMatrix<f64>, nalgebra::DMatrix<f64>) {
        let n = self.n_free();
        let mut q = vec![0.0; n];
        let mut v = vec![0.0; n];
        self.free_state(&mut q, &mut v);
        let t = self.st.t;
        crate::model::modal::dense_matrices(self, t, &q).expect("finite")
    }
}

impl Model for Beam3d {
    /// The centre line through the node positions.
    fn sketch(&self) -> crate::model::Sketch {
        let mut s = crate::model::Sketch::new(format!(
            "{} seed-003 co-rotational beam elements, {} nodes with position and orientation",
            self.n_elements(),
            self.n_nodes()
        ));
        s.line((0..self.n_nodes()).map(|k| self.node_position(k)));
        s
    }

    fn set_input(&mut self, input: usize, value: f64) {
        let t = self.st.t;
        self.input_signal(input).set(value, t);
    }

    fn set_input_derivative(
        &mut self,
        input: usize,
        order: usize,
        value: f64,
    ) -> Result<(), String> {
        if !(1..=2).contains(&order) {
            return Err(format!("derivative order {order} not supported (1 or 2)"));
        }
        self.input_signal(input).set_derivative(order, value);
        Ok(())
    }

    fn output(&self, output: usize) -> f64 {
        self.output_of(self.roles.outputs[output])
    }

    fn output_derivative(&self, output: usize) -> Option<f64> {
        self.output_rate(self.roles.outputs[output])
    }

    fn accept(&mut self, state: &mut DynState) {
        self.st.accept(state, |_, _, _| {});
    }

    fn free_state(&self, q: &mut [f64], v: &mut [f64]) {
        self.st.free_state(q, v);
    }

    /// Committed time, coordinates, velocities and accelerations, nodal orientations
    /// (quaternions) and load signals.
    fn save(&self, w: &mut StateWriter) -> Result<(), String> {
        self.st.save(w);
        for l in &self.loads {
            l.save(w);
        }
        Ok(())
    }

    fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        self.st.restore(r)?;
        for l in &mut self.loads {
            l.restore(r).map_err(e)?;
        }
        Ok(())
    }
}

impl MechanicalSystem for Beam3d {
    fn n_free(&self) -> usize {
        self.st.asm.dofs.n_free()
    }

    fn pattern(&self) -> &CscPattern {
        &self.st.asm.pattern
    }

    fn scales(&self) -> &[f64] {
        &self.scales
    }

    fn residual(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        load_factor: f64,
        r: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        self.st.expand(q, v, a);
        self.assemble(t, load_factor, 1.0, r, jac)
    }

    /// Implicit midpoint rule: the residual at the mean configuration `(q_a + q_b)/2` (in the
    /// chart of the stored orientations) with the mean velocity and acceleration the
    /// integrator passes. For a free rigid body this conserves the kinetic energy exactly
    /// (`J(Ω₁ − Ω₀)/h + Ω_m × J Ω_m = 0`); for the co-rotational strain energy (not quadratic in
    /// the coordinates) it is second order but not exactly energy conserving.
    fn midpoint_residual(
        &mut self,
        t_a: f64,
        t_b: f64,
        q_a: &[f64],
        q_b: &[f64],
        v: &[f64],
        a: &[f64],
        r: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        self.st.expand_midpoint(q_a, q_b, v, a);
        self.assemble(0.5 * (t_a + t_b), 1.0, 0.5, r, jac)
    }

    fn rebase(&mut self, q: &mut [f64]) {
        self.st.rebase(q);
    }
}
