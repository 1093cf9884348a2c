//! Speed of the 3D belt (`scenes/belt_drive_3d.toml`) against the planar belt
//! (`scenes/belt_drive.toml`, same belt and pulleys) at 60/120/240 elements, 1 ms
//! communication steps, over one of two protocols:
//! * `slow` (default): 0.3 s of running, pulley 1 ramped to 10 rad/s over 0.1 s, 5 N m load on
//!   pulley 2;
//! * `fmpy` (`--protocol fmpy`): the protocol of `scripts/bench_belt.py` (pulley 1 ramped to
//!   60 rad/s over 0.3 s, load ramped to 4 N m over 0.3 s), 0.6 s.
//!
//! Prints wall time, real-time factor (simulated / wall time, in process, without fmpy),
//! accepted substeps and failed (rejected) steps, Newton iterations and factorizations per
//! communication step and the cost per element per Newton iteration; the 3D belt with and
//! without its transport predictor (`Belt3d::set_transport_predictor`), with the contact at
//! the centre line (`contact.width_points` = 1) and across the width (3 points). `--only3`
//! runs the planar belt and the 3D belt with 3 width points and the predictor only;
//! `--no-planar` leaves the planar belt out (a profile of the 3D belt alone).
//! `--set key=value` sets a scene parameter (integer or real), `--set3 key=value` one of the
//! 3D scene only (`contact.points_per_element`, which the planar scene has too). `--log` prints the rejections by coordinate kind (node position, node rotation, other) and
//! cause (Newton or error estimate). `--max-step H` sets `solver.max_step` (a reference run).
//! The line after each row gives the same from the thread's CPU time (10 ms resolution).
//! Element counts from the command line (default 60 120 240). Timings are of this run on this
//! machine; compare the ratios within one run.
//!
//! `cargo run --release --example bench_belt_3d -- [--protocol fmpy] [--only3] [--log] [N ...]`

use flexfmu::kinds::belt_3d::model::Belt3d;
use flexfmu::model::build_model;
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::solver::simulation::{RunStats, Simulation, SolverConfig};
use flexfmu::variables::{Role, Value, VariableTable};
use std::time::Instant;

/// Driver protocol: final speed [rad/s], speed ramp [s], load [N m], load ramp [s], end [s].
#[derive(Clone, Copy)]
struct Protocol {
    omega: f64,
    t_ramp: f64,
    load: f64,
    t_load: f64,
    t_end: f64,
}

struct Options {
    protocol: Protocol,
    log: bool,
    max_step: Option<f64>,
    set: Vec<(&'static str, Value)>,
    /// Parameters of the 3D scene only (`--set3`).
    set3: Vec<(&'static str, Value)>,
}

fn run(
    name: &str,
    n_el: i32,
    width_points: Option<i32>,
    predictor: bool,
    o: &Options,
) -> (f64, f64, RunStats, Option<Belt3dSummary>) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{name}.toml"));
    let scene = Scene::from_path(&path).unwrap();
    let vars = VariableTable::from_scene(&scene);
    let mut p = ParamValues::defaults(&scene.params);
    p.set("belt.n_elements", Value::Integer(n_el));
    if let Some(w) = width_points {
        p.set("contact.width_points", Value::Integer(w));
    }
    for &(k, ref v) in &o.set {
        p.set(k, *v);
    }
    if name != "belt_drive" {
        for &(k, ref v) in &o.set3 {
            p.set(k, *v);
        }
    }
    if let Some(h) = o.max_step {
        p.set("solver.max_step", Value::Real(h));
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
    sim.log_rejections(o.log);
    let pr = o.protocol;
    let start = Instant::now();
    let cpu0 = thread_cpu();
    let h = 1e-3;
    let mut angle = 0.0;
    let mut rejections = vec![];
    for i in 0..(pr.t_end / h).round() as usize {
        let t = i as f64 * h;
        let r = |t: f64| (t / pr.t_ramp).min(1.0);
        let w = 0.5 * pr.omega * (r(t) + r(t + h));
        sim.set_input(ia, angle);
        sim.set_input(iw, w);
        sim.set_input(it, -pr.load * (t / pr.t_load).min(1.0));
        sim.advance(t + h).unwrap();
        angle += w * h;
        if o.log {
            rejections.extend(sim.take_rejections());
        }
    }
    let wall = start.elapsed().as_secs_f64();
    let cpu = thread_cpu() - cpu0;
    if o.log && !rejections.is_empty() {
        // node coordinates come first (6 per node, all free: the belt is a closed loop)
        let n_node_dofs = 6 * n_el as usize;
        let mut count = [[0usize; 3]; 2];
        for r in &rejections {
            let kind = if r.coordinate >= n_node_dofs {
                2
            } else if r.coordinate % 6 < 3 {
                0
            } else {
                1
            };
            count[usize::from(r.newton.is_some())][kind] += 1;
        }
        println!(
            "  rejections: error estimate (position/rotation/other) {:?}, Newton {:?}; first: {:?}",
            count[0],
            count[1],
            &rejections[..rejections.len().min(3)]
        );
    }
    let summary = sim.model_as::<Belt3d>().map(|m| Belt3dSummary {
        tensions: m.span_tensions().to_vec(),
        omega2: m.pulley_motion(1).1,
        lateral: m.lateral(1),
    });
    (wall, cpu, sim.stats(), summary)
}

/// CPU time of this thread [s] (user + system, from `/proc/thread-self/stat`, clock ticks
/// of 10 ms; NaN where it cannot be read): the speed on a loaded machine.
fn thread_cpu() -> f64 {
    std::fs::read_to_string("/proc/thread-self/stat")
        .ok()
        .and_then(|s| {
            // fields after the command name (in parentheses): utime and stime are 14 and 15
            let rest = &s[s.rfind(')')? + 2..];
            let f: Vec<&str> = rest.split_whitespace().collect();
            let ticks = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
            Some(ticks / 100.0)
        })
        .unwrap_or(f64::NAN)
}

/// End state of a 3D belt run (compare substep settings).
struct Belt3dSummary {
    tensions: Vec<f64>,
    omega2: f64,
    lateral: f64,
}

fn main() {
    let mut o = Options {
        protocol: Protocol {
            omega: 10.0,
            t_ramp: 0.1,
            load: 5.0,
            t_load: 0.1,
            t_end: 0.3,
        },
        log: false,
        max_step: None,
        set: vec![],
        set3: vec![],
    };
    let mut only3 = false;
    let mut no_planar = false;
    let mut counts = vec![];
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--protocol" => {
                if args.next().as_deref() == Some("fmpy") {
                    o.protocol = Protocol {
                        omega: 60.0,
                        t_ramp: 0.3,
                        load: 4.0,
                        t_load: 0.3,
                        t_end: 0.6,
                    };
                }
            }
            "--t-end" => o.protocol.t_end = args.next().unwrap().parse().unwrap(),
            "--log" => o.log = true,
            "--only3" => only3 = true,
            "--no-planar" => no_planar = true,
            "--max-step" => o.max_step = Some(args.next().unwrap().parse().unwrap()),
            a @ ("--set" | "--set3") => {
                let kv = args.next().unwrap();
                let (k, v) = kv.split_once('=').expect("--set key=value");
                let v = match v.parse::<i32>() {
                    Ok(i) => Value::Integer(i),
                    Err(_) => Value::Real(v.parse().unwrap()),
                };
                let list = if a == "--set" {
                    &mut o.set
                } else {
                    &mut o.set3
                };
                list.push((k.to_string().leak(), v));
            }
            n => counts.push(n.parse::<i32>().expect("element count")),
        }
    }
    if counts.is_empty() {
        counts = vec![60, 120, 240];
    }
    let t_end = o.protocol.t_end;
    println!(
        "scene | elements | predictor | wall [s] for {t_end} s | real-time factor | substeps | failed steps | Newton it./step | factorizations/step | substeps/step | us per element per iteration"
    );
    let cases: &[(&str, Option<i32>, bool)] = if only3 {
        &[("belt_drive", None, true), ("belt_drive_3d", Some(3), true)]
    } else {
        &[
            ("belt_drive", None, true),
            ("belt_drive_3d", Some(1), false),
            ("belt_drive_3d", Some(1), true),
            ("belt_drive_3d", Some(3), false),
            ("belt_drive_3d", Some(3), true),
        ]
    };
    for n in counts {
        for &(name, width, predictor) in cases {
            if no_planar && name == "belt_drive" {
                continue;
            }
            let (wall, cpu, s, summary) = run(name, n, width, predictor, &o);
            let name = match width {
                Some(w) => format!("{name} (width_points {w})"),
                None => name.to_string(),
            };
            let its = s.newton.iterations;
            let comm = (t_end / 1e-3).round();
            println!(
                "{name} | {n} | {} | {wall:.3} | {:.3} | {} | {} | {:.2} | {:.2} | {:.2} | {:.3}",
                if predictor { "on" } else { "off" },
                t_end / wall,
                s.steps,
                s.rejected,
                its as f64 / comm,
                s.newton.factorizations as f64 / comm,
                s.steps as f64 / comm,
                1e6 * wall / (n as f64 * its as f64)
            );
            println!(
                "  CPU time {cpu:.2} s: real-time factor {:.3}, us per element per iteration {:.3}",
                t_end / cpu,
                1e6 * cpu / (n as f64 * its as f64)
            );
            if let Some(b) = summary {
                println!(
                    "  end: span tensions {:?} N, omega2 {:.6} rad/s, lateral {:.3e} m; line-search backtracks per step {:.2}, refreshed matrices per step {:.2}",
                    b.tensions,
                    b.omega2,
                    b.lateral,
                    s.newton.backtracks as f64 / comm,
                    s.newton.refreshes as f64 / comm
                );
            }
        }
    }
}
