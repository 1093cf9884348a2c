//! Time integrators on a model's free coordinates. Each advances a [`DynState`] by one internal
//! step (implicit schemes with Newton's method) and leaves the input state untouched on failure.

mod central_difference;
mod generalized_alpha;
mod midpoint;
mod quasi_static;
mod scheme;
mod state;

pub use central_difference::CentralDifference;
pub use generalized_alpha::GeneralizedAlpha;
pub use midpoint::Midpoint;
pub use quasi_static::{QuasiStatic, StepTrend, lagrange3};
pub use scheme::Integrator;
pub use state::DynState;
