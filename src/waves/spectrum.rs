//! The JONSWAP spectrum (DNV-RP-C205) and its discretization into components.
//!
//! ```text
//! S(w) = (1 - 0.287 ln gamma) 5/16 Hs^2 wp^4 w^-5 exp(-5/4 (w / wp)^-4) gamma^exp(-(w - wp)^2 / (2 sigma^2 wp^2))
//! ```
//!
//! `wp = 2 pi / Tp`, `sigma = 0.07` for `w <= wp`, `0.09` above; gamma = 1 is
//! Pierson-Moskowitz. The range `[0.5, 6] wp` (intersected with the excitation table's band)
//! is cut into `N` bins of equal weight under the density `(S / m0 + 1 / width) / 2`: half
//! the resolution follows the energy (the peak), half is uniform (no bin is wider than
//! `2 width / N`, so forces whose `|X|^2` rises in the tail are sampled too). Bin `n` gets one
//! frequency uniform inside it, the amplitude `a_n = sqrt(2 S(w_n) dw_n)` (so `E[a_n^2 / 2]`
//! is the bin's energy exactly) and a phase uniform in `[0, 2 pi)`, drawn in that order, bin
//! after bin, from SplitMix64.

use super::{WaveError, WaveParams};
use crate::numerics::SplitMix64;
use std::f64::consts::PI;

/// The frequency range of a JONSWAP sea, as multiples of the peak frequency `wp`. Outside it
/// lies `A_gamma (e^-20 + 1 - e^(-5/4 / 6^4))` Hs^2/16, i.e. 9.6e-4 of m0 for gamma = 1 and
/// 6.3e-4 for gamma = 3.3 (Pierson-Moskowitz tails in closed form).
pub(crate) const SPECTRUM_RANGE: (f64, f64) = (0.5, 6.0);

/// Fine intervals for the spectrum's cumulative integral (at least; 8 per component above).
const FINE_INTERVALS: usize = 8192;

/// The JONSWAP spectral density `S(omega)` (m^2 s) of DNV-RP-C205 for significant height
/// `hs` (m), peak period `tp` (s) and peak enhancement `gamma` (module docs). Returns 0 for
/// `omega <= 0`; the other arguments are not checked (see [`WaveParams::validate`]).
pub(crate) fn jonswap(omega: f64, hs: f64, tp: f64, gamma: f64) -> f64 {
    if omega.is_nan() || omega <= 0.0 {
        return 0.0;
    }
    let wp = 2.0 * PI / tp;
    let sigma = if omega <= wp { 0.07 } else { 0.09 };
    let ratio = wp / omega;
    let ratio4 = ratio * ratio * ratio * ratio;
    let normalization = 1.0 - 0.287 * gamma.ln();
    let peak = gamma.powf((-(omega - wp).powi(2) / (2.0 * sigma * sigma * wp * wp)).exp());
    normalization * 5.0 / 16.0 * hs * hs * ratio4 / omega * (-1.25 * ratio4).exp() * peak
}

/// The components of a sea and what was said about them.
pub(super) struct Components {
    pub(crate) omega: Vec<f64>,
    pub(crate) amplitude: Vec<f64>,
    pub(crate) phase: Vec<f64>,
    /// `integral S` over the bins (the expected elevation variance).
    pub(crate) represented_m0: f64,
    /// `integral S` over all frequencies.
    pub(crate) spectrum_m0: f64,
    pub(crate) notes: Vec<String>,
}

/// Draws the JONSWAP components for `params` over [`SPECTRUM_RANGE`] intersected with `band`
/// (rad/s, the excitation table's band when there is one).
pub(super) fn discretize(
    params: &WaveParams,
    band: Option<(f64, f64)>,
) -> Result<Components, WaveError> {
    let (hs, tp, gamma) = (params.height, params.period, params.gamma);
    let spectrum = |w: f64| jonswap(w, hs, tp, gamma);
    let wp = 2.0 * PI / tp;
    let (low, high) = (SPECTRUM_RANGE.0 * wp, SPECTRUM_RANGE.1 * wp);
    let (start, end) = match band {
        Some((band_low, band_high)) => (low.max(band_low), high.min(band_high)),
        None => (low, high),
    };
    if start >= end {
        let (band_low, band_high) = band.unwrap_or((low, high));
        return Err(WaveError::Band {
            message: format!(
                "the JONSWAP spectrum (Tp = {tp} s) carries its energy over {low:.4}..{high:.4} \
                 rad/s ({}..{} omega_p), outside the excitation table's band \
                 {band_low:.4}..{band_high:.4} rad/s",
                SPECTRUM_RANGE.0, SPECTRUM_RANGE.1
            ),
        });
    }
    let count = params.components;
    let fine = FINE_INTERVALS.max(8 * count);
    let step = (end - start) / fine as f64;
    let mut cumulative = Vec::with_capacity(fine + 1);
    cumulative.push(0.0);
    let mut previous = spectrum(start);
    for i in 1..=fine {
        let value = spectrum(start + i as f64 * step);
        let last = cumulative[i - 1];
        cumulative.push(last + 0.5 * (previous + value) * step);
        previous = value;
    }
    let represented_m0 = cumulative[fine];
    let range_m0 = if (start, end) == (low, high) {
        represented_m0
    } else {
        trapezoid(&spectrum, low, high, fine)
    };
    let a_gamma = 1.0 - 0.287 * gamma.ln();
    let tails = a_gamma * hs * hs / 16.0
        * ((-1.25 / SPECTRUM_RANGE.0.powi(4)).exp() - (-1.25 / SPECTRUM_RANGE.1.powi(4)).exp_m1());
    let spectrum_m0 = range_m0 + tails;
    let mut notes = Vec::new();
    if (start, end) != (low, high) && spectrum_m0 > 0.0 {
        notes.push(format!(
            "JONSWAP: the excitation table's band cuts the spectrum to {start:.4}..{end:.4} rad/s \
             (of {low:.4}..{high:.4}): {:.3e} of m0 is left out of the sea (elevation and force)",
            (range_m0 - represented_m0) / spectrum_m0
        ));
    }
    // Equal weights of the density (S / m0 + 1 / (end - start)) / 2 (uniform if S = 0).
    let weight: Vec<f64> = cumulative
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let uniform = i as f64 / fine as f64;
            if represented_m0 > 0.0 {
                0.5 * (c / represented_m0 + uniform)
            } else {
                uniform
            }
        })
        .collect();
    let edges = bin_edges(&weight, start, step, count);
    let mut rng = SplitMix64::new(params.seed as i64 as u64);
    let mut omega = Vec::with_capacity(count);
    let mut amplitude = Vec::with_capacity(count);
    let mut phase = Vec::with_capacity(count);
    for bin in edges.windows(2) {
        let width = bin[1] - bin[0];
        let w = bin[0] + rng.uniform() * width;
        omega.push(w);
        amplitude.push((2.0 * spectrum(w) * width).sqrt());
        phase.push(2.0 * PI * rng.uniform());
    }
    Ok(Components {
        omega,
        amplitude,
        phase,
        represented_m0,
        spectrum_m0,
        notes,
    })
}

/// `count + 1` edges from `start` to the grid's end holding equal shares of the increasing
/// `weight` (0 at `start`, 1 at the end, on the fine grid of spacing `step`).
fn bin_edges(weight: &[f64], start: f64, step: f64, count: usize) -> Vec<f64> {
    let fine = weight.len() - 1;
    let mut edges = Vec::with_capacity(count + 1);
    edges.push(start);
    let mut i = 0;
    for n in 1..count {
        let target = n as f64 / count as f64;
        while i + 1 < fine && weight[i + 1] < target {
            i += 1;
        }
        let rise = weight[i + 1] - weight[i];
        let fraction = ((target - weight[i]) / rise).clamp(0.0, 1.0);
        edges.push(start + (i as f64 + fraction) * step);
    }
    edges.push(start + fine as f64 * step);
    edges
}

fn trapezoid(f: &dyn Fn(f64) -> f64, a: f64, b: f64, intervals: usize) -> f64 {
    let step = (b - a) / intervals as f64;
    let inner: f64 = (1..intervals).map(|i| f(a + i as f64 * step)).sum();
    step * (0.5 * (f(a) + f(b)) + inner)
}
