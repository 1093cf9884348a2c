//! A straight planar beam meshed with seed-000 shear-deformable ANCF elements or with ANCF
//! cable elements (`element.type`): supports, point loads, gravity, probes and energies. Both
//! elements have 4 coordinates per node, the position first (seed 000: position and
//! cross-section gradient `r_y`; cable: position and axial slope `r'`), so the mesh, the
//! supports of positions, the loads, probes and motion ports share one numbering.

use crate::assembly::{Assembly, DofMap, ElementSet, Eval, check_finite};
use crate::elements::ancf_cable2d::{self, AncfCable2d, CableRule, CableSection};
use crate::elements::ancf_shear2d::{
    ELEMENT_COORDS, ElemMat, ElemVec, NODE_COORDS, Section, Shear2dElement, ShearRule,
};
use crate::elements::material::{PlaneElasticity, StrainEnergy};
use crate::elements::{Element, ElementState};
use crate::integrators::DynState;
use crate::kinds::KindIo;
use crate::kinds::beam_2d::scene::{Input, Output, io};
use crate::kinds::beam_2d::{Beam2dElementType, Beam2dScene};
use crate::kinds::energy::EnergyKind;
use crate::linalg::CscPattern;
use crate::meshers::stations::{ElementPoint, Stations};
use crate::model::inputs::InputSignal;
use crate::model::ports::{PortHost, Ports};
use crate::model::{JacobianCoeffs, MechanicalSystem, Model, ModelError};
use crate::scene::params::{ParamValues, names::*};
use crate::scene::tables::{Axis, ProbeQuantity, SupportKind};
use crate::snapshot::{StateReader, StateWriter};
use nalgebra::{Vector2, Vector3};
use std::sync::Arc;

/// The element of every element of the mesh (one shared element: the mesh is uniform).
type PlanarElement = Arc<dyn Element<ELEMENT_COORDS>>;

/// Interpolation of a centre-line point of element `e` at `ξ = x/L_e`: weights on the x
/// coordinates of the element's nodes (y is the next index). Seed 000: nodes `e`, `e + 1` with
/// `1 − ξ`, `ξ` on their positions (the gradient terms vanish at y = 0; Kerkkänen et al. 2003,
/// Eq. 3). Cable: the cubic Hermite functions `S1..S4` on `r_e, r'_e, r_{e+1}, r'_{e+1}`
/// (`ancf_cable2d::shape_functions`). A point load `F` is `Sᵀ F` with the same weights.
#[derive(Clone, Copy, Debug)]
struct PointMap {
    weights: [(usize, f64); 4],
    len: usize,
}

impl PointMap {
    fn new(p: ElementPoint, element: Beam2dElementType, le: f64) -> Self {
        let (a, b) = (p.element * NODE_COORDS, (p.element + 1) * NODE_COORDS);
        match element {
            Beam2dElementType::AncfShear2d => Self {
                weights: [(a, 1.0 - p.xi), (b, p.xi), (0, 0.0), (0, 0.0)],
                len: 2,
            },
            Beam2dElementType::AncfCable2d => {
                let s = ancf_cable2d::shape_functions(le, p.xi * le);
                Self {
                    weights: [(a, s[0]), (a + 2, s[1]), (b, s[2]), (b + 2, s[3])],
                    len: 4,
                }
            }
        }
    }

    /// `(full index, weight)` of the x component; y is the next index.
    fn weights(&self) -> &[(usize, f64)] {
        &self.weights[..self.len]
    }

    fn eval(&self, full: &[f64], axis: usize) -> f64 {
        self.weights().iter().map(|(i, w)| w * full[i + axis]).sum()
    }
}

/// The planar beam model.
#[derive(Clone, Debug)]
pub struct Beam2d {
    length: f64,
    /// Element family (`element.type`).
    element: Beam2dElementType,
    set: ElementSet<PlanarElement, ELEMENT_COORDS>,
    asm: Assembly,
    gravity_full: Vec<f64>,
    q0: Vec<f64>,
    load_maps: Vec<PointMap>,
    loads: Vec<[InputSignal; 2]>,
    /// Motion ports (the two position coordinates of a node each): inputs x, y [m],
    /// vx, vy [m/s], their interface Jacobian and reactions.
    ports: Ports,
    probes: Vec<PointMap>,
    scales: Vec<f64>,
    /// What each input and output means, by index.
    roles: KindIo<Input, Output>,
    // committed state (outputs are computed from it)
    t: f64,
    q: Vec<f64>,
    v: Vec<f64>,
    acc: Vec<f64>,
    // work buffers
    qw: Vec<f64>,
    qw2: Vec<f64>,
    vw: Vec<f64>,
    aw: Vec<f64>,
    fw: Vec<f64>,
}

impl Beam2d {
    /// Builds the model of a scene with the given parameter values (already validated).
    /// Errors name the scene key or parameter at fault.
    pub fn build(scene: &Beam2dScene, p: &ParamValues) -> Result<Self, String> {
        let geometry = &scene.geometry;
        let n_el = p.integer(MESH_N_ELEMENTS) as usize;
        let element = Beam2dElementType::from_code(p.integer(ELEMENT_TYPE))
            .ok_or_else(|| format!("{ELEMENT_TYPE}: 1 or 2"))?;
        let length = p.real(GEOMETRY_LENGTH);
        let section = Section {
            width: p.real(GEOMETRY_WIDTH),
            height: p.real(GEOMETRY_HEIGHT),
        };
        let rule = match p.integer(ELEMENT_SHEAR_RULE) {
            1 => ShearRule::Original1x1,
            _ => ShearRule::Fixed1x2,
        };
        let form = match p.integer(ELEMENT_STRAIN_ENERGY) {
            2 => StrainEnergy::Lame,
            _ => StrainEnergy::Decoupled,
        };
        let law = PlaneElasticity::new(
            p.real(MATERIAL_E),
            p.real(MATERIAL_NU),
            p.real(ELEMENT_SHEAR_COEFFICIENT),
            form,
        );
        let rho = p.real(MATERIAL_RHO);
        let gravity = Vector2::new(
            p.get(GRAVITY_X).map_or(0.0, |_| p.real(GRAVITY_X)),
            p.get(GRAVITY_Y).map_or(0.0, |_| p.real(GRAVITY_Y)),
        );

        let n_nodes = n_el + 1;
        let n_full = n_nodes * NODE_COORDS;
        let theta = geometry.angle_deg.to_radians();
        let dir = Vector2::new(theta.cos(), theta.sin());
        let normal = Vector2::new(-dir.y, dir.x);
        let origin = Vector2::from(geometry.origin);
        let le = length / n_el as f64;
        // The second pair of node coordinates: the cross-section gradient (the unit normal) of
        // the seed-000 element, the axial slope (the unit tangent) of the cable.
        let grad = match element {
            Beam2dElementType::AncfShear2d => normal,
            Beam2dElementType::AncfCable2d => dir,
        };
        let mut q0 = vec![0.0; n_full];
        for k in 0..n_nodes {
            let r = origin + dir * (le * k as f64);
            q0[k * 4..k * 4 + 4].copy_from_slice(&[r.x, r.y, grad.x, grad.y]);
        }
        // A clamp fixes the position and the direction of the section. Seed 000: the whole
        // cross-section gradient. Cable: the slope component along the normal (the slope's
        // length is the axial stretch, which a clamp leaves free, as Exudyn's ANCF cantilever
        // examples do); that component is one coordinate only for an axis along x or y.
        let cable_clamp = if normal.y.abs() <= 1e-12 {
            Some(2)
        } else if normal.x.abs() <= 1e-12 {
            Some(3)
        } else {
            None
        };

        let stations = Stations::uniform(n_el, length);
        let mut constrained = vec![false; n_full];
        for (i, s) in scene.supports.iter().enumerate() {
            let node = stations.node_at(&format!("supports[{i}]"), s.at, MESH_N_ELEMENTS)?;
            let base = node * NODE_COORDS;
            let fixed: &[usize] = match (s.kind, s.fixed) {
                (SupportKind::Clamp, _) if element == Beam2dElementType::AncfShear2d => {
                    &[0, 1, 2, 3]
                }
                (SupportKind::Clamp, _) => match cable_clamp {
                    Some(2) => &[0, 1, 2],
                    Some(_) => &[0, 1, 3],
                    None => {
                        return Err(format!(
                            "supports[{i}]: a clamp of the ANCF cable ({ELEMENT_TYPE} = 2) needs the beam axis along x or y (geometry.angle_deg a multiple of 90), not {}",
                            geometry.angle_deg
                        ));
                    }
                },
                (SupportKind::Pin, _) => &[0, 1],
                (SupportKind::Roller, Some(Axis::X)) => &[0],
                (SupportKind::Roller, _) => &[1],
            };
            for &c in fixed {
                constrained[base + c] = true;
            }
        }
        let mut port_coords = Vec::with_capacity(scene.motions.len());
        for (i, m) in scene.motions.iter().enumerate() {
            let node = stations.node_at(&format!("motions[{i}]"), m.at, MESH_N_ELEMENTS)?;
            let base = node * NODE_COORDS;
            if constrained[base] || constrained[base + 1] {
                return Err(format!(
                    "motions[{i}].at = {}: the node is already supported (a [[supports]] entry at the same place)",
                    m.at
                ));
            }
            constrained[base] = true;
            constrained[base + 1] = true;
            port_coords.push(vec![base, base + 1]);
        }
        let dofs = DofMap::new(&constrained);
        if dofs.n_free() == 0 {
            return Err("the supports fix every coordinate: nothing left to simulate".into());
        }
        let connectivity: Vec<[usize; ELEMENT_COORDS]> = (0..n_el)
            .map(|e| std::array::from_fn(|i| e * NODE_COORDS + i))
            .collect();
        let asm = Assembly::new(dofs, &[(ELEMENT_COORDS, connectivity.as_flattened())], &[]);

        // A straight mesh of equal elements: one element (its reference data are invariant
        // under the translation from one element to the next) shared by the whole set.
        let degenerate = || {
            format!(
                "degenerate element geometry ({GEOMETRY_LENGTH} = {length} m over {MESH_N_ELEMENTS} = {n_el}, {GEOMETRY_WIDTH} = {} m, {GEOMETRY_HEIGHT} = {} m)",
                section.width, section.height
            )
        };
        let el: PlanarElement = match element {
            Beam2dElementType::AncfShear2d => {
                let e0 = ElemVec::from_fn(|i, _| q0[connectivity[0][i]]);
                Arc::new(
                    Shear2dElement::new(&e0, le, section, rule, law, rho).ok_or_else(degenerate)?,
                )
            }
            Beam2dElementType::AncfCable2d => {
                // Euler–Bernoulli section of a homogeneous rectangle: EA = E b h,
                // EI = E b h³/12, ρA = ρ b h.
                let (e, b, h) = (p.real(MATERIAL_E), section.width, section.height);
                let cable = CableSection {
                    ea: e * b * h,
                    ei: e * b * h.powi(3) / 12.0,
                    mass_per_length: rho * b * h,
                    damping_axial: 0.0,
                    damping_bending: 0.0,
                    prestrain: 0.0,
                };
                if !(le.is_finite() && le > 0.0) {
                    return Err(degenerate());
                }
                Arc::new(AncfCable2d::new(le, cable, CableRule::Full))
            }
        };
        let set = ElementSet::new(vec![el], connectivity, &asm);
        let mut gravity_full = vec![0.0; n_full];
        let g3 = Vector3::new(gravity.x, gravity.y, 0.0);
        set.add_gravity(&q0, None, &g3, 1.0, &mut gravity_full);
        // Initial rigid rotation about the first end: v = ω × (r − r₀) for positions, ω × n for
        // the cross-section gradients.
        let omega = p
            .get(INITIAL_ANGULAR_VELOCITY)
            .map_or(0.0, |_| p.real(INITIAL_ANGULAR_VELOCITY));
        let mut v0 = vec![0.0; n_full];
        for k in 0..n_nodes {
            let b = k * NODE_COORDS;
            let (dx, dy) = (q0[b] - origin.x, q0[b + 1] - origin.y);
            v0[b..b + 4].copy_from_slice(&[
                -omega * dy,
                omega * dx,
                -omega * q0[b + 3],
                omega * q0[b + 2],
            ]);
        }
        for (i, c) in constrained.iter().enumerate() {
            if *c && v0[i] != 0.0 {
                return Err(format!(
                    "{INITIAL_ANGULAR_VELOCITY}: a support at a moving coordinate conflicts with the initial rotation about the first end"
                ));
            }
        }
        let scales = asm
            .dofs
            .free_to_full()
            .iter()
            .map(|&i| if i % 4 < 2 { length } else { 1.0 })
            .collect();
        let load_maps: Vec<PointMap> = scene
            .loads
            .iter()
            .map(|l| PointMap::new(stations.point_at(l.at), element, le))
            .collect();
        let loads = scene
            .loads
            .iter()
            .map(|l| [InputSignal::constant(l.fx), InputSignal::constant(l.fy)])
            .collect();
        // Motion ports start where the node is in the reference configuration, at rest.
        let ports = Ports::new(&port_coords, &q0, p.real(SOLVER_MAX_STEP));
        let probes = scene
            .probes
            .iter()
            .map(|p| PointMap::new(stations.point_at(p.at), element, le))
            .collect();
        Ok(Self {
            length,
            element,
            set,
            asm,
            gravity_full,
            t: 0.0,
            q: q0.clone(),
            v: v0,
            acc: vec![0.0; n_full],
            qw: q0.clone(),
            qw2: q0.clone(),
            vw: vec![0.0; n_full],
            aw: vec![0.0; n_full],
            fw: vec![0.0; n_full],
            q0,
            load_maps,
            loads,
            ports,
            probes,
            scales,
            roles: io(scene),
        })
    }

    /// Body length [m].
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.set.len()
    }

    /// Full coordinate vector of the committed state.
    pub fn coordinates(&self) -> &[f64] {
        &self.q
    }

    /// Reference coordinates.
    pub fn reference_coordinates(&self) -> &[f64] {
        &self.q0
    }

    /// Elements adjacent to a node.
    fn elements_at(&self, node: usize) -> impl Iterator<Item = usize> {
        let n_el = self.set.len();
        [node.checked_sub(1), (node < n_el).then_some(node)]
            .into_iter()
            .flatten()
    }

    /// Computes the interface Jacobian of the motion ports at the committed state unless it
    /// is current ([`Ports::update_interface`]).
    fn update_interface(&mut self) {
        let mut ports = std::mem::take(&mut self.ports);
        ports.update_interface(self);
        self.ports = ports;
    }

    /// An output of the committed state with the current inputs.
    fn output_of(&self, kind: Output) -> f64 {
        match kind {
            Output::Probe { probe, quantity } => {
                let p = &self.probes[probe];
                match quantity {
                    ProbeQuantity::X => p.eval(&self.q, 0),
                    ProbeQuantity::Y => p.eval(&self.q, 1),
                    ProbeQuantity::Vx => p.eval(&self.v, 0),
                    ProbeQuantity::Vy => p.eval(&self.v, 1),
                    // 3D quantities are rejected for planar scenes by `scene::beam2d::check`
                    _ => f64::NAN,
                }
            }
            Output::Energy(k) => match k {
                EnergyKind::Kinetic => self.kinetic_energy(),
                EnergyKind::Potential => self.potential_energy(),
                EnergyKind::Strain => self.strain_energy(),
                EnergyKind::Total => {
                    self.kinetic_energy() + self.potential_energy() + self.strain_energy()
                }
            },
            Output::Reaction { port, axis } => self.ports.force(self, port, axis),
            // not declared by planar beam scenes
        }
    }

    /// `½ vᵀ M v` [J] of the committed state.
    pub fn kinetic_energy(&self) -> f64 {
        self.set.kinetic_energy(&self.q, &self.v, None)
    }

    /// Gravity potential `−Q_gᵀ q` [J] of the committed state.
    pub fn potential_energy(&self) -> f64 {
        -self
            .gravity_full
            .iter()
            .zip(&self.q)
            .map(|(g, q)| g * q)
            .sum::<f64>()
    }

    /// Strain energy [J] of the committed state.
    pub fn strain_energy(&self) -> f64 {
        self.set.strain_energy(&self.q, None)
    }

    /// Time derivatives of the energies: `(dT/dt, dV/dt, dU/dt)` [W] of the committed state.
    fn energy_rates(&self) -> (f64, f64, f64) {
        let (mut dt, mut du) = (0.0, 0.0);
        let mut fe = ElemVec::zeros();
        self.set.for_each_state(&self.q, &self.v, None, |e, el, s| {
            let ae = self.set.gather(e, &self.acc);
            let mut m = ElemMat::zeros();
            el.mass_into(s, &mut m);
            dt += s.v.dot(&(m * ae));
            el.force_into(s, &mut fe);
            du += fe.dot(&s.v);
        });
        let dv = -self
            .gravity_full
            .iter()
            .zip(&self.v)
            .map(|(g, v)| g * v)
            .sum::<f64>();
        (dt, dv, du)
    }

    /// External force (gravity and point loads at time `t`) times `lambda`, added into a full
    /// vector with a minus sign (residual convention).
    fn subtract_external(&self, t: f64, lambda: f64, full: &mut [f64]) {
        for (f, g) in full.iter_mut().zip(&self.gravity_full) {
            *f -= lambda * g;
        }
        for (map, sig) in self.load_maps.iter().zip(&self.loads) {
            let (fx, fy) = (sig[0].at(t), sig[1].at(t));
            for &(i, w) in map.weights() {
                full[i] -= lambda * w * fx;
                full[i + 1] -= lambda * w * fy;
            }
        }
    }

    fn finish(
        &self,
        r: &mut [f64],
        jac: &Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        self.asm.dofs.restrict(&self.fw, r);
        check_finite(r, jac.as_ref().map(|(_, vals)| &**vals))
    }

    /// The signal of an input; planar scenes declare no z forces and no moments (see
    /// `scene::beam2d::check`).
    fn input_signal(&mut self, input: usize) -> &mut InputSignal {
        match self.roles.inputs[input] {
            Input::Load { load, axis } => &mut self.loads[load][axis],
            Input::Motion { port, component } => self.ports.signal_mut(port, component),
        }
    }
}

impl Model for Beam2d {
    /// The centre line through the node positions.
    fn sketch(&self) -> crate::model::Sketch {
        let n = self.n_elements();
        let what = match self.element {
            Beam2dElementType::AncfShear2d => "seed-000 shear-deformable ANCF",
            Beam2dElementType::AncfCable2d => "ANCF cable (Euler-Bernoulli, cubic)",
        };
        let mut s = crate::model::Sketch::new(format!(
            "{n} {what} elements, {} nodes, {} coordinates",
            n + 1,
            self.q.len()
        ));
        s.line_xy((0..=n).map(|k| [self.q[k * NODE_COORDS], self.q[k * NODE_COORDS + 1]]));
        s
    }

    fn set_input(&mut self, input: usize, value: f64) {
        let t = self.t;
        self.input_signal(input).set(value, t);
        if matches!(self.roles.inputs[input], Input::Motion { .. }) {
            self.update_interface();
        }
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
        self.input_signal(input).set_derivative(order, value);
        if matches!(self.roles.inputs[input], Input::Motion { .. }) {
            self.update_interface();
        }
        Ok(())
    }

    fn output(&self, output: usize) -> f64 {
        self.output_of(self.roles.outputs[output])
    }

    fn output_derivative(&self, output: usize) -> Option<f64> {
        Some(match self.roles.outputs[output] {
            Output::Probe { probe, quantity } => {
                let p = &self.probes[probe];
                match quantity {
                    ProbeQuantity::X => p.eval(&self.v, 0),
                    ProbeQuantity::Y => p.eval(&self.v, 1),
                    ProbeQuantity::Vx => p.eval(&self.acc, 0),
                    ProbeQuantity::Vy => p.eval(&self.acc, 1),
                    // planar scenes declare no 3D probe quantities (scene::beam2d::check)
                    _ => return None,
                }
            }
            Output::Energy(k) => {
                let (dt, dv, du) = self.energy_rates();
                match k {
                    EnergyKind::Kinetic => dt,
                    EnergyKind::Potential => dv,
                    EnergyKind::Strain => du,
                    EnergyKind::Total => dt + dv + du,
                }
            }
            // d/dt of the stiffness part of the reaction, K_c: v (inertia rates neglected).
            Output::Reaction { port, axis } => self.ports.force_rate(self, port, axis, &self.v),
        })
    }

    fn output_input_derivative(&mut self, output: usize, input: usize) -> Option<f64> {
        Some(
            match (self.roles.outputs[output], self.roles.inputs[input]) {
                (
                    Output::Reaction { port, axis },
                    Input::Motion {
                        port: p2,
                        component,
                    },
                ) => {
                    let mut ports = std::mem::take(&mut self.ports);
                    let d = ports.force_input_derivative(self, port, axis, p2, component);
                    self.ports = ports;
                    d
                }
                // A load on the port node goes straight into the driver (`port_reaction`).
                (Output::Reaction { port, axis }, Input::Load { load, axis: a2 }) => {
                    let base = self.ports.coords(port)[0];
                    if a2 != axis {
                        return Some(0.0);
                    }
                    self.load_maps[load]
                        .weights()
                        .iter()
                        .filter(|(i, _)| *i == base)
                        .map(|(_, w)| w)
                        .sum()
                }
                _ => 0.0,
            },
        )
    }

    fn constant_mass(&self) -> bool {
        true
    }

    fn hold_prescribed_motion(&mut self, hold: bool) {
        self.ports.hold(hold);
    }

    fn begin_communication_step(&mut self, t0: f64, t1: f64) {
        self.ports.begin_communication_step(t0, t1);
    }

    fn accept(&mut self, state: &mut DynState) {
        self.t = state.t;
        self.asm.dofs.expand(&state.q, &mut self.q);
        self.asm.dofs.expand(&state.v, &mut self.v);
        self.asm.dofs.expand(&state.acc, &mut self.acc);
        let (mut q, mut v, mut a) = (
            std::mem::take(&mut self.q),
            std::mem::take(&mut self.v),
            std::mem::take(&mut self.acc),
        );
        self.ports
            .apply(self.t, 1.0, Some(&mut q), Some(&mut v), Some(&mut a));
        self.ports.commit(self.t, &q, &v);
        (self.q, self.v, self.acc) = (q, v, a);
    }

    fn free_state(&self, q: &mut [f64], v: &mut [f64]) {
        self.asm.dofs.restrict(&self.q, q);
        self.asm.dofs.restrict(&self.v, v);
    }

    fn save(&self, w: &mut StateWriter) -> Result<(), String> {
        w.f64(self.t);
        w.f64s(&self.q);
        w.f64s(&self.v);
        w.f64s(&self.acc);
        for sig in self.loads.iter().flatten() {
            sig.save(w);
        }
        self.ports.save(w);
        Ok(())
    }

    fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        self.t = r.f64().map_err(e)?;
        r.f64s_into(&mut self.q).map_err(e)?;
        r.f64s_into(&mut self.v).map_err(e)?;
        r.f64s_into(&mut self.acc).map_err(e)?;
        for sig in self.loads.iter_mut().flatten() {
            *sig = InputSignal::restore(r).map_err(e)?;
        }
        self.ports.restore(r).map_err(e)?;
        self.ports.commit(self.t, &self.q, &self.v);
        self.update_interface();
        Ok(())
    }
}

impl MechanicalSystem for Beam2d {
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
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        let (mut qw, mut vw, mut aw) = (
            std::mem::take(&mut self.qw),
            std::mem::take(&mut self.vw),
            std::mem::take(&mut self.aw),
        );
        self.asm.dofs.expand(q, &mut qw);
        self.asm.dofs.expand(v, &mut vw);
        self.asm.dofs.expand(a, &mut aw);
        self.ports
            .apply(t, load_factor, Some(&mut qw), Some(&mut vw), Some(&mut aw));
        let mut f = std::mem::take(&mut self.fw);
        f.fill(0.0);
        if let Some((_, vals)) = jac.as_mut() {
            vals.fill(0.0);
        }
        let x = Eval {
            q: &qw,
            v: &vw,
            a: &aw,
            g: Vector3::zeros(),
        };
        self.set
            .add_residual(&x, None, &mut f, jac.as_mut().map(|(c, v)| (*c, &mut **v)));
        self.subtract_external(t, load_factor, &mut f);
        (self.qw, self.vw, self.aw, self.fw) = (qw, vw, aw, f);
        self.finish(r, &jac)
    }

    fn midpoint_residual(
        &mut self,
        t_a: f64,
        t_b: f64,
        q_a: &[f64],
        q_b: &[f64],
        v: &[f64],
        a: &[f64],
        r: &mut [f64],
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        let (mut qa, mut qb, mut vw, mut aw) = (
            std::mem::take(&mut self.qw),
            std::mem::take(&mut self.qw2),
            std::mem::take(&mut self.vw),
            std::mem::take(&mut self.aw),
        );
        self.asm.dofs.expand(q_a, &mut qa);
        self.asm.dofs.expand(q_b, &mut qb);
        self.asm.dofs.expand(v, &mut vw);
        self.asm.dofs.expand(a, &mut aw);
        let t_mid = 0.5 * (t_a + t_b);
        self.ports.apply(t_a, 1.0, Some(&mut qa), None, None);
        self.ports.apply(t_b, 1.0, Some(&mut qb), None, None);
        self.ports
            .apply(t_mid, 1.0, None, Some(&mut vw), Some(&mut aw));
        let mut f = std::mem::take(&mut self.fw);
        f.fill(0.0);
        if let Some((_, vals)) = jac.as_mut() {
            vals.fill(0.0);
        }
        // the average-stress form of the seed-000 element: exactly energy conserving; the
        // cable has none and takes the plain midpoint rule (`ElementSet::add_midpoint_residual`)
        let x = Eval {
            q: &qb,
            v: &vw,
            a: &aw,
            g: Vector3::zeros(),
        };
        self.set.add_midpoint_residual(
            &qa,
            &qb,
            &x,
            &mut f,
            jac.as_mut().map(|(c, v)| (*c, &mut **v)),
        );
        self.subtract_external(t_mid, 1.0, &mut f);
        (self.qw, self.qw2, self.vw, self.aw, self.fw) = (qa, qb, vw, aw, f);
        self.finish(r, &jac)
    }
}

/// The rows and free–free matrix of the beam at its motion ports (two position coordinates of
/// a node each), at the committed state.
impl PortHost for Beam2d {
    fn free_index(&self, full: usize) -> Option<usize> {
        self.asm.dofs.free_index(full)
    }

    /// `(M a + f_int − f_ext)` at the port node's two position coordinates, summed over the
    /// adjacent elements.
    fn port_residual(&self, coords: &[usize], out: &mut [f64]) {
        let base = coords[0];
        let node = base / NODE_COORDS;
        let mut r = [0.0; 2];
        let mut fe = ElemVec::zeros();
        for e in self.elements_at(node) {
            let s = ElementState::new(self.set.gather(e, &self.q), ElemVec::zeros());
            let ae = self.set.gather(e, &self.acc);
            let el = self.set.element(e);
            el.force_into(&s, &mut fe);
            let mut m = ElemMat::zeros();
            el.mass_into(&s, &mut m);
            fe += m * ae;
            let local = if self.set.element_dofs(e)[0] == base {
                0
            } else {
                4
            };
            r[0] += fe[local];
            r[1] += fe[local + 1];
        }
        let mut ext = [0.0; 2];
        for axis in 0..2 {
            ext[axis] += self.gravity_full[base + axis];
        }
        for (map, sig) in self.load_maps.iter().zip(&self.loads) {
            for &(i, w) in map.weights() {
                if i == base {
                    ext[0] += w * sig[0].at(self.t);
                    ext[1] += w * sig[1].at(self.t);
                }
            }
        }
        out[0] = r[0] - ext[0];
        out[1] = r[1] - ext[1];
    }

    /// Rows of `K_T + c_m M` of the adjacent elements, element after element.
    fn port_rows(&self, coords: &[usize], c_m: f64, add: &mut dyn FnMut(usize, usize, f64)) {
        let base = coords[0];
        let node = base / NODE_COORDS;
        let (mut fe, mut ke) = (ElemVec::zeros(), ElemMat::zeros());
        for e in self.elements_at(node) {
            let s = ElementState::new(self.set.gather(e, &self.q), ElemVec::zeros());
            let el = self.set.element(e);
            el.tangent_into(&s, &mut fe, &mut ke, None);
            let mut m = ElemMat::zeros();
            el.mass_into(&s, &mut m);
            ke += c_m * m;
            let dofs = self.set.element_dofs(e);
            let local = if dofs[0] == base { 0 } else { 4 };
            for (j, &col) in dofs.iter().enumerate() {
                add(0, col, ke[(local, j)]);
                add(1, col, ke[(local + 1, j)]);
            }
        }
    }

    fn free_matrix(&mut self, c_m: f64, vals: &mut [f64]) {
        let mut f = std::mem::take(&mut self.fw);
        f.fill(0.0);
        let coeffs = JacobianCoeffs {
            mass: c_m,
            damping: 0.0,
            stiffness: 1.0,
        };
        let x = Eval {
            q: &self.q,
            v: &self.v,
            a: &self.acc,
            g: Vector3::zeros(),
        };
        self.set
            .add_residual(&x, None, &mut f, Some((coeffs, vals)));
        self.fw = f;
    }
}
