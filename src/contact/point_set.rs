//! A set of contact points on the elements of a flexible body against a list of obstacles of
//! one type: the points (element, interpolation weights), their friction history, the
//! evaluation loop with the scatter into the assembly, and the committed loads and energy
//! book of the contact.
//!
//! A point of element `e` sits at `r = Σ_a w_a r_a`, the weighted sum of the element's nodal
//! `D`-vectors `r_a` (for an ANCF element position and slope vectors). Each (element,
//! obstacle) pair has one block of `NB` coordinates in a [`Connectivity`]: the element's
//! coordinates, then the obstacle's own. The points' histories are stored by element, point,
//! then obstacle. The loop allocates nothing.

use super::circle_friction::ContactLaw;
use super::obstacle::{
    ContactHistory, MAX_OBSTACLE_COORDS, Obstacle, ObstacleContact, PointMotion,
};
use crate::assembly::Connectivity;
use crate::model::JacobianCoeffs;
use crate::snapshot::{StateReader, StateWriter};
use nalgebra::{SMatrix, SVector};

/// Largest point-plus-obstacle dimension `D + N_COORDS` of an iteration block.
const MAX_BLOCK: usize = 9;

/// Loads of the body on one obstacle in the committed state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObstacleLoad<const D: usize> {
    /// Force of the body on the obstacle [N].
    pub force: SVector<f64, D>,
    /// Generalized forces on the obstacle's own coordinates (a pulley's torque [N m]).
    pub generalized: [f64; MAX_OBSTACLE_COORDS],
}

impl<const D: usize> Default for ObstacleLoad<D> {
    fn default() -> Self {
        Self {
            force: SVector::zeros(),
            generalized: [0.0; MAX_OBSTACLE_COORDS],
        }
    }
}

/// Energy terms of the contact in a committed state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactBook {
    /// Points sliding.
    pub slipping: usize,
    /// Elastic energy of the normal penalty [J].
    pub normal_energy: f64,
    /// Power dissipated by normal damping [W].
    pub dissipation: f64,
    /// Work against friction since the previous commit [J].
    pub friction_work: f64,
}

/// Contact points on `n_elements` elements of `NV` nodal `D`-vectors against obstacles of type
/// `O`, `NB` = `NV · D + O::N_COORDS` coordinates per (element, obstacle) block.
#[derive(Clone, Debug)]
pub struct ContactPointSet<O: Obstacle<D>, const D: usize, const NV: usize, const NB: usize> {
    law: ContactLaw,
    obstacles: Vec<O>,
    blocks: Connectivity<NB>,
    n_elements: usize,
    /// Nodal vectors that are the element's end positions (broad phase).
    ends: [usize; 2],
    /// Weights of the nodal vectors for every point of an element.
    weights: Vec<[f64; NV]>,
    /// Body length (or area) a point stands for.
    w: f64,
    hist: Vec<O::History>,
    loads: Vec<ObstacleLoad<D>>,
}

impl<O: Obstacle<D>, const D: usize, const NV: usize, const NB: usize>
    ContactPointSet<O, D, NV, NB>
{
    /// Points on the elements of `blocks` (row `e · n_obstacles + k`: element `e`'s
    /// coordinates, `NV` nodal `D`-vectors, then obstacle `k`'s coordinates), with the
    /// nodal vectors `ends` as the element's end positions. Points are placed by
    /// [`Self::set_points`].
    pub fn new(
        law: ContactLaw,
        obstacles: Vec<O>,
        blocks: Connectivity<NB>,
        ends: [usize; 2],
    ) -> Self {
        assert!(D + O::N_COORDS <= MAX_BLOCK);
        assert_eq!(NV * D + O::N_COORDS, NB, "block size");
        let no = obstacles.len().max(1);
        let n_elements = blocks.len() / no;
        Self {
            law,
            loads: vec![ObstacleLoad::default(); obstacles.len()],
            obstacles,
            blocks,
            n_elements,
            ends,
            weights: vec![],
            w: 0.0,
            hist: vec![],
        }
    }

    /// Places the points: `weights` holds the interpolation weights of every point of an
    /// element, the same on all elements; each stands for `w` [m] (or [m²]). Histories are
    /// reset when the number of points changes.
    pub fn set_points(&mut self, weights: Vec<[f64; NV]>, w: f64) {
        self.weights = weights;
        self.w = w;
        let n = self.n_elements * self.points_per_element() * self.obstacles.len();
        if self.hist.len() != n {
            self.hist = vec![O::History::default(); n];
        }
    }

    /// Points per element.
    pub fn points_per_element(&self) -> usize {
        self.weights.len()
    }

    /// Contact constants.
    pub fn law(&self) -> &ContactLaw {
        &self.law
    }

    /// The obstacles.
    pub fn obstacles(&self) -> &[O] {
        &self.obstacles
    }

    /// Loads on every obstacle in the committed state.
    pub fn loads(&self) -> &[ObstacleLoad<D>] {
        &self.loads
    }

    /// Shifts the histories of all points on obstacle `k` for its coordinate `l` moved by
    /// `by` without slip ([`Obstacle::shift_history`]).
    pub fn shift_obstacle(&mut self, k: usize, l: usize, by: f64) {
        let no = self.obstacles.len();
        for h in self.hist.iter_mut().skip(k).step_by(no) {
            O::shift_history(h, l, by);
        }
    }

    /// Whether element `e` can touch obstacle `k` at full coordinates `q`.
    #[inline(always)]
    fn near(&self, e: usize, k: usize, q: &[f64]) -> bool {
        let d = self.blocks.dofs(e * self.obstacles.len() + k);
        let end = |a: usize| SVector::<f64, D>::from_fn(|i, _| q[d[D * a + i]]);
        self.obstacles[k].near(&end(self.ends[0]), &end(self.ends[1]))
    }

    /// Position and velocity of point `i` of block `b`, and the obstacle's coordinates and
    /// rates.
    #[inline(always)]
    #[allow(clippy::type_complexity)]
    fn motion(
        &self,
        b: usize,
        i: usize,
        q: &[f64],
        v: &[f64],
    ) -> (
        PointMotion<D>,
        [f64; MAX_OBSTACLE_COORDS],
        [f64; MAX_OBSTACLE_COORDS],
    ) {
        let d = self.blocks.dofs(b);
        let nv = NV;
        let s = &self.weights[i];
        let (mut r, mut vel) = (SVector::<f64, D>::zeros(), SVector::<f64, D>::zeros());
        for (a, &sa) in s.iter().enumerate() {
            for c in 0..D {
                r[c] += sa * q[d[D * a + c]];
                vel[c] += sa * v[d[D * a + c]];
            }
        }
        let (mut x, mut xd) = ([0.0; MAX_OBSTACLE_COORDS], [0.0; MAX_OBSTACLE_COORDS]);
        for l in 0..O::N_COORDS {
            x[l] = q[d[nv * D + l]];
            xd[l] = v[d[nv * D + l]];
        }
        (PointMotion { r, v: vel }, x, xd)
    }

    /// Subtracts the contact forces at full coordinates `q`, velocities `v` from the full
    /// residual `f` and, with `jac`, adds `−∂F/∂(q, v)` (weighted by the coefficients) into
    /// the values of the iteration matrix.
    pub fn add_residual(
        &mut self,
        q: &[f64],
        v: &[f64],
        f: &mut [f64],
        mut jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) {
        let no = self.obstacles.len();
        let n_cp = self.points_per_element();
        let nc = O::N_COORDS;
        let ne = NV * D;
        let np = D + nc;
        let mut block = [0.0; MAX_BLOCK * MAX_BLOCK];
        let mut blk = SMatrix::<f64, NB, NB>::zeros();
        for e in 0..self.n_elements {
            for k in 0..no {
                if !self.near(e, k, q) {
                    continue;
                }
                let b = e * no + k;
                let mut any = false;
                blk.fill(0.0);
                let d = self.blocks.dofs(b);
                for i in 0..n_cp {
                    let (p, x, xd) = self.motion(b, i, q, v);
                    let h = &self.hist[(e * n_cp + i) * no + k];
                    let Some(res) = self.obstacles[k].evaluate(&self.law, self.w, &p, &x, &xd, h)
                    else {
                        continue;
                    };
                    any = true;
                    let s = &self.weights[i];
                    let force = res.force();
                    for (a, &sa) in s.iter().enumerate() {
                        for c in 0..D {
                            f[d[D * a + c]] -= sa * force[c];
                        }
                    }
                    for l in 0..nc {
                        f[d[ne + l]] -= res.generalized_force(l);
                    }
                    if let Some((c, _)) = jac.as_ref() {
                        res.iteration_block(c.stiffness, c.damping, &mut block[..np * np]);
                        let m = |i: usize, j: usize| block[i + np * j];
                        // T maps (element coordinates, obstacle coordinates) to (r, x):
                        // block −Tᵀ m T
                        for (a, &sa) in s.iter().enumerate() {
                            for (bb, &sb) in s.iter().enumerate() {
                                let ss = sa * sb;
                                for i in 0..D {
                                    for j in 0..D {
                                        blk[(D * a + i, D * bb + j)] -= ss * m(i, j);
                                    }
                                }
                            }
                            for l in 0..nc {
                                for i in 0..D {
                                    blk[(D * a + i, ne + l)] -= sa * m(i, D + l);
                                    blk[(ne + l, D * a + i)] -= sa * m(D + l, i);
                                }
                            }
                        }
                        for l in 0..nc {
                            for l2 in 0..nc {
                                blk[(ne + l, ne + l2)] -= m(D + l, D + l2);
                            }
                        }
                    }
                }
                if any && let Some((_, vals)) = jac.as_mut() {
                    self.blocks.add_matrix(b, &blk, 1.0, vals);
                }
            }
        }
    }

    /// Commits the state at full coordinates `q`, velocities `v`: new histories, the loads
    /// on the obstacles ([`Self::loads`]) and the energy terms. `initial`: no contact is
    /// evaluated (histories at rest).
    pub fn commit(&mut self, q: &[f64], v: &[f64], initial: bool) -> ContactBook {
        let no = self.obstacles.len();
        let n_cp = self.points_per_element();
        self.loads.fill(ObstacleLoad::default());
        let mut book = ContactBook::default();
        for e in 0..self.n_elements {
            for k in 0..no {
                let near = self.near(e, k, q);
                let b = e * no + k;
                for i in 0..n_cp {
                    let idx = (e * n_cp + i) * no + k;
                    let (p, x, xd) = self.motion(b, i, q, v);
                    let h = self.hist[idx];
                    let ob = &self.obstacles[k];
                    let res = if near && !initial {
                        ob.evaluate(&self.law, self.w, &p, &x, &xd, &h)
                    } else {
                        None
                    };
                    if let Some(r) = &res {
                        let load = &mut self.loads[k];
                        for l in 0..O::N_COORDS {
                            load.generalized[l] += r.generalized_force(l);
                        }
                        load.force -= r.force();
                        book.slipping += r.slipping() as usize;
                        book.normal_energy += r.normal_energy();
                        book.dissipation += r.dissipation();
                        book.friction_work += O::friction_work(self.w, &h, r);
                    }
                    self.hist[idx] = ob.committed(&p, &x, res.as_ref());
                }
            }
        }
        book
    }

    /// Writes the histories into a snapshot.
    pub fn save(&self, w: &mut StateWriter) {
        w.u64(self.hist.len() as u64);
        for h in &self.hist {
            h.save(w);
        }
    }

    /// Reads histories written by [`Self::save`].
    pub fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        if r.u64().map_err(e)? as usize != self.hist.len() {
            return Err("contact history of another mesh".into());
        }
        for h in self.hist.iter_mut() {
            *h = O::History::restore(r).map_err(e)?;
        }
        Ok(())
    }
}
