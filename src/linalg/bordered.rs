//! Bordered banded LU: for patterns that are banded after a Cuthill–McKee reordering except for
//! a few dense rows and columns (a closed belt loop is a ring, which no fixed order makes
//! banded; the angles of free pulleys couple with every belt coordinate).
//!
//! With the permutation `P`, `P A Pᵀ = [B C; D E]`: `B` (the core) is banded, `C`, `D` are the
//! few dense border columns and rows, `E` is small. Factorization: banded LU of `B`,
//! `W = B⁻¹C`, dense LU of the Schur complement `S = E − D W`. Solve: `y = B⁻¹ b₁`,
//! `x₂ = S⁻¹ (b₂ − D y)`, `x₁ = y − W x₂`. Cost O(n kl (kl + ku)) plus O(n m²) for `m` border
//! columns, against the fill of a general sparse LU on a ring with a dense border.

use super::FactorError;
use super::banded::BandedLu;
use super::csc::CscPattern;
use std::collections::VecDeque;

/// Where a value of the original pattern goes.
#[derive(Clone, Copy, Debug)]
enum Dest {
    /// Index into the core values.
    Core(usize),
    /// Border column `j` (border index), core row `i` (new index): `C[i, j]`.
    C(usize, usize),
    /// Border row `i`, core column `j`: `D[i, j]`.
    D(usize, usize),
    /// `E[i, j]`.
    E(usize, usize),
}

/// The bordered banded factorization of one pattern.
#[derive(Clone, Debug)]
pub struct BorderedBanded {
    n: usize,
    nb: usize,
    m: usize,
    /// new index → old index (core first, then border)
    perm: Vec<usize>,
    core: CscPattern,
    core_vals: Vec<f64>,
    dest: Vec<Dest>,
    band: BandedLu,
    /// `C`, then `W = B⁻¹C`, column-major `nb × m`
    w: Vec<f64>,
    /// `D`, row-major `m × nb`
    d: Vec<f64>,
    /// `E`, then the LU of the Schur complement, column-major `m × m`
    s: Vec<f64>,
    piv: Vec<usize>,
    work: Vec<f64>,
}

impl BorderedBanded {
    /// Analyses `pattern`: columns with more than `n/4` entries (at most 16, and only for
    /// `n ≥ 64`) form the border; the rest is reordered by Cuthill–McKee. Returns `None` when
    /// the reordered core is not narrow (`8 (kl + ku) > n_core` and `kl + ku > 24`).
    pub fn analyse(pattern: &CscPattern) -> Option<Self> {
        let n = pattern.n();
        let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
        let mut border: Vec<usize> = if n >= 64 {
            (0..n).filter(|&c| cp[c + 1] - cp[c] > n / 4).collect()
        } else {
            vec![]
        };
        if border.len() > 16 {
            return None;
        }
        border.sort_unstable();
        let mut is_border = vec![false; n];
        for &b in &border {
            is_border[b] = true;
        }
        // adjacency of the core (symmetrised)
        let mut adj: Vec<Vec<usize>> = vec![vec![]; n];
        for c in 0..n {
            for &r in &ri[cp[c]..cp[c + 1]] {
                if r != c && !is_border[r] && !is_border[c] {
                    adj[c].push(r);
                    adj[r].push(c);
                }
            }
        }
        for a in adj.iter_mut() {
            a.sort_unstable();
            a.dedup();
        }
        // Cuthill–McKee from a minimum-degree node of each component.
        let mut order = Vec::with_capacity(n);
        let mut seen = is_border.clone();
        loop {
            let start = (0..n).filter(|&i| !seen[i]).min_by_key(|&i| adj[i].len());
            let Some(start) = start else { break };
            let mut queue = VecDeque::from([start]);
            seen[start] = true;
            while let Some(v) = queue.pop_front() {
                order.push(v);
                let mut next: Vec<usize> = adj[v].iter().copied().filter(|&u| !seen[u]).collect();
                next.sort_by_key(|&u| adj[u].len());
                for u in next {
                    seen[u] = true;
                    queue.push_back(u);
                }
            }
        }
        let nb = order.len();
        let m = border.len();
        let mut perm = order;
        perm.extend_from_slice(&border);
        let mut inv = vec![0; n];
        for (new, &old) in perm.iter().enumerate() {
            inv[old] = new;
        }
        let mut entries = Vec::new();
        for c in 0..n {
            for &r in &ri[cp[c]..cp[c + 1]] {
                let (nr, nc) = (inv[r], inv[c]);
                if nr < nb && nc < nb {
                    entries.push((nr, nc));
                }
            }
        }
        let core = CscPattern::from_entries(nb, entries);
        let (kl, ku) = core.bandwidths();
        if !super::solver::band_is_cheap(kl + ku, nb) {
            return None;
        }
        let mut dest = Vec::with_capacity(pattern.nnz());
        for c in 0..n {
            for &r in &ri[cp[c]..cp[c + 1]] {
                let (nr, nc) = (inv[r], inv[c]);
                dest.push(match (nr < nb, nc < nb) {
                    (true, true) => Dest::Core(core.position(nr, nc).expect("in core pattern")),
                    (true, false) => Dest::C(nc - nb, nr),
                    (false, true) => Dest::D(nr - nb, nc),
                    (false, false) => Dest::E(nr - nb, nc - nb),
                });
            }
        }
        Some(Self {
            n,
            nb,
            m,
            perm,
            core_vals: vec![0.0; core.nnz()],
            band: BandedLu::new(nb, kl, ku),
            core,
            dest,
            w: vec![0.0; nb * m],
            d: vec![0.0; m * nb],
            s: vec![0.0; m * m],
            piv: vec![0; m],
            work: vec![0.0; n],
        })
    }

    /// Bandwidths `(kl, ku)` of the reordered core and the border size.
    pub fn shape(&self) -> (usize, usize, usize) {
        let (kl, ku) = self.core.bandwidths();
        (kl, ku, self.m)
    }

    /// Numeric factorization of `vals` (laid out in the analysed pattern).
    pub fn factor(&mut self, vals: &[f64]) -> Result<(), FactorError> {
        let (nb, m) = (self.nb, self.m);
        self.core_vals.iter_mut().for_each(|v| *v = 0.0);
        self.w.iter_mut().for_each(|v| *v = 0.0);
        self.d.iter_mut().for_each(|v| *v = 0.0);
        self.s.iter_mut().for_each(|v| *v = 0.0);
        for (v, d) in vals.iter().zip(&self.dest) {
            if !v.is_finite() {
                return Err(FactorError::NonFinite);
            }
            match *d {
                Dest::Core(p) => self.core_vals[p] = *v,
                Dest::C(j, i) => self.w[j * nb + i] = *v,
                Dest::D(i, j) => self.d[i * nb + j] = *v,
                Dest::E(i, j) => self.s[j * m + i] = *v,
            }
        }
        self.band.factor(&self.core, &self.core_vals)?;
        if m == 0 {
            return Ok(());
        }
        for j in 0..m {
            self.band.solve_in_place(&mut self.w[j * nb..(j + 1) * nb]);
        }
        // S = E − D W
        for j in 0..m {
            for i in 0..m {
                let row = &self.d[i * nb..(i + 1) * nb];
                let col = &self.w[j * nb..(j + 1) * nb];
                let dot: f64 = row.iter().zip(col).map(|(a, b)| a * b).sum();
                self.s[j * m + i] -= dot;
            }
        }
        // dense LU with partial pivoting (column-major)
        let scale = self.s.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for k in 0..m {
            let p = (k..m)
                .max_by(|&a, &b| self.s[k * m + a].abs().total_cmp(&self.s[k * m + b].abs()))
                .unwrap_or(k);
            self.piv[k] = p;
            if self.s[k * m + p].abs() <= scale * 1e-18 || self.s[k * m + p] == 0.0 {
                return Err(FactorError::Singular {
                    index: nb + k,
                    pivot: self.s[k * m + p],
                });
            }
            if p != k {
                for c in 0..m {
                    self.s.swap(c * m + p, c * m + k);
                }
            }
            let inv = 1.0 / self.s[k * m + k];
            for r in k + 1..m {
                self.s[k * m + r] *= inv;
            }
            for c in k + 1..m {
                let u = self.s[c * m + k];
                for r in k + 1..m {
                    self.s[c * m + r] -= self.s[k * m + r] * u;
                }
            }
        }
        Ok(())
    }

    /// Solves `A x = b` in place with the last factorization.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        let (n, nb, m) = (self.n, self.nb, self.m);
        for (new, &old) in self.perm.iter().enumerate() {
            self.work[new] = b[old];
        }
        let (x1, x2) = self.work.split_at_mut(nb);
        self.band.solve_in_place(x1);
        if m > 0 {
            for i in 0..m {
                let row = &self.d[i * nb..(i + 1) * nb];
                x2[i] -= row.iter().zip(x1.iter()).map(|(a, b)| a * b).sum::<f64>();
            }
            for k in 0..m {
                let p = self.piv[k];
                x2.swap(k, p);
                for r in k + 1..m {
                    x2[r] -= self.s[k * m + r] * x2[k];
                }
            }
            for k in (0..m).rev() {
                x2[k] /= self.s[k * m + k];
                for r in 0..k {
                    x2[r] -= self.s[k * m + r] * x2[k];
                }
            }
            for j in 0..m {
                let col = &self.w[j * nb..(j + 1) * nb];
                for (x, w) in x1.iter_mut().zip(col) {
                    *x -= w * x2[j];
                }
            }
        }
        for (new, &old) in self.perm.iter().enumerate().take(n) {
            b[old] = self.work[new];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ring of 2×2 blocks (a closed chain) with two dense border rows/columns: the bordered
    /// solver analyses it as narrow and solves like a dense reference.
    #[test]
    fn ring_with_border_solves_exactly() {
        let nodes = 60;
        let nc = 2 * nodes;
        let n = nc + 2;
        let mut entries = vec![];
        for k in 0..nodes {
            let a = 2 * k;
            let b = 2 * ((k + 1) % nodes);
            for i in [a, a + 1, b, b + 1] {
                for j in [a, a + 1, b, b + 1] {
                    entries.push((i, j));
                }
            }
        }
        for bcol in [nc, nc + 1] {
            for i in 0..n {
                entries.push((i, bcol));
                entries.push((bcol, i));
            }
        }
        let p = CscPattern::from_entries(n, entries);
        let mut vals = vec![0.0; p.nnz()];
        for c in 0..n {
            for k in p.col_ptr()[c]..p.col_ptr()[c + 1] {
                let r = p.row_idx()[k];
                vals[k] = if r == c {
                    10.0 + (c % 7) as f64
                } else {
                    ((r * 31 + c * 17) % 13) as f64 / 13.0 - 0.5
                };
            }
        }
        let mut s = BorderedBanded::analyse(&p).expect("narrow after reordering");
        let (kl, ku, m) = s.shape();
        assert_eq!(m, 2);
        assert!(kl + ku <= 16, "bandwidths {kl} {ku}");
        s.factor(&vals).unwrap();
        let rhs: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).cos()).collect();
        let mut x = rhs.clone();
        s.solve_in_place(&mut x);
        let mut y = vec![0.0; n];
        p.mul_vec(&vals, &x, &mut y);
        for i in 0..n {
            assert!(
                (y[i] - rhs[i]).abs() < 1e-12,
                "residual at {i}: {}",
                y[i] - rhs[i]
            );
        }
    }
}
