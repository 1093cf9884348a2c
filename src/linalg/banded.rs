//! Banded LU factorization with partial pivoting (the algorithm of LAPACK `dgbtf2`/`dgbtrs`,
//! written from its description). Cost O(n kl (kl + ku)), storage (2 kl + ku + 1) n.

use super::FactorError;
use super::csc::CscPattern;

/// A banded LU factorization with partial pivoting; buffers are reused between factorizations.
#[derive(Clone, Debug, Default)]
pub struct BandedLu {
    n: usize,
    kl: usize,
    ku: usize,
    ldab: usize,
    ab: Vec<f64>,
    ipiv: Vec<usize>,
    /// Upper bandwidth of the last factorization's `U`: `ku` plus the fill of row
    /// interchanges, at most `kl + ku` (the back substitution skips the band above it, which
    /// holds exact zeros).
    ub: usize,
}

impl BandedLu {
    /// Storage for an `n × n` matrix with lower and upper bandwidths `kl`, `ku`.
    pub fn new(n: usize, kl: usize, ku: usize) -> Self {
        let ldab = 2 * kl + ku + 1;
        Self {
            n,
            kl,
            ku,
            ldab,
            ab: vec![0.0; ldab * n],
            ipiv: vec![0; n],
            ub: kl + ku,
        }
    }

    /// Index of `A(i, j)` in band storage (valid for `j − ku − kl ≤ i ≤ j + kl`).
    #[inline(always)]
    fn at(&self, i: usize, j: usize) -> usize {
        (self.kl + self.ku + i - j) + j * self.ldab
    }

    /// Factorizes the matrix with values `vals` in `pattern` (which must fit the bandwidths).
    pub fn factor(&mut self, pattern: &CscPattern, vals: &[f64]) -> Result<(), FactorError> {
        let n = self.n;
        self.ab.iter_mut().for_each(|v| *v = 0.0);
        let mut scale = 0.0f64;
        for c in 0..n {
            for k in pattern.col_ptr()[c]..pattern.col_ptr()[c + 1] {
                let v = vals[k];
                if !v.is_finite() {
                    return Err(FactorError::NonFinite);
                }
                scale = scale.max(v.abs());
                let idx = self.at(pattern.row_idx()[k], c);
                self.ab[idx] = v;
            }
        }
        // Only exact or round-off-level pivots count as singular: thin, stiff beams legitimately have
        // pivots ~1e-13 of the largest entry.
        let tiny = scale * 1e-18;
        let (kl, kv) = (self.kl, self.kl + self.ku);
        let mut ju = 0usize;
        let mut ub = self.ku;
        for j in 0..n {
            let km = kl.min(n - 1 - j);
            // pivot search in column j, rows j..=j+km
            let mut jp = 0;
            let mut best = self.ab[self.at(j, j)].abs();
            for r in 1..=km {
                let v = self.ab[self.at(j + r, j)].abs();
                if v > best {
                    best = v;
                    jp = r;
                }
            }
            self.ipiv[j] = j + jp;
            if best <= tiny || best == 0.0 {
                return Err(FactorError::Singular {
                    index: j,
                    pivot: self.ab[self.at(j + jp, j)],
                });
            }
            ju = ju.max((j + self.ku + jp).min(n - 1));
            ub = ub.max(ju - j);
            if jp != 0 {
                for c in j..=ju {
                    let (a, b) = (self.at(j + jp, c), self.at(j, c));
                    self.ab.swap(a, b);
                }
            }
            if km > 0 {
                // In band storage the rows j+1..=j+km of any column are contiguous.
                let jj = self.at(j, j);
                let inv = 1.0 / self.ab[jj];
                let (head, tail) = self.ab.split_at_mut((j + 1) * self.ldab);
                let l = &mut head[jj + 1..jj + 1 + km];
                l.iter_mut().for_each(|x| *x *= inv);
                for c in (j + 1)..=ju {
                    // A(j, c) in `tail`, column c starting at (c − j − 1) ldab
                    let top = kv + j - c + (c - j - 1) * self.ldab;
                    let u = tail[top];
                    if u != 0.0 {
                        let col = &mut tail[top + 1..top + 1 + km];
                        for (x, &lr) in col.iter_mut().zip(l.iter()) {
                            *x -= lr * u;
                        }
                    }
                }
            }
            debug_assert!(kv >= self.ku);
        }
        self.ub = ub.min(kv);
        Ok(())
    }

    /// Solves `A x = b` in place with the last factorization.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let n = self.n;
        // rows of U above j − ub in column j are zero: row j's entries reach column ju ≤ j + ub
        let kv = self.ub;
        for j in 0..n {
            let l = self.ipiv[j];
            if l != j {
                b.swap(l, j);
            }
            let lm = self.kl.min(n - 1 - j);
            let bj = b[j];
            if bj != 0.0 {
                let jj = self.at(j, j);
                let l = &self.ab[jj + 1..jj + 1 + lm];
                for (x, &lr) in b[j + 1..j + 1 + lm].iter_mut().zip(l) {
                    *x -= lr * bj;
                }
            }
        }
        for j in (0..n).rev() {
            b[j] /= self.ab[self.at(j, j)];
            let bj = b[j];
            let i0 = j.saturating_sub(kv);
            let u = &self.ab[self.at(i0, j)..self.at(j, j)];
            for (x, &ur) in b[i0..j].iter_mut().zip(u) {
                *x -= ur * bj;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Random banded matrices that need pivoting: the residual of the solve is small.
    #[test]
    fn solves_banded_systems_with_pivoting() {
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        for &(n, kl, ku) in &[
            (1usize, 0usize, 0usize),
            (5, 1, 1),
            (20, 3, 2),
            (40, 7, 7),
            (30, 0, 4),
        ] {
            let mut entries = vec![];
            for c in 0..n {
                for r in c.saturating_sub(ku)..(c + kl + 1).min(n) {
                    entries.push((r, c));
                }
            }
            let p = CscPattern::from_entries(n, entries);
            let vals: Vec<f64> = (0..p.nnz()).map(|_| rnd()).collect();
            let x: Vec<f64> = (0..n).map(|_| rnd()).collect();
            let mut b = vec![0.0; n];
            p.mul_vec(&vals, &x, &mut b);
            let mut lu = BandedLu::new(n, kl, ku);
            lu.factor(&p, &vals).unwrap();
            lu.solve_in_place(&mut b);
            let err: f64 = b
                .iter()
                .zip(&x)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(err < 1e-8, "n={n} kl={kl} ku={ku}: error {err}");
        }
    }

    #[test]
    fn reports_singular_matrices() {
        let p = CscPattern::from_entries(2, [(0, 1), (1, 0)]);
        let vals = [1.0, 2.0, 2.0, 4.0];
        let mut lu = BandedLu::new(2, 1, 1);
        assert!(matches!(
            lu.factor(&p, &vals),
            Err(FactorError::Singular { .. })
        ));
    }
}
