//! One-DOF forms (series chain, parallel bank): Levenberg-Marquardt on the log stage values
//! `[ln m, ln k, ln c]` with the analytic Jacobian of the chain recursion, orders 1, 2, ...
//! from continuation and grid starts, then seeded random restarts (see [`crate::identify`]).
//! Normalized units: frequencies over `omega_ref`, masses over `s = s_1`.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::chain::{chain_response, LOG_BOUND};
use super::problem::{fastest_rate, keep_best, Problem};
use super::{FitParams, IdentifyError};
use crate::network::{Branch, Network, NetworkForm, Stage};
use crate::numerics::{levenberg_marquardt, nnls, LeastSquares, SplitMix64};

/// Random restarts are tried only if the best deterministic start is within this factor of
/// the tolerance.
pub(super) const RESTART_GATE: f64 = 4.0;

impl Problem {
    /// One-DOF forms: orders 1, 2, ... (see the module docs). Returns the order, the network
    /// and the LM iterations.
    pub(super) fn fit_single_dof(
        &self,
        params: &FitParams,
        form: NetworkForm,
        tolerance: f64,
    ) -> Result<(usize, Network, usize), IdentifyError> {
        let chain = form == NetworkForm::SeriesChain;
        // A fixed order still climbs from order 1: each order warm-starts the next.
        let last = params.order.unwrap_or(params.max_order);
        let mut iterations = 0;
        let mut best: Option<(f64, usize, Network)> = None;
        let mut over_fit = None;
        let mut previous: Option<Vec<Vec<Stage>>> = None;
        for order in 1..=last {
            let candidate = params.order.is_none() || order == last;
            let (stages, its) = self.fit_scalar(
                chain,
                order,
                previous.as_ref(),
                params,
                tolerance,
                candidate,
            );
            iterations += its;
            let network = self.scalar_network(&stages, form);
            previous = Some(stages);
            if !candidate {
                continue;
            }
            let rate = fastest_rate(&network);
            if rate > self.rate_limit() {
                over_fit = Some((order, rate));
                continue;
            }
            let err = self.max_relative_error(&network);
            let met = err <= tolerance;
            keep_best(&mut best, (err, order, network));
            if met {
                break;
            }
        }
        let (_, order, network) = best.ok_or_else(|| match over_fit {
            Some((order, rate)) => self.over_fit_error(order, rate),
            None => {
                IdentifyError::InvalidParams("no order could be fitted within max_order".into())
            }
        })?;
        Ok((order, network, iterations))
    }

    /// Normalized one-DOF target.
    pub(super) fn scalar_target(&self) -> Vec<Complex64> {
        self.target.iter().map(|m| m[(0, 0)]).collect()
    }

    /// Network from normalized one-DOF stages.
    pub(super) fn scalar_network(&self, stages: &[Vec<Stage>], form: NetworkForm) -> Network {
        let s = self.scale[0];
        let w = self.omega_ref;
        let branches = stages
            .iter()
            .map(|chain| Branch {
                direction: DVector::from_element(1, 1.0),
                stages: chain
                    .iter()
                    .map(|st| Stage {
                        mass: st.mass * s,
                        stiffness: st.stiffness * s * w * w,
                        damping: st.damping * s * w,
                    })
                    .collect(),
            })
            .collect();
        Network {
            substructures: Vec::new(),
            dof_names: self.dof_names.clone(),
            added_mass_inf: self.added_mass_inf.clone(),
            branches,
            rho: self.rho,
            g: self.g,
            form,
        }
    }

    /// Fits one order of a one-DOF form; returns normalized stages and LM iterations.
    pub(super) fn fit_scalar(
        &self,
        chain: bool,
        order: usize,
        previous: Option<&Vec<Vec<Stage>>>,
        params: &FitParams,
        tolerance: f64,
        allow_restarts: bool,
    ) -> (Vec<Vec<Stage>>, usize) {
        let target = self.scalar_target();
        let nu = &self.nu;
        let (nu_lo, nu_hi) = (nu[0], nu[nu.len() - 1]);
        let layout: Vec<usize> = if chain { vec![order] } else { vec![1; order] };
        let model = ChainModel {
            nu,
            target: &target,
            layout: layout.clone(),
        };
        // Zero-frequency mass estimate: Re of the target at the lowest band frequency.
        let low_mass = target[0]
            .re
            .max(0.05 * target.iter().map(|t| t.norm()).fold(0.0, f64::max));
        let mut starts: Vec<Vec<Vec<Stage>>> = Vec::new();
        if let Some(prev) = previous.filter(|p| count_stages(p) + 1 == order) {
            // Continuation: add a stage (chain end) or a branch where the residual is largest.
            let worst = worst_frequency(nu, &target, |s| chain_dynamic_mass(prev, s));
            for (factor, zeta) in [(1.0, 0.5), (0.3, 0.5), (3.0, 0.5), (1.0, 1.5)] {
                let mut start = prev.clone();
                let nu_n = (worst * factor).clamp(nu_lo * 0.3, nu_hi * 3.0);
                let m = 0.1 * low_mass;
                let stage = unit_stage(nu_n, zeta, m);
                if chain {
                    start[0].push(stage);
                } else {
                    start.push(vec![stage]);
                }
                starts.push(start);
            }
        }
        for zeta in [0.5, 1.5] {
            for reversed in [false, true] {
                if !chain && reversed {
                    continue;
                }
                let mut stages = Vec::with_capacity(order);
                for j in 0..order {
                    let f = (j as f64 + 0.5) / order as f64;
                    let f = if reversed { 1.0 - f } else { f };
                    let nu_n = nu_lo.powf(1.0 - f) * nu_hi.powf(f);
                    let m = low_mass * 0.5f64.powi(j as i32 + 1) * if chain { 1.0 } else { 2.0 };
                    stages.push(unit_stage(nu_n, zeta, m));
                }
                if chain {
                    starts.push(vec![stages]);
                } else {
                    starts.push(bank_with_nnls_masses(nu, &target, stages));
                }
            }
        }
        let mut iterations = 0;
        let mut best: Option<(f64, DVector<f64>)> = None;
        let run =
            |x0: DVector<f64>, iterations: &mut usize, best: &mut Option<(f64, DVector<f64>)>| {
                let result = levenberg_marquardt(&model, x0, params.max_iterations, LOG_BOUND);
                *iterations += result.iterations;
                if !matches!(&best, Some((c, _)) if *c <= result.cost) {
                    *best = Some((result.cost, result.x));
                }
            };
        for start in &starts {
            run(stages_to_params(start), &mut iterations, &mut best);
        }
        let max_error = |x: &DVector<f64>| {
            let stages = params_to_stages(x, &layout);
            nu.iter()
                .zip(&target)
                .map(|(&v, t)| (chain_dynamic_mass(&stages, Complex64::new(0.0, v)) - t).norm())
                .fold(0.0, f64::max)
        };
        let met = |best: &Option<(f64, DVector<f64>)>| {
            best.as_ref()
                .is_some_and(|(_, x)| max_error(x) <= tolerance)
        };
        // Random restarts at low orders (cheap), or when the deterministic starts came close.
        let close = order <= 3
            || best
                .as_ref()
                .is_some_and(|(_, x)| max_error(x) <= RESTART_GATE * tolerance);
        if allow_restarts && order >= 2 && close && !met(&best) {
            let mut rng = SplitMix64::new(params.seed ^ (order as u64).wrapping_mul(0x9E37_79B9));
            for _ in 0..params.restarts {
                let mut stages = Vec::with_capacity(order);
                for _ in 0..order {
                    let nu_n = (nu_lo / 3.0) * (9.0 * nu_hi / nu_lo).powf(rng.uniform());
                    let zeta = 0.05 * 60f64.powf(rng.uniform());
                    let m = low_mass * 0.01 * 200f64.powf(rng.uniform());
                    stages.push(unit_stage(nu_n, zeta, m));
                }
                let start = if chain {
                    vec![stages]
                } else {
                    stages.into_iter().map(|s| vec![s]).collect()
                };
                run(stages_to_params(&start), &mut iterations, &mut best);
                if met(&best) {
                    break;
                }
            }
        }
        let x = best
            .map(|(_, x)| x)
            .unwrap_or_else(|| stages_to_params(&starts[0]));
        (params_to_stages(&x, &layout), iterations)
    }
}

pub(super) fn count_stages(stages: &[Vec<Stage>]) -> usize {
    stages.iter().map(|b| b.len()).sum()
}

/// Stage with unit-mass natural frequency `nu_n` and damping ratio `zeta`, scaled to mass `m`.
pub(super) fn unit_stage(nu_n: f64, zeta: f64, m: f64) -> Stage {
    Stage {
        mass: m,
        stiffness: m * nu_n * nu_n,
        damping: m * 2.0 * zeta * nu_n,
    }
}

/// `g(s) = (k + c s) / (s^2 + c s + k)`: dynamic mass of a one-stage branch of unit mass.
pub(super) fn unit_shape(k: f64, c: f64, s: Complex64) -> Complex64 {
    let num = Complex64::new(k, 0.0) + s * c;
    num / (s * s + num)
}

/// Sum of the chains' dynamic masses (one DOF, unit directions).
pub(super) fn chain_dynamic_mass(stages: &[Vec<Stage>], s: Complex64) -> Complex64 {
    stages
        .iter()
        .map(|chain| {
            let mut beyond = Complex64::new(0.0, 0.0);
            for st in chain.iter().rev() {
                let node = beyond + st.mass;
                let z = Complex64::new(st.stiffness, 0.0) + s * st.damping;
                beyond = node * z / (z + s * s * node);
            }
            beyond
        })
        .sum()
}

/// Normalized frequency where `|target - model|` is largest.
pub(super) fn worst_frequency<F: Fn(Complex64) -> Complex64>(
    nu: &[f64],
    target: &[Complex64],
    model: F,
) -> f64 {
    let mut worst = (0.0, nu[0]);
    for (&v, t) in nu.iter().zip(target) {
        let e = (model(Complex64::new(0.0, v)) - t).norm();
        if e > worst.0 {
            worst = (e, v);
        }
    }
    worst.1
}

/// One-stage branches with the given frequencies and damping ratios; masses by NNLS.
pub(super) fn bank_with_nnls_masses(
    nu: &[f64],
    target: &[Complex64],
    stages: Vec<Stage>,
) -> Vec<Vec<Stage>> {
    let k = stages.len();
    let rows = 2 * nu.len();
    let mut a = DMatrix::zeros(rows, k);
    let mut b = DVector::zeros(rows);
    for (i, &v) in nu.iter().enumerate() {
        let s = Complex64::new(0.0, v);
        for (p, st) in stages.iter().enumerate() {
            let g = unit_shape(st.stiffness / st.mass, st.damping / st.mass, s);
            a[(2 * i, p)] = g.re;
            a[(2 * i + 1, p)] = g.im;
        }
        b[2 * i] = target[i].re;
        b[2 * i + 1] = target[i].im;
    }
    let masses = nnls(&a, &b);
    let floor = 1e-3 * masses.amax().max(1e-6);
    stages
        .iter()
        .zip(masses.iter())
        .map(|(st, &m)| {
            let m = m.max(floor);
            vec![Stage {
                mass: m,
                stiffness: st.stiffness / st.mass * m,
                damping: st.damping / st.mass * m,
            }]
        })
        .collect()
}

pub(super) fn stages_to_params(stages: &[Vec<Stage>]) -> DVector<f64> {
    DVector::from_iterator(
        3 * count_stages(stages),
        stages
            .iter()
            .flatten()
            .flat_map(|s| [s.mass.ln(), s.stiffness.ln(), s.damping.ln()]),
    )
}

pub(super) fn params_to_stages(x: &DVector<f64>, layout: &[usize]) -> Vec<Vec<Stage>> {
    let mut k = 0;
    layout
        .iter()
        .map(|&len| {
            (0..len)
                .map(|_| {
                    let s = Stage {
                        mass: x[k].exp(),
                        stiffness: x[k + 1].exp(),
                        damping: x[k + 2].exp(),
                    };
                    k += 3;
                    s
                })
                .collect()
        })
        .collect()
}

/// One-DOF chains along the unit direction, log parameters `[ln m, ln k, ln c]` per stage.
pub(super) struct ChainModel<'a> {
    nu: &'a [f64],
    target: &'a [Complex64],
    layout: Vec<usize>,
}

impl LeastSquares for ChainModel<'_> {
    fn residual_count(&self) -> usize {
        2 * self.nu.len()
    }

    fn evaluate(
        &self,
        x: &DVector<f64>,
        r: &mut DVector<f64>,
        mut jacobian: Option<&mut DMatrix<f64>>,
    ) {
        let values: Vec<f64> = x.iter().map(|v| v.exp()).collect();
        let mut grad = vec![Complex64::new(0.0, 0.0); values.len()];
        for (i, (&v, t)) in self.nu.iter().zip(self.target).enumerate() {
            let s = Complex64::new(0.0, v);
            let mut total = Complex64::new(0.0, 0.0);
            let mut offset = 0;
            for &len in &self.layout {
                let range = offset..offset + 3 * len;
                if let Some(jac) = jacobian.as_deref_mut() {
                    total +=
                        chain_response(&values[range.clone()], s, Some(&mut grad[range.clone()]));
                    for q in range {
                        jac[(2 * i, q)] = grad[q].re;
                        jac[(2 * i + 1, q)] = grad[q].im;
                    }
                } else {
                    total += chain_response(&values[range], s, None);
                }
                offset += 3 * len;
            }
            let e = total - t;
            r[2 * i] = e.re;
            r[2 * i + 1] = e.im;
        }
    }
}
