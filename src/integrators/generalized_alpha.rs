//! Generalized-α (Chung & Hulbert 1993) in the form of Arnold & Brüls 2007: equilibrium at
//! `t_{n+1}`, algorithmic acceleration `a`. With ρ∞ = 1 it is the trapezoidal rule (Newmark
//! average acceleration, β = ¼, γ = ½). Reference: `shared/reference/time-integration.md` F.1.

use super::state::DynState;
use crate::model::{JacobianCoeffs, MechanicalSystem};
use crate::solver::newton::{self, NewtonError, NewtonSettings, NewtonStats, Workspace};

/// Generalized-α coefficients.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeneralizedAlpha {
    /// α_m
    pub alpha_m: f64,
    /// α_f
    pub alpha_f: f64,
    /// β
    pub beta: f64,
    /// γ
    pub gamma: f64,
}

impl GeneralizedAlpha {
    /// Coefficients for spectral radius `rho_inf` ∈ [0, 1] at infinite frequency:
    /// `α_m = (2ρ∞ − 1)/(ρ∞ + 1)`, `α_f = ρ∞/(ρ∞ + 1)`, `γ = ½ − α_m + α_f`,
    /// `β = ¼(1 − α_m + α_f)²`.
    pub fn from_rho_inf(rho_inf: f64) -> Self {
        let r = rho_inf.clamp(0.0, 1.0);
        let alpha_m = (2.0 * r - 1.0) / (r + 1.0);
        let alpha_f = r / (r + 1.0);
        let gamma = 0.5 - alpha_m + alpha_f;
        let beta = 0.25 * (1.0 - alpha_m + alpha_f).powi(2);
        Self {
            alpha_m,
            alpha_f,
            beta,
            gamma,
        }
    }

    /// Newmark average acceleration (trapezoidal rule), ρ∞ = 1.
    pub fn newmark() -> Self {
        Self::from_rho_inf(1.0)
    }

    /// Advances `s0` by `h` into `s1`. On error `s1` is unspecified and `s0` untouched.
    pub fn step(
        &self,
        sys: &mut dyn MechanicalSystem,
        ws: &mut Workspace,
        settings: &NewtonSettings,
        s0: &DynState,
        h: f64,
        s1: &mut DynState,
    ) -> Result<NewtonStats, NewtonError> {
        let Self {
            alpha_m: am,
            alpha_f: af,
            beta,
            gamma,
        } = *self;
        let t1 = s0.t + h;
        let ratio = (1.0 - af) / (1.0 - am);
        let coeffs = JacobianCoeffs {
            mass: 1.0,
            damping: gamma * h * ratio,
            stiffness: beta * h * h * ratio,
        };
        // Unknown: acceleration at t_{n+1}; predictor: the old one (or the model's, below).
        s1.acc.copy_from_slice(&s0.acc);
        let mut acc = std::mem::take(&mut s1.acc);
        let (q, v, a) = (&mut s1.q, &mut s1.v, &mut s1.a);
        let update = |x: &[f64], q: &mut [f64], v: &mut [f64], a: &mut [f64]| {
            for i in 0..x.len() {
                a[i] = (af * s0.acc[i] - am * s0.a[i] + (1.0 - af) * x[i]) / (1.0 - am);
                q[i] = s0.q[i] + h * s0.v[i] + h * h * ((0.5 - beta) * s0.a[i] + beta * a[i]);
                v[i] = s0.v[i] + h * ((1.0 - gamma) * s0.a[i] + gamma * a[i]);
            }
        };
        // The model's own prediction of the coordinates, if it has one (the belt transported
        // along its path): converted into the unknown by inverting the update (q is linear in
        // it); `v` holds the integrator's predicted q meanwhile.
        update(&acc, q, v, a);
        v.copy_from_slice(q);
        if sys.predict(&s0.q, &s0.v, h, q) {
            // a kept iteration matrix holds the contact blocks of the material points that
            // were on the pulleys, which the prediction has moved on: start with a fresh one
            // (belt drive, 100 elements: 3.2 iterations and 1.7 factorizations per step
            // instead of 5.2 and 2.0; modified Newton reuses it within the step)
            if !sys.prediction_keeps_matrix() {
                ws.invalidate();
            }
            for i in 0..acc.len() {
                if q[i] != v[i] {
                    let ai = (q[i] - s0.q[i] - h * s0.v[i] - h * h * (0.5 - beta) * s0.a[i])
                        / (beta * h * h);
                    acc[i] = ((1.0 - am) * ai - af * s0.acc[i] + am * s0.a[i]) / (1.0 - af);
                }
            }
        }
        let res = newton::solve(
            ws,
            &mut acc,
            settings,
            coeffs.stiffness,
            coeffs,
            |x, r, jac| {
                update(x, q, v, a);
                let built = jac.is_some();
                sys.residual(t1, q, v, x, 1.0, r, jac.map(|j| (coeffs, j)))?;
                Ok(sys.matrix_state(built))
            },
        );
        update(&acc, q, v, a);
        s1.acc = acc;
        s1.t = t1;
        res
    }
}

impl GeneralizedAlpha {
    /// Local displacement error estimate of a step, `h² (β − 1/6)(acc₁ − acc₀)`
    /// (Zienkiewicz & Xie 1991, for the Newmark family).
    pub fn error_estimate(&self, s0: &DynState, s1: &DynState, h: f64, out: &mut [f64]) {
        let c = h * h * (self.beta - 1.0 / 6.0);
        for i in 0..out.len() {
            out[i] = c * (s1.acc[i] - s0.acc[i]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Coefficients of reference F.1 for ρ∞ = 0.9.
    #[test]
    fn coefficients_for_rho_0_9() {
        let g = GeneralizedAlpha::from_rho_inf(0.9);
        assert!((g.alpha_m - 0.42105).abs() < 1e-5);
        assert!((g.alpha_f - 0.47368).abs() < 1e-5);
        assert!((g.gamma - 0.55263).abs() < 1e-5);
        assert!((g.beta - 0.27701).abs() < 1e-5);
        let n = GeneralizedAlpha::newmark();
        assert!((n.beta - 0.25).abs() < 1e-15 && (n.gamma - 0.5).abs() < 1e-15);
    }
}
