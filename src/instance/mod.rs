//! The safe FMI 2.0 Co-Simulation instance. The C shims in [`crate::fmi2`] check pointers and
//! forward here; every method enforces the state machine, logs the reason of any non-OK
//! status through the importer's logger, and returns the fmi2Status.
//!
//! [`core`]: lifecycle, variables, stepping, status; [`fmu_state`]: FMU state save, restore and
//! serialization; [`derivatives`]: directional derivatives, input and output derivatives.

mod core;
mod derivatives;
mod fmu_state;

pub use core::{Instance, LogSink, SCENE_FILE, StatusKind, resource_dir_from_uri};
pub use fmu_state::STATE_FORMAT_VERSION;
