//! Exact discretization of `z' = A z + B u` over one communication step h.
//!
//! With the input held (zero-order hold, ZOH) or ramped (first-order hold, FOH, when the
//! master gives the input derivative `u'`) over the step,
//!
//! ```text
//! z(t + h) = Phi z(t) + Gamma0 u(t) + Gamma1 u'(t)
//! Phi    = exp(A h)
//! Gamma0 = integral_0^h exp(A s) ds B
//! Gamma1 = integral_0^h exp(A (h - s)) s ds B
//! ```
//!
//! is exact for those inputs. All three blocks come from one exponential of an augmented
//! matrix (Van Loan):
//!
//! ```text
//!        [A  B  0]     [Phi  Gamma0  Gamma1]
//! exp(h  [0  0  I]) =  [0    I       h I   ]
//!        [0  0  0]     [0    0       I     ]
//! ```
//!
//! (the last block row and column are dropped for ZOH). The exponential is computed by
//! scaling and squaring with diagonal Pade approximants of degree 3, 5, 7, 9 or 13, chosen by
//! the 1-norm as in Higham, "The scaling and squaring method for the matrix exponential
//! revisited" (SIAM J. Matrix Anal. Appl. 26, 2005): backward error below the unit roundoff.
//!
//! [`BlockDiscretizationCache`] keeps the last few step sizes of a system of independent
//! blocks, each driven by one scalar input (a network's branches, driven by their speeds
//! `d_b . v`): one small exponential per block, and a step costs the blocks' own sizes.

use std::ops::Range;

use nalgebra::DMatrix;
use num_complex::Complex64;
use std::fmt;

/// Why a step could not be discretized.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum DiscretizeError {
    /// The step size is not a finite positive number.
    BadStepSize(f64),
    /// The matrices do not fit together.
    Dimensions(String),
    /// The exponential produced non-finite numbers or a singular Pade denominator.
    NotFinite,
    /// A mode oscillates through more than [`MAX_PHASE_PER_STEP`] radians within one step
    /// before it decays.
    PhaseTooLarge {
        /// Step size h.
        step: f64,
        /// The mode's angular frequency (rad/s).
        frequency: f64,
        /// Its decay rate (1/s).
        decay: f64,
    },
}

impl fmt::Display for DiscretizeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DiscretizeError::BadStepSize(h) => {
                write!(f, "step size {h} is not a finite positive number")
            }
            DiscretizeError::Dimensions(what) => write!(f, "dimension mismatch: {what}"),
            DiscretizeError::NotFinite => {
                write!(
                    f,
                    "the matrix exponential is not finite (step size too large?)"
                )
            }
            DiscretizeError::PhaseTooLarge {
                step,
                frequency,
                decay,
            } => write!(
                f,
                "step size {step:e} s: a mode of the network oscillates at {frequency:e} rad/s \
                 (about sqrt(k/m) of a stiff stage) and decays at {decay:e} 1/s, {:e} rad \
                 within the step, beyond {MAX_PHASE_PER_STEP:e} rad (MAX_PHASE_PER_STEP): \
                 rounding would cost more than about 1e-7 of the step's value; use steps of \
                 at most {:e} s",
                effective_phase(*frequency, *decay, *step),
                MAX_PHASE_PER_STEP / frequency
            ),
        }
    }
}

impl std::error::Error for DiscretizeError {}

const PADE3: [f64; 4] = [120.0, 60.0, 12.0, 1.0];
const PADE5: [f64; 6] = [30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0];
const PADE7: [f64; 8] = [
    17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0,
];
const PADE9: [f64; 10] = [
    17643225600.0,
    8821612800.0,
    2075673600.0,
    302702400.0,
    30270240.0,
    2162160.0,
    110880.0,
    3960.0,
    90.0,
    1.0,
];
const PADE13: [f64; 14] = [
    64764752532480000.0,
    32382376266240000.0,
    7771770303897600.0,
    1187353796428800.0,
    129060195264000.0,
    10559470521600.0,
    670442572800.0,
    33522128640.0,
    1323241920.0,
    40840800.0,
    960960.0,
    16380.0,
    182.0,
    1.0,
];
/// Largest 1-norms for which Pade 3, 5, 7, 9, 13 reach unit roundoff (Higham 2005, table 2.3).
const THETA: [f64; 5] = [
    1.495585217958292e-2,
    2.539_398_330_063_23e-1,
    9.504178996162932e-1,
    2.097847961257068,
    5.371920351148152,
];

fn norm1(a: &DMatrix<f64>) -> f64 {
    a.column_iter()
        .map(|c| c.iter().map(|x| x.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Pade approximant r_m(A) = (V - U)^-1 (V + U) with even and odd parts from `coef`.
fn pade(a: &DMatrix<f64>, coef: &[f64]) -> Option<DMatrix<f64>> {
    let n = a.nrows();
    let identity = DMatrix::<f64>::identity(n, n);
    let a2 = a * a;
    let (u, v) = if coef.len() < 14 {
        // Powers A^0, A^2, A^4, ...
        let mut even = identity.clone();
        let mut odd_sum = DMatrix::<f64>::zeros(n, n);
        let mut even_sum = DMatrix::<f64>::zeros(n, n);
        for k in 0..coef.len() / 2 {
            even_sum += &even * coef[2 * k];
            odd_sum += &even * coef[2 * k + 1];
            even = &even * &a2;
        }
        (a * odd_sum, even_sum)
    } else {
        let b = coef;
        let a4 = &a2 * &a2;
        let a6 = &a4 * &a2;
        let u_inner = &a6 * (&a6 * b[13] + &a4 * b[11] + &a2 * b[9])
            + &a6 * b[7]
            + &a4 * b[5]
            + &a2 * b[3]
            + &identity * b[1];
        let u = a * u_inner;
        let v = &a6 * (&a6 * b[12] + &a4 * b[10] + &a2 * b[8])
            + &a6 * b[6]
            + &a4 * b[4]
            + &a2 * b[2]
            + &identity * b[0];
        (u, v)
    };
    let denominator = &v - &u;
    let numerator = &v + &u;
    denominator.lu().solve(&numerator)
}

/// Matrix exponential by scaling and squaring with Pade approximants (module docs).
///
/// Returns [`DiscretizeError::NotFinite`] if the result is not finite.
pub fn expm(a: &DMatrix<f64>) -> Result<DMatrix<f64>, DiscretizeError> {
    if a.nrows() != a.ncols() {
        return Err(DiscretizeError::Dimensions(format!(
            "exponential of a {}x{} matrix",
            a.nrows(),
            a.ncols()
        )));
    }
    if a.iter().any(|x| !x.is_finite()) {
        return Err(DiscretizeError::NotFinite);
    }
    let norm = norm1(a);
    let small: [&[f64]; 4] = [&PADE3, &PADE5, &PADE7, &PADE9];
    for (coef, theta) in small.iter().zip(THETA) {
        if norm <= theta {
            return finite(pade(a, coef));
        }
    }
    let squarings = if norm > THETA[4] {
        (norm / THETA[4]).log2().ceil().max(0.0) as i32
    } else {
        0
    };
    if squarings > 1000 {
        return Err(DiscretizeError::NotFinite);
    }
    let scaled = a / 2f64.powi(squarings);
    let mut r = finite(pade(&scaled, &PADE13))?;
    for _ in 0..squarings {
        r = &r * &r;
    }
    finite(Some(r))
}

fn finite(r: Option<DMatrix<f64>>) -> Result<DMatrix<f64>, DiscretizeError> {
    match r {
        Some(r) if r.iter().all(|x| x.is_finite()) => Ok(r),
        _ => Err(DiscretizeError::NotFinite),
    }
}

/// The matrices of one step (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Discretization {
    /// Step size h.
    pub step: f64,
    /// `exp(A h)`.
    pub phi: DMatrix<f64>,
    /// Response to an input held over the step.
    pub gamma0: DMatrix<f64>,
    /// Response to an input ramp `u' s` over the step (present with first-order hold).
    pub gamma1: Option<DMatrix<f64>>,
}

/// A matrix stored by its non-zero entries (compressed rows): `y = M x` costs one multiply
/// per non-zero (the model's branch forces `C_r z`, one short row per branch).
#[derive(Clone, Debug, PartialEq)]
pub struct LinearMap {
    rows: usize,
    cols: usize,
    row_start: Vec<usize>,
    col: Vec<usize>,
    value: Vec<f64>,
}

impl LinearMap {
    /// The map of `m`.
    pub fn new(m: &DMatrix<f64>) -> LinearMap {
        let mut row_start = Vec::with_capacity(m.nrows() + 1);
        let mut col = Vec::new();
        let mut value = Vec::new();
        row_start.push(0);
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                let x = m[(i, j)];
                if x != 0.0 {
                    col.push(j);
                    value.push(x);
                }
            }
            row_start.push(col.len());
        }
        LinearMap {
            rows: m.nrows(),
            cols: m.ncols(),
            row_start,
            col,
            value,
        }
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// Number of stored (non-zero) entries.
    pub fn non_zeros(&self) -> usize {
        self.value.len()
    }

    /// `y = M x`. Panics if the lengths do not match (a programming error).
    pub fn apply(&self, x: &[f64], y: &mut [f64]) {
        assert!(x.len() == self.cols && y.len() == self.rows);
        for (i, out) in y.iter_mut().enumerate() {
            let (a, b) = (self.row_start[i], self.row_start[i + 1]);
            let mut sum = 0.0;
            for (c, v) in self.col[a..b].iter().zip(&self.value[a..b]) {
                sum += v * x[*c];
            }
            *out = sum;
        }
    }
}

/// Discretizes `z' = A z + B u` over h, with first-order hold if `first_order_hold`.
pub fn discretize(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    step: f64,
    first_order_hold: bool,
) -> Result<Discretization, DiscretizeError> {
    discretize_balanced(a, b, step, first_order_hold, &vec![1.0; a.nrows()])
}

/// [`discretize`] computed in the balanced coordinates `y = D z`, `D = diag(scale)`
/// (positive, finite): `y' = (D A D^-1) y + (D B) u`, the matrices then mapped back to z
/// (`Phi = D^-1 Phi_y D`, `Gamma = D^-1 Gamma_y`). Each input is scaled by a power of 2 so
/// that its column of `D B` is no larger in 1-norm than `D A D^-1` (no squarings for the input
/// alone).
///
/// With `D = P^(1/2)` for a stored energy `1/2 z^T P z` (P diagonal) of a passive system,
/// `exp(D A D^-1 t)` is a contraction, and scaling and squaring keeps its error near
/// `|A h|` unit roundoffs relative to the state's energy norm, whatever the spread of the
/// coefficients. Unscaled, a stage of stiffness k and mass m has `Phi` entries of order
/// `sqrt(k / m)` and its inverse, and each squaring multiplies the rounding by their ratio:
/// at `sqrt(k / m) h` = 1e6 the step's value was wrong in sign.
pub fn discretize_balanced(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    step: f64,
    first_order_hold: bool,
    scale: &[f64],
) -> Result<Discretization, DiscretizeError> {
    if !(step.is_finite() && step > 0.0) {
        return Err(DiscretizeError::BadStepSize(step));
    }
    check_system(a, b)?;
    let ns = a.nrows();
    check_scale(scale, ns)?;
    let m = b.ncols();
    let balanced_a = DMatrix::from_fn(ns, ns, |i, j| a[(i, j)] * scale[i] / scale[j]);
    let balanced_b = DMatrix::from_fn(ns, m, |i, c| b[(i, c)] * scale[i]);
    let a_norm = norm1(&balanced_a);
    let input_scale: Vec<f64> = balanced_b
        .column_iter()
        .map(|col| {
            let ratio = col.iter().map(|x| x.abs()).sum::<f64>() / a_norm;
            if ratio > 1.0 && ratio.is_finite() {
                2f64.powi(ratio.log2().ceil() as i32)
            } else {
                1.0
            }
        })
        .collect();
    let size = if first_order_hold { ns + 2 * m } else { ns + m };
    let mut big = DMatrix::<f64>::zeros(size, size);
    big.view_mut((0, 0), (ns, ns))
        .copy_from(&(balanced_a * step));
    for c in 0..m {
        for i in 0..ns {
            big[(i, ns + c)] = balanced_b[(i, c)] / input_scale[c] * step;
        }
    }
    if first_order_hold {
        for i in 0..m {
            big[(ns + i, ns + m + i)] = step;
        }
    }
    let e = expm(&big)?;
    let unscale = |rows: std::ops::Range<usize>,
                   cols: std::ops::Range<usize>,
                   col_scale: &dyn Fn(usize) -> f64| {
        DMatrix::from_fn(ns, cols.len(), |i, c| {
            e[(rows.start + i, cols.start + c)] * col_scale(c) / scale[i]
        })
    };
    // big = h S M S^-1 with M the unscaled augmented matrix, so these blocks are exactly
    // Phi, Gamma0 and Gamma1 once mapped back.
    let phi = unscale(0..ns, 0..ns, &|c| scale[c]);
    let gamma0 = unscale(0..ns, ns..ns + m, &|c| input_scale[c]);
    let gamma1 = first_order_hold.then(|| unscale(0..ns, ns + m..ns + 2 * m, &|c| input_scale[c]));
    let result = Discretization {
        step,
        phi,
        gamma0,
        gamma1,
    };
    let blocks = [
        Some(&result.phi),
        Some(&result.gamma0),
        result.gamma1.as_ref(),
    ];
    if blocks
        .iter()
        .flatten()
        .any(|m| m.iter().any(|x| !x.is_finite()))
    {
        return Err(DiscretizeError::NotFinite);
    }
    Ok(result)
}

/// The phase a mode of angular frequency `frequency` and decay rate `decay` turns through
/// while it lasts within a step h: `frequency min(h, 1 / decay)`. Rounding in the phase of a
/// mode that has decayed costs nothing.
fn effective_phase(frequency: f64, decay: f64, step: f64) -> f64 {
    frequency * step.min(1.0 / decay.max(0.0))
}

/// The 1-norm of the skew-symmetric part of `D A D^-1`, `D = diag(scale)`.
fn skew_norm(a: &DMatrix<f64>, scale: &[f64]) -> f64 {
    let n = a.nrows();
    let balanced = |i: usize, j: usize| a[(i, j)] * scale[i] / scale[j];
    (0..n)
        .map(|j| {
            (0..n)
                .map(|i| 0.5 * (balanced(i, j) - balanced(j, i)).abs())
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
}

/// `scale` holds `states` finite positive numbers.
fn check_scale(scale: &[f64], states: usize) -> Result<(), DiscretizeError> {
    if scale.len() != states {
        return Err(DiscretizeError::Dimensions(format!(
            "{} state scales for {states} states",
            scale.len()
        )));
    }
    if let Some(x) = scale.iter().find(|x| !(x.is_finite() && **x > 0.0)) {
        return Err(DiscretizeError::Dimensions(format!(
            "state scale {x:e} is not finite and > 0"
        )));
    }
    Ok(())
}

/// `A` square and `B` with as many rows.
fn check_system(a: &DMatrix<f64>, b: &DMatrix<f64>) -> Result<(), DiscretizeError> {
    if a.nrows() != a.ncols() || b.nrows() != a.nrows() {
        return Err(DiscretizeError::Dimensions(format!(
            "A is {}x{}, B is {}x{}",
            a.nrows(),
            a.ncols(),
            b.nrows(),
            b.ncols()
        )));
    }
    Ok(())
}

/// The entry for `step` in a most-recently-used-last list, made and inserted (dropping the
/// least recently used beyond `capacity`) when missing.
fn recently_used<T>(
    entries: &mut Vec<T>,
    capacity: usize,
    step: f64,
    step_of: impl Fn(&T) -> f64,
    make: impl FnOnce() -> Result<T, DiscretizeError>,
) -> Result<&T, DiscretizeError> {
    match entries
        .iter()
        .rposition(|d| step_of(d).to_bits() == step.to_bits())
    {
        Some(i) => {
            if i + 1 != entries.len() {
                let entry = entries.remove(i);
                entries.push(entry);
            }
        }
        None => {
            let entry = make()?;
            if entries.len() >= capacity {
                entries.remove(0);
            }
            entries.push(entry);
        }
    }
    Ok(entries.last().expect("an entry was just found or inserted"))
}

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
    entries: Vec<BlockDiscretization>,
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
    phi: Vec<f64>,
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
    /// ([`discretize_balanced`]; the square roots of a diagonal energy weight). Refused unless
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

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DVector;

    /// The seed's 2-DOF network (hull held): z = [e1, e2, w1, w2].
    fn seed_system() -> (DMatrix<f64>, DMatrix<f64>) {
        let (m1, k1, c1, m2, k2, c2) = (0.5434, 0.2339, 0.9962, 0.1877, 0.5522, 0.2453);
        let a = DMatrix::from_row_slice(
            4,
            4,
            &[
                0.0,
                0.0,
                -1.0,
                0.0,
                0.0,
                0.0,
                1.0,
                -1.0,
                k1 / m1,
                -k2 / m1,
                -(c1 + c2) / m1,
                c2 / m1,
                0.0,
                k2 / m2,
                c2 / m2,
                -c2 / m2,
            ],
        );
        let b = DMatrix::from_column_slice(4, 1, &[1.0, 0.0, c1 / m1, 0.0]);
        (a, b)
    }

    fn max_abs(m: &DMatrix<f64>) -> f64 {
        m.iter().fold(0.0, |acc, x| acc.max(x.abs()))
    }

    /// exp by an explicit Taylor series (only for small norms).
    fn taylor(a: &DMatrix<f64>) -> DMatrix<f64> {
        let n = a.nrows();
        let mut term = DMatrix::<f64>::identity(n, n);
        let mut sum = term.clone();
        for k in 1..40 {
            term = &term * a / k as f64;
            sum += &term;
        }
        sum
    }

    #[test]
    fn exponential_matches_taylor_series_for_small_steps() {
        let (a, _) = seed_system();
        for h in [1e-6, 1e-3, 0.05, 0.3, 1.0] {
            let e = expm(&(&a * h)).unwrap();
            let t = taylor(&(&a * h));
            // Taylor with 40 terms is exact to rounding for |A h| <= ~5.
            assert!(max_abs(&(e - &t)) < 1e-14 * max_abs(&t).max(1.0), "h = {h}");
        }
    }

    #[test]
    fn exponential_matches_eigen_decomposition_for_long_steps() {
        // Symmetric negative definite A: exp(A h) = V exp(L h) V^T independently.
        let s = DMatrix::from_row_slice(3, 3, &[-2.0, 0.5, 0.1, 0.5, -1.0, 0.3, 0.1, 0.3, -0.7]);
        let eig = crate::numerics::symmetric_eigen(&s);
        for h in [1e-6, 1.0, 10.0, 100.0] {
            let e = expm(&(&s * h)).unwrap();
            let diag = DVector::from_iterator(3, eig.eigenvalues.iter().map(|l| (l * h).exp()));
            let reference =
                &eig.eigenvectors * DMatrix::from_diagonal(&diag) * eig.eigenvectors.transpose();
            // Relative to the largest entry; squaring loses ~log2(|A h|) bits at most.
            let scale = max_abs(&reference).max(1e-300);
            assert!(
                max_abs(&(e - &reference)) <= 1e-12 * scale,
                "h = {h}: {}",
                max_abs(&(expm(&(&s * h)).unwrap() - &reference)) / scale
            );
        }
    }

    #[test]
    fn exponential_agrees_with_nalgebra_and_semigroup_property() {
        let (a, _) = seed_system();
        for h in [0.01, 3.0, 100.0] {
            let e = expm(&(&a * h)).unwrap();
            let other = (&a * h).exp();
            assert!(max_abs(&(&e - &other)) < 1e-10, "h = {h}");
            let half = expm(&(&a * (h / 2.0))).unwrap();
            assert!(max_abs(&(&half * &half - &e)) < 1e-12, "h = {h}");
        }
    }

    #[test]
    fn input_blocks_match_closed_forms() {
        // A invertible: Gamma0 = A^-1 (Phi - I) B, Gamma1 = A^-2 (Phi - I - A h) B.
        let (a, b) = seed_system();
        let inv = a.clone().try_inverse().unwrap();
        let id = DMatrix::<f64>::identity(4, 4);
        for h in [0.01, 0.5, 7.0, 100.0] {
            let d = discretize(&a, &b, h, true).unwrap();
            let g0 = &inv * (&d.phi - &id) * &b;
            let g1 = &inv * &inv * (&d.phi - &id - &a * h) * &b;
            assert!(
                max_abs(&(&d.gamma0 - &g0)) < 1e-11 * max_abs(&g0).max(1.0),
                "h = {h}"
            );
            let g1_err = max_abs(&(d.gamma1.as_ref().unwrap() - &g1));
            assert!(g1_err < 1e-10 * max_abs(&g1).max(1.0), "h = {h}: {g1_err}");
        }
    }

    #[test]
    fn input_blocks_match_series_for_tiny_steps() {
        // Gamma0 = sum A^k h^(k+1)/(k+1)! B, Gamma1 = sum A^k h^(k+2)/(k+2)! B.
        let (a, b) = seed_system();
        for h in [1e-6, 1e-4] {
            let d = discretize(&a, &b, h, true).unwrap();
            let mut g0 = DMatrix::<f64>::zeros(4, 1);
            let mut g1 = DMatrix::<f64>::zeros(4, 1);
            let mut power = b.clone();
            let mut fact0 = 1.0;
            let mut fact1 = 2.0;
            for k in 0..12 {
                fact0 *= (k + 1) as f64;
                if k > 0 {
                    fact1 *= (k + 2) as f64;
                }
                g0 += &power * (h.powi(k + 1) / fact0);
                g1 += &power * (h.powi(k + 2) / fact1);
                power = &a * power;
            }
            // Relative accuracy near rounding even though the blocks are ~h and ~h^2.
            assert!(
                max_abs(&(&d.gamma0 - &g0)) < 1e-14 * max_abs(&g0),
                "h = {h}"
            );
            let g1_err = max_abs(&(d.gamma1.as_ref().unwrap() - &g1));
            assert!(g1_err < 1e-13 * max_abs(&g1), "h = {h}: {g1_err}");
        }
    }

    #[test]
    fn step_responses_are_consistent_under_splitting() {
        // Two half steps with a ramp equal one full step (exactness of FOH).
        let (a, b) = seed_system();
        let z0 = DVector::from_vec(vec![0.1, -0.2, 0.3, 0.05]);
        let (u, du) = (0.7, -1.3);
        let h = 0.4;
        let full = discretize(&a, &b, h, true).unwrap();
        let half = discretize(&a, &b, h / 2.0, true).unwrap();
        let step = |d: &Discretization, z: &DVector<f64>, u: f64, du: f64| {
            &d.phi * z + d.gamma0.column(0) * u + d.gamma1.as_ref().unwrap().column(0) * du
        };
        let one = step(&full, &z0, u, du);
        let mid = step(&half, &z0, u, du);
        let two = step(&half, &mid, u + du * h / 2.0, du);
        assert!((one - two).amax() < 1e-14);
    }

    #[test]
    fn linear_map_equals_the_dense_product_and_skips_exact_zeros() {
        let (a, _) = seed_system();
        let map = LinearMap::new(&a);
        assert_eq!(map.non_zeros(), a.iter().filter(|x| **x != 0.0).count());
        let x: Vec<f64> = (0..4).map(|k| (k as f64 * 0.7).sin()).collect();
        let mut y = vec![0.0; 4];
        map.apply(&x, &mut y);
        let dense = &a * DVector::from_column_slice(&x);
        for i in 0..4 {
            assert!((y[i] - dense[i]).abs() < 1e-15, "{i}");
        }
    }

    #[test]
    fn bad_steps_are_rejected() {
        let (a, b) = seed_system();
        for h in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                discretize(&a, &b, h, false),
                Err(DiscretizeError::BadStepSize(_))
            ));
        }
        let wrong = DMatrix::<f64>::zeros(3, 1);
        assert!(matches!(
            discretize(&a, &wrong, 0.1, false),
            Err(DiscretizeError::Dimensions(_))
        ));
        let unstable = DMatrix::from_element(1, 1, 1.0);
        assert_eq!(expm(&(unstable * 1e6)), Err(DiscretizeError::NotFinite));
    }

    #[test]
    fn cache_keeps_recent_steps() {
        let (a, b) = seed_system();
        let mut cache = BlockDiscretizationCache::new(
            &a,
            &b,
            &[vec![0, 1, 2, 3]],
            std::slice::from_ref(&(0..1)),
            &[1.0; 4],
        )
        .unwrap();
        let first = cache.get(0.01).unwrap().clone();
        let full = discretize(&a, &b, 0.01, true).unwrap();
        assert_eq!(first.phi, full.phi.transpose().as_slice());
        assert_eq!(cache.entries.len(), 1);
        for k in 1..=10 {
            cache.get(0.01 * k as f64).unwrap();
        }
        assert_eq!(
            cache.entries.len(),
            BlockDiscretizationCache::DEFAULT_CAPACITY
        );
        assert!(cache.get(-1.0).is_err());
    }

    #[test]
    fn blocks_reproduce_the_whole_system_and_coupling_is_refused() {
        // Two copies of the seed chain, interleaved, each driven by its own input: the block
        // step must equal the full system's step (same exact discretization, to rounding).
        let (a1, b1) = seed_system();
        let order = [0usize, 5, 2, 7, 1, 3, 6, 4];
        let (block0, block1): (Vec<usize>, Vec<usize>) = (order[..4].to_vec(), order[4..].to_vec());
        let mut a = DMatrix::zeros(8, 8);
        let mut b = DMatrix::zeros(8, 2);
        for (j, states) in [&block0, &block1].iter().enumerate() {
            let scale = 1.0 + j as f64;
            for r in 0..4 {
                b[(states[r], j)] = b1[(r, 0)] * scale;
                for c in 0..4 {
                    a[(states[r], states[c])] = a1[(r, c)] * scale;
                }
            }
        }
        let mut blocks =
            BlockDiscretizationCache::new(&a, &b, &[block0, block1], &[0..1, 1..2], &[1.0; 8])
                .unwrap();
        let full = discretize(&a, &b, 0.37, true).unwrap();
        let z = DVector::from_fn(8, |i, _| (i as f64 * 0.7).sin());
        let (u, du) = ([0.3, -1.2], [2.0, 0.5]);
        let mut next = vec![0.0; 8];
        blocks
            .get(0.37)
            .unwrap()
            .apply(z.as_slice(), &u, &du, &mut next);
        let expected = &full.phi * &z
            + &full.gamma0 * DVector::from_row_slice(&u)
            + full.gamma1.as_ref().unwrap() * DVector::from_row_slice(&du);
        for i in 0..8 {
            assert!((next[i] - expected[i]).abs() < 1e-14, "{i}");
        }
        // A coupling between the blocks, or a block missing a state, is refused.
        let mut coupled = a.clone();
        coupled[(0, 1)] = 1e-3;
        let halves = [vec![0, 5, 2, 7], vec![1, 3, 6, 4]];
        assert!(
            BlockDiscretizationCache::new(&coupled, &b, &halves, &[0..1, 1..2], &[1.0; 8]).is_err()
        );
        assert!(BlockDiscretizationCache::new(
            &a,
            &b,
            &[vec![0, 5, 2, 7], vec![1, 3, 6]],
            &[0..1, 1..2],
            &[1.0; 8]
        )
        .is_err());
        // An input in two blocks, or one driving the other block's states, is refused.
        assert!(BlockDiscretizationCache::new(&a, &b, &halves, &[0..2, 1..2], &[1.0; 8]).is_err());
        assert!(BlockDiscretizationCache::new(&a, &b, &halves, &[1..2, 0..1], &[1.0; 8]).is_err());
        assert!(blocks.get(0.0).is_err());
    }

    #[test]
    fn a_block_with_several_inputs_steps_like_the_whole_system() {
        // Block 0: the seed chain driven by two inputs (columns 0 and 1), block 1: the same
        // chain scaled, driven by input 2.
        let (a1, b1) = seed_system();
        let mut a = DMatrix::zeros(8, 8);
        let mut b = DMatrix::zeros(8, 3);
        for r in 0..4 {
            b[(r, 0)] = b1[(r, 0)];
            b[(r, 1)] = (r as f64 + 1.0) * 0.3;
            b[(4 + r, 2)] = 2.0 * b1[(r, 0)];
            for c in 0..4 {
                a[(r, c)] = a1[(r, c)];
                a[(4 + r, 4 + c)] = 2.0 * a1[(r, c)];
            }
        }
        let mut blocks = BlockDiscretizationCache::new(
            &a,
            &b,
            &[vec![0, 1, 2, 3], vec![4, 5, 6, 7]],
            &[0..2, 2..3],
            &[1.0; 8],
        )
        .unwrap();
        assert_eq!(blocks.input_count(), 3);
        let full = discretize(&a, &b, 0.21, true).unwrap();
        let z = DVector::from_fn(8, |i, _| (i as f64 * 1.3).cos());
        let (u, du) = ([0.3, -1.2, 0.8], [2.0, 0.5, -0.4]);
        let mut next = vec![0.0; 8];
        blocks
            .get(0.21)
            .unwrap()
            .apply(z.as_slice(), &u, &du, &mut next);
        let expected = &full.phi * &z
            + &full.gamma0 * DVector::from_row_slice(&u)
            + full.gamma1.as_ref().unwrap() * DVector::from_row_slice(&du);
        for i in 0..8 {
            assert!((next[i] - expected[i]).abs() < 1e-14, "{i}");
        }
    }
}
