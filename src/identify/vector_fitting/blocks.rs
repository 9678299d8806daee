//! The fit block by block ([`super::passive_block_vector_fit`]): the normalized data reduced
//! to the subspace it spans and split into invariant blocks, each fitted with its own poles
//! and passive residues, the model their sum.

use super::{
    enforce, Enforcement, FrequencyResponse, IdentifyError, Poles, Problem, RationalFit,
    VectorFitParams, REFINEMENT_STEP, REFINEMENT_TOLERANCE,
};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// The normalized data of a fit split into its invariant blocks (see
/// [`super::passive_block_vector_fit`]); each block can be fitted on its own, with its own poles.
pub struct Blocks {
    problem: Problem,
    target: Vec<DMatrix<Complex64>>,
    blocks: Vec<(Problem, DMatrix<Complex64>)>,
}

/// The passive fit of one block ([`Blocks::fit`]), in normalized units, mapped to all DOFs.
#[derive(Clone, Debug)]
pub struct BlockFit {
    /// The block's poles in units of [`Blocks::omega_ref`].
    pub poles: Poles,
    residues: Vec<DMatrix<Complex64>>,
    /// How the block's fit was made passive.
    pub enforcement: Enforcement,
    /// The block's own largest error (normalized, in the original DOFs).
    pub error: f64,
    /// States of the block's realization (the block's dimension per pole).
    pub states: usize,
}

impl Blocks {
    /// The data of `response` in the band of `params`, reduced to the subspace it spans and
    /// split into invariant blocks (couplings of at most `params.block_coupling` dropped);
    /// blocks whose data stays within that budget everywhere are left out.
    pub fn new(
        response: &FrequencyResponse,
        params: &VectorFitParams,
    ) -> Result<Blocks, IdentifyError> {
        let problem = Problem::new(response, params)?;
        let n = problem.n;
        let target: Vec<DMatrix<Complex64>> = (0..problem.s.len())
            .map(|k| {
                let mut t = DMatrix::zeros(n, n);
                for (e, &(i, j)) in problem.pairs.iter().enumerate() {
                    t[(i, j)] = problem.entries[e][k];
                    t[(j, i)] = problem.entries[e][k];
                }
                t
            })
            .collect();
        // The subspace the data spans (Gram matrix of the real and imaginary parts).
        let mut gram = DMatrix::<f64>::zeros(n, n);
        for t in &target {
            let (re, im) = (t.map(|z| z.re), t.map(|z| z.im));
            gram += &re * re.transpose() + &im * im.transpose();
        }
        let eigen = crate::numerics::symmetric_eigen(&gram);
        let largest = eigen.eigenvalues.max();
        let kept: Vec<usize> = (0..n)
            .filter(|&i| eigen.eigenvalues[i] > 1e-12 * largest)
            .collect();
        let span = DMatrix::from_fn(n, kept.len(), |i, c| eigen.eigenvectors[(i, kept[c])]);
        let reduced: Vec<DMatrix<Complex64>> = target
            .iter()
            .map(|t| {
                let q = span.map(|x| Complex64::new(x, 0.0));
                q.transpose() * t * &q
            })
            .collect();
        let mut blocks = Vec::new();
        for block in noisy_invariant_blocks(&reduced, &span, params.block_coupling) {
            let basis = &span * block; // n x d, orthonormal
            let d = basis.ncols();
            let q = basis.map(|x| Complex64::new(x, 0.0));
            let block_target: Vec<DMatrix<Complex64>> =
                target.iter().map(|t| q.transpose() * t * &q).collect();
            let pairs: Vec<(usize, usize)> =
                (0..d).flat_map(|i| (i..d).map(move |j| (i, j))).collect();
            let entries: Vec<DVector<Complex64>> = pairs
                .iter()
                .map(|&(i, j)| {
                    DVector::from_iterator(
                        block_target.len(),
                        block_target.iter().map(|t| t[(i, j)]),
                    )
                })
                .collect();
            let largest = entries
                .iter()
                .flat_map(|e| e.iter().map(|z| z.norm()))
                .fold(0.0, f64::max);
            if largest <= params.block_coupling {
                continue;
            }
            let sub = Problem {
                n: d,
                s: problem.s.clone(),
                pairs,
                entries,
                scales: DVector::from_element(d, 1.0),
                omega_ref: 1.0,
            };
            blocks.push((sub, q));
        }
        Ok(Blocks {
            problem,
            target,
            blocks,
        })
    }

    /// The frequency unit of the normalized poles (rad/s).
    pub fn omega_ref(&self) -> f64 {
        self.problem.omega_ref
    }

    /// The number of blocks fitted.
    pub fn len(&self) -> usize {
        self.blocks.len()
    }

    /// Whether no block carries data above the budget.
    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }

    /// The dimension of block `b`.
    pub fn dimension(&self, b: usize) -> usize {
        self.blocks[b].0.n
    }

    /// The passive fit of block `b` with the poles of `params` (its band and margin are the
    /// ones [`Blocks::new`] was made with).
    pub fn fit(&self, b: usize, params: &VectorFitParams) -> BlockFit {
        let sub = &self.blocks[b].0;
        let poles = sub.poles(params);
        let (x, enforcement) = enforce(sub, &poles, params);
        self.block_fit(b, &poles, &x, enforcement)
    }

    /// Moves the poles of `fit` (block `b`) to lower the error of the passive fit: the
    /// relocation places them for the free fit, and where the passivity constraints bind
    /// (data whose damping vanishes in the band, as a submerged body's at high frequency)
    /// other poles fit better under them. Nelder-Mead (`src/numerics/nelder_mead.rs`) over
    /// the logarithms of each pole's decay rate and frequency, each candidate's residues
    /// enforced passive as in [`Blocks::fit`], at most `evaluations` enforcements. Returns
    /// the better of `fit` and the refined fit.
    pub fn refine(
        &self,
        b: usize,
        fit: &BlockFit,
        params: &VectorFitParams,
        evaluations: usize,
    ) -> BlockFit {
        let sub = &self.blocks[b].0;
        let start: Vec<f64> = fit
            .poles
            .iter()
            .flat_map(|p| {
                if p.im == 0.0 {
                    vec![(-p.re).ln()]
                } else {
                    vec![(-p.re).ln(), p.im.ln()]
                }
            })
            .collect();
        let layout: Vec<bool> = fit.poles.iter().map(|p| p.im != 0.0).collect();
        let poles_of = |v: &[f64]| -> Poles {
            let mut at = 0;
            layout
                .iter()
                .map(|&pair| {
                    let re = -v[at].exp();
                    at += 1;
                    if pair {
                        at += 1;
                        Complex64::new(re, v[at - 1].exp())
                    } else {
                        Complex64::new(re, 0.0)
                    }
                })
                .collect()
        };
        let mut objective = |v: &[f64]| {
            let (_, enforcement) = enforce(sub, &poles_of(v), params);
            if enforcement.passive {
                enforcement.error
            } else {
                f64::INFINITY
            }
        };
        let minimum = crate::numerics::nelder_mead(
            &mut objective,
            &start,
            REFINEMENT_STEP,
            REFINEMENT_TOLERANCE * fit.error,
            evaluations,
        );
        if !minimum.value.is_finite() {
            return fit.clone();
        }
        let poles = poles_of(&minimum.x);
        let (x, enforcement) = enforce(sub, &poles, params);
        let refined = self.block_fit(b, &poles, &x, enforcement);
        if refined.enforcement.passive && refined.error < fit.error {
            refined
        } else {
            fit.clone()
        }
    }

    /// The block fit of poles and passive coefficients `x`, mapped to all DOFs.
    fn block_fit(
        &self,
        b: usize,
        poles: &Poles,
        x: &DMatrix<f64>,
        enforcement: Enforcement,
    ) -> BlockFit {
        let (sub, q) = &self.blocks[b];
        let model = sub.model(poles, x, 0.0, true);
        let residues: Vec<DMatrix<Complex64>> = model
            .residues
            .iter()
            .map(|r| q * r * q.transpose())
            .collect();
        // The block's own error in the original DOFs: Q (model - data) Q^T.
        let mut error: f64 = 0.0;
        for k in 0..sub.s.len() {
            let mut data = DMatrix::zeros(sub.n, sub.n);
            for (e, &(i, j)) in sub.pairs.iter().enumerate() {
                data[(i, j)] = sub.entries[e][k];
                data[(j, i)] = sub.entries[e][k];
            }
            let g = model.evaluate(sub.s[k].im) - data;
            error = error.max(
                (q * g * q.transpose())
                    .iter()
                    .map(|z| z.norm())
                    .fold(0.0, f64::max),
            );
        }
        let states = model.pole_count() * sub.n;
        BlockFit {
            poles: model.poles,
            residues,
            enforcement,
            error,
            states,
        }
    }

    /// The sum of the blocks' fits (SI), its `max_error` against all of the data.
    pub fn assemble(&self, fits: &[&BlockFit]) -> RationalFit {
        let problem = &self.problem;
        let n = problem.n;
        let poles: Poles = fits.iter().flat_map(|f| f.poles.iter().copied()).collect();
        let residues: Vec<DMatrix<Complex64>> = fits
            .iter()
            .flat_map(|f| f.residues.iter().cloned())
            .collect();
        let normalized = RationalFit {
            poles: poles.clone(),
            residues: residues.clone(),
            dof_scales: DVector::from_element(n, 1.0),
            max_error: 0.0,
        };
        let mut max_error: f64 = 0.0;
        for (k, t) in self.target.iter().enumerate() {
            let g = normalized.evaluate(problem.s[k].im);
            max_error = max_error.max((g - t).iter().map(|z| z.norm()).fold(0.0, f64::max));
        }
        let scales = problem.scales.clone();
        let si = |r: &DMatrix<Complex64>| {
            DMatrix::from_fn(n, n, |i, j| {
                r[(i, j)] * (scales[i] * scales[j]).sqrt() * problem.omega_ref
            })
        };
        RationalFit {
            poles: poles.iter().map(|p| p * problem.omega_ref).collect(),
            residues: residues.iter().map(si).collect(),
            dof_scales: problem.scales.clone(),
            max_error,
        }
    }
}

/// The invariant blocks of the reduced target ([`crate::identify`], module docs) of noisy
/// data: for each commutant threshold (1e-6 .. 1e-2 of the largest singular value) the blocks,
/// then the two blocks coupled most merged until the couplings dropped are at most `budget`
/// (normalized, in the original DOFs through `span`); the most blocks win. One block (the
/// identity) if no split keeps within the budget.
fn noisy_invariant_blocks(
    reduced: &[DMatrix<Complex64>],
    span: &DMatrix<f64>,
    budget: f64,
) -> Vec<DMatrix<f64>> {
    use super::super::coupled::blocks::{
        invariant_blocks_with_gap, BLOCK_GAP, COMMUTANT_THRESHOLD,
    };
    let r = span.ncols();
    let complex = |m: &DMatrix<f64>| m.map(|x| Complex64::new(x, 0.0));
    let span_c = complex(span);
    // Largest normalized entry of span Q_a Q_a^T T Q_b Q_b^T span^T over the band.
    let coupling = |a: &DMatrix<f64>, b: &DMatrix<f64>| {
        let (pa, pb) = (complex(&(a * a.transpose())), complex(&(b * b.transpose())));
        reduced
            .iter()
            .map(|t| {
                (&span_c * &pa * t * &pb * span_c.transpose())
                    .iter()
                    .map(|z| z.norm())
                    .fold(0.0, f64::max)
            })
            .fold(0.0, f64::max)
    };
    let mut best = vec![DMatrix::identity(r, r)];
    let mut threshold = COMMUTANT_THRESHOLD;
    while threshold <= 1e-2 * (1.0 + 1e-9) {
        let mut blocks =
            invariant_blocks_with_gap(reduced, threshold, BLOCK_GAP.max(10.0 * threshold));
        threshold *= 10.0;
        while blocks.len() > best.len() {
            // The pair coupled most; the split is kept when even that one is within budget.
            let mut worst = (0.0, 0, 0);
            for i in 0..blocks.len() {
                for j in i + 1..blocks.len() {
                    let c = coupling(&blocks[i], &blocks[j]);
                    if c > worst.0 {
                        worst = (c, i, j);
                    }
                }
            }
            if worst.0 <= budget {
                best = blocks;
                break;
            }
            let (_, i, j) = worst;
            let merged = DMatrix::from_fn(r, blocks[i].ncols() + blocks[j].ncols(), |row, c| {
                if c < blocks[i].ncols() {
                    blocks[i][(row, c)]
                } else {
                    blocks[j][(row, c - blocks[i].ncols())]
                }
            });
            blocks.remove(j);
            blocks[i] = merged;
        }
    }
    best
}
