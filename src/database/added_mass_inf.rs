//! `A_inf` of a database that gives none, from the Kramers-Kronig relation between the added
//! mass and the damping of a causal radiation kernel (Ogilvie 1964):
//!
//! `a(omega) - A_inf = (2 / pi) PV integral_0^inf b(nu) / (nu^2 - omega^2) d nu`,
//!
//! so every frequency `omega_k` of the grid gives an estimate
//! `A_inf(k) = a(omega_k) - (2 / pi) PV integral ...`. The damping is taken linear between the
//! grid's points, zero at `omega = 0` (a 3D body radiates no energy in infinitely long waves),
//! and beyond the last point `b(omega_N) (omega_N / nu)^p` with `p` from the last two points
//! (clamped to 1..8). The estimate is the median over the upper half of the grid (where
//! `a - A_inf` is smallest), at most `MAX_ESTIMATE_FREQUENCIES` = 128 of its frequencies evenly
//! spread by index: each estimate integrates over the whole grid, so the cost is
//! `MAX_ESTIMATE_FREQUENCIES` times the rows, linear in them. How well the data fixes it: the
//! sum of the half range of the per-frequency estimates and the tail's share (the change when
//! the damping is cut at `omega_N` instead); both are reported.

use nalgebra::DMatrix;
use num_complex::Complex64;
use std::f64::consts::PI;

/// The estimate and how well the data fixes it.
#[derive(Clone, Debug)]
pub(crate) struct Estimate {
    /// `A_inf`, SI, symmetric.
    pub added_mass_inf: DMatrix<f64>,
    /// The uncertainty per entry, SI: the per-frequency estimates' half range plus the tail's
    /// share.
    pub spread: DMatrix<f64>,
    /// How many frequencies the median is over.
    pub frequencies_used: usize,
}

/// Most frequencies the median is over: beyond, every `k`-th of the upper half (evenly by
/// index), which keeps the estimate's cost linear in the grid.
pub(crate) const MAX_ESTIMATE_FREQUENCIES: usize = 128;

/// `PV integral_0^inf b(nu) / (nu^2 - w^2) d nu` for `b` linear between `(nodes, values)`
/// (`nodes[0] = 0`) and `b_N (w_N / nu)^p` beyond, and the same integral cut at the last
/// node; `w` a node other than the last.
fn principal_value(nodes: &[f64], values: &[f64], p: f64, w: f64) -> (f64, f64) {
    // Antiderivative of (alpha + beta nu) / (nu^2 - w^2): F = [(alpha + beta w) ln|nu - w| -
    // (alpha - beta w) ln|nu + w|] / (2 w); the ln 0 terms at nu = w cancel between the two
    // segments meeting there (b is continuous), so they are left out.
    let log_abs = |x: f64| if x == 0.0 { 0.0 } else { x.abs().ln() };
    let mut total = 0.0;
    for s in 0..nodes.len() - 1 {
        let (x0, x1) = (nodes[s], nodes[s + 1]);
        let beta = (values[s + 1] - values[s]) / (x1 - x0);
        let alpha = values[s] - beta * x0;
        let f = |x: f64| {
            ((alpha + beta * w) * log_abs(x - w) - (alpha - beta * w) * log_abs(x + w)) / (2.0 * w)
        };
        total += f(x1) - f(x0);
    }
    // Tail: nu = w_N / s, integral_0^1 b_N s^p w_N / (w_N^2 - w^2 s^2) ds (composite Gauss).
    let last = nodes[nodes.len() - 1];
    let b_last = values[values.len() - 1];
    let pieces = 32;
    let mut tail = 0.0;
    for piece in 0..pieces {
        let (a, b) = (
            piece as f64 / pieces as f64,
            (piece + 1) as f64 / pieces as f64,
        );
        for &(node, weight) in &crate::numerics::GAUSS_LEGENDRE_8 {
            let s = a + (b - a) * (node + 1.0) / 2.0;
            tail += weight * (b - a) / 2.0 * s.powf(p) * last / (last * last - w * w * s * s);
        }
    }
    (total + b_last * tail, total)
}

/// The tail exponent `p` of `b ~ nu^-p` from the last two points, clamped to 1..8 (2 when
/// they do not decay with one sign).
fn tail_exponent(omega: &[f64], damping: &[f64]) -> f64 {
    let n = omega.len();
    if n < 2 {
        return 2.0;
    }
    let (b0, b1) = (damping[n - 2], damping[n - 1]);
    if b0 * b1 <= 0.0 || b1.abs() >= b0.abs() {
        return 2.0;
    }
    (-(b1 / b0).ln() / (omega[n - 1] / omega[n - 2]).ln()).clamp(1.0, 8.0)
}

/// Estimates `A_inf` from `A~(omega)` on an ascending grid of at least 3 frequencies;
/// `None` with fewer.
pub(crate) fn estimate(omega: &[f64], added_mass: &[DMatrix<Complex64>]) -> Option<Estimate> {
    let count = omega.len();
    if count < 3 || added_mass.len() != count {
        return None;
    }
    let n = added_mass[0].nrows();
    // Frequencies used: the upper half, without the last (the tail's own node), at most
    // MAX_ESTIMATE_FREQUENCIES of them.
    let first = count / 2;
    let upper: Vec<usize> = (first.min(count - 2)..count - 1).collect();
    let used: Vec<usize> = if upper.len() <= MAX_ESTIMATE_FREQUENCIES {
        upper
    } else {
        let last = (upper.len() - 1) as f64;
        let steps = (MAX_ESTIMATE_FREQUENCIES - 1) as f64;
        (0..MAX_ESTIMATE_FREQUENCIES)
            .map(|k| upper[(k as f64 * last / steps).round() as usize])
            .collect()
    };
    let mut nodes = Vec::with_capacity(count + 1);
    nodes.push(0.0);
    nodes.extend_from_slice(omega);
    let mut estimate = DMatrix::zeros(n, n);
    let mut spread = DMatrix::zeros(n, n);
    for i in 0..n {
        for j in 0..n {
            let a: Vec<f64> = added_mass.iter().map(|m| m[(i, j)].re).collect();
            let b: Vec<f64> = added_mass
                .iter()
                .zip(omega)
                .map(|(m, w)| -m[(i, j)].im * w)
                .collect();
            let mut values = Vec::with_capacity(count + 1);
            values.push(0.0);
            values.extend_from_slice(&b);
            let p = tail_exponent(omega, &b);
            // Per used frequency: the estimate with the tail and without it.
            let (with_tail, without_tail): (Vec<f64>, Vec<f64>) = used
                .iter()
                .map(|&k| {
                    let (whole, cut) = principal_value(&nodes, &values, p, omega[k]);
                    (a[k] - 2.0 / PI * whole, a[k] - 2.0 / PI * cut)
                })
                .unzip();
            let estimates = |mut per_frequency: Vec<f64>| {
                per_frequency.sort_by(f64::total_cmp);
                let m = per_frequency.len();
                let median = if m % 2 == 1 {
                    per_frequency[m / 2]
                } else {
                    (per_frequency[m / 2 - 1] + per_frequency[m / 2]) / 2.0
                };
                (median, (per_frequency[m - 1] - per_frequency[0]) / 2.0)
            };
            let (median, half_range) = estimates(with_tail);
            let (without_tail, _) = estimates(without_tail);
            estimate[(i, j)] = median;
            spread[(i, j)] = half_range + (median - without_tail).abs();
        }
    }
    let symmetric = (&estimate + estimate.transpose()) / 2.0;
    let spread = spread.zip_map(&spread.transpose(), f64::max);
    Some(Estimate {
        added_mass_inf: symmetric,
        spread,
        frequencies_used: used.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A~ of a mass m0 hung on a spring k from the hull and damped by c to the ground:
    /// the hull's force `F = -k (q - x)`, `m0 x'' = k (q - x) - c x'`, and `F = omega^2 A~ q`:
    /// `A~ = A_inf - k (-m0 omega^2 + i omega c) / (omega^2 (k - m0 omega^2 + i omega c))`,
    /// from `A_inf + m0` at `omega = 0` to `A_inf`, with a damping that vanishes at both ends.
    fn branch(omega: f64, a_inf: f64, m0: f64, k: f64, c: f64) -> Complex64 {
        let w2 = omega * omega;
        let top = Complex64::new(-m0 * w2, omega * c) * k;
        let bottom = Complex64::new(k - m0 * w2, omega * c) * w2;
        Complex64::new(a_inf, 0.0) - top / bottom
    }

    #[test]
    fn a_causal_branch_gives_its_a_inf_back() {
        // A_inf = 1000 kg; branch m0 = 500 kg, natural frequency 1 rad/s, damping ratio 0.3:
        // a(omega) runs from 1500 kg to 1000 kg. Grid 0.1 .. 4 rad/s, 40 points.
        let (a_inf, m0): (f64, f64) = (1000.0, 500.0);
        let k = m0 * 1.0;
        let c = 2.0 * 0.3 * (k * m0).sqrt();
        let omega: Vec<f64> = (1..=40).map(|s| 0.1 * s as f64).collect();
        let added: Vec<DMatrix<Complex64>> = omega
            .iter()
            .map(|&w| DMatrix::from_element(1, 1, branch(w, a_inf, m0, k, c)))
            .collect();
        // The data is causal: the high frequencies' a differs from A_inf by 1-2 %.
        let last = added[39][(0, 0)].re;
        assert!((last - a_inf).abs() > 5.0, "{last}");
        let e = estimate(&omega, &added).unwrap();
        let error = e.added_mass_inf[(0, 0)] - a_inf;
        // Measured: within 0.3 % of A_inf; the spread bounds the error.
        assert!(error.abs() < 0.003 * a_inf, "{error}");
        assert!(
            e.spread[(0, 0)] >= error.abs() * 0.5,
            "{:?} {error}",
            e.spread
        );
    }

    #[test]
    fn a_dense_grid_is_estimated_from_a_bounded_number_of_frequencies() {
        // The causal branch above on 4000 frequencies (0.001 .. 4 rad/s): the median is over
        // MAX_ESTIMATE_FREQUENCIES of the 1999 upper-half frequencies, not all of them (each
        // costs a pass over the grid: 2000 passes were quadratic in the rows).
        let (a_inf, m0): (f64, f64) = (1000.0, 500.0);
        let c = 2.0 * 0.3 * m0;
        let omega: Vec<f64> = (1..=4000).map(|s| 0.001 * s as f64).collect();
        let added: Vec<DMatrix<Complex64>> = omega
            .iter()
            .map(|&w| DMatrix::from_element(1, 1, branch(w, a_inf, m0, m0, c)))
            .collect();
        let e = estimate(&omega, &added).unwrap();
        assert_eq!(e.frequencies_used, MAX_ESTIMATE_FREQUENCIES);
        // Measured: within 0.3 % of A_inf, as on the coarse grid.
        let error = e.added_mass_inf[(0, 0)] - a_inf;
        assert!(error.abs() < 0.003 * a_inf, "{error}");
    }

    #[test]
    fn too_few_frequencies_give_no_estimate() {
        let m = DMatrix::from_element(1, 1, Complex64::new(1.0, -1.0));
        assert!(estimate(&[1.0, 2.0], &[m.clone(), m]).is_none());
    }
}
