//! Units and scales of the 2D radiation problem: the deep-water dispersion relation and the
//! nondimensional coefficients.
//!
//! Deep water, time factor `exp(+i omega t)`, `R` the hull's reference half-beam:
//!
//! ```text
//! k      = omega^2 / g            (wavenumber, 1/m)
//! kR     = omega^2 R / g          (nondimensional frequency)
//! omega  = sqrt(kR g / R)
//! A~_ij / (rho pi R^2)            (nondimensional added mass, both parts of A~ = a - i b / omega)
//! ```
//!
//! Each function keeps the order of its floating-point operations (the order written in its
//! doc), so results are bit for bit the same wherever it replaces an inline formula.
//!
//! [`WaterDepth`] carries a finite depth and its dispersion relation `omega^2 = g k tanh(k h)`.

use crate::green::finite_depth::DepthError;

/// `omega = sqrt(kR g / R)` (rad/s), computed as `(kr * g / radius).sqrt()`.
pub fn omega_from_kr(kr: f64, radius: f64, g: f64) -> f64 {
    (kr * g / radius).sqrt()
}

/// `kR = omega^2 R / g`, computed as `omega * omega * radius / g`.
pub fn kr_from_omega(omega: f64, radius: f64, g: f64) -> f64 {
    omega * omega * radius / g
}

/// Deep-water wavenumber `k = omega^2 / g` (1/m), computed as `omega * omega / g`.
pub fn wavenumber(omega: f64, g: f64) -> f64 {
    omega * omega / g
}

/// Wavenumber of a nondimensional frequency: `k = kR / R` (1/m).
pub(crate) fn wavenumber_from_kr(kr: f64, radius: f64) -> f64 {
    kr / radius
}

/// Scale of the nondimensional added mass: `A~ = rho pi R^2 (A~ / (rho pi R^2))`, computed as
/// `rho * PI * radius * radius` (kg/m per unit of the nondimensional value). With `rho = 1`
/// it is the area `pi R^2`.
pub(crate) fn added_mass_scale(rho: f64, radius: f64) -> f64 {
    rho * std::f64::consts::PI * radius * radius
}

/// The water depth a computation is for: deep water (the default) or a finite depth `h` (m,
/// flat bottom at `y = -h`). Tables record it as `# depth: h/R` (`# depth: inf` for deep
/// water, docs/DESIGN.md); the propagating wavenumber solves `omega^2 = g k tanh(k h)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum WaterDepth {
    /// `h -> inf`: `k = omega^2 / g`.
    #[default]
    Infinite,
    /// A finite depth `h` (m), finite and > 0.
    Finite(f64),
}

impl WaterDepth {
    /// `h` (m): `inf` gives [`WaterDepth::Infinite`].
    ///
    /// # Errors
    /// [`DepthError::InvalidDepth`] for NaN, zero or a negative depth.
    pub fn new(depth: f64) -> Result<Self, DepthError> {
        if depth == f64::INFINITY {
            Ok(WaterDepth::Infinite)
        } else if depth.is_finite() && depth > 0.0 {
            Ok(WaterDepth::Finite(depth))
        } else {
            Err(DepthError::InvalidDepth(depth))
        }
    }

    /// `h` in metres (`inf` for deep water).
    pub fn metres(self) -> f64 {
        match self {
            WaterDepth::Infinite => f64::INFINITY,
            WaterDepth::Finite(h) => h,
        }
    }

    /// Whether this is deep water.
    pub fn is_infinite(self) -> bool {
        self == WaterDepth::Infinite
    }

    /// The propagating wavenumber (1/m) at `omega` (rad/s): `omega^2 / g` in deep water
    /// ([`wavenumber`], bit for bit), else the root of `omega^2 = g k tanh(k h)`.
    ///
    /// # Errors
    /// [`DepthError`] when `omega^2 / g` is not finite and > 0 in finite depth, or the
    /// dispersion relation does not converge.
    pub fn wavenumber(self, omega: f64, g: f64) -> Result<f64, DepthError> {
        match self {
            WaterDepth::Infinite => Ok(wavenumber(omega, g)),
            WaterDepth::Finite(h) => crate::green::finite_depth::wavenumber(omega * omega / g, h),
        }
    }

    /// The value of a table's `# depth:` line for reference length `radius` (m): `h/R`, or
    /// `inf`.
    pub fn table_value(self, radius: f64) -> String {
        match self {
            WaterDepth::Infinite => "inf".to_string(),
            WaterDepth::Finite(h) => format!("{}", h / radius),
        }
    }

    /// The depth of a table's `# depth:` value (`h/R` or `inf`) for reference length `radius`.
    ///
    /// # Errors
    /// A value that is not a number, or not finite and > 0 (named in the message).
    pub fn from_table_value(value: &str, radius: f64) -> Result<Self, String> {
        let value = value.trim();
        if value == "inf" {
            return Ok(WaterDepth::Infinite);
        }
        let ratio: f64 = value
            .parse()
            .map_err(|_| format!("`# depth: {value}`: expected h/R (a number) or `inf`"))?;
        if !(ratio.is_finite() && ratio > 0.0) {
            return Err(format!(
                "`# depth: {value}`: h/R must be finite and > 0 (`inf` for deep water)"
            ));
        }
        WaterDepth::new(ratio * radius).map_err(|e| format!("`# depth: {value}`: {e}"))
    }
}

impl std::fmt::Display for WaterDepth {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            WaterDepth::Infinite => write!(f, "infinite (deep water)"),
            WaterDepth::Finite(h) => write!(f, "{h} m"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dispersion_relation_round_trips() {
        let (g, radius) = (9.81, 2.0);
        for kr in [0.01, 0.05, 1.0, 5.0, 10.0] {
            let omega = omega_from_kr(kr, radius, g);
            assert_eq!(omega, (kr * g / radius).sqrt());
            assert!((kr_from_omega(omega, radius, g) - kr).abs() <= 1e-14 * kr);
            let k = wavenumber(omega, g);
            assert!((k - wavenumber_from_kr(kr, radius)).abs() <= 1e-14 * k);
        }
        assert_eq!(added_mass_scale(1.0, 3.0), std::f64::consts::PI * 3.0 * 3.0);
        assert_eq!(added_mass_scale(1025.0, 1.0), 1025.0 * std::f64::consts::PI);
    }

    #[test]
    fn water_depth_round_trips_through_its_table_line() {
        let radius = 2.0;
        for depth in [
            WaterDepth::Infinite,
            WaterDepth::Finite(3.0),
            WaterDepth::Finite(0.25),
        ] {
            let value = depth.table_value(radius);
            assert_eq!(WaterDepth::from_table_value(&value, radius), Ok(depth));
        }
        assert_eq!(WaterDepth::Finite(3.0).table_value(radius), "1.5");
        for bad in ["0", "-1", "nan", "NaN", "x", "", "1e999"] {
            assert!(WaterDepth::from_table_value(bad, radius).is_err(), "{bad}");
        }
        assert_eq!(WaterDepth::new(f64::INFINITY), Ok(WaterDepth::Infinite));
        for bad in [0.0, -1.0, f64::NAN, f64::NEG_INFINITY] {
            assert!(WaterDepth::new(bad).is_err());
        }
    }

    #[test]
    fn water_depth_wavenumber_is_deep_water_bit_for_bit_and_tends_to_it() {
        let (g, omega) = (9.81, 1.3);
        assert_eq!(
            WaterDepth::Infinite.wavenumber(omega, g).unwrap(),
            wavenumber(omega, g)
        );
        let deep = wavenumber(omega, g);
        let k = WaterDepth::Finite(2.0).wavenumber(omega, g).unwrap();
        assert!((omega * omega - g * k * (k * 2.0).tanh()).abs() < 1e-13);
        assert!(k > deep);
        let k = WaterDepth::Finite(200.0).wavenumber(omega, g).unwrap();
        assert!((k - deep).abs() < 1e-14 * deep);
    }
}
