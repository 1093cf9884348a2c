//! Kind `belt_drive`: a closed belt of ANCF cable (or seed-000) elements around pulleys that
//! are driven (motion in, belt torque out) or free (inertia inside the FMU, torque in), with
//! Coulomb friction contact. Scene tables here, declarations in [`scene`], the model in
//! [`model`], assembled from its pulleys (`pulleys.rs`), pre-load (`preload.rs`) and energy book
//! (`energy.rs`) and the contact point set of [`crate::contact`].

pub mod ale;
pub mod ale_drive;
pub mod creep;
mod energy;
pub mod model;
pub(crate) mod preload;
mod pulleys;
pub mod scene;
mod tensioner;

use crate::scene::tables::{Choice, ExperimentSection, FmuSection, Gravity2d, SolverSection};
use model::BeltDrive;
use serde::Deserialize;

body_kind! {
    /// The kind (registry entry).
    BeltDriveKind {
        tables: BeltDriveScene,
        build: |s, p| BeltDrive::build_model(s, p, true),
        name: "belt_drive",
        summary: "closed planar belt over driven and free pulleys with friction contact",
        validation: include_str!("validation.txt"),
        legacy: |t| claims_legacy(t).then_some(super::LegacyClaim::Tables),
        presets: |s| scene::presets(s),
        smoke_test: |s| scene::smoke_test(s),
        initial_state: Some("the belt mounted on the pulleys with its pre-tension, after the static pre-load"),
        build_to_restore: |s, p| BeltDrive::build_model(s, p, false),
        knobs: |s| scene::knobs(s),
    }
}

/// The old rule for files without a `kind` key: a `[belt]` or `[[pulley]]` table whose
/// pulleys lie in the drive's plane (a planar pulley's `center` is (x, y): a centre with a
/// third component is not a planar drive's).
fn claims_legacy(t: &toml::Table) -> bool {
    let in_plane = |p: &toml::Value| {
        p.as_table()
            .and_then(|p| p.get("center"))
            .and_then(|c| c.as_array())
            .is_none_or(|c| c.len() != 3)
    };
    let planar = match t.get("pulley") {
        Some(toml::Value::Array(a)) => a.iter().all(in_plane),
        Some(p) => in_plane(p),
        None => true,
    };
    (t.contains_key("belt") || t.contains_key("pulley")) && planar
}

/// A `belt_drive` scene file.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct BeltDriveScene {
    /// `kind = "belt_drive"` (optional: `[belt]` and `[[pulley]]` say it).
    #[serde(default)]
    pub kind: Option<String>,
    /// FMU identity.
    pub fmu: FmuSection,
    /// Default experiment.
    #[serde(default)]
    pub experiment: ExperimentSection,
    /// The belt element.
    #[serde(default)]
    pub element: BeltElement,
    /// The belt.
    pub belt: BeltSection,
    /// Belt–pulley contact.
    pub contact: ContactSection,
    /// `[[pulley]]`: the pulleys in the order the belt runs over them (the belt runs
    /// counter-clockwise around the loop; back-side pulleys outside it); the first is
    /// `pulley1`.
    #[serde(default)]
    pub pulley: Vec<PulleySpec>,
    /// `[tensioner]`: one of the free pulleys on a spring-loaded arm (omit for none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tensioner: Option<TensionerSpec>,
    /// Gravity (omit for none).
    #[serde(default)]
    pub gravity: Option<Gravity2d>,
    /// Solver settings.
    #[serde(default)]
    pub solver: SolverSection,
    /// Further outputs.
    #[serde(default)]
    pub outputs: BeltOutputs,
}

/// Belt element families.
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
pub enum BeltElementType {
    /// Gradient-deficient ANCF cable (r, r' per node, cubic Hermite).
    #[default]
    #[serde(rename = "ancf_cable_2d")]
    AncfCable2d,
    /// Seed 000 element (equivalent rectangle h = sqrt(12 EI/EA)).
    #[serde(rename = "ancf_shear_2d")]
    AncfShear2d,
}

/// `[element]` of a belt drive.
#[derive(Clone, Debug, Default, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct BeltElement {
    /// Element family (the parameter `belt.element`).
    #[serde(rename = "type", default)]
    pub element_type: BeltElementType,
}

/// `[outputs]` of a belt drive.
#[derive(Clone, Debug, Default, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct BeltOutputs {
    /// Expose `energy.kinetic`, `energy.potential`, `energy.strain`, `energy.total`,
    /// `energy.input_work`, `energy.dissipated` [J].
    #[serde(default)]
    pub energy: bool,
    /// Number of equally spaced belt points exposed as `belt.point[i].x/y` (default:
    /// `belt.n_elements`, i.e. the nodes).
    #[serde(default)]
    pub belt_points: Option<i64>,
}

/// `[belt]`: the belt as datasheets give it.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
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
    /// Span tension at rest [N]: the mean over the spans of the axial force at the span
    /// middles (with gravity, a horizontal span's mid-span force is its catenary's horizontal
    /// tension; the tension rises towards the span's ends by the weight times the height).
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
    /// Formulation: `"lagrangian"` (1, the mesh moves with the material; default) or `"ale"`
    /// (2, the mesh stays on the loop's shape and the material flows through it:
    /// [`ale_drive::AleDrive`]; scenes outside its scope are refused, see [`ale::check`]).
    #[serde(
        default = "default_belt_formulation",
        skip_serializing_if = "is_default_formulation"
    )]
    pub formulation: Choice,
}

fn default_belt_integration() -> Choice {
    Choice::Name("full".into())
}

fn default_belt_formulation() -> Choice {
    Choice::Name("lagrangian".into())
}

fn is_default_formulation(c: &Choice) -> bool {
    *c == default_belt_formulation()
}

/// `[contact]`: belt–pulley contact; stiffness and damping 0 mean "derived from the belt".
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
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
#[derive(Clone, Copy, Debug, Deserialize, serde::Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum PulleyMode {
    /// Angle and angular velocity are inputs; the belt torque is an output.
    Driven,
    /// Rigid body with inertia inside the FMU; an input torque drives it.
    Free,
}

/// Which face of the belt runs on a pulley.
#[derive(Clone, Copy, Debug, Default, Deserialize, serde::Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum PulleySide {
    /// The inner face: the pulley lies inside the loop, the belt wraps it counter-clockwise.
    #[default]
    Front,
    /// The back of the belt: an idler outside the loop, wrapped clockwise (its speed is
    /// negative while the front pulleys turn counter-clockwise).
    Back,
}

fn is_front(s: &PulleySide) -> bool {
    *s == PulleySide::Front
}

/// `[tensioner]`: an idler on an arm pivoting about `pivot`, pressed into the belt by a
/// pre-loaded torsion spring, with a viscous damper. The idler is one of the `[[pulley]]`
/// entries (a free pulley); its centre there is the design position of the arm, whose length
/// is the distance from the pivot.
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct TensionerSpec {
    /// Number N of the idler `pulleyN` (1-based).
    pub pulley: i64,
    /// Pivot of the arm [m].
    pub pivot: [f64; 2],
    /// Torsion spring stiffness [N m/rad].
    pub stiffness: f64,
    /// Spring torque at the design angle [N m] (turns the idler into the belt).
    pub preload: f64,
    /// Viscous damping of the arm [N m s/rad].
    #[serde(default)]
    pub damping: f64,
    /// Moment of inertia of arm and idler about the pivot [kg m2].
    pub inertia: f64,
}

/// `[[pulley]]`
#[derive(Clone, Debug, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct PulleySpec {
    /// Centre [m] (for two pulleys the distance is the parameter `pulleys.center_distance`,
    /// along the direction given here).
    pub center: [f64; 2],
    /// Radius [m] (the belt's inner face rests on it).
    pub radius: f64,
    /// Driven or free.
    pub mode: PulleyMode,
    /// Which face of the belt runs on the pulley: `"front"` (default) or `"back"`.
    #[serde(default, skip_serializing_if = "is_front")]
    pub side: PulleySide,
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
