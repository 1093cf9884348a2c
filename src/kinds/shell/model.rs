//! A shell of seed-004 trapezoidal elements ([`TrapezoidShell`], Pogorelov & Rodikov 2021):
//! a flat plate ([`PlateMesh`]) or a surface of revolution ([`RevolutionMesh`]), with
//! supports, point and line loads, a uniform follower pressure ([`pressure_into`]), gravity,
//! probes, ring outputs, the enclosed volume ([`volume_part`]) and energies.
//!
//! **Coordinates.** Per node `[x, y, z, θx, θy, θz]`: the absolute position [m] and an
//! incremental rotation vector θ [rad] from the node's stored orientation (a unit quaternion,
//! [`NodeFrames`]), absorbed after every accepted step and every converged load increment,
//! exactly as in the 3D beam (see [`crate::kinds::beam_3d::model`]): the shared additive
//! integrators then act as Lie-group schemes. Velocities are `[ẋ, Ω]` with the body angular
//! velocity `Ω`.
//!
//! **Residual.** `r = M a + f_int(q) − Q_g − λ (f_loads + f_pressure(q))`: force rows in global
//! components, moment rows in body components. The pressure `p` acts on every element as the
//! follower load `f_i = p ∫ N_i (x_ξ × x_η) dξ dη` of the bilinear patch through its four nodes,
//! with its exact tangent (not symmetric) in the iteration matrix.

use super::scene::{Input, Output, io, names::*, support_param};
use super::{MeridianSection, RingAt, RingQuantity, ShellMotion, ShellScene, SupportCondition};
use crate::assembly::{Assembly, Connectivity, DofMap, ElementSet};
use crate::elements::Element;
use crate::elements::node_frames::NodeFrames;
use crate::elements::surface_load::{pressure_into, volume_part};
use crate::elements::trapezoid_shell::{
    Bending, ELEMENT_DOFS, NODE_DOFS, ShellMaterial, ShellOptions, TrapezoidShell,
};
use crate::integrators::DynState;
use crate::kinds::KindIo;
use crate::kinds::energy::EnergyKind;
use crate::linalg::CscPattern;
use crate::meshers::plate::{PlateEdge, PlateMesh, line_weights, node_at_point};
use crate::meshers::revolution::{MeridianEnd, MeridianPiece, RevolutionMesh};
use crate::model::framed::FramedState;
use crate::model::inputs::InputSignal;
use crate::model::nodes3d::{NodeLoad, NodeMotion};
use crate::model::ports::{Channel, PortHost, Ports};
use crate::model::rates;
use crate::model::{JacobianCoeffs, MechanicalSystem, Model, ModelError};
use crate::scene::params::{ParamValues, names::*};
use crate::snapshot::{StateReader, StateWriter};
use crate::variables::Value;
use nalgebra::{SMatrix, SVector, Vector2, Vector3};
use std::collections::BTreeMap;

/// The reference mesh of either geometry: nodes, elements (counter-clockwise about their
/// normal), rings of a surface of revolution with their arc lengths, and what names the mesh
/// in messages.
#[derive(Clone, Debug)]
struct Geometry {
    nodes: Vec<Vector3<f64>>,
    elements: Vec<[usize; 4]>,
    /// `(arc length [m], nodes)` of every ring, in meridian order (empty for a plate).
    rings: Vec<(f64, Vec<usize>)>,
    /// The plate mesh (edges), if a plate.
    plate: Option<PlateMesh>,
    /// Whether the plate is a rectangle (all elements equal).
    rectangle: bool,
    /// Scene keys and parameters the nodes follow from.
    keys: &'static str,
    /// Whether the surface is closed (both ends of the meridian on the axis).
    closed: bool,
    /// The nodes on the axis at both poles of a closed surface, if both have one.
    poles: Option<(usize, usize)>,
}

const PLATE_KEYS: &str = "plate.length_x, plate.length_y, plate.width_top, mesh.n_x and mesh.n_y";
const REVOLUTION_KEYS: &str = "meridian.start, the direction, length, radius and angle_deg of the meridian.pieces, mesh.n_circumferential and mesh.n_meridional";

fn meridian_pieces(m: &MeridianSection) -> Result<Vec<MeridianPiece>, String> {
    m.pieces
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let direction = p.direction.map(|d| Vector2::new(d[0], d[1]));
            match (p.length, p.radius, p.angle_deg) {
                (Some(length), ..) => Ok(MeridianPiece::Line { direction, length }),
                (None, Some(radius), Some(a)) => Ok(MeridianPiece::Arc {
                    direction,
                    radius,
                    angle: a.to_radians(),
                }),
                _ => Err(format!("meridian.pieces[{i}]: incomplete piece")),
            }
        })
        .collect()
}

fn count(p: &ParamValues, name: &str) -> usize {
    p.integer(name).max(0) as usize
}

/// The mesh of a scene with the parameter values `p`.
fn geometry(scene: &ShellScene, p: &ParamValues) -> Result<Geometry, String> {
    if let Some(pl) = &scene.plate {
        let (n_x, n_y) = (count(p, MESH_N_X), count(p, MESH_N_Y));
        if (n_x as i64) * (n_y as i64) > super::scene::MAX_ELEMENTS {
            return Err(format!(
                "{MESH_N_X} = {n_x}, {MESH_N_Y} = {n_y}: {} elements, at most {}",
                n_x * n_y,
                super::scene::MAX_ELEMENTS
            ));
        }
        let mesh = PlateMesh::new(pl.length_x, pl.length_y, pl.width_top, n_x, n_y)?;
        return Ok(Geometry {
            nodes: mesh.nodes.clone(),
            elements: mesh.elements.clone(),
            rings: vec![],
            rectangle: pl.width_top.is_none_or(|w| w == pl.length_x),
            plate: Some(mesh),
            closed: false,
            poles: None,
            keys: PLATE_KEYS,
        });
    }
    let mer = scene
        .meridian
        .as_ref()
        .ok_or("plate, meridian: give [plate] or [meridian]")?;
    let (n_c, n_m) = (
        count(p, MESH_N_CIRCUMFERENTIAL),
        count(p, MESH_N_MERIDIONAL),
    );
    if (n_c as i64) * (n_m as i64) > super::scene::MAX_ELEMENTS {
        return Err(format!(
            "{MESH_N_CIRCUMFERENTIAL} = {n_c}, {MESH_N_MERIDIONAL} = {n_m}: {} elements, at most {}",
            n_c * n_m,
            super::scene::MAX_ELEMENTS
        ));
    }
    let mesh = RevolutionMesh::new(
        Vector2::new(mer.start[0], mer.start[1]),
        &meridian_pieces(mer)?,
        n_c,
        n_m,
        "meridian.pieces",
    )
    .map_err(|e| format!("{e} (the surface follows from {REVOLUTION_KEYS})"))?;
    let arcs = mesh.meridian.stations.arc_lengths();
    let rings = (0..mesh.n_stations())
        .filter_map(|j| mesh.ring_nodes(j).map(|r| (arcs[j], r.collect())))
        .collect();
    let axis_node = |end| mesh.pole(end).and_then(|p| p.axis_node);
    let poles = match (axis_node(MeridianEnd::Start), axis_node(MeridianEnd::End)) {
        (Some(a), Some(b)) => Some((a, b)),
        _ => None,
    };
    Ok(Geometry {
        closed: mesh.is_closed(),
        poles,
        nodes: mesh.nodes,
        elements: mesh.elements,
        rings,
        plate: None,
        rectangle: false,
        keys: REVOLUTION_KEYS,
    })
}

impl Geometry {
    /// The node at the point `at` (2 or 3 numbers) of the scene entry `key`.
    fn node_at(&self, key: &str, at: &[f64]) -> Result<usize, String> {
        let p = Vector3::new(at[0], at[1], at.get(2).copied().unwrap_or(0.0));
        node_at_point(&self.nodes, &p, key, self.keys)
    }

    /// The ring `ring` of the scene entry `key`.
    fn ring(&self, key: &str, ring: &RingAt) -> Result<&[usize], String> {
        let last = self.rings.len().saturating_sub(1);
        let j = match ring {
            RingAt::Name(n) if n == "first" => 0,
            RingAt::Name(n) if n == "last" => last,
            RingAt::Name(n) => {
                return Err(format!(
                    "{key}.ring = \"{n}\": give \"first\", \"last\" or an arc length [m]"
                ));
            }
            RingAt::Arc(s) => {
                let total = self.rings[last].0;
                let (j, d) = self
                    .rings
                    .iter()
                    .enumerate()
                    .map(|(j, r)| (j, (r.0 - s).abs()))
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .unwrap_or((0, f64::INFINITY));
                if d > 1e-6 * total {
                    return Err(format!(
                        "{key}.ring = {s}: no ring at that arc length of the meridian (total {total} m; the nearest ring is at {} m; the rings follow from {})",
                        self.rings[j].0, self.keys
                    ));
                }
                j
            }
        };
        Ok(&self.rings[j].1)
    }
}

impl Geometry {
    /// The nodes of motion port `m` (scene entry `key`) and its reference point [m]: the
    /// midpoint of the end nodes of a plate edge, the centre of a ring on the z axis, or the
    /// node itself.
    fn motion_group(&self, key: &str, m: &ShellMotion) -> Result<(Vec<usize>, [f64; 3]), String> {
        match (&m.edge, &m.ring, &m.at, &self.plate) {
            (Some(e), None, None, Some(plate)) => {
                let nodes = plate.edge_nodes(*e);
                let (a, b) = (self.nodes[nodes[0]], self.nodes[nodes[nodes.len() - 1]]);
                let mid = std::array::from_fn(|d| 0.5 * (a[d] + b[d]));
                Ok((nodes, mid))
            }
            (None, Some(r), None, None) => {
                let nodes = self.ring(key, r)?.to_vec();
                let z = self.nodes[nodes[0]].z;
                Ok((nodes, [0.0, 0.0, z]))
            }
            (None, None, Some(at), _) => {
                let k = self.node_at(key, at)?;
                Ok((vec![k], self.nodes[k].into()))
            }
            _ => Err(format!(
                "{key}: an edge of a plate, a ring of a surface of revolution or one node (at)"
            )),
        }
    }
}

/// Reference points [m] of the motion ports of a scene (the start values of their position
/// inputs), from the mesh at the default parameter values; `[0, 0, 0]` where that mesh
/// cannot be built (the scene's errors are reported elsewhere).
pub(super) fn motion_references(scene: &ShellScene) -> Vec<[f64; 3]> {
    if scene.motions.is_empty() {
        return vec![];
    }
    let geo = super::scene::params(scene)
        .ok()
        .and_then(|defs| geometry(scene, &ParamValues::defaults(&defs)).ok());
    scene
        .motions
        .iter()
        .enumerate()
        .map(|(i, m)| {
            geo.as_ref()
                .and_then(|g| g.motion_group(&format!("motions[{i}]"), m).ok())
                .map_or([0.0; 3], |(_, r)| r)
        })
        .collect()
}

/// Whether the constrained coordinates remove every rigid motion: the six rigid modes
/// (translations; rotations about the centroid, positions scaled by the extent) restricted to
/// the constrained coordinates have full rank.
fn holds_rigid_motion(nodes: &[Vector3<f64>], constrained: &[bool]) -> bool {
    let n = nodes.len().max(1) as f64;
    let c = nodes.iter().map(|x| x / n).sum::<Vector3<f64>>();
    let extent = nodes
        .iter()
        .map(|x| (x - c).norm())
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut g = SMatrix::<f64, 6, 6>::zeros();
    for (k, x) in nodes.iter().enumerate() {
        let r = (x - c) / extent;
        for d in 0..NODE_DOFS {
            if !constrained[k * NODE_DOFS + d] {
                continue;
            }
            let mut m = SVector::<f64, 6>::zeros();
            if d < 3 {
                m[d] = 1.0;
                // rotation about axis a moves the position by e_a × r: component d
                for a in 0..3 {
                    m[3 + a] = Vector3::ith(a, 1.0).cross(&r)[d];
                }
            } else {
                m[d] = 1.0;
            }
            g += m * m.transpose();
        }
    }
    // each mode normalised (a long thin plate has rotation modes of very different sizes)
    let d = g
        .diagonal()
        .map(|x| if x > 0.0 { 1.0 / x.sqrt() } else { 0.0 });
    let g = SMatrix::<f64, 6, 6>::from_fn(|i, j| g[(i, j)] * d[i] * d[j]);
    let ev = g.symmetric_eigenvalues();
    ev.min() > 1e-10
}

/// A probe at a node.
#[derive(Clone, Copy, Debug)]
struct Probe {
    node: usize,
}

/// The seed-004 shell model.
#[derive(Clone, Debug)]
pub struct Shell {
    set: ElementSet<TrapezoidShell, ELEMENT_DOFS>,
    /// Position coordinates of every element (12), for the pressure.
    positions: Connectivity<12>,
    gravity: Vector3<f64>,
    /// Gravity load of the reference (constant: the element's gravity is) [N], full vector.
    gravity_load: Vec<f64>,
    loads: Vec<NodeLoad>,
    pressure: InputSignal,
    /// Motion ports: three channels (x, y, z) per port, each driving that position
    /// coordinate of every node of the group (their rotations are constrained).
    ports: Ports,
    /// Pressure [Pa] of the committed state: the follower tangent of the ports' interface
    /// Jacobian is taken with it (so the Jacobian is a function of the committed state, not of
    /// the pressure input set since).
    port_pressure: f64,
    /// `+1`, or `−1` where a closed surface's element normals point inwards: the pressure and
    /// the volume are taken along the outward normal.
    orientation: f64,
    probes: Vec<Probe>,
    /// Nodes of every ring probe.
    ring_probes: Vec<Vec<usize>>,
    /// Nodes of the first and last rings, and the two poles of a closed surface.
    ends: (Vec<usize>, Vec<usize>),
    poles: Option<(usize, usize)>,
    n_nodes: usize,
    scales: Vec<f64>,
    /// Assembly, node orientations, committed state and work buffers.
    st: FramedState,
    roles: KindIo<Input, Output>,
}

impl Shell {
    /// Builds the model of a scene with the given parameter values (already validated).
    /// Errors name the scene key or parameter at fault.
    pub fn build(scene: &ShellScene, p: &ParamValues) -> Result<Self, String> {
        let geo = geometry(scene, p)?;
        let mat = ShellMaterial {
            e: p.real(MATERIAL_E),
            nu: p.real(MATERIAL_NU),
            rho: p.real(MATERIAL_RHO),
            thickness: p.real(SHELL_THICKNESS),
        };
        let opt = ShellOptions {
            bending: match p.integer(ELEMENT_BENDING) {
                1 => Bending::V1,
                _ => Bending::V2,
            },
            drilling: p.real(ELEMENT_DRILLING_STIFFNESS),
            geometric_stiffness: p.boolean(ELEMENT_GEOMETRIC_STIFFNESS),
            membrane: true,
        };
        let gravity = Vector3::new(
            p.get(GRAVITY_X).map_or(0.0, |_| p.real(GRAVITY_X)),
            p.get(GRAVITY_Y).map_or(0.0, |_| p.real(GRAVITY_Y)),
            p.get(GRAVITY_Z).map_or(0.0, |_| p.real(GRAVITY_Z)),
        );
        let n_nodes = geo.nodes.len();
        let n_full = n_nodes * NODE_DOFS;
        // supports
        let mut constrained = vec![false; n_full];
        let mut fix = |nodes: &[usize], c: SupportCondition| {
            for &k in nodes {
                for d in 0..c.n_fixed() {
                    constrained[k * NODE_DOFS + d] = true;
                }
            }
        };
        if let Some(plate) = &geo.plate {
            for e in PlateEdge::ALL {
                let c = SupportCondition::from_code(p.integer(support_param(e)));
                fix(&plate.edge_nodes(e), c);
            }
        }
        for (i, r) in scene.ring_supports.iter().enumerate() {
            fix(geo.ring(&format!("ring_supports[{i}]"), &r.ring)?, r.kind);
        }
        for (i, s) in scene.point_supports.iter().enumerate() {
            fix(
                &[geo.node_at(&format!("point_supports[{i}]"), &s.at)?],
                s.kind,
            );
        }
        // motion ports: the group's positions follow the port, its rotations are held
        let mut channels = Vec::with_capacity(scene.motions.len());
        let mut port_node = vec![false; n_nodes];
        for (i, m) in scene.motions.iter().enumerate() {
            let key = format!("motions[{i}]");
            let (nodes, reference) = geo.motion_group(&key, m)?;
            for &k in &nodes {
                if (0..NODE_DOFS).any(|d| constrained[k * NODE_DOFS + d]) {
                    let x = geo.nodes[k];
                    return Err(format!(
                        "{key}: the node at [{}, {}, {}] m is already held by a support or another motion port",
                        x.x, x.y, x.z
                    ));
                }
            }
            for &k in &nodes {
                port_node[k] = true;
                for d in 0..NODE_DOFS {
                    constrained[k * NODE_DOFS + d] = true;
                }
            }
            channels.push(
                (0..3)
                    .map(|d| Channel {
                        members: nodes.iter().map(|&k| k * NODE_DOFS + d).collect(),
                        reference: reference[d],
                    })
                    .collect::<Vec<_>>(),
            );
        }
        let on_port = |key: &str, nodes: &[usize]| -> Result<(), String> {
            match nodes.iter().find(|&&k| port_node[k]) {
                Some(&k) => {
                    let x = geo.nodes[k];
                    Err(format!(
                        "{key}: acts on the node at [{}, {}, {}] m, which a motion port moves (the load would go straight into the driver); put it elsewhere",
                        x.x, x.y, x.z
                    ))
                }
                None => Ok(()),
            }
        };
        let statics = matches!(p.get(SOLVER_STATIC), Some(Value::Boolean(true)));
        if statics && !holds_rigid_motion(&geo.nodes, &constrained) {
            return Err(format!(
                "{SOLVER_STATIC} = true: the supports leave the shell (from {}) free to move as a rigid body, so there is no static equilibrium; fix more (support.x0 ... support.y1 of a plate, ring_supports, point_supports) or set {SOLVER_STATIC} = false (the dynamic problem may be free)",
                geo.keys
            ));
        }
        let dofs = DofMap::new(&constrained);
        if dofs.n_free() == 0 {
            return Err("the supports fix every coordinate: nothing left to simulate".into());
        }
        let connectivity: Vec<[usize; ELEMENT_DOFS]> = geo
            .elements
            .iter()
            .map(|el| std::array::from_fn(|i| el[i / NODE_DOFS] * NODE_DOFS + i % NODE_DOFS))
            .collect();
        let asm = Assembly::new(dofs, &[(ELEMENT_DOFS, connectivity.as_flattened())], &[]);
        let make = |e: usize| {
            let x = geo.elements[e].map(|k| geo.nodes[k]);
            TrapezoidShell::new(x, &mat, &opt).map_err(|err| {
                format!(
                    "element {e}: {err} (the geometry follows from {}; the material from {MATERIAL_E}, {MATERIAL_NU}, {MATERIAL_RHO}, {SHELL_THICKNESS})",
                    geo.keys
                )
            })
        };
        let elements: Vec<TrapezoidShell> = if geo.rectangle {
            vec![make(0)?]
        } else {
            (0..geo.elements.len())
                .map(make)
                .collect::<Result<_, _>>()?
        };
        let frames = NodeFrames::new((0..n_nodes).map(|k| k * NODE_DOFS + 3).collect());
        let positions = Connectivity::new(
            connectivity
                .iter()
                .map(|d| std::array::from_fn(|i| d[(i / 3) * NODE_DOFS + i % 3]))
                .collect(),
            &asm,
        );
        let set = ElementSet::new(elements, connectivity, &asm).with_frames(&frames);
        // loads
        let mut loads = Vec::with_capacity(scene.loads.len() + scene.line_loads.len());
        for (i, l) in scene.loads.iter().enumerate() {
            let k = geo.node_at(&format!("loads[{i}]"), &l.at)?;
            on_port(&format!("loads[{i}]"), &[k])?;
            loads.push(NodeLoad::at_node(k, l.start(), false));
        }
        for (i, l) in scene.line_loads.iter().enumerate() {
            let key = format!("line_loads[{i}]");
            let (nodes, closed) = match (&l.edge, &l.ring, &geo.plate) {
                (Some(e), _, Some(plate)) => (plate.edge_nodes(*e), false),
                (_, Some(r), None) => (geo.ring(&key, r)?.to_vec(), true),
                _ => {
                    return Err(format!(
                        "{key}: an edge of a plate or a ring of a surface of revolution"
                    ));
                }
            };
            on_port(&key, &nodes)?;
            let pts: Vec<_> = nodes.iter().map(|&k| geo.nodes[k]).collect();
            let w = line_weights(&pts, closed);
            loads.push(NodeLoad::spread(
                nodes.into_iter().zip(w).collect(),
                l.start(),
                false,
            ));
        }
        let mut probes = Vec::with_capacity(scene.probes.len());
        for (i, pr) in scene.probes.iter().enumerate() {
            probes.push(Probe {
                node: geo.node_at(&format!("probes[{i}]"), &pr.at)?,
            });
        }
        let mut ring_probes = Vec::with_capacity(scene.ring_probes.len());
        for (i, rp) in scene.ring_probes.iter().enumerate() {
            ring_probes.push(geo.ring(&format!("ring_probes[{i}]"), &rp.ring)?.to_vec());
        }
        let closed = geo.closed;
        if scene.outputs.volume && !closed {
            return Err(format!(
                "outputs.volume: the surface is not closed (the meridian of {} must start and end on the z axis), so it encloses no volume",
                geo.keys
            ));
        }
        let poles = geo.poles;
        let ends = match (geo.rings.first(), geo.rings.last()) {
            (Some(a), Some(b)) => (a.1.clone(), b.1.clone()),
            _ => (vec![], vec![]),
        };
        let mut q0 = vec![0.0; n_full];
        for (k, x) in geo.nodes.iter().enumerate() {
            q0[k * NODE_DOFS..k * NODE_DOFS + 3].copy_from_slice(x.as_slice());
        }
        let extent = geo.nodes.iter().map(|x| x.norm()).fold(0.0, f64::max);
        let scale = if extent > 0.0 { extent } else { 1.0 };
        let scales = asm
            .dofs
            .free_to_full()
            .iter()
            .map(|&i| if i % NODE_DOFS < 3 { scale } else { 1.0 })
            .collect();
        let mut gravity_load = vec![0.0; n_full];
        set.add_gravity(&q0, Some(&frames), &gravity, 1.0, &mut gravity_load);
        let ports = Ports::grouped(&channels, &q0, p.real(SOLVER_MAX_STEP));
        let mut model = Self {
            set,
            positions,
            gravity,
            gravity_load,
            loads,
            pressure: InputSignal::constant(scene.pressure.as_ref().map_or(0.0, |p| p.value)),
            ports,
            port_pressure: scene.pressure.as_ref().map_or(0.0, |p| p.value),
            orientation: 1.0,
            probes,
            ring_probes,
            ends,
            poles,
            n_nodes,
            scales,
            st: FramedState::new(asm, frames, q0),
            roles: io(scene),
        };
        if closed && model.signed_volume(&model.st.q) < 0.0 {
            model.orientation = -1.0;
        }
        Ok(model)
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.set.len()
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.n_nodes
    }

    /// Number of free coordinates.
    pub fn n_free_coordinates(&self) -> usize {
        self.st.asm.dofs.n_free()
    }

    /// Position of node `k` in the committed state [m].
    pub fn node_position(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.st.q[k * NODE_DOFS..k * NODE_DOFS + 3])
    }

    fn element_positions(&self, e: usize, q: &[f64]) -> [Vector3<f64>; 4] {
        let d = self.positions.dofs(e);
        std::array::from_fn(|i| Vector3::new(q[d[3 * i]], q[d[3 * i + 1]], q[d[3 * i + 2]]))
    }

    /// `Σ volume_part` over the elements at full coordinates `q` [m3] (signed by the element
    /// normals).
    fn signed_volume(&self, q: &[f64]) -> f64 {
        (0..self.positions.len())
            .map(|e| volume_part(&self.element_positions(e, q)))
            .sum()
    }

    /// Enclosed volume [m3] of the committed state (a closed surface).
    pub fn volume(&self) -> f64 {
        self.orientation * self.signed_volume(&self.st.q)
    }

    fn node(q: &[f64], k: usize) -> Vector3<f64> {
        Vector3::new(q[k * NODE_DOFS], q[k * NODE_DOFS + 1], q[k * NODE_DOFS + 2])
    }

    fn ring_value(q: &[f64], nodes: &[usize], quantity: RingQuantity) -> f64 {
        let n = nodes.len().max(1) as f64;
        nodes
            .iter()
            .map(|&k| {
                let x = Self::node(q, k);
                match quantity {
                    RingQuantity::Radius => x.xy().norm(),
                    RingQuantity::Z => x.z,
                }
            })
            .sum::<f64>()
            / n
    }

    fn length_at(&self, q: &[f64]) -> f64 {
        match self.poles {
            Some((a, b)) => (Self::node(q, b) - Self::node(q, a)).norm(),
            None => (Self::ring_value(q, &self.ends.1, RingQuantity::Z)
                - Self::ring_value(q, &self.ends.0, RingQuantity::Z))
            .abs(),
        }
    }

    /// Kinetic energy [J] at full coordinates and rates.
    fn kinetic_energy_at(&self, q: &[f64], v: &[f64]) -> f64 {
        self.set.kinetic_energy(q, v, Some(&self.st.frames))
    }

    /// Gravity potential [J] relative to the origin: `−Q_gᵀ x` (the gravity load is constant).
    fn potential_energy_at(&self, q: &[f64]) -> f64 {
        -self
            .gravity_load
            .iter()
            .zip(q)
            .enumerate()
            .filter(|(i, _)| i % NODE_DOFS < 3)
            .map(|(_, (f, x))| f * x)
            .sum::<f64>()
    }

    /// Strain energy [J] at full coordinates.
    fn strain_energy_at(&self, q: &[f64]) -> f64 {
        self.set.strain_energy(q, Some(&self.st.frames))
    }

    fn value_at(&self, kind: Output, q: &[f64], v: &[f64]) -> f64 {
        match kind {
            Output::Probe { probe, quantity } => NodeMotion {
                q,
                v,
                acc: &self.st.acc,
                frames: &self.st.frames,
            }
            .probe(self.probes[probe].node, quantity, None),
            Output::Ring { probe, quantity } => {
                Self::ring_value(q, &self.ring_probes[probe], quantity)
            }
            Output::Volume => self.orientation * self.signed_volume(q),
            Output::Reaction { port, axis } => self.ports.force(self, port, axis),
            Output::Length => self.length_at(q),
            Output::Energy(k) => match k {
                EnergyKind::Kinetic => self.kinetic_energy_at(q, v),
                EnergyKind::Potential => self.potential_energy_at(q),
                EnergyKind::Strain => self.strain_energy_at(q),
                EnergyKind::Total => {
                    self.kinetic_energy_at(q, v)
                        + self.potential_energy_at(q)
                        + self.strain_energy_at(q)
                }
            },
        }
    }

    /// Time derivative of an output: probes analytically ([`NodeMotion::probe_rate`]), the
    /// others along the motion ([`rates::along_motion`]).
    fn output_rate(&self, kind: Output) -> Option<f64> {
        match kind {
            Output::Probe { probe, quantity } => NodeMotion {
                q: &self.st.q,
                v: &self.st.v,
                acc: &self.st.acc,
                frames: &self.st.frames,
            }
            .probe_rate(self.probes[probe].node, quantity, None),
            // d/dt of the stiffness part of the reaction, K_c v (inertia rates neglected)
            Output::Reaction { port, axis } => {
                Some(self.ports.force_rate(self, port, axis, &self.st.v))
            }
            _ => {
                let mut work = [Vec::new(), Vec::new()];
                Some(rates::along_motion(
                    &self.st.q,
                    &self.st.v,
                    &self.st.acc,
                    &mut work,
                    |q, v| self.value_at(kind, q, v),
                ))
            }
        }
    }

    fn input_signal(&mut self, input: usize) -> &mut InputSignal {
        match self.roles.inputs[input] {
            Input::Load { load, comp } => &mut self.loads[load].values[comp],
            Input::Pressure => &mut self.pressure,
            Input::Motion { port, component } => self.ports.signal_mut(port, component),
        }
    }

    /// A motion input needs the interface Jacobian for the extrapolated reactions.
    fn after_input(&mut self, input: usize) {
        if matches!(self.roles.inputs[input], Input::Motion { .. }) {
            self.update_interface();
        }
    }

    /// Computes the interface Jacobian of the motion ports at the committed state unless it
    /// is current ([`Ports::update_interface`]).
    fn update_interface(&mut self) {
        let mut ports = std::mem::take(&mut self.ports);
        ports.update_interface(self);
        self.ports = ports;
    }

    /// Calls `f(e, element, state, accelerations)` for every element that has a node in
    /// `nodes` (all if `None`), at the committed state.
    fn for_each_committed(
        &self,
        nodes: Option<&[bool]>,
        mut f: impl FnMut(usize, &TrapezoidShell, &crate::elements::ElementState<ELEMENT_DOFS>),
    ) {
        self.set.for_each_state(
            &self.st.q,
            &self.st.v,
            Some(&self.st.frames),
            |e, el, st| {
                if nodes.is_none_or(|n| self.set.element_dofs(e).iter().any(|&i| n[i / NODE_DOFS]))
                {
                    f(e, el, st);
                }
            },
        );
    }

    /// Marks the nodes of the full coordinates `coords`.
    fn node_mask(&self, coords: &[usize]) -> Vec<bool> {
        let mut mask = vec![false; self.n_nodes];
        for &i in coords {
            mask[i / NODE_DOFS] = true;
        }
        mask
    }

    /// Pressure load per unit pressure [N/Pa] at the full coordinates `coords` (along the
    /// outward normal of a closed surface), of the committed state.
    fn unit_pressure_load(&self, coords: &[usize], out: &mut [f64]) {
        let row: BTreeMap<usize, usize> = coords.iter().enumerate().map(|(k, &i)| (i, k)).collect();
        out.fill(0.0);
        let mut f = SVector::<f64, 12>::zeros();
        for e in 0..self.positions.len() {
            let d = self.positions.dofs(e);
            if !d.iter().any(|i| row.contains_key(i)) {
                continue;
            }
            pressure_into(
                &self.element_positions(e, &self.st.q),
                self.orientation,
                &mut f,
                None,
            );
            for (a, i) in d.iter().enumerate() {
                if let Some(&k) = row.get(i) {
                    out[k] += f[a];
                }
            }
        }
    }

    /// Residual and iteration matrix at time `t` [s] of the configuration in `self.st.qw`, rates
    /// in `self.st.vw`, `self.st.aw`; the stiffness part of the iteration matrix is scaled by
    /// `k_scale`.
    fn assemble(
        &mut self,
        t: f64,
        lambda: f64,
        k_scale: f64,
        r: &mut [f64],
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        let mut fw = self.st.assemble_elements(
            &self.set,
            &self.loads,
            self.gravity * lambda,
            t,
            lambda,
            k_scale,
            &mut jac,
        );
        let p = self.pressure.at(t) * lambda * self.orientation;
        if p != 0.0 {
            let (mut f, mut k) = (SVector::<f64, 12>::zeros(), SMatrix::<f64, 12, 12>::zeros());
            for e in 0..self.positions.len() {
                let xe = self.element_positions(e, &self.st.qw);
                match jac.as_mut() {
                    Some((c, vals)) => {
                        pressure_into(&xe, p, &mut f, Some(&mut k));
                        self.positions
                            .add_matrix(e, &k, -c.stiffness * k_scale, vals);
                    }
                    None => pressure_into(&xe, p, &mut f, None),
                }
                self.positions.add_vector(e, &f, -1.0, &mut fw);
            }
        }
        self.st
            .finish_assembly(fw, r, jac.as_ref().map(|(_, vals)| &**vals))
    }
}

impl Model for Shell {
    /// The outline of every element through its four node positions.
    fn sketch(&self) -> crate::model::Sketch {
        let mut s = crate::model::Sketch::new(format!(
            "{} seed-004 trapezoidal shell elements, {} nodes with position and orientation",
            self.n_elements(),
            self.n_nodes()
        ));
        for e in 0..self.positions.len() {
            let c = self.element_positions(e, &self.st.q);
            s.line([c[0], c[1], c[2], c[3], c[0]]);
        }
        s
    }

    fn set_input(&mut self, input: usize, value: f64) {
        let t = self.st.t;
        self.input_signal(input).set(value, t);
        self.after_input(input);
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
        self.after_input(input);
        Ok(())
    }

    fn output(&self, output: usize) -> f64 {
        self.value_at(self.roles.outputs[output], &self.st.q, &self.st.v)
    }

    fn output_derivative(&self, output: usize) -> Option<f64> {
        self.output_rate(self.roles.outputs[output])
    }

    /// Reactions: `−K_int` for the port positions (times `τ` for the velocities,
    /// [`Ports::force_input_derivative`]) and the pressure load at the group's nodes per unit
    /// pressure; no other input reaches a reaction (loads on port nodes are refused), and the
    /// other outputs are of the committed state.
    fn output_input_derivative(&mut self, output: usize, input: usize) -> Option<f64> {
        let Output::Reaction { port, axis } = self.roles.outputs[output] else {
            return None;
        };
        Some(match self.roles.inputs[input] {
            Input::Motion {
                port: p2,
                component,
            } => {
                let mut ports = std::mem::take(&mut self.ports);
                let d = ports.force_input_derivative(self, port, axis, p2, component);
                self.ports = ports;
                d
            }
            Input::Pressure => {
                let members = self.ports.channel_members(port, axis);
                let mut f = vec![0.0; members.len()];
                self.unit_pressure_load(members, &mut f);
                f.iter().sum()
            }
            Input::Load { .. } => 0.0,
        })
    }

    fn hold_prescribed_motion(&mut self, hold: bool) {
        self.ports.hold(hold);
    }

    fn begin_communication_step(&mut self, t0: f64, t1: f64) {
        self.ports.begin_communication_step(t0, t1);
    }

    fn accept(&mut self, state: &mut DynState) {
        let (ports, t) = (&self.ports, state.t);
        self.st
            .accept(state, |q, v, a| ports.apply(t, 1.0, q, v, a));
        self.port_pressure = self.pressure.at(self.st.t);
        self.ports.commit(self.st.t, &self.st.q, &self.st.v);
    }

    fn free_state(&self, q: &mut [f64], v: &mut [f64]) {
        self.st.free_state(q, v);
    }

    fn constant_mass(&self) -> bool {
        true
    }

    /// Committed time, coordinates, velocities and accelerations, nodal orientations and input
    /// signals.
    fn save(&self, w: &mut StateWriter) -> Result<(), String> {
        self.st.save(w);
        for l in &self.loads {
            l.save(w);
        }
        self.pressure.save(w);
        w.f64(self.port_pressure);
        self.ports.save(w);
        Ok(())
    }

    fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        self.st.restore(r)?;
        for l in &mut self.loads {
            l.restore(r).map_err(e)?;
        }
        self.pressure = InputSignal::restore(r).map_err(e)?;
        self.port_pressure = r.f64().map_err(e)?;
        self.ports.restore(r).map_err(e)?;
        self.ports.commit(self.st.t, &self.st.q, &self.st.v);
        self.update_interface();
        Ok(())
    }
}

impl MechanicalSystem for Shell {
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
        self.ports.apply(
            t,
            load_factor,
            Some(&mut self.st.qw),
            Some(&mut self.st.vw),
            Some(&mut self.st.aw),
        );
        self.assemble(t, load_factor, 1.0, r, jac)
    }

    /// Implicit midpoint rule: the residual at the mean configuration `(q_a + q_b)/2` (in the
    /// chart of the stored orientations) with the mean velocity and acceleration the
    /// integrator passes, as the 3D beam does (second order, not exactly energy conserving
    /// for the shell's non-quadratic strain energy).
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
        let t_mid = 0.5 * (t_a + t_b);
        self.ports.apply_mean(t_a, t_b, &mut self.st.qw);
        self.ports.apply(
            t_mid,
            1.0,
            None,
            Some(&mut self.st.vw),
            Some(&mut self.st.aw),
        );
        self.assemble(t_mid, 1.0, 0.5, r, jac)
    }

    fn rebase(&mut self, q: &mut [f64]) {
        self.st.rebase(q);
    }
}

/// The rows and free–free matrix of the shell at its motion ports (the position coordinates of
/// the groups' nodes), at the committed state.
impl PortHost for Shell {
    fn free_index(&self, full: usize) -> Option<usize> {
        self.st.asm.dofs.free_index(full)
    }

    /// `M a + f_int − Q_g − f_pressure` at the coordinates, from the elements at their nodes
    /// (no point or line load acts on a port node: `Shell::build` refuses them).
    fn port_residual(&self, coords: &[usize], out: &mut [f64]) {
        let row: BTreeMap<usize, usize> = coords.iter().enumerate().map(|(k, &i)| (i, k)).collect();
        let mask = self.node_mask(coords);
        out.fill(0.0);
        let mut fe = SVector::<f64, ELEMENT_DOFS>::zeros();
        self.for_each_committed(Some(&mask), |e, el, st| {
            let ae = self.set.gather(e, &self.st.acc);
            el.residual_into(st, &ae, &self.gravity, &mut fe, None);
            for (a, i) in self.set.element_dofs(e).iter().enumerate() {
                if let Some(&k) = row.get(i) {
                    out[k] += fe[a];
                }
            }
        });
        let p = self.pressure.at(self.st.t);
        if p != 0.0 {
            let mut unit = vec![0.0; coords.len()];
            self.unit_pressure_load(coords, &mut unit);
            for (o, u) in out.iter_mut().zip(unit) {
                *o -= p * u;
            }
        }
    }

    /// Rows of the elements at the nodes (`K_T + c_m M`, element after element), then of the
    /// follower pressure's tangent at the committed pressure.
    fn port_rows(&self, coords: &[usize], c_m: f64, add: &mut dyn FnMut(usize, usize, f64)) {
        let row: BTreeMap<usize, usize> = coords.iter().enumerate().map(|(k, &i)| (i, k)).collect();
        let mask = self.node_mask(coords);
        let coeffs = JacobianCoeffs {
            mass: c_m,
            damping: 0.0,
            stiffness: 1.0,
        };
        let (mut fe, mut me) = (
            SVector::<f64, ELEMENT_DOFS>::zeros(),
            SMatrix::<f64, ELEMENT_DOFS, ELEMENT_DOFS>::zeros(),
        );
        self.for_each_committed(Some(&mask), |e, el, st| {
            let ae = self.set.gather(e, &self.st.acc);
            el.residual_into(st, &ae, &self.gravity, &mut fe, Some((coeffs, &mut me)));
            let dofs = self.set.element_dofs(e);
            for (a, i) in dofs.iter().enumerate() {
                if let Some(&k) = row.get(i) {
                    for (j, &col) in dofs.iter().enumerate() {
                        add(k, col, me[(a, j)]);
                    }
                }
            }
        });
        let p = self.port_pressure * self.orientation;
        if p != 0.0 {
            let (mut f, mut k) = (SVector::<f64, 12>::zeros(), SMatrix::<f64, 12, 12>::zeros());
            for e in 0..self.positions.len() {
                let d = self.positions.dofs(e);
                if !d.iter().any(|i| row.contains_key(i)) {
                    continue;
                }
                pressure_into(
                    &self.element_positions(e, &self.st.q),
                    p,
                    &mut f,
                    Some(&mut k),
                );
                for (a, i) in d.iter().enumerate() {
                    if let Some(&r) = row.get(i) {
                        for (j, &col) in d.iter().enumerate() {
                            add(r, col, -k[(a, j)]);
                        }
                    }
                }
            }
        }
    }

    fn free_matrix(&mut self, c_m: f64, vals: &mut [f64]) {
        self.st.qw.copy_from_slice(&self.st.q);
        self.st.vw.copy_from_slice(&self.st.v);
        self.st.aw.copy_from_slice(&self.st.acc);
        let coeffs = JacobianCoeffs {
            mass: c_m,
            damping: 0.0,
            stiffness: 1.0,
        };
        let mut r = vec![0.0; self.st.asm.dofs.n_free()];
        let input = std::mem::replace(
            &mut self.pressure,
            InputSignal::constant(self.port_pressure),
        );
        // a non-finite state has no interface matrix worth keeping: the values say so
        let _ = self.assemble(self.st.t, 1.0, 1.0, &mut r, Some((coeffs, vals)));
        self.pressure = input;
    }
}
