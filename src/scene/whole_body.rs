//! The checks of a whole body's scene (a ship swept by strip theory or an imported 3D
//! database), before its fit: the band cut at the Nyquist frequency of the largest
//! communication step, the tolerance, and at least [`MIN_FREQUENCIES`] frequencies in the band.
//!
//! The messages name the command-line options (`--max-step`, `--tol`, `--band`, `--omega`)
//! that `fmu-pack` gives these values by.

use super::Band;
use crate::database::Database;
use std::fmt;

/// The fewest frequencies of the data inside the band that a fit accepts.
pub const MIN_FREQUENCIES: usize = 3;

/// Why a whole body's scene was refused.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WholeBodyError(pub String);

impl fmt::Display for WholeBodyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for WholeBodyError {}

/// The band to fit in rad/s (kR with R = `reference_length`, or rad/s), cut at the Nyquist
/// frequency pi / h of the largest communication step `max_step` h. Refused when the step is
/// not finite and > 0, or when pi / h is at most 1.5 times the band's lower end.
pub fn band(
    band: Band,
    reference_length: f64,
    g: f64,
    max_step: Option<f64>,
) -> Result<(f64, f64), WholeBodyError> {
    let (lo, mut hi) = band.to_rad_per_second(reference_length, g);
    if let Some(h) = max_step {
        if !(h.is_finite() && h > 0.0) {
            return Err(WholeBodyError(format!(
                "--max-step {h}: the step must be finite and > 0 s"
            )));
        }
        let nyquist = std::f64::consts::PI / h;
        if nyquist <= lo * 1.5 {
            return Err(WholeBodyError(format!(
                "--max-step {h}: its Nyquist frequency pi/h = {nyquist:.4} rad/s leaves nothing \
                 of the band {lo:.4} .. {hi:.4} rad/s"
            )));
        }
        hi = hi.min(nyquist);
    }
    Ok((lo, hi))
}

/// Refuses a tolerance that is not finite and > 0 (`None`: the fit's default).
pub fn tolerance(tolerance: Option<f64>) -> Result<(), WholeBodyError> {
    match tolerance {
        Some(t) if !(t.is_finite() && t > 0.0) => Err(WholeBodyError(format!(
            "--tol {t}: the tolerance must be finite and > 0"
        ))),
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
        return Err(WholeBodyError(format!(
            "the band {lo:.4} .. {hi:.4} rad/s holds {inside} of the {} frequencies ({:.4} .. \
             {:.4} rad/s); at least 3 are needed (--band{})",
            database.omega.len(),
            database.omega.first().copied().unwrap_or(f64::NAN),
            database.omega.last().copied().unwrap_or(f64::NAN),
            if database.body_panels.is_empty() {
                ""
            } else {
                ", --omega"
            }
        )));
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
        let (lo, hi) = band(given, 1.0, 9.81, Some(1.0)).unwrap();
        assert_eq!(lo, 0.5);
        assert!((hi - std::f64::consts::PI).abs() < 1e-15);
        // pi / 5 = 0.628 <= 1.5 * 0.5: nothing left.
        let e = band(given, 1.0, 9.81, Some(5.0)).unwrap_err();
        assert!(
            e.0.starts_with("--max-step 5: its Nyquist frequency pi/h = 0.6283"),
            "{e}"
        );
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = band(given, 1.0, 9.81, Some(bad)).unwrap_err();
            assert!(e.0.ends_with("the step must be finite and > 0 s"), "{e}");
        }
    }

    #[test]
    fn the_tolerance_must_be_finite_and_positive() {
        assert_eq!(tolerance(None), Ok(()));
        assert_eq!(tolerance(Some(0.01)), Ok(()));
        for bad in [0.0, -0.1, f64::NAN] {
            let e = tolerance(Some(bad)).unwrap_err();
            assert!(e.0.ends_with("the tolerance must be finite and > 0"), "{e}");
        }
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
        assert!(e.0.contains("holds 2 of the"), "{e}");
        // An imported database's frequencies are the file's: no --omega.
        assert!(e.0.ends_with("at least 3 are needed (--band)"), "{e}");
    }
}
