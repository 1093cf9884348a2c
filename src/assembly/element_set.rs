//! A set of elements of one type over the global coordinates: connectivity, the gather →
//! kernel → scatter loop into the sparse iteration matrix (positions precomputed once),
//! energy sums and the non-finite check.
//!
//! A model may hold several sets over one [`Assembly`] (elements of different sizes: shell
//! elements next to beam elements), and a [`Connectivity`] alone serves coupling blocks that are
//! not elements (a belt element plus the angle of the pulley it touches: 9 coordinates).

use super::scatter::Assembly;
use crate::elements::element::{Element, ElementState, Frame, MAX_FRAMES, Slot};
use crate::elements::node_frames::NodeFrames;
use crate::model::{JacobianCoeffs, ModelError};
use nalgebra::{SMatrix, SVector, Vector3};

const NONE: u32 = u32::MAX;

/// Global coordinate indices of groups of `N` coordinates and, for every group, where each
/// entry of its `N × N` block goes in the values of the free–free matrix.
#[derive(Clone, Debug)]
pub struct Connectivity<const N: usize> {
    dofs: Vec<[usize; N]>,
    pos: Vec<u32>,
}

impl<const N: usize> Connectivity<N> {
    /// Connectivity of the groups `dofs` (full coordinate indices) in the pattern of `asm`
    /// (which must contain every free–free pair of a group).
    pub fn new(dofs: Vec<[usize; N]>, asm: &Assembly) -> Self {
        let mut pos = Vec::with_capacity(dofs.len() * N * N);
        for d in &dofs {
            for &j in d {
                for &i in d {
                    pos.push(match (asm.dofs.free_index(i), asm.dofs.free_index(j)) {
                        (Some(a), Some(b)) => {
                            asm.pattern.position(a, b).expect("in pattern") as u32
                        }
                        _ => NONE,
                    });
                }
            }
        }
        Self { dofs, pos }
    }

    /// Number of groups.
    pub fn len(&self) -> usize {
        self.dofs.len()
    }

    /// Whether there are no groups.
    pub fn is_empty(&self) -> bool {
        self.dofs.is_empty()
    }

    /// Full coordinate indices of group `e`.
    #[inline]
    pub fn dofs(&self, e: usize) -> &[usize; N] {
        &self.dofs[e]
    }

    /// Gathers group `e`'s entries of a full vector.
    #[inline]
    pub fn gather(&self, e: usize, full: &[f64]) -> SVector<f64, N> {
        let d = &self.dofs[e];
        SVector::<f64, N>::from_fn(|i, _| full[d[i]])
    }

    /// Adds `scale · f` into a full vector.
    #[inline]
    pub fn add_vector(&self, e: usize, f: &SVector<f64, N>, scale: f64, full: &mut [f64]) {
        for (i, &d) in self.dofs[e].iter().enumerate() {
            full[d] += scale * f[i];
        }
    }

    /// Adds `scale · m` into the values of the free–free matrix (constrained rows and
    /// columns skipped).
    #[inline]
    pub fn add_matrix(&self, e: usize, m: &SMatrix<f64, N, N>, scale: f64, vals: &mut [f64]) {
        let pos = &self.pos[e * N * N..(e + 1) * N * N];
        for (p, v) in pos.iter().zip(m.as_slice()) {
            if *p != NONE {
                vals[*p as usize] += scale * v;
            }
        }
    }

    /// Adds `a · ma + b · mb` of row `e` into `vals` in one pass (two element matrices, e.g.
    /// stiffness and damping, weighted by their iteration coefficients).
    pub fn add_matrix2(
        &self,
        e: usize,
        ma: &SMatrix<f64, N, N>,
        a: f64,
        mb: &SMatrix<f64, N, N>,
        b: f64,
        vals: &mut [f64],
    ) {
        let pos = &self.pos[e * N * N..(e + 1) * N * N];
        for (p, (x, y)) in pos.iter().zip(ma.as_slice().iter().zip(mb.as_slice())) {
            if *p != NONE {
                vals[*p as usize] += a * x + b * y;
            }
        }
    }

    /// [`Self::add_matrix`] (`scale · m`) over the rows and columns `k` with `used[k]` only
    /// (the others' entries must be zero: a block whose coordinates are not all coupled).
    pub fn add_matrix_used(
        &self,
        e: usize,
        m: &SMatrix<f64, N, N>,
        scale: f64,
        used: &[bool; N],
        vals: &mut [f64],
    ) {
        let pos = &self.pos[e * N * N..(e + 1) * N * N];
        for j in (0..N).filter(|&j| used[j]) {
            for i in (0..N).filter(|&i| used[i]) {
                let p = pos[j * N + i];
                if p != NONE {
                    vals[p as usize] += scale * m[(i, j)];
                }
            }
        }
    }
}

/// Elements of one type with their connectivity. A uniform mesh may share one element among
/// all connectivity rows.
#[derive(Clone, Debug)]
pub struct ElementSet<E, const N: usize> {
    elements: Vec<E>,
    conn: Connectivity<N>,
    /// Node (in the model's [`NodeFrames`]) of every rotation slot, `n_frames` per element.
    frame_nodes: Vec<usize>,
    n_frames: usize,
    /// The assembled mass (free–free values) if every element's mass is constant.
    mass_vals: Option<Vec<f64>>,
    /// Number of values of the free–free matrix.
    nnz: usize,
    /// Mid-point coordinates (full vector) of the plain midpoint rule.
    qm: Vec<f64>,
}

/// The residual evaluation a set performs.
#[derive(Clone, Copy, Debug)]
pub struct Eval<'a> {
    /// Full coordinates.
    pub q: &'a [f64],
    /// Full velocities.
    pub v: &'a [f64],
    /// Full accelerations.
    pub a: &'a [f64],
    /// Gravity acting on the elements [m/s²] (zero if the model assembles a constant gravity
    /// load itself, see [`ElementSet::add_gravity`]).
    pub g: Vector3<f64>,
}

impl<E: Element<N>, const N: usize> ElementSet<E, N> {
    /// A set of `elements` (one per row of `dofs`, or a single one shared by all rows) in
    /// the pattern of `asm`. Elements with rotation slots need [`ElementSet::with_frames`].
    pub fn new(elements: Vec<E>, dofs: Vec<[usize; N]>, asm: &Assembly) -> Self {
        assert!(
            elements.len() == dofs.len() || elements.len() == 1,
            "one element per connectivity row, or one shared"
        );
        let n_frames = elements.first().map_or(0, |e| e.layout().n_frames());
        assert!(n_frames <= MAX_FRAMES);
        assert!(elements.iter().all(|e| e.layout().n_coords() == N));
        let n_full = asm.dofs.n_full();
        let mut set = Self {
            elements,
            conn: Connectivity::new(dofs, asm),
            frame_nodes: Vec::new(),
            n_frames,
            mass_vals: None,
            nnz: asm.pattern.nnz(),
            qm: vec![0.0; n_full],
        };
        set.assemble_constant_mass();
        set
    }

    /// Assembles the mass once if every element's mass is constant.
    fn assemble_constant_mass(&mut self) {
        self.mass_vals = None;
        if (0..self.len()).all(|e| self.element(e).constant_mass_matrix().is_some()) {
            let mut vals = vec![0.0; self.nnz];
            for e in 0..self.len() {
                if let Some(m) = self.element(e).constant_mass_matrix() {
                    self.conn.add_matrix(e, m, 1.0, &mut vals);
                }
            }
            self.mass_vals = Some(vals);
        }
    }

    /// Maps every rotation slot of every element to its node in `frames` (by the full index
    /// of the slot's first coordinate). Panics if a rotation slot has no node frame.
    pub fn with_frames(mut self, frames: &NodeFrames) -> Self {
        // node of every full coordinate index that starts a rotation vector
        let n = (0..frames.len())
            .map(|k| frames.theta_index(k) + 1)
            .max()
            .unwrap_or(0);
        let mut node_at = vec![usize::MAX; n];
        for k in 0..frames.len() {
            node_at[frames.theta_index(k)] = k;
        }
        self.frame_nodes.clear();
        for e in 0..self.conn.len() {
            let layout = self.element(e).layout();
            for (slot, at) in layout.offsets() {
                if slot == Slot::Rotation {
                    let i = self.conn.dofs(e)[at];
                    let k = node_at.get(i).copied().unwrap_or(usize::MAX);
                    assert!(k != usize::MAX, "a node frame for every rotation slot");
                    self.frame_nodes.push(k);
                }
            }
        }
        self
    }

    /// Number of elements (connectivity rows).
    pub fn len(&self) -> usize {
        self.conn.len()
    }

    /// Whether the set is empty.
    pub fn is_empty(&self) -> bool {
        self.conn.is_empty()
    }

    /// Element `e`.
    #[inline]
    pub fn element(&self, e: usize) -> &E {
        if self.elements.len() == 1 {
            &self.elements[0]
        } else {
            &self.elements[e]
        }
    }

    /// Replaces the elements (same count rule as [`ElementSet::new`]), e.g. after a change of
    /// the reference length.
    pub fn set_elements(&mut self, elements: Vec<E>) {
        assert!(elements.len() == self.conn.len() || elements.len() == 1);
        self.elements = elements;
        self.assemble_constant_mass();
    }

    /// Connectivity and scatter positions.
    pub fn connectivity(&self) -> &Connectivity<N> {
        &self.conn
    }

    /// Full coordinate indices of element `e`.
    #[inline]
    pub fn element_dofs(&self, e: usize) -> &[usize; N] {
        self.conn.dofs(e)
    }

    /// Element `e`'s entries of a full vector.
    #[inline]
    pub fn gather(&self, e: usize, full: &[f64]) -> SVector<f64, N> {
        self.conn.gather(e, full)
    }

    /// Frames of element `e`'s rotation slots from a frame table (one per node).
    #[inline]
    fn frames_of(&self, e: usize, table: &[Frame], out: &mut [Frame; MAX_FRAMES]) {
        let nodes = &self.frame_nodes[e * self.n_frames..(e + 1) * self.n_frames];
        for (o, &k) in out.iter_mut().zip(nodes) {
            *o = table[k];
        }
    }

    /// Calls `f(e, element, state)` for every element at full coordinates `q` and velocities
    /// `v`; frames are computed from `q` (nothing stored).
    pub fn for_each_state(
        &self,
        q: &[f64],
        v: &[f64],
        frames: Option<&NodeFrames>,
        mut f: impl FnMut(usize, &E, &ElementState<N>),
    ) {
        let mut buf = [Frame::default(); MAX_FRAMES];
        for e in 0..self.len() {
            if let Some(nf) = frames {
                let nodes = &self.frame_nodes[e * self.n_frames..(e + 1) * self.n_frames];
                for (o, &k) in buf.iter_mut().zip(nodes) {
                    *o = nf.frame(k, q);
                }
            }
            let s = ElementState {
                q: self.gather(e, q),
                v: self.gather(e, v),
                frames: &buf[..self.n_frames],
            };
            f(e, self.element(e), &s);
        }
    }

    /// Sum of the strain energies [J] at full coordinates `q`.
    pub fn strain_energy(&self, q: &[f64], frames: Option<&NodeFrames>) -> f64 {
        let mut u = 0.0;
        self.for_each_state(q, q, frames, |_, el, s| u += el.strain_energy_at(s));
        u
    }

    /// Sum of the kinetic energies [J].
    pub fn kinetic_energy(&self, q: &[f64], v: &[f64], frames: Option<&NodeFrames>) -> f64 {
        let mut t = 0.0;
        self.for_each_state(q, v, frames, |_, el, s| t += el.kinetic_energy_at(s));
        t
    }

    /// Sum of the material damping powers [W].
    pub fn damping_power(&self, q: &[f64], v: &[f64], frames: Option<&NodeFrames>) -> f64 {
        let mut p = 0.0;
        self.for_each_state(q, v, frames, |_, el, s| p += el.damping_power_at(s));
        p
    }

    /// Adds `scale · Q_g(g)` of every element into a full vector (a constant gravity load of
    /// constant-mass elements is assembled once this way).
    pub fn add_gravity(
        &self,
        q: &[f64],
        frames: Option<&NodeFrames>,
        g: &Vector3<f64>,
        scale: f64,
        full: &mut [f64],
    ) {
        let mut qg = SVector::<f64, N>::zeros();
        self.for_each_state(q, q, frames, |e, el, s| {
            el.gravity_into(s, g, &mut qg);
            self.conn.add_vector(e, &qg, scale, full);
        });
    }

    /// Adds `scale · M` of every element into the values of the free–free matrix.
    pub fn add_mass(&self, q: &[f64], frames: Option<&NodeFrames>, scale: f64, vals: &mut [f64]) {
        let mut m = SMatrix::<f64, N, N>::zeros();
        self.for_each_state(q, q, frames, |e, el, s| {
            el.mass_into(s, &mut m);
            self.conn.add_matrix(e, &m, scale, vals);
        });
    }

    /// The gather → kernel → scatter loop: adds every element's residual
    /// `f_inertia + f_int − Q_g` into the full vector `f` and, with `jac`, its iteration matrix
    /// into the free–free values (neither is cleared first). Node frames, if any, are updated
    /// from `x.q` first (so the model can use [`NodeFrames::current`] afterwards). Returns the
    /// strain energy [J].
    ///
    /// Elements with a constant mass take a faster path with the same result as
    /// [`Element::residual_into`]: the mass part of the matrix is the mass assembled once,
    /// and per element only `c_K K` (and `c_C C`) are scattered.
    pub fn add_residual(
        &self,
        x: &Eval,
        frames: Option<&mut NodeFrames>,
        f: &mut [f64],
        jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> f64 {
        self.add_residual_over(0..self.len(), x, frames, f, jac)
    }

    /// [`ElementSet::add_residual`] of the listed elements only, without the iteration matrix:
    /// the rows of coordinates that only these elements touch are those of the full residual,
    /// bit for bit when `elements` ascend (the same terms added in the same order). For the
    /// reactions of a few prescribed rows (e.g. a ring held by a plate) without a pass over
    /// every element. Returns the listed elements' strain energy [J].
    pub fn add_residual_of(
        &self,
        elements: &[usize],
        x: &Eval,
        frames: Option<&mut NodeFrames>,
        f: &mut [f64],
    ) -> f64 {
        self.add_residual_over(elements.iter().copied(), x, frames, f, None)
    }

    fn add_residual_over(
        &self,
        elements: impl Iterator<Item = usize>,
        x: &Eval,
        frames: Option<&mut NodeFrames>,
        f: &mut [f64],
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> f64 {
        let table: &[Frame] = match frames {
            Some(nf) => {
                nf.update(x.q);
                nf.current()
            }
            None => &[],
        };
        let mut buf = [Frame::default(); MAX_FRAMES];
        let (mut fe, mut me) = (SVector::<f64, N>::zeros(), SMatrix::<f64, N, N>::zeros());
        let mut ce = SMatrix::<f64, N, N>::zeros();
        let mut u = 0.0;
        let gravity = x.g != Vector3::zeros();
        // no accelerations (quasi-static steps, static solves): no inertia force to add
        let inertia = x.a.iter().any(|&a| a != 0.0);
        if let (Some(mass), Some((c, vals))) = (&self.mass_vals, jac.as_mut()) {
            for (v, m) in vals.iter_mut().zip(mass) {
                *v += c.mass * m;
            }
        }
        for e in elements {
            if self.n_frames > 0 {
                self.frames_of(e, table, &mut buf);
            }
            let s = ElementState {
                q: self.gather(e, x.q),
                v: self.gather(e, x.v),
                frames: &buf[..self.n_frames],
            };
            let el = self.element(e);
            match (self.mass_vals.is_some(), el.constant_mass_matrix()) {
                (true, Some(m)) => {
                    match jac.as_mut() {
                        Some((c, vals)) => {
                            let damped = c.damping != 0.0;
                            u += el.tangent_into(&s, &mut fe, &mut me, damped.then_some(&mut ce));
                            if damped {
                                self.conn
                                    .add_matrix2(e, &me, c.stiffness, &ce, c.damping, vals);
                            } else {
                                self.conn.add_matrix(e, &me, c.stiffness, vals);
                            }
                        }
                        None => u += el.force_into(&s, &mut fe),
                    }
                    if inertia {
                        // the accelerations are gathered only where the inertia force needs them
                        fe.gemv(1.0, m, &self.gather(e, x.a), 1.0);
                    }
                    if gravity {
                        let mut qg = SVector::<f64, N>::zeros();
                        el.gravity_into(&s, &x.g, &mut qg);
                        fe -= qg;
                    }
                }
                _ => {
                    let ae = self.gather(e, x.a);
                    match jac.as_mut() {
                        Some((c, vals)) => {
                            u += el.residual_into(&s, &ae, &x.g, &mut fe, Some((*c, &mut me)));
                            self.conn.add_matrix(e, &me, 1.0, vals);
                        }
                        None => u += el.residual_into(&s, &ae, &x.g, &mut fe, None),
                    }
                }
            }
            self.conn.add_vector(e, &fe, 1.0, f);
        }
        u
    }

    /// The default midpoint residual over a step from `q_a` to `q_b` (full vectors), added like
    /// [`ElementSet::add_residual`]: elements with an energy-conserving average-stress force
    /// ([`Element::average_force_into`]) contribute `M a + Q_alg(q_a, q_b) − Q_g` with the
    /// matrix `c_M M + c_K ∂Q_alg/∂q_b` (no material damping in that form), the others the
    /// plain midpoint rule, their residual at `(q_a + q_b)/2` with velocities `x.v` and the
    /// stiffness coefficient halved. `x.q` is ignored. Elements with rotation slots are not
    /// supported here (the mean of two charts is the model's business).
    pub fn add_midpoint_residual(
        &mut self,
        q_a: &[f64],
        q_b: &[f64],
        x: &Eval,
        f: &mut [f64],
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) {
        assert_eq!(
            self.n_frames, 0,
            "midpoint of node frames is the model's business"
        );
        let mut qm = std::mem::take(&mut self.qm);
        for (m, (a, b)) in qm.iter_mut().zip(q_a.iter().zip(q_b)) {
            *m = 0.5 * (a + b);
        }
        let (mut fe, mut me, mut ke) = (
            SVector::<f64, N>::zeros(),
            SMatrix::<f64, N, N>::zeros(),
            SMatrix::<f64, N, N>::zeros(),
        );
        for e in 0..self.len() {
            let el = self.element(e);
            let sa = ElementState::new(self.gather(e, q_a), self.gather(e, x.v));
            let sb = ElementState::new(self.gather(e, q_b), sa.v);
            let ae = self.gather(e, x.a);
            let k = jac.as_ref().map(|_| &mut ke);
            if el.average_force_into(&sa, &sb, &mut fe, k) {
                el.mass_into(&sb, &mut me);
                fe += me * ae;
                if x.g != Vector3::zeros() {
                    let mut qg = SVector::<f64, N>::zeros();
                    el.gravity_into(&sb, &x.g, &mut qg);
                    fe -= qg;
                }
                if let Some((c, vals)) = jac.as_mut() {
                    me = me * c.mass + ke * c.stiffness;
                    self.conn.add_matrix(e, &me, 1.0, vals);
                }
            } else {
                let sm = ElementState::new(self.gather(e, &qm), sa.v);
                match jac.as_mut() {
                    Some((c, vals)) => {
                        let half = JacobianCoeffs {
                            stiffness: 0.5 * c.stiffness,
                            ..*c
                        };
                        el.residual_into(&sm, &ae, &x.g, &mut fe, Some((half, &mut me)));
                        self.conn.add_matrix(e, &me, 1.0, vals);
                    }
                    None => {
                        el.residual_into(&sm, &ae, &x.g, &mut fe, None);
                    }
                }
            }
            self.conn.add_vector(e, &fe, 1.0, f);
        }
        self.qm = qm;
    }
}

/// `Err(ModelError::NonFinite)` if a residual entry or an iteration-matrix value is NaN or
/// infinite.
pub fn check_finite(r: &[f64], vals: Option<&[f64]>) -> Result<(), ModelError> {
    if r.iter().any(|x| !x.is_finite()) || vals.is_some_and(|v| v.iter().any(|x| !x.is_finite())) {
        return Err(ModelError::NonFinite);
    }
    Ok(())
}
