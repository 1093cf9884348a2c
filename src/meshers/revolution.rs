//! Surfaces of revolution about the global z axis from a meridian of straight and circular
//! pieces in the r-z plane, cut into rings of isosceles trapezoids (the element shape of the
//! seed-004 shell, Pogorelov & Rodikov 2021): `n_circumferential` elements around each closed
//! ring, `n_meridional` rings along the meridian. Bellows of air springs, tyres, cylinders.

use super::centreline::{LineMesh, Piece, mesh_centreline};
use nalgebra::{Vector2, Vector3};
use std::f64::consts::PI;

/// One piece of a meridian in the r-z plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MeridianPiece {
    /// A straight piece.
    Line {
        /// Start direction `(dr, dz)` (`None`: the end direction of the previous piece).
        direction: Option<Vector2<f64>>,
        /// Length [m].
        length: f64,
    },
    /// A circular arc; positive angles turn the direction counter-clockwise in the r-z plane
    /// (from +r towards +z).
    Arc {
        /// Start direction `(dr, dz)` (`None`: the end direction of the previous piece).
        direction: Option<Vector2<f64>>,
        /// Radius [m].
        radius: f64,
        /// Signed angle [rad].
        angle: f64,
    },
}

/// The geometry of one isosceles trapezoid: parallel sides on the two rings and the distance
/// between them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trapezoid {
    /// Side on the lower ring (first two nodes) [m].
    pub a: f64,
    /// Side on the upper ring (last two nodes) [m].
    pub b: f64,
    /// Height: distance between the midpoints of the two sides [m].
    pub h: f64,
}

/// A meshed surface of revolution.
#[derive(Clone, Debug)]
pub struct RevolutionMesh {
    /// Elements around a ring.
    pub n_circumferential: usize,
    /// Node positions [m], ring by ring: node `i` of ring `j` is `j * n_circumferential + i`, at
    /// the angle `2 pi i / n_circumferential` from the x axis.
    pub nodes: Vec<Vector3<f64>>,
    /// Elements, ring by ring, each `[lower i, lower i+1, upper i+1, upper i]` (the ring closed:
    /// `i+1` wraps to 0); counter-clockwise seen from the side the meridian's left normal
    /// points to.
    pub elements: Vec<[usize; 4]>,
    /// The meridian's nodes as `(r, 0, z)` and their arc lengths.
    pub meridian: LineMesh,
}

impl RevolutionMesh {
    /// Cuts the surface swept by the meridian from `(r0, z0)` into `n_meridional` rings of
    /// `n_circumferential` trapezoids. `key` names the scene table of the meridian in messages.
    pub fn new(
        start: Vector2<f64>,
        pieces: &[MeridianPiece],
        n_circumferential: usize,
        n_meridional: usize,
        key: &str,
    ) -> Result<Self, String> {
        if n_circumferential < 3 {
            return Err(format!(
                "mesh.n_circumferential = {n_circumferential}: a ring needs at least 3 elements"
            ));
        }
        let lift = |d: Option<Vector2<f64>>| d.map(|d| Vector3::new(d.x, 0.0, d.y));
        // The r-z plane is the x-z plane; turning from +x towards +z is about -y.
        let pieces3: Vec<Piece> = pieces
            .iter()
            .map(|p| match *p {
                MeridianPiece::Line { direction, length } => Piece::Line {
                    direction: lift(direction),
                    length,
                },
                MeridianPiece::Arc {
                    direction,
                    radius,
                    angle,
                } => Piece::Arc {
                    direction: lift(direction),
                    radius,
                    angle: angle.abs(),
                    bend_axis: -Vector3::y() * angle.signum(),
                },
            })
            .collect();
        let meridian = mesh_centreline(
            Vector3::new(start.x, 0.0, start.y),
            &pieces3,
            n_meridional,
            "mesh.n_meridional",
            key,
        )?;
        if let Some((j, p)) = meridian.x.iter().enumerate().find(|(_, p)| p.x <= 0.0) {
            return Err(format!(
                "{key}: the meridian reaches the axis (r = {:.3e} m at node {j}); a closed pole cannot be cut into trapezoids",
                p.x
            ));
        }
        let n = n_circumferential;
        let mut nodes = Vec::with_capacity(meridian.x.len() * n);
        for p in &meridian.x {
            for i in 0..n {
                let phi = 2.0 * PI * i as f64 / n as f64;
                nodes.push(Vector3::new(p.x * phi.cos(), p.x * phi.sin(), p.z));
            }
        }
        let mut elements = Vec::with_capacity(n_meridional * n);
        for j in 0..n_meridional {
            for i in 0..n {
                let i1 = (i + 1) % n;
                elements.push([j * n + i, j * n + i1, (j + 1) * n + i1, (j + 1) * n + i]);
            }
        }
        Ok(Self {
            n_circumferential,
            nodes,
            elements,
            meridian,
        })
    }

    /// The trapezoid of element `e`.
    pub fn trapezoid(&self, e: usize) -> Trapezoid {
        let [n0, n1, n2, n3] = self.elements[e];
        let x = &self.nodes;
        Trapezoid {
            a: (x[n1] - x[n0]).norm(),
            b: (x[n2] - x[n3]).norm(),
            h: (0.5 * (x[n2] + x[n3]) - 0.5 * (x[n0] + x[n1])).norm(),
        }
    }

    /// Area of the meshed (faceted) surface [m2].
    pub fn area(&self) -> f64 {
        (0..self.elements.len())
            .map(|e| {
                let t = self.trapezoid(e);
                0.5 * (t.a + t.b) * t.h
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cylinder(n_c: usize, n_m: usize) -> RevolutionMesh {
        let wall = [MeridianPiece::Line {
            direction: Some(Vector2::new(0.0, 1.0)),
            length: 0.3,
        }];
        RevolutionMesh::new(Vector2::new(0.1, 0.0), &wall, n_c, n_m, "meridian").unwrap()
    }

    /// A cylinder: rectangles (trapezoids with equal sides), the polygon's area exactly.
    #[test]
    fn cylinder_is_cut_into_rectangles() {
        let m = cylinder(12, 5);
        assert_eq!(m.nodes.len(), 6 * 12);
        assert_eq!(m.elements.len(), 5 * 12);
        let chord = 2.0 * 0.1 * (PI / 12.0).sin();
        for e in 0..m.elements.len() {
            let t = m.trapezoid(e);
            assert!((t.a - chord).abs() < 1e-14 && (t.b - chord).abs() < 1e-14);
            assert!((t.h - 0.06).abs() < 1e-14);
        }
        assert!((m.area() - 12.0 * chord * 0.3).abs() < 1e-12);
    }

    /// The ring is closed: the last element of a ring shares its side with the first, and every
    /// interior node belongs to four elements.
    #[test]
    fn rings_are_closed() {
        let m = cylinder(8, 3);
        assert_eq!(m.elements[7], [7, 0, 8, 15]);
        let mut count = vec![0; m.nodes.len()];
        for el in &m.elements {
            for &k in el {
                count[k] += 1;
            }
        }
        for (k, c) in count.iter().enumerate() {
            let ring = k / 8;
            assert_eq!(*c, if ring == 0 || ring == 3 { 2 } else { 4 }, "node {k}");
        }
    }

    /// A half torus (meridian: half circle of radius 0.05 around r = 0.15) converges to the
    /// area 2 pi R pi a at second order in the element size.
    #[test]
    fn torus_area_converges() {
        let exact = 2.0 * PI * 0.15 * PI * 0.05;
        let err = |n: usize| {
            let arc = [MeridianPiece::Arc {
                direction: Some(Vector2::new(0.0, 1.0)),
                radius: 0.05,
                angle: PI,
            }];
            let m = RevolutionMesh::new(Vector2::new(0.2, 0.0), &arc, 4 * n, n, "m").unwrap();
            let top = m.meridian.x[n];
            assert!((top - Vector3::new(0.1, 0.0, 0.0)).norm() < 1e-12, "{top}");
            (m.area() - exact).abs() / exact
        };
        let (e1, e2) = (err(8), err(16));
        assert!(e1 < 0.02, "{e1}");
        assert!((e1 / e2 - 4.0).abs() < 0.3, "order: {e1} / {e2}");
    }

    #[test]
    fn the_axis_and_too_few_elements_are_rejected() {
        let through = [MeridianPiece::Line {
            direction: Some(Vector2::new(-1.0, 0.0)),
            length: 0.2,
        }];
        let err =
            RevolutionMesh::new(Vector2::new(0.1, 0.0), &through, 8, 4, "meridian").unwrap_err();
        assert!(err.contains("meridian") && err.contains("axis"), "{err}");
        let wall = [MeridianPiece::Line {
            direction: Some(Vector2::new(0.0, 1.0)),
            length: 0.3,
        }];
        let err = RevolutionMesh::new(Vector2::new(0.1, 0.0), &wall, 2, 4, "m").unwrap_err();
        assert!(err.contains("mesh.n_circumferential"), "{err}");
    }
}
