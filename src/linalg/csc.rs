//! Compressed sparse column pattern with a lookup from (row, column) to value position.

use std::collections::BTreeSet;

/// A fixed square sparsity pattern in compressed sparse column form.
#[derive(Clone, Debug, Default)]
pub struct CscPattern {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl CscPattern {
    /// Pattern of an `n × n` matrix with the given nonzero `(row, col)` positions; the diagonal
    /// is always included.
    pub fn from_entries(n: usize, entries: impl IntoIterator<Item = (usize, usize)>) -> Self {
        let mut set: BTreeSet<(usize, usize)> = entries.into_iter().map(|(r, c)| (c, r)).collect();
        for i in 0..n {
            set.insert((i, i));
        }
        let mut col_ptr = vec![0usize; n + 1];
        let mut row_idx = Vec::with_capacity(set.len());
        for &(c, r) in &set {
            assert!(r < n && c < n, "pattern entry ({r}, {c}) outside {n}×{n}");
            col_ptr[c + 1] += 1;
            row_idx.push(r);
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        Self {
            n,
            col_ptr,
            row_idx,
        }
    }

    /// Matrix dimension.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Column pointers (length `n + 1`).
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }

    /// Row indices, sorted within each column.
    pub fn row_idx(&self) -> &[usize] {
        &self.row_idx
    }

    /// Position of entry `(row, col)` in the value array, if it is in the pattern.
    pub fn position(&self, row: usize, col: usize) -> Option<usize> {
        let (a, b) = (self.col_ptr[col], self.col_ptr[col + 1]);
        self.row_idx[a..b].binary_search(&row).ok().map(|k| a + k)
    }

    /// Lower and upper bandwidth `(kl, ku)`.
    pub fn bandwidths(&self) -> (usize, usize) {
        let (mut kl, mut ku) = (0, 0);
        for c in 0..self.n {
            for &r in &self.row_idx[self.col_ptr[c]..self.col_ptr[c + 1]] {
                if r > c {
                    kl = kl.max(r - c);
                } else {
                    ku = ku.max(c - r);
                }
            }
        }
        (kl, ku)
    }

    /// `y = A x` for values `vals` in this pattern.
    pub fn mul_vec(&self, vals: &[f64], x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        for c in 0..self.n {
            let xc = x[c];
            for k in self.col_ptr[c]..self.col_ptr[c + 1] {
                y[self.row_idx[k]] += vals[k] * xc;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_and_bandwidth() {
        let p = CscPattern::from_entries(4, [(0, 1), (3, 1), (2, 0)]);
        assert_eq!(p.nnz(), 7);
        assert!(p.position(3, 1).is_some());
        assert!(p.position(1, 3).is_none());
        assert_eq!(p.bandwidths(), (2, 1));
        let vals: Vec<f64> = (1..=7).map(|v| v as f64).collect();
        let mut y = vec![0.0; 4];
        p.mul_vec(&vals, &[1.0, 0.0, 0.0, 0.0], &mut y);
        // column 0 holds rows 0 and 2 with values 1 and 2
        assert_eq!(y, vec![1.0, 0.0, 2.0, 0.0]);
    }
}
