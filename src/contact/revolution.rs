//! Rigid parts of revolution about the z axis seen from the meridian plane `(r, z)` of an
//! axisymmetric membrane: the air spring's piston (a contour `r_p(z)` up to its top) and its
//! top plate (a plane `z = z_plate` the bellows stays below). Frictionless penalty contact with
//! the smoothed normal law of the belt ([`smoothed_penalty`]), through the shared
//! [`super::ContactPointSet`]; each obstacle has one own coordinate, its axial position, so the
//! force on it appears in the residual of that coordinate (the top plate's is the prescribed
//! `top.z`: its reaction is part of the spring force).
//!
//! A point of the membrane stands for the reference area `w` [m²]; the law's `k_n` is then a
//! pressure per penetration [N/m³] (`shared/reference/air-spring-physics.md` §1.7).
//!
//! Friction (the meridian plane, [`SlideHistory`]): the elasto-plastic bristle law of the belt
//! ([`super::circle_friction`], Wriggers, Computational Contact Mechanics, 2nd ed., §5.2) in
//! the obstacle's tangent `t = (−n_z, n_r)` (up the piston contour; outward on the plate). The
//! slip over a step is measured relative to the obstacle, `Δs = t · (ρ − ρ_old)` with
//! `ρ = (r, z − z₀)`, so a point that lies on the piston and stays there (a rolling lobe lays
//! the sleeve down without sliding) makes no friction force however the plate moves: only
//! sliding does. Trial stress `f* = k_t (z_old + Δs) + d_t ṡ` (`z` the bristle deflection,
//! `ṡ = t · (ṙ, ż − ż₀)`), stick while `|f*| ≤ μ p`, else Coulomb sliding `f = μ p sign f*`,
//! blended C¹ ([`super::circle_friction::stick_slip`]); force on the point `w (p n − f t)`.
//! The hoop direction carries no slip by symmetry.

use super::circle_friction::{ContactLaw, bristle_factor, smoothed_penalty, stick_slip};
use super::obstacle::{ContactHistory, Obstacle, ObstacleContact, PointMotion};
use crate::snapshot::{SnapshotError, StateReader, StateWriter};
use nalgebra::{Matrix3, Matrix4, SVector, Vector2, Vector3};

/// The history of a frictionless contact: nothing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NoHistory;

impl ContactHistory for NoHistory {
    fn save(&self, _w: &mut StateWriter) {}

    fn restore(_r: &mut StateReader) -> Result<Self, SnapshotError> {
        Ok(NoHistory)
    }
}

/// An obstacle of revolution in the meridian plane.
#[derive(Clone, Debug, PartialEq)]
pub enum AxisymObstacle {
    /// The piston: the solid `r < r_p(z − z₀)` for `z − z₀` up to the last contour point (its
    /// top; above it no contact), with `z₀` the obstacle coordinate (the piston base height).
    /// Contour points `(r, z)` relative to the base, `z` increasing; below the first point the
    /// contour continues vertically.
    Piston {
        /// Contour points `[r, z]` [m].
        contour: Vec<[f64; 2]>,
    },
    /// The top plate: the solid `z > z₀` for `r` up to `radius` [m] (beyond it no contact),
    /// `z₀` the obstacle coordinate.
    Plate {
        /// Outer radius of the plate [m].
        radius: f64,
    },
    /// The bottom plate of a convoluted spring: the solid `z < z₀` for `r` up to `radius` [m]
    /// (beyond it no contact), `z₀` the obstacle coordinate.
    Floor {
        /// Outer radius of the plate [m].
        radius: f64,
    },
}

/// Committed friction history of a (meridian point, obstacle) pair.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SlideHistory {
    /// The point relative to the obstacle, `(r, z − z₀)`, at the last commit [m].
    pub rel: [f64; 2],
    /// Bristle deflection (elastic part, [`bristle_factor`]) [m].
    pub z: f64,
    /// Friction stress `f` [N/m²] (for the work over the next step).
    pub f: f64,
    /// Whether `rel` is recorded: before the first commit (the mounting and the design
    /// state are solved frictionless) there is no friction.
    pub valid: bool,
}

impl ContactHistory for SlideHistory {
    fn save(&self, w: &mut StateWriter) {
        for x in [self.rel[0], self.rel[1], self.z, self.f] {
            w.f64(x);
        }
        w.bool(self.valid);
    }

    fn restore(r: &mut StateReader) -> Result<Self, SnapshotError> {
        Ok(Self {
            rel: [r.f64()?, r.f64()?],
            z: r.f64()?,
            f: r.f64()?,
            valid: r.bool()?,
        })
    }
}

/// An active contact point: force on the point and its derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisymContact {
    /// Force on the point `w (p n − f t)` [N] (`n` the outward normal of the obstacle, `t` its
    /// tangent, `f` the friction stress).
    pub force: Vector2<f64>,
    /// Penetration [m].
    pub penetration: f64,
    /// `∂δ/∂(r, z, z₀)`.
    grad: [f64; 3],
    /// Normal `n`.
    normal: Vector2<f64>,
    /// `∂p/∂δ` and `∂p/∂δ̇` times `w`.
    dp: [f64; 2],
    /// Elastic energy [J].
    energy: f64,
    /// Damping power [W].
    power: f64,
    /// Friction stress `f` [N/m²] along `−t` on the point.
    pub friction: f64,
    /// Slip over the step `Δs` [m].
    pub slip_increment: f64,
    /// Bristle deflection (elastic part, [`bristle_factor`]) [m].
    z: f64,
    /// Whether the point slides.
    slipping: bool,
    /// `(t_r, t_z, −t_z)`: `∂Δs/∂(r, z, z₀)` and the friction's direction in the force vector.
    tf: [f64; 3],
    /// `w ∂f/∂(r, z, z₀)` and `w ∂f/∂(ṙ, ż, ż₀)`.
    df: [[f64; 3]; 2],
}

impl AxisymObstacle {
    /// Penetration `δ` (positive inside), normal and `∂δ/∂(r, z, z₀)` of a point `(r, z)` with
    /// the obstacle at `z0`; `None` where the obstacle cannot be touched.
    #[inline(always)]
    fn gap(&self, r: f64, z: f64, z0: f64) -> Option<(f64, Vector2<f64>, [f64; 3])> {
        match self {
            AxisymObstacle::Piston { contour } => {
                let zr = z - z0;
                let last = contour.last()?;
                if zr > last[1] {
                    return None;
                }
                // the segment containing zr (vertical extension below the first point)
                let mut rp = contour[0][0];
                let mut slope = 0.0;
                for s in contour.windows(2) {
                    let (a, b) = (s[0], s[1]);
                    if zr >= a[1] && zr <= b[1] && b[1] > a[1] {
                        slope = (b[0] - a[0]) / (b[1] - a[1]);
                        rp = a[0] + slope * (zr - a[1]);
                        break;
                    }
                }
                // a cylindrical segment (the shipped pistons): c = 1 exactly, without the root
                let c = if slope == 0.0 {
                    1.0
                } else {
                    1.0 / (1.0 + slope * slope).sqrt()
                };
                let delta = (rp - r) * c;
                let n = Vector2::new(c, -slope * c);
                Some((delta, n, [-c, slope * c, -slope * c]))
            }
            AxisymObstacle::Plate { radius } => {
                if r > *radius {
                    return None;
                }
                Some((z - z0, Vector2::new(0.0, -1.0), [0.0, 1.0, -1.0]))
            }
            AxisymObstacle::Floor { radius } => {
                if r > *radius {
                    return None;
                }
                Some((z0 - z, Vector2::new(0.0, 1.0), [0.0, -1.0, 1.0]))
            }
        }
    }
}

impl ObstacleContact<2> for AxisymContact {
    fn force(&self) -> SVector<f64, 2> {
        self.force
    }

    /// Force on the obstacle along the axis: `−F_z`.
    fn generalized_force(&self, _l: usize) -> f64 {
        -self.force.y
    }

    fn iteration_block(&self, ks: f64, kd: f64, out: &mut [f64]) {
        // F = (w p n, −w p n_z) over x = (r, z, z₀); ∂p/∂x = p_δ ∂δ/∂x (+ p_δ̇ for rates)
        // friction: −w f tf, ∂(w f)/∂x in `df`
        let nf = [self.normal.x, self.normal.y, -self.normal.y];
        for j in 0..3 {
            let dfj = ks * self.df[0][j] + kd * self.df[1][j];
            for i in 0..3 {
                out[i + 3 * j] =
                    nf[i] * self.grad[j] * (ks * self.dp[0] + kd * self.dp[1]) - self.tf[i] * dfj;
            }
        }
    }

    fn slipping(&self) -> bool {
        self.slipping
    }

    fn normal_energy(&self) -> f64 {
        self.energy
    }

    fn dissipation(&self) -> f64 {
        self.power
    }
}

impl Obstacle<2> for AxisymObstacle {
    const N_COORDS: usize = 1;
    type History = SlideHistory;
    type Contact = AxisymContact;

    /// The piston: a segment with both ends outside the largest contour radius cannot touch
    /// it (its points are convex combinations of the ends, and the piston's radius is at most
    /// that largest radius at every height): skipped without evaluating its points, which
    /// would all be out of contact. The plate (whose height is a coordinate, not known here):
    /// every segment is checked.
    fn near(&self, a: &SVector<f64, 2>, b: &SVector<f64, 2>) -> bool {
        match self {
            AxisymObstacle::Piston { contour } => {
                let r_max = contour
                    .iter()
                    .map(|p| p[0])
                    .fold(f64::NEG_INFINITY, f64::max);
                let r = a.x.min(b.x);
                r <= r_max || r.is_nan()
            }
            AxisymObstacle::Plate { .. } | AxisymObstacle::Floor { .. } => true,
        }
    }

    /// [`Obstacle::near`], and for the plate (the floor) at height `x[0]`: a segment with
    /// both ends below (above) it cannot penetrate it (its points are convex combinations of
    /// the ends and the penetration is `z − x[0]` (`x[0] − z`)).
    #[inline]
    fn near_at(&self, a: &SVector<f64, 2>, b: &SVector<f64, 2>, x: &[f64]) -> bool {
        use std::cmp::Ordering::{Equal, Greater, Less};
        match self {
            AxisymObstacle::Plate { .. } => {
                !matches!(a.y.max(b.y).partial_cmp(&x[0]), Some(Less | Equal))
            }
            AxisymObstacle::Floor { .. } => {
                !matches!(a.y.min(b.y).partial_cmp(&x[0]), Some(Greater | Equal))
            }
            AxisymObstacle::Piston { contour } => {
                // above the contour's top (relative to the piston at `x[0]`): out of contact
                let top = contour.last().map_or(f64::INFINITY, |p| p[1]);
                !matches!((a.y.min(b.y) - x[0]).partial_cmp(&top), Some(Greater)) && self.near(a, b)
            }
        }
    }

    /// Inlined into the contact loops: a residual does not compute the energy and power it
    /// does not read (the commit does).
    #[inline(always)]
    fn evaluate(
        &self,
        law: &ContactLaw,
        w: f64,
        p: &PointMotion<2>,
        x: &[f64],
        xd: &[f64],
        hist: &SlideHistory,
    ) -> Option<AxisymContact> {
        let (delta, n, grad) = self.gap(p.r.x, p.r.y, x[0])?;
        if delta <= 0.0 {
            return None;
        }
        let rate = grad[0] * p.v.x + grad[1] * p.v.y + grad[2] * xd[0];
        let (pe, dpe, ramp, dramp, ue) = smoothed_penalty(law, delta);
        let pressure = pe + law.d_n * ramp * rate;
        if pressure <= 0.0 {
            return None;
        }
        let dp = [w * (dpe + law.d_n * dramp * rate), w * law.d_n * ramp];
        let t = Vector2::new(-n.y, n.x);
        let tf = [t.x, t.y, -t.y];
        let (mut friction, mut ds, mut z, mut slipping, mut df) =
            (0.0, 0.0, 0.0, false, [[0.0; 3]; 2]);
        if law.mu > 0.0 && hist.valid {
            ds = t.x * (p.r.x - hist.rel[0]) + t.y * (p.r.y - x[0] - hist.rel[1]);
            let sdot = t.x * p.v.x + t.y * (p.v.y - xd[0]);
            let f_trial = law.k_t * (hist.z + ds) + law.d_t * sdot;
            let cap = law.mu * pressure;
            let xr = f_trial / cap;
            let (ph, dph) = stick_slip(xr.abs(), law.blend);
            let ph = ph.copysign(xr);
            friction = cap * ph;
            slipping = f_trial.abs() >= cap;
            z = if law.k_t > 0.0 {
                bristle_factor(friction.abs(), f_trial.abs()) * (hist.z + ds)
            } else {
                0.0
            };
            // w ∂f = φ' w ∂f* + (φ − x φ') μ w ∂p, ∂f*/∂x = k_t tf, ∂f*/∂ẋ = d_t tf
            let rest = ph - xr * dph;
            for j in 0..3 {
                df[0][j] = dph * w * law.k_t * tf[j] + rest * law.mu * dp[0] * grad[j];
                df[1][j] = dph * w * law.d_t * tf[j] + rest * law.mu * dp[1] * grad[j];
            }
        }
        Some(AxisymContact {
            force: w * pressure * n - (w * friction) * t,
            penetration: delta,
            grad,
            normal: n,
            dp,
            energy: w * ue,
            power: w * law.d_n * ramp * rate * rate,
            friction,
            slip_increment: ds,
            z,
            slipping,
            tf,
            df,
        })
    }

    fn committed(&self, p: &PointMotion<2>, x: &[f64], c: Option<&AxisymContact>) -> SlideHistory {
        SlideHistory {
            rel: [p.r.x, p.r.y - x[0]],
            z: c.map_or(0.0, |c| c.z),
            f: c.map_or(0.0, |c| c.friction),
            valid: true,
        }
    }

    /// Trapezoidal in the slip: `w (f_old + f)/2 Δs` (the bristle's elastic part included,
    /// of the order of `μ p`²/`k_t` per area).
    fn friction_work(w: f64, h: &SlideHistory, c: &AxisymContact) -> f64 {
        w * 0.5 * (h.f + c.friction) * c.slip_increment
    }

    /// The history is relative to the obstacle already: nothing to shift.
    fn shift_history(_h: &mut SlideHistory, _l: usize, _by: f64) {}
}

/// Committed friction history of a (surface point, piston) pair in space: the bristle is a
/// vector in the tangent plane (the slip has a meridional and a hoop part once the plate moves
/// sideways or tilts).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SlideHistory3 {
    /// The point relative to the obstacle, `(x, y, z − z₀)`, at the last commit [m].
    pub rel: [f64; 3],
    /// Bristle deflection (elastic part, [`bristle_factor`]) [m].
    pub z: [f64; 3],
    /// Friction stress `f` [N/m²].
    pub f: [f64; 3],
    /// Whether `rel` is recorded (no friction before the first commit).
    pub valid: bool,
}

impl ContactHistory for SlideHistory3 {
    fn save(&self, w: &mut StateWriter) {
        for x in self.rel.iter().chain(&self.z).chain(&self.f) {
            w.f64(*x);
        }
        w.bool(self.valid);
    }

    fn restore(r: &mut StateReader) -> Result<Self, SnapshotError> {
        let mut v = [0.0; 9];
        for x in v.iter_mut() {
            *x = r.f64()?;
        }
        Ok(Self {
            rel: [v[0], v[1], v[2]],
            z: [v[3], v[4], v[5]],
            f: [v[6], v[7], v[8]],
            valid: r.bool()?,
        })
    }
}

/// An active contact point in space (the shell level): force on the point and its
/// derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RevolutionContact {
    /// Force on the point `w (p n − f)` [N] (`f` the friction stress in the tangent plane).
    pub force: Vector3<f64>,
    /// Friction stress `f` [N/m²] (on the point: `−w f`).
    pub friction: Vector3<f64>,
    /// Slip over the step `Δs` (in the tangent plane) [m].
    pub slip_increment: Vector3<f64>,
    /// Bristle deflection (elastic part, [`bristle_factor`]) [m].
    bristle: Vector3<f64>,
    /// Whether the point slides.
    slipping: bool,
    /// `∂F_f/∂X` and `∂F_f/∂Ẋ` of the friction part `F_f = (−w f, w f_z)` of the force
    /// vector over `X = (x, y, z, z₀)`.
    dfric: [Matrix4<f64>; 2],
    /// Penetration [m].
    pub penetration: f64,
    /// `∂δ/∂(x, y, z, z₀)`.
    grad: [f64; 4],
    /// Normal `n`.
    normal: Vector3<f64>,
    /// `w p ∂n/∂x` (the normal turns with the point about the axis).
    dn: Matrix3<f64>,
    /// `w ∂p/∂(x, y)` through the penetration rate at fixed velocity (the radial direction of
    /// the rate turns with the point).
    dp_turn: [f64; 2],
    /// `∂p/∂δ` and `∂p/∂δ̇` times `w`.
    dp: [f64; 2],
    /// Elastic energy [J].
    energy: f64,
    /// Damping power [W].
    power: f64,
}

impl ObstacleContact<3> for RevolutionContact {
    fn force(&self) -> SVector<f64, 3> {
        self.force
    }

    /// Force on the obstacle along the axis: `−F_z`.
    fn generalized_force(&self, _l: usize) -> f64 {
        -self.force.z
    }

    fn iteration_block(&self, ks: f64, kd: f64, out: &mut [f64]) {
        // F = (w p n, −w p n_z) over x = (x, y, z, z₀): ∂F/∂x = n' ∇δᵀ (p_δ, p_δ̇) + w p ∂n/∂x
        let nf = [self.normal.x, self.normal.y, self.normal.z, -self.normal.z];
        let s = ks * self.dp[0] + kd * self.dp[1];
        for j in 0..4 {
            for i in 0..4 {
                out[i + 4 * j] = nf[i] * self.grad[j] * s;
            }
        }
        for j in 0..3 {
            for i in 0..3 {
                out[i + 4 * j] += ks * self.dn[(i, j)];
            }
        }
        for j in 0..2 {
            for i in 0..4 {
                out[i + 4 * j] += ks * nf[i] * self.dp_turn[j];
            }
        }
        for j in 0..4 {
            for i in 0..4 {
                out[i + 4 * j] += ks * self.dfric[0][(i, j)] + kd * self.dfric[1][(i, j)];
            }
        }
    }

    fn slipping(&self) -> bool {
        self.slipping
    }

    fn normal_energy(&self) -> f64 {
        self.energy
    }

    fn dissipation(&self) -> f64 {
        self.power
    }
}

/// The same obstacles seen in space (the axis is z): a point `(x, y, z)` is at radius
/// `r = √(x² + y²)` of its meridian plane, and the normal `(n_r e_r, n_z)` turns with it about
/// the axis. Only the piston is defined in space: the plate of a shell spring tilts, which its
/// axial coordinate cannot say (the shell level uses [`super::plate3d::Plate3d`] for it).
impl Obstacle<3> for AxisymObstacle {
    const N_COORDS: usize = 1;
    type History = SlideHistory3;
    type Contact = RevolutionContact;

    fn near(&self, _a: &SVector<f64, 3>, _b: &SVector<f64, 3>) -> bool {
        matches!(self, AxisymObstacle::Piston { .. })
    }

    fn evaluate(
        &self,
        law: &ContactLaw,
        w: f64,
        p: &PointMotion<3>,
        x: &[f64],
        xd: &[f64],
        hist: &SlideHistory3,
    ) -> Option<RevolutionContact> {
        if !matches!(self, AxisymObstacle::Piston { .. }) {
            return None;
        }
        let r = p.r.xy().norm();
        if r <= 0.0 {
            return None;
        }
        let (delta, n2, g2) = self.gap(r, p.r.z, x[0])?;
        if delta <= 0.0 {
            return None;
        }
        let er = p.r.xy() / r;
        let grad = [g2[0] * er.x, g2[0] * er.y, g2[1], g2[2]];
        let rate = grad[0] * p.v.x + grad[1] * p.v.y + grad[2] * p.v.z + grad[3] * xd[0];
        let (pe, dpe, ramp, dramp, ue) = smoothed_penalty(law, delta);
        let pressure = pe + law.d_n * ramp * rate;
        if pressure <= 0.0 {
            return None;
        }
        let normal = Vector3::new(n2.x * er.x, n2.x * er.y, n2.y);
        // ∂(n_r e_r)/∂(x, y) = n_r (I − e_r e_rᵀ)/r
        let mut dn = Matrix3::zeros();
        let c = w * pressure * n2.x / r;
        dn[(0, 0)] = c * (1.0 - er.x * er.x);
        dn[(1, 1)] = c * (1.0 - er.y * er.y);
        dn[(0, 1)] = -c * er.x * er.y;
        dn[(1, 0)] = dn[(0, 1)];
        // ∂(∇δ · v)/∂(x, y) = (∂δ/∂r) (I − e_r e_rᵀ) v_xy / r
        let vt = (p.v.xy() - er * er.dot(&p.v.xy())) * (g2[0] / r);
        let turn = w * law.d_n * ramp;
        let dp = [w * (dpe + law.d_n * dramp * rate), w * law.d_n * ramp];
        let dp_turn = [turn * vt.x, turn * vt.y];
        let fr = if law.mu > 0.0 && hist.valid {
            friction3(
                law, w, pressure, &normal, &dn, &grad, dp, dp_turn, p, x, xd, hist,
            )
        } else {
            Friction3::default()
        };
        Some(RevolutionContact {
            dp_turn,
            force: w * pressure * normal - w * fr.f,
            friction: fr.f,
            slip_increment: fr.ds,
            bristle: fr.bristle,
            slipping: fr.slipping,
            dfric: fr.d,
            penetration: delta,
            grad,
            normal,
            dn,
            dp,
            energy: w * ue,
            power: w * law.d_n * ramp * rate * rate,
        })
    }

    fn committed(
        &self,
        p: &PointMotion<3>,
        x: &[f64],
        c: Option<&RevolutionContact>,
    ) -> SlideHistory3 {
        let (f, z) = c.map_or((Vector3::zeros(), Vector3::zeros()), |c| {
            (c.friction, c.bristle)
        });
        SlideHistory3 {
            rel: [p.r.x, p.r.y, p.r.z - x[0]],
            z: [z.x, z.y, z.z],
            f: [f.x, f.y, f.z],
            valid: true,
        }
    }

    /// Trapezoidal in the slip: `w (f_old + f)/2 · Δs`.
    fn friction_work(w: f64, h: &SlideHistory3, c: &RevolutionContact) -> f64 {
        let f_old = Vector3::from(h.f);
        w * 0.5 * (f_old + c.friction).dot(&c.slip_increment)
    }

    /// The history is relative to the obstacle already: nothing to shift.
    fn shift_history(_h: &mut SlideHistory3, _l: usize, _by: f64) {}
}

/// Friction of a point in space ([`friction3`]).
#[derive(Clone, Copy, Debug, Default)]
struct Friction3 {
    f: Vector3<f64>,
    ds: Vector3<f64>,
    bristle: Vector3<f64>,
    slipping: bool,
    d: [Matrix4<f64>; 2],
}

/// The bristle law in the tangent plane of a point pressed on the piston with pressure `p`
/// [Pa], normal `n` (turning with the point about the axis: `dn = w p ∂n/∂(x, y, z)`): slip
/// `Δs = P (ρ − ρ_old)` with `P = I − n nᵀ` and `ρ = (x, y, z − z₀)`; trial stress
/// `f* = k_t P (z_old + ρ − ρ_old) + d_t P (v − ż₀ e_z)`; `f = μ p φ(|f*|/(μ p)) f*/|f*|`
/// ([`stick_slip`]); and the derivatives of the friction part `(−w f, w f_z)` of the force
/// vector over `X = (x, y, z, z₀)` and its rates:
/// `∂f = [φ' u uᵀ + (μ p φ/|f*|)(I − u uᵀ)] ∂f* + (φ − x φ') u μ ∂p`, `u = f*/|f*|`,
/// `∂(P a)/∂X_j = P ∂a/∂X_j − ∂n_j (n·a) − n (∂n_j·a)`.
#[allow(clippy::too_many_arguments)]
fn friction3(
    law: &ContactLaw,
    w: f64,
    p: f64,
    n: &Vector3<f64>,
    dn: &Matrix3<f64>,
    grad: &[f64; 4],
    dp: [f64; 2],
    dp_turn: [f64; 2],
    pt: &PointMotion<3>,
    x: &[f64],
    xd: &[f64],
    hist: &SlideHistory3,
) -> Friction3 {
    let rel = Vector3::new(pt.r.x, pt.r.y, pt.r.z - x[0]);
    let d = rel - Vector3::from(hist.rel);
    let a = Vector3::from(hist.z) + d;
    let b = Vector3::new(pt.v.x, pt.v.y, pt.v.z - xd[0]);
    let proj = |u: &Vector3<f64>| u - n * n.dot(u);
    let ds = proj(&d);
    let fstar = law.k_t * proj(&a) + law.d_t * proj(&b);
    let cap = law.mu * p;
    let m = fstar.norm();
    // ∂f/∂f* and ∂f/∂p
    let (f, jac, along, slipping) = if m > 0.0 {
        let u = fstar / m;
        let xr = m / cap;
        let (ph, dph) = stick_slip(xr, law.blend);
        let uu = u * u.transpose();
        let jac = dph * uu + (cap * ph / m) * (Matrix3::identity() - uu);
        (cap * ph * u, jac, (ph - xr * dph) * law.mu * u, m >= cap)
    } else {
        (
            Vector3::zeros(),
            Matrix3::identity(),
            Vector3::zeros(),
            false,
        )
    };
    let mut out = Friction3 {
        f,
        ds,
        bristle: if law.k_t > 0.0 {
            proj(&a) * bristle_factor(f.norm(), m)
        } else {
            Vector3::zeros()
        },
        slipping,
        d: [Matrix4::zeros(); 2],
    };
    let e_z = Vector3::z();
    for j in 0..4 {
        let dd = if j < 3 { Vector3::ith(j, 1.0) } else { -e_z };
        let dnj = if j < 3 {
            dn.column(j) / (w * p)
        } else {
            Vector3::zeros()
        };
        let dproj = |u: &Vector3<f64>| -(dnj * n.dot(u) + n * dnj.dot(u));
        let dfs = law.k_t * (proj(&dd) + dproj(&a)) + law.d_t * dproj(&b);
        let dfs_rate = law.d_t * proj(&dd);
        let wdp = dp[0] * grad[j] + if j < 2 { dp_turn[j] } else { 0.0 };
        let wdp_rate = dp[1] * grad[j];
        for (k, (dfsk, wdpk)) in [(dfs, wdp), (dfs_rate, wdp_rate)].into_iter().enumerate() {
            let df = w * (jac * dfsk) + along * wdpk;
            out.d[k][(0, j)] = -df.x;
            out.d[k][(1, j)] = -df.y;
            out.d[k][(2, j)] = -df.z;
            out.d[k][(3, j)] = df.z;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The iteration block of a contact (`ks`: stiffness, `kd`: damping, column-major
    /// `N × N`) against the crate's central-difference helper applied to `eval(x, v)` (the
    /// force on the point and the generalized force on the obstacle coordinate), steps `hx` in
    /// position and `hv` in rate, relative Frobenius tolerances `rtol`.
    #[allow(clippy::too_many_arguments)]
    #[track_caller]
    fn assert_block<const N: usize>(
        what: &str,
        ks: &[f64],
        kd: &[f64],
        x: [f64; N],
        v: [f64; N],
        (hx, hv): (f64, f64),
        (rtol_s, rtol_d): (f64, f64),
        eval: impl Fn([f64; N], [f64; N]) -> [f64; N],
    ) {
        use crate::elements::finite_difference::{assert_close, jacobian};
        use nalgebra::DMatrix;
        let arr = |y: &[f64]| -> [f64; N] { y.try_into().expect("N values") };
        let fx = jacobian(
            &x,
            N,
            |_| hx,
            |y, out| out.copy_from_slice(&eval(arr(y), v)),
        );
        let fv = jacobian(
            &v,
            N,
            |_| hv,
            |y, out| out.copy_from_slice(&eval(x, arr(y))),
        );
        let tiny = f64::MIN_POSITIVE;
        let (s, d) = (
            DMatrix::from_column_slice(N, N, ks),
            DMatrix::from_column_slice(N, N, kd),
        );
        assert_close(
            &format!("{what}: d force / d position"),
            &s,
            &fx,
            rtol_s,
            tiny,
        );
        assert_close(&format!("{what}: d force / d rate"), &d, &fv, rtol_d, tiny);
    }

    use crate::contact::test_laws::frictionless as law;

    /// The iteration block against finite differences of the force in position, obstacle
    /// coordinate and rates, on a tapered piston and the plate.
    #[test]
    fn block_matches_finite_differences() {
        let piston = AxisymObstacle::Piston {
            contour: vec![[0.11, 0.0], [0.1, 0.1], [0.1, 0.15]],
        };
        let plate = AxisymObstacle::Plate { radius: 0.2 };
        let floor = AxisymObstacle::Floor { radius: 0.2 };
        let cases = [
            (&piston, [0.1045, 0.05, 0.001], [0.1, -0.2, 0.05]),
            (&plate, [0.13, 0.25002, 0.25], [0.1, 0.3, -0.2]),
            (&floor, [0.13, -0.00002, 0.0], [0.1, -0.3, 0.2]),
        ];
        for (ob, x, v) in cases {
            let eval = |x: [f64; 3], v: [f64; 3]| {
                let p = PointMotion {
                    r: Vector2::new(x[0], x[1]),
                    v: Vector2::new(v[0], v[1]),
                };
                let c = ob
                    .evaluate(&law(), 0.01, &p, &[x[2]], &[v[2]], &SlideHistory::default())
                    .expect("in contact");
                [c.force.x, c.force.y, c.generalized_force(0)]
            };
            let p = PointMotion {
                r: Vector2::new(x[0], x[1]),
                v: Vector2::new(v[0], v[1]),
            };
            let c = ob
                .evaluate(&law(), 0.01, &p, &[x[2]], &[v[2]], &SlideHistory::default())
                .unwrap();
            let mut ks = [0.0; 9];
            let mut kd = [0.0; 9];
            c.iteration_block(1.0, 0.0, &mut ks);
            c.iteration_block(0.0, 1.0, &mut kd);
            assert_block("2D", &ks, &kd, x, v, (1e-9, 1e-3), (1e-5, 1e-6), eval);
        }
    }

    /// The force pushes out of the piston and down from the plate; none above the piston top,
    /// beyond the plate or outside.
    #[test]
    fn forces_point_out_of_the_solid() {
        let piston = AxisymObstacle::Piston {
            contour: vec![[0.1, 0.0], [0.1, 0.15]],
        };
        let at = |r: f64, z: f64| PointMotion {
            r: Vector2::new(r, z),
            v: Vector2::zeros(),
        };
        let c = piston
            .evaluate(
                &law(),
                1.0,
                &at(0.0999, 0.1),
                &[0.0],
                &[0.0],
                &SlideHistory::default(),
            )
            .unwrap();
        assert!(c.force.x > 0.0 && c.force.y == 0.0);
        assert!(
            piston
                .evaluate(
                    &law(),
                    1.0,
                    &at(0.0999, 0.16),
                    &[0.0],
                    &[0.0],
                    &SlideHistory::default()
                )
                .is_none()
        );
        assert!(
            piston
                .evaluate(
                    &law(),
                    1.0,
                    &at(0.1001, 0.1),
                    &[0.0],
                    &[0.0],
                    &SlideHistory::default()
                )
                .is_none()
        );
        let floor = AxisymObstacle::Floor { radius: 0.15 };
        let c = floor
            .evaluate(
                &law(),
                1.0,
                &at(0.1, -0.0001),
                &[0.0],
                &[0.0],
                &SlideHistory::default(),
            )
            .unwrap();
        assert!(c.force.y > 0.0 && c.force.x == 0.0 && c.generalized_force(0) < 0.0);
        for (r, z) in [(0.1, 0.0001), (0.16, -0.0001)] {
            assert!(
                floor
                    .evaluate(
                        &law(),
                        1.0,
                        &at(r, z),
                        &[0.0],
                        &[0.0],
                        &SlideHistory::default()
                    )
                    .is_none()
            );
        }
        let plate = AxisymObstacle::Plate { radius: 0.15 };
        let c = plate
            .evaluate(
                &law(),
                1.0,
                &at(0.1, 0.2501),
                &[0.25],
                &[0.0],
                &SlideHistory::default(),
            )
            .unwrap();
        assert!(c.force.y < 0.0 && c.generalized_force(0) > 0.0);
        assert!(
            plate
                .evaluate(
                    &law(),
                    1.0,
                    &at(0.16, 0.2501),
                    &[0.25],
                    &[0.0],
                    &SlideHistory::default()
                )
                .is_none()
        );
    }

    /// The spatial view: the force and its iteration block against finite differences on a
    /// tapered piston at a point off the x axis; the force is the meridian-plane force turned
    /// about the axis.
    #[test]
    fn spatial_block_matches_finite_differences() {
        let piston = AxisymObstacle::Piston {
            contour: vec![[0.11, 0.0], [0.1, 0.1], [0.1, 0.15]],
        };
        let (phi, r) = (0.7f64, 0.1045);
        let x = [r * phi.cos(), r * phi.sin(), 0.05, 0.001];
        let v = [0.1, -0.2, 0.05, 0.03];
        let eval = |x: [f64; 4], v: [f64; 4]| {
            let p = PointMotion {
                r: Vector3::new(x[0], x[1], x[2]),
                v: Vector3::new(v[0], v[1], v[2]),
            };
            let c = Obstacle::<3>::evaluate(
                &piston,
                &law(),
                0.01,
                &p,
                &[x[3]],
                &[v[3]],
                &SlideHistory3::default(),
            )
            .expect("in contact");
            [c.force.x, c.force.y, c.force.z, c.generalized_force(0)]
        };
        let f = eval(x, v);
        let p2 = PointMotion {
            r: Vector2::new(r, x[2]),
            v: Vector2::new(v[0] * phi.cos() + v[1] * phi.sin(), v[2]),
        };
        let c2 = Obstacle::<2>::evaluate(
            &piston,
            &law(),
            0.01,
            &p2,
            &[x[3]],
            &[v[3]],
            &SlideHistory::default(),
        )
        .unwrap();
        assert!((f[0] - c2.force.x * phi.cos()).abs() < 1e-9 * c2.force.norm());
        assert!((f[1] - c2.force.x * phi.sin()).abs() < 1e-9 * c2.force.norm());
        assert!((f[2] - c2.force.y).abs() < 1e-9 * c2.force.norm());
        let p = PointMotion {
            r: Vector3::new(x[0], x[1], x[2]),
            v: Vector3::new(v[0], v[1], v[2]),
        };
        let c = Obstacle::<3>::evaluate(
            &piston,
            &law(),
            0.01,
            &p,
            &[x[3]],
            &[v[3]],
            &SlideHistory3::default(),
        )
        .unwrap();
        let (mut ks, mut kd) = ([0.0; 16], [0.0; 16]);
        c.iteration_block(1.0, 0.0, &mut ks);
        c.iteration_block(0.0, 1.0, &mut kd);
        assert_block("3D", &ks, &kd, x, v, (1e-9, 1e-3), (1e-5, 1e-6), eval);
    }

    fn friction_law() -> ContactLaw {
        ContactLaw {
            k_t: 1e9,
            d_t: 2e3,
            mu: 0.4,
            blend: 0.1,
            ..law()
        }
    }

    /// With friction: the iteration block against finite differences of the force in
    /// position, obstacle coordinate and rates, in stick, in the stick–slip blend and in
    /// sliding, on the tapered piston and on the plate.
    #[test]
    fn friction_block_matches_finite_differences() {
        let piston = AxisymObstacle::Piston {
            contour: vec![[0.11, 0.0], [0.1, 0.1], [0.1, 0.15]],
        };
        let plate = AxisymObstacle::Plate { radius: 0.2 };
        let floor = AxisymObstacle::Floor { radius: 0.2 };
        let law = friction_law();
        // the trial stress f* at `target` × μ p: stick, the blend zone, sliding either way
        for (ob, x, v, target, expect) in [
            (
                &piston,
                [0.1045, 0.05, 0.001],
                [0.1, -0.2, 0.05],
                0.3,
                "stick",
            ),
            (
                &piston,
                [0.1045, 0.05, 0.001],
                [0.1, -0.2, 0.05],
                0.97,
                "blend",
            ),
            (
                &piston,
                [0.1045, 0.05, 0.001],
                [0.1, -0.2, 0.05],
                -3.0,
                "slide",
            ),
            (&plate, [0.13, 0.251, 0.25], [0.1, 0.3, -0.2], -0.5, "stick"),
            (&plate, [0.13, 0.251, 0.25], [0.1, 0.3, -0.2], 2.0, "slide"),
            (&floor, [0.13, -0.001, 0.0], [0.1, -0.3, 0.2], 0.5, "stick"),
            (&floor, [0.13, -0.001, 0.0], [0.1, -0.3, 0.2], -1.5, "slide"),
        ] {
            // the committed point: shifted along the tangent from x
            let at = |x: [f64; 3], v: [f64; 3]| PointMotion {
                r: Vector2::new(x[0], x[1]),
                v: Vector2::new(v[0], v[1]),
            };
            let c0 = ob
                .evaluate(
                    &law,
                    0.01,
                    &at(x, v),
                    &[x[2]],
                    &[v[2]],
                    &SlideHistory::default(),
                )
                .unwrap();
            let t = [-c0.normal.y, c0.normal.x];
            let p0 = c0.force.dot(&c0.normal) / 0.01;
            let sdot = t[0] * v[0] + t[1] * (v[1] - v[2]);
            let rel_shift = (target * law.mu * p0 - law.d_t * sdot) / law.k_t;
            let hist = SlideHistory {
                rel: [x[0] - rel_shift * t[0], x[1] - x[2] - rel_shift * t[1]],
                z: 0.0,
                f: 0.0,
                valid: true,
            };
            let eval = |x: [f64; 3], v: [f64; 3]| {
                let c = ob
                    .evaluate(&law, 0.01, &at(x, v), &[x[2]], &[v[2]], &hist)
                    .expect("in contact");
                [c.force.x, c.force.y, c.generalized_force(0)]
            };
            let c = ob
                .evaluate(&law, 0.01, &at(x, v), &[x[2]], &[v[2]], &hist)
                .unwrap();
            let ratio = c.friction.abs() / (law.mu * c.force.dot(&c.normal) / 0.01);
            match expect {
                "stick" => assert!(!c.slipping && ratio < 0.9, "{ratio}"),
                "blend" => assert!(ratio > 0.9 && ratio < 1.0, "{ratio}"),
                _ => assert!(c.slipping && (ratio - 1.0).abs() < 1e-12, "{ratio}"),
            }
            let mut ks = [0.0; 9];
            let mut kd = [0.0; 9];
            c.iteration_block(1.0, 0.0, &mut ks);
            c.iteration_block(0.0, 1.0, &mut kd);
            assert_block(expect, &ks, &kd, x, v, (1e-8, 1e-4), (1e-6, 1e-6), eval);
        }
    }

    /// A point that stays where it lies on the piston while the piston moves (rolling: no
    /// sliding) carries no friction; one that slides down the piston is pushed up by `μ p`
    /// per area, and the friction work of the step is `w f Δs` > 0.
    #[test]
    fn friction_acts_against_sliding_only() {
        let piston = AxisymObstacle::Piston {
            contour: vec![[0.1, 0.0], [0.1, 0.15]],
        };
        let law = ContactLaw {
            d_t: 0.0,
            ..friction_law()
        };
        let p = PointMotion {
            r: Vector2::new(0.0995, 0.08),
            v: Vector2::new(0.0, 0.0),
        };
        // committed at z₀ = 0; now the piston and the point have both moved up 5 mm
        let h = Obstacle::<2>::committed(&piston, &p, &[0.0], None);
        let moved = PointMotion {
            r: Vector2::new(0.0995, 0.085),
            v: Vector2::new(0.0, 0.0),
        };
        let c = piston
            .evaluate(&law, 1e-4, &moved, &[0.005], &[0.0], &h)
            .unwrap();
        assert_eq!(c.friction, 0.0);
        assert_eq!(c.force.y, 0.0);
        // the point slides 5 mm down a fixed piston
        let slid = PointMotion {
            r: Vector2::new(0.0995, 0.075),
            v: Vector2::new(0.0, -0.1),
        };
        let c = piston
            .evaluate(&law, 1e-4, &slid, &[0.0], &[0.0], &h)
            .unwrap();
        let p_n = c.force.x / 1e-4;
        assert!(c.slipping);
        assert!(
            (c.force.y / 1e-4 - law.mu * p_n).abs() < 1e-9 * p_n,
            "{:?}",
            c.force
        );
        assert!(
            <AxisymObstacle as Obstacle<2>>::friction_work(1e-4, &h, &c) > 0.0,
            "sliding along −t (Δs < 0) against f < 0: the work w f Δs is dissipated"
        );
    }

    /// With friction in space: the iteration block against finite differences of the force
    /// in position, piston coordinate and rates, in stick, in the blend and sliding, with a
    /// bristle from the last step lying off the current tangent plane (the normal has turned);
    /// and a point that stays where it lies on the piston carries no friction.
    #[test]
    fn spatial_friction_block_matches_finite_differences() {
        let piston = AxisymObstacle::Piston {
            contour: vec![[0.11, 0.0], [0.1, 0.1], [0.1, 0.15]],
        };
        let law = friction_law();
        let (phi, r) = (0.7f64, 0.1045);
        let x = [r * phi.cos(), r * phi.sin(), 0.05, 0.001];
        let v = [0.1, -0.2, 0.05, 0.03];
        let at = |x: [f64; 4], v: [f64; 4]| PointMotion {
            r: Vector3::new(x[0], x[1], x[2]),
            v: Vector3::new(v[0], v[1], v[2]),
        };
        let c0 = Obstacle::<3>::evaluate(
            &piston,
            &law,
            0.01,
            &at(x, v),
            &[x[3]],
            &[v[3]],
            &SlideHistory3::default(),
        )
        .unwrap();
        let p0 = c0.force.dot(&c0.normal) / 0.01;
        // a slip direction in the tangent plane (hoop and meridional) and an old bristle
        let t_dir = Vector3::new(-phi.sin(), phi.cos(), 0.6).normalize();
        let t_dir = (t_dir - c0.normal * c0.normal.dot(&t_dir)).normalize();
        let old_dir = Vector3::new(0.3, -0.2, 0.9);
        let n0 = c0.normal;
        let a_dir = 0.8 * t_dir + 0.2 * (old_dir - n0 * n0.dot(&old_dir));
        for (target, expect) in [(0.3, "stick"), (0.97, "blend"), (3.0, "slide")] {
            // |f*| ≈ k_t |P (z_old + Δρ)| = target μ p
            let shift = target * law.mu * p0 / law.k_t / a_dir.norm();
            let old = 0.2 * shift * old_dir;
            let hist = SlideHistory3 {
                rel: [
                    x[0] - 0.8 * shift * t_dir.x,
                    x[1] - 0.8 * shift * t_dir.y,
                    x[2] - x[3] - 0.8 * shift * t_dir.z,
                ],
                z: [old.x, old.y, old.z],
                f: [0.0; 3],
                valid: true,
            };
            let eval = |x: [f64; 4], v: [f64; 4]| {
                let c = Obstacle::<3>::evaluate(
                    &piston,
                    &law,
                    0.01,
                    &at(x, v),
                    &[x[3]],
                    &[v[3]],
                    &hist,
                )
                .expect("in contact");
                [c.force.x, c.force.y, c.force.z, c.generalized_force(0)]
            };
            let c =
                Obstacle::<3>::evaluate(&piston, &law, 0.01, &at(x, v), &[x[3]], &[v[3]], &hist)
                    .unwrap();
            let pn = c.force.dot(&c.normal) / 0.01;
            let ratio = c.friction.norm() / (law.mu * pn);
            match expect {
                "stick" => assert!(!c.slipping && ratio < 0.9, "{ratio}"),
                "blend" => assert!(ratio > 0.85 && ratio < 1.0, "{ratio}"),
                _ => assert!(c.slipping && (ratio - 1.0).abs() < 1e-12, "{ratio}"),
            }
            assert!(c.friction.dot(&c.normal).abs() < 1e-9 * c.friction.norm());
            let (mut ks, mut kd) = ([0.0; 16], [0.0; 16]);
            c.iteration_block(1.0, 0.0, &mut ks);
            c.iteration_block(0.0, 1.0, &mut kd);
            assert_block(expect, &ks, &kd, x, v, (1e-9, 1e-4), (1e-6, 1e-6), eval);
        }
        // rolling: committed here, the piston and the point then move up together
        let law = ContactLaw { d_t: 0.0, ..law };
        let p = at(x, [0.0; 4]);
        let h = Obstacle::<3>::committed(&piston, &p, &[x[3]], None);
        let moved = at([x[0], x[1], x[2] + 0.004, 0.0], [0.0; 4]);
        let c = Obstacle::<3>::evaluate(&piston, &law, 0.01, &moved, &[x[3] + 0.004], &[0.0], &h)
            .unwrap();
        // (rounding of z − z₀ only: 1e-17 m of slip against a bristle of k_t = 1e9 Pa/m)
        let pn = c.force.dot(&c.normal) / 0.01;
        assert!(
            c.friction.norm() < 1e-12 * law.mu * pn,
            "{}",
            c.friction.norm()
        );
    }
}
