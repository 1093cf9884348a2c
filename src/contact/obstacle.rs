//! What a contact point can touch: the obstacle trait of [`super::ContactPointSet`] and its
//! first implementation, the rotating circle (pulley) of [`super::circle_friction`].
//!
//! An obstacle is rigid geometry with coordinates of its own (a pulley's angle; later a plate's
//! position, a 3D pulley's angle about its axis). For one material point of the flexible body
//! in `D` dimensions it gives the gap, normal, tangent and friction (inside
//! [`Obstacle::evaluate`]), the force on the point, the generalized forces on its own
//! coordinates and their derivatives: the point set scatters these through the point's
//! interpolation weights into the assembly. A plane, a surface of revolution (bellows against
//! piston and bead plate) and a 3D pulley with an axis are further implementations.

use super::circle_friction::{self, Circle, ContactLaw, PointContact, PointHistory, PointState};
use crate::snapshot::{SnapshotError, StateReader, StateWriter};
use nalgebra::{SVector, Vector3};

/// Largest number of own coordinates an obstacle may have (a rigid body in space: 6).
pub const MAX_OBSTACLE_COORDS: usize = 6;

/// Position and velocity of a material point of the flexible body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointMotion<const D: usize> {
    /// Position [m].
    pub r: SVector<f64, D>,
    /// Velocity [m/s].
    pub v: SVector<f64, D>,
}

/// Committed per-point state of a contact pair (friction history), saved in FMU states.
pub trait ContactHistory: Copy + Default + std::fmt::Debug {
    /// Writes the history into a snapshot.
    fn save(&self, w: &mut StateWriter);

    /// Reads a history written by [`ContactHistory::save`].
    fn restore(r: &mut StateReader) -> Result<Self, SnapshotError>;
}

/// Result of an active contact point, as the point set needs it.
pub trait ObstacleContact<const D: usize> {
    /// Force on the body's point [N].
    fn force(&self) -> SVector<f64, D>;

    /// Generalized force on the obstacle's own coordinate `l` (a pulley's torque [N m]).
    fn generalized_force(&self, l: usize) -> f64;

    /// Iteration-matrix block `ks ∂F/∂x + kd ∂F/∂ẋ` of the force vector `F` = (force on the
    /// point, generalized forces) with respect to `x` = (point position, obstacle
    /// coordinates), column-major into `out` (`(D + N_COORDS)²` entries).
    fn iteration_block(&self, ks: f64, kd: f64, out: &mut [f64]);

    /// Whether the point slides.
    fn slipping(&self) -> bool;

    /// Elastic energy of the normal penalty [J].
    fn normal_energy(&self) -> f64;

    /// Power dissipated by normal damping [W].
    fn dissipation(&self) -> f64;

    /// Moment of the force on the obstacle about its reference point [N m] (3D obstacles;
    /// planar ones give their moment as the generalized force).
    fn moment(&self) -> Vector3<f64> {
        Vector3::zeros()
    }

    /// Force of the point on the obstacle's side faces (a pulley's flanges) along its axis
    /// [N] (0 for obstacles without side faces).
    fn side_force(&self) -> f64 {
        0.0
    }
}

/// Rigid geometry a contact point can touch, with its own coordinates.
pub trait Obstacle<const D: usize> {
    /// Number of the obstacle's own coordinates (a circle pulley: 1, its angle θ [rad]);
    /// at most [`MAX_OBSTACLE_COORDS`].
    const N_COORDS: usize;

    /// Committed per-point history.
    type History: ContactHistory;

    /// Result of an active point.
    type Contact: ObstacleContact<D>;

    /// Broad phase: whether a segment of the body with end points `a`, `b` [m] can touch.
    fn near(&self, a: &SVector<f64, D>, b: &SVector<f64, D>) -> bool;

    /// [`Obstacle::near`] knowing the obstacle's coordinates `x` (first
    /// [`Obstacle::N_COORDS`] entries): an obstacle that moves (a plate at height `x[0]`) can
    /// skip the segments it cannot reach there. Default: [`Obstacle::near`].
    #[inline(always)]
    fn near_at(&self, a: &SVector<f64, D>, b: &SVector<f64, D>, _x: &[f64]) -> bool {
        self.near(a, b)
    }

    /// Contact of a point standing for the body length (or area) `w` with the obstacle at
    /// coordinates `x` and rates `xd` (first [`Obstacle::N_COORDS`] entries); `None` out of
    /// contact.
    fn evaluate(
        &self,
        law: &ContactLaw,
        w: f64,
        p: &PointMotion<D>,
        x: &[f64],
        xd: &[f64],
        hist: &Self::History,
    ) -> Option<Self::Contact>;

    /// The history to commit for a point at `p`, obstacle coordinates `x`, with the contact
    /// result `c` (`None`: out of contact, friction relaxed).
    fn committed(&self, p: &PointMotion<D>, x: &[f64], c: Option<&Self::Contact>) -> Self::History;

    /// Work of a point of weight `w` against friction between the history `h` and the
    /// contact `c` [J].
    fn friction_work(w: f64, h: &Self::History, c: &Self::Contact) -> f64;

    /// The obstacle's coordinate `l` moved by `by` under the point without slip: shift the
    /// history so that no friction comes from it.
    fn shift_history(h: &mut Self::History, l: usize, by: f64);
}

impl ContactHistory for PointHistory {
    fn save(&self, w: &mut StateWriter) {
        for x in [self.dir.x, self.dir.y, self.theta, self.z, self.f] {
            w.f64(x);
        }
    }

    fn restore(r: &mut StateReader) -> Result<Self, SnapshotError> {
        Ok(Self {
            dir: nalgebra::Vector2::new(r.f64()?, r.f64()?),
            theta: r.f64()?,
            z: r.f64()?,
            f: r.f64()?,
        })
    }
}

impl ObstacleContact<2> for PointContact {
    #[inline]
    fn force(&self) -> SVector<f64, 2> {
        self.force
    }

    #[inline]
    fn generalized_force(&self, _l: usize) -> f64 {
        self.torque
    }

    #[inline]
    fn iteration_block(&self, ks: f64, kd: f64, out: &mut [f64]) {
        let m = ks * self.k + kd * self.c;
        out.copy_from_slice(m.as_slice());
    }

    fn slipping(&self) -> bool {
        self.slipping
    }

    fn normal_energy(&self) -> f64 {
        self.normal_energy
    }

    fn dissipation(&self) -> f64 {
        self.dissipation
    }
}

/// The planar pulley: a circle of fixed centre turning by its angle θ (its one coordinate).
impl Obstacle<2> for Circle {
    const N_COORDS: usize = 1;
    type History = PointHistory;
    type Contact = PointContact;

    /// Nearest end distance minus 0.55 of the chord (a sagging segment) and 0.1 % of the
    /// radius below the radius.
    #[inline(always)]
    fn near(&self, a: &SVector<f64, 2>, b: &SVector<f64, 2>) -> bool {
        let chord = (b - a).norm();
        let dist = (a - self.center).norm().min((b - self.center).norm());
        dist - 0.55 * chord - 1e-3 * self.radius < self.radius
    }

    #[inline]
    fn evaluate(
        &self,
        law: &ContactLaw,
        w: f64,
        p: &PointMotion<2>,
        x: &[f64],
        xd: &[f64],
        hist: &PointHistory,
    ) -> Option<PointContact> {
        let s = PointState {
            r: p.r,
            v: p.v,
            theta: x[0],
            omega: xd[0],
        };
        circle_friction::evaluate(law, self, w, &s, hist)
    }

    fn committed(&self, p: &PointMotion<2>, x: &[f64], c: Option<&PointContact>) -> PointHistory {
        let (z, f) = c.map_or((0.0, 0.0), |c| (c.z, c.friction));
        PointHistory {
            dir: p.r - self.center,
            theta: x[0],
            z,
            f,
        }
    }

    /// Trapezoidal in the slip: `w (f_old + f)/2 Δs`.
    #[inline]
    fn friction_work(w: f64, h: &PointHistory, c: &PointContact) -> f64 {
        w * 0.5 * (h.f + c.friction) * c.slip_increment
    }

    fn shift_history(h: &mut PointHistory, _l: usize, by: f64) {
        h.theta += by;
    }
}
