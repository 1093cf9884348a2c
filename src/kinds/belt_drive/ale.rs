//! The axially moving (ALE) belt of the belt-drive kind (`belt.formulation = "ale"`, issue 12
//! item 2, design note "ale", prototype `scripts/ale_prototype.py`): IN PROGRESS.
//!
//! What exists: the parameter `belt.formulation` (`"lagrangian"` = 1, the default, and
//! `"ale"` = 2) and [`check`], the refusal of the scenes the ALE model will not cover. A scene
//! that passes [`check`] is still refused by [`BeltDrive::build`](super::model::BeltDrive::build)
//! until the model exists.
//!
//! The model (step 3 of the plan, not written yet), as the prototype measured it:
//! * unknowns: the ring mesh `q` (cable nodes fixed in space, the loop's shape; `4 n` coordinates)
//!   and the belt speed `v` (one extra unknown, `s` its integral, `x = X + s`);
//! * gauge: node 0 is held along its own tangent (one row), since the mesh has a sliding mode
//!   (moving the nodes along the loop does not change the shape); the equation of `v` is the
//!   projection of the q-equations on that sliding mode (a separately discretized s-equation
//!   left a spurious drag of 0.8 N in the prototype);
//! * residual: elements + `ancf_cable2d::ale_inertia_into` + `AncfCable2d::convective_damping_into`
//!   − contact at the fixed mesh points, whose friction history is transported from upstream
//!   (`contact::ale_transport::{upstream, transported_history, history_rate}`), the points
//!   `m = n · points_per_element` equally spaced by `w = l / points_per_element` round the loop;
//! * Jacobian: the banded q-block, a dense `v` column and the gauge row: the bordered banded
//!   solver (`linalg::bordered`);
//! * FMU state: the Lagrangian state plus `v`, `s` and the committed mesh `q_n` (the history's
//!   `dir` reads the committed field upstream).

use super::BeltDriveScene;
use super::PulleySide;
use super::scene::names::{BELT_DAMPING_BENDING, BELT_ELEMENT, BELT_FORMULATION};
use crate::scene::ParamValues;
use crate::scene::params::names::{GRAVITY_X, GRAVITY_Y};
use crate::variables::Value;

/// Code of `belt.formulation = "ale"`.
pub const ALE: i32 = 2;

/// Whether the parameters ask for the ALE belt (a missing `belt.formulation` is Lagrangian).
pub fn requested(p: &ParamValues) -> bool {
    matches!(p.get(BELT_FORMULATION), Some(Value::Integer(ALE)))
}

/// The reasons the ALE belt cannot model this scene with these parameters, each naming the key
/// (empty: the scene is within the ALE model's scope). The scope is the prototype's: a closed
/// cable belt on front-side pulleys, no tensioner, no gravity, no bending damping (the
/// convective rate of the bending damping is not in the kernel), contact points equally spaced
/// round the loop (the history transport interpolates between neighbours spaced by `w`; the
/// belt-drive kind places `contact.points_per_element` points equally spaced in equal
/// elements, so this holds by construction, and the belt-drive scene always closes the belt).
pub fn check(scene: &BeltDriveScene, p: &ParamValues) -> Vec<String> {
    let mut errs = Vec::new();
    let why = "belt.formulation = \"ale\"";
    if scene.tensioner.is_some() {
        errs.push(format!(
            "[tensioner]: {why} does not model a tensioner yet (use \"lagrangian\")"
        ));
    }
    for (i, s) in scene.pulley.iter().enumerate() {
        if s.side == PulleySide::Back {
            errs.push(format!(
                "pulley[{i}] (pulley{}).side = \"back\": {why} does not model back-side idlers yet",
                i + 1
            ));
        }
    }
    for key in [GRAVITY_X, GRAVITY_Y] {
        if let Some(Value::Real(g)) = p.get(key)
            && g != 0.0
        {
            errs.push(format!(
                "{key} = {g}: {why} does not model gravity yet (the belt's weight)"
            ));
        }
    }
    if let Some(Value::Integer(e)) = p.get(BELT_ELEMENT)
        && e != 1
    {
        errs.push(format!(
            "{BELT_ELEMENT} = {e}: {why} needs the ANCF cable (1); the shear element has no ALE terms"
        ));
    }
    if let Some(Value::Real(d)) = p.get(BELT_DAMPING_BENDING)
        && d != 0.0
    {
        errs.push(format!(
            "{BELT_DAMPING_BENDING} = {d}: {why} needs 0 (the convective bending-damping rate v K' is not modelled)"
        ));
    }
    errs
}

use crate::elements::ancf_cable2d::{
    AleBand, AleInertiaTangent, AleRates, AncfCable2d, CableRule, CableSection, ElemMat, ElemVec,
    ale_band, ale_inertia_into,
};

/// The belt of the ALE model without its contact: a closed ring of `n` equal ANCF cable
/// elements whose mesh stands on the loop's shape (element `e` joins nodes `e` and `e + 1`
/// round the loop; node `k` holds `(x, y, x', y')` at coordinates `4k..4k + 4`). Its
/// q-equations are `Q_int(q, q̇) + f_v(q, v) + M q̈ + v̇ G q + 2 v G q̇ − v² H q` (the element
/// forces, the convective axial damping and the ALE inertia, see `ancf_cable2d`); the model
/// adds the contact at the fixed mesh points, the gauge row and the equation of `v`.
/// Building block of step 3 (no scene uses it yet).
#[derive(Clone, Debug)]
pub struct AleRing {
    n: usize,
    cable: AncfCable2d,
    band: AleBand,
    mass: ElemMat,
}

impl AleRing {
    /// A ring of `n` elements of reference length `l` [m].
    pub fn new(n: usize, l: f64, section: CableSection, rule: CableRule) -> Self {
        let cable = AncfCable2d::new(l, section, rule);
        Self {
            n,
            band: ale_band(l, section.mass_per_length),
            mass: cable.mass(),
            cable,
        }
    }

    /// Number of mesh coordinates (`4 n`).
    pub fn n_coords(&self) -> usize {
        4 * self.n
    }

    /// Global index of local coordinate `i` (0..8) of element `e`.
    fn index(&self, e: usize, i: usize) -> usize {
        if i < 4 {
            4 * e + i
        } else {
            4 * ((e + 1) % self.n) + i - 4
        }
    }

    fn gather(&self, x: &[f64], e: usize) -> ElemVec {
        ElemVec::from_fn(|i, _| x[self.index(e, i)])
    }

    /// The q-equations without contact at mesh coordinates `q`, their rates `qd`, `qdd` and the
    /// belt speed and acceleration, written into `r` (`4 n`) [N].
    pub fn residual_into(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        rates: AleRates,
        r: &mut [f64],
    ) {
        r.iter_mut().for_each(|x| *x = 0.0);
        let (mut f, mut fi) = (ElemVec::zeros(), ElemVec::zeros());
        for e in 0..self.n {
            let (qe, qde, qdde) = (self.gather(q, e), self.gather(qd, e), self.gather(qdd, e));
            self.cable.internal_force(&qe, &qde, &mut f);
            self.cable
                .convective_damping_into(&qe, rates.v, &mut f, None);
            ale_inertia_into(
                &self.mass, &self.band, &qe, &qde, &qdde, rates, &mut fi, None,
            );
            for i in 0..8 {
                r[self.index(e, i)] += f[i] + fi[i];
            }
        }
    }

    /// Tangent of [`Self::residual_into`]: calls `add(row, col, value)` with the entries of
    /// `∂r/∂q + a_qd ∂r/∂q̇ + a_qdd ∂r/∂q̈` (the integrator's coefficients, element by element,
    /// repeated indices to be summed) and writes `∂r/∂v` into `dv`, `∂r/∂v̇` into `dv_dot`.
    #[allow(clippy::too_many_arguments)]
    pub fn tangent(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        rates: AleRates,
        (a_qd, a_qdd): (f64, f64),
        mut add: impl FnMut(usize, usize, f64),
        dv: &mut [f64],
        dv_dot: &mut [f64],
    ) {
        dv.iter_mut().for_each(|x| *x = 0.0);
        dv_dot.iter_mut().for_each(|x| *x = 0.0);
        let (mut f, mut fi, mut fdv) = (ElemVec::zeros(), ElemVec::zeros(), ElemVec::zeros());
        let (mut k, mut c) = (ElemMat::zeros(), ElemMat::zeros());
        let mut t = AleInertiaTangent::default();
        for e in 0..self.n {
            let (qe, qde, qdde) = (self.gather(q, e), self.gather(qd, e), self.gather(qdd, e));
            k.fill(0.0);
            c.fill(0.0);
            f.fill(0.0);
            self.cable
                .internal_force_tangent(&qe, &qde, &mut f, &mut k, &mut c);
            self.cable
                .convective_damping_into(&qe, rates.v, &mut f, Some((&mut k, &mut fdv)));
            ale_inertia_into(
                &self.mass,
                &self.band,
                &qe,
                &qde,
                &qdde,
                rates,
                &mut fi,
                Some(&mut t),
            );
            for i in 0..8 {
                let gi = self.index(e, i);
                dv[gi] += fdv[i] + t.dv[i];
                dv_dot[gi] += t.dv_dot[i];
                for j in 0..8 {
                    let val = k[(i, j)]
                        + t.k[(i, j)]
                        + a_qd * (c[(i, j)] + t.c[(i, j)])
                        + a_qdd * self.mass[(i, j)];
                    if val != 0.0 {
                        add(gi, self.index(e, j), val);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn section(ei: f64) -> CableSection {
        CableSection {
            ea: 5e4,
            ei,
            mass_per_length: 0.15,
            damping_axial: 20.0,
            damping_bending: 0.0,
            prestrain: 0.0,
        }
    }

    /// Mesh of a circle of radius `r` with slopes of length `sigma` (nodes at `2πk/n`).
    fn circle(n: usize, r: f64, sigma: f64) -> Vec<f64> {
        let mut q = vec![0.0; 4 * n];
        for k in 0..n {
            let a = 2.0 * PI * k as f64 / n as f64;
            let (s, c) = a.sin_cos();
            q[4 * k..4 * k + 4].copy_from_slice(&[r * c, r * s, -sigma * s, sigma * c]);
        }
        q
    }

    /// A free ring running at belt speed v stands still in the mesh when its hoop force carries
    /// the material's centripetal force: `ρA v² (1 + ε) = N = EA ε` (per reference length,
    /// `|r'| = 1 + ε`), so `ε = ρA v²/(EA − ρA v²)`; at rest (v = 0) it keeps its length.
    #[test]
    fn a_free_ring_running_at_speed_v_stretches_by_the_centripetal_hoop_force() {
        let (n, r0) = (60, 0.25);
        let l = 2.0 * PI * r0 / n as f64;
        let ring = AleRing::new(n, l, section(1e-6), CableRule::Full);
        let zero = vec![0.0; 4 * n];
        let mut r = vec![0.0; 4 * n];
        for v in [0.0, 30.0] {
            let rates = AleRates { v, v_dot: 0.0 };
            // by symmetry two unknowns (radius, slope length) and two residuals (radial
            // force on the positions, tangential on the slopes)
            let mut res = |x: [f64; 2]| {
                ring.residual_into(&circle(n, x[0], x[1]), &zero, &zero, rates, &mut r);
                let (mut fr, mut fs) = (0.0, 0.0);
                for k in 0..n {
                    let (s, c) = (2.0 * PI * k as f64 / n as f64).sin_cos();
                    fr += r[4 * k] * c + r[4 * k + 1] * s;
                    fs += -r[4 * k + 2] * s + r[4 * k + 3] * c;
                }
                [fr / n as f64, fs / n as f64]
            };
            let mut x = [r0, 1.0];
            for _ in 0..20 {
                let f = res(x);
                let h = 1e-9;
                let (fa, fb) = (res([x[0] + h, x[1]]), res([x[0], x[1] + h]));
                let j = [
                    [(fa[0] - f[0]) / h, (fb[0] - f[0]) / h],
                    [(fa[1] - f[1]) / h, (fb[1] - f[1]) / h],
                ];
                let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
                x[0] -= (j[1][1] * f[0] - j[0][1] * f[1]) / det;
                x[1] -= (-j[1][0] * f[0] + j[0][0] * f[1]) / det;
            }
            let f = res(x);
            assert!(
                f[0].abs() < 1e-8 && f[1].abs() < 1e-8,
                "not converged: {f:?}"
            );
            let ra = 0.15 * v * v;
            let expected = ra / (5e4 - ra);
            let (eps_slope, eps_radius) = (x[1] - 1.0, x[0] / r0 - 1.0);
            assert!(
                (eps_slope - expected).abs() < 1e-3 * expected + 1e-6,
                "v = {v}: slope strain {eps_slope:e}, expected {expected:e}"
            );
            assert!(
                (eps_radius - expected).abs() < 1e-3 * expected + 1e-6,
                "v = {v}: radius strain {eps_radius:e}, expected {expected:e}"
            );
        }
    }

    /// The tangent against central differences of the residual, on a perturbed, moving mesh.
    #[test]
    fn the_ring_tangent_matches_finite_differences() {
        let (n, r0) = (8, 0.2);
        let l = 2.0 * PI * r0 / n as f64;
        let ring = AleRing::new(n, l, section(0.05), CableRule::Full);
        let m = 4 * n;
        let wave =
            |a: f64, b: f64| -> Vec<f64> { (0..m).map(|i| a * ((i as f64) * b).sin()).collect() };
        let q: Vec<f64> = circle(n, r0 * 1.01, 1.02)
            .iter()
            .zip(wave(2e-3, 1.3))
            .map(|(x, d)| x + d)
            .collect();
        let (qd, qdd) = (wave(0.3, 0.7), wave(5.0, 2.1));
        let rates = AleRates { v: 7.0, v_dot: 3.0 };
        let (a_qd, a_qdd) = (1e3, 1e6);
        let mut jac = vec![0.0; m * m];
        let (mut dv, mut dvd) = (vec![0.0; m], vec![0.0; m]);
        ring.tangent(
            &q,
            &qd,
            &qdd,
            rates,
            (a_qd, a_qdd),
            |i, j, x| jac[i * m + j] += x,
            &mut dv,
            &mut dvd,
        );
        let (mut rp, mut rm) = (vec![0.0; m], vec![0.0; m]);
        let mut scale = 0.0f64;
        let mut worst = 0.0f64;
        for j in 0..m {
            let h = 1e-7;
            // one column: q, qd, qdd moved together as the integrator couples them
            let shift = |x: &[f64], s: f64| -> Vec<f64> {
                let mut y = x.to_vec();
                y[j] += s;
                y
            };
            ring.residual_into(
                &shift(&q, h),
                &shift(&qd, a_qd * h),
                &shift(&qdd, a_qdd * h),
                rates,
                &mut rp,
            );
            ring.residual_into(
                &shift(&q, -h),
                &shift(&qd, -a_qd * h),
                &shift(&qdd, -a_qdd * h),
                rates,
                &mut rm,
            );
            for i in 0..m {
                let fd = (rp[i] - rm[i]) / (2.0 * h);
                scale = scale.max(fd.abs());
                worst = worst.max((fd - jac[i * m + j]).abs());
            }
        }
        assert!(worst < 1e-6 * scale, "q column: {worst:e} of {scale:e}");
        for (which, d) in [(0, &dv), (1, &dvd)] {
            // the residual is quadratic in v and linear in v̇: central differences are exact
            let h = 1.0;
            let moved = |s: f64| {
                let mut r = rates;
                if which == 0 {
                    r.v += s;
                } else {
                    r.v_dot += s;
                }
                r
            };
            ring.residual_into(&q, &qd, &qdd, moved(h), &mut rp);
            ring.residual_into(&q, &qd, &qdd, moved(-h), &mut rm);
            let s = d.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            for i in 0..m {
                let fd = (rp[i] - rm[i]) / (2.0 * h);
                assert!(
                    (fd - d[i]).abs() < 1e-6 * s.max(1e-12),
                    "d/d{}[{i}]: {fd} against {}",
                    ["v", "v_dot"][which],
                    d[i]
                );
            }
        }
    }
}
