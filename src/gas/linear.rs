//! The linearized two-volume frequency response of bag, pipe and reservoir
//! (air-spring-physics.md 1.5).
//!
//! Small changes about a rest state, `s = iω`. Each control volume follows
//! `δp/p = n(s) (δm/m − δV/V)`: `n(s) = n` for the polytropic law; for the energy law the
//! linearized `dσ/dt = h (T_a/T − 1)/(m c_v)` (module [`super::model`]) gives
//! `n(s) = (γ s τ + 1)/(s τ + 1)`, `τ = m c_v / h` (γ at h = 0 or ω → ∞, 1 at ω → 0). With the
//! mass capacitances `C_i = m_i/(n_i p_i) = ρ_i V_i/(n_i p_i)` [kg/Pa] (ρ times the volume
//! capacitances `V/(n p)` of air-spring-physics.md 1.5), the bag `δp_b = (δm_b − ρ_b δV_b)/C_b`,
//! the reservoir `δp_r = δm_r/C_r`, and the pipe in mass flow `(R + s I) ṁ = δp_b − δp_r` with
//! `I = ℓ/A_pipe` and `R = dΔp_loss/dṁ` at ṁ = 0 = `128 μ ℓ/(π D⁴ ρ̄)` (the orifice drop is
//! quadratic in ṁ, so it adds nothing at zero flow), eliminating ṁ:
//!
//! `dp_b/dV_b = −ρ_b / (C_b + C_r / (1 + s R C_r + s² I C_r))`,
//!
//! which is `−K(ω)/A²` of air-spring-physics.md 1.5 (there in volume flow: `C_v = C/ρ`,
//! `R_v = ρ R`, `I_v = ρ I`, the same products `R C` and `I C`). Without a reservoir it is
//! `−n(s) p_b/V_b`.

use super::GAMMA_AIR;
use super::model::Gas;
use super::params::{GasLaw, R_AIR};
use nalgebra::Complex;

impl Gas {
    /// Dynamic "stiffness" of the gas `dp_bag / dV_bag` [Pa/m³] at the angular frequency
    /// `omega` [rad/s] of the model linearized about the committed state taken as an
    /// equilibrium (after [`Gas::charge`] or [`Gas::set_static`]; module documentation). Times
    /// `−A²` it is the spring stiffness [N/m] of a piston of area A; its phase is the loss angle.
    pub fn linear_dynamic_stiffness(&self, omega: f64) -> Complex<f64> {
        let s = Complex::new(0.0, omega);
        let one = Complex::new(1.0, 0.0);
        let c_v = R_AIR / (GAMMA_AIR - 1.0);
        let exponent = |m: f64| match self.params().law {
            GasLaw::Polytropic { n } => Complex::new(n, 0.0),
            GasLaw::Energy { heat_transfer } if heat_transfer > 0.0 => {
                let tau = m * c_v / heat_transfer;
                (s * (GAMMA_AIR * tau) + one) / (s * tau + one)
            }
            GasLaw::Energy { .. } => Complex::new(GAMMA_AIR, 0.0),
        };
        let lp = self.linear_point();
        let c_b = Complex::new(lp.m_b / lp.p_b, 0.0) / exponent(lp.m_b);
        let Some(r) = lp.reservoir else {
            return -lp.rho_b / c_b;
        };
        let c_r = Complex::new(r.m_r / r.p_r, 0.0) / exponent(r.m_r);
        let resistance = r.laminar / (0.5 * (lp.rho_b + r.rho_r));
        let branch = one + s * c_r * (s * r.inertance + resistance);
        -lp.rho_b / (c_b + c_r / branch)
    }
}
