//! Banded LU factorization with partial pivoting (the algorithm of LAPACK `dgbtf2`/`dgbtrs`,
//! written from its description). Cost O(n kl (kl + ku)), storage (2 kl + ku + 1) n.
//!
//! **Pivoting on the equilibrated matrix.** The pivot of column `j` is chosen on the scaled
//! magnitudes `d_i |a_ij|` with `d_i = 1/√|a_ii|` (the symmetric diagonal scaling `D A D`; the
//! column's own factor `d_j` is common to the candidates), and the diagonal is kept unless a
//! candidate below it is larger than `1/τ` times it, `τ =` [`PIVOT_THRESHOLD`] (threshold
//! partial pivoting: Duff, Erisman & Reid, *Direct Methods for Sparse Matrices*, 2nd ed. 2017,
//! §4.4; the bound on the growth per step is `1 + 1/τ`). Elimination commutes with the
//! scaling, so this is partial pivoting (with a threshold) of `D A D`, as stable as that, with
//! the factors of `A` itself. It matters for coordinates of mixed units: the iteration matrix of
//! an ANCF element couples positions [m] with slopes [–], whose mass entries are ~`L²` smaller.
//! Plain partial pivoting then swaps most rows (357 of 480 for a 120-element belt loop), and
//! each swap widens `U` from `ku` towards `kl + ku` and the work with it.
//!
//! **Panels.** Wide bands are eliminated in panels ([`panel_width`]); the columns right of a panel
//! take its updates afterwards, four at a time in registers, each entry in the order and with
//! the roundings of the column-by-column elimination (the factors are the same to the bit: test
//! `panels_give_the_column_by_column_factors_to_the_bit`). A row interchange first brings the
//! columns right of the panel up to date.

use super::FactorError;
use super::csc::CscPattern;

/// Threshold `τ` of the pivot choice: the diagonal stays the pivot while its scaled magnitude
/// is at least `τ` times the largest below it (see the module notes).
pub const PIVOT_THRESHOLD: f64 = 0.1;

/// A banded LU factorization with partial pivoting; buffers are reused between factorizations.
#[derive(Clone, Debug, Default)]
pub struct BandedLu {
    n: usize,
    kl: usize,
    ku: usize,
    ldab: usize,
    ab: Vec<f64>,
    ipiv: Vec<usize>,
    /// Pivot scale `d_i` of the row now at position `i` (swapped with the rows).
    scale: Vec<f64>,
    /// Band-storage index of each value of the pattern, built at the first factorization (an
    /// object factorizes the values of one pattern).
    map: Vec<usize>,
    /// Upper bandwidth of the last factorization's `U`: `ku` plus the fill of row
    /// interchanges, at most `kl + ku` (the back substitution skips the band above it, which
    /// holds exact zeros).
    ub: usize,
    /// Reciprocals of `U`'s diagonal (the back substitution multiplies: a division on its
    /// dependency chain costs several times a multiplication).
    inv_diag: Vec<f64>,
    /// Whether the last factorization interchanged rows (else the solves skip the pivots).
    swapped: bool,
    /// Columns eliminated together before the columns right of them are updated (see
    /// [`flush`]): [`panel_width`]; 1 is the column-by-column order of `dgbtf2` (tests compare).
    panel: usize,
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
            scale: vec![0.0; n],
            map: Vec::new(),
            ub: kl + ku,
            inv_diag: vec![0.0; n],
            swapped: true,
            panel: panel_width(kl),
        }
    }

    /// Index of `A(i, j)` in band storage (valid for `j − ku − kl ≤ i ≤ j + kl`).
    #[inline(always)]
    fn at(&self, i: usize, j: usize) -> usize {
        (self.kl + self.ku + i - j) + j * self.ldab
    }

    /// Index of `A(i, j)` in the band storage (`j − ku ≤ i ≤ j + kl`), for callers that
    /// scatter their values themselves ([`Self::factor_entries`]).
    pub fn band_index(&self, i: usize, j: usize) -> usize {
        debug_assert!(i + self.ku >= j && i <= j + self.kl);
        self.at(i, j)
    }

    /// Factorizes the matrix with values `vals` in `pattern` (which must fit the bandwidths).
    pub fn factor(&mut self, pattern: &CscPattern, vals: &[f64]) -> Result<(), FactorError> {
        if self.map.len() != pattern.nnz() {
            // band position of every entry of the pattern (one pattern per factorization object)
            self.map = (0..self.n)
                .flat_map(|c| {
                    (pattern.col_ptr()[c]..pattern.col_ptr()[c + 1])
                        .map(move |k| (pattern.row_idx()[k], c))
                })
                .map(|(r, c)| self.at(r, c))
                .collect();
        }
        let map = std::mem::take(&mut self.map);
        let res = self.factor_entries(map.iter().copied().zip(vals.iter().copied()));
        self.map = map;
        res
    }

    /// Factorizes the matrix given as `(band index, value)` pairs (band indices from
    /// [`Self::band_index`]; positions not given are zero).
    pub fn factor_entries(
        &mut self,
        entries: impl Iterator<Item = (usize, f64)>,
    ) -> Result<(), FactorError> {
        let n = self.n;
        let (kl, ku, ldab) = (self.kl, self.ku, self.ldab);
        let kv = kl + ku;
        // Zero the storage. Rows 0..kl − (ub − ku) of every column (above U's last bandwidth
        // `ub`) only receive the fill of row interchanges and are still zero.
        let skip = kv - self.ub;
        if skip == 0 {
            self.ab.fill(0.0);
        } else {
            for col in self.ab.chunks_exact_mut(ldab) {
                col[skip..].fill(0.0);
            }
        }
        // the largest magnitude by a plain comparison (one `maxsd` on the loop's dependency
        // chain, not `f64::max`'s NaN handling): a NaN or infinity is reported below, and for
        // finite values the maximum is the same
        let mut scale = 0.0f64;
        let mut finite = true;
        for (idx, v) in entries {
            finite &= v.is_finite();
            let a = v.abs();
            scale = if a > scale { a } else { scale };
            self.ab[idx] = v;
        }
        if !finite {
            self.ub = kv;
            return Err(FactorError::NonFinite);
        }
        // pivot scales d_i = 1/√|a_ii|; a zero diagonal takes the matrix's largest entry
        let fallback = if scale > 0.0 { 1.0 / scale.sqrt() } else { 1.0 };
        for (i, d) in self.scale.iter_mut().enumerate() {
            let a = self.ab[kv + i * ldab].abs();
            *d = if a > 0.0 { 1.0 / a.sqrt() } else { fallback };
        }
        // Only exact or round-off-level pivots count as singular: thin, stiff beams legitimately have
        // pivots ~1e-13 of the largest entry.
        let tiny = scale * 1e-18;
        let mut ju = 0usize;
        let mut ub = ku;
        // until the elimination ends, the storage may hold fill above `ub` (a failed
        // factorization leaves it there)
        self.ub = kv;
        let nb = self.panel.max(1);
        let mut j0 = 0;
        while j0 < n {
            // Panel: columns j0..pend eliminate each other at once; the columns right of it
            // have received the updates of the panel's columns below `ds` (see `flush`).
            let pend = (j0 + nb).min(n);
            let mut ds = j0;
            for j in j0..pend {
                let km = kl.min(n - 1 - j);
                let jj = kv + j * ldab;
                // pivot search in column j, rows j..=j+km, on the scaled magnitudes
                let (jp, best) = {
                    let col = &self.ab[jj..jj + km + 1];
                    let sc = &self.scale[j..j + km + 1];
                    let diag = col[0].abs() * sc[0];
                    // the largest scaled candidate below the diagonal (no index: the diagonal
                    // stays in almost every column), then the first row that reaches it if it
                    // must
                    let b = scaled_max(&col[1..], &sc[1..]);
                    let jp = if b <= diag || diag >= PIVOT_THRESHOLD * b {
                        0
                    } else {
                        1 + col[1..]
                            .iter()
                            .zip(&sc[1..])
                            .position(|(&a, &d)| a.abs() * d == b)
                            .expect("the maximum is reached")
                    };
                    (jp, col[jp].abs())
                };
                self.ipiv[j] = j + jp;
                if best <= tiny || best == 0.0 {
                    return Err(FactorError::Singular {
                        index: j,
                        pivot: self.ab[jj + jp],
                    });
                }
                if jp != 0 && nb > 1 {
                    // the rows to interchange must hold every update before them in the
                    // columns right of the panel too
                    flush(&mut self.ab, kv, ldab, kl, n, ds..j, pend..ju + 1);
                    ds = j;
                }
                ju = ju.max((j + ku + jp).min(n - 1));
                ub = ub.max(ju - j);
                if jp != 0 {
                    for c in j..=ju {
                        let (a, b) = (self.at(j + jp, c), self.at(j, c));
                        self.ab.swap(a, b);
                    }
                    self.scale.swap(j, j + jp);
                }
                if km > 0 {
                    // In band storage the rows j+1..=j+km of any column are contiguous.
                    let inv = 1.0 / self.ab[jj];
                    let (head, tail) = self.ab.split_at_mut(jj + 1 + km);
                    let l = &mut head[jj + 1..];
                    l.iter_mut().for_each(|x| *x *= inv);
                    let l: &[f64] = l;
                    // A(j, c) for c = j + 1 + k is at jj + (k + 1)(ldab − 1), i.e. in `tail`
                    // at (k + 1)(ldab − 1) − 1 − km; its column's rows j+1..=j+km follow it.
                    // Columns of the panel only: the others wait for `flush` (one column
                    // at a time: every column, as `dgbtf2`).
                    let reach = if nb > 1 { ju.min(pend - 1) } else { ju };
                    let stride = ldab - 1;
                    for k in 0..reach - j {
                        let top = (k + 1) * stride - 1 - km;
                        let u = tail[top];
                        if u != 0.0 {
                            axpy_neg(&mut tail[top + 1..top + 1 + km], l, u);
                        }
                    }
                }
            }
            if nb > 1 {
                flush(&mut self.ab, kv, ldab, kl, n, ds..pend, pend..ju + 1);
            }
            j0 = pend;
        }
        self.ub = ub.min(kv);
        for (j, d) in self.inv_diag.iter_mut().enumerate() {
            *d = 1.0 / self.ab[kv + j * ldab];
        }
        self.swapped = (0..n).any(|j| self.ipiv[j] != j);
        Ok(())
    }

    /// Row interchanges of the last factorization.
    pub fn row_swaps(&self) -> usize {
        (0..self.n).filter(|&j| self.ipiv[j] != j).count()
    }

    /// Solves `A x = b` in place with the last factorization. Without row interchanges both
    /// sweeps take four columns of `L` or `U` at a time ([`forward4`], [`backward4`]: each
    /// entry of `b` takes the four updates in a register, in the order and with the roundings
    /// of the column-by-column sweeps, so the solution is the same to the bit; test
    /// `blocked_solve_gives_the_column_by_column_solution_to_the_bit`). Session 39: the sweeps
    /// stream the factors (`n (kl + ub)` values, 3.6 MB for the level-1 air spring's
    /// `n` = 2808, `kl = ub` = 80, beyond L2) and one pass per column also loaded and stored
    /// `b`'s band rows once per column.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        if self.swapped {
            return self.solve_in_place_columns(b);
        }
        let n = self.n;
        let (kl, kv, ldab) = (self.kl, self.kl + self.ku, self.ldab);
        let ab = &self.ab[..];
        let mut j = 0;
        while j < n {
            if kl >= 4 && j + 3 + kl < n && forward4(ab, kv, ldab, kl, j, b) {
                j += 4;
                continue;
            }
            let lm = kl.min(n - 1 - j);
            let bj = b[j];
            if bj != 0.0 {
                let jj = kv + j * ldab;
                axpy_neg(&mut b[j + 1..j + 1 + lm], &ab[jj + 1..jj + 1 + lm], bj);
            }
            j += 1;
        }
        let ub = self.ub;
        // columns j + 1.. are done; j counts down
        let mut j = n;
        while j > 0 {
            if ub >= 4 && j >= ub + 4 {
                backward4(ab, kv, ldab, ub, &self.inv_diag, j - 1, b);
                j -= 4;
                continue;
            }
            j -= 1;
            let jj = kv + j * ldab;
            b[j] *= self.inv_diag[j];
            let bj = b[j];
            let i0 = j.saturating_sub(ub);
            axpy_neg(&mut b[i0..j], &ab[jj - (j - i0)..jj], bj);
        }
    }

    /// [`Self::solve_in_place`] one column at a time (the order of `dgbtrs`), with row
    /// interchanges.
    fn solve_in_place_columns(&self, b: &mut [f64]) {
        let n = self.n;
        let (kv, ldab) = (self.kl + self.ku, self.ldab);
        for j in 0..n {
            if self.swapped {
                let l = self.ipiv[j];
                if l != j {
                    b.swap(l, j);
                }
            }
            let lm = self.kl.min(n - 1 - j);
            let bj = b[j];
            if bj != 0.0 {
                let jj = kv + j * ldab;
                axpy_neg(&mut b[j + 1..j + 1 + lm], &self.ab[jj + 1..jj + 1 + lm], bj);
            }
        }
        // rows of U above j − ub in column j are zero: row j's entries reach column ju ≤ j + ub
        let ub = self.ub;
        for j in (0..n).rev() {
            let jj = kv + j * ldab;
            b[j] *= self.inv_diag[j];
            let bj = b[j];
            let i0 = j.saturating_sub(ub);
            axpy_neg(&mut b[i0..j], &self.ab[jj - (j - i0)..jj], bj);
        }
    }

    /// Solves `A X = B` in place for the right-hand sides stored one after the other in `b`
    /// (column-major `n × k`, `b.len() = k n`): one pass over `L` and `U` for all of them
    /// (each column as [`Self::solve_in_place`] solves it).
    pub fn solve_many_in_place(&self, b: &mut [f64]) {
        let n = self.n;
        if b.len() == n {
            return self.solve_in_place(b);
        }
        if n == 0 {
            return;
        }
        debug_assert!(b.len().is_multiple_of(n));
        let (kv, ldab) = (self.kl + self.ku, self.ldab);
        for j in 0..n {
            let l = self.ipiv[j];
            let lm = self.kl.min(n - 1 - j);
            let jj = kv + j * ldab;
            let lcol = &self.ab[jj + 1..jj + 1 + lm];
            for x in b.chunks_exact_mut(n) {
                if l != j {
                    x.swap(l, j);
                }
                let bj = x[j];
                if bj != 0.0 {
                    axpy_neg(&mut x[j + 1..j + 1 + lm], lcol, bj);
                }
            }
        }
        // rows of U above j − ub in column j are zero: row j's entries reach column ju ≤ j + ub
        let ub = self.ub;
        for j in (0..n).rev() {
            let jj = kv + j * ldab;
            let i0 = j.saturating_sub(ub);
            let ucol = &self.ab[jj - (j - i0)..jj];
            let d = self.inv_diag[j];
            for x in b.chunks_exact_mut(n) {
                x[j] *= d;
                let bj = x[j];
                axpy_neg(&mut x[i0..j], ucol, bj);
            }
        }
    }
}

/// `max_i |a_i| d_i` (0 for empty slices), NaN ignored as by `f64::max`: four independent
/// running maxima instead of one serial chain (the pivot search of every column; the maximum
/// does not depend on the order).
#[inline(always)]
fn scaled_max(a: &[f64], d: &[f64]) -> f64 {
    let mut m = [0.0f64; 4];
    let (ca, cd) = (a.chunks_exact(4), d.chunks_exact(4));
    let (ra, rd) = (ca.remainder(), cd.remainder());
    for (x, s) in ca.zip(cd) {
        for k in 0..4 {
            let v = x[k].abs() * s[k];
            if v > m[k] {
                m[k] = v;
            }
        }
    }
    for (x, s) in ra.iter().zip(rd) {
        let v = x.abs() * s;
        if v > m[0] {
            m[0] = v;
        }
    }
    m[0].max(m[1]).max(m[2].max(m[3]))
}

/// Columns per panel of the factorization for the lower bandwidth `kl`. Each column right of
/// a panel takes the panel's updates four columns at a time in registers ([`group4`]) instead
/// of one pass per column (LAPACK `dgbtrf` blocks with work arrays; this keeps the arithmetic
/// of `dgbtf2`). On full random bands (best of 20, `n`, `kl = ku`) panels of 16 were 1.27x
/// faster at 480, 7, 1.17x at 726, 17 and 1.40x at 2880, 75; but on the belts' bands, whose
/// `U` rows hold exact zeros that the column-by-column elimination skips (and that end a group
/// of four), whole runs were 5-10 % slower (planar belt, 120 elements, `kl` 7; 3D belt, `kl` 17).
/// Wide bands fill in (the shell's ring-ordered meshes, `kl` ~ 75: 3 % faster level-1 air
/// spring runs): panels from `kl` = 24 on.
fn panel_width(kl: usize) -> usize {
    if kl >= 24 { 16 } else { 1 }
}

/// The updates of the eliminated columns `ks` (their `L` columns are final) on the columns
/// `cols` right of the panel, column by column: each column takes them in the order of `ks`,
/// the order in which the column-by-column elimination applies them, so the result is the
/// same to the bit. A row `k` of a column `c` outside the band storage (`c − k > kv`) or holding
/// an exact zero gives no update, as in the column-by-column elimination.
fn flush(
    ab: &mut [f64],
    kv: usize,
    ldab: usize,
    kl: usize,
    n: usize,
    ks: std::ops::Range<usize>,
    cols: std::ops::Range<usize>,
) {
    if ks.is_empty() {
        return;
    }
    for c in cols {
        let (head, tail) = ab.split_at_mut(c * ldab);
        let mut k = ks.start;
        while k < ks.end {
            // rows k..=k+km of column c start at kv + k − c in its storage
            let Some(top) = (kv + k).checked_sub(c) else {
                k += 1;
                continue;
            };
            // four columns at once where all four reach kl rows down and none of their `U`
            // entries in column c is zero (each row of column c then takes the four updates
            // in a register, in the same order and roundings as four passes)
            if k + 4 <= ks.end
                && kl >= 4
                && k + 3 + kl < n
                && group4(head, tail, kv, ldab, kl, k, top)
            {
                k += 4;
                continue;
            }
            let km = kl.min(n - 1 - k);
            let u = tail[top];
            if u != 0.0 {
                let lk = kv + 1 + k * ldab;
                axpy_neg(&mut tail[top + 1..top + 1 + km], &head[lk..lk + km], u);
            }
            k += 1;
        }
    }
}

/// The updates of the four eliminated columns `k..k + 4` (each with `kl` rows of `L`) on the
/// column whose storage is `col`, row `k` of it at `col[top]`; `l` holds the `L` columns. Does
/// nothing and returns false if one of the four `U` entries is zero (the caller then skips
/// that update, as the column-by-column elimination does).
fn group4(
    l: &[f64],
    col: &mut [f64],
    kv: usize,
    ldab: usize,
    kl: usize,
    k: usize,
    top: usize,
) -> bool {
    let lk = |j: usize| kv + 1 + (k + j) * ldab;
    let mut u = [col[top], 0.0, 0.0, 0.0];
    if u[0] == 0.0 {
        return false;
    }
    // rows k+1..=k+3 first: row k+j becomes U's entry u[j] once the columns before it are
    // applied
    for j in 1..4 {
        // the value of row k+j after the updates of columns k..k+j (not yet applied)
        let mut x = col[top + j];
        for (i, ui) in u.iter().enumerate().take(j) {
            x -= l[lk(i) + j - i - 1] * ui;
        }
        if x == 0.0 {
            return false;
        }
        u[j] = x;
    }
    col[top + 1..top + 4].copy_from_slice(&u[1..4]);
    // rows k+4..=k+kl take all four
    {
        let x = &mut col[top + 4..=top + kl];
        let l0 = &l[lk(0) + 3..lk(0) + kl];
        let l1 = &l[lk(1) + 2..lk(1) + kl - 1];
        let l2 = &l[lk(2) + 1..lk(2) + kl - 2];
        let l3 = &l[lk(3)..lk(3) + kl - 3];
        for ((((x, a), b), c), d) in x.iter_mut().zip(l0).zip(l1).zip(l2).zip(l3) {
            *x = *x - a * u[0] - b * u[1] - c * u[2] - d * u[3];
        }
    }
    // rows k+kl+1..=k+kl+3 below column k's reach
    for r in kl + 1..=kl + 3 {
        let mut x = col[top + r];
        for (j, uj) in u.iter().enumerate().skip(r - kl) {
            x -= l[lk(j) + r - j - 1] * uj;
        }
        col[top + r] = x;
    }
    true
}

/// The forward sweep's updates of the four columns `j..j + 4` of `L` (each `kl` rows long, at
/// `ab`'s band storage) on `b`, each row taking them in column order in a register: the values
/// and roundings of four column passes. Does nothing and returns false if one of `b[j..j + 4]`
/// is an exact zero once the columns before it are applied (the column pass skips that
/// column; the caller then takes column `j` alone).
fn forward4(ab: &[f64], kv: usize, ldab: usize, kl: usize, j: usize, b: &mut [f64]) -> bool {
    // L(j + c + 1 + r, j + c) is at lc(c) + r
    let lc = |c: usize| kv + 1 + (j + c) * ldab;
    let mut u = [b[j], 0.0, 0.0, 0.0];
    if u[0] == 0.0 {
        return false;
    }
    for r in 1..4 {
        let mut x = b[j + r];
        for (c, uc) in u.iter().enumerate().take(r) {
            x -= ab[lc(c) + r - c - 1] * uc;
        }
        if x == 0.0 {
            return false;
        }
        u[r] = x;
    }
    b[j + 1..j + 4].copy_from_slice(&u[1..4]);
    // rows j + 4..=j + kl take all four
    {
        let x = &mut b[j + 4..=j + kl];
        let l0 = &ab[lc(0) + 3..lc(0) + kl];
        let l1 = &ab[lc(1) + 2..lc(1) + kl - 1];
        let l2 = &ab[lc(2) + 1..lc(2) + kl - 2];
        let l3 = &ab[lc(3)..lc(3) + kl - 3];
        for ((((x, a), bb), c), d) in x.iter_mut().zip(l0).zip(l1).zip(l2).zip(l3) {
            *x = *x - a * u[0] - bb * u[1] - c * u[2] - d * u[3];
        }
    }
    // rows j + kl + 1..=j + kl + 3, below column j's reach
    for r in kl + 1..=kl + 3 {
        let mut x = b[j + r];
        for (c, uc) in u.iter().enumerate().skip(r - kl) {
            x -= ab[lc(c) + r - c - 1] * uc;
        }
        b[j + r] = x;
    }
    true
}

/// The back substitution of the four columns `j, j − 1, j − 2, j − 3` of `U` (upper bandwidth
/// `ub`, `j ≥ ub + 3`, diagonal reciprocals `inv_diag`) on `b`: each row takes the four updates
/// in a register in the order of the column passes (column `j` first), with their roundings.
fn backward4(
    ab: &[f64],
    kv: usize,
    ldab: usize,
    ub: usize,
    inv_diag: &[f64],
    j: usize,
    b: &mut [f64],
) {
    // U(i, j − c) is at dc(c) − (j − c − i), dc(c) its diagonal's position
    let dc = |c: usize| kv + (j - c) * ldab;
    let at = |c: usize, i: usize| dc(c) - (j - c - i);
    let mut x = [0.0f64; 4];
    for c in 0..4 {
        let mut y = b[j - c];
        for (k, xk) in x.iter().enumerate().take(c) {
            y -= ab[at(k, j - c)] * xk;
        }
        x[c] = y * inv_diag[j - c];
    }
    for (c, xc) in x.iter().enumerate() {
        b[j - c] = *xc;
    }
    // rows j − ub..=j − 4 take all four
    {
        let lo = j - ub;
        let y = &mut b[lo..=j - 4];
        let u0 = &ab[at(0, lo)..=at(0, j - 4)];
        let u1 = &ab[at(1, lo)..=at(1, j - 4)];
        let u2 = &ab[at(2, lo)..=at(2, j - 4)];
        let u3 = &ab[at(3, lo)..=at(3, j - 4)];
        for ((((y, a), bb), c), d) in y.iter_mut().zip(u0).zip(u1).zip(u2).zip(u3) {
            *y = *y - a * x[0] - bb * x[1] - c * x[2] - d * x[3];
        }
    }
    // rows j − 3 − ub..j − ub, above column j's reach: column j − c reaches rows ≥ j − c − ub
    for i in j - 3 - ub..j - ub {
        let mut y = b[i];
        for (c, xc) in x.iter().enumerate() {
            if i + ub >= j - c {
                y -= ab[at(c, i)] * xc;
            }
        }
        b[i] = y;
    }
}

/// `x −= u l` over equal-length slices (the compiler vectorises the zipped loop).
#[inline(always)]
fn axpy_neg(x: &mut [f64], l: &[f64], u: f64) {
    for (x, &lr) in x.iter_mut().zip(l) {
        *x -= lr * u;
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

    /// An SPD matrix with coordinates of mixed units, as an ANCF belt's iteration matrix: a
    /// chain of nodes with a position (scale 1) and a slope coordinate (scale `L` = 1e-2), the
    /// matrix `S (M + K) S` with `M`, `K` diagonally dominant. Plain partial pivoting swaps rows
    /// here (a position entry below a slope diagonal is larger); pivoting on the scaled
    /// magnitudes keeps the diagonal, so `U` keeps the bandwidth `ku`, and the solve is exact.
    /// A zero diagonal (a constraint-like row) still takes a pivot from below.
    #[test]
    fn scaled_pivoting_keeps_the_diagonal_of_mixed_unit_matrices() {
        let nodes = 40;
        let n = 2 * nodes;
        let (kl, ku) = (3usize, 3usize);
        let sc = |i: usize| if i.is_multiple_of(2) { 1.0 } else { 1e-2 };
        let mut entries = vec![];
        let mut dense = vec![vec![0.0; n]; n];
        for c in 0..n {
            for r in c.saturating_sub(ku)..(c + kl + 1).min(n) {
                entries.push((r, c));
                let base = if r == c {
                    4.0
                } else {
                    0.9 / (1.0 + (r as f64 - c as f64).abs())
                };
                dense[r][c] = sc(r) * base * sc(c);
            }
        }
        let p = CscPattern::from_entries(n, entries);
        let fill = |dense: &Vec<Vec<f64>>| -> Vec<f64> {
            let mut vals = vec![0.0; p.nnz()];
            for c in 0..n {
                for k in p.col_ptr()[c]..p.col_ptr()[c + 1] {
                    vals[k] = dense[p.row_idx()[k]][c];
                }
            }
            vals
        };
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let check = |dense: &Vec<Vec<f64>>, swaps_expected: Option<usize>| {
            let vals = fill(dense);
            let mut b = vec![0.0; n];
            p.mul_vec(&vals, &x, &mut b);
            let mut lu = BandedLu::new(n, kl, ku);
            lu.factor(&p, &vals).unwrap();
            if let Some(s) = swaps_expected {
                assert_eq!(lu.row_swaps(), s);
            } else {
                assert!(lu.row_swaps() > 0);
            }
            lu.solve_in_place(&mut b);
            let err = b
                .iter()
                .zip(&x)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(err < 1e-10, "error {err}");
        };
        // plain partial pivoting would swap: a position entry exceeds the slope diagonal
        assert!(dense[2][1].abs() > dense[1][1].abs());
        check(&dense, Some(0));
        // a zero pivot (the first diagonal, before any update) needs a row interchange
        dense[0][0] = 0.0;
        check(&dense, None);
    }

    /// A random banded system of size `n` (values from `seed`), optionally with a zero first
    /// diagonal (a row interchange and the fill of `U` it brings).
    fn random_band(
        n: usize,
        kl: usize,
        ku: usize,
        seed: u64,
        zero_pivot: bool,
    ) -> (CscPattern, Vec<f64>) {
        let mut seed = seed;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let mut entries = vec![];
        for c in 0..n {
            for r in c.saturating_sub(ku)..(c + kl + 1).min(n) {
                entries.push((r, c));
            }
        }
        let p = CscPattern::from_entries(n, entries);
        let mut vals = vec![0.0; p.nnz()];
        for c in 0..n {
            for k in p.col_ptr()[c]..p.col_ptr()[c + 1] {
                let r = p.row_idx()[k];
                vals[k] = if r == c { 4.0 + rnd() } else { rnd() };
                if zero_pivot && r == 0 && c == 0 {
                    vals[k] = 0.0;
                }
            }
        }
        (p, vals)
    }

    /// One object refactorizing matrices with and without row interchanges (the storage is
    /// only partly cleared between them) solves every one exactly as a fresh object does, and
    /// the multi-column solve gives each column exactly as the single solve.
    #[test]
    fn refactorization_and_multi_column_solve_match_fresh_single_solves() {
        let (n, kl, ku) = (30, 3, 2);
        let rhs: Vec<f64> = (0..3 * n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut lu = BandedLu::new(n, kl, ku);
        for (seed, zero_pivot) in [(1, true), (2, false), (3, true), (4, false)] {
            let (p, vals) = random_band(n, kl, ku, seed, zero_pivot);
            let mut fresh = BandedLu::new(n, kl, ku);
            fresh.factor(&p, &vals).unwrap();
            assert_eq!(fresh.row_swaps() > 0, zero_pivot);
            lu.factor(&p, &vals).unwrap();
            let mut many = rhs.clone();
            lu.solve_many_in_place(&mut many);
            for (k, col) in many.chunks(n).enumerate() {
                let mut single = rhs[k * n..(k + 1) * n].to_vec();
                fresh.solve_in_place(&mut single);
                assert_eq!(col, &single[..], "seed {seed}, column {k}");
            }
        }
    }

    /// Panels change the order of the loops, not the arithmetic: factors, pivots and solves of
    /// wide random bands, with row interchanges in the middle of panels (small diagonals every
    /// 7th column), equal the column-by-column elimination's to the bit, for several widths.
    #[test]
    fn panels_give_the_column_by_column_factors_to_the_bit() {
        let (n, kl, ku) = (150, 30, 24);
        for seed in [5, 6] {
            let (p, mut vals) = random_band(n, kl, ku, seed, true);
            for c in (3..n).step_by(7) {
                let k = p.position(c, c).unwrap();
                vals[k] *= 1e-3;
            }
            let rhs: Vec<f64> = (0..n).map(|i| (i as f64 * 0.61).cos()).collect();
            let mut one = BandedLu::new(n, kl, ku);
            one.panel = 1;
            one.factor(&p, &vals).unwrap();
            assert!(one.row_swaps() > 10, "{} interchanges", one.row_swaps());
            let mut x1 = rhs.clone();
            one.solve_in_place(&mut x1);
            for nb in [2, 5, 16, 64] {
                let mut lu = BandedLu::new(n, kl, ku);
                lu.panel = nb;
                lu.factor(&p, &vals).unwrap();
                assert_eq!(lu.ipiv, one.ipiv, "panel {nb}");
                assert_eq!(lu.ub, one.ub, "panel {nb}");
                let same = lu
                    .ab
                    .iter()
                    .zip(&one.ab)
                    .all(|(a, b)| a.to_bits() == b.to_bits());
                assert!(same, "panel {nb}: factors differ");
                let mut x = rhs.clone();
                lu.solve_in_place(&mut x);
                assert_eq!(x, x1, "panel {nb}");
            }
            // and the solution is one
            let mut r = 0.0f64;
            let mut ax = vec![0.0; n];
            for c in 0..n {
                for k in p.col_ptr()[c]..p.col_ptr()[c + 1] {
                    ax[p.row_idx()[k]] += vals[k] * x1[c];
                }
            }
            for i in 0..n {
                r = r.max((ax[i] - rhs[i]).abs());
            }
            assert!(r < 1e-9, "residual {r}");
        }
    }

    /// The blocked sweeps of [`BandedLu::solve_in_place`] (four columns at a time, without row
    /// interchanges) give the column-by-column solution to the bit, for bands narrower and wider
    /// than a block, `ku` below and above `kl`, and right-hand sides with exact zeros (the
    /// forward column pass skips a zero; the blocked one must then take that column alone).
    #[test]
    fn blocked_solve_gives_the_column_by_column_solution_to_the_bit() {
        for &(n, kl, ku) in &[
            (150usize, 30usize, 24usize),
            (97, 9, 13),
            (64, 4, 4),
            (40, 7, 3),
            (12, 5, 5),
            (9, 3, 2),
        ] {
            for seed in [7, 8] {
                let (p, mut vals) = random_band(n, kl, ku, seed, false);
                // diagonally dominant: no row interchanges (the blocked path)
                for c in 0..n {
                    for k in p.col_ptr()[c]..p.col_ptr()[c + 1] {
                        if p.row_idx()[k] != c {
                            vals[k] *= 1.0 / (kl + ku) as f64;
                        }
                    }
                }
                let mut lu = BandedLu::new(n, kl, ku);
                lu.factor(&p, &vals).unwrap();
                assert_eq!(lu.row_swaps(), 0);
                // zeros in runs and alone: the forward sweep meets zero pivots' rows in every
                // position of a block of four
                let rhs: Vec<f64> = (0..n)
                    .map(|i| {
                        if i % 11 < 2 || i % 17 == 5 {
                            0.0
                        } else {
                            (i as f64 * 0.61).cos()
                        }
                    })
                    .collect();
                let mut x1 = rhs.clone();
                lu.solve_in_place_columns(&mut x1);
                let mut x = rhs.clone();
                lu.solve_in_place(&mut x);
                let same = x.iter().zip(&x1).all(|(a, b)| a.to_bits() == b.to_bits());
                assert!(same, "n {n}, kl {kl}, ku {ku}, seed {seed}");
                // and it is the solution
                let mut ax = vec![0.0; n];
                p.mul_vec(&vals, &x, &mut ax);
                let r = ax
                    .iter()
                    .zip(&rhs)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                assert!(r < 1e-12, "residual {r}");
            }
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
