//! The state of a model whose nodes carry node frames (position and incremental rotation
//! vector per node: the 3D beam, the shell): its assembly, the stored orientations, the
//! committed state and the work buffers the residual is evaluated in, with the steps every
//! such model takes in the same way (expanding free coordinates, the mean state of the
//! midpoint rule, absorbing rotations into the stored orientations, snapshots).

use crate::assembly::{Assembly, ElementSet, Eval, check_finite};
use crate::elements::Element;
use crate::elements::node_frames::NodeFrames;
use crate::integrators::DynState;
use crate::model::nodes3d::NodeLoad;
use crate::model::{JacobianCoeffs, ModelError};
use crate::snapshot::{SnapshotError, StateReader, StateWriter};
use nalgebra::Vector3;

/// Committed state and work buffers of a model with node frames.
#[derive(Clone, Debug)]
pub struct FramedState {
    /// Free and constrained coordinates and the sparse pattern.
    pub asm: Assembly,
    /// Stored orientations of the nodes (the incremental rotation vectors are coordinates).
    pub frames: NodeFrames,
    /// Committed time [s].
    pub t: f64,
    /// Committed full coordinates.
    pub q: Vec<f64>,
    /// Committed full velocities.
    pub v: Vec<f64>,
    /// Committed full accelerations (`θ̈ = Ẇ` at θ = 0), for output rates.
    pub acc: Vec<f64>,
    /// Full coordinates of the evaluation in progress.
    pub qw: Vec<f64>,
    /// Full velocities of the evaluation in progress.
    pub vw: Vec<f64>,
    /// Full accelerations of the evaluation in progress.
    pub aw: Vec<f64>,
    /// Full residual buffer.
    pub fw: Vec<f64>,
    /// Free coordinates of the midpoint rule's mean state.
    qmid: Vec<f64>,
}

impl FramedState {
    /// At rest at the full coordinates `q0`, time 0.
    pub fn new(asm: Assembly, frames: NodeFrames, q0: Vec<f64>) -> Self {
        let n_full = q0.len();
        let n_free = asm.dofs.n_free();
        Self {
            asm,
            frames,
            t: 0.0,
            q: q0.clone(),
            v: vec![0.0; n_full],
            acc: vec![0.0; n_full],
            qw: q0,
            vw: vec![0.0; n_full],
            aw: vec![0.0; n_full],
            fw: vec![0.0; n_full],
            qmid: vec![0.0; n_free],
        }
    }

    /// Expands free coordinates, velocities and accelerations into the work buffers.
    pub fn expand(&mut self, q: &[f64], v: &[f64], a: &[f64]) {
        self.asm.dofs.expand(q, &mut self.qw);
        self.asm.dofs.expand(v, &mut self.vw);
        self.asm.dofs.expand(a, &mut self.aw);
    }

    /// The midpoint rule's state: the mean configuration `(q_a + q_b)/2` (in the chart of the
    /// stored orientations) with the velocity and acceleration the integrator passes.
    pub fn expand_midpoint(&mut self, q_a: &[f64], q_b: &[f64], v: &[f64], a: &[f64]) {
        let mut qm = std::mem::take(&mut self.qmid);
        for i in 0..qm.len() {
            qm[i] = 0.5 * (q_a[i] + q_b[i]);
        }
        self.asm.dofs.expand(&qm, &mut self.qw);
        self.qmid = qm;
        self.asm.dofs.expand(v, &mut self.vw);
        self.asm.dofs.expand(a, &mut self.aw);
    }

    /// Commits an accepted state: the incremental rotations are absorbed into the stored
    /// orientations (and zeroed in `state.q`). `prescribe` sets prescribed coordinates of the
    /// full vectors: called with the coordinates before the absorption, then with the
    /// velocities and accelerations.
    pub fn accept(
        &mut self,
        state: &mut DynState,
        mut prescribe: impl FnMut(Option<&mut [f64]>, Option<&mut [f64]>, Option<&mut [f64]>),
    ) {
        let mut q = std::mem::take(&mut self.q);
        self.asm.dofs.expand(&state.q, &mut q);
        prescribe(Some(&mut q), None, None);
        self.frames.absorb(&mut q);
        self.asm.dofs.restrict(&q, &mut state.q);
        self.q = q;
        self.asm.dofs.expand(&state.v, &mut self.v);
        self.asm.dofs.expand(&state.acc, &mut self.acc);
        prescribe(None, Some(&mut self.v), Some(&mut self.acc));
        self.t = state.t;
    }

    /// Absorbs the incremental rotations of free coordinates `q` into the stored orientations
    /// (a converged static load increment).
    pub fn rebase(&mut self, q: &mut [f64]) {
        let mut full = std::mem::take(&mut self.q);
        self.asm.dofs.expand(q, &mut full);
        self.frames.absorb(&mut full);
        self.asm.dofs.restrict(&full, q);
        self.q = full;
    }

    /// First part of an assembly at the work state: zeroes the matrix values, and returns the
    /// full residual (the buffer taken out of `self.fw`, give it back with
    /// [`Self::finish_assembly`]) with the elements' part (inertia, internal forces, gravity
    /// `g` [m/s²]) and the node loads at time `t` [s] times `lambda`; the stiffness part of the
    /// iteration matrix is scaled by `k_scale`.
    #[allow(clippy::too_many_arguments)]
    pub fn assemble_elements<E: Element<N>, const N: usize>(
        &mut self,
        set: &ElementSet<E, N>,
        loads: &[NodeLoad],
        g: Vector3<f64>,
        t: f64,
        lambda: f64,
        k_scale: f64,
        jac: &mut Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Vec<f64> {
        let mut fw = std::mem::take(&mut self.fw);
        fw.fill(0.0);
        if let Some((_, vals)) = jac.as_mut() {
            vals.fill(0.0);
        }
        let x = Eval {
            q: &self.qw,
            v: &self.vw,
            a: &self.aw,
            g,
        };
        let elem_jac = jac.as_mut().map(|(c, vals)| {
            let c = JacobianCoeffs {
                stiffness: c.stiffness * k_scale,
                ..*c
            };
            (c, &mut **vals)
        });
        set.add_residual(&x, Some(&mut self.frames), &mut fw, elem_jac);
        let frames = self.frames.current();
        for l in loads {
            let jac = jac.as_mut().map(|(c, vals)| (&*c, k_scale, &mut **vals));
            l.add_residual(t, lambda, frames, &mut fw, &self.asm, jac);
        }
        fw
    }

    /// Last part of an assembly: the free rows of the full residual `fw` into `r`, the buffer
    /// back into `self.fw`, and the check that residual and matrix values are finite.
    pub fn finish_assembly(
        &mut self,
        fw: Vec<f64>,
        r: &mut [f64],
        vals: Option<&[f64]>,
    ) -> Result<(), ModelError> {
        self.asm.dofs.restrict(&fw, r);
        self.fw = fw;
        check_finite(r, vals)
    }

    /// The committed free coordinates and velocities.
    pub fn free_state(&self, q: &mut [f64], v: &mut [f64]) {
        self.asm.dofs.restrict(&self.q, q);
        self.asm.dofs.restrict(&self.v, v);
    }

    /// Writes the committed time, coordinates, velocities, accelerations and orientations.
    pub fn save(&self, w: &mut StateWriter) {
        w.f64(self.t);
        w.f64s(&self.q);
        w.f64s(&self.v);
        w.f64s(&self.acc);
        self.frames.save(w);
    }

    /// Reads what [`Self::save`] wrote.
    pub fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: SnapshotError| e.to_string();
        self.t = r.f64().map_err(e)?;
        r.f64s_into(&mut self.q).map_err(e)?;
        r.f64s_into(&mut self.v).map_err(e)?;
        r.f64s_into(&mut self.acc).map_err(e)?;
        self.frames.restore(r)
    }
}
