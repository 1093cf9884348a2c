//! Finite elements: one file per element, each in the fixed order shape functions, mass,
//! internal forces, tangent, then its implementation of the one [`Element`] trait.
//!
//! Kernels are pure functions of the element coordinates and of precomputed reference data; the
//! assembly ([`crate::assembly::ElementSet`]) gathers, calls and scatters. Node frames
//! ([`node_frames`]) hold the orientations of elements with rotational coordinates. Every
//! element passes the conformance checks ([`conformance`], one line per element in
//! `src/elements/tests/`).

pub mod ancf_cable2d;
pub mod ancf_shear2d;
pub mod axisym_bending;
pub mod axisym_membrane;
pub mod conformance;
pub mod cord_rubber;
pub mod cord_rubber_quad;
pub mod corotational3d;
pub mod element;
pub mod finite_difference;
pub mod material;
pub mod node_frames;
pub mod quadrature;
pub mod rotation;
pub mod surface_load;
pub mod trapezoid_shell;

#[cfg(test)]
mod tests;

pub use element::{Element, ElementState, Frame, Layout, Slot};
