//! Builds the model a scene asks for.

use super::Model;
use crate::scene::{ParamValues, Scene};

/// The model of `scene` with parameter values `params` (validated here). Errors name the
/// parameter or scene key at fault.
pub fn build_model(scene: &Scene, params: &ParamValues) -> Result<Box<dyn Model>, String> {
    scene.validate_params(params)?;
    scene.body.build_model(params)
}

/// [`build_model`] for a model about to receive a saved state: the kind may skip setup the
/// state carries ([`crate::kinds::KindScene::build_model_to_restore`]).
pub fn build_model_to_restore(
    scene: &Scene,
    params: &ParamValues,
) -> Result<Box<dyn Model>, String> {
    scene.validate_params(params)?;
    scene.body.build_model_to_restore(params)
}
