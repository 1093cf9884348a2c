//! The interface between models and solvers ([`Model`], [`MechanicalSystem`]) and the pieces
//! models share (input signals, output rates). Each kind's model lives in its module under
//! [`crate::kinds`].

mod factory;
pub mod framed;
pub mod inputs;
pub mod modal;
pub mod nodes3d;
pub mod ports;
pub mod rates;
pub mod sketch;
mod system;

pub use factory::{build_model, build_model_to_restore};
pub use sketch::Sketch;
pub use system::{
    JacobianCoeffs, MechanicalSystem, Model, ModelError, newton_scales_with_gradients,
};
