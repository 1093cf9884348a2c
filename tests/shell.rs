//! The `shell` body kind (issue 10): strict tables, parameter ranges, mesh and support errors,
//! the outputs of the reference state, line loads and ring supports through small linear
//! responses, the model's iteration matrix against finite differences, and the shipped scenes
//! run through the FMI instance. Validation against published shell results is elsewhere.
//! Measured figures are printed (`--nocapture`).

mod common;
use common::*;
use flexfmu::kinds::shell::ShellScene;
use flexfmu::kinds::shell::model::Shell;
use flexfmu::model::{JacobianCoeffs, MechanicalSystem, Model};
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::variables::Value;
use std::f64::consts::PI;

fn text(name: &str) -> String {
    std::fs::read_to_string(scene_path(name)).unwrap()
}

/// Replaces `from` (which must be there) by `to` in `base`.
fn edit(base: &str, from: &str, to: &str) -> String {
    assert!(base.contains(from), "{from:?} not in the scene");
    base.replacen(from, to, 1)
}

fn scene_error(text: &str) -> String {
    Scene::from_toml(text).unwrap_err().0
}

/// An open tube (no poles: the ring mesher as it is) of radius 0.1 m and length 0.5 m,
/// clamped at its first ring, with a line load on its last ring and ring outputs.
const TUBE: &str = r#"
kind = "shell"
[fmu]
model_name = "tube"
[material]
E = 210e9
nu = 0.0
rho = 7850.0
[shell]
thickness = 0.002
[meridian]
start = [0.1, 0.0]
[[meridian.pieces]]
direction = [0.0, 1.0]
length = 0.5
[mesh]
n_circumferential = 16
n_meridional = 10
[[ring_supports]]
ring = "first"
kind = "clamped"
[[line_loads]]
name = "end"
ring = "last"
[[ring_probes]]
name = "mid"
ring = 0.25
outputs = ["radius", "z"]
[[probes]]
name = "top"
at = [0.1, 0.0, 0.5]
outputs = ["x", "y", "z", "rx", "wy"]
[outputs]
length = true
energy = true
"#;

/// Unknown keys and tables are named with the kind; wrong geometry tables are named.
#[test]
fn strict_tables_name_unknown_keys() {
    let plate = text("plate");
    let err = scene_error(&edit(
        &plate,
        "length_y = 1.0",
        "length_y = 1.0\nlenght_z = 2.0",
    ));
    assert!(err.contains("lenght_z") && err.contains("shell"), "{err}");
    let err = scene_error(&edit(
        &plate,
        "[shell]",
        "[shells]\nthickness = 1.0\n[shell]",
    ));
    assert!(err.contains("shells") && err.contains("shell"), "{err}");
    let err = scene_error(&edit(
        &plate,
        "x0 = \"simply_supported\"",
        "x0 = \"hinged\"",
    ));
    assert!(err.contains("x0"), "{err}");
    let err = scene_error(&edit(&plate, "n_y = 10\n", ""));
    assert!(err.contains("mesh.n_y"), "{err}");
    let err = scene_error(&edit(&plate, "n_y = 10", "n_y = 10\nn_meridional = 4"));
    assert!(err.contains("mesh.n_meridional"), "{err}");
    let both = format!(
        "{plate}\n[meridian]\nstart = [0.1, 0.0]\n[[meridian.pieces]]\ndirection = [0.0, 1.0]\nlength = 1.0\n"
    );
    let err = scene_error(&both);
    assert!(err.contains("plate") && err.contains("meridian"), "{err}");
    let err = scene_error(&edit(
        &plate,
        "outputs = [\"x\", \"y\", \"z\"]",
        "outputs = [\"x\", \"tz\"]",
    ));
    assert!(err.contains("probes[0].outputs"), "{err}");
    let err = scene_error(&format!(
        "{plate}\n[[ring_supports]]\nring = \"first\"\nkind = \"clamped\"\n"
    ));
    assert!(err.contains("ring_supports[0]"), "{err}");
    let err = scene_error(&format!(
        "{plate}\n[[line_loads]]\nname = \"load\"\nedge = \"x1\"\n"
    ));
    assert!(
        err.contains("line_loads[0]") && err.contains("loads[0]") && err.contains("load.fx"),
        "{err}"
    );
    let err = scene_error(&edit(&plate, "at = [0.5, 0.5, 0.0]", "at = [0.5]"));
    assert!(err.contains("loads[0].at"), "{err}");
    let err = scene_error(&edit(TUBE, "ring = 0.25", "ring = \"middle\""));
    assert!(err.contains("ring_probes[0].ring"), "{err}");
    let err = scene_error(&edit(TUBE, "ring = \"last\"", "edge = \"x1\""));
    assert!(err.contains("line_loads[0].edge"), "{err}");
    // a surface of revolution takes [x, y, z] points; a plate also [x, y]
    let err = scene_error(&edit(TUBE, "at = [0.1, 0.0, 0.5]", "at = [0.1, 0.0]"));
    assert!(err.contains("probes[0].at"), "{err}");
    assert!(
        Scene::from_toml(&edit(
            &plate,
            "at = [0.5, 0.5, 0.0]\noutputs",
            "at = [0.5, 0.5]\noutputs"
        ))
        .is_ok()
    );
}

/// Parameter ranges: every shell parameter rejects what it cannot take, naming itself.
#[test]
fn parameter_ranges() {
    let sc = scene("plate");
    for (name, bad) in [
        ("mesh.n_x", Value::Integer(0)),
        ("mesh.n_y", Value::Integer(100_001)),
        ("element.bending", Value::Integer(3)),
        ("element.bending", Value::Integer(0)),
        ("element.drilling_stiffness", Value::Real(0.0)),
        ("support.x0", Value::Integer(3)),
        ("support.y1", Value::Integer(-1)),
        ("material.nu", Value::Real(0.5)),
        ("material.E", Value::Real(-1.0)),
        ("shell.thickness", Value::Real(0.0)),
        ("material.rho", Value::Real(f64::NAN)),
    ] {
        let mut p = ParamValues::defaults(&sc.params);
        set_param(&mut p, name, bad);
        let errs = p.validate(&sc.params).unwrap_err();
        assert!(
            errs.len() == 1 && errs[0].contains(name),
            "{name}: {errs:?}"
        );
    }
    let tube = Scene::from_toml(TUBE).unwrap();
    let mut p = ParamValues::defaults(&tube.params);
    set_param(&mut p, "mesh.n_circumferential", Value::Integer(2));
    let errs = p.validate(&tube.params).unwrap_err();
    assert!(errs[0].contains("mesh.n_circumferential"), "{errs:?}");
    // the plate parameters belong to plates only
    assert!(tube.params.iter().all(|d| !d.name.starts_with("support.")));
    assert!(sc.params.iter().all(|d| d.name != "mesh.n_meridional"));
}

/// Mesh and support errors at build time name the key or parameter; a free shell may move
/// but has no static equilibrium.
#[test]
fn mesh_and_support_errors() {
    let sc = scene("plate");
    let err = simulation(&sc, &[("mesh.n_x", Value::Integer(3))]).unwrap_err();
    assert!(
        err.contains("loads[0].at") && err.contains("mesh.n_x"),
        "{err}"
    );
    let free = [
        ("support.x0", Value::Integer(0)),
        ("support.x1", Value::Integer(0)),
        ("support.y0", Value::Integer(0)),
        ("support.y1", Value::Integer(0)),
    ];
    let err = simulation(&sc, &free).unwrap_err();
    assert!(err.contains("solver.static_equilibrium"), "{err}");
    let mut dynamic = free.to_vec();
    dynamic.push(("solver.static_equilibrium", Value::Boolean(false)));
    assert!(simulation(&sc, &dynamic).is_ok());
    // one simply supported edge leaves the rotation about it: still a mechanism
    let err = simulation(
        &sc,
        &[
            ("support.x1", Value::Integer(0)),
            ("support.y0", Value::Integer(0)),
            ("support.y1", Value::Integer(0)),
        ],
    )
    .unwrap_err();
    assert!(err.contains("solver.static_equilibrium"), "{err}");
    // one clamped edge holds it
    assert!(
        simulation(
            &sc,
            &[
                ("support.x0", Value::Integer(2)),
                ("support.x1", Value::Integer(0)),
                ("support.y0", Value::Integer(0)),
                ("support.y1", Value::Integer(0)),
            ],
        )
        .is_ok()
    );
    let tube = Scene::from_toml(&edit(TUBE, "ring = 0.25", "ring = 0.23")).unwrap();
    let err = simulation(&tube, &[]).unwrap_err();
    assert!(
        err.contains("ring_probes[0].ring") && err.contains("mesh.n_meridional"),
        "{err}"
    );
    let tube =
        Scene::from_toml(&edit(TUBE, "length = true", "length = true\nvolume = true")).unwrap();
    let err = simulation(&tube, &[]).unwrap_err();
    assert!(err.contains("outputs.volume"), "{err}");
}

/// The outputs of the reference state: the plate centre where the scene puts it, the closed
/// cylinder's volume that of the prism on its polygon, mean ring radii and lengths exact
/// (nodes on the circle), zero energies.
#[test]
fn reference_state_outputs() {
    let sc = scene("plate");
    let sim = simulation(&sc, &[]).unwrap();
    assert_eq!(output(&sc, &sim, "centre.x"), 0.5);
    assert_eq!(output(&sc, &sim, "centre.y"), 0.5);
    assert_eq!(output(&sc, &sim, "centre.z"), 0.0);
    // the closed cylinder: flat caps and planar walls enclose the prism on the 16-gon exactly
    let cyl = scene("cylinder");
    let sim = simulation(&cyl, &[]).unwrap();
    let (r, l, n) = (0.1f64, 0.5f64, 16.0f64);
    let prism = 0.5 * n * r * r * (2.0 * PI / n).sin() * l;
    let v = output(&cyl, &sim, "shell.volume");
    assert!((v / prism - 1.0).abs() < 1e-12, "{v} vs {prism}");
    assert!((output(&cyl, &sim, "mid.radius") - r).abs() < 1e-15);
    assert!((output(&cyl, &sim, "shell.length") - l).abs() < 1e-15);
    let tube = Scene::from_toml(TUBE).unwrap();
    let sim = simulation(&tube, &[]).unwrap();
    assert!((output(&tube, &sim, "mid.radius") - 0.1).abs() < 1e-15);
    assert!((output(&tube, &sim, "mid.z") - 0.25).abs() < 1e-15);
    assert!((output(&tube, &sim, "shell.length") - 0.5).abs() < 1e-15);
    assert_eq!(output(&tube, &sim, "top.rx"), 0.0);
    for e in ["kinetic", "potential"] {
        assert_eq!(output(&tube, &sim, &format!("energy.{e}")), 0.0, "{e}");
    }
    // the element frames of the reference carry round-off only (strains ~1e-12 or less)
    let (e, area): (f64, f64) = (210e9 * 0.002, 2.0 * PI * 0.1 * 0.5);
    let strain = output(&tube, &sim, "energy.strain");
    assert!(strain.abs() < 0.5 * e * area * 1e-24, "{strain}");
}

/// Euler–Bernoulli cantilever (ν = 0, so the strip bends like a beam): a small total force
/// and, separately, a small total moment spread along the free edge give the tip deflections
/// `F L³/(3 EI)` and `M L²/(2 EI)` (EI = E b h³/12; the V2 functions hold cubics, so to
/// round-off and the O(θ²) nonlinearity); a plumbing check of the edge load, the
/// clamped edge and the probe (the elastica and the roll-up are the validation's).
#[test]
fn strip_small_end_loads_match_beam_theory() {
    let sc = scene("strip");
    let (e, b, h, l): (f64, f64, f64, f64) = (1.2e6, 1.0, 0.1, 10.0);
    let ei = e * b * h.powi(3) / 12.0;
    let f = 1e-4 * ei / (l * l);
    let sim = simulation(&sc, &[("load.fz", Value::Real(f))]).unwrap();
    let z = output(&sc, &sim, "tip.z");
    let expect = f * l.powi(3) / (3.0 * ei);
    eprintln!(
        "strip 20x2, end force: tip.z = {z:.6e}, beam theory {expect:.6e}, error {:+.2e}",
        z / expect - 1.0
    );
    assert!((z / expect - 1.0).abs() < 1e-6, "{z} vs {expect}");
    // the moment turns the edge about +y: the tip moves along -z
    let m = 1e-4 * ei / l;
    let sim = simulation(&sc, &[("load.my", Value::Real(m))]).unwrap();
    let z = output(&sc, &sim, "tip.z");
    let expect = -m * l * l / (2.0 * ei);
    eprintln!(
        "strip 20x2, end moment: tip.z = {z:.6e}, beam theory {expect:.6e}, error {:+.2e}",
        z / expect - 1.0
    );
    assert!((z / expect - 1.0).abs() < 1e-6, "{z} vs {expect}");
    assert!((output(&sc, &sim, "tip.y") - 0.5).abs() < 1e-9 * l);
}

/// A total axial force on the last ring of the clamped tube (ν = 0) stretches it by
/// `F L/(E A)` with the polygon's section `A = 2 n R sin(π/n) t`: the ring load's shares, the
/// ring support and the ring outputs.
#[test]
fn tube_stretched_by_a_ring_load() {
    let tube = Scene::from_toml(TUBE).unwrap();
    let (e, r, t, l, n): (f64, f64, f64, f64, f64) = (210e9, 0.1, 0.002, 0.5, 16.0);
    let area = 2.0 * n * r * (PI / n).sin() * t;
    let f = 1e-5 * e * area;
    let sim = simulation(
        &tube,
        &[
            ("end.fz", Value::Real(f)),
            ("solver.static_equilibrium", Value::Boolean(true)),
        ],
    )
    .unwrap();
    let dl = output(&tube, &sim, "shell.length") - l;
    let expect = f * l / (e * area);
    eprintln!(
        "tube, axial ring load: elongation {dl:.6e}, F L/(E A) {expect:.6e}, error {:+.2e}",
        dl / expect - 1.0
    );
    assert!((dl / expect - 1.0).abs() < 1e-6, "{dl} vs {expect}");
    let mid = output(&tube, &sim, "mid.z") - 0.25;
    assert!((mid / (0.5 * expect) - 1.0).abs() < 1e-3, "{mid}");
}

/// An isosceles trapezoidal plate (`width_top`) clamped along its bottom edge under a total
/// force on its top edge: the mesh is symmetric about x = length_x/2, so the top corners
/// deflect alike and the top centre lies on the axis of symmetry; the top edge's nodes are
/// found by point.
#[test]
fn trapezoidal_plate_deflects_symmetrically() {
    let text = edit(
        &edit(
            &edit(
                &text("strip"),
                "length_y = 1.0",
                "length_y = 2.0\nwidth_top = 0.5",
            ),
            "x0 = \"clamped\"",
            "y0 = \"clamped\"",
        ),
        "edge = \"x1\"",
        "edge = \"y1\"",
    )
    .replace("at = [10.0, 0.5, 0.0]", "at = [4.75, 2.0, 0.0]")
        + "\n[[probes]]\nname = \"right\"\nat = [5.25, 2.0]\noutputs = [\"x\", \"z\"]\n\n[[probes]]\nname = \"mid\"\nat = [5.0, 2.0]\noutputs = [\"x\", \"z\"]\n";
    let sc = Scene::from_toml(&text).unwrap();
    let sim = simulation(&sc, &[("load.fz", Value::Real(1.0))]).unwrap();
    let (zl, zr) = (output(&sc, &sim, "tip.z"), output(&sc, &sim, "right.z"));
    let zm = output(&sc, &sim, "mid.z");
    eprintln!("trapezoidal plate: top corners z = {zl:.6e}, {zr:.6e}, top centre {zm:.6e}");
    assert!(zl > 0.0 && zm > 0.0);
    assert!((zl - zr).abs() < 1e-9 * zl, "{zl} vs {zr}");
    assert!((output(&sc, &sim, "mid.x") - 5.0).abs() < 1e-9);
}

/// The assembled iteration matrix of the whole model against central differences of its
/// residual (mass, damping and stiffness parts) at a configuration with large incremental
/// rotations, velocities and accelerations, with gravity, a point force and moment, a line
/// load and the follower pressure (its non-symmetric tangent).
#[test]
fn model_jacobian_matches_finite_differences() {
    let text = edit(
        &edit(
            &edit(&text("plate"), "n_x = 10\nn_y = 10", "n_x = 2\nn_y = 2"),
            "at = [0.5, 0.5, 0.0]\n",
            "at = [0.5, 0.5, 0.0]\nfx = 3e3\nfy = -5e3\nfz = 2e3\nmx = 300.0\nmy = -400.0\nmz = 500.0\n",
        ),
        "value = 0.0",
        "value = 2e5",
    ) + "\n[[line_loads]]\nname = \"edge\"\nedge = \"y1\"\nfz = 1e3\nmx = 200.0\n\n[gravity]\nx = 1.0\ny = -2.0\nz = -9.81\n";
    let sc = Scene::from_toml(&text).unwrap();
    let mut p = ParamValues::defaults(&sc.params);
    set_param(&mut p, "support.x1", Value::Integer(0));
    set_param(&mut p, "support.y1", Value::Integer(0));
    set_param(&mut p, "material.E", Value::Real(2e7));
    let mut m = Shell::build(sc.tables::<ShellScene>().unwrap(), &p).unwrap();
    let n = m.n_free();
    let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
    m.free_state(&mut q, &mut v);
    let wave = |i: usize, s: f64| (i as f64 * s).sin();
    for i in 0..n {
        q[i] += 0.02 * wave(i, 1.3);
        v[i] = 2.0 * wave(i, 0.4);
    }
    let a: Vec<f64> = (0..n).map(|i| 5.0 * wave(i, 0.9)).collect();
    let pattern = m.pattern().clone();
    let mut r = vec![0.0; n];
    for (which, c) in [
        (2, (1.0, 0.0, 0.0)),
        (1, (0.0, 1.0, 0.0)),
        (0, (0.0, 0.0, 1.0)),
    ] {
        let mut vals = vec![0.0; pattern.nnz()];
        let coeffs = JacobianCoeffs {
            mass: c.0,
            damping: c.1,
            stiffness: c.2,
        };
        m.residual(0.0, &q, &v, &a, 0.8, &mut r, Some((coeffs, &mut vals)))
            .unwrap();
        let hstep = if which == 0 { 1e-7 } else { 1e-2 };
        let (mut worst, mut scale): (f64, f64) = (0.0, 0.0);
        for j in 0..n {
            let (mut xp, mut xm) = (
                [q.clone(), v.clone(), a.clone()],
                [q.clone(), v.clone(), a.clone()],
            );
            xp[which][j] += hstep;
            xm[which][j] -= hstep;
            let (mut rp, mut rm) = (vec![0.0; n], vec![0.0; n]);
            m.residual(0.0, &xp[0], &xp[1], &xp[2], 0.8, &mut rp, None)
                .unwrap();
            m.residual(0.0, &xm[0], &xm[1], &xm[2], 0.8, &mut rm, None)
                .unwrap();
            for i in 0..n {
                let fd = (rp[i] - rm[i]) / (2.0 * hstep);
                let an = pattern.position(i, j).map_or(0.0, |k| vals[k]);
                worst = worst.max((fd - an).abs());
                scale = scale.max(an.abs());
            }
        }
        let rmax = r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let tol = 1e-6 * scale + 1e-13 * rmax / hstep;
        eprintln!(
            "shell model Jacobian, coefficients {c:?}: largest error {worst:.2e} of {scale:.2e} (tolerance {tol:.1e})"
        );
        assert!(worst < tol, "{c:?}: largest error {worst} of {scale}");
    }
}

/// Every shipped shell scene runs through the FMI instance with its inputs set: the plate
/// bulges along +z under pressure and a centre force, the strip's tip lifts, the closed
/// cylinder's volume, mid radius and length grow under internal pressure.
#[test]
fn shipped_scenes_run() {
    let (mut inst, _log) = instance("plate", false);
    init(&mut inst);
    set(&mut inst, "load.pressure", Value::Real(1e3));
    set(&mut inst, "load.fz", Value::Real(100.0));
    run(&mut inst, 0.0, 5e-3, 1e-3);
    let z = get(&mut inst, "centre.z");
    eprintln!("plate, 5 ms after 1 kPa + 100 N: centre.z = {z:.4e} m");
    assert!(z > 0.0, "{z}");

    let (mut inst, _log) = instance("strip", false);
    init(&mut inst);
    set(&mut inst, "load.fz", Value::Real(0.1));
    run(&mut inst, 0.0, 0.05, 1e-2);
    let z = get(&mut inst, "tip.z");
    eprintln!("strip, 50 ms after 0.1 N: tip.z = {z:.4e} m");
    assert!(z > 0.0, "{z}");

    let (mut inst, _log) = instance("cylinder", false);
    init(&mut inst);
    let (v0, r0, l0) = (
        get(&mut inst, "shell.volume"),
        get(&mut inst, "mid.radius"),
        get(&mut inst, "shell.length"),
    );
    set(&mut inst, "load.pressure", Value::Real(1e5));
    run(&mut inst, 0.0, 5e-3, 1e-3);
    let (v1, r1, l1) = (
        get(&mut inst, "shell.volume"),
        get(&mut inst, "mid.radius"),
        get(&mut inst, "shell.length"),
    );
    eprintln!(
        "cylinder, 5 ms after 1 bar: volume {v0:.6e} -> {v1:.6e}, mid radius {r0:.6e} -> {r1:.6e}, length {l0:.6e} -> {l1:.6e}"
    );
    assert!(v1 > v0 && r1 > r0 && l1 > l0);
}
