//! The interface between models and solvers: residual and iteration matrix on the free
//! coordinates.

use crate::linalg::CscPattern;

/// Coefficients of the iteration matrix `J = mass·∂r/∂a + damping·∂r/∂v + stiffness·∂r/∂q`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JacobianCoeffs {
    /// Factor on the mass matrix [1].
    pub mass: f64,
    /// Factor on the damping matrix [s].
    pub damping: f64,
    /// Factor on the tangent stiffness [s²].
    pub stiffness: f64,
}

/// A model evaluation that cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// NaN or infinite values in the forces.
    #[error("non-finite internal force (NaN or infinity): the configuration is invalid")]
    NonFinite,
}

/// A discretised mechanical system `M(q) a + f_int(q, v) = λ f_ext(t, q, v)` on its free
/// coordinates (supports and prescribed motions are eliminated).
pub trait MechanicalSystem {
    /// Number of free coordinates.
    fn n_free(&self) -> usize;

    /// Pattern of the free–free iteration matrix.
    fn pattern(&self) -> &CscPattern;

    /// Characteristic size of each free coordinate (m for positions, 1 for gradients), used
    /// to scale convergence norms.
    fn scales(&self) -> &[f64];

    /// Residual `r = M a + f_int(q, v) − λ f_ext(t)` at time `t` [s] and, if asked, the
    /// iteration matrix values (in [`Self::pattern`]) for the given coefficients.
    #[allow(clippy::too_many_arguments)]
    fn residual(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        load_factor: f64,
        r: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError>;

    /// Residual of the energy-conserving midpoint rule: `M a + Q_alg(q_a, q_b) − f_ext(t)`,
    /// with the average-stress internal force between `q_a` and `q_b` and a damping force at
    /// `v`. The iteration matrix is `mass·M + damping·C + stiffness·∂Q_alg/∂q_b`.
    #[allow(clippy::too_many_arguments)]
    fn midpoint_residual(
        &mut self,
        t: f64,
        q_a: &[f64],
        q_b: &[f64],
        v: &[f64],
        a: &[f64],
        r: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError>;
}

/// A model as the simulation driver and the FMU see it: a mechanical system with inputs,
/// outputs and a committed state.
pub trait Model: MechanicalSystem + Send {
    /// Sets an input value (held until the next call; see
    /// [`Model::begin_communication_step`]).
    fn set_input(&mut self, kind: crate::variables::InputKind, value: f64);

    /// An output of the committed state.
    fn output(&self, kind: crate::variables::OutputKind) -> f64;

    /// Called with the state after initialization and after every accepted internal step: the
    /// model commits it (outputs refer to it) and updates its history (friction states,
    /// rotation bases). It may re-express the coordinates, e.g. switch a rotation vector to its
    /// complement, by changing `state` consistently.
    fn accept(&mut self, state: &mut crate::integrators::DynState);

    /// Free coordinates and velocities of the committed state.
    fn free_state(&self, q: &mut [f64], v: &mut [f64]);

    /// Called before the internal steps of a communication step from `t0` to `t1` [s], after
    /// the inputs of that step were set.
    fn begin_communication_step(&mut self, _t0: f64, _t1: f64) {}

    /// Whether a change of this input calls for new consistent accelerations at the start of
    /// the next step (default: yes). Inputs that change every communication step as a smooth
    /// signal (a prescribed pulley angle) can say no: the integrator continues with its own
    /// accelerations, which keeps the scheme's energy behaviour and saves a factorization.
    fn input_restarts_accelerations(&self, _kind: crate::variables::InputKind) -> bool {
        true
    }
}
