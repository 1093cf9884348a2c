//! Kind `beam_2d`: a straight planar beam of seed-000 shear-deformable ANCF elements
//! (Kerkkänen, Sopanen & Mikkola 2003) or of gradient-deficient ANCF cable elements
//! (Euler–Bernoulli, cubic; `element.type`), with supports, point loads, motion ports and probes.
//! Scene tables here, declarations in [`scene`], the model in [`model`].

pub mod model;
pub mod scene;

use super::{LegacyClaim, legacy_element_type};
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
        summary: "straight planar beam of seed-000 shear-deformable ANCF elements or ANCF cable elements",
        validation: include_str!("validation.txt"),
        legacy: |t| matches!(legacy_element_type(t), Some("ancf_shear_2d" | "ancf_cable_2d"))
            .then_some(LegacyClaim::ElementType),
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

/// The element of a planar beam: the scene key `[element] type` (a string) and the start value
/// of the Integer parameter `element.type` ([`Beam2dElementType::code`]).
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
pub enum Beam2dElementType {
    /// `element.type = 1`: seed 000, the linear shear-deformable 2D ANCF beam of Kerkkänen,
    /// Sopanen & Mikkola 2003 (4 coordinates per node: position and cross-section gradient).
    #[default]
    #[serde(rename = "ancf_shear_2d")]
    AncfShear2d,
    /// `element.type = 2`: the gradient-deficient ANCF cable (Euler–Bernoulli, cubic Hermite
    /// interpolation, 4 coordinates per node: position and axial slope;
    /// `src/elements/ancf_cable2d.rs`).
    #[serde(rename = "ancf_cable_2d")]
    AncfCable2d,
}

impl Beam2dElementType {
    /// Every element type with its scene string and its value of `element.type`.
    pub const ALL: [(Self, &'static str, i32); 2] = [
        (Self::AncfShear2d, "ancf_shear_2d", 1),
        (Self::AncfCable2d, "ancf_cable_2d", 2),
    ];

    /// The value of the Integer parameter `element.type`.
    pub fn code(self) -> i32 {
        Self::ALL
            .iter()
            .find(|(t, _, _)| *t == self)
            .map_or(1, |e| e.2)
    }

    /// The element type of a value of `element.type` (`None` outside 1..=2).
    pub fn from_code(code: i32) -> Option<Self> {
        Self::ALL.iter().find(|e| e.2 == code).map(|e| e.0)
    }

    /// The scene string (`[element] type = "..."`).
    pub fn scene_name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(t, _, _)| *t == self)
            .map_or("", |e| e.1)
    }
}

/// `[element]` of a planar beam. The seed-000 options (`shear_rule`, `strain_energy`,
/// `shear_coefficient`) may be given only with `type = "ancf_shear_2d"` (the cable has no
/// shear); omitted, they take their defaults (the start values of their parameters).
#[derive(Clone, Debug, Default, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Beam2dElement {
    /// Element family.
    #[serde(rename = "type", default)]
    pub element_type: Beam2dElementType,
    /// 1 = original 1x1 shear integration, 2 = the 1x2 fix (default). Seed-000 element only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_rule: Option<i32>,
    /// 1 = Eq. 12 (default), 2 = Lamé form of Eqs. 10–11. Seed-000 element only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strain_energy: Option<i32>,
    /// Shear correction factor k_s of Eq. 12 (default 5/6). Seed-000 element only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_coefficient: Option<f64>,
}

impl Beam2dElement {
    /// `shear_rule`, or its default 2 (the 1x2 fix).
    pub fn shear_rule(&self) -> i32 {
        self.shear_rule.unwrap_or(2)
    }

    /// `strain_energy`, or its default 1 (Eq. 12).
    pub fn strain_energy(&self) -> i32 {
        self.strain_energy.unwrap_or(1)
    }

    /// `shear_coefficient`, or its default 5/6.
    pub fn shear_coefficient(&self) -> f64 {
        self.shear_coefficient.unwrap_or(5.0 / 6.0)
    }
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
