//! The double-convoluted air spring (`bellows.type = "convoluted"`, issue 11 item 2, second
//! geometry) at the membrane level against the independent shooting solution of
//! `scripts/air_spring_reference.py --convoluted` (`tests/data/air_spring_convoluted_reference.toml`:
//! the spring of `scenes/air_spring_convoluted.toml` at 5 bar, constant pressure), the strictness
//! of its scene tables, and the closed-gas stiffness.

mod common;

use common::{output, simulation, with};
use flexfmu::kinds::air_spring::AirSpringScene;
use flexfmu::kinds::air_spring::model::AirSpring;
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::variables::Value;

fn reference() -> toml::Table {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/air_spring_convoluted_reference.toml"
    ))
    .unwrap();
    toml::from_str(&text).unwrap()
}

fn floats(t: &toml::Value, key: &str) -> Vec<f64> {
    t[key]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_float().unwrap())
        .collect()
}

fn text() -> String {
    std::fs::read_to_string(common::scene_path("air_spring_convoluted")).unwrap()
}

fn build(text: &str) -> AirSpring {
    let scene = Scene::from_toml(text).unwrap();
    let tables: &AirSpringScene = scene.tables().unwrap();
    AirSpring::build(tables, &ParamValues::defaults(&scene.params)).unwrap()
}

/// Largest relative errors of F and V over the reference heights at constant pressure, on a
/// mesh of `n` elements.
fn errors(n: usize) -> (f64, f64) {
    let r = reference();
    let c = &r["constant_pressure"];
    let (hs, fs, vs) = (floats(c, "h"), floats(c, "F"), floats(c, "V"));
    let p = floats(c, "p_gauge")[0];
    let mut m = build(&with(&text(), "n_meridional", &n.to_string()));
    let (mut ef, mut ev) = (0.0f64, 0.0f64);
    // from the design height down, then up (continuation from the last equilibrium)
    let mut order: Vec<usize> = (0..hs.len())
        .filter(|&i| hs[i] <= 0.2 + 1e-12)
        .rev()
        .collect();
    order.extend((0..hs.len()).filter(|&i| hs[i] > 0.2 + 1e-12));
    for i in order {
        if (hs[i] - 0.21).abs() < 1e-12 {
            m.equilibrium_at(0.2, p).unwrap();
        }
        let (f, v) = m.equilibrium_at(hs[i], p).unwrap();
        println!(
            "n = {n}, h = {:.2}: F {f:.3} vs {:.3}, V {v:.7e} vs {:.7e}",
            hs[i], fs[i], vs[i]
        );
        ef = ef.max((f / fs[i] - 1.0).abs());
        ev = ev.max((v / vs[i] - 1.0).abs());
    }
    (ef, ev)
}

/// Force and volume over the stroke (0.17–0.23 m at 5 bar) converge to the shooting solution:
/// measured largest errors 2.0e-3 (F) and 7.1e-4 (V) at 60 elements, 4.8e-4 and 1.7e-4 at 120
/// (the design point: 2.3e-4 and 1.3e-4 at 120; 3.7e-5 and 3.1e-5 at 240).
#[test]
fn constant_pressure_characteristic_matches_the_shooting_solution() {
    let (f60, v60) = errors(60);
    let (f120, v120) = errors(120);
    println!("60: {f60:.2e} {v60:.2e}; 120: {f120:.2e} {v120:.2e}");
    assert!(f120 < 6e-4 && v120 < 3e-4, "{f120} {v120}");
    assert!(f120 < 0.5 * f60 && v120 < 0.5 * v60);
}

/// The effective area `top.fz / p_g` of the design state is `π r_h²` of the departure point
/// from the top plate in the shooting solution (exact for a membrane: the first integral of the
/// axial equilibrium, constant across the axially free girdle ring), and the lobes roll on the
/// plates: the top plate carries contact (the bead alone would give `p π r_b²` minus the
/// sleeve's pull).
#[test]
fn effective_area_is_that_of_the_departure_radius() {
    let r = reference();
    let c = &r["constant_pressure"];
    let (hs, rh) = (floats(c, "h"), floats(c, "r_h"));
    let i = hs.iter().position(|h| (h - 0.2).abs() < 1e-12).unwrap();
    let scene = Scene::from_toml(&with(&text(), "n_meridional", "120")).unwrap();
    let sim = simulation(&scene, &[]).unwrap();
    let a_e = output(&scene, &sim, "spring.effective_area");
    let exact = std::f64::consts::PI * rh[i] * rh[i];
    println!("A_e {a_e:.6} vs pi r_h^2 {exact:.6}");
    assert!((a_e / exact - 1.0).abs() < 5e-4);
    // far from the bead value: the plate contact matters
    let bead = std::f64::consts::PI * 0.115f64.powi(2);
    assert!(a_e > 1.1 * bead);
}

/// Closed gas at the design state: the stiffness output is `n p_abs A_e A_v / V + p_g dA_e/dz`
/// with `A_v` the volumetric-area output (the closed path) and `dA_e/dz` by central differences
/// of the closed-gas effective area (two static solves at ±0.1 mm); the usual `A_e²` form
/// differs by more than the identity's error.
#[test]
fn closed_gas_stiffness_identity() {
    let scene = Scene::from_toml(&with(&text(), "n_meridional", "60")).unwrap();
    let at = |h: f64| {
        let sim = simulation(&scene, &[("top.z", Value::Real(h))]).unwrap();
        [
            "top.fz",
            "gas.pressure",
            "gas.pressure_gauge",
            "gas.volume",
            "spring.effective_area",
            "spring.volumetric_area",
            "spring.stiffness",
        ]
        .map(|n| output(&scene, &sim, n))
    };
    let h = 0.2;
    let dh = 1e-4;
    let [_, p, pg, v, ae, av, k] = at(h);
    let ae_p = at(h + dh)[4];
    let ae_m = at(h - dh)[4];
    let dae_dz = -(ae_p - ae_m) / (2.0 * dh);
    let n = 1.4;
    let k_identity = n * p * ae * av / v + pg * dae_dz;
    let k_ae2 = n * p * ae * ae / v + pg * dae_dz;
    println!("k {k:.1}, identity {k_identity:.1}, A_e^2 form {k_ae2:.1}");
    assert!((k / k_identity - 1.0).abs() < 2e-3);
    assert!((k_ae2 - k).abs() > 2.0 * (k_identity - k).abs());
}

/// `bellows.type` is strict, and the tables of the other type are rejected with their name.
#[test]
fn scene_tables_are_strict() {
    let t = text();
    let bad = [
        (
            t.replace("type = \"convoluted\"", "type = \"convolutd\""),
            "bellows.type",
        ),
        (
            t.replace("[girdle]\nradius = 0.110", "[piston]\nradius = 0.110"),
            "piston",
        ),
        (
            t.replace("n_convolutions = 2", "n_convolutions = 3"),
            "n_convolutions",
        ),
        (
            t.replace("n_convolutions = 2", "n_convolutions = 1"),
            "girdle",
        ),
        (
            t.replace("fidelity = 2 ", "fidelity = 1 "),
            "model.fidelity",
        ),
        (
            std::fs::read_to_string(common::scene_path("air_spring_axisym"))
                .unwrap()
                .replace("[spring]", "[girdle]\nradius = 0.1\n\n[spring]"),
            "girdle",
        ),
    ];
    for (text, key) in bad {
        let e = match Scene::from_toml(&text) {
            Ok(_) => panic!("accepted a scene with a bad {key}"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(key), "{key}: {e}");
    }
    // an odd mesh cannot hold the girdle at a node
    let scene = Scene::from_toml(&with(&t, "n_meridional", "61")).unwrap();
    let tables: &AirSpringScene = scene.tables().unwrap();
    let e = AirSpring::build(tables, &ParamValues::defaults(&scene.params)).unwrap_err();
    assert!(e.contains("even"), "{e}");
}

/// Level 3 of the convoluted spring: `scenes/air_spring_convoluted_table.toml` is what
/// `flexfmu air-spring-table` makes from the membrane level (regenerated here, 120 elements,
/// 0.16–0.24 m), and with the closed gas it follows the membrane level (60 elements, the
/// shipped mesh) over a slow ±20 mm sine: force within 0.5 % of the design force, pressure
/// within 0.1 % (measured: 1.5e-3 and 1.4e-4; the table keeps the shape of its reference pressure and a linear volume compliance).
#[test]
fn table_level_of_the_convoluted_spring() {
    let hs: Vec<f64> = (0..17)
        .map(|k| 0.16 + (0.24 - 0.16) * k as f64 / 16.0)
        .collect();
    let generated = flexfmu::kinds::air_spring::table::generate(
        &text(),
        &hs,
        None,
        Some(120),
        "air_spring_convoluted_table",
        &mut |_, _| {},
    )
    .unwrap();
    let shipped =
        std::fs::read_to_string(common::scene_path("air_spring_convoluted_table")).unwrap();
    assert!(
        generated == shipped,
        "scenes/air_spring_convoluted_table.toml is stale: regenerate it with `flexfmu air-spring-table scenes/air_spring_convoluted.toml -o scenes/air_spring_convoluted_table.toml --heights 0.16:0.24:17 --elements 120 --name air_spring_convoluted_table`"
    );
    let run = |name: &str| {
        let scene = common::scene(name);
        let mut sim = simulation(&scene, &[]).unwrap();
        let iz = common::input_index(&scene, "top.z");
        let iv = common::input_index(&scene, "top.vz");
        let h0 = output(&scene, &sim, "spring.height");
        let w = std::f64::consts::PI;
        let mut out = vec![];
        for k in 0..2000 {
            let t = k as f64 * 1e-3;
            sim.set_input(iz, h0 + 0.02 * (w * t).sin());
            sim.set_input(iv, 0.02 * w * (w * t).cos());
            sim.advance(t + 1e-3).unwrap();
            out.push((
                output(&scene, &sim, "top.fz"),
                output(&scene, &sim, "gas.pressure_gauge"),
            ));
        }
        out
    };
    let membrane = run("air_spring_convoluted");
    let table = run("air_spring_convoluted_table");
    let f0 = membrane[0].0;
    let (mut df, mut dp) = (0.0f64, 0.0f64);
    for (m, t) in membrane.iter().zip(&table) {
        df = df.max((m.0 - t.0).abs() / f0);
        dp = dp.max((m.1 - t.1).abs() / m.1);
    }
    println!(
        "convoluted level 3 against level 2 over ±20 mm: force {df:.2e} of the design force, gauge pressure {dp:.2e}"
    );
    assert!(df < 5e-3, "{df}");
    assert!(dp < 1e-3, "{dp}");
}
