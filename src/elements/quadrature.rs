//! Gauss–Legendre rules on [-1, 1].

/// Gauss–Legendre points and weights on [-1, 1] for `n` = 1 to 5 points.
///
/// # Panics
/// Panics for any other `n` (a programming error, not a user error).
pub fn gauss_legendre(n: usize) -> &'static [(f64, f64)] {
    const G1: [(f64, f64); 1] = [(0.0, 2.0)];
    // 1/sqrt(3)
    const A2: f64 = 0.577_350_269_189_625_8;
    const G2: [(f64, f64); 2] = [(-A2, 1.0), (A2, 1.0)];
    // sqrt(3/5)
    const A3: f64 = 0.774_596_669_241_483_4;
    const G3: [(f64, f64); 3] = [(-A3, 5.0 / 9.0), (0.0, 8.0 / 9.0), (A3, 5.0 / 9.0)];
    const A4: f64 = 0.339_981_043_584_856_3;
    const B4: f64 = 0.861_136_311_594_052_6;
    const W4A: f64 = 0.652_145_154_862_546_1;
    const W4B: f64 = 0.347_854_845_137_453_9;
    const G4: [(f64, f64); 4] = [(-B4, W4B), (-A4, W4A), (A4, W4A), (B4, W4B)];
    const A5: f64 = 0.538_469_310_105_683_1;
    const B5: f64 = 0.906_179_845_938_664;
    const W5A: f64 = 0.478_628_670_499_366_5;
    const W5B: f64 = 0.236_926_885_056_189_1;
    const G5: [(f64, f64); 5] = [
        (-B5, W5B),
        (-A5, W5A),
        (0.0, 0.568_888_888_888_888_9),
        (A5, W5A),
        (B5, W5B),
    ];
    match n {
        1 => &G1,
        2 => &G2,
        3 => &G3,
        4 => &G4,
        5 => &G5,
        _ => panic!("gauss_legendre: {n} points not tabulated"),
    }
}

/// Three-point Gauss–Lobatto rule on [-1, 1] (points −1, 0, 1; weights 1/3, 4/3, 1/3), exact for
/// polynomials up to degree 3.
pub fn lobatto3() -> &'static [(f64, f64)] {
    lobatto(3)
}

/// Gauss–Lobatto points `(ξ, ω)` on [−1, 1] for `n` = 2 … 5 points (both ends included,
/// weights summing to 2); `n = 1`: the middle with weight 2. Abramowitz & Stegun, Table 25.6.
pub fn lobatto(n: usize) -> &'static [(f64, f64)] {
    const P1: [(f64, f64); 1] = [(0.0, 2.0)];
    const P2: [(f64, f64); 2] = [(-1.0, 1.0), (1.0, 1.0)];
    const P3: [(f64, f64); 3] = [(-1.0, 1.0 / 3.0), (0.0, 4.0 / 3.0), (1.0, 1.0 / 3.0)];
    // ±1/√5
    const A4: f64 = 0.447_213_595_499_958;
    const P4: [(f64, f64); 4] = [
        (-1.0, 1.0 / 6.0),
        (-A4, 5.0 / 6.0),
        (A4, 5.0 / 6.0),
        (1.0, 1.0 / 6.0),
    ];
    // ±√(3/7)
    const A5: f64 = 0.654_653_670_707_977_1;
    const P5: [(f64, f64); 5] = [
        (-1.0, 0.1),
        (-A5, 49.0 / 90.0),
        (0.0, 32.0 / 45.0),
        (A5, 49.0 / 90.0),
        (1.0, 0.1),
    ];
    match n {
        1 => &P1,
        2 => &P2,
        3 => &P3,
        4 => &P4,
        5 => &P5,
        _ => panic!("Gauss–Lobatto rule with {n} points: 1 to 5 are tabulated"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Lobatto rules of 2 … 5 points integrate x^k exactly for k <= 2n − 3.
    #[test]
    fn lobatto_rules_are_exact_to_degree_2n_minus_3() {
        for n in 2..=5 {
            for k in 0..=(2 * n - 3) {
                let exact = if k % 2 == 0 {
                    2.0 / (k as f64 + 1.0)
                } else {
                    0.0
                };
                let sum: f64 = lobatto(n).iter().map(|&(x, w)| w * x.powi(k as i32)).sum();
                assert!(
                    (sum - exact).abs() < 1e-14,
                    "n = {n}, k = {k}: {sum} vs {exact}"
                );
            }
        }
        assert_eq!(lobatto(1), &[(0.0, 2.0)]);
    }

    /// Lobatto 3 integrates x^k exactly for k <= 3.
    #[test]
    fn lobatto_is_exact_to_degree_3() {
        for k in 0..4 {
            let exact = if k % 2 == 1 {
                0.0
            } else {
                2.0 / (k as f64 + 1.0)
            };
            let q: f64 = lobatto3().iter().map(|(x, w)| w * x.powi(k)).sum();
            assert!((q - exact).abs() < 1e-14, "k={k}");
        }
    }

    /// An n-point rule integrates x^k exactly for k < 2n.
    #[test]
    fn rules_are_exact_to_their_degree() {
        for n in 1..=5 {
            for k in 0..(2 * n) {
                let exact = if k % 2 == 1 {
                    0.0
                } else {
                    2.0 / (k as f64 + 1.0)
                };
                let q: f64 = gauss_legendre(n)
                    .iter()
                    .map(|(x, w)| w * x.powi(k as i32))
                    .sum();
                assert!((q - exact).abs() < 1e-14, "n={n} k={k}: {q} vs {exact}");
            }
        }
    }
}
