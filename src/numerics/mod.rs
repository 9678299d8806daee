//! Hydrodynamics-free numerics used by the identification: nonlinear least squares
//! (Levenberg-Marquardt with a typed termination reason), non-negative least squares,
//! projection onto the positive semi-definite cone, and a small deterministic random
//! generator. Each module states its equation.

mod least_squares;
mod nnls;
mod psd;
mod rng;

pub use least_squares::{levenberg_marquardt, LeastSquares};
pub use nnls::nnls;
pub use psd::project_psd;
pub use rng::SplitMix64;
