//! The gas component: charge, static pressure, implicit steps, energy accounts and snapshots.

use super::params::{GasError, GasParams};
use crate::snapshot::{SnapshotError, StateReader, StateWriter};

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

/// The gas of one air spring: parameters, charge and the committed state.
#[derive(Clone, Debug, PartialEq)]
pub struct Gas {
    params: GasParams,
}

impl Gas {
    /// A gas component with `params`, charged at the design state (see [`Gas::charge`]).
    pub fn new(
        params: GasParams,
        p_gauge_design: f64,
        v_membrane_design: f64,
    ) -> Result<Self, GasError> {
        let _ = (params, p_gauge_design, v_membrane_design);
        todo!()
    }

    /// The parameters.
    pub fn params(&self) -> &GasParams {
        &self.params
    }

    /// Fixes the gas masses from the design state: bag (and reservoir) at `p_a +
    /// p_gauge_design` [Pa] and `T_a`, membrane volume `v_membrane_design` [m³], no flow. This
    /// becomes the committed state; the energy accounts restart at zero.
    pub fn charge(&mut self, p_gauge_design: f64, v_membrane_design: f64) -> Result<(), GasError> {
        let _ = (p_gauge_design, v_membrane_design);
        todo!()
    }

    /// Static absolute bag pressure [Pa] and its derivative d p / d v_membrane [Pa/m³] at the
    /// membrane volume `v_membrane` [m³] with the committed masses at rest: energy law at
    /// thermal equilibrium (T_a, reservoir pressure equal to the bag's), polytropic law on the
    /// total volume.
    pub fn static_pressure(&self, v_membrane: f64) -> Result<(f64, f64), GasError> {
        let _ = v_membrane;
        todo!()
    }

    /// Makes the static state of [`Gas::static_pressure`] at `v_membrane` [m³] the committed
    /// one (masses redistributed between bag and reservoir, no flow); the energy accounts
    /// restart at zero.
    pub fn set_static(&mut self, v_membrane: f64) -> Result<(), GasError> {
        let _ = v_membrane;
        todo!()
    }

    /// The state at the end of a step of `dt` [s] (≥ 0) over which the membrane volume goes
    /// linearly from the committed value to `v_membrane_end` [m³]; `dt = 0` gives the
    /// instantaneous response. Does not change the committed state.
    pub fn evaluate(&self, dt: f64, v_membrane_end: f64) -> Result<GasEval, GasError> {
        let _ = (dt, v_membrane_end);
        todo!()
    }

    /// [`Gas::evaluate`] and makes its end state the committed one.
    pub fn commit(&mut self, dt: f64, v_membrane_end: f64) -> Result<GasEval, GasError> {
        let _ = (dt, v_membrane_end);
        todo!()
    }

    /// The committed state (with the instantaneous `dp_dv` of `evaluate(0, v)`).
    pub fn committed(&self) -> GasEval {
        todo!()
    }

    /// The committed membrane volume [m³].
    pub fn membrane_volume(&self) -> f64 {
        todo!()
    }

    /// Writes the committed state (and the charge) to `w`.
    pub fn save(&self, w: &mut StateWriter) {
        let _ = w;
        todo!()
    }

    /// Reads what [`Gas::save`] wrote (into a gas with the same parameters).
    pub fn restore(&mut self, r: &mut StateReader) -> Result<(), SnapshotError> {
        let _ = r;
        todo!()
    }
}
