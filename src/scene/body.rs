//! The scene of a whole body: a ship swept by strip theory or an imported 3D database, its
//! DOFs, band, tolerance, largest step and network form, and the fit of its radiation force.
//!
//! ```text
//! BodyScene --fit--> FittedBody (FitReport, SceneReport, the fit in words)
//! ```
//!
//! * The band is given in kR (`kR = omega^2 R / g`, R = [`BodyScene::band_length`]) or in
//!   rad/s, and cut at the Nyquist frequency `pi / max_step` ([`whole_body::band_and_cut`]).
//! * The DOFs kept are fitted together; the full database stays for the report, which states
//!   what the left-out DOFs would have coupled ([`SceneReport`]).
//! * The fit: every kept DOF at once, with the database's own noise
//!   ([`Database::noise`]); with [`BodyScene::length_unit`] L, in DOF coordinates where a
//!   rotation counts L times its angle ([`identify::fit_in_dof_units`]), so that the fit does
//!   not depend on the unit of length. The form is automatic unless given; the one-DOF forms
//!   need one DOF ([`whole_body::form`]).

use super::whole_body::{self, WholeBodyError};
use super::{Band, SceneReport};
use crate::database::Database;
use crate::identify::{self, FitParams, FitReport};
use crate::network::NetworkForm;
use crate::xml::{format_number, Notation};
use std::time::{Duration, Instant};

/// What a master asks of the FMU of a whole body.
#[derive(Clone, Debug)]
pub struct BodyScene {
    /// The body's data: every DOF swept or imported (SI, at the reference `rho` and `g`).
    pub database: Database,
    /// The DOFs to fit, in this order; `None`: every DOF of the database.
    pub dofs: Option<Vec<String>>,
    /// The band to fit.
    pub band: Band,
    /// The length R of a band given in kR (m).
    pub band_length: f64,
    /// The gravity of a band given in kR (m/s^2).
    pub g: f64,
    /// Tolerance as a fraction of `sqrt(|A_ii A_jj|)`; `None`: 1 %.
    pub tolerance: Option<f64>,
    /// The largest communication step the master will use (s).
    pub max_step: Option<f64>,
    /// Network form; `None`: automatic.
    pub form: Option<NetworkForm>,
    /// Fixed order, or automatic.
    pub order: Option<usize>,
    /// The length L of the fit's DOF coordinates (see the module docs); `None`: SI units.
    pub length_unit: Option<f64>,
    /// What the body is, in a line or more (first lines of the fit in words).
    pub description: String,
    /// Lines appended to the fit in words (e.g. a ship's girder modes' dry properties).
    pub appendix: String,
    /// Wall time of the sweep or import that made the database.
    pub acquisition_time: Duration,
}

/// Every frequency of `database`, its ends widened by a relative 1e-12; `None` without two.
pub fn all_frequencies(database: &Database) -> Option<Band> {
    let (first, last) = (database.omega.first()?, database.omega.last()?);
    Band::rad_per_second(first * (1.0 - 1e-12), last * (1.0 + 1e-12)).ok()
}

impl BodyScene {
    /// A scene of every DOF of `database` over all its frequencies ([`all_frequencies`]),
    /// kR relative to its reference length and gravity, the fit in SI units, tolerance 1 %,
    /// automatic form and order; described by its name.
    pub fn new(database: Database) -> BodyScene {
        BodyScene {
            band: all_frequencies(&database).unwrap_or(Band::RadPerSecond(0.0, 0.0)),
            band_length: database.reference_length,
            g: database.g,
            description: database.name.clone(),
            database,
            dofs: None,
            tolerance: None,
            max_step: None,
            form: None,
            order: None,
            length_unit: None,
            appendix: String::new(),
            acquisition_time: Duration::ZERO,
        }
    }

    /// Checks the scene ([`whole_body`]) and fits the network of its DOFs in its band.
    pub fn fit(self) -> Result<FittedBody, WholeBodyError> {
        whole_body::tolerance(self.tolerance)?;
        let (band, nyquist_cut) =
            whole_body::band_and_cut(self.band, self.band_length, self.g, self.max_step)?;
        let (database, full) = match &self.dofs {
            None => (self.database, None),
            Some(names) => {
                let names: Vec<&str> = names.iter().map(String::as_str).collect();
                let all = &self.database;
                whole_body::dofs(&names, &all.name, &all.dof_names)?;
                let kept = all
                    .select_dofs(&names)
                    .ok_or_else(|| WholeBodyError::UnknownDof {
                        name: names.join(","),
                        body: all.name.clone(),
                        available: all.dof_names.clone(),
                    })?;
                let full = (kept.dof_names.len() < all.dof_names.len()).then(|| all.response());
                (kept, full)
            }
        };
        whole_body::form(self.form, database.dof_names.len())?;
        whole_body::frequencies_in_band(&database, band)?;
        let start = Instant::now();
        let params = FitParams {
            band,
            tolerance: self.tolerance,
            order: self.order,
            form: self.form,
            noise: Some(database.noise.clone()),
            // Sections and ships list their panels; imports (3D) none.
            pole_range_below: identify::pole_range_below(
                database.depth,
                !database.body_panels.is_empty(),
            ),
            ..FitParams::default()
        };
        let response = database.response();
        let fit = match self.length_unit {
            Some(unit) => {
                let factors: Vec<f64> = database
                    .dof_units
                    .iter()
                    .map(|d| unit.powi(i32::from(d.length_exponent)))
                    .collect();
                identify::fit_in_dof_units(&response, &params, &factors)
            }
            None => identify::fit(&response, &params),
        }
        .map_err(|error| WholeBodyError::Fit {
            body: database.name.clone(),
            error,
        })?;
        let fit_time = start.elapsed();
        let report = SceneReport::new(&response, full.as_ref(), &fit, band, nyquist_cut);
        Ok(FittedBody {
            database,
            description: self.description,
            appendix: self.appendix,
            band,
            fit,
            report,
            times: (self.acquisition_time, fit_time),
        })
    }
}

/// A whole body's fit.
#[derive(Clone, Debug)]
pub struct FittedBody {
    /// The database of the fitted DOFs (SI, at the reference `rho` and `g`).
    pub database: Database,
    /// What the body is (first lines of [`FittedBody::fit_text`]).
    pub description: String,
    /// Lines appended to [`FittedBody::fit_text`].
    pub appendix: String,
    /// The band fitted after the Nyquist cut (rad/s).
    pub band: (f64, f64),
    /// The fit.
    pub fit: FitReport,
    /// What the FMU models and leaves out, and the error.
    pub report: SceneReport,
    /// Wall times of the sweep (or import) and of the fit.
    pub times: (Duration, Duration),
}

impl FittedBody {
    /// The fit in words: the description, the DOFs, the band and its frequencies, the
    /// network, the error against the tolerance, the wall times, the notes, the frequencies
    /// left out of the data (`left out: omega = ...`) and the appendix.
    pub fn fit_text(&self) -> String {
        let fit = &self.fit;
        let db = &self.database;
        let mut text = format!(
            "{}\nDOFs {}\nband {:.4} .. {:.4} rad/s ({} of {} frequencies)\n\
             network: {}, order {}, {} states\n\
             largest error {:.3} % of sqrt(|A_ii A_jj|) (tolerance {:.2} %, {})\n\
             {} {:.2} s, fit {:.2} s",
            self.description,
            db.dof_names.join(" "),
            self.band.0,
            self.band.1,
            db.omega
                .iter()
                .filter(|w| **w >= self.band.0 && **w <= self.band.1)
                .count(),
            db.omega.len(),
            fit.network.form,
            fit.order,
            fit.states,
            100.0 * fit.max_relative_error,
            100.0 * fit.tolerance,
            if fit.tolerance_met { "met" } else { "NOT met" },
            if db.body_panels.is_empty() {
                "import"
            } else {
                "sweep"
            },
            self.times.0.as_secs_f64(),
            self.times.1.as_secs_f64(),
        );
        for note in fit.notes.iter().chain(&db.notes) {
            text.push_str(&format!("\nnote: {note}"));
        }
        for (omega, reason) in &db.failures {
            text.push_str(&format!(
                "\nleft out: omega = {} rad/s: {reason}",
                format_number(*omega, Notation::Plain)
            ));
        }
        if !self.appendix.is_empty() {
            text.push('\n');
            text.push_str(self.appendix.trim_end());
        }
        text
    }

    /// The text of the archive's `documentation/scene.txt`: the scene report
    /// ([`SceneReport`]'s lines), a blank line, then the fit in words.
    pub fn scene_text(&self) -> String {
        format!("{}\n\n{}", self.report, self.fit_text())
    }
}

#[cfg(test)]
mod tests;
