//! 3D belt drive (issue 13) against the planar drive and belt kinematics.
//!
//! Planar limit: the 3D belt (seed-003 co-rotational elements over `Pulley3d` obstacles, axes
//! along z, flat rims) mounted over the same pulleys with the same reference length as the
//! pre-loaded planar drive (ANCF cable, `kinds::belt_drive`, validated against Euler–Eytelwein
//! and Grashof in `tests/belt_drive.rs`) must carry the same span tensions. The chord of a
//! co-rotational element on a pulley is short of its arc by `Δφ²/24` (Taylor series of
//! `2 sin(Δφ/2)/Δφ`); the bowing term of the element cancels it (Crisfield vol. 1 §7).

mod common;

use flexfmu::elements::ancf_cable2d::{CableRule, CableSection};
use flexfmu::elements::corotational3d::BeamSection;
use flexfmu::integrators::{GeneralizedAlpha, Integrator};
use flexfmu::kinds::belt_3d::model::{Belt3d, Belt3dSpec, Pulley3dDef, Pulley3dMotion};
use flexfmu::kinds::belt_3d::scene::{Output as SpatialOutput, PulleyInput as SpatialInput};
use flexfmu::kinds::belt_drive::PulleySide;
use flexfmu::kinds::belt_drive::model::{
    BeltDrive, BeltElementKind, BeltPath, BeltSpec, PulleyDef, PulleyKind, default_contact,
};
use flexfmu::kinds::belt_drive::scene::{
    BeltOutput, Output as PlanarOutput, PulleyInput as PlanarInput,
};
use flexfmu::kinds::energy::EnergyKind;
use flexfmu::linalg::SolverKind;
use flexfmu::solver::newton::{NewtonPolicy, NewtonSettings};
use flexfmu::solver::simulation::{Simulation, SolverConfig};
use flexfmu::variables::Value;
use nalgebra::{Vector2, Vector3};

fn newton() -> NewtonSettings {
    NewtonSettings {
        tolerance: 1e-9,
        max_iterations: 30,
        policy: NewtonPolicy::Full,
        line_search: false,
    }
}

/// The belt of the shipped planar drive (`scenes/belt_drive.toml`): EA = 5e4 N, EI = 0.05 N m²,
/// 0.15 kg/m, 4 mm thick, 300 N pre-tension, μ = 0.4, pulleys r = 0.08 m (driven) and
/// 0.12 m (free) 0.5 m apart.
struct Drive {
    ea: f64,
    ei: f64,
    mass: f64,
    thickness: f64,
    width: f64,
    pretension: f64,
    mu: f64,
    radii: [f64; 2],
    distance: f64,
}

const SHIPPED: Drive = Drive {
    ea: 5.0e4,
    ei: 0.05,
    mass: 0.15,
    thickness: 0.004,
    width: 0.03,
    pretension: 300.0,
    mu: 0.4,
    radii: [0.08, 0.12],
    distance: 0.5,
};

impl Drive {
    fn contact(&self) -> flexfmu::contact::ContactLaw {
        let half_t = 0.5 * self.thickness;
        default_contact(
            self.ea,
            self.mass,
            self.thickness,
            self.radii[0] + half_t,
            self.radii[1] + half_t,
            self.pretension,
            self.mu,
            (0.0, 0.0, 0.0),
        )
    }

    fn planar(&self, n_el: usize) -> BeltDrive {
        self.planar_points(n_el, 4)
    }

    /// The planar drive with `points` contact points per element (at `(i + 0.5)/points`).
    fn planar_points(&self, n_el: usize, points: usize) -> BeltDrive {
        BeltDrive::new(BeltSpec {
            section: CableSection {
                ea: self.ea,
                ei: self.ei,
                mass_per_length: self.mass,
                damping_axial: 0.0,
                damping_bending: 0.0,
                prestrain: 0.0,
            },
            element: BeltElementKind::Cable(CableRule::Full),
            thickness: self.thickness,
            pulleys: vec![
                PulleyDef {
                    center: Vector2::zeros(),
                    radius: self.radii[0],
                    side: PulleySide::Front,
                    kind: PulleyKind::Driven,
                },
                PulleyDef {
                    center: Vector2::new(self.distance, 0.0),
                    radius: self.radii[1],
                    side: PulleySide::Front,
                    kind: PulleyKind::Free {
                        inertia: 0.01,
                        damping: 0.2,
                    },
                },
            ],
            contact: self.contact(),
            points_per_element: points,
            gravity: Vector2::zeros(),
            tensioner: None,
            path: BeltPath::Closed {
                n_elements: n_el,
                pretension: self.pretension,
            },
            n_points: 0,
            track_energy: false,
            statics: (newton(), SolverKind::Auto, 1),
        })
        .unwrap()
    }

    /// The rectangular section of EA and the in-plane EI (equivalent thickness
    /// `h = √(12 EI/EA)`, `E = EA/(b h)`, `G = E/2.6`): in-plane bending about the width axis
    /// (local z), out-of-plane `EI_y = EA b²/12`, torsion `G b h³/3`, shear `5/6 G b h`.
    fn section(&self) -> BeamSection {
        let (b, ea) = (self.width, self.ea);
        let h = (12.0 * self.ei / ea).sqrt();
        let e = ea / (b * h);
        let g = e / 2.6;
        let rho = self.mass / (b * h);
        BeamSection {
            ea,
            ga_y: 5.0 / 6.0 * g * b * h,
            ga_z: 5.0 / 6.0 * g * b * h,
            gj: g * b * h.powi(3) / 3.0,
            ei_y: ea * b * b / 12.0,
            ei_z: self.ei,
            rho_a: self.mass,
            rho_jx: rho * b * h * (b * b + h * h) / 12.0,
            rho_iy: rho * b * h * b * b / 12.0,
            rho_iz: rho * b * h * h * h / 12.0,
        }
    }

    fn spatial(&self, n_el: usize, bowing: bool) -> Belt3d {
        self.spatial_mounted(n_el, bowing, false)
    }

    fn spatial_mounted(&self, n_el: usize, bowing: bool, space_mount: bool) -> Belt3d {
        let rim = |center: Vector3<f64>, radius: f64, motion| Pulley3dDef {
            center,
            axis: Vector3::z(),
            radius,
            rim_width: 2.0 * self.width,
            crown: 0.0,
            flange: 0.0,
            motion,
        };
        let mut contact = self.contact();
        contact.k_t = 0.1 * contact.k_n;
        Belt3d::new(Belt3dSpec {
            section: self.section(),
            thickness: self.thickness,
            width: self.width,
            pulleys: vec![
                rim(
                    Vector3::zeros(),
                    self.radii[0],
                    Pulley3dMotion::Driven { omega: 0.0 },
                ),
                rim(
                    Vector3::new(self.distance, 0.0, 0.0),
                    self.radii[1],
                    Pulley3dMotion::Free {
                        inertia: 0.01,
                        damping: 0.2,
                        torque: 0.0,
                    },
                ),
            ],
            contact,
            n_elements: n_el,
            pretension: self.pretension,
            gravity: Vector3::zeros(),
            bowing,
            space_mount,
            // the scenes' default, 3 across the width; BELT3D_WIDTH_POINTS=1 measures the
            // planar limit with the centre-line contact
            width_points: std::env::var("BELT3D_WIDTH_POINTS").map_or(3, |v| v.parse().unwrap()),
            // BELT3D_PPE: contact sections per element (default: the scenes')
            points_per_element: std::env::var("BELT3D_PPE").map_or(
                flexfmu::kinds::belt_3d::DEFAULT_POINTS_PER_ELEMENT.into(),
                |v| v.parse().unwrap(),
            ),
        })
        .unwrap()
    }
}

/// Planar limit at rest: the 3D belt given the reference length of the pre-loaded planar belt
/// (300 N) and brought into static equilibrium carries the planar belt's span tensions. Table
/// over 36/72/144 elements with and without the bowing term; with it the error must be below
/// the 0.5 % at 144 elements (issue 13; measured 5.5/1.1/0.08 % at 36/72/144: the
/// 0.5 % is not reached at 72 elements, open).
#[test]
fn planar_limit_span_tensions_at_rest() {
    let d = SHIPPED;
    println!(
        "elements | planar T1, T2 [N] | 3D chord only T1, T2 [N] (error) | 3D with bowing T1, T2 [N] (error)"
    );
    for n_el in [36, 72, 144] {
        let planar = d.planar(n_el);
        let t2d = planar.span_tensions().to_vec();
        let l = planar.element_length();
        let mut row = format!("{n_el} | {:.2}, {:.2}", t2d[0], t2d[1]);
        for bowing in [false, true] {
            let mut m = d.spatial(n_el, bowing);
            m.set_reference_length(l);
            if let Err(e) = m.preload(None, &newton()) {
                assert!(!bowing, "{n_el} elements with bowing: {e}");
                row += " | no static equilibrium found";
                continue;
            }
            let t3 = m.span_tensions();
            let err = (0..2)
                .map(|i| ((t3[i] - t2d[i]) / t2d[i]).abs())
                .fold(0.0, f64::max);
            row += &format!(" | {:.2}, {:.2} ({:.2} %)", t3[0], t3[1], 100.0 * err);
            if bowing && n_el >= 144 {
                assert!(
                    err < 5e-3,
                    "{n_el} elements with bowing: span tensions {t3:?} vs planar {t2d:?}"
                );
            }
        }
        println!("{row}");
    }
}

/// The mount in space (`kinds::belt_3d::path`, built for pulleys on crossed axes) of a
/// coplanar drive is the planar mount: pre-loaded to 300 N with 72 elements, the span
/// tensions of both mounts agree within 0.1 % (measured: 1e-13) and so do the nodes, within
/// 1e-9 m (measured: 3e-16 m; before session 34 the path in space started the belt at the
/// arrival on pulley 1, the planar loop at the departure of span 1: nodes up to 0.24 m apart,
/// the same loop discretized at other points).
#[test]
fn space_mount_of_coplanar_pulleys_is_the_planar_mount() {
    let d = SHIPPED;
    let mut t = vec![];
    let mut nodes = vec![];
    for space in [false, true] {
        let mut m = d.spatial_mounted(72, true, space);
        m.preload(Some(d.pretension), &newton())
            .unwrap_or_else(|e| panic!("space mount {space}: {e}"));
        t.push(m.span_tensions().to_vec());
        nodes.push(
            (0..m.n_nodes())
                .map(|k| m.node_position(k))
                .collect::<Vec<_>>(),
        );
    }
    let apart = nodes[0]
        .iter()
        .zip(&nodes[1])
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max);
    println!(
        "span tensions: planar mount {:?}, space mount {:?}; nodes at most {apart:.2e} m apart",
        t[0], t[1]
    );
    for i in 0..2 {
        assert!((t[1][i] / t[0][i] - 1.0).abs() < 1e-3, "{t:?}");
    }
    assert!(apart < 1e-9, "nodes {apart} m apart");
}

fn config(h: f64) -> SolverConfig {
    SolverConfig {
        integrator: Integrator::GeneralizedAlpha(GeneralizedAlpha::from_rho_inf(0.8)),
        max_step: h,
        newton: NewtonSettings {
            // BELT3D_TOL: the exploration tables' check of the Newton tolerance
            tolerance: std::env::var("BELT3D_TOL").map_or(1e-7, |v| v.parse().unwrap()),
            max_iterations: 25,
            policy: NewtonPolicy::Modified,
            line_search: false,
        },
        static_equilibrium: false,
        load_steps: 1,
        linear: SolverKind::Auto,
        tolerance: 0.0,
    }
}

/// Mean over the last `window` seconds of a run of both drives: tight and slack span
/// tensions [N], speed of pulley 2 [rad/s], slip [1], belt torque on pulley 1 [N m].
#[derive(Clone, Copy, Debug, Default)]
struct Steady {
    tight: f64,
    slack: f64,
    omega2: f64,
    slip: f64,
    torque1: f64,
}

impl Steady {
    fn add(&mut self, o: [f64; 5]) {
        self.tight += o[0];
        self.slack += o[1];
        self.omega2 += o[2];
        self.slip += o[3];
        self.torque1 += o[4];
    }
    fn mean(self, n: f64) -> Self {
        Self {
            tight: self.tight / n,
            slack: self.slack / n,
            omega2: self.omega2 / n,
            slip: self.slip / n,
            torque1: self.torque1 / n,
        }
    }
}

/// Runs `sim` for `t_end` s at step `h`: pulley 1 speed ramped to `omega` and the load
/// torque on pulley 2 to `load` over `ramp` s; `set(sim, angle, omega, torque)` sets the
/// inputs and `read(sim)` returns the five quantities of [`Steady`], averaged over the last
/// `window` s.
#[allow(clippy::too_many_arguments)]
fn run_steady(
    sim: &mut Simulation,
    h: f64,
    t_end: f64,
    window: f64,
    omega: f64,
    load: f64,
    ramp: f64,
    set: impl Fn(&mut Simulation, f64, f64, f64),
    read: impl Fn(&Simulation) -> [f64; 5],
) -> Steady {
    let (mut angle, mut acc, mut n) = (0.0, Steady::default(), 0.0);
    let steps = (t_end / h).round() as usize;
    for i in 0..steps {
        let t = i as f64 * h;
        let r = |t: f64| (t / ramp).min(1.0);
        let w = 0.5 * omega * (r(t) + r(t + h));
        set(sim, angle, w, -load * r(t));
        sim.advance(t + h)
            .unwrap_or_else(|e| panic!("t = {t}: {}", e.message));
        angle += w * h;
        if t + h > t_end - window + 1e-12 {
            acc.add(read(sim));
            n += 1.0;
        }
    }
    acc.mean(n)
}

/// Planar limit running: the shipped belt at 10 rad/s on pulley 1 with 10 N m load on
/// pulley 2, 100 elements (the planar scene's count), 1 ms steps, 0.6 s (ramps over 0.2 s),
/// means over the last 0.1 s: the 3D drive's span tensions, pulley-2 speed and creep against
/// the planar drive's (issue 13: 0.5 %; the creep as the difference of slips relative to the
/// planar slip). Session 33 (both pre-loads in frictionless equilibrium, 2 contact sections
/// per element): +0.05 / +0.08 % in tensions, −0.01 % in speed, creep +5.6 % (at 72 elements
/// +0.40 / +0.59 %: above the bound, hence 100; 120 elements +0.02 / +0.03 %; node-only
/// contact at 72 elements −0.28 / −0.46 %, creep −72 %).
#[test]
fn planar_limit_running_drive_equals_planar_drive() {
    let d = SHIPPED;
    let n_el: usize = std::env::var("BELT3D_N").map_or(100, |v| v.parse().unwrap());
    let (h, t_end, window, omega, load, ramp) = (1e-3, 0.6, 0.1, 10.0, 10.0, 0.2);
    let (p, _) = steady_planar(&d, n_el, 4, h, t_end, window, omega, load, ramp);
    let (mut spatial, _) = spatial_sim(&d, d.spatial(n_el, true), h);
    let energy = |sim: &Simulation| {
        let m = sim.model_as::<Belt3d>().unwrap();
        (
            m.output_of(SpatialOutput::Energy(EnergyKind::Total)),
            m.input_work(),
            m.dissipated(),
        )
    };
    let e0 = energy(&spatial);
    let s = run_spatial(&mut spatial, h, t_end, window, omega, load, ramp);
    // energy balance: work of the drive and the load = change of kinetic, strain and
    // contact energy + dissipation (contact damping, friction, bearing)
    let e1 = energy(&spatial);
    let (w_in, stored, diss) = (e1.1 - e0.1, e1.0 - e0.0, e1.2 - e0.2);
    let balance = (w_in - stored - diss) / w_in;
    println!(
        "energy balance of the 3D drive: input work {w_in:.3} J = stored {stored:.3} J + dissipated {diss:.3} J, defect {:.3} % of the input work",
        100.0 * balance
    );
    let rel = |a: f64, b: f64| (a - b) / b;
    println!("running planar limit, {n_el} elements: planar | 3D | difference");
    println!(
        "T tight [N]: {:.2} | {:.2} | {:.3} %",
        p.tight,
        s.tight,
        100.0 * rel(s.tight, p.tight)
    );
    println!(
        "T slack [N]: {:.2} | {:.2} | {:.3} %",
        p.slack,
        s.slack,
        100.0 * rel(s.slack, p.slack)
    );
    println!(
        "omega2 [rad/s]: {:.5} | {:.5} | {:.4} %",
        p.omega2,
        s.omega2,
        100.0 * rel(s.omega2, p.omega2)
    );
    println!(
        "slip [%]: {:.4} | {:.4} | {:.2} % of the slip",
        100.0 * p.slip,
        100.0 * s.slip,
        100.0 * rel(s.slip, p.slip)
    );
    println!(
        "torque on pulley 1 [N m]: {:.4} | {:.4}",
        p.torque1, s.torque1
    );
    for (what, a, b) in [
        ("tight tension", s.tight, p.tight),
        ("slack tension", s.slack, p.slack),
        ("pulley-2 speed", s.omega2, p.omega2),
    ] {
        assert!(rel(a, b).abs() < 5e-3, "{what}: 3D {a} vs planar {b}");
    }
    assert!(balance.abs() < 0.02, "energy defect {balance}");
}

/// Runs the planar drive (`points` contact points per element) as
/// [`planar_limit_running_drive_equals_planar_drive`] does.
#[allow(clippy::too_many_arguments)]
fn steady_planar(
    d: &Drive,
    n_el: usize,
    points: usize,
    h: f64,
    t_end: f64,
    window: f64,
    omega: f64,
    load: f64,
    ramp: f64,
) -> (Steady, f64) {
    let m = d.planar_points(n_el, points);
    let rest = m.span_tensions().iter().sum::<f64>() / m.span_tensions().len() as f64;
    let mut planar = Simulation::new(Box::new(m), config(h), 0.0).unwrap();
    planar.initialize().unwrap();
    let s = run_steady(
        &mut planar,
        h,
        t_end,
        window,
        omega,
        load,
        ramp,
        |sim, a, w, tq| {
            let m = sim.model_as_mut::<BeltDrive>().unwrap();
            m.set_pulley_input(0, PlanarInput::Angle, a);
            m.set_pulley_input(0, PlanarInput::Omega, w);
            m.set_pulley_input(1, PlanarInput::Torque, tq);
        },
        |sim| {
            let m = sim.model_as::<BeltDrive>().unwrap();
            let o = |b| m.output_of(PlanarOutput::Belt(b));
            [
                o(BeltOutput::TensionTight),
                o(BeltOutput::TensionSlack),
                m.pulley_motion(1).1,
                o(BeltOutput::Slip),
                m.pulley_torque(0),
            ]
        },
    );
    (s, rest)
}

/// The 3D drive `m3` pre-loaded to the drive's pre-tension, in a simulation with steps `h`,
/// and its mean span tension at rest [N].
fn spatial_sim(d: &Drive, mut m3: Belt3d, h: f64) -> (Simulation, f64) {
    m3.preload(Some(d.pretension), &newton()).unwrap();
    let rest = m3.span_tensions().iter().sum::<f64>() / m3.span_tensions().len() as f64;
    let mut spatial = Simulation::new(Box::new(m3), config(h), 0.0).unwrap();
    spatial.initialize().unwrap();
    (spatial, rest)
}

/// Runs the 3D drive in `spatial` as [`planar_limit_running_drive_equals_planar_drive`] does.
#[allow(clippy::too_many_arguments)]
fn run_spatial(
    spatial: &mut Simulation,
    h: f64,
    t_end: f64,
    window: f64,
    omega: f64,
    load: f64,
    ramp: f64,
) -> Steady {
    run_steady(
        spatial,
        h,
        t_end,
        window,
        omega,
        load,
        ramp,
        |sim, a, w, tq| {
            let m = sim.model_as_mut::<Belt3d>().unwrap();
            m.set_pulley_input(0, SpatialInput::Angle, a);
            m.set_pulley_input(0, SpatialInput::Omega, w);
            m.set_pulley_input(1, SpatialInput::Torque, tq);
        },
        |sim| {
            let m = sim.model_as::<Belt3d>().unwrap();
            let t = m.span_tensions();
            [
                t[0].max(t[1]),
                t[0].min(t[1]),
                m.pulley_motion(1).1,
                m.slip(),
                m.pulley_load(0).2,
            ]
        },
    )
}

/// Runs the 3D drive (`m3`, not yet pre-loaded) as
/// [`planar_limit_running_drive_equals_planar_drive`] does.
#[allow(clippy::too_many_arguments)]
fn steady_spatial(
    d: &Drive,
    m3: Belt3d,
    h: f64,
    t_end: f64,
    window: f64,
    omega: f64,
    load: f64,
    ramp: f64,
) -> (Steady, f64) {
    let (mut spatial, rest) = spatial_sim(d, m3, h);
    (
        run_spatial(&mut spatial, h, t_end, window, omega, load, ramp),
        rest,
    )
}

/// Loaded and unequal-radii planar limit (issue 13 item 4): the shipped belt at 10 rad/s,
/// means over 0.6-1.2 s, 1 ms steps; cases: the shipped drive at 10 and 30 N m load, radii
/// 0.05/0.15 m at 10 N m; 72 and 144 elements (`BELT3D_CASES=i,j` picks cases, `BELT3D_NS`
/// element counts). Prints the planar drive with 4 and with 1 contact point per element and
/// the 3D drive (and the planar drive with 2 points), each against the planar drive with 4
/// points: if the planar belt with one
/// point per element shows the 3D belt's offsets, the node-only contact is their cause.
#[test]
#[ignore = "exploration: prints the loaded planar-limit table, no check (about a minute)"]
fn planar_limit_loaded_table() {
    let cases = [
        ("shipped, 10 N m", SHIPPED, 10.0),
        ("shipped, 30 N m", SHIPPED, 30.0),
        (
            "r 0.05/0.15, 10 N m",
            Drive {
                radii: [0.05, 0.15],
                ..SHIPPED
            },
            10.0,
        ),
    ];
    let pick: Vec<usize> = std::env::var("BELT3D_CASES").map_or((0..cases.len()).collect(), |v| {
        v.split(',').map(|x| x.parse().unwrap()).collect()
    });
    let ns: Vec<usize> = std::env::var("BELT3D_NS").map_or(vec![72, 144], |v| {
        v.split(',').map(|x| x.parse().unwrap()).collect()
    });
    let omega: f64 = std::env::var("BELT3D_OMEGA").map_or(10.0, |v| v.parse().unwrap());
    let load_env: Option<f64> = std::env::var("BELT3D_LOAD")
        .ok()
        .map(|v| v.parse().unwrap());
    let h: f64 = std::env::var("BELT3D_H").map_or(1e-3, |v| v.parse().unwrap());
    let (t_end, window, ramp) = (1.2, 0.6, 0.2);
    let rel = |a: f64, b: f64| 100.0 * (a - b) / b;
    println!("pulley 1 at {omega} rad/s, steps {h} s");
    println!(
        "case | elements | model | mean T at rest [N] | T tight [N] | T slack [N] | omega2 [rad/s] | slip [%] | against planar 4 pts: tight, slack, omega2, slip [%]"
    );
    for &c in &pick {
        let (name, d, load) = &cases[c];
        let load = &load_env.unwrap_or(*load);
        // BELT3D_EI: the in-plane bending stiffness [N m2] of both belts
        let d = &Drive {
            ei: std::env::var("BELT3D_EI").map_or(d.ei, |v| v.parse().unwrap()),
            ..*d
        };
        for &n_el in &ns {
            let (p4, p4_rest) = steady_planar(d, n_el, 4, h, t_end, window, omega, *load, ramp);
            let p1 = steady_planar(d, n_el, 1, h, t_end, window, omega, *load, ramp);
            let p2 = steady_planar(d, n_el, 2, h, t_end, window, omega, *load, ramp);
            let s = steady_spatial(
                d,
                d.spatial(n_el, true),
                h,
                t_end,
                window,
                omega,
                *load,
                ramp,
            );
            for (model, (r, rest)) in [
                ("planar 4 pts", (p4, p4_rest)),
                ("planar 1 pt", p1),
                ("planar 2 pts", p2),
                ("3D", s),
            ] {
                println!(
                    "{name} ({load} N m) | {n_el} | {model} | {rest:.2} | {:.2} | {:.2} | {:.5} | {:.4} | {:+.3}, {:+.3}, {:+.4}, {:+.2}",
                    r.tight,
                    r.slack,
                    r.omega2,
                    100.0 * r.slip,
                    rel(r.tight, p4.tight),
                    rel(r.slack, p4.slack),
                    rel(r.omega2, p4.omega2),
                    rel(r.slip, p4.slip),
                );
            }
        }
    }
}

/// Walking (issue 13): pulley 2 of `belt_drive_3d` skewed by 0.02 rad (its axis turned about
/// the drive-plane perpendicular of the arriving span, so that the span enters its rim at
/// that angle). Kinematics of a belt on a rim (a point landing on the rim keeps its axial
/// place, so the belt moves sideways at `v sin β` with the entry angle β): the first landings on
/// the skewed rim walk at up to `v × skew` (a single rim, the span not yet inclined). Over a
/// whole loop the drive walks slower (loop model `v × skew × l / L` = 0.30 v skew, measured about
/// 0.20 v skew: `tilt_walk_exploration`, README "A tilted pulley walks the belt"; an earlier
/// version of this comment claimed a steady `v × skew / 2`, which is wrong). Measured here: the
/// lateral speed of the belt on pulley 2 between 0.15 and 0.3 s (after the 0.1 s speed ramp,
/// away from the flange, within the first landings) must lie between 0.5 and 1 times
/// `v × skew`: above every steady rate, so it checks the landing rate (measured 0.62).
/// Pulley 1 at 10 rad/s, no load, 1 ms steps, 0.5 s.
#[test]
fn skewed_pulley_walks_the_belt_onto_the_flange() {
    let scene = common::scene("belt_drive_3d");
    let skew: f64 = std::env::var("BELT3D_SKEW").map_or(0.02, |v| v.parse().unwrap());
    // BELT3D_PARAM=pulley2.tilt measures the walk of a tilt instead (not asserted on)
    let param = std::env::var("BELT3D_PARAM").unwrap_or("pulley2.skew".into());
    let mut sim = common::simulation(
        &scene,
        &[(param.as_str(), Value::Real(skew)), width_points()],
    )
    .unwrap();
    let out = |sim: &Simulation, name: &str| common::output(&scene, sim, name);
    let mut trace = vec![];
    drive_ramped(&scene, &mut sim, 500, 0.0, |sim, t, i| {
        trace.push((
            t,
            out(sim, "belt2.lateral"),
            out(sim, "belt.speed"),
            out(sim, "pulley2.flange_force"),
        ));
        if i % 100 == 99 {
            println!(
                "t = {:.2} s: belt2.lateral = {:+.3} mm, belt1.lateral = {:+.3} mm, belt.speed {:.3} m/s, pulley2.flange_force {:.2} N, pulley2.force_z {:.3} N, pulley2.moment_x {:.4} N m",
                t,
                1e3 * trace.last().unwrap().1,
                1e3 * out(sim, "belt1.lateral"),
                trace.last().unwrap().2,
                trace.last().unwrap().3,
                out(sim, "pulley2.force_z"),
                out(sim, "pulley2.moment_x"),
            );
        }
    });
    // walking rate over 0.2-0.4 s (after the ramp, before the flange)
    let at = |t: f64| {
        trace
            .iter()
            .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
            .unwrap()
    };
    let (a, b) = (at(0.15), at(0.3));
    let rate = (b.1 - a.1) / (b.0 - a.0);
    let v = 0.5 * (a.2 + b.2);
    let expected = v * skew;
    println!(
        "walking: lateral speed {:.3} mm/s, belt speed x skew = {:.3} mm/s (ratio {:.3}; landing rate, at most 1)",
        1e3 * rate,
        1e3 * expected,
        rate.abs() / expected
    );
    if param != "pulley2.skew" {
        return;
    }
    assert!(
        rate.abs() > 0.5 * expected && rate.abs() < expected,
        "lateral speed {rate} vs v skew {expected}"
    );
}

/// Drives `belt_drive_3d` (`scene`, `sim`) for `steps` steps of 1 ms: pulley 1 ramped to
/// 10 rad/s over 0.1 s, the load torque on pulley 2 ramped to `load` [N m] with it (0: the
/// input is left alone); calls `each(sim, t, i)` after every step (`t` the time reached, `i`
/// the step's index).
fn drive_ramped(
    scene: &flexfmu::scene::Scene,
    sim: &mut Simulation,
    steps: usize,
    load: f64,
    mut each: impl FnMut(&Simulation, f64, usize),
) {
    let (ia, iw) = (
        common::input_index(scene, "pulley1.angle"),
        common::input_index(scene, "pulley1.omega"),
    );
    let it = (load != 0.0).then(|| common::input_index(scene, "pulley2.torque_in"));
    let (h, omega, ramp) = (1e-3, 10.0, 0.1);
    let mut angle = 0.0;
    for i in 0..steps {
        let t = i as f64 * h;
        let r = |t: f64| (t / ramp).min(1.0);
        let w = 0.5 * omega * (r(t) + r(t + h));
        sim.set_input(ia, angle);
        sim.set_input(iw, w);
        if let Some(it) = it {
            sim.set_input(it, -load * r(t));
        }
        sim.advance(t + h)
            .unwrap_or_else(|e| panic!("t = {t}: {}", e.message));
        angle += w * h;
        each(sim, t + h, i);
    }
}

/// The scene in `text` driven by [`drive_ramped`] with 10 N m on pulley 2 for `steps` steps
/// of 1 ms: the outputs `names` averaged over the last `window` steps.
fn ramped_means(text: &str, names: &[&str], steps: usize, window: usize) -> Vec<f64> {
    let scene = flexfmu::scene::Scene::from_toml(text).unwrap();
    let mut sim = common::simulation(&scene, &[]).unwrap();
    let mut sums = vec![0.0; names.len()];
    drive_ramped(&scene, &mut sim, steps, 10.0, |sim, _, i| {
        if i >= steps - window {
            for (s, n) in sums.iter_mut().zip(names) {
                *s += common::output(&scene, sim, n) / window as f64;
            }
        }
    });
    sums
}

/// `contact.width_points` of the shipped scenes' tests: the scene's default, or
/// `BELT3D_WIDTH_POINTS` to measure them with another count.
fn width_points() -> (&'static str, Value) {
    let default = common::scene("belt_drive_3d")
        .params
        .iter()
        .find(|p| p.name == "contact.width_points")
        .map(|p| p.start)
        .unwrap();
    (
        "contact.width_points",
        std::env::var("BELT3D_WIDTH_POINTS")
            .map_or(default, |v| Value::Integer(v.parse().unwrap())),
    )
}

/// Runs `belt_drive_3d` with the parameters `params`, pulley 1 ramped to 10 rad/s over
/// 0.1 s, no load, 1 ms steps, for `steps` steps; returns (t, belt2.lateral, belt1.lateral,
/// belt.speed) after every step.
fn lateral_trace(params: &[(&str, Value)], steps: usize) -> Vec<[f64; 4]> {
    let scene = common::scene("belt_drive_3d");
    let mut sim = common::simulation(&scene, params).unwrap();
    let out = |sim: &Simulation, name: &str| common::output(&scene, sim, name);
    let mut trace = vec![];
    drive_ramped(&scene, &mut sim, steps, 0.0, |sim, t, _| {
        trace.push([
            t,
            out(sim, "belt2.lateral"),
            out(sim, "belt1.lateral"),
            out(sim, "belt.speed"),
        ]);
    });
    if std::env::var("BELT3D_DIAG").is_ok() {
        // node by node: position, width direction's radial component about pulley 2
        let m = sim.model_as::<Belt3d>().unwrap();
        let c2 = Vector3::new(0.5, 0.0, 0.0);
        for k in 0..m.n_nodes() {
            let r = m.node_position(k);
            let d = m.node_width_direction(k);
            let mut rad = r - c2;
            rad.z = 0.0;
            let e = rad.normalize();
            println!(
                "node {k}: x {:+.4} y {:+.4} z {:+.4} mm, |r - c2| {:.5} m, d.e {:+.5}, d.z {:+.5}",
                r.x,
                r.y,
                1e3 * r.z,
                rad.norm(),
                d.dot(&e),
                d.z
            );
        }
    }
    trace
}

/// Crown (exploration, prints, asserts nothing; issue 13 item 4 is OPEN): pulley 2 offset
/// along its axis so that the belt runs `offset` (5 mm) off the middle of its rim, with and
/// without a crown (0.5 mm on the 40 mm rim); prints belt2.lateral against time. Measured:
/// without crown the belt stays at −5.000 mm, with it −5.000 → −4.979 mm in 0.45 s at
/// 0.83 m/s (0.05 mm/s, against the belt speed times the crown slope at 5 mm, 10 mm/s): the
/// centre-line contact does not centre the belt. One contact point per node at the centre
/// line feels the crown only through the normal `e − R'(ζ) a`, which pushes the point down
/// the slope (a string slides off a barrel); the real centring needs the belt lying across
/// the crown (a contact moment about the belt's tangent tilting its section onto the cone,
/// whose in-plane curvature steers the arriving span up the slope).
#[test]
#[ignore = "exploration: prints the lateral position, no check"]
fn crown_exploration() {
    let crown: f64 = std::env::var("BELT3D_CROWN").map_or(5e-4, |v| v.parse().unwrap());
    let offset: f64 = std::env::var("BELT3D_OFFSET").map_or(5e-3, |v| v.parse().unwrap());
    let steps: usize = std::env::var("BELT3D_STEPS").map_or(600, |v| v.parse().unwrap());
    let width: i32 = std::env::var("BELT3D_WIDTH_POINTS").map_or(3, |v| v.parse().unwrap());
    for c in [0.0, crown] {
        let tr = lateral_trace(
            &[
                ("pulley2.crown", Value::Real(c)),
                ("pulley2.offset_z", Value::Real(offset)),
                ("contact.width_points", Value::Integer(width)),
            ],
            steps,
        );
        for s in tr.iter().step_by(50) {
            println!(
                "crown {:.2} mm t {:.3}: belt2.lateral {:+.3} mm belt1.lateral {:+.3} mm speed {:.3}",
                1e3 * c,
                s[0],
                1e3 * s[1],
                1e3 * s[2],
                s[3]
            );
        }
    }
}

/// Crown (issue 13): a crowned pulley brings an offset belt back to the crown. Pulley 2 of
/// `belt_drive_3d` offset by 5 mm along its axis (the belt runs 5 mm off the middle of its
/// 40 mm rim), crown `h_c` = 0.5 mm, contact across the width (`contact.width_points` = 3),
/// pulley 1 ramped to 10 rad/s over 0.1 s, no load, 1 ms steps.
///
/// First-order estimate (ours): the rim's pitch radius `R(ζ) = R − h_c (ζ/h)²` (h = 20 mm,
/// half the rim) has the slope `α(ζ) = −2 h_c ζ/h²`. The belt lies across the crown, its
/// sections tilted onto the local cone by `α`; lying along the rim (stick) it is then bent
/// in its own plane by `α/R` (the part of the rim's curvature `1/R` in the tilted belt
/// plane). That edgewise moment `EI_lat α/R` bends the arriving span near the rim over the
/// length `λ = √(EI_lat/T)` (a beam under tension), so the span enters the rim at the angle
/// `β = (α/R) λ` up the slope, and a belt entering a rim at `β` walks sideways at `v β`
/// (the kinematic rule of the skewed-pulley test above; `v β/2` when the two pulleys of the
/// drive share the correction, as measured there). `α` is proportional to `ζ`: the offset
/// decays exponentially, `ζ̇ = −c v (2 h_c/h²) ζ` with `c = λ/(2R)` = 0.46 (EI_lat =
/// 3.75 N m², T = 300 N, R = 0.122 m) for the shared correction, `λ/R` = 0.92 on a single
/// rim. Measured with 0.8 s (`crown_exploration`, `BELT3D_WIDTH_POINTS=3 BELT3D_STEPS=800`):
/// after a build-up of ~0.2 s the belt crosses at a steady ~1.9 mm/s at 4.3 mm, c ≈ 0.21;
/// over this test's 0.15–0.4 s window (build-up included) c ≈ 0.13. Checked: the decay rate
/// over 0.15–0.4 s lies between 0.05 and 1 times `v 2h_c/h²` (first-order agreement: the
/// centre-line contact alone gives c = 0.005, the single-rim kinematic bound is 0.92), and
/// the control, the flat rim of the same drive and contact, keeps the offset within 0.05 mm.
#[test]
fn crowned_pulley_centres_the_belt() {
    let (offset, crown, half_rim) = (5e-3, 5e-4, 0.02);
    let run = |c: f64, steps: usize| {
        lateral_trace(
            &[
                ("pulley2.crown", Value::Real(c)),
                ("pulley2.offset_z", Value::Real(offset)),
                ("contact.width_points", Value::Integer(3)),
            ],
            steps,
        )
    };
    let at = |tr: &[[f64; 4]], t: f64| {
        *tr.iter()
            .min_by(|a, b| (a[0] - t).abs().total_cmp(&(b[0] - t).abs()))
            .unwrap()
    };
    let crowned = run(crown, 400);
    for s in crowned.iter().step_by(50) {
        println!(
            "crowned: t {:.3} s belt2.lateral {:+.3} mm belt1.lateral {:+.3} mm speed {:.3} m/s",
            s[0],
            1e3 * s[1],
            1e3 * s[2],
            s[3]
        );
    }
    let (a, b) = (at(&crowned, 0.15), at(&crowned, 0.4));
    assert!(
        a[1] < 0.0 && b[1] < 0.0,
        "the belt stays on the side it started: {a:?} {b:?}"
    );
    let rate = (a[1] / b[1]).ln() / (b[0] - a[0]);
    let v = 0.5 * (a[3] + b[3]);
    let estimate = v * 2.0 * crown / (half_rim * half_rim);
    println!(
        "crown: decay rate {rate:.3} 1/s, v 2 h_c/h^2 = {estimate:.3} 1/s, c = {:.3}",
        rate / estimate
    );
    assert!(
        rate > 0.05 * estimate && rate < estimate,
        "decay rate {rate} 1/s against v 2h_c/h² = {estimate} 1/s"
    );
    let flat = run(0.0, 300);
    let drift = flat
        .iter()
        .map(|s| (s[1] + offset).abs())
        .fold(0.0, f64::max);
    println!(
        "flat rim: largest departure from the offset {:.4} mm",
        1e3 * drift
    );
    assert!(drift < 5e-5, "flat rim: the offset moved by {drift} m");
}

/// The flange stops the walk (issue 13 item 4): pulley 2 of `belt_drive_3d` skewed by
/// 0.03 rad walks the belt onto its flange (rim half width h = 20 mm, belt half width
/// b = 15 mm: the edge meets the flange at `belt2.lateral` = −(h − b) = −5 mm), with the
/// default contact across the width; pulley 1 ramped to 10 rad/s over 0.1 s, no load, 1 ms,
/// 1.3 s. Checked: over 1.0–1.3 s the belt rides on the flange (the mean of `belt2.lateral`
/// within 0.3 mm of −5 mm) and it never rides over it (never beyond −5.5 mm); over 1.0–1.3 s
/// the flange pushes it back
/// (`pulley2.flange_force`, the belt's axial force on the flanges, has the walk's sign and a
/// mean of at least 1 N), on average below what friction on the rim can push sideways,
/// μ (T1 + T2) (the rim's normal force on a 180° wrap, the pre-tension 300 N in both spans).
/// Measured (session 26): lateral −4.961 mm, flange force mean −14.4 N, standard deviation
/// 9.1 N, largest 43.8 N without the transport predictor; with it (the default) −4.714 mm,
/// mean −14.5 N, standard deviation 37.8 N, single spikes up to 629 N (edge points hitting
/// the flange face; the spikes are not asserted on). With the centre-line contact alone
/// (`contact.width_points` = 1) the single edge point made spikes of 331 N (before session
/// 26's bristle it jumped the flange top at 1828 N). Riding the flange is not smooth (the
/// flange face's penalty acts on the edge points only): 76 of 1459 steps failed Newton and
/// were halved without the predictor (not asserted on). The ride oscillates across the
/// width by tenths of a millimetre, so the position checked is the mean over the window, not
/// a sample at its end (session 30: dropping the acceleration restart at communication steps
/// moved the sample at 1.3 s out of the ±0.3 mm band while the window's mean moved by
/// 0.12 mm). Session 31 (arc nodes keep their rim gap in the predictor, no acceleration
/// restart): at 1.3 s −4.965 mm, mean over 1.0–1.3 s −4.939 mm (range −4.965 to
/// −4.852 mm), flange force mean −23.3 N, standard deviation 12.7 N, largest 62.6 N.
/// Session 33 (100 elements, 2 contact sections per element, frictionless pre-load): at
/// 1.3 s −4.939 mm, mean −4.936 mm (range −4.940 to −4.930 mm), flange force mean −28.5 N,
/// standard deviation 5.0 N, largest 45.1 N; 1 of 1301 steps halved.
#[test]
fn walked_belt_rides_the_flange() {
    let scene = common::scene("belt_drive_3d");
    let mut sim = common::simulation(&scene, &[("pulley2.skew", Value::Real(0.03))]).unwrap();
    let (flange_at, mu, pretension) = (-0.005, 0.4, 300.0);
    let mut f = vec![];
    let mut lateral: f64 = 0.0;
    let mut ride = vec![];
    drive_ramped(&scene, &mut sim, 1300, 0.0, |sim, t, _| {
        lateral = common::output(&scene, sim, "belt2.lateral");
        assert!(
            lateral > flange_at - 5e-4,
            "t = {t}: over the flange, lateral {lateral}"
        );
        if t > 1.0 + 1e-9 {
            f.push(common::output(&scene, sim, "pulley2.flange_force"));
            ride.push(lateral);
        }
    });
    let s = sim.stats();
    println!("flange run: {s:?}");
    let n = f.len() as f64;
    let mean = f.iter().sum::<f64>() / n;
    let sd = (f.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
    let peak = f.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let ride_mean = ride.iter().sum::<f64>() / ride.len() as f64;
    let (ride_min, ride_max) = ride
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    println!(
        "flange: belt2.lateral at 1.3 s {:.3} mm, over 1.0-1.3 s mean {:.3} mm (from {:.3} to {:.3} mm); pulley2.flange_force over 1.0-1.3 s mean {mean:.2} N, standard deviation {sd:.2} N, largest {peak:.2} N",
        1e3 * lateral,
        1e3 * ride_mean,
        1e3 * ride_min,
        1e3 * ride_max
    );
    assert!(
        (ride_mean - flange_at).abs() < 3e-4,
        "mean lateral over 1.0-1.3 s {ride_mean}"
    );
    assert!(mean < -1.0, "mean flange force {mean}");
    assert!(
        mean.abs() < mu * 2.0 * pretension,
        "mean flange force {mean}"
    );
}

/// Quarter-twist drive (`scenes/conveyor_twist.toml`, issue 13): pre-loaded from the mount
/// along the quarter-twist path (Newton alone diverges from that mount; the pre-load relaxes
/// it in pseudo time first, `statics::relax`). Pulley 1 about z driven to 10 rad/s over
/// 0.1 s, pulley 2 about −x loaded with 5 N m (ramped over 0.1 s), 1 ms steps, 0.4 s, means
/// over the last 0.1 s. Checks, one quantity each:
/// - the width direction at the middle of each span is turned about half a quarter turn
///   from both pulleys' axes (the twist is spread over the span: the mount puts it there and
///   the running belt keeps it, 45° ± 10°);
/// - the driven pulley follows: its speed is pulley 1's times R1/R2 (= 1, equal radii) less
///   the creep, within 1 %;
/// - the torque the belt carries, Euler's equation of moments with the exit angle: each span
///   arrives at a pulley in its plane and leaves the other at `α = 2 atan(R/D)` (15.6°) out of
///   its plane, so only `T cos α` of the leaving span has a moment about that pulley's axis:
///   driver `τ1 = R (T_t − T_s cos α)` (the tight span arrives), driven
///   `τ2 = R (T_t cos α − T_s)` (the tight span leaves), within 5 % (the edgewise stiffness
///   spreads the exit over ~0.1 m, so the exit angle at the rim is not exactly α: measured
///   2.0 % and 3.9 % with the span tensions taken at the span middles);
/// - pulley 2's equation of motion in the steady state: belt torque = load + bearing damping
///   `c ω2`, within 3 %;
/// - energy balance: input work = stored + dissipated within 2 %.
#[test]
fn quarter_twist_drive_carries_torque() {
    let scene = flexfmu::scene::Scene::from_path(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/conveyor_twist.toml"),
    )
    .unwrap();
    let mut sim = common::simulation(&scene, &[width_points()]).unwrap();
    let (ia, iw, it) = (
        common::input_index(&scene, "pulley1.angle"),
        common::input_index(&scene, "pulley1.omega"),
        common::input_index(&scene, "pulley2.torque_in"),
    );
    let (h, omega, load, ramp, t_end, window): (f64, f64, f64, f64, f64, f64) =
        (1e-3, 10.0, 5.0, 0.1, 0.4, 0.1);
    let axes = [Vector3::z(), -Vector3::x()];
    let energy = |sim: &Simulation| {
        let m = sim.model_as::<Belt3d>().unwrap();
        (
            m.output_of(SpatialOutput::Energy(EnergyKind::Total)),
            m.input_work(),
            m.dissipated(),
        )
    };
    // twist at the middles of the spans: the node nearest to each span's middle
    let mid_twist = |sim: &Simulation| {
        let m = sim.model_as::<Belt3d>().unwrap();
        let n = m.n_nodes();
        let p1: Vector3<f64> = Vector3::zeros();
        let p2 = Vector3::new(0.082, 0.6, 0.082);
        let c = 0.5 * (p1 + p2);
        // the two nodes nearest to the plane through the middle of the centres, normal to
        // the line of centres, one on each span
        let d = (p2 - p1).normalize();
        let mut idx: Vec<usize> = (0..n).collect();
        idx.sort_by(|&a, &b| {
            let f = |k: usize| (m.node_position(k) - c).dot(&d).abs();
            f(a).total_cmp(&f(b))
        });
        let first = idx[0];
        let second = *idx[1..]
            .iter()
            .find(|&&k| {
                (k as isize - first as isize).rem_euclid(n as isize) > 3
                    && (first as isize - k as isize).rem_euclid(n as isize) > 3
            })
            .unwrap();
        [first, second].map(|k| {
            let w = m.node_width_direction(k);
            axes.map(|a| w.dot(&a).abs().clamp(0.0, 1.0).acos().to_degrees())
        })
    };
    let at_mount = mid_twist(&sim);
    let e0 = energy(&sim);
    let mut angle = 0.0;
    let (mut acc, mut count) = ([0.0; 5], 0.0);
    let steps = (t_end / h).round() as usize;
    for i in 0..steps {
        let t = i as f64 * h;
        let r = |t: f64| (t / ramp).min(1.0);
        let w = 0.5 * omega * (r(t) + r(t + h));
        sim.set_input(ia, angle);
        sim.set_input(iw, w);
        sim.set_input(it, -load * r(t + h));
        sim.advance(t + h)
            .unwrap_or_else(|e| panic!("t = {t}: {}", e.message));
        angle += w * h;
        if t + h > t_end - window + 1e-12 {
            let m = sim.model_as::<Belt3d>().unwrap();
            let tn = m.span_tensions();
            acc[0] += tn[0];
            acc[1] += tn[1];
            acc[2] += m.pulley_motion(1).1;
            acc[3] += m.pulley_load(0).2;
            acc[4] += m.pulley_load(1).2;
            count += 1.0;
        }
    }
    let [t_a, t_b, omega2, torque1, torque2] = acc.map(|x| x / count);
    let running = mid_twist(&sim);
    let e1 = energy(&sim);
    let (w_in, stored, diss) = (e1.1 - e0.1, e1.0 - e0.0, e1.2 - e0.2);
    let balance = (w_in - stored - diss) / w_in;
    let r = 0.08 + 0.002;
    let alpha = 2.0 * (r / 0.6f64).atan();
    let (t_t, t_s) = (t_a.max(t_b), t_a.min(t_b));
    let euler1 = r * (t_t - t_s * alpha.cos());
    let euler2 = r * (t_t * alpha.cos() - t_s);
    let damping = 0.2;
    println!(
        "quarter twist: width direction at the span middles, angle to axis 1 / axis 2 [deg]: mounted {at_mount:.1?}, running {running:.1?}"
    );
    println!(
        "span tensions {t_a:.2} N, {t_b:.2} N; belt torque on pulley 1 {torque1:.3} N m against R (T_t - T_s cos a) = {euler1:.3} N m; on pulley 2 {torque2:.3} N m against R (T_t cos a - T_s) = {euler2:.3} N m and load + c w2 = {:.3} N m; w2 = {omega2:.4} rad/s; power to pulley 2 / input {:.3}",
        load + damping * omega2,
        (torque2 * omega2 / (torque1 * omega)).abs()
    );
    println!(
        "energy: input work {w_in:.3} J = stored {stored:.3} J + dissipated {diss:.3} J, defect {:.3} %",
        100.0 * balance
    );
    for span in running {
        for ang in span {
            assert!((ang - 45.0).abs() < 10.0, "span twist {running:?}");
        }
    }
    assert!(
        (omega2 / omega - 1.0).abs() < 0.01,
        "pulley 2 at {omega2} rad/s"
    );
    assert!(
        (torque1.abs() / euler1 - 1.0).abs() < 0.05,
        "driver: tensions {t_a}, {t_b} vs torque {torque1}"
    );
    assert!(
        (torque2.abs() / euler2 - 1.0).abs() < 0.05,
        "driven: tensions {t_a}, {t_b} vs torque {torque2}"
    );
    assert!(
        (torque2.abs() / (load + damping * omega2) - 1.0).abs() < 0.03,
        "torque {torque2} vs load"
    );
    assert!(balance.abs() < 0.02, "energy defect {balance}");
}

/// The shipped `belt_drive_3d` started from rest (pulley 1 ramped to 10 rad/s over 0.1 s, the
/// load on pulley 2 to 5 N m), 1 ms steps, 0.2 s: no time step may fail. Before the bristle
/// became a Kelvin–Voigt element (`contact::circle_friction::bristle_factor`) the committed
/// deflection `f/k_t` held the damper's force, and from 12 ms on a step-to-step oscillation of
/// the driver's arc grew until Newton cycled (the whole arc flipping between slip directions):
/// 308 failed steps in 0.3 s at 120 elements. The remaining failures at 60-72 elements, a
/// node arriving on an arc, are what damped Newton (`Belt3d::damped_newton`) takes away.
#[test]
fn start_from_rest_has_no_failed_steps() {
    let scene = common::scene("belt_drive_3d");
    let mut sim = common::simulation(&scene, &[]).unwrap();
    drive_ramped(&scene, &mut sim, 200, 5.0, |_, _, _| {});
    let s = sim.stats();
    assert_eq!(s.rejected - s.rejected_error, 0, "Newton failures: {s:?}");
    // pulley 2 follows the driver at the ratio of the radii, still settling 0.1 s after the
    // ramp (measured 6.80 against 6.67 rad/s)
    let speed = common::output(&scene, &sim, "pulley2.omega");
    let ratio = 10.0 * 0.08 / 0.12;
    assert!((speed - ratio).abs() < 0.05 * ratio, "{speed}");
}

/// The scene `belt_drive_3d` with pulley 2's centre at `distance` [m] along x (shipped:
/// 0.5 m) and both rims `rim_width` [m] wide (shipped: 0.04 m).
fn drive_variant(distance: f64, rim_width: f64) -> flexfmu::scene::Scene {
    let text = std::fs::read_to_string(common::scene_path("belt_drive_3d")).unwrap();
    let text = text.replace(
        "center = [0.5, 0.0, 0.0]",
        &format!("center = [{distance}, 0.0, 0.0]"),
    );
    let text = text.replace("width = 0.04\n", &format!("width = {rim_width}\n"));
    flexfmu::scene::Scene::from_toml(&text).unwrap()
}

/// Tilt walk (exploration, prints, asserts nothing): `belt_drive_3d` with pulley 2 at
/// `BELT3D_D` (0.5 m) and rims `BELT3D_RIM` (0.04 m) wide, `BELT3D_PARAM` (pulley2.tilt) set
/// to `BELT3D_VALUE` (0.02 rad), `BELT3D_N` elements (72), `BELT3D_STEPS` 1 ms steps (2000);
/// prints belt1/belt2.lateral every 0.1 s and the lateral speeds over 0.1 s windows.
#[test]
#[ignore = "exploration: prints the lateral positions, no check"]
fn tilt_walk_exploration() {
    let env = |k: &str, d: f64| std::env::var(k).map_or(d, |v| v.parse().unwrap());
    let scene = drive_variant(env("BELT3D_D", 0.5), env("BELT3D_RIM", 0.04));
    let param = std::env::var("BELT3D_PARAM").unwrap_or("pulley2.tilt".into());
    let value = env("BELT3D_VALUE", 0.02);
    let n = env("BELT3D_N", 72.0) as i32;
    let steps = env("BELT3D_STEPS", 2000.0) as usize;
    let mut sim = common::simulation(
        &scene,
        &[
            (param.as_str(), Value::Real(value)),
            ("belt.n_elements", Value::Integer(n)),
            width_points(),
        ],
    )
    .unwrap();
    let mut trace: Vec<[f64; 5]> = vec![];
    drive_ramped(&scene, &mut sim, steps, 0.0, |sim, t, i| {
        if i % 10 == 9 {
            let out = |name: &str| common::output(&scene, sim, name);
            trace.push([
                t,
                out("belt1.lateral"),
                out("belt2.lateral"),
                out("belt.speed"),
                out("pulley2.flange_force"),
            ]);
        }
    });
    println!("{param} = {value}: stats {:?}", sim.stats());
    for w in trace.windows(11).step_by(10) {
        let (a, b) = (w[0], w[10]);
        let dt = b[0] - a[0];
        println!(
            "{param} {value} t {:.2}: belt1.lateral {:+.3} mm belt2.lateral {:+.3} mm speed {:.3} m/s flange {:+.2} N | over the next 0.1 s: {:+.3} mm/s on 1, {:+.3} mm/s on 2, ratio to v*{param} {:+.3} {:+.3}",
            a[0],
            1e3 * a[1],
            1e3 * a[2],
            a[3],
            a[4],
            1e3 * (b[1] - a[1]) / dt,
            1e3 * (b[2] - a[2]) / dt,
            (b[1] - a[1]) / dt / (a[3] * value),
            (b[2] - a[2]) / dt / (a[3] * value),
        );
    }
}

/// Tilt walk (issue 13 item 4): pulley 2 of `belt_drive_3d` tilted by `t` = 0.02 rad about
/// the line of centres (`pulley2.tilt`), pulley 1 ramped to 10 rad/s over 0.1 s, no load,
/// 1 ms steps, rims widened to 80 mm so that the belt does not reach a flange.
///
/// Derivation (ours, first order in `t`; kinematics of a belt on a rim as in the skew test:
/// a point landing on a rim keeps its axial place, a span arriving at the angle β to the rim's
/// plane moves the landing place by `−β` per unit of belt travel; spans straight between their
/// tangent points, pitch radii `R1`, `R2`, centre distance `D`, span length
/// `l = √(D² − (R2 − R1)²)`, wraps `w1 = R1 (π − 2γ)`, `w2 = R2 (π + 2γ)`, `sin γ = (R2 − R1)/D`,
/// loop `L = 2 l + w1 + w2`): the tilt moves pulley 2's rim at its tangent points by `±R2 t`
/// along z (its tangents there stay in the drive plane), and the spans' inclination
/// `(R2 − R1)/D` adds `∓(R2 − R1) t` to their angle with pulley 2's axis. A span lands
/// without entry angle when it arrives `R1 t` (on pulley 2) and `R2 t` (on pulley 1) to the
/// side of its departure place, and the landing places then stay on the rims for the wraps:
/// the belt comes round shifted by `(R1 + R2) t` per loop. Steady walk on both pulleys:
/// `ζ̇ = v (R1 + R2) t / L` (0.124 v t here; the lag of the landing places makes a lateral
/// wave that travels round the loop, period `L/v`, so the rate is measured over one loop
/// period, 0.5 s to 0.5 s + L/v, as the mean of the two pulleys' rates; each pulley's alone is
/// off by up to ±25 % with the wave). Measured at 72 elements (session 29, exploration
/// `tilt_walk_exploration`): 0.96–1.04 of it for tilt ±0.01, ±0.02 rad and D = 0.8 m from
/// any start after 0.3 s; the straight-span model leaves out the belt's edgewise stiffness,
/// which for a skewed pulley (whose rim leaves the belt out of the drive plane) brings the
/// steady walk to 0.67 of the same model (`v skew l/L`). Checked: the walk rate within ±15 %
/// of `v (R1 + R2) t / L` (this excludes no walk and the rate `v (R1 + R2) t/(2D)` of spans
/// without the wraps' memory, 1.6 times it).
#[test]
fn tilted_pulley_walks_the_belt_at_the_loop_rate() {
    let (d, tilt, rim) = (0.5, 0.02, 0.08);
    let scene = drive_variant(d, rim);
    let n_el: i32 = std::env::var("BELT3D_N").map_or(48, |v| v.parse().unwrap());
    // pitch radii: the rims' radii plus half the 4 mm belt (scene `belt.thickness`)
    let (r1, r2) = (0.08 + 0.002, 0.12 + 0.002);
    let gamma = ((r2 - r1) / d).asin();
    let span = (d * d - (r2 - r1) * (r2 - r1)).sqrt();
    let loop_length = 2.0 * span
        + r1 * (std::f64::consts::PI - 2.0 * gamma)
        + r2 * (std::f64::consts::PI + 2.0 * gamma);
    let (t0, v_nominal) = (0.5, 10.0 * r1);
    let t1 = t0 + loop_length / v_nominal;
    let steps = (t1 / 1e-3).ceil() as usize + 2;
    let mut sim = common::simulation(
        &scene,
        &[
            ("pulley2.tilt", Value::Real(tilt)),
            ("belt.n_elements", Value::Integer(n_el)),
        ],
    )
    .unwrap();
    let mut trace: Vec<[f64; 4]> = vec![];
    drive_ramped(&scene, &mut sim, steps, 0.0, |sim, t, _| {
        let out = |name: &str| common::output(&scene, sim, name);
        trace.push([
            t,
            out("belt1.lateral"),
            out("belt2.lateral"),
            out("belt.speed"),
        ]);
    });
    let at = |t: f64| {
        *trace
            .iter()
            .min_by(|a, b| (a[0] - t).abs().total_cmp(&(b[0] - t).abs()))
            .unwrap()
    };
    let (a, b) = (at(t0), at(t1));
    let window: Vec<&[f64; 4]> = trace
        .iter()
        .filter(|s| s[0] >= a[0] && s[0] <= b[0])
        .collect();
    // belt speed: the driver's pitch speed (the creep of the unloaded drive is ~0.1 %);
    // `belt.speed` is printed (its mean over the window is 3 % high at 48 elements)
    let v = v_nominal;
    let speed = window.iter().map(|s| s[3]).sum::<f64>() / window.len() as f64;
    let dt = b[0] - a[0];
    let rates = [(b[1] - a[1]) / dt, (b[2] - a[2]) / dt];
    let rate = 0.5 * (rates[0] + rates[1]);
    let expected = v * (r1 + r2) * tilt / loop_length;
    for s in trace.iter().step_by(250) {
        println!(
            "tilt walk: t {:.2} s belt1.lateral {:+.3} mm belt2.lateral {:+.3} mm",
            s[0],
            1e3 * s[1],
            1e3 * s[2]
        );
    }
    println!(
        "tilt walk over {:.2}-{:.2} s (one loop, L = {loop_length:.4} m, v = {v:.4} m/s, mean belt.speed {speed:.4} m/s): pulley 1 {:+.3} mm/s, pulley 2 {:+.3} mm/s, mean {:+.3} mm/s against v (R1 + R2) t / L = {:+.3} mm/s (ratio {:.3}); stats {:?}",
        a[0],
        b[0],
        1e3 * rates[0],
        1e3 * rates[1],
        1e3 * rate,
        1e3 * expected,
        rate / expected,
        sim.stats()
    );
    assert!(
        (rate / expected - 1.0).abs() < 0.15,
        "walk rate {rate} m/s against {expected} m/s"
    );
}

/// The flange stops the tilt walk (issue 13 item 4): pulley 2 of `belt_drive_3d` (shipped
/// 40 mm rims, belt 30 mm: the edge meets a flange at `beltN.lateral` = ±5 mm) tilted by
/// 0.03 rad, pulley 1 ramped to 10 rad/s over 0.1 s, no load, 1 ms steps, 2.5 s. The belt
/// walks to +z on both pulleys (`tilted_pulley_walks_the_belt_at_the_loop_rate`; measured:
/// it reaches pulley 1's flange at ~1.3 s, pulley 2's at ~1.9 s). Checked as the skew's
/// flange test: at the end the belt is on pulley 2's flange (`belt2.lateral` within 0.5 mm of
/// +5 mm), never over it (never beyond +5.5 mm on either pulley), and over the last 0.3 s
/// `pulley2.flange_force` has the walk's sign with a mean of at least 1 N, below what
/// friction on the rim can push sideways, μ (T1 + T2) = 240 N.
#[test]
fn tilted_pulley_walks_the_belt_onto_the_flange() {
    let scene = common::scene("belt_drive_3d");
    let mut sim = common::simulation(&scene, &[("pulley2.tilt", Value::Real(0.03))]).unwrap();
    let (flange_at, mu, pretension, t_end) = (0.005, 0.4, 300.0, 2.5);
    let mut f = vec![];
    let mut lateral = [0.0; 2];
    let steps = (t_end / 1e-3_f64).round() as usize;
    drive_ramped(&scene, &mut sim, steps, 0.0, |sim, t, i| {
        lateral = [
            common::output(&scene, sim, "belt1.lateral"),
            common::output(&scene, sim, "belt2.lateral"),
        ];
        for l in lateral {
            assert!(l < flange_at + 5e-4, "t = {t}: over a flange, lateral {l}");
        }
        if t > t_end - 0.3 + 1e-9 {
            f.push(common::output(&scene, sim, "pulley2.flange_force"));
        }
        if i % 250 == 249 {
            println!(
                "tilt 0.03: t {t:.2} s belt1.lateral {:+.3} mm belt2.lateral {:+.3} mm pulley1.flange_force {:+.2} N pulley2.flange_force {:+.2} N",
                1e3 * lateral[0],
                1e3 * lateral[1],
                common::output(&scene, sim, "pulley1.flange_force"),
                common::output(&scene, sim, "pulley2.flange_force"),
            );
        }
    });
    let n = f.len() as f64;
    let mean = f.iter().sum::<f64>() / n;
    let sd = (f.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
    let peak = f.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    println!(
        "tilt flange: belt1.lateral {:.3} mm, belt2.lateral {:.3} mm, pulley2.flange_force over the last 0.3 s mean {mean:.2} N, standard deviation {sd:.2} N, largest {peak:.2} N; stats {:?}",
        1e3 * lateral[0],
        1e3 * lateral[1],
        sim.stats()
    );
    assert!(
        (lateral[1] - flange_at).abs() < 5e-4,
        "belt2.lateral {}",
        lateral[1]
    );
    assert!(mean > 1.0, "mean flange force {mean}");
    assert!(mean < mu * 2.0 * pretension, "mean flange force {mean}");
}

/// Mean axial force [N] of the elements whose middles lie on pulley 1's arc, on pulley 2's
/// arc and on the spans (a middle within 0.2 mm of the pitch circle `R + t/2`, on the outer
/// side of the pulley; the chord's middle of an arc element lies inside it).
fn arc_and_span_tensions(d: &Drive, mids: &[Vector2<f64>], tensions: &[f64]) -> [f64; 3] {
    let centers = [Vector2::zeros(), Vector2::new(d.distance, 0.0)];
    let mut sums = [(0.0, 0.0); 3];
    for (m, t) in mids.iter().zip(tensions) {
        let on = (0..2).find(|&i| {
            let outer = if i == 0 { m.x < 0.0 } else { m.x > d.distance };
            outer && (m - centers[i]).norm() < d.radii[i] + 0.5 * d.thickness + 2e-4
        });
        let c = on.unwrap_or(2);
        sums[c].0 += t;
        sums[c].1 += 1.0;
    }
    sums.map(|(s, n)| s / n)
}

/// Configurational force of a bent belt (issue 13 item 4): in frictionless equilibrium the
/// axial force of an elastica wrapped on a pulley of pitch radius ρ is the span's less
/// `EI/(2ρ²)` (tangential equilibrium `T' = κ Q`, moment `M' = −Q`, `M = EI κ`: `T + EI κ²/2`
/// is constant where no friction acts; Eshelby's force on the curvature jump). The pre-load
/// of both drives is that equilibrium (the run-in state), so at rest the arcs of the shipped
/// belt (EI 0.05 N m², ρ 0.082 / 0.122 m: 3.72 / 1.68 N) must carry that much less than the
/// spans, in the planar and in the 3D drive (144 elements, measured over the outer half of
/// each arc: planar 3.65 / 1.72 N, 3D 3.62 / 1.72 N). With friction in the pre-load the
/// arcs kept the mount's strain (over the whole arcs: 10.2 / 6.3 N planar, 4.8 / 3.3 N 3D).
#[test]
fn arcs_at_rest_carry_the_span_tension_less_ei_over_two_rho_squared() {
    let d = SHIPPED;
    let n = 144;
    let planar = d.planar_points(n, 4);
    assert!(planar.preload_was_frictionless());
    let q = planar.coordinates();
    let p = |k: usize| Vector2::new(q[4 * (k % n)], q[4 * (k % n) + 1]);
    let mids: Vec<_> = (0..n).map(|e| 0.5 * (p(e) + p(e + 1))).collect();
    let t: Vec<_> = (0..n).map(|e| planar.element_tension(e)).collect();
    let tp = arc_and_span_tensions(&d, &mids, &t);
    let mut spatial = d.spatial(n, true);
    spatial.preload(Some(d.pretension), &newton()).unwrap();
    assert!(spatial.preload_was_frictionless());
    let p = |k: usize| spatial.node_position(k % n).xy();
    let mids: Vec<_> = (0..n).map(|e| 0.5 * (p(e) + p(e + 1))).collect();
    let t: Vec<_> = (0..n).map(|e| spatial.element_tension(e)).collect();
    let ts = arc_and_span_tensions(&d, &mids, &t);
    for (model, [a1, a2, span]) in [("planar", tp), ("3D", ts)] {
        for (i, arc) in [a1, a2].into_iter().enumerate() {
            let rho = d.radii[i] + 0.5 * d.thickness;
            let expected = d.ei / (2.0 * rho * rho);
            println!(
                "{model}: span {span:.3} N, arc {} {arc:.3} N: {:.3} N below, EI/(2 rho^2) = {expected:.3} N",
                i + 1,
                span - arc
            );
            assert!(
                ((span - arc) / expected - 1.0).abs() < 0.05,
                "{model}, pulley {}: {} N against {expected} N",
                i + 1,
                span - arc
            );
        }
    }
}

/// Planar limit of a drive of three pulleys (issue 13 item 4, "outputs as the 2D scenes"):
/// the shipped `belt_drive` and `belt_drive_3d` scenes with a third pulley (free, r 0.06 m at
/// (0.25, 0.3) m, inertia 0.002 kg m², bearing damping 0.05 N m s; the belt wraps the three
/// counter-clockwise), pulley 1 ramped to 10 rad/s over 0.1 s, 10 N m on pulley 2, 1 ms steps,
/// means over 0.5–0.6 s: every span tension (`spanN.tension`) within 0.5 % of the planar
/// drive's and the free pulleys' speeds within 0.1 % (measured: spans +0.22 / +0.17 / +0.16 %,
/// speeds −0.002 / −0.026 %; `pulleyN.slip` printed, not checked: pulley 2's creep 0.21 %
/// within 1 %, the idling pulley 3's 0.054 % against 0.080 %, which is its speed's −0.026 %).
#[test]
fn three_pulley_planar_limit() {
    let third = |planar: bool| {
        format!(
            "[[pulley]]\ncenter = [0.25, 0.3{}]\n{}radius = 0.06\n{}mode = \"free\"\ninertia = 0.002\ndamping = 0.05\n\n[outputs]",
            if planar { "" } else { ", 0.0" },
            if planar {
                ""
            } else {
                "axis = [0.0, 0.0, 1.0]\n"
            },
            if planar {
                ""
            } else {
                "width = 0.04\nflange = 0.006\n"
            },
        )
    };
    let text = |name: &str, planar: bool| {
        std::fs::read_to_string(common::scene_path(name))
            .unwrap()
            .replacen("[outputs]", &third(planar), 1)
    };
    let names = [
        "span1.tension",
        "span2.tension",
        "span3.tension",
        "pulley2.omega",
        "pulley3.omega",
        "pulley2.slip",
        "pulley3.slip",
    ];
    let p = ramped_means(&text("belt_drive", true), &names, 600, 100);
    let s = ramped_means(&text("belt_drive_3d", false), &names, 600, 100);
    for (i, n) in names.iter().enumerate() {
        let rel = (s[i] - p[i]) / p[i].abs();
        println!(
            "{n}: planar {:.6} | 3D {:.6} | {:+.3} %",
            p[i],
            s[i],
            100.0 * rel
        );
        let bound = if i < 3 {
            5e-3
        } else if i < 5 {
            1e-3
        } else {
            f64::INFINITY
        };
        assert!(
            rel.abs() < bound,
            "{n}: 3D {} against planar {}",
            s[i],
            p[i]
        );
    }
}

/// The drive turned in space (sessions 33, 34: qa33, qa34): `belt_drive_3d` turned rigidly by
/// 90° about y (axes along x, pulley 2's centre at z = −0.5 m) and by 0.9 rad about
/// (1, 2, 3)/√14, mounted by the path in space, against the drive along z, mounted in the plane
/// z = 0. Pulley 1 ramped to 10 rad/s over 0.1 s, 10 N m on pulley 2, 1 ms steps, Newton
/// tolerance 1e-10, means over 0.2–0.3 s: span tensions, pulley 2's speed and the belt's creep
/// `belt.slip` within 1e-8 (measured: axes along x ≤ 1e-12, oblique ≤ 1.3e-10, the creep, a
/// ratio of small numbers, included; at the scene's tolerance 1e-6 the oblique drive is off by
/// ~1e-6). Both mounts start the belt at the departure of span 1: before session 34 the path in
/// space started it at the arrival on pulley 1, so the nodes lay elsewhere on the loop and the
/// turned drive was off by +6.4e-5 in `belt.tension_tight` here (qa33: +6.5e-5, +7.2e-5,
/// −3.4e-5 in tensions and speed at tolerance 1e-6) and its creep by 13–31 % (`pulleyN.slip`
/// of a three-pulley drive: the idling pulley's 6.2e-4 against 7.9e-4 along z, which is its
/// speed's +1.7e-4).
#[test]
fn drive_turned_in_space_equals_the_drive_along_z() {
    use nalgebra::{Rotation3, Unit};
    let text = std::fs::read_to_string(common::scene_path("belt_drive_3d")).unwrap();
    let text = common::with(&text, "newton_tolerance", "1e-10");
    let v = |v: Vector3<f64>| format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z);
    let turned = |r: Rotation3<f64>| {
        let t = text
            .replace(
                "axis = [0.0, 0.0, 1.0]",
                &format!("axis = {}", v(r * Vector3::z())),
            )
            .replace(
                "center = [0.5, 0.0, 0.0]",
                &format!("center = {}", v(r * Vector3::new(0.5, 0.0, 0.0))),
            );
        assert_ne!(t, text);
        t
    };
    let names = [
        "belt.tension_tight",
        "belt.tension_slack",
        "pulley2.omega",
        "belt.slip",
    ];
    let a = ramped_means(&text, &names, 300, 100);
    for (tag, r) in [
        (
            "axes along x",
            Rotation3::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2),
        ),
        (
            "oblique",
            Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::new(1.0, 2.0, 3.0)), 0.9),
        ),
    ] {
        let b = ramped_means(&turned(r), &names, 300, 100);
        for (i, n) in names.iter().enumerate() {
            let rel = (b[i] - a[i]) / a[i];
            println!(
                "{tag}, {n}: along z {:.9e} | turned {:.9e} | {rel:+.2e}",
                a[i], b[i]
            );
            assert!(rel.abs() < 1e-8, "{tag}, {n}: {} against {}", b[i], a[i]);
        }
    }
    // pulley 2 tilted and skewed: the misalignment is defined in the pulley's own plane, so
    // two turned copies walk the same way. (Compared between the copies with axes along x and
    // oblique, both mounted by the path in space: the drive along z is mounted by the planar
    // loop, which puts the belt on a tilted rim at another lateral place, and its frictionless
    // pre-load keeps that place.) Before session 34 the arriving span was projected on the xy
    // plane: the copy with its axes along x (centres differing in z only) had no tilt or skew
    // at all, and the oblique copy another misalignment than the one asked for (measured
    // before the fix: its scene was refused, the span missing pulley 1's pitch circle by
    // 1.52 mm).
    let misaligned = |t: &str| {
        let m = t.replace("tilt = 0.0", "tilt = 0.005\nskew = 0.003");
        assert_ne!(m, t);
        m
    };
    let names = ["belt2.lateral", "pulley2.omega", "belt.tension_tight"];
    let along_x = Rotation3::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    let oblique =
        Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::new(1.0, 2.0, 3.0)), 0.9);
    let a = ramped_means(&misaligned(&turned(along_x)), &names, 150, 50);
    let b = ramped_means(&misaligned(&turned(oblique)), &names, 150, 50);
    assert!(
        a[0].abs() > 1e-4,
        "the misaligned drive did not walk: {} m",
        a[0]
    );
    for (i, n) in names.iter().enumerate() {
        let rel = (b[i] - a[i]) / a[i];
        println!(
            "misaligned, {n}: axes along x {:.9e} | oblique {:.9e} | {rel:+.2e}",
            a[i], b[i]
        );
        assert!(
            rel.abs() < 1e-6,
            "misaligned, {n}: {} against {}",
            b[i],
            a[i]
        );
    }
}
