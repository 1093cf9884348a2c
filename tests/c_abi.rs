//! The C ABI itself: random call sequences with random (and hostile) arguments, and instances
//! running in parallel threads. Calls go through the exported `extern "C"` functions exactly as
//! an importer makes them (with a NULL logger: a C-variadic logger cannot be written in stable
//! Rust; the fmpy tests exercise the logger).

use flexfmu::fmi2::exports::*;
use flexfmu::fmi2::types::*;
use flexfmu::model_description::scene_guid;
use flexfmu::scene::Scene;
use std::ffi::{CString, c_char, c_void};
use std::path::PathBuf;
use std::ptr;

mod common;

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

/// Deterministic xorshift generator.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn real(&mut self) -> f64 {
        match self.below(12) {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => f64::NEG_INFINITY,
            3 => 0.0,
            4 => -1.0,
            5 => 1e300,
            6 => -1e-300,
            _ => {
                (self.next() as f64 / u64::MAX as f64 - 0.5) * 10f64.powi(self.below(12) as i32 - 6)
            }
        }
    }
}

fn valid(status: Fmi2Status) {
    assert!(
        (FMI2_OK..=FMI2_FATAL).contains(&status),
        "invalid status {status}"
    );
    assert_ne!(
        status, FMI2_FATAL,
        "fmi2Fatal means a panic was caught: a bug"
    );
}

/// Thousands of random calls with random arguments: every call returns a valid status, no
/// call panics (fmi2Fatal) or crashes.
#[test]
fn random_call_sequences_never_crash() {
    let fmus = [
        Fmu::new("cantilever"),
        Fmu::new("cantilever_motion"),
        Fmu::new("pendulum"),
    ];
    let mut rng = Rng(0x9e3779b97f4a7c15);
    let mut comps: Vec<(usize, Fmi2Component)> = Vec::new();
    let mut states: Vec<(usize, Fmi2FmuState)> = Vec::new();
    let mut serialized: Vec<Vec<u8>> = Vec::new();
    let garbage = [0u64; 16];
    let mut counts = [0usize; 5];
    let mut times: std::collections::HashMap<usize, f64> = std::collections::HashMap::new();
    for _ in 0..20000 {
        if comps.is_empty() || rng.below(40) == 0 {
            let f = rng.below(3) as usize;
            let c = fmus[f].instantiate("fuzz");
            assert!(!c.is_null());
            comps.push((f, c));
        }
        let (f, c) = comps[rng.below(comps.len() as u64) as usize];
        let nvars = 40;
        let vr = [rng.below(nvars) as u32, rng.below(nvars + 5) as u32];
        let n = rng.below(3) as usize;
        let reals = [rng.real(), rng.real()];
        let ints = [rng.below(20) as i32 - 5, rng.below(3) as i32];
        let orders = [rng.below(4) as i32, 1];
        let mut out = [0.0f64; 2];
        let mut iout = [0i32; 2];
        let nullish = rng.below(10) == 0;
        // SAFETY: arguments follow the FMI signatures; deliberately NULL where `nullish`.
        let status = unsafe {
            match rng.below(32) {
                0 => fmi2SetupExperiment(c, 1, 1e-6, rng.real(), rng.below(2) as i32, rng.real()),
                1 | 2 => fmi2EnterInitializationMode(c),
                3 | 4 => fmi2ExitInitializationMode(c),
                5..=8 => {
                    // mostly at the right time, with step sizes from tiny to huge and invalid
                    let now = times.get(&(c as usize)).copied().unwrap_or(0.0);
                    let t = if rng.below(4) == 0 { rng.real() } else { now };
                    let h =
                        [1e-6, 1e-4, 1e-3, 2e-2, 0.0, -1e-3, f64::NAN, 1e12][rng.below(8) as usize];
                    let st = fmi2DoStep(c, t, h, 1);
                    if st == FMI2_OK {
                        times.insert(c as usize, t + h);
                    }
                    st
                }
                9 => fmi2SetReal(
                    c,
                    if nullish { ptr::null() } else { vr.as_ptr() },
                    n,
                    reals.as_ptr(),
                ),
                10 => fmi2SetInteger(c, vr.as_ptr(), n, ints.as_ptr()),
                11 => fmi2SetBoolean(c, vr.as_ptr(), n, ints.as_ptr()),
                12 => fmi2GetReal(
                    c,
                    vr.as_ptr(),
                    n,
                    if nullish {
                        ptr::null_mut()
                    } else {
                        out.as_mut_ptr()
                    },
                ),
                13 => fmi2GetInteger(c, vr.as_ptr(), n, iout.as_mut_ptr()),
                14 => fmi2GetBoolean(c, vr.as_ptr(), n, iout.as_mut_ptr()),
                15 => fmi2Terminate(c),
                16 | 30 | 31 => {
                    times.remove(&(c as usize));
                    fmi2Reset(c)
                }
                17 => {
                    let mut s: Fmi2FmuState = ptr::null_mut();
                    let st = fmi2GetFMUstate(c, if nullish { ptr::null_mut() } else { &mut s });
                    if !s.is_null() {
                        states.push((f, s));
                    }
                    st
                }
                18 if !states.is_empty() => {
                    // a state of this or another instance, possibly of another FMU
                    let (_, s) = states[rng.below(states.len() as u64) as usize];
                    times.remove(&(c as usize));
                    fmi2SetFMUstate(c, s)
                }
                19 if !states.is_empty() => {
                    let i = rng.below(states.len() as u64) as usize;
                    let (_, mut s) = states.swap_remove(i);
                    let st = fmi2FreeFMUstate(c, &mut s);
                    if st != FMI2_OK {
                        states.push((f, s)); // not freed; keep it for the cleanup
                    }
                    st
                }
                20 if !states.is_empty() => {
                    let (_, s) = states[rng.below(states.len() as u64) as usize];
                    let mut size = 0usize;
                    let st = fmi2SerializedFMUstateSize(c, s, &mut size);
                    if st == FMI2_OK {
                        let mut buf = vec![0u8; size];
                        let st2 =
                            fmi2SerializeFMUstate(c, s, buf.as_mut_ptr() as *mut c_char, size);
                        valid(st2);
                        if st2 == FMI2_OK {
                            serialized.push(buf);
                        }
                    }
                    st
                }
                21 => {
                    // deserialize: a real buffer, a truncated or corrupted one, or noise
                    let mut buf = if serialized.is_empty() || rng.below(4) == 0 {
                        (0..rng.below(200)).map(|_| rng.next() as u8).collect()
                    } else {
                        serialized[rng.below(serialized.len() as u64) as usize].clone()
                    };
                    match rng.below(3) {
                        0 if !buf.is_empty() => {
                            let l = rng.below(buf.len() as u64) as usize;
                            buf.truncate(l);
                        }
                        1 if !buf.is_empty() => {
                            let i = rng.below(buf.len() as u64) as usize;
                            buf[i] ^= 0xff;
                        }
                        _ => {}
                    }
                    let mut s: Fmi2FmuState = ptr::null_mut();
                    let st = fmi2DeSerializeFMUstate(
                        c,
                        buf.as_ptr() as *const c_char,
                        buf.len(),
                        &mut s,
                    );
                    if !s.is_null() {
                        states.push((f, s));
                    }
                    st
                }
                22 => {
                    // a readable pointer that is not a state
                    fmi2SetFMUstate(c, garbage.as_ptr() as *mut c_void)
                }
                23 => fmi2GetDirectionalDerivative(
                    c,
                    vr.as_ptr(),
                    n,
                    vr[1..].as_ptr(),
                    n.min(1),
                    reals.as_ptr(),
                    out.as_mut_ptr(),
                ),
                24 => {
                    fmi2SetRealInputDerivatives(c, vr.as_ptr(), n, orders.as_ptr(), reals.as_ptr())
                }
                25 => fmi2GetRealOutputDerivatives(
                    c,
                    vr.as_ptr(),
                    n,
                    orders.as_ptr(),
                    out.as_mut_ptr(),
                ),
                26 => {
                    let mut b = 0;
                    fmi2GetBooleanStatus(
                        c,
                        rng.below(6) as i32,
                        if nullish { ptr::null_mut() } else { &mut b },
                    )
                }
                27 => {
                    let mut t = 0.0;
                    fmi2GetRealStatus(c, rng.below(6) as i32, &mut t)
                }
                28 => fmi2CancelStep(c),
                _ => {
                    let cats = [c"logEvents".as_ptr(), c"nope".as_ptr()];
                    fmi2SetDebugLogging(c, 1, n, cats.as_ptr())
                }
            }
        };
        valid(status);
        counts[status as usize] += 1;
        if rng.below(60) == 0 {
            let i = rng.below(comps.len() as u64) as usize;
            let (_, c) = comps.swap_remove(i);
            // SAFETY: a live component, freed once.
            unsafe { fmi2FreeInstance(c) };
        }
    }
    // NULL and freed components are rejected without touching memory we do not own.
    // SAFETY: NULL is always allowed to be passed.
    unsafe {
        assert_eq!(fmi2DoStep(ptr::null_mut(), 0.0, 1e-3, 1), FMI2_ERROR);
        assert_eq!(fmi2Terminate(ptr::null_mut()), FMI2_ERROR);
        fmi2FreeInstance(ptr::null_mut());
    }
    let (_, c0) = comps[0];
    for (_, mut s) in states {
        // SAFETY: live states; the component is live.
        unsafe {
            let _ = fmi2FreeFMUstate(c0, &mut s);
        }
    }
    for (_, c) in comps {
        // SAFETY: live components.
        unsafe { fmi2FreeInstance(c) };
    }
    println!("status counts OK/Warning/Discard/Error/Fatal: {counts:?}");
    assert!(counts[FMI2_OK as usize] > 3000 && counts[FMI2_ERROR as usize] > 100);
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
