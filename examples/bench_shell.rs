//! Benchmark of the seed-004 trapezoidal shell (issue 10, item 5), on the library directly (no
//! FMI layer), release build, one thread. Prints markdown tables:
//!
//! 1. Cost per element per Newton iteration of the whole `Shell` model (internal force,
//!    tangent, inertia and loads, scattered into the fixed sparse pattern:
//!    `MechanicalSystem::residual` with its iteration matrix) on plate meshes 4 × 4 … 64 × 64
//!    for V2, V1 and V2 with the geometric stiffness (target: at most 10 µs), the factorization
//!    and solve, and one element's kernels alone.
//! 2. The closed cylinder (`scenes/cylinder.toml`) against the number of rings
//!    (`mesh.n_meridional` 8 … 128, `n_circumferential` 16): a whole static solve under
//!    pressure and a dynamic step; the slope (time per ring), how linear the growth is, and the
//!    linear solver that `solver.linear_solver = auto` picks.
//! 3. Error against wall time on the strip's free vibration (`scenes/strip.toml`) over meshes,
//!    integrators and step sizes against a fine reference run; Pareto table.
//! 4. The strip as a shell against the same strip as a co-rotational 3D beam (`beam_3d`):
//!    accuracy of the end-shear tip (elastica, k = PL²/EI = 4) and of the roll-up, and cost per
//!    static solve and per dynamic step: what the shell costs.
//!
//! Run: `cargo run --release --example bench_shell [out-dir]` (default `build/bench`); writes
//! `shell_cost.csv`, `shell_cylinder.csv` and `shell_pareto.csv`; `scripts/bench_shell.py` runs
//! it and plots `docs/shell_pareto.png`.

mod bench_util;
#[allow(dead_code)]
#[path = "../tests/common/shell_reference.rs"]
mod shell_reference;

use bench_util::{best, scene, time_it};
use flexfmu::elements::Element;
use flexfmu::elements::element::{ElementState, Frame};
use flexfmu::elements::rotation::exp_so3;
use flexfmu::elements::trapezoid_shell::{
    Bending, Mat24, ShellMaterial, ShellOptions, TrapezoidShell, Vec24,
};
use flexfmu::kinds::shell::ShellScene;
use flexfmu::kinds::shell::model::Shell;
use flexfmu::linalg::{Backend, LinearSolver, SolverKind};
use flexfmu::model::{JacobianCoeffs, MechanicalSystem, Model, build_model};
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use flexfmu::variables::{Role, Value, VariableTable};
use nalgebra::{Matrix3, Vector3};
use std::hint::black_box;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Strip data (`scenes/strip.toml`): length, width, thickness [m], E [Pa], ρ [kg/m3].
const STRIP: (f64, f64, f64, f64, f64) = (10.0, 1.0, 0.1, 1.2e6, 1.0);

/// Parameter values and input values of `sc` with overrides by variable name.
fn setup(sc: &Scene, overrides: &[(&str, Value)]) -> (ParamValues, Vec<(usize, f64)>) {
    let vars = VariableTable::from_scene(sc);
    let mut p = ParamValues::defaults(&sc.params);
    let mut inputs = vec![];
    for (name, value) in overrides {
        match (vars.by_name(name).map(|v| v.role), value) {
            (Some(Role::Parameter(k)), _) => p.set(k, *value),
            (Some(Role::Input(k)), Value::Real(x)) => inputs.push((k, *x)),
            other => panic!("{name}: {other:?}"),
        }
    }
    (p, inputs)
}

/// A simulation of `sc` before `initialize`, with overrides by variable name.
fn simulation(sc: &Scene, overrides: &[(&str, Value)]) -> Simulation {
    let (p, inputs) = setup(sc, overrides);
    let mut model = build_model(sc, &p).unwrap();
    for (k, x) in inputs {
        model.set_input(k, x);
    }
    Simulation::new(model, SolverConfig::from_params(&p), 0.0).unwrap()
}

/// Index of the input or output `name` of `sc`.
fn index(sc: &Scene, name: &str) -> usize {
    match VariableTable::from_scene(sc).by_name(name).map(|v| v.role) {
        Some(Role::Input(k) | Role::Output(k)) => k,
        other => panic!("{name}: {other:?}"),
    }
}

/// The backend `solver.linear_solver = auto` picks for a pattern.
fn solver_name(s: &LinearSolver) -> &'static str {
    match s.backend() {
        Backend::Banded(_) => "banded LU",
        Backend::Sparse(_) => "sparse LU (faer, fill-reducing)",
        Backend::Bordered(_) => "bordered banded (Cuthill-McKee)",
    }
}

// ---------------------------------------------------------------------------------------------
// 1. Cost per element per Newton iteration
// ---------------------------------------------------------------------------------------------

/// Cost of one plate configuration [µs per element]: residual + iteration matrix, residual
/// alone, factor + solve (auto) and, when asked, factor + solve with sparse LU; the auto
/// backend's name.
struct Cost {
    n: i32,
    variant: &'static str,
    asm: f64,
    force: f64,
    factor: Option<(f64, f64, &'static str)>,
}

fn plate_cost(n: i32, bending: i32, geometric: bool, factor: bool) -> Cost {
    let sc = scene("plate");
    let (p, _) = setup(
        &sc,
        &[
            ("mesh.n_x", Value::Integer(n)),
            ("mesh.n_y", Value::Integer(n)),
            ("element.bending", Value::Integer(bending)),
            ("element.geometric_stiffness", Value::Boolean(geometric)),
        ],
    );
    let mut m = Shell::build(sc.tables::<ShellScene>().unwrap(), &p).unwrap();
    let n_el = m.n_elements() as f64;
    let nf = m.n_free();
    let (mut q, mut v) = (vec![0.0; nf], vec![0.0; nf]);
    m.free_state(&mut q, &mut v);
    // a deformed, moving state (the work does not depend on the values)
    for (i, (qi, vi)) in q.iter_mut().zip(v.iter_mut()).enumerate() {
        let s = (i as f64 * 0.37).sin();
        *qi += 1e-4 * s;
        *vi = 0.1 * s;
    }
    let a: Vec<f64> = (0..nf).map(|i| (i as f64 * 0.11).cos()).collect();
    let c = JacobianCoeffs {
        mass: 1.0,
        damping: 1e-3,
        stiffness: 1e-6,
    };
    let mut r = vec![0.0; nf];
    let mut jac = vec![0.0; m.pattern().nnz()];
    // best of three means: the machine is shared
    let asm = (0..3)
        .map(|_| {
            time_it(0.07, || {
                m.residual(0.0, black_box(&q), &v, &a, 1.0, &mut r, Some((c, &mut jac)))
                    .unwrap();
            })
        })
        .fold(f64::INFINITY, f64::min);
    let force = (0..3)
        .map(|_| {
            time_it(0.03, || {
                m.residual(0.0, black_box(&q), &v, &a, 1.0, &mut r, None)
                    .unwrap();
            })
        })
        .fold(f64::INFINITY, f64::min);
    let factor = factor.then(|| {
        let pattern = m.pattern().clone();
        let run = |kind| {
            let mut s = LinearSolver::new(&pattern, kind).unwrap();
            let name = solver_name(&s);
            let mut x = r.clone();
            let t = best(if n_el > 1000.0 { 1 } else { 3 }, || {
                s.factor(&pattern, &jac).unwrap();
                x.copy_from_slice(&r);
                s.solve_in_place(&mut x);
            });
            (t, name)
        };
        let (auto, name) = run(SolverKind::Auto);
        let (sparse, _) = run(SolverKind::SparseLu);
        (1e6 * auto / n_el, 1e6 * sparse / n_el, name)
    });
    Cost {
        n,
        variant: match (bending, geometric) {
            (1, _) => "V1",
            (_, false) => "V2",
            (_, true) => "V2 + geometric",
        },
        asm: 1e6 * asm / n_el,
        force: 1e6 * force / n_el,
        factor,
    }
}

/// One element's force and force + tangent [µs per call] on a deformed trapezoid.
fn kernel(bending: Bending, geometric_stiffness: bool) -> [f64; 2] {
    let mat = ShellMaterial {
        e: 2.1e11,
        nu: 0.3,
        rho: 7850.0,
        thickness: 0.01,
    };
    let x0 = [(0.0, 0.0), (0.5, 0.0), (0.4, 0.3), (0.1, 0.3)].map(|(x, y)| Vector3::new(x, y, 0.0));
    let opt = ShellOptions {
        bending,
        geometric_stiffness,
        membrane: true,
        ..ShellOptions::default()
    };
    let el = TrapezoidShell::new(x0, &mat, &opt).unwrap();
    let q0 = exp_so3(&Vector3::new(0.3, -0.2, 0.5));
    let mut q = Vec24::zeros();
    for (i, x) in x0.iter().enumerate() {
        q.fixed_rows_mut::<3>(6 * i)
            .copy_from(&(q0 * x + Vector3::new(0.001 * i as f64, 0.0, 0.002)));
    }
    let frames: Vec<Frame> = (0..4)
        .map(|i| Frame {
            rot: q0 * exp_so3(&Vector3::new(0.01 * i as f64, 0.02, 0.0)),
            tangent: Matrix3::identity(),
        })
        .collect();
    let s = ElementState {
        q,
        v: Vec24::zeros(),
        frames: &frames,
    };
    let (mut f, mut k) = (Vec24::zeros(), Mat24::zeros());
    let tf = time_it(0.1, || {
        el.force_into(black_box(&s), &mut f);
        black_box(&f);
    });
    let tk = time_it(0.1, || {
        el.tangent_into(black_box(&s), &mut f, &mut k, None);
        black_box(&k);
    });
    [1e6 * tf, 1e6 * tk]
}

fn cost_section(dir: &Path) {
    println!(
        "## 1. Cost per element per Newton iteration (plate, release, 1 thread)\n\n\
         force + tangent + assembly = `Shell::residual` with the iteration matrix (internal force and tangent, \
         inertia, loads, scatter into the sparse pattern); force only = the residual alone; factor + solve \
         = one LU of the iteration matrix and one solve, per element (auto backend, and faer sparse LU). \
         Target: force + tangent + assembly <= 10 us.\n"
    );
    println!(
        "| mesh | elements | variant | force + tangent + asm [us] | force only [us] | factor + solve, auto [us] | auto backend | factor + solve, sparse LU [us] |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let mut f = std::fs::File::create(dir.join("shell_cost.csv")).unwrap();
    writeln!(
        f,
        "n,elements,variant,assemble_us_per_element,force_us_per_element,factor_auto_us_per_element,factor_sparse_us_per_element"
    )
    .unwrap();
    for n in [4, 8, 16, 32, 64] {
        for (bending, geo) in [(2, false), (1, false), (2, true)] {
            let c = plate_cost(n, bending, geo, bending == 2 && !geo);
            let (fa, fs, name) = match c.factor {
                Some((a, s, name)) => (format!("{a:.2}"), format!("{s:.2}"), name),
                None => (String::new(), String::new(), ""),
            };
            println!(
                "| {0}x{0} | {1} | {2} | {3:.2} | {4:.2} | {fa} | {name} | {fs} |",
                c.n,
                c.n * c.n,
                c.variant,
                c.asm,
                c.force
            );
            writeln!(
                f,
                "{},{},{},{},{},{fa},{fs}",
                c.n,
                c.n * c.n,
                c.variant,
                c.asm,
                c.force
            )
            .unwrap();
        }
    }
    println!("\nOne element alone (deformed trapezoid, 24 coordinates):\n");
    println!("| variant | force [us] | force + tangent [us] |");
    println!("|---|---|---|");
    for (name, bending, geo) in [
        ("V2", Bending::V2, false),
        ("V1", Bending::V1, false),
        ("V2 + geometric", Bending::V2, true),
    ] {
        let [tf, tk] = kernel(bending, geo);
        println!("| {name} | {tf:.2} | {tk:.2} |");
    }
}

// ---------------------------------------------------------------------------------------------
// 2. Closed cylinder against the number of rings
// ---------------------------------------------------------------------------------------------

/// Rings, static solve [s], dynamic step [s], dynamic step per Newton iteration [s].
type RingTiming = (f64, f64, f64, f64);

fn cylinder_section(dir: &Path) {
    // the mid-wall ring probe is not on a ring of every mesh: probe the first ring instead
    let text = scene("cylinder")
        .text
        .replace("ring = 0.35", "ring = \"first\"");
    assert!(
        text.contains("ring = \"first\""),
        "scenes/cylinder.toml changed"
    );
    let sc = Scene::from_toml(&text).unwrap();
    let n_c = 16;
    let pressure = 1e5;
    let steps = 5;
    println!(
        "\n## 2. Closed cylinder (`scenes/cylinder.toml`), n_circumferential = {n_c}, against the rings\n\n\
         static = whole static solve under load.pressure = {pressure:.0e} Pa (`initialize`: load steps, Newton, \
         initial accelerations); step = one dynamic step of 1 ms (generalized-alpha, modified Newton) after it, \
         mean of {steps}.\n"
    );
    println!(
        "| rings | elements | coordinates | backend (auto) | static [ms] | static / ring [ms] | step [ms] | step / ring [ms] | Newton it./step |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    let mut f = std::fs::File::create(dir.join("shell_cylinder.csv")).unwrap();
    writeln!(
        f,
        "rings,elements,coordinates,static_s,step_s,newton_per_step"
    )
    .unwrap();
    let mut pts = vec![];
    for rings in [8, 16, 32, 64, 128] {
        let o = [
            ("mesh.n_circumferential", Value::Integer(n_c)),
            ("mesh.n_meridional", Value::Integer(rings)),
            ("load.pressure", Value::Real(pressure)),
        ];
        let probe = simulation(&sc, &o);
        let shell = probe.model_as::<Shell>().unwrap();
        let (n_el, nf) = (shell.n_elements(), shell.n_free());
        let backend = solver_name(&LinearSolver::new(shell.pattern(), SolverKind::Auto).unwrap());
        drop(probe);
        let mut t_static = f64::INFINITY;
        let mut t_step = f64::INFINITY;
        let mut its = 0.0;
        for _ in 0..2 {
            let mut sim = simulation(&sc, &o);
            let t = Instant::now();
            sim.initialize().unwrap();
            t_static = t_static.min(t.elapsed().as_secs_f64());
            let before = sim.stats().newton.iterations;
            let t = Instant::now();
            for k in 0..steps {
                sim.advance((k + 1) as f64 * 1e-3).unwrap();
            }
            t_step = t_step.min(t.elapsed().as_secs_f64() / steps as f64);
            its = (sim.stats().newton.iterations - before) as f64 / steps as f64;
        }
        let r = rings as f64;
        println!(
            "| {rings} | {n_el} | {nf} | {backend} | {:.1} | {:.3} | {:.2} | {:.4} | {its:.1} |",
            1e3 * t_static,
            1e3 * t_static / r,
            1e3 * t_step,
            1e3 * t_step / r
        );
        writeln!(f, "{rings},{n_el},{nf},{t_static},{t_step},{its}").unwrap();
        pts.push((r, t_static, t_step, t_step / its));
    }
    // least-squares line t = a + b·rings, and the growth exponent between the last two meshes
    let fit = |y: &dyn Fn(&RingTiming) -> f64| {
        let n = pts.len() as f64;
        let (sx, sy) = pts
            .iter()
            .fold((0.0, 0.0), |(sx, sy), p| (sx + p.0, sy + y(p)));
        let (mx, my) = (sx / n, sy / n);
        let (sxy, sxx) = pts.iter().fold((0.0, 0.0), |(a, b), p| {
            (a + (p.0 - mx) * (y(p) - my), b + (p.0 - mx).powi(2))
        });
        let b = sxy / sxx;
        let a = my - b * mx;
        let ss_res: f64 = pts.iter().map(|p| (y(p) - a - b * p.0).powi(2)).sum();
        let ss_tot: f64 = pts.iter().map(|p| (y(p) - my).powi(2)).sum();
        let k = pts.len() - 1;
        let exponent = (y(&pts[k]) / y(&pts[k - 1])).ln() / (pts[k].0 / pts[k - 1].0).ln();
        (b, 1.0 - ss_res / ss_tot, exponent)
    };
    println!(
        "\n| quantity | slope [ms per ring] | R^2 of the straight line | exponent 64 -> 128 rings |"
    );
    println!("|---|---|---|---|");
    for (name, y) in [
        (
            "static solve",
            &(|p: &RingTiming| p.1) as &dyn Fn(&_) -> f64,
        ),
        ("dynamic step", &|p: &RingTiming| p.2),
        ("dynamic step per Newton iteration", &|p: &(
            f64,
            f64,
            f64,
            f64,
        )| p.3),
    ] {
        let (b, r2, e) = fit(y);
        println!("| {name} | {:.3} | {r2:.4} | {e:.2} |", 1e3 * b);
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Error against wall time: free vibration of the strip
// ---------------------------------------------------------------------------------------------

/// Free vibration of the strip released from the static deflection under load.fz = 0.2 N:
/// tip.z at every 0.1 s over `T` s, wall time [s] of the run (static solve included).
const VIB_T: f64 = 6.0;
const VIB_H: f64 = 0.1;

fn vibration(n_x: i32, integrator: i32, dt: f64) -> (Vec<f64>, f64) {
    let sc = scene("strip");
    let t0 = Instant::now();
    let mut sim = simulation(
        &sc,
        &[
            ("mesh.n_x", Value::Integer(n_x)),
            ("mesh.n_y", Value::Integer(2)),
            ("load.fz", Value::Real(0.2)),
            ("solver.integrator", Value::Integer(integrator)),
            ("solver.max_step", Value::Real(dt)),
        ],
    );
    sim.initialize().unwrap();
    let (fz, tip) = (index(&sc, "load.fz"), index(&sc, "tip.z"));
    sim.set_input(fz, 0.0);
    let n = (VIB_T / VIB_H).round() as usize;
    let mut z = Vec::with_capacity(n);
    for k in 0..n {
        sim.advance((k + 1) as f64 * VIB_H).unwrap();
        z.push(sim.output(tip));
    }
    (z, t0.elapsed().as_secs_f64())
}

const INTEGRATORS: [(i32, &str); 3] = [(1, "generalized-alpha"), (2, "Newmark"), (3, "midpoint")];

fn pareto_section(dir: &Path) {
    let (n_ref, dt_ref, int_ref) = (40, 0.003125, 3);
    println!(
        "\n## 3. Error against wall time: free vibration of the strip (`scenes/strip.toml`)\n\n\
         Released from the static deflection under load.fz = 0.2 N (tip ~ L/15), {VIB_T} s (about one period \
         of the first mode); error = largest |tip.z - reference| at the {VIB_H} s communication points / \
         largest |tip.z| of the reference (n_x = {n_ref}, n_y = 2, midpoint, dt = {dt_ref} s); wall time per \
         simulated second (static solve included). * = Pareto-optimal (no run both faster and more accurate).\n"
    );
    let (z_ref, _) = vibration(n_ref, int_ref, dt_ref);
    let amp = z_ref.iter().fold(0.0_f64, |m, z| m.max(z.abs()));
    let mut rows = vec![];
    for (code, name) in INTEGRATORS {
        for n_x in [5, 10, 20] {
            for dt in [0.1, 0.05, 0.025, 0.0125] {
                let (z, w1) = vibration(n_x, code, dt);
                let wall = w1.min(vibration(n_x, code, dt).1) / VIB_T;
                let err = z
                    .iter()
                    .zip(&z_ref)
                    .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
                    / amp;
                rows.push((name, code, n_x, dt, wall, err));
            }
        }
    }
    let optimal: Vec<bool> = rows
        .iter()
        .map(|r| {
            !rows
                .iter()
                .any(|o| o.4 <= r.4 && o.5 <= r.5 && (o.4 < r.4 || o.5 < r.5))
        })
        .collect();
    let fastest = rows.iter().map(|r| r.4).fold(f64::INFINITY, f64::min);
    println!(
        "| integrator | n_x | dt [s] | wall per simulated s [ms] | wall / fastest | error | Pareto |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut f = std::fs::File::create(dir.join("shell_pareto.csv")).unwrap();
    writeln!(
        f,
        "integrator,code,n_x,dt,wall_per_simulated_s,error,pareto"
    )
    .unwrap();
    for (r, opt) in rows.iter().zip(&optimal) {
        println!(
            "| {} | {} | {} | {:.2} | {:.1} | {:.2e} | {} |",
            r.0,
            r.2,
            r.3,
            1e3 * r.4,
            r.4 / fastest,
            r.5,
            if *opt { "*" } else { "" }
        );
        writeln!(
            f,
            "{},{},{},{},{},{},{}",
            r.0, r.1, r.2, r.3, r.4, r.5, *opt as i32
        )
        .unwrap();
    }
}

// ---------------------------------------------------------------------------------------------
// 4. The strip as a shell against the strip as a 3D beam
// ---------------------------------------------------------------------------------------------

/// The strip of `scenes/strip.toml` as a co-rotational 3D beam (Timoshenko, lumped mass):
/// ν = 0, G = E/2, shear coefficient 5/6, St-Venant torsion of a thin rectangle
/// J = b h³/3 (1 − 0.63 h/b), rotary inertia ρ I.
fn beam_strip(n: i32) -> Scene {
    let (l, b, h, e, rho) = STRIP;
    let g = 0.5 * e;
    let (area, iy, iz) = (b * h, b * h.powi(3) / 12.0, h * b.powi(3) / 12.0);
    let j = b * h.powi(3) / 3.0 * (1.0 - 0.63 * h / b);
    let text = format!(
        r#"[fmu]
model_name = "strip_beam"
description = "The shell strip as a co-rotational 3D beam"

[experiment]
start_time = 0.0
stop_time = 1.0
step_size = 1e-2

[element]
type = "corotational_3d"
theory = 2
mass = 1

[mesh]
n_elements = {n}

[section]
EA = {ea}
GAy = {ga}
GAz = {ga}
GJ = {gj}
EIy = {eiy}
EIz = {eiz}
rhoA = {rhoa}
rhoJx = {rhojx}
rhoIy = {rhoiy}
rhoIz = {rhoiz}

[centreline]
start = [0.0, 0.0, 0.0]

[[centreline.segments]]
direction = [1.0, 0.0, 0.0]
length = {l}

[solver]
static_equilibrium = true
integrator = "generalized_alpha"
max_step = 1e-2
load_steps = 8

[[supports]]
kind = "clamp"
at = 0.0

[[loads]]
name = "load"
at = 1.0

[[probes]]
name = "tip"
at = 1.0
outputs = ["x", "y", "z"]
"#,
        ea = e * area,
        ga = 5.0 / 6.0 * g * area,
        gj = g * j,
        eiy = e * iy,
        eiz = e * iz,
        rhoa = rho * area,
        rhojx = rho * (iy + iz),
        rhoiy = rho * iy,
        rhoiz = rho * iz,
    );
    Scene::from_toml(&text).unwrap()
}

/// Static tip (x, z) [m] of a strip model under `load`, the wall time of the solve [s] and
/// its Newton iterations.
fn strip_static(sc: &Scene, mesh: (&str, i32), load: (&str, f64), steps: i32) -> ([f64; 2], f64) {
    let o = [
        (mesh.0, Value::Integer(mesh.1)),
        (load.0, Value::Real(load.1)),
        ("solver.load_steps", Value::Integer(steps)),
    ];
    let mut tip = [0.0; 2];
    let wall = best(2, || {
        let mut sim = simulation(sc, &o);
        sim.initialize().unwrap();
        tip = [
            sim.output(index(sc, "tip.x")),
            sim.output(index(sc, "tip.z")),
        ];
    });
    (tip, wall)
}

/// Mean wall time of a dynamic step of 0.01 s [s] of the strip's free vibration (released
/// from load.fz = 0.2 N), and Newton iterations per step.
fn strip_step(sc: &Scene, mesh: (&str, i32)) -> (f64, f64) {
    let mut sim = simulation(
        sc,
        &[
            (mesh.0, Value::Integer(mesh.1)),
            ("load.fz", Value::Real(0.2)),
            ("solver.max_step", Value::Real(0.01)),
            ("solver.integrator", Value::Integer(1)),
        ],
    );
    sim.initialize().unwrap();
    sim.set_input(index(sc, "load.fz"), 0.0);
    let before = sim.stats().newton.iterations;
    let n = 300;
    let t = Instant::now();
    for k in 0..n {
        sim.advance((k + 1) as f64 * 0.01).unwrap();
    }
    let wall = t.elapsed().as_secs_f64() / n as f64;
    (
        wall,
        (sim.stats().newton.iterations - before) as f64 / n as f64,
    )
}

fn shell_vs_beam_section() {
    let (l, b, h, e, _) = STRIP;
    let ei = e * b * h.powi(3) / 12.0;
    let k = 4.0;
    let p = k * ei / (l * l);
    let tip = shell_reference::elastica_tip_shear(k);
    let m_full = shell_reference::rollup_full_ring_moment(l, ei);
    let (rx, rz) = shell_reference::rollup_tip(l, ei, m_full);
    println!(
        "\n## 4. The strip as a shell against the strip as a 3D beam (`beam_3d`, Timoshenko, lumped mass)\n\n\
         End shear P = {p} N (k = PL^2/EI = {k}): error = |tip - elastica| / L (elastica -u/L = {:.5}, w/L = {:.5}), \
         10 load steps. Roll-up M = 2 pi EI/L = {m_full:.4} N m: error = |tip - ({rx:.1e}, {rz:.1e})| / L, 40 load steps. \
         Static = build + whole static solve; step = one 0.01 s step of the free vibration (generalized-alpha). \
         Shell meshes n_x x 2.\n",
        tip.u, tip.w
    );
    println!(
        "| model | elements along | coordinates | elastica error | elastica static [ms] | roll-up error | roll-up static [ms] | step [ms] | Newton it./step | step / beam step |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let shell = scene("strip");
    for n in [10, 20, 40] {
        let beam = beam_strip(n);
        let mut beam_step = 0.0;
        for (name, sc, mesh) in [
            ("beam", &beam, ("mesh.n_elements", n)),
            ("shell", &shell, ("mesh.n_x", n)),
        ] {
            let nf = simulation(sc, &[(mesh.0, Value::Integer(mesh.1))])
                .model()
                .n_free();
            let (t1, w1) = strip_static(sc, mesh, ("load.fz", p), 10);
            let e1 = ((1.0 - t1[0] / l - tip.u).powi(2) + (t1[1] / l - tip.w).powi(2)).sqrt();
            let (t2, w2) = strip_static(sc, mesh, ("load.my", -m_full), 40);
            let e2 = ((t2[0] - rx).powi(2) + (t2[1] - rz).powi(2)).sqrt() / l;
            let (step, its) = strip_step(sc, mesh);
            if name == "beam" {
                beam_step = step;
            }
            println!(
                "| {name} | {n} | {nf} | {e1:.2e} | {:.2} | {e2:.2e} | {:.2} | {:.3} | {its:.1} | {:.1} |",
                1e3 * w1,
                1e3 * w2,
                1e3 * step,
                step / beam_step
            );
        }
    }
}

fn main() {
    let dir = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("build/bench"));
    std::fs::create_dir_all(&dir).unwrap();
    // BENCH_SECTIONS=24 runs sections 2 and 4 only (default: all)
    let only = std::env::var("BENCH_SECTIONS").unwrap_or_else(|_| "1234".into());
    let t = Instant::now();
    if only.contains('1') {
        cost_section(&dir);
    }
    if only.contains('2') {
        cylinder_section(&dir);
    }
    if only.contains('3') {
        pareto_section(&dir);
    }
    if only.contains('4') {
        shell_vs_beam_section();
    }
    println!(
        "\nCSV: {}; total {:.0} s",
        dir.display(),
        t.elapsed().as_secs_f64()
    );
}
