//! Kind `beam_3d`: a 3D beam of seed-003 co-rotational elements (Wang, Qi & Xu 2020) along a
//! centre line of straight and circular pieces, with supports, point loads (forces and
//! moments) and probes. Scene tables here, declarations in [`scene`], the model in
//! [`model`].

pub mod model;
pub mod scene;

use super::{LegacyClaim, legacy_element_type};
use crate::scene::tables::{
    EnergyOutputs, ExperimentSection, FmuSection, Gravity3d, MeshSection, ProbeSpec, SolverSection,
    SupportSpec,
};
use model::Beam3d;
use serde::Deserialize;

body_kind! {
    /// The kind (registry entry).
    Beam3dKind {
        tables: Beam3dScene,
        model: Beam3d,
        name: "beam_3d",
        summary: "3D beam of seed-003 co-rotational elements along straight and circular pieces",
        validation: include_str!("validation.txt"),
        legacy: |t| (legacy_element_type(t) == Some("corotational_3d"))
            .then_some(LegacyClaim::ElementType),
        smoke_test: |s| scene::smoke_test(s),
        knobs: |s| scene::knobs(s),
    }
}

/// A `beam_3d` scene file.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Beam3dScene {
    /// `kind = "beam_3d"` (optional: the element type says it).
    #[serde(default)]
    pub kind: Option<String>,
    /// FMU identity.
    pub fmu: FmuSection,
    /// Default experiment.
    #[serde(default)]
    pub experiment: ExperimentSection,
    /// Element options.
    #[serde(default)]
    pub element: Beam3dElement,
    /// Mesh.
    pub mesh: MeshSection,
    /// Section properties.
    pub section: SectionTable,
    /// Reference centre line.
    pub centreline: CentrelineSection,
    /// Gravity (omit for none: then no gravity parameters are exposed).
    #[serde(default)]
    pub gravity: Option<Gravity3d>,
    /// Solver settings.
    #[serde(default)]
    pub solver: SolverSection,
    /// Supports (clamp or pin).
    #[serde(default)]
    pub supports: Vec<SupportSpec>,
    /// Point loads: force and moment inputs.
    #[serde(default)]
    pub loads: Vec<Load3d>,
    /// Probes.
    #[serde(default)]
    pub probes: Vec<ProbeSpec>,
    /// Energy outputs.
    #[serde(default)]
    pub outputs: EnergyOutputs,
}

/// The element of a 3D beam (one so far).
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
pub enum Beam3dElementType {
    /// Seed 003: two-node co-rotational 3D beam (6 coordinates per node).
    #[default]
    #[serde(rename = "corotational_3d")]
    Corotational3d,
}

/// `[element]` of a 3D beam.
#[derive(Clone, Debug, Default, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Beam3dElement {
    /// Element family.
    #[serde(rename = "type", default)]
    pub element_type: Beam3dElementType,
    /// 1 = Euler–Bernoulli, 2 = Timoshenko local stiffness (default 2).
    #[serde(default)]
    pub theory: Option<i32>,
    /// 1 = three lumped masses, 2 = consistent (default 1).
    #[serde(default)]
    pub mass: Option<i32>,
}

/// `[[loads]]` of a 3D beam: force and moment inputs at a node.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Load3d {
    /// Variable prefix (`<name>.fx`, ..., `<name>.mz`).
    pub name: String,
    /// Location as a fraction of the length, in [0, 1].
    pub at: f64,
    /// Start value of the x force [N].
    #[serde(default)]
    pub fx: f64,
    /// Start value of the y force [N].
    #[serde(default)]
    pub fy: f64,
    /// Start value of the z force [N].
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
    /// `false` (default) = fixed-direction (dead) load, components in the global frame;
    /// `true` = follower load, components given in the global frame of the reference
    /// configuration and rotating with the node.
    #[serde(default)]
    pub follower: bool,
}

/// `[section]`: section properties of a co-rotational beam, as beam users give them (the
/// names are the FMU parameters `section.EA`, ...).
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
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
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
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
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
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
