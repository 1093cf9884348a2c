//! The TOML scene format (deserialized with serde; unknown keys are errors).
//!
//! Table and key names mirror the FMU variable names: `[material] E` becomes the parameter
//! `material.E`, `[[loads]] name = "load"` the inputs `load.fx`, `load.fy`, and so on.

use serde::Deserialize;

/// A whole scene file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// FMU identity.
    pub fmu: FmuSection,
    /// Default experiment written into the model description.
    #[serde(default)]
    pub experiment: ExperimentSection,
    /// Element type and options (the type decides the scene kind).
    pub element: ElementSection,
    /// Mesh (beam scenes).
    #[serde(default)]
    pub mesh: Option<MeshSection>,
    /// Geometry of the body (beam scenes).
    #[serde(default)]
    pub geometry: Option<GeometrySection>,
    /// Material (continuum elements).
    #[serde(default)]
    pub material: Option<MaterialSection>,
    /// Section properties (co-rotational 3D beams).
    #[serde(default)]
    pub section: Option<SectionTable>,
    /// Reference centre line (co-rotational 3D beams).
    #[serde(default)]
    pub centreline: Option<CentrelineSection>,
    /// Gravity (omit for none: then no gravity parameters are exposed).
    #[serde(default)]
    pub gravity: Option<GravitySection>,
    /// Solver settings (all exposed as `solver.*` parameters).
    #[serde(default)]
    pub solver: SolverSection,
    /// Supports.
    #[serde(default)]
    pub supports: Vec<SupportSpec>,
    /// Point loads: force inputs.
    #[serde(default)]
    pub loads: Vec<LoadSpec>,
    /// Probes: position/velocity outputs at points of the body.
    #[serde(default)]
    pub probes: Vec<ProbeSpec>,
    /// Motion ports: prescribed position/velocity inputs, reaction-force outputs.
    #[serde(default)]
    pub motions: Vec<MotionSpec>,
    /// Further outputs.
    #[serde(default)]
    pub outputs: OutputsSection,
    /// The belt of a belt-drive scene.
    #[serde(default)]
    pub belt: Option<BeltSection>,
    /// Belt–pulley contact of a belt-drive scene.
    #[serde(default)]
    pub contact: Option<ContactSection>,
    /// `[[pulley]]`: the pulleys of a belt-drive scene in the order the belt wraps them
    /// (counter-clockwise); the first is `pulley1`.
    #[serde(default)]
    pub pulley: Vec<PulleySpec>,
    /// Initial motion (omit: the body starts at rest).
    #[serde(default)]
    pub initial: Option<InitialSection>,
}

/// `[initial]`: a rigid initial motion of the whole body.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSection {
    /// Angular velocity about the body's first end (counter-clockwise) [rad/s]; exposed as the
    /// parameter `initial.angular_velocity`.
    #[serde(default)]
    pub angular_velocity: f64,
}

/// `[fmu]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FmuSection {
    /// `modelName` and `modelIdentifier` (file name of the shared library); letters, digits
    /// and underscores.
    pub model_name: String,
    /// Free text for the `description` attribute.
    #[serde(default)]
    pub description: String,
}

/// `[experiment]`: the DefaultExperiment.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExperimentSection {
    /// [s]
    #[serde(default)]
    pub start_time: f64,
    /// [s]
    #[serde(default = "default_stop_time")]
    pub stop_time: f64,
    /// Suggested communication step [s].
    #[serde(default = "default_step_size")]
    pub step_size: f64,
}

fn default_stop_time() -> f64 {
    1.0
}
fn default_step_size() -> f64 {
    1e-3
}

impl Default for ExperimentSection {
    fn default() -> Self {
        Self {
            start_time: 0.0,
            stop_time: default_stop_time(),
            step_size: default_step_size(),
        }
    }
}

/// Element families known to flexfmu.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ElementType {
    /// Seed 000: linear shear-deformable 2D ANCF beam (4 coordinates per node).
    #[serde(rename = "ancf_shear_2d")]
    AncfShear2d,
    /// Seed 003: two-node co-rotational 3D beam (6 coordinates per node).
    #[serde(rename = "corotational_3d")]
    Corotational3d,
    /// Gradient-deficient ANCF cable (r, r' per node, cubic Hermite): belts.
    #[serde(rename = "ancf_cable_2d")]
    AncfCable2d,
}

impl ElementType {
    /// Whether the element lives in 3D (positions x, y, z).
    pub fn is_3d(&self) -> bool {
        matches!(self, Self::Corotational3d)
    }
}

/// `[element]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElementSection {
    /// Element family.
    #[serde(rename = "type")]
    pub kind: ElementType,
    /// 1 = original 1x1 shear integration, 2 = the 1x2 fix (default).
    #[serde(default = "default_shear_rule")]
    pub shear_rule: i32,
    /// 1 = Eq. 12 (default), 2 = Lamé form of Eqs. 10–11.
    #[serde(default = "default_strain_energy")]
    pub strain_energy: i32,
    /// Shear correction factor k_s of Eq. 12.
    #[serde(default = "default_shear_coefficient")]
    pub shear_coefficient: f64,
    /// Co-rotational beams: 1 = Euler–Bernoulli, 2 = Timoshenko local stiffness (default 2).
    #[serde(default)]
    pub theory: Option<i32>,
    /// Co-rotational beams: 1 = three lumped masses, 2 = consistent (default 1).
    #[serde(default)]
    pub mass: Option<i32>,
}

fn default_shear_rule() -> i32 {
    2
}
fn default_strain_energy() -> i32 {
    1
}
fn default_shear_coefficient() -> f64 {
    5.0 / 6.0
}

/// `[mesh]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSection {
    /// Number of elements along the body.
    pub n_elements: i64,
}

/// `[geometry]`: a straight rectangular beam.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeometrySection {
    /// [m]
    pub length: f64,
    /// Out-of-plane width [m].
    pub width: f64,
    /// Height [m].
    pub height: f64,
    /// Position of the first end [m] (not a parameter).
    #[serde(default)]
    pub origin: [f64; 2],
    /// Direction of the axis, counter-clockwise from +x [deg] (not a parameter).
    #[serde(default)]
    pub angle_deg: f64,
}

/// `[material]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct MaterialSection {
    /// Young's modulus [Pa].
    pub E: f64,
    /// Poisson's ratio [1].
    pub nu: f64,
    /// Density [kg/m3].
    pub rho: f64,
}

/// `[gravity]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GravitySection {
    /// [m/s2]
    #[serde(default)]
    pub x: f64,
    /// [m/s2]
    #[serde(default)]
    pub y: f64,
    /// [m/s2] (3D scenes only)
    #[serde(default)]
    pub z: f64,
}

/// `[section]`: section properties of a co-rotational beam, as beam users give them (the
/// names are the FMU parameters `section.EA`, ...).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct SectionTable {
    /// Axial stiffness [N].
    pub EA: f64,
    /// Shear stiffness (with shear coefficient) for deflection along local y [N].
    pub GAy: f64,
    /// Shear stiffness for deflection along local z [N].
    pub GAz: f64,
    /// Torsional stiffness [N m2].
    pub GJ: f64,
    /// Bending stiffness about local y [N m2].
    pub EIy: f64,
    /// Bending stiffness about local z [N m2].
    pub EIz: f64,
    /// Mass per length [kg/m].
    pub rhoA: f64,
    /// Polar rotary inertia per length [kg m].
    pub rhoJx: f64,
    /// Rotary inertia per length about local y [kg m].
    pub rhoIy: f64,
    /// Rotary inertia per length about local z [kg m].
    pub rhoIz: f64,
}

/// `[centreline]`: the reference centre line of a 3D beam, piece by piece from `start`
/// (not parameters).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CentrelineSection {
    /// Start point [m].
    #[serde(default)]
    pub start: [f64; 3],
    /// Hint for the local z axis of the sections: `e2 = hint × e1/|…|`, `e3 = e1 × e2`
    /// (default global z; global y where an element is parallel to the hint).
    #[serde(default)]
    pub section_z: Option<[f64; 3]>,
    /// The pieces, in order.
    pub segments: Vec<SegmentSpec>,
}

/// `[[centreline.segments]]`: a straight piece (`length`) or a circular arc (`radius`,
/// `angle_deg`, `bend_axis`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpec {
    /// Start tangent (required for the first piece; default: the end tangent of the previous
    /// piece).
    #[serde(default)]
    pub direction: Option<[f64; 3]>,
    /// Length of a straight piece [m].
    #[serde(default)]
    pub length: Option<f64>,
    /// Radius of an arc [m].
    #[serde(default)]
    pub radius: Option<f64>,
    /// Angle of an arc [deg].
    #[serde(default)]
    pub angle_deg: Option<f64>,
    /// Axis about which an arc turns its tangent (right-hand rule), not parallel to it.
    #[serde(default)]
    pub bend_axis: Option<[f64; 3]>,
}

/// Integer code or name of a choice parameter.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum Choice {
    /// The integer code of the FMU parameter.
    Code(i64),
    /// A name, e.g. `"newmark"`.
    Name(String),
}

/// `[solver]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSection {
    /// Solve the static equilibrium during initialization.
    #[serde(default)]
    pub static_equilibrium: bool,
    /// Time integrator: `"generalized_alpha"` (1), `"newmark"` (2), `"midpoint"` (3) or
    /// `"central_difference"` (4).
    #[serde(default = "default_integrator")]
    pub integrator: Choice,
    /// Spectral radius at infinite frequency for generalized-alpha, in [0, 1].
    #[serde(default = "default_rho_inf")]
    pub rho_inf: f64,
    /// Largest internal step [s].
    #[serde(default = "default_max_step")]
    pub max_step: f64,
    /// Newton tolerance on the scaled increment [1].
    #[serde(default = "default_newton_tolerance")]
    pub newton_tolerance: f64,
    /// Newton iterations per solve before the step or load increment is cut.
    #[serde(default = "default_max_iterations")]
    pub max_iterations: i64,
    /// Initial number of load increments of the static solve.
    #[serde(default = "default_load_steps")]
    pub load_steps: i64,
    /// `"auto"` (0), `"banded"` (1) or `"sparse_lu"` (2).
    #[serde(default = "default_linear_solver")]
    pub linear_solver: Choice,
    /// `"full"` (1) or `"modified"` (2) Newton.
    #[serde(default = "default_newton")]
    pub newton: Choice,
    /// Local error tolerance of adaptive substeps (0: fixed substeps).
    #[serde(default)]
    pub tolerance: f64,
}

fn default_newton() -> Choice {
    Choice::Name("modified".into())
}

fn default_integrator() -> Choice {
    Choice::Name("generalized_alpha".into())
}
fn default_rho_inf() -> f64 {
    0.9
}
fn default_max_step() -> f64 {
    1e-3
}
fn default_newton_tolerance() -> f64 {
    1e-10
}
fn default_max_iterations() -> i64 {
    25
}
fn default_load_steps() -> i64 {
    1
}
fn default_linear_solver() -> Choice {
    Choice::Name("auto".into())
}

impl Default for SolverSection {
    fn default() -> Self {
        Self {
            static_equilibrium: false,
            integrator: default_integrator(),
            rho_inf: default_rho_inf(),
            max_step: default_max_step(),
            newton_tolerance: default_newton_tolerance(),
            max_iterations: default_max_iterations(),
            load_steps: default_load_steps(),
            linear_solver: default_linear_solver(),
            newton: default_newton(),
            tolerance: 0.0,
        }
    }
}

/// Kind of support.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SupportKind {
    /// Position and gradient fixed.
    Clamp,
    /// Position fixed.
    Pin,
    /// One position component fixed (`fixed = "x"` or `"y"`).
    Roller,
}

/// A global direction.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    /// Global x.
    X,
    /// Global y.
    Y,
}

/// `[[supports]]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SupportSpec {
    /// Clamp, pin or roller.
    pub kind: SupportKind,
    /// Location as a fraction of the length, in [0, 1]; must fall on a node.
    pub at: f64,
    /// For a roller: the fixed direction.
    #[serde(default)]
    pub fixed: Option<Axis>,
}

/// `[[loads]]`: a force input at a point of the centre line.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// Variable prefix (`<name>.fx`, `<name>.fy`).
    pub name: String,
    /// Location as a fraction of the length, in [0, 1].
    pub at: f64,
    /// Start value of the x force [N].
    #[serde(default)]
    pub fx: f64,
    /// Start value of the y force [N].
    #[serde(default)]
    pub fy: f64,
    /// Start value of the z force [N] (3D scenes).
    #[serde(default)]
    pub fz: f64,
    /// Start value of the moment about x [N m] (3D scenes).
    #[serde(default)]
    pub mx: f64,
    /// Start value of the moment about y [N m] (3D scenes).
    #[serde(default)]
    pub my: f64,
    /// Start value of the moment about z [N m] (3D scenes).
    #[serde(default)]
    pub mz: f64,
    /// 3D scenes: `false` (default) = fixed-direction (dead) load, components in the global
    /// frame; `true` = follower load, components given in the global frame of the reference
    /// configuration and rotating with the node.
    #[serde(default)]
    pub follower: bool,
}

/// `[[motions]]`: a node whose position is prescribed by inputs (motion in, force out).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionSpec {
    /// Variable prefix: inputs `<name>.x`, `<name>.y` [m], `<name>.vx`, `<name>.vy` [m/s];
    /// outputs `<name>.fx`, `<name>.fy` [N].
    pub name: String,
    /// Location as a fraction of the length, in [0, 1]; must fall on a node.
    pub at: f64,
}

/// Quantities a probe can output.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ProbeQuantity {
    /// Position x [m].
    X,
    /// Position y [m].
    Y,
    /// Velocity x [m/s].
    Vx,
    /// Velocity y [m/s].
    Vy,
    /// Position z [m] (3D).
    Z,
    /// Velocity z [m/s] (3D).
    Vz,
    /// Rotation vector of the node from its reference orientation, x component [rad] (3D,
    /// principal value, |r| ≤ π).
    Rx,
    /// Rotation vector, y component [rad] (3D).
    Ry,
    /// Rotation vector, z component [rad] (3D).
    Rz,
    /// Direction cosine of the beam axis with global x [1] (3D).
    Tx,
    /// Direction cosine of the beam axis with global y [1] (3D).
    Ty,
    /// Direction cosine of the beam axis with global z [1] (3D).
    Tz,
    /// Angular velocity, global x component [rad/s] (3D).
    Wx,
    /// Angular velocity, global y component [rad/s] (3D).
    Wy,
    /// Angular velocity, global z component [rad/s] (3D).
    Wz,
}

impl ProbeQuantity {
    /// Whether the quantity exists in planar scenes.
    pub fn is_planar(&self) -> bool {
        matches!(self, Self::X | Self::Y | Self::Vx | Self::Vy)
    }
}

/// `[[probes]]`: outputs at a point of the centre line.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeSpec {
    /// Variable prefix (`<name>.x`, ...).
    pub name: String,
    /// Location as a fraction of the length, in [0, 1].
    pub at: f64,
    /// Which quantities (default: x and y).
    #[serde(default = "default_probe_quantities")]
    pub outputs: Vec<ProbeQuantity>,
}

fn default_probe_quantities() -> Vec<ProbeQuantity> {
    vec![ProbeQuantity::X, ProbeQuantity::Y]
}

/// `[outputs]`
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputsSection {
    /// Expose `energy.kinetic`, `energy.potential`, `energy.strain`, `energy.total` [J]
    /// (belt drives also `energy.input_work`, `energy.dissipated`).
    #[serde(default)]
    pub energy: bool,
    /// Belt drives: number of equally spaced belt points exposed as `belt.point[i].x/y`
    /// (default: `belt.n_elements`, i.e. the nodes).
    #[serde(default)]
    pub belt_points: Option<i64>,
}

/// `[belt]`: the belt as datasheets give it.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct BeltSection {
    /// Axial stiffness [N].
    pub EA: f64,
    /// Bending stiffness [N m2].
    pub EI: f64,
    /// Mass per unit length [kg/m].
    pub mass_per_length: f64,
    /// Thickness [m]: the centre line runs at pulley radius + thickness/2.
    pub thickness: f64,
    /// Span tension at rest [N].
    pub pretension: f64,
    /// Number of belt elements.
    pub n_elements: i64,
    /// Axial material damping [N s].
    #[serde(default)]
    pub damping_axial: f64,
    /// Bending material damping [N m2 s].
    #[serde(default)]
    pub damping_bending: f64,
    /// Cable integration rule: `"full"` (1), `"reduced"` (2) or `"mixed"` (3).
    #[serde(default = "default_belt_integration")]
    pub integration: Choice,
}

fn default_belt_integration() -> Choice {
    Choice::Name("full".into())
}

/// `[contact]`: belt–pulley contact; stiffness and damping 0 mean "derived from the belt".
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSection {
    /// Coulomb friction coefficient [1].
    pub mu: f64,
    /// Normal penalty stiffness per unit belt length [N/m2] (0: automatic).
    #[serde(default)]
    pub stiffness: f64,
    /// Normal damping per unit belt length [N s/m2] (0: automatic).
    #[serde(default)]
    pub damping: f64,
    /// Tangential (bristle) stiffness per unit belt length [N/m2] (0: automatic).
    #[serde(default)]
    pub friction_stiffness: f64,
    /// Contact points per belt element.
    #[serde(default = "default_contact_points")]
    pub points_per_element: i64,
}

fn default_contact_points() -> i64 {
    4
}

/// How a pulley moves.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum PulleyMode {
    /// Angle and angular velocity are inputs; the belt torque is an output.
    Driven,
    /// Rigid body with inertia inside the FMU; an input torque drives it.
    Free,
}

/// `[[pulley]]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PulleySpec {
    /// Centre [m] (for two pulleys the distance is the parameter `pulleys.center_distance`,
    /// along the direction given here).
    pub center: [f64; 2],
    /// Radius [m] (the belt's inner face rests on it).
    pub radius: f64,
    /// Driven or free.
    pub mode: PulleyMode,
    /// Free pulleys: moment of inertia [kg m2].
    #[serde(default)]
    pub inertia: Option<f64>,
    /// Free pulleys: viscous bearing damping [N m s/rad].
    #[serde(default)]
    pub damping: f64,
    /// Start value of the input `pulleyN.omega` (driven) [rad/s].
    #[serde(default)]
    pub omega: f64,
    /// Start value of the input `pulleyN.torque_in` (free) [N m].
    #[serde(default)]
    pub torque_in: f64,
}
