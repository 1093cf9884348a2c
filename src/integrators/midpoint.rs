//! Energy-conserving midpoint rule for strains quadratic in the coordinates (reference F.4,
//! after Simo & Tarnow 1992): `M (v₁ − v₀)/h + Q_alg(q₀, q₁) = f_ext`, `q₁ − q₀ = h (v₀ + v₁)/2`,
//! with the average-stress internal force `Q_alg`, which makes
//! `T₁ + U₁ − T₀ − U₀ = f_extᵀ (q₁ − q₀)` hold exactly (up to the Newton tolerance).

use super::state::DynState;
use crate::model::{JacobianCoeffs, MechanicalSystem};
use crate::solver::newton::{self, NewtonError, NewtonSettings, NewtonStats, Workspace};

/// The energy-conserving midpoint scheme.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Midpoint;

impl Midpoint {
    /// Advances `s0` by `h` into `s1` (unknown: the mean acceleration `(v₁ − v₀)/h`).
    pub fn step(
        &self,
        sys: &mut dyn MechanicalSystem,
        ws: &mut Workspace,
        settings: &NewtonSettings,
        s0: &DynState,
        h: f64,
        s1: &mut DynState,
    ) -> Result<NewtonStats, NewtonError> {
        let coeffs = JacobianCoeffs {
            mass: 1.0,
            damping: 0.5 * h,
            stiffness: 0.5 * h * h,
        };
        s1.acc.copy_from_slice(&s0.acc);
        let mut acc = std::mem::take(&mut s1.acc);
        let (q, v) = (&mut s1.q, &mut s1.v);
        let update = |x: &[f64], q: &mut [f64], v: &mut [f64]| {
            for i in 0..x.len() {
                q[i] = s0.q[i] + h * s0.v[i] + 0.5 * h * h * x[i];
                v[i] = s0.v[i] + 0.5 * h * x[i];
            }
        };
        // The model's own prediction of q₁, if any, converted into the mean acceleration.
        update(&acc, q, v);
        v.copy_from_slice(q);
        if sys.predict(&s0.q, &s0.v, h, q) {
            // start with a fresh iteration matrix, as generalized-α does (see there)
            if !sys.prediction_keeps_matrix() {
                ws.invalidate();
            }
            for i in 0..acc.len() {
                if q[i] != v[i] {
                    acc[i] = 2.0 * (q[i] - s0.q[i] - h * s0.v[i]) / (h * h);
                }
            }
        }
        // v holds the midpoint velocity during the iteration (for damping forces).
        let res = newton::solve(
            ws,
            &mut acc,
            settings,
            coeffs.stiffness,
            coeffs,
            |x, r, jac| {
                update(x, q, v);
                let built = jac.is_some();
                sys.midpoint_residual(s0.t, s0.t + h, &s0.q, q, v, x, r, jac.map(|j| (coeffs, j)))?;
                Ok(sys.matrix_state(built))
            },
        );
        for i in 0..acc.len() {
            s1.q[i] = s0.q[i] + h * s0.v[i] + 0.5 * h * h * acc[i];
            s1.v[i] = s0.v[i] + h * acc[i];
        }
        s1.a.copy_from_slice(&acc);
        s1.acc = acc;
        s1.t = s0.t + h;
        res
    }
}
