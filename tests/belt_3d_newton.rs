//! Newton at arc entry of the 3D belt (issue 13 item 5): the shipped `belt_drive_3d` at 120
//! elements over the 60 rad/s protocol of `scripts/bench_belt.py`.

mod common;

use flexfmu::variables::Value;

/// 120 elements, pulley 1 ramped to 60 rad/s over 0.3 s and the load on pulley 2 to 4 N m
/// (`scripts/bench_belt.py`'s protocol), 1 ms steps, 0.3 s: no Newton solve may fail. With
/// three line-search halvings the solve at t = 0.286 s failed (25 iterations): a node arriving
/// on pulley 2 cycled in and out of contact (out at +0.44 δ0, the full increment 34 δ0 deep,
/// three halvings 3.8 δ0, the next increment out again); with
/// `Belt3d::line_search_cuts` = 6 it converges.
#[test]
fn arc_entry_at_60_rad_s_has_no_failed_solves() {
    let scene = common::scene("belt_drive_3d");
    let mut sim = common::simulation(&scene, &[("belt.n_elements", Value::Integer(120))]).unwrap();
    let (ia, iw, it) = (
        common::input_index(&scene, "pulley1.angle"),
        common::input_index(&scene, "pulley1.omega"),
        common::input_index(&scene, "pulley2.torque_in"),
    );
    let (h, omega, ramp, load) = (1e-3, 60.0, 0.3, 4.0);
    let mut angle = 0.0;
    for i in 0..300 {
        let t = i as f64 * h;
        let r = |t: f64| (t / ramp).min(1.0);
        let w = 0.5 * omega * (r(t) + r(t + h));
        sim.set_input(ia, angle);
        sim.set_input(iw, w);
        sim.set_input(it, -load * r(t));
        sim.advance(t + h)
            .unwrap_or_else(|e| panic!("t = {t}: {}", e.message));
        angle += w * h;
    }
    let s = sim.stats();
    assert_eq!(s.rejected - s.rejected_error, 0, "Newton failures: {s:?}");
}
