//! A pulley on a pivoted arm (the idler of a belt tensioner): a circle whose centre swings with
//! the arm angle `ψ` about a fixed pivot, `c(ψ) = p + l (cos ψ, sin ψ)`, and turns by its own
//! angle `θ`. Two coordinates, `(θ, ψ)`.
//!
//! The contact of a belt point is the rotating circle's ([`super::circle_friction`]) at the
//! relative position `d = r − c(ψ)` and relative velocity `v − c'(ψ) ψ̇`, so the belt slides
//! over the idler's surface whatever the arm does. Force on the belt `F(r − c, v − ċ, θ, ω)`,
//! torque on the idler `τ` as for a fixed pulley; the arm receives the reaction `−F` at the
//! idler centre, whose virtual work gives the generalized force `Q_ψ = −F·c'(ψ)` (the
//! friction torque `τ` goes into the idler's spin, its bearing sits on the arm). The iteration
//! block follows by the chain rule from the circle's blocks `K = ∂(F, τ)/∂(r, θ)`,
//! `C = ∂(F, τ)/∂(v, ω)`:
//! `∂(F, τ)/∂ψ = −K_r c' − C_v c'' ψ̇`, `∂(F, τ)/∂ψ̇ = −C_v c'`,
//! `∂Q_ψ/∂x = −c'ᵀ ∂F/∂x` for `x ∈ (r, θ, v, ω)`, `∂Q_ψ/∂ψ = −c'ᵀ ∂F/∂ψ − F·c''`,
//! `∂Q_ψ/∂ψ̇ = c'ᵀ C_{F,v} c'`.

use super::circle_friction::{self, Circle, ContactLaw, PointContact, PointHistory, PointState};
use super::obstacle::{Obstacle, ObstacleContact, PointMotion};
use nalgebra::{Matrix4, SVector, Vector2};

/// A pulley of pitch radius `radius` [m] on an arm of length `arm` [m] pivoting about `pivot`
/// [m]; its coordinates are the spin angle `θ` [rad] and the arm angle `ψ` [rad] (polar angle
/// of the idler centre about the pivot, counter-clockwise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmPulley {
    /// Pivot of the arm [m].
    pub pivot: Vector2<f64>,
    /// Arm length: pivot to idler centre [m].
    pub arm: f64,
    /// Contact radius of the belt centre line (pulley radius + half the belt thickness) [m].
    pub radius: f64,
}

impl ArmPulley {
    /// Idler centre at arm angle `psi` [m].
    #[inline]
    pub fn center(&self, psi: f64) -> Vector2<f64> {
        self.pivot + self.arm * Vector2::new(psi.cos(), psi.sin())
    }

    /// `c'(ψ)` [m/rad].
    #[inline]
    pub fn center_slope(&self, psi: f64) -> Vector2<f64> {
        self.arm * Vector2::new(-psi.sin(), psi.cos())
    }

    /// The idler's circle at arm angle `psi`.
    #[inline]
    pub fn circle(&self, psi: f64) -> Circle {
        Circle {
            center: self.center(psi),
            radius: self.radius,
        }
    }
}

/// Contact of a belt point with an [`ArmPulley`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmContact {
    /// The circle's contact at the relative position and velocity.
    pub inner: PointContact,
    /// Generalized force on the arm angle `Q_ψ = −F·c'(ψ)` [N m].
    pub arm_moment: f64,
    /// `∂(F_x, F_y, τ, Q_ψ)/∂(r_x, r_y, θ, ψ)`.
    pub k: Matrix4<f64>,
    /// `∂(F_x, F_y, τ, Q_ψ)/∂(v_x, v_y, ω, ψ̇)`.
    pub c: Matrix4<f64>,
}

/// Contact of a belt point of weight `w` [m] at `p` with the arm pulley at spin angle and arm
/// angle `x = (θ, ψ)`, rates `xd = (ω, ψ̇)`; `None` out of contact.
pub fn evaluate(
    law: &ContactLaw,
    pulley: &ArmPulley,
    w: f64,
    p: &PointMotion<2>,
    x: &[f64],
    xd: &[f64],
    hist: &PointHistory,
) -> Option<ArmContact> {
    let (psi, psid) = (x[1], xd[1]);
    let cs = pulley.center_slope(psi);
    // c'' = −l (cos ψ, sin ψ)
    let css = pulley.center(psi) - pulley.pivot;
    let css = -css;
    let s = PointState {
        r: p.r,
        v: p.v - cs * psid,
        theta: x[0],
        omega: xd[0],
    };
    let inner = circle_friction::evaluate(law, &pulley.circle(psi), w, &s, hist)?;
    let (k3, c3) = (inner.k, inner.c);
    let fvec = nalgebra::Vector3::new(inner.force.x, inner.force.y, inner.torque);
    let arm_moment = -inner.force.dot(&cs);
    let mut k = Matrix4::zeros();
    let mut c = Matrix4::zeros();
    // rows F_x, F_y, τ
    for i in 0..3 {
        for j in 0..3 {
            k[(i, j)] = k3[(i, j)];
            c[(i, j)] = c3[(i, j)];
        }
        let kr = k3[(i, 0)] * cs.x + k3[(i, 1)] * cs.y;
        let cr = c3[(i, 0)] * cs.x + c3[(i, 1)] * cs.y;
        let cr2 = c3[(i, 0)] * css.x + c3[(i, 1)] * css.y;
        k[(i, 3)] = -kr - cr2 * psid;
        c[(i, 3)] = -cr;
    }
    // row Q_ψ = −c'·F
    for j in 0..4 {
        k[(3, j)] = -(cs.x * k[(0, j)] + cs.y * k[(1, j)]);
        c[(3, j)] = -(cs.x * c[(0, j)] + cs.y * c[(1, j)]);
    }
    k[(3, 3)] -= fvec.x * css.x + fvec.y * css.y;
    Some(ArmContact {
        inner,
        arm_moment,
        k,
        c,
    })
}

impl ObstacleContact<2> for ArmContact {
    #[inline]
    fn force(&self) -> SVector<f64, 2> {
        self.inner.force
    }

    /// `l = 0`: torque on the idler's spin [N m]; `l = 1`: moment on the arm [N m].
    #[inline]
    fn generalized_force(&self, l: usize) -> f64 {
        if l == 0 {
            self.inner.torque
        } else {
            self.arm_moment
        }
    }

    #[inline]
    fn iteration_block(&self, ks: f64, kd: f64, out: &mut [f64]) {
        let m = ks * self.k + kd * self.c;
        out.copy_from_slice(m.as_slice());
    }

    fn slipping(&self) -> bool {
        self.inner.slipping
    }

    fn normal_energy(&self) -> f64 {
        self.inner.normal_energy
    }

    fn dissipation(&self) -> f64 {
        self.inner.dissipation
    }
}

/// The tensioner idler: coordinates `(θ, ψ)`.
impl Obstacle<2> for ArmPulley {
    const N_COORDS: usize = 2;
    type History = PointHistory;
    type Contact = ArmContact;

    /// The circle's broad phase with the arm allowed to swing by its own length's 5 % (the
    /// centre is not known here).
    #[inline(always)]
    fn near(&self, a: &SVector<f64, 2>, b: &SVector<f64, 2>) -> bool {
        let chord = (b - a).norm();
        let dist = (a - self.pivot).norm().min((b - self.pivot).norm());
        dist - 0.55 * chord < self.arm + self.radius * 1.001 + 0.05 * self.arm
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
    ) -> Option<ArmContact> {
        evaluate(law, self, w, p, x, xd, hist)
    }

    fn committed(&self, p: &PointMotion<2>, x: &[f64], c: Option<&ArmContact>) -> PointHistory {
        let (z, f) = c.map_or((0.0, 0.0), |c| (c.inner.z, c.inner.friction));
        PointHistory {
            dir: p.r - self.circle(x[1]).center,
            theta: x[0],
            z,
            f,
        }
    }

    #[inline]
    fn friction_work(w: f64, h: &PointHistory, c: &ArmContact) -> f64 {
        w * 0.5 * (h.f + c.inner.friction) * c.inner.slip_increment
    }

    fn shift_history(h: &mut PointHistory, l: usize, by: f64) {
        if l == 0 {
            h.theta += by;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::finite_difference as fd;
    use nalgebra::DMatrix;

    use crate::contact::test_laws::belt as law;

    /// Idler of R = 0.04 m on a 0.1 m arm at ψ = 0.7 rad; a point pressed in by 20 µm,
    /// moving with the idler's surface (plus 5 mm/s of slip and 10 mm/s normal) while the arm
    /// swings, sticking (bristle `z_hist` small) or sliding (large).
    fn case(
        f_hist: f64,
        z_hist: f64,
    ) -> (ArmPulley, PointMotion<2>, [f64; 2], [f64; 2], PointHistory) {
        let pulley = ArmPulley {
            pivot: Vector2::new(0.3, -0.2),
            arm: 0.1,
            radius: 0.04,
        };
        let x = [0.4, 0.7];
        let xd = [30.0, 0.8];
        let c = pulley.center(x[1]);
        let a: f64 = 1.1;
        let n = Vector2::new(a.cos(), a.sin());
        let t = Vector2::new(-n.y, n.x);
        let r = c + (0.04 - 2e-5) * n;
        // rolling with the idler while the arm swings, plus a little normal and slip speed
        let v = pulley.center_slope(x[1]) * xd[1] + (xd[0] * 0.04 + 0.005) * t + 0.01 * n;
        let p = PointMotion { r, v };
        let h = PointHistory::at_angle(a - 1e-4, 0.4 - 5e-5, z_hist, f_hist);
        (pulley, p, x, xd, h)
    }

    fn check(f_hist: f64, z_hist: f64, expect_slip: bool) {
        let law = law();
        let w = 4e-3;
        let (pulley, p, x, xd, h) = case(f_hist, z_hist);
        let res = evaluate(&law, &pulley, w, &p, &x, &xd, &h).expect("in contact");
        assert_eq!(res.inner.slipping, expect_slip);
        let out = |p: &PointMotion<2>, x: &[f64], xd: &[f64], o: &mut [f64]| {
            let r = evaluate(&law, &pulley, w, p, x, xd, &h).unwrap();
            o.copy_from_slice(&[
                r.inner.force.x,
                r.inner.force.y,
                r.inner.torque,
                r.arm_moment,
            ]);
        };
        let pos = [p.r.x, p.r.y, x[0], x[1]];
        let vel = [p.v.x, p.v.y, xd[0], xd[1]];
        let kfd = fd::jacobian(
            &pos,
            4,
            |_| 1e-9,
            |y, o| {
                let pm = PointMotion {
                    r: Vector2::new(y[0], y[1]),
                    v: p.v,
                };
                out(&pm, &y[2..], &xd, o)
            },
        );
        let cfd = fd::jacobian(
            &vel,
            4,
            |_| 1e-6,
            |y, o| {
                let pm = PointMotion {
                    r: p.r,
                    v: Vector2::new(y[0], y[1]),
                };
                out(&pm, &x, &y[2..], o)
            },
        );
        let k = DMatrix::from_column_slice(4, 4, res.k.as_slice());
        let c = DMatrix::from_column_slice(4, 4, res.c.as_slice());
        fd::assert_close("arm pulley K", &k, &kfd, 1e-5, 1e-6 * k.amax());
        fd::assert_close("arm pulley C", &c, &cfd, 1e-5, 1e-6 * c.amax());
    }

    #[test]
    fn stick_tangent_matches_finite_differences() {
        check(0.0, 0.0, false);
    }

    #[test]
    fn slip_tangent_matches_finite_differences() {
        check(5e3, 1e-3, true);
    }

    /// A point at rest on a still idler: the arm moment is the moment of the reaction about
    /// the pivot, `(c − p) × (−F)`, since `c'(ψ) = ẑ × (c − p)`.
    #[test]
    fn arm_moment_is_the_moment_of_the_reaction() {
        let law = law();
        let (pulley, mut p, x, _, _) = case(0.0, 0.0);
        p.v = Vector2::zeros();
        let h = PointHistory {
            dir: p.r - pulley.circle(x[1]).center,
            theta: x[0],
            z: 0.0,
            f: 0.0,
        };
        let res = evaluate(&law, &pulley, 4e-3, &p, &x, &[0.0, 0.0], &h).unwrap();
        let arm = pulley.center(x[1]) - pulley.pivot;
        let f = -res.inner.force;
        let moment = arm.x * f.y - arm.y * f.x;
        assert!(res.arm_moment.abs() > 0.0);
        assert!(
            (res.arm_moment - moment).abs() <= 1e-12 * moment.abs(),
            "{} vs {moment}",
            res.arm_moment
        );
    }
}
