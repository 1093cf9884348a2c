//! The air spring at the shell level (`model.fidelity = 1`): its design state against the
//! membrane level (issue 11: "levels 1 and 2 agree on vertical force within 1 %"), the port
//! block against finite differences of the static equilibrium, and symmetry.

mod common;

use flexfmu::kinds::air_spring::AirSpringScene;
use flexfmu::kinds::air_spring::model::AirSpring;
use flexfmu::kinds::air_spring::shell::AirSpringShell;
use flexfmu::scene::{ParamValues, Scene};

fn text() -> String {
    std::fs::read_to_string(common::scene_path("air_spring")).unwrap()
}

/// The scene text with `key = old` replaced by `key = new` in the line starting with `key`.
fn with(text: &str, key: &str, value: &str) -> String {
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

#[test]
#[ignore]
fn explore_mesh() {
    let t = text();
    for (nc, nm) in [(16, 40), (20, 40), (24, 40), (24, 30), (32, 40)] {
        let tt = with(
            &with(&t, "n_circumferential", &nc.to_string()),
            "n_meridional",
            &nm.to_string(),
        );
        let t0 = std::time::Instant::now();
        let shell = build_shell(&tt);
        let dt = t0.elapsed().as_secs_f64();
        let membrane = build_membrane(&tt);
        let f1 = shell.committed_force()[2];
        let f2 = membrane.committed_force();
        eprintln!(
            "{nc}x{nm}: shell {f1:.2} membrane {f2:.2} rel {:.3e} V {:.4e} vs {:.4e} build {dt:.2}s",
            f1 / f2 - 1.0,
            shell.gas().committed().volume,
            membrane.gas().committed().volume
        );
    }
}

#[test]
#[ignore]
fn explore_dynamics() {
    use common::{get, init, instance, set, step};
    use flexfmu::variables::Value;
    let (mut inst, _log) = instance("air_spring", false);
    init(&mut inst);
    let f0 = get(&mut inst, "top.fz");
    eprintln!("init fz {f0} k {}", get(&mut inst, "spring.stiffness"));
    let h = 1e-3;
    let t0 = std::time::Instant::now();
    let n = 100;
    for i in 0..n {
        let t = i as f64 * h;
        let z = 0.25 + 0.01 * (2.0 * std::f64::consts::PI * 2.0 * (t + h)).sin();
        set(&mut inst, "top.z", Value::Real(z));
        step(&mut inst, t, h);
        if i % 10 == 9 {
            eprintln!(
                "t {:.3} z {z:.5} fz {:.2} fx {:.3e} p {:.1}",
                t + h,
                get(&mut inst, "top.fz"),
                get(&mut inst, "top.fx"),
                get(&mut inst, "gas.pressure_gauge")
            );
        }
    }
    eprintln!(
        "wall per sim s: {:.3}",
        t0.elapsed().as_secs_f64() / (n as f64 * h)
    );
    set(&mut inst, "top.rx", Value::Real(0.01));
    step(&mut inst, n as f64 * h, h);
    eprintln!(
        "tilted: fz {:.2} mx {:.3} my {:.3} fy {:.3}",
        get(&mut inst, "top.fz"),
        get(&mut inst, "top.mx"),
        get(&mut inst, "top.my"),
        get(&mut inst, "top.fy")
    );
}

#[test]
#[ignore]
fn explore_bending() {
    let t = with(&text(), "tension_only", "false\nbending_stiffness = 0.027");
    let t0 = std::time::Instant::now();
    let shell = build_shell(&t);
    eprintln!("build {:.2}s", t0.elapsed().as_secs_f64());
    let membrane = build_membrane(&t);
    eprintln!(
        "bending: shell {:?} membrane {}",
        shell.committed_force(),
        membrane.committed_force()
    );
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
        let mut m = build_shell(&t);
        m.move_plate(pose).unwrap();
        let (k, dv) = m.port_block().unwrap();
        let v0 = m.gas().committed().volume;
        let steps = [2e-5, 2e-5, 2e-5, 2e-4, 2e-4];
        for j in 0..5 {
            let at = |s: f64| {
                let mut p = pose;
                p[j] += s;
                let mut mm = build_shell(&t);
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
}

#[test]
#[ignore]
fn explore_fmu_static() {
    use common::{get, init, instance, set};
    use flexfmu::variables::Value;
    for z in [0.24 - 2e-5, 0.24, 0.24 + 2e-5] {
        let (mut inst, _log) = instance("air_spring", false);
        for (k, v) in [("top.x", 0.003), ("top.z", z), ("top.ry", 0.01)] {
            set(&mut inst, k, Value::Real(v));
        }
        init(&mut inst);
        eprintln!("z {z}: fx {} fz {} my {} x {}", get(&mut inst, "top.fx"), get(&mut inst, "top.fz"), get(&mut inst, "top.my"), get(&mut inst, "spring.height"));
    }
}

#[test]
#[ignore]
fn explore_branches() {
    let base = text();
    for (label, t) in [
        ("D0 m40", with(&base, "n_meridional", "40")),
        ("D0 24x40", with(&with(&base, "n_meridional", "40"), "n_circumferential", "24")),
    ] {
        for z in [0.24 - 2e-5, 0.24, 0.24 + 2e-5] {
            let mut m = build_shell(&t);
            let f0 = m.move_plate([0.003, 0.0, 0.25, 0.0, 0.0]).unwrap();
            let f1 = match m.move_plate([0.003, 0.0, z, 0.0, 0.0]) {
                Ok(f) => f,
                Err(e) => { eprintln!("{label} z {z}: {e}"); continue; }
            };
            let f = match m.move_plate([0.003, 0.0, z, 0.0, 0.01]) {
                Ok(f) => f,
                Err(e) => { eprintln!("{label} z {z} tilt: {e}"); continue; }
            };
            eprintln!("{label} z {z}: x-shift fx {:.3} | then z fx {:.3} | then tilt fx {:.3} fz {:.3} my {:.3}", f0[0], f1[0], f[0], f[2], f[4]);
        }
    }
}
