//! Belt drive: a belt of ANCF cable (or seed-000) elements in frictional contact with pulleys
//! that are driven (prescribed angle and speed, belt torque out) or free (rigid bodies with
//! inertia and bearing damping inside the model, driven by an input torque).
//!
//! Coordinates: the belt's nodal coordinates (4 per node) followed by one angle per pulley;
//! driven pulleys' angles are constrained (prescribed), free pulleys' are unknowns coupled to
//! every belt coordinate through the contact (the iteration matrix is a ring with a border,
//! factorized by the bordered banded LU of [`crate::linalg::bordered`]).
//!
//! Contact: [`crate::contact::circle_friction`] at `contact.points_per_element` equally spaced
//! material points per element. Equations of motion:
//! `M q̈ + Q_int(q, q̇) − Σ Q_contact(q, q̇, θ, ω) − Q_g = 0` for the belt and
//! `J θ̈ + c θ̇ − τ_in − Σ τ_contact = 0` for each free pulley.

use crate::assembly::{Assembly, Connectivity, DofMap, ElementSet, Eval, check_finite};
use crate::contact::circle_friction::{self, polar_angle};
use crate::contact::{Circle, ContactLaw, PointHistory, PointState};
use crate::elements::Element;
use crate::elements::ancf_cable2d::{self, AncfCable2d, CableRule, CableSection, ElemVec};
use crate::elements::ancf_shear2d::{AncfShear2d, Section, Shear2dElement, ShearRule};
use crate::elements::material::{PlaneElasticity, StrainEnergy};
use crate::integrators::DynState;
use crate::kinds::KindIo;
use crate::kinds::belt_drive::scene::{BeltOutput, Input, Output, PulleyInput};
use crate::kinds::belt_drive::{BeltDriveScene, PulleyMode};
use crate::kinds::energy::EnergyKind;
use crate::linalg::CscPattern;
use crate::meshers::belt_loop::{Loop, PitchCircle};
use crate::model::inputs::{InputSignal, prescribed};
use crate::model::rates;
use crate::model::{JacobianCoeffs, MechanicalSystem, Model, ModelError};
use crate::scene::params::{
    ParamValues,
    names::{GRAVITY_X, GRAVITY_Y},
};
use crate::snapshot::{StateReader, StateWriter};
use crate::solver::simulation::SolverConfig;
use nalgebra::{SMatrix, Vector2, Vector3};
use std::sync::Arc;

/// Coordinates per belt node.
const NC: usize = 4;

/// Which element the belt is made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BeltElementKind {
    /// Gradient-deficient ANCF cable with the given integration rule.
    Cable(CableRule),
    /// Seed-000 shear-deformable ANCF beam with an equivalent rectangle of height
    /// `h = √(12 EI/EA)`, unit width, `E = EA/h`, ν = 0.3, 1×2 shear rule.
    Shear,
}

/// How a pulley moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PulleyKind {
    /// Angle and speed prescribed by inputs.
    Driven,
    /// Rigid body: moment of inertia [kg m²] and bearing damping [N m s/rad].
    Free {
        /// Moment of inertia [kg m²].
        inertia: f64,
        /// Bearing damping [N m s/rad].
        damping: f64,
    },
}

/// A pulley of the drive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PulleyDef {
    /// Centre [m].
    pub center: Vector2<f64>,
    /// Radius [m] (the belt's inner face rests on it).
    pub radius: f64,
    /// Driven or free.
    pub kind: PulleyKind,
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
/// `k_t = k_n/100` (a stiffer bristle makes Newton's method cycle between stick and slip at
/// 1 ms steps; the bristle only sets the micro-slip before sliding, μp/k_t), `d_t = d_n √(k_t/k_n)`. `thickness` is floored at 1 % of the smallest radius. The
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
    let k_t = if given.2 > 0.0 { given.2 } else { 0.01 * k_n };
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
trait BeltElement: Element<8> {
    /// Reference length [m].
    fn length(&self) -> f64;

    /// Weights of the four nodal 2-vectors in the centre-line position at `x` [m].
    fn centerline(&self, x: f64) -> [f64; 4];

    /// Axial force at the middle of the element [N] for a belt of axial stiffness `ea` [N].
    fn axial_force_mid(&self, q: &ElemVec, ea: f64) -> f64;
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

#[derive(Clone, Copy, Debug, Default)]
struct PulleyIo {
    /// Prescribed angle [rad], speed [rad/s] (driven) and input torque [N m] (free) as
    /// signals of time (`fmi2SetRealInputDerivatives`).
    angle_in: InputSignal,
    omega_in: InputSignal,
    torque_in: InputSignal,
    // results of the committed state
    torque: f64,
    force: Vector2<f64>,
}

/// Outputs that depend on the contact history (pulley torques and forces, span tensions,
/// contact energy, dissipated energy), or their rates over the last internal step.
#[derive(Clone, Debug, Default, PartialEq)]
struct StepRates {
    /// Per pulley: torque [N m], force x, y [N] (or their rates).
    pulleys: Vec<[f64; 3]>,
    /// Larger and smaller span tension [N].
    tight: f64,
    slack: f64,
    /// Penalty energy of the contact [J].
    contact_energy: f64,
    /// Energy dissipated since the start [J].
    dissipated: f64,
}

impl StepRates {
    /// `(self − before)/h`.
    fn rate_since(&self, before: &Self, h: f64) -> Self {
        let d = |a: f64, b: f64| (a - b) / h;
        Self {
            pulleys: self
                .pulleys
                .iter()
                .zip(&before.pulleys)
                .map(|(a, b)| [d(a[0], b[0]), d(a[1], b[1]), d(a[2], b[2])])
                .collect(),
            tight: d(self.tight, before.tight),
            slack: d(self.slack, before.slack),
            contact_energy: d(self.contact_energy, before.contact_energy),
            dissipated: d(self.dissipated, before.dissipated),
        }
    }

    fn save(&self, w: &mut StateWriter) {
        w.u64(self.pulleys.len() as u64);
        for p in &self.pulleys {
            w.f64s(p);
        }
        for x in [self.tight, self.slack, self.contact_energy, self.dissipated] {
            w.f64(x);
        }
    }

    fn restore(
        r: &mut StateReader,
        n_pulleys: usize,
    ) -> Result<Self, crate::snapshot::SnapshotError> {
        let n = r.u64()? as usize;
        let mut pulleys = vec![[0.0; 3]; n.min(n_pulleys)];
        for p in pulleys.iter_mut() {
            r.f64s_into(p)?;
        }
        Ok(Self {
            pulleys,
            tight: r.f64()?,
            slack: r.f64()?,
            contact_energy: r.f64()?,
            dissipated: r.f64()?,
        })
    }
}

#[derive(Clone, Copy, Debug, Default)]
struct EnergyBook {
    input_work: f64,
    dissipated: f64,
    p_in: f64,
    p_diss: f64,
    contact_energy: f64,
}

/// What the static pre-load did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PreloadReport {
    /// Static solves (one per reference-length correction).
    pub solves: usize,
    /// Newton iterations in total.
    pub iterations: usize,
    /// Span tensions after the last solve [N].
    pub span_tensions: Vec<f64>,
}

/// The belt-drive model.
#[derive(Clone, Debug)]
pub struct BeltDrive {
    spec: BeltSpec,
    /// What each input and output of the scene means, by index (empty for a model built
    /// from a [`BeltSpec`] without a scene: drive it with the typed methods).
    roles: KindIo<Input, Output>,
    /// The belt's elements (one shared element: all have the same reference length).
    set: ElementSet<Arc<dyn BeltElement>, 8>,
    n_el: usize,
    n_nodes: usize,
    closed: bool,
    asm: Assembly,
    pulley_dof: Vec<usize>,
    circles: Vec<Circle>,
    cp: Vec<[f64; 4]>,
    cp_w: f64,
    hist: Vec<PointHistory>,
    /// Element coordinates plus the angle of pulley `k`, row `e · n_pulleys + k`: the contact
    /// blocks.
    contact_blocks: Connectivity<9>,
    gravity_full: Vec<f64>,
    end_loads: [Vector2<f64>; 2],
    span_mid: Vec<Vector2<f64>>,
    scales: Vec<f64>,
    io: Vec<PulleyIo>,
    t0_step: Option<f64>,
    // committed state
    t: f64,
    q: Vec<f64>,
    v: Vec<f64>,
    /// Accelerations of the committed state (output rates).
    acc: Vec<f64>,
    /// Rates of the history-dependent outputs over the last internal step.
    step_rates: Option<StepRates>,
    tensions: Vec<f64>,
    slipping_points: usize,
    energy: EnergyBook,
    preload: PreloadReport,
    /// Free pulleys held at these angles by a stiff bearing spring during static solves (the
    /// pre-load, a static initialization): otherwise belt and free pulleys turning together
    /// are a mechanism.
    held_angles: Option<Vec<f64>>,
    // work buffers
    qw: Vec<f64>,
    vw: Vec<f64>,
    aw: Vec<f64>,
    fw: Vec<f64>,
    qmid: Vec<f64>,
}

impl BeltDrive {
    /// Builds the drive; a closed belt is brought into static equilibrium with the requested
    /// span tension (the reference length is corrected until the mean span tension matches
    /// within 0.1 %).
    pub fn new(spec: BeltSpec) -> Result<Self, String> {
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
                let lp = Loop::new(
                    &circles
                        .iter()
                        .map(|c| PitchCircle {
                            center: c.center,
                            radius: c.radius,
                        })
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
        if n_el < 1 {
            return Err("the belt needs at least one element".into());
        }
        let mounted = match &lp {
            Some(lp) => lp.length / n_el as f64,
            None => (nodes[1].0 - nodes[0].0).norm(),
        };
        let l_ref = mounted / stretch;
        let element = belt_element(spec.element, s, l_ref)?;

        // Coordinates: belt nodes, then one angle per pulley.
        let n_full = n_nodes * NC + np;
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
        let asm = Assembly::new(
            DofMap::new(&constrained),
            &[(8, connectivity.as_flattened())],
            &extra,
        );
        let blocks: Vec<[usize; 9]> = connectivity
            .iter()
            .flat_map(|d| {
                pulley_dof
                    .iter()
                    .map(|&pd| std::array::from_fn(|i| if i < 8 { d[i] } else { pd }))
            })
            .collect();
        let contact_blocks = Connectivity::new(blocks, &asm);
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
            .collect();
        let n_cp = spec.points_per_element.max(1);
        let mut me = Self {
            roles: KindIo::default(),
            set,
            n_el,
            n_nodes,
            closed,
            pulley_dof,
            circles,
            cp: vec![],
            cp_w: l_ref / n_cp as f64,
            hist: vec![PointHistory::default(); n_el * n_cp * np],
            contact_blocks,
            gravity_full: vec![0.0; n_full],
            end_loads: [Vector2::zeros(); 2],
            span_mid,
            scales,
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
            asm,
            spec,
        };
        me.set_reference_length(l_ref)?;
        me.commit(0.0, true);
        if let BeltPath::Closed { pretension, .. } = me.spec.path {
            me.preload(pretension)?;
        }
        Ok(me)
    }

    /// Builds the model of a belt-drive scene with validated parameter values.
    pub fn build(scene: &BeltDriveScene, p: &ParamValues) -> Result<Self, String> {
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
        let mut drive = Self::new(BeltSpec {
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
            statics: (cfg.newton, cfg.linear, cfg.load_steps),
        })?;
        for (i, s) in scene.pulley.iter().enumerate() {
            drive.io[i].omega_in = InputSignal::constant(s.omega);
            drive.io[i].torque_in = InputSignal::constant(s.torque_in);
        }
        drive.roles = io(scene);
        Ok(drive)
    }

    /// Rebuilds the element, mass, gravity and contact points for reference length `l`.
    fn set_reference_length(&mut self, l: f64) -> Result<(), String> {
        self.set.set_elements(vec![belt_element(
            self.spec.element,
            &self.spec.section,
            l,
        )?]);
        let n_cp = self.spec.points_per_element.max(1);
        self.cp = (0..n_cp)
            .map(|i| {
                self.element()
                    .centerline((i as f64 + 0.5) / n_cp as f64 * l)
            })
            .collect();
        self.cp_w = l / n_cp as f64;
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
    fn element(&self) -> &dyn BeltElement {
        &**self.set.element(0)
    }

    /// Static pre-load: solve, compare the mean span tension with `pretension`, correct the
    /// reference length, repeat (at most 4 times). Free pulleys are held at their angles
    /// while the belt is mounted (see [`MechanicalSystem::hold_for_statics`]).
    fn preload(&mut self, pretension: f64) -> Result<(), String> {
        use crate::solver::newton::Workspace;
        let (settings, kind, load_steps) = self.spec.statics;
        let mut ws = Workspace::new(&*self, kind).map_err(|e| e.to_string())?;
        let n = self.n_free();
        let (mut qf, mut vf) = (vec![0.0; n], vec![0.0; n]);
        for round in 0..5 {
            self.free_state(&mut qf, &mut vf);
            let st = crate::solver::statics::solve(self, &mut ws, &mut qf, &settings, load_steps)
                .map_err(|e| {
                    let s = &self.spec.section;
                    format!(
                        "static pre-load of the belt (belt.EA = {} N, belt.EI = {} N.m2, belt.mass_per_length = {} kg/m, belt.damping_axial = {} N.s, belt.damping_bending = {} N.m2.s, belt.pretension = {pretension} N, belt.thickness = {} m, contact.mu = {}, contact.stiffness = {} N/m2, with the pulleys' radius and center; solver.newton_tolerance = {}, solver.max_iterations = {}): {e}",
                        s.ea, s.ei, s.mass_per_length, s.damping_axial, s.damping_bending, self.spec.thickness, self.spec.contact.mu, self.spec.contact.k_n, settings.tolerance, settings.max_iterations
                    )
                })?;
            self.preload.solves += 1;
            self.preload.iterations += st.newton.iterations;
            self.asm.dofs.expand(&qf, &mut self.q);
            let t = self.t;
            self.commit(t, false);
            let mean = self.tensions.iter().sum::<f64>() / self.tensions.len().max(1) as f64;
            self.preload.span_tensions = self.tensions.clone();
            if (mean - pretension).abs() <= 1e-3 * pretension || round == 4 {
                break;
            }
            let ea = self.spec.section.ea;
            let l = self.element().length() * (1.0 + mean / ea) / (1.0 + pretension / ea);
            self.set_reference_length(l)?;
        }
        Ok(())
    }

    /// Report of the static pre-load.
    pub fn preload_report(&self) -> &PreloadReport {
        &self.preload
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

    /// Pitch radius of pulley `k` [m].
    pub fn pitch_radius(&self, k: usize) -> f64 {
        self.circles[k].radius
    }

    /// Prescribed angle, speed and angular acceleration of a driven pulley at time `t`: the
    /// angle input's polynomial if it has derivatives, else the angle advanced with the speed
    /// input ([`prescribed`]).
    fn driven(&self, k: usize, t: f64) -> (f64, f64, f64) {
        let io = &self.io[k];
        prescribed(&io.angle_in, &io.omega_in, t)
    }

    /// Sets the driven pulleys' angles and speeds into full vectors.
    fn prescribe(&self, t: f64, q: &mut [f64], v: &mut [f64], a: Option<&mut [f64]>) {
        let mut a = a;
        for (k, p) in self.spec.pulleys.iter().enumerate() {
            if p.kind == PulleyKind::Driven {
                let (th, om, al) = self.driven(k, t);
                q[self.pulley_dof[k]] = th;
                v[self.pulley_dof[k]] = om;
                if let Some(a) = a.as_deref_mut() {
                    a[self.pulley_dof[k]] = al;
                }
            }
        }
    }

    #[inline]
    fn point_state(&self, e: usize, i: usize, k: usize, q: &[f64], v: &[f64]) -> PointState {
        let d = self.set.element_dofs(e);
        let s = &self.cp[i];
        let (mut r, mut vel) = (Vector2::zeros(), Vector2::zeros());
        for a in 0..4 {
            r.x += s[a] * q[d[2 * a]];
            r.y += s[a] * q[d[2 * a + 1]];
            vel.x += s[a] * v[d[2 * a]];
            vel.y += s[a] * v[d[2 * a + 1]];
        }
        let pd = self.pulley_dof[k];
        PointState {
            r,
            v: vel,
            theta: q[pd],
            omega: v[pd],
        }
    }

    /// Whether element `e` can touch pulley `k` (node distances minus half the chord).
    #[inline]
    fn near(&self, e: usize, k: usize, q: &[f64]) -> bool {
        let d = self.set.element_dofs(e);
        let ri = Vector2::new(q[d[0]], q[d[1]]);
        let rj = Vector2::new(q[d[4]], q[d[5]]);
        let c = &self.circles[k];
        let chord = (rj - ri).norm();
        let dist = (ri - c.center).norm().min((rj - c.center).norm());
        dist - 0.55 * chord - 1e-3 * c.radius < c.radius
    }

    /// Residual terms into `self.fw` from `self.qw`, `self.vw`, `self.aw`, and the iteration
    /// matrix (stiffness part scaled by `k_scale`, for the midpoint rule).
    fn evaluate(
        &mut self,
        t: f64,
        load_factor: f64,
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        let np = self.circles.len();
        let n_cp = self.cp.len();
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
        // pulleys
        for (k, p) in self.spec.pulleys.iter().enumerate() {
            if let PulleyKind::Free { inertia, damping } = p.kind {
                let pd = self.pulley_dof[k];
                f[pd] += inertia * self.aw[pd] + damping * self.vw[pd] - self.io[k].torque_in.at(t);
                // bearing spring of a held pulley while the belt is mounted [N m/rad]
                let k_hold = match &self.held_angles {
                    Some(held) => {
                        let k_hold = 1e3 * self.spec.section.ea * p.radius * p.radius;
                        f[pd] += k_hold * (self.qw[pd] - held[k]);
                        k_hold
                    }
                    None => 0.0,
                };
                if let Some((c, vals)) = jac.as_mut() {
                    let m = c.mass * inertia + c.damping * damping + c.stiffness * k_hold;
                    self.asm.add_entry(pd, pd, m, vals);
                }
            }
        }
        // contact
        let mut blk = SMatrix::<f64, 9, 9>::zeros();
        for e in 0..self.n_el {
            for k in 0..np {
                if !self.near(e, k, &self.qw) {
                    continue;
                }
                let mut any = false;
                blk.fill(0.0);
                let d = *self.set.element_dofs(e);
                for i in 0..n_cp {
                    let st = self.point_state(e, i, k, &self.qw, &self.vw);
                    let h = &self.hist[(e * n_cp + i) * np + k];
                    let Some(res) = circle_friction::evaluate(
                        &self.spec.contact,
                        &self.circles[k],
                        self.cp_w,
                        &st,
                        h,
                    ) else {
                        continue;
                    };
                    any = true;
                    let s = &self.cp[i];
                    for a in 0..4 {
                        f[d[2 * a]] -= s[a] * res.force.x;
                        f[d[2 * a + 1]] -= s[a] * res.force.y;
                    }
                    f[self.pulley_dof[k]] -= res.torque;
                    if let Some((c, _)) = jac.as_ref() {
                        let m = c.stiffness * res.k + c.damping * res.c;
                        // T maps (element coords, θ) to (r_x, r_y, θ); block −Tᵀ m T
                        for a in 0..4 {
                            for b in 0..4 {
                                let ss = s[a] * s[b];
                                for i in 0..2 {
                                    for j in 0..2 {
                                        blk[(2 * a + i, 2 * b + j)] -= ss * m[(i, j)];
                                    }
                                }
                            }
                            for i in 0..2 {
                                blk[(2 * a + i, 8)] -= s[a] * m[(i, 2)];
                                blk[(8, 2 * a + i)] -= s[a] * m[(2, i)];
                            }
                        }
                        blk[(8, 8)] -= m[(2, 2)];
                    }
                }
                if any && let Some((_, vals)) = jac.as_mut() {
                    self.contact_blocks.add_matrix(e * np + k, &blk, 1.0, vals);
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
    fn commit(&mut self, t: f64, initial: bool) {
        let np = self.circles.len();
        let n_cp = self.cp.len();
        let (mut q, mut v) = (std::mem::take(&mut self.q), std::mem::take(&mut self.v));
        self.prescribe(t, &mut q, &mut v, None);
        for io in self.io.iter_mut() {
            io.torque = 0.0;
            io.force = Vector2::zeros();
        }
        let mut slipping = 0;
        let (mut contact_energy, mut contact_diss, mut friction_work) = (0.0, 0.0, 0.0);
        for e in 0..self.n_el {
            for k in 0..np {
                let near = self.near(e, k, &q);
                for i in 0..n_cp {
                    let idx = (e * n_cp + i) * np + k;
                    let st = self.point_state(e, i, k, &q, &v);
                    let h = self.hist[idx];
                    let res = if near && !initial {
                        circle_friction::evaluate(
                            &self.spec.contact,
                            &self.circles[k],
                            self.cp_w,
                            &st,
                            &h,
                        )
                    } else {
                        None
                    };
                    let (z, f) = match res {
                        Some(r) => {
                            self.io[k].torque += r.torque;
                            self.io[k].force -= r.force;
                            slipping += r.slipping as usize;
                            contact_energy += r.normal_energy;
                            contact_diss += r.dissipation;
                            // work against friction over the step (trapezoidal in the slip)
                            friction_work +=
                                self.cp_w * 0.5 * (h.f + r.friction) * r.slip_increment;
                            (r.z, r.friction)
                        }
                        None => (0.0, 0.0),
                    };
                    self.hist[idx] = PointHistory {
                        phi: polar_angle(&self.circles[k], st.r),
                        theta: st.theta,
                        z,
                        f,
                    };
                }
            }
        }
        self.slipping_points = slipping;
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
        if self.spec.track_energy {
            let mut p_in = 0.0;
            let mut p_diss = contact_diss;
            for (k, p) in self.spec.pulleys.iter().enumerate() {
                let om = self.v[self.pulley_dof[k]];
                match p.kind {
                    PulleyKind::Driven => p_in -= self.io[k].torque * om,
                    PulleyKind::Free { damping, .. } => {
                        p_in += self.io[k].torque_in.at(t) * om;
                        p_diss += damping * om * om;
                    }
                }
            }
            if !self.closed {
                let last = (self.n_nodes - 1) * NC;
                p_in += self.end_loads[0].dot(&Vector2::new(self.v[0], self.v[1]))
                    + self.end_loads[1].dot(&Vector2::new(self.v[last], self.v[last + 1]));
            }
            self.set.for_each_state(&self.q, &self.v, None, |_, el, s| {
                p_diss += el.damping_power_at(s);
            });
            let h = t - self.t;
            if !initial && h > 0.0 {
                self.energy.input_work += 0.5 * h * (self.energy.p_in + p_in);
                self.energy.dissipated += 0.5 * h * (self.energy.p_diss + p_diss) + friction_work;
            }
            self.energy.p_in = p_in;
            self.energy.p_diss = p_diss;
        }
        self.energy.contact_energy = contact_energy;
        self.t = t;
    }

    /// Kinetic energy of belt and free pulleys [J] (committed state).
    pub fn kinetic_energy(&self) -> f64 {
        self.kinetic_energy_of(&self.v)
    }

    /// Kinetic energy [J] at full velocities `v`.
    fn kinetic_energy_of(&self, v: &[f64]) -> f64 {
        let mut t = 0.0;
        self.set.for_each_state(&self.q, v, None, |_, el, s| {
            t += el.kinetic_energy_at(s);
        });
        for (k, p) in self.spec.pulleys.iter().enumerate() {
            if let PulleyKind::Free { inertia, .. } = p.kind {
                t += 0.5 * inertia * v[self.pulley_dof[k]].powi(2);
            }
        }
        t
    }

    /// Strain energy of the belt plus the penalty energy of the contact [J].
    pub fn strain_energy(&self) -> f64 {
        self.energy.contact_energy + self.belt_strain_energy_of(&self.q)
    }

    /// Strain energy of the belt elements [J] at full coordinates `q`.
    fn belt_strain_energy_of(&self, q: &[f64]) -> f64 {
        self.set.strain_energy(q, None)
    }

    /// Gravity potential `−Q_gᵀ q` [J].
    pub fn potential_energy(&self) -> f64 {
        self.potential_energy_of(&self.q)
    }

    fn potential_energy_of(&self, q: &[f64]) -> f64 {
        -self
            .gravity_full
            .iter()
            .zip(q)
            .map(|(g, q)| g * q)
            .sum::<f64>()
    }

    /// Work done by drives, input torques and end loads since the start [J].
    pub fn input_work(&self) -> f64 {
        self.energy.input_work
    }

    /// Energy dissipated since the start [J].
    pub fn dissipated(&self) -> f64 {
        self.energy.dissipated
    }

    /// Torque of the belt on pulley `k` [N m] (committed state).
    pub fn pulley_torque(&self, k: usize) -> f64 {
        self.io[k].torque
    }

    /// Force of the belt on pulley `k` [N].
    pub fn pulley_force(&self, k: usize) -> Vector2<f64> {
        self.io[k].force
    }

    /// Angle and speed of pulley `k` (committed state).
    pub fn pulley_motion(&self, k: usize) -> (f64, f64) {
        (self.q[self.pulley_dof[k]], self.v[self.pulley_dof[k]])
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

    /// Sets a pulley input (the typed form of `Model::set_input`).
    pub fn set_pulley_input(&mut self, pulley: usize, quantity: PulleyInput, value: f64) {
        if quantity == PulleyInput::Angle
            && self.t0_step.is_none()
            && self.spec.pulleys[pulley].kind == PulleyKind::Driven
            && value.is_finite()
        {
            let pd = self.pulley_dof[pulley];
            let turn = value - self.q[pd];
            let np = self.circles.len();
            for h in self.hist.iter_mut().skip(pulley).step_by(np) {
                h.theta += turn;
            }
            self.q[pd] = value;
        }
        let t = self.t;
        self.signal(pulley, quantity).set(value, t);
    }

    /// `1 − ω_last ρ_last / (ω_1 ρ_1)` at full velocities `v`.
    fn slip_of(&self, v: &[f64]) -> f64 {
        let last = self.circles.len() - 1;
        let v1 = v[self.pulley_dof[0]] * self.circles[0].radius;
        let vn = v[self.pulley_dof[last]] * self.circles[last].radius;
        if v1.abs() > 1e-12 { 1.0 - vn / v1 } else { 0.0 }
    }

    /// The signal of a pulley input.
    fn signal(&mut self, pulley: usize, quantity: PulleyInput) -> &mut InputSignal {
        let io = &mut self.io[pulley];
        match quantity {
            PulleyInput::Angle => &mut io.angle_in,
            PulleyInput::Omega => &mut io.omega_in,
            PulleyInput::Torque => &mut io.torque_in,
        }
    }

    /// The history-dependent outputs of the committed state.
    fn history_outputs(&self) -> StepRates {
        let (tight, slack) = if self.tensions.is_empty() {
            (0.0, 0.0)
        } else {
            (
                self.output_of(Output::Belt(BeltOutput::TensionTight)),
                self.output_of(Output::Belt(BeltOutput::TensionSlack)),
            )
        };
        StepRates {
            pulleys: self
                .io
                .iter()
                .map(|io| [io.torque, io.force.x, io.force.y])
                .collect(),
            tight,
            slack,
            contact_energy: self.energy.contact_energy,
            dissipated: self.energy.dissipated,
        }
    }

    /// Time derivative of an output of the committed state. Analytic: pulley angles and
    /// speeds (`ω`, `α`), belt points (interpolated velocities), the input work (the input
    /// power at the committed state). Along the motion ([`rates::along_motion`]): belt speed,
    /// slip, kinetic and potential energy, the belt's strain energy. Over the last internal
    /// step (backward difference, first order): pulley torques and forces, span tensions, the
    /// contact part of the strain energy and the dissipated energy, which depend on the
    /// friction history; `None` before the first step.
    fn output_rate(&self, kind: Output) -> Option<f64> {
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
        w.u64(self.hist.len() as u64);
        for h in &self.hist {
            for x in [h.phi, h.theta, h.z, h.f] {
                w.f64(x);
            }
        }
        w.u64(self.io.len() as u64);
        for io in &self.io {
            for sig in [&io.angle_in, &io.omega_in, &io.torque_in] {
                sig.save(w);
            }
            for x in [io.torque, io.force.x, io.force.y] {
                w.f64(x);
            }
        }
        w.f64s(&self.acc);
        w.bool(self.step_rates.is_some());
        if let Some(r) = &self.step_rates {
            r.save(w);
        }
        w.f64s(&self.tensions);
        w.u64(self.slipping_points as u64);
        let e = &self.energy;
        for x in [
            e.input_work,
            e.dissipated,
            e.p_in,
            e.p_diss,
            e.contact_energy,
        ] {
            w.f64(x);
        }
        w.bool(self.t0_step.is_some());
        w.f64(self.t0_step.unwrap_or(0.0));
        Ok(())
    }

    fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        let t = r.f64().map_err(e)?;
        r.f64s_into(&mut self.q).map_err(e)?;
        r.f64s_into(&mut self.v).map_err(e)?;
        if r.u64().map_err(e)? as usize != self.hist.len() {
            return Err("contact history of another mesh".into());
        }
        for h in self.hist.iter_mut() {
            *h = PointHistory {
                phi: r.f64().map_err(e)?,
                theta: r.f64().map_err(e)?,
                z: r.f64().map_err(e)?,
                f: r.f64().map_err(e)?,
            };
        }
        if r.u64().map_err(e)? as usize != self.io.len() {
            return Err("pulleys of another drive".into());
        }
        for io in self.io.iter_mut() {
            io.angle_in = InputSignal::restore(r).map_err(e)?;
            io.omega_in = InputSignal::restore(r).map_err(e)?;
            io.torque_in = InputSignal::restore(r).map_err(e)?;
            io.torque = r.f64().map_err(e)?;
            io.force = Vector2::new(r.f64().map_err(e)?, r.f64().map_err(e)?);
        }
        r.f64s_into(&mut self.acc).map_err(e)?;
        self.step_rates = if r.bool().map_err(e)? {
            Some(StepRates::restore(r, self.io.len()).map_err(e)?)
        } else {
            None
        };
        r.f64s_into(&mut self.tensions).map_err(e)?;
        self.slipping_points = r.u64().map_err(e)? as usize;
        self.energy = EnergyBook {
            input_work: r.f64().map_err(e)?,
            dissipated: r.f64().map_err(e)?,
            p_in: r.f64().map_err(e)?,
            p_diss: r.f64().map_err(e)?,
            contact_energy: r.f64().map_err(e)?,
        };
        let has_t0 = r.bool().map_err(e)?;
        let t0 = r.f64().map_err(e)?;
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::GeneralizedAlpha;
    use crate::model::MechanicalSystem;
    use crate::scene::{ParamValues, Scene};
    use crate::solver::newton::Workspace;

    fn shipped() -> (Scene, ParamValues) {
        let text = std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/belt_drive.toml"),
        )
        .unwrap();
        let scene = Scene::from_toml(&text).unwrap();
        let p = ParamValues::defaults(&scene.params);
        (scene, p)
    }

    /// Runs `steps` steps of h with the driver accelerating, returns the model and its state.
    fn running(steps: usize, h: f64) -> (BeltDrive, DynState) {
        let (scene, mut p) = shipped();
        p.set(
            crate::kinds::belt_drive::scene::names::BELT_N_ELEMENTS,
            crate::variables::Value::Integer(24),
        );
        let mut m = BeltDrive::build(scene.tables().unwrap(), &p).unwrap();
        let mut cfg = SolverConfig::from_params(&p);
        // the state this test checks the Jacobian in was chosen with full Newton
        cfg.newton.policy = crate::solver::newton::NewtonPolicy::Full;
        let mut ws = Workspace::new(&m, cfg.linear).unwrap();
        let n = m.n_free();
        let mut s0 = DynState::zeros(n, 0.0);
        m.free_state(&mut s0.q, &mut s0.v);
        let mut s1 = s0.clone();
        let ga = GeneralizedAlpha::from_rho_inf(0.8);
        m.set_pulley_input(1, PulleyInput::Torque, -20.0);
        for i in 0..steps {
            let t = i as f64 * h;
            m.set_pulley_input(0, PulleyInput::Omega, 200.0 * t);
            m.begin_communication_step(t, t + h);
            ga.step(&mut m, &mut ws, &cfg.newton, &s0, h, &mut s1)
                .unwrap_or_else(|e| panic!("step {i}: {e}"));
            m.accept(&mut s1);
            std::mem::swap(&mut s0, &mut s1);
            m.set_pulley_input(0, PulleyInput::Angle, 100.0 * (t + h).powi(2));
        }
        (m, s0)
    }

    /// The iteration matrix of the whole model (elements, contact, pulleys) against central
    /// differences of the residual, in a running state with contact, stick and slip.
    #[test]
    fn model_jacobian_matches_finite_differences() {
        let (mut m, s) = running(60, 5e-4);
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
            for j in 0..n {
                let hstep = if stiff > 0.0 { 1e-8 } else { 1e-6 };
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
                    worst = worst.max((fd - an).abs());
                    scale = scale.max(an.abs());
                }
            }
            assert!(
                worst <= 1e-4 * scale,
                "stiffness {stiff} damping {damp}: worst {worst:.3e} of {scale:.3e}"
            );
        }
    }
}
