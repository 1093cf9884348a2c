//! Motion ports of the `shell` kind (issue 10 item 3): a plate edge, a ring or a node moved
//! rigidly in translation by the master, rotations held. Static reactions against the
//! clamped–guided plate strip and the stretched tube, a harmonic drive, the interface Jacobian
//! against stepped finite differences, and the scene errors. Measured figures are printed
//! (`--nocapture`).

mod common;
use common::*;
use flexfmu::scene::Scene;
use flexfmu::snapshot::{StateReader, StateWriter};
use flexfmu::solver::simulation::Simulation;
use flexfmu::variables::Value;
use std::f64::consts::PI;

const E: f64 = 210e9;
const RHO: f64 = 7850.0;

/// A steel strip `L × b × h` = 1 m × 0.2 m × 10 mm, ν = 0, clamped at x = 0, its edge x = L
/// the motion port `tip` (`{extra}` appended).
fn strip(static_eq: bool, extra: &str) -> Scene {
    let text = format!(
        r#"
kind = "shell"
[fmu]
model_name = "strip_port"
[experiment]
step_size = 1e-3
[material]
E = {E}
nu = 0.0
rho = {RHO}
[shell]
thickness = 0.01
[plate]
length_x = 1.0
length_y = 0.2
[mesh]
n_x = 8
n_y = 2
[support]
x0 = "clamped"
[solver]
static_equilibrium = {static_eq}
max_step = 1e-3
[[motions]]
name = "tip"
edge = "x1"
[[probes]]
name = "mid"
at = [0.5, 0.1]
outputs = ["z"]
{extra}
"#
    );
    Scene::from_toml(&text).unwrap_or_else(|e| panic!("{}", e.0))
}

/// An open steel tube, radius 0.1 m, length 0.5 m, 2 mm wall, ν = 0, clamped at its first
/// ring; its last ring the motion port `end`. Newmark steps (the condensation's own scheme)
/// and the geometric stiffness on (an exact tangent).
fn tube(static_eq: bool) -> Scene {
    let text = format!(
        r#"
kind = "shell"
[fmu]
model_name = "tube_port"
[experiment]
step_size = 1e-4
[material]
E = {E}
nu = 0.0
rho = {RHO}
[shell]
thickness = 0.002
[element]
geometric_stiffness = true
[meridian]
start = [0.1, 0.0]
[[meridian.pieces]]
direction = [0.0, 1.0]
length = 0.5
[mesh]
n_circumferential = 16
n_meridional = 8
[[ring_supports]]
ring = "first"
kind = "clamped"
[solver]
static_equilibrium = {static_eq}
max_step = 1e-4
integrator = "newmark"
[[motions]]
name = "end"
ring = "last"
"#
    );
    Scene::from_toml(&text).unwrap_or_else(|e| panic!("{}", e.0))
}

/// Stiffness of the clamped–guided strip (the port holds the edge's rotations), ν = 0:
/// `12 E I / L³`, `I = b h³ / 12`.
fn guided_strip_stiffness() -> f64 {
    let (l, b, h) = (1.0, 0.2, 0.01);
    12.0 * E * (b * h * h * h / 12.0) / (l * l * l)
}

/// The port's inputs start at its reference point (the edge's midpoint), and a static
/// transverse displacement `δ` of the edge gives the force on the driver `−12 E I δ / L³`
/// (the strip pulls the driver back), no in-plane force to first order.
#[test]
fn static_reaction_of_the_guided_strip() {
    let sc = strip(true, "");
    let sim = simulation(&sc, &[]).unwrap();
    let vars = flexfmu::variables::VariableTable::from_scene(&sc);
    let start = |n: &str| match vars.by_name(n).unwrap().start {
        Some(Value::Real(x)) => x,
        other => panic!("{n}: {other:?}"),
    };
    assert_eq!(
        [start("tip.x"), start("tip.y"), start("tip.z")],
        [1.0, 0.1, 0.0]
    );
    for c in ["fx", "fy", "fz"] {
        let f = output(&sc, &sim, &format!("tip.{c}"));
        assert!(f.abs() < 1e-9, "tip.{c} = {f} at the reference");
    }
    let k = guided_strip_stiffness();
    let delta = 1e-5;
    let sim = simulation(&sc, &[("tip.z", Value::Real(delta))]).unwrap();
    let fz = output(&sc, &sim, "tip.fz");
    let rel = (fz + k * delta).abs() / (k * delta);
    println!(
        "guided strip: fz = {fz:.6} N, -12EI/L^3 delta = {:.6} N, rel. error {rel:.2e}",
        -k * delta
    );
    assert!(rel < 2e-3, "fz = {fz}, want {}", -k * delta);
    // the midpoint of a guided strip deflects by δ/2 (antisymmetric about it)
    let mid = output(&sc, &sim, "mid.z");
    assert!((mid - 0.5 * delta).abs() < 2e-3 * delta, "mid.z = {mid}");
    // to second order the guided strip is stretched by the shortening of its bent centre
    // line, `∫ w'²/2 dx = 0.6 δ² / L` for `w = δ (3ξ² − 2ξ³)`: `fx = −E A 0.6 δ² / L²`
    let fx = output(&sc, &sim, "tip.fx");
    let ea = E * 0.2 * 0.01;
    let fx2 = -ea * 0.6 * delta * delta;
    println!("guided strip: fx = {fx:.5e} N, second order -EA 0.6 delta^2/L^2 = {fx2:.5e} N");
    assert!((fx - fx2).abs() < 0.03 * fx2.abs(), "fx = {fx}");
    let fy = output(&sc, &sim, "tip.fy");
    assert!(fy.abs() < 1e-9 * k * delta, "tip.fy = {fy}");
    // an in-plane shift along x stretches the strip: EA / L
    let sim = simulation(&sc, &[("tip.x", Value::Real(1.0 + delta))]).unwrap();
    let fx = output(&sc, &sim, "tip.fx");
    let ka = E * 0.2 * 0.01 / 1.0;
    println!(
        "strip stretched: fx = {fx:.4} N, -EA/L delta = {:.4} N",
        -ka * delta
    );
    assert!((fx + ka * delta).abs() < 1e-6 * ka * delta, "fx = {fx}");
}

/// A ring port pushed along the axis of a tube stretches it uniformly: `fz = −E A δ / L` with
/// the area of the 16-gon wall, `A = 2 n R sin(π/n) h`; no lateral force.
#[test]
fn static_reaction_of_the_stretched_tube() {
    let sc = tube(true);
    let delta = 1e-6;
    let sim = simulation(&sc, &[("end.z", Value::Real(0.5 + delta))]).unwrap();
    let n = 16.0;
    let area = 2.0 * n * 0.1 * (PI / n).sin() * 0.002;
    let k = E * area / 0.5;
    let fz = output(&sc, &sim, "end.fz");
    println!(
        "tube: fz = {fz:.6} N, -EA/L delta = {:.6} N (rel. {:.2e})",
        -k * delta,
        (fz + k * delta).abs() / (k * delta)
    );
    assert!((fz + k * delta).abs() < 1e-6 * k * delta, "fz = {fz}");
    for c in ["fx", "fy"] {
        let f = output(&sc, &sim, &format!("end.{c}"));
        assert!(f.abs() < 1e-9 * k * delta, "end.{c} = {f}");
    }
}

/// Master loop: sets `name.{axis}` and its velocity to `u(t)`, `u'(t)` at every communication
/// point and steps; returns `(t, u, force)` after every step.
fn drive(
    sc: &Scene,
    sim: &mut Simulation,
    (port, axis): (&str, &str),
    u: impl Fn(f64) -> (f64, f64),
    base: f64,
    dt: f64,
    n: usize,
) -> Vec<(f64, f64, f64)> {
    let pos = input_index(sc, &format!("{port}.{axis}"));
    let vel = input_index(sc, &format!("{port}.v{axis}"));
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let t = k as f64 * dt;
        let (x, v) = u(t);
        sim.set_input(pos, base + x);
        sim.set_input(vel, v);
        sim.advance(t + dt).unwrap();
        let (x1, _) = u(t + dt);
        out.push((t + dt, x1, output(sc, sim, &format!("{port}.f{axis}"))));
    }
    out
}

/// A slow harmonic drive of the strip's edge (1 Hz, the first clamped–guided mode at 13 Hz):
/// the reaction follows the quasi-static `−k u` up to the inertia of the strip
/// (`(ω/ω₁)² ≈ 0.6 %`) and the transient the start excites.
#[test]
fn reaction_follows_a_harmonic_motion() {
    let sc = strip(false, "");
    let mut sim = simulation(&sc, &[]).unwrap();
    let (a, w) = (1e-3, 2.0 * PI);
    // smooth start: u = A (1 − cos ωt), at rest at t = 0
    let hist = drive(
        &sc,
        &mut sim,
        ("tip", "z"),
        |t| (a * (1.0 - (w * t).cos()), a * w * (w * t).sin()),
        0.0,
        1e-3,
        1000,
    );
    let k = guided_strip_stiffness();
    let worst = hist
        .iter()
        .map(|&(_, u, f)| (f + k * u).abs())
        .fold(0.0, f64::max);
    let peak = hist.iter().map(|&(_, _, f)| f.abs()).fold(0.0, f64::max);
    println!(
        "harmonic drive: peak |fz| = {peak:.3} N (k 2A = {:.3} N), worst |fz + k u| = {worst:.4} N ({:.2} % of k 2A)",
        k * 2.0 * a,
        100.0 * worst / (k * 2.0 * a)
    );
    assert!(worst < 0.03 * k * 2.0 * a, "worst deviation {worst}");
    assert!(
        (peak - k * 2.0 * a).abs() < 0.03 * k * 2.0 * a,
        "peak {peak}"
    );
}

/// The interface Jacobian (the model's ∂f/∂u, what `fmi2GetDirectionalDerivative` returns)
/// predicts the change of the reactions after one communication step (one internal step) when
/// the prescribed position is shifted by ±δ: central differences of the stepped outputs, with
/// state rollback. For the strip's edge (bent by a motion first; generalized-α) and the tube's
/// ring (Newmark).
#[test]
fn interface_jacobian_predicts_the_step_response() {
    for (sc, port, h, moving, axes) in [
        (strip(false, ""), "tip", 1e-3, "z", ["x", "y", "z"]),
        (tube(false), "end", 1e-4, "x", ["x", "y", "z"]),
    ] {
        let mut sim = simulation(&sc, &[]).unwrap();
        let base = |axis: &str| match flexfmu::variables::VariableTable::from_scene(&sc)
            .by_name(&format!("{port}.{axis}"))
            .unwrap()
            .start
        {
            Some(Value::Real(x)) => x,
            _ => unreachable!(),
        };
        // move the port for ten steps at 0.2 m/s
        let b = base(moving);
        drive(&sc, &mut sim, (port, moving), |t| (0.2 * t, 0.2), b, h, 10);
        let t = 10.0 * h;
        let inputs: Vec<usize> = axes
            .iter()
            .map(|a| input_index(&sc, &format!("{port}.{a}")))
            .collect();
        let outputs: Vec<usize> = axes
            .iter()
            .map(|a| {
                let vars = flexfmu::variables::VariableTable::from_scene(&sc);
                match vars.by_name(&format!("{port}.f{a}")).unwrap().role {
                    flexfmu::variables::Role::Output(k) => k,
                    _ => unreachable!(),
                }
            })
            .collect();
        // the position of the coming point, then the state to roll back to
        let mut u: Vec<f64> = axes.iter().map(|a| base(a)).collect();
        let m = axes.iter().position(|a| *a == moving).unwrap();
        u[m] += 0.2 * (t + h);
        for (j, &i) in inputs.iter().enumerate() {
            sim.set_input(i, u[j]);
        }
        let mut w = StateWriter::new();
        sim.save(&mut w).unwrap();
        let state = w.into_bytes();
        let delta = 1e-8;
        let (mut jac, mut fd) = ([[0.0; 3]; 3], [[0.0; 3]; 3]);
        for (j, &input) in inputs.iter().enumerate() {
            for (i, &o) in outputs.iter().enumerate() {
                jac[i][j] = sim.output_input_derivative(o, input).unwrap();
            }
            let mut f = [[0.0; 3]; 2];
            for (s, sign) in [1.0, -1.0].into_iter().enumerate() {
                sim.restore(&mut StateReader::new(&state)).unwrap();
                sim.set_input(input, u[j] + sign * delta);
                sim.advance(t + h).unwrap();
                for (i, &o) in outputs.iter().enumerate() {
                    f[s][i] = sim.output(o);
                }
            }
            sim.restore(&mut StateReader::new(&state)).unwrap();
            for i in 0..3 {
                fd[i][j] = (f[0][i] - f[1][i]) / (2.0 * delta);
            }
        }
        // the Jacobian at the end of the unperturbed step
        let mut jac1 = [[0.0; 3]; 3];
        sim.advance(t + h).unwrap();
        for (j, &input) in inputs.iter().enumerate() {
            for (i, &o) in outputs.iter().enumerate() {
                jac1[i][j] = sim.output_input_derivative(o, input).unwrap();
            }
        }
        sim.restore(&mut StateReader::new(&state)).unwrap();
        for i in 0..3 {
            for j in 0..3 {
                println!(
                    "{port}: d f{} / d {}: Jacobian {:.6e} (after the step {:.6e}), stepped FD {:.6e}",
                    axes[i], axes[j], jac[i][j], jac1[i][j], fd[i][j]
                );
            }
        }
        for i in 0..3 {
            assert!(jac[i][i] < 0.0, "{port}.{}: the shell pushes back", axes[i]);
            for j in 0..3 {
                // the Jacobian takes the tangent at the start of the step, the step the
                // tangent along it (the moving, bent shell): agreement to 5e-3 of the
                // geometric mean of the two port stiffnesses
                let scale = (jac[i][i] * jac[j][j]).abs().sqrt();
                assert!(
                    (jac[i][j] - fd[i][j]).abs() <= 5e-3 * scale,
                    "{port}: d f{} / d {}: derivative {} vs stepped FD {}",
                    axes[i],
                    axes[j],
                    jac[i][j],
                    fd[i][j]
                );
                // what is left is the change of the tangent along the step: the Jacobian of
                // the state after the step agrees with the stepped difference entry by entry,
                // the cross terms (from the bending stresses, which vibrate) included, to
                // 5e-3 (generalized-α, whose step the Newmark condensation approximates) or
                // better (Newmark)
                assert!(
                    (jac1[i][j] - fd[i][j]).abs() <= 5e-3 * fd[i][j].abs() + 1e-6 * scale,
                    "{port}: d f{} / d {} after the step: {} vs stepped FD {}",
                    axes[i],
                    axes[j],
                    jac1[i][j],
                    fd[i][j]
                );
            }
        }
    }
}

/// Scene errors name the entry: two of edge/ring/at, a ring on a plate, a port on a supported
/// edge, a load on a port's node, repeated variable names.
#[test]
fn scene_errors_name_the_motion_entry() {
    let err = |extra: &str| -> String {
        let text = format!(
            r#"
kind = "shell"
[fmu]
model_name = "bad"
[material]
E = 1e9
nu = 0.3
rho = 1000.0
[shell]
thickness = 0.01
[plate]
length_x = 1.0
length_y = 1.0
[mesh]
n_x = 2
n_y = 2
[support]
x0 = "clamped"
{extra}
"#
        );
        match Scene::from_toml(&text) {
            Err(e) => e.0,
            Ok(sc) => match simulation(&sc, &[]) {
                Err(e) => e,
                Ok(_) => panic!("{extra}: accepted"),
            },
        }
    };
    let e = err("[[motions]]\nname = \"p\"\nedge = \"x1\"\nat = [1.0, 0.0]\n");
    assert!(e.contains("motions[0]") && e.contains("exactly one"), "{e}");
    let e = err("[[motions]]\nname = \"p\"\nring = \"last\"\n");
    assert!(e.contains("motions[0].ring"), "{e}");
    let e = err("[[motions]]\nname = \"p\"\nedge = \"x0\"\n");
    assert!(
        e.contains("motions[0]") && e.contains("already held"),
        "{e}"
    );
    let e =
        err("[[motions]]\nname = \"p\"\nedge = \"x1\"\n[[loads]]\nname = \"f\"\nat = [1.0, 0.5]\n");
    assert!(e.contains("loads[0]") && e.contains("motion port"), "{e}");
    let e = err(
        "[[motions]]\nname = \"p\"\nedge = \"x1\"\n[[motions]]\nname = \"p\"\nat = [0.5, 0.5]\n",
    );
    assert!(e.contains("motions[1]") && e.contains("p.x"), "{e}");
}
