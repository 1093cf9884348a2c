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
}

impl std::ops::AddAssign for NewtonStats {
    fn add_assign(&mut self, o: Self) {
        self.iterations += o.iterations;
        self.factorizations += o.factorizations;
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
    /// Copy of the model's coordinate scales.
    pub scales: Vec<f64>,
    /// Coefficients of the iteration matrix currently factorized, if it may be reused.
    factored: Option<[u64; 3]>,
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
            scales: sys.scales().to_vec(),
            factored: None,
        })
    }

    /// Whether the factorization holds the iteration matrix of `coeffs`.
    pub fn is_factored(&self, coeffs: &JacobianCoeffs) -> bool {
        self.factored == Some(coeff_key(coeffs))
    }

    /// Records that the solver now holds a factorization of the matrix with key `key`.
    pub fn mark_factored(&mut self, key: [u64; 3]) {
        self.factored = Some(key);
    }

    /// Forgets the current factorization (after the solver was used for another matrix, or
    /// when the state jumped, e.g. at an FMU state restore).
    pub fn invalidate(&mut self) {
        self.factored = None;
    }
}

/// Key of an iteration matrix: the bit patterns of its coefficients.
pub fn coeff_key(c: &JacobianCoeffs) -> [u64; 3] {
    [c.mass.to_bits(), c.damping.to_bits(), c.stiffness.to_bits()]
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
/// `jac` is given, the iteration matrix for the coefficients `coeffs`. `increment_factor`
/// converts an increment of `x` into coordinate units for the convergence test (`β h²` when
/// `x` is an acceleration). With [`NewtonPolicy::Modified`], a factorization of the same
/// coefficients from an earlier solve is reused while the iteration contracts fast.
pub fn solve(
    ws: &mut Workspace,
    x: &mut [f64],
    settings: &NewtonSettings,
    increment_factor: f64,
    coeffs: JacobianCoeffs,
    mut eval: impl FnMut(&[f64], &mut [f64], Option<&mut [f64]>) -> Result<(), ModelError>,
) -> Result<NewtonStats, NewtonError> {
    let key = coeff_key(&coeffs);
    let modified = settings.policy == NewtonPolicy::Modified;
    let mut stats = NewtonStats::default();
    let mut fresh = !(modified && ws.factored == Some(key));
    let mut last = f64::INFINITY;
    let mut stale_iterations = 0;
    let mut it = 0;
    while it < settings.max_iterations {
        it += 1;
        if fresh {
            eval(x, &mut ws.r, Some(&mut ws.jac))?;
            ws.factored = None;
            ws.solver.factor(&ws.pattern, &ws.jac)?;
            ws.factored = Some(key);
            stats.factorizations += 1;
        } else {
            eval(x, &mut ws.r, None)?;
        }
        for (d, r) in ws.dx.iter_mut().zip(&ws.r) {
            *d = -r;
        }
        ws.solver.solve_in_place(&mut ws.dx);
        stats.iterations = it;
        let inc = scaled_max(&ws.dx, increment_factor, &ws.scales);
        let rate = inc / last;
        if !inc.is_finite() || inc > 1e6 || (!fresh && rate > 1.0) {
            if !fresh {
                // a stale iteration matrix: retry this iteration with a fresh one
                fresh = true;
                last = f64::INFINITY;
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
        // With linear convergence at rate θ the remaining error is about θ/(1−θ) times the
        // increment (Hairer & Wanner); with quadratic convergence the increment bounds it.
        // A first increment with a kept (stale) matrix says nothing about the rate: iterate on.
        let estimate = if fresh {
            inc
        } else if last.is_finite() && rate < 1.0 {
            inc * rate / (1.0 - rate)
        } else if inc == 0.0 {
            0.0
        } else {
            f64::INFINITY
        };
        if inc <= settings.tolerance && estimate <= settings.tolerance {
            if !modified {
                ws.factored = None;
            }
            return Ok(stats);
        }
        stale_iterations = if fresh { 0 } else { stale_iterations + 1 };
        // Rebuild when the iteration contracts slowly, or after a few iterations with the same
        // matrix (a kept matrix must not turn one step into many cheap but slow iterations).
        fresh = !modified
            || (last.is_finite() && rate > MODIFIED_NEWTON_RATE)
            || stale_iterations >= MODIFIED_NEWTON_MAX_REUSE;
        last = inc;
    }
    ws.factored = None;
    Err(NewtonError::NotConverged {
        iterations: settings.max_iterations,
        increment: last,
    })
}
