//! The ANCF cable element (`element.type = 2`) in the planar beam scenes: the static cantilever
//! against the inextensible elastica (integrated here, and Mattiasson 1981's tables), the simply
//! supported beam against Euler–Bernoulli beam theory, the motion port of `cantilever_motion`
//! against the tip stiffness `3EI/L³`, the pendulum's convergence against its own fine mesh,
//! and the scene keys.

mod common;
use common::*;
use flexfmu::scene::Scene;
use flexfmu::variables::Value;

const E: f64 = 2.07e11;
/// Width of the shipped scenes [m].
const W: f64 = 0.1;

fn cable(n: i32) -> Vec<(&'static str, Value)> {
    vec![
        ("element.type", Value::Integer(2)),
        ("mesh.n_elements", Value::Integer(n)),
    ]
}

/// `EI = E w h³/12` [N m²].
fn ei(h: f64) -> f64 {
    E * W * h.powi(3) / 12.0
}

/// The inextensible elastica of a cantilever of length 1 clamped along +x with a dead end load
/// of dimensionless magnitude `k = P L²/EI` along −y: tip position `(x, y)/L`. Shooting on
/// the root curvature: `θ' = κ`, `κ' = k cos θ`, `x' = cos θ`, `y' = sin θ` with `θ(0) = 0`
/// and `κ(1) = 0` (the moment vanishes at the free end), classical RK4 with 4000 steps,
/// bisection on `κ(0) ∈ [−k, 0]`.
fn elastica_tip(k: f64) -> (f64, f64) {
    let run = |k0: f64| {
        let n = 4000;
        let h = 1.0 / n as f64;
        let f = |s: [f64; 4]| [s[1], k * s[0].cos(), s[0].cos(), s[0].sin()];
        let mut s = [0.0, k0, 0.0, 0.0];
        for _ in 0..n {
            let a = f(s);
            let b = f(std::array::from_fn(|i| s[i] + 0.5 * h * a[i]));
            let c = f(std::array::from_fn(|i| s[i] + 0.5 * h * b[i]));
            let d = f(std::array::from_fn(|i| s[i] + h * c[i]));
            s = std::array::from_fn(|i| s[i] + h / 6.0 * (a[i] + 2.0 * b[i] + 2.0 * c[i] + d[i]));
        }
        s
    };
    let (mut lo, mut hi) = (-k, 0.0);
    // κ(1) increases with κ(0) on this bracket: negative at −k, positive at 0
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if run(mid)[1] < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let s = run(0.5 * (lo + hi));
    (s[2], s[3])
}

/// The elastica integrator reproduces Mattiasson's tabulated tip displacements (K. Mattiasson,
/// "Numerical results from large deflection beam and frame problems analysed by means of
/// elliptic integrals", Int. J. Numer. Meth. Engng 17 (1981) 145–153, Table 1: cantilever with
/// an end load, `PL²/EI` = 1, 2, 10: vertical tip deflection `v/L` and horizontal `u/L`).
#[test]
fn elastica_reference_matches_mattiasson_1981() {
    for (k, v, u) in [
        (1.0, 0.30172, 0.05643),
        (2.0, 0.49346, 0.16064),
        (10.0, 0.81061, 0.55500),
    ] {
        let (x, y) = elastica_tip(k);
        println!("k = {k}: v/L = {:.5}, u/L = {:.5}", -y, 1.0 - x);
        assert!((-y - v).abs() <= 1e-5, "k = {k}: v/L = {} vs {v}", -y);
        assert!(
            (1.0 - x - u).abs() <= 1e-5,
            "k = {k}: u/L = {} vs {u}",
            1.0 - x
        );
    }
}

/// Static cantilever (`cantilever.toml` with the cable, slender: h = 0.01 m so that the axial
/// stretch, which the elastica neglects, stays below 3e-5) under end loads up to
/// `PL²/EI = 10`: the tip within 3e-4 L of the elastica with 16 elements (measured 4e-6 to
/// 1.8e-4), and the error falls by more than 8 from 8 to 16 elements (measured 13 to 50).
#[test]
fn cable_cantilever_matches_the_elastica() {
    let sc = scene("cantilever");
    let (h, l) = (0.01, 2.0);
    for k in [1.0, 2.0, 10.0] {
        let (xr, yr) = elastica_tip(k);
        let mut errs = vec![];
        for n in [4, 8, 16] {
            let mut ov = cable(n);
            ov.extend([
                ("geometry.height", Value::Real(h)),
                ("solver.static_equilibrium", Value::Boolean(true)),
                ("solver.load_steps", Value::Integer(10)),
                ("load.fy", Value::Real(-k * ei(h) / (l * l))),
            ]);
            let sim = simulation(&sc, &ov).unwrap();
            let (x, y) = (output(&sc, &sim, "tip.x"), output(&sc, &sim, "tip.y"));
            let err = (x / l - xr).hypot(y / l - yr);
            println!(
                "k = {k:4}, n = {n:2}: tip/L = ({:.6}, {:.6}), elastica ({xr:.6}, {yr:.6}), error {err:.2e}",
                x / l,
                y / l
            );
            errs.push(err);
        }
        assert!(errs[2] <= 3e-4, "k = {k}: {errs:?}");
        assert!(
            errs[1] / errs[2] > 8.0,
            "k = {k}: slow convergence {errs:?}"
        );
    }
}

/// Simply supported beam (`simply_supported.toml`, cable), small mid-span load: the mid-span
/// deflection is Euler–Bernoulli's `PL³/(48 EI)` (no shear), which the cubic element
/// represents exactly when the load sits on a node, so to 1e-4 from 2 elements on.
#[test]
fn cable_simply_supported_matches_beam_theory() {
    let sc = scene("simply_supported");
    let (h, l, p): (f64, f64, f64) = (0.1, 2.0, -1000.0);
    let exact = p * l.powi(3) / (48.0 * ei(h));
    for n in [2, 4, 8] {
        let mut ov = cable(n);
        ov.extend([
            ("solver.static_equilibrium", Value::Boolean(true)),
            ("load.fy", Value::Real(p)),
        ]);
        let sim = simulation(&sc, &ov).unwrap();
        let y = output(&sc, &sim, "mid.y");
        println!("n = {n}: {y:.6e} m, PL^3/(48 EI) = {exact:.6e} m");
        assert!((y / exact - 1.0).abs() <= 1e-4, "n = {n}: {y} vs {exact}");
    }
}

/// `cantilever_motion.toml` with the cable: the tip moved statically by δ (small) gives the
/// reaction `−3EI δ/L³` (Euler–Bernoulli tip stiffness; the beam pushes the driver back).
#[test]
fn cable_motion_port_gives_the_tip_stiffness() {
    let sc = scene("cantilever_motion");
    let (h, l, d): (f64, f64, f64) = (0.1, 2.0, 1e-4);
    let expect = -3.0 * ei(h) * d / l.powi(3);
    let mut ov = cable(4);
    ov.extend([
        ("solver.static_equilibrium", Value::Boolean(true)),
        ("tip.y", Value::Real(d)),
    ]);
    let sim = simulation(&sc, &ov).unwrap();
    let f = output(&sc, &sim, "tip.fy");
    let mid = output(&sc, &sim, "mid.y");
    println!("tip.fy = {f:.6} N, -3 EI d / L^3 = {expect:.6} N; mid.y = {mid:.4e}");
    assert!((f / expect - 1.0).abs() <= 1e-3, "{f} vs {expect}");
    // the mid-span deflection of the same beam: δ (3 (L/2)² L − (L/2)³)/(2 L³) = 5δ/16
    assert!((mid / (5.0 * d / 16.0) - 1.0).abs() <= 1e-3, "{mid}");
}

/// Largest tip distance [m] between two runs sampled at the same times.
fn max_distance(a: &[(f64, f64)], b: &[(f64, f64)]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p.0 - q.0).hypot(p.1 - q.1))
        .fold(0.0, f64::max)
}

/// Tip trajectory of the pendulum with the cable over 1 s, sampled every 10 ms.
fn pendulum_tip(n: i32, h: f64) -> Vec<(f64, f64)> {
    let sc = scene("pendulum");
    let mut ov = cable(n);
    ov.push(("solver.max_step", Value::Real(h)));
    let mut sim = simulation(&sc, &ov).unwrap();
    let mut out = vec![];
    for k in 1..=100 {
        sim.advance(k as f64 * 1e-2).unwrap();
        out.push((output(&sc, &sim, "tip.x"), output(&sc, &sim, "tip.y")));
    }
    out
}

/// The soft pendulum (`pendulum.toml`) with the cubic cable: 8 elements within 1e-3 m of 64 over
/// the whole second (measured 3.9e-4 m; issue 15: the seed-000 element needs about 64 for that),
/// and the error of 4, 8, 16 elements against 64 falls by more than the second order's factor 4
/// per halving (measured 5.6 and 8.2; same internal step 1e-3 s: the spatial error only).
#[test]
fn cable_pendulum_converges_faster_than_second_order() {
    let fine = pendulum_tip(64, 1e-3);
    let errs: Vec<f64> = [4, 8, 16]
        .iter()
        .map(|&n| max_distance(&pendulum_tip(n, 1e-3), &fine))
        .collect();
    println!(
        "errors against 64 elements: 4: {:.2e}, 8: {:.2e}, 16: {:.2e}",
        errs[0], errs[1], errs[2]
    );
    assert!(errs[1] <= 1e-3, "{errs:?}");
    assert!(
        errs[0] / errs[1] > 4.0 && errs[1] / errs[2] > 4.0,
        "{errs:?}"
    );
    // it falls and hangs: the tip went below the pin by more than half the length
    assert!(fine.iter().any(|p| p.1 < -1.0));
}

/// Scene keys: `type = "ancf_cable_2d"` sets the start value of `element.type` to 2; the
/// seed-000 options are refused with the cable, naming the key; an unknown type names the key.
#[test]
fn cable_scene_keys() {
    let text = std::fs::read_to_string(scene_path("cantilever")).unwrap();
    let cable_text = with(&text, "type", "\"ancf_cable_2d\"");
    let refused = Scene::from_toml(&cable_text)
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(refused.contains("element.shear_rule"), "{refused}");
    assert!(refused.contains("element.strain_energy"), "{refused}");
    let ok_text: String = cable_text
        .lines()
        .filter(|l| !l.starts_with("shear_rule") && !l.starts_with("strain_energy"))
        .collect::<Vec<_>>()
        .join("\n");
    let sc = Scene::from_toml(&ok_text).unwrap();
    let p = sc.params.iter().find(|p| p.name == "element.type").unwrap();
    assert_eq!(p.start, Value::Integer(2));
    let bad_text = format!(
        "kind = \"beam_2d\"\n{}",
        with(&text, "type", "\"ancf_cable_3d\"")
    );
    let bad = Scene::from_toml(&bad_text)
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(
        bad.contains("type") && bad.contains("ancf_cable_2d"),
        "{bad}"
    );
    // a clamp of the cable needs the axis along x or y
    let tilted = with(&ok_text, "height", "0.1\nangle_deg = 30.0");
    let sc = Scene::from_toml(&tilted).unwrap();
    let err = simulation(&sc, &[]).map(|_| ()).unwrap_err();
    assert!(
        err.contains("supports[0]") && err.contains("angle_deg"),
        "{err}"
    );
}
