//! Why a sweep cannot start or gives nothing: [`SweepError`].

use super::{readable, SizeLimit};
use crate::bem::{describe_surface, BemError};
use crate::green::FreeSurface;
use crate::panels::PanelError;
use crate::units::WaterDepth;
use std::fmt;

/// A sweep that cannot start.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum SweepError {
    /// A kR grid specification that gives no valid grid.
    Grid {
        /// Smallest kR.
        min: f64,
        /// Largest kR.
        max: f64,
        /// Point count.
        count: usize,
    },
    /// A kR in the grid that is not finite and positive.
    Frequency(f64),
    /// No discretization level.
    NoLevels,
    /// The coarsest extrapolation mesh would have fewer than 4 panels.
    TooFewPanelsForLevels {
        /// The requested body panel count.
        panels: usize,
        /// The extrapolation levels.
        levels: usize,
        /// Panels of the coarsest mesh.
        coarsest: usize,
    },
    /// The hull cannot be discretized.
    Mesh(PanelError),
    /// The panel method failed to prepare a mesh.
    Problem(BemError),
    /// A thread count of 0, or a thread pool that cannot start.
    Threads {
        /// The requested thread count.
        threads: usize,
        /// What the thread pool reported (empty for a count of 0).
        message: String,
    },
    /// A frequency limit (A_inf or A(0)) failed: without A_inf there is nothing to fit.
    Limit {
        /// The limit's free-surface condition.
        surface: FreeSurface,
        /// Why it failed.
        cause: BemError,
    },
    /// A size the parameters decide is above its limit (see [`SizeLimit`]).
    TooLarge {
        /// Which size.
        limit: SizeLimit,
        /// The size asked for.
        requested: usize,
    },
    /// The grid has no frequency.
    NoFrequencies,
    /// The water depth cannot serve this sweep.
    Depth {
        /// The depth asked for.
        depth: WaterDepth,
        /// Why not.
        reason: String,
    },
    /// A value computed once for the whole sweep is not finite after its normalization.
    NonFinite {
        /// What: `A_inf`, `A(0)` or the long-wave exciting force.
        quantity: &'static str,
        /// The reference half-beam R it was normalized with (m).
        half_beam: f64,
    },
    /// Every frequency failed: there is no table.
    NothingComputed {
        /// Each frequency with the reason it failed, in grid order.
        failures: Vec<(f64, String)>,
    },
}

impl fmt::Display for SweepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SweepError::Grid { min, max, count } if min.is_finite() && max.is_finite() && *min > 0.0 => write!(
                f,
                "kR grid {}:{}:{count}: need MIN <= MAX and COUNT >= 2 (or MIN = MAX with COUNT = 1)",
                readable(*min),
                readable(*max)
            ),
            SweepError::Grid { min, max, .. } => write!(
                f,
                "kR grid {}:{}: kR must be finite and > 0",
                readable(*min),
                readable(*max)
            ),
            SweepError::Frequency(bad) => write!(
                f,
                "kR = {} in the grid: every kR must be finite and > 0",
                readable(*bad)
            ),
            SweepError::NoFrequencies => f.write_str("the kR grid has no frequency"),
            SweepError::Depth { depth, reason } => write!(f, "water depth {depth}: {reason}"),
            SweepError::TooLarge { limit, requested } => write!(
                f,
                "{requested} {} requested; at most {} ({})",
                limit.quantity(),
                limit.max(),
                limit.reason()
            ),
            SweepError::NonFinite {
                quantity,
                half_beam,
            } => write!(
                f,
                "{quantity} is not finite after its normalization by the reference half-beam \
                 R = {} m",
                readable(*half_beam)
            ),
            SweepError::NothingComputed { failures } => {
                match failures.len() {
                    1 => f.write_str("the sweep's only frequency failed")?,
                    n => write!(f, "all {n} frequencies of the sweep failed")?,
                }
                if let Some((kr, reason)) = failures.first() {
                    write!(f, "; kR = {}: {reason}", readable(*kr))?;
                }
                Ok(())
            }
            SweepError::NoLevels => f.write_str("at least one discretization level is needed"),
            SweepError::TooFewPanelsForLevels {
                panels,
                levels,
                coarsest,
            } => write!(
                f,
                "{panels} panels are too few for {levels} extrapolation levels (the coarsest \
                 mesh would have {coarsest}); raise --panels"
            ),
            SweepError::Mesh(e) => write!(f, "{e}"),
            SweepError::Problem(e) => write!(f, "{e}"),
            SweepError::Threads { threads: 0, .. } => {
                f.write_str("the thread count must be at least 1")
            }
            SweepError::Threads { threads, message } => {
                write!(f, "cannot start {threads} threads: {message}")
            }
            SweepError::Limit { surface, cause } => {
                write!(f, "{} failed: {cause}", describe_surface(*surface))
            }
        }
    }
}

impl std::error::Error for SweepError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SweepError::Mesh(e) => Some(e),
            SweepError::Problem(e) | SweepError::Limit { cause: e, .. } => Some(e),
            _ => None,
        }
    }
}
