//! A scene: the hull, the DOFs the master couples, the band, the tolerance and the master's
//! largest step, and the pipeline that turns them into a fitted network and its report.
//!
//! ```text
//! Scene --build--> BuiltScene --sweep--> SweepResult --response--> SceneResponse
//!       --fit--> FitReport --report--> SceneReport
//! ```
//!
//! * Build: checks the tolerance and the band, and cuts the band at the Nyquist frequency
//!   `pi / max_step` of the master's largest communication step (its signals cannot carry
//!   faster motion). The band must keep 3 of the sweep's frequencies.
//! * Sweep: the whole hull, nondimensional (`kR = omega^2 R / g`, `A~ / (rho pi R^2)`; see
//!   [`crate::units`]); progress goes to a callback, warnings stay in the result.
//! * Response: the sweep in SI units at the reference [`DEFAULT_RHO`] and [`DEFAULT_G`] (the
//!   FMU rescales the network exactly to the `rho` and `g` a master sets), restricted to the
//!   scene's DOFs; the full response is kept for the report.
//! * Fit: the network form is automatic unless given: a series chain for one DOF (a parallel
//!   bank when the chain misses the tolerance and the bank does better), the coupled network
//!   for several.
//! * Report: [`SceneReport`], the error in, below and above the band and what the left-out
//!   DOFs would have coupled.

mod body;
mod report;
pub mod whole_body;

pub use body::{all_frequencies, BodyScene, FittedBody};
pub use report::{LeftOut, RangeError, SceneReport};

use crate::fmu::description::{DEFAULT_G, DEFAULT_RHO};
use crate::hull::Hull;
use crate::identify::{self, FitParams, FitReport, FrequencyResponse, IdentifyError};
use crate::network::NetworkForm;
use crate::panels::PanelParams;
use crate::sweep::{self, SweepError, SweepParams, SweepResult};
use crate::units;
use std::fmt;

/// Default fit band in kR: where ship-section radiation forces matter for multibody scenes.
/// Below kR ~ 0.05 the added mass of heave-like DOFs (heave, cb2, cb5) diverges
/// logarithmically, which a finite network can follow only with many auxiliary DOFs; scenes
/// that need it ask for a wider band.
pub const DEFAULT_BAND_KR: (f64, f64) = (0.05, 5.0);

/// Relative slack of the band edges when sorting sweep frequencies into below, in and above.
const EDGE: f64 = 1e-12;

/// A frequency band `min .. max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Band {
    /// In kR (nondimensional).
    Wavenumber(f64, f64),
    /// In rad/s.
    RadPerSecond(f64, f64),
}

impl Default for Band {
    fn default() -> Self {
        Band::Wavenumber(DEFAULT_BAND_KR.0, DEFAULT_BAND_KR.1)
    }
}

impl Band {
    /// A band in kR; needs `0 <= min < max`, both finite.
    pub fn kr(min: f64, max: f64) -> Result<Band, SceneError> {
        Band::Wavenumber(min, max).checked()
    }

    /// A band in rad/s; needs `0 <= min < max`, both finite.
    pub fn rad_per_second(min: f64, max: f64) -> Result<Band, SceneError> {
        Band::RadPerSecond(min, max).checked()
    }

    /// The band itself if `0 <= min < max`, both finite.
    pub fn checked(self) -> Result<Band, SceneError> {
        let (Band::Wavenumber(min, max) | Band::RadPerSecond(min, max)) = self;
        if min.is_finite() && max.is_finite() && min >= 0.0 && max > min {
            Ok(self)
        } else {
            Err(SceneError::EmptyBand(self))
        }
    }

    /// The band in rad/s for a hull of half-beam `radius` under gravity `g`
    /// ([`units::omega_from_kr`]).
    pub fn to_rad_per_second(self, radius: f64, g: f64) -> (f64, f64) {
        match self {
            Band::RadPerSecond(a, b) => (a, b),
            Band::Wavenumber(a, b) => (
                units::omega_from_kr(a, radius, g),
                units::omega_from_kr(b, radius, g),
            ),
        }
    }

    /// The band in kR ([`units::kr_from_omega`]).
    pub fn to_kr(self, radius: f64, g: f64) -> (f64, f64) {
        match self {
            Band::Wavenumber(a, b) => (a, b),
            Band::RadPerSecond(a, b) => (
                units::kr_from_omega(a, radius, g),
                units::kr_from_omega(b, radius, g),
            ),
        }
    }
}

/// Why a scene cannot be built or run.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum SceneError {
    /// The tolerance is not finite and > 0.
    InvalidTolerance(f64),
    /// The band is empty or not finite.
    EmptyBand(Band),
    /// The master's largest step is not finite and > 0 (s).
    InvalidMaxStep(f64),
    /// The Nyquist frequency of the master's step leaves (almost) nothing of the band.
    BandAboveNyquist {
        /// The step (s).
        max_step: f64,
        /// Its Nyquist frequency `pi / max_step` (rad/s).
        nyquist: f64,
        /// The band before the cut (rad/s).
        band: (f64, f64),
    },
    /// The band holds fewer than 3 of the sweep's frequencies.
    TooFewFrequencies {
        /// The band in kR.
        kr: (f64, f64),
    },
    /// The sweep failed.
    Sweep(SweepError),
    /// The DOF selection or the fit failed.
    Identify(IdentifyError),
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::InvalidTolerance(t) => {
                write!(f, "tolerance {t}: the tolerance must be finite and > 0")
            }
            SceneError::EmptyBand(band) => write!(
                f,
                "band {band:?}: the band is empty; need 0 <= MIN < MAX, both finite"
            ),
            SceneError::InvalidMaxStep(h) => {
                write!(f, "max_step {h}: the step must be finite and > 0 s")
            }
            SceneError::BandAboveNyquist {
                max_step,
                nyquist,
                band,
            } => write!(
                f,
                "max_step {max_step} s: its Nyquist frequency pi/h = {nyquist:.4} rad/s leaves \
                 nothing of the band {:.4} .. {:.4} rad/s; use a smaller step or a lower band",
                band.0, band.1
            ),
            SceneError::TooFewFrequencies { kr } => write!(
                f,
                "the band kR {:.4} .. {:.4} holds fewer than 3 of the sweep's frequencies",
                kr.0, kr.1
            ),
            SceneError::Sweep(e) => e.fmt(f),
            SceneError::Identify(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for SceneError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SceneError::Sweep(e) => Some(e),
            SceneError::Identify(e) => Some(e),
            _ => None,
        }
    }
}

impl From<SweepError> for SceneError {
    fn from(e: SweepError) -> Self {
        SceneError::Sweep(e)
    }
}

impl From<IdentifyError> for SceneError {
    fn from(e: IdentifyError) -> Self {
        SceneError::Identify(e)
    }
}

/// What a master asks of the FMU of one hull.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The hull, swept whole.
    pub hull: Hull,
    /// The DOFs to fit, in this order; `None`: every DOF of the hull. The sweep covers the
    /// whole hull either way (its cost hardly depends on the DOF count), so the report can
    /// state what the left-out DOFs would have coupled.
    pub dofs: Option<Vec<String>>,
    /// The band to fit. Default [`DEFAULT_BAND_KR`].
    pub band: Band,
    /// Tolerance as a fraction of the largest `|A~|` scale (see [`crate::identify`]);
    /// `None`: 1 %.
    pub tolerance: Option<f64>,
    /// The largest communication step the master will use (s): the band is cut at its
    /// Nyquist frequency `pi / max_step`.
    pub max_step: Option<f64>,
    /// Network form; `None`: automatic (see the module docs).
    pub form: Option<NetworkForm>,
    /// Fixed order, or automatic.
    pub order: Option<usize>,
    /// The sweep's grid and discretization.
    pub sweep: SweepParams,
}

impl Scene {
    /// A scene of every DOF of `hull` with the defaults: the band [`DEFAULT_BAND_KR`],
    /// tolerance 1 %, automatic form and order, the default grid and the panels of
    /// [`PanelParams::for_hull`].
    pub fn new(hull: Hull) -> Scene {
        let sweep = SweepParams {
            panels: PanelParams::for_hull(&hull),
            ..SweepParams::default()
        };
        Scene {
            hull,
            dofs: None,
            band: Band::default(),
            tolerance: None,
            max_step: None,
            form: None,
            order: None,
            sweep,
        }
    }

    /// The band to fit in rad/s after the `max_step` cut, and the Nyquist frequency when it
    /// cut the band.
    pub fn effective_band(&self) -> Result<((f64, f64), Option<f64>), SceneError> {
        let (lo, hi) = self
            .band
            .checked()?
            .to_rad_per_second(self.hull.reference_half_beam(), DEFAULT_G);
        let Some(h) = self.max_step else {
            return Ok(((lo, hi), None));
        };
        if !(h.is_finite() && h > 0.0) {
            return Err(SceneError::InvalidMaxStep(h));
        }
        let nyquist = std::f64::consts::PI / h;
        if nyquist >= hi {
            return Ok(((lo, hi), None));
        }
        if nyquist <= lo * 1.5 {
            return Err(SceneError::BandAboveNyquist {
                max_step: h,
                nyquist,
                band: (lo, hi),
            });
        }
        Ok(((lo, nyquist), Some(nyquist)))
    }

    /// Checks the scene and fixes its band (see the module docs).
    pub fn build(self) -> Result<BuiltScene, SceneError> {
        if let Some(t) = self.tolerance {
            if !(t.is_finite() && t > 0.0) {
                return Err(SceneError::InvalidTolerance(t));
            }
        }
        let radius = self.hull.reference_half_beam();
        let (band, nyquist_cut) = self.effective_band()?;
        let (kr_min, kr_max) = Band::RadPerSecond(band.0, band.1).to_kr(radius, DEFAULT_G);
        let inside = self
            .sweep
            .kr
            .iter()
            .filter(|k| **k >= kr_min && **k <= kr_max)
            .count();
        if inside < 3 {
            return Err(SceneError::TooFewFrequencies {
                kr: (kr_min, kr_max),
            });
        }
        Ok(BuiltScene {
            scene: self,
            band,
            nyquist_cut,
        })
    }

    /// The sweep of the hull; `progress(done, total)` is called after each frequency. The
    /// table records the hull's `H/R` when its contour is a circle.
    pub fn sweep(
        &self,
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<SweepResult, SceneError> {
        Ok(sweep::run(&self.hull, &self.sweep, progress)?)
    }
}

/// The sweep in SI units, for the scene's DOFs.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneResponse {
    /// The scene's DOFs: the data the network is fitted to.
    pub fitted: FrequencyResponse,
    /// Every DOF of the hull, when the scene leaves some out.
    pub full: Option<FrequencyResponse>,
}

/// A checked scene with its band fixed; runs the pipeline stage by stage.
#[derive(Clone, Debug)]
pub struct BuiltScene {
    scene: Scene,
    band: (f64, f64),
    nyquist_cut: Option<f64>,
}

impl BuiltScene {
    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The band to fit, after the `max_step` cut (rad/s). The fit uses the sweep's
    /// frequencies inside it.
    pub fn band(&self) -> (f64, f64) {
        self.band
    }

    /// The Nyquist frequency of `max_step` when it cut the band (rad/s).
    pub fn nyquist_cut(&self) -> Option<f64> {
        self.nyquist_cut
    }

    /// The sweep of the whole hull (see [`Scene::sweep`]).
    pub fn sweep(
        &self,
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<SweepResult, SceneError> {
        self.scene.sweep(progress)
    }

    /// The sweep in SI units at the reference `rho` and `g`, restricted to the scene's DOFs.
    pub fn response(&self, sweep: &SweepResult) -> Result<SceneResponse, SceneError> {
        let response = FrequencyResponse::from_sweep(sweep, DEFAULT_RHO, DEFAULT_G);
        let Some(keep) = &self.scene.dofs else {
            return Ok(SceneResponse {
                fitted: response,
                full: None,
            });
        };
        let names: Vec<&str> = keep.iter().map(String::as_str).collect();
        let kept = response.select(&names)?;
        Ok(if kept.dof_count() < response.dof_count() {
            SceneResponse {
                fitted: kept,
                full: Some(response),
            }
        } else {
            SceneResponse {
                fitted: kept,
                full: None,
            }
        })
    }

    /// Fits the network to the scene's DOFs in the band.
    pub fn fit(&self, response: &SceneResponse) -> Result<FitReport, SceneError> {
        let params = FitParams {
            band: self.band,
            tolerance: self.scene.tolerance,
            order: self.scene.order,
            form: self.scene.form,
            pole_range_below: identify::pole_range_below(self.scene.sweep.depth, true),
            ..FitParams::default()
        };
        Ok(identify::fit(&response.fitted, &params)?)
    }

    /// The scene report of a fit (see [`SceneReport`]).
    pub fn report(&self, response: &SceneResponse, fit: &FitReport) -> SceneReport {
        SceneReport::new(
            &response.fitted,
            response.full.as_ref(),
            fit,
            self.band,
            self.nyquist_cut,
        )
    }
}

#[cfg(test)]
mod tests;
