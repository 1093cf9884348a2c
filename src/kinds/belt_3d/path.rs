//! The mounted path of a 3D belt whose pulleys are not all on parallel axes (the quarter-twist
//! drive): arcs on the pulleys' pitch circles, each in its pulley's middle plane, joined by
//! straight spans. A span runs from pulley `i` to the next pulley `j` as belts run in real
//! drives with crossed axes: it arrives at pulley `j` tangentially in `j`'s plane (the rule
//! that keeps a belt on a pulley: the arriving belt's centre line lies in the pulley's plane)
//! and leaves pulley `i` tangentially to its rim cylinder, possibly at an angle to `i`'s plane
//! (a departing belt may leave obliquely). The span is the tangent line of circle `j` at the
//! angle `φ` that touches `i`'s pitch cylinder in its middle plane: distance from `i`'s axis
//! minus its radius `g(φ)` and axial offset of the touching point `u(φ)` both zero. That is
//! two conditions on one angle, so the pulleys must be placed for it (for perpendicular axes:
//! the plane of each pulley tangent to the other's pitch cylinder, see
//! `scenes/conveyor_twist.toml`); `φ` minimizes `|g| + |u|` (scan, then golden section), a
//! small remaining miss is accepted (the departure point is put onto the cylinder, an axial
//! offset taken up by a helical arc on `i`), a larger one is an error.
//!
//! The belt's width direction: the pulley's axis on an arc; on a span it turns about the
//! span's direction from the departing pulley's axis (projected normal to the span) to the
//! arriving pulley's axis at a uniform rate, so the twist is spread over the span.

use nalgebra::{Rotation3, Unit, Vector3};

/// A pitch circle in space: centre [m], unit axis (the belt runs counter-clockwise about it),
/// pitch radius [m].
#[derive(Clone, Copy, Debug)]
pub struct SpaceCircle {
    /// Centre [m].
    pub center: Vector3<f64>,
    /// Unit axis.
    pub axis: Vector3<f64>,
    /// Pitch radius [m].
    pub radius: f64,
}

impl SpaceCircle {
    fn basis(&self) -> (Vector3<f64>, Vector3<f64>) {
        let a = self.axis;
        let k = a.iamin();
        let mut u = Vector3::zeros();
        u[k] = 1.0;
        let u1 = (u - a.dot(&u) * a).normalize();
        (u1, a.cross(&u1))
    }

    /// Point and unit tangent (direction of belt travel) at polar angle `phi`.
    fn at(&self, phi: f64) -> (Vector3<f64>, Vector3<f64>) {
        let (u1, u2) = self.basis();
        (
            self.center + self.radius * (phi.cos() * u1 + phi.sin() * u2),
            -phi.sin() * u1 + phi.cos() * u2,
        )
    }

    /// Polar angle of the point `r` about the axis.
    fn angle(&self, r: &Vector3<f64>) -> f64 {
        let (u1, u2) = self.basis();
        let d = r - self.center;
        d.dot(&u2).atan2(d.dot(&u1))
    }
}

#[derive(Clone, Copy, Debug)]
enum Piece {
    /// On pulley `k` from polar angle `phi0` through `wrap` [rad], axial position from 0 to
    /// `u1` [m].
    Arc {
        k: usize,
        phi0: f64,
        wrap: f64,
        u1: f64,
    },
    /// From `p0` to `p1`, width direction turning from `w0` by `twist` [rad] about the span.
    Line {
        p0: Vector3<f64>,
        p1: Vector3<f64>,
        w0: Vector3<f64>,
        twist: f64,
    },
}

/// The closed mounted path.
#[derive(Clone, Debug)]
pub struct SpacePath {
    circles: Vec<SpaceCircle>,
    pieces: Vec<(f64, Piece)>,
    /// Total length [m].
    pub length: f64,
    /// Length of the arc on pulley 1 [m]: [`Self::at`] measures from its end (the departure
    /// of span 1), as the planar loop ([`crate::meshers::belt_loop::Loop::at`]) does.
    start: f64,
}

/// One point of the path: position [m], unit tangent, unit width direction (normal to the
/// tangent), and the pulley whose arc it is on (`None` on a span).
#[derive(Clone, Copy, Debug)]
pub struct PathPoint {
    /// Position [m].
    pub r: Vector3<f64>,
    /// Unit tangent (direction of belt travel).
    pub t: Vector3<f64>,
    /// Unit width direction, normal to `t`.
    pub w: Vector3<f64>,
    /// The pulley whose arc the point is on.
    pub pulley: Option<usize>,
}

/// The span arriving at `cj` from `ci`: arrival angle on `cj`, the departure point on `ci`
/// (on its pitch cylinder) and its axial offset from `ci`'s middle plane [m], and the miss
/// `|g| + |u|` [m] of the best line (0 where the geometry admits the span exactly).
fn span(ci: &SpaceCircle, cj: &SpaceCircle) -> Option<(f64, Vector3<f64>, f64, f64)> {
    // the tangent line of j at φ: g = its distance from the axis of i minus i's radius,
    // u = axial position of its nearest point; valid where that point lies behind the
    // arrival (s < 0) and the belt there runs counter-clockwise about i's axis. Tangency in
    // i's middle plane is g = u = 0, a double root of g where it exists (the line only
    // touches the cylinder): minimize |g| + |u| instead of solving g = 0.
    let eval = |phi: f64| {
        let (p, t) = cj.at(phi);
        let w0 = p - ci.center;
        let (b, d, e) = (t.dot(&ci.axis), t.dot(&w0), ci.axis.dot(&w0));
        let den = 1.0 - b * b;
        if den < 1e-6 {
            return None;
        }
        let s = (b * e - d) / den;
        let u = (e - b * d) / den;
        let foot = p + s * t;
        let diff = foot - (ci.center + u * ci.axis);
        if !(s < 0.0 && t.dot(&ci.axis.cross(&diff)) > 0.0) || diff.norm() <= 0.0 {
            return None;
        }
        let g = diff.norm() - ci.radius;
        let on_cylinder = ci.center + u * ci.axis + ci.radius * diff.normalize();
        Some((g.abs() + u.abs(), on_cylinder, u))
    };
    let miss = |phi: f64| eval(phi).map_or(f64::INFINITY, |e| e.0);
    let n = 3600;
    let h = std::f64::consts::TAU / n as f64;
    let phi0 = (0..n)
        .map(|k| k as f64 * h)
        .min_by(|a, b| miss(*a).total_cmp(&miss(*b)))?;
    if !miss(phi0).is_finite() {
        return None;
    }
    // golden-section refinement on [φ0 − h, φ0 + h]
    let (mut lo, mut hi) = (phi0 - h, phi0 + h);
    let r = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..80 {
        let (m1, m2) = (hi - r * (hi - lo), lo + r * (hi - lo));
        if miss(m1) < miss(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    let phi = 0.5 * (lo + hi);
    let (m, foot, u) = eval(phi)?;
    Some((phi, foot, u, m))
}

/// `w` projected normal to the unit vector `t`, normalized.
fn normal_part(w: &Vector3<f64>, t: &Vector3<f64>) -> Vector3<f64> {
    (w - w.dot(t) * t).normalize()
}

impl SpacePath {
    /// The path around `circles` in order (the belt runs counter-clockwise about each axis).
    /// Errors name the pulleys whose span cannot be laid (no tangent line, or one that
    /// touches the departing pulley more than `max_offset` [m] off its middle plane).
    pub fn new(circles: &[SpaceCircle], max_offset: &[f64]) -> Result<Self, String> {
        let n = circles.len();
        // spans[i]: from pulley i to pulley i+1
        let mut spans = Vec::with_capacity(n);
        for i in 0..n {
            let j = (i + 1) % n;
            let (phi, foot, u, miss) = span(&circles[i], &circles[j]).ok_or_else(|| {
                format!(
                    "no belt span from pulley{} to pulley{} (a line arriving tangentially in pulley{}'s plane and touching pulley{}'s pitch cylinder): check pulley.center, axis, radius, tilt, skew and offset_z",
                    i + 1,
                    j + 1,
                    j + 1,
                    i + 1
                )
            })?;
            if miss > max_offset[i] {
                return Err(format!(
                    "the span from pulley{} to pulley{} misses pulley{}'s pitch circle by {:.2} mm (at most {:.2} mm, a quarter of the rim's free play (pulley.width − belt.width)/2): place the pulleys (pulley.center, axis, radius, width, tilt, skew, offset_z; belt.thickness, width) so that a line arriving tangentially in pulley{}'s plane touches pulley{}'s pitch circle (quarter twist: pulley 2's plane tangent to pulley 1's pitch cylinder and its pitch circle touching pulley 1's plane)",
                    i + 1,
                    j + 1,
                    i + 1,
                    1e3 * miss,
                    1e3 * max_offset[i],
                    j + 1,
                    i + 1
                ));
            }
            spans.push((phi, foot, u));
        }
        let mut pieces = Vec::new();
        let mut length = 0.0;
        for i in 0..n {
            let prev = (i + n - 1) % n;
            let c = &circles[i];
            // arc on pulley i: from the arrival of the span prev → i to the departure of
            // span i → i+1
            let phi0 = spans[prev].0;
            let phi1 = c.angle(&spans[i].1);
            let wrap = (phi1 - phi0).rem_euclid(std::f64::consts::TAU);
            let u1 = spans[i].2;
            let arc_len = ((c.radius * wrap).powi(2) + u1 * u1).sqrt();
            pieces.push((
                arc_len,
                Piece::Arc {
                    k: i,
                    phi0,
                    wrap,
                    u1,
                },
            ));
            length += arc_len;
            let j = (i + 1) % n;
            let p0 = spans[i].1;
            let p1 = circles[j].at(spans[i].0).0;
            let d = (p1 - p0).normalize();
            let w0 = normal_part(&c.axis, &d);
            let w1 = normal_part(&circles[j].axis, &d);
            let twist = w0.cross(&w1).dot(&d).atan2(w0.dot(&w1));
            let l = (p1 - p0).norm();
            pieces.push((l, Piece::Line { p0, p1, w0, twist }));
            length += l;
        }
        Ok(Self {
            circles: circles.to_vec(),
            start: pieces[0].0,
            pieces,
            length,
        })
    }

    /// The point at arc length `s` [m] from the departure of span 1 (pulley 1 to 2), the
    /// start of the planar loop's arc length: a coplanar drive is mounted at the same points
    /// by either path, so a drive turned in space (mounted by this path) has the nodes of the
    /// drive along z (mounted in the plane), turned.
    pub fn at(&self, s: f64) -> PathPoint {
        self.at_from_first_arc(s + self.start)
    }

    /// The point at arc length `s` [m] from the start of the arc on pulley 1 (the arrival of
    /// the last span).
    fn at_from_first_arc(&self, s: f64) -> PathPoint {
        let mut s = s.rem_euclid(self.length);
        for (l, piece) in &self.pieces {
            if s > *l {
                s -= l;
                continue;
            }
            let f = if *l > 0.0 { s / l } else { 0.0 };
            return match *piece {
                Piece::Arc { k, phi0, wrap, u1 } => {
                    let c = &self.circles[k];
                    let (p, tc) = c.at(phi0 + f * wrap);
                    let t = (c.radius * wrap * tc + u1 * c.axis).normalize();
                    PathPoint {
                        r: p + f * u1 * c.axis,
                        t,
                        w: normal_part(&c.axis, &t),
                        pulley: Some(k),
                    }
                }
                Piece::Line { p0, p1, w0, twist } => {
                    let t = (p1 - p0).normalize();
                    let rot = Rotation3::from_axis_angle(&Unit::new_unchecked(t), f * twist);
                    PathPoint {
                        r: p0 + f * (p1 - p0),
                        t,
                        w: rot * w0,
                        pulley: None,
                    }
                }
            };
        }
        // rounding at the very end of the loop: its start
        self.at_from_first_arc(0.0)
    }

    /// The middle points of the spans, span `i` from pulley `i+1` to the next [m].
    pub fn span_middles(&self) -> Vec<Vector3<f64>> {
        self.pieces
            .iter()
            .filter_map(|(_, p)| match p {
                Piece::Line { p0, p1, .. } => Some(0.5 * (p0 + p1)),
                Piece::Arc { .. } => None,
            })
            .collect()
    }

    /// Twist of each span [rad] (the turn of the width direction along it).
    pub fn span_twists(&self) -> Vec<f64> {
        self.pieces
            .iter()
            .filter_map(|(_, p)| match p {
                Piece::Line { twist, .. } => Some(*twist),
                Piece::Arc { .. } => None,
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two coplanar pulleys (axes z): the path is the planar open-belt loop, its length
    /// `π (R1 + R2) + 2 √(D² − (R2 − R1)²) + 2 (R2 − R1) asin((R2 − R1)/D)` (open belt
    /// length, e.g. Shigley's Mechanical Engineering Design, §17-1), spans without twist.
    #[test]
    fn coplanar_pulleys_give_the_open_belt_length() {
        let (r1, r2, d) = (0.082, 0.122, 0.5);
        let c = [
            SpaceCircle {
                center: Vector3::zeros(),
                axis: Vector3::z(),
                radius: r1,
            },
            SpaceCircle {
                center: Vector3::new(d, 0.0, 0.0),
                axis: Vector3::z(),
                radius: r2,
            },
        ];
        let p = SpacePath::new(&c, &[1e-6, 1e-6]).unwrap();
        let dr: f64 = r2 - r1;
        let exact = std::f64::consts::PI * (r1 + r2)
            + 2.0 * (d * d - dr * dr).sqrt()
            + 2.0 * dr * (dr / d).asin();
        assert!((p.length - exact).abs() < 1e-9, "{} vs {exact}", p.length);
        assert!(p.span_twists().iter().all(|t| t.abs() < 1e-9));
    }

    /// Quarter twist: pulley 1 about z at the origin, pulley 2 about −x at (R1, D, R2) (its
    /// plane tangent to pulley 1's pitch cylinder, its pitch circle touching pulley 1's
    /// plane): both spans leave their pulley in its middle plane and each turns the belt's
    /// width by a quarter turn.
    #[test]
    fn quarter_twist_spans_leave_in_the_middle_planes_and_twist_a_quarter_turn() {
        let (r1, r2, d) = (0.082, 0.082, 0.6);
        let c = [
            SpaceCircle {
                center: Vector3::zeros(),
                axis: Vector3::z(),
                radius: r1,
            },
            SpaceCircle {
                center: Vector3::new(r1, d, r2),
                axis: -Vector3::x(),
                radius: r2,
            },
        ];
        let p = SpacePath::new(&c, &[1e-9, 1e-9]).unwrap();
        for tw in p.span_twists() {
            assert!(
                (tw.abs() - std::f64::consts::FRAC_PI_2).abs() < 1e-9,
                "twist {tw}"
            );
        }
        // continuity: consecutive points are one step apart
        let n = 2000;
        let h = p.length / n as f64;
        for k in 0..n {
            let (a, b) = (p.at(k as f64 * h), p.at((k + 1) as f64 * h));
            assert!((b.r - a.r).norm() <= h * (1.0 + 1e-9) + 1e-12, "gap at {k}");
            assert!(a.w.dot(&a.t).abs() < 1e-9);
        }
    }
}
