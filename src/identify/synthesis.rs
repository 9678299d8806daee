//! Realization of a passive rational fit as a mechanical [`Substructure`] (reciprocal passive
//! synthesis in state space; Anderson & Vongpanitlerd, Network Analysis and Synthesis, on the
//! positive-real lemma and reciprocal synthesis).
//!
//! # Steps
//!
//! The fit `G(s) = sum_m R_m / (s - p_m)` ([`RationalFit`], passive by the exact check) has the
//! impedance `Z(s) = s G(s)`, computed in normalized units (DOF scales `sqrt(s_i)`, time by
//! `omega_0`, the geometric mean of the smallest and largest pole modulus).
//!
//! 1. Minimal realization `(A, B, C_Z, D)` pole by pole: `R_m = X Y^T` by its eigen (real pole)
//!    or singular value (pair) decomposition, as many states as the residue's rank.
//! 2. Reciprocity: `Z = Z^T` makes the transposed realization similar to it,
//!    `T A = A^T T`, `T B = C_Z^T` with `T` symmetric and invertible; per pole,
//!    `T = [C_Z^T, A^T C_Z^T] [B, A B]^+`.
//! 3. A storage function `x^T P x / 2` (positive-real lemma): `P > 0` with
//!
//!    ```text
//!    [ A^T P + P A    P B - C_Z^T ]
//!    [ B^T P - C_Z    -(D + D^T)  ]  <=  0,
//!    ```
//!
//!    from the Riccati equation of its boundary, solved through the matrix sign function of
//!    its Hamiltonian. The Riccati equation needs `D + D^T > 0`, so `D` gets `delta I`,
//!    `delta = 1e-8` of the impedance's scale: a damper to the ground that the network keeps
//!    (its force is 1e-8 of the water's; it makes the KYP inequality strict).
//! 4. A storage compatible with reciprocity: the set of such `P` is convex and mapped onto
//!    itself by `P -> T P^-1 T`; the averages `P <- (P + T P^-1 T) / 2` (Newton's iteration for
//!    the sign of `T^-1 P`) stay in it and converge to `P = T P^-1 T`.
//! 5. Coordinates `x~ = Q^T L^T x` (`P = L L^T`, `L^-1 T L^-T = Q Sigma Q^T`, `Sigma = diag(+1,
//!    -1)`): the storage becomes `|x~|^2 / 2` and the realization `Sigma`-symmetric,
//!    `Sigma A = A^T Sigma`, `C_Z^T = Sigma B`. The `+1` coordinates are unit springs, the
//!    `-1` coordinates unit masses, and the KYP inequality says exactly that the substructure's
//!    relaxation and damping matrices are PSD. Rounding is removed by taking the structured
//!    parts and projecting onto the PSD cone; [`SynthesisReport`] says how much that moved.

use super::vector_fitting::RationalFit;
use super::IdentifyError;
use crate::network::Substructure;
use crate::numerics::{matrix_sign, project_psd};
use nalgebra::DMatrix;
use num_complex::Complex64;

/// `delta` of step 3 relative to the impedance's scale.
pub(crate) const REGULARIZATION: f64 = 1e-8;

/// Residue singular values below this fraction of the largest are dropped (as in
/// [`RationalFit::state_count`]).
const RANK_TOLERANCE: f64 = 1e-9;

/// What [`synthesize`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct SynthesisReport {
    /// Springs of the substructure.
    pub springs: usize,
    /// Unit masses of the substructure.
    pub masses: usize,
    /// The damper to the ground added for the Riccati equation (normalized, step 3).
    pub regularization: f64,
    /// Largest departure from the `Sigma`-symmetric structure before it was imposed, relative
    /// to the realization's size.
    pub structure_residual: f64,
    /// Frobenius norm moved by the PSD projections, relative to the matrices' norms.
    pub projection: f64,
    /// Largest `|G_sub - G_fit|` at 0.3, 1 and 3 times each pole's modulus (and its imaginary
    /// part), each entry divided by `sqrt(s_i s_j)`.
    pub deviation: f64,
}

fn failure(message: String) -> IdentifyError {
    IdentifyError::Synthesis(message)
}

/// A real state-space realization of a normalized fit (step 1) with `C_Z`, `D` and the
/// reciprocity matrix `T` (step 2), block by block.
struct Reciprocal {
    a: DMatrix<f64>,
    b: DMatrix<f64>,
    c: DMatrix<f64>,
    d: DMatrix<f64>,
    t: DMatrix<f64>,
}

/// Steps 1 and 2 for poles and residues already normalized.
fn reciprocal_realization(
    poles: &[Complex64],
    residues: &[DMatrix<Complex64>],
    n: usize,
) -> Result<Reciprocal, IdentifyError> {
    let largest = residues
        .iter()
        .flat_map(|r| r.iter().map(|z| z.norm()))
        .fold(0.0, f64::max);
    // (A_b, B_b, Cg_b) per pole, G = Cg (sI - A)^-1 B.
    let mut blocks: Vec<(DMatrix<f64>, DMatrix<f64>, DMatrix<f64>)> = Vec::new();
    for (p, r) in poles.iter().zip(residues) {
        if p.im == 0.0 {
            let eigen = crate::numerics::symmetric_eigen(&r.map(|z| z.re));
            let kept: Vec<usize> = (0..n)
                .filter(|&i| eigen.eigenvalues[i].abs() > RANK_TOLERANCE * largest)
                .collect();
            let k = kept.len();
            if k == 0 {
                continue;
            }
            let a = DMatrix::from_diagonal_element(k, k, p.re);
            let b = DMatrix::from_fn(k, n, |i, j| {
                eigen.eigenvalues[kept[i]].abs().sqrt() * eigen.eigenvectors[(j, kept[i])]
            });
            let cg = DMatrix::from_fn(n, k, |i, j| {
                let l = eigen.eigenvalues[kept[j]];
                eigen.eigenvectors[(i, kept[j])] * l.abs().sqrt() * l.signum()
            });
            blocks.push((a, b, cg));
        } else {
            let svd = crate::numerics::svd(r.clone(), true, true).ok_or_else(|| {
                failure(format!(
                    "the residue of the pole {p} has no singular value decomposition (not \
                     finite, or the iteration did not converge)"
                ))
            })?;
            let (u, v_t) = (svd.u.expect("requested"), svd.v_t.expect("requested"));
            let kept: Vec<usize> = (0..n)
                .filter(|&i| svd.singular_values[i] > RANK_TOLERANCE * largest)
                .collect();
            let k = kept.len();
            if k == 0 {
                continue;
            }
            // R = X Y^T, X = U S^1/2, Y^T = S^1/2 V^H; zeta' = p zeta + Y^T v, G = 2 Re(X zeta).
            let root = |i: usize| svd.singular_values[kept[i]].sqrt();
            let x = DMatrix::from_fn(n, k, |i, j| u[(i, kept[j])] * root(j));
            let yt = DMatrix::from_fn(k, n, |i, j| v_t[(kept[i], j)] * root(i));
            let mut a = DMatrix::zeros(2 * k, 2 * k);
            for i in 0..k {
                a[(i, i)] = p.re;
                a[(i, k + i)] = -p.im;
                a[(k + i, i)] = p.im;
                a[(k + i, k + i)] = p.re;
            }
            let mut b = DMatrix::zeros(2 * k, n);
            b.view_mut((0, 0), (k, n)).copy_from(&yt.map(|z| z.re));
            b.view_mut((k, 0), (k, n)).copy_from(&yt.map(|z| z.im));
            let mut cg = DMatrix::zeros(n, 2 * k);
            cg.view_mut((0, 0), (n, k))
                .copy_from(&x.map(|z| 2.0 * z.re));
            cg.view_mut((0, k), (n, k))
                .copy_from(&x.map(|z| -2.0 * z.im));
            blocks.push((a, b, cg));
        }
    }
    let states: usize = blocks.iter().map(|(a, _, _)| a.nrows()).sum();
    let mut out = Reciprocal {
        a: DMatrix::zeros(states, states),
        b: DMatrix::zeros(states, n),
        c: DMatrix::zeros(n, states),
        d: DMatrix::zeros(n, n),
        t: DMatrix::zeros(states, states),
    };
    let mut at = 0;
    for (a, b, cg) in &blocks {
        let k = a.nrows();
        // Z = s G: C_Z = Cg A, D = Cg B.
        let c = cg * a;
        out.d += cg * b;
        // T [B, A B] = [C^T, A^T C^T].
        let mut krylov = DMatrix::zeros(k, 2 * n);
        krylov.columns_mut(0, n).copy_from(b);
        krylov.columns_mut(n, n).copy_from(&(a * b));
        let mut image = DMatrix::zeros(k, 2 * n);
        image.columns_mut(0, n).copy_from(&c.transpose());
        image
            .columns_mut(n, n)
            .copy_from(&(a.transpose() * c.transpose()));
        let floor = 1e-14 * krylov.norm();
        let pinv = krylov
            .pseudo_inverse(floor)
            .map_err(|e| failure(format!("reciprocity matrix: {e}")))?;
        let t = &image * pinv;
        let t = (&t + t.transpose()) * 0.5;
        out.a.view_mut((at, at), (k, k)).copy_from(a);
        out.b.view_mut((at, 0), (k, n)).copy_from(b);
        out.c.view_mut((0, at), (n, k)).copy_from(&c);
        out.t.view_mut((at, at), (k, k)).copy_from(&t);
        at += k;
    }
    out.d = (&out.d + out.d.transpose()) * 0.5;
    Ok(out)
}

/// The stabilizing solution of `F^T P + P F + P G P + Q = 0` from the sign of its Hamiltonian
/// `[[F, G], [-Q, -F^T]]`: `[I; P]` spans its stable invariant subspace, the null space of
/// `sign(H) + I`.
fn riccati(f: &DMatrix<f64>, g: &DMatrix<f64>, q: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let k = f.nrows();
    let mut h = DMatrix::zeros(2 * k, 2 * k);
    h.view_mut((0, 0), (k, k)).copy_from(f);
    h.view_mut((0, k), (k, k)).copy_from(g);
    h.view_mut((k, 0), (k, k)).copy_from(&(-q));
    h.view_mut((k, k), (k, k)).copy_from(&(-f.transpose()));
    let w = matrix_sign(&h)? + DMatrix::identity(2 * k, 2 * k);
    let lhs = w.columns(k, k).into_owned();
    let rhs = -w.columns(0, k).into_owned();
    let p = crate::numerics::svd(lhs, true, true)?
        .solve(&rhs, 1e-14)
        .ok()?;
    Some((&p + p.transpose()) * 0.5)
}

/// Step 4 stops when a step changes `P` by less than this (relative, Frobenius).
const RECIPROCAL_CHANGE: f64 = 1e-13;

/// Step 4 accepts a stall: a change below this that no longer halves (Newton's iteration has
/// reached its rounding level, which for an ill-conditioned `P` can lie above
/// [`RECIPROCAL_CHANGE`]).
const RECIPROCAL_STALL: f64 = 1e-8;

/// The reciprocal storage of step 4 (module docs): `P <- (P + T P^-1 T) / 2` from a storage
/// `P` in the KYP set until the change is below `tolerance` or stalls at rounding level.
fn reciprocal_storage(
    mut p: DMatrix<f64>,
    t: &DMatrix<f64>,
    tolerance: f64,
) -> Result<DMatrix<f64>, IdentifyError> {
    let mut previous = f64::INFINITY;
    for _ in 0..200 {
        let inverse = p
            .clone()
            .cholesky()
            .ok_or_else(|| failure("the storage lost positive definiteness".into()))?
            .inverse();
        let next = (&p + t * inverse * t) * 0.5;
        let next = (&next + next.transpose()) * 0.5;
        let change = (&next - &p).norm() / next.norm();
        p = next;
        let stalled = change < RECIPROCAL_STALL && (change == 0.0 || change > 0.5 * previous);
        if change < tolerance || stalled {
            return Ok(p);
        }
        previous = change;
    }
    Err(failure("the reciprocal storage did not converge".into()))
}

/// Realizes a passive [`RationalFit`] as a [`Substructure`] on its DOFs (module docs).
/// Fails with [`IdentifyError::Synthesis`] when the fit is not passive (no storage function
/// exists) or a step loses its accuracy.
pub fn synthesize(fit: &RationalFit) -> Result<(Substructure, SynthesisReport), IdentifyError> {
    let n = fit.dof_scales.len();
    if fit.poles.len() != fit.residues.len()
        || fit.residues.iter().any(|r| r.shape() != (n, n))
        || fit.dof_scales.iter().any(|s| !(s.is_finite() && *s > 0.0))
    {
        return Err(failure(
            "the fit's poles, residues and scales do not match".into(),
        ));
    }
    if fit.poles.iter().any(|p| !(p.re < 0.0 && p.is_finite())) {
        return Err(failure("a pole is not in the open left half-plane".into()));
    }
    let w = fit.dof_scales.map(f64::sqrt);
    let moduli = fit.poles.iter().map(|p| p.norm());
    let (lo, hi) = moduli.fold((f64::INFINITY, 0.0_f64), |(l, h), m| (l.min(m), h.max(m)));
    let omega0 = if fit.poles.is_empty() {
        1.0
    } else {
        (lo * hi).sqrt()
    };
    let poles: Vec<Complex64> = fit.poles.iter().map(|p| p / omega0).collect();
    let residues: Vec<DMatrix<Complex64>> = fit
        .residues
        .iter()
        .map(|r| DMatrix::from_fn(n, n, |i, j| r[(i, j)] / (w[i] * w[j] * omega0)))
        .collect();
    let sys = reciprocal_realization(&poles, &residues, n)?;
    let states = sys.a.nrows();
    // Impedance scale: sum over poles of |p| |R| (a pair twice).
    let z_scale: f64 = poles
        .iter()
        .zip(&residues)
        .map(|(p, r)| p.norm() * r.norm() * if p.im == 0.0 { 1.0 } else { 2.0 })
        .sum::<f64>()
        .max(sys.d.norm())
        .max(f64::MIN_POSITIVE);
    let delta = REGULARIZATION * z_scale;
    let d = &sys.d + DMatrix::identity(n, n) * delta;

    if states == 0 {
        return Err(failure(
            "the fit has no pole with a non-zero residue".into(),
        ));
    }
    let (ns, substructure_normalized, structure_residual, projection) = {
        // Step 3: Riccati of the KYP boundary, R = D + D^T.
        let r_inv = (&d * 2.0)
            .try_inverse()
            .ok_or_else(|| failure("D + D^T is singular".into()))?;
        let f = &sys.a - &sys.b * &r_inv * &sys.c;
        let g = &sys.b * &r_inv * sys.b.transpose();
        let q = sys.c.transpose() * &r_inv * &sys.c;
        let p = riccati(&f, &g, &q).ok_or_else(|| {
            failure(
                "no storage function: the Hamiltonian has eigenvalues on the imaginary axis \
                 (the fit is not passive)"
                    .into(),
            )
        })?;
        if p.clone().cholesky().is_none() {
            return Err(failure(
                "the storage function is not positive definite (the fit is not passive)".into(),
            ));
        }
        // Step 4: P <- (P + T P^-1 T) / 2 until P = T P^-1 T.
        let p = reciprocal_storage(p, &sys.t, RECIPROCAL_CHANGE)?;
        // Step 5: coordinates with storage |x|^2 / 2 and signature Sigma.
        let l = p
            .cholesky()
            .ok_or_else(|| failure("the storage lost positive definiteness".into()))?
            .l();
        let l_inv = l
            .clone()
            .try_inverse()
            .ok_or_else(|| failure("the storage factor is singular".into()))?;
        let sigma0 = &l_inv * &sys.t * l_inv.transpose();
        let eigen = crate::numerics::symmetric_eigen(&sigma0);
        if let Some(bad) = eigen
            .eigenvalues
            .iter()
            .find(|l| (l.abs() - 1.0).abs() > 1e-6)
        {
            return Err(failure(format!(
                "the signature has an eigenvalue {bad:e}, not +-1"
            )));
        }
        // Springs (+1) first, then masses (-1).
        let mut order: Vec<usize> = (0..states).collect();
        order.sort_by_key(|&i| (eigen.eigenvalues[i] < 0.0, i));
        let ns = order
            .iter()
            .filter(|&&i| eigen.eigenvalues[i] > 0.0)
            .count();
        let q_mat = DMatrix::from_fn(states, states, |i, j| eigen.eigenvectors[(i, order[j])]);
        let to_new = q_mat.transpose() * l.transpose();
        let from_new = l_inv.transpose() * &q_mat;
        let a = &to_new * &sys.a * &from_new;
        let b = &to_new * &sys.b;
        let c = &sys.c * &from_new;
        let nm = states - ns;
        let a11 = a.view((0, 0), (ns, ns));
        let a12 = a.view((0, ns), (ns, nm));
        let a21 = a.view((ns, 0), (nm, ns));
        let a22 = a.view((ns, ns), (nm, nm));
        let (b1, b2) = (b.rows(0, ns), b.rows(ns, nm));
        let (c1, c2) = (c.columns(0, ns), c.columns(ns, nm));
        let residual = [
            (a12 + a21.transpose()).norm() / a.norm(),
            (a11 - a11.transpose()).norm() / a.norm(),
            (a22 - a22.transpose()).norm() / a.norm(),
            (b1 - c1.transpose()).norm() / b.norm(),
            (b2 + c2.transpose()).norm() / b.norm(),
        ]
        .into_iter()
        .fold(0.0, f64::max);
        if residual.is_nan() || residual >= 1e-6 {
            return Err(failure(format!(
                "the realization is not reciprocal to 1e-6 (residual {residual:e})"
            )));
        }
        let relaxation = -(a11 + a11.transpose()) * 0.5;
        let coupling = (a12 - a21.transpose()) * 0.5;
        let spring_input = (b1 + c1.transpose()) * 0.5;
        let damper_input = (c2.transpose() - b2) * 0.5;
        let mass_damping = -(a22 + a22.transpose()) * 0.5;
        let mut damping = DMatrix::zeros(nm + n, nm + n);
        damping.view_mut((0, 0), (nm, nm)).copy_from(&mass_damping);
        damping.view_mut((0, nm), (nm, n)).copy_from(&damper_input);
        damping
            .view_mut((nm, 0), (n, nm))
            .copy_from(&damper_input.transpose());
        damping.view_mut((nm, nm), (n, n)).copy_from(&d);
        let relaxation_psd = project_psd(&relaxation);
        let damping_psd = project_psd(&damping);
        let moved = ((&relaxation_psd - &relaxation).norm()
            / relaxation.norm().max(f64::MIN_POSITIVE))
        .max((&damping_psd - &damping).norm() / damping.norm());
        let mut incidence = DMatrix::zeros(ns, nm + n);
        incidence.columns_mut(0, nm).copy_from(&coupling);
        incidence.columns_mut(nm, n).copy_from(&spring_input);
        let sub = Substructure {
            masses: nm,
            spring_incidence: incidence,
            spring_relaxation: relaxation_psd,
            damping: damping_psd,
        };
        (ns, sub, residual, moved)
    };
    // Back to SI: time by omega_0, DOFs by w (a congruence on the hull's columns).
    let mut sub = substructure_normalized.scaled(1.0, omega0 * omega0);
    let nm = sub.masses;
    for j in 0..n {
        sub.spring_incidence.column_mut(nm + j).scale_mut(w[j]);
    }
    for i in 0..nm + n {
        for j in 0..nm + n {
            let wi = if i < nm { 1.0 } else { w[i - nm] };
            let wj = if j < nm { 1.0 } else { w[j - nm] };
            sub.damping[(i, j)] *= wi * wj;
        }
    }
    // Deviation from the fit around every pole.
    let mut deviation: f64 = 0.0;
    let frequencies = fit.poles.iter().flat_map(|p| {
        [
            0.3 * p.norm(),
            p.im.abs().max(p.norm() * 0.1),
            3.0 * p.norm(),
        ]
    });
    for omega in frequencies {
        let got = sub.dynamic_mass(Complex64::new(0.0, omega));
        let want = fit.evaluate(omega);
        for i in 0..n {
            for j in 0..n {
                deviation = deviation.max(
                    (got[(i, j)] - want[(i, j)]).norm()
                        / (fit.dof_scales[i] * fit.dof_scales[j]).sqrt(),
                );
            }
        }
    }
    let report = SynthesisReport {
        springs: ns,
        masses: sub.masses,
        regularization: delta,
        structure_residual,
        projection,
        deviation,
    };
    Ok((sub, report))
}

#[cfg(test)]
mod tests;
