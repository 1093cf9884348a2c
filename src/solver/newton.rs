//! Newton's method with a sparse iteration matrix and scaled increment convergence.

use crate::linalg::{CscPattern, FactorError, LinearSolver, SolverKind};
use crate::model::{JacobianCoeffs, MechanicalSystem, ModelError};

/// Newton settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonSettings {
    /// Converged when the largest scaled coordinate increment (increment / coordinate scale)
    /// is below this [1].
    pub tolerance: f64,
    /// Iterations before giving up.
    pub max_iterations: usize,
    /// Full Newton (new iteration matrix every iteration) or modified Newton (keep the
    /// factorization while the iteration contracts fast).
    pub policy: NewtonPolicy,
    /// Damped Newton: backtrack a full-Newton increment that raises the residual norm (see
    /// [`solve`]). Set for the models that ask for it
    /// ([`crate::model::MechanicalSystem::damped_newton`]: the planar and 3D belt drives,
    /// where it breaks the cycles of contact points changing state). Not on for every model:
    /// a backtracked increment moves the converged state within the Newton tolerance, and
    /// the other kinds' references (`compat/`) were computed without it.
    pub line_search: bool,
}

/// When the iteration matrix is rebuilt and refactorized.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NewtonPolicy {
    /// Every iteration (quadratic convergence, most work per iteration).
    Full,
    /// Only when the contraction of the increments is slower than [`MODIFIED_NEWTON_RATE`],
    /// when the step coefficients change, or when an iteration diverges; the factorization is
    /// kept across steps.
    Modified,
}

/// Largest contraction rate accepted before modified Newton rebuilds the iteration matrix.
pub const MODIFIED_NEWTON_RATE: f64 = 0.25;

/// Iterations in a row that modified Newton does with one matrix before rebuilding it.
pub const MODIFIED_NEWTON_MAX_REUSE: usize = 4;

/// Share of a solve's outcome in the running mean of failures of a kept matrix in the second
/// iteration ([`Workspace`]'s `second_failures`) [1].
pub const SECOND_FRESH_MEMORY: f64 = 0.125;

/// Modified Newton computes a solve's second iteration with a fresh matrix (as the first one)
/// while the kept matrix has failed there (its increment larger than the first, so the
/// iteration is redone with a fresh matrix) in more than this share of recent solves [1].
/// On the serpentine drive (`examples/bench_belt_predictor.rs serpentine`) the matrix of the
/// transport predictor's state failed in 78 % of the second iterations (contact points at the
/// arc ends change state in the first increment), each failure a residual and a solve for
/// nothing; on the two-pulley drive in 20 %, where the rule stays off.
pub const SECOND_FRESH_THRESHOLD: f64 = 0.5;

/// While [`SECOND_FRESH_THRESHOLD`] is exceeded, every this-many-th solve still tries the kept
/// matrix in its second iteration, so that the rate of failures goes on being measured.
pub const SECOND_FRESH_PROBE: usize = 8;

/// Halvings of a full-Newton increment that raised the residual norm, at most, before the
/// iteration goes on from the shortened increment (see [`solve`]).
pub const LINE_SEARCH_MAX_CUTS: usize = 3;

/// Rise of the residual norm over a full-Newton increment that makes [`solve`] backtrack [1]:
/// the increment is halved when `|r(x + α dx)| > 1.05 |r(x)|`. Not at 1: on a smooth drive
/// (the planar belt drive) a converging iteration's residual norm often stays level within
/// 0.1-1 % over one increment (rows of different units), and halving those steps only moves
/// the converged state within the Newton tolerance; the serpentine drive's cycling
/// (`examples/bench_belt_predictor.rs serpentine`) rises by 5 % to 10x.
pub const LINE_SEARCH_RISE: f64 = 1.05;

/// Why Newton failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NewtonError {
    /// No convergence within the iteration limit.
    #[error(
        "Newton did not converge in {iterations} iterations (last scaled increment {increment:.3e})"
    )]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// Last scaled increment.
        increment: f64,
    },
    /// The increments grew beyond any sensible size or became NaN.
    #[error("Newton diverged (scaled increment {increment:.3e} after {iterations} iterations)")]
    Diverged {
        /// Iterations done.
        iterations: usize,
        /// The offending increment.
        increment: f64,
    },
    /// The iteration matrix could not be factorized.
    #[error("{0}")]
    Factor(#[from] FactorError),
    /// The model could not be evaluated.
    #[error("{0}")]
    Model(#[from] ModelError),
}

/// Work counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NewtonStats {
    /// Newton iterations.
    pub iterations: usize,
    /// Numeric factorizations.
    pub factorizations: usize,
    /// Residual evaluations spent shortening increments (backtracking, see [`solve`]).
    pub backtracks: usize,
    /// Of the factorizations, those of a refreshed kept matrix ([`MatrixState::Refreshed`]).
    pub refreshes: usize,
}

impl std::ops::AddAssign for NewtonStats {
    fn add_assign(&mut self, o: Self) {
        self.iterations += o.iterations;
        self.factorizations += o.factorizations;
        self.backtracks += o.backtracks;
        self.refreshes += o.refreshes;
    }
}

/// What an evaluation of [`solve`]'s `eval` says about the iteration matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MatrixState {
    /// A matrix built at the evaluated state, or (an evaluation without one) the kept matrix
    /// still describes the residual.
    Current,
    /// Evaluated without a matrix: the kept one no longer describes the residual (see
    /// [`MechanicalSystem::kept_matrix_current`]); the iteration asks for one at the same state.
    Stale,
    /// Asked for a matrix right after a [`MatrixState::Stale`] answer, at the same state: the
    /// kept matrix with only the parts that made it stale rebuilt (see
    /// [`MechanicalSystem::refreshed_matrix`]). Not the exact matrix of the state: the
    /// iteration treats it as a kept one (convergence judged from the contraction rate).
    Refreshed,
}

impl From<bool> for MatrixState {
    /// `true`: [`MatrixState::Current`], `false`: [`MatrixState::Stale`].
    fn from(current: bool) -> Self {
        if current { Self::Current } else { Self::Stale }
    }
}

/// Buffers and the factorization for one model; allocated once per mesh.
#[derive(Debug)]
pub struct Workspace {
    /// Residual.
    pub r: Vec<f64>,
    /// Increment.
    pub dx: Vec<f64>,
    /// Iteration matrix values.
    pub jac: Vec<f64>,
    /// Factorization.
    pub solver: LinearSolver,
    /// Copy of the model's pattern.
    pub pattern: CscPattern,
    /// Copy of the model's Newton scales ([`MechanicalSystem::newton_scales`]).
    pub scales: Vec<f64>,
    /// Copy of the model's coordinate scales for error estimates
    /// ([`MechanicalSystem::scales`]).
    pub error_scales: Vec<f64>,
    /// Coefficients of the iteration matrix currently factorized, if it may be reused.
    factored: Option<JacobianCoeffs>,
    /// The contraction rate the factorized matrix showed in its last iteration with a measured
    /// rate (see [`MechanicalSystem::trusts_kept_contraction`]).
    kept_rate: Option<f64>,
    /// Whether the first iteration of a solve with a kept matrix is judged by `kept_rate`.
    trust_kept: bool,
    /// Whether a solve that converged with a kept matrix contracting slower than
    /// `rebuild_rate` leaves it for a fresh one in the next solve
    /// ([`MechanicalSystem::rebuilds_slow_kept_matrix`]).
    rebuild_slow: bool,
    /// Running mean of the failures of a kept matrix in the second iteration of a solve that
    /// started with a fresh one (see [`SECOND_FRESH_THRESHOLD`]) [1].
    second_failures: f64,
    /// Solves counted modulo [`SECOND_FRESH_PROBE`].
    second_probe: usize,
    /// Whether the rule of [`SECOND_FRESH_THRESHOLD`] is on
    /// ([`MechanicalSystem::learns_second_iteration`]).
    learn_second: bool,
    /// Contraction rate above which modified Newton rebuilds the matrix
    /// ([`MechanicalSystem::modified_newton_rate`]).
    rebuild_rate: f64,
    /// Halvings of a full-Newton increment that raised the residual norm, at most
    /// ([`MechanicalSystem::line_search_cuts`]).
    max_cuts: usize,
}

impl Workspace {
    /// Buffers for a model's pattern, with the chosen factorization.
    pub fn new(sys: &dyn MechanicalSystem, kind: SolverKind) -> Result<Self, FactorError> {
        let n = sys.n_free();
        Ok(Self {
            r: vec![0.0; n],
            dx: vec![0.0; n],
            jac: vec![
                0.0;
                if sys.rank_one() {
                    crate::linalg::rank_one_len(sys.pattern())
                } else {
                    sys.pattern().nnz()
                }
            ],
            solver: LinearSolver::new(sys.pattern(), kind)?,
            pattern: sys.pattern().clone(),
            scales: sys.newton_scales().to_vec(),
            error_scales: sys.scales().to_vec(),
            factored: None,
            kept_rate: None,
            second_failures: 0.0,
            second_probe: 0,
            learn_second: sys.learns_second_iteration(),
            trust_kept: sys.trusts_kept_contraction(),
            rebuild_slow: sys.rebuilds_slow_kept_matrix(),
            rebuild_rate: sys.modified_newton_rate(),
            max_cuts: sys.line_search_cuts(),
        })
    }

    /// Whether the factorization holds the iteration matrix of `coeffs`.
    pub fn is_factored(&self, coeffs: &JacobianCoeffs) -> bool {
        self.factored.is_some_and(|f| same_coeffs(&f, coeffs))
    }

    /// Records that the solver now holds a factorization of the matrix with coefficients
    /// `coeffs`.
    pub fn mark_factored(&mut self, coeffs: &JacobianCoeffs) {
        self.factored = Some(*coeffs);
    }

    /// Forgets what the solves so far taught about the kept matrix (the running mean of
    /// [`SECOND_FRESH_THRESHOLD`]), so that a run continued after a saved state and a run
    /// restored from it iterate alike.
    pub fn forget_history(&mut self) {
        self.second_failures = 0.0;
        self.second_probe = 0;
    }

    /// Forgets the current factorization (after the solver was used for another matrix, or
    /// when the state jumped, e.g. at an FMU state restore).
    pub fn invalidate(&mut self) {
        self.factored = None;
        self.kept_rate = None;
    }
}

/// Whether two iteration matrices count as the same for reusing a factorization: every
/// coefficient equal to 1e-9 relative. A communication step that a master computes as a
/// difference of times (`0.0010000000000000009` for 1 ms) must not change the iteration path:
/// a fresh factorization there makes the converged state differ by up to the Newton
/// tolerance, which is what an importer's re-run of a reference result then shows.
pub fn same_coeffs(a: &JacobianCoeffs, b: &JacobianCoeffs) -> bool {
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-9 * x.abs().max(y.abs());
    close(a.mass, b.mass) && close(a.damping, b.damping) && close(a.stiffness, b.stiffness)
}

/// Largest `|dx_i| · factor / scale_i`.
pub fn scaled_max(dx: &[f64], factor: f64, scales: &[f64]) -> f64 {
    dx.iter()
        .zip(scales)
        .map(|(d, s)| (d * factor / s).abs())
        .fold(0.0, |m, v| {
            if v.is_nan() || m.is_nan() {
                f64::NAN
            } else {
                m.max(v)
            }
        })
}

/// Solves `F(x) = 0` by Newton's method. `eval(x, r, jac)` fills the residual and, when
/// `jac` is given, the iteration matrix for the coefficients `coeffs`; it returns whether a
/// matrix built earlier still describes this residual (always true when it built one; see
/// [`MechanicalSystem::kept_matrix_current`]), else the iteration rebuilds it (after the
/// backtracking test below has judged the last full-Newton increment by that residual), as a
/// [`MatrixState`] (or a `bool`: current or not). A model may answer that rebuild with a
/// refreshed kept matrix ([`MatrixState::Refreshed`]); the iteration then goes on as with a
/// kept matrix, and a failure of it (divergence) asks for a matrix again.
/// `increment_factor` converts an increment of `x` into coordinate units for the convergence
/// test (`β h²` when `x` is an acceleration). With [`NewtonPolicy::Modified`], a factorization of the same
/// coefficients from an earlier solve is reused while the iteration contracts fast.
///
/// Damped Newton (backtracking on the residual norm, e.g. Deuflhard, Newton Methods for
/// Nonlinear Problems, 2004, §3.1): when an increment computed with a fresh iteration matrix
/// raises `|r|` by more than [`LINE_SEARCH_RISE`], half of what was applied is taken back, up to
/// [`LINE_SEARCH_MAX_CUTS`] times, and the iteration goes on from there. This breaks the
/// two-step cycles that contact points changing state (in/out of contact, stick/slip) cause
/// with full steps; the convergence test is unchanged (scaled increment).
pub fn solve<S: Into<MatrixState>>(
    ws: &mut Workspace,
    x: &mut [f64],
    settings: &NewtonSettings,
    increment_factor: f64,
    coeffs: JacobianCoeffs,
    mut eval: impl FnMut(&[f64], &mut [f64], Option<&mut [f64]>) -> Result<S, ModelError>,
) -> Result<NewtonStats, NewtonError> {
    let modified = settings.policy == NewtonPolicy::Modified;
    let mut stats = NewtonStats::default();
    let mut fresh = !(modified && ws.is_factored(&coeffs));
    let mut last = f64::INFINITY;
    let mut stale_iterations = 0;
    let mut it = 0;
    // Backtracking: the residual norm at the start of the last full-Newton step and the
    // fraction of that step still applied (None: the last step was not a full-Newton step).
    let mut line: Option<(f64, f64)> = None;
    let mut cuts = 0;
    // Whether the first iteration of this solve had a fresh matrix (then the kept matrix's
    // outcome in the second iteration is recorded in `ws.second_failures`).
    let mut first_fresh = false;
    while it < settings.max_iterations {
        let state: MatrixState = if fresh {
            eval(x, &mut ws.r, Some(&mut ws.jac))?.into()
        } else {
            eval(x, &mut ws.r, None)?.into()
        };
        let current = state != MatrixState::Stale;
        let refreshed = fresh && state == MatrixState::Refreshed;
        // the residual norm only steers the backtracking
        let norm = if settings.line_search {
            ws.r.iter().map(|r| r * r).sum::<f64>().sqrt()
        } else {
            0.0
        };
        if let Some((prev, alpha)) = line
            && (norm > LINE_SEARCH_RISE * prev || norm.is_nan())
            && cuts < ws.max_cuts
            && settings.line_search
        {
            // The full-Newton increment (whose direction is one of descent for |r|²) did not
            // lower the residual: take back half of what was applied and evaluate again.
            let back = 0.5 * alpha;
            for (xi, d) in x.iter_mut().zip(&ws.dx) {
                *xi -= back * d;
            }
            line = Some((prev, alpha - back));
            last *= (alpha - back) / alpha;
            cuts += 1;
            stats.backtracks += 1;
            continue;
        }
        if !current {
            // the kept matrix no longer describes the residual (contact points changed):
            // evaluate again with a new one
            fresh = true;
            last = f64::INFINITY;
            line = None;
            continue;
        }
        it += 1;
        if it == 1 {
            first_fresh = fresh;
        }
        if fresh {
            ws.factored = None;
            ws.kept_rate = None;
            ws.solver.factor(&ws.pattern, &ws.jac)?;
            ws.factored = Some(coeffs);
            stats.factorizations += 1;
            stats.refreshes += usize::from(refreshed);
            // a refreshed matrix is judged as a kept one from here on
            fresh = !refreshed;
        }
        for (d, r) in ws.dx.iter_mut().zip(&ws.r) {
            *d = -r;
        }
        ws.solver.solve_in_place(&mut ws.dx);
        stats.iterations = it;
        let inc = scaled_max(&ws.dx, increment_factor, &ws.scales);
        let rate = inc / last;
        let stale_failed = !inc.is_finite() || inc > 1e6 || (!fresh && rate > 1.0);
        if ws.learn_second && modified && !fresh && it == 2 && first_fresh {
            let failed = if stale_failed { 1.0 } else { 0.0 };
            ws.second_failures += SECOND_FRESH_MEMORY * (failed - ws.second_failures);
        }
        if stale_failed {
            if !fresh {
                // a stale iteration matrix: retry this iteration with a fresh one
                fresh = true;
                last = f64::INFINITY;
                line = None;
                continue;
            }
            ws.factored = None;
            return Err(NewtonError::Diverged {
                iterations: it,
                increment: inc,
            });
        }
        for (xi, d) in x.iter_mut().zip(&ws.dx) {
            *xi += d;
        }
        // (a refreshed matrix's increment too: it is nearly a full-Newton one)
        line = (fresh || refreshed).then_some((norm, 1.0));
        cuts = 0;
        // With linear convergence at rate θ the remaining error is about θ/(1−θ) times the
        // increment (Hairer & Wanner); with quadratic convergence the increment bounds it.
        // A first increment with a kept (stale) matrix says nothing about the rate: iterate on
        // (unless the model trusts the rate the matrix showed in its last use, and that rate
        // was fast).
        let estimate = if fresh {
            inc
        } else if last.is_finite() && rate < 1.0 {
            ws.kept_rate = Some(rate);
            inc * rate / (1.0 - rate)
        } else if inc == 0.0 {
            0.0
        } else if let Some(theta) = ws
            .kept_rate
            .filter(|&t| ws.trust_kept && t <= MODIFIED_NEWTON_RATE)
        {
            inc * theta / (1.0 - theta)
        } else {
            f64::INFINITY
        };
        if inc <= settings.tolerance && estimate <= settings.tolerance {
            if !modified {
                ws.factored = None;
            } else if ws.rebuild_slow && !fresh && last.is_finite() && rate > ws.rebuild_rate {
                // converged, but the kept matrix contracts slowly: the next solve would take
                // at least two iterations with it again (its rate is not trusted)
                ws.factored = None;
                ws.kept_rate = None;
            }
            return Ok(stats);
        }
        // The second iteration with a fresh matrix where the first one's matrix has recently
        // failed in it (see `SECOND_FRESH_THRESHOLD`); every `SECOND_FRESH_PROBE`-th solve
        // tries the kept one anyway, to go on measuring.
        let second_fresh = ws.learn_second && modified && fresh && it == 1 && {
            ws.second_probe = (ws.second_probe + 1) % SECOND_FRESH_PROBE;
            ws.second_failures > SECOND_FRESH_THRESHOLD && ws.second_probe != 0
        };
        stale_iterations = if fresh { 0 } else { stale_iterations + 1 };
        // Rebuild when the iteration contracts slowly, or after a few iterations with the same
        // matrix (a kept matrix must not turn one step into many cheap but slow iterations).
        fresh = !modified
            || second_fresh
            || (last.is_finite() && rate > ws.rebuild_rate)
            || stale_iterations >= MODIFIED_NEWTON_MAX_REUSE;
        last = inc;
    }
    ws.factored = None;
    Err(NewtonError::NotConverged {
        iterations: settings.max_iterations,
        increment: last,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A workspace for one unknown (unit scales, the default rates), learning the second
    /// iteration if `learn`.
    fn scalar_workspace(learn: bool) -> Workspace {
        let pattern = CscPattern::from_entries(1, [(0, 0)]);
        Workspace {
            r: vec![0.0],
            dx: vec![0.0],
            jac: vec![0.0],
            solver: LinearSolver::new(&pattern, SolverKind::Auto).unwrap(),
            pattern,
            scales: vec![1.0],
            error_scales: vec![1.0],
            factored: None,
            kept_rate: None,
            second_failures: 0.0,
            second_probe: 0,
            learn_second: learn,
            trust_kept: false,
            rebuild_slow: false,
            rebuild_rate: MODIFIED_NEWTON_RATE,
            max_cuts: LINE_SEARCH_MAX_CUTS,
        }
    }

    /// A solve that converges with a kept matrix contracting slower than the rebuild rate
    /// leaves it for a fresh one in the next solve when the model asks
    /// ([`MechanicalSystem::rebuilds_slow_kept_matrix`]), and keeps it otherwise.
    #[test]
    fn slow_kept_matrix_is_dropped_after_convergence_on_request() {
        let settings = NewtonSettings {
            tolerance: 1e-6,
            max_iterations: 10,
            policy: NewtonPolicy::Modified,
            line_search: false,
        };
        let coeffs = JacobianCoeffs {
            mass: 0.0,
            damping: 0.0,
            stiffness: 1.0,
        };
        for rebuild in [false, true] {
            let mut ws = scalar_workspace(false);
            ws.rebuild_slow = rebuild;
            // r = 2 (x − 1) with its exact matrix: converged, the matrix kept (rate 0)
            let mut x = [0.0];
            solve(&mut ws, &mut x, &settings, 1.0, coeffs, |x, r, jac| {
                r[0] = 2.0 * (x[0] - 1.0);
                if let Some(j) = jac {
                    j[0] = 2.0;
                }
                Ok(true)
            })
            .unwrap();
            assert!(ws.is_factored(&coeffs));
            // r = 3 (x − 2) from within the tolerance: the kept matrix (2) contracts at 1/2,
            // the first increment is not trusted, the second converges
            let mut x = [2.0 + 0.5e-6];
            let stats = solve(&mut ws, &mut x, &settings, 1.0, coeffs, |x, r, jac| {
                r[0] = 3.0 * (x[0] - 2.0);
                if let Some(j) = jac {
                    j[0] = 3.0;
                }
                Ok(true)
            })
            .unwrap();
            assert_eq!((stats.iterations, stats.factorizations), (2, 0));
            assert_eq!(ws.is_factored(&coeffs), !rebuild, "rebuild_slow {rebuild}");
        }
    }

    /// A kept matrix found stale is asked for again at the same state; a model answering with
    /// a refreshed matrix ([`MatrixState::Refreshed`]) has it factorized and counted, and the
    /// iteration judges it as a kept one: on `r = 2 (x − 1)` from 0 with a tolerance above the
    /// first increment (1), a fresh matrix converges in one iteration, a refreshed one
    /// (exact here) takes a second to measure its rate.
    #[test]
    fn refreshed_matrix_is_judged_as_a_kept_one() {
        let settings = NewtonSettings {
            tolerance: 2.0,
            max_iterations: 10,
            policy: NewtonPolicy::Modified,
            line_search: true,
        };
        let coeffs = JacobianCoeffs {
            mass: 0.0,
            damping: 0.0,
            stiffness: 1.0,
        };
        for refresh in [false, true] {
            let mut ws = scalar_workspace(false);
            ws.factored = Some(coeffs);
            let mut stale_answers = 0;
            let mut x = [0.0];
            let stats = solve(&mut ws, &mut x, &settings, 1.0, coeffs, |x, r, jac| {
                r[0] = 2.0 * (x[0] - 1.0);
                Ok(match jac {
                    Some(j) => {
                        j[0] = 2.0;
                        if refresh {
                            MatrixState::Refreshed
                        } else {
                            MatrixState::Current
                        }
                    }
                    None if stale_answers == 0 => {
                        stale_answers += 1;
                        MatrixState::Stale
                    }
                    None => MatrixState::Current,
                })
            })
            .unwrap();
            assert_eq!(stale_answers, 1);
            let expect = if refresh { (2, 1, 1) } else { (1, 1, 0) };
            assert_eq!(
                (stats.iterations, stats.factorizations, stats.refreshes),
                expect,
                "refresh {refresh}"
            );
            assert_eq!(x[0], 1.0);
        }
    }

    /// Damped Newton on `atan(x) = 0` from `x0 = 2`: the full step lands at
    /// `2 − atan(2)·5 = −3.54`, where `|atan|` is larger (1.295 > 1.107), and undamped Newton
    /// diverges from there (a textbook case, Deuflhard 2004, §1.1); halving the step brings
    /// the iteration into the region of convergence and it finds the root 0.
    #[test]
    fn backtracking_converges_where_full_newton_steps_diverge() {
        let mut ws = scalar_workspace(false);
        let x0: f64 = 2.0;
        let full_step = x0 - x0.atan() * (1.0 + x0 * x0);
        assert!(full_step.atan().abs() > LINE_SEARCH_RISE * x0.atan().abs());
        let settings = NewtonSettings {
            tolerance: 1e-12,
            max_iterations: 25,
            policy: NewtonPolicy::Full,
            line_search: true,
        };
        let coeffs = JacobianCoeffs {
            mass: 1.0,
            damping: 0.0,
            stiffness: 0.0,
        };
        let mut x = [x0];
        let stats = solve(&mut ws, &mut x, &settings, 1.0, coeffs, |x, r, jac| {
            r[0] = x[0].atan();
            if let Some(j) = jac {
                j[0] = 1.0 / (1.0 + x[0] * x[0]);
            }
            Ok(true)
        })
        .unwrap();
        assert!(x[0].abs() < 1e-12, "{}", x[0]);
        assert!(stats.backtracks >= 1, "{stats:?}");
    }

    /// Ten solves of `f(x) = 0` from `x0`, each starting with a fresh matrix (as after the belt's
    /// predictor), with or without learning the second iteration: total work and the roots.
    fn repeated_solves(f: fn(f64) -> (f64, f64), x0: f64, learn: bool) -> (NewtonStats, Vec<f64>) {
        let mut ws = scalar_workspace(learn);
        let settings = NewtonSettings {
            tolerance: 1e-12,
            max_iterations: 25,
            policy: NewtonPolicy::Modified,
            line_search: false,
        };
        let coeffs = JacobianCoeffs {
            mass: 1.0,
            damping: 0.0,
            stiffness: 0.0,
        };
        let mut total = NewtonStats::default();
        let mut roots = Vec::new();
        for _ in 0..10 {
            ws.invalidate();
            let mut x = [x0];
            total += solve(&mut ws, &mut x, &settings, 1.0, coeffs, |x, r, jac| {
                let (v, d) = f(x[0]);
                r[0] = v;
                if let Some(j) = jac {
                    j[0] = d;
                }
                Ok(true)
            })
            .unwrap();
            roots.push(x[0]);
        }
        (total, roots)
    }

    /// `x³ = 8` from 1: the first increment lands at 3.33, where the matrix of x = 1 (slope 3
    /// against 33) gives a larger second increment than the first, so modified Newton redoes
    /// that iteration with a fresh matrix. Learning it, the solves from the sixth on compute
    /// their second iteration with a fresh matrix directly (one probe in eight with the kept
    /// one): fewer iterations, the same factorizations and roots. Where the kept matrix works
    /// (`x + 0.1 x³ = 1` from 0, second increment a tenth of the first) nothing changes.
    #[test]
    fn second_iteration_is_fresh_where_the_kept_matrix_keeps_failing() {
        let cubic = |x: f64| (x * x * x - 8.0, 3.0 * x * x);
        let (off, roots_off) = repeated_solves(cubic, 1.0, false);
        let (on, roots_on) = repeated_solves(cubic, 1.0, true);
        assert!(on.iterations + 4 <= off.iterations, "{on:?} {off:?}");
        assert_eq!(on.factorizations, off.factorizations, "{on:?} {off:?}");
        for (a, b) in roots_on.iter().zip(&roots_off) {
            assert!(
                (a - 2.0).abs() < 1e-12 && (b - 2.0).abs() < 1e-12,
                "{a} {b}"
            );
        }
        let mild = |x: f64| (x + 0.1 * x * x * x - 1.0, 1.0 + 0.3 * x * x);
        let (off, roots_off) = repeated_solves(mild, 0.0, false);
        let (on, roots_on) = repeated_solves(mild, 0.0, true);
        assert_eq!(on, off);
        assert_eq!(roots_on, roots_off);
    }

    /// A step size that differs from the factorized one by round-off (a master's
    /// `t_{k+1} − t_k`) reuses the factorization; a step size 1e-6 apart does not.
    #[test]
    fn factorization_reuse_tolerates_round_off_in_the_step_size() {
        let h: f64 = 1e-3;
        let h_master = 0.009 - 0.008; // 0.0010000000000000009
        assert_ne!(h, h_master);
        let c = |h: f64| JacobianCoeffs {
            mass: 1.0,
            damping: 0.5 * h,
            stiffness: 0.25 * h * h,
        };
        assert!(same_coeffs(&c(h), &c(h_master)));
        assert!(!same_coeffs(&c(h), &c(h * (1.0 + 1e-6))));
        assert!(!same_coeffs(&c(h), &JacobianCoeffs { mass: 0.0, ..c(h) }));
    }
}
