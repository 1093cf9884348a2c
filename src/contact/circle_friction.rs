//! Penalty contact with elasto-plastic ("bristle") Coulomb friction between a material point of
//! a belt centre line and a rotating circle (pulley), with the consistent tangent for implicit
//! integration.
//!
//! After the point-wise penalty contact of Kerkkänen et al. 2006 and Dufva et al. 2007 and the
//! bristle friction of Exudyn's `ObjectContactFrictionCircleCable2D` (reference
//! `shared/reference/belt-drive.md` E.2), written as a return mapping (Wriggers, Computational
//! Contact Mechanics, 2nd ed., §5.2: friction as elasto-plasticity):
//!
//! * geometry: `d = r − c`, `ρ = |d|`, normal `n = d/ρ`, tangent `t = (−n_y, n_x)`
//!   (counter-clockwise), gap `g = ρ − R` with `R` = pulley radius + half the belt thickness
//!   (the centre line runs at the pitch radius);
//! * normal pressure per unit belt length `p = −k_n g − d_n ġ` (`ġ = v·n`), active while
//!   `g < 0` and `p > 0`; force on the belt `w p n` (`w` = belt length the point stands for);
//! * relative slip of the belt over the pulley surface, measured in the pulley frame:
//!   increment over a step `Δs = ρ (Δφ − Δθ)` (`φ` = polar angle of the point, `θ` = pulley
//!   angle), so pure rolling (`Δφ = Δθ`) creates no force at any step size; slip rate
//!   `ṡ = v·t − ω ρ`;
//! * friction per unit length: trial `f* = k_t (z_n + Δs) + d_t ṡ` (`z` = bristle deflection);
//!   stick if `|f*| ≤ μ p` (then `z = z_n + Δs`), else slip with `f = μ p sign(f*)` and
//!   `z = sign(f*) μ p / k_t`; force on the belt `−w f t`, torque on the pulley `τ = ρ w f`.

use nalgebra::{Matrix3, Vector2};

/// Contact and friction constants (per unit belt length).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLaw {
    /// Normal penalty stiffness `k_n` [N/m²].
    pub k_n: f64,
    /// Normal damping `d_n` [N s/m²].
    pub d_n: f64,
    /// Tangential (bristle) stiffness `k_t` [N/m²].
    pub k_t: f64,
    /// Tangential damping in stick `d_t` [N s/m²].
    pub d_t: f64,
    /// Coulomb friction coefficient `μ` [1].
    pub mu: f64,
}

/// A pulley as the contact sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Circle {
    /// Centre [m] (fixed).
    pub center: Vector2<f64>,
    /// Contact radius of the belt centre line `R` = pulley radius + half belt thickness [m].
    pub radius: f64,
}

/// Committed history of one (belt point, pulley) pair.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PointHistory {
    /// Polar angle of the point about the pulley centre at the last accepted step [rad].
    pub phi: f64,
    /// Pulley angle at the last accepted step [rad].
    pub theta: f64,
    /// Bristle deflection [m] (0 out of contact).
    pub z: f64,
}

/// Kinematic state of a point and its pulley.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointState {
    /// Position of the belt point [m].
    pub r: Vector2<f64>,
    /// Its velocity [m/s].
    pub v: Vector2<f64>,
    /// Pulley angle [rad].
    pub theta: f64,
    /// Pulley angular velocity [rad/s].
    pub omega: f64,
}

/// Result of an active contact point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointContact {
    /// Force on the belt point [N].
    pub force: Vector2<f64>,
    /// Torque on the pulley about its centre [N m] (counter-clockwise positive).
    pub torque: f64,
    /// New bristle deflection [m].
    pub z: f64,
    /// Whether the point slips.
    pub slipping: bool,
    /// Normal pressure [N/m].
    pub pressure: f64,
    /// Gap [m] (negative: penetration).
    pub gap: f64,
    /// Slip rate `ṡ` [m/s].
    pub slip_rate: f64,
    /// Elastic energy of the normal penalty `½ k_n g² w` [J].
    pub normal_energy: f64,
    /// Dissipated power: normal damping `w d_n ġ²` plus friction `−f_t ṡ` [W].
    pub dissipation: f64,
    /// `∂(F_x, F_y, τ)/∂(r_x, r_y, θ)`.
    pub k: Matrix3<f64>,
    /// `∂(F_x, F_y, τ)/∂(v_x, v_y, ω)`.
    pub c: Matrix3<f64>,
}

/// Wraps an angle difference into (−π, π].
#[inline]
pub fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let mut x = a % TAU;
    if x > PI {
        x -= TAU;
    } else if x <= -PI {
        x += TAU;
    }
    x
}

/// Polar angle of `r` about the circle's centre [rad].
#[inline]
pub fn polar_angle(circle: &Circle, r: Vector2<f64>) -> f64 {
    let d = r - circle.center;
    d.y.atan2(d.x)
}

/// Contact of a belt point standing for the length `w` [m] with history `hist`; `None` when
/// out of contact (then the bristle is relaxed: `z = 0`).
pub fn evaluate(
    law: &ContactLaw,
    circle: &Circle,
    w: f64,
    s: &PointState,
    hist: &PointHistory,
) -> Option<PointContact> {
    let d = s.r - circle.center;
    let rho2 = d.norm_squared();
    if rho2 >= circle.radius * circle.radius {
        return None;
    }
    let rho = rho2.sqrt();
    let n = d / rho;
    let t = Vector2::new(-n.y, n.x);
    let g = rho - circle.radius;
    let (vn, vt) = (s.v.dot(&n), s.v.dot(&t));
    let p = -law.k_n * g - law.d_n * vn;
    if p <= 0.0 {
        return None;
    }
    // ∂p/∂d, ∂p/∂v (row vectors as 2-vectors)
    let dp_dd = -law.k_n * n - (law.d_n * vt / rho) * t;
    let dp_dv = -law.d_n * n;

    // Slip increment and rate.
    let phi = d.y.atan2(d.x);
    let dphi = wrap_angle(phi - hist.phi);
    let dtheta = s.theta - hist.theta;
    let ds = rho * (dphi - dtheta);
    let sdot = vt - s.omega * rho;
    let z_trial = hist.z + ds;
    let f_trial = law.k_t * z_trial + law.d_t * sdot;
    let cap = law.mu * p;
    // f_t: friction force on the belt along t (per point), and its derivatives.
    let (f_t, z, slipping, dft_dd, dft_dv, dft_dth, dft_dom);
    if f_trial.abs() <= cap {
        f_t = -w * f_trial;
        z = z_trial;
        slipping = false;
        let dds_dd = (dphi - dtheta) * n + t;
        let dsdot_dd = -(vn / rho) * t - s.omega * n;
        dft_dd = -w * (law.k_t * dds_dd + law.d_t * dsdot_dd);
        dft_dv = -w * law.d_t * t;
        dft_dth = w * law.k_t * rho;
        dft_dom = w * law.d_t * rho;
    } else {
        let sign = f_trial.signum();
        f_t = -w * sign * cap;
        z = if law.k_t > 0.0 { sign * cap / law.k_t } else { 0.0 };
        slipping = true;
        dft_dd = -w * sign * law.mu * dp_dd;
        dft_dv = -w * sign * law.mu * dp_dv;
        dft_dth = 0.0;
        dft_dom = 0.0;
    }
    let force = (w * p) * n + f_t * t;
    let torque = -rho * f_t;

    // ∂F/∂d = w n ∂p/∂d + w p t tᵀ/ρ + t ∂f_t/∂d − f_t n tᵀ/ρ
    let mut k = Matrix3::zeros();
    let mut c = Matrix3::zeros();
    for i in 0..2 {
        for j in 0..2 {
            k[(i, j)] = w * n[i] * dp_dd[j] + (w * p / rho) * t[i] * t[j] + t[i] * dft_dd[j]
                - (f_t / rho) * n[i] * t[j];
            c[(i, j)] = w * n[i] * dp_dv[j] + t[i] * dft_dv[j];
        }
        k[(i, 2)] = t[i] * dft_dth;
        c[(i, 2)] = t[i] * dft_dom;
    }
    // τ = −ρ f_t
    for j in 0..2 {
        k[(2, j)] = -f_t * n[j] - rho * dft_dd[j];
        c[(2, j)] = -rho * dft_dv[j];
    }
    k[(2, 2)] = -rho * dft_dth;
    c[(2, 2)] = -rho * dft_dom;

    Some(PointContact {
        force,
        torque,
        z,
        slipping,
        pressure: p,
        gap: g,
        slip_rate: sdot,
        normal_energy: 0.5 * law.k_n * g * g * w,
        dissipation: w * law.d_n * vn * vn - f_t * sdot,
        k,
        c,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law() -> ContactLaw {
        ContactLaw {
            k_n: 2e7,
            d_n: 3e3,
            k_t: 1e7,
            d_t: 1e3,
            mu: 0.3,
        }
    }

    fn circle() -> Circle {
        Circle {
            center: Vector2::new(0.2, -0.1),
            radius: 0.1,
        }
    }

    /// Finite-difference check of k and c for a state (stick or slip decided by the state).
    fn check_jacobians(s: PointState, h: PointHistory, expect_slip: bool) {
        let (law, cir, w) = (law(), circle(), 4e-3);
        let res = evaluate(&law, &cir, w, &s, &h).expect("in contact");
        assert_eq!(res.slipping, expect_slip);
        let out = |s: &PointState| {
            let r = evaluate(&law, &cir, w, s, &h).unwrap();
            nalgebra::Vector3::new(r.force.x, r.force.y, r.torque)
        };
        let eps = 1e-9;
        let scale = out(&s).norm();
        for j in 0..3 {
            let (mut sp, mut sm) = (s, s);
            match j {
                0 => {
                    sp.r.x += eps;
                    sm.r.x -= eps
                }
                1 => {
                    sp.r.y += eps;
                    sm.r.y -= eps
                }
                _ => {
                    sp.theta += eps;
                    sm.theta -= eps
                }
            }
            let fd = (out(&sp) - out(&sm)) / (2.0 * eps);
            let err = (fd - res.k.column(j)).norm();
            assert!(
                err <= 1e-6 * res.k.norm(),
                "k column {j}: {fd} vs {}",
                res.k.column(j)
            );
            let (mut sp, mut sm) = (s, s);
            match j {
                0 => {
                    sp.v.x += eps;
                    sm.v.x -= eps
                }
                1 => {
                    sp.v.y += eps;
                    sm.v.y -= eps
                }
                _ => {
                    sp.omega += eps;
                    sm.omega -= eps
                }
            }
            let fd = (out(&sp) - out(&sm)) / (2.0 * eps);
            let err = (fd - res.c.column(j)).norm();
            assert!(
                err <= 1e-6 * res.c.norm().max(scale),
                "c column {j}: {fd} vs {}",
                res.c.column(j)
            );
        }
    }

    fn at(angle: f64, rho: f64) -> Vector2<f64> {
        circle().center + rho * Vector2::new(angle.cos(), angle.sin())
    }

    #[test]
    fn stick_tangent_matches_finite_differences() {
        let s = PointState {
            r: at(0.7, 0.1 - 2e-5),
            v: Vector2::new(-0.3, 0.2),
            theta: 0.31,
            omega: 4.0,
        };
        let h = PointHistory {
            phi: 0.7 - 1e-4,
            theta: 0.3101,
            z: 1e-7,
        };
        check_jacobians(s, h, false);
    }

    #[test]
    fn slip_tangent_matches_finite_differences() {
        let s = PointState {
            r: at(2.2, 0.1 - 3e-5),
            v: Vector2::new(1.0, 0.5),
            theta: 1.0,
            omega: -3.0,
        };
        let h = PointHistory {
            phi: 2.1,
            theta: 0.9,
            z: 0.0,
        };
        check_jacobians(s, h, true);
    }

    /// Pure rolling at pitch radius: the point moves with the pulley, no friction force, the
    /// force is the normal pressure only.
    #[test]
    fn pure_rolling_has_no_friction() {
        let (law, cir) = (law(), circle());
        let rho = 0.1 - 1e-5;
        let omega = 5.0;
        let (th0, th1): (f64, f64) = (0.2, 0.25);
        let phi0: f64 = 1.0;
        let phi1 = phi0 + (th1 - th0);
        let n = Vector2::new(phi1.cos(), phi1.sin());
        let t = Vector2::new(-n.y, n.x);
        let s = PointState {
            r: at(phi1, rho),
            v: omega * rho * t,
            theta: th1,
            omega,
        };
        let h = PointHistory {
            phi: phi0,
            theta: th0,
            z: 0.0,
        };
        let r = evaluate(&law, &cir, 1e-2, &s, &h).unwrap();
        assert!(!r.slipping);
        assert!(r.torque.abs() < 1e-9, "{}", r.torque);
        assert!((r.force - 1e-2 * law.k_n * 1e-5 * n).norm() < 1e-9);
    }

    /// Sliding: tangential force = μ × normal force, opposing the slip; torque = ρ × friction.
    #[test]
    fn sliding_force_is_mu_times_normal_force() {
        let (law, cir) = (law(), circle());
        let s = PointState {
            r: at(0.0, 0.1 - 1e-4),
            v: Vector2::new(0.0, 0.0),
            theta: 0.0,
            omega: 0.0,
        };
        // the belt point moved by +1 mm along t (counter-clockwise) relative to the pulley
        let h = PointHistory {
            phi: -1e-3 / 0.1,
            theta: 0.0,
            z: 0.0,
        };
        let r = evaluate(&law, &cir, 1e-2, &s, &h).unwrap();
        assert!(r.slipping);
        let fn_ = 1e-2 * law.k_n * 1e-4;
        assert!((r.force.x - fn_).abs() < 1e-9);
        assert!((r.force.y + law.mu * fn_).abs() < 1e-9, "{}", r.force.y);
        assert!((r.torque - (0.1 - 1e-4) * law.mu * fn_).abs() < 1e-9);
        // out of contact: nothing
        let far = PointState {
            r: at(0.0, 0.1 + 1e-6),
            ..s
        };
        assert!(evaluate(&law, &cir, 1e-2, &far, &h).is_none());
    }

    #[test]
    fn wraps_angles() {
        assert!((wrap_angle(3.0 * std::f64::consts::PI) - std::f64::consts::PI).abs() < 1e-12);
        assert!((wrap_angle(-0.1) + 0.1).abs() < 1e-15);
        assert!((wrap_angle(6.2) - (6.2 - std::f64::consts::TAU)).abs() < 1e-12);
    }
}
