//! Helpers shared by the integration tests.
#![allow(dead_code)]

pub mod shell_reference;

use flexfmu::fmi2::state_machine::Call;
use flexfmu::instance::Instance;
use flexfmu::logging::Status;
use flexfmu::model::build_model;
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use flexfmu::variables::{Role, Value, VarType, VariableTable};
use std::cell::RefCell;
use std::path::PathBuf;
use std::rc::Rc;

/// Path of a shipped scene.
pub fn scene_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(format!("{name}.toml"))
}

/// Loads a shipped scene.
/// The scene text `text` with the line starting with `key =` replaced by `key = value`.
pub fn with(text: &str, key: &str, value: &str) -> String {
    text.lines()
        .map(|l| {
            if l.trim_start().starts_with(&format!("{key} =")) {
                format!("{key} = {value}")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

pub fn scene(name: &str) -> Scene {
    Scene::from_path(&scene_path(name)).unwrap()
}

/// A simulation of `scene` with parameter and input overrides by variable name.
pub fn simulation(scene: &Scene, overrides: &[(&str, Value)]) -> Result<Simulation, String> {
    let vars = VariableTable::from_scene(scene);
    let mut params = ParamValues::defaults(&scene.params);
    let mut inputs = vec![];
    for (name, value) in overrides {
        let v = vars
            .by_name(name)
            .unwrap_or_else(|| panic!("no variable {name}"));
        match v.role {
            Role::Parameter(p) => set_param(&mut params, p, *value),
            Role::Input(k) => match value {
                Value::Real(x) => inputs.push((k, *x)),
                _ => panic!("inputs are Real"),
            },
            Role::Output(_) => panic!("{name} is an output"),
        }
    }
    let mut model = build_model(scene, &params)?;
    for (k, x) in inputs {
        model.set_input(k, x);
    }
    let cfg = SolverConfig::from_params(&params);
    let mut sim = Simulation::new(model, cfg, 0.0)?;
    sim.initialize()?;
    Ok(sim)
}

/// The index of input `name` among the scene's inputs (what `Model::set_input` takes).
pub fn input_index(scene: &Scene, name: &str) -> usize {
    match VariableTable::from_scene(scene)
        .by_name(name)
        .map(|v| v.role)
    {
        Some(Role::Input(k)) => k,
        other => panic!("{name} is not an input: {other:?}"),
    }
}

/// An output of a simulation by variable name.
pub fn output(scene: &Scene, sim: &Simulation, name: &str) -> f64 {
    let vars = VariableTable::from_scene(scene);
    match vars
        .by_name(name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .role
    {
        Role::Output(k) => sim.output(k),
        _ => panic!("{name} is not an output"),
    }
}

/// Log of an instance: status, category, message of every delivered message.
pub type Log = Rc<RefCell<Vec<(Status, String, String)>>>;

thread_local! {
    /// The last Warning/Discard/Error/Fatal message of any instance made by [`instance`] on
    /// this thread (each test runs on its own thread): quoted when a status check fails.
    static LAST_PROBLEM: RefCell<String> = const { RefCell::new(String::new()) };
}

/// The last Warning-or-worse message logged on this thread, for panic messages.
fn last_problem() -> String {
    LAST_PROBLEM.with(|m| m.borrow().clone())
}

/// An instance of a shipped scene whose log messages are collected.
pub fn instance(scene_name: &str, logging_on: bool) -> (Instance, Log) {
    let log: Log = Rc::default();
    let l2 = log.clone();
    let inst = Instance::from_scene(
        "test",
        scene(scene_name),
        logging_on,
        Box::new(move |s, c, m| {
            if s >= Status::Warning {
                LAST_PROBLEM.with(|p| *p.borrow_mut() = m.to_string());
            }
            l2.borrow_mut().push((s, c.to_string(), m.to_string()))
        }),
    );
    (inst, log)
}

/// The last message of a log ("" when there is none).
pub fn last_message(log: &Log) -> String {
    log.borrow()
        .last()
        .map(|(_, _, m)| m.clone())
        .unwrap_or_default()
}

/// Value reference of a variable by name.
pub fn vr(inst: &Instance, name: &str) -> u32 {
    inst.variables()
        .by_name(name)
        .unwrap_or_else(|| panic!("no {name}"))
        .vr
}

/// Panics unless `got` is `expected`, naming the call and quoting the last problem message.
#[track_caller]
pub fn expect_status(got: Status, expected: Status, call: impl std::fmt::Display) {
    if got != expected {
        panic!(
            "{call} returned {got:?}, expected {expected:?}; last message: \"{}\"",
            last_problem()
        );
    }
}

/// The fmi2Set call of a value's type.
fn set_call(v: &Value) -> Call {
    match v {
        Value::Real(_) => Call::SetReal,
        Value::Integer(_) => Call::SetInteger,
        Value::Boolean(_) => Call::SetBoolean,
    }
}

/// Sets a variable by name with the fmi2Set call of its type and returns the status unchecked:
/// only for callers that assert the status themselves (prefer [`set`] and [`set_expect`]).
pub fn try_set(inst: &mut Instance, name: &str, v: Value) -> Status {
    let r = vr(inst, name);
    inst.set(set_call(&v), &[r], &[v])
}

/// Sets a variable by name; the call must return fmi2OK (a rejected value would otherwise run
/// silently at its default).
#[track_caller]
pub fn set(inst: &mut Instance, name: &str, v: Value) {
    set_expect(inst, name, v, Status::Ok);
}

/// Sets a variable by name and checks that the call returns exactly `expected`.
#[track_caller]
pub fn set_expect(inst: &mut Instance, name: &str, v: Value, expected: Status) {
    let s = try_set(inst, name, v);
    expect_status(
        s,
        expected,
        format_args!("{:?}({name} = {v:?})", set_call(&v)),
    );
}

/// fmi2GetReal of one variable by name: the status and the value (NaN when none came).
pub fn get_real(inst: &mut Instance, name: &str) -> (Status, f64) {
    let r = vr(inst, name);
    let mut out = f64::NAN;
    let s = inst.get(Call::GetReal, VarType::Real, &[r], &mut |_, v| {
        if let Value::Real(x) = v {
            out = x
        }
    });
    (s, out)
}

/// fmi2GetReal of one variable by name, which must succeed.
#[track_caller]
pub fn get(inst: &mut Instance, name: &str) -> f64 {
    let (s, x) = get_real(inst, name);
    expect_status(s, Status::Ok, format_args!("fmi2GetReal({name})"));
    x
}

/// fmi2SetupExperiment (start time 0, no tolerance, no stop time), fmi2EnterInitializationMode
/// and fmi2ExitInitializationMode, each of which must succeed.
#[track_caller]
pub fn init(inst: &mut Instance) {
    expect_status(
        inst.setup_experiment(None, 0.0, None),
        Status::Ok,
        "fmi2SetupExperiment",
    );
    expect_status(
        inst.enter_initialization_mode(),
        Status::Ok,
        "fmi2EnterInitializationMode",
    );
    expect_status(
        inst.exit_initialization_mode(),
        Status::Ok,
        "fmi2ExitInitializationMode",
    );
}

/// fmi2DoStep from `t` over `h` [s], which must succeed.
#[track_caller]
pub fn step(inst: &mut Instance, t: f64, h: f64) {
    expect_status(
        inst.do_step(t, h),
        Status::Ok,
        format_args!("fmi2DoStep(t = {t}, h = {h})"),
    );
}

/// Communication steps of `h` [s] from `t0` to `t1` [s], each of which must succeed.
#[track_caller]
pub fn run(inst: &mut Instance, t0: f64, t1: f64, h: f64) {
    let n = ((t1 - t0) / h).round() as usize;
    for k in 0..n {
        step(inst, t0 + k as f64 * h, h);
    }
}

/// Sets a parameter of a parameter set by name, checking that the scene has it with the same
/// type (a misspelled name or a wrong type would otherwise be ignored by the model).
#[track_caller]
pub fn set_param(p: &mut ParamValues, name: &'static str, v: Value) {
    match (p.get(name), v) {
        (Some(Value::Real(_)), Value::Real(_))
        | (Some(Value::Integer(_)), Value::Integer(_))
        | (Some(Value::Boolean(_)), Value::Boolean(_)) => p.set(name, v),
        (old, _) => panic!("parameter {name}: the scene has {old:?}, the test sets {v:?}"),
    }
}

/// A TOML file of `tests/data/` (reference curves of other programs and scripts).
#[allow(dead_code)]
pub fn data_toml(name: &str) -> toml::Table {
    let path = format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    toml::from_str(&text).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// An array of floats `key` of a TOML table.
#[allow(dead_code)]
pub fn floats(t: &toml::Value, key: &str) -> Vec<f64> {
    t[key]
        .as_array()
        .unwrap_or_else(|| panic!("{key}: not an array"))
        .iter()
        .map(|x| x.as_float().unwrap_or_else(|| panic!("{key}: not floats")))
        .collect()
}

/// Energy outputs over a run: after each step of `h` [s] (inputs set by `drive(t)` at the
/// step's start), the outputs `names`, the dissipated energy, the numerical part of the energy
/// balance (plate work − change of gas, strain and kinetic energy − dissipated) and the plate
/// work [J] (air-spring kinds).
#[allow(dead_code)]
pub fn energy_run(
    scene: &Scene,
    sim: &mut Simulation,
    steps: usize,
    h: f64,
    drive: impl Fn(f64) -> Vec<(usize, f64)>,
    names: &[&str],
) -> Vec<(Vec<f64>, f64, f64, f64)> {
    let stored = |sim: &Simulation| {
        ["energy.gas", "energy.strain", "energy.kinetic"]
            .iter()
            .map(|n| output(scene, sim, n))
            .sum::<f64>()
    };
    let e0 = stored(sim);
    let t0 = sim.time();
    (0..steps)
        .map(|k| {
            let t = t0 + k as f64 * h;
            for (i, u) in drive(t) {
                sim.set_input(i, u);
            }
            sim.advance(t + h)
                .unwrap_or_else(|e| panic!("step at t = {t}: {}", e.message));
            let work = output(scene, sim, "energy.plate_work");
            let lost = output(scene, sim, "energy.dissipated");
            let outs = names.iter().map(|n| output(scene, sim, n)).collect();
            (outs, lost, work - (stored(sim) - e0) - lost, work)
        })
        .collect()
}

/// The port block of an air spring's shell level (the analytic static condensation with the
/// gas's stiffness) at the plate pose `pose` against central differences of the static
/// equilibrium with the gas closed (each a fresh model from `build`, moved to `pose`, then
/// one step off it), column by column: forces and moments within 2e-3 of the column's
/// largest entry, `dV/d(pose)` within 2e-3 of its largest.
pub fn assert_port_block(
    build: impl Fn() -> flexfmu::kinds::air_spring::shell::AirSpringShell,
    pose: [f64; 5],
) {
    let mut m = build();
    m.move_plate(pose).unwrap();
    let (k, dv) = m.port_block().unwrap();
    let v0 = m.gas().committed().volume;
    let steps = [2e-5, 2e-5, 2e-5, 2e-4, 2e-4];
    for j in 0..5 {
        let at = |s: f64| {
            let mut p = pose;
            p[j] += s;
            let mut mm = build();
            mm.move_plate(pose).unwrap();
            let f = mm.move_plate(p).unwrap();
            (f, mm.gas().committed().volume)
        };
        let (fp, vp) = at(steps[j]);
        let (fm, vm) = at(-steps[j]);
        let scale_f = k.iter().map(|r| r[j].abs()).fold(0.0, f64::max);
        for i in 0..5 {
            let fd = (fp[i] - fm[i]) / (2.0 * steps[j]);
            assert!(
                (fd - k[i][j]).abs() <= 2e-3 * scale_f,
                "pose {pose:?}: d{i}/d{j} analytic {} vs difference {fd}",
                k[i][j]
            );
        }
        let fdv = (vp - vm) / (2.0 * steps[j]);
        assert!(
            (fdv - dv[j]).abs() <= 2e-3 * dv.iter().map(|x| x.abs()).fold(1e-12, f64::max),
            "dV/d{j}: {} vs {fdv} (V {v0})",
            dv[j]
        );
    }
}
