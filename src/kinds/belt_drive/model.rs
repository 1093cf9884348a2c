//! Belt drive: a belt of ANCF cable (or seed-000) elements in frictional contact with pulleys
//! that are driven (prescribed angle and speed, belt torque out) or free (rigid bodies with
//! inertia and bearing damping inside the model, driven by an input torque).
//!
//! Coordinates: the belt's nodal coordinates (4 per node) followed by one angle per pulley;
//! driven pulleys' angles are constrained (prescribed), free pulleys' are unknowns coupled to
//! every belt coordinate through the contact (the iteration matrix is a ring with a border,
//! factorized by the bordered banded LU of [`crate::linalg::bordered`]).
//!
//! Contact: a [`ContactPointSet`] of `contact.points_per_element` equally spaced material
//! points per element against the pulleys' pitch circles ([`Circle`] obstacles, kernel
//! [`crate::contact::circle_friction`]). This file assembles the drive from its pieces: the
//! pulleys (`pulleys.rs`), the static pre-load (`preload.rs`) and the energy book
//! (`energy.rs`). Equations of motion:
//! `M q̈ + Q_int(q, q̇) − Σ Q_contact(q, q̇, θ, ω) − Q_g = 0` for the belt and
//! `J θ̈ + c θ̇ − τ_in − Σ τ_contact = 0` for each free pulley.

use super::energy::{EnergyBook, StepRates};
pub use super::preload::PreloadReport;
use super::pulleys::PulleyIo;
pub use super::pulleys::{PulleyDef, PulleyKind};
use super::tensioner::Tensioner;
pub use super::tensioner::TensionerDef;
use crate::assembly::{Assembly, Connectivity, DofMap, ElementSet, Eval, check_finite};
use crate::contact::{ArmPulley, Circle, ContactLaw, ContactPointSet};
use crate::elements::Element;
use crate::elements::ancf_cable2d::{self, AncfCable2d, CableRule, CableSection, ElemVec};
use crate::elements::ancf_shear2d::{AncfShear2d, Section, Shear2dElement, ShearRule};
use crate::elements::material::{PlaneElasticity, StrainEnergy};
use crate::integrators::DynState;
use crate::kinds::KindIo;
use crate::kinds::belt_drive::scene::{BeltOutput, Input, Output};
use crate::kinds::belt_drive::{BeltDriveScene, PulleyMode, PulleySide};
use crate::kinds::energy::EnergyKind;
use crate::linalg::CscPattern;
use crate::meshers::belt_loop::{Loop, PitchCircle};
use crate::model::inputs::InputSignal;
use crate::model::rates;
use crate::model::{
    JacobianCoeffs, MechanicalSystem, Model, ModelError, newton_scales_with_gradients,
};
use crate::scene::params::{
    ParamValues,
    names::{GRAVITY_X, GRAVITY_Y},
};
use crate::snapshot::{StateReader, StateWriter};
use crate::solver::simulation::SolverConfig;
use nalgebra::{Vector2, Vector3};
use std::sync::Arc;

/// Coordinates per belt node.
pub(super) const NC: usize = 4;

/// Which element the belt is made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BeltElementKind {
    /// Gradient-deficient ANCF cable with the given integration rule.
    Cable(CableRule),
    /// Seed-000 shear-deformable ANCF beam with an equivalent rectangle of height
    /// `h = √(12 EI/EA)`, unit width, `E = EA/h`, ν = 0.3, 1×2 shear rule.
    Shear,
}

/// The belt's path at the start.
#[derive(Clone, Debug, PartialEq)]
pub enum BeltPath {
    /// Closed loop around all pulleys (in order, counter-clockwise), `n_elements` elements,
    /// mounted with span tension `pretension` [N] and brought into static equilibrium.
    Closed {
        /// Number of elements.
        n_elements: usize,
        /// Span tension at rest [N].
        pretension: f64,
    },
    /// Open belt through the given nodes (position, unit tangent), elements of reference
    /// length `|r_{k+1} − r_k| / stretch`; ends loaded by [`BeltDrive::set_end_load`].
    Open {
        /// Node positions [m] and unit tangents.
        nodes: Vec<(Vector2<f64>, Vector2<f64>)>,
        /// Mounted / reference length.
        stretch: f64,
    },
}

/// Everything a belt drive is built from.
#[derive(Clone, Debug, PartialEq)]
pub struct BeltSpec {
    /// Section (EA, EI, mass per length, material damping; pre-strain is not used: the
    /// pre-tension comes from the reference length).
    pub section: CableSection,
    /// Element type.
    pub element: BeltElementKind,
    /// Belt thickness [m].
    pub thickness: f64,
    /// Pulleys.
    pub pulleys: Vec<PulleyDef>,
    /// Contact constants.
    pub contact: ContactLaw,
    /// Contact points per element.
    pub points_per_element: usize,
    /// Gravity [m/s²].
    pub gravity: Vector2<f64>,
    /// Path.
    pub path: BeltPath,
    /// Number of `belt.point[i]` outputs.
    pub n_points: usize,
    /// Track input work and dissipation (energy outputs).
    pub track_energy: bool,
    /// A tensioner (its idler one of the free pulleys), or none.
    pub tensioner: Option<TensionerDef>,
    /// Newton settings and linear solver of the static pre-load.
    pub statics: (
        crate::solver::newton::NewtonSettings,
        crate::linalg::SolverKind,
        usize,
    ),
}

/// Default contact constants derived from the belt (see the `contact.*` parameters):
/// `k_n = EA/(t r_min)` (penetration = belt strain × thickness on the smallest pulley),
/// `d_n = √(k_n m')` (half the critical damping of the belt on the penalty spring),
/// `k_t = k_n/10` (chosen by the creep comparison of `kinds::belt_drive::creep`, README belt
/// section: with the slip measured on the pitch circle, k_n/10 keeps the creep of the stiff and
/// the soft belt within 4 % of Grashof's at 1 ms steps for the cost of k_n/100, whose
/// micro-slip μp/k_t made the creep 60-100 % too large; k_t ≥ k_n sticks harder but halves
/// steps on the stiff belt and leaves the creep 3-10 % short at 1 ms), `d_t = d_n √(k_t/k_n)`. `thickness` is floored at 1 % of the smallest radius. The
/// penalty is smoothed over a quarter of the penetration that the tension `t_ref` [N] causes
/// on a pulley of radius `r_max` (`δ0 = t_ref/(4 r_max k_n)`); stick and sliding are blended
/// over ±5 % of the friction limit.
#[allow(clippy::too_many_arguments)]
pub fn default_contact(
    ea: f64,
    mass_per_length: f64,
    thickness: f64,
    r_min: f64,
    r_max: f64,
    t_ref: f64,
    mu: f64,
    given: (f64, f64, f64),
) -> ContactLaw {
    let t = thickness.max(0.01 * r_min);
    let k_n = if given.0 > 0.0 {
        given.0
    } else {
        ea / (t * r_min)
    };
    let d_n = if given.1 > 0.0 {
        given.1
    } else {
        (k_n * mass_per_length).sqrt()
    };
    let k_t = if given.2 > 0.0 { given.2 } else { 0.1 * k_n };
    ContactLaw {
        k_n,
        d_n,
        k_t,
        d_t: d_n * (k_t / k_n).sqrt(),
        mu,
        smoothing: 0.25 * t_ref / (r_max * k_n),
        blend: 0.05,
    }
}

/// What the belt needs of its element besides the [`Element`] trait: centre-line weights and
/// the axial force. Implemented by the cable and by the seed-000 beam; the belt holds one
/// shared element of either type in its [`ElementSet`].
pub(super) trait BeltElement: Element<8> {
    /// Reference length [m].
    fn length(&self) -> f64;

    /// Weights of the four nodal 2-vectors in the centre-line position at `x` [m].
    fn centerline(&self, x: f64) -> [f64; 4];

    /// Axial force at the middle of the element [N] for a belt of axial stiffness `ea` [N].
    fn axial_force_mid(&self, q: &ElemVec, ea: f64) -> f64;

    /// Weights of the four nodal 2-vectors in the centre-line position and in its slope
    /// `∂r/∂x` at `x` [m], if the element's nodal vectors are position and slope (the belt's
    /// transport predictor needs them; `None`: no transport).
    fn transport_weights(&self, _x: f64) -> Option<([f64; 4], [f64; 4])> {
        None
    }
}

impl BeltElement for AncfCable2d {
    fn length(&self) -> f64 {
        AncfCable2d::length(self)
    }

    fn centerline(&self, x: f64) -> [f64; 4] {
        ancf_cable2d::shape_functions(AncfCable2d::length(self), x)
    }

    /// The cable's own `EA(ε − ε0)` (its section is the belt's).
    fn axial_force_mid(&self, q: &ElemVec, _ea: f64) -> f64 {
        self.axial_force(q, 0.5 * AncfCable2d::length(self))
    }

    /// Cubic Hermite shape functions and their first derivatives.
    fn transport_weights(&self, x: f64) -> Option<([f64; 4], [f64; 4])> {
        let l = AncfCable2d::length(self);
        Some((
            ancf_cable2d::shape_functions(l, x),
            ancf_cable2d::shape_d1(l, x),
        ))
    }
}

impl BeltElement for Shear2dElement {
    fn length(&self) -> f64 {
        self.kernel.length()
    }

    fn centerline(&self, x: f64) -> [f64; 4] {
        let xi = x / self.kernel.length();
        [1.0 - xi, 0.0, xi, 0.0]
    }

    /// `EA (chord / l − 1)`.
    fn axial_force_mid(&self, q: &ElemVec, ea: f64) -> f64 {
        let d = Vector2::new(q[4] - q[0], q[5] - q[1]);
        ea * (d.norm() / self.kernel.length() - 1.0)
    }
}

/// The belt element of a kind for section `sec` and reference length `l` [m]: a cable, or a
/// seed-000 beam with an equivalent rectangle of height `h = √(12 EI/EA)`, unit width,
/// `E = EA/h`, ν = 0.3, 1×2 shear rule.
fn belt_element(
    kind: BeltElementKind,
    sec: &CableSection,
    l: f64,
) -> Result<Arc<dyn BeltElement>, String> {
    Ok(match kind {
        BeltElementKind::Cable(rule) => Arc::new(AncfCable2d::new(l, *sec, rule)),
        BeltElementKind::Shear => {
            let h = (12.0 * sec.ei / sec.ea).sqrt();
            let e0 = AncfShear2d::straight_reference(Vector2::zeros(), Vector2::new(l, 0.0));
            let section = Section {
                width: 1.0,
                height: h,
            };
            let law = PlaneElasticity::new(sec.ea / h, 0.3, 5.0 / 6.0, StrainEnergy::Decoupled);
            Arc::new(
                Shear2dElement::new(
                    &e0,
                    l,
                    section,
                    ShearRule::Fixed1x2,
                    law,
                    sec.mass_per_length / h,
                )
                .ok_or("belt element: degenerate reference geometry")?,
            )
        }
    })
}

/// The belt-drive model.
#[derive(Clone, Debug)]
pub struct BeltDrive {
    pub(super) spec: BeltSpec,
    /// What each input and output of the scene means, by index (empty for a model built
    /// from a [`BeltSpec`] without a scene: drive it with the typed methods).
    pub(super) roles: KindIo<Input, Output>,
    /// The belt's elements (one shared element: all have the same reference length).
    pub(super) set: ElementSet<Arc<dyn BeltElement>, 8>,
    pub(super) n_el: usize,
    pub(super) n_nodes: usize,
    pub(super) closed: bool,
    pub(super) asm: Assembly,
    pub(super) pulley_dof: Vec<usize>,
    /// Contact points on the belt against the pitch circles of the pulleys on fixed centres
    /// (all but a tensioner's idler); blocks: element coordinates plus the angle of pulley
    /// `fixed[k]`, row `e · fixed.len() + k`.
    pub(super) contact: ContactPointSet<Circle, 2, 4, 9>,
    /// Pulley index of each obstacle of `contact`.
    pub(super) fixed: Vec<usize>,
    /// Pitch radius of each pulley [m].
    pub(super) pitch: Vec<f64>,
    /// The tensioner, if any.
    pub(super) tensioner: Option<Tensioner>,
    pub(super) gravity_full: Vec<f64>,
    pub(super) end_loads: [Vector2<f64>; 2],
    pub(super) span_mid: Vec<Vector2<f64>>,
    pub(super) scales: Vec<f64>,
    /// Scales of the Newton convergence test (slopes in the length they move the belt by).
    pub(super) newton_scales: Vec<f64>,
    pub(super) io: Vec<PulleyIo>,
    pub(super) t0_step: Option<f64>,
    // committed state
    pub(super) t: f64,
    pub(super) q: Vec<f64>,
    pub(super) v: Vec<f64>,
    /// Accelerations of the committed state (output rates).
    pub(super) acc: Vec<f64>,
    /// Rates of the history-dependent outputs over the last internal step.
    pub(super) step_rates: Option<StepRates>,
    pub(super) tensions: Vec<f64>,
    pub(super) slipping_points: usize,
    pub(super) energy: EnergyBook,
    pub(super) preload: PreloadReport,
    /// Free pulleys held at these angles by a stiff bearing spring during static solves (the
    /// pre-load, a static initialization): otherwise belt and free pulleys turning together
    /// are a mechanism.
    pub(super) held_angles: Option<Vec<f64>>,
    /// During the frictionless static pre-loads: the first belt node is held at this
    /// position [m] along this unit direction (the belt's tangent there) by a spring of this
    /// stiffness [N/m] (without friction the belt sliding round its loop is a mechanism; see
    /// `preload.rs`). Only along the tangent: the spring must not hold the node against the
    /// rim or across a span, which would leave its force in the equilibrium.
    pub(super) belt_anchor: Option<(Vector2<f64>, Vector2<f64>, f64)>,
    /// Whether the static pre-load was frictionless (drives with a tensioner; see
    /// `preload.rs`, which falls back to the pre-load with friction where that fails).
    pub(super) frictionless_preload: bool,
    /// The spans' sag length coefficient `Σ (m' g⊥)² a³ / 24` [N² m] (`m'` the mass per
    /// length, `g⊥` the gravity across the span of chord length `a`): a span of tension `T`
    /// hangs as a catenary whose length exceeds its chord by `(m' g⊥)² a³ / (24 T²)` (the
    /// parabola's `8 d²/(3 a)`, `d = m' g⊥ a²/(8 T)`; Irvine, Cable Structures, 1981, ch. 1);
    /// used by the pre-load's reference-length correction (`preload.rs`). 0 without gravity.
    pub(super) sag_coeff: f64,
    /// Predict each time step's belt coordinates by transporting the committed belt along its
    /// path ([`MechanicalSystem::predict`]; closed cable belts only).
    pub(super) transport_predictor: bool,
    // work buffers
    pub(super) qw: Vec<f64>,
    pub(super) vw: Vec<f64>,
    pub(super) aw: Vec<f64>,
    pub(super) fw: Vec<f64>,
    pub(super) qmid: Vec<f64>,
}

impl BeltDrive {
    /// Builds the drive; a closed belt is brought into static equilibrium with the requested
    /// span tension (the reference length is corrected until the mean span tension matches
    /// within 0.1 %).
    pub fn new(spec: BeltSpec) -> Result<Self, String> {
        Self::new_with(spec, true)
    }

    /// [`Self::new`], with the static pre-load of a closed belt only if `preload` (without it
    /// the belt is mounted at the stretch of its span tension, not in equilibrium: for a
    /// model about to receive a saved state, which carries the pre-loaded belt and its
    /// reference length).
    pub fn new_with(spec: BeltSpec, preload: bool) -> Result<Self, String> {
        let np = spec.pulleys.len();
        let half_t = 0.5 * spec.thickness;
        let circles: Vec<Circle> = spec
            .pulleys
            .iter()
            .map(|p| Circle {
                center: p.center,
                radius: p.radius + half_t,
            })
            .collect();
        let s = &spec.section;
        let (nodes, stretch, closed, span_mid, lp) = match &spec.path {
            BeltPath::Closed {
                n_elements,
                pretension,
            } => {
                let lp = Loop::with_sides(
                    &circles
                        .iter()
                        .map(|c| PitchCircle {
                            center: c.center,
                            radius: c.radius,
                        })
                        .collect::<Vec<_>>(),
                    &spec
                        .pulleys
                        .iter()
                        .map(|p| p.side == PulleySide::Back)
                        .collect::<Vec<_>>(),
                )?;
                let n = *n_elements;
                let stretch = 1.0 + pretension / s.ea;
                let mut nodes = Vec::with_capacity(n);
                for k in 0..n {
                    let p = lp.at(lp.length * k as f64 / n as f64);
                    nodes.push((p.r, p.t));
                }
                let mids = (0..lp.spans.len())
                    .map(|i| lp.at(lp.span_middle(i)).r)
                    .collect();
                (nodes, stretch, true, mids, Some(lp))
            }
            BeltPath::Open { nodes, stretch } => (nodes.clone(), *stretch, false, vec![], None),
        };
        let n_nodes = nodes.len();
        let n_el = if closed { n_nodes } else { n_nodes - 1 };
        let idler = spec.tensioner.map(|t| t.pulley);
        if let Some(j) = idler {
            if j >= np || !matches!(spec.pulleys[j].kind, PulleyKind::Free { .. }) {
                return Err(format!(
                    "tensioner.pulley = {}: the tensioner's idler must be a free pulley of the drive",
                    j + 1
                ));
            }
            if lp.is_none() {
                return Err("a tensioner needs a closed belt".into());
            }
        }
        let fixed: Vec<usize> = (0..np).filter(|&k| Some(k) != idler).collect();
        if n_el < 1 {
            return Err("the belt needs at least one element".into());
        }
        let mounted = match &lp {
            Some(lp) => lp.length / n_el as f64,
            None => (nodes[1].0 - nodes[0].0).norm(),
        };
        let l_ref = mounted / stretch;
        let element = belt_element(spec.element, s, l_ref)?;

        // Coordinates: belt nodes, then one angle per pulley, then the tensioner's arm angle.
        let n_full = n_nodes * NC + np + usize::from(idler.is_some());
        let arm_dof = n_nodes * NC + np;
        let pulley_dof: Vec<usize> = (0..np).map(|k| n_nodes * NC + k).collect();
        let mut constrained = vec![false; n_full];
        for (k, p) in spec.pulleys.iter().enumerate() {
            if p.kind == PulleyKind::Driven {
                constrained[pulley_dof[k]] = true;
            }
        }
        let node = |k: usize| (k % n_nodes) * NC;
        let connectivity: Vec<[usize; 8]> = (0..n_el)
            .map(|e| {
                let (a, b) = (node(e), node(e + 1));
                std::array::from_fn(|i| if i < NC { a + i } else { b + i - NC })
            })
            .collect();
        let mut extra = Vec::new();
        for &pd in &pulley_dof {
            for i in 0..n_nodes * NC {
                extra.push((i, pd));
            }
        }
        if let Some(j) = idler {
            for i in 0..n_nodes * NC {
                extra.push((i, arm_dof));
            }
            extra.push((pulley_dof[j], arm_dof));
        }
        let asm = Assembly::new(
            DofMap::new(&constrained),
            &[(8, connectivity.as_flattened())],
            &extra,
        );
        let blocks: Vec<[usize; 9]> = connectivity
            .iter()
            .flat_map(|d| {
                fixed.iter().map(|&k| {
                    let pd = pulley_dof[k];
                    std::array::from_fn(|i| if i < 8 { d[i] } else { pd })
                })
            })
            .collect();
        let contact_blocks = Connectivity::new(blocks, &asm);
        let tensioner = match (spec.tensioner, &lp) {
            (Some(def), Some(lp)) => {
                let des = super::tensioner::design(&def, lp)?;
                let (psi_d, arm, sigma) = (des.angle, des.arm, des.sigma);
                let t_mount = match spec.path {
                    BeltPath::Closed { pretension, .. } => pretension,
                    BeltPath::Open { .. } => 0.0,
                };
                let arm_blocks: Vec<[usize; 10]> = connectivity
                    .iter()
                    .map(|d| {
                        std::array::from_fn(|i| match i {
                            0..8 => d[i],
                            8 => pulley_dof[def.pulley],
                            _ => arm_dof,
                        })
                    })
                    .collect();
                let obstacle = ArmPulley {
                    pivot: def.pivot,
                    arm,
                    radius: circles[def.pulley].radius,
                };
                Some(Tensioner {
                    def,
                    dof: arm_dof,
                    design: psi_d,
                    free_angle: psi_d + sigma * def.preload / def.stiffness,
                    mounted_free_angle: psi_d + sigma * t_mount * des.lever / def.stiffness,
                    contact: ContactPointSet::new(
                        spec.contact,
                        vec![obstacle],
                        Connectivity::new(arm_blocks, &asm),
                        [0, 2],
                    ),
                    belt_moment: 0.0,
                })
            }
            _ => None,
        };
        let set = ElementSet::new(vec![element], connectivity, &asm);

        // Initial coordinates: nodes on the path; on the arcs moved inwards by the predicted
        // penetration p/k_n with p = T/ρ.
        let tension0 = match &spec.path {
            BeltPath::Closed { pretension, .. } => *pretension,
            BeltPath::Open { stretch, .. } => s.ea * (stretch - 1.0),
        };
        let mut q = vec![0.0; n_full];
        for (k, (r, t)) in nodes.iter().enumerate() {
            let mut r = *r;
            for c in &circles {
                let d = r - c.center;
                if (d.norm() - c.radius).abs() < 1e-9 * c.radius.max(1.0) && tension0 > 0.0 {
                    let pen = tension0 / (c.radius * spec.contact.k_n);
                    r = c.center + d * ((c.radius - pen) / d.norm());
                }
            }
            let slope = match spec.element {
                BeltElementKind::Cable(_) => *t * stretch,
                BeltElementKind::Shear => Vector2::new(-t.y, t.x),
            };
            q[k * NC..k * NC + NC].copy_from_slice(&[r.x, r.y, slope.x, slope.y]);
        }
        let length_scale = match &lp {
            Some(lp) => lp.length,
            None => mounted * n_el as f64,
        };
        let scales = asm
            .dofs
            .free_to_full()
            .iter()
            .map(|&i| {
                if i >= n_nodes * NC || i % NC >= 2 {
                    1.0
                } else {
                    length_scale
                }
            })
            .collect::<Vec<f64>>();
        // Newton's convergence test measures every increment in the length it moves the belt
        // by, against the loop length: a slope (dr/ds, dimensionless) increment δ changes the
        // stretch as a position increment δ·l_e does and moves the element's points by up to
        // 4/27 δ·l_e (the Hermite slope shape function l_e ξ(1−ξ)²). Slopes are measured
        // against L / (4 l_e), i.e. a slope increment counts as a position increment of 4 δ l_e
        // — chosen by measurement (session 28, README "Belt Newton scales"): against L / l_e
        // the serpentine drive's energy mismatch (`energy_balance_of_the_serpentine_drive`)
        // rose from 0.74 to 1.11 % of the input work, against L / (4 l_e) to 0.77 %. With 1
        // (before) a slope was held to l_e / L of the positions' tolerance (1/120 at 120
        // elements), which cost an iteration per step where contact points enter the arcs.
        // The error estimate of adaptive steps keeps the scales above.
        let newton_scales = newton_scales_with_gradients(
            &scales,
            asm.dofs.free_to_full(),
            |i| i < n_nodes * NC && i % NC >= 2,
            length_scale,
            mounted,
        );
        let pitch = circles.iter().map(|c| c.radius).collect();
        let sag_coeff = lp.as_ref().map_or(0.0, |lp| {
            lp.spans
                .iter()
                .map(|sp| {
                    let c = sp.end - sp.start;
                    let a = c.norm();
                    let across = s.mass_per_length * spec.gravity.perp(&c).abs() / a.max(1e-300);
                    across * across * a.powi(3) / 24.0
                })
                .sum::<f64>()
        });
        if let Some(t) = &tensioner {
            q[t.dof] = t.design;
        }
        let contact = ContactPointSet::new(
            spec.contact,
            fixed.iter().map(|&k| circles[k]).collect(),
            contact_blocks,
            [0, 2],
        );
        let mut me = Self {
            roles: KindIo::default(),
            set,
            n_el,
            n_nodes,
            closed,
            pulley_dof,
            contact,
            fixed,
            pitch,
            tensioner,
            gravity_full: vec![0.0; n_full],
            end_loads: [Vector2::zeros(); 2],
            span_mid,
            scales,
            newton_scales,
            io: vec![PulleyIo::default(); np],
            t0_step: None,
            t: 0.0,
            v: vec![0.0; n_full],
            acc: vec![0.0; n_full],
            step_rates: None,
            qw: q.clone(),
            vw: vec![0.0; n_full],
            aw: vec![0.0; n_full],
            fw: vec![0.0; n_full],
            qmid: vec![],
            q,
            tensions: vec![],
            slipping_points: 0,
            energy: EnergyBook::default(),
            preload: PreloadReport::default(),
            held_angles: None,
            belt_anchor: None,
            frictionless_preload: false,
            sag_coeff,
            transport_predictor: true,
            asm,
            spec,
        };
        me.set_reference_length(l_ref)?;
        me.commit(0.0, true);
        if let BeltPath::Closed { pretension, .. } = me.spec.path
            && preload
        {
            me.preload(pretension)?;
        }
        Ok(me)
    }

    /// Builds the model of a belt-drive scene with validated parameter values.
    pub fn build(scene: &BeltDriveScene, p: &ParamValues) -> Result<Self, String> {
        Self::build_with(scene, p, true)
    }

    /// [`Self::build`] for a model about to receive a saved state (fmi2SetFMUstate into a
    /// new simulation): the static pre-load is skipped, since the state carries the
    /// pre-loaded belt and its reference length.
    pub fn build_to_restore(scene: &BeltDriveScene, p: &ParamValues) -> Result<Self, String> {
        Self::build_with(scene, p, false)
    }

    fn build_with(scene: &BeltDriveScene, p: &ParamValues, preload: bool) -> Result<Self, String> {
        use crate::kinds::belt_drive::scene::names::BELT_FORMULATION;
        if super::ale::requested(p) {
            let errs = super::ale::check(scene, p);
            if !errs.is_empty() {
                return Err(errs.join("; "));
            }
            return Err(format!(
                "{BELT_FORMULATION} = \"ale\" (2): `BeltDrive` is the Lagrangian model; the ALE drive is `AleDrive` (built by the kind, see `build_model`)"
            ));
        }
        Self::build_lagrangian(scene, p, preload)
    }

    /// The model of a belt-drive scene as the kind builds it: the Lagrangian [`BeltDrive`], or
    /// with `belt.formulation = "ale"` the [`AleDrive`](super::ale_drive::AleDrive) mounted on
    /// the Lagrangian drive's pre-load (refused, naming the keys, outside the ALE scope).
    /// `preload` false: for a model about to receive a saved state.
    pub fn build_model(
        scene: &BeltDriveScene,
        p: &ParamValues,
        preload: bool,
    ) -> Result<Box<dyn Model>, String> {
        use crate::kinds::belt_drive::scene::names::BELT_INTEGRATION;
        if !super::ale::requested(p) {
            return Ok(Box::new(Self::build_with(scene, p, preload)?));
        }
        let errs = super::ale::check(scene, p);
        if !errs.is_empty() {
            return Err(errs.join("; "));
        }
        let rule = match p.integer(BELT_INTEGRATION) {
            2 => CableRule::Reduced,
            3 => CableRule::Mixed,
            _ => CableRule::Full,
        };
        let base = Self::build_lagrangian(scene, p, preload)?;
        Ok(Box::new(super::ale_drive::AleDrive::mount(base, rule)?))
    }

    fn build_lagrangian(
        scene: &BeltDriveScene,
        p: &ParamValues,
        preload: bool,
    ) -> Result<Self, String> {
        use crate::kinds::belt_drive::scene::{names::*, *};
        let rule = match p.integer(BELT_INTEGRATION) {
            2 => CableRule::Reduced,
            3 => CableRule::Mixed,
            _ => CableRule::Full,
        };
        let element = match p.integer(BELT_ELEMENT) {
            2 => BeltElementKind::Shear,
            _ => BeltElementKind::Cable(rule),
        };
        let section = CableSection {
            ea: p.real(BELT_EA),
            ei: p.real(BELT_EI),
            mass_per_length: p.real(BELT_MASS),
            damping_axial: p.real(BELT_DAMPING_AXIAL),
            damping_bending: p.real(BELT_DAMPING_BENDING),
            prestrain: 0.0,
        };
        let mut centers: Vec<Vector2<f64>> = scene
            .pulley
            .iter()
            .map(|s| Vector2::from(s.center))
            .collect();
        if centers.len() == 2 {
            let dir = (centers[1] - centers[0]).normalize();
            centers[1] = centers[0] + p.real(CENTER_DISTANCE) * dir;
        }
        let pulleys: Vec<PulleyDef> = scene
            .pulley
            .iter()
            .enumerate()
            .map(|(i, s)| PulleyDef {
                center: centers[i],
                radius: p.real(PULLEY_RADIUS[i]),
                side: s.side,
                kind: match s.mode {
                    PulleyMode::Driven => PulleyKind::Driven,
                    PulleyMode::Free => PulleyKind::Free {
                        inertia: p.real(PULLEY_INERTIA[i]),
                        damping: p.real(PULLEY_DAMPING[i]),
                    },
                },
            })
            .collect();
        let thickness = p.real(BELT_THICKNESS);
        let r_min = pulleys
            .iter()
            .map(|p| p.radius)
            .fold(f64::INFINITY, f64::min);
        let r_max = pulleys.iter().map(|p| p.radius).fold(0.0, f64::max);
        let contact = default_contact(
            section.ea,
            section.mass_per_length,
            thickness,
            r_min + 0.5 * thickness,
            r_max + 0.5 * thickness,
            p.real(BELT_PRETENSION),
            p.real(CONTACT_MU),
            (
                p.real(CONTACT_STIFFNESS),
                p.real(CONTACT_DAMPING),
                p.real(CONTACT_FRICTION_STIFFNESS),
            ),
        );
        let gravity = Vector2::new(
            p.get(GRAVITY_X).map_or(0.0, |_| p.real(GRAVITY_X)),
            p.get(GRAVITY_Y).map_or(0.0, |_| p.real(GRAVITY_Y)),
        );
        let cfg = SolverConfig::from_params(p);
        let mut drive = Self::new_with(
            BeltSpec {
                section,
                element,
                thickness,
                pulleys,
                contact,
                points_per_element: p.integer(CONTACT_POINTS) as usize,
                gravity,
                path: BeltPath::Closed {
                    n_elements: p.integer(BELT_N_ELEMENTS) as usize,
                    pretension: p.real(BELT_PRETENSION),
                },
                n_points: belt_points(scene),
                track_energy: scene.outputs.energy,
                tensioner: scene.tensioner.as_ref().map(|t| TensionerDef {
                    pulley: t.pulley as usize - 1,
                    pivot: Vector2::from(t.pivot),
                    stiffness: p.real(TENSIONER_STIFFNESS),
                    preload: p.real(TENSIONER_PRELOAD),
                    damping: p.real(TENSIONER_DAMPING),
                    inertia: p.real(TENSIONER_INERTIA),
                }),
                statics: (cfg.newton, cfg.linear, cfg.load_steps),
            },
            preload,
        )?;
        for (i, s) in scene.pulley.iter().enumerate() {
            drive.io[i].omega_in = InputSignal::constant(s.omega);
            drive.io[i].torque_in = InputSignal::constant(s.torque_in);
        }
        drive.roles = io(scene);
        Ok(drive)
    }

    /// Rebuilds the element, mass, gravity and contact points for reference length `l`.
    pub(super) fn set_reference_length(&mut self, l: f64) -> Result<(), String> {
        self.set.set_elements(vec![belt_element(
            self.spec.element,
            &self.spec.section,
            l,
        )?]);
        let n_cp = self.spec.points_per_element.max(1);
        let weights: Vec<[f64; 4]> = (0..n_cp)
            .map(|i| {
                self.element()
                    .centerline((i as f64 + 0.5) / n_cp as f64 * l)
            })
            .collect();
        if let Some(t) = self.tensioner.as_mut() {
            t.contact.set_points(weights.clone(), l / n_cp as f64);
        }
        self.contact.set_points(weights, l / n_cp as f64);
        self.gravity_full.iter_mut().for_each(|x| *x = 0.0);
        let g = self.spec.gravity;
        self.set.add_gravity(
            &self.q,
            None,
            &Vector3::new(g.x, g.y, 0.0),
            1.0,
            &mut self.gravity_full,
        );
        Ok(())
    }

    /// The belt element (all elements share it).
    pub(super) fn element(&self) -> &dyn BeltElement {
        &**self.set.element(0)
    }

    /// Switches the transport predictor of the time steps on or off (default on; see
    /// [`MechanicalSystem::predict`] for this model). The converged steps agree within the
    /// Newton tolerance either way; the predictor saves iterations.
    pub fn set_transport_predictor(&mut self, on: bool) {
        self.transport_predictor = on;
    }

    /// What free coordinate `k` is, for diagnostics: `node i r.x` (`r.y`, `r'.x`, `r'.y`)
    /// with the gap of that node to the nearest pulley's pitch circle [mm] (committed state;
    /// positive: off the pulley), `pulley k angle`, or `tensioner arm`.
    pub fn describe_free_coordinate(&self, k: usize) -> String {
        let Some(&i) = self.asm.dofs.free_to_full().get(k) else {
            return format!("free coordinate {k} (none)");
        };
        let belt = self.n_nodes * NC;
        if i < belt {
            let (node, c) = (i / NC, i % NC);
            let r = Vector2::new(self.q[node * NC], self.q[node * NC + 1]);
            let (gap, pulley) = (0..self.spec.pulleys.len())
                .map(|p| ((r - self.pulley_center(p)).norm() - self.pitch[p], p))
                .fold((f64::INFINITY, 0), |b, x| {
                    if x.0.abs() < b.0.abs() { x } else { b }
                });
            let name = ["r.x", "r.y", "r'.x", "r'.y"][c];
            format!(
                "node {node} {name} (gap {:.3} mm to pulley {})",
                1e3 * gap,
                pulley + 1
            )
        } else if let Some(p) = self.pulley_dof.iter().position(|&d| d == i) {
            format!("pulley {} angle", p + 1)
        } else {
            "tensioner arm".into()
        }
    }

    /// Force on an end of an open belt (0: first node, 1: last node) [N].
    pub fn set_end_load(&mut self, end: usize, f: Vector2<f64>) {
        self.end_loads[end] = f;
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.n_el
    }

    /// Reference length of one element [m].
    pub fn element_length(&self) -> f64 {
        self.element().length()
    }

    /// Full coordinates of the committed state (belt nodes, then pulley angles).
    pub fn coordinates(&self) -> &[f64] {
        &self.q
    }

    /// Full velocities of the committed state.
    pub fn velocities(&self) -> &[f64] {
        &self.v
    }

    /// Span tensions of the committed state [N] (span `i` from pulley `i` to `i + 1`).
    pub fn span_tensions(&self) -> &[f64] {
        &self.tensions
    }

    /// Number of contact points sliding in the committed state.
    pub fn slipping_points(&self) -> usize {
        self.slipping_points
    }

    /// Contact constants in use.
    pub fn contact_law(&self) -> &ContactLaw {
        &self.spec.contact
    }

    /// Axial force in the middle of element `e` [N] (committed state).
    pub fn element_tension(&self, e: usize) -> f64 {
        let qe = self.set.gather(e, &self.q);
        self.element().axial_force_mid(&qe, self.spec.section.ea)
    }

    /// Residual terms into `self.fw` from `self.qw`, `self.vw`, `self.aw`, and the iteration
    /// matrix (stiffness part scaled by `k_scale`, for the midpoint rule).
    fn evaluate(
        &mut self,
        t: f64,
        load_factor: f64,
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        let mut f = std::mem::take(&mut self.fw);
        f.iter_mut().for_each(|x| *x = 0.0);
        let mut jac = jac;
        if let Some((_, vals)) = jac.as_mut() {
            vals.iter_mut().for_each(|x| *x = 0.0);
        }
        let x = Eval {
            q: &self.qw,
            v: &self.vw,
            a: &self.aw,
            g: Vector3::zeros(),
        };
        self.set
            .add_residual(&x, None, &mut f, jac.as_mut().map(|(c, v)| (*c, &mut **v)));
        self.add_pulley_residual(t, &mut f, jac.as_mut().map(|(c, v)| (*c, &mut **v)));
        self.contact.add_residual(
            &self.qw,
            &self.vw,
            &mut f,
            jac.as_mut().map(|(c, v)| (*c, &mut **v)),
        );
        if self.tensioner.is_some() {
            self.add_tensioner_residual(
                load_factor,
                &mut f,
                jac.as_mut().map(|(c, v)| (*c, &mut **v)),
            );
            let mut ten = self.tensioner.take();
            if let Some(tn) = ten.as_mut() {
                tn.contact.add_residual(
                    &self.qw,
                    &self.vw,
                    &mut f,
                    jac.as_mut().map(|(c, v)| (*c, &mut **v)),
                );
            }
            self.tensioner = ten;
        }
        if let Some((anchor, t, k)) = self.belt_anchor {
            let along = k * t.dot(&(Vector2::new(self.qw[0], self.qw[1]) - anchor));
            f[0] += along * t.x;
            f[1] += along * t.y;
            if let Some((c, vals)) = jac.as_mut() {
                for i in 0..2 {
                    for j in 0..2 {
                        self.asm
                            .add_entry(i, j, c.stiffness * k * t[i] * t[j], vals);
                    }
                }
            }
        }
        // external: gravity and end loads
        for (fi, g) in f.iter_mut().zip(&self.gravity_full) {
            *fi -= load_factor * g;
        }
        if !self.closed {
            let last = (self.n_nodes - 1) * NC;
            for (node, load) in [(0, self.end_loads[0]), (last, self.end_loads[1])] {
                f[node] -= load_factor * load.x;
                f[node + 1] -= load_factor * load.y;
            }
        }
        self.fw = f;
        check_finite(&[], jac.as_ref().map(|(_, vals)| &**vals))
    }

    /// Commits the full state `self.q`, `self.v` at time `t`: contact histories, pulley
    /// results, span tensions and (after a step, `initial` false) the energy book.
    pub(super) fn commit(&mut self, t: f64, initial: bool) {
        let (mut q, mut v) = (std::mem::take(&mut self.q), std::mem::take(&mut self.v));
        self.prescribe(t, &mut q, &mut v, None);
        let mut book = self.contact.commit(&q, &v, initial);
        for (&k, load) in self.fixed.iter().zip(self.contact.loads()) {
            self.io[k].torque = load.generalized[0];
            self.io[k].force = load.force;
        }
        if let Some(tn) = self.tensioner.as_mut() {
            let arm = tn.contact.commit(&q, &v, initial);
            let load = tn.contact.loads()[0];
            let io = &mut self.io[tn.def.pulley];
            io.torque = load.generalized[0];
            io.force = load.force;
            tn.belt_moment = load.generalized[1];
            book.slipping += arm.slipping;
            book.normal_energy += arm.normal_energy;
            book.dissipation += arm.dissipation;
            book.friction_work += arm.friction_work;
        }
        self.slipping_points = book.slipping;
        self.q = q;
        self.v = v;
        // span tensions: average of the axial force in the three elements nearest to the
        // middle of each span
        self.tensions = self
            .span_mid
            .iter()
            .map(|m| {
                let mut best = (f64::INFINITY, 0);
                for e in 0..self.n_el {
                    let d = self.set.element_dofs(e);
                    let mid = 0.5
                        * Vector2::new(self.q[d[0]] + self.q[d[4]], self.q[d[1]] + self.q[d[5]]);
                    let dist = (mid - m).norm();
                    if dist < best.0 {
                        best = (dist, e);
                    }
                }
                let e = best.1;
                let n = self.n_el;
                (self.element_tension((e + n - 1) % n)
                    + self.element_tension(e)
                    + self.element_tension((e + 1) % n))
                    / 3.0
            })
            .collect();
        self.book_energy(t, initial, &book);
        self.t = t;
    }

    /// Belt centre-line point at material fraction `u ∈ [0, 1)` of the loop [m].
    pub fn belt_point(&self, u: f64) -> Vector2<f64> {
        self.belt_point_of(u, &self.q)
    }

    /// The belt point at `u` interpolated from full coordinates (or velocities) `x`.
    fn belt_point_of(&self, u: f64, full: &[f64]) -> Vector2<f64> {
        let s = u.rem_euclid(1.0) * self.n_el as f64;
        let e = (s.floor() as usize).min(self.n_el - 1);
        let x = (s - e as f64) * self.element().length();
        let w = self.element().centerline(x);
        let qe = self.set.gather(e, full);
        let mut r = Vector2::zeros();
        for a in 0..4 {
            r.x += w[a] * qe[2 * a];
            r.y += w[a] * qe[2 * a + 1];
        }
        r
    }

    /// Mean speed of the belt nodes [m/s].
    pub fn belt_speed(&self) -> f64 {
        self.belt_speed_of(&self.v)
    }

    fn belt_speed_of(&self, v: &[f64]) -> f64 {
        (0..self.n_nodes)
            .map(|k| Vector2::new(v[k * NC], v[k * NC + 1]).norm())
            .sum::<f64>()
            / self.n_nodes as f64
    }

    /// Time derivative of an output of the committed state. Analytic: pulley angles and
    /// speeds (`ω`, `α`), belt points (interpolated velocities), the input work (the input
    /// power at the committed state). Along the motion ([`rates::along_motion`]): belt speed,
    /// slip, kinetic and potential energy, the belt's strain energy. Over the last internal
    /// step (backward difference, first order): pulley torques and forces, span tensions, the
    /// contact part of the strain energy and the dissipated energy, which depend on the
    /// friction history; `None` before the first step.
    pub(super) fn output_rate(&self, kind: Output) -> Option<f64> {
        let along = |f: &dyn Fn(&[f64], &[f64]) -> f64| {
            let mut work = [Vec::new(), Vec::new()];
            rates::along_motion(&self.q, &self.v, &self.acc, &mut work, f)
        };
        let last = || self.step_rates.as_ref();
        let point = |i: usize| self.belt_point_of(i as f64 / self.spec.n_points as f64, &self.v);
        let strain = || Some(along(&|q, _| self.belt_strain_energy_of(q)) + last()?.contact_energy);
        Some(match kind {
            Output::Belt(b) => match b {
                BeltOutput::PulleyTorque(k) => last()?.pulleys.get(k)?[0],
                BeltOutput::PulleyForceX(k) => last()?.pulleys.get(k)?[1],
                BeltOutput::PulleyForceY(k) => last()?.pulleys.get(k)?[2],
                BeltOutput::PulleyAngle(k) => self.v[self.pulley_dof[k]],
                BeltOutput::PulleyOmega(k) => self.acc[self.pulley_dof[k]],
                BeltOutput::TensionTight => last()?.tight,
                BeltOutput::TensionSlack => last()?.slack,
                BeltOutput::Slip => along(&|_, v| self.slip_of(v)),
                BeltOutput::PulleySlip(k) => along(&|_, v| self.pulley_slip_of(k, v)),
                BeltOutput::TensionerAngle => {
                    self.tensioner.as_ref().map_or(0.0, |t| self.v[t.dof])
                }
                BeltOutput::TensionerTorque => along(&|q, v| self.tensioner_torque_of(q, v)),
                // by differences of the outputs (not in the step rates: the saved state of
                // the two-pulley drives keeps its layout)
                BeltOutput::SpanTension(_) => return None,
                BeltOutput::Speed => along(&|_, v| self.belt_speed_of(v)),
                BeltOutput::PointX(i) => point(i).x,
                BeltOutput::PointY(i) => point(i).y,
                BeltOutput::InputWork => self.energy.p_in,
                BeltOutput::Dissipated => last()?.dissipated,
            },
            Output::Energy(k) => match k {
                EnergyKind::Kinetic => along(&|_, v| self.kinetic_energy_of(v)),
                EnergyKind::Potential => along(&|q, _| self.potential_energy_of(q)),
                EnergyKind::Strain => strain()?,
                EnergyKind::Total => {
                    strain()?
                        + along(&|q, v| self.kinetic_energy_of(v) + self.potential_energy_of(q))
                }
            },
        })
    }

    /// An output of the committed state.
    pub fn output_of(&self, kind: Output) -> f64 {
        match kind {
            Output::Belt(b) => match b {
                BeltOutput::PulleyTorque(k) => self.io[k].torque,
                BeltOutput::PulleyForceX(k) => self.io[k].force.x,
                BeltOutput::PulleyForceY(k) => self.io[k].force.y,
                BeltOutput::PulleyAngle(k) => self.q[self.pulley_dof[k]],
                BeltOutput::PulleyOmega(k) => self.v[self.pulley_dof[k]],
                BeltOutput::TensionTight => self
                    .tensions
                    .iter()
                    .copied()
                    .fold(f64::NEG_INFINITY, f64::max),
                BeltOutput::TensionSlack => {
                    self.tensions.iter().copied().fold(f64::INFINITY, f64::min)
                }
                BeltOutput::Slip => self.slip_of(&self.v),
                BeltOutput::PulleySlip(k) => self.pulley_slip_of(k, &self.v),
                BeltOutput::TensionerAngle => self.tensioner_angle(),
                BeltOutput::TensionerTorque => self.tensioner_torque(),
                BeltOutput::SpanTension(i) => self.tensions.get(i).copied().unwrap_or(0.0),
                BeltOutput::Speed => self.belt_speed(),
                BeltOutput::PointX(i) => self.belt_point(i as f64 / self.spec.n_points as f64).x,
                BeltOutput::PointY(i) => self.belt_point(i as f64 / self.spec.n_points as f64).y,
                BeltOutput::InputWork => self.energy.input_work,
                BeltOutput::Dissipated => self.energy.dissipated,
            },
            Output::Energy(k) => match k {
                EnergyKind::Kinetic => self.kinetic_energy(),
                EnergyKind::Strain => self.strain_energy(),
                EnergyKind::Potential => self.potential_energy(),
                EnergyKind::Total => {
                    self.kinetic_energy() + self.strain_energy() + self.potential_energy()
                }
            },
        }
    }

    fn finish(&self, r: &mut [f64]) -> Result<(), ModelError> {
        self.asm.dofs.restrict(&self.fw, r);
        check_finite(r, None)
    }
}

impl Model for BeltDrive {
    /// What the static pre-load could not do ([`PreloadReport::note`]).
    ///
    /// [`PreloadReport::note`]: super::preload::PreloadReport::note
    fn build_note(&self) -> Option<String> {
        self.preload.note.clone()
    }

    /// The belt's centre line (four points per element) and each pulley's pitch circle with
    /// a radius marking its angle.
    fn sketch(&self) -> crate::model::Sketch {
        let mut s = crate::model::Sketch::new(format!(
            "{} {} belt elements, {} pulleys",
            self.n_el,
            match self.spec.element {
                BeltElementKind::Cable(_) => "gradient-deficient ANCF cable",
                BeltElementKind::Shear => "seed-000 shear-deformable ANCF",
            },
            self.spec.pulleys.len()
        ));
        let n = 4 * self.n_el;
        let last = if self.closed { n } else { n - 1 };
        s.line_xy((0..=last).map(|k| {
            let p = self.belt_point(k as f64 / n as f64);
            [p.x, p.y]
        }));
        for (k, p) in self.spec.pulleys.iter().enumerate() {
            let pc = self.pulley_center(k);
            let c = Vector3::new(pc.x, pc.y, 0.0);
            s.circle(c, p.radius, Vector3::z());
            let phi = self.q[self.pulley_dof[k]];
            s.line([c, c + p.radius * Vector3::new(phi.cos(), phi.sin(), 0.0)]);
        }
        if let Some(t) = &self.tensioner {
            let o = t.contact.obstacles()[0];
            let c = o.center(self.q[t.dof]);
            s.line([
                Vector3::new(o.pivot.x, o.pivot.y, 0.0),
                Vector3::new(c.x, c.y, 0.0),
            ]);
        }
        s
    }

    /// Before the first communication step the angle of a driven pulley is where the master's
    /// rigid body starts: the pulley is turned there under the belt without slip (a pulley's
    /// absolute angle means nothing to the belt; only its rotation during the run does).
    fn set_input(&mut self, input: usize, value: f64) {
        let Input::Pulley { pulley, quantity } = self.roles.inputs[input];
        self.set_pulley_input(pulley, quantity, value);
    }

    fn set_input_derivative(
        &mut self,
        input: usize,
        order: usize,
        value: f64,
    ) -> Result<(), String> {
        if !(1..=2).contains(&order) {
            return Err(format!("derivative order {order} not supported (1 or 2)"));
        }
        let Input::Pulley { pulley, quantity } = self.roles.inputs[input];
        self.signal(pulley, quantity).set_derivative(order, value);
        Ok(())
    }

    fn output_derivative(&self, output: usize) -> Option<f64> {
        self.output_rate(self.roles.outputs[output])
    }

    fn output(&self, output: usize) -> f64 {
        self.output_of(self.roles.outputs[output])
    }

    fn accept(&mut self, state: &mut DynState) {
        self.asm.dofs.expand(&state.q, &mut self.q);
        self.asm.dofs.expand(&state.v, &mut self.v);
        self.asm.dofs.expand(&state.acc, &mut self.acc);
        let mut a = std::mem::take(&mut self.acc);
        let (mut q, mut v) = (std::mem::take(&mut self.qw), std::mem::take(&mut self.vw));
        q.copy_from_slice(&self.q);
        v.copy_from_slice(&self.v);
        self.prescribe(state.t, &mut q, &mut v, Some(&mut a));
        (self.acc, self.qw, self.vw) = (a, q, v);
        let before = self.history_outputs();
        let t_before = self.t;
        self.commit(state.t, false);
        let h = state.t - t_before;
        if h > 0.0 {
            let after = self.history_outputs();
            self.step_rates = Some(after.rate_since(&before, h));
        }
    }

    fn free_state(&self, q: &mut [f64], v: &mut [f64]) {
        self.asm.dofs.restrict(&self.q, q);
        self.asm.dofs.restrict(&self.v, v);
    }

    fn begin_communication_step(&mut self, t0: f64, _t1: f64) {
        self.t0_step = Some(t0);
    }

    /// Pulley angles, speeds and torques are smooth signals set at every communication step:
    /// the integrator keeps its accelerations.
    fn input_restarts_accelerations(&self, _input: usize) -> bool {
        false
    }

    /// Committed state, friction history of every contact point, pulley inputs and results,
    /// span tensions and the energy book.
    fn save(&self, w: &mut StateWriter) -> Result<(), String> {
        w.f64(self.t);
        w.f64s(&self.q);
        w.f64s(&self.v);
        self.contact.save(w);
        self.save_pulleys(w);
        w.f64s(&self.acc);
        w.bool(self.step_rates.is_some());
        if let Some(r) = &self.step_rates {
            r.save(w);
        }
        w.f64s(&self.tensions);
        w.u64(self.slipping_points as u64);
        self.energy.save(w);
        w.bool(self.t0_step.is_some());
        w.f64(self.t0_step.unwrap_or(0.0));
        // the reference length the pre-load settled on (a model built to restore has none)
        w.f64(self.element().length());
        if let Some(t) = &self.tensioner {
            t.contact.save(w);
            w.f64(t.belt_moment);
        }
        Ok(())
    }

    fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        let t = r.f64().map_err(e)?;
        r.f64s_into(&mut self.q).map_err(e)?;
        r.f64s_into(&mut self.v).map_err(e)?;
        self.contact.restore(r)?;
        self.restore_pulleys(r)?;
        r.f64s_into(&mut self.acc).map_err(e)?;
        self.step_rates = if r.bool().map_err(e)? {
            Some(StepRates::restore(r, self.io.len()).map_err(e)?)
        } else {
            None
        };
        r.f64s_into(&mut self.tensions).map_err(e)?;
        self.slipping_points = r.u64().map_err(e)? as usize;
        self.energy = EnergyBook::restore(r).map_err(e)?;
        let has_t0 = r.bool().map_err(e)?;
        let t0 = r.f64().map_err(e)?;
        let length = r.f64().map_err(e)?;
        if !(length > 0.0 && length.is_finite()) {
            return Err(format!(
                "belt element reference length {length} m in the state"
            ));
        }
        if length != self.element().length() {
            self.set_reference_length(length)?;
        }
        if let Some(tn) = self.tensioner.as_mut() {
            tn.contact.restore(r)?;
            tn.belt_moment = r.f64().map_err(e)?;
        }
        self.t0_step = has_t0.then_some(t0);
        self.t = t;
        Ok(())
    }
}

impl MechanicalSystem for BeltDrive {
    fn n_free(&self) -> usize {
        self.asm.dofs.n_free()
    }

    fn pattern(&self) -> &CscPattern {
        &self.asm.pattern
    }

    fn scales(&self) -> &[f64] {
        &self.scales
    }

    fn newton_scales(&self) -> &[f64] {
        &self.newton_scales
    }

    fn residual(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        load_factor: f64,
        r: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        let (mut qw, mut vw, mut aw) = (
            std::mem::take(&mut self.qw),
            std::mem::take(&mut self.vw),
            std::mem::take(&mut self.aw),
        );
        self.asm.dofs.expand(q, &mut qw);
        self.asm.dofs.expand(v, &mut vw);
        self.asm.dofs.expand(a, &mut aw);
        self.prescribe(t, &mut qw, &mut vw, Some(&mut aw));
        (self.qw, self.vw, self.aw) = (qw, vw, aw);
        self.evaluate(t, load_factor, jac)?;
        self.finish(r)
    }

    /// No exact average force exists for `ε = |r'| − 1` and the contact; the midpoint rule
    /// evaluates the residual at the midpoint configuration `½(q_a + q_b)` (then the
    /// stiffness part of the iteration matrix is ½ ∂Q/∂q): second-order accurate, but not
    /// exactly energy-conserving.
    fn midpoint_residual(
        &mut self,
        t_a: f64,
        t_b: f64,
        q_a: &[f64],
        q_b: &[f64],
        v: &[f64],
        a: &[f64],
        r: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        let mut qm = std::mem::take(&mut self.qmid);
        qm.clear();
        qm.extend(q_a.iter().zip(q_b).map(|(x, y)| 0.5 * (x + y)));
        let jac = jac.map(|(c, vals)| {
            (
                JacobianCoeffs {
                    stiffness: 0.5 * c.stiffness,
                    ..c
                },
                vals,
            )
        });
        let res = self.residual(0.5 * (t_a + t_b), &qm, v, a, 1.0, r, jac);
        self.qmid = qm;
        res
    }

    fn hold_for_statics(&mut self, held: bool) {
        self.held_angles = held.then(|| self.pulley_dof.iter().map(|&d| self.q[d]).collect());
    }

    /// Damped Newton on the planar belt drives (issue 12, session 25): on the serpentine drive
    /// tens of contact points at the arcs' ends change state in one full-Newton increment and
    /// the iteration cycled; backtracking broke it (120 elements, 1 s ramp: 0.021 → 0.055×
    /// real time with the kept substep, rejected steps 3757 → 58). The two-pulley drives
    /// are unchanged (no backtrack: the rise threshold is 5 %).
    fn damped_newton(&self) -> bool {
        true
    }

    /// The second iteration of a step with a fresh matrix while the first one's matrix mostly
    /// fails there (issue 12 item 2, session 30): on the serpentine drive (120 elements, 0.5 s
    /// ramp) the matrix of the transported belt failed in 78 % of the second iterations
    /// (10-30 contact points change between contact and no contact, stick and slip in the
    /// first increment); 26.5 → 19.8 iterations and 13.9 → 13.0 factorizations per
    /// communication step. The two-pulley drive's fails in 20 % and the rule stays off there.
    fn learns_second_iteration(&self) -> bool {
        true
    }

    /// Modified Newton keeps its matrix while the increments contract by 0.5 per iteration
    /// (issue 12 item 2, session 29). On the 120-element drive at 60 rad/s (1 ms) a rebuild
    /// (residual with the matrix 190 µs, factorization 98 µs) costs about 3.5 iterations with
    /// the kept one (residual 69 µs, solve 15 µs); the rebuilds at a rate of 0.25-0.5 were
    /// mostly followed by one more iteration anyway: 2.85 → 2.90 iterations and
    /// 1.64 → 1.51 factorizations per step (0.6: 2.91 / 1.48, no faster; the soft belt stays
    /// at 1.98 / 1.00). Results move within the Newton tolerance.
    fn modified_newton_rate(&self) -> f64 {
        0.5
    }

    /// Transport predictor of a closed cable belt (issue 12): in steady running the belt's
    /// shape is stationary in space while the material moves along it, so material point `X`
    /// at `t + h` is where `X + ΔX` was at `t`, with `ΔX = h (v·r')/|r'|²` (`r' = ∂r/∂X` the
    /// ANCF slope, `v` the node velocity). Each node's position and slope are predicted from
    /// the cubic Hermite interpolation of the belt at the start of the step at `X_i + ΔX_i`
    /// (across element boundaries round the closed loop, any distance), plus `h v_n`, the
    /// part of the node's velocity normal to the transport (`v − (v·r')/|r'|² r'`: transverse
    /// motion of a span). Pulley angles and the tensioner arm keep the integrator's predictor.
    /// Off for open belts and the seed-000 belt element (no slope coordinates).
    fn predict(&mut self, q0: &[f64], v0: &[f64], h: f64, q1: &mut [f64]) -> bool {
        if !self.transport_predictor || !self.closed || h <= 0.0 {
            return false;
        }
        let l = self.element().length();
        if self.element().transport_weights(0.0).is_none() || l <= 0.0 {
            return false;
        }
        let (mut qf, mut vf, mut pred) = (
            std::mem::take(&mut self.qw),
            std::mem::take(&mut self.vw),
            std::mem::take(&mut self.aw),
        );
        self.asm.dofs.expand(q0, &mut qf);
        self.asm.dofs.expand(v0, &mut vf);
        let (n, nn) = (self.n_el, self.n_nodes);
        let total = l * n as f64;
        for i in 0..nn {
            let k = i * NC;
            let slope = Vector2::new(qf[k + 2], qf[k + 3]);
            let vel = Vector2::new(vf[k], vf[k + 1]);
            let s2 = slope.norm_squared();
            if s2 <= 0.0 || !s2.is_finite() || !vel.x.is_finite() || !vel.y.is_finite() {
                pred[k..k + NC].copy_from_slice(&qf[k..k + NC]);
                continue;
            }
            let flux = vel.dot(&slope) / s2;
            let x = (i as f64 * l + h * flux).rem_euclid(total);
            let e = ((x / l).floor() as usize).min(n - 1);
            let Some((w, dw)) = self.element().transport_weights(x - e as f64 * l) else {
                pred[k..k + NC].copy_from_slice(&qf[k..k + NC]);
                continue;
            };
            let (a, b) = (e * NC, ((e + 1) % nn) * NC);
            let vecs = [a, a + 2, b, b + 2];
            let (mut r, mut rp) = (Vector2::zeros(), Vector2::zeros());
            for (j, &o) in vecs.iter().enumerate() {
                let p = Vector2::new(qf[o], qf[o + 1]);
                r += w[j] * p;
                rp += dw[j] * p;
            }
            let normal = vel - flux * slope;
            r += h * normal;
            pred[k..k + NC].copy_from_slice(&[r.x, r.y, rp.x, rp.y]);
        }
        let belt = nn * NC;
        for (kf, &i) in self.asm.dofs.free_to_full().iter().enumerate() {
            if i < belt {
                q1[kf] = pred[i];
            }
        }
        (self.qw, self.vw, self.aw) = (qf, vf, pred);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::GeneralizedAlpha;
    use crate::kinds::belt_drive::scene::PulleyInput;
    use crate::model::MechanicalSystem;
    use crate::scene::{ParamValues, Scene};
    use crate::solver::newton::Workspace;

    fn shipped_scene(name: &str) -> (Scene, ParamValues) {
        let text = std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{name}.toml")),
        )
        .unwrap();
        let scene = Scene::from_toml(&text).unwrap();
        let p = ParamValues::defaults(&scene.params);
        (scene, p)
    }

    /// Runs `steps` steps of h with the driver accelerating, returns the model and its state.
    fn running(steps: usize, h: f64) -> (BeltDrive, DynState) {
        running_scene("belt_drive", 24, 1, -20.0, 200.0, steps, h)
    }

    /// [`running`] for the shipped scene `name` with `n_el` elements, the input torque `load`
    /// [N m] on pulley `loaded` and the driver accelerating at `alpha` [rad/s²].
    fn running_scene(
        name: &str,
        n_el: i32,
        loaded: usize,
        load: f64,
        alpha: f64,
        steps: usize,
        h: f64,
    ) -> (BeltDrive, DynState) {
        let (scene, mut p) = shipped_scene(name);
        p.set(
            crate::kinds::belt_drive::scene::names::BELT_N_ELEMENTS,
            crate::variables::Value::Integer(n_el),
        );
        // the Lagrangian belt (the shipped serpentine is an ALE belt since session 38)
        p.set(
            crate::kinds::belt_drive::scene::names::BELT_FORMULATION,
            crate::variables::Value::Integer(1),
        );
        let mut m = BeltDrive::build(scene.tables().unwrap(), &p).unwrap();
        let mut cfg = SolverConfig::from_params(&p);
        // the state this test checks the Jacobian in was chosen with full Newton
        cfg.newton.policy = crate::solver::newton::NewtonPolicy::Full;
        // damped as in a simulation of the model
        cfg.newton.line_search = m.damped_newton();
        let mut ws = Workspace::new(&m, cfg.linear).unwrap();
        let n = m.n_free();
        let mut s0 = DynState::zeros(n, 0.0);
        m.free_state(&mut s0.q, &mut s0.v);
        let mut s1 = s0.clone();
        let ga = GeneralizedAlpha::from_rho_inf(0.8);
        m.set_pulley_input(loaded, PulleyInput::Torque, load);
        for i in 0..steps {
            let t = i as f64 * h;
            m.set_pulley_input(0, PulleyInput::Omega, alpha * t);
            m.begin_communication_step(t, t + h);
            ga.step(&mut m, &mut ws, &cfg.newton, &s0, h, &mut s1)
                .unwrap_or_else(|e| panic!("step {i}: {e}"));
            m.accept(&mut s1);
            std::mem::swap(&mut s0, &mut s1);
            m.set_pulley_input(0, PulleyInput::Angle, 0.5 * alpha * (t + h).powi(2));
        }
        (m, s0)
    }

    /// The iteration matrix of the whole model (elements, contact, pulleys) against central
    /// differences of the residual, in a running state with contact, stick and slip.
    #[test]
    fn model_jacobian_matches_finite_differences() {
        let (m, s) = running(60, 5e-4);
        check_model_jacobian(m, s);
    }

    /// The same for the serpentine drive: back-side idlers and the tensioner's arm angle,
    /// coupled to the belt through its idler's contact (the blocks belt ↔ ψ, idler ↔ ψ, ψ ↔ ψ).
    #[test]
    fn serpentine_jacobian_with_tensioner_matches_finite_differences() {
        // two steps: after the first the damped Newton (session 25) converges to a state
        // without sliding points (the undamped one had some); before the damping, full Newton
        // did not converge in the second step at 60 elements (session 23)
        let (m, s) = running_scene("serpentine", 60, 5, -6.0, 2000.0, 2, 5e-4);
        let t = m
            .tensioner
            .as_ref()
            .expect("the serpentine drive has a tensioner");
        assert!(
            (m.q[t.dof] - t.design).abs() > 1e-5 && m.v[t.dof].abs() > 1e-4,
            "the arm should move: {} {}",
            m.q[t.dof] - t.design,
            m.v[t.dof]
        );
        check_model_jacobian(m, s);
    }

    /// The transport predictor against the belt's path: a belt mounted on the loop (no
    /// pre-load: nodes on the pitch path, moved in by the contact penetration on the arcs)
    /// moving along it at speed `c` is predicted at the path point `c h` further on, across
    /// element boundaries and round the loop's start, 2.6 elements in one step. Reference: the
    /// loop geometry (`meshers::belt_loop`, tangent lines and arcs). The integrator's own
    /// predictor `q + h v` would put the nodes on the arcs off the path by the chord's sagitta.
    #[test]
    fn transport_predictor_moves_the_belt_along_its_path() {
        let (scene, p) = shipped_scene("belt_drive");
        let mut m = BeltDrive::build_to_restore(scene.tables().unwrap(), &p).unwrap();
        let half_t = 0.5 * m.spec.thickness;
        let circles: Vec<PitchCircle> = m
            .spec
            .pulleys
            .iter()
            .map(|p| PitchCircle {
                center: p.center,
                radius: p.radius + half_t,
            })
            .collect();
        let lp = Loop::with_sides(&circles, &[false, false]).unwrap();
        let n = m.n_free();
        let (mut q0, mut v0) = (vec![0.0; n], vec![0.0; n]);
        m.free_state(&mut q0, &mut v0);
        let (nn, l_mount) = (m.n_nodes, lp.length / m.n_nodes as f64);
        let (c, h) = (30.0, 2.6 * l_mount / 30.0);
        let mut full = vec![0.0; m.q.len()];
        m.asm.dofs.expand(&q0, &mut full);
        let mut vfull = vec![0.0; m.q.len()];
        for i in 0..nn {
            let t = Vector2::new(full[i * NC + 2], full[i * NC + 3]).normalize();
            vfull[i * NC] = c * t.x;
            vfull[i * NC + 1] = c * t.y;
        }
        m.asm.dofs.restrict(&vfull, &mut v0);
        let mut q1 = q0.clone();
        assert!(m.predict(&q0, &v0, h, &mut q1));
        let mut pred = full.clone();
        m.asm.dofs.expand(&q1, &mut pred);
        let stretch = Vector2::new(full[2], full[3]).norm();
        let (mut worst_r, mut worst_t): (f64, f64) = (0.0, 0.0);
        for i in 0..nn {
            let want = lp.at((i as f64 * l_mount + c * h).rem_euclid(lp.length));
            let r = Vector2::new(pred[i * NC], pred[i * NC + 1]);
            let slope = Vector2::new(pred[i * NC + 2], pred[i * NC + 3]);
            worst_r = worst_r.max((r - want.r).norm());
            worst_t = worst_t.max((slope / stretch - want.t).norm());
        }
        // the penetration on the arcs (T/(ρ k_n) = 2.4e-5 m) and the cubic interpolation of
        // an arc at 0.2 rad per element; its slope is off most where the curvature jumps
        // (arc to span: 3.9e-3 measured). Keeping the slope (the integrator's q + h v) would
        // be off by the arc's turn c h/ρ = 0.5 rad.
        println!("transport predictor: position {worst_r:.3e} m, slope {worst_t:.3e}");
        assert!(worst_r < 1e-4, "position off the path by {worst_r:.3e} m");
        assert!(
            worst_t < 1e-2,
            "slope off the path's tangent by {worst_t:.3e}"
        );
        // the pulley angles keep the integrator's predictor
        for &d in &m.pulley_dof {
            if let Some(k) = m.asm.dofs.free_to_full().iter().position(|&f| f == d) {
                assert_eq!(q1[k], q0[k]);
            }
        }
    }

    fn check_model_jacobian(mut m: BeltDrive, s: DynState) {
        assert!(
            m.slipping_points() > 0,
            "the test state should have sliding points"
        );
        let n = m.n_free();
        let t = s.t;
        let pat = m.pattern().clone();
        for (stiff, damp) in [(1.0, 0.0), (0.0, 1.0)] {
            let coeffs = JacobianCoeffs {
                mass: 0.0,
                damping: damp,
                stiffness: stiff,
            };
            let mut r = vec![0.0; n];
            let mut vals = vec![0.0; pat.nnz()];
            m.residual(
                t,
                &s.q,
                &s.v,
                &s.acc,
                1.0,
                &mut r,
                Some((coeffs, &mut vals)),
            )
            .unwrap();
            let mut worst: f64 = 0.0;
            let mut scale: f64 = 0.0;
            let mut at = (0, 0, 0.0, 0.0);
            for j in 0..n {
                // 1e-9 m: in the serpentine state contact points lie within 1e-8 m of a
                // stick/slip or contact threshold (a 1e-8 m step put 0.3 % into the diagonal of
                // free row 53, a 1e-7 m step a sign change into (108, 109)): the residual has
                // kinks there, and a smaller step stays on one side of them
                let hstep = if stiff > 0.0 { 1e-9 } else { 1e-6 };
                let (mut xp, mut xm) = if stiff > 0.0 {
                    (s.q.clone(), s.q.clone())
                } else {
                    (s.v.clone(), s.v.clone())
                };
                xp[j] += hstep;
                xm[j] -= hstep;
                let (mut rp, mut rm) = (vec![0.0; n], vec![0.0; n]);
                if stiff > 0.0 {
                    m.residual(t, &xp, &s.v, &s.acc, 1.0, &mut rp, None)
                        .unwrap();
                    m.residual(t, &xm, &s.v, &s.acc, 1.0, &mut rm, None)
                        .unwrap();
                } else {
                    m.residual(t, &s.q, &xp, &s.acc, 1.0, &mut rp, None)
                        .unwrap();
                    m.residual(t, &s.q, &xm, &s.acc, 1.0, &mut rm, None)
                        .unwrap();
                }
                for i in 0..n {
                    let fd = (rp[i] - rm[i]) / (2.0 * hstep);
                    let an = pat.position(i, j).map_or(0.0, |p| vals[p]);
                    if (fd - an).abs() > worst {
                        at = (i, j, fd, an);
                    }
                    worst = worst.max((fd - an).abs());
                    scale = scale.max(an.abs());
                }
            }
            assert!(
                worst <= 1e-4 * scale,
                "stiffness {stiff} damping {damp}: worst {worst:.3e} of {scale:.3e} at (free row, column, difference, analytic) {at:?} of {n}"
            );
        }
    }
}
