//! A pulley in space as an obstacle of the contact point set: centre, axis direction, radius,
//! a flat or crowned rim of finite width and optional flanges, turning by its angle θ about its
//! axis (its one coordinate). The point is a material point of a belt's centre line; the belt
//! has a half width `b` (its edges meet the flanges) and its centre line runs at the pitch
//! radius `R` = pulley radius + half the belt thickness.
//!
//! The planar kernel [`super::circle_friction`] extended to 3D (same penalty, same smoothed
//! normal law [`smoothed_penalty`], same return mapping [`stick_slip`], Wriggers,
//! Computational Contact Mechanics, 2nd ed., §5.2, now with a two-component bristle):
//!
//! * geometry: `d = r − c`, axial coordinate `ζ = a·d`, radial vector `d_r = d − ζ a`,
//!   `ρ = |d_r|`, `e = d_r/ρ`, circumferential tangent `t = a × e`; polar angle `φ` about `a`
//!   in a fixed basis `(u₁, u₂ = a × u₁)`;
//! * rim: radius of the pitch surface `R(ζ) = R − h_c (ζ/h)²` for `|ζ| ≤ h` (`h` = rim half
//!   width, `h_c` = crown height; continued by its tangent line beyond `h`), gap
//!   `g = ρ − R(ζ)`, contact while `g < 0` and the belt still rests on the rim
//!   (`|ζ| < h + b`). The normal force derives from the penalty potential of `g`:
//!   `F_n = w p ∇g`, `∇g = e − R'(ζ) a` (so a crowned rim pushes a point down its slope,
//!   conservative), `p = p_e(δ) − d_n ġ s(δ)`, `δ = −g`, `ġ = v·∇g`;
//! * rim friction in the surface basis `(t, a)`: slip increment since the last accepted step
//!   `Δs = (ρ Δφ − R(ζ) Δθ, Δζ)`, slip rate `ṡ = (v·t − ω R(ζ), v·a)`: the belt sticks when
//!   its centre line moves at the pitch surface's speed `ω R(ζ)`, whatever the penalty
//!   penetration (as the planar kernel: slip at the penetrated radius `ρ` makes a stuck belt
//!   run at `ω ρ` and shifts the creep by `δ/R`); trial
//!   `f* = k_t (z_n + Δs) + d_t ṡ` (a 2-vector), return mapping on its length:
//!   `f = μ p φ(|f*|/(μ p)) f*/|f*|` with the C¹ blend `φ` of [`stick_slip`]; new bristle
//!   `z = (|f|/|f*|)(z_n + Δs)` ([`bristle_factor`]); force on the belt `−w (f₁ t + f₂ a)`,
//!   torque on the pulley about its axis `τ = R(ζ) w f₁` (the pitch surface's arm, so that the
//!   friction work `−w f·Δs` is what belt and pulley lose; the axial component has no moment
//!   about the axis);
//! * flanges (height `h_f` > 0): at `ζ = ±h` the belt edge `ζ ± b` meets the flange face
//!   while `ρ` is below the flange top; penetration `δ_f = ±ζ + b − h`, frictionless normal
//!   force `∓ w p_f a` with the same smoothed penalty.
//!
//! Rim-edge and flange-top cut-offs are discontinuous: a belt falling off the rim or jumping a
//! flange is not a smooth event, and nothing is meant to run there.

use super::circle_friction::{
    ContactLaw, bristle_factor, smoothed_penalty, stick_slip, wrap_angle,
};
use super::obstacle::{ContactHistory, Obstacle, ObstacleContact, PointMotion};
use crate::snapshot::{SnapshotError, StateReader, StateWriter};
use nalgebra::{Matrix2, Matrix4, RowVector3, SVector, Vector2, Vector3};

/// A pulley in space as the contact sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pulley3d {
    /// Centre (middle of the rim on the axis) [m].
    pub center: Vector3<f64>,
    /// Unit axis; the pulley angle θ turns counter-clockwise about it.
    pub axis: Vector3<f64>,
    /// Pitch radius `R` of the belt centre line at the middle of the rim = pulley radius +
    /// half the belt thickness [m].
    pub radius: f64,
    /// Half width of the rim `h` (flange faces at `ζ = ±h`) [m].
    pub half_width: f64,
    /// Crown height `h_c`: the rim's radius at its middle minus that at its edges [m].
    pub crown: f64,
    /// Radius of the flange tops about the axis [m]; flanges act only if greater than the
    /// pitch radius (no flanges: 0).
    pub flange_top: f64,
    /// Half width of the belt `b` [m].
    pub belt_half_width: f64,
    /// First basis vector of the polar angle, perpendicular to the axis.
    u1: Vector3<f64>,
}

impl Pulley3d {
    /// A pulley at `center` with axis direction `axis` (normalized here).
    pub fn new(
        center: Vector3<f64>,
        axis: Vector3<f64>,
        radius: f64,
        half_width: f64,
        crown: f64,
        flange_top: f64,
        belt_half_width: f64,
    ) -> Self {
        let a = axis.normalize();
        let k = a.iamin();
        let mut u = Vector3::zeros();
        u[k] = 1.0;
        let u1 = (u - a.dot(&u) * a).normalize();
        Self {
            center,
            axis: a,
            radius,
            half_width,
            crown,
            flange_top,
            belt_half_width,
            u1,
        }
    }

    /// Axial position ζ, radius ρ, radial unit vector `e` and tangent `t` of the point `r`.
    #[inline]
    fn frame(&self, r: &Vector3<f64>) -> (f64, f64, Vector3<f64>, Vector3<f64>) {
        let d = r - self.center;
        let zeta = self.axis.dot(&d);
        let dr = d - zeta * self.axis;
        let rho = dr.norm();
        let e = if rho > 0.0 { dr / rho } else { self.u1 };
        let t = self.axis.cross(&e);
        (zeta, rho, e, t)
    }

    /// [`Self::frame`] and the radial vector `d_r` of the point `r`.
    #[inline]
    fn frame_radial(&self, r: &Vector3<f64>) -> (PointFrame, Vector3<f64>) {
        let (zeta, rho, dr) = self.radial(r);
        (self.frame_of(zeta, rho, &dr), dr)
    }

    /// Axial position ζ, radius ρ and radial vector `d_r` of the point `r`: the part of
    /// [`Self::frame_radial`] the contact tests need.
    #[inline(always)]
    fn radial(&self, r: &Vector3<f64>) -> (f64, f64, Vector3<f64>) {
        let d = r - self.center;
        let zeta = self.axis.dot(&d);
        let dr = d - zeta * self.axis;
        (zeta, dr.norm(), dr)
    }

    /// The frame of a point with axial position `zeta`, radius `rho`, radial vector `dr`
    /// ([`Self::radial`]).
    #[inline(always)]
    fn frame_of(&self, zeta: f64, rho: f64, dr: &Vector3<f64>) -> PointFrame {
        let e = if rho > 0.0 { dr / rho } else { self.u1 };
        let t = self.axis.cross(&e);
        PointFrame { zeta, rho, e, t }
    }

    /// Polar angle φ [rad] about the axis from `u1` of a point with radial vector `dr` (an
    /// `atan2`: only where the slip or the history needs it, after the gap test).
    #[inline]
    fn polar_angle_of(&self, dr: &Vector3<f64>) -> f64 {
        let [x, y] = self.polar_components(dr);
        y.atan2(x)
    }

    /// Components `(d_r·u1, d_r·u2)` of a radial vector in the basis of the polar angle.
    #[inline]
    fn polar_components(&self, dr: &Vector3<f64>) -> [f64; 2] {
        let u2 = self.axis.cross(&self.u1);
        [dr.dot(&self.u1), dr.dot(&u2)]
    }

    /// Pitch radius of the rim at axial position ζ: `R(ζ)`, `R'`, `R''` [m, 1, 1/m].
    #[inline]
    pub fn rim_radius(&self, zeta: f64) -> (f64, f64, f64) {
        let (h, hc) = (self.half_width, self.crown);
        if hc == 0.0 || h <= 0.0 {
            return (self.radius, 0.0, 0.0);
        }
        if zeta.abs() <= h {
            let s = zeta / h;
            (
                self.radius - hc * s * s,
                -2.0 * hc * zeta / (h * h),
                -2.0 * hc / (h * h),
            )
        } else {
            // tangent continuation: R(h) + R'(h)(|ζ| − h)
            let sg = zeta.signum();
            (
                self.radius - hc - 2.0 * hc / h * (zeta.abs() - h),
                -2.0 * hc / h * sg,
                0.0,
            )
        }
    }

    /// Gap `ρ − R(ζ)` of the point `r` to the pitch surface of the rim [m] (negative:
    /// penetration; the rim's width is not checked).
    #[inline]
    pub fn rim_gap(&self, r: &Vector3<f64>) -> f64 {
        let (zeta, rho, ..) = self.frame(r);
        rho - self.rim_radius(zeta).0
    }

    /// The point `r` moved along the rim's radial direction (at its own axial position ζ and
    /// polar angle) to the gap `gap` from the pitch surface [m].
    #[inline]
    pub fn at_rim_gap(&self, r: &Vector3<f64>, gap: f64) -> Vector3<f64> {
        let (zeta, _, e, _) = self.frame(r);
        self.center + zeta * self.axis + (self.rim_radius(zeta).0 + gap) * e
    }

    /// First basis vector of the polar angle (perpendicular to the axis).
    pub fn u1(&self) -> Vector3<f64> {
        self.u1
    }

    /// Axial position of the point `r` on the rim, measured from the rim's middle [m] (the
    /// belt's lateral position on this pulley).
    pub fn lateral(&self, r: &Vector3<f64>) -> f64 {
        self.axis.dot(&(r - self.center))
    }
}

/// Axial position ζ, radius ρ, radial unit vector `e` and tangent `t` of a point.
#[derive(Clone, Copy, Debug)]
struct PointFrame {
    zeta: f64,
    rho: f64,
    e: Vector3<f64>,
    t: Vector3<f64>,
}

/// Committed history of one (belt point, 3D pulley) pair.
///
/// A pair out of contact at the commit keeps its polar angle untaken (an `atan2` per pair and
/// step, most of them never needed): `phi` is NaN and `z` holds the components `(d_r·u1,
/// d_r·u2)` of the point's radial vector, whose `atan2` is the angle
/// ([`Self::polar_angle`], the same operations as an angle taken at the commit); its bristle
/// deflection is zero ([`Self::bristle`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pulley3dHistory {
    /// Polar angle of the point about the axis at the last accepted step [rad] (NaN: not
    /// taken, see the type's notes).
    pub phi: f64,
    /// Axial position of the point at the last accepted step [m].
    pub zeta: f64,
    /// Pulley angle at the last accepted step [rad].
    pub theta: f64,
    /// Bristle deflection (circumferential, axial) [m] (0 out of contact; the radial
    /// components [m] while `phi` is NaN).
    pub z: [f64; 2],
    /// Friction per unit length (circumferential, axial) at the last accepted step [N/m].
    pub f: [f64; 2],
}

impl Pulley3dHistory {
    /// Polar angle of the point about the axis at the last accepted step [rad] (taken here
    /// for a pair that was out of contact).
    #[inline]
    pub fn polar_angle(&self) -> f64 {
        if self.phi.is_nan() {
            self.z[1].atan2(self.z[0])
        } else {
            self.phi
        }
    }

    /// Bristle deflection (circumferential, axial) at the last accepted step [m].
    #[inline]
    pub fn bristle(&self) -> [f64; 2] {
        if self.phi.is_nan() { [0.0; 2] } else { self.z }
    }
}

impl ContactHistory for Pulley3dHistory {
    fn save(&self, w: &mut StateWriter) {
        for x in [
            self.phi, self.zeta, self.theta, self.z[0], self.z[1], self.f[0], self.f[1],
        ] {
            w.f64(x);
        }
    }

    fn restore(r: &mut StateReader) -> Result<Self, SnapshotError> {
        Ok(Self {
            phi: r.f64()?,
            zeta: r.f64()?,
            theta: r.f64()?,
            z: [r.f64()?, r.f64()?],
            f: [r.f64()?, r.f64()?],
        })
    }
}

/// Result of an active point against a 3D pulley (`Default`: all zero, a buffer for
/// [`evaluate_parts_into`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pulley3dContact {
    /// Force on the belt point [N].
    pub force: Vector3<f64>,
    /// Torque on the pulley about its axis [N m].
    pub torque: f64,
    /// Moment of the force on the pulley about its centre [N m].
    pub moment: Vector3<f64>,
    /// Axial force of the flanges on the belt point [N] (0 off the flanges).
    pub flange_force: f64,
    /// Whether the point slips on the rim.
    pub slipping: bool,
    /// Rim pressure [N/m] (0 off the rim).
    pub pressure: f64,
    /// New bristle deflection (circumferential, axial) [m].
    pub z: [f64; 2],
    /// Friction per unit length (circumferential, axial) [N/m].
    pub friction: [f64; 2],
    /// Slip increment since the last accepted step (circumferential, axial) [m].
    pub slip_increment: [f64; 2],
    /// Elastic energy of the normal penalties [J].
    pub normal_energy: f64,
    /// Dissipated power of the normal damping [W].
    pub dissipation: f64,
    /// Polar angle of the point about the axis [rad] (the history's `phi`).
    pub phi: f64,
    /// `∂(F, τ)/∂(r, θ)`.
    pub k: Matrix4<f64>,
    /// `∂(F, τ)/∂(v, ω)`.
    pub c: Matrix4<f64>,
}

/// The rim contact of a point: its force and torque and, with `tangent`, their derivatives
/// added into `res`, and its polar angle `res.phi` (from the radial vector `dr` of the frame
/// `fr`); returns whether the rim touches. Without `tangent` (a residual-only
/// evaluation: modified Newton's kept matrix, the line search) `res.k`, `res.c` are left
/// alone; every other output is computed by the same operations either way.
#[allow(clippy::too_many_arguments)]
fn rim(
    pul: &Pulley3d,
    law: &ContactLaw,
    w: f64,
    p: &PointMotion<3>,
    theta: f64,
    omega: f64,
    hist: &Pulley3dHistory,
    (fr, dr): (&PointFrame, &Vector3<f64>),
    tangent: bool,
    res: &mut Pulley3dContact,
) -> bool {
    let a = pul.axis;
    let PointFrame { zeta, rho, e, t } = *fr;
    if zeta.abs() >= pul.half_width + pul.belt_half_width || rho <= 0.0 {
        return false;
    }
    let (rz, drz, ddrz) = pul.rim_radius(zeta);
    let g = rho - rz;
    if g >= 0.0 {
        return false;
    }
    let delta = -g;
    let ng = e - drz * a;
    let v = p.v;
    let (vt, va, ve) = (v.dot(&t), v.dot(&a), v.dot(&e));
    let gdot = v.dot(&ng);
    let (pe, dpe, ramp, dramp, ue) = smoothed_penalty(law, delta);
    let pr = pe - law.d_n * gdot * ramp;
    if pr <= 0.0 {
        return false;
    }
    // the polar angle (an `atan2`) only for a point that presses on the rim
    res.phi = pul.polar_angle_of(dr);

    // slip increment and rate in (t, a)
    let dphi = wrap_angle(res.phi - hist.polar_angle());
    let dtheta = theta - hist.theta;
    let ds = Vector2::new(rho * dphi - rz * dtheta, zeta - hist.zeta);
    let sdot = Vector2::new(vt - omega * rz, va);
    let ftr = law.k_t * (Vector2::from(hist.bristle()) + ds) + law.d_t * sdot;

    // return mapping: f = cap φ(x) f*/|f*|, x = |f*|/cap
    let cap = law.mu * pr;
    let nf = ftr.norm();
    let stick = cap > 0.0 && nf <= (1.0 - law.blend) * cap;
    let f = if cap <= 0.0 {
        Vector2::zeros()
    } else if stick {
        ftr
    } else {
        let x = nf / cap;
        let (ph, _) = stick_slip(x, law.blend);
        cap * ph * (ftr / nf)
    };

    // F = w p ∇g − w f₁ t − w f₂ a; τ = ρ w f₁
    let force = (w * pr) * ng - (w * f[0]) * t - (w * f[1]) * a;
    let torque = rz * w * f[0];
    if tangent {
        let tt: RowVector3<f64> = t.transpose();
        let at: RowVector3<f64> = a.transpose();
        let et: RowVector3<f64> = e.transpose();
        // ∂ġ/∂d = (v·t/ρ) tᵀ − R'' (v·a) aᵀ; ∂p/∂d = −(p_e' − d_n ġ s') ∇gᵀ − d_n s ∂ġ/∂d
        let dgdot_dd = (vt / rho) * tt - (ddrz * va) * at;
        let dp_dd = -(dpe - law.d_n * gdot * dramp) * ng.transpose() - (law.d_n * ramp) * dgdot_dd;
        let dp_dv = -(law.d_n * ramp) * ng.transpose();
        // rows of ∂f*/∂(d, θ) and ∂f*/∂(v, ω)
        let mut dftr_dd = nalgebra::Matrix2x3::zeros();
        let mut dftr_dv = nalgebra::Matrix2x3::zeros();
        dftr_dd.set_row(
            0,
            &(law.k_t * (dphi * et + tt - (dtheta * drz) * at)
                + law.d_t * (-(ve / rho) * tt - (omega * drz) * at)),
        );
        dftr_dd.set_row(1, &(law.k_t * at));
        dftr_dv.set_row(0, &(law.d_t * tt));
        dftr_dv.set_row(1, &(law.d_t * at));
        let dftr_dth = Vector2::new(-law.k_t * rz, 0.0);
        let dftr_dom = Vector2::new(-law.d_t * rz, 0.0);
        let (df, dcap) = if cap <= 0.0 {
            (Matrix2::zeros(), Vector2::zeros())
        } else if stick {
            (Matrix2::identity(), Vector2::zeros())
        } else {
            let x = nf / cap;
            let (ph, dph) = stick_slip(x, law.blend);
            let eh = ftr / nf;
            let ee = eh * eh.transpose();
            (
                dph * ee + (ph / x) * (Matrix2::identity() - ee),
                (ph - x * dph) * eh,
            )
        };
        // ∂f = df ∂f* + dcap μ ∂p
        let df_dd = df * dftr_dd + dcap * (law.mu * dp_dd);
        let df_dv = df * dftr_dv + dcap * (law.mu * dp_dv);
        let df_dth = df * dftr_dth;
        let df_dom = df * dftr_dom;
        // ∂∇g/∂d = t tᵀ/ρ − R'' a aᵀ; ∂t/∂d = −e tᵀ/ρ
        let k_dd = w * ng * dp_dd + (w * pr) * (t * tt / rho - ddrz * a * at)
            - w * t * df_dd.row(0)
            + (w * f[0] / rho) * e * tt
            - w * a * df_dd.row(1);
        let k_dth = -w * t * df_dth[0] - w * a * df_dth[1];
        let c_dv = w * ng * dp_dv - w * t * df_dv.row(0) - w * a * df_dv.row(1);
        let c_dom = -w * t * df_dom[0] - w * a * df_dom[1];
        let tq_dd = (w * f[0] * drz) * at + (rz * w) * df_dd.row(0);
        let tq_dv = (rz * w) * df_dv.row(0);
        for i in 0..3 {
            for j in 0..3 {
                res.k[(i, j)] += k_dd[(i, j)];
                res.c[(i, j)] += c_dv[(i, j)];
            }
            res.k[(i, 3)] += k_dth[i];
            res.c[(i, 3)] += c_dom[i];
            res.k[(3, i)] += tq_dd[i];
            res.c[(3, i)] += tq_dv[i];
        }
        res.k[(3, 3)] += rz * w * df_dth[0];
        res.c[(3, 3)] += rz * w * df_dom[0];
    }

    res.force += force;
    res.torque += torque;
    res.pressure = pr;
    res.slipping = cap <= 0.0 || nf >= cap;
    res.z = if law.k_t > 0.0 {
        let zt = (Vector2::from(hist.bristle()) + ds) * bristle_factor(f.norm(), nf);
        [zt[0], zt[1]]
    } else {
        [0.0; 2]
    };
    res.friction = [f[0], f[1]];
    res.slip_increment = [ds[0], ds[1]];
    res.normal_energy += w * ue;
    res.dissipation += w * law.d_n * ramp * gdot * gdot;
    true
}

/// The flange contacts of a point (frictionless normal force along the axis and, with
/// `tangent`, its derivatives) added into `res`; returns whether a flange touches.
fn flanges(
    pul: &Pulley3d,
    law: &ContactLaw,
    w: f64,
    p: &PointMotion<3>,
    fr: &PointFrame,
    tangent: bool,
    res: &mut Pulley3dContact,
) -> bool {
    if pul.flange_top <= pul.radius {
        return false;
    }
    let a = pul.axis;
    let (zeta, rho) = (fr.zeta, fr.rho);
    if rho >= pul.flange_top {
        return false;
    }
    let mut any = false;
    for s in [1.0, -1.0] {
        let delta = s * zeta + pul.belt_half_width - pul.half_width;
        if delta <= 0.0 {
            continue;
        }
        let ddot = s * p.v.dot(&a);
        let (pe, dpe, ramp, dramp, ue) = smoothed_penalty(law, delta);
        let pf = pe - law.d_n * ddot * ramp;
        if pf <= 0.0 {
            continue;
        }
        any = true;
        // F = −s w p_f a; ∂p_f/∂d = s (p_e' − d_n δ̇ s') aᵀ, ∂p_f/∂v = −d_n s_r s aᵀ
        res.force -= (s * w * pf) * a;
        res.flange_force -= s * w * pf;
        if tangent {
            let aa = a * a.transpose();
            let kf = -w * (dpe - law.d_n * ddot * dramp) * aa;
            let cf = (w * law.d_n * ramp) * aa;
            for i in 0..3 {
                for j in 0..3 {
                    res.k[(i, j)] += kf[(i, j)];
                    res.c[(i, j)] += cf[(i, j)];
                }
            }
        }
        res.normal_energy += w * ue;
        res.dissipation += w * law.d_n * ramp * ddot * ddot;
    }
    any
}

/// Contact of a belt point standing for the length `w` [m] with the pulley at angle `theta`
/// turning at `omega`, history `hist`; `None` when neither rim nor flanges touch.
pub fn evaluate(
    pul: &Pulley3d,
    law: &ContactLaw,
    w: f64,
    p: &PointMotion<3>,
    theta: f64,
    omega: f64,
    hist: &Pulley3dHistory,
) -> Option<Pulley3dContact> {
    evaluate_parts(pul, law, w, w, p, theta, omega, hist, true)
}

/// [`evaluate`] with separate weights of the rim contact `w_rim` [m] (the belt length, or
/// the share of the section, the point stands for) and of the flange contact `w_flange` [m]
/// (the belt length whose edge the point is; 0: the point does not touch the flanges).
/// Without `tangent` the derivatives `k`, `c` are not computed (left zero); the other
/// outputs are those of the evaluation with them.
#[allow(clippy::too_many_arguments)]
pub fn evaluate_parts(
    pul: &Pulley3d,
    law: &ContactLaw,
    w_rim: f64,
    w_flange: f64,
    p: &PointMotion<3>,
    theta: f64,
    omega: f64,
    hist: &Pulley3dHistory,
    tangent: bool,
) -> Option<Pulley3dContact> {
    let mut res = Pulley3dContact::default();
    evaluate_parts_into(
        pul, law, w_rim, w_flange, p, theta, omega, hist, tangent, &mut res,
    )
    .then_some(res)
}

/// [`evaluate_parts`] into the caller's `res`; returns whether the point touches (else `res`
/// holds no result). The same operations: the hot loops
/// ([`super::section3d::SectionContactSet::add_residual`]) reuse one result instead of
/// copying a returned one (its 0.4 kB were a `memcpy` per touching point, 1.6 % of the 3D
/// belt's run at 120 elements, session 39).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn evaluate_parts_into(
    pul: &Pulley3d,
    law: &ContactLaw,
    w_rim: f64,
    w_flange: f64,
    p: &PointMotion<3>,
    theta: f64,
    omega: f64,
    hist: &Pulley3dHistory,
    tangent: bool,
    res: &mut Pulley3dContact,
) -> bool {
    let (zeta, rho, dr) = pul.radial(&p.r);
    // the tests of `rim` and `flanges` before anything else (most points near a pulley do
    // not touch it), and the point's frame (three divisions) only after them
    let maybe_rim = w_rim > 0.0
        && zeta.abs() < pul.half_width + pul.belt_half_width
        && rho > 0.0
        && rho - pul.rim_radius(zeta).0 < 0.0;
    let maybe_flange = w_flange > 0.0
        && pul.flange_top > pul.radius
        && rho < pul.flange_top
        && zeta.abs() + pul.belt_half_width - pul.half_width > 0.0;
    if !(maybe_rim || maybe_flange) {
        return false;
    }
    let fr = pul.frame_of(zeta, rho, &dr);
    *res = Pulley3dContact {
        force: Vector3::zeros(),
        torque: 0.0,
        moment: Vector3::zeros(),
        flange_force: 0.0,
        slipping: false,
        pressure: 0.0,
        z: [0.0; 2],
        friction: [0.0; 2],
        slip_increment: [0.0; 2],
        normal_energy: 0.0,
        dissipation: 0.0,
        // set by `rim`, or below for a point on the flanges only
        phi: f64::NAN,
        k: Matrix4::zeros(),
        c: Matrix4::zeros(),
    };
    let on_rim = maybe_rim
        && rim(
            pul,
            law,
            w_rim,
            p,
            theta,
            omega,
            hist,
            (&fr, &dr),
            tangent,
            res,
        );
    let on_flange = maybe_flange && flanges(pul, law, w_flange, p, &fr, tangent, res);
    if !(on_rim || on_flange) {
        return false;
    }
    if !on_rim {
        res.phi = pul.polar_angle_of(&dr);
    }
    res.moment = (p.r - pul.center).cross(&(-res.force));
    true
}

impl ObstacleContact<3> for Pulley3dContact {
    #[inline]
    fn force(&self) -> SVector<f64, 3> {
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

    fn moment(&self) -> Vector3<f64> {
        self.moment
    }

    /// The flanges' push on the belt, reversed: the belt's axial force on the flanges.
    fn side_force(&self) -> f64 {
        -self.flange_force
    }
}

impl Obstacle<3> for Pulley3d {
    const N_COORDS: usize = 1;
    type History = Pulley3dHistory;
    type Contact = Pulley3dContact;

    /// A segment can touch if an end, widened by 0.55 of the chord (a sagging segment) and
    /// 0.1 % of the radius, lies inside the larger of pitch radius and flange top and axially
    /// within the rim plus the belt's half width.
    #[inline(always)]
    fn near(&self, a: &SVector<f64, 3>, b: &SVector<f64, 3>) -> bool {
        let margin = 0.55 * (b - a).norm() + 1e-3 * self.radius;
        let reach = self.radius.max(self.flange_top);
        [a, b].iter().any(|r| {
            let (zeta, rho, ..) = self.frame(r);
            rho - margin < reach && zeta.abs() - margin < self.half_width + self.belt_half_width
        })
    }

    #[inline]
    fn evaluate(
        &self,
        law: &ContactLaw,
        w: f64,
        p: &PointMotion<3>,
        x: &[f64],
        xd: &[f64],
        hist: &Pulley3dHistory,
    ) -> Option<Pulley3dContact> {
        evaluate(self, law, w, p, x[0], xd[0], hist)
    }

    fn committed(
        &self,
        p: &PointMotion<3>,
        x: &[f64],
        c: Option<&Pulley3dContact>,
    ) -> Pulley3dHistory {
        let (fr, dr) = self.frame_radial(&p.r);
        let zeta = fr.zeta;
        let Some(c) = c else {
            // out of contact: the polar angle is taken only if the pair touches in the next
            // step (see [`Pulley3dHistory`])
            return Pulley3dHistory {
                phi: f64::NAN,
                zeta,
                theta: x[0],
                z: self.polar_components(&dr),
                f: [0.0; 2],
            };
        };
        // the evaluation's polar angle (the same operations)
        let (z, f) = if c.pressure > 0.0 {
            (c.z, c.friction)
        } else {
            ([0.0; 2], [0.0; 2])
        };
        Pulley3dHistory {
            phi: c.phi,
            zeta,
            theta: x[0],
            z,
            f,
        }
    }

    /// Trapezoidal in the slip: `w (f_old + f)/2 · Δs`.
    #[inline]
    fn friction_work(w: f64, h: &Pulley3dHistory, c: &Pulley3dContact) -> f64 {
        if c.pressure <= 0.0 {
            return 0.0;
        }
        w * 0.5
            * ((h.f[0] + c.friction[0]) * c.slip_increment[0]
                + (h.f[1] + c.friction[1]) * c.slip_increment[1])
    }

    fn shift_history(h: &mut Pulley3dHistory, _l: usize, by: f64) {
        h.theta += by;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::finite_difference as fd;
    use nalgebra::DMatrix;

    use crate::contact::test_laws::belt as law;

    /// A pulley off the origin with a skew axis, radius 0.1 m, rim half width 15 mm, belt half
    /// width 10 mm, crown 0.5 mm, flanges 5 mm high.
    fn pulley(crown: f64) -> Pulley3d {
        Pulley3d::new(
            Vector3::new(0.2, -0.1, 0.05),
            Vector3::new(0.1, -0.2, 1.0),
            0.1,
            0.015,
            crown,
            0.105,
            0.010,
        )
    }

    /// Point at polar angle `phi`, radius `rho`, axial position `zeta` of pulley `p`.
    fn at(p: &Pulley3d, phi: f64, rho: f64, zeta: f64) -> Vector3<f64> {
        let u2 = p.axis.cross(&p.u1);
        p.center + rho * (phi.cos() * p.u1 + phi.sin() * u2) + zeta * p.axis
    }

    /// Rim radius at axial position `zeta`.
    fn rim_r(p: &Pulley3d, zeta: f64) -> f64 {
        p.rim_radius(zeta).0
    }

    fn out(pul: &Pulley3d, m: &PointMotion<3>, th: f64, om: f64, h: &Pulley3dHistory) -> [f64; 4] {
        let r = evaluate(pul, &law(), 4e-3, m, th, om, h).expect("in contact");
        [r.force.x, r.force.y, r.force.z, r.torque]
    }

    /// `k` and `c` against central differences; the state's stick or slip as expected.
    fn check(pul: &Pulley3d, m: PointMotion<3>, th: f64, om: f64, h: Pulley3dHistory, slip: bool) {
        let res = evaluate(pul, &law(), 4e-3, &m, th, om, &h).expect("in contact");
        assert_eq!(res.slipping, slip, "stick/slip state of the test point");
        let dm = |x: &Matrix4<f64>| DMatrix::from_column_slice(4, 4, x.as_slice());
        let x0 = [m.r.x, m.r.y, m.r.z, th];
        fd::assert_jacobian("k", &dm(&res.k), &x0, 1e-9, 2e-6, |x, o| {
            let mm = PointMotion {
                r: Vector3::new(x[0], x[1], x[2]),
                v: m.v,
            };
            o.copy_from_slice(&out(pul, &mm, x[3], om, &h));
        });
        let scale = Vector3::from_column_slice(&out(pul, &m, th, om, &h)[..3]).norm();
        let v0 = [m.v.x, m.v.y, m.v.z, om];
        let cfd = fd::jacobian(
            &v0,
            4,
            |_| 1e-9,
            |x, o| {
                let mm = PointMotion {
                    r: m.r,
                    v: Vector3::new(x[0], x[1], x[2]),
                };
                o.copy_from_slice(&out(pul, &mm, th, x[3], &h));
            },
        );
        fd::assert_close("c", &dm(&res.c), &cfd, 2e-6, scale);
    }

    #[test]
    fn stick_tangent_on_a_crowned_rim_matches_finite_differences() {
        let p = pulley(5e-4);
        let zeta = 0.004;
        let r = at(&p, 0.7, rim_r(&p, zeta) - 2e-5, zeta);
        let m = PointMotion {
            r,
            v: Vector3::new(-0.3, 0.2, 0.05),
        };
        let h = Pulley3dHistory {
            phi: 0.7 - 1e-4,
            zeta: zeta - 1e-6,
            theta: 0.3101,
            z: [1e-7, -2e-8],
            f: [0.0; 2],
        };
        check(&p, m, 0.31, 4.0, h, false);
    }

    #[test]
    fn slip_tangent_matches_finite_differences() {
        for crown in [0.0, 5e-4] {
            let p = pulley(crown);
            let zeta = -0.006;
            let r = at(&p, 2.2, rim_r(&p, zeta) - 3e-5, zeta);
            let m = PointMotion {
                r,
                v: Vector3::new(1.0, 0.5, -0.2),
            };
            let h = Pulley3dHistory {
                phi: 2.1,
                zeta: zeta + 1e-3,
                theta: 0.9,
                z: [0.0; 2],
                f: [0.0; 2],
            };
            check(&p, m, 1.0, -3.0, h, true);
        }
    }

    /// In the smoothing zone of the penalty, on the crown beyond the rim's quadratic part
    /// (|ζ| > h: the belt's edge still on the rim), and in the stick–slip blend.
    #[test]
    fn tangents_in_the_smoothing_zone_the_rim_shoulder_and_the_blend() {
        let p = pulley(5e-4);
        let zeta = 0.018;
        let r = at(&p, -0.4, rim_r(&p, zeta) - 2e-6, zeta);
        let m = PointMotion {
            r,
            v: Vector3::new(0.1, 0.3, 0.0),
        };
        let h = Pulley3dHistory {
            phi: -0.4 + 2e-4,
            zeta,
            theta: 0.0,
            z: [0.0; 2],
            f: [0.0; 2],
        };
        // the belt edge (ζ + b = 28 mm) is beyond the flange face (15 mm): flange in contact
        let res = evaluate(&p, &law(), 4e-3, &m, 0.0, 2.0, &h).unwrap();
        assert!(
            res.flange_force < 0.0,
            "the flange at +h pushes the belt back"
        );
        check(&p, m, 0.0, 2.0, h, true);
        // blend: an axial and circumferential slip putting |f*| at 1.02 μ p
        let q = pulley(0.0);
        let delta = 2e-5;
        let pr = law().k_n * (delta - 0.5 * law().smoothing);
        let s = 1.02 * law().mu * pr / law().k_t;
        let (s1, s2) = (0.6 * s, 0.8 * s);
        let rho = 0.1 - delta;
        let m = PointMotion {
            r: at(&q, 1.0, rho, 0.002),
            v: Vector3::zeros(),
        };
        let h = Pulley3dHistory {
            phi: 1.0 - s1 / rho,
            zeta: 0.002 - s2,
            theta: 0.0,
            z: [0.0; 2],
            f: [0.0; 2],
        };
        let res = evaluate(&q, &law(), 1e-3, &m, 0.0, 0.0, &h).unwrap();
        let ratio = Vector2::from(res.friction).norm() / (law().mu * pr);
        assert!(ratio > 0.99 && ratio < 1.0, "{ratio}");
        check(&q, m, 0.0, 0.0, h, true);
    }

    /// Flange contact alone (the point above the rim, below the flange top) and on both.
    #[test]
    fn flange_tangent_matches_finite_differences() {
        let p = pulley(0.0);
        let zeta = -0.0062;
        let m = PointMotion {
            r: at(&p, 0.3, 0.1 + 1e-3, zeta),
            v: Vector3::new(0.2, -0.1, 0.3),
        };
        let h = Pulley3dHistory::default();
        let res = evaluate(&p, &law(), 4e-3, &m, 0.0, 1.0, &h).expect("flange contact");
        // the flange at ζ = −h pushes the belt towards +a; no friction, no torque
        assert!(res.force.dot(&p.axis) > 0.0 && res.torque == 0.0);
        assert!((res.force - res.force.dot(&p.axis) * p.axis).norm() < 1e-12 * res.force.norm());
        check(&p, m, 0.0, 1.0, h, false);
        let m2 = PointMotion {
            r: at(&p, 0.3, 0.1 - 3e-5, zeta),
            ..m
        };
        let h2 = Pulley3dHistory {
            phi: 0.3 - 1e-3,
            zeta,
            ..h
        };
        check(&p, m2, 0.0, 1.0, h2, true);
    }

    /// Pure rolling of the pitch line in the pulley's plane (the penetrated point moves at
    /// `ω R`, `ρ Δφ = R Δθ`): no friction, the force is the normal pressure only, radial; no
    /// moment about the axis.
    #[test]
    fn pure_rolling_has_no_friction() {
        let p = pulley(0.0);
        let (th0, th1) = (0.2, 0.25);
        let (phi0, omega, rho) = (1.0, 5.0, 0.1 - 1e-5);
        let phi1 = phi0 + (th1 - th0) * p.radius / rho;
        let r = at(&p, phi1, rho, 0.003);
        let e = (r - p.center - 0.003 * p.axis).normalize();
        let t = p.axis.cross(&e);
        let m = PointMotion {
            r,
            v: omega * p.radius * t,
        };
        let h = Pulley3dHistory {
            phi: phi0,
            zeta: 0.003,
            theta: th0,
            ..Default::default()
        };
        let res = evaluate(&p, &law(), 1e-2, &m, th1, omega, &h).unwrap();
        assert!(!res.slipping && res.torque.abs() < 1e-9, "{}", res.torque);
        let expect = 1e-2 * law().k_n * (1e-5 - 0.5 * law().smoothing);
        assert!((res.force - expect * e).norm() < 1e-9);
        // moment on the pulley about its centre: (r − c) × (−F), perpendicular to the axis
        assert!(res.moment.dot(&p.axis).abs() < 1e-12);
        assert!((res.moment - (r - p.center).cross(&(-res.force))).norm() < 1e-12);
    }

    /// Sliding along a diagonal of the surface: friction = μ × normal force, opposed to the
    /// slip; torque = pitch radius R × circumferential friction force.
    #[test]
    fn sliding_force_is_mu_times_normal_force_against_the_slip() {
        let p = pulley(0.0);
        let rho = 0.1 - 1e-4;
        let m = PointMotion {
            r: at(&p, 0.0, rho, 0.0),
            v: Vector3::zeros(),
        };
        // slipped 1 mm along t and 1 mm along a relative to the pulley
        let h = Pulley3dHistory {
            phi: -1e-3 / rho,
            zeta: -1e-3,
            ..Default::default()
        };
        let w = 1e-2;
        let res = evaluate(&p, &law(), w, &m, 0.0, 0.0, &h).unwrap();
        assert!(res.slipping);
        let fn_ = w * law().k_n * (1e-4 - 0.5 * law().smoothing);
        let e = p.u1;
        let t = p.axis.cross(&e);
        assert!((res.force.dot(&e) - fn_).abs() < 1e-9);
        let ft = law().mu * fn_ / 2f64.sqrt();
        assert!(
            (res.force.dot(&t) + ft).abs() < 1e-9,
            "{}",
            res.force.dot(&t)
        );
        assert!((res.force.dot(&p.axis) + ft).abs() < 1e-9);
        assert!((res.torque - p.radius * ft).abs() < 1e-9);
        // off the rim (beyond h + b) of a pulley without flanges: nothing; with flanges the
        // flange holds it; above the surface: nothing
        let bare = Pulley3d {
            flange_top: 0.0,
            ..p
        };
        let off = PointMotion {
            r: at(&p, 0.0, rho, 0.026),
            ..m
        };
        assert!(evaluate(&bare, &law(), w, &off, 0.0, 0.0, &h).is_none());
        let held = evaluate(&p, &law(), w, &off, 0.0, 0.0, &h).expect("on the flange");
        assert!(held.force.dot(&p.axis) < 0.0 && held.pressure == 0.0);
        let above = PointMotion {
            r: at(&p, 0.0, 0.1 + 1e-6, 0.0),
            ..m
        };
        assert!(evaluate(&p, &law(), w, &above, 0.0, 0.0, &h).is_none());
    }

    /// The crowned rim's elastic force is the gradient of its penalty energy (conservative:
    /// without friction or damping `F = −∇U`), and points down the crown's slope.
    #[test]
    fn crown_force_is_the_gradient_of_the_penalty_energy() {
        let p = pulley(5e-4);
        let mut frictionless = law();
        frictionless.mu = 0.0;
        frictionless.d_n = 0.0;
        // the belt edge ζ + b = 14 mm stays off the flange at 15 mm
        let zeta = 0.004;
        let r = at(&p, 0.5, rim_r(&p, zeta) - 4e-5, zeta);
        let h = Pulley3dHistory::default();
        let energy = |x: &[f64]| {
            let m = PointMotion {
                r: Vector3::new(x[0], x[1], x[2]),
                v: Vector3::zeros(),
            };
            evaluate(&p, &frictionless, 1e-2, &m, 0.0, 0.0, &h).map_or(0.0, |c| c.normal_energy)
        };
        let grad = fd::gradient(&[r.x, r.y, r.z], |_| 1e-9, energy);
        let m = PointMotion {
            r,
            v: Vector3::zeros(),
        };
        let f = evaluate(&p, &frictionless, 1e-2, &m, 0.0, 0.0, &h)
            .unwrap()
            .force;
        let minus_grad = -Vector3::from_column_slice(&grad);
        assert!(
            (f - minus_grad).norm() <= 1e-6 * f.norm(),
            "{f} vs {minus_grad}"
        );
        assert!(f.dot(&p.axis) > 0.0, "a point at ζ > 0 is pushed outwards");
    }

    #[test]
    fn histories_survive_a_snapshot() {
        let h = Pulley3dHistory {
            phi: 0.1,
            zeta: -2e-3,
            theta: 3.0,
            z: [1e-6, -2e-6],
            f: [4.0, -5.0],
        };
        let mut w = StateWriter::new();
        h.save(&mut w);
        let bytes = w.into_bytes();
        let mut r = StateReader::new(&bytes);
        assert_eq!(Pulley3dHistory::restore(&mut r).unwrap(), h);
    }

    /// Every result carries the polar angle of its point, taken after the contact tests.
    #[test]
    fn every_contact_carries_its_polar_angle() {
        // the polar angle is taken after the contact tests: on the rim, on a flange only
        // (above the rim), on both; a reused result buffer gives the returned result
        let pul = pulley(0.0);
        let zeta = -0.0062;
        let h = Pulley3dHistory::default();
        let mut buf = Pulley3dContact::default();
        for (k, (rho, zeta, rim, flange)) in [
            (pul.radius - 1e-5, 0.0, true, false),
            (pul.radius + 1e-3, zeta, false, true),
            (pul.radius - 3e-5, zeta, true, true),
        ]
        .into_iter()
        .enumerate()
        {
            let phi = 0.3 + k as f64;
            let m = PointMotion {
                r: at(&pul, phi, rho, zeta),
                v: Vector3::zeros(),
            };
            let c = evaluate(&pul, &law(), 4e-3, &m, 0.0, 1.0, &h).expect("in contact");
            assert_eq!(c.pressure > 0.0, rim, "{c:?}");
            assert_eq!(c.flange_force != 0.0, flange, "{c:?}");
            let (_, dr) = pul.frame_radial(&m.r);
            assert_eq!(c.phi.to_bits(), pul.polar_angle_of(&dr).to_bits());
            assert!((c.phi - phi).abs() < 1e-12);
            assert!(evaluate_parts_into(
                &pul,
                &law(),
                4e-3,
                4e-3,
                &m,
                0.0,
                1.0,
                &h,
                true,
                &mut buf
            ));
            assert_eq!(buf, c);
        }
    }

    /// A pair committed out of contact keeps its polar angle untaken: the angle taken later
    /// is the one the commit would have taken (to the bit, in every quadrant), it survives a
    /// snapshot, its bristle is unloaded, and the slip increment of a point landing from it is
    /// the arc it moved along.
    #[test]
    fn untaken_polar_angle_is_the_committed_one() {
        let pul = pulley(0.0);
        for k in 0..16 {
            let phi = -3.1 + 0.41 * k as f64;
            let r = at(&pul, phi, pul.radius + 0.02, 1e-3);
            let m = PointMotion {
                r,
                v: Vector3::zeros(),
            };
            let h = pul.committed(&m, &[0.3], None);
            assert!(h.phi.is_nan());
            let (_, dr) = pul.frame_radial(&r);
            assert_eq!(h.polar_angle().to_bits(), pul.polar_angle_of(&dr).to_bits());
            assert!((h.polar_angle() - phi).abs() < 1e-12);
            assert_eq!(h.bristle(), [0.0; 2]);
            assert_eq!(h.f, [0.0; 2]);
            let mut w = StateWriter::new();
            h.save(&mut w);
            let bytes = w.into_bytes();
            let back = Pulley3dHistory::restore(&mut StateReader::new(&bytes)).unwrap();
            assert_eq!(back.polar_angle().to_bits(), h.polar_angle().to_bits());
            // landing 1e-3 rad further on, pulley at rest: circumferential slip ρ Δφ
            let r1 = at(&pul, phi + 1e-3, pul.radius - 1e-5, 1e-3);
            let c = evaluate(
                &pul,
                &law(),
                0.01,
                &PointMotion { r: r1, v: m.v },
                0.3,
                0.0,
                &h,
            )
            .expect("in contact");
            let rho = pul.radius - 1e-5;
            assert!((c.slip_increment[0] - rho * 1e-3).abs() < 1e-12, "{c:?}");
        }
    }
}
