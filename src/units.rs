//! Units of FMU variables, typed: every unit a variable can carry is a variant here, with its
//! FMI name and its exponents in the SI base units, so a missing unit is a compile error and
//! `UnitDefinitions` in `modelDescription.xml` cannot miss one (FMI 2.0 section 2.2.2).

/// A unit of a Real variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Unit {
    /// Dimensionless `1`.
    One,
    /// Degree, `π/180` rad (a plane angle given in degrees in a scene and its parameter).
    Deg,
    /// Radian `rad` (dimensionless in SI base units).
    Rad,
    /// Metre `m`.
    M,
    /// Square metre `m2`.
    M2,
    /// Cubic metre `m3`.
    M3,
    /// Second `s`.
    S,
    /// Kilogram `kg`.
    Kg,
    /// Kelvin `K`.
    K,
    /// `m/s`.
    MPerS,
    /// `m/s2`.
    MPerS2,
    /// `rad/s`.
    RadPerS,
    /// Newton `N`.
    N,
    /// Pascal `Pa`.
    Pa,
    /// Joule `J`.
    J,
    /// Watt `W`.
    W,
    /// `W/K` (heat transfer coefficient times area).
    WPerK,
    /// `J/(kg.K)` (specific heat, gas constant).
    JPerKgK,
    /// `kg/m3`.
    KgPerM3,
    /// `N.m`.
    NM,
    /// `N.m2`.
    NM2,
    /// `kg/m`.
    KgPerM,
    /// `kg.m`.
    KgM,
    /// `kg.m2`.
    KgM2,
    /// `N.m.s/rad`.
    NMSPerRad,
    /// `N.m/rad` (torsion spring stiffness).
    NMPerRad,
    /// `N/m` (stiffness).
    NPerM,
    /// `N/m2`.
    NPerM2,
    /// Pressure per length `N/m3` (a contact penalty per penetration).
    NPerM3,
    /// `N.s/m2`.
    NSPerM2,
    /// `N.s`.
    NS,
    /// `N.m2.s`.
    NM2S,
}

impl Unit {
    /// The unit's name in `modelDescription.xml`.
    pub const fn name(self) -> &'static str {
        match self {
            Unit::One => "1",
            Unit::Deg => "deg",
            Unit::Rad => "rad",
            Unit::M => "m",
            Unit::M2 => "m2",
            Unit::M3 => "m3",
            Unit::S => "s",
            Unit::Kg => "kg",
            Unit::K => "K",
            Unit::MPerS => "m/s",
            Unit::MPerS2 => "m/s2",
            Unit::RadPerS => "rad/s",
            Unit::N => "N",
            Unit::Pa => "Pa",
            Unit::J => "J",
            Unit::W => "W",
            Unit::WPerK => "W/K",
            Unit::JPerKgK => "J/(kg.K)",
            Unit::KgPerM3 => "kg/m3",
            Unit::NM => "N.m",
            Unit::NM2 => "N.m2",
            Unit::KgPerM => "kg/m",
            Unit::KgM => "kg.m",
            Unit::KgM2 => "kg.m2",
            Unit::NMSPerRad => "N.m.s/rad",
            Unit::NMPerRad => "N.m/rad",
            Unit::NPerM => "N/m",
            Unit::NPerM2 => "N/m2",
            Unit::NPerM3 => "N/m3",
            Unit::NSPerM2 => "N.s/m2",
            Unit::NS => "N.s",
            Unit::NM2S => "N.m2.s",
        }
    }

    /// Exponents in the SI base units `[kg, m, s, K]` (radians are dimensionless).
    pub const fn exponents(self) -> [i32; 4] {
        match self {
            Unit::One | Unit::Rad | Unit::Deg => [0, 0, 0, 0],
            Unit::M => [0, 1, 0, 0],
            Unit::M2 => [0, 2, 0, 0],
            Unit::M3 => [0, 3, 0, 0],
            Unit::S => [0, 0, 1, 0],
            Unit::Kg => [1, 0, 0, 0],
            Unit::K => [0, 0, 0, 1],
            Unit::MPerS => [0, 1, -1, 0],
            Unit::MPerS2 => [0, 1, -2, 0],
            Unit::RadPerS => [0, 0, -1, 0],
            Unit::N => [1, 1, -2, 0],
            Unit::Pa => [1, -1, -2, 0],
            Unit::J | Unit::NM | Unit::NMPerRad => [1, 2, -2, 0],
            Unit::W => [1, 2, -3, 0],
            Unit::WPerK => [1, 2, -3, -1],
            Unit::JPerKgK => [0, 2, -2, -1],
            Unit::KgPerM3 => [1, -3, 0, 0],
            Unit::NM2 => [1, 3, -2, 0],
            Unit::KgPerM => [1, -1, 0, 0],
            Unit::KgM => [1, 1, 0, 0],
            Unit::KgM2 => [1, 2, 0, 0],
            Unit::NMSPerRad => [1, 2, -1, 0],
            Unit::NPerM => [1, 0, -2, 0],
            Unit::NPerM2 => [1, -1, -2, 0],
            Unit::NPerM3 => [1, -2, -2, 0],
            Unit::NSPerM2 => [1, -1, -1, 0],
            Unit::NS => [1, 1, -1, 0],
            Unit::NM2S => [1, 3, -1, 0],
        }
    }

    /// Factor to the base units (`BaseUnit factor`): `π/180` for degrees, else 1.
    pub const fn factor(self) -> f64 {
        match self {
            Unit::Deg => std::f64::consts::PI / 180.0,
            _ => 1.0,
        }
    }

    /// Names of the base units in the order of [`Self::exponents`] (FMI `BaseUnit` attributes).
    pub const BASE: [&'static str; 4] = ["kg", "m", "s", "K"];
}

impl std::fmt::Display for Unit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::Unit;

    /// Products that must hold between the units (a wrong exponent shows here).
    #[test]
    fn exponents_are_consistent() {
        let sum = |x: [i32; 4], y: [i32; 4]| [x[0] + y[0], x[1] + y[1], x[2] + y[2], x[3] + y[3]];
        let add = |a: Unit, b: Unit| sum(a.exponents(), b.exponents());
        assert_eq!(add(Unit::N, Unit::M), Unit::J.exponents());
        assert_eq!(add(Unit::Pa, Unit::M2), Unit::N.exponents());
        assert_eq!(add(Unit::W, Unit::S), Unit::J.exponents());
        assert_eq!(add(Unit::WPerK, Unit::K), Unit::W.exponents());
        assert_eq!(
            sum(add(Unit::JPerKgK, Unit::Kg), Unit::K.exponents()),
            Unit::J.exponents()
        );
        assert_eq!(add(Unit::NPerM, Unit::M), Unit::N.exponents());
        assert_eq!(add(Unit::KgPerM3, Unit::M3), Unit::Kg.exponents());
    }
}
