//! FMU parameters of a scene: their definitions (name, type, unit, default from the scene file)
//! and the validation of their values, shared by the CLI and the FMU.

use super::file::{Choice, SceneFile};
use crate::variables::{Value, VarType};
use std::collections::BTreeMap;

/// Parameter names (public interface: never rename silently).
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
}

use names::*;

/// Time integrators (values of `solver.integrator`).
pub const INTEGRATORS: &[(&str, i32)] =
    &[("generalized_alpha", 1), ("newmark", 2), ("midpoint", 3)];
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

/// Definition of one FMU parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamDef {
    /// Structured variable name.
    pub name: &'static str,
    /// Default value (from the scene file), which also fixes the type.
    pub start: Value,
    /// Unit (Real only).
    pub unit: Option<&'static str>,
    /// Description.
    pub description: String,
    /// Fixed or tunable.
    pub variability: ParamVariability,
    /// Declared lower bound, if any.
    pub min: Option<f64>,
    /// Declared upper bound, if any.
    pub max: Option<f64>,
}

impl ParamDef {
    fn new(
        name: &'static str,
        start: Value,
        unit: Option<&'static str>,
        description: &str,
    ) -> Self {
        Self {
            name,
            start,
            unit,
            description: description.to_string(),
            variability: ParamVariability::Fixed,
            min: None,
            max: None,
        }
    }
    fn range(mut self, min: Option<f64>, max: Option<f64>) -> Self {
        self.min = min;
        self.max = max;
        self
    }
    fn tunable(mut self) -> Self {
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

fn describe(table: &[(&str, i32)]) -> String {
    table
        .iter()
        .map(|(n, c)| format!("{c} = {n}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The parameters a scene exposes, with the scene's values as defaults.
pub fn parameter_defs(scene: &SceneFile) -> Result<Vec<ParamDef>, String> {
    let int = |v: i64, key: &str| -> Result<i32, String> {
        i32::try_from(v).map_err(|_| format!("{key}: {v} does not fit a 32-bit Integer"))
    };
    let mut defs = vec![
        ParamDef::new(MATERIAL_E, Value::Real(scene.material.E), Some("Pa"), "Young's modulus")
            .range(Some(0.0), None),
        ParamDef::new(MATERIAL_NU, Value::Real(scene.material.nu), Some("1"), "Poisson's ratio, in (-1, 0.5)")
            .range(Some(-1.0), Some(0.5)),
        ParamDef::new(MATERIAL_RHO, Value::Real(scene.material.rho), Some("kg/m3"), "Density")
            .range(Some(0.0), None),
        ParamDef::new(GEOMETRY_LENGTH, Value::Real(scene.geometry.length), Some("m"), "Undeformed length")
            .range(Some(0.0), None),
        ParamDef::new(GEOMETRY_WIDTH, Value::Real(scene.geometry.width), Some("m"), "Cross-section width (out of plane)")
            .range(Some(0.0), None),
        ParamDef::new(GEOMETRY_HEIGHT, Value::Real(scene.geometry.height), Some("m"), "Cross-section height")
            .range(Some(0.0), None),
        ParamDef::new(
            MESH_N_ELEMENTS,
            Value::Integer(int(scene.mesh.n_elements, MESH_N_ELEMENTS)?),
            None,
            "Number of elements",
        )
        .range(Some(1.0), None),
        ParamDef::new(
            ELEMENT_SHEAR_RULE,
            Value::Integer(scene.element.shear_rule),
            None,
            "Shear-energy integration: 1 = original 1x1 rule, 2 = the 1x2 fix (Kerkkanen et al. 2003, sections 5 and 7)",
        )
        .range(Some(1.0), Some(2.0)),
        ParamDef::new(
            ELEMENT_STRAIN_ENERGY,
            Value::Integer(scene.element.strain_energy),
            None,
            "Strain energy: 1 = Eq. 12 (no Poisson coupling), 2 = Lame form of Eqs. 10-11",
        )
        .range(Some(1.0), Some(2.0)),
        ParamDef::new(
            ELEMENT_SHEAR_COEFFICIENT,
            Value::Real(scene.element.shear_coefficient),
            Some("1"),
            "Shear correction factor k_s of Eq. 12",
        )
        .range(Some(0.0), None),
    ];
    if let Some(g) = &scene.gravity {
        defs.push(ParamDef::new(
            GRAVITY_X,
            Value::Real(g.x),
            Some("m/s2"),
            "Gravity, x component",
        ));
        defs.push(ParamDef::new(
            GRAVITY_Y,
            Value::Real(g.y),
            Some("m/s2"),
            "Gravity, y component",
        ));
    }
    let s = &scene.solver;
    defs.extend([
        ParamDef::new(
            SOLVER_STATIC,
            Value::Boolean(s.static_equilibrium),
            None,
            "Solve the static equilibrium (Newton with load stepping) during initialization",
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
        )
        .range(Some(1.0), Some(INTEGRATORS.len() as f64)),
        ParamDef::new(
            SOLVER_RHO_INF,
            Value::Real(s.rho_inf),
            Some("1"),
            "Spectral radius at infinite frequency of generalized-alpha, in [0, 1]",
        )
        .range(Some(0.0), Some(1.0)),
        ParamDef::new(
            SOLVER_MAX_STEP,
            Value::Real(s.max_step),
            Some("s"),
            "Largest internal time step",
        )
        .range(Some(0.0), None)
        .tunable(),
        ParamDef::new(
            SOLVER_NEWTON_TOL,
            Value::Real(s.newton_tolerance),
            Some("1"),
            "Newton tolerance on the increment, relative to the body length",
        )
        .range(Some(0.0), None)
        .tunable(),
        ParamDef::new(
            SOLVER_MAX_ITER,
            Value::Integer(int(s.max_iterations, SOLVER_MAX_ITER)?),
            None,
            "Newton iterations before the time step or load increment is halved",
        )
        .range(Some(1.0), None)
        .tunable(),
        ParamDef::new(
            SOLVER_LOAD_STEPS,
            Value::Integer(int(s.load_steps, SOLVER_LOAD_STEPS)?),
            None,
            "Initial number of load increments of the static solve (halved on failure)",
        )
        .range(Some(1.0), None),
        ParamDef::new(
            SOLVER_LINEAR,
            Value::Integer(resolve_choice(
                SOLVER_LINEAR,
                &s.linear_solver,
                LINEAR_SOLVERS,
            )?),
            None,
            &format!("Linear solver: {}", describe(LINEAR_SOLVERS)),
        )
        .range(Some(0.0), Some(2.0)),
    ]);
    Ok(defs)
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

    /// Checks every value; returns all problems, each naming the parameter.
    pub fn validate(&self) -> Result<(), Vec<String>> {
        let mut errs = Vec::new();
        let mut real = |name: &str, ok: fn(f64) -> bool, what: &str| {
            if let Some(Value::Real(v)) = self.get(name) {
                if !v.is_finite() {
                    errs.push(format!("{name} = {v} is not a finite number"));
                } else if !ok(v) {
                    errs.push(format!("{name} = {v} is invalid: {what}"));
                }
            }
        };
        real(MATERIAL_E, |v| v > 0.0, "Young's modulus must be positive");
        real(
            MATERIAL_NU,
            |v| v > -1.0 && v < 0.5,
            "Poisson's ratio must lie in (-1, 0.5)",
        );
        real(MATERIAL_RHO, |v| v > 0.0, "density must be positive");
        real(GEOMETRY_LENGTH, |v| v > 0.0, "length must be positive");
        real(GEOMETRY_WIDTH, |v| v > 0.0, "width must be positive");
        real(GEOMETRY_HEIGHT, |v| v > 0.0, "height must be positive");
        real(
            ELEMENT_SHEAR_COEFFICIENT,
            |v| v > 0.0,
            "shear coefficient must be positive",
        );
        real(GRAVITY_X, |_| true, "");
        real(GRAVITY_Y, |_| true, "");
        real(
            SOLVER_RHO_INF,
            |v| (0.0..=1.0).contains(&v),
            "must lie in [0, 1]",
        );
        real(SOLVER_MAX_STEP, |v| v > 0.0, "must be positive");
        real(
            SOLVER_NEWTON_TOL,
            |v| v > 0.0 && v < 1.0,
            "must lie in (0, 1)",
        );
        let mut int = |name: &str, lo: i32, hi: i32, what: &str| {
            if let Some(Value::Integer(v)) = self.get(name) {
                if v < lo || v > hi {
                    errs.push(format!("{name} = {v} is invalid: {what}"));
                }
            }
        };
        int(
            MESH_N_ELEMENTS,
            1,
            1_000_000,
            "need at least 1 element (at most 1e6)",
        );
        int(
            ELEMENT_SHEAR_RULE,
            1,
            2,
            "1 = original 1x1 rule, 2 = the 1x2 fix",
        );
        int(ELEMENT_STRAIN_ENERGY, 1, 2, "1 = Eq. 12, 2 = Lame form");
        int(
            SOLVER_INTEGRATOR,
            1,
            INTEGRATORS.len() as i32,
            &describe(INTEGRATORS),
        );
        int(SOLVER_MAX_ITER, 1, 10_000, "must be at least 1");
        int(SOLVER_LOAD_STEPS, 1, 1_000_000, "must be at least 1");
        int(SOLVER_LINEAR, 0, 2, &describe(LINEAR_SOLVERS));
        if errs.is_empty() { Ok(()) } else { Err(errs) }
    }
}
