//! Linear-elastic material laws in Voigt form for Green–Lagrange strains (St. Venant–Kirchhoff).

use nalgebra::Matrix3;

/// Which strain-energy form the seed-000 element uses.
///
/// Kerkkänen, Sopanen, Mikkola 2003 (seed 000): Eq. 12 for the proposed element, Eqs. 10–11 for
/// the full isotropic (Lamé) form that suffers from Poisson locking in beams.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StrainEnergy {
    /// Eq. 12: `U = ½∫(E ε11² + E ε22² + 4 k_s G ε12²) dV` (no Poisson coupling).
    Decoupled,
    /// Eqs. 10–11: `U = ½∫ εᵀ E_mat ε dV` with Lamé constants λ, μ.
    Lame,
}

/// Plane elasticity tensors of a 2D continuum element in Voigt form `[ε11, ε22, 2ε12]`,
/// split into the part integrated with the normal-strain rule and the part integrated with the
/// shear rule (selective integration, seed 000 section 5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneElasticity {
    /// Moduli applied at the normal-strain integration points [Pa].
    pub normal: Matrix3<f64>,
    /// Moduli applied at the shear integration points [Pa].
    pub shear: Matrix3<f64>,
}

impl PlaneElasticity {
    /// Moduli for Young's modulus `e` [Pa], Poisson's ratio `nu` [1] and shear correction factor
    /// `k_s` [1] (5/6 for a rectangle; used by Eq. 12 only).
    pub fn new(e: f64, nu: f64, k_s: f64, form: StrainEnergy) -> Self {
        let g = e / (2.0 * (1.0 + nu));
        match form {
            StrainEnergy::Decoupled => Self {
                normal: Matrix3::new(e, 0.0, 0.0, 0.0, e, 0.0, 0.0, 0.0, 0.0),
                shear: Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, k_s * g),
            },
            StrainEnergy::Lame => {
                let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
                let mu = g;
                Self {
                    normal: Matrix3::new(
                        lambda + 2.0 * mu,
                        lambda,
                        0.0,
                        lambda,
                        lambda + 2.0 * mu,
                        0.0,
                        0.0,
                        0.0,
                        0.0,
                    ),
                    shear: Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, mu),
                }
            }
        }
    }
}
