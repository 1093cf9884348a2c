//! Belt-drive validation against analytic belt mechanics (reference
//! `shared/reference/belt-drive.md` E.4):
//! * static capstan (Euler–Eytelwein): a belt over a fixed drum starts to slide when
//!   `T1/T2 = e^{μφ}`;
//! * steady drive: the torque on the driven pulley equals `(T1 − T2) ρ` (span tensions,
//!   pitch radius) and balances the load;
//! * creep (Grashof/Reynolds): the speed ratio of driven to driver `ω2 ρ2/(ω1 ρ1)` equals
//!   `(EA + T2)/(EA + T1)` (mass flow `v/(1 + ε)` constant, adhesion at the entry of each
//!   pulley);
//! * energy balance: work of the drives = dissipation + change of stored energy.

use flexfmu::elements::ancf_cable2d::{CableRule, CableSection};
use flexfmu::integrators::{GeneralizedAlpha, Integrator};
use flexfmu::linalg::SolverKind;
use flexfmu::model::Model;
use flexfmu::model::belt_drive::{
    BeltDrive, BeltElementKind, BeltPath, BeltSpec, PulleyDef, PulleyKind, default_contact,
};
use flexfmu::solver::newton::NewtonSettings;
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use flexfmu::variables::{BeltOutput, EnergyKind, InputKind, OutputKind, PulleyInput};
use nalgebra::Vector2;
use std::f64::consts::PI;

fn newton() -> NewtonSettings {
    NewtonSettings {
        tolerance: 1e-7,
        max_iterations: 25,
    }
}

fn config(rho_inf: f64, h: f64) -> SolverConfig {
    SolverConfig {
        integrator: Integrator::GeneralizedAlpha(GeneralizedAlpha::from_rho_inf(rho_inf)),
        max_step: h,
        newton: newton(),
        static_equilibrium: true,
        load_steps: 1,
        linear: SolverKind::Auto,
    }
}

fn input(pulley: usize, quantity: PulleyInput) -> InputKind {
    InputKind::Pulley { pulley, quantity }
}

/// A belt over a fixed drum of radius 0.1 m (wrap φ = π, μ = 0.3), both ends hanging down and
/// loaded by T2 = 100 N and a slowly growing T1. Slip onset is where the free end starts to
/// run (speed above 0.02 m/s); Euler–Eytelwein: T1/T2 = e^{μφ} = 2.566.
#[test]
fn capstan_slip_onset_matches_euler_eytelwein() {
    let (r, span, mu, t2) = (0.1, 0.2, 0.3, 100.0);
    let expected = (mu * PI).exp();
    let measured = capstan_ramp(r, span, mu, t2, 1.8, 0.5, 1e-3);
    let err = (measured - expected).abs() / expected;
    println!(
        "capstan: slip onset at T1/T2 = {measured:.4}, Euler-Eytelwein e^(mu phi) = {expected:.4}, error {:.2} %",
        100.0 * err
    );
    assert!(err < 0.02, "onset {measured} vs {expected}");
}

/// Runs the capstan ramp with the model driven step by step (the end load changes every step)
/// and returns T1/T2 at slip onset.
fn capstan_ramp(r: f64, span: f64, mu: f64, t2: f64, ratio0: f64, rate: f64, h: f64) -> f64 {
    use flexfmu::integrators::DynState;
    use flexfmu::model::MechanicalSystem;
    use flexfmu::solver::newton::Workspace;
    let ea = 5e4;
    let n_el = 40;
    let total = 2.0 * span + PI * r;
    let at = |s: f64| -> (Vector2<f64>, Vector2<f64>) {
        if s <= span {
            (Vector2::new(r, -span + s), Vector2::new(0.0, 1.0))
        } else if s <= span + PI * r {
            let a = (s - span) / r;
            (
                Vector2::new(r * a.cos(), r * a.sin()),
                Vector2::new(-a.sin(), a.cos()),
            )
        } else {
            let d = s - span - PI * r;
            (Vector2::new(-r, -d), Vector2::new(0.0, -1.0))
        }
    };
    let nodes: Vec<_> = (0..=n_el)
        .map(|k| at(total * k as f64 / n_el as f64))
        .collect();
    let spec = BeltSpec {
        section: CableSection {
            ea,
            ei: 1e-3,
            mass_per_length: 0.15,
            damping_axial: 50.0,
            damping_bending: 0.0,
            prestrain: 0.0,
        },
        element: BeltElementKind::Cable(CableRule::Full),
        thickness: 0.0,
        pulleys: vec![PulleyDef {
            center: Vector2::zeros(),
            radius: r,
            kind: PulleyKind::Driven,
        }],
        contact: default_contact(ea, 0.15, 0.0, r, r, t2, mu, (0.0, 0.0, 0.0)),
        points_per_element: 4,
        gravity: Vector2::zeros(),
        path: BeltPath::Open {
            nodes,
            stretch: 1.0 + t2 / ea,
        },
        n_points: 0,
        track_energy: false,
        statics: (newton(), SolverKind::Auto, 1),
    };
    let mut m = BeltDrive::new(spec).unwrap();
    // balanced loads: the mounted state is (nearly) in equilibrium
    m.set_end_load(0, Vector2::new(0.0, -t2));
    m.set_end_load(1, Vector2::new(0.0, -t2));
    let mut ws = Workspace::new(&m, SolverKind::Auto).unwrap();
    let n = m.n_free();
    let mut s0 = DynState::zeros(n, 0.0);
    m.free_state(&mut s0.q, &mut s0.v);
    flexfmu::solver::statics::solve(&mut m, &mut ws, &mut s0.q, &newton(), 1).unwrap();
    m.accept(&mut s0);
    let mut s1 = s0.clone();
    let ga = GeneralizedAlpha::from_rho_inf(0.8);
    let mut t = 0.0;
    // load to ratio0 in 0.4 s, hold 0.3 s, then the slow ramp
    let ratio_at = |t: f64| {
        if t < 0.4 {
            1.0 + (ratio0 - 1.0) * t / 0.4
        } else if t < 0.7 {
            ratio0
        } else {
            ratio0 + rate * (t - 0.7)
        }
    };
    loop {
        let ratio = ratio_at(t + h);
        m.set_end_load(0, Vector2::new(0.0, -t2 * ratio));
        ga.step(&mut m, &mut ws, &newton(), &s0, h, &mut s1)
            .unwrap_or_else(|e| panic!("t = {t}: {e}"));
        m.accept(&mut s1);
        std::mem::swap(&mut s0, &mut s1);
        t += h;
        let v = m.velocities();
        let speed = Vector2::new(v[0], v[1]).norm();
        if speed > 0.02 {
            assert!(t > 0.7, "the belt slid already at T1/T2 = {ratio} during loading");
            return ratio;
        }
        assert!(ratio < 3.5, "no slip up to T1/T2 = {ratio}");
    }
}
