//! What a body kind declares for the FMI-LS-REF files of its FMUs: parameter presets and the
//! smoke-test experiment. A kind gives them through [`crate::kinds::KindScene::presets`] and
//! [`crate::kinds::KindScene::smoke_test`]; nothing outside the kind's module knows them.

use crate::variables::Value;

/// One parameter of a preset: a value, or a factor on the scene's default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PresetValue {
    /// This value.
    Set(Value),
    /// The scene's default value (a Real parameter) times this factor.
    Scale(f64),
}

/// A named parameter set: the scene's defaults with some parameters changed. Written as a
/// complete SSP parameter set `<name>.ssv` (every parameter of the FMU), so that applying it
/// alone defines the FMU.
#[derive(Clone, Debug, PartialEq)]
pub struct Preset {
    /// File stem and SSV `name` (letters, digits, `_`).
    pub name: &'static str,
    /// What the preset is, for the manifest and the SSV `description`.
    pub description: String,
    /// Parameters that differ from the defaults, by variable name.
    pub changes: Vec<(&'static str, PresetValue)>,
}

/// Time shape of a stimulus over the smoke test of duration `T`, with `ω = 2π / T` (one
/// period over the run) and `a` the stimulus amplitude; both start at the input's start value
/// `u0`, so the run starts from the initialized state without a jump.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// `u0 + a (1 − cos ω t)`: a smooth excursion to `u0 + 2a` and back.
    Excursion,
    /// `u0 + a ω sin ω t`: the rate of [`Shape::Excursion`] of the same `a` (velocity inputs
    /// that go with a position input).
    Rate,
}

/// One input signal of the smoke test.
#[derive(Clone, Debug, PartialEq)]
pub struct Stimulus {
    /// Input variable name.
    pub input: String,
    /// Amplitude `a` in the input's unit (for [`Shape::Rate`]: of the position whose rate it is).
    pub amplitude: f64,
    /// Time shape.
    pub shape: Shape,
}

impl Stimulus {
    /// The stimulus value at `t` after the start of a run of duration `duration` [s], given
    /// the input's start value `start`.
    pub fn value(&self, start: f64, t: f64, duration: f64) -> f64 {
        let w = 2.0 * std::f64::consts::PI / duration;
        match self.shape {
            Shape::Excursion => start + self.amplitude * (1.0 - (w * t).cos()),
            Shape::Rate => start + self.amplitude * w * (w * t).sin(),
        }
    }
}

/// The smoke-test experiment: communication steps of the scene's `[experiment] step_size`
/// from its `start_time`, the default parameters, inputs at their start values except the
/// stimuli.
#[derive(Clone, Debug, PartialEq)]
pub struct SmokeTest {
    /// Number of communication steps.
    pub steps: usize,
    /// Input signals; inputs not listed keep their start values.
    pub stimuli: Vec<Stimulus>,
}

/// Communication steps of a smoke test unless the kind says otherwise: short, to keep the
/// build of every FMU fast, and long enough for one period of a stimulus.
pub const SMOKE_STEPS: usize = 40;

impl Default for SmokeTest {
    fn default() -> Self {
        Self {
            steps: SMOKE_STEPS,
            stimuli: Vec::new(),
        }
    }
}

impl SmokeTest {
    /// A smoke test of [`SMOKE_STEPS`] steps with `stimuli`.
    pub fn with(stimuli: Vec<Stimulus>) -> Self {
        Self {
            steps: SMOKE_STEPS,
            stimuli,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both shapes start at the start value, and the rate shape is the time derivative of
    /// the excursion (central differences).
    #[test]
    fn rate_is_the_derivative_of_the_excursion() {
        let x = |shape| Stimulus {
            input: "u".into(),
            amplitude: 0.3,
            shape,
        };
        let (ex, rate) = (x(Shape::Excursion), x(Shape::Rate));
        let duration = 0.04;
        assert_eq!(ex.value(1.5, 0.0, duration), 1.5);
        assert_eq!(rate.value(-2.0, 0.0, duration), -2.0);
        assert!((ex.value(0.0, 0.5 * duration, duration) - 0.6).abs() < 1e-15);
        let d = 1e-7;
        for k in 1..10 {
            let t = k as f64 * duration / 10.0;
            let fd = (ex.value(0.0, t + d, duration) - ex.value(0.0, t - d, duration)) / (2.0 * d);
            let r = rate.value(0.0, t, duration);
            assert!((fd - r).abs() < 1e-6 * r.abs().max(1.0), "{t}: {fd} {r}");
        }
    }
}
