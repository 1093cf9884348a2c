//! Kind `shell`: a shell of seed-004 trapezoidal elements (Pogorelov & Rodikov 2021): a flat
//! rectangular or trapezoidal plate (`[plate]`) or a surface of revolution about the z axis
//! from a meridian of straight and circular pieces (`[meridian]`), with supports on edges,
//! rings and points, point loads, line loads along an edge or ring, a uniform follower
//! pressure, probes, ring outputs, the enclosed volume and energies. Scene tables here,
//! declarations in [`scene`], the model in [`model`].

pub mod model;
pub mod scene;

use crate::meshers::plate::PlateEdge;
use crate::scene::tables::{
    ExperimentSection, FmuSection, Gravity3d, MaterialSection, ProbeQuantity, SolverSection,
};
use model::Shell;
use serde::Deserialize;

body_kind! {
    /// The kind (registry entry).
    ShellKind {
        tables: ShellScene,
        model: Shell,
        name: "shell",
        summary: "shell of seed-004 trapezoidal elements: plates and surfaces of revolution",
        validation: include_str!("validation.txt"),
        legacy: |_t| None,
    }
}

/// A `shell` scene file (`kind = "shell"` is required).
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct ShellScene {
    /// `kind = "shell"`.
    #[serde(default)]
    pub kind: Option<String>,
    /// FMU identity.
    pub fmu: FmuSection,
    /// Default experiment.
    #[serde(default)]
    pub experiment: ExperimentSection,
    /// Solver settings.
    #[serde(default)]
    pub solver: SolverSection,
    /// Material (`material.E`, `material.nu`, `material.rho`).
    pub material: MaterialSection,
    /// Shell properties (`shell.thickness`).
    pub shell: ShellSection,
    /// Element options.
    #[serde(default)]
    pub element: ShellElement,
    /// Mesh sizes: `n_x`, `n_y` for a plate, `n_circumferential`, `n_meridional` for a surface
    /// of revolution.
    pub mesh: ShellMesh,
    /// A flat plate (give this or `[meridian]`).
    #[serde(default)]
    pub plate: Option<PlateSection>,
    /// A surface of revolution (give this or `[plate]`).
    #[serde(default)]
    pub meridian: Option<MeridianSection>,
    /// Supports of the plate edges (default free); parameters `support.x0`, ...
    #[serde(default)]
    pub support: Option<EdgeSupports>,
    /// Supports of rings of a surface of revolution.
    #[serde(default)]
    pub ring_supports: Vec<RingSupport>,
    /// Supports at single nodes.
    #[serde(default)]
    pub point_supports: Vec<PointSupport>,
    /// Gravity (omit for none: then no gravity parameters are exposed).
    #[serde(default)]
    pub gravity: Option<Gravity3d>,
    /// Point loads: force and moment inputs at a node.
    #[serde(default)]
    pub loads: Vec<PointLoad>,
    /// Line loads: a total force and moment spread along a plate edge or a ring.
    #[serde(default)]
    pub line_loads: Vec<LineLoad>,
    /// Uniform pressure on the whole surface (follower load).
    #[serde(default)]
    pub pressure: Option<PressureSection>,
    /// Motion ports: a plate edge, a ring or a node moved rigidly in translation by the
    /// master (position and velocity inputs, reaction-force outputs).
    #[serde(default)]
    pub motions: Vec<ShellMotion>,
    /// Probes at nodes.
    #[serde(default)]
    pub probes: Vec<PointProbe>,
    /// Outputs of rings of a surface of revolution.
    #[serde(default)]
    pub ring_probes: Vec<RingProbe>,
    /// Optional outputs: energies, enclosed volume, length.
    #[serde(default)]
    pub outputs: ShellOutputs,
}

/// `[shell]`: section properties.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct ShellSection {
    /// Thickness [m] (parameter `shell.thickness`).
    pub thickness: f64,
}

/// `[element]`: the options of the seed-004 element.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct ShellElement {
    /// Bending shape functions: 2 = V2 (12-DOF rectangle functions, default), 1 = V1 (products
    /// of beam Hermite polynomials). Parameter `element.bending`.
    #[serde(default = "default_bending")]
    pub bending: i64,
    /// Include the geometric (initial-stress) stiffness. Parameter
    /// `element.geometric_stiffness`.
    #[serde(default = "default_geometric_stiffness")]
    pub geometric_stiffness: bool,
    /// Drilling stiffness as a ratio of the membrane shear stiffness `G h` [1]. Parameter
    /// `element.drilling_stiffness`.
    #[serde(default = "default_drilling")]
    pub drilling_stiffness: f64,
}

fn default_bending() -> i64 {
    2
}
/// On by default: measured, it lets much coarser meshes reach the same large-deflection
/// accuracy (README, "The seed-004 element") for about 1.7 times the cost of a tangent.
fn default_geometric_stiffness() -> bool {
    true
}
fn default_drilling() -> f64 {
    1e-3
}

impl Default for ShellElement {
    fn default() -> Self {
        Self {
            bending: default_bending(),
            geometric_stiffness: default_geometric_stiffness(),
            drilling_stiffness: default_drilling(),
        }
    }
}

/// `[mesh]` of a shell.
#[derive(Clone, Debug, Default, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct ShellMesh {
    /// Plate: elements along x.
    #[serde(default)]
    pub n_x: Option<i64>,
    /// Plate: element rows along y.
    #[serde(default)]
    pub n_y: Option<i64>,
    /// Surface of revolution: elements around a ring.
    #[serde(default)]
    pub n_circumferential: Option<i64>,
    /// Surface of revolution: element rings along the meridian.
    #[serde(default)]
    pub n_meridional: Option<i64>,
}

/// `[plate]`: a flat plate in the x-y plane from the origin (not parameters).
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct PlateSection {
    /// Length of the bottom side (y = 0) along x [m].
    pub length_x: f64,
    /// Height along y [m].
    pub length_y: f64,
    /// Length of the top side (y = `length_y`) for an isosceles trapezoid [m] (default
    /// `length_x`: a rectangle).
    #[serde(default)]
    pub width_top: Option<f64>,
}

/// `[meridian]`: the meridian in the r-z plane, piece by piece from `start` (not parameters).
/// The surface is swept about the global z axis.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct MeridianSection {
    /// Start point `[r, z]` [m].
    pub start: [f64; 2],
    /// The pieces, in order.
    pub pieces: Vec<MeridianPieceSpec>,
}

/// `[[meridian.pieces]]`: a straight piece (`length`) or a circular arc (`radius`,
/// `angle_deg`; positive angles turn counter-clockwise in the r-z plane, from +r towards +z).
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct MeridianPieceSpec {
    /// Start direction `[dr, dz]` (required for the first piece; default: the end direction
    /// of the previous piece).
    #[serde(default)]
    pub direction: Option<[f64; 2]>,
    /// Length of a straight piece [m].
    #[serde(default)]
    pub length: Option<f64>,
    /// Radius of an arc [m].
    #[serde(default)]
    pub radius: Option<f64>,
    /// Signed angle of an arc [deg].
    #[serde(default)]
    pub angle_deg: Option<f64>,
}

/// A support condition.
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SupportCondition {
    /// Nothing fixed (parameter code 0).
    #[default]
    Free,
    /// Translations fixed (code 1).
    SimplySupported,
    /// Translations and rotations fixed (code 2).
    Clamped,
}

impl SupportCondition {
    /// The Integer code of the support parameters.
    pub fn code(self) -> i32 {
        match self {
            Self::Free => 0,
            Self::SimplySupported => 1,
            Self::Clamped => 2,
        }
    }

    /// The condition of a code (codes above 2 clamp, below 1 free).
    pub fn from_code(c: i32) -> Self {
        match c {
            ..=0 => Self::Free,
            1 => Self::SimplySupported,
            _ => Self::Clamped,
        }
    }

    /// Number of the node's coordinates fixed (the first ones: translations, then rotations).
    pub fn n_fixed(self) -> usize {
        match self {
            Self::Free => 0,
            Self::SimplySupported => 3,
            Self::Clamped => 6,
        }
    }
}

/// `[support]`: the condition of each plate edge (defaults of the parameters `support.x0`,
/// `support.x1`, `support.y0`, `support.y1`).
#[derive(Clone, Debug, Default, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct EdgeSupports {
    /// The left edge.
    #[serde(default)]
    pub x0: SupportCondition,
    /// The right edge.
    #[serde(default)]
    pub x1: SupportCondition,
    /// The bottom edge (y = 0).
    #[serde(default)]
    pub y0: SupportCondition,
    /// The top edge.
    #[serde(default)]
    pub y1: SupportCondition,
}

impl EdgeSupports {
    /// The condition of an edge.
    pub fn of(&self, e: PlateEdge) -> SupportCondition {
        match e {
            PlateEdge::X0 => self.x0,
            PlateEdge::X1 => self.x1,
            PlateEdge::Y0 => self.y0,
            PlateEdge::Y1 => self.y1,
        }
    }
}

/// A ring of a surface of revolution: `"first"`, `"last"` or the arc length along the
/// meridian from its start [m].
#[derive(Clone, Debug, Deserialize, serde::Serialize, PartialEq)]
#[serde(untagged)]
pub enum RingAt {
    /// Arc length from the start of the meridian [m].
    Arc(f64),
    /// `"first"` or `"last"`.
    Name(String),
}

/// `[[ring_supports]]`: a ring of a surface of revolution held.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct RingSupport {
    /// The ring.
    pub ring: RingAt,
    /// `"clamped"` or `"simply_supported"`.
    pub kind: SupportCondition,
}

/// `[[point_supports]]`: one node held.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct PointSupport {
    /// The node's position `[x, y, z]` (or `[x, y]` on a plate) [m].
    pub at: Vec<f64>,
    /// `"clamped"` or `"simply_supported"`.
    pub kind: SupportCondition,
}

/// `[[loads]]`: force and moment inputs at a node.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct PointLoad {
    /// Variable prefix (`<name>.fx`, ..., `<name>.mz`).
    pub name: String,
    /// The node's position `[x, y, z]` (or `[x, y]` on a plate) [m].
    pub at: Vec<f64>,
    /// Start value of the force x [N] (global axes, fixed direction).
    #[serde(default)]
    pub fx: f64,
    /// Start value of the force y [N].
    #[serde(default)]
    pub fy: f64,
    /// Start value of the force z [N].
    #[serde(default)]
    pub fz: f64,
    /// Start value of the moment about x [N m].
    #[serde(default)]
    pub mx: f64,
    /// Start value of the moment about y [N m].
    #[serde(default)]
    pub my: f64,
    /// Start value of the moment about z [N m].
    #[serde(default)]
    pub mz: f64,
}

impl PointLoad {
    /// `[fx, fy, fz, mx, my, mz]` start values.
    pub fn start(&self) -> [f64; 6] {
        [self.fx, self.fy, self.fz, self.mx, self.my, self.mz]
    }
}

impl LineLoad {
    /// `[fx, fy, fz, mx, my, mz]` start values.
    pub fn start(&self) -> [f64; 6] {
        [self.fx, self.fy, self.fz, self.mx, self.my, self.mz]
    }
}

/// `[[line_loads]]`: a total force and moment spread over the nodes of a plate edge or a ring
/// by the trapezoid rule (a uniform line load with that resultant).
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct LineLoad {
    /// Variable prefix (`<name>.fx`, ..., `<name>.mz`).
    pub name: String,
    /// A plate edge: `"x0"`, `"x1"`, `"y0"` or `"y1"`.
    #[serde(default)]
    pub edge: Option<PlateEdge>,
    /// A ring of a surface of revolution.
    #[serde(default)]
    pub ring: Option<RingAt>,
    /// Start value of the total force x [N] (global axes, fixed direction).
    #[serde(default)]
    pub fx: f64,
    /// Start value of the force y [N].
    #[serde(default)]
    pub fy: f64,
    /// Start value of the force z [N].
    #[serde(default)]
    pub fz: f64,
    /// Start value of the total moment about x [N m].
    #[serde(default)]
    pub mx: f64,
    /// Start value of the total moment about y [N m].
    #[serde(default)]
    pub my: f64,
    /// Start value of the total moment about z [N m].
    #[serde(default)]
    pub mz: f64,
}

/// `[[motions]]`: a motion port. The nodes of a plate edge, a ring or one node translate
/// rigidly with the prescribed position of the group's reference point (inputs `<name>.x`,
/// `.y`, `.z` [m], `.vx`, `.vy`, `.vz` [m/s]) and keep their reference orientation (a clamped
/// attachment); outputs `<name>.fx`, `.fy`, `.fz` [N] are the total force the shell exerts on
/// the driver. Give exactly one of `edge`, `ring`, `at`.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct ShellMotion {
    /// Variable prefix.
    pub name: String,
    /// A plate edge: `"x0"`, `"x1"`, `"y0"` or `"y1"` (reference point: the edge's midpoint).
    #[serde(default)]
    pub edge: Option<PlateEdge>,
    /// A ring of a surface of revolution (reference point: the ring's centre on the z axis).
    #[serde(default)]
    pub ring: Option<RingAt>,
    /// One node `[x, y, z]` (or `[x, y]` on a plate) [m] (reference point: the node).
    #[serde(default)]
    pub at: Option<Vec<f64>>,
}

/// `[pressure]`: a uniform pressure on the whole surface, acting along the surface normal and
/// following it (input `<name>.pressure` [Pa]). The normal is +z on a plate (before
/// deformation); on a closed surface of revolution it points outwards (positive = internal
/// pressure); on an open one it is the mesher's normal `dz e_r − dr e_z` for the meridian
/// direction `(dr, dz)` (outwards for a meridian running up, +z).
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct PressureSection {
    /// Variable prefix.
    pub name: String,
    /// Start value [Pa].
    #[serde(default)]
    pub value: f64,
}

/// `[[probes]]`: outputs at a node.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct PointProbe {
    /// Variable prefix (`<name>.x`, ...).
    pub name: String,
    /// The node's position `[x, y, z]` (or `[x, y]` on a plate) [m].
    pub at: Vec<f64>,
    /// Which quantities (default: x, y, z): x, y, z, vx, vy, vz, rx, ry, rz, wx, wy, wz.
    #[serde(default = "default_probe_outputs")]
    pub outputs: Vec<ProbeQuantity>,
}

fn default_probe_outputs() -> Vec<ProbeQuantity> {
    vec![ProbeQuantity::X, ProbeQuantity::Y, ProbeQuantity::Z]
}

/// A quantity of a ring.
#[derive(Clone, Copy, Debug, Deserialize, serde::Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum RingQuantity {
    /// Mean distance of the ring's nodes from the z axis [m].
    Radius,
    /// Mean z of the ring's nodes [m].
    Z,
}

/// `[[ring_probes]]`: outputs of a ring of a surface of revolution.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct RingProbe {
    /// Variable prefix (`<name>.radius`, `<name>.z`).
    pub name: String,
    /// The ring.
    pub ring: RingAt,
    /// Which quantities (default: radius).
    #[serde(default = "default_ring_outputs")]
    pub outputs: Vec<RingQuantity>,
}

fn default_ring_outputs() -> Vec<RingQuantity> {
    vec![RingQuantity::Radius]
}

/// `[outputs]` of a shell.
#[derive(Clone, Debug, Default, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct ShellOutputs {
    /// Expose `energy.kinetic`, `energy.potential`, `energy.strain`, `energy.total` [J].
    #[serde(default)]
    pub energy: bool,
    /// Expose `shell.volume` [m3], the volume enclosed by a closed surface of revolution.
    #[serde(default)]
    pub volume: bool,
    /// Expose `shell.length` [m]: the distance between the two nodes on the axis of a closed
    /// surface of revolution, else (open, or poles without an axis node) between the mean z of
    /// its first and last rings.
    #[serde(default)]
    pub length: bool,
}
