//! The belt tensioner: an idler (one of the drive's free pulleys) on an arm pivoting about a
//! fixed point, loaded by a pre-loaded torsion spring and a viscous damper. The arm angle `ψ`
//! (polar angle of the idler centre about the pivot, counter-clockwise) is one extra coordinate
//! after the pulley angles; the idler's contact is an [`ArmPulley`] whose centre moves with `ψ`.
//!
//! Arm equation: `I ψ̈ + c ψ̇ + k (ψ − ψ_free) − Σ Q_ψ = 0` with `Q_ψ = −F·c'(ψ)` the moment
//! of the belt's contact forces on the idler about the pivot ([`crate::contact::arm_pulley`]).
//! The spring's free angle `ψ_free = ψ_d + σ τ_pre / k` puts the pre-load torque `τ_pre` at the
//! design angle `ψ_d` (the idler centre of the scene), turning the idler into the belt: `σ = ±1`
//! opposes the moment of the mounted belt's tension on the idler at the design angle.

use super::model::BeltDrive;
use crate::contact::{ArmPulley, ContactPointSet};
use crate::meshers::belt_loop::Loop;
use crate::model::JacobianCoeffs;
use nalgebra::Vector2;

/// A tensioner as the model is built from it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TensionerDef {
    /// Index of its idler among the pulleys (a free pulley; 0 for `pulley1`).
    pub pulley: usize,
    /// Pivot of the arm [m].
    pub pivot: Vector2<f64>,
    /// Torsion spring stiffness `k` [N m/rad].
    pub stiffness: f64,
    /// Spring torque at the design angle `τ_pre` [N m] (≥ 0; it turns the idler into the
    /// belt).
    pub preload: f64,
    /// Viscous damping of the arm `c` [N m s/rad].
    pub damping: f64,
    /// Moment of inertia of arm and idler about the pivot `I` [kg m²].
    pub inertia: f64,
}

/// The tensioner in a running model.
#[derive(Clone, Debug)]
pub(super) struct Tensioner {
    pub(super) def: TensionerDef,
    /// Full index of `ψ`.
    pub(super) dof: usize,
    /// Design angle `ψ_d` [rad].
    pub(super) design: f64,
    /// Free angle of the spring `ψ_free` [rad].
    pub(super) free_angle: f64,
    /// Free angle `ψ_m` at which the spring balances the mounted belt (one tension, the
    /// mounting tension, on the design layout) at the design angle [rad]: the start of the
    /// static pre-load's continuation in the spring's pre-load (see
    /// [`BeltDrive::add_tensioner_residual`]).
    pub(super) mounted_free_angle: f64,
    /// Contact of the belt with the idler; blocks: element coordinates, idler angle, `ψ`.
    pub(super) contact: ContactPointSet<ArmPulley, 2, 4, 10>,
    /// Moment of the belt on the arm in the committed state [N m].
    pub(super) belt_moment: f64,
}

/// What [`design`] finds of a tensioner on its loop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Design {
    /// Design angle `ψ_d` [rad] (polar angle of the idler centre about the pivot).
    pub(super) angle: f64,
    /// Arm length `|c − p|` [m].
    pub(super) arm: f64,
    /// Spring direction `σ = ±1`.
    pub(super) sigma: f64,
    /// Moment arm of the belt's tension about the pivot `|(c − p) × (t_out − t_in)|` [m]: a
    /// belt of one tension `T` has the moment `T` times this on the arm.
    pub(super) lever: f64,
}

/// Design angle, arm length, spring direction `σ` and lever of a tensioner whose idler `j` has
/// the centre `c` on the loop `lp` (`σ` opposes the moment of the belt's tension on the idler,
/// `(c − p) × (t_out − t_in)`, t the unit directions of the leaving and arriving spans).
pub(super) fn design(def: &TensionerDef, lp: &Loop) -> Result<Design, String> {
    let j = def.pulley;
    let n = lp.circles.len();
    let c = lp.circles[j].center;
    let arm = c - def.pivot;
    let l = arm.norm();
    if l.is_nan() || l <= lp.circles[j].radius * 1e-3 {
        return Err(format!(
            "tensioner.pivot: the pivot must lie away from the idler centre (pulley{})",
            j + 1
        ));
    }
    let dir = |i: usize| {
        let s = &lp.spans[i];
        (s.end - s.start).normalize()
    };
    let f = dir(j) - dir((j + n - 1) % n);
    let m = arm.x * f.y - arm.y * f.x;
    if m.abs() <= 1e-6 * l * f.norm().max(1e-12) {
        return Err(format!(
            "tensioner.pivot (with pulley{}.center and the pulleys' center, radius and side): the arm of pulley{} points along the belt's force on the idler, the spring cannot tension the belt",
            j + 1,
            j + 1
        ));
    }
    Ok(Design {
        angle: arm.y.atan2(arm.x),
        arm: l,
        sigma: -m.signum(),
        lever: m.abs(),
    })
}

impl BeltDrive {
    /// Arm angle from the design angle [rad] (committed state), 0 without a tensioner.
    pub fn tensioner_angle(&self) -> f64 {
        self.tensioner
            .as_ref()
            .map_or(0.0, |t| self.q[t.dof] - t.design)
    }

    /// Spring plus damper torque on the arm [N m] at full coordinates `q` and velocities `v`.
    pub(super) fn tensioner_torque_of(&self, q: &[f64], v: &[f64]) -> f64 {
        self.tensioner.as_ref().map_or(0.0, |t| {
            -t.def.stiffness * (q[t.dof] - t.free_angle) - t.def.damping * v[t.dof]
        })
    }

    /// Spring plus damper torque on the arm [N m] (committed state).
    pub fn tensioner_torque(&self) -> f64 {
        self.tensioner_torque_of(&self.q, &self.v)
    }

    /// Moment of the belt's contact forces on the arm about the pivot [N m] (committed).
    pub fn tensioner_belt_moment(&self) -> f64 {
        self.tensioner.as_ref().map_or(0.0, |t| t.belt_moment)
    }

    /// Elastic energy of the spring `½ k (ψ − ψ_free)²` [J] at full coordinates `q`.
    pub(super) fn tensioner_energy_of(&self, q: &[f64]) -> f64 {
        self.tensioner.as_ref().map_or(0.0, |t| {
            0.5 * t.def.stiffness * (q[t.dof] - t.free_angle).powi(2)
        })
    }

    /// Adds the arm equation `I ψ̈ + c ψ̇ + k (ψ − ψ_free)` into the full residual and the
    /// iteration matrix (the contact adds its own terms).
    ///
    /// During static solves (free pulleys held, [`MechanicalSystem::hold_for_statics`]) the
    /// spring's free angle follows the load factor `λ`: `ψ_m + λ (ψ_free − ψ_m)`, from the
    /// angle `ψ_m` that balances the mounted belt at the design angle to the scene's. The
    /// static solver's load stepping then walks the arm from the mounted state to its
    /// equilibrium (a pre-load far from the mounting tension's balance moves the arm by tens
    /// of mrad, which one Newton solve from the mounted state does not converge to); at
    /// `λ = 1`, and in every dynamic step, the spring is the scene's.
    ///
    /// [`MechanicalSystem::hold_for_statics`]: crate::model::MechanicalSystem::hold_for_statics
    pub(super) fn add_tensioner_residual(
        &self,
        load_factor: f64,
        f: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) {
        let Some(t) = &self.tensioner else { return };
        let d = t.dof;
        let def = &t.def;
        let free = if self.held_angles.is_some() {
            t.mounted_free_angle + load_factor * (t.free_angle - t.mounted_free_angle)
        } else {
            t.free_angle
        };
        f[d] += def.inertia * self.aw[d]
            + def.damping * self.vw[d]
            + def.stiffness * (self.qw[d] - free);
        if let Some((c, vals)) = jac {
            let m = c.mass * def.inertia + c.damping * def.damping + c.stiffness * def.stiffness;
            self.asm.add_entry(d, d, m, vals);
        }
    }
}
