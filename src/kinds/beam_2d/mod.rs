//! Kind `beam_2d`: a straight planar beam of seed-000 shear-deformable ANCF elements
//! (Kerkkänen, Sopanen & Mikkola 2003) with supports, point loads, motion ports and probes.
//! Scene tables here, declarations in [`scene`], the model in [`model`].

pub mod model;
pub mod scene;

use super::{legacy_element_type, legacy_has_belt};
use crate::scene::tables::{
    EnergyOutputs, ExperimentSection, FmuSection, Gravity2d, InitialSection, MaterialSection,
    MeshSection, MotionSpec, ProbeSpec, SolverSection, SupportSpec,
};
use model::Beam2d;
use serde::Deserialize;

body_kind! {
    /// The kind (registry entry).
    Beam2dKind {
        tables: Beam2dScene,
        model: Beam2d,
        name: "beam_2d",
        summary: "straight planar beam of seed-000 shear-deformable ANCF elements",
        validation: include_str!("validation.txt"),
        legacy: |t| legacy_element_type(t) == Some("ancf_shear_2d") && !legacy_has_belt(t),
        smoke_test: |s| scene::smoke_test(s),
        knobs: |s| scene::knobs(s),
    }
}

/// A `beam_2d` scene file.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Beam2dScene {
    /// `kind = "beam_2d"` (optional: the element type says it).
    #[serde(default)]
    pub kind: Option<String>,
    /// FMU identity.
    pub fmu: FmuSection,
    /// Default experiment.
    #[serde(default)]
    pub experiment: ExperimentSection,
    /// Element options.
    #[serde(default)]
    pub element: Beam2dElement,
    /// Mesh.
    pub mesh: MeshSection,
    /// Geometry of the straight beam.
    pub geometry: GeometrySection,
    /// Material.
    pub material: MaterialSection,
    /// Gravity (omit for none: then no gravity parameters are exposed).
    #[serde(default)]
    pub gravity: Option<Gravity2d>,
    /// Solver settings.
    #[serde(default)]
    pub solver: SolverSection,
    /// Supports.
    #[serde(default)]
    pub supports: Vec<SupportSpec>,
    /// Point loads: force inputs.
    #[serde(default)]
    pub loads: Vec<Load2d>,
    /// Probes: position/velocity outputs.
    #[serde(default)]
    pub probes: Vec<ProbeSpec>,
    /// Motion ports: prescribed position/velocity inputs, reaction-force outputs.
    #[serde(default)]
    pub motions: Vec<MotionSpec>,
    /// Energy outputs.
    #[serde(default)]
    pub outputs: EnergyOutputs,
    /// Initial rigid rotation (omit: the body starts at rest).
    #[serde(default)]
    pub initial: Option<InitialSection>,
}

/// The element of a planar beam (one so far).
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
pub enum Beam2dElementType {
    /// Seed 000: linear shear-deformable 2D ANCF beam (4 coordinates per node).
    #[default]
    #[serde(rename = "ancf_shear_2d")]
    AncfShear2d,
}

/// `[element]` of a planar beam.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Beam2dElement {
    /// Element family.
    #[serde(rename = "type", default)]
    pub element_type: Beam2dElementType,
    /// 1 = original 1x1 shear integration, 2 = the 1x2 fix (default).
    #[serde(default = "default_shear_rule")]
    pub shear_rule: i32,
    /// 1 = Eq. 12 (default), 2 = Lamé form of Eqs. 10–11.
    #[serde(default = "default_strain_energy")]
    pub strain_energy: i32,
    /// Shear correction factor k_s of Eq. 12.
    #[serde(default = "default_shear_coefficient")]
    pub shear_coefficient: f64,
}

impl Default for Beam2dElement {
    fn default() -> Self {
        Self {
            element_type: Beam2dElementType::AncfShear2d,
            shear_rule: default_shear_rule(),
            strain_energy: default_strain_energy(),
            shear_coefficient: default_shear_coefficient(),
        }
    }
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

/// `[geometry]`: a straight rectangular beam.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
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

/// `[[loads]]`: a fixed-direction force input at a point of the centre line.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Load2d {
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
}
