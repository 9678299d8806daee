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
}
