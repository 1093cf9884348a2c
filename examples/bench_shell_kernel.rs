//! Cost of the seed-004 shell element kernels: internal force, force + tangent, per element
//! and call, for both bending variants and with the geometric stiffness. Prints a table.
use flexfmu::elements::Element;
use flexfmu::elements::element::{ElementState, Frame};
use flexfmu::elements::rotation::exp_so3;
use flexfmu::elements::trapezoid_shell::*;
use nalgebra::{Matrix3, Vector3};
use std::time::Instant;

fn main() {
    let mat = ShellMaterial {
        e: 2.1e11,
        nu: 0.3,
        rho: 7850.0,
        thickness: 0.01,
    };
    let x0 = [(0.0, 0.0), (0.5, 0.0), (0.4, 0.3), (0.1, 0.3)].map(|(x, y)| Vector3::new(x, y, 0.0));
    println!("| variant | force [us] | force + tangent [us] |");
    println!("|---|---|---|");
    for (name, bending, geo) in [
        ("V2", Bending::V2, false),
        ("V1", Bending::V1, false),
        ("V2 + geometric", Bending::V2, true),
    ] {
        let opt = ShellOptions {
            bending,
            geometric_stiffness: geo,
            ..ShellOptions::default()
        };
        let el = TrapezoidShell::new(x0, &mat, &opt).unwrap();
        let q0 = exp_so3(&Vector3::new(0.3, -0.2, 0.5));
        let mut q = Vec24::zeros();
        for (i, x) in x0.iter().enumerate() {
            q.fixed_rows_mut::<3>(6 * i)
                .copy_from(&(q0 * x + Vector3::new(0.001 * i as f64, 0.0, 0.002)));
        }
        let frames: Vec<Frame> = (0..4)
            .map(|i| Frame {
                rot: q0 * exp_so3(&Vector3::new(0.01 * i as f64, 0.02, 0.0)),
                tangent: Matrix3::identity(),
            })
            .collect();
        let s = ElementState {
            q,
            v: Vec24::zeros(),
            frames: &frames,
        };
        let (mut f, mut k) = (Vec24::zeros(), Mat24::zeros());
        let n = 20000;
        let t = Instant::now();
        for _ in 0..n {
            el.force_into(std::hint::black_box(&s), &mut f);
        }
        let tf = t.elapsed().as_secs_f64() / n as f64 * 1e6;
        let t = Instant::now();
        for _ in 0..n {
            el.tangent_into(std::hint::black_box(&s), &mut f, &mut k, None);
        }
        let tk = t.elapsed().as_secs_f64() / n as f64 * 1e6;
        println!("| {name} | {tf:.2} | {tk:.2} |");
    }
}
