//! Speed of the 3D belt (`scenes/belt_drive_3d.toml`) against the planar belt
//! (`scenes/belt_drive.toml`, same belt and pulleys) at 60/120/240 elements: 0.3 s of
//! running (pulley 1 ramped to 10 rad/s over 0.1 s, 5 N m load on pulley 2), 1 ms steps.
//! Prints wall time, real-time factor (simulated / wall time, in process, without fmpy),
//! Newton iterations and the cost per element per Newton iteration. Timings are of this run
//! on this machine; compare the ratios within one run. The 3D belt runs with the contact at
//! the centre line (`contact.width_points` = 1) and across the width (3 points).
//!
//! `cargo run --release --example bench_belt_3d`

use flexfmu::model::build_model;
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use flexfmu::variables::{Role, Value, VariableTable};
use std::time::Instant;

fn run(name: &str, n_el: i32, width_points: Option<i32>) -> (f64, usize, usize) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{name}.toml"));
    let scene = Scene::from_path(&path).unwrap();
    let vars = VariableTable::from_scene(&scene);
    let mut p = ParamValues::defaults(&scene.params);
    p.set("belt.n_elements", Value::Integer(n_el));
    if let Some(w) = width_points {
        p.set("contact.width_points", Value::Integer(w));
    }
    let input = |n: &str| match vars.by_name(n).unwrap().role {
        Role::Input(k) => k,
        _ => panic!("{n}"),
    };
    let (ia, iw, it) = (
        input("pulley1.angle"),
        input("pulley1.omega"),
        input("pulley2.torque_in"),
    );
    let model = build_model(&scene, &p).unwrap();
    let cfg = SolverConfig::from_params(&p);
    let mut sim = Simulation::new(model, cfg, 0.0).unwrap();
    sim.initialize().unwrap();
    let start = Instant::now();
    let (h, t_end) = (1e-3, 0.3);
    let mut angle = 0.0;
    for i in 0..(t_end / h) as usize {
        let t = i as f64 * h;
        let r = |t: f64| (t / 0.1_f64).min(1.0);
        let w = 0.5 * 10.0 * (r(t) + r(t + h));
        sim.set_input(ia, angle);
        sim.set_input(iw, w);
        sim.set_input(it, -5.0 * r(t));
        sim.advance(t + h).unwrap();
        angle += w * h;
    }
    let wall = start.elapsed().as_secs_f64();
    let s = sim.stats();
    (wall, s.steps, s.newton.iterations)
}

fn main() {
    println!(
        "scene | elements | wall [s] for 0.3 s | real-time factor | steps | Newton iterations | us per element per iteration"
    );
    for n in [60, 120, 240] {
        for (name, width) in [
            ("belt_drive", None),
            ("belt_drive_3d", Some(1)),
            ("belt_drive_3d", Some(3)),
        ] {
            let (wall, steps, its) = run(name, n, width);
            let name = match width {
                Some(w) => format!("{name} (width_points {w})"),
                None => name.to_string(),
            };
            println!(
                "{name} | {n} | {wall:.3} | {:.2} | {steps} | {its} | {:.3}",
                0.3 / wall,
                1e6 * wall / (n as f64 * its as f64)
            );
        }
    }
}
