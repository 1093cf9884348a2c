//! `flexfmu advise` on the pendulum, the cantilever, the right-angle cantilever and the belt
//! drive: the advice must be checkable — the advised scene file, parsed and run on its own,
//! meets TOL against the converged answer the study estimated (Richardson extrapolation).
//!
//! To keep each test within ~15 s the studies are short and coarse: stop times of 0.05 to
//! 2 s, three or four refinement levels, one thread, and on the belt the integrator, the step
//! and the contact points kept at the scene's values (its step ladder does not converge over
//! 0.1 s, which the advisor reports; see `belt_drive_step_ladder_is_refused`).

mod common;

use flexfmu::advise::report;
use flexfmu::advise::study::{Advice, Config, max_difference, run_one};
use flexfmu::advise::{AdviseOptions, Signals, advise};
use flexfmu::scene::Scene;
use flexfmu::variables::{Role, VariableTable};
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/advise")
        .join(name)
}

/// Options for a test: one thread, no progress bar.
fn options(output: &str, tol: f64, levels: usize, finer: usize) -> AdviseOptions {
    let mut o = AdviseOptions::new(output, tol);
    o.levels = levels;
    o.finer = finer;
    o.jobs = 1;
    o.progress = false;
    o
}

fn signals(scene: &Scene, file: &str) -> Signals {
    Signals::parse(&std::fs::read_to_string(data(file)).unwrap(), scene).unwrap()
}

/// Checks the advice: the advised scene text parses, and run on its own (its own parameter
/// defaults, nothing overridden) its output stays within TOL of the family's converged answer
/// at every common time point. Prints the figures for the report.
fn check_advice(scene: &Scene, opts: &AdviseOptions, a: &Advice) {
    let Some(i) = a.chosen else {
        panic!("no advice:\n{}", report::summary(a));
    };
    let text = report::advised_scene(scene, a).unwrap();
    let advised = Scene::from_toml(&text).unwrap();
    let k = match VariableTable::from_scene(&advised)
        .by_name(&opts.output)
        .unwrap()
        .role
    {
        Role::Output(k) => k,
        r => panic!("{r:?}"),
    };
    let alone = Config {
        values: vec![],
        family: None,
        mesh_level: 0,
        step_level: 0,
        scene_variant: true,
        tol_level: None,
    };
    // the inputs by name against the advised scene (another family's inputs may be
    // numbered differently: the air spring's shell level has five plate axes)
    let inputs = opts.inputs.as_ref().map(|s| s.for_scene(&advised).unwrap());
    let (samples, _) = run_one(&advised, &alone, k, &a.times, inputs.as_ref());
    let y = samples.unwrap();
    let err = max_difference(&y, &a.answer_of(i).answer);
    let finest = a.answer_of(i).path[2];
    println!(
        "{}: advice {} error {err:.3e} (study {:.3e}) vs TOL {:e}; order {:?}; speed-up against the finest run {:.1}x\n{}",
        scene.model_name(),
        a.runs[i].config.label(),
        a.runs[i].error,
        a.tol,
        a.answer_of(i).order,
        a.runs[finest].wall / a.runs[i].wall,
        report::summary(a)
    );
    assert!(
        err <= a.tol,
        "the advised scene alone misses TOL: {err:e} > {:e}\n{text}",
        a.tol
    );
    assert_eq!(
        err, a.runs[i].error,
        "the advised scene differs from the study's run"
    );
}

/// Pendulum (seed 000, Kerkkanen et al. 2003 Problem 4), tip.y to 2 mm over 0.3 s.
#[test]
fn pendulum_advice_is_checkable() {
    let scene = common::scene("pendulum");
    let mut opts = options("tip.y", 2e-3, 3, 1);
    opts.stop_time = Some(0.3);
    let a = advise(&scene, &opts).unwrap();
    check_advice(&scene, &opts, &a);
}

/// Pendulum with both element families (race: seed 000 against the ANCF cable): each family
/// against its own converged answer; the difference between the answers decides whether the
/// family may change; with `--allow-element-change` the advice may be the cable, and the
/// advised scene (the seed-000 options removed) meets TOL on its own.
#[test]
fn pendulum_element_families() {
    let scene = common::scene("pendulum");
    let mut opts = options("tip.y", 2e-3, 3, 1);
    opts.stop_time = Some(0.3);
    let a = advise(&scene, &opts).unwrap();
    assert_eq!(a.families.len(), 2);
    let (code, diff) = a.family_differences[0];
    assert_eq!(code, 2);
    println!("pendulum: converged tip.y of seed 000 and cable differ by {diff:.3e} m over 0.3 s");
    assert_eq!(a.allowed_families.contains(&Some(2)), diff <= opts.tol);
    let chosen = a.runs[a.chosen.unwrap()].config.family;
    assert!(a.allowed_families.contains(&chosen));
    opts.allow_element_change = true;
    let b = advise(&scene, &opts).unwrap();
    assert!(b.allowed_families.contains(&Some(2)));
    check_advice(&scene, &opts, &b);
}

/// Cantilever (seed 000, Problem 2) under a tip force ramp from the inputs CSV, tip.y to
/// 0.2 mm over 0.05 s.
#[test]
fn cantilever_advice_is_checkable() {
    let scene = common::scene("cantilever");
    let mut opts = options("tip.y", 2e-4, 3, 2);
    opts.stop_time = Some(0.05);
    opts.inputs = Some(signals(&scene, "cantilever_load.csv"));
    let a = advise(&scene, &opts).unwrap();
    check_advice(&scene, &opts, &a);
}

/// Right-angle cantilever (Simo and Vu-Quoc 1988) under the first 2 s of its load pulse,
/// tip.z to 1 cm; the Euler–Bernoulli and Timoshenko families are both studied and their
/// converged answers compared.
#[test]
fn right_angle_cantilever_advice_is_checkable() {
    let scene = common::scene("right_angle_cantilever");
    let mut opts = options("tip.z", 1e-2, 3, 1);
    opts.stop_time = Some(2.0);
    opts.inputs = Some(signals(&scene, "right_angle_pulse.csv"));
    let a = advise(&scene, &opts).unwrap();
    assert_eq!(a.families.len(), 2, "both beam theories studied");
    assert_eq!(a.family_differences.len(), 1);
    check_advice(&scene, &opts, &a);
}

/// The air spring (issue 11's rolling lobe) at its three fidelity levels, top.fz under a
/// ±20 mm, 5 Hz plate sine over 0.05 s, TOL 1 kN (5 % of the 21.5 kN design force), coarse
/// (20 meridional elements; the shell level 1 costs 0.1–0.2 s of CPU per simulated ms at
/// 20×16 and 40×32 elements, so its ladder stops there), the integrator and the adaptive
/// steps kept. Each level is measured against its own converged answer; the counts are
/// varied only where they apply (no circumferential count at level 2, no count at level 3,
/// whose table is generated from the membrane level of the same scene); the family changes
/// only where the levels' converged answers agree within TOL; the advised scene meets TOL on
/// its own.
#[test]
fn air_spring_fidelity_advice_is_checkable() {
    let text = std::fs::read_to_string(common::scene_path("air_spring_axisym")).unwrap();
    let scene = Scene::from_toml(&common::with(&text, "n_meridional", "20")).unwrap();
    let mut opts = options("top.fz", 1e3, 3, 1);
    opts.stop_time = Some(0.05);
    opts.inputs = Some(signals(&scene, "air_spring_sine.csv"));
    opts.keep = vec!["solver.integrator".into(), "solver.tolerance".into()];
    let a = advise(&scene, &opts).unwrap();
    let codes: Vec<Option<i32>> = a.families.iter().map(|f| f.family).collect();
    assert_eq!(
        codes,
        [Some(2), Some(1), Some(3)],
        "{}",
        report::summary(&a)
    );
    // knobs only where they apply
    for r in &a.runs {
        let has = |n: &str| r.config.values.iter().any(|(p, _)| *p == n);
        let f = r.config.family.unwrap();
        assert_eq!(
            has("mesh.n_circumferential"),
            f == 1,
            "{}",
            r.config.label()
        );
        assert_eq!(has("mesh.n_meridional"), f != 3, "{}", r.config.label());
    }
    // level 3 refines its step only: three runs; levels 1 and 2 three meshes by three steps
    let count = |f: i32| a.runs.iter().filter(|r| r.config.family == Some(f)).count();
    assert_eq!((count(1), count(2), count(3)), (9, 9, 3));
    for (code, diff) in &a.family_differences {
        println!("air spring: converged top.fz of level 2 and level {code} differ by {diff:.3e} N");
        assert_eq!(a.allowed_families.contains(&Some(*code)), *diff <= opts.tol);
    }
    println!("{}", report::markdown(&a));
    check_advice(&scene, &opts, &a);
}

/// A coarse belt drive (24 elements, 2 contact points per element, 4 belt points) for the
/// belt tests.
fn coarse_belt() -> Scene {
    let text = std::fs::read_to_string(common::scene_path("belt_drive")).unwrap();
    let text = common::with(&text, "n_elements", "24");
    let text = common::with(&text, "points_per_element", "2");
    let text = common::with(&text, "belt_points", "4");
    Scene::from_toml(&text).unwrap()
}

/// Belt drive with pulley 1 speeding up: the belt element count refined (24, 48, 96, 192) at
/// the scene's step, pulley2.angle to 0.05 rad over 0.1 s. Since the slip is taken on the pitch
/// circle (issue 12) the differences 24-48-96 do not shrink yet (1.1e-3 then 2.2e-3: the
/// advisor refuses); 48-96-192 converge at order 1.2.
#[test]
fn belt_drive_advice_is_checkable() {
    let scene = coarse_belt();
    let mut opts = options("pulley2.angle", 5e-2, 4, 3);
    opts.stop_time = Some(0.1);
    opts.inputs = Some(signals(&scene, "belt_ramp.csv"));
    opts.keep = [
        "belt.element",
        "contact.points_per_element",
        "solver.integrator",
        "solver.max_step",
        "solver.tolerance",
    ]
    .map(String::from)
    .to_vec();
    let a = advise(&scene, &opts).unwrap();
    check_advice(&scene, &opts, &a);
}

/// On the belt the internal-step ladder (1, 0.5, 0.25 ms) does not resolve pulley1.torque over
/// 0.1 s to 5e-2 N m: the advisor gives no advice rather than a meaningless one. (Until session
/// 38 the ladder did not even converge, through an artefact: the study sets input derivatives,
/// and each one restarted the integrator's accelerations at every communication step; now it
/// converges at first order with an estimated error of 18 N m for the finest run, so the family
/// is trusted and no configuration meets the tolerance.)
#[test]
fn belt_drive_step_ladder_is_refused() {
    let scene = coarse_belt();
    let mut opts = options("pulley1.torque", 5e-2, 3, 2);
    opts.stop_time = Some(0.1);
    opts.inputs = Some(signals(&scene, "belt_ramp.csv"));
    opts.keep = [
        "belt.element",
        "belt.n_elements",
        "contact.points_per_element",
        "solver.integrator",
    ]
    .map(String::from)
    .to_vec();
    let a = advise(&scene, &opts).unwrap();
    let f = &a.families[0];
    assert!(
        f.warning.is_some() || f.uncertainty > opts.tol,
        "{}",
        report::summary(&a)
    );
    assert_eq!(a.chosen, None);
    let e = report::advised_scene(&scene, &a).unwrap_err();
    assert!(e.contains("no advice"), "{e}");
}

#[test]
fn unknown_output_lists_the_outputs() {
    let scene = common::scene("pendulum");
    let e = advise(&scene, &options("tip.z", 1e-3, 3, 1)).unwrap_err();
    assert!(e.contains("tip.z") && e.contains("tip.x, tip.y"), "{e}");
}

#[test]
fn bad_tolerance_and_levels_are_refused() {
    let scene = common::scene("pendulum");
    for tol in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        let e = advise(&scene, &options("tip.y", tol, 3, 1)).unwrap_err();
        assert!(e.contains("--tol"), "{e}");
    }
    let e = advise(&scene, &options("tip.y", 1e-3, 2, 1)).unwrap_err();
    assert!(e.contains("at least 3 levels"), "{e}");
    let mut o = options("tip.y", 1e-3, 3, 1);
    o.keep = vec!["mesh.count".into()];
    let e = advise(&scene, &o).unwrap_err();
    assert!(
        e.contains("mesh.count") && e.contains("mesh.n_elements"),
        "{e}"
    );
}

#[test]
fn inputs_csv_problems_are_named() {
    let scene = common::scene("cantilever");
    let cases = [
        ("", "empty file"),
        ("time,load.fy\n", "no rows"),
        ("t0,load.fy\n0,1\n", "first column must be `time`"),
        ("time,load.fz\n0,1\n", "load.fx, load.fy"),
        ("time,load.fy\n0,1\n0,2\n", "does not increase"),
        ("time,load.fy\n0,abc\n", "not a number"),
        ("time,load.fy\n0,1,2\n", "3 values"),
        ("time,load.fy,load.fy\n0,1,2\n", "twice"),
    ];
    for (text, want) in cases {
        let e = Signals::parse(text, &scene).unwrap_err();
        assert!(e.contains(want), "{text:?}: {e}");
    }
    let s = Signals::parse("time,load.fy\n0,0\n1,10\n", &scene).unwrap();
    assert_eq!(s.at(0, 0.25), (2.5, 10.0));
    assert_eq!(s.at(0, 2.0), (10.0, 0.0));
}

/// The command line: files written next to the advised scene, the markdown table and the
/// summary printed, a clear failure for an unknown output.
#[test]
fn cli_writes_scene_table_and_plot() {
    let exe = env!("CARGO_BIN_EXE_flexfmu");
    let dir = std::env::temp_dir().join(format!("flexfmu_advise_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("pendulum_fast.toml");
    let scene = common::scene_path("pendulum");
    let args = [
        "advise",
        scene.to_str().unwrap(),
        "--output",
        "tip.y",
        "--tol",
        "5e-3",
        "--stop-time",
        "0.1",
        "--levels",
        "3",
        "--jobs",
        "1",
        "--keep",
        "solver.integrator",
        "--keep",
        "solver.tolerance",
        "--keep",
        "element.type",
        "-o",
        out.to_str().unwrap(),
    ];
    let r = std::process::Command::new(exe).args(args).output().unwrap();
    let stdout = String::from_utf8_lossy(&r.stdout);
    assert!(
        r.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&r.stderr)
    );
    assert!(
        stdout.contains("| configuration | family | error |"),
        "{stdout}"
    );
    assert!(stdout.contains("observed order p = log2 r"), "{stdout}");
    assert!(
        String::from_utf8_lossy(&r.stderr).contains("advise: ["),
        "progress bar"
    );
    let advised = Scene::from_path(&out).unwrap();
    assert_eq!(advised.model_name(), "pendulum");
    let csv = std::fs::read_to_string(dir.join("pendulum_fast_table.csv")).unwrap();
    assert!(
        csv.starts_with("configuration,family,mesh.n_elements,solver.max_step,error,"),
        "{csv}"
    );
    assert_eq!(
        csv.lines()
            .filter(|l| l.contains(",true,") && l.ends_with(",true,"))
            .count(),
        1,
        "one chosen row\n{csv}"
    );
    let svg = std::fs::read_to_string(dir.join("pendulum_fast_pareto.svg")).unwrap();
    assert!(
        svg.starts_with("<svg") && svg.contains("<polyline"),
        "{svg}"
    );
    let r = std::process::Command::new(exe)
        .args([
            "advise",
            scene.to_str().unwrap(),
            "--output",
            "nope",
            "--tol",
            "1e-3",
        ])
        .output()
        .unwrap();
    assert!(!r.status.success());
    assert!(String::from_utf8_lossy(&r.stderr).contains("its outputs are: tip.x, tip.y"));
    std::fs::remove_dir_all(&dir).unwrap();
}
