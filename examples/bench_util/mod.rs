//! Helpers shared by the benchmark examples (`mod bench_util;`): scenes by name and timers.
//! Not every example uses every helper.
#![allow(dead_code)]

use flexfmu::scene::Scene;
use std::path::Path;
use std::time::Instant;

/// A shipped scene `scenes/<name>.toml`.
pub fn scene(name: &str) -> Scene {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    Scene::from_path(&root.join("scenes").join(format!("{name}.toml"))).unwrap()
}

/// Best of `reps` timings of `f` [s].
pub fn best<F: FnMut()>(reps: usize, mut f: F) -> f64 {
    (0..reps)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Mean seconds per call of `f`, repeated for at least `min_secs`.
pub fn time_it(min_secs: f64, mut f: impl FnMut()) -> f64 {
    let mut reps = 1usize;
    loop {
        let t = Instant::now();
        for _ in 0..reps {
            f();
        }
        let dt = t.elapsed().as_secs_f64();
        if dt >= min_secs {
            return dt / reps as f64;
        }
        reps = (reps * 2).max((reps as f64 * min_secs / dt.max(1e-9)) as usize / 2);
    }
}
