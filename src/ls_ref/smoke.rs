//! The smoke-test run that produces an FMU's reference result: the scene's own model driven
//! through the same safe FMI instance ([`crate::instance::Instance`]) the shared library
//! wraps, in process, at build time. The stimulated inputs are set before initialization and
//! at every communication point before `fmi2DoStep` (the first included), as a master does;
//! outputs are read at the start and after every step.

use super::declare::SmokeTest;
use crate::fmi2::state_machine::Call;
use crate::instance::Instance;
use crate::logging::Status;
use crate::scene::Scene;
use crate::variables::{Causality, Value, VarType};
use std::cell::RefCell;
use std::rc::Rc;

/// Result of a smoke-test run.
#[derive(Clone, Debug, PartialEq)]
pub struct SmokeRun {
    /// Communication points `t0 + k h`, k = 0..=steps [s].
    pub times: Vec<f64>,
    /// Names of the stimulated inputs.
    pub input_names: Vec<String>,
    /// Input values per communication point (k = 0..steps; the last point has none applied,
    /// it repeats the value at the end time).
    pub inputs: Vec<Vec<f64>>,
    /// Names of the Real outputs, in value-reference order.
    pub output_names: Vec<String>,
    /// Output values per communication point.
    pub outputs: Vec<Vec<f64>>,
    /// `fmi2SerializeFMUstate` bytes right after `fmi2ExitInitializationMode`, if asked.
    pub initial_state: Option<Vec<u8>>,
    /// `[experiment] start_time` [s].
    pub start_time: f64,
    /// `[experiment] step_size` [s].
    pub step_size: f64,
}

/// Runs `test` on `scene` with the default parameters; with `save_state`, also serializes the
/// FMU state after initialization. Any status other than OK is an error with the FMU's
/// messages.
pub fn run(scene: &Scene, test: &SmokeTest, save_state: bool) -> Result<SmokeRun, String> {
    let messages = Rc::new(RefCell::new(Vec::<String>::new()));
    let sink = {
        let m = messages.clone();
        Box::new(move |_: Status, _: &str, msg: &str| m.borrow_mut().push(msg.to_string()))
    };
    let mut inst = Instance::from_scene("ls-ref", scene.clone(), false, sink);
    let fail = |what: &str, s: Status, m: &Rc<RefCell<Vec<String>>>| {
        format!(
            "smoke test of {}: {what} returned {s:?}: {}",
            scene.model_name(),
            m.borrow().join("; ")
        )
    };
    let vars = inst.variables().clone();
    let mut stim = Vec::new();
    for s in &test.stimuli {
        let v = vars
            .by_name(&s.input)
            .filter(|v| v.causality == Causality::Input && v.ty == VarType::Real)
            .ok_or_else(|| {
                format!(
                    "smoke test of {}: stimulus {} is no Real input",
                    scene.model_name(),
                    s.input
                )
            })?;
        let start = match v.start {
            Some(Value::Real(x)) => x,
            _ => 0.0,
        };
        stim.push((v.vr, start, s));
    }
    let outs: Vec<(u32, String)> = vars
        .vars()
        .iter()
        .filter(|v| v.causality == Causality::Output && v.ty == VarType::Real)
        .map(|v| (v.vr, v.name.clone()))
        .collect();
    let out_vrs: Vec<u32> = outs.iter().map(|o| o.0).collect();
    let exp = &scene.common.experiment;
    let (t0, h) = (exp.start_time, exp.step_size);
    let duration = test.steps as f64 * h;
    let time = |k: usize| t0 + k as f64 * h;
    let inputs_at = |t: f64| -> Vec<f64> {
        stim.iter()
            .map(|(_, start, s)| s.value(*start, t - t0, duration))
            .collect()
    };
    let set_inputs = |inst: &mut Instance, u: &[f64]| -> Status {
        for ((vr, _, _), x) in stim.iter().zip(u) {
            let s = inst.set(Call::SetReal, &[*vr], &[Value::Real(*x)]);
            if s != Status::Ok {
                return s;
            }
        }
        Status::Ok
    };
    let read = |inst: &mut Instance| -> Result<Vec<f64>, Status> {
        let mut row = vec![0.0; out_vrs.len()];
        let s = inst.get(Call::GetReal, VarType::Real, &out_vrs, &mut |i, v| {
            if let Value::Real(x) = v {
                row[i] = x;
            }
        });
        if s == Status::Ok { Ok(row) } else { Err(s) }
    };
    let s = inst.setup_experiment(None, t0, Some(time(test.steps)));
    if s != Status::Ok {
        return Err(fail("fmi2SetupExperiment", s, &messages));
    }
    let s = inst.enter_initialization_mode();
    if s != Status::Ok {
        return Err(fail("fmi2EnterInitializationMode", s, &messages));
    }
    let mut inputs = vec![inputs_at(t0)];
    let s = set_inputs(&mut inst, &inputs[0]);
    if s != Status::Ok {
        return Err(fail("fmi2SetReal", s, &messages));
    }
    let s = inst.exit_initialization_mode();
    if s != Status::Ok {
        return Err(fail("fmi2ExitInitializationMode", s, &messages));
    }
    let initial_state = if save_state {
        Some(
            inst.save_fmu_state(Call::SerializeFmuState)
                .map_err(|s| fail("fmi2SerializeFMUstate", s, &messages))?,
        )
    } else {
        None
    };
    let mut outputs = vec![read(&mut inst).map_err(|s| fail("fmi2GetReal", s, &messages))?];
    for k in 0..test.steps {
        // a master sets the inputs before every step, the first one included
        if k > 0 {
            inputs.push(inputs_at(time(k)));
        }
        let s = set_inputs(&mut inst, &inputs[k]);
        if s != Status::Ok {
            return Err(fail("fmi2SetReal", s, &messages));
        }
        let s = inst.do_step(time(k), h);
        if s != Status::Ok {
            return Err(fail(
                &format!("fmi2DoStep at t = {}", time(k)),
                s,
                &messages,
            ));
        }
        outputs.push(read(&mut inst).map_err(|s| fail("fmi2GetReal", s, &messages))?);
    }
    inputs.push(inputs_at(time(test.steps)));
    Ok(SmokeRun {
        times: (0..=test.steps).map(time).collect(),
        input_names: test.stimuli.iter().map(|s| s.input.clone()).collect(),
        inputs,
        output_names: outs.into_iter().map(|o| o.1).collect(),
        outputs,
        initial_state,
        start_time: t0,
        step_size: h,
    })
}

/// CSV of a time series: a header `"time","name",...` (names quoted, as the FMI cross-check
/// results and the Reference FMUs write them), then one row per time, numbers in Rust's
/// shortest round-trip exponent form, comma-separated, `\n` line ends.
pub fn csv(times: &[f64], names: &[String], rows: &[Vec<f64>]) -> String {
    let mut s = String::from("\"time\"");
    for n in names {
        s.push_str(&format!(",\"{}\"", n.replace('"', "\"\"")));
    }
    s.push('\n');
    for (t, row) in times.iter().zip(rows) {
        s.push_str(&format!("{t:e}"));
        for x in row {
            s.push_str(&format!(",{x:e}"));
        }
        s.push('\n');
    }
    s
}
