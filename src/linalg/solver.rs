//! Choice of factorization for the global iteration matrix.

use super::FactorError;
use super::banded::BandedLu;
use super::bordered::BorderedBanded;
use super::csc::CscPattern;
use super::sparse_lu::SparseLu;

/// Which factorization to use (FMU parameter `solver.linear_solver`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolverKind {
    /// Banded when the bandwidth is small against the size; else bordered banded when a
    /// Cuthill–McKee reordering makes it narrow apart from a few dense rows and columns (closed
    /// loops); sparse LU otherwise.
    Auto,
    /// Banded LU with partial pivoting.
    Banded,
    /// faer sparse LU.
    SparseLu,
}

/// Whether banded LU of a matrix of size `n` with the band `kl + ku` is cheaper than
/// fill-reducing sparse LU. A band wider than an eighth of the matrix (closed loops, dense
/// couplings) costs more, and so does a wide band of a 2D mesh (a shell: band ∝ √n): on plates
/// of 32 × 32 and 64 × 64 shell elements (band 400–800) sparse LU factors and solves 1.9 and
/// 3.0 times faster than banded LU, and 4 and 8 times faster than the bordered banded solver
/// (examples/bench_shell.rs, section 1).
pub(crate) fn band_is_cheap(band: usize, n: usize) -> bool {
    band <= 24 || (8 * band <= n && band <= 96)
}

/// A factorization backend bound to one pattern.
#[derive(Debug)]
pub enum LinearSolver {
    /// Banded LU.
    Banded(BandedLu),
    /// Sparse LU.
    Sparse(Box<SparseLu>),
    /// Banded LU of a reordered core with a dense border (Schur complement).
    Bordered(Box<BorderedBanded>),
}

impl LinearSolver {
    /// Analyses `pattern` and prepares buffers for the chosen backend.
    pub fn new(pattern: &CscPattern, kind: SolverKind) -> Result<Self, FactorError> {
        let (kl, ku) = pattern.bandwidths();
        let n = pattern.n();
        let banded = match kind {
            SolverKind::Banded => true,
            SolverKind::SparseLu => false,
            SolverKind::Auto => band_is_cheap(kl + ku, n),
        };
        if banded {
            return Ok(LinearSolver::Banded(BandedLu::new(n, kl, ku)));
        }
        if kind == SolverKind::Auto
            && let Some(b) = BorderedBanded::analyse(pattern)
        {
            return Ok(LinearSolver::Bordered(Box::new(b)));
        }
        Ok(LinearSolver::Sparse(Box::new(SparseLu::new(pattern)?)))
    }

    /// Numeric factorization.
    pub fn factor(&mut self, pattern: &CscPattern, vals: &[f64]) -> Result<(), FactorError> {
        match self {
            LinearSolver::Banded(b) => b.factor(pattern, vals),
            LinearSolver::Sparse(s) => s.factor(pattern, vals),
            LinearSolver::Bordered(b) => b.factor(vals),
        }
    }

    /// Solves with the last factorization, in place.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        match self {
            LinearSolver::Banded(lu) => lu.solve_in_place(b),
            LinearSolver::Sparse(s) => s.solve_in_place(b),
            LinearSolver::Bordered(s) => s.solve_in_place(b),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both backends solve the same (non-banded, arrow-shaped) system.
    #[test]
    fn backends_agree() {
        let n = 30;
        let mut entries = vec![];
        for i in 0..n {
            if i + 1 < n {
                entries.push((i, i + 1));
                entries.push((i + 1, i));
            }
            entries.push((i, n - 1));
            entries.push((n - 1, i));
        }
        let p = CscPattern::from_entries(n, entries);
        let mut vals = vec![0.0; p.nnz()];
        for c in 0..n {
            for k in p.col_ptr()[c]..p.col_ptr()[c + 1] {
                let r = p.row_idx()[k];
                vals[k] = if r == c {
                    4.0 + c as f64
                } else {
                    -1.0 / (1.0 + (r + c) as f64)
                };
            }
        }
        let rhs: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut sols = vec![];
        for kind in [SolverKind::Banded, SolverKind::SparseLu] {
            let mut s = LinearSolver::new(&p, kind).unwrap();
            s.factor(&p, &vals).unwrap();
            let mut x = rhs.clone();
            s.solve_in_place(&mut x);
            let mut y = vec![0.0; n];
            p.mul_vec(&vals, &x, &mut y);
            for i in 0..n {
                assert!((y[i] - rhs[i]).abs() < 1e-12, "{kind:?} residual at {i}");
            }
            sols.push(x);
        }
        for i in 0..n {
            assert!((sols[0][i] - sols[1][i]).abs() < 1e-12);
        }
    }
}
