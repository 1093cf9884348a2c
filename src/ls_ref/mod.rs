//! FMI-LS-REF inside every FMU: the layered standard "References" (modelica/fmi-ls-ref,
//! `docs/index.adoc`, version 1.0.0-alpha.1) places related files under
//! `extra/org.fmi-standard.fmi-ls-ref/` and describes each one, with its role, in
//! `fmi-ls-manifest.xml` there. flexfmu ships the scene source, one SSP parameter set per
//! preset of the scene's kind, a smoke-test experiment with its stimuli and reference result,
//! and, where the kind asks for it, the serialized FMU state after initialization.
//!
//! What a kind declares is in [`declare`] (methods of [`crate::kinds::KindScene`]); the file
//! formats in [`ssv`] and [`manifest`]; the in-process run that produces the reference result
//! in [`smoke`]; [`files`] assembles everything for a scene.

pub mod declare;
pub mod files;
pub mod manifest;
pub mod smoke;
pub mod ssv;

pub use declare::{Preset, PresetValue, Shape, SmokeTest, Stimulus};
pub use files::{LS_REF_DIR, ls_ref_files};
