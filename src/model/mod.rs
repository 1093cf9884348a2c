//! Discretised models built from scenes, and the interface the solvers see.

pub mod beam2d;
pub mod belt_drive;
pub mod corot3d;
mod factory;
pub mod inputs;
pub mod rates;
mod system;

pub use factory::build_model;
pub use system::{JacobianCoeffs, MechanicalSystem, Model, ModelError};
