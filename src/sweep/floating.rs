//! A floating section's tables: its motion per unit wave amplitude (RAO) and its mean drift,
//! from the sweep of its hull and its mass properties ([`crate::motion`]).
//!
//! ```text
//! RAO:   kR,j,heading,re,im   value = xi_j R^e_j / a      (rigid DOFs; elastic DOFs held)
//! drift: kR,j,heading,value   value = D_j / (rho g R^e_j)  (every DOF)
//! ```
//!
//! The floating drift in sway is Maruo's `c (1 + |R|^2 - |T|^2) / 4` with the reflected and
//! transmitted waves of the moving section: the scattered wave plus the waves its motion
//! radiates ([`crate::bem::Drift::horizontal_far_field_moving`]); the other DOFs' is the
//! pressure integration over the moving section ([`crate::bem::Drift::near_field_moving`]),
//! whose horizontal force the header compares with the far field's.

use super::SweepResult;
use crate::bem::HEADINGS;
use crate::motion::{Floating, MotionError};
use num_complex::Complex64;
use std::io::Write;

/// Why a floating section's table could not be written.
#[derive(Debug)]
#[non_exhaustive]
pub enum FloatingTableError {
    /// The motion could not be computed.
    Motion(MotionError),
    /// Writing failed.
    Io(std::io::Error),
}

impl std::fmt::Display for FloatingTableError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FloatingTableError::Motion(e) => e.fmt(f),
            FloatingTableError::Io(e) => write!(f, "cannot write the table: {e}"),
        }
    }
}

impl std::error::Error for FloatingTableError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            FloatingTableError::Motion(e) => Some(e),
            FloatingTableError::Io(e) => Some(e),
        }
    }
}

impl From<MotionError> for FloatingTableError {
    fn from(e: MotionError) -> Self {
        FloatingTableError::Motion(e)
    }
}

impl From<std::io::Error> for FloatingTableError {
    fn from(e: std::io::Error) -> Self {
        FloatingTableError::Io(e)
    }
}

impl SweepResult {
    /// Writes the motion table of the section floating as `floating` (described by
    /// `properties`, e.g. [`crate::motion::MassProperties`]'s line): the excitation table's
    /// header, then `kR,j,heading,re,im` with `xi_j R^e_j / a` for every rigid DOF.
    pub fn write_rao_csv(
        &self,
        floating: &Floating,
        properties: &str,
        out: &mut dyn Write,
    ) -> Result<(), FloatingTableError> {
        let raos = floating.sweep_raos(self)?;
        self.write_header_with_exponents(out)?;
        writeln!(
            out,
            "# values: xi_j R^e_j / a, the motion per unit wave amplitude (rigid DOFs; elastic DOFs held)"
        )?;
        writeln!(out, "# body: floating; {properties}")?;
        self.write_notes(out)?;
        writeln!(out, "kR,j,heading,re,im")?;
        let scale = self.length_scales();
        for (kr, rao) in self.kr.iter().zip(&raos) {
            for (h, heading) in HEADINGS.iter().enumerate().take(rao.ncols()) {
                for j in (0..rao.nrows()).filter(|&j| floating.moves(j)) {
                    let value = rao[(j, h)] * scale[j];
                    writeln!(
                        out,
                        "{kr:e},{},{heading},{:e},{:e}",
                        j + 1,
                        value.re + 0.0,
                        value.im + 0.0
                    )?;
                }
            }
        }
        Ok(())
    }

    /// Writes the mean drift table of the section floating as `floating`: the drift table's
    /// header, then `kR,j,heading,value` with `D_j / (rho g R^e_j)` for every DOF
    /// ([`Floating::sweep_drift`]: rigid sway by the far field with the waves the motion
    /// radiates, the others by pressure integration over the moving section). The header
    /// gives the energy defect of the moving section's waves and the largest difference of
    /// the two methods' horizontal force.
    pub fn write_floating_drift_csv(
        &self,
        floating: &Floating,
        properties: &str,
        out: &mut dyn Write,
    ) -> Result<(), FloatingTableError> {
        let raos = floating.sweep_raos(self)?;
        let drifts = floating.sweep_drift(self)?;
        self.write_header_with_exponents(out)?;
        writeln!(
            out,
            "# values: D_j / (rho g R^e_j), a^2 D_j the mean force of a regular wave of amplitude a"
        )?;
        writeln!(
            out,
            "# body: floating; {properties}; rigid sway by the far field (Maruo) with the waves the \
             motion radiates, the other DOFs by pressure integration over the moving section \
             (roll about the roll reference point's mean position; elastic DOFs held)"
        )?;
        let scale = self.length_scales();
        let mut rows = Vec::new();
        let (mut energy, mut methods, mut largest): (f64, f64, f64) = (0.0, 0.0, 0.0);
        for (((kr, forces), rao), values) in
            self.kr.iter().zip(&self.excitation).zip(&raos).zip(&drifts)
        {
            let Some(drift) = &forces.drift else {
                continue;
            };
            let count = drift.cosines.len().min(rao.ncols());
            for (h, heading) in HEADINGS.iter().enumerate().take(count) {
                let motion: Vec<Complex64> = rao.column(h).iter().copied().collect();
                let (reflected, transmitted) = drift.coefficients_moving(h, &motion);
                energy = energy.max((reflected.norm_sqr() + transmitted.norm_sqr() - 1.0).abs());
                let far = drift.horizontal_far_field_moving(h, &motion);
                let near = drift.near_field_moving(h, &motion);
                methods = methods.max((far - near[near.len() - 1]).abs());
                largest = largest.max(far.abs());
                for j in 0..values.nrows() {
                    rows.push((*kr, j, *heading, values[(j, h)] / scale[j]));
                }
            }
        }
        writeln!(
            out,
            "# energy, |R|^2 + |T|^2 - 1 of the floating section (max over kR of its magnitude; 0 without external damping, which absorbs): {energy:.2e}"
        )?;
        writeln!(
            out,
            "# horizontal force, pressure integration - far field (max over kR, per rho g a^2; the largest is {largest:.3e}): {methods:.2e}"
        )?;
        self.write_notes(out)?;
        writeln!(out, "kR,j,heading,value")?;
        for (kr, j, heading, value) in rows {
            writeln!(out, "{kr:e},{},{heading},{:e}", j + 1, value + 0.0)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
