//! Kind `belt_3d`: checks of the tables, parameters, inputs and outputs, and what each input
//! and output means to the model.

use super::{Belt3dScene, Pulley3dMode};
use crate::kinds::KindIo;
use crate::kinds::energy::{EnergyKind, declare_energy_outputs};
use crate::scene::params::{Check, ParamDef, gravity_params_3d, int_param};
use crate::units::Unit;
use crate::variables::Value;

/// What a pulley input sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PulleyInput {
    /// `pulleyN.angle`: prescribed angle of a driven pulley about its axis [rad].
    Angle,
    /// `pulleyN.omega`: prescribed angular velocity of a driven pulley [rad/s].
    Omega,
    /// `pulleyN.torque_in`: external torque on a free pulley about its axis [N m].
    Torque,
}

/// What an input of a 3D belt drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Input {
    /// Index of the pulley (0 for `pulley1`).
    pub pulley: usize,
    /// Which quantity.
    pub quantity: PulleyInput,
}

/// Outputs of a 3D belt (pulley indices start at 0 for `pulley1`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// `pulleyN.torque`: torque of the belt on the pulley about its axis [N m].
    PulleyTorque(usize),
    /// `pulleyN.force_x`, `_y`, `_z` (component 0, 1, 2 in the scene's global frame): force of
    /// the belt on the pulley [N].
    PulleyForce(usize, usize),
    /// `pulleyN.moment_x`, `_y` (component 0, 1 in the scene's global frame): moment of the
    /// belt's contact forces about the pulley's centre [N m].
    PulleyMoment(usize, usize),
    /// `pulleyN.flange_force`: axial force of the belt's edges on the pulley's flanges, signed
    /// along its axis [N].
    FlangeForce(usize),
    /// `pulleyN.angle` of a free pulley [rad].
    PulleyAngle(usize),
    /// `pulleyN.omega` of a free pulley [rad/s].
    PulleyOmega(usize),
    /// `beltN.lateral`: mean axial position of the belt's contact points on pulley N, from
    /// the rim's middle along its axis [m].
    Lateral(usize),
    /// `pulleyN.slip`: speed loss against pulley 1 [1] (drives of three or more pulleys, as the
    /// planar drive).
    PulleySlip(usize),
    /// `spanN.tension`: axial force in the middle of span N, from pulley N to pulley N + 1 [N]
    /// (drives of three or more pulleys, as the planar drive).
    SpanTension(usize),
    /// `belt.tension_tight` [N].
    TensionTight,
    /// `belt.tension_slack` [N].
    TensionSlack,
    /// `belt.slip` [1].
    Slip,
    /// `belt.speed` [m/s].
    Speed,
    /// `belt.point[i].x`, `.y`, `.z` (component 0, 1, 2) [m].
    Point(usize, usize),
    /// `energy.input_work` [J].
    InputWork,
    /// `energy.dissipated` [J].
    Dissipated,
    /// An energy.
    Energy(EnergyKind),
}

/// Largest number of pulleys of a 3D belt scene.
pub const MAX_PULLEYS: usize = 8;

/// Parameter names of the 3D belt (public interface: never rename silently).
pub mod names {
    /// Axial stiffness [N].
    pub const BELT_EA: &str = "belt.EA";
    /// Bending stiffness over the pulleys [N m2].
    pub const BELT_EI: &str = "belt.EI";
    /// Bending stiffness in the belt's plane [N m2].
    pub const BELT_EI_LATERAL: &str = "belt.EI_lateral";
    /// Torsional stiffness [N m2].
    pub const BELT_GJ: &str = "belt.GJ";
    /// Shear stiffness [N].
    pub const BELT_GA: &str = "belt.GA";
    /// Mass per length [kg/m].
    pub const BELT_MASS: &str = "belt.mass_per_length";
    /// Width [m].
    pub const BELT_WIDTH: &str = "belt.width";
    /// Thickness [m].
    pub const BELT_THICKNESS: &str = "belt.thickness";
    /// Pre-tension [N].
    pub const BELT_PRETENSION: &str = "belt.pretension";
    /// Element count (Integer).
    pub const BELT_N_ELEMENTS: &str = "belt.n_elements";
    /// Bowing term (Boolean).
    pub const BELT_BOWING: &str = "belt.bowing";
    /// Friction coefficient [1].
    pub const CONTACT_MU: &str = "contact.mu";
    /// Normal penalty stiffness [N/m2] (0: automatic).
    pub const CONTACT_STIFFNESS: &str = "contact.stiffness";
    /// Normal damping [N s/m2] (0: automatic).
    pub const CONTACT_DAMPING: &str = "contact.damping";
    /// Bristle stiffness [N/m2] (0: automatic).
    pub const CONTACT_FRICTION_STIFFNESS: &str = "contact.friction_stiffness";
    /// Contact points across the belt's width per node (Integer).
    pub const CONTACT_WIDTH_POINTS: &str = "contact.width_points";
    /// Contact sections per element between the nodes (Integer; 0: at the nodes).
    pub const CONTACT_POINTS_PER_ELEMENT: &str = "contact.points_per_element";
}

use names::*;

macro_rules! pulley_names {
    ($suffix:literal) => {
        [
            concat!("pulley1.", $suffix),
            concat!("pulley2.", $suffix),
            concat!("pulley3.", $suffix),
            concat!("pulley4.", $suffix),
            concat!("pulley5.", $suffix),
            concat!("pulley6.", $suffix),
            concat!("pulley7.", $suffix),
            concat!("pulley8.", $suffix),
        ]
    };
}

/// `pulleyN.radius` [m].
pub const PULLEY_RADIUS: [&str; MAX_PULLEYS] = pulley_names!("radius");
/// `pulleyN.width` [m].
pub const PULLEY_WIDTH: [&str; MAX_PULLEYS] = pulley_names!("width");
/// `pulleyN.crown` [m].
pub const PULLEY_CROWN: [&str; MAX_PULLEYS] = pulley_names!("crown");
/// `pulleyN.flange` [m].
pub const PULLEY_FLANGE: [&str; MAX_PULLEYS] = pulley_names!("flange");
/// `pulleyN.tilt` [rad].
pub const PULLEY_TILT: [&str; MAX_PULLEYS] = pulley_names!("tilt");
/// `pulleyN.skew` [rad].
pub const PULLEY_SKEW: [&str; MAX_PULLEYS] = pulley_names!("skew");
/// `pulleyN.offset_z` [m].
pub const PULLEY_OFFSET: [&str; MAX_PULLEYS] = pulley_names!("offset_z");
/// `pulleyN.inertia` [kg m2] (free pulleys).
pub const PULLEY_INERTIA: [&str; MAX_PULLEYS] = pulley_names!("inertia");
/// `pulleyN.damping` [N m s/rad] (free pulleys).
pub const PULLEY_DAMPING: [&str; MAX_PULLEYS] = pulley_names!("damping");

fn norm3(v: &[f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Problems of a 3D belt scene.
pub fn check(s: &Belt3dScene) -> Result<(), Vec<String>> {
    let mut errs = Vec::new();
    if s.pulley.len() < 2 || s.pulley.len() > MAX_PULLEYS {
        errs.push(format!(
            "[[pulley]]: a 3D belt needs 2 to {MAX_PULLEYS} pulleys, the scene has {}",
            s.pulley.len()
        ));
    }
    for (i, p) in s.pulley.iter().enumerate() {
        let key = format!("pulley[{i}] (pulley{})", i + 1);
        if !p.center.iter().chain(&p.axis).all(|v| v.is_finite()) {
            errs.push(format!("{key}.center, axis: must be finite numbers"));
        }
        let n = norm3(&p.axis);
        if n.is_nan() || n <= 0.0 {
            errs.push(format!(
                "{key}.axis: must be a non-zero direction (all along z: the belt is mounted in the plane z = 0; crossed axes: along the path in space of the quarter-twist drive)"
            ));
        }
        match (p.mode, p.inertia) {
            (Pulley3dMode::Free, None) => errs.push(format!(
                "{key}.inertia: a free pulley needs its moment of inertia [kg m2]"
            )),
            (Pulley3dMode::Driven, Some(_)) => errs.push(format!(
                "{key}.inertia: a driven pulley has its motion prescribed (use mode = \"free\")"
            )),
            _ => {}
        }
        if p.mode == Pulley3dMode::Driven && (p.damping != 0.0 || p.torque_in != 0.0) {
            errs.push(format!(
                "{key}: damping and torque_in apply to free pulleys only"
            ));
        }
        if p.mode == Pulley3dMode::Free && p.omega != 0.0 {
            errs.push(format!(
                "{key}.omega: a free pulley starts at rest; omega is the input of a driven pulley"
            ));
        }
    }
    // consecutive centres must not lie on one axis line: the belt runs across the axes (axes
    // along z: the centres differ in x, y; the check before session 33 demanded that of every
    // drive, and refused a drive with its axes along x whose centres differ in z only)
    let np = s.pulley.len();
    for i in 0..np {
        let j = (i + 1) % np;
        let (a, b) = (s.pulley[i].center, s.pulley[j].center);
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let ax = s.pulley[i].axis;
        let n = norm3(&ax);
        let along = if n > 0.0 {
            (d[0] * ax[0] + d[1] * ax[1] + d[2] * ax[2]) / n
        } else {
            0.0
        };
        let across = (norm3(&d).powi(2) - along * along).max(0.0).sqrt();
        if (j > i || np > 2) && across <= 1e-9 * norm3(&d).max(1e-300) {
            errs.push(format!(
                "pulley[{j}].center: must not lie on pulley[{i}]'s axis line through its centre (the belt runs across the axes; with the axes along z the centres must differ in x, y)"
            ));
        }
    }
    if let Some(n) = s.outputs.belt_points
        && !(2..=10_000).contains(&n)
    {
        errs.push(format!("outputs.belt_points = {n}: must lie in [2, 10000]"));
    }
    if errs.is_empty() { Ok(()) } else { Err(errs) }
}

/// Section values derived from the datasheet ones: `(EI_lateral, GJ, GA)` [N m2, N m2, N].
pub fn derived_section(s: &Belt3dScene) -> (f64, f64, f64) {
    let b = &s.belt;
    let e = b.EA / (b.width * b.thickness);
    let g = e / 2.6;
    (
        b.EI_lateral.unwrap_or(b.EA * b.width * b.width / 12.0),
        b.GJ.unwrap_or(g * b.width * b.thickness.powi(3) / 3.0),
        b.GA.unwrap_or(5.0 / 6.0 * g * b.width * b.thickness),
    )
}

/// Parameters of a 3D belt scene ([`check`] passed).
pub fn params(s: &Belt3dScene) -> Result<Vec<ParamDef>, String> {
    let (b, c) = (&s.belt, &s.contact);
    let real = Value::Real;
    let (ei_lat, gj, ga) = derived_section(s);
    let mut out = vec![
        ParamDef::new(
            BELT_EA,
            real(b.EA),
            Some(Unit::N),
            "Axial stiffness EA of the belt",
            Check::Positive,
        ),
        ParamDef::new(
            BELT_EI,
            real(b.EI),
            Some(Unit::NM2),
            "Bending stiffness of the belt over the pulleys (about its width axis)",
            Check::Positive,
        ),
        ParamDef::new(
            BELT_EI_LATERAL,
            real(ei_lat),
            Some(Unit::NM2),
            "Bending stiffness of the belt in its own plane (about its thickness axis; default belt.EA width^2/12 from belt.EA and belt.width)",
            Check::Positive,
        ),
        ParamDef::new(
            BELT_GJ,
            real(gj),
            Some(Unit::NM2),
            "Torsional stiffness of the belt (default G width thickness^3/3, G = E/2.6, E = belt.EA/(width thickness))",
            Check::Positive,
        ),
        ParamDef::new(
            BELT_GA,
            real(ga),
            Some(Unit::N),
            "Shear stiffness of the belt (both directions, shear coefficient included; default 5/6 G width thickness, G = belt.EA/(2.6 width thickness))",
            Check::Positive,
        ),
        ParamDef::new(
            BELT_MASS,
            real(b.mass_per_length),
            Some(Unit::KgPerM),
            "Mass per unit (unstretched) length",
            Check::Positive,
        ),
        ParamDef::new(
            BELT_WIDTH,
            real(b.width),
            Some(Unit::M),
            "Belt width (its edges meet the flanges)",
            Check::Positive,
        ),
        ParamDef::new(
            BELT_THICKNESS,
            real(b.thickness),
            Some(Unit::M),
            "Belt thickness: the centre line runs at pulley radius + thickness/2",
            Check::Positive,
        ),
        ParamDef::new(
            BELT_PRETENSION,
            real(b.pretension),
            Some(Unit::N),
            "Span tension at rest: the belt is mounted with it and the static pre-load is solved at initialization",
            Check::Positive,
        ),
        ParamDef::new(
            BELT_N_ELEMENTS,
            Value::Integer(int_param(b.n_elements, BELT_N_ELEMENTS)?),
            None,
            "Number of belt elements around the loop",
            Check::IntRange(8, 100_000),
        ),
        ParamDef::new(
            BELT_BOWING,
            Value::Boolean(b.bowing),
            None,
            "Bowing term in the elements' axial strain (restores the arc length that the chord of an element wrapped on a pulley misses)",
            Check::None,
        ),
        ParamDef::new(
            CONTACT_MU,
            real(c.mu),
            Some(Unit::One),
            "Coulomb friction coefficient between belt and pulley rims",
            Check::NonNegative,
        ),
        ParamDef::new(
            CONTACT_STIFFNESS,
            real(c.stiffness),
            Some(Unit::NPerM2),
            "Normal penalty stiffness per unit belt length; 0 = automatic: EA/(thickness r_min)",
            Check::NonNegative,
        ),
        ParamDef::new(
            CONTACT_DAMPING,
            real(c.damping),
            Some(Unit::NSPerM2),
            "Normal damping per unit belt length; 0 = automatic: sqrt(k_n m')",
            Check::NonNegative,
        ),
        ParamDef::new(
            CONTACT_FRICTION_STIFFNESS,
            real(c.friction_stiffness),
            Some(Unit::NPerM2),
            "Bristle stiffness per unit belt length in stick (both surface directions); 0 = automatic: 1/10 of the normal stiffness",
            Check::NonNegative,
        ),
        ParamDef::new(
            CONTACT_WIDTH_POINTS,
            Value::Integer(c.width_points.into()),
            None,
            "Contact points across the belt's width per node (Gauss-Lobatto, edges included; 1 = the centre line only): with 2 or more the rim pressure over the width gives a moment about the belt's tangent, so a crowned rim centres the belt, and the belt's edges meet the flanges",
            Check::IntRange(1, 5),
        ),
        ParamDef::new(
            CONTACT_POINTS_PER_ELEMENT,
            Value::Integer(c.points_per_element.into()),
            None,
            "Contact sections per element, on the element's cubic centre line at (i + 0.5)/n of its length, each with contact.width_points points across the width (0 = at the nodes only, each node standing for an element length: the belt meets the rims at the node-passing frequency)",
            Check::IntRange(0, 4),
        ),
    ];
    for (i, p) in s.pulley.iter().enumerate() {
        out.push(ParamDef::new(
            PULLEY_RADIUS[i],
            real(p.radius),
            Some(Unit::M),
            "Rim radius at its middle (the belt's inner face rests on it)",
            Check::Positive,
        ));
        out.push(ParamDef::new(
            PULLEY_WIDTH[i],
            real(p.width),
            Some(Unit::M),
            "Rim width between the flange faces",
            Check::Positive,
        ));
        out.push(ParamDef::new(
            PULLEY_CROWN[i],
            real(p.crown),
            Some(Unit::M),
            "Crown height: rim radius at the middle minus at the edges (0: flat)",
            Check::NonNegative,
        ));
        out.push(ParamDef::new(
            PULLEY_FLANGE[i],
            real(p.flange),
            Some(Unit::M),
            "Flange height above the rim (0: no flanges)",
            Check::NonNegative,
        ));
        out.push(ParamDef::new(
            PULLEY_TILT[i],
            real(p.tilt),
            Some(Unit::Rad),
            "Tilt of the pulley axis about the direction of the span arriving from the previous pulley (the line of centres projected on the pulley's plane; right-handed; misalignment: in a two-pulley drive the belt walks at belt speed x tilt x (R1 + R2) / loop length)",
            Check::Closed(-0.5, 0.5),
        ));
        out.push(ParamDef::new(
            PULLEY_SKEW[i],
            real(p.skew),
            Some(Unit::Rad),
            "Skew of the pulley axis about the perpendicular of the arriving span in the pulley's plane (axis x span; a positive skew leans the axis, as given in the scene, towards the arriving span's direction; the span enters the rim at this angle: the belt first walks at up to belt speed x skew, over a loop slower)",
            Check::Closed(-0.5, 0.5),
        ));
        out.push(ParamDef::new(
            PULLEY_OFFSET[i],
            real(p.offset_z),
            Some(Unit::M),
            "Offset of the pulley along its axis (misalignment)",
            Check::Finite,
        ));
        if p.mode == Pulley3dMode::Free {
            out.push(ParamDef::new(
                PULLEY_INERTIA[i],
                real(p.inertia.unwrap_or(0.0)),
                Some(Unit::KgM2),
                "Moment of inertia of the free pulley about its axis",
                Check::Positive,
            ));
            out.push(ParamDef::new(
                PULLEY_DAMPING[i],
                real(p.damping),
                Some(Unit::NMSPerRad),
                "Viscous bearing damping of the free pulley (torque -d omega)",
                Check::NonNegative,
            ));
        }
    }
    out.extend(gravity_params_3d(s.gravity.as_ref()));
    Ok(out)
}

/// Number of `belt.point[i]` outputs.
pub fn belt_points(s: &Belt3dScene) -> usize {
    s.outputs.belt_points.unwrap_or(s.belt.n_elements).max(0) as usize
}

/// Inputs and outputs of a 3D belt scene.
pub fn io(s: &Belt3dScene) -> KindIo<Input, Output> {
    let mut io = KindIo::default();
    for (i, p) in s.pulley.iter().enumerate() {
        let n = i + 1;
        let role = |quantity| Input {
            pulley: i,
            quantity,
        };
        match p.mode {
            Pulley3dMode::Driven => {
                io.input(
                    format!("pulley{n}.angle"),
                    0.0,
                    Unit::Rad,
                    "Prescribed angle of the driven pulley about its axis; inside a step it is extrapolated with pulleyN.omega".into(),
                    role(PulleyInput::Angle),
                );
                io.input(
                    format!("pulley{n}.omega"),
                    p.omega,
                    Unit::RadPerS,
                    "Prescribed angular velocity of the driven pulley about its axis".into(),
                    role(PulleyInput::Omega),
                );
            }
            Pulley3dMode::Free => {
                io.input(
                    format!("pulley{n}.torque_in"),
                    p.torque_in,
                    Unit::NM,
                    "External torque on the free pulley about its axis (motor or load)".into(),
                    role(PulleyInput::Torque),
                );
            }
        }
    }
    let mut out = |name: String, unit: Unit, what: &str, kind: Output| {
        io.output(name, unit, what.into(), kind);
    };
    for (i, p) in s.pulley.iter().enumerate() {
        let n = i + 1;
        if p.mode == Pulley3dMode::Free {
            out(
                format!("pulley{n}.angle"),
                Unit::Rad,
                "Angle of the free pulley about its axis",
                Output::PulleyAngle(i),
            );
            out(
                format!("pulley{n}.omega"),
                Unit::RadPerS,
                "Angular velocity of the free pulley about its axis",
                Output::PulleyOmega(i),
            );
        }
        out(
            format!("pulley{n}.torque"),
            Unit::NM,
            "Torque the belt exerts on the pulley about its axis",
            Output::PulleyTorque(i),
        );
        for (c, x) in ["x", "y", "z"].iter().enumerate() {
            out(
                format!("pulley{n}.force_{x}"),
                Unit::N,
                &format!(
                    "Force the belt exerts on the pulley, {x} component in the scene's (global) frame (the axial force of a pulley whose axis is along z: force_z)"
                ),
                Output::PulleyForce(i, c),
            );
        }
        for (c, x) in ["x", "y"].iter().enumerate() {
            out(
                format!("pulley{n}.moment_{x}"),
                Unit::NM,
                &format!(
                    "Moment of the belt's contact forces about the pulley's centre, {x} component in the scene's (global) frame (bearing moment of a misaligned belt)"
                ),
                Output::PulleyMoment(i, c),
            );
        }
        out(
            format!("pulley{n}.flange_force"),
            Unit::N,
            "Axial force of the belt's edges on the pulley's flanges (along the pulley axis, signed)",
            Output::FlangeForce(i),
        );
        if s.pulley.len() >= 3 {
            out(
                format!("pulley{n}.slip"),
                Unit::One,
                "Speed loss of the pulley against pulley 1 by creep and sliding: 1 - omega rho/(omega_1 rho_1), rho = pitch radius, omega about the pulley's own axis (0 while pulley 1 is at rest)",
                Output::PulleySlip(i),
            );
        }
    }
    if s.pulley.len() >= 3 {
        for i in 0..s.pulley.len() {
            let (name, what) =
                crate::kinds::belt_drive::scene::span_tension_output(i, s.pulley.len());
            out(name, Unit::N, &what, Output::SpanTension(i));
        }
    }
    for i in 0..s.pulley.len() {
        out(
            format!("belt{}.lateral", i + 1),
            Unit::M,
            "Lateral position of the belt on pulley N: mean axial position of its contact points from the rim's middle",
            Output::Lateral(i),
        );
    }
    out(
        "belt.tension_tight".into(),
        Unit::N,
        "Axial force in the middle of the tighter span",
        Output::TensionTight,
    );
    out(
        "belt.tension_slack".into(),
        Unit::N,
        "Axial force in the middle of the slacker span",
        Output::TensionSlack,
    );
    out(
        "belt.slip".into(),
        Unit::One,
        "Speed loss from pulley 1 to the last pulley by creep and sliding: 1 - omega_last rho_last/(omega_1 rho_1) (0 while pulley 1 is at rest)",
        Output::Slip,
    );
    out(
        "belt.speed".into(),
        Unit::MPerS,
        "Mean speed of the belt nodes",
        Output::Speed,
    );
    for k in 0..belt_points(s) {
        for (c, x) in ["x", "y", "z"].iter().enumerate() {
            out(
                format!("belt.point[{}].{x}", k + 1),
                Unit::M,
                &format!("Belt centre-line point at an equally spaced material position, {x}"),
                Output::Point(k, c),
            );
        }
    }
    if s.outputs.energy {
        declare_energy_outputs(
            &mut io,
            Output::Energy,
            &[
                (
                    EnergyKind::Kinetic,
                    "Kinetic energy of belt and free pulleys",
                ),
                (
                    EnergyKind::Strain,
                    "Strain energy of the belt plus the elastic energy of the contact penalty",
                ),
                (EnergyKind::Potential, "Gravity potential of the belt"),
                (EnergyKind::Total, "Kinetic + strain + potential energy"),
            ],
        );
        io.output(
            "energy.input_work".into(),
            Unit::J,
            "Work done on the system by the driven pulleys and the input torques since the start"
                .into(),
            Output::InputWork,
        );
        io.output(
            "energy.dissipated".into(),
            Unit::J,
            "Energy dissipated since the start by contact damping, friction and bearing damping"
                .into(),
            Output::Dissipated,
        );
    }
    io
}
