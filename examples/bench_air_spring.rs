//! Benchmark of the air spring (issue 11, item 10), on the library directly (no FMI layer),
//! release build, one thread. Prints markdown tables:
//!
//! 1. Level 2 (`scenes/air_spring_axisym.toml`, axisymmetric membrane) over meshes
//!    (`mesh.n_meridional` = 30, 60, 120, 240): a 2 Hz, ±10 mm sine of `top.z` about the
//!    design height for 1 s at 1 ms communication steps (`top.z` and `top.vz` set at the start
//!    of every step, as a co-simulation master does); wall time per simulated second, the
//!    real-time factor (best of three runs: the machine may be shared), Newton iterations and factorizations per step, the cost per element per
//!    Newton iteration (whole step: assembly, factorizations, solves, gas, condensation), and
//!    two errors of `top.fz`: the design state (5 bar at 0.25 m) against the shooting solution
//!    of `scripts/air_spring_reference.py` (`tests/data/air_spring_reference.toml`,
//!    `[design]`: F = 21533.04 N; the mesh error), and the largest deviation over the run
//!    from the quasi-static force of the same mesh at 19 instants (static solves of the closed
//!    spring at the plate's heights; the error of the time integration and of the Newton
//!    tolerance, the membrane's own inertia being below 1e-4 at 2 Hz), both relative to the
//!    design force.
//! 2. Where the time goes at 60 elements: one residual with and without the iteration matrix,
//!    one factorization and solve, one accepted step's bookkeeping.
//! 3. Level 3 (effective-area table, `scenes/air_spring_table.toml`) and level 1 (shell,
//!    `scenes/air_spring.toml`) over meshes (`mesh.n_circumferential` × `mesh.n_meridional`),
//!    the shell over the first 0.25 s of the sine only (one run per mesh: it is slow), with the
//!    design force error against the shooting solution.
//! 4. The same sine through the FMI instance (`flexfmu::instance::Instance`: what an importer
//!    pays per communication step, without the C ABI shims): fmi2SetReal of `top.z` and
//!    `top.vz`, fmi2DoStep, and fmi2GetReal of `top.fz` alone or of every output. The
//!    instance computes an output when it is read (`Instance::fresh`), so a master that reads
//!    only the force does not pay for the stiffness output (level 2: the static condensation).
//!
//! Run: `cargo run --release --example bench_air_spring [out-dir] [name=value ...]` (default
//! `build/bench`; `name=value` overrides a parameter of the scene, e.g. `solver.rho_inf=0.9`);
//! writes `air_spring.csv` (one row per level and mesh: wall time per simulated second and
//! the errors; `BENCH_SECTIONS=level2,breakdown,level3,level1,fmi` picks sections, default all);
//! `scripts/bench_air_spring.py` runs it and plots `docs/air_spring_pareto.png`.

mod bench_util;

use bench_util::{scene, time_it};
use flexfmu::fmi2::state_machine::Call;
use flexfmu::instance::Instance;
use flexfmu::linalg::{LinearSolver, SolverKind, rank_one_len};
use flexfmu::logging::Status;
use flexfmu::model::{JacobianCoeffs, build_model};
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use flexfmu::variables::{Role, Value, VarType, VariableTable};
use std::f64::consts::PI;
use std::hint::black_box;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Sine of `top.z`: amplitude [m] and frequency [Hz] about the design height [m].
const AMPLITUDE: f64 = 0.01;
const FREQUENCY: f64 = 2.0;
const DESIGN_HEIGHT: f64 = 0.25;
/// Communication step [s] and simulated time [s].
const STEP: f64 = 1e-3;
const DURATION: f64 = 1.0;

/// Parameter values of `sc` with overrides by variable name.
fn params(sc: &Scene, overrides: &[(&str, Value)]) -> ParamValues {
    let vars = VariableTable::from_scene(sc);
    let mut p = ParamValues::defaults(&sc.params);
    for (name, value) in overrides {
        match vars.by_name(name).map(|v| v.role) {
            Some(Role::Parameter(k)) => p.set(k, *value),
            other => panic!("{name}: {other:?}"),
        }
    }
    p
}

/// Index of the input or output `name` of `sc`.
fn index(sc: &Scene, name: &str) -> usize {
    match VariableTable::from_scene(sc).by_name(name).map(|v| v.role) {
        Some(Role::Input(k) | Role::Output(k)) => k,
        other => panic!("{name}: {other:?}"),
    }
}

/// The design force of the shooting solution [N] (`[design] F`).
fn reference_force() -> f64 {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/air_spring_reference.toml");
    let t: toml::Table = toml::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    t["design"]["F"].as_float().unwrap()
}

/// One sine run: the force history, wall time [s] of build + initialize and of the run, and
/// the simulation's counters.
struct Run {
    force: Vec<f64>,
    /// The failure of a communication step, if one failed (the run stops there).
    failed: Option<String>,
    design_force: f64,
    setup: f64,
    wall: f64,
    steps: usize,
    iterations: usize,
    factorizations: usize,
}

fn sine_run(sc: &Scene, overrides: &[(&str, Value)]) -> Run {
    sine_run_for(sc, overrides, DURATION)
}

/// [`sine_run`] over the first `duration` [s] of the sine.
fn sine_run_for(sc: &Scene, overrides: &[(&str, Value)], duration: f64) -> Run {
    let p = params(sc, overrides);
    let t0 = Instant::now();
    let model = build_model(sc, &p).unwrap();
    let mut sim = Simulation::new(model, SolverConfig::from_params(&p), 0.0).unwrap();
    sim.initialize().unwrap();
    let setup = t0.elapsed().as_secs_f64();
    let (iz, ivz, ofz) = (index(sc, "top.z"), index(sc, "top.vz"), index(sc, "top.fz"));
    let design_force = sim.output(ofz);
    let before = sim.stats();
    let n = (duration / STEP).round() as usize;
    let mut force = Vec::with_capacity(n);
    let w = 2.0 * PI * FREQUENCY;
    let mut failed = None;
    let t1 = Instant::now();
    for k in 0..n {
        let t = k as f64 * STEP;
        sim.set_input(iz, DESIGN_HEIGHT + AMPLITUDE * (w * t).sin());
        sim.set_input(ivz, AMPLITUDE * w * (w * t).cos());
        if let Err(e) = sim.advance(t + STEP) {
            failed = Some(format!("failed at t = {:.4} s: {}", e.reached, e.message));
            break;
        }
        force.push(sim.output(ofz));
    }
    let wall = t1.elapsed().as_secs_f64();
    let s = sim.stats();
    Run {
        force,
        failed,
        design_force,
        setup,
        wall,
        steps: s.steps - before.steps,
        iterations: s.newton.iterations - before.newton.iterations,
        factorizations: s.newton.factorizations - before.newton.factorizations,
    }
}

/// Height of the plate [m] at the end of communication step `k` (`top.z` and `top.vz` of the
/// sine set at its start, the plate moved with that velocity over the step).
fn plate_height(k: usize) -> f64 {
    let w = 2.0 * PI * FREQUENCY;
    let t = k as f64 * STEP;
    DESIGN_HEIGHT + AMPLITUDE * ((w * t).sin() + STEP * w * (w * t).cos())
}

/// Communication steps at which the run is compared with the quasi-static force: every 50 ms
/// from the second on (the first step starts the plate from rest at 0.126 m/s: the velocity
/// jump shakes the membrane, a transient the quasi-static force does not have).
fn samples() -> impl Iterator<Item = usize> {
    let n = (DURATION / STEP).round() as usize;
    (n / 20..n).step_by(n / 20)
}

/// The quasi-static force [N] of the closed spring (gas at rest, the same mesh) at the plate
/// heights of [`samples`]: the charged spring moved to the height before initialization and
/// the static solve of the initialization. The membrane is light (about 1 kg against a plate
/// acceleration of at most 1.6 m/s²) and its modes are above 100 Hz, so at 2 Hz the dynamic
/// force differs from this by about 1e-4 of the force at most.
fn quasi_static(sc: &Scene, overrides: &[(&str, Value)]) -> Vec<f64> {
    let p = params(sc, overrides);
    let (iz, ofz) = (index(sc, "top.z"), index(sc, "top.fz"));
    samples()
        .map(|k| {
            let mut model = build_model(sc, &p).unwrap();
            model.set_input(iz, plate_height(k));
            let mut sim = Simulation::new(model, SolverConfig::from_params(&p), 0.0).unwrap();
            sim.initialize().unwrap();
            sim.output(ofz)
        })
        .collect()
}

/// Largest `|run − static|` at the sample steps relative to the design force `scale`.
fn deviation(run: &[f64], stat: &[f64], scale: f64) -> f64 {
    samples()
        .zip(stat)
        .map(|(k, y)| (run[k] - y).abs())
        .fold(0.0, f64::max)
        / scale
}

/// A row of the Pareto table.
struct Row {
    level: u8,
    label: String,
    wall_per_s: f64,
    design_error: f64,
    run_error: f64,
}

/// `name=value` arguments as parameter overrides (a value with `.` or `e` is Real, `true` or
/// `false` Boolean, else Integer).
fn overrides(args: &[String]) -> Vec<(&'static str, Value)> {
    args.iter()
        .map(|a| {
            let (k, v) = a.split_once('=').expect("name=value");
            let value = match v {
                "true" | "false" => Value::Boolean(v == "true"),
                _ if v.contains(['.', 'e']) => Value::Real(v.parse().expect("a number")),
                _ => Value::Integer(v.parse().expect("an integer")),
            };
            (&*String::leak(k.to_string()), value)
        })
        .collect()
}

/// Meshes of the level-2 table: `BENCH_MESHES=30,60` (default 30, 60, 120, 240).
fn meshes() -> Vec<i32> {
    match std::env::var("BENCH_MESHES") {
        Ok(s) => s
            .split(',')
            .map(|x| x.trim().parse().expect("BENCH_MESHES: integers"))
            .collect(),
        Err(_) => vec![30, 60, 120, 240],
    }
}

/// Runs per timing, the best taken: `BENCH_RUNS` (default 3).
fn runs() -> usize {
    std::env::var("BENCH_RUNS").map_or(3, |s| s.parse().expect("BENCH_RUNS: an integer"))
}

/// `BENCH_FORCES=dir` writes each level-2 run's `top.fz` history to `dir/level2_<n>.txt` (level 1:
/// `dir/level1_<nc>x<nm>.txt`).
/// When `BENCH_SKIP_ERRORS` is set, the level-2 table skips the quasi-static reference solves
/// (the run error column shows NaN): for quick timings.
fn skip_errors() -> bool {
    std::env::var("BENCH_SKIP_ERRORS").is_ok()
}

fn level2(rows: &mut Vec<Row>, extra: &[(&'static str, Value)]) {
    let sc = scene("air_spring_axisym");
    let f_ref = reference_force();
    println!(
        "## Level 2 (axisymmetric membrane): {AMPLITUDE} m, {FREQUENCY} Hz sine of top.z for {DURATION} s, communication step {STEP} s\n"
    );
    println!(
        "| elements | setup [s] | wall per simulated s [s] | real-time factor | Newton it./step | factorizations/step | µs per element per Newton it. | design F error (shooting) | run error (quasi-static) |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for n in meshes() {
        let mut ov = vec![("mesh.n_meridional", Value::Integer(n))];
        ov.extend_from_slice(extra);
        // the machine is shared: the best of three runs
        let run = (0..runs())
            .map(|_| sine_run(&sc, &ov))
            .min_by(|a, b| a.wall.total_cmp(&b.wall))
            .unwrap();
        if let Some(msg) = run.failed.as_ref() {
            println!("| {n} | {:.3} | {msg} |||||||", run.setup);
            continue;
        }
        if let Ok(dir) = std::env::var("BENCH_FORCES") {
            // the top.fz history, one value per communication step, for comparing builds
            let path = Path::new(&dir).join(format!("level2_{n}.txt"));
            let text: String = run.force.iter().map(|f| format!("{f:.17e}\n")).collect();
            std::fs::write(&path, text).unwrap();
        }
        let steps = run.steps as f64;
        let per_s = run.wall / DURATION;
        let design_error = (run.design_force / f_ref - 1.0).abs();
        let run_error = if skip_errors() {
            f64::NAN
        } else {
            deviation(&run.force, &quasi_static(&sc, &ov), f_ref)
        };
        println!(
            "| {n} | {:.3} | {per_s:.4} | {:.1} | {:.2} | {:.2} | {:.3} | {design_error:.2e} | {run_error:.2e} |",
            run.setup,
            1.0 / per_s,
            run.iterations as f64 / steps,
            run.factorizations as f64 / steps,
            1e6 * run.wall / (run.iterations as f64 * n as f64),
        );
        rows.push(Row {
            level: 2,
            label: format!("{n} el."),
            wall_per_s: per_s,
            design_error,
            run_error,
        });
    }
    println!();
}

/// Level 3: the effective-area table from the membrane level with the gas law, the same sine.
fn level3(rows: &mut Vec<Row>) {
    let sc = scene("air_spring_table");
    let f_ref = reference_force();
    println!("## Level 3 (effective-area table, scenes/air_spring_table.toml), the same sine\n");
    println!(
        "| model | wall per simulated s [s] | real-time factor | µs per step | design F error (shooting) | run error (own quasi-static) |"
    );
    println!("|---|---:|---:|---:|---:|---:|");
    let run = (0..3)
        .map(|_| sine_run(&sc, &[]))
        .min_by(|a, b| a.wall.total_cmp(&b.wall))
        .unwrap();
    if let Some(msg) = run.failed.as_ref() {
        println!("| table | {msg} |||||\n");
        return;
    }
    let per_s = run.wall / DURATION;
    let design_error = (run.design_force / f_ref - 1.0).abs();
    let run_error = deviation(&run.force, &quasi_static(&sc, &[]), f_ref);
    println!(
        "| table | {per_s:.5} | {:.0} | {:.2} | {design_error:.2e} | {run_error:.2e} |\n",
        1.0 / per_s,
        1e6 * run.wall / run.steps as f64,
    );
    rows.push(Row {
        level: 3,
        label: "table".into(),
        wall_per_s: per_s,
        design_error,
        run_error,
    });
}

/// Level 1: the shell over meshes, the first quarter second of the same sine.
fn level1(rows: &mut Vec<Row>, extra: &[(&'static str, Value)]) {
    let sc = scene("air_spring");
    let f_ref = reference_force();
    // `BENCH_L1_DURATION=1.0` runs longer (default the first 0.25 s)
    let duration: f64 = std::env::var("BENCH_L1_DURATION")
        .map_or(0.25, |s| s.parse().expect("BENCH_L1_DURATION: seconds"));
    println!(
        "## Level 1 (shell, scenes/air_spring.toml): the same sine for its first {duration} s, one run per mesh\n"
    );
    println!(
        "| elements (around × along) | setup [s] | wall per simulated s [s] | real-time factor | Newton it./step | factorizations/step | µs per element per Newton it. | design F error (shooting) |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    // `BENCH_L1_MESHES=24x40,32x60` picks meshes (default the four below)
    let meshes: Vec<(i32, i32)> = match std::env::var("BENCH_L1_MESHES") {
        Ok(s) => s
            .split(',')
            .map(|m| {
                let (a, b) = m
                    .trim()
                    .split_once('x')
                    .expect("BENCH_L1_MESHES: NCxNM,...");
                (a.parse().unwrap(), b.parse().unwrap())
            })
            .collect(),
        Err(_) => vec![(12, 30), (16, 40), (24, 40), (32, 60)],
    };
    for (nc, nm) in meshes {
        let mut ov = vec![
            ("mesh.n_circumferential", Value::Integer(nc)),
            ("mesh.n_meridional", Value::Integer(nm)),
        ];
        ov.extend_from_slice(extra);
        let run = sine_run_for(&sc, &ov, duration);
        if let Some(msg) = run.failed.as_ref() {
            println!("| {nc} × {nm} | {:.3} | {msg} ||||||", run.setup);
            continue;
        }
        if let Ok(dir) = std::env::var("BENCH_FORCES") {
            // the top.fz history, one value per communication step, for comparing settings
            let path = Path::new(&dir).join(format!("level1_{nc}x{nm}.txt"));
            let text: String = run.force.iter().map(|f| format!("{f:.17e}\n")).collect();
            std::fs::write(&path, text).unwrap();
        }
        let steps = run.steps as f64;
        let per_s = run.wall / duration;
        let design_error = (run.design_force / f_ref - 1.0).abs();
        let n_el = (nc * nm) as f64;
        println!(
            "| {nc} × {nm} | {:.2} | {per_s:.3} | {:.4} | {:.2} | {:.2} | {:.3} | {design_error:.2e} |",
            run.setup,
            1.0 / per_s,
            run.iterations as f64 / steps,
            run.factorizations as f64 / steps,
            1e6 * run.wall / (run.iterations as f64 * n_el),
        );
        rows.push(Row {
            level: 1,
            label: format!("{nc}x{nm} el."),
            wall_per_s: per_s,
            design_error,
            run_error: f64::NAN,
        });
    }
    println!();
}

/// Where the time of a step goes at 60 elements.
fn breakdown() {
    let sc = scene("air_spring_axisym");
    let n_el = 60;
    let p = params(&sc, &[("mesh.n_meridional", Value::Integer(n_el))]);
    let mut m = build_model(&sc, &p).unwrap();
    let nf = m.n_free();
    let (mut q, mut v) = (vec![0.0; nf], vec![0.0; nf]);
    m.free_state(&mut q, &mut v);
    let a = vec![0.0; nf];
    let c = JacobianCoeffs {
        mass: 1.0,
        damping: 0.5e-3,
        stiffness: 0.25e-6,
    };
    let mut r = vec![0.0; nf];
    let mut jac = vec![0.0; rank_one_len(m.pattern())];
    // a residual at the end of a 1 ms step (the gas's own step inside)
    let t = 1e-3;
    let full = time_it(0.1, || {
        m.residual(t, black_box(&q), &v, &a, 1.0, &mut r, Some((c, &mut jac)))
            .unwrap();
    });
    let res = time_it(0.1, || {
        m.residual(t, black_box(&q), &v, &a, 1.0, &mut r, None)
            .unwrap();
    });
    let pattern = m.pattern().clone();
    let mut solver = LinearSolver::new(&pattern, SolverKind::Auto).unwrap();
    let factor = time_it(0.1, || solver.factor(&pattern, black_box(&jac)).unwrap());
    let mut x = r.clone();
    let solve = time_it(0.1, || {
        x.copy_from_slice(&r);
        solver.solve_in_place(black_box(&mut x));
    });
    let mut state = flexfmu::integrators::DynState::zeros(nf, 0.0);
    m.free_state(&mut state.q, &mut state.v);
    let accept = time_it(0.1, || {
        state.t += 1e-9;
        m.accept(black_box(&mut state));
    });
    println!("## Cost of the pieces of a step, {n_el} elements ({nf} free coordinates)\n");
    println!("| piece | µs per call | µs per element |");
    println!("|---|---:|---:|");
    for (name, s) in [
        ("residual + iteration matrix", full),
        ("residual alone", res),
        ("factorization (with the rank-one gas part)", factor),
        ("solve", solve),
        ("accept (gas commit, reaction, energies, outputs)", accept),
    ] {
        println!("| {name} | {:.2} | {:.3} |", 1e6 * s, 1e6 * s / n_el as f64);
    }
    println!();
}

/// Wall time [s] per communication step of the sine through an FMI instance of scene `name`
/// (parameters at their defaults except `overrides`), reading `top.fz` alone or every output:
/// best of three runs.
fn fmi_step_time(name: &str, overrides: &[(&str, Value)], all_outputs: bool) -> f64 {
    let run = || {
        let mut inst = Instance::from_scene("bench", scene(name), false, Box::new(|_, _, _| {}));
        let vr = |inst: &Instance, n: &str| inst.variables().by_name(n).unwrap().vr;
        let (z, vz, fz) = (vr(&inst, "top.z"), vr(&inst, "top.vz"), vr(&inst, "top.fz"));
        let outputs: Vec<u32> = inst
            .variables()
            .vars()
            .iter()
            .filter(|v| matches!(v.role, Role::Output(_)))
            .map(|v| v.vr)
            .collect();
        let read: Vec<u32> = if all_outputs { outputs } else { vec![fz] };
        for (n, v) in overrides {
            let r = vr(&inst, n);
            assert_eq!(inst.set(Call::SetInteger, &[r], &[*v]), Status::Ok, "{n}");
        }
        assert_eq!(inst.setup_experiment(None, 0.0, None), Status::Ok);
        assert_eq!(inst.enter_initialization_mode(), Status::Ok);
        assert_eq!(inst.exit_initialization_mode(), Status::Ok);
        let w = 2.0 * PI * FREQUENCY;
        let n = (DURATION / STEP).round() as usize;
        let mut sum = 0.0;
        let t0 = Instant::now();
        for k in 0..n {
            let t = k as f64 * STEP;
            let u = [
                Value::Real(DESIGN_HEIGHT + AMPLITUDE * (w * t).sin()),
                Value::Real(AMPLITUDE * w * (w * t).cos()),
            ];
            assert_eq!(inst.set(Call::SetReal, &[z, vz], &u), Status::Ok);
            assert_eq!(inst.do_step(t, STEP), Status::Ok, "fmi2DoStep at t = {t}");
            let status = inst.get(Call::GetReal, VarType::Real, &read, &mut |_, v| {
                if let Value::Real(x) = v {
                    sum += x;
                }
            });
            assert_eq!(status, Status::Ok);
        }
        black_box(sum);
        t0.elapsed().as_secs_f64() / n as f64
    };
    (0..runs()).map(|_| run()).fold(f64::INFINITY, f64::min)
}

/// The sine through the FMI instance: level 2 at 60 elements and level 3.
fn fmi_rows() {
    println!("## Through the FMI instance (fmi2SetReal, fmi2DoStep, fmi2GetReal), the same sine\n");
    println!("| model | outputs read | µs per communication step | real-time factor |");
    println!("|---|---|---:|---:|");
    let mut cases = vec![(
        "level 2, 60 elements",
        "air_spring_axisym",
        vec![("mesh.n_meridional", Value::Integer(60))],
    )];
    if Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/air_spring_table.toml")
        .exists()
    {
        cases.push(("level 3 (table)", "air_spring_table", vec![]));
    }
    // `BENCH_FMI_LEVEL1=0` leaves the shell out (its runs take minutes)
    if std::env::var("BENCH_FMI_LEVEL1").map_or(true, |v| v != "0") {
        cases.push((
            "level 1, the shipped scene (24 × 40 elements)",
            "air_spring",
            vec![],
        ));
    }
    // `BENCH_FMI_ALL=0` reads `top.fz` only (for profiles of the step itself)
    let alls: &[bool] = if std::env::var("BENCH_FMI_ALL").is_ok_and(|v| v == "0") {
        &[false]
    } else {
        &[false, true]
    };
    for (label, name, ov) in &cases {
        for &all in alls {
            let t = fmi_step_time(name, ov, all);
            // three significant digits: level 1 runs below real time
            let rt = STEP / t;
            let digits = if rt >= 100.0 {
                0
            } else {
                (2 - rt.log10().floor() as i32).clamp(0, 5) as usize
            };
            println!(
                "| {label} | {} | {:.2} | {rt:.digits$} |",
                if all { "all" } else { "top.fz" },
                1e6 * t,
            );
        }
    }
    println!();
}

fn write_csv(dir: &Path, rows: &[Row]) {
    std::fs::create_dir_all(dir).unwrap();
    let path = dir.join("air_spring.csv");
    let mut f = std::fs::File::create(&path).unwrap();
    writeln!(f, "level,label,wall_per_s,design_error,run_error").unwrap();
    for r in rows {
        writeln!(
            f,
            "{},{},{:.6e},{:.6e},{:.6e}",
            r.level, r.label, r.wall_per_s, r.design_error, r.run_error
        )
        .unwrap();
    }
    println!("wrote {}", path.display());
}

fn main() {
    let out: PathBuf = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("build/bench"));
    let args: Vec<String> = std::env::args().skip(2).collect();
    let extra = overrides(&args);
    if !extra.is_empty() {
        println!("parameter overrides: {args:?}\n");
    }
    // `BENCH_SECTIONS=level2,fmi` runs only those sections (default: all)
    let sections = std::env::var("BENCH_SECTIONS").unwrap_or_default();
    let run = |s: &str| sections.is_empty() || sections.split(',').any(|x| x == s);
    let mut rows = vec![];
    if run("level2") {
        level2(&mut rows, &extra);
    }
    if run("breakdown") {
        breakdown();
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    if run("level3") && root.join("air_spring_table.toml").exists() {
        level3(&mut rows);
    }
    if run("level1") {
        level1(&mut rows, &extra);
    }
    if run("fmi") {
        fmi_rows();
    }
    write_csv(&out, &rows);
}
