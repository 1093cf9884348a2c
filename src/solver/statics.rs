//! Static equilibrium `f_int(q) = λ f_ext` by Newton's method with adaptive load stepping and
//! path following: each load increment starts from the tangent predictor, and an increment
//! whose Newton correction exceeds `PATH_JUMP_RATIO` times the predictor is rejected as a jump
//! to another equilibrium branch (a limit point, bifurcation or spurious mode) and cut. A start
//! guess out of equilibrium without load is not on the path: its first increment is unchecked.

use super::newton::{
    self, NewtonError, NewtonPolicy, NewtonSettings, NewtonStats, Workspace, scaled_max,
};
use crate::model::{JacobianCoeffs, MechanicalSystem};

/// Smallest load increment before the static solve gives up, as a fraction of the load.
pub const MIN_LOAD_INCREMENT: f64 = 1.0 / 4096.0;

/// Largest accepted ratio of the Newton correction to the tangent predictor of an increment.
pub const PATH_JUMP_RATIO: f64 = 1.0;

/// A static solve that did not reach the full load.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "static equilibrium not found: reached load factor {reached:.4} of 1; at {attempted:.4} the solve failed even with the load increment cut to {increment:.2e} ({cause}). The structure may be a mechanism (unsupported rigid motion, e.g. a pendulum), have a spurious zero-energy mode (element.shear_rule = 1 on deep beams, Kerkkanen et al. 2003 Table 4), or reach a limit point"
)]
pub struct StaticError {
    /// Largest load factor in equilibrium.
    pub reached: f64,
    /// Load factor of the last failed attempt.
    pub attempted: f64,
    /// Last increment tried.
    pub increment: f64,
    /// Why the last attempt failed.
    pub cause: String,
}

/// Counters of a static solve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StaticStats {
    /// Load increments that converged.
    pub increments: usize,
    /// Newton work.
    pub newton: NewtonStats,
}

/// Solves for the free coordinates `q` (start guess on entry, equilibrium on success; left at
/// the last equilibrium reached on failure), starting with `load_steps` equal increments.
pub fn solve(
    sys: &mut dyn MechanicalSystem,
    ws: &mut Workspace,
    q: &mut [f64],
    settings: &NewtonSettings,
    load_steps: usize,
) -> Result<StaticStats, StaticError> {
    sys.hold_for_statics(true);
    let result = follow_load(sys, ws, q, settings, load_steps);
    sys.hold_for_statics(false);
    result
}

/// The load stepping of [`solve`].
fn follow_load(
    sys: &mut dyn MechanicalSystem,
    ws: &mut Workspace,
    q: &mut [f64],
    settings: &NewtonSettings,
    load_steps: usize,
) -> Result<StaticStats, StaticError> {
    let n = q.len();
    let zeros = vec![0.0; n];
    let mut trial = q.to_vec();
    let mut predictor = vec![0.0; n];
    let mut lambda = 0.0;
    let mut dl = 1.0 / load_steps.max(1) as f64;
    let mut stats = StaticStats::default();
    // Path following wants the quadratic convergence of full Newton.
    let settings = &NewtonSettings {
        policy: NewtonPolicy::Full,
        ..*settings
    };
    let coeffs = JacobianCoeffs {
        mass: 0.0,
        damping: 0.0,
        stiffness: 1.0,
    };
    // A start guess out of equilibrium without load (a belt mounted with a shorter reference
    // length) is not on the load path: its first increment cannot be checked against the path.
    // (A failure here is left to the first increment, which reports it.)
    let mut on_path = true;
    if sys
        .residual(
            0.0,
            q,
            &zeros,
            &zeros,
            0.0,
            &mut ws.r,
            Some((coeffs, &mut ws.jac)),
        )
        .is_ok()
        && ws.solver.factor(&ws.pattern, &ws.jac).is_ok()
    {
        ws.solver.solve_in_place(&mut ws.r);
        let defect = scaled_max(&ws.r, 1.0, &ws.scales);
        on_path = defect.is_nan() || defect <= settings.tolerance;
    }
    while lambda < 1.0 {
        let target = (lambda + dl).min(1.0);
        let mut attempt = || -> Result<NewtonStats, String> {
            // Tangent predictor from the last equilibrium.
            sys.residual(
                0.0,
                q,
                &zeros,
                &zeros,
                target,
                &mut ws.r,
                Some((coeffs, &mut ws.jac)),
            )
            .map_err(|e| e.to_string())?;
            ws.solver
                .factor(&ws.pattern, &ws.jac)
                .map_err(|e| e.to_string())?;
            for (p, r) in predictor.iter_mut().zip(&ws.r) {
                *p = -r;
            }
            ws.solver.solve_in_place(&mut predictor);
            for i in 0..n {
                trial[i] = q[i] + predictor[i];
            }
            let mut s = newton::solve(ws, &mut trial, settings, 1.0, coeffs, |x, r, jac| {
                sys.residual(0.0, x, &zeros, &zeros, target, r, jac.map(|j| (coeffs, j)))
            })
            .map_err(|e: NewtonError| e.to_string())?;
            s.factorizations += 1;
            let pred = scaled_max(&predictor, 1.0, &ws.scales);
            if !pred.is_finite() {
                return Err("non-finite predictor".into());
            }
            for i in 0..n {
                predictor[i] = trial[i] - q[i] - predictor[i];
            }
            let corr = scaled_max(&predictor, 1.0, &ws.scales);
            if on_path && corr > PATH_JUMP_RATIO * pred && corr > settings.tolerance {
                return Err(format!(
                    "the Newton correction ({corr:.2e}) exceeds the tangent predictor ({pred:.2e}): the solution jumped off the load path"
                ));
            }
            Ok(s)
        };
        match attempt() {
            Ok(s) => {
                stats.newton += s;
                stats.increments += 1;
                q.copy_from_slice(&trial);
                sys.rebase(q);
                on_path = true;
                lambda = target;
                if s.iterations <= settings.max_iterations / 3 {
                    dl *= 2.0;
                }
            }
            Err(cause) => {
                dl *= 0.5;
                if dl < MIN_LOAD_INCREMENT {
                    return Err(StaticError {
                        reached: lambda,
                        attempted: target,
                        increment: dl * 2.0,
                        cause,
                    });
                }
            }
        }
    }
    Ok(stats)
}
