//! Contact between flexible bodies and rigid parts: penalty contact with Coulomb friction for
//! implicit integration. [`obstacle`]: what a point can touch (today the pulley circle);
//! [`point_set`]: the points of a body, their history, the evaluation loop and the scatter
//! into the assembly; [`circle_friction`]: the belt–pulley kernel.

pub mod circle_friction;
pub mod obstacle;
pub mod point_set;
pub mod revolution;

pub use circle_friction::{Circle, ContactLaw, PointContact, PointHistory, PointState};
pub use obstacle::{ContactHistory, Obstacle, ObstacleContact, PointMotion};
pub use point_set::{ContactBook, ContactPointSet, ObstacleLoad};
