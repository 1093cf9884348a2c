//! Semi-Lagrangian transport of the friction history for contact points fixed in the mesh of an
//! axially moving (ALE) belt (design note "ale", prototype `scripts/ale_prototype.py`, issue 12
//! item 2).
//!
//! The mesh coordinate `x` of the ALE belt is the reference arc length shifted by the belt travel
//! (`x = X + s`, `v = ṡ`); its contact points stand still in the mesh, `m` of them equally spaced
//! by `w` round the closed loop (point `j` at `x_j = x_0 + j w`). The bristle deflection belongs
//! to the material: the material at `x_j` now sat at `x_j − h v` at the last accepted step. Its
//! history for [`circle_friction::evaluate`](super::circle_friction::evaluate) is
//! * `z`: linearly interpolated between the committed deflections of the two points around
//!   `x_j − h v` (each taken as 0 unless it was in contact with the same pulley);
//! * `f`: the committed friction force per length, interpolated the same way (the material's
//!   last friction, which the trapezoidal friction work `w (f_n + f)/2 Δs` reads);
//! * `dir`: `r_n(x_j − h v) − c` with the committed mesh coordinates `q_n`;
//!   for an upstream position off the pulley (material entering from the span) turned back by
//!   `d/R − atan(d/R)`, so that `R Δφ` is the path along the span's line and the arc (`d` its
//!   distance to the tangent point, at most the travel `|h v r'|`);
//! * `theta`: the pulley's committed angle;
//!
//! and [`evaluate`](super::circle_friction::evaluate) is called with the material velocity
//! `S q̇ + v r'` as the point's velocity. The history depends on `v` through the upstream shift;
//! [`TransportedHistory::dz_trial_dv`] gives the rate of the trial deflection `z + Δs` in `v`,
//! and [`history_rate`] turns it into the contact's `∂(F_x, F_y, τ)/∂v` from the kernel's own
//! tangent (`θ` enters the kernel only through `Δs = ρ Δφ − R Δθ`, so
//! `∂/∂(z + Δs) = −∂/∂θ / R`).

use super::circle_friction::{Circle, PointContact, PointHistory};
use nalgebra::{Vector2, Vector3};

/// Where the material at a mesh point was at the last step, as an interpolation between two
/// points of the loop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Upstream {
    /// First point (at or before the upstream position).
    pub j0: usize,
    /// Next point (round the loop).
    pub j1: usize,
    /// Interpolation weight of `j1` in `[0, 1)`.
    pub alpha: f64,
    /// Distance of the upstream position after point `j0` [m] (`alpha · w`): with `x_{j0}`, the
    /// mesh position where the caller evaluates the committed field.
    pub offset: f64,
}

/// The upstream position of point `j` of `m` points spaced by `w` [m] round the loop, for the
/// mesh shift `shift = h v` [m] over the step (positive: the material moves towards larger `x`).
pub fn upstream(j: usize, m: usize, w: f64, shift: f64) -> Upstream {
    let a = (j as f64 - shift / w).rem_euclid(m as f64);
    let base = a.floor();
    let alpha = a - base;
    // rem_euclid can round up to m itself
    let j0 = (base as usize) % m;
    Upstream {
        j0,
        j1: (j0 + 1) % m,
        alpha,
        offset: alpha * w,
    }
}

/// The history of one point against one pulley, transported from upstream.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransportedHistory {
    /// History to pass to [`evaluate`](super::circle_friction::evaluate).
    pub hist: PointHistory,
    /// `∂z/∂v` [s] of the interpolated deflection.
    pub dz_dv: f64,
    /// `∂φ_n/∂v` [rad s/m] of the polar angle of the upstream point's committed direction.
    pub dphi_dv: f64,
}

impl TransportedHistory {
    /// `∂(z + Δs)/∂v` [s] for a point at distance `rho` [m] from the pulley centre
    /// (`Δs = ρ (φ − φ_n) − R Δθ`).
    pub fn dz_trial_dv(&self, rho: f64) -> f64 {
        self.dz_dv - rho * self.dphi_dv
    }
}

/// The transported history of a point: `up` from [`upstream`] with the shift `h v`, `committed`
/// the committed `(z, f)` (bristle deflection [m], friction force per length [N/m]) of points
/// `up.j0` and `up.j1` against this pulley (0 for a point that was not in contact with it),
/// `r_up` and `rp_up` the committed position [m] and slope of the
/// mesh at the upstream position, `theta_n` the pulley's committed angle [rad], `h` [s] the step,
/// `shift` the mesh shift `h v` [m] of [`upstream`] and `w` [m] the spacing of the points.
#[allow(clippy::too_many_arguments)]
pub fn transported_history(
    up: &Upstream,
    committed: ((f64, f64), (f64, f64)),
    r_up: Vector2<f64>,
    rp_up: Vector2<f64>,
    circle: &Circle,
    theta_n: f64,
    h: f64,
    shift: f64,
    w: f64,
) -> TransportedHistory {
    let mut dir = r_up - circle.center;
    let ((z0, f0), (z1, f1)) = committed;
    let z_up = (1.0 - up.alpha) * z0 + up.alpha * z1;
    let f_up = (1.0 - up.alpha) * f0 + up.alpha * f1;
    // a = j − h v / w: ∂z/∂v = (z1 − z0) ∂α/∂v = −(z1 − z0) h / w
    let dz_dv = -(z1 - z0) * h / w;
    // ∂dir/∂v = −h r'_n; ∂φ/∂dir = (−dir_y, dir_x)/|dir|²
    let ddir = -h * rp_up;
    let mut dphi_dv = (dir.x * ddir.y - dir.y * ddir.x) / dir.norm_squared();
    // Upstream off the pulley (on the span's straight line, entering): the material travels
    // the distance `d` to the tangent point and then wraps, so its path round the pulley is
    // `R (φ − φ_n) + d − R atan(d/R)`, not `R (φ − φ_n)`: the history's angle is moved back
    // by `d/R − atan(d/R)` (`d` at most the travel `|h v r'|`). Without it an entering point
    // starts with the spurious deflection `d − R atan(d/R) ≈ d³/(3 R²)`: at 5 ms steps of the
    // 60 rad/s drive (d ≈ 24 mm, R = 0.12 m) 0.3 mm, which saturated the entry's friction.
    let big_r = circle.radius;
    let dist2 = dir.norm_squared();
    let travel = shift.abs() * rp_up.norm();
    // direction of the material's travel in the polar angle
    let turn = shift.signum() * (dir.x * rp_up.y - dir.y * rp_up.x).signum();
    // (only near the tangent point: farther up the line than the travel the material cannot
    // reach the pulley within the step; 4 travels keep the history continuous wherever the
    // point may touch, without a square root per point and pulley elsewhere)
    let r2 = big_r * big_r;
    if dist2 > r2 && dist2 < r2 + 16.0 * travel * travel && turn != 0.0 {
        let d_line = (dist2 - big_r * big_r).sqrt();
        let (d, dd_dv) = if d_line < travel {
            (d_line, dir.dot(&ddir) / d_line)
        } else {
            (travel, h * shift.signum() * rp_up.norm())
        };
        let u = d / big_r;
        let back = -turn * (u - u.atan());
        let (sn, cs) = back.sin_cos();
        dir = Vector2::new(cs * dir.x - sn * dir.y, sn * dir.x + cs * dir.y);
        // ∂(u − atan u)/∂d = u² / (R (1 + u²))
        dphi_dv -= turn * u * u / (big_r * (1.0 + u * u)) * dd_dv;
    }
    TransportedHistory {
        hist: PointHistory {
            dir,
            theta: theta_n,
            z: z_up,
            f: f_up,
        },
        dz_dv,
        dphi_dv,
    }
}

/// `∂(F_x, F_y, τ)/∂v` of a contact evaluated with a transported history, through the history
/// alone (the velocity's part, `c · (r'_x, r'_y, 0)`, is the caller's).
pub fn history_rate(
    contact: &PointContact,
    circle: &Circle,
    tr: &TransportedHistory,
) -> Vector3<f64> {
    let rho = circle.radius + contact.gap;
    let d_trial = tr.dz_trial_dv(rho);
    contact.k.column(2) * (-d_trial / circle.radius)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::circle_friction::{PointState, evaluate};
    use crate::contact::test_laws::belt;

    /// Spacing, pulley and the committed loop of the tests: the mesh wraps the pulley of
    /// radius 0.1 m at radius `R − 2e−5` (in contact), points every 5 mm.
    const W: f64 = 5e-3;
    const M: usize = 100;
    const RADIUS: f64 = 0.1;

    fn circle() -> Circle {
        Circle {
            center: Vector2::new(0.3, -0.1),
            radius: RADIUS,
        }
    }

    /// Committed mesh (position and slope per unit mesh length) at mesh position `x`.
    fn committed(x: f64) -> (Vector2<f64>, Vector2<f64>) {
        let rho = RADIUS - 2e-5;
        let a = x / RADIUS;
        (
            circle().center + rho * Vector2::new(a.cos(), a.sin()),
            (rho / RADIUS) * Vector2::new(-a.sin(), a.cos()),
        )
    }

    /// Committed deflection of point `j` [m].
    fn z_of(j: usize) -> f64 {
        2e-6 * (0.3 * j as f64).sin() + 1e-6
    }

    /// Committed friction force per length of point `j` [N/m] (of the sign of its deflection).
    fn f_of(j: usize) -> f64 {
        1e4 * z_of(j)
    }

    fn history(j: usize, h: f64, v: f64) -> TransportedHistory {
        let up = upstream(j, M, W, h * v);
        let (r, rp) = committed(up.j0 as f64 * W + up.offset);
        let committed = |j: usize| (z_of(j), f_of(j));
        transported_history(
            &up,
            (committed(up.j0), committed(up.j1)),
            r,
            rp,
            &circle(),
            0.4,
            h,
            h * v,
            W,
        )
    }

    /// No shift: the point's own history; a shift of whole spacings: the history of the point
    /// as many places upstream (wrapping round the loop, both directions); half a spacing: the
    /// mean of the two deflections (and of the two friction forces, which the trapezoidal
    /// friction work reads) and the committed mesh half way.
    #[test]
    fn upstream_interpolation() {
        let h = 1e-3;
        let t = history(7, h, 0.0);
        assert_eq!(t.hist.z, z_of(7));
        assert_eq!(t.hist.f, f_of(7));
        assert!((t.hist.dir - (committed(7.0 * W).0 - circle().center)).norm() < 1e-15);
        assert_eq!(upstream(2, M, W, 3.0 * W).j0, M - 1);
        assert_eq!(upstream(2, M, W, 3.0 * W).alpha, 0.0);
        assert_eq!(upstream(M - 1, M, W, -2.0 * W).j0, 1);
        let up = upstream(10, M, W, 2.5 * W);
        assert_eq!((up.j0, up.j1), (7, 8));
        assert!((up.alpha - 0.5).abs() < 1e-12);
        let t = history(10, h, 2.5 * W / h);
        assert!((t.hist.z - 0.5 * (z_of(7) + z_of(8))).abs() < 1e-18);
        assert!((t.hist.f - 0.5 * (f_of(7) + f_of(8))).abs() < 1e-12);
        assert!((t.hist.dir - (committed(7.5 * W).0 - circle().center)).norm() < 1e-14);
        // a shift below round-off of the loop length stays at the point itself
        let tiny = upstream(0, M, W, 1e-18);
        assert_eq!((tiny.j0, tiny.alpha), (0, 0.0));
        assert_eq!(upstream(0, M, W, 1e-9 * W).j0, M - 1);
    }

    /// The contact force and torque with the transported history, as functions of `v` through
    /// the history alone (fixed point state), against central differences, in stick and in the
    /// stick/slip blend (the derivative is not zero), and in Coulomb sliding (it is: the force is
    /// `μ p`, which the history does not touch).
    #[test]
    fn history_rate_matches_finite_differences() {
        let h = 1e-3;
        let law = belt();
        let c = circle();
        for (j, v, slip_speed) in [
            (20, 3.7, 0.0),
            (31, 11.3, 0.02),
            (40, -6.1, 0.135),
            (45, 6.1, 0.5),
        ] {
            let x = j as f64 * W;
            let a = x / RADIUS;
            let n = Vector2::new(a.cos(), a.sin());
            let t = Vector2::new(-n.y, n.x);
            let state = PointState {
                r: c.center + (RADIUS - 3e-5) * n,
                v: (v + slip_speed) * t,
                theta: 0.4 + h * v / RADIUS,
                omega: v / RADIUS,
            };
            let eval = |v: f64| {
                let tr = history(j, h, v);
                let pc = evaluate(&law, &c, W, &state, &tr.hist).expect("in contact");
                (pc, tr)
            };
            let (pc, tr) = eval(v);
            let analytic = history_rate(&pc, &c, &tr);
            let dv = 1e-4;
            let (p1, _) = eval(v + dv);
            let (p0, _) = eval(v - dv);
            let diff = |p: &PointContact| Vector3::new(p.force.x, p.force.y, p.torque);
            let fd = (diff(&p1) - diff(&p0)) / (2.0 * dv);
            if slip_speed >= 0.5 {
                assert!(pc.slipping && analytic == Vector3::zeros() && fd.norm() < 1e-9);
                continue;
            }
            assert!(analytic.norm() > 1.0, "j {j}: {analytic}");
            // the third case lies in the stick/slip blend (|f| between 0.95 and 1 of μ p)
            let ratio = (pc.friction / (law.mu * pc.pressure)).abs();
            assert_eq!(ratio > 0.95, slip_speed > 0.1, "j {j}: |f|/(μ p) = {ratio}");
            assert!(ratio < 1.0);
            assert!(
                (analytic - fd).norm() <= 1e-6 * fd.norm(),
                "j {j}, v {v}, slipping {}: {analytic} vs {fd}",
                pc.slipping
            );
        }
    }

    /// A point whose material came off the span's straight line onto the pulley within the
    /// step: its history's angle is the tangent point's less `d/R` (`d` the distance the
    /// material still had to the tangent point), so that `R (φ − φ_n)` is the path the
    /// material travelled (the polar angle alone, `−atan(d/R)`, shortens it by
    /// `d − R atan(d/R)`); and `∂φ_n/∂v` against central differences.
    #[test]
    fn entering_point_history_unwraps_the_span() {
        let c = circle();
        // committed loop: the straight line `x < 0` up to the tangent point `c + (R, 0)`, then
        // the arc; the material moves towards larger `x` (counterclockwise round `c`)
        let field = |x: f64| {
            if x < 0.0 {
                (c.center + Vector2::new(RADIUS, x), Vector2::new(0.0, 1.0))
            } else {
                let a = x / RADIUS;
                (
                    c.center + RADIUS * Vector2::new(a.cos(), a.sin()),
                    Vector2::new(-a.sin(), a.cos()),
                )
            }
        };
        let (h, x_j) = (5e-3, 8e-3);
        let angle = |v: f64| {
            let (r, rp) = field(x_j - h * v);
            let up = upstream(0, M, W, 0.0);
            let tr =
                transported_history(&up, ((0.0, 0.0), (0.0, 0.0)), r, rp, &c, 0.0, h, h * v, W);
            (tr.hist.dir.y.atan2(tr.hist.dir.x), tr.dphi_dv)
        };
        for v in [4.0, 6.0] {
            let d = h * v - x_j;
            let (phi, dphi_dv) = angle(v);
            assert!(
                (phi + d / RADIUS).abs() < 1e-12,
                "v {v}: {phi} against {}",
                -d / RADIUS
            );
            assert!((phi + (d / RADIUS).atan()).abs() > 1e-3 * d / RADIUS);
            let dv = 1e-5;
            let fd = (angle(v + dv).0 - angle(v - dv).0) / (2.0 * dv);
            assert!(
                (dphi_dv - fd).abs() < 1e-7 * fd.abs(),
                "{dphi_dv} against {fd}"
            );
        }
        // on the arc (in contact): the polar angle, unchanged
        let (r, rp) = field(1e-3);
        let tr = transported_history(
            &upstream(0, M, W, 0.0),
            ((0.0, 0.0), (0.0, 0.0)),
            r,
            rp,
            &c,
            0.0,
            h,
            0.05,
            W,
        );
        assert_eq!(tr.hist.dir, r - c.center);
    }
}
