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
            // the shell stretches (EA = 1.2e5 N), the elastica does not: 3e-5 L at k = 4
            let tol = 2e-4;
            assert!(
                (u - tip.u).abs() < tol && (w - tip.w).abs() < tol,
                "k = {k}, n = {n}"
            );
        }
    }
}

/// A disc of radius `a` (meridian from the pole outwards), steel 10 mm, clamped at its rim,
/// under a uniform pressure; probe at the centre.
fn clamped_disc(a: f64) -> Scene {
    Scene::from_toml(&format!(
        r#"
kind = "shell"
[fmu]
model_name = "disc"
[material]
E = 210e9
nu = 0.3
rho = 7850.0
[shell]
thickness = 0.01
[meridian]
start = [0.0, 0.0]
[[meridian.pieces]]
direction = [1.0, 0.0]
length = {a}
[mesh]
n_circumferential = 16
n_meridional = 4
[[ring_supports]]
ring = "last"
kind = "clamped"
[pressure]
name = "load"
[[probes]]
name = "centre"
at = [0.0, 0.0, 0.0]
outputs = ["z"]
"#
    ))
    .unwrap()
}

/// Clamped circular plate under a uniform pressure: centre deflection against `q a⁴/(64 D)`
/// (Timoshenko & Woinowsky-Krieger), on surface-of-revolution meshes with the O-grid pole
/// patch (n_circumferential = 4 n_meridional). Measured: +2.1 %, +0.27 %, −0.13 % at n = 4,
/// 8, 16 (the error changes sign: the inscribed polygon of the rim shortens the radius by
/// `O(1/n²)` while the element converges from above, so no order is asserted).
#[test]
fn clamped_circular_plate_under_pressure() {
    let a = 0.5;
    let sc = clamped_disc(a);
    let (e, nu, _, h) = PLATE;
    let d = reference::plate_rigidity(e, h, nu);
    let q = 1000.0;
    let exact = reference::clamped_circular_uniform_deflection(a, d, q, 0.0);
    let sizes = [4, 8, 16];
    let values: Vec<f64> = sizes
        .iter()
        .map(|&n| {
            statics(
                &sc,
                &[
                    ("load.pressure", Value::Real(q)),
                    ("mesh.n_circumferential", Value::Integer(4 * n)),
                    ("mesh.n_meridional", Value::Integer(n)),
                ],
                &["centre.z"],
            )[0]
            .abs()
        })
        .collect();
    let (err, ord) = table(
        "Clamped circular plate, uniform pressure, centre deflection, V2",
        &sizes,
        &values,
        exact,
    );
    assert!(err[1] < 0.01 && err[2] < 0.005, "{err:?} (orders {ord:?})");
}

/// Closed cylinder (R = 0.1, t = 2 mm, L = 0.5, flat end caps) under internal pressure: the
/// change of the mid-ring radius against the membrane solution `ΔR = p R²/(E t) (1 − ν/2)`
/// (far from the caps: the bending boundary layer decays over `≈ 2.4 √(R t)` = 0.05 m), the
/// axial strain of the wall between two rings 0.1 m from the caps against
/// `ε_x = p R/(2 E t)(1 − 2ν)`, and the enclosed volume at rest against the polygonal prism.
#[test]
fn closed_cylinder_under_pressure() {
    let text = std::fs::read_to_string(scene_path("cylinder"))
        .unwrap()
        .replace("n_meridional = 14", "n_meridional = 28")
        + r#"
[[ring_probes]]
name = "low"
ring = 0.2
outputs = ["z"]
[[ring_probes]]
name = "high"
ring = 0.5
outputs = ["z"]
"#;
    let sc = Scene::from_toml(&text).unwrap();
    let cyl = reference::ClosedCylinder {
        radius: 0.1,
        thickness: 0.002,
        length: 0.5,
        e: 2.1e11,
        nu: 0.3,
    };
    let p = 1e5;
    let outs = ["mid.radius", "low.z", "high.z", "shell.volume"];
    println!("| n_circumferential | ΔR / exact | ε_x / exact |");
    println!("|---|---|---|");
    for n_c in [16, 32, 64] {
        let n = [("mesh.n_circumferential", Value::Integer(n_c))];
        let rest = statics(&sc, &n, &outs);
        let mut with_p = n.to_vec();
        with_p.push(("load.pressure", Value::Real(p)));
        let loaded = statics(&sc, &with_p, &outs);
        let dr = (loaded[0] - rest[0]) / cyl.radius_change(p);
        let ex = ((loaded[2] - loaded[1]) / (rest[2] - rest[1]) - 1.0) / cyl.axial_strain(p);
        let prism = 0.5 * n_c as f64 * 0.01 * (2.0 * std::f64::consts::PI / n_c as f64).sin();
        println!("| {n_c} | {dr:.4} | {ex:.4} |");
        assert!(
            (rest[3] / (prism * 0.5) - 1.0).abs() < 1e-9,
            "volume at rest {}",
            rest[3]
        );
        if n_c >= 32 {
            assert!((dr - 1.0).abs() < 0.02, "n_c = {n_c}: ΔR ratio {dr}");
            assert!((ex - 1.0).abs() < 0.05, "n_c = {n_c}: ε_x ratio {ex}");
        }
    }
}

fn set_input(sc: &Scene, sim: &mut flexfmu::solver::simulation::Simulation, name: &str, v: f64) {
    sim.set_input(input_index(sc, name), v);
}

/// Free vibration of the strip released from a statically deflected state (tip force 0.2 N,
/// tip deflection ≈ L/15), 0.02 s steps over about two periods of the first mode: every
/// implicit integrator runs the shell; the energy-conserving ones (Newmark on the Lie group,
/// implicit midpoint) keep the total energy, generalized-α (ρ∞ = default) only loses some.
#[test]
fn free_vibration_keeps_its_energy() {
    let text =
        std::fs::read_to_string(scene_path("strip")).unwrap() + "\n[outputs]\nenergy = true\n";
    let sc = Scene::from_toml(&text).unwrap();
    println!("| integrator | E0 [J] | largest |ΔE|/E0 | E_end/E0 |");
    println!("|---|---|---|---|");
    for code in [1, 2, 3] {
        let mut sim = simulation(
            &sc,
            &[
                ("load.fz", Value::Real(0.2)),
                ("solver.integrator", Value::Integer(code)),
                ("solver.max_step", Value::Real(0.02)),
                ("solver.static_equilibrium", Value::Boolean(true)),
            ],
        )
        .unwrap();
        set_input(&sc, &mut sim, "load.fz", 0.0);
        let e0 = output(&sc, &sim, "energy.total");
        let (mut dev, mut z_min, mut z_max): (f64, f64, f64) = (0.0, f64::MAX, f64::MIN);
        let h = 0.02;
        for k in 0..600 {
            sim.advance((k + 1) as f64 * h).unwrap();
            let e = output(&sc, &sim, "energy.total");
            dev = dev.max((e - e0).abs() / e0);
            let z = output(&sc, &sim, "tip.z");
            z_min = z_min.min(z);
            z_max = z_max.max(z);
        }
        let e_end = output(&sc, &sim, "energy.total");
        println!("| {code} | {e0:.4e} | {dev:.2e} | {:.4} |", e_end / e0);
        assert!(
            z_min < -0.3 && z_max > 0.3,
            "integrator {code}: the tip did not swing ({z_min}, {z_max})"
        );
        match code {
            1 => assert!(
                e_end <= e0 * 1.001 && e_end > 0.5 * e0,
                "gen-alpha: {e_end} of {e0}"
            ),
            _ => assert!(dev < 0.01, "integrator {code}: energy changed by {dev}"),
        }
    }
}

/// Natural frequencies of the simply supported square plate (translations held on the edges)
/// against `ω_mn = π²(m² + n²)/a² √(D/(ρh))` (Leissa, NASA SP-160): modes (1,1), (1,2) =
/// (2,1) and (2,2), n × n meshes (dense eigenproblem of the assembled matrices). Measured:
/// the frequencies converge from above at second order (ω11 +7.1 %, +1.7 %, +0.76 % at n =
/// 4, 8, 12; ω22 +29 %, +7.1 %, +3.1 %): the translational mass is that of the bilinear
/// position field (module notes of the element).
#[test]
fn simply_supported_plate_frequencies() {
    use flexfmu::kinds::shell::model::Shell;
    use flexfmu::model::{MechanicalSystem, Model, modal};
    let sc = scene("plate");
    let (e, nu, rho, h) = PLATE;
    let d = reference::plate_rigidity(e, h, nu);
    let exact = [(1, 1), (1, 2), (2, 1), (2, 2)]
        .map(|(m, n)| reference::ss_plate_frequency(1.0, 1.0, d, rho, h, m, n));
    println!("| n | ω11 / exact | ω12 / exact | ω21 / exact | ω22 / exact |");
    println!("|---|---|---|---|---|");
    let mut errors = Vec::new();
    for n in [4, 8, 12] {
        let mut sim = simulation(
            &sc,
            &[
                ("mesh.n_x", Value::Integer(n)),
                ("mesh.n_y", Value::Integer(n)),
            ],
        )
        .unwrap();
        let m = sim.model_as_mut::<Shell>().unwrap();
        let nf = m.n_free();
        let (mut q, mut v) = (vec![0.0; nf], vec![0.0; nf]);
        m.free_state(&mut q, &mut v);
        let (mm, kk) = modal::dense_matrices(m, 0.0, &q).unwrap();
        let w = modal::natural_frequencies(&mm, &kk).unwrap();
        let ratios: Vec<f64> = (0..4).map(|i| w[i] / exact[i]).collect();
        println!(
            "| {n} | {:.4} | {:.4} | {:.4} | {:.4} |",
            ratios[0], ratios[1], ratios[2], ratios[3]
        );
        errors.push((ratios[0] - 1.0, ratios[3] - 1.0));
        if n == 12 {
            for r in &ratios {
                assert!(*r > 1.0 && *r < 1.04, "{ratios:?}");
            }
        }
    }
    // second order: the error falls by (12/8)² = 2.25 from n = 8 to 12
    for k in [0, 1] {
        let pick = |e: &(f64, f64)| if k == 0 { e.0 } else { e.1 };
        let ratio = pick(&errors[1]) / pick(&errors[2]);
        assert!(ratio > 2.0, "mode {k}: {errors:?}");
    }
}

/// Does the geometric (initial-stress) stiffness allow coarser meshes, as Part I of the paper
/// says (Eq. 21)? Measured on two large-deflection problems, printed as tables: the strip
/// under an end shear k = PL²/EI = 4 against the elastica, and the simply supported square
/// plate (edges held in plane) under a pressure that deflects it 1.9 thicknesses, where the
/// membrane action matters, against the finest mesh. Both options must converge to the same
/// answer; which is better on coarse meshes is the measurement.
#[test]
fn geometric_stiffness_on_coarse_meshes() {
    let sc = scene("strip");
    let tip = reference::elastica_tip_shear(4.0);
    println!(
        "strip, end shear k = 4: error of w/L (elastica {:.5})",
        tip.w
    );
    println!("| n_x | linear local energy | with geometric stiffness |");
    println!("|---|---|---|");
    let mut finest = [0.0; 2];
    for n in [4, 8, 16, 32] {
        let mut errs = [0.0; 2];
        for (i, gs) in [false, true].into_iter().enumerate() {
            let v = statics(
                &sc,
                &[
                    ("load.fz", Value::Real(4.0)),
                    ("mesh.n_x", Value::Integer(n)),
                    ("mesh.n_y", Value::Integer(2)),
                    ("element.geometric_stiffness", Value::Boolean(gs)),
                    ("solver.load_steps", Value::Integer(10)),
                ],
                &["tip.z"],
            );
            errs[i] = (v[0] / 10.0 - tip.w).abs() / tip.w;
        }
        println!("| {n} | {:.3e} | {:.3e} |", errs[0], errs[1]);
        finest = errs;
    }
    assert!(finest[0] < 2e-3 && finest[1] < 2e-3, "{finest:?}");

    let sc = scene("plate");
    let q = 2.0e5;
    let run = |n: i32, gs: bool| {
        statics(
            &sc,
            &[
                ("load.pressure", Value::Real(q)),
                ("mesh.n_x", Value::Integer(n)),
                ("mesh.n_y", Value::Integer(n)),
                ("element.geometric_stiffness", Value::Boolean(gs)),
                ("solver.load_steps", Value::Integer(10)),
            ],
            &["centre.z"],
        )[0]
    };
    let reference = run(24, true);
    let linear = reference::navier_uniform_deflection(
        1.0,
        1.0,
        reference::plate_rigidity(PLATE.0, PLATE.3, PLATE.1),
        q,
        0.5,
        0.5,
    );
    println!(
        "SS plate (edges held in plane), q = {q} Pa: centre deflection, reference 24 x 24 with geometric stiffness {reference:.5e} m (linear theory {linear:.5e} m)"
    );
    println!("| n | linear local energy | with geometric stiffness |");
    println!("|---|---|---|");
    let mut last = [0.0; 2];
    for n in [4, 8, 12] {
        let e = [run(n, false), run(n, true)].map(|w| (w / reference - 1.0).abs());
        println!("| {n} | {:.3e} | {:.3e} |", e[0], e[1]);
        last = e;
    }
    assert!(
        reference < 0.7 * linear,
        "no membrane stiffening: {reference} vs {linear}"
    );
    assert!(last[0] < 0.02 && last[1] < 0.02, "{last:?}");
}

/// A half-torus bellows (meridian: a half circle of radius 40 mm about r = 80 mm, t = 2 mm,
/// E = 50 MPa, both rings clamped) inflated to 1 bar: the static solve follows the deflection,
/// the top ring of the lobe (r = 80 mm, z = 40 mm) rises, the shape stays axisymmetric (nodes
/// 90° apart on that ring at the same radius), and the rise converges with the mesh (printed).
#[test]
fn bellows_of_revolution_inflates_axisymmetrically() {
    let scene = |n_c: i32, n_m: i32| {
        Scene::from_toml(&format!(
            r#"
kind = "shell"
[fmu]
model_name = "bellows"
[material]
E = 5e7
nu = 0.45
rho = 1100.0
[shell]
thickness = 0.002
[meridian]
start = [0.12, 0.0]
[[meridian.pieces]]
direction = [0.0, 1.0]
radius = 0.04
angle_deg = 180.0
[mesh]
n_circumferential = {n_c}
n_meridional = {n_m}
[[ring_supports]]
ring = "first"
kind = "clamped"
[[ring_supports]]
ring = "last"
kind = "clamped"
[pressure]
name = "load"
[[ring_probes]]
name = "top"
ring = {crown}
outputs = ["radius", "z"]
[[probes]]
name = "a"
at = [0.08, 0.0, 0.04]
[[probes]]
name = "b"
at = [0.0, 0.08, 0.04]
"#,
            crown = 0.02 * std::f64::consts::PI
        ))
        .unwrap()
    };
    println!(
        "| n_circumferential × n_meridional | top ring radius change [mm] | rise [mm] | |a| − |b| [m] |"
    );
    println!("|---|---|---|---|");
    let mut growth = Vec::new();
    for (n_c, n_m) in [(16, 8), (32, 16), (64, 32)] {
        let sc = scene(n_c, n_m);
        let v = statics(
            &sc,
            &[
                ("load.pressure", Value::Real(1e5)),
                ("solver.load_steps", Value::Integer(10)),
            ],
            &["top.radius", "top.z", "a.x", "a.y", "b.x", "b.y"],
        );
        let (ra, rb) = (v[2].hypot(v[3]), v[4].hypot(v[5]));
        let (dr, dz) = (v[0] - 0.08, v[1] - 0.04);
        println!(
            "| {n_c} × {n_m} | {:.4} | {:.4} | {:.1e} |",
            1e3 * dr,
            1e3 * dz,
            ra - rb
        );
        assert!((ra - rb).abs() < 1e-9, "not axisymmetric: {ra} vs {rb}");
        assert!(dz > 0.0, "the lobe did not rise: {dz}");
        growth.push(dz);
    }
    let (d1, d2) = (growth[1] - growth[0], growth[2] - growth[1]);
    assert!(
        d2.abs() < 0.5 * d1.abs() + 1e-6,
        "no convergence: {growth:?}"
    );
}

/// The pinched hemisphere of MacNeal & Harder 1985 (R = 10, t = 0.04, E = 6.825e7, ν = 0.3,
/// an 18° hole at the pole, radial forces of 2 at 90° on the equator, alternately outwards
/// and inwards): the radial displacement under the outward load against their reference
/// 0.094 (a benchmark that locks flat facets with stiff membranes). The whole hemisphere is
/// modelled; the inward load at +y is the reaction of a clamp there (the other three loads
/// are not in equilibrium by exactly that force), which holds the rigid motion. Measured at
/// A, far from the clamp.
#[test]
fn pinched_hemisphere() {
    let scene = |n_c: i32| {
        Scene::from_toml(&format!(
            r#"
kind = "shell"
[fmu]
model_name = "hemisphere"
[material]
E = 6.825e7
nu = 0.3
rho = 1.0
[shell]
thickness = 0.04
[meridian]
start = [10.0, 0.0]
[[meridian.pieces]]
direction = [0.0, 1.0]
radius = 10.0
angle_deg = 72.0
[mesh]
n_circumferential = {n_c}
n_meridional = {n_m}
[[point_supports]]
at = [0.0, 10.0, 0.0]
kind = "clamped"
[[loads]]
name = "a"
at = [10.0, 0.0, 0.0]
fx = 2.0
[[loads]]
name = "c"
at = [-10.0, 0.0, 0.0]
fx = -2.0
[[loads]]
name = "b"
at = [0.0, -10.0, 0.0]
fy = 2.0
[[probes]]
name = "pa"
at = [10.0, 0.0, 0.0]
outputs = ["x"]
"#,
            n_m = n_c / 4
        ))
        .unwrap()
    };
    println!("| elements around | rings | radial displacement at A | / 0.094 |");
    println!("|---|---|---|---|");
    for n_c in [16, 32, 64] {
        let d = statics(&scene(n_c), &[], &["pa.x"])[0] - 10.0;
        println!("| {n_c} | {} | {d:.5} | {:.4} |", n_c / 4, d / 0.094);
        if n_c >= 32 {
            assert!((d / 0.094 - 1.0).abs() < 0.015, "n_c = {n_c}: {d}");
        }
    }
}
