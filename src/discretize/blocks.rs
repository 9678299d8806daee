//! Systems of independent blocks, each driven by its own inputs: one small exponential per
//! block and step size ([`BlockDiscretizationCache`]), steps bounded by
//! [`MAX_PHASE_PER_STEP`].

use super::{
    check_scale, check_system, discretize_balanced, effective_phase, recently_used, skew_norm,
    DiscretizeError,
};
use nalgebra::DMatrix;
use num_complex::Complex64;
use std::ops::Range;

/// Most radians a block may oscillate through in one step of a [`BlockDiscretizationCache`].
/// Balanced, a step's error relative to its data (energy norm) grows with the phase of the
/// fastest oscillation, by at most 0.54 unit roundoffs per radian in the one-stage tests
/// (4.3e-11 at 1e6 rad, 9.0e-9 at 5e8 rad): about 1.2e-7 here. No f64 method does much better:
/// a relative change of one unit roundoff in the stiffness moves the phase by half as many
/// unit roundoffs.
pub const MAX_PHASE_PER_STEP: f64 = 1e9;

/// One block of a [`BlockDiscretizationCache`]: its states, its inputs, `A_j`, `B_j` and its
/// states' scales.
type DiscreteBlock = (
    Vec<usize>,
    Range<usize>,
    DMatrix<f64>,
    DMatrix<f64>,
    Vec<f64>,
);

/// A system of independent blocks, each driven by its own inputs: block j holds the states
/// `states_j` and obeys `z_j' = A_j z_j + B_j u_(inputs_j)`. A network's branches are such
/// blocks with one scalar input each (the branch speed `d_b . v`), a substructure one with the
/// hull velocities; a step costs the blocks' own sizes, `sum m_j (m_j + k_j)`, and a new step
/// size one small exponential per block instead of one of all states.
#[derive(Clone, Debug)]
pub struct BlockDiscretizationCache {
    state_count: usize,
    input_count: usize,
    blocks: Vec<DiscreteBlock>,
    capacity: usize,
    pub(super) entries: Vec<BlockDiscretization>,
    /// Per block: a bound on its fastest angular frequency (rad/s), see
    /// [`BlockDiscretizationCache::oscillation_bound`].
    oscillation_bounds: Vec<f64>,
    /// Per block, once a step needed them: the eigenvalues of its balanced matrix.
    modes: Vec<Option<Vec<Complex64>>>,
}

/// One step of a [`BlockDiscretizationCache`] system, stored flat for speed.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockDiscretization {
    /// Step size h.
    pub step: f64,
    /// Start of each block in `states` (one past the end last).
    starts: Vec<usize>,
    /// Start of each block's `Phi` (row-major m x m) in `phi`.
    phi_starts: Vec<usize>,
    /// Start of each block's `Gamma0`, `Gamma1` (row-major m x k) in `gamma0`, `gamma1`.
    gamma_starts: Vec<usize>,
    /// Each block's inputs.
    inputs: Vec<Range<usize>>,
    states: Vec<usize>,
    pub(super) phi: Vec<f64>,
    gamma0: Vec<f64>,
    gamma1: Vec<f64>,
}

impl BlockDiscretization {
    /// `next_j = Phi_j z_j + Gamma0_j u_j + Gamma1_j u'_j` for every block. `next` may not
    /// alias `z`.
    pub fn apply(&self, z: &[f64], input: &[f64], input_rate: &[f64], next: &mut [f64]) {
        let blocks = self.starts.len() - 1;
        assert!(input.len() == input_rate.len() && z.len() == next.len());
        for j in 0..blocks {
            let (start, end) = (self.starts[j], self.starts[j + 1]);
            let inputs = self.inputs[j].clone();
            let block = Block {
                states: &self.states[start..end],
                phi: &self.phi[self.phi_starts[j]..self.phi_starts[j + 1]],
                gamma0: &self.gamma0[self.gamma_starts[j]..self.gamma_starts[j + 1]],
                gamma1: &self.gamma1[self.gamma_starts[j]..self.gamma_starts[j + 1]],
            };
            if inputs.len() != 1 {
                block.apply_inputs(z, &input[inputs.clone()], &input_rate[inputs], next);
                continue;
            }
            let (u, du) = (input[inputs.start], input_rate[inputs.start]);
            // Fixed sizes (chains of 1 to 4 masses) unroll; others take the general loop.
            match end - start {
                2 => block.apply_fixed::<2>(z, u, du, next),
                4 => block.apply_fixed::<4>(z, u, du, next),
                6 => block.apply_fixed::<6>(z, u, du, next),
                8 => block.apply_fixed::<8>(z, u, du, next),
                _ => block.apply(z, u, du, next),
            }
        }
    }
}

/// One block's slices of a [`BlockDiscretization`].
struct Block<'a> {
    states: &'a [usize],
    phi: &'a [f64],
    gamma0: &'a [f64],
    gamma1: &'a [f64],
}

impl Block<'_> {
    fn apply_fixed<const M: usize>(&self, z: &[f64], u: f64, du: f64, next: &mut [f64]) {
        let states: &[usize] = &self.states[..M];
        let phi: &[f64] = &self.phi[..M * M];
        let (g0, g1) = (&self.gamma0[..M], &self.gamma1[..M]);
        let mut local = [0.0f64; M];
        for (l, &i) in local.iter_mut().zip(states) {
            *l = z[i];
        }
        for row in 0..M {
            let mut sum = g0[row] * u + g1[row] * du;
            for (p, x) in phi[row * M..row * M + M].iter().zip(&local) {
                sum += p * x;
            }
            next[states[row]] = sum;
        }
    }

    fn apply(&self, z: &[f64], u: f64, du: f64, next: &mut [f64]) {
        let m = self.states.len();
        for (row, &i) in self.states.iter().enumerate() {
            let phi_row = &self.phi[row * m..(row + 1) * m];
            let sum: f64 = phi_row
                .iter()
                .zip(self.states)
                .map(|(p, &k)| p * z[k])
                .sum();
            next[i] = sum + self.gamma0[row] * u + self.gamma1[row] * du;
        }
    }

    /// A block with several inputs (a substructure: the hull velocities along its span).
    fn apply_inputs(&self, z: &[f64], u: &[f64], du: &[f64], next: &mut [f64]) {
        let (m, k) = (self.states.len(), u.len());
        // A substructure's states are contiguous: a plain dense product.
        let first = self.states.first().copied().unwrap_or(0);
        let contiguous = self.states.iter().enumerate().all(|(j, &s)| s == first + j);
        let local = if contiguous {
            Some(&z[first..first + m])
        } else {
            None
        };
        for (row, &i) in self.states.iter().enumerate() {
            let phi_row = &self.phi[row * m..(row + 1) * m];
            let mut sum: f64 = match local {
                Some(local) => dot(phi_row, local),
                None => phi_row
                    .iter()
                    .zip(self.states)
                    .map(|(p, &s)| p * z[s])
                    .sum(),
            };
            let g0 = &self.gamma0[row * k..(row + 1) * k];
            let g1 = &self.gamma1[row * k..(row + 1) * k];
            for c in 0..k {
                sum += g0[c] * u[c] + g1[c] * du[c];
            }
            next[i] = sum;
        }
    }
}

/// `a . b` with four partial sums (lets the compiler use vector registers).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut partial = [0.0f64; 4];
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = a4
        .remainder()
        .iter()
        .zip(b4.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in a4.zip(b4) {
        for l in 0..4 {
            partial[l] += x[l] * y[l];
        }
    }
    (partial[0] + partial[1]) + (partial[2] + partial[3]) + tail
}

/// The block owning each of `count` items (states or inputs), refused unless the groups
/// partition `0..count`; `what` names the items in the error.
fn owners(
    count: usize,
    groups: impl Iterator<Item = Vec<usize>>,
    what: &str,
) -> Result<Vec<usize>, DiscretizeError> {
    let mut owner = vec![usize::MAX; count];
    for (j, group) in groups.enumerate() {
        for i in group {
            if i >= count || owner[i] != usize::MAX {
                return Err(DiscretizeError::Dimensions(format!(
                    "block {j}: {what} {i} is out of range or in two blocks"
                )));
            }
            owner[i] = j;
        }
    }
    if owner.contains(&usize::MAX) {
        return Err(DiscretizeError::Dimensions(format!(
            "the blocks do not cover every {what}"
        )));
    }
    Ok(owner)
}

impl BlockDiscretizationCache {
    /// Number of step sizes kept (masters usually use one or two).
    pub const DEFAULT_CAPACITY: usize = 4;

    /// The blocks of `z' = A z + B u`, block j with the states `blocks[j]` and the inputs
    /// (columns of `B`) `inputs[j]`, each discretized in the coordinates `scale_i z_i`
    /// (`discretize_balanced`; the square roots of a diagonal energy weight). Refused unless
    /// the blocks partition the states and the inputs, `A` couples no two blocks, every column
    /// of `B` is zero outside its block and every scale is finite and positive.
    pub fn new(
        a: &DMatrix<f64>,
        b: &DMatrix<f64>,
        blocks: &[Vec<usize>],
        inputs: &[Range<usize>],
        scale: &[f64],
    ) -> Result<Self, DiscretizeError> {
        check_system(a, b)?;
        let ns = a.nrows();
        check_scale(scale, ns)?;
        if inputs.len() != blocks.len() {
            return Err(DiscretizeError::Dimensions(format!(
                "{} input ranges for {} blocks",
                inputs.len(),
                blocks.len()
            )));
        }
        let input_owner = owners(
            b.ncols(),
            inputs.iter().map(|r| r.clone().collect::<Vec<_>>()),
            "input",
        )?;
        let owner = owners(ns, blocks.iter().cloned(), "state")?;
        for i in 0..ns {
            let coupled = (0..ns).any(|k| owner[k] != owner[i] && a[(i, k)] != 0.0);
            let driven = (0..b.ncols()).any(|c| owner[i] != input_owner[c] && b[(i, c)] != 0.0);
            if coupled || driven {
                return Err(DiscretizeError::Dimensions(format!(
                    "state {i} is coupled to another block"
                )));
            }
        }
        let blocks: Vec<DiscreteBlock> = blocks
            .iter()
            .zip(inputs)
            .map(|(states, range)| {
                let m = states.len();
                let a_j = DMatrix::from_fn(m, m, |r, c| a[(states[r], states[c])]);
                let b_j = DMatrix::from_fn(m, range.len(), |r, c| b[(states[r], range.start + c)]);
                let scale_j = states.iter().map(|&i| scale[i]).collect();
                (states.clone(), range.clone(), a_j, b_j, scale_j)
            })
            .collect();
        let oscillation_bounds = blocks
            .iter()
            .map(|(_, _, a, _, scale)| skew_norm(a, scale))
            .collect();
        Ok(BlockDiscretizationCache {
            state_count: ns,
            input_count: b.ncols(),
            oscillation_bounds,
            modes: vec![None; blocks.len()],
            blocks,
            capacity: Self::DEFAULT_CAPACITY,
            entries: Vec::with_capacity(Self::DEFAULT_CAPACITY),
        })
    }

    /// Number of states.
    pub fn state_count(&self) -> usize {
        self.state_count
    }

    /// Number of blocks.
    pub fn block_count(&self) -> usize {
        self.blocks.len()
    }

    /// Number of inputs.
    pub fn input_count(&self) -> usize {
        self.input_count
    }

    /// Bound on the fastest angular frequency (rad/s) of the blocks: the 1-norm of the
    /// skew-symmetric part of each balanced block `D A D^-1`, which bounds the imaginary parts
    /// of its eigenvalues (Bendixson). For a stage in energy coordinates it is `sqrt(k / m)`.
    pub fn oscillation_bound(&self) -> f64 {
        self.oscillation_bounds.iter().copied().fold(0.0, f64::max)
    }

    /// Refuses `step` if a mode of a block turns through more than [`MAX_PHASE_PER_STEP`]
    /// radians within it before it decays ([`effective_phase`]). Only blocks whose
    /// [`oscillation_bound`](Self::oscillation_bound) allows that get their eigenvalues
    /// computed (once; a block's size is bounded by the network's limits).
    fn check_phase(&mut self, step: f64) -> Result<(), DiscretizeError> {
        for (j, bound) in self.oscillation_bounds.iter().enumerate() {
            if bound * step <= MAX_PHASE_PER_STEP {
                continue;
            }
            let (_, _, a, _, scale) = &self.blocks[j];
            let modes = self.modes[j].get_or_insert_with(|| {
                let n = a.nrows();
                let balanced = DMatrix::from_fn(n, n, |r, c| a[(r, c)] * scale[r] / scale[c]);
                // Undecided eigenvalues: the bound itself, undamped.
                crate::numerics::eigenvalues(&balanced)
                    .unwrap_or_else(|| vec![Complex64::new(0.0, *bound)])
            });
            let worst = modes.iter().max_by(|x, y| {
                let phase = |l: &Complex64| effective_phase(l.im.abs(), -l.re, step);
                phase(x).total_cmp(&phase(y))
            });
            if let Some(mode) = worst {
                let (frequency, decay) = (mode.im.abs(), -mode.re);
                if effective_phase(frequency, decay, step) > MAX_PHASE_PER_STEP {
                    return Err(DiscretizeError::PhaseTooLarge {
                        step,
                        frequency,
                        decay,
                    });
                }
            }
        }
        Ok(())
    }

    /// The discretization for step h, computed once per step size while it stays among the
    /// last few used. It always carries `Gamma1`, so that the matrices (to the last bit) do
    /// not depend on whether the master ever used first-order hold. A step through more than
    /// [`MAX_PHASE_PER_STEP`] radians of the fastest oscillation is refused before any work.
    pub fn get(&mut self, step: f64) -> Result<&BlockDiscretization, DiscretizeError> {
        if !(step.is_finite() && step > 0.0) {
            return Err(DiscretizeError::BadStepSize(step));
        }
        self.check_phase(step)?;
        let blocks = &self.blocks;
        recently_used(
            &mut self.entries,
            self.capacity,
            step,
            |d| d.step,
            || {
                let mut d = BlockDiscretization {
                    step,
                    starts: vec![0],
                    phi_starts: vec![0],
                    gamma_starts: vec![0],
                    inputs: Vec::with_capacity(blocks.len()),
                    states: Vec::new(),
                    phi: Vec::new(),
                    gamma0: Vec::new(),
                    gamma1: Vec::new(),
                };
                for (states, inputs, a, b, scale) in blocks {
                    let one = discretize_balanced(a, b, step, true, scale)?;
                    d.states.extend_from_slice(states);
                    d.phi.extend(one.phi.transpose().iter());
                    d.gamma0.extend(one.gamma0.transpose().iter());
                    d.gamma1.extend(
                        one.gamma1
                            .as_ref()
                            .expect("first-order hold")
                            .transpose()
                            .iter(),
                    );
                    d.inputs.push(inputs.clone());
                    d.starts.push(d.states.len());
                    d.phi_starts.push(d.phi.len());
                    d.gamma_starts.push(d.gamma0.len());
                }
                Ok(d)
            },
        )
    }
}
