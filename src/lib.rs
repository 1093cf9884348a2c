//! flexfmu: flexible bodies as FMI 2.0 Co-Simulation units.
//!
//! A scene file (TOML, see [`scene`]) describes a flexible body, its supports, loads and coupling
//! ports. The same scene drives the generated `modelDescription.xml` ([`model_description`]),
//! the variable table ([`variables`]) and, inside the shared library, the simulation
//! ([`instance`]). The C ABI lives in [`fmi2`], the only module with `unsafe` code.
//!
//! Physics: element kernels in [`elements`], global assembly in [`assembly`], linear algebra in
//! [`linalg`], static and dynamic solvers in [`solver`] and [`integrators`], and the
//! scene-specific models in [`model`]. What the `flexfmu check` command does is in [`cli`].
#![warn(missing_docs)]
#![deny(unsafe_op_in_unsafe_fn)]
// Only the C ABI shims in `fmi2` may use `unsafe`; everything else is safe Rust.
#![deny(unsafe_code)]
// Numeric kernels index several arrays with one loop variable; iterators would obscure them.
#![allow(clippy::needless_range_loop)]

pub mod advise;
pub mod assembly;
pub mod cli;
pub mod contact;
pub mod docs;
pub mod elements;
#[allow(unsafe_code)]
pub mod fmi2;
pub mod gas;
pub mod guid;
pub mod instance;
pub mod integrators;
pub mod kinds;
pub mod linalg;
pub mod logging;
pub mod ls_ref;
pub mod meshers;
pub mod model;
pub mod model_description;
pub mod packaging;
pub mod scene;
pub mod snapshot;
pub mod solver;
pub mod sweep;
pub mod units;
pub mod variables;
