//! Global assembly: which coordinates are free, the sparsity pattern of the free–free iteration
//! matrix, and precomputed scatter positions so that assembly never searches or allocates.

mod dofs;
mod scatter;

pub use dofs::DofMap;
pub use scatter::Assembly;
