//! Pulleys of the belt drive: their definitions, driven (prescribed angle and speed) or free
//! (rigid body with inertia and bearing damping) motion, their inputs as signals of time and
//! the belt's loads on them.

use super::PulleySide;
use super::model::BeltDrive;
use super::scene::PulleyInput;
use crate::model::JacobianCoeffs;
use crate::model::inputs::{InputSignal, prescribed};
use crate::snapshot::{StateReader, StateWriter};
use nalgebra::Vector2;

/// How a pulley moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PulleyKind {
    /// Angle and speed prescribed by inputs.
    Driven,
    /// Rigid body: moment of inertia [kg m²] and bearing damping [N m s/rad].
    Free {
        /// Moment of inertia [kg m²].
        inertia: f64,
        /// Bearing damping [N m s/rad].
        damping: f64,
    },
}

/// A pulley of the drive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PulleyDef {
    /// Centre [m].
    pub center: Vector2<f64>,
    /// Radius [m] (the belt's inner face rests on it).
    pub radius: f64,
    /// Driven or free.
    pub kind: PulleyKind,
    /// Which face of the belt runs on it (back: wrapped clockwise, outside the loop).
    pub side: PulleySide,
}

/// Inputs and committed results of one pulley.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct PulleyIo {
    /// Prescribed angle [rad], speed [rad/s] (driven) and input torque [N m] (free) as
    /// signals of time (`fmi2SetRealInputDerivatives`).
    pub(super) angle_in: InputSignal,
    pub(super) omega_in: InputSignal,
    pub(super) torque_in: InputSignal,
    // results of the committed state
    pub(super) torque: f64,
    pub(super) force: Vector2<f64>,
}

impl BeltDrive {
    /// Pitch radius of pulley `k` [m].
    pub fn pitch_radius(&self, k: usize) -> f64 {
        self.pitch[k]
    }

    /// Centre of pulley `k` [m] in the committed state (a tensioner's idler moves with its
    /// arm).
    pub fn pulley_center(&self, k: usize) -> Vector2<f64> {
        match &self.tensioner {
            Some(t) if t.def.pulley == k => t.contact.obstacles()[0].center(self.q[t.dof]),
            _ => self.spec.pulleys[k].center,
        }
    }

    /// Prescribed angle, speed and angular acceleration of a driven pulley at time `t`: the
    /// angle input's polynomial if it has derivatives, else the angle advanced with the speed
    /// input ([`prescribed`]).
    pub(super) fn driven(&self, k: usize, t: f64) -> (f64, f64, f64) {
        let io = &self.io[k];
        prescribed(&io.angle_in, &io.omega_in, t)
    }

    /// Sets the driven pulleys' angles and speeds into full vectors. In a static solve
    /// ([`MechanicalSystem::hold_for_statics`]) the driven pulleys stand at their angles with
    /// zero speed and acceleration: statics is the belt at rest, and a master that starts a
    /// driven pulley at speed (`pulleyN.omega` start value ≠ 0) must not make the friction of
    /// the static problem slide (it did: "static equilibrium not found" at
    /// `fmi2ExitInitializationMode`); the dynamics then start from rest with the pulley at its
    /// speed.
    ///
    /// [`MechanicalSystem::hold_for_statics`]: crate::model::MechanicalSystem::hold_for_statics
    pub(super) fn prescribe(&self, t: f64, q: &mut [f64], v: &mut [f64], a: Option<&mut [f64]>) {
        let mut a = a;
        let at_rest = self.held_angles.is_some();
        for (k, p) in self.spec.pulleys.iter().enumerate() {
            if p.kind == PulleyKind::Driven {
                let (th, om, al) = self.driven(k, t);
                let (om, al) = if at_rest { (0.0, 0.0) } else { (om, al) };
                q[self.pulley_dof[k]] = th;
                v[self.pulley_dof[k]] = om;
                if let Some(a) = a.as_deref_mut() {
                    a[self.pulley_dof[k]] = al;
                }
            }
        }
    }

    /// Sets a pulley input (the typed form of `Model::set_input`).
    pub fn set_pulley_input(&mut self, pulley: usize, quantity: PulleyInput, value: f64) {
        if quantity == PulleyInput::Angle
            && self.t0_step.is_none()
            && self.spec.pulleys[pulley].kind == PulleyKind::Driven
            && value.is_finite()
        {
            let pd = self.pulley_dof[pulley];
            let turn = value - self.q[pd];
            if let Some(k) = self.fixed.iter().position(|&k| k == pulley) {
                self.contact.shift_obstacle(k, 0, turn);
            }
            self.q[pd] = value;
        }
        let t = self.t;
        self.signal(pulley, quantity).set(value, t);
    }

    /// `1 − ω_last ρ_last / (ω_1 ρ_1)` at full velocities `v`.
    pub(super) fn slip_of(&self, v: &[f64]) -> f64 {
        self.pulley_slip_of(self.spec.pulleys.len() - 1, v)
    }

    /// Wrap direction of pulley `k`: +1 front side, −1 back side.
    pub fn side_sign(&self, k: usize) -> f64 {
        match self.spec.pulleys[k].side {
            PulleySide::Front => 1.0,
            PulleySide::Back => -1.0,
        }
    }

    /// Slip of pulley `k` against pulley 1: `1 − s_k ω_k ρ_k / (s_1 ω_1 ρ_1)` (`s = ±1`
    /// the wrap direction, `ρ` the pitch radius) at full velocities `v`; 0 while pulley 1 is
    /// at rest.
    pub(super) fn pulley_slip_of(&self, k: usize, v: &[f64]) -> f64 {
        let v1 = self.side_sign(0) * v[self.pulley_dof[0]] * self.pitch[0];
        let vk = self.side_sign(k) * v[self.pulley_dof[k]] * self.pitch[k];
        if v1.abs() > 1e-12 { 1.0 - vk / v1 } else { 0.0 }
    }

    /// The signal of a pulley input.
    pub(super) fn signal(&mut self, pulley: usize, quantity: PulleyInput) -> &mut InputSignal {
        let io = &mut self.io[pulley];
        match quantity {
            PulleyInput::Angle => &mut io.angle_in,
            PulleyInput::Omega => &mut io.omega_in,
            PulleyInput::Torque => &mut io.torque_in,
        }
    }

    /// Torque of the belt on pulley `k` [N m] (committed state).
    pub fn pulley_torque(&self, k: usize) -> f64 {
        self.io[k].torque
    }

    /// Force of the belt on pulley `k` [N].
    pub fn pulley_force(&self, k: usize) -> Vector2<f64> {
        self.io[k].force
    }

    /// Angle and speed of pulley `k` (committed state).
    pub fn pulley_motion(&self, k: usize) -> (f64, f64) {
        (self.q[self.pulley_dof[k]], self.v[self.pulley_dof[k]])
    }

    /// Adds the free pulleys' equations `J θ̈ + c θ̇ − τ_in` (plus the bearing spring of a
    /// held pulley during static solves) into the full residual `f` and the iteration matrix.
    pub(super) fn add_pulley_residual(
        &self,
        t: f64,
        f: &mut [f64],
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) {
        for (k, p) in self.spec.pulleys.iter().enumerate() {
            if let PulleyKind::Free { inertia, damping } = p.kind {
                let pd = self.pulley_dof[k];
                f[pd] += inertia * self.aw[pd] + damping * self.vw[pd] - self.io[k].torque_in.at(t);
                // bearing spring of a held pulley while the belt is mounted [N m/rad]; with a
                // tensioner a soft one (1e-6 of the stiff), so that the free pulleys turn
                // with the belt as the arm settles and every span ends at one tension
                let k_hold = match &self.held_angles {
                    Some(held) => {
                        let factor = if self.tensioner.is_some() { 1e-3 } else { 1e3 };
                        let k_hold = factor * self.spec.section.ea * p.radius * p.radius;
                        f[pd] += k_hold * (self.qw[pd] - held[k]);
                        k_hold
                    }
                    None => 0.0,
                };
                if let Some((c, vals)) = jac.as_mut() {
                    let m = c.mass * inertia + c.damping * damping + c.stiffness * k_hold;
                    self.asm.add_entry(pd, pd, m, vals);
                }
            }
        }
    }

    /// Writes the pulleys' input signals and committed results into a snapshot.
    pub(super) fn save_pulleys(&self, w: &mut StateWriter) {
        w.u64(self.io.len() as u64);
        for io in &self.io {
            for sig in [&io.angle_in, &io.omega_in, &io.torque_in] {
                sig.save(w);
            }
            for x in [io.torque, io.force.x, io.force.y] {
                w.f64(x);
            }
        }
    }

    /// Reads what [`Self::save_pulleys`] wrote.
    pub(super) fn restore_pulleys(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        if r.u64().map_err(e)? as usize != self.io.len() {
            return Err("pulleys of another drive".into());
        }
        for io in self.io.iter_mut() {
            io.angle_in = InputSignal::restore(r).map_err(e)?;
            io.omega_in = InputSignal::restore(r).map_err(e)?;
            io.torque_in = InputSignal::restore(r).map_err(e)?;
            io.torque = r.f64().map_err(e)?;
            io.force = Vector2::new(r.f64().map_err(e)?, r.f64().map_err(e)?);
        }
        Ok(())
    }
}
