//! Finite rotations: the exponential and logarithm of SO(3) and the tangent operators of the
//! rotation vector, with series expansions near zero so that every function is accurate to
//! round-off for all angles where it is defined.
//!
//! Conventions (all exact; `shared/reference/seed003-corotational-beam.md` B.1, Crisfield
//! 1990, Battini & Pacoste 2002):
//!
//! - `exp(θ̃) = I + (sin θ/θ) θ̃ + ((1 − cos θ)/θ²) θ̃²`, θ = |θ| (Rodrigues).
//! - A *spatial* (left) spin `δw` perturbs `R` as `exp(δw̃) R`, a *body* (right) spin `δW` as
//!   `R exp(δW̃)`; `δw = R δW`.
//! - Spatial tangent `T_s(θ) = I + ((1 − cos θ)/θ²) θ̃ + ((θ − sin θ)/θ³) θ̃²`:
//!   `exp((θ + δθ)~) = exp((T_s δθ)~) exp(θ̃)` to first order.
//! - Body tangent `T(θ) = T_s(θ)ᵀ = T_s(−θ)`: `exp((θ + δθ)~) = exp(θ̃) exp((T δθ)~)`.
//! - `T_s⁻¹(θ) = I − ½ θ̃ + ((1 − (θ/2) cot(θ/2))/θ²) θ̃²`, singular at θ = 2π.

use nalgebra::{Matrix3, Vector3};

/// Below this angle [rad] the coefficient functions use their Taylor series.
const SERIES_ANGLE: f64 = 0.1;

/// Skew-symmetric matrix `ṽ` with `ṽ u = v × u`.
#[inline]
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Axial vector of the skew-symmetric part of `m`: `axial(ṽ) = v`.
#[inline]
pub fn axial(m: &Matrix3<f64>) -> Vector3<f64> {
    0.5 * Vector3::new(
        m[(2, 1)] - m[(1, 2)],
        m[(0, 2)] - m[(2, 0)],
        m[(1, 0)] - m[(0, 1)],
    )
}

/// `sin θ/θ`.
#[inline]
fn sinc(t: f64) -> f64 {
    if t < SERIES_ANGLE {
        let t2 = t * t;
        1.0 - t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0)))
    } else {
        t.sin() / t
    }
}

/// `(1 − cos θ)/θ²`.
#[inline]
fn coef_a(t: f64) -> f64 {
    if t < SERIES_ANGLE {
        let t2 = t * t;
        0.5 - t2 / 24.0 * (1.0 - t2 / 30.0 * (1.0 - t2 / 56.0 * (1.0 - t2 / 90.0)))
    } else {
        (1.0 - t.cos()) / (t * t)
    }
}

/// `(θ − sin θ)/θ³`.
#[inline]
fn coef_b(t: f64) -> f64 {
    if t < SERIES_ANGLE {
        let t2 = t * t;
        1.0 / 6.0 - t2 / 120.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0 * (1.0 - t2 / 110.0)))
    } else {
        (t - t.sin()) / (t * t * t)
    }
}

/// `c(θ) = (1 − (θ/2) cot(θ/2))/θ²` and `c'(θ)/θ`.
#[inline]
fn coef_c(t: f64) -> (f64, f64) {
    if t < SERIES_ANGLE {
        let t2 = t * t;
        (
            1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0 + t2 * t2 * t2 / 1_209_600.0,
            1.0 / 360.0 + t2 / 7560.0 + t2 * t2 / 201_600.0 + t2 * t2 * t2 / 5_987_520.0,
        )
    } else {
        let h = 0.5 * t;
        let cot = h.cos() / h.sin();
        let f = 1.0 - h * cot;
        // f' = −½ cot(θ/2) + (θ/4) / sin²(θ/2)
        let fp = -0.5 * cot + 0.25 * t / (h.sin() * h.sin());
        let c = f / (t * t);
        let cp = fp / (t * t) - 2.0 * f / (t * t * t);
        (c, cp / t)
    }
}

/// Rotation matrix `exp(θ̃)` of a rotation vector θ [rad] (any magnitude).
pub fn exp_so3(th: &Vector3<f64>) -> Matrix3<f64> {
    let t = th.norm();
    let k = skew(th);
    Matrix3::identity() + sinc(t) * k + coef_a(t) * k * k
}

/// Principal logarithm: the rotation vector θ with |θ| ≤ π and `exp(θ̃) = R`. Robust near
/// θ = 0 and θ = π (axis from the symmetric part there). `R` must be a rotation matrix.
pub fn log_so3(r: &Matrix3<f64>) -> Vector3<f64> {
    let w = axial(r); // sin θ · n
    let s2 = w.norm_squared();
    let tr = r.trace();
    if s2 < ASIN_SERIES_S2 && tr > 1.0 {
        // near the identity (sin θ < 0.2, cos θ > 0): θ/sin θ = asin(s)/s, no atan2
        return w * asin_over_x(s2);
    }
    let s = s2.sqrt();
    let c = (0.5 * (tr - 1.0)).clamp(-1.0, 1.0);
    let t = s.atan2(c);
    if c > -0.9 {
        // θ/sin θ = 1/sinc(θ)
        w / sinc(t)
    } else {
        // (R + Rᵀ)/2 − cos θ I = (1 − cos θ) n nᵀ
        let b = 0.5 * (r + r.transpose()) - Matrix3::identity() * c;
        let k = (0..3)
            .max_by(|&i, &j| b[(i, i)].total_cmp(&b[(j, j)]))
            .unwrap_or(0);
        let mut n =
            b.column(k).into_owned() / (b[(k, k)] * (1.0 - c)).max(f64::MIN_POSITIVE).sqrt();
        n /= n.norm().max(f64::MIN_POSITIVE);
        if n.dot(&w) < 0.0 {
            n = -n;
        }
        n * t
    }
}

/// Largest `sin² θ` of [`log_so3`]'s series branch.
const ASIN_SERIES_S2: f64 = 0.04;

/// `asin(x)/x` for `x² = x2 < 0.04`: its Taylor series `Σ a_n x²ⁿ`,
/// `a_n = a_{n−1} (2n − 1)²/(2n (2n + 1))`, to `n = 10` (the rest is below 1e-17).
#[inline]
fn asin_over_x(x2: f64) -> f64 {
    const A: [f64; 11] = [
        1.0,
        1.0 / 6.0,
        3.0 / 40.0,
        5.0 / 112.0,
        35.0 / 1152.0,
        63.0 / 2816.0,
        231.0 / 13312.0,
        143.0 / 10240.0,
        6435.0 / 557056.0,
        12155.0 / 1245184.0,
        46189.0 / 5505024.0,
    ];
    A.iter().rev().fold(0.0, |acc, &a| acc * x2 + a)
}

/// Body tangent `T(θ) = I − ((1 − cos θ)/θ²) θ̃ + ((θ − sin θ)/θ³) θ̃²`:
/// `exp((θ + δθ)~) = exp(θ̃) exp((T(θ) δθ)~)` to first order. Singular at θ = 2π.
pub fn tangent_body(th: &Vector3<f64>) -> Matrix3<f64> {
    let t = th.norm();
    let k = skew(th);
    Matrix3::identity() - coef_a(t) * k + coef_b(t) * k * k
}

/// Spatial tangent `T_s(θ) = T(θ)ᵀ`: `exp((θ + δθ)~) = exp((T_s(θ) δθ)~) exp(θ̃)`.
pub fn tangent_spatial(th: &Vector3<f64>) -> Matrix3<f64> {
    tangent_body(th).transpose()
}

/// `T_s⁻¹(θ) = I − ½ θ̃ + c(θ) θ̃²`, `c = (1 − (θ/2) cot(θ/2))/θ²`: the variation of the
/// rotation vector of `R̄ = exp(θ̃)` under a spatial spin `δω` is `δθ = T_s⁻¹(θ) δω`.
pub fn tangent_spatial_inv(th: &Vector3<f64>) -> Matrix3<f64> {
    let t = th.norm();
    let k = skew(th);
    let (c, _) = coef_c(t);
    Matrix3::identity() - 0.5 * k + c * k * k
}

/// `T_s⁻ᵀ(θ) n = n + ½ θ × n + c(θ) θ × (θ × n)` (the value of
/// [`tangent_spatial_inv_t_apply`] by the same operations, without the derivative).
#[inline]
pub fn tangent_spatial_inv_t(th: &Vector3<f64>, n: &Vector3<f64>) -> Vector3<f64> {
    let t = th.norm();
    let (c, _) = coef_c(t);
    let txn = th.cross(n);
    let ttn = th.cross(&txn);
    n + 0.5 * txn + c * ttn
}

/// `T_s⁻ᵀ(θ) n = n + ½ θ × n + c(θ) θ × (θ × n)` and its derivative with respect to θ for
/// fixed `n`: `−½ ñ + c [(θ·n) I + θ nᵀ − 2 n θᵀ] + (θ × (θ × n)) (c'(θ)/θ) θᵀ`.
pub fn tangent_spatial_inv_t_apply(
    th: &Vector3<f64>,
    n: &Vector3<f64>,
) -> (Vector3<f64>, Matrix3<f64>) {
    let t = th.norm();
    let (c, cp_over_t) = coef_c(t);
    let txn = th.cross(n);
    let ttn = th.cross(&txn);
    let value = n + 0.5 * txn + c * ttn;
    let d = -0.5 * skew(n)
        + c * (Matrix3::identity() * th.dot(n) + th * n.transpose() - 2.0 * n * th.transpose())
        + (ttn * cp_over_t) * th.transpose();
    (value, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vectors() -> Vec<Vector3<f64>> {
        vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1e-9, -2e-9, 3e-10),
            Vector3::new(0.03, -0.02, 0.05),
            Vector3::new(0.09, 0.01, -0.04),
            Vector3::new(0.3, -0.7, 1.1),
            Vector3::new(-2.0, 1.0, 1.5),
            Vector3::new(0.0, 0.0, 3.1),
            Vector3::new(1.0, 2.0, -4.0),
            Vector3::new(3.0, -4.0, 2.0),
        ]
    }

    /// exp is orthogonal with determinant 1 and agrees with nalgebra's Rodrigues formula.
    #[test]
    fn exp_is_a_rotation() {
        for th in vectors() {
            let r = exp_so3(&th);
            assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-14);
            assert!((r.determinant() - 1.0).abs() < 1e-14);
            let nr = nalgebra::Rotation3::from_scaled_axis(th).into_inner();
            assert!((r - nr).norm() < 1e-14, "{th:?}");
        }
    }

    /// The series branch of log (sin θ < 0.2) agrees with the `atan2` form `θ/sin θ` to
    /// round-off on both sides of its bound.
    #[test]
    fn log_series_branch_matches_atan2() {
        let axis = Vector3::new(0.3, -0.5, 0.8).normalize();
        for k in 0..=400 {
            let th = axis * (0.21 * k as f64 / 400.0);
            let r = exp_so3(&th);
            let w = axial(&r);
            let (s, c) = (w.norm(), 0.5 * (r.trace() - 1.0));
            let reference = if s > 0.0 { w * (s.atan2(c) / s) } else { w };
            let back = log_so3(&r);
            assert!(
                (back - reference).norm() <= 4.0 * f64::EPSILON * reference.norm(),
                "{th:?}: {back:?} vs {reference:?}"
            );
        }
    }

    /// log inverts exp in the principal ball, including angles near π, and returns the
    /// principal value (|θ| ≤ π) for larger angles.
    #[test]
    fn log_inverts_exp() {
        let pi = std::f64::consts::PI;
        let mut cases = vectors();
        for eps in [1e-3, 1e-7, 1e-10] {
            cases.push(Vector3::new(0.6, -0.8, 0.0) * (pi - eps));
            cases.push(Vector3::new(0.0, 0.0, 1.0) * (pi - eps));
            cases.push(Vector3::new(-1.0, 2.0, 2.0) / 3.0 * (pi - eps));
        }
        for th in cases {
            let r = exp_so3(&th);
            let back = log_so3(&r);
            let t = th.norm();
            if t <= pi {
                assert!((back - th).norm() < 1e-8 * (1.0 + t), "{th:?} -> {back:?}");
            } else {
                assert!(back.norm() <= pi + 1e-12);
                assert!((exp_so3(&back) - r).norm() < 1e-12);
                // complement: (1 − 2π/|θ|) θ when |θ| < 2π
                if t < 2.0 * pi {
                    let c = th * (1.0 - 2.0 * pi / t);
                    assert!((back - c).norm() < 1e-10, "{th:?}: {back:?} vs {c:?}");
                }
            }
        }
    }

    /// exp(θ + εδ) against exp(θ) exp(ε T δ) (body) and exp(ε T_s δ) exp(θ) (spatial).
    #[test]
    fn tangents_match_finite_differences() {
        let eps = 1e-6;
        for th in vectors() {
            let r = exp_so3(&th);
            for k in 0..3 {
                let mut d = Vector3::zeros();
                d[k] = 1.0;
                let dr = (exp_so3(&(th + eps * d)) - exp_so3(&(th - eps * d))) / (2.0 * eps);
                let body = axial(&(r.transpose() * dr));
                let spatial = axial(&(dr * r.transpose()));
                assert!((body - tangent_body(&th) * d).norm() < 1e-8, "{th:?}");
                assert!((spatial - tangent_spatial(&th) * d).norm() < 1e-8, "{th:?}");
                let tsi = tangent_spatial_inv(&th);
                assert!((tsi * tangent_spatial(&th) - Matrix3::identity()).norm() < 1e-12);
            }
        }
    }

    /// The derivative of T_s⁻ᵀ(θ) n against central differences.
    #[test]
    fn inverse_tangent_derivative() {
        let n = Vector3::new(0.3, -1.2, 0.7);
        let eps = 1e-6;
        for th in vectors() {
            let (v, d) = tangent_spatial_inv_t_apply(&th, &n);
            assert!((v - tangent_spatial_inv(&th).transpose() * n).norm() < 1e-14);
            for k in 0..3 {
                let mut e = Vector3::zeros();
                e[k] = eps;
                let fd = (tangent_spatial_inv_t_apply(&(th + e), &n).0
                    - tangent_spatial_inv_t_apply(&(th - e), &n).0)
                    / (2.0 * eps);
                assert!((fd - d.column(k)).norm() < 1e-8, "{th:?} column {k}");
            }
        }
    }

    /// The series and closed forms agree at the switch angle.
    #[test]
    fn series_are_continuous() {
        let (lo, hi) = (SERIES_ANGLE * (1.0 - 1e-12), SERIES_ANGLE * (1.0 + 1e-12));
        assert!((sinc(lo) - sinc(hi)).abs() < 1e-14);
        assert!((coef_a(lo) - coef_a(hi)).abs() < 1e-14);
        assert!((coef_b(lo) - coef_b(hi)).abs() < 1e-14);
        let (c1, d1) = coef_c(lo);
        let (c2, d2) = coef_c(hi);
        // the closed form loses ~4 digits to cancellation at the switch angle
        assert!((c1 - c2).abs() < 1e-13, "{c1} vs {c2}");
        assert!((d1 - d2).abs() < 1e-11, "{d1} vs {d2}");
    }
}
