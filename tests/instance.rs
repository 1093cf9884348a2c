//! The safe FMI instance: calling sequence, errors with messages, parameters, outputs.

mod common;
use flexfmu::fmi2::state_machine::{Call, State};
use flexfmu::instance::Instance;

use flexfmu::logging::Status;
use flexfmu::variables::Value;

use common::{Log, get, instance, set, set_expect, vr};

fn last_error(log: &Log) -> String {
    log.borrow()
        .iter()
        .rev()
        .find(|(s, _, _)| *s >= Status::Discard)
        .map(|(_, _, m)| m.clone())
        .unwrap_or_default()
}

fn init(inst: &mut Instance) -> Status {
    assert_eq!(inst.setup_experiment(None, 0.0, Some(1.0)), Status::Ok);
    assert_eq!(inst.enter_initialization_mode(), Status::Ok);
    inst.exit_initialization_mode()
}

#[test]
fn static_equilibrium_outputs_are_valid_right_after_initialization() {
    let (mut inst, _) = instance("cantilever", false);
    set(&mut inst, "load.fy", Value::Real(-5e5));
    set(&mut inst, "solver.static_equilibrium", Value::Boolean(true));
    set(&mut inst, "element.shear_rule", Value::Integer(1));
    assert_eq!(init(&mut inst), Status::Ok);
    let x = get(&mut inst, "tip.x");
    let y = get(&mut inst, "tip.y");
    // Table 3 of Kerkkanen et al. 2003, 8 elements: (1.85667, -0.67758)
    assert!(
        (x - 1.85667).abs() < 5e-6 && (y + 0.67758).abs() < 5e-6,
        "({x}, {y})"
    );
    // Starting in equilibrium with the same load, a dynamic step stays there.
    assert_eq!(inst.do_step(0.0, 1e-3), Status::Ok);
    let y1 = get(&mut inst, "tip.y");
    assert!((y1 - y).abs() < 1e-9, "{y1} vs {y}");
}

#[test]
fn outputs_can_be_read_in_initialization_mode() {
    let (mut inst, _) = instance("simply_supported", false);
    assert_eq!(inst.enter_initialization_mode(), Status::Ok);
    set(&mut inst, "load.fy", Value::Real(-1000.0));
    set(&mut inst, "solver.static_equilibrium", Value::Boolean(true));
    let y = get(&mut inst, "mid.y");
    assert!(y < -9e-5 && y > -1e-4, "{y}");
    // A later parameter change in Initialization Mode is honoured at exit.
    set(&mut inst, "load.fy", Value::Real(-2000.0));
    assert_eq!(inst.exit_initialization_mode(), Status::Ok);
    let y2 = get(&mut inst, "mid.y");
    assert!((y2 / y - 2.0).abs() < 1e-6, "{y2} vs 2 * {y}");
}

#[test]
fn illegal_call_order_is_an_error_with_a_message() {
    let (mut inst, log) = instance("cantilever", false);
    assert_eq!(inst.do_step(0.0, 1e-3), Status::Error);
    assert!(
        last_error(&log).contains("fmi2DoStep is not allowed in state Instantiated"),
        "{:?}",
        log.borrow()
    );
    assert_eq!(inst.state(), State::Error);
    // Reset brings it back.
    assert_eq!(inst.reset(), Status::Ok);
    assert_eq!(init(&mut inst), Status::Ok);
    assert_eq!(inst.exit_initialization_mode(), Status::Error);
    assert!(last_error(&log).contains("fmi2ExitInitializationMode is not allowed"));
}

#[test]
fn bad_parameters_fail_initialization_naming_the_parameter() {
    for (name, value, expect) in [
        ("material.E", Value::Real(-1.0), "material.E"),
        ("material.nu", Value::Real(0.5), "material.nu"),
        ("material.nu", Value::Real(0.7), "material.nu"),
        ("mesh.n_elements", Value::Integer(0), "mesh.n_elements"),
        ("geometry.height", Value::Real(0.0), "geometry.height"),
        (
            "element.shear_rule",
            Value::Integer(3),
            "element.shear_rule",
        ),
        ("solver.max_step", Value::Real(-1e-3), "solver.max_step"),
    ] {
        let (mut inst, log) = instance("cantilever", false);
        set(&mut inst, name, value);
        assert_eq!(init(&mut inst), Status::Error, "{name} = {value:?}");
        let msg = last_error(&log);
        assert!(msg.contains(expect), "message for {name}: {msg}");
        assert_eq!(inst.state(), State::Error);
    }
}

#[test]
fn nan_input_unknown_reference_and_wrong_type_are_errors() {
    let (mut inst, log) = instance("cantilever", false);
    assert_eq!(init(&mut inst), Status::Ok);
    set_expect(&mut inst, "load.fy", Value::Real(f64::NAN), Status::Error);
    assert!(last_error(&log).contains("load.fy"));

    let (mut inst, log) = instance("cantilever", false);
    assert_eq!(init(&mut inst), Status::Ok);
    assert_eq!(
        inst.set(Call::SetReal, &[9999], &[Value::Real(1.0)]),
        Status::Error
    );
    assert!(last_error(&log).contains("unknown value reference 9999"));

    let (mut inst, log) = instance("cantilever", false);
    assert_eq!(init(&mut inst), Status::Ok);
    let n = vr(&inst, "mesh.n_elements");
    assert_eq!(
        inst.set(Call::SetReal, &[n], &[Value::Real(3.0)]),
        Status::Error
    );
    assert!(last_error(&log).contains("Integer"));

    let (mut inst, log) = instance("cantilever", false);
    assert_eq!(init(&mut inst), Status::Ok);
    set_expect(&mut inst, "material.E", Value::Real(1e9), Status::Error);
    assert!(last_error(&log).contains("fixed parameter"));
}

#[test]
fn tunable_parameters_and_inputs_change_during_the_run() {
    let (mut inst, _) = instance("cantilever", false);
    assert_eq!(init(&mut inst), Status::Ok);
    set(&mut inst, "solver.max_step", Value::Real(5e-5));
    set(&mut inst, "load.fy", Value::Real(-100.0));
    assert_eq!(inst.do_step(0.0, 1e-3), Status::Ok);
    let y = get(&mut inst, "tip.y");
    assert!(y < 0.0, "the load pulls the tip down: {y}");
    // an invalid tunable value is rejected and the old one kept
    set_expect(
        &mut inst,
        "solver.max_step",
        Value::Real(0.0),
        Status::Error,
    );
}

#[test]
fn reset_allows_a_second_run_with_other_parameters() {
    let (mut inst, _) = instance("simply_supported", false);
    let run = |inst: &mut Instance, e: f64| {
        set(inst, "material.E", Value::Real(e));
        set(inst, "load.fy", Value::Real(-1000.0));
        set(inst, "solver.static_equilibrium", Value::Boolean(true));
        assert_eq!(init(inst), Status::Ok);
        get(inst, "mid.y")
    };
    let y1 = run(&mut inst, 2.07e11);
    assert_eq!(inst.terminate(), Status::Ok);
    assert_eq!(inst.reset(), Status::Ok);
    let y2 = run(&mut inst, 1.035e11);
    assert!(
        (y2 / y1 - 2.0).abs() < 1e-6,
        "halving E doubles a linear deflection: {y1} {y2}"
    );
}

#[test]
fn logging_respects_logging_on_and_categories() {
    let (mut inst, log) = instance("cantilever", false);
    assert_eq!(init(&mut inst), Status::Ok);
    assert!(
        log.borrow().iter().all(|(s, _, _)| *s >= Status::Warning),
        "no info when off"
    );
    let (mut inst, log) = instance("cantilever", true);
    assert_eq!(init(&mut inst), Status::Ok);
    assert!(log.borrow().iter().any(|(_, c, _)| c == "logEvents"));
    let (mut inst, log) = instance("cantilever", true);
    assert_eq!(inst.set_debug_logging(false, &["logEvents"]), Status::Ok);
    assert_eq!(init(&mut inst), Status::Ok);
    assert!(
        !log.borrow()
            .iter()
            .skip(1)
            .any(|(_, c, _)| c == "logEvents")
    );
    assert_eq!(
        inst.set_debug_logging(true, &["noSuchCategory"]),
        Status::Error
    );
}

/// Pendulum (Problem 4 of the paper): over 1 s the total energy T + V + U stays within 1e-3 of
/// the potential energy exchanged, for Newmark and for the energy-conserving midpoint rule.
#[test]
fn pendulum_conserves_energy() {
    for integrator in [2, 3] {
        let (mut inst, _) = instance("pendulum", false);
        set(&mut inst, "solver.integrator", Value::Integer(integrator));
        assert_eq!(init(&mut inst), Status::Ok);
        let e0 = get(&mut inst, "energy.total");
        let (mut drift, mut drop) = (0.0f64, 0.0f64);
        for k in 0..100 {
            assert_eq!(inst.do_step(k as f64 * 0.01, 0.01), Status::Ok);
            let e = get(&mut inst, "energy.total");
            let v = get(&mut inst, "energy.potential");
            drift = drift.max((e - e0).abs());
            drop = drop.max(-v);
        }
        assert!(drop > 1000.0, "the pendulum falls: potential drop {drop} J");
        println!("integrator {integrator}: drift {drift:.3e} J of {drop:.1} J");
        assert!(
            drift <= 1e-3 * drop,
            "integrator {integrator}: drift {drift} J vs drop {drop} J"
        );
        if integrator == 3 {
            assert!(
                drift <= 1e-6 * drop,
                "midpoint rule conserves energy: drift {drift} J"
            );
        }
    }
}

/// Outputs are computed when they are read: an instance that reads only `top.fz` for a
/// while and then every output returns, bit for bit, what an instance that read every output
/// after every step returns, including the stiffness (the static condensation it skipped),
/// the output derivatives (`top.fz` analytic, `gas.pressure` by differences over the last
/// step, asked for from step 10 on) and the outputs of a saved and restored state.
#[test]
fn outputs_read_late_equal_outputs_read_every_step() {
    let names: Vec<String> = {
        let (inst, _) = instance("air_spring_axisym", false);
        inst.variables()
            .vars()
            .iter()
            .filter(|v| v.causality == flexfmu::variables::Causality::Output)
            .map(|v| v.name.clone())
            .collect()
    };
    assert!(names.iter().any(|n| n == "spring.stiffness"), "{names:?}");
    let run = |every: bool| {
        let (mut inst, _) = instance("air_spring_axisym", false);
        assert_eq!(init(&mut inst), Status::Ok);
        let mut last = vec![];
        let mut d = [0.0; 2];
        for k in 0..20 {
            let t = k as f64 * 1e-3;
            set(
                &mut inst,
                "top.z",
                Value::Real(0.25 + 0.01 * (20.0 * t).sin()),
            );
            set(&mut inst, "top.vz", Value::Real(0.2 * (20.0 * t).cos()));
            assert_eq!(inst.do_step(t, 1e-3), Status::Ok);
            let read: Vec<&str> = if every || k == 19 {
                names.iter().map(|s| s.as_str()).collect()
            } else {
                vec!["top.fz"]
            };
            last = read.iter().map(|n| get(&mut inst, n)).collect();
            if k >= 10 {
                let d_vrs = [vr(&inst, "top.fz"), vr(&inst, "gas.pressure")];
                assert_eq!(
                    inst.get_real_output_derivatives(&d_vrs, &[1, 1], &mut d),
                    Status::Ok
                );
            }
        }
        assert!(d.iter().all(|x| *x != 0.0 && x.is_finite()), "{d:?}");
        let saved = inst.save_fmu_state(Call::GetFmuState).expect("state");
        let mut other = {
            let (mut o, _) = instance("air_spring_axisym", false);
            assert_eq!(init(&mut o), Status::Ok);
            o
        };
        assert_eq!(other.restore_fmu_state(&saved), Status::Ok);
        let restored: Vec<f64> = names.iter().map(|n| get(&mut other, n)).collect();
        (last, d, restored)
    };
    let (every, d_every, r_every) = run(true);
    let (late, d_late, r_late) = run(false);
    assert_eq!(every, late);
    assert_eq!(d_every, d_late);
    assert_eq!(r_every, every);
    assert_eq!(r_late, late);
}
