//! The C ABI itself: random call sequences with random (and hostile) arguments, and instances
//! running in parallel threads. Calls go through the exported `extern "C"` functions exactly as
//! an importer makes them (with a NULL logger: a C-variadic logger cannot be written in stable
//! Rust; the fmpy tests exercise the logger).

use flexfmu::fmi2::exports::*;
use flexfmu::fmi2::types::*;
use flexfmu::model_description::scene_guid;
use flexfmu::scene::Scene;
use std::ffi::CString;
use std::path::PathBuf;
use std::ptr;

mod common;
#[path = "fuzz_harness/mod.rs"]
mod fuzz;

/// A resources directory holding the scene, and the scene's GUID.
fn resources(name: &str) -> (PathBuf, String) {
    let scene: Scene = common::scene(name);
    static COUNTER: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("flexfmu-cabi-{}-{k}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("scene.toml"), &scene.text).unwrap();
    (dir, scene_guid(&scene))
}

fn callbacks() -> Fmi2CallbackFunctions {
    Fmi2CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: ptr::null_mut(),
    }
}

struct Fmu {
    guid: CString,
    uri: CString,
    cb: Box<Fmi2CallbackFunctions>,
}

impl Fmu {
    fn new(name: &str) -> Self {
        let (dir, guid) = resources(name);
        Self {
            guid: CString::new(guid).unwrap(),
            uri: CString::new(format!("file://{}", dir.display())).unwrap(),
            cb: Box::new(callbacks()),
        }
    }

    fn instantiate(&self, name: &str) -> Fmi2Component {
        let n = CString::new(name).unwrap();
        // SAFETY: valid C strings and callbacks that outlive the instance.
        unsafe {
            fmi2Instantiate(
                n.as_ptr(),
                FMI2_COSIMULATION,
                self.guid.as_ptr(),
                self.uri.as_ptr(),
                &*self.cb,
                0,
                0,
            )
        }
    }
}

/// A slice of the FMI call-sequence fuzzer (`tests/fuzz_harness`; the full run of 100,000
/// sequences is `cargo run --release --example fuzz_fmi`): random call sequences over every
/// shipped scene with hostile arguments. Every call returns a valid status and never fmi2Fatal,
/// no sequence hangs, and the slice reaches what it is meant to reach: every scene steps, every
/// function is called, resets happen in every state, damaged and foreign serialized states are
/// rejected and intact ones accepted.
#[test]
fn random_call_sequences_never_crash() {
    let harness = fuzz::Harness::new();
    let shipped = std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes"))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .is_ok_and(|e| e.path().extension().is_some_and(|x| x == "toml"))
        })
        .count();
    assert!(shipped >= 13, "shipped scenes: {shipped}");
    assert_eq!(harness.fmus.len(), shipped, "every shipped scene");
    let cfg = fuzz::Config {
        sequences: 3000,
        seed: 0x5eed_f00d,
        threads: 2,
        ..fuzz::Config::default()
    };
    let sum = harness.run(&cfg);
    println!("{}", sum.report());
    assert!(sum.passed(), "{}", sum.report());
    assert_eq!(sum.sequences, cfg.sequences);
    for f in &harness.fmus {
        let steps = sum.ok_steps_by_scene.get(&f.name).copied().unwrap_or(0);
        assert!(steps >= 20, "{}: only {steps} successful steps", f.name);
    }
    for f in [
        "fmi2SetupExperiment",
        "fmi2EnterInitializationMode",
        "fmi2ExitInitializationMode",
        "fmi2DoStep",
        "fmi2Terminate",
        "fmi2Reset",
        "fmi2SetReal",
        "fmi2SetInteger",
        "fmi2SetBoolean",
        "fmi2GetReal",
        "fmi2GetInteger",
        "fmi2GetBoolean",
        "fmi2GetFMUstate",
        "fmi2SetFMUstate",
        "fmi2FreeFMUstate",
        "fmi2SerializedFMUstateSize",
        "fmi2SerializeFMUstate",
        "fmi2DeSerializeFMUstate",
        "fmi2SetRealInputDerivatives",
        "fmi2GetRealOutputDerivatives",
        "fmi2GetDirectionalDerivative",
        "fmi2SetDebugLogging",
        "fmi2GetRealStatus",
    ] {
        let c = sum.by_function.get(f).copied().unwrap_or_default();
        assert!(
            c[FMI2_OK as usize] > 0 && c[FMI2_ERROR as usize] > 0,
            "{f}: OK and Error both expected, got {c:?}"
        );
    }
    for state in [
        "Instantiated",
        "InitializationMode",
        "StepComplete",
        "Terminated",
        "Error",
    ] {
        let n = sum.resets_by_state.get(state).copied().unwrap_or(0);
        assert!(n > 0, "no fmi2Reset in {state}");
    }
    for kind in ["other scene", "truncated", "corrupted", "extended", "noise"] {
        let n = sum.rejected_blobs.get(kind).copied().unwrap_or(0);
        assert!(n > 0, "no {kind} serialized state rejected");
        assert_eq!(sum.accepted_blobs.get(kind), None, "{kind} state accepted");
    }
    assert!(sum.accepted_blobs.get("own scene").copied().unwrap_or(0) > 0);
}

/// Instantiation failures: NULL arguments, wrong GUID, wrong fmuType, bad resource location.
#[test]
fn instantiate_rejects_bad_arguments() {
    let fmu = Fmu::new("pendulum");
    let name = c"x";
    let wrong = c"{00000000-0000-0000-0000-000000000000}";
    let missing = c"file:///nonexistent/resources";
    // SAFETY: valid or NULL C strings, valid callbacks.
    unsafe {
        let cb = &*fmu.cb;
        let g = fmu.guid.as_ptr();
        let u = fmu.uri.as_ptr();
        assert!(fmi2Instantiate(ptr::null(), 1, g, u, cb, 0, 0).is_null());
        assert!(
            fmi2Instantiate(name.as_ptr(), 0, g, u, cb, 0, 0).is_null(),
            "Model Exchange"
        );
        assert!(fmi2Instantiate(name.as_ptr(), 1, wrong.as_ptr(), u, cb, 0, 0).is_null());
        assert!(fmi2Instantiate(name.as_ptr(), 1, ptr::null(), u, cb, 0, 0).is_null());
        assert!(fmi2Instantiate(name.as_ptr(), 1, g, missing.as_ptr(), cb, 0, 0).is_null());
        assert!(fmi2Instantiate(name.as_ptr(), 1, g, ptr::null(), cb, 0, 0).is_null());
        assert!(fmi2Instantiate(name.as_ptr(), 1, g, u, ptr::null(), 0, 0).is_null());
        let c = fmi2Instantiate(name.as_ptr(), 1, g, u, cb, 0, 0);
        assert!(!c.is_null());
        fmi2FreeInstance(c);
    }
}

/// Runs the pendulum with `n` elements for 0.1 s and returns tip.x, tip.y and energy.total
/// after every step.
fn pendulum_run(fmu: &Fmu, n: i32) -> Vec<u64> {
    let c = fmu.instantiate("thread");
    assert!(!c.is_null());
    let mut out = Vec::new();
    // SAFETY: a live component and valid arrays.
    unsafe {
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), FMI2_OK);
        let vr_n = [6u32]; // mesh.n_elements (the scene declares it 7th)
        assert_eq!(fmi2SetInteger(c, vr_n.as_ptr(), 1, [n].as_ptr()), FMI2_OK);
        assert_eq!(fmi2EnterInitializationMode(c), FMI2_OK);
        assert_eq!(fmi2ExitInitializationMode(c), FMI2_OK);
        let scene = common::scene("pendulum");
        let vars = flexfmu::variables::VariableTable::from_scene(&scene);
        let vrs: Vec<u32> = ["tip.x", "tip.y", "energy.total"]
            .iter()
            .map(|n| vars.by_name(n).unwrap().vr)
            .collect();
        assert_eq!(vars.by_name("mesh.n_elements").unwrap().vr, 6);
        let mut y = [0.0; 3];
        for k in 0..50 {
            assert_eq!(fmi2DoStep(c, k as f64 * 2e-3, 2e-3, 1), FMI2_OK);
            assert_eq!(fmi2GetReal(c, vrs.as_ptr(), 3, y.as_mut_ptr()), FMI2_OK);
            out.extend(y.iter().map(|v| v.to_bits()));
        }
        fmi2FreeInstance(c);
    }
    out
}

/// Eight instances stepping concurrently in threads give exactly the results of sequential runs.
#[test]
fn eight_instances_in_threads_match_sequential_runs() {
    let fmu = std::sync::Arc::new(Fmu::new("pendulum"));
    let sizes: Vec<i32> = (0..8).map(|i| 2 + i).collect();
    let sequential: Vec<Vec<u64>> = sizes.iter().map(|&n| pendulum_run(&fmu, n)).collect();
    let handles: Vec<_> = sizes
        .iter()
        .map(|&n| {
            let fmu = fmu.clone();
            std::thread::spawn(move || pendulum_run(&fmu, n))
        })
        .collect();
    let parallel: Vec<Vec<u64>> = handles.into_iter().map(|h| h.join().unwrap()).collect();
    assert_eq!(sequential, parallel);
}

// The callbacks struct holds raw pointers; the test shares it read-only between threads.
unsafe impl Send for Fmu {}
unsafe impl Sync for Fmu {}
