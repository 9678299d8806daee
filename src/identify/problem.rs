//! The normalized fitting problem: the band's data, frequencies over `omega_ref`, entries over
//! `sqrt(s_i s_j)` (see [`crate::identify`]), with its error measures and the report; the DOF
//! scales; the rate limit that refuses over-fitted networks.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::{FitReport, FrequencyResponse, IdentifyError};
use crate::network::{Branch, Network};

/// The normalized fitting problem.
pub(super) struct Problem {
    pub(super) dof_names: Vec<String>,
    pub(super) rho: f64,
    pub(super) g: f64,
    /// Frequency scale.
    pub(super) omega_ref: f64,
    /// Band frequencies over `omega_ref`.
    pub(super) nu: Vec<f64>,
    /// Band frequencies (rad/s) and the raw data there.
    pub(super) omega: Vec<f64>,
    pub(super) raw: Vec<DMatrix<Complex64>>,
    /// `(sym(A~) - A_inf) / sqrt(s_i s_j)` at the band frequencies.
    pub(super) target: Vec<DMatrix<Complex64>>,
    /// `s_i`.
    pub(super) scale: DVector<f64>,
    /// Symmetric PSD `A_inf`.
    pub(super) added_mass_inf: DMatrix<f64>,
    pub(super) added_mass_inf_adjustment: f64,
}

impl Problem {
    pub(super) fn new(
        data: &FrequencyResponse,
        band: (f64, f64),
    ) -> Result<Problem, IdentifyError> {
        let (lo, hi) = band;
        if lo.is_nan() || hi.is_nan() || lo < 0.0 || hi <= lo {
            return Err(IdentifyError::InvalidBand(format!(
                "band ({lo}, {hi}) rad/s is empty or not ordered"
            )));
        }
        let indices: Vec<usize> = (0..data.omega.len())
            .filter(|&k| data.omega[k] >= lo && data.omega[k] <= hi)
            .collect();
        if indices.len() < 3 {
            return Err(IdentifyError::InvalidBand(format!(
                "band ({lo}, {hi}) rad/s holds {} frequency points, at least 3 are needed",
                indices.len()
            )));
        }
        let n = data.dof_count();
        let omega: Vec<f64> = indices.iter().map(|&k| data.omega[k]).collect();
        let raw: Vec<DMatrix<Complex64>> = indices
            .iter()
            .map(|&k| data.added_mass[k].clone())
            .collect();
        let omega_ref = (omega[0] * omega[omega.len() - 1]).sqrt();
        let nu = omega.iter().map(|w| w / omega_ref).collect();

        // Symmetric PSD A_inf.
        let a = &data.added_mass_inf;
        let sym = (a + a.transpose()) * 0.5;
        let eigen = crate::numerics::symmetric_eigen(&sym);
        let largest = eigen.eigenvalues.amax();
        let smallest = eigen.eigenvalues.min();
        if smallest < -1e-3 * largest {
            return Err(IdentifyError::InvalidData(format!(
                "added_mass_inf has the eigenvalue {smallest:e} (largest {largest:e}): it is not \
                 a physical (positive semi-definite) added mass"
            )));
        }
        let clipped = eigen.eigenvalues.map(|l| l.max(0.0));
        let added_mass_inf = if smallest < 0.0 {
            let v = &eigen.eigenvectors;
            let m = v * DMatrix::from_diagonal(&clipped) * v.transpose();
            (&m + m.transpose()) * 0.5
        } else {
            sym
        };
        let added_mass_inf_adjustment = (&added_mass_inf - a).amax();

        let scale = dof_scales(&raw).ok_or_else(|| {
            IdentifyError::InvalidData("the added mass is zero over the band".into())
        })?;
        let target = raw
            .iter()
            .map(|m| {
                DMatrix::from_fn(n, n, |i, j| {
                    ((m[(i, j)] + m[(j, i)]) * 0.5 - added_mass_inf[(i, j)])
                        / error_scale(&scale, i, j)
                })
            })
            .collect();
        Ok(Problem {
            dof_names: data.dof_names.clone(),
            rho: data.rho,
            g: data.g,
            omega_ref,
            nu,
            omega,
            raw,
            target,
            scale,
            added_mass_inf,
            added_mass_inf_adjustment,
        })
    }

    pub(super) fn n(&self) -> usize {
        self.scale.len()
    }

    /// Largest normalized error of a network over the band.
    pub(super) fn max_relative_error(&self, net: &Network) -> f64 {
        let (max, _) = self.errors(net);
        let n = self.n();
        let mut worst: f64 = 0.0;
        for i in 0..n {
            for j in 0..n {
                worst = nan_max(worst, max[(i, j)] / error_scale(&self.scale, i, j));
            }
        }
        worst
    }

    /// Absolute max and RMS errors per entry.
    pub(super) fn errors(&self, net: &Network) -> (DMatrix<f64>, DMatrix<f64>) {
        let n = self.n();
        let mut max = DMatrix::zeros(n, n);
        let mut sum = DMatrix::zeros(n, n);
        for (k, &w) in self.omega.iter().enumerate() {
            let h = net.added_mass_tf(w);
            for j in 0..n {
                for i in 0..n {
                    let e = (h[(i, j)] - self.raw[k][(i, j)]).norm();
                    if e > max[(i, j)] || e.is_nan() {
                        max[(i, j)] = e;
                    }
                    sum[(i, j)] += e * e;
                }
            }
        }
        let count = self.omega.len() as f64;
        (max, sum.map(|s: f64| (s / count).sqrt()))
    }

    pub(super) fn report(
        &self,
        network: Network,
        order: usize,
        tolerance: f64,
        iterations: usize,
    ) -> FitReport {
        let n = self.n();
        let (max_error, rms_error) = self.errors(&network);
        let error_scale = DMatrix::from_fn(n, n, |i, j| error_scale(&self.scale, i, j));
        let max_relative_error = relative_error(&max_error, &error_scale);
        FitReport {
            aux_dofs: network.aux_dof_count(),
            states: network.state_count(),
            network,
            order,
            max_error,
            rms_error,
            error_scale,
            max_relative_error,
            tolerance,
            tolerance_met: max_relative_error <= tolerance,
            band: (self.omega[0], self.omega[self.omega.len() - 1]),
            points: self.omega.len(),
            iterations,
            added_mass_inf_adjustment: self.added_mass_inf_adjustment,
            notes: Vec::new(),
        }
    }

    pub(super) fn shallow_clone(&self) -> Problem {
        Problem {
            dof_names: self.dof_names.clone(),
            rho: self.rho,
            g: self.g,
            omega_ref: self.omega_ref,
            nu: self.nu.clone(),
            omega: self.omega.clone(),
            raw: Vec::new(),
            target: Vec::new(),
            scale: self.scale.clone(),
            added_mass_inf: self.added_mass_inf.clone(),
            added_mass_inf_adjustment: 0.0,
        }
    }

    /// The fastest rate a fitted network may have (1/s), see [`FASTEST_RATE_OVER_BAND`].
    pub(super) fn rate_limit(&self) -> f64 {
        FASTEST_RATE_OVER_BAND * self.omega[self.omega.len() - 1]
    }

    pub(super) fn over_fit_error(&self, order: usize, rate: f64) -> IdentifyError {
        IdentifyError::InvalidParams(format!(
            "order {order} over-fits the data: a stage has the rate {rate:.3e} 1/s, more than \
             {FASTEST_RATE_OVER_BAND:e} times the band's top frequency {:.4} rad/s (negligible \
             mass with extreme stiffness or damping); use a lower order or the automatic one",
            self.omega[self.omega.len() - 1]
        ))
    }
}

/// `sqrt(s_i s_j)`, without overflow: at a length scale of 1e30 m the products of the
/// rotations' scales (7e155 kg m^2) were infinite, every error zero, and a network of no
/// states reported 0 % error.
pub(super) fn error_scale(scale: &DVector<f64>, i: usize, j: usize) -> f64 {
    scale[i].sqrt() * scale[j].sqrt()
}

/// The larger of two errors, NaN if either is (`f64::max` would drop it, and a network
/// whose response is not finite would be reported within the tolerance).
pub(super) fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// The largest `max_error_ij / error_scale_ij` (NaN if any is).
pub(super) fn relative_error(max_error: &DMatrix<f64>, error_scale: &DMatrix<f64>) -> f64 {
    max_error
        .iter()
        .zip(error_scale.iter())
        .fold(0.0, |worst, (e, s)| nan_max(worst, e / s))
}

/// Smallest DOF scale `s_i`, as a fraction of the largest one (see the module docs).
pub(crate) const SCALE_FLOOR: f64 = 1e-6;

/// The DOF scales of the error measure (module docs): `s_i = max |A~_ii|` over the given
/// matrices, raised to `SCALE_FLOOR` times the largest for a DOF that moves (almost) no
/// water. `None` when every `s_i` is zero or NaN (or no matrix is given).
pub fn dof_scales(added_mass: &[DMatrix<Complex64>]) -> Option<DVector<f64>> {
    let n = added_mass.first()?.nrows();
    let scale = DVector::from_fn(n, |i, _| {
        added_mass
            .iter()
            .map(|m| m[(i, i)].norm())
            .fold(0.0, f64::max)
    });
    let largest = scale.max();
    if largest.is_nan() || largest <= 0.0 {
        return None;
    }
    Some(scale.map(|s| s.max(SCALE_FLOOR * largest)))
}

/// Fastest time scale a fitted network may have, as a multiple of the band's top frequency.
/// An over-fitted stage (negligible mass with extreme stiffness or damping) has rates far
/// beyond any band and any communication step; it carries no information and makes the
/// network stiff. Such candidates are refused.
pub const FASTEST_RATE_OVER_BAND: f64 = 1e4;

/// The fastest rate (1/s) of a network's stages: `sqrt(k / m)` and `c / m` for the masses
/// each spring and damper acts on (an upper estimate of the state matrix's largest
/// eigenvalue, cheap and robust for any values), and the largest eigenvalue modulus of each
/// substructure.
pub fn fastest_rate(network: &Network) -> f64 {
    let substructures = network.substructures.iter().map(|sub| {
        // Undecidable eigenvalues count as infinitely fast (the network is refused).
        crate::numerics::eigenvalues(&sub.impedance_realization().a).map_or(f64::INFINITY, |e| {
            e.iter().map(|p| p.norm()).fold(0.0, f64::max)
        })
    });
    network
        .branches
        .iter()
        .map(branch_rate)
        .chain(substructures)
        .fold(0.0, f64::max)
}

/// [`fastest_rate`] of one branch.
pub(super) fn branch_rate(branch: &Branch) -> f64 {
    let mut fastest = 0.0f64;
    let mut previous: Option<f64> = None;
    for stage in &branch.stages {
        for m in [Some(stage.mass), previous].into_iter().flatten() {
            fastest = fastest
                .max((stage.stiffness / m).sqrt())
                .max(stage.damping / m);
        }
        previous = Some(stage.mass);
    }
    fastest
}

/// Keeps the better of `best` and `candidate` (smaller error).
pub(super) fn keep_best(
    best: &mut Option<(f64, usize, Network)>,
    candidate: (f64, usize, Network),
) {
    if !matches!(best, Some((e, _, _)) if *e <= candidate.0) {
        *best = Some(candidate);
    }
}
