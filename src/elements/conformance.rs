//! Element conformance: the checks every element passes, in one line per element with
//! [`element_conformance!`](crate::element_conformance):
//!
//! * mass symmetric and positive definite;
//! * gravity = `M u_g`, with `u_g` the rigid translation field by `g` (positions `g`,
//!   directions and rotations 0). This holds for a consistent mass and for a lumped mass whose
//!   gravity acts on the same mass points as its inertia (the 3D beam's three lumped masses); it
//!   does not say that `M` is the consistent mass;
//! * internal force = gradient of the strain energy (finite differences; rotation rows are body
//!   moments, so `T(θ)ᵀ f` is compared with `∂U/∂θ`), at zero velocity;
//! * tangent stiffness `K` and damping matrix `C` against finite differences of the force, and
//!   the iteration matrix `c_M M + c_C C + c_K K` of [`Element::residual_into`] (inertia and
//!   gravity included) against finite differences of its force in `a`, `v` and `q`;
//! * rigid-motion invariance: a rigid translation and rotations of any size leave the strain
//!   energy unchanged and turn the internal force with the body (positions and directions
//!   rotated, body moments unchanged);
//! * self-equilibrium: the internal force (elastic and damping) does no work on infinitesimal
//!   rigid motions: zero resultant force and zero resultant moment.
//!
//! Tolerances: `1e-6` relative for finite differences, `1e-10` for identities, with an absolute
//! floor from the element's own stiffness (`‖K‖` times the element size times `1e-11`, scaled
//! up with the distance from the origin for round-off of large coordinates).

use super::element::{Element, ElementState, Frame, Layout, MAX_FRAMES, Slot};
use super::finite_difference::{assert_close, gradient, jacobian};
use super::rotation::{exp_so3, tangent_body};
use crate::model::JacobianCoeffs;
use nalgebra::{DMatrix, Matrix3, SMatrix, SVector, Vector3};

/// Relative tolerance of finite-difference checks.
const FD_RTOL: f64 = 1e-6;
/// Relative tolerance of identities.
const RTOL: f64 = 1e-10;
/// Relative finite-difference step in the coordinates (of the element size for positions,
/// absolute otherwise).
const STEP: f64 = 1e-6;
/// Finite-difference step in velocities [1/s, m/s] and accelerations: forces are at most
/// quadratic in them (gyroscopic terms), for which central differences are exact, so a large
/// step keeps the round-off of large elastic forces out of the mass and damping parts.
const STEP_RATES: f64 = 1e-2;

/// One state of an element under test.
#[derive(Clone, Debug)]
pub struct Config<const N: usize> {
    /// Name in failure messages ("reference", "bent", ...).
    pub label: &'static str,
    /// Coordinates.
    pub q: SVector<f64, N>,
    /// Velocities.
    pub v: SVector<f64, N>,
    /// Accelerations (for the iteration matrix).
    pub a: SVector<f64, N>,
    /// Stored orientation `R_ref` of every rotation slot (empty without rotations).
    pub r_ref: Vec<Matrix3<f64>>,
}

impl<const N: usize> Config<N> {
    /// A state at rest without node frames.
    pub fn at(label: &'static str, q: SVector<f64, N>) -> Self {
        Self {
            label,
            q,
            v: SVector::zeros(),
            a: SVector::zeros(),
            r_ref: Vec::new(),
        }
    }

    /// With velocities and accelerations.
    pub fn moving(mut self, v: SVector<f64, N>, a: SVector<f64, N>) -> Self {
        self.v = v;
        self.a = a;
        self
    }

    /// With stored node orientations.
    pub fn frames(mut self, r_ref: Vec<Matrix3<f64>>) -> Self {
        self.r_ref = r_ref;
        self
    }
}

/// An element and the states it is checked in.
#[derive(Clone, Debug)]
pub struct Case<E, const N: usize> {
    /// The element.
    pub element: E,
    /// States (reference, bent, large rigid rotation, stretched, ...).
    pub states: Vec<Config<N>>,
}

/// Gravity of the checks [m/s²] (2D elements use x and y).
pub const GRAVITY: Vector3<f64> = Vector3::new(0.3, -9.81, 1.7);

/// Node frames of a configuration at coordinates `q`.
fn frames_at<const N: usize>(
    layout: &Layout,
    c: &Config<N>,
    q: &SVector<f64, N>,
) -> [Frame; MAX_FRAMES] {
    let mut out = [Frame::default(); MAX_FRAMES];
    let mut k = 0;
    for (slot, at) in layout.offsets() {
        if slot == Slot::Rotation {
            let th = q.fixed_rows::<3>(at).into_owned();
            out[k] = Frame {
                rot: c.r_ref[k] * exp_so3(&th),
                tangent: tangent_body(&th),
            };
            k += 1;
        }
    }
    out
}

/// Calls `f` with the element state at `(q, v)` of configuration `c`.
fn with_state<const N: usize, R>(
    layout: &Layout,
    c: &Config<N>,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
    f: impl FnOnce(&ElementState<N>) -> R,
) -> R {
    let fr = frames_at(layout, c, q);
    let s = ElementState {
        q: *q,
        v: *v,
        frames: &fr[..layout.n_frames()],
    };
    f(&s)
}

fn sv<const N: usize>(x: &[f64]) -> SVector<f64, N> {
    SVector::<f64, N>::from_column_slice(x)
}

fn dm<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

/// Element size (largest distance between two position slots) and largest position
/// component [m].
fn sizes<const N: usize>(layout: &Layout, q: &SVector<f64, N>) -> (f64, f64) {
    let pos: Vec<Vector3<f64>> = layout
        .offsets()
        .filter(|(s, _)| *s == Slot::Position)
        .map(|(_, at)| {
            let mut x = Vector3::zeros();
            x.rows_mut(0, layout.dim).copy_from(&q.rows(at, layout.dim));
            x
        })
        .collect();
    let mut len: f64 = 0.0;
    let mut xmax: f64 = 0.0;
    for a in &pos {
        xmax = xmax.max(a.amax());
        for b in &pos {
            len = len.max((a - b).norm());
        }
    }
    (len, xmax)
}

/// Finite-difference step of every coordinate.
fn steps(layout: &Layout, len: f64) -> Vec<f64> {
    let mut h = Vec::new();
    for (slot, _) in layout.offsets() {
        let s = if slot == Slot::Position {
            STEP * len
        } else {
            STEP
        };
        h.extend(std::iter::repeat_n(s, layout.width(slot)));
    }
    h
}

/// `‖K‖` at a configuration (with velocities).
fn stiffness_norm<E: Element<N>, const N: usize>(el: &E, c: &Config<N>) -> f64 {
    let layout = el.layout();
    with_state(&layout, c, &c.q, &c.v, |s| {
        let (mut f, mut k, mut d) = (SVector::zeros(), SMatrix::zeros(), SMatrix::zeros());
        el.tangent_into(s, &mut f, &mut k, Some(&mut d));
        k.norm()
    })
}

/// Absolute force floor of identities (round-off) [N]:
/// `‖K‖ · max(size, largest coordinate) · 1e-11`.
fn force_floor<E: Element<N>, const N: usize>(el: &E, c: &Config<N>) -> f64 {
    let (len, xmax) = sizes(&el.layout(), &c.q);
    stiffness_norm(el, c) * len.max(xmax) * 1e-11
}

/// Force scale of finite-difference checks [N]: the force of a 0.1 % strain, `‖K‖ · size ·
/// 1e-3` (forces that vanish, as in the reference state, are compared with it).
fn fd_force_scale<E: Element<N>, const N: usize>(el: &E, c: &Config<N>) -> f64 {
    let (len, _) = sizes(&el.layout(), &c.q);
    stiffness_norm(el, c) * len * 1e-3
}

/// Mass symmetric and positive definite in every state.
pub fn check_mass<E: Element<N>, const N: usize>(case: &Case<E, N>) {
    let el = &case.element;
    let layout = el.layout();
    for c in &case.states {
        let m = with_state(&layout, c, &c.q, &c.v, |s| {
            let mut m = SMatrix::<f64, N, N>::zeros();
            el.mass_into(s, &mut m);
            m
        });
        let asym = (m - m.transpose()).norm() / m.norm();
        assert!(asym <= RTOL, "{}: mass not symmetric ({asym:.2e})", c.label);
        let min = dm(&m).symmetric_eigenvalues().min();
        assert!(
            min > 1e-12 * m.norm(),
            "{}: mass not positive definite (smallest eigenvalue {min:.3e}, ‖M‖ = {:.3e})",
            c.label,
            m.norm()
        );
    }
}

/// The rigid translation field by `g`: positions `g`, everything else 0.
pub fn translation_field<const N: usize>(layout: &Layout, g: &Vector3<f64>) -> SVector<f64, N> {
    let mut u = SVector::<f64, N>::zeros();
    for (slot, at) in layout.offsets() {
        if slot == Slot::Position {
            u.rows_mut(at, layout.dim).copy_from(&g.rows(0, layout.dim));
        }
    }
    u
}

/// Gravity equals the mass times the rigid translation field by `g`.
pub fn check_gravity<E: Element<N>, const N: usize>(case: &Case<E, N>) {
    let el = &case.element;
    let layout = el.layout();
    for c in &case.states {
        let (qg, m) = with_state(&layout, c, &c.q, &c.v, |s| {
            let mut qg = SVector::<f64, N>::zeros();
            let mut m = SMatrix::<f64, N, N>::zeros();
            el.gravity_into(s, &GRAVITY, &mut qg);
            el.mass_into(s, &mut m);
            (qg, m)
        });
        let mu = m * translation_field::<N>(&layout, &GRAVITY);
        let err = (qg - mu).norm() / mu.norm();
        assert!(
            err <= RTOL,
            "{}: gravity {qg:?} differs from M u_g {mu:?} (relative {err:.2e})",
            c.label
        );
    }
}

/// The internal force at rest is the gradient of the strain energy (rotation rows through
/// `T(θ)ᵀ`).
pub fn check_energy_gradient<E: Element<N>, const N: usize>(case: &Case<E, N>) {
    let el = &case.element;
    let layout = el.layout();
    let zero = SVector::<f64, N>::zeros();
    for c in &case.states {
        let (len, _) = sizes(&layout, &c.q);
        let h = steps(&layout, len);
        let (f, u) = with_state(&layout, c, &c.q, &zero, |s| {
            let mut f = SVector::<f64, N>::zeros();
            let u = el.force_into(s, &mut f);
            // rows conjugate to θ: T(θ)ᵀ times the body moments
            let mut k = 0;
            for (slot, at) in layout.offsets() {
                if slot == Slot::Rotation {
                    let m = s.frames[k].tangent.transpose() * f.fixed_rows::<3>(at);
                    f.fixed_rows_mut::<3>(at).copy_from(&m);
                    k += 1;
                }
            }
            (f, u)
        });
        let u_direct = with_state(&layout, c, &c.q, &zero, |s| el.strain_energy_at(s));
        assert!(
            (u - u_direct).abs() <= RTOL * u.abs().max(1e-300),
            "{}: force_into returns U = {u}, strain_energy_at {u_direct}",
            c.label
        );
        let g = gradient(
            c.q.as_slice(),
            |j| h[j],
            |x| with_state(&layout, c, &sv(x), &zero, |s| el.strain_energy_at(s)),
        );
        let floor = fd_force_scale(el, c);
        assert_close(
            &format!(
                "{}: internal force vs gradient of the strain energy",
                c.label
            ),
            &DMatrix::from_column_slice(N, 1, f.as_slice()),
            &DMatrix::from_column_slice(N, 1, &g),
            FD_RTOL,
            floor,
        );
    }
}

/// Tangent stiffness and damping matrices against finite differences of the internal force.
pub fn check_tangent<E: Element<N>, const N: usize>(case: &Case<E, N>) {
    let el = &case.element;
    let layout = el.layout();
    for c in &case.states {
        let (len, _) = sizes(&layout, &c.q);
        let h = steps(&layout, len);
        let (f, k, d) = with_state(&layout, c, &c.q, &c.v, |s| {
            let (mut f, mut k, mut d) = (SVector::zeros(), SMatrix::zeros(), SMatrix::zeros());
            el.tangent_into(s, &mut f, &mut k, Some(&mut d));
            (f, k, d)
        });
        let f2 = with_state(&layout, c, &c.q, &c.v, |s| {
            let mut f = SVector::<f64, N>::zeros();
            el.force_into(s, &mut f);
            f
        });
        assert!(
            (f - f2).norm() <= RTOL * f.norm() + force_floor(el, c),
            "{}: tangent_into and force_into disagree on the force",
            c.label
        );
        let force = |q: &SVector<f64, N>, v: &SVector<f64, N>, out: &mut [f64]| {
            with_state(&layout, c, q, v, |s| {
                let mut f = SVector::<f64, N>::zeros();
                el.force_into(s, &mut f);
                out.copy_from_slice(f.as_slice());
            })
        };
        let kfd = jacobian(
            c.q.as_slice(),
            N,
            |j| h[j],
            |x, out| force(&sv(x), &c.v, out),
        );
        assert_close(
            &format!("{}: tangent stiffness K", c.label),
            &dm(&k),
            &kfd,
            FD_RTOL,
            k.norm() * 1e-9,
        );
        let cfd = jacobian(
            c.v.as_slice(),
            N,
            |_| STEP_RATES,
            |x, out| force(&c.q, &sv(x), out),
        );
        assert_close(
            &format!("{}: damping matrix C", c.label),
            &dm(&d),
            &cfd,
            FD_RTOL,
            k.norm() * 1e-9,
        );
    }
}

/// The iteration matrix of [`Element::residual_into`] (with gravity) against finite
/// differences of its force in `a` (mass), `v` (damping, gyroscopic) and `q` (stiffness).
pub fn check_iteration_matrix<E: Element<N>, const N: usize>(case: &Case<E, N>) {
    let el = &case.element;
    let layout = el.layout();
    for c in &case.states {
        let (len, _) = sizes(&layout, &c.q);
        let h = steps(&layout, len);
        let residual = |q: &SVector<f64, N>, v: &SVector<f64, N>, a: &SVector<f64, N>| {
            with_state(&layout, c, q, v, |s| {
                let mut f = SVector::<f64, N>::zeros();
                el.residual_into(s, a, &GRAVITY, &mut f, None);
                f
            })
        };
        let matrix = |coeffs: JacobianCoeffs| {
            with_state(&layout, c, &c.q, &c.v, |s| {
                let mut f = SVector::<f64, N>::zeros();
                let mut m = SMatrix::<f64, N, N>::zeros();
                el.residual_into(s, &c.a, &GRAVITY, &mut f, Some((coeffs, &mut m)));
                (f, m)
            })
        };
        let unit = |mass, damping, stiffness| JacobianCoeffs {
            mass,
            damping,
            stiffness,
        };
        let f0 = residual(&c.q, &c.v, &c.a);
        let (f1, mm) = matrix(unit(1.0, 0.0, 0.0));
        let (_, cc) = matrix(unit(0.0, 1.0, 0.0));
        let (_, kk) = matrix(unit(0.0, 0.0, 1.0));
        let (_, all) = matrix(unit(2.0, 0.3, 0.7));
        let floor = force_floor(el, c);
        assert!(
            (f0 - f1).norm() <= RTOL * f0.norm() + floor,
            "{}: residual_into gives another force when asked for the matrix",
            c.label
        );
        let comb = mm * 2.0 + cc * 0.3 + kk * 0.7;
        assert!(
            (all - comb).norm() <= RTOL * comb.norm(),
            "{}: the iteration matrix is not linear in its coefficients",
            c.label
        );
        let out = |f: SVector<f64, N>, o: &mut [f64]| o.copy_from_slice(f.as_slice());
        let mfd = jacobian(
            c.a.as_slice(),
            N,
            |_| STEP_RATES,
            |x, o| out(residual(&c.q, &c.v, &sv(x)), o),
        );
        let floor_m = mm.norm() * 1e-9;
        assert_close(
            &format!("{}: mass part", c.label),
            &dm(&mm),
            &mfd,
            FD_RTOL,
            floor_m,
        );
        let cfd = jacobian(
            c.v.as_slice(),
            N,
            |_| STEP_RATES,
            |x, o| out(residual(&c.q, &sv(x), &c.a), o),
        );
        assert_close(
            &format!("{}: damping part (material and gyroscopic)", c.label),
            &dm(&cc),
            &cfd,
            FD_RTOL,
            floor_m.max(kk.norm() * 1e-9),
        );
        let kfd = jacobian(
            c.q.as_slice(),
            N,
            |j| h[j],
            |x, o| out(residual(&sv(x), &c.v, &c.a), o),
        );
        assert_close(
            &format!("{}: stiffness part (elastic, inertia, gravity)", c.label),
            &dm(&kk),
            &kfd,
            FD_RTOL,
            kk.norm() * 1e-9,
        );
    }
}

/// A rigid motion `x → Q x + t` of a configuration: positions rotated and translated,
/// directions rotated, stored orientations turned (`R_ref → Q R_ref`, θ unchanged); velocities
/// and accelerations of positions and directions rotated, body rates unchanged. 2D elements
/// use the upper-left block of `Q` (a rotation about z).
pub fn rigid_motion<const N: usize>(
    layout: &Layout,
    c: &Config<N>,
    q: &Matrix3<f64>,
    t: &Vector3<f64>,
) -> Config<N> {
    let mut out = c.clone();
    let d = layout.dim;
    let turn = |x: &SVector<f64, N>, at: usize, shift: bool, y: &mut SVector<f64, N>| {
        let mut p = Vector3::zeros();
        p.rows_mut(0, d).copy_from(&x.rows(at, d));
        let mut r = q * p;
        if shift {
            r += t;
        }
        y.rows_mut(at, d).copy_from(&r.rows(0, d));
    };
    for (slot, at) in layout.offsets() {
        match slot {
            Slot::Position | Slot::Direction => {
                turn(&c.q, at, slot == Slot::Position, &mut out.q);
                turn(&c.v, at, false, &mut out.v);
                turn(&c.a, at, false, &mut out.a);
            }
            Slot::Rotation => {}
        }
    }
    for r in out.r_ref.iter_mut() {
        *r = q * *r;
    }
    out
}

/// The force of a configuration turned by `Q` (positions and directions rotated, body
/// moments unchanged).
fn rotate_force<const N: usize>(
    layout: &Layout,
    q: &Matrix3<f64>,
    f: &SVector<f64, N>,
) -> SVector<f64, N> {
    let mut out = *f;
    let d = layout.dim;
    for (slot, at) in layout.offsets() {
        if slot != Slot::Rotation {
            let mut x = Vector3::zeros();
            x.rows_mut(0, d).copy_from(&f.rows(at, d));
            let y = q * x;
            out.rows_mut(at, d).copy_from(&y.rows(0, d));
        }
    }
    out
}

/// Rigid motions of the checks: a translation and rotations of 0.9 rad, π and 2π + 1 rad
/// about a skew axis (about z in 2D), each with a translation.
pub fn rigid_motions(dim: usize) -> Vec<(Matrix3<f64>, Vector3<f64>)> {
    let axis = if dim == 2 {
        Vector3::z()
    } else {
        Vector3::new(0.3, -0.5, 0.8).normalize()
    };
    let t = if dim == 2 {
        Vector3::new(3.0, -1.0, 0.0)
    } else {
        Vector3::new(3.0, -1.0, 2.0)
    };
    vec![
        (Matrix3::identity(), t),
        (exp_so3(&(axis * 0.9)), Vector3::zeros()),
        (exp_so3(&(axis * std::f64::consts::PI)), t),
        (exp_so3(&(axis * (2.0 * std::f64::consts::PI + 1.0))), -t),
    ]
}

/// Strain energy unchanged and internal force turned with the body under rigid motions.
pub fn check_rigid_motion<E: Element<N>, const N: usize>(case: &Case<E, N>) {
    let el = &case.element;
    let layout = el.layout();
    for c in &case.states {
        let eval = |cfg: &Config<N>| {
            with_state(&layout, cfg, &cfg.q, &cfg.v, |s| {
                let mut f = SVector::<f64, N>::zeros();
                let u = el.force_into(s, &mut f);
                (u, f)
            })
        };
        let (u0, f0) = eval(c);
        for (q, t) in rigid_motions(layout.dim) {
            let moved = rigid_motion(&layout, c, &q, &t);
            let (u1, f1) = eval(&moved);
            let floor = force_floor(el, c).max(force_floor(el, &moved));
            let (len, _) = sizes(&layout, &c.q);
            assert!(
                (u1 - u0).abs() <= RTOL * u0.abs() + floor * len,
                "{}: strain energy {u0:.10e} becomes {u1:.10e} under a rigid motion (Q = {q:?}, t = {t:?})",
                c.label
            );
            let expect = rotate_force(&layout, &q, &f0);
            let err = (f1 - expect).norm();
            assert!(
                err <= 1e-8 * f0.norm() + floor,
                "{}: internal force not turned with the body under a rigid motion (error {err:.3e}, ‖f‖ = {:.3e}, floor {floor:.1e})",
                c.label,
                f0.norm()
            );
        }
    }
}

/// Resultant force and moment about the origin of a force vector: `Σ f_pos`,
/// `Σ x × f_pos + Σ d × f_dir + Σ R m_body` (3D components; 2D in the x-y plane).
pub fn resultants<const N: usize>(
    layout: &Layout,
    s: &ElementState<N>,
    f: &SVector<f64, N>,
) -> (Vector3<f64>, Vector3<f64>) {
    let d = layout.dim;
    let (mut force, mut moment) = (Vector3::zeros(), Vector3::zeros());
    let mut k = 0;
    let v3 = |x: &SVector<f64, N>, at: usize| {
        let mut p = Vector3::zeros();
        p.rows_mut(0, d).copy_from(&x.rows(at, d));
        p
    };
    for (slot, at) in layout.offsets() {
        match slot {
            Slot::Position => {
                force += v3(f, at);
                moment += v3(&s.q, at).cross(&v3(f, at));
            }
            Slot::Direction => moment += v3(&s.q, at).cross(&v3(f, at)),
            Slot::Rotation => {
                moment += s.frames[k].rot * f.fixed_rows::<3>(at);
                k += 1;
            }
        }
    }
    (force, moment)
}

/// The internal force (elastic and damping) has zero resultant force and moment.
pub fn check_self_equilibrium<E: Element<N>, const N: usize>(case: &Case<E, N>) {
    let el = &case.element;
    let layout = el.layout();
    for c in &case.states {
        let (len, xmax) = sizes(&layout, &c.q);
        let floor = force_floor(el, c);
        let (nf, force, moment) = with_state(&layout, c, &c.q, &c.v, |s| {
            let mut f = SVector::<f64, N>::zeros();
            el.force_into(s, &mut f);
            let (force, moment) = resultants(&layout, s, &f);
            (f.norm(), force, moment)
        });
        assert!(
            force.norm() <= 1e-9 * nf + floor,
            "{}: resultant force {force:?} (‖f‖ = {nf:.3e})",
            c.label
        );
        let arm = len.max(xmax).max(1.0);
        assert!(
            moment.norm() <= (1e-9 * nf + floor) * arm,
            "{}: resultant moment {moment:?} (‖f‖ = {nf:.3e})",
            c.label
        );
    }
}

/// Generates one test per conformance property for an element: `element_conformance!(name,
/// || case)` where the closure returns a [`Case`] (the element and its states).
#[macro_export]
macro_rules! element_conformance {
    ($name:ident, $make:expr) => {
        mod $name {
            #[allow(unused_imports)]
            use super::*;
            use $crate::elements::conformance as c;

            #[test]
            fn mass_is_symmetric_positive_definite() {
                c::check_mass(&($make)());
            }
            #[test]
            fn gravity_is_mass_times_translation() {
                c::check_gravity(&($make)());
            }
            #[test]
            fn force_is_energy_gradient() {
                c::check_energy_gradient(&($make)());
            }
            #[test]
            fn tangent_and_damping_match_finite_differences() {
                c::check_tangent(&($make)());
            }
            #[test]
            fn iteration_matrix_matches_finite_differences() {
                c::check_iteration_matrix(&($make)());
            }
            #[test]
            fn rigid_motion_is_invariant() {
                c::check_rigid_motion(&($make)());
            }
            #[test]
            fn internal_force_is_self_equilibrated() {
                c::check_self_equilibrium(&($make)());
            }
        }
    };
}

#[cfg(test)]
mod tests {
    //! Each check fails on an element with the defect it looks for.
    use super::*;
    use crate::elements::ancf_cable2d::{
        AncfCable2d, CableRule, CableSection, straight_coordinates,
    };
    use nalgebra::Vector2;

    /// Which defect the wrapped cable has.
    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Defect {
        AsymmetricMass,
        WrongGravity,
        ForceNotGradient,
        WrongTangent,
        WrongDamping,
        WrongIterationMass,
        ConstantForce,
    }

    #[derive(Clone, Debug)]
    struct Broken(AncfCable2d, Defect);

    type V = SVector<f64, 8>;
    type M = SMatrix<f64, 8, 8>;

    impl Element<8> for Broken {
        fn layout(&self) -> Layout {
            self.0.layout()
        }
        fn constant_mass_matrix(&self) -> Option<&M> {
            None
        }
        fn mass_into(&self, s: &ElementState<8>, m: &mut M) {
            self.0.mass_into(s, m);
            if self.1 == Defect::AsymmetricMass {
                m[(0, 1)] += 1e-3 * m[(0, 0)];
            }
        }
        fn gravity_into(&self, s: &ElementState<8>, g: &Vector3<f64>, f: &mut V) {
            self.0.gravity_into(s, g, f);
            if self.1 == Defect::WrongGravity {
                f[1] *= 1.01;
            }
        }
        fn strain_energy_at(&self, s: &ElementState<8>) -> f64 {
            self.0.strain_energy_at(s)
        }
        fn force_into(&self, s: &ElementState<8>, f: &mut V) -> f64 {
            let u = self.0.force_into(s, f);
            match self.1 {
                Defect::ForceNotGradient => *f *= 1.001,
                Defect::ConstantForce => f[0] += 1.0,
                _ => {}
            }
            u
        }
        fn tangent_into(
            &self,
            s: &ElementState<8>,
            f: &mut V,
            k: &mut M,
            mut c: Option<&mut M>,
        ) -> f64 {
            let u = self.0.tangent_into(s, f, k, c.as_deref_mut());
            self.force_into(s, f);
            match self.1 {
                Defect::WrongTangent => k[(2, 3)] += 1e-3 * k.norm(),
                Defect::WrongDamping => {
                    if let Some(c) = c {
                        c[(0, 0)] += 1e-3 * c.norm().max(1.0)
                    }
                }
                _ => {}
            }
            u
        }
        fn residual_into(
            &self,
            s: &ElementState<8>,
            a: &V,
            g: &Vector3<f64>,
            f: &mut V,
            mat: Option<(JacobianCoeffs, &mut M)>,
        ) -> f64 {
            let wrong = self.1 == Defect::WrongIterationMass;
            match mat {
                Some((c, m)) => {
                    let u = self.0.residual_into(s, a, g, f, Some((c, &mut *m)));
                    if wrong {
                        m[(0, 0)] *= 1.0 + 1e-3 * c.mass.signum();
                    }
                    u
                }
                None => self.0.residual_into(s, a, g, f, None),
            }
        }
    }

    fn case(defect: Defect) -> Case<Broken, 8> {
        let sec = CableSection {
            ea: 5e4,
            ei: 0.8,
            mass_per_length: 0.2,
            damping_axial: 30.0,
            damping_bending: 2e-3,
            prestrain: 0.0,
        };
        let q = straight_coordinates(Vector2::zeros(), Vector2::new(0.3, 0.0), 1.0)
            + V::from_column_slice(&[2e-3, -1e-3, 0.02, 0.15, 4e-3, 0.03, -0.05, -0.1]);
        let v = V::from_column_slice(&[0.3, -0.2, 0.5, 1.0, -0.4, 0.1, 0.7, -0.3]);
        Case {
            element: Broken(AncfCable2d::new(0.3, sec, CableRule::Full), defect),
            states: vec![Config::at("bent", q).moving(v, v)],
        }
    }

    #[test]
    #[should_panic(expected = "mass not symmetric")]
    fn detects_asymmetric_mass() {
        check_mass(&case(Defect::AsymmetricMass));
    }

    #[test]
    #[should_panic(expected = "differs from M u_g")]
    fn detects_wrong_gravity() {
        check_gravity(&case(Defect::WrongGravity));
    }

    #[test]
    #[should_panic(expected = "gradient of the strain energy")]
    fn detects_force_that_is_not_the_energy_gradient() {
        check_energy_gradient(&case(Defect::ForceNotGradient));
    }

    #[test]
    #[should_panic(expected = "tangent stiffness K")]
    fn detects_wrong_tangent() {
        check_tangent(&case(Defect::WrongTangent));
    }

    #[test]
    #[should_panic(expected = "damping matrix C")]
    fn detects_wrong_damping_matrix() {
        check_tangent(&case(Defect::WrongDamping));
    }

    #[test]
    #[should_panic(expected = "mass part")]
    fn detects_wrong_iteration_matrix() {
        check_iteration_matrix(&case(Defect::WrongIterationMass));
    }

    #[test]
    #[should_panic(expected = "not turned with the body")]
    fn detects_force_that_does_not_turn() {
        check_rigid_motion(&case(Defect::ConstantForce));
    }

    #[test]
    #[should_panic(expected = "resultant force")]
    fn detects_unbalanced_force() {
        check_self_equilibrium(&case(Defect::ConstantForce));
    }

    /// The unbroken wrapper passes every check (so the failures above come from the defects).
    #[test]
    fn intact_element_passes() {
        let c = case(Defect::AsymmetricMass);
        let intact = Case {
            element: c.element.0.clone(),
            states: c.states,
        };
        check_mass(&intact);
        check_gravity(&intact);
        check_energy_gradient(&intact);
        check_tangent(&intact);
        check_iteration_matrix(&intact);
        check_rigid_motion(&intact);
        check_self_equilibrium(&intact);
    }
}
