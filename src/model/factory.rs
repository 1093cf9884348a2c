//! Builds the model a scene asks for.

use super::Model;
use super::beam2d::Beam2d;
use super::belt_drive::BeltDrive;
use super::corot3d::Corot3dModel;
use crate::scene::{ParamValues, Scene, SceneKind};

/// The model of `scene` with parameter values `params` (validated here). Errors name the
/// parameter or scene key at fault.
pub fn build_model(scene: &Scene, params: &ParamValues) -> Result<Box<dyn Model>, String> {
    scene.validate_params(params)?;
    match scene.kind {
        SceneKind::Beam2d => Ok(Box::new(Beam2d::build(&scene.file, params)?)),
        SceneKind::Corot3d => Ok(Box::new(Corot3dModel::build(&scene.file, params)?)),
        SceneKind::BeltDrive => Ok(Box::new(BeltDrive::build(&scene.file, params)?)),
    }
}
