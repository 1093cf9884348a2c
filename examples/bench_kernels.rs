//! Cost of the numerical kernels (release build, one core), printed as tables:
//!
//! 1. force + tangent + assembly per element per Newton iteration, and the whole step, for the
//!    seed-000 pendulum at 16 to 1024 elements (the cost per step must grow linearly: a chain is
//!    banded);
//! 2. the overhead of `fmi2DoStep` itself (C shim, state machine, inputs, outputs) on top of
//!    the integration, for a step that does almost no work.
//!
//! `cargo run --release --example bench_kernels [-- --csv out.csv]`

mod bench_util;
use bench_util::time_it;
use flexfmu::fmi2::exports::*;
use flexfmu::fmi2::types::*;
use flexfmu::model::{JacobianCoeffs, build_model};
use flexfmu::model_description::scene_guid;
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use flexfmu::variables::Value;
use std::ffi::CString;
use std::hint::black_box;
use std::path::Path;
use std::ptr;
use std::time::Instant;

fn pendulum(n: i32) -> (Scene, ParamValues) {
    let scene =
        Scene::from_path(Path::new("scenes/pendulum.toml")).expect("run from the repository root");
    let mut p = ParamValues::defaults(&scene.params);
    p.set("mesh.n_elements", Value::Integer(n));
    (scene, p)
}

fn main() {
    let csv_path = std::env::args().skip_while(|a| a != "--csv").nth(1);
    let mut csv = String::from(
        "n_elements,n_dof,force_tangent_assembly_us_per_element,force_only_us_per_element,factor_solve_us,step_us,step_us_per_element,newton_iterations_per_step\n",
    );
    println!(
        "Seed-000 pendulum (E = 2.07e7 Pa), generalized-alpha, h = 1 ms, modified Newton, deformed state after 0.2 s"
    );
    println!(
        "{:>6} {:>6} {:>14} {:>12} {:>12} {:>10} {:>12} {:>8}",
        "n_el", "n_dof", "F+K+asm/el", "F/el", "factor+solve", "step", "step/el", "it/step"
    );
    println!(
        "{:>6} {:>6} {:>14} {:>12} {:>12} {:>10} {:>12} {:>8}",
        "", "", "[us]", "[us]", "[us]", "[us]", "[us]", ""
    );
    for n in [16, 32, 64, 128, 256, 512, 1024] {
        let (scene, params) = pendulum(n);
        let model = build_model(&scene, &params).unwrap();
        let mut sim = Simulation::new(model, SolverConfig::from_params(&params), 0.0).unwrap();
        sim.initialize().unwrap();
        sim.advance(0.2).unwrap();
        // a copy of the model at the same state for the kernel timings
        let mut model = build_model(&scene, &params).unwrap();
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
        let t_fk = time_it(0.3, || {
            model
                .residual(0.2, black_box(&q), &v, &a, 1.0, &mut r, Some((c, &mut jac)))
                .unwrap();
        });
        let t_f = time_it(0.3, || {
            model
                .residual(0.2, black_box(&q), &v, &a, 1.0, &mut r, None)
                .unwrap();
        });
        let mut solver =
            flexfmu::linalg::LinearSolver::new(model.pattern(), flexfmu::linalg::SolverKind::Auto)
                .unwrap();
        let pattern = model.pattern().clone();
        let t_fs = time_it(0.3, || {
            solver.factor(&pattern, &jac).unwrap();
            let mut x = r.clone();
            solver.solve_in_place(&mut x);
            black_box(&x);
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
        let us = 1e6;
        println!(
            "{:>6} {:>6} {:>14.3} {:>12.3} {:>12.2} {:>10.1} {:>12.3} {:>8.2}",
            n,
            nf,
            t_fk * us / n as f64,
            t_f * us / n as f64,
            t_fs * us,
            t_step * us,
            t_step * us / n as f64,
            its
        );
        csv += &format!(
            "{n},{nf},{},{},{},{},{},{}\n",
            t_fk * us / n as f64,
            t_f * us / n as f64,
            t_fs * us,
            t_step * us,
            t_step * us / n as f64,
            its
        );
    }

    // fmi2DoStep overhead: a 1-element cantilever at rest, modified Newton: the step is one
    // force evaluation and one solve with a kept factorization.
    let scene = Scene::from_path(Path::new("scenes/cantilever.toml")).unwrap();
    let dir = std::env::temp_dir().join(format!("flexfmu-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("scene.toml"), &scene.text).unwrap();
    let uri = CString::new(format!("file://{}", dir.display())).unwrap();
    let guid = CString::new(scene_guid(&scene)).unwrap();
    let cb = Fmi2CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: ptr::null_mut(),
    };
    let vr_n = scene
        .params
        .iter()
        .position(|p| p.name == "mesh.n_elements")
        .unwrap() as u32;
    // SAFETY: valid arguments per the FMI signatures.
    let per_step = unsafe {
        let c = fmi2Instantiate(
            c"bench".as_ptr(),
            FMI2_COSIMULATION,
            guid.as_ptr(),
            uri.as_ptr(),
            &cb,
            0,
            0,
        );
        assert!(!c.is_null());
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), FMI2_OK);
        assert_eq!(fmi2SetInteger(c, [vr_n].as_ptr(), 1, [1].as_ptr()), FMI2_OK);
        assert_eq!(fmi2EnterInitializationMode(c), FMI2_OK);
        assert_eq!(fmi2ExitInitializationMode(c), FMI2_OK);
        let mut t = 0.0;
        let h = 1e-4;
        let per = time_it(0.5, || {
            let s = fmi2DoStep(c, t, h, 1);
            assert_eq!(s, FMI2_OK);
            t += h;
        });
        fmi2FreeInstance(c);
        per
    };
    let (_, mut params) = pendulum(1);
    params = {
        let mut p = ParamValues::defaults(&scene.params);
        p.set("mesh.n_elements", Value::Integer(1));
        let _ = params;
        p
    };
    let model = build_model(&scene, &params).unwrap();
    let mut sim = Simulation::new(model, SolverConfig::from_params(&params), 0.0).unwrap();
    sim.initialize().unwrap();
    let mut t = 0.0;
    let per_advance = time_it(0.5, || {
        t += 1e-4;
        sim.advance(t).unwrap();
    });
    println!("\nfmi2DoStep on a 1-element cantilever at rest (h = 0.1 ms, one internal step):");
    println!(
        "  fmi2DoStep through the C ABI: {:.3} us; Simulation::advance alone: {:.3} us; FMI overhead: {:.3} us",
        per_step * 1e6,
        per_advance * 1e6,
        (per_step - per_advance) * 1e6
    );
    csv += &format!(
        "# dostep_us,{},advance_us,{},overhead_us,{}\n",
        per_step * 1e6,
        per_advance * 1e6,
        (per_step - per_advance) * 1e6
    );
    if let Some(p) = csv_path {
        std::fs::write(&p, csv).unwrap();
        println!("csv: {p}");
    }
}
