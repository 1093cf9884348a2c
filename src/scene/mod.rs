//! Scenes: what an FMU models. A TOML file ([`file`]) is parsed and checked; its kind (from
//! the element type) declares the parameters ([`params`]) and the inputs and outputs, from
//! which the variable table and the model are built.

pub mod beam2d;
pub mod belt_drive;
pub mod corot3d;
pub mod file;
pub mod params;
mod validate;

pub use file::SceneFile;
pub use params::{ParamDef, ParamValues};

use crate::variables::IoVariable;
use file::ElementType;

/// What a scene models, decided by its element type and tables.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneKind {
    /// A straight planar beam of seed-000 elements with supports, point loads and probes.
    Beam2d,
    /// A closed belt (ANCF cable or seed-000 elements) around driven or free pulleys.
    BeltDrive,
    /// A 3D beam of seed-003 co-rotational elements along a centre line of straight and
    /// circular pieces, with supports, point loads (forces and moments) and probes.
    Corot3d,
}

/// A parsed and checked scene.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The parsed file.
    pub file: SceneFile,
    /// The exact text it was parsed from (packaged into the FMU's `resources/`).
    pub text: String,
    /// Its kind.
    pub kind: SceneKind,
    /// Parameters the scene exposes, with its values as defaults.
    pub params: Vec<ParamDef>,
    /// Inputs and outputs the scene exposes.
    pub io: Vec<IoVariable>,
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
        let kind = match (
            file.element.kind,
            file.belt.is_some() || !file.pulley.is_empty(),
        ) {
            (_, true) => SceneKind::BeltDrive,
            (ElementType::AncfShear2d, false) => SceneKind::Beam2d,
            (ElementType::Corotational3d, false) => SceneKind::Corot3d,
            (ElementType::AncfCable2d, false) => {
                return Err(SceneError(
                    "scene file: element type \"ancf_cable_2d\" is the belt element: add [belt], [contact] and [[pulley]] tables".into(),
                ));
            }
        };
        let fail = |errs: Vec<String>| SceneError(format!("scene file: {}", errs.join("; ")));
        validate::check_common(&file).map_err(fail)?;
        let (mut params, io) = match kind {
            SceneKind::Beam2d => {
                beam2d::check(&file).map_err(fail)?;
                (
                    beam2d::params(&file).map_err(|e| fail(vec![e]))?,
                    beam2d::io(&file),
                )
            }
            SceneKind::Corot3d => {
                corot3d::check(&file).map_err(fail)?;
                (
                    corot3d::params(&file).map_err(|e| fail(vec![e]))?,
                    corot3d::io(&file),
                )
            }
            SceneKind::BeltDrive => {
                belt_drive::check(&file).map_err(fail)?;
                (
                    belt_drive::params(&file).map_err(|e| fail(vec![e]))?,
                    belt_drive::io(&file),
                )
            }
        };
        params.extend(params::gravity_params(&file));
        params.extend(params::solver_params(&file).map_err(|e| fail(vec![e]))?);
        validate::check_names(&params, &io).map_err(fail)?;
        ParamValues::defaults(&params)
            .validate(&params)
            .map_err(fail)?;
        Ok(Self {
            file,
            text: text.to_string(),
            kind,
            params,
            io,
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

    /// Checks parameter values (from the importer) against their definitions.
    pub fn validate_params(&self, values: &ParamValues) -> Result<(), String> {
        values.validate(&self.params).map_err(|e| e.join("; "))
    }
}
