//! The knobs of a convergence study: the parameters of a scene that trade accuracy for speed,
//! each with what it does to the answer (a different element family converges to a different
//! answer; counts, steps and tolerances converge to one answer) and where it is written in a
//! scene file. Each kind lists its own knobs ([`crate::kinds::KindScene::knobs`]); the solver
//! knobs every kind has are [`solver_knobs`].

use crate::scene::params::{INTEGRATORS, names};

/// What a knob does to the answer, and how the study varies it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum KnobRole {
    /// An element family (Integer codes): each family converges to its own answer (the
    /// seed-000 element has shear deformation, the cable has none), so each is measured
    /// against its own converged answer.
    Family(&'static [i32]),
    /// Discrete choices that converge to the same answer (integrator, mass matrix, ...): every
    /// code is tried at every mesh and step level.
    Variant(&'static [i32]),
    /// An Integer resolution (element count, contact points per element): doubled per
    /// refinement level, never below `min`. All counts of a scene move together by level. A
    /// scene value of 0 (the model chooses the count) stays 0.
    Count {
        /// Smallest admissible value.
        min: i32,
    },
    /// The largest internal step [s]: halved per refinement level.
    Step,
    /// The local error tolerance of adaptive steps (0 = fixed steps): the study adds adaptive
    /// runs with a ladder of tolerances.
    Tolerance,
}

/// Where a knob is written in a scene file: `[table] key = value`. `names` maps an Integer
/// code to the name the scene file uses (written as a string), when the key takes names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneKey {
    /// The table (`solver`, `mesh`, ...).
    pub table: &'static str,
    /// The key inside it.
    pub key: &'static str,
    /// Code → name table for keys written as names; `None`: the value itself is written.
    pub names: Option<&'static [(&'static str, i32)]>,
}

/// One knob of a scene: an FMU parameter the study varies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Knob {
    /// The FMU parameter (`mesh.n_elements`, `solver.max_step`, ...).
    pub param: &'static str,
    /// How the study varies it.
    pub role: KnobRole,
    /// Where the advised scene file sets it.
    pub key: SceneKey,
    /// Keys `(code, table, key)` the advised scene file must not have when the knob takes
    /// `code` (options of one family that another family's scene check rejects).
    pub drops: &'static [(i32, &'static str, &'static str)],
    /// The element families (codes of the family knob) the knob applies to; `None`: all. A
    /// knob that does not apply to a family is not varied for it and not written into its
    /// scene (the air spring's circumferential count is the shell level's only).
    pub families: Option<&'static [i32]>,
}

impl Knob {
    /// A knob written as `[table] key` where the parameter is `table.key`.
    pub fn new(param: &'static str, role: KnobRole) -> Self {
        let (table, key) = param.split_once('.').unwrap_or(("", param));
        Self {
            param,
            role,
            key: SceneKey {
                table,
                key,
                names: None,
            },
            drops: &[],
            families: None,
        }
    }

    /// The same knob, applying to the given families only.
    pub fn only_for(mut self, families: &'static [i32]) -> Self {
        self.families = Some(families);
        self
    }

    /// Whether the knob applies to `family` (`None`: the kind has no family knob).
    pub fn applies_to(&self, family: Option<i32>) -> bool {
        match (self.families, family) {
            (Some(fs), Some(f)) => fs.contains(&f),
            _ => true,
        }
    }

    /// The same knob, removing `drops` from the advised scene for the given codes.
    pub fn dropping(mut self, drops: &'static [(i32, &'static str, &'static str)]) -> Self {
        self.drops = drops;
        self
    }

    /// The same knob written at `[table] key`, by name from `names` when given.
    pub fn at(
        mut self,
        table: &'static str,
        key: &'static str,
        names: Option<&'static [(&'static str, i32)]>,
    ) -> Self {
        self.key = SceneKey { table, key, names };
        self
    }
}

/// The implicit integrators the study tries (the explicit scheme chooses its own step, which
/// for the stiff beams of the shipped scenes is far below any useful internal step).
pub const IMPLICIT_INTEGRATORS: &[i32] = &[1, 2, 3];

/// The solver knobs every kind has: integrator (implicit ones), internal step and the
/// tolerance of adaptive steps (`solver.*`, README "Parameters").
pub fn solver_knobs() -> Vec<Knob> {
    vec![
        Knob::new(
            names::SOLVER_INTEGRATOR,
            KnobRole::Variant(IMPLICIT_INTEGRATORS),
        )
        .at("solver", "integrator", Some(INTEGRATORS)),
        Knob::new(names::SOLVER_MAX_STEP, KnobRole::Step),
        Knob::new(names::SOLVER_TOLERANCE, KnobRole::Tolerance),
    ]
}
