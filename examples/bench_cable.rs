//! Cost of the ANCF cable path of the planar beam (`element.type = 2`, release build, one
//! core): per element and Newton iteration, the residual alone and the residual with the
//! iteration matrix (force + tangent + assembly), and the whole implicit step, on the soft
//! pendulum (`scenes/pendulum.toml`) at 16 to 1024 elements, deformed state after 0.2 s,
//! generalized-α, h = 1 ms, modified Newton. `scripts/race_exudyn.py` compares these with
//! Exudyn's residual and Jacobian of its `ANCFCable2D`.
//!
//! `cargo run --release --example bench_cable [-- --csv out.csv]`; with `-- --run N H` it only
//! simulates the pendulum with N elements and internal steps of H s for 1 s, 20 times, and
//! prints the wall time per run (a profiling target: `perf record`).

mod bench_util;
use bench_util::time_it;
use flexfmu::model::{JacobianCoeffs, build_model};
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use flexfmu::variables::Value;
use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

/// `--run N H [NAME=VALUE...]`: 20 runs of 1 s (with the given parameters), the best wall time per run and the solver statistics.
fn profile_run(scene: &Scene, n: i32, h: f64, extra: &[String]) {
    let mut p = ParamValues::defaults(&scene.params);
    for kv in extra {
        let (k, v) = kv.split_once('=').expect("extra arguments are NAME=VALUE");
        let value = match v.parse::<i32>() {
            Ok(i) => Value::Integer(i),
            Err(_) => Value::Real(v.parse().expect("a number")),
        };
        // Parameter names are 'static in the table; a handful of leaked names is fine here.
        p.set(Box::leak(k.to_string().into_boxed_str()), value);
    }
    p.set("mesh.n_elements", Value::Integer(n));
    p.set("element.type", Value::Integer(2));
    p.set("solver.max_step", Value::Real(h));
    let mut best = f64::INFINITY;
    let mut stats = None;
    for _ in 0..20 {
        let model = build_model(scene, &p).unwrap();
        let mut sim = Simulation::new(model, SolverConfig::from_params(&p), 0.0).unwrap();
        sim.initialize().unwrap();
        let t0 = Instant::now();
        sim.advance(1.0).unwrap();
        best = best.min(t0.elapsed().as_secs_f64());
        stats = Some(sim.stats());
    }
    println!(
        "{n} elements, h = {h} s: {:.3} ms per simulated second; {:?}",
        best * 1e3,
        stats.unwrap()
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--run") {
        let scene = Scene::from_path(Path::new("scenes/pendulum.toml"))
            .expect("run from the repository root");
        profile_run(
            &scene,
            args[i + 1].parse().unwrap(),
            args[i + 2].parse().unwrap(),
            &args[i + 3..],
        );
        return;
    }
    let csv_path = std::env::args().skip_while(|a| a != "--csv").nth(1);
    let mut csv = String::from(
        "n_elements,n_dof,residual_us_per_element,residual_jacobian_us_per_element,step_us_per_element,newton_iterations_per_step\n",
    );
    println!(
        "ANCF cable pendulum (element.type = 2), generalized-alpha, h = 1 ms, modified Newton, state after 0.2 s"
    );
    println!(
        "{:>6} {:>6} {:>12} {:>14} {:>12} {:>8}",
        "n_el", "n_dof", "F/el [us]", "F+K+asm/el", "step/el", "it/step"
    );
    let scene =
        Scene::from_path(Path::new("scenes/pendulum.toml")).expect("run from the repository root");
    for n in [16, 64, 256, 1024] {
        let mut p = ParamValues::defaults(&scene.params);
        p.set("mesh.n_elements", Value::Integer(n));
        p.set("element.type", Value::Integer(2));
        let model = build_model(&scene, &p).unwrap();
        let mut sim = Simulation::new(model, SolverConfig::from_params(&p), 0.0).unwrap();
        sim.initialize().unwrap();
        sim.advance(0.2).unwrap();
        let mut model = build_model(&scene, &p).unwrap();
        let nf = model.n_free();
        let (mut q, mut v) = (vec![0.0; nf], vec![0.0; nf]);
        sim.model().free_state(&mut q, &mut v);
        let a = vec![0.0; nf];
        let mut r = vec![0.0; nf];
        let mut jac = vec![0.0; model.pattern().nnz()];
        let c = JacobianCoeffs {
            mass: 1.0,
            damping: 0.0,
            stiffness: 2.5e-7,
        };
        let t_f = time_it(0.3, || {
            model
                .residual(0.2, black_box(&q), &v, &a, 1.0, &mut r, None)
                .unwrap();
        });
        let t_fk = time_it(0.3, || {
            model
                .residual(0.2, black_box(&q), &v, &a, 1.0, &mut r, Some((c, &mut jac)))
                .unwrap();
        });
        let before = sim.stats();
        let steps = 200;
        let t0 = Instant::now();
        let mut t = 0.2;
        for _ in 0..steps {
            t += 1e-3;
            sim.advance(t).unwrap();
        }
        let t_step = t0.elapsed().as_secs_f64() / steps as f64;
        let its = (sim.stats().newton.iterations - before.newton.iterations) as f64 / steps as f64;
        let per = |x: f64| x * 1e6 / n as f64;
        println!(
            "{:>6} {:>6} {:>12.3} {:>14.3} {:>12.3} {:>8.2}",
            n,
            nf,
            per(t_f),
            per(t_fk),
            per(t_step),
            its
        );
        csv += &format!(
            "{n},{nf},{},{},{},{its}\n",
            per(t_f),
            per(t_fk),
            per(t_step)
        );
    }
    if let Some(p) = csv_path {
        std::fs::write(&p, csv).unwrap();
        println!("csv: {p}");
    }
}
