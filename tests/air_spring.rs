//! The air spring at the membrane level against the independent shooting solution of the
//! membrane equations (`scripts/air_spring_reference.py`, data in
//! `tests/data/air_spring_reference.json`), the exact membrane identities, and the gas.

use flexfmu::kinds::air_spring::AirSpringScene;
use flexfmu::kinds::air_spring::model::AirSpring;
use flexfmu::scene::Scene;


fn build(text: &str, set: &[(&'static str, f64)]) -> AirSpring {
    let scene = Scene::from_toml(text).unwrap();
    let tables: &AirSpringScene = scene.tables().unwrap();
    let mut p = flexfmu::scene::ParamValues::defaults(&scene.params);
    for (k, v) in set {
        p.set(k, flexfmu::variables::Value::Real(*v));
    }
    AirSpring::build(tables, &p).unwrap()
}

fn axisym() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/air_spring_axisym.toml"))
        .unwrap()
}

/// The design state (5 bar at 0.25 m) of the reference spring: force, volume and effective
/// area against the shooting solution, as the mesh is refined.
#[test]
fn design_state_converges_to_the_shooting_solution() {
    let (f_ref, v_ref) = (21533.036721294928, 0.008456948509839048);
    for (n, k) in [(30, 1e10), (60, 1e10), (120, 1e10), (120, 1e11), (240, 1e11), (240, 1e12)] {
        let text = axisym().replace("n_meridional = 60", &format!("n_meridional = {n}"));
        let m = build(&text, &[("contact.stiffness", k)]);
        let f = m.committed_force();
        let v = m.gas().committed().volume;
        let lobe = m.meridian().iter().map(|p| p[0]).fold(0.0, f64::max);
        println!(
            "n = {n}: F = {f:.3} N ({:+.3e}), V = {:.6} L ({:+.3e}), lobe {lobe:.5}",
            f / f_ref - 1.0,
            v * 1e3,
            v / v_ref - 1.0
        );
    }
}
