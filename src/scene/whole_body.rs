//! The checks of a whole body's scene (a ship swept by strip theory or an imported 3D
//! database), before its fit: the band cut at the Nyquist frequency `pi / h` of the largest
//! communication step `h`, the tolerance, the DOFs kept, the network form (the one-DOF forms
//! need one DOF) and at least [`MIN_FREQUENCIES`] frequencies in the band.
//!
//! The messages name the command-line options (`--max-step`, `--tol`, `--band`, `--omega`,
//! `--dofs`, `--form`) that `fmu-pack` gives these values by.

use super::Band;
use crate::database::Database;
use crate::identify::IdentifyError;
use crate::network::NetworkForm;
use std::fmt;

/// The fewest frequencies of the data inside the band that a fit accepts.
pub const MIN_FREQUENCIES: usize = 3;

/// Why a whole body's scene was refused, or its fit failed.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum WholeBodyError {
    /// The largest step is not finite and > 0 (s).
    InvalidMaxStep(f64),
    /// The Nyquist frequency of the largest step leaves (almost) nothing of the band.
    BandAboveNyquist {
        /// The step (s).
        max_step: f64,
        /// Its Nyquist frequency `pi / max_step` (rad/s).
        nyquist: f64,
        /// The band before the cut (rad/s).
        band: (f64, f64),
    },
    /// The band is empty or not finite.
    EmptyBand(Band),
    /// The tolerance is not finite and > 0.
    InvalidTolerance(f64),
    /// The band holds fewer than [`MIN_FREQUENCIES`] of the data's frequencies.
    TooFewFrequencies {
        /// The band (rad/s).
        band: (f64, f64),
        /// The data's frequencies inside it.
        inside: usize,
        /// The data's first and last frequency (rad/s) and their count.
        data: (f64, f64, usize),
        /// Whether the frequencies were chosen (a sweep: `--omega`) rather than read.
        chosen: bool,
    },
    /// A DOF asked for is not the body's, or is named twice.
    UnknownDof {
        /// The DOF asked for.
        name: String,
        /// The body.
        body: String,
        /// The body's DOFs.
        available: Vec<String>,
    },
    /// A one-DOF network form asked for several DOFs.
    FormNeedsOneDof {
        /// The form.
        form: NetworkForm,
        /// The DOFs to fit.
        dofs: usize,
    },
    /// The fit failed.
    Fit {
        /// The body.
        body: String,
        /// Why.
        error: IdentifyError,
    },
}

impl fmt::Display for WholeBodyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WholeBodyError::InvalidMaxStep(h) => {
                write!(f, "--max-step {h}: the step must be finite and > 0 s")
            }
            WholeBodyError::BandAboveNyquist {
                max_step,
                nyquist,
                band: (lo, hi),
            } => write!(
                f,
                "--max-step {max_step}: its Nyquist frequency pi/h = {nyquist:.4} rad/s leaves \
                 nothing of the band {lo:.4} .. {hi:.4} rad/s"
            ),
            WholeBodyError::EmptyBand(band) => write!(
                f,
                "--band {band:?}: the band is empty; need 0 <= MIN < MAX, both finite"
            ),
            WholeBodyError::InvalidTolerance(t) => {
                write!(f, "--tol {t}: the tolerance must be finite and > 0")
            }
            WholeBodyError::TooFewFrequencies {
                band: (lo, hi),
                inside,
                data: (first, last, count),
                chosen,
            } => write!(
                f,
                "the band {lo:.4} .. {hi:.4} rad/s holds {inside} of the {count} frequencies \
                 ({first:.4} .. {last:.4} rad/s); at least {MIN_FREQUENCIES} are needed \
                 (--band{})",
                if *chosen { ", --omega" } else { "" }
            ),
            WholeBodyError::UnknownDof {
                name,
                body,
                available,
            } => write!(
                f,
                "--dofs: '{name}' is not a DOF of {body} or is named twice; its DOFs: {}",
                available.join(" ")
            ),
            WholeBodyError::FormNeedsOneDof { form, dofs } => write!(
                f,
                "--form {form}: a one-DOF form, and the body has {dofs} DOFs to fit; use \
                 --form coupled, or keep one DOF with --dofs"
            ),
            WholeBodyError::Fit { body, error } => write!(f, "{body}: the fit failed: {error}"),
        }
    }
}

impl std::error::Error for WholeBodyError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            WholeBodyError::Fit { error, .. } => Some(error),
            _ => None,
        }
    }
}

/// The band to fit in rad/s (kR with R = `reference_length`, or rad/s), cut at the Nyquist
/// frequency pi / h of the largest communication step `max_step` h, and that frequency when
/// it cut the band. Refused when the step is not finite and > 0, or when pi / h is at most
/// 1.5 times the band's lower end.
pub fn band_and_cut(
    band: Band,
    reference_length: f64,
    g: f64,
    max_step: Option<f64>,
) -> Result<((f64, f64), Option<f64>), WholeBodyError> {
    let band = band
        .checked()
        .map_err(|_| WholeBodyError::EmptyBand(band))?;
    let (lo, hi) = band.to_rad_per_second(reference_length, g);
    let Some(h) = max_step else {
        return Ok(((lo, hi), None));
    };
    if !(h.is_finite() && h > 0.0) {
        return Err(WholeBodyError::InvalidMaxStep(h));
    }
    let nyquist = std::f64::consts::PI / h;
    if nyquist <= lo * 1.5 {
        return Err(WholeBodyError::BandAboveNyquist {
            max_step: h,
            nyquist,
            band: (lo, hi),
        });
    }
    Ok(if nyquist < hi {
        ((lo, nyquist), Some(nyquist))
    } else {
        ((lo, hi), None)
    })
}

/// [`band_and_cut`] without the cut frequency.
pub fn band(
    band: Band,
    reference_length: f64,
    g: f64,
    max_step: Option<f64>,
) -> Result<(f64, f64), WholeBodyError> {
    band_and_cut(band, reference_length, g, max_step).map(|(band, _)| band)
}

/// Refuses a tolerance that is not finite and > 0 (`None`: the fit's default).
pub fn tolerance(tolerance: Option<f64>) -> Result<(), WholeBodyError> {
    match tolerance {
        Some(t) if !(t.is_finite() && t > 0.0) => Err(WholeBodyError::InvalidTolerance(t)),
        _ => Ok(()),
    }
}

/// Refuses the DOFs `names` unless each is one of `available` (the DOFs of `body`) and named
/// once.
pub fn dofs(names: &[&str], body: &str, available: &[String]) -> Result<(), WholeBodyError> {
    for (k, name) in names.iter().enumerate() {
        if !available.iter().any(|d| d == name) || names[..k].contains(name) {
            return Err(WholeBodyError::UnknownDof {
                name: (*name).to_string(),
                body: body.to_string(),
                available: available.to_vec(),
            });
        }
    }
    Ok(())
}

/// Refuses a one-DOF network form (series chain, parallel bank) for more than one DOF.
pub fn form(form: Option<NetworkForm>, dofs: usize) -> Result<(), WholeBodyError> {
    match form {
        Some(f) if f.is_single_dof() && dofs > 1 => {
            Err(WholeBodyError::FormNeedsOneDof { form: f, dofs })
        }
        _ => Ok(()),
    }
}

/// The number of the database's frequencies inside `band` (rad/s, ends included); refused
/// below [`MIN_FREQUENCIES`]. The message suggests `--omega` for a ship (whose database
/// has panels), whose frequencies are chosen.
pub fn frequencies_in_band(database: &Database, band: (f64, f64)) -> Result<usize, WholeBodyError> {
    let (lo, hi) = band;
    let inside = database
        .omega
        .iter()
        .filter(|w| **w >= lo && **w <= hi)
        .count();
    if inside < MIN_FREQUENCIES {
        return Err(WholeBodyError::TooFewFrequencies {
            band,
            inside,
            data: (
                database.omega.first().copied().unwrap_or(f64::NAN),
                database.omega.last().copied().unwrap_or(f64::NAN),
                database.omega.len(),
            ),
            chosen: !database.body_panels.is_empty(),
        });
    }
    Ok(inside)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::database::import::{self, ImportParams};
    use std::path::Path;

    fn sphere() -> Database {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/wamit/sphere.1");
        import::import(&path, &ImportParams::new()).unwrap()
    }

    #[test]
    fn the_band_is_cut_at_the_nyquist_frequency() {
        let given = Band::rad_per_second(0.5, 10.0).unwrap();
        assert_eq!(band(given, 1.0, 9.81, None), Ok((0.5, 10.0)));
        assert_eq!(
            band_and_cut(given, 1.0, 9.81, Some(0.1)),
            Ok(((0.5, 10.0), None))
        );
        let ((lo, hi), cut) = band_and_cut(given, 1.0, 9.81, Some(1.0)).unwrap();
        assert_eq!(lo, 0.5);
        assert!((hi - std::f64::consts::PI).abs() < 1e-15);
        assert_eq!(cut, Some(hi));
        // pi / 5 = 0.628 <= 1.5 * 0.5: nothing left.
        let e = band(given, 1.0, 9.81, Some(5.0)).unwrap_err();
        assert!(matches!(e, WholeBodyError::BandAboveNyquist { max_step, .. } if max_step == 5.0));
        assert!(
            e.to_string()
                .starts_with("--max-step 5: its Nyquist frequency pi/h = 0.6283"),
            "{e}"
        );
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = band(given, 1.0, 9.81, Some(bad)).unwrap_err();
            assert!(matches!(e, WholeBodyError::InvalidMaxStep(_)), "{e}");
            assert!(
                e.to_string().ends_with("the step must be finite and > 0 s"),
                "{e}"
            );
        }
        let empty = Band::RadPerSecond(2.0, 1.0);
        let e = band(empty, 1.0, 9.81, None).unwrap_err();
        assert_eq!(e, WholeBodyError::EmptyBand(empty));
    }

    #[test]
    fn the_tolerance_must_be_finite_and_positive() {
        assert_eq!(tolerance(None), Ok(()));
        assert_eq!(tolerance(Some(0.01)), Ok(()));
        for bad in [0.0, -0.1, f64::NAN] {
            let e = tolerance(Some(bad)).unwrap_err();
            assert!(matches!(e, WholeBodyError::InvalidTolerance(_)), "{e}");
            assert!(
                e.to_string()
                    .ends_with("the tolerance must be finite and > 0"),
                "{e}"
            );
        }
    }

    #[test]
    fn the_dofs_must_be_the_bodys_and_named_once() {
        let available: Vec<String> = ["surge", "heave"].map(String::from).to_vec();
        assert_eq!(dofs(&["heave", "surge"], "sphere", &available), Ok(()));
        for bad in [&["roll"][..], &["heave", "heave"][..]] {
            let e = dofs(bad, "sphere", &available).unwrap_err();
            assert!(
                e.to_string()
                    .ends_with("is not a DOF of sphere or is named twice; its DOFs: surge heave"),
                "{e}"
            );
        }
    }

    #[test]
    fn the_one_dof_forms_are_refused_for_several_dofs() {
        assert_eq!(form(None, 6), Ok(()));
        assert_eq!(form(Some(NetworkForm::Coupled), 6), Ok(()));
        assert_eq!(form(Some(NetworkForm::SeriesChain), 1), Ok(()));
        let e = form(Some(NetworkForm::ParallelBank), 3).unwrap_err();
        assert_eq!(
            e,
            WholeBodyError::FormNeedsOneDof {
                form: NetworkForm::ParallelBank,
                dofs: 3
            }
        );
        assert!(
            e.to_string()
                .starts_with("--form parallel_bank: a one-DOF form, and the body has 3 DOFs"),
            "{e}"
        );
    }

    #[test]
    fn at_least_three_frequencies_are_in_the_band() {
        let database = sphere();
        let omega = database.omega.clone();
        assert!(omega.len() >= MIN_FREQUENCIES);
        let all = (omega[0], omega[omega.len() - 1]);
        assert_eq!(frequencies_in_band(&database, all), Ok(omega.len()));
        let two = (omega[0], omega[1]);
        let e = frequencies_in_band(&database, two).unwrap_err();
        assert!(matches!(
            e,
            WholeBodyError::TooFewFrequencies {
                inside: 2,
                chosen: false,
                ..
            }
        ));
        assert!(e.to_string().contains("holds 2 of the"), "{e}");
        // An imported database's frequencies are the file's: no --omega.
        assert!(
            e.to_string().ends_with("at least 3 are needed (--band)"),
            "{e}"
        );
    }
}
