//! Creep measurement of a two-pulley drive in steady state (issue 12 item 1): pulley 1 driven at
//! a given speed, pulley 2 free with a load torque, the speed ratio against Grashof's creep law
//! (reference `shared/reference/belt-drive.md` E.4; Johnson, Contact Mechanics, 1985, §8.4):
//!
//! `ω2 ρ2 / (ω1 ρ1) = (1 + T2/EA) / (1 + T1/EA)`
//!
//! (mass flow `v/(1 + ε)` constant along the belt; the belt adheres to each pulley on the arc
//! after its entry, where it keeps the tension of the span it comes from: `T1` on the driver,
//! `T2` on the driven pulley). The creep is `c = 1 − ω2 ρ2/(ω1 ρ1)`, theory
//! `c_th = (T1 − T2)/(EA + T1)`, with the span tensions `T1`, `T2` of the model itself.
//!
//! Reference radius: the theory's `ρ` is the radius at which the tension member (here: the
//! belt centre line) runs on the pulley. Two are reported:
//! * the pitch radius `ρ = r + t/2` (the contact's circle, what a datasheet gives);
//! * the running radius `ρ − δ(T)`, with `δ` the penalty penetration under the adhering
//!   tension (pressure `p = T/ρ`, `p = k_n (δ − δ0/2)` of the smoothed penalty): the driver's
//!   at `T1`, the driven pulley's at `T2`. The penetration is a model compliance, not belt
//!   theory: with a pitch-radius reference it shows up as creep error of relative size
//!   `≈ δ/ρ / c_th`.
//!
//! Speeds are averaged over the window from the angles (`(θ(t_b) − θ(t_a))/(t_b − t_a)`), the
//! tensions as the mean of the committed span tensions of every step in the window.

use super::PulleySide;
use super::model::{BeltDrive, BeltElementKind, BeltPath, BeltSpec, default_contact};
use super::pulleys::{PulleyDef, PulleyKind};
use super::scene::{BeltOutput, Output, PulleyInput};
use crate::contact::ContactLaw;
use crate::elements::ancf_cable2d::{CableRule, CableSection};
use crate::integrators::{GeneralizedAlpha, Integrator};
use crate::linalg::SolverKind;
use crate::solver::newton::{NewtonPolicy, NewtonSettings};
use crate::solver::simulation::{Simulation, SolverConfig};
use nalgebra::Vector2;

/// A two-pulley drive run to steady state. Geometry of the shipped `scenes/belt_drive.toml`
/// by default ([`CreepCase::stiff`]).
#[derive(Clone, Debug, PartialEq)]
pub struct CreepCase {
    /// Axial stiffness `EA` [N].
    pub ea: f64,
    /// Bending stiffness [N m²].
    pub ei: f64,
    /// Mass per length [kg/m].
    pub mass_per_length: f64,
    /// Axial material damping [N s].
    pub damping_axial: f64,
    /// Belt thickness `t` [m].
    pub thickness: f64,
    /// Span tension at rest [N].
    pub pretension: f64,
    /// Friction coefficient [1].
    pub mu: f64,
    /// Pulley radii (driver, driven) [m].
    pub radii: [f64; 2],
    /// Centre distance [m].
    pub center_distance: f64,
    /// Inertia of the driven pulley [kg m²].
    pub inertia: f64,
    /// Bearing damping of the driven pulley [N m s/rad].
    pub bearing_damping: f64,
    /// Belt elements.
    pub n_elements: usize,
    /// Contact points per element.
    pub points_per_element: usize,
    /// Driver speed [rad/s] (reached by a linear ramp over `ramp` seconds).
    pub omega: f64,
    /// Load torque on the driven pulley [N m] (ramped like the speed).
    pub load: f64,
    /// Ramp time [s].
    pub ramp: f64,
    /// Start and end of the averaging window [s].
    pub window: [f64; 2],
    /// Communication step = largest internal step [s].
    pub step: f64,
    /// Newton tolerance (scaled increment) [1].
    pub newton_tolerance: f64,
    /// Contact law; `None`: the default derived from the belt ([`default_contact`]).
    pub contact: Option<ContactLaw>,
}

impl CreepCase {
    /// The shipped drive (`scenes/belt_drive.toml`): EA = 5e4 N, pre-tension 300 N, μ = 0.4,
    /// pulleys of 80 and 120 mm at 0.5 m, belt 4 mm thick, 100 elements; driver at 30 rad/s,
    /// load `load` [N m], bearing damping 0.01 N m s.
    pub fn stiff(load: f64) -> Self {
        Self {
            ea: 5e4,
            ei: 0.05,
            mass_per_length: 0.15,
            damping_axial: 20.0,
            thickness: 0.004,
            pretension: 300.0,
            mu: 0.4,
            radii: [0.08, 0.12],
            center_distance: 0.5,
            inertia: 0.01,
            bearing_damping: 0.01,
            n_elements: 100,
            points_per_element: 4,
            omega: 30.0,
            load,
            ramp: 0.3,
            window: [0.8, 1.4],
            step: 1e-3,
            newton_tolerance: 1e-7,
            contact: None,
        }
    }

    /// The soft belt of issue 12: the same drive with EA = 8000 N, pre-tension 400 N (5 %
    /// strain), μ = 0.5, 120 elements.
    pub fn soft(load: f64) -> Self {
        Self {
            ea: 8000.0,
            pretension: 400.0,
            mu: 0.5,
            n_elements: 120,
            ..Self::stiff(load)
        }
    }

    /// Pitch radii `r + t/2` [m].
    pub fn pitch_radii(&self) -> [f64; 2] {
        self.radii.map(|r| r + 0.5 * self.thickness)
    }

    /// The contact law in use.
    pub fn law(&self) -> ContactLaw {
        self.contact.unwrap_or_else(|| self.default_law())
    }

    /// The default contact law for this belt ([`default_contact`], as a scene builds it).
    pub fn default_law(&self) -> ContactLaw {
        let rp = self.pitch_radii();
        default_contact(
            self.ea,
            self.mass_per_length,
            self.thickness,
            rp[0].min(rp[1]),
            rp[0].max(rp[1]),
            self.pretension,
            self.mu,
            (0.0, 0.0, 0.0),
        )
    }

    /// Wrap angles of the open belt on the (driver, driven) pulley [rad].
    pub fn wrap_angles(&self) -> [f64; 2] {
        let [a, b] = self.pitch_radii();
        let beta = ((b - a) / self.center_distance).asin();
        [
            std::f64::consts::PI - 2.0 * beta,
            std::f64::consts::PI + 2.0 * beta,
        ]
    }

    /// The model of the drive.
    pub fn model(&self) -> Result<BeltDrive, String> {
        let newton = self.newton();
        BeltDrive::new(BeltSpec {
            section: CableSection {
                ea: self.ea,
                ei: self.ei,
                mass_per_length: self.mass_per_length,
                damping_axial: self.damping_axial,
                damping_bending: 0.0,
                prestrain: 0.0,
            },
            element: BeltElementKind::Cable(CableRule::Full),
            thickness: self.thickness,
            pulleys: vec![
                PulleyDef {
                    center: Vector2::zeros(),
                    radius: self.radii[0],
                    kind: PulleyKind::Driven,
                    side: PulleySide::Front,
                },
                PulleyDef {
                    center: Vector2::new(self.center_distance, 0.0),
                    radius: self.radii[1],
                    kind: PulleyKind::Free {
                        inertia: self.inertia,
                        damping: self.bearing_damping,
                    },
                    side: PulleySide::Front,
                },
            ],
            contact: self.law(),
            points_per_element: self.points_per_element,
            gravity: Vector2::zeros(),
            path: BeltPath::Closed {
                n_elements: self.n_elements,
                pretension: self.pretension,
            },
            n_points: 0,
            track_energy: false,
            tensioner: None,
            statics: (newton, SolverKind::Auto, 1),
        })
    }

    fn newton(&self) -> NewtonSettings {
        NewtonSettings {
            tolerance: self.newton_tolerance,
            max_iterations: 25,
            policy: NewtonPolicy::Modified,
            line_search: true,
        }
    }

    /// Runs the drive and measures its creep.
    pub fn measure(&self) -> Result<CreepReport, String> {
        let cfg = SolverConfig {
            integrator: Integrator::GeneralizedAlpha(GeneralizedAlpha::from_rho_inf(0.8)),
            max_step: self.step,
            newton: self.newton(),
            static_equilibrium: true,
            load_steps: 1,
            linear: SolverKind::Auto,
            tolerance: 0.0,
        };
        let mut sim = Simulation::new(Box::new(self.model()?), cfg, 0.0)?;
        sim.initialize()?;
        let h = self.step;
        let n = (self.window[1] / h).round() as usize;
        let start = (self.window[0] / h).round() as usize;
        let ramp = |t: f64| (t / self.ramp).min(1.0);
        let (mut angle, mut theta_a, mut t_a) = (0.0, 0.0, 0.0);
        let (mut t1, mut t2, mut samples) = (0.0, 0.0, 0.0);
        let (mut steps, mut iterations, mut factorizations) = (0, 0, 0);
        let wall = std::time::Instant::now();
        for i in 0..n {
            let t = i as f64 * h;
            let (w0, w1) = (self.omega * ramp(t), self.omega * ramp(t + h));
            let m = sim.model_as_mut::<BeltDrive>().ok_or("not a belt drive")?;
            m.set_pulley_input(0, PulleyInput::Angle, angle);
            m.set_pulley_input(0, PulleyInput::Omega, 0.5 * (w0 + w1));
            m.set_pulley_input(1, PulleyInput::Torque, -self.load * ramp(t));
            let s0 = sim.stats();
            sim.advance(t + h)
                .map_err(|e| format!("t = {t}: {}", e.message))?;
            angle += 0.5 * (w0 + w1) * h;
            let d = sim.model_as::<BeltDrive>().ok_or("not a belt drive")?;
            if i + 1 == start {
                theta_a = d.output_of(Output::Belt(BeltOutput::PulleyAngle(1)));
                t_a = t + h;
                (samples, t1, t2) = (0.0, 0.0, 0.0);
            }
            if i + 1 > start {
                t1 += d.output_of(Output::Belt(BeltOutput::TensionTight));
                t2 += d.output_of(Output::Belt(BeltOutput::TensionSlack));
                samples += 1.0;
                let s1 = sim.stats();
                steps += s1.steps - s0.steps;
                iterations += s1.newton.iterations - s0.newton.iterations;
                factorizations += s1.newton.factorizations - s0.newton.factorizations;
            }
        }
        let wall = wall.elapsed().as_secs_f64();
        let d = sim.model_as::<BeltDrive>().ok_or("not a belt drive")?;
        let t_b = n as f64 * h;
        let omega2 =
            (d.output_of(Output::Belt(BeltOutput::PulleyAngle(1))) - theta_a) / (t_b - t_a);
        let (t1, t2) = (t1 / samples, t2 / samples);
        let total = sim.stats();
        let adhering = adhesion_radii(self, d, t1, t2);
        Ok(CreepReport::new(
            self,
            t1,
            t2,
            omega2,
            adhering,
            Cost {
                steps,
                iterations,
                factorizations,
                wall,
                simulated: t_b - t_a,
                total_steps: total.steps,
            },
        ))
    }
}

/// Mean radius of the belt nodes on each pulley's adhesion arc (see
/// [`CreepReport::adhering`]) in the committed state of `d`.
fn adhesion_radii(case: &CreepCase, d: &BeltDrive, t1: f64, t2: f64) -> [f64; 2] {
    let q = d.coordinates();
    let n = d.n_elements();
    let rp = case.pitch_radii();
    let centers = [Vector2::zeros(), Vector2::new(case.center_distance, 0.0)];
    let band = 0.1 * (t1 - t2).abs();
    std::array::from_fn(|k| {
        let entry = if k == 0 { t1 } else { t2 };
        let (mut sum, mut count) = (0.0, 0.0);
        for node in 0..n {
            let r = (Vector2::new(q[4 * node], q[4 * node + 1]) - centers[k]).norm();
            let near = |e: usize| (d.element_tension(e) - entry).abs() < band;
            if r < rp[k] && near(node) && near((node + n - 1) % n) {
                sum += r;
                count += 1.0;
            }
        }
        if count > 0.0 { sum / count } else { f64::NAN }
    })
}

/// Work of a measurement over its averaging window.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cost {
    /// Internal steps in the window.
    pub steps: usize,
    /// Newton iterations in the window.
    pub iterations: usize,
    /// Factorizations in the window.
    pub factorizations: usize,
    /// Wall time of the whole run (start-up included) [s].
    pub wall: f64,
    /// Simulated time of the window [s].
    pub simulated: f64,
    /// Internal steps of the whole run.
    pub total_steps: usize,
}

impl Cost {
    /// Newton iterations per internal step in the window.
    pub fn iterations_per_step(&self) -> f64 {
        self.iterations as f64 / self.steps.max(1) as f64
    }

    /// Factorizations per internal step in the window.
    pub fn factorizations_per_step(&self) -> f64 {
        self.factorizations as f64 / self.steps.max(1) as f64
    }
}

/// What a creep measurement found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreepReport {
    /// Mean tight and slack span tension [N].
    pub tensions: [f64; 2],
    /// Driver and (mean) driven speed [rad/s].
    pub omegas: [f64; 2],
    /// Grashof's creep `(T1 − T2)/(EA + T1)` [1].
    pub theory: f64,
    /// Measured creep with the pitch radii `r + t/2` [1].
    pub pitch: f64,
    /// Measured creep with the running radii `ρ − δ(T)` (driver at `T1`, driven at `T2`) [1].
    pub running: f64,
    /// Measured creep with the measured radii of the adhesion arcs [1].
    pub measured: f64,
    /// Mean distance of the belt nodes on the adhesion arcs from the pulley centres (driver,
    /// driven) [m]: nodes in contact whose elements carry the entry tension within 10 % of
    /// `T1 − T2` (`T1` on the driver, `T2` on the driven pulley); NaN if none.
    pub adhering: [f64; 2],
    /// Sliding arc `ln(T1/T2)/μ` over the smaller wrap angle [1] (Grashof's theory needs
    /// adhesion arcs: well below 1).
    pub sliding_fraction: f64,
    /// Torque balance error `|(T1 − T2) ρ2 − (M + c ω2)| / (M + c ω2)` [1].
    pub torque_error: f64,
    /// Work of the run.
    pub cost: Cost,
}

impl CreepReport {
    fn new(
        case: &CreepCase,
        t1: f64,
        t2: f64,
        omega2: f64,
        adhering: [f64; 2],
        cost: Cost,
    ) -> Self {
        let rp = case.pitch_radii();
        let law = case.law();
        // penetration of the smoothed penalty under the pressure T/ρ
        let delta = |t: f64, rho: f64| {
            let p = t / rho;
            let lin = p / law.k_n + 0.5 * law.smoothing;
            if lin >= law.smoothing {
                lin
            } else {
                (2.0 * law.smoothing * p / law.k_n).sqrt()
            }
        };
        let w1 = case.omega;
        let pitch = 1.0 - omega2 * rp[1] / (w1 * rp[0]);
        let running = 1.0 - omega2 * (rp[1] - delta(t2, rp[1])) / (w1 * (rp[0] - delta(t1, rp[0])));
        let measured = 1.0 - omega2 * adhering[1] / (w1 * adhering[0]);
        let wraps = case.wrap_angles();
        let load = case.load + case.bearing_damping * omega2;
        Self {
            tensions: [t1, t2],
            omegas: [w1, omega2],
            theory: (t1 - t2) / (case.ea + t1),
            pitch,
            running,
            measured,
            adhering,
            sliding_fraction: (t1 / t2).ln() / case.mu / wraps[0].min(wraps[1]),
            torque_error: ((t1 - t2) * rp[1] - load).abs() / load.abs(),
            cost,
        }
    }

    /// Slip error with the pitch radii: `|c − c_th| / c_th` [1].
    pub fn pitch_error(&self) -> f64 {
        (self.pitch - self.theory).abs() / self.theory
    }

    /// Slip error with the measured radii of the adhesion arcs [1].
    pub fn measured_error(&self) -> f64 {
        (self.measured - self.theory).abs() / self.theory
    }

    /// Slip error with the running radii [1].
    pub fn running_error(&self) -> f64 {
        (self.running - self.theory).abs() / self.theory
    }
}
