//! Settings and result of [`fit`](super::fit).

use nalgebra::DMatrix;

use super::rational::POLE_RANGE;
use crate::network::{Network, NetworkForm};
use crate::units::WaterDepth;

/// Settings of [`fit`](super::fit).
#[derive(Clone, Debug, PartialEq)]
pub struct FitParams {
    /// Network form; `None` (default): automatic (module docs of [`crate::identify`]):
    /// several DOFs get [`NetworkForm::Coupled`]; one DOF the fewest states among the series
    /// chain, the rational fit (with [`CoupledMethod::Rational`]) and (if the chain misses the
    /// tolerance) the parallel bank. The
    /// single-DOF forms need one-DOF data (see
    /// [`FrequencyResponse::select`](super::FrequencyResponse::select)).
    pub form: Option<NetworkForm>,
    /// Frequency band (rad/s), inclusive; default `(0, inf)`: every data point.
    pub band: (f64, f64),
    /// Admissible largest error as a fraction of `sqrt(s_i s_j)` (see the module docs);
    /// `None`: 0.01.
    pub tolerance: Option<f64>,
    /// Fixed order (auxiliary masses for one DOF, groups for the coupled form, per invariant
    /// block if the data has such blocks); `None`: automatic, the smallest order that meets
    /// the tolerance.
    pub order: Option<usize>,
    /// Largest order tried (per invariant block for the coupled form). Default 12.
    pub max_order: usize,
    /// Levenberg-Marquardt iterations per start (and per joint refinement). Default 300.
    pub max_iterations: usize,
    /// Random starts per order, single-DOF forms, only when the deterministic starts miss the
    /// tolerance, and then only at orders up to 3 or when they came within 4 times the
    /// tolerance (a local minimum, not a too-low order). Default 12.
    pub restarts: usize,
    /// Seed of the random starts. Default 1.
    pub seed: u64,
    /// Coupled form: `None` (default) tries both paths of the module docs (one-stage groups by
    /// variable projection, two-stage groups from the dictionary); `Some(1)` only the first;
    /// `Some(2)` the dictionary and two-stage variable projection; `Some(3 | 4)` variable
    /// projection with that many stages.
    pub coupled_stages: Option<usize>,
    /// How the coupled form is fitted; default [`CoupledMethod::Rational`] (fewest states).
    pub coupled_method: CoupledMethod,
    /// The data's own noise per entry (n x n, A~ units), e.g. an imported database's
    /// reciprocity gap ([`crate::database::Database::noise`]); `None` (default):
    /// none known. Where its largest entry over `sqrt(s_i s_j)` (the noise floor) exceeds the
    /// tolerance, the fit still aims at the tolerance but is judged against the noise floor
    /// ([`FitReport::tolerance`], `tolerance_met`) and says so in [`FitReport::notes`]: no
    /// network can be told apart from the data more finely.
    pub noise: Option<DMatrix<f64>>,
    /// How far below the band's bottom (a factor, >= 1; infinite: no bound) a pole of the
    /// rational fit may lie; default [`POLE_RANGE`] (30), above the band's top always
    /// [`POLE_RANGE`]. Two-dimensional data
    /// in finite depth take [`STRIP_FINITE_DEPTH_POLE_RANGE`] ([`pole_range_below`]): their
    /// damping tends to a constant as `omega -> 0`, a dashpot that only a slow pole can carry.
    pub pole_range_below: f64,
}

/// The range below the band for [`FitParams::pole_range_below`]: [`POLE_RANGE`], or
/// [`STRIP_FINITE_DEPTH_POLE_RANGE`] for two-dimensional data (`strips`: a section or a
/// ship's strips) in finite depth.
///
/// A 2D section in depth `h` radiates long waves at the speed `sqrt(g h)`: its heave damping
/// tends to `b(0) = rho g |x(0)|^2 / (2 sqrt(g h))` (both sides; `x = X / (rho g a)`, the
/// hydrostatic limit), not to zero as in deep water or around a 3D body, and `A~` grows like
/// `1 / omega` through `b / omega`. A network carries that constant damping in the band by a
/// pole far below it (`R / (i omega - p) ~ -i R / omega` for `|p| << omega`: damping `R`);
/// vector fitting places it 200 to 1e5 times below the band.
pub fn pole_range_below(depth: WaterDepth, strips: bool) -> f64 {
    if strips && !depth.is_infinite() {
        STRIP_FINITE_DEPTH_POLE_RANGE
    } else {
        POLE_RANGE
    }
}

/// [`FitParams::pole_range_below`] for 2D data in finite depth: `1e6` (the slowest pole
/// vector fitting proposed on the prismatic ship of `src/ship/depth_tests.rs`, 8.4e-6 rad/s
/// below a band from 0.71 rad/s, lies 8.4e4 below it).
pub const STRIP_FINITE_DEPTH_POLE_RANGE: f64 = 1e6;

/// How the coupled form is fitted (module docs of [`crate::identify`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CoupledMethod {
    /// Passive vector fitting per invariant block, each realized as a mechanical substructure
    /// (fewest states). Falls back to [`CoupledMethod::Chains`] if no order gives
    /// a passive network.
    Rational,
    /// Groups of branch chains (networks of branches only, readable by tools that know no
    /// substructures); also used whenever `coupled_stages` is set.
    Chains,
}

impl Default for FitParams {
    fn default() -> Self {
        FitParams {
            form: None,
            band: (0.0, f64::INFINITY),
            tolerance: None,
            order: None,
            max_order: 12,
            max_iterations: 300,
            restarts: 12,
            seed: 1,
            coupled_stages: None,
            coupled_method: CoupledMethod::Rational,
            noise: None,
            pole_range_below: POLE_RANGE,
        }
    }
}

/// Default tolerance: 1 % of the scale.
pub(crate) const DEFAULT_TOLERANCE: f64 = 0.01;

/// Result of [`fit`](super::fit).
#[derive(Clone, Debug, PartialEq)]
pub struct FitReport {
    /// The fitted network (valid, passive).
    pub network: Network,
    /// Order: auxiliary masses (single-DOF forms) or distinct chain dynamics (coupled form,
    /// summed over its invariant blocks, after pruning).
    pub order: usize,
    /// Auxiliary masses of the network.
    pub aux_dofs: usize,
    /// States of the realized network ([`Network::state_count`]).
    pub states: usize,
    /// Largest `|A~_ij - H_ij|` over the band, per entry (A~ units).
    pub max_error: DMatrix<f64>,
    /// RMS of `|A~_ij - H_ij|` over the band points, per entry.
    pub rms_error: DMatrix<f64>,
    /// `sqrt(s_i s_j)`, `s_i = max_band |A~_ii|`: the scale of the tolerance.
    pub error_scale: DMatrix<f64>,
    /// Largest `max_error / error_scale` over the entries.
    pub max_relative_error: f64,
    /// The tolerance used (fraction of `error_scale`): the one asked for, or the data's noise
    /// floor where that is larger ([`FitParams::noise`]).
    pub tolerance: f64,
    /// Whether `max_relative_error <= tolerance`.
    pub tolerance_met: bool,
    /// First and last frequency of the data inside the requested band (rad/s).
    pub band: (f64, f64),
    /// Number of frequency points fitted.
    pub points: usize,
    /// Levenberg-Marquardt iterations, summed over all starts and orders.
    pub iterations: usize,
    /// Largest change made to `A_inf` to make it symmetric PSD.
    pub added_mass_inf_adjustment: f64,
    /// What the fit decided and why, one sentence each: the form the automatic choice took,
    /// orders that failed (and why), the order kept when none met the tolerance, a fallback
    /// to branch chains, a tolerance raised to the data's noise floor, few frequencies. The
    /// form used is `network.form`.
    pub notes: Vec<String>,
}
