//! The simulation driver: static initialization, consistent initial accelerations, and the
//! advance over a communication step with internal substeps that are halved when Newton fails.

use super::newton::{NewtonSettings, NewtonStats, Workspace};
use super::statics;
use crate::integrators::{DynState, Integrator};
use crate::linalg::SolverKind;
use crate::model::{JacobianCoeffs, Model};
use crate::scene::params::{ParamValues, names::*};
use crate::variables::{InputKind, OutputKind};

/// Substeps may be halved this many times below `solver.max_step` before a communication step
/// is given up.
pub const MAX_HALVINGS: u32 = 30;

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
            },
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
    /// Rejected internal steps (Newton failures).
    pub rejected: usize,
    /// Newton work.
    pub newton: NewtonStats,
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
    pub fn new(model: Box<dyn Model>, cfg: SolverConfig, t0: f64) -> Result<Self, String> {
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
        self.restart_accelerations()?;
        self.model.accept(&mut self.state);
        Ok(report)
    }

    /// Solves `M acc = f_ext − f_int(q, v)` at the current state and restarts the algorithmic
    /// acceleration (used at initialization and when inputs jump).
    fn restart_accelerations(&mut self) -> Result<(), String> {
        let n = self.state.q.len();
        self.trial.a.iter_mut().for_each(|x| *x = 0.0);
        let coeffs = JacobianCoeffs {
            mass: 1.0,
            damping: 0.0,
            stiffness: 0.0,
        };
        self.model
            .residual(
                self.state.t,
                &self.state.q,
                &self.state.v,
                &self.trial.a,
                1.0,
                &mut self.ws.r,
                Some((coeffs, &mut self.ws.jac)),
            )
            .map_err(|e| e.to_string())?;
        self.ws
            .solver
            .factor(&self.ws.pattern, &self.ws.jac)
            .map_err(|e| format!("mass matrix: {e}"))?;
        for i in 0..n {
            self.state.acc[i] = -self.ws.r[i];
        }
        self.ws.solver.solve_in_place(&mut self.state.acc);
        if self.state.acc.iter().any(|x| !x.is_finite()) {
            return Err("initial accelerations are not finite".into());
        }
        self.state.a.copy_from_slice(&self.state.acc);
        self.inputs_changed = false;
        Ok(())
    }

    /// Sets an input; takes effect at the next advance (held constant over it).
    pub fn set_input(&mut self, kind: InputKind, value: f64) {
        self.model.set_input(kind, value);
        if self.model.input_restarts_accelerations(kind) {
            self.inputs_changed = true;
        }
    }

    /// Current time [s].
    pub fn time(&self) -> f64 {
        self.state.t
    }

    /// An output of the current state.
    pub fn output(&self, kind: OutputKind) -> f64 {
        self.model.output(kind)
    }

    /// Work counters so far.
    pub fn stats(&self) -> RunStats {
        self.stats
    }

    /// Current solver settings.
    pub fn config(&self) -> &SolverConfig {
        &self.cfg
    }

    /// Changes the tunable settings (step size, Newton settings).
    pub fn set_tunables(&mut self, max_step: f64, newton: NewtonSettings) {
        self.cfg.max_step = max_step;
        self.cfg.newton = newton;
    }

    /// The model.
    pub fn model(&self) -> &dyn Model {
        self.model.as_ref()
    }

    /// Advances to `t_end` with substeps of at most `solver.max_step`, halving a substep when
    /// Newton fails. On failure the state stays at the last accepted substep.
    pub fn advance(&mut self, t_end: f64) -> Result<(), AdvanceError> {
        self.model.begin_communication_step(self.state.t, t_end);
        if self.inputs_changed {
            self.restart_accelerations()
                .map_err(|message| AdvanceError {
                    reached: self.state.t,
                    message,
                })?;
        }
        let h_max = self.cfg.max_step;
        let mut h_limit = h_max;
        let h_min = h_max * 0.5f64.powi(MAX_HALVINGS as i32);
        let span = (t_end - self.state.t).abs().max(f64::MIN_POSITIVE);
        while t_end - self.state.t > 1e-12 * span.max(t_end.abs()) {
            let remaining = t_end - self.state.t;
            let n_left = (remaining / h_limit - 1e-9).ceil().max(1.0);
            let h = remaining / n_left;
            let last = n_left == 1.0;
            let res = self.cfg.integrator.step(
                self.model.as_mut(),
                &mut self.ws,
                &self.cfg.newton,
                &self.state,
                h,
                &mut self.trial,
            );
            match res {
                Ok(s) => {
                    self.stats.newton += s;
                    self.stats.steps += 1;
                    if last {
                        self.trial.t = t_end;
                    }
                    std::mem::swap(&mut self.state, &mut self.trial);
                    self.model.accept(&mut self.state);
                    // Grow back towards the nominal step after a cut.
                    if h_limit < h_max {
                        h_limit = (2.0 * h_limit).min(h_max);
                    }
                }
                Err(e) => {
                    self.stats.rejected += 1;
                    h_limit = 0.5 * h;
                    if h_limit < h_min {
                        return Err(AdvanceError {
                            reached: self.state.t,
                            message: format!(
                                "time step failed at t = {:.9} s with the substep cut to {:.3e} s: {e}",
                                self.state.t, h
                            ),
                        });
                    }
                }
            }
        }
        self.state.t = t_end;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::GeneralizedAlpha;
    use crate::linalg::CscPattern;
    use crate::model::{MechanicalSystem, ModelError};
    use crate::variables::{EnergyKind, OutputKind};

    /// A unit mass on a unit spring whose force evaluation breaks down after `t_fail`.
    struct Oscillator {
        pattern: CscPattern,
        scales: Vec<f64>,
        t_fail: f64,
        q: f64,
        v: f64,
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
                j[0] = c.mass + c.stiffness;
            }
            Ok(())
        }
        fn midpoint_residual(
            &mut self,
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
        fn set_input(&mut self, _k: InputKind, _v: f64) {}
        fn output(&self, _k: OutputKind) -> f64 {
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
    }

    fn sim(t_fail: f64) -> Simulation {
        let model = Oscillator {
            pattern: CscPattern::from_entries(1, []),
            scales: vec![1.0],
            t_fail,
            q: 1.0,
            v: 0.0,
        };
        let cfg = SolverConfig {
            integrator: Integrator::GeneralizedAlpha(GeneralizedAlpha::newmark()),
            max_step: 1e-2,
            newton: NewtonSettings {
                tolerance: 1e-12,
                max_iterations: 10,
            },
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
        let q = s.output(OutputKind::Energy(EnergyKind::Total));
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
        let q = s.output(OutputKind::Energy(EnergyKind::Total));
        assert!((q - err.reached.cos()).abs() < 1e-4);
        assert!(err.message.contains("non-finite"), "{}", err.message);
    }
}
