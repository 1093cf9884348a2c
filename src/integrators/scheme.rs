//! The integrator chosen by `solver.integrator`.

use super::{DynState, GeneralizedAlpha, Midpoint};
use crate::model::MechanicalSystem;
use crate::solver::newton::{NewtonError, NewtonSettings, NewtonStats, Workspace};

/// An implicit time integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integrator {
    /// Generalized-α (Newmark average acceleration when ρ∞ = 1).
    GeneralizedAlpha(GeneralizedAlpha),
    /// Energy-conserving midpoint rule with average stresses.
    Midpoint(Midpoint),
}

impl Integrator {
    /// From the `solver.integrator` code and `solver.rho_inf`.
    pub fn from_code(code: i32, rho_inf: f64) -> Self {
        match code {
            1 => Integrator::GeneralizedAlpha(GeneralizedAlpha::from_rho_inf(rho_inf)),
            3 => Integrator::Midpoint(Midpoint),
            _ => Integrator::GeneralizedAlpha(GeneralizedAlpha::newmark()),
        }
    }

    /// One internal step of size `h` from `s0` into `s1`.
    pub fn step(
        &self,
        sys: &mut dyn MechanicalSystem,
        ws: &mut Workspace,
        settings: &NewtonSettings,
        s0: &DynState,
        h: f64,
        s1: &mut DynState,
    ) -> Result<NewtonStats, NewtonError> {
        match self {
            Integrator::GeneralizedAlpha(g) => g.step(sys, ws, settings, s0, h, s1),
            Integrator::Midpoint(m) => m.step(sys, ws, settings, s0, h, s1),
        }
    }
}
