//! The sweep's tables (docs/DESIGN.md): the added-mass table `kR,i,j,re,im` and the excitation
//! table `kR,j,heading,re,im`, both nondimensional, with their commented header; and a sweep
//! restricted to some of its DOFs.

use super::{readable, SweepResult};
use crate::bem::{Drift, WaveForces, HEADINGS};
use nalgebra::DMatrix;
use num_complex::Complex64;
use std::io::Write;

/// Which exciting force an excitation table holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExcitationPart {
    /// The total force (Froude-Krylov plus diffraction), by the direct diffraction solve.
    Total,
    /// The Froude-Krylov part alone (the undisturbed incident wave's pressure).
    FroudeKrylov,
}

impl SweepResult {
    /// The same sweep restricted to the DOFs `names`, in that order (for the table of an FMU
    /// that models only some of the hull's DOFs). `None` if a name is not in the sweep.
    pub fn select_dofs(&self, names: &[&str]) -> Option<SweepResult> {
        let index: Vec<usize> = names
            .iter()
            .map(|name| self.dof_names.iter().position(|d| d == name))
            .collect::<Option<_>>()?;
        let n = index.len();
        let square =
            |m: &DMatrix<Complex64>| DMatrix::from_fn(n, n, |i, j| m[(index[i], index[j])]);
        let rows = |m: &DMatrix<Complex64>| DMatrix::from_fn(n, m.ncols(), |i, h| m[(index[i], h)]);
        Some(SweepResult {
            dof_names: index.iter().map(|&i| self.dof_names[i].clone()).collect(),
            added_mass: self.added_mass.iter().map(square).collect(),
            added_mass_inf: DMatrix::from_fn(n, n, |i, j| {
                self.added_mass_inf[(index[i], index[j])]
            }),
            added_mass_zero: DMatrix::from_fn(n, n, |i, j| {
                self.added_mass_zero[(index[i], index[j])]
            }),
            length_exponents: index.iter().map(|&i| self.length_exponents[i]).collect(),
            excitation: self
                .excitation
                .iter()
                .map(|w| WaveForces {
                    haskind: rows(&w.haskind),
                    direct: rows(&w.direct),
                    froude_krylov: rows(&w.froude_krylov),
                    drift: w.drift.as_ref().map(|d| d.select(&index)),
                })
                .collect(),
            excitation_long_wave: index
                .iter()
                .map(|&i| self.excitation_long_wave[i])
                .collect(),
            ..self.clone()
        })
    }

    /// For each DOF, the largest `|Haskind - direct|` over the sweep relative to the largest
    /// direct `|X_j|` (the two exciting-force methods share the mesh but not the right-hand
    /// side, so their difference measures the solver's accuracy). 0 for a DOF that waves do not excite
    /// (largest `|X_j|` below 1e-8 of the largest of all DOFs, such as roll of a circle about
    /// its centre, where both values are rounding noise).
    pub fn haskind_direct_difference(&self) -> Vec<f64> {
        let n = self.dof_names.len();
        let per_dof: Vec<(f64, f64)> = (0..n)
            .map(|j| {
                let (mut largest, mut difference) = (0.0f64, 0.0f64);
                for forces in &self.excitation {
                    for h in 0..forces.haskind.ncols() {
                        largest = largest.max(forces.direct[(j, h)].norm());
                        difference =
                            difference.max((forces.haskind[(j, h)] - forces.direct[(j, h)]).norm());
                    }
                }
                (largest, difference)
            })
            .collect();
        let overall = per_dof.iter().map(|p| p.0).fold(0.0, f64::max);
        per_dof
            .iter()
            .map(|&(largest, difference)| {
                if largest > 1e-8 * overall {
                    difference / largest
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// Writes the excitation table of docs/DESIGN.md: the added-mass table's header lines, the
    /// DOFs' length exponents, then `kR,j,heading,re,im` with `re, im = X_j / (rho g a
    /// R^(1 + e_j))`; the long-wave `kR = 0` rows first, then the frequencies in ascending
    /// order, each with headings 0 and 180 and every DOF.
    pub fn write_excitation_csv(
        &self,
        out: &mut dyn Write,
        part: ExcitationPart,
    ) -> std::io::Result<()> {
        self.write_header_with_exponents(out)?;
        writeln!(
            out,
            "# values: X_j / (rho g a R^(1 + e_j)), a the wave amplitude"
        )?;
        match part {
            ExcitationPart::Total => {
                writeln!(
                    out,
                    "# force: total (Froude-Krylov + diffraction), by the direct diffraction solve"
                )?;
                let difference = self
                    .haskind_direct_difference()
                    .iter()
                    .copied()
                    .fold(0.0, f64::max);
                writeln!(
                    out,
                    "# Haskind relation (max over kR and DOFs of |difference| / max |X_j|): {difference:.2e}"
                )?;
            }
            ExcitationPart::FroudeKrylov => {
                writeln!(out, "# force: Froude-Krylov part (incident wave only)")?
            }
        }
        self.write_notes(out)?;
        // Already nondimensional: a scale of 1 (exact).
        let unit = vec![1.0; self.dof_names.len()];
        let rows = self.kr.iter().zip(&self.excitation).map(|(kr, forces)| {
            let values = match part {
                ExcitationPart::Total => &forces.direct,
                ExcitationPart::FroudeKrylov => &forces.froude_krylov,
            };
            (*kr, values)
        });
        crate::waves::write_excitation_rows(
            out,
            &HEADINGS,
            Some(&self.excitation_long_wave),
            &unit,
            rows,
        )
    }

    /// Writes the fixed section's mean drift table of docs/DESIGN.md: the added-mass table's
    /// header lines, the DOFs' length exponents, then `kR,j,heading,value` with `value = D_j /
    /// (rho g R^e_j)`, `a^2 D_j` the mean force in DOF j in a regular wave of amplitude `a`; the
    /// frequencies in ascending order, each with headings 0 and 180 and every DOF. Frequencies
    /// solved without the drift (oblique waves) are left out.
    pub fn write_drift_csv(&self, out: &mut dyn Write) -> std::io::Result<()> {
        self.write_header_with_exponents(out)?;
        writeln!(
            out,
            "# values: D_j / (rho g R^e_j), a^2 D_j the mean force of a regular wave of amplitude a"
        )?;
        writeln!(
            out,
            "# body: fixed; rigid sway by the far field (Maruo), the other DOFs by pressure integration"
        )?;
        let drifts: Vec<(f64, &Drift)> = self
            .kr
            .iter()
            .zip(&self.excitation)
            .filter_map(|(kr, forces)| forces.drift.as_ref().map(|d| (*kr, d)))
            .collect();
        let largest = drifts
            .iter()
            .flat_map(|(_, d)| d.mean_drift().iter().map(|v| v.abs()).collect::<Vec<_>>())
            .fold(0.0, f64::max);
        let difference = drifts
            .iter()
            .flat_map(|(_, d)| {
                (0..d.cosines.len())
                    .map(|h| (d.horizontal_near_field(h) - d.horizontal_far_field(h)).abs())
                    .collect::<Vec<_>>()
            })
            .fold(0.0, f64::max);
        if largest > 0.0 {
            writeln!(
                out,
                "# horizontal force, pressure integration against far field (max over kR of |difference| / max |D_j|): {:.2e}",
                difference / largest
            )?;
        }
        let energy = drifts
            .iter()
            .flat_map(|(_, d)| {
                (0..d.cosines.len())
                    .map(|h| {
                        (d.reflection(h).norm_sqr() + d.transmission(h).norm_sqr() - 1.0).abs()
                    })
                    .collect::<Vec<_>>()
            })
            .fold(0.0, f64::max);
        writeln!(
            out,
            "# energy, |R|^2 + |T|^2 - 1 of the fixed section (max over kR of its magnitude): {energy:.2e}"
        )?;
        self.write_notes(out)?;
        self.write_drift_rows(out, drifts.iter().map(|(kr, d)| (*kr, d.mean_drift())))
    }

    /// Writes the drift table of a body described by `body` (after `# body: `) with `values`
    /// `(kR, D)`, `D` per `rho g a^2` in SI of each DOF (DOFs x headings 0 and 180): the header
    /// of [`SweepResult::write_drift_csv`] without its fixed-section checks, the notes, then the
    /// rows.
    pub fn write_drift_values(
        &self,
        out: &mut dyn Write,
        body: &str,
        values: &[(f64, DMatrix<f64>)],
    ) -> std::io::Result<()> {
        self.write_header_with_exponents(out)?;
        writeln!(
            out,
            "# values: D_j / (rho g R^e_j), a^2 D_j the mean force of a regular wave of amplitude a"
        )?;
        writeln!(out, "# body: {body}")?;
        self.write_notes(out)?;
        self.write_drift_rows(out, values.iter().cloned())
    }

    /// The column line and the rows `kR,j,heading,value` of `(kR, D)`.
    fn write_drift_rows(
        &self,
        out: &mut dyn Write,
        rows: impl Iterator<Item = (f64, DMatrix<f64>)>,
    ) -> std::io::Result<()> {
        writeln!(out, "kR,j,heading,value")?;
        let scale = self.length_scales();
        for (kr, values) in rows {
            for (h, heading) in HEADINGS.iter().enumerate().take(values.ncols()) {
                for j in 0..values.nrows() {
                    writeln!(
                        out,
                        "{kr:e},{},{heading},{:e}",
                        j + 1,
                        values[(j, h)] / scale[j] + 0.0
                    )?;
                }
            }
        }
        Ok(())
    }

    /// `R^e_j` of every DOF.
    pub(super) fn length_scales(&self) -> Vec<f64> {
        self.length_exponents
            .iter()
            .map(|&e| self.reference_half_beam.powi(i32::from(e)))
            .collect()
    }

    /// [`Self::write_header`], then the DOFs' length exponents (excitation and drift tables).
    pub(super) fn write_header_with_exponents(&self, out: &mut dyn Write) -> std::io::Result<()> {
        self.write_header(out)?;
        let exponents: Vec<String> = self
            .length_exponents
            .iter()
            .map(|e| e.to_string())
            .collect();
        writeln!(out, "# length exponents: {}", exponents.join(" "))
    }

    /// The lines every table starts with: hull, H/R, modes, convention, R, panels.
    fn write_header(&self, out: &mut dyn Write) -> std::io::Result<()> {
        writeln!(out, "# hull: {}", self.hull_name)?;
        if let Some(depth) = self.depth_over_radius {
            writeln!(out, "# H/R: {depth}")?;
        }
        writeln!(out, "# modes: {}", self.dof_names.join(" "))?;
        writeln!(out, "# convention: exp(+i omega t)")?;
        writeln!(out, "# R: {} m", self.reference_half_beam)?;
        writeln!(
            out,
            "# depth: {}",
            self.depth.table_value(self.reference_half_beam)
        )?;
        writeln!(
            out,
            "# panels: {} body, {} lid",
            self.panel_counts.0, self.panel_counts.1
        )
    }

    /// Warnings and failed frequencies, as comment lines.
    pub(super) fn write_notes(&self, out: &mut dyn Write) -> std::io::Result<()> {
        for warning in &self.warnings {
            writeln!(out, "# warning: {warning}")?;
        }
        for (kr, reason) in &self.failures {
            writeln!(out, "# failed: kR = {}: {reason}", readable(*kr))?;
        }
        Ok(())
    }

    /// Writes the coefficient table of docs/DESIGN.md: a commented header, then `kR,i,j,re,im`
    /// with one row per matrix entry, `kR = inf` rows (A_inf), the finite `kR = 0` rows, and the
    /// frequency rows in ascending order.
    pub fn write_csv(&self, out: &mut dyn Write) -> std::io::Result<()> {
        self.write_header(out)?;
        let reciprocity = self
            .reciprocity_residual
            .iter()
            .copied()
            .fold(0.0, f64::max);
        writeln!(
            out,
            "# reciprocity residual (max over kR): {reciprocity:.2e}"
        )?;
        self.write_notes(out)?;
        writeln!(out, "kR,i,j,re,im")?;
        let n = self.dof_names.len();
        for i in 0..n {
            for j in 0..n {
                if let Some(value) = self.added_mass_zero[(i, j)] {
                    writeln!(out, "0,{},{},{:e},0", i + 1, j + 1, value)?;
                }
            }
        }
        for (kr, matrix) in self.kr.iter().zip(&self.added_mass) {
            for i in 0..n {
                for j in 0..n {
                    let z = matrix[(i, j)];
                    writeln!(out, "{kr:e},{},{},{:e},{:e}", i + 1, j + 1, z.re, z.im)?;
                }
            }
        }
        for i in 0..n {
            for j in 0..n {
                let value = self.added_mass_inf[(i, j)];
                writeln!(out, "inf,{},{},{:e},0", i + 1, j + 1, value)?;
            }
        }
        Ok(())
    }
}
