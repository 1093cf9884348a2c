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

/// What a pulley input sets (belt-drive scenes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PulleyInput {
    /// `pulleyN.angle`: prescribed angle of a driven pulley [rad].
    Angle,
    /// `pulleyN.omega`: prescribed angular velocity of a driven pulley [rad/s].
    Omega,
    /// `pulleyN.torque_in`: external torque on a free pulley [N m].
    Torque,
}

/// What an input drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputKind {
    /// Component `axis` (0 = x, 1 = y, 2 = z) of the force of point load `load` [N].
    Load {
        /// Index into the scene's loads.
        load: usize,
        /// 0 = x, 1 = y, 2 = z.
        axis: usize,
    },
    /// Component `axis` (0 = x, 1 = y, 2 = z) of the moment of point load `load` [N m]
    /// (3D scenes).
    Moment {
        /// Index into the scene's loads.
        load: usize,
        /// 0 = x, 1 = y, 2 = z.
        axis: usize,
    },
    /// Prescribed motion of a port: `component` 0, 1 = position x, y [m]; 2, 3 = velocity
    /// x, y [m/s].
    Motion {
        /// Index into the scene's motion ports.
        port: usize,
        /// 0 = x, 1 = y, 2 = vx, 3 = vy.
        component: usize,
    },
    /// A pulley input (belt-drive scenes).
    Pulley {
        /// Index of the pulley (0 for `pulley1`).
        pulley: usize,
        /// Which quantity.
        quantity: PulleyInput,
    },
}

/// Outputs of belt-drive scenes (pulley indices start at 0 for `pulley1`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BeltOutput {
    /// `pulleyN.torque`: torque the belt exerts on the pulley about its centre [N m]
    /// (counter-clockwise positive).
    PulleyTorque(usize),
    /// `pulleyN.force_x`: force the belt exerts on the pulley, x [N].
    PulleyForceX(usize),
    /// `pulleyN.force_y`: force the belt exerts on the pulley, y [N].
    PulleyForceY(usize),
    /// `pulleyN.angle` of a free pulley [rad].
    PulleyAngle(usize),
    /// `pulleyN.omega` of a free pulley [rad/s].
    PulleyOmega(usize),
    /// `belt.tension_tight`: the larger span tension [N].
    TensionTight,
    /// `belt.tension_slack`: the smaller span tension [N].
    TensionSlack,
    /// `belt.slip`: `1 − ω_last ρ_last / (ω_1 ρ_1)` (speed loss by creep and slip) [1].
    Slip,
    /// `belt.speed`: mean speed of the belt nodes [m/s].
    Speed,
    /// `belt.point[i].x` [m].
    PointX(usize),
    /// `belt.point[i].y` [m].
    PointY(usize),
    /// `energy.input_work`: work of the pulley drives and input torques since t = 0 [J].
    InputWork,
    /// `energy.dissipated`: energy dissipated by contact, friction and damping since t = 0 [J].
    Dissipated,
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
    /// Force exerted by the body on whatever drives a motion port [N], component `axis`.
    Reaction {
        /// Index into the scene's motion ports.
        port: usize,
        /// 0 = x, 1 = y.
        axis: usize,
    },
    /// A belt-drive output.
    Belt(BeltOutput),
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
/// [`crate::scene::ParamDef`]).
#[derive(Clone, Debug, PartialEq)]
pub struct IoVariable {
    /// Structured name.
    pub name: String,
    /// Input or output.
    pub causality: Causality,
    /// Start value (inputs).
    pub start: Option<f64>,
    /// Unit.
    pub unit: &'static str,
    /// Description.
    pub description: String,
    /// Role in the model.
    pub role: Role,
    /// For outputs: the inputs (by name) it depends on directly at a communication point
    /// (direct feedthrough, written as ModelStructure dependencies). Empty: none.
    pub depends_on: Vec<String>,
}

impl IoVariable {
    /// A continuous Real input.
    pub fn input(
        name: String,
        start: f64,
        unit: &'static str,
        description: String,
        kind: InputKind,
    ) -> Self {
        Self {
            name,
            causality: Causality::Input,
            start: Some(start),
            unit,
            description,
            role: Role::Input(kind),
            depends_on: vec![],
        }
    }

    /// A continuous Real output.
    pub fn output(name: String, unit: &'static str, description: String, kind: OutputKind) -> Self {
        Self {
            name,
            causality: Causality::Output,
            start: None,
            unit,
            description,
            role: Role::Output(kind),
            depends_on: vec![],
        }
    }

    /// The same output with direct feedthrough from the named inputs.
    pub fn depending_on(mut self, inputs: &[&str]) -> Self {
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
        for v in &scene.io {
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
                role: v.role,
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
        "rad/s" => (0, 0, -1),
        "N" => (1, 1, -2),
        "Pa" => (1, -1, -2),
        "J" => (1, 2, -2),
        "kg/m3" => (1, -3, 0),
        "N.m" => (1, 2, -2),
        "N.m2" => (1, 3, -2),
        "kg/m" => (1, -1, 0),
        "kg.m" => (1, 1, 0),
        // radians are dimensionless in SI base units
        "rad" => (0, 0, 0),
        "kg.m2" => (1, 2, 0),
        "N.m.s/rad" => (1, 2, -1),
        "N/m2" => (1, -1, -2),
        "N.s/m2" => (1, -1, -1),
        "N.s" => (1, 1, -1),
        "N.m2.s" => (1, 3, -1),
        _ => return None,
    })
}
