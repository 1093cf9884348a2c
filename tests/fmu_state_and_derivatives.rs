//! FMU state save/restore, directional derivatives, input and output derivatives, through the
//! safe instance API.

mod common;
use flexfmu::fmi2::state_machine::{Call, State};
use flexfmu::instance::Instance;
use flexfmu::logging::Status;
use flexfmu::variables::Value;

use common::{Log, get, init, run, set, vr};

fn instance(scene: &str) -> (Instance, Log) {
    common::instance(scene, false)
}

fn outputs(inst: &mut Instance) -> Vec<u64> {
    let names: Vec<String> = inst
        .variables()
        .vars()
        .iter()
        .filter(|v| v.causality == flexfmu::variables::Causality::Output)
        .map(|v| v.name.clone())
        .collect();
    names.iter().map(|n| get(inst, n).to_bits()).collect()
}

/// Save at t1, run to t2, restore, run to t2 again: identical outputs bit for bit — directly,
/// through serialized bytes, and in a second instance.
#[test]
fn restore_is_bit_exact() {
    let (mut a, _) = instance("pendulum");
    init(&mut a);
    run(&mut a, 0.0, 0.2, 0.01);
    let state = a.save_fmu_state(Call::GetFmuState).unwrap();
    run(&mut a, 0.2, 0.4, 0.01);
    let first = outputs(&mut a);
    assert_eq!(a.restore_fmu_state(&state), Status::Ok);
    assert_eq!(get(&mut a, "tip.x"), {
        let (mut b, _) = instance("pendulum");
        init(&mut b);
        run(&mut b, 0.0, 0.2, 0.01);
        get(&mut b, "tip.x")
    });
    run(&mut a, 0.2, 0.4, 0.01);
    assert_eq!(outputs(&mut a), first, "same instance");

    // another instance of the same FMU, never initialized, takes the state
    let (mut b, _) = instance("pendulum");
    assert_eq!(b.restore_fmu_state(&state), Status::Ok);
    assert_eq!(b.state(), State::StepComplete);
    run(&mut b, 0.2, 0.4, 0.01);
    assert_eq!(outputs(&mut b), first, "other instance");
}

/// The complete state includes parameters, inputs and their derivatives: a state saved with
/// other parameter values restores them (and rebuilds the model).
#[test]
fn restore_brings_back_parameters_and_inputs() {
    let (mut a, _) = instance("cantilever");
    set(&mut a, "mesh.n_elements", Value::Integer(4));
    init(&mut a);
    set(&mut a, "load.fy", Value::Real(-1e5));
    run(&mut a, 0.0, 2e-3, 1e-3);
    let state = a.save_fmu_state(Call::GetFmuState).unwrap();
    run(&mut a, 2e-3, 4e-3, 1e-3);
    let first = outputs(&mut a);

    let (mut b, _) = instance("cantilever");
    set(&mut b, "mesh.n_elements", Value::Integer(16));
    init(&mut b);
    run(&mut b, 0.0, 1e-3, 1e-3);
    assert_eq!(b.restore_fmu_state(&state), Status::Ok);
    run(&mut b, 2e-3, 4e-3, 1e-3);
    assert_eq!(outputs(&mut b), first);
}

#[test]
fn bad_state_buffers_are_rejected() {
    let (mut a, log) = instance("pendulum");
    init(&mut a);
    run(&mut a, 0.0, 0.01, 0.01);
    let good = a.save_fmu_state(Call::GetFmuState).unwrap();
    let before = outputs(&mut a);

    // truncated at every length, corrupted bytes, a trailing byte, another FMU's state
    for cut in [0, 1, 15, 16, 30, good.len() / 2, good.len() - 1] {
        let (mut b, _) = instance("pendulum");
        assert_eq!(
            b.restore_fmu_state(&good[..cut]),
            Status::Error,
            "cut {cut}"
        );
    }
    for pos in [20, good.len() / 3, good.len() - 5] {
        let mut bad = good.clone();
        bad[pos] ^= 0x5a;
        let (mut b, _) = instance("pendulum");
        assert_eq!(b.restore_fmu_state(&bad), Status::Error, "flip at {pos}");
    }
    // trailing bytes after the announced length
    let mut longer = good.clone();
    longer.push(0);
    let (mut b, _) = instance("pendulum");
    assert_eq!(b.restore_fmu_state(&longer), Status::Error, "trailing byte");
    let (mut other, _) = instance("cantilever");
    init(&mut other);
    let foreign = other.save_fmu_state(Call::GetFmuState).unwrap();
    assert_eq!(a.restore_fmu_state(&foreign), Status::Error);
    assert!(
        log.borrow()
            .iter()
            .any(|(_, _, m)| m.contains("another FMU"))
    );
    // a failed restore leaves the simulation as it was
    assert_eq!(outputs(&mut a), before);
}

/// Motion port: ∂(tip.fx, tip.fy)/∂(tip.x, tip.y) from the tangent stiffness equals central
/// finite differences of the output function (states frozen), in a deformed state.
#[test]
fn directional_derivatives_match_finite_differences() {
    let (mut a, _) = instance("cantilever_motion");
    init(&mut a);
    // bend the beam dynamically by moving the tip
    for k in 0..20 {
        let t = k as f64 * 1e-3;
        set(
            &mut a,
            "tip.y",
            Value::Real(-0.05 * (1.0 - (-(t / 5e-3)).exp())),
        );
        set(&mut a, "tip.x", Value::Real(2.0 - 0.01 * t));
        assert_eq!(a.do_step(t, 1e-3), Status::Ok);
    }
    let unknown = [vr(&a, "tip.fx"), vr(&a, "tip.fy")];
    for (k, input) in ["tip.x", "tip.y"].iter().enumerate() {
        let known = [vr(&a, input)];
        let mut d = [0.0; 2];
        assert_eq!(
            a.get_directional_derivative(&unknown, &known, &[1.0], &mut d),
            Status::Ok
        );
        let u = get(&mut a, input);
        let h = 1e-7;
        set(&mut a, input, Value::Real(u + h));
        let (fxp, fyp) = (get(&mut a, "tip.fx"), get(&mut a, "tip.fy"));
        set(&mut a, input, Value::Real(u - h));
        let (fxm, fym) = (get(&mut a, "tip.fx"), get(&mut a, "tip.fy"));
        set(&mut a, input, Value::Real(u));
        let fd = [(fxp - fxm) / (2.0 * h), (fyp - fym) / (2.0 * h)];
        let scale = d[k].abs();
        assert!(scale > 1e6, "the interface stiffness is large: {d:?}");
        for i in 0..2 {
            assert!(
                (d[i] - fd[i]).abs() <= 1e-5 * scale,
                "{input}: analytic {d:?} vs FD {fd:?}"
            );
        }
        // restoring force: the beam pushes back against a displacement of the port
        assert!(d[k] < 0.0);
    }
    // no feedthrough from the velocity inputs at the communication point
    let mut d = [1.0; 2];
    let known = [vr(&a, "tip.vx")];
    assert_eq!(
        a.get_directional_derivative(&unknown, &known, &[1.0], &mut d),
        Status::Ok
    );
    assert_eq!(d, [0.0, 0.0]);
}

/// In Initialization Mode with a static solve, ∂tip.y/∂load.fy is the static compliance:
/// Timoshenko cantilever L³/(3EI) + L/(k_s G A) (small-load limit), within the discretization
/// error of 16 elements.
#[test]
fn directional_derivative_through_the_static_initialization() {
    let (mut a, _) = instance("cantilever");
    set(&mut a, "mesh.n_elements", Value::Integer(16));
    set(&mut a, "solver.static_equilibrium", Value::Boolean(true));
    assert_eq!(a.enter_initialization_mode(), Status::Ok);
    let (un, kn) = (vr(&a, "tip.y"), vr(&a, "load.fy"));
    let mut d = [0.0];
    assert_eq!(
        a.get_directional_derivative(&[un], &[kn], &[1.0], &mut d),
        Status::Ok
    );
    let (e, nu, l, b, h) = (2.07e11, 0.3, 2.0, 0.1, 0.1);
    let i = b * h * h * h / 12.0;
    let g = e / (2.0 * (1.0 + nu));
    let c = l * l * l / (3.0 * e * i) + l / (5.0 / 6.0 * g * b * h);
    assert!((d[0] / c - 1.0).abs() < 5e-3, "{} vs {c}", d[0]);

    // With respect to a parameter (a known in Initialization Mode): in the linear range the
    // deflection is proportional to 1/E, so ∂y/∂E = −y/E.
    set(&mut a, "load.fy", Value::Real(-1000.0));
    let y = get(&mut a, "tip.y");
    let ke = vr(&a, "material.E");
    assert_eq!(
        a.get_directional_derivative(&[un], &[ke], &[1.0], &mut d),
        Status::Ok
    );
    assert!(
        (d[0] / (-y / e) - 1.0).abs() < 1e-3,
        "{} vs {}",
        d[0],
        -y / e
    );
}

/// With input derivatives the load is a ramp inside the step: one step of 1 ms with
/// d(load.fy)/dt matches ten steps of 0.1 ms that set the ramp values (and their derivative),
/// while plain zero-order hold does not.
#[test]
fn input_derivatives_extrapolate_inside_the_step() {
    let rate = -2e8; // N/s
    let ramp = |(mut a, _): (Instance, Log), steps: usize, with_rate: bool| {
        // Newmark: a restart of the accelerations at a communication point leaves the
        // trapezoidal rule's state as it is (generalized-α would reset its algorithmic one)
        set(&mut a, "solver.integrator", Value::Integer(2));
        init(&mut a);
        let h = 1e-3 / steps as f64;
        for k in 0..steps {
            let t = k as f64 * h;
            set(&mut a, "load.fy", Value::Real(rate * t));
            if with_rate {
                let r = vr(&a, "load.fy");
                assert_eq!(
                    a.set_real_input_derivatives(&[r], &[1], &[rate]),
                    Status::Ok
                );
            }
            assert_eq!(a.do_step(t, h), Status::Ok);
        }
        get(&mut a, "tip.y")
    };
    let one = ramp(instance("cantilever"), 1, true);
    let ten = ramp(instance("cantilever"), 10, true);
    let zoh = ramp(instance("cantilever"), 1, false);
    assert!(
        one < 0.0 && (one - ten).abs() <= 1e-9 * one.abs().max(1e-12) + 1e-15,
        "{one} vs {ten}"
    );
    assert!(zoh.abs() < 1e-15, "zero-order hold of a zero load: {zoh}");
    // order 3 is refused
    let (mut a, _) = instance("cantilever");
    init(&mut a);
    let r = vr(&a, "load.fy");
    assert_eq!(
        a.set_real_input_derivatives(&[r], &[3], &[1.0]),
        Status::Error
    );
}

/// Output derivatives: d(tip.y)/dt against a forward difference in time, and the energy rates
/// of the conservative pendulum summing to zero (Newmark: the stored acceleration satisfies the
/// equations of motion at the step end; the midpoint rule stores the step's mean acceleration).
#[test]
fn output_derivatives() {
    let (mut a, _) = instance("pendulum");
    set(&mut a, "solver.max_step", Value::Real(1e-4));
    init(&mut a);
    run(&mut a, 0.0, 0.3, 1e-3);
    let names = [
        "tip.y",
        "energy.kinetic",
        "energy.potential",
        "energy.strain",
        "energy.total",
    ];
    let vrs: Vec<u32> = names.iter().map(|n| vr(&a, n)).collect();
    let mut d = vec![0.0; vrs.len()];
    assert_eq!(
        a.get_real_output_derivatives(&vrs, &vec![1; vrs.len()], &mut d),
        Status::Ok
    );
    let state = a.save_fmu_state(Call::GetFmuState).unwrap();
    let y0 = get(&mut a, "tip.y");
    run(&mut a, 0.3, 0.3 + 1e-4, 1e-4);
    let y1 = get(&mut a, "tip.y");
    assert_eq!(a.restore_fmu_state(&state), Status::Ok);
    let fd = (y1 - y0) / 1e-4;
    assert!((d[0] - fd).abs() < 1e-2 * fd.abs(), "{} vs {fd}", d[0]);
    assert!(d[1].abs() > 100.0, "kinetic energy changes: {}", d[1]);
    assert!(
        d[4].abs() < 1e-6 * d[1].abs(),
        "dE/dt = {} with dT/dt = {}",
        d[4],
        d[1]
    );
    assert_eq!(
        a.get_real_output_derivatives(&vrs[..1], &[2], &mut d[..1]),
        Status::Error
    );
}

/// The motion port's derivative is the interface Jacobian of the FMU's time step (Sicklinger et
/// al. 2014): shifting the prescribed tip position by ±δ and taking one communication step (one
/// internal step) changes the force after the step by the directional derivative times δ
/// (checked by central differences of the stepped outputs, with FMU state rollback).
#[test]
fn interface_jacobian_predicts_the_step_response() {
    let (mut a, _) = instance("cantilever_motion");
    set(&mut a, "solver.max_step", Value::Real(1e-3));
    init(&mut a);
    // bend the beam by driving the tip down at 2 m/s for 10 ms
    for k in 0..10 {
        let t = k as f64 * 1e-3;
        set(&mut a, "tip.vy", Value::Real(-2.0));
        assert_eq!(a.do_step(t, 1e-3), Status::Ok);
        set(&mut a, "tip.y", Value::Real(-2.0 * (t + 1e-3)));
    }
    // then communicate with h = 0.1 ms (one internal step each)
    let h = 1e-4;
    set(&mut a, "solver.max_step", Value::Real(h));
    assert_eq!(a.do_step(0.01, h), Status::Ok);
    set(&mut a, "tip.y", Value::Real(-2.0 * (0.01 + h)));
    let t = 0.01 + h;
    let unknown = [vr(&a, "tip.fx"), vr(&a, "tip.fy")];
    let state = a.save_fmu_state(Call::GetFmuState).unwrap();
    let y = get(&mut a, "tip.y");
    for (axis, input) in ["tip.x", "tip.y"].iter().enumerate() {
        let mut d = [0.0; 2];
        assert_eq!(
            a.get_directional_derivative(&unknown, &[vr(&a, input)], &[1.0], &mut d),
            Status::Ok
        );
        let u = if axis == 0 { 2.0 } else { y };
        let delta = 1e-7;
        let mut f = [[0.0; 2]; 2];
        for (s, sign) in [1.0, -1.0].iter().enumerate() {
            assert_eq!(a.restore_fmu_state(&state), Status::Ok);
            set(&mut a, input, Value::Real(u + sign * delta));
            assert_eq!(a.do_step(t, h), Status::Ok);
            f[s] = [get(&mut a, "tip.fx"), get(&mut a, "tip.fy")];
        }
        assert_eq!(a.restore_fmu_state(&state), Status::Ok);
        for i in 0..2 {
            let fd = (f[0][i] - f[1][i]) / (2.0 * delta);
            let scale = d[axis].abs();
            // the Jacobian uses the tangent at the start of the step, the step response the
            // tangent along the step (the bent, moving beam): agreement to 5e-3 of the port
            // stiffness (the geometric cross terms differ by ~1.5 % of themselves)
            assert!(
                (d[i] - fd).abs() <= 5e-3 * scale,
                "{input}, output {i}: derivative {d:?} vs stepped FD {fd}"
            );
        }
    }
}

/// The same for the co-rotational 3D beam: the state includes the nodal orientations.
#[test]
fn restore_is_bit_exact_for_the_3d_beam() {
    let (mut a, _) = instance("right_angle_cantilever");
    init(&mut a);
    set(&mut a, "load.fz", Value::Real(50.0));
    run(&mut a, 0.0, 1.0, 0.05);
    let state = a.save_fmu_state(Call::GetFmuState).unwrap();
    run(&mut a, 1.0, 3.0, 0.05);
    let first = outputs(&mut a);
    assert_eq!(a.restore_fmu_state(&state), Status::Ok);
    run(&mut a, 1.0, 3.0, 0.05);
    assert_eq!(outputs(&mut a), first);
    let (mut b, _) = instance("right_angle_cantilever");
    assert_eq!(b.restore_fmu_state(&state), Status::Ok);
    run(&mut b, 1.0, 3.0, 0.05);
    assert_eq!(outputs(&mut b), first);
}

/// And for the belt drive: the state includes the friction history of every contact point, the
/// pulley inputs and the energy book.
#[test]
fn restore_is_bit_exact_for_the_belt_drive() {
    let (mut a, log) = instance("belt_drive_inertia");
    set(&mut a, "belt.n_elements", Value::Integer(40));
    assert_eq!(a.setup_experiment(None, 0.0, None), Status::Ok);
    assert_eq!(a.enter_initialization_mode(), Status::Ok);
    let s = a.exit_initialization_mode();
    assert_eq!(s, Status::Ok, "{:?}", log.borrow());
    set(&mut a, "pulley1.torque_in", Value::Real(20.0));
    run(&mut a, 0.0, 0.05, 1e-3);
    let state = a.save_fmu_state(Call::GetFmuState).unwrap();
    run(&mut a, 0.05, 0.1, 1e-3);
    let first = outputs(&mut a);
    assert_eq!(a.restore_fmu_state(&state), Status::Ok);
    run(&mut a, 0.05, 0.1, 1e-3);
    assert_eq!(outputs(&mut a), first);
}

/// Outputs read straight after a restore, before any step, are those of the saved state: for
/// the drives whose outputs read committed contact loads (the 3D belt's pulley forces, moments
/// and flange force; the serpentine drive's tensioner and span tensions).
#[test]
fn outputs_straight_after_restore_are_the_saved_ones() {
    for (scene, mesh) in [("belt_drive_3d", 48), ("serpentine", 120)] {
        let (mut a, log) = instance(scene);
        set(&mut a, "belt.n_elements", Value::Integer(mesh));
        assert_eq!(a.setup_experiment(None, 0.0, None), Status::Ok);
        assert_eq!(a.enter_initialization_mode(), Status::Ok);
        let s = a.exit_initialization_mode();
        assert_eq!(s, Status::Ok, "{scene}: {:?}", log.borrow());
        run(&mut a, 0.0, 0.005, 1e-3);
        let state = a.save_fmu_state(Call::GetFmuState).unwrap();
        let saved = outputs(&mut a);
        run(&mut a, 0.005, 0.01, 1e-3);
        assert_ne!(
            outputs(&mut a),
            saved,
            "{scene}: the run should change the outputs"
        );
        assert_eq!(a.restore_fmu_state(&state), Status::Ok);
        assert_eq!(outputs(&mut a), saved, "{scene}");
    }
}

/// A master whose pulley starts at another angle: before the first communication step the
/// driven pulley is turned there under the belt without slip (no pre-twist, the same torques
/// as at angle 0); a turn during the run does load the belt.
#[test]
fn driven_pulley_angle_before_the_first_step_mounts_the_belt() {
    let torques = |angle0: f64, turn: f64| {
        let (mut a, log) = instance("belt_drive_cosim");
        set(&mut a, "belt.n_elements", Value::Integer(40));
        assert_eq!(a.setup_experiment(None, 0.0, None), Status::Ok);
        assert_eq!(a.enter_initialization_mode(), Status::Ok);
        set(&mut a, "pulley2.angle", Value::Real(angle0));
        let s = a.exit_initialization_mode();
        assert_eq!(s, Status::Ok, "{:?}", log.borrow());
        let at_start = get(&mut a, "pulley1.torque");
        run(&mut a, 0.0, 0.01, 1e-3);
        set(&mut a, "pulley2.angle", Value::Real(angle0 + turn));
        run(&mut a, 0.01, 0.02, 1e-3);
        (at_start, get(&mut a, "pulley1.torque"))
    };
    let (t0, t0_end) = torques(0.0, 0.0);
    let (t1, t1_end) = torques(0.7, 0.0);
    println!(
        "torque on pulley 1: {t0:.3e} / {t0_end:.3e} N m (angle 0), {t1:.3e} / {t1_end:.3e} (0.7 rad)"
    );
    assert!((t1 - t0).abs() < 1e-6 && (t1_end - t0_end).abs() < 1e-6);
    // a turn of 2 mrad of pulley 2 during the run stretches a span: about EA ρ2 Δθ / L_span · ρ1
    let (_, turned) = torques(0.7, 2e-3);
    println!("after a 2 mrad turn: {turned:.3} N m");
    assert!(turned.abs() > 1.0, "{turned}");
}
