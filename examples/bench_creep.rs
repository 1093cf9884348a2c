//! Creep of the two-pulley drive against Grashof's law, and its cost, for friction variants
//! (issue 12 items 1 and 2): prints one row per (belt, load torque, variant) with the measured
//! and theoretical creep, the slip error with pitch and running radii, Newton iterations and
//! factorizations per step and the wall time. The harness is
//! [`flexfmu::kinds::belt_drive::creep`].
//!
//! Run: `cargo run --release --example bench_creep [variant ...]` with variants
//! `default` (the contact law a scene gets) or `kt=<k_t/k_n>[,blend=<ε>][,dt=<d_t factor>]`; further keys: `ppe`, `h`, `n`, `kn` (factor on
//! k_n), `w` (driver speed [rad/s]) and `bd` (bearing damping [N m s]).

use flexfmu::kinds::belt_drive::creep::CreepCase;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let variants = if args.is_empty() {
        vec!["default".to_string()]
    } else {
        args
    };
    println!(
        "{:6} {:>6} {:24} {:>8} {:>8} {:>9} {:>9} {:>9} {:>8} {:>6} {:>6} {:>6} {:>7} {:>6} {:>6} {:>8} {:>8}",
        "belt",
        "M[Nm]",
        "variant",
        "T1[N]",
        "T2[N]",
        "c_th[%]",
        "c_pit[%]",
        "c_run[%]",
        "err_pit",
        "err_rn",
        "err_ms",
        "it/st",
        "fac/st",
        "wall",
        "steps",
        "dr1[um]",
        "dr2[um]"
    );
    for v in &variants {
        for (belt, loads) in belts() {
            for load in loads {
                let mut case = if belt == "stiff" {
                    CreepCase::stiff(load)
                } else {
                    CreepCase::soft(load)
                };
                if v != "default" {
                    let mut law = case.default_law();
                    let mut dt = 1.0;
                    for kv in v.split(',') {
                        let (k, x) = kv.split_once('=').expect("key=value");
                        let x: f64 = x.parse().expect("a number");
                        match k {
                            "kt" => law.k_t = x * law.k_n,
                            "blend" => law.blend = x,
                            "dt" => dt = x,
                            "ppe" => case.points_per_element = x as usize,
                            "h" => case.step = x,
                            "n" => case.n_elements = x as usize,
                            "kn" => law.k_n *= x,
                            "w" => case.omega = x,
                            "bd" => case.bearing_damping = x,
                            _ => panic!("unknown key {k}"),
                        }
                    }
                    law.d_t = dt * law.d_n * (law.k_t / law.k_n).sqrt();
                    case.contact = Some(law);
                }
                match case.measure() {
                    Ok(r) => println!(
                        "{:6} {:6.1} {:24} {:8.2} {:8.2} {:9.4} {:9.4} {:9.4} {:7.1}% {:5.1}% {:5.1}% {:6.2} {:7.3} {:6.2} {:6} {:8.1} {:8.1}",
                        belt,
                        load,
                        v,
                        r.tensions[0],
                        r.tensions[1],
                        100.0 * r.theory,
                        100.0 * r.pitch,
                        100.0 * r.running,
                        100.0 * r.pitch_error(),
                        100.0 * r.running_error(),
                        100.0 * r.measured_error(),
                        r.cost.iterations_per_step(),
                        r.cost.factorizations_per_step(),
                        r.cost.wall,
                        r.cost.total_steps,
                        1e6 * (case.pitch_radii()[0] - r.adhering[0]),
                        1e6 * (case.pitch_radii()[1] - r.adhering[1])
                    ),
                    Err(e) => println!("{belt:6} {load:6.1} {v:24} failed: {e}"),
                }
            }
        }
    }
}

/// The belts and load torques [N m] to run: `CREEP_BELTS=stiff|soft|both` (default both).
fn belts() -> Vec<(&'static str, [f64; 3])> {
    let which = std::env::var("CREEP_BELTS").unwrap_or_default();
    [("stiff", [4.0, 10.0, 20.0]), ("soft", [4.0, 10.0, 20.0])]
        .into_iter()
        .filter(|(b, _)| which.is_empty() || which == "both" || which == *b)
        .collect()
}
