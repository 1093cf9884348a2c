//! Scenes: what an FMU models. A TOML file ([`file`]) is parsed, checked, and turned into
//! parameter definitions ([`params`]); the variable table and the model are built from it.

pub mod file;
pub mod params;
mod validate;

pub use file::SceneFile;
pub use params::{ParamDef, ParamValues};

/// A parsed and checked scene.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The parsed file.
    pub file: SceneFile,
    /// The exact text it was parsed from (packaged into the FMU's `resources/`).
    pub text: String,
    /// Parameters the scene exposes, with its values as defaults.
    pub params: Vec<ParamDef>,
}

/// A scene that cannot be used; the message names the key and the problem.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{0}")]
pub struct SceneError(pub String);

impl Scene {
    /// Parses and checks a scene from TOML text.
    pub fn from_toml(text: &str) -> Result<Self, SceneError> {
        let file: SceneFile =
            toml::from_str(text).map_err(|e| SceneError(format!("scene file: {e}")))?;
        let params = params::parameter_defs(&file).map_err(SceneError)?;
        validate::check(&file)
            .and_then(|_| ParamValues::defaults(&params).validate())
            .map_err(|errs| SceneError(format!("scene file: {}", errs.join("; "))))?;
        Ok(Self {
            file,
            text: text.to_string(),
            params,
        })
    }

    /// Reads and parses a scene file.
    pub fn from_path(path: &std::path::Path) -> Result<Self, SceneError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| SceneError(format!("cannot read scene {}: {e}", path.display())))?;
        Self::from_toml(&text).map_err(|e| SceneError(format!("{}: {}", path.display(), e.0)))
    }

    /// Model name (also the model identifier).
    pub fn model_name(&self) -> &str {
        &self.file.fmu.model_name
    }
}
