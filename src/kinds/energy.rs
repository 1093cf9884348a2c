//! Energy outputs, shared by the kinds that report them (`[outputs] energy = true`).

use super::KindIo;
use crate::units::Unit;

/// Energy outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnergyKind {
    /// `energy.kinetic` = ½ vᵀ M v [J]
    Kinetic,
    /// `energy.potential` = −Q_gᵀ q, gravity potential relative to the origin [J]
    Potential,
    /// `energy.strain` = U [J]
    Strain,
    /// `energy.total` = kinetic + potential + strain [J]
    Total,
}

impl EnergyKind {
    /// The output's name after `energy.`.
    pub fn name(self) -> &'static str {
        match self {
            EnergyKind::Kinetic => "kinetic",
            EnergyKind::Potential => "potential",
            EnergyKind::Strain => "strain",
            EnergyKind::Total => "total",
        }
    }
}

/// Descriptions of the energies of a body of elements, in output order.
pub const BODY_ENERGIES: [(EnergyKind, &str); 4] = [
    (EnergyKind::Kinetic, "Kinetic energy 1/2 v^T M v"),
    (
        EnergyKind::Potential,
        "Gravity potential energy relative to y = 0 (-Q_g^T q)",
    ),
    (EnergyKind::Strain, "Strain energy U"),
    (EnergyKind::Total, "Kinetic + potential + strain energy"),
];

/// Declares the outputs `energy.<name>` [J] of `energies` (kind and description, in output
/// order), each with the kind's output role `role(kind)`.
pub fn declare_energy_outputs<I, O>(
    io: &mut KindIo<I, O>,
    role: impl Fn(EnergyKind) -> O,
    energies: &[(EnergyKind, &str)],
) {
    for (kind, what) in energies {
        io.output(
            format!("energy.{}", kind.name()),
            Unit::J,
            what.to_string(),
            role(*kind),
        );
    }
}
