//! A whole-body hydrodynamic database in SI: what a ship's strip theory computes and what an
//! imported 3D database (WAMIT, Capytaine) holds, in the product's conventions (docs/DESIGN.md,
//! "Ships and imported 3D databases"):
//!
//! - complex added mass `A~_ij(omega) = a_ij(omega) - i b_ij(omega) / omega` (kg, kg m,
//!   kg m^2), time factor `exp(+i omega t)`, and its infinite-frequency limit `A_inf`;
//! - exciting force `X_j(omega, beta)` per unit wave amplitude (N/m, N m/m), the wave
//!   `eta = a cos(omega t - k (x cos beta + y sin beta))`;
//! - hydrostatic restoring `C_ij` (buoyancy part, N/m, N, N m).
//!
//! The tables written from it are those of docs/DESIGN.md; [`Database::response`] is what the
//! identification fits.

pub mod added_mass_inf;
pub mod capytaine;
pub mod import;
pub mod irregular;
pub mod section;
pub mod wamit;

use crate::fmu::DofUnit;
use crate::units::WaterDepth;
use crate::xml::{format_number, Notation};
use nalgebra::DMatrix;
use num_complex::Complex64;
use std::io::Write;

/// Whole-body coefficients in SI (docs/DESIGN.md, "Ships and imported 3D databases").
#[derive(Clone, Debug)]
pub struct Database {
    /// Body name (the ship's, or the imported file's stem).
    pub name: String,
    /// Where the numbers come from, in words (shown in the tables' headers).
    pub source: String,
    /// DOF names.
    pub dof_names: Vec<String>,
    /// Each DOF's unit: a length (exponent 0), an angle (rad) or a mode amplitude.
    pub dof_units: Vec<DofUnit>,
    /// Water density used, kg/m^3.
    pub rho: f64,
    /// Gravity used, m/s^2.
    pub g: f64,
    /// The frequencies computed, rad/s, ascending.
    pub omega: Vec<f64>,
    /// `A~_rs(omega)` in SI (kg, kg m, kg m^2), `Im = -b/omega`.
    pub added_mass: Vec<DMatrix<Complex64>>,
    /// `A_inf` in SI.
    pub added_mass_inf: DMatrix<f64>,
    /// Headings of the excitation columns, degrees.
    pub headings: Vec<f64>,
    /// Exciting force per unit wave amplitude (N/m, N m/m), one column per heading (a ship:
    /// the zero-speed Salvesen-Tuck-Faltinsen force). Empty when the source gives none.
    pub excitation: Vec<DMatrix<Complex64>>,
    /// The Froude-Krylov part of the same; empty when the source gives none.
    pub froude_krylov: Vec<DMatrix<Complex64>>,
    /// The long-wave limit of the exciting force per unit amplitude (`omega -> 0`, every
    /// heading): `rho g integral n_j dS`, the hydrostatic pressure of the wave's crest; `None`
    /// when unknown.
    pub excitation_long_wave: Option<Vec<f64>>,
    /// Hydrostatic restoring (N/m, N, N m), buoyancy part (docs/DESIGN.md).
    pub stiffness_hydrostatic: DMatrix<f64>,
    /// Reference length R of the excitation table's `kR` (a ship: the largest section
    /// half-beam; an import: ULEN; a section's 1 m slice: 1), m.
    pub reference_length: f64,
    /// Frequencies that failed, with the reason.
    pub failures: Vec<(f64, String)>,
    /// Physics sanity warnings.
    pub warnings: Vec<String>,
    /// What an import left out, estimated or assumed, one line each (for the reports).
    pub notes: Vec<String>,
    /// The data's own noise, per entry (SI): the largest reciprocity gap
    /// `|A~_ij - A~_ji| / 2` over the frequencies kept, before `A~` was made symmetric; zero
    /// where the source is reciprocal by construction (sections, ships). The fit is judged
    /// against no less than this ([`crate::identify`]).
    pub noise: DMatrix<f64>,
    /// Body panels of each distinct section (finest level); empty for an imported database.
    pub body_panels: Vec<usize>,
    /// Mean wave drift per unit wave amplitude squared at each frequency (`a^2 D_j` the mean
    /// force in DOF j of a regular wave of amplitude a; N/m^2, N m/m^2), one column per
    /// [`Database::drift_headings`]. Empty when the source gives none.
    pub drift: Vec<DMatrix<f64>>,
    /// The headings of [`Database::drift`]'s columns, degrees.
    pub drift_headings: Vec<f64>,
    /// The water depth the coefficients are for (deep water unless the source says otherwise:
    /// a Capytaine dataset's `water_depth`, a ship's depth, `--water-depth` for WAMIT files).
    /// Every table written states it (`# depth:`).
    pub depth: WaterDepth,
}

/// Most wave headings of one database (the FMU's excitation table's limit).
pub const MAX_HEADINGS: usize = crate::waves::MAX_HEADINGS;

/// An imported file that cannot be used: which file, which line (when one), and why.
pub type DatabaseError = crate::input::FileError;

/// Keeps the entries of `v` whose flag in `keep` is true (`v` and `keep` of one length; a
/// `v` of another length, an absent table, is left as it is).
fn retain_flagged<T>(v: &mut Vec<T>, keep: &[bool]) {
    if v.len() == keep.len() {
        let mut flags = keep.iter();
        v.retain(|_| flags.next().copied().unwrap_or(true));
    }
}

fn readable(x: f64) -> String {
    format_number(x, Notation::Plain)
}

impl Database {
    /// The first table holding a non-finite number, by name; `None` when all are finite.
    pub fn first_non_finite(&self) -> Option<&'static str> {
        let complex =
            |m: &DMatrix<Complex64>| m.iter().all(|z| z.re.is_finite() && z.im.is_finite());
        if !self.omega.iter().all(|w| w.is_finite()) {
            Some("a frequency")
        } else if !self.added_mass.iter().all(complex) {
            Some("the added mass or damping")
        } else if !self.added_mass_inf.iter().all(|x| x.is_finite()) {
            Some("A_inf")
        } else if !(self.excitation.iter().all(complex) && self.froude_krylov.iter().all(complex)) {
            Some("the exciting force")
        } else if !self
            .excitation_long_wave
            .iter()
            .flatten()
            .all(|x| x.is_finite())
        {
            Some("the long-wave exciting force")
        } else if !self.stiffness_hydrostatic.iter().all(|x| x.is_finite()) {
            Some("the hydrostatic restoring")
        } else if !self.drift.iter().all(|m| m.iter().all(|x| x.is_finite())) {
            Some("the mean drift")
        } else {
            None
        }
    }

    /// The added mass in SI as the identification takes it.
    pub fn response(&self) -> crate::FrequencyResponse {
        crate::FrequencyResponse {
            dof_names: self.dof_names.clone(),
            omega: self.omega.clone(),
            added_mass: self.added_mass.clone(),
            added_mass_inf: self.added_mass_inf.clone(),
            rho: self.rho,
            g: self.g,
        }
    }

    /// The same sweep restricted to the DOFs `names`, in that order; `None` if a name is not
    /// in the sweep.
    pub fn select_dofs(&self, names: &[&str]) -> Option<Database> {
        let index: Vec<usize> = names
            .iter()
            .map(|name| self.dof_names.iter().position(|d| d == name))
            .collect::<Option<_>>()?;
        let n = index.len();
        let square_c =
            |m: &DMatrix<Complex64>| DMatrix::from_fn(n, n, |i, j| m[(index[i], index[j])]);
        let rows = |m: &DMatrix<Complex64>| DMatrix::from_fn(n, m.ncols(), |i, h| m[(index[i], h)]);
        Some(Database {
            dof_names: index.iter().map(|&i| self.dof_names[i].clone()).collect(),
            added_mass: self.added_mass.iter().map(square_c).collect(),
            added_mass_inf: DMatrix::from_fn(n, n, |i, j| {
                self.added_mass_inf[(index[i], index[j])]
            }),
            excitation: self.excitation.iter().map(rows).collect(),
            froude_krylov: self.froude_krylov.iter().map(rows).collect(),
            excitation_long_wave: self
                .excitation_long_wave
                .as_ref()
                .map(|x| index.iter().map(|&i| x[i]).collect()),
            stiffness_hydrostatic: DMatrix::from_fn(n, n, |i, j| {
                self.stiffness_hydrostatic[(index[i], index[j])]
            }),
            noise: DMatrix::from_fn(n, n, |i, j| self.noise[(index[i], index[j])]),
            drift: self
                .drift
                .iter()
                .map(|m| DMatrix::from_fn(n, m.ncols(), |i, h| m[(index[i], h)]))
                .collect(),
            dof_units: index.iter().map(|&i| self.dof_units[i].clone()).collect(),
            ..self.clone()
        })
    }

    /// The exciting force as the FMU's excitation table (`crate::waves::ExcitationTable`):
    /// `kR,j,heading,re,im` with `kR = omega^2 R / g` and `X_j / (rho g a R^(1 + e_j))`,
    /// R = [`Database::reference_length`]; the long-wave rows first.
    ///
    /// # Errors
    /// The writer's.
    pub fn write_excitation_table(&self, out: &mut dyn Write) -> std::io::Result<()> {
        let r = self.reference_length;
        self.fmu_table_header(out, "X_j / (rho g a R^(1 + e_j)), a the wave amplitude")?;
        let scale: Vec<f64> = self
            .dof_units
            .iter()
            .map(|u| self.rho * self.g * r.powi(1 + i32::from(u.length_exponent)))
            .collect();
        let rows = self
            .omega
            .iter()
            .zip(&self.excitation)
            .map(|(omega, forces)| (crate::units::kr_from_omega(*omega, r, self.g), forces));
        crate::waves::write_excitation_rows(
            out,
            &self.headings,
            self.excitation_long_wave.as_deref(),
            &scale,
            rows,
        )
    }

    /// The mean drift as the FMU's drift table (`crate::waves::DriftTable`): the excitation
    /// table's header, then `kR,j,heading,value` with `kR = omega^2 R / g` and
    /// `value = D_j / (rho g R^e_j)`, R = [`Database::reference_length`]; nothing when the
    /// database has no drift.
    ///
    /// # Errors
    /// The writer's.
    pub fn write_drift_table(&self, out: &mut dyn Write) -> std::io::Result<()> {
        let r = self.reference_length;
        self.fmu_table_header(
            out,
            "D_j / (rho g R^e_j), a^2 D_j the mean force of a regular wave of amplitude a",
        )?;
        writeln!(out, "kR,j,heading,value")?;
        let number = |x: f64| format_number(x, Notation::Scientific);
        for (omega, drift) in self.omega.iter().zip(&self.drift) {
            let kr = crate::units::kr_from_omega(*omega, r, self.g);
            for (h, heading) in self.drift_headings.iter().enumerate() {
                for (j, unit) in self.dof_units.iter().enumerate() {
                    let scale = self.rho * self.g * r.powi(i32::from(unit.length_exponent));
                    writeln!(
                        out,
                        "{},{},{},{}",
                        number(kr),
                        j + 1,
                        number(*heading),
                        number(drift[(j, h)] / scale)
                    )?;
                }
            }
        }
        Ok(())
    }

    /// The header of a table the FMU reads (excitation, drift): hull, modes, convention, R,
    /// length exponents, and what the values are (`values`; whole body, the source).
    fn fmu_table_header(&self, out: &mut dyn Write, values: &str) -> std::io::Result<()> {
        writeln!(out, "# hull: {}", self.name)?;
        writeln!(out, "# modes: {}", self.dof_names.join(" "))?;
        writeln!(out, "# convention: exp(+i omega t)")?;
        writeln!(out, "# R: {} m", self.reference_length)?;
        let exponents: Vec<String> = self
            .dof_units
            .iter()
            .map(|u| u.length_exponent.to_string())
            .collect();
        writeln!(out, "# length exponents: {}", exponents.join(" "))?;
        writeln!(
            out,
            "# depth: {}",
            self.depth.table_value(self.reference_length)
        )?;
        writeln!(out, "# values: {values}; whole body, {}", self.source)
    }

    fn header(&self, out: &mut dyn Write) -> std::io::Result<()> {
        writeln!(out, "# hull: {}", self.name)?;
        writeln!(out, "# modes: {}", self.dof_names.join(" "))?;
        writeln!(out, "# convention: exp(+i omega t)")?;
        writeln!(out, "# units: SI")?;
        writeln!(out, "# rho: {} kg/m^3", readable(self.rho))?;
        writeln!(out, "# g: {} m/s^2", readable(self.g))?;
        match self.depth {
            WaterDepth::Infinite => writeln!(out, "# depth: inf"),
            WaterDepth::Finite(h) => writeln!(out, "# depth: {} m", readable(h)),
        }
    }

    /// The added-mass table of docs/DESIGN.md ("Ships"): `omega,i,j,re,im`, `omega = inf` rows
    /// for `A_inf`, then one block per frequency.
    ///
    /// # Errors
    /// The writer's.
    pub fn write_csv(&self, out: &mut dyn Write) -> std::io::Result<()> {
        self.header(out)?;
        writeln!(out, "omega,i,j,re,im")?;
        let n = self.dof_names.len();
        let number = |x: f64| format_number(x, Notation::Scientific);
        for i in 0..n {
            for j in 0..n {
                writeln!(
                    out,
                    "inf,{},{},{},0",
                    i + 1,
                    j + 1,
                    number(self.added_mass_inf[(i, j)])
                )?;
            }
        }
        for (omega, a) in self.omega.iter().zip(&self.added_mass) {
            for i in 0..n {
                for j in 0..n {
                    let z = a[(i, j)];
                    writeln!(
                        out,
                        "{},{},{},{},{}",
                        number(*omega),
                        i + 1,
                        j + 1,
                        number(z.re),
                        number(z.im)
                    )?;
                }
            }
        }
        Ok(())
    }

    /// The excitation table: `omega,j,heading,re,im`, `X_j` per unit wave amplitude in SI.
    ///
    /// # Errors
    /// The writer's.
    pub fn write_excitation_csv(&self, out: &mut dyn Write) -> std::io::Result<()> {
        self.header(out)?;
        writeln!(out, "omega,j,heading,re,im")?;
        let number = |x: f64| format_number(x, Notation::Scientific);
        for (omega, x) in self.omega.iter().zip(&self.excitation) {
            for j in 0..self.dof_names.len() {
                for (h, heading) in self.headings.iter().enumerate() {
                    let z = x[(j, h)];
                    writeln!(
                        out,
                        "{},{},{},{},{}",
                        number(*omega),
                        j + 1,
                        number(*heading),
                        number(z.re),
                        number(z.im)
                    )?;
                }
            }
        }
        Ok(())
    }

    /// The mean drift as CSV: the header, then `omega,j,heading,value` with `value = D_j` in
    /// SI (`a^2 D_j` the mean force of a regular wave of amplitude a; N/m^2, N m/m^2).
    ///
    /// # Errors
    /// The writer's.
    pub fn write_drift_csv(&self, out: &mut dyn Write) -> std::io::Result<()> {
        self.header(out)?;
        writeln!(out, "omega,j,heading,value")?;
        let number = |x: f64| format_number(x, Notation::Scientific);
        for (omega, d) in self.omega.iter().zip(&self.drift) {
            for j in 0..self.dof_names.len() {
                for (h, heading) in self.drift_headings.iter().enumerate() {
                    writeln!(
                        out,
                        "{},{},{},{}",
                        number(*omega),
                        j + 1,
                        number(*heading),
                        number(d[(j, h)])
                    )?;
                }
            }
        }
        Ok(())
    }

    /// The restoring as the FMU's table ([`crate::hydrostatics::Table`]): `C / (rho g)`.
    pub fn hydrostatics_table(&self) -> crate::hydrostatics::Table {
        crate::hydrostatics::Table {
            modes: self.dof_names.clone(),
            stiffness_per_rho_g: &self.stiffness_hydrostatic / (self.rho * self.g),
        }
    }

    /// The hydrostatic restoring as CSV: `i,j,c`.
    ///
    /// # Errors
    /// The writer's.
    pub fn write_hydrostatics_csv(&self, out: &mut dyn Write) -> std::io::Result<()> {
        self.header(out)?;
        writeln!(out, "i,j,c")?;
        let n = self.dof_names.len();
        for i in 0..n {
            for j in 0..n {
                writeln!(
                    out,
                    "{},{},{}",
                    i + 1,
                    j + 1,
                    format_number(self.stiffness_hydrostatic[(i, j)], Notation::Scientific)
                )?;
            }
        }
        Ok(())
    }
}
