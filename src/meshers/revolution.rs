//! Surfaces of revolution about the global z axis from a meridian of straight and circular
//! pieces in the r-z plane, cut into rings of isosceles trapezoids (the element shape of the
//! seed-004 shell, Pogorelov & Rodikov 2021): `n_circumferential` elements around each closed
//! ring, `n_meridional` rings along the meridian. Bellows of air springs, tyres, cylinders.
//!
//! A meridian may start or end exactly on the axis (a *pole*: the flat end cap of a closed
//! cylinder, the apex of a dome). The disc inside the circle next to the pole is closed by an
//! O-grid of convex planar quadrilaterals: a central `m × m` grid in the plane of the pole
//! (`m = n_circumferential / 4`), and one ring of quadrilaterals from its boundary to the
//! circle: a rounded square for a flat cap, the regular polygon (isosceles trapezoids in the
//! ring) when the circle lies outside the plane of the pole.

use super::centreline::{LineMesh, Piece, mesh_centreline};
use super::surface::{enclosed_volume, surface_area};
use nalgebra::{Vector2, Vector3};
use std::f64::consts::PI;
use std::ops::Range;

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

/// An end of the meridian.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeridianEnd {
    /// Its first node (station 0).
    Start,
    /// Its last node (station `n_meridional`).
    End,
}

/// A pole: a meridian end on the axis, closed by a patch of quadrilaterals: a flat central grid
/// in the plane `z = z_pole` and a transition ring to the circle of the neighbouring station.
#[derive(Clone, Debug, PartialEq)]
pub struct Pole {
    /// The meridian station on the axis (0 or `n_meridional`).
    pub station: usize,
    /// The patch's nodes, `(m + 1)²` of them (`m = n_circumferential / 4`): node `(a, b)` of
    /// the central grid is `nodes.start + b (m + 1) + a` (`a` and `b` counter-clockwise about +z,
    /// `a` near +x).
    pub nodes: Range<usize>,
    /// The one node on the axis, `(0, 0, z_pole)`: the centre of the grid when `m` is even;
    /// `None` when `m` is odd (the axis then passes through the central element).
    pub axis_node: Option<usize>,
    /// The patch's elements: `m²` of the central grid and `n_circumferential` of the
    /// transition ring.
    pub elements: Range<usize>,
}

/// A meshed surface of revolution.
#[derive(Clone, Debug)]
pub struct RevolutionMesh {
    /// Elements around a ring.
    pub n_circumferential: usize,
    /// Node positions [m]: the patch of a pole at the start (see [`Pole`]), then the rings of
    /// the stations off the axis, then the patch of a pole at the end. Node `i` of a ring is
    /// at the angle `2 pi i / n_circumferential` from the x axis; without poles node `i` of
    /// ring `j` is `j * n_circumferential + i` ([`RevolutionMesh::ring_nodes`] in general).
    pub nodes: Vec<Vector3<f64>>,
    /// Elements in the order of the nodes; a ring between stations `j` and `j + 1` off the
    /// axis is `[lower i, lower i+1, upper i+1, upper i]` (the ring closed: `i+1` wraps to 0).
    /// All elements, pole patches included, run counter-clockwise about the normal
    /// `dz e_r − dr e_z` of the meridian direction `(dr, dz)` (see [`RevolutionMesh::new`]),
    /// so the normals of a closed surface all point outwards or all inwards.
    pub elements: Vec<[usize; 4]>,
    /// The meridian's nodes as `(r, 0, z)` and their arc lengths (`r` exactly 0 at a pole).
    pub meridian: LineMesh,
    /// The first node of the ring of every station (`None` at a pole).
    ring_first: Vec<Option<usize>>,
    /// The poles at the start and at the end.
    poles: [Option<Pole>; 2],
}

impl RevolutionMesh {
    /// Cuts the surface swept by the meridian from `start = (r0, z0)` into `n_meridional`
    /// rings of `n_circumferential` trapezoids. `key` names the scene table of the meridian in
    /// messages.
    ///
    /// Orientation: for the meridian direction `(dr, dz)` the elements run counter-clockwise
    /// about the normal `dz e_r − dr e_z` (the right-hand normal in the r-z plane drawn with r
    /// to the right and z up). A meridian that runs counter-clockwise around the region between
    /// it and the axis in that drawing (e.g. a closed cylinder: out along the bottom, up the wall, in
    /// along the top) gives outward normals and a positive [`RevolutionMesh::volume`].
    ///
    /// Only the first and the last node may lie on the axis (`|r| ≤ 1e-9` of the meridian's
    /// length; snapped to 0): such an end is a [`Pole`], closed by a patch flat in its plane,
    /// and needs `n_circumferential` to be a multiple of 4. The meridian must not reach the
    /// axis anywhere else nor cross it.
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
        let mut meridian = mesh_centreline(
            Vector3::new(start.x, 0.0, start.y),
            &pieces3,
            n_meridional,
            "mesh.n_meridional",
            key,
        )?;
        let n = n_circumferential;
        let last = meridian.x.len() - 1;
        let tol = 1e-9 * meridian.stations.length();
        let mut on_axis = [false; 2];
        for (j, p) in meridian.x.iter_mut().enumerate() {
            let end = if j == 0 {
                Some(0)
            } else if j == last {
                Some(1)
            } else {
                None
            };
            match end {
                Some(e) if p.x.abs() <= tol => {
                    p.x = 0.0;
                    on_axis[e] = true;
                }
                _ if p.x <= tol => {
                    return Err(format!(
                        "{key}: the meridian reaches or crosses the axis (r = {:.3e} m at node {j} of {}); only its first and last node may lie on the axis (a pole)",
                        p.x,
                        last + 1
                    ));
                }
                _ => {}
            }
        }
        if on_axis[0] && on_axis[1] && last < 2 {
            return Err(format!(
                "{key}: both ends lie on the axis and mesh.n_meridional = {n_meridional}; closing two poles needs at least one ring off the axis (mesh.n_meridional >= 2)"
            ));
        }
        if (on_axis[0] || on_axis[1]) && !n.is_multiple_of(4) {
            let which = if on_axis[0] { "starts" } else { "ends" };
            return Err(format!(
                "mesh.n_circumferential = {n}: the meridian {key} {which} on the axis, and the pole is closed by an m x m grid with 4 m = n_circumferential, so n_circumferential must be a multiple of 4"
            ));
        }
        let m = n / 4;
        let patch_nodes = (m + 1) * (m + 1);
        let patch_elements = m * m + n;
        let n_rings = meridian.x.len() - on_axis.iter().filter(|&&a| a).count();
        let mut nodes = Vec::with_capacity(n_rings * n + 2 * patch_nodes);
        let mut elements = Vec::with_capacity((n_rings - 1) * n + 2 * patch_elements);
        let mut poles = [None, None];
        // start pole: nodes first; its elements need the first ring, added below
        let start_patch = if on_axis[0] {
            let base = nodes.len();
            let (r1, z_pole) = (meridian.x[1].x, meridian.x[0].z);
            let flat = (meridian.x[1].z - z_pole).abs() <= tol;
            pole_patch_nodes(m, r1, z_pole, flat, &mut nodes);
            Some(base)
        } else {
            None
        };
        let mut ring_first = vec![None; meridian.x.len()];
        for (j, p) in meridian.x.iter().enumerate() {
            if (j == 0 && on_axis[0]) || (j == last && on_axis[1]) {
                continue;
            }
            ring_first[j] = Some(nodes.len());
            for i in 0..n {
                let phi = 2.0 * PI * i as f64 / n as f64;
                nodes.push(Vector3::new(p.x * phi.cos(), p.x * phi.sin(), p.z));
            }
        }
        if let Some(base) = start_patch {
            let e0 = elements.len();
            let ring = ring_first[1].expect("the station next to a pole is a ring");
            pole_patch_elements(m, base, ring, MeridianEnd::Start, &mut elements);
            poles[0] = Some(Pole {
                station: 0,
                nodes: base..base + patch_nodes,
                axis_node: m
                    .is_multiple_of(2)
                    .then_some(base + (m / 2) * (m + 1) + m / 2),
                elements: e0..elements.len(),
            });
        }
        for j in 0..last {
            if let (Some(lo), Some(up)) = (ring_first[j], ring_first[j + 1]) {
                for i in 0..n {
                    let i1 = (i + 1) % n;
                    elements.push([lo + i, lo + i1, up + i1, up + i]);
                }
            }
        }
        if on_axis[1] {
            let base = nodes.len();
            let (r1, z_pole) = (meridian.x[last - 1].x, meridian.x[last].z);
            let flat = (meridian.x[last - 1].z - z_pole).abs() <= tol;
            pole_patch_nodes(m, r1, z_pole, flat, &mut nodes);
            let e0 = elements.len();
            let ring = ring_first[last - 1].expect("the station next to a pole is a ring");
            pole_patch_elements(m, base, ring, MeridianEnd::End, &mut elements);
            poles[1] = Some(Pole {
                station: last,
                nodes: base..base + patch_nodes,
                axis_node: m
                    .is_multiple_of(2)
                    .then_some(base + (m / 2) * (m + 1) + m / 2),
                elements: e0..elements.len(),
            });
        }
        Ok(Self {
            n_circumferential,
            nodes,
            elements,
            meridian,
            ring_first,
            poles,
        })
    }

    /// The trapezoid of element `e` (for an element of a pole patch: its first and third
    /// sides and the distance between their midpoints).
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
        surface_area(&self.nodes, &self.elements)
    }

    /// Volume enclosed by the meshed surface [m3] ([`enclosed_volume`]): positive for a closed
    /// surface with outward normals (see [`RevolutionMesh::new`]).
    pub fn volume(&self) -> f64 {
        enclosed_volume(&self.nodes, &self.elements)
    }

    /// Number of meridian stations (`n_meridional + 1`).
    pub fn n_stations(&self) -> usize {
        self.ring_first.len()
    }

    /// The `n_circumferential` nodes of the ring at meridian station `j` (node `i` at the
    /// angle `2 pi i / n_circumferential`); `None` at a pole (see [`RevolutionMesh::pole`]).
    ///
    /// # Panics
    /// Panics if `j > n_meridional`.
    pub fn ring_nodes(&self, j: usize) -> Option<Range<usize>> {
        self.ring_first[j].map(|f| f..f + self.n_circumferential)
    }

    /// The meridian station whose arc length is nearest to `s` [m] (clamped to the meridian;
    /// see [`crate::meshers::stations::Stations::node_at`] for a fraction that must fall on a
    /// node).
    pub fn ring_at(&self, s: f64) -> usize {
        let arc = self.meridian.stations.arc_lengths();
        arc.iter()
            .enumerate()
            .min_by(|a, b| (a.1 - s).abs().total_cmp(&(b.1 - s).abs()))
            .map_or(0, |(j, _)| j)
    }

    /// The pole at an end of the meridian, if that end lies on the axis.
    pub fn pole(&self, end: MeridianEnd) -> Option<&Pole> {
        self.poles[match end {
            MeridianEnd::Start => 0,
            MeridianEnd::End => 1,
        }]
        .as_ref()
    }

    /// Whether the surface is closed: both ends of the meridian lie on the axis.
    pub fn is_closed(&self) -> bool {
        self.poles.iter().all(Option::is_some)
    }
}

/// Pushes the `(m + 1)²` nodes of the O-grid closing a pole in the plane `z` inside the circle
/// of radius `r1` [m] with `4 m` nodes. Boundary node `k` of the grid (counter-clockwise about
/// +z from the corner `(m, 0)`) faces circle node `i = (k − ⌊m/2⌋) mod 4m` at the angle `φ_i`;
/// it lies at `rho ((1 − λ) (cos φ_i, sin φ_i) + λ q_k)` with `rho = r1 m / (m + 1)` and `q_k`
/// the point of the square inscribed in the unit circle (corners at the angles of the circle
/// nodes `k = 0, m, 2m, 3m`, nodes evenly along its sides). `flat` (the circle lies in the
/// plane of the pole): `λ = 3/4`, a rounded square whose elements keep their angles within
/// about 67°–135° for any `m`; otherwise `λ = 0`, the regular polygon, whose sides are
/// parallel to the circle's chords so that the transition ring (a cone) is made of planar
/// isosceles trapezoids, at the price of corner angles `180° − 360° / (4m)`. Interior nodes by
/// transfinite (Coons) interpolation of the boundary; the centre exactly on the axis for even
/// `m`.
fn pole_patch_nodes(m: usize, r1: f64, z: f64, flat: bool, nodes: &mut Vec<Vector3<f64>>) {
    let n = 4 * m;
    let rho = r1 * m as f64 / (m as f64 + 1.0);
    let lambda = if flat { 0.75 } else { 0.0 };
    let base = nodes.len();
    nodes.resize(base + (m + 1) * (m + 1), Vector3::zeros());
    let id = |a: usize, b: usize| base + b * (m + 1) + a;
    // the square's corner (m, 0) at the angle of its circle node; unrotated it is at -45°
    let delta = -2.0 * PI * (m / 2) as f64 / n as f64 + 0.25 * PI;
    let (cd, sd) = (delta.cos(), delta.sin());
    for k in 0..n {
        let (a, b) = boundary_cell(m, k);
        let i = (k + n - m / 2) % n;
        let phi = 2.0 * PI * i as f64 / n as f64;
        let u = (2.0 * a as f64 / m as f64 - 1.0) * std::f64::consts::FRAC_1_SQRT_2;
        let v = (2.0 * b as f64 / m as f64 - 1.0) * std::f64::consts::FRAC_1_SQRT_2;
        let q = Vector2::new(cd * u - sd * v, sd * u + cd * v);
        let p = (Vector2::new(phi.cos(), phi.sin()) * (1.0 - lambda) + q * lambda) * rho;
        nodes[id(a, b)] = Vector3::new(p.x, p.y, z);
    }
    for b in 1..m {
        for a in 1..m {
            let (u, v) = (a as f64 / m as f64, b as f64 / m as f64);
            let p = nodes[id(0, b)] * (1.0 - u)
                + nodes[id(m, b)] * u
                + nodes[id(a, 0)] * (1.0 - v)
                + nodes[id(a, m)] * v
                - (nodes[id(0, 0)] * ((1.0 - u) * (1.0 - v))
                    + nodes[id(m, 0)] * (u * (1.0 - v))
                    + nodes[id(0, m)] * ((1.0 - u) * v)
                    + nodes[id(m, m)] * (u * v));
            nodes[id(a, b)] = Vector3::new(p.x, p.y, z);
        }
    }
    if m.is_multiple_of(2) {
        nodes[id(m / 2, m / 2)] = Vector3::new(0.0, 0.0, z);
    }
}

/// Grid position `(a, b)` of boundary node `k` of the `m × m` grid, counter-clockwise about +z
/// from the corner `(m, 0)`.
fn boundary_cell(m: usize, k: usize) -> (usize, usize) {
    match k / m {
        0 => (m, k),
        1 => (2 * m - k, m),
        2 => (0, 3 * m - k),
        _ => (k - 3 * m, 0),
    }
}

/// Pushes the elements of a pole patch whose nodes start at `base`, joined to the ring whose
/// nodes start at `ring`: at the start pole the central grid then the transition ring (the
/// meridian runs away from the pole, normals along −z), at the end pole the transition ring
/// then the grid (normals along +z); the same rule as the rings (see [`RevolutionMesh::new`]).
fn pole_patch_elements(
    m: usize,
    base: usize,
    ring: usize,
    end: MeridianEnd,
    elements: &mut Vec<[usize; 4]>,
) {
    let n = 4 * m;
    let id = |a: usize, b: usize| base + b * (m + 1) + a;
    // boundary node of the grid at the angle of circle node i
    let inner = |i: usize| {
        let (a, b) = boundary_cell(m, (i + m / 2) % n);
        id(a, b)
    };
    let grid = |elements: &mut Vec<[usize; 4]>| {
        for b in 0..m {
            for a in 0..m {
                elements.push(match end {
                    MeridianEnd::Start => [id(a, b), id(a, b + 1), id(a + 1, b + 1), id(a + 1, b)],
                    MeridianEnd::End => [id(a, b), id(a + 1, b), id(a + 1, b + 1), id(a, b + 1)],
                });
            }
        }
    };
    if end == MeridianEnd::Start {
        grid(elements);
    }
    for i in 0..n {
        let i1 = (i + 1) % n;
        elements.push(match end {
            MeridianEnd::Start => [inner(i), inner(i1), ring + i1, ring + i],
            MeridianEnd::End => [ring + i, ring + i1, inner(i1), inner(i)],
        });
    }
    if end == MeridianEnd::End {
        grid(elements);
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

    /// A closed cylinder of radius `r` and length `l`: out along the bottom from the axis, up
    /// the wall, in along the top to the axis (outward normals).
    fn closed_cylinder(r: f64, l: f64, n_c: usize, n_m: usize) -> RevolutionMesh {
        let meridian = [
            MeridianPiece::Line {
                direction: Some(Vector2::new(1.0, 0.0)),
                length: r,
            },
            MeridianPiece::Line {
                direction: Some(Vector2::new(0.0, 1.0)),
                length: l,
            },
            MeridianPiece::Line {
                direction: Some(Vector2::new(-1.0, 0.0)),
                length: r,
            },
        ];
        RevolutionMesh::new(Vector2::zeros(), &meridian, n_c, n_m, "meridian").unwrap()
    }

    /// A sphere of radius `r` about the origin: a half circle from the south to the north pole.
    fn sphere(r: f64, n_c: usize, n_m: usize) -> RevolutionMesh {
        let arc = [MeridianPiece::Arc {
            direction: Some(Vector2::new(1.0, 0.0)),
            radius: r,
            angle: PI,
        }];
        RevolutionMesh::new(Vector2::new(0.0, -r), &arc, n_c, n_m, "meridian").unwrap()
    }

    /// Checks a closed surface mesh: every node used, no two nodes at the same place, every
    /// edge shared by exactly two elements that run along it in opposite directions (watertight
    /// and consistently oriented), every element planar and strictly convex, and every normal
    /// pointing away from `centre` (for star-shaped surfaces about it).
    fn check_closed_surface(m: &RevolutionMesh, centre: Vector3<f64>, what: &str) {
        let x = &m.nodes;
        let scale = x.iter().map(|p| (p - centre).norm()).fold(0.0, f64::max);
        let mut used = vec![false; x.len()];
        let mut edges = std::collections::HashMap::new();
        for (e, el) in m.elements.iter().enumerate() {
            for k in 0..4 {
                used[el[k]] = true;
                let (a, b) = (el[k], el[(k + 1) % 4]);
                assert_ne!(a, b, "{what}: element {e} repeats node {a}");
                let entry = edges.entry((a.min(b), a.max(b))).or_insert((0, 0));
                if a < b {
                    entry.0 += 1;
                } else {
                    entry.1 += 1;
                }
            }
            let p = el.map(|k| x[k]);
            let normal = (p[2] - p[0]).cross(&(p[3] - p[1]));
            let size = normal.norm().sqrt();
            assert!(size > 1e-6 * scale, "{what}: element {e} degenerate");
            let warp = (p[1] - p[0]).cross(&(p[2] - p[0])).dot(&(p[3] - p[0]));
            assert!(
                warp.abs() < 1e-12 * size.powi(3),
                "{what}: element {e} not planar: {warp:e}"
            );
            for k in 0..4 {
                let turn = (p[(k + 1) % 4] - p[k]).cross(&(p[(k + 2) % 4] - p[(k + 1) % 4]));
                assert!(
                    turn.dot(&normal) > 1e-3 * size.powi(4),
                    "{what}: element {e} not convex at corner {}: {p:?}",
                    (k + 1) % 4
                );
            }
            let c = (p[0] + p[1] + p[2] + p[3]) / 4.0;
            assert!(
                normal.dot(&(c - centre)) > 0.0,
                "{what}: element {e} faces inwards"
            );
        }
        assert!(used.iter().all(|&u| u), "{what}: unused nodes");
        for ((a, b), (fwd, back)) in &edges {
            assert_eq!((*fwd, *back), (1, 1), "{what}: edge {a}-{b}");
        }
        for i in 0..x.len() {
            for j in 0..i {
                let d = (x[i] - x[j]).norm();
                assert!(d > 1e-6 * scale, "{what}: nodes {i} and {j} coincide");
            }
        }
    }

    /// The closed cylinder with flat caps is the prism on the inscribed polygon: its volume
    /// and area exactly, both converging to the cylinder's at second order in
    /// 1 / n_circumferential; the volume is the same about any origin.
    #[test]
    fn closed_cylinder_volume_and_area_are_the_polygon_prism() {
        let (r, l) = (0.1, 0.5);
        let err = |n_c: usize| {
            let m = closed_cylinder(r, l, n_c, 2 * n_c);
            let n = n_c as f64;
            let polygon = 0.5 * n * r * r * (2.0 * PI / n).sin();
            let chord = 2.0 * r * (PI / n).sin();
            let v = m.volume();
            assert!((v - polygon * l).abs() < 1e-12 * v, "n = {n_c}: volume {v}");
            let area = 2.0 * polygon + n * chord * l;
            assert!(
                (m.area() - area).abs() < 1e-12 * area,
                "n = {n_c}: area {}",
                m.area()
            );
            let shifted: Vec<_> = m
                .nodes
                .iter()
                .map(|p| p + Vector3::new(1.0, -2.0, 3.0))
                .collect();
            let vs = enclosed_volume(&shifted, &m.elements);
            assert!(
                (vs - v).abs() < 1e-11 * v,
                "n = {n_c}: {vs} about another origin"
            );
            let exact = PI * r * r * l;
            (exact - v) / exact
        };
        let errs: Vec<f64> = [8, 16, 32, 64].iter().map(|&n| err(n)).collect();
        assert!(errs[0] > 0.0 && errs[0] < 0.11, "{errs:?}");
        // the same cylinder from the top pole down: every normal inwards, the volume negative
        let down = [
            MeridianPiece::Line {
                direction: Some(Vector2::new(1.0, 0.0)),
                length: r,
            },
            MeridianPiece::Line {
                direction: Some(Vector2::new(0.0, -1.0)),
                length: l,
            },
            MeridianPiece::Line {
                direction: Some(Vector2::new(-1.0, 0.0)),
                length: r,
            },
        ];
        let m = RevolutionMesh::new(Vector2::new(0.0, l), &down, 16, 32, "m").unwrap();
        let v = closed_cylinder(r, l, 16, 32).volume();
        assert!((m.volume() + v).abs() < 1e-12 * v, "{} vs {v}", m.volume());
        for w in errs.windows(2) {
            assert!((w[0] / w[1] - 4.0).abs() < 0.2, "order: {errs:?}");
        }
    }

    /// Closed cylinders over many meshes: watertight, consistently oriented outwards, planar
    /// convex quadrilaterals, no duplicate nodes; one node on the axis per pole when n/4 is
    /// even, none when odd; the node and element counts of the O-grid.
    #[test]
    fn closed_cylinder_is_watertight_planar_convex_and_outward() {
        for (n_c, n_m) in [
            (4, 3),
            (8, 6),
            (12, 7),
            (16, 14),
            (20, 9),
            (24, 30),
            (64, 40),
        ] {
            let what = format!("n_c = {n_c}, n_m = {n_m}");
            let m = closed_cylinder(0.1, 0.5, n_c, n_m);
            check_closed_surface(&m, Vector3::new(0.0, 0.0, 0.25), &what);
            assert!(m.is_closed(), "{what}");
            let q = n_c / 4;
            assert_eq!(
                m.nodes.len(),
                (n_m - 1) * n_c + 2 * (q + 1) * (q + 1),
                "{what}"
            );
            assert_eq!(
                m.elements.len(),
                (n_m - 2) * n_c + 2 * (q * q + n_c),
                "{what}"
            );
            for (end, z) in [(MeridianEnd::Start, 0.0), (MeridianEnd::End, 0.5)] {
                let pole = m.pole(end).expect("pole");
                let on_axis: Vec<usize> = pole
                    .nodes
                    .clone()
                    .filter(|&k| m.nodes[k].xy().norm() < 1e-12)
                    .collect();
                assert_eq!(
                    on_axis,
                    pole.axis_node.into_iter().collect::<Vec<_>>(),
                    "{what}"
                );
                assert_eq!(pole.axis_node.is_some(), q % 2 == 0, "{what}");
                assert!(
                    pole.nodes.clone().all(|k| m.nodes[k].z == z),
                    "{what}: cap plane"
                );
                assert_eq!(m.ring_nodes(pole.station), None);
                assert_eq!(pole.elements.len(), q * q + n_c);
            }
            let all_axis = m.nodes.iter().filter(|p| p.xy().norm() < 1e-12).count();
            assert_eq!(all_axis, if q % 2 == 0 { 2 } else { 0 }, "{what}");
        }
    }

    /// Rings of a closed mesh: the ring at mid length is the wall's middle circle, the rings
    /// next to the poles are the caps' inner circles, the stations count `n_meridional + 1`.
    #[test]
    fn ring_accessors() {
        let m = closed_cylinder(0.1, 0.5, 16, 14);
        assert_eq!(m.n_stations(), 15);
        let total = m.meridian.stations.length();
        assert!((total - 0.7).abs() < 1e-12);
        let j = m.ring_at(0.5 * total);
        let ring = m.ring_nodes(j).unwrap();
        assert_eq!(ring.len(), 16);
        for k in ring {
            assert!(
                (m.nodes[k].z - 0.25).abs() < 1e-12 && (m.nodes[k].xy().norm() - 0.1).abs() < 1e-12
            );
        }
        assert_eq!(m.ring_at(-1.0), 0);
        assert_eq!(m.ring_at(10.0), 14);
        let first = m.ring_nodes(1).unwrap();
        assert!(
            first
                .clone()
                .all(|k| (m.nodes[k].xy().norm() - 0.05).abs() < 1e-12 && m.nodes[k].z == 0.0)
        );
        // the meshes without poles keep their numbering
        let open = cylinder(8, 3);
        assert!(!open.is_closed() && open.pole(MeridianEnd::Start).is_none());
        assert_eq!(open.ring_nodes(2), Some(16..24));
        // a cup: a flat bottom from the axis and a wall, open at the top
        let cup = [
            MeridianPiece::Line {
                direction: Some(Vector2::new(1.0, 0.0)),
                length: 0.1,
            },
            MeridianPiece::Line {
                direction: Some(Vector2::new(0.0, 1.0)),
                length: 0.2,
            },
        ];
        let m = RevolutionMesh::new(Vector2::zeros(), &cup, 8, 6, "cup").unwrap();
        assert!(!m.is_closed());
        assert!(m.pole(MeridianEnd::Start).is_some() && m.pole(MeridianEnd::End).is_none());
        assert_eq!(m.ring_nodes(6).map(|r| r.len()), Some(8));
        let area = 8.0 * 0.5 * 0.01 * (PI / 4.0).sin() + 8.0 * 2.0 * 0.1 * (PI / 8.0).sin() * 0.2;
        assert!((m.area() - area).abs() < 1e-12, "{} vs {area}", m.area());
    }

    /// A sphere (curved caps: the pole patch is flat in the plane of the pole, the transition
    /// ring a cone): closed, convex planar elements, the volume converging to 4/3 pi R^3 at
    /// second order.
    #[test]
    fn sphere_volume_converges_at_second_order() {
        let r: f64 = 0.2;
        let exact = 4.0 / 3.0 * PI * r.powi(3);
        let err = |n: usize| {
            let m = sphere(r, 4 * n, 2 * n);
            check_closed_surface(&m, Vector3::zeros(), &format!("sphere {n}"));
            let top = m.nodes[m.pole(MeridianEnd::End).unwrap().axis_node.unwrap()];
            assert!((top - Vector3::new(0.0, 0.0, r)).norm() < 1e-14, "{top}");
            (exact - m.volume()) / exact
        };
        let errs: Vec<f64> = [8, 16, 32].iter().map(|&n| err(n)).collect();
        assert!(errs[0] > 0.0 && errs[0] < 0.02, "{errs:?}");
        for w in errs.windows(2) {
            assert!((w[0] / w[1] - 4.0).abs() < 0.25, "order: {errs:?}");
        }
    }

    /// On a closed mesh (pole patches included) the assembled pressure force per unit pressure
    /// is the gradient of the enclosed volume.
    #[test]
    fn pressure_force_is_the_volume_gradient_on_a_closed_mesh() {
        use crate::elements::surface_load::{pressure_into, volume_part_gradient};
        use nalgebra::SVector;
        let m = sphere(0.2, 12, 6);
        let mut grad = vec![Vector3::zeros(); m.nodes.len()];
        let mut force = vec![Vector3::zeros(); m.nodes.len()];
        let mut f = SVector::<f64, 12>::zeros();
        for el in &m.elements {
            let x = el.map(|k| m.nodes[k]);
            let g = volume_part_gradient(&x);
            pressure_into(&x, 1.0, &mut f, None);
            for (i, &k) in el.iter().enumerate() {
                grad[k] += g.fixed_rows::<3>(3 * i);
                force[k] += f.fixed_rows::<3>(3 * i);
            }
        }
        let scale = force.iter().map(|v| v.norm()).fold(0.0, f64::max);
        for k in 0..m.nodes.len() {
            assert!((grad[k] - force[k]).norm() < 1e-12 * scale, "node {k}");
            // outward: the force points away from the centre
            assert!(force[k].dot(&m.nodes[k]) > 0.0, "node {k}");
        }
    }

    /// Poles need n_circumferential = 4 m; only the ends may touch the axis; two poles need a
    /// ring between them.
    #[test]
    fn pole_errors() {
        let meridian = [MeridianPiece::Line {
            direction: Some(Vector2::new(1.0, 0.0)),
            length: 0.1,
        }];
        let err = RevolutionMesh::new(Vector2::zeros(), &meridian, 10, 3, "cap").unwrap_err();
        assert!(
            err.contains("mesh.n_circumferential = 10") && err.contains("multiple of 4"),
            "{err}"
        );
        let along = [
            MeridianPiece::Line {
                direction: Some(Vector2::new(-1.0, 0.0)),
                length: 0.1,
            },
            MeridianPiece::Line {
                direction: Some(Vector2::new(0.0, 1.0)),
                length: 0.1,
            },
        ];
        let err = RevolutionMesh::new(Vector2::new(0.1, 0.0), &along, 8, 4, "m").unwrap_err();
        assert!(err.contains("axis") && err.contains("node 2"), "{err}");
        let half = [MeridianPiece::Arc {
            direction: Some(Vector2::new(1.0, 0.0)),
            radius: 0.1,
            angle: PI,
        }];
        let err = RevolutionMesh::new(Vector2::new(0.0, -0.1), &half, 8, 1, "m").unwrap_err();
        assert!(err.contains("mesh.n_meridional = 1"), "{err}");
        assert!(RevolutionMesh::new(Vector2::new(0.0, -0.1), &half, 8, 2, "m").is_ok());
    }

    /// The elements of the pole patches keep their shape as the mesh is refined: on flat caps
    /// every angle stays within 60°–140° from n_circumferential = 8 to 128 (the rounded square); on
    /// a curved cap (sphere) the polygon's corner angle is `180° − 360° / n`, still convex.
    #[test]
    fn pole_patch_angles() {
        let angles = |m: &RevolutionMesh, end: MeridianEnd| {
            let (mut lo, mut hi) = (180.0f64, 0.0f64);
            for e in m.pole(end).unwrap().elements.clone() {
                let p = m.elements[e].map(|k| m.nodes[k]);
                for k in 0..4 {
                    let a = (p[(k + 3) % 4] - p[k])
                        .angle(&(p[(k + 1) % 4] - p[k]))
                        .to_degrees();
                    (lo, hi) = (lo.min(a), hi.max(a));
                }
            }
            (lo, hi)
        };
        // (n_c = 4: one square in four trapezoids with 45° and 135° angles)
        for n_c in [8, 12, 16, 32, 64, 128] {
            let m = closed_cylinder(0.1, 0.5, n_c, 8);
            for end in [MeridianEnd::Start, MeridianEnd::End] {
                let (lo, hi) = angles(&m, end);
                assert!(
                    lo > 60.0 && hi < 140.0,
                    "n_c = {n_c}: {lo:.1}..{hi:.1} degrees"
                );
            }
        }
        let m = sphere(0.2, 32, 16);
        let (lo, hi) = angles(&m, MeridianEnd::Start);
        assert!(
            lo > 20.0 && (hi - (180.0 - 360.0 / 32.0)).abs() < 1e-9,
            "{lo}..{hi}"
        );
    }

    /// Every element of closed meshes (flat and curved caps) is accepted by the seed-004 shell
    /// element (convex, planar, counter-clockwise about its normal) with the mesh's area.
    #[test]
    fn shell_elements_accept_the_closed_meshes() {
        use crate::elements::trapezoid_shell::{ShellMaterial, ShellOptions, TrapezoidShell};
        let mat = ShellMaterial {
            e: 2.1e11,
            nu: 0.3,
            rho: 7850.0,
            thickness: 2e-3,
        };
        let opt = ShellOptions::default();
        let meshes = [
            ("cylinder 8", closed_cylinder(0.1, 0.5, 8, 10)),
            ("cylinder 12", closed_cylinder(0.1, 0.5, 12, 10)),
            ("cylinder 32", closed_cylinder(0.1, 0.5, 32, 24)),
            ("sphere 16", sphere(0.2, 16, 8)),
        ];
        for (what, m) in &meshes {
            let mut area = 0.0;
            for (e, el) in m.elements.iter().enumerate() {
                let shell = TrapezoidShell::new(el.map(|k| m.nodes[k]), &mat, &opt)
                    .unwrap_or_else(|err| panic!("{what}: element {e}: {err}"));
                area += shell.area();
            }
            assert!(
                (area - m.area()).abs() < 1e-12 * area,
                "{what}: {area} vs {}",
                m.area()
            );
        }
    }
}
