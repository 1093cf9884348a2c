//! Speed of the 3D belt (`scenes/belt_drive_3d.toml`) against the planar belt
//! (`scenes/belt_drive.toml`, same belt and pulleys) at 60/120/240 elements: 0.3 s of
//! running (pulley 1 ramped to 10 rad/s over 0.1 s, 5 N m load on pulley 2), 1 ms steps.
//! Prints wall time, real-time factor (simulated / wall time, in process, without fmpy),
//! failed (rejected) steps, Newton iterations and factorizations per step and the cost per
//! element per Newton iteration; the 3D belt with and without its transport predictor
//! (`Belt3d::set_transport_predictor`). Element counts from the command line (default 60 120
//! 240). Timings are of this run
//! on this machine; compare the ratios within one run. The 3D belt runs with the contact at
//! the centre line (`contact.width_points` = 1) and across the width (3 points).
//!
//! `cargo run --release --example bench_belt_3d`

use flexfmu::kinds::belt_3d::model::Belt3d;
use flexfmu::model::build_model;
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::solver::simulation::{RunStats, Simulation, SolverConfig};
use flexfmu::variables::{Role, Value, VariableTable};
use std::time::Instant;

fn run(name: &str, n_el: i32, width_points: Option<i32>, predictor: bool) -> (f64, RunStats) {
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
    if let Some(m) = sim.model_as_mut::<Belt3d>() {
        m.set_transport_predictor(predictor);
    }
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
    (wall, sim.stats())
}

fn main() {
    let counts: Vec<i32> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("element count"))
        .collect();
    let counts = if counts.is_empty() {
        vec![60, 120, 240]
    } else {
        counts
    };
    println!(
        "scene | elements | predictor | wall [s] for 0.3 s | real-time factor | steps | failed steps | Newton it./step | factorizations/step | us per element per iteration"
    );
    for n in counts {
        for (name, width, predictor) in [
            ("belt_drive", None, true),
            ("belt_drive_3d", Some(1), false),
            ("belt_drive_3d", Some(1), true),
            ("belt_drive_3d", Some(3), false),
            ("belt_drive_3d", Some(3), true),
        ] {
            let (wall, s) = run(name, n, width, predictor);
            let name = match width {
                Some(w) => format!("{name} (width_points {w})"),
                None => name.to_string(),
            };
            let its = s.newton.iterations;
            println!(
                "{name} | {n} | {} | {wall:.3} | {:.2} | {} | {} | {:.2} | {:.2} | {:.3}",
                if predictor { "on" } else { "off" },
                0.3 / wall,
                s.steps,
                s.rejected,
                its as f64 / s.steps as f64,
                s.newton.factorizations as f64 / s.steps as f64,
                1e6 * wall / (n as f64 * its as f64)
            );
        }
    }
}
