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
pub enum Backend {
    /// Banded LU.
    Banded(BandedLu),
    /// Sparse LU.
    Sparse(Box<SparseLu>),
    /// Banded LU of a reordered core with a dense border (Schur complement).
    Bordered(Box<BorderedBanded>),
}

/// Length of the values of an iteration matrix `J = S + c g gᵀ` with a rank-one part over
/// the pattern `pattern`: the `nnz` values of the sparse part `S`, then `c`, then `g` (`n`
/// entries). A model whose matrix has such a part (the pressure of an enclosed gas:
/// `c g gᵀ = −(dp/dV) ∇V ∇Vᵀ`, dense over every coordinate of the bag) writes it in this
/// layout ([`crate::model::MechanicalSystem::rank_one`]).
pub fn rank_one_len(pattern: &CscPattern) -> usize {
    pattern.nnz() + 1 + pattern.n()
}

/// The rank-one part of the last factorized matrix and `y = S⁻¹ g`.
#[derive(Debug, Default)]
struct RankOne {
    active: bool,
    c: f64,
    g: Vec<f64>,
    y: Vec<f64>,
    /// `1 + c gᵀ y`.
    denom: f64,
}

/// A factorization bound to one pattern: the backend for the sparse part and, when the values
/// carry one ([`rank_one_len`]), the rank-one part by the Sherman–Morrison formula
/// `(S + c g gᵀ)⁻¹ b = x − y (c gᵀ x)/(1 + c gᵀ y)` with `x = S⁻¹ b`, `y = S⁻¹ g`: the
/// bordered system `[S g; gᵀ −1/c]` eliminated, at the cost of one extra solve per
/// factorization and two dot products per solve, without the dense fill.
#[derive(Debug)]
pub struct LinearSolver {
    backend: Backend,
    /// Size of the system.
    n: usize,
    rank_one: RankOne,
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
        let backend = if banded {
            Backend::Banded(BandedLu::new(n, kl, ku))
        } else if kind == SolverKind::Auto
            && let Some(b) = BorderedBanded::analyse(pattern)
        {
            Backend::Bordered(Box::new(b))
        } else {
            Backend::Sparse(Box::new(SparseLu::new(pattern)?))
        };
        Ok(Self {
            backend,
            n,
            rank_one: RankOne::default(),
        })
    }

    /// The backend of the sparse part.
    pub fn backend(&self) -> &Backend {
        &self.backend
    }

    /// Numeric factorization of the values `vals`: the `nnz` values of `pattern`, optionally
    /// followed by a rank-one part `c, g` ([`rank_one_len`]).
    pub fn factor(&mut self, pattern: &CscPattern, vals: &[f64]) -> Result<(), FactorError> {
        let nnz = pattern.nnz();
        match &mut self.backend {
            Backend::Banded(b) => b.factor(pattern, &vals[..nnz])?,
            Backend::Sparse(s) => s.factor(pattern, &vals[..nnz])?,
            Backend::Bordered(b) => b.factor(&vals[..nnz])?,
        }
        let r = &mut self.rank_one;
        r.active = vals.len() == rank_one_len(pattern) && vals[nnz] != 0.0;
        if r.active {
            r.c = vals[nnz];
            r.g.clear();
            r.g.extend_from_slice(&vals[nnz + 1..]);
            r.y.clear();
            r.y.extend_from_slice(&vals[nnz + 1..]);
            match &mut self.backend {
                Backend::Banded(lu) => lu.solve_in_place(&mut r.y),
                Backend::Sparse(s) => s.solve_in_place(&mut r.y),
                Backend::Bordered(s) => s.solve_in_place(&mut r.y),
            }
            r.denom = 1.0 + r.c * dot(&r.g, &r.y);
            if !(r.denom.is_finite() && r.denom.abs() > 1e-14) {
                r.active = false;
                return Err(FactorError::Singular {
                    index: pattern.n(),
                    pivot: r.denom,
                });
            }
        }
        Ok(())
    }

    /// Solves with the last factorization, in place.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        match &mut self.backend {
            Backend::Banded(lu) => lu.solve_in_place(b),
            Backend::Sparse(s) => s.solve_in_place(b),
            Backend::Bordered(s) => s.solve_in_place(b),
        }
        let r = &self.rank_one;
        if r.active {
            let f = r.c * dot(&r.g, b) / r.denom;
            for (bi, yi) in b.iter_mut().zip(&r.y) {
                *bi -= f * yi;
            }
        }
    }
}

impl LinearSolver {
    /// Solves `A X = B` in place for the right-hand sides stored one after the other in `b`
    /// (column-major `n × k`, `b.len() = k n`), each column as [`Self::solve_in_place`] solves
    /// it; the banded backend passes over its factors once for all of them (the solve of a
    /// wide band is bound by reading the factors).
    pub fn solve_many_in_place(&mut self, b: &mut [f64]) {
        let n = self.n;
        if n == 0 {
            return;
        }
        debug_assert!(b.len().is_multiple_of(n));
        match &mut self.backend {
            Backend::Banded(lu) => lu.solve_many_in_place(b),
            Backend::Sparse(s) => b.chunks_exact_mut(n).for_each(|x| s.solve_in_place(x)),
            Backend::Bordered(s) => b.chunks_exact_mut(n).for_each(|x| s.solve_in_place(x)),
        }
        let r = &self.rank_one;
        if r.active {
            for x in b.chunks_exact_mut(n) {
                let f = r.c * dot(&r.g, x) / r.denom;
                for (bi, yi) in x.iter_mut().zip(&r.y) {
                    *bi -= f * yi;
                }
            }
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rank-one part `c g gᵀ` in the values is solved exactly (Sherman–Morrison) on every
    /// backend: the product with the full matrix gives back the right-hand side.
    #[test]
    fn rank_one_part_is_solved_exactly() {
        let n: usize = 40;
        let mut entries = vec![];
        for i in 0..n {
            for j in i.saturating_sub(2)..(i + 3).min(n) {
                entries.push((i, j));
            }
        }
        let p = CscPattern::from_entries(n, entries);
        let mut vals = vec![0.0; rank_one_len(&p)];
        for c in 0..n {
            for k in p.col_ptr()[c]..p.col_ptr()[c + 1] {
                let r = p.row_idx()[k];
                vals[k] = if r == c {
                    5.0
                } else {
                    -1.0 / (1.0 + (r + 2 * c) as f64)
                };
            }
        }
        let cc = 0.37;
        vals[p.nnz()] = cc;
        let g: Vec<f64> = (0..n).map(|i| (0.3 * i as f64).cos()).collect();
        vals[p.nnz() + 1..].copy_from_slice(&g);
        let rhs: Vec<f64> = (0..n).map(|i| (i as f64).sin() + 0.5).collect();
        for kind in [SolverKind::Banded, SolverKind::SparseLu, SolverKind::Auto] {
            let mut s = LinearSolver::new(&p, kind).unwrap();
            s.factor(&p, &vals).unwrap();
            let mut x = rhs.clone();
            s.solve_in_place(&mut x);
            let mut y = vec![0.0; n];
            p.mul_vec(&vals[..p.nnz()], &x, &mut y);
            let gx = dot(&g, &x);
            for i in 0..n {
                y[i] += cc * g[i] * gx;
                assert!((y[i] - rhs[i]).abs() < 1e-12, "{kind:?} residual at {i}");
            }
            // several right-hand sides at once: the same solutions
            let rhs2: Vec<f64> = (0..n).map(|i| (0.7 * i as f64).cos() - 0.2).collect();
            let mut many = [rhs.clone(), rhs2.clone()].concat();
            s.solve_many_in_place(&mut many);
            let mut x2 = rhs2;
            s.solve_in_place(&mut x2);
            for i in 0..n {
                assert!(
                    (many[i] - x[i]).abs() < 1e-14,
                    "{kind:?} many, column 0 at {i}"
                );
                assert!(
                    (many[n + i] - x2[i]).abs() < 1e-14,
                    "{kind:?} many, column 1 at {i}"
                );
            }
            // without the tail the rank-one part is off
            s.factor(&p, &vals[..p.nnz()]).unwrap();
            let mut z = rhs.clone();
            s.solve_in_place(&mut z);
            assert!((z[0] - x[0]).abs() > 1e-6);
        }
    }

    /// Several right-hand sides with a rank-one part on the bordered backend (a ring with a
    /// dense last row and column, which `Auto` gives to it): each column is the single solve's,
    /// and the product with the full matrix gives it back.
    #[test]
    fn solve_many_on_the_bordered_backend() {
        let n: usize = 80;
        let mut entries = vec![];
        for i in 0..n {
            entries.push((i, i));
            entries.push((i, (i + 1) % n));
            entries.push(((i + 1) % n, i));
            entries.push((i, n - 1));
            entries.push((n - 1, i));
        }
        let p = CscPattern::from_entries(n, entries);
        let mut vals = vec![0.0; rank_one_len(&p)];
        for c in 0..n {
            for k in p.col_ptr()[c]..p.col_ptr()[c + 1] {
                let r = p.row_idx()[k];
                vals[k] = if r == c {
                    6.0
                } else {
                    -0.3 / (1.0 + ((r + 3 * c) % 7) as f64)
                };
            }
        }
        let cc = -0.21;
        vals[p.nnz()] = cc;
        let g: Vec<f64> = (0..n).map(|i| (0.2 * i as f64).sin() + 0.1).collect();
        vals[p.nnz() + 1..].copy_from_slice(&g);
        let mut s = LinearSolver::new(&p, SolverKind::Auto).unwrap();
        assert!(matches!(s.backend(), Backend::Bordered(_)));
        s.factor(&p, &vals).unwrap();
        let cols: Vec<Vec<f64>> = (0..3)
            .map(|j| {
                (0..n)
                    .map(|i| ((j + 1) as f64 * 0.37 * i as f64).cos())
                    .collect()
            })
            .collect();
        let mut many = cols.concat();
        s.solve_many_in_place(&mut many);
        for (j, rhs) in cols.iter().enumerate() {
            let mut x = rhs.clone();
            s.solve_in_place(&mut x);
            let col = &many[j * n..(j + 1) * n];
            let mut y = vec![0.0; n];
            p.mul_vec(&vals[..p.nnz()], col, &mut y);
            let gx = dot(&g, col);
            for i in 0..n {
                assert!((col[i] - x[i]).abs() < 1e-14, "column {j} at {i}");
                y[i] += cc * g[i] * gx;
                assert!((y[i] - rhs[i]).abs() < 1e-12, "column {j}: residual at {i}");
            }
        }
    }

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
