//! Dynamic state of the free coordinates.

/// Coordinates, velocities and accelerations at time `t`.
#[derive(Clone, Debug, PartialEq)]
pub struct DynState {
    /// Time [s].
    pub t: f64,
    /// Free coordinates.
    pub q: Vec<f64>,
    /// Their velocities.
    pub v: Vec<f64>,
    /// Their accelerations (solution of the equations of motion).
    pub acc: Vec<f64>,
    /// Algorithmic acceleration of generalized-alpha (equals `acc` for other schemes).
    pub a: Vec<f64>,
}

impl DynState {
    /// Zero state of size `n` at time `t`.
    pub fn zeros(n: usize, t: f64) -> Self {
        Self {
            t,
            q: vec![0.0; n],
            v: vec![0.0; n],
            acc: vec![0.0; n],
            a: vec![0.0; n],
        }
    }

    /// Copies another state of the same size without allocating.
    pub fn assign(&mut self, o: &DynState) {
        self.t = o.t;
        self.q.copy_from_slice(&o.q);
        self.v.copy_from_slice(&o.v);
        self.acc.copy_from_slice(&o.acc);
        self.a.copy_from_slice(&o.a);
    }
}
