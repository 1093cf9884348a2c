//! The static benchmarks of Kerkkänen, Sopanen & Mikkola 2003 (seed 000), proposed-element
//! columns, reproduced to the printed digits. Values as tabulated in
//! `shared/reference/seed000-ancf-shear-beam.md` A.9.

mod common;
use common::*;
use flexfmu::variables::Value;

fn static_run(
    scene_name: &str,
    n: i32,
    nu: f64,
    rule: i32,
    extra: &[(&str, Value)],
) -> Result<(f64, f64), String> {
    let sc = scene(scene_name);
    let mut ov = vec![
        ("mesh.n_elements", Value::Integer(n)),
        ("material.nu", Value::Real(nu)),
        ("element.shear_rule", Value::Integer(rule)),
        ("solver.static_equilibrium", Value::Boolean(true)),
    ];
    ov.extend_from_slice(extra);
    let sim = simulation(&sc, &ov)?;
    let p = if scene_name == "simply_supported" {
        "mid"
    } else {
        "tip"
    };
    Ok((
        output(&sc, &sim, &format!("{p}.x")),
        output(&sc, &sim, &format!("{p}.y")),
    ))
}

/// Round to `digits` decimals (the printed precision).
fn printed(v: f64, digits: i32) -> f64 {
    let s = 10f64.powi(digits);
    (v * s).round() / s
}

/// Tables 1 and 2: simply supported beam, 1000 N at mid-span, mid-point deflection [mm],
/// proposed element (original 1x1 shear rule), nu = 0 and nu = 0.3.
#[test]
fn table_1_and_2_simply_supported() {
    let table: [(i32, f64, f64); 6] = [
        (2, -0.07304348, -0.07321739),
        (4, -0.09115942, -0.09133333),
        (8, -0.09568840, -0.09586232),
        (16, -0.09682065, -0.09699456),
        (32, -0.09710371, -0.09727763),
        (64, -0.09717448, -0.09734839),
    ];
    for (n, nu0, nu3) in table {
        for (nu, expect) in [(0.0, nu0), (0.3, nu3)] {
            let (_, y) = static_run(
                "simply_supported",
                n,
                nu,
                1,
                &[("load.fy", Value::Real(-1000.0))],
            )
            .unwrap();
            let mm = y * 1e3;
            println!("n = {n:2} nu = {nu}: {mm:.8} mm (paper {expect:.8})");
            assert_eq!(printed(mm, 8), expect, "n = {n}, nu = {nu}: {mm:.10} mm");
        }
    }
}

/// Table 3: cantilever (Model 1, h = 0.1 m, nu = 0.3), tip force -5e5 N, proposed element with
/// the original 1x1 shear rule, tip position (x, y) [m].
#[test]
fn table_3_cantilever_large_deflection() {
    let table: [(i32, f64, f64); 6] = [
        (2, 1.93097, -0.47477),
        (4, 1.86837, -0.64974),
        (8, 1.85667, -0.67758),
        (16, 1.85526, -0.68046),
        (32, 1.85497, -0.68100),
        (64, 1.85489, -0.68114),
    ];
    for (n, ex, ey) in table {
        let (x, y) =
            static_run("cantilever", n, 0.3, 1, &[("load.fy", Value::Real(-5e5))]).unwrap();
        println!("n = {n:2}: ({x:.6}, {y:.6}) (paper {ex}, {ey})");
        assert_eq!(
            (printed(x, 5), printed(y, 5)),
            (ex, ey),
            "n = {n}: ({x:.7}, {y:.7})"
        );
    }
}

/// Table 6: axial cantilever (pinned at x = 0), 50 kN at the free end, elongation 0.048307 mm
/// for nu = 0 and 0.3 and any element count (nonlinear Green–Lagrange solution).
#[test]
fn table_6_axial_elongation() {
    for n in [2, 16, 64] {
        for nu in [0.0, 0.3] {
            let (x, _) =
                static_run("cantilever", n, nu, 1, &[("load.fx", Value::Real(5e4))]).unwrap();
            let mm = (x - 2.0) * 1e3;
            assert_eq!(printed(mm, 6), 0.048307, "n = {n}, nu = {nu}: {mm:.8} mm");
        }
    }
}

/// Tables 4 and 5, Model 2 (deep beam: h = 0.5 m, b = 0.1 m, nu = 0, F = -5e8 h^3 =
/// -6.25e7 N), tip position (x, y) [m] of the proposed element.
///
/// Table 4 (original 1x1 shear rule): the paper reports "No convergence" for 32 and 64
/// elements; our static solve must fail there with an error, not return a spurious branch.
/// One printed digit differs by one unit (16 elements, y: paper -0.71123, ours -0.7112375),
/// which the reference's independent check also found; it is allowed here and only there.
/// Table 5 (the 1x2 fix): all entries to the printed digits.
#[test]
fn tables_4_and_5_deep_beam_shear_rules() {
    let deep = [
        ("geometry.height", Value::Real(0.5)),
        ("load.fy", Value::Real(-5e8 * 0.5f64.powi(3))),
    ];
    let table4: [(i32, Option<(f64, f64)>); 6] = [
        (2, Some((1.87049, -0.65646))),
        (4, Some((1.84801, -0.70045))),
        (8, Some((1.84334, -0.70883))),
        (16, Some((1.84204, -0.71123))),
        (32, None),
        (64, None),
    ];
    for (n, expect) in table4 {
        let r = static_run("cantilever", n, 0.0, 1, &deep);
        match (expect, r) {
            (Some((ex, ey)), Ok((x, y))) => {
                let tol_y = if n == 16 { 1.01e-5 } else { 0.0 };
                assert_eq!(printed(x, 5), ex, "Table 4, n = {n}: x = {x:.7}");
                assert!(
                    (printed(y, 5) - ey).abs() <= tol_y + 1e-12,
                    "Table 4, n = {n}: y = {y:.7}"
                );
            }
            (None, Err(msg)) => {
                assert!(msg.contains("static equilibrium not found"), "{msg}");
            }
            (e, r) => panic!("Table 4, n = {n}: expected {e:?}, got {r:?}"),
        }
    }
    let table5: [(i32, f64, f64); 6] = [
        (2, 1.87066, -0.65601),
        (4, 1.84801, -0.70045),
        (8, 1.84343, -0.70861),
        (16, 1.84228, -0.71066),
        (32, 1.84198, -0.71119),
        (64, 1.84191, -0.71133),
    ];
    for (n, ex, ey) in table5 {
        let (x, y) = static_run("cantilever", n, 0.0, 2, &deep).unwrap();
        assert_eq!(
            (printed(x, 5), printed(y, 5)),
            (ex, ey),
            "Table 5, n = {n}: ({x:.7}, {y:.7})"
        );
    }
}
