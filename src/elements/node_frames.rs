//! Node frames: a stored unit quaternion `R_ref` per node and an incremental rotation vector
//! `θ` among the coordinates, `R = R_ref exp(θ̃)` (seed-003 3D beam; the seed-004 shell's
//! node-fixed frames).
//!
//! The model absorbs `θ` into `R_ref` and resets it to zero after every accepted time step and
//! every converged static load increment ([`NodeFrames::absorb`]). With the integrators'
//! additive update from `θ_n = 0` every step is then the Lie-group Newmark / generalized-α
//! update `R_{n+1} = R_n exp(θ̃)` of Brüls, Cardona & Arnold 2012
//! (`shared/reference/time-integration.md` F.1); velocities are body angular velocities `Ω`
//! (`Ṙ = R Ω̃`) and need no re-expression. Orientations are never described by a total
//! rotation vector, so nodes may turn through any number of revolutions; `θ` only has to stay
//! below 2π within one step (the singularity of `T(θ)`).

use super::element::Frame;
use super::rotation::{exp_so3, tangent_body};
use crate::snapshot::{StateReader, StateWriter};
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

/// Stored orientations of the nodes and their current frames.
#[derive(Debug)]
pub struct NodeFrames {
    r_ref: Vec<UnitQuaternion<f64>>,
    /// Full index of `θ_x` of every node (`θ_y`, `θ_z` follow).
    theta_at: Vec<usize>,
    /// Frames of the coordinates of the last [`NodeFrames::update`].
    work: Vec<Frame>,
}

impl Clone for NodeFrames {
    fn clone(&self) -> Self {
        Self {
            r_ref: self.r_ref.clone(),
            theta_at: self.theta_at.clone(),
            work: self.work.clone(),
        }
    }

    /// Field by field, so that a copy kept as scratch reuses its buffers.
    fn clone_from(&mut self, source: &Self) {
        self.r_ref.clone_from(&source.r_ref);
        self.theta_at.clone_from(&source.theta_at);
        self.work.clone_from(&source.work);
    }
}

impl NodeFrames {
    /// Frames at the reference orientation (`R_ref = I`) for nodes whose rotation vectors
    /// start at the given full coordinate indices.
    pub fn new(theta_at: Vec<usize>) -> Self {
        let n = theta_at.len();
        Self {
            r_ref: vec![UnitQuaternion::identity(); n],
            theta_at,
            work: vec![Frame::default(); n],
        }
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.r_ref.len()
    }

    /// Whether there are no nodes.
    pub fn is_empty(&self) -> bool {
        self.r_ref.is_empty()
    }

    /// Full index of `θ_x` of node `k`.
    pub fn theta_index(&self, k: usize) -> usize {
        self.theta_at[k]
    }

    /// The node whose rotation vector starts at full index `i`.
    pub fn node_of_coordinate(&self, i: usize) -> Option<usize> {
        self.theta_at.iter().position(|&t| t == i)
    }

    /// Incremental rotation vector of node `k` in a full coordinate vector [rad].
    #[inline]
    pub fn theta(&self, k: usize, full: &[f64]) -> Vector3<f64> {
        let i = self.theta_at[k];
        Vector3::new(full[i], full[i + 1], full[i + 2])
    }

    /// Stored orientation `R_ref` of node `k`.
    pub fn reference(&self, k: usize) -> &UnitQuaternion<f64> {
        &self.r_ref[k]
    }

    /// Sets the stored orientation of node `k`.
    pub fn set_reference(&mut self, k: usize, r: UnitQuaternion<f64>) {
        self.r_ref[k] = r;
    }

    /// Orientation `R = R_ref exp(θ̃)` of node `k` for a full coordinate vector.
    #[inline]
    pub fn rotation(&self, k: usize, full: &[f64]) -> Matrix3<f64> {
        self.r_ref[k].to_rotation_matrix().into_inner() * exp_so3(&self.theta(k, full))
    }

    /// Frame (orientation and tangent `T(θ)`) of node `k` for a full coordinate vector.
    #[inline]
    pub fn frame(&self, k: usize, full: &[f64]) -> Frame {
        let th = self.theta(k, full);
        Frame {
            rot: self.r_ref[k].to_rotation_matrix().into_inner() * exp_so3(&th),
            tangent: tangent_body(&th),
        }
    }

    /// Computes the frames of every node for a full coordinate vector (kept until the next
    /// update, see [`NodeFrames::current`]).
    pub fn update(&mut self, full: &[f64]) {
        for k in 0..self.r_ref.len() {
            self.work[k] = self.frame(k, full);
        }
    }

    /// Frames of the last [`NodeFrames::update`].
    #[inline]
    pub fn current(&self) -> &[Frame] {
        &self.work
    }

    /// Body angular velocity `Ω` of node `k` [rad/s] (the velocity entries of its rotation
    /// vector); the spatial one is `R Ω`.
    pub fn angular_velocity(&self, k: usize, v_full: &[f64]) -> Vector3<f64> {
        self.theta(k, v_full)
    }

    /// Absorbs the incremental rotations of a full coordinate vector into the stored
    /// orientations and sets them to zero (rebase after a load increment, commit after a
    /// step).
    pub fn absorb(&mut self, full: &mut [f64]) {
        for k in 0..self.r_ref.len() {
            let th = self.theta(k, full);
            if th != Vector3::zeros() {
                let mut nq = self.r_ref[k] * UnitQuaternion::from_scaled_axis(th);
                nq.renormalize();
                self.r_ref[k] = nq;
                let i = self.theta_at[k];
                full[i..i + 3].fill(0.0);
            }
        }
    }

    /// Writes the stored orientations (quaternion components `[i, j, k, w]` per node).
    pub fn save(&self, w: &mut StateWriter) {
        let quats: Vec<f64> = self
            .r_ref
            .iter()
            .flat_map(|r| {
                let c = r.as_ref().coords;
                [c[0], c[1], c[2], c[3]]
            })
            .collect();
        w.f64s(&quats);
    }

    /// Restores what [`NodeFrames::save`] wrote; rejects anything but unit quaternions.
    pub fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let quats = r
            .f64s(Some(4 * self.r_ref.len()))
            .map_err(|e| e.to_string())?;
        for (k, c) in quats.chunks(4).enumerate() {
            let q = Quaternion::new(c[3], c[0], c[1], c[2]);
            if !(q.norm() - 1.0).abs().is_finite() || (q.norm() - 1.0).abs() > 1e-9 {
                return Err("a stored orientation is not a unit quaternion".into());
            }
            self.r_ref[k] = UnitQuaternion::new_unchecked(q);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::rotation::log_so3;

    /// Absorbing θ keeps the orientation and zeroes the coordinates; a sequence of increments
    /// composes to the product of their exponentials (turns beyond 2π included).
    #[test]
    fn absorb_composes_rotations() {
        let mut nf = NodeFrames::new(vec![3, 9]);
        let mut q = vec![0.0; 12];
        let steps = [
            Vector3::new(0.3, -1.2, 2.0),
            Vector3::new(2.5, 1.0, -0.4),
            Vector3::new(-0.7, 3.0, 0.1),
        ];
        let mut expect = Matrix3::identity();
        for th in steps {
            q[3..6].copy_from_slice(th.as_slice());
            let before = nf.rotation(0, &q);
            nf.absorb(&mut q);
            assert_eq!(&q[3..6], &[0.0; 3]);
            let after = nf.rotation(0, &q);
            assert!((before - after).norm() < 1e-14, "absorb changed R");
            expect *= exp_so3(&th);
        }
        assert!((nf.rotation(0, &q) - expect).norm() < 1e-13);
        // node 1 never moved
        assert_eq!(nf.rotation(1, &q), Matrix3::identity());
    }

    /// Frames from `update` agree with `frame`, and the tangent maps δθ to the body spin:
    /// `R(θ + δθ) ≈ R(θ) exp(T(θ) δθ)`.
    #[test]
    fn frame_tangent_is_body_spin() {
        let mut nf = NodeFrames::new(vec![0]);
        nf.set_reference(
            0,
            UnitQuaternion::from_scaled_axis(Vector3::new(0.4, 0.1, -2.0)),
        );
        let th = Vector3::new(0.5, -0.8, 1.1);
        let q = th.as_slice().to_vec();
        nf.update(&q);
        let fr = nf.current()[0];
        assert_eq!(fr, nf.frame(0, &q));
        let h = 1e-6;
        for c in 0..3 {
            let mut qp = q.clone();
            qp[c] += h;
            let spin = log_so3(&(fr.rot.transpose() * nf.rotation(0, &qp))) / h;
            let err = (spin - fr.tangent.column(c)).norm();
            assert!(err < 1e-5, "component {c}: {err}");
        }
    }

    /// Save and restore round-trip; a non-unit quaternion is rejected.
    #[test]
    fn save_restore_round_trip() {
        let mut nf = NodeFrames::new(vec![3, 9]);
        nf.set_reference(
            1,
            UnitQuaternion::from_scaled_axis(Vector3::new(1.0, 2.0, 0.5)),
        );
        let mut w = StateWriter::new();
        nf.save(&mut w);
        let bytes = w.into_bytes();
        let mut other = NodeFrames::new(vec![3, 9]);
        other
            .restore(&mut StateReader::new(&bytes))
            .expect("restores");
        assert_eq!(other.reference(1), nf.reference(1));
        let mut w = StateWriter::new();
        w.f64s(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0]);
        let bytes = w.into_bytes();
        assert!(other.restore(&mut StateReader::new(&bytes)).is_err());
    }
}
