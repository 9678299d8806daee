//! The input of the identification: the complex added mass `A~(omega) = a - i b / omega` of
//! the hull on an ascending frequency grid, with `A_inf` (SI, per unit length, symmetric
//! n x n, time factor `exp(+i omega t)`).

use crate::units;
use nalgebra::DMatrix;
use num_complex::Complex64;

use super::IdentifyError;
use crate::network::Network;

/// The frequencies a fit accepts (rad/s): wider grids make the vector fit's basis span more
/// than 24 decades and its least-squares problems lose every digit.
pub const FREQUENCY_RANGE: (f64, f64) = (1e-12, 1e12);

/// The largest frequency over the smallest a fit accepts.
pub const MAX_FREQUENCY_RATIO: f64 = 1e12;

/// The magnitudes (SI) a fit accepts for the largest entry of `A~` and `A_inf`: the fit and
/// the network it builds square and multiply values (stiffness `m omega^2`, the passivity
/// check's products), which left the representable range from about 1e150 (overflow) and
/// 1e-85 (underflow, a worse fit) on the hemisphere's data scaled up and down.
pub const VALUE_RANGE: (f64, f64) = (1e-50, 1e50);

/// Complex added mass of the hull over frequency (the panel method's output).
#[derive(Clone, Debug, PartialEq)]
pub struct FrequencyResponse {
    /// Names of the hull DOFs.
    pub dof_names: Vec<String>,
    /// Circular frequencies (rad/s), ascending.
    pub omega: Vec<f64>,
    /// `A~(omega) = a - i b / omega` (SI, n x n, symmetric), one per frequency.
    pub added_mass: Vec<DMatrix<Complex64>>,
    /// `A_inf`, from the `omega -> inf` problem (never fitted).
    pub added_mass_inf: DMatrix<f64>,
    /// Water density the data was computed for.
    pub rho: f64,
    /// Gravity the data was computed for.
    pub g: f64,
}

impl FrequencyResponse {
    /// The panel method's nondimensional sweep in SI units for `rho` and `g`:
    /// `omega = sqrt(kR g / R)`, `A~ = rho pi R^2 (A~ / (rho pi R^2))`.
    pub fn from_sweep(sweep: &crate::sweep::SweepResult, rho: f64, g: f64) -> FrequencyResponse {
        let radius = sweep.reference_half_beam;
        let scale = units::added_mass_scale(rho, radius);
        FrequencyResponse {
            dof_names: sweep.dof_names.clone(),
            omega: sweep
                .kr
                .iter()
                .map(|kr| units::omega_from_kr(*kr, radius, g))
                .collect(),
            added_mass: sweep
                .added_mass
                .iter()
                .map(|m| m * Complex64::new(scale, 0.0))
                .collect(),
            added_mass_inf: &sweep.added_mass_inf * scale,
            rho,
            g,
        }
    }

    /// Number of DOFs.
    pub fn dof_count(&self) -> usize {
        self.dof_names.len()
    }

    /// Checks sizes, ordering, finiteness and ranges ([`FREQUENCY_RANGE`],
    /// [`MAX_FREQUENCY_RATIO`], [`VALUE_RANGE`]).
    pub fn validate(&self) -> Result<(), IdentifyError> {
        let bad = |m: String| Err(IdentifyError::InvalidData(m));
        let n = self.dof_names.len();
        if n == 0 {
            return bad("no DOFs".into());
        }
        for (i, name) in self.dof_names.iter().enumerate() {
            if name.is_empty() || self.dof_names[..i].contains(name) {
                return bad(format!("DOF name {name:?} is empty or repeated"));
            }
        }
        if !(self.rho.is_finite() && self.rho > 0.0 && self.g.is_finite() && self.g > 0.0) {
            return bad(format!(
                "rho and g must be finite and > 0, got {} and {}",
                self.rho, self.g
            ));
        }
        if self.omega.len() != self.added_mass.len() {
            return bad(format!(
                "{} frequencies but {} added mass matrices",
                self.omega.len(),
                self.added_mass.len()
            ));
        }
        for (k, &w) in self.omega.iter().enumerate() {
            if !(w.is_finite() && w > 0.0) {
                return bad(format!("omega[{k}] = {w} is not finite and > 0"));
            }
            if k > 0 && w <= self.omega[k - 1] {
                return bad(format!("omega is not strictly ascending at index {k}"));
            }
        }
        let (lowest, highest) = FREQUENCY_RANGE;
        if let Some(&w) = self
            .omega
            .iter()
            .find(|&&w| !(lowest..=highest).contains(&w))
        {
            return bad(format!(
                "omega = {w:e} rad/s is outside the range {lowest:e} .. {highest:e} rad/s a fit \
                 accepts (check the frequency column's unit)"
            ));
        }
        if let (Some(&first), Some(&last)) = (self.omega.first(), self.omega.last()) {
            if last > MAX_FREQUENCY_RATIO * first {
                return bad(format!(
                    "the frequencies span {first:e} .. {last:e} rad/s, a ratio above \
                     {MAX_FREQUENCY_RATIO:e}: the fit cannot resolve so wide a grid"
                ));
            }
        }
        for (k, a) in self.added_mass.iter().enumerate() {
            if a.nrows() != n || a.ncols() != n {
                return bad(format!(
                    "added_mass[{k}] is {} x {}, expected {n} x {n}",
                    a.nrows(),
                    a.ncols()
                ));
            }
            if let Some(p) = a
                .iter()
                .position(|x| !(x.re.is_finite() && x.im.is_finite()))
            {
                return bad(format!(
                    "added_mass at omega = {} has a non-finite entry [{},{}]",
                    self.omega[k],
                    p % n + 1,
                    p / n + 1
                ));
            }
        }
        let a = &self.added_mass_inf;
        if a.nrows() != n || a.ncols() != n {
            return bad(format!(
                "added_mass_inf is {} x {}, expected {n} x {n}",
                a.nrows(),
                a.ncols()
            ));
        }
        if a.iter().any(|x| !x.is_finite()) {
            return bad("added_mass_inf has a non-finite entry".into());
        }
        self.check_value_range()
    }

    /// The largest entry of `A~` and `A_inf` within [`VALUE_RANGE`] (all zero is left to the
    /// fit, which names it).
    fn check_value_range(&self) -> Result<(), IdentifyError> {
        let largest = self
            .added_mass
            .iter()
            .flat_map(|m| m.iter().map(|z| z.norm()))
            .chain(self.added_mass_inf.iter().map(|x| x.abs()))
            .fold(0.0, f64::max);
        let (smallest_allowed, largest_allowed) = VALUE_RANGE;
        if largest > largest_allowed || (largest > 0.0 && largest < smallest_allowed) {
            return Err(IdentifyError::InvalidData(format!(
                "the largest added mass entry is {largest:e} (SI), outside the range \
                 {smallest_allowed:e} .. {largest_allowed:e} the fit can represent (check the \
                 length scale and units of the data)"
            )));
        }
        Ok(())
    }

    /// The sub-response of the named DOFs (in the given order).
    pub fn select(&self, names: &[&str]) -> Result<FrequencyResponse, IdentifyError> {
        let mut index = Vec::with_capacity(names.len());
        for name in names {
            match self.dof_names.iter().position(|d| d == name) {
                Some(i) => index.push(i),
                None => {
                    return Err(IdentifyError::InvalidData(format!(
                        "no DOF named {name:?} (have: {})",
                        self.dof_names.join(", ")
                    )))
                }
            }
        }
        let m = index.len();
        let pick_c =
            |a: &DMatrix<Complex64>| DMatrix::from_fn(m, m, |i, j| a[(index[i], index[j])]);
        Ok(FrequencyResponse {
            dof_names: index.iter().map(|&i| self.dof_names[i].clone()).collect(),
            omega: self.omega.clone(),
            added_mass: self.added_mass.iter().map(pick_c).collect(),
            added_mass_inf: DMatrix::from_fn(m, m, |i, j| {
                self.added_mass_inf[(index[i], index[j])]
            }),
            rho: self.rho,
            g: self.g,
        })
    }

    /// The response of a network on a frequency grid (synthetic data, checks).
    pub fn from_network(network: &Network, omega: &[f64]) -> FrequencyResponse {
        FrequencyResponse {
            dof_names: network.dof_names.clone(),
            omega: omega.to_vec(),
            added_mass: omega.iter().map(|&w| network.added_mass_tf(w)).collect(),
            added_mass_inf: network.added_mass_inf.clone(),
            rho: network.rho,
            g: network.g,
        }
    }
}
