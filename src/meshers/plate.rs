//! Flat plates in the global x-y plane for the seed-004 shell (Pogorelov & Rodikov 2021): a
//! rectangle `length_x × length_y`, or an isosceles trapezoid whose bottom side (y = 0) is
//! `length_x` long and whose top side (y = `length_y`) is `width_top` long, centred on the
//! bottom side. `n_x` elements across, `n_y` rows up; every row is cut into equal parts, so the
//! elements are trapezoids with sides parallel to x (rectangles for a rectangular plate).
//!
//! Edges: `x0` the left side (x = 0 for a rectangle), `x1` the right side, `y0` the bottom
//! (y = 0), `y1` the top (y = `length_y`). Nodes are found by point ([`node_at_point`]).

use nalgebra::Vector3;

/// A side of a plate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PlateEdge {
    /// The left side (x = 0 for a rectangle).
    X0,
    /// The right side (x = `length_x` for a rectangle).
    X1,
    /// The bottom side, y = 0.
    Y0,
    /// The top side, y = `length_y`.
    Y1,
}

impl PlateEdge {
    /// All four edges in the order x0, x1, y0, y1.
    pub const ALL: [PlateEdge; 4] = [Self::X0, Self::X1, Self::Y0, Self::Y1];

    /// The edge's scene name (`x0`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Self::X0 => "x0",
            Self::X1 => "x1",
            Self::Y0 => "y0",
            Self::Y1 => "y1",
        }
    }
}

/// A meshed plate.
#[derive(Clone, Debug)]
pub struct PlateMesh {
    /// Elements across (along x).
    pub n_x: usize,
    /// Element rows (along y).
    pub n_y: usize,
    /// Node positions [m]: node `(i, j)` (column `i` of row `j`) is `j (n_x + 1) + i`.
    pub nodes: Vec<Vector3<f64>>,
    /// Elements row by row, each `[(i, j), (i+1, j), (i+1, j+1), (i, j+1)]`: counter-clockwise
    /// about +z.
    pub elements: Vec<[usize; 4]>,
}

impl PlateMesh {
    /// Cuts the plate into `n_x × n_y` elements. `width_top` (default `length_x`) makes it an
    /// isosceles trapezoid. Errors name the scene keys `plate.*` and `mesh.n_x`, `mesh.n_y`.
    pub fn new(
        length_x: f64,
        length_y: f64,
        width_top: Option<f64>,
        n_x: usize,
        n_y: usize,
    ) -> Result<Self, String> {
        let top = width_top.unwrap_or(length_x);
        for (key, v) in [
            ("plate.length_x", length_x),
            ("plate.length_y", length_y),
            ("plate.width_top", top),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{key} = {v}: must be a positive length [m]"));
            }
        }
        if n_x == 0 || n_y == 0 {
            return Err(format!(
                "mesh.n_x = {n_x}, mesh.n_y = {n_y}: a plate needs at least one element each way"
            ));
        }
        let mut nodes = Vec::with_capacity((n_x + 1) * (n_y + 1));
        for j in 0..=n_y {
            let eta = j as f64 / n_y as f64;
            let width = length_x + (top - length_x) * eta;
            let left = 0.5 * (length_x - width);
            for i in 0..=n_x {
                nodes.push(Vector3::new(
                    left + width * i as f64 / n_x as f64,
                    length_y * eta,
                    0.0,
                ));
            }
        }
        if nodes.iter().any(|x| !(x.x.is_finite() && x.y.is_finite())) {
            return Err(format!(
                "plate.length_x = {length_x}, plate.length_y = {length_y}, plate.width_top = {top}: the node positions are not finite"
            ));
        }
        let row = n_x + 1;
        let mut elements = Vec::with_capacity(n_x * n_y);
        for j in 0..n_y {
            for i in 0..n_x {
                let a = j * row + i;
                elements.push([a, a + 1, a + row + 1, a + row]);
            }
        }
        Ok(Self {
            n_x,
            n_y,
            nodes,
            elements,
        })
    }

    /// The nodes of an edge in order along it (x0, x1 from bottom to top; y0, y1 from left to
    /// right).
    pub fn edge_nodes(&self, edge: PlateEdge) -> Vec<usize> {
        let row = self.n_x + 1;
        match edge {
            PlateEdge::X0 => (0..=self.n_y).map(|j| j * row).collect(),
            PlateEdge::X1 => (0..=self.n_y).map(|j| j * row + self.n_x).collect(),
            PlateEdge::Y0 => (0..=self.n_x).collect(),
            PlateEdge::Y1 => (0..=self.n_x).map(|i| self.n_y * row + i).collect(),
        }
    }

    /// Area of the plate [m2] (sum of the element trapezoids).
    pub fn area(&self) -> f64 {
        self.elements
            .iter()
            .map(|&[a, b, c, d]| {
                let x = &self.nodes;
                0.5 * (x[c] - x[a]).cross(&(x[d] - x[b])).norm()
            })
            .sum()
    }
}

/// The node of `nodes` at the point `p` [m] (within 1e-6 of the mesh's extent). The scene
/// entry `key` and the mesh parameters `mesh_keys` name the problem when no node is there.
pub fn node_at_point(
    nodes: &[Vector3<f64>],
    p: &Vector3<f64>,
    key: &str,
    mesh_keys: &str,
) -> Result<usize, String> {
    let (lo, hi) = nodes.iter().fold(
        (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        ),
        |(lo, hi), x| (lo.inf(x), hi.sup(x)),
    );
    let extent = (hi - lo).norm();
    let (k, d) = nodes
        .iter()
        .enumerate()
        .map(|(k, x)| (k, (x - p).norm()))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .ok_or_else(|| format!("{key}: the mesh has no nodes"))?;
    if d <= 1e-6 * extent {
        Ok(k)
    } else {
        let x = nodes[k];
        Err(format!(
            "{key}.at = [{}, {}, {}]: no node there (the nearest node is at [{}, {}, {}], {d:.3e} m away; the nodes follow from {mesh_keys})",
            p.x, p.y, p.z, x.x, x.y, x.z
        ))
    }
}

/// Weights of the trapezoid rule over the nodes of a polyline (`closed`: the last node joins
/// the first): half the length of the segments at each node over the total length, so that a
/// total force `F` spread as `w_k F` is the resultant of a uniform line load. Summing to one.
pub fn line_weights(points: &[Vector3<f64>], closed: bool) -> Vec<f64> {
    let n = points.len();
    if n == 1 {
        return vec![1.0];
    }
    let mut w = vec![0.0; n];
    let n_seg = if closed { n } else { n - 1 };
    let mut total = 0.0;
    for s in 0..n_seg {
        let (a, b) = (s, (s + 1) % n);
        let l = (points[b] - points[a]).norm();
        w[a] += 0.5 * l;
        w[b] += 0.5 * l;
        total += l;
    }
    if total > 0.0 {
        w.iter_mut().for_each(|x| *x /= total);
    } else {
        w.fill(1.0 / n as f64);
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rectangle: the node grid, counter-clockwise elements, edges and area.
    #[test]
    fn rectangle_grid_and_edges() {
        let m = PlateMesh::new(2.0, 1.0, None, 4, 2).unwrap();
        assert_eq!(m.nodes.len(), 15);
        assert_eq!(m.elements.len(), 8);
        assert_eq!(m.elements[5], [6, 7, 12, 11]);
        for &[a, b, c, d] in &m.elements {
            let n = (m.nodes[c] - m.nodes[a]).cross(&(m.nodes[d] - m.nodes[b]));
            assert!(n.z > 0.0 && n.x == 0.0 && n.y == 0.0);
        }
        assert_eq!(m.edge_nodes(PlateEdge::X0), vec![0, 5, 10]);
        assert_eq!(m.edge_nodes(PlateEdge::X1), vec![4, 9, 14]);
        assert_eq!(m.edge_nodes(PlateEdge::Y0), vec![0, 1, 2, 3, 4]);
        assert_eq!(m.edge_nodes(PlateEdge::Y1), vec![10, 11, 12, 13, 14]);
        for k in m.edge_nodes(PlateEdge::X1) {
            assert_eq!(m.nodes[k].x, 2.0);
        }
        assert!((m.area() - 2.0).abs() < 1e-14);
    }

    /// A trapezoid: the top side centred and `width_top` long, the area (a + b) h / 2.
    #[test]
    fn trapezoid_sides_and_area() {
        let m = PlateMesh::new(2.0, 1.5, Some(1.0), 3, 3).unwrap();
        let top = m.edge_nodes(PlateEdge::Y1);
        let (l, r) = (m.nodes[top[0]], m.nodes[top[3]]);
        assert!((l.x - 0.5).abs() < 1e-15 && (r.x - 1.5).abs() < 1e-15 && l.y == 1.5);
        assert!((m.area() - 0.5 * (2.0 + 1.0) * 1.5).abs() < 1e-13);
    }

    #[test]
    fn nodes_are_found_by_point_or_named_missing() {
        let m = PlateMesh::new(1.0, 1.0, None, 2, 2).unwrap();
        let k = node_at_point(&m.nodes, &Vector3::new(0.5, 0.5, 0.0), "probes[0]", "mesh").unwrap();
        assert_eq!(k, 4);
        let err = node_at_point(
            &m.nodes,
            &Vector3::new(0.25, 0.5, 0.0),
            "probes[0]",
            "mesh.n_x",
        )
        .unwrap_err();
        assert!(
            err.contains("probes[0].at") && err.contains("mesh.n_x"),
            "{err}"
        );
    }

    #[test]
    fn bad_sizes_are_named() {
        let err = PlateMesh::new(-1.0, 1.0, None, 2, 2).unwrap_err();
        assert!(err.contains("plate.length_x"), "{err}");
        let err = PlateMesh::new(1.0, 1.0, Some(0.0), 2, 2).unwrap_err();
        assert!(err.contains("plate.width_top"), "{err}");
        let err = PlateMesh::new(1.0, 1.0, None, 0, 2).unwrap_err();
        assert!(err.contains("mesh.n_x"), "{err}");
    }

    /// The trapezoid rule: end nodes get half a segment, closed rings equal shares.
    #[test]
    fn line_weights_sum_to_one() {
        let p: Vec<_> = (0..5).map(|i| Vector3::new(i as f64, 0.0, 0.0)).collect();
        let w = line_weights(&p, false);
        assert_eq!(w, vec![0.125, 0.25, 0.25, 0.25, 0.125]);
        let ring: Vec<_> = (0..6)
            .map(|i| {
                let a = i as f64 * std::f64::consts::PI / 3.0;
                Vector3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        for w in line_weights(&ring, true) {
            assert!((w - 1.0 / 6.0).abs() < 1e-15);
        }
    }
}
