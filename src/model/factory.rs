//! Builds the model a scene asks for.

use super::Model;
use crate::scene::{ParamValues, Scene};

/// The model of `scene` with parameter values `params` (validated here). Errors name the
/// parameter or scene key at fault.
pub fn build_model(scene: &Scene, params: &ParamValues) -> Result<Box<dyn Model>, String> {
    scene.validate_params(params)?;
    scene.body.build_model(params)
}
