//! The air spring off its shipped design (the fast subset of `scripts/air_spring_sweep.py`):
//! other springs, gas laws and start heights, checked against exact identities and against
//! other runs of the same model that must agree (no stored figures).
//!
//! What the sweep found (session 28): started away from the design height, the energy law
//! and the reservoir began out of equilibrium (the consistent initial accelerations used the
//! design charge's step law instead of the static state the solve had reached), so the spring
//! rang at a fixed plate and the force of the energy law with a strong heat transfer left the
//! isothermal law's by 1.6 % over a slow stroke.

mod common;

use common::{input_index, output, simulation};
use flexfmu::scene::Scene;
use flexfmu::solver::simulation::Simulation;
use flexfmu::variables::Value;

fn scene(name: &str) -> Scene {
    common::scene(name)
}

/// `top.fz` [N] after every one of `n` steps of 1 ms with the plate held at `z` [m].
fn at_rest(scene: &Scene, sim: &mut Simulation, z: f64, n: usize) -> Vec<f64> {
    let (iz, iv) = (input_index(scene, "top.z"), input_index(scene, "top.vz"));
    let t0 = sim.time();
    (1..=n)
        .map(|k| {
            sim.set_input(iz, z);
            sim.set_input(iv, 0.0);
            sim.advance(t0 + k as f64 * 1e-3).unwrap();
            output(scene, sim, "top.fz")
        })
        .collect()
}

/// A swept case: name, parameter overrides, start height [m].
type SweptCase<'a> = (&'a str, &'a [(&'a str, Value)], f64);

fn worst_rel(a: &[f64], b: f64) -> f64 {
    a.iter().map(|x| (x / b - 1.0).abs()).fold(0.0, f64::max)
}

/// Started at rest away from the design height, a spring with the energy law (any heat
/// transfer) or with a reservoir stays at rest when the plate is held: its force does not
/// move. The static state of the energy law is the isothermal one (thermal equilibrium), so
/// its force is that of the polytropic law with n = 1 from the same design charge.
#[test]
fn off_design_start_is_an_equilibrium_level_2() {
    let axisym = scene("air_spring_axisym");
    let z = 0.20;
    let mut iso = simulation(
        &axisym,
        &[
            ("gas.polytropic_exponent", Value::Real(1.0)),
            ("top.z", Value::Real(z)),
        ],
    )
    .unwrap();
    let f_iso = output(&axisym, &iso, "top.fz");
    let held = at_rest(&axisym, &mut iso, z, 5);
    assert!(worst_rel(&held, f_iso) < 1e-9, "n = 1 held: {held:?}");
    for h in [0.0, 1e6] {
        let mut sim = simulation(
            &axisym,
            &[
                ("gas.model", Value::Integer(2)),
                ("gas.heat_transfer", Value::Real(h)),
                ("top.z", Value::Real(z)),
            ],
        )
        .unwrap();
        let f0 = output(&axisym, &sim, "top.fz");
        let held = at_rest(&axisym, &mut sim, z, 20);
        let drift = worst_rel(&held, f0);
        println!(
            "energy law, h = {h} W/K, start {z} m: start force {f0:.3} N (n = 1: {f_iso:.3} N), held 20 ms within {drift:.2e}"
        );
        assert!(
            (f0 / f_iso - 1.0).abs() < 1e-9,
            "start force {f0} against {f_iso}"
        );
        assert!(drift < 1e-7, "the held spring moves: {held:?}");
    }
    let reservoir = scene("air_spring_reservoir");
    let mut sim = simulation(&reservoir, &[("top.z", Value::Real(z))]).unwrap();
    let f0 = output(&reservoir, &sim, "top.fz");
    let held = at_rest(&reservoir, &mut sim, z, 20);
    let drift = worst_rel(&held, f0);
    println!("reservoir, start {z} m: start force {f0:.3} N, held 20 ms within {drift:.2e}");
    assert!(drift < 1e-7, "the held spring moves: {held:?}");
}

/// The same at the shell level (16 x 40, a short hold).
#[test]
fn off_design_start_is_an_equilibrium_level_1() {
    let shell = scene("air_spring");
    let z = 0.22;
    let energy = [
        ("gas.model", Value::Integer(2)),
        ("gas.heat_transfer", Value::Real(0.0)),
        ("top.z", Value::Real(z)),
    ];
    let mut sim = simulation(&shell, &energy).unwrap();
    let f0 = output(&shell, &sim, "top.fz");
    let held = at_rest(&shell, &mut sim, z, 5);
    let drift = worst_rel(&held, f0);
    let iso = simulation(
        &shell,
        &[
            ("gas.polytropic_exponent", Value::Real(1.0)),
            ("top.z", Value::Real(z)),
        ],
    )
    .unwrap();
    let f_iso = output(&shell, &iso, "top.fz");
    println!(
        "level 1, energy law h = 0, start {z} m: {f0:.3} N (n = 1: {f_iso:.3} N), held 5 ms within {drift:.2e}"
    );
    assert!(
        (f0 / f_iso - 1.0).abs() < 1e-7,
        "start force {f0} against {f_iso}"
    );
    assert!(drift < 1e-6, "the held spring moves: {held:?}");
}

/// A slow stroke from an off-design start with a strong heat transfer follows the isothermal
/// law (the polytropic law with n = 1 from the same start), as it does from the design height
/// (`tests/air_spring.rs`, `energy_law_reduces_to_adiabatic_and_isothermal`).
#[test]
fn isothermal_limit_from_an_off_design_start() {
    let axisym = scene("air_spring_axisym");
    let z0 = 0.20;
    let run = |overrides: &[(&str, Value)]| {
        let mut all = overrides.to_vec();
        all.push(("top.z", Value::Real(z0)));
        let mut sim = simulation(&axisym, &all).unwrap();
        let (iz, iv) = (
            input_index(&axisym, "top.z"),
            input_index(&axisym, "top.vz"),
        );
        let (amp, w) = (0.02, 2.0 * std::f64::consts::PI * 0.5);
        (1..=200)
            .map(|k| {
                let t = k as f64 * 1e-3;
                sim.set_input(iz, z0 + amp * (w * t).sin());
                sim.set_input(iv, amp * w * (w * t).cos());
                sim.advance(t).unwrap();
                output(&axisym, &sim, "top.fz")
            })
            .collect::<Vec<_>>()
    };
    let hot = run(&[
        ("gas.model", Value::Integer(2)),
        ("gas.heat_transfer", Value::Real(1e6)),
    ]);
    let iso = run(&[("gas.polytropic_exponent", Value::Real(1.0))]);
    let worst = hot
        .iter()
        .zip(&iso)
        .map(|(a, b)| (a / b - 1.0).abs())
        .fold(0.0, f64::max);
    println!(
        "energy law h = 1e6 W/K from {z0} m against n = 1: worst force difference {worst:.2e}"
    );
    assert!(worst < 1e-4);
}

/// Swept springs at level 2 (other piston, sleeve, pressure, start height): the stiffness
/// output is the derivative of the closed-gas force over the start height (central
/// differences of re-initialisations, 10 µm) and satisfies the exact membrane identity
/// k = n p_abs A_e A_v / V + p_g dA_e/dz (air-spring-physics.md §0) with the model's own
/// A_e, A_v = -dV/dz, V and dA_e/dz.
#[test]
fn stiffness_identities_for_other_springs() {
    let axisym = scene("air_spring_axisym");
    let cases: [SweptCase; 4] = [
        (
            "piston 0.08 m",
            &[("piston.radius", Value::Real(0.08))],
            0.25,
        ),
        (
            "sleeve 0.40 m, n = 1.2",
            &[
                ("bellows.sleeve_length", Value::Real(0.40)),
                ("gas.polytropic_exponent", Value::Real(1.2)),
            ],
            0.25,
        ),
        ("2 bar", &[("gas.pressure_design", Value::Real(2e5))], 0.25),
        ("start 0.19 m", &[], 0.19),
    ];
    for (name, overrides, z) in cases {
        let state = |h: f64| {
            let mut all = overrides.to_vec();
            all.push(("top.z", Value::Real(h)));
            let sim = simulation(&axisym, &all).unwrap();
            let o = |n: &str| output(&axisym, &sim, n);
            [
                o("top.fz"),
                o("spring.stiffness"),
                o("gas.pressure"),
                o("gas.pressure_gauge"),
                o("spring.effective_area"),
                o("spring.volumetric_area"),
                o("gas.volume"),
            ]
        };
        let dz = 1e-5;
        let [_, k, p, pg, ae, av, v] = state(z);
        let (up, dn) = (state(z + dz), state(z - dz));
        let k_fd = -(up[0] - dn[0]) / (2.0 * dz);
        let dae_dz = -(up[4] - dn[4]) / (2.0 * dz);
        let n = overrides
            .iter()
            .find(|(k, _)| *k == "gas.polytropic_exponent")
            .map_or(1.4, |(_, v)| match v {
                Value::Real(x) => *x,
                _ => unreachable!(),
            });
        let k_id = n * p * ae * av / v + pg * dae_dz;
        println!(
            "{name}: k = {k:.1} N/m, difference of the force {:+.1e}, identity {:+.1e}",
            k / k_fd - 1.0,
            k / k_id - 1.0
        );
        assert!((k / k_fd - 1.0).abs() < 1e-4, "{name}: {k} against {k_fd}");
        assert!((k / k_id - 1.0).abs() < 1e-4, "{name}: {k} against {k_id}");
    }
}

/// A spring whose sleeve cannot reach from the bead to the piston is refused with a message
/// that names the parameters, not a panic.
#[test]
fn impossible_spring_names_its_parameters() {
    let axisym = scene("air_spring_axisym");
    let Err(e) = simulation(&axisym, &[("bellows.sleeve_length", Value::Real(0.10))]) else {
        panic!("a 0.10 m sleeve was mounted");
    };
    println!("{e}");
    assert!(e.contains("bellows.sleeve_length"), "{e}");
}

/// One ply (cords at +54 deg only) at the shell level: the unbalanced ply twists the sleeve and
/// the design state is not found; the refusal says why and names the parameter (the membrane
/// level, without twist, mounts the same spring as if the plies were balanced).
#[test]
fn one_ply_at_the_shell_level_names_the_unbalanced_ply() {
    let shell = scene("air_spring");
    let Err(e) = simulation(&shell, &[("bellows.n_plies", Value::Integer(1))]) else {
        panic!("one ply was mounted at the shell level: the message test has nothing to check");
    };
    println!("{e}");
    assert!(e.contains("bellows.n_plies = 1 is odd"), "{e}");
}

/// Quasi-static steps (the shipped level-2 scenes) take a jump of the position input, as a
/// master with long communication steps or without `top.vz` sends: the plate is moved 5 and
/// 30 mm down in one 1 ms step. Before session 31 the jump was applied at the step's start,
/// so halving the substep did not shrink it and Newton failed (5 mm: fmi2Discard with a
/// non-finite internal force; generalized-α took it). Held one more step, the closed spring
/// (polytropic, frictionless: its equilibria do not depend on the path) has the force of the
/// plate brought down in 1 mm steps, to Newton's tolerance. With the reservoir the first step's force lies between
/// the design force and the closed spring's (little air has passed the orifice).
#[test]
fn quasi_static_steps_take_a_jump_of_the_plate() {
    let closed = scene("air_spring_axisym");
    let reservoir = scene("air_spring_reservoir");
    for dz in [-0.005, -0.03] {
        let z = 0.25 + dz;
        let mut jump = simulation(&closed, &[]).unwrap();
        let f_design = output(&closed, &jump, "top.fz");
        let f_jump = at_rest(&closed, &mut jump, z, 2);
        let mut gradual = simulation(&closed, &[]).unwrap();
        let n = (dz.abs() / 1e-3).round() as usize;
        for k in 1..n {
            at_rest(&closed, &mut gradual, 0.25 + dz * k as f64 / n as f64, 1);
        }
        let f_gradual = at_rest(&closed, &mut gradual, z, 2)[1];
        let mut res = simulation(&reservoir, &[]).unwrap();
        let f_res = at_rest(&reservoir, &mut res, z, 1)[0];
        println!(
            "jump {dz} m in one step: {:.6} N (held {:.6} N), in 1 mm steps: {f_gradual:.6} N; with the reservoir {f_res:.6} N",
            f_jump[0], f_jump[1]
        );
        assert!(
            // Newton's tolerance (1e-8 on the scaled increment) moves the force by about
            // 1e-3 N (4e-8 measured at 5 mm)
            (f_jump[1] / f_gradual - 1.0).abs() < 1e-6,
            "closed spring {dz}: {f_jump:?} against {f_gradual}"
        );
        assert!(
            f_res > f_design && f_res <= f_jump[0] * (1.0 + 1e-9),
            "reservoir {dz}: {f_res} outside ({f_design}, {}]",
            f_jump[0]
        );
    }
}

/// The same at the shell level with quasi-static steps (`solver.integrator` = 5; the shipped
/// scene steps with generalized-α): 10 mm down in one step failed Newton before session 31.
/// Held one more step, its force is the membrane level's at that height within the levels'
/// 1 % band (0.17 % measured).
#[test]
fn quasi_static_shell_steps_take_a_jump_of_the_plate() {
    let z = 0.24;
    let shell = scene("air_spring");
    let mut sim = simulation(&shell, &[("solver.integrator", Value::Integer(5))]).unwrap();
    let f_shell = at_rest(&shell, &mut sim, z, 2)[1];
    let membrane = scene("air_spring_axisym");
    let mut sim = simulation(&membrane, &[]).unwrap();
    let f_membrane = at_rest(&membrane, &mut sim, z, 2)[1];
    println!(
        "10 mm down in one quasi-static step: shell {f_shell:.3} N, membrane {f_membrane:.3} N"
    );
    assert!(
        (f_shell / f_membrane - 1.0).abs() < 0.01,
        "{f_shell} against {f_membrane}"
    );
}
