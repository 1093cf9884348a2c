//! Geometry of a belt loop around pulleys: straight spans on the common external tangents and
//! arcs at the pitch radius, and the nodes of a belt mesh placed evenly along it.
//!
//! The belt wraps the pulleys in the order given, each counter-clockwise (the pulleys lie on the
//! left of the direction of travel, inside the loop), so the pulleys must form a convex chain
//! in counter-clockwise order (any order for two pulleys).

use nalgebra::Vector2;
use std::f64::consts::TAU;

/// A pulley as the layout sees it: centre [m] and pitch radius (pulley radius plus half the
/// belt thickness) [m].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PitchCircle {
    /// Centre [m].
    pub center: Vector2<f64>,
    /// Pitch radius [m].
    pub radius: f64,
}

/// A straight span from pulley `from` to pulley `to`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    /// Pulley the belt leaves.
    pub from: usize,
    /// Pulley the belt arrives at.
    pub to: usize,
    /// Tangent point on `from` [m].
    pub start: Vector2<f64>,
    /// Tangent point on `to` [m].
    pub end: Vector2<f64>,
}

/// The closed belt path.
#[derive(Clone, Debug, PartialEq)]
pub struct Loop {
    /// Pitch circles.
    pub circles: Vec<PitchCircle>,
    /// Spans, span `i` from pulley `i` to pulley `i + 1` (cyclic).
    pub spans: Vec<Span>,
    /// Wrap angle on each pulley [rad].
    pub wrap: Vec<f64>,
    /// Polar angle (about its centre) of the arrival tangent point on each pulley [rad].
    arrive: Vec<f64>,
    /// Total length [m].
    pub length: f64,
}

/// A point of the path: position and unit tangent (direction of travel).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathPoint {
    /// Position [m].
    pub r: Vector2<f64>,
    /// Unit tangent.
    pub t: Vector2<f64>,
}

impl Loop {
    /// The loop around `circles` (at least 2). Errors describe impossible layouts.
    pub fn new(circles: &[PitchCircle]) -> Result<Self, String> {
        let n = circles.len();
        if n < 2 {
            return Err("a belt drive needs at least two pulleys".into());
        }
        // Outward unit normal m of the tangent leaving i towards j: m·e = (r_i − r_j)/L.
        let mut normals = Vec::with_capacity(n);
        let mut spans = Vec::with_capacity(n);
        for i in 0..n {
            let j = (i + 1) % n;
            let (ci, cj) = (circles[i], circles[j]);
            let d = cj.center - ci.center;
            let l = d.norm();
            let a = (ci.radius - cj.radius) / l;
            if l.is_nan() || l <= 0.0 || a.abs() >= 1.0 {
                return Err(format!(
                    "pulley{0}.radius, pulley{1}.radius (pulleys {0} and {1}): the centre distance {l:.6} m must exceed the difference of the pitch radii {2:.6} m",
                    i + 1,
                    j + 1,
                    (ci.radius - cj.radius).abs()
                ));
            }
            let e = d / l;
            let e_right = Vector2::new(e.y, -e.x);
            let m = a * e + (1.0 - a * a).sqrt() * e_right;
            normals.push(m);
            spans.push(Span {
                from: i,
                to: j,
                start: ci.center + ci.radius * m,
                end: cj.center + cj.radius * m,
            });
        }
        let mut wrap = Vec::with_capacity(n);
        let mut arrive = Vec::with_capacity(n);
        for j in 0..n {
            let m_in = normals[(j + n - 1) % n];
            let m_out = normals[j];
            let a_in = m_in.y.atan2(m_in.x);
            let a_out = m_out.y.atan2(m_out.x);
            let mut w = (a_out - a_in).rem_euclid(TAU);
            if n == 2 || w == 0.0 {
                // two pulleys: wrap between 0 and 2π; a zero wrap only for equal tangents
                w = if w == 0.0 { TAU } else { w };
            }
            wrap.push(w);
            arrive.push(a_in);
        }
        // A convex counter-clockwise chain has wraps summing to 2π.
        let total: f64 = wrap.iter().sum();
        if (total - TAU).abs() > 1e-9 {
            return Err(format!(
                "the pulleys are not a convex chain in counter-clockwise order (wrap angles sum to {:.4} rad, not 2π): list them counter-clockwise around the loop",
                total
            ));
        }
        let length = spans.iter().map(|s| (s.end - s.start).norm()).sum::<f64>()
            + wrap
                .iter()
                .zip(circles)
                .map(|(w, c)| w * c.radius)
                .sum::<f64>();
        Ok(Self {
            circles: circles.to_vec(),
            spans,
            wrap,
            arrive,
            length,
        })
    }

    /// Point at arc length `s` [m] from the start of span 0 (cyclic).
    pub fn at(&self, s: f64) -> PathPoint {
        let mut s = s.rem_euclid(self.length);
        let n = self.circles.len();
        for i in 0..n {
            let sp = &self.spans[i];
            let d = sp.end - sp.start;
            let l = d.norm();
            let t = d / l;
            if s <= l {
                return PathPoint {
                    r: sp.start + s * t,
                    t,
                };
            }
            s -= l;
            let j = sp.to;
            let c = &self.circles[j];
            let arc = self.wrap[j] * c.radius;
            if s <= arc || i == n - 1 {
                let a = self.arrive[j] + s.min(arc) / c.radius;
                let nrm = Vector2::new(a.cos(), a.sin());
                return PathPoint {
                    r: c.center + c.radius * nrm,
                    t: Vector2::new(-nrm.y, nrm.x),
                };
            }
            s -= arc;
        }
        unreachable!("s is reduced modulo the loop length")
    }

    /// Arc length of the middle of span `i` [m].
    pub fn span_middle(&self, i: usize) -> f64 {
        let mut s = 0.0;
        for k in 0..i {
            let sp = &self.spans[k];
            s += (sp.end - sp.start).norm() + self.wrap[sp.to] * self.circles[sp.to].radius;
        }
        s + 0.5 * (self.spans[i].end - self.spans[i].start).norm()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Open belt over two pulleys: L = 2√(C² − (R − r)²) + π(R + r) + 2(R − r) asin((R − r)/C)
    /// (the standard open-belt length formula, e.g. Shigley's Mechanical Engineering Design,
    /// Table 17-2), wrap on the small pulley π − 2 asin((R − r)/C).
    #[test]
    fn two_pulley_length_and_wraps() {
        let (c, r1, r2) = (0.5, 0.05, 0.12);
        let lp = Loop::new(&[
            PitchCircle {
                center: Vector2::new(0.0, 0.0),
                radius: r1,
            },
            PitchCircle {
                center: Vector2::new(c * 0.6, c * 0.8),
                radius: r2,
            },
        ])
        .unwrap();
        let d = r2 - r1;
        let expect = 2.0 * (c * c - d * d).sqrt() + PI * (r1 + r2) + 2.0 * d * (d / c).asin();
        assert!((lp.length - expect).abs() < 1e-12, "{} {expect}", lp.length);
        let small = PI - 2.0 * (d / c).asin();
        assert!((lp.wrap[0] - small).abs() < 1e-12);
        assert!((lp.wrap[1] - (TAU - small)).abs() < 1e-12);
        // the path is continuous, unit-speed and tangent to the pulleys
        let n = 2000;
        for k in 0..n {
            let s = lp.length * k as f64 / n as f64;
            let (a, b) = (lp.at(s), lp.at(s + 1e-7));
            assert!(((b.r - a.r) / 1e-7 - a.t).norm() < 1e-5, "at s = {s}");
            let dist = lp
                .circles
                .iter()
                .map(|c| (a.r - c.center).norm() - c.radius)
                .fold(f64::INFINITY, f64::min);
            assert!(dist > -1e-12, "inside a pulley at s = {s}");
        }
        // the loop closes
        assert!((lp.at(0.0).r - lp.at(lp.length - 1e-12).r).norm() < 1e-9);
    }

    #[test]
    fn three_pulleys_and_bad_layouts() {
        let p = |x: f64, y: f64, r: f64| PitchCircle {
            center: Vector2::new(x, y),
            radius: r,
        };
        let lp = Loop::new(&[p(0.0, 0.0, 0.1), p(1.0, 0.0, 0.1), p(0.5, 0.8, 0.05)]).unwrap();
        assert!((lp.wrap.iter().sum::<f64>() - TAU).abs() < 1e-12);
        // clockwise order is rejected
        assert!(Loop::new(&[p(0.0, 0.0, 0.1), p(0.5, 0.8, 0.05), p(1.0, 0.0, 0.1)]).is_err());
        // overlapping radii difference
        assert!(Loop::new(&[p(0.0, 0.0, 0.1), p(0.05, 0.0, 0.3)]).is_err());
    }
}
