//! Benchmark of the seed-003 co-rotational 3D beam (issue 6), on the library directly (no FMI
//! layer), release build, one thread:
//!
//! 1. Cost per element per Newton iteration on the cantilever (`scenes/cantilever3d.toml`) for
//!    16 to 1024 elements and both inertia models: element kernels (internal force and exact
//!    tangent, inertia force with mass, gyroscopic and configuration matrices, loads) plus
//!    scatter into the fixed sparse pattern, and separately the factorization and solve; and
//!    the split of one element evaluation into its kernels.
//! 2. Accuracy against wall time on the Simo–Vu-Quoc right-angle cantilever
//!    (`scenes/right_angle_cantilever.toml`, 30 s, elbow pulse, Newmark): lumped against
//!    consistent inertia over element counts at Δt = 0.05 s (error against 128 elements,
//!    consistent, same Δt), and over internal steps at 20 elements (error against Δt/32).
//!
//! Run: `cargo run --release --example bench_beam_3d [out-dir]` (default `build/bench`); writes
//! `corot_cost.csv` and `corot_tradeoff.csv`; `scripts/bench_beam_3d.py` plots them.

mod bench_util;
use bench_util::{best, scene};
use flexfmu::elements::corotational3d::{
    BeamSection, Corot3d, MassModel, Mat12, Nodes, Rates, Theory, Vec12,
};
use flexfmu::elements::rotation::exp_so3;
use flexfmu::kinds::beam_3d::Beam3dScene;
use flexfmu::kinds::beam_3d::model::Beam3d;
use flexfmu::linalg::SolverKind;
use flexfmu::model::{JacobianCoeffs, MechanicalSystem, Model, build_model};
use flexfmu::scene::ParamValues;
use flexfmu::solver::newton::Workspace;
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use flexfmu::variables::{Role, Value, VariableTable};
use nalgebra::{Matrix3, Vector3};
use std::hint::black_box;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

struct Cost {
    n: usize,
    mass: i32,
    assemble_us: f64,
    factor_us: f64,
}

fn cost(n: usize, mass: i32) -> Cost {
    let sc = scene("cantilever3d");
    let mut p = ParamValues::defaults(&sc.params);
    p.set("mesh.n_elements", Value::Integer(n as i32));
    p.set("element.mass", Value::Integer(mass));
    let mut m = Beam3d::build(sc.tables::<Beam3dScene>().unwrap(), &p).unwrap();
    let nf = m.n_free();
    let (mut q, mut v) = (vec![0.0; nf], vec![0.0; nf]);
    m.free_state(&mut q, &mut v);
    // a deformed, moving state (values do not change the work, but avoid trivial zeros)
    for (i, (qi, vi)) in q.iter_mut().zip(v.iter_mut()).enumerate() {
        let s = (i as f64 * 0.37).sin();
        *qi += 1e-3 * s;
        *vi = 0.1 * s;
    }
    let a: Vec<f64> = (0..nf).map(|i| (i as f64 * 0.11).cos()).collect();
    let mut ws = Workspace::new(&m, SolverKind::Auto).unwrap();
    let c = JacobianCoeffs {
        mass: 1.0,
        damping: 1e-3,
        stiffness: 1e-6,
    };
    let reps = (20_000 / n).max(5);
    let mut r = vec![0.0; nf];
    let mut jac = vec![0.0; m.pattern().nnz()];
    let t_asm = best(5, || {
        for _ in 0..reps {
            m.residual(0.0, &q, &v, &a, 1.0, &mut r, Some((c, &mut jac)))
                .unwrap();
        }
    }) / reps as f64;
    let pattern = m.pattern().clone();
    let t_lu = best(5, || {
        for _ in 0..reps {
            ws.solver.factor(&pattern, &jac).unwrap();
            ws.dx.copy_from_slice(&r);
            ws.solver.solve_in_place(&mut ws.dx);
        }
    }) / reps as f64;
    Cost {
        n,
        mass,
        assemble_us: 1e6 * t_asm / n as f64,
        factor_us: 1e6 * t_lu / n as f64,
    }
}

/// Time per call [µs] of the element kernels on a deformed, moving element.
fn kernels(mass: MassModel) -> [f64; 4] {
    let s = BeamSection {
        ea: 2e6,
        ga_y: 8e5,
        ga_z: 6e5,
        gj: 3e3,
        ei_y: 5e3,
        ei_z: 8e3,
        rho_a: 7.0,
        rho_jx: 0.03,
        rho_iy: 0.01,
        rho_iz: 0.02,
    };
    let el = Corot3d::new(0.7, Matrix3::identity(), &s, Theory::Timoshenko, mass);
    let n = Nodes {
        x: [Vector3::zeros(), Vector3::new(0.7, 0.01, 0.02)],
        r: [
            exp_so3(&Vector3::new(0.1, 0.2, 0.3)),
            exp_so3(&Vector3::new(0.12, 0.18, 0.33)),
        ],
    };
    let v = Rates {
        x: [Vector3::new(1.0, 2.0, 3.0); 2],
        w: [Vector3::new(0.1, 0.2, 0.3); 2],
    };
    let g = Vector3::zeros();
    let reps = 100_000;
    let (mut f, mut k, mut mc) = (Vec12::zeros(), Mat12::zeros(), Mat12::zeros());
    let time = |body: &mut dyn FnMut()| {
        1e6 * best(3, || {
            for _ in 0..reps {
                body();
            }
        }) / reps as f64
    };
    [
        time(&mut || {
            el.internal_force(black_box(&n), &mut f);
            black_box(&f);
        }),
        time(&mut || {
            el.internal_force_tangent(black_box(&n), &mut f, &mut k);
            black_box(&k);
        }),
        time(&mut || {
            el.inertia_force(black_box(&n), &v, &v, &g, &mut f, None);
            black_box(&f);
        }),
        time(&mut || {
            el.inertia_force(
                black_box(&n),
                &v,
                &v,
                &g,
                &mut f,
                Some((1.0, 0.1, &mut mc, &mut k)),
            );
            black_box(&k);
        }),
    ]
}

/// The right-angle cantilever, 30 s, elbow pulse sampled at mid-step; returns (tip z, elbow z)
/// at every communication point, the wall time [s] and the Newton iterations.
fn right_angle(n: usize, mass: i32, max_step: f64) -> (Vec<[f64; 2]>, f64, usize) {
    let sc = scene("right_angle_cantilever");
    let vars = VariableTable::from_scene(&sc);
    let mut p = ParamValues::defaults(&sc.params);
    p.set("mesh.n_elements", Value::Integer(n as i32));
    p.set("element.mass", Value::Integer(mass));
    p.set("solver.max_step", Value::Real(max_step));
    let role = |name: &str| vars.by_name(name).unwrap().role;
    let (Role::Input(fz), Role::Output(tip), Role::Output(elbow)) =
        (role("load.fz"), role("tip.z"), role("elbow.z"))
    else {
        panic!("scene variables")
    };
    let t0 = Instant::now();
    let model = build_model(&sc, &p).unwrap();
    let mut sim = Simulation::new(model, SolverConfig::from_params(&p), 0.0).unwrap();
    sim.initialize().unwrap();
    let h = 0.05;
    let mut out = vec![[0.0, 0.0]];
    for k in 0..600 {
        let t = (k as f64 + 0.5) * h;
        let f = if t < 1.0 {
            50.0 * t
        } else if t < 2.0 {
            50.0 * (2.0 - t)
        } else {
            0.0
        };
        sim.set_input(fz, f);
        sim.advance((k + 1) as f64 * h).unwrap();
        out.push([sim.output(tip), sim.output(elbow)]);
    }
    (
        out,
        t0.elapsed().as_secs_f64(),
        sim.stats().newton.iterations,
    )
}

/// Largest deviation over time and over tip/elbow, relative to the largest reference value.
fn error(a: &[[f64; 2]], r: &[[f64; 2]]) -> f64 {
    let amp = r
        .iter()
        .map(|x| x[0].abs().max(x[1].abs()))
        .fold(0.0, f64::max);
    a.iter()
        .zip(r)
        .map(|(x, y)| (x[0] - y[0]).abs().max((x[1] - y[1]).abs()))
        .fold(0.0, f64::max)
        / amp
}

fn main() {
    let dir = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("build/bench"));
    std::fs::create_dir_all(&dir).unwrap();

    println!(
        "Co-rotational 3D beam: cost per element per Newton iteration (cantilever3d, release, 1 thread)"
    );
    println!(
        "{:>6} {:>12} {:>22} {:>18} {:>12}",
        "n_el", "inertia", "force+tangent+asm [us]", "factor+solve [us]", "total [us]"
    );
    let mut f = std::fs::File::create(dir.join("corot_cost.csv")).unwrap();
    writeln!(
        f,
        "n_elements,mass,assemble_us_per_element,factor_solve_us_per_element"
    )
    .unwrap();
    for n in [16, 64, 256, 1024] {
        for mass in [1, 2] {
            let c = cost(n, mass);
            println!(
                "{:>6} {:>12} {:>22.3} {:>18.3} {:>12.3}",
                c.n,
                ["", "lumped", "consistent"][c.mass as usize],
                c.assemble_us,
                c.factor_us,
                c.assemble_us + c.factor_us
            );
            writeln!(f, "{},{},{},{}", c.n, c.mass, c.assemble_us, c.factor_us).unwrap();
        }
    }

    println!("\nOne element evaluation [us]:");
    println!(
        "{:>12} {:>15} {:>23} {:>15} {:>26}",
        "inertia",
        "internal force",
        "internal force+tangent",
        "inertia force",
        "inertia force+M, C, K"
    );
    for (mass, name) in [
        (MassModel::Lumped, "lumped"),
        (MassModel::Consistent, "consistent"),
    ] {
        let t = kernels(mass);
        println!(
            "{:>12} {:>15.3} {:>23.3} {:>15.3} {:>26.3}",
            name, t[0], t[1], t[2], t[3]
        );
    }

    println!(
        "\nRight-angle cantilever (Simo & Vu-Quoc 1988), 30 s, Newmark; error = max deviation of tip/elbow z over time / amplitude"
    );
    println!(
        "{:>12} {:>6} {:>9} {:>11} {:>9} {:>11} {:>13}",
        "inertia", "n_el", "dt [s]", "wall [s]", "Newton", "us/el/it", "error"
    );
    let mut f = std::fs::File::create(dir.join("corot_tradeoff.csv")).unwrap();
    writeln!(f, "study,mass,n_elements,dt,wall_s,newton_iterations,error").unwrap();
    let (space_ref, _, _) = right_angle(128, 2, 0.05);
    let line =
        |f: &mut std::fs::File, study: &str, mass: i32, n: usize, dt: f64, r: &[[f64; 2]]| {
            let (out, _, it) = right_angle(n, mass, dt);
            let wall = best(3, || {
                right_angle(n, mass, dt);
            });
            let err = error(&out, r);
            println!(
                "{:>12} {:>6} {:>9.5} {:>11.4} {:>9} {:>11.2} {:>13.3e}",
                ["", "lumped", "consistent"][mass as usize],
                n,
                dt,
                wall,
                it,
                1e6 * wall / (it * n) as f64,
                err
            );
            writeln!(f, "{study},{mass},{n},{dt},{wall},{it},{err}").unwrap();
        };
    for mass in [1, 2] {
        for n in [2, 4, 8, 16, 32, 64] {
            line(&mut f, "elements", mass, n, 0.05, &space_ref);
        }
    }
    let (time_ref, _, _) = right_angle(20, 1, 0.05 / 32.0);
    for dt in [0.05, 0.025, 0.0125, 0.00625] {
        line(&mut f, "step", 1, 20, dt, &time_ref);
    }
    println!("\nCSV: {}", dir.display());
}
