//! Viscous roll damping of a section by Ikeda's components at zero speed, and cross-flow drag.
//!
//! Conventions (docs/DESIGN.md, "Slow and viscous forces"): per unit length of hull, SI units,
//! roll angle `phi` positive as the section's roll DOF, the damping moment
//! `M = -B_l phi_dot - B_q |phi_dot| phi_dot` ([`Damping`]). `OG` is Ikeda's distance from the
//! waterline down to the roll axis: `OG > 0` the axis below the water, `OG < 0` above it (a
//! ship's centre of gravity usually lies above: `OG < 0`); `OG = T` is the keel. The field
//! [`RollDampingParams::roll_axis_height`] holds `OG` with this sign.
//!
//! Components (Ikeda, Himeno and Tanaka 1978; ITTC 2011 recommended procedure 7.5-02-07-04.5):
//!
//! - friction (Kato 1958), linear at a given frequency and amplitude:
//!   `r_f = ((0.887 + 0.145 sigma) S_g - 2 OG) / pi`,
//!   `B_F = 0.787 rho S_g r_f^2 sqrt(omega nu) (1 + 0.00814 (r_f^2 phi_a^2 omega / nu)^0.386)`,
//!   with the wetted girth `S_g = 1.7 T + sigma B` (per unit length);
//! - eddy making at zero speed (Ikeda 1978): the Lewis form of `B`, `T`, `sigma`
//!   (coefficients `a_1`, `a_3`, scale `M`), the largest radius `r_max`, the velocity ratio
//!   `gamma`, the pressure coefficient `C_P = 0.5 (0.87 e^-gamma - 4 e^(-0.187 gamma) + 3)` and
//!   `C_R = r_max^2/T^2 C_P [(1 - f_1 R/T)(1 - OG/T - f_1 R/T) + f_2 (H_0 - f_1 R/T)^2]`;
//!   Ikeda's equivalent linear value `4/(3 pi) rho T^4 omega phi_a C_R` is quadratic:
//!   `B_q = rho T^4 max(C_R, 0) / 2` (the fit dips below zero for near-circular sections
//!   rolling off their centre);
//! - bilge keels (Ikeda 1978, ITTC): the normal force with
//!   `C_D = 22.5 b/(pi l phi_a f) + 2.4` splits into a linear part `B_l = 60 rho l^2 b^2 omega
//!   / pi^2` and a quadratic part `B_q = 2.4 rho l^3 b f` (`l`: roll axis to bilge, `b`: keel
//!   breadth, `f = 1 + 0.3 exp(-160 (1 - sigma))`); the hull pressure part is given as its
//!   equivalent linear value at the amplitude; all times the keels' length fraction.
//!
//! Equivalent linear damping: harmonic amplitude `B_eq = B_l + 8/(3 pi) omega phi_a B_q`;
//! a Gaussian sea state with roll-velocity standard deviation `s`: `B_eq = B_l + sqrt(8/pi) s B_q`.
//!
//! Validity (Kawahara et al. 2009 for the simplified method, used here as the range in which
//! Ikeda's formulas were checked): `2.5 <= B/T <= 4.5`, `0.5 <= sigma <= 1.0`,
//! `-1.5 <= OG/T <= 0.2`: outside, a [`Warning`]. Refused ([`ViscousError`]): non-finite or
//! negative inputs, `R > B/2` or `R > T`, `OG >= T` (axis at or below the keel), `sigma`
//! outside the Lewis forms' range.
//!
//! Kinematic viscosity default: `1.19e-6 m^2/s` (sea water at 15 C, ITTC 7.5-02-01-03).

mod components;
mod drag;
mod hull;
mod ship;

pub use components::{bilge_keel, eddy_coefficient, eddy_making, friction, lewis_form, LewisForm};
pub use drag::{cross_flow_drag_coefficient, cross_flow_force, CrossFlow};
pub use hull::{
    bilge_radius_from_area, hull_roll_damping, roll_natural_frequency, roll_params, section_drag,
    section_estimate, HullDampingError, HullRoll, RollAxis, SectionDrag, SectionEstimate,
};
pub use ship::{ship_estimate, ShipEstimate};

use std::fmt;

/// Kinematic viscosity of sea water at 15 C (m^2/s).
pub const SEA_WATER_KINEMATIC_VISCOSITY: f64 = 1.19e-6;

/// Bilge keels of a section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BilgeKeels {
    /// Breadth of one keel normal to the hull (m).
    pub breadth: f64,
    /// Fraction of the section's length that carries keels (0..=1).
    pub length_fraction: f64,
}

/// The roll-damping input of one section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RollDampingParams {
    /// Waterline breadth B (m).
    pub breadth: f64,
    /// Draft T (m).
    pub draft: f64,
    /// Area coefficient sigma = area / (B T).
    pub area_coefficient: f64,
    /// Bilge radius R (m).
    pub bilge_radius: f64,
    /// OG (m): the roll axis's depth below the waterline (negative above it; module docs).
    pub roll_axis_height: f64,
    /// Bilge keels, if any.
    pub bilge_keels: Option<BilgeKeels>,
    /// Water density (kg/m^3).
    pub rho: f64,
    /// Kinematic viscosity (m^2/s).
    pub nu: f64,
}

impl RollDampingParams {
    /// A section with sea water (1025 kg/m^3, [`SEA_WATER_KINEMATIC_VISCOSITY`]), no keels.
    pub fn new(breadth: f64, draft: f64, area_coefficient: f64, bilge_radius: f64) -> Self {
        RollDampingParams {
            breadth,
            draft,
            area_coefficient,
            bilge_radius,
            roll_axis_height: 0.0,
            bilge_keels: None,
            rho: 1025.0,
            nu: SEA_WATER_KINEMATIC_VISCOSITY,
        }
    }

    /// Checks the inputs: an error for what the formulas cannot take, warnings where they
    /// extrapolate.
    pub fn validate(&self) -> Result<Vec<Warning>, ViscousError> {
        let positive = [
            ("breadth", self.breadth),
            ("draft", self.draft),
            ("area_coefficient", self.area_coefficient),
            ("rho", self.rho),
            ("nu", self.nu),
        ];
        for (field, value) in positive {
            if !value.is_finite() || value <= 0.0 {
                return Err(ViscousError::new(
                    field,
                    value,
                    "must be finite and positive",
                ));
            }
        }
        check_non_negative("bilge_radius", self.bilge_radius)?;
        if !self.roll_axis_height.is_finite() {
            return Err(ViscousError::new(
                "roll_axis_height",
                self.roll_axis_height,
                "must be finite",
            ));
        }
        if self.bilge_radius > 0.5 * self.breadth || self.bilge_radius > self.draft {
            return Err(ViscousError::new(
                "bilge_radius",
                self.bilge_radius,
                "larger than the half beam or the draft",
            ));
        }
        if self.roll_axis_height >= self.draft {
            return Err(ViscousError::new(
                "roll_axis_height",
                self.roll_axis_height,
                "roll axis at or below the keel (OG >= T)",
            ));
        }
        if self.area_coefficient > 1.0 {
            return Err(ViscousError::new(
                "area_coefficient",
                self.area_coefficient,
                "above 1",
            ));
        }
        if let Some(keels) = self.bilge_keels {
            check_non_negative("bilge_keels.breadth", keels.breadth)?;
            check_non_negative("bilge_keels.length_fraction", keels.length_fraction)?;
            if keels.length_fraction > 1.0 {
                return Err(ViscousError::new(
                    "bilge_keels.length_fraction",
                    keels.length_fraction,
                    "above 1",
                ));
            }
        }
        let mut warnings = Vec::new();
        let ratio = self.breadth / self.draft;
        if !(2.5..=4.5).contains(&ratio) {
            warnings.push(Warning::new("breadth/draft", ratio, "outside 2.5..4.5"));
        }
        if self.area_coefficient < 0.5 {
            warnings.push(Warning::new(
                "area_coefficient",
                self.area_coefficient,
                "below 0.5",
            ));
        }
        let og = self.roll_axis_height / self.draft;
        if !(-1.5..=0.2).contains(&og) {
            warnings.push(Warning::new(
                "roll_axis_height/draft",
                og,
                "outside -1.5..0.2",
            ));
        }
        Ok(warnings)
    }
}

fn check_non_negative(field: &'static str, value: f64) -> Result<(), ViscousError> {
    if !value.is_finite() || value < 0.0 {
        return Err(ViscousError::new(
            field,
            value,
            "must be finite and non-negative",
        ));
    }
    Ok(())
}

/// A roll damping `M = -linear phi_dot - quadratic |phi_dot| phi_dot` per unit length.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Damping {
    /// B_l (N m s per m per rad).
    pub linear: f64,
    /// B_q (N m s^2 per m per rad^2).
    pub quadratic: f64,
}

impl Damping {
    /// The sum of two dampings.
    pub fn plus(self, other: Damping) -> Damping {
        Damping {
            linear: self.linear + other.linear,
            quadratic: self.quadratic + other.quadratic,
        }
    }

    /// Equivalent linear damping for a harmonic roll of amplitude `phi_a` at `omega`.
    pub fn equivalent_linear(&self, omega: f64, phi_a: f64) -> f64 {
        self.linear + 8.0 / (3.0 * std::f64::consts::PI) * omega * phi_a * self.quadratic
    }

    /// Stochastic linearization for a Gaussian roll velocity of standard deviation `sigma`.
    pub fn stochastic_linear(&self, roll_velocity_std: f64) -> f64 {
        self.linear + (8.0 / std::f64::consts::PI).sqrt() * roll_velocity_std * self.quadratic
    }
}

/// The components of one section's roll damping.
#[derive(Debug, Clone, PartialEq)]
pub struct RollDamping {
    /// Skin friction (linear at the frequency and amplitude).
    pub friction: Damping,
    /// Eddy making (quadratic).
    pub eddy_making: Damping,
    /// Bilge keels: normal force and hull pressure.
    pub bilge_keel: Damping,
    /// Where the formulas extrapolate.
    pub warnings: Vec<Warning>,
}

impl RollDamping {
    /// The sum of the components.
    pub fn total(&self) -> Damping {
        self.friction.plus(self.eddy_making).plus(self.bilge_keel)
    }
}

/// All components of a section at frequency `omega` (rad/s) and amplitude `phi_a` (rad).
pub fn roll_damping(
    params: &RollDampingParams,
    omega: f64,
    phi_a: f64,
) -> Result<RollDamping, ViscousError> {
    let warnings = params.validate()?;
    for (field, value) in [("omega", omega), ("phi_a", phi_a)] {
        if !value.is_finite() || value <= 0.0 {
            return Err(ViscousError::new(
                field,
                value,
                "must be finite and positive",
            ));
        }
    }
    Ok(RollDamping {
        friction: friction(params, omega, phi_a),
        eddy_making: eddy_making(params)?,
        bilge_keel: bilge_keel(params, omega, phi_a),
        warnings,
    })
}

/// The equivalent linear roll damping `B_l(omega, phi_a) + 8/(3 pi) omega phi_a B_q` of all
/// components at `omega` (rad/s) and amplitude `phi_a` (rad, `>= 0`): at `phi_a = 0` the
/// linear parts at vanishing amplitude (friction, the keels' normal force and hull pressure).
pub fn equivalent_roll_damping(
    params: &RollDampingParams,
    omega: f64,
    phi_a: f64,
) -> Result<f64, ViscousError> {
    params.validate()?;
    if !omega.is_finite() || omega <= 0.0 {
        return Err(ViscousError::new(
            "omega",
            omega,
            "must be finite and positive",
        ));
    }
    check_non_negative("phi_a", phi_a)?;
    let total = friction(params, omega, phi_a)
        .plus(eddy_making(params)?)
        .plus(bilge_keel(params, omega, phi_a));
    Ok(total.equivalent_linear(omega, phi_a))
}

/// A ship's roll damping: trapezoidal integral of the sections' dampings over `x` (m).
pub fn integrate_along(stations: &[(f64, Damping)]) -> Damping {
    stations.windows(2).fold(Damping::default(), |sum, pair| {
        let (x0, d0) = pair[0];
        let (x1, d1) = pair[1];
        let half = 0.5 * (x1 - x0);
        sum.plus(Damping {
            linear: half * (d0.linear + d1.linear),
            quadratic: half * (d0.quadratic + d1.quadratic),
        })
    })
}

/// An input the formulas refuse, naming its field.
#[derive(Debug, Clone, PartialEq)]
pub struct ViscousError {
    /// The field.
    pub field: &'static str,
    /// Its value.
    pub value: f64,
    /// Why it is refused.
    pub reason: &'static str,
}

impl ViscousError {
    fn new(field: &'static str, value: f64, reason: &'static str) -> Self {
        ViscousError {
            field,
            value,
            reason,
        }
    }
}

impl fmt::Display for ViscousError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}: {}", self.field, self.value, self.reason)
    }
}

impl std::error::Error for ViscousError {}

/// An input outside the range where Ikeda's method was checked.
pub type Warning = ViscousError;

#[cfg(test)]
mod tests;
