//! Helpers shared by the integration tests.
#![allow(dead_code)]

use flexfmu::fmi2::state_machine::Call;
use flexfmu::instance::Instance;
use flexfmu::logging::Status;
use flexfmu::model::build_model;
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use flexfmu::variables::{Role, Value, VarType, VariableTable};
use std::cell::RefCell;
use std::path::PathBuf;
use std::rc::Rc;

/// Path of a shipped scene.
pub fn scene_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(format!("{name}.toml"))
}

/// Loads a shipped scene.
pub fn scene(name: &str) -> Scene {
    Scene::from_path(&scene_path(name)).unwrap()
}

/// A simulation of `scene` with parameter and input overrides by variable name.
pub fn simulation(scene: &Scene, overrides: &[(&str, Value)]) -> Result<Simulation, String> {
    let vars = VariableTable::from_scene(scene);
    let mut params = ParamValues::defaults(&scene.params);
    let mut inputs = vec![];
    for (name, value) in overrides {
        let v = vars
            .by_name(name)
            .unwrap_or_else(|| panic!("no variable {name}"));
        match v.role {
            Role::Parameter(p) => params.set(p, *value),
            Role::Input(k) => match value {
                Value::Real(x) => inputs.push((k, *x)),
                _ => panic!("inputs are Real"),
            },
            Role::Output(_) => panic!("{name} is an output"),
        }
    }
    let mut model = build_model(scene, &params)?;
    for (k, x) in inputs {
        model.set_input(k, x);
    }
    let cfg = SolverConfig::from_params(&params);
    let mut sim = Simulation::new(model, cfg, 0.0)?;
    sim.initialize()?;
    Ok(sim)
}

/// The index of input `name` among the scene's inputs (what `Model::set_input` takes).
pub fn input_index(scene: &Scene, name: &str) -> usize {
    match VariableTable::from_scene(scene)
        .by_name(name)
        .map(|v| v.role)
    {
        Some(Role::Input(k)) => k,
        other => panic!("{name} is not an input: {other:?}"),
    }
}

/// An output of a simulation by variable name.
pub fn output(scene: &Scene, sim: &Simulation, name: &str) -> f64 {
    let vars = VariableTable::from_scene(scene);
    match vars
        .by_name(name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .role
    {
        Role::Output(k) => sim.output(k),
        _ => panic!("{name} is not an output"),
    }
}

/// Log of an instance: status, category, message of every delivered message.
pub type Log = Rc<RefCell<Vec<(Status, String, String)>>>;

/// An instance of a shipped scene whose log messages are collected.
pub fn instance(scene_name: &str, logging_on: bool) -> (Instance, Log) {
    let log: Log = Rc::default();
    let l2 = log.clone();
    let inst = Instance::from_scene(
        "test",
        scene(scene_name),
        logging_on,
        Box::new(move |s, c, m| l2.borrow_mut().push((s, c.to_string(), m.to_string()))),
    );
    (inst, log)
}

/// The last message of a log ("" when there is none).
pub fn last_message(log: &Log) -> String {
    log.borrow()
        .last()
        .map(|(_, _, m)| m.clone())
        .unwrap_or_default()
}

/// Value reference of a variable by name.
pub fn vr(inst: &Instance, name: &str) -> u32 {
    inst.variables()
        .by_name(name)
        .unwrap_or_else(|| panic!("no {name}"))
        .vr
}

/// Sets a variable by name with the fmi2Set call of its type.
pub fn set(inst: &mut Instance, name: &str, v: Value) -> Status {
    let call = match v {
        Value::Real(_) => Call::SetReal,
        Value::Integer(_) => Call::SetInteger,
        Value::Boolean(_) => Call::SetBoolean,
    };
    let r = vr(inst, name);
    inst.set(call, &[r], &[v])
}

/// fmi2GetReal of one variable by name: the status and the value (NaN when none came).
pub fn get_real(inst: &mut Instance, name: &str) -> (Status, f64) {
    let r = vr(inst, name);
    let mut out = f64::NAN;
    let s = inst.get(Call::GetReal, VarType::Real, &[r], &mut |_, v| {
        if let Value::Real(x) = v {
            out = x
        }
    });
    (s, out)
}

/// fmi2GetReal of one variable by name, which must succeed.
pub fn get(inst: &mut Instance, name: &str) -> f64 {
    let (s, x) = get_real(inst, name);
    assert_eq!(s, Status::Ok, "fmi2GetReal({name})");
    x
}
