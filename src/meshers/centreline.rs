//! Centre lines of straight and circular pieces, cut into elements: the 3D beam's reference
//! line, and (in the r-z plane) the meridian of a shell of revolution.

use super::stations::Stations;
use nalgebra::Vector3;

/// One piece of a centre line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Piece {
    /// A straight piece.
    Line {
        /// Start tangent (`None`: the end tangent of the previous piece).
        direction: Option<Vector3<f64>>,
        /// Length [m].
        length: f64,
    },
    /// A circular arc that turns its tangent about `bend_axis` (right-hand rule).
    Arc {
        /// Start tangent (`None`: the end tangent of the previous piece).
        direction: Option<Vector3<f64>>,
        /// Radius [m].
        radius: f64,
        /// Angle [rad].
        angle: f64,
        /// Axis the tangent turns about; not parallel to the tangent.
        bend_axis: Vector3<f64>,
    },
}

impl Piece {
    fn direction(&self) -> Option<Vector3<f64>> {
        match self {
            Piece::Line { direction, .. } | Piece::Arc { direction, .. } => *direction,
        }
    }

    fn length(&self) -> f64 {
        match self {
            Piece::Line { length, .. } => *length,
            Piece::Arc { radius, angle, .. } => radius * angle,
        }
    }
}

/// Nodes along a centre line.
#[derive(Clone, Debug)]
pub struct LineMesh {
    /// Node positions [m].
    pub x: Vec<Vector3<f64>>,
    /// Arc length of every node.
    pub stations: Stations,
}

/// A piece placed in space: start point, start tangent and the normal it turns towards.
struct Placed {
    p: Vector3<f64>,
    t: Vector3<f64>,
    /// Unit normal towards the centre of an arc (zero for a line).
    n: Vector3<f64>,
    piece: Piece,
}

impl Placed {
    fn point(&self, u: f64) -> Vector3<f64> {
        match self.piece {
            Piece::Line { length, .. } => self.p + self.t * (length * u),
            Piece::Arc { radius, angle, .. } => {
                let a = angle * u;
                self.p + (self.t * a.sin() + self.n * (1.0 - a.cos())) * radius
            }
        }
    }
}

/// Cuts the centre line from `start` (first tangent: the first piece's direction, default +x)
/// into `n_elements` elements shared among the pieces in proportion to their lengths (largest
/// remainder, at least one each); piece ends are always nodes. `count` names the element-count
/// parameter in messages, `key` the scene table of the pieces.
pub fn mesh_centreline(
    start: Vector3<f64>,
    pieces: &[Piece],
    n_elements: usize,
    count: &str,
    key: &str,
) -> Result<LineMesh, String> {
    let n_pieces = pieces.len();
    if n_pieces == 0 {
        return Err(format!("{key}: give at least one piece"));
    }
    if n_elements < n_pieces {
        return Err(format!(
            "{count} = {n_elements}: the centre line has {n_pieces} pieces and each needs at least one element"
        ));
    }
    let mut placed: Vec<Placed> = Vec::with_capacity(n_pieces);
    let (mut p, mut t) = (start, Vector3::x());
    for (i, piece) in pieces.iter().enumerate() {
        if let Some(d) = piece.direction() {
            // scaled first: components near f64::MAX would overflow the norm
            t = (d / d.amax()).normalize();
        }
        let n = match piece {
            Piece::Line { .. } => Vector3::zeros(),
            Piece::Arc { bend_axis, .. } => {
                let b = bend_axis / bend_axis.amax();
                let bp = b - t * b.dot(&t);
                if bp.norm() < 1e-8 * b.norm() {
                    return Err(format!(
                        "{key}[{i}].bend_axis: parallel to the tangent {t:?} (the direction of this or an earlier piece)"
                    ));
                }
                bp.normalize().cross(&t)
            }
        };
        let pl = Placed {
            p,
            t,
            n,
            piece: *piece,
        };
        p = pl.point(1.0);
        if let Piece::Arc { angle, .. } = piece {
            t = t * angle.cos() + n * angle.sin();
        }
        placed.push(pl);
    }
    let lengths: Vec<f64> = pieces.iter().map(Piece::length).collect();
    if let Some(i) = lengths.iter().position(|l| !(l.is_finite() && *l > 0.0)) {
        return Err(format!(
            "{key}[{i}]: length {} m; every piece needs a finite positive length",
            lengths[i]
        ));
    }
    if !lengths.iter().sum::<f64>().is_finite() {
        return Err(format!("{key}: the total length is not a finite number"));
    }
    let counts = share(&lengths, n_elements)?;
    let mut x = vec![start];
    let mut s = vec![0.0];
    let mut s0 = 0.0;
    for (k, pl) in placed.iter().enumerate() {
        let m = counts[k];
        for j in 1..=m {
            let u = j as f64 / m as f64;
            x.push(pl.point(u));
            s.push(s0 + lengths[k] * u);
        }
        s0 += lengths[k];
    }
    Ok(LineMesh {
        x,
        stations: Stations::new(s),
    })
}

/// Largest-remainder distribution of `n` elements over pieces of the given lengths, at least
/// one each.
fn share(lengths: &[f64], n: usize) -> Result<Vec<usize>, String> {
    let total: f64 = lengths.iter().sum();
    let exact: Vec<f64> = lengths.iter().map(|l| n as f64 * (l / total)).collect();
    let mut counts: Vec<usize> = exact.iter().map(|e| (e.floor() as usize).max(1)).collect();
    let k_all = 0..lengths.len();
    while counts.iter().sum::<usize>() > n {
        let k = k_all
            .clone()
            .filter(|&k| counts[k] > 1)
            .max_by(|&a, &b| {
                (counts[a] as f64 - exact[a]).total_cmp(&(counts[b] as f64 - exact[b]))
            })
            .ok_or("cannot distribute the elements")?;
        counts[k] -= 1;
    }
    while counts.iter().sum::<usize>() < n {
        let k = k_all
            .clone()
            .max_by(|&a, &b| {
                (exact[a] - counts[a] as f64).total_cmp(&(exact[b] - counts[b] as f64))
            })
            .ok_or("cannot distribute the elements")?;
        counts[k] += 1;
    }
    Ok(counts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// The right-angle frame of Simo & Vu-Quoc: two legs of 10 meet at a node.
    #[test]
    fn piece_ends_are_nodes() {
        let legs = [
            Piece::Line {
                direction: Some(Vector3::x()),
                length: 10.0,
            },
            Piece::Line {
                direction: Some(Vector3::y()),
                length: 10.0,
            },
        ];
        let m = mesh_centreline(Vector3::zeros(), &legs, 5, "mesh.n_elements", "c").unwrap();
        assert_eq!(m.x.len(), 6);
        assert!((m.x[5] - Vector3::new(10.0, 10.0, 0.0)).norm() < 1e-12);
        assert!(
            m.x.iter()
                .any(|p| (p - Vector3::new(10.0, 0.0, 0.0)).norm() < 1e-12)
        );
        assert!(mesh_centreline(Vector3::zeros(), &legs, 1, "mesh.n_elements", "c").is_err());
    }

    /// A quarter circle of radius 2 bent about z: the nodes lie on the circle, the arc length
    /// is exact.
    /// Lengths that overflow are an error, not an endless distribution of elements.
    #[test]
    fn huge_pieces_are_rejected() {
        let arc = [Piece::Arc {
            direction: Some(Vector3::x()),
            radius: 1.7e308,
            angle: PI,
            bend_axis: Vector3::z(),
        }];
        let err = mesh_centreline(Vector3::zeros(), &arc, 4, "n", "c").unwrap_err();
        assert!(err.contains("c[0]"), "{err}");
    }

    #[test]
    fn arcs_lie_on_their_circle() {
        let arc = [Piece::Arc {
            direction: Some(Vector3::x()),
            radius: 2.0,
            angle: PI / 2.0,
            bend_axis: Vector3::z(),
        }];
        let m = mesh_centreline(Vector3::zeros(), &arc, 8, "n", "c").unwrap();
        let centre = Vector3::new(0.0, 2.0, 0.0);
        for p in &m.x {
            assert!(((p - centre).norm() - 2.0).abs() < 1e-12);
        }
        assert!((m.x[8] - Vector3::new(2.0, 2.0, 0.0)).norm() < 1e-12);
        assert!((m.stations.length() - PI).abs() < 1e-12);
    }
}
