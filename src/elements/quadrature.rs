//! Gauss–Legendre rules on [-1, 1].

/// Gauss–Legendre points and weights on [-1, 1] for `n` = 1 to 4 points.
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
    // sqrt(3/7 ∓ (2/7) sqrt(6/5)) and (18 ± sqrt(30))/36
    const A4: f64 = 0.339_981_043_584_856_3;
    const B4: f64 = 0.861_136_311_594_052_6;
    const WA4: f64 = 0.652_145_154_862_546_1;
    const WB4: f64 = 0.347_854_845_137_453_9;
    const G4: [(f64, f64); 4] = [(-B4, WB4), (-A4, WA4), (A4, WA4), (B4, WB4)];
    match n {
        1 => &G1,
        2 => &G2,
        3 => &G3,
        4 => &G4,
        _ => panic!("gauss_legendre: {n} points not tabulated"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An n-point rule integrates x^k exactly for k < 2n.
    #[test]
    fn rules_are_exact_to_their_degree() {
        for n in 1..=4 {
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
