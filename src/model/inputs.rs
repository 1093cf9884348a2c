//! Input signals inside a communication step: the value set at the reference time and, with
//! `canInterpolateInputs`, its first and second time derivatives, extrapolated as a polynomial
//! (FMI 2.0 section 4.2.2: "inputs and their derivatives are set with respect to the beginning
//! of a communication time step").

use crate::snapshot::{SnapshotError, StateReader, StateWriter};

/// One Real input as a function of time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InputSignal {
    /// Value at `t_ref`.
    pub value: f64,
    /// First and second time derivatives at `t_ref` (zero unless set).
    pub derivatives: [f64; 2],
    /// Reference time [s].
    pub t_ref: f64,
    /// Whether derivatives were set since the last value (the signal is then a polynomial).
    pub interpolated: bool,
}

impl InputSignal {
    /// A constant signal.
    pub fn constant(value: f64) -> Self {
        Self {
            value,
            ..Self::default()
        }
    }

    /// Sets the value at time `t` and clears the derivatives.
    pub fn set(&mut self, value: f64, t: f64) {
        self.value = value;
        self.derivatives = [0.0; 2];
        self.t_ref = t;
        self.interpolated = false;
    }

    /// Sets derivative `order` (1 or 2) at the current reference time.
    pub fn set_derivative(&mut self, order: usize, value: f64) {
        self.derivatives[order - 1] = value;
        self.interpolated = true;
    }

    /// Value at time `t`.
    pub fn at(&self, t: f64) -> f64 {
        let tau = t - self.t_ref;
        self.value + tau * (self.derivatives[0] + 0.5 * tau * self.derivatives[1])
    }

    /// First derivative at time `t`.
    pub fn rate_at(&self, t: f64) -> f64 {
        self.derivatives[0] + (t - self.t_ref) * self.derivatives[1]
    }

    /// Second derivative (constant).
    pub fn accel(&self) -> f64 {
        self.derivatives[1]
    }

    /// Appends the signal to a snapshot.
    pub fn save(&self, w: &mut StateWriter) {
        w.f64(self.value);
        w.f64(self.derivatives[0]);
        w.f64(self.derivatives[1]);
        w.f64(self.t_ref);
        w.bool(self.interpolated);
    }

    /// Reads a signal from a snapshot.
    pub fn restore(r: &mut StateReader) -> Result<Self, SnapshotError> {
        Ok(Self {
            value: r.f64()?,
            derivatives: [r.f64()?, r.f64()?],
            t_ref: r.f64()?,
            interpolated: r.bool()?,
        })
    }
}

/// Prescribed position, velocity and acceleration of a coordinate driven by a position and a
/// velocity input (a motion port, a driven pulley) at `t`:
/// the position input's own polynomial if derivatives were given, otherwise the position
/// advanced with the velocity input (integrated exactly).
pub fn prescribed(pos: &InputSignal, vel: &InputSignal, t: f64) -> (f64, f64, f64) {
    if pos.interpolated {
        (pos.at(t), pos.rate_at(t), pos.accel())
    } else {
        let tau = t - pos.t_ref;
        let [d1, d2] = vel.derivatives;
        (
            pos.value + tau * (vel.value + tau * (0.5 * d1 + tau * d2 / 6.0)),
            vel.value + tau * (d1 + 0.5 * tau * d2),
            d1 + tau * d2,
        )
    }
}
