//! A line drawing of a model's geometry ([`Sketch`]): what the FMU's documentation page and
//! its `model.png` show. A model draws itself from its node positions in the committed state
//! ([`crate::model::Model::sketch`]); the drawing code (`crate::docs`) never knows the kind.

use nalgebra::Vector3;

/// Polylines in the model frame [m] and a one-line description of the mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sketch {
    /// Polylines through points [m] (a closed curve repeats its first point at the end).
    pub lines: Vec<Vec<Vector3<f64>>>,
    /// What the mesh is, e.g. "16 seed-000 ANCF elements, 17 nodes".
    pub mesh: String,
}

impl Sketch {
    /// An empty sketch with the mesh description `mesh`.
    pub fn new(mesh: impl Into<String>) -> Self {
        Self {
            lines: Vec::new(),
            mesh: mesh.into(),
        }
    }

    /// Adds a polyline through `points` [m].
    pub fn line(&mut self, points: impl IntoIterator<Item = Vector3<f64>>) -> &mut Self {
        let pts: Vec<_> = points.into_iter().collect();
        if pts.len() >= 2 {
            self.lines.push(pts);
        }
        self
    }

    /// Adds a polyline through planar points `(x, y)` [m] (z = 0).
    pub fn line_xy(&mut self, points: impl IntoIterator<Item = [f64; 2]>) -> &mut Self {
        self.line(points.into_iter().map(|p| Vector3::new(p[0], p[1], 0.0)))
    }

    /// Adds the circle of radius `radius` [m] about `centre` in the plane normal to the unit
    /// vector `axis`, as a closed polygon of 72 sides.
    pub fn circle(&mut self, centre: Vector3<f64>, radius: f64, axis: Vector3<f64>) -> &mut Self {
        let a = axis.normalize();
        let helper = if a.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let e1 = a.cross(&helper).normalize();
        let e2 = a.cross(&e1);
        self.line((0..=72).map(|k| {
            let phi = std::f64::consts::TAU * k as f64 / 72.0;
            centre + radius * (phi.cos() * e1 + phi.sin() * e2)
        }))
    }

    /// Whether nothing is drawn.
    pub fn is_empty(&self) -> bool {
        self.lines.is_empty()
    }

    /// All points, for bounds.
    pub fn points(&self) -> impl Iterator<Item = &Vector3<f64>> {
        self.lines.iter().flatten()
    }

    /// The polylines seen in a fixed view, in drawing coordinates (x right, y up) [m].
    ///
    /// A flat drawing (the extent along one axis below 1e-9 of the largest extent) is seen
    /// along that axis: a planar model in its own plane, an axisymmetric meridian drawn in the
    /// x–z plane from the front. Anything else is drawn in the isometric view of technical
    /// drawing (DIN ISO 5456-3): the x, y and z axes at 30° below the horizontal to the right,
    /// 30° below to the left and vertical (z up).
    pub fn projected(&self) -> Vec<Vec<[f64; 2]>> {
        let (lo, hi) = self.bounds();
        let ext = hi - lo;
        let size = ext.max();
        let flat = |e: f64| size > 0.0 && e <= 1e-9 * size;
        // drawing axes as combinations of x, y, z
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let (right, up) = if flat(ext.z) {
            (Vector3::x(), Vector3::y())
        } else if flat(ext.y) {
            (Vector3::x(), Vector3::z())
        } else if flat(ext.x) {
            (Vector3::y(), Vector3::z())
        } else {
            (Vector3::new(c, -c, 0.0), Vector3::new(-s, -s, 1.0))
        };
        let view = |p: &Vector3<f64>| [right.dot(p), up.dot(p)];
        self.lines
            .iter()
            .map(|l| l.iter().map(&view).collect())
            .collect()
    }

    /// Smallest and largest coordinates over all points [m] (zeros when empty).
    pub fn bounds(&self) -> (Vector3<f64>, Vector3<f64>) {
        let mut it = self.points();
        let Some(first) = it.next() else {
            return (Vector3::zeros(), Vector3::zeros());
        };
        it.fold((*first, *first), |(lo, hi), p| (lo.inf(p), hi.sup(p)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_planar_drawing_is_seen_in_its_plane() {
        let mut s = Sketch::new("test");
        s.line_xy([[0.0, 0.0], [1.0, 2.0]]);
        assert_eq!(s.projected(), vec![vec![[0.0, 0.0], [1.0, 2.0]]]);
        let mut m = Sketch::new("meridian");
        m.line([Vector3::new(0.1, 0.0, 0.0), Vector3::new(0.2, 0.0, 0.3)]);
        assert_eq!(m.projected(), vec![vec![[0.1, 0.0], [0.2, 0.3]]]);
    }

    #[test]
    fn a_spatial_drawing_is_isometric() {
        let mut s = Sketch::new("axes");
        s.line([Vector3::zeros(), Vector3::x(), Vector3::new(1.0, 1.0, 1.0)]);
        let p = &s.projected()[0];
        // x axis: 30° below the horizontal to the right; the diagonal ends above the origin
        assert!((p[1][0] - 30f64.to_radians().cos()).abs() < 1e-15);
        assert!((p[1][1] + 0.5).abs() < 1e-15);
        assert!(p[2][0].abs() < 1e-15 && p[2][1].abs() < 1e-15, "{:?}", p[2]);
    }

    #[test]
    fn a_circle_has_its_radius_and_plane() {
        let mut s = Sketch::new("c");
        s.circle(Vector3::new(1.0, 2.0, 3.0), 0.5, Vector3::z());
        let l = &s.lines[0];
        assert_eq!(l.len(), 73);
        for p in l {
            assert!(((p - Vector3::new(1.0, 2.0, 3.0)).norm() - 0.5).abs() < 1e-14);
            assert!((p.z - 3.0).abs() < 1e-14);
        }
        assert!((l[0] - l[72]).norm() < 1e-14);
    }
}
