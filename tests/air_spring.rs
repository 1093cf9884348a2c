//! The air spring at the membrane level (`model.fidelity = 2`) against the independent
//! shooting solution of the axisymmetric membrane equations (`scripts/air_spring_reference.py`,
//! curves in `tests/data/air_spring_reference.toml`), the exact membrane identities of
//! `shared/reference/air-spring-physics.md` §0, and the gas.

mod common;

use common::{floats, output, simulation, with};
use flexfmu::kinds::air_spring::AirSpringScene;
use flexfmu::kinds::air_spring::model::AirSpring;
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::variables::Value;

fn reference() -> toml::Table {
    common::data_toml("air_spring_reference.toml")
}

fn axisym_text() -> String {
    std::fs::read_to_string(common::scene_path("air_spring_axisym")).unwrap()
}

fn build(text: &str) -> AirSpring {
    let scene = Scene::from_toml(text).unwrap();
    let tables: &AirSpringScene = scene.tables().unwrap();
    AirSpring::build(tables, &ParamValues::defaults(&scene.params)).unwrap()
}

/// Radius where the meridian's tangent is horizontal (bottom of the lobe), from the lowest
/// node and a parabola through it and its neighbours.
fn horizontal_tangent_radius(m: &AirSpring) -> f64 {
    let pts = m.meridian();
    let k = (1..pts.len() - 1)
        .min_by(|&a, &b| pts[a][1].total_cmp(&pts[b][1]))
        .unwrap();
    // parabola z(r) through the three points around the minimum... the lobe bottom is
    // where dz/ds = 0: fit z(s) with s = node index
    let (z0, z1, z2) = (pts[k - 1][1], pts[k][1], pts[k + 1][1]);
    let s = 0.5 * (z0 - z2) / (z0 - 2.0 * z1 + z2);
    let (r0, r1, r2) = (pts[k - 1][0], pts[k][0], pts[k + 1][0]);
    // r(s) through the same three points
    r1 + 0.5 * s * (r2 - r0) + 0.5 * s * s * (r0 - 2.0 * r1 + r2)
}

/// The design state (5 bar at 0.25 m) of the reference spring: force and volume against the
/// shooting solution (F = 21533.04 N, V = 8.456949 L, the figures) converge with the
/// mesh, and the effective area equals π r_h² of the lobe bottom.
#[test]
fn design_state_converges_to_the_shooting_solution() {
    let r = reference();
    let d = &r["design"];
    let (f_ref, v_ref) = (d["F"].as_float().unwrap(), d["V"].as_float().unwrap());
    let mut errors = vec![];
    for n in [30, 60, 120, 240] {
        let m = build(&with(&axisym_text(), "n_meridional", &n.to_string()));
        let f = m.committed_force();
        let v = m.gas().committed().volume;
        let rh = horizontal_tangent_radius(&m);
        let ae = f / 5e5;
        println!(
            "n = {n:3}: F = {f:.3} N ({:+.2e}), V = {:.6} L ({:+.2e}), A_e/(pi r_h^2) - 1 = {:+.2e}",
            f / f_ref - 1.0,
            v * 1e3,
            v / v_ref - 1.0,
            ae / (std::f64::consts::PI * rh * rh) - 1.0
        );
        errors.push(((f / f_ref - 1.0).abs(), (v / v_ref - 1.0).abs()));
        if n >= 120 {
            assert!((ae / (std::f64::consts::PI * rh * rh) - 1.0).abs() < 1e-3);
        }
    }
    assert!(
        errors[1].0 < 2e-3 && errors[1].1 < 2e-3,
        "n = 60: {:?}",
        errors[1]
    );
    assert!(
        errors[3].0 < 1e-4 && errors[3].1 < 1e-4,
        "n = 240: {:?}",
        errors[3]
    );
}

/// The constant-pressure characteristic F(h), V(h) at 3, 5 and 7 bar over the stroke
/// 0.20–0.30 m, and a second spring (spring B of the reference: other piston, bead, sleeve,
/// cords) at 4 bar, against the shooting solution.
#[test]
fn constant_pressure_characteristics_match_the_shooting_solution() {
    let r = reference();
    for c in r["constant_pressure"].as_array().unwrap() {
        let spring = c["spring"].as_str().unwrap();
        let p = floats(c, "p_gauge")[0];
        let mut text = with(&axisym_text(), "n_meridional", "120");
        text = with(&text, "pressure_design", &format!("{p:e}"));
        if spring == "B" {
            for (k, v) in [
                ("radius", "0.09"),
                ("height", "0.12"),
                ("bead_radius", "0.13"),
                ("sleeve_radius", "0.115"),
                ("sleeve_length", "0.26"),
                ("cord_angle", "50.0"),
                ("cord_stiffness", "1.0e6"),
                ("matrix_stiffness", "3.0e4"),
            ] {
                text = with(&text, k, v);
            }
        }
        let mut m = build(&text);
        let (hs, fs, vs) = (floats(c, "h"), floats(c, "F"), floats(c, "V"));
        let mut worst: f64 = 0.0;
        for i in 0..hs.len() {
            if spring == "B" && hs[i] > 0.275 {
                // the lobe rolls off the piston top: not a rolling lobe any more
                continue;
            }
            let (f, v) = m.equilibrium_at(hs[i], p).unwrap();
            let (ef, ev) = (f / fs[i] - 1.0, v / vs[i] - 1.0);
            println!("  h = {:.2}: F {ef:+.2e}, V {ev:+.2e}", hs[i]);
            worst = worst.max(ef.abs()).max(ev.abs());
        }
        println!("spring {spring} at {p:.0} Pa: worst relative error of F, V {worst:.2e}");
        assert!(worst < 1e-3, "spring {spring}, {p} Pa: {worst}");
    }
}

/// Fixed gas mass (polytropic n = 1.4 and 1.0 from the design state): the static solve at
/// initialization moves the plate to `top.z`; force and pressure against the shooting solution
/// of the closed spring, and the stiffness output against the exact identity
/// `k = n p_abs A_e A_v / V − p_g dA_e/dh` (reference `k`).
#[test]
fn closed_gas_characteristic_and_stiffness() {
    let r = reference();
    let scene = Scene::from_toml(&with(&axisym_text(), "n_meridional", "120")).unwrap();
    for c in r["closed"].as_array().unwrap() {
        if c["spring"].as_str().unwrap() != "default" {
            continue;
        }
        let n = c["n"].as_float().unwrap();
        let (hs, fs, ks, ps) = (
            floats(c, "h"),
            floats(c, "F"),
            floats(c, "k"),
            floats(c, "p_gauge"),
        );
        for i in (0..hs.len()).step_by(2) {
            let sim = simulation(
                &scene,
                &[
                    ("gas.polytropic_exponent", Value::Real(n)),
                    ("top.z", Value::Real(hs[i])),
                ],
            )
            .unwrap();
            let f = output(&scene, &sim, "top.fz");
            let p = output(&scene, &sim, "gas.pressure_gauge");
            let k = output(&scene, &sim, "spring.stiffness");
            println!(
                "n = {n}, h = {:.2}: F {:+.2e}, p {:+.2e}, k {:.1} vs {:.1} ({:+.2e})",
                hs[i],
                f / fs[i] - 1.0,
                p / ps[i] - 1.0,
                k,
                ks[i],
                k / ks[i] - 1.0
            );
            assert!((f / fs[i] - 1.0).abs() < 2e-3);
            assert!((p / ps[i] - 1.0).abs() < 2e-3);
            // the discrete characteristic ripples as nodes peel off the piston (linear
            // elements, the departure jumps from node to node): its pointwise slope is within
            // 2.6 % at these heights at 120 elements of the graded mesh (4.2 % uniform;
            // 2.8 % every 0.5 mm, `stiffness_ripple_table`)
            assert!((k / ks[i] - 1.0).abs() < 5e-2);
        }
    }
}

/// `spring.stiffness` (the static condensation) is the derivative of the model's own force:
/// central differences of `top.fz` over two static solves at ±0.01 mm (the discrete
/// characteristic has kinks where a node rolls onto the piston, so the difference must be
/// local).
#[test]
fn stiffness_is_the_derivative_of_the_force() {
    let scene = Scene::from_toml(&with(&axisym_text(), "n_meridional", "60")).unwrap();
    let at = |h: f64| {
        let sim = simulation(&scene, &[("top.z", Value::Real(h))]).unwrap();
        (
            output(&scene, &sim, "top.fz"),
            output(&scene, &sim, "spring.stiffness"),
            output(&scene, &sim, "gas.volume"),
            output(&scene, &sim, "spring.volumetric_area"),
        )
    };
    for h in [0.22, 0.27] {
        let dh = 1e-5;
        let (fp, _, vp, _) = at(h + dh);
        let (fm, _, vm, _) = at(h - dh);
        let (_, k, _, av) = at(h);
        let k_fd = -(fp - fm) / (2.0 * dh);
        let av_fd = (vp - vm) / (2.0 * dh);
        println!("h = {h}: k {k:.2} vs {k_fd:.2}, A_v {av:.6} vs {av_fd:.6}");
        assert!((k / k_fd - 1.0).abs() < 1e-4);
        assert!((av / av_fd - 1.0).abs() < 1e-4);
    }
}

/// The shipped level-3 scene is what `flexfmu air-spring-table scenes/air_spring_axisym.toml
/// --heights 0.18:0.32:29 --elements 240 --name air_spring_table` generates.
#[test]
fn shipped_table_is_regenerated() {
    let hs: Vec<f64> = (0..29).map(|k| 0.18 + 0.14 * k as f64 / 28.0).collect();
    let text = flexfmu::kinds::air_spring::table::generate(
        &axisym_text(),
        &hs,
        None,
        Some(240),
        "air_spring_table",
        &mut |_, _| {},
    )
    .unwrap();
    let shipped = std::fs::read_to_string(common::scene_path("air_spring_table")).unwrap();
    assert!(
        text == shipped,
        "scenes/air_spring_table.toml is stale: regenerate it with `flexfmu air-spring-table scenes/air_spring_axisym.toml -o scenes/air_spring_table.toml --heights 0.18:0.32:29 --elements 240 --name air_spring_table`"
    );
}

/// Level 3 (the table at 5 bar from the membrane level) with the gas at constant mass against
/// the shooting solution of the closed spring (n = 1.4): the table misses the pressure
/// dependence of the shape beyond its linear compliance, so its error grows away from the
/// design state; the table's force and stiffness over the stroke, and its stiffness is the
/// derivative of its force.
#[test]
fn table_level_over_the_stroke() {
    let r = reference();
    let scene = common::scene("air_spring_table");
    let c = r["closed"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["spring"].as_str() == Some("default") && c["n"].as_float() == Some(1.4))
        .unwrap();
    let (hs, fs, ks) = (floats(c, "h"), floats(c, "F"), floats(c, "k"));
    let (mut worst, mut worst_k): (f64, f64) = (0.0, 0.0);
    for i in 0..hs.len() {
        let sim = simulation(&scene, &[("top.z", Value::Real(hs[i]))]).unwrap();
        let f = output(&scene, &sim, "top.fz");
        let k = output(&scene, &sim, "spring.stiffness");
        println!(
            "h = {:.2}: F {:+.2e}, k {:+.2e}",
            hs[i],
            f / fs[i] - 1.0,
            k / ks[i] - 1.0
        );
        worst = worst.max((f / fs[i] - 1.0).abs());
        if (hs[i] - 0.25).abs() < 1e-9 {
            assert!((f / fs[i] - 1.0).abs() < 1e-4, "design state");
        }
        worst_k = worst_k.max((k / ks[i] - 1.0).abs());
    }
    println!(
        "worst error of the table over the stroke: force {worst:.2e}, stiffness {worst_k:.2e}"
    );
    // measured: 7.3e-3 at h = 0.20 m (the table's shape is the one at 5 bar; at 0.20 m the
    // closed gas is at 6.4 bar), 5.5e-7 at the design height
    assert!(worst < 1e-2);
    assert!(worst_k < 5e-2);
    // the stiffness output is the derivative of the force
    let at = |h: f64| {
        let sim = simulation(&scene, &[("top.z", Value::Real(h))]).unwrap();
        (
            output(&scene, &sim, "top.fz"),
            output(&scene, &sim, "spring.stiffness"),
        )
    };
    let dh = 1e-5;
    let k_fd = -(at(0.23 + dh).0 - at(0.23 - dh).0) / (2.0 * dh);
    let k = at(0.23).1;
    assert!((k / k_fd - 1.0).abs() < 1e-5, "{k} vs {k_fd}");
}

/// `spring.stiffness` is the instantaneous stiffness at every level: the gas compressed at its
/// current state, without time for heat exchange or orifice flow (what `d top.fz / d top.z`
/// means at a communication point). With the energy law it is therefore the adiabatic value
/// whatever `gas.heat_transfer`, and with a reservoir the bag's alone, at both levels (until
/// session 31 level 3 reported the response over one step instead: isothermal with a large heat
/// transfer, and the bag in equilibrium with the reservoir at rest).
#[test]
fn stiffness_is_instantaneous_at_levels_2_and_3() {
    let table = std::fs::read_to_string(common::scene_path("air_spring_table")).unwrap();
    let reservoir = std::fs::read_to_string(common::scene_path("air_spring_reservoir")).unwrap();
    // the table scene with the reservoir scene's reservoir, orifice and pipe
    let section = |name: &str| {
        let start = reservoir.find(&format!("[{name}]")).unwrap();
        let end = reservoir[start + 1..]
            .find("\n[")
            .map_or(reservoir.len(), |e| start + 1 + e);
        reservoir[start..end].to_string()
    };
    let table_reservoir = format!(
        "{table}\n{}\n{}\n{}\n",
        section("reservoir"),
        section("orifice"),
        section("pipe")
    );
    // stiffness after 5 steps of 1 ms at rest at the design height
    let stiffness = |text: &str, overrides: &[(&str, Value)]| {
        let scene = Scene::from_toml(text).unwrap();
        let mut sim = simulation(&scene, overrides).unwrap();
        let k0 = output(&scene, &sim, "spring.stiffness");
        for k in 1..=5 {
            sim.advance(k as f64 * 1e-3).unwrap();
        }
        (k0, output(&scene, &sim, "spring.stiffness"))
    };
    let energy = |h: f64| {
        vec![
            ("gas.model", Value::Integer(2)),
            ("gas.heat_transfer", Value::Real(h)),
        ]
    };
    // At rest at the design state the gas is at the design temperature, so the adiabatic
    // stiffness is the polytropic one with n = γ = 1.4, and the bag's alone is the closed bag's.
    for (level, closed, with_reservoir) in [
        (2, axisym_text(), reservoir.clone()),
        (3, table.clone(), table_reservoir.clone()),
    ] {
        let polytropic = stiffness(&closed, &[]).1;
        for h in [0.0, 5.0, 1e6] {
            let (k_start, k) = stiffness(&closed, &energy(h));
            println!(
                "level {level}, energy law, heat transfer {h:e} W/K: {k_start:.1} -> {k:.1} N/m (polytropic 1.4: {polytropic:.1})"
            );
            for k in [k_start, k] {
                assert!((k / polytropic - 1.0).abs() < 1e-9, "level {level}: {k}");
            }
        }
        let (k_start, k) = stiffness(&with_reservoir, &[]);
        println!(
            "level {level}, 20 L reservoir: {k_start:.1} -> {k:.1} N/m (closed bag: {polytropic:.1})"
        );
        for k in [k_start, k] {
            assert!((k / polytropic - 1.0).abs() < 1e-9, "level {level}: {k}");
        }
    }
}

/// A contoured piston widening downwards (radius 0.110 m at the base, 0.100 m at the top):
/// as the spring is compressed the lobe rolls onto the wider part and the effective area grows
/// (a progressive spring, `shared/reference/air-spring-physics.md` §1.1), while the exact
/// identity A_e = π r_h² still holds.
#[test]
fn contoured_piston_makes_the_effective_area_grow_with_compression() {
    let text = axisym_text().replace(
        "height = 0.15           # m, top above the piston base",
        "height = 0.15           # m, top above the piston base\ncontour = [[0.110, 0.0], [0.100, 0.15]]",
    );
    let text = with(&text, "n_meridional", "120");
    assert!(text.contains("contour"));
    let mut m = build(&text);
    let mut areas = vec![];
    for h in [0.27, 0.25, 0.23, 0.21] {
        let (f, _) = m.equilibrium_at(h, 5e5).unwrap();
        let rh = horizontal_tangent_radius(&m);
        let ae = f / 5e5;
        println!(
            "h = {h}: A_e = {ae:.6} m2, r_h = {rh:.5} m, A_e/(pi r_h^2) - 1 = {:+.2e}",
            ae / (std::f64::consts::PI * rh * rh) - 1.0
        );
        assert!((ae / (std::f64::consts::PI * rh * rh) - 1.0).abs() < 2e-3);
        areas.push(ae);
    }
    assert!(areas.windows(2).all(|w| w[1] > w[0]), "{areas:?}");
}

/// The energy law of the gas through the membrane level: with `gas.heat_transfer` = 0 it is the
/// adiabatic law (the polytropic law with n = γ = 1.4, same force along a sine of the plate to
/// 1e-9), and with a large heat transfer it follows the isothermal law (n = 1) in a slow
/// motion; the temperature rises under adiabatic compression as T V^(γ−1) = const.
#[test]
fn energy_law_reduces_to_adiabatic_and_isothermal() {
    let scene = Scene::from_toml(&axisym_text()).unwrap();
    let run = |overrides: &[(&str, Value)], freq: f64, amp: f64| {
        let mut sim = simulation(&scene, overrides).unwrap();
        let iz = common::input_index(&scene, "top.z");
        let iv = common::input_index(&scene, "top.vz");
        let w = 2.0 * std::f64::consts::PI * freq;
        let mut out = vec![];
        let n = (0.25 / freq / 1e-3).round() as usize; // a quarter period: compression
        for k in 0..n {
            let t = k as f64 * 1e-3;
            sim.set_input(iz, 0.25 - amp * (w * t).sin());
            sim.set_input(iv, -amp * w * (w * t).cos());
            sim.advance(t + 1e-3).unwrap();
            out.push((
                output(&scene, &sim, "top.fz"),
                output(&scene, &sim, "gas.temperature"),
                output(&scene, &sim, "gas.volume"),
            ));
        }
        out
    };
    let energy = |h: f64| {
        vec![
            ("gas.model", Value::Integer(2)),
            ("gas.heat_transfer", Value::Real(h)),
        ]
    };
    // adiabatic
    let a = run(&energy(0.0), 2.0, 0.02);
    let p = run(&[("gas.polytropic_exponent", Value::Real(1.4))], 2.0, 0.02);
    let worst = a
        .iter()
        .zip(&p)
        .map(|(x, y)| (x.0 / y.0 - 1.0).abs())
        .fold(0.0, f64::max);
    println!("energy law h = 0 against polytropic n = 1.4: worst force difference {worst:.2e}");
    assert!(worst < 1e-9);
    let (t0, v0) = (293.15, a[0].2);
    let (t1, v1) = (a.last().unwrap().1, a.last().unwrap().2);
    assert!(t1 > t0 + 5.0, "compression heats the gas: {t1} K");
    let inv = |t: f64, v: f64| t * v.powf(0.4);
    println!("T V^0.4: {:.6e} -> {:.6e}", inv(t0, v0), inv(t1, v1));
    // the first state is one step in: compare from there
    assert!((inv(a[0].1, a[0].2) / inv(t1, v1) - 1.0).abs() < 1e-9);
    // isothermal in a slow motion with a strong heat transfer
    let i = run(&energy(1e6), 0.05, 0.02);
    let p1 = run(&[("gas.polytropic_exponent", Value::Real(1.0))], 0.05, 0.02);
    let worst = i
        .iter()
        .zip(&p1)
        .map(|(x, y)| (x.0 / y.0 - 1.0).abs())
        .fold(0.0, f64::max);
    let t_dev = i.iter().map(|x| (x.1 - 293.15).abs()).fold(0.0, f64::max);
    println!(
        "energy law h = 1e6 W/K against polytropic n = 1: worst force difference {worst:.2e}, temperature within {t_dev:.2e} K"
    );
    assert!(worst < 1e-4);
    assert!(t_dev < 1e-2);
}

/// Bending of the wall (`bellows.bending_stiffness`, rotation-free hinges): the rubber's own
/// `E t³/12` (0.027 N m for the reference wall: E t = 2e4 N/m, t = 4 mm) changes the design
/// force of the membrane by a few 1e-4, and the change vanishes with the stiffness.
#[test]
fn bending_stiffness_is_a_small_perturbation_of_the_membrane() {
    let base = with(&axisym_text(), "n_meridional", "120");
    let f0 = build(&base).committed_force();
    let mut last = f64::INFINITY;
    for d in [2.7e-2, 2.7e-3, 2.7e-4] {
        let text = base.replace(
            "tension_only = false",
            &format!("tension_only = false\nbending_stiffness = {d:e}"),
        );
        let m = build(&text);
        let change = (m.committed_force() / f0 - 1.0).abs();
        println!("D = {d:e} N m: design force changes by {change:.2e}");
        assert!(change < 2e-3);
        assert!(change < last);
        last = change;
    }
}

/// Friction between sleeve and piston (`contact.mu`, level 2): over a slow ±30 mm cycle of the
/// closed spring (0.5 Hz) the lobe still rolls (the sleeve is laid down on the piston and
/// lifted off it without sticking: the force and the lobe radius stay those of the frictionless
/// spring), friction dissipates energy (a hysteresis: the dissipated energy grows over the
/// cycle), and the energy balance closes with the friction work in it: plate work = change of
/// (gas + strain + kinetic) + dissipated.
#[test]
fn friction_on_the_piston_lets_the_lobe_roll_and_dissipates() {
    let scene = Scene::from_toml(&axisym_text()).unwrap();
    let run = |mu: f64| {
        let mut sim = simulation(&scene, &[("contact.mu", Value::Real(mu))]).unwrap();
        let iz = common::input_index(&scene, "top.z");
        let iv = common::input_index(&scene, "top.vz");
        let (amp, w) = (0.03, std::f64::consts::PI);
        let drive = |t: f64| {
            vec![
                (iz, 0.25 - amp * (w * t).sin()),
                (iv, -amp * w * (w * t).cos()),
            ]
        };
        common::energy_run(
            &scene,
            &mut sim,
            2000,
            1e-3,
            drive,
            &["top.fz", "bellows.lobe_radius"],
        )
        .into_iter()
        .map(|(o, lost, num, work)| (o[0], o[1], lost, num, work))
        .collect::<Vec<_>>()
    };
    let free = run(0.0);
    let rough = run(0.5);
    let f_design = free[0].0;
    let df = free
        .iter()
        .zip(&rough)
        .map(|(a, b)| (a.0 - b.0).abs() / f_design)
        .fold(0.0, f64::max);
    let dr = free
        .iter()
        .zip(&rough)
        .map(|(a, b)| (a.1 - b.1).abs())
        .fold(0.0, f64::max);
    let lost = rough.last().unwrap().2 - free.last().unwrap().2;
    let scale = rough.iter().map(|x| x.4.abs()).fold(0.0, f64::max);
    let numerical = rough.iter().map(|x| x.3.abs()).fold(0.0, f64::max);
    println!(
        "mu = 0.5 against frictionless over the cycle: force within {df:.2e} of the design force, lobe radius within {dr:.2e} m; friction dissipated {lost:.4e} J; energy balance: numerical part {numerical:.2e} J of plate work up to {scale:.3} J"
    );
    assert!(df < 2e-2, "{df}");
    assert!(dr < 1e-3, "{dr}");
    assert!(lost > 0.0, "{lost}");
    assert!(numerical < 2e-3 * scale, "{numerical} of {scale}");
}

/// `contact.mu` is a parameter of the levels with contact (1 and 2): a table scene that sets
/// it is refused with a message naming it, a negative value is refused, and the table level
/// does not expose it.
#[test]
fn friction_is_refused_where_it_is_not_modelled() {
    let read = |name: &str| std::fs::read_to_string(common::scene_path(name)).unwrap();
    let mu = |text: &str, v: &str| text.replace("[contact]\n", &format!("[contact]\nmu = {v}\n"));
    for (text, what) in [
        (mu(&read("air_spring_table"), "0.3"), "level 3"),
        (mu(&axisym_text(), "-0.1"), "negative"),
    ] {
        assert!(text.contains("mu = "), "{what}: no [contact] table");
        let err = Scene::from_toml(&text)
            .err()
            .map(|e| e.0)
            .unwrap_or_default();
        assert!(err.contains("contact.mu"), "{what}: {err}");
    }
    for name in ["air_spring", "air_spring_axisym"] {
        let ok = Scene::from_toml(&mu(&read(name), "0.3")).unwrap();
        assert!(ok.params.iter().any(|p| p.name == "contact.mu"), "{name}");
    }
    let table = Scene::from_toml(&read("air_spring_table")).unwrap();
    assert!(!table.params.iter().any(|p| p.name == "contact.mu"));
}

/// Natural cubic spline through `(x, y)` evaluated at `t` (the reference's stiffness is smooth
/// in h: between its 10 mm samples a spline is good to about 1e-3).
fn spline(x: &[f64], y: &[f64], t: f64) -> f64 {
    let n = x.len();
    let mut m = vec![0.0; n];
    let (mut c, mut d) = (vec![0.0; n], vec![0.0; n]);
    for i in 1..n - 1 {
        let (h0, h1) = (x[i] - x[i - 1], x[i + 1] - x[i]);
        let a = h0;
        let b = 2.0 * (h0 + h1);
        let rhs = 6.0 * ((y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0);
        let den = b - a * c[i - 1];
        c[i] = h1 / den;
        d[i] = (rhs - a * d[i - 1]) / den;
    }
    for i in (1..n - 1).rev() {
        m[i] = d[i] - c[i] * m[i + 1];
    }
    let i = (0..n - 1).find(|&i| t <= x[i + 1]).unwrap_or(n - 2);
    let h = x[i + 1] - x[i];
    let (a, b) = ((x[i + 1] - t) / h, (t - x[i]) / h);
    a * y[i] + b * y[i + 1] + ((a * a * a - a) * m[i] + (b * b * b - b) * m[i + 1]) * h * h / 6.0
}

/// Exploration (issue 11, the stiffness ripple): the closed spring (n = 1.4) sampled every
/// 0.5 mm over h = 0.20–0.30 m; per height the errors of F and k against the shooting
/// solution (splined between its 10 mm samples), the node where the sleeve leaves the piston
/// (first node from the clamp off the contour) and how far it is off, the lobe's lowest node.
/// `RIPPLE_N` = the element counts (default 60,120). Run with `--ignored --nocapture`.
#[test]
#[ignore]
fn stiffness_ripple_table() {
    let r = reference();
    let c = r["closed"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["spring"].as_str() == Some("default") && c["n"].as_float() == Some(1.4))
        .unwrap()
        .clone();
    let (hs, fs, ks) = (floats(&c, "h"), floats(&c, "F"), floats(&c, "k"));
    let ns: Vec<usize> = std::env::var("RIPPLE_N")
        .unwrap_or("60,120".into())
        .split(',')
        .map(|s| s.parse().unwrap())
        .collect();
    let step: f64 = std::env::var("RIPPLE_STEP")
        .ok()
        .map_or(5e-4, |s| s.parse().unwrap());
    for n in ns {
        let scene =
            Scene::from_toml(&with(&axisym_text(), "n_meridional", &n.to_string())).unwrap();
        let (mut worst, mut worst_f, mut worst_k10): (f64, f64, f64) = (0.0, 0.0, 0.0);
        let m = (0.1 / step).round() as usize;
        for j in 0..=m {
            let h = 0.20 + 0.1 * j as f64 / m as f64;
            let sim = simulation(&scene, &[("top.z", Value::Real(h))]).unwrap();
            let f = output(&scene, &sim, "top.fz");
            let k = output(&scene, &sim, "spring.stiffness");
            let model = sim.model_as::<AirSpring>().unwrap();
            let pts = model.meridian();
            // from the clamp (last node) back while on the piston wall (r = 0.1)
            let mut d = pts.len() - 1;
            while d > 0 && (pts[d - 1][0] - 0.1).abs() < 1e-5 {
                d -= 1;
            }
            let low = (0..pts.len())
                .min_by(|&a, &b| pts[a][1].total_cmp(&pts[b][1]))
                .unwrap();
            let ek = k / spline(&hs, &ks, h) - 1.0;
            let ef = f / spline(&hs, &fs, h) - 1.0;
            worst = worst.max(ek.abs());
            worst_f = worst_f.max(ef.abs());
            if j % ((0.01 / step).round() as usize) == 0 {
                worst_k10 = worst_k10.max(ek.abs());
            }
            println!(
                "n {n} h {h:.4} F {ef:+.2e} k {ek:+.3e} landed {d} (z {:.5}, next off by {:.2e} at z {:.5}) low {low} (z {:.5}, r {:.5})",
                pts[d][1],
                pts[d - 1][0] - 0.1,
                pts[d - 1][1],
                pts[low][1],
                pts[low][0]
            );
        }
        println!(
            "n = {n}: worst k error {worst:.3e} (every 10 mm {worst_k10:.3e}), worst F error {worst_f:.2e}"
        );
    }
}
