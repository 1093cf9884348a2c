//! The enclosed gas of an air spring: bag (bellows volume plus a fixed inner volume) and an
//! optional reservoir behind a pipe and an orifice.
//!
//! The component knows nothing of meshes: a model gives it the volume enclosed by its membrane
//! (`v_membrane` [m³]) and gets back the absolute bag pressure [Pa] and its total derivative with
//! respect to that volume [Pa/m³], consistent with the implicit time integration of the gas
//! states inside the step. Physics: `../shared/reference/air-spring-physics.md` 1.4–1.5 and
//! section D.2 of `seed004-trapezoid-shell-and-air-spring.md`; issue 11, item 1.
//!
//! - [`params`]: air constants, the gas laws, the reservoir, validation and the error type.
//! - [`model`]: [`Gas`], its charge, static and stepped evaluations, energy accounts, snapshots.
//! - [`flow`]: the pipe and orifice pressure losses (Saint-Venant orifice, Hagen–Poiseuille pipe).
//! - [`linear`]: the linearized two-volume frequency response.
//! - `dual`: forward-mode dual numbers that give the inner Newton solve its exact Jacobian.

mod dual;
pub mod flow;
pub mod linear;
pub mod model;
pub mod params;
#[cfg(test)]
mod tests;

pub use model::{Gas, GasEval};
pub use params::{GAMMA_AIR, GasError, GasLaw, GasParams, MU_AIR, R_AIR, Reservoir};
