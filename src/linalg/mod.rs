//! Sparse storage and factorizations of the global iteration matrix.
//!
//! The pattern is fixed per mesh ([`csc::CscPattern`]); assembly writes into preallocated values;
//! [`LinearSolver`] factorizes with a banded LU (chains of elements), a bordered banded LU
//! (closed loops with a few dense couplings) or faer's sparse LU (general patterns), analysing
//! the structure once.

pub mod banded;
pub mod bordered;
pub mod csc;
pub mod solver;
pub mod sparse_lu;

pub use csc::CscPattern;
pub use solver::{Backend, LinearSolver, SolverKind, rank_one_len};

/// A failed factorization.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FactorError {
    /// A zero or negligible pivot: the matrix is singular (a mechanism or zero-energy mode).
    #[error(
        "singular iteration matrix (pivot {pivot:.3e} at equation {index}): the structure is a mechanism or has a zero-energy mode"
    )]
    Singular {
        /// Equation at which the pivot vanished.
        index: usize,
        /// The pivot value.
        pivot: f64,
    },
    /// Non-finite entries (NaN or infinity) in the matrix.
    #[error("non-finite entry in the iteration matrix")]
    NonFinite,
    /// The sparse factorization backend reported an error.
    #[error("sparse LU failed: {0}")]
    Backend(String),
}
