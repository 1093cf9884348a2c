//! Linearised mass and stiffness of any mechanical system as dense matrices, and its natural
//! frequencies: for modal checks in tests and for small models (the solvers never use them).

use super::{JacobianCoeffs, MechanicalSystem};
use nalgebra::DMatrix;

/// The iteration matrices `M = ∂r/∂a` and `K = ∂r/∂q` of `sys` at time `t` [s], coordinates
/// `q` and zero rates (free coordinates, dense).
pub fn dense_matrices(
    sys: &mut dyn MechanicalSystem,
    t: f64,
    q: &[f64],
) -> Result<(DMatrix<f64>, DMatrix<f64>), String> {
    let n = sys.n_free();
    let zeros = vec![0.0; n];
    let mut r = vec![0.0; n];
    let mut dense = |c: JacobianCoeffs| -> Result<DMatrix<f64>, String> {
        let mut vals = vec![0.0; sys.pattern().nnz()];
        sys.residual(t, q, &zeros, &zeros, 1.0, &mut r, Some((c, &mut vals)))
            .map_err(|e| e.to_string())?;
        let p = sys.pattern();
        let mut m = DMatrix::zeros(n, n);
        for col in 0..n {
            for k in p.col_ptr()[col]..p.col_ptr()[col + 1] {
                m[(p.row_idx()[k], col)] = vals[k];
            }
        }
        Ok(m)
    };
    let m = dense(JacobianCoeffs {
        mass: 1.0,
        damping: 0.0,
        stiffness: 0.0,
    })?;
    let k = dense(JacobianCoeffs {
        mass: 0.0,
        damping: 0.0,
        stiffness: 1.0,
    })?;
    Ok((m, k))
}

/// Circular natural frequencies [rad/s], ascending, of `K φ = ω² M φ` (the symmetric parts;
/// negative eigenvalues of an unstable state clipped at 0). `M` must be positive definite.
pub fn natural_frequencies(m: &DMatrix<f64>, k: &DMatrix<f64>) -> Result<Vec<f64>, String> {
    let ms = (m + m.transpose()) * 0.5;
    let l = ms
        .cholesky()
        .ok_or("the mass matrix is not positive definite")?;
    let li = l.l().try_inverse().ok_or("singular mass matrix")?;
    let a = &li * k * li.transpose();
    let a = (&a + a.transpose()) * 0.5;
    let mut w: Vec<f64> = a
        .symmetric_eigenvalues()
        .iter()
        .map(|x| x.max(0.0).sqrt())
        .collect();
    w.sort_by(f64::total_cmp);
    Ok(w)
}
