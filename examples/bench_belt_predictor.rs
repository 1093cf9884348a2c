//! Belt drives with and without the transport predictor (issue 12 item 2), in process (no FMI
//! layer, no Python), the two variants in the same run: real-time factor, Newton iterations and
//! factorizations per communication step, accepted and rejected internal steps, and why steps
//! were rejected (Newton failure or the local error estimate, and at which coordinate: node
//! position or slope, on a pulley's arc or in a span, a pulley angle, the tensioner arm).
//!
//! Protocols (1 ms communication steps):
//! - `belt_drive`: `scripts/bench_belt.py`'s (driver ramped to 60 rad/s in 0.3 s, load torque on
//!   pulley 2 ramped to 4 N m);
//! - `serpentine`: `scripts/serpentine_demo.py`'s compressed to `t_end` (crank from rest to
//!   800 rpm in 0.1 s, held until 0.2 s, ramped to 3000 rpm until 0.2 + 0.6 t_end, held; the
//!   A/C compressor's 5 N m engaged over 50 ms at 0.4 t_end).
//!
//! Run: `cargo run --release --example bench_belt_predictor [scene] [n_elements] [t_end]
//! [both|on|off|percall] [name=value ...]` (defaults: belt_drive 100 1.0 both; further
//! parameters by name, e.g. `solver.newton=1`, `belt.formulation=2` for the ALE belt, whose
//! model has no transport predictor: run it with `on` (the shipped serpentine is an ALE belt
//! since session 38: `belt.formulation=1` for its Lagrangian drive); `BENCH_TRACE=1` prints the pulley
//! speeds, the tensioner angle and the span tensions every 50 ms; `BENCH_COMM=0.002` sets the
//! communication step [s], default 1 ms; `BENCH_DERIV=1` gives the crank speed's slope over
//! each communication step as an input derivative, as a master with `canInterpolateInputs`
//! does; `BENCH_ANGLE_EXTRAP=1` advances the crank angle input with the step-start speed, as the
//! FMU extrapolates it, instead of the trapezoidal rule, so that the angle input does not jump
//! at communication points; `BENCH_EXAMPLES=N` lists N rejected steps instead of 12). `percall` runs the protocol with the predictor
//! to `t_end`, then times one Newton iteration's pieces on the state reached: the residual
//! alone, the residual with the iteration matrix, a factorization and a solve [µs per call,
//! best of 5 batches]. Timings are of this run on this machine: compare the ratios within one
//! run.

use flexfmu::kinds::belt_drive::model::BeltDrive;
use flexfmu::linalg::{LinearSolver, SolverKind};
use flexfmu::model::build_model;
use flexfmu::model::{JacobianCoeffs, MechanicalSystem, Model};
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use flexfmu::variables::{Role, Value, VariableTable};
use std::collections::BTreeMap;
use std::time::Instant;

/// Best-of-5 time per call [µs] of `f` over batches of `reps` calls.
fn per_call(reps: usize, mut f: impl FnMut()) -> f64 {
    (0..5)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..reps {
                f();
            }
            t.elapsed().as_secs_f64() * 1e6 / reps as f64
        })
        .fold(f64::INFINITY, f64::min)
}

/// One Newton iteration's pieces on the belt's state at the end of the run.
fn pieces(sim: &mut Simulation) {
    let t = sim.time();
    let Some(d) = sim.model_as_mut::<BeltDrive>() else {
        println!("percall: the Lagrangian drive only");
        return;
    };
    let n = d.n_free();
    let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
    d.free_state(&mut q, &mut v);
    let a = vec![0.0; n];
    let mut r = vec![0.0; n];
    let pattern = d.pattern().clone();
    let mut vals = vec![0.0; pattern.nnz()];
    let h = 1e-3;
    let coeffs = JacobianCoeffs {
        mass: 1.0,
        damping: 0.5 * h,
        stiffness: 0.25 * h * h,
    };
    let res = per_call(200, || {
        d.residual(t, &q, &v, &a, 1.0, &mut r, None).unwrap();
    });
    let resjac = per_call(200, || {
        d.residual(t, &q, &v, &a, 1.0, &mut r, Some((coeffs, &mut vals)))
            .unwrap();
    });
    let mut solver = LinearSolver::new(&pattern, SolverKind::Auto).unwrap();
    let fact = per_call(200, || solver.factor(&pattern, &vals).unwrap());
    let mut b = r.clone();
    let solve = per_call(1000, || {
        b.copy_from_slice(&r);
        solver.solve_in_place(&mut b);
    });
    let shape = match solver.backend() {
        flexfmu::linalg::Backend::Bordered(s) => format!("{:?}", s.shape()),
        _ => "not bordered".into(),
    };
    println!(
        "coordinates {n}, nonzeros {}, (kl, ku, border) {shape}",
        pattern.nnz()
    );
    println!("| piece | µs per call |");
    println!("|---|---|");
    println!("| residual alone | {res:.1} |");
    println!("| residual + iteration matrix | {resjac:.1} |");
    println!("| factorization | {fact:.1} |");
    println!("| solve | {solve:.1} |");
}

struct Run {
    wall: f64,
    steps: usize,
    rejected: usize,
    rejected_error: usize,
    iterations: usize,
    factorizations: usize,
    backtracks: usize,
    causes: BTreeMap<String, usize>,
    examples: Vec<String>,
    omega: Vec<f64>,
}

fn run(name: &str, n_el: i32, t_end: f64, predictor: bool, extra: &[String], percall: bool) -> Run {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{name}.toml"));
    let scene = Scene::from_path(&path).unwrap();
    let vars = VariableTable::from_scene(&scene);
    let mut p = ParamValues::defaults(&scene.params);
    p.set("belt.n_elements", Value::Integer(n_el));
    for kv in extra {
        let (k, v) = kv.split_once('=').expect("name=value");
        let value = match p.get(k).expect("no such parameter") {
            Value::Integer(_) => Value::Integer(v.parse().unwrap()),
            Value::Boolean(_) => Value::Boolean(v == "true"),
            _ => Value::Real(v.parse().unwrap()),
        };
        p.set(Box::leak(k.to_string().into_boxed_str()), value);
    }
    let input = |n: &str| match vars.by_name(n).unwrap().role {
        Role::Input(k) => k,
        _ => panic!("{n}"),
    };
    let serp = name == "serpentine";
    let (ia, iw, it) = (
        input("pulley1.angle"),
        input("pulley1.omega"),
        input(if serp {
            "pulley7.torque_in"
        } else {
            "pulley2.torque_in"
        }),
    );
    let n_p = if serp { 7 } else { 2 };
    let omega_out: Vec<usize> = (2..=n_p)
        .map(
            |k| match vars.by_name(&format!("pulley{k}.omega")).unwrap().role {
                Role::Output(o) => o,
                _ => panic!(),
            },
        )
        .collect();
    let model = build_model(&scene, &p).unwrap();
    let cfg = SolverConfig::from_params(&p);
    let mut sim = Simulation::new(model, cfg, 0.0).unwrap();
    if let Some(d) = sim.model_as_mut::<BeltDrive>() {
        d.set_transport_predictor(predictor);
    }
    // `BENCH_TRACE=1`: every 50 ms the pulley speeds, the tensioner angle and the span
    // tensions (serpentine), for the validation of one run against another
    let trace = std::env::var("BENCH_TRACE").is_ok_and(|v| v == "1");
    let out = |n: &str| match vars.by_name(n).map(|v| v.role) {
        Some(Role::Output(o)) => Some(o),
        _ => None,
    };
    let traced: Vec<(String, usize)> = (2..=n_p)
        .map(|k| format!("pulley{k}.omega"))
        .chain(["tensioner.angle".to_string()])
        .chain((1..=n_p).map(|k| format!("span{k}.tension")))
        .chain(["pulley1.torque".to_string()])
        .filter_map(|n| out(&n).map(|o| (n, o)))
        .collect();
    if trace {
        println!(
            "trace | t | {}",
            traced
                .iter()
                .map(|(n, _)| n.as_str())
                .collect::<Vec<_>>()
                .join(" | ")
        );
    }
    sim.initialize().unwrap();
    sim.log_rejections(true);
    let s0 = sim.stats();
    // `BENCH_COMM=h`: the communication step [s] (default 1 ms)
    let h: f64 = std::env::var("BENCH_COMM")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1e-3);
    let n = (t_end / h).round() as usize;
    // driver speed [rad/s] and load torque [N m] at time t
    let omega = |t: f64| -> f64 {
        if serp {
            let t2 = 0.2 + 0.6 * t_end;
            let rpm = if t < 0.2 {
                800.0
            } else if t < t2 {
                800.0 + 2200.0 * (t - 0.2) / (t2 - 0.2)
            } else {
                3000.0
            };
            rpm * (t / 0.1).min(1.0) * std::f64::consts::PI / 30.0
        } else {
            60.0 * (t / 0.3).min(1.0)
        }
    };
    let load = |t: f64| -> f64 {
        if serp {
            -5.0 * ((t - 0.4 * t_end) / 0.05).clamp(0.0, 1.0)
        } else {
            -4.0 * (t / 0.3).min(1.0)
        }
    };
    let deriv = std::env::var("BENCH_DERIV").is_ok_and(|v| v == "1");
    let mut causes = BTreeMap::new();
    let mut examples = Vec::new();
    let mut angle = 0.0;
    let start = Instant::now();
    for i in 0..n {
        let t = i as f64 * h;
        sim.set_input(ia, angle);
        sim.set_input(iw, omega(t));
        if deriv {
            // the speed's slope over the step (`BENCH_DERIV=1`): the driven angle and
            // speed then follow the master's ramp inside the step instead of jumping at
            // its end
            sim.set_input_derivative(iw, 1, (omega(t + h) - omega(t)) / h)
                .unwrap();
        }
        sim.set_input(it, load(t));
        if let Err(e) = sim.advance(t + h) {
            println!("  step at t = {t}: {}", e.message);
            break;
        }
        angle += if std::env::var("BENCH_ANGLE_EXTRAP").is_ok() {
            omega(t) * h
        } else {
            0.5 * (omega(t) + omega(t + h)) * h
        };
        if trace && (i + 1) % 50 == 0 {
            let st = sim.stats();
            println!(
                "trace | {:.3} | it {} fact {} steps {} | {}",
                t + h,
                st.newton.iterations - s0.newton.iterations,
                st.newton.factorizations - s0.newton.factorizations,
                st.steps - s0.steps,
                traced
                    .iter()
                    .map(|(_, o)| format!("{:.6}", sim.output(*o)))
                    .collect::<Vec<_>>()
                    .join(" | ")
            );
        }
        let rej = sim.take_rejections();
        if !rej.is_empty() {
            let d = sim.model_as::<BeltDrive>();
            for r in rej {
                let what = d.map_or_else(
                    || format!("ALE coordinate {}", r.coordinate),
                    |d| d.describe_free_coordinate(r.coordinate),
                );
                let cause = match &r.newton {
                    None => "error estimate".to_string(),
                    Some(m) if m.contains("did not converge") => "Newton not converged".into(),
                    Some(m) if m.contains("diverged") => "Newton diverged".into(),
                    Some(m) => format!("other: {}", &m[..m.len().min(60)]),
                };
                let class = if what.starts_with("node") {
                    let gap: f64 = what
                        .split("gap ")
                        .nth(1)
                        .and_then(|s| s.split(' ').next())
                        .and_then(|s| s.parse().ok())
                        .unwrap_or(f64::INFINITY);
                    let coord = if what.contains("r'") {
                        "slope"
                    } else {
                        "position"
                    };
                    let place = if gap < 0.2 {
                        "on an arc"
                    } else if gap < 3.0 {
                        "within 3 mm of an arc"
                    } else {
                        "in a span"
                    };
                    format!("{coord} {place}")
                } else {
                    what.split(' ').take(2).collect::<Vec<_>>().join(" ")
                };
                *causes.entry(format!("{cause}: {class}")).or_insert(0) += 1;
                if examples.len()
                    < std::env::var("BENCH_EXAMPLES")
                        .ok()
                        .and_then(|v| v.parse().ok())
                        .unwrap_or(12)
                {
                    examples.push(format!(
                        "t = {:.4} s h = {:.2e} s {cause} at {what}, scaled {:.3e}",
                        r.t, r.h, r.value
                    ));
                }
            }
        }
    }
    let wall = start.elapsed().as_secs_f64();
    if percall {
        pieces(&mut sim);
    }
    let s = sim.stats();
    Run {
        wall,
        steps: s.steps - s0.steps,
        rejected: s.rejected - s0.rejected,
        rejected_error: s.rejected_error - s0.rejected_error,
        iterations: s.newton.iterations - s0.newton.iterations,
        factorizations: s.newton.factorizations - s0.newton.factorizations,
        backtracks: s.newton.backtracks - s0.newton.backtracks,
        causes,
        examples,
        omega: omega_out.iter().map(|&o| sim.output(o)).collect(),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map_or("belt_drive", |s| s.as_str()).to_string();
    let n_el: i32 = args.get(2).map_or(100, |s| s.parse().unwrap());
    let t_end: f64 = args.get(3).map_or(1.0, |s| s.parse().unwrap());
    let which = args.get(4).map_or("both", |s| s.as_str());
    let extra: Vec<String> = args.iter().skip(5).cloned().collect();
    let variants: &[bool] = match which {
        "on" | "percall" => &[true],
        "off" => &[false],
        _ => &[false, true],
    };
    println!(
        "scene | elements | predictor | real-time factor | it/step | fact/step | backtracks/step | internal steps | rejected (error estimate) | omega 2..n at the end [rad/s]"
    );
    for &pred in variants {
        let r = run(&name, n_el, t_end, pred, &extra, which == "percall");
        let comm = (t_end / 1e-3).round();
        println!(
            "{name} | {n_el} | {} | {:.3} | {:.3} | {:.3} | {:.2} | {} | {} ({}) | {:?}",
            if pred { "transport" } else { "integrator's" },
            t_end / r.wall,
            r.iterations as f64 / comm,
            r.factorizations as f64 / comm,
            r.backtracks as f64 / comm,
            r.steps,
            r.rejected,
            r.rejected_error,
            r.omega
                .iter()
                .map(|w| format!("{w:.4}"))
                .collect::<Vec<_>>()
        );
        for (c, k) in &r.causes {
            println!("    {k:6} {c}");
        }
        for e in &r.examples {
            println!("    e.g. {e}");
        }
    }
}
