//! Quasi-static stepping: the equilibrium `f_int(q₁, v₁) − f_ext(t₁) = 0` at the end of every
//! step, without inertia, with the backward-Euler velocity `v₁ = (q₁ − q₀)/h` for the forces
//! that depend on rates (contact damping, friction, a gas law that exchanges heat over the
//! step). For bodies whose own inertia is far below that of what they connect and whose
//! supports hold them statically (the air spring's bellows between two plates: its lowest
//! membrane mode lies far above the vehicle's frequencies), a sequence of static solves, each
//! starting from the last and the model's predictor: no membrane modes to ring and no
//! transients to follow, so that most steps converge in one Newton iteration. Only models that
//! say they are statically supported accept it ([`MechanicalSystem::set_quasi_static`]).

use super::state::DynState;
use crate::model::{JacobianCoeffs, MechanicalSystem};
use crate::solver::newton::{self, NewtonError, NewtonSettings, NewtonStats, Workspace};

/// The quasi-static scheme (`solver.integrator = "quasi_static"`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct QuasiStatic;

impl QuasiStatic {
    /// Advances `s0` by `h` into `s1` (unknown: the coordinates; accelerations stay zero).
    /// The predictor is `q₀ + h v₀` or the model's own ([`MechanicalSystem::predict`]).
    pub fn step(
        &self,
        sys: &mut dyn MechanicalSystem,
        ws: &mut Workspace,
        settings: &NewtonSettings,
        s0: &DynState,
        h: f64,
        s1: &mut DynState,
    ) -> Result<NewtonStats, NewtonError> {
        let t1 = s0.t + h;
        // r(q₁) with v₁ = (q₁ − q₀)/h: ∂r/∂q₁ = K + C/h
        let coeffs = JacobianCoeffs {
            mass: 0.0,
            damping: 1.0 / h,
            stiffness: 1.0,
        };
        let mut q = std::mem::take(&mut s1.q);
        for i in 0..q.len() {
            q[i] = s0.q[i] + h * s0.v[i];
        }
        if sys.predict(&s0.q, &s0.v, h, &mut q) && !sys.prediction_keeps_matrix() {
            ws.invalidate();
        }
        s1.a.fill(0.0);
        s1.acc.fill(0.0);
        let (v, a) = (&mut s1.v, &s1.a);
        let res = newton::solve(ws, &mut q, settings, 1.0, coeffs, |x, r, jac| {
            for i in 0..x.len() {
                v[i] = (x[i] - s0.q[i]) / h;
            }
            let built = jac.is_some();
            sys.residual(t1, x, v, a, 1.0, r, jac.map(|j| (coeffs, j)))?;
            Ok(built || sys.kept_matrix_current())
        });
        for i in 0..q.len() {
            s1.v[i] = (q[i] - s0.q[i]) / h;
        }
        s1.q = q;
        s1.t = t1;
        res
    }
}
