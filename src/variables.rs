//! The variable table: every FMU variable is declared here once, from the scene. The model
//! description XML ([`crate::model_description`]), the getters and the setters
//! ([`crate::instance`]) all derive from this table.

use crate::scene::Scene;
use crate::scene::params::ParamVariability;
use crate::units::Unit;

/// FMI base type of a variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VarType {
    /// fmi2Real
    Real,
    /// fmi2Integer
    Integer,
    /// fmi2Boolean
    Boolean,
}

/// A value of one of the FMI base types.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// Real
    Real(f64),
    /// Integer
    Integer(i32),
    /// Boolean
    Boolean(bool),
}

impl Value {
    /// Type of the value.
    pub fn ty(&self) -> VarType {
        match self {
            Value::Real(_) => VarType::Real,
            Value::Integer(_) => VarType::Integer,
            Value::Boolean(_) => VarType::Boolean,
        }
    }

    /// Text for the XML `start` attribute (shortest round-trip form for reals).
    pub fn xml(&self) -> String {
        match self {
            Value::Real(v) => format!("{v:?}"),
            Value::Integer(v) => v.to_string(),
            Value::Boolean(v) => v.to_string(),
        }
    }
}

/// FMI causality.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    /// parameter
    Parameter,
    /// input
    Input,
    /// output
    Output,
}

impl Causality {
    /// XML attribute value.
    pub fn as_str(&self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::Input => "input",
            Causality::Output => "output",
        }
    }
}

/// FMI variability.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    /// fixed
    Fixed,
    /// tunable
    Tunable,
    /// continuous
    Continuous,
}

impl Variability {
    /// XML attribute value.
    pub fn as_str(&self) -> &'static str {
        match self {
            Variability::Fixed => "fixed",
            Variability::Tunable => "tunable",
            Variability::Continuous => "continuous",
        }
    }
}

/// Role of a variable in the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// A parameter, by name.
    Parameter(&'static str),
    /// An input: its index among the scene's inputs (the kind's model knows what it drives).
    Input(usize),
    /// An output: its index among the scene's outputs.
    Output(usize),
}

/// One FMU variable.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    /// Structured name, e.g. `tip.x`.
    pub name: String,
    /// Value reference (unique across types; equals the position in the table).
    pub vr: u32,
    /// Base type.
    pub ty: VarType,
    /// Causality.
    pub causality: Causality,
    /// Variability.
    pub variability: Variability,
    /// Start value (parameters and inputs).
    pub start: Option<Value>,
    /// Unit (Real only), declared in UnitDefinitions.
    pub unit: Option<Unit>,
    /// Description.
    pub description: String,
    /// Declared minimum.
    pub min: Option<f64>,
    /// Declared maximum.
    pub max: Option<f64>,
    /// What the variable means to the model.
    pub role: Role,
    /// Outputs: value references of the inputs it depends on directly.
    pub depends_on: Vec<u32>,
}

impl Variable {
    /// The FMI `initial` attribute: exact for parameters, calculated for outputs, none for
    /// inputs.
    pub fn initial(&self) -> Option<&'static str> {
        match self.causality {
            Causality::Parameter => Some("exact"),
            Causality::Output => Some("calculated"),
            Causality::Input => None,
        }
    }
}

/// An input or output a scene kind declares (parameters come from
/// [`crate::scene::ParamDef`]). Its role is its position among the scene's inputs or outputs;
/// the kind keeps, in the same order, what each one means to its model
/// ([`crate::kinds::KindIo`]).
#[derive(Clone, Debug, PartialEq)]
pub struct IoVariable {
    /// Structured name.
    pub name: String,
    /// Input or output.
    pub causality: Causality,
    /// Start value (inputs).
    pub start: Option<f64>,
    /// Unit.
    pub unit: Unit,
    /// Description.
    pub description: String,
    /// For outputs: the inputs (by name) it depends on directly at a communication point
    /// (direct feedthrough, written as ModelStructure dependencies). Empty: none.
    pub depends_on: Vec<String>,
}

impl IoVariable {
    /// The same output with direct feedthrough from the named inputs.
    pub fn depending_on(&mut self, inputs: &[&str]) -> &mut Self {
        self.depends_on = inputs.iter().map(|s| s.to_string()).collect();
        self
    }
}

/// All variables of a scene, in value-reference order.
#[derive(Clone, Debug, PartialEq)]
pub struct VariableTable {
    vars: Vec<Variable>,
}

impl VariableTable {
    /// The variables of a scene: its parameters, then its inputs and outputs, in the order the
    /// scene declares them.
    pub fn from_scene(scene: &Scene) -> Self {
        let mut vars = Vec::new();
        for p in &scene.params {
            let (min, max) = p.check.bounds();
            vars.push(Variable {
                name: p.name.to_string(),
                vr: vars.len() as u32,
                ty: p.ty(),
                causality: Causality::Parameter,
                variability: match p.variability {
                    ParamVariability::Fixed => Variability::Fixed,
                    ParamVariability::Tunable => Variability::Tunable,
                },
                start: Some(p.start),
                unit: if p.ty() == VarType::Real {
                    p.unit
                } else {
                    None
                },
                description: p.description.clone(),
                min,
                max,
                role: Role::Parameter(p.name),
                depends_on: vec![],
            });
        }
        let first_io = vars.len();
        let (mut n_in, mut n_out) = (0, 0);
        for v in &scene.io {
            let role = match v.causality {
                Causality::Input => {
                    n_in += 1;
                    Role::Input(n_in - 1)
                }
                _ => {
                    n_out += 1;
                    Role::Output(n_out - 1)
                }
            };
            vars.push(Variable {
                name: v.name.clone(),
                vr: vars.len() as u32,
                ty: VarType::Real,
                causality: v.causality,
                variability: Variability::Continuous,
                start: v.start.map(Value::Real),
                unit: Some(v.unit),
                description: v.description.clone(),
                min: None,
                max: None,
                role,
                depends_on: vec![],
            });
        }
        for (k, v) in scene.io.iter().enumerate() {
            let mut deps: Vec<u32> = v
                .depends_on
                .iter()
                .map(|n| {
                    scene
                        .io
                        .iter()
                        .position(|w| &w.name == n && w.causality == Causality::Input)
                        .map(|i| (first_io + i) as u32)
                        .unwrap_or_else(|| panic!("{}: depends on unknown input {n}", v.name))
                })
                .collect();
            deps.sort_unstable();
            vars[first_io + k].depends_on = deps;
        }
        Self { vars }
    }

    /// All variables.
    pub fn vars(&self) -> &[Variable] {
        &self.vars
    }

    /// Variable with value reference `vr`.
    pub fn get(&self, vr: u32) -> Option<&Variable> {
        self.vars.get(vr as usize)
    }

    /// Variable by name.
    pub fn by_name(&self, name: &str) -> Option<&Variable> {
        self.vars.iter().find(|v| v.name == name)
    }

    /// Units used by the variables, in first-use order.
    pub fn units(&self) -> Vec<Unit> {
        let mut out: Vec<Unit> = Vec::new();
        for u in self.vars.iter().filter_map(|v| v.unit) {
            if !out.contains(&u) {
                out.push(u);
            }
        }
        out
    }
}
