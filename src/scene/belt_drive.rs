//! Scene kind "belt drive": a closed belt of ANCF cable (or seed-000) elements around pulleys
//! that are driven (motion in, belt torque out) or free (inertia inside the FMU, torque in):
//! required tables, parameters, inputs and outputs.

use super::file::{PulleyMode, SceneFile};
use super::params::{Check, ParamDef, describe, int_param, resolve_choice};
use super::validate::{reject_present, require_tables};
use crate::variables::{
    BeltOutput, EnergyKind, InputKind, IoVariable, OutputKind, PulleyInput, Value,
};

/// Largest number of pulleys of a belt-drive scene.
pub const MAX_PULLEYS: usize = 8;

/// Parameter names of belt-drive scenes (public interface: never rename silently).
pub mod names {
    /// Axial stiffness [N].
    pub const BELT_EA: &str = "belt.EA";
    /// Bending stiffness [N m2].
    pub const BELT_EI: &str = "belt.EI";
    /// Mass per length [kg/m].
    pub const BELT_MASS: &str = "belt.mass_per_length";
    /// Thickness [m].
    pub const BELT_THICKNESS: &str = "belt.thickness";
    /// Pre-tension [N].
    pub const BELT_PRETENSION: &str = "belt.pretension";
    /// Element count (Integer).
    pub const BELT_N_ELEMENTS: &str = "belt.n_elements";
    /// Axial damping [N s].
    pub const BELT_DAMPING_AXIAL: &str = "belt.damping_axial";
    /// Bending damping [N m2 s].
    pub const BELT_DAMPING_BENDING: &str = "belt.damping_bending";
    /// Element type (Integer: 1 = ANCF cable, 2 = seed-000).
    pub const BELT_ELEMENT: &str = "belt.element";
    /// Cable integration rule (Integer).
    pub const BELT_INTEGRATION: &str = "belt.integration";
    /// Friction coefficient [1].
    pub const CONTACT_MU: &str = "contact.mu";
    /// Normal penalty stiffness [N/m2] (0: automatic).
    pub const CONTACT_STIFFNESS: &str = "contact.stiffness";
    /// Normal damping [N s/m2] (0: automatic).
    pub const CONTACT_DAMPING: &str = "contact.damping";
    /// Bristle stiffness [N/m2] (0: automatic).
    pub const CONTACT_FRICTION_STIFFNESS: &str = "contact.friction_stiffness";
    /// Contact points per element (Integer).
    pub const CONTACT_POINTS: &str = "contact.points_per_element";
    /// Centre distance of a two-pulley drive [m].
    pub const CENTER_DISTANCE: &str = "pulleys.center_distance";
}

use names::*;

/// Belt element types (values of `belt.element`).
pub const BELT_ELEMENTS: &[(&str, i32)] = &[("ancf_cable_2d", 1), ("ancf_shear_2d", 2)];
/// Cable integration rules (values of `belt.integration`).
pub const BELT_INTEGRATIONS: &[(&str, i32)] = &[("full", 1), ("reduced", 2), ("mixed", 3)];

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
/// `pulleyN.inertia` [kg m2] (free pulleys).
pub const PULLEY_INERTIA: [&str; MAX_PULLEYS] = pulley_names!("inertia");
/// `pulleyN.damping` [N m s/rad] (free pulleys).
pub const PULLEY_DAMPING: [&str; MAX_PULLEYS] = pulley_names!("damping");

/// Problems of a belt-drive scene.
pub fn check(s: &SceneFile) -> Result<(), Vec<String>> {
    let mut errs = Vec::new();
    require_tables(
        &[("belt", s.belt.is_some()), ("contact", s.contact.is_some())],
        "a belt drive",
        &mut errs,
    );
    reject_present(
        &[
            ("[mesh]", s.mesh.is_some()),
            ("[geometry]", s.geometry.is_some()),
            ("[material]", s.material.is_some()),
        ],
        "not used by a belt drive (the belt is described by [belt])",
        &mut errs,
    );
    if !s.supports.is_empty() || !s.loads.is_empty() || !s.probes.is_empty() {
        errs.push("[[supports]], [[loads]], [[probes]]: not used by a belt drive".into());
    }
    if s.pulley.len() < 2 || s.pulley.len() > MAX_PULLEYS {
        errs.push(format!(
            "[[pulley]]: a belt drive needs 2 to {MAX_PULLEYS} pulleys, the scene has {}",
            s.pulley.len()
        ));
    }
    for (i, p) in s.pulley.iter().enumerate() {
        let key = format!("pulley[{i}] (pulley{})", i + 1);
        if !p.center.iter().all(|v| v.is_finite()) {
            errs.push(format!("{key}.center: must be finite numbers"));
        }
        if !p.omega.is_finite() || !p.torque_in.is_finite() || !p.damping.is_finite() {
            errs.push(format!(
                "{key}: omega, torque_in and damping must be finite"
            ));
        }
        match (p.mode, p.inertia) {
            (PulleyMode::Free, None) => errs.push(format!(
                "{key}.inertia: a free pulley needs its moment of inertia [kg m2]"
            )),
            (PulleyMode::Driven, Some(_)) => errs.push(format!(
                "{key}.inertia: a driven pulley has its motion prescribed; its inertia belongs to the importer (use mode = \"free\" to simulate it here)"
            )),
            _ => {}
        }
        if p.mode == PulleyMode::Driven && (p.damping != 0.0 || p.torque_in != 0.0) {
            errs.push(format!(
                "{key}: damping and torque_in apply to free pulleys only"
            ));
        }
        if p.mode == PulleyMode::Free && p.omega != 0.0 {
            errs.push(format!(
                "{key}.omega: a free pulley starts at rest; omega is the input of a driven pulley"
            ));
        }
    }
    if s.pulley.len() == 2 {
        let (a, b) = (s.pulley[0].center, s.pulley[1].center);
        if a == b {
            errs.push("pulley[1].center: must differ from pulley[0].center".into());
        }
    }
    if let Some(n) = s.outputs.belt_points
        && !(2..=10_000).contains(&n)
    {
        errs.push(format!("outputs.belt_points = {n}: must lie in [2, 10000]"));
    }
    if errs.is_empty() { Ok(()) } else { Err(errs) }
}

/// Parameters of a belt-drive scene ([`check`] passed).
pub fn params(s: &SceneFile) -> Result<Vec<ParamDef>, String> {
    let b = s.belt.as_ref().ok_or("[belt] missing")?;
    let c = s.contact.as_ref().ok_or("[contact] missing")?;
    let real = Value::Real;
    let element = match s.element.kind {
        super::file::ElementType::AncfCable2d => 1,
        super::file::ElementType::AncfShear2d => 2,
        super::file::ElementType::Corotational3d => {
            return Err("element.type = \"corotational_3d\" is a 3D beam, not a belt element: use \"ancf_cable_2d\" or \"ancf_shear_2d\"".into());
        }
    };
    let mut out = vec![
        ParamDef::new(
            BELT_EA,
            real(b.EA),
            Some("N"),
            "Axial stiffness EA of the belt (datasheet value; independent of EI)",
            Check::Positive,
        ),
        ParamDef::new(
            BELT_EI,
            real(b.EI),
            Some("N.m2"),
            "Bending stiffness EI of the belt",
            Check::Positive,
        ),
        ParamDef::new(
            BELT_MASS,
            real(b.mass_per_length),
            Some("kg/m"),
            "Mass per unit (unstretched) length",
            Check::Positive,
        ),
        ParamDef::new(
            BELT_THICKNESS,
            real(b.thickness),
            Some("m"),
            "Belt thickness: the centre line runs at pulley radius + thickness/2 (contact offset, pitch radius)",
            Check::NonNegative,
        ),
        ParamDef::new(
            BELT_PRETENSION,
            real(b.pretension),
            Some("N"),
            "Span tension at rest: the belt is mounted with this tension and the static pre-load is solved at initialization",
            Check::Positive,
        ),
        ParamDef::new(
            BELT_N_ELEMENTS,
            Value::Integer(int_param(b.n_elements, BELT_N_ELEMENTS)?),
            None,
            "Number of belt elements around the loop",
            Check::IntRange(4, 100_000),
        ),
        ParamDef::new(
            BELT_DAMPING_AXIAL,
            real(b.damping_axial),
            Some("N.s"),
            "Axial material damping d_eps: N = EA eps + d_eps deps/dt (ANCF cable only)",
            Check::NonNegative,
        ),
        ParamDef::new(
            BELT_DAMPING_BENDING,
            real(b.damping_bending),
            Some("N.m2.s"),
            "Bending material damping d_K: M = EI K + d_K dK/dt (ANCF cable only)",
            Check::NonNegative,
        ),
        ParamDef::new(
            BELT_ELEMENT,
            Value::Integer(element),
            None,
            &format!(
                "Belt element: {} (seed 000 with an equivalent rectangle of height sqrt(12 EI/EA))",
                describe(BELT_ELEMENTS)
            ),
            Check::Choice(BELT_ELEMENTS),
        ),
        ParamDef::new(
            BELT_INTEGRATION,
            Value::Integer(resolve_choice(
                "belt.integration",
                &b.integration,
                BELT_INTEGRATIONS,
            )?),
            None,
            &format!(
                "ANCF cable integration: {} (full: 5/3 Gauss points axial/bending; reduced: 4/2; mixed: Lobatto 3 axial, Gauss 2 bending)",
                describe(BELT_INTEGRATIONS)
            ),
            Check::Choice(BELT_INTEGRATIONS),
        ),
        ParamDef::new(
            CONTACT_MU,
            real(c.mu),
            Some("1"),
            "Coulomb friction coefficient between belt and pulleys",
            Check::NonNegative,
        ),
        ParamDef::new(
            CONTACT_STIFFNESS,
            real(c.stiffness),
            Some("N/m2"),
            "Normal penalty stiffness per unit belt length; 0 = automatic: EA/(thickness r_min), so that the penetration is the belt strain times the thickness",
            Check::NonNegative,
        ),
        ParamDef::new(
            CONTACT_DAMPING,
            real(c.damping),
            Some("N.s/m2"),
            "Normal (and stick) damping per unit belt length; 0 = automatic: sqrt(k_n m') (half the critical damping of the belt on the penalty spring)",
            Check::NonNegative,
        ),
        ParamDef::new(
            CONTACT_FRICTION_STIFFNESS,
            real(c.friction_stiffness),
            Some("N/m2"),
            "Tangential bristle stiffness per unit belt length in stick; 0 = automatic: 1/100 of the normal stiffness",
            Check::NonNegative,
        ),
        ParamDef::new(
            CONTACT_POINTS,
            Value::Integer(int_param(c.points_per_element, CONTACT_POINTS)?),
            None,
            "Contact points per belt element (equally spaced, each standing for its share of the length)",
            Check::IntRange(1, 32),
        ),
    ];
    if s.pulley.len() == 2 {
        let (a, b) = (s.pulley[0].center, s.pulley[1].center);
        let d = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        out.push(ParamDef::new(
            CENTER_DISTANCE,
            real(d),
            Some("m"),
            "Distance of the pulley centres (pulley 2 moves along the direction of the scene file)",
            Check::Positive,
        ));
    }
    for (i, p) in s.pulley.iter().enumerate() {
        out.push(ParamDef::new(
            PULLEY_RADIUS[i],
            real(p.radius),
            Some("m"),
            "Pulley radius (the belt's inner face rests on it)",
            Check::Positive,
        ));
        if p.mode == PulleyMode::Free {
            out.push(ParamDef::new(
                PULLEY_INERTIA[i],
                real(p.inertia.unwrap_or(0.0)),
                Some("kg.m2"),
                "Moment of inertia of the free pulley about its axis",
                Check::Positive,
            ));
            out.push(ParamDef::new(
                PULLEY_DAMPING[i],
                real(p.damping),
                Some("N.m.s/rad"),
                "Viscous bearing damping of the free pulley (torque -d omega)",
                Check::NonNegative,
            ));
        }
    }
    Ok(out)
}

/// Number of `belt.point[i]` outputs.
pub fn belt_points(s: &SceneFile) -> usize {
    s.outputs
        .belt_points
        .or(s.belt.as_ref().map(|b| b.n_elements))
        .unwrap_or(0)
        .max(0) as usize
}

/// Inputs and outputs of a belt-drive scene.
pub fn io(s: &SceneFile) -> Vec<IoVariable> {
    let mut out = Vec::new();
    for (i, p) in s.pulley.iter().enumerate() {
        let n = i + 1;
        match p.mode {
            PulleyMode::Driven => {
                out.push(IoVariable::input(
                    format!("pulley{n}.angle"),
                    0.0,
                    "rad",
                    "Prescribed angle of the driven pulley (counter-clockwise); inside a step it is extrapolated with pulleyN.omega".into(),
                    InputKind::Pulley {
                        pulley: i,
                        quantity: PulleyInput::Angle,
                    },
                ));
                out.push(IoVariable::input(
                    format!("pulley{n}.omega"),
                    p.omega,
                    "rad/s",
                    "Prescribed angular velocity of the driven pulley".into(),
                    InputKind::Pulley {
                        pulley: i,
                        quantity: PulleyInput::Omega,
                    },
                ));
            }
            PulleyMode::Free => {
                out.push(IoVariable::input(
                    format!("pulley{n}.torque_in"),
                    p.torque_in,
                    "N.m",
                    "External torque on the free pulley (motor or load), counter-clockwise".into(),
                    InputKind::Pulley {
                        pulley: i,
                        quantity: PulleyInput::Torque,
                    },
                ));
            }
        }
    }
    for (i, p) in s.pulley.iter().enumerate() {
        let n = i + 1;
        let mut add = |suffix: &str, unit: &'static str, what: &str, kind: BeltOutput| {
            out.push(IoVariable::output(
                format!("pulley{n}.{suffix}"),
                unit,
                what.into(),
                OutputKind::Belt(kind),
            ));
        };
        if p.mode == PulleyMode::Free {
            add(
                "angle",
                "rad",
                "Angle of the free pulley",
                BeltOutput::PulleyAngle(i),
            );
            add(
                "omega",
                "rad/s",
                "Angular velocity of the free pulley",
                BeltOutput::PulleyOmega(i),
            );
        }
        add(
            "torque",
            "N.m",
            "Torque the belt exerts on the pulley about its centre (counter-clockwise positive)",
            BeltOutput::PulleyTorque(i),
        );
        add(
            "force_x",
            "N",
            "Force the belt exerts on the pulley, x",
            BeltOutput::PulleyForceX(i),
        );
        add(
            "force_y",
            "N",
            "Force the belt exerts on the pulley, y",
            BeltOutput::PulleyForceY(i),
        );
    }
    let belt = |name: &str, unit: &'static str, what: &str, kind: BeltOutput| {
        IoVariable::output(name.into(), unit, what.into(), OutputKind::Belt(kind))
    };
    out.push(belt(
        "belt.tension_tight",
        "N",
        "Axial force in the middle of the tighter span",
        BeltOutput::TensionTight,
    ));
    out.push(belt(
        "belt.tension_slack",
        "N",
        "Axial force in the middle of the slacker span",
        BeltOutput::TensionSlack,
    ));
    out.push(belt(
        "belt.slip",
        "1",
        "Speed loss from pulley 1 to the last pulley by creep and sliding: 1 - omega_last rho_last/(omega_1 rho_1), rho = pitch radius (0 while pulley 1 is at rest)",
        BeltOutput::Slip,
    ));
    out.push(belt(
        "belt.speed",
        "m/s",
        "Mean speed of the belt nodes",
        BeltOutput::Speed,
    ));
    let n_points = belt_points(s);
    for k in 0..n_points {
        out.push(belt(
            &format!("belt.point[{}].x", k + 1),
            "m",
            "Belt centre-line point at an equally spaced material position, x",
            BeltOutput::PointX(k),
        ));
        out.push(belt(
            &format!("belt.point[{}].y", k + 1),
            "m",
            "Belt centre-line point at an equally spaced material position, y",
            BeltOutput::PointY(k),
        ));
    }
    if s.outputs.energy {
        for (kind, name, what) in [
            (
                EnergyKind::Kinetic,
                "kinetic",
                "Kinetic energy of belt and free pulleys",
            ),
            (
                EnergyKind::Strain,
                "strain",
                "Strain energy of the belt plus the elastic energy of the contact penalty",
            ),
            (
                EnergyKind::Potential,
                "potential",
                "Gravity potential of the belt (-Q_g^T q)",
            ),
            (
                EnergyKind::Total,
                "total",
                "Kinetic + strain + potential energy",
            ),
        ] {
            out.push(IoVariable::output(
                format!("energy.{name}"),
                "J",
                what.into(),
                OutputKind::Energy(kind),
            ));
        }
        out.push(belt(
            "energy.input_work",
            "J",
            "Work done on the system by the driven pulleys and the input torques since the start (trapezoidal rule over the internal steps)",
            BeltOutput::InputWork,
        ));
        out.push(belt(
            "energy.dissipated",
            "J",
            "Energy dissipated since the start by contact damping, friction (including the bristle energy), material and bearing damping",
            BeltOutput::Dissipated,
        ));
    }
    out
}
