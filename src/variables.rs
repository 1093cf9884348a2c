//! The variable table: every FMU variable is declared here once, from the scene. The model
//! description XML ([`crate::model_description`]), the getters and the setters
//! ([`crate::instance`]) all derive from this table.

use crate::scene::Scene;
use crate::scene::file::ProbeQuantity;
use crate::scene::params::ParamVariability;

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

/// Energy outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnergyKind {
    /// `energy.kinetic` = ½ vᵀ M v [J]
    Kinetic,
    /// `energy.potential` = −Q_gᵀ q, gravity potential relative to the origin [J]
    Potential,
    /// `energy.strain` = U [J]
    Strain,
    /// `energy.total` = kinetic + potential + strain [J]
    Total,
}

/// What an input drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputKind {
    /// Component `axis` (0 = x, 1 = y) of point load `load` [N].
    Load {
        /// Index into the scene's loads.
        load: usize,
        /// 0 = x, 1 = y.
        axis: usize,
    },
}

/// What an output reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputKind {
    /// A probe quantity.
    Probe {
        /// Index into the scene's probes.
        probe: usize,
        /// Position or velocity component.
        quantity: ProbeQuantity,
    },
    /// An energy.
    Energy(EnergyKind),
}

/// Role of a variable in the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// A parameter, by name.
    Parameter(&'static str),
    /// An input.
    Input(InputKind),
    /// An output.
    Output(OutputKind),
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
    /// Unit name (Real only), declared in UnitDefinitions.
    pub unit: Option<&'static str>,
    /// Description.
    pub description: String,
    /// Declared minimum.
    pub min: Option<f64>,
    /// Declared maximum.
    pub max: Option<f64>,
    /// What the variable means to the model.
    pub role: Role,
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

/// All variables of a scene, in value-reference order.
#[derive(Clone, Debug, PartialEq)]
pub struct VariableTable {
    vars: Vec<Variable>,
}

impl VariableTable {
    /// Declares the variables a scene needs: its parameters, one input per load component,
    /// the probe outputs and, if asked for, the energies.
    pub fn from_scene(scene: &Scene) -> Self {
        let mut vars = Vec::new();
        let mut push = |name: String,
                        ty: VarType,
                        causality: Causality,
                        variability: Variability,
                        start: Option<Value>,
                        unit: Option<&'static str>,
                        description: String,
                        range: (Option<f64>, Option<f64>),
                        role: Role| {
            let vr = vars.len() as u32;
            vars.push(Variable {
                name,
                vr,
                ty,
                causality,
                variability,
                start,
                unit,
                description,
                min: range.0,
                max: range.1,
                role,
            });
        };
        for p in &scene.params {
            push(
                p.name.to_string(),
                p.ty(),
                Causality::Parameter,
                match p.variability {
                    ParamVariability::Fixed => Variability::Fixed,
                    ParamVariability::Tunable => Variability::Tunable,
                },
                Some(p.start),
                if p.ty() == VarType::Real {
                    p.unit
                } else {
                    None
                },
                p.description.clone(),
                (p.min, p.max),
                Role::Parameter(p.name),
            );
        }
        for (i, l) in scene.file.loads.iter().enumerate() {
            for (axis, (comp, start)) in [("fx", l.fx), ("fy", l.fy)].into_iter().enumerate() {
                push(
                    format!("{}.{comp}", l.name),
                    VarType::Real,
                    Causality::Input,
                    Variability::Continuous,
                    Some(Value::Real(start)),
                    Some("N"),
                    format!(
                        "Force along {} at {} of the length (fixed direction)",
                        ["x", "y"][axis],
                        l.at
                    ),
                    (None, None),
                    Role::Input(InputKind::Load { load: i, axis }),
                );
            }
        }
        for (i, p) in scene.file.probes.iter().enumerate() {
            for q in &p.outputs {
                let (suffix, unit, what) = match q {
                    ProbeQuantity::X => ("x", "m", "Position x"),
                    ProbeQuantity::Y => ("y", "m", "Position y"),
                    ProbeQuantity::Vx => ("vx", "m/s", "Velocity x"),
                    ProbeQuantity::Vy => ("vy", "m/s", "Velocity y"),
                };
                push(
                    format!("{}.{suffix}", p.name),
                    VarType::Real,
                    Causality::Output,
                    Variability::Continuous,
                    None,
                    Some(unit),
                    format!("{what} of the centre line at {} of the length", p.at),
                    (None, None),
                    Role::Output(OutputKind::Probe {
                        probe: i,
                        quantity: *q,
                    }),
                );
            }
        }
        if scene.file.outputs.energy {
            for (kind, name, what) in [
                (EnergyKind::Kinetic, "kinetic", "Kinetic energy 1/2 v^T M v"),
                (
                    EnergyKind::Potential,
                    "potential",
                    "Gravity potential energy relative to y = 0 (-Q_g^T q)",
                ),
                (EnergyKind::Strain, "strain", "Strain energy U"),
                (
                    EnergyKind::Total,
                    "total",
                    "Kinetic + potential + strain energy",
                ),
            ] {
                push(
                    format!("energy.{name}"),
                    VarType::Real,
                    Causality::Output,
                    Variability::Continuous,
                    None,
                    Some("J"),
                    what.to_string(),
                    (None, None),
                    Role::Output(OutputKind::Energy(kind)),
                );
            }
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
    pub fn units(&self) -> Vec<&'static str> {
        let mut out: Vec<&'static str> = Vec::new();
        for u in self.vars.iter().filter_map(|v| v.unit) {
            if !out.contains(&u) {
                out.push(u);
            }
        }
        out
    }
}

/// SI base-unit exponents `(kg, m, s)` of the units flexfmu uses.
pub fn unit_exponents(unit: &str) -> Option<(i32, i32, i32)> {
    Some(match unit {
        "1" => (0, 0, 0),
        "m" => (0, 1, 0),
        "s" => (0, 0, 1),
        "m/s" => (0, 1, -1),
        "m/s2" => (0, 1, -2),
        "N" => (1, 1, -2),
        "Pa" => (1, -1, -2),
        "J" => (1, 2, -2),
        "kg/m3" => (1, -3, 0),
        _ => return None,
    })
}
