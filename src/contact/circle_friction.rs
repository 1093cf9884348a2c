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
//! * normal pressure per unit belt length `p = p_e(δ) − d_n ġ s(δ)` (`δ = −g`, `ġ = v·n`),
//!   active while `δ > 0` and `p > 0`; force on the belt `w p n` (`w` = belt length the point
//!   stands for). The penalty is smoothed over a small penetration `δ0`: `p_e = k_n δ²/(2δ0)`
//!   and `s = δ/δ0` for `δ < δ0`, `p_e = k_n (δ − δ0/2)` and `s = 1` beyond, so that the force
//!   is C¹ in the gap: a belt leaves and meets a pulley tangentially, points sit at `g ≈ 0`, and
//!   a kinked penalty makes Newton's method cycle between "in" and "out" there;
//! * relative slip of the belt over the pulley's pitch circle: increment over a step
//!   `Δs = ρ Δφ − R Δθ` (`φ` = polar angle of the point, `θ` = pulley angle), slip rate
//!   `ṡ = v·t − ω R`. The belt sticks when its centre line moves at the pitch circle's
//!   speed `ω R`, whatever the penalty penetration `δ = R − ρ`: the penetration regularizes
//!   the normal contact only and does not change the tangential kinematics (measured in
//!   `kinds::belt_drive::creep`: with the slip taken at the penetrated radius, `ρ (Δφ − Δθ)`,
//!   a stuck belt runs at `ω (R − δ)` and the creep of a drive is off by about `δ/R`, 20-120 %
//!   of Grashof's creep for the default penalty). Pure rolling of the pitch line
//!   (`ρ Δφ = R Δθ`) creates no force at any step size;
//! * friction per unit length: trial `f* = k_t (z_n + Δs) + d_t ṡ` (`z` = bristle deflection);
//!   stick if `|f*| ≤ μ p` (`f = f*`), else slip with `f = μ p sign(f*)`, blended C¹ over
//!   `|f*|/(μp) ∈ [1 − ε, 1 + ε]` ([`stick_slip`]); new deflection
//!   `z = (f/f*) (z_n + Δs)` ([`bristle_factor`]: a Kelvin–Voigt bristle); force on the
//!   belt `−w f t`, torque on the pulley `τ = R w f` (the moment arm of the pitch circle, so
//!   that the friction work `−w f Δs` is what belt and pulley lose: `−w f ρΔφ + τ Δθ`).

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
    /// Penetration over which the penalty stiffness ramps up from 0 to `k_n` [m] (0: a
    /// kinked penalty).
    pub smoothing: f64,
    /// Relative half width `ε` of the C¹ blend between stick and Coulomb sliding (see
    /// [`stick_slip`]; 0: exact elasto-plastic law).
    pub blend: f64,
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
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointHistory {
    /// Direction of the point from the pulley centre at the last accepted step, `r − c` [m]
    /// (any length > 0): the polar angle `φ` without an `atan2` per point and commit (issue
    /// 12 item 2, session 29); [`evaluate`] takes the angle turned since,
    /// `Δφ = atan2(d_n × d, d_n · d)`, which is `φ − φ_n` wrapped into (−π, π].
    pub dir: Vector2<f64>,
    /// Pulley angle at the last accepted step [rad].
    pub theta: f64,
    /// Bristle deflection [m] (0 out of contact).
    pub z: f64,
    /// Friction force per unit length `f` at the last accepted step [N/m] (0 out of contact).
    pub f: f64,
}

/// At rest: polar angle 0 (direction `+x`), pulley angle 0, no bristle deflection.
impl Default for PointHistory {
    fn default() -> Self {
        Self::at_angle(0.0, 0.0, 0.0, 0.0)
    }
}

impl PointHistory {
    /// The history of a point at polar angle `phi` [rad] about the centre, pulley angle
    /// `theta` [rad], bristle deflection `z` [m] and friction `f` [N/m].
    pub fn at_angle(phi: f64, theta: f64, z: f64, f: f64) -> Self {
        Self {
            dir: Vector2::new(phi.cos(), phi.sin()),
            theta,
            z,
            f,
        }
    }
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
    /// Elastic energy of the normal penalty `w ∫ p_e dδ` [J].
    pub normal_energy: f64,
    /// Dissipated power of the normal damping `w d_n s ġ²` [W].
    pub dissipation: f64,
    /// Friction force per unit length `f` (the belt receives `−w f t`) [N/m].
    pub friction: f64,
    /// Slip increment `Δs` since the last accepted step [m].
    pub slip_increment: f64,
    /// `∂(F_x, F_y, τ)/∂(r_x, r_y, θ)`.
    pub k: Matrix3<f64>,
    /// `∂(F_x, F_y, τ)/∂(v_x, v_y, ω)`.
    pub c: Matrix3<f64>,
}

/// The stick–slip map `φ(x)` for `x = |f*|/(μ p) ≥ 0` and its slope: `φ = x` (stick) for
/// `x ≤ 1 − ε`, `φ = 1` (Coulomb sliding) for `x ≥ 1 + ε`, and the C¹ quadratic
/// `1 − (1 + ε − x)²/(4ε)` between, so that the iteration matrix does not jump between the
/// stick stiffness and zero when a point changes state (a jump makes Newton's method cycle).
/// `ε = 0` gives the exact (kinked) elasto-plastic law.
#[inline]
pub fn stick_slip(x: f64, eps: f64) -> (f64, f64) {
    if x <= 1.0 - eps {
        (x, 1.0)
    } else if x >= 1.0 + eps {
        (1.0, 0.0)
    } else {
        let u = 1.0 + eps - x;
        (1.0 - u * u / (4.0 * eps), u / (2.0 * eps))
    }
}

/// The factor that turns the trial bristle deflection `z_n + Δs` into the committed one:
/// `z = (|f|/|f*|) (z_n + Δs)` for the returned friction `f` of the trial `f*`. The bristle
/// is a Kelvin–Voigt element, spring `k_t` and damper `d_t` in parallel: in stick (`f = f*`)
/// it keeps the whole trial deflection, in slip it gives back what the return mapping took
/// off `f*`, and the damper's share `d_t ṡ` never enters the spring. (Committing `z = f/k_t`
/// instead stores the damper's force in the spring: over a step `f` then grows by
/// `k_t Δs + d_t ṡ`, the damper acts as a stiffness `d_t/h`, and on the 3D belt of issue 13
/// it fed a growing step-to-step oscillation of the driver's arc that Newton could not follow:
/// 308 failed steps in 0.3 s at 120 elements, none with this factor.)
#[inline]
pub fn bristle_factor(f_norm: f64, f_trial_norm: f64) -> f64 {
    if f_trial_norm > 0.0 {
        f_norm / f_trial_norm
    } else {
        1.0
    }
}

/// Wraps an angle difference into (−π, π].
#[inline]
pub fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    // `a % TAU` is `a` itself for |a| < 2π (an exact remainder), without the call to fmod
    let mut x = if a.abs() < TAU { a } else { a % TAU };
    if x > PI {
        x -= TAU;
    } else if x <= -PI {
        x += TAU;
    }
    x
}

/// The smoothed normal penalty at the penetration `delta` > 0 [m]: elastic pressure `p_e`
/// [N/m per unit length, N/m² per unit area], its slope, the damping ramp `s` and its slope,
/// and the elastic energy density `∫ p_e dδ` (see the module notes). Shared by every obstacle.
#[inline]
pub fn smoothed_penalty(law: &ContactLaw, delta: f64) -> (f64, f64, f64, f64, f64) {
    let d0 = law.smoothing;
    if delta < d0 {
        (
            law.k_n * delta * delta / (2.0 * d0),
            law.k_n * delta / d0,
            delta / d0,
            1.0 / d0,
            law.k_n * delta.powi(3) / (6.0 * d0),
        )
    } else {
        (
            law.k_n * (delta - 0.5 * d0),
            law.k_n,
            1.0,
            0.0,
            law.k_n * (0.5 * delta * delta - 0.5 * d0 * delta + d0 * d0 / 6.0),
        )
    }
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
    let delta = -g;
    let (vn, vt) = (s.v.dot(&n), s.v.dot(&t));
    let (pe, dpe, ramp, dramp, ue) = smoothed_penalty(law, delta);
    let p = pe - law.d_n * vn * ramp;
    if p <= 0.0 {
        return None;
    }
    // ∂p/∂d, ∂p/∂v (row vectors as 2-vectors); ∂δ/∂d = −n, ∂ġ/∂d = (v·t)/ρ t
    let dp_dd = -(dpe - law.d_n * vn * dramp) * n - (law.d_n * ramp * vt / rho) * t;
    let dp_dv = -law.d_n * ramp * n;

    // Slip increment and rate over the pitch circle (radius R).
    let big_r = circle.radius;
    let dn = hist.dir;
    let dphi = (dn.x * d.y - dn.y * d.x).atan2(dn.x * d.x + dn.y * d.y);
    let dtheta = s.theta - hist.theta;
    let ds = rho * dphi - big_r * dtheta;
    let sdot = vt - s.omega * big_r;
    let z_trial = hist.z + ds;
    let f_trial = law.k_t * z_trial + law.d_t * sdot;
    let cap = law.mu * p;
    // derivatives of the trial force
    let dds_dd = dphi * n + t;
    let dsdot_dd = -(vn / rho) * t;
    let dftr_dd = law.k_t * dds_dd + law.d_t * dsdot_dd;
    let dftr_dv = law.d_t * t;
    let dftr_dth = -law.k_t * big_r;
    let dftr_dom = -law.d_t * big_r;
    // f = cap φ(f*/cap): ∂f = φ' ∂f* + (φ − x φ') ∂cap, ∂cap = μ ∂p
    let (f, dphi_dx, rest) = if cap > 0.0 {
        let x = f_trial / cap;
        let (ph, dph) = stick_slip(x.abs(), law.blend);
        let ph = ph.copysign(x);
        (cap * ph, dph, ph - x * dph)
    } else {
        (0.0, 0.0, 0.0)
    };
    let slipping = cap <= 0.0 || f_trial.abs() >= cap;
    let z = if law.k_t > 0.0 {
        bristle_factor(f.abs(), f_trial.abs()) * z_trial
    } else {
        0.0
    };
    // friction force on the belt along t: f_t = −w f
    let f_t = -w * f;
    let dft_dd = -w * (dphi_dx * dftr_dd + rest * law.mu * dp_dd);
    let dft_dv = -w * (dphi_dx * dftr_dv + rest * law.mu * dp_dv);
    let dft_dth = -w * dphi_dx * dftr_dth;
    let dft_dom = -w * dphi_dx * dftr_dom;
    let force = (w * p) * n + f_t * t;
    let torque = -big_r * f_t;

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
    // τ = −R f_t
    for j in 0..2 {
        k[(2, j)] = -big_r * dft_dd[j];
        c[(2, j)] = -big_r * dft_dv[j];
    }
    k[(2, 2)] = -big_r * dft_dth;
    c[(2, 2)] = -big_r * dft_dom;

    Some(PointContact {
        force,
        torque,
        z,
        slipping,
        pressure: p,
        gap: g,
        slip_rate: sdot,
        normal_energy: ue * w,
        dissipation: w * law.d_n * ramp * vn * vn,
        friction: f,
        slip_increment: ds,
        k,
        c,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::finite_difference as fd;

    use crate::contact::test_laws::belt as law;

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
        let scale = out(&s).norm();
        // coordinates (r_x, r_y, θ) and rates (v_x, v_y, ω) as vectors
        let with = |x: &[f64], rates: bool| {
            let mut p = s;
            if rates {
                (p.v.x, p.v.y, p.omega) = (x[0], x[1], x[2]);
            } else {
                (p.r.x, p.r.y, p.theta) = (x[0], x[1], x[2]);
            }
            p
        };
        let dm =
            |m: &nalgebra::Matrix3<f64>| nalgebra::DMatrix::from_column_slice(3, 3, m.as_slice());
        fd::assert_jacobian(
            "k",
            &dm(&res.k),
            &[s.r.x, s.r.y, s.theta],
            1e-9,
            2e-6,
            |x, o| o.copy_from_slice(out(&with(x, false)).as_slice()),
        );
        let cfd = fd::jacobian(
            &[s.v.x, s.v.y, s.omega],
            3,
            |_| 1e-9,
            |x, o| o.copy_from_slice(out(&with(x, true)).as_slice()),
        );
        fd::assert_close("c", &dm(&res.c), &cfd, 2e-6, scale);
    }

    fn at(angle: f64, rho: f64) -> Vector2<f64> {
        circle().center + rho * Vector2::new(angle.cos(), angle.sin())
    }

    /// A point that sticks while it slides slowly on the rim (slip rate ≠ 0).
    fn sticking() -> (PointState, PointHistory) {
        let s = PointState {
            r: at(0.7, 0.1 - 2e-5),
            v: Vector2::new(-0.3, 0.2),
            theta: 0.31,
            omega: 4.0,
        };
        let h = PointHistory::at_angle(0.7 - 1e-4, 0.3101, 1e-7, 0.0);
        (s, h)
    }

    #[test]
    fn stick_tangent_matches_finite_differences() {
        let (s, h) = sticking();
        check_jacobians(s, h, false);
    }

    /// Inside the smoothing zone of the penalty (δ < δ0).
    #[test]
    fn tangent_in_the_smoothing_zone() {
        let s = PointState {
            r: at(-0.4, 0.1 - 2e-6),
            v: Vector2::new(0.1, 0.3),
            theta: 0.0,
            omega: 2.0,
        };
        let h = PointHistory::at_angle(-0.4 + 2e-4, 0.0, 0.0, 0.0);
        check_jacobians(s, h, true);
        let s2 = PointState {
            r: at(-0.4, 0.1 - 2e-6),
            v: Vector2::new(0.0, 0.0),
            theta: 0.0,
            omega: 0.0,
        };
        let h2 = PointHistory::at_angle(-0.4, 0.0, 1e-9, 0.0);
        check_jacobians(s2, h2, false);
    }

    #[test]
    fn slip_tangent_matches_finite_differences() {
        let s = PointState {
            r: at(2.2, 0.1 - 3e-5),
            v: Vector2::new(1.0, 0.5),
            theta: 1.0,
            omega: -3.0,
        };
        let h = PointHistory::at_angle(2.1, 0.9, 0.0, 0.0);
        check_jacobians(s, h, true);
    }

    /// Pure rolling of the pitch line: a point pressed in by δ that moves at the pitch
    /// circle's speed `ω R` (`ρ Δφ = R Δθ`) feels no friction force, only the normal
    /// pressure; a point turning rigidly with the pulley at the penetrated radius slips by
    /// `Δs = −δ Δθ` and is pushed forward.
    #[test]
    fn pure_rolling_has_no_friction() {
        let (law, cir) = (law(), circle());
        let rho = 0.1 - 1e-5;
        let omega = 5.0;
        let (th0, th1): (f64, f64) = (0.2, 0.25);
        let phi0: f64 = 1.0;
        let phi1 = phi0 + (th1 - th0) * cir.radius / rho;
        let n = Vector2::new(phi1.cos(), phi1.sin());
        let t = Vector2::new(-n.y, n.x);
        let s = PointState {
            r: at(phi1, rho),
            v: omega * cir.radius * t,
            theta: th1,
            omega,
        };
        let rigid = PointState {
            r: at(phi0 + (th1 - th0), rho),
            v: omega * rho * t,
            ..s
        };
        let hist = PointHistory::at_angle(phi0, th0, 0.0, 0.0);
        let r = evaluate(&law, &cir, 1e-2, &rigid, &hist).unwrap();
        assert!(
            (r.slip_increment + 1e-5 * (th1 - th0)).abs() < 1e-12,
            "{}",
            r.slip_increment
        );
        assert!(r.torque < 0.0, "the pulley is held back: {}", r.torque);
        let h = PointHistory::at_angle(phi0, th0, 0.0, 0.0);
        let r = evaluate(&law, &cir, 1e-2, &s, &h).unwrap();
        assert!(!r.slipping);
        assert!(r.torque.abs() < 1e-9, "{}", r.torque);
        let expect = 1e-2 * law.k_n * (1e-5 - 0.5 * law.smoothing);
        assert!((r.force - expect * n).norm() < 1e-9);
    }

    /// Sliding: tangential force = μ × normal force, opposing the slip; torque = R × friction.
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
        let h = PointHistory::at_angle(-1e-3 / 0.1, 0.0, 0.0, 0.0);
        let r = evaluate(&law, &cir, 1e-2, &s, &h).unwrap();
        assert!(r.slipping);
        let fn_ = 1e-2 * law.k_n * (1e-4 - 0.5 * law.smoothing);
        assert!((r.force.x - fn_).abs() < 1e-9);
        assert!((r.force.y + law.mu * fn_).abs() < 1e-9, "{}", r.force.y);
        assert!((r.torque - 0.1 * law.mu * fn_).abs() < 1e-9);
        // out of contact: nothing
        let far = PointState {
            r: at(0.0, 0.1 + 1e-6),
            ..s
        };
        assert!(evaluate(&law, &cir, 1e-2, &far, &h).is_none());
    }

    /// In the blend zone between stick and slip (|f*| ≈ μ p).
    #[test]
    fn tangent_in_the_stick_slip_blend() {
        let law = law();
        // find a slip increment that puts f* at 1.02 μ p: f* = k_t ρ Δφ, p ≈ k_n (δ − δ0/2)
        let delta = 2e-5;
        let p = law.k_n * (delta - 0.5 * law.smoothing);
        let dphi = 1.02 * law.mu * p / (law.k_t * (0.1 - delta));
        let s = PointState {
            r: at(1.0, 0.1 - delta),
            v: Vector2::zeros(),
            theta: 0.0,
            omega: 0.0,
        };
        let h = PointHistory::at_angle(1.0 - dphi, 0.0, 0.0, 0.0);
        let r = evaluate(&law, &circle(), 1e-3, &s, &h).unwrap();
        let ratio =
            -r.force.dot(&Vector2::new(-(1.0f64).sin(), 1.0f64.cos())) / (1e-3 * law.mu * p);
        assert!(ratio > 0.99 && ratio < 1.0, "{ratio}");
        check_jacobians(s, h, true);
        // the map is C¹ at both ends of the blend
        for x in [0.95, 1.05] {
            let (a, da) = stick_slip(x - 1e-9, 0.05);
            let (b, db) = stick_slip(x + 1e-9, 0.05);
            assert!((a - b).abs() < 1e-8 && (da - db).abs() < 1e-6);
        }
    }

    /// The committed bristle deflection is the spring's (Kelvin–Voigt bristle,
    /// [`bristle_factor`]): in stick the trial deflection `z_n + Δs` whatever the damper
    /// carries, in slip the same deflection scaled by `f/f*`, so that the spring never holds
    /// more than the friction limit.
    #[test]
    fn committed_bristle_is_the_spring_deflection() {
        let law = law();
        let (stick, h) = sticking();
        let r = evaluate(&law, &circle(), 4e-3, &stick, &h).unwrap();
        assert!(!r.slipping && r.slip_rate.abs() > 1e-3, "{r:?}");
        assert!((r.z - (h.z + r.slip_increment)).abs() <= 1e-15);
        // f/k_t would have stored the damper's force d_t ṡ as a deflection
        let damper = law.d_t * r.slip_rate / law.k_t;
        assert!((r.friction / law.k_t - r.z - damper).abs() <= 1e-9 * damper.abs());
        // slip: the trial scaled back onto the limit
        let slip = PointState {
            omega: 40.0,
            ..stick
        };
        let r = evaluate(&law, &circle(), 4e-3, &slip, &h).unwrap();
        assert!(r.slipping, "{r:?}");
        let z_trial = h.z + r.slip_increment;
        let f_trial = law.k_t * z_trial + law.d_t * r.slip_rate;
        assert!((r.z - z_trial * r.friction / f_trial).abs() <= 1e-12 * z_trial.abs());
        assert!(law.k_t * r.z.abs() < law.mu * r.pressure);
    }

    #[test]
    fn wraps_angles() {
        assert!((wrap_angle(3.0 * std::f64::consts::PI) - std::f64::consts::PI).abs() < 1e-12);
        assert!((wrap_angle(-0.1) + 0.1).abs() < 1e-15);
        assert!((wrap_angle(6.2) - (6.2 - std::f64::consts::TAU)).abs() < 1e-12);
    }
}
