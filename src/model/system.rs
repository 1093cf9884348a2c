//! The interface between models and solvers: residual and iteration matrix on the free
//! coordinates.

use crate::integrators::DynState;
use crate::linalg::CscPattern;
use crate::snapshot::{StateReader, StateWriter};

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
    /// A prescribed motion outside what the model can represent (the message says which).
    #[error("{0}")]
    Outside(String),
}

/// A discretised mechanical system `M(q) a + f_int(q, v) = λ f_ext(t, q, v)` on its free
/// coordinates (supports and prescribed motions are eliminated).
pub trait MechanicalSystem {
    /// Number of free coordinates.
    fn n_free(&self) -> usize;

    /// Pattern of the free–free iteration matrix.
    fn pattern(&self) -> &CscPattern;

    /// Characteristic size of each free coordinate (m for positions, 1 for gradients), used
    /// to scale the local error estimate of adaptive steps and, unless
    /// [`Self::newton_scales`] says otherwise, the Newton convergence test.
    fn scales(&self) -> &[f64];

    /// Scales of the Newton convergence test (increment / scale against the Newton
    /// tolerance); default [`Self::scales`]. A model whose coordinates mix units may measure
    /// the increments of some in the length they move the body by (the planar belt drive's
    /// ANCF slopes) while its error estimate keeps [`Self::scales`] (the 3D belt measures its
    /// node rotations that way in both, through its `scales`).
    fn newton_scales(&self) -> &[f64] {
        self.scales()
    }

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

    /// Residual of the energy-conserving midpoint rule over a step from `t_a` to `t_b`:
    /// `M a + Q_alg(q_a, q_b) − f_ext(t_mid)`, with the average-stress internal force between
    /// `q_a` (at `t_a`) and `q_b` (at `t_b`) and a damping force at the midpoint velocity `v`.
    /// The iteration matrix is `mass·M + damping·C + stiffness·∂Q_alg/∂q_b`.
    #[allow(clippy::too_many_arguments)]
    fn midpoint_residual(
        &mut self,
        t_a: f64,
        t_b: f64,
        q_a: &[f64],
        q_b: &[f64],
        v: &[f64],
        a: &[f64],
        r: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError>;

    /// Whether the iteration matrix has a rank-one part `c g gᵀ` besides the sparse pattern
    /// (the pressure of an enclosed gas). Then the values buffers given to
    /// [`MechanicalSystem::residual`] are [`crate::linalg::rank_one_len`] long and the model
    /// writes `c` and `g` after the sparse values when the buffer is that long (callers that
    /// only need the sparse part pass `nnz` values). Default: no.
    fn rank_one(&self) -> bool {
        false
    }

    /// Whether the time steps' Newton iterations backtrack a full-Newton increment that
    /// raises the residual norm ([`crate::solver::newton::NewtonSettings::line_search`]).
    /// Default: no.
    fn damped_newton(&self) -> bool {
        false
    }

    /// Halvings of a full-Newton increment that raised the residual norm, at most, before the
    /// iteration goes on from the shortened increment (with [`Self::damped_newton`]).
    /// Default: [`crate::solver::newton::LINE_SEARCH_MAX_CUTS`].
    fn line_search_cuts(&self) -> usize {
        crate::solver::newton::LINE_SEARCH_MAX_CUTS
    }

    /// A start for the Newton iteration of a time step that is better than the integrator's
    /// own predictor. `q0`, `v0` are the free coordinates and velocities at the start of the
    /// step, `h` the step [s]; on entry `q1` holds the integrator's predicted coordinates at
    /// the end of the step. The model may overwrite any entries of `q1` with its own
    /// prediction (the integrator converts those into its unknowns, the rest keep its
    /// predictor) and returns whether it changed anything. The prediction only moves the
    /// start of the iteration: where Newton converges from either start, the converged step
    /// is the same within the Newton tolerance (where only one converges, the substeps taken
    /// differ). Must not allocate (it runs every step). Default: no prediction.
    fn predict(&mut self, _q0: &[f64], _v0: &[f64], _h: f64, _q1: &mut [f64]) -> bool {
        false
    }

    /// Whether the integrator may keep a factorized iteration matrix across a step that
    /// [`MechanicalSystem::predict`] started (modified Newton goes on with it while it
    /// contracts). Default: no, a prediction starts with a fresh matrix (the belts move their
    /// material points along the pulleys, so the contact blocks of a kept matrix belong to
    /// other points). A model whose prediction only moves the coordinates closer to where the
    /// kept matrix was computed says yes.
    fn prediction_keeps_matrix(&self) -> bool {
        false
    }

    /// Whether modified Newton learns, over the solves, whether the matrix of a solve's first
    /// iteration fails in its second (its increment larger than the first one's, so that the
    /// iteration is redone with a fresh matrix), and computes the second iteration with a
    /// fresh matrix while it mostly does ([`crate::solver::newton::SECOND_FRESH_THRESHOLD`]).
    /// Default: no (the converged states move within the Newton tolerance, and the other
    /// kinds' references were computed without it).
    fn learns_second_iteration(&self) -> bool {
        false
    }

    /// Whether modified Newton may accept the first iteration of a time step done with a kept
    /// iteration matrix when its increment is within the tolerance, judging the remaining
    /// error `θ/(1−θ)` times the increment by the contraction rate `θ` that matrix showed in
    /// its last measured iteration (if at most [`crate::solver::newton::MODIFIED_NEWTON_RATE`]).
    /// Default: no, such an iteration only measures the rate (a second iteration follows).
    /// For a model with a predictor that lands within the tolerance (the air spring's
    /// quasi-static one), one evaluation per step instead of two; the converged state moves
    /// within the tolerance.
    fn trusts_kept_contraction(&self) -> bool {
        false
    }

    /// Whether modified Newton drops a kept iteration matrix after a solve that converged
    /// with it although it contracted slower than the rebuild rate
    /// ([`MechanicalSystem::modified_newton_rate`]) in its last iteration, so that the next
    /// solve starts with a fresh one. Default: no, the matrix is kept while solves converge.
    /// For a model whose kept matrix [`MechanicalSystem::trusts_kept_contraction`]: a slow
    /// rate is not trusted, so every following solve would take two iterations or more with
    /// that matrix (the air spring's membrane level, where each converges in its second
    /// iteration and the matrix is never rebuilt).
    fn rebuilds_slow_kept_matrix(&self) -> bool {
        false
    }

    /// Contraction rate of the scaled increments above which modified Newton rebuilds and
    /// refactorizes the iteration matrix [1]. A rebuild costs the matrix and a factorization,
    /// a slower iteration with the kept matrix a residual and a solve: a model whose matrix
    /// costs several residuals may accept slower contraction. Default
    /// [`crate::solver::newton::MODIFIED_NEWTON_RATE`] (0.25).
    fn modified_newton_rate(&self) -> f64 {
        crate::solver::newton::MODIFIED_NEWTON_RATE
    }

    /// Whether an iteration matrix built at an earlier evaluation still describes the last
    /// residual evaluated without one (called by Newton's method after every evaluation with a
    /// kept matrix). A model with contact answers no when the points in contact changed since
    /// the matrix was built (its penalty blocks belong to other points); Newton then rebuilds
    /// the matrix before taking the increment. Default: yes.
    fn kept_matrix_current(&self) -> bool {
        true
    }

    /// Whether the last evaluation asked for an iteration matrix answered with a refreshed
    /// kept one instead of a matrix built at its state: asked right after an evaluation
    /// without a matrix at the same state for which [`Self::kept_matrix_current`] said no, a
    /// model may rebuild only the part that made the kept matrix stale (its contact blocks)
    /// and keep the rest from the kept matrix's build. Newton's method then treats it as a
    /// kept matrix ([`crate::solver::newton::MatrixState::Refreshed`]). Default: no.
    fn refreshed_matrix(&self) -> bool {
        false
    }

    /// The [`crate::solver::newton::MatrixState`] of the last evaluation, which built a
    /// matrix if `built` (the answer of Newton's `eval`; from [`Self::kept_matrix_current`]
    /// and [`Self::refreshed_matrix`]).
    fn matrix_state(&self, built: bool) -> crate::solver::newton::MatrixState {
        use crate::solver::newton::MatrixState;
        match (built, self.refreshed_matrix()) {
            (true, true) => MatrixState::Refreshed,
            (true, false) => MatrixState::Current,
            (false, _) => self.kept_matrix_current().into(),
        }
    }

    /// Switches the model to quasi-static steps (`solver.integrator = "quasi_static"`,
    /// [`crate::integrators::QuasiStatic`]): no inertia, an equilibrium at the end of every
    /// step. Returns whether the model supports it: only a model whose every free coordinate
    /// is held by stiffness (not by inertia alone) has an equilibrium to solve for. Default:
    /// no (a free pulley, a belt running along its path or a free-flying beam are held by their
    /// inertia).
    fn set_quasi_static(&mut self, _on: bool) -> bool {
        false
    }

    /// Called by the static solver after every converged load increment with the free
    /// coordinates of that equilibrium. A model whose coordinates are increments from stored
    /// values (incremental rotation vectors) absorbs them here and resets `q` consistently, so
    /// that load stepping can follow rotations of any size. The default does nothing.
    fn rebase(&mut self, _q: &mut [f64]) {}

    /// Called with `true` before and `false` after a static solve. A model with coordinates
    /// that have no static support (the angle of a free pulley driven only by inertia and an
    /// input torque) holds them at their committed values meanwhile, so that the static
    /// problem is not a mechanism. The default does nothing.
    fn hold_for_statics(&mut self, _held: bool) {}
}

/// A model as the simulation driver and the FMU see it: a mechanical system with inputs,
/// outputs and a committed state. Every optional FMI feature flexfmu declares
/// ([`crate::model_description::Capabilities::ALL`]: input interpolation, output derivatives,
/// FMU state) is a required method here, so a kind cannot declare what its model lacks.
pub trait Model: MechanicalSystem + Send + std::any::Any {
    /// Sets input `input` (its index among the scene's inputs, see
    /// [`crate::kinds::KindIo`]) at the model's current (committed) time; clears its
    /// derivatives.
    fn set_input(&mut self, input: usize, value: f64);

    /// Sets the `order`-th (1 or 2) time derivative of an input at the model's current time,
    /// for polynomial extrapolation inside the next communication step
    /// (`fmi2SetRealInputDerivatives`). Models that cannot interpolate return an error.
    fn set_input_derivative(
        &mut self,
        input: usize,
        order: usize,
        value: f64,
    ) -> Result<(), String>;

    /// Output `output` (its index among the scene's outputs) of the committed state with the
    /// current inputs.
    fn output(&self, output: usize) -> f64;

    /// First time derivative of an output at the committed state, if the model provides it.
    fn output_derivative(&self, output: usize) -> Option<f64>;

    /// Partial derivative of an output with respect to an input at the committed state
    /// (states frozen, FMI 2.0 Co-Simulation directional derivative), if the model provides it
    /// analytically.
    fn output_input_derivative(&mut self, _output: usize, _input: usize) -> Option<f64> {
        None
    }

    /// Called with the state after initialization and after every accepted internal step: the
    /// model commits it (outputs refer to it) and updates its history (friction states,
    /// rotation bases). It may re-express the coordinates, e.g. switch a rotation vector to its
    /// complement, by changing `state` consistently.
    fn accept(&mut self, state: &mut DynState);

    /// Free coordinates and velocities of the committed state.
    fn free_state(&self, q: &mut [f64], v: &mut [f64]);

    /// Whether the mass matrix is constant (ANCF elements): its factorization can then be kept
    /// by explicit schemes.
    fn constant_mass(&self) -> bool {
        false
    }

    /// While `hold` is set, residuals evaluated at the committed time keep prescribed-motion
    /// coordinates where the committed state has them, even if their inputs changed since: the
    /// consistent accelerations at the start of a communication step must not see a jump of a
    /// prescribed position, which the step then makes instead. Default: nothing to hold.
    fn hold_prescribed_motion(&mut self, _hold: bool) {}

    /// Called before the internal steps of a communication step from `t0` to `t1` [s], after
    /// the inputs of that step were set.
    fn begin_communication_step(&mut self, _t0: f64, _t1: f64) {}

    /// Writes everything the model needs besides the integrator state to continue exactly:
    /// inputs, committed state, history variables.
    fn save(&self, w: &mut StateWriter) -> Result<(), String>;

    /// Restores what [`Model::save`] wrote.
    fn restore(&mut self, r: &mut StateReader) -> Result<(), String>;

    /// Whether a change of this input calls for new consistent accelerations at the start of
    /// the next step (default: yes). Inputs that change every communication step as a smooth
    /// signal (a prescribed pulley angle) can say no: the integrator continues with its own
    /// accelerations, which keeps the scheme's energy behaviour and saves a factorization.
    fn input_restarts_accelerations(&self, _input: usize) -> bool {
        true
    }

    /// A line drawing of the committed state (node positions, pulleys, plates) for the FMU's
    /// documentation and icon. Every shipped kind draws itself; the default (nothing drawn)
    /// only serves models under construction, and `tests/fmu_documentation.rs` fails for a
    /// shipped scene whose model draws nothing.
    fn sketch(&self) -> super::Sketch {
        super::Sketch::default()
    }

    /// What the model chose while it was built (e.g. an automatic mesh), for the importer's
    /// log (category `logEvents`); `None` when it chose nothing.
    fn build_note(&self) -> Option<String> {
        None
    }
}

/// Newton scales of a body whose node coordinates mix lengths with dimensionless gradients or
/// rotations ([`MechanicalSystem::newton_scales`]): `scales` (per free coordinate) with every
/// free coordinate whose full index `free_to_full[k]` satisfies `gradient` measured against
/// `body_length / (4 l_e)` instead: a gradient or rotation increment δ moves the element's
/// points by about δ·l_e (`l_e` [m], the element length; `body_length` [m] the positions'
/// scale), and counting it as a position increment of 4 δ·l_e keeps the converged state as
/// accurate as before on the belt drives (README "Belt Newton scales", session 28).
pub fn newton_scales_with_gradients(
    scales: &[f64],
    free_to_full: &[usize],
    gradient: impl Fn(usize) -> bool,
    body_length: f64,
    element_length: f64,
) -> Vec<f64> {
    let g = body_length / (4.0 * element_length);
    free_to_full
        .iter()
        .zip(scales)
        .map(|(&i, &s)| if gradient(i) { g } else { s })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::newton_scales_with_gradients;

    /// Two free nodes of (x, y, x', y') and a pulley angle; node 1's x is fixed: the gradients
    /// get L / (4 l_e), the positions and the angle keep their scales.
    #[test]
    fn gradient_coordinates_are_measured_by_the_length_they_move_an_element() {
        let free_to_full = [0, 1, 2, 3, 5, 6, 7, 8];
        let scales = [2.0, 2.0, 1.0, 1.0, 2.0, 1.0, 1.0, 1.0];
        let s = newton_scales_with_gradients(
            &scales,
            &free_to_full,
            |i| i < 8 && i % 4 >= 2,
            2.0,
            0.05,
        );
        assert_eq!(s, vec![2.0, 2.0, 10.0, 10.0, 2.0, 10.0, 10.0, 1.0]);
    }
}
