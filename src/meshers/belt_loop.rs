//! Geometry of a belt loop around pulleys: straight spans on the common external tangents and
//! arcs at the pitch radius, and the nodes of a belt mesh placed evenly along it.
//!
//! The belt runs counter-clockwise around the loop and wraps the pulleys in the order given. A
//! front-side pulley lies inside the loop (on the left of the direction of travel) and the belt
//! wraps it counter-clockwise; a back-side pulley (an idler on the back of the belt) lies outside
//! the loop and the belt wraps it clockwise ([`Loop::with_sides`]). With signed pitch radii
//! `ρ = +R` (front) and `ρ = −R` (back) every span lies on the common tangent of the two circles
//! with outward unit normal `m`, `m·e = (ρ_i − ρ_j)/L` (external tangent between pulleys of the
//! same side, internal, crossed tangent between a front and a back pulley), tangent points
//! `c + ρ m`; the turning of the belt direction, `Σ s_j w_j` (`s_j = ±1`, `w_j` the wrap), is 2π
//! for a layout the belt can follow.

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
    /// Wrap angle on each pulley [rad] (positive on both sides).
    pub wrap: Vec<f64>,
    /// Wrap direction of each pulley: +1 front side (counter-clockwise), −1 back side
    /// (clockwise).
    pub sides: Vec<f64>,
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
    /// The loop around `circles` (at least 2), every pulley on the front side (wrapped
    /// counter-clockwise). Errors describe impossible layouts.
    pub fn new(circles: &[PitchCircle]) -> Result<Self, String> {
        Self::with_sides(circles, &vec![false; circles.len()])
    }

    /// The loop around `circles` (at least 2) with the pulleys flagged in `back` on the back
    /// of the belt (outside the loop, wrapped clockwise; at least three pulleys then). Errors
    /// name the pulleys of an impossible layout: overlapping circles, spans that cross, a
    /// chain the belt cannot follow.
    pub fn with_sides(circles: &[PitchCircle], back: &[bool]) -> Result<Self, String> {
        let n = circles.len();
        if n < 2 {
            return Err("a belt drive needs at least two pulleys".into());
        }
        assert_eq!(back.len(), n, "one side per pulley");
        if n < 3 && back.iter().any(|&b| b) {
            return Err(
                "a back-side pulley needs at least two front-side pulleys in the loop".into(),
            );
        }
        let sides: Vec<f64> = back.iter().map(|&b| if b { -1.0 } else { 1.0 }).collect();
        let rho = |i: usize| sides[i] * circles[i].radius;
        // Outward unit normal m of the tangent leaving i towards j: m·e = (ρ_i − ρ_j)/L.
        let mut normals = Vec::with_capacity(n);
        let mut spans = Vec::with_capacity(n);
        for i in 0..n {
            let j = (i + 1) % n;
            let (ci, cj) = (circles[i], circles[j]);
            let d = cj.center - ci.center;
            let l = d.norm();
            let a = (rho(i) - rho(j)) / l;
            if l.is_nan() || l <= 0.0 || a.abs() >= 1.0 {
                let what = if sides[i] == sides[j] {
                    "difference"
                } else {
                    "sum"
                };
                return Err(format!(
                    "pulley{0}.center, pulley{1}.center, pulley{0}.radius, pulley{1}.radius (pulleys {0} and {1}): the centre distance {l:.6} m must exceed the {what} of the pitch radii (radius + belt.thickness/2) {2:.6} m",
                    i + 1,
                    j + 1,
                    (rho(i) - rho(j)).abs()
                ));
            }
            let e = d / l;
            let e_right = Vector2::new(e.y, -e.x);
            let m = a * e + (1.0 - a * a).sqrt() * e_right;
            normals.push(m);
            spans.push(Span {
                from: i,
                to: j,
                start: ci.center + rho(i) * m,
                end: cj.center + rho(j) * m,
            });
        }
        let mut wrap = Vec::with_capacity(n);
        let mut arrive = Vec::with_capacity(n);
        for j in 0..n {
            // the contact point on pulley j lies at c + ρ m: polar direction s m
            let m_in = sides[j] * normals[(j + n - 1) % n];
            let m_out = sides[j] * normals[j];
            let a_in = m_in.y.atan2(m_in.x);
            let a_out = m_out.y.atan2(m_out.x);
            let mut w = (sides[j] * (a_out - a_in)).rem_euclid(TAU);
            if n == 2 || w == 0.0 {
                // two pulleys: wrap between 0 and 2π; a zero wrap only for equal tangents
                w = if w == 0.0 { TAU } else { w };
            }
            wrap.push(w);
            arrive.push(a_in);
        }
        // The belt direction turns by 2π around a loop it can follow.
        let total: f64 = wrap.iter().zip(&sides).map(|(w, s)| w * s).sum();
        if (total - TAU).abs() > 1e-9 {
            let front: Vec<String> = (0..n)
                .filter(|&i| sides[i] > 0.0)
                .map(|i| format!("pulley{}", i + 1))
                .collect();
            let back_list: Vec<String> = (0..n)
                .filter(|&i| sides[i] < 0.0)
                .map(|i| format!("pulley{}", i + 1))
                .collect();
            return Err(format!(
                "the belt cannot follow the pulleys in this order (the belt direction turns by {total:.4} rad around the loop, not 2π): list the front-side pulleys ({}) counter-clockwise around the loop{} (pulley.center, radius{})",
                front.join(", "),
                if back_list.is_empty() {
                    String::new()
                } else {
                    format!(
                        ", each back-side pulley ({}) outside the loop between its neighbours",
                        back_list.join(", ")
                    )
                },
                // the side key exists where back-side pulleys do (the planar drives)
                if back_list.is_empty() { "" } else { ", side" }
            ));
        }
        // Spans must not cross one another.
        for i in 0..n {
            for j in i + 1..n {
                if j == i + 1 || (i == 0 && j == n - 1) {
                    continue;
                }
                let (a, b) = (&spans[i], &spans[j]);
                if segments_cross(a.start, a.end, b.start, b.end) {
                    return Err(format!(
                        "the span from pulley{} to pulley{} crosses the span from pulley{} to pulley{}: reorder the pulleys, move them (pulley.center, radius) or change the wrap side of one",
                        a.from + 1,
                        a.to + 1,
                        b.from + 1,
                        b.to + 1
                    ));
                }
            }
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
            sides,
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
                let sd = self.sides[j];
                let a = self.arrive[j] + sd * s.min(arc) / c.radius;
                let nrm = Vector2::new(a.cos(), a.sin());
                return PathPoint {
                    r: c.center + c.radius * nrm,
                    t: sd * Vector2::new(-nrm.y, nrm.x),
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

/// Whether the segments `a0 a1` and `b0 b1` cross at an interior point of both.
fn segments_cross(a0: Vector2<f64>, a1: Vector2<f64>, b0: Vector2<f64>, b1: Vector2<f64>) -> bool {
    let cross = |u: Vector2<f64>, v: Vector2<f64>| u.x * v.y - u.y * v.x;
    let (da, db) = (a1 - a0, b1 - b0);
    let den = cross(da, db);
    if den.abs() <= 1e-14 * da.norm() * db.norm() {
        return false;
    }
    let t = cross(b0 - a0, db) / den;
    let u = cross(b0 - a0, da) / den;
    (0.0..1.0).contains(&t) && t > 0.0 && (0.0..1.0).contains(&u) && u > 0.0
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

    /// A back-side idler on the upper span of two equal pulleys (A at the origin, B at
    /// (1, 0), R = 0.1; idler C of r = 0.05 at (0.5, 0.12), belt order A, B, C). Hand
    /// computation: the spans B–C and C–A are internal tangents of length √(L² − (R + r)²),
    /// L = |BC|, tilted by α below the horizontal with (c_C − c_B)·(−sin α, cos α) = R + r,
    /// i.e. α = asin((R + r)/L) − atan(0.12/0.5); wraps π + α on A and B, 2α on C;
    /// length 1 + 2√(L² − (R + r)²) + 2R(π + α) + 2rα.
    #[test]
    fn back_side_idler_lengths_and_wraps() {
        let p = |x: f64, y: f64, r: f64| PitchCircle {
            center: Vector2::new(x, y),
            radius: r,
        };
        let (big_r, r) = (0.1, 0.05);
        let circles = [p(0.0, 0.0, big_r), p(1.0, 0.0, big_r), p(0.5, 0.12, r)];
        let lp = Loop::with_sides(&circles, &[false, false, true]).unwrap();
        let l = (0.5f64.powi(2) + 0.12f64.powi(2)).sqrt();
        let alpha = ((big_r + r) / l).asin() - (0.12f64 / 0.5).atan();
        let tangent = (l * l - (big_r + r).powi(2)).sqrt();
        assert!(alpha > 0.0);
        for (k, w) in [PI + alpha, PI + alpha, 2.0 * alpha].iter().enumerate() {
            assert!(
                (lp.wrap[k] - w).abs() < 1e-12,
                "wrap {k}: {} vs {w}",
                lp.wrap[k]
            );
        }
        let expect = 1.0 + 2.0 * tangent + 2.0 * big_r * (PI + alpha) + 2.0 * r * alpha;
        assert!((lp.length - expect).abs() < 1e-12, "{} {expect}", lp.length);
        for sp in &lp.spans[1..] {
            assert!(((sp.end - sp.start).norm() - tangent).abs() < 1e-12);
        }
        assert_eq!(lp.sides, vec![1.0, 1.0, -1.0]);
        // continuous, unit speed, outside every pulley, touching the idler from below
        let n = 3000;
        for k in 0..n {
            let s = lp.length * k as f64 / n as f64;
            let (a, b) = (lp.at(s), lp.at(s + 1e-7));
            assert!(((b.r - a.r) / 1e-7 - a.t).norm() < 1e-5, "at s = {s}");
            for c in &lp.circles {
                assert!(
                    (a.r - c.center).norm() - c.radius > -1e-12,
                    "inside at s = {s}"
                );
            }
        }
        let lowest = lp.at(lp.span_middle(1) + 0.5 * tangent + r * alpha);
        assert!((lowest.r - Vector2::new(0.5, 0.12 - r)).norm() < 1e-9);
        assert!((lowest.t - Vector2::new(-1.0, 0.0)).norm() < 1e-9);
        assert!((lp.at(0.0).r - lp.at(lp.length - 1e-12).r).norm() < 1e-9);
        // all front: the same as Loop::new
        let front = Loop::with_sides(&circles[..2], &[false, false]).unwrap();
        assert_eq!(front, Loop::new(&circles[..2]).unwrap());
    }

    #[test]
    fn bad_back_side_layouts_name_the_pulleys() {
        let p = |x: f64, y: f64, r: f64| PitchCircle {
            center: Vector2::new(x, y),
            radius: r,
        };
        // an idler above the span it should press down: the belt would wrap it the wrong way
        let e = Loop::with_sides(
            &[p(0.0, 0.0, 0.1), p(1.0, 0.0, 0.1), p(0.5, 0.3, 0.05)],
            &[false, false, true],
        )
        .unwrap_err();
        assert!(e.contains("pulley3") && e.contains("cannot follow"), "{e}");
        // an idler overlapping a front pulley: no internal tangent
        let e = Loop::with_sides(
            &[p(0.0, 0.0, 0.1), p(1.0, 0.0, 0.1), p(0.95, 0.1, 0.05)],
            &[false, false, true],
        )
        .unwrap_err();
        assert!(e.contains("pulleys 2 and 3") && e.contains("sum"), "{e}");
        // two pulleys cannot have a back side
        assert!(Loop::with_sides(&[p(0.0, 0.0, 0.1), p(1.0, 0.0, 0.1)], &[false, true]).is_err());
        // spans that cross: an idler drawn across the loop to the far side
        let e = Loop::with_sides(
            &[
                p(0.0, 0.0, 0.1),
                p(1.0, 0.0, 0.1),
                p(1.0, 1.0, 0.1),
                p(0.5, -0.5, 0.05),
                p(0.0, 1.0, 0.1),
            ],
            &[false, false, false, true, false],
        )
        .unwrap_err();
        assert!(e.contains("pulley"), "{e}");
    }
}
