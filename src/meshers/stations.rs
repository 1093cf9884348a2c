//! Stations along a body: where a fraction of the body's length falls on the mesh. Supports,
//! motion ports, loads and probes of every line-like kind (planar and 3D beams; the meridian
//! of a shell of revolution) are placed with this one piece.

/// The arc-length positions of the nodes of a line mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Stations {
    /// Arc length of every node from the first [m], increasing.
    s: Vec<f64>,
}

/// Where a fraction of the length falls inside an element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElementPoint {
    /// Element (its first node).
    pub element: usize,
    /// Fraction of the element's length from its first node, in [0, 1].
    pub xi: f64,
}

impl Stations {
    /// Nodes at the given arc lengths (at least two, increasing).
    pub fn new(s: Vec<f64>) -> Self {
        debug_assert!(s.len() >= 2 && s.windows(2).all(|w| w[1] > w[0]));
        Self { s }
    }

    /// `n_elements` equal elements over `length`.
    pub fn uniform(n_elements: usize, length: f64) -> Self {
        Self::new(
            (0..=n_elements)
                .map(|k| length * k as f64 / n_elements as f64)
                .collect(),
        )
    }

    /// Total length [m].
    pub fn length(&self) -> f64 {
        self.s[self.s.len() - 1]
    }

    /// Arc length of every node [m].
    pub fn arc_lengths(&self) -> &[f64] {
        &self.s
    }

    /// The node at fraction `at` of the length; the scene entry `key` (e.g. `supports[0]`)
    /// and the element-count parameter `count` (e.g. `mesh.n_elements`) name the problem when
    /// `at` falls between nodes.
    pub fn node_at(&self, key: &str, at: f64, count: &str) -> Result<usize, String> {
        let length = self.length();
        let target = at * length;
        let k = self
            .s
            .iter()
            .enumerate()
            .min_by(|a, b| (a.1 - target).abs().total_cmp(&(b.1 - target).abs()))
            .map_or(0, |(k, _)| k);
        if (self.s[k] - target).abs() <= 1e-9 * length {
            return Ok(k);
        }
        let lo = self.s.iter().rev().find(|&&s| s <= target).unwrap_or(&0.0);
        let hi = self.s.iter().find(|&&s| s >= target).unwrap_or(&length);
        Err(format!(
            "{key}.at = {at}: must fall on a node; with {count} = {} the nearest nodes are at {:.6} and {:.6} of the length",
            self.s.len() - 1,
            lo / length,
            hi / length
        ))
    }

    /// The element and local fraction at fraction `at` of the length (the last element for
    /// `at` = 1).
    pub fn point_at(&self, at: f64) -> ElementPoint {
        let target = at * self.length();
        let n_el = self.s.len() - 1;
        let e = self.s[1..n_el].partition_point(|&s| s <= target);
        let (a, b) = (self.s[e], self.s[e + 1]);
        ElementPoint {
            element: e,
            xi: ((target - a) / (b - a)).clamp(0.0, 1.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nodes_and_points_of_a_uniform_mesh() {
        let st = Stations::uniform(4, 2.0);
        assert_eq!(st.node_at("supports[0]", 0.5, "mesh.n_elements"), Ok(2));
        assert_eq!(st.node_at("supports[0]", 1.0, "mesh.n_elements"), Ok(4));
        let err = st.node_at("probes[1]", 0.3, "mesh.n_elements").unwrap_err();
        assert!(
            err.contains("probes[1].at = 0.3")
                && err.contains("mesh.n_elements = 4")
                && err.contains("0.250000 and 0.500000"),
            "{err}"
        );
        let p = st.point_at(0.3);
        assert_eq!(p.element, 1);
        assert!((p.xi - 0.2).abs() < 1e-12);
        assert_eq!(
            st.point_at(1.0),
            ElementPoint {
                element: 3,
                xi: 1.0
            }
        );
        assert_eq!(
            st.point_at(0.0),
            ElementPoint {
                element: 0,
                xi: 0.0
            }
        );
    }

    #[test]
    fn nodes_of_an_uneven_mesh() {
        let st = Stations::new(vec![0.0, 1.0, 1.5, 4.0]);
        assert_eq!(st.node_at("loads[0]", 0.375, "n"), Ok(2));
        assert!(st.node_at("loads[0]", 0.5, "n").is_err());
        let p = st.point_at(0.5);
        assert_eq!(p.element, 2);
        assert!((p.xi - 0.2).abs() < 1e-12);
    }
}
