//! Air constants, the gas laws, the reservoir description and the error type of the gas model.

/// Specific gas constant of dry air R [J/(kg K)].
pub const R_AIR: f64 = 287.05;
/// Ratio of specific heats of air γ = c_p / c_v [1].
pub const GAMMA_AIR: f64 = 1.4;
/// Dynamic viscosity of air μ [Pa s] (at about 20 °C), used by the laminar pipe friction.
pub const MU_AIR: f64 = 1.81e-5;

/// How the pressure of a control volume follows its volume, mass and heat exchange.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GasLaw {
    /// `p = K ρⁿ` in every control volume (one `K`, fixed by the charge): `p Vⁿ = const` for a
    /// closed volume; isentropic-like flow between bag and reservoir. `n` [1] > 0
    /// (1 isothermal, 1.4 adiabatic; air-spring-physics.md 1.4).
    Polytropic {
        /// Polytropic exponent n [1].
        n: f64,
    },
    /// Energy balance per control volume (air-spring-physics.md 1.4, seed004 ref. D.2):
    /// `d(m c_v T)/dt = Σ ṁ_in c_p T_up − p dV/dt + h (T_a − T)`, `p = m R T / V`.
    Energy {
        /// Heat-transfer coefficient h [W/K] between each control volume and the ambient. The
        /// reservoir gets the same h as the bag (not scaled by its wall area).
        heat_transfer: f64,
    },
}

/// A fixed reservoir joined to the bag by a pipe with an orifice (air-spring-physics.md 1.5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reservoir {
    /// Reservoir volume [m³].
    pub volume: f64,
    /// Orifice diameter [m].
    pub orifice_diameter: f64,
    /// Orifice discharge coefficient C_d [1], in (0, 1].
    pub cd: f64,
    /// Pipe length ℓ [m] (> 0: it carries the inertance ℓ / A_pipe).
    pub pipe_length: f64,
    /// Pipe inner diameter [m].
    pub pipe_diameter: f64,
}

/// Everything that defines a gas component except its charge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GasParams {
    /// The gas law.
    pub law: GasLaw,
    /// Ambient pressure p_a [Pa] (absolute).
    pub ambient_pressure: f64,
    /// Ambient temperature T_a [K]; the charge temperature and the heat-transfer sink.
    pub ambient_temperature: f64,
    /// Fixed volume added to the membrane volume in the bag (piston interior) [m³], ≥ 0.
    pub inner_volume: f64,
    /// Optional reservoir behind a pipe and an orifice.
    pub reservoir: Option<Reservoir>,
}

/// A gas evaluation that failed: bad input, non-positive volume or pressure, non-finite values
/// or an inner Newton solve that did not converge. The message says which.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("gas model: {0}")]
pub struct GasError(pub String);

impl GasParams {
    /// Checks that every parameter is finite and in its range.
    pub fn validate(&self) -> Result<(), GasError> {
        let check = |name: &str, v: f64, ok: bool, range: &str| {
            if v.is_finite() && ok {
                Ok(())
            } else {
                Err(GasError(format!("{name} = {v} must be finite and {range}")))
            }
        };
        check(
            "ambient pressure",
            self.ambient_pressure,
            self.ambient_pressure > 0.0,
            "> 0 Pa",
        )?;
        check(
            "ambient temperature",
            self.ambient_temperature,
            self.ambient_temperature > 0.0,
            "> 0 K",
        )?;
        check(
            "inner volume",
            self.inner_volume,
            self.inner_volume >= 0.0,
            ">= 0 m3",
        )?;
        match self.law {
            GasLaw::Polytropic { n } => check("polytropic exponent", n, n > 0.0, "> 0")?,
            GasLaw::Energy { heat_transfer } => check(
                "heat transfer coefficient",
                heat_transfer,
                heat_transfer >= 0.0,
                ">= 0 W/K",
            )?,
        }
        if let Some(r) = &self.reservoir {
            check("reservoir volume", r.volume, r.volume > 0.0, "> 0 m3")?;
            check(
                "orifice diameter",
                r.orifice_diameter,
                r.orifice_diameter > 0.0,
                "> 0 m",
            )?;
            check("orifice cd", r.cd, r.cd > 0.0 && r.cd <= 1.0, "in (0, 1]")?;
            check("pipe length", r.pipe_length, r.pipe_length > 0.0, "> 0 m")?;
            check(
                "pipe diameter",
                r.pipe_diameter,
                r.pipe_diameter > 0.0,
                "> 0 m",
            )?;
        }
        Ok(())
    }

    /// The exponent κ of the entropy-like variable `σ = ln p − κ ln ρ` of the model: `n` of
    /// the polytropic law, γ for the energy law.
    pub fn kappa(&self) -> f64 {
        match self.law {
            GasLaw::Polytropic { n } => n,
            GasLaw::Energy { .. } => GAMMA_AIR,
        }
    }
}
