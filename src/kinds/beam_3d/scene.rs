//! Kind `beam_3d`: checks of the tables (centre line, supports, loads, probes), parameters,
//! inputs and outputs, and what each input and output means to the model.

use super::Beam3dScene;
use crate::kinds::KindIo;
use crate::kinds::energy::{EnergyKind, declare_energy_outputs};
use crate::scene::params::{Check, ParamDef, gravity_params_3d, int_param, names::MESH_N_ELEMENTS};
use crate::scene::tables::{ProbeQuantity, SupportKind};
use crate::scene::validate::{check_fraction, check_identifier, reject_repeated};
use crate::units::Unit;
use crate::variables::Value;

/// What an input of a 3D beam drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Input {
    /// Component `axis` (0 = x, 1 = y, 2 = z) of the force of point load `load` [N].
    Load {
        /// Index into the scene's loads.
        load: usize,
        /// 0 = x, 1 = y, 2 = z.
        axis: usize,
    },
    /// Component `axis` of the moment of point load `load` [N m].
    Moment {
        /// Index into the scene's loads.
        load: usize,
        /// 0 = x, 1 = y, 2 = z.
        axis: usize,
    },
}

/// What an output of a 3D beam reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// A probe quantity.
    Probe {
        /// Index into the scene's probes.
        probe: usize,
        /// Position, velocity, rotation or direction component.
        quantity: ProbeQuantity,
    },
    /// An energy.
    Energy(EnergyKind),
}

/// Parameter names of the 3D beam (public interface: never rename silently).
pub mod names {
    /// Axial stiffness [N].
    pub const SECTION_EA: &str = "section.EA";
    /// Shear stiffness along local y [N].
    pub const SECTION_GAY: &str = "section.GAy";
    /// Shear stiffness along local z [N].
    pub const SECTION_GAZ: &str = "section.GAz";
    /// Torsional stiffness [N m2].
    pub const SECTION_GJ: &str = "section.GJ";
    /// Bending stiffness about local y [N m2].
    pub const SECTION_EIY: &str = "section.EIy";
    /// Bending stiffness about local z [N m2].
    pub const SECTION_EIZ: &str = "section.EIz";
    /// Mass per length [kg/m].
    pub const SECTION_RHOA: &str = "section.rhoA";
    /// Polar rotary inertia per length [kg m].
    pub const SECTION_RHOJX: &str = "section.rhoJx";
    /// Rotary inertia per length about local y [kg m].
    pub const SECTION_RHOIY: &str = "section.rhoIy";
    /// Rotary inertia per length about local z [kg m].
    pub const SECTION_RHOIZ: &str = "section.rhoIz";
    /// Local beam theory (Integer: 1 = Euler–Bernoulli, 2 = Timoshenko).
    pub const ELEMENT_THEORY: &str = "element.theory";
    /// Mass model (Integer: 1 = three lumped masses, 2 = consistent).
    pub const ELEMENT_MASS: &str = "element.mass";
}

use names::*;

fn finite3(v: &[f64; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Euclidean norm, scaled so that components up to f64::MAX do not overflow.
fn norm3(v: &[f64; 3]) -> f64 {
    let m = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    m * v.iter().map(|x| (x / m) * (x / m)).sum::<f64>().sqrt()
}

/// Problems of a 3D-beam scene: required tables, centre line, supports, loads, probes.
pub fn check(s: &Beam3dScene) -> Result<(), Vec<String>> {
    let mut errs = Vec::new();
    {
        let c = &s.centreline;
        if !finite3(&c.start) {
            errs.push("centreline.start: must be finite numbers".into());
        }
        if let Some(z) = &c.section_z
            && (!finite3(z) || norm3(z) == 0.0)
        {
            errs.push("centreline.section_z: must be a finite non-zero vector".into());
        }
        if c.segments.is_empty() {
            errs.push("centreline.segments: give at least one piece".into());
        }
        for (i, seg) in c.segments.iter().enumerate() {
            let key = format!("centreline.segments[{i}]");
            match &seg.direction {
                Some(d) if !finite3(d) || norm3(d) == 0.0 => {
                    errs.push(format!("{key}.direction: must be a finite non-zero vector"))
                }
                None if i == 0 => errs.push(format!(
                    "{key}.direction: required for the first piece (the start tangent)"
                )),
                _ => {}
            }
            let arc = seg.radius.is_some() || seg.angle_deg.is_some() || seg.bend_axis.is_some();
            match (seg.length, arc) {
                (Some(l), false) => {
                    if !(l.is_finite() && l > 0.0) {
                        errs.push(format!("{key}.length = {l}: must be positive"));
                    }
                }
                (None, true) => {
                    match seg.radius {
                        Some(r) if r.is_finite() && r > 0.0 => {}
                        _ => errs.push(format!("{key}.radius: an arc needs a positive radius")),
                    }
                    match seg.angle_deg {
                        Some(a) if a.is_finite() && a > 0.0 && a <= 360.0 => {}
                        _ => errs.push(format!(
                            "{key}.angle_deg: an arc needs an angle in (0, 360] degrees"
                        )),
                    }
                    match &seg.bend_axis {
                        Some(b) if finite3(b) && norm3(b) > 0.0 => {}
                        _ => errs.push(format!(
                            "{key}.bend_axis: an arc needs the (non-zero) axis its tangent turns about"
                        )),
                    }
                }
                (Some(_), true) => errs.push(format!(
                    "{key}: give either length (straight piece) or radius, angle_deg and bend_axis (arc), not both"
                )),
                (None, false) => errs.push(format!(
                    "{key}: give length (straight piece) or radius, angle_deg and bend_axis (arc)"
                )),
            }
        }
    }
    let at_ok = |key: String, at: f64, errs: &mut Vec<String>| {
        check_fraction(&key, at, "the centre-line length", errs)
    };
    let name_ok =
        |key: String, name: &str, errs: &mut Vec<String>| check_identifier(&key, name, errs);
    for (i, sup) in s.supports.iter().enumerate() {
        let key = format!("supports[{i}]");
        at_ok(key.clone(), sup.at, &mut errs);
        if sup.kind == SupportKind::Roller || sup.fixed.is_some() {
            errs.push(format!(
                "{key}: 3D beams support kind = \"clamp\" (position and orientation fixed) or \"pin\" (position fixed)"
            ));
        }
    }
    for (i, l) in s.loads.iter().enumerate() {
        let key = format!("loads[{i}]");
        name_ok(key.clone(), &l.name, &mut errs);
        at_ok(key.clone(), l.at, &mut errs);
        if ![l.fx, l.fy, l.fz, l.mx, l.my, l.mz]
            .iter()
            .all(|v| v.is_finite())
        {
            errs.push(format!("{key}: fx, fy, fz, mx, my, mz must be finite"));
        }
    }
    for (i, p) in s.probes.iter().enumerate() {
        let key = format!("probes[{i}]");
        name_ok(key.clone(), &p.name, &mut errs);
        at_ok(key.clone(), p.at, &mut errs);
        if p.outputs.is_empty() {
            errs.push(format!(
                "{key}.outputs: empty; list at least one of x, y, z, vx, vy, vz, rx, ry, rz, tx, ty, tz, wx, wy, wz"
            ));
        }
        reject_repeated(&key, &p.outputs, &mut errs);
    }
    if errs.is_empty() { Ok(()) } else { Err(errs) }
}

/// Parameters of a 3D-beam scene (the tables exist: [`check`] passed).
pub fn params(s: &Beam3dScene) -> Result<Vec<ParamDef>, String> {
    let (sec, mesh) = (&s.section, &s.mesh);
    let real = |v: f64| Value::Real(v);
    let p =
        |name, v, unit, what: &str, check| ParamDef::new(name, real(v), Some(unit), what, check);
    let mut defs = vec![
        p(
            SECTION_EA,
            sec.EA,
            Unit::N,
            "Axial stiffness EA",
            Check::Positive,
        ),
        p(
            SECTION_GAY,
            sec.GAy,
            Unit::N,
            "Shear stiffness k G A for deflection along local y (Timoshenko theory)",
            Check::Positive,
        ),
        p(
            SECTION_GAZ,
            sec.GAz,
            Unit::N,
            "Shear stiffness k G A for deflection along local z (Timoshenko theory)",
            Check::Positive,
        ),
        p(
            SECTION_GJ,
            sec.GJ,
            Unit::NM2,
            "Torsional stiffness GJ",
            Check::Positive,
        ),
        p(
            SECTION_EIY,
            sec.EIy,
            Unit::NM2,
            "Bending stiffness about local y (deflection along local z)",
            Check::Positive,
        ),
        p(
            SECTION_EIZ,
            sec.EIz,
            Unit::NM2,
            "Bending stiffness about local z (deflection along local y)",
            Check::Positive,
        ),
        p(
            SECTION_RHOA,
            sec.rhoA,
            Unit::KgPerM,
            "Mass per length",
            Check::Positive,
        ),
        p(
            SECTION_RHOJX,
            sec.rhoJx,
            Unit::KgM,
            "Polar rotary inertia per length (rho J; at most rhoIy + rhoIz)",
            Check::Positive,
        ),
        p(
            SECTION_RHOIY,
            sec.rhoIy,
            Unit::KgM,
            "Rotary inertia per length about local y (rho I_y)",
            Check::NonNegative,
        ),
        p(
            SECTION_RHOIZ,
            sec.rhoIz,
            Unit::KgM,
            "Rotary inertia per length about local z (rho I_z)",
            Check::NonNegative,
        ),
        ParamDef::new(
            MESH_N_ELEMENTS,
            Value::Integer(int_param(mesh.n_elements, MESH_N_ELEMENTS)?),
            None,
            "Number of elements along the whole centre line (shared among its pieces by length)",
            Check::IntRange(1, 100_000),
        ),
        ParamDef::new(
            ELEMENT_THEORY,
            Value::Integer(s.element.theory.unwrap_or(2)),
            None,
            "Local beam theory: 1 = Euler-Bernoulli, 2 = Timoshenko",
            Check::IntRange(1, 2),
        ),
        ParamDef::new(
            ELEMENT_MASS,
            Value::Integer(s.element.mass.unwrap_or(1)),
            None,
            "Inertia: 1 = three lumped masses per element (ends and mid-point), 2 = consistent",
            Check::IntRange(1, 2),
        ),
    ];
    defs.extend(gravity_params_3d(s.gravity.as_ref()));
    Ok(defs)
}

/// Inputs (force and moment components of the loads) and outputs (probe quantities,
/// energies) of a 3D-beam scene.
pub fn io(s: &Beam3dScene) -> KindIo<Input, Output> {
    let mut io = KindIo::default();
    for (i, l) in s.loads.iter().enumerate() {
        let how = if l.follower {
            "follower: global components in the reference configuration, rotating with the node"
        } else {
            "fixed direction"
        };
        let starts = [l.fx, l.fy, l.fz, l.mx, l.my, l.mz];
        for (k, comp) in ["fx", "fy", "fz", "mx", "my", "mz"].into_iter().enumerate() {
            let axis = ["x", "y", "z"][k % 3];
            let (unit, what, role) = if k < 3 {
                (Unit::N, "Force", Input::Load { load: i, axis: k })
            } else {
                (
                    Unit::NM,
                    "Moment",
                    Input::Moment {
                        load: i,
                        axis: k - 3,
                    },
                )
            };
            io.input(
                format!("{}.{comp}", l.name),
                starts[k],
                unit,
                format!(
                    "{what} about/along {axis} at {} of the centre-line length ({how})",
                    l.at
                ),
                role,
            );
        }
    }
    for (i, p) in s.probes.iter().enumerate() {
        for q in &p.outputs {
            let (suffix, unit, what) = q.declaration();
            io.output(
                format!("{}.{suffix}", p.name),
                unit,
                format!("{what} of the node at {} of the centre-line length", p.at),
                Output::Probe {
                    probe: i,
                    quantity: *q,
                },
            );
        }
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

/// Smoke test of a 3D beam: the first load's `fz` rises smoothly by the force that bends a
/// straight cantilever of the centre line's length by 0.1 % of it,
/// `F = 2e-3 L · 3 EIy / L³` (Euler–Bernoulli tip stiffness), and back.
pub fn smoke_test(s: &Beam3dScene) -> crate::ls_ref::SmokeTest {
    use crate::ls_ref::{Shape, SmokeTest, Stimulus};
    let l: f64 = s
        .centreline
        .segments
        .iter()
        .map(|g| match (g.length, g.radius, g.angle_deg) {
            (Some(l), _, _) => l,
            (None, Some(r), Some(a)) => r * a.to_radians(),
            _ => 0.0,
        })
        .sum();
    match s.loads.first() {
        Some(load) if l > 0.0 => SmokeTest::with(vec![Stimulus {
            input: format!("{}.fz", load.name),
            amplitude: 0.5 * 2e-3 * l * 3.0 * s.section.EIy / l.powi(3),
            shape: Shape::Excursion,
        }]),
        _ => SmokeTest::default(),
    }
}

/// The knobs `flexfmu advise` varies: the beam theory (a family: Euler–Bernoulli and
/// Timoshenko converge to different answers), the element count (at least 1), the mass
/// matrix (lumped or consistent, one converged answer) and the solver knobs.
pub fn knobs(_s: &Beam3dScene) -> Vec<crate::advise::Knob> {
    use crate::advise::{Knob, KnobRole, solver_knobs};
    let mut k = vec![
        Knob::new(ELEMENT_THEORY, KnobRole::Family(&[1, 2])),
        Knob::new(MESH_N_ELEMENTS, KnobRole::Count { min: 1 }),
        Knob::new(ELEMENT_MASS, KnobRole::Variant(&[1, 2])),
    ];
    k.extend(solver_knobs());
    k
}
