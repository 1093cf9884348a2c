//! Belt-drive profile run on the library (no FMI C layer, no Python): the protocol of
//! `scripts/bench_belt.py` (driver ramp to 60 rad/s in 0.3 s, load torque on pulley 2 ramped to
//! 4 N m, communication step 1 ms) through the safe `Instance` API, printing wall time, the
//! real-time factor and the solver statistics logged at fmi2Terminate.
//!
//! Run: `cargo run --release --example bench_belt [n_elements] [t_end] [name=value ...]`
//! (further parameters by name, e.g. `solver.newton=1`).

use flexfmu::fmi2::state_machine::Call;
use flexfmu::instance::Instance;
use flexfmu::logging::Status;
use flexfmu::scene::Scene;
use flexfmu::variables::Value;
use std::path::Path;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n_el: i32 = args.get(1).map_or(100, |s| s.parse().unwrap());
    let t_end: f64 = args.get(2).map_or(1.0, |s| s.parse().unwrap());
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/belt_drive.toml");
    let scene = Scene::from_path(&path).unwrap();
    let mut inst = Instance::from_scene(
        "bench",
        scene,
        true,
        Box::new(|s, _c, m| {
            if m.contains("statistics") || s != Status::Ok {
                println!("{m}")
            }
        }),
    );
    let vr = |inst: &Instance, n: &str| inst.variables().by_name(n).unwrap().vr;
    let (ne, a1, w1, tq) = (
        vr(&inst, "belt.n_elements"),
        vr(&inst, "pulley1.angle"),
        vr(&inst, "pulley1.omega"),
        vr(&inst, "pulley2.torque_in"),
    );
    assert_eq!(
        inst.set(Call::SetInteger, &[ne], &[Value::Integer(n_el)]),
        Status::Ok
    );
    for kv in args.iter().skip(3) {
        let (name, value) = kv.split_once('=').expect("name=value");
        let v = inst.variables().by_name(name).expect("no such variable");
        let (vr, start) = (v.vr, v.start);
        let status = match start {
            Some(Value::Integer(_)) => inst.set(
                Call::SetInteger,
                &[vr],
                &[Value::Integer(value.parse().unwrap())],
            ),
            Some(Value::Boolean(_)) => {
                inst.set(Call::SetBoolean, &[vr], &[Value::Boolean(value == "true")])
            }
            _ => inst.set(Call::SetReal, &[vr], &[Value::Real(value.parse().unwrap())]),
        };
        assert_eq!(status, Status::Ok, "{kv}");
    }
    let t0 = Instant::now();
    assert_eq!(inst.setup_experiment(None, 0.0, None), Status::Ok);
    assert_eq!(inst.enter_initialization_mode(), Status::Ok);
    assert_eq!(inst.exit_initialization_mode(), Status::Ok);
    let init = t0.elapsed().as_secs_f64();
    let (w_max, t_ramp, load, h) = (60.0, 0.3, 4.0, 1e-3);
    let n = (t_end / h).round() as usize;
    let t1 = Instant::now();
    for i in 0..n {
        let t = i as f64 * h;
        let (w, a) = if t < t_ramp {
            (w_max * t / t_ramp, 0.5 * w_max * t * t / t_ramp)
        } else {
            (w_max, 0.5 * w_max * t_ramp + w_max * (t - t_ramp))
        };
        let values = [
            Value::Real(a),
            Value::Real(w),
            Value::Real(-load * (t / t_ramp).min(1.0)),
        ];
        assert_eq!(inst.set(Call::SetReal, &[a1, w1, tq], &values), Status::Ok);
        assert_eq!(inst.do_step(t, h), Status::Ok, "step at {t}");
    }
    let wall = t1.elapsed().as_secs_f64();
    println!(
        "{n_el} elements: initialization {init:.3} s, {t_end} s simulated in {wall:.3} s: real-time factor {:.2}",
        t_end / wall
    );
    assert_eq!(inst.terminate(), Status::Ok);
}
