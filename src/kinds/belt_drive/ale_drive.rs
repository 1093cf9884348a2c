//! The ALE belt-drive model (`belt.formulation = "ale"`, issue 12 item 2): the mesh of the
//! closed cable belt stands on the loop's shape and the material flows through it at the belt
//! speed `v` (design note "ale", building blocks in [`super::ale`]).
//!
//! Free coordinates: the mesh `q` (`4 n`, node `k` at `4k..4k + 4`), the belt travel `s`
//! (reference length [m]; its velocity is the belt speed `v`, its acceleration `v̇`), then the
//! angles of the free pulleys. Equations: the ring's q-equations minus the contact at the fixed
//! mesh points ([`AleRing`], [`AlePoints::contact_into`]); the free pulleys'
//! `J θ̈ + c θ̇ − τ_in − τ_contact = 0`; and in the row of `s` the gauge of the mesh's sliding
//! mode: node 0 held along its committed unit tangent `t₀` by
//! `k_g t₀·(r₀ − r₀ₙ) + m_g t₀·r̈₀ = 0` (`k_g = EA/l`, `m_g` one element's mass: the small mass
//! term lets the consistent initial accelerations be solved; it moves node 0 along the loop by
//! `m_g/k_g` times its tangential acceleration per step, nanometres). The equation of `v` is
//! the projection of the q-equations on the sliding mode, which the gauge leaves to `s`.
//! Iteration matrix: the banded ring plus the dense columns of `s` and of the free pulleys and
//! the pulley rows (bordered banded LU, [`crate::linalg::bordered`]).
//!
//! The pulleys' inputs, the roles of the scene's inputs and outputs and the pulley results are
//! those of the Lagrangian [`BeltDrive`] the model was mounted from (its static pre-load is the
//! ALE model's initial mesh); the Lagrangian belt itself is not integrated.

use super::ale::{AleArm, AleHistory, AlePoints, AlePulley, AleRing, ArmTangent, ContactTangent};
use super::model::BeltDrive;
use super::pulleys::PulleyKind;
use super::scene::{BeltOutput, Output};
use crate::contact::ArmPulley;
use crate::contact::circle_friction::Circle;
use crate::elements::ancf_cable2d::{AleRates, CableRule, CableSection};
use crate::integrators::DynState;
use crate::kinds::energy::EnergyKind;
use crate::linalg::CscPattern;
use crate::model::{JacobianCoeffs, MechanicalSystem, Model, ModelError};
use crate::snapshot::{StateReader, StateWriter};
use nalgebra::{Vector2, Vector3};

/// Share of the belt speed by which the speed may move before a kept iteration matrix is
/// rebuilt ([`MechanicalSystem::kept_matrix_current`]).
pub const STALE_SPEED: f64 = 0.05;

/// Share of an accepted step in the running share of steps whose solution the
/// constant-velocity start came closer to ([`MechanicalSystem::predict`] of [`AleDrive`]) [1]:
/// a step's verdict alone flips the start back and forth on the serpentine's 0.5 s ramp
/// (3.85 iterations and 1.30 factorizations per step against 3.50 and 1.14 with 1/4).
pub const CV_MEMORY: f64 = 0.25;

/// The ALE belt drive (two or more pulleys on either face of the belt, a tensioner or none,
/// gravity or none).
#[derive(Clone, Debug)]
pub struct AleDrive {
    /// The Lagrangian drive it was mounted from: pulley inputs and results, roles, spans.
    base: BeltDrive,
    ring: AleRing,
    pts: AlePoints,
    section: CableSection,
    rule: CableRule,
    n: usize,
    /// Pulley index of each free-pulley coordinate (after `s`).
    free: Vec<usize>,
    /// The tensioner: its idler's pulley index, its free-pulley number, the arm's geometry
    /// and the index of the arm angle `ψ` among the free coordinates (after the pulleys).
    arm: Option<AleTensioner>,
    pattern: CscPattern,
    scales: Vec<f64>,
    newton_scales: Vec<f64>,
    /// Value positions of the ring's band: column `j`, rows of the nodes before, at and after
    /// `j`'s node (`12 j + 4 slot + component`; empty below 3 elements, where
    /// [`CscPattern::position`] searches).
    ring_pos: Vec<u32>,
    /// Value positions: column `s` (rows `0..4n`), the gauge row's `(s, 0)`, `(s, 1)`.
    col_s: Vec<usize>,
    gauge_pos: [usize; 2],
    /// Per free pulley: its column (rows `0..4n`), its row (columns `0..4n`), `(p, s)`, `(p, p)`.
    col_p: Vec<Vec<usize>>,
    row_p: Vec<Vec<usize>>,
    ps_pos: Vec<usize>,
    pp_pos: Vec<usize>,
    /// With a tensioner: column `ψ` (rows `0..4n`), row `ψ` (columns `0..4n`), `(ψ, s)`,
    /// `(ψ, θ)`, `(θ, ψ)` (θ the idler's angle) and `(ψ, ψ)`.
    col_a: Vec<usize>,
    row_a: Vec<usize>,
    arm_pos: [usize; 4],
    k_gauge: f64,
    m_gauge: f64,
    /// Free coordinates held during a static solve (the pre-load is the equilibrium).
    held: Option<Vec<f64>>,
    /// Belt speed at which the last iteration matrix was built [m/s].
    v_matrix: f64,
    // committed state
    t: f64,
    x: Vec<f64>,
    xd: Vec<f64>,
    xdd: Vec<f64>,
    hist: AleHistory,
    tensions: Vec<f64>,
    input_work: f64,
    p_in: f64,
    /// Energy dissipated since the start [J] and the dissipated power of the committed state
    /// (contact normal damping, bearings, belt material with its convective rate) [W].
    dissipated: f64,
    p_diss: f64,
    /// Penalty energy of the contact in the committed state [J].
    contact_energy: f64,
    /// Work done on the belt through its travel `s` since the start [J] (see
    /// [`Self::sliding_work`]), the momentum conjugate to `s`, `∂T/∂v` [N s], and the power
    /// `v Q_s` of the forces on `s` [W] of the committed state.
    sliding_work: f64,
    p_s: f64,
    power_s: f64,
    /// Belt speed of the last booked state [m/s].
    v_s: f64,
    /// Diagnostic split of `dissipated` (not in the FMU state, restarts at a restore):
    /// friction, contact normal damping, belt material, bearings and tensioner damper [J],
    /// and the powers of the committed state [W].
    split: [f64; 4],
    p_split: [f64; 4],
    /// Diagnostic split of `sliding_work` (not in the FMU state): `∫ v ṗ_s`, `−∫ v Q_s` of the
    /// contact and of the material damping [J], and the two powers of the committed state [W].
    travel_split: [f64; 3],
    p_travel: [f64; 2],
    // work buffers
    trial: AleHistory,
    pulleys: Vec<AlePulley>,
    torque: Vec<f64>,
    forces: Vec<Vector2<f64>>,
    dv: Vec<f64>,
    dvd: Vec<f64>,
    dth: Vec<f64>,
    tdq: Vec<f64>,
    tdv: Vec<f64>,
    tdth: Vec<f64>,
    arm_t: ArmTangent,
    /// Moment of the contact on the tensioner's arm at the last residual [N m].
    arm_moment: f64,
    /// The two starts of the step being solved ([`MechanicalSystem::predict`]): the
    /// integrator's (generalized-α: the old acceleration carried on) and the constant-velocity
    /// one `q₀ + h v₀`; whether they were set since the last accepted step.
    pred_alpha: Vec<f64>,
    pred_cv: Vec<f64>,
    predicted: bool,
    /// Running share of the accepted steps whose solution the constant-velocity start came
    /// closer to than the integrator's (memory [`CV_MEMORY`]); above one half the steps start
    /// from `q₀ + h v₀` (part of the FMU state).
    cv_share: f64,
}

/// The tensioner of the ALE drive (see [`super::tensioner`]): the arm angle `ψ` is the free
/// coordinate `dof`, the idler (pulley `pulley`, free coordinate `nq + 1 + free`) turns on the
/// arm's end.
#[derive(Clone, Copy, Debug)]
struct AleTensioner {
    pulley: usize,
    free: usize,
    dof: usize,
    geometry: ArmPulley,
}

impl AleDrive {
    /// The ALE drive on the pre-loaded belt of the Lagrangian `base` (mesh = its committed
    /// nodes, `s = 0`, at rest as the Lagrangian drive starts), cable rule `rule`.
    pub fn mount(base: BeltDrive, rule: CableRule) -> Result<Self, String> {
        let n = base.n_elements();
        let l = base.element_length();
        let nq = 4 * n;
        let section = base.spec.section;
        let ppe = base.spec.points_per_element.max(1);
        let ring = AleRing::new(n, l, section, rule);
        let pts = AlePoints::new(n, l, ppe);
        let np = base.spec.pulleys.len();
        let free: Vec<usize> = (0..np)
            .filter(|&k| matches!(base.spec.pulleys[k].kind, PulleyKind::Free { .. }))
            .collect();
        let nf = free.len();
        let na = usize::from(base.tensioner.is_some());
        let (is, nfree) = (nq, nq + 1 + nf + na);
        let arm = match &base.tensioner {
            Some(t) => Some(AleTensioner {
                pulley: t.def.pulley,
                free: free
                    .iter()
                    .position(|&k| k == t.def.pulley)
                    .ok_or("the tensioner's idler must be a free pulley")?,
                dof: nq + 1 + nf,
                geometry: t.contact.obstacles()[0],
            }),
            None => None,
        };
        let mut entries = Vec::new();
        for e in 0..n {
            for i in 0..8 {
                for j in 0..8 {
                    entries.push((ring.index(e, i), ring.index(e, j)));
                }
            }
        }
        for i in 0..nq {
            entries.push((i, is));
        }
        entries.push((is, 0));
        entries.push((is, 1));
        for f in 0..nf {
            let ip = is + 1 + f;
            for i in 0..nq {
                entries.push((i, ip));
                entries.push((ip, i));
            }
            entries.push((ip, is));
        }
        if let Some(a) = &arm {
            let (ia, ip) = (a.dof, is + 1 + a.free);
            for i in 0..nq {
                entries.push((i, ia));
                entries.push((ia, i));
            }
            entries.extend([(ia, is), (ia, ip), (ip, ia), (ia, ia)]);
        }
        let pattern = CscPattern::from_entries(nfree, entries);
        let pos = |r: usize, c: usize| pattern.position(r, c).expect("in the pattern");
        let col_s = (0..nq).map(|i| pos(i, is)).collect();
        let ring_pos = if n >= 3 {
            (0..nq)
                .flat_map(|j| {
                    let kj = j / 4;
                    (0..12).map(move |r| (4 * ((kj + n - 1 + r / 4) % n) + r % 4, j))
                })
                .map(|(i, j)| pos(i, j) as u32)
                .collect()
        } else {
            vec![]
        };
        let gauge_pos = [pos(is, 0), pos(is, 1)];
        let col_p = (0..nf)
            .map(|f| (0..nq).map(|i| pos(i, is + 1 + f)).collect())
            .collect();
        let row_p = (0..nf)
            .map(|f| (0..nq).map(|i| pos(is + 1 + f, i)).collect())
            .collect();
        let ps_pos = (0..nf).map(|f| pos(is + 1 + f, is)).collect();
        let pp_pos = (0..nf).map(|f| pos(is + 1 + f, is + 1 + f)).collect();
        let (col_a, row_a, arm_pos) = match &arm {
            Some(a) => {
                let (ia, ip) = (a.dof, is + 1 + a.free);
                (
                    (0..nq).map(|i| pos(i, ia)).collect(),
                    (0..nq).map(|i| pos(ia, i)).collect(),
                    [pos(ia, is), pos(ia, ip), pos(ip, ia), pos(ia, ia)],
                )
            }
            None => (vec![], vec![], [0; 4]),
        };
        // the Lagrangian drive's free coordinates: belt nodes, then the free pulleys, then the
        // tensioner's arm
        let (bs, bn) = (&base.scales, &base.newton_scales);
        if bs.len() != nq + nf + na {
            return Err("the ALE belt needs a closed belt of cable elements".into());
        }
        let mut scales = bs[..nq].to_vec();
        scales.push(bs[0]);
        scales.extend_from_slice(&bs[nq..]);
        let mut newton_scales = bn[..nq].to_vec();
        newton_scales.push(bs[0]);
        newton_scales.extend_from_slice(&bn[nq..]);
        let mut x = base.coordinates()[..nq].to_vec();
        x.push(0.0);
        for &k in &free {
            x.push(base.coordinates()[base.pulley_dof[k]]);
        }
        if let Some(t) = &base.tensioner {
            x.push(base.coordinates()[t.dof]);
        }
        let m = pts.len();
        let hist = AleHistory::new(m, &x[..nq]);
        let pulleys = (0..np)
            .map(|k| AlePulley {
                circle: Circle {
                    center: base.spec.pulleys[k].center,
                    radius: base.pitch[k],
                },
                theta: 0.0,
                omega: 0.0,
                theta_n: 0.0,
                center_n: base.spec.pulleys[k].center,
                arm: None,
            })
            .collect();
        let n_spans = base.span_mid.len();
        let mut me = Self {
            k_gauge: section.ea / l,
            m_gauge: section.mass_per_length * l,
            ring,
            pts,
            section,
            rule,
            n,
            free,
            arm,
            col_a,
            row_a,
            arm_pos,
            arm_t: ArmTangent::new(if na > 0 { nq } else { 0 }),
            arm_moment: 0.0,
            pattern,
            scales,
            newton_scales,
            ring_pos,
            col_s,
            gauge_pos,
            col_p,
            row_p,
            ps_pos,
            pp_pos,
            held: None,
            v_matrix: 0.0,
            t: base.t,
            xd: vec![0.0; nfree],
            xdd: vec![0.0; nfree],
            trial: hist.clone(),
            hist,
            x,
            tensions: vec![0.0; n_spans],
            input_work: 0.0,
            p_in: 0.0,
            dissipated: 0.0,
            p_diss: 0.0,
            contact_energy: 0.0,
            sliding_work: 0.0,
            split: [0.0; 4],
            p_split: [0.0; 4],
            travel_split: [0.0; 3],
            p_travel: [0.0; 2],
            p_s: 0.0,
            power_s: 0.0,
            v_s: 0.0,
            pulleys,
            torque: vec![0.0; np],
            forces: vec![Vector2::zeros(); np],
            dv: vec![0.0; nq],
            dvd: vec![0.0; nq],
            dth: vec![0.0; np * nq],
            tdq: vec![0.0; np * nq],
            tdv: vec![0.0; np],
            tdth: vec![0.0; np],
            pred_alpha: vec![0.0; nfree],
            pred_cv: vec![0.0; nfree],
            predicted: false,
            cv_share: 0.0,
            base,
        };
        me.commit(me.t, 0.0);
        Ok(me)
    }

    fn nq(&self) -> usize {
        4 * self.n
    }

    /// The mesh's element length [m] (reference length of the material per element).
    pub fn element_length(&self) -> f64 {
        self.pts.spacing() * self.base.spec.points_per_element.max(1) as f64
    }

    /// Work done on the belt through its travel `s` since the start [J]: `∫ v (ṗ_s − Q_s) dt`
    /// with `p_s = ∂T/∂v` and `Q_s` the generalized force of the contact (`Σ F·r'`) and of
    /// the material damping (`−∫ d_ε (ε̇ + v ε') ε' dx`) on `s` (trapezoidal over the step,
    /// `ṗ_s` by the difference of the committed values). Lagrange's equation of `s` would make
    /// it vanish; the model replaces it by the gauge of the mesh's sliding mode (the equation
    /// of `v` is the q-equations' projection on a sliding mode the mesh does not represent
    /// exactly), so the discrete belt gains or loses this work through `s`. In steady running
    /// it is about the belt material's convective dissipation `∫ d_ε (v ε')² dx` of the fixed
    /// mesh (the damping's drag on `s` is not balanced by the contact), mostly the zero-mean
    /// strain variation inside the elements: a term of the spatial discretization that falls
    /// about as the element length squared (the serpentine at 3000 rpm: 939 / 225 / 72 W on
    /// 120 / 240 / 480 elements, independent of the step). Not part of `energy.input_work`
    /// (the drives' port work, as the Lagrangian drive's); `energy.dissipated` is booked net
    /// of it, so the balance closes the same (`belt_ale`'s `travel_work_diagnostic`).
    pub fn sliding_work(&self) -> f64 {
        self.sliding_work
    }

    /// Diagnostic split of the dissipated energy since construction or the last restore:
    /// friction, contact normal damping, belt material, bearings and tensioner damper [J].
    pub fn dissipation_split(&self) -> [f64; 4] {
        self.split
    }

    /// Diagnostic split of [`Self::sliding_work`] since construction or the last restore:
    /// `∫ v ṗ_s` (the travel's momentum), `−∫ v Q_s` of the contact and of the belt material's
    /// damping [J].
    pub fn travel_split(&self) -> [f64; 3] {
        self.travel_split
    }

    /// Belt speed `v` of the committed state [m/s of reference length].
    pub fn belt_speed_reference(&self) -> f64 {
        self.xd[self.nq()]
    }

    /// Belt travel `s` of the committed state [m of reference length].
    pub fn travel(&self) -> f64 {
        self.x[self.nq()]
    }

    /// Committed mesh coordinates (`4 n`).
    pub fn mesh(&self) -> &[f64] {
        &self.x[..self.nq()]
    }

    /// The pulleys at time `t` with free coordinates `x`, `xd` into `self.pulleys`.
    fn set_pulleys(&mut self, t: f64, x: &[f64], xd: &[f64]) {
        let nq = self.nq();
        for (k, pl) in self.pulleys.iter_mut().enumerate() {
            pl.theta_n = self.base.q[self.base.pulley_dof[k]];
            match self.free.iter().position(|&f| f == k) {
                Some(f) => {
                    pl.theta = x[nq + 1 + f];
                    pl.omega = xd[nq + 1 + f];
                }
                None => {
                    let (th, om, _) = self.base.driven(k, t);
                    pl.theta = th;
                    pl.omega = om;
                }
            }
        }
        if let Some(a) = &self.arm {
            let g = &a.geometry;
            let (psi, psi_n) = (x[a.dof], self.base.q[self.base_arm_dof()]);
            let pl = &mut self.pulleys[a.pulley];
            pl.circle.center = g.center(psi);
            pl.center_n = g.center(psi_n);
            pl.arm = Some(AleArm {
                slope: g.center_slope(psi),
                curvature: g.pivot - pl.circle.center,
                rate: xd[a.dof],
            });
        }
    }

    /// Index of the arm angle among the Lagrangian drive's coordinates (with a tensioner).
    fn base_arm_dof(&self) -> usize {
        self.base.tensioner.as_ref().map_or(0, |t| t.dof)
    }

    /// Commits the free state `self.x`, `self.xd`, `self.xdd` at time `t` after a step `h`:
    /// contact histories (evaluated at the committed state), pulley results, span tensions and
    /// the energy book: input and dissipated power, their trapezoidal integrals over the step
    /// plus the friction work of the step, and the contact's penalty energy (as the Lagrangian
    /// drive's `book_energy`).
    fn commit(&mut self, t: f64, h: f64) {
        let nq = self.nq();
        let (x, xd) = (std::mem::take(&mut self.x), std::mem::take(&mut self.xd));
        self.set_pulleys(t, &x, &xd);
        self.torque.iter_mut().for_each(|v| *v = 0.0);
        self.forces.iter_mut().for_each(|v| *v = Vector2::zeros());
        let mut r = std::mem::take(&mut self.dv);
        let (book, force_s, arm_moment) = self.pts.contact_into(
            &self.ring,
            self.base.contact_law(),
            &self.pulleys,
            &self.hist,
            (&x[..nq], &xd[..nq], xd[nq], h, 0.0),
            &mut r,
            &mut self.torque,
            &mut self.trial,
            None,
            Some(&mut self.forces),
        );
        self.dv = r;
        self.hist.pulley.copy_from_slice(&self.trial.pulley);
        self.hist.z.copy_from_slice(&self.trial.z);
        self.hist.f.copy_from_slice(&self.trial.f);
        self.hist.q.copy_from_slice(&x[..nq]);
        // pulleys: angles, speeds, accelerations and results into the Lagrangian drive's book
        let mut p_in = 0.0;
        let mut p_diss = book.dissipation;
        let mut ps = [0.0, book.dissipation, 0.0, 0.0];
        for k in 0..self.pulleys.len() {
            let pd = self.base.pulley_dof[k];
            let (th, om, al) = match self.free.iter().position(|&f| f == k) {
                Some(f) => (x[nq + 1 + f], xd[nq + 1 + f], self.xdd[nq + 1 + f]),
                None => self.base.driven(k, t),
            };
            self.base.q[pd] = th;
            self.base.v[pd] = om;
            self.base.acc[pd] = al;
            self.base.io[k].torque = self.torque[k];
            self.base.io[k].force = self.forces[k];
            match self.base.spec.pulleys[k].kind {
                PulleyKind::Driven => p_in -= self.torque[k] * om,
                PulleyKind::Free { damping, .. } => {
                    p_in += self.base.io[k].torque_in.at(t) * om;
                    p_diss += damping * om * om;
                    ps[3] += damping * om * om;
                }
            }
        }
        // the tensioner's arm: its state into the Lagrangian drive's book, its damper's power
        if let Some(a) = &self.arm {
            let bd = self.base_arm_dof();
            self.base.q[bd] = x[a.dof];
            self.base.v[bd] = xd[a.dof];
            self.base.acc[bd] = self.xdd[a.dof];
            if let Some(tn) = self.base.tensioner.as_mut() {
                tn.belt_moment = arm_moment;
                p_diss += tn.def.damping * xd[a.dof] * xd[a.dof];
                ps[3] += tn.def.damping * xd[a.dof] * xd[a.dof];
            }
        }
        if h > 0.0 {
            self.input_work += 0.5 * h * (self.p_in + p_in);
        }
        // the rest of the book (per element: material damping, momentum of the travel) only
        // with the energy outputs, as the Lagrangian drive's
        if self.base.spec.track_energy {
            let v = xd[nq];
            let (mut q_s, mut p_s) = (force_s, 0.0);
            for e in 0..self.n {
                let (qe, qde) = (self.ring.gather(&x, e), self.ring.gather(&xd, e));
                let (pw, fs) = self.ring.cable.ale_damping_terms(&qe, &qde, v);
                // the upwinding's force is booked with the material damping (its power
                // through the mesh rates; it does not act on the travel)
                let pw = pw + self.ring.cable.upwinding_power(&qe, &qde, v);
                p_diss += pw;
                ps[2] += pw;
                q_s += fs;
                p_s += qde.dot(&(self.ring.band.g * qe)) + v * qe.dot(&(self.ring.band.h * qe));
            }
            if h > 0.0 {
                self.sliding_work +=
                    0.5 * (self.v_s + v) * (p_s - self.p_s) - 0.5 * h * (self.power_s + v * q_s);
                self.dissipated += 0.5 * h * (self.p_diss + p_diss) + book.friction_work;
                self.split[0] += book.friction_work;
                let q_d = q_s - force_s;
                self.travel_split[0] += 0.5 * (self.v_s + v) * (p_s - self.p_s);
                self.travel_split[1] -= 0.5 * h * (self.p_travel[0] + v * force_s);
                self.travel_split[2] -= 0.5 * h * (self.p_travel[1] + v * q_d);
                for j in 1..4 {
                    self.split[j] += 0.5 * h * (self.p_split[j] + ps[j]);
                }
            }
            self.p_split = ps;
            self.p_travel = [v * force_s, v * (q_s - force_s)];
            self.v_s = v;
            self.p_s = p_s;
            self.power_s = v * q_s;
            self.p_diss = p_diss;
        }
        self.p_in = p_in;
        self.contact_energy = book.normal_energy;
        // span tensions: the mean axial force of the three mesh elements nearest to each
        // span's middle (as the Lagrangian drive, with mesh elements)
        let (n, l) = (self.n, self.element_length());
        for (s, m) in self.base.span_mid.iter().enumerate() {
            let mut best = (f64::INFINITY, 0);
            for e in 0..n {
                let (a, b) = (4 * e, 4 * ((e + 1) % n));
                let mid = 0.5 * Vector2::new(x[a] + x[b], x[a + 1] + x[b + 1]);
                let d = (mid - m).norm();
                if d < best.0 {
                    best = (d, e);
                }
            }
            let e = best.1;
            self.tensions[s] = [(e + n - 1) % n, e, (e + 1) % n]
                .iter()
                .map(|&k| {
                    self.ring
                        .cable
                        .axial_force(&self.ring.gather(&x, k), 0.5 * l)
                })
                .sum::<f64>()
                / 3.0;
        }
        (self.x, self.xd) = (x, xd);
        self.t = t;
        self.base.t = t;
    }

    /// Mean material speed at the mesh nodes, `|q̇ₖ + v r'ₖ|` [m/s] (the Lagrangian drive's
    /// `belt.speed` is the mean node speed, its nodes being material points).
    fn belt_speed(&self) -> f64 {
        let v = self.xd[self.nq()];
        (0..self.n)
            .map(|k| {
                let (q, qd) = (&self.x[4 * k..4 * k + 4], &self.xd[4 * k..4 * k + 4]);
                Vector2::new(qd[0] + v * q[2], qd[1] + v * q[3]).norm()
            })
            .sum::<f64>()
            / self.n as f64
    }

    /// Centre-line point at mesh fraction `u` of the loop [m].
    fn mesh_point(&self, u: f64) -> Vector2<f64> {
        let total = self.n as f64 * self.element_length();
        self.pts
            .field_at(&self.ring, self.mesh(), u.rem_euclid(1.0) * total)
            .0
    }

    /// Kinetic energy of the belt material `½ ∫ ρA |S q̇ + v S' q|² dx` and the free pulleys
    /// [J].
    fn kinetic_energy(&self) -> f64 {
        let v = self.xd[self.nq()];
        let mut t = 0.0;
        for e in 0..self.n {
            let (q, qd) = (self.ring.gather(&self.x, e), self.ring.gather(&self.xd, e));
            t += 0.5
                * (qd.dot(&(self.ring.mass * qd))
                    + 2.0 * v * qd.dot(&(self.ring.band.g * q))
                    + v * v * q.dot(&(self.ring.band.h * q)));
        }
        for (f, &k) in self.free.iter().enumerate() {
            if let PulleyKind::Free { inertia, .. } = self.base.spec.pulleys[k].kind {
                t += 0.5 * inertia * self.xd[self.nq() + 1 + f].powi(2);
            }
        }
        if let (Some(a), Some(tn)) = (&self.arm, &self.base.tensioner) {
            t += 0.5 * tn.def.inertia * self.xd[a.dof].powi(2);
        }
        t
    }

    /// Strain energy of the belt elements plus the contact's penalty energy and the
    /// tensioner's spring [J] (as the Lagrangian drive's `energy.strain`).
    fn strain_energy(&self) -> f64 {
        self.contact_energy
            + self.base.tensioner_energy_of(&self.base.q)
            + (0..self.n)
                .map(|e| self.ring.cable.strain_energy(&self.ring.gather(&self.x, e)))
                .sum::<f64>()
    }

    /// Gravity potential of the mesh `−Q_gᵀ q` [J] (`Q_g` the Lagrangian drive's consistent
    /// load; its work through the belt travel, `∫ ρA g·r' dx`, vanishes round the closed loop).
    fn potential_energy(&self) -> f64 {
        -self
            .base
            .gravity_full
            .iter()
            .zip(self.mesh())
            .map(|(g, q)| g * q)
            .sum::<f64>()
    }

    /// An output of the committed state.
    pub fn output_of(&self, kind: Output) -> f64 {
        let b = &self.base;
        match kind {
            Output::Belt(o) => match o {
                BeltOutput::TensionTight => self
                    .tensions
                    .iter()
                    .copied()
                    .fold(f64::NEG_INFINITY, f64::max),
                BeltOutput::TensionSlack => {
                    self.tensions.iter().copied().fold(f64::INFINITY, f64::min)
                }
                BeltOutput::SpanTension(i) => self.tensions.get(i).copied().unwrap_or(0.0),
                BeltOutput::Speed => self.belt_speed(),
                BeltOutput::PointX(i) => self.mesh_point(i as f64 / b.spec.n_points as f64).x,
                BeltOutput::PointY(i) => self.mesh_point(i as f64 / b.spec.n_points as f64).y,
                // the drives' port work; the work through the belt travel (a discretization
                // term, see `sliding_work`) is taken off the dissipation it feeds
                BeltOutput::InputWork => self.input_work,
                BeltOutput::Dissipated => self.dissipated - self.sliding_work,
                // pulley angles, speeds, torques, forces, slip: the base's book, which
                // `commit` keeps
                _ => b.output_of(kind),
            },
            Output::Energy(k) => match k {
                EnergyKind::Kinetic => self.kinetic_energy(),
                EnergyKind::Strain => self.strain_energy(),
                EnergyKind::Potential => self.potential_energy(),
                EnergyKind::Total => {
                    self.kinetic_energy() + self.strain_energy() + self.potential_energy()
                }
            },
        }
    }

    /// Rebuilds the ring and the contact points for reference element length `l` (a state
    /// restored into a model built without the pre-load).
    fn set_reference_length(&mut self, l: f64) -> Result<(), String> {
        self.base.set_reference_length(l)?;
        self.ring = AleRing::new(self.n, l, self.section, self.rule);
        self.pts = AlePoints::new(self.n, l, self.base.spec.points_per_element.max(1));
        self.k_gauge = self.section.ea / l;
        self.m_gauge = self.section.mass_per_length * l;
        Ok(())
    }
}

impl Model for AleDrive {
    fn build_note(&self) -> Option<String> {
        self.base.build_note()
    }

    /// The mesh's centre line (four points per element) and the pulleys with their angles.
    fn sketch(&self) -> crate::model::Sketch {
        let b = &self.base;
        let mut s = crate::model::Sketch::new(format!(
            "{} ALE ANCF cable belt elements (mesh fixed on the loop), {} pulleys",
            self.n,
            b.spec.pulleys.len()
        ));
        let n = 4 * self.n;
        s.line_xy((0..=n).map(|k| {
            let p = self.mesh_point(k as f64 / n as f64);
            [p.x, p.y]
        }));
        for (k, p) in b.spec.pulleys.iter().enumerate() {
            let pc = p.center;
            let c = Vector3::new(pc.x, pc.y, 0.0);
            s.circle(c, p.radius, Vector3::z());
            let phi = b.q[b.pulley_dof[k]];
            s.line([c, c + p.radius * Vector3::new(phi.cos(), phi.sin(), 0.0)]);
        }
        s
    }

    fn set_input(&mut self, input: usize, value: f64) {
        self.base.set_input(input, value);
    }

    fn set_input_derivative(
        &mut self,
        input: usize,
        order: usize,
        value: f64,
    ) -> Result<(), String> {
        self.base.set_input_derivative(input, order, value)
    }

    fn output(&self, output: usize) -> f64 {
        self.output_of(self.base.roles.outputs[output])
    }

    /// Pulley angles and speeds (analytic); the others are not provided by the ALE model.
    fn output_derivative(&self, output: usize) -> Option<f64> {
        match self.base.roles.outputs[output] {
            k @ Output::Belt(BeltOutput::PulleyAngle(_) | BeltOutput::PulleyOmega(_)) => {
                self.base.output_rate(k)
            }
            _ => None,
        }
    }

    fn accept(&mut self, state: &mut DynState) {
        if self.predicted {
            // which start of the step came closer to its solution (scaled as Newton's
            // increments), into the running share that picks the next steps' start
            let (mut e_alpha, mut e_cv) = (0.0f64, 0.0f64);
            for (i, (&q, &s)) in state.q.iter().zip(&self.newton_scales).enumerate() {
                e_alpha = e_alpha.max(((q - self.pred_alpha[i]) / s).abs());
                e_cv = e_cv.max(((q - self.pred_cv[i]) / s).abs());
            }
            let won = if e_cv < e_alpha { 1.0 } else { 0.0 };
            self.cv_share += CV_MEMORY * (won - self.cv_share);
            self.predicted = false;
        }
        self.x.copy_from_slice(&state.q);
        self.xd.copy_from_slice(&state.v);
        self.xdd.copy_from_slice(&state.acc);
        let h = state.t - self.t;
        self.commit(state.t, h.max(0.0));
    }

    fn free_state(&self, q: &mut [f64], v: &mut [f64]) {
        q.copy_from_slice(&self.x);
        v.copy_from_slice(&self.xd);
    }

    fn begin_communication_step(&mut self, t0: f64, t1: f64) {
        self.base.begin_communication_step(t0, t1);
    }

    fn input_restarts_accelerations(&self, _input: usize) -> bool {
        false
    }

    /// The ALE state: time, free coordinates with their rates, the points' histories and the
    /// committed mesh, pulley inputs, angles and results, span tensions, the energy book (input
    /// work, dissipated energy, their committed powers, the contact's penalty energy, the
    /// sliding work with its committed momentum and power), the
    /// communication step's start and the reference element length.
    fn save(&self, w: &mut StateWriter) -> Result<(), String> {
        w.f64(self.t);
        w.f64s(&self.x);
        w.f64s(&self.xd);
        w.f64s(&self.xdd);
        w.u64(self.hist.pulley.len() as u64);
        for &p in &self.hist.pulley {
            w.u64(p as u64);
        }
        w.f64s(&self.hist.z);
        w.f64s(&self.hist.f);
        w.f64s(&self.hist.q);
        self.base.save_pulleys(w);
        for &pd in &self.base.pulley_dof {
            for x in [self.base.q[pd], self.base.v[pd], self.base.acc[pd]] {
                w.f64(x);
            }
        }
        w.f64s(&self.tensions);
        w.f64(self.input_work);
        w.f64(self.p_in);
        w.f64(self.dissipated);
        w.f64(self.p_diss);
        w.f64(self.contact_energy);
        w.f64(self.sliding_work);
        w.f64(self.p_s);
        w.f64(self.power_s);
        w.bool(self.base.t0_step.is_some());
        w.f64(self.base.t0_step.unwrap_or(0.0));
        w.f64(self.element_length());
        if let Some(tn) = &self.base.tensioner {
            w.f64(tn.belt_moment);
        }
        w.f64(self.cv_share);
        Ok(())
    }

    fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        let t = r.f64().map_err(e)?;
        r.f64s_into(&mut self.x).map_err(e)?;
        r.f64s_into(&mut self.xd).map_err(e)?;
        r.f64s_into(&mut self.xdd).map_err(e)?;
        let m = r.u64().map_err(e)? as usize;
        if m != self.hist.pulley.len() {
            return Err(format!(
                "{m} contact points in the state, {} in the model",
                self.hist.pulley.len()
            ));
        }
        for p in self.hist.pulley.iter_mut() {
            *p = r.u64().map_err(e)? as u32;
        }
        r.f64s_into(&mut self.hist.z).map_err(e)?;
        r.f64s_into(&mut self.hist.f).map_err(e)?;
        r.f64s_into(&mut self.hist.q).map_err(e)?;
        self.base.restore_pulleys(r)?;
        for k in 0..self.base.pulley_dof.len() {
            let pd = self.base.pulley_dof[k];
            self.base.q[pd] = r.f64().map_err(e)?;
            self.base.v[pd] = r.f64().map_err(e)?;
            self.base.acc[pd] = r.f64().map_err(e)?;
        }
        r.f64s_into(&mut self.tensions).map_err(e)?;
        self.input_work = r.f64().map_err(e)?;
        self.p_in = r.f64().map_err(e)?;
        self.dissipated = r.f64().map_err(e)?;
        self.p_diss = r.f64().map_err(e)?;
        self.contact_energy = r.f64().map_err(e)?;
        self.sliding_work = r.f64().map_err(e)?;
        self.p_s = r.f64().map_err(e)?;
        self.power_s = r.f64().map_err(e)?;
        let has_t0 = r.bool().map_err(e)?;
        let t0 = r.f64().map_err(e)?;
        let length = r.f64().map_err(e)?;
        if !(length > 0.0 && length.is_finite()) {
            return Err(format!(
                "belt element reference length {length} m in the state"
            ));
        }
        if length != self.element_length() {
            self.set_reference_length(length)?;
        }
        if let Some(a) = self.arm {
            let bd = self.base_arm_dof();
            self.base.q[bd] = self.x[a.dof];
            self.base.v[bd] = self.xd[a.dof];
            self.base.acc[bd] = self.xdd[a.dof];
            if let Some(tn) = self.base.tensioner.as_mut() {
                tn.belt_moment = r.f64().map_err(e)?;
            }
        }
        self.cv_share = r.f64().map_err(e)?;
        self.predicted = false;
        self.base.t0_step = has_t0.then_some(t0);
        self.v_s = self.xd[self.nq()];
        self.t = t;
        self.base.t = t;
        Ok(())
    }
}

impl MechanicalSystem for AleDrive {
    fn n_free(&self) -> usize {
        self.x.len()
    }

    fn pattern(&self) -> &CscPattern {
        &self.pattern
    }

    fn scales(&self) -> &[f64] {
        &self.scales
    }

    fn newton_scales(&self) -> &[f64] {
        &self.newton_scales
    }

    fn residual(
        &mut self,
        t: f64,
        x: &[f64],
        xd: &[f64],
        xdd: &[f64],
        _load_factor: f64,
        r: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        let nq = self.nq();
        let is = nq;
        if let Some(held) = &self.held {
            // static solve: the pre-load's mesh is the equilibrium; hold every coordinate
            for i in 0..r.len() {
                r[i] = x[i] - held[i];
            }
            if let Some((c, vals)) = jac {
                vals.iter_mut().for_each(|v| *v = 0.0);
                for i in 0..r.len() {
                    let p = self.pattern.position(i, i).expect("diagonal");
                    vals[p] = c.stiffness;
                }
            }
            return Ok(());
        }
        let h = t - self.t;
        let (q, qd, qdd) = (&x[..nq], &xd[..nq], &xdd[..nq]);
        let v = xd[is];
        let rates = AleRates { v, v_dot: xdd[is] };
        self.ring.residual_into(q, qd, qdd, rates, &mut r[..nq]);
        // the belt's weight: the Lagrangian drive's consistent load of the reference length
        // (each mesh element holds the material of one reference element length)
        if self.base.spec.gravity != Vector2::zeros() {
            for (ri, g) in r[..nq].iter_mut().zip(&self.base.gravity_full) {
                *ri -= g;
            }
        }
        self.set_pulleys(t, x, xd);
        self.torque.iter_mut().for_each(|v| *v = 0.0);
        let law = *self.base.contact_law();
        let t0 = Vector2::new(self.hist.q[2], self.hist.q[3]).normalize();
        let gauge = t0.dot(&Vector2::new(q[0] - self.hist.q[0], q[1] - self.hist.q[1]));
        r[is] = self.k_gauge * gauge + self.m_gauge * t0.dot(&Vector2::new(qdd[0], qdd[1]));
        match jac {
            None => {
                (_, _, self.arm_moment) = self.pts.contact_into(
                    &self.ring,
                    &law,
                    &self.pulleys,
                    &self.hist,
                    (q, qd, v, h, 0.0),
                    &mut r[..nq],
                    &mut self.torque,
                    &mut self.trial,
                    None,
                    None,
                );
            }
            Some((c, vals)) => {
                self.v_matrix = v;
                vals.iter_mut().for_each(|v| *v = 0.0);
                // the kernels' tangents are ∂/∂q + a_qd ∂/∂q̇ + a_qdd ∂/∂q̈, scaled here by
                // the stiffness factor (the mass matrix alone: a vanishing one)
                let st = c.stiffness.max(1e-300);
                let (a_qd, a_qdd) = (c.damping / st, c.mass / st);
                let (pattern, ring_pos, n) = (&self.pattern, &self.ring_pos, self.n);
                let mut add = |i: usize, j: usize, val: f64| {
                    let p = if ring_pos.is_empty() {
                        pattern.position(i, j).expect("ring entry")
                    } else {
                        // node of row i relative to column j's: before, at, after
                        let (ki, kj) = (i / 4, j / 4);
                        let slot = if ki == kj {
                            1
                        } else if ki == kj + 1 || (ki == 0 && kj == n - 1) {
                            2
                        } else {
                            0
                        };
                        ring_pos[12 * j + 4 * slot + i % 4] as usize
                    };
                    vals[p] += st * val;
                };
                self.ring.tangent(
                    q,
                    qd,
                    qdd,
                    rates,
                    (a_qd, a_qdd),
                    &mut add,
                    &mut self.dv,
                    &mut self.dvd,
                );
                for b in [&mut self.dth, &mut self.tdq, &mut self.tdv, &mut self.tdth] {
                    b.iter_mut().for_each(|v| *v = 0.0);
                }
                self.arm_t.clear();
                let has_arm = self.arm.is_some();
                (_, _, self.arm_moment) = self.pts.contact_into(
                    &self.ring,
                    &law,
                    &self.pulleys,
                    &self.hist,
                    (q, qd, v, h, a_qd),
                    &mut r[..nq],
                    &mut self.torque,
                    &mut self.trial,
                    Some(ContactTangent {
                        add: &mut add,
                        dv: &mut self.dv,
                        a_theta: a_qd,
                        dtheta: &mut self.dth,
                        torque_dq: &mut self.tdq,
                        torque_dv: &mut self.tdv,
                        torque_dtheta: &mut self.tdth,
                        arm: has_arm.then_some(&mut self.arm_t),
                    }),
                    None,
                );
                for i in 0..nq {
                    vals[self.col_s[i]] += c.damping * self.dv[i] + c.mass * self.dvd[i];
                }
                let g = c.stiffness * self.k_gauge + c.mass * self.m_gauge;
                vals[self.gauge_pos[0]] += g * t0.x;
                vals[self.gauge_pos[1]] += g * t0.y;
                for (f, &k) in self.free.iter().enumerate() {
                    let PulleyKind::Free { inertia, damping } = self.base.spec.pulleys[k].kind
                    else {
                        continue;
                    };
                    for i in 0..nq {
                        vals[self.col_p[f][i]] += st * self.dth[k * nq + i];
                        vals[self.row_p[f][i]] -= st * self.tdq[k * nq + i];
                    }
                    vals[self.ps_pos[f]] -= c.damping * self.tdv[k];
                    vals[self.pp_pos[f]] +=
                        c.mass * inertia + c.damping * damping - st * self.tdth[k];
                }
                if let (Some(_), Some(tn)) = (&self.arm, &self.base.tensioner) {
                    let at = &self.arm_t;
                    for i in 0..nq {
                        vals[self.col_a[i]] += st * at.dpsi[i];
                        vals[self.row_a[i]] -= st * at.moment_dq[i];
                    }
                    let d = &tn.def;
                    vals[self.arm_pos[0]] -= c.damping * at.moment_dv;
                    vals[self.arm_pos[1]] -= st * at.moment_dtheta;
                    vals[self.arm_pos[2]] -= st * at.torque_dpsi;
                    vals[self.arm_pos[3]] +=
                        c.mass * d.inertia + c.damping * d.damping + c.stiffness * d.stiffness
                            - st * at.moment_dpsi;
                }
            }
        }
        for (f, &k) in self.free.iter().enumerate() {
            if let PulleyKind::Free { inertia, damping } = self.base.spec.pulleys[k].kind {
                let ip = is + 1 + f;
                r[ip] = inertia * xdd[ip] + damping * xd[ip]
                    - self.base.io[k].torque_in.at(t)
                    - self.torque[k];
            }
        }
        // the tensioner's arm: I ψ̈ + c ψ̇ + k (ψ − ψ_free) − Q_ψ = 0
        if let (Some(a), Some(tn)) = (&self.arm, &self.base.tensioner) {
            let (d, ia) = (&tn.def, a.dof);
            r[ia] =
                d.inertia * xdd[ia] + d.damping * xd[ia] + d.stiffness * (x[ia] - tn.free_angle)
                    - self.arm_moment;
        }
        if r.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(ModelError::NonFinite)
        }
    }

    /// Not supported (refused at build, see `ale::check`): the midpoint rule's average
    /// configuration has no ALE form here.
    fn midpoint_residual(
        &mut self,
        _t_a: f64,
        _t_b: f64,
        _q_a: &[f64],
        _q_b: &[f64],
        _v: &[f64],
        _a: &[f64],
        _r: &mut [f64],
        _jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        Err(ModelError::Outside(
            "belt.formulation = \"ale\" does not support the midpoint integrator".into(),
        ))
    }

    /// The mesh of a running drive stands still: modified Newton keeps one matrix for the
    /// whole run and its first iteration with it is accepted when the increment and the
    /// remaining error `θ/(1−θ)` times it (θ that matrix's last measured contraction rate)
    /// are within the tolerance (60 rad/s protocol, 60 / 120 / 240 elements, with the rebuild
    /// of [`Self::kept_matrix_current`]: 2.34 / 2.01 / 2.25 → 1.38 / 1.40 / 1.34 iterations
    /// per step).
    fn trusts_kept_contraction(&self) -> bool {
        true
    }

    /// Damped Newton (backtracking, as the Lagrangian drive): no backtrack at 1 ms steps on
    /// the 60 rad/s protocol; at 3 ms steps (10 N m) it breaks the cycling of the free
    /// pulley's angle in the halved substeps of the start (rejected substeps 270 → 27).
    fn damped_newton(&self) -> bool {
        true
    }

    /// The step starts from `q₀ + h v₀` (every free coordinate) instead of the integrator's
    /// start while that came closer to the accepted steps' solutions (running share above one
    /// half, see [`CV_MEMORY`]; judged in `accept`).
    /// On the serpentine drive the accelerations of the mesh at the arc ends and of the light
    /// back-side idlers jump from step to step (contact points at the arc ends of the crank
    /// and the A/C compressor going in and out of contact and between stick and slip), and
    /// generalized-α's start, which carries the old acceleration on, lands farther from the
    /// solution than no acceleration at all. `bench_belt_predictor serpentine 120`: the 0.5 s
    /// ramp 8.09 → 3.50 iterations and 4.49 → 1.14 factorizations per step, 46 → 2 rejected
    /// steps; steady 800 rpm 6.1 → 2.0 iterations, 3.0 → 0.02 factorizations; steady
    /// 3000 rpm 11.8 → 3.0 and 6.8 → 0.6. On the two-pulley drive, whose accelerations are
    /// smooth, the integrator's start stays the closer one in most steps (1.05 iterations
    /// per step either way).
    fn predict(&mut self, q0: &[f64], v0: &[f64], h: f64, q1: &mut [f64]) -> bool {
        self.pred_alpha.copy_from_slice(q1);
        for ((p, &q), &v) in self.pred_cv.iter_mut().zip(q0).zip(v0) {
            *p = q + h * v;
        }
        self.predicted = true;
        let cv = self.cv_share > 0.5;
        if cv {
            q1.copy_from_slice(&self.pred_cv);
        }
        cv
    }

    /// The constant-velocity start moves no material point along the pulleys (the mesh stands
    /// still): the kept matrix still describes it.
    fn prediction_keeps_matrix(&self) -> bool {
        true
    }

    /// A kept matrix is stale once the committed belt speed moved by more than
    /// [`STALE_SPEED`] of the speed it was built at (at least 0.1 m/s): the convective terms
    /// (`2 v G`, `v² H`, the contact's `v r'`) change with it. The committed speed, not the
    /// iterate's: at most one rebuild per step for this reason (judged by the iterate's, the
    /// halved substeps of 3 ms steps rebuilt in every iteration and failed 4 times as often).
    fn kept_matrix_current(&self) -> bool {
        (self.xd[self.nq()] - self.v_matrix).abs()
            <= STALE_SPEED * self.v_matrix.abs().max(0.1 / STALE_SPEED)
    }

    fn hold_for_statics(&mut self, held: bool) {
        self.held = held.then(|| self.x.clone());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{ParamValues, Scene};
    use crate::solver::simulation::{Simulation, SolverConfig};

    /// The ALE drive of `belt_drive.toml` (30 elements) after 60 steps of 1 ms with pulley 1
    /// speeding up to 6 rad/s and 2 N m on pulley 2: a running belt with friction histories.
    fn running() -> AleDrive {
        running_scene(
            "belt_drive.toml",
            ("n_elements = 100", "n_elements = 30"),
            2.0,
        )
    }

    /// The ALE drive of scene `name` with `elements` replaced, after 60 steps of 1 ms with
    /// pulley 1 speeding up to 6 rad/s and the load `load` on pulley 2.
    fn running_scene(name: &str, elements: (&str, &str), load: f64) -> AleDrive {
        let text = std::fs::read_to_string(format!("{}/scenes/{name}", env!("CARGO_MANIFEST_DIR")))
            .unwrap();
        // the ALE belt (the shipped serpentine says so itself since session 38)
        let text = if text.contains("formulation = \"ale\"") {
            text
        } else {
            text.replace("[belt]", "[belt]\nformulation = \"ale\"")
        };
        assert!(text.contains(elements.0));
        let text = text.replace(elements.0, elements.1);
        let scene = Scene::from_toml(&text).unwrap();
        let p = ParamValues::defaults(&scene.params);
        let model = crate::model::build_model(&scene, &p).unwrap();
        let inputs: Vec<String> = scene
            .io
            .iter()
            .filter(|v| v.causality == crate::variables::Causality::Input)
            .map(|v| v.name.clone())
            .collect();
        let idx = |n: &str| inputs.iter().position(|x| x == n).unwrap();
        let mut sim = Simulation::new(model, SolverConfig::from_params(&p), 0.0).unwrap();
        sim.initialize().unwrap();
        for i in 0..60 {
            let t = i as f64 * 1e-3;
            sim.set_input(idx("pulley1.omega"), 100.0 * t);
            sim.set_input(idx("pulley2.torque_in"), -load);
            sim.advance(t + 1e-3).unwrap();
        }
        sim.model_as::<AleDrive>().unwrap().clone()
    }

    /// The iteration matrix of a generalized-α step against central differences of the
    /// residual in the step's unknown (the acceleration `δ`: `q += β h² δ`, `v += γ h δ`,
    /// `a += δ`), every column: mesh, `s` (through `v`, `v̇`) and pulley 2's angle; and the
    /// residual's rows (the gauge, pulley 2) are the model's equations at the committed state.
    #[test]
    fn the_ale_drive_iteration_matrix_matches_finite_differences() {
        let mut m = running();
        iteration_matrix_against_differences(&mut m);
        // the drive runs and pulley 2 is a free coordinate with its equation
        assert!(m.xd[m.nq()] > 0.1, "belt speed {}", m.xd[m.nq()]);
        assert_eq!(m.n_free(), m.nq() + 2);
    }

    /// The same on the serpentine drive (60 elements, pulley 2 the tensioner's idler, free,
    /// no load): the columns of the six free pulleys and of the arm angle `ψ` with the idler's
    /// centre moving with it, the arm's row.
    #[test]
    fn the_ale_serpentine_iteration_matrix_matches_finite_differences() {
        let mut m = running_scene(
            "serpentine.toml",
            ("n_elements = 120", "n_elements = 60"),
            0.0,
        );
        assert_eq!(m.n_free(), m.nq() + 1 + 6 + 1);
        let ia = m.arm.unwrap().dof;
        assert!(m.xd[ia].abs() > 1e-4, "the arm moves: {}", m.xd[ia]);
        assert!(m.arm_moment.abs() > 1.0, "the belt loads the arm");
        iteration_matrix_against_differences(&mut m);
        assert!(m.xd[m.nq()] > 0.1, "belt speed {}", m.xd[m.nq()]);
    }

    fn iteration_matrix_against_differences(m: &mut AleDrive) {
        let n = m.n_free();
        let (h, beta, gamma) = (1e-3, 0.3, 0.6);
        let t = m.t + h;
        let coeffs = JacobianCoeffs {
            mass: 1.0,
            damping: gamma * h,
            stiffness: beta * h * h,
        };
        let (q0, v0) = (m.x.clone(), m.xd.clone());
        // a trial state of the step: the committed one moved on a little
        let a0: Vec<f64> = (0..n).map(|i| 0.3 * (0.7 * i as f64).sin()).collect();
        let state = |d: &[f64]| {
            let q: Vec<f64> = (0..n)
                .map(|i| q0[i] + h * v0[i] + beta * h * h * (a0[i] + d[i]))
                .collect();
            let v: Vec<f64> = (0..n).map(|i| v0[i] + gamma * h * (a0[i] + d[i])).collect();
            let a: Vec<f64> = (0..n).map(|i| a0[i] + d[i]).collect();
            (q, v, a)
        };
        let zero = vec![0.0; n];
        let (q, v, a) = state(&zero);
        let mut r = vec![0.0; n];
        let mut vals = vec![0.0; m.pattern.nnz()];
        m.residual(t, &q, &v, &a, 1.0, &mut r, Some((coeffs, &mut vals)))
            .unwrap();
        let pattern = m.pattern.clone();
        let eps = 1e-4;
        let (mut worst, mut scale) = (0.0f64, 0.0f64);
        let mut worst_at = (0, 0);
        // the border (columns and rows of s, the pulleys and the arm) on its own scale:
        // (worst, scale) per border column and per border row
        let nq = m.nq();
        let mut border = vec![(0.0f64, 0.0f64); 2 * (n - nq)];
        for c in 0..n {
            let mut d = zero.clone();
            d[c] = eps;
            let (qp, vp, ap) = state(&d);
            d[c] = -eps;
            let (qm, vm, am) = state(&d);
            let (mut rp, mut rm) = (vec![0.0; n], vec![0.0; n]);
            m.residual(t, &qp, &vp, &ap, 1.0, &mut rp, None).unwrap();
            m.residual(t, &qm, &vm, &am, 1.0, &mut rm, None).unwrap();
            for i in 0..n {
                let fd = (rp[i] - rm[i]) / (2.0 * eps);
                let an = pattern.position(i, c).map_or(0.0, |p| vals[p]);
                scale = scale.max(fd.abs());
                if (fd - an).abs() > worst {
                    worst = (fd - an).abs();
                    worst_at = (i, c);
                }
                for k in [
                    (c >= nq).then(|| c - nq),
                    (i >= nq).then(|| n - nq + i - nq),
                ]
                .into_iter()
                .flatten()
                {
                    border[k].0 = border[k].0.max((fd - an).abs());
                    border[k].1 = border[k].1.max(fd.abs());
                }
            }
        }
        assert!(
            worst < 1e-5 * scale,
            "worst {worst:e} of {scale:e} at (row, col) {worst_at:?} (n = {n})"
        );
        for (k, &(w, sc)) in border.iter().enumerate() {
            assert!(
                w <= 1e-5 * sc,
                "border {} {}: worst {w:e} of {sc:e}",
                if k < n - nq { "column" } else { "row" },
                nq + k % (n - nq)
            );
        }
    }
}
