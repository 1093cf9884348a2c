//! The cord–rubber wall of an air-spring bellows as a membrane law: per ply a fiber energy
//! `W_c = K_c (λ_c − 1)²/2` per reference area with the cord stretch `λ_c = |F a₀|` (plies at
//! `±α₀` from the meridian of the stress-free sleeve), plus an isotropic rubber matrix with
//! `ν = 0`, `W_m = (E t/2) Σ (λ_i − 1)²` over the principal stretches (Biot strain). Issue 11,
//! item 2; `shared/reference/air-spring-physics.md` §1.6 (the law of the independent reference
//! of the reference spring, `λ_c² = λ_s² cos²α₀ + λ_θ² sin²α₀` in axisymmetry).
//!
//! Cords are linear in tension and compression by default; with `tension_only` a cord under
//! compression (`λ_c < 1`) carries nothing (the energy stays C¹, its second derivative jumps at
//! `λ_c = 1`).

/// Constants of the wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CordRubberWall {
    /// Cord stiffness of one ply `K_c` [N/m] (force per unit width per unit cord strain).
    pub cord_stiffness: f64,
    /// Number of plies (alternating `+α₀`, `−α₀`) [1].
    pub n_plies: usize,
    /// Cord angle `α₀` from the meridian in the stress-free sleeve [rad].
    pub cord_angle: f64,
    /// Membrane stiffness of the rubber matrix `E t` [N/m] (`ν = 0`).
    pub matrix_stiffness: f64,
    /// Cords carry no compression.
    pub tension_only: bool,
}

/// Energy per reference area [J/m²] and its first and second derivatives with respect to the
/// meridional and hoop stretches `(λ_s, λ_θ)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AxisymEnergy {
    /// `W` [J/m²].
    pub w: f64,
    /// `(∂W/∂λ_s, ∂W/∂λ_θ)` [N/m].
    pub grad: [f64; 2],
    /// `∂²W/∂λ_i∂λ_j` [N/m].
    pub hess: [[f64; 2]; 2],
}

impl CordRubberWall {
    /// The energy of an axisymmetric deformation without twist (the plies keep their
    /// symmetry, so `λ_s`, `λ_θ` are principal stretches and both plies have the same cord
    /// stretch).
    pub fn axisym(&self, ls: f64, lt: f64) -> AxisymEnergy {
        self.axisym_with(ls, lt, self.cord_angle.sin_cos())
    }

    /// [`CordRubberWall::axisym`] with `(sin α₀, cos α₀)` of the cord angle given (a caller
    /// that evaluates many points keeps them).
    pub fn axisym_with(&self, ls: f64, lt: f64, (s, c): (f64, f64)) -> AxisymEnergy {
        let et = self.matrix_stiffness;
        let mut e = AxisymEnergy {
            w: 0.5 * et * ((ls - 1.0).powi(2) + (lt - 1.0).powi(2)),
            grad: [et * (ls - 1.0), et * (lt - 1.0)],
            hess: [[et, 0.0], [0.0, et]],
        };
        let (c2, s2) = (c * c, s * s);
        let lc = (ls * ls * c2 + lt * lt * s2).sqrt();
        if lc <= 0.0 || (self.tension_only && lc <= 1.0) {
            return e;
        }
        let k = self.cord_stiffness * self.n_plies as f64;
        let d = [ls * c2 / lc, lt * s2 / lc];
        let dd = [
            [c2 / lc - d[0] * d[0] / lc, -d[0] * d[1] / lc],
            [-d[0] * d[1] / lc, s2 / lc - d[1] * d[1] / lc],
        ];
        let fc = k * (lc - 1.0);
        e.w += 0.5 * k * (lc - 1.0).powi(2);
        for i in 0..2 {
            e.grad[i] += fc * d[i];
            for j in 0..2 {
                e.hess[i][j] += k * d[i] * d[j] + fc * dd[i][j];
            }
        }
        e
    }

    /// Membrane forces per current length `(N_s, N_θ)` [N/m] of an axisymmetric state:
    /// `N_s = (∂W/∂λ_s)/λ_θ`, `N_θ = (∂W/∂λ_θ)/λ_s`.
    pub fn axisym_forces(&self, ls: f64, lt: f64) -> [f64; 2] {
        let e = self.axisym(ls, lt);
        [e.grad[0] / lt, e.grad[1] / ls]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wall(tension_only: bool) -> CordRubberWall {
        CordRubberWall {
            cord_stiffness: 1.5e6,
            n_plies: 2,
            cord_angle: 54f64.to_radians(),
            matrix_stiffness: 2.0e4,
            tension_only,
        }
    }

    /// Gradient and Hessian against central differences, in tension and compression.
    #[test]
    fn derivatives_match_finite_differences() {
        for to in [false, true] {
            let w = wall(to);
            // (1, 1) is the kink of the tension-only law: only the linear law is checked there
            for &(ls, lt) in &[
                (1.3, 0.8),
                (1.05, 1.12),
                (0.9, 0.95),
                (1.0, 1.0),
                (1.2, 1.3),
            ] {
                if to && ls == 1.0 && lt == 1.0 {
                    continue;
                }
                let e = w.axisym(ls, lt);
                let h = 1e-6;
                for i in 0..2 {
                    let dl = |s: f64| {
                        let (a, b) = if i == 0 { (ls + s, lt) } else { (ls, lt + s) };
                        w.axisym(a, b)
                    };
                    let (p, m) = (dl(h), dl(-h));
                    let g = (p.w - m.w) / (2.0 * h);
                    assert!(
                        (g - e.grad[i]).abs() <= 1e-6 * (1e3 + e.grad[i].abs()),
                        "grad {i}"
                    );
                    for j in 0..2 {
                        let hh = (p.grad[j] - m.grad[j]) / (2.0 * h);
                        assert!(
                            (hh - e.hess[j][i]).abs() <= 1e-5 * (1e3 + e.hess[j][i].abs()),
                            "hess {i}{j} at {ls},{lt}: {hh} vs {}",
                            e.hess[j][i]
                        );
                    }
                }
            }
        }
    }

    /// The cord stretch of a state where the cords keep their length (`λ_c = 1`) leaves
    /// only the matrix energy; a uniaxial stretch along the cords of a 0° ply gives
    /// `K_c` per ply.
    #[test]
    fn cords_follow_their_stretch() {
        let w = wall(false);
        let (s, c) = w.cord_angle.sin_cos();
        // λ_θ chosen so that λ_c = 1 at λ_s = 1.1
        let ls = 1.1f64;
        let lt = ((1.0 - ls * ls * c * c) / (s * s)).sqrt();
        let e = w.axisym(ls, lt);
        let matrix = 0.5 * 2.0e4 * ((ls - 1.0).powi(2) + (lt - 1.0).powi(2));
        assert!((e.w - matrix).abs() < 1e-9 * matrix);
        let w0 = CordRubberWall {
            cord_angle: 0.0,
            matrix_stiffness: 0.0,
            ..w
        };
        let e = w0.axisym(1.01, 1.0);
        assert!((e.grad[0] - 2.0 * 1.5e6 * 0.01).abs() < 1e-6);
        // tension-only: a compressed cord carries nothing
        let w1 = CordRubberWall {
            tension_only: true,
            ..w0
        };
        assert_eq!(w1.axisym(0.99, 1.0).w, 0.0);
        assert!(w0.axisym(0.99, 1.0).w > 0.0);
    }
}
