//! Incident waves in the time domain: the elevation at x = 0 and the exciting force of every
//! DOF, for calm water, a regular wave or a JONSWAP sea (`docs/WAVES.md`).
//!
//! Time factor `exp(+i omega t)`, heading 0 (waves towards +x) or 180 (towards -x), phase
//! reference x = 0. The water depth enters only through the tables (their `# depth:` line;
//! [`ExcitationTable::depth`]): the elevation at x = 0 and the spectrum in omega do not involve
//! the wavenumber, and the tables are read at `kR = omega^2 R / g` in any depth. A sea is a
//! harmonic sum of components
//! `(omega_n, a_n, eps_n)`:
//!
//! ```text
//! eta(t)  = r(t) sum_n a_n cos(omega_n t + eps_n)
//! F_j(t)  = r(t) sum_n Re[c_nj e^{i omega_n t}],   c_nj = a_n X_j(omega_n) e^{i eps_n}
//! r(t)    = (1 - cos(pi (t - t0) / T_ramp)) / 2 for t0 <= t < t0 + T_ramp, 0 before t0, else 1
//! ```
//!
//! with `X_j` the exciting force per unit wave amplitude (SI) interpolated from an
//! [`ExcitationTable`] and `t0` the start time (`T_ramp = 0`: no ramp).
//!
//! - Regular: one component, `a = H / 2`, `omega = 2 pi / T`, `eps = 0`.
//! - JONSWAP (`jonswap`, DNV-RP-C205; gamma = 1 is Pierson-Moskowitz): `N` components, one
//!   in each of `N` bins over `[0.5, 6] omega_p` (intersected with the table's band), of
//!   equal weight half by energy and half by width, the frequency uniform inside its bin, `a_n = sqrt(2 S(omega_n) d omega_n)`, the
//!   phase uniform in `[0, 2 pi)`, all from SplitMix64 seeded by the seed.
//!
//! Drift ([`Sea::with_drift`], a [`DriftTable`] and `wave.drift` = [`DriftMode`]): with
//! `d_nj = D_j(omega_n)` in SI (`rho g R^e_j` times the table's value, linear in `kR`),
//!
//! ```text
//! mean    F_j = r(t)^2 sum_n a_n^2 d_nj
//! Newman  F_j = r(t)^2 Re[P_j(t) conj(Q(t))],  P_j = sum_n a_n d_nj e^{i(omega_n t + eps_n)},
//!                                              Q   = sum_n a_n e^{i(omega_n t + eps_n)}
//! ```
//!
//! Newman's approximation `T_nm = (T_nn + T_mm) / 2` keeps the difference frequencies only:
//! `Re[P conj Q] = sum_n a_n^2 d_nj + sum_{n<m} 2 a_n a_m T_nm cos(theta_n - theta_m)`, whose
//! time mean is the mean drift (`2 int S D d omega` in the limit) and whose variance is
//! `sum_{n != m} a_n^2 a_m^2 T_nm^2`. A regular wave gives `a^2 D_j` in both modes. DOFs with
//! zero drift at every frequency are skipped; the cost is O(N) per step from the same phasors.
//!
//! [`Sea`] is the immutable realization (rebuilt from the parameters and the start time);
//! [`SeaScratch`] caches the phasors `e^{i omega_n t}` that [`Sea::evaluate`] advances by
//! multiplication.
//!
//! Where things are: `table.rs` the excitation table and its interpolation (and the parser
//! both tables share), `drift_table.rs` the drift table, `spectrum.rs` the
//! JONSWAP spectrum and its discretization, `sea.rs` the realization and its evaluation.

mod drift_table;
mod sea;
mod spectrum;
mod table;

pub use drift_table::{DriftMode, DriftTable};
pub use sea::{Sea, SeaScratch};
#[cfg(test)]
use spectrum::jonswap;
pub(crate) use table::write_excitation_rows;
pub use table::{
    ExcitationTable, MAX_HEADINGS, MAX_MODES, MAX_ROWS, MAX_TABLE_BYTES, MAX_WAVE_FREQUENCIES,
};

use std::fmt;

/// Default number of JONSWAP components (chosen from `benches/waves.rs`, `docs/WAVES.md`).
pub const DEFAULT_COMPONENTS: usize = 64;

/// Largest number of JONSWAP components accepted.
pub const MAX_COMPONENTS: usize = 10_000;

/// Tolerance on the heading (degrees): 0 and 180 are accepted within it, modulo 360.
pub(crate) const HEADING_TOLERANCE: f64 = 1e-9;

/// The largest JONSWAP peak enhancement accepted. DNV-RP-C205's normalization
/// `1 - 0.287 ln gamma` is for 1..7; measured, the variance falls 3.2 % short of `Hs^2/16` at 8
/// and 6.9 % at 10 (a warning above 7), 39 % at 20 and 61 % at 25, and the factor is negative
/// from 32.6.
pub const MAX_GAMMA: f64 = 10.0;

/// Why a sea could not be built.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum WaveError {
    /// A parameter out of its range.
    Parameter {
        /// The parameter's name (`wave.height`, `rho`, ...).
        name: &'static str,
        /// The value as given.
        value: String,
        /// What the value must satisfy.
        requirement: String,
    },
    /// A malformed excitation table.
    Table {
        /// The table's name (file name).
        source: String,
        /// 1-based line, when the problem is on one line.
        line: Option<usize>,
        /// The problem, naming the field.
        message: String,
    },
    /// A wave the excitation table cannot give the force for (outside its band, or a heading
    /// it does not have).
    Band {
        /// The problem, with the frequencies involved.
        message: String,
    },
}

impl WaveError {
    fn parameter(name: &'static str, value: impl fmt::Display, requirement: &str) -> Self {
        WaveError::Parameter {
            name,
            value: value.to_string(),
            requirement: requirement.to_string(),
        }
    }
}

impl fmt::Display for WaveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WaveError::Parameter {
                name,
                value,
                requirement,
            } => write!(f, "{name} = {value}: {requirement}"),
            WaveError::Table {
                source,
                line: Some(line),
                message,
            } => write!(f, "{source}:{line}: {message}"),
            WaveError::Table {
                source,
                line: None,
                message,
            } => write!(f, "{source}: {message}"),
            WaveError::Band { message } => write!(f, "{message}"),
        }
    }
}

impl std::error::Error for WaveError {}

/// The kind of sea.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WaveKind {
    /// Calm water: no waves, no exciting force (code 0).
    Calm,
    /// One regular wave of height `H` and period `T` (code 1).
    Regular,
    /// A JONSWAP sea of significant height `Hs` and peak period `Tp` (code 2).
    Jonswap,
}

impl WaveKind {
    /// The kind with FMU code 0 (calm), 1 (regular) or 2 (JONSWAP).
    ///
    /// # Errors
    /// Any other code.
    pub fn from_code(code: i32) -> Result<WaveKind, WaveError> {
        match code {
            0 => Ok(WaveKind::Calm),
            1 => Ok(WaveKind::Regular),
            2 => Ok(WaveKind::Jonswap),
            _ => Err(WaveError::parameter(
                "wave.kind",
                code,
                "unknown kind: must be 0 (calm), 1 (regular) or 2 (JONSWAP)",
            )),
        }
    }

    /// The FMU code: 0, 1 or 2.
    pub fn code(self) -> i32 {
        match self {
            WaveKind::Calm => 0,
            WaveKind::Regular => 1,
            WaveKind::Jonswap => 2,
        }
    }
}

/// The parameters of a sea (the FMU's `wave.*` parameters).
#[derive(Clone, Debug, PartialEq)]
pub struct WaveParams {
    /// Calm, regular or JONSWAP. Default calm.
    pub kind: WaveKind,
    /// Regular: wave height `H = 2a`; JONSWAP: significant height `Hs` (m, >= 0). Default 1.
    pub height: f64,
    /// Regular: period `T`; JONSWAP: peak period `Tp` (s, > 0). Default 8.
    pub period: f64,
    /// Heading in degrees: 0 (towards +x) or 180 (towards -x), modulo 360. Default 0.
    pub heading: f64,
    /// JONSWAP peak enhancement (1..=[`MAX_GAMMA`]; 1 is Pierson-Moskowitz; DNV's range 1..7).
    /// Default 3.3.
    pub gamma: f64,
    /// JONSWAP seed: the same seed gives the same record bit for bit. Default 1.
    pub seed: i32,
    /// JONSWAP component count, 1..=[`MAX_COMPONENTS`]. Default [`DEFAULT_COMPONENTS`].
    pub components: usize,
    /// Ramp duration from the start time (s, >= 0; 0: no ramp). Default 0.
    pub ramp: f64,
    /// The drift force (`wave.drift`, only with a drift table). Default off.
    pub drift: DriftMode,
}

impl Default for WaveParams {
    fn default() -> Self {
        WaveParams {
            kind: WaveKind::Calm,
            height: 1.0,
            period: 8.0,
            heading: 0.0,
            gamma: 3.3,
            seed: 1,
            components: DEFAULT_COMPONENTS,
            ramp: 0.0,
            drift: DriftMode::Off,
        }
    }
}

impl WaveParams {
    /// Checks every parameter (whatever the kind) and returns the warnings: gamma outside
    /// DNV's range 1..7 for a JONSWAP sea.
    ///
    /// # Errors
    /// Height < 0 or non-finite, period <= 0 or non-finite, heading non-finite (which
    /// headings exist is the excitation table's to say, when the sea is built), gamma outside
    /// 1..=[`MAX_GAMMA`] or non-finite, components 0 or above [`MAX_COMPONENTS`], ramp < 0 or non-finite.
    pub fn validate(&self) -> Result<Vec<String>, WaveError> {
        if !(self.height.is_finite() && self.height >= 0.0) {
            return Err(WaveError::parameter(
                "wave.height",
                self.height,
                "must be finite and >= 0 (m)",
            ));
        }
        if !(self.period.is_finite() && self.period > 0.0) {
            return Err(WaveError::parameter(
                "wave.period",
                self.period,
                "must be finite and > 0 (s)",
            ));
        }
        heading_direction(self.heading)?;
        if !(self.gamma.is_finite() && (1.0..=MAX_GAMMA).contains(&self.gamma)) {
            return Err(WaveError::parameter(
                "wave.gamma",
                self.gamma,
                &format!(
                    "must be 1..={MAX_GAMMA} (1: Pierson-Moskowitz; beyond {MAX_GAMMA} DNV's \
                     normalization 1 - 0.287 ln gamma leaves the sea's variance far below \
                     Hs^2/16: 0.61 of it at 20, 0.39 at 25, negative from 32.6)"
                ),
            ));
        }
        if self.components == 0 || self.components > MAX_COMPONENTS {
            return Err(WaveError::parameter(
                "wave.components",
                self.components,
                &format!("must be 1..={MAX_COMPONENTS}"),
            ));
        }
        if !(self.ramp.is_finite() && self.ramp >= 0.0) {
            return Err(WaveError::parameter(
                "wave.ramp",
                self.ramp,
                "must be finite and >= 0 (s; 0: no ramp)",
            ));
        }
        let mut warnings = Vec::new();
        if self.kind == WaveKind::Jonswap && self.gamma > 7.0 {
            warnings.push(format!(
                "wave.gamma = {} is outside DNV-RP-C205's range 1..7: the spectrum's \
                 normalization (1 - 0.287 ln gamma) is less accurate there (the variance 3.2 % \
                 below Hs^2/16 at 8, 6.9 % at 10)",
                self.gamma
            ));
        }
        Ok(warnings)
    }
}

/// Whether two headings (degrees) are one direction: equal modulo 360 within
/// [`HEADING_TOLERANCE`].
pub(crate) fn same_direction(a: f64, b: f64) -> bool {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d) <= HEADING_TOLERANCE
}

/// The heading reduced to 0 or 180 degrees.
fn heading_direction(heading: f64) -> Result<f64, WaveError> {
    if heading.is_finite() {
        let reduced = heading.rem_euclid(360.0);
        if reduced >= 360.0 - HEADING_TOLERANCE {
            return Ok(0.0);
        }
        return Ok(reduced);
    }
    Err(WaveError::parameter(
        "wave.heading",
        heading,
        "must be finite (degrees; a 2D section's table has 0 and 180, a ship's the headings \
         it was swept for)",
    ))
}

#[cfg(test)]
mod drift_tests;
#[cfg(test)]
mod tests;
