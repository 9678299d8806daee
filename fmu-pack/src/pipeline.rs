//! The library's scene pipeline on the command line: the band as typed, progress on the
//! terminal, timings, warnings and notes on standard error, and the messages that name the
//! command-line options.
//!
//! Frequencies are requested in the nondimensional `kR = omega^2 R / g` or in rad/s; the
//! network is fitted and stored in SI units for the reference `rho` and `g`, and the FMU
//! rescales it exactly to the `rho` and `g` a master sets (see [`hydrofmu::scene`]).

use crate::progress::Progress;
use hydrofmu::identify::FitReport;
use hydrofmu::panels::{PanelError, MAX_BODY_PANELS};
use hydrofmu::scene::{Band, BuiltScene, Scene, SceneError, SceneReport, SceneResponse};
use hydrofmu::sweep::{SizeLimit, SweepError, SweepResult};
use std::time::{Duration, Instant};

/// Parses a band as `--band` gives it: `MIN:MAX` (kR) or `MIN:MAXrad/s` (rad/s).
pub fn parse_band(text: &str) -> Result<Band, String> {
    let (body, rad) = match text.trim().strip_suffix("rad/s") {
        Some(body) => (body, true),
        None => (text.trim(), false),
    };
    let (min, max) = crate::hull_arg::parse_range(body, "--band")?;
    let band = if rad {
        Band::rad_per_second(min, max)
    } else {
        Band::kr(min, max)
    };
    band.map_err(|_| {
        format!("--band '{text}': the band is empty; need 0 <= MIN < MAX, both finite")
    })
}

/// A scene error in the words of the command line (the options it names).
pub fn message(error: SceneError) -> String {
    match error {
        SceneError::InvalidTolerance(t) => {
            format!("--tol {t}: the tolerance must be finite and > 0")
        }
        SceneError::InvalidMaxStep(h) => {
            format!("--max-step {h}: the step must be finite and > 0 s")
        }
        SceneError::BandAboveNyquist {
            max_step: h,
            nyquist,
            band: (lo, hi),
        } => format!(
            "--max-step {h} s: its Nyquist frequency pi/h = {nyquist:.4} rad/s leaves nothing \
             of the band {lo:.4} .. {hi:.4} rad/s; use a smaller step or a lower band"
        ),
        SceneError::Sweep(e) => sweep_message(&e),
        other => other.to_string(),
    }
}

/// A sweep error in the words of the command line: a size limit names its option.
pub fn sweep_message(error: &SweepError) -> String {
    match error {
        SweepError::TooLarge { limit, requested } => {
            let option = match limit {
                SizeLimit::Frequencies => "--kr COUNT",
                SizeLimit::ExtrapolationLevels => "--levels",
                SizeLimit::Threads => "--threads",
                _ => "--kr COUNT and --dofs",
            };
            format!(
                "{option} {requested}: at most {} {} ({})",
                limit.max(),
                limit.quantity(),
                limit.reason()
            )
        }
        SweepError::Threads { threads: 0, .. } => "--threads 0: at least 1 is needed".into(),
        SweepError::NoLevels => "--levels 0: at least 1 is needed".into(),
        SweepError::Mesh(PanelError::TooManyPanels { requested }) => format!(
            "--panels {requested}: at most {MAX_BODY_PANELS} (the dense panel system needs \
             memory growing as N^2 and time as N^3: about 7 GB and minutes per frequency at the \
             limit)"
        ),
        other => other.to_string(),
    }
}

/// Everything the pipeline produced.
pub struct Built {
    /// The checked scene, with its band after the `--max-step` cut.
    pub scene: BuiltScene,
    /// The sweep (nondimensional).
    pub sweep: SweepResult,
    /// The sweep in SI units: the fitted DOFs, and all of the hull's when some were left out.
    pub response: SceneResponse,
    /// The fit.
    pub fit: FitReport,
    /// Wall time of the sweep.
    pub sweep_time: Duration,
    /// Wall time of the fit.
    pub fit_time: Duration,
}

impl Built {
    /// What the scene's FMU models and leaves out, and the error.
    pub fn report(&self) -> SceneReport {
        self.scene.report(&self.response, &self.fit)
    }
}

/// Runs the sweep of the scene's hull and fits its network, with a progress bar; warnings
/// and notes go to standard error.
pub fn build_network(scene: Scene) -> Result<Built, String> {
    let scene = scene.build().map_err(message)?;
    let progress = Progress::new("sweep");
    let start = Instant::now();
    let sweep = scene
        .sweep(&|d, t| progress.update(d, t))
        .map_err(message)?;
    let sweep_time = start.elapsed();
    for note in &sweep.notes {
        crate::output::stderr_line(&format!("fmu-pack: note: {note}"));
    }
    for warning in &sweep.warnings {
        crate::output::stderr_line(&format!("fmu-pack: warning: {warning}"));
    }
    let response = scene.response(&sweep).map_err(message)?;
    let start = Instant::now();
    let fit = scene.fit(&response).map_err(message)?;
    for note in &fit.notes {
        crate::output::stderr_line(&format!("fmu-pack: {note}"));
    }
    let fit_time = start.elapsed();
    Ok(Built {
        scene,
        sweep,
        response,
        fit,
        sweep_time,
        fit_time,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_parse_in_kr_and_rad_per_second() {
        assert_eq!(parse_band("0.05:4").unwrap(), Band::Wavenumber(0.05, 4.0));
        assert_eq!(
            parse_band("0.5:3rad/s").unwrap(),
            Band::RadPerSecond(0.5, 3.0)
        );
        for bad in ["4:1", "1:1", "a:b", "1", "-1:2", "1:inf"] {
            let e = parse_band(bad).unwrap_err();
            assert!(e.starts_with(&format!("--band '{bad}'")), "{e}");
        }
    }

    #[test]
    fn scene_errors_name_the_options() {
        let e = message(SceneError::InvalidTolerance(0.0));
        assert_eq!(e, "--tol 0: the tolerance must be finite and > 0");
        let e = message(SceneError::InvalidMaxStep(-1.0));
        assert_eq!(e, "--max-step -1: the step must be finite and > 0 s");
        let e = message(SceneError::BandAboveNyquist {
            max_step: 10.0,
            nyquist: 0.1 * std::f64::consts::PI,
            band: (0.5, 8.0),
        });
        assert!(
            e.starts_with("--max-step 10 s: its Nyquist frequency"),
            "{e}"
        );
    }
}
