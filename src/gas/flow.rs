//! Pressure losses of the reservoir connection: a compressible orifice (isentropic nozzle,
//! Saint-Venant) in series with laminar pipe friction (Hagen–Poiseuille).
//!
//! Orifice (Saint-Venant–Wantzel; e.g. ISO 9300, or any gas-dynamics text): the mass flow
//! through an isentropic nozzle of area `A` from the upstream state `(p_u, T_u)` to the
//! downstream pressure `p_d = π p_u` is
//! `ṁ = C_d A p_u √(2γ / ((γ−1) R T_u)) ψ(π)`, `ψ(π)² = π^{2/γ} − π^{(γ+1)/γ}`,
//! for `π ≥ π_c = (2/(γ+1))^{γ/(γ−1)}` (0.528 for air); below `π_c` the flow is choked at
//! `ṁ* = C_d A p_u √(γ/(R T_u)) (2/(γ+1))^{(γ+1)/(2(γ−1))}`. The gas model needs the inverse: the
//! drop `Δp = p_u x` (`x = 1 − π`) at a given flow ratio `Φ = ṁ/ṁ*`; `ψ(1−x)² = Φ² ψ(π_c)²` is
//! solved for `x` by bracketed Newton. Near `Φ = 0` it is `x ≈ γ/(γ−1) ψ_c² Φ²` (the
//! incompressible `Δp = ṁ²/(2 ρ C_d² A²)`), so the orifice adds no resistance at zero flow.
//!
//! Choking: `dx/dΦ` is infinite at `Φ = 1` (the flow cannot grow beyond `ṁ*`). Above
//! [`CHOKE_BLEND`] of the choked flow the drop is continued linearly with the slope it has there
//! (continuous value and slope), which keeps the inner Newton solve of the gas model regular; the
//! slope there is 12 times the slope at half the choked flow (x = 0.405 there, π = 0.595), so the flow stays close to
//! `ṁ*` while the pressure ratio falls below `π_c`, as a choked nozzle does.

/// Fraction of the choked flow above which the orifice drop is continued linearly (see the
/// module documentation).
pub const CHOKE_BLEND: f64 = 0.99;

/// Critical pressure ratio `π_c = (2/(γ+1))^{γ/(γ−1)}` [1].
pub fn critical_pressure_ratio(gamma: f64) -> f64 {
    (2.0 / (gamma + 1.0)).powf(gamma / (gamma - 1.0))
}

/// `ψ(1−x)² = π^{2/γ} − π^{(γ+1)/γ}` with `π = 1 − x`, and its derivative with respect to `x`,
/// written with `ln_1p`/`exp_m1` so that small drops keep their relative accuracy.
fn psi2(x: f64, gamma: f64) -> (f64, f64) {
    let l = (-x).ln_1p(); // ln π
    let a = (gamma - 1.0) / gamma;
    let value = (2.0 * l / gamma).exp() * -(a * l).exp_m1();
    // d/dx = π^{1/γ} ((γ−1)/γ − (2/γ)(π^{−a} − 1))
    let slope = (l / gamma).exp() * (a - 2.0 / gamma * (-a * l).exp_m1());
    (value, slope)
}

/// The relative orifice drop `x = Δp / p_u` [1] at the flow ratio `Φ = ṁ/ṁ*` ≥ 0 [1], and
/// `dx/dΦ`; linear continuation above [`CHOKE_BLEND`].
pub fn orifice_drop_ratio(phi: f64, gamma: f64) -> (f64, f64) {
    if phi <= 0.0 {
        return (0.0, 0.0);
    }
    let xc = 1.0 - critical_pressure_ratio(gamma);
    let (psic2, _) = psi2(xc, gamma);
    let solve = |phi: f64| -> (f64, f64) {
        let target = phi * phi * psic2;
        let (mut lo, mut hi) = (0.0, xc);
        let mut x = (target * gamma / (gamma - 1.0)).min(0.5 * xc);
        for _ in 0..200 {
            let (f, df) = psi2(x, gamma);
            let r = f - target;
            if r == 0.0 {
                break;
            }
            if r < 0.0 {
                lo = x;
            } else {
                hi = x;
            }
            let newton = x - r / df;
            if newton > lo && newton < hi {
                let step = (newton - x).abs();
                x = newton;
                if step <= 4.0 * f64::EPSILON * x {
                    break;
                }
            } else {
                x = 0.5 * (lo + hi);
                if hi - lo <= 4.0 * f64::EPSILON * hi {
                    break;
                }
            }
        }
        let (_, df) = psi2(x, gamma);
        (x, 2.0 * phi * psic2 / df)
    };
    if phi <= CHOKE_BLEND {
        solve(phi)
    } else {
        let (xs, ds) = solve(CHOKE_BLEND);
        (xs + ds * (phi - CHOKE_BLEND), ds)
    }
}

/// Choked mass flow per unit `p_u / √T_u`: `C_d A √(γ/R) (2/(γ+1))^{(γ+1)/(2(γ−1))}`
/// [kg √K /(s Pa)], so that `ṁ* = choked_flow_coefficient · p_u / √T_u`.
pub fn choked_flow_coefficient(cd: f64, area: f64, gamma: f64, r_gas: f64) -> f64 {
    cd * area
        * (gamma / r_gas).sqrt()
        * (2.0 / (gamma + 1.0)).powf((gamma + 1.0) / (2.0 * (gamma - 1.0)))
}

/// Hagen–Poiseuille resistance of a pipe to volume flow `Δp / Q = 128 μ ℓ / (π D⁴)`
/// [Pa s/m³] (laminar, fully developed); divided by the density it is the resistance to mass
/// flow.
pub fn laminar_resistance(mu: f64, length: f64, diameter: f64) -> f64 {
    128.0 * mu * length / (std::f64::consts::PI * diameter.powi(4))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gas::{GAMMA_AIR, R_AIR};

    /// The inversion reproduces the forward Saint-Venant flow (evaluated directly with
    /// `powf`, which loses digits at tiny drops, hence Φ ≥ 0.01), over the subsonic range.
    #[test]
    fn orifice_inverse_matches_forward_flow() {
        let g = GAMMA_AIR;
        let (p_u, t_u, cd, area): (f64, f64, f64, f64) = (5.0e5, 293.15, 0.7, 4.9e-4);
        let m_star = choked_flow_coefficient(cd, area, g, R_AIR) * p_u / t_u.sqrt();
        for &phi in &[0.01, 0.2, 0.5, 0.9, 0.98] {
            let (x, _) = orifice_drop_ratio(phi, g);
            let pi = 1.0 - x;
            let mdot = cd
                * area
                * p_u
                * (2.0 * g / ((g - 1.0) * R_AIR * t_u)).sqrt()
                * (pi.powf(2.0 / g) - pi.powf((g + 1.0) / g)).sqrt();
            let rel = (mdot - phi * m_star).abs() / (phi * m_star);
            assert!(
                rel < 1e-9,
                "Φ = {phi}: forward flow {mdot} vs {} ({rel:e})",
                phi * m_star
            );
        }
    }

    /// At small flow the drop is the incompressible orifice `ṁ²/(2 ρ C_d² A²)`.
    #[test]
    fn orifice_small_flow_is_incompressible() {
        let g = GAMMA_AIR;
        let (p_u, t_u, cd, area): (f64, f64, f64, f64) = (5.0e5, 293.15, 0.7, 4.9e-4);
        let rho = p_u / (R_AIR * t_u);
        let m_star = choked_flow_coefficient(cd, area, g, R_AIR) * p_u / t_u.sqrt();
        let mdot = 1e-4 * m_star;
        let (x, _) = orifice_drop_ratio(1e-4, g);
        let incompressible = mdot * mdot / (2.0 * rho * cd * cd * area * area);
        let rel = (p_u * x - incompressible).abs() / incompressible;
        assert!(
            rel < 1e-6,
            "drop {} vs incompressible {incompressible} ({rel:e})",
            p_u * x
        );
    }

    /// dx/dΦ against central differences, below and above the choke blend.
    #[test]
    fn orifice_slope_matches_finite_differences() {
        for &phi in &[0.05, 0.3, 0.7, 0.95, 1.2] {
            let h = 1e-6;
            let fd = (orifice_drop_ratio(phi + h, GAMMA_AIR).0
                - orifice_drop_ratio(phi - h, GAMMA_AIR).0)
                / (2.0 * h);
            let (_, d) = orifice_drop_ratio(phi, GAMMA_AIR);
            assert!((d - fd).abs() < 1e-6 * d.abs(), "Φ = {phi}: {d} vs {fd}");
        }
    }
}
