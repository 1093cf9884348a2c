//! The air spring at the shell level (`model.fidelity = 1`): the sleeve as a surface mesh of
//! `mesh.n_circumferential × mesh.n_meridional` quadrilaterals carrying the cord–rubber
//! membrane ([`CordRubberQuad`], exact in finite strain) and, where the wall has a bending
//! stiffness, the seed-004 element ([`TrapezoidShell`], bending and drilling only) on the same
//! nodes; the gas of the bag ([`crate::gas::Gas`]) as a follower pressure with its rank-one
//! volume coupling; penalty contact of the nodes with the piston of revolution
//! ([`AxisymObstacle`] seen in space, friction `contact.mu`) and, frictionless, with the top
//! plate's underside where the sleeve folds against it ([`Plate3d`], out to 10 bead radii as
//! at the membrane level). The top plate moves in five axes (`top.x`, `top.y`, `top.z`,
//! `top.rx`, `top.ry`) and reports force and moment.
//!
//! **Mesh.** Ring `i` (0 at the top bead, `n` at the clamp on the piston top) and angle
//! `φ_j = 2π j/n_c`; the stress-free sleeve is the cylinder of `bellows.sleeve_radius`. Every
//! ring is an *equal-area polygon*: its nodes lie on a circle enlarged by
//! `s = √(2π/(n_c sin(2π/n_c)))`, so that the polygon encloses the area of the circle it
//! stands for (bead ring, clamp ring, piston contour and sleeve alike). Hoop stretches are
//! ratios of radii and keep their value, and the bag's cross-sections, volume and effective
//! area are those of the surface of revolution at any `n_c`; the facets' own error is left
//! (measured against the membrane level in `tests/air_spring_shell.rs`).
//!
//! **Coordinates.** Per node `[x, y, z, θx, θy, θz]` as the shell kind (incremental rotations
//! absorbed into stored node frames, [`FramedState`]); with `bellows.bending_stiffness = 0`
//! the wall is a pure membrane and the rotations are not coordinates. Then the piston's axial
//! position (fixed at 0), then the plate's pose `(x, y, z, rx, ry)` as the plate contact's
//! obstacle coordinates (prescribed by the inputs; free in the condensation). The bead ring follows the plate rigidly (positions prescribed,
//! rotations free: a pinned bead, as the membrane level's), the clamp ring is fixed.
//!
//! **Residual.** `r = M a + f_int(q) − p_g f_p(q) − f_contact` with the follower load of the
//! bilinear patches ([`pressure_into`]) at the gauge pressure `p_g(V)` of the gas; the bag
//! volume `V` is the exact volume of the closed polyhedron (the patches' parts
//! [`volume_part`] plus the two planar polygon caps at the plate and the piston top). The
//! iteration matrix carries `−p_g ∂f_p/∂q` and the gas stiffness `−(dp/dV) g gᵀ`,
//! `g = f_p = ∂V/∂q` on the free nodes, as the rank-one part of the solver (issue 11 item 1).
//!
//! **Design state.** The membrane level ([`super::model::AirSpring`], same parameters and
//! meridional mesh) solves the axisymmetric design state; its meridian, revolved, with node
//! frames turned by the meridian's angle, is the start of Newton's method for this level under
//! the fixed design pressure. The gas is charged with this level's bag volume.
//!
//! **Plate force.** `top.f = −Σ_bead r_k + p_g A + Σ_k f_k` (`A` the vector area of the plate
//! cap, `f_k` the plate contact's force on the plate at node `k`) and
//! `top.m = −Σ_bead (x_k − c) × r_k + Σ_k (x_k − c) × f_k` about the plate centre `c`. The port block (the 5 × 5
//! derivatives of `top.fx … top.my` with respect to the plate axes) is the static condensation
//! of the tangent, with the gas: computed on request at the committed state; the plate's
//! coordinates move with the bead ring there, so the contact's dependence on the pose enters
//! both the shape change and the load change.

use super::model::AirSpring;
use super::relax::{Pressure, Relaxation};
use super::scene::{Input, Output, io, names::*, piston_contour};
use super::table::{gas_error, gas_output, gas_params};
use super::{AXIS_Z, AirSpringScene, PLATE_AXES, PlateInput};
use crate::assembly::{Assembly, Connectivity, DofMap, ElementSet, Eval};
use crate::contact::circle_friction::ContactLaw;
use crate::contact::plate3d::{PLATE_COORDS, Plate3d};
use crate::contact::revolution::AxisymObstacle;
use crate::contact::{ContactBook, ContactPointSet};
use crate::elements::cord_rubber::CordRubberWall;
use crate::elements::cord_rubber_quad::{CordRubberQuad, QUAD_DOFS};
use crate::elements::node_frames::NodeFrames;
use crate::elements::rotation::{exp_so3, tangent_spatial};
use crate::elements::surface_load::{pressure_into, volume_part, volume_part_gradient};
use crate::elements::trapezoid_shell::{
    Bending, ELEMENT_DOFS, NODE_DOFS, ShellMaterial, ShellOptions, TrapezoidShell,
};
use crate::gas::Gas;
use crate::integrators::{DynState, StepTrend};
use crate::linalg::{CscPattern, LinearSolver, SolverKind, rank_one_len};
use crate::model::framed::FramedState;
use crate::model::{JacobianCoeffs, MechanicalSystem, Model, ModelError};
use crate::scene::params::ParamValues;
use crate::snapshot::{StateReader, StateWriter};
use crate::variables::Value;
use nalgebra::{Matrix3, SMatrix, SVector, UnitQuaternion, Vector3};
use std::cell::{Cell, RefCell};
use std::f64::consts::PI;
use std::sync::Arc;

/// Radius factor of an equal-area polygon of `n` sides: its vertices on the circle of radius
/// `s r` enclose `π r²`.
pub fn equal_area_factor(n: usize) -> f64 {
    let a = 2.0 * PI / n as f64;
    (a / a.sin()).sqrt()
}

/// Circumferential counts `mesh.n_circumferential = 0` tries, coarsest first.
pub const AUTO_CIRCUMFERENTIAL: &[usize] = &[16, 24, 32];

/// Relative difference of the design force from the membrane level's that the automatic
/// circumferential count accepts [1].
pub const AUTO_FORCE_TOLERANCE: f64 = 5e-3;

/// The linear solver of the model's own solves (design state, condensation): a ring-ordered
/// surface mesh has a band a few rings wide, and banded LU beats the simplicial sparse LU that
/// the automatic choice takes for it (measured 12x at 16 × 60 elements).
fn solver_kind(pattern: &CscPattern) -> SolverKind {
    let (kl, ku) = pattern.bandwidths();
    if 4 * (kl + ku) <= pattern.n() {
        SolverKind::Banded
    } else {
        SolverKind::Auto
    }
}

/// Element sets and contact over one split of the coordinates into free and prescribed.
#[derive(Clone, Debug)]
struct Mech {
    asm: Assembly,
    shells: Option<ElementSet<Arc<TrapezoidShell>, ELEMENT_DOFS>>,
    quads: ElementSet<Arc<CordRubberQuad>, QUAD_DOFS>,
    contact: ContactPointSet<AxisymObstacle, 3, 1, 4>,
    /// The nodes between the rings at the bead and the clamp against the top plate (obstacle
    /// coordinates: the plate's pose, after the piston's coordinate).
    plate: ContactPointSet<Plate3d, 3, 1, 8>,
    /// Whether the plate contact is assembled ([`AirSpringShell::set_plate_contact`]).
    plate_on: bool,
    /// Coordinate indices of the plate contact's nodes' `x` and of the plate's pose.
    plate_rows: Vec<usize>,
    plate_coord: usize,
}

/// What a [`Mech`] is built from.
struct MechParts<'a> {
    shells: Option<&'a [Arc<TrapezoidShell>]>,
    quads: &'a [Arc<CordRubberQuad>],
    elements: &'a [[usize; 4]],
    n_nodes: usize,
    frames: &'a NodeFrames,
    law: ContactLaw,
    piston: AxisymObstacle,
    /// The top plate and the nodes that can touch it.
    plate: Plate3d,
    plate_nodes: &'a [usize],
    node_area: f64,
}

impl Mech {
    fn new(parts: &MechParts, constrained: &[bool]) -> Self {
        let n_nodes = parts.n_nodes;
        let shell_dofs: Vec<[usize; ELEMENT_DOFS]> = parts
            .elements
            .iter()
            .map(|el| std::array::from_fn(|i| el[i / NODE_DOFS] * NODE_DOFS + i % NODE_DOFS))
            .collect();
        let quad_dofs: Vec<[usize; QUAD_DOFS]> = parts
            .elements
            .iter()
            .map(|el| std::array::from_fn(|i| el[i / 3] * NODE_DOFS + i % 3))
            .collect();
        let piston = n_nodes * NODE_DOFS;
        let blocks: Vec<[usize; 4]> = (0..n_nodes)
            .map(|k| [k * NODE_DOFS, k * NODE_DOFS + 1, k * NODE_DOFS + 2, piston])
            .collect();
        let plate = piston + 1;
        let plate_blocks: Vec<[usize; 8]> = parts
            .plate_nodes
            .iter()
            .map(|&k| {
                let i = k * NODE_DOFS;
                [
                    i,
                    i + 1,
                    i + 2,
                    plate,
                    plate + 1,
                    plate + 2,
                    plate + 3,
                    plate + 4,
                ]
            })
            .collect();
        let mut groups: Vec<(usize, &[usize])> = vec![
            (QUAD_DOFS, quad_dofs.as_flattened()),
            (4, blocks.as_flattened()),
            (8, plate_blocks.as_flattened()),
        ];
        if parts.shells.is_some() {
            groups.push((ELEMENT_DOFS, shell_dofs.as_flattened()));
        }
        let asm = Assembly::new(DofMap::new(constrained), &groups, &[]);
        let shells = parts.shells.map(|s| {
            ElementSet::new(s.to_vec(), shell_dofs.clone(), &asm).with_frames(parts.frames)
        });
        let quads = ElementSet::new(parts.quads.to_vec(), quad_dofs, &asm);
        let mut contact = ContactPointSet::new(
            parts.law,
            vec![parts.piston.clone()],
            Connectivity::new(blocks, &asm),
            [0, 0],
        );
        contact.set_points(vec![[1.0]], parts.node_area);
        let mut plate = ContactPointSet::new(
            parts.law,
            vec![parts.plate],
            Connectivity::new(plate_blocks, &asm),
            [0, 0],
        );
        plate.set_points(vec![[1.0]], parts.node_area);
        Self {
            asm,
            shells,
            quads,
            contact,
            plate,
            plate_on: true,
            plate_rows: parts.plate_nodes.iter().map(|k| k * NODE_DOFS).collect(),
            plate_coord: n_nodes * NODE_DOFS + 1,
        }
    }

    /// Whether the plate contact has work at full coordinates `q`: switched on and a node above
    /// the plate's plane (a cheap pass that spares the contact loop while the sleeve hangs
    /// clear of the plate, the rolling lobe's usual state).
    fn plate_touched(&self, q: &[f64]) -> bool {
        if !self.plate_on {
            return false;
        }
        let x = &q[self.plate_coord..self.plate_coord + PLATE_COORDS];
        let c = Vector3::new(x[0], x[1], x[2]);
        let n = exp_so3(&Vector3::new(x[3], x[4], 0.0)) * Vector3::z();
        self.plate_rows
            .iter()
            .any(|&i| (Vector3::new(q[i], q[i + 1], q[i + 2]) - c).dot(&n) > 0.0)
    }
}

/// Geometry of the plate and the bag's ends.
#[derive(Clone, Debug)]
struct Ends {
    /// Nodes of the bead ring and their offsets from the plate centre in the plate's frame [m].
    bead: Vec<(usize, Vector3<f64>)>,
    /// The elements with a node on the bead ring, ascending (the only ones with a residual
    /// in the bead ring's rows, [`AirSpringShell::bead_rows`]).
    bead_elements: Vec<usize>,
    /// Vector area of the plate cap in the plate's frame (along +z) [m²].
    plate_area: Vector3<f64>,
    /// Bag volume below the piston-top cap: `(1/3) x · A` of that cap [m³] (constant).
    clamp_cap: f64,
    /// The nodes in contact with the plate, in the order of the plate contact's blocks.
    plate_nodes: Vec<usize>,
    /// First of the plate's five coordinates `(x, y, z, rx, ry)` (prescribed; free in the
    /// condensation).
    plate_coord: usize,
}

/// The port block and the volume derivative of a committed state.
#[derive(Clone, Copy, Debug)]
struct Condensed {
    /// `∂(fx, fy, fz, mx, my)/∂(x, y, z, rx, ry)`.
    k: [[f64; PLATE_AXES]; PLATE_AXES],
    /// `dV/d(x, y, z, rx, ry)` [m², m³].
    dv: [f64; PLATE_AXES],
}

/// The condensation's own assembly (every coordinate free), solvers and cache.
#[derive(Debug)]
struct Condensation {
    /// A copy of the main system's sets (the condensation assembles while the model is shared).
    main: Mech,
    /// Scratch state (the committed one, at rest) and buffers, kept between requests.
    st: FramedState,
    /// Full vectors: unit pressure load, residual, patch volume gradient, `T_j`, `K T_j`, the
    /// full direction and its `K` product.
    g: Vec<f64>,
    f: Vec<f64>,
    vgrad: Vec<f64>,
    t: Vec<f64>,
    kt: Vec<f64>,
    dfull: Vec<f64>,
    dr: Vec<f64>,
    /// Free shape changes of the plate axes (`n_free × 5`, column-major).
    y: Vec<f64>,
    full: Mech,
    main_solver: Option<LinearSolver>,
    main_vals: Vec<f64>,
    full_vals: Vec<f64>,
    /// Position in `full_vals` of every value of the main system's pattern (its free rows
    /// and columns: the main system's `K` is gathered from the full one, not assembled again).
    main_in_full: Vec<usize>,
    /// The plate contact's part of `K` (every coordinate free), its residual and the change of
    /// that residual along a direction (full vectors).
    plate_vals: Vec<f64>,
    fc: Vec<f64>,
    dfc: Vec<f64>,
    cache: Option<(u64, Option<Condensed>)>,
}

/// Work buffers of an evaluation.
#[derive(Clone, Debug, Default)]
struct Work {
    /// Unit pressure load (= volume gradient on the free nodes), full.
    g: Vec<f64>,
    /// Pose, rates and second rates of the plate of the evaluation.
    pose: [[f64; PLATE_AXES]; 3],
}

/// The air-spring model at the shell level.
pub struct AirSpringShell {
    n_circ: usize,
    n_mer: usize,
    n_nodes: usize,
    st: FramedState,
    main: Mech,
    cond: RefCell<Condensation>,
    ends: Ends,
    /// Equal-area radius factor.
    scale: f64,
    gas: Gas,
    ambient: f64,
    v_charge: f64,
    inputs: Vec<Input>,
    outputs: Vec<Output>,
    plate: PlateInput,
    static_from: [f64; PLATE_AXES],
    statics: bool,
    hold: bool,
    initialized: bool,
    /// Committed plate pose.
    pose: [f64; PLATE_AXES],
    /// Committed `(fx, fy, fz, mx, my)` [N, N m].
    force: [f64; PLATE_AXES],
    /// The fixed gauge pressure of the last constant-pressure equilibrium [Pa].
    pressure_now: f64,
    scales: Vec<f64>,
    work: Work,
    last_strain: f64,
    /// Strain energy of the committed state (elements and the plate contact's penalty) [J],
    /// computed on the first request after a commit ([`AirSpringShell::strain_energy`]).
    strain: Cell<Option<f64>>,
    /// The plate contact's penalty energy of the committed state [J] (stored elastic energy).
    plate_energy: f64,
    /// Kinetic energy of the committed state [J] (zero with quasi-static steps), computed on
    /// the first request after a commit ([`AirSpringShell::kinetic_energy`]).
    kinetic: Cell<Option<f64>>,
    /// Quasi-static steps (`solver.integrator = "quasi_static"`): no inertia, no kinetic
    /// energy.
    quasi_static: bool,
    /// Quasi-static steps: the communication step `(t0, t1)` being advanced and the committed
    /// pose's offsets from the position inputs at `t0`, spread linearly over the step
    /// ([`AirSpringShell::plate_motion`]); `None` outside a step or with inertia.
    input_jump: Option<(f64, f64, [f64; PLATE_AXES])>,
    /// Quasi-static steps: the predictor's history of step increments
    /// ([`MechanicalSystem::predict`]).
    trend: StepTrend,
    plate_work: f64,
    contact_loss: f64,
    last_damping_power: f64,
    commits: u64,
    mass_per_area: f64,
    /// The plate poses the sleeve can reach: `(piston top height [m], sleeve length [m], bead
    /// radius [m])`.
    envelope: (f64, f64, f64),
    /// What the automatic circumferential count chose, for the log.
    auto_note: Option<String>,
}

impl std::fmt::Debug for AirSpringShell {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AirSpringShell")
            .field("n_circ", &self.n_circ)
            .field("n_mer", &self.n_mer)
            .field("t", &self.st.t)
            .finish()
    }
}

/// Rotation, spatial tangent of the tilt `(rx, ry, 0)`.
fn tilt(pose: &[f64; PLATE_AXES]) -> (Matrix3<f64>, Matrix3<f64>) {
    let th = Vector3::new(pose[3], pose[4], 0.0);
    (exp_so3(&th), tangent_spatial(&th))
}

impl AirSpringShell {
    /// Builds the model and solves the design state. Errors name the parameter.
    ///
    /// With `mesh.n_circumferential` = 0 the count is chosen: the coarsest of
    /// [`AUTO_CIRCUMFERENTIAL`] whose design force, and the design force of the same spring
    /// charged to half the pressure, are within [`AUTO_FORCE_TOLERANCE`] of the membrane
    /// level's (the axisymmetric start shape, built anyway; the closest count if none is).
    /// A sleeve rolled onto a piston narrower than it is in hoop compression
    /// (λ_θ = r_piston / r_sleeve), and there a coarse polygon ring misplaces the lobe: at
    /// 2 bar the 16-gon gives −7 % (8088 N against 8693 N), 24 −0.5 %, 32 −0.1 % (README
    /// "Level 1 off its design"). With an odd ply count (one ply unbalanced, which the
    /// membrane level cannot model) it takes the coarsest. The choice is deterministic in the
    /// parameters, so a restored FMU state meets the mesh it was saved from.
    pub fn build(scene: &AirSpringScene, p: &ParamValues) -> Result<Self, String> {
        match p.integer(MESH_N_CIRCUMFERENTIAL) {
            0 => {}
            n if n < 8 => {
                return Err(format!(
                    "{MESH_N_CIRCUMFERENTIAL} = {n}: must be 0 (automatic) or at least 8"
                ));
            }
            n => return Self::build_with(scene, p, n as usize, &AirSpring::build(scene, p)?),
        }
        // the axisymmetric design state of the membrane level: the shell's start shape and the
        // reference of the automatic count
        let axisym = AirSpring::build(scene, p)?;
        // with an odd ply count the membrane level (balanced plies, no twist) is no reference
        if p.integer(BELLOWS_N_PLIES) % 2 == 1 {
            return Self::build_with(scene, p, AUTO_CIRCUMFERENTIAL[0], &axisym);
        }
        // the design state and the same spring charged to half its pressure (the sleeve's
        // tension falls on extension, and the hoop compression on the piston matters more)
        let mut half = p.clone();
        half.set(
            GAS_PRESSURE_DESIGN,
            Value::Real(0.5 * p.real(GAS_PRESSURE_DESIGN)),
        );
        // no membrane equilibrium at half the pressure: no shell one is looked for either
        let axisym_half = AirSpring::build(scene, &half).ok();
        let deviation = |m: &Self, f_membrane: f64| ((m.force[2] - f_membrane) / f_membrane).abs();
        // (model, deviation at the design pressure, at half of it: infinite without a shell
        // equilibrium there)
        let mut best: Option<(Self, f64, f64)> = None;
        let mut first_error = None;
        let score = |d: f64, h: f64| (d.max(h), d);
        for &n in AUTO_CIRCUMFERENTIAL {
            let m = match Self::build_with(scene, p, n, &axisym) {
                Ok(m) => m,
                Err(e) => {
                    first_error.get_or_insert(e);
                    continue;
                }
            };
            let dev = deviation(&m, axisym.committed_force());
            let dev_half = axisym_half.as_ref().map_or(f64::INFINITY, |a| {
                Self::build_with(scene, &half, n, a)
                    .map_or(f64::INFINITY, |mh| deviation(&mh, a.committed_force()))
            });
            let done = dev.max(dev_half) <= AUTO_FORCE_TOLERANCE;
            if best
                .as_ref()
                .is_none_or(|(_, d, h)| score(dev, dev_half) < score(*d, *h))
            {
                best = Some((m, dev, dev_half));
            }
            if done {
                break;
            }
        }
        match best {
            Some((mut m, dev, dev_half)) => {
                let accepted = dev.max(dev_half) <= AUTO_FORCE_TOLERANCE;
                m.auto_note = Some(format!(
                    "{MESH_N_CIRCUMFERENTIAL} = 0 (automatic): {} elements around; the design force is {:.2} % off the membrane level's, {} at half the design pressure ({})",
                    m.n_circ,
                    100.0 * dev,
                    if dev_half.is_finite() {
                        format!("{:.2} %", 100.0 * dev_half)
                    } else {
                        "no shell equilibrium".to_string()
                    },
                    if accepted {
                        format!("within {:.1} %", 100.0 * AUTO_FORCE_TOLERANCE)
                    } else {
                        format!(
                            "no count of {AUTO_CIRCUMFERENTIAL:?} is within {:.1} % at both: the closest; set {MESH_N_CIRCUMFERENTIAL} to choose",
                            100.0 * AUTO_FORCE_TOLERANCE
                        )
                    }
                ));
                Ok(m)
            }
            None => Err(first_error.unwrap_or_default()),
        }
    }

    /// [`AirSpringShell::build`] with `n_circ` elements around from `axisym`, the membrane
    /// level's design state of the same parameters `p`.
    fn build_with(
        scene: &AirSpringScene,
        p: &ParamValues,
        n_circ: usize,
        axisym: &AirSpring,
    ) -> Result<Self, String> {
        let n_mer = p.integer(MESH_N_MERIDIONAL).max(2) as usize;
        let s = equal_area_factor(n_circ);
        let contour = piston_contour(scene, p);
        let clamp = *contour.last().expect("two points");
        let rb = p.real(TOP_PLATE_BEAD_RADIUS);
        let r0 = p.real(BELLOWS_SLEEVE_RADIUS);
        let length = p.real(BELLOWS_SLEEVE_LENGTH);
        let hd = p.real(SPRING_DESIGN_HEIGHT);
        let pd = p.real(GAS_PRESSURE_DESIGN);
        let thickness = p.real(BELLOWS_THICKNESS);
        let density = p.real(BELLOWS_DENSITY);
        let d_bend = p.real(BELLOWS_BENDING_STIFFNESS);
        let rotations = d_bend > 0.0;
        let wall = CordRubberWall {
            cord_stiffness: p.real(BELLOWS_CORD_STIFFNESS),
            n_plies: p.integer(BELLOWS_N_PLIES).max(1) as usize,
            cord_angle: p.real(BELLOWS_CORD_ANGLE).to_radians(),
            matrix_stiffness: p.real(BELLOWS_MATRIX_STIFFNESS),
            tension_only: p.boolean(BELLOWS_TENSION_ONLY),
        };
        let n_rings = n_mer + 1;
        let n_nodes = n_rings * n_circ;
        // nodes of a ring interleaved from both sides (0, 1, n−1, 2, n−2, …): neighbours on the
        // ring, the closing pair included, are at most two apart, so the band of the matrix
        // is about three nodes wider than a ring
        let mut order = vec![0];
        for k in 1..n_circ {
            for j in [k, n_circ - k] {
                if order.len() < n_circ && !order.contains(&j) {
                    order.push(j);
                }
            }
        }
        let mut slot = vec![0; n_circ];
        for (p, &j) in order.iter().enumerate() {
            slot[j] = p;
        }
        let node = |i: usize, j: usize| i * n_circ + slot[j % n_circ];
        let phi = |j: usize| 2.0 * PI * j as f64 / n_circ as f64;
        // reference sleeve: the cylinder from the bead (z = 0) down
        let ell = length / n_mer as f64;
        let reference = |i: usize, j: usize| {
            Vector3::new(
                s * r0 * phi(j).cos(),
                s * r0 * phi(j).sin(),
                -(i as f64) * ell,
            )
        };
        let mut elements = Vec::with_capacity(n_mer * n_circ);
        for i in 0..n_mer {
            for j in 0..n_circ {
                elements.push([
                    node(i, j),
                    node(i + 1, j),
                    node(i + 1, j + 1),
                    node(i, j + 1),
                ]);
            }
        }
        let meridian = Vector3::new(0.0, 0.0, -1.0);
        let quad_mass = if rotations { 0.0 } else { density * thickness };
        let mut quads = Vec::with_capacity(elements.len());
        let mut shells = Vec::new();
        let mat = ShellMaterial {
            // D = E t³/12 with ν = 0
            e: 12.0 * d_bend / thickness.powi(3),
            nu: 0.0,
            rho: density,
            thickness,
        };
        let opt = ShellOptions {
            bending: Bending::V2,
            // the drilling penalty, 0.1 G h with G h = 6 D/t² of the bending-only element (about
            // 1e-3 of the cords' stiffness for the reference wall: the design force moves by
            // 7e-6); at the shell kind's 1e-3 the drilling rotations are so loosely held that
            // Newton's increments do not settle and steps are rejected (27x slower, measured)
            drilling: 0.1,
            geometric_stiffness: true,
            membrane: false,
        };
        let corners = |el: &[usize; 4]| el.map(|k| reference(k / n_circ, order[k % n_circ]));
        // the quad's reference data are intrinsic (metric, cord components): the facets differ
        // by rotations about the axis, so one element serves all
        quads.push(Arc::new(
            CordRubberQuad::new(corners(&elements[0]), meridian, wall, quad_mass)
                .map_err(|e| format!("{e} ({MESH_N_CIRCUMFERENTIAL}, {MESH_N_MERIDIONAL})"))?,
        ));
        // the seed-004 element keeps its reference frame: one per facet
        if rotations {
            for el in &elements {
                shells.push(Arc::new(TrapezoidShell::new(corners(el), &mat, &opt).map_err(|e| {
                    format!("{e} ({BELLOWS_BENDING_STIFFNESS}, {BELLOWS_THICKNESS}, {BELLOWS_DENSITY}, {MESH_N_CIRCUMFERENTIAL}, {MESH_N_MERIDIONAL})")
                })?));
            }
        }
        let piston_coord = n_nodes * NODE_DOFS;
        let plate_coord = piston_coord + 1;
        let n_full = plate_coord + PLATE_COORDS;
        let mut constrained = vec![false; n_full];
        constrained[piston_coord] = true;
        constrained[plate_coord..].fill(true);
        for j in 0..n_circ {
            for i in [0, n_mer] {
                for d in 0..3 {
                    constrained[node(i, j) * NODE_DOFS + d] = true;
                }
            }
        }
        if !rotations {
            for k in 0..n_nodes {
                for d in 3..6 {
                    constrained[k * NODE_DOFS + d] = true;
                }
            }
        }
        let mut frames = NodeFrames::new((0..n_nodes).map(|k| k * NODE_DOFS + 3).collect());
        // revolve the membrane level's meridian
        let mer = axisym.meridian();
        let mut q0 = vec![0.0; n_full];
        q0[plate_coord + AXIS_Z] = hd;
        for i in 0..n_rings {
            let [r, z] = mer[i];
            let prev = mer[i.saturating_sub(1)];
            let next = mer[(i + 1).min(n_mer)];
            let (dr, dz) = (next[0] - prev[0], next[1] - prev[1]);
            for j in 0..n_circ {
                let (sn, cs) = phi(j).sin_cos();
                let k = node(i, j);
                q0[k * NODE_DOFS..k * NODE_DOFS + 3].copy_from_slice(&[s * r * cs, s * r * sn, z]);
                // the frame turns about the hoop direction from the reference tangent (down)
                // to the meridian's
                let e_phi = Vector3::new(-sn, cs, 0.0);
                let t = Vector3::new(dr * cs, dr * sn, dz);
                let t0 = Vector3::new(0.0, 0.0, -1.0);
                let beta = t0.cross(&t).dot(&e_phi).atan2(t0.dot(&t));
                frames.set_reference(k, UnitQuaternion::from_scaled_axis(e_phi * beta));
            }
        }
        let area = 2.0 * PI * r0 * length / (n_circ * n_mer) as f64;
        // friction (`contact.mu`) as at level 2: a bristle as stiff per slip as the penalty
        // per penetration, the stick–slip switch blended over ±10 % of μ p
        let k_n = p.real(CONTACT_STIFFNESS);
        let law = ContactLaw {
            k_n,
            d_n: 0.0,
            k_t: k_n,
            d_t: 0.0,
            mu: p.real(CONTACT_MU),
            // a C¹ penalty over a penetration of a hundredth of a millimetre (level 2's ramp,
            // scaled with the pressure, gained nothing at the shipped 24 × 40 and made the
            // design-state search of far-off springs slow: session 34)
            smoothing: 1e-5,
            blend: 0.1,
        };
        let piston = AxisymObstacle::Piston {
            contour: contour.iter().map(|c| [s * c[0], c[1]]).collect(),
        };
        // the plate (out to 10 bead radii, as the membrane level's) against every node but the
        // bead ring (on the plate: a zero gap) and the clamp ring
        let plate_nodes: Vec<usize> = (1..n_mer)
            .flat_map(|i| (0..n_circ).map(move |j| (i, j)))
            .map(|(i, j)| node(i, j))
            .collect();
        let parts = MechParts {
            shells: rotations.then_some(&shells[..]),
            quads: &quads,
            elements: &elements,
            n_nodes,
            frames: &frames,
            law,
            piston,
            plate: Plate3d { radius: 10.0 * rb },
            plate_nodes: &plate_nodes,
            node_area: area,
        };
        let main = Mech::new(&parts, &constrained);
        let full = Mech::new(&parts, &vec![false; n_full]);
        let main_copy = main.clone();
        let scratch = FramedState::new(main.asm.clone(), frames.clone(), q0.clone());
        let asm = main.asm.clone();
        let n_free = asm.dofs.n_free();
        let scales = asm
            .dofs
            .free_to_full()
            .iter()
            .map(|&i| if i % NODE_DOFS < 3 { length } else { 1.0 })
            .collect();
        let bead = (0..n_circ)
            .map(|j| {
                let (sn, cs) = phi(j).sin_cos();
                (node(0, j), Vector3::new(s * rb * cs, s * rb * sn, 0.0))
            })
            .collect::<Vec<_>>();
        let bead_elements = (0..elements.len())
            .filter(|&e| elements[e].iter().any(|k| bead.iter().any(|(b, _)| b == k)))
            .collect();
        let poly =
            |r: f64| 0.5 * n_circ as f64 * (s * r).powi(2) * (2.0 * PI / n_circ as f64).sin();
        let ends = Ends {
            bead,
            bead_elements,
            plate_area: Vector3::new(0.0, 0.0, poly(rb)),
            clamp_cap: -clamp[1] * poly(clamp[0]) / 3.0,
            plate_nodes,
            plate_coord,
        };
        let gp = gas_params(p, scene);
        let io = io(scene);
        let mut model = Self {
            n_circ,
            n_mer,
            n_nodes,
            st: FramedState::new(asm, frames, q0),
            main,
            cond: RefCell::new(Condensation {
                main: main_copy,
                st: scratch,
                g: vec![0.0; n_full],
                f: vec![0.0; n_full],
                vgrad: vec![0.0; n_full],
                t: vec![0.0; n_full],
                kt: vec![0.0; n_full],
                dfull: vec![0.0; n_full],
                dr: vec![0.0; n_full],
                y: vec![0.0; n_free * PLATE_AXES],
                full,
                main_solver: None,
                main_vals: vec![],
                full_vals: vec![],
                main_in_full: vec![],
                plate_vals: vec![],
                fc: vec![0.0; n_full],
                dfc: vec![0.0; n_full],
                cache: None,
            }),
            ends,
            scale: s,
            gas: Gas::new(gp, pd, 1.0).map_err(|e| gas_error(e, &gp))?,
            ambient: gp.ambient_pressure,
            v_charge: 0.0,
            inputs: io.inputs,
            outputs: io.outputs,
            plate: PlateInput::at_rest(hd),
            static_from: PlateInput::at_rest(hd).targets(),
            statics: false,
            hold: false,
            initialized: false,
            pose: PlateInput::at_rest(hd).targets(),
            force: [0.0; PLATE_AXES],
            pressure_now: pd,
            scales,
            work: Work {
                g: vec![0.0; n_full],
                pose: [[0.0; PLATE_AXES]; 3],
            },
            last_strain: 0.0,
            strain: Cell::new(Some(0.0)),
            plate_energy: 0.0,
            kinetic: Cell::new(Some(0.0)),
            quasi_static: false,
            input_jump: None,
            trend: StepTrend::new(n_free),
            plate_work: 0.0,
            contact_loss: 0.0,
            last_damping_power: 0.0,
            commits: 0,
            mass_per_area: density * thickness,
            envelope: (clamp[1], length, rb),
            auto_note: None,
        };
        model.prescribe_pose(&model.pose.clone(), true);
        let pose = model.pose;
        model
            .continuation(pose, pose, Pressure::Fixed(pd))
            .map_err(|e| {
                // an odd number of plies alternating +-angle leaves one family unbalanced: the
                // shell level models the twist this couples to extension and pressure (the
                // membrane level, axisymmetric without twist, cannot), and with a single ply
                // the sleeve has nothing but the matrix against it
                let unbalanced = if wall.n_plies % 2 == 1 {
                    format!(
                        "; {BELLOWS_N_PLIES} = {} is odd: the plies alternate +-{BELLOWS_CORD_ANGLE}, so one ply is unbalanced and twists the sleeve (the membrane level has no twist and treats the plies as balanced)",
                        wall.n_plies
                    )
                } else {
                    String::new()
                };
                format!("design state of the shell level: {e}{unbalanced}")
            })?;
        let vd = model.bag_volume(&model.st.q, &pose);
        model.gas.charge(pd, vd).map_err(|e| gas_error(e, &gp))?;
        model.v_charge = model.gas.committed().volume;
        model
            .commit_reaction(vd)
            .map_err(|e| gas_error(format!("design state: {e}"), &gp))?;
        Ok(model)
    }

    /// Number of elements `(around, along)`.
    pub fn mesh(&self) -> (usize, usize) {
        (self.n_circ, self.n_mer)
    }

    /// Switches the sleeve's contact with the top plate on (the default) or off, for
    /// comparisons in tools and tests; the next solve or step uses it.
    pub fn set_plate_contact(&mut self, on: bool) {
        self.main.plate_on = on;
        let mut c = self.cond.borrow_mut();
        c.main.plate_on = on;
        c.full.plate_on = on;
        c.cache = None;
    }

    /// Number of free coordinates.
    pub fn n_free_coordinates(&self) -> usize {
        self.st.asm.dofs.n_free()
    }

    /// The gas component.
    pub fn gas(&self) -> &Gas {
        &self.gas
    }

    /// Committed `(fx, fy, fz, mx, my)` on the plate [N, N m] (without extrapolation).
    pub fn committed_force(&self) -> [f64; PLATE_AXES] {
        self.force
    }

    /// Moves the plate quasi-statically to `pose` (axes as [`PLATE_AXES`]) with the gas closed
    /// and at rest, from the committed shape; returns the committed `(fx, fy, fz, mx, my)`.
    /// For tools and tests, before a simulation starts.
    pub fn move_plate(&mut self, pose: [f64; PLATE_AXES]) -> Result<[f64; PLATE_AXES], String> {
        let from = self.pose;
        self.continuation(from, pose, Pressure::Static)?;
        let vb = self.bag_volume(&self.st.q, &self.pose);
        self.gas.set_static(vb).map_err(|e| e.to_string())?;
        self.commit_reaction(vb).map_err(|e| e.to_string())?;
        Ok(self.force)
    }

    /// The static equilibrium with the plate at `pose` under the fixed gauge pressure `p_gauge`
    /// [Pa] (no gas law: a constant-pressure state, as on a test rig with a large supply),
    /// reached from the committed shape; returns `(fx, fy, fz, mx, my)` and the bag volume
    /// with `gas.inner_volume` [m³]. For tools and tests, before a simulation starts.
    pub fn equilibrium_at(
        &mut self,
        pose: [f64; PLATE_AXES],
        p_gauge: f64,
    ) -> Result<([f64; PLATE_AXES], f64), String> {
        let from = self.pose;
        let steps = ((p_gauge - self.pressure_now).abs() / 1e5).ceil().max(1.0) as usize;
        let p0 = self.pressure_now;
        for k in 1..=steps {
            let p = p0 + (p_gauge - p0) * k as f64 / steps as f64;
            let to = if k == 1 { pose } else { self.pose };
            self.continuation(
                if k == 1 { from } else { self.pose },
                to,
                Pressure::Fixed(p),
            )?;
        }
        let n = self.st.asm.dofs.n_free();
        let (mut q, zeros) = (vec![0.0; n], vec![0.0; n]);
        self.st.asm.dofs.restrict(&self.st.q, &mut q);
        self.st.expand(&q, &zeros, &zeros);
        self.prescribe_pose(&pose, true);
        let mut r = vec![0.0; n];
        self.evaluate_filled(Pressure::Fixed(p_gauge), &mut r, None)
            .map_err(|e| e.to_string())?;
        let v = self.bag_volume(&self.st.q, &pose) + self.gas.params().inner_volume;
        Ok((self.plate_load(p_gauge), v))
    }

    /// The port block `∂(fx, fy, fz, mx, my)/∂(x, y, z, rx, ry)` of the committed state (the
    /// static condensation with the gas), and `dV/d(x, y, z, rx, ry)`.
    #[allow(clippy::type_complexity)]
    pub fn port_block(&self) -> Option<([[f64; PLATE_AXES]; PLATE_AXES], [f64; PLATE_AXES])> {
        self.condensed().map(|c| (c.k, c.dv))
    }

    /// Node positions of the committed state [m].
    pub fn nodes(&self) -> Vec<Vector3<f64>> {
        (0..self.n_nodes)
            .map(|k| self.node(&self.st.q, k))
            .collect()
    }

    fn node(&self, q: &[f64], k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&q[k * NODE_DOFS..k * NODE_DOFS + 3])
    }

    /// Plate centre and rotation of a pose.
    fn plate_frame(pose: &[f64; PLATE_AXES]) -> (Vector3<f64>, Matrix3<f64>, Matrix3<f64>) {
        let (r, ts) = tilt(pose);
        (Vector3::new(pose[0], pose[1], pose[2]), r, ts)
    }

    /// Bag volume at full coordinates `q` with the plate at `pose` (without
    /// `gas.inner_volume`) [m³].
    fn bag_volume(&self, q: &[f64], pose: &[f64; PLATE_AXES]) -> f64 {
        let conn = self.main.quads.connectivity();
        let mut v = 0.0;
        for e in 0..conn.len() {
            let d = conn.dofs(e);
            let x: [Vector3<f64>; 4] = std::array::from_fn(|i| {
                Vector3::new(q[d[3 * i]], q[d[3 * i + 1]], q[d[3 * i + 2]])
            });
            v += volume_part(&x);
        }
        let (c, r, _) = Self::plate_frame(pose);
        v + c.dot(&(r * self.ends.plate_area)) / 3.0 + self.ends.clamp_cap
    }

    /// Whether the sleeve can reach the plate pose `pose`: the plate above the piston top, its
    /// centre less than the sleeve length from the clamp, shifted less than the bead radius and
    /// tilted less than 0.5 rad. A motion that leaves this leaves the model (the step fails
    /// with the reason instead of grinding through a torn sleeve).
    fn admissible(&self, pose: &[f64; PLATE_AXES]) -> Result<(), ModelError> {
        let (top, length, rb) = self.envelope;
        let tilt = pose[3].hypot(pose[4]);
        let shift = pose[0].hypot(pose[1]);
        if !(pose[AXIS_Z] > top && pose[AXIS_Z] < top + length && shift < rb && tilt < 0.5) {
            return Err(ModelError::Outside(format!(
                "the top plate pose (x, y, z, rx, ry) = ({:.4}, {:.4}, {:.4} m, {:.4}, {:.4} rad) is outside what the sleeve can reach (z between the piston top {top} m and {} m, a shift below the bead radius {rb} m, a tilt below 0.5 rad)",
                pose[0],
                pose[1],
                pose[2],
                pose[3],
                pose[4],
                top + length
            )));
        }
        Ok(())
    }

    /// Prescribed pose, rates and second rates at `t` (in a static solve at load factor `lambda`).
    fn plate_motion(&self, t: f64, lambda: f64) -> [[f64; PLATE_AXES]; 3] {
        let mut out = [[0.0; PLATE_AXES]; 3];
        if self.statics {
            let to = self.plate.targets();
            for i in 0..PLATE_AXES {
                out[0][i] = self.static_from[i] + lambda * (to[i] - self.static_from[i]);
            }
            return out;
        }
        for i in 0..PLATE_AXES {
            let (x, v, a) = self.plate.axis_motion(i, t);
            out[0][i] = if self.hold && t == self.st.t {
                self.pose[i]
            } else {
                match self.input_jump {
                    // quasi-static steps: a position input that jumped away from the committed
                    // pose is reached at the step's end, not at its start, so that a halved
                    // substep halves the jump (a continuation); the end state is the same
                    Some((t0, t1, d)) if t < t1 => x + d[i] * (t1 - t) / (t1 - t0),
                    _ => x,
                }
            };
            out[1][i] = v;
            out[2][i] = a;
        }
        out
    }

    /// Writes the bead ring's positions (and, with `rates`, velocities and accelerations of
    /// `self.work.pose`) into the work buffers for the pose `pose`.
    fn prescribe_pose(&mut self, pose: &[f64; PLATE_AXES], rest: bool) {
        self.work.pose[0] = *pose;
        if rest {
            self.work.pose[1] = [0.0; PLATE_AXES];
            self.work.pose[2] = [0.0; PLATE_AXES];
        }
        let [u, ud, udd] = self.work.pose;
        let (c, r, ts) = Self::plate_frame(&u);
        let omega = ts * Vector3::new(ud[3], ud[4], 0.0);
        let alpha = ts * Vector3::new(udd[3], udd[4], 0.0);
        let (cd, cdd) = (
            Vector3::new(ud[0], ud[1], ud[2]),
            Vector3::new(udd[0], udd[1], udd[2]),
        );
        for &(k, rho) in &self.ends.bead {
            let arm = r * rho;
            let x = c + arm;
            let v = cd + omega.cross(&arm);
            let a = cdd + alpha.cross(&arm) + omega.cross(&omega.cross(&arm));
            let i = k * NODE_DOFS;
            for d in 0..3 {
                self.st.qw[i + d] = x[d];
                self.st.vw[i + d] = v[d];
                self.st.aw[i + d] = a[d];
            }
        }
        let pc = self.ends.plate_coord;
        self.st.qw[pc..pc + PLATE_AXES].copy_from_slice(&u);
        self.st.vw[pc..pc + PLATE_AXES].copy_from_slice(&ud);
        self.st.aw[pc..pc + PLATE_AXES].copy_from_slice(&udd);
    }

    /// Fills the work buffers with the full state at `t` from free `q`, `v`, `a`.
    fn fill_work(&mut self, t: f64, lambda: f64, q: &[f64], v: &[f64], a: &[f64]) {
        self.st.expand(q, v, a);
        self.work.pose = self.plate_motion(t, lambda);
        let pose = self.work.pose[0];
        self.prescribe_pose(&pose, false);
    }

    /// Residual of `mech` at the work state into the full `f` (with the iteration matrix if
    /// asked, the rank-one part if its buffer is long enough); the unit pressure load into
    /// `g`. Returns the strain energy [J].
    #[allow(clippy::too_many_arguments)]
    fn assemble(
        mech: &mut Mech,
        st: &mut FramedState,
        g: &mut [f64],
        p_g: f64,
        dp_dv: f64,
        f: &mut [f64],
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> f64 {
        f.fill(0.0);
        g.fill(0.0);
        if let Some((_, vals)) = jac.as_mut() {
            vals.fill(0.0);
        }
        let x = Eval {
            q: &st.qw,
            v: &st.vw,
            a: &st.aw,
            g: Vector3::zeros(),
        };
        let mut u = mech
            .quads
            .add_residual(&x, None, f, jac.as_mut().map(|(c, v)| (*c, &mut **v)));
        if let Some(s) = &mech.shells {
            u += s.add_residual(
                &x,
                Some(&mut st.frames),
                f,
                jac.as_mut().map(|(c, v)| (*c, &mut **v)),
            );
        }
        let conn = mech.quads.connectivity();
        let (mut fe, mut ke) = (SVector::<f64, 12>::zeros(), SMatrix::<f64, 12, 12>::zeros());
        for e in 0..conn.len() {
            let d = conn.dofs(e);
            let xe: [Vector3<f64>; 4] = std::array::from_fn(|i| {
                Vector3::new(st.qw[d[3 * i]], st.qw[d[3 * i + 1]], st.qw[d[3 * i + 2]])
            });
            match jac.as_mut() {
                Some((c, vals)) => {
                    pressure_into(&xe, 1.0, &mut fe, Some(&mut ke));
                    conn.add_matrix(e, &ke, -c.stiffness * p_g, vals);
                }
                None => pressure_into(&xe, 1.0, &mut fe, None),
            }
            conn.add_vector(e, &fe, 1.0, g);
        }
        for (fi, gi) in f.iter_mut().zip(g.iter()) {
            *fi -= p_g * gi;
        }
        mech.contact
            .add_residual(&st.qw, &st.vw, f, jac.as_mut().map(|(c, v)| (*c, &mut **v)));
        if mech.plate_touched(&st.qw) {
            mech.plate
                .add_residual(&st.qw, &st.vw, f, jac.as_mut().map(|(c, v)| (*c, &mut **v)));
        }
        if let Some((c, vals)) = jac {
            let nnz = mech.asm.pattern.nnz();
            if vals.len() == rank_one_len(&mech.asm.pattern) {
                vals[nnz] = -c.stiffness * dp_dv;
                for (i, &full) in mech.asm.dofs.free_to_full().iter().enumerate() {
                    vals[nnz + 1 + i] = g[full];
                }
            }
        }
        u
    }

    /// Residual and iteration matrix on the free coordinates at the work state.
    fn evaluate_filled(
        &mut self,
        mode: Pressure,
        r: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        let vb = self.bag_volume(&self.st.qw, &self.work.pose[0]);
        if !(vb.is_finite() && vb > 0.0) {
            return Err(ModelError::NonFinite);
        }
        let (p_g, dp_dv) = mode.gauge(&self.gas, self.ambient, vb)?;
        let check = jac.is_some();
        let mut jac = jac;
        let mut f = std::mem::take(&mut self.st.fw);
        self.last_strain = Self::assemble(
            &mut self.main,
            &mut self.st,
            &mut self.work.g,
            p_g,
            dp_dv,
            &mut f,
            jac.as_mut().map(|(c, v)| (*c, &mut **v)),
        );
        let res = self.st.finish_assembly(
            f,
            r,
            if check {
                jac.as_ref().map(|(_, v)| &**v)
            } else {
                None
            },
        );
        if !self.last_strain.is_finite() {
            return Err(ModelError::NonFinite);
        }
        res
    }

    /// Force and moment on the plate of the residual in `self.st.fw` at the work pose and the
    /// gauge pressure `p_g` [Pa].
    fn plate_load(&self, p_g: f64) -> [f64; PLATE_AXES] {
        let (c, r, _) = Self::plate_frame(&self.work.pose[0]);
        let mut force = r * self.ends.plate_area * p_g;
        let mut moment = Vector3::zeros();
        for &(k, _) in &self.ends.bead {
            let i = k * NODE_DOFS;
            let rk = Vector3::new(self.st.fw[i], self.st.fw[i + 1], self.st.fw[i + 2]);
            force -= rk;
            moment -= (self.node(&self.st.qw, k) - c).cross(&rk);
        }
        let (fc, mc) = Self::plate_contact_load(&self.main, &self.ends, &self.st, &c);
        force += fc;
        moment += mc;
        [force.x, force.y, force.z, moment.x, moment.y]
    }

    /// Force and moment about the plate centre `c` of the plate contact on the plate at the
    /// work state [N, N m]: the force on the plate at a node is what the contact adds to the
    /// node's residual (frictionless: along the plate normal, so the node's position is as
    /// good an arm as the contact point's).
    fn plate_contact_load(
        mech: &Mech,
        ends: &Ends,
        st: &FramedState,
        c: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let (mut force, mut moment) = (Vector3::zeros(), Vector3::zeros());
        if !mech.plate_touched(&st.qw) {
            return (force, moment);
        }
        for (e, &k) in ends.plate_nodes.iter().enumerate() {
            let mut fk = [0.0; 3];
            mech.plate
                .subtract_element_forces(e, &st.qw, &st.vw, &mut fk);
            if fk != [0.0; 3] {
                let fk = Vector3::from(fk);
                let i = k * NODE_DOFS;
                let xk = Vector3::new(st.qw[i], st.qw[i + 1], st.qw[i + 2]);
                force += fk;
                moment += (xk - c).cross(&fk);
            }
        }
        (force, moment)
    }

    /// Pseudo-transient continuation (`(K + c M) Δq = −r`, `c` shrinking with the residual)
    /// moving the plate from pose `from` to `to` under the gas mode `mode`, from the committed
    /// shape, in levels of at most an element length of plate motion.
    fn continuation(
        &mut self,
        from: [f64; PLATE_AXES],
        to: [f64; PLATE_AXES],
        mode: Pressure,
    ) -> Result<(), String> {
        self.admissible(&to).map_err(|e| e.to_string())?;
        let n = self.st.asm.dofs.n_free();
        let length = self.scales.iter().fold(0.0f64, |a, &b| a.max(b));
        let ell = length / self.n_mer as f64;
        let dist = (0..3)
            .map(|i| (to[i] - from[i]).powi(2))
            .sum::<f64>()
            .sqrt()
            + (to[3].hypot(to[4]) - from[3].hypot(from[4])).abs() * length;
        let max_step = if dist > 0.0 {
            (0.25 * ell / dist).min(0.25)
        } else {
            1.0
        };
        let mut step = max_step.min(1.0);
        let mut ws = crate::solver::Workspace::new(&*self, solver_kind(&self.st.asm.pattern))
            .map_err(|e| e.to_string())?;
        let mut x = vec![0.0; n];
        self.st.asm.dofs.restrict(&self.st.q, &mut x);
        let zeros = vec![0.0; n];
        let c_start = 1e6 / (length * length) * 4.4 / self.mass_per_area.max(1e-300);
        let p_scale = match mode {
            Pressure::Fixed(p) => p.abs(),
            _ => self.gas.committed().p_gauge.abs(),
        }
        .max(1e3);
        let r_scale = p_scale * length * length / (self.n_mer * self.n_circ) as f64;
        let mut level = 0.0f64;
        let mut last_err = String::new();
        // a budget of Newton iterations: a level converges in 6 to 60 where the path exists
        // (measured on the reference spring), so a level that needs more has lost it
        let mut budget = 1000usize;
        let frames_saved = self.st.frames.clone();
        let q_saved = self.st.q.clone();
        while level < 1.0 {
            let target = (level + step).min(1.0);
            let saved = x.clone();
            let frames_level = self.st.frames.clone();
            let mut pose = [0.0; PLATE_AXES];
            for i in 0..PLATE_AXES {
                pose[i] = from[i] + target * (to[i] - from[i]);
            }
            let mut relax = Relaxation::new(1e-2 * c_start);
            let mut ok = false;
            for _ in 0..80 {
                if budget == 0 {
                    last_err = "1000 Newton iterations spent".into();
                    break;
                }
                budget -= 1;
                self.st.expand(&x, &zeros, &zeros);
                self.prescribe_pose(&pose, true);
                let coeffs = JacobianCoeffs {
                    mass: relax.c,
                    damping: 0.0,
                    stiffness: 1.0,
                };
                if let Err(e) = self.evaluate_filled(mode, &mut ws.r, Some((coeffs, &mut ws.jac))) {
                    last_err = e.to_string();
                    break;
                }
                let cap = 0.25 / self.n_mer as f64;
                let it = match relax.iterate(&mut ws, &mut x, &self.scales, cap) {
                    Ok(it) => it,
                    Err(e) => {
                        last_err = e;
                        break;
                    }
                };
                // absorb the rotations: the increments stay small
                let mut full = std::mem::take(&mut self.st.q);
                self.st.asm.dofs.expand(&x, &mut full);
                self.st.frames.absorb(&mut full);
                self.st.asm.dofs.restrict(&full, &mut x);
                self.st.q = full;
                if std::env::var("AIRSPRING_DEBUG").is_ok() {
                    eprintln!(
                        "shell level {target:.3} |r| {:.3e} inc {:.3e} scale {:.2e} c {:.3e}",
                        it.r_norm, it.inc, it.scale, relax.c
                    );
                }
                if it.inc < 1e-10 && it.scale == 1.0 && it.r_norm < 1e-8 * r_scale {
                    ok = true;
                    break;
                }
                relax.settle();
            }
            if ok {
                level = target;
                step = (step * 1.5).min(max_step);
            } else {
                x = saved;
                self.st.frames = frames_level;
                step *= 0.5;
                if step < 1e-3 || budget == 0 {
                    self.st.frames = frames_saved;
                    self.st.q = q_saved;
                    return Err(format!(
                        "no static equilibrium of the shell sleeve from pose {from:?} to {to:?} (reached {:.0} % of the way: {last_err}); the membrane level of the same parameters found one: try a finer {MESH_N_CIRCUMFERENTIAL}, or a {BELLOWS_BENDING_STIFFNESS}",
                        100.0 * level
                    ));
                }
            }
        }
        let mut q = std::mem::take(&mut self.st.q);
        self.st.asm.dofs.expand(&x, &mut q);
        self.st.qw.copy_from_slice(&q);
        self.st.q = q;
        self.prescribe_pose(&to, true);
        let qw = self.st.qw.clone();
        for &(k, _) in &self.ends.bead {
            let i = k * NODE_DOFS;
            self.st.q[i..i + 3].copy_from_slice(&qw[i..i + 3]);
        }
        let pc = self.ends.plate_coord;
        self.st.q[pc..pc + PLATE_AXES].copy_from_slice(&qw[pc..pc + PLATE_AXES]);
        self.st.v.fill(0.0);
        self.st.acc.fill(0.0);
        self.pose = to;
        self.plate = PlateInput::at_pose(&to);
        self.pressure_now = match mode {
            Pressure::Fixed(p) => p,
            _ => {
                let vb = self.bag_volume(&self.st.q, &to);
                self.gas
                    .static_pressure(vb)
                    .map_or(0.0, |(p, _)| p - self.ambient)
            }
        };
        // a new shape: the predictor's history is stale
        self.trend.reset();
        self.commits += 1;
        Ok(())
    }

    /// Books the plate load of the committed state (its accelerations); `vb` is its bag volume ([`AirSpringShell::bag_volume`] of the committed coordinates and
    /// pose, which every caller has computed already). The load comes from the bead ring's
    /// rows alone ([`AirSpringShell::bead_rows`]: those of the full residual, bit for bit); the
    /// strain and kinetic energies are computed when asked ([`AirSpringShell::strain_energy`],
    /// [`AirSpringShell::kinetic_energy`]).
    fn commit_reaction(&mut self, vb: f64) -> Result<(), ModelError> {
        self.st.qw.copy_from_slice(&self.st.q);
        self.st.vw.copy_from_slice(&self.st.v);
        self.st.aw.copy_from_slice(&self.st.acc);
        let pose = self.pose;
        self.work.pose[0] = pose;
        // the committed bead motion: rates of the inputs at the committed time
        for i in 0..PLATE_AXES {
            let (_, rate, acc) = self.plate.axis_motion(i, self.st.t);
            self.work.pose[1][i] = rate;
            self.work.pose[2][i] = acc;
        }
        self.prescribe_pose(&pose, false);
        self.strain.set(None);
        self.plate_energy = 0.0;
        // no inertia in quasi-static steps (whether they are is what counts at the commit)
        self.kinetic.set(self.quasi_static.then_some(0.0));
        if !(vb.is_finite() && vb > 0.0) {
            return Err(ModelError::NonFinite);
        }
        let (p_res, _) = Pressure::Step(0.0).gauge(&self.gas, self.ambient, vb)?;
        self.bead_rows(p_res);
        let p_g = self
            .gas
            .evaluate(0.0, vb)
            .map_err(|_| ModelError::NonFinite)?
            .p_gauge;
        self.force = self.plate_load(p_g);
        if !self.force.iter().all(|f| f.is_finite()) {
            return Err(ModelError::NonFinite);
        }
        Ok(())
    }

    /// The bead ring's rows of the residual at the work state with the gauge pressure `p_g`
    /// [Pa] into `self.st.fw`, as [`AirSpringShell::assemble`] puts them there (the same terms
    /// added in the same order: the elements on the ring in ascending order, the gas on them,
    /// the piston contact of the ring's nodes; the plate contact has no bead node), from the
    /// [`Ends::bead_elements`] alone. The other rows of `fw` hold partial sums.
    fn bead_rows(&mut self, p_g: f64) {
        let mut f = std::mem::take(&mut self.st.fw);
        f.fill(0.0);
        let g = &mut self.work.g;
        g.fill(0.0);
        let (mech, st, ends) = (&self.main, &mut self.st, &self.ends);
        let x = Eval {
            q: &st.qw,
            v: &st.vw,
            a: &st.aw,
            g: Vector3::zeros(),
        };
        mech.quads
            .add_residual_of(&ends.bead_elements, &x, None, &mut f);
        if let Some(s) = &mech.shells {
            s.add_residual_of(&ends.bead_elements, &x, Some(&mut st.frames), &mut f);
        }
        let conn = mech.quads.connectivity();
        let mut fe = SVector::<f64, 12>::zeros();
        for &e in &ends.bead_elements {
            let d = conn.dofs(e);
            let xe: [Vector3<f64>; 4] = std::array::from_fn(|i| {
                Vector3::new(st.qw[d[3 * i]], st.qw[d[3 * i + 1]], st.qw[d[3 * i + 2]])
            });
            pressure_into(&xe, 1.0, &mut fe, None);
            conn.add_vector(e, &fe, 1.0, g);
        }
        for &(k, _) in &ends.bead {
            let i = k * NODE_DOFS;
            let mut row: [f64; 3] = std::array::from_fn(|c| f[i + c] - p_g * g[i + c]);
            // the piston contact's block `k` is node `k`'s
            mech.contact
                .subtract_element_forces(k, &st.qw, &st.vw, &mut row);
            f[i..i + 3].copy_from_slice(&row);
        }
        st.fw = f;
    }

    /// The kinetic energy of the committed state [J], computed on the first request after a
    /// commit.
    fn kinetic_energy(&self) -> f64 {
        if let Some(t) = self.kinetic.get() {
            return t;
        }
        let (q, v) = (&self.st.q, &self.st.v);
        let mut t = self.main.quads.kinetic_energy(q, v, None);
        if let Some(s) = &self.main.shells {
            t += s.kinetic_energy(q, v, Some(&self.st.frames));
        }
        self.kinetic.set(Some(t));
        t
    }

    /// The strain energy of the committed state [J]: the elements' and the plate contact's
    /// penalty energy, computed on the first request after a commit.
    fn strain_energy(&self) -> f64 {
        if let Some(u) = self.strain.get() {
            return u;
        }
        let mut u = self.main.quads.strain_energy(&self.st.q, None);
        if let Some(s) = &self.main.shells {
            u += s.strain_energy(&self.st.q, Some(&self.st.frames));
        }
        let u = u + self.plate_energy;
        self.strain.set(Some(u));
        u
    }

    /// The port block of the committed state, computed on the first request after a commit.
    fn condensed(&self) -> Option<Condensed> {
        let mut guard = self.cond.borrow_mut();
        let cond = &mut *guard;
        if let Some((k, c)) = cond.cache
            && k == self.commits
        {
            return c;
        }
        let c = self.compute_condensed(cond);
        cond.cache = Some((self.commits, c));
        c
    }

    /// Static condensation at the committed state (at rest, the gas's instantaneous `dp/dV`):
    /// for each plate axis `j` the bead ring's motion `T_j`, the shape change
    /// `y_j = −K_ff⁻¹ ∂r_f/∂u_j` (with the rank-one gas term), and the change of the plate load.
    fn compute_condensed(&self, cond: &mut Condensation) -> Option<Condensed> {
        let Condensation {
            main,
            full,
            main_solver,
            main_vals,
            full_vals,
            main_in_full,
            plate_vals,
            fc,
            dfc,
            st,
            g,
            f,
            vgrad,
            t,
            kt,
            dfull,
            dr,
            y,
            ..
        } = cond;
        // the committed friction: stuck points stay stuck
        full.contact.copy_histories(&self.main.contact);
        st.qw.copy_from_slice(&self.st.q);
        st.vw.fill(0.0);
        st.aw.fill(0.0);
        st.frames.clone_from(&self.st.frames);
        let vb = self.bag_volume(&self.st.q, &self.pose);
        let e = self.gas.evaluate(0.0, vb).ok()?;
        let (p_g, dp_dv) = (e.p_gauge, e.dp_dv);
        let coeffs = JacobianCoeffs {
            mass: 0.0,
            damping: 0.0,
            stiffness: 1.0,
        };
        // the main system (free coordinates, rank-one gas term)
        if main_solver.is_none() {
            *main_solver =
                Some(LinearSolver::new(&main.asm.pattern, solver_kind(&main.asm.pattern)).ok()?);
            *main_vals = vec![0.0; rank_one_len(&main.asm.pattern)];
            *full_vals = vec![0.0; full.asm.pattern.nnz()];
            *plate_vals = vec![0.0; full.asm.pattern.nnz()];
            let (mp, fp) = (&main.asm.pattern, &full.asm.pattern);
            let to_full = main.asm.dofs.free_to_full();
            *main_in_full = (0..mp.n())
                .flat_map(|c| (mp.col_ptr()[c]..mp.col_ptr()[c + 1]).map(move |k| (k, c)))
                .map(|(k, c)| fp.position(to_full[mp.row_idx()[k]], to_full[c]))
                .collect::<Option<Vec<usize>>>()?;
        }
        let solver = main_solver.as_mut()?;
        // every coordinate free: K over all rows and columns, and the residual of the state
        Self::assemble(full, st, g, p_g, 0.0, f, Some((coeffs, &mut full_vals[..])));
        // the main system (free coordinates): the same element, pressure and contact blocks
        // restricted to the free rows and columns, and the rank-one gas term
        let nnz = main.asm.pattern.nnz();
        for (v, &k) in main_vals.iter_mut().zip(main_in_full.iter()) {
            *v = full_vals[k];
        }
        main_vals[nnz] = -coeffs.stiffness * dp_dv;
        for (i, &fi) in main.asm.dofs.free_to_full().iter().enumerate() {
            main_vals[nnz + 1 + i] = g[fi];
        }
        solver.factor(&main.asm.pattern, main_vals).ok()?;
        // the plate contact alone: its forces on the plate and their derivatives
        plate_vals.fill(0.0);
        fc.fill(0.0);
        if full.plate_touched(&st.qw) {
            full.plate
                .add_residual(&st.qw, &st.vw, fc, Some((coeffs, &mut plate_vals[..])));
        }
        // out of contact the plate's part is zero: no products with it
        let on_plate = fc.iter().any(|x| *x != 0.0);
        let dofs = &main.asm.dofs;
        // ∂V/∂q of every patch (for the direct volume change of a plate motion)
        let conn = main.quads.connectivity();
        vgrad.fill(0.0);
        for el in 0..conn.len() {
            let d = conn.dofs(el);
            let xe: [Vector3<f64>; 4] = std::array::from_fn(|i| {
                Vector3::new(st.qw[d[3 * i]], st.qw[d[3 * i + 1]], st.qw[d[3 * i + 2]])
            });
            let ge = volume_part_gradient(&xe);
            for (a, &i) in d.iter().enumerate() {
                vgrad[i] += ge[a];
            }
        }
        let pose = self.pose;
        let (c, r, ts) = Self::plate_frame(&pose);
        let a_out = r * self.ends.plate_area;
        let mut out = Condensed {
            k: [[0.0; PLATE_AXES]; PLATE_AXES],
            dv: [0.0; PLATE_AXES],
        };
        // T_j (the bead ring's and the plate's motion along plate axis j), the turn of the
        // plate frame and the direct volume change (patches and the plate cap)
        let direction = |j: usize, t: &mut [f64]| {
            t.fill(0.0);
            let turn = if j >= 3 {
                Some(ts * Vector3::ith(j - 3, 1.0))
            } else {
                None
            };
            for &(k, rho) in &self.ends.bead {
                let dx = match turn {
                    Some(w) => w.cross(&(r * rho)),
                    None => Vector3::ith(j, 1.0),
                };
                t[k * NODE_DOFS..k * NODE_DOFS + 3].copy_from_slice(dx.as_slice());
            }
            // the plate as the contact's obstacle
            t[self.ends.plate_coord + j] = 1.0;
            let mut vdir: f64 = vgrad.iter().zip(t.iter()).map(|(a, b)| a * b).sum();
            vdir += match turn {
                Some(w) => c.dot(&w.cross(&a_out)) / 3.0,
                None => a_out[j] / 3.0,
            };
            (turn, vdir)
        };
        // ∂r_f/∂u_j = (K T_j)_f − dp/dV vdir g_f; y_j = −K_ff⁻¹ that, the five solved together
        let n_free = dofs.n_free();
        for (j, yj) in y.chunks_exact_mut(n_free).enumerate() {
            let (_, vdir) = direction(j, t);
            full.asm.pattern.mul_vec(full_vals, t, kt);
            for (i, &fi) in dofs.free_to_full().iter().enumerate() {
                yj[i] = -(kt[fi] - dp_dv * vdir * g[fi]);
            }
        }
        solver.solve_many_in_place(y);
        for j in 0..PLATE_AXES {
            let (turn, vdir) = direction(j, t);
            let y = &y[j * n_free..(j + 1) * n_free];
            dfull.copy_from_slice(t);
            let mut dv = vdir;
            for (i, &fi) in dofs.free_to_full().iter().enumerate() {
                dfull[fi] = y[i];
                dv += g[fi] * y[i];
            }
            let dp = dp_dv * dv;
            full.asm.pattern.mul_vec(full_vals, dfull, dr);
            let mut df = a_out * dp
                + match turn {
                    Some(w) => w.cross(&a_out) * p_g,
                    None => Vector3::zeros(),
                };
            let mut dm = Vector3::zeros();
            for &(k, _) in &self.ends.bead {
                let i = k * NODE_DOFS;
                let drk = Vector3::new(dr[i], dr[i + 1], dr[i + 2])
                    - Vector3::new(g[i], g[i + 1], g[i + 2]) * dp;
                let rk = Vector3::new(f[i], f[i + 1], f[i + 2]);
                let arm = self.node(&st.qw, k) - c;
                let darm = match turn {
                    Some(w) => w.cross(&arm),
                    None => Vector3::zeros(),
                };
                df -= drk;
                dm -= darm.cross(&rk) + arm.cross(&drk);
            }
            // the plate contact: force `fc_k` on the plate at node k, moment `(x_k − c) × fc_k`
            if on_plate {
                full.asm.pattern.mul_vec(plate_vals, dfull, dfc);
                let dc = if j < 3 {
                    Vector3::ith(j, 1.0)
                } else {
                    Vector3::zeros()
                };
                for &k in &self.ends.plate_nodes {
                    let i = k * NODE_DOFS;
                    let fk = Vector3::new(fc[i], fc[i + 1], fc[i + 2]);
                    let dfk = Vector3::new(dfc[i], dfc[i + 1], dfc[i + 2]);
                    if fk == Vector3::zeros() && dfk == Vector3::zeros() {
                        continue;
                    }
                    let arm = self.node(&st.qw, k) - c;
                    let darm = Vector3::new(dfull[i], dfull[i + 1], dfull[i + 2]) - dc;
                    df += dfk;
                    dm += darm.cross(&fk) + arm.cross(&dfk);
                }
            }
            let col = [df.x, df.y, df.z, dm.x, dm.y];
            for (i, v) in col.iter().enumerate() {
                out.k[i][j] = *v;
            }
            out.dv[j] = dv;
        }
        Some(out)
    }

    /// Largest distance of a node from the axis, as the radius of the circle its ring stands
    /// for [m].
    fn lobe_radius(&self) -> f64 {
        (0..self.n_nodes)
            .map(|k| self.node(&self.st.q, k).xy().norm())
            .fold(0.0, f64::max)
            / self.scale
    }

    fn output_index(o: Output) -> Option<usize> {
        Some(match o {
            Output::TopFx => 0,
            Output::TopFy => 1,
            Output::TopFz => 2,
            Output::TopMx => 3,
            Output::TopMy => 4,
            _ => return None,
        })
    }

    fn value(&self, o: Output) -> f64 {
        if let Some(v) = gas_output(o, &self.gas, self.v_charge) {
            return v;
        }
        if let Some(i) = Self::output_index(o) {
            // extrapolated to the plate inputs at the committed time
            let du: [f64; PLATE_AXES] =
                std::array::from_fn(|j| self.plate.axis_motion(j, self.st.t).0 - self.pose[j]);
            if du.iter().all(|d| *d == 0.0) {
                return self.force[i];
            }
            return match self.condensed() {
                Some(c) => self.force[i] + (0..PLATE_AXES).map(|j| c.k[i][j] * du[j]).sum::<f64>(),
                None => self.force[i],
            };
        }
        let e = self.gas.committed();
        match o {
            Output::Height => self.pose[AXIS_Z],
            Output::EffectiveArea => {
                if e.p_gauge != 0.0 {
                    self.force[2] / e.p_gauge
                } else {
                    f64::NAN
                }
            }
            Output::VolumetricArea => self.condensed().map_or(f64::NAN, |c| c.dv[AXIS_Z]),
            Output::Stiffness => self.condensed().map_or(f64::NAN, |c| -c.k[2][AXIS_Z]),
            Output::LobeRadius => self.lobe_radius(),
            Output::StrainEnergy => self.strain_energy(),
            Output::KineticEnergy => self.kinetic_energy(),
            Output::PlateWork => self.plate_work,
            Output::Dissipated => e.heat_out + e.loss_work + self.contact_loss,
            _ => f64::NAN,
        }
    }
}

impl MechanicalSystem for AirSpringShell {
    fn n_free(&self) -> usize {
        self.st.asm.dofs.n_free()
    }

    fn pattern(&self) -> &CscPattern {
        &self.st.asm.pattern
    }

    fn scales(&self) -> &[f64] {
        &self.scales
    }

    fn rank_one(&self) -> bool {
        true
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
        // Before the first accepted state (the consistent initial accelerations after the
        // static solve) the gas is at rest in the static state the solve used: its committed
        // state is still the design charge, whose step law would give another pressure off
        // the design height with the energy law or a reservoir (the spring would start out
        // of equilibrium and ring).
        let mode = if self.statics || !self.initialized {
            Pressure::Static
        } else {
            Pressure::Step((t - self.st.t).max(0.0))
        };
        self.fill_work(t, load_factor, q, v, a);
        self.admissible(&self.work.pose[0])?;
        self.evaluate_filled(mode, r, jac)
    }

    /// The plain implicit midpoint rule: the residual at `(q_a + q_b)/2` (in the chart of the
    /// stored orientations) and the midpoint time, the stiffness coefficient halved.
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
        let tm = 0.5 * (t_a + t_b);
        self.st.expand_midpoint(q_a, q_b, v, a);
        self.work.pose = self.plate_motion(tm, 1.0);
        let pose = self.work.pose[0];
        self.admissible(&pose)?;
        self.prescribe_pose(&pose, false);
        let jac = jac.map(|(c, vals)| {
            (
                JacobianCoeffs {
                    stiffness: 0.5 * c.stiffness,
                    ..c
                },
                vals,
            )
        });
        self.evaluate_filled(Pressure::Step((tm - self.st.t).max(0.0)), r, jac)
    }

    fn rebase(&mut self, q: &mut [f64]) {
        self.st.rebase(q);
    }

    /// The wall is held by the bead and the clamp rings, the plate's pose is prescribed and
    /// the gas pressure inflates it: every coordinate has its equilibrium, inertia is optional.
    fn set_quasi_static(&mut self, on: bool) -> bool {
        self.quasi_static = on;
        true
    }

    /// Quasi-static steps: the step's increment extrapolated quadratically in time through
    /// the last two steps' increments ([`StepTrend`]; the node rotations are increments in
    /// the chart of the committed orientations, so the shape itself cannot be extrapolated
    /// as the membrane level's is). The integrator's `q₀ + h v₀` is exact only for a
    /// motion linear in time. Left to the integrator with inertia, in a static solve, with
    /// fewer than three commits since the last new shape, or for a step more than three
    /// times the last ones.
    fn predict(&mut self, q0: &[f64], _v0: &[f64], h: f64, q1: &mut [f64]) -> bool {
        self.quasi_static && !self.statics && self.trend.predict(self.st.t, h, q0, q1)
    }

    /// Quasi-static steps: the prediction moves the shape along the path the kept matrix
    /// was computed on.
    fn prediction_keeps_matrix(&self) -> bool {
        self.quasi_static
    }

    /// Quasi-static steps: with the predictor most steps start near the solution (as the
    /// membrane level's).
    fn trusts_kept_contraction(&self) -> bool {
        self.quasi_static
    }

    /// Damped Newton where the sleeve has friction on the piston (`contact.mu` > 0), as on the
    /// belt drives: a node on the piston's contact line cycled between stick and slip from one
    /// iteration to the next (session 39: 24 × 40, μ = 0.5, a ±5 mm, 1 Hz lateral sine at 1 ms;
    /// the same node's increment stalling at 2.4e-7 of the length scale whatever the step), so
    /// that quasi-static steps failed at 12 ms even with the step cut to 1e-12 s (no inertia
    /// term to regularize the cycle), and generalized-α's steps were halved 318 times over the
    /// second (69 s of CPU time). Backtracking the full-Newton increments that raise the
    /// residual breaks the cycle: quasi-static steps run through (12 rejections over 1 s at
    /// 12 × 30, 32 at 24 × 40 with the tolerance 1e-7, 6 with 1e-8), generalized-α's
    /// rejections 318 → 17 (9.3 s). Without friction nothing cycles and the iteration is left
    /// as it was (bit-identical).
    fn damped_newton(&self) -> bool {
        self.main.contact.law().mu > 0.0
    }

    /// Quasi-static steps: a kept matrix holds the penalty blocks of the points that were in
    /// contact when it was built.
    fn kept_matrix_current(&self) -> bool {
        !self.quasi_static
            || (self.main.contact.matrix_is_current()
                && (!self.main.plate_on || self.main.plate.matrix_is_current()))
    }

    /// The static solve moves the plate from the last equilibrium to the inputs' pose with its
    /// load factor.
    fn hold_for_statics(&mut self, held: bool) {
        self.statics = held;
        if held {
            self.static_from = self.pose;
        }
    }
}

impl Model for AirSpringShell {
    /// Quasi-static steps spread a jump of the position inputs over the communication step
    /// ([`AirSpringShell::plate_motion`]).
    fn begin_communication_step(&mut self, t0: f64, t1: f64) {
        let d: [f64; PLATE_AXES] =
            std::array::from_fn(|i| self.pose[i] - self.plate.axis_motion(i, t0).0);
        self.input_jump =
            (self.quasi_static && !self.statics && t1 > t0 && d.iter().any(|x| *x != 0.0))
                .then_some((t0, t1, d));
    }

    /// What the automatic count around chose (`mesh.n_circumferential = 0`).
    fn build_note(&self) -> Option<String> {
        self.auto_note.clone()
    }

    /// Rings of nodes (ordered by angle) and meridian lines through the committed node
    /// positions, at most 16 of each (evenly picked, first and last included) so that the
    /// drawing stays legible.
    fn sketch(&self) -> crate::model::Sketch {
        let (n_circ, n_mer) = self.mesh();
        let nodes = self.nodes();
        let mut s = crate::model::Sketch::new(format!(
            "{n_circ} × {n_mer} cord-rubber membrane quadrilaterals on the sleeve, {} nodes",
            nodes.len()
        ));
        let pick = |n: usize| -> Vec<usize> {
            let m = n.min(16);
            (0..m).map(|k| k * (n - 1) / (m - 1).max(1)).collect()
        };
        let rings: Vec<&[Vector3<f64>]> = nodes.chunks(n_circ).collect();
        for ring in pick(rings.len()).into_iter().map(|i| rings[i]) {
            let c = ring.iter().sum::<Vector3<f64>>() / ring.len() as f64;
            let mut pts = ring.to_vec();
            pts.sort_by(|a, b| {
                let angle = |p: &Vector3<f64>| (p.y - c.y).atan2(p.x - c.x);
                angle(a).total_cmp(&angle(b))
            });
            pts.push(pts[0]);
            s.line(pts);
        }
        // meridians at evenly spread angles of the first ring
        let first = rings[0];
        let c0 = first.iter().sum::<Vector3<f64>>() / first.len() as f64;
        let mut by_angle: Vec<usize> = (0..n_circ).collect();
        by_angle.sort_by(|&a, &b| {
            let angle = |p: &Vector3<f64>| (p.y - c0.y).atan2(p.x - c0.x);
            angle(&first[a]).total_cmp(&angle(&first[b]))
        });
        for k in pick(n_circ)
            .into_iter()
            .map(|i| by_angle[i])
            .take(n_circ.min(16))
        {
            s.line(nodes.iter().skip(k).step_by(n_circ).copied());
        }
        s
    }

    /// Before the first accepted state, a new plate input moves the charged spring there
    /// quasi-statically with the gas at rest.
    fn set_input(&mut self, input: usize, value: f64) {
        let role = self.inputs[input];
        let (axis, rate) = role.axis();
        if !self.initialized && !rate && value.is_finite() && value != self.pose[axis] {
            let from = self.pose;
            let mut to = from;
            to[axis] = value;
            if self.continuation(from, to, Pressure::Static).is_ok() {
                return;
            }
        }
        self.plate.set(role, value, self.st.t);
    }

    fn set_input_derivative(
        &mut self,
        input: usize,
        order: usize,
        value: f64,
    ) -> Result<(), String> {
        self.plate.set_derivative(self.inputs[input], order, value);
        Ok(())
    }

    fn output(&self, output: usize) -> f64 {
        self.value(self.outputs[output])
    }

    fn output_derivative(&self, output: usize) -> Option<f64> {
        let o = self.outputs[output];
        if o == Output::Height {
            return Some(self.plate.axis_motion(AXIS_Z, self.st.t).1);
        }
        let i = Self::output_index(o)?;
        let c = self.condensed()?;
        Some(
            (0..PLATE_AXES)
                .map(|j| c.k[i][j] * self.plate.axis_motion(j, self.st.t).1)
                .sum(),
        )
    }

    fn output_input_derivative(&mut self, output: usize, input: usize) -> Option<f64> {
        let i = Self::output_index(self.outputs[output])?;
        let (axis, rate) = self.inputs[input].axis();
        let k = self.condensed()?.k[i][axis];
        Some(if rate {
            k * self.plate.axis_lever(axis, self.st.t)
        } else {
            k
        })
    }

    fn hold_prescribed_motion(&mut self, hold: bool) {
        self.hold = hold;
    }

    fn input_restarts_accelerations(&self, _input: usize) -> bool {
        false
    }

    fn accept(&mut self, state: &mut DynState) {
        let dt = (state.t - self.st.t).max(0.0);
        self.fill_work(state.t, 1.0, &state.q, &state.v, &state.acc);
        let vb = self.bag_volume(&self.st.qw, &self.work.pose[0]);
        let committed = if self.initialized {
            self.gas.commit(dt, vb).map(|_| ())
        } else {
            self.gas.set_static(vb)
        };
        if let Err(e) = committed {
            debug_assert!(false, "gas commit failed: {e}");
        }
        let old_force = self.force;
        let old_pose = self.pose;
        let pose = self.work.pose;
        let ends = &self.ends.bead;
        let (c, r, ts) = Self::plate_frame(&pose[0]);
        let omega = ts * Vector3::new(pose[1][3], pose[1][4], 0.0);
        let alpha = ts * Vector3::new(pose[2][3], pose[2][4], 0.0);
        let pc = self.ends.plate_coord;
        self.st.accept(state, |mut q, mut v, mut a| {
            for (k, buf) in [q.as_deref_mut(), v.as_deref_mut(), a.as_deref_mut()]
                .into_iter()
                .enumerate()
            {
                if let Some(buf) = buf {
                    buf[pc..pc + PLATE_AXES].copy_from_slice(&pose[k]);
                }
            }
            for &(k, rho) in ends {
                let arm = r * rho;
                let i = k * NODE_DOFS;
                if let Some(q) = q.as_deref_mut() {
                    let x = c + arm;
                    q[i..i + 3].copy_from_slice(x.as_slice());
                }
                if let Some(v) = v.as_deref_mut() {
                    let w = Vector3::new(pose[1][0], pose[1][1], pose[1][2]) + omega.cross(&arm);
                    v[i..i + 3].copy_from_slice(w.as_slice());
                }
                if let Some(a) = a.as_deref_mut() {
                    let w = Vector3::new(pose[2][0], pose[2][1], pose[2][2])
                        + alpha.cross(&arm)
                        + omega.cross(&omega.cross(&arm));
                    a[i..i + 3].copy_from_slice(w.as_slice());
                }
            }
        });
        self.pose = pose[0];
        let book = self.main.contact.commit(&self.st.q, &self.st.v, false);
        let plate = if self.main.plate_touched(&self.st.q) {
            self.main.plate.commit(&self.st.q, &self.st.v, false)
        } else {
            ContactBook::default()
        };
        let power = book.dissipation + plate.dissipation;
        self.contact_loss += 0.5 * (self.last_damping_power + power) * dt + book.friction_work;
        self.last_damping_power = power;
        // `vb`: the committed state's bag volume (the same coordinates and pose)
        if self.commit_reaction(vb).is_err() {
            self.force = [f64::NAN; PLATE_AXES];
        }
        // the plate's penalty energy is stored elastic energy
        self.plate_energy = plate.normal_energy;
        if self.initialized {
            for i in 0..PLATE_AXES {
                self.plate_work -=
                    0.5 * (old_force[i] + self.force[i]) * (self.pose[i] - old_pose[i]);
            }
        }
        self.initialized = true;
        self.commits += 1;
        if self.quasi_static && !self.statics {
            self.trend.record(state.t, &state.v);
        } else {
            self.trend.reset();
        }
    }

    fn free_state(&self, q: &mut [f64], v: &mut [f64]) {
        self.st.free_state(q, v);
    }

    fn constant_mass(&self) -> bool {
        true
    }

    fn save(&self, w: &mut StateWriter) -> Result<(), String> {
        self.st.save(w);
        self.plate.save(w);
        w.bool(self.initialized);
        for x in self.pose.iter().chain(&self.force) {
            w.f64(*x);
        }
        for x in [
            self.strain_energy(),
            self.kinetic_energy(),
            self.plate_work,
            self.contact_loss,
            self.last_damping_power,
        ] {
            w.f64(x);
        }
        self.main.contact.save(w);
        self.gas.save(w);
        // the predictor's history only exists with quasi-static steps (a parameter)
        if self.quasi_static {
            self.trend.save(w);
        }
        Ok(())
    }

    fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        self.st.restore(r)?;
        self.plate = PlateInput::restore(r).map_err(e)?;
        self.initialized = r.bool().map_err(e)?;
        for i in 0..PLATE_AXES {
            self.pose[i] = r.f64().map_err(e)?;
        }
        for i in 0..PLATE_AXES {
            self.force[i] = r.f64().map_err(e)?;
        }
        let (mut strain, mut kinetic) = (0.0, 0.0);
        for x in [
            &mut strain,
            &mut kinetic,
            &mut self.plate_work,
            &mut self.contact_loss,
            &mut self.last_damping_power,
        ] {
            *x = r.f64().map_err(e)?;
        }
        self.strain.set(Some(strain));
        self.kinetic.set(Some(kinetic));
        self.plate_energy = 0.0;
        self.main.contact.restore(r)?;
        self.gas.restore(r).map_err(e)?;
        if self.quasi_static {
            self.trend.restore(r).map_err(e)?;
        }
        self.commits += 1;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    impl AirSpringShell {
        /// The plate load of the committed state from the full residual (what the accept
        /// computed before it took the bead ring's rows alone) and its strain energy.
        fn full_reaction(&mut self) -> ([f64; PLATE_AXES], f64) {
            let mut r = vec![0.0; self.n_free()];
            self.evaluate_filled(Pressure::Step(0.0), &mut r, None)
                .unwrap();
            let vb = self.bag_volume(&self.st.qw, &self.pose);
            let p_g = self.gas.evaluate(0.0, vb).unwrap().p_gauge;
            (self.plate_load(p_g), self.last_strain)
        }
    }

    /// The plate load the accept takes from the bead ring's rows is that of the full residual,
    /// and the strain energy computed when asked is the full residual's, on a plate moving
    /// down, sideways and tilting (with rates and the sleeve's velocities and accelerations),
    /// with and without bending (the shell elements' rows).
    #[test]
    fn plate_load_from_the_bead_rows_is_that_of_the_full_residual() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/air_spring.toml");
        let scene = Scene::from_path(&path).unwrap();
        let tables: &AirSpringScene = scene.tables().unwrap();
        for bending in [0.0, 0.05] {
            let mut p = ParamValues::defaults(&scene.params);
            p.set(BELLOWS_BENDING_STIFFNESS, Value::Real(bending));
            p.set(MESH_N_CIRCUMFERENTIAL, Value::Integer(12));
            p.set(MESH_N_MERIDIONAL, Value::Integer(16));
            let mut m = AirSpringShell::build(tables, &p).unwrap();
            let n = m.n_free();
            let mut state = DynState::zeros(n, 0.0);
            m.free_state(&mut state.q, &mut state.v);
            m.accept(&mut state);
            let input = |i: Input| m.inputs.iter().position(|x| *x == i).unwrap();
            let motion = [
                (input(Input::TopZ), input(Input::TopVz), 0.25, -0.5),
                (input(Input::TopX), input(Input::TopVx), 0.0, 0.2),
                (input(Input::TopRx), input(Input::TopWx), 0.0, 1.0),
                (input(Input::TopRy), input(Input::TopWy), 0.0, -0.5),
            ];
            for k in 0..6 {
                let t = 1e-3 * (k + 1) as f64;
                for &(ix, iv, x0, rate) in &motion {
                    m.set_input(ix, x0 + rate * t);
                    m.set_input(iv, rate);
                }
                // a nearby state: the last commit's shape, some velocity and acceleration
                let mut s = DynState::zeros(n, t);
                m.free_state(&mut s.q, &mut s.v);
                for i in 0..n {
                    s.v[i] = 0.01 * ((i * 7) % 5) as f64 - 0.02;
                    s.acc[i] = 3.0 * ((i * 3) % 7) as f64 - 9.0;
                }
                m.accept(&mut s);
                let rows = m.force;
                let lazy = m.strain_energy();
                let plate_energy = m.plate_energy;
                let (full, u) = m.full_reaction();
                let scale = full[2].abs();
                assert!(scale > 1e3, "fz {}", full[2]);
                for i in 0..PLATE_AXES {
                    assert!(
                        (rows[i] - full[i]).abs() <= 1e-12 * scale,
                        "bending {bending}, step {k}, axis {i}: {} from the rows, {} from the full residual",
                        rows[i],
                        full[i]
                    );
                }
                assert!(full[0].abs() > 1.0 && full[3].abs() > 1e-2, "{full:?}");
                let u = u + plate_energy;
                assert!(
                    (lazy - u).abs() <= 1e-12 * u.abs(),
                    "strain energy {lazy} vs {u}"
                );
            }
        }
    }
}
