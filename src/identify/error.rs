//! Errors of the identification.

use std::fmt;

/// Errors of [`fit`](super::fit).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum IdentifyError {
    /// The frequency response is unusable (sizes, NaN, non-physical `A_inf`).
    InvalidData(String),
    /// The band holds too few frequency points.
    InvalidBand(String),
    /// A fit parameter is out of range.
    InvalidParams(String),
    /// A rational fit could not be realized as a passive network.
    Synthesis(String),
    /// The fitted network holds numbers a network file cannot.
    NotWritable(String),
}

impl fmt::Display for IdentifyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IdentifyError::InvalidData(m) => write!(f, "invalid frequency response: {m}"),
            IdentifyError::InvalidBand(m) => write!(f, "invalid fit band: {m}"),
            IdentifyError::InvalidParams(m) => write!(f, "invalid fit parameters: {m}"),
            IdentifyError::Synthesis(m) => write!(f, "no passive network realizes the fit: {m}"),
            IdentifyError::NotWritable(m) => {
                write!(
                    f,
                    "the fitted network cannot be written as a network file: {m}"
                )
            }
        }
    }
}

impl std::error::Error for IdentifyError {}
