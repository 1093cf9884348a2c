//! `modelDescription.xml` for FMI 2.0 Co-Simulation, written with quick-xml from the variable
//! table. Element order follows the FMI 2.0 schema: CoSimulation, UnitDefinitions,
//! LogCategories, DefaultExperiment, ModelVariables, ModelStructure.

use crate::guid::guid_of;
use crate::logging::CATEGORIES;
use crate::scene::Scene;
use crate::units::Unit;
use crate::variables::{Causality, VarType, VariableTable};
use quick_xml::Writer;
use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, Event};

/// FMI capability flags, stated honestly: a flag is true only when the feature works.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Capabilities {
    /// canHandleVariableCommunicationStepSize
    pub variable_step: bool,
    /// canInterpolateInputs
    pub interpolate_inputs: bool,
    /// maxOutputDerivativeOrder
    pub max_output_derivative_order: u32,
    /// canGetAndSetFMUstate
    pub get_set_state: bool,
    /// canSerializeFMUstate
    pub serialize_state: bool,
    /// providesDirectionalDerivative
    pub directional_derivative: bool,
}

impl Capabilities {
    /// Every optional FMI 2.0 Co-Simulation feature flexfmu implements (maxOutputDerivativeOrder
    /// 1).
    pub const ALL: Capabilities = Capabilities {
        variable_step: true,
        interpolate_inputs: true,
        max_output_derivative_order: 1,
        get_set_state: true,
        serialize_state: true,
        directional_derivative: true,
    };
}

const GUID_PLACEHOLDER: &str = "{00000000-0000-0000-0000-000000000000}";

/// The GUID of a scene: the hash of its model description (with a placeholder GUID) and of
/// the scene text that the FMU reads at instantiation.
pub fn scene_guid(scene: &Scene) -> String {
    let vars = VariableTable::from_scene(scene);
    let body = render(scene, &vars, GUID_PLACEHOLDER);
    let mut data = body.into_bytes();
    data.extend_from_slice(scene.text.as_bytes());
    guid_of(&data)
}

/// The complete model description of a scene.
pub fn model_description(scene: &Scene) -> String {
    let vars = VariableTable::from_scene(scene);
    render(scene, &vars, &scene_guid(scene))
}

fn b(v: bool) -> &'static str {
    if v { "true" } else { "false" }
}

fn render(scene: &Scene, vars: &VariableTable, guid: &str) -> String {
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    let io = |r: std::io::Result<()>| r.expect("writing XML to memory cannot fail");
    io(w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None))));
    let name = scene.model_name();
    let description = if scene.common.fmu.description.is_empty() {
        "flexfmu flexible body".to_string()
    } else {
        scene.common.fmu.description.clone()
    };
    let version = format!("flexfmu {}", env!("CARGO_PKG_VERSION"));
    io(w.write_event(Event::Start(
        BytesStart::new("fmiModelDescription").with_attributes([
            ("fmiVersion", "2.0"),
            ("modelName", name),
            ("guid", guid),
            ("description", description.as_str()),
            ("generationTool", version.as_str()),
            ("variableNamingConvention", "structured"),
            ("numberOfEventIndicators", "0"),
        ]),
    )));

    let c = Capabilities::ALL;
    let order = c.max_output_derivative_order.to_string();
    io(w.write_event(Event::Empty(
        BytesStart::new("CoSimulation").with_attributes([
            ("modelIdentifier", name),
            ("needsExecutionTool", "false"),
            ("canHandleVariableCommunicationStepSize", b(c.variable_step)),
            ("canInterpolateInputs", b(c.interpolate_inputs)),
            ("maxOutputDerivativeOrder", order.as_str()),
            ("canRunAsynchronuously", "false"),
            ("canBeInstantiatedOnlyOncePerProcess", "false"),
            ("canNotUseMemoryManagementFunctions", "true"),
            ("canGetAndSetFMUstate", b(c.get_set_state)),
            ("canSerializeFMUstate", b(c.serialize_state)),
            ("providesDirectionalDerivative", b(c.directional_derivative)),
        ]),
    )));

    io(w.write_event(Event::Start(BytesStart::new("UnitDefinitions"))));
    for unit in vars.units() {
        io(w.write_event(Event::Start(
            BytesStart::new("Unit").with_attributes([("name", unit.name())]),
        )));
        let mut base = BytesStart::new("BaseUnit");
        for (k, e) in Unit::BASE.into_iter().zip(unit.exponents()) {
            if e != 0 {
                base.push_attribute((k, e.to_string().as_str()));
            }
        }
        if unit.factor() != 1.0 {
            base.push_attribute(("factor", format!("{:e}", unit.factor()).as_str()));
        }
        io(w.write_event(Event::Empty(base)));
        io(w.write_event(Event::End(BytesEnd::new("Unit"))));
    }
    io(w.write_event(Event::End(BytesEnd::new("UnitDefinitions"))));

    io(w.write_event(Event::Start(BytesStart::new("LogCategories"))));
    for (cat, desc) in CATEGORIES {
        io(w.write_event(Event::Empty(
            BytesStart::new("Category").with_attributes([("name", *cat), ("description", *desc)]),
        )));
    }
    io(w.write_event(Event::End(BytesEnd::new("LogCategories"))));

    let e = &scene.common.experiment;
    let (t0, t1, dt) = (
        format!("{:?}", e.start_time),
        format!("{:?}", e.stop_time),
        format!("{:?}", e.step_size),
    );
    io(w.write_event(Event::Empty(
        BytesStart::new("DefaultExperiment").with_attributes([
            ("startTime", t0.as_str()),
            ("stopTime", t1.as_str()),
            ("stepSize", dt.as_str()),
        ]),
    )));

    io(w.write_event(Event::Start(BytesStart::new("ModelVariables"))));
    for v in vars.vars() {
        let vr = v.vr.to_string();
        let mut sv = BytesStart::new("ScalarVariable").with_attributes([
            ("name", v.name.as_str()),
            ("valueReference", vr.as_str()),
            ("description", v.description.as_str()),
            ("causality", v.causality.as_str()),
            ("variability", v.variability.as_str()),
        ]);
        if let Some(init) = v.initial() {
            sv.push_attribute(("initial", init));
        }
        io(w.write_event(Event::Start(sv)));
        let tag = match v.ty {
            VarType::Real => "Real",
            VarType::Integer => "Integer",
            VarType::Boolean => "Boolean",
        };
        let mut t = BytesStart::new(tag);
        if let Some(u) = v.unit {
            t.push_attribute(("unit", u.name()));
        }
        let fmt_bound = |x: f64| match v.ty {
            VarType::Integer => format!("{}", x as i64),
            _ => format!("{x:?}"),
        };
        if v.ty != VarType::Boolean {
            if let Some(m) = v.min {
                t.push_attribute(("min", fmt_bound(m).as_str()));
            }
            if let Some(m) = v.max {
                t.push_attribute(("max", fmt_bound(m).as_str()));
            }
        }
        if let Some(s) = v.start {
            t.push_attribute(("start", s.xml().as_str()));
        }
        io(w.write_event(Event::Empty(t)));
        io(w.write_event(Event::End(BytesEnd::new("ScalarVariable"))));
    }
    io(w.write_event(Event::End(BytesEnd::new("ModelVariables"))));

    io(w.write_event(Event::Start(BytesStart::new("ModelStructure"))));
    let outputs: Vec<_> = vars
        .vars()
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .collect();
    if !outputs.is_empty() {
        io(w.write_event(Event::Start(BytesStart::new("Outputs"))));
        for v in &outputs {
            let idx = (v.vr + 1).to_string();
            // Direct feedthrough at a communication point (FMI 2.0.4 section 2.2.8): the
            // inputs whose change moves the output before the next fmi2DoStep, as the variable
            // table declares them (ScalarVariable index = value reference + 1, ascending).
            // Empty: the output is a function of the state only. No `dependenciesKind`: the
            // default "dependent" is the true statement, since the factors (e.g. the interface
            // stiffness of a motion port) depend on the continuous state.
            let deps = v
                .depends_on
                .iter()
                .map(|d| (d + 1).to_string())
                .collect::<Vec<_>>()
                .join(" ");
            io(
                w.write_event(Event::Empty(BytesStart::new("Unknown").with_attributes([
                    ("index", idx.as_str()),
                    ("dependencies", deps.as_str()),
                ]))),
            );
        }
        io(w.write_event(Event::End(BytesEnd::new("Outputs"))));
        io(w.write_event(Event::Start(BytesStart::new("InitialUnknowns"))));
        for v in &outputs {
            let idx = (v.vr + 1).to_string();
            // At initialization an output may depend on every known (parameters, inputs
            // through the static solve): no dependencies attribute.
            io(w.write_event(Event::Empty(
                BytesStart::new("Unknown").with_attributes([("index", idx.as_str())]),
            )));
        }
        io(w.write_event(Event::End(BytesEnd::new("InitialUnknowns"))));
    }
    io(w.write_event(Event::End(BytesEnd::new("ModelStructure"))));
    io(w.write_event(Event::End(BytesEnd::new("fmiModelDescription"))));
    let mut s = String::from_utf8(w.into_inner()).expect("UTF-8");
    s.push('\n');
    s
}
