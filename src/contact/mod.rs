//! Contact between flexible bodies and rigid parts: penalty contact with Coulomb friction for
//! implicit integration. [`obstacle`]: what a point can touch (the pulley circle, the 3D pulley of [`pulley3d`], surfaces of revolution, the
//! tilting plate of [`plate3d`]);
//! [`point_set`]: the points of a body, their history, the evaluation loop and the scatter
//! into the assembly; [`circle_friction`]: the belt–pulley kernel; [`ale_transport`]: the
//! friction history of contact points fixed in the mesh of an axially moving belt.

pub mod ale_transport;
pub mod arm_pulley;
pub mod circle_friction;
pub mod obstacle;
pub mod plate3d;
pub mod point_set;
pub mod pulley3d;
pub mod revolution;
pub mod section3d;
#[cfg(test)]
mod test_laws;

pub use arm_pulley::{ArmContact, ArmPulley};
pub use circle_friction::{Circle, ContactLaw, PointContact, PointHistory, PointState};
pub use obstacle::{ContactHistory, Obstacle, ObstacleContact, PointMotion};
pub use plate3d::{Plate3d, Plate3dContact};
pub use point_set::{ContactBook, ContactPointSet, ObstacleLoad};
pub use pulley3d::{Pulley3d, Pulley3dContact, Pulley3dHistory};
pub use section3d::SectionContactSet;
