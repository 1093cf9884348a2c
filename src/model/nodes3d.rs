//! Nodes with six coordinates `[x, y, z, θx, θy, θz]` (position and the incremental rotation
//! vector of a node frame, [`NodeFrames`]), shared by the 3D beam and the shell: loads spread
//! over nodes (forces and moments, fixed-direction or follower) and probe quantities with
//! their time derivatives.

use crate::assembly::Assembly;
use crate::elements::element::Frame;
use crate::elements::node_frames::NodeFrames;
use crate::elements::rotation::{skew, tangent_spatial_inv};
use crate::model::JacobianCoeffs;
use crate::model::inputs::InputSignal;
use crate::scene::tables::ProbeQuantity;
use crate::snapshot::{SnapshotError, StateReader, StateWriter};
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// Coordinates of a node.
const NODE_DOFS: usize = 6;

/// A force and moment `[fx, fy, fz, mx, my, mz]` [N, N m] (input signals) applied at one node,
/// or spread over several nodes with weights summing to one (a line load: the total force
/// and moment shared by the trapezoid rule).
#[derive(Clone, Debug)]
pub struct NodeLoad {
    /// `(node, weight)` pairs.
    pub nodes: Vec<(usize, f64)>,
    /// `[fx, fy, fz, mx, my, mz]` as signals of time (extrapolated inside a communication step
    /// with the derivatives of `fmi2SetRealInputDerivatives`).
    pub values: [InputSignal; 6],
    /// `false` = fixed-direction (dead) load, global components; `true` = follower load,
    /// components in the global frame of the reference configuration rotating with the node.
    pub follower: bool,
}

impl NodeLoad {
    /// A load at one node with the start values `start`.
    pub fn at_node(node: usize, start: [f64; 6], follower: bool) -> Self {
        Self::spread(vec![(node, 1.0)], start, follower)
    }

    /// A load spread over weighted nodes.
    pub fn spread(nodes: Vec<(usize, f64)>, start: [f64; 6], follower: bool) -> Self {
        Self {
            nodes,
            values: start.map(InputSignal::constant),
            follower,
        }
    }

    /// Adds `−λ f_ext(t)` into the full residual `fw` (force rows in global components,
    /// moment rows in body components) and, with `jac`, its derivative with respect to the
    /// body spins, chained with `T(θ)`, times `c_K k_scale` into the free–free values.
    /// `frames` are the current node frames ([`NodeFrames::current`]).
    #[allow(clippy::too_many_arguments)]
    pub fn add_residual(
        &self,
        t: f64,
        lambda: f64,
        frames: &[Frame],
        fw: &mut [f64],
        asm: &Assembly,
        jac: Option<(&JacobianCoeffs, f64, &mut [f64])>,
    ) {
        let at = |i: usize| self.values[i].at(t) * lambda;
        let force = Vector3::new(at(0), at(1), at(2));
        let moment = Vector3::new(at(3), at(4), at(5));
        let mut jac = jac;
        for &(node, w) in &self.nodes {
            let b = node * NODE_DOFS;
            let frame = &frames[node];
            let rot = &frame.rot;
            let (f, m) = (force * w, moment * w);
            // Residual −f_ext; `blk` = ∂(−f_ext)/∂W (body spin) for the rows x or θ.
            let (fx, mb, blk, rows): (Vector3<f64>, Vector3<f64>, Matrix3<f64>, usize) =
                if self.follower {
                    (rot * f, m, rot * skew(&f), 0)
                } else {
                    let mb = rot.transpose() * m;
                    (f, mb, -skew(&mb), 3)
                };
            for c in 0..3 {
                fw[b + c] -= fx[c];
                fw[b + 3 + c] -= mb[c];
            }
            if let Some((c, k_scale, vals)) = jac.as_mut()
                && (f != Vector3::zeros() && self.follower
                    || m != Vector3::zeros() && !self.follower)
            {
                let d = blk * frame.tangent * (c.stiffness * *k_scale);
                for i in 0..3 {
                    for j in 0..3 {
                        asm.add_entry(b + rows + i, b + 3 + j, d[(i, j)], vals);
                    }
                }
            }
        }
    }

    /// Saves the signals.
    pub fn save(&self, w: &mut StateWriter) {
        for s in &self.values {
            s.save(w);
        }
    }

    /// Restores what [`NodeLoad::save`] wrote.
    pub fn restore(&mut self, r: &mut StateReader) -> Result<(), SnapshotError> {
        for s in &mut self.values {
            *s = InputSignal::restore(r)?;
        }
        Ok(())
    }
}

/// The committed motion of nodes: full coordinates, velocities (body angular velocities in
/// the rotation rows), accelerations and the node frames.
#[derive(Clone, Copy, Debug)]
pub struct NodeMotion<'a> {
    /// Full coordinates.
    pub q: &'a [f64],
    /// Full velocities.
    pub v: &'a [f64],
    /// Full accelerations.
    pub acc: &'a [f64],
    /// Node frames (node `k`'s coordinates start at `6 k`).
    pub frames: &'a NodeFrames,
}

fn component(v: &Vector3<f64>, quantity: ProbeQuantity, axes: [ProbeQuantity; 3]) -> f64 {
    v[axes.iter().position(|x| *x == quantity).unwrap_or(0)]
}

impl NodeMotion<'_> {
    /// Probe quantity `quantity` of node `node`: position, velocity, rotation vector from the
    /// reference orientation (principal value), angular velocity in global components, and the
    /// direction cosines of the rotated reference direction `axis` (the beam axis; zero if
    /// `None`).
    pub fn probe(&self, node: usize, quantity: ProbeQuantity, axis: Option<&Vector3<f64>>) -> f64 {
        let b = node * NODE_DOFS;
        let r = || self.frames.rotation(node, self.q);
        use ProbeQuantity::*;
        match quantity {
            X => self.q[b],
            Y => self.q[b + 1],
            Z => self.q[b + 2],
            Vx => self.v[b],
            Vy => self.v[b + 1],
            Vz => self.v[b + 2],
            Rx | Ry | Rz => component(
                &UnitQuaternion::from_matrix(&r()).scaled_axis(),
                quantity,
                [Rx, Ry, Rz],
            ),
            Tx | Ty | Tz => axis.map_or(0.0, |a| component(&(r() * a), quantity, [Tx, Ty, Tz])),
            Wx | Wy | Wz => component(
                &(r() * self.frames.angular_velocity(node, self.v)),
                quantity,
                [Wx, Wy, Wz],
            ),
        }
    }

    /// Time derivative of [`NodeMotion::probe`]: positions, velocities, angular velocities and
    /// direction cosines analytically (`ẋ`, `ẍ`, `R Ẇ`, `ω × t`); the rotation vector φ by
    /// `φ̇ = T_s(φ)⁻¹ ω` (not defined within 1e-6 rad of |φ| = π, where the principal value
    /// jumps: `None`).
    pub fn probe_rate(
        &self,
        node: usize,
        quantity: ProbeQuantity,
        axis: Option<&Vector3<f64>>,
    ) -> Option<f64> {
        let b = node * NODE_DOFS;
        let r = self.frames.rotation(node, self.q);
        let omega = r * self.frames.angular_velocity(node, self.v);
        let v3 = |x: &[f64], i: usize| Vector3::new(x[i], x[i + 1], x[i + 2]);
        use ProbeQuantity::*;
        let (vec, axes) = match quantity {
            X | Y | Z => (v3(self.v, b), [X, Y, Z]),
            Vx | Vy | Vz => (v3(self.acc, b), [Vx, Vy, Vz]),
            Wx | Wy | Wz => (r * v3(self.acc, b + 3), [Wx, Wy, Wz]),
            Tx | Ty | Tz => (
                axis.map_or(Vector3::zeros(), |a| omega.cross(&(r * a))),
                [Tx, Ty, Tz],
            ),
            Rx | Ry | Rz => {
                let phi = UnitQuaternion::from_matrix(&r).scaled_axis();
                if phi.norm() > std::f64::consts::PI - 1e-6 {
                    return None;
                }
                (tangent_spatial_inv(&phi) * omega, [Rx, Ry, Rz])
            }
        };
        Some(component(&vec, quantity, axes))
    }
}
