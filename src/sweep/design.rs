//! The points of a sweep: grids (`linspace`, lists, constants) crossed with a seeded Latin
//! hypercube sample.
//!
//! Latin hypercube sampling after McKay, Beckman and Conover (1979), "A comparison of three
//! methods for selecting values of input variables in the analysis of output from a computer
//! code", Technometrics 21(2): each of the `n` equal strata of every range holds exactly one
//! sample, at a uniformly random place inside it; the strata are paired across dimensions by
//! independent random permutations. The random numbers come from SplitMix64 (Steele, Lea and
//! Flood 2014, "Fast splittable pseudorandom number generators", OOPSLA), so a seed gives the
//! same design on every platform.

/// SplitMix64 pseudo-random generator (Steele, Lea and Flood 2014, the `mix64` finaliser).
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator started from `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform number in [0, 1): the top 53 bits over 2^53.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A uniform integer in 0..n (`n` > 0; modulo bias below n / 2^64).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// `n` values from `lo` to `hi` inclusive, equally spaced: `lo + (hi - lo) i / (n - 1)`
/// (the last one is `hi` exactly); one value `lo` when `n` = 1.
pub fn linspace(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| match (i, n) {
            (0, _) => lo,
            (i, n) if i + 1 == n => hi,
            (i, n) => lo + (hi - lo) * (i as f64 / (n - 1) as f64),
        })
        .collect()
}

/// A Latin hypercube sample of `n` points over the ranges `[lo, hi]` (one per dimension),
/// seeded: `out[i][d]` = `lo_d + (hi_d - lo_d) (π_d(i) + u_id) / n`, with `π_d` a random
/// permutation of `0..n` (Fisher–Yates) and `u_id` uniform in [0, 1) (McKay et al. 1979).
/// Dimension by dimension: first the permutation, then the `n` offsets.
pub fn latin_hypercube(ranges: &[[f64; 2]], n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = SplitMix64::new(seed);
    let mut out = vec![Vec::with_capacity(ranges.len()); n];
    for &[lo, hi] in ranges {
        let mut perm: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            perm.swap(i, rng.below(i + 1));
        }
        for (i, row) in out.iter_mut().enumerate() {
            let u = rng.uniform();
            row.push(lo + (hi - lo) * ((perm[i] as f64 + u) / n as f64));
        }
    }
    out
}

/// The Cartesian product of `axes` (the first axis varies slowest), each point the list of
/// one value per axis. No axes: one empty point.
pub fn grid<T: Clone>(axes: &[Vec<T>]) -> Vec<Vec<T>> {
    let mut points = vec![Vec::new()];
    for axis in axes {
        points = points
            .iter()
            .flat_map(|p| {
                axis.iter().map(move |v| {
                    let mut q = p.clone();
                    q.push(v.clone());
                    q
                })
            })
            .collect();
    }
    points
}

/// The slice of `0..total` that chunk `k` of `n` (1-based) runs: `[⌊(k-1) total / n⌋,
/// ⌊k total / n⌋)`. The chunks of `1..=n` cover `0..total` once, in order.
pub fn chunk_range(total: usize, k: usize, n: usize) -> std::ops::Range<usize> {
    (k - 1) * total / n..k * total / n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_matches_the_reference_sequence() {
        // First outputs of SplitMix64 with state 0, the values of Vigna's reference
        // splitmix64.c (https://prng.di.unimi.it/splitmix64.c) that the xoshiro seeders publish.
        let mut r = SplitMix64::new(0);
        let want = [
            0xE220_A839_7B1D_CDAFu64,
            0x6E78_9E6A_A1B9_65F4,
            0x06C4_5D18_8009_454F,
            0xF88B_B8A8_724C_81EC,
        ];
        for w in want {
            assert_eq!(r.next_u64(), w);
        }
    }

    #[test]
    fn latin_hypercube_has_one_sample_per_stratum_in_every_dimension() {
        let ranges = [[0.0, 1.0], [-3.0, 5.0], [1e7, 3e7]];
        for n in [1, 2, 7, 200] {
            let s = latin_hypercube(&ranges, n, 42);
            assert_eq!(s.len(), n);
            for (d, &[lo, hi]) in ranges.iter().enumerate() {
                let mut hit = vec![0; n];
                for row in &s {
                    let x = row[d];
                    assert!((lo..hi).contains(&x), "{x} outside [{lo}, {hi})");
                    let k = (((x - lo) / (hi - lo)) * n as f64).floor() as usize;
                    hit[k.min(n - 1)] += 1;
                }
                assert!(hit.iter().all(|&h| h == 1), "n = {n}, dim {d}: {hit:?}");
            }
        }
    }

    #[test]
    fn latin_hypercube_is_seeded() {
        let r = [[0.0, 1.0], [0.0, 1.0]];
        assert_eq!(latin_hypercube(&r, 50, 7), latin_hypercube(&r, 50, 7));
        assert_ne!(latin_hypercube(&r, 50, 7), latin_hypercube(&r, 50, 8));
        // the dimensions are paired by independent permutations, not in lockstep
        let s = latin_hypercube(&r, 50, 7);
        let same = s
            .iter()
            .filter(|p| (p[0] * 50.0).floor() == (p[1] * 50.0).floor())
            .count();
        assert!(same < 10, "{same} of 50 points on the diagonal strata");
    }

    #[test]
    fn linspace_and_grid() {
        assert_eq!(linspace(1.0, 2.0, 3), vec![1.0, 1.5, 2.0]);
        assert_eq!(linspace(0.1, 0.7, 7)[6], 0.7);
        assert_eq!(linspace(5.0, 9.0, 1), vec![5.0]);
        let g = grid(&[vec![1, 2], vec![10, 20, 30]]);
        assert_eq!(g.len(), 6);
        assert_eq!(g[0], vec![1, 10]);
        assert_eq!(g[1], vec![1, 20]);
        assert_eq!(g[5], vec![2, 30]);
        assert_eq!(grid::<i32>(&[]), vec![Vec::<i32>::new()]);
    }

    #[test]
    fn chunks_cover_the_points_once() {
        for total in [0, 1, 5, 200, 201] {
            for n in 1..=7 {
                let mut all = vec![];
                for k in 1..=n {
                    all.extend(chunk_range(total, k, n));
                }
                assert_eq!(all, (0..total).collect::<Vec<_>>());
            }
        }
    }
}
