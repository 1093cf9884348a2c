//! Explicit central differences (leap-frog; Newmark β = 0, γ = ½): no Newton iteration, one
//! mass-matrix solve per step, stable for `h ≤ 2/ω_max` (reference F.2). The simulation driver
//! picks the step from the highest frequency of the model ([`crate::solver::simulation`]).

use super::state::DynState;
use crate::model::{JacobianCoeffs, MechanicalSystem};
use crate::solver::newton::{NewtonError, NewtonStats, Workspace};

/// The central-difference scheme.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CentralDifference;

/// Coefficients of the mass matrix as an iteration matrix.
pub const MASS_ONLY: JacobianCoeffs = JacobianCoeffs {
    mass: 1.0,
    damping: 0.0,
    stiffness: 0.0,
};

impl CentralDifference {
    /// Advances `s0` by `h` into `s1`: `v½ = v₀ + h/2 a₀`, `q₁ = q₀ + h v½`,
    /// `M a₁ = f_ext − f_int(q₁, v½)`, `v₁ = v½ + h/2 a₁`. The factorized mass matrix is kept
    /// when `constant_mass`.
    pub fn step(
        &self,
        sys: &mut dyn MechanicalSystem,
        ws: &mut Workspace,
        constant_mass: bool,
        s0: &DynState,
        h: f64,
        s1: &mut DynState,
    ) -> Result<NewtonStats, NewtonError> {
        let n = s0.q.len();
        for i in 0..n {
            s1.v[i] = s0.v[i] + 0.5 * h * s0.acc[i];
            s1.q[i] = s0.q[i] + h * s1.v[i];
            s1.a[i] = 0.0;
        }
        let t1 = s0.t + h;
        let mut stats = NewtonStats {
            iterations: 1,
            factorizations: 0,
            backtracks: 0,
            refreshes: 0,
        };
        let reuse = constant_mass && ws.is_factored(&MASS_ONLY);
        if reuse {
            sys.residual(t1, &s1.q, &s1.v, &s1.a, 1.0, &mut ws.r, None)?;
        } else {
            sys.residual(
                t1,
                &s1.q,
                &s1.v,
                &s1.a,
                1.0,
                &mut ws.r,
                Some((MASS_ONLY, &mut ws.jac)),
            )?;
            ws.invalidate();
            ws.solver.factor(&ws.pattern, &ws.jac)?;
            if constant_mass {
                ws.mark_factored(&MASS_ONLY);
            }
            stats.factorizations = 1;
        }
        for i in 0..n {
            s1.acc[i] = -ws.r[i];
        }
        ws.solver.solve_in_place(&mut s1.acc);
        if s1.acc.iter().any(|a| !a.is_finite()) {
            return Err(NewtonError::Model(crate::model::ModelError::NonFinite));
        }
        for i in 0..n {
            s1.v[i] += 0.5 * h * s1.acc[i];
        }
        s1.a.copy_from_slice(&s1.acc);
        s1.t = t1;
        Ok(stats)
    }
}
