//! The integrator chosen by `solver.integrator`.

use super::{CentralDifference, DynState, GeneralizedAlpha, Midpoint, QuasiStatic};
use crate::model::MechanicalSystem;
use crate::solver::newton::{NewtonError, NewtonSettings, NewtonStats, Workspace};

/// A time integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integrator {
    /// Generalized-α (Newmark average acceleration when ρ∞ = 1).
    GeneralizedAlpha(GeneralizedAlpha),
    /// Energy-conserving midpoint rule with average stresses.
    Midpoint(Midpoint),
    /// Explicit central differences.
    CentralDifference(CentralDifference),
    /// Static equilibrium at the end of every step, no inertia (statically supported models
    /// only, [`MechanicalSystem::set_quasi_static`]).
    QuasiStatic(QuasiStatic),
}

impl Integrator {
    /// From the `solver.integrator` code and `solver.rho_inf`.
    pub fn from_code(code: i32, rho_inf: f64) -> Self {
        match code {
            1 => Integrator::GeneralizedAlpha(GeneralizedAlpha::from_rho_inf(rho_inf)),
            3 => Integrator::Midpoint(Midpoint),
            4 => Integrator::CentralDifference(CentralDifference),
            5 => Integrator::QuasiStatic(QuasiStatic),
            _ => Integrator::GeneralizedAlpha(GeneralizedAlpha::newmark()),
        }
    }

    /// Whether the scheme drops inertia (a static solve per step).
    pub fn is_quasi_static(&self) -> bool {
        matches!(self, Integrator::QuasiStatic(_))
    }

    /// Whether the scheme is explicit (its step is bounded by stability, not accuracy).
    pub fn is_explicit(&self) -> bool {
        matches!(self, Integrator::CentralDifference(_))
    }

    /// One internal step of size `h` from `s0` into `s1`.
    #[allow(clippy::too_many_arguments)]
    pub fn step(
        &self,
        sys: &mut dyn MechanicalSystem,
        ws: &mut Workspace,
        settings: &NewtonSettings,
        constant_mass: bool,
        s0: &DynState,
        h: f64,
        s1: &mut DynState,
    ) -> Result<NewtonStats, NewtonError> {
        match self {
            Integrator::GeneralizedAlpha(g) => g.step(sys, ws, settings, s0, h, s1),
            Integrator::Midpoint(m) => m.step(sys, ws, settings, s0, h, s1),
            Integrator::CentralDifference(c) => c.step(sys, ws, constant_mass, s0, h, s1),
            Integrator::QuasiStatic(s) => s.step(sys, ws, settings, s0, h, s1),
        }
    }

    /// Local displacement error estimate of an implicit step (Zienkiewicz & Xie 1991), `None`
    /// for explicit schemes and for quasi-static steps.
    pub fn error_estimate(&self, s0: &DynState, s1: &DynState, h: f64, out: &mut [f64]) -> bool {
        match self {
            Integrator::GeneralizedAlpha(g) => {
                g.error_estimate(s0, s1, h, out);
                true
            }
            // the midpoint rule shares the trapezoidal rule's β = 1/4 error constant
            Integrator::Midpoint(_) => {
                GeneralizedAlpha::newmark().error_estimate(s0, s1, h, out);
                true
            }
            // no time-integration error of its own: a sequence of equilibria
            Integrator::CentralDifference(_) | Integrator::QuasiStatic(_) => false,
        }
    }
}
