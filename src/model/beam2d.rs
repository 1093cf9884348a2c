//! A straight planar beam meshed with seed-000 elements: supports, point loads, gravity,
//! probes and energies.

use super::system::{JacobianCoeffs, MechanicalSystem, Model, ModelError};
use crate::assembly::{Assembly, DofMap};
use crate::elements::ancf_shear2d::{
    AncfShear2d, ElemMat, ElemVec, NODE_COORDS, Section, ShearRule,
};
use crate::elements::material::{PlaneElasticity, StrainEnergy};
use crate::integrators::DynState;
use crate::linalg::CscPattern;
use crate::scene::file::{Axis, ProbeQuantity, SceneFile, SupportKind};
use crate::scene::params::{ParamValues, names::*};
use crate::variables::{EnergyKind, InputKind, OutputKind};
use nalgebra::Vector2;

/// Interpolation of a centre-line point: nodes `a`, `a + 1` with weights `1 − ξ`, `ξ` on their
/// positions (the gradient terms vanish at y = 0).
#[derive(Clone, Copy, Debug)]
struct PointMap {
    node: usize,
    xi: f64,
}

impl PointMap {
    fn new(at: f64, n_el: usize) -> Self {
        let s = at * n_el as f64;
        let e = (s.floor() as usize).min(n_el - 1);
        Self {
            node: e,
            xi: s - e as f64,
        }
    }

    /// `(full index, weight)` of the x component; y is the next index.
    fn weights(&self) -> [(usize, f64); 2] {
        [
            (self.node * NODE_COORDS, 1.0 - self.xi),
            ((self.node + 1) * NODE_COORDS, self.xi),
        ]
    }

    fn eval(&self, full: &[f64], axis: usize) -> f64 {
        self.weights().iter().map(|(i, w)| w * full[i + axis]).sum()
    }
}

/// The seed-000 beam model.
#[derive(Clone, Debug)]
pub struct Beam2d {
    length: f64,
    elements: Vec<AncfShear2d>,
    mass_elem: Vec<ElemMat>,
    law: PlaneElasticity,
    asm: Assembly,
    mass_vals: Vec<f64>,
    gravity_full: Vec<f64>,
    q0: Vec<f64>,
    loads: Vec<PointMap>,
    load_values: Vec<[f64; 2]>,
    probes: Vec<PointMap>,
    scales: Vec<f64>,
    // committed state (outputs are computed from it)
    q: Vec<f64>,
    v: Vec<f64>,
    // work buffers
    qw: Vec<f64>,
    qw2: Vec<f64>,
    aw: Vec<f64>,
    fw: Vec<f64>,
}

impl Beam2d {
    /// Builds the model of a scene with the given parameter values (already validated).
    /// Errors name the scene key or parameter at fault.
    pub fn build(scene: &SceneFile, p: &ParamValues) -> Result<Self, String> {
        let geometry = scene.geometry.as_ref().ok_or("[geometry] missing")?;
        let n_el = p.integer(MESH_N_ELEMENTS) as usize;
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
        let mut q0 = vec![0.0; n_full];
        for k in 0..n_nodes {
            let r = origin + dir * (le * k as f64);
            q0[k * 4..k * 4 + 4].copy_from_slice(&[r.x, r.y, normal.x, normal.y]);
        }

        let mut constrained = vec![false; n_full];
        for (i, s) in scene.supports.iter().enumerate() {
            let pos = s.at * n_el as f64;
            let node = pos.round();
            if (pos - node).abs() > 1e-9 * n_el as f64 {
                return Err(format!(
                    "supports[{i}].at = {}: a support must fall on a node; with {MESH_N_ELEMENTS} = {n_el} the nodes are at multiples of 1/{n_el}",
                    s.at
                ));
            }
            let base = node as usize * NODE_COORDS;
            let fixed: &[usize] = match (s.kind, s.fixed) {
                (SupportKind::Clamp, _) => &[0, 1, 2, 3],
                (SupportKind::Pin, _) => &[0, 1],
                (SupportKind::Roller, Some(Axis::X)) => &[0],
                (SupportKind::Roller, _) => &[1],
            };
            for &c in fixed {
                constrained[base + c] = true;
            }
        }
        let dofs = DofMap::new(&constrained);
        if dofs.n_free() == 0 {
            return Err("the supports fix every coordinate: nothing left to simulate".into());
        }
        let element_dofs: Vec<usize> = (0..n_el).flat_map(|e| e * 4..e * 4 + 8).collect();
        let asm = Assembly::new(dofs, 8, element_dofs, &[]);

        let mut elements = Vec::with_capacity(n_el);
        let mut mass_elem = Vec::with_capacity(n_el);
        let mut gravity_full = vec![0.0; n_full];
        let mut mass_vals = vec![0.0; asm.pattern.nnz()];
        for e in 0..n_el {
            let e0: ElemVec = asm.gather(e, &q0);
            let el = AncfShear2d::new(&e0, le, section, rule)
                .ok_or_else(|| format!("element {e}: degenerate reference geometry"))?;
            let m = el.mass(&e0, rho);
            asm.add_matrix(e, &m, 1.0, &mut mass_vals);
            asm.add_vector(e, &el.gravity(&e0, rho, gravity), 1.0, &mut gravity_full);
            mass_elem.push(m);
            elements.push(el);
        }
        let scales = asm
            .dofs
            .free_to_full()
            .iter()
            .map(|&i| if i % 4 < 2 { length } else { 1.0 })
            .collect();
        let loads: Vec<PointMap> = scene
            .loads
            .iter()
            .map(|l| PointMap::new(l.at, n_el))
            .collect();
        let load_values = scene.loads.iter().map(|l| [l.fx, l.fy]).collect();
        let probes = scene
            .probes
            .iter()
            .map(|p| PointMap::new(p.at, n_el))
            .collect();
        Ok(Self {
            length,
            elements,
            mass_elem,
            law,
            asm,
            mass_vals,
            gravity_full,
            q: q0.clone(),
            v: vec![0.0; n_full],
            qw: q0.clone(),
            qw2: q0.clone(),
            aw: vec![0.0; n_full],
            fw: vec![0.0; n_full],
            q0,
            loads,
            load_values,
            probes,
            scales,
        })
    }

    /// Body length [m].
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.elements.len()
    }

    /// Full coordinate vector of the committed state.
    pub fn coordinates(&self) -> &[f64] {
        &self.q
    }

    /// Reference coordinates.
    pub fn reference_coordinates(&self) -> &[f64] {
        &self.q0
    }

    /// An output of the committed state.
    fn output_of(&self, kind: OutputKind) -> f64 {
        match kind {
            OutputKind::Probe { probe, quantity } => {
                let p = &self.probes[probe];
                match quantity {
                    ProbeQuantity::X => p.eval(&self.q, 0),
                    ProbeQuantity::Y => p.eval(&self.q, 1),
                    ProbeQuantity::Vx => p.eval(&self.v, 0),
                    ProbeQuantity::Vy => p.eval(&self.v, 1),
                }
            }
            OutputKind::Energy(k) => match k {
                EnergyKind::Kinetic => self.kinetic_energy(),
                EnergyKind::Potential => self.potential_energy(),
                EnergyKind::Strain => self.strain_energy(),
                EnergyKind::Total => {
                    self.kinetic_energy() + self.potential_energy() + self.strain_energy()
                }
            },
            // not declared by beam scenes
            OutputKind::Belt(_) => f64::NAN,
        }
    }

    /// `½ vᵀ M v` [J] of the committed state.
    pub fn kinetic_energy(&self) -> f64 {
        (0..self.elements.len())
            .map(|e| {
                let ve: ElemVec = self.asm.gather(e, &self.v);
                0.5 * ve.dot(&(self.mass_elem[e] * ve))
            })
            .sum()
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
        (0..self.elements.len())
            .map(|e| {
                let qe: ElemVec = self.asm.gather(e, &self.q);
                self.elements[e].strain_energy(&qe, &self.law)
            })
            .sum()
    }

    /// External force (gravity and point loads) times `lambda`, added into a full vector with
    /// a minus sign (residual convention).
    fn subtract_external(&self, lambda: f64, full: &mut [f64]) {
        for (f, g) in full.iter_mut().zip(&self.gravity_full) {
            *f -= lambda * g;
        }
        for (map, val) in self.loads.iter().zip(&self.load_values) {
            for (i, w) in map.weights() {
                full[i] -= lambda * w * val[0];
                full[i + 1] -= lambda * w * val[1];
            }
        }
    }

    /// Adds `M a` (element by element, so that prescribed accelerations count).
    fn add_inertia(&self, a_full: &[f64], full: &mut [f64]) {
        for e in 0..self.elements.len() {
            let ae: ElemVec = self.asm.gather(e, a_full);
            self.asm.add_vector(e, &(self.mass_elem[e] * ae), 1.0, full);
        }
    }

    fn start_jacobian(&self, coeffs: JacobianCoeffs, vals: &mut [f64]) {
        for (j, m) in vals.iter_mut().zip(&self.mass_vals) {
            *j = coeffs.mass * m;
        }
    }

    fn finish(
        &self,
        r: &mut [f64],
        jac: &Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        self.asm.dofs.restrict(&self.fw, r);
        if r.iter().any(|x| !x.is_finite()) {
            return Err(ModelError::NonFinite);
        }
        if let Some((_, vals)) = jac {
            if vals.iter().any(|x| !x.is_finite()) {
                return Err(ModelError::NonFinite);
            }
        }
        Ok(())
    }

    /// Full residual vector (including constrained coordinates, where it is minus the
    /// reaction) of the committed state in static equilibrium terms: `f_int(q) − f_ext`.
    pub fn static_residual_full(&mut self) -> &[f64] {
        self.fw.iter_mut().for_each(|x| *x = 0.0);
        let mut fe = ElemVec::zeros();
        for e in 0..self.elements.len() {
            let qe: ElemVec = self.asm.gather(e, &self.q);
            self.elements[e].internal_force(&qe, &self.law, &mut fe);
            self.asm.add_vector(e, &fe, 1.0, &mut self.fw);
        }
        let mut f = std::mem::take(&mut self.fw);
        self.subtract_external(1.0, &mut f);
        self.fw = f;
        &self.fw
    }
}

impl Model for Beam2d {
    fn set_input(&mut self, kind: InputKind, value: f64) {
        match kind {
            InputKind::Load { load, axis } => self.load_values[load][axis] = value,
            // not declared by beam scenes
            InputKind::Pulley { .. } => {}
        }
    }

    fn output(&self, kind: OutputKind) -> f64 {
        self.output_of(kind)
    }

    fn accept(&mut self, state: &mut DynState) {
        self.asm.dofs.expand(&state.q, &mut self.q);
        self.asm.dofs.expand(&state.v, &mut self.v);
    }

    fn free_state(&self, q: &mut [f64], v: &mut [f64]) {
        self.asm.dofs.restrict(&self.q, q);
        self.asm.dofs.restrict(&self.v, v);
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
        _t: f64,
        q: &[f64],
        _v: &[f64],
        a: &[f64],
        load_factor: f64,
        r: &mut [f64],
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        self.asm.dofs.expand(q, &mut self.qw);
        self.asm.dofs.expand(a, &mut self.aw);
        let mut f = std::mem::take(&mut self.fw);
        f.iter_mut().for_each(|x| *x = 0.0);
        if let Some((c, vals)) = jac.as_mut() {
            self.start_jacobian(*c, vals);
        }
        let (mut fe, mut ke) = (ElemVec::zeros(), ElemMat::zeros());
        for e in 0..self.elements.len() {
            let qe: ElemVec = self.asm.gather(e, &self.qw);
            match jac.as_mut() {
                Some((c, vals)) => {
                    self.elements[e].internal_force_tangent(&qe, &self.law, &mut fe, &mut ke);
                    self.asm.add_matrix(e, &ke, c.stiffness, vals);
                }
                None => {
                    self.elements[e].internal_force(&qe, &self.law, &mut fe);
                }
            }
            self.asm.add_vector(e, &fe, 1.0, &mut f);
        }
        self.add_inertia(&self.aw, &mut f);
        self.subtract_external(load_factor, &mut f);
        self.fw = f;
        self.finish(r, &jac)
    }

    fn midpoint_residual(
        &mut self,
        _t: f64,
        q_a: &[f64],
        q_b: &[f64],
        _v: &[f64],
        a: &[f64],
        r: &mut [f64],
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        self.asm.dofs.expand(q_a, &mut self.qw);
        self.asm.dofs.expand(q_b, &mut self.qw2);
        self.asm.dofs.expand(a, &mut self.aw);
        let mut f = std::mem::take(&mut self.fw);
        f.iter_mut().for_each(|x| *x = 0.0);
        if let Some((c, vals)) = jac.as_mut() {
            self.start_jacobian(*c, vals);
        }
        let (mut fe, mut ke) = (ElemVec::zeros(), ElemMat::zeros());
        for e in 0..self.elements.len() {
            let ea: ElemVec = self.asm.gather(e, &self.qw);
            let eb: ElemVec = self.asm.gather(e, &self.qw2);
            match jac.as_mut() {
                Some((c, vals)) => {
                    self.elements[e].average_stress_force(
                        &ea,
                        &eb,
                        &self.law,
                        &mut fe,
                        Some(&mut ke),
                    );
                    self.asm.add_matrix(e, &ke, c.stiffness, vals);
                }
                None => self.elements[e].average_stress_force(&ea, &eb, &self.law, &mut fe, None),
            }
            self.asm.add_vector(e, &fe, 1.0, &mut f);
        }
        self.add_inertia(&self.aw, &mut f);
        self.subtract_external(1.0, &mut f);
        self.fw = f;
        self.finish(r, &jac)
    }
}
