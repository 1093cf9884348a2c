//! Kind `beam_2d`: checks of the tables, parameters, inputs and outputs, and what each input
//! and output means to the model.

use super::{Beam2dElementType, Beam2dScene};
use crate::kinds::KindIo;
use crate::kinds::energy::{BODY_ENERGIES, EnergyKind, declare_energy_outputs};
use crate::scene::params::{
    Check, ParamDef, gravity_params_2d, int_param, material_params, names::*,
};
use crate::scene::tables::{ProbeQuantity, SupportKind};
use crate::scene::validate::{check_fraction, check_identifier, reject_repeated};
use crate::units::Unit;
use crate::variables::Value;

/// What an input of a planar beam drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Input {
    /// Component `axis` (0 = x, 1 = y) of the force of point load `load` [N].
    Load {
        /// Index into the scene's loads.
        load: usize,
        /// 0 = x, 1 = y.
        axis: usize,
    },
    /// Prescribed motion of a port: `component` 0, 1 = position x, y [m]; 2, 3 = velocity
    /// x, y [m/s].
    Motion {
        /// Index into the scene's motion ports.
        port: usize,
        /// 0 = x, 1 = y, 2 = vx, 3 = vy.
        component: usize,
    },
}

/// What an output of a planar beam reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// A probe quantity.
    Probe {
        /// Index into the scene's probes.
        probe: usize,
        /// Position or velocity component.
        quantity: ProbeQuantity,
    },
    /// An energy.
    Energy(EnergyKind),
    /// Force exerted by the beam on whatever drives a motion port [N], component `axis`.
    Reaction {
        /// Index into the scene's motion ports.
        port: usize,
        /// 0 = x, 1 = y.
        axis: usize,
    },
}

/// Problems of a planar-beam scene: required tables, supports, loads, probes.
pub fn check(s: &Beam2dScene) -> Result<(), Vec<String>> {
    let mut errs = Vec::new();
    let el = &s.element;
    if el.element_type == Beam2dElementType::AncfCable2d {
        let given = [
            ("shear_rule", el.shear_rule.is_some()),
            ("strain_energy", el.strain_energy.is_some()),
            ("shear_coefficient", el.shear_coefficient.is_some()),
        ];
        for (key, _) in given.iter().filter(|(_, g)| *g) {
            errs.push(format!(
                "element.{key}: applies to the seed-000 element only (type = \"ancf_shear_2d\"); the ANCF cable (type = \"ancf_cable_2d\") has no shear: remove the key"
            ));
        }
    }
    let g = &s.geometry;
    if !g.origin.iter().all(|v| v.is_finite()) || !g.angle_deg.is_finite() {
        errs.push("geometry.origin / geometry.angle_deg: must be finite numbers".into());
    }
    let at_ok =
        |key: String, at: f64, errs: &mut Vec<String>| check_fraction(&key, at, "the length", errs);
    let name_ok =
        |key: String, name: &str, errs: &mut Vec<String>| check_identifier(&key, name, errs);
    for (i, sup) in s.supports.iter().enumerate() {
        let key = format!("supports[{i}]");
        at_ok(key.clone(), sup.at, &mut errs);
        match (sup.kind, sup.fixed) {
            (SupportKind::Roller, None) => errs.push(format!(
                "{key}.fixed: a roller needs the fixed direction, \"x\" or \"y\""
            )),
            (SupportKind::Clamp | SupportKind::Pin, Some(_)) => errs.push(format!(
                "{key}.fixed: only a roller takes a fixed direction"
            )),
            _ => {}
        }
    }
    for (i, l) in s.loads.iter().enumerate() {
        let key = format!("loads[{i}]");
        name_ok(key.clone(), &l.name, &mut errs);
        at_ok(key.clone(), l.at, &mut errs);
        if !l.fx.is_finite() || !l.fy.is_finite() {
            errs.push(format!("{key}: fx and fy must be finite"));
        }
    }
    for (i, m) in s.motions.iter().enumerate() {
        let key = format!("motions[{i}]");
        name_ok(key.clone(), &m.name, &mut errs);
        at_ok(key.clone(), m.at, &mut errs);
    }
    for (i, p) in s.probes.iter().enumerate() {
        let key = format!("probes[{i}]");
        name_ok(key.clone(), &p.name, &mut errs);
        at_ok(key.clone(), p.at, &mut errs);
        if p.outputs.is_empty() {
            errs.push(format!(
                "{key}.outputs: empty; list at least one of x, y, vx, vy"
            ));
        }
        for q in p.outputs.iter().filter(|q| !q.is_planar()) {
            errs.push(format!(
                "{key}.outputs: {q:?} is for 3D beams only; planar probes give x, y, vx, vy"
            ));
        }
        reject_repeated(&key, &p.outputs, &mut errs);
    }
    if errs.is_empty() { Ok(()) } else { Err(errs) }
}

/// Parameters of a planar-beam scene (the tables exist: [`check`] passed).
pub fn params(s: &Beam2dScene) -> Result<Vec<ParamDef>, String> {
    let (m, g, mesh) = (&s.material, &s.geometry, &s.mesh);
    let real = |v: f64| Value::Real(v);
    let mut defs = material_params(m);
    defs.extend([
        ParamDef::new(
            GEOMETRY_LENGTH,
            real(g.length),
            Some(Unit::M),
            "Undeformed length",
            Check::Positive,
        ),
        ParamDef::new(
            GEOMETRY_WIDTH,
            real(g.width),
            Some(Unit::M),
            "Cross-section width (out of plane)",
            Check::Positive,
        ),
        ParamDef::new(
            GEOMETRY_HEIGHT,
            real(g.height),
            Some(Unit::M),
            "Cross-section height",
            Check::Positive,
        ),
        ParamDef::new(
            MESH_N_ELEMENTS,
            Value::Integer(int_param(mesh.n_elements, MESH_N_ELEMENTS)?),
            None,
            "Number of elements",
            Check::IntRange(1, MAX_ELEMENTS as i32),
        ),
        ParamDef::new(
            ELEMENT_TYPE,
            Value::Integer(s.element.element_type.code()),
            None,
            "Element family: 1 = seed-000 shear-deformable ANCF beam, linear, 4 coordinates per node (Kerkkanen, Sopanen & Mikkola 2003; the default); 2 = gradient-deficient ANCF cable, Euler-Bernoulli, cubic Hermite, position and axial slope per node (Gerstmayr & Irschik 2008), with EA = E width height, EI = E width height^3/12, rhoA = rho width height (material.nu and the element.shear_* and element.strain_energy parameters do not apply to it and are ignored)",
            Check::IntRange(1, 2),
        ),
        ParamDef::new(
            ELEMENT_SHEAR_RULE,
            Value::Integer(s.element.shear_rule()),
            None,
            "Shear-energy integration of the seed-000 element (element.type = 1; ignored by the cable): 1 = original 1x1 rule, 2 = the 1x2 fix (Kerkkanen et al. 2003, sections 5 and 7)",
            Check::IntRange(1, 2),
        ),
        ParamDef::new(
            ELEMENT_STRAIN_ENERGY,
            Value::Integer(s.element.strain_energy()),
            None,
            "Strain energy of the seed-000 element (element.type = 1; ignored by the cable): 1 = Eq. 12 (no Poisson coupling), 2 = Lame form of Eqs. 10-11",
            Check::IntRange(1, 2),
        ),
        ParamDef::new(
            ELEMENT_SHEAR_COEFFICIENT,
            real(s.element.shear_coefficient()),
            Some(Unit::One),
            "Shear correction factor k_s of Eq. 12 of the seed-000 element (element.type = 1; ignored by the cable)",
            Check::Positive,
        ),
    ]);
    if let Some(init) = &s.initial {
        defs.push(ParamDef::new(
            INITIAL_ANGULAR_VELOCITY,
            real(init.angular_velocity),
            Some(Unit::RadPerS),
            "Initial rigid rotation of the body about its first end, counter-clockwise",
            Check::Finite,
        ));
    }
    defs.extend(gravity_params_2d(s.gravity.as_ref()));
    Ok(defs)
}

/// Largest `mesh.n_elements` of a planar beam.
const MAX_ELEMENTS: usize = 100_000;

/// Whether a point load at fraction `load_at` of the length puts weight on the node at fraction
/// `node_at` for some element count at which every support and motion port falls on a node
/// (as `model::beam2d` builds the mesh and interpolates loads). The ModelStructure must hold
/// for every value of the fixed parameter `mesh.n_elements`, and must not list more.
fn load_reaches_node(s: &Beam2dScene, load_at: f64, node_at: f64) -> bool {
    (1..=MAX_ELEMENTS).any(|n| {
        let nf = n as f64;
        let on_node = |x: f64| (x * nf - (x * nf).round()).abs() <= 1e-9 * nf;
        if !s.supports.iter().all(|p| on_node(p.at)) || !s.motions.iter().all(|p| on_node(p.at)) {
            return false;
        }
        let node = (node_at * nf).round() as usize;
        let x = load_at * nf;
        let e = (x.floor() as usize).min(n - 1);
        let xi = x - e as f64;
        (e == node && xi != 1.0) || (e + 1 == node && xi != 0.0)
    })
}

/// Inputs (load components, motion ports) and outputs (reactions, probe quantities, energies)
/// of a planar-beam scene.
pub fn io(s: &Beam2dScene) -> KindIo<Input, Output> {
    let mut io = KindIo::default();
    for (i, l) in s.loads.iter().enumerate() {
        for (axis, (comp, start)) in [("fx", l.fx), ("fy", l.fy)].into_iter().enumerate() {
            io.input(
                format!("{}.{comp}", l.name),
                start,
                Unit::N,
                format!(
                    "Force along {} at {} of the length (fixed direction)",
                    ["x", "y"][axis],
                    l.at
                ),
                Input::Load { load: i, axis },
            );
        }
    }
    let g = &s.geometry;
    for (port, m) in s.motions.iter().enumerate() {
        // Start values: the port's position in the reference configuration of the scene.
        let th = g.angle_deg.to_radians();
        let (x0, y0) = (
            g.origin[0] + m.at * g.length * th.cos(),
            g.origin[1] + m.at * g.length * th.sin(),
        );
        let inputs = [
            ("x", x0, Unit::M, "Prescribed position x"),
            ("y", y0, Unit::M, "Prescribed position y"),
            ("vx", 0.0, Unit::MPerS, "Prescribed velocity x"),
            ("vy", 0.0, Unit::MPerS, "Prescribed velocity y"),
        ];
        for (component, (suffix, start, unit, what)) in inputs.into_iter().enumerate() {
            io.input(
                format!("{}.{suffix}", m.name),
                start,
                unit,
                format!(
                    "{what} of the centre line at {} of the length (motion port; extrapolated inside a step with the velocity input)",
                    m.at
                ),
                Input::Motion { port, component },
            );
        }
        for (axis, suffix) in ["fx", "fy"].into_iter().enumerate() {
            // Direct feedthrough at a communication point (`Beam2d::port_force`): the reaction
            // moves with every port's prescribed position through the interface Jacobian
            // (positions and velocities: a position set at an earlier communication point is
            // extrapolated with the velocity input), and takes the loads of the same axis
            // that act on the port node for some `mesh.n_elements`.
            let mut deps: Vec<String> = s
                .loads
                .iter()
                .filter(|l| load_reaches_node(s, l.at, m.at))
                .map(|l| format!("{}.{}", l.name, ["fx", "fy"][axis]))
                .collect();
            for p in &s.motions {
                deps.extend(["x", "y", "vx", "vy"].map(|c| format!("{}.{c}", p.name)));
            }
            let deps: Vec<&str> = deps.iter().map(String::as_str).collect();
            io.output(
                format!("{}.{suffix}", m.name),
                Unit::N,
                format!(
                    "Force exerted by the beam on the body driving the motion port, {} component",
                    ["x", "y"][axis]
                ),
                Output::Reaction { port, axis },
            )
            .depending_on(&deps);
        }
    }
    for (i, p) in s.probes.iter().enumerate() {
        for q in &p.outputs {
            if !q.is_planar() {
                continue; // rejected by `check`
            }
            let (suffix, unit, what) = q.declaration();
            io.output(
                format!("{}.{suffix}", p.name),
                unit,
                format!("{what} of the centre line at {} of the length", p.at),
                Output::Probe {
                    probe: i,
                    quantity: *q,
                },
            );
        }
    }
    if s.outputs.energy {
        declare_energy_outputs(&mut io, Output::Energy, &BODY_ENERGIES);
    }
    io
}

/// Smoke test of a planar beam: the first load's `fy` rises smoothly to the force that bends
/// a cantilever of this section and length by 0.1 % of its length, `F = 2e-3 L · 3 EI / L³`
/// with `EI = E w h³ / 12` (Euler–Bernoulli tip stiffness), and back; without loads the first
/// motion moves by up to 0.2 % of the length in y. Without either, inputs stay constant.
pub fn smoke_test(s: &Beam2dScene) -> crate::ls_ref::SmokeTest {
    use crate::ls_ref::{Shape, SmokeTest, Stimulus};
    let g = &s.geometry;
    let l = g.length;
    let ei = s.material.E * g.width * g.height.powi(3) / 12.0;
    if let Some(load) = s.loads.first() {
        return SmokeTest::with(vec![Stimulus {
            input: format!("{}.fy", load.name),
            amplitude: 0.5 * 2e-3 * l * 3.0 * ei / l.powi(3),
            shape: Shape::Excursion,
        }]);
    }
    if let Some(m) = s.motions.first() {
        return SmokeTest::with(vec![
            Stimulus {
                input: format!("{}.y", m.name),
                amplitude: 1e-3 * l,
                shape: Shape::Excursion,
            },
            Stimulus {
                input: format!("{}.vy", m.name),
                amplitude: 1e-3 * l,
                shape: Shape::Rate,
            },
        ]);
    }
    SmokeTest::default()
}

/// `element.type` codes by scene name ([`super::Beam2dElementType::ALL`]), as the advised
/// scene writes them.
const ELEMENT_TYPES: &[(&str, i32)] = &[("ancf_shear_2d", 1), ("ancf_cable_2d", 2)];

/// The knobs `flexfmu advise` varies: the element family (`element.type`: the seed-000
/// element and the cable converge to different answers; the seed-000 options are removed from
/// a scene advised to use the cable), the element count (at least 1) and the solver knobs.
pub fn knobs(_s: &Beam2dScene) -> Vec<crate::advise::Knob> {
    use crate::advise::{Knob, KnobRole, solver_knobs};
    let mut k = vec![
        Knob::new(ELEMENT_TYPE, KnobRole::Family(&[1, 2]))
            .at("element", "type", Some(ELEMENT_TYPES))
            .dropping(&[
                (2, "element", "shear_rule"),
                (2, "element", "strain_energy"),
                (2, "element", "shear_coefficient"),
            ]),
        Knob::new(MESH_N_ELEMENTS, KnobRole::Count { min: 1 }),
    ];
    k.extend(solver_knobs());
    k
}

#[cfg(test)]
mod advise_tests {
    use super::*;

    #[test]
    fn element_type_names_match_the_scene_enum() {
        for (t, name, code) in super::super::Beam2dElementType::ALL {
            assert!(ELEMENT_TYPES.contains(&(name, code)), "{t:?}");
        }
        assert_eq!(
            ELEMENT_TYPES.len(),
            super::super::Beam2dElementType::ALL.len()
        );
    }
}
