//! Quasi-static stepping: the equilibrium `f_int(q₁, v₁) − f_ext(t₁) = 0` at the end of every
//! step, without inertia, with the backward-Euler velocity `v₁ = (q₁ − q₀)/h` for the forces
//! that depend on rates (contact damping, friction, a gas law that exchanges heat over the
//! step). For bodies whose own inertia is far below that of what they connect and whose
//! supports hold them statically (the air spring's bellows between two plates: its lowest
//! membrane mode lies far above the vehicle's frequencies), a sequence of static solves, each
//! starting from the last and the model's predictor: no membrane modes to ring and no
//! transients to follow, so that most steps converge in one Newton iteration. Only models that
//! say they are statically supported accept it ([`MechanicalSystem::set_quasi_static`]).

use super::state::DynState;
use crate::model::{JacobianCoeffs, MechanicalSystem};
use crate::snapshot::{SnapshotError, StateReader, StateWriter};
use crate::solver::newton::{self, NewtonError, NewtonSettings, NewtonStats, Workspace};

/// The quasi-static scheme (`solver.integrator = "quasi_static"`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct QuasiStatic;

impl QuasiStatic {
    /// Advances `s0` by `h` into `s1` (unknown: the coordinates; accelerations stay zero).
    /// The predictor is `q₀ + h v₀` or the model's own ([`MechanicalSystem::predict`]).
    pub fn step(
        &self,
        sys: &mut dyn MechanicalSystem,
        ws: &mut Workspace,
        settings: &NewtonSettings,
        s0: &DynState,
        h: f64,
        s1: &mut DynState,
    ) -> Result<NewtonStats, NewtonError> {
        let t1 = s0.t + h;
        // r(q₁) with v₁ = (q₁ − q₀)/h: ∂r/∂q₁ = K + C/h
        let coeffs = JacobianCoeffs {
            mass: 0.0,
            damping: 1.0 / h,
            stiffness: 1.0,
        };
        let mut q = std::mem::take(&mut s1.q);
        for i in 0..q.len() {
            q[i] = s0.q[i] + h * s0.v[i];
        }
        if sys.predict(&s0.q, &s0.v, h, &mut q) && !sys.prediction_keeps_matrix() {
            ws.invalidate();
        }
        s1.a.fill(0.0);
        s1.acc.fill(0.0);
        let (v, a) = (&mut s1.v, &s1.a);
        let res = newton::solve(ws, &mut q, settings, 1.0, coeffs, |x, r, jac| {
            for i in 0..x.len() {
                v[i] = (x[i] - s0.q[i]) / h;
            }
            let built = jac.is_some();
            sys.residual(t1, x, v, a, 1.0, r, jac.map(|j| (coeffs, j)))?;
            Ok(sys.matrix_state(built))
        });
        for i in 0..q.len() {
            s1.v[i] = (q[i] - s0.q[i]) / h;
        }
        s1.q = q;
        s1.t = t1;
        res
    }
}

/// Quadratic Lagrange weights `[l_a, l_b, l_c]` of the nodes `x = [a, b, c]` at `x1`
/// (`Σ l = 1`; extrapolation when `x1` lies outside the nodes).
pub fn lagrange3(x: [f64; 3], x1: f64) -> [f64; 3] {
    let [a, b, c] = x;
    [
        (x1 - b) * (x1 - c) / ((a - b) * (a - c)),
        (x1 - a) * (x1 - c) / ((b - a) * (b - c)),
        (x1 - a) * (x1 - b) / ((c - a) * (c - b)),
    ]
}

/// A quasi-static predictor in time for models whose coordinates are increments in a chart
/// that moves with every commit (node rotations absorbed into stored orientations): the
/// step's increment extrapolated quadratically through the last two steps' increments.
///
/// With the backward-Euler velocities of quasi-static steps the increment of the last step
/// is `Δ_a = (t_a − t_b) v_a` and of the one before `Δ_b = (t_b − t_c) v_b`; the quadratic
/// Lagrange extrapolation through the commits at `t_a > t_b > t_c` to `t_1 = t_a + h` with
/// weights `l_a + l_b + l_c = 1` gives `q_1 − q_a = (l_a − 1) Δ_a − l_c Δ_b` (with equal
/// steps `2 Δ_a − Δ_b`: exact for a motion quadratic in time, against the integrator's
/// `q_0 + h v_0`, exact only for a linear one).
#[derive(Clone, Debug, Default)]
pub struct StepTrend {
    /// Times of the last three commits, newest first [s].
    t: [f64; 3],
    /// Backward-Euler velocities of the last step and of the one before.
    v_last: Vec<f64>,
    v_prev: Vec<f64>,
    /// How many of the commits in `t` are valid (0 … 3).
    n: usize,
}

impl StepTrend {
    /// An empty history over `n_free` coordinates.
    pub fn new(n_free: usize) -> Self {
        Self {
            t: [0.0; 3],
            v_last: vec![0.0; n_free],
            v_prev: vec![0.0; n_free],
            n: 0,
        }
    }

    /// Forgets the history (a new shape: a static solve, a restart).
    pub fn reset(&mut self) {
        self.n = 0;
    }

    /// Records the commit at `t` [s] with the step's velocities `v` (free coordinates).
    pub fn record(&mut self, t: f64, v: &[f64]) {
        if self.n > 0 && t <= self.t[0] {
            self.n = 0;
        }
        self.t.rotate_right(1);
        self.t[0] = t;
        std::mem::swap(&mut self.v_last, &mut self.v_prev);
        self.v_last.copy_from_slice(v);
        self.n = (self.n + 1).min(3);
    }

    /// Writes the prediction at `t0 + h` from the committed coordinates `q0` at `t0` into
    /// `q1` and returns true; false (and `q1` untouched) with fewer than three commits, when
    /// `t0` is not the last commit's time, or for a step more than three times the last
    /// spacings (after a halved substep the trend would overshoot).
    pub fn predict(&self, t0: f64, h: f64, q0: &[f64], q1: &mut [f64]) -> bool {
        let [ta, tb, tc] = self.t;
        if self.n < 3 || ta != t0 || !(ta > tb && tb > tc) || h > 3.0 * (ta - tb).min(tb - tc) {
            return false;
        }
        let [la, _, lc] = lagrange3(self.t, t0 + h);
        let (ca, cb) = ((la - 1.0) * (ta - tb), -lc * (tb - tc));
        for (((x, q), va), vb) in q1.iter_mut().zip(q0).zip(&self.v_last).zip(&self.v_prev) {
            *x = q + ca * va + cb * vb;
        }
        true
    }

    /// Writes the history into a snapshot.
    pub fn save(&self, w: &mut StateWriter) {
        w.u64(self.n as u64);
        w.f64s(&self.t);
        w.f64s(&self.v_last);
        w.f64s(&self.v_prev);
    }

    /// Reads a history written by [`Self::save`].
    pub fn restore(&mut self, r: &mut StateReader) -> Result<(), SnapshotError> {
        self.n = (r.u64()? as usize).min(3);
        r.f64s_into(&mut self.t)?;
        r.f64s_into(&mut self.v_last)?;
        r.f64s_into(&mut self.v_prev)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A motion quadratic in time is predicted exactly from the increments of two unequal
    /// steps, in any step; a linear one by the weights' sum.
    #[test]
    fn step_trend_extrapolates_a_quadratic_exactly() {
        let q = |t: f64| [1.0 + 2.0 * t - 3.0 * t * t, -0.5 * t];
        let ts = [0.0, 0.01, 0.015];
        let mut trend = StepTrend::new(2);
        let mut last = q(ts[0]);
        trend.record(ts[0], &[0.0, 0.0]);
        for w in ts.windows(2) {
            let next = q(w[1]);
            let v: Vec<f64> = (0..2)
                .map(|i| (next[i] - last[i]) / (w[1] - w[0]))
                .collect();
            trend.record(w[1], &v);
            last = next;
        }
        let mut q1 = [0.0; 2];
        assert!(
            !trend.predict(0.014, 0.004, &last, &mut q1),
            "not the last commit"
        );
        assert!(
            !trend.predict(0.015, 0.02, &last, &mut q1),
            "step too large"
        );
        assert!(trend.predict(0.015, 0.004, &last, &mut q1));
        let exact = q(0.019);
        for i in 0..2 {
            assert!(
                (q1[i] - exact[i]).abs() < 1e-14,
                "{i}: {} vs {}",
                q1[i],
                exact[i]
            );
        }
        // a repeated time forgets the history
        trend.record(0.015, &[0.0, 0.0]);
        assert!(!trend.predict(0.015, 0.004, &last, &mut q1));
        let mut w = StateWriter::default();
        trend.save(&mut w);
        let mut back = StepTrend::new(2);
        back.restore(&mut StateReader::new(&w.into_bytes()))
            .unwrap();
        assert_eq!(back.n, trend.n);
    }
}
