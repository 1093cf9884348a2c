//! Time integrators on a model's free coordinates. Each advances a [`DynState`] by one internal
//! step with Newton's method and leaves the input state untouched on failure.

mod generalized_alpha;
mod midpoint;
mod scheme;
mod state;

pub use generalized_alpha::GeneralizedAlpha;
pub use midpoint::Midpoint;
pub use scheme::Integrator;
pub use state::DynState;
