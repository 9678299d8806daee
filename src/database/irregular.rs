//! Irregular-frequency spikes in an imported database: found, reported, and kept out of the
//! fit and the excitation table.
//!
//! A panel code without irregular-frequency removal (no lid, WAMIT's IRR = 0) solves a
//! resonating interior problem near the interior eigenfrequencies: `A~` and the exciting
//! force jump over a narrow band, one or two grid points wide, and the damping may turn
//! negative. Two tests, each frequency against the rest:
//!
//! - **Outlier:** for every entry, the value at `omega_k` against the polynomial through up
//!   to two neighbours on each side (leave-one-out), as a fraction of the entry's scale
//!   `sqrt(s_i s_j)`, `s_i = max_k |A~_ii(omega_k)|`. The worst frequency is a spike when its
//!   deviation exceeds [`SpikeParams::threshold`] and [`SpikeParams::over_median`] times the
//!   median deviation (a coarse grid's smooth peaks deviate everywhere alike); it is removed
//!   and the search repeats.
//! - **Negative damping:** the symmetric damping matrix `B(omega_k)` with an eigenvalue below
//!   `-threshold` times the largest diagonal damping of the sweep radiates negative energy.
//!
//! DOFs whose scale is below 1e-8 of the largest (noise only) are left out of the outlier test.
//! The grid's first and last frequencies have neighbours on one side only and are tested for
//! negative damping alone. At most [`SpikeParams::max_fraction`] of the grid is removed.

use nalgebra::DMatrix;
use num_complex::Complex64;

/// Tuning of the spike search, with documented defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct SpikeParams {
    /// Deviation from the neighbours, as a fraction of the entry's scale, above which a
    /// frequency may be a spike. Default 0.1.
    pub threshold: f64,
    /// A spike's deviation must also exceed this many times the median deviation. Default 8.
    pub over_median: f64,
    /// Largest fraction of the grid removed. Default 0.25.
    pub max_fraction: f64,
}

impl Default for SpikeParams {
    fn default() -> Self {
        SpikeParams {
            threshold: 0.1,
            over_median: 8.0,
            max_fraction: 0.25,
        }
    }
}

/// A frequency found to be a spike.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Spike {
    /// Index into the grid given.
    pub index: usize,
    /// Why, in words (the entry and its deviation).
    pub reason: String,
}

/// The value at `x` of the polynomial through `points`.
fn lagrange(points: &[(f64, Complex64)], x: f64) -> Complex64 {
    let mut total = Complex64::new(0.0, 0.0);
    for (a, &(xa, ya)) in points.iter().enumerate() {
        let mut weight = 1.0;
        for (b, &(xb, _)) in points.iter().enumerate() {
            if a != b {
                weight *= (x - xb) / (xa - xb);
            }
        }
        total += ya * weight;
    }
    total
}

/// The spikes of `A~` on the ascending grid `omega`, in the order found. `names` label the
/// DOFs in the reasons.
pub(crate) fn find(
    omega: &[f64],
    added_mass: &[DMatrix<Complex64>],
    names: &[String],
    params: &SpikeParams,
) -> Vec<Spike> {
    let count = omega.len();
    let Some(n) = added_mass.first().map(DMatrix::nrows) else {
        return Vec::new();
    };
    let limit = (params.max_fraction * count as f64).floor() as usize;
    let scale: Vec<f64> = (0..n)
        .map(|i| {
            added_mass
                .iter()
                .map(|m| m[(i, i)].norm())
                .fold(0.0, f64::max)
                .max(f64::MIN_POSITIVE)
        })
        .collect();
    // A DOF the body hardly radiates in (a hemisphere's yaw: 1e-12 of the rest) holds only
    // the solver's noise, which is no curve to test.
    let largest_scale = scale.iter().copied().fold(0.0, f64::max);
    let resolved: Vec<bool> = scale.iter().map(|s| *s > 1e-8 * largest_scale).collect();
    let mut spikes = Vec::new();
    // Negative damping first.
    let largest_damping = added_mass
        .iter()
        .zip(omega)
        .flat_map(|(m, w)| (0..n).map(move |i| -m[(i, i)].im * w))
        .fold(0.0, f64::max);
    for (k, (m, w)) in added_mass.iter().zip(omega).enumerate() {
        let b = m.map(|z| -z.im * w);
        let symmetric = (&b + b.transpose()) / 2.0;
        let lowest = crate::numerics::symmetric_eigen(&symmetric)
            .eigenvalues
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        if largest_damping > 0.0 && lowest < -params.threshold * largest_damping {
            spikes.push(Spike {
                index: k,
                reason: format!(
                    "negative damping: B has the eigenvalue {lowest:.4e} ({:.1} % of the largest \
                     diagonal damping)",
                    100.0 * lowest / largest_damping
                ),
            });
        }
    }
    if count < 5 {
        spikes.truncate(limit);
        return spikes;
    }
    let mut removed: Vec<bool> = vec![false; count];
    for s in &spikes {
        removed[s.index] = true;
    }
    while spikes.len() < limit {
        let alive: Vec<usize> = (0..count).filter(|k| !removed[*k]).collect();
        if alive.len() < 5 {
            break;
        }
        // Leave-one-out deviation of every interior alive frequency.
        let mut deviations = Vec::with_capacity(alive.len());
        for p in 1..alive.len() - 1 {
            let left = &alive[p.saturating_sub(2)..p];
            let right = &alive[p + 1..(p + 3).min(alive.len())];
            let k = alive[p];
            let mut worst = (0.0, 0, 0);
            for i in (0..n).filter(|i| resolved[*i]) {
                for j in (i..n).filter(|j| resolved[*j]) {
                    let points: Vec<(f64, Complex64)> = left
                        .iter()
                        .chain(right)
                        .map(|&q| (omega[q], added_mass[q][(i, j)]))
                        .collect();
                    let predicted = lagrange(&points, omega[k]);
                    let d =
                        (added_mass[k][(i, j)] - predicted).norm() / (scale[i] * scale[j]).sqrt();
                    if d > worst.0 {
                        worst = (d, i, j);
                    }
                }
            }
            deviations.push((worst.0, k, worst.1, worst.2));
        }
        let mut sorted: Vec<f64> = deviations.iter().map(|d| d.0).collect();
        sorted.sort_by(f64::total_cmp);
        let median = sorted[sorted.len() / 2];
        let Some(&(d, k, i, j)) = deviations.iter().max_by(|a, b| a.0.total_cmp(&b.0)) else {
            break;
        };
        if !(d > params.threshold && d > params.over_median * median) {
            break;
        }
        removed[k] = true;
        let entry = if i == j {
            names[i].clone()
        } else {
            format!("{}-{}", names[i], names[j])
        };
        spikes.push(Spike {
            index: k,
            reason: format!(
                "A~ of {entry} deviates {:.0} % of its scale from its neighbours (the median \
                 frequency: {:.1} %)",
                100.0 * d,
                100.0 * median
            ),
        });
    }
    spikes
}

#[cfg(test)]
mod tests {
    use super::*;

    fn smooth(w: f64) -> Complex64 {
        // A resonance-like smooth curve: a + i b / omega with a peak at 1 rad/s.
        let z = Complex64::new(1.0 - w * w, 0.4 * w);
        Complex64::new(2.0, 0.0) + Complex64::new(1.0, 0.0) / z
    }

    fn grid(count: usize) -> Vec<f64> {
        (0..count).map(|k| 0.2 + 0.1 * k as f64).collect()
    }

    #[test]
    fn a_smooth_resonance_on_a_coarse_grid_has_no_spike() {
        let omega = grid(24);
        let data: Vec<DMatrix<Complex64>> = omega
            .iter()
            .map(|&w| DMatrix::from_element(1, 1, smooth(w)))
            .collect();
        let found = find(
            &omega,
            &data,
            &["heave".to_string()],
            &SpikeParams::default(),
        );
        assert!(found.is_empty(), "{found:?}");
    }

    #[test]
    fn a_one_point_jump_is_found_and_named() {
        let omega = grid(24);
        let mut data: Vec<DMatrix<Complex64>> = omega
            .iter()
            .map(|&w| DMatrix::from_element(1, 1, smooth(w)))
            .collect();
        // A jump of 40 % of the entry's scale at omega = 2.0 (index 18), where the curve is
        // flat: an irregular frequency's size.
        let scale = data.iter().map(|m| m[(0, 0)].norm()).fold(0.0, f64::max);
        data[18][(0, 0)] += Complex64::new(0.0, -0.4 * scale);
        let found = find(
            &omega,
            &data,
            &["heave".to_string()],
            &SpikeParams::default(),
        );
        assert_eq!(found.len(), 1, "{found:?}");
        assert_eq!(found[0].index, 18);
        assert!(found[0].reason.contains("heave"), "{}", found[0].reason);
    }

    #[test]
    fn negative_damping_is_a_spike() {
        let omega = grid(8);
        let mut data: Vec<DMatrix<Complex64>> = omega
            .iter()
            .map(|&w| DMatrix::from_element(1, 1, smooth(w)))
            .collect();
        // Im A~ > 0 is b < 0.
        data[0][(0, 0)].im = 5.0;
        let found = find(
            &omega,
            &data,
            &["heave".to_string()],
            &SpikeParams::default(),
        );
        assert_eq!(found.first().map(|s| s.index), Some(0), "{found:?}");
        assert!(found[0].reason.contains("negative damping"));
    }
}
