//! The mean drift table written by `fmu-pack sweep HULL --drift FILE` (docs/DESIGN.md), read by
//! the excitation table's parser (the same header and bounds), and its interpolation in `kR`.
//!
//! ```text
//! # modes: sway heave roll ...          (required)
//! # convention: exp(+i omega t)         (required, exactly)
//! # R: 1 m                              (required: the reference radius)
//! # length exponents: 0 0 1 ...         (required: e_j per mode)
//! # depth: inf                         (optional: h/R, or `inf`; absent: deep water)
//! kR,j,heading,value
//! ```
//!
//! `value = D_j / (rho g R^e_j)`; in SI `D_j = value rho g R^e_j` at `omega = sqrt(kR g / R)`,
//! and `a^2 D_j` is the mean force in DOF `j` (per metre for a section) of a regular wave of
//! amplitude `a`. Every (kR, heading) must hold each `j` exactly once.
//!
//! Interpolation: linear in `kR` between the table's frequencies. Below the lowest positive
//! `kR`, linear towards `D_j = 0` at `kR = 0` (long waves pass a hull without reflection: the
//! drift vanishes), or towards the table's own `kR = 0` rows when it has them. Above the
//! highest `kR`: none (the sea refuses the component, as the excitation table does).

use super::table::Grid;
use super::WaveError;
use crate::units::WaterDepth;

/// The drift force the FMU adds (`wave.drift`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DriftMode {
    /// No drift force (code 0, the default).
    #[default]
    Off,
    /// The mean drift `r^2 sum_n a_n^2 D_j(omega_n)` (code 1).
    Mean,
    /// The slow drift by Newman's approximation (code 2): `r^2 Re[P_j conj(Q)]`.
    Newman,
}

impl DriftMode {
    /// The mode with FMU code 0 (off), 1 (mean) or 2 (slow drift by Newman).
    ///
    /// # Errors
    /// Any other code.
    pub fn from_code(code: i32) -> Result<DriftMode, WaveError> {
        match code {
            0 => Ok(DriftMode::Off),
            1 => Ok(DriftMode::Mean),
            2 => Ok(DriftMode::Newman),
            _ => Err(WaveError::parameter(
                "wave.drift",
                code,
                "unknown mode: must be 0 (none), 1 (mean drift) or 2 (slow drift, Newman)",
            )),
        }
    }

    /// The FMU code: 0, 1 or 2.
    pub fn code(self) -> i32 {
        match self {
            DriftMode::Off => 0,
            DriftMode::Mean => 1,
            DriftMode::Newman => 2,
        }
    }
}

const COLUMNS: &str = "kR,j,heading,value";
/// Relative slack on the band's upper end (rounding of `kR = omega^2 R / g`).
const BAND_SLACK: f64 = 1e-12;

/// A parsed drift table: nondimensional `D_j / (rho g R^e_j)` on a rectangular set of
/// `kR` x heading x mode.
#[derive(Clone, Debug, PartialEq)]
pub struct DriftTable {
    hull: Option<String>,
    modes: Vec<String>,
    radius: f64,
    length_exponents: Vec<i32>,
    /// Ascending, starting with 0 (the table's `kR = 0` rows, or zeros added).
    kr: Vec<f64>,
    headings: Vec<f64>,
    /// `[(heading * modes + j) * kr.len() + k]`.
    values: Vec<f64>,
    depth: WaterDepth,
}

impl DriftTable {
    /// Parses the table text; `source_name` (the file name) starts every error message.
    ///
    /// # Errors
    /// As [`super::ExcitationTable::from_csv_str`], with the column line `kR,j,heading,value`:
    /// text over [`super::MAX_TABLE_BYTES`]; a missing, repeated or malformed header line; a
    /// row with a wrong field count, a bad or non-finite number, `j` out of range, a negative
    /// `kR`; duplicated or missing rows; more than [`super::MAX_ROWS`] rows,
    /// [`super::MAX_WAVE_FREQUENCIES`] `kR`, [`super::MAX_MODES`] modes or
    /// [`super::MAX_HEADINGS`] headings; fewer than two positive `kR`.
    pub fn from_csv_str(text: &str, source_name: &str) -> Result<DriftTable, WaveError> {
        let grid = Grid::parse(text, source_name, COLUMNS)?;
        let (kr_count, series) = (grid.kr.len(), grid.headings.len() * grid.modes.len());
        let long_wave = grid.kr[0] == 0.0;
        let mut kr = Vec::with_capacity(kr_count + 1);
        let mut values = Vec::with_capacity(series * (kr_count + 1));
        if !long_wave {
            kr.push(0.0);
        }
        kr.extend_from_slice(&grid.kr);
        for chunk in grid.values.chunks_exact(kr_count) {
            if !long_wave {
                values.push(0.0);
            }
            values.extend(chunk.iter().map(|z| z.re));
        }
        Ok(DriftTable {
            hull: grid.hull,
            modes: grid.modes,
            radius: grid.radius,
            length_exponents: grid.length_exponents,
            kr,
            headings: grid.headings,
            values,
            depth: grid.depth,
        })
    }

    /// The water depth the table is for (`# depth:`; deep water without that line).
    pub fn depth(&self) -> WaterDepth {
        self.depth
    }

    /// The hull's name from the `# hull:` line, when present.
    pub fn hull(&self) -> Option<&str> {
        self.hull.as_deref()
    }

    /// The DOF names (`# modes:`), in the order of `j`.
    pub fn modes(&self) -> &[String] {
        &self.modes
    }

    /// The reference radius `R` (m).
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The length exponents `e_j` (`# length exponents:`).
    pub fn length_exponents(&self) -> &[i32] {
        &self.length_exponents
    }

    /// The distinct `kR`, ascending, starting with 0 (the long-wave limit: the table's rows,
    /// or zero drift when it has none).
    pub fn kr(&self) -> &[f64] {
        &self.kr
    }

    /// The distinct headings in degrees, in `[0, 360)`, ascending.
    pub fn headings(&self) -> &[f64] {
        &self.headings
    }

    /// The index of `heading` (degrees, modulo 360, within 1e-9) in [`Self::headings`].
    pub fn heading_index(&self, heading: f64) -> Option<usize> {
        let reduced = super::heading_direction(heading).ok()?;
        self.headings
            .iter()
            .position(|&h| super::same_direction(h, reduced))
    }

    /// The tabulated `D_j / (rho g R^e_j)` of mode `mode` (0-based), heading `heading` and
    /// `kR` at the given indices (of [`Self::kr`]); `None` when an index is out of range.
    pub fn value(&self, mode: usize, heading: usize, kr: usize) -> Option<f64> {
        if mode >= self.modes.len() || heading >= self.headings.len() || kr >= self.kr.len() {
            return None;
        }
        Some(self.values[(heading * self.modes.len() + mode) * self.kr.len() + kr])
    }

    /// Whether mode `mode` has zero drift at every `kR` of heading `heading` (true out of range).
    pub fn is_zero(&self, mode: usize, heading: usize) -> bool {
        self.series(mode, heading)
            .is_none_or(|series| series.iter().all(|&v| v == 0.0))
    }

    /// The largest `kR` interpolated at.
    pub fn highest_kr(&self) -> f64 {
        self.kr[self.kr.len() - 1]
    }

    /// `rho g R^e_j`: multiplies the table's numbers to give `D_j` in SI (N/m^2 per metre of
    /// section, or N m/m^2 for DOFs in rad); `None` for a mode out of range.
    pub fn force_scale(&self, mode: usize, rho: f64, g: f64) -> Option<f64> {
        let exponent = *self.length_exponents.get(mode)?;
        Some(rho * g * self.radius.powi(exponent))
    }

    /// The nondimensional `D_j` interpolated linearly in `kR` at `kr` (module docs): `None`
    /// above the highest `kR` (with 1e-12 relative slack), for a negative or non-finite `kr`
    /// or an index out of range.
    pub fn interpolate(&self, mode: usize, heading: usize, kr: f64) -> Option<f64> {
        let series = self.series(mode, heading)?;
        if !(kr.is_finite() && kr >= 0.0) || kr > self.highest_kr() * (1.0 + BAND_SLACK) {
            return None;
        }
        let kr = kr.min(self.highest_kr());
        let upper = self
            .kr
            .partition_point(|&k| k <= kr)
            .clamp(1, self.kr.len() - 1);
        let (k0, k1) = (self.kr[upper - 1], self.kr[upper]);
        let t = (kr - k0) / (k1 - k0);
        Some(series[upper - 1] + (series[upper] - series[upper - 1]) * t)
    }

    fn series(&self, mode: usize, heading: usize) -> Option<&[f64]> {
        if mode >= self.modes.len() || heading >= self.headings.len() {
            return None;
        }
        let start = (heading * self.modes.len() + mode) * self.kr.len();
        Some(&self.values[start..start + self.kr.len()])
    }
}
