//! Kind `shell`: checks of the tables (geometry, mesh keys, supports, loads, probes),
//! parameters, inputs and outputs, and what each input and output means to the model.

use super::{RingAt, RingQuantity, ShellScene};
use crate::kinds::KindIo;
use crate::kinds::energy::{EnergyKind, declare_energy_outputs};
use crate::meshers::plate::PlateEdge;
use crate::scene::params::{Check, ParamDef, gravity_params_3d, int_param, material_params};
use crate::scene::tables::ProbeQuantity;
use crate::scene::validate::{check_identifier, reject_repeated};
use crate::units::Unit;
use crate::variables::Value;

/// What an input of a shell drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Input {
    /// Component `comp` (0-2 force x, y, z [N]; 3-5 moment about x, y, z [N m]) of load
    /// `load`: the scene's point loads first, then its line loads.
    Load {
        /// Index into the point loads followed by the line loads.
        load: usize,
        /// 0..6: fx, fy, fz, mx, my, mz.
        comp: usize,
    },
    /// The uniform pressure [Pa].
    Pressure,
    /// Component `component` of motion port `port`: 0-2 position x, y, z of its reference
    /// point [m], 3-5 velocity x, y, z [m/s].
    Motion {
        /// Index into the scene's motion ports.
        port: usize,
        /// 0..6: x, y, z, vx, vy, vz.
        component: usize,
    },
}

/// What an output of a shell reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// A probe quantity at a node.
    Probe {
        /// Index into the scene's probes.
        probe: usize,
        /// Position, velocity, rotation or angular-velocity component.
        quantity: ProbeQuantity,
    },
    /// A quantity of a ring.
    Ring {
        /// Index into the scene's ring probes.
        probe: usize,
        /// Mean radius or mean z.
        quantity: RingQuantity,
    },
    /// `shell.volume` [m3].
    Volume,
    /// `shell.length` [m].
    Length,
    /// An energy.
    Energy(EnergyKind),
    /// Force [N] the shell exerts on the driver of motion port `port` along global `axis`.
    Reaction {
        /// Index into the scene's motion ports.
        port: usize,
        /// 0..3: x, y, z.
        axis: usize,
    },
}

/// Parameter and output names of the shell (public interface: never rename silently).
pub mod names {
    /// Thickness [m].
    pub const SHELL_THICKNESS: &str = "shell.thickness";
    /// Plate: elements along x (Integer).
    pub const MESH_N_X: &str = "mesh.n_x";
    /// Plate: element rows along y (Integer).
    pub const MESH_N_Y: &str = "mesh.n_y";
    /// Surface of revolution: elements around a ring (Integer).
    pub const MESH_N_CIRCUMFERENTIAL: &str = "mesh.n_circumferential";
    /// Surface of revolution: element rings along the meridian (Integer).
    pub const MESH_N_MERIDIONAL: &str = "mesh.n_meridional";
    /// Bending shape functions (Integer: 1 = V1, 2 = V2).
    pub const ELEMENT_BENDING: &str = "element.bending";
    /// Geometric stiffness on (Boolean).
    pub const ELEMENT_GEOMETRIC_STIFFNESS: &str = "element.geometric_stiffness";
    /// Drilling stiffness ratio [1].
    pub const ELEMENT_DRILLING_STIFFNESS: &str = "element.drilling_stiffness";
    /// Support of the plate edge x0 (Integer: 0 free, 1 simply supported, 2 clamped).
    pub const SUPPORT_X0: &str = "support.x0";
    /// Support of the plate edge x1.
    pub const SUPPORT_X1: &str = "support.x1";
    /// Support of the plate edge y0.
    pub const SUPPORT_Y0: &str = "support.y0";
    /// Support of the plate edge y1.
    pub const SUPPORT_Y1: &str = "support.y1";
    /// Output: enclosed volume [m3].
    pub const SHELL_VOLUME: &str = "shell.volume";
    /// Output: length between the poles or end rings [m].
    pub const SHELL_LENGTH: &str = "shell.length";
}

use names::*;

/// The support parameter of a plate edge.
pub fn support_param(e: PlateEdge) -> &'static str {
    match e {
        PlateEdge::X0 => SUPPORT_X0,
        PlateEdge::X1 => SUPPORT_X1,
        PlateEdge::Y0 => SUPPORT_Y0,
        PlateEdge::Y1 => SUPPORT_Y1,
    }
}

/// Input suffixes of a motion port: position x, y, z [m] and velocity x, y, z [m/s] of its
/// reference point.
pub const MOTION_INPUTS: [&str; 6] = ["x", "y", "z", "vx", "vy", "vz"];

/// Output suffixes of a motion port: the force on the driver [N].
pub const REACTIONS: [&str; 3] = ["fx", "fy", "fz"];

/// Largest number of elements of a shell mesh.
pub const MAX_ELEMENTS: i64 = 1_000_000;

fn finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Problems of a point `at` of the entry `key` (2 numbers on a plate, else 3).
fn check_point(key: &str, at: &[f64], plate: bool, errs: &mut Vec<String>) {
    let n_ok = at.len() == 3 || (plate && at.len() == 2);
    if !n_ok {
        errs.push(format!(
            "{key}.at: give the node's position as [x, y, z]{} [m], not {} numbers",
            if plate { " or [x, y]" } else { "" },
            at.len()
        ));
    } else if !finite(at) {
        errs.push(format!("{key}.at: must be finite numbers"));
    }
}

/// Problems of a ring reference of the entry `key`.
fn check_ring(key: &str, ring: &RingAt, errs: &mut Vec<String>) {
    match ring {
        RingAt::Arc(s) if !(s.is_finite() && *s >= 0.0) => errs.push(format!(
            "{key}.ring = {s}: give the arc length along the meridian (>= 0, in m), \"first\" or \"last\""
        )),
        RingAt::Name(n) if n != "first" && n != "last" => errs.push(format!(
            "{key}.ring = \"{n}\": give \"first\", \"last\" or the arc length along the meridian [m]"
        )),
        _ => {}
    }
}

/// Problems of a shell scene: geometry (exactly one of `[plate]`, `[meridian]`), mesh keys,
/// supports, loads, probes and outputs that fit the geometry.
pub fn check(s: &ShellScene) -> Result<(), Vec<String>> {
    let mut errs = Vec::new();
    let m = &s.mesh;
    let plate = s.plate.is_some();
    match (&s.plate, &s.meridian) {
        (Some(_), Some(_)) => errs.push(
            "plate, meridian: give either [plate] (a flat plate) or [meridian] (a surface of revolution), not both".into(),
        ),
        (None, None) => errs.push(
            "plate, meridian: give [plate] (a flat plate) or [meridian] (a surface of revolution)".into(),
        ),
        _ => {}
    }
    let need = |key: &str, v: Option<i64>, what: &str, errs: &mut Vec<String>| {
        if v.is_none() {
            errs.push(format!("{key}: required for {what}"));
        }
    };
    let refuse = |key: &str, v: Option<i64>, what: &str, errs: &mut Vec<String>| {
        if v.is_some() {
            errs.push(format!("{key}: only for {what}"));
        }
    };
    if let Some(p) = &s.plate {
        need(MESH_N_X, m.n_x, "a plate", &mut errs);
        need(MESH_N_Y, m.n_y, "a plate", &mut errs);
        refuse(
            MESH_N_CIRCUMFERENTIAL,
            m.n_circumferential,
            "a surface of revolution ([meridian]); a plate takes mesh.n_x and mesh.n_y",
            &mut errs,
        );
        refuse(
            MESH_N_MERIDIONAL,
            m.n_meridional,
            "a surface of revolution ([meridian]); a plate takes mesh.n_x and mesh.n_y",
            &mut errs,
        );
        for (key, v) in [
            ("plate.length_x", Some(p.length_x)),
            ("plate.length_y", Some(p.length_y)),
            ("plate.width_top", p.width_top),
        ] {
            if let Some(v) = v
                && !(v.is_finite() && v > 0.0)
            {
                errs.push(format!("{key} = {v}: must be a positive length [m]"));
            }
        }
    }
    if let Some(mer) = &s.meridian {
        need(
            MESH_N_CIRCUMFERENTIAL,
            m.n_circumferential,
            "a surface of revolution",
            &mut errs,
        );
        need(
            MESH_N_MERIDIONAL,
            m.n_meridional,
            "a surface of revolution",
            &mut errs,
        );
        refuse(
            MESH_N_X,
            m.n_x,
            "a plate ([plate]); a surface of revolution takes mesh.n_circumferential and mesh.n_meridional",
            &mut errs,
        );
        refuse(
            MESH_N_Y,
            m.n_y,
            "a plate ([plate]); a surface of revolution takes mesh.n_circumferential and mesh.n_meridional",
            &mut errs,
        );
        if !finite(&mer.start) || mer.start[0] < 0.0 {
            errs.push("meridian.start: must be finite [r, z] with r >= 0 [m]".into());
        }
        if mer.pieces.is_empty() {
            errs.push("meridian.pieces: give at least one piece".into());
        }
        for (i, piece) in mer.pieces.iter().enumerate() {
            let key = format!("meridian.pieces[{i}]");
            match &piece.direction {
                Some(d) if !finite(d) || d[0].hypot(d[1]) == 0.0 => errs.push(format!(
                    "{key}.direction: must be a finite non-zero [dr, dz]"
                )),
                None if i == 0 => errs.push(format!(
                    "{key}.direction: required for the first piece (the start direction [dr, dz])"
                )),
                _ => {}
            }
            let arc = piece.radius.is_some() || piece.angle_deg.is_some();
            match (piece.length, arc) {
                (Some(l), false) => {
                    if !(l.is_finite() && l > 0.0) {
                        errs.push(format!("{key}.length = {l}: must be positive"));
                    }
                }
                (None, true) => {
                    match piece.radius {
                        Some(r) if r.is_finite() && r > 0.0 => {}
                        _ => errs.push(format!("{key}.radius: an arc needs a positive radius")),
                    }
                    match piece.angle_deg {
                        Some(a) if a.is_finite() && a != 0.0 && a.abs() <= 360.0 => {}
                        _ => errs.push(format!(
                            "{key}.angle_deg: an arc needs a non-zero angle in [-360, 360] degrees"
                        )),
                    }
                }
                (Some(_), true) => errs.push(format!(
                    "{key}: give either length (straight piece) or radius and angle_deg (arc), not both"
                )),
                (None, false) => errs.push(format!(
                    "{key}: give length (straight piece) or radius and angle_deg (arc)"
                )),
            }
        }
    }
    let only_plate = |key: String, errs: &mut Vec<String>| {
        errs.push(format!(
            "{key}: plate edges exist only on a plate ([plate]); a surface of revolution has rings"
        ))
    };
    let only_revolution = |key: String, errs: &mut Vec<String>| {
        errs.push(format!(
            "{key}: rings exist only on a surface of revolution ([meridian]); a plate has edges"
        ))
    };
    if s.support.is_some() && !plate && s.meridian.is_some() {
        only_plate("support".into(), &mut errs);
    }
    for (i, r) in s.ring_supports.iter().enumerate() {
        let key = format!("ring_supports[{i}]");
        if plate {
            only_revolution(key.clone(), &mut errs);
        }
        check_ring(&key, &r.ring, &mut errs);
    }
    for (i, p) in s.point_supports.iter().enumerate() {
        check_point(&format!("point_supports[{i}]"), &p.at, plate, &mut errs);
    }
    for (i, l) in s.loads.iter().enumerate() {
        let key = format!("loads[{i}]");
        check_identifier(&key, &l.name, &mut errs);
        check_point(&key, &l.at, plate, &mut errs);
        if !finite(&l.start()) {
            errs.push(format!("{key}: fx, fy, fz, mx, my, mz must be finite"));
        }
    }
    for (i, l) in s.line_loads.iter().enumerate() {
        let key = format!("line_loads[{i}]");
        check_identifier(&key, &l.name, &mut errs);
        match (&l.edge, &l.ring) {
            (Some(_), None) if !plate => only_plate(format!("{key}.edge"), &mut errs),
            (None, Some(r)) => {
                if plate {
                    only_revolution(format!("{key}.ring"), &mut errs);
                }
                check_ring(&key, r, &mut errs);
            }
            (Some(_), Some(_)) => errs.push(format!(
                "{key}: give edge (a plate edge) or ring (a ring of a surface of revolution), not both"
            )),
            (None, None) => errs.push(format!(
                "{key}: give edge = \"x0\", \"x1\", \"y0\" or \"y1\" (plate) or ring (surface of revolution)"
            )),
            _ => {}
        }
        if !finite(&l.start()) {
            errs.push(format!("{key}: fx, fy, fz, mx, my, mz must be finite"));
        }
    }
    if let Some(p) = &s.pressure {
        check_identifier("pressure", &p.name, &mut errs);
        if !p.value.is_finite() {
            errs.push(format!("pressure.value = {}: must be finite", p.value));
        }
    }
    for (i, p) in s.probes.iter().enumerate() {
        let key = format!("probes[{i}]");
        check_identifier(&key, &p.name, &mut errs);
        check_point(&key, &p.at, plate, &mut errs);
        if p.outputs.is_empty() {
            errs.push(format!(
                "{key}.outputs: empty; list at least one of x, y, z, vx, vy, vz, rx, ry, rz, wx, wy, wz"
            ));
        }
        use ProbeQuantity::*;
        for q in p.outputs.iter().filter(|q| matches!(q, Tx | Ty | Tz)) {
            errs.push(format!(
                "{key}.outputs: {q:?} (a beam axis direction) is for beams; shell probes give x, y, z, vx, vy, vz, rx, ry, rz, wx, wy, wz"
            ));
        }
        reject_repeated(&key, &p.outputs, &mut errs);
    }
    for (i, p) in s.ring_probes.iter().enumerate() {
        let key = format!("ring_probes[{i}]");
        check_identifier(&key, &p.name, &mut errs);
        if plate {
            only_revolution(key.clone(), &mut errs);
        }
        check_ring(&key, &p.ring, &mut errs);
        if p.outputs.is_empty() {
            errs.push(format!("{key}.outputs: empty; list radius and/or z"));
        }
        reject_repeated(&key, &p.outputs, &mut errs);
    }
    for (i, m) in s.motions.iter().enumerate() {
        let key = format!("motions[{i}]");
        check_identifier(&key, &m.name, &mut errs);
        match (&m.edge, &m.ring, &m.at) {
            (Some(_), None, None) => {
                if !plate {
                    only_plate(format!("{key}.edge"), &mut errs);
                }
            }
            (None, Some(r), None) => {
                if plate {
                    only_revolution(format!("{key}.ring"), &mut errs);
                }
                check_ring(&key, r, &mut errs);
            }
            (None, None, Some(at)) => check_point(&key, at, plate, &mut errs),
            _ => errs.push(format!(
                "{key}: give exactly one of edge (a plate edge), ring (a ring of a surface of revolution) or at (one node)"
            )),
        }
    }
    check_variable_names(s, &mut errs);
    if plate && (s.outputs.volume || s.outputs.length) {
        errs.push(
            "outputs.volume, outputs.length: for a surface of revolution ([meridian]) only".into(),
        );
    }
    if errs.is_empty() { Ok(()) } else { Err(errs) }
}

/// Records every variable name that two entries declare, naming both entries.
fn check_variable_names(s: &ShellScene, errs: &mut Vec<String>) {
    const LOAD: [&str; 6] = ["fx", "fy", "fz", "mx", "my", "mz"];
    let mut vars: Vec<(String, String)> = Vec::new();
    for (i, l) in s.loads.iter().enumerate() {
        vars.extend(LOAD.map(|c| (format!("{}.{c}", l.name), format!("loads[{i}]"))));
    }
    for (i, l) in s.line_loads.iter().enumerate() {
        vars.extend(LOAD.map(|c| (format!("{}.{c}", l.name), format!("line_loads[{i}]"))));
    }
    if let Some(p) = &s.pressure {
        vars.push((format!("{}.pressure", p.name), "pressure".into()));
    }
    for (i, p) in s.probes.iter().enumerate() {
        for q in &p.outputs {
            vars.push((
                format!("{}.{}", p.name, q.declaration().0),
                format!("probes[{i}]"),
            ));
        }
    }
    for (i, p) in s.ring_probes.iter().enumerate() {
        for q in &p.outputs {
            let suffix = match q {
                RingQuantity::Radius => "radius",
                RingQuantity::Z => "z",
            };
            vars.push((format!("{}.{suffix}", p.name), format!("ring_probes[{i}]")));
        }
    }
    for (i, m) in s.motions.iter().enumerate() {
        for c in MOTION_INPUTS.iter().chain(&REACTIONS) {
            vars.push((format!("{}.{c}", m.name), format!("motions[{i}]")));
        }
    }
    if s.outputs.volume {
        vars.push((SHELL_VOLUME.into(), "outputs.volume".into()));
    }
    if s.outputs.length {
        vars.push((SHELL_LENGTH.into(), "outputs.length".into()));
    }
    let mut seen = std::collections::BTreeMap::new();
    for (name, key) in vars {
        if let Some(first) = seen.get(&name) {
            if *first != key {
                errs.push(format!(
                    "{key}: declares the variable {name}, which {first} declares too; rename one of them"
                ));
            }
        } else {
            seen.insert(name, key);
        }
    }
}

/// Parameters of a shell scene (the tables exist: [`check`] passed).
pub fn params(s: &ShellScene) -> Result<Vec<ParamDef>, String> {
    let mut defs = material_params(&s.material);
    defs.push(ParamDef::new(
        SHELL_THICKNESS,
        Value::Real(s.shell.thickness),
        Some(Unit::M),
        "Shell thickness",
        Check::Positive,
    ));
    let count =
        |name: &'static str, v: Option<i64>, lo: i32, what: &str| -> Result<ParamDef, String> {
            let v = v.ok_or_else(|| format!("{name}: required"))?;
            Ok(ParamDef::new(
                name,
                Value::Integer(int_param(v, name)?),
                None,
                what,
                Check::IntRange(lo, 100_000),
            ))
        };
    let m = &s.mesh;
    if s.plate.is_some() {
        defs.push(count(MESH_N_X, m.n_x, 1, "Elements along x")?);
        defs.push(count(MESH_N_Y, m.n_y, 1, "Element rows along y")?);
    } else {
        defs.push(count(
            MESH_N_CIRCUMFERENTIAL,
            m.n_circumferential,
            3,
            "Elements around every ring",
        )?);
        defs.push(count(
            MESH_N_MERIDIONAL,
            m.n_meridional,
            1,
            "Element rings along the meridian (shared among its pieces by length)",
        )?);
    }
    defs.push(ParamDef::new(
        ELEMENT_BENDING,
        Value::Integer(int_param(s.element.bending, ELEMENT_BENDING)?),
        None,
        "Bending shape functions: 1 = V1 (products of beam Hermite polynomials), 2 = V2 (12-DOF rectangle functions)",
        Check::IntRange(1, 2),
    ));
    defs.push(ParamDef::new(
        ELEMENT_GEOMETRIC_STIFFNESS,
        Value::Boolean(s.element.geometric_stiffness),
        None,
        "Include the geometric (initial-stress) stiffness of the element",
        Check::None,
    ));
    defs.push(ParamDef::new(
        ELEMENT_DRILLING_STIFFNESS,
        Value::Real(s.element.drilling_stiffness),
        Some(Unit::One),
        "Drilling stiffness (rotation about the normal) as a ratio of the membrane shear stiffness G h (small, e.g. 1e-3)",
        Check::Positive,
    ));
    if s.plate.is_some() {
        let sup = s.support.clone().unwrap_or_default();
        for e in PlateEdge::ALL {
            defs.push(ParamDef::new(
                support_param(e),
                Value::Integer(sup.of(e).code()),
                None,
                &format!(
                    "Support of the plate edge {}: 0 = free, 1 = simply supported (translations fixed), 2 = clamped (translations and rotations fixed)",
                    e.name()
                ),
                Check::IntRange(0, 2),
            ));
        }
    }
    defs.extend(gravity_params_3d(s.gravity.as_ref()));
    Ok(defs)
}

fn point_text(at: &[f64]) -> String {
    let v: Vec<String> = at.iter().map(|x| format!("{x}")).collect();
    format!("[{}] m", v.join(", "))
}

fn ring_text(r: &RingAt) -> String {
    match r {
        RingAt::Arc(s) => format!("the ring at arc length {s} m of the meridian"),
        RingAt::Name(n) => format!("the {n} ring"),
    }
}

/// Inputs (load components, pressure, motion ports) and outputs (port reactions, probes,
/// rings, volume, length, energies) of a shell scene.
pub fn io(s: &ShellScene) -> KindIo<Input, Output> {
    let mut io = KindIo::default();
    let declare_load =
        |io: &mut KindIo<Input, Output>, i: usize, name: &str, start: [f64; 6], at: String| {
            for (k, comp) in ["fx", "fy", "fz", "mx", "my", "mz"].into_iter().enumerate() {
                let axis = ["x", "y", "z"][k % 3];
                let (unit, what) = if k < 3 {
                    (Unit::N, "Force along")
                } else {
                    (Unit::NM, "Moment about")
                };
                io.input(
                    format!("{name}.{comp}"),
                    start[k],
                    unit,
                    format!("{what} global {axis} {at} (fixed direction)"),
                    Input::Load { load: i, comp: k },
                );
            }
        };
    for (i, l) in s.loads.iter().enumerate() {
        declare_load(
            &mut io,
            i,
            &l.name,
            l.start(),
            format!("at the node {}", point_text(&l.at)),
        );
    }
    let n_point = s.loads.len();
    for (i, l) in s.line_loads.iter().enumerate() {
        let along = match (&l.edge, &l.ring) {
            (Some(e), _) => format!("along the plate edge {}", e.name()),
            (_, Some(r)) => format!("along {}", ring_text(r)),
            _ => String::new(),
        };
        declare_load(
            &mut io,
            n_point + i,
            &l.name,
            l.start(),
            format!("{along}, total spread over its nodes"),
        );
    }
    if let Some(p) = &s.pressure {
        io.input(
            format!("{}.pressure", p.name),
            p.value,
            Unit::Pa,
            "Uniform pressure on the whole surface along its normal (follower load; +z on a plate, outwards on a closed surface of revolution)".into(),
            Input::Pressure,
        );
    }
    let refs = super::model::motion_references(s);
    // Direct feedthrough at a communication point (`Ports::force`): a reaction moves with
    // every port's prescribed position through the interface Jacobian (positions and
    // velocities: a position set at an earlier communication point is extrapolated with the
    // velocity input), and with the pressure, which loads the port's nodes (loads on port
    // nodes are refused by `Shell::build`).
    let mut deps: Vec<String> = vec![];
    for m in &s.motions {
        deps.extend(MOTION_INPUTS.map(|c| format!("{}.{c}", m.name)));
    }
    if let Some(p) = &s.pressure {
        deps.push(format!("{}.pressure", p.name));
    }
    let deps: Vec<&str> = deps.iter().map(String::as_str).collect();
    for (port, m) in s.motions.iter().enumerate() {
        let what = match (&m.edge, &m.ring, &m.at) {
            (Some(e), ..) => format!(
                "the plate edge {} (reference point: its midpoint)",
                e.name()
            ),
            (_, Some(r), _) => format!(
                "{} (reference point: its centre on the z axis)",
                ring_text(r)
            ),
            (.., Some(at)) => format!("the node at {}", point_text(at)),
            _ => String::new(),
        };
        let start = refs.get(port).copied().unwrap_or([0.0; 3]);
        for (component, suffix) in MOTION_INPUTS.into_iter().enumerate() {
            let axis = ["x", "y", "z"][component % 3];
            let (start, unit, kind) = if component < 3 {
                (start[component], Unit::M, "position")
            } else {
                (0.0, Unit::MPerS, "velocity")
            };
            io.input(
                format!("{}.{suffix}", m.name),
                start,
                unit,
                format!(
                    "Prescribed {kind} {axis} of the reference point of {what}, whose nodes translate rigidly with it, their rotations held (motion port; a position is extrapolated inside a step with the velocity input)"
                ),
                Input::Motion { port, component },
            );
        }
        for (axis, suffix) in REACTIONS.into_iter().enumerate() {
            io.output(
                format!("{}.{suffix}", m.name),
                Unit::N,
                format!(
                    "Force exerted by the shell on the body driving the motion port ({what}), global {} component",
                    ["x", "y", "z"][axis]
                ),
                Output::Reaction { port, axis },
            )
            .depending_on(&deps);
        }
    }
    for (i, p) in s.probes.iter().enumerate() {
        for q in &p.outputs {
            let (suffix, unit, what) = q.declaration();
            io.output(
                format!("{}.{suffix}", p.name),
                unit,
                format!("{what} of the node at {}", point_text(&p.at)),
                Output::Probe {
                    probe: i,
                    quantity: *q,
                },
            );
        }
    }
    for (i, p) in s.ring_probes.iter().enumerate() {
        for q in &p.outputs {
            let (suffix, what) = match q {
                RingQuantity::Radius => ("radius", "Mean distance from the z axis of the nodes of"),
                RingQuantity::Z => ("z", "Mean z of the nodes of"),
            };
            io.output(
                format!("{}.{suffix}", p.name),
                Unit::M,
                format!("{what} {}", ring_text(&p.ring)),
                Output::Ring {
                    probe: i,
                    quantity: *q,
                },
            );
        }
    }
    if s.outputs.volume {
        io.output(
            SHELL_VOLUME.into(),
            Unit::M3,
            "Volume enclosed by the closed surface".into(),
            Output::Volume,
        );
    }
    if s.outputs.length {
        io.output(
            SHELL_LENGTH.into(),
            Unit::M,
            "Distance between the two pole nodes (closed surface) or between the mean z of the first and last rings".into(),
            Output::Length,
        );
    }
    if s.outputs.energy {
        declare_energy_outputs(
            &mut io,
            Output::Energy,
            &[
                (EnergyKind::Kinetic, "Kinetic energy"),
                (
                    EnergyKind::Potential,
                    "Gravity potential energy relative to the origin",
                ),
                (EnergyKind::Strain, "Strain energy"),
                (EnergyKind::Total, "Kinetic + potential + strain energy"),
            ],
        );
    }
    io
}
