//! Kind `belt_drive`: checks of the tables, parameters, inputs and outputs, and what each
//! input and output means to the model.

use super::{BeltDriveScene, BeltElementType, PulleyMode};
use crate::kinds::KindIo;
use crate::kinds::energy::{EnergyKind, declare_energy_outputs};
use crate::scene::params::{
    Check, ParamDef, describe, gravity_params_2d, int_param, resolve_choice,
};
use crate::units::Unit;
use crate::variables::Value;

/// What a pulley input sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PulleyInput {
    /// `pulleyN.angle`: prescribed angle of a driven pulley [rad].
    Angle,
    /// `pulleyN.omega`: prescribed angular velocity of a driven pulley [rad/s].
    Omega,
    /// `pulleyN.torque_in`: external torque on a free pulley [N m].
    Torque,
}

/// What an input of a belt drive drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Input {
    /// A pulley input.
    Pulley {
        /// Index of the pulley (0 for `pulley1`).
        pulley: usize,
        /// Which quantity.
        quantity: PulleyInput,
    },
}

/// Outputs of belt-drive scenes (pulley indices start at 0 for `pulley1`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BeltOutput {
    /// `pulleyN.torque`: torque the belt exerts on the pulley about its centre [N m]
    /// (counter-clockwise positive).
    PulleyTorque(usize),
    /// `pulleyN.force_x`: force the belt exerts on the pulley, x [N].
    PulleyForceX(usize),
    /// `pulleyN.force_y`: force the belt exerts on the pulley, y [N].
    PulleyForceY(usize),
    /// `pulleyN.angle` of a free pulley [rad].
    PulleyAngle(usize),
    /// `pulleyN.omega` of a free pulley [rad/s].
    PulleyOmega(usize),
    /// `pulleyN.slip`: `1 − s_N ω_N ρ_N / (s_1 ω_1 ρ_1)` (`s` = +1 front, −1 back side, `ρ`
    /// pitch radius): speed loss of the pulley against pulley 1 [1] (drives of three or more
    /// pulleys).
    PulleySlip(usize),
    /// `spanN.tension`: axial force in the middle of span N, from pulley N to pulley N + 1
    /// (the last to pulley 1) [N] (drives of three or more pulleys).
    SpanTension(usize),
    /// `tensioner.angle`: arm angle from its design position, counter-clockwise [rad].
    TensionerAngle,
    /// `tensioner.torque`: spring plus damper torque on the arm, counter-clockwise [N m].
    TensionerTorque,
    /// `belt.tension_tight`: the larger span tension [N].
    TensionTight,
    /// `belt.tension_slack`: the smaller span tension [N].
    TensionSlack,
    /// `belt.slip`: `1 − ω_last ρ_last / (ω_1 ρ_1)` (speed loss by creep and slip) [1].
    Slip,
    /// `belt.speed`: mean speed of the belt nodes [m/s].
    Speed,
    /// `belt.point[i].x` [m].
    PointX(usize),
    /// `belt.point[i].y` [m].
    PointY(usize),
    /// `energy.input_work`: work of the pulley drives and input torques since t = 0 [J].
    InputWork,
    /// `energy.dissipated`: energy dissipated by contact, friction and damping since t = 0 [J].
    Dissipated,
}

/// What an output of a belt drive reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// A belt or pulley quantity.
    Belt(BeltOutput),
    /// An energy.
    Energy(EnergyKind),
}

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
    /// Formulation (Integer: 1 = Lagrangian, 2 = ALE).
    pub const BELT_FORMULATION: &str = "belt.formulation";
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
    /// Tensioner spring stiffness [N m/rad].
    pub const TENSIONER_STIFFNESS: &str = "tensioner.stiffness";
    /// Tensioner spring torque at the design angle [N m].
    pub const TENSIONER_PRELOAD: &str = "tensioner.preload";
    /// Tensioner arm damping [N m s/rad].
    pub const TENSIONER_DAMPING: &str = "tensioner.damping";
    /// Tensioner arm inertia about the pivot [kg m2].
    pub const TENSIONER_INERTIA: &str = "tensioner.inertia";
}

use names::*;

/// Belt element types (values of `belt.element`).
pub const BELT_ELEMENTS: &[(&str, i32)] = &[("ancf_cable_2d", 1), ("ancf_shear_2d", 2)];
/// Cable integration rules (values of `belt.integration`).
pub const BELT_INTEGRATIONS: &[(&str, i32)] = &[("full", 1), ("reduced", 2), ("mixed", 3)];
/// Belt formulations (values of `belt.formulation`).
pub const BELT_FORMULATIONS: &[(&str, i32)] = &[("lagrangian", 1), ("ale", 2)];

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
pub fn check(s: &BeltDriveScene) -> Result<(), Vec<String>> {
    let mut errs = Vec::new();
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
    if let Some(t) = &s.tensioner {
        let ok = t.pulley >= 1
            && (t.pulley as usize) <= s.pulley.len()
            && s.pulley[t.pulley as usize - 1].mode == PulleyMode::Free;
        if !ok {
            errs.push(format!(
                "tensioner.pulley = {}: must name a free pulley (1 to {})",
                t.pulley,
                s.pulley.len()
            ));
        }
        if !t.pivot.iter().all(|v| v.is_finite()) {
            errs.push("tensioner.pivot: must be finite numbers".into());
        }
        for (key, v) in [
            ("stiffness", t.stiffness),
            ("preload", t.preload),
            ("damping", t.damping),
            ("inertia", t.inertia),
        ] {
            if !v.is_finite() {
                errs.push(format!("tensioner.{key}: must be a finite number"));
            }
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
pub fn params(s: &BeltDriveScene) -> Result<Vec<ParamDef>, String> {
    let (b, c) = (&s.belt, &s.contact);
    let real = Value::Real;
    let element = match s.element.element_type {
        BeltElementType::AncfCable2d => 1,
        BeltElementType::AncfShear2d => 2,
    };
    let mut out = vec![
        ParamDef::new(
            BELT_EA,
            real(b.EA),
            Some(Unit::N),
            "Axial stiffness EA of the belt (datasheet value; independent of EI)",
            Check::Positive,
        ),
        ParamDef::new(
            BELT_EI,
            real(b.EI),
            Some(Unit::NM2),
            "Bending stiffness EI of the belt",
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
            BELT_THICKNESS,
            real(b.thickness),
            Some(Unit::M),
            "Belt thickness: the centre line runs at pulley radius + thickness/2 (contact offset, pitch radius)",
            Check::NonNegative,
        ),
        ParamDef::new(
            BELT_PRETENSION,
            real(b.pretension),
            Some(Unit::N),
            "Span tension at rest: the mean over the spans of the axial force at each span's middle (with gravity a span sags and its tension rises towards its ends by the weight times the height; on a horizontal span the mid-span force is the catenary's horizontal tension); the belt is mounted with this tension and the static pre-load is solved at initialization",
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
            Some(Unit::NS),
            "Axial material damping d_eps: N = EA eps + d_eps deps/dt (ANCF cable only)",
            Check::NonNegative,
        ),
        ParamDef::new(
            BELT_DAMPING_BENDING,
            real(b.damping_bending),
            Some(Unit::NM2S),
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
            Some(Unit::One),
            "Coulomb friction coefficient between belt and pulleys",
            Check::NonNegative,
        ),
        ParamDef::new(
            CONTACT_STIFFNESS,
            real(c.stiffness),
            Some(Unit::NPerM2),
            "Normal penalty stiffness per unit belt length; 0 = automatic: EA/(thickness r_min), so that the penetration is the belt strain times the thickness",
            Check::NonNegative,
        ),
        ParamDef::new(
            CONTACT_DAMPING,
            real(c.damping),
            Some(Unit::NSPerM2),
            "Normal (and stick) damping per unit belt length; 0 = automatic: sqrt(k_n m') (half the critical damping of the belt on the penalty spring)",
            Check::NonNegative,
        ),
        ParamDef::new(
            CONTACT_FRICTION_STIFFNESS,
            real(c.friction_stiffness),
            Some(Unit::NPerM2),
            "Tangential bristle stiffness per unit belt length in stick; 0 = automatic: 1/10 of the normal stiffness",
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
            Some(Unit::M),
            "Distance of the pulley centres (pulley 2 moves along the direction of the scene file)",
            Check::Positive,
        ));
    }
    for (i, p) in s.pulley.iter().enumerate() {
        out.push(ParamDef::new(
            PULLEY_RADIUS[i],
            real(p.radius),
            Some(Unit::M),
            "Pulley radius (the belt's inner face rests on it)",
            Check::Positive,
        ));
        if p.mode == PulleyMode::Free {
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
    if let Some(t) = &s.tensioner {
        out.push(ParamDef::new(
            TENSIONER_STIFFNESS,
            real(t.stiffness),
            Some(Unit::NMPerRad),
            "Torsion spring stiffness of the tensioner arm",
            Check::Positive,
        ));
        out.push(ParamDef::new(
            TENSIONER_PRELOAD,
            real(t.preload),
            Some(Unit::NM),
            "Spring torque on the tensioner arm at its design angle (the idler centre of the scene), turning the idler into the belt",
            Check::NonNegative,
        ));
        out.push(ParamDef::new(
            TENSIONER_DAMPING,
            real(t.damping),
            Some(Unit::NMSPerRad),
            "Viscous damping of the tensioner arm (torque -c dpsi/dt)",
            Check::NonNegative,
        ));
        out.push(ParamDef::new(
            TENSIONER_INERTIA,
            real(t.inertia),
            Some(Unit::KgM2),
            "Moment of inertia of the tensioner arm with its idler about the pivot",
            Check::Positive,
        ));
    }
    out.extend(gravity_params_2d(s.gravity.as_ref()));
    // Last of the kind's own parameters, so that the value references before it keep theirs.
    out.push(ParamDef::new(
        BELT_FORMULATION,
        Value::Integer(resolve_choice(
            BELT_FORMULATION,
            &b.formulation,
            BELT_FORMULATIONS,
        )?),
        None,
        &format!(
            "Belt formulation: {} (lagrangian: the mesh moves with the material; ale: the mesh stays on the loop's shape and the material flows through it at the belt speed; closed cable belt on front- or back-side pulleys, with or without a tensioner and gravity, without bending damping)",
            describe(BELT_FORMULATIONS)
        ),
        Check::Choice(BELT_FORMULATIONS),
    ));
    Ok(out)
}

/// Number of `belt.point[i]` outputs.
pub fn belt_points(s: &BeltDriveScene) -> usize {
    s.outputs.belt_points.unwrap_or(s.belt.n_elements).max(0) as usize
}

/// Inputs and outputs of a belt-drive scene.
pub fn io(s: &BeltDriveScene) -> KindIo<Input, Output> {
    let mut io = KindIo::default();
    let pulley_input = |pulley, quantity| Input::Pulley { pulley, quantity };
    for (i, p) in s.pulley.iter().enumerate() {
        let n = i + 1;
        match p.mode {
            PulleyMode::Driven => {
                io.input(
                    format!("pulley{n}.angle"),
                    0.0,
                    Unit::Rad,
                    "Prescribed angle of the driven pulley (counter-clockwise); inside a step it is extrapolated with pulleyN.omega".into(),
                    pulley_input(i, PulleyInput::Angle),
                );
                io.input(
                    format!("pulley{n}.omega"),
                    p.omega,
                    Unit::RadPerS,
                    "Prescribed angular velocity of the driven pulley".into(),
                    pulley_input(i, PulleyInput::Omega),
                );
            }
            PulleyMode::Free => {
                io.input(
                    format!("pulley{n}.torque_in"),
                    p.torque_in,
                    Unit::NM,
                    "External torque on the free pulley (motor or load), counter-clockwise".into(),
                    pulley_input(i, PulleyInput::Torque),
                );
            }
        }
    }
    let mut belt = |name: String, unit: Unit, what: &str, kind: BeltOutput| {
        io.output(name, unit, what.into(), Output::Belt(kind));
    };
    for (i, p) in s.pulley.iter().enumerate() {
        let n = i + 1;
        let mut add = |suffix: &str, unit: Unit, what: &str, kind: BeltOutput| {
            belt(format!("pulley{n}.{suffix}"), unit, what, kind)
        };
        if p.mode == PulleyMode::Free {
            add(
                "angle",
                Unit::Rad,
                "Angle of the free pulley",
                BeltOutput::PulleyAngle(i),
            );
            add(
                "omega",
                Unit::RadPerS,
                "Angular velocity of the free pulley",
                BeltOutput::PulleyOmega(i),
            );
        }
        add(
            "torque",
            Unit::NM,
            "Torque the belt exerts on the pulley about its centre (counter-clockwise positive)",
            BeltOutput::PulleyTorque(i),
        );
        add(
            "force_x",
            Unit::N,
            "Force the belt exerts on the pulley, x",
            BeltOutput::PulleyForceX(i),
        );
        add(
            "force_y",
            Unit::N,
            "Force the belt exerts on the pulley, y",
            BeltOutput::PulleyForceY(i),
        );
        if s.pulley.len() >= 3 {
            add(
                "slip",
                Unit::One,
                "Speed loss of the pulley against pulley 1 by creep and sliding: 1 - s omega rho/(s_1 omega_1 rho_1), rho = pitch radius, s = +1 front side, -1 back side (0 while pulley 1 is at rest)",
                BeltOutput::PulleySlip(i),
            );
        }
    }
    if s.pulley.len() >= 3 {
        for i in 0..s.pulley.len() {
            let (name, what) = span_tension_output(i, s.pulley.len());
            belt(name, Unit::N, &what, BeltOutput::SpanTension(i));
        }
    }
    if s.tensioner.is_some() {
        belt(
            "tensioner.angle".into(),
            Unit::Rad,
            "Angle of the tensioner arm from its design position (counter-clockwise)",
            BeltOutput::TensionerAngle,
        );
        belt(
            "tensioner.torque".into(),
            Unit::NM,
            "Spring plus damper torque on the tensioner arm (counter-clockwise)",
            BeltOutput::TensionerTorque,
        );
    }
    belt(
        "belt.tension_tight".into(),
        Unit::N,
        "Axial force in the middle of the tighter span",
        BeltOutput::TensionTight,
    );
    belt(
        "belt.tension_slack".into(),
        Unit::N,
        "Axial force in the middle of the slacker span",
        BeltOutput::TensionSlack,
    );
    belt(
        "belt.slip".into(),
        Unit::One,
        "Speed loss from pulley 1 to the last pulley by creep and sliding: 1 - omega_last rho_last/(omega_1 rho_1), rho = pitch radius (0 while pulley 1 is at rest)",
        BeltOutput::Slip,
    );
    belt(
        "belt.speed".into(),
        Unit::MPerS,
        "Mean speed of the belt nodes (ale: of the material at the mesh nodes)",
        BeltOutput::Speed,
    );
    for k in 0..belt_points(s) {
        belt(
            format!("belt.point[{}].x", k + 1),
            Unit::M,
            "Belt centre-line point at an equally spaced material position, x (ale: at an equally spaced mesh position, fixed on the loop)",
            BeltOutput::PointX(k),
        );
        belt(
            format!("belt.point[{}].y", k + 1),
            Unit::M,
            "Belt centre-line point at an equally spaced material position, y (ale: at an equally spaced mesh position, fixed on the loop)",
            BeltOutput::PointY(k),
        );
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
                (
                    EnergyKind::Potential,
                    "Gravity potential of the belt (-Q_g^T q)",
                ),
                (EnergyKind::Total, "Kinetic + strain + potential energy"),
            ],
        );
        let mut belt = |name: &str, what: &str, kind: BeltOutput| {
            io.output(name.into(), Unit::J, what.into(), Output::Belt(kind));
        };
        belt(
            "energy.input_work",
            "Work done on the system by the driven pulleys and the input torques since the start (trapezoidal rule over the internal steps)",
            BeltOutput::InputWork,
        );
        belt(
            "energy.dissipated",
            "Energy dissipated since the start by contact damping, friction (including the bristle energy), material and bearing damping (ale: the material damping with the convective strain rate, net of the work through the belt travel that feeds it, a term of the fixed mesh)",
            BeltOutput::Dissipated,
        );
    }
    io
}

/// Parameter presets of a belt drive (FMI-LS-REF parameter sets, [`crate::ls_ref`]): the
/// pre-tension halved and one and a half times the scene's.
pub fn presets(_s: &BeltDriveScene) -> Vec<crate::ls_ref::Preset> {
    use crate::ls_ref::{Preset, PresetValue::Scale};
    vec![
        Preset {
            name: "pretension_low",
            description: "belt.pretension half the default (a slack belt that slips earlier)"
                .into(),
            changes: vec![(BELT_PRETENSION, Scale(0.5))],
        },
        Preset {
            name: "pretension_high",
            description: "belt.pretension 1.5 times the default".into(),
            changes: vec![(BELT_PRETENSION, Scale(1.5))],
        },
    ]
}

/// Smoke test of a belt drive: the first pulley turns by up to 0.02 rad and back (driven:
/// its angle and, consistently, its speed; free: a torque excursion to 2 N m).
pub fn smoke_test(s: &BeltDriveScene) -> crate::ls_ref::SmokeTest {
    use crate::ls_ref::{Shape, SmokeTest, Stimulus};
    let Some(p) = s.pulley.first() else {
        return SmokeTest::default();
    };
    let stim = |input: &str, amplitude, shape| Stimulus {
        input: format!("pulley1.{input}"),
        amplitude,
        shape,
    };
    SmokeTest::with(match p.mode {
        PulleyMode::Driven => vec![
            stim("angle", 0.01, Shape::Excursion),
            stim("omega", 0.01, Shape::Rate),
        ],
        PulleyMode::Free => vec![stim("torque_in", 1.0, Shape::Excursion)],
    })
}

/// The knobs `flexfmu advise` varies: the belt element (a family: the cable and the seed-000
/// element converge to different answers), the elements around the loop (at least 4) and the
/// contact points per element (at least 1), which move together by level, and the solver knobs.
pub fn knobs(_s: &BeltDriveScene) -> Vec<crate::advise::Knob> {
    use crate::advise::{Knob, KnobRole, solver_knobs};
    let mut k = vec![
        Knob::new(BELT_ELEMENT, KnobRole::Family(&[1, 2])).at(
            "element",
            "type",
            Some(BELT_ELEMENTS),
        ),
        Knob::new(BELT_N_ELEMENTS, KnobRole::Count { min: 4 }),
        Knob::new(CONTACT_POINTS, KnobRole::Count { min: 1 }),
    ];
    k.extend(solver_knobs());
    k
}

/// Name and description of the `spanN.tension` output of span `i` (0-based) of a closed belt
/// over `n` pulleys (the planar and the 3D belt drives).
pub fn span_tension_output(i: usize, n: usize) -> (String, String) {
    (
        format!("span{}.tension", i + 1),
        format!(
            "Axial force in the middle of span {}, from pulley {} to pulley {}",
            i + 1,
            i + 1,
            (i + 1) % n + 1
        ),
    )
}
