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
use flexfmu::kinds::belt_drive::PulleySide;
use flexfmu::kinds::belt_drive::model::{
    BeltDrive, BeltElementKind, BeltPath, BeltSpec, PulleyDef, PulleyKind, default_contact,
};
use flexfmu::kinds::belt_drive::scene::{BeltOutput, Output, PulleyInput};
use flexfmu::kinds::energy::EnergyKind;
use flexfmu::linalg::SolverKind;
use flexfmu::model::Model;
use flexfmu::solver::newton::{NewtonPolicy, NewtonSettings};
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use nalgebra::Vector2;
use std::f64::consts::PI;

fn newton() -> NewtonSettings {
    NewtonSettings {
        tolerance: 1e-7,
        max_iterations: 25,
        policy: NewtonPolicy::Modified,
        line_search: true,
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
        tolerance: 0.0,
    }
}

fn input(sim: &mut Simulation, pulley: usize, quantity: PulleyInput, value: f64) {
    drive_mut(sim).set_pulley_input(pulley, quantity, value)
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
            side: PulleySide::Front,
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
        tensioner: None,
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
            assert!(
                t > 0.7,
                "the belt slid already at T1/T2 = {ratio} during loading"
            );
            return ratio;
        }
        assert!(ratio < 3.5, "no slip up to T1/T2 = {ratio}");
    }
}

/// A two-pulley drive: pulley 1 driven, pulley 2 free with a load torque and bearing damping.
struct Drive {
    ea: f64,
    pretension: f64,
    radius: f64,
    thickness: f64,
    mu: f64,
    n_el: usize,
    load: f64,
    damping: f64,
    omega: f64,
    track_energy: bool,
}

impl Drive {
    fn soft() -> Self {
        Self {
            ea: 5000.0,
            pretension: 300.0,
            radius: 0.1,
            thickness: 0.002,
            mu: 0.5,
            n_el: 60,
            load: 10.0,
            damping: 0.02,
            omega: 30.0,
            track_energy: false,
        }
    }

    fn model(&self) -> BeltDrive {
        let rp = self.radius + 0.5 * self.thickness;
        let section = CableSection {
            ea: self.ea,
            ei: 0.01,
            mass_per_length: 0.1,
            damping_axial: 5.0,
            damping_bending: 0.0,
            prestrain: 0.0,
        };
        BeltDrive::new(BeltSpec {
            section,
            element: BeltElementKind::Cable(CableRule::Full),
            thickness: self.thickness,
            pulleys: vec![
                PulleyDef {
                    center: Vector2::zeros(),
                    radius: self.radius,
                    kind: PulleyKind::Driven,
                    side: PulleySide::Front,
                },
                PulleyDef {
                    center: Vector2::new(0.5, 0.0),
                    radius: self.radius,
                    kind: PulleyKind::Free {
                        inertia: 0.01,
                        damping: self.damping,
                    },
                    side: PulleySide::Front,
                },
            ],
            contact: default_contact(
                self.ea,
                0.1,
                self.thickness,
                rp,
                rp,
                self.pretension,
                self.mu,
                (0.0, 0.0, 0.0),
            ),
            points_per_element: 4,
            gravity: Vector2::zeros(),
            path: BeltPath::Closed {
                n_elements: self.n_el,
                pretension: self.pretension,
            },
            n_points: 0,
            track_energy: self.track_energy,
            tensioner: None,
            statics: (newton(), SolverKind::Auto, 1),
        })
        .unwrap()
    }

    /// Runs `t_end` seconds at communication step `h` (driver speed and load ramped over the
    /// first 0.3 s); calls `sample(t, sim)` after every step.
    fn run(&self, rho_inf: f64, h: f64, t_end: f64, mut sample: impl FnMut(f64, &Simulation)) {
        let mut sim = Simulation::new(Box::new(self.model()), config(rho_inf, h), 0.0).unwrap();
        sim.initialize().unwrap();
        let mut angle = 0.0;
        let n = (t_end / h).round() as usize;
        for i in 0..n {
            let t = i as f64 * h;
            let ramp = |t: f64| (t / 0.3).min(1.0);
            let w0 = self.omega * ramp(t);
            let w1 = self.omega * ramp(t + h);
            input(&mut sim, 0, PulleyInput::Angle, angle);
            input(&mut sim, 0, PulleyInput::Omega, 0.5 * (w0 + w1));
            input(&mut sim, 1, PulleyInput::Torque, -self.load * ramp(t));
            sim.advance(t + h)
                .unwrap_or_else(|e| panic!("t = {t}: {}", e.message));
            angle += 0.5 * (w0 + w1) * h;
            sample(t + h, &sim);
        }
    }
}

fn drive(sim: &Simulation) -> &BeltDrive {
    sim.model_as::<BeltDrive>()
        .expect("a belt-drive simulation")
}

fn drive_mut(sim: &mut Simulation) -> &mut BeltDrive {
    sim.model_as_mut::<BeltDrive>()
        .expect("a belt-drive simulation")
}

fn belt(sim: &Simulation, o: BeltOutput) -> f64 {
    drive(sim).output_of(Output::Belt(o))
}

/// Steady drive, averaged over the last 0.2 s of 1.2 s: torque balance (T1 − T2) ρ against
/// the load torque plus bearing damping (1 %), and the creep speed ratio against
/// (EA + T2)/(EA + T1) (1 %; the soft belt, EA = 5 kN, makes the creep about 2 %).
#[test]
fn steady_drive_torque_balance_and_creep() {
    let d = Drive::soft();
    let rp = d.radius + 0.5 * d.thickness;
    let (mut n, mut t1, mut t2, mut w1, mut w2, mut tq2) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    d.run(0.8, 1e-3, 1.2, |t, sim| {
        if t > 1.0 {
            n += 1.0;
            t1 += belt(sim, BeltOutput::TensionTight);
            t2 += belt(sim, BeltOutput::TensionSlack);
            w1 += d.omega;
            w2 += belt(sim, BeltOutput::PulleyOmega(1));
            tq2 += belt(sim, BeltOutput::PulleyTorque(1));
        }
    });
    let (t1, t2, w1, w2, tq2) = (t1 / n, t2 / n, w1 / n, w2 / n, tq2 / n);
    let load = d.load + d.damping * w2;
    let balance = (t1 - t2) * rp;
    let err_torque = (balance - load).abs() / load;
    let ratio = w2 / w1;
    let theory = (d.ea + t2) / (d.ea + t1);
    let err_creep = (ratio - theory).abs() / theory;
    let creep_err = ((1.0 - ratio) - (1.0 - theory)).abs() / (1.0 - theory);
    println!(
        "steady drive: T1 = {t1:.2} N, T2 = {t2:.2} N, (T1-T2) rho = {balance:.4} N m, load {load:.4} N m (error {:.3} %), belt torque on pulley 2 {tq2:.4} N m",
        100.0 * err_torque
    );
    println!(
        "creep: omega2/omega1 = {ratio:.5}, (EA+T2)/(EA+T1) = {theory:.5} (ratio error {:.3} %, creep {:.3} % vs {:.3} %: {:.1} % of the creep)",
        100.0 * err_creep,
        100.0 * (1.0 - ratio),
        100.0 * (1.0 - theory),
        100.0 * creep_err
    );
    assert!(err_torque < 0.01, "torque balance error {err_torque}");
    assert!(err_creep < 0.01, "creep ratio error {err_creep}");
    // the creep is real (not a rigid-belt ratio of 1)
    assert!(1.0 - ratio > 0.01, "creep {}", 1.0 - ratio);
}

/// Energy balance over a start-up with load (Newmark, no numerical damping): the work of the
/// driver and of the load torque equals the change of kinetic, strain and contact energy plus
/// the dissipation by friction, contact, material and bearing damping, within 1 % of the
/// input work.
#[test]
fn energy_balance() {
    let d = Drive {
        track_energy: true,
        ..Drive::soft()
    };
    let mut first = None;
    let mut last = (0.0, 0.0, 0.0);
    d.run(1.0, 5e-4, 0.6, |_t, sim| {
        let e = drive(sim).output_of(Output::Energy(EnergyKind::Total));
        if first.is_none() {
            first = Some(e);
        }
        last = (
            e,
            belt(sim, BeltOutput::InputWork),
            belt(sim, BeltOutput::Dissipated),
        );
    });
    let e0 = first.unwrap();
    let (e1, w, diss) = last;
    let mismatch = w - (e1 - e0) - diss;
    println!(
        "energy: input work {w:.4} J, stored change {:.4} J, dissipated {diss:.4} J, mismatch {mismatch:.3e} J ({:.3} % of the input)",
        e1 - e0,
        100.0 * mismatch.abs() / w.abs()
    );
    assert!(w > 1.0, "the drive does work: {w}");
    assert!(diss > 0.0);
    assert!(mismatch.abs() < 0.01 * w.abs());
}

/// A model built to receive a saved state skips the static pre-load (issue 14: an importer
/// starts from the FMU's shipped state without it) and, given the state of a pre-loaded drive,
/// is that drive: the same state (with the reference length the pre-load settled on) and the
/// same next step, bit for bit.
#[test]
fn a_model_built_to_restore_skips_the_preload_and_takes_the_state() {
    use flexfmu::kinds::belt_drive::BeltDriveScene;
    use flexfmu::scene::{ParamValues, Scene};
    use flexfmu::snapshot::{StateReader, StateWriter};
    let scene = Scene::from_path(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/belt_drive.toml"
    )))
    .unwrap();
    let tables: &BeltDriveScene = scene.tables().unwrap();
    let p = ParamValues::defaults(&scene.params);
    let save = |m: &dyn Model| {
        let mut w = StateWriter::new();
        m.save(&mut w).unwrap();
        w.bytes().to_vec()
    };
    let loaded = BeltDrive::build(tables, &p).unwrap();
    assert!(loaded.preload_report().solves >= 1);
    let bare = BeltDrive::build_to_restore(tables, &p).unwrap();
    assert_eq!(bare.preload_report().solves, 0);
    let state = save(&loaded);
    assert_ne!(save(&bare), state, "the pre-load changed nothing");
    let mut restored = BeltDrive::build_to_restore(tables, &p).unwrap();
    let mut r = StateReader::new(&state);
    restored.restore(&mut r).unwrap();
    assert!(r.finished());
    assert_eq!(save(&restored), state);
    let cfg = SolverConfig::from_params(&p);
    let mut a = Simulation::new(Box::new(loaded), cfg, 0.0).unwrap();
    let mut b = Simulation::new(Box::new(restored), cfg, 0.0).unwrap();
    a.advance(1e-3).unwrap();
    b.advance(1e-3).unwrap();
    let (mut wa, mut wb) = (StateWriter::new(), StateWriter::new());
    a.save(&mut wa).unwrap();
    b.save(&mut wb).unwrap();
    assert_eq!(wa.bytes(), wb.bytes(), "the states after one step differ");
}
