//! The simulation driver: static initialization, consistent initial accelerations, and the
//! advance over a communication step with internal substeps that are halved when Newton fails.

use super::newton::{NewtonPolicy, NewtonSettings, NewtonStats, Workspace, scaled_max};
use super::statics;
use crate::integrators::{DynState, Integrator};
use crate::linalg::SolverKind;
use crate::model::{JacobianCoeffs, Model};
use crate::scene::params::{ParamValues, names::*};
use crate::snapshot::{StateReader, StateWriter};

/// Substeps may be halved this many times below `solver.max_step` before a communication step
/// is given up.
pub const MAX_HALVINGS: u32 = 30;

/// Largest number of internal steps one communication step may need; a longer one is refused
/// instead of running for hours.
pub const MAX_SUBSTEPS: f64 = 1e7;

/// Internal step attempts (accepted or rejected) that one communication step may spend beyond
/// its nominal count (span / largest step): substeps cut far below `solver.max_step` over a
/// whole communication step make it fail with a message instead of running for minutes (a
/// motion input jumping by 100 m in 1 ms took 420,000 substeps of 5e-9 s, 12 s of CPU, found by
/// the FMI call-sequence fuzzer).
pub const MAX_EXTRA_SUBSTEPS: f64 = 1e4;

/// Largest scaled local error estimate of an accepted implicit step even without error control
/// (`solver.tolerance` = 0): a tenth of the body length (or 0.1 rad, 0.1 of a unit gradient) in
/// one step. Beyond it the converged Newton solution is no approximation of the motion (large
/// steps can converge to a spurious, highly strained configuration); the step is halved instead.
pub const SAFETY_ERROR: f64 = 0.1;

/// Relative size of the finite-difference perturbation of an input in
/// [`Simulation::output_input_difference`].
pub const FD_REL: f64 = 1e-6;

/// Solver settings from the `solver.*` parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverConfig {
    /// Time integrator.
    pub integrator: Integrator,
    /// Largest internal step [s].
    pub max_step: f64,
    /// Newton settings.
    pub newton: NewtonSettings,
    /// Solve the static equilibrium at initialization.
    pub static_equilibrium: bool,
    /// Initial load increments of the static solve.
    pub load_steps: usize,
    /// Factorization.
    pub linear: SolverKind,
    /// Local error tolerance of adaptive substeps, relative to the coordinate scales (0: fixed
    /// substeps of `max_step`).
    pub tolerance: f64,
}

impl SolverConfig {
    /// From validated parameter values.
    pub fn from_params(p: &ParamValues) -> Self {
        Self {
            integrator: Integrator::from_code(p.integer(SOLVER_INTEGRATOR), p.real(SOLVER_RHO_INF)),
            max_step: p.real(SOLVER_MAX_STEP),
            newton: NewtonSettings {
                tolerance: p.real(SOLVER_NEWTON_TOL),
                max_iterations: p.integer(SOLVER_MAX_ITER) as usize,
                policy: match p.integer(SOLVER_NEWTON) {
                    1 => NewtonPolicy::Full,
                    _ => NewtonPolicy::Modified,
                },
                line_search: false,
            },
            tolerance: p.real(SOLVER_TOLERANCE),
            static_equilibrium: p.boolean(SOLVER_STATIC),
            load_steps: p.integer(SOLVER_LOAD_STEPS) as usize,
            linear: match p.integer(SOLVER_LINEAR) {
                1 => SolverKind::Banded,
                2 => SolverKind::SparseLu,
                _ => SolverKind::Auto,
            },
        }
    }
}

/// Work counters of a simulation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RunStats {
    /// Accepted internal steps.
    pub steps: usize,
    /// Rejected internal steps (Newton failures and error-estimate rejections).
    pub rejected: usize,
    /// Of those, the steps rejected by the local error estimate (above `solver.tolerance`
    /// with error control, above [`SAFETY_ERROR`] without); the rest are Newton failures.
    pub rejected_error: usize,
    /// Newton work.
    pub newton: NewtonStats,
}

/// One rejected internal step, recorded when [`Simulation::log_rejections`] is on
/// (diagnostics: which coordinate stopped the step).
#[derive(Clone, Debug, PartialEq)]
pub struct Rejection {
    /// Start of the step [s].
    pub t: f64,
    /// Step size [s].
    pub h: f64,
    /// The Newton failure, or `None` for a rejection by the error estimate.
    pub newton: Option<String>,
    /// Free coordinate with the largest scaled entry: of the error estimate, or of the last
    /// Newton increment.
    pub coordinate: usize,
    /// That scaled entry [1] (error / coordinate scale, or increment · β h² / scale).
    pub value: f64,
}

/// A communication step that could not be completed.
#[derive(Debug, Clone, PartialEq)]
pub struct AdvanceError {
    /// Time up to which the simulation advanced successfully [s].
    pub reached: f64,
    /// What went wrong.
    pub message: String,
}

/// A model with its integrator state.
pub struct Simulation {
    model: Box<dyn Model>,
    cfg: SolverConfig,
    ws: Workspace,
    state: DynState,
    trial: DynState,
    stats: RunStats,
    inputs_changed: bool,
    /// Next substep proposed by the step-size controller [s].
    h_next: f64,
    /// Error estimate buffer.
    err: Vec<f64>,
    /// Buffers of the explicit scheme's stable-step estimate (sized on first use).
    power: PowerScratch,
    /// Rejected steps since logging was switched on, if it is.
    rejections: Option<Vec<Rejection>>,
}

/// Buffers of the power iteration in [`Simulation::explicit_step_limit`].
#[derive(Default)]
struct PowerScratch {
    /// Tangent stiffness values (in the model's pattern).
    k: Vec<f64>,
    /// Iterate and its image.
    x: Vec<f64>,
    y: Vec<f64>,
    /// Zero accelerations.
    zeros: Vec<f64>,
}

impl PowerScratch {
    fn resize(&mut self, n: usize, nnz: usize) {
        self.k.resize(nnz, 0.0);
        self.x.resize(n, 0.0);
        self.y.resize(n, 0.0);
        self.zeros.resize(n, 0.0);
    }
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("t", &self.state.t)
            .field("n_free", &self.state.q.len())
            .field("stats", &self.stats)
            .finish()
    }
}

impl Simulation {
    /// Prepares buffers and the factorization for `model` at time `t0`, from its committed
    /// state.
    pub fn new(mut model: Box<dyn Model>, mut cfg: SolverConfig, t0: f64) -> Result<Self, String> {
        cfg.newton.line_search = model.damped_newton();
        if cfg.integrator.is_quasi_static() && !model.set_quasi_static(true) {
            return Err(
                "solver.integrator = quasi_static: this model does not offer quasi-static steps (the air spring's levels do; a belt drive's pulleys and running belt are held by their inertia); use an inertial integrator".into(),
            );
        }
        let ws = Workspace::new(model.as_ref(), cfg.linear).map_err(|e| e.to_string())?;
        let n = model.n_free();
        let mut state = DynState::zeros(n, t0);
        model.free_state(&mut state.q, &mut state.v);
        let trial = state.clone();
        Ok(Self {
            model,
            cfg,
            ws,
            state,
            trial,
            stats: RunStats::default(),
            inputs_changed: true,
            h_next: cfg.max_step,
            err: vec![0.0; n],
            power: PowerScratch::default(),
            rejections: None,
        })
    }

    /// Static equilibrium (if configured) and consistent initial accelerations. Returns a
    /// description of the static solve for the log.
    pub fn initialize(&mut self) -> Result<Option<String>, String> {
        let mut report = None;
        if self.cfg.static_equilibrium {
            let s = statics::solve(
                self.model.as_mut(),
                &mut self.ws,
                &mut self.state.q,
                &self.cfg.newton,
                self.cfg.load_steps,
            )
            .map_err(|e| e.to_string())?;
            self.state.v.iter_mut().for_each(|v| *v = 0.0);
            self.stats.newton += s.newton;
            report = Some(format!(
                "static equilibrium: {} load increment(s), {} Newton iterations",
                s.increments, s.newton.iterations
            ));
        }
        self.restart_accelerations(false)?;
        self.model.accept(&mut self.state);
        Ok(report)
    }

    /// Solves `M acc = f_ext − f_int(q, v)` at the current state: at initialization the
    /// algorithmic acceleration starts equal to it; when inputs jump at a communication point
    /// (zero-order hold) the algorithmic acceleration moves by the same jump, so that
    /// generalized-α keeps its history (and Newmark's `a = acc` stays true).
    /// With `hold_ports`, prescribed-motion inputs that changed at this communication point
    /// are not applied at its start: a port that was told to be elsewhere gets there during the
    /// step instead of jumping (see [`Model::hold_prescribed_motion`]).
    fn restart_accelerations(&mut self, hold_ports: bool) -> Result<(), String> {
        let n = self.state.q.len();
        if self.cfg.integrator.is_quasi_static() {
            // no inertia: the accelerations are not unknowns
            self.state.acc.fill(0.0);
            self.state.a.fill(0.0);
            self.inputs_changed = false;
            return Ok(());
        }
        self.model.hold_prescribed_motion(hold_ports);
        self.trial.a.iter_mut().for_each(|x| *x = 0.0);
        let coeffs = JacobianCoeffs {
            mass: 1.0,
            damping: 0.0,
            stiffness: 0.0,
        };
        let res = self
            .model
            .residual(
                self.state.t,
                &self.state.q,
                &self.state.v,
                &self.trial.a,
                1.0,
                &mut self.ws.r,
                Some((coeffs, &mut self.ws.jac)),
            )
            .map_err(|e| e.to_string());
        self.model.hold_prescribed_motion(false);
        let () = res?;
        self.ws.invalidate();
        self.ws
            .solver
            .factor(&self.ws.pattern, &self.ws.jac)
            .map_err(|e| format!("mass matrix: {e}"))?;
        if self.model.constant_mass() {
            self.ws.mark_factored(&coeffs);
        }
        let acc = &mut self.trial.acc;
        for i in 0..n {
            acc[i] = -self.ws.r[i];
        }
        self.ws.solver.solve_in_place(acc);
        if acc.iter().any(|x| !x.is_finite()) {
            return Err("initial accelerations are not finite".into());
        }
        if hold_ports {
            for i in 0..n {
                self.state.a[i] += acc[i] - self.state.acc[i];
            }
        } else {
            self.state.a.copy_from_slice(acc);
        }
        self.state.acc.copy_from_slice(acc);
        self.inputs_changed = false;
        Ok(())
    }

    /// Sets input `input` (index among the scene's inputs); takes effect at the next advance
    /// (held constant over it).
    pub fn set_input(&mut self, input: usize, value: f64) {
        self.model.set_input(input, value);
        if self.model.input_restarts_accelerations(input) {
            self.inputs_changed = true;
        }
    }

    /// Current time [s].
    pub fn time(&self) -> f64 {
        self.state.t
    }

    /// Output `output` (index among the scene's outputs) of the current state.
    pub fn output(&self, output: usize) -> f64 {
        self.model.output(output)
    }

    /// The model, if it is of type `T` (tests and tools that use a model's typed methods).
    pub fn model_as_mut<T: Model>(&mut self) -> Option<&mut T> {
        (self.model.as_mut() as &mut dyn std::any::Any).downcast_mut::<T>()
    }

    /// The model, if it is of type `T`.
    pub fn model_as<T: Model>(&self) -> Option<&T> {
        (self.model.as_ref() as &dyn std::any::Any).downcast_ref::<T>()
    }

    /// Work counters so far.
    pub fn stats(&self) -> RunStats {
        self.stats
    }

    /// Switches the log of rejected internal steps on (cleared) or off (diagnostics; a
    /// rejection allocates its record).
    pub fn log_rejections(&mut self, on: bool) {
        self.rejections = on.then(Vec::new);
    }

    /// The rejected internal steps logged since [`Simulation::log_rejections`], emptied.
    pub fn take_rejections(&mut self) -> Vec<Rejection> {
        self.rejections
            .as_mut()
            .map(std::mem::take)
            .unwrap_or_default()
    }

    /// Records a rejection when logging (largest scaled entry of `x`, times `factor`).
    fn record_rejection(&mut self, h: f64, newton: Option<String>, from_error: bool) {
        let Some(log) = self.rejections.as_mut() else {
            return;
        };
        let (x, factor, scales) = if from_error {
            (&self.err, 1.0, &self.ws.error_scales)
        } else {
            let f = match self.cfg.integrator {
                Integrator::GeneralizedAlpha(g) => g.beta * h * h,
                // the unknown is the coordinates themselves
                Integrator::QuasiStatic(_) => 1.0,
                _ => 0.5 * h * h,
            };
            (&self.ws.dx, f, &self.ws.scales)
        };
        let (mut coordinate, mut value) = (0, 0.0);
        for (k, (d, s)) in x.iter().zip(scales).enumerate() {
            let e = (d * factor / s).abs();
            if e > value || e.is_nan() {
                (coordinate, value) = (k, e);
            }
        }
        log.push(Rejection {
            t: self.state.t,
            h,
            newton,
            coordinate,
            value,
        });
    }

    /// Current solver settings.
    pub fn config(&self) -> &SolverConfig {
        &self.cfg
    }

    /// Changes the tunable settings (step size, Newton settings).
    pub fn set_tunables(&mut self, cfg: &SolverConfig) {
        self.cfg.max_step = cfg.max_step;
        self.cfg.newton = NewtonSettings {
            line_search: self.cfg.newton.line_search,
            ..cfg.newton
        };
        self.cfg.tolerance = cfg.tolerance;
        self.h_next = self.h_next.min(cfg.max_step);
    }

    /// The model.
    pub fn model(&self) -> &dyn Model {
        self.model.as_ref()
    }

    /// Sets an input time derivative (for extrapolation inside the next step).
    pub fn set_input_derivative(
        &mut self,
        kind: usize,
        order: usize,
        value: f64,
    ) -> Result<(), String> {
        self.model.set_input_derivative(kind, order, value)?;
        if self.model.input_restarts_accelerations(kind) {
            self.inputs_changed = true;
        }
        Ok(())
    }

    /// First time derivative of an output, if the model provides it.
    pub fn output_derivative(&self, kind: usize) -> Option<f64> {
        self.model.output_derivative(kind)
    }

    /// ∂output/∂input with the state frozen, if the model provides it analytically.
    pub fn output_input_derivative(&mut self, output: usize, input: usize) -> Option<f64> {
        self.model.output_input_derivative(output, input)
    }

    /// Central difference of the output function with respect to an input whose current value
    /// is `u`, the state frozen (FMI 2.0 section 4.1: the direct feedthrough at a communication
    /// point). The relative step is [`FD_REL`]; the simulation is unchanged afterwards (saved
    /// and restored, which also restores the input signal).
    pub fn output_input_difference(
        &mut self,
        output: usize,
        input: usize,
        u: f64,
    ) -> Result<f64, String> {
        let mut backup = StateWriter::new();
        self.save(&mut backup)?;
        let h = FD_REL * u.abs().max(1.0);
        self.model.set_input(input, u + h);
        let yp = self.model.output(output);
        self.model.set_input(input, u - h);
        let ym = self.model.output(output);
        self.restore(&mut StateReader::new(backup.bytes()))?;
        Ok((yp - ym) / (2.0 * h))
    }

    /// ∂output/∂input at a communication point with the state frozen: the model's analytic
    /// partial where it has one, else [`Simulation::output_input_difference`]. This is what
    /// `fmi2GetDirectionalDerivative` returns for a pair that the model description declares
    /// (`ModelStructure/Outputs` dependencies); undeclared pairs are zero by declaration, and
    /// `tests/model_structure.rs` checks that the declaration is exactly the set of pairs
    /// with a non-zero partial.
    pub fn output_input_partial(
        &mut self,
        output: usize,
        input: usize,
        u: f64,
    ) -> Result<f64, String> {
        match self.model.output_input_derivative(output, input) {
            Some(d) => Ok(d),
            None => self.output_input_difference(output, input, u),
        }
    }

    /// Response of outputs to input changes `du` through the static equilibrium at the current
    /// state (linearized): `dq = −K⁻¹ (∂r/∂u) du`, then `dy = (∂y/∂q) dq + (∂y/∂u) du`, with the
    /// partials of the residual and of the output functions by central differences. Without a
    /// static equilibrium the state does not depend on the inputs and only `(∂y/∂u) du` remains.
    /// The simulation is unchanged afterwards.
    pub fn linearized_output_response(
        &mut self,
        du: &[(usize, f64, f64)],
        outputs: &[usize],
    ) -> Result<Vec<f64>, String> {
        let mut backup = StateWriter::new();
        self.save(&mut backup)?;
        let result = self.linearized_inner(du, outputs);
        self.restore(&mut StateReader::new(backup.bytes()))?;
        result
    }

    fn linearized_inner(
        &mut self,
        du: &[(usize, f64, f64)],
        outputs: &[usize],
    ) -> Result<Vec<f64>, String> {
        let n = self.state.q.len();
        // Step along the seed: small against every input it touches.
        let h = du
            .iter()
            .filter(|(_, _, d)| *d != 0.0)
            .map(|(_, u, d)| 1e-6 * u.abs().max(1.0) / d.abs())
            .fold(f64::INFINITY, f64::min);
        if !h.is_finite() {
            return Ok(vec![0.0; outputs.len()]);
        }
        let set_inputs = |model: &mut dyn Model, s: f64| {
            for &(k, u, d) in du {
                model.set_input(k, u + s * h * d);
            }
        };
        let mut dq = vec![0.0; n];
        if self.cfg.static_equilibrium {
            let zeros = vec![0.0; n];
            let mut rp = vec![0.0; n];
            let coeffs = JacobianCoeffs {
                mass: 0.0,
                damping: 0.0,
                stiffness: 1.0,
            };
            let t = self.state.t;
            set_inputs(self.model.as_mut(), 1.0);
            self.model
                .residual(t, &self.state.q, &zeros, &zeros, 1.0, &mut rp, None)
                .map_err(|e| e.to_string())?;
            set_inputs(self.model.as_mut(), -1.0);
            self.model
                .residual(
                    t,
                    &self.state.q,
                    &zeros,
                    &zeros,
                    1.0,
                    &mut self.ws.r,
                    Some((coeffs, &mut self.ws.jac)),
                )
                .map_err(|e| e.to_string())?;
            self.ws
                .solver
                .factor(&self.ws.pattern, &self.ws.jac)
                .map_err(|e| e.to_string())?;
            for i in 0..n {
                dq[i] = -(rp[i] - self.ws.r[i]) / (2.0 * h);
            }
            self.ws.solver.solve_in_place(&mut dq);
        }
        let mut probe = self.state.clone();
        let base = self.state.q.clone();
        let mut eval = |sim: &mut Self, s: f64| -> Vec<f64> {
            for i in 0..n {
                probe.q[i] = base[i] + s * h * dq[i];
            }
            set_inputs(sim.model.as_mut(), s);
            sim.model.accept(&mut probe);
            outputs.iter().map(|&k| sim.model.output(k)).collect()
        };
        let yp = eval(self, 1.0);
        let ym = eval(self, -1.0);
        Ok(yp
            .iter()
            .zip(&ym)
            .map(|(a, b)| (a - b) / (2.0 * h))
            .collect())
    }

    /// Writes the complete simulation state (integrator state, step-size controller, model
    /// state, pending restart). The kept factorization of modified Newton is dropped, so that
    /// the run continues from here exactly as a run restored from this state will (and so is
    /// what modified Newton learnt about it, [`Workspace::forget_history`]).
    pub fn save(&mut self, w: &mut StateWriter) -> Result<(), String> {
        self.ws.invalidate();
        self.ws.forget_history();
        let s = &self.state;
        w.f64(s.t);
        for v in [&s.q, &s.v, &s.acc, &s.a] {
            w.f64s(v);
        }
        w.bool(self.inputs_changed);
        w.f64(self.h_next);
        self.model.save(w)
    }

    /// Restores what [`Simulation::save`] wrote (into a simulation of the same model).
    pub fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        let s = &mut self.state;
        s.t = r.f64().map_err(e)?;
        for v in [&mut s.q, &mut s.v, &mut s.acc, &mut s.a] {
            r.f64s_into(v).map_err(e)?;
        }
        self.inputs_changed = r.bool().map_err(e)?;
        self.h_next = r.f64().map_err(e)?;
        self.ws.invalidate();
        self.ws.forget_history();
        self.model.restore(r)
    }

    /// Largest stable step of the explicit scheme, `0.8 · 2/ω_max`, with the highest
    /// eigenfrequency of `K_T v = ω² M v` at the current state from 60 power iterations on
    /// `M⁻¹ K_T` (the free–free seed-000 element's through-height mode dominates: reference
    /// F.2).
    fn explicit_step_limit(&mut self) -> Result<f64, String> {
        let n = self.state.q.len();
        let stiff = JacobianCoeffs {
            mass: 0.0,
            damping: 0.0,
            stiffness: 1.0,
        };
        let mass = JacobianCoeffs {
            mass: 1.0,
            damping: 0.0,
            stiffness: 0.0,
        };
        let (t, model, ws, state) = (self.state.t, &mut self.model, &mut self.ws, &self.state);
        let power = &mut self.power;
        power.resize(n, ws.jac.len());
        let mut matrix = |coeffs: JacobianCoeffs, jac: &mut [f64]| {
            model
                .residual(
                    t,
                    &state.q,
                    &state.v,
                    &power.zeros,
                    1.0,
                    &mut ws.r,
                    Some((coeffs, jac)),
                )
                .map_err(|e| e.to_string())
        };
        matrix(stiff, &mut power.k)?;
        matrix(mass, &mut ws.jac)?;
        self.ws.invalidate();
        self.ws
            .solver
            .factor(&self.ws.pattern, &self.ws.jac)
            .map_err(|e| e.to_string())?;
        if self.model.constant_mass() {
            self.ws.mark_factored(&mass);
        }
        let lambda = self.power_iteration();
        if lambda.is_nan() || lambda <= 0.0 || !lambda.is_finite() {
            return Err("cannot estimate the highest eigenfrequency for the explicit step".into());
        }
        let omega = lambda.sqrt();
        // The damping forces are explicit too (evaluated at the half-step velocity): a mode
        // with frequency ω and damping ratio ξ is stable for h ≤ (2/ω)(√(1 + ξ²) − ξ)
        // (the damped central-difference limit, Belytschko, Liu & Moran, Nonlinear Finite
        // Elements for Continua and Structures, section 6.2; it is the spectral-radius bound of
        // this scheme's amplification matrix for ξ = 0 … 10 to 1e-5). The bound takes
        // the highest frequency with the largest damping rate c of M⁻¹C (ξ = c / 2ω): at most
        // both at once, so on the safe side.
        let damp = JacobianCoeffs {
            mass: 0.0,
            damping: 1.0,
            stiffness: 0.0,
        };
        let (t, model, ws, state) = (self.state.t, &mut self.model, &mut self.ws, &self.state);
        model
            .residual(
                t,
                &state.q,
                &state.v,
                &self.power.zeros,
                1.0,
                &mut ws.r,
                Some((damp, &mut self.power.k)),
            )
            .map_err(|e| e.to_string())?;
        let c = self.power_iteration();
        let xi = if c.is_finite() && c > 0.0 {
            0.5 * c / omega
        } else {
            0.0
        };
        Ok(0.8 * 2.0 / omega * ((1.0 + xi * xi).sqrt() - xi))
    }

    /// The largest eigenvalue of `M⁻¹ A` by power iteration, `A` in `self.power.k` (with its
    /// rank-one part, if the model has one) and `M` factorized in the workspace's solver.
    fn power_iteration(&mut self) -> f64 {
        let n = self.state.q.len();
        // deterministic start vector with all modes present
        let PowerScratch { k, x, y, .. } = &mut self.power;
        for (i, xi) in x.iter_mut().enumerate() {
            *xi = 1.0 + ((i * 7919) % 13) as f64 / 13.0;
        }
        let mut lambda = 0.0;
        let nnz = self.ws.pattern.nnz();
        for _ in 0..60 {
            self.ws.pattern.mul_vec(&k[..nnz], x, y);
            // the rank-one part c g gᵀ of the stiffness, if the model has one
            if k.len() > nnz && k[nnz] != 0.0 {
                let (c, g) = (k[nnz], &k[nnz + 1..]);
                let gx: f64 = g.iter().zip(x.iter()).map(|(a, b)| a * b).sum();
                for (yi, gi) in y.iter_mut().zip(g) {
                    *yi += c * gx * gi;
                }
            }
            self.ws.solver.solve_in_place(y);
            let norm = y.iter().map(|v| v * v).sum::<f64>().sqrt();
            let xn = x.iter().map(|v| v * v).sum::<f64>().sqrt();
            if norm == 0.0 || !norm.is_finite() {
                break;
            }
            lambda = norm / xn;
            for i in 0..n {
                x[i] = y[i] / norm;
            }
        }
        lambda
    }

    /// Advances to `t_end`. Implicit schemes take substeps of at most `solver.max_step`; with
    /// `solver.tolerance` > 0 the substep follows a local error estimate (accepted when the
    /// scaled error is below the tolerance, grown or shrunk by `0.9 (tol/err)^(1/3)`, at most
    /// ×2). A Newton failure halves the substep, and so does an estimate above
    /// [`SAFETY_ERROR`] without error control. The explicit scheme takes equal substeps below
    /// its stability limit. On failure the state stays at the last accepted substep.
    pub fn advance(&mut self, t_end: f64) -> Result<(), AdvanceError> {
        self.model.begin_communication_step(self.state.t, t_end);
        let fail = |reached: f64, message: String| AdvanceError { reached, message };
        if self.inputs_changed {
            self.restart_accelerations(true)
                .map_err(|m| fail(self.state.t, m))?;
        }
        let explicit = self.cfg.integrator.is_explicit();
        let h_max = if explicit {
            let limit = self
                .explicit_step_limit()
                .map_err(|m| fail(self.state.t, m))?;
            if (t_end - self.state.t) / limit > MAX_SUBSTEPS {
                return Err(fail(
                    self.state.t,
                    format!(
                        "the explicit scheme's stable step is {limit:.3e} s: more than 1e7 steps for this communication step; use an implicit integrator"
                    ),
                ));
            }
            self.cfg.max_step.min(limit)
        } else {
            self.cfg.max_step
        };
        let adaptive = self.cfg.tolerance > 0.0 && !explicit;
        // Adaptive: the controller's proposal; fixed substeps: the step the safety check of
        // the error estimate left (see the growth rule below), h_max without rejections.
        let mut h_limit = self.h_next.min(h_max);
        let h_min = h_max * 0.5f64.powi(MAX_HALVINGS as i32);
        let span = (t_end - self.state.t).abs().max(f64::MIN_POSITIVE);
        let constant_mass = self.model.constant_mass();
        let nominal = (span / h_max).ceil();
        let mut attempts = 0.0;
        while t_end - self.state.t > 1e-12 * span.max(t_end.abs()) {
            attempts += 1.0;
            if attempts > nominal + MAX_EXTRA_SUBSTEPS {
                return Err(fail(
                    self.state.t,
                    format!(
                        "the step size control gave up after {} internal step attempts ({nominal} nominal) at t = {:.9} s (inputs or parameters that change too violently for the integrator); use shorter communication steps or smoother inputs",
                        attempts - 1.0,
                        self.state.t
                    ),
                ));
            }
            let remaining = t_end - self.state.t;
            let n_left = (remaining / h_limit - 1e-9).ceil().max(1.0);
            let h = if adaptive && n_left > 1.0 {
                // keep the proposed step; leave no sliver at the end
                if remaining < 1.5 * h_limit {
                    0.5 * remaining
                } else {
                    h_limit
                }
            } else {
                remaining / n_left
            };
            let last = h >= remaining;
            let res = self.cfg.integrator.step(
                self.model.as_mut(),
                &mut self.ws,
                &self.cfg.newton,
                constant_mass,
                &self.state,
                h,
                &mut self.trial,
            );
            let failure = match res {
                Ok(s) => {
                    self.stats.newton += s;
                    let mut factor = None;
                    let mut grow = true;
                    if self.cfg.integrator.error_estimate(
                        &self.state,
                        &self.trial,
                        h,
                        &mut self.err,
                    ) {
                        let raw = scaled_max(&self.err, 1.0, &self.ws.error_scales);
                        if adaptive {
                            let e = raw / self.cfg.tolerance;
                            factor = Some((0.9 * e.max(1e-10).powf(-1.0 / 3.0)).clamp(0.2, 2.0));
                            if e > 1.0 && h > h_min {
                                self.stats.rejected += 1;
                                self.stats.rejected_error += 1;
                                self.record_rejection(h, None, true);
                                h_limit = h * factor.unwrap_or(0.5);
                                continue;
                            }
                            if e > 1.0 {
                                // Accepting steps of h_min with the error above the
                                // tolerance would report fmi2OK for what was not delivered
                                // (and take ~1e9 steps per communication step).
                                return Err(fail(
                                    self.state.t,
                                    format!(
                                        "the local error {raw:.3e} exceeds solver.tolerance = {:.3e} even at the smallest internal step {h:.3e} s (t = {:.9} s)",
                                        self.cfg.tolerance, self.state.t
                                    ),
                                ));
                            }
                        }
                        if (raw > SAFETY_ERROR || raw.is_nan()) && h > h_min {
                            self.stats.rejected += 1;
                            self.stats.rejected_error += 1;
                            self.record_rejection(h, None, true);
                            h_limit = 0.5 * h;
                            continue;
                        }
                        // The estimate is h² (β − 1/6) Δa and Δa grows with h: doubling the
                        // step multiplies it by about 8. Grow only when the doubled step would
                        // pass the safety check (else every communication step would try the
                        // step that the check rejects).
                        grow = 8.0 * raw <= SAFETY_ERROR;
                    }
                    self.stats.steps += 1;
                    if last {
                        self.trial.t = t_end;
                    }
                    std::mem::swap(&mut self.state, &mut self.trial);
                    self.model.accept(&mut self.state);
                    h_limit = match factor {
                        Some(f) => (h * f).min(h_max),
                        // grow back towards the nominal step after a cut
                        None if grow => (2.0 * h_limit).min(h_max),
                        None => h_limit,
                    };
                    if !last || !adaptive {
                        self.h_next = h_limit;
                    }
                    None
                }
                Err(e) => Some(e.to_string()),
            };
            if let Some(e) = failure {
                self.stats.rejected += 1;
                if self.rejections.is_some() {
                    self.record_rejection(h, Some(e.clone()), false);
                }
                h_limit = 0.5 * h;
                if h_limit < h_min {
                    return Err(fail(
                        self.state.t,
                        format!(
                            "time step failed at t = {:.9} s with the substep cut to {:.3e} s: {e}",
                            self.state.t, h
                        ),
                    ));
                }
            }
        }
        self.state.t = t_end;
        if self
            .state
            .q
            .iter()
            .chain(&self.state.v)
            .any(|x| !x.is_finite())
        {
            return Err(fail(self.state.t, "non-finite state".into()));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::GeneralizedAlpha;
    use crate::linalg::CscPattern;
    use crate::model::{MechanicalSystem, ModelError};

    /// A unit mass on a unit spring whose force evaluation breaks down after `t_fail`.
    struct Oscillator {
        pattern: CscPattern,
        scales: Vec<f64>,
        t_fail: f64,
        q: f64,
        v: f64,
        /// what `input_restarts_accelerations` answers
        restarts: bool,
        /// residual calls with the mass matrix alone: the acceleration restarts
        restart_calls: usize,
    }

    impl MechanicalSystem for Oscillator {
        fn n_free(&self) -> usize {
            1
        }
        fn pattern(&self) -> &CscPattern {
            &self.pattern
        }
        fn scales(&self) -> &[f64] {
            &self.scales
        }
        fn residual(
            &mut self,
            t: f64,
            q: &[f64],
            _v: &[f64],
            a: &[f64],
            _l: f64,
            r: &mut [f64],
            jac: Option<(JacobianCoeffs, &mut [f64])>,
        ) -> Result<(), ModelError> {
            if t > self.t_fail {
                return Err(ModelError::NonFinite);
            }
            r[0] = a[0] + q[0];
            if let Some((c, j)) = jac {
                if c.stiffness == 0.0 && c.damping == 0.0 {
                    self.restart_calls += 1;
                }
                j[0] = c.mass + c.stiffness;
            }
            Ok(())
        }
        fn midpoint_residual(
            &mut self,
            _ta: f64,
            t: f64,
            _qa: &[f64],
            qb: &[f64],
            v: &[f64],
            a: &[f64],
            r: &mut [f64],
            jac: Option<(JacobianCoeffs, &mut [f64])>,
        ) -> Result<(), ModelError> {
            self.residual(t, qb, v, a, 1.0, r, jac)
        }
    }

    impl Model for Oscillator {
        fn set_input(&mut self, _k: usize, _v: f64) {}
        fn output(&self, _k: usize) -> f64 {
            self.q
        }
        fn accept(&mut self, s: &mut DynState) {
            self.q = s.q[0];
            self.v = s.v[0];
        }
        fn free_state(&self, q: &mut [f64], v: &mut [f64]) {
            q[0] = self.q;
            v[0] = self.v;
        }
        fn set_input_derivative(&mut self, _k: usize, _o: usize, _v: f64) -> Result<(), String> {
            Ok(())
        }
        fn input_restarts_accelerations(&self, _input: usize) -> bool {
            self.restarts
        }
        fn output_derivative(&self, _k: usize) -> Option<f64> {
            Some(self.v)
        }
        fn save(&self, w: &mut crate::snapshot::StateWriter) -> Result<(), String> {
            w.f64(self.q);
            w.f64(self.v);
            Ok(())
        }
        fn restore(&mut self, r: &mut crate::snapshot::StateReader) -> Result<(), String> {
            self.q = r.f64().map_err(|e| e.to_string())?;
            self.v = r.f64().map_err(|e| e.to_string())?;
            Ok(())
        }
    }

    fn sim(t_fail: f64) -> Simulation {
        sim_with(t_fail, true)
    }

    fn sim_with(t_fail: f64, restarts: bool) -> Simulation {
        let model = Oscillator {
            pattern: CscPattern::from_entries(1, []),
            scales: vec![1.0],
            t_fail,
            q: 1.0,
            v: 0.0,
            restarts,
            restart_calls: 0,
        };
        let cfg = SolverConfig {
            integrator: Integrator::GeneralizedAlpha(GeneralizedAlpha::newmark()),
            max_step: 1e-2,
            newton: NewtonSettings {
                tolerance: 1e-12,
                max_iterations: 10,
                policy: NewtonPolicy::Full,
                line_search: false,
            },
            tolerance: 0.0,
            static_equilibrium: false,
            load_steps: 1,
            linear: SolverKind::Auto,
        };
        let mut s = Simulation::new(Box::new(model), cfg, 0.0).unwrap();
        s.initialize().unwrap();
        s
    }

    /// Newmark on q'' = -q: the phase error is O(h^2), amplitude exact.
    #[test]
    fn oscillator_follows_cos_t() {
        let mut s = sim(f64::INFINITY);
        s.advance(1.0).unwrap();
        let q = s.output(0);
        assert!((q - 1f64.cos()).abs() < 1e-4, "{q} vs {}", 1f64.cos());
        assert_eq!(s.time(), 1.0);
    }

    /// A step that cannot be completed stops at the last accepted substep.
    #[test]
    fn failure_keeps_the_last_good_state() {
        let mut s = sim(0.255);
        let err = s.advance(1.0).unwrap_err();
        assert!(
            err.reached <= 0.255 && err.reached > 0.25,
            "{}",
            err.reached
        );
        assert_eq!(s.time(), err.reached);
        let q = s.output(0);
        assert!((q - err.reached.cos()).abs() < 1e-4);
        assert!(err.message.contains("non-finite"), "{}", err.message);
    }

    /// An input derivative restarts the accelerations exactly when a new input value would
    /// (`Model::input_restarts_accelerations`): a master that interpolates inputs
    /// (`canInterpolateInputs`, `fmi2SetRealInputDerivatives` at every communication step)
    /// must not make a model whose inputs are smooth motions re-solve its accelerations at
    /// every step (it did: the ALE serpentine at 2 ms communication steps iterated 3x more).
    #[test]
    fn input_derivatives_restart_accelerations_only_when_the_model_asks() {
        for restarts in [false, true] {
            let mut s = sim_with(f64::INFINITY, restarts);
            let start = s.model_as::<Oscillator>().unwrap().restart_calls;
            for k in 1..=5 {
                s.set_input_derivative(0, 1, 0.5).unwrap();
                s.advance(0.01 * k as f64).unwrap();
            }
            let calls = s.model_as::<Oscillator>().unwrap().restart_calls - start;
            assert_eq!(calls, if restarts { 5 } else { 0 }, "restarts {restarts}");
        }
    }
}
