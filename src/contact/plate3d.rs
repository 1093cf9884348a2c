//! A flat plate in space that moves in five axes: the top plate of the air spring's shell level
//! as an obstacle of the shared [`super::ContactPointSet`]. Its own coordinates are the plate's
//! pose `x = (c_x, c_y, c_z, θ_x, θ_y)`: the centre `c` [m] and the tilt, a rotation vector
//! `θ = (θ_x, θ_y, 0)` [rad] (`R = exp(θ̃)`, as the shell kind turns its bead ring). The solid
//! is the half space above the plate's plane, `(r − c) · n > 0` with `n = R e_z`, out to the
//! plate radius `radius` (measured in the plane from `c`; beyond it no contact): a sleeve that
//! hangs below the plate touches it from the gas side.
//!
//! Frictionless penalty contact with the smoothed normal law of the piston
//! ([`super::circle_friction::smoothed_penalty`]): penetration `δ = (r − c) · n`, pressure
//! `p = p_e(δ) + d_n ramp(δ) δ̇` [Pa], a point standing for the area `w` [m²] is pushed by
//! `F = −w p n` [N]; the plate takes `w p n` and the moment `(r − c) × w p n` about its centre.
//! The force vector over `X = (r, x)` (point position, plate coordinates) is
//! `F = −w p ∇δ` (the obstacle's generalized forces `−w p ∂δ/∂x`, as the gradient of the
//! penalty energy), with the iteration block
//! `∂F/∂X = −w p_δ ∇δ ∇δᵀ − w d_n ramp ∇δ (H Ẋ)ᵀ − w p H` (`H` the Hessian of `δ`) and
//! `∂F/∂Ẋ = −w d_n ramp ∇δ ∇δᵀ`. Friction (`contact.mu`) is not applied on the plate.
//!
//! The normal of the tilt `θ = (a, b, 0)` in closed form: with `u = a² + b²`,
//! `f(u) = sin √u / √u` and `g(u) = cos √u`, `n = (b f, −a f, g)` (Rodrigues' formula with
//! `θ · e_z = 0`); its first and second derivatives follow from `f'`, `f''`, `g' = −f/2`,
//! `g'' = −f'/2` (series for small `u`).

use super::circle_friction::{ContactLaw, smoothed_penalty};
use super::obstacle::{Obstacle, ObstacleContact, PointMotion};
use super::revolution::NoHistory;
use nalgebra::{SMatrix, SVector, Vector3};

/// Number of the plate's own coordinates `(c_x, c_y, c_z, θ_x, θ_y)`.
pub const PLATE_COORDS: usize = 5;

/// Size of the force vector `(point, plate coordinates)`.
const NX: usize = 3 + PLATE_COORDS;

/// The plate: the solid above its plane out to `radius` [m] from its centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plate3d {
    /// Outer radius of the plate, in its plane from the centre [m].
    pub radius: f64,
}

/// An active contact point on the plate: the force vector and what its derivatives need.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plate3dContact {
    /// Force on the point `−w p n` [N].
    pub force: Vector3<f64>,
    /// Penetration `δ` [m].
    pub penetration: f64,
    /// `∇δ` over `X = (r, c, θ_x, θ_y)`.
    grad: SVector<f64, NX>,
    /// `H Ẋ` (the rate's change with position).
    h_rate: SVector<f64, NX>,
    /// Hessian `H` of `δ` over `X`.
    hess: SMatrix<f64, NX, NX>,
    /// `w p` [N/m²·m²].
    wp: f64,
    /// `w ∂p/∂δ`, `w ∂p/∂δ̇`.
    dp: [f64; 2],
    /// Moment of the force on the plate about its centre [N m].
    moment: Vector3<f64>,
    /// Elastic energy [J].
    energy: f64,
    /// Damping power [W].
    power: f64,
}

/// Series / closed forms of `f(u) = sin √u/√u`, `f'`, `f''` and `g(u) = cos √u`.
fn tilt_functions(u: f64) -> (f64, f64, f64, f64) {
    if u < 1e-2 {
        // Taylor series: f = Σ (−u)^k/(2k+1)!, g = Σ (−u)^k/(2k)!
        let f = 1.0 - u / 6.0 + u * u / 120.0 - u.powi(3) / 5040.0 + u.powi(4) / 362880.0;
        let f1 =
            -1.0 / 6.0 + u / 60.0 - u * u / 1680.0 + u.powi(3) / 90720.0 - u.powi(4) / 7983360.0;
        let f2 = 1.0 / 60.0 - u / 840.0 + u * u / 30240.0 - u.powi(3) / 1995840.0;
        let g = 1.0 - u / 2.0 + u * u / 24.0 - u.powi(3) / 720.0 + u.powi(4) / 40320.0;
        (f, f1, f2, g)
    } else {
        let phi = u.sqrt();
        let (s, c) = phi.sin_cos();
        let f = s / phi;
        let f1 = (c - f) / (2.0 * u);
        let f2 = (-0.5 * f - 3.0 * f1) / (2.0 * u);
        (f, f1, f2, c)
    }
}

/// The plate normal `n = R(θ) e_z` for the tilt `θ = (a, b, 0)`, its derivatives
/// `∂n/∂a`, `∂n/∂b` and second derivatives `∂²n/∂a²`, `∂²n/∂a∂b`, `∂²n/∂b²`.
pub fn plate_normal(a: f64, b: f64) -> (Vector3<f64>, [Vector3<f64>; 2], [Vector3<f64>; 3]) {
    let u = a * a + b * b;
    let (f, f1, f2, g) = tilt_functions(u);
    let (g1, g2) = (-0.5 * f, -0.5 * f1);
    let n = Vector3::new(b * f, -a * f, g);
    let na = Vector3::new(2.0 * a * b * f1, -f - 2.0 * a * a * f1, 2.0 * a * g1);
    let nb = Vector3::new(f + 2.0 * b * b * f1, -2.0 * a * b * f1, 2.0 * b * g1);
    let naa = Vector3::new(
        2.0 * b * f1 + 4.0 * a * a * b * f2,
        -6.0 * a * f1 - 4.0 * a.powi(3) * f2,
        2.0 * g1 + 4.0 * a * a * g2,
    );
    let nab = Vector3::new(
        2.0 * a * f1 + 4.0 * a * b * b * f2,
        -2.0 * b * f1 - 4.0 * a * a * b * f2,
        4.0 * a * b * g2,
    );
    let nbb = Vector3::new(
        6.0 * b * f1 + 4.0 * b.powi(3) * f2,
        -2.0 * a * f1 - 4.0 * a * b * b * f2,
        2.0 * g1 + 4.0 * b * b * g2,
    );
    (n, [na, nb], [naa, nab, nbb])
}

impl ObstacleContact<3> for Plate3dContact {
    fn force(&self) -> SVector<f64, 3> {
        self.force
    }

    /// `−w p ∂δ/∂x_l`: the force on the plate for `l < 3`, the moment's component along the
    /// tilt axis `∂(R)/∂θ_l` for the tilts.
    fn generalized_force(&self, l: usize) -> f64 {
        -self.wp * self.grad[3 + l]
    }

    fn iteration_block(&self, ks: f64, kd: f64, out: &mut [f64]) {
        let s = ks * self.dp[0] + kd * self.dp[1];
        let damp = ks * self.dp[1];
        for j in 0..NX {
            for i in 0..NX {
                out[i + NX * j] = -s * self.grad[i] * self.grad[j]
                    - damp * self.grad[i] * self.h_rate[j]
                    - ks * self.wp * self.hess[(i, j)];
            }
        }
    }

    fn slipping(&self) -> bool {
        false
    }

    fn normal_energy(&self) -> f64 {
        self.energy
    }

    fn dissipation(&self) -> f64 {
        self.power
    }

    fn moment(&self) -> Vector3<f64> {
        self.moment
    }
}

impl Obstacle<3> for Plate3d {
    const N_COORDS: usize = PLATE_COORDS;
    type History = NoHistory;
    type Contact = Plate3dContact;

    /// The plate's pose is a coordinate, not known here: every point is checked.
    fn near(&self, _a: &SVector<f64, 3>, _b: &SVector<f64, 3>) -> bool {
        true
    }

    fn evaluate(
        &self,
        law: &ContactLaw,
        w: f64,
        p: &PointMotion<3>,
        x: &[f64],
        xd: &[f64],
        _hist: &NoHistory,
    ) -> Option<Plate3dContact> {
        let c = Vector3::new(x[0], x[1], x[2]);
        let (a, b) = (x[3], x[4]);
        let u = a * a + b * b;
        let (f, _, _, g) = tilt_functions(u);
        let n = Vector3::new(b * f, -a * f, g);
        let d = p.r - c;
        let delta = d.dot(&n);
        if delta <= 0.0 || (d - n * delta).norm() > self.radius {
            return None;
        }
        let (n, dn, ddn) = plate_normal(a, b);
        let mut grad = SVector::<f64, NX>::zeros();
        let mut hess = SMatrix::<f64, NX, NX>::zeros();
        for i in 0..3 {
            grad[i] = n[i];
            grad[3 + i] = -n[i];
        }
        for j in 0..2 {
            grad[6 + j] = d.dot(&dn[j]);
            for i in 0..3 {
                hess[(i, 6 + j)] = dn[j][i];
                hess[(6 + j, i)] = dn[j][i];
                hess[(3 + i, 6 + j)] = -dn[j][i];
                hess[(6 + j, 3 + i)] = -dn[j][i];
            }
        }
        hess[(6, 6)] = d.dot(&ddn[0]);
        hess[(6, 7)] = d.dot(&ddn[1]);
        hess[(7, 6)] = hess[(6, 7)];
        hess[(7, 7)] = d.dot(&ddn[2]);
        let xdot = SVector::<f64, NX>::from_fn(|i, _| if i < 3 { p.v[i] } else { xd[i - 3] });
        let rate = grad.dot(&xdot);
        let (pe, dpe, ramp, dramp, ue) = smoothed_penalty(law, delta);
        let pressure = pe + law.d_n * ramp * rate;
        if pressure <= 0.0 {
            return None;
        }
        let force = -w * pressure * n;
        Some(Plate3dContact {
            force,
            penetration: delta,
            grad,
            h_rate: hess * xdot,
            hess,
            wp: w * pressure,
            dp: [w * (dpe + law.d_n * dramp * rate), w * law.d_n * ramp],
            moment: d.cross(&(-force)),
            energy: w * ue,
            power: w * law.d_n * ramp * rate * rate,
        })
    }

    fn committed(&self, _p: &PointMotion<3>, _x: &[f64], _c: Option<&Plate3dContact>) -> NoHistory {
        NoHistory
    }

    fn friction_work(_w: f64, _h: &NoHistory, _c: &Plate3dContact) -> f64 {
        0.0
    }

    fn shift_history(_h: &mut NoHistory, _l: usize, _by: f64) {}
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::finite_difference::{assert_close, jacobian};
    use crate::elements::rotation::exp_so3;
    use nalgebra::DMatrix;

    use crate::contact::test_laws::frictionless as law;

    /// The closed-form normal is `exp(θ̃) e_z` (the shell kind's rotation of the plate), and
    /// its derivatives match central differences, at a large and at a tiny tilt (the series).
    #[test]
    fn normal_is_the_rotated_axis_with_its_derivatives() {
        for (a, b) in [(0.3, -0.2), (2e-3, 1e-3), (0.0, 0.0), (0.08, 0.05)] {
            let (n, dn, ddn) = plate_normal(a, b);
            let r = exp_so3(&Vector3::new(a, b, 0.0));
            assert!((n - r * Vector3::z()).norm() < 1e-15, "n at ({a}, {b})");
            let h = 1e-6;
            for (j, e) in [(0, [h, 0.0]), (1, [0.0, h])] {
                let fd = (plate_normal(a + e[0], b + e[1]).0 - plate_normal(a - e[0], b - e[1]).0)
                    / (2.0 * h);
                assert!((fd - dn[j]).norm() < 1e-9, "dn/d{j} at ({a}, {b})");
                let fd1 = (plate_normal(a + e[0], b + e[1]).1[0]
                    - plate_normal(a - e[0], b - e[1]).1[0])
                    / (2.0 * h);
                let fd2 = (plate_normal(a + e[0], b + e[1]).1[1]
                    - plate_normal(a - e[0], b - e[1]).1[1])
                    / (2.0 * h);
                // ∂/∂a of ∂n/∂a is naa, ∂/∂b of it nab; ∂/∂b of ∂n/∂b is nbb
                let (want1, want2) = if j == 0 {
                    (ddn[0], ddn[1])
                } else {
                    (ddn[1], ddn[2])
                };
                assert!((fd1 - want1).norm() < 1e-8, "d2n/d a d{j} at ({a}, {b})");
                assert!((fd2 - want2).norm() < 1e-8, "d2n/d b d{j} at ({a}, {b})");
            }
        }
    }

    /// The iteration block against the crate's central differences of the force vector
    /// (force on the point, generalized forces on the five plate coordinates) in the point's
    /// position, the plate's coordinates and their rates: on a tilted, shifted, moving plate,
    /// once in the smoothing ramp and once beyond it; the generalized forces are the force on
    /// the plate and its moment about the centre along the tilt axes.
    #[test]
    fn block_matches_finite_differences() {
        let plate = Plate3d { radius: 0.5 };
        let law = law();
        let w = 3e-4;
        let eval = |x: &[f64], v: &[f64]| -> [f64; NX] {
            let p = PointMotion {
                r: Vector3::new(x[0], x[1], x[2]),
                v: Vector3::new(v[0], v[1], v[2]),
            };
            let mut out = [0.0; NX];
            if let Some(c) = plate.evaluate(&law, w, &p, &x[3..], &v[3..], &NoHistory) {
                for i in 0..3 {
                    out[i] = c.force()[i];
                }
                for l in 0..PLATE_COORDS {
                    out[3 + l] = c.generalized_force(l);
                }
            }
            out
        };
        let (a, b) = (0.12, -0.07);
        let pose = [0.01, -0.02, 0.25, a, b];
        let n = plate_normal(a, b).0;
        let v = [0.3, -0.1, 0.2, 0.05, 0.1, -0.4, 0.7, -0.3];
        for depth in [4e-6, 3e-5] {
            // a point 0.08 m from the centre in the plane, `depth` above it
            let t = n.cross(&Vector3::x()).normalize();
            let r = Vector3::new(pose[0], pose[1], pose[2]) + 0.08 * t + depth * n;
            let x: Vec<f64> = r.iter().copied().chain(pose).collect();
            let c = plate
                .evaluate(
                    &law,
                    w,
                    &PointMotion {
                        r,
                        v: Vector3::new(v[0], v[1], v[2]),
                    },
                    &pose,
                    &v[3..],
                    &NoHistory,
                )
                .expect("in contact");
            // the force on the plate and its moment along the tilt axes
            let on_plate = -c.force;
            for l in 0..3 {
                assert!((c.generalized_force(l) - on_plate[l]).abs() < 1e-12 * on_plate.norm());
            }
            let ts = crate::elements::rotation::tangent_spatial(&Vector3::new(a, b, 0.0));
            for l in 0..2 {
                let axis = ts * Vector3::ith(l, 1.0);
                let want = c.moment.dot(&axis);
                assert!(
                    (c.generalized_force(3 + l) - want).abs() < 1e-10 * c.moment.norm(),
                    "moment {l}: {} vs {want}",
                    c.generalized_force(3 + l)
                );
            }
            let (mut ks, mut kd) = ([0.0; NX * NX], [0.0; NX * NX]);
            c.iteration_block(1.0, 0.0, &mut ks);
            c.iteration_block(0.0, 1.0, &mut kd);
            let fx = jacobian(&x, NX, |_| 1e-9, |y, out| out.copy_from_slice(&eval(y, &v)));
            let fv = jacobian(&v, NX, |_| 1e-6, |y, out| out.copy_from_slice(&eval(&x, y)));
            let tiny = f64::MIN_POSITIVE;
            assert_close(
                &format!("depth {depth}: d force / d position"),
                &DMatrix::from_column_slice(NX, NX, &ks),
                &fx,
                1e-5,
                tiny,
            );
            assert_close(
                &format!("depth {depth}: d force / d rate"),
                &DMatrix::from_column_slice(NX, NX, &kd),
                &fv,
                1e-6,
                tiny,
            );
        }
    }

    /// No contact below the plate, beyond its radius, or pulled away fast (negative pressure).
    #[test]
    fn no_contact_below_or_beyond_the_plate() {
        let plate = Plate3d { radius: 0.1 };
        let law = law();
        let pose = [0.0, 0.0, 0.2, 0.1, 0.0];
        let n = plate_normal(0.1, 0.0).0;
        let at = |r: Vector3<f64>, v: Vector3<f64>| {
            plate.evaluate(
                &law,
                1e-4,
                &PointMotion { r, v },
                &pose,
                &[0.0; 5],
                &NoHistory,
            )
        };
        let c = Vector3::new(0.0, 0.0, 0.2);
        let t = n.cross(&Vector3::x()).normalize();
        assert!(at(c + 0.05 * t + 1e-5 * n, Vector3::zeros()).is_some());
        assert!(at(c + 0.05 * t - 1e-5 * n, Vector3::zeros()).is_none());
        assert!(at(c + 0.11 * t + 1e-5 * n, Vector3::zeros()).is_none());
        assert!(at(c + 0.05 * t + 1e-5 * n, -n).is_none());
    }
}
