//! Seed-004 element: four-node trapezoidal shell in absolute coordinates (Pogorelov & Rodikov
//! 2021, Part I). SKELETON: the API the shell kind is written against; the kernels follow.

#![allow(missing_docs, unused_variables, dead_code)]

use super::element::{Element, ElementState, Layout, Slot};
use nalgebra::{SMatrix, SVector, Vector3};

/// Coordinates per node `[x, y, z, θx, θy, θz]`.
pub const NODE_DOFS: usize = 6;
/// Coordinates per element (4 nodes).
pub const ELEMENT_DOFS: usize = 24;
/// Element vector.
pub type Vec24 = SVector<f64, ELEMENT_DOFS>;
/// Element matrix.
pub type Mat24 = SMatrix<f64, ELEMENT_DOFS, ELEMENT_DOFS>;

/// Bending shape functions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bending {
    /// V1: products of beam Hermite polynomials (Eq. 26-27).
    V1,
    /// V2: the 12-DOF rectangle (Adini-Clough-Melosh) functions (Eq. 28), the default.
    V2,
}

/// Material and thickness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShellMaterial {
    /// Young's modulus [Pa].
    pub e: f64,
    /// Poisson's ratio [1].
    pub nu: f64,
    /// Density [kg/m3].
    pub rho: f64,
    /// Thickness [m].
    pub thickness: f64,
}

/// Element options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShellOptions {
    /// Bending variant.
    pub bending: Bending,
    /// Drilling stiffness as a ratio of the membrane shear stiffness `G h` [1].
    pub drilling: f64,
    /// Include the geometric (initial-stress) stiffness of the local von Karman strains.
    pub geometric_stiffness: bool,
}

impl Default for ShellOptions {
    fn default() -> Self {
        Self {
            bending: Bending::V2,
            drilling: 1e-3,
            geometric_stiffness: false,
        }
    }
}

/// One element.
#[derive(Clone, Debug)]
pub struct TrapezoidShell {}

impl TrapezoidShell {
    /// An element on four reference nodes, counter-clockwise about the element normal
    /// `(x3 - x1) x (x4 - x2)`. Errors for degenerate or non-convex quadrilaterals.
    pub fn new(
        x: [Vector3<f64>; 4],
        mat: &ShellMaterial,
        opt: &ShellOptions,
    ) -> Result<Self, String> {
        todo!()
    }
    /// Reference area [m2].
    pub fn area(&self) -> f64 {
        todo!()
    }
}

impl Element<ELEMENT_DOFS> for TrapezoidShell {
    fn layout(&self) -> Layout {
        Layout {
            dim: 3,
            slots: &[
                Slot::Position,
                Slot::Rotation,
                Slot::Position,
                Slot::Rotation,
                Slot::Position,
                Slot::Rotation,
                Slot::Position,
                Slot::Rotation,
            ],
        }
    }
    fn constant_mass_matrix(&self) -> Option<&Mat24> {
        todo!()
    }
    fn mass_into(&self, s: &ElementState<ELEMENT_DOFS>, m: &mut Mat24) {
        todo!()
    }
    fn gravity_into(&self, s: &ElementState<ELEMENT_DOFS>, g: &Vector3<f64>, f: &mut Vec24) {
        todo!()
    }
    fn strain_energy_at(&self, s: &ElementState<ELEMENT_DOFS>) -> f64 {
        todo!()
    }
    fn force_into(&self, s: &ElementState<ELEMENT_DOFS>, f: &mut Vec24) -> f64 {
        todo!()
    }
    fn tangent_into(
        &self,
        s: &ElementState<ELEMENT_DOFS>,
        f: &mut Vec24,
        k: &mut Mat24,
        c: Option<&mut Mat24>,
    ) -> f64 {
        todo!()
    }
}
