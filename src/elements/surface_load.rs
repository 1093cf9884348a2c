//! SKELETON: follower pressure on a bilinear quadrilateral surface patch and its enclosed-volume
//! contribution. API for the shell kind; kernels follow.
#![allow(missing_docs, unused_variables)]
use nalgebra::{SMatrix, SVector, Vector3};

/// Pressure force on the 4 corner positions `[f1, f2, f3, f4]` (12) of a bilinear patch for
/// the pressure `p` [Pa] acting along `+n = x_ξ × x_η` (the side the counter-clockwise normal
/// points to), `f_i = p ∫ N_i (x_ξ × x_η) dξ dη`, and its tangent `∂f/∂x` (12 × 12).
pub fn pressure_into(
    x: &[Vector3<f64>; 4],
    p: f64,
    f: &mut SVector<f64, 12>,
    k: Option<&mut SMatrix<f64, 12, 12>>,
) {
    todo!()
}

/// The patch's part `(1/3) ∫ x · (x_ξ × x_η) dξ dη` [m3] of the volume enclosed by a closed
/// surface whose normals point outwards; exact for the bilinear patch.
pub fn volume_part(x: &[Vector3<f64>; 4]) -> f64 {
    todo!()
}
