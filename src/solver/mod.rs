//! Nonlinear solvers: Newton's method on a model's free coordinates, the static equilibrium
//! with load stepping, and the simulation driver that advances a communication step with
//! internal substeps.

pub mod newton;
pub mod simulation;
pub mod statics;

pub use newton::{NewtonError, NewtonSettings, NewtonStats, Workspace};
