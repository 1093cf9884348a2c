//! The gas component: charge, static pressure, implicit steps, energy accounts and snapshots.
//!
//! # States and time discretization
//! Each control volume `i` (bag `b`, reservoir `r`) carries its mass `m_i` and the entropy-like
//! variable `σ_i = ln p_i − κ ln ρ_i` (`ρ_i = m_i/V_i`, κ = n for the polytropic law, γ for the
//! energy law); the pipe carries the mass flow `ṁ` (positive from bag to reservoir). Then
//! `p_i = e^{σ_i} ρ_i^κ`, `T_i = p_i/(ρ_i R)`.
//!
//! - Polytropic law: `σ_i = ln K` for ever (one `K` from the charge): `p_i = K ρ_i^n` holds
//!   exactly at the end of every step, whatever the volume path.
//! - Energy law: with `U_i = m_i c_v T_i = p_i V_i/(γ−1)`,
//!   `d(m c_v T)/dt = ṁ_in c_p T_up − p dV/dt + h (T_a − T)` (air-spring-physics.md 1.4) is, in
//!   σ (divide by `p V/(γ−1)` and use `(γ−1) c_p = γ R`),
//!   `dσ/dt = γ (T_up/T − 1) ṁ_in/m + h (T_a/T − 1)/(m c_v)`.
//!   The volume term `−γ d ln V` has disappeared into σ, so it is integrated exactly (V linear
//!   in time does not even matter); an outflow (`T_up = T`) leaves σ unchanged (isentropic
//!   expansion of the gas left behind), exactly. The inflow mixing term is integrated by the
//!   trapezoidal rule (second order, no numerical damping), the heat term by backward Euler
//!   (L-stable: with h → ∞ the end state is at `T_a` whatever the step, the isothermal limit).
//!   With h = 0 and no flow σ and m are constant: `p V^γ` is constant to round-off.
//! - Masses: `m_b' = m_b − Δt (ṁ + ṁ')/2`, `m_r' = m_r + Δt (ṁ + ṁ')/2` (total mass exact).
//! - Pipe (inertance `I = ℓ/A_pipe` [1/m]): `I dṁ/dt = p_b − p_r − Δp_loss(ṁ)` by the
//!   trapezoidal rule. `Δp_loss` = the compressible orifice ([`super::flow`], upstream state =
//!   the upstream volume) + laminar friction `128 μ ℓ ṁ/(π D⁴ ρ̄)` with `ρ̄` the mean of the two
//!   densities.
//!
//! The end-of-step unknowns `(σ_b, σ_r, ṁ)` are found by Newton's method with the exact Jacobian
//! (dual numbers); `dp/dv` follows from the implicit function theorem,
//! `dp/dv = ∂p/∂V + ∂p/∂u · (−J⁻¹ ∂r/∂V)`.
//!
//! # Energy accounts
//! - Energy law: `U = Σ m_i c_v T_i`; heat to the ambient `Q_out = Σ ∫ h (T_i − T_a) dt`
//!   (backward Euler, as in the step); the flow losses heat the gas (throttling keeps the
//!   enthalpy), so nothing leaves the gas through them: `loss_work = 0`.
//! - Polytropic law: `U = Σ m_i e(ρ_i)` with `de/dρ = p/ρ²` (`e = K(ρ^{n−1} − ρ_ref^{n−1})/(n−1)`,
//!   zero at the charge density, `K ln(ρ/ρ_ref)` at n = 1), so `dU_i = h_i dm_i − p_i dV_i` with
//!   `h_i = e_i + p_i/ρ_i`; the polytropic law keeps no heat, so the energy the flow loses,
//!   `loss_work = ∫ (h_b − h_r) ṁ dt` (trapezoidal), leaves the gas.
//! - In both: `ΔU + ∫ p_b dV_b + Q_out + loss_work = 0` up to the time discretization. The
//!   kinetic energy of the pipe flow (`I ṁ²/(2ρ)`, below 1e-5 of the volume work in the rail
//!   example) is outside the accounts, as in every lumped inertance model.

use super::dual::Dual;
use super::flow::{choked_flow_coefficient, laminar_resistance, orifice_drop_ratio};
use super::params::{GAMMA_AIR, GasError, GasLaw, GasParams, MU_AIR, R_AIR};
use crate::snapshot::{SnapshotError, StateReader, StateWriter};
use nalgebra::{Matrix3, Vector3};

/// Dual numbers over (σ_b, σ_r, ṁ, V_b) at the end of the step.
type D = Dual<4>;
/// Specific heat at constant volume c_v = R/(γ−1) [J/(kg K)].
const C_V: f64 = R_AIR / (GAMMA_AIR - 1.0);
/// Newton tolerance on the σ increments [1] (and on ṁ relative to the total mass per second).
const NEWTON_TOL: f64 = 1e-12;
/// Increments below which an iteration that no longer contracts counts as converged (round-off).
const STAGNATION_TOL: f64 = 1e-10;
/// Default largest number of Newton iterations of a step.
const MAX_ITERATIONS: usize = 50;

/// Pressures, temperatures, masses and energy accounts of the gas at one state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GasEval {
    /// Absolute bag pressure p [Pa].
    pub p_abs: f64,
    /// Gauge bag pressure p − p_a [Pa].
    pub p_gauge: f64,
    /// Total derivative d p_abs / d v_membrane [Pa/m³] at this state, through the implicit gas
    /// states of the step (negative for a stable spring).
    pub dp_dv: f64,
    /// Total bag volume (membrane + inner) [m³].
    pub volume: f64,
    /// Bag temperature T = p V / (m R) [K].
    pub temperature: f64,
    /// Gas mass in the bag [kg].
    pub mass: f64,
    /// Absolute reservoir pressure [Pa] (0 without a reservoir).
    pub reservoir_pressure: f64,
    /// Reservoir temperature [K] (0 without a reservoir).
    pub reservoir_temperature: f64,
    /// Gas mass in the reservoir [kg] (0 without a reservoir).
    pub reservoir_mass: f64,
    /// Mass flow from bag to reservoir ṁ [kg/s] (0 without a reservoir).
    pub mass_flow: f64,
    /// Gas energy U [J] of bag and reservoir: `Σ m c_v T` for the energy law; for the
    /// polytropic law the potential `Σ m e(ρ)` with `de/dρ = p/ρ²`, zero at the charge, so that
    /// `dU = −p dV` for a closed volume.
    pub internal_energy: f64,
    /// Heat given to the ambient since the charge (or the last [`Gas::set_static`]) [J].
    pub heat_out: f64,
    /// Work of the flow losses that left the gas energy since the charge (or the last
    /// [`Gas::set_static`]) [J]: with `W_bag = ∫ p dV_bag`, `ΔU + W_bag + heat_out + loss_work
    /// = 0` up to the time discretization.
    pub loss_work: f64,
}

/// The committed state (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct State {
    v_membrane: f64,
    sigma_b: f64,
    sigma_r: f64,
    m_b: f64,
    m_r: f64,
    mdot: f64,
    heat_out: f64,
    loss_work: f64,
}

/// Constants of the reservoir connection.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pipe {
    /// Reservoir volume [m³].
    volume: f64,
    /// Inertance ℓ/A_pipe [1/m] (mass-flow form: `I dṁ/dt = Δp`).
    inertance: f64,
    /// Hagen–Poiseuille resistance to volume flow [Pa s/m³].
    laminar: f64,
    /// Choked-flow coefficient of the orifice: `ṁ* = choke · p_u/√T_u`.
    choke: f64,
}

/// Bag and reservoir quantities at one state (reservoir entries zero without one).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Quantities {
    p_b: D,
    t_b: D,
    rho_b: D,
    m_b: D,
    p_r: D,
    t_r: D,
    rho_r: D,
    m_r: D,
    mdot: D,
    /// Inflow mixing rate of σ_b: `γ (T_up/T − 1) ṁ_in/m` [1/s].
    g_b: D,
    /// The same for the reservoir.
    g_r: D,
    /// Heat rate of σ_b: `h (T_a/T − 1)/(m c_v)` [1/s].
    heat_b: D,
    /// The same for the reservoir.
    heat_r: D,
    /// Net pipe force `p_b − p_r − Δp_loss(ṁ)` [Pa].
    force: D,
}

/// The gas of one air spring: parameters, charge and the committed state.
#[derive(Clone, Debug, PartialEq)]
pub struct Gas {
    params: GasParams,
    kappa: f64,
    pipe: Option<Pipe>,
    /// `p/ρ` at the charge [J/kg] (the polytropic energy scale `K ρ_ref^{n−1}`).
    e_ref: f64,
    /// Density at the charge [kg/m³] (zero of the polytropic energy).
    rho_ref: f64,
    committed: State,
    /// The quantities and the evaluation of `committed` ([`Gas::committed`]), recomputed
    /// whenever it changes: steps start from them and outputs read them, so they are computed
    /// once per commit instead of once per use.
    committed_cache: (Quantities, GasEval),
    /// Closed bag without heat exchange (no reservoir; polytropic, or the energy law with
    /// `gas.heat_transfer` = 0): σ and the mass are constant, and a step has the closed form
    /// of [`Gas::closed_step`].
    pub(super) closed: bool,
    max_iterations: usize,
}

fn err<T>(msg: String) -> Result<T, GasError> {
    Err(GasError(msg))
}

/// `(e^{a y} − 1)/a`, continuous at a = 0 (= y).
fn expm1_over(a: f64, y: f64) -> f64 {
    if a == 0.0 { y } else { (a * y).exp_m1() / a }
}

impl Quantities {
    /// All zero (a placeholder before the charge).
    fn zero() -> Self {
        let z = D::c(0.0);
        Self {
            p_b: z,
            t_b: z,
            rho_b: z,
            m_b: z,
            p_r: z,
            t_r: z,
            rho_r: z,
            m_r: z,
            mdot: z,
            g_b: z,
            g_r: z,
            heat_b: z,
            heat_r: z,
            force: z,
        }
    }
}

impl Gas {
    /// A gas component with `params`, charged at the design state (see [`Gas::charge`]).
    pub fn new(
        params: GasParams,
        p_gauge_design: f64,
        v_membrane_design: f64,
    ) -> Result<Self, GasError> {
        params.validate()?;
        let pipe = params.reservoir.map(|r| {
            let a_pipe = std::f64::consts::PI * r.pipe_diameter.powi(2) / 4.0;
            let a_orifice = std::f64::consts::PI * r.orifice_diameter.powi(2) / 4.0;
            Pipe {
                volume: r.volume,
                inertance: r.pipe_length / a_pipe,
                laminar: laminar_resistance(MU_AIR, r.pipe_length, r.pipe_diameter),
                choke: choked_flow_coefficient(r.cd, a_orifice, GAMMA_AIR, R_AIR),
            }
        });
        let zero = State {
            v_membrane: 0.0,
            sigma_b: 0.0,
            sigma_r: 0.0,
            m_b: 0.0,
            m_r: 0.0,
            mdot: 0.0,
            heat_out: 0.0,
            loss_work: 0.0,
        };
        let closed = pipe.is_none()
            && match params.law {
                GasLaw::Polytropic { .. } => true,
                GasLaw::Energy { heat_transfer } => heat_transfer == 0.0,
            };
        let mut gas = Self {
            params,
            kappa: params.kappa(),
            pipe,
            e_ref: 0.0,
            rho_ref: 0.0,
            committed: zero,
            committed_cache: (
                Quantities::zero(),
                GasEval {
                    p_abs: 0.0,
                    p_gauge: 0.0,
                    dp_dv: 0.0,
                    volume: 0.0,
                    temperature: 0.0,
                    mass: 0.0,
                    reservoir_pressure: 0.0,
                    reservoir_temperature: 0.0,
                    reservoir_mass: 0.0,
                    mass_flow: 0.0,
                    internal_energy: 0.0,
                    heat_out: 0.0,
                    loss_work: 0.0,
                },
            ),
            closed,
            max_iterations: MAX_ITERATIONS,
        };
        gas.charge(p_gauge_design, v_membrane_design)?;
        Ok(gas)
    }

    /// The parameters.
    pub fn params(&self) -> &GasParams {
        &self.params
    }

    fn bag_volume(&self, v_membrane: f64, what: &str) -> Result<f64, GasError> {
        if !v_membrane.is_finite() {
            return err(format!(
                "{what}: membrane volume {v_membrane} is not finite"
            ));
        }
        let v = v_membrane + self.params.inner_volume;
        if v > 0.0 {
            Ok(v)
        } else {
            err(format!(
                "{what}: bag volume {v} m3 (membrane {v_membrane} + inner {}) is not positive",
                self.params.inner_volume
            ))
        }
    }

    fn reservoir_volume(&self) -> f64 {
        self.pipe.map_or(0.0, |p| p.volume)
    }

    /// Fixes the gas masses from the design state: bag (and reservoir) at `p_a +
    /// p_gauge_design` [Pa] and `T_a`, membrane volume `v_membrane_design` [m³], no flow. This
    /// becomes the committed state; the energy accounts restart at zero.
    pub fn charge(&mut self, p_gauge_design: f64, v_membrane_design: f64) -> Result<(), GasError> {
        let v_b = self.bag_volume(v_membrane_design, "charge")?;
        let p = self.params.ambient_pressure + p_gauge_design;
        if !(p.is_finite() && p > 0.0) {
            return err(format!(
                "charge: absolute pressure {p} Pa (gauge {p_gauge_design}) is not positive"
            ));
        }
        let rho = p / (R_AIR * self.params.ambient_temperature);
        let sigma = p.ln() - self.kappa * rho.ln();
        self.e_ref = p / rho;
        self.rho_ref = rho;
        self.set_committed(State {
            v_membrane: v_membrane_design,
            sigma_b: sigma,
            sigma_r: sigma,
            m_b: rho * v_b,
            m_r: rho * self.reservoir_volume(),
            mdot: 0.0,
            heat_out: 0.0,
            loss_work: 0.0,
        });
        Ok(())
    }

    /// Density and pressure of the static state at `v_membrane`.
    fn static_state(&self, v_membrane: f64) -> Result<(f64, f64, f64), GasError> {
        let v_b = self.bag_volume(v_membrane, "static pressure")?;
        let v_tot = v_b + self.reservoir_volume();
        let s = &self.committed;
        let rho = (s.m_b + s.m_r) / v_tot;
        let p = match self.params.law {
            GasLaw::Polytropic { n } => (s.sigma_b + n * rho.ln()).exp(),
            GasLaw::Energy { .. } => rho * R_AIR * self.params.ambient_temperature,
        };
        Ok((rho, p, v_tot))
    }

    /// Static absolute bag pressure [Pa] and its derivative d p / d v_membrane [Pa/m³] at the
    /// membrane volume `v_membrane` [m³] with the committed masses at rest: energy law at
    /// thermal equilibrium (T_a, reservoir pressure equal to the bag's), polytropic law on the
    /// total volume.
    pub fn static_pressure(&self, v_membrane: f64) -> Result<(f64, f64), GasError> {
        let (_, p, v_tot) = self.static_state(v_membrane)?;
        let n = match self.params.law {
            GasLaw::Polytropic { n } => n,
            GasLaw::Energy { .. } => 1.0,
        };
        Ok((p, -n * p / v_tot))
    }

    /// Makes the static state of [`Gas::static_pressure`] at `v_membrane` [m³] the committed
    /// one (masses redistributed between bag and reservoir, no flow); the energy accounts
    /// restart at zero.
    pub fn set_static(&mut self, v_membrane: f64) -> Result<(), GasError> {
        let (rho, p, _) = self.static_state(v_membrane)?;
        let v_b = self.bag_volume(v_membrane, "static pressure")?;
        let sigma = p.ln() - self.kappa * rho.ln();
        self.set_committed(State {
            v_membrane,
            sigma_b: sigma,
            sigma_r: sigma,
            m_b: rho * v_b,
            m_r: rho * self.reservoir_volume(),
            mdot: 0.0,
            heat_out: 0.0,
            loss_work: 0.0,
        });
        Ok(())
    }

    /// Bag and reservoir quantities (NaN where a mass or volume is not positive).
    fn quantities(&self, sigma_b: D, sigma_r: D, mdot: D, v_b: D, m_b: D, m_r: D) -> Quantities {
        let kappa = self.kappa;
        let t_a = self.params.ambient_temperature;
        let h = match self.params.law {
            GasLaw::Energy { heat_transfer } => heat_transfer,
            GasLaw::Polytropic { .. } => 0.0,
        };
        let energy = matches!(self.params.law, GasLaw::Energy { .. });
        let volume = |sigma: D, m: D, v: D| {
            let rho = m / v;
            let p = (sigma + rho.ln() * kappa).exp();
            let t = p / (rho * R_AIR);
            let heat = if h > 0.0 {
                (t_a / t - 1.0) * (h / C_V) / m
            } else {
                D::c(0.0)
            };
            (rho, p, t, heat)
        };
        let (rho_b, p_b, t_b, heat_b) = volume(sigma_b, m_b, v_b);
        let zero = D::c(0.0);
        let Some(pipe) = self.pipe else {
            return Quantities {
                p_b,
                t_b,
                rho_b,
                m_b,
                p_r: zero,
                t_r: zero,
                rho_r: zero,
                m_r: zero,
                mdot: zero,
                g_b: zero,
                g_r: zero,
                heat_b,
                heat_r: zero,
                force: zero,
            };
        };
        let (rho_r, p_r, t_r, heat_r) = volume(sigma_r, m_r, D::c(pipe.volume));
        let forward = mdot.v >= 0.0;
        let (p_up, t_up, sign) = if forward {
            (p_b, t_b, 1.0)
        } else {
            (p_r, t_r, -1.0)
        };
        let phi = mdot * sign / (p_up * pipe.choke / t_up.sqrt());
        let (x, dx) = orifice_drop_ratio(phi.v, GAMMA_AIR);
        let orifice = p_up * phi.map(x, dx) * sign;
        let friction = mdot * pipe.laminar / ((rho_b + rho_r) * 0.5);
        let force = p_b - p_r - orifice - friction;
        let (g_b, g_r) = if !energy {
            (zero, zero)
        } else if forward {
            (zero, (t_b / t_r - 1.0) * mdot * GAMMA_AIR / m_r)
        } else {
            ((t_r / t_b - 1.0) * -mdot * GAMMA_AIR / m_b, zero)
        };
        Quantities {
            p_b,
            t_b,
            rho_b,
            m_b,
            p_r,
            t_r,
            rho_r,
            m_r,
            mdot,
            g_b,
            g_r,
            heat_b,
            heat_r,
            force,
        }
    }

    /// Makes `s` the committed state and recomputes what is derived from it.
    fn set_committed(&mut self, s: State) {
        self.committed = s;
        let q = self.committed_quantities();
        let v_b = s.v_membrane + self.params.inner_volume;
        let e = self.evaluation(&s, &q, v_b, -self.kappa * q.p_b.v / v_b);
        self.committed_cache = (q, e);
    }

    /// Quantities of the committed state (constants), computed.
    fn committed_quantities(&self) -> Quantities {
        let s = &self.committed;
        let c = D::c;
        self.quantities(
            c(s.sigma_b),
            c(s.sigma_r),
            c(s.mdot),
            c(s.v_membrane + self.params.inner_volume),
            c(s.m_b),
            c(s.m_r),
        )
    }

    /// Residuals of the step at the end unknowns `u = (σ_b, σ_r, ṁ)` and bag volume `v_b`.
    fn residual(&self, dt: f64, q0: &Quantities, u: [f64; 3], v_b: f64) -> ([D; 3], Quantities) {
        let s0 = &self.committed;
        let (sb, sr, md) = (D::var(u[0], 0), D::var(u[1], 1), D::var(u[2], 2));
        let moved = (md + s0.mdot) * (0.5 * dt);
        let m_b = D::c(s0.m_b) - moved;
        let m_r = D::c(s0.m_r) + moved;
        let q = self.quantities(sb, sr, md, D::var(v_b, 3), m_b, m_r);
        let half = 0.5 * dt;
        let r0 = sb - s0.sigma_b - (q.g_b + q0.g_b.v) * half - q.heat_b * dt;
        let (r1, r2) = match self.pipe {
            Some(pipe) => (
                sr - s0.sigma_r - (q.g_r + q0.g_r.v) * half - q.heat_r * dt,
                md - s0.mdot - (q.force + q0.force.v) * (half / pipe.inertance),
            ),
            None => (sr - s0.sigma_r, md),
        };
        ([r0, r1, r2], q)
    }

    /// The end state of a step and its evaluation: [`Gas::closed_step`] where it applies, else
    /// [`Gas::solve_newton`].
    fn solve(&self, dt: f64, v_membrane_end: f64) -> Result<(State, GasEval), GasError> {
        if self.closed
            && dt.is_finite()
            && dt >= 0.0
            && let Ok(v_b) = self.bag_volume(v_membrane_end, "step")
            && let Some(done) = self.closed_step(v_membrane_end, v_b)
        {
            return Ok(done);
        }
        self.solve_newton(dt, v_membrane_end)
    }

    /// Newton solve of the step; the end state and its evaluation.
    pub(super) fn solve_newton(
        &self,
        dt: f64,
        v_membrane_end: f64,
    ) -> Result<(State, GasEval), GasError> {
        if !(dt.is_finite() && dt >= 0.0) {
            return err(format!("step: time step {dt} s must be finite and >= 0"));
        }
        let v_b = self.bag_volume(v_membrane_end, "step")?;
        let s0 = self.committed;
        let q0 = self.committed_cache.0;
        let finite = |r: &[D; 3], q: &Quantities| {
            r.iter().all(|x| x.is_finite())
                && q.m_b.v > 0.0
                && (self.pipe.is_none() || q.m_r.v > 0.0)
        };
        let m_scale = s0.m_b + s0.m_r;
        let mut u = [s0.sigma_b, s0.sigma_r, s0.mdot];
        let mut converged = false;
        let mut last = [f64::NAN; 3];
        for _ in 0..self.max_iterations {
            let (r, q) = self.residual(dt, &q0, u, v_b);
            if !finite(&r, &q) {
                return err(format!(
                    "step: non-finite gas state (dt = {dt} s, bag volume {v_b} m3, bag mass {}, reservoir mass {})",
                    q.m_b.v, q.m_r.v
                ));
            }
            let jac = Matrix3::from_fn(|i, k| r[i].d[k]);
            let rhs = Vector3::new(-r[0].v, -r[1].v, -r[2].v);
            let Some(du) = jac.lu().solve(&rhs) else {
                return err(format!(
                    "step: singular gas Jacobian (dt = {dt} s, bag volume {v_b} m3)"
                ));
            };
            let big = du[0].abs().max(du[1].abs());
            let mut lambda = if big > 0.5 { 0.5 / big } else { 1.0 };
            let trial = loop {
                let t = [
                    u[0] + lambda * du[0],
                    u[1] + lambda * du[1],
                    u[2] + lambda * du[2],
                ];
                let (rt, qt) = self.residual(dt, &q0, t, v_b);
                if finite(&rt, &qt) {
                    break t;
                }
                lambda *= 0.5;
                if lambda < 1e-6 {
                    return err(format!(
                        "step: no admissible Newton update (dt = {dt} s, bag volume {v_b} m3): the flow empties a volume"
                    ));
                }
            };
            let size = |d: &[f64; 3]| d[0].abs().max(d[1].abs()).max(d[2].abs() / m_scale);
            let previous = size(&last);
            last = [lambda * du[0], lambda * du[1], lambda * du[2]];
            u = trial;
            let now = size(&last);
            // Converged, or stagnating at the round-off level of the residual.
            if lambda == 1.0
                && (now <= NEWTON_TOL || (now <= STAGNATION_TOL && now >= 0.5 * previous))
            {
                converged = true;
                break;
            }
        }
        if !converged {
            return err(format!(
                "step: gas Newton did not converge in {} iterations (dt = {dt} s, bag volume {v_b} m3, last increments dσ_b = {:.3e}, dσ_r = {:.3e}, dṁ = {:.3e} kg/s)",
                self.max_iterations, last[0], last[1], last[2]
            ));
        }
        let (r, q) = self.residual(dt, &q0, u, v_b);
        let jac = Matrix3::from_fn(|i, k| r[i].d[k]);
        let r_v = Vector3::new(r[0].d[3], r[1].d[3], r[2].d[3]);
        let Some(du_dv) = jac.lu().solve(&-r_v) else {
            return err(format!(
                "step: singular gas Jacobian (dt = {dt} s, bag volume {v_b} m3)"
            ));
        };
        let dp_dv = q.p_b.d[3] + (0..3).map(|k| q.p_b.d[k] * du_dv[k]).sum::<f64>();
        let mut s1 = State {
            v_membrane: v_membrane_end,
            sigma_b: u[0],
            sigma_r: u[1],
            m_b: q.m_b.v,
            m_r: if self.pipe.is_some() { q.m_r.v } else { 0.0 },
            mdot: u[2],
            heat_out: s0.heat_out,
            loss_work: s0.loss_work,
        };
        let t_a = self.params.ambient_temperature;
        match self.params.law {
            GasLaw::Energy { heat_transfer } => {
                let mut dq = q.t_b.v - t_a;
                if self.pipe.is_some() {
                    dq += q.t_r.v - t_a;
                }
                s1.heat_out += dt * heat_transfer * dq;
            }
            GasLaw::Polytropic { .. } => {
                if self.pipe.is_some() {
                    s1.loss_work +=
                        0.5 * dt * (self.flow_loss_power(&q0) + self.flow_loss_power(&q));
                }
            }
        }
        let eval = self.evaluation(&s1, &q, v_b, dp_dv);
        let numbers = [
            eval.p_abs,
            eval.temperature,
            eval.dp_dv,
            eval.internal_energy,
        ];
        if !numbers.iter().all(|x| x.is_finite()) || eval.p_abs <= 0.0 {
            return err(format!(
                "step: invalid gas state p = {} Pa, T = {} K, dp/dv = {} (dt = {dt} s, bag volume {v_b} m3)",
                eval.p_abs, eval.temperature, eval.dp_dv
            ));
        }
        Ok((s1, eval))
    }

    /// The step of a closed bag without heat exchange (`self.closed`): σ, the mass and the
    /// energy accounts stay; `p = e^σ (m/V)^κ` and `dp/dV = −κ p/V` at the end volume. The
    /// operations are those the general Newton solve does on its dual numbers in this case
    /// (its residual is zero at the committed σ, so it takes no step), so the result is the
    /// same to the last bit (`tests::closed_step_is_the_newton_solve`). `None` when the state
    /// is not admissible: the general solve then reports why.
    pub(super) fn closed_step(&self, v_membrane_end: f64, v_b: f64) -> Option<(State, GasEval)> {
        let s0 = &self.committed;
        let (p, dp_dv) = self.closed_pressure(v_b)?;
        let rho = s0.m_b / v_b;
        let t = p / (rho * R_AIR);
        if !t.is_finite() {
            return None;
        }
        let mut q = Quantities::zero();
        q.p_b = D::c(p);
        q.t_b = D::c(t);
        q.rho_b = D::c(rho);
        q.m_b = D::c(s0.m_b);
        let s1 = State {
            v_membrane: v_membrane_end,
            mdot: 0.0,
            m_r: 0.0,
            ..*s0
        };
        let eval = self.evaluation(&s1, &q, v_b, dp_dv);
        let ok =
            eval.p_abs > 0.0 && eval.temperature.is_finite() && eval.internal_energy.is_finite();
        ok.then_some((s1, eval))
    }

    /// Pressure and `dp/dV` of [`Gas::closed_step`] at the bag volume `v_b` [m³] (`None` if
    /// not finite and positive).
    fn closed_pressure(&self, v_b: f64) -> Option<(f64, f64)> {
        let s0 = &self.committed;
        // as the dual numbers compute ρ = m/V, ln ρ · κ + σ, exp and d/dV
        let rho = s0.m_b / v_b;
        let drho = (0.0 - rho * 1.0) / v_b;
        let p = (s0.sigma_b + rho.ln() * self.kappa).exp();
        let dp_dv = ((drho * (1.0 / rho)) * self.kappa) * p;
        (s0.m_b > 0.0 && p.is_finite() && p > 0.0 && dp_dv.is_finite()).then_some((p, dp_dv))
    }

    /// Specific polytropic energy e(ρ) [J/kg], zero at the charge density.
    fn poly_energy(&self, rho: f64) -> f64 {
        self.e_ref * expm1_over(self.kappa - 1.0, (rho / self.rho_ref).ln())
    }

    /// Polytropic flow-loss power `(h_b − h_r) ṁ` [W], `h = e + p/ρ`.
    fn flow_loss_power(&self, q: &Quantities) -> f64 {
        let h = |rho: f64, p: f64| self.poly_energy(rho) + p / rho;
        (h(q.rho_b.v, q.p_b.v) - h(q.rho_r.v, q.p_r.v)) * q.mdot.v
    }

    fn evaluation(&self, s: &State, q: &Quantities, v_b: f64, dp_dv: f64) -> GasEval {
        let has_res = self.pipe.is_some();
        let v_r = self.reservoir_volume();
        let internal_energy = match self.params.law {
            GasLaw::Energy { .. } => {
                let mut u = q.p_b.v * v_b;
                if has_res {
                    u += q.p_r.v * v_r;
                }
                u / (GAMMA_AIR - 1.0)
            }
            GasLaw::Polytropic { .. } => {
                let mut u = s.m_b * self.poly_energy(q.rho_b.v);
                if has_res {
                    u += s.m_r * self.poly_energy(q.rho_r.v);
                }
                u
            }
        };
        let res = |x: f64| if has_res { x } else { 0.0 };
        GasEval {
            p_abs: q.p_b.v,
            p_gauge: q.p_b.v - self.params.ambient_pressure,
            dp_dv,
            volume: v_b,
            temperature: q.t_b.v,
            mass: s.m_b,
            reservoir_pressure: res(q.p_r.v),
            reservoir_temperature: res(q.t_r.v),
            reservoir_mass: res(s.m_r),
            mass_flow: res(s.mdot),
            internal_energy,
            heat_out: s.heat_out,
            loss_work: s.loss_work,
        }
    }

    /// The state at the end of a step of `dt` [s] (≥ 0) over which the membrane volume goes
    /// linearly from the committed value to `v_membrane_end` [m³]; `dt = 0` gives the
    /// instantaneous response. Does not change the committed state.
    pub fn evaluate(&self, dt: f64, v_membrane_end: f64) -> Result<GasEval, GasError> {
        self.solve(dt, v_membrane_end).map(|(_, e)| e)
    }

    /// The absolute bag pressure [Pa] and `dp/dv` [Pa/m³] of [`Gas::evaluate`], without the
    /// energy accounts and temperatures where the step has a closed form (a closed bag without
    /// heat exchange): what a model's Newton iteration needs.
    pub fn pressure(&self, dt: f64, v_membrane_end: f64) -> Result<(f64, f64), GasError> {
        if self.closed
            && dt.is_finite()
            && dt >= 0.0
            && let Ok(v_b) = self.bag_volume(v_membrane_end, "step")
            && let Some((p, dp_dv)) = self.closed_pressure(v_b)
        {
            return Ok((p, dp_dv));
        }
        self.evaluate(dt, v_membrane_end)
            .map(|e| (e.p_abs, e.dp_dv))
    }

    /// [`Gas::evaluate`] and makes its end state the committed one.
    pub fn commit(&mut self, dt: f64, v_membrane_end: f64) -> Result<GasEval, GasError> {
        let (s, e) = self.solve(dt, v_membrane_end)?;
        self.set_committed(s);
        Ok(e)
    }

    /// The committed state (with the instantaneous `dp_dv = −κ p/V` of `evaluate(0, v)`).
    pub fn committed(&self) -> GasEval {
        self.committed_cache.1
    }

    /// The committed membrane volume [m³].
    pub fn membrane_volume(&self) -> f64 {
        self.committed.v_membrane
    }

    /// Linearization data of the committed state: per volume (bag, reservoir) pressure [Pa],
    /// mass [kg], density [kg/m³]; the pipe's inertance [1/m] and laminar resistance to volume
    /// flow [Pa s/m³]; and κ.
    pub(super) fn linear_point(&self) -> LinearPoint {
        let q = self.committed_cache.0;
        LinearPoint {
            p_b: q.p_b.v,
            m_b: q.m_b.v,
            rho_b: q.rho_b.v,
            reservoir: self.pipe.map(|pipe| LinearReservoir {
                p_r: q.p_r.v,
                m_r: q.m_r.v,
                rho_r: q.rho_r.v,
                inertance: pipe.inertance,
                laminar: pipe.laminar,
            }),
        }
    }

    /// Writes the committed state (and the charge) to `w`.
    pub fn save(&self, w: &mut StateWriter) {
        let s = &self.committed;
        w.f64s(&[
            s.v_membrane,
            s.sigma_b,
            s.sigma_r,
            s.m_b,
            s.m_r,
            s.mdot,
            s.heat_out,
            s.loss_work,
            self.e_ref,
            self.rho_ref,
        ]);
    }

    /// Reads what [`Gas::save`] wrote (into a gas with the same parameters).
    pub fn restore(&mut self, r: &mut StateReader) -> Result<(), SnapshotError> {
        let mut v = [0.0; 10];
        r.f64s_into(&mut v)?;
        if !v.iter().all(|x| x.is_finite()) {
            return Err(SnapshotError("gas state is not finite".into()));
        }
        self.e_ref = v[8];
        self.rho_ref = v[9];
        self.set_committed(State {
            v_membrane: v[0],
            sigma_b: v[1],
            sigma_r: v[2],
            m_b: v[3],
            m_r: v[4],
            mdot: v[5],
            heat_out: v[6],
            loss_work: v[7],
        });
        Ok(())
    }

    /// Test hook: the largest number of Newton iterations per step.
    #[cfg(test)]
    pub(super) fn set_max_iterations(&mut self, n: usize) {
        self.max_iterations = n;
    }
}

/// Linearization data of the committed state (see [`Gas::linear_point`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct LinearPoint {
    pub p_b: f64,
    pub m_b: f64,
    pub rho_b: f64,
    pub reservoir: Option<LinearReservoir>,
}

/// The reservoir part of [`LinearPoint`].
#[derive(Clone, Copy, Debug)]
pub(super) struct LinearReservoir {
    pub p_r: f64,
    pub m_r: f64,
    pub rho_r: f64,
    pub inertance: f64,
    pub laminar: f64,
}
