//! FMU parameters: definitions (name, type, unit, default from the scene file, admissible
//! values) and their validation, shared by the CLI and the FMU. Each scene kind declares its
//! own parameters (e.g. [`super::beam2d`]); the solver and gravity parameters are common.

use super::tables::{Choice, Gravity2d, Gravity3d, MaterialSection, SolverSection};
use crate::units::Unit;
use crate::variables::{Value, VarType};
use std::collections::BTreeMap;

/// Names of the common parameters (public interface: never rename silently).
pub mod names {
    /// Young's modulus [Pa].
    pub const MATERIAL_E: &str = "material.E";
    /// Poisson's ratio [1].
    pub const MATERIAL_NU: &str = "material.nu";
    /// Density [kg/m3].
    pub const MATERIAL_RHO: &str = "material.rho";
    /// Length [m].
    pub const GEOMETRY_LENGTH: &str = "geometry.length";
    /// Width [m].
    pub const GEOMETRY_WIDTH: &str = "geometry.width";
    /// Height [m].
    pub const GEOMETRY_HEIGHT: &str = "geometry.height";
    /// Element count (Integer).
    pub const MESH_N_ELEMENTS: &str = "mesh.n_elements";
    /// Element family of a planar beam (Integer: 1 = seed-000 shear-deformable ANCF, 2 = ANCF
    /// cable).
    pub const ELEMENT_TYPE: &str = "element.type";
    /// Shear integration rule (Integer: 1 = 1x1, 2 = 1x2).
    pub const ELEMENT_SHEAR_RULE: &str = "element.shear_rule";
    /// Strain-energy form (Integer: 1 = Eq. 12, 2 = Lamé).
    pub const ELEMENT_STRAIN_ENERGY: &str = "element.strain_energy";
    /// Shear correction factor [1].
    pub const ELEMENT_SHEAR_COEFFICIENT: &str = "element.shear_coefficient";
    /// Gravity x [m/s2].
    pub const GRAVITY_X: &str = "gravity.x";
    /// Gravity y [m/s2].
    pub const GRAVITY_Y: &str = "gravity.y";
    /// Gravity z [m/s2] (3D scenes).
    pub const GRAVITY_Z: &str = "gravity.z";
    /// Static solve at initialization (Boolean).
    pub const SOLVER_STATIC: &str = "solver.static_equilibrium";
    /// Integrator (Integer).
    pub const SOLVER_INTEGRATOR: &str = "solver.integrator";
    /// Spectral radius at infinity [1].
    pub const SOLVER_RHO_INF: &str = "solver.rho_inf";
    /// Largest internal step [s].
    pub const SOLVER_MAX_STEP: &str = "solver.max_step";
    /// Newton tolerance [1].
    pub const SOLVER_NEWTON_TOL: &str = "solver.newton_tolerance";
    /// Newton iteration limit (Integer).
    pub const SOLVER_MAX_ITER: &str = "solver.max_iterations";
    /// Initial load increments of the static solve (Integer).
    pub const SOLVER_LOAD_STEPS: &str = "solver.load_steps";
    /// Linear solver (Integer: 0 auto, 1 banded, 2 sparse LU).
    pub const SOLVER_LINEAR: &str = "solver.linear_solver";
    /// Newton variant (Integer: 1 full, 2 modified).
    pub const SOLVER_NEWTON: &str = "solver.newton";
    /// Local error tolerance of adaptive substeps [1] (0: fixed substeps).
    pub const SOLVER_TOLERANCE: &str = "solver.tolerance";
    /// Initial angular velocity about the first end [rad/s].
    pub const INITIAL_ANGULAR_VELOCITY: &str = "initial.angular_velocity";
}

use names::*;

/// Time integrators (values of `solver.integrator`).
pub const INTEGRATORS: &[(&str, i32)] = &[
    ("generalized_alpha", 1),
    ("newmark", 2),
    ("midpoint", 3),
    ("central_difference", 4),
    ("quasi_static", 5),
];
/// Newton variants (values of `solver.newton`).
pub const NEWTON_VARIANTS: &[(&str, i32)] = &[("full", 1), ("modified", 2)];
/// Linear solvers (values of `solver.linear_solver`).
pub const LINEAR_SOLVERS: &[(&str, i32)] = &[("auto", 0), ("banded", 1), ("sparse_lu", 2)];

/// Variability of a parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamVariability {
    /// Set before initialization ends; fixed afterwards.
    Fixed,
    /// May also be changed at communication points.
    Tunable,
}

/// Admissible values of a parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Check {
    /// Any finite value.
    Finite,
    /// `> 0`.
    Positive,
    /// `>= 0`.
    NonNegative,
    /// In the open interval `(lo, hi)`.
    Open(f64, f64),
    /// In the closed interval `[lo, hi]`.
    Closed(f64, f64),
    /// An Integer in `[lo, hi]`.
    IntRange(i32, i32),
    /// An Integer code from a table of named choices.
    Choice(&'static [(&'static str, i32)]),
    /// No check (Booleans).
    None,
}

impl Check {
    /// `None` if `v` is admissible, else what is required.
    pub fn violation(&self, v: Value) -> Option<String> {
        let real = |x: f64, ok: bool, what: String| {
            if !x.is_finite() {
                Some("must be a finite number".to_string())
            } else if !ok {
                Some(what)
            } else {
                None
            }
        };
        match (*self, v) {
            (Check::Finite, Value::Real(x)) => real(x, true, String::new()),
            (Check::Positive, Value::Real(x)) => real(x, x > 0.0, "must be positive".into()),
            (Check::NonNegative, Value::Real(x)) => {
                real(x, x >= 0.0, "must not be negative".into())
            }
            (Check::Open(lo, hi), Value::Real(x)) => {
                real(x, x > lo && x < hi, format!("must lie in ({lo}, {hi})"))
            }
            (Check::Closed(lo, hi), Value::Real(x)) => {
                real(x, x >= lo && x <= hi, format!("must lie in [{lo}, {hi}]"))
            }
            (Check::IntRange(lo, hi), Value::Integer(i)) => {
                (i < lo || i > hi).then(|| format!("must lie in [{lo}, {hi}]"))
            }
            (Check::Choice(table), Value::Integer(i)) => (!table.iter().any(|(_, c)| *c == i))
                .then(|| format!("must be one of {}", describe(table))),
            _ => None,
        }
    }

    /// Declared `min`/`max` for the model description.
    pub fn bounds(&self) -> (Option<f64>, Option<f64>) {
        match *self {
            Check::Positive | Check::NonNegative => (Some(0.0), None),
            Check::Open(lo, hi) | Check::Closed(lo, hi) => (Some(lo), Some(hi)),
            Check::IntRange(lo, hi) => (Some(lo as f64), Some(hi as f64)),
            Check::Choice(t) => (
                t.iter().map(|(_, c)| *c as f64).reduce(f64::min),
                t.iter().map(|(_, c)| *c as f64).reduce(f64::max),
            ),
            _ => (None, None),
        }
    }
}

/// Definition of one FMU parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamDef {
    /// Structured variable name.
    pub name: &'static str,
    /// Default value (from the scene file), which also fixes the type.
    pub start: Value,
    /// Unit (Real only).
    pub unit: Option<Unit>,
    /// Description.
    pub description: String,
    /// Fixed or tunable.
    pub variability: ParamVariability,
    /// Admissible values.
    pub check: Check,
}

impl ParamDef {
    /// A fixed parameter.
    pub fn new(
        name: &'static str,
        start: Value,
        unit: Option<Unit>,
        description: &str,
        check: Check,
    ) -> Self {
        Self {
            name,
            start,
            unit,
            description: description.to_string(),
            variability: ParamVariability::Fixed,
            check,
        }
    }

    /// The same parameter, tunable.
    pub fn tunable(mut self) -> Self {
        self.variability = ParamVariability::Tunable;
        self
    }

    /// Type of the parameter.
    pub fn ty(&self) -> VarType {
        self.start.ty()
    }
}

/// Resolves a choice given as code or name against a table; the error names the key.
pub fn resolve_choice(key: &str, choice: &Choice, table: &[(&str, i32)]) -> Result<i32, String> {
    let known = || {
        table
            .iter()
            .map(|(n, c)| format!("\"{n}\" ({c})"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    match choice {
        Choice::Code(c) => table
            .iter()
            .find(|(_, code)| i64::from(*code) == *c)
            .map(|(_, code)| *code)
            .ok_or_else(|| format!("{key}: unknown value {c}; expected one of {}", known())),
        Choice::Name(n) => table
            .iter()
            .find(|(name, _)| name == n)
            .map(|(_, code)| *code)
            .ok_or_else(|| format!("{key}: unknown value \"{n}\"; expected one of {}", known())),
    }
}

/// `"1 = a, 2 = b"` for descriptions and messages.
pub fn describe(table: &[(&str, i32)]) -> String {
    table
        .iter()
        .map(|(n, c)| format!("{c} = {n}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// An Integer from a TOML integer; the error names the key.
pub fn int_param(v: i64, key: &str) -> Result<i32, String> {
    i32::try_from(v).map_err(|_| format!("{key}: {v} does not fit a 32-bit Integer"))
}

/// The parameters `material.E` [Pa], `material.nu` [1] (in (−1, 0.5)) and `material.rho`
/// [kg/m3] of an isotropic elastic material.
pub fn material_params(m: &MaterialSection) -> Vec<ParamDef> {
    let real = Value::Real;
    vec![
        ParamDef::new(
            MATERIAL_E,
            real(m.E),
            Some(Unit::Pa),
            "Young's modulus",
            Check::Positive,
        ),
        ParamDef::new(
            MATERIAL_NU,
            real(m.nu),
            Some(Unit::One),
            "Poisson's ratio, in (-1, 0.5)",
            Check::Open(-1.0, 0.5),
        ),
        ParamDef::new(
            MATERIAL_RHO,
            real(m.rho),
            Some(Unit::KgPerM3),
            "Density",
            Check::Positive,
        ),
    ]
}

/// Gravity parameters `gravity.x`, `gravity.y` of a planar scene with a `[gravity]` table.
pub fn gravity_params_2d(g: Option<&Gravity2d>) -> Vec<ParamDef> {
    g.map_or(vec![], |g| gravity_params(&[g.x, g.y]))
}

/// Gravity parameters `gravity.x`, `gravity.y`, `gravity.z` of a 3D scene with a `[gravity]`
/// table.
pub fn gravity_params_3d(g: Option<&Gravity3d>) -> Vec<ParamDef> {
    g.map_or(vec![], |g| gravity_params(&[g.x, g.y, g.z]))
}

fn gravity_params(components: &[f64]) -> Vec<ParamDef> {
    [
        (GRAVITY_X, "Gravity, x component"),
        (GRAVITY_Y, "Gravity, y component"),
        (GRAVITY_Z, "Gravity, z component"),
    ]
    .iter()
    .zip(components)
    .map(|((name, what), v)| {
        ParamDef::new(
            name,
            Value::Real(*v),
            Some(Unit::MPerS2),
            what,
            Check::Finite,
        )
    })
    .collect()
}

/// The `solver.*` parameters common to every scene.
pub fn solver_params(s: &SolverSection) -> Result<Vec<ParamDef>, String> {
    Ok(vec![
        ParamDef::new(
            SOLVER_STATIC,
            Value::Boolean(s.static_equilibrium),
            None,
            "Solve the static equilibrium (Newton with load stepping) during initialization",
            Check::None,
        ),
        ParamDef::new(
            SOLVER_INTEGRATOR,
            Value::Integer(resolve_choice(
                SOLVER_INTEGRATOR,
                &s.integrator,
                INTEGRATORS,
            )?),
            None,
            &format!("Time integrator: {}", describe(INTEGRATORS)),
            Check::Choice(INTEGRATORS),
        ),
        ParamDef::new(
            SOLVER_RHO_INF,
            Value::Real(s.rho_inf),
            Some(Unit::One),
            "Spectral radius at infinite frequency of generalized-alpha, in [0, 1]",
            Check::Closed(0.0, 1.0),
        ),
        ParamDef::new(
            SOLVER_MAX_STEP,
            Value::Real(s.max_step),
            Some(Unit::S),
            "Largest internal time step",
            Check::Positive,
        )
        .tunable(),
        ParamDef::new(
            SOLVER_TOLERANCE,
            Value::Real(s.tolerance),
            Some(Unit::One),
            "Local error tolerance of adaptive internal steps, relative to the body length (0: fixed steps of solver.max_step)",
            Check::Closed(0.0, 1.0),
        )
        .tunable(),
        ParamDef::new(
            SOLVER_NEWTON,
            Value::Integer(resolve_choice(SOLVER_NEWTON, &s.newton, NEWTON_VARIANTS)?),
            None,
            &format!(
                "Newton iteration: {} (modified keeps the factorization while it converges fast)",
                describe(NEWTON_VARIANTS)
            ),
            Check::Choice(NEWTON_VARIANTS),
        )
        .tunable(),
        ParamDef::new(
            SOLVER_NEWTON_TOL,
            Value::Real(s.newton_tolerance),
            Some(Unit::One),
            "Newton tolerance on the increment, relative to the body length",
            Check::Open(0.0, 1.0),
        )
        .tunable(),
        ParamDef::new(
            SOLVER_MAX_ITER,
            Value::Integer(int_param(s.max_iterations, SOLVER_MAX_ITER)?),
            None,
            "Newton iterations before the time step or load increment is halved",
            Check::IntRange(1, 10_000),
        )
        .tunable(),
        ParamDef::new(
            SOLVER_LOAD_STEPS,
            Value::Integer(int_param(s.load_steps, SOLVER_LOAD_STEPS)?),
            None,
            "Initial number of load increments of the static solve (halved on failure)",
            Check::IntRange(1, 1_000_000),
        ),
        ParamDef::new(
            SOLVER_LINEAR,
            Value::Integer(resolve_choice(
                SOLVER_LINEAR,
                &s.linear_solver,
                LINEAR_SOLVERS,
            )?),
            None,
            &format!("Linear solver: {}", describe(LINEAR_SOLVERS)),
            Check::Choice(LINEAR_SOLVERS),
        ),
    ])
}

/// Current parameter values by name.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParamValues {
    values: BTreeMap<&'static str, Value>,
}

impl ParamValues {
    /// The defaults of a list of definitions.
    pub fn defaults(defs: &[ParamDef]) -> Self {
        Self {
            values: defs.iter().map(|d| (d.name, d.start)).collect(),
        }
    }

    /// Sets a value (the caller has checked the type).
    pub fn set(&mut self, name: &'static str, v: Value) {
        self.values.insert(name, v);
    }

    /// Value of a parameter, if the scene has it.
    pub fn get(&self, name: &str) -> Option<Value> {
        self.values.get(name).copied()
    }

    /// A Real parameter.
    ///
    /// # Panics
    /// If the scene has no such Real parameter (a programming error).
    pub fn real(&self, name: &str) -> f64 {
        match self.get(name) {
            Some(Value::Real(v)) => v,
            other => panic!("parameter {name} is not a Real: {other:?}"),
        }
    }

    /// An Integer parameter (panics like [`Self::real`]).
    pub fn integer(&self, name: &str) -> i32 {
        match self.get(name) {
            Some(Value::Integer(v)) => v,
            other => panic!("parameter {name} is not an Integer: {other:?}"),
        }
    }

    /// A Boolean parameter (panics like [`Self::real`]).
    pub fn boolean(&self, name: &str) -> bool {
        match self.get(name) {
            Some(Value::Boolean(v)) => v,
            other => panic!("parameter {name} is not a Boolean: {other:?}"),
        }
    }

    /// Checks every value against its definition; returns all problems, each naming the
    /// parameter, its value and what is required.
    pub fn validate(&self, defs: &[ParamDef]) -> Result<(), Vec<String>> {
        let mut errs = Vec::new();
        for d in defs {
            match self.get(d.name) {
                Some(v) if v.ty() != d.ty() => {
                    errs.push(format!("{}: wrong type {:?}", d.name, v.ty()))
                }
                Some(v) => {
                    if let Some(why) = d.check.violation(v) {
                        let shown = match v {
                            Value::Real(x) => format!("{x}"),
                            Value::Integer(i) => format!("{i}"),
                            Value::Boolean(b) => format!("{b}"),
                        };
                        errs.push(format!(
                            "{} = {shown} is invalid: {why} ({})",
                            d.name, d.description
                        ));
                    }
                }
                None => errs.push(format!("{}: missing", d.name)),
            }
        }
        if errs.is_empty() { Ok(()) } else { Err(errs) }
    }
}
