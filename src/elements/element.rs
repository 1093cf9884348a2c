//! The one interface of every finite element: mass, gravity, internal force with strain energy,
//! and the element's part of the residual with its iteration matrix `c_M M + c_C C + c_K K`, all
//! written into caller buffers of fixed size (no allocation per call).
//!
//! An element has `N` coordinates made of *slots* ([`Slot`]) in a fixed order
//! ([`Element::layout`]): positions, directions (position gradients of ANCF elements) and
//! incremental rotation vectors of node frames ([`crate::elements::node_frames`]). For a
//! rotation slot the element sees its node's current orientation `R = R_ref exp(θ̃)` and the
//! tangent `T(θ)` in an [`ElementState`], the coordinate `θ` itself only through them:
//! velocity and acceleration entries of a rotation slot are the body angular velocity `Ω`
//! [rad/s] and its rate `Ω̇` [rad/s²], and force rows of a rotation slot are moments in body
//! components (conjugate to a body spin `δW`, `R → R exp(δW̃)`), so that at `θ = 0` they are
//! `∂U/∂θ` and in general `T(θ)⁻ᵀ ∂U/∂θ`. Stiffness matrices are derivatives with respect to the
//! coordinates (rotation columns chained with `T(θ)`), mass and damping matrices with respect to
//! `a` and `v` as they are.
//!
//! The seed-004 trapezoidal shell (4 nodes × [position, rotation], 24 coordinates, consistent
//! mass in node-fixed frames) fits the same trait: 8 slots, four frames, a configuration-
//! dependent mass handled in [`Element::residual_into`] as the 3D beam does.

use crate::model::JacobianCoeffs;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Most node frames of one element (the seed-004 shell has four nodes).
pub const MAX_FRAMES: usize = 4;

/// Kind of a group of element coordinates, for rigid motions, gravity and node frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// A position (`dim` components) [m]: rotates and translates with a rigid motion.
    Position,
    /// A direction (`dim` components, a position gradient) [1]: rotates with a rigid motion,
    /// does not translate.
    Direction,
    /// An incremental rotation vector of a node frame (3 components) [rad]; velocities and
    /// accelerations are body angular rates, force rows body moments (see the module notes).
    Rotation,
}

/// Coordinate layout of an element: spatial dimension and slots in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Spatial dimension (2 or 3) of positions and directions.
    pub dim: usize,
    /// Slots in the order of the element coordinates.
    pub slots: &'static [Slot],
}

impl Layout {
    /// Number of coordinates of a slot.
    pub fn width(&self, s: Slot) -> usize {
        match s {
            Slot::Rotation => 3,
            _ => self.dim,
        }
    }

    /// `(slot, first coordinate)` of every slot.
    pub fn offsets(&self) -> impl Iterator<Item = (Slot, usize)> + '_ {
        self.slots.iter().scan(0, move |at, &s| {
            let first = *at;
            *at += self.width(s);
            Some((s, first))
        })
    }

    /// Number of coordinates.
    pub fn n_coords(&self) -> usize {
        self.slots.iter().map(|&s| self.width(s)).sum()
    }

    /// Number of rotation slots (node frames).
    pub fn n_frames(&self) -> usize {
        self.slots.iter().filter(|&&s| s == Slot::Rotation).count()
    }
}

/// Orientation of a node frame at the current coordinates: `rot = R_ref exp(θ̃)` and the
/// body tangent `tangent = T(θ)` (`δW = T(θ) δθ`, [`crate::elements::rotation::tangent_body`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Rotation from the reference configuration.
    pub rot: Matrix3<f64>,
    /// Body tangent `T(θ)` of the incremental rotation vector.
    pub tangent: Matrix3<f64>,
}

impl Default for Frame {
    fn default() -> Self {
        Self {
            rot: Matrix3::identity(),
            tangent: Matrix3::identity(),
        }
    }
}

/// The state of one element: gathered coordinates `q`, velocities `v` and, per rotation slot
/// in order, the node frame.
#[derive(Clone, Copy, Debug)]
pub struct ElementState<'a, const N: usize> {
    /// Coordinates (units per slot: m, 1, rad).
    pub q: SVector<f64, N>,
    /// Velocities (m/s, 1/s, body rad/s).
    pub v: SVector<f64, N>,
    /// Node frames of the rotation slots (empty for elements without rotations).
    pub frames: &'a [Frame],
}

impl<'a, const N: usize> ElementState<'a, N> {
    /// A state without node frames.
    pub fn new(q: SVector<f64, N>, v: SVector<f64, N>) -> Self {
        Self { q, v, frames: &[] }
    }
}

/// A finite element with `N` coordinates. Every method writes into the caller's buffers
/// (overwriting them) and allocates nothing.
pub trait Element<const N: usize>: Send + Sync + std::fmt::Debug {
    /// Coordinate layout (slots).
    fn layout(&self) -> Layout;

    /// The mass matrix if it is independent of the state (ANCF elements), else `None`. An
    /// element set assembles a constant mass once and scatters only `K` and `C` per
    /// evaluation.
    fn constant_mass_matrix(&self) -> Option<&SMatrix<f64, N, N>>;

    /// Mass matrix `M = ∂f_inertia/∂a` at the state [kg, kg m, kg m² by slot].
    fn mass_into(&self, s: &ElementState<N>, m: &mut SMatrix<f64, N, N>);

    /// Generalized gravity force `Q_g` [N, N m] for the acceleration `g` [m/s²] (2D elements
    /// use `g.x`, `g.y`).
    fn gravity_into(&self, s: &ElementState<N>, g: &Vector3<f64>, f: &mut SVector<f64, N>);

    /// Strain energy `U` [J].
    fn strain_energy_at(&self, s: &ElementState<N>) -> f64;

    /// Internal force `f_int(q, v)` [N, N m] (elastic plus material damping), returns `U` [J].
    fn force_into(&self, s: &ElementState<N>, f: &mut SVector<f64, N>) -> f64;

    /// Internal force, tangent stiffness `K = ∂f_int/∂q` [N/m, N, N m] and, if `c` is given,
    /// the damping matrix `C = ∂f_int/∂v` [N s/m, ...]; returns `U` [J].
    fn tangent_into(
        &self,
        s: &ElementState<N>,
        f: &mut SVector<f64, N>,
        k: &mut SMatrix<f64, N, N>,
        c: Option<&mut SMatrix<f64, N, N>>,
    ) -> f64;

    /// Kinetic energy [J]; default `½ vᵀ M v`.
    fn kinetic_energy_at(&self, s: &ElementState<N>) -> f64 {
        let mut m = SMatrix::<f64, N, N>::zeros();
        self.mass_into(s, &mut m);
        0.5 * s.v.dot(&(m * s.v))
    }

    /// Power dissipated by the material damping at the state [W]; default 0.
    fn damping_power_at(&self, _s: &ElementState<N>) -> f64 {
        0.0
    }

    /// The element's part of the residual, `f = f_inertia(q, v, a) + f_int(q, v) − Q_g(g)`,
    /// and, if asked, the iteration matrix `c_M ∂f/∂a + c_C ∂f/∂v + c_K ∂f/∂q`; returns `U`
    /// [J]. The default is for a constant mass (`f_inertia = M a`); elements whose inertia
    /// depends on the state override it. Pass `g = 0` when the gravity load is assembled once
    /// elsewhere.
    fn residual_into(
        &self,
        s: &ElementState<N>,
        a: &SVector<f64, N>,
        g: &Vector3<f64>,
        f: &mut SVector<f64, N>,
        mat: Option<(JacobianCoeffs, &mut SMatrix<f64, N, N>)>,
    ) -> f64 {
        let mut buf = SMatrix::<f64, N, N>::zeros();
        let m = match self.constant_mass_matrix() {
            Some(m) => m,
            None => {
                self.mass_into(s, &mut buf);
                &buf
            }
        };
        let u = match mat {
            Some((c, out)) => {
                let mut d = SMatrix::<f64, N, N>::zeros();
                let damped = c.damping != 0.0;
                let u = self.tangent_into(s, f, out, damped.then_some(&mut d));
                // slices: nalgebra's element iterators are not vectorized
                for (o, mi) in out.as_mut_slice().iter_mut().zip(m.as_slice()) {
                    *o = c.stiffness * *o + c.mass * mi;
                }
                if damped {
                    for (o, di) in out.as_mut_slice().iter_mut().zip(d.as_slice()) {
                        *o += c.damping * di;
                    }
                }
                u
            }
            None => self.force_into(s, f),
        };
        f.gemv(1.0, m, a, 1.0);
        if *g != Vector3::zeros() {
            let mut qg = SVector::<f64, N>::zeros();
            self.gravity_into(s, g, &mut qg);
            *f -= qg;
        }
        u
    }

    /// Energy-conserving ("average stress") internal force of the midpoint rule between the
    /// states `a` and `b`, with `Q·(q_b − q_a) = U(q_b) − U(q_a)`, and with `k` its derivative
    /// with respect to `q_b`. Returns `false` (and writes nothing) if the element has no such
    /// form; the default.
    fn average_force_into(
        &self,
        _a: &ElementState<N>,
        _b: &ElementState<N>,
        _f: &mut SVector<f64, N>,
        _k: Option<&mut SMatrix<f64, N, N>>,
    ) -> bool {
        false
    }
}

/// A shared element (one element for a uniform mesh, or a trait object) is an element.
impl<const N: usize, T: Element<N> + ?Sized> Element<N> for std::sync::Arc<T> {
    fn layout(&self) -> Layout {
        (**self).layout()
    }
    fn constant_mass_matrix(&self) -> Option<&SMatrix<f64, N, N>> {
        (**self).constant_mass_matrix()
    }
    fn mass_into(&self, s: &ElementState<N>, m: &mut SMatrix<f64, N, N>) {
        (**self).mass_into(s, m)
    }
    fn gravity_into(&self, s: &ElementState<N>, g: &Vector3<f64>, f: &mut SVector<f64, N>) {
        (**self).gravity_into(s, g, f)
    }
    fn strain_energy_at(&self, s: &ElementState<N>) -> f64 {
        (**self).strain_energy_at(s)
    }
    fn force_into(&self, s: &ElementState<N>, f: &mut SVector<f64, N>) -> f64 {
        (**self).force_into(s, f)
    }
    fn tangent_into(
        &self,
        s: &ElementState<N>,
        f: &mut SVector<f64, N>,
        k: &mut SMatrix<f64, N, N>,
        c: Option<&mut SMatrix<f64, N, N>>,
    ) -> f64 {
        (**self).tangent_into(s, f, k, c)
    }
    fn kinetic_energy_at(&self, s: &ElementState<N>) -> f64 {
        (**self).kinetic_energy_at(s)
    }
    fn damping_power_at(&self, s: &ElementState<N>) -> f64 {
        (**self).damping_power_at(s)
    }
    fn residual_into(
        &self,
        s: &ElementState<N>,
        a: &SVector<f64, N>,
        g: &Vector3<f64>,
        f: &mut SVector<f64, N>,
        mat: Option<(JacobianCoeffs, &mut SMatrix<f64, N, N>)>,
    ) -> f64 {
        (**self).residual_into(s, a, g, f, mat)
    }
    fn average_force_into(
        &self,
        a: &ElementState<N>,
        b: &ElementState<N>,
        f: &mut SVector<f64, N>,
        k: Option<&mut SMatrix<f64, N, N>>,
    ) -> bool {
        (**self).average_force_into(a, b, f, k)
    }
}
