//! The ModelStructure is true: for every shipped scene (and a test scene with every kind of
//! planar-beam feedthrough), an output/input pair is declared in
//! `ModelStructure/Outputs/Unknown/@dependencies` exactly when the output moves with the input
//! at a communication point, the states frozen.
//!
//! "Moves" is measured on the model's own output function (a central difference through
//! `Model::set_input` and `Model::output`, independent of the declaration), at several
//! communication points: after initialization, after steps without new inputs (positions set
//! at an earlier point are then extrapolated with velocity inputs), and after new inputs.
//! Undeclared pairs must be exactly zero at every point; declared pairs non-zero at one at
//! least; `fmi2GetDirectionalDerivative` must agree with the difference on declared pairs; and
//! the XML must carry the table's dependencies.

mod common;
use flexfmu::fmi2::state_machine::Call;
use flexfmu::logging::Status;
use flexfmu::model_description::model_description;
use flexfmu::scene::Scene;
use flexfmu::solver::simulation::{FD_REL, Simulation};
use flexfmu::units::Unit;
use flexfmu::variables::{Role, Value, VariableTable};
use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

/// Every shipped scene plus the test scene.
fn scenes() -> Vec<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut out: Vec<PathBuf> = std::fs::read_dir(root.join("scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    out.sort();
    assert!(out.len() >= 10, "shipped scenes: {out:?}");
    out.push(root.join("tests/data/motion_port_loads.toml"));
    out
}

struct Io {
    inputs: Vec<(u32, usize, f64)>,
    outputs: Vec<(u32, usize)>,
    declared: BTreeSet<(u32, u32)>,
}

fn io(vars: &VariableTable) -> Io {
    let mut io = Io {
        inputs: vec![],
        outputs: vec![],
        declared: BTreeSet::new(),
    };
    for v in vars.vars() {
        match (v.role, v.start) {
            (Role::Input(k), Some(Value::Real(u))) => io.inputs.push((v.vr, k, u)),
            (Role::Output(k), _) => {
                io.outputs.push((v.vr, k));
                for &d in &v.depends_on {
                    io.declared.insert((v.vr, d));
                }
            }
            _ => {}
        }
    }
    io
}

/// A small change of an input, by unit, that moves a port, turns a pulley or loads the body
/// (forces, moments, pressures).
fn nudge(unit: Option<Unit>) -> f64 {
    match unit {
        Some(Unit::M) => 1e-3,
        Some(Unit::MPerS) => 5e-2,
        Some(Unit::Rad) => 1e-2,
        Some(Unit::RadPerS) => 0.5,
        Some(Unit::N) => 10.0,
        Some(Unit::NM) => 1.0,
        Some(Unit::Pa) => 1e3,
        other => panic!("no nudge for unit {other:?}"),
    }
}

/// Partials of every output with respect to every input at the current point: (output vr,
/// input vr, difference of the output function, what fmi2GetDirectionalDerivative returns for
/// a declared pair, round-off bound of the difference).
fn partials(
    sim: &mut Simulation,
    io: &Io,
    values: &BTreeMap<u32, f64>,
) -> Vec<(u32, u32, f64, f64, f64)> {
    let mut out = vec![];
    for &(ivr, input, _) in &io.inputs {
        let u = values[&ivr];
        for &(ovr, output) in &io.outputs {
            let fd = sim.output_input_difference(output, input, u).unwrap();
            let partial = sim.output_input_partial(output, input, u).unwrap();
            let h = FD_REL * u.abs().max(1.0);
            let roundoff = 1e3 * f64::EPSILON * sim.output(output).abs().max(1.0) / h;
            out.push((ovr, ivr, fd, partial, roundoff));
        }
    }
    out
}

fn check_scene(path: &std::path::Path) -> usize {
    let scene = Scene::from_path(path).unwrap();
    let vars = VariableTable::from_scene(&scene);
    let io = io(&vars);
    let name = scene.model_name().to_string();

    // The XML carries the table's dependencies (1-based indices, ascending).
    let xml = model_description(&scene);
    let outputs_xml = &xml[xml.find("<Outputs>").unwrap()..xml.find("</Outputs>").unwrap()];
    for &(ovr, _) in &io.outputs {
        let deps: Vec<String> = vars.vars()[ovr as usize]
            .depends_on
            .iter()
            .map(|d| (d + 1).to_string())
            .collect();
        let line = format!(
            "<Unknown index=\"{}\" dependencies=\"{}\"/>",
            ovr + 1,
            deps.join(" ")
        );
        assert!(outputs_xml.contains(&line), "{name}: {line} missing");
    }

    // Parameter variants: the default, and for the test scene a coarse mesh on which other
    // loads reach the port nodes.
    let mut variants: Vec<Vec<(&str, Value)>> = vec![vec![]];
    if name == "motion_port_loads" {
        variants.push(vec![("mesh.n_elements", Value::Integer(2))]);
    }
    let mut seen_nonzero = BTreeSet::new();
    let mut checked = 0;
    for overrides in variants {
        let mut sim = common::simulation(&scene, &overrides).unwrap();
        let mut values: BTreeMap<u32, f64> = io.inputs.iter().map(|&(v, _, u)| (v, u)).collect();
        let dt = scene.common.experiment.step_size;
        let mut points = vec![];
        // 1: after initialization
        points.push(partials(&mut sim, &io, &values));
        // 2: new inputs, three steps without setting them again
        for &(ivr, input, _) in &io.inputs {
            let u = values[&ivr] + nudge(vars.vars()[ivr as usize].unit);
            values.insert(ivr, u);
            sim.set_input(input, u);
        }
        for k in 1..=3 {
            sim.advance(k as f64 * dt).unwrap();
        }
        points.push(partials(&mut sim, &io, &values));
        // 3: the same inputs set again at this communication point
        for &(ivr, input, _) in &io.inputs {
            sim.set_input(input, values[&ivr]);
        }
        points.push(partials(&mut sim, &io, &values));

        for (ovr, ivr, fd, partial, roundoff) in points.into_iter().flatten() {
            let pair = format!(
                "{name} {overrides:?}: d {} / d {}",
                vars.vars()[ovr as usize].name,
                vars.vars()[ivr as usize].name
            );
            assert!(
                fd.is_finite() && partial.is_finite(),
                "{pair}: {fd} {partial}"
            );
            if io.declared.contains(&(ovr, ivr)) {
                if fd != 0.0 {
                    seen_nonzero.insert((ovr, ivr));
                }
                assert!(
                    (partial - fd).abs() <= 1e-5 * fd.abs() + roundoff,
                    "{pair}: fmi2GetDirectionalDerivative {partial} vs difference {fd}"
                );
            } else {
                assert_eq!(fd, 0.0, "{pair}: not declared, but the output moves");
            }
            checked += 1;
        }
    }
    let never: Vec<String> = io
        .declared
        .difference(&seen_nonzero)
        .map(|(o, i)| {
            format!(
                "{} / {}",
                vars.vars()[*o as usize].name,
                vars.vars()[*i as usize].name
            )
        })
        .collect();
    assert!(
        never.is_empty(),
        "{name}: declared, but never moves: {never:?}"
    );
    checked
}

#[test]
fn declared_dependencies_are_exactly_the_direct_feedthrough() {
    let mut total = 0;
    let mut declared = 0;
    for path in scenes() {
        let scene = Scene::from_path(&path).unwrap();
        declared += io(&VariableTable::from_scene(&scene)).declared.len();
        total += check_scene(&path);
    }
    // cantilever_motion: 2 reactions x 4 motion inputs; the test scene: 4 reactions x (8
    // motion inputs + its reachable loads).
    assert!(declared >= 8 + 32, "declared pairs: {declared}");
    assert!(total > 3_000, "pairs checked: {total}");
}

/// Through the FMI layer: fmi2GetDirectionalDerivative of the reaction of `cantilever_motion`
/// with respect to the port's velocity is zero right after the velocity is set (the position
/// was set at the same point) and non-zero at a later point where only the velocity is set
/// (the position is extrapolated from the earlier point), as the ModelStructure declares.
#[test]
fn velocity_feedthrough_through_the_fmi_layer() {
    let (mut inst, _) = common::instance("cantilever_motion", false);
    assert_eq!(inst.setup_experiment(None, 0.0, None), Status::Ok);
    assert_eq!(inst.enter_initialization_mode(), Status::Ok);
    assert_eq!(inst.exit_initialization_mode(), Status::Ok);
    let (fy, x, y, vy) = (
        common::vr(&inst, "tip.fy"),
        common::vr(&inst, "tip.x"),
        common::vr(&inst, "tip.y"),
        common::vr(&inst, "tip.vy"),
    );
    let dt = 1e-4;
    let pos = [2.0, 1e-3];
    assert_eq!(
        inst.set(
            Call::SetReal,
            &[x, y],
            &[Value::Real(pos[0]), Value::Real(pos[1])]
        ),
        Status::Ok
    );
    common::set(&mut inst, "tip.vy", Value::Real(0.1));
    let mut d = [f64::NAN];
    assert_eq!(
        inst.get_directional_derivative(&[fy], &[vy], &[1.0], &mut d),
        Status::Ok
    );
    assert_eq!(
        d[0], 0.0,
        "position set at this point: no velocity feedthrough"
    );
    let mut dy = [f64::NAN];
    assert_eq!(
        inst.get_directional_derivative(&[fy], &[y], &[1.0], &mut dy),
        Status::Ok
    );
    assert!(dy[0] < 0.0, "the beam pulls the tip back: {}", dy[0]);
    for k in 0..3 {
        assert_eq!(inst.do_step(k as f64 * dt, dt), Status::Ok);
    }
    // only the velocity at t = 3 dt: the position input is still referred to t = 0, so the
    // port is at y + 3 dt vy and d fy / d vy = 3 dt d fy / d y
    common::set(&mut inst, "tip.vy", Value::Real(0.2));
    let mut d = [f64::NAN; 2];
    assert_eq!(
        inst.get_directional_derivative(&[fy], &[vy], &[1.0], &mut d[..1]),
        Status::Ok
    );
    assert_eq!(
        inst.get_directional_derivative(&[fy], &[y], &[1.0], &mut d[1..]),
        Status::Ok
    );
    assert!(d[1] < 0.0, "{d:?}");
    assert!(
        (d[0] - 3.0 * dt * d[1]).abs() <= 1e-9 * d[1].abs(),
        "d fy/d vy = {} vs 3 dt d fy/d y = {}",
        d[0],
        3.0 * dt * d[1]
    );
}
