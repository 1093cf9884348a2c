//! The finite-difference helper of the tests: central differences of a vector function and the
//! comparison of a Jacobian with an analytic one, with a failure message that says what, where
//! and by how much.

use nalgebra::DMatrix;

/// Central-difference Jacobian `J_ij ≈ (f_i(x + h_j e_j) − f_i(x − h_j e_j)) / (2 h_j)` of
/// `f: ℝⁿ → ℝᵐ` at `x`, with the step `h_j = step(j)`. `f(x, out)` writes `m` values.
pub fn jacobian(
    x: &[f64],
    m: usize,
    step: impl Fn(usize) -> f64,
    mut f: impl FnMut(&[f64], &mut [f64]),
) -> DMatrix<f64> {
    let n = x.len();
    let mut jac = DMatrix::zeros(m, n);
    let (mut xp, mut fp, mut fm) = (x.to_vec(), vec![0.0; m], vec![0.0; m]);
    for j in 0..n {
        let h = step(j);
        xp[j] = x[j] + h;
        f(&xp, &mut fp);
        xp[j] = x[j] - h;
        f(&xp, &mut fm);
        xp[j] = x[j];
        for i in 0..m {
            jac[(i, j)] = (fp[i] - fm[i]) / (2.0 * h);
        }
    }
    jac
}

/// Central-difference gradient of a scalar function, as a column.
pub fn gradient(
    x: &[f64],
    step: impl Fn(usize) -> f64,
    mut f: impl FnMut(&[f64]) -> f64,
) -> Vec<f64> {
    let jac = jacobian(x, 1, step, |x, out| out[0] = f(x));
    jac.iter().copied().collect()
}

/// Compares an analytic Jacobian with a finite-difference one: passes if
/// `‖fd − analytic‖_F ≤ rtol · max(‖analytic‖_F, floor)` (`floor` > 0 is the magnitude below
/// which differences count as zero, for matrices that vanish). The error names `what`, the
/// relative error, both norms and the worst entry.
pub fn compare(
    what: &str,
    analytic: &DMatrix<f64>,
    fd: &DMatrix<f64>,
    rtol: f64,
    floor: f64,
) -> Result<(), String> {
    assert_eq!(analytic.shape(), fd.shape(), "{what}: shapes differ");
    let diff = fd - analytic;
    let scale = analytic.norm().max(floor);
    let err = diff.norm() / scale;
    if err <= rtol {
        return Ok(());
    }
    let (mut worst, mut at) = (0.0, (0, 0));
    for j in 0..diff.ncols() {
        for i in 0..diff.nrows() {
            if diff[(i, j)].abs() >= worst {
                worst = diff[(i, j)].abs();
                at = (i, j);
            }
        }
    }
    Err(format!(
        "{what}: relative error {err:.3e} > {rtol:.1e} (‖analytic‖ = {:.4e}, ‖fd‖ = {:.4e}, floor {floor:.1e}); worst entry ({}, {}): analytic {:.8e}, finite differences {:.8e}",
        analytic.norm(),
        fd.norm(),
        at.0,
        at.1,
        analytic[at],
        fd[at],
    ))
}

/// [`compare`] that panics with its message.
#[track_caller]
pub fn assert_close(what: &str, analytic: &DMatrix<f64>, fd: &DMatrix<f64>, rtol: f64, floor: f64) {
    if let Err(msg) = compare(what, analytic, fd, rtol, floor) {
        panic!("{msg}");
    }
}

/// Finite-difference Jacobian of `f` at `x` ([`jacobian`] with one step `h`) compared with
/// `analytic` ([`assert_close`] with `floor` = the analytic norm's own scale, i.e. pure
/// relative error unless the analytic matrix vanishes).
#[track_caller]
pub fn assert_jacobian(
    what: &str,
    analytic: &DMatrix<f64>,
    x: &[f64],
    h: f64,
    rtol: f64,
    f: impl FnMut(&[f64], &mut [f64]),
) {
    let fd = jacobian(x, analytic.nrows(), |_| h, f);
    assert_close(what, analytic, &fd, rtol, f64::MIN_POSITIVE);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Jacobian of a smooth map is reproduced; a wrong entry is reported with its place.
    #[test]
    fn jacobian_of_a_smooth_map_and_a_useful_message() {
        let f = |x: &[f64], out: &mut [f64]| {
            out[0] = x[0] * x[1].sin();
            out[1] = x[0].exp() + x[1] * x[1];
        };
        let x = [0.3f64, 1.2];
        let exact = DMatrix::from_row_slice(
            2,
            2,
            &[x[1].sin(), x[0] * x[1].cos(), x[0].exp(), 2.0 * x[1]],
        );
        let fd = jacobian(&x, 2, |_| 1e-6, f);
        assert!(compare("smooth", &exact, &fd, 1e-8, 0.0).is_ok());
        let mut wrong = exact.clone();
        wrong[(1, 0)] += 0.1;
        let msg = compare("wrong", &wrong, &fd, 1e-8, 0.0).unwrap_err();
        assert!(msg.contains("wrong") && msg.contains("(1, 0)"), "{msg}");
        let g = gradient(&x, |_| 1e-6, |x| x[0] * x[0] * x[1]);
        assert!((g[0] - 2.0 * x[0] * x[1]).abs() < 1e-8 && (g[1] - x[0] * x[0]).abs() < 1e-8);
    }
}
