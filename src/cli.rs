//! The library side of the `flexfmu` command line: what `flexfmu check` does, callable from
//! tests so that they exercise exactly the code path of the command.
//!
//! `flexfmu check scene.toml` = [`parse_scene`] (TOML, the kind's checks, the parameter
//! defaults against their admissible values) then [`build_default_model`] (the model with the
//! default parameters, as an FMU builds it at instantiation). [`check_scene`] does both.

use crate::model::build_model;
use crate::scene::{ParamValues, Scene};
use crate::variables::Causality;
use std::path::Path;

/// What `flexfmu check` reports about an accepted scene.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CheckSummary {
    /// Model name (`[fmu] model_name`).
    pub model_name: String,
    /// Kind of body the scene models (e.g. `belt_drive`).
    pub kind: String,
    /// Number of FMU parameters.
    pub parameters: usize,
    /// Number of FMU inputs.
    pub inputs: usize,
    /// Number of FMU outputs.
    pub outputs: usize,
}

impl std::fmt::Display for CheckSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} ({}): {} parameters, {} inputs, {} outputs",
            self.model_name, self.kind, self.parameters, self.inputs, self.outputs
        )
    }
}

impl CheckSummary {
    /// The summary of a parsed scene.
    pub fn of(scene: &Scene) -> Self {
        let count = |c: Causality| scene.io.iter().filter(|v| v.causality == c).count();
        Self {
            model_name: scene.model_name().to_string(),
            kind: kind_name(scene),
            parameters: scene.params.len(),
            inputs: count(Causality::Input),
            outputs: count(Causality::Output),
        }
    }
}

/// First half of `flexfmu check`: parses scene text and runs every scene check (unknown and
/// missing keys, the kind's tables, the parameter defaults against their admissible values).
/// The error names the key and the problem.
pub fn parse_scene(text: &str) -> Result<Scene, String> {
    Scene::from_toml(text).map_err(|e| e.0)
}

/// Second half of `flexfmu check`: builds the model of `scene` with its default parameter
/// values (mesh, layout, a belt's static pre-load), as an FMU does when it is instantiated.
pub fn build_default_model(scene: &Scene) -> Result<(), String> {
    build_model(scene, &ParamValues::defaults(&scene.params)).map(|_| ())
}

/// `flexfmu check` on scene text: [`parse_scene`] then [`build_default_model`].
pub fn check_scene(text: &str) -> Result<CheckSummary, String> {
    let scene = parse_scene(text)?;
    build_default_model(&scene)?;
    Ok(CheckSummary::of(&scene))
}

/// `flexfmu check` on a scene file; errors are prefixed with the path.
pub fn check_path(path: &Path) -> Result<CheckSummary, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read scene {}: {e}", path.display()))?;
    check_scene(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// The name of the body kind of `scene` (`beam_2d`, `belt_drive`, ...), as the scene key
/// `kind = "..."` and messages name it.
pub fn kind_name(scene: &Scene) -> String {
    scene.kind().name().to_string()
}
