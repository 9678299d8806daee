//! Units of the per-hull variables, from each DOF's length exponent e.
//!
//! e = 0: the generalized coordinate is a length (m); e = 1: an angle (rad) or a
//! dimensionless mode amplitude, and the generalized force carries one more metre.
//!
//! | quantity | e = 0 | e = 1, angle | e = 1, mode |
//! | --- | --- | --- | --- |
//! | velocity | m/s | rad/s | 1/s |
//! | acceleration | m/s2 | rad/s2 | 1/s2 |
//! | force (per unit length) | N/m | N | N |
//!
//! `added_mass_inf[i,j]` is in kg/m, kg, kg.m and `damping_direct[i,j]` in N.s/m2, N.s/m,
//! N.s for e_i + e_j = 0, 1, 2. Every unit is declared in `modelDescription/fixed.xml`
//! ([`crate::fmu::description::UNITS`]).
//!
//! A whole body (a ship, [`Extent::WholeBody`]) has forces, masses, damping, stiffness,
//! power and energy with one more metre than a section's per unit length: N and N.m, kg,
//! kg.m and kg.m2, W, J.

/// Whether the FMU's forces are per unit length (a 2D section) or of a whole body (a ship).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Extent {
    /// Per unit length of hull: force N/m (N for an angle or mode), power W/m.
    #[default]
    PerUnitLength,
    /// Of the whole body: force N (N.m), power W.
    WholeBody,
}

impl Extent {
    /// The extra power of the metre this extent adds to a per-length quantity.
    fn shift(self) -> usize {
        match self {
            Extent::PerUnitLength => 0,
            Extent::WholeBody => 1,
        }
    }

    /// Unit of a generalized force of a DOF with length exponent `e`.
    pub fn force_unit(self, e: u8) -> &'static str {
        ["N/m", "N", "N.m"][usize::from(e.min(1)) + self.shift()]
    }

    /// Unit of `added_mass_inf[i,j]` for `e_i + e_j`.
    pub fn added_mass_unit(self, sum: u8) -> &'static str {
        ["kg/m", "kg", "kg.m", "kg.m2"][usize::from(sum.min(2)) + self.shift()]
    }

    /// Unit of `damping_direct[i,j]` for `e_i + e_j`.
    pub fn damping_unit(self, sum: u8) -> &'static str {
        ["N.s/m2", "N.s/m", "N.s", "N.s.m"][usize::from(sum.min(2)) + self.shift()]
    }

    /// Unit of `damping_quadratic[i]` (force per velocity squared) for a DOF of exponent `e`.
    pub fn quadratic_damping_unit(self, e: u8) -> &'static str {
        ["kg/m2", "kg/m", "kg.m", "kg.m2"][2 * usize::from(e.min(1)) + self.shift()]
    }

    /// Unit of `stiffness_hydrostatic[i,j]` for `e_i + e_j`.
    pub fn stiffness_unit(self, sum: u8) -> &'static str {
        ["N/m2", "N/m", "N", "N.m"][usize::from(sum.min(2)) + self.shift()]
    }

    /// Unit of power.
    pub fn power_unit(self) -> &'static str {
        ["W/m", "W"][self.shift()]
    }

    /// Unit of energy.
    pub fn energy_unit(self) -> &'static str {
        ["J/m", "J"][self.shift()]
    }

    /// "per unit length" or "of the whole body", for descriptions.
    pub fn words(self) -> &'static str {
        ["per unit length", "of the whole body"][self.shift()]
    }
}

/// Unit information of one DOF, filled from the hull by `fmu-pack`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DofUnit {
    /// DOF name (a letter, then letters, digits or `_`).
    pub name: String,
    /// 0: the generalized coordinate is a length (m); 1: it is an angle or a dimensionless
    /// mode amplitude, and the generalized force carries one more metre.
    pub length_exponent: u8,
    /// For `length_exponent` 1: the coordinate is an angle (rad) rather than dimensionless.
    pub is_angle: bool,
}

impl DofUnit {
    /// A DOF with the given unit information.
    pub fn new(name: &str, length_exponent: u8, is_angle: bool) -> DofUnit {
        DofUnit {
            name: name.to_string(),
            length_exponent,
            is_angle,
        }
    }

    /// Unit information of the built-in DOF names: `sway`, `heave`, `cb1`, `cb2`, `cb4`,
    /// `cb5` are displacements (e = 0); `roll`, `cb3`, `cb6` are angles (e = 1).
    pub fn builtin(name: &str) -> Option<DofUnit> {
        match name {
            "sway" | "heave" | "cb1" | "cb2" | "cb4" | "cb5" => Some(DofUnit::new(name, 0, false)),
            "roll" | "cb3" | "cb6" => Some(DofUnit::new(name, 1, true)),
            _ => None,
        }
    }

    /// Unit of the velocity input.
    pub fn velocity_unit(&self) -> &'static str {
        match (self.length_exponent, self.is_angle) {
            (0, _) => "m/s",
            (_, true) => "rad/s",
            _ => "1/s",
        }
    }

    /// Unit of the acceleration input.
    pub fn acceleration_unit(&self) -> &'static str {
        match (self.length_exponent, self.is_angle) {
            (0, _) => "m/s2",
            (_, true) => "rad/s2",
            _ => "1/s2",
        }
    }
}
