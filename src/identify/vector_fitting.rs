//! Vector fitting of the radiation part of the added mass with poles common to every matrix
//! entry (Gustavsen & Semlyen 1999; relaxed form: Gustavsen 2006; the per-entry QR
//! compression of "fast" vector fitting: Deschrijver et al. 2008):
//!
//! ```text
//! G(s) = A~(omega) - A_inf  ~  sum_m R_m / (s - p_m),   s = i omega,
//! ```
//!
//! strictly proper (`G(inf) = 0`: `A_inf` is data, never fitted), real in time (a complex pole
//! comes with its conjugate and the conjugate residue), symmetric residues `R_m` (only the
//! entries `i <= j` are fitted). The error measure is the identification's (module docs of
//! [`crate::identify`]): entry `(i, j)` is fitted and reported divided by `sqrt(s_i s_j)`.
//! Fitting `G` unweighted is the same least-squares problem as fitting the radiation impedance
//! `K(s) = s G(s)` (force per velocity) with the weight `1 / omega`.
//!
//! # Algorithm (deterministic)
//!
//! Frequencies are scaled by `omega_ref = sqrt(omega_lo omega_hi)`. Starting poles: complex
//! pairs `p = -beta / 100 + i beta` and real poles `-beta`, `beta` log-spaced over the band.
//! Each iteration relocates the poles: with the weight function
//! `sigma(s) = sum_m c_m phi_m(s) + d` (same real basis `phi_m` as the fit), the linear
//! problem `sigma f_e ~ sum_m r_em phi_m` for every entry e, in real form (real and imaginary
//! rows), is compressed per entry by a QR factorization to the rows that involve `(c, d)`
//! only; those rows of all entries, with the relaxation row `Re sum_k sigma(s_k) = K`, give
//! `(c, d)` by least squares, and the new poles are the zeros of `sigma`: the eigenvalues of
//! `H - b c^T / d` (`H` the poles in real block form). Unstable poles are mirrored into the
//! left half-plane. After the iterations, the residues are the linear least-squares solution
//! with the final poles (one factorization shared by all entries).
//!
//! The free fit is not passive by construction; [`crate::passivity`] decides, exactly, whether
//! a realization of it is. [`passive_vector_fit`] solves the residues again under the matrix
//! inequalities that make it passive at sampled frequencies (poles fixed, convex), until the
//! exact check passes.
//! The inequality is enforced as a whole (every eigenvalue, not one direction per violation):
//! the damping of a 2D section has rank 2, so the data lies on the boundary of passivity at
//! every frequency, and one-direction cuts chase a turning null space without end (the midship
//! section's 6 x 6 was not passive after 30 rounds of them at any order above 1; now every
//! order is, in 1 to 3 rounds). [`passive_block_vector_fit`] fits the invariant blocks one by
//! one ([`Blocks`]): the semicircle's 9 x 9 with 2 pairs and 1 real pole per block, 0.76 %
//! with 25 states, passive (kR 0.05 .. 4.5); over kR 0.01 .. 4.5 with 2 pairs and 2 real
//! poles, 0.46 % with 30 states. `fit` realizes such a fit as a network
//! ([`super::synthesis`]).

mod blocks;

pub use blocks::{BlockFit, Blocks};

use super::{dof_scales, FrequencyResponse, IdentifyError};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// Parameters of [`vector_fit`].
#[derive(Clone, Debug, PartialEq)]
pub struct VectorFitParams {
    /// Complex-conjugate pole pairs to start from (two states each per residue rank).
    pub complex_pairs: usize,
    /// Real poles to start from (one state each per residue rank).
    pub real_poles: usize,
    /// Pole relocation iterations (default 10; the poles settle in 3 to 6 on the semicircle).
    pub iterations: usize,
    /// Fitted band `(omega_lo, omega_hi)` in rad/s; frequencies outside are ignored.
    pub band: (f64, f64),
    /// The passive fits' margin `mu` (normalized, module docs of [`passive_vector_fit`]): the
    /// damping it adds changes `A~` by at most `mu sqrt(s_i s_j)`. Default 1e-4.
    pub passivity_margin: f64,
    /// [`passive_block_vector_fit`]: the largest coupling between invariant blocks
    /// (normalized, as the error) that the split may drop. Data of a symmetric body is block
    /// diagonal only to its mesh's accuracy. Default 1e-3 (a tenth of the default tolerance).
    pub block_coupling: f64,
}

impl Default for VectorFitParams {
    fn default() -> Self {
        VectorFitParams {
            complex_pairs: 2,
            real_poles: 0,
            iterations: 10,
            band: (0.0, f64::INFINITY),
            passivity_margin: 1e-4,
            block_coupling: 1e-3,
        }
    }
}

/// A common-pole rational model of `G(s) = A~ - A_inf` (SI).
#[derive(Clone, Debug, PartialEq)]
pub struct RationalFit {
    /// One entry per real pole (`im = 0`) and per conjugate pair (the pole with `im > 0`),
    /// rad/s, every `re < 0`.
    pub poles: Vec<Complex64>,
    /// `R_m` (n x n, symmetric) of each pole; a pair's conjugate pole has `conj(R_m)`.
    pub residues: Vec<DMatrix<Complex64>>,
    /// The DOF scales `s_i` of the error measure.
    pub dof_scales: DVector<f64>,
    /// Largest `|G_fit - G|_ij / sqrt(s_i s_j)` over the band.
    pub max_error: f64,
}

impl RationalFit {
    /// `G(i omega)` of the model (without `A_inf`).
    pub fn evaluate(&self, omega: f64) -> DMatrix<Complex64> {
        let s = Complex64::new(0.0, omega);
        let n = self.dof_scales.len();
        let mut out = DMatrix::zeros(n, n);
        for (p, r) in self.poles.iter().zip(&self.residues) {
            if p.im == 0.0 {
                out += r * (1.0 / (s - p));
            } else {
                out += r * (1.0 / (s - p)) + r.map(|x| x.conj()) * (1.0 / (s - p.conj()));
            }
        }
        out
    }

    /// A real state-space realization of the radiation impedance in the convention of
    /// [`crate::realize::StateSpace`] (`F = C z + D v`, force on the hull): with
    /// `K(s) = s G(s) = sum_m R_m + sum_m p_m R_m / (s - p_m)`, `D = -sum_m R_m` (conjugates
    /// included) and one block of n states per pole (two per pair, in real form). Not
    /// minimal (`n` states per pole whatever the residue's rank); for [`crate::passivity`].
    pub fn impedance_realization(&self) -> [DMatrix<f64>; 4] {
        let n = self.dof_scales.len();
        let states = n * self.pole_count();
        let mut a = DMatrix::zeros(states, states);
        let mut b = DMatrix::zeros(states, n);
        let mut c = DMatrix::zeros(n, states);
        let mut d = DMatrix::zeros(n, n);
        let mut at = 0;
        for (p, r) in self.poles.iter().zip(&self.residues) {
            let pr = r * *p;
            if p.im == 0.0 {
                for i in 0..n {
                    a[(at + i, at + i)] = p.re;
                    b[(at + i, i)] = 1.0;
                }
                c.view_mut((0, at), (n, n)).copy_from(&(-pr.map(|x| x.re)));
                d -= r.map(|x| x.re);
                at += n;
            } else {
                // x1' = Re p x1 - Im p x2 + v, x2' = Im p x1 + Re p x2 (x1 + i x2 = X, X' = p X + v):
                // 2 Re[pR / (s - p)] v = 2 Re(pR) x1 - 2 Im(pR) x2.
                for i in 0..n {
                    a[(at + i, at + i)] = p.re;
                    a[(at + i, at + n + i)] = -p.im;
                    a[(at + n + i, at + i)] = p.im;
                    a[(at + n + i, at + n + i)] = p.re;
                    b[(at + i, i)] = 1.0;
                }
                c.view_mut((0, at), (n, n))
                    .copy_from(&(-pr.map(|x| 2.0 * x.re)));
                c.view_mut((0, at + n), (n, n))
                    .copy_from(&pr.map(|x| 2.0 * x.im));
                d -= r.map(|x| 2.0 * x.re);
                at += 2 * n;
            }
        }
        [a, b, c, d]
    }

    /// The exact passivity check ([`crate::passivity`]) of [`Self::impedance_realization`].
    pub fn passivity(&self, tolerance: f64) -> crate::passivity::PassivityReport {
        let [a, b, c, d] = self.impedance_realization();
        crate::passivity::check_realization(
            &crate::passivity::Realization {
                a: &a,
                b: &b,
                c: &c,
                d: &d,
            },
            tolerance,
        )
    }

    /// States of a minimal realization: per pole the rank of its residue (singular values
    /// above `1e-9` of the largest residue's), twice for a conjugate pair.
    pub fn state_count(&self) -> usize {
        let largest = self
            .residues
            .iter()
            .flat_map(|r| r.iter().map(|z| z.norm()))
            .fold(0.0, f64::max);
        self.poles
            .iter()
            .zip(&self.residues)
            .map(|(p, r)| {
                let rank = r
                    .clone()
                    .singular_values()
                    .iter()
                    .filter(|&&v| v > 1e-9 * largest)
                    .count();
                if p.im == 0.0 {
                    rank
                } else {
                    2 * rank
                }
            })
            .sum()
    }

    /// The number of poles, a conjugate pair counted twice.
    pub fn pole_count(&self) -> usize {
        self.poles
            .iter()
            .map(|p| if p.im == 0.0 { 1 } else { 2 })
            .sum()
    }
}

/// Poles in the scaled frequency `s / omega_ref`.
type Poles = Vec<Complex64>;

/// The real basis at `s`: `1 / (s - p)` for a real pole; `1/(s - p) + 1/(s - conj p)` and
/// `i/(s - p) - i/(s - conj p)` for a pair (coefficients `Re r`, `Im r`).
fn basis_row(poles: &Poles, s: Complex64, row: &mut Vec<Complex64>) {
    row.clear();
    for p in poles {
        let a = 1.0 / (s - p);
        if p.im == 0.0 {
            row.push(a);
        } else {
            let b = 1.0 / (s - p.conj());
            row.push(a + b);
            row.push(Complex64::i() * (a - b));
        }
    }
}

/// The basis at every `s_k` (K x N complex).
fn basis(poles: &Poles, s: &[Complex64]) -> DMatrix<Complex64> {
    let mut row = Vec::new();
    basis_row(poles, s[0], &mut row);
    let mut out = DMatrix::zeros(s.len(), row.len());
    for (k, &sk) in s.iter().enumerate() {
        basis_row(poles, sk, &mut row);
        for (j, x) in row.iter().enumerate() {
            out[(k, j)] = *x;
        }
    }
    out
}

/// Least squares `min |a x - b|` with column scaling (SVD, rank-revealing).
fn least_squares(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    let norms = DVector::from_fn(a.ncols(), |j, _| {
        let n = a.column(j).norm();
        if n > 0.0 {
            n
        } else {
            1.0
        }
    });
    let mut scaled = a.clone();
    for j in 0..a.ncols() {
        scaled.column_mut(j).unscale_mut(norms[j]);
    }
    // No decomposition (non-finite or not converging): zeros, whose error the fit reports.
    let Some(svd) = crate::numerics::svd(scaled, true, true) else {
        return DMatrix::zeros(a.ncols(), b.ncols());
    };
    let tol = 1e-13 * svd.singular_values.max();
    let mut x = svd
        .solve(b, tol)
        .unwrap_or_else(|_| DMatrix::zeros(a.ncols(), b.ncols()));
    for j in 0..a.ncols() {
        x.row_mut(j).unscale_mut(norms[j]);
    }
    x
}

/// One relocation of the poles (module docs).
fn relocate(poles: &Poles, s: &[Complex64], entries: &[DVector<Complex64>]) -> Poles {
    let phi = basis(poles, s);
    let (k, n) = (s.len(), phi.ncols());
    let mut rows: Vec<DMatrix<f64>> = Vec::with_capacity(entries.len() + 1);
    let mut data_norm = 0.0;
    for f in entries {
        data_norm += f.norm_squared();
        // Real form of [phi, -f phi, -f]: 2K x (2N + 1).
        let mut a = DMatrix::zeros(2 * k, 2 * n + 1);
        for row in 0..k {
            for j in 0..n {
                let x = phi[(row, j)];
                let y = -f[row] * x;
                a[(row, j)] = x.re;
                a[(k + row, j)] = x.im;
                a[(row, n + j)] = y.re;
                a[(k + row, n + j)] = y.im;
            }
            a[(row, 2 * n)] = -f[row].re;
            a[(k + row, 2 * n)] = -f[row].im;
        }
        let r = a.qr().r();
        let keep = r.nrows().saturating_sub(n).min(n + 1);
        rows.push(r.view((n, n), (keep, n + 1)).into_owned());
    }
    // Relaxation: Re sum_k sigma(s_k) = K, weighted like the data.
    let weight = data_norm.sqrt() / (k * entries.len()) as f64;
    let mut relaxation = DMatrix::zeros(1, n + 1);
    for j in 0..n {
        relaxation[(0, j)] = weight * phi.column(j).iter().map(|x| x.re).sum::<f64>();
    }
    relaxation[(0, n)] = weight * k as f64;
    rows.push(relaxation);
    let total: usize = rows.iter().map(|m| m.nrows()).sum();
    let mut system = DMatrix::zeros(total, n + 1);
    let mut at = 0;
    for m in &rows {
        system.view_mut((at, 0), (m.nrows(), n + 1)).copy_from(m);
        at += m.nrows();
    }
    let mut rhs = DMatrix::zeros(total, 1);
    rhs[(total - 1, 0)] = weight * k as f64;
    let x = least_squares(&system, &rhs);
    let c = x.rows(0, n).column(0).into_owned();
    let mut d = x[(n, 0)];
    if d.abs() < 1e-8 {
        d = 1e-8f64.copysign(d);
    }
    // Zeros of sigma: eig(H - b c^T / d).
    let mut h = DMatrix::zeros(n, n);
    let mut b = DVector::zeros(n);
    let mut j = 0;
    for p in poles {
        if p.im == 0.0 {
            h[(j, j)] = p.re;
            b[j] = 1.0;
            j += 1;
        } else {
            h[(j, j)] = p.re;
            h[(j, j + 1)] = p.im;
            h[(j + 1, j)] = -p.im;
            h[(j + 1, j + 1)] = p.re;
            b[j] = 2.0;
            j += 2;
        }
    }
    // A relocation that cannot be computed keeps the poles it started from.
    let Some(zeros) = crate::numerics::eigenvalues(&(h - b * c.transpose() / d)) else {
        return poles.clone();
    };
    let largest = zeros.iter().map(|z| z.norm()).fold(0.0, f64::max);
    let mut out: Poles = Vec::new();
    for z in zeros.iter() {
        let re = -z.re.abs().max(1e-12 * largest);
        if z.im.abs() <= 1e-10 * largest {
            out.push(Complex64::new(re, 0.0));
        } else if z.im > 0.0 {
            out.push(Complex64::new(re, z.im));
        }
    }
    out.sort_by(|a, b| a.norm().total_cmp(&b.norm()).then(a.im.total_cmp(&b.im)));
    out
}

/// The normalized data of a fit: entries `i <= j` of `(A~ - A_inf) / sqrt(s_i s_j)` at the
/// scaled frequencies `s_k = i omega_k / omega_ref` inside the band.
struct Problem {
    n: usize,
    s: Vec<Complex64>,
    pairs: Vec<(usize, usize)>,
    entries: Vec<DVector<Complex64>>,
    scales: DVector<f64>,
    omega_ref: f64,
}

impl Problem {
    fn new(
        response: &FrequencyResponse,
        params: &VectorFitParams,
    ) -> Result<Problem, IdentifyError> {
        response.validate()?;
        let (lo, hi) = params.band;
        if !(lo >= 0.0 && hi > lo) {
            return Err(IdentifyError::InvalidBand(format!(
                "({lo}, {hi}) rad/s: need 0 <= low < high"
            )));
        }
        let order = 2 * params.complex_pairs + params.real_poles;
        if order == 0 || params.iterations == 0 {
            return Err(IdentifyError::InvalidParams(
                "vector fitting needs at least one pole and one iteration".into(),
            ));
        }
        let inside: Vec<usize> = (0..response.omega.len())
            .filter(|&k| response.omega[k] >= lo && response.omega[k] <= hi)
            .collect();
        if inside.len() < order + 1 {
            return Err(IdentifyError::InvalidBand(format!(
                "{} frequency points in the band for {order} poles: need at least {}",
                inside.len(),
                order + 1
            )));
        }
        let n = response.dof_count();
        let band_matrices: Vec<DMatrix<Complex64>> = inside
            .iter()
            .map(|&k| response.added_mass[k].clone())
            .collect();
        let scales = dof_scales(&band_matrices)
            .ok_or_else(|| IdentifyError::InvalidData("no added mass in the band".into()))?;
        let omega_lo = response.omega[inside[0]];
        let omega_hi = response.omega[inside[inside.len() - 1]];
        let omega_ref = (omega_lo.max(1e-300) * omega_hi).sqrt();
        let s: Vec<Complex64> = inside
            .iter()
            .map(|&k| Complex64::new(0.0, response.omega[k] / omega_ref))
            .collect();
        let pairs: Vec<(usize, usize)> = (0..n).flat_map(|i| (i..n).map(move |j| (i, j))).collect();
        let entries: Vec<DVector<Complex64>> = pairs
            .iter()
            .map(|&(i, j)| {
                let norm = (scales[i] * scales[j]).sqrt();
                DVector::from_iterator(
                    inside.len(),
                    inside.iter().map(|&k| {
                        (response.added_mass[k][(i, j)]
                            - Complex64::new(response.added_mass_inf[(i, j)], 0.0))
                            / norm
                    }),
                )
            })
            .collect();
        Ok(Problem {
            n,
            s,
            pairs,
            entries,
            scales,
            omega_ref,
        })
    }

    /// Starting poles, then `iterations` relocations (module docs).
    fn poles(&self, params: &VectorFitParams) -> Poles {
        let (b_lo, b_hi) = (self.s[0].im, self.s[self.s.len() - 1].im);
        let spread = |count: usize, k: usize| {
            if count == 1 {
                (b_lo * b_hi).sqrt()
            } else {
                b_lo * (b_hi / b_lo).powf(k as f64 / (count - 1) as f64)
            }
        };
        let mut poles: Poles = (0..params.complex_pairs)
            .map(|k| {
                let beta = spread(params.complex_pairs, k);
                Complex64::new(-beta / 100.0, beta)
            })
            .chain(
                (0..params.real_poles).map(|k| Complex64::new(-spread(params.real_poles, k), 0.0)),
            )
            .collect();
        for _ in 0..params.iterations {
            poles = relocate(&poles, &self.s, &self.entries);
        }
        poles
    }

    /// The real least-squares system of the residues: `a` (2K x N) and one right-hand side
    /// per entry (2K x entries).
    fn residue_system(&self, poles: &Poles) -> (DMatrix<f64>, DMatrix<f64>) {
        let phi = basis(poles, &self.s);
        let (k, m) = (self.s.len(), phi.ncols());
        let mut a = DMatrix::zeros(2 * k, m);
        let mut rhs = DMatrix::zeros(2 * k, self.entries.len());
        for row in 0..k {
            for j in 0..m {
                a[(row, j)] = phi[(row, j)].re;
                a[(k + row, j)] = phi[(row, j)].im;
            }
            for (e, f) in self.entries.iter().enumerate() {
                rhs[(row, e)] = f[row].re;
                rhs[(k + row, e)] = f[row].im;
            }
        }
        (a, rhs)
    }

    /// Largest `|fit - data|` (normalized) for coefficients `x` (N x entries).
    fn max_error(&self, a: &DMatrix<f64>, rhs: &DMatrix<f64>, x: &DMatrix<f64>) -> f64 {
        let k = self.s.len();
        let fitted = a * x;
        let mut max_error: f64 = 0.0;
        for e in 0..self.entries.len() {
            for row in 0..k {
                let d = Complex64::new(
                    fitted[(row, e)] - rhs[(row, e)],
                    fitted[(k + row, e)] - rhs[(k + row, e)],
                );
                max_error = max_error.max(d.norm());
            }
        }
        max_error
    }

    /// The model of coefficients `x`: in SI (`normalized = false`) or in the normalized
    /// problem's units (scaled frequency, unit DOF scales).
    fn model(
        &self,
        poles: &Poles,
        x: &DMatrix<f64>,
        max_error: f64,
        normalized: bool,
    ) -> RationalFit {
        let n = self.n;
        let (frequency, scales) = if normalized {
            (1.0, DVector::from_element(n, 1.0))
        } else {
            (self.omega_ref, self.scales.clone())
        };
        // R = r omega_ref sqrt(s_i s_j) (G(s) = r / (s / omega_ref - p)).
        let mut residues = Vec::with_capacity(poles.len());
        let mut column = 0;
        for p in poles {
            let mut r = DMatrix::zeros(n, n);
            for (e, &(i, j)) in self.pairs.iter().enumerate() {
                let norm = (scales[i] * scales[j]).sqrt() * frequency;
                let value = if p.im == 0.0 {
                    Complex64::new(x[(column, e)], 0.0)
                } else {
                    Complex64::new(x[(column, e)], x[(column + 1, e)])
                } * norm;
                r[(i, j)] = value;
                r[(j, i)] = value;
            }
            column += if p.im == 0.0 { 1 } else { 2 };
            residues.push(r);
        }
        RationalFit {
            poles: poles.iter().map(|p| p * frequency).collect(),
            residues,
            dof_scales: scales,
            max_error,
        }
    }
}

/// Fits a common-pole rational model to `G = A~ - A_inf` over the band (module docs).
pub fn vector_fit(
    response: &FrequencyResponse,
    params: &VectorFitParams,
) -> Result<RationalFit, IdentifyError> {
    let problem = Problem::new(response, params)?;
    let poles = problem.poles(params);
    let (a, rhs) = problem.residue_system(&poles);
    let x = least_squares(&a, &rhs);
    let error = problem.max_error(&a, &rhs, &x);
    Ok(problem.model(&poles, &x, error, false))
}

/// How [`passive_vector_fit`] made the fit passive.
#[derive(Clone, Debug, PartialEq)]
pub struct Enforcement {
    /// The free fit's largest normalized error (before the constraints).
    pub free_error: f64,
    /// The largest normalized error of the residues returned.
    pub error: f64,
    /// Constrained solves (each after an exact check that failed; the first on the log grid,
    /// each later one with the violations the check found added).
    pub rounds: usize,
    /// Constraint frequencies of the last solve.
    pub samples: usize,
    /// ADMM iterations over all rounds.
    pub iterations: usize,
    /// The exact check ([`crate::passivity`]) passes on the result.
    pub passive: bool,
}

/// Largest number of constraint rounds of [`passive_vector_fit`].
const MAX_ROUNDS: usize = 6;

/// [`vector_fit`], then the residues again, least squares under the constraints that make the
/// model passive (poles fixed; convex): the whole matrix inequality
///
/// ```text
/// Re K(i omega) >= delta(omega) I,   delta(omega) = mu b_lo omega^2 / (omega^2 + b_lo^2),
/// ```
///
/// `K(s) = s G(s)` the impedance (normalized units, `b_lo` the band's bottom, `mu` =
/// [`VectorFitParams::passivity_margin`]), at every frequency of a log grid (16 per decade
/// from 1e-3 of the band's bottom to 1e3 times its top), the band's points, the poles'
/// frequencies and `omega -> inf`; solved by ADMM (`src/numerics/lmi_least_squares.rs`), then
/// made feasible at every sample by the smallest step along residues that raise `Re K` at
/// every frequency. Each round runs the exact check ([`crate::passivity`]); if it fails, a
/// fine grid over every interval between its crossings where `Re K` is indefinite joins the
/// samples and the solve continues from where it stopped, at most 6 rounds.
/// The margin's damping changes `A~` by at most `mu sqrt(s_i s_j)` anywhere: it lets the
/// model keep the data's zero damping directions (a 2D section radiates two waves, so its
/// damping matrix has rank 2) without crossing into negative damping.
pub fn passive_vector_fit(
    response: &FrequencyResponse,
    params: &VectorFitParams,
) -> Result<(RationalFit, Enforcement), IdentifyError> {
    let problem = Problem::new(response, params)?;
    let poles = problem.poles(params);
    let (x, enforcement) = enforce(&problem, &poles, params);
    Ok((
        problem.model(&poles, &x, enforcement.error, false),
        enforcement,
    ))
}

/// [`passive_vector_fit`] block by block: the normalized data is reduced to the subspace its
/// entries span and split into the invariant blocks of [`crate::identify`] (for a
/// mirror-symmetric hull, its symmetric and antisymmetric motions); each block gets its own
/// poles (`params` per block) and its own passive residues, and the model is their sum
/// `sum_b B_b G_b(s) B_b^T` (passive: a sum of passive blocks). `max_error` is the full
/// model's, over every entry.
pub fn passive_block_vector_fit(
    response: &FrequencyResponse,
    params: &VectorFitParams,
) -> Result<(RationalFit, Vec<Enforcement>), IdentifyError> {
    let blocks = Blocks::new(response, params)?;
    let fits: Vec<BlockFit> = (0..blocks.len()).map(|b| blocks.fit(b, params)).collect();
    let enforcements = fits.iter().map(|f| f.enforcement.clone()).collect();
    Ok((
        blocks.assemble(&fits.iter().collect::<Vec<_>>()),
        enforcements,
    ))
}

/// Constraint frequencies per decade of the enforcement's log grid.
const SAMPLES_PER_DECADE: f64 = 16.0;

/// ADMM iterations per enforcement round, and its relative stopping tolerance.
const ADMM_ITERATIONS: usize = 100;
const ADMM_TOLERANCE: f64 = 1e-6;

/// [`Blocks::refine`]: the first simplex's step in the logarithms of the poles' parts (a
/// 10 % change), and the spread of the simplex's errors, relative to the starting error, at
/// which it stops.
const REFINEMENT_STEP: f64 = 0.1;
const REFINEMENT_TOLERANCE: f64 = 1e-3;

/// The passive residues of a normalized problem for given poles (see [`passive_vector_fit`]).
fn enforce(
    problem: &Problem,
    poles: &Poles,
    params: &VectorFitParams,
) -> (DMatrix<f64>, Enforcement) {
    use crate::numerics::{lmi_least_squares, MatrixInequalities};

    let (a, rhs) = problem.residue_system(poles);
    let basis_size = a.ncols();
    let free = least_squares(&a, &rhs);
    let free_error = problem.max_error(&a, &rhs, &free);
    // Columns scaled to unit norm (the constraint rows with them), then R of a QR.
    let norms = DVector::from_fn(basis_size, |j, _| {
        let n = a.column(j).norm();
        if n > 0.0 {
            n
        } else {
            1.0
        }
    });
    let mut scaled = a.clone();
    for j in 0..basis_size {
        scaled.column_mut(j).unscale_mut(norms[j]);
    }
    let qr = scaled.qr();
    let r = qr.r();
    let c = qr.q().tr_mul(&rhs);
    let to_scaled = |x: &DMatrix<f64>| {
        let mut y = x.clone();
        for j in 0..basis_size {
            y.row_mut(j).scale_mut(norms[j]);
        }
        y
    };
    let from_scaled = |y: &DMatrix<f64>| {
        let mut x = y.clone();
        for j in 0..basis_size {
            x.row_mut(j).unscale_mut(norms[j]);
        }
        x
    };

    // Re K(i w) = sum_j psi_j(w) x_j with psi_j = Re(i w phi_j(i w)); at w -> inf: 1 per real
    // pole, (2, 0) per pair. Margin delta(w) = mu b_lo w^2 / (w^2 + b_lo^2): the damping it
    // adds costs at most mu (normalized) in A~ at any frequency.
    let (b_lo, b_hi) = (problem.s[0].im, problem.s[problem.s.len() - 1].im);
    let mu = params.passivity_margin;
    let margin = |w: f64| {
        if w.is_infinite() {
            mu * b_lo
        } else {
            mu * b_lo * w * w / (w * w + b_lo * b_lo)
        }
    };
    let psi = |w: f64| -> Vec<f64> {
        if w.is_infinite() {
            return poles
                .iter()
                .flat_map(|p| {
                    if p.im == 0.0 {
                        vec![1.0]
                    } else {
                        vec![2.0, 0.0]
                    }
                })
                .collect();
        }
        let mut row = Vec::new();
        basis_row(poles, Complex64::new(0.0, w), &mut row);
        row.iter()
            .map(|phi| (Complex64::new(0.0, w) * phi).re)
            .collect()
    };
    let (from, to) = (b_lo * 1e-3, b_hi * 1e3);
    // At most 24 decades' worth of samples, however wide the band (a bound, not a hang).
    let count = ((to / from).log10().min(24.0) * SAMPLES_PER_DECADE).ceil() as usize;
    let mut frequencies: Vec<f64> = (0..=count)
        .map(|k| from * (to / from).powf(k as f64 / count as f64))
        .collect();
    frequencies.extend(problem.s.iter().map(|s| s.im));
    frequencies.push(f64::INFINITY);
    // The pole frequencies themselves, where lightly damped poles change fastest.
    frequencies.extend(poles.iter().map(|p| p.im.abs()).filter(|w| *w > 0.0));

    let n = problem.n;
    // A direction that raises Re K at every frequency: per real pole the residue I, per pair
    // p = -alpha + i beta the residue (1 - i beta / alpha) I, whose term
    // 2 (s + |p|^2 / alpha) / (s^2 + 2 alpha s + |p|^2) has Re K = 2 w^2 (w^2 + |p|^2) / |den|^2.
    // Each pole's part has unit norm in the scaled coefficients.
    let mut raise = DVector::<f64>::zeros(basis_size);
    let mut column = 0;
    for p in poles {
        let part: Vec<f64> = if p.im == 0.0 {
            vec![norms[column]]
        } else {
            vec![norms[column], -p.im / -p.re * norms[column + 1]]
        };
        let size = part.iter().map(|v| v * v).sum::<f64>().sqrt();
        for (j, v) in part.iter().enumerate() {
            raise[column + j] = v / size;
        }
        column += part.len();
    }
    let diagonal: Vec<usize> = (0..problem.pairs.len())
        .filter(|&e| problem.pairs[e].0 == problem.pairs[e].1)
        .collect();
    let mut y = to_scaled(&free);
    let mut shifted = y.clone();
    let mut rounds = 0;
    let mut iterations = 0;
    let mut passive = false;
    let mut state = None;
    let tolerance = 1e-9;
    loop {
        let x = from_scaled(&shifted);
        let model = problem.model(poles, &x, 0.0, true);
        let report = model.passivity(tolerance);
        if report.passive {
            passive = true;
            break;
        }
        if rounds == MAX_ROUNDS {
            break;
        }
        rounds += 1;
        if rounds > 1 {
            // Violations between the samples: a fine grid over every interval between the
            // check's crossings where Re K is indefinite (the samples are appended: the solve
            // continues from its state).
            let mut edges = vec![0.0];
            edges.extend(&report.crossings);
            edges.push(2.0 * report.crossings.last().copied().unwrap_or(b_hi).max(b_hi));
            for w in edges.windows(2) {
                let (lo, hi) = (w[0].max(from), w[1]);
                if hi <= lo {
                    continue;
                }
                let middle = (lo * hi).sqrt();
                let k = model.evaluate(middle) * Complex64::new(0.0, middle);
                let re = (&k + k.adjoint()).map(|z| z.re) * 0.5;
                if crate::numerics::symmetric_eigen(&re).eigenvalues.min() < 0.0 {
                    frequencies.extend((0..=16).map(|j| lo * (hi / lo).powf(j as f64 / 16.0)));
                }
            }
            if report.at_omega.is_finite() && report.at_omega > 0.0 {
                frequencies.push(report.at_omega);
            }
        }
        let mut rows = DMatrix::zeros(frequencies.len(), basis_size);
        for (k, &w) in frequencies.iter().enumerate() {
            for (j, v) in psi(w).into_iter().enumerate() {
                rows[(k, j)] = v / norms[j];
            }
        }
        let margins: Vec<f64> = frequencies.iter().map(|&w| margin(w)).collect();
        let constraints = MatrixInequalities {
            n,
            pairs: &problem.pairs,
            rows: &rows,
            margins: &margins,
        };
        let solution = lmi_least_squares(
            &r,
            &c,
            &constraints,
            &y,
            state.as_ref(),
            ADMM_ITERATIONS,
            ADMM_TOLERANCE,
        );
        iterations += solution.iterations;
        y = solution.x;
        state = Some(solution.state);
        // The iterate meets the inequalities to the solver's residual; the smallest step along
        // `raise` that gives every sample half its margin removes the rest.
        let values = &rows * &y;
        let mut step: f64 = 0.0;
        for k in 0..frequencies.len() {
            let mut m = DMatrix::zeros(n, n);
            for (e, &(i, j)) in problem.pairs.iter().enumerate() {
                m[(i, j)] = values[(k, e)];
                m[(j, i)] = values[(k, e)];
            }
            let lowest = crate::numerics::symmetric_eigen(&m).eigenvalues.min();
            let gain = rows.row(k).dot(&raise.transpose());
            let missing = 0.5 * margins[k] - lowest;
            if missing > 0.0 && gain > 0.0 {
                step = step.max(missing / gain);
            }
        }
        shifted = y.clone();
        for &e in &diagonal {
            shifted.column_mut(e).axpy(step, &raise, 1.0);
        }
    }
    let x = from_scaled(&shifted);
    let error = problem.max_error(&a, &rhs, &x);
    (
        x,
        Enforcement {
            free_error,
            error,
            rounds,
            samples: frequencies.len(),
            iterations,
            passive,
        },
    )
}

#[cfg(test)]
mod tests;
