//! The serialized initial state shipped in the belt drives' FMI-LS-REF files: set into a fresh
//! instance instead of initializing, it reproduces the smoke test's reference result (made
//! from the normal start: initialization with the static pre-load) step for step.

use flexfmu::fmi2::state_machine::{Call, State};
use flexfmu::instance::Instance;
use flexfmu::logging::Status;
use flexfmu::ls_ref::files::paths;
use flexfmu::ls_ref::{LS_REF_DIR, ls_ref_files};
use flexfmu::scene::Scene;
use flexfmu::variables::{Value, VarType};

fn csv(text: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(|n| n.trim_matches('"').to_string())
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

fn restored_run_matches_reference(scene_file: &str) {
    let path = format!("{}/scenes/{scene_file}", env!("CARGO_MANIFEST_DIR"));
    let scene = Scene::from_path(std::path::Path::new(&path)).unwrap();
    let files = ls_ref_files(&scene).unwrap();
    let get = |rel: &str| {
        let p = format!("{LS_REF_DIR}/{rel}");
        files
            .iter()
            .find(|f| f.path == p)
            .unwrap_or_else(|| panic!("{scene_file}: no {p}"))
            .data
            .clone()
    };
    let state = get(paths::STATE);
    let text = |b: Vec<u8>| String::from_utf8(b).unwrap();
    let (out_names, reference) = csv(&text(get(&format!("experiments/{}", paths::REFERENCE))));
    let (in_names, stimuli) = csv(&text(get(&format!("experiments/{}", paths::STIMULI))));

    let mut inst = Instance::from_scene("restored", scene.clone(), false, Box::new(|_, _, _| {}));
    let vars = inst.variables().clone();
    let vr = |n: &str| vars.by_name(n).unwrap_or_else(|| panic!("{n}")).vr;
    // fmi2Instantiate, then fmi2DeSerializeFMUstate + fmi2SetFMUstate: no initialization
    assert_eq!(
        inst.check_fmu_state(Call::DeSerializeFmuState, &state),
        Ok(())
    );
    assert_eq!(inst.restore_fmu_state(&state), Status::Ok);
    assert_eq!(inst.state(), State::StepComplete);
    let out_vrs: Vec<u32> = out_names[1..].iter().map(|n| vr(n)).collect();
    let in_vrs: Vec<u32> = in_names[1..].iter().map(|n| vr(n)).collect();
    let h = scene.common.experiment.step_size;
    let mut worst = 0.0f64;
    for (k, want) in reference.iter().enumerate() {
        if k > 0 {
            let t = stimuli[k - 1][0];
            for (v, x) in in_vrs.iter().zip(&stimuli[k - 1][1..]) {
                assert_eq!(
                    inst.set(Call::SetReal, &[*v], &[Value::Real(*x)]),
                    Status::Ok
                );
            }
            assert_eq!(inst.do_step(t, h), Status::Ok, "{scene_file}: step at {t}");
        }
        let mut got = vec![0.0; out_vrs.len()];
        let s = inst.get(Call::GetReal, VarType::Real, &out_vrs, &mut |i, v| {
            if let Value::Real(x) = v {
                got[i] = x;
            }
        });
        assert_eq!(s, Status::Ok);
        for ((n, g), w) in out_names[1..].iter().zip(&got).zip(&want[1..]) {
            let err = (g - w).abs() / (1.0 + w.abs());
            worst = worst.max(err);
            assert!(
                err <= 1e-12,
                "{scene_file}: {n} at row {k}: {g} vs reference {w}"
            );
        }
    }
    eprintln!("{scene_file}: largest difference after restoring the state {worst:e}");
}

#[test]
fn belt_drive_starts_from_the_shipped_state() {
    restored_run_matches_reference("belt_drive.toml");
}

#[test]
fn belt_drive_inertia_starts_from_the_shipped_state() {
    restored_run_matches_reference("belt_drive_inertia.toml");
}

#[test]
fn belt_drive_cosim_starts_from_the_shipped_state() {
    restored_run_matches_reference("belt_drive_cosim.toml");
}

/// Only the kinds that ask for it ship a state.
#[test]
fn beams_ship_no_state() {
    let path = format!("{}/scenes/pendulum.toml", env!("CARGO_MANIFEST_DIR"));
    let scene = Scene::from_path(std::path::Path::new(&path)).unwrap();
    let files = ls_ref_files(&scene).unwrap();
    assert!(files.iter().all(|f| !f.path.ends_with(".state")));
    // no inputs: no stimuli file, and the experiment names none
    assert!(files.iter().all(|f| !f.path.ends_with(paths::STIMULI)));
    let exp = files.iter().find(|f| f.path.ends_with(".exp")).unwrap();
    assert!(!String::from_utf8_lossy(&exp.data).contains("<Stimuli"));
}
