//! Element tests, one file per element: the conformance checks in one line per element and
//! state set, then each element's own quantities (closed-form mass and gravity, strains,
//! papers' figures).

mod ancf_cable2d;
mod ancf_shear2d;
mod axisym_bending;
mod axisym_membrane;
mod cord_rubber_quad;
mod corotational3d;
mod trapezoid_shell;
