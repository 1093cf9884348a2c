//! Energy book of the belt drive: input work of drives, input torques and end loads,
//! dissipation (contact damping and friction, bearings, belt material), kinetic, strain and
//! potential energy, and the history-dependent outputs whose rates are taken over a step.

use super::model::{BeltDrive, NC};
use super::pulleys::PulleyKind;
use super::scene::{BeltOutput, Output};
use crate::contact::ContactBook;
use crate::snapshot::{SnapshotError, StateReader, StateWriter};
use nalgebra::Vector2;

/// Outputs that depend on the contact history (pulley torques and forces, span tensions,
/// contact energy, dissipated energy), or their rates over the last internal step.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct StepRates {
    /// Per pulley: torque [N m], force x, y [N] (or their rates).
    pub(super) pulleys: Vec<[f64; 3]>,
    /// Larger and smaller span tension [N].
    pub(super) tight: f64,
    pub(super) slack: f64,
    /// Penalty energy of the contact [J].
    pub(super) contact_energy: f64,
    /// Energy dissipated since the start [J].
    pub(super) dissipated: f64,
}

impl StepRates {
    /// `(self − before)/h`.
    pub(super) fn rate_since(&self, before: &Self, h: f64) -> Self {
        let d = |a: f64, b: f64| (a - b) / h;
        Self {
            pulleys: self
                .pulleys
                .iter()
                .zip(&before.pulleys)
                .map(|(a, b)| [d(a[0], b[0]), d(a[1], b[1]), d(a[2], b[2])])
                .collect(),
            tight: d(self.tight, before.tight),
            slack: d(self.slack, before.slack),
            contact_energy: d(self.contact_energy, before.contact_energy),
            dissipated: d(self.dissipated, before.dissipated),
        }
    }

    pub(super) fn save(&self, w: &mut StateWriter) {
        w.u64(self.pulleys.len() as u64);
        for p in &self.pulleys {
            w.f64s(p);
        }
        for x in [self.tight, self.slack, self.contact_energy, self.dissipated] {
            w.f64(x);
        }
    }

    pub(super) fn restore(
        r: &mut StateReader,
        n_pulleys: usize,
    ) -> Result<Self, crate::snapshot::SnapshotError> {
        let n = r.u64()? as usize;
        let mut pulleys = vec![[0.0; 3]; n.min(n_pulleys)];
        for p in pulleys.iter_mut() {
            r.f64s_into(p)?;
        }
        Ok(Self {
            pulleys,
            tight: r.f64()?,
            slack: r.f64()?,
            contact_energy: r.f64()?,
            dissipated: r.f64()?,
        })
    }
}

/// Input work and dissipation integrated over the run, the powers of the committed state
/// and the contact's penalty energy.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct EnergyBook {
    /// Work of drives, input torques and end loads since the start [J].
    pub(super) input_work: f64,
    /// Energy dissipated since the start [J].
    pub(super) dissipated: f64,
    /// Input power of the committed state [W].
    pub(super) p_in: f64,
    /// Dissipated power (contact normal damping, bearings, belt material) of the committed
    /// state [W] (friction work is booked per step).
    pub(super) p_diss: f64,
    /// Penalty energy of the contact [J].
    pub(super) contact_energy: f64,
    /// Diagnostic split of `dissipated` (not in the FMU state, restarts at a restore):
    /// friction, contact normal damping, belt material, bearings and tensioner damper [J],
    /// and the powers of the last three in the committed state [W].
    pub(super) split: [f64; 4],
    pub(super) p_split: [f64; 4],
}

impl EnergyBook {
    /// Writes the book into a snapshot.
    pub(super) fn save(&self, w: &mut StateWriter) {
        for x in [
            self.input_work,
            self.dissipated,
            self.p_in,
            self.p_diss,
            self.contact_energy,
        ] {
            w.f64(x);
        }
    }

    /// Reads a book written by [`Self::save`].
    pub(super) fn restore(r: &mut StateReader) -> Result<Self, SnapshotError> {
        Ok(Self {
            input_work: r.f64()?,
            dissipated: r.f64()?,
            p_in: r.f64()?,
            p_diss: r.f64()?,
            contact_energy: r.f64()?,
            ..Self::default()
        })
    }
}

impl BeltDrive {
    /// Kinetic energy of belt and free pulleys [J] (committed state).
    pub fn kinetic_energy(&self) -> f64 {
        self.kinetic_energy_of(&self.v)
    }

    /// Kinetic energy [J] at full velocities `v`.
    pub(super) fn kinetic_energy_of(&self, v: &[f64]) -> f64 {
        let mut t = 0.0;
        self.set.for_each_state(&self.q, v, None, |_, el, s| {
            t += el.kinetic_energy_at(s);
        });
        for (k, p) in self.spec.pulleys.iter().enumerate() {
            if let PulleyKind::Free { inertia, .. } = p.kind {
                t += 0.5 * inertia * v[self.pulley_dof[k]].powi(2);
            }
        }
        if let Some(tn) = &self.tensioner {
            t += 0.5 * tn.def.inertia * v[tn.dof].powi(2);
        }
        t
    }

    /// Strain energy of the belt plus the penalty energy of the contact and the tensioner's
    /// spring energy [J].
    pub fn strain_energy(&self) -> f64 {
        self.energy.contact_energy + self.belt_strain_energy_of(&self.q)
    }

    /// Strain energy of the belt elements and the tensioner's spring [J] at full coordinates
    /// `q`.
    pub(super) fn belt_strain_energy_of(&self, q: &[f64]) -> f64 {
        self.set.strain_energy(q, None) + self.tensioner_energy_of(q)
    }

    /// Gravity potential `−Q_gᵀ q` [J].
    pub fn potential_energy(&self) -> f64 {
        self.potential_energy_of(&self.q)
    }

    /// Gravity potential [J] at full coordinates `q`.
    pub(super) fn potential_energy_of(&self, q: &[f64]) -> f64 {
        -self
            .gravity_full
            .iter()
            .zip(q)
            .map(|(g, q)| g * q)
            .sum::<f64>()
    }

    /// Work done by drives, input torques and end loads since the start [J].
    pub fn input_work(&self) -> f64 {
        self.energy.input_work
    }

    /// Energy dissipated since the start [J].
    pub fn dissipated(&self) -> f64 {
        self.energy.dissipated
    }

    /// Diagnostic split of the dissipated energy since construction or the last restore:
    /// friction, contact normal damping, belt material, bearings and tensioner damper [J].
    pub fn dissipation_split(&self) -> [f64; 4] {
        self.energy.split
    }

    /// The history-dependent outputs of the committed state.
    pub(super) fn history_outputs(&self) -> StepRates {
        let (tight, slack) = if self.tensions.is_empty() {
            (0.0, 0.0)
        } else {
            (
                self.output_of(Output::Belt(BeltOutput::TensionTight)),
                self.output_of(Output::Belt(BeltOutput::TensionSlack)),
            )
        };
        StepRates {
            pulleys: self
                .io
                .iter()
                .map(|io| [io.torque, io.force.x, io.force.y])
                .collect(),
            tight,
            slack,
            contact_energy: self.energy.contact_energy,
            dissipated: self.energy.dissipated,
        }
    }

    /// Books the committed state at time `t` (after a step unless `initial`): input and
    /// dissipated power, their trapezoidal integrals since the last commit plus the friction
    /// work of the step, and the contact's penalty energy.
    pub(super) fn book_energy(&mut self, t: f64, initial: bool, contact: &ContactBook) {
        if self.spec.track_energy {
            let mut p_in = 0.0;
            let mut p_diss = contact.dissipation;
            let mut ps = [0.0, contact.dissipation, 0.0, 0.0];
            for (k, p) in self.spec.pulleys.iter().enumerate() {
                let om = self.v[self.pulley_dof[k]];
                match p.kind {
                    PulleyKind::Driven => p_in -= self.io[k].torque * om,
                    PulleyKind::Free { damping, .. } => {
                        p_in += self.io[k].torque_in.at(t) * om;
                        p_diss += damping * om * om;
                        ps[3] += damping * om * om;
                    }
                }
            }
            if let Some(tn) = &self.tensioner {
                p_diss += tn.def.damping * self.v[tn.dof].powi(2);
                ps[3] += tn.def.damping * self.v[tn.dof].powi(2);
            }
            if !self.closed {
                let last = (self.n_nodes - 1) * NC;
                p_in += self.end_loads[0].dot(&Vector2::new(self.v[0], self.v[1]))
                    + self.end_loads[1].dot(&Vector2::new(self.v[last], self.v[last + 1]));
            }
            self.set.for_each_state(&self.q, &self.v, None, |_, el, s| {
                let pw = el.damping_power_at(s);
                p_diss += pw;
                ps[2] += pw;
            });
            let h = t - self.t;
            if !initial && h > 0.0 {
                self.energy.input_work += 0.5 * h * (self.energy.p_in + p_in);
                self.energy.dissipated +=
                    0.5 * h * (self.energy.p_diss + p_diss) + contact.friction_work;
                self.energy.split[0] += contact.friction_work;
                for j in 1..4 {
                    self.energy.split[j] += 0.5 * h * (self.energy.p_split[j] + ps[j]);
                }
            }
            self.energy.p_split = ps;
            self.energy.p_in = p_in;
            self.energy.p_diss = p_diss;
        }
        self.energy.contact_energy = contact.normal_energy;
    }
}
