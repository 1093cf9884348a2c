//! Helpers shared by the integration tests.
#![allow(dead_code)]

use flexfmu::model::build_model;
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use flexfmu::variables::{Role, Value, VariableTable};
use std::path::PathBuf;

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
