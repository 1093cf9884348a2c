//! The air spring at the shell level (`model.fidelity = 1`): its design state against the
//! membrane level (issue 11: "levels 1 and 2 agree on vertical force within 1 %"), the port
//! block against finite differences of the static equilibrium, and symmetry.

mod common;

use common::with;

use flexfmu::kinds::air_spring::AirSpringScene;
use flexfmu::kinds::air_spring::model::AirSpring;
use flexfmu::kinds::air_spring::shell::AirSpringShell;
use flexfmu::scene::{ParamValues, Scene};

/// The shipped scene at 16 elements around, the mesh these comparisons were measured on (the
/// shipped automatic count takes 24 for the reference spring; `tests/air_spring_auto_mesh.rs`).
fn text() -> String {
    let t = std::fs::read_to_string(common::scene_path("air_spring")).unwrap();
    with(&t, "n_circumferential", "16")
}

fn build_shell(text: &str) -> AirSpringShell {
    let scene = Scene::from_toml(text).unwrap();
    let tables: &AirSpringScene = scene.tables().unwrap();
    AirSpringShell::build(tables, &ParamValues::defaults(&scene.params)).unwrap()
}

fn build_membrane(text: &str) -> AirSpring {
    let t = with(text, "fidelity", "2");
    let t: String = t
        .lines()
        .filter(|l| !l.trim_start().starts_with("n_circumferential"))
        .collect::<Vec<_>>()
        .join("\n");
    let scene = Scene::from_toml(&t).unwrap();
    let tables: &AirSpringScene = scene.tables().unwrap();
    AirSpring::build(tables, &ParamValues::defaults(&scene.params)).unwrap()
}

/// At the design height the shell's vertical force and bag volume agree with the membrane
/// level's on the same meridional mesh within 1 %, and the lateral force and moments vanish
/// (the mesh is symmetric).
#[test]
fn design_state_agrees_with_the_membrane_level() {
    let t = text();
    let shell = build_shell(&t);
    let membrane = build_membrane(&t);
    let f1 = shell.committed_force();
    let f2 = membrane.committed_force();
    let v1 = shell.gas().committed().volume;
    let v2 = membrane.gas().committed().volume;
    eprintln!("shell {f1:?} V {v1}; membrane {f2} V {v2}");
    assert!((f1[2] - f2).abs() < 0.01 * f2, "fz {} vs {f2}", f1[2]);
    assert!((v1 - v2).abs() < 0.01 * v2, "V {v1} vs {v2}");
    for i in [0, 1] {
        assert!(f1[i].abs() < 1e-6 * f2, "lateral {i}: {}", f1[i]);
    }
    for i in [3, 4] {
        assert!(f1[i].abs() < 1e-6 * f2 * 0.14, "moment {i}: {}", f1[i]);
    }
}

/// The constant-pressure characteristic (5 bar gauge) over the stroke: the shell's vertical
/// force and bag volume agree with the membrane level's within 1 % (issue 11 item 8), with the
/// shipped meshes (16 × 40 shell, 60 membrane elements).
#[test]
fn constant_pressure_characteristic_agrees_with_the_membrane_level() {
    let t = text();
    for h in [0.20, 0.22, 0.235, 0.265, 0.28, 0.30] {
        // from the design state (see the module notes on longer paths)
        let mut shell = build_shell(&t);
        let mut membrane = build_membrane(&with(&t, "n_meridional", "60"));
        let (f1, v1) = shell.equilibrium_at([0.0, 0.0, h, 0.0, 0.0], 5e5).unwrap();
        let (f2, v2) = membrane.equilibrium_at(h, 5e5).unwrap();
        eprintln!(
            "h {h}: shell {:.2} N {v1:.5e} m3, membrane {f2:.2} N {v2:.5e} m3 ({:+.2e}, {:+.2e}) {f1:?} lobe {:?}",
            f1[2],
            f1[2] / f2 - 1.0,
            v1 / v2 - 1.0,
            shell
                .nodes()
                .iter()
                .map(|x| x.xy().norm())
                .fold(0.0, f64::max)
        );
        assert!((f1[2] / f2 - 1.0).abs() < 0.01, "h {h}: {} vs {f2}", f1[2]);
        assert!((v1 / v2 - 1.0).abs() < 0.01, "h {h}: V {v1} vs {v2}");
    }
}

/// With a bending stiffness (the rubber's own, `E t³/12` = 0.027 N m) the seed-004 elements join
/// the membrane: the design force stays within 1 % of the membrane level with the same
/// meridional bending, and moves from the pure membrane by about as much as there.
#[test]
fn bending_wall_agrees_with_the_membrane_level() {
    let t = with(
        &with(&text(), "n_meridional", "20"),
        "tension_only",
        "false\nbending_stiffness = 0.027",
    );
    let shell = build_shell(&t);
    let membrane = build_membrane(&t);
    let (f1, f2) = (shell.committed_force()[2], membrane.committed_force());
    eprintln!(
        "bending: shell {f1:.2} membrane {f2:.2} ({:+.2e})",
        f1 / f2 - 1.0
    );
    assert!((f1 / f2 - 1.0).abs() < 0.01);
}

/// The port block (the analytic static condensation with the gas's stiffness) against central
/// differences of the static equilibrium with the gas closed, column by column, at the design
/// pose and at a tilted, shifted, compressed pose.
#[test]
fn port_block_matches_finite_differences_of_the_equilibrium() {
    let t = with(&text(), "n_meridional", "30");

    for pose in [
        [0.0, 0.0, 0.25, 0.0, 0.0],
        [0.004, -0.003, 0.235, 0.02, -0.015],
    ] {
        common::assert_port_block(|| build_shell(&t), pose);
    }
}

/// The closed-gas characteristic through the FMI instances (the start value of `top.z` moves
/// the charged spring there before the static initialization): the shell level's force, volume
/// and pressure agree with the membrane level's within 1 % over the stroke 0.18 … 0.30 m; at
/// the full extension 0.32 m the force is 1.3 % low (measured; the facets' share of the wall
/// force grows as the pressure falls), checked within 2 %.
#[test]
fn closed_gas_characteristic_agrees_with_the_membrane_level() {
    use common::{get, init, instance, set};
    use flexfmu::variables::Value;
    for h in [0.18, 0.21, 0.27, 0.30, 0.32] {
        let mut out = vec![];
        for name in ["air_spring", "air_spring_axisym"] {
            let (mut inst, _log) = instance(name, false);
            set(&mut inst, "top.z", Value::Real(h));
            init(&mut inst);
            out.push([
                get(&mut inst, "top.fz"),
                get(&mut inst, "gas.volume"),
                get(&mut inst, "gas.pressure_gauge"),
            ]);
        }
        eprintln!("h {h}: shell {:?} membrane {:?}", out[0], out[1]);
        let tol = if h > 0.31 { 0.02 } else { 0.01 };
        for (k, (a, b)) in out[0].iter().zip(&out[1]).enumerate() {
            assert!((a / b - 1.0).abs() < tol, "h {h}, quantity {k}: {a} vs {b}");
        }
    }
}

/// Other springs and gas laws than the shipped scene: spring B of the reference (other piston,
/// bead, sleeve and cords) at 4 bar, and the energy law with heat transfer and a 20 L reservoir
/// behind pipe and orifice. The closed-gas force after the static initialization at heights off
/// the design state agrees with the membrane level's within 1 %.
#[test]
fn other_springs_and_gas_laws_agree_with_the_membrane_level() {
    use common::{output, simulation};
    use flexfmu::variables::Value;
    let base = text();
    let mut spring_b = with(&base, "pressure_design", "4.0e5");
    for (k, v) in [
        ("radius", "0.09"),
        ("height", "0.12"),
        ("bead_radius", "0.13"),
        ("sleeve_radius", "0.115"),
        ("sleeve_length", "0.26"),
        ("cord_angle", "50.0"),
        ("cord_stiffness", "1.0e6"),
        ("matrix_stiffness", "3.0e4"),
    ] {
        spring_b = with(&spring_b, k, v);
    }
    let reservoir = format!(
        "{}\n[reservoir]\nvolume = 0.020\n[orifice]\ndiameter = 0.008\ncd = 0.7\n[pipe]\nlength = 1.5\ndiameter = 0.016\n",
        with(&with(&base, "model", "\"energy\""), "heat_transfer", "5.0")
    );
    for (label, t, heights) in [
        ("spring B, 4 bar", spring_b, [0.21, 0.26]),
        ("energy law with a reservoir", reservoir, [0.22, 0.28]),
    ] {
        let membrane = with(&t, "fidelity", "2").replace("n_circumferential = 16\n", "");
        let membrane = with(&membrane, "n_meridional", "60");
        for h in heights {
            let z = [("top.z", Value::Real(h))];
            let mut f = vec![];
            for text in [&t, &membrane] {
                let scene = Scene::from_toml(text).unwrap();
                let sim = simulation(&scene, &z).unwrap_or_else(|e| panic!("{label} at {h}: {e}"));
                f.push(output(&scene, &sim, "top.fz"));
            }
            eprintln!(
                "{label} at {h} m: shell {:.2} N, membrane {:.2} N ({:+.2e})",
                f[0],
                f[1],
                f[0] / f[1] - 1.0
            );
            assert!((f[0] / f[1] - 1.0).abs() < 0.01, "{label} at {h}: {f:?}");
        }
    }
}

/// Friction at the shell level (`contact.mu` = 0.5, 12 × 30 elements): over a ±5 mm lateral
/// sine of the plate (1 Hz, one period at 1 ms steps) the sleeve slides on the piston where it
/// is dragged sideways, so friction dissipates, the lateral force changes by a fraction of
/// itself (stick stiffens, sliding lags: a hysteresis; measured 115 N of 978 N), the vertical
/// force stays within 2 % of the frictionless spring's (measured 1.0 %), and the energy
/// balance closes with the friction work in it
/// (plate work = change of gas + strain + kinetic energy + dissipated).
#[test]
fn friction_at_the_shell_level_dissipates_and_keeps_the_energy_balance() {
    use common::{input_index, simulation};
    use flexfmu::variables::Value;
    let scene = Scene::from_toml(&text()).unwrap();
    let run = |mu: f64| {
        let mut sim = simulation(
            &scene,
            &[
                ("contact.mu", Value::Real(mu)),
                ("mesh.n_circumferential", Value::Integer(12)),
                ("mesh.n_meridional", Value::Integer(30)),
            ],
        )
        .unwrap();
        let (ix, ivx) = (input_index(&scene, "top.x"), input_index(&scene, "top.vx"));
        let w = 2.0 * std::f64::consts::PI;
        let drive = |t: f64| {
            vec![
                (ix, 0.005 * (w * t).sin()),
                (ivx, 0.005 * w * (w * t).cos()),
            ]
        };
        common::energy_run(&scene, &mut sim, 1000, 1e-3, drive, &["top.fx", "top.fz"])
            .into_iter()
            .map(|(o, lost, num, work)| (o[0], o[1], lost, num, work))
            .collect::<Vec<_>>()
    };
    let free = run(0.0);
    let rough = run(0.5);
    let fx_max = free.iter().map(|x| x.0.abs()).fold(0.0, f64::max);
    let dfx = free
        .iter()
        .zip(&rough)
        .map(|(a, b)| (a.0 - b.0).abs())
        .fold(0.0, f64::max);
    let dfz = free
        .iter()
        .zip(&rough)
        .map(|(a, b)| (a.1 - b.1).abs() / a.1)
        .fold(0.0, f64::max);
    let lost = rough.last().unwrap().2 - free.last().unwrap().2;
    let scale = rough.iter().map(|x| x.4.abs()).fold(0.0, f64::max);
    let numerical = rough.iter().map(|x| x.3.abs()).fold(0.0, f64::max);
    println!(
        "shell, mu = 0.5, ±5 mm lateral: lateral force up to {fx_max:.1} N changes by up to {dfx:.2} N, vertical force within {dfz:.2e}; friction dissipated {lost:.3e} J; energy balance: numerical part {numerical:.2e} J of plate work up to {scale:.3e} J"
    );
    assert!(lost > 0.0, "{lost}");
    assert!(dfx > 0.0 && dfx < 0.5 * fx_max, "{dfx} of {fx_max}");
    assert!(dfz < 2e-2, "{dfz}");
    assert!(numerical < 1e-2 * scale, "{numerical} of {scale}");
}
