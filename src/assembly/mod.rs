//! Global assembly: which coordinates are free, the sparsity pattern of the free–free iteration
//! matrix, and element sets with precomputed scatter positions so that assembly never searches
//! or allocates.

mod dofs;
mod element_set;
mod scatter;

pub use dofs::DofMap;
pub use element_set::{Connectivity, ElementSet, Eval, check_finite};
pub use scatter::Assembly;
