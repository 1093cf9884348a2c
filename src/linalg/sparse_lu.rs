//! faer's sparse LU (COLAMD ordering, simplicial or supernodal), analysed once per pattern and
//! refactorized numerically with reused buffers, sequentially (one core per FMU instance).

use super::FactorError;
use super::csc::CscPattern;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par};

/// A sparse LU factorization for one fixed pattern.
pub struct SparseLu {
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    factor_mem: MemBuffer,
    solve_mem: MemBuffer,
    factored: bool,
}

impl std::fmt::Debug for SparseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLu")
            .field("factored", &self.factored)
            .finish()
    }
}

fn view(pattern: &CscPattern) -> SymbolicSparseColMatRef<'_, usize> {
    SymbolicSparseColMatRef::new_checked(
        pattern.n(),
        pattern.n(),
        pattern.col_ptr(),
        None,
        pattern.row_idx(),
    )
}

impl SparseLu {
    /// Symbolic analysis (fill-reducing ordering, elimination tree) of `pattern`.
    pub fn new(pattern: &CscPattern) -> Result<Self, FactorError> {
        let symbolic = factorize_symbolic_lu(view(pattern), Default::default())
            .map_err(|e| FactorError::Backend(format!("{e:?}")))?;
        let factor_mem = MemBuffer::new(
            symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
        );
        let solve_mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        Ok(Self {
            symbolic,
            numeric: NumericLu::new(),
            factor_mem,
            solve_mem,
            factored: false,
        })
    }

    /// Numeric factorization of the values `vals` laid out in `pattern`.
    pub fn factor(&mut self, pattern: &CscPattern, vals: &[f64]) -> Result<(), FactorError> {
        self.factored = false;
        if vals.iter().any(|v| !v.is_finite()) {
            return Err(FactorError::NonFinite);
        }
        let mat = SparseColMatRef::new(view(pattern), vals);
        let stack = MemStack::new(&mut self.factor_mem);
        self.symbolic
            .factorize_numeric_lu(&mut self.numeric, mat, Par::Seq, stack, Default::default())
            .map_err(|e| match e {
                faer::sparse::linalg::LuError::SymbolicSingular { index } => {
                    FactorError::Singular { index, pivot: 0.0 }
                }
                other => FactorError::Backend(format!("{other:?}")),
            })?;
        self.factored = true;
        Ok(())
    }

    /// Solves `A x = b` in place.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        debug_assert!(self.factored);
        let n = b.len();
        let rhs = MatMut::from_column_major_slice_mut(b, n, 1);
        let lu = faer::sparse::linalg::lu::LuRef::new_unchecked(&self.symbolic, &self.numeric);
        lu.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(&mut self.solve_mem));
    }
}
