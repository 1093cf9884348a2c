//! The linearized two-volume frequency response of bag, pipe and reservoir
//! (air-spring-physics.md 1.5).

use super::model::Gas;
use nalgebra::Complex;

impl Gas {
    /// Dynamic "stiffness" of the gas `dp_bag / dV_bag` [Pa/m³] at the angular frequency
    /// `omega` [rad/s] of the model linearized about the committed state taken as an
    /// equilibrium (after [`Gas::charge`] or [`Gas::set_static`]). Times `−A²` it is the spring
    /// stiffness [N/m] of a piston of area A.
    pub fn linear_dynamic_stiffness(&self, omega: f64) -> Complex<f64> {
        let _ = omega;
        todo!()
    }
}
