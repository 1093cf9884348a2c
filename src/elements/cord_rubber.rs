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

use nalgebra::{Matrix3, Vector3};

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
    #[inline(always)]
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
        let inv = 1.0 / lc;
        let d = [ls * c2 * inv, lt * s2 * inv];
        let dd = [
            [(c2 - d[0] * d[0]) * inv, -d[0] * d[1] * inv],
            [-d[0] * d[1] * inv, (s2 - d[1] * d[1]) * inv],
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

/// A quadratic form `L = A₁₁ C₁₁ + A₂₂ C₂₂ + 2 A₁₂ C₁₂` of the surface metric: its
/// gradient in `(C₁₁, C₂₂, C₁₂)`.
#[inline]
fn form_gradient(a: &[f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], 2.0 * a[2])
}

/// Energy per reference area [J/m²] of a surface state and its derivatives with respect to
/// the metric components `(C₁₁, C₂₂, C₁₂)` (`C_ab = g_a · g_b`, `C₁₂` counted once).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceEnergy {
    /// `W` [J/m²].
    pub w: f64,
    /// `∂W/∂(C₁₁, C₂₂, C₁₂)` [N/m per m²].
    pub grad: Vector3<f64>,
    /// Second derivatives.
    pub hess: Matrix3<f64>,
}

/// The reference of a point of a curved wall in surface coordinates `(θ¹, θ²)`: the inverse
/// reference metric `Gᵃᵇ` as `[G¹¹, G²², G¹²]`, `det G`, and per ply direction (`+α₀`, `−α₀`)
/// the tensor `cᵃ cᵇ` of its contravariant components as `[c¹c¹, c²c², c¹c²]` (`a₀ = cᵃ G_a`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceReference {
    /// `[G¹¹, G²², G¹²]` [1/m² in the surface coordinates' units].
    pub g_inv: [f64; 3],
    /// `det G`.
    pub det_g: f64,
    /// `cᵃcᵇ` of the `+α₀` and the `−α₀` plies.
    pub cords: [[f64; 3]; 2],
}

impl SurfaceReference {
    /// From the reference tangent vectors `G₁`, `G₂` and the unit meridian direction `m₀` of the
    /// stress-free sleeve (in its tangent plane), with the cord angle `alpha` [rad] from it.
    pub fn new(
        g1: &Vector3<f64>,
        g2: &Vector3<f64>,
        meridian: &Vector3<f64>,
        alpha: f64,
    ) -> Option<Self> {
        let (g11, g22, g12) = (g1.dot(g1), g2.dot(g2), g1.dot(g2));
        let det_g = g11 * g22 - g12 * g12;
        if det_g.is_nan() || det_g <= 0.0 {
            return None;
        }
        let g_inv = [g22 / det_g, g11 / det_g, -g12 / det_g];
        let n = g1.cross(g2).normalize();
        let m = (meridian - n * n.dot(meridian)).try_normalize(1e-12)?;
        let h = n.cross(&m);
        let (s, c) = alpha.sin_cos();
        let cords = [1.0, -1.0].map(|sign| {
            let a0 = m * c + h * (sign * s);
            // cᵃ = Gᵃᵇ (G_b · a₀)
            let (p1, p2) = (g1.dot(&a0), g2.dot(&a0));
            let c1 = g_inv[0] * p1 + g_inv[2] * p2;
            let c2 = g_inv[2] * p1 + g_inv[1] * p2;
            [c1 * c1, c2 * c2, c1 * c2]
        });
        Some(Self {
            g_inv,
            det_g,
            cords,
        })
    }
}

impl CordRubberWall {
    /// The energy of a general membrane state of a curved wall from the current metric
    /// `c = (C₁₁, C₂₂, C₁₂)` at a point with reference `r`: per ply the cord stretch
    /// `λ_c² = cᵃcᵇ C_ab` (plies alternate `+α₀`, `−α₀`: `⌈n/2⌉` and `⌊n/2⌋` of them), and the
    /// matrix `(E t/2) Σ (λ_i − 1)²` over the principal stretches, written with the invariants
    /// `I₁ = Gᵃᵇ C_ab = λ₁² + λ₂²` and `J = √(det C/det G) = λ₁ λ₂` as
    /// `(E t/2)(I₁ + 2 − 2√(I₁ + 2J))` (no eigenvalues, smooth). Reduces to
    /// [`CordRubberWall::axisym`] where the meridian and the hoop are principal.
    pub fn surface(&self, c: &[f64; 3], r: &SurfaceReference) -> SurfaceEnergy {
        self.surface_with(c, r, true)
    }

    /// [`Self::surface`], the second derivatives only if `hessian` (else zero): a residual
    /// without the tangent needs the energy and its gradient alone, which are the same
    /// values either way.
    pub fn surface_with(&self, c: &[f64; 3], r: &SurfaceReference, hessian: bool) -> SurfaceEnergy {
        let mut out = SurfaceEnergy::default();
        // matrix
        let et = self.matrix_stiffness;
        if et != 0.0 {
            let gi1 = form_gradient(&r.g_inv);
            let i1 = r.g_inv[0] * c[0] + r.g_inv[1] * c[1] + 2.0 * r.g_inv[2] * c[2];
            let det_c = c[0] * c[1] - c[2] * c[2];
            let d = det_c / r.det_g;
            if d.is_nan() || d <= 0.0 {
                // a collapsed element: no finite energy (the solver rejects the state)
                out.w = f64::NAN;
                return out;
            }
            let gd = Vector3::new(c[1], c[0], -2.0 * c[2]) / r.det_g;
            let j = d.sqrt();
            let gj = gd / (2.0 * j);
            let u = i1 + 2.0 * j;
            let su = u.sqrt();
            let gu = gi1 + 2.0 * gj;
            out.w += 0.5 * et * (i1 + 2.0 - 2.0 * su);
            out.grad += 0.5 * et * gi1 - et * gu / (2.0 * su);
            if hessian {
                let hd = Matrix3::new(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -2.0) / r.det_g;
                let hj = hd / (2.0 * j) - gd * gd.transpose() / (4.0 * j * j * j);
                out.hess -= et * (2.0 * hj / (2.0 * su) - gu * gu.transpose() / (4.0 * u * su));
            }
        }
        // cords
        let k = self.cord_stiffness;
        let n_plus = self.n_plies.div_ceil(2);
        for (ply, a) in r.cords.iter().enumerate() {
            let count = if ply == 0 {
                n_plus
            } else {
                self.n_plies - n_plus
            } as f64;
            if count == 0.0 {
                continue;
            }
            let l = a[0] * c[0] + a[1] * c[1] + 2.0 * a[2] * c[2];
            let lc = l.max(0.0).sqrt();
            if lc <= 0.0 || (self.tension_only && lc <= 1.0) {
                continue;
            }
            let kk = k * count;
            let gl = form_gradient(a);
            out.w += 0.5 * kk * (lc - 1.0).powi(2);
            out.grad += 0.5 * kk * (1.0 - 1.0 / lc) * gl;
            if hessian {
                out.hess += kk / (4.0 * l * lc) * gl * gl.transpose();
            }
        }
        out
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

    /// The reference of a cylinder of radius `r0` in the surface coordinates `(s, θ)`
    /// (meridian length, angle): `G₁ = ∂X/∂s`, `G₂ = ∂X/∂θ`.
    fn cylinder(r0: f64, alpha: f64) -> SurfaceReference {
        let g1 = Vector3::new(0.0, 0.0, -1.0);
        let g2 = Vector3::new(0.0, r0, 0.0);
        SurfaceReference::new(&g1, &g2, &g1, alpha).unwrap()
    }

    /// A state with principal stretches along meridian and hoop has the energy of
    /// [`CordRubberWall::axisym`] (both laws, several plies).
    #[test]
    fn surface_law_reduces_to_the_axisymmetric_one() {
        for to in [false, true] {
            for n in [1, 2, 3] {
                let w = CordRubberWall {
                    n_plies: n,
                    ..wall(to)
                };
                let r0 = 0.125;
                let r = cylinder(r0, w.cord_angle);
                for &(ls, lt) in &[(1.3, 0.8), (1.05, 1.12), (0.9, 0.95), (1.2, 1.3)] {
                    // the metric of the stretched cylinder
                    let c = [ls * ls, (lt * r0).powi(2), 0.0];
                    let a = w.surface(&c, &r).w;
                    // without shear both ply directions have the same stretch
                    let b = w.axisym(ls, lt).w;
                    assert!(
                        (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                        "{n} plies at {ls},{lt}: {a} vs {b}"
                    );
                }
            }
        }
    }

    /// Gradient and Hessian of the surface law against central differences, with shear (the
    /// plies at different stretches).
    #[test]
    fn surface_derivatives_match_finite_differences() {
        for to in [false, true] {
            let w = CordRubberWall {
                n_plies: 3,
                ..wall(to)
            };
            let r = cylinder(0.125, w.cord_angle);
            for c in [[1.3, 0.0125, 0.02], [1.1, 0.018, -0.03], [0.8, 0.02, 0.004]] {
                let e = w.surface(&c, &r);
                for i in 0..3 {
                    let h = 1e-6 * c[i].abs().max(1e-3);
                    let at = |s: f64| {
                        let mut x = c;
                        x[i] += s;
                        w.surface(&x, &r)
                    };
                    let (p, m) = (at(h), at(-h));
                    let g = (p.w - m.w) / (2.0 * h);
                    assert!(
                        (g - e.grad[i]).abs() <= 1e-6 * (1.0 + e.grad[i].abs()) * 1e3,
                        "grad {i} at {c:?}: {g} vs {}",
                        e.grad[i]
                    );
                    for j in 0..3 {
                        let hh = (p.grad[j] - m.grad[j]) / (2.0 * h);
                        assert!(
                            (hh - e.hess[(j, i)]).abs() <= 1e-5 * (1e3 + e.hess[(j, i)].abs()),
                            "hess {i}{j} at {c:?}: {hh} vs {}",
                            e.hess[(j, i)]
                        );
                    }
                }
            }
        }
    }
}
