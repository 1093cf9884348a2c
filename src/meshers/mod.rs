//! Meshers shared by the body kinds: stations along a line ([`stations`]: where a fraction of
//! the length falls on the mesh), centre lines of straight and circular pieces
//! ([`centreline`]), the belt loop around pulleys ([`belt_loop`]), flat rectangular and
//! trapezoidal plates ([`plate`]), surfaces of revolution from a meridian ([`revolution`]) and
//! quantities of surface meshes such as the enclosed volume ([`surface`]).

pub mod bellows;
pub mod belt_loop;
pub mod centreline;
pub mod plate;
pub mod revolution;
pub mod stations;
pub mod surface;
