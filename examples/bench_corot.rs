//! Cost of the co-rotational 3D beam's kernels (release build, one core) on 256 configurations
//! of a belt element (Timoshenko, lumped inertia, bowing term; l0 = 10 mm, node rotations up
//! to 0.05 rad apart, any rigid rotation): the internal force alone, force and tangent, and
//! the inertia force with its matrices; best of 5 passes, ns per element.
//!
//! `cargo run --release --example bench_corot [-- dump.txt]`: with a path, also writes every
//! force and matrix entry (one per line), to compare two builds for round-off.

use flexfmu::elements::corotational3d::{
    BeamSection, Corot3d, MassModel, Mat12, Nodes, Rates, Theory, Vec12,
};
use flexfmu::elements::rotation::exp_so3;
use nalgebra::{Matrix3, Vector3};
use std::hint::black_box;
use std::io::Write;
use std::time::Instant;

/// Best of 5 passes of `reps` × `f` over the configurations, ns per call.
fn best_ns(n: usize, reps: usize, mut f: impl FnMut()) -> f64 {
    (0..5)
        .map(|_| {
            let t0 = Instant::now();
            for _ in 0..reps {
                f();
            }
            t0.elapsed().as_secs_f64() * 1e9 / (reps * n) as f64
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    let dump = std::env::args().nth(1);
    let s = BeamSection {
        ea: 5e4,
        ga_y: 2e4,
        ga_z: 2e4,
        gj: 0.02,
        ei_y: 0.05,
        ei_z: 2.0,
        rho_a: 0.1,
        rho_jx: 1e-5,
        rho_iy: 1e-6,
        rho_iz: 1e-5,
    };
    let l0 = 0.01;
    let el = Corot3d::new(
        l0,
        Matrix3::identity(),
        &s,
        Theory::Timoshenko,
        MassModel::Lumped,
    )
    .with_bowing(true);
    // deterministic pseudo-random configurations (xorshift)
    let mut seed = 12345u64;
    let mut rnd = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut nodes = Vec::new();
    for _ in 0..256 {
        let g = exp_so3(&Vector3::new(rnd() * 3.0, rnd() * 3.0, rnd() * 3.0));
        let r1 = g * exp_so3(&Vector3::new(rnd() * 0.05, rnd() * 0.05, rnd() * 0.05));
        let r2 = g * exp_so3(&Vector3::new(rnd() * 0.05, rnd() * 0.05, rnd() * 0.05));
        let x1 = Vector3::new(rnd(), rnd(), rnd()) * 0.1;
        let d = Vector3::new(
            l0 * (1.0 + 1e-3 * rnd()),
            l0 * 0.02 * rnd(),
            l0 * 0.02 * rnd(),
        );
        nodes.push(Nodes {
            x: [x1, x1 + g * d],
            r: [r1, r2],
        });
    }
    let rates = |n: &Nodes| {
        let w = n.x[0] * 37.0;
        Rates {
            x: [w, w * 1.1],
            w: [
                Vector3::new(3.0, -2.0, 40.0) + w,
                Vector3::new(3.5, -2.2, 41.0) - w,
            ],
        }
    };
    let g = Vector3::new(0.0, -9.81, 0.0);
    let (mut f, mut k, mut mc) = (Vec12::zeros(), Mat12::zeros(), Mat12::zeros());
    let reps = 400;
    let nn = nodes.len();
    let force = best_ns(nn, reps, || {
        for n in &nodes {
            black_box(el.internal_force(black_box(n), &mut f));
        }
    });
    let tangent = best_ns(nn, reps, || {
        for n in &nodes {
            black_box(el.internal_force_tangent(black_box(n), &mut f, &mut k));
        }
    });
    let inertia = best_ns(nn, reps, || {
        for n in &nodes {
            let v = rates(n);
            // (`Mat12::zeros()`, not `fill(0.0)`: the fill compiled to a slow loop that cost
            // more than the kernel, session 38, helper b3inert)
            mc = Mat12::zeros();
            k = Mat12::zeros();
            el.inertia_force(
                black_box(n),
                &v,
                &v,
                &g,
                &mut f,
                Some((1e6, 1e3, &mut mc, &mut k)),
            );
            black_box(&mc);
        }
    });
    println!(
        "internal force {force:.1} ns, force and tangent {tangent:.1} ns ({:.2}x), \
         inertia with matrices {inertia:.1} ns",
        tangent / force
    );
    if let Some(path) = dump {
        let mut file = std::fs::File::create(path).expect("dump file");
        for n in &nodes {
            el.internal_force_tangent(n, &mut f, &mut k);
            for x in f.iter().chain(k.iter()) {
                writeln!(file, "{x:e}").expect("write");
            }
            let v = rates(n);
            mc.fill(0.0);
            k.fill(0.0);
            f.fill(0.0);
            el.inertia_force(n, &v, &v, &g, &mut f, Some((1e6, 1e3, &mut mc, &mut k)));
            for x in f.iter().chain(mc.iter()).chain(k.iter()) {
                writeln!(file, "{x:e}").expect("write");
            }
        }
    }
}
