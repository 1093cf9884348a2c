//! FMI call-sequence fuzzer over the exported `extern "C"` functions, for every shipped scene.
//!
//! One harness, used twice: a short slice in `cargo test` (`tests/c_abi.rs`) and the full run
//! as `cargo run --release --example fuzz_fmi -- --sequences 100000` (`examples/fuzz_fmi.rs`).
//!
//! A *sequence* instantiates one to three FMUs of random shipped scenes and makes up to 48
//! calls on them, half of them along the legal calling sequence (setup, initialization,
//! communication steps) and half random: null and foreign pointers (another live instance's
//! component, an FMU state or a readable buffer passed as a component, a component passed as a
//! state), unknown value references, every setter and getter on every value reference,
//! NaN/inf/huge/subnormal values, illegal call orders, corrupt, truncated, extended and foreign
//! (other scene's) serialized states, fmi2Reset in every state, zero/negative/huge step sizes.
//! Pointers are never dangling: freed instances and states are forgotten at once (passing
//! them would be undefined behaviour for any C library).
//!
//! Every call must return a valid status that is not fmi2Fatal (a fmi2Fatal means a panic was
//! caught inside the FMU); a crash (an escaping panic aborts, a segfault) kills the process;
//! a sequence slower than the hang limit counts as a hang, and a watchdog aborts the process
//! when one runs for six times that limit. Sequence `k` of seed `s` is reproducible on its
//! own (`--first k --sequences 1`): its generator is seeded from `(s, k)` only.
//!
//! Values are hostile but the work is bounded: valid parameter values are small (meshes of a
//! few elements, communication steps up to 5 ms); sizes that are valid but expensive (10^5
//! elements, steps of seconds) are legitimately slow, not hangs, and are not drawn.
#![allow(dead_code)]

use flexfmu::fmi2::exports::*;
use flexfmu::fmi2::types::*;
use flexfmu::model_description::scene_guid;
use flexfmu::scene::Scene;
use flexfmu::variables::{Causality, Value, VarType, VariableTable};
use std::cell::Cell;
use std::collections::{BTreeMap, HashMap};
use std::ffi::{CString, c_char};
use std::path::{Path, PathBuf};
use std::ptr;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Deterministic xorshift64* generator.
pub struct Rng(u64);

impl Rng {
    /// A generator for sequence `k` of run seed `seed` (splitmix64 of both).
    pub fn for_sequence(seed: u64, k: u64) -> Self {
        let mut z = seed ^ k.wrapping_mul(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        Rng(z | 1)
    }

    /// Next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in `0..n` (`n` > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        ((self.next() >> 11) as f64 / (1u64 << 53) as f64) < p
    }

    /// One element of a non-empty slice.
    pub fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[self.below(xs.len())]
    }

    /// A hostile or ordinary Real: NaN, infinities, signed zeros, extremes, subnormals, or a
    /// random number of magnitude 1e-6 to 1e6.
    pub fn real(&mut self) -> f64 {
        match self.below(16) {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => f64::NEG_INFINITY,
            3 => 0.0,
            4 => -0.0,
            5 => f64::MAX,
            6 => -1e300,
            7 => 5e-324,
            8 => f64::MIN_POSITIVE,
            9 => -1.0,
            _ => {
                let m = (self.next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                2.0 * m * 10f64.powi(self.below(13) as i32 - 6)
            }
        }
    }

    /// A hostile or ordinary Integer (no valid but expensive sizes: see the module doc).
    pub fn integer(&mut self) -> i32 {
        self.pick(&[
            i32::MIN,
            -1,
            0,
            1,
            2,
            3,
            4,
            5,
            8,
            33,
            100_001,
            1 << 20,
            i32::MAX,
        ])
    }

    /// An fmi2Boolean, also values other than fmi2True/fmi2False.
    pub fn boolean(&mut self) -> i32 {
        self.pick(&[0, 1, 1, 0, 2, -1, i32::MIN])
    }
}

/// The status names, indexed by the C value.
pub const STATUS_NAMES: [&str; 5] = ["OK", "Warning", "Discard", "Error", "Fatal"];

/// One variable of a scene, as the fuzzer sees it.
#[derive(Clone, Debug)]
pub struct Var {
    /// Value reference.
    pub vr: u32,
    /// Base type.
    pub ty: VarType,
    /// Causality.
    pub causality: Causality,
    /// Start value, if any.
    pub start: Option<Value>,
}

/// A shipped scene prepared as an FMU: resources directory, GUID, variables, and a serialized
/// state after one communication step (for foreign-state tests).
pub struct Fmu {
    /// Scene name (file stem).
    pub name: String,
    guid: CString,
    uri: CString,
    vars: Vec<Var>,
    /// `belt.n_elements` or `mesh.n_elements`: kept small by most sequences.
    mesh_vr: Option<u32>,
    /// `solver.max_step`, kept at least 1e-4 s by most sequences.
    max_step_vr: Option<u32>,
    /// `solver.load_steps`: valid values are kept at most 32.
    load_steps_vr: Option<u32>,
    blob: Vec<u8>,
}

/// The callbacks passed to fmi2Instantiate: no logger (a C-variadic logger cannot be written
/// in stable Rust; the fmpy tests exercise the logger).
struct Callbacks(Fmi2CallbackFunctions);
// SAFETY: all function pointers are None and the environment is NULL; shared read-only.
unsafe impl Sync for Callbacks {}
// SAFETY: as above.
unsafe impl Send for Callbacks {}

/// The prepared FMUs of every shipped scene.
pub struct Harness {
    /// One per shipped scene, sorted by name.
    pub fmus: Vec<Fmu>,
    cb: Box<Callbacks>,
    dir: PathBuf,
}

impl Drop for Harness {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// Run settings.
#[derive(Clone, Debug)]
pub struct Config {
    /// Number of sequences.
    pub sequences: u64,
    /// Index of the first sequence.
    pub first: u64,
    /// Run seed.
    pub seed: u64,
    /// Worker threads.
    pub threads: usize,
    /// A sequence slower than this (wall time) is a hang. 30 s by default: a legitimate
    /// sequence building and stepping the level-1 air spring takes 2.5–5.5 s alone and took
    /// 15.6 s on this 2-core machine while three other builds ran; a loop that does not end
    /// still shows.
    pub hang_limit: Duration,
    /// Print a progress line every this many sequences (0: never).
    pub progress_every: u64,
    /// Print every call's arguments and status (to replay one sequence).
    pub trace: bool,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            sequences: 1000,
            first: 0,
            seed: 0x5eed_f00d,
            threads: 1,
            hang_limit: Duration::from_secs(30),
            progress_every: 0,
            trace: false,
        }
    }
}

/// Counters of a run.
#[derive(Clone, Debug, Default)]
pub struct Summary {
    /// Sequences run.
    pub sequences: u64,
    /// FMI calls made (including fmi2Instantiate and fmi2FreeInstance).
    pub calls: u64,
    /// Returned statuses by C value (OK, Warning, Discard, Error, Fatal).
    pub statuses: [u64; 5],
    /// Statuses outside the fmi2Status enum.
    pub invalid: u64,
    /// Per function: calls by returned status.
    pub by_function: BTreeMap<&'static str, [u64; 5]>,
    /// fmi2Reset calls on a live component, by the state the instance was in.
    pub resets_by_state: BTreeMap<&'static str, u64>,
    /// Successful communication steps, per scene.
    pub ok_steps_by_scene: BTreeMap<String, u64>,
    /// Serialized states rejected by fmi2DeSerializeFMUstate, by kind of blob.
    pub rejected_blobs: BTreeMap<&'static str, u64>,
    /// Serialized states accepted, by kind of blob.
    pub accepted_blobs: BTreeMap<&'static str, u64>,
    /// Instantiations refused (bad arguments), and made.
    pub instantiations: [u64; 2],
    /// Sequences slower than the hang limit: (index, seconds).
    pub hangs: Vec<(u64, f64)>,
    /// Sequences with a fmi2Fatal or an invalid status: (index, function).
    pub failures: Vec<(u64, String)>,
    /// Slowest sequence: (seconds, index).
    pub max_sequence: (f64, u64),
    /// Sum of the sequences' wall times [s].
    pub total_sequence_time: f64,
    /// Wall time of the run [s].
    pub wall: f64,
}

impl Summary {
    fn merge(&mut self, o: &Summary) {
        self.sequences += o.sequences;
        self.calls += o.calls;
        for i in 0..5 {
            self.statuses[i] += o.statuses[i];
        }
        self.invalid += o.invalid;
        for (k, v) in &o.by_function {
            let e = self.by_function.entry(k).or_default();
            for i in 0..5 {
                e[i] += v[i];
            }
        }
        for (k, v) in &o.resets_by_state {
            *self.resets_by_state.entry(k).or_default() += v;
        }
        for (k, v) in &o.ok_steps_by_scene {
            *self.ok_steps_by_scene.entry(k.clone()).or_default() += v;
        }
        for (k, v) in &o.rejected_blobs {
            *self.rejected_blobs.entry(k).or_default() += v;
        }
        for (k, v) in &o.accepted_blobs {
            *self.accepted_blobs.entry(k).or_default() += v;
        }
        self.instantiations[0] += o.instantiations[0];
        self.instantiations[1] += o.instantiations[1];
        self.hangs.extend(o.hangs.iter().copied());
        self.failures.extend(o.failures.iter().cloned());
        if o.max_sequence.0 > self.max_sequence.0 {
            self.max_sequence = o.max_sequence;
        }
        self.total_sequence_time += o.total_sequence_time;
    }

    /// Crashes are fatal to the process; what a finished run can fail on: fmi2Fatal, invalid
    /// statuses, hangs, and a damaged or foreign serialized state that was accepted.
    pub fn passed(&self) -> bool {
        self.statuses[4] == 0
            && self.invalid == 0
            && self.hangs.is_empty()
            && self
                .accepted_blobs
                .keys()
                .all(|k| *k == BlobKind::Own.name())
    }

    /// A human-readable report.
    pub fn report(&self) -> String {
        let mut s = String::new();
        use std::fmt::Write;
        let _ = writeln!(
            s,
            "{} sequences, {} FMI calls in {:.1} s wall ({:.2} ms per sequence on average, slowest {:.3} s: sequence {})",
            self.sequences,
            self.calls,
            self.wall,
            1e3 * self.total_sequence_time / self.sequences.max(1) as f64,
            self.max_sequence.0,
            self.max_sequence.1
        );
        let _ = writeln!(
            s,
            "statuses: {}; invalid statuses: {}",
            STATUS_NAMES
                .iter()
                .zip(self.statuses)
                .map(|(n, c)| format!("{n} {c}"))
                .collect::<Vec<_>>()
                .join(", "),
            self.invalid
        );
        let _ = writeln!(
            s,
            "crashes: 0 (the process is alive); fmi2Fatal (caught panics): {}; hangs (> limit): {}; damaged or foreign states accepted: {}",
            self.statuses[4],
            self.hangs.len(),
            self.accepted_blobs
                .iter()
                .filter(|(k, _)| **k != BlobKind::Own.name())
                .map(|(_, n)| n)
                .sum::<u64>()
        );
        let _ = writeln!(
            s,
            "instantiations: {} made, {} refused (bad arguments)",
            self.instantiations[1], self.instantiations[0]
        );
        let _ = writeln!(s, "fmi2Reset by state: {:?}", self.resets_by_state);
        let _ = writeln!(
            s,
            "successful fmi2DoStep by scene: {:?}",
            self.ok_steps_by_scene
        );
        let _ = writeln!(
            s,
            "serialized states accepted: {:?}; rejected: {:?}",
            self.accepted_blobs, self.rejected_blobs
        );
        let _ = writeln!(s, "calls by function (OK/Warning/Discard/Error/Fatal):");
        for (f, c) in &self.by_function {
            let _ = writeln!(s, "  {f:32} {c:?}");
        }
        for (k, t) in self.hangs.iter().take(20) {
            let _ = writeln!(s, "HANG: sequence {k} took {t:.1} s");
        }
        for (k, f) in self.failures.iter().take(20) {
            let _ = writeln!(s, "FAILURE: sequence {k}: {f}");
        }
        s
    }
}

thread_local! {
    /// The sequence this thread is running (for the panic hook).
    static CURRENT: Cell<Option<(u64, u64)>> = const { Cell::new(None) };
}

/// Makes a panic anywhere (also one caught inside the FMU and turned into fmi2Fatal) name the
/// sequence that caused it.
fn install_panic_hook() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if let Some((seed, k)) = CURRENT.with(|c| c.get()) {
                eprintln!(
                    "fuzz: panic in sequence {k} of seed {seed:#x} (replay: cargo run --release --example fuzz_fmi -- --seed {seed:#x} --first {k} --sequences 1)"
                );
            }
            previous(info);
        }));
    });
}

/// State of an instance as the fuzzer tracks it from the returned statuses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Tracked {
    Instantiated,
    Initialization,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
    /// After fmi2SetFMUstate: the state saved in the blob.
    Restored,
}

impl Tracked {
    fn name(self) -> &'static str {
        match self {
            Tracked::Instantiated => "Instantiated",
            Tracked::Initialization => "InitializationMode",
            Tracked::StepComplete => "StepComplete",
            Tracked::StepFailed => "StepFailed",
            Tracked::Terminated => "Terminated",
            Tracked::Error => "Error",
            Tracked::Restored => "Restored",
        }
    }
}

struct Live {
    c: Fmi2Component,
    fmu: usize,
    state: Tracked,
    time: f64,
}

/// A serialized state and where it came from.
#[derive(Clone, Copy, Debug)]
enum BlobKind {
    Own,
    Foreign,
    Truncated,
    Corrupted,
    Extended,
    Noise,
    Empty,
}

impl BlobKind {
    fn name(self) -> &'static str {
        match self {
            BlobKind::Own => "own scene",
            BlobKind::Foreign => "other scene",
            BlobKind::Truncated => "truncated",
            BlobKind::Corrupted => "corrupted",
            BlobKind::Extended => "extended",
            BlobKind::Noise => "noise",
            BlobKind::Empty => "empty",
        }
    }
}

/// The scene files shipped in `scenes/`.
pub fn shipped_scenes() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    v.sort();
    v
}

impl Harness {
    /// Prepares every shipped scene: a resources directory with its scene file, and a
    /// serialized state after initialization and one step.
    pub fn new() -> Self {
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        let dir = std::env::temp_dir().join(format!(
            "flexfmu-fuzz-{}-{}",
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        let cb = Box::new(Callbacks(Fmi2CallbackFunctions {
            logger: None,
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: ptr::null_mut(),
        }));
        let mut fmus = Vec::new();
        for path in shipped_scenes() {
            let name = path.file_stem().unwrap().to_string_lossy().into_owned();
            let scene = Scene::from_path(&path).unwrap_or_else(|e| panic!("{name}: {e:?}"));
            let res = dir.join(&name);
            std::fs::create_dir_all(&res).unwrap();
            std::fs::write(res.join("scene.toml"), &scene.text).unwrap();
            let table = VariableTable::from_scene(&scene);
            let vars: Vec<Var> = table
                .vars()
                .iter()
                .map(|v| Var {
                    vr: v.vr,
                    ty: v.ty,
                    causality: v.causality,
                    start: v.start,
                })
                .collect();
            let by_name = |n: &str| table.by_name(n).map(|v| v.vr);
            let mut fmu = Fmu {
                name,
                guid: CString::new(scene_guid(&scene)).unwrap(),
                uri: CString::new(format!("file://{}", res.display())).unwrap(),
                vars,
                mesh_vr: by_name("belt.n_elements").or(by_name("mesh.n_elements")),
                max_step_vr: by_name("solver.max_step"),
                load_steps_vr: by_name("solver.load_steps"),
                blob: Vec::new(),
            };
            fmu.blob = fmu.reference_blob(&cb.0);
            fmus.push(fmu);
        }
        Self { fmus, cb, dir }
    }

    /// Runs `cfg.sequences` sequences on `cfg.threads` threads.
    pub fn run(&self, cfg: &Config) -> Summary {
        install_panic_hook();
        let start = Instant::now();
        let next = AtomicU64::new(cfg.first);
        let end = cfg.first + cfg.sequences;
        let done = AtomicU64::new(0);
        let finished = AtomicBool::new(false);
        let threads = cfg.threads.max(1);
        // per worker: (sequence, start in ms since the run started + 1; 0 when idle)
        let running: Arc<Vec<(AtomicU64, AtomicU64)>> = Arc::new(
            (0..threads)
                .map(|_| (AtomicU64::new(0), AtomicU64::new(0)))
                .collect(),
        );
        let total = Mutex::new(Summary::default());
        std::thread::scope(|s| {
            // watchdog: a sequence running for six times the hang limit never ends
            let running_w = running.clone();
            let finished_w = &finished;
            let abort_after = cfg.hang_limit.as_millis() as u64 * 6;
            let seed = cfg.seed;
            s.spawn(move || {
                while !finished_w.load(Ordering::Relaxed) {
                    std::thread::sleep(Duration::from_millis(200));
                    let now = start.elapsed().as_millis() as u64 + 1;
                    for (k, t0) in running_w.iter() {
                        let t0 = t0.load(Ordering::Relaxed);
                        if t0 != 0 && now.saturating_sub(t0) > abort_after {
                            eprintln!(
                                "fuzz: HANG: sequence {} of seed {seed:#x} has run for {} s; aborting",
                                k.load(Ordering::Relaxed),
                                now.saturating_sub(t0) / 1000
                            );
                            std::process::abort();
                        }
                    }
                }
            });
            let workers: Vec<_> = (0..threads)
                .map(|w| {
                    let running = running.clone();
                    let (next, done, total) = (&next, &done, &total);
                    s.spawn(move || {
                        let mut local = Summary::default();
                        loop {
                            let k = next.fetch_add(1, Ordering::Relaxed);
                            if k >= end {
                                break;
                            }
                            running[w].0.store(k, Ordering::Relaxed);
                            running[w]
                                .1
                                .store(start.elapsed().as_millis() as u64 + 1, Ordering::Relaxed);
                            CURRENT.with(|c| c.set(Some((cfg.seed, k))));
                            let t = Instant::now();
                            self.sequence(cfg.seed, k, cfg.trace, &mut local);
                            let dt = t.elapsed().as_secs_f64();
                            CURRENT.with(|c| c.set(None));
                            running[w].1.store(0, Ordering::Relaxed);
                            local.sequences += 1;
                            local.total_sequence_time += dt;
                            if dt > local.max_sequence.0 {
                                local.max_sequence = (dt, k);
                            }
                            if dt > cfg.hang_limit.as_secs_f64() {
                                local.hangs.push((k, dt));
                            }
                            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                            if cfg.progress_every > 0 && n % cfg.progress_every == 0 {
                                let el = start.elapsed().as_secs_f64();
                                eprintln!(
                                    "fuzz: {n}/{} sequences, {el:.0} s, about {:.0} s to go",
                                    cfg.sequences,
                                    el / n as f64 * (cfg.sequences - n) as f64
                                );
                            }
                        }
                        total.lock().unwrap().merge(&local);
                    })
                })
                .collect();
            for h in workers {
                h.join().unwrap();
            }
            finished.store(true, Ordering::Relaxed);
        });
        let mut summary = total.into_inner().unwrap();
        summary.wall = start.elapsed().as_secs_f64();
        summary
    }

    /// One sequence (sequence `k` of `seed`): its counters are added to `sum`.
    pub fn sequence(&self, seed: u64, k: u64, trace: bool, sum: &mut Summary) {
        let mut rng = Rng::for_sequence(seed, k);
        let mut seq = Seq {
            h: self,
            rng: &mut rng,
            sum,
            k,
            trace,
            live: Vec::new(),
            states: Vec::new(),
            state_scene: HashMap::new(),
            blobs: Vec::new(),
            garbage: Box::new([0u64; 64]),
        };
        seq.run();
    }
}

impl Fmu {
    fn instantiate(&self, cb: &Fmi2CallbackFunctions, logging_on: bool) -> Fmi2Component {
        // SAFETY: valid C strings and callbacks that outlive the instance.
        unsafe {
            fmi2Instantiate(
                c"fuzz".as_ptr(),
                FMI2_COSIMULATION,
                self.guid.as_ptr(),
                self.uri.as_ptr(),
                cb,
                0,
                logging_on as i32,
            )
        }
    }

    /// A new instance in step mode, with `mesh` = (value reference, element count) set
    /// first; `None` if initialization did not return `fmi2OK` (the instance is freed).
    fn initialized(
        &self,
        cb: &Fmi2CallbackFunctions,
        mesh: Option<(u32, i32)>,
    ) -> Option<Fmi2Component> {
        let c = self.instantiate(cb, false);
        assert!(!c.is_null(), "{}: fmi2Instantiate failed", self.name);
        // SAFETY: a live component and one-element arrays.
        unsafe {
            if let Some((vr, n)) = mesh {
                assert_eq!(fmi2SetInteger(c, &vr, 1, &n), FMI2_OK, "{}", self.name);
            }
            assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), FMI2_OK);
            assert_eq!(fmi2EnterInitializationMode(c), FMI2_OK);
            if fmi2ExitInitializationMode(c) != FMI2_OK {
                fmi2FreeInstance(c);
                return None;
            }
        }
        Some(c)
    }

    /// Serialized state after initialization and one step of 1 ms: with a small mesh, or
    /// with the scene's own where the small one has no static pre-load (drives of many
    /// pulleys, the 3D belt: their pre-loads need more elements, issues 12 and 13).
    fn reference_blob(&self, cb: &Fmi2CallbackFunctions) -> Vec<u8> {
        let small = if self.name.starts_with("belt") { 16 } else { 4 };
        let c = self
            .initialized(cb, self.mesh_vr.map(|vr| (vr, small)))
            .or_else(|| self.initialized(cb, None))
            .unwrap_or_else(|| panic!("{}: initialization failed", self.name));
        // SAFETY: a live component and arrays of the stated lengths.
        unsafe {
            assert_eq!(fmi2DoStep(c, 0.0, 1e-3, 1), FMI2_OK, "{}", self.name);
            let mut s: Fmi2FmuState = ptr::null_mut();
            assert_eq!(fmi2GetFMUstate(c, &mut s), FMI2_OK);
            let mut size = 0usize;
            assert_eq!(fmi2SerializedFMUstateSize(c, s, &mut size), FMI2_OK);
            let mut buf = vec![0u8; size];
            assert_eq!(
                fmi2SerializeFMUstate(c, s, buf.as_mut_ptr() as *mut c_char, size),
                FMI2_OK
            );
            assert_eq!(fmi2FreeFMUstate(c, &mut s), FMI2_OK);
            assert!(s.is_null());
            fmi2FreeInstance(c);
            buf
        }
    }
}

/// The calls of one sequence.
struct Seq<'a> {
    h: &'a Harness,
    rng: &'a mut Rng,
    sum: &'a mut Summary,
    k: u64,
    trace: bool,
    live: Vec<Live>,
    /// Live FMU states (any instance's).
    states: Vec<Fmi2FmuState>,
    /// Scene of each live FMU state (by address).
    state_scene: HashMap<usize, usize>,
    /// Serialized states made in this sequence, with their scene.
    blobs: Vec<(usize, Vec<u8>)>,
    /// A readable, aligned buffer that is neither a component nor a state.
    garbage: Box<[u64; 64]>,
}

impl Seq<'_> {
    fn note(&self, msg: impl FnOnce() -> String) {
        if self.trace {
            eprintln!("  {}", msg());
        }
    }

    fn record(&mut self, f: &'static str, status: Fmi2Status) -> Fmi2Status {
        self.note(|| format!("{f} -> {status}"));
        self.sum.calls += 1;
        if !(FMI2_OK..=FMI2_FATAL).contains(&status) {
            self.sum.invalid += 1;
            self.sum
                .failures
                .push((self.k, format!("{f} returned the invalid status {status}")));
            return status;
        }
        self.sum.statuses[status as usize] += 1;
        self.sum.by_function.entry(f).or_default()[status as usize] += 1;
        if status == FMI2_FATAL {
            self.sum
                .failures
                .push((self.k, format!("{f} returned fmi2Fatal (a caught panic)")));
        }
        status
    }

    fn run(&mut self) {
        let n_inst = self.rng.pick(&[1, 1, 1, 1, 2, 2, 2, 3]);
        for _ in 0..n_inst {
            self.instantiate();
        }
        let n_calls = 4 + self.rng.below(45);
        for _ in 0..n_calls {
            if self.live.is_empty() {
                self.instantiate();
            }
            let i = self.rng.below(self.live.len());
            if self.rng.chance(0.5) {
                self.progress(i);
            } else {
                self.random_call(i);
            }
        }
        // clean up: every state through some live component, then the instances
        if self.live.is_empty() && !self.states.is_empty() {
            self.instantiate();
        }
        while let Some(mut s) = self.states.pop() {
            let c = self.live[0].c;
            // SAFETY: a live component and a live state.
            let st = unsafe { fmi2FreeFMUstate(c, &mut s) };
            if st != FMI2_OK {
                // a component in the Fatal state refuses: free through a fresh instance
                let fresh = self.h.fmus[0].instantiate(&self.h.cb.0, false);
                assert!(!fresh.is_null());
                // SAFETY: as above.
                let st2 = unsafe { fmi2FreeFMUstate(fresh, &mut s) };
                // SAFETY: a live component, freed once.
                unsafe { fmi2FreeInstance(fresh) };
                self.record("fmi2FreeFMUstate", st2);
                assert_eq!(st2, FMI2_OK, "sequence {}: a live state not freed", self.k);
            }
            self.record("fmi2FreeFMUstate", st);
        }
        for l in std::mem::take(&mut self.live) {
            // SAFETY: a live component, freed once.
            unsafe { fmi2FreeInstance(l.c) };
            self.sum.calls += 1;
        }
    }

    fn instantiate(&mut self) {
        let f = self.rng.below(self.h.fmus.len());
        let fmu = &self.h.fmus[f];
        // sometimes first a refused attempt
        if self.rng.chance(0.15) {
            let other = &self.h.fmus[self.rng.below(self.h.fmus.len())];
            let bad_uri = c"file:///nonexistent/resources";
            let remote = c"http://example.com/resources";
            let (name, ty, guid, uri, cb): (_, _, _, _, *const Fmi2CallbackFunctions) =
                match self.rng.below(7) {
                    0 => (
                        ptr::null(),
                        FMI2_COSIMULATION,
                        fmu.guid.as_ptr(),
                        fmu.uri.as_ptr(),
                        &self.h.cb.0,
                    ),
                    1 => (
                        c"x".as_ptr(),
                        0,
                        fmu.guid.as_ptr(),
                        fmu.uri.as_ptr(),
                        &self.h.cb.0,
                    ),
                    2 => (
                        c"x".as_ptr(),
                        FMI2_COSIMULATION,
                        ptr::null(),
                        fmu.uri.as_ptr(),
                        &self.h.cb.0,
                    ),
                    3 => (
                        c"x".as_ptr(),
                        FMI2_COSIMULATION,
                        fmu.guid.as_ptr(),
                        if self.rng.chance(0.5) {
                            bad_uri.as_ptr()
                        } else {
                            remote.as_ptr()
                        },
                        &self.h.cb.0,
                    ),
                    4 => (
                        c"x".as_ptr(),
                        FMI2_COSIMULATION,
                        fmu.guid.as_ptr(),
                        ptr::null(),
                        &self.h.cb.0,
                    ),
                    5 => (
                        c"x".as_ptr(),
                        FMI2_COSIMULATION,
                        fmu.guid.as_ptr(),
                        fmu.uri.as_ptr(),
                        ptr::null(),
                    ),
                    // another scene's GUID
                    _ => (
                        c"x".as_ptr(),
                        FMI2_COSIMULATION,
                        other.guid.as_ptr(),
                        fmu.uri.as_ptr(),
                        &self.h.cb.0,
                    ),
                };
            // SAFETY: C strings or NULL, callbacks or NULL.
            let c = unsafe { fmi2Instantiate(name, ty, guid, uri, cb, 0, 1) };
            self.sum.calls += 1;
            if c.is_null() {
                self.sum.instantiations[0] += 1;
            } else {
                // only the foreign GUID of the same scene can succeed
                assert!(
                    ptr::eq(other, fmu),
                    "sequence {}: fmi2Instantiate accepted bad arguments",
                    self.k
                );
                self.live.push(Live {
                    c,
                    fmu: f,
                    state: Tracked::Instantiated,
                    time: 0.0,
                });
                self.sum.instantiations[1] += 1;
                return;
            }
        }
        let c = fmu.instantiate(&self.h.cb.0, self.rng.chance(0.3));
        self.sum.calls += 1;
        assert!(!c.is_null(), "sequence {}: fmi2Instantiate failed", self.k);
        self.sum.instantiations[1] += 1;
        self.live.push(Live {
            c,
            fmu: f,
            state: Tracked::Instantiated,
            time: 0.0,
        });
        // most sequences keep meshes and steps small (the module doc)
        if self.rng.chance(0.9)
            && let Some(vr) = fmu.mesh_vr
        {
            let n = if fmu.name.starts_with("belt") {
                self.rng.pick(&[16, 16, 20, 24, 32, 8])
            } else {
                self.rng.pick(&[1, 2, 4, 8])
            };
            // SAFETY: a live component and one-element arrays.
            self.note(|| format!("{c:?} {}: mesh vr {vr} = {n}", fmu.name));
            let s = unsafe { fmi2SetInteger(c, &vr, 1, &n) };
            self.record("fmi2SetInteger", s);
        }
    }

    /// A value-reference array of `n` entries: mostly of variables of `ty`, some of any type,
    /// some unknown.
    fn vrs(&mut self, fmu: usize, ty: Option<VarType>, n: usize) -> Vec<u32> {
        let vars = &self.h.fmus[fmu].vars;
        let nv = vars.len() as u32;
        (0..n)
            .map(|_| match self.rng.below(10) {
                0 => nv + self.rng.below(5) as u32,
                1 => self.rng.pick(&[u32::MAX, u32::MAX - 1, 1 << 31]),
                2 | 3 => self.rng.below(nv as usize) as u32,
                _ => {
                    let of_ty: Vec<u32> = vars
                        .iter()
                        .filter(|v| ty.is_none_or(|t| v.ty == t))
                        .map(|v| v.vr)
                        .collect();
                    if of_ty.is_empty() {
                        self.rng.below(nv as usize) as u32
                    } else {
                        self.rng.pick(&of_ty)
                    }
                }
            })
            .collect()
    }

    /// The component argument of a call: mostly the instance's own, sometimes another live
    /// instance's, NULL, an FMU state, a readable buffer, or a misaligned pointer.
    fn component(&mut self, i: usize) -> Fmi2Component {
        match self.rng.below(40) {
            0 => ptr::null_mut(),
            1 if !self.states.is_empty() => self.rng.pick(&self.states),
            2 => self.garbage.as_mut_ptr() as Fmi2Component,
            3 => (self.garbage.as_mut_ptr() as usize + 1) as Fmi2Component,
            4 => {
                let j = self.rng.below(self.live.len());
                self.live[j].c
            }
            _ => self.live[i].c,
        }
    }

    /// Applies a status to the tracked state of the instance behind `c` (if it is one).
    fn track(&mut self, c: Fmi2Component, status: Fmi2Status, on_ok: impl FnOnce(&mut Live)) {
        if let Some(l) = self.live.iter_mut().find(|l| l.c == c) {
            match status {
                FMI2_OK => on_ok(l),
                FMI2_ERROR => l.state = Tracked::Error,
                _ => {}
            }
        }
    }

    /// The next call of a legal calling sequence for instance `i`, with ordinary arguments.
    fn progress(&mut self, i: usize) {
        let c = self.live[i].c;
        let fmu = self.live[i].fmu;
        // SAFETY: live components, arrays of the stated lengths.
        unsafe {
            match self.live[i].state {
                Tracked::Instantiated => {
                    if self.rng.chance(0.5) {
                        let s = fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0);
                        self.record("fmi2SetupExperiment", s);
                        self.track(c, s, |_| {});
                    } else {
                        let s = fmi2EnterInitializationMode(c);
                        self.record("fmi2EnterInitializationMode", s);
                        self.track(c, s, |l| l.state = Tracked::Initialization);
                    }
                }
                Tracked::Initialization => {
                    if self.rng.chance(0.3) {
                        self.set_plausible(i);
                    } else {
                        let s = fmi2ExitInitializationMode(c);
                        self.record("fmi2ExitInitializationMode", s);
                        self.track(c, s, |l| {
                            l.state = Tracked::StepComplete;
                            l.time = 0.0;
                        });
                    }
                }
                Tracked::StepComplete => match self.rng.below(10) {
                    0 => self.set_plausible(i),
                    1 => self.get_outputs(i),
                    2 => {
                        let s = fmi2Terminate(c);
                        self.record("fmi2Terminate", s);
                        self.track(c, s, |l| l.state = Tracked::Terminated);
                    }
                    _ => {
                        let t = self.live[i].time;
                        let h = self.rng.pick(&[1e-5, 1e-4, 1e-3, 1e-3, 2e-3, 5e-3]);
                        self.note(|| format!("{c:?} fmi2DoStep({t}, {h})"));
                        let s = fmi2DoStep(c, t, h, 1);
                        self.record("fmi2DoStep", s);
                        if s == FMI2_OK {
                            *self
                                .sum
                                .ok_steps_by_scene
                                .entry(self.h.fmus[fmu].name.clone())
                                .or_default() += 1;
                        }
                        if s == FMI2_DISCARD {
                            self.live[i].state = Tracked::StepFailed;
                        }
                        self.track(c, s, |l| l.time = t + h);
                    }
                },
                Tracked::Restored => {
                    let mut t = 0.0;
                    let s = fmi2GetRealStatus(c, 2, &mut t);
                    self.record("fmi2GetRealStatus", s);
                    self.track(c, s, |l| {
                        l.state = Tracked::StepComplete;
                        l.time = t;
                    });
                    if s == FMI2_ERROR {
                        // not stepComplete/stepFailed/terminated: saved in Instantiated or
                        // Initialization Mode; the Error state is tracked
                    }
                }
                Tracked::StepFailed | Tracked::Terminated | Tracked::Error => {
                    if self.rng.chance(0.7) {
                        self.reset(c);
                    } else {
                        self.get_outputs(i);
                    }
                }
            }
        }
    }

    /// Scene of the live instance behind `c`, if it is one.
    fn scene_of(&self, c: Fmi2Component) -> Option<usize> {
        self.live.iter().find(|l| l.c == c).map(|l| l.fmu)
    }

    fn reset(&mut self, c: Fmi2Component) {
        if let Some(l) = self.live.iter().find(|l| l.c == c) {
            *self.sum.resets_by_state.entry(l.state.name()).or_default() += 1;
        }
        // SAFETY: a component argument as made by `component`.
        let s = unsafe { fmi2Reset(c) };
        self.record("fmi2Reset", s);
        self.track(c, s, |l| {
            l.state = Tracked::Instantiated;
            l.time = 0.0;
        });
    }

    /// Sets an input or tunable parameter (or, before initialization, any parameter) to a
    /// value near its start value.
    fn set_plausible(&mut self, i: usize) {
        let c = self.live[i].c;
        let fmu = &self.h.fmus[self.live[i].fmu];
        let settable: Vec<&Var> = fmu
            .vars
            .iter()
            .filter(|v| v.causality != Causality::Output)
            .collect();
        if settable.is_empty() {
            return;
        }
        let v = settable[self.rng.below(settable.len())].clone();
        if Some(v.vr) == fmu.mesh_vr {
            return;
        }
        self.note(|| format!("{c:?} set plausible vr {} (start {:?})", v.vr, v.start));
        // SAFETY: a live component, one-element arrays.
        let s = unsafe {
            match v.start {
                Some(Value::Integer(x)) => ("fmi2SetInteger", fmi2SetInteger(c, &v.vr, 1, &x)),
                Some(Value::Boolean(b)) => {
                    let b = if self.rng.chance(0.5) {
                        b as i32
                    } else {
                        1 - b as i32
                    };
                    ("fmi2SetBoolean", fmi2SetBoolean(c, &v.vr, 1, &b))
                }
                Some(Value::Real(x)) => {
                    let f = 1.0 + 0.2 * (self.rng.below(11) as f64 - 5.0) / 5.0;
                    let x = if x == 0.0 {
                        self.rng.pick(&[0.0, 1.0, -10.0, 100.0])
                    } else {
                        x * f
                    };
                    self.note(|| format!("  value {x:e}"));
                    ("fmi2SetReal", fmi2SetReal(c, &v.vr, 1, &x))
                }
                None => return,
            }
        };
        self.record(s.0, s.1);
        self.track(c, s.1, |_| {});
    }

    fn get_outputs(&mut self, i: usize) {
        let c = self.live[i].c;
        let fmu = self.live[i].fmu;
        let outs: Vec<u32> = self.h.fmus[fmu]
            .vars
            .iter()
            .filter(|v| v.causality == Causality::Output)
            .map(|v| v.vr)
            .collect();
        let mut y = vec![0.0; outs.len()];
        // SAFETY: a live component, arrays of the stated length.
        let s = unsafe { fmi2GetReal(c, outs.as_ptr(), outs.len(), y.as_mut_ptr()) };
        self.record("fmi2GetReal", s);
        self.track(c, s, |_| {});
    }

    /// A serialized state to deserialize: own, foreign, damaged or noise.
    fn blob(&mut self, fmu: usize) -> (BlobKind, Vec<u8>) {
        let own = if !self.blobs.is_empty() && self.rng.chance(0.5) {
            let (f, b) = &self.blobs[self.rng.below(self.blobs.len())];
            (*f, b.clone())
        } else {
            (fmu, self.h.fmus[fmu].blob.clone())
        };
        let base = if own.0 == fmu {
            own.1
        } else {
            return (BlobKind::Foreign, own.1);
        };
        match self.rng.below(8) {
            0 | 1 => (BlobKind::Own, base),
            2 => {
                let f = self.rng.below(self.h.fmus.len());
                let kind = if f == fmu {
                    BlobKind::Own
                } else {
                    BlobKind::Foreign
                };
                (kind, self.h.fmus[f].blob.clone())
            }
            3 => {
                let mut b = base;
                let l = self.rng.below(b.len());
                b.truncate(l);
                (BlobKind::Truncated, b)
            }
            4 => {
                let mut b = base.clone();
                for _ in 0..1 + self.rng.below(3) {
                    let p = self.rng.below(b.len());
                    b[p] ^= 1 << self.rng.below(8);
                }
                if b == base {
                    // two flips of the same bit cancelled
                    b[0] ^= 1;
                }
                (BlobKind::Corrupted, b)
            }
            5 => {
                let mut b = base;
                for _ in 0..1 + self.rng.below(64) {
                    b.push(self.rng.next() as u8);
                }
                (BlobKind::Extended, b)
            }
            6 => {
                let n = self.rng.below(300);
                let mut b: Vec<u8> = (0..n).map(|_| self.rng.next() as u8).collect();
                // sometimes with the real header in front
                if self.rng.chance(0.5) {
                    let l = base.len().min(64).min(b.len());
                    b[..l].copy_from_slice(&base[..l]);
                }
                (BlobKind::Noise, b)
            }
            _ => (BlobKind::Empty, Vec::new()),
        }
    }

    /// One random call with hostile arguments on (mostly) instance `i`.
    fn random_call(&mut self, i: usize) {
        let fmu = self.live[i].fmu;
        let c = self.component(i);
        let n = self.rng.pick(&[0, 1, 1, 1, 2, 3, 4]);
        let nullish = self.rng.chance(0.08);
        let mut reals: Vec<f64> = (0..n).map(|_| self.rng.real()).collect();
        let ints: Vec<i32> = (0..n).map(|_| self.rng.integer()).collect();
        let bools: Vec<i32> = (0..n).map(|_| self.rng.boolean()).collect();
        let mut out = vec![0.0f64; n];
        let mut iout = vec![0i32; n];
        let arr = |v: &Vec<u32>| if nullish { ptr::null() } else { v.as_ptr() };
        let action = self.rng.below(30);
        // SAFETY: every array holds the number of elements passed with it (or is NULL);
        // pointers are live components, live states, NULL, or readable buffers.
        unsafe {
            match action {
                0 => {
                    let start = if self.rng.chance(0.7) {
                        0.0
                    } else {
                        self.rng.real()
                    };
                    let s = fmi2SetupExperiment(
                        c,
                        self.rng.boolean(),
                        self.rng.real(),
                        start,
                        self.rng.boolean(),
                        self.rng.real(),
                    );
                    self.record("fmi2SetupExperiment", s);
                    self.track(c, s, |_| {});
                }
                1 => {
                    let s = fmi2EnterInitializationMode(c);
                    self.record("fmi2EnterInitializationMode", s);
                    self.track(c, s, |l| l.state = Tracked::Initialization);
                }
                2 => {
                    let s = fmi2ExitInitializationMode(c);
                    self.record("fmi2ExitInitializationMode", s);
                    self.track(c, s, |l| {
                        l.state = Tracked::StepComplete;
                        l.time = 0.0;
                    });
                }
                3 => {
                    let s = fmi2Terminate(c);
                    self.record("fmi2Terminate", s);
                    self.track(c, s, |l| l.state = Tracked::Terminated);
                }
                4 => self.reset(c),
                5 | 6 => {
                    let now = self.live[i].time;
                    let t = match self.rng.below(6) {
                        0 => self.rng.real(),
                        1 => now + 1e-3,
                        _ => now,
                    };
                    let h = self.rng.pick(&[
                        1e-6,
                        1e-4,
                        1e-3,
                        5e-3,
                        0.0,
                        -0.0,
                        -1e-3,
                        f64::NAN,
                        f64::INFINITY,
                        f64::NEG_INFINITY,
                        1e12,
                        1e300,
                        f64::MAX,
                        5e-324,
                    ]);
                    self.note(|| format!("{c:?} fmi2DoStep({t}, {h})"));
                    let s = fmi2DoStep(c, t, h, self.rng.boolean());
                    self.record("fmi2DoStep", s);
                    if s == FMI2_OK {
                        *self
                            .sum
                            .ok_steps_by_scene
                            .entry(self.h.fmus[fmu].name.clone())
                            .or_default() += 1;
                    }
                    if s == FMI2_DISCARD
                        && let Some(l) = self.live.iter_mut().find(|l| l.c == c)
                    {
                        l.state = Tracked::StepFailed;
                    }
                    self.track(c, s, |l| l.time = t + h);
                }
                7 => {
                    let v = self.vrs(fmu, Some(VarType::Real), n);
                    // keep solver.max_step at least 0.1 ms (the module doc)
                    let max_step = self.h.fmus[fmu].max_step_vr;
                    for (vr, x) in v.iter().zip(reals.iter_mut()) {
                        if Some(*vr) == max_step && x.is_finite() && *x > 0.0 {
                            *x = x.max(1e-4);
                        }
                    }
                    let vals = if nullish && self.rng.chance(0.5) {
                        ptr::null()
                    } else {
                        reals.as_ptr()
                    };
                    let p = if vals.is_null() { v.as_ptr() } else { arr(&v) };
                    self.note(|| format!("{c:?} fmi2SetReal({v:?}, {reals:?})"));
                    let s = fmi2SetReal(c, p, n, vals);
                    self.record("fmi2SetReal", s);
                    self.track(c, s, |_| {});
                }
                8 => {
                    let (mesh, load_steps) =
                        (self.h.fmus[fmu].mesh_vr, self.h.fmus[fmu].load_steps_vr);
                    let v = self.vrs(fmu, Some(VarType::Integer), n);
                    // valid mesh sizes and load increments stay small (the module doc)
                    let ints: Vec<i32> = v
                        .iter()
                        .zip(&ints)
                        .map(|(vr, &x)| {
                            let big = |hi| (33..=hi).contains(&x);
                            if Some(*vr) == mesh && big(100_000)
                                || Some(*vr) == load_steps && big(1_000_000)
                            {
                                4
                            } else {
                                x
                            }
                        })
                        .collect();
                    self.note(|| format!("{c:?} fmi2SetInteger({v:?}, {ints:?})"));
                    let s = fmi2SetInteger(c, arr(&v), n, ints.as_ptr());
                    self.record("fmi2SetInteger", s);
                    self.track(c, s, |_| {});
                }
                9 => {
                    let v = self.vrs(fmu, Some(VarType::Boolean), n);
                    self.note(|| format!("{c:?} fmi2SetBoolean({v:?}, {bools:?})"));
                    let s = fmi2SetBoolean(c, arr(&v), n, bools.as_ptr());
                    self.record("fmi2SetBoolean", s);
                    self.track(c, s, |_| {});
                }
                10 | 11 => {
                    let ty = if action == 10 {
                        Some(VarType::Real)
                    } else {
                        None
                    };
                    let v = self.vrs(fmu, ty, n);
                    let o = if nullish {
                        ptr::null_mut()
                    } else {
                        out.as_mut_ptr()
                    };
                    let s = fmi2GetReal(c, v.as_ptr(), n, o);
                    self.record("fmi2GetReal", s);
                    self.track(c, s, |_| {});
                }
                12 => {
                    let v = self.vrs(fmu, Some(VarType::Integer), n);
                    let s = fmi2GetInteger(c, arr(&v), n, iout.as_mut_ptr());
                    self.record("fmi2GetInteger", s);
                    self.track(c, s, |_| {});
                }
                13 => {
                    let v = self.vrs(fmu, Some(VarType::Boolean), n);
                    let s = fmi2GetBoolean(c, arr(&v), n, iout.as_mut_ptr());
                    self.record("fmi2GetBoolean", s);
                    self.track(c, s, |_| {});
                }
                14 => {
                    let v = self.vrs(fmu, None, n);
                    let strings: Vec<Fmi2String> = (0..n)
                        .map(|_| {
                            if self.rng.chance(0.2) {
                                ptr::null()
                            } else {
                                c"text".as_ptr()
                            }
                        })
                        .collect();
                    let s = if self.rng.chance(0.5) {
                        (
                            "fmi2SetString",
                            fmi2SetString(c, arr(&v), n, strings.as_ptr()),
                        )
                    } else {
                        let mut so: Vec<Fmi2String> = vec![ptr::null(); n];
                        (
                            "fmi2GetString",
                            fmi2GetString(c, arr(&v), n, so.as_mut_ptr()),
                        )
                    };
                    self.record(s.0, s.1);
                    self.track(c, s.1, |_| {});
                }
                15 => {
                    // into a new state, into a live one (updated in place), into a foreign
                    // pointer, or NULL
                    let mut target: Fmi2FmuState = ptr::null_mut();
                    let mut reuse = None;
                    match self.rng.below(6) {
                        0 if !self.states.is_empty() => {
                            let j = self.rng.below(self.states.len());
                            target = self.states[j];
                            reuse = Some(j);
                        }
                        1 => target = self.live[self.rng.below(self.live.len())].c,
                        2 => target = self.garbage.as_mut_ptr() as Fmi2FmuState,
                        _ => {}
                    }
                    let foreign = !target.is_null() && reuse.is_none();
                    let s = if nullish {
                        fmi2GetFMUstate(c, ptr::null_mut())
                    } else {
                        fmi2GetFMUstate(c, &mut target)
                    };
                    self.record("fmi2GetFMUstate", s);
                    self.track(c, s, |_| {});
                    if s == FMI2_OK && !nullish {
                        assert!(
                            !foreign,
                            "sequence {}: fmi2GetFMUstate accepted a foreign pointer",
                            self.k
                        );
                        if reuse.is_none() {
                            self.states.push(target);
                        }
                        if let Some(f) = self.scene_of(c) {
                            self.state_scene.insert(target as usize, f);
                        }
                    }
                }
                16 => {
                    let target = match self.rng.below(8) {
                        0 => ptr::null_mut(),
                        1 => self.garbage.as_mut_ptr() as Fmi2FmuState,
                        2 => self.live[self.rng.below(self.live.len())].c,
                        _ if !self.states.is_empty() => self.rng.pick(&self.states),
                        _ => ptr::null_mut(),
                    };
                    let s = fmi2SetFMUstate(c, target);
                    self.record("fmi2SetFMUstate", s);
                    self.track(c, s, |l| l.state = Tracked::Restored);
                }
                17 => {
                    // free a live state, a NULL state (no-op), NULL, or a foreign pointer
                    let choice = self.rng.below(6);
                    if choice < 3 && !self.states.is_empty() {
                        let j = self.rng.below(self.states.len());
                        let mut s0 = self.states[j];
                        let s = fmi2FreeFMUstate(c, &mut s0);
                        self.record("fmi2FreeFMUstate", s);
                        self.track(c, s, |_| {});
                        if s == FMI2_OK {
                            assert!(s0.is_null());
                            let freed = self.states.swap_remove(j);
                            self.state_scene.remove(&(freed as usize));
                        }
                    } else {
                        let mut p: Fmi2FmuState = match choice {
                            3 => self.garbage.as_mut_ptr() as Fmi2FmuState,
                            4 => self.live[self.rng.below(self.live.len())].c,
                            _ => ptr::null_mut(),
                        };
                        let s = if nullish {
                            fmi2FreeFMUstate(c, ptr::null_mut())
                        } else {
                            fmi2FreeFMUstate(c, &mut p)
                        };
                        self.record("fmi2FreeFMUstate", s);
                        self.track(c, s, |_| {});
                    }
                }
                18 | 19 => {
                    // size and serialization of a live state (or of a foreign pointer)
                    let st = if !self.states.is_empty() && self.rng.chance(0.85) {
                        self.rng.pick(&self.states)
                    } else if self.rng.chance(0.5) {
                        self.live[self.rng.below(self.live.len())].c
                    } else {
                        ptr::null_mut()
                    };
                    let mut size = 0usize;
                    let s = if nullish {
                        fmi2SerializedFMUstateSize(c, st, ptr::null_mut())
                    } else {
                        fmi2SerializedFMUstateSize(c, st, &mut size)
                    };
                    self.record("fmi2SerializedFMUstateSize", s);
                    self.track(c, s, |_| {});
                    if s == FMI2_OK && !nullish {
                        let (len, pass) = match self.rng.below(5) {
                            0 => (size.saturating_sub(1), size.saturating_sub(1)),
                            1 => (size + 16, size + 16),
                            2 => (0, size),
                            _ => (size, size),
                        };
                        let mut buf = vec![0u8; len];
                        let p = if len == 0 && pass > 0 {
                            ptr::null_mut()
                        } else {
                            buf.as_mut_ptr() as *mut c_char
                        };
                        let s2 = fmi2SerializeFMUstate(c, st, p, pass);
                        self.record("fmi2SerializeFMUstate", s2);
                        self.track(c, s2, |_| {});
                        if s2 == FMI2_OK && pass >= size && !p.is_null() {
                            buf.truncate(size);
                            if let Some(&f) = self.state_scene.get(&(st as usize))
                                && self.blobs.len() < 8
                            {
                                self.blobs.push((f, buf));
                            }
                        }
                    }
                }
                20 | 21 => {
                    let (kind, data) = self.blob(self.scene_of(c).unwrap_or(fmu));
                    let mut st: Fmi2FmuState = ptr::null_mut();
                    let (p, len) = match self.rng.below(12) {
                        0 => (ptr::null(), data.len()),
                        _ => (data.as_ptr() as *const c_char, data.len()),
                    };
                    let s = if nullish {
                        fmi2DeSerializeFMUstate(c, p, len, ptr::null_mut())
                    } else {
                        fmi2DeSerializeFMUstate(c, p, len, &mut st)
                    };
                    self.record("fmi2DeSerializeFMUstate", s);
                    self.track(c, s, |_| {});
                    let real_c = self.live.iter().any(|l| l.c == c);
                    if real_c && !nullish && (!p.is_null() || len == 0) {
                        let book = if s == FMI2_OK {
                            &mut self.sum.accepted_blobs
                        } else {
                            &mut self.sum.rejected_blobs
                        };
                        *book.entry(kind.name()).or_default() += 1;
                    }
                    if !st.is_null() {
                        assert_eq!(s, FMI2_OK);
                        self.states.push(st);
                        if let Some(f) = self.scene_of(c) {
                            self.state_scene.insert(st as usize, f);
                        }
                    }
                }
                22 => {
                    let nk = self.rng.pick(&[0, 1, 1, 2]);
                    let unknown = self.vrs(fmu, Some(VarType::Real), n);
                    let known = self.vrs(fmu, Some(VarType::Real), nk);
                    let dk: Vec<f64> = (0..nk).map(|_| self.rng.real()).collect();
                    let s = fmi2GetDirectionalDerivative(
                        c,
                        arr(&unknown),
                        n,
                        known.as_ptr(),
                        nk,
                        dk.as_ptr(),
                        out.as_mut_ptr(),
                    );
                    self.record("fmi2GetDirectionalDerivative", s);
                    self.track(c, s, |_| {});
                }
                23 => {
                    let v = self.vrs(fmu, Some(VarType::Real), n);
                    let orders: Vec<i32> = (0..n)
                        .map(|_| self.rng.pick(&[1, 1, 2, 0, 3, -1, i32::MAX, i32::MIN]))
                        .collect();
                    let s =
                        fmi2SetRealInputDerivatives(c, arr(&v), n, orders.as_ptr(), reals.as_ptr());
                    self.record("fmi2SetRealInputDerivatives", s);
                    self.track(c, s, |_| {});
                }
                24 => {
                    let v = self.vrs(fmu, Some(VarType::Real), n);
                    let orders: Vec<i32> = (0..n)
                        .map(|_| self.rng.pick(&[1, 1, 2, 0, 3, -1, i32::MAX]))
                        .collect();
                    let s = fmi2GetRealOutputDerivatives(
                        c,
                        arr(&v),
                        n,
                        orders.as_ptr(),
                        out.as_mut_ptr(),
                    );
                    self.record("fmi2GetRealOutputDerivatives", s);
                    self.track(c, s, |_| {});
                }
                25 => {
                    let s = fmi2CancelStep(c);
                    self.record("fmi2CancelStep", s);
                    self.track(c, s, |_| {});
                }
                26 => {
                    let kind = self.rng.below(7) as i32 - 1;
                    let null = self.rng.chance(0.1);
                    let (f, s) = match self.rng.below(5) {
                        0 => {
                            let mut v = 0;
                            let p = if null { ptr::null_mut() } else { &mut v };
                            ("fmi2GetStatus", fmi2GetStatus(c, kind, p))
                        }
                        1 => {
                            let mut v = 0.0;
                            let p = if null { ptr::null_mut() } else { &mut v };
                            ("fmi2GetRealStatus", fmi2GetRealStatus(c, kind, p))
                        }
                        2 => {
                            let mut v = 0;
                            let p = if null { ptr::null_mut() } else { &mut v };
                            ("fmi2GetIntegerStatus", fmi2GetIntegerStatus(c, kind, p))
                        }
                        3 => {
                            let mut v = 0;
                            let p = if null { ptr::null_mut() } else { &mut v };
                            ("fmi2GetBooleanStatus", fmi2GetBooleanStatus(c, kind, p))
                        }
                        _ => {
                            let mut v: Fmi2String = ptr::null();
                            let p = if null { ptr::null_mut() } else { &mut v };
                            ("fmi2GetStringStatus", fmi2GetStringStatus(c, kind, p))
                        }
                    };
                    self.record(f, s);
                    self.track(c, s, |_| {});
                }
                27 => {
                    let names = [
                        c"logEvents".as_ptr(),
                        c"logCalls".as_ptr(),
                        c"logStatusError".as_ptr(),
                        c"noSuchCategory".as_ptr(),
                        c"".as_ptr(),
                        ptr::null(),
                    ];
                    let cats: Vec<*const c_char> = (0..n)
                        .map(|_| {
                            let j = if self.rng.chance(0.9) {
                                self.rng.below(3)
                            } else {
                                self.rng.below(names.len())
                            };
                            names[j]
                        })
                        .collect();
                    let p = if nullish { ptr::null() } else { cats.as_ptr() };
                    let s = fmi2SetDebugLogging(c, self.rng.boolean(), n, p);
                    self.record("fmi2SetDebugLogging", s);
                    self.track(c, s, |_| {});
                }
                28 => {
                    // free an instance in the middle (or try a NULL or foreign pointer), or
                    // make another one
                    match self.rng.below(6) {
                        0 => {
                            let l = self.live.swap_remove(i);
                            fmi2FreeInstance(l.c);
                        }
                        1 => fmi2FreeInstance(ptr::null_mut()),
                        2 => fmi2FreeInstance(self.garbage.as_mut_ptr() as Fmi2Component),
                        3 if !self.states.is_empty() => {
                            // a state is not a component: ignored
                            fmi2FreeInstance(self.rng.pick(&self.states))
                        }
                        _ if self.live.len() < 4 => self.instantiate(),
                        _ => {}
                    }
                    self.sum.calls += 1;
                }
                _ => {
                    let tp = fmi2GetTypesPlatform();
                    let v = fmi2GetVersion();
                    assert!(!tp.is_null() && !v.is_null());
                    self.sum.calls += 2;
                }
            }
        }
    }
}
