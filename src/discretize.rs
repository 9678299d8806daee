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

mod blocks;

pub use blocks::{BlockDiscretization, BlockDiscretizationCache, MAX_PHASE_PER_STEP};

use nalgebra::DMatrix;
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
pub(crate) fn discretize_balanced(
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

#[cfg(test)]
mod tests;
