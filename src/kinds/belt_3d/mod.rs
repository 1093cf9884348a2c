//! Kind `belt_3d` (issue 13): a closed belt of seed-003 co-rotational elements (with the
//! bowing term in their axial strain) over pulleys in space with crowned rims and flanges,
//! tilted and offset, driven or free. Scene tables here, declarations in [`scene`], the model
//! in [`model`].

pub mod model;
pub mod path;
pub mod scene;

use crate::scene::tables::{ExperimentSection, FmuSection, Gravity3d, SolverSection};
use model::Belt3d;
use serde::Deserialize;

body_kind! {
    /// The kind (registry entry).
    Belt3dKind {
        tables: Belt3dScene,
        model: Belt3d,
        name: "belt_3d",
        summary: "closed belt of co-rotational 3D beam elements over pulleys in space (tilt, offset, crown, flanges) with friction contact",
        validation: include_str!("validation.txt"),
        legacy: |t| claims_legacy(t).then_some(super::LegacyClaim::Tables),
    }
}

/// The rule for files without a `kind` key, from the keys only a 3D belt has: a `[belt]` with
/// a `width`, or a `[[pulley]]` with a three-component `center` or a rim `width`.
fn claims_legacy(t: &toml::Table) -> bool {
    let belt_width = t
        .get("belt")
        .and_then(|b| b.as_table())
        .is_some_and(|b| b.contains_key("width"));
    let pulley_3d = |p: &toml::Value| {
        p.as_table().is_some_and(|p| {
            p.contains_key("width")
                || p.get("center")
                    .and_then(|c| c.as_array())
                    .is_some_and(|c| c.len() == 3)
        })
    };
    let pulleys_3d = match t.get("pulley") {
        Some(toml::Value::Array(a)) => a.iter().any(pulley_3d),
        Some(p) => pulley_3d(p),
        None => false,
    };
    belt_width || pulleys_3d
}

/// A `belt_3d` scene file (`kind = "belt_3d"`; without it, a `[belt]` with a `width` or a
/// `[[pulley]]` with a three-component `center` or a `width` says it).
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Belt3dScene {
    /// `kind = "belt_3d"` (optional: the 3D belt tables say it).
    #[serde(default)]
    pub kind: Option<String>,
    /// FMU identity.
    pub fmu: FmuSection,
    /// Default experiment.
    #[serde(default)]
    pub experiment: ExperimentSection,
    /// The belt.
    pub belt: Belt3dBelt,
    /// Belt–pulley contact.
    pub contact: Contact3d,
    /// `[[pulley]]`: the pulleys in the order the belt wraps them, counter-clockwise about
    /// each pulley's axis; the first is `pulley1`. With all axes along z the belt is mounted
    /// in the plane z = 0; with crossed axes along the path in space of
    /// [`path::SpacePath`] (quarter-twist drive).
    #[serde(default)]
    pub pulley: Vec<Pulley3dSpec>,
    /// Gravity (omit for none).
    #[serde(default)]
    pub gravity: Option<Gravity3d>,
    /// Solver settings.
    #[serde(default)]
    pub solver: SolverSection,
    /// Further outputs.
    #[serde(default)]
    pub outputs: Belt3dOutputs,
}

/// `[belt]` of a 3D belt: a rectangular section (width × thickness) as datasheets give it.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct Belt3dBelt {
    /// Axial stiffness [N].
    pub EA: f64,
    /// Bending stiffness over the pulleys (about the width axis) [N m2].
    pub EI: f64,
    /// Bending stiffness in the belt's plane (about the thickness axis) [N m2] (default:
    /// `EA width²/12`, a homogeneous section).
    #[serde(default)]
    pub EI_lateral: Option<f64>,
    /// Torsional stiffness [N m2] (default: `G width t³/3` with `G = E/2.6`, `E = EA/(b t)`).
    #[serde(default)]
    pub GJ: Option<f64>,
    /// Shear stiffness (both directions, shear coefficient included) [N] (default
    /// `5/6 G b t`).
    #[serde(default)]
    pub GA: Option<f64>,
    /// Mass per unit length [kg/m].
    pub mass_per_length: f64,
    /// Width [m].
    pub width: f64,
    /// Thickness [m]: the centre line runs at pulley radius + thickness/2.
    pub thickness: f64,
    /// Span tension at rest [N].
    pub pretension: f64,
    /// Number of belt elements.
    pub n_elements: i64,
    /// Bowing term in the elements' axial strain (default on; see the README).
    #[serde(default = "default_true")]
    pub bowing: bool,
}

fn default_true() -> bool {
    true
}

/// `[contact]` of a 3D belt; stiffness and damping 0 mean "derived from the belt" (as the
/// planar drive).
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Contact3d {
    /// Coulomb friction coefficient [1].
    pub mu: f64,
    /// Normal penalty stiffness per unit belt length [N/m2] (0: automatic).
    #[serde(default)]
    pub stiffness: f64,
    /// Normal damping per unit belt length [N s/m2] (0: automatic).
    #[serde(default)]
    pub damping: f64,
    /// Bristle stiffness per unit belt length [N/m2] (0: automatic, k_n/10).
    #[serde(default)]
    pub friction_stiffness: f64,
    /// Contact points across the belt's width per section, 1 … 5 (Gauss–Lobatto, edges
    /// included; 1: the centre line only, no contact moment about the belt's tangent;
    /// default 3).
    #[serde(default = "default_width_points")]
    pub width_points: u8,
    /// Contact sections per element between the nodes, 0 … 4 (on the element's cubic centre
    /// line at `(i + 0.5)/n` of its length; 0: at the nodes only; default
    /// [`DEFAULT_POINTS_PER_ELEMENT`]).
    #[serde(default = "default_points_per_element")]
    pub points_per_element: u8,
}

/// Default of `[contact] points_per_element`: 2 (session 33; 0, the node-only contact, before).
/// Measured (`tests/belt_3d.rs` `planar_limit_loaded_table`, README "Contact between the
/// nodes"): with both drives pre-loaded in frictionless equilibrium, the 3D drive with 2
/// sections is within 0.04 % of the planar drive's span tensions at 144 elements (10 and
/// 30 N m, radii 0.08/0.12 and 0.05/0.15 m) and within 0.5 % at 72, the node-only contact
/// off by up to 2.9 % at 72 and 0.37 % at 144, with creep errors up to +121 %. The cost per
/// element and iteration is higher (1.36x at 120 elements in session 32), partly paid back
/// by fewer iterations.
pub const DEFAULT_POINTS_PER_ELEMENT: u8 = 2;

fn default_points_per_element() -> u8 {
    DEFAULT_POINTS_PER_ELEMENT
}

/// Default of `[contact] width_points`: three (the edges and the middle); measured against
/// one point: the planar limit unchanged, the walking rate within 2 %, the quarter-twist
/// torques closer to Euler's moments, 1.01–1.28 × the cost per element and Newton iteration
/// (`examples/bench_belt_3d.rs`), and only with it does a crowned rim centre the belt.
fn default_width_points() -> u8 {
    3
}

/// How a 3D pulley moves (as the planar drive's).
#[derive(Clone, Copy, Debug, Deserialize, serde::Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Pulley3dMode {
    /// Angle and angular velocity are inputs; the belt torque is an output.
    Driven,
    /// Rigid body with inertia inside the FMU; an input torque drives or loads it.
    Free,
}

/// `[[pulley]]` of a 3D belt.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Pulley3dSpec {
    /// Centre of the rim's middle [m] (the belt is mounted in the plane z = 0 through the
    /// centres' x, y).
    pub center: [f64; 3],
    /// Axis direction (any length; default +z).
    #[serde(default = "default_axis")]
    pub axis: [f64; 3],
    /// Rim radius at its middle [m] (the belt's inner face rests on it).
    pub radius: f64,
    /// Rim width between the flange faces [m].
    pub width: f64,
    /// Crown height: rim radius at the middle minus at the edges [m].
    #[serde(default)]
    pub crown: f64,
    /// Flange height above the rim [m] (0: no flanges).
    #[serde(default)]
    pub flange: f64,
    /// Tilt of the axis [rad] about the direction of the span arriving from the previous
    /// pulley (the parameter `pulleyN.tilt`).
    #[serde(default)]
    pub tilt: f64,
    /// Skew of the axis [rad] about the line through the centre perpendicular to that span in
    /// the drive plane (the parameter `pulleyN.skew`): the span then enters the rim at this
    /// angle to its mid-plane, the classical misalignment that makes a belt walk at
    /// `v × skew`.
    #[serde(default)]
    pub skew: f64,
    /// Offset of the pulley along its axis [m] (the parameter `pulleyN.offset_z`).
    #[serde(default)]
    pub offset_z: f64,
    /// Driven or free.
    pub mode: Pulley3dMode,
    /// Free pulleys: moment of inertia about the axis [kg m2].
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

fn default_axis() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

/// `[outputs]` of a 3D belt.
#[derive(Clone, Debug, Default, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Belt3dOutputs {
    /// Expose the energies and `energy.input_work`, `energy.dissipated` [J].
    #[serde(default)]
    pub energy: bool,
    /// Number of belt points `belt.point[i].x/y/z` (default: the nodes).
    #[serde(default)]
    pub belt_points: Option<i64>,
}
