//! Hydrodynamics-free numerics used by the identification: nonlinear least squares
//! (Levenberg-Marquardt with a typed termination reason), non-negative least squares, least
//! squares under linear inequality constraints, projection onto the positive semi-definite
//! cone, the matrix sign function, eigenvalues with a bounded iteration, and a small deterministic random generator. Each module states its equation.

mod eigenvalues;
mod inequality_least_squares;
mod least_squares;
mod nnls;
mod psd;
mod rng;
mod sign;

pub use eigenvalues::{eigenvalues, symmetric_eigen};
pub use inequality_least_squares::triangular_inequality_least_squares;
pub use least_squares::{levenberg_marquardt, LeastSquares};
pub use nnls::nnls;
pub use psd::project_psd;
pub use rng::SplitMix64;
pub use sign::matrix_sign;
