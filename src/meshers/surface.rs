//! Quantities of a surface mesh of four-node patches (node positions plus elements of four node
//! indices, corners counter-clockwise seen from the side the normal points to): the volume it
//! encloses and its area. Used by the shell of revolution and the shell kind.

use crate::elements::surface_load::volume_part;
use nalgebra::Vector3;

/// Volume [m3] enclosed by a closed surface whose elements run counter-clockwise seen from
/// outside: the sum of [`volume_part`] (bilinear patches, exact; independent of the origin for
/// a closed surface). Negative when the elements run clockwise seen from outside; for an open
/// surface it is the volume of the cone from the origin to the surface.
pub fn enclosed_volume(nodes: &[Vector3<f64>], elements: &[[usize; 4]]) -> f64 {
    elements
        .iter()
        .map(|el| volume_part(&el.map(|k| nodes[k])))
        .sum()
}

/// Area [m2] of the bilinear patch on four corners `½ |(x3 − x1) × (x4 − x2)|`; exact for a
/// planar quadrilateral.
pub fn quad_area(x: &[Vector3<f64>; 4]) -> f64 {
    0.5 * (x[2] - x[0]).cross(&(x[3] - x[1])).norm()
}

/// Area [m2] of a mesh of planar quadrilaterals ([`quad_area`] summed).
pub fn surface_area(nodes: &[Vector3<f64>], elements: &[[usize; 4]]) -> f64 {
    elements
        .iter()
        .map(|el| quad_area(&el.map(|k| nodes[k])))
        .sum()
}
