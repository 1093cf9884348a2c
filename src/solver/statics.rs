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
    held(sys, |sys| follow_load(sys, ws, q, settings, load_steps))
}

/// Runs `f` with the model's coordinates without static support held
/// ([`MechanicalSystem::hold_for_statics`]).
fn held<T>(sys: &mut dyn MechanicalSystem, f: impl FnOnce(&mut dyn MechanicalSystem) -> T) -> T {
    sys.hold_for_statics(true);
    let result = f(&mut *sys);
    sys.hold_for_statics(false);
    result
}

/// The static residual `f_int(q) − λ f_ext` at rest (zero velocities and accelerations,
/// `zeros` of the length of `q`) into `ws.r`, and the iteration matrix for `coeffs` into
/// `ws.jac`.
fn static_residual(
    sys: &mut dyn MechanicalSystem,
    ws: &mut Workspace,
    q: &[f64],
    zeros: &[f64],
    load: f64,
    coeffs: JacobianCoeffs,
) -> Result<(), crate::model::ModelError> {
    sys.residual(
        0.0,
        q,
        zeros,
        zeros,
        load,
        &mut ws.r,
        Some((coeffs, &mut ws.jac)),
    )
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
    if static_residual(sys, ws, q, &zeros, 0.0, coeffs).is_ok()
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
            static_residual(sys, ws, q, &zeros, target, coeffs).map_err(|e| e.to_string())?;
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
                let built = jac.is_some();
                sys.residual(0.0, x, &zeros, &zeros, target, r, jac.map(|j| (coeffs, j)))?;
                Ok(sys.matrix_state(built))
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

/// Counters of a pseudo-transient relaxation ([`relax`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RelaxStats {
    /// Pseudo-time steps taken (each one factorization and one solve).
    pub iterations: usize,
    /// Residual norm at the end over that at the start [1].
    pub reduction: f64,
}

/// Pseudo-transient continuation towards static equilibrium at full load (Kelley & Keyes,
/// "Convergence analysis of pseudo-transient continuation", SIAM J. Numer. Anal. 35, 1998,
/// eq. 1.4, with the switched evolution relaxation of Mulder & van Leer 1985 for the pseudo
/// time step): each iteration solves `(K + c M) Δq = −r(q)` and takes the full step, with
/// `c` = 1/Δτ² following the residual, `c_{k+1} = c_k ‖r_k‖/‖r_{k−1}‖` (clamped to a factor
/// 1/4..4 per iteration). Not monotone: the residual of a mount far from equilibrium may
/// grow before it falls (a safeguard that took such steps back stalled the quarter-twist
/// mount), and the iteration is not globally convergent (the softening spring `atan` from
/// far away cycles, as Newton's method does). The mass term regularizes what Newton alone cannot take from a
/// start far from equilibrium (a belt mounted with kinks); as the residual falls, `c` → 0
/// and the iteration becomes Newton's. Starts with `c` equal to the median over the
/// coordinates of `K_ii / M_ii` (the mass term as large as the stiffness). Stops when the Newton-like increment
/// (`c` below 1e-8 of its start, or the residual 1e-14 of its start) is below the tolerance, or after `max_iterations`; `q` is
/// left at the last iterate (a start for [`solve`], which then finishes at full load).
/// Held coordinates as in [`solve`].
pub fn relax(
    sys: &mut dyn MechanicalSystem,
    ws: &mut Workspace,
    q: &mut [f64],
    settings: &NewtonSettings,
    max_iterations: usize,
) -> Result<RelaxStats, String> {
    held(sys, |sys| relax_held(sys, ws, q, settings, max_iterations))
}

/// The iteration of [`relax`].
fn relax_held(
    sys: &mut dyn MechanicalSystem,
    ws: &mut Workspace,
    q: &mut [f64],
    settings: &NewtonSettings,
    max_iterations: usize,
) -> Result<RelaxStats, String> {
    let n = q.len();
    let zeros = vec![0.0; n];
    // diagonals of K and M, one evaluation each
    let diagonal = |sys: &mut dyn MechanicalSystem,
                    ws: &mut Workspace,
                    c: JacobianCoeffs,
                    out: &mut Vec<f64>| {
        static_residual(sys, ws, q, &zeros, 1.0, c).map_err(|e| e.to_string())?;
        out.clear();
        out.extend((0..n).map(|j| ws.pattern.position(j, j).map_or(0.0, |p| ws.jac[p].abs())));
        Ok::<(), String>(())
    };
    let (mut k_diag, mut m_diag) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let stiff = JacobianCoeffs {
        mass: 0.0,
        damping: 0.0,
        stiffness: 1.0,
    };
    let inert = JacobianCoeffs {
        mass: 1.0,
        damping: 0.0,
        stiffness: 0.0,
    };
    diagonal(sys, ws, stiff, &mut k_diag)?;
    diagonal(sys, ws, inert, &mut m_diag)?;
    // the median of K_ii / M_ii: one coordinate with an extreme inertia (a pulley of 1e300
    // kg m²) must not set the pseudo time step of all the others
    let mut ratios: Vec<f64> = k_diag
        .iter()
        .zip(&m_diag)
        .filter(|&(k, m)| *m > 0.0 && k.is_finite() && m.is_finite())
        .map(|(k, m)| k / m)
        .collect();
    if ratios.is_empty() {
        return Err("pseudo-transient relaxation needs a mass matrix".into());
    }
    ratios.sort_by(f64::total_cmp);
    let c0 = ratios[ratios.len() / 2];
    let mut c = c0;
    let norm = |r: &[f64]| r.iter().map(|x| x * x).sum::<f64>().sqrt();
    let (mut r_first, mut r_prev) = (f64::NAN, f64::NAN);
    let mut stats = RelaxStats::default();
    ws.invalidate();
    while stats.iterations < max_iterations {
        let coeffs = JacobianCoeffs {
            mass: c,
            damping: 0.0,
            stiffness: 1.0,
        };
        static_residual(sys, ws, q, &zeros, 1.0, coeffs).map_err(|e| e.to_string())?;
        let r_now = norm(&ws.r);
        if !r_now.is_finite() {
            return Err("non-finite residual in the pseudo-transient relaxation".into());
        }
        if r_first.is_nan() {
            r_first = r_now;
        } else if r_prev > 0.0 {
            c = (c * (r_now / r_prev).clamp(0.25, 4.0)).min(1e3 * c0);
        }
        r_prev = r_now;
        ws.solver
            .factor(&ws.pattern, &ws.jac)
            .map_err(|e| e.to_string())?;
        ws.dx.iter_mut().zip(&ws.r).for_each(|(d, r)| *d = -r);
        ws.solver.solve_in_place(&mut ws.dx);
        let inc = scaled_max(&ws.dx, 1.0, &ws.scales);
        if !inc.is_finite() {
            return Err("non-finite increment in the pseudo-transient relaxation".into());
        }
        for (qi, d) in q.iter_mut().zip(&ws.dx) {
            *qi += d;
        }
        sys.rebase(q);
        stats.iterations += 1;
        stats.reduction = r_now / r_first;
        if inc <= settings.tolerance && (c < 1e-8 * c0 || r_now <= 1e-14 * r_first) {
            break;
        }
    }
    ws.invalidate();
    Ok(stats)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::{CscPattern, SolverKind};
    use crate::model::ModelError;

    /// One coordinate, unit mass, the softening spring `f(q) = atan(q − 3)`: Newton's method
    /// diverges from any start farther than about 1.39 from the root (the classic example,
    /// e.g. Kelley, "Solving Nonlinear Equations with Newton's Method", SIAM 2003, §1.7);
    /// the relaxation from 2 away converges (from much farther it cycles: it is not globally
    /// convergent).
    struct AtanSpring {
        pattern: CscPattern,
        scales: Vec<f64>,
    }

    impl MechanicalSystem for AtanSpring {
        fn n_free(&self) -> usize {
            1
        }
        fn pattern(&self) -> &CscPattern {
            &self.pattern
        }
        fn scales(&self) -> &[f64] {
            &self.scales
        }
        fn residual(
            &mut self,
            _t: f64,
            q: &[f64],
            _v: &[f64],
            a: &[f64],
            _l: f64,
            r: &mut [f64],
            jac: Option<(JacobianCoeffs, &mut [f64])>,
        ) -> Result<(), ModelError> {
            r[0] = a[0] + (q[0] - 3.0).atan();
            if let Some((c, j)) = jac {
                j[0] = c.mass + c.stiffness / (1.0 + (q[0] - 3.0).powi(2));
            }
            Ok(())
        }
        fn midpoint_residual(
            &mut self,
            _ta: f64,
            t: f64,
            _qa: &[f64],
            qb: &[f64],
            v: &[f64],
            a: &[f64],
            r: &mut [f64],
            jac: Option<(JacobianCoeffs, &mut [f64])>,
        ) -> Result<(), ModelError> {
            self.residual(t, qb, v, a, 1.0, r, jac)
        }
    }

    fn spring() -> (AtanSpring, Workspace, NewtonSettings) {
        let s = AtanSpring {
            pattern: CscPattern::from_entries(1, []),
            scales: vec![1.0],
        };
        let ws = Workspace::new(&s, SolverKind::Auto).unwrap();
        let settings = NewtonSettings {
            tolerance: 1e-12,
            max_iterations: 25,
            policy: NewtonPolicy::Full,
            line_search: false,
        };
        (s, ws, settings)
    }

    #[test]
    fn relaxation_reaches_what_newton_misses() {
        let (mut s, mut ws, settings) = spring();
        // Newton alone (undamped, as the settings of a model without `damped_newton`; one
        // load step: the spring has no load to step) fails from q = 1
        let mut q = [1.0];
        assert!(solve(&mut s, &mut ws, &mut q, &settings, 1).is_err());
        let mut q = [1.0];
        let st = relax(&mut s, &mut ws, &mut q, &settings, 200).unwrap();
        assert!((q[0] - 3.0).abs() < 1e-10, "q = {}", q[0]);
        assert!(st.iterations < 200 && st.reduction < 1e-10, "{st:?}");
    }
}
