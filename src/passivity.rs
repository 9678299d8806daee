//! Exact passivity check of a realized network, at every frequency, not only on samples.
//!
//! The network's force on the hull is `F = C z + D v` ([`StateSpace`]); the water's mechanical
//! impedance is `Z(s) = -(C (sI - A)^-1 B + D)` (force the hull exerts per hull velocity). The
//! network is passive when `A` is stable and
//!
//! ```text
//! Re Z(i omega) = (Z(i omega) + Z(i omega)^H) / 2  is positive semi-definite for all omega >= 0,
//! ```
//!
//! the time-averaged power the hull delivers to the water, `v^H Re Z v / 2`, never negative.
//!
//! # Method (Hamiltonian matrix)
//!
//! With `Z_eps = Z + eps I` (so that `R = D' + D'^T`, `D' = -D + eps I`, is positive definite
//! even without a direct damper), the frequencies where an eigenvalue of `Re Z_eps(i omega)`
//! crosses or touches zero are exactly the purely imaginary eigenvalues `i omega` of
//!
//! ```text
//! M = [ A - B R^-1 C'        -B R^-1 B^T        ]      C' = -C
//!     [ C'^T R^-1 C'         -A^T + C'^T R^-1 B^T ]
//! ```
//!
//! (the zeros of `det(Z_eps(s) + Z_eps(-s)^T)`). Between two consecutive such frequencies the
//! eigenvalues of `Re Z_eps` keep their signs, so one evaluation inside each interval (and
//! beyond the last) decides the sign everywhere: the check is exact up to the tolerance
//! `eps = tolerance x scale` (`scale`: the largest `|Z_ij|` on a log grid around the poles)
//! and the accuracy of the eigenvalues. `omega = 0` is always a double root for a network
//! without a spring to ground (`Z(0) = 0`); `eps` moves it off the axis.
//!
//! Eigenvalues come from a Schur iteration with a bounded number of steps; if it does not
//! converge, the system is reported unstable (state matrix) or not passive (Hamiltonian):
//! the check never calls undecided passive, and never hangs.
//!
//! A network whose elements are all positive (`m, k, c > 0`, [`crate::realize`]) is passive by
//! construction; this check verifies it independently of how the network was built.

use crate::numerics::eigenvalues;
use crate::realize::StateSpace;
use nalgebra::DMatrix;
use num_complex::Complex64;

/// The smallest eigenvalue of the symmetric `m`; minus infinity (never passive) for a
/// non-finite entry, on which nalgebra's iteration does not end.
fn smallest_eigenvalue(m: &DMatrix<f64>) -> f64 {
    if m.iter().all(|x| x.is_finite()) {
        m.clone().symmetric_eigenvalues().min()
    } else {
        f64::NEG_INFINITY
    }
}

/// The result of [`check`].
#[derive(Clone, Debug)]
pub struct PassivityReport {
    /// `stable` and `Re Z + eps I` positive semi-definite at every frequency.
    pub passive: bool,
    /// No eigenvalue of `A` in the open right half-plane, beyond rounding (`Re p <= 1e-12
    /// max |p|`; a positive-real impedance may have simple poles on the imaginary axis).
    pub stable: bool,
    /// The pole of `A` with the largest real part (the slowest decay), if any.
    pub slowest_pole: Option<Complex64>,
    /// The scale of `|Z|` the tolerance refers to.
    pub scale: f64,
    /// The frequencies (rad/s, ascending) where an eigenvalue of `Re Z + eps I` reaches zero.
    pub crossings: Vec<f64>,
    /// The smallest eigenvalue of `Re Z(i omega)` over the tested frequencies (crossings,
    /// interval midpoints, 0, beyond the last crossing and omega -> inf), relative to `scale`.
    pub min_eigenvalue: f64,
    /// The frequency (rad/s) of `min_eigenvalue` (infinite: the direct feedthrough).
    pub at_omega: f64,
}

/// Checks the passivity of `system` (module docs); `tolerance` relative to the scale of `Z`
/// (1e-9 is a sensible default).
pub fn check(system: &StateSpace, tolerance: f64) -> PassivityReport {
    check_realization(
        &Realization {
            a: &system.a,
            b: &system.b,
            c: &system.c,
            d: &system.d,
        },
        tolerance,
    )
}

/// A state-space model `F = C z + D v`, `z' = A z + B v` (the convention of [`StateSpace`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Realization<'a> {
    /// State matrix.
    pub(crate) a: &'a DMatrix<f64>,
    /// Input matrix (hull velocity).
    pub(crate) b: &'a DMatrix<f64>,
    /// Output matrix (force on the hull).
    pub(crate) c: &'a DMatrix<f64>,
    /// Direct feedthrough.
    pub(crate) d: &'a DMatrix<f64>,
}

impl Realization<'_> {
    fn state_count(&self) -> usize {
        self.a.nrows()
    }

    fn input_count(&self) -> usize {
        self.b.ncols()
    }

    fn transfer(&self, s: Complex64) -> DMatrix<Complex64> {
        crate::realize::transfer_function(self.a, self.b, self.c, self.d, s)
    }
}

/// [`check`] for any realization (for instance of a rational fit, before it is a network).
pub(crate) fn check_realization(system: &Realization, tolerance: f64) -> PassivityReport {
    let states = system.state_count();
    let n = system.input_count();
    // A state matrix whose eigenvalues cannot be computed counts as unstable (not passive).
    let (poles, decided) = match eigenvalues(system.a) {
        Some(poles) => (poles, true),
        None => (Vec::new(), false),
    };
    let largest_pole = poles.iter().map(|p| p.norm()).fold(0.0, f64::max);
    let stable = decided && poles.iter().all(|p| p.re <= 1e-12 * largest_pole);
    let slowest_pole = poles.iter().copied().max_by(|a, b| a.re.total_cmp(&b.re));
    let impedance =
        |omega: f64| -> DMatrix<Complex64> { -system.transfer(Complex64::new(0.0, omega)) };
    let magnitudes: Vec<f64> = poles
        .iter()
        .map(|p| p.norm())
        .filter(|&m| m > 0.0)
        .collect();
    let (low, high) = magnitudes
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &m| (l.min(m), h.max(m)));
    let (low, high) = if magnitudes.is_empty() {
        (1.0, 1.0)
    } else {
        (low, high)
    };
    let grid: Vec<f64> = (0..=64)
        .map(|k| low / 10.0 * (100.0 * high / low).powf(k as f64 / 64.0))
        .collect();
    let scale = grid
        .iter()
        .map(|&w| impedance(w).iter().map(|z| z.norm()).fold(0.0, f64::max))
        .fold(0.0, f64::max)
        .max(system.d.amax())
        .max(f64::MIN_POSITIVE);
    let eps = tolerance * scale;

    let mut crossings = Vec::new();
    let mut hamiltonian_failed = false;
    if states > 0 && stable {
        // R = D' + D'^T with D' = -D + eps I; C' = -C.
        let d_prime = -system.d + DMatrix::identity(n, n) * eps;
        let r = &d_prime + d_prime.transpose();
        if let Some(r_inv) = r.clone().try_inverse() {
            let c_prime = -system.c;
            let b = system.b;
            let mut m = DMatrix::zeros(2 * states, 2 * states);
            let top_left = system.a - b * &r_inv * &c_prime;
            m.view_mut((0, 0), (states, states)).copy_from(&top_left);
            m.view_mut((0, states), (states, states))
                .copy_from(&(-(b * &r_inv * b.transpose())));
            m.view_mut((states, 0), (states, states))
                .copy_from(&(c_prime.transpose() * &r_inv * &c_prime));
            m.view_mut((states, states), (states, states))
                .copy_from(&(-top_left.transpose()));
            match eigenvalues(&m) {
                Some(values) => {
                    let largest = values.iter().map(|e| e.norm()).fold(0.0, f64::max);
                    for e in values.iter() {
                        if e.im >= 0.0 && e.re.abs() <= 1e-7 * largest.max(1.0) {
                            crossings.push(e.im);
                        }
                    }
                }
                // Undecided: never reported passive.
                None => hamiltonian_failed = true,
            }
        }
    }
    crossings.sort_by(f64::total_cmp);
    crossings.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs().max(1e-300));

    // One frequency inside each interval between crossings, the crossings themselves, 0 and
    // beyond the last one (and the grid, which costs little and guards the eigenvalue tolerance).
    let mut tested: Vec<f64> = vec![0.0];
    tested.extend(&crossings);
    for pair in crossings.windows(2) {
        tested.push(0.5 * (pair[0] + pair[1]));
    }
    if let Some(&first) = crossings.first() {
        tested.push(0.5 * first);
    }
    let last = crossings.last().copied().unwrap_or(0.0).max(high);
    tested.push(2.0 * last);
    tested.extend(&grid);
    let (mut min_eigenvalue, mut at_omega) = (f64::INFINITY, 0.0);
    for &omega in &tested {
        let z = impedance(omega);
        let hermitian = (&z + z.adjoint()).map(|x| x.re) * 0.5;
        // Re Z(i omega) is real symmetric for a reciprocal network; the imaginary part of the
        // Hermitian part (antisymmetric) is included by the real embedding below.
        let imaginary = (&z + z.adjoint()).map(|x| x.im) * 0.5;
        let mut embedded = DMatrix::zeros(2 * n, 2 * n);
        embedded.view_mut((0, 0), (n, n)).copy_from(&hermitian);
        embedded.view_mut((n, n), (n, n)).copy_from(&hermitian);
        embedded.view_mut((0, n), (n, n)).copy_from(&(-&imaginary));
        embedded.view_mut((n, 0), (n, n)).copy_from(&imaginary);
        let smallest = smallest_eigenvalue(&embedded);
        if smallest < min_eigenvalue {
            min_eigenvalue = smallest;
            at_omega = omega;
        }
    }
    // omega -> inf: Re Z = -(D + D^T) / 2 (exact; a finite test frequency may miss it).
    let at_infinity = smallest_eigenvalue(&(-(system.d + system.d.transpose()) * 0.5));
    if n > 0 && at_infinity < min_eigenvalue {
        min_eigenvalue = at_infinity;
        at_omega = f64::INFINITY;
    }
    let min_eigenvalue = min_eigenvalue / scale;
    PassivityReport {
        passive: stable && !hamiltonian_failed && min_eigenvalue >= -tolerance,
        stable,
        slowest_pole,
        scale,
        crossings,
        min_eigenvalue,
        at_omega,
    }
}

#[cfg(test)]
mod tests;
