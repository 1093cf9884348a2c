//! Contact between flexible bodies and rigid parts: belt–pulley penalty contact with Coulomb
//! friction for implicit integration.

pub mod circle_friction;

pub use circle_friction::{Circle, ContactLaw, PointContact, PointHistory, PointState};
