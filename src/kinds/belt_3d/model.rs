//! 3D belt drive (work in progress for issue 13, not yet a registered kind): a closed belt of
//! seed-003 co-rotational beam elements (rectangular belt section: EA, bending about both
//! section axes, torsion, shear) in frictional contact with pulleys in space
//! ([`Pulley3d`]: centre, axis, crowned rim, flanges), through the shared
//! [`ContactPointSet`].
//!
//! Coordinates: per node `[x, y, z, θx, θy, θz]` (position, incremental rotation vector from
//! the node's stored orientation, as in `beam_3d`), then one angle per pulley about its axis;
//! driven pulleys' angles are prescribed (`θ = ω t`), free pulleys' are unknowns with
//! `J θ̈ + c θ̇ − Σ τ_contact = 0`.
//!
//! Stress-free shape: straight. Every element's reference section frame is the identity and
//! node `k` starts with the orientation `T_k = [t, a × t, a]` of the mounted path (tangent
//! `t`, width direction `a` = the pulleys' nominal axis), so the element's local rotations
//! `log(R_rᵀ R_k)` measure the bending of the mounted belt from a straight one (the belt on
//! a pulley carries the bending moment `EI/R`, as the 2D cable does).
//!
//! Contact: `contact.points_per_element` sections per element (default 2), at
//! `(i + 0.5)/m` of its length on the element's cubic Hermite centre line (the nodes'
//! positions and tangents), each standing for `l/m` ([`SectionContactSet`]: the forces and
//! moments go to both nodes). Points on the chord would not do: they sit
//! `l² ξ(1 − ξ)/(2R)` inside a pulley of pitch radius `R` (0.16 mm for 8 mm elements on a
//! 50 mm pulley, far beyond the penalty penetration). With `points_per_element = 0` (the
//! default until session 33) only the nodes, which lie on the centre line, carry contact,
//! each standing for one element length: the belt then meets the rims at the node-passing
//! frequency, which excites the spans and raised the loaded drive's tensions and creep above
//! the planar drive's (README "Running planar limit"). Each section touches the rims at
//! `contact.width_points` points across the width, so that the belt lies across a crown; on
//! a pulley's arc the mount turns the node sections onto the rim's generator (tilted by the
//! crown's slope and the pulley's tilt).

use super::Belt3dScene;
use super::path::{SpaceCircle, SpacePath};
use super::scene::{Input, Output, PulleyInput};
use crate::assembly::{Assembly, Connectivity, DofMap, ElementSet};
use crate::contact::section3d::SECTION_BLOCK;
use crate::contact::{ContactBook, ContactLaw, Pulley3d, SectionContactSet};
use crate::elements::corotational3d::{
    BeamSection, Corot3d, ELEMENT_DOFS, MassModel, NODE_DOFS, Nodes, Theory, hermite, hermite_d1,
};
use crate::elements::node_frames::NodeFrames;
use crate::integrators::DynState;
use crate::kinds::KindIo;
use crate::kinds::energy::EnergyKind;
use crate::linalg::CscPattern;
use crate::meshers::belt_loop::{Loop, PitchCircle};
use crate::model::framed::FramedState;
use crate::model::inputs::{InputSignal, prescribed};
use crate::model::{
    JacobianCoeffs, MechanicalSystem, Model, ModelError, newton_scales_with_gradients,
};
use crate::scene::ParamValues;
use crate::snapshot::{StateReader, StateWriter};
use crate::solver::simulation::SolverConfig;
use nalgebra::{Matrix3, Rotation3, Unit, UnitQuaternion, Vector2, Vector3};

/// Halvings of a full-Newton increment that raised the residual norm, at most, for the 3D
/// belt ([`Belt3d::line_search_cuts`]).
pub const BELT3D_LINE_SEARCH_CUTS: usize = 6;

/// How a 3D pulley moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pulley3dMotion {
    /// Turning at the prescribed speed [rad/s] about its axis.
    Driven {
        /// Angular velocity [rad/s].
        omega: f64,
    },
    /// Rigid body turning about its axis, loaded by a torque.
    Free {
        /// Moment of inertia about the axis [kg m²].
        inertia: f64,
        /// Viscous bearing damping [N m s/rad].
        damping: f64,
        /// Applied torque about the axis [N m].
        torque: f64,
    },
}

/// A pulley of the 3D drive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pulley3dDef {
    /// Centre of the rim's middle [m].
    pub center: Vector3<f64>,
    /// Axis direction (any length).
    pub axis: Vector3<f64>,
    /// Rim radius at its middle [m] (the belt's inner face rests on it).
    pub radius: f64,
    /// Rim width between the flange faces [m].
    pub rim_width: f64,
    /// Crown height [m] (0: flat rim).
    pub crown: f64,
    /// Flange height above the rim [m] (0: no flanges).
    pub flange: f64,
    /// Driven or free.
    pub motion: Pulley3dMotion,
}

/// Everything a 3D belt drive is built from.
#[derive(Clone, Debug, PartialEq)]
pub struct Belt3dSpec {
    /// Belt section.
    pub section: BeamSection,
    /// Belt thickness [m] (the centre line runs at rim radius + thickness/2).
    pub thickness: f64,
    /// Belt width [m].
    pub width: f64,
    /// Pulleys, in the order the belt wraps them counter-clockwise about `+z` when laid out
    /// in their nominal plane (centres' x, y).
    pub pulleys: Vec<Pulley3dDef>,
    /// Contact constants (per unit belt length).
    pub contact: ContactLaw,
    /// Number of elements.
    pub n_elements: usize,
    /// Span tension of the mounted belt [N] (reference length = mounted / (1 + T/EA)).
    pub pretension: f64,
    /// Gravity [m/s²].
    pub gravity: Vector3<f64>,
    /// Bowing term in the elements' axial strain ([`Corot3d::with_bowing`]): the chord of an
    /// element wrapped on a pulley is short of its arc by `Δφ²/24`; the term restores it.
    pub bowing: bool,
    /// Mount the belt along the path in space of [`SpacePath`] (pulleys on crossed axes, the
    /// quarter-twist drive: arcs in each pulley's plane, spans arriving in the next pulley's
    /// plane, twist spread over the spans) instead of in the plane z = 0.
    pub space_mount: bool,
    /// Contact points across the belt's width per section (Gauss–Lobatto, 1 … 5;
    /// [`SectionContactSet`]): 1 = the centre line only; more give the contact's moment
    /// about the belt's tangent (a crowned rim centres the belt).
    pub width_points: usize,
    /// Contact sections per element between the nodes, at `(i + 0.5)/m` of its length on its
    /// cubic centre line ([`SectionContactSet`]); 0: one section at each node.
    pub points_per_element: usize,
}

/// The 3D belt-drive model.
#[derive(Clone, Debug)]
pub struct Belt3d {
    spec: Belt3dSpec,
    set: ElementSet<Corot3d, ELEMENT_DOFS>,
    n_nodes: usize,
    pulley_dof: Vec<usize>,
    contact: SectionContactSet,
    /// Coordinate scales of the Newton test and of the error estimate (rotations in the
    /// length they move the belt by).
    scales: Vec<f64>,
    st: FramedState,
    book: ContactBook,
    /// Middle of each span of the mounted path (span `i` from pulley `i` to `i + 1`) [m].
    span_mid: Vec<Vector3<f64>>,
    /// Span tensions of the committed state [N].
    tensions: Vec<f64>,
    /// Input signals of the pulleys.
    signals: Vec<PulleySignals>,
    /// The scene's inputs and outputs (empty for a model built from a spec).
    roles: KindIo<Input, Output>,
    /// Number of `belt.point[i]` outputs.
    n_points: usize,
    /// Energy book.
    energy: EnergyBook,
    /// Pre-load report: Newton iterations of the static solves.
    preload_iterations: usize,
    /// Angles [rad] at which free pulleys are held by a stiff bearing spring during static
    /// solves (as the planar drive: a free pulley the belt does not touch is a mechanism).
    held: Option<Vec<f64>>,
    /// During the pre-load's last solve after a fallback to friction: free pulleys are not
    /// held by the bearing spring ([`Belt3d::preload`]).
    release_free: bool,
    /// What the pre-load could not do (the pre-tension not reached, the free pulleys not
    /// released), for the importer's log ([`Model::build_note`]).
    preload_note: Option<String>,
    /// Whether time steps start from the transport predictor ([`MechanicalSystem::predict`]).
    transport_predictor: bool,
    /// During the pre-load's frictionless solve: node 0 is held at this position [m] by a
    /// spring of this stiffness [N/m] (without friction the belt sliding round its loop and
    /// along the pulley axes is a mechanism).
    /// Only along the belt's tangent and width direction there (the two directions it can
    /// slide in): a spring holding the node against the rim or across a span would leave its
    /// force in the equilibrium.
    anchor: Option<(Vector3<f64>, [Vector3<f64>; 2], f64)>,
    /// Whether the static pre-load ended in frictionless equilibrium ([`Belt3d::preload`]).
    frictionless_preload: bool,
    /// What a refreshed kept matrix is made of ([`MechanicalSystem::refreshed_matrix`]).
    refresh: RefreshCache,
    /// The node orientations and element arc lengths of the step's start, computed once per
    /// prediction ([`MechanicalSystem::predict`]).
    predict_scratch: PredictScratch,
}

/// Per-step buffers of the transport predictor (allocated at the first use, reused after):
/// every node's orientation and every element's centre-line length at the start of the step,
/// which the prediction of each node reads several times (issue 13 item 5, session 39: they
/// were recomputed about seven and two times per node).
#[derive(Clone, Debug, Default)]
struct PredictScratch {
    /// Node orientations `R_i`.
    frames: Vec<UnitQuaternion<f64>>,
    /// Element `e`'s centre-line length [m]: its chord times `(φ/2)/sin(φ/2)`.
    arcs: Vec<f64>,
}

/// The parts of the last evaluations that refresh a kept iteration matrix whose contact set
/// is stale (issue 13 item 5, session 37): the matrix of the last build without the contact
/// blocks, and the state and residual of the last evaluation without a matrix. Buffers
/// allocated at the first use, reused after.
#[derive(Clone, Debug, Default)]
struct RefreshCache {
    /// Matrix values of the last build (elements, free pulleys, anchor) before the contact
    /// blocks were added.
    base: Vec<f64>,
    /// Coefficients (stiffness times the assembly's `k_scale`) of that build.
    base_coeffs: Option<JacobianCoeffs>,
    /// Full coordinates, velocities and accelerations (prescribed ones set), time and load
    /// factor of the last evaluation without a matrix.
    qw: Vec<f64>,
    vw: Vec<f64>,
    aw: Vec<f64>,
    t_lambda: (f64, f64),
    /// Its residual.
    r: Vec<f64>,
    /// Scratch full residual of the contact forces of a refresh (discarded).
    fw: Vec<f64>,
    /// Set when [`MechanicalSystem::kept_matrix_current`] answers no after that evaluation;
    /// cleared by the next evaluation.
    pending: std::cell::Cell<bool>,
    /// Whether the last evaluation asked for a matrix refreshed the kept one.
    refreshed: bool,
}

/// Input work and dissipation since the start [J], their rates at the last commit [W], and
/// the time of that commit [s].
#[derive(Clone, Copy, Debug, Default)]
struct EnergyBook {
    input_work: f64,
    dissipated: f64,
    p_in: f64,
    p_diss: f64,
    t: f64,
}

/// Input signals of one pulley (`pulleyN.angle`, `.omega` of a driven pulley, `.torque_in`
/// of a free one).
#[derive(Clone, Copy, Debug, Default)]
struct PulleySignals {
    angle: InputSignal,
    omega: InputSignal,
    torque: InputSignal,
}

impl Belt3d {
    /// Mounts the belt: the closed path around the pulleys' pitch circles laid out in the
    /// plane z = 0 (centres' x, y; each pulley's centre z and axis tilt act only through the
    /// contact), `n_elements` equal elements, nodes on the path.
    pub fn new(spec: Belt3dSpec) -> Result<Self, String> {
        let half_t = 0.5 * spec.thickness;
        let n = spec.n_elements;
        if n < 3 {
            return Err("the belt needs at least 3 elements".into());
        }
        let obstacles: Vec<Pulley3d> = spec
            .pulleys
            .iter()
            .map(|p| {
                Pulley3d::new(
                    p.center,
                    p.axis,
                    p.radius + half_t,
                    0.5 * p.rim_width,
                    p.crown,
                    if p.flange > 0.0 {
                        p.radius + p.flange
                    } else {
                        0.0
                    },
                    0.5 * spec.width,
                )
            })
            .collect();
        let mount = if spec.space_mount {
            Mount::Space(SpacePath::new(
                &obstacles
                    .iter()
                    .map(|o| SpaceCircle {
                        center: o.center,
                        axis: o.axis,
                        radius: o.radius,
                    })
                    .collect::<Vec<_>>(),
                &obstacles
                    .iter()
                    .map(|o| 0.25 * (o.half_width - o.belt_half_width).max(0.0))
                    .collect::<Vec<_>>(),
            )?)
        } else {
            Mount::Plane(
                Loop::new(
                    &spec
                        .pulleys
                        .iter()
                        .map(|p| PitchCircle {
                            center: Vector2::new(p.center.x, p.center.y),
                            radius: p.radius + half_t,
                        })
                        .collect::<Vec<_>>(),
                )
                .map_err(|e| {
                    format!("pulley.center, pulley.radius (the pulleys' centres and radii): {e}")
                })?,
            )
        };
        let path_length = mount.length();
        let np = obstacles.len();
        let stretch = 1.0 + spec.pretension / spec.section.ea;
        let mounted = path_length / n as f64;
        let l0 = mounted / stretch;
        let n_full = n * NODE_DOFS + np;
        let pulley_dof: Vec<usize> = (0..np).map(|k| n * NODE_DOFS + k).collect();
        let mut constrained = vec![false; n_full];
        for (k, p) in spec.pulleys.iter().enumerate() {
            if let Pulley3dMotion::Driven { .. } = p.motion {
                constrained[pulley_dof[k]] = true;
            }
        }
        let node = |k: usize| (k % n) * NODE_DOFS;
        let connectivity: Vec<[usize; ELEMENT_DOFS]> = (0..n)
            .map(|e| {
                let (a, b) = (node(e), node(e + 1));
                std::array::from_fn(|i| {
                    if i < NODE_DOFS {
                        a + i
                    } else {
                        b + i - NODE_DOFS
                    }
                })
            })
            .collect();
        let mut extra = Vec::new();
        for &pd in &pulley_dof {
            for k in 0..n {
                for c in 0..NODE_DOFS {
                    extra.push((k * NODE_DOFS + c, pd));
                }
            }
            extra.push((pd, pd));
        }
        let asm = Assembly::new(
            DofMap::new(&constrained),
            &[(ELEMENT_DOFS, connectivity.as_flattened())],
            &extra,
        );
        let blocks: Vec<[usize; SECTION_BLOCK]> = (0..n)
            .flat_map(|e| {
                let (a, b) = (node(e), node(e + 1));
                pulley_dof.iter().map(move |&pd| {
                    std::array::from_fn(|i| match i {
                        0..6 => a + i,
                        6..12 => b + i - 6,
                        _ => pd,
                    })
                })
            })
            .collect();
        let contact_blocks = Connectivity::new(blocks, &asm);
        let element = Corot3d::new(
            l0,
            Matrix3::identity(),
            &spec.section,
            Theory::Timoshenko,
            MassModel::Lumped,
        )
        .with_bowing(spec.bowing);
        let span_mid = mount.span_middles();
        let mut frames = NodeFrames::new((0..n).map(|k| k * NODE_DOFS + 3).collect());
        let mut q0 = vec![0.0; n_full];
        for k in 0..n {
            let (mut r, mut t, mut width_dir, on) = mount.at(path_length * k as f64 / n as f64);
            // on an arc of the layout: put onto the pulley's own (tilted, offset, crowned)
            // rim, the predicted penetration T/(R k_n) inside it
            for (i, (c, p)) in obstacles.iter().zip(&spec.pulleys).enumerate() {
                let planar = Vector2::new(r.x - p.center.x, r.y - p.center.y).norm();
                let on_arc = match on {
                    Some(j) => j == i,
                    None => {
                        !spec.space_mount && (planar - c.radius).abs() < 1e-9 * c.radius.max(1.0)
                    }
                };
                if on_arc {
                    let d = r - c.center;
                    let zeta = c.axis.dot(&d);
                    let radial = d - zeta * c.axis;
                    let pen = spec.pretension / (c.radius * spec.contact.k_n);
                    let (rim, slope, _) = c.rim_radius(zeta);
                    let e = radial.normalize();
                    r = c.center + zeta * c.axis + (rim - pen) * e;
                    if spec.width_points > 1 {
                        // the section lies across the rim: width direction along the rim's
                        // generator (axis tilted by the crown's slope), tangent normal to it
                        let along = (c.axis + slope * e).normalize();
                        width_dir = along * along.dot(&width_dir).signum();
                        t = (t - t.dot(&width_dir) * width_dir).normalize();
                    }
                }
            }
            q0[k * NODE_DOFS..k * NODE_DOFS + 3].copy_from_slice(r.as_slice());
            let frame = Matrix3::from_columns(&[t, width_dir.cross(&t), width_dir]);
            frames.set_reference(
                k,
                UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(frame)),
            );
        }
        let set = ElementSet::new(vec![element], connectivity, &asm).with_frames(&frames);
        if !(1..=5).contains(&spec.width_points) {
            return Err(format!(
                "contact.width_points = {}: 1 to 5 points across the width",
                spec.width_points
            ));
        }
        // node frames [t, a × t, a]: the width axis is the frame's z, the thickness axis y
        let contact = SectionContactSet::new(
            spec.contact,
            obstacles,
            contact_blocks,
            (0..n).map(|e| [e, (e + 1) % n]).collect(),
            Vector3::z(),
            Vector3::y(),
            spec.width_points,
            spec.points_per_element,
            l0,
        );
        let lengths = asm
            .dofs
            .free_to_full()
            .iter()
            .map(|&i| {
                if i < n * NODE_DOFS && i % NODE_DOFS < 3 {
                    path_length
                } else {
                    1.0
                }
            })
            .collect::<Vec<f64>>();
        // Newton's convergence test: a node rotation increment δ moves the belt by about
        // δ·l_e; measured as the planar drive's slopes (`belt_drive::model`, README "Belt
        // Newton scales"): against path_length / (4 l_e). The local error estimate measures
        // the rotations the same way, by the motion of the belt they cause: a node entering
        // an arc spins up from 0 to v/R within a step (the kinematics of wrapping, computed
        // correctly by the step), and its rotation's estimate h² (β − 1/6) Δα (0.1 rad at
        // 4.9 m/s and 1 ms steps) counted in radians halved every substep of the running
        // drive while moving the belt by 0.1·l_e (session 29, issue 13 item 5). The positions
        // keep the path length.
        let scales = newton_scales_with_gradients(
            &lengths,
            asm.dofs.free_to_full(),
            |i| i < n * NODE_DOFS && i % NODE_DOFS >= 3,
            path_length,
            mounted,
        );
        let mut me = Self {
            spec,
            set,
            n_nodes: n,
            pulley_dof,
            contact,
            scales,
            st: FramedState::new(asm, frames, q0),
            book: ContactBook::default(),
            span_mid,
            tensions: vec![],
            signals: vec![],
            roles: KindIo::default(),
            n_points: 0,
            energy: EnergyBook::default(),
            preload_iterations: 0,
            held: None,
            release_free: false,
            preload_note: None,
            transport_predictor: true,
            anchor: None,
            frictionless_preload: false,
            refresh: RefreshCache::default(),
            predict_scratch: PredictScratch::default(),
        };
        me.signals = me
            .spec
            .pulleys
            .iter()
            .map(|p| match p.motion {
                Pulley3dMotion::Driven { omega } => PulleySignals {
                    omega: InputSignal::constant(omega),
                    ..Default::default()
                },
                Pulley3dMotion::Free { torque, .. } => PulleySignals {
                    torque: InputSignal::constant(torque),
                    ..Default::default()
                },
            })
            .collect();
        me.contact.commit(&me.st.q, &me.st.v, &me.st.frames, true);
        me.update_tensions();
        Ok(me)
    }

    /// Reference length of one element [m].
    pub fn element_length(&self) -> f64 {
        self.set.element(0).length()
    }

    /// Rebuilds the elements and contact points for reference length `l` [m] (all elements
    /// share it; the pre-load corrects it).
    pub fn set_reference_length(&mut self, l: f64) {
        let el = Corot3d::new(
            l,
            Matrix3::identity(),
            &self.spec.section,
            Theory::Timoshenko,
            MassModel::Lumped,
        )
        .with_bowing(self.spec.bowing);
        self.set.set_elements(vec![el]);
        self.contact.set_length(l);
    }

    /// Switches the transport predictor of the time steps on or off (default on; see
    /// [`MechanicalSystem::predict`] for this model). The converged steps agree within the
    /// Newton tolerance either way; the predictor saves iterations.
    pub fn set_transport_predictor(&mut self, on: bool) {
        self.transport_predictor = on;
    }

    /// Orientation `R_ref exp(θ̃)` of node `k` for the full coordinates `full`.
    fn node_orientation(&self, k: usize, full: &[f64]) -> UnitQuaternion<f64> {
        self.st.frames.reference(k)
            * UnitQuaternion::from_scaled_axis(self.st.frames.theta(k, full))
    }

    /// Axial force of element `e` in the committed state [N] (with the bowing term if on).
    pub fn element_tension(&self, e: usize) -> f64 {
        let n = self.n_nodes;
        let (a, b) = (e % n, (e + 1) % n);
        let nodes = Nodes {
            x: [self.node_position(a), self.node_position(b)],
            r: [
                self.st.frames.rotation(a, &self.st.q),
                self.st.frames.rotation(b, &self.st.q),
            ],
        };
        self.set.element(0).axial_force(&nodes)
    }

    /// Span tensions of the committed state [N]: the mean axial force of the three elements
    /// nearest to the middle of each span of the mounted path (as the planar drive).
    pub fn span_tensions(&self) -> &[f64] {
        &self.tensions
    }

    fn update_tensions(&mut self) {
        let n = self.n_nodes;
        self.tensions = self
            .span_mid
            .iter()
            .map(|m| {
                let mut best = (f64::INFINITY, 0);
                for e in 0..n {
                    let mid = 0.5 * (self.node_position(e) + self.node_position((e + 1) % n));
                    let d = (mid - m).norm();
                    if d < best.0 {
                        best = (d, e);
                    }
                }
                let e = best.1;
                (self.element_tension((e + n - 1) % n)
                    + self.element_tension(e)
                    + self.element_tension((e + 1) % n))
                    / 3.0
            })
            .collect();
    }

    /// Mean speed of the belt nodes in the committed state [m/s].
    pub fn belt_speed(&self) -> f64 {
        (0..self.n_nodes)
            .map(|k| {
                Vector3::from_column_slice(&self.st.v[k * NODE_DOFS..k * NODE_DOFS + 3]).norm()
            })
            .sum::<f64>()
            / self.n_nodes as f64
    }

    /// Static equilibrium of the mounted belt (pulleys at rest, free pulleys held by their
    /// belt contact), then, if `pretension` is given, the reference length corrected until
    /// the mean span tension is it within 0.1 % (at most 5 solves, as the planar drive's
    /// pre-load). Returns the Newton iterations.
    ///
    /// Each solve with friction is followed by one without ([`Self::frictionless_solve`]):
    /// the belt is mounted on the rims with its span tension, and with friction the arcs
    /// keep the tension of the mount where the belt sinks into the rims, while running lets
    /// them take the tension of a belt sliding on its rims (in frictionless equilibrium the
    /// axial force on an arc is the span's less `EI/(2ρ²)`, Eshelby's configurational force
    /// of a bent elastica). The pre-load is the state of a belt after running in (as belt
    /// makers tension a drive: turned over a few times, then measured on the spans), and it
    /// does not depend on the contact's penalty and bristle stiffness, which the mount
    /// would lock into the arcs: issue 13 item 4, session 33: with friction the arcs of the
    /// shipped drive at rest held 4.8 / 3.3 N less than the spans here and 10.2 / 6.3 N in
    /// the planar drive, so that the two drives, running, differed by 1 N in mean span
    /// tension. If the frictionless solve fails or moves a node across the belt (along its
    /// width direction) by more than a tenth of the belt width (a belt that would slide
    /// across its rims without friction; moves in the drive's plane, as spans sagging under
    /// gravity take length from the arcs, do not count), the solve with friction stands
    /// ([`Self::preload_was_frictionless`]).
    pub fn preload(
        &mut self,
        pretension: Option<f64>,
        settings: &crate::solver::newton::NewtonSettings,
    ) -> Result<usize, String> {
        use crate::solver::newton::Workspace;
        let mut ws =
            Workspace::new(&*self, crate::linalg::SolverKind::Auto).map_err(|e| e.to_string())?;
        let n = self.n_free();
        let (mut qf, mut vf) = (vec![0.0; n], vec![0.0; n]);
        let mut iterations = 0;
        // the last round's reference length and mean span tension (secant correction)
        let mut last: Option<(f64, f64)> = None;
        self.frictionless_preload = true;
        for round in 0..5 {
            self.free_state(&mut qf, &mut vf);
            if round == 0 || !self.frictionless_preload {
                iterations += self.friction_solve(&mut ws, &mut qf, settings)?;
            }
            if self.frictionless_preload {
                let with_friction = qf.clone();
                match self.frictionless_solve(&mut ws, &mut qf, settings) {
                    Ok(it) => iterations += it,
                    Err(_) => {
                        self.frictionless_preload = false;
                        qf.copy_from_slice(&with_friction);
                        if round > 0 {
                            iterations += self.friction_solve(&mut ws, &mut qf, settings)?;
                        }
                    }
                }
            }
            // histories at rest after a frictionless solve; after a solve with friction (the
            // fallback) they keep the bristles' deflection, which that equilibrium needs (as
            // the planar pre-load's commit): reset, the initial static solve let the stuck
            // arcs relax, and the quarter-twist drive started 1.6 % below its pre-tension
            self.commit_static(&qf, self.frictionless_preload);
            if !self.frictionless_preload {
                iterations += self.release_free_pulleys(&mut ws, settings);
            }
            let Some(target) = pretension else { break };
            let mean = self.tensions.iter().sum::<f64>() / self.tensions.len().max(1) as f64;
            if (mean - target).abs() <= 1e-3 * target {
                break;
            }
            if round == 4 {
                self.add_preload_note(format!(
                    "the static pre-load of the 3D belt stopped after 5 corrections of the belt's reference length with a mean span tension of {mean:.6} N against belt.pretension = {target} N ({:+.2} %)",
                    100.0 * (mean / target - 1.0)
                ));
                break;
            }
            let l_now = self.element_length();
            let l = crate::kinds::belt_drive::preload::secant_length(l_now, mean, last, target)
                .unwrap_or_else(|| {
                    let ea = self.spec.section.ea;
                    l_now * (1.0 + mean / ea) / (1.0 + target / ea)
                });
            last = Some((l_now, mean));
            self.set_reference_length(l);
        }
        Ok(iterations)
    }

    /// Commits a static equilibrium of the pre-load (free coordinates `qf`, at rest): the
    /// state, the contact histories (`initial`: at rest) and loads, the span tensions.
    fn commit_static(&mut self, qf: &[f64], initial: bool) {
        let mut state = DynState::zeros(qf.len(), self.st.t);
        state.q.copy_from_slice(qf);
        self.st.accept(&mut state, |_, _, _| {});
        self.contact
            .commit(&self.st.q, &self.st.v, &self.st.frames, initial);
        self.update_tensions();
    }

    /// Adds `note` to what the pre-load tells the importer's log (once).
    fn add_preload_note(&mut self, note: String) {
        match &mut self.preload_note {
            Some(all) if all.contains(&note) => {}
            Some(all) => *all = format!("{all}; {note}"),
            None => self.preload_note = Some(note),
        }
    }

    /// After a pre-load with friction (the fallback of [`Self::preload`]): one more static
    /// solve with the free pulleys released from the statics' bearing spring, so that the
    /// belt's friction holds them as it does at t = 0. Held, they carried the torque of the
    /// stuck arcs, which was released at the start (`conveyor_twist`: 0.86 N m, pulley 2 at
    /// −0.09 rad/s after 1 ms, the belt moving 0.19 mm in 10 ms at rest; session 33 qa33).
    /// If that solve fails (friction cannot hold a free pulley's load torque at rest), the
    /// held equilibrium stands and the importer's log says so. The Newton iterations.
    fn release_free_pulleys(
        &mut self,
        ws: &mut crate::solver::newton::Workspace,
        settings: &crate::solver::newton::NewtonSettings,
    ) -> usize {
        let any_free =
            (self.spec.pulleys.iter()).any(|p| matches!(p.motion, Pulley3dMotion::Free { .. }));
        if !any_free {
            return 0;
        }
        let n = self.n_free();
        let (mut qf, mut vf) = (vec![0.0; n], vec![0.0; n]);
        self.free_state(&mut qf, &mut vf);
        self.release_free = true;
        let solved = crate::solver::statics::solve(self, ws, &mut qf, settings, 1);
        self.release_free = false;
        match solved {
            Ok(st) => {
                self.commit_static(&qf, false);
                st.newton.iterations
            }
            Err(e) => {
                let note = format!(
                    "the static pre-load of the 3D belt kept friction (the belt would slide across its rims without it) and could not release the free pulleys from their bearing spring ({e}): they start held against the belt's torque"
                );
                self.add_preload_note(note);
                0
            }
        }
    }

    /// Whether the static pre-load ended in frictionless equilibrium ([`Self::preload`]).
    pub fn preload_was_frictionless(&self) -> bool {
        self.frictionless_preload
    }

    /// Static solve with the scene's friction from the free coordinates `qf` (the mounted
    /// belt, or the last equilibrium); the Newton iterations.
    fn friction_solve(
        &mut self,
        ws: &mut crate::solver::newton::Workspace,
        qf: &mut [f64],
        settings: &crate::solver::newton::NewtonSettings,
    ) -> Result<usize, String> {
        match crate::solver::statics::solve(self, ws, qf, settings, 8) {
            Ok(st) => Ok(st.newton.iterations),
            Err(e) => {
                // a mount with kinks (the quarter-twist path leaves each pulley 15.6° out
                // of its plane) is too far from equilibrium for Newton: relax it in pseudo
                // time first, then finish with the load path from there
                let mut vf = vec![0.0; qf.len()];
                self.free_state(qf, &mut vf);
                let relaxed = crate::solver::statics::relax(self, ws, qf, settings, 400)
                    .map_err(|r| format!("static pre-load of the 3D belt: {e}; relaxation: {r}"))?;
                let st = crate::solver::statics::solve(self, ws, qf, settings, 1).map_err(|e2| {
                    format!(
                        "static pre-load of the 3D belt: {e}; after a pseudo-transient relaxation ({} iterations, residual down to {:.1e} of its start): {e2}",
                        relaxed.iterations, relaxed.reduction
                    )
                })?;
                Ok(relaxed.iterations + st.newton.iterations)
            }
        }
    }

    /// Static solve without friction from the equilibrium with friction in `qf`: `μ = 0` on
    /// every rim and flange, node 0 held where it is by a spring of `EA/L` (`L` the loop
    /// length) along the belt's tangent and width direction there (without friction the belt
    /// sliding round its loop, or along flat rims, is a mechanism; at equilibrium the spring
    /// carries no load but what the friction carried in that direction; held across the
    /// belt too, against the rim, the spring kept a force in the equilibrium that was
    /// released at t = 0: 13 N on a belt of EA 5e6 N, the belt moving 0.1 mm in 10 ms at
    /// rest, session 33 qa33). Fails if Newton does not converge or a node moves across
    /// the belt by more than a tenth of the belt width.
    fn frictionless_solve(
        &mut self,
        ws: &mut crate::solver::newton::Workspace,
        qf: &mut [f64],
        settings: &crate::solver::newton::NewtonSettings,
    ) -> Result<usize, String> {
        let law = *self.contact.law();
        self.contact.set_law(ContactLaw { mu: 0.0, ..law });
        let length = self.element_length() * self.n_nodes as f64;
        let (mut full0, mut full1) = (self.st.q.clone(), self.st.q.clone());
        self.st.asm.dofs.expand(qf, &mut full0);
        let x0 = Vector3::from_column_slice(&full0[..3]);
        // node 0's tangent and width direction: the columns 1 and 3 of its frame
        let frame = self.st.frames.rotation(0, &full0);
        let dirs = [
            (frame * Vector3::x()).normalize(),
            (frame * Vector3::z()).normalize(),
        ];
        self.anchor = Some((x0, dirs, self.spec.section.ea / length));
        let solved = crate::solver::statics::solve(self, ws, qf, settings, 1);
        self.contact.set_law(law);
        self.anchor = None;
        let st = solved.map_err(|e| e.to_string())?;
        // the largest move of a node across the belt [m] (along its width direction before
        // the solve)
        self.st.asm.dofs.expand(qf, &mut full1);
        let moved = (0..self.n_nodes)
            .map(|k| {
                let i = k * NODE_DOFS;
                let w = self.st.frames.rotation(k, &full0) * Vector3::z();
                (Vector3::from_column_slice(&full1[i..i + 3])
                    - Vector3::from_column_slice(&full0[i..i + 3]))
                .dot(&w)
                .abs()
            })
            .fold(0.0, f64::max);
        if moved > 0.1 * self.spec.width {
            return Err(format!(
                "a node moved {moved:.2e} m without friction (belt width {} m)",
                self.spec.width
            ));
        }
        Ok(st.newton.iterations)
    }

    /// Number of belt nodes (= elements).
    pub fn n_nodes(&self) -> usize {
        self.n_nodes
    }

    /// Position of node `k` in the committed state [m].
    pub fn node_position(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.st.q[k * NODE_DOFS..k * NODE_DOFS + 3])
    }

    /// Width direction of the belt at node `k` in the committed state (unit; the third
    /// column of the node's frame `[t, a × t, a]`).
    pub fn node_width_direction(&self, k: usize) -> Vector3<f64> {
        (self.st.frames.rotation(k, &self.st.q) * Vector3::z()).normalize()
    }

    /// Angle [rad] and angular velocity [rad/s] of pulley `k` in the committed state.
    pub fn pulley_motion(&self, k: usize) -> (f64, f64) {
        (self.st.q[self.pulley_dof[k]], self.st.v[self.pulley_dof[k]])
    }

    /// Loads of the belt on pulley `k` in the committed state: force [N], moment about its
    /// centre [N m], torque about its axis [N m], flange force [N].
    pub fn pulley_load(&self, k: usize) -> (Vector3<f64>, Vector3<f64>, f64, f64) {
        let l = &self.contact.loads()[k];
        (l.force, l.moment, l.generalized[0], l.side_force)
    }

    /// Mean lateral (axial) position of the belt's contact points on pulley `k` [m] (0 if
    /// none touches).
    pub fn lateral(&self, k: usize) -> f64 {
        let ob = &self.contact.obstacles()[k];
        let (mut sum, mut count) = (0.0, 0);
        for i in 0..self.n_nodes {
            let r = self.node_position(i);
            let d = r - ob.center;
            let rho = (d - ob.axis.dot(&d) * ob.axis).norm();
            if rho < ob.radius + 1e-3 * ob.radius
                && ob.lateral(&r).abs() < ob.half_width + ob.radius
            {
                sum += ob.lateral(&r);
                count += 1;
            }
        }
        if count == 0 { 0.0 } else { sum / count as f64 }
    }

    /// Energy terms of the contact at the last commit.
    pub fn contact_book(&self) -> ContactBook {
        self.book
    }

    /// Strain energy of the belt in the committed state [J].
    pub fn strain_energy(&self) -> f64 {
        self.set.strain_energy(&self.st.q, Some(&self.st.frames))
    }

    /// Kinetic energy of the belt in the committed state [J].
    pub fn kinetic_energy(&self) -> f64 {
        self.set
            .kinetic_energy(&self.st.q, &self.st.v, Some(&self.st.frames))
    }

    /// Prescribed angle, speed and acceleration of driven pulley `k` at time `t` (the angle
    /// input's polynomial if it has derivatives, else the angle advanced with the speed).
    fn driven(&self, k: usize, t: f64) -> (f64, f64, f64) {
        let sg = &self.signals[k];
        prescribed(&sg.angle, &sg.omega, t)
    }

    /// Sets the driven pulleys' angles and speeds at time `t` into full vectors. In a static
    /// solve ([`MechanicalSystem::hold_for_statics`]) the driven pulleys stand at their angles
    /// with zero speed, as in the planar drive: statics is the belt at rest, and a master that
    /// starts a driven pulley at speed (`pulleyN.omega` start value ≠ 0) must not make the
    /// friction of the static problem slide (it did: "static equilibrium not found" at
    /// `fmi2ExitInitializationMode`).
    ///
    /// [`MechanicalSystem::hold_for_statics`]: crate::model::MechanicalSystem::hold_for_statics
    fn prescribe(&self, t: f64, q: Option<&mut [f64]>, v: Option<&mut [f64]>) {
        let (mut q, mut v) = (q, v);
        let at_rest = self.held.is_some();
        for (k, p) in self.spec.pulleys.iter().enumerate() {
            if let Pulley3dMotion::Driven { .. } = p.motion {
                let (th, om, _) = self.driven(k, t);
                let om = if at_rest { 0.0 } else { om };
                if let Some(q) = q.as_deref_mut() {
                    q[self.pulley_dof[k]] = th;
                }
                if let Some(v) = v.as_deref_mut() {
                    v[self.pulley_dof[k]] = om;
                }
            }
        }
    }

    /// Commits an accepted state: node rotations absorbed, contact histories and loads,
    /// span tensions, energy book.
    pub fn accept(&mut self, state: &mut DynState) {
        let t = state.t;
        // (a fixed array: no allocation per accepted step)
        let mut driven = [(0usize, (0.0, 0.0, 0.0)); super::scene::MAX_PULLEYS];
        let mut n_driven = 0;
        for (k, p) in self.spec.pulleys.iter().enumerate() {
            if matches!(p.motion, Pulley3dMotion::Driven { .. }) {
                driven[n_driven] = (self.pulley_dof[k], self.driven(k, t));
                n_driven += 1;
            }
        }
        self.st.accept(state, |q, v, a| {
            let (mut q, mut v, mut a) = (q, v, a);
            for &(d, (th, om, al)) in &driven[..n_driven] {
                if let Some(q) = q.as_deref_mut() {
                    q[d] = th;
                }
                if let Some(v) = v.as_deref_mut() {
                    v[d] = om;
                }
                if let Some(a) = a.as_deref_mut() {
                    a[d] = al;
                }
            }
        });
        // positions and pulley angles, all the contact uses, are unchanged by the absorption
        self.book = self
            .contact
            .commit(&self.st.q, &self.st.v, &self.st.frames, false);
        self.update_tensions();
        self.book_energy(t, false);
    }

    /// Input power (drives and input torques) and dissipated power (contact damping,
    /// bearings) of the committed state [W], integrated by the trapezoidal rule from the
    /// previous commit (plus the friction work of the step).
    fn book_energy(&mut self, t: f64, initial: bool) {
        let (mut p_in, mut p_diss) = (0.0, self.book.dissipation);
        for (k, p) in self.spec.pulleys.iter().enumerate() {
            let om = self.st.v[self.pulley_dof[k]];
            match p.motion {
                Pulley3dMotion::Driven { .. } => {
                    p_in -= self.contact.loads()[k].generalized[0] * om
                }
                Pulley3dMotion::Free { damping, .. } => {
                    p_in += self.signals[k].torque.at(t) * om;
                    p_diss += damping * om * om;
                }
            }
        }
        let e = &mut self.energy;
        let h = t - e.t;
        if !initial && h > 0.0 {
            e.input_work += 0.5 * h * (e.p_in + p_in);
            e.dissipated += 0.5 * h * (e.p_diss + p_diss) + self.book.friction_work;
        }
        e.p_in = p_in;
        e.p_diss = p_diss;
        e.t = t;
    }

    /// The committed free coordinates and velocities.
    pub fn free_state(&self, q: &mut [f64], v: &mut [f64]) {
        self.st.free_state(q, v);
    }

    fn assemble(
        &mut self,
        t: f64,
        lambda: f64,
        k_scale: f64,
        r: &mut [f64],
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        let mut qw = std::mem::take(&mut self.st.qw);
        let mut vw = std::mem::take(&mut self.st.vw);
        self.prescribe(t, Some(&mut qw), Some(&mut vw));
        (self.st.qw, self.st.vw) = (qw, vw);
        let pending = self.refresh.pending.take();
        self.refresh.refreshed = false;
        if pending && let Some((c, vals)) = jac.as_mut() {
            let rc = &self.refresh;
            let same = rc.base_coeffs
                == Some(JacobianCoeffs {
                    stiffness: c.stiffness * k_scale,
                    ..*c
                })
                && rc.base.len() == vals.len()
                && rc.t_lambda == (t, lambda)
                && rc.qw == self.st.qw
                && rc.vw == self.st.vw
                && rc.aw == self.st.aw;
            if same && c.stiffness * k_scale != 0.0 {
                return self.refresh_matrix(k_scale, r, (*c, vals));
            }
        }
        let g = self.spec.gravity * lambda;
        let mut fw = self
            .st
            .assemble_elements(&self.set, &[], g, t, lambda, k_scale, &mut jac);
        for (k, p) in self.spec.pulleys.iter().enumerate() {
            if let Pulley3dMotion::Free {
                inertia, damping, ..
            } = p.motion
            {
                let d = self.pulley_dof[k];
                let torque = self.signals[k].torque.at(t);
                fw[d] += inertia * self.st.aw[d] + damping * self.st.vw[d] - lambda * torque;
                let k_hold = match &self.held {
                    Some(held) if !self.release_free => {
                        let k_hold = 1e3 * self.spec.section.ea * p.radius * p.radius;
                        fw[d] += k_hold * (self.st.qw[d] - held[k]);
                        k_hold
                    }
                    _ => 0.0,
                };
                if let Some((c, vals)) = jac.as_mut() {
                    let i = self.st.asm.dofs.free_index(d).expect("free pulley");
                    let pos = self.st.asm.pattern.position(i, i).expect("diagonal");
                    vals[pos] += c.mass * inertia + c.damping * damping + c.stiffness * k_hold;
                }
            }
        }
        if let Some((x0, dirs, k)) = self.anchor {
            let d = Vector3::from_column_slice(&self.st.qw[..3]) - x0;
            for e in dirs {
                let along = k * e.dot(&d);
                for i in 0..3 {
                    fw[i] += along * e[i];
                }
                if let Some((c, vals)) = jac.as_mut() {
                    for i in 0..3 {
                        for j in 0..3 {
                            if let (Some(a), Some(b)) = (
                                self.st.asm.dofs.free_index(i),
                                self.st.asm.dofs.free_index(j),
                            ) {
                                let pos = self.st.asm.pattern.position(a, b).expect("node block");
                                vals[pos] += c.stiffness * k * e[i] * e[j];
                            }
                        }
                    }
                }
            }
        }
        // the matrix without the contact blocks, for a refresh of it
        // ([`MechanicalSystem::refreshed_matrix`])
        if let Some((c, vals)) = jac.as_ref() {
            let rc = &mut self.refresh;
            rc.base.clear();
            rc.base.extend_from_slice(vals);
            rc.base_coeffs = Some(JacobianCoeffs {
                stiffness: c.stiffness * k_scale,
                ..*c
            });
        }
        // the contact has no mass: without stiffness and damping coefficients (consistent
        // accelerations) its matrix is zero
        let cjac = jac
            .as_mut()
            .filter(|(c, _)| c.stiffness != 0.0 || c.damping != 0.0)
            .map(|(c, vals)| {
                (
                    JacobianCoeffs {
                        stiffness: c.stiffness * k_scale,
                        ..*c
                    },
                    &mut **vals,
                )
            });
        self.contact.add_residual(
            &self.st.qw,
            &self.st.vw,
            self.st.frames.current(),
            &mut fw,
            cjac,
        );
        let built = jac.is_some();
        self.st
            .finish_assembly(fw, r, jac.as_ref().map(|(_, vals)| &**vals))?;
        if !built {
            // the state and residual a refresh of the kept matrix would be asked for
            let rc = &mut self.refresh;
            for (dst, src) in [
                (&mut rc.qw, &self.st.qw[..]),
                (&mut rc.vw, &self.st.vw[..]),
                (&mut rc.aw, &self.st.aw[..]),
                (&mut rc.r, &r[..]),
            ] {
                dst.clear();
                dst.extend_from_slice(src);
            }
            rc.t_lambda = (t, lambda);
        }
        Ok(())
    }

    /// The kept iteration matrix refreshed at the state of the last evaluation without a
    /// matrix (the caller has checked that this is that state and that the kept matrix is
    /// the last one built, with these coefficients): the matrix of that build without its
    /// contact blocks plus the contact blocks of this state; the residual is that
    /// evaluation's. See [`MechanicalSystem::refreshed_matrix`].
    fn refresh_matrix(
        &mut self,
        k_scale: f64,
        r: &mut [f64],
        (c, vals): (JacobianCoeffs, &mut [f64]),
    ) -> Result<(), ModelError> {
        let rc = &mut self.refresh;
        vals.copy_from_slice(&rc.base);
        rc.fw.clear();
        rc.fw.resize(self.st.qw.len(), 0.0);
        self.contact.add_residual(
            &self.st.qw,
            &self.st.vw,
            self.st.frames.current(),
            &mut rc.fw,
            Some((
                JacobianCoeffs {
                    stiffness: c.stiffness * k_scale,
                    ..c
                },
                vals,
            )),
        );
        r.copy_from_slice(&rc.r);
        rc.refreshed = true;
        crate::assembly::check_finite(r, Some(vals))
    }
}

impl Belt3d {
    /// Builds the model of a `belt_3d` scene with validated parameter values and brings the
    /// mounted belt into static equilibrium with its pre-tension.
    pub fn build(scene: &Belt3dScene, p: &ParamValues) -> Result<Self, String> {
        use super::scene::names::*;
        use super::scene::*;
        use crate::scene::params::names::{GRAVITY_X, GRAVITY_Y, GRAVITY_Z};
        let (ea, width, thickness) = (p.real(BELT_EA), p.real(BELT_WIDTH), p.real(BELT_THICKNESS));
        let mass = p.real(BELT_MASS);
        let ga = p.real(BELT_GA);
        let rho = mass / (width * thickness);
        let section = BeamSection {
            ea,
            ga_y: ga,
            ga_z: ga,
            gj: p.real(BELT_GJ),
            // node frames [t, a × t, a]: local y is the thickness direction, local z the
            // width axis, so bending over the pulleys is about z, lateral bending about y
            ei_y: p.real(BELT_EI_LATERAL),
            ei_z: p.real(BELT_EI),
            rho_a: mass,
            rho_jx: rho * width * thickness * (width * width + thickness * thickness) / 12.0,
            rho_iy: rho * width * thickness * width * width / 12.0,
            rho_iz: rho * width * thickness * thickness * thickness / 12.0,
        };
        let centers: Vec<Vector3<f64>> = scene
            .pulley
            .iter()
            .map(|s| Vector3::from(s.center))
            .collect();
        let np = centers.len();
        let pulleys: Vec<Pulley3dDef> = scene
            .pulley
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let prev = centers[(i + np - 1) % np];
                let axis0 = Vector3::from(s.axis).normalize();
                // the arriving span in the pulley's own plane (normal to its axis): for a drive
                // along z with its centres at one z the span in the xy plane; any turned copy
                // of a drive gets the same misalignment (before session 34 the span was
                // projected on the xy plane: a drive with its axes along x ignored tilt and
                // skew)
                let d = centers[i] - prev;
                let span = d - axis0.dot(&d) * axis0;
                let (tilt, skew) = (p.real(PULLEY_TILT[i]), p.real(PULLEY_SKEW[i]));
                let mut axis = axis0;
                if span.norm() > 0.0 {
                    let along = Unit::new_normalize(span);
                    let across = Unit::new_normalize(axis0.cross(&span));
                    axis = Rotation3::from_axis_angle(&across, skew)
                        * Rotation3::from_axis_angle(&along, tilt)
                        * axis;
                }
                Pulley3dDef {
                    center: centers[i] + p.real(PULLEY_OFFSET[i]) * axis,
                    axis,
                    radius: p.real(PULLEY_RADIUS[i]),
                    rim_width: p.real(PULLEY_WIDTH[i]),
                    crown: p.real(PULLEY_CROWN[i]),
                    flange: p.real(PULLEY_FLANGE[i]),
                    motion: match s.mode {
                        super::Pulley3dMode::Driven => Pulley3dMotion::Driven { omega: s.omega },
                        super::Pulley3dMode::Free => Pulley3dMotion::Free {
                            inertia: p.real(PULLEY_INERTIA[i]),
                            damping: p.real(PULLEY_DAMPING[i]),
                            torque: s.torque_in,
                        },
                    },
                }
            })
            .collect();
        let r_min = pulleys
            .iter()
            .map(|p| p.radius)
            .fold(f64::INFINITY, f64::min);
        let r_max = pulleys.iter().map(|p| p.radius).fold(0.0, f64::max);
        let pretension = p.real(BELT_PRETENSION);
        let contact = crate::kinds::belt_drive::model::default_contact(
            ea,
            mass,
            thickness,
            r_min + 0.5 * thickness,
            r_max + 0.5 * thickness,
            pretension,
            p.real(CONTACT_MU),
            (
                p.real(CONTACT_STIFFNESS),
                p.real(CONTACT_DAMPING),
                p.real(CONTACT_FRICTION_STIFFNESS),
            ),
        );
        let g = |name: &str| p.get(name).map_or(0.0, |_| p.real(name));
        let mut m = Self::new(Belt3dSpec {
            section,
            thickness,
            width,
            pulleys,
            contact,
            n_elements: p.integer(BELT_N_ELEMENTS) as usize,
            pretension,
            gravity: Vector3::new(g(GRAVITY_X), g(GRAVITY_Y), g(GRAVITY_Z)),
            bowing: p.boolean(BELT_BOWING),
            width_points: p.integer(CONTACT_WIDTH_POINTS) as usize,
            points_per_element: p.integer(CONTACT_POINTS_PER_ELEMENT) as usize,
            space_mount: scene.pulley.iter().any(|s| {
                Vector3::from(s.axis)
                    .normalize()
                    .cross(&Vector3::z())
                    .norm()
                    > 1e-9
            }),
        })?;
        m.roles = io(scene);
        m.n_points = belt_points(scene);
        let cfg = SolverConfig::from_params(p);
        m.preload_iterations = m.preload(Some(pretension), &cfg.newton).map_err(|e| {
            format!(
                "{e} (belt.EA = {ea} N, belt.EI, belt.EI_lateral, belt.GJ, belt.GA, belt.mass_per_length, belt.width, belt.thickness, belt.pretension = {pretension} N, belt.n_elements, contact.mu, contact.stiffness, contact.damping, contact.friction_stiffness, the pulleys' center, axis, radius, width, crown, flange, tilt, skew, offset_z, inertia and damping (the pseudo-transient relaxation of a mount far from equilibrium uses the masses); solver.newton_tolerance, solver.max_iterations)"
            )
        })?;
        Ok(m)
    }

    /// Newton iterations of the static pre-load.
    pub fn preload_iterations(&self) -> usize {
        self.preload_iterations
    }

    /// Sets a pulley input (the typed form of `Model::set_input`).
    pub fn set_pulley_input(&mut self, pulley: usize, quantity: PulleyInput, value: f64) {
        let t = self.st.t;
        let sg = &mut self.signals[pulley];
        match quantity {
            PulleyInput::Angle => sg.angle.set(value, t),
            PulleyInput::Omega => sg.omega.set(value, t),
            PulleyInput::Torque => sg.torque.set(value, t),
        }
    }

    /// Belt centre-line point at material fraction `u ∈ [0, 1)` of the loop (the elements'
    /// cubic Hermite centre line) [m].
    pub fn belt_point(&self, u: f64) -> Vector3<f64> {
        let n = self.n_nodes;
        let sfrac = u.rem_euclid(1.0) * n as f64;
        let e = (sfrac.floor() as usize).min(n - 1);
        let (a, b) = (e, (e + 1) % n);
        let nodes = Nodes {
            x: [self.node_position(a), self.node_position(b)],
            r: [
                self.st.frames.rotation(a, &self.st.q),
                self.st.frames.rotation(b, &self.st.q),
            ],
        };
        self.set.element(0).centre_line(&nodes, sfrac - e as f64)
    }

    /// `1 − ω_last ρ_last / (ω_1 ρ_1)` (0 while pulley 1 is at rest).
    pub fn slip(&self) -> f64 {
        self.pulley_slip(self.contact.obstacles().len() - 1)
    }

    /// Speed loss of pulley `k` against pulley 1, `1 − ω_k ρ_k/(ω_1 ρ_1)` (0 while pulley 1 is
    /// at rest).
    pub fn pulley_slip(&self, k: usize) -> f64 {
        let ob = self.contact.obstacles();
        let v1 = self.st.v[self.pulley_dof[0]] * ob[0].radius;
        let vk = self.st.v[self.pulley_dof[k]] * ob[k].radius;
        if v1.abs() > 1e-12 { 1.0 - vk / v1 } else { 0.0 }
    }

    /// Kinetic energy of belt and free pulleys [J].
    pub fn total_kinetic_energy(&self) -> f64 {
        let mut t = self.kinetic_energy();
        for (k, p) in self.spec.pulleys.iter().enumerate() {
            if let Pulley3dMotion::Free { inertia, .. } = p.motion {
                t += 0.5 * inertia * self.st.v[self.pulley_dof[k]].powi(2);
            }
        }
        t
    }

    /// Gravity potential of the belt's mass points [J].
    pub fn potential_energy(&self) -> f64 {
        let n = self.n_nodes;
        let el = self.set.element(0);
        (0..n)
            .map(|e| {
                let (a, b) = (e, (e + 1) % n);
                let nodes = Nodes {
                    x: [self.node_position(a), self.node_position(b)],
                    r: [
                        self.st.frames.rotation(a, &self.st.q),
                        self.st.frames.rotation(b, &self.st.q),
                    ],
                };
                el.gravity_potential(&nodes, &self.spec.gravity)
            })
            .sum()
    }

    /// Work of the drives and input torques since the start [J].
    pub fn input_work(&self) -> f64 {
        self.energy.input_work
    }

    /// Energy dissipated since the start by contact damping, friction and bearings [J].
    pub fn dissipated(&self) -> f64 {
        self.energy.dissipated
    }

    /// An output of the committed state.
    pub fn output_of(&self, kind: Output) -> f64 {
        let tmax = || {
            self.tensions
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max)
        };
        let tmin = || self.tensions.iter().copied().fold(f64::INFINITY, f64::min);
        match kind {
            Output::PulleyTorque(k) => self.contact.loads()[k].generalized[0],
            Output::PulleyForce(k, c) => self.contact.loads()[k].force[c],
            Output::PulleyMoment(k, c) => self.contact.loads()[k].moment[c],
            Output::FlangeForce(k) => self.contact.loads()[k].side_force,
            Output::PulleyAngle(k) => self.st.q[self.pulley_dof[k]],
            Output::PulleyOmega(k) => self.st.v[self.pulley_dof[k]],
            Output::Lateral(k) => self.lateral(k),
            Output::PulleySlip(k) => self.pulley_slip(k),
            Output::SpanTension(i) => self.tensions[i],
            Output::TensionTight => tmax(),
            Output::TensionSlack => tmin(),
            Output::Slip => self.slip(),
            Output::Speed => self.belt_speed(),
            Output::Point(i, c) => self.belt_point(i as f64 / self.n_points.max(1) as f64)[c],
            Output::InputWork => self.energy.input_work,
            Output::Dissipated => self.energy.dissipated,
            Output::Energy(e) => {
                let strain = || self.strain_energy() + self.book.normal_energy;
                match e {
                    EnergyKind::Kinetic => self.total_kinetic_energy(),
                    EnergyKind::Strain => strain(),
                    EnergyKind::Potential => self.potential_energy(),
                    EnergyKind::Total => {
                        self.total_kinetic_energy() + strain() + self.potential_energy()
                    }
                }
            }
        }
    }
}

impl Model for Belt3d {
    /// Pulley angles, speeds and torques are smooth signals set at every communication step:
    /// the integrator keeps its accelerations, as on the planar drive. A restart solves for
    /// new consistent accelerations with the new inputs held at the step's start and
    /// factorizes the mass matrix for it in every communication step (issue 13 item 5,
    /// session 31).
    fn input_restarts_accelerations(&self, _input: usize) -> bool {
        false
    }

    /// The belt's centre line and each pulley's rim circle.
    fn sketch(&self) -> crate::model::Sketch {
        let mut s = crate::model::Sketch::new(format!(
            "{} seed-003 co-rotational belt elements, {} pulleys in space",
            self.n_nodes,
            self.spec.pulleys.len()
        ));
        let n = 4 * self.n_nodes;
        s.line((0..=n).map(|i| self.belt_point(i as f64 / n as f64)));
        for ob in self.contact.obstacles() {
            s.circle(ob.center, ob.radius, ob.axis);
        }
        s
    }

    fn set_input(&mut self, input: usize, value: f64) {
        let Input { pulley, quantity } = self.roles.inputs[input];
        self.set_pulley_input(pulley, quantity, value);
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
        let Input { pulley, quantity } = self.roles.inputs[input];
        let sg = &mut self.signals[pulley];
        match quantity {
            PulleyInput::Angle => sg.angle.set_derivative(order, value),
            PulleyInput::Omega => sg.omega.set_derivative(order, value),
            PulleyInput::Torque => sg.torque.set_derivative(order, value),
        }
        Ok(())
    }

    fn output(&self, output: usize) -> f64 {
        self.output_of(self.roles.outputs[output])
    }

    /// Analytic for the free pulleys' angle and speed; the others by differences.
    fn output_derivative(&self, output: usize) -> Option<f64> {
        match self.roles.outputs[output] {
            Output::PulleyAngle(k) => Some(self.st.v[self.pulley_dof[k]]),
            Output::PulleyOmega(k) => Some(self.st.acc[self.pulley_dof[k]]),
            _ => None,
        }
    }

    fn accept(&mut self, state: &mut DynState) {
        Belt3d::accept(self, state);
    }

    fn free_state(&self, q: &mut [f64], v: &mut [f64]) {
        self.st.free_state(q, v);
    }

    /// Committed state and node orientations, reference length, contact histories, loads and
    /// book, input signals and energy book.
    fn save(&self, w: &mut StateWriter) -> Result<(), String> {
        self.st.save(w);
        w.f64(self.element_length());
        self.contact.save(w);
        // the pulley outputs and the contact energy read the committed loads and book
        self.contact.save_loads(w);
        let b = &self.book;
        w.u64(b.slipping as u64);
        for x in [b.normal_energy, b.dissipation, b.friction_work] {
            w.f64(x);
        }
        w.u64(self.signals.len() as u64);
        for sg in &self.signals {
            sg.angle.save(w);
            sg.omega.save(w);
            sg.torque.save(w);
        }
        let e = &self.energy;
        for x in [e.input_work, e.dissipated, e.p_in, e.p_diss, e.t] {
            w.f64(x);
        }
        Ok(())
    }

    fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        self.st.restore(r)?;
        let l = r.f64().map_err(e)?;
        if !(l.is_finite() && l > 0.0) {
            return Err(format!("reference length {l} in the state"));
        }
        self.set_reference_length(l);
        self.refresh.pending.set(false);
        self.contact.restore(r)?;
        self.contact.restore_loads(r)?;
        self.book = ContactBook {
            slipping: r.u64().map_err(e)? as usize,
            normal_energy: r.f64().map_err(e)?,
            dissipation: r.f64().map_err(e)?,
            friction_work: r.f64().map_err(e)?,
        };
        if r.u64().map_err(e)? as usize != self.signals.len() {
            return Err("pulleys of another drive".into());
        }
        for sg in self.signals.iter_mut() {
            sg.angle = InputSignal::restore(r).map_err(e)?;
            sg.omega = InputSignal::restore(r).map_err(e)?;
            sg.torque = InputSignal::restore(r).map_err(e)?;
        }
        let mut x = [0.0; 5];
        for v in x.iter_mut() {
            *v = r.f64().map_err(e)?;
        }
        self.energy = EnergyBook {
            input_work: x[0],
            dissipated: x[1],
            p_in: x[2],
            p_diss: x[3],
            t: x[4],
        };
        self.update_tensions();
        Ok(())
    }

    /// What the static pre-load could not do ([`Belt3d::preload`]).
    fn build_note(&self) -> Option<String> {
        self.preload_note.clone()
    }
}

impl MechanicalSystem for Belt3d {
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

    /// The residual at the mean configuration (as `beam_3d`).
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

    /// Damped Newton, as on the planar drives: at 60-72 elements a node arriving on a
    /// pulley's arc enters contact within one increment and the iteration cycled between the
    /// arriving node and its neighbour (`belt_drive_3d` from rest, 0.3 s: 2 failed steps at 72
    /// elements, 6 at 60; none with backtracking, at the same cost). Session 25 had kept it
    /// off because it moved the quarter-twist drive's energy balance to 3.4 %; that was the
    /// bristle storing the damper's force (`contact::circle_friction::bristle_factor`):
    /// with the Kelvin–Voigt bristle the balance is −0.31 % with it, −0.30 % without.
    fn damped_newton(&self) -> bool {
        true
    }

    /// Six halvings instead of three (issue 13 item 5, session 29): the failed solves of the
    /// 60 rad/s protocol were a node arriving on a pulley cycling in and out of contact. Out
    /// of contact (gap +0.44 δ0, δ0 the penalty's smoothing depth) the full-Newton increment
    /// put it 34 δ0 deep; three halvings left it at 3.8 δ0, from where the next increment
    /// took it out again (converged: 1.2 δ0), 25 iterations on the same five states. A
    /// fourth halving lands at 1.7 δ0 and the iteration converges (120 elements: 18 failed
    /// solves → 0). The cuts cost residual evaluations only where the residual rose.
    fn line_search_cuts(&self) -> usize {
        BELT3D_LINE_SEARCH_CUTS
    }

    /// A kept iteration matrix is current while the section points in contact are those it
    /// was built with (issue 13 item 5, session 36). At 60 rad/s a section lands on a rim in
    /// 62 % of the 1 ms steps at 120 elements (two sections per element pass each of the two
    /// arrival tangent points every 1.4 ms). The matrix of the predicted state has no contact
    /// block for the landing points: the first increment of such a step was 2–3 times that of
    /// the other steps, the residual often rose (backtracked), and the next iteration with the
    /// same matrix mostly diverged (rate > 1) before a fresh one was built. Landing steps took
    /// 4.9 iterations and 2.5 factorizations, the others 2.7 and 1.23. Rebuilt as soon as the
    /// set of points in contact has changed (after the backtracking test, which still judges
    /// the full-Newton increment), landing steps take 3.5 and 2.3; all steps 4.18 → 3.15
    /// iterations and 2.12 → 1.91 factorizations per step at 120 elements (README, the 3D
    /// belt's speed). Stick/slip changes do not count: a kept matrix mostly converges through
    /// them (counting them too: 2.35 factorizations per step, slower).
    fn kept_matrix_current(&self) -> bool {
        let current = self.contact.contacts_as_in_matrix();
        self.refresh.pending.set(!current);
        current
    }

    /// A kept matrix that went stale because sections landed (or lifted) is refreshed
    /// rather than rebuilt (issue 13 item 5, session 37): the matrix of its build without
    /// the contact blocks, plus the contact blocks at the state where the contact set was
    /// found changed (the landing points' blocks included). Newton's method asks for the
    /// matrix at that state right after [`Self::kept_matrix_current`] said no; the elements'
    /// tangents and inertia (three quarters of a matrix's assembly) are those of the kept
    /// matrix, one Newton increment old, as in any kept-matrix iteration.
    fn refreshed_matrix(&self) -> bool {
        self.refresh.refreshed
    }

    /// The transport predictor (the 3D analogue of the planar drive's, issue 12): node `i` at
    /// `t + h` is where the material at `X_i + ΔX_i` was at `t`, `ΔX = h (v · t_i)` along the
    /// centre line (`t_i = R_i e₁`, the node's tangent; element lengths: chord times
    /// `(φ/2)/sin(φ/2)`, φ the turn between the node tangents), plus
    /// `h v_n`, the velocity normal to the transport. Position from the cubic Hermite centre
    /// line between the element's nodes (end tangents `R e₁` times the element's length), orientation from the
    /// geodesic between the element's two node orientations, `R_a exp(ξ log(R_aᵀ R_b))`,
    /// turned by the smallest rotation that takes its `e₁` onto the tangent of that Hermite
    /// centre line at ξ (as the planar drive's slopes are the Hermite slopes), across
    /// element boundaries and round the loop; written as the incremental rotation vector
    /// `log(R_refᵀ R_pred)` from the node's stored orientation.
    ///
    /// The tangent (issue 13 item 5, session 34): the geodesic interpolates a node's
    /// in-plane angle linearly between the element's nodes, which is exact on an arc and on a
    /// span but not across a tangent point, where the curvature jumps from 0 to 1/R inside the
    /// element. There it turned a node landing on (leaving) a rim too early (too late):
    /// 60 rad/s protocol, 120 elements, the predicted `e₁` against the converged one, rms over
    /// nodes within 4° of 100° from the line of centres on pulley 1, 1.0e-2 rad with the
    /// geodesic, 2.7e-3 with the Hermite tangent (quadratic in ξ); within 4e-5 rad of each
    /// other on the arcs, 1.6e-3 both on the spans (their vibration). Those nodes' rotations
    /// were the largest scaled first Newton increments and changed sign from one iteration
    /// to the next while the sections next to them entered contact. The pulley angles keep the
    /// integrator's predictor. Off in statics (no transport) and if switched off
    /// ([`Belt3d::set_transport_predictor`]).
    ///
    /// A node whose centre line is pressed onto a pulley's rim at the start of the step
    /// (gap `g₀ = ρ − R(ζ)` < 0, [`Pulley3d::rim_gap`], axially within the rim's reach
    /// `|ζ| < h + b`) and whose transported place on the centre line (before `h v_n`) is
    /// still inside that rim keeps its gap: its predicted position is moved along the rim's
    /// radial direction to `R(ζ) + g₀` ([`Pulley3d::at_rim_gap`]); a node carried off the arc
    /// onto a span keeps the transport. On the rim the penalty holds the radial position to
    /// within the ringing of the contact (issue 13 item 5, session 31: 60 rad/s, 120 elements, rms
    /// change of an arc node's gap over a step 9e-6 m on pulley 1), while the interpolated
    /// centre line plus `h v_n` missed it by 5e-5 m rms (`h v_n` carries that ringing's
    /// velocity), 1.8 times the penetration itself and 12 times the penalty's smoothing depth:
    /// the first Newton increment then moved arc points in and out of contact and between
    /// stick and slip. Spans and nodes off the rims keep the transport.
    fn predict(&mut self, q0: &[f64], v0: &[f64], h: f64, q1: &mut [f64]) -> bool {
        let l = self.element_length();
        if !self.transport_predictor || self.held.is_some() || h <= 0.0 || l <= 0.0 {
            return false;
        }
        let (mut qf, mut vf, mut pred) = (
            std::mem::take(&mut self.st.qw),
            std::mem::take(&mut self.st.vw),
            std::mem::take(&mut self.st.aw),
        );
        self.st.asm.dofs.expand(q0, &mut qf);
        self.st.asm.dofs.expand(v0, &mut vf);
        let n = self.n_nodes;
        let at = |k: usize| Vector3::from_column_slice(&qf[k * NODE_DOFS..k * NODE_DOFS + 3]);
        let mut ps = std::mem::take(&mut self.predict_scratch);
        ps.frames.clear();
        ps.frames
            .extend((0..n).map(|k| self.node_orientation(k, &qf)));
        let tangent = |k: usize| ps.frames[k] * Vector3::x();
        // length of element e's centre line [m]: its chord times (φ/2)/sin(φ/2), the arc
        // through the chord turning by the angle φ between the node tangents
        ps.arcs.clear();
        for e in 0..n {
            let half = 0.5 * tangent(e).angle(&tangent((e + 1) % n));
            let f = if half > 1e-8 { half / half.sin() } else { 1.0 };
            ps.arcs.push((at((e + 1) % n) - at(e)).norm() * f);
        }
        let arc = |e: usize| ps.arcs[e];
        for i in 0..n {
            let k = i * NODE_DOFS;
            let ri = ps.frames[i];
            let t = ri * Vector3::x();
            let vel = Vector3::from_column_slice(&vf[k..k + 3]);
            let vt = vel.dot(&t);
            // the element holding the point h (v·t) further along the centre line, and the
            // remaining distance s into it [m] (the stretched belt's lengths)
            let (mut e, mut s) = (i, h * vt);
            let mut steps = 0;
            while s.is_finite() && steps <= n {
                steps += 1;
                if s < 0.0 {
                    e = (e + n - 1) % n;
                    s += arc(e);
                } else if s > arc(e) {
                    s -= arc(e);
                    e = (e + 1) % n;
                } else {
                    break;
                }
            }
            let lc = arc(e);
            if !s.is_finite() || steps > n || lc <= 0.0 {
                pred[k..k + NODE_DOFS].copy_from_slice(&qf[k..k + NODE_DOFS]);
                continue;
            }
            let xi = (s / lc).clamp(0.0, 1.0);
            let (a, b) = (e, (e + 1) % n);
            let (qa, qb) = (ps.frames[a], ps.frames[b]);
            // cubic Hermite centre line with end tangents R e₁ times the element's length
            // (the element's own are scaled by l0: on a stretched span this one moves the
            // material uniformly, the element's would be off by up to 0.1 (l − l0))
            let w = hermite(xi);
            let centre = w[0] * at(a)
                + w[2] * at(b)
                + lc * (w[1] * (qa * Vector3::x()) + w[3] * (qb * Vector3::x()));
            let mut r = centre + h * (vel - vt * t);
            // a node pressed onto a rim keeps its gap to that rim where the transported
            // centre line is still inside it (see the doc above)
            let r0 = at(i);
            for ob in self.contact.obstacles() {
                let g0 = ob.rim_gap(&r0);
                if g0 < 0.0 && ob.lateral(&r0).abs() < ob.half_width + ob.belt_half_width {
                    if ob.rim_gap(&centre) < 0.0 {
                        r = ob.at_rim_gap(&r, g0);
                    }
                    break;
                }
            }
            // orientation: the geodesic between the element's node orientations, turned
            // (by the smallest rotation) so that its e₁ follows the Hermite centre line's
            // tangent at ξ (see the doc above)
            let mut rp =
                qa * UnitQuaternion::from_scaled_axis(xi * (qa.inverse() * qb).scaled_axis());
            let dw = hermite_d1(xi);
            let tangent_at = dw[0] * at(a)
                + dw[2] * at(b)
                + lc * (dw[1] * (qa * Vector3::x()) + dw[3] * (qb * Vector3::x()));
            if let Some(turn) = UnitQuaternion::rotation_between(&(rp * Vector3::x()), &tangent_at)
            {
                rp = turn * rp;
            }
            let th = (self.st.frames.reference(i).inverse() * rp).scaled_axis();
            pred[k..k + 3].copy_from_slice(r.as_slice());
            pred[k + 3..k + 6].copy_from_slice(th.as_slice());
        }
        let belt = n * NODE_DOFS;
        for (kf, &i) in self.st.asm.dofs.free_to_full().iter().enumerate() {
            if i < belt {
                q1[kf] = pred[i];
            }
        }
        (self.st.qw, self.st.vw, self.st.aw) = (qf, vf, pred);
        self.predict_scratch = ps;
        true
    }

    fn rebase(&mut self, q: &mut [f64]) {
        self.st.rebase(q);
    }

    /// Free pulleys held at their committed angles by a stiff bearing spring
    /// (`10³ EA r²` [N m/rad]) while the belt is mounted.
    fn hold_for_statics(&mut self, held: bool) {
        self.held = held.then(|| self.pulley_dof.iter().map(|&d| self.st.q[d]).collect());
    }
}

/// The mounted path: planar (pulley axes along z) or in space.
enum Mount {
    Plane(Loop),
    Space(SpacePath),
}

impl Mount {
    fn length(&self) -> f64 {
        match self {
            Mount::Plane(lp) => lp.length,
            Mount::Space(sp) => sp.length,
        }
    }

    fn span_middles(&self) -> Vec<Vector3<f64>> {
        match self {
            Mount::Plane(lp) => (0..lp.spans.len())
                .map(|i| {
                    let m = lp.at(lp.span_middle(i)).r;
                    Vector3::new(m.x, m.y, 0.0)
                })
                .collect(),
            Mount::Space(sp) => sp.span_middles(),
        }
    }

    /// Position, tangent, width direction and (in space) the pulley whose arc the point at
    /// arc length `s` lies on.
    fn at(&self, s: f64) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>, Option<usize>) {
        match self {
            Mount::Plane(lp) => {
                let p = lp.at(s);
                (
                    Vector3::new(p.r.x, p.r.y, 0.0),
                    Vector3::new(p.t.x, p.t.y, 0.0),
                    Vector3::z(),
                    None,
                )
            }
            Mount::Space(sp) => {
                let p = sp.at(s);
                (p.r, p.t, p.w, p.pulley)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::GeneralizedAlpha;
    use crate::linalg::SolverKind;
    use crate::solver::newton::{NewtonPolicy, NewtonSettings, Workspace};

    /// A 2 m belt drive of 72 elements: pulley 1 (r = 0.1 m, crowned) driven at 2 rad/s,
    /// pulley 2 (r = 0.08 m, flanged) free with a load torque, its axis tilted by 0.02 rad
    /// about the span direction and offset 2 mm along it; `width_points` contact points
    /// across the belt's width.
    fn drive(width_points: usize, points_per_element: usize) -> Belt3d {
        let (b, t) = (0.03, 0.003);
        let e = 1e8;
        let (ea, g) = (e * b * t, 0.4e8 * b * t);
        let section = BeamSection {
            ea,
            ga_y: 5.0 / 6.0 * g,
            ga_z: 5.0 / 6.0 * g,
            gj: 0.4e8 * b * t.powi(3) / 3.0,
            ei_y: e * t * b.powi(3) / 12.0,
            ei_z: e * b * t.powi(3) / 12.0,
            rho_a: 0.1,
            rho_jx: 0.1 / (b * t) * b * t * (b * b + t * t) / 12.0,
            rho_iy: 0.1 * b * b / 12.0,
            rho_iz: 0.1 * t * t / 12.0,
        };
        let tilt: f64 = 0.02;
        let pulleys = vec![
            Pulley3dDef {
                center: Vector3::zeros(),
                axis: Vector3::z(),
                radius: 0.1,
                rim_width: 0.04,
                crown: 3e-4,
                flange: 0.0,
                motion: Pulley3dMotion::Driven { omega: 2.0 },
            },
            Pulley3dDef {
                center: Vector3::new(0.7, 0.0, 0.002),
                axis: Vector3::new(0.0, -tilt.sin(), tilt.cos()),
                radius: 0.08,
                rim_width: 0.04,
                crown: 0.0,
                flange: 0.01,
                motion: Pulley3dMotion::Free {
                    inertia: 2e-3,
                    damping: 1e-3,
                    torque: -0.2,
                },
            },
        ];
        let mut contact = crate::kinds::belt_drive::model::default_contact(
            ea,
            0.1,
            t,
            0.08 + 0.5 * t,
            0.1 + 0.5 * t,
            200.0,
            0.4,
            (0.0, 0.0, 0.0),
        );
        // the bristle this unbalanced start (no pre-load yet) was written for: the 2D drive's
        // default moved to k_n/10 (creep), with which Newton fails at step 5 from this start
        contact.k_t = 0.01 * contact.k_n;
        Belt3d::new(Belt3dSpec {
            section,
            thickness: t,
            width: b,
            pulleys,
            contact,
            n_elements: 72,
            pretension: 200.0,
            gravity: Vector3::zeros(),
            bowing: true,
            space_mount: false,
            width_points,
            points_per_element,
        })
        .unwrap()
    }

    fn run(m: &mut Belt3d, steps: usize, h: f64) -> DynState {
        let settings = NewtonSettings {
            tolerance: 1e-10,
            max_iterations: 30,
            policy: NewtonPolicy::Full,
            line_search: false,
        };
        let mut ws = Workspace::new(m, SolverKind::Auto).unwrap();
        let n = m.n_free();
        let mut s0 = DynState::zeros(n, 0.0);
        m.free_state(&mut s0.q, &mut s0.v);
        let mut s1 = s0.clone();
        let ga = GeneralizedAlpha::from_rho_inf(0.8);
        for i in 0..steps {
            ga.step(m, &mut ws, &settings, &s0, h, &mut s1)
                .unwrap_or_else(|e| panic!("step {i}: {e}"));
            m.accept(&mut s1);
            std::mem::swap(&mut s0, &mut s1);
        }
        s0
    }

    /// The iteration matrix of `m` at state `s` against central differences of the residual.
    fn check_jacobian(m: &mut Belt3d, s: &DynState) {
        let n = m.n_free();
        let pat = m.pattern().clone();
        for (stiff, damp) in [(1.0, 0.0), (0.0, 1.0)] {
            let coeffs = JacobianCoeffs {
                mass: 0.0,
                damping: damp,
                stiffness: stiff,
            };
            let mut r = vec![0.0; n];
            let mut vals = vec![0.0; pat.nnz()];
            m.residual(
                s.t,
                &s.q,
                &s.v,
                &s.acc,
                1.0,
                &mut r,
                Some((coeffs, &mut vals)),
            )
            .unwrap();
            let (mut worst, mut scale, mut at) = (0.0f64, 0.0f64, (0, 0));
            for j in 0..n {
                let hstep = if stiff > 0.0 { 1e-8 } else { 1e-6 };
                let (mut xp, mut xm) = if stiff > 0.0 {
                    (s.q.clone(), s.q.clone())
                } else {
                    (s.v.clone(), s.v.clone())
                };
                xp[j] += hstep;
                xm[j] -= hstep;
                let (mut rp, mut rm) = (vec![0.0; n], vec![0.0; n]);
                if stiff > 0.0 {
                    m.residual(s.t, &xp, &s.v, &s.acc, 1.0, &mut rp, None)
                        .unwrap();
                    m.residual(s.t, &xm, &s.v, &s.acc, 1.0, &mut rm, None)
                        .unwrap();
                } else {
                    m.residual(s.t, &s.q, &xp, &s.acc, 1.0, &mut rp, None)
                        .unwrap();
                    m.residual(s.t, &s.q, &xm, &s.acc, 1.0, &mut rm, None)
                        .unwrap();
                }
                for i in 0..n {
                    let fd = (rp[i] - rm[i]) / (2.0 * hstep);
                    let an = pat.position(i, j).map_or(0.0, |p| vals[p]);
                    if (fd - an).abs() > worst {
                        (worst, at) = ((fd - an).abs(), (i, j));
                    }
                    scale = scale.max(an.abs());
                }
            }
            assert!(
                worst <= 1e-4 * scale,
                "t = {}: stiffness {stiff} damping {damp}: worst {worst:.3e} of {scale:.3e} at {at:?}",
                s.t
            );
        }
    }

    /// The iteration matrix of the whole model (co-rotational elements, 3D pulley contact
    /// with crown, flanges, a free pulley) against central differences of the residual, as
    /// mounted and after 10 steps of running; with the centre-line contact and with three
    /// points across the width (the contact moments on the node rotations; after 3 steps:
    /// from this unbalanced start without pre-load full Newton stalls at step 4 with them).
    #[test]
    fn model_jacobian_matches_finite_differences() {
        for (width_points, per_element, steps) in [(1, 0, 10), (3, 0, 3), (3, 2, 3)] {
            let mut m = drive(width_points, per_element);
            let s = run(&mut m, 0, 5e-4);
            check_jacobian(&mut m, &s);
            let s = run(&mut m, steps, 2e-4);
            assert!(
                m.contact_book().normal_energy > 0.0,
                "the belt touches the pulleys"
            );
            check_jacobian(&mut m, &s);
        }
    }

    /// A refreshed kept matrix ([`MechanicalSystem::refreshed_matrix`]) is the matrix of the
    /// kept build without its contact blocks plus the contact blocks of the evaluated state:
    /// refreshed at the state of that build it is that build's matrix to the bit, with the
    /// residual of the evaluation without a matrix; at another state (or without the stale
    /// answer) the model builds the matrix in full.
    #[test]
    fn refreshed_matrix_is_the_kept_build_with_the_contact_of_the_state() {
        let mut m = drive(3, 2);
        let s = run(&mut m, 3, 2e-4);
        assert!(m.contact_book().normal_energy > 0.0, "in contact");
        let n = m.n_free();
        let nnz = m.pattern().nnz();
        let c = JacobianCoeffs {
            mass: 1.0,
            damping: 1e-3,
            stiffness: 4e-8,
        };
        let (mut r_full, mut j_full) = (vec![0.0; n], vec![0.0; nnz]);
        m.residual(
            s.t,
            &s.q,
            &s.v,
            &s.acc,
            1.0,
            &mut r_full,
            Some((c, &mut j_full)),
        )
        .unwrap();
        assert!(!m.refreshed_matrix());
        // a residual at another state, then the stale answer and a matrix at that state:
        // built in full (its residual is not the one of the evaluation without a matrix)
        let mut q1 = s.q.clone();
        q1[0] += 1e-6;
        let mut r = vec![0.0; n];
        m.residual(s.t, &q1, &s.v, &s.acc, 1.0, &mut r, None)
            .unwrap();
        m.refresh.pending.set(true);
        let mut j = vec![0.0; nnz];
        m.residual(s.t, &s.q, &s.v, &s.acc, 1.0, &mut r, Some((c, &mut j)))
            .unwrap();
        assert!(!m.refreshed_matrix(), "another state: built in full");
        assert_eq!(j, j_full);
        // the same state: refreshed, the same matrix and residual
        m.residual(s.t, &s.q, &s.v, &s.acc, 1.0, &mut r, None)
            .unwrap();
        assert_eq!(r, r_full);
        m.refresh.pending.set(true);
        let (mut r2, mut j2) = (vec![f64::NAN; n], vec![f64::NAN; nnz]);
        m.residual(s.t, &s.q, &s.v, &s.acc, 1.0, &mut r2, Some((c, &mut j2)))
            .unwrap();
        assert!(m.refreshed_matrix());
        assert_eq!(r2, r_full);
        assert_eq!(j2, j_full);
        // the refreshed matrix keeps the elements' part of the kept build: refreshed at q1
        // after a build at q1, it is the matrix of q1 (the kept build) and not the one of s.q
        let mut j1 = vec![0.0; nnz];
        m.residual(s.t, &q1, &s.v, &s.acc, 1.0, &mut r, Some((c, &mut j1)))
            .unwrap();
        assert_ne!(j1, j_full);
        m.residual(s.t, &s.q, &s.v, &s.acc, 1.0, &mut r, None)
            .unwrap();
        m.refresh.pending.set(true);
        m.residual(s.t, &s.q, &s.v, &s.acc, 1.0, &mut r2, Some((c, &mut j2)))
            .unwrap();
        assert!(m.refreshed_matrix());
        assert_ne!(j2, j_full);
        // no stale answer: a full build
        m.residual(s.t, &s.q, &s.v, &s.acc, 1.0, &mut r, None)
            .unwrap();
        m.residual(s.t, &s.q, &s.v, &s.acc, 1.0, &mut r2, Some((c, &mut j2)))
            .unwrap();
        assert!(!m.refreshed_matrix());
        assert_eq!(j2, j_full);
    }

    /// The transport predictor against the belt's path: the belt mounted on the loop of two
    /// coplanar pulleys ([`Belt3d::new`]: nodes on the pitch path, on the arcs moved in by the
    /// contact penetration) moving along it at speed `c` is predicted at the path point `c h`
    /// further on, across element boundaries and round the loop's start, 2.6 elements in one
    /// step, its tangent along the path's and its width direction along the axes. Reference:
    /// the loop geometry (`meshers::belt_loop`, tangent lines and arcs). The integrator's own
    /// predictor `q + h v` would put the nodes on the arcs off the path by the chord's
    /// sagitta and keep the orientations.
    #[test]
    fn transport_predictor_moves_the_belt_along_its_path() {
        let mut spec = drive(1, 0).spec;
        spec.pulleys[1].axis = Vector3::z();
        spec.pulleys[1].center.z = 0.0;
        let mut m = Belt3d::new(spec).unwrap();
        let half_t = 0.5 * m.spec.thickness;
        let circles: Vec<PitchCircle> = m
            .spec
            .pulleys
            .iter()
            .map(|p| PitchCircle {
                center: Vector2::new(p.center.x, p.center.y),
                radius: p.radius + half_t,
            })
            .collect();
        let lp = Loop::new(&circles).unwrap();
        let n = m.n_free();
        let (mut q0, mut v0) = (vec![0.0; n], vec![0.0; n]);
        m.free_state(&mut q0, &mut v0);
        let nn = m.n_nodes;
        let l_mount = lp.length / nn as f64;
        let (c, h) = (30.0, 2.6 * l_mount / 30.0);
        let mut vfull = vec![0.0; m.st.q.len()];
        for i in 0..nn {
            let t = m.st.frames.rotation(i, &m.st.q) * Vector3::x();
            vfull[i * NODE_DOFS..i * NODE_DOFS + 3].copy_from_slice((c * t).as_slice());
        }
        m.st.asm.dofs.restrict(&vfull, &mut v0);
        let mut q1 = q0.clone();
        assert!(m.predict(&q0, &v0, h, &mut q1));
        let mut pred = m.st.q.clone();
        m.st.asm.dofs.expand(&q1, &mut pred);
        // worst position and tangent errors on elements wholly on a span or an arc, and on
        // elements across a span's end (where the path's curvature jumps), and of the width
        // direction
        let (mut worst_r, mut worst_t, mut worst_w) = ([0.0f64; 2], [0.0f64; 2], 0.0f64);
        for i in 0..nn {
            let s = i as f64 * l_mount + c * h;
            let s0 = (s / l_mount).floor() * l_mount;
            let turn = lp.at(s0).t.angle(&lp.at(s0 + l_mount).t);
            let across = usize::from(
                turn > 1e-9
                    && circles
                        .iter()
                        .all(|p| (turn - l_mount / p.radius).abs() > 1e-9),
            );
            let want = lp.at(s);
            let r = Vector3::from_column_slice(&pred[i * NODE_DOFS..i * NODE_DOFS + 3]);
            let rot = m.st.frames.rotation(i, &pred);
            let t = rot * Vector3::x();
            let (er, et) = (
                (Vector3::new(want.r.x, want.r.y, 0.0) - r).norm(),
                (Vector3::new(want.t.x, want.t.y, 0.0) - t).norm(),
            );
            worst_r[across] = worst_r[across].max(er);
            worst_t[across] = worst_t[across].max(et);
            worst_w = worst_w.max((rot * Vector3::z() - Vector3::z()).norm());
        }
        let pen = m.spec.pretension / (circles[1].radius * m.spec.contact.k_n);
        println!(
            "transport predictor: position {:.3e} m, {:.3e} m across a span's end (penetration {pen:.3e} m), tangent {:.3e}, {:.3e}, width direction {worst_w:.3e}",
            worst_r[0], worst_r[1], worst_t[0], worst_t[1]
        );
        // on a span or an arc: the reference puts the nodes at the pitch path's arc length,
        // the mount moves those on the arcs in by the penetration `pen`, which also shortens
        // their spacing by pen/R: the predicted nodes are off by at most pen (1 + c h/R)
        // (measured 9.1e-5 m) and their tangents by c h pen/R² (7.1e-4 rad)
        let r_min = circles
            .iter()
            .map(|p| p.radius)
            .fold(f64::INFINITY, f64::min);
        // (that with the geodesic orientation alone); the orientation follows the Hermite
        // centre line's tangent, which on a span element whose end node the mount moved in
        // onto an arc bends with the chord by up to 6ξ(1−ξ) pen/l ≤ 1.5 pen/l (measured
        // 2.8e-3 rad)
        let chord_slope = 1.5 * pen / l_mount;
        let (bound_r, bound_t) = (
            pen * (1.0 + c * h / r_min),
            1.1 * c * h * pen / (r_min * r_min) + chord_slope,
        );
        assert!(
            worst_r[0] < bound_r,
            "position off the path by {:.3e} m",
            worst_r[0]
        );
        assert!(
            worst_t[0] < bound_t,
            "tangent off the path's by {:.3e}",
            worst_t[0]
        );
        // across a span's end the path's curvature jumps from 0 to 1/R within an element: the
        // orientation interpolated at a constant rate (the geodesic alone) is off the path's
        // by up to l/(4R) (at half the element on the arc; measured 6.8e-2 rad), the Hermite
        // tangent by up to 0.084 l/R (computed for a straight-to-arc element, any tangent
        // point and ξ; measured 1.7e-2 rad), the cubic's position by about l²/(32R) more
        // than above
        let (bound_r, bound_t) = (
            bound_r + l_mount * l_mount / (32.0 * r_min),
            l_mount / (8.0 * r_min) + chord_slope,
        );
        assert!(
            worst_r[1] < bound_r,
            "position off the path by {:.3e} m",
            worst_r[1]
        );
        assert!(
            worst_t[1] < bound_t,
            "tangent off the path's by {:.3e}",
            worst_t[1]
        );
        assert!(
            worst_w < 1e-12,
            "width direction off the axis by {worst_w:.3e}"
        );
        // the pulley angles keep the integrator's predictor
        for &d in &m.pulley_dof {
            if let Some(k) = m.st.asm.dofs.free_index(d) {
                assert_eq!(q1[k], q0[k]);
            }
        }
    }
}
