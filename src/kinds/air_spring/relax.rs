//! One iteration of the pseudo-transient continuation both membrane levels use to find the
//! sleeve's static equilibria (design state, a plate moved with the gas closed or at a fixed
//! pressure): Newton's method on `(K + c M) Δq = −r` with the pseudo-time coefficient `c`
//! following the residual (switched evolution relaxation, Mulder & van Leer 1985: `c` shrinks as
//! the residual falls, so the iteration turns into Newton's method near the solution) and the
//! increment capped, so that no node jumps through a fold. Also how both take the gas pressure in
//! an evaluation ([`Pressure`]).

use crate::gas::Gas;
use crate::model::ModelError;
use crate::solver::Workspace;

/// How the gas pressure is taken in an evaluation.
#[derive(Clone, Copy, Debug)]
pub(super) enum Pressure {
    /// A fixed gauge pressure [Pa] (the design state).
    Fixed(f64),
    /// The gas at the end of a step of this length [s] from the committed state.
    Step(f64),
    /// The gas at rest (static solve).
    Static,
}

impl Pressure {
    /// The gauge pressure [Pa] and `dp/dV` [Pa/m³] of `gas` (ambient pressure `ambient` [Pa])
    /// at the bag volume `v` [m³] (without the fixed inner volume).
    pub fn gauge(self, gas: &Gas, ambient: f64, v: f64) -> Result<(f64, f64), ModelError> {
        let bad = |_e| ModelError::NonFinite;
        match self {
            Pressure::Fixed(p) => Ok((p, 0.0)),
            Pressure::Step(dt) => {
                let (p, dp_dv) = gas.pressure(dt, v).map_err(bad)?;
                Ok((p - ambient, dp_dv))
            }
            Pressure::Static => {
                let (p, d) = gas.static_pressure(v).map_err(bad)?;
                Ok((p - ambient, d))
            }
        }
    }
}

/// What an iteration did.
#[derive(Clone, Copy, Debug)]
pub(super) struct Iteration {
    /// Norm of the residual it started from.
    pub r_norm: f64,
    /// Largest increment relative to the coordinate scales (before the cap).
    pub inc: f64,
    /// Factor the increment was scaled by to respect the cap (1: the full Newton step).
    pub scale: f64,
}

/// Pseudo-time coefficient and the residual norm it follows.
#[derive(Clone, Copy, Debug)]
pub(super) struct Relaxation {
    /// Coefficient `c` of the mass matrix in the iteration matrix [1/s²].
    pub c: f64,
    r_old: f64,
}

impl Relaxation {
    /// Starting with the coefficient `c`.
    pub fn new(c: f64) -> Self {
        Self {
            c,
            r_old: f64::INFINITY,
        }
    }

    /// With the residual and the iteration matrix (assembled with [`Self::c`]) in `ws`: factors,
    /// solves, adds the increment, capped at `cap` of the scales `scales`, to `x`, and updates
    /// `c` by the ratio of the residual norms (clamped to 0.1–4; 0 once below 1e-8).
    pub fn iterate(
        &mut self,
        ws: &mut Workspace,
        x: &mut [f64],
        scales: &[f64],
        cap: f64,
    ) -> Result<Iteration, String> {
        let r_norm = ws.r.iter().map(|v| v * v).sum::<f64>().sqrt();
        ws.solver
            .factor(&ws.pattern, &ws.jac)
            .map_err(|e| e.to_string())?;
        for (d, r) in ws.dx.iter_mut().zip(&ws.r) {
            *d = -r;
        }
        ws.solver.solve_in_place(&mut ws.dx);
        let inc = ws
            .dx
            .iter()
            .zip(scales)
            .map(|(d, s)| (d / s).abs())
            .fold(0.0, f64::max);
        if !inc.is_finite() {
            return Err("non-finite increment".into());
        }
        let scale = if inc > cap { cap / inc } else { 1.0 };
        for (xi, d) in x.iter_mut().zip(&ws.dx) {
            *xi += scale * d;
        }
        if r_norm.is_finite() && self.r_old.is_finite() {
            self.c *= (r_norm / self.r_old).clamp(0.1, 4.0);
        }
        self.r_old = r_norm;
        Ok(Iteration { r_norm, inc, scale })
    }

    /// Drops the relaxation once it is negligible (call after the convergence test).
    pub fn settle(&mut self) {
        if self.c < 1e-8 {
            self.c = 0.0;
        }
    }
}
