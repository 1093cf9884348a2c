//! Kind `air_spring`: checks of the tables, parameters, inputs and outputs, and what each
//! input and output means to the model.

use super::AirSpringScene;
use crate::kinds::KindIo;
use crate::scene::params::{Check, ParamDef, int_param};
use crate::units::Unit;
use crate::variables::Value;

/// What an input drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Input {
    /// `top.z` [m]: height of the top plate above the piston base.
    TopZ,
    /// `top.vz` [m/s]: its velocity.
    TopVz,
    /// `top.x` [m] (shell level): lateral position of the plate centre.
    TopX,
    /// `top.y` [m] (shell level).
    TopY,
    /// `top.vx` [m/s] (shell level).
    TopVx,
    /// `top.vy` [m/s] (shell level).
    TopVy,
    /// `top.rx` [rad] (shell level): tilt of the plate, first component of its rotation
    /// vector `(rx, ry, 0)`.
    TopRx,
    /// `top.ry` [rad] (shell level).
    TopRy,
    /// `top.wx` [rad/s] (shell level): rate of `top.rx`.
    TopWx,
    /// `top.wy` [rad/s] (shell level): rate of `top.ry`.
    TopWy,
}

impl Input {
    /// The plate axis (as [`super::PLATE_AXES`]) and whether the input is its rate.
    pub fn axis(self) -> (usize, bool) {
        match self {
            Input::TopX => (0, false),
            Input::TopY => (1, false),
            Input::TopZ => (2, false),
            Input::TopRx => (3, false),
            Input::TopRy => (4, false),
            Input::TopVx => (0, true),
            Input::TopVy => (1, true),
            Input::TopVz => (2, true),
            Input::TopWx => (3, true),
            Input::TopWy => (4, true),
        }
    }
}

/// What an output reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// `top.fz` [N].
    TopFz,
    /// `top.fx` [N] (shell level).
    TopFx,
    /// `top.fy` [N] (shell level).
    TopFy,
    /// `top.mx` [N m] (shell level): moment on the plate about its centre.
    TopMx,
    /// `top.my` [N m] (shell level).
    TopMy,
    /// `gas.pressure` [Pa] absolute.
    Pressure,
    /// `gas.pressure_gauge` [Pa].
    PressureGauge,
    /// `gas.volume` [m3].
    Volume,
    /// `gas.temperature` [K].
    Temperature,
    /// `gas.mass` [kg].
    Mass,
    /// `spring.height` [m].
    Height,
    /// `spring.effective_area` [m2].
    EffectiveArea,
    /// `spring.volumetric_area` [m2].
    VolumetricArea,
    /// `spring.stiffness` [N/m].
    Stiffness,
    /// `bellows.lobe_radius` [m].
    LobeRadius,
    /// `reservoir.pressure` [Pa].
    ReservoirPressure,
    /// `energy.strain` [J].
    StrainEnergy,
    /// `energy.kinetic` [J].
    KineticEnergy,
    /// `energy.gas` [J].
    GasEnergy,
    /// `energy.plate_work` [J].
    PlateWork,
    /// `energy.dissipated` [J].
    Dissipated,
}

/// Parameter names (public interface, issue 11 item 6: never rename silently).
pub mod names {
    /// Fidelity level (Integer).
    pub const MODEL_FIDELITY: &str = "model.fidelity";
    /// Piston radius [m].
    pub const PISTON_RADIUS: &str = "piston.radius";
    /// Piston height [m].
    pub const PISTON_HEIGHT: &str = "piston.height";
    /// Bead radius of the bottom plate of a convoluted spring [m].
    pub const BOTTOM_PLATE_BEAD_RADIUS: &str = "bottom_plate.bead_radius";
    /// Inner radius of the girdle ring of a double-convoluted spring [m].
    pub const GIRDLE_RADIUS: &str = "girdle.radius";
    /// Bead radius of the top plate [m].
    pub const TOP_PLATE_BEAD_RADIUS: &str = "top_plate.bead_radius";
    /// Sleeve radius [m].
    pub const BELLOWS_SLEEVE_RADIUS: &str = "bellows.sleeve_radius";
    /// Sleeve length [m].
    pub const BELLOWS_SLEEVE_LENGTH: &str = "bellows.sleeve_length";
    /// Cord angle [deg].
    pub const BELLOWS_CORD_ANGLE: &str = "bellows.cord_angle";
    /// Plies (Integer).
    pub const BELLOWS_N_PLIES: &str = "bellows.n_plies";
    /// Cord stiffness per ply [N/m].
    pub const BELLOWS_CORD_STIFFNESS: &str = "bellows.cord_stiffness";
    /// Matrix stiffness [N/m].
    pub const BELLOWS_MATRIX_STIFFNESS: &str = "bellows.matrix_stiffness";
    /// Wall thickness [m].
    pub const BELLOWS_THICKNESS: &str = "bellows.thickness";
    /// Wall density [kg/m3].
    pub const BELLOWS_DENSITY: &str = "bellows.density";
    /// Tension-only cords (Boolean).
    pub const BELLOWS_TENSION_ONLY: &str = "bellows.tension_only";
    /// Meridional bending stiffness [N m].
    pub const BELLOWS_BENDING_STIFFNESS: &str = "bellows.bending_stiffness";
    /// Design height [m].
    pub const SPRING_DESIGN_HEIGHT: &str = "spring.design_height";
    /// Design gauge pressure [Pa].
    pub const GAS_PRESSURE_DESIGN: &str = "gas.pressure_design";
    /// Polytropic exponent [1].
    pub const GAS_POLYTROPIC_EXPONENT: &str = "gas.polytropic_exponent";
    /// Gas law (Integer: 1 polytropic, 2 energy).
    pub const GAS_MODEL: &str = "gas.model";
    /// Heat transfer [W/K].
    pub const GAS_HEAT_TRANSFER: &str = "gas.heat_transfer";
    /// Inner volume [m3].
    pub const GAS_INNER_VOLUME: &str = "gas.inner_volume";
    /// Ambient pressure [Pa].
    pub const AMBIENT_PRESSURE: &str = "ambient.pressure";
    /// Ambient temperature [K].
    pub const AMBIENT_TEMPERATURE: &str = "ambient.temperature";
    /// Reservoir volume [m3].
    pub const RESERVOIR_VOLUME: &str = "reservoir.volume";
    /// Orifice diameter [m].
    pub const ORIFICE_DIAMETER: &str = "orifice.diameter";
    /// Orifice discharge coefficient [1].
    pub const ORIFICE_CD: &str = "orifice.cd";
    /// Pipe length [m].
    pub const PIPE_LENGTH: &str = "pipe.length";
    /// Pipe diameter [m].
    pub const PIPE_DIAMETER: &str = "pipe.diameter";
    /// Contact penalty [N/m3].
    pub const CONTACT_STIFFNESS: &str = "contact.stiffness";
    /// Coulomb friction coefficient of the contact [1] (levels 1 and 2).
    pub const CONTACT_MU: &str = "contact.mu";
    /// Elements along the sleeve (Integer).
    pub const MESH_N_MERIDIONAL: &str = "mesh.n_meridional";
    /// Elements around the sleeve (Integer, shell level).
    pub const MESH_N_CIRCUMFERENTIAL: &str = "mesh.n_circumferential";
}

use names::*;

/// Gas laws (values of `gas.model`).
pub const GAS_MODELS: &[(&str, i32)] = &[("polytropic", 1), ("energy", 2)];

/// Fidelity levels (values of `model.fidelity`).
pub const FIDELITIES: &[(&str, i32)] = &[("shell", 1), ("axisymmetric_membrane", 2), ("table", 3)];

/// The shell level only.
const SHELL_ONLY: &[(&str, i32)] = &[("shell", 1)];

/// The membrane level only.
const MEMBRANE_ONLY: &[(&str, i32)] = &[("axisymmetric_membrane", 2)];
/// The table level only.
const TABLE_ONLY: &[(&str, i32)] = &[("table", 3)];

/// Whether a scene is a table scene (level 3).
pub fn is_table(s: &AirSpringScene) -> bool {
    s.model.fidelity == 3
}

/// Bellows types (values of `bellows.type`).
pub const BELLOWS_TYPES: &[&str] = &["rolling_lobe", "convoluted"];

/// Whether a scene's sleeve is convoluted (`bellows.type = "convoluted"`): clamped between a
/// top and a bottom bead plate, no piston.
pub fn is_convoluted(s: &AirSpringScene) -> bool {
    s.bellows.kind.as_deref() == Some("convoluted")
}

/// Convolutions of a convoluted sleeve: `bellows.n_convolutions`, 2 (double bellows) unless the
/// scene says.
pub fn n_convolutions(s: &AirSpringScene) -> i64 {
    s.bellows.n_convolutions.unwrap_or(2)
}

/// What the plate height `top.z` is measured from: the piston base, or for a convoluted spring
/// the bottom plate.
fn base(s: &AirSpringScene) -> &'static str {
    if is_convoluted(s) {
        "the bottom plate"
    } else {
        "the piston base"
    }
}

/// Whether a scene is a shell scene (level 1).
pub fn is_shell(s: &AirSpringScene) -> bool {
    s.model.fidelity == 1
}

/// Elements around the sleeve of a shell scene when the scene does not say.
pub const DEFAULT_N_CIRCUMFERENTIAL: i64 = 0;

/// Checks what the parameters cannot: the reservoir tables come together, the contour is
/// increasing, the gas law is known.
pub fn check(s: &AirSpringScene) -> Result<(), Vec<String>> {
    let mut errs = vec![];
    if !GAS_MODELS.iter().any(|(n, _)| *n == s.gas.model) {
        errs.push(format!(
            "gas.model = \"{}\": must be one of {}",
            s.gas.model,
            crate::scene::params::describe(GAS_MODELS)
        ));
    }
    if !FIDELITIES
        .iter()
        .any(|(_, c)| *c as i64 == s.model.fidelity)
    {
        errs.push(format!(
            "model.fidelity = {}: the levels are {}",
            s.model.fidelity,
            crate::scene::params::describe(FIDELITIES)
        ));
    }
    if s.contact.mu != 0.0 && is_table(s) {
        errs.push(format!(
            "contact.mu = {}: the table level (model.fidelity = 3) has no contact; remove it or set model.fidelity = 1 or 2",
            s.contact.mu
        ));
    }
    if !(s.contact.mu >= 0.0 && s.contact.mu.is_finite()) {
        errs.push("contact.mu: must be a finite number >= 0".into());
    }
    if s.mesh.n_circumferential.is_some() && !is_shell(s) {
        errs.push(
            "mesh.n_circumferential: used by the shell level (model.fidelity = 1) only; remove it or set the fidelity".into(),
        );
    }
    check_bellows_type(s, &mut errs);
    let parts = [s.reservoir.is_some(), s.orifice.is_some(), s.pipe.is_some()];
    if parts.iter().any(|&p| p) && !parts.iter().all(|&p| p) {
        errs.push(
            "reservoir, orifice, pipe: a reservoir needs all three tables ([reservoir] volume, [orifice] diameter, [pipe] length and diameter)".into(),
        );
    }
    match (&s.table, is_table(s)) {
        (None, true) => errs.push(
            "table: model.fidelity = 3 needs a [table] (generate one with `flexfmu air-spring-table SCENE.toml`, or take it from a data sheet)".into(),
        ),
        (Some(_), false) => errs.push(
            "table: a [table] is used by model.fidelity = 3 only; remove it or set the fidelity".into(),
        ),
        (Some(t), true) => {
            let n = t.height.len();
            if n < 4 {
                errs.push("table.height: give at least 4 heights".into());
            }
            for (k, v) in [
                ("effective_area", &t.effective_area),
                ("volume", &t.volume),
                ("volume_compliance", &t.volume_compliance),
            ] {
                if v.len() != n {
                    errs.push(format!(
                        "table.{k}: {} values for {n} heights",
                        v.len()
                    ));
                }
            }
            if t.height.windows(2).any(|w| w[1] <= w[0] || w[1].is_nan()) || t.height.iter().any(|x| !x.is_finite()) {
                errs.push("table.height: strictly increasing finite heights [m]".into());
            }
            for (k, v) in [("effective_area", &t.effective_area), ("volume", &t.volume)] {
                if v.iter().any(|&x| !(x > 0.0 && x.is_finite())) {
                    errs.push(format!("table.{k}: positive finite values"));
                }
            }
            if t.volume_compliance.iter().any(|&x| !x.is_finite()) {
                errs.push("table.volume_compliance: finite values [m3/Pa]".into());
            }
            if !(t.reference_pressure > 0.0 && t.reference_pressure.is_finite()) {
                errs.push("table.reference_pressure: a positive gauge pressure [Pa]".into());
            }
        }
        (None, false) => {}
    }
    if is_table(s) {
        // the membrane tables of a table scene are its record, not parameters: still sane
        let b = &s.bellows;
        let piston = s.piston();
        for (k, v) in [
            ("piston.radius", piston.radius),
            ("piston.height", piston.height),
            ("top_plate.bead_radius", s.top_plate.bead_radius),
            ("bellows.sleeve_radius", b.sleeve_radius),
            ("bellows.sleeve_length", b.sleeve_length),
            ("bellows.cord_angle", b.cord_angle),
            ("bellows.cord_stiffness", b.cord_stiffness + 1.0),
            ("bellows.matrix_stiffness", b.matrix_stiffness),
            ("bellows.thickness", b.thickness),
            ("bellows.density", b.density),
            ("contact.stiffness", s.contact.stiffness),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                errs.push(format!("{k}: must be a positive finite number"));
            }
        }
    }
    if let Some(c) = s.piston.as_ref().and_then(|p| p.contour.as_ref()) {
        if c.len() < 2 {
            errs.push("piston.contour: give at least two points [r, z]".into());
        } else if c.windows(2).any(|w| w[1][1] <= w[0][1])
            || c.iter()
                .any(|p| !(p[0] > 0.0 && p[0].is_finite() && p[1].is_finite()))
        {
            errs.push(
                "piston.contour: points [r, z] with r > 0 and z strictly increasing from the base up"
                    .into(),
            );
        }
    }
    if errs.is_empty() { Ok(()) } else { Err(errs) }
}

/// The tables of the bellows type: a rolling lobe has a piston and neither a bottom plate nor a
/// girdle; a convoluted sleeve has a `[bottom_plate]`, 1 or 2 convolutions, a `[girdle]`
/// exactly when it has 2, and no `[piston]`; level 1 (the shell) is built for the rolling lobe
/// only.
fn check_bellows_type(s: &AirSpringScene, errs: &mut Vec<String>) {
    if let Some(t) = &s.bellows.kind
        && !BELLOWS_TYPES.contains(&t.as_str())
    {
        errs.push(format!(
            "bellows.type = \"{t}\": must be one of {}",
            BELLOWS_TYPES
                .iter()
                .map(|t| format!("\"{t}\""))
                .collect::<Vec<_>>()
                .join(", ")
        ));
        return;
    }
    if !is_convoluted(s) {
        if s.bellows.n_convolutions.is_some() {
            errs.push("bellows.n_convolutions: used by a convoluted sleeve (bellows.type = \"convoluted\") only".into());
        }
        if s.bottom_plate.is_some() {
            errs.push("bottom_plate: used by a convoluted sleeve (bellows.type = \"convoluted\") only; a rolling lobe stands on its piston".into());
        }
        if s.girdle.is_some() {
            errs.push("girdle: used by a double-convoluted sleeve (bellows.type = \"convoluted\", bellows.n_convolutions = 2) only".into());
        }
        return;
    }
    let n = n_convolutions(s);
    if !(n == 1 || n == 2) {
        errs.push(format!(
            "bellows.n_convolutions = {n}: a convoluted sleeve has 1 or 2 convolutions"
        ));
    }
    if s.piston.is_some() {
        errs.push("piston: a convoluted sleeve (bellows.type = \"convoluted\") has no piston; it stands on a [bottom_plate]".into());
    }
    if s.bottom_plate.is_none() {
        errs.push("bottom_plate: a convoluted sleeve needs [bottom_plate] bead_radius [m]".into());
    }
    match (n, &s.girdle) {
        (2, None) => errs.push(
            "girdle: a double-convoluted sleeve (bellows.n_convolutions = 2) needs [girdle] radius [m]"
                .into(),
        ),
        (1, Some(_)) => errs.push(
            "girdle: a single convolution has no girdle ring; remove [girdle] or set bellows.n_convolutions = 2".into(),
        ),
        _ => {}
    }
    if is_shell(s) {
        errs.push("model.fidelity = 1: the shell level is built for the rolling lobe only; a convoluted sleeve has levels 2 and 3".into());
    }
    if is_table(s) {
        for (k, v) in [
            (
                "bottom_plate.bead_radius",
                s.bottom_plate.as_ref().map_or(1.0, |b| b.bead_radius),
            ),
            ("girdle.radius", s.girdle.as_ref().map_or(1.0, |g| g.radius)),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                errs.push(format!("{k}: must be a positive finite number"));
            }
        }
    }
}

/// The piston contour `[r, z]` points of a scene with the parameter values `p`: the scene's
/// contour, or the cylinder of `piston.radius`, `piston.height`.
pub fn piston_contour(s: &AirSpringScene, p: &crate::scene::ParamValues) -> Vec<[f64; 2]> {
    match s.piston.as_ref().and_then(|p| p.contour.as_ref()) {
        Some(c) => c.clone(),
        None => {
            let (radius, height) = (p.real(PISTON_RADIUS), p.real(PISTON_HEIGHT));
            vec![[radius, 0.0], [radius, height]]
        }
    }
}

fn real(name: &'static str, v: f64, unit: Unit, what: &str, check: Check) -> ParamDef {
    ParamDef::new(name, Value::Real(v), Some(unit), what, check)
}

/// The parameters.
pub fn params(s: &AirSpringScene) -> Result<Vec<ParamDef>, String> {
    let fid = int_param(s.model.fidelity, MODEL_FIDELITY)?;
    let table = is_table(s);
    let mut defs = vec![ParamDef::new(
        MODEL_FIDELITY,
        Value::Integer(fid),
        None,
        if table {
            "Fidelity level: 3 = effective-area table with the gas law on top (this FMU carries the table only)"
        } else if is_shell(s) {
            "Fidelity level: 1 = shell (seed-004 elements for bending, cord-rubber membrane quadrilaterals, on the same nodes)"
        } else {
            "Fidelity level: 2 = axisymmetric membrane (2-node conical elements on the meridian)"
        },
        Check::Choice(if table {
            TABLE_ONLY
        } else if is_shell(s) {
            SHELL_ONLY
        } else {
            MEMBRANE_ONLY
        }),
    )];
    if table {
        defs.extend(gas_params(s));
        return Ok(defs);
    }
    let piston = s.piston();
    if is_convoluted(s) {
        let bottom = s.bottom_plate.as_ref().map_or(0.0, |b| b.bead_radius);
        defs.push(real(
            BOTTOM_PLATE_BEAD_RADIUS,
            bottom,
            Unit::M,
            "Radius of the bead ring where the sleeve is clamped to the bottom plate (at z = 0)",
            Check::Positive,
        ));
        if let Some(g) = &s.girdle {
            defs.push(real(
                GIRDLE_RADIUS,
                g.radius,
                Unit::M,
                "Inner radius of the girdle ring between the two convolutions (a rigid ring at the middle of the sleeve's length, free along the axis)",
                Check::Positive,
            ));
        }
    } else if piston.contour.is_none() {
        // a contoured piston's shape is its contour (not a parameter)
        defs.extend([
            real(
                PISTON_RADIUS,
                piston.radius,
                Unit::M,
                "Piston radius (a cylinder from its base up to its top)",
                Check::Positive,
            ),
            real(
                PISTON_HEIGHT,
                piston.height,
                Unit::M,
                "Height of the piston top above its base (where the sleeve is clamped)",
                Check::Positive,
            ),
        ]);
    }
    defs.extend([
        real(
            TOP_PLATE_BEAD_RADIUS,
            s.top_plate.bead_radius,
            Unit::M,
            "Radius of the bead ring where the sleeve is clamped to the top plate",
            Check::Positive,
        ),
        real(
            BELLOWS_SLEEVE_RADIUS,
            s.bellows.sleeve_radius,
            Unit::M,
            "Radius of the stress-free sleeve (a cylinder)",
            Check::Positive,
        ),
        real(
            BELLOWS_SLEEVE_LENGTH,
            s.bellows.sleeve_length,
            Unit::M,
            "Length of the stress-free sleeve",
            Check::Positive,
        ),
        real(
            BELLOWS_CORD_ANGLE,
            s.bellows.cord_angle,
            Unit::Deg,
            "Cord angle from the meridian in the stress-free sleeve (plies alternate +/-)",
            Check::Open(0.0, 90.0),
        ),
        ParamDef::new(
            BELLOWS_N_PLIES,
            Value::Integer(int_param(s.bellows.n_plies, BELLOWS_N_PLIES)?),
            None,
            "Number of cord plies",
            Check::IntRange(1, 16),
        ),
        real(
            BELLOWS_CORD_STIFFNESS,
            s.bellows.cord_stiffness,
            Unit::NPerM,
            "Cord stiffness K_c of one ply (force per unit width per unit cord strain): W_c = K_c (lambda_c - 1)^2 / 2 per reference area",
            Check::NonNegative,
        ),
        real(
            BELLOWS_MATRIX_STIFFNESS,
            s.bellows.matrix_stiffness,
            Unit::NPerM,
            "Membrane stiffness E t of the rubber matrix (nu = 0)",
            Check::Positive,
        ),
        real(
            BELLOWS_THICKNESS,
            s.bellows.thickness,
            Unit::M,
            "Wall thickness (mass per area = density * thickness)",
            Check::Positive,
        ),
        real(
            BELLOWS_DENSITY,
            s.bellows.density,
            Unit::KgPerM3,
            "Wall density",
            Check::Positive,
        ),
        real(
            BELLOWS_BENDING_STIFFNESS,
            s.bellows.bending(),
            Unit::NM,
            if is_shell(s) {
                "Bending stiffness D of the wall (the seed-004 elements, isotropic, nu = 0); 0 = a pure membrane (default: the node rotations are then not coordinates); the rubber's own is matrix_stiffness * thickness^2 / 12"
            } else {
                "Meridional bending stiffness D of the wall (rotation-free hinges at the nodes); 0 = a pure membrane (default); the rubber's own is matrix_stiffness * thickness^2 / 12"
            },
            Check::NonNegative,
        ),
        ParamDef::new(
            BELLOWS_TENSION_ONLY,
            Value::Boolean(s.bellows.tension_only),
            None,
            "Cords carry tension only (default: linear in tension and compression)",
            Check::None,
        ),
    ]);
    defs.extend(gas_params(s));
    defs.push(real(
        CONTACT_STIFFNESS,
        s.contact.stiffness,
        Unit::NPerM3,
        if is_convoluted(s) {
            "Penalty of the contact with the top and bottom plates (pressure per penetration)"
        } else {
            "Penalty of the contact with piston and top plate (pressure per penetration)"
        },
        Check::Positive,
    ));
    if !table {
        defs.push(real(
            CONTACT_MU,
            s.contact.mu,
            Unit::One,
            "Coulomb friction between sleeve and piston / top plate (elasto-plastic bristle of stiffness contact.stiffness per slip, blended stick-slip); 0 = frictionless (default)",
            Check::NonNegative,
        ));
    }
    defs.push(ParamDef::new(
        MESH_N_MERIDIONAL,
        Value::Integer(int_param(s.mesh.n_meridional, MESH_N_MERIDIONAL)?),
        None,
        "Elements along the sleeve",
        Check::IntRange(8, 100_000),
    ));
    if is_shell(s) {
        let n = s
            .mesh
            .n_circumferential
            .unwrap_or(DEFAULT_N_CIRCUMFERENTIAL);
        defs.push(ParamDef::new(
            MESH_N_CIRCUMFERENTIAL,
            Value::Integer(int_param(n, MESH_N_CIRCUMFERENTIAL)?),
            None,
            "Elements around the sleeve, at least 8 (the rings are equal-area polygons: their nodes lie on circles enlarged so that each polygon encloses the circle's area); 0 = automatic: the coarsest of 16, 24, 32 whose design force, at the design pressure and at half of it, is within 0.5 % of the membrane level's",
            Check::IntRange(0, 10_000),
        ));
    }
    Ok(defs)
}

/// The parameters of the design state, the gas, the ambient air and the reservoir (every level).
fn gas_params(s: &AirSpringScene) -> Vec<ParamDef> {
    let mut defs = vec![
        real(
            SPRING_DESIGN_HEIGHT,
            s.spring.design_height,
            Unit::M,
            &format!(
                "Design height: top plate above {} where the gas is charged to gas.pressure_design",
                base(s)
            ),
            Check::Positive,
        ),
        real(
            GAS_PRESSURE_DESIGN,
            s.gas.pressure_design,
            Unit::Pa,
            "Gauge pressure at the design height (fixes the gas mass)",
            Check::Positive,
        ),
        ParamDef::new(
            GAS_MODEL,
            Value::Integer(
                GAS_MODELS
                    .iter()
                    .find(|(n, _)| *n == s.gas.model)
                    .map_or(1, |(_, c)| *c),
            ),
            None,
            "Gas law: 1 = polytropic p V^n = const, 2 = energy balance with heat transfer (adiabatic for gas.heat_transfer = 0, isothermal as it grows)",
            Check::Choice(GAS_MODELS),
        ),
        real(
            GAS_POLYTROPIC_EXPONENT,
            s.gas.polytropic_exponent,
            Unit::One,
            "Polytropic exponent n of the polytropic law (1 isothermal, 1.4 adiabatic)",
            Check::Positive,
        ),
        real(
            GAS_HEAT_TRANSFER,
            s.gas.heat_transfer,
            Unit::WPerK,
            "Heat-transfer coefficient between the gas and the ambient (energy law)",
            Check::NonNegative,
        ),
        real(
            GAS_INNER_VOLUME,
            s.gas.inner_volume,
            Unit::M3,
            "Fixed volume joined to the bag (piston interior)",
            Check::NonNegative,
        ),
        real(
            AMBIENT_PRESSURE,
            s.ambient.pressure,
            Unit::Pa,
            "Ambient (absolute) pressure",
            Check::Positive,
        ),
        real(
            AMBIENT_TEMPERATURE,
            s.ambient.temperature,
            Unit::K,
            "Ambient temperature (charge temperature and heat sink)",
            Check::Positive,
        ),
    ];
    if let (Some(r), Some(o), Some(p)) = (&s.reservoir, &s.orifice, &s.pipe) {
        defs.extend([
            real(
                RESERVOIR_VOLUME,
                r.volume,
                Unit::M3,
                "Reservoir volume",
                Check::Positive,
            ),
            real(
                ORIFICE_DIAMETER,
                o.diameter,
                Unit::M,
                "Orifice diameter",
                Check::Positive,
            ),
            real(
                ORIFICE_CD,
                o.cd,
                Unit::One,
                "Orifice discharge coefficient",
                Check::Closed(0.01, 1.0),
            ),
            real(
                PIPE_LENGTH,
                p.length,
                Unit::M,
                "Pipe length (inertance)",
                Check::Positive,
            ),
            real(
                PIPE_DIAMETER,
                p.diameter,
                Unit::M,
                "Pipe diameter",
                Check::Positive,
            ),
        ]);
    }
    defs
}

/// The inputs and outputs.
pub fn io(s: &AirSpringScene) -> KindIo<Input, Output> {
    let mut io = KindIo::default();
    let table = is_table(s);
    io.input(
        "top.z".into(),
        s.spring.design_height,
        Unit::M,
        format!(
            "Height of the top plate above {} (start: the design height)",
            base(s)
        ),
        Input::TopZ,
    );
    io.input(
        "top.vz".into(),
        0.0,
        Unit::MPerS,
        "Velocity of the top plate along the axis".into(),
        Input::TopVz,
    );
    let shell = is_shell(s);
    let plate_inputs: &[&str] = if shell {
        &[
            "top.x", "top.y", "top.z", "top.rx", "top.ry", "top.vx", "top.vy", "top.vz", "top.wx",
            "top.wy",
        ]
    } else {
        &["top.z", "top.vz"]
    };
    if shell {
        let more: &[(&str, Unit, &str, Input)] = &[
            (
                "top.x",
                Unit::M,
                "Lateral position of the top plate's centre along x",
                Input::TopX,
            ),
            (
                "top.y",
                Unit::M,
                "Lateral position of the top plate's centre along y",
                Input::TopY,
            ),
            (
                "top.vx",
                Unit::MPerS,
                "Velocity of the top plate along x",
                Input::TopVx,
            ),
            (
                "top.vy",
                Unit::MPerS,
                "Velocity of the top plate along y",
                Input::TopVy,
            ),
            (
                "top.rx",
                Unit::Rad,
                "Tilt of the top plate: x component of its rotation vector (rx, ry, 0) about its centre",
                Input::TopRx,
            ),
            (
                "top.ry",
                Unit::Rad,
                "Tilt of the top plate: y component of its rotation vector (rx, ry, 0) about its centre",
                Input::TopRy,
            ),
            ("top.wx", Unit::RadPerS, "Rate of top.rx", Input::TopWx),
            ("top.wy", Unit::RadPerS, "Rate of top.ry", Input::TopWy),
        ];
        for (name, unit, what, role) in more {
            io.input(name.to_string(), 0.0, *unit, what.to_string(), *role);
        }
    }
    io.output(
        "top.fz".into(),
        Unit::N,
        "Axial force of the spring on the top plate (positive pushes it up)".into(),
        Output::TopFz,
    )
    .depending_on(plate_inputs);
    if shell {
        let more: &[(&str, Unit, &str, Output)] = &[
            (
                "top.fx",
                Unit::N,
                "Lateral force of the spring on the top plate along x",
                Output::TopFx,
            ),
            (
                "top.fy",
                Unit::N,
                "Lateral force of the spring on the top plate along y",
                Output::TopFy,
            ),
            (
                "top.mx",
                Unit::NM,
                "Moment of the spring on the top plate about x through the plate centre (the bead ring's centre)",
                Output::TopMx,
            ),
            (
                "top.my",
                Unit::NM,
                "Moment of the spring on the top plate about y through the plate centre",
                Output::TopMy,
            ),
        ];
        for (name, unit, what, role) in more {
            io.output(name.to_string(), *unit, what.to_string(), *role)
                .depending_on(plate_inputs);
        }
    }
    let outs: &[(&str, Unit, &str, Output)] = &[
        (
            "gas.pressure",
            Unit::Pa,
            "Absolute gas pressure in the bag",
            Output::Pressure,
        ),
        (
            "gas.pressure_gauge",
            Unit::Pa,
            "Gauge gas pressure in the bag (absolute minus ambient)",
            Output::PressureGauge,
        ),
        (
            "gas.volume",
            Unit::M3,
            "Gas volume of the bag (membrane volume plus gas.inner_volume)",
            Output::Volume,
        ),
        (
            "gas.temperature",
            Unit::K,
            "Gas temperature in the bag",
            Output::Temperature,
        ),
        ("gas.mass", Unit::Kg, "Gas mass in the bag", Output::Mass),
        (
            "spring.height",
            Unit::M,
            if is_convoluted(s) {
                "Height of the top plate above the bottom plate in the committed state"
            } else {
                "Height of the top plate above the piston base in the committed state"
            },
            Output::Height,
        ),
        (
            "spring.effective_area",
            Unit::M2,
            "Effective area top.fz / gas.pressure_gauge",
            Output::EffectiveArea,
        ),
        (
            "spring.volumetric_area",
            Unit::M2,
            "Volumetric area A_v = dV/d(top.z) (= -dV/dz for the compression z): the bag's volume change per plate height along the quasi-static path, the gas responding instantaneously (not the constant-pressure value)",
            Output::VolumetricArea,
        ),
        (
            "spring.stiffness",
            Unit::NPerM,
            "Quasi-static stiffness -d(top.fz)/d(top.z) (compression positive) with the gas's instantaneous response (polytropic law; adiabatic for the energy law; bag only with a reservoir)",
            Output::Stiffness,
        ),
        (
            "bellows.lobe_radius",
            Unit::M,
            "Largest radius of the bellows (outer radius of the lobe)",
            Output::LobeRadius,
        ),
    ];
    for (name, unit, what, role) in outs {
        if table && *role == Output::LobeRadius {
            continue;
        }
        io.output(name.to_string(), *unit, what.to_string(), *role);
    }
    if s.reservoir.is_some() {
        io.output(
            "reservoir.pressure".into(),
            Unit::Pa,
            "Absolute gas pressure in the reservoir".into(),
            Output::ReservoirPressure,
        );
    }
    let energies: &[(&str, &str, Output)] = &[
        (
            "energy.strain",
            "Strain energy of the wall",
            Output::StrainEnergy,
        ),
        (
            "energy.kinetic",
            "Kinetic energy of the wall",
            Output::KineticEnergy,
        ),
        (
            "energy.gas",
            "Gas energy relative to the ambient, U + p_a (V - V_charge) (U: internal energy m c_v T of the energy law; for the polytropic law the potential with dU = -p dV, zero at the charge): without heat and flow losses it changes by -(p - p_a) dV, the work of the gauge pressure",
            Output::GasEnergy,
        ),
        (
            "energy.plate_work",
            "Work done by the top plate on the spring since the start",
            Output::PlateWork,
        ),
        (
            "energy.dissipated",
            "Energy that left the system since the start: heat to the ambient, flow losses and contact damping (the integrator's numerical dissipation is the rest of the balance)",
            Output::Dissipated,
        ),
    ];
    for (name, what, role) in energies {
        if table && matches!(role, Output::StrainEnergy | Output::KineticEnergy) {
            continue;
        }
        io.output(name.to_string(), Unit::J, what.to_string(), *role);
    }
    io
}

/// Parameter presets of an air spring (FMI-LS-REF parameter sets, [`crate::ls_ref`]): the
/// isothermal gas (n = 1), the energy-balance gas law, and 80 % of the design pressure.
pub fn presets(_s: &AirSpringScene) -> Vec<crate::ls_ref::Preset> {
    use crate::ls_ref::{
        Preset,
        PresetValue::{Scale, Set},
    };
    vec![
        Preset {
            name: "isothermal",
            description: "isothermal gas: gas.polytropic_exponent = 1".into(),
            changes: vec![(GAS_POLYTROPIC_EXPONENT, Set(Value::Real(1.0)))],
        },
        Preset {
            name: "energy_law",
            description: "gas law from the energy balance (gas.model = 2)".into(),
            changes: vec![(GAS_MODEL, Set(Value::Integer(2)))],
        },
        Preset {
            name: "pressure_low",
            description: "design pressure 80 % of the default".into(),
            changes: vec![(GAS_PRESSURE_DESIGN, Scale(0.8))],
        },
    ]
}

/// Smoke test of an air spring: the plate rises by up to 2 mm and back (`top.z` and,
/// consistently, `top.vz`); the other plate inputs stay at their start values.
pub fn smoke_test(_s: &AirSpringScene) -> crate::ls_ref::SmokeTest {
    use crate::ls_ref::{Shape, SmokeTest, Stimulus};
    SmokeTest::with(vec![
        Stimulus {
            input: "top.z".into(),
            amplitude: 1e-3,
            shape: Shape::Excursion,
        },
        Stimulus {
            input: "top.vz".into(),
            amplitude: 1e-3,
            shape: Shape::Rate,
        },
    ])
}

/// The knobs `flexfmu advise` varies: the fidelity level (a family: the shell, the
/// axisymmetric membrane and the effective-area table converge to different answers; a level
/// whose scene lacks its tables is left out with the reason), the meridional and
/// circumferential element counts (together by level; even counts stay even) and the solver
/// knobs.
///
/// The counts apply where they exist: the meridional count to levels 1 and 2, the
/// circumferential count to the shell level only; the table level has no count (its
/// resolution is that of the membrane run the table was generated from), so only its step and
/// integrator are varied.
pub fn knobs(_s: &AirSpringScene) -> Vec<crate::advise::Knob> {
    use crate::advise::{Knob, KnobRole, solver_knobs};
    let mut k = vec![
        Knob::new(MODEL_FIDELITY, KnobRole::Family(&[1, 2, 3])),
        Knob::new(MESH_N_MERIDIONAL, KnobRole::Count { min: 4 }).only_for(&[1, 2]),
        Knob::new(MESH_N_CIRCUMFERENTIAL, KnobRole::Count { min: 4 }).only_for(&[1]),
    ];
    k.extend(solver_knobs());
    k
}

/// The heights of a table generated for `flexfmu advise` from a membrane scene, as fractions
/// of the design height: 0.72 to 1.28 in 29 steps (the shipped `air_spring_table.toml`,
/// 0.18 to 0.32 m at the 0.25 m design height).
pub const ADVISE_TABLE_HEIGHTS: (f64, f64, usize) = (0.72, 1.28, 29);

/// The scene of fidelity level `code` derived from a scene of another level (for
/// `flexfmu advise`): the table level from a membrane or shell scene is generated by
/// [`super::table::generate`] (the membrane level at the scene's meridional count, heights
/// [`ADVISE_TABLE_HEIGHTS`] of the design height, at the design pressure); the membrane and
/// shell levels from any scene are its tables with the fidelity set, the `[table]` removed and
/// the circumferential count kept for the shell level only. `None` for the scene's own level.
pub fn family_scene(s: &AirSpringScene, text: &str, code: i32) -> Option<Result<String, String>> {
    if i64::from(code) == s.model.fidelity {
        return None;
    }
    let name = format!("{}_level{code}", s.fmu.model_name);
    if code == 3 {
        if is_table(s) {
            return None;
        }
        let mut membrane = s.clone();
        membrane.model.fidelity = 2;
        membrane.mesh.n_circumferential = None;
        let text = if is_shell(s) {
            match toml::to_string(&membrane) {
                Ok(t) => t,
                Err(e) => return Some(Err(e.to_string())),
            }
        } else {
            text.to_string()
        };
        let (lo, hi, n) = ADVISE_TABLE_HEIGHTS;
        let h0 = s.spring.design_height;
        let heights: Vec<f64> = (0..n)
            .map(|i| h0 * (lo + (hi - lo) * i as f64 / (n - 1) as f64))
            .collect();
        return Some(super::table::generate(
            &text,
            &heights,
            None,
            None,
            &name,
            &mut |_, _| {},
        ));
    }
    let mut out = s.clone();
    out.model.fidelity = i64::from(code);
    out.table = None;
    out.fmu.model_name = name;
    if code != 1 {
        out.mesh.n_circumferential = None;
    }
    Some(toml::to_string(&out).map_err(|e| e.to_string()))
}
