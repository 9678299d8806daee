//! Coupled path 2: a dictionary of 80 two-stage band-pass chains over the band gets PSD
//! weights at once; the `order` groups that carry the most response are kept, weighted and
//! refined.

use num_complex::Complex64;

use super::groups::GroupSet;
use super::weights::{psd_weights, DICTIONARY_PRECISION, PSD_PRECISION};
use super::CoupledState;
use crate::identify::problem::Problem;
use crate::identify::FitParams;
use crate::network::Network;

/// Band-pass two-stage chains (first damper tiny) over the band, plus a few with a normal
/// first damper (high-pass), as `GroupSet` with first mass 1.
pub(super) fn band_pass_dictionary(nu_lo: f64, nu_hi: f64) -> GroupSet {
    let count = 20;
    let mut theta = Vec::new();
    for i in 0..count {
        let f = i as f64 / (count - 1) as f64;
        let w = (nu_lo / 2.0) * (4.0 * nu_hi / nu_lo).powf(f);
        for (mu, ratio, zeta, c1) in [
            (0.3f64, 1.0f64, 0.5f64, 0.01f64),
            (1.0, 1.0, 0.3, 0.01),
            (0.3, 2.0, 0.5, 0.01),
            (0.3, 1.0, 0.5, 1.0),
        ] {
            let w2 = ratio * w;
            theta.extend([
                (w * w).ln(),
                (c1 * w).ln(),
                mu.ln(),
                (mu * w2 * w2).ln(),
                (2.0 * zeta * w2 * mu).ln(),
            ]);
        }
    }
    GroupSet { stages: 2, theta }
}

impl Problem {
    /// Coupled fit from a dictionary of band-pass two-stage chains: the PSD weights of the
    /// whole dictionary, the `order` groups that carry the most response, their PSD weights,
    /// then the joint refinement.
    pub(super) fn fit_coupled_dictionary(
        &self,
        order: usize,
        state: &mut CoupledState,
        params: &FitParams,
        tolerance: f64,
    ) -> (Option<Network>, usize) {
        let nu = &self.nu;
        let reduced = state.scope.reduced.clone();
        let target = &reduced.target;
        if state.dictionary.is_none() {
            let groups = band_pass_dictionary(nu[0], nu[nu.len() - 1]);
            let weights = psd_weights(nu, target, &groups, DICTIONARY_PRECISION);
            let sp = groups.params_per_group();
            let energy: Vec<f64> = (0..groups.count())
                .map(|p| {
                    let peak = nu
                        .iter()
                        .map(|&v| groups.shape(p, Complex64::new(0.0, v)).norm())
                        .fold(0.0, f64::max);
                    weights[p].norm() * peak
                })
                .collect();
            let mut ranked: Vec<usize> = (0..groups.count()).collect();
            ranked.sort_by(|&a, &b| energy[b].total_cmp(&energy[a]).then(a.cmp(&b)));
            let ranked = ranked
                .into_iter()
                .map(|p| {
                    (
                        groups.theta[p * sp..(p + 1) * sp].to_vec(),
                        weights[p].clone(),
                    )
                })
                .collect();
            state.dictionary = Some(ranked);
        }
        let ranked = state.dictionary.as_ref().map_or(&[][..], |d| &d[..]);
        if ranked.len() < order {
            return (None, 0);
        }
        let groups = GroupSet {
            stages: 2,
            theta: ranked[..order]
                .iter()
                .flat_map(|(t, _)| t.clone())
                .collect(),
        };
        let weights = psd_weights(nu, target, &groups, PSD_PRECISION);
        let (network, its) = self.refined_network(
            &state.scope,
            groups,
            weights,
            params,
            tolerance,
            f64::INFINITY,
        );
        (Some(network), its)
    }
}
