//! The axially moving (ALE) belt of the belt-drive kind (`belt.formulation`, issue 12 item 2):
//! the parameter (default Lagrangian, the scenes' other parameters unchanged), the refusals of
//! the scenes outside the ALE model's scope, each naming its key, and the model
//! (`src/kinds/belt_drive/ale_drive.rs`) through `Simulation` as the FMU runs it: steady
//! running at 60 rad/s (stiff belt at 10 N m, soft belt at 20 N m) against the Lagrangian
//! drive run the same way (span tensions and pulley 2's speed within 0.5 %), its torque
//! balance, its creep against Grashof, and the FMU state's round trip.

use flexfmu::kinds::belt_drive::BeltDriveScene;
use flexfmu::kinds::belt_drive::model::BeltDrive;
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::variables::Value;

fn scene_text(name: &str) -> String {
    std::fs::read_to_string(format!("{}/scenes/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

/// The scene `name` with `key = value` added at the end of its `[belt]` table.
fn with_belt_key(name: &str, line: &str) -> String {
    with_belt_key_in(&scene_text(name), line)
}

/// `text` with the Lagrangian belt asked for by name (the shipped serpentine is an ALE belt
/// since session 38).
fn lagrangian(text: &str) -> String {
    with_belt_key_in(text, "formulation = \"lagrangian\"")
}

fn build(text: &str) -> Result<BeltDrive, String> {
    let scene = Scene::from_toml(text).map_err(|e| e.0)?;
    let tables: &BeltDriveScene = scene.tables().unwrap();
    let p = ParamValues::defaults(&scene.params);
    BeltDrive::build(tables, &p)
}

fn formulation(text: &str) -> Option<Value> {
    let scene = Scene::from_toml(text).unwrap();
    ParamValues::defaults(&scene.params).get("belt.formulation")
}

#[test]
fn the_formulation_defaults_to_lagrangian_and_takes_names_and_codes() {
    let plain = scene_text("belt_drive.toml");
    assert_eq!(formulation(&plain), Some(Value::Integer(1)));
    let named = with_belt_key("belt_drive.toml", "formulation = \"lagrangian\"");
    assert_eq!(formulation(&named), Some(Value::Integer(1)));
    let coded = with_belt_key("belt_drive.toml", "formulation = 2");
    assert_eq!(formulation(&coded), Some(Value::Integer(2)));
    let wrong = with_belt_key("belt_drive.toml", "formulation = \"eulerian\"");
    let err = Scene::from_toml(&wrong).err().unwrap().0;
    assert!(err.contains("belt.formulation"), "{err}");
    assert!(err.contains("\"ale\" (2)"), "{err}");
}

#[test]
fn an_explicit_lagrangian_formulation_builds_the_same_drive() {
    use flexfmu::model::Model;
    use flexfmu::snapshot::StateWriter;
    let save = |m: &BeltDrive| {
        let mut w = StateWriter::new();
        m.save(&mut w).unwrap();
        w.bytes().to_vec()
    };
    let a = build(&scene_text("belt_drive.toml")).unwrap();
    let b = build(&with_belt_key(
        "belt_drive.toml",
        "formulation = \"lagrangian\"",
    ))
    .unwrap();
    assert_eq!(save(&a), save(&b));
}

/// In its scope the kind builds the ALE model (`AleDrive`); `BeltDrive::build`, the
/// Lagrangian model's own constructor, refuses the ALE formulation and says where it is.
#[test]
fn the_ale_belt_in_its_scope_is_built_by_the_kind_as_ale_drive() {
    use flexfmu::kinds::belt_drive::ale_drive::AleDrive;
    let text = with_belt_key("belt_drive.toml", "formulation = \"ale\"");
    let err = build(&text).err().unwrap();
    assert!(err.contains("AleDrive"), "{err}");
    let run = Run::new(&text);
    assert!(run.sim.model_as::<AleDrive>().is_some());
    assert!(run.sim.model_as::<BeltDrive>().is_none());
    let lag = Run::new(&scene_text("belt_drive.toml"));
    assert!(lag.sim.model_as::<BeltDrive>().is_some());
}

/// The serpentine drive (tensioner, back-side idlers) and gravity are in the ALE model's
/// scope since session 37 (the Lagrangian constructor names the ALE model).
#[test]
fn the_ale_belt_takes_the_serpentine_and_gravity() {
    let err = build(&with_belt_key("serpentine.toml", "formulation = \"ale\""))
        .err()
        .unwrap();
    assert!(err.contains("AleDrive"), "in scope: {err}");
    let err = build(&with_gravity(&ale_text(), -9.81)).err().unwrap();
    assert!(err.contains("AleDrive"), "in scope: {err}");
    assert!(!err.contains("gravity"), "{err}");
}

/// `text` with gravity `g` [m/s²] along y.
fn with_gravity(text: &str, g: f64) -> String {
    format!("{text}\n[gravity]\nx = 0.0\ny = {g:?}\n")
}

/// The shipped drive under a strong gravity (−100 m/s² along y: the belt's weight 15 N/m, so
/// that the sag moves the span tensions by a few newtons) at 10 N m, 60 rad/s (the protocol of
/// [`Run::steady`]): the ALE drive's T1, T2 and ω2 within 0.5 % of the Lagrangian drive's,
/// and the change of T1 and T2 that gravity causes within 10 % of the Lagrangian drive's (on 200
/// elements, where that change is nearer mesh convergence than on the scene's 100);
/// with 9.81 m/s² the energy balance, the gravity potential in the stored energy, within 1 %
/// of the input work (as without gravity). (The torque balance of
/// [`steady_against_lagrangian`] does not hold under −100 m/s² for either drive: the span
/// tension varies along a sagging span.)
#[test]
fn ale_drive_with_gravity_matches_the_lagrangian_drive() {
    // 200 elements: the slack side's shift is not mesh-converged at the scene's 100 (the
    // Lagrangian drive's −0.630 N there against −0.337 N on 200; `gravity_shift_diagnostic`)
    let plain = scene_text("belt_drive.toml").replace("n_elements = 100", "n_elements = 200");
    assert!(plain.contains("n_elements = 200"));
    let heavy = with_gravity(&plain, -100.0);
    let run = |text: &str| Run::new(text).steady(60.0, 10.0, 1.0);
    let ale = |text: &str| with_belt_key_in(text, "formulation = \"ale\"");
    let (lag0, lag_g) = (run(&plain), run(&heavy));
    let (ale0, ale_g) = (run(&ale(&plain)), run(&ale(&heavy)));
    eprintln!(
        "gravity -100: ALE {ale_g:?} (without {ale0:?}), Lagrangian {lag_g:?} (without {lag0:?})"
    );
    for j in 0..3 {
        assert!(
            (ale_g[j] / lag_g[j] - 1.0).abs() < 5e-3,
            "{j}: ALE {} against Lagrangian {}",
            ale_g[j],
            lag_g[j]
        );
    }
    for j in 0..2 {
        let (da, dl) = (ale_g[j] - ale0[j], lag_g[j] - lag0[j]);
        assert!(dl.abs() > 0.3, "gravity moves the tension: {dl}");
        assert!(
            (da / dl - 1.0).abs() < 0.1,
            "{j}: gravity moves the ALE tension by {da} N, the Lagrangian by {dl} N"
        );
    }
    let light = ale(&with_gravity(&plain, -9.81));
    let v0 = Run::new(&light).out("energy.potential");
    assert!(v0 != 0.0, "the belt has weight: {v0}");
    let (w, de, d) = energy_book(&light);
    let mismatch = w - de - d;
    eprintln!(
        "ALE with gravity: input work {w:.4} J, stored change {de:.4} J, dissipated {d:.4} J, \
         mismatch {mismatch:.3e} J ({:+.3} % of the input)",
        100.0 * mismatch / w
    );
    assert!(mismatch.abs() < 0.01 * w);
}

/// Diagnostic (not a check): the tension shifts of [`ale_drive_with_gravity_matches_the_lagrangian_drive`]
/// with `GD_N` elements and internal steps of at most `GD_H` [s] (both drives).
#[test]
#[ignore = "diagnostic"]
fn gravity_shift_diagnostic() {
    let env = |k: &str, d: &str| std::env::var(k).unwrap_or_else(|_| d.to_string());
    let plain = scene_text("belt_drive.toml")
        .replace(
            "n_elements = 100",
            &format!("n_elements = {}", env("GD_N", "100")),
        )
        .replace(
            "max_step = 1e-3",
            &format!("max_step = {}", env("GD_H", "1e-3")),
        );
    let heavy = with_gravity(&plain, -100.0);
    let run = |text: &str| Run::new(text).steady(60.0, 10.0, 1.0);
    let ale = |text: &str| with_belt_key_in(text, "formulation = \"ale\"");
    for (name, a, b) in [
        ("Lagrangian", plain.clone(), heavy.clone()),
        ("ALE", ale(&plain), ale(&heavy)),
    ] {
        let (t0, tg) = (run(&a), run(&b));
        eprintln!(
            "{name}: gravity shifts T1 by {:.4} N, T2 by {:.4} N (T2 {:.4} N)",
            tg[0] - t0[0],
            tg[1] - t0[1],
            tg[1]
        );
    }
}

#[test]
fn the_ale_belt_refuses_the_shear_element_bending_damping_and_other_integrators() {
    let text = with_belt_key("belt_drive.toml", "formulation = \"ale\"")
        .replace("damping_bending = 0.0", "damping_bending = 0.001");
    let err = build(&text).err().unwrap();
    assert!(err.contains("belt.damping_bending"), "{err}");
    let text = with_belt_key("belt_drive.toml", "formulation = \"ale\"")
        .replace("type = \"ancf_cable_2d\"", "type = \"ancf_shear_2d\"")
        .replace("damping_axial = 20.0", "damping_axial = 0.0");
    let err = build(&text).err().unwrap();
    assert!(err.contains("belt.element"), "{err}");
    let text = with_belt_key("belt_drive.toml", "formulation = \"ale\"").replace(
        "integrator = \"generalized_alpha\"",
        "integrator = \"midpoint\"",
    );
    let err = build(&text).err().unwrap();
    assert!(err.contains("solver.integrator"), "{err}");
    let text = with_belt_key("belt_drive.toml", "formulation = \"ale\"").replace(
        "integrator = \"generalized_alpha\"",
        "integrator = \"newmark\"",
    );
    assert!(
        Run::new(&text)
            .sim
            .model_as::<flexfmu::kinds::belt_drive::ale_drive::AleDrive>()
            .is_some()
    );
}

// ---------------------------------------------------------------------------------------------
// The ALE model through `Simulation` (the path the FMU takes), against the Lagrangian drive.

use flexfmu::model::build_model;
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use flexfmu::variables::Causality;

/// A simulation of scene text `text` (default parameters) and the index of each named input
/// and output.
struct Run {
    sim: Simulation,
    inputs: Vec<String>,
    outputs: Vec<String>,
}

impl Run {
    fn new(text: &str) -> Self {
        let scene = Scene::from_toml(text).map_err(|e| e.0).unwrap();
        let p = ParamValues::defaults(&scene.params);
        let model = build_model(&scene, &p).unwrap();
        let names = |c: Causality| {
            scene
                .io
                .iter()
                .filter(|v| v.causality == c)
                .map(|v| v.name.clone())
                .collect()
        };
        let mut sim = Simulation::new(model, SolverConfig::from_params(&p), 0.0).unwrap();
        sim.initialize().unwrap();
        Self {
            sim,
            inputs: names(Causality::Input),
            outputs: names(Causality::Output),
        }
    }

    fn set(&mut self, name: &str, value: f64) {
        let i = self.inputs.iter().position(|n| n == name).unwrap();
        self.sim.set_input(i, value);
    }

    fn out(&self, name: &str) -> f64 {
        let i = self.outputs.iter().position(|n| n == name).unwrap();
        self.sim.output(i)
    }

    /// The 60 rad/s protocol: pulley 1 ramped to `omega` and the load on pulley 2 to `load`
    /// over 0.3 s, communication step 1 ms, up to `t_end`; returns the means over the last
    /// 0.2 s of T1, T2 (tight, slack span), omega2 and pulley 1's torque.
    fn steady(&mut self, omega: f64, load: f64, t_end: f64) -> [f64; 4] {
        self.steady_at(omega, load, t_end, 1e-3)
    }

    /// [`Self::steady`] with the communication step `h`.
    fn steady_at(&mut self, omega: f64, load: f64, t_end: f64, h: f64) -> [f64; 4] {
        let n = (t_end / h).round() as usize;
        let (mut angle, mut sum, mut k) = (0.0, [0.0; 4], 0);
        for i in 0..n {
            let t = i as f64 * h;
            let ramp = |t: f64| (t / 0.3).min(1.0);
            let w = 0.5 * omega * (ramp(t) + ramp(t + h));
            self.set("pulley1.angle", angle);
            self.set("pulley1.omega", w);
            self.set("pulley2.torque_in", -load * ramp(t));
            self.sim
                .advance(t + h)
                .unwrap_or_else(|e| panic!("t = {t}: {}", e.message));
            angle += w * h;
            if t + h > t_end - 0.2 + 1e-9 {
                let o = [
                    self.out("belt.tension_tight"),
                    self.out("belt.tension_slack"),
                    self.out("pulley2.omega"),
                    self.out("pulley1.torque"),
                ];
                for j in 0..4 {
                    sum[j] += o[j];
                }
                k += 1;
            }
        }
        sum.map(|s| s / k as f64)
    }
}

fn ale_text() -> String {
    with_belt_key("belt_drive.toml", "formulation = \"ale\"")
}

/// `text` with `line` (`key = value`) in its `[belt]` table, replacing the key's line there if
/// the scene has one.
fn with_belt_key_in(text: &str, line: &str) -> String {
    let key = line.split('=').next().unwrap().trim();
    let at = text.find("[belt]").unwrap() + "[belt]".len();
    let end = text[at..].find("\n[").map_or(text.len(), |e| at + e);
    let table: String = text[at..end]
        .lines()
        .filter(|l| l.split('=').next().map(str::trim) != Some(key))
        .collect::<Vec<_>>()
        .join("\n");
    format!("{}\n{line}{table}{}", &text[..at], &text[end..])
}

/// The soft belt of issue 12 (EA 8000 N, pre-tension 400 N, μ 0.5, 120 elements) on the
/// shipped two-pulley drive.
fn soft_belt() -> String {
    scene_text("belt_drive.toml")
        .replace("EA = 5.0e4", "EA = 8000.0")
        .replace("pretension = 300.0", "pretension = 400.0")
        .replace("n_elements = 100", "n_elements = 120")
        .replace("mu = 0.4", "mu = 0.5")
}

/// Steady running at 60 rad/s with the load `load` on pulley 2: the ALE drive's span tensions
/// and pulley 2's speed against the Lagrangian drive of the same scene run the same way
/// (within 0.5 %); its torque balance `(T1 − T2) ρ1` against pulley 1's torque and its creep
/// against Grashof's `(EA + T2)/(EA + T1)`.
fn steady_against_lagrangian(text: &str, load: f64, ea: f64, rho: [f64; 2]) {
    let t_end = 1.0;
    let ale_scene = with_belt_key_in(text, "formulation = \"ale\"");
    let ale = Run::new(&ale_scene).steady(60.0, load, t_end);
    let lag = Run::new(text).steady(60.0, load, t_end);
    eprintln!("load {load}: ALE T1 T2 omega2 tau1 {ale:?}, Lagrangian {lag:?}");
    for (j, what) in ["T1", "T2", "omega2"].iter().enumerate() {
        let rel = ale[j] / lag[j] - 1.0;
        assert!(
            rel.abs() < 5e-3,
            "{what}: ALE {} against Lagrangian {} ({:+.3} %)",
            ale[j],
            lag[j],
            100.0 * rel
        );
    }
    let balance = (ale[0] - ale[1]) * rho[0] / ale[3].abs();
    assert!(
        (balance - 1.0).abs() < 1e-2,
        "(T1 - T2) rho1 / tau1 = {balance}"
    );
    let creep_err = |o: &[f64; 4]| {
        let grashof = (ea + o[1]) / (ea + o[0]);
        let ratio = o[2] * rho[1] / (60.0 * rho[0]);
        (1.0 - ratio) / (1.0 - grashof) - 1.0
    };
    let (ca, cl) = (creep_err(&ale), creep_err(&lag));
    eprintln!(
        "creep against Grashof: ALE {:+.2} %, Lagrangian {:+.2} %",
        100.0 * ca,
        100.0 * cl
    );
    assert!(ca.abs() < 0.05, "creep {ca:+.3} off Grashof");
}

#[test]
fn ale_steady_running_at_10_n_m_matches_the_lagrangian_drive() {
    let text = scene_text("belt_drive.toml");
    steady_against_lagrangian(&text, 10.0, 5e4, [0.082, 0.122]);
}

/// Internal steps of 5 ms (`solver.max_step` = communication step) against 1 ms: span
/// tensions within 0.5 % (issue 12, qa36's finding: before the transported history of the
/// points entering a pulley took the material's wrap off the span's straight line into
/// account, +1.9 / +3.1 % for T1 / T2 while T1 − T2 stayed; after, +0.10 / +0.17 %).
#[test]
fn ale_span_tensions_hold_at_5_ms_internal_steps() {
    let at = |h: f64| {
        let text = ale_text().replace("max_step = 1e-3", &format!("max_step = {h:e}"));
        assert!(text.contains(&format!("max_step = {h:e}")));
        Run::new(&text).steady_at(60.0, 10.0, 0.6, h)
    };
    let (fine, coarse) = (at(1e-3), at(5e-3));
    eprintln!("T1 T2 omega2 tau1 at 1 ms {fine:?}, at 5 ms {coarse:?}");
    for (j, what) in ["T1", "T2", "omega2", "tau1"].iter().enumerate() {
        let rel = coarse[j] / fine[j] - 1.0;
        assert!(
            rel.abs() < 5e-3,
            "{what}: {} at 5 ms against {} at 1 ms ({:+.3} %)",
            coarse[j],
            fine[j],
            100.0 * rel
        );
    }
}

#[test]
fn ale_soft_belt_at_20_n_m_matches_the_lagrangian_drive() {
    let text = soft_belt();
    assert!(text.contains("EA = 8000.0") && text.contains("n_elements = 120"));
    steady_against_lagrangian(&text, 20.0, 8000.0, [0.082, 0.122]);
}

/// The state of a running ALE drive saved, restored into a model built to restore (no
/// pre-load) and both advanced by 20 steps: the same bytes (and the restored model is not the
/// same before the restore).
#[test]
fn ale_state_round_trip_through_simulation() {
    use flexfmu::model::build_model_to_restore;
    use flexfmu::snapshot::{StateReader, StateWriter};
    let text = ale_text();
    let mut a = Run::new(&text);
    a.steady(60.0, 10.0, 0.35);
    let mut w = StateWriter::new();
    a.sim.save(&mut w).unwrap();
    let state = w.bytes().to_vec();
    let scene = Scene::from_toml(&text).map_err(|e| e.0).unwrap();
    let p = ParamValues::defaults(&scene.params);
    let model = build_model_to_restore(&scene, &p).unwrap();
    let mut sim = Simulation::new(model, SolverConfig::from_params(&p), 0.0).unwrap();
    let mut w0 = StateWriter::new();
    sim.save(&mut w0).unwrap();
    assert_ne!(
        w0.bytes(),
        &state[..],
        "a fresh model has the saved state already"
    );
    let mut r = StateReader::new(&state);
    sim.restore(&mut r).unwrap();
    assert!(r.finished());
    let mut b = Run {
        sim,
        inputs: a.inputs.clone(),
        outputs: a.outputs.clone(),
    };
    let mut w1 = StateWriter::new();
    b.sim.save(&mut w1).unwrap();
    assert_eq!(w1.bytes(), &state[..], "restore then save");
    for run in [&mut a, &mut b] {
        let mut t = 0.35;
        for _ in 0..20 {
            run.set("pulley1.omega", 60.0);
            run.set("pulley2.torque_in", -10.0);
            run.sim.advance(t + 1e-3).unwrap();
            t += 1e-3;
        }
    }
    let (mut wa, mut wb) = (StateWriter::new(), StateWriter::new());
    a.sim.save(&mut wa).unwrap();
    b.sim.save(&mut wb).unwrap();
    assert_eq!(
        wa.bytes(),
        wb.bytes(),
        "the states 20 steps after the restore differ"
    );
    assert_eq!(a.out("belt.tension_tight"), b.out("belt.tension_tight"));
}

/// `belt_drive_inertia.toml` (both pulleys free: pulley 1 driven by a motor torque ramped to
/// 4 N m over 0.3 s, pulley 2 loaded by its bearing damping only) after 1 s, as the ALE and the
/// Lagrangian drive run it: both pulleys' speeds and the span tensions within 0.5 %.
#[test]
fn ale_drive_with_two_free_pulleys_matches_the_lagrangian_drive() {
    let run = |text: &str| {
        let mut r = Run::new(text);
        let h = 1e-3;
        for i in 0..1000 {
            let t = i as f64 * h;
            r.set("pulley1.torque_in", 4.0 * (t / 0.3).min(1.0));
            r.set("pulley2.torque_in", 0.0);
            r.sim.advance(t + h).unwrap();
        }
        [
            r.out("pulley1.omega"),
            r.out("pulley2.omega"),
            r.out("belt.tension_tight"),
            r.out("belt.tension_slack"),
        ]
    };
    let text = scene_text("belt_drive_inertia.toml");
    let lag = run(&text);
    let ale = run(&with_belt_key_in(&text, "formulation = \"ale\""));
    eprintln!("omega1 omega2 T1 T2: ALE {ale:?}, Lagrangian {lag:?}");
    assert!(lag[1] > 10.0, "the drive runs: {lag:?}");
    for j in 0..4 {
        assert!(
            (ale[j] / lag[j] - 1.0).abs() < 5e-3,
            "{j}: ALE {} against Lagrangian {}",
            ale[j],
            lag[j]
        );
    }
}

/// The energy book of a run of `text` with generalized-α at ρ∞ = 1 (no numerical damping),
/// internal steps of at most 0.25 ms and no bearing damping on pulley 2 (the shipped 0.2 N m s
/// would dissipate 129 J of the 141 J of input work, hiding the belt's own terms): pulley 1
/// ramped to 60 rad/s and the load on pulley 2 to 10 N m over 0.3 s, then steady running to
/// 0.6 s, communication step 1 ms. Between the end of the first step and the end (the
/// Lagrangian drive's contact book starts at its first step): input work `W`, change of the
/// stored energy `ΔE` (`energy.total`: kinetic, strain and contact penalty) and dissipated
/// energy `D`; returns `(W, ΔE, D)`.
fn energy_book(text: &str) -> (f64, f64, f64) {
    let text = text
        .replace("rho_inf = 0.8", "rho_inf = 1.0")
        .replace("max_step = 1e-3", "max_step = 2.5e-4")
        .replace("damping = 0.2", "damping = 0.0");
    let mut r = Run::new(&text);
    let book = booked_ramp(&mut r, 600, 0.3, &[("pulley2.torque_in", -10.0)]);
    if let Some(a) = r
        .sim
        .model_as::<flexfmu::kinds::belt_drive::ale_drive::AleDrive>()
    {
        eprintln!(
            "ALE: sliding work (taken off the dissipated energy) {:.4} J",
            a.sliding_work()
        );
    }
    book
}

/// Runs `r` for `steps` communication steps of 1 ms: pulley 1 ramped to 60 rad/s and the
/// torque inputs `loads` (name, final value [N m]) to their values over `ramp_time` [s]. The
/// energy book between the end of the first step and the end: input work `W`, change of the
/// stored energy `ΔE` (`energy.total`) and dissipated energy `D`, `(W, ΔE, D)`.
fn booked_ramp(
    r: &mut Run,
    steps: usize,
    ramp_time: f64,
    loads: &[(&str, f64)],
) -> (f64, f64, f64) {
    let read = |r: &Run| {
        [
            r.out("energy.input_work"),
            r.out("energy.total"),
            r.out("energy.dissipated"),
        ]
    };
    let h = 1e-3;
    let (mut angle, mut first) = (0.0, None);
    for i in 0..steps {
        let t = i as f64 * h;
        let ramp = |t: f64| (t / ramp_time).min(1.0);
        let w = 0.5 * 60.0 * (ramp(t) + ramp(t + h));
        r.set("pulley1.angle", angle);
        r.set("pulley1.omega", w);
        for &(name, load) in loads {
            r.set(name, load * ramp(t));
        }
        r.sim
            .advance(t + h)
            .unwrap_or_else(|e| panic!("t = {t}: {}", e.message));
        angle += w * h;
        first.get_or_insert(read(r));
    }
    let (a, b) = (first.unwrap(), read(r));
    (b[0] - a[0], b[1] - a[1], b[2] - a[2])
}

/// Energy balance of the ALE drive (issue 12 item 4) over a spin-up and steady running under
/// load: the input work (pulley work plus the sliding work of the ALE gauge) equals the change
/// of kinetic (material velocity `S q̇ + v S' q`), strain and contact penalty energy plus the
/// dissipation (friction work, contact damping, the material damping with its convective rate)
/// within 1 % of the input work; the Lagrangian drive of the same scene run the same way for
/// comparison (same bound). Measured (session 36): ALE +0.05 %, Lagrangian −0.53 %; without
/// the friction work the ALE figure is +2.3 %, without the sliding work −1.5 %.
#[test]
fn ale_energy_balance_against_the_lagrangian_drive() {
    let text = scene_text("belt_drive.toml");
    assert!(text.contains("rho_inf = 0.8") && text.contains("max_step = 1e-3"));
    assert_eq!(text.matches("damping = 0.2").count(), 1);
    let mut shares = Vec::new();
    for (name, scene) in [("ALE", ale_text()), ("Lagrangian", text)] {
        let (w, de, d) = energy_book(&scene);
        let mismatch = w - de - d;
        let share = mismatch / w;
        eprintln!(
            "{name}: input work {w:.4} J, stored change {de:.4} J, dissipated {d:.4} J, \
             mismatch {mismatch:.3e} J ({:+.3} % of the input)",
            100.0 * share
        );
        assert!(w > 5.0, "{name}: the drive does work: {w}");
        assert!(d > 0.02 * w, "{name}: dissipation {d} J of {w} J");
        shares.push(share);
    }
    for (name, s) in ["ALE", "Lagrangian"].iter().zip(&shares) {
        assert!(
            s.abs() < 0.01,
            "{name}: mismatch {:+.3} % of the input",
            100.0 * s
        );
    }
}

/// The shipped two-pulley drive with a back-side idler (pulley 3, radius 40 mm, free, light)
/// pressing the upper span down from outside the loop by about 20 mm.
fn back_idler() -> String {
    let text = scene_text("belt_drive.toml");
    let at = text.find("[outputs]").unwrap();
    format!(
        "{}[[pulley]]\ncenter = [0.25, 0.14]\nradius = 0.04\nmode = \"free\"\nside = \"back\"\ninertia = 1.0e-4\ndamping = 1.0e-4\n\n{}",
        &text[..at],
        &text[at..]
    )
}

/// A three-pulley drive with a back-side idler (200 elements), run by the 60 rad/s protocol at
/// 10 N m: the ALE drive's span tensions and the speeds of pulley 2 and of the idler against
/// the Lagrangian drive within 0.5 %, and the idler turning the other way (clockwise) at the
/// belt's speed. Measured when written (T1, T2, idler speed, ALE against Lagrangian): 200
/// elements at 1 ms −0.06 %, −0.12 %, +0.41 %; at 0.25 ms internal steps +0.01 %, −0.004 %,
/// −0.05 %. With 100 elements at 1 ms the Lagrangian drive's T1 is 0.45 % above its own
/// 200-element, 0.25 ms value (the idler's wrap is 2-3 elements long), the ALE drive's 0.09 %
/// below it.
#[test]
fn ale_drive_with_a_back_side_idler_matches_the_lagrangian_drive() {
    let text = back_idler().replace("n_elements = 100", "n_elements = 200");
    assert!(text.contains("n_elements = 200"));
    let run = |text: &str| {
        let mut r = Run::new(text);
        let o = r.steady(60.0, 10.0, 1.0);
        let spans: Vec<f64> = (1..=3)
            .map(|i| r.out(&format!("span{i}.tension")))
            .collect();
        (o, spans, r.out("pulley3.omega"))
    };
    let (lag, lag_spans, lag_w3) = run(&text);
    let (ale, ale_spans, ale_w3) = run(&with_belt_key_in(&text, "formulation = \"ale\""));
    eprintln!(
        "T1 T2 omega2 tau1: ALE {ale:?}, Lagrangian {lag:?}; spans ALE {ale_spans:?}, Lagrangian {lag_spans:?}; omega3 ALE {ale_w3}, Lagrangian {lag_w3}"
    );
    let v = 60.0 * 0.082;
    assert!(
        lag_w3 < -0.9 * v / 0.042 && lag_w3 > -1.1 * v / 0.042,
        "the idler turns clockwise at the belt speed: {lag_w3}"
    );
    let mut pairs: Vec<(String, f64, f64)> = ["T1", "T2", "omega2"]
        .iter()
        .enumerate()
        .map(|(j, w)| (w.to_string(), ale[j], lag[j]))
        .collect();
    for (i, (a, l)) in ale_spans.iter().zip(&lag_spans).enumerate() {
        pairs.push((format!("span{}", i + 1), *a, *l));
    }
    pairs.push(("omega3".into(), ale_w3, lag_w3));
    for (what, a, l) in pairs {
        let rel = a / l - 1.0;
        assert!(
            rel.abs() < 5e-3,
            "{what}: ALE {a} against Lagrangian {l} ({:+.3} %)",
            100.0 * rel
        );
    }
}

/// Diagnostic (not a check): the axial force `EA (|r'| − 1)` at every element's middle of the
/// serpentine drive after a ramp of the crank to `SERP_W` rad/s (ALE and Lagrangian).
/// `SERP_REPLACE="old=>new;..."` edits the scene text (damping, contact points, radii);
/// `SERP_FINE=1` adds the strain [1e-5] and `u·r''` [1/m] at five points along each element.
#[test]
#[ignore = "diagnostic"]
fn serpentine_axial_force_profile() {
    use flexfmu::kinds::belt_drive::ale_drive::AleDrive;
    let w: f64 = std::env::var("SERP_W").map_or(300.0, |s| s.parse().unwrap());
    for ale in [true, false] {
        let mut text = scene_text("serpentine.toml");
        // SERP_REPLACE="old=>new;old2=>new2": textual edits of the scene (diagnostic variants).
        if let Ok(edits) = std::env::var("SERP_REPLACE") {
            for e in edits.split(';').filter(|e| !e.is_empty()) {
                let (a, b) = e.split_once("=>").unwrap();
                assert!(text.contains(a), "{a} not in the scene");
                text = text.replace(a, b);
            }
        }
        let text = if ale {
            with_belt_key_in(&text, "formulation = \"ale\"")
        } else {
            lagrangian(&text)
        };
        let mut r = Run::new(&text);
        let h = 1e-3;
        let mut angle = 0.0;
        for i in 0..500 {
            let t = i as f64 * h;
            let om = w * (t / 0.3).min(1.0);
            r.set("pulley1.angle", angle);
            r.set("pulley1.omega", om);
            r.sim.advance(t + h).unwrap();
            angle += om * h;
        }
        let (q, l, n): (Vec<f64>, f64, usize) = if ale {
            let d = r.sim.model_as::<AleDrive>().unwrap();
            (d.mesh().to_vec(), d.element_length(), d.mesh().len() / 4)
        } else {
            let d = r.sim.model_as::<BeltDrive>().unwrap();
            let n = d.n_elements();
            (d.coordinates()[..4 * n].to_vec(), d.element_length(), n)
        };
        let spans: Vec<f64> = (1..=7)
            .map(|i| r.out(&format!("span{i}.tension")))
            .collect();
        eprintln!("{} spans {spans:?}", if ale { "ALE" } else { "Lagrangian" });
        for e in 0..n {
            let (a, b) = (4 * e, 4 * ((e + 1) % n));
            let (r0, r1) = ([q[a], q[a + 1]], [q[b], q[b + 1]]);
            let (t0, t1) = ([q[a + 2], q[a + 3]], [q[b + 2], q[b + 3]]);
            let rp = [
                1.5 * (r1[0] - r0[0]) / l - 0.25 * (t0[0] + t1[0]),
                1.5 * (r1[1] - r0[1]) / l - 0.25 * (t0[1] + t1[1]),
            ];
            let eps = (rp[0] * rp[0] + rp[1] * rp[1]).sqrt() - 1.0;
            // SERP_FINE: the strain at five points along the element [1e-5] and u·r'' [1/m]
            let fine = if std::env::var("SERP_FINE").is_ok() {
                let mut out = String::new();
                for k in 0..=4 {
                    let xi = k as f64 / 4.0;
                    // cubic Hermite derivatives on [0, l]
                    let d1 = [
                        (6.0 * xi * xi - 6.0 * xi) / l,
                        3.0 * xi * xi - 4.0 * xi + 1.0,
                        (-6.0 * xi * xi + 6.0 * xi) / l,
                        3.0 * xi * xi - 2.0 * xi,
                    ];
                    let d2 = [
                        (12.0 * xi - 6.0) / (l * l),
                        (6.0 * xi - 4.0) / l,
                        (-12.0 * xi + 6.0) / (l * l),
                        (6.0 * xi - 2.0) / l,
                    ];
                    let c = |d: &[f64; 4], i: usize| {
                        d[0] * r0[i] + d[1] * t0[i] + d[2] * r1[i] + d[3] * t1[i]
                    };
                    let (a1, b1) = (c(&d1, 0), c(&d1, 1));
                    let (a2, b2) = (c(&d2, 0), c(&d2, 1));
                    let nn = (a1 * a1 + b1 * b1).sqrt();
                    out += &format!(" {:.1}/{:.3}", 1e5 * (nn - 1.0), (a1 * a2 + b1 * b2) / nn);
                }
                out
            } else {
                String::new()
            };
            eprintln!(
                "{} {e} {:.4} {:.4} {:.2}{fine}",
                if ale { "A" } else { "L" },
                0.5 * (r0[0] + r1[0]),
                0.5 * (r0[1] + r1[1]),
                1e5 * eps
            );
        }
    }
}

/// Diagnostic (not a check): span tensions of the two-pulley drive and of the drive with a
/// back-side idler at `SERP_W` rad/s (no load), ALE against Lagrangian, 1 ms.
#[test]
#[ignore = "diagnostic"]
fn span_tensions_at_speed() {
    let w: f64 = std::env::var("SERP_W").map_or(300.0, |s| s.parse().unwrap());
    for (name, text) in [
        ("two pulleys", scene_text("belt_drive.toml")),
        ("back idler", back_idler()),
    ] {
        for ale in [true, false] {
            let t = if ale {
                with_belt_key_in(&text, "formulation = \"ale\"")
            } else {
                text.clone()
            };
            let mut r = Run::new(&t);
            let o = r.steady(w, 0.0, 0.6);
            let spans: Vec<f64> = (1..=3)
                .filter_map(|i| {
                    r.outputs
                        .iter()
                        .position(|n| n == &format!("span{i}.tension"))
                        .map(|k| r.sim.output(k))
                })
                .collect();
            eprintln!(
                "{name} {} T1 T2 omega2 tau1 {o:?} spans {spans:?}",
                if ale { "ALE" } else { "Lagrangian" }
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The serpentine drive (tensioner, back-side idlers) on the ALE belt (session 37).

fn serpentine_ale() -> String {
    with_belt_key("serpentine.toml", "formulation = \"ale\"")
}

/// One communication step `h` from `t` of the serpentine protocol: the crank ramped to `omega`
/// [rad/s] over 0.1 s (its angle `angle` advanced with the step's mean speed), the A/C
/// compressor's load to 5 N m over the same time.
fn serpentine_step(r: &mut Run, t: f64, h: f64, omega: f64, angle: &mut f64) {
    let ramp = |t: f64| (t / 0.1).min(1.0);
    let w = 0.5 * omega * (ramp(t) + ramp(t + h));
    r.set("pulley1.angle", *angle);
    r.set("pulley1.omega", w);
    r.set("pulley7.torque_in", -5.0 * ramp(t));
    r.sim
        .advance(t + h)
        .unwrap_or_else(|e| panic!("t = {t}: {}", e.message));
    *angle += w * h;
}

/// The serpentine scene `text` with `solver.max_step` = `h_max`: the crank ramped to `omega`
/// over 0.1 s, the A/C compressor's load to 5 N m over the same time, steady running to
/// 0.4 s (communication step 1 ms); the means over the last 0.1 s of the speeds of pulleys
/// 2..7, the tensioner angle and the tensions of spans 1..7.
fn serpentine_steady(text: &str, h_max: f64, omega: f64) -> Vec<f64> {
    let text = text.replace("max_step = 1e-3", &format!("max_step = {h_max:e}"));
    assert!(text.contains(&format!("max_step = {h_max:e}")));
    let mut r = Run::new(&text);
    let names: Vec<String> = (2..=7)
        .map(|k| format!("pulley{k}.omega"))
        .chain(["tensioner.angle".to_string()])
        .chain((1..=7).map(|k| format!("span{k}.tension")))
        .collect();
    let (h, t_end): (f64, f64) = (1e-3, 0.4);
    let (mut angle, mut sum, mut k) = (0.0, vec![0.0; names.len()], 0);
    for i in 0..(t_end / h).round() as usize {
        let t = i as f64 * h;
        serpentine_step(&mut r, t, h, omega, &mut angle);
        if t + h > t_end - 0.1 + 1e-9 {
            for (s, n) in sum.iter_mut().zip(&names) {
                *s += r.out(n);
            }
            k += 1;
        }
    }
    sum.iter().map(|s| s / k as f64).collect()
}

/// The serpentine drive at a steady 800 rpm of the crank with the A/C compressor loaded
/// (5 N m): the ALE drive at the scene's 1 ms steps against the Lagrangian drive at internal
/// steps of at most 0.1 ms (reference), means over 0.3-0.4 s: the six pulley speeds within
/// 0.5 %, the tensioner angle within 2 %, span tensions within 2 %.
#[test]
fn ale_serpentine_at_800_rpm_matches_the_lagrangian_drive() {
    let omega = 800.0 * std::f64::consts::PI / 30.0;
    let ale = serpentine_steady(&serpentine_ale(), 1e-3, omega);
    let lag = serpentine_steady(&lagrangian(&scene_text("serpentine.toml")), 1e-4, omega);
    let what = |j: usize| match j {
        0..6 => format!("pulley{}.omega", j + 2),
        6 => "tensioner.angle".into(),
        _ => format!("span{}.tension", j - 6),
    };
    let mut worst = Vec::new();
    for j in 0..ale.len() {
        let rel = ale[j] / lag[j] - 1.0;
        eprintln!(
            "{:16} ALE {:12.6} Lagrangian (0.1 ms) {:12.6} ({:+.3} %)",
            what(j),
            ale[j],
            lag[j],
            100.0 * rel
        );
        let bound = if j < 6 { 5e-3 } else { 2e-2 };
        if rel.abs() >= bound {
            worst.push(format!("{} {:+.3} %", what(j), 100.0 * rel));
        }
    }
    assert!(worst.is_empty(), "off: {worst:?}");
}

/// The ALE serpentine at a steady 800 rpm (the protocol of [`serpentine_steady`], 1 ms):
/// Newton iterations and factorizations per step over 0.3-0.4 s. The integrator's start of a
/// step carries the old acceleration on, which jumps from step to step at the arc ends and on
/// the light back-side idlers; the ALE drive starts from `q₀ + h v₀` while that lands closer
/// (here 7.74 iterations and 3.73 factorizations per step with the integrator's start
/// always, 2.3 and 0.26 with that rule).
#[test]
fn ale_serpentine_at_800_rpm_iterates_little() {
    let mut r = Run::new(&serpentine_ale());
    let omega = 800.0 * std::f64::consts::PI / 30.0;
    let h = 1e-3;
    let mut angle = 0.0;
    let mut s0 = r.sim.stats();
    for i in 0..400 {
        let t = i as f64 * h;
        if i == 300 {
            s0 = r.sim.stats();
        }
        serpentine_step(&mut r, t, h, omega, &mut angle);
    }
    let s = r.sim.stats();
    let it = (s.newton.iterations - s0.newton.iterations) as f64 / 100.0;
    let fact = (s.newton.factorizations - s0.newton.factorizations) as f64 / 100.0;
    eprintln!("per step: {it} iterations, {fact} factorizations");
    assert!(
        it < 3.5 && fact < 1.0,
        "{it} iterations, {fact} factorizations per step"
    );
}

/// Diagnostic (not a check): [`serpentine_steady`] at `SERP_RPM` of the crank, ALE at 1 ms
/// and `SERP_ALE_H` internal steps against the Lagrangian drive at `SERP_LAG_H`.
#[test]
#[ignore = "diagnostic"]
fn serpentine_steady_at_speed() {
    let env = |k: &str, d: f64| std::env::var(k).map_or(d, |s| s.parse().unwrap());
    let omega = env("SERP_RPM", 3000.0) * std::f64::consts::PI / 30.0;
    let n = format!("n_elements = {}", env("SERP_N", 120.0));
    let n_lag = format!("n_elements = {}", env("SERP_LAG_N", env("SERP_N", 120.0)));
    // SERP_PRE: the pre-tension [N]; SERP_FORM: `ale` or `lag` runs only that drive (the other
    // column repeats it)
    let pre = format!("pretension = {:.1} ", env("SERP_PRE", 350.0));
    let form = std::env::var("SERP_FORM").unwrap_or_default();
    let edit = |t: String, n: &str| {
        t.replace("n_elements = 120", n)
            .replace("pretension = 350.0 ", &pre)
    };
    let ale = (form != "lag")
        .then(|| serpentine_steady(&edit(serpentine_ale(), &n), env("SERP_ALE_H", 1e-3), omega));
    let lag = (form != "ale").then(|| {
        serpentine_steady(
            &edit(lagrangian(&scene_text("serpentine.toml")), &n_lag),
            env("SERP_LAG_H", 1e-4),
            omega,
        )
    });
    let (ale, lag) = match (ale, lag) {
        (Some(a), Some(l)) => (a, l),
        (Some(a), None) => (a.clone(), a),
        (None, Some(l)) => (l.clone(), l),
        (None, None) => unreachable!(),
    };
    for j in 0..ale.len() {
        eprintln!(
            "{j:2} ALE {:12.6} Lagrangian {:12.6} ({:+.3} %)",
            ale[j],
            lag[j],
            100.0 * (ale[j] / lag[j] - 1.0)
        );
    }
}

/// Energy balance of the ALE serpentine drive (tensioner spring, damper and arm inertia in the
/// book): the protocol of `belt_serpentine.rs`'s `energy_balance_of_the_serpentine_drive`
/// (ρ∞ = 1, internal steps of at most 0.25 ms, the crank ramped to 60 rad/s over 0.2 s with
/// 2 and 4 N m ramped on the alternator and the A/C compressor, to 0.35 s), booked from the
/// end of the first step: input work = change of the stored energy + dissipated, within 1 %
/// of the input work (the Lagrangian drive's bound there).
#[test]
fn ale_serpentine_energy_balance() {
    let text = serpentine_ale()
        .replace("rho_inf = 0.8", "rho_inf = 1.0")
        .replace("max_step = 1e-3", "max_step = 2.5e-4");
    assert!(text.contains("rho_inf = 1.0") && text.contains("max_step = 2.5e-4"));
    let mut r = Run::new(&text);
    let (w, de, d) = booked_ramp(
        &mut r,
        350,
        0.2,
        &[("pulley6.torque_in", -2.0), ("pulley7.torque_in", -4.0)],
    );
    let mismatch = w - de - d;
    eprintln!(
        "ALE serpentine: input work {w:.4} J, stored change {de:.4} J, dissipated {d:.4} J, \
         mismatch {mismatch:.3e} J ({:+.3} % of the input), tensioner angle {:.5} rad, torque {:.4} N m",
        100.0 * mismatch / w,
        r.out("tensioner.angle"),
        r.out("tensioner.torque")
    );
    assert!(w > 1.0 && d > 0.0, "the drive does work: {w}, {d}");
    assert!(mismatch.abs() < 0.01 * w, "mismatch {mismatch} of {w}");
}

/// Diagnostic (not a check): the energy book of the ALE drive against the Lagrangian drive,
/// with the dissipation split (friction, contact normal damping, belt material, bearings and
/// tensioner) and the ALE drive's work through the belt travel. `TW_SCENE` (`belt_drive` or
/// `serpentine`), `TW_N` elements, `TW_H` internal step, `TW_MU`, `TW_DA` (`damping_axial`),
/// `TW_W` driver speed [rad/s], `TW_T` end [s], `TW_RHO` (ρ∞, default 1); the driver ramped
/// over 0.2 s with the loads of the energy-balance tests, booked from the end of the first
/// step; `TW_FORM` (`ale`, `lag` or both).
#[test]
#[ignore = "diagnostic"]
fn travel_work_diagnostic() {
    use flexfmu::kinds::belt_drive::ale_drive::AleDrive;
    let env = |k: &str, d: &str| std::env::var(k).unwrap_or_else(|_| d.to_string());
    let scene = env("TW_SCENE", "belt_drive");
    let serp = scene == "serpentine";
    let mut text = scene_text(&format!("{scene}.toml"));
    let mut edit = |a: &str, b: String| {
        assert!(text.contains(a), "{a}");
        text = text.replacen(a, &b, 1);
    };
    let n0 = if serp {
        "n_elements = 120"
    } else {
        "n_elements = 100"
    };
    edit(n0, format!("n_elements = {}", env("TW_N", &n0[13..])));
    edit(
        "max_step = 1e-3",
        format!("max_step = {}", env("TW_H", "2.5e-4")),
    );
    edit(
        "rho_inf = 0.8",
        format!("rho_inf = {}", env("TW_RHO", "1.0")),
    );
    let mu0 = if serp { "mu = 0.5 " } else { "mu = 0.4" };
    edit(mu0, format!("mu = {} ", env("TW_MU", &mu0[5..])));
    edit(
        "damping_axial = 20.0",
        format!("damping_axial = {}", env("TW_DA", "20.0")),
    );
    if !serp {
        // the pulley bearing (0.2 N m s), off as in the energy-balance test (`TW_BD`)
        edit(
            "damping = 0.2",
            format!("damping = {}", env("TW_BD", "0.0")),
        );
    }
    let w_end: f64 = env("TW_W", "60").parse().unwrap();
    let t_end: f64 = env("TW_T", if serp { "0.35" } else { "0.6" })
        .parse()
        .unwrap();
    let forms = env("TW_FORM", "both");
    for ale in [true, false] {
        if (ale && forms == "lag") || (!ale && forms == "ale") {
            continue;
        }
        let text = if ale {
            with_belt_key_in(&text, "formulation = \"ale\"")
        } else {
            lagrangian(&text)
        };
        let mut r = Run::new(&text);
        let read = |r: &Run| {
            let (sw, split, ts) = match r.sim.model_as::<AleDrive>() {
                Some(a) => (a.sliding_work(), a.dissipation_split(), a.travel_split()),
                None => (
                    0.0,
                    r.sim.model_as::<BeltDrive>().unwrap().dissipation_split(),
                    [0.0; 3],
                ),
            };
            [
                r.out("energy.input_work"),
                r.out("energy.total"),
                r.out("energy.dissipated"),
                sw,
                split[0],
                split[1],
                split[2],
                split[3],
                ts[0],
                ts[1],
                ts[2],
            ]
        };
        let h = 1e-3;
        let (mut angle, mut first, mut late) = (0.0, None, None);
        let steps = (t_end / h).round() as usize;
        for i in 0..steps {
            let t = i as f64 * h;
            let ramp = |t: f64| (t / 0.2).min(1.0);
            let w = 0.5 * w_end * (ramp(t) + ramp(t + h));
            r.set("pulley1.angle", angle);
            r.set("pulley1.omega", w);
            if serp {
                r.set("pulley6.torque_in", -2.0 * ramp(t));
                r.set("pulley7.torque_in", -4.0 * ramp(t));
            } else {
                r.set("pulley2.torque_in", -10.0 * ramp(t));
            }
            r.sim
                .advance(t + h)
                .unwrap_or_else(|e| panic!("t = {t}: {}", e.message));
            angle += w * h;
            first.get_or_insert(read(&r));
            if i + 1 == steps - 100 {
                late = Some(read(&r));
            }
        }
        let (a, b, c) = (first.unwrap(), read(&r), late.unwrap());
        let st = r.sim.stats();
        eprintln!(
            "  Newton: {:.3} iterations, {:.3} factorizations per step",
            st.newton.iterations as f64 / steps as f64,
            st.newton.factorizations as f64 / steps as f64
        );
        let d: Vec<f64> = (0..11).map(|j| b[j] - a[j]).collect();
        let p: Vec<f64> = (0..11).map(|j| (b[j] - c[j]) / 0.1).collect();
        eprintln!(
            "  travel work split: momentum {:.4} contact {:.4} damping {:.4} J",
            d[8], d[9], d[10]
        );
        eprintln!(
            "{} {scene} N {} h {} mu {} da {} w {w_end}: W {:.4} port {:.4} travel {:.4} dE {:.4} \
             D {:.4} [fric {:.4} norm {:.4} mat {:.4} bear {:.4}] mismatch {:+.3} % | last 0.1 s \
             power: in {:.2} port {:.2} travel {:.2} D {:.2} [fric {:.2} norm {:.2} mat {:.2} \
             bear {:.2}] W, travel [momentum {:.2} contact {:.2} damping {:.2}] W",
            if ale { "ALE" } else { "LAG" },
            env("TW_N", &n0[13..]),
            env("TW_H", "2.5e-4"),
            env("TW_MU", &mu0[5..]),
            env("TW_DA", "20.0"),
            d[0],
            d[0] - d[3],
            d[3],
            d[1],
            d[2],
            d[4],
            d[5],
            d[6],
            d[7],
            100.0 * (d[0] - d[1] - d[2]) / d[0],
            p[0],
            p[0] - p[3],
            p[3],
            p[2],
            p[4],
            p[5],
            p[6],
            p[7],
            p[8],
            p[9],
            p[10]
        );
    }
}
