//! Scene tables shared by several body kinds (each kind's own tables live in its module,
//! [`crate::kinds`]); deserialized with serde, unknown keys are errors.
//!
//! Table and key names mirror the FMU variable names: `[material] E` becomes the parameter
//! `material.E`, `[[loads]] name = "load"` the inputs `load.fx`, `load.fy`, and so on.

use crate::units::Unit;
use serde::Deserialize;

/// `[initial]`: a rigid initial motion of the whole body.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSection {
    /// Angular velocity about the body's first end (counter-clockwise) [rad/s]; exposed as the
    /// parameter `initial.angular_velocity`.
    #[serde(default)]
    pub angular_velocity: f64,
}

/// `[material]`
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
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

/// `[fmu]`
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
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
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
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

/// `[mesh]`
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSection {
    /// Number of elements along the body.
    pub n_elements: i64,
}

/// Integer code or name of a choice parameter.
#[derive(Clone, Debug, Deserialize, serde::Serialize, PartialEq)]
#[serde(untagged)]
pub enum Choice {
    /// The integer code of the FMU parameter.
    Code(i64),
    /// A name, e.g. `"newmark"`.
    Name(String),
}

/// `[solver]`
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSection {
    /// Solve the static equilibrium during initialization.
    #[serde(default)]
    pub static_equilibrium: bool,
    /// Time integrator: `"generalized_alpha"` (1), `"newmark"` (2), `"midpoint"` (3),
    /// `"central_difference"` (4) or `"quasi_static"` (5, statically supported models only).
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
#[derive(Clone, Copy, Debug, Deserialize, serde::Serialize, PartialEq, Eq)]
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
#[derive(Clone, Copy, Debug, Deserialize, serde::Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    /// Global x.
    X,
    /// Global y.
    Y,
}

/// `[[supports]]`
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
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

/// `[[motions]]`: a node whose position is prescribed by inputs (motion in, force out).
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct MotionSpec {
    /// Variable prefix: inputs `<name>.x`, `<name>.y` [m], `<name>.vx`, `<name>.vy` [m/s];
    /// outputs `<name>.fx`, `<name>.fy` [N].
    pub name: String,
    /// Location as a fraction of the length, in [0, 1]; must fall on a node.
    pub at: f64,
}

/// Quantities a probe can output.
#[derive(Clone, Copy, Debug, Deserialize, serde::Serialize, PartialEq, Eq)]
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
    /// Output name suffix, unit and description of the quantity.
    pub fn declaration(self) -> (&'static str, Unit, &'static str) {
        match self {
            Self::X => ("x", Unit::M, "Position x"),
            Self::Y => ("y", Unit::M, "Position y"),
            Self::Z => ("z", Unit::M, "Position z"),
            Self::Vx => ("vx", Unit::MPerS, "Velocity x"),
            Self::Vy => ("vy", Unit::MPerS, "Velocity y"),
            Self::Vz => ("vz", Unit::MPerS, "Velocity z"),
            Self::Rx => (
                "rx",
                Unit::Rad,
                "Rotation vector from the reference orientation (principal value, |r| <= pi), x",
            ),
            Self::Ry => ("ry", Unit::Rad, "Rotation vector (principal value), y"),
            Self::Rz => ("rz", Unit::Rad, "Rotation vector (principal value), z"),
            Self::Tx => ("tx", Unit::One, "Beam axis direction cosine with x"),
            Self::Ty => ("ty", Unit::One, "Beam axis direction cosine with y"),
            Self::Tz => ("tz", Unit::One, "Beam axis direction cosine with z"),
            Self::Wx => ("wx", Unit::RadPerS, "Angular velocity, global x"),
            Self::Wy => ("wy", Unit::RadPerS, "Angular velocity, global y"),
            Self::Wz => ("wz", Unit::RadPerS, "Angular velocity, global z"),
        }
    }

    /// Whether the quantity exists in planar scenes.
    pub fn is_planar(&self) -> bool {
        matches!(self, Self::X | Self::Y | Self::Vx | Self::Vy)
    }
}

/// `[[probes]]`: outputs at a point of the centre line.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
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

/// `[gravity]` of a planar scene.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Gravity2d {
    /// [m/s2]
    #[serde(default)]
    pub x: f64,
    /// [m/s2]
    #[serde(default)]
    pub y: f64,
}

/// `[gravity]` of a 3D scene.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Gravity3d {
    /// [m/s2]
    #[serde(default)]
    pub x: f64,
    /// [m/s2]
    #[serde(default)]
    pub y: f64,
    /// [m/s2]
    #[serde(default)]
    pub z: f64,
}

/// `[outputs]` of kinds whose only optional outputs are the energies.
#[derive(Clone, Debug, Default, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct EnergyOutputs {
    /// Expose `energy.kinetic`, `energy.potential`, `energy.strain`, `energy.total` [J].
    #[serde(default)]
    pub energy: bool,
}

/// The tables every kind has, read from any scene file without checking the rest (the kind
/// reads them again, strictly).
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
pub struct CommonTables {
    /// FMU identity.
    pub fmu: FmuSection,
    /// Default experiment written into the model description.
    #[serde(default)]
    pub experiment: ExperimentSection,
    /// Solver settings (all exposed as `solver.*` parameters).
    #[serde(default)]
    pub solver: SolverSection,
}
