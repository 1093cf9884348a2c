//! Contact laws shared by the contact modules' unit tests (test builds only).

use super::circle_friction::ContactLaw;

/// A belt on a pulley: penalty 2e7 N/m², Coulomb friction μ = 0.3 with a bristle of 1e7 N/m²,
/// 5 µm smoothing.
pub(crate) fn belt() -> ContactLaw {
    ContactLaw {
        k_n: 2e7,
        d_n: 3e3,
        k_t: 1e7,
        d_t: 1e3,
        mu: 0.3,
        smoothing: 5e-6,
        blend: 0.05,
    }
}

/// A membrane on a piston or plate: penalty 1e9 N/m³, frictionless, 10 µm smoothing.
pub(crate) fn frictionless() -> ContactLaw {
    ContactLaw {
        k_n: 1e9,
        d_n: 1e4,
        k_t: 0.0,
        d_t: 0.0,
        mu: 0.0,
        smoothing: 1e-5,
        blend: 0.0,
    }
}
