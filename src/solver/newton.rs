//! Newton's method with a sparse iteration matrix and scaled increment convergence.

use crate::linalg::{CscPattern, FactorError, LinearSolver, SolverKind};
use crate::model::{MechanicalSystem, ModelError};

/// Newton settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonSettings {
    /// Converged when the largest scaled coordinate increment (increment / coordinate scale)
    /// is below this [1].
    pub tolerance: f64,
    /// Iterations before giving up.
    pub max_iterations: usize,
}

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
}

impl Workspace {
    /// Buffers for a model's pattern, with the chosen factorization.
    pub fn new(sys: &dyn MechanicalSystem, kind: SolverKind) -> Result<Self, FactorError> {
        let n = sys.n_free();
        Ok(Self {
            r: vec![0.0; n],
            dx: vec![0.0; n],
            jac: vec![0.0; sys.pattern().nnz()],
            solver: LinearSolver::new(sys.pattern(), kind)?,
            pattern: sys.pattern().clone(),
            scales: sys.scales().to_vec(),
        })
    }
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
/// `jac` is given, the iteration matrix. `increment_factor` converts an increment of `x` into
/// coordinate units for the convergence test (`β h²` when `x` is an acceleration).
pub fn solve(
    ws: &mut Workspace,
    x: &mut [f64],
    settings: &NewtonSettings,
    increment_factor: f64,
    mut eval: impl FnMut(&[f64], &mut [f64], Option<&mut [f64]>) -> Result<(), ModelError>,
) -> Result<NewtonStats, NewtonError> {
    let mut stats = NewtonStats::default();
    let mut last = f64::INFINITY;
    for it in 1..=settings.max_iterations {
        eval(x, &mut ws.r, Some(&mut ws.jac))?;
        ws.solver.factor(&ws.pattern, &ws.jac)?;
        stats.factorizations += 1;
        for (d, r) in ws.dx.iter_mut().zip(&ws.r) {
            *d = -r;
        }
        ws.solver.solve_in_place(&mut ws.dx);
        stats.iterations = it;
        let inc = scaled_max(&ws.dx, increment_factor, &ws.scales);
        if !inc.is_finite() || inc > 1e6 {
            return Err(NewtonError::Diverged {
                iterations: it,
                increment: inc,
            });
        }
        for (xi, d) in x.iter_mut().zip(&ws.dx) {
            *xi += d;
        }
        if inc <= settings.tolerance {
            return Ok(stats);
        }
        last = inc;
    }
    Err(NewtonError::NotConverged {
        iterations: settings.max_iterations,
        increment: last,
    })
}
