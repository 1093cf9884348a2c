use flexfmu::model::build_model;
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use flexfmu::variables::{BeltOutput, InputKind, OutputKind, PulleyInput, Value};

#[test]
#[ignore]
fn explore() {
    let scene = Scene::from_path(std::path::Path::new("scenes/belt_drive.toml")).unwrap();
    let mut p = ParamValues::defaults(&scene.params);
    if let Ok(n) = std::env::var("NEL") { p.set("belt.n_elements", Value::Integer(n.parse().unwrap())); }
    if let Ok(n) = std::env::var("HMAX") { p.set("solver.max_step", Value::Real(n.parse().unwrap())); }
    if let Ok(list) = std::env::var("PARAMS") {
        for kv in list.split(',') {
            let (k, v) = kv.split_once('=').unwrap();
            let name = scene.params.iter().find(|d| d.name == k).unwrap().name;
            match p.get(k).unwrap() {
                Value::Real(_) => p.set(name, Value::Real(v.parse().unwrap())),
                Value::Integer(_) => p.set(name, Value::Integer(v.parse().unwrap())),
                Value::Boolean(_) => p.set(name, Value::Boolean(v == "true")),
            }
        }
    }
    let t0 = std::time::Instant::now();
    let model = build_model(&scene, &p).unwrap();
    println!("build {:?}", t0.elapsed());
    let cfg = SolverConfig::from_params(&p);
    let mut sim = Simulation::new(model, cfg, 0.0).unwrap();
    println!("{:?}", sim.initialize());
    let out = |sim: &Simulation, b| sim.output(OutputKind::Belt(b));
    println!("t=0 tight {} slack {}", out(&sim, BeltOutput::TensionTight), out(&sim, BeltOutput::TensionSlack));
    let dt = 1e-3;
    let t_end: f64 = std::env::var("TEND").map(|s| s.parse().unwrap()).unwrap_or(0.5);
    let w_max = 50.0;
    let mut angle = 0.0;
    let t1 = std::time::Instant::now();
    let n = (t_end / dt).round() as usize;
    for i in 0..n {
        let t = i as f64 * dt;
        let w = w_max * (t / 0.2).min(1.0);
        sim.set_input(InputKind::Pulley { pulley: 0, quantity: PulleyInput::Angle }, angle);
        sim.set_input(InputKind::Pulley { pulley: 0, quantity: PulleyInput::Omega }, w);
        sim.set_input(InputKind::Pulley { pulley: 1, quantity: PulleyInput::Torque }, -5.0 * (t / 0.2).min(1.0));
        if let Err(e) = sim.advance(t + dt) { println!("FAIL {e:?}"); break; }
        angle += w * dt;
        if i % 50 == 49 {
            println!("t={:.3} tq1={:.3} w2={:.3} tight={:.1} slack={:.1} slip={:.4} speed={:.3} stats={:?}", t + dt,
              out(&sim, BeltOutput::PulleyTorque(0)), out(&sim, BeltOutput::PulleyOmega(1)),
              out(&sim, BeltOutput::TensionTight), out(&sim, BeltOutput::TensionSlack), out(&sim, BeltOutput::Slip), out(&sim, BeltOutput::Speed), sim.stats());
        }
    }
    let el = t1.elapsed().as_secs_f64();
    println!("wall {el:.3} s for {t_end} s: RTF {:.2}", t_end / el);
}
