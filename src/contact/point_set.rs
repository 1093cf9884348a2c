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
use nalgebra::{SMatrix, SVector, Vector3};

/// Largest point-plus-obstacle dimension `D + N_COORDS` of an iteration block.
const MAX_BLOCK: usize = 9;

/// Loads of the body on one obstacle in the committed state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObstacleLoad<const D: usize> {
    /// Force of the body on the obstacle [N].
    pub force: SVector<f64, D>,
    /// Generalized forces on the obstacle's own coordinates (a pulley's torque [N m]).
    pub generalized: [f64; MAX_OBSTACLE_COORDS],
    /// Moment of the body's forces on the obstacle about its reference point [N m]
    /// ([`ObstacleContact::moment`]).
    pub moment: Vector3<f64>,
    /// Force of the body on the obstacle's side faces [N] ([`ObstacleContact::side_force`]).
    pub side_force: f64,
}

impl<const D: usize> Default for ObstacleLoad<D> {
    fn default() -> Self {
        Self {
            force: SVector::zeros(),
            generalized: [0.0; MAX_OBSTACLE_COORDS],
            moment: Vector3::zeros(),
            side_force: 0.0,
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
    /// Per element, the length (or area) each of its points stands for, replacing `w` (empty:
    /// `w` on every element).
    element_w: Vec<f64>,
    hist: Vec<O::History>,
    loads: Vec<ObstacleLoad<D>>,
    /// The points in contact in the last [`Self::add_residual`] (count and a signature of
    /// which), and in the last one that built an iteration matrix.
    active: ActiveSet,
    active_in_matrix: Option<ActiveSet>,
}

/// Which contact points are in contact: their count and an order-dependent hash of their
/// indices (equal sets give equal values; different sets almost surely differ).
type ActiveSet = (usize, u64);

/// Adds point `idx` to an [`ActiveSet`] (FNV-style mixing).
#[inline]
fn mark_active(set: &mut ActiveSet, idx: usize) {
    set.0 += 1;
    set.1 = (set.1 ^ (idx as u64 + 1)).wrapping_mul(0x0100_0000_01b3);
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
            element_w: vec![],
            hist: vec![],
            active: (0, 0),
            active_in_matrix: None,
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

    /// Gives the points of every element their own length (or area) `w[e]` [m] (or [m²]),
    /// for elements of different sizes; replaces the common one of [`Self::set_points`].
    pub fn set_element_weights(&mut self, w: Vec<f64>) {
        assert_eq!(w.len(), self.n_elements, "one length per element");
        self.element_w = w;
    }

    /// The length (or area) a point of element `e` stands for.
    #[inline]
    fn w_of(&self, e: usize) -> f64 {
        if self.element_w.is_empty() {
            self.w
        } else {
            self.element_w[e]
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

    /// Replaces the contact constants (e.g. `mu = 0` for a frictionless static solve; a
    /// commit under `mu = 0` leaves every friction history at rest: zero bristle force at the
    /// committed position).
    pub fn set_law(&mut self, law: ContactLaw) {
        self.law = law;
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
        let mut x = [0.0; MAX_OBSTACLE_COORDS];
        for (l, xl) in x.iter_mut().enumerate().take(O::N_COORDS) {
            *xl = q[d[NV * D + l]];
        }
        self.obstacles[k].near_at(&end(self.ends[0]), &end(self.ends[1]), &x)
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
        let mut active = (0, 0);
        for e in 0..self.n_elements {
            for k in 0..no {
                if !self.near(e, k, q) {
                    continue;
                }
                let b = e * no + k;
                let mut any = false;
                let d = self.blocks.dofs(b);
                for i in 0..n_cp {
                    let (p, x, xd) = self.motion(b, i, q, v);
                    let idx = (e * n_cp + i) * no + k;
                    let h = &self.hist[idx];
                    let Some(res) =
                        self.obstacles[k].evaluate(&self.law, self.w_of(e), &p, &x, &xd, h)
                    else {
                        continue;
                    };
                    any = true;
                    mark_active(&mut active, idx);
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
                    // zeroed after use, not before every pair (most pairs have no point in
                    // contact); a plain memset, not nalgebra's element iterator
                    blk.as_mut_slice().fill(0.0);
                }
            }
        }
        self.active = active;
        if jac.is_some() {
            self.active_in_matrix = Some(active);
        }
    }

    /// Whether the points in contact in the last [`Self::add_residual`] are those of the last
    /// one that built an iteration matrix (true before any matrix). A kept (modified-Newton)
    /// matrix that lacks a point's penalty stiffness, or holds one of a point that has left,
    /// gives increments that can pass a convergence test far from the solution (the air
    /// spring at 3 m/s: a force 4 % off accepted after one iteration); such a matrix is
    /// rebuilt ([`crate::model::MechanicalSystem::kept_matrix_current`]).
    pub fn matrix_is_current(&self) -> bool {
        self.active_in_matrix.is_none_or(|m| m == self.active)
    }

    /// Subtracts the contact forces of element `e`'s points from `out`, the element's node
    /// entries (`NV · D` values in the order of its nodal vectors), exactly as
    /// [`Self::add_residual`] subtracts them from the element's rows of the full residual
    /// (obstacles in order, points in order): a reaction at a few rows needs no pass over
    /// the whole body.
    pub fn subtract_element_forces(&self, e: usize, q: &[f64], v: &[f64], out: &mut [f64]) {
        let no = self.obstacles.len();
        let n_cp = self.points_per_element();
        for k in 0..no {
            if !self.near(e, k, q) {
                continue;
            }
            let b = e * no + k;
            for i in 0..n_cp {
                let (p, x, xd) = self.motion(b, i, q, v);
                let h = &self.hist[(e * n_cp + i) * no + k];
                let Some(res) = self.obstacles[k].evaluate(&self.law, self.w_of(e), &p, &x, &xd, h)
                else {
                    continue;
                };
                let force = res.force();
                for (a, &sa) in self.weights[i].iter().enumerate() {
                    for c in 0..D {
                        out[D * a + c] -= sa * force[c];
                    }
                }
            }
        }
    }

    /// Commits the state at full coordinates `q`, velocities `v`: new histories, the loads
    /// on the obstacles ([`Self::loads`]) and the energy terms. `initial`: no contact is
    /// evaluated (histories at rest).
    pub fn commit(&mut self, q: &[f64], v: &[f64], initial: bool) -> ContactBook {
        self.commit_with::<true>(q, v, initial, None)
    }

    /// [`Self::commit`] without new histories: the loads on the obstacles and the energy
    /// terms of the state at full coordinates `q`, velocities `v`, evaluated with the
    /// histories as they are, which stay unchanged. For a frictionless contact whose
    /// obstacle reads its history only for friction (the air spring's [`AxisymObstacle`] with
    /// `mu = 0`: the loads and the book are those of [`Self::commit`], the histories unused),
    /// it skips the points out of reach and the pass that records every point's position.
    ///
    /// [`AxisymObstacle`]: super::revolution::AxisymObstacle
    ///
    /// With `only = Some(k)` it evaluates obstacle `k` alone: the loads of the others are
    /// zero and the book is obstacle `k`'s (for a model that reads no other load and whose
    /// other obstacles book no energy: no damping, no friction).
    pub fn commit_loads(&mut self, q: &[f64], v: &[f64], only: Option<usize>) -> ContactBook {
        self.commit_with::<false>(q, v, false, only)
    }

    /// [`Self::commit`] (`HISTORIES`) or [`Self::commit_loads`]; `only`: obstacle `k` alone
    /// (without histories only).
    fn commit_with<const HISTORIES: bool>(
        &mut self,
        q: &[f64],
        v: &[f64],
        initial: bool,
        only: Option<usize>,
    ) -> ContactBook {
        debug_assert!(!HISTORIES || only.is_none());
        let no = self.obstacles.len();
        let n_cp = self.points_per_element();
        self.loads.fill(ObstacleLoad::default());
        let mut book = ContactBook::default();
        for e in 0..self.n_elements {
            for k in 0..no {
                if only.is_some_and(|o| o != k) {
                    continue;
                }
                let near = self.near(e, k, q);
                if !HISTORIES && !near {
                    continue;
                }
                let b = e * no + k;
                for i in 0..n_cp {
                    let idx = (e * n_cp + i) * no + k;
                    let (p, x, xd) = self.motion(b, i, q, v);
                    let h = self.hist[idx];
                    let ob = &self.obstacles[k];
                    let res = if near && !initial {
                        ob.evaluate(&self.law, self.w_of(e), &p, &x, &xd, &h)
                    } else {
                        None
                    };
                    if let Some(r) = &res {
                        let load = &mut self.loads[k];
                        for l in 0..O::N_COORDS {
                            load.generalized[l] += r.generalized_force(l);
                        }
                        load.force -= r.force();
                        load.moment += r.moment();
                        load.side_force += r.side_force();
                        book.slipping += r.slipping() as usize;
                        book.normal_energy += r.normal_energy();
                        book.dissipation += r.dissipation();
                        book.friction_work += O::friction_work(self.w_of(e), &h, r);
                    }
                    if HISTORIES {
                        self.hist[idx] = ob.committed(&p, &x, res.as_ref());
                    }
                }
            }
        }
        book
    }

    /// Takes the committed histories of `other`, a set of the same points and obstacles (a
    /// second assembly of the same body, e.g. for a static condensation).
    pub fn copy_histories(&mut self, other: &Self) {
        self.hist.copy_from_slice(&other.hist);
    }

    /// Writes the histories into a snapshot.
    pub fn save(&self, w: &mut StateWriter) {
        write_histories(&self.hist, w);
    }

    /// Writes the committed loads on the obstacles ([`Self::loads`]), for a model whose
    /// outputs read them straight after a state is restored.
    pub fn save_loads(&self, w: &mut StateWriter) {
        write_loads(&self.loads, w);
    }

    /// Reads loads written by [`Self::save_loads`].
    pub fn restore_loads(&mut self, r: &mut StateReader) -> Result<(), String> {
        read_loads(&mut self.loads, r)
    }

    /// Reads histories written by [`Self::save`].
    pub fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        read_histories(&mut self.hist, r)
    }
}

/// Writes contact histories (of a point set or a section set) to a state snapshot.
pub(crate) fn write_histories<H: ContactHistory>(hist: &[H], w: &mut StateWriter) {
    w.u64(hist.len() as u64);
    for h in hist {
        h.save(w);
    }
}

/// Reads histories written by [`write_histories`] into `hist` (same count).
pub(crate) fn read_histories<H: ContactHistory>(
    hist: &mut [H],
    r: &mut StateReader,
) -> Result<(), String> {
    let e = |e: crate::snapshot::SnapshotError| e.to_string();
    if r.u64().map_err(e)? as usize != hist.len() {
        return Err("contact history of another mesh".into());
    }
    for h in hist.iter_mut() {
        *h = H::restore(r).map_err(e)?;
    }
    Ok(())
}

/// Writes obstacle loads (the committed loads of a contact set) to a state snapshot.
pub(crate) fn write_loads<const D: usize>(loads: &[ObstacleLoad<D>], w: &mut StateWriter) {
    w.u64(loads.len() as u64);
    for l in loads {
        for x in l.force.iter().chain(&l.generalized).chain(l.moment.iter()) {
            w.f64(*x);
        }
        w.f64(l.side_force);
    }
}

/// Reads obstacle loads written by [`write_loads`] into `loads` (same count).
pub(crate) fn read_loads<const D: usize>(
    loads: &mut [ObstacleLoad<D>],
    r: &mut StateReader,
) -> Result<(), String> {
    let e = |e: crate::snapshot::SnapshotError| e.to_string();
    if r.u64().map_err(e)? as usize != loads.len() {
        return Err("contact loads of other obstacles".into());
    }
    for l in loads.iter_mut() {
        for x in l
            .force
            .iter_mut()
            .chain(l.generalized.iter_mut())
            .chain(l.moment.iter_mut())
        {
            *x = r.f64().map_err(e)?;
        }
        l.side_force = r.f64().map_err(e)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assembly::{Assembly, DofMap};
    use crate::contact::{Circle, PointHistory};
    use crate::elements::ancf_cable2d::shape_functions;
    use crate::elements::finite_difference as fd;
    use nalgebra::{DMatrix, Vector2};

    /// One cable element (coordinates 0..8) of length 4 mm lying across the top of a circle
    /// of radius 0.1 m (angle: coordinate 8), pressed in by 30 µm at its middle, three points,
    /// moving and with a friction history that makes the points stick or slide.
    fn case() -> (
        ContactPointSet<Circle, 2, 4, 9>,
        Assembly,
        Vec<f64>,
        Vec<f64>,
    ) {
        let law = crate::contact::test_laws::belt();
        let circle = Circle {
            center: Vector2::new(0.0, 0.0),
            radius: 0.1,
        };
        let dofs: Vec<usize> = (0..9).collect();
        let asm = Assembly::new(DofMap::new(&[false; 9]), &[(9, &dofs)], &[]);
        let blocks = Connectivity::new(vec![std::array::from_fn(|i| i)], &asm);
        let mut set = ContactPointSet::new(law, vec![circle], blocks, [0, 2]);
        let l = 4e-3;
        let n_cp = 3;
        let weights = (0..n_cp)
            .map(|i| shape_functions(l, (i as f64 + 0.5) / n_cp as f64 * l))
            .collect();
        set.set_points(weights, l / n_cp as f64);
        let y = 0.1 - 3e-5;
        let q = vec![-0.002, y, 1.0, 0.01, 0.002, y + 1e-6, 1.0, -0.01, 0.3];
        let v = vec![0.4, -0.01, 0.0, 0.2, 0.5, 0.02, 0.1, 0.0, 2.0];
        // histories: the points were 20 µm further back along the circle, pulley turned less
        for (i, h) in set.hist.iter_mut().enumerate() {
            *h = PointHistory::at_angle(
                std::f64::consts::FRAC_PI_2 + 0.01 + 2e-4 * (i as f64 - 1.0),
                0.2999,
                1e-7,
                0.5,
            );
        }
        (set, asm, q, v)
    }

    fn dense(asm: &Assembly, vals: &[f64]) -> DMatrix<f64> {
        DMatrix::from_fn(9, 9, |i, j| {
            asm.pattern.position(i, j).map_or(0.0, |p| vals[p])
        })
    }

    /// The scatter of forces and of the iteration block through the point weights, against
    /// central differences of the scattered residual, in coordinates and in rates.
    #[test]
    fn scattered_jacobian_matches_finite_differences() {
        let (mut set, asm, q, v) = case();
        let mut r = vec![0.0; 9];
        set.add_residual(&q, &v, &mut r, None);
        assert!(r[8].abs() > 0.0 && r[1] < 0.0, "points in contact: {r:?}");
        for (ks, kd) in [(1.0, 0.0), (0.0, 1.0)] {
            let coeffs = JacobianCoeffs {
                mass: 0.0,
                damping: kd,
                stiffness: ks,
            };
            let mut vals = vec![0.0; asm.pattern.nnz()];
            let mut f = vec![0.0; 9];
            set.add_residual(&q, &v, &mut f, Some((coeffs, &mut vals)));
            let x0 = if ks > 0.0 { &q } else { &v };
            let fdm = fd::jacobian(
                x0,
                9,
                |j| if j == 8 || ks == 0.0 { 1e-7 } else { 1e-10 },
                |x, out| {
                    out.fill(0.0);
                    let (qq, vv) = if ks > 0.0 { (x, &v[..]) } else { (&q[..], x) };
                    set.add_residual(qq, vv, out, None);
                },
            );
            let an = dense(&asm, &vals);
            fd::assert_close(&format!("ks {ks} kd {kd}"), &an, &fdm, 1e-5, 1e-6);
        }
    }

    /// The committed loads on the obstacle are what the residual applied: torque on the
    /// pulley = −(its residual entry), and the committed histories relax out of contact.
    #[test]
    fn commit_books_the_loads_of_the_residual() {
        let (mut set, _, q, v) = case();
        let mut r = vec![0.0; 9];
        set.add_residual(&q, &v, &mut r, None);
        let book = set.commit(&q, &v, false);
        let load = set.loads()[0];
        assert!(load.generalized[0].abs() > 1e-6);
        assert!((load.generalized[0] + r[8]).abs() <= 1e-12 * r[8].abs());
        assert!(
            load.force.y < 0.0,
            "the belt presses the pulley down: {:?}",
            load.force
        );
        assert!(book.normal_energy > 0.0);
        // far away: no loads, histories relaxed
        let mut far = q.clone();
        for k in [1, 5] {
            far[k] += 0.01;
        }
        let book = set.commit(&far, &v, false);
        assert_eq!(book, ContactBook::default());
        assert!(set.hist.iter().all(|h| h.z == 0.0 && h.f == 0.0));
        assert_eq!(set.loads()[0], ObstacleLoad::default());
    }
}
