//! The FMI 2.0 Co-Simulation C API. This is the only module with `unsafe` code: the exported
//! functions in [`exports`] null-check their arguments, wrap every call in `catch_unwind`
//! (a panic becomes fmi2Fatal) and forward to the safe [`crate::instance::Instance`].
//! [`state_machine`] is the table of allowed calls per state; [`logger`] keeps the caller's
//! `componentEnvironment` and calls the C logger with a "%s" format.

pub mod exports;
pub mod logger;
pub mod state_machine;
pub mod types;
