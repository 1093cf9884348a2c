//! Output time derivatives (`fmi2GetRealOutputDerivatives`) shared by the models: the rate of
//! any function of the committed state along the motion.

/// Time step of the central difference in [`along_motion`] [s]: the state moves by `ε v`, so
/// the truncation error is `(ε ω)²/6` of the rate for motions of angular frequency `ω`
/// (below 1e-4 up to 2·10⁴ rad/s) and the round-off `1e-16 |f| / ε`.
pub const RATE_EPS: f64 = 1e-6;

/// `d/dt f(q(t), v(t))` at the committed state `(q, v)` with acceleration `a`, by the central
/// difference `[f(q + ε v, v + ε a) − f(q − ε v, v − ε a)] / 2ε` ([`RATE_EPS`]). Exact to
/// second order for any smooth function of coordinates and velocities (energies, points,
/// speeds), including models whose rotation coordinates are incremental rotation vectors that
/// are zero at the committed state (`θ = ε W` is then the body-spin motion). `work` holds two
/// buffers of the size of `q` (resized as needed).
pub fn along_motion(
    q: &[f64],
    v: &[f64],
    a: &[f64],
    work: &mut [Vec<f64>; 2],
    f: impl Fn(&[f64], &[f64]) -> f64,
) -> f64 {
    let side = |s: f64, work: &mut [Vec<f64>; 2]| {
        let [qs, vs] = work;
        qs.clear();
        vs.clear();
        qs.extend(q.iter().zip(v).map(|(q, v)| q + s * RATE_EPS * v));
        vs.extend(v.iter().zip(a).map(|(v, a)| v + s * RATE_EPS * a));
        f(qs, vs)
    };
    let fp = side(1.0, work);
    let fm = side(-1.0, work);
    (fp - fm) / (2.0 * RATE_EPS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rate_of_a_smooth_function_along_the_motion() {
        // f = q0² v1 + sin(q1): df/dt = 2 q0 v0 v1 + q0² a1 + cos(q1) v1
        let (q, v, a): ([f64; 2], [f64; 2], [f64; 2]) = ([0.7, -0.3], [1.3, 2.1], [-0.4, 5.0]);
        let f = |q: &[f64], v: &[f64]| q[0] * q[0] * v[1] + q[1].sin();
        let exact = 2.0 * q[0] * v[0] * v[1] + q[0] * q[0] * a[1] + q[1].cos() * v[1];
        let mut work = [vec![], vec![]];
        let r = along_motion(&q, &v, &a, &mut work, f);
        assert!((r - exact).abs() < 1e-8 * exact.abs(), "{r} vs {exact}");
    }
}
