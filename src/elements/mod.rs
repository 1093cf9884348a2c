//! Finite-element kernels: one file per element, each in the fixed order
//! shape functions, mass, internal forces, tangent.
//!
//! Kernels are pure functions of the element coordinates and of precomputed reference data; the
//! assembly ([`crate::assembly`]) gathers, calls and scatters.

pub mod ancf_cable2d;
pub mod ancf_shear2d;
pub mod corotational3d;
pub mod material;
pub mod quadrature;
pub mod rotation;
