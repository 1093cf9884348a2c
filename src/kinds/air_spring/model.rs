//! The air spring at the membrane level (`model.fidelity = 2`): the sleeve's meridian as a
//! chain of conical membrane elements ([`AxisymMembrane`]) from the top bead (node 0) round the
//! rolling lobe to the clamp on the piston top (node `n`), the gas of the bag
//! ([`crate::gas::Gas`]) and frictionless penalty contact with the piston contour and the top
//! plate ([`AxisymObstacle`]).
//!
//! **Coordinates.** Per node `[r, z]` [m]; then the piston's axial position (fixed at 0) and
//! the top plate's (`top.z`). The bead node and the plate follow `top.z`, the clamp node is
//! fixed at the piston's top edge.
//!
//! **Residual.** `r = M a + f_int(q) − p_g ∇V(q) − f_contact`, with the gauge pressure
//! `p_g = p(V) − p_a` of the gas at the end of the step (the bag volume `V` is the exact volume
//! of the polygonal meridian, [`frustum_volume`], plus `gas.inner_volume`); the iteration
//! matrix carries `−p_g ∇²V` in the sparse part and the gas stiffness `−(dp/dV) ∇V ∇Vᵀ` as the
//! rank-one part of [`crate::linalg::LinearSolver`] (issue 11, item 1).
//!
//! **Design state.** At build the sleeve is mounted at `spring.design_height` under the fixed
//! gauge pressure `gas.pressure_design` (pseudo-transient continuation from a geometric start
//! shape, [`rolling_lobe_start`]); its bag volume fixes the gas mass. At level 2 the rolling
//! lobe is then remeshed, graded towards the material that rolls through the lobe
//! (`AirSpring::graded_mesh`), and solved again from the interpolated shape. A static solve at
//! initialization (`solver.static_equilibrium`) then moves the plate to the start value of
//! `top.z` with the gas law at rest (the load factor of the static solver moves the plate).
//!
//! **Force and stiffness.** `top.fz` is the reaction at the bead and the plate (gas on the
//! plate plus membrane plus plate contact), extrapolated to the current `top.z` with the
//! quasi-static stiffness; that stiffness and `spring.volumetric_area` come from the static
//! condensation of the tangent (with the gas's instantaneous `dp/dV`) onto the plate
//! coordinates, solved on a second assembly where they are free.

use super::relax::{Pressure, Relaxation};
use super::scene::{Input, Output, io, is_convoluted, names::*, piston_contour};
use super::table::{gas_error, gas_output, gas_params};
use super::{AirSpringScene, PlateInput, scene};
use crate::assembly::{Assembly, Connectivity, DofMap, ElementSet, Eval, check_finite};
use crate::contact::ContactPointSet;
use crate::contact::circle_friction::ContactLaw;
use crate::contact::revolution::AxisymObstacle;
use crate::elements::axisym_bending::AxisymHinge;
use crate::elements::axisym_membrane::{AxisymMembrane, frustum_volume};
use crate::elements::cord_rubber::CordRubberWall;
use crate::elements::{Element, ElementState};
use crate::gas::Gas;
use crate::integrators::DynState;
use crate::integrators::lagrange3;
use crate::linalg::{CscPattern, LinearSolver, SolverKind, rank_one_len};
use crate::meshers::bellows::{convoluted_start, rolling_lobe_start};
use crate::model::{JacobianCoeffs, MechanicalSystem, Model, ModelError};
use crate::scene::params::ParamValues;
use crate::snapshot::{StateReader, StateWriter};
use nalgebra::{SVector, Vector3};
use std::cell::{Cell, RefCell};

/// Element density in the rolling lobe's zone against the rest of the sleeve (level 2,
/// [`AirSpring::graded_mesh`]).
const GRADING: f64 = 4.0;

/// Index of the top plate among the obstacles of the meridian (after the piston or the
/// bottom plate).
const PLATE_OBSTACLE: usize = 1;

/// Elements, contact and pattern over one split of the coordinates into free and prescribed.
#[derive(Clone, Debug)]
struct Mech {
    asm: Assembly,
    elements: ElementSet<AxisymMembrane, 4>,
    /// Meridional bending hinges at the inner nodes (none for a pure membrane).
    hinges: Option<ElementSet<AxisymHinge, 6>>,
    contact: ContactPointSet<AxisymObstacle, 2, 2, 5>,
    scales: Vec<f64>,
}

impl Mech {
    fn new(
        n_el: usize,
        elements: Vec<AxisymMembrane>,
        hinges: Option<Vec<AxisymHinge>>,
        constrained: &[bool],
        law: ContactLaw,
        obstacles: Vec<AxisymObstacle>,
        scale: f64,
    ) -> Self {
        let n_nodes = n_el + 1;
        let dofs = DofMap::new(constrained);
        let el_dofs: Vec<[usize; 4]> = (0..n_el)
            .map(|e| [2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3])
            .collect();
        let blocks: Vec<[usize; 5]> = (0..n_el)
            .flat_map(|e| {
                (0..obstacles.len())
                    .map(move |k| [2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3, 2 * n_nodes + k])
            })
            .collect();
        let flat4: Vec<usize> = el_dofs.iter().flatten().copied().collect();
        let flat5: Vec<usize> = blocks.iter().flatten().copied().collect();
        let hinge_dofs: Vec<[usize; 6]> = match hinges {
            Some(_) => (1..n_el)
                .map(|k| std::array::from_fn(|i| 2 * (k - 1) + i))
                .collect(),
            None => vec![],
        };
        let flat6: Vec<usize> = hinge_dofs.iter().flatten().copied().collect();
        let asm = Assembly::new(dofs, &[(4, &flat4), (5, &flat5), (6, &flat6)], &[]);
        let hinges = hinges.map(|h| ElementSet::new(h, hinge_dofs, &asm));
        // two points per element (more do not change the characteristic: measured with 4, 8)
        let np = 2usize;
        let w_of =
            |e: &AxisymMembrane| 2.0 * std::f64::consts::PI * e.radius[0] * e.length / np as f64;
        let w = w_of(&elements[0]);
        let element_w: Vec<f64> = elements.iter().map(w_of).collect();
        let graded = element_w.iter().any(|&x| x != w);
        let elements = ElementSet::new(elements, el_dofs, &asm);
        let mut contact =
            ContactPointSet::new(law, obstacles, Connectivity::new(blocks, &asm), [0, 1]);
        let pts: Vec<[f64; 2]> = (0..np)
            .map(|i| {
                let x = (i as f64 + 0.5) / np as f64;
                [1.0 - x, x]
            })
            .collect();
        contact.set_points(pts, w);
        if graded {
            contact.set_element_weights(element_w);
        }
        let n_free = asm.dofs.n_free();
        Self {
            asm,
            elements,
            hinges,
            contact,
            scales: vec![scale; n_free],
        }
    }

    fn pattern(&self) -> &CscPattern {
        &self.asm.pattern
    }
}

/// Where the sleeve is held: its lower end, the girdle ring, the obstacles (the lower one, then
/// the top plate) and the start meridian (`n + 1` points from the top bead).
#[derive(Clone)]
struct Mounting {
    clamp: [f64; 2],
    girdle: Option<(usize, f64)>,
    obstacles: Vec<AxisymObstacle>,
    start: Vec<[f64; 2]>,
    /// Reference (stress-free) length of every element [m], from the top bead.
    lengths: Vec<f64>,
    /// Whether `start` is already an equilibrium at the design pressure (a remeshed one).
    loaded: bool,
}

impl Mounting {
    /// A convoluted sleeve: from the top bead ring down to the bottom bead ring
    /// (`bottom_plate.bead_radius` at `z = 0`), with two convolutions through the girdle ring
    /// (`girdle.radius`) at the middle node; both plates are flat obstacles.
    fn convoluted(scene: &AirSpringScene, p: &ParamValues) -> Result<Self, String> {
        let rb = p.real(TOP_PLATE_BEAD_RADIUS);
        let rbb = p.real(BOTTOM_PLATE_BEAD_RADIUS);
        let length = p.real(BELLOWS_SLEEVE_LENGTH);
        let hd = p.real(SPRING_DESIGN_HEIGHT);
        let n_el = p.integer(MESH_N_MERIDIONAL).max(2) as usize;
        let rg = (scene::n_convolutions(scene) == 2).then(|| p.real(GIRDLE_RADIUS));
        if let Some(rg) = rg
            && !n_el.is_multiple_of(2)
        {
            return Err(format!(
                "{MESH_N_MERIDIONAL} = {n_el}: a double-convoluted sleeve needs an even number of elements (the girdle ring {GIRDLE_RADIUS} = {rg} m holds the middle node)"
            ));
        }
        // the sleeve's meridian at a mean stretch of 1 (the convolutions' hoop stretch and
        // the cord angle set the meridional one; the design solve finds it)
        let start = convoluted_start([rb, hd], [rbb, 0.0], rg, length, n_el).map_err(|e| {
            format!(
                "{e} ({BELLOWS_SLEEVE_LENGTH}, {TOP_PLATE_BEAD_RADIUS}, {BOTTOM_PLATE_BEAD_RADIUS}, {GIRDLE_RADIUS}, {SPRING_DESIGN_HEIGHT})"
            )
        })?;
        let big = 10.0 * rb.max(rbb);
        Ok(Self {
            clamp: [rbb, 0.0],
            girdle: rg.map(|rg| (n_el / 2, rg)),
            obstacles: vec![
                AxisymObstacle::Floor { radius: big },
                AxisymObstacle::Plate { radius: big },
            ],
            lengths: vec![length / n_el as f64; n_el],
            loaded: false,
            start,
        })
    }
}

/// Work buffers of an evaluation (full coordinates).
#[derive(Clone, Debug, Default)]
struct Work {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    f: Vec<f64>,
    grad: Vec<f64>,
}

/// Quasi-static derivatives of the committed state.
#[derive(Clone, Copy, Debug)]
struct Condensed {
    /// `d top.fz / d top.z` [N/m].
    dfdh: f64,
    /// `dV/d top.z` [m²].
    dvdh: f64,
}

/// The quasi-static condensation: its own assembly (bead z and plate free), factorization and
/// buffers, and the result of the last computation with the commit it belongs to. Computed on
/// demand (an output, a derivative or the `top.fz` extrapolation asks), at most once per commit,
/// so a step whose outputs do not need it pays nothing for it.
#[derive(Debug)]
struct Condensation {
    ext: Mech,
    solver: Option<LinearSolver>,
    vals: Vec<f64>,
    work: Work,
    /// Columns of `K⁻¹` at the two plate coordinates.
    y: [Vec<f64>; 2],
    /// Commit counter and result (`None`: the condensation failed) of the last computation.
    cache: Option<(u64, Option<Condensed>)>,
}

/// Depth [m] of the C¹ ramp of the membrane level's contact penalty (`ContactLaw::smoothing`;
/// the shell level keeps 10 µm): the penetration at a fifth of the design gauge pressure `p_g`
/// [Pa] (at least 0.1 bar) under the penalty `k_n` [N/m³], at most 10 µm. A contact point
/// within the ramp has a stiffness that grows with its penetration, so that modified Newton's
/// kept matrix goes stale as the points move; the pressed sleeve sits at about `p/k_n`
/// (0.55 µm at 5 bar and 1e12 N/m³), which a fixed 10 µm ramp (before session 34) put every
/// point inside (3.2 µm deep). At level 2's shipped 60 elements (2 Hz ± 10 mm sine,
/// `bench_air_spring`): 1.67 → 1.40 Newton iterations and 0.26 → 0.19 factorizations per step
/// against the fixed 10 µm (1 µm: 1.56 and 0.23).
pub fn contact_smoothing(p_g: f64, k_n: f64) -> f64 {
    (0.2 * p_g.max(1e4) / k_n).min(1e-5)
}

/// The air-spring model at the membrane level.
pub struct AirSpring {
    n_el: usize,
    main: Mech,
    /// The same with the bead's z and the plate free: the condensation, computed on demand.
    cond: RefCell<Condensation>,
    bead_radius: f64,
    /// The lower end of the sleeve: the clamp at the piston's top edge, or the bottom bead of
    /// a convoluted sleeve (`[r, 0]`).
    clamp: [f64; 2],
    /// The girdle ring of a double-convoluted sleeve: its node and radius [m] (the node's
    /// radius is prescribed, its height free).
    girdle: Option<(usize, f64)>,
    /// A convoluted sleeve (bottom plate instead of a piston).
    convoluted: bool,
    design_height: f64,
    ambient: f64,
    gas: Gas,
    inputs: Vec<Input>,
    outputs: Vec<Output>,
    plate: PlateInput,
    /// Plate height the static solve starts from (the last equilibrium) [m].
    static_from: f64,
    statics: bool,
    hold: bool,
    initialized: bool,
    /// Committed time [s], full coordinates and velocities.
    t: f64,
    q: Vec<f64>,
    v: Vec<f64>,
    work: Work,
    /// Committed reaction `top.fz` [N], plate height [m].
    force: f64,
    height: f64,
    /// The fixed gauge pressure of the last constant-pressure equilibrium [Pa].
    pressure_now: f64,
    /// Mass of the wall per reference area [kg/m²].
    mass_per_area: f64,
    /// Strain energy of the last residual evaluation [J].
    last_strain: f64,
    /// Bag volume at the charge [m³].
    v_charge: f64,
    /// Strain energy of the committed state [J], computed when first asked after a commit
    /// (`None` until then).
    strain: Cell<Option<f64>>,
    kinetic: f64,
    plate_work: f64,
    contact_loss: f64,
    last_damping_power: f64,
    commits: u64,
    /// Free-coordinate buffers of [`AirSpring::reaction`] (`q`, `v`, residual) and the
    /// midpoint coordinates of [`MechanicalSystem::midpoint_residual`].
    scratch: [Vec<f64>; 3],
    midpoint: Vec<f64>,
    /// Free coordinates and plate heights [m] of the last commits, newest first, for the
    /// quasi-static predictor ([`MechanicalSystem::predict`]); the first `n_history` valid.
    history_q: [Vec<f64>; 3],
    history_z: [f64; 3],
    /// Times of those commits [s].
    history_t: [f64; 3],
    n_history: usize,
    /// Quasi-static steps (`solver.integrator = "quasi_static"`): the wall has no inertia
    /// and no kinetic energy.
    quasi_static: bool,
    /// Quasi-static steps: the communication step `(t0, t1)` being advanced and the committed
    /// plate height's offset from the position input at `t0` [m], spread linearly over the
    /// step ([`AirSpring::plate_motion`]); `None` outside a step or with inertia.
    input_jump: Option<(f64, f64, f64)>,
}

impl std::fmt::Debug for AirSpring {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AirSpring")
            .field("n_el", &self.n_el)
            .field("t", &self.t)
            .finish()
    }
}

/// Volume of the meridian `q` (full coordinates) and its gradient into `grad` (full).
fn volume_gradient(n_el: usize, q: &[f64], grad: &mut [f64]) -> f64 {
    grad.fill(0.0);
    let mut v = 0.0;
    for e in 0..n_el {
        let qe = SVector::<f64, 4>::from_column_slice(&q[2 * e..2 * e + 4]);
        let (ve, ge, _) = frustum_volume(&qe);
        v += ve;
        for i in 0..4 {
            grad[2 * e + i] += ge[i];
        }
    }
    v
}

impl AirSpring {
    /// Builds the model and solves the design state. Errors name the parameter.
    pub fn build(scene: &AirSpringScene, p: &ParamValues) -> Result<Self, String> {
        let convoluted = is_convoluted(scene);
        let rb = p.real(TOP_PLATE_BEAD_RADIUS);
        let length = p.real(BELLOWS_SLEEVE_LENGTH);
        let hd = p.real(SPRING_DESIGN_HEIGHT);
        let n_el = p.integer(MESH_N_MERIDIONAL).max(2) as usize;
        if convoluted {
            return Self::build_on(scene, p, Mounting::convoluted(scene, p)?);
        }
        let contour = piston_contour(scene, p);
        let clamp = *contour.last().expect("two points");
        if rb <= clamp[0] {
            return Err(format!(
                "{TOP_PLATE_BEAD_RADIUS} = {rb} m must exceed the piston radius at its top ({} m): a rolling lobe forms between them",
                clamp[0]
            ));
        }
        if hd <= clamp[1] {
            return Err(format!(
                "{SPRING_DESIGN_HEIGHT} = {hd} m must exceed {PISTON_HEIGHT} = {} m",
                clamp[1]
            ));
        }
        // start shape: a lobe of outer radius a fifth of the bead–piston gap beyond the bead
        let start = rolling_lobe_start(
            &contour,
            rb,
            hd,
            rb + 0.2 * (rb - clamp[0]),
            1.15 * length,
            n_el,
        )
        .map_err(|e| {
            format!(
                "{e} ({BELLOWS_SLEEVE_LENGTH}, {TOP_PLATE_BEAD_RADIUS}, {PISTON_RADIUS}, {SPRING_DESIGN_HEIGHT}, {PISTON_HEIGHT})"
            )
        })?;
        let mounting = Mounting {
            clamp,
            girdle: None,
            obstacles: vec![
                AxisymObstacle::Piston {
                    contour: contour.clone(),
                },
                AxisymObstacle::Plate { radius: 10.0 * rb },
            ],
            lengths: vec![length / n_el as f64; n_el],
            loaded: false,
            start,
        };
        let uniform = Self::build_on(scene, p, mounting.clone())?;
        if p.integer(MODEL_FIDELITY) != 2 {
            // the shell level revolves this meridian onto its own, uniform material mesh
            return Ok(uniform);
        }
        let (start, lengths) = uniform.graded_mesh(&contour);
        // should the graded mesh find no equilibrium, the uniform one serves
        Ok(Self::build_on(
            scene,
            p,
            Mounting {
                start,
                lengths,
                loaded: true,
                ..mounting
            },
        )
        .unwrap_or(uniform))
    }

    /// A meridian mesh graded for the rolling lobe from this (uniform) design state: the
    /// material that can roll through the lobe gets elements [`GRADING`] times shorter than
    /// the rest (the top bead's side of the outer wall). The discrete characteristic ripples
    /// as nodes peel off the piston (the departure point of a linear-element meridian moves
    /// from node to node), with a slope error proportional to the element length there.
    /// The zone reaches from the clamp (full extension unrolls the sleeve from the piston)
    /// past the lobe to the material that rolls onto the piston at the largest compression:
    /// half of `min(2 z_b, h_d − h_p)` (the lobe bottom `z_b` reaching the piston base, or
    /// the plate the piston top; the lobe rolls at half the plate's speed). Returns the start
    /// shape (this meridian at the new nodes' material positions) and the element lengths.
    fn graded_mesh(&self, contour: &[[f64; 2]]) -> (Vec<[f64; 2]>, Vec<f64>) {
        let n = self.n_el;
        let mer = self.meridian();
        let length = self.main.elements.element(0).length * n as f64;
        let top = contour[contour.len() - 1];
        let radius_at = |z: f64| -> f64 {
            for w in contour.windows(2) {
                if z <= w[1][1] {
                    let t = ((z - w[0][1]) / (w[1][1] - w[0][1])).max(0.0);
                    return w[0][0] + t * (w[1][0] - w[0][0]);
                }
            }
            top[0]
        };
        // departure: the first node (from the clamp back) off the piston's contour
        let mut d = n;
        while d > 1 && mer[d - 1][0] - radius_at(mer[d - 1][1]) < 1e-5 * length {
            d -= 1;
        }
        let low = (1..n)
            .min_by(|&a, &b| mer[a][1].total_cmp(&mer[b][1]))
            .unwrap_or(n / 2);
        let stretched: f64 = mer
            .windows(2)
            .map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt())
            .sum();
        let stretch = stretched / length;
        let compression = (2.0 * mer[low][1])
            .min(self.design_height - top[1])
            .max(0.0);
        // material fractions: the lobe's outer half mirrors its inner one
        let f_low = low as f64 / n as f64;
        let f_dep = d as f64 / n as f64;
        let a = (2.0 * f_low - f_dep - 0.5 * compression / (stretch * length)).clamp(0.0, 1.0);
        // cumulative element density: GRADING per length in [a, 1], 1 before
        let cum = |f: f64| f.min(a) + GRADING * (f - a).max(0.0);
        let total = cum(1.0);
        let frac: Vec<f64> = (0..=n)
            .map(|k| {
                let t = total * k as f64 / n as f64;
                if t <= a { t } else { a + (t - a) / GRADING }
            })
            .collect();
        let start = frac
            .iter()
            .map(|&f| {
                let x = (f * n as f64).clamp(0.0, n as f64);
                let i = (x.floor() as usize).min(n - 1);
                let t = x - i as f64;
                [
                    mer[i][0] + t * (mer[i + 1][0] - mer[i][0]),
                    mer[i][1] + t * (mer[i + 1][1] - mer[i][1]),
                ]
            })
            .collect();
        let lengths = frac.windows(2).map(|w| length * (w[1] - w[0])).collect();
        (start, lengths)
    }

    /// Builds the model on a mounting and solves the design state.
    fn build_on(scene: &AirSpringScene, p: &ParamValues, m: Mounting) -> Result<Self, String> {
        let Mounting {
            clamp,
            girdle,
            obstacles,
            start,
            lengths,
            loaded,
        } = m;
        let rb = p.real(TOP_PLATE_BEAD_RADIUS);
        let r0 = p.real(BELLOWS_SLEEVE_RADIUS);
        let length = p.real(BELLOWS_SLEEVE_LENGTH);
        let hd = p.real(SPRING_DESIGN_HEIGHT);
        let n_el = start.len() - 1;
        let wall = CordRubberWall {
            cord_stiffness: p.real(BELLOWS_CORD_STIFFNESS),
            n_plies: p.integer(BELLOWS_N_PLIES).max(1) as usize,
            cord_angle: p.real(BELLOWS_CORD_ANGLE).to_radians(),
            matrix_stiffness: p.real(BELLOWS_MATRIX_STIFFNESS),
            tension_only: p.boolean(BELLOWS_TENSION_ONLY),
        };
        let elements: Vec<AxisymMembrane> = lengths
            .iter()
            .map(|&l| {
                AxisymMembrane::new(
                    l,
                    [r0, r0],
                    wall,
                    p.real(BELLOWS_DENSITY) * p.real(BELLOWS_THICKNESS),
                )
            })
            .collect();
        let n_nodes = n_el + 1;
        let n_full = 2 * n_nodes + 2;
        // friction (`contact.mu`): a bristle as stiff per slip as the penalty per penetration
        // (stick to within μ p / k_n, a fraction of a micrometre at 5 bar), the stick–slip
        // switch blended over ±10 % of μ p so that Newton's method does not cycle
        let k_n = p.real(CONTACT_STIFFNESS);
        let law = ContactLaw {
            k_n,
            d_n: 0.0,
            k_t: k_n,
            d_t: 0.0,
            // level 2's parameter; 0 where the membrane serves another level (the shell's
            // design state, a table's generation)
            mu: match p.get(CONTACT_MU) {
                Some(crate::variables::Value::Real(mu)) => mu,
                _ => 0.0,
            },
            smoothing: contact_smoothing(p.real(GAS_PRESSURE_DESIGN), k_n),
            blend: 0.1,
        };
        let mut constrained = vec![false; n_full];
        for i in [0, 1, 2 * n_el, 2 * n_el + 1, 2 * n_nodes, 2 * n_nodes + 1] {
            constrained[i] = true;
        }
        if let Some((k, _)) = girdle {
            constrained[2 * k] = true;
        }
        let d = p.real(BELLOWS_BENDING_STIFFNESS);
        let hinges = (d > 0.0).then(|| {
            lengths
                .windows(2)
                .map(|l| AxisymHinge::new(d, r0, [l[0], l[1]]))
                .collect::<Vec<_>>()
        });
        let main = Mech::new(
            n_el,
            elements.clone(),
            hinges.clone(),
            &constrained,
            law,
            obstacles.clone(),
            length,
        );
        constrained[1] = false;
        constrained[2 * n_nodes + 1] = false;
        let ext = Mech::new(n_el, elements, hinges, &constrained, law, obstacles, length);
        let n_ext = ext.asm.dofs.n_free();
        let mut q = vec![0.0; n_full];
        for (k, pt) in start.iter().enumerate() {
            q[2 * k] = pt[0];
            q[2 * k + 1] = pt[1];
        }
        q[2 * n_nodes + 1] = hd;
        let gp = gas_params(p, scene);
        let pd = p.real(GAS_PRESSURE_DESIGN);
        let io = io(scene);
        let work = || Work {
            q: vec![0.0; n_full],
            v: vec![0.0; n_full],
            a: vec![0.0; n_full],
            f: vec![0.0; n_full],
            grad: vec![0.0; n_full],
        };
        let n_main = main.asm.dofs.n_free();
        let mut model = Self {
            n_el,
            main,
            cond: RefCell::new(Condensation {
                ext,
                solver: None,
                vals: vec![],
                work: work(),
                y: [vec![0.0; n_ext], vec![0.0; n_ext]],
                cache: None,
            }),
            bead_radius: rb,
            clamp,
            girdle,
            convoluted: is_convoluted(scene),
            design_height: hd,
            ambient: gp.ambient_pressure,
            // charged after the design solve
            gas: Gas::new(gp, pd, 1.0).map_err(|e| gas_error(e, &gp))?,
            inputs: io.inputs,
            outputs: io.outputs,
            plate: PlateInput::at_rest(hd),
            static_from: hd,
            statics: false,
            hold: false,
            initialized: false,
            t: 0.0,
            q,
            v: vec![0.0; n_full],
            work: work(),
            force: 0.0,
            height: hd,
            pressure_now: 0.0,
            mass_per_area: p.real(BELLOWS_DENSITY) * p.real(BELLOWS_THICKNESS),
            last_strain: 0.0,
            v_charge: 0.0,
            strain: Cell::new(Some(0.0)),
            kinetic: 0.0,
            quasi_static: false,
            input_jump: None,
            plate_work: 0.0,
            contact_loss: 0.0,
            last_damping_power: 0.0,
            commits: 0,
            scratch: [vec![0.0; n_main], vec![0.0; n_main], vec![0.0; n_main]],
            midpoint: vec![0.0; n_main],
            history_q: [vec![0.0; n_main], vec![0.0; n_main], vec![0.0; n_main]],
            history_z: [0.0; 3],
            history_t: [0.0; 3],
            n_history: 0,
        };
        if loaded {
            model.continuation((hd, pd), (hd, pd), false)?;
        } else {
            model.solve_design(pd)?;
        }
        let vd = volume_gradient(n_el, &model.q, &mut model.work.grad);
        model.gas.charge(pd, vd).map_err(|e| gas_error(e, &gp))?;
        model.v_charge = model.gas.committed().volume;
        let zeros = vec![0.0; model.n_free()];
        model.force = model
            .reaction(&zeros)
            .map_err(|e| gas_error(format!("design state: {e}"), &gp))?;
        Ok(model)
    }

    /// The design state under the fixed gauge pressure `pd` [Pa] from the start shape.
    fn solve_design(&mut self, pd: f64) -> Result<(), String> {
        let h = self.design_height;
        self.continuation((h, 0.0), (h, pd), false)
    }

    /// The static equilibrium with the plate at height `h` [m] under the fixed gauge pressure
    /// `p_gauge` [Pa] (no gas law: a constant-pressure state, as on a test rig with a large
    /// supply), reached from the committed shape; it becomes the committed shape. Returns
    /// the force on the plate [N] and the bag volume (membrane plus inner) [m³]. For tools
    /// (the effective-area table of level 3) and tests, before a simulation starts.
    pub fn equilibrium_at(&mut self, h: f64, p_gauge: f64) -> Result<(f64, f64), String> {
        let from = (self.q[1], self.pressure_now);
        self.continuation(from, (h, p_gauge), false)?;
        let zeros = vec![0.0; self.n_free()];
        let mut r = vec![0.0; self.n_free()];
        let mut qf = vec![0.0; self.n_free()];
        self.main.asm.dofs.restrict(&self.q, &mut qf);
        self.evaluate(
            0.0,
            &qf,
            &zeros,
            &zeros,
            Pressure::Fixed(p_gauge),
            &mut r,
            None,
        )
        .map_err(|e| e.to_string())?;
        let force = self.plate_force();
        let vm = volume_gradient(self.n_el, &self.q, &mut self.work.grad);
        Ok((force, vm + self.gas.params().inner_volume))
    }

    /// Pseudo-transient continuation (`(K + c M) Δq = −r`, `c` shrinking with the residual:
    /// switched evolution relaxation) from plate height and fixed gauge pressure `from` to
    /// `to` [m, Pa] in adaptive levels, starting from the committed shape; with `gas` the
    /// pressure is the gas's at rest instead (the charged spring moved to another height).
    fn continuation(&mut self, from: (f64, f64), to: (f64, f64), gas: bool) -> Result<(), String> {
        let pd = to.1.abs().max(from.1.abs()).max(1.0);
        let n = self.main.asm.dofs.n_free();
        let mut ws = crate::solver::Workspace::new(&*self, SolverKind::Auto)
            .map_err(|e| format!("design state: {e}"))?;
        let mut x = vec![0.0; n];
        self.main.asm.dofs.restrict(&self.q, &mut x);
        let zeros = vec![0.0; n];
        let mut level = 0.0f64;
        // the plate moves at most an element length per level: the path stays close to
        // equilibrium and no element is pushed through a fold
        let ell = self.main.scales[0] / self.n_el as f64;
        let max_step = (ell / (to.0 - from.0).abs().max(1e-300)).min(0.25);
        let mut step = max_step.min(0.1);
        let mut last_err = String::new();
        // pseudo-time coefficient: starts as a strong relaxation (1e6/L² per unit mass)
        // (scaled with the wall's mass per area against 4.4 kg/m², the reference spring's, so
        // that the relaxation does not depend on the density)
        let c_start = 1e6 / (self.main.scales[0] * self.main.scales[0]) * 4.4
            / self.mass_per_area.max(1e-300);
        let mut c_level = c_start;
        // residual scale: the pressure force on an element
        let r_scale = pd * self.main.scales[0] * self.main.scales[0] / self.n_el as f64;
        // restored if the continuation fails: the shape stays at the last equilibrium
        let (q1_saved, plate_saved) = (self.q[1], self.plate);
        while level < 1.0 {
            let target = (level + step).min(1.0);
            let saved = x.clone();
            let mut relax = Relaxation::new(c_level.max(1e-3 * c_start));
            let mut ok = false;
            for _ in 0..400 {
                let coeffs = JacobianCoeffs {
                    mass: relax.c,
                    damping: 0.0,
                    stiffness: 1.0,
                };
                let h = from.0 + target * (to.0 - from.0);
                self.plate = PlateInput::at_rest(h);
                self.q[1] = h;
                let res = self.evaluate(
                    0.0,
                    &x,
                    &zeros,
                    &zeros,
                    if gas {
                        Pressure::Static
                    } else {
                        Pressure::Fixed(from.1 + target * (to.1 - from.1))
                    },
                    &mut ws.r,
                    Some((coeffs, &mut ws.jac)),
                );
                if let Err(e) = res {
                    last_err = e.to_string();
                    break;
                }
                // keep the increment a fraction of an element length
                let cap = 0.25 / self.n_el as f64;
                let it = match relax.iterate(&mut ws, &mut x, &self.main.scales, cap) {
                    Ok(it) => it,
                    Err(e) => {
                        last_err = e;
                        break;
                    }
                };
                if std::env::var("AIRSPRING_DEBUG").is_ok() {
                    eprintln!(
                        "level {target:.3} |r| {:.3e} inc {:.3e} scale {:.2e} c {:.3e}",
                        it.r_norm, it.inc, it.scale, relax.c
                    );
                }
                if it.inc < 1e-11 && it.scale == 1.0 && it.r_norm < 1e-9 * r_scale {
                    ok = true;
                    break;
                }
                relax.settle();
            }
            if ok {
                // a membrane without bending can fold: an element squeezed to a fraction of
                // its length is a spurious equilibrium, not the rolling lobe
                let mut full = std::mem::take(&mut self.work.q);
                self.expand(&x, &mut full);
                let squeezed = (0..self.n_el).any(|e| {
                    let w = &full[2 * e..2 * e + 4];
                    ((w[2] - w[0]).powi(2) + (w[3] - w[1]).powi(2)).sqrt() < 0.25 * ell
                });
                self.work.q = full;
                if squeezed {
                    ok = false;
                    last_err = "an element folded".into();
                }
            }
            if ok {
                c_level = relax.c;
                level = target;
                step = (step * 1.5).min(max_step);
            } else {
                x = saved;
                step *= 0.5;
                c_level = c_start;
                if step < 1e-3 {
                    self.q[1] = q1_saved;
                    self.plate = plate_saved;
                    // the geometry's parameters of this bellows type
                    let lower = if self.convoluted {
                        format!("{BOTTOM_PLATE_BEAD_RADIUS}, {GIRDLE_RADIUS}")
                    } else {
                        format!("{PISTON_RADIUS}, {PISTON_HEIGHT}")
                    };
                    return Err(format!(
                        "no static equilibrium of the sleeve from height {:.4} m, gauge pressure {:.4e} Pa to {:.4} m, {:.4e} Pa (reached {:.0} % of the way: {last_err}); check the geometry ({TOP_PLATE_BEAD_RADIUS}, {lower}, {BELLOWS_SLEEVE_RADIUS}, {BELLOWS_SLEEVE_LENGTH}, {SPRING_DESIGN_HEIGHT}), the wall ({BELLOWS_CORD_STIFFNESS}, {BELLOWS_N_PLIES}, {BELLOWS_CORD_ANGLE}, {BELLOWS_MATRIX_STIFFNESS}, {BELLOWS_TENSION_ONLY}, {BELLOWS_DENSITY}, {BELLOWS_THICKNESS}), {CONTACT_STIFFNESS}, {MESH_N_MERIDIONAL} and {GAS_PRESSURE_DESIGN}",
                        from.0,
                        from.1,
                        to.0,
                        to.1,
                        100.0 * level
                    ));
                }
            }
        }
        let mut q = self.q.clone();
        self.expand(&x, &mut q);
        self.q = q;
        self.height = to.0;
        self.pressure_now = if gas {
            let vm = volume_gradient(self.n_el, &self.q, &mut self.work.grad);
            self.gas
                .static_pressure(vm)
                .map_or(0.0, |(p, _)| p - self.ambient)
        } else {
            to.1
        };
        self.plate = PlateInput::at_rest(to.0);
        // a new shape: the condensation of the old one is stale, the predictor's history too
        self.commits += 1;
        self.n_history = 0;
        Ok(())
    }

    /// Prescribed plate height, velocity and acceleration at `t` (or in a static solve at the
    /// load factor `lambda`).
    fn plate_motion(&self, t: f64, lambda: f64) -> (f64, f64, f64) {
        if self.statics {
            let z = self.static_from + lambda * (self.plate.z().value - self.static_from);
            return (z, 0.0, 0.0);
        }
        let mut m = self.plate.motion(t);
        if self.hold && t == self.t {
            return (self.height, m.1, m.2);
        }
        if let Some((t0, t1, dz)) = self.input_jump
            && t < t1
        {
            // quasi-static steps: a position input that jumped away from the committed
            // height is reached at the step's end, not at its start, so that a halved
            // substep halves the jump (a continuation); the end state is the same
            m.0 += dz * (t1 - t) / (t1 - t0);
        }
        m
    }

    /// Full coordinates from free ones with the prescribed values of the committed plate.
    fn expand(&self, free: &[f64], full: &mut [f64]) {
        self.main.asm.dofs.expand(free, full);
        self.prescribe(full, self.q[1]);
    }

    /// Sets the prescribed coordinates of full coordinates `full`: bead and clamp nodes, the
    /// piston at 0 and the plate (and the bead's z) at the height `z` [m].
    fn prescribe(&self, full: &mut [f64], z: f64) {
        let n_nodes = self.n_el + 1;
        full[0] = self.bead_radius;
        full[1] = z;
        full[2 * self.n_el] = self.clamp[0];
        full[2 * self.n_el + 1] = self.clamp[1];
        if let Some((k, rg)) = self.girdle {
            full[2 * k] = rg;
        }
        full[2 * n_nodes] = 0.0;
        full[2 * n_nodes + 1] = z;
    }

    /// The force on the plate [N] of the residual in the work vectors: minus the residual at
    /// the bead's z and at the plate coordinate (gas on the plate, membrane, plate contact).
    fn plate_force(&self) -> f64 {
        -(self.work.f[1] + self.work.f[2 * (self.n_el + 1) + 1])
    }

    /// Fills the work vectors with the full state at `t` from free `q`, `v`, `a`.
    fn fill_work(&mut self, t: f64, lambda: f64, q: &[f64], v: &[f64], a: &[f64]) {
        let (z, vz, az) = self.plate_motion(t, lambda);
        let n_nodes = self.n_el + 1;
        let mut full = std::mem::take(&mut self.work.q);
        self.main.asm.dofs.expand(q, &mut full);
        self.prescribe(&mut full, z);
        self.work.q = full;
        let d = &self.main.asm.dofs;
        let w = &mut self.work;
        d.expand(v, &mut w.v);
        d.expand(a, &mut w.a);
        for x in [&mut w.v, &mut w.a] {
            for i in [0, 2 * self.n_el, 2 * self.n_el + 1, 2 * n_nodes] {
                x[i] = 0.0;
            }
            if let Some((k, _)) = self.girdle {
                x[2 * k] = 0.0;
            }
        }
        w.v[1] = vz;
        w.v[2 * n_nodes + 1] = vz;
        w.a[1] = az;
        w.a[2 * n_nodes + 1] = az;
    }

    /// Residual over the work state of `mech` (full `f`), with the iteration matrix if asked;
    /// returns the strain energy [J] and the membrane volume [m³].
    fn assemble_full(
        mech: &mut Mech,
        n_el: usize,
        work: &mut Work,
        p_g: f64,
        dp_dv: f64,
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> f64 {
        let Work { q, v, a, f, grad } = work;
        f.fill(0.0);
        if let Some((_, vals)) = jac.as_mut() {
            vals.fill(0.0);
        }
        let x = Eval {
            q,
            v,
            a,
            g: Vector3::zeros(),
        };
        let mut u =
            mech.elements
                .add_residual(&x, None, f, jac.as_mut().map(|(c, v)| (*c, &mut **v)));
        if let Some(h) = &mech.hinges {
            u += h.add_residual(&x, None, f, jac.as_mut().map(|(c, v)| (*c, &mut **v)));
        }
        for i in 0..f.len() {
            f[i] -= p_g * grad[i];
        }
        if let Some((c, vals)) = jac.as_mut() {
            let conn = mech.elements.connectivity();
            for e in 0..n_el {
                let qe = SVector::<f64, 4>::from_column_slice(&q[2 * e..2 * e + 4]);
                let (_, _, he) = frustum_volume(&qe);
                conn.add_matrix(e, &he, -c.stiffness * p_g, vals);
            }
        }
        mech.contact
            .add_residual(q, v, f, jac.as_mut().map(|(c, v)| (*c, &mut **v)));
        if let Some((c, vals)) = jac {
            let nnz = mech.asm.pattern.nnz();
            if vals.len() == rank_one_len(&mech.asm.pattern) {
                vals[nnz] = -c.stiffness * dp_dv;
                for (i, &full) in mech.asm.dofs.free_to_full().iter().enumerate() {
                    vals[nnz + 1 + i] = grad[full];
                }
            }
        }
        u
    }

    /// Residual and iteration matrix on the free coordinates of the main system.
    #[allow(clippy::too_many_arguments)]
    fn evaluate(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        mode: Pressure,
        r: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        self.fill_work(t, 1.0, q, v, a);
        self.evaluate_filled(mode, r, jac)
    }

    fn evaluate_filled(
        &mut self,
        mode: Pressure,
        r: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        let vm = volume_gradient(self.n_el, &self.work.q, &mut self.work.grad);
        if !(vm.is_finite() && vm > 0.0) {
            return Err(ModelError::NonFinite);
        }
        let (p_g, dp_dv) = mode.gauge(&self.gas, self.ambient, vm)?;
        let check = jac.is_some();
        let mut jac = jac;
        self.last_strain = Self::assemble_full(
            &mut self.main,
            self.n_el,
            &mut self.work,
            p_g,
            dp_dv,
            jac.as_mut().map(|(c, v)| (*c, &mut **v)),
        );
        self.main.asm.dofs.restrict(&self.work.f, r);
        check_finite(
            r,
            if check {
                jac.as_ref().map(|(_, v)| &**v)
            } else {
                None
            },
        )
    }

    /// The quasi-static derivatives of the committed state, computed on the first request
    /// after a commit (see [`Condensation`]) on the second assembly (bead z and plate free):
    /// with the columns `Y` of `K⁻¹` at the two plate coordinates, the Schur complement is
    /// `S = Y_hh⁻¹`, `d top.fz/d top.z = −dᵀ S d` and the shape change `Y S d`.
    fn condensed(&self) -> Option<Condensed> {
        let mut guard = self.cond.borrow_mut();
        let cond = &mut *guard;
        if let Some((k, c)) = cond.cache
            && k == self.commits
        {
            return c;
        }
        let c = self.compute_condensed(cond);
        cond.cache = Some((self.commits, c));
        c
    }

    fn compute_condensed(&self, cond: &mut Condensation) -> Option<Condensed> {
        let n_nodes = self.n_el + 1;
        let Condensation {
            ext,
            solver,
            vals,
            work,
            y,
            ..
        } = cond;
        if solver.is_none() {
            *solver = Some(LinearSolver::new(&ext.asm.pattern, SolverKind::Auto).ok()?);
            *vals = vec![0.0; rank_one_len(&ext.asm.pattern)];
        }
        let solver = solver.as_mut()?;
        // committed state, at rest, with the committed friction (stuck points stay stuck)
        ext.contact.copy_histories(&self.main.contact);
        work.q.copy_from_slice(&self.q);
        work.v.fill(0.0);
        work.a.fill(0.0);
        let vm = volume_gradient(self.n_el, &work.q, &mut work.grad);
        let e = self.gas.evaluate(0.0, vm).ok()?;
        let coeffs = JacobianCoeffs {
            mass: 0.0,
            damping: 0.0,
            stiffness: 1.0,
        };
        Self::assemble_full(
            ext,
            self.n_el,
            work,
            e.p_gauge,
            e.dp_dv,
            Some((coeffs, &mut vals[..])),
        );
        // S = K_hh − K_hf K_ff⁻¹ K_fh from the inverse of the matrix with ε added on both plate
        // coordinates (the plate's own row is empty out of contact): S = Y_hh⁻¹ − ε I.
        let eps = 1e6;
        let dofs = &ext.asm.dofs;
        let pattern = &ext.asm.pattern;
        let hz = [dofs.free_index(1)?, dofs.free_index(2 * n_nodes + 1)?];
        for &h in &hz {
            vals[pattern.position(h, h)?] += eps;
        }
        solver.factor(pattern, vals).ok()?;
        for (j, col) in y.iter_mut().enumerate() {
            col.fill(0.0);
            col[hz[j]] = 1.0;
            solver.solve_in_place(col);
        }
        let yhh = [[y[0][hz[0]], y[1][hz[0]]], [y[0][hz[1]], y[1][hz[1]]]];
        let det = yhh[0][0] * yhh[1][1] - yhh[0][1] * yhh[1][0];
        if det.abs() < 1e-300 || !det.is_finite() {
            return None;
        }
        // S d with d = (1, 1): S = Y_hh⁻¹
        let s = [
            [yhh[1][1] / det - eps, -yhh[0][1] / det],
            [-yhh[1][0] / det, yhh[0][0] / det - eps],
        ];
        let sd = [s[0][0] + s[0][1], s[1][0] + s[1][1]];
        let dfdh = -(sd[0] + sd[1]);
        let mut dvdh = 0.0;
        for (i, &full) in dofs.free_to_full().iter().enumerate() {
            // δx = Y (S + ε I) d
            dvdh += work.grad[full] * (y[0][i] * (sd[0] + eps) + y[1][i] * (sd[1] + eps));
        }
        Some(Condensed { dfdh, dvdh })
    }

    /// Largest radius of the committed meridian [m].
    fn lobe_radius(&self) -> f64 {
        (0..=self.n_el).map(|k| self.q[2 * k]).fold(0.0, f64::max)
    }

    /// Number of elements along the sleeve.
    pub fn n_elements(&self) -> usize {
        self.n_el
    }

    /// Committed meridian points `[r, z]` [m], bead first.
    pub fn meridian(&self) -> Vec<[f64; 2]> {
        (0..=self.n_el)
            .map(|k| [self.q[2 * k], self.q[2 * k + 1]])
            .collect()
    }

    /// The committed force on the plate [N] (without extrapolation).
    pub fn committed_force(&self) -> f64 {
        self.force
    }

    /// The gas component.
    pub fn gas(&self) -> &Gas {
        &self.gas
    }

    /// Reaction at the plate of the committed state with accelerations `acc` (free).
    fn reaction(&mut self, acc: &[f64]) -> Result<f64, ModelError> {
        let [mut qf, mut vf, mut r] = std::mem::take(&mut self.scratch);
        self.main.asm.dofs.restrict(&self.q, &mut qf);
        self.main.asm.dofs.restrict(&self.v, &mut vf);
        let saved = self.hold;
        self.hold = true;
        self.fill_work(self.t, 1.0, &qf, &vf, acc);
        self.hold = saved;
        let res = self.evaluate_filled(Pressure::Step(0.0), &mut r, None);
        self.scratch = [qf, vf, r];
        res?;
        // the strain energy of the residual just evaluated (elements and hinges)
        self.strain.set(Some(self.last_strain));
        self.kinetic = self.kinetic_energy(&self.work.q, &self.work.v);
        Ok(self.plate_force())
    }

    /// Kinetic energy of the wall [J] at full coordinates `q`, velocities `v` (0 in
    /// quasi-static steps, whose equations have no inertia).
    fn kinetic_energy(&self, q: &[f64], v: &[f64]) -> f64 {
        if self.quasi_static {
            0.0
        } else {
            self.main.elements.kinetic_energy(q, v, None)
        }
    }

    /// The strain energy of the committed meridian [J] (elements and hinges), computed on the
    /// first request after a commit.
    fn strain_energy(&self) -> f64 {
        if let Some(u) = self.strain.get() {
            return u;
        }
        let mut u = self.main.elements.strain_energy(&self.q, None);
        if let Some(h) = &self.main.hinges {
            u += h.strain_energy(&self.q, None);
        }
        self.strain.set(Some(u));
        u
    }

    /// [`AirSpring::reaction`] from the two rows it needs, after [`ContactPointSet::commit`]
    /// of the committed state: the bead's z row (element 0, the first hinge, the gas on the
    /// first frustum and element 0's contact points, added in the order of the full residual)
    /// and the plate's row (the contact load on the plate, which the commit summed). The
    /// force is that of the full residual to round-off, without a pass over every element
    /// (the strain energy it also gave is computed when asked, [`AirSpring::strain_energy`]).
    /// Called by the accept, whose work vectors hold the committed state already (what
    /// [`AirSpring::reaction`] fills them with: the same coordinates, rates and plate motion).
    fn reaction_rows(&mut self) -> Result<f64, ModelError> {
        let (p_g, _) =
            Pressure::Step(0.0).gauge(&self.gas, self.ambient, self.gas.membrane_volume())?;
        let w = &self.work;
        let els = &self.main.elements;
        let mut fe = SVector::<f64, 4>::zeros();
        let s = ElementState {
            q: els.gather(0, &w.q),
            v: els.gather(0, &w.v),
            frames: &[],
        };
        els.element(0)
            .residual_into(&s, &els.gather(0, &w.a), &Vector3::zeros(), &mut fe, None);
        let mut f1 = 0.0 + fe[1];
        if let Some(h) = &self.main.hinges {
            let mut fh = SVector::<f64, 6>::zeros();
            let s = ElementState {
                q: h.gather(0, &w.q),
                v: h.gather(0, &w.v),
                frames: &[],
            };
            h.element(0)
                .residual_into(&s, &h.gather(0, &w.a), &Vector3::zeros(), &mut fh, None);
            f1 += fh[1];
        }
        let (_, ge, _) = frustum_volume(&s.q);
        f1 -= p_g * ge[1];
        let mut rows = [0.0, f1, 0.0, 0.0];
        self.main
            .contact
            .subtract_element_forces(0, &w.q, &w.v, &mut rows);
        let plate = self.main.contact.loads()[PLATE_OBSTACLE].generalized[0];
        let force = -(rows[1] - plate);
        self.kinetic = self.kinetic_energy(&w.q, &w.v);
        if !force.is_finite() {
            return Err(ModelError::NonFinite);
        }
        self.strain.set(None);
        Ok(force)
    }

    fn value(&self, o: Output) -> f64 {
        if let Some(v) = gas_output(o, &self.gas, self.v_charge) {
            return v;
        }
        let e = self.gas.committed();
        match o {
            Output::TopFz => {
                let dz = self.plate.motion(self.t).0 - self.height;
                if dz == 0.0 {
                    self.force
                } else {
                    self.force + self.condensed().map_or(0.0, |c| c.dfdh) * dz
                }
            }
            Output::Height => self.height,
            Output::EffectiveArea => {
                if e.p_gauge != 0.0 {
                    self.force / e.p_gauge
                } else {
                    f64::NAN
                }
            }
            Output::VolumetricArea => self.condensed().map_or(f64::NAN, |c| c.dvdh),
            Output::Stiffness => self.condensed().map_or(f64::NAN, |c| -c.dfdh),
            Output::LobeRadius => self.lobe_radius(),
            Output::StrainEnergy => self.strain_energy(),
            Output::KineticEnergy => self.kinetic,
            Output::PlateWork => self.plate_work,
            Output::Dissipated => e.heat_out + e.loss_work + self.contact_loss,
            // the gas's outputs are above
            _ => f64::NAN,
        }
    }
}

impl MechanicalSystem for AirSpring {
    fn n_free(&self) -> usize {
        self.main.asm.dofs.n_free()
    }

    fn pattern(&self) -> &CscPattern {
        self.main.pattern()
    }

    fn scales(&self) -> &[f64] {
        &self.main.scales
    }

    fn rank_one(&self) -> bool {
        true
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
        // Before the first accepted state (the consistent initial accelerations after the
        // static solve) the gas is at rest in the static state the solve used: its committed
        // state is still the design charge, whose step law would give another pressure off
        // the design height with the energy law or a reservoir (the spring would start out
        // of equilibrium and ring).
        let mode = if self.statics || !self.initialized {
            Pressure::Static
        } else {
            Pressure::Step((t - self.t).max(0.0))
        };
        self.fill_work(t, load_factor, q, v, a);
        self.evaluate_filled(mode, r, jac)
    }

    /// The plain implicit midpoint rule: the residual at `(q_a + q_b)/2` and the midpoint time
    /// (the gas over half the step), the stiffness coefficient halved.
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
        let mut qm = std::mem::take(&mut self.midpoint);
        for ((m, x), y) in qm.iter_mut().zip(q_a).zip(q_b) {
            *m = 0.5 * (x + y);
        }
        let tm = 0.5 * (t_a + t_b);
        let jac = jac.map(|(c, vals)| {
            (
                JacobianCoeffs {
                    stiffness: 0.5 * c.stiffness,
                    ..c
                },
                vals,
            )
        });
        self.fill_work(tm, 1.0, &qm, v, a);
        self.midpoint = qm;
        self.evaluate_filled(Pressure::Step((tm - self.t).max(0.0)), r, jac)?;
        // the step commits the gas at the end volume: it must exist there too
        self.fill_work(t_b, 1.0, q_b, v, a);
        let vb = volume_gradient(self.n_el, &self.work.q, &mut self.work.grad);
        Pressure::Step((t_b - self.t).max(0.0))
            .gauge(&self.gas, self.ambient, vb)
            .map(|_| ())
    }

    /// The quasi-static predictor: the membrane follows the prescribed plate, so the shape at
    /// the end of the step is extrapolated in the plate height `z` (not in time) through the
    /// last three commits (quadratic Lagrange interpolation in `z`). The plate's input is
    /// piecewise linear in time (a velocity jump at every communication step), which the
    /// integrator's Taylor predictor in time carries into the next step; in `z` the shape is
    /// smooth. 60 elements, the 2 Hz sine of `examples/bench_air_spring.rs`: the first Newton
    /// increment is below the tolerance in a quarter of the steps (median 5.6e-8, against
    /// 4.7e-8 for the integrator's, whose 10 % quantile is 1.2e-8). Left to the integrator's
    /// predictor: fewer than three commits since the last jump of the shape, the plate at rest
    /// or turning (the heights not monotone), or a step more than three times the last ones.
    fn predict(&mut self, _q0: &[f64], _v0: &[f64], h: f64, q1: &mut [f64]) -> bool {
        if self.n_history < 3 || self.statics {
            return false;
        }
        let [za, zb, zc] = self.history_z;
        let z1 = self.plate_motion(self.t + h, 1.0).0;
        let (d1, d0, dm) = (z1 - za, za - zb, zb - zc);
        // monotone heights (a step of either sign is fine), at most 3 times the last spacings
        let monotone = (d1 > 0.0 && d0 > 0.0 && dm > 0.0) || (d1 < 0.0 && d0 < 0.0 && dm < 0.0);
        let weights = if monotone && d1.abs() <= 3.0 * d0.abs().min(dm.abs()) {
            lagrange3([za, zb, zc], z1)
        } else if self.quasi_static {
            // Quasi-static steps: the plate at rest or turning, the shape a smooth function of
            // time through the equilibria (the same extrapolation in t).
            let [ta, tb, tc] = self.history_t;
            let t1 = self.t + h;
            if !(ta > tb && tb > tc) || t1 - ta > 3.0 * (ta - tb).min(tb - tc) {
                return false;
            }
            lagrange3([ta, tb, tc], t1)
        } else {
            return false;
        };
        let [la, lb, lc] = weights;
        let [qa, qb, qc] = &self.history_q;
        for i in 0..q1.len() {
            q1[i] = la * qa[i] + lb * qb[i] + lc * qc[i];
        }
        true
    }

    /// A kept matrix holds the penalty blocks of the points that were in contact when it was
    /// built.
    fn kept_matrix_current(&self) -> bool {
        self.main.contact.matrix_is_current()
    }

    /// The prediction moves the shape along the path the kept matrix was computed on.
    fn prediction_keeps_matrix(&self) -> bool {
        true
    }

    /// With the quasi-static predictor most steps start within the tolerance of the solution.
    fn trusts_kept_contraction(&self) -> bool {
        true
    }

    /// A kept matrix that contracts slowly is not trusted: rebuilt for the next step.
    fn rebuilds_slow_kept_matrix(&self) -> bool {
        true
    }

    /// The wall is held by the bead and the clamp, the plate's motion is prescribed and the
    /// gas pressure inflates it: every coordinate has its equilibrium, inertia is optional.
    fn set_quasi_static(&mut self, on: bool) -> bool {
        self.quasi_static = on;
        true
    }

    /// The static solve moves the plate from the last equilibrium (the design height, or the
    /// start `top.z` the spring was moved to) to `top.z` with its load factor.
    fn hold_for_statics(&mut self, held: bool) {
        self.statics = held;
        if held {
            self.static_from = self.height;
        }
    }
}

impl Model for AirSpring {
    /// Quasi-static steps spread a jump of the position input over the communication step
    /// ([`AirSpring::plate_motion`]).
    fn begin_communication_step(&mut self, t0: f64, t1: f64) {
        let dz = self.height - self.plate.motion(t0).0;
        self.input_jump =
            (self.quasi_static && !self.statics && t1 > t0 && dz != 0.0).then_some((t0, t1, dz));
    }

    /// The meridian on both sides of the axis (drawn in the x–z plane), the top plate and
    /// the piston's top between the clamps.
    fn sketch(&self) -> crate::model::Sketch {
        let mut s = crate::model::Sketch::new(format!(
            "{} axisymmetric cord-rubber membrane elements on the meridian, {} nodes (r, z)",
            self.n_el,
            self.n_el + 1
        ));
        let m = self.meridian();
        for side in [1.0, -1.0] {
            s.line(m.iter().map(|p| Vector3::new(side * p[0], 0.0, p[1])));
        }
        let w = 1.15 * self.bead_radius;
        s.line([
            Vector3::new(-w, 0.0, self.height),
            Vector3::new(w, 0.0, self.height),
        ]);
        let [rc, zc] = self.clamp;
        if self.convoluted {
            // the bottom plate and the girdle ring
            s.line([Vector3::new(-w, 0.0, 0.0), Vector3::new(w, 0.0, 0.0)]);
            if let Some((k, rg)) = self.girdle {
                let z = self.q[2 * k + 1];
                for side in [1.0, -1.0] {
                    s.line([
                        Vector3::new(side * rg, 0.0, z),
                        Vector3::new(side * 1.05 * rg, 0.0, z),
                    ]);
                }
            }
        } else {
            s.line([Vector3::new(-rc, 0.0, zc), Vector3::new(rc, 0.0, zc)]);
        }
        s
    }

    /// Before the first accepted state, a new `top.z` moves the charged spring there
    /// quasi-statically with the gas at rest (the static solve of the initialization then
    /// starts in equilibrium).
    fn set_input(&mut self, input: usize, value: f64) {
        match self.inputs[input] {
            Input::TopZ if !self.initialized && value != self.height && value.is_finite() => {
                let from = (self.height, self.pressure_now);
                if self.continuation(from, (value, 0.0), true).is_err() {
                    // left at the last equilibrium; the static solve of the initialization
                    // tries from there
                    self.plate.set(Input::TopZ, value, self.t);
                }
            }
            i => self.plate.set(i, value, self.t),
        }
    }

    fn set_input_derivative(
        &mut self,
        input: usize,
        order: usize,
        value: f64,
    ) -> Result<(), String> {
        self.plate.set_derivative(self.inputs[input], order, value);
        Ok(())
    }

    fn output(&self, output: usize) -> f64 {
        self.value(self.outputs[output])
    }

    fn output_derivative(&self, output: usize) -> Option<f64> {
        match self.outputs[output] {
            Output::Height => Some(self.plate.motion(self.t).1),
            Output::TopFz => {
                let vz = self.plate.motion(self.t).1;
                self.condensed().map(|c| c.dfdh * vz)
            }
            _ => None,
        }
    }

    fn output_input_derivative(&mut self, output: usize, input: usize) -> Option<f64> {
        match (self.outputs[output], self.inputs[input]) {
            (Output::TopFz, Input::TopZ) => self.condensed().map(|c| c.dfdh),
            (Output::TopFz, Input::TopVz) => {
                let lever = self.plate.velocity_lever(self.t);
                self.condensed().map(|c| c.dfdh * lever)
            }
            _ => None,
        }
    }

    fn hold_prescribed_motion(&mut self, hold: bool) {
        self.hold = hold;
    }

    /// `top.z` and `top.vz` are set at every communication step as a smooth motion: the
    /// integrator keeps its accelerations. At a held plate position the residual of the free
    /// coordinates does not depend on the inputs (no damping acts on the plate velocity), so a
    /// restart would only recompute the accelerations the integrator has (and cost a
    /// factorization of the mass matrix per communication step, which also throws away the
    /// kept iteration matrix of modified Newton).
    fn input_restarts_accelerations(&self, _input: usize) -> bool {
        false
    }

    fn accept(&mut self, state: &mut DynState) {
        let dt = (state.t - self.t).max(0.0);
        let lambda = 1.0;
        self.fill_work(state.t, lambda, &state.q, &state.v, &state.acc);
        let mut q = std::mem::take(&mut self.work.q);
        let vm = volume_gradient(self.n_el, &q, &mut self.work.grad);
        let committed = if self.initialized {
            self.gas.commit(dt, vm).map(|_| ())
        } else {
            self.gas.set_static(vm)
        };
        if let Err(e) = committed {
            // the step was accepted by the solver with a gas state the residual evaluated;
            // a failure here is a broken invariant of the gas component
            debug_assert!(false, "gas commit failed: {e}");
        }
        self.q.copy_from_slice(&q);
        std::mem::swap(&mut self.work.q, &mut q);
        self.v.copy_from_slice(&self.work.v);
        let old_force = self.force;
        let old_height = self.height;
        self.t = state.t;
        self.height = self.q[1];
        // frictionless (`contact.mu = 0`, fixed for the model's life): the obstacles read no
        // history, so the commit books the loads only; without damping either, the book has
        // no energy terms the model reads, and of the loads only the top plate's
        // ([`AirSpring::reaction_rows`])
        let law = self.main.contact.law();
        let book = if law.mu == 0.0 {
            let only = (law.d_n == 0.0).then_some(PLATE_OBSTACLE);
            self.main.contact.commit_loads(&self.q, &self.v, only)
        } else {
            self.main.contact.commit(&self.q, &self.v, false)
        };
        self.contact_loss +=
            0.5 * (self.last_damping_power + book.dissipation) * dt + book.friction_work;
        self.last_damping_power = book.dissipation;
        self.force = self.reaction_rows().unwrap_or(f64::NAN);
        if self.initialized {
            self.plate_work -= 0.5 * (old_force + self.force) * (self.height - old_height);
        }
        self.initialized = true;
        self.commits += 1;
        self.history_q.rotate_right(1);
        self.history_z.rotate_right(1);
        self.history_t.rotate_right(1);
        self.main.asm.dofs.restrict(&self.q, &mut self.history_q[0]);
        self.history_z[0] = self.height;
        self.history_t[0] = self.t;
        self.n_history = (self.n_history + 1).min(3);
    }

    fn free_state(&self, q: &mut [f64], v: &mut [f64]) {
        self.main.asm.dofs.restrict(&self.q, q);
        self.main.asm.dofs.restrict(&self.v, v);
    }

    fn constant_mass(&self) -> bool {
        true
    }

    fn save(&self, w: &mut StateWriter) -> Result<(), String> {
        w.f64(self.t);
        w.f64s(&self.q);
        w.f64s(&self.v);
        self.plate.save(w);
        w.bool(self.initialized);
        for x in [
            self.force,
            self.height,
            self.strain_energy(),
            self.kinetic,
            self.plate_work,
            self.contact_loss,
            self.last_damping_power,
        ] {
            w.f64(x);
        }
        self.main.contact.save(w);
        self.gas.save(w);
        // the predictor's history: a restored run predicts as the original one
        w.u64(self.n_history as u64);
        w.f64s(&self.history_z);
        w.f64s(&self.history_t);
        for q in &self.history_q {
            w.f64s(q);
        }
        Ok(())
    }

    fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        self.t = r.f64().map_err(e)?;
        let n = self.q.len();
        self.q = r.f64s(Some(n)).map_err(e)?;
        self.v = r.f64s(Some(n)).map_err(e)?;
        self.plate = PlateInput::restore(r).map_err(e)?;
        self.initialized = r.bool().map_err(e)?;
        let mut strain = 0.0;
        for x in [
            &mut self.force,
            &mut self.height,
            &mut strain,
            &mut self.kinetic,
            &mut self.plate_work,
            &mut self.contact_loss,
            &mut self.last_damping_power,
        ] {
            *x = r.f64().map_err(e)?;
        }
        self.strain.set(Some(strain));
        self.main.contact.restore(r)?;
        self.gas.restore(r).map_err(e)?;
        self.n_history = (r.u64().map_err(e)? as usize).min(3);
        r.f64s_into(&mut self.history_z).map_err(e)?;
        r.f64s_into(&mut self.history_t).map_err(e)?;
        for q in self.history_q.iter_mut() {
            r.f64s_into(q).map_err(e)?;
        }
        // the condensation of the restored state is computed when asked
        self.commits += 1;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;
    use crate::variables::Value;

    /// The reaction the accept takes from two rows is the reaction of the full residual, on a
    /// wall with bending hinges, moving, with accelerations, along 40 steps of a fast
    /// compression (the lobe rolling onto the piston).
    #[test]
    fn reaction_from_rows_is_the_full_reaction() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/air_spring_axisym.toml");
        let scene = Scene::from_path(&path).unwrap();
        let tables: &AirSpringScene = scene.tables().unwrap();
        let mut p = ParamValues::defaults(&scene.params);
        p.set(BELLOWS_BENDING_STIFFNESS, Value::Real(0.05));
        p.set(MESH_N_MERIDIONAL, Value::Integer(30));
        let mut m = AirSpring::build(tables, &p).unwrap();
        let n = m.n_free();
        let mut state = DynState::zeros(n, 0.0);
        m.free_state(&mut state.q, &mut state.v);
        m.accept(&mut state);
        let iz = m.inputs.iter().position(|i| *i == Input::TopZ).unwrap();
        let ivz = m.inputs.iter().position(|i| *i == Input::TopVz).unwrap();
        for k in 0..40 {
            let t = 1e-3 * k as f64;
            m.set_input(iz, 0.25 - 0.5 * t);
            m.set_input(ivz, -0.5);
            // a nearby state: shape of the last commit, some velocity and acceleration
            let mut s = DynState::zeros(n, t + 1e-3);
            m.free_state(&mut s.q, &mut s.v);
            for i in 0..n {
                s.v[i] = 0.01 * ((i * 7) % 5) as f64 - 0.02;
                s.acc[i] = 3.0 * ((i * 3) % 7) as f64 - 9.0;
            }
            m.accept(&mut s);
            let rows = m.force;
            let full = m.reaction(&s.acc).unwrap();
            assert!(
                (rows - full).abs() <= 1e-12 * full.abs(),
                "step {k}: {rows} from the rows, {full} from the full residual"
            );
            // the strain energy asked after the commit is the full residual's
            m.strain.set(None);
            let lazy = m.strain_energy();
            assert!((lazy - m.last_strain).abs() <= 1e-12 * m.last_strain.abs());
        }
    }
}
