//! Hydrodynamics-free numerics used by the identification: nonlinear least squares
//! (Levenberg-Marquardt with a typed termination reason), non-negative least squares, least
//! squares under sampled linear matrix inequalities (ADMM), derivative-free minimization
//! (Nelder-Mead), projection onto the positive semi-definite
//! cone, the matrix sign function, eigenvalues and singular values with a bounded iteration, and a small deterministic random generator. Each module states its equation.

mod eigenvalues;
mod least_squares;
mod lmi_least_squares;
mod nelder_mead;
mod nnls;
mod psd;
mod rng;
mod sign;
mod svd;

pub use eigenvalues::{eigenvalues, symmetric_eigen};
pub use least_squares::{levenberg_marquardt, LeastSquares};
pub use lmi_least_squares::{lmi_least_squares, MatrixInequalities};
pub use nelder_mead::nelder_mead;
pub use nnls::nnls;
pub use psd::project_psd;
pub use rng::SplitMix64;
pub use sign::matrix_sign;
pub use svd::svd;

/// 8-point Gauss-Legendre nodes and weights on [-1, 1] (exact for polynomials of degree 15).
pub const GAUSS_LEGENDRE_8: [(f64, f64); 8] = [
    (-0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
];
