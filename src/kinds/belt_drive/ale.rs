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
