//! The pipeline from a hull to a fitted network: sweep -> frequency response -> fit.
//!
//! Frequencies are requested in the nondimensional `kR = omega^2 R / g` or in rad/s; the
//! network is fitted and stored in SI units for the reference `rho` and `g` below, and the FMU
//! rescales it exactly to the `rho` and `g` a master sets.

use crate::progress::Progress;
use hydrofmu::hull::{DofKind, Hull, RigidKind};
use hydrofmu::identify::{self, FitParams, FitReport, FrequencyResponse};
use hydrofmu::model_description::{DEFAULT_G, DEFAULT_RHO};
use hydrofmu::realize::NetworkForm;
use hydrofmu::sweep::{self, SweepParams, SweepResult};
use hydrofmu::variables::DofUnit;
use std::time::{Duration, Instant};

/// Default fit band in kR: where ship-section radiation forces matter for multibody scenes.
/// Below kR ~ 0.05 the added mass of heave-like DOFs (heave, cb2, cb5) diverges
/// logarithmically, which a finite network can follow only with many auxiliary DOFs; scenes
/// that need it pass `--band`.
pub const DEFAULT_BAND_KR: (f64, f64) = (0.05, 5.0);

/// A frequency band, as the command line gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Band {
    /// In kR (nondimensional).
    Wavenumber(f64, f64),
    /// In rad/s.
    RadPerSecond(f64, f64),
}

impl Band {
    /// Parses `MIN:MAX` (kR) or `MIN:MAXrad/s` (rad/s).
    pub fn parse(text: &str) -> Result<Band, String> {
        let (body, rad) = match text.trim().strip_suffix("rad/s") {
            Some(body) => (body, true),
            None => (text.trim(), false),
        };
        let (min, max) = crate::hull_arg::parse_range(body, "--band")?;
        if !(min.is_finite() && max.is_finite() && min >= 0.0 && max > min) {
            return Err(format!(
                "--band '{text}': the band is empty; need 0 <= MIN < MAX, both finite"
            ));
        }
        Ok(if rad {
            Band::RadPerSecond(min, max)
        } else {
            Band::Wavenumber(min, max)
        })
    }

    /// The band in rad/s for a hull of half-beam `radius` under gravity `g`.
    pub fn rad_per_second(self, radius: f64, g: f64) -> (f64, f64) {
        match self {
            Band::RadPerSecond(a, b) => (a, b),
            Band::Wavenumber(a, b) => ((a * g / radius).sqrt(), (b * g / radius).sqrt()),
        }
    }

    /// The band in kR.
    pub fn wavenumber(self, radius: f64, g: f64) -> (f64, f64) {
        match self {
            Band::Wavenumber(a, b) => (a, b),
            Band::RadPerSecond(a, b) => (a * a * radius / g, b * b * radius / g),
        }
    }
}

/// What a scene asks of the network.
#[derive(Clone, Debug)]
pub struct FitRequest {
    /// The band to fit.
    pub band: Band,
    /// Tolerance as a fraction of the largest |A~| scale (see `identify`); `None`: 1 %.
    pub tolerance: Option<f64>,
    /// Fixed order, or automatic.
    pub order: Option<usize>,
    /// Network form; `None`: series chain for one DOF, coupled network for several.
    pub form: Option<NetworkForm>,
    /// The DOFs to fit, in this order; `None`: every swept DOF. The sweep covers the whole
    /// hull either way (its cost hardly depends on the DOF count), so the report can state
    /// what the left-out DOFs would have coupled.
    pub dofs: Option<Vec<String>>,
    /// The largest communication step the master will use (s). The band is cut at its
    /// Nyquist frequency `pi / max_step`: the master's signals cannot carry faster motion.
    pub max_step: Option<f64>,
}

impl Default for FitRequest {
    fn default() -> Self {
        Self {
            band: Band::Wavenumber(DEFAULT_BAND_KR.0, DEFAULT_BAND_KR.1),
            tolerance: None,
            order: None,
            form: None,
            max_step: None,
            dofs: None,
        }
    }
}

impl FitRequest {
    /// The band to fit in rad/s for a hull of half-beam `radius`, after the `max_step` cut,
    /// and the Nyquist frequency when it cut the band.
    pub fn effective_band(&self, radius: f64) -> Result<((f64, f64), Option<f64>), String> {
        let (lo, hi) = self.band.rad_per_second(radius, DEFAULT_G);
        let Some(h) = self.max_step else {
            return Ok(((lo, hi), None));
        };
        if !(h.is_finite() && h > 0.0) {
            return Err(format!("--max-step {h}: the step must be finite and > 0 s"));
        }
        let nyquist = std::f64::consts::PI / h;
        if nyquist >= hi {
            return Ok(((lo, hi), None));
        }
        if nyquist <= lo * 1.5 {
            return Err(format!(
                "--max-step {h} s: its Nyquist frequency pi/h = {nyquist:.4} rad/s leaves nothing \
                 of the band {lo:.4} .. {hi:.4} rad/s; use a smaller step or a lower band"
            ));
        }
        Ok(((lo, nyquist), Some(nyquist)))
    }
}

/// Everything the pipeline produced.
pub struct Built {
    /// The sweep (nondimensional).
    pub sweep: SweepResult,
    /// The sweep in SI units.
    pub response: FrequencyResponse,
    /// The fit.
    pub fit: FitReport,
    /// Wall time of the sweep.
    pub sweep_time: Duration,
    /// Wall time of the fit.
    pub fit_time: Duration,
    /// The band asked for, after the `--max-step` cut (rad/s). The fit uses the sweep's
    /// frequencies inside it.
    pub band: (f64, f64),
    /// The Nyquist frequency of `--max-step` when it cut the band (rad/s).
    pub nyquist_cut: Option<f64>,
    /// The response of every swept DOF, when the fit kept only some (`FitRequest::dofs`).
    pub all_dofs: Option<FrequencyResponse>,
}

/// Runs the sweep of `hull` and fits the network the request asks for.
pub fn build_network(
    hull: &Hull,
    depth: Option<f64>,
    sweep_params: &SweepParams,
    request: &FitRequest,
) -> Result<Built, String> {
    if let Some(t) = request.tolerance {
        if !(t.is_finite() && t > 0.0) {
            return Err(format!("--tol {t}: the tolerance must be finite and > 0"));
        }
    }
    let radius = hull.reference_half_beam();
    let (band, nyquist_cut) = request.effective_band(radius)?;
    let (kr_min, kr_max) = Band::RadPerSecond(band.0, band.1).wavenumber(radius, DEFAULT_G);
    let grid = &sweep_params.kr;
    if grid
        .iter()
        .filter(|k| **k >= kr_min && **k <= kr_max)
        .count()
        < 3
    {
        return Err(format!(
            "the band kR {kr_min:.4} .. {kr_max:.4} holds fewer than 3 of the sweep's frequencies"
        ));
    }
    let progress = Progress::new("sweep");
    let start = Instant::now();
    let sweep = sweep::run(hull, depth, sweep_params, &|d, t| progress.update(d, t))
        .map_err(|e| e.to_string())?;
    let sweep_time = start.elapsed();
    for warning in &sweep.warnings {
        eprintln!("fmu-pack: warning: {warning}");
    }
    let mut response = FrequencyResponse::from_sweep(&sweep, DEFAULT_RHO, DEFAULT_G);
    let mut all_dofs = None;
    if let Some(keep) = &request.dofs {
        let names: Vec<&str> = keep.iter().map(String::as_str).collect();
        let kept = response.select(&names).map_err(|e| e.to_string())?;
        if kept.dof_count() < response.dof_count() {
            all_dofs = Some(std::mem::replace(&mut response, kept));
        } else {
            response = kept;
        }
    }
    let form = request.form.unwrap_or(if response.dof_count() == 1 {
        NetworkForm::SeriesChain
    } else {
        NetworkForm::Coupled
    });
    let params = FitParams {
        form,
        band,
        tolerance: request.tolerance,
        order: request.order,
        ..FitParams::default()
    };
    let start = Instant::now();
    let mut fit = identify::fit(&response, &params).map_err(|e| e.to_string())?;
    // One DOF, form not chosen: a series chain first (the seed's form); if it misses the
    // tolerance, the parallel bank, and the better of the two.
    if request.form.is_none() && form == NetworkForm::SeriesChain && !fit.tolerance_met {
        let bank = FitParams {
            form: NetworkForm::ParallelBank,
            ..params.clone()
        };
        if let Ok(other) = identify::fit(&response, &bank) {
            let better = (other.tolerance_met, -other.max_relative_error)
                > (fit.tolerance_met, -fit.max_relative_error);
            if better {
                eprintln!(
                    "fmu-pack: the series chain misses the tolerance ({:.2} %); the parallel \
                     bank meets it better ({:.2} %) and is used",
                    100.0 * fit.max_relative_error,
                    100.0 * other.max_relative_error
                );
                fit = other;
            }
        }
    }
    let fit_time = start.elapsed();
    Ok(Built {
        sweep,
        response,
        fit,
        sweep_time,
        fit_time,
        band,
        nyquist_cut,
        all_dofs,
    })
}

/// What `pack` needs to know about the hull.
#[derive(Clone, Debug)]
pub struct HullInfo {
    /// Hull name (shown in the model description and the documentation).
    pub name: String,
    /// DOFs with their units, in the hull's order.
    pub dofs: Vec<DofUnit>,
    /// Canonical hull file text, packed as `resources/hull.xml`.
    pub xml: Option<String>,
}

/// Unit information of a hull DOF (see docs/DESIGN-NOTES.md, "Units of generalized DOFs").
pub fn dof_unit(name: &str, kind: Option<DofKind>) -> DofUnit {
    match kind {
        Some(DofKind::Rigid {
            kind: RigidKind::Roll,
            ..
        }) => DofUnit::new(name, 1, true),
        Some(DofKind::Rigid { .. }) => DofUnit::new(name, 0, false),
        Some(DofKind::CraigBampton { mode }) if mode == 3 || mode == 6 => {
            DofUnit::new(name, 1, true)
        }
        Some(DofKind::CraigBampton { .. }) => DofUnit::new(name, 0, false),
        _ => DofUnit::new(name, 1, false),
    }
}

impl HullInfo {
    /// What `pack` needs of a resolved hull (see [`crate::hull_arg::resolve`]).
    pub fn new(hull: &Hull) -> HullInfo {
        let dofs = (0..hull.dof_count())
            .map(|j| dof_unit(hull.dof_names()[j], hull.dof_kind(j)))
            .collect();
        let mut name = hull.name().to_string();
        if let Some(first) = name.get_mut(0..1) {
            first.make_ascii_uppercase();
        }
        HullInfo {
            name,
            dofs,
            xml: Some(hull.to_xml_string()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_parse_in_kr_and_rad_per_second() {
        assert_eq!(Band::parse("0.05:4").unwrap(), Band::Wavenumber(0.05, 4.0));
        assert_eq!(
            Band::parse("0.5:3rad/s").unwrap(),
            Band::RadPerSecond(0.5, 3.0)
        );
        let (a, b) = Band::Wavenumber(1.0, 4.0).rad_per_second(1.0, 9.81);
        assert!((a - 9.81f64.sqrt()).abs() < 1e-12 && (b - 2.0 * 9.81f64.sqrt()).abs() < 1e-12);
        for bad in ["4:1", "1:1", "a:b", "1", "-1:2", "1:inf"] {
            assert!(Band::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn max_step_cuts_the_band_at_nyquist() {
        let request = |max_step| FitRequest {
            band: Band::RadPerSecond(0.5, 8.0),
            max_step,
            ..FitRequest::default()
        };
        assert_eq!(
            request(None).effective_band(1.0).unwrap(),
            ((0.5, 8.0), None)
        );
        // pi / 0.1 = 31.4 rad/s lies above the band: nothing is cut.
        assert_eq!(
            request(Some(0.1)).effective_band(1.0).unwrap(),
            ((0.5, 8.0), None)
        );
        let ((lo, hi), cut) = request(Some(1.0)).effective_band(1.0).unwrap();
        assert_eq!((lo, cut), (0.5, Some(std::f64::consts::PI)));
        assert_eq!(hi, std::f64::consts::PI);
        for bad in [Some(0.0), Some(-1.0), Some(f64::NAN), Some(10.0)] {
            assert!(request(bad).effective_band(1.0).is_err(), "{bad:?}");
        }
    }
}
