//! Validation of the seed-004 trapezoidal shell (issue 10) on the shipped shell scenes and on
//! scenes derived from them, one quantity at a time, against the analytic and published
//! references of `common::shell_reference`: the simply supported square plate (Navier), the
//! clamped circular plate, the closed cylinder under pressure, the strip rolled up by an end
//! moment and the strip under end shear (elastica). Convergence tables are printed
//! (`cargo test --release --test shell_validation -- --nocapture`).

mod common;
use common::shell_reference as reference;
use common::*;
use flexfmu::scene::Scene;
use flexfmu::variables::Value;

/// Static solution of a scene with parameter and input overrides; the output values named.
fn statics(sc: &Scene, overrides: &[(&str, Value)], outputs: &[&str]) -> Vec<f64> {
    let mut all: Vec<(&str, Value)> = overrides.to_vec();
    all.push(("solver.static_equilibrium", Value::Boolean(true)));
    let sim = simulation(sc, &all).unwrap_or_else(|e| panic!("{overrides:?}: {e}"));
    outputs.iter().map(|o| output(sc, &sim, o)).collect()
}

/// Observed order of convergence from errors at meshes refined by 2.
fn orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

/// Prints a convergence table and returns the orders.
fn table(title: &str, sizes: &[i32], values: &[f64], exact: f64) -> (Vec<f64>, Vec<f64>) {
    let errors: Vec<f64> = values.iter().map(|v| (v / exact - 1.0).abs()).collect();
    let ord = orders(&errors);
    println!("{title} (reference {exact:.6e})");
    println!("| n | value | relative error | order |");
    println!("|---|---|---|---|");
    for (i, n) in sizes.iter().enumerate() {
        let o = if i == 0 {
            String::from("")
        } else {
            format!("{:.2}", ord[i - 1])
        };
        println!("| {n} | {:.6e} | {:.3e} | {o} |", values[i], errors[i]);
    }
    (errors, ord)
}

const PLATE: (f64, f64, f64, f64) = (2.1e11, 0.3, 7850.0, 0.01);

/// Simply supported square plate under a uniform pressure: centre deflection against the
/// Navier series `α q a⁴/D`, α = 0.00406235 (Timoshenko & Woinowsky-Krieger: 0.00406), on
/// n × n meshes, both bending variants. The load keeps the deflection below h/100 (linear).
/// V2 converges at second order. V1 does not converge to the plate solution: its products of
/// Hermite cubics have no twist function inside the element, so a twisting plate is too stiff
/// at every mesh (measured errors 11.7 %, 5.6 %, 4.2 % at n = 4, 8, 16); the paper's V1 is
/// kept selectable, and this test fails if that changes.
#[test]
fn simply_supported_plate_under_pressure_converges_to_navier() {
    let sc = scene("plate");
    let (e, nu, _, h) = PLATE;
    let d = reference::plate_rigidity(e, h, nu);
    let q = 200.0;
    let exact = reference::navier_uniform_deflection(1.0, 1.0, d, q, 0.5, 0.5);
    let sizes = [4, 8, 16];
    for bending in [2, 1] {
        let values: Vec<f64> = sizes
            .iter()
            .map(|&n| {
                statics(
                    &sc,
                    &[
                        ("load.pressure", Value::Real(q)),
                        ("mesh.n_x", Value::Integer(n)),
                        ("mesh.n_y", Value::Integer(n)),
                        ("element.bending", Value::Integer(bending)),
                    ],
                    &["centre.z"],
                )[0]
            })
            .collect();
        let (err, ord) = table(
            &format!("SS plate, uniform pressure, centre deflection, V{bending}"),
            &sizes,
            &values,
            exact,
        );
        if bending == 2 {
            assert!(err[2] < 0.005, "V2: {err:?}");
            assert!(ord[0] > 1.7 && ord[1] > 1.7, "V2: orders {ord:?}");
        } else {
            assert!(
                err[2] > 0.02 && ord[1] < 1.0,
                "V1 now converges: {err:?}, update the docs"
            );
        }
    }
}

/// Simply supported square plate under a central force: centre deflection against the Navier
/// series `α P a²/D`, α = 0.01160084 (Timoshenko: 0.01160).
#[test]
fn simply_supported_plate_under_a_point_load_converges_to_navier() {
    let sc = scene("plate");
    let (e, nu, _, h) = PLATE;
    let d = reference::plate_rigidity(e, h, nu);
    let p = 100.0;
    let exact = reference::navier_point_deflection(1.0, 1.0, d, p, 0.5, 0.5, 0.5, 0.5);
    let sizes = [4, 8, 16];
    let values: Vec<f64> = sizes
        .iter()
        .map(|&n| {
            statics(
                &sc,
                &[
                    ("load.fz", Value::Real(p)),
                    ("mesh.n_x", Value::Integer(n)),
                    ("mesh.n_y", Value::Integer(n)),
                ],
                &["centre.z"],
            )[0]
        })
        .collect();
    let (err, ord) = table(
        "SS plate, central force, centre deflection, V2",
        &sizes,
        &values,
        exact,
    );
    assert!(err[2] < 0.01, "{err:?}");
    assert!(ord[1] > 1.5, "orders {ord:?}");
}

/// The strip (L = 10, b = 1, h = 0.1, E = 1.2e6, ν = 0, EI = 100) rolled up by an end moment:
/// the tip against the exact circular arc (Sze, Liu & Lo 2004 roll-up benchmark), up to the
/// full ring `M = 2π EI/L` where the tip returns to the root.
#[test]
fn strip_rolls_up_into_a_ring() {
    let sc = scene("strip");
    let (l, ei) = (10.0, 100.0);
    let m_full = reference::rollup_full_ring_moment(l, ei);
    println!("| M/M_full | n_x | tip x | tip z | exact x | exact z | error / L |");
    println!("|---|---|---|---|---|---|---|");
    for n in [20, 40] {
        for frac in [0.25, 0.5, 1.0] {
            let m = frac * m_full;
            let v = statics(
                &sc,
                &[
                    ("load.my", Value::Real(-m)),
                    ("mesh.n_x", Value::Integer(n)),
                    ("solver.load_steps", Value::Integer((40.0 * frac) as i32)),
                ],
                &["tip.x", "tip.z"],
            );
            let (x, z) = reference::rollup_tip(l, ei, m);
            let err = ((v[0] - x).powi(2) + (v[1] - z).powi(2)).sqrt() / l;
            println!(
                "| {frac} | {n} | {:.5} | {:.5} | {x:.5} | {z:.5} | {err:.2e} |",
                v[0], v[1]
            );
            assert!(
                err < if n == 40 { 2e-3 } else { 8e-3 },
                "M/M_full = {frac}, n = {n}: {err}"
            );
        }
    }
}

/// The strip under an end shear force P (dead load along z) against the inextensible elastica
/// (Mattiasson 1981 tabulates the same exact solution) at k = PL²/EI = 1, 2, 4.
#[test]
fn strip_under_end_shear_follows_the_elastica() {
    let sc = scene("strip");
    let (l, ei) = (10.0, 100.0);
    println!("| k | n_x | -u/L | w/L | exact -u/L | exact w/L |");
    println!("|---|---|---|---|---|---|");
    for k in [1.0, 2.0, 4.0] {
        let p = k * ei / (l * l);
        let tip = reference::elastica_tip_shear(k);
        for n in [20, 40] {
            let v = statics(
                &sc,
                &[
                    ("load.fz", Value::Real(p)),
                    ("mesh.n_x", Value::Integer(n)),
                    ("solver.load_steps", Value::Integer(10)),
                ],
                &["tip.x", "tip.z"],
            );
            let (u, w) = (1.0 - v[0] / l, v[1] / l);
            println!(
                "| {k} | {n} | {u:.5} | {w:.5} | {:.5} | {:.5} |",
                tip.u, tip.w
            );
            let tol = if n == 40 { 2e-3 } else { 6e-3 };
            assert!(
                (u - tip.u).abs() < tol && (w - tip.w).abs() < tol,
                "k = {k}, n = {n}"
            );
        }
    }
}
