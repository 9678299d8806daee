//! Identification of a passive equivalent mass-spring-damper network from the complex added
//! mass `A~(omega)` (Schilder et al., section 4).
//!
//! # Target and error
//!
//! Input: [`FrequencyResponse`], the panel method's `A~(omega) = a(omega) - i b(omega) / omega`
//! (time factor `exp(+i omega t)`, SI, symmetric n x n) on a frequency grid, and `A_inf`. The
//! network of [`crate::realize`] has the added mass transfer function
//! `H(s) = A_inf + sum_b d_b d_b^T G_b(s)`, and the force on the hull by the water is
//! `F = -s^2 H(s) q`, the same map as `F = -s^2 A~ q` (Cummins' equation with `s = i omega`), so
//! `H(i omega)` must approximate `A~(omega)`. `m0 = A_inf` is taken from the data and never
//! fitted (Schilder et al.: `H(s -> inf) = m0`). The fit minimizes Schilder et al.'s error (eq. 17),
//!
//! ```text
//! e = sum_omega sum_ij [ (Re A~_ij - Re H_ij)^2 + (Im A~_ij - Im H_ij)^2 ] / (s_i s_j),
//! s_i = max over the band of |A~_ii(omega)|,
//! ```
//!
//! over the frequency points inside `FitParams::band`. The normalization by `sqrt(s_i s_j)`
//! weighs every matrix entry by its natural scale, so weak couplings neither dominate nor get
//! lost. For one DOF it is the constant `s = max |A~|` (Schilder et al.'s plain error, eq. 17). A DOF
//! that moves (almost) no water, like the roll of a circle about its centre, has `s_i` raised
//! to `SCALE_FLOOR` times the largest `s_j`, so its entries are fitted in absolute terms.
//! Reported errors are absolute (`FitReport::max_error`, `rms_error`, in A~ units per entry);
//! the tolerance is a fraction of the fixed scale `sqrt(s_i s_j)`, so it bounds the absolute
//! error, not the error relative to each point's value. Default: 1 % (for one DOF: 1 % of the
//! largest |A~| in the band).
//!
//! # Passive by construction
//!
//! Every stage value is parameterized by its logarithm (`m = exp(p)` and so on), and the
//! coupled form's weight matrices are PSD (projected onto the cone, then factored), so every
//! network the fitter can return has `m, k, c > 0`: passive and reciprocal (see
//! [`crate::realize`]). `A_inf` is symmetrized and, if it has slightly negative eigenvalues
//! (discretization), clipped to PSD (`FitReport::added_mass_inf_adjustment`).
//!
//! # Algorithms (deterministic)
//!
//! Frequencies are scaled by `omega_ref = sqrt(omega_lo omega_hi)` of the band and masses by
//! `s_i`, so all parameters are O(1).
//!
//! * Series chain and parallel bank (one DOF): Levenberg-Marquardt (hand-written) on the log
//!   parameters with the analytic Jacobian of the chain recursion. Starting points: the fit of
//!   one order less with a stage or branch added (a continuation, so a higher order is never
//!   worse), and a physically motivated grid (stage frequencies log-spaced across the band,
//!   damping ratios 0.5 and 1.5; parallel-bank masses from non-negative least squares). Only if
//!   the tolerance is not met: `FitParams::restarts` random starts from a fixed seed (bitwise
//!   reproducible).
//! * Coupled (n DOFs): branches whose chain dynamics are shared in groups. A group `p` is a
//!   chain with first mass 1 and dynamic mass `g_p(s)` (one stage:
//!   `g_p = (k_p + c_p s) / (s^2 + c_p s + k_p)`), weighted by a PSD matrix `W_p`:
//!   `H = A_inf + sum_p W_p g_p(s)`. Each `W_p = sum_r lambda_r v_r v_r^T` becomes one branch per
//!   eigenvalue (direction `v_r`, the chain scaled by `lambda_r`). The order of a coupled fit
//!   is the number of groups; its auxiliary DOFs are the ranks times the stages. The fit works
//!   in the subspace the normalized data span (e.g. 6 of the 9 DOFs of a hull whose rigid
//!   motions are combinations of its Craig-Bampton modes). Two paths per order, the network
//!   with the fewest auxiliary DOFs that meets the tolerance wins:
//!   1. Variable projection: LM on the one-stage groups' `ln k_p, ln c_p` with the `W_p`
//!      solved by linear least squares for every entry at once (Kaufman's Jacobian), started
//!      from a parallel-bank fit of the mean normalized diagonal, a log-spaced grid, and the
//!      previous order's groups. Exact for data made by such a network. It stops being tried
//!      once it falls far behind path 2.
//!   2. Dictionary: 80 two-stage band-pass chains (tiny first damper) spread over the band get
//!      PSD weights at once; the `order` groups that carry the most response are kept.
//!
//!   In both, the `W_p` are solved under `W_p >= 0` (accelerated projected gradient, convex),
//!   then the groups' chain values and factors `W_p = L_p L_p^T` are refined jointly by LM
//!   (passive at every step) until the tolerance is met or the error stalls. The refinement
//!   aims at the largest error, not the sum of squares: every 5 iterations the rows of band
//!   point k are reweighted by `rho_k <- rho_k sqrt(e_k / max_k e_k)` (Lawson's minimax
//!   iteration, damped; `e_k` the largest normalized entry error at point k), and the iterate
//!   with the smallest largest error is kept. Why groups of band-pass chains: the damping
//!   `b(omega)` of a 2D hull has rank 2 (one symmetric and one antisymmetric wave) and its
//!   principal directions turn with frequency. A branch only adds damping along its own
//!   direction, so following a turning direction takes branches whose damping is confined to
//!   a band; one-mass branches keep damping `c` up to infinite frequency and cannot (on the
//!   semicircle's 9 DOFs they stall near 4 % error).
//! * Invariant blocks (coupled): a mirror-symmetric hull's data is block diagonal in a
//!   suitable orthogonal basis of DOF space (symmetric and antisymmetric motions), and each
//!   block is fitted on its own, its damping of rank 1. The blocks are found from the data,
//!   without knowledge of the hull: in the reduced subspace (dimension r) the commutant
//!
//!   ```text
//!   C = { X = X^T :  X M = M X  for every M in { Re T(omega_k), Im T(omega_k) } },
//!   ```
//!
//!   `T` the normalized target, is the null space of a linear least-squares problem in the
//!   `r (r + 1) / 2` entries of `X` (right singular vectors whose singular value is below
//!   1e-6 of the largest; `X = I` is always in it). If `dim C >= 2`, every eigenspace of a
//!   generic element `X = sum_q c_q X_q` (fixed pseudo-random `c_q`) is invariant under every
//!   `T(omega)`; its eigenvectors give an orthogonal `Q = [Q_1 .. Q_m]` with
//!   `Q^T T(omega) Q = diag(T_1(omega), .., T_m(omega))`. Block b is fitted by the machinery
//!   above on `T_b` with its branch directions mapped back, `d = S^(1/2) basis Q_b v`
//!   (normalized), and the branches of all blocks form one network (`A_inf` unchanged, not
//!   fitted, so not part of the commutant). The split is used only if the couplings it drops
//!   stay below 1e-3 of the tolerance. The blocks' errors add up in the DOFs they share (the
//!   semicircle's `cb1` is half symmetric, half antisymmetric), so every block first gets the
//!   tolerance, then, while the joined network misses it, the blocks' tolerance is scaled by
//!   `0.95 tol / error` (at most 4 rounds; each block continues from its previous order). A
//!   fixed `order` applies to every block. The semicircle's data is mirror-symmetric to
//!   rounding (singular values 1e-15 against 7e-3 of the largest for the first genuine
//!   coupling); a DOF that moves no water (its roll) lies outside the reduced subspace and
//!   gets no branch.
//! * Rational path (coupled, [`CoupledMethod::Rational`], the default): passive vector
//!   fitting of every invariant block ([`vector_fitting`]; blocks of noisy data, e.g. a
//!   symmetric hull on an asymmetric mesh, drop couplings of at most a tenth of the
//!   tolerance), the passivity enforced by the whole matrix inequality at sampled frequencies
//!   with a margin of 2 % of the tolerance, poles kept within a factor 30 of the band; each
//!   part of the fit that acts on its own motions realized as a mechanical substructure
//!   ([`synthesis`]). Every block searches its own order (poles per block), the smallest that
//!   meets the block's tolerance, and keeps its best fit; while the joined network misses the
//!   tolerance the blocks' tolerances are tightened (module docs of `rational`). On the
//!   semicircle's 9 DOFs (kR 0.05 .. 4.5): 25 states at 0.75 %, where the chains need 56; the
//!   midship section's 6 DOFs: 28 states at 0.90 % (docs/IDENTIFICATION.md). For one DOF
//!   (automatic form) it then competes with the series chain and the parallel bank: the
//!   fewest states within the tolerance win. The chains are the fallback when no order gives
//!   a passive network (said in the notes).
//! * Pruning (coupled): the branches are tried for removal in order of their largest
//!   normalized contribution `max_band |G_b(i omega)| max_i d_i^2 / s_i`; a branch goes if the
//!   network without it still meets the tolerance (if the tolerance is not met: if the error
//!   does not grow). The reported order is the number of distinct chain dynamics left.
//!
//! Automatic order: orders 1, 2, ... `max_order` (the rational path: per block, and below the
//! band's point count); the first one whose largest normalized error is within the tolerance
//! is returned. If none is, the fit with the smallest error seen is returned with
//! `tolerance_met = false`, never a worse one; the notes name the orders that failed and why.
//!
//! Noise floor: [`FitParams::noise`] (an imported database's reciprocity gap) over
//! `sqrt(s_i s_j)`; where it exceeds the tolerance the fit still aims at the tolerance, is
//! judged against the floor (`FitReport::tolerance`), and says so.
//! Few frequencies (fewer than 16 in the band): a note says what the network assumes between
//! them.
//!
//! Automatic form (`FitParams::form = None`): several DOFs get the coupled form. One DOF gets
//! the series chain and, with the rational path, a one-DOF coupled fit; if the chain misses
//! the tolerance, the parallel bank is fitted as well. Among those that meet the tolerance the
//! fewest states win (the chain on a tie), else the smallest error; a choice other than the
//! chain is said in `FitReport::notes`.
//!
//! # Layout
//!
//! - `response`: the input [`FrequencyResponse`]; `error`: [`IdentifyError`].
//! - `params`: [`FitParams`] and [`FitReport`].
//! - `problem`: the normalized problem, its errors and the report; [`dof_scales`] and the
//!   rate limit ([`fastest_rate`]).
//! - `chain`: the chain recursion and its log-parameter derivatives.
//! - `single_dof`: series chain and parallel bank.
//! - `coupled/`: the coupled form (blocks, groups, weights, the two paths, refinement,
//!   branches).
//! - `vector_fitting`, `synthesis`, `rational`: the rational path.
//!
//! The hydrodynamics-free numerics (least squares, NNLS, PSD projection, random starts) are in
//! `src/numerics/`.

mod chain;
mod coupled;
mod error;
mod params;
mod problem;
mod rational;
mod response;
mod single_dof;
pub mod synthesis;
#[cfg(test)]
mod tests;
pub mod vector_fitting;

pub use error::IdentifyError;
pub(crate) use params::DEFAULT_TOLERANCE;
pub use params::{
    pole_range_below, CoupledMethod, FitParams, FitReport, STRIP_FINITE_DEPTH_POLE_RANGE,
};
pub use rational::POLE_RANGE;

pub use problem::{dof_scales, fastest_rate, FASTEST_RATE_OVER_BAND};
pub use response::{FrequencyResponse, FREQUENCY_RANGE, MAX_FREQUENCY_RATIO, VALUE_RANGE};

use crate::network::{Network, NetworkError, NetworkForm};
use nalgebra::DMatrix;
use problem::Problem;

/// Fits a network to `data` (see the module docs): of `params.form`, or of the automatic form
/// if it is `None`. The report's errors and verdict are those of the network as its file
/// holds it (`check_written_network`).
pub fn fit(data: &FrequencyResponse, params: &FitParams) -> Result<FitReport, IdentifyError> {
    let mut report = match params.form {
        Some(form) => fit_form(data, params, form),
        None if data.dof_count() == 1 => fit_one_dof_automatic(data, params),
        None => fit_form(data, params, NetworkForm::Coupled),
    }?;
    check_written_network(&mut report, data)?;
    Ok(report)
}

/// [`fit`] in scaled DOF coordinates `q'_i = f_i q_i`: the data `A~'_ij = A~_ij / (f_i f_j)`
/// is fitted and the network mapped back ([`Network::with_dof_factors`]); the report is the
/// mapped network's against `data`. With `f_i = L^(e_i)` (`L` a length, `e_i` the DOF's length
/// exponent: 1 for a rotation) every entry has the units of a mass, so the fit no longer
/// depends on the unit of length: the error floor `SCALE_FLOOR` compares DOFs of one
/// dimension. Without it, a sphere's WAMIT data at a length scale of 1e6 m (translations
/// 2e23 kg, rotations 7e35 kg m^2) had its translations measured against 1e-6 of the
/// rotations': its heave went unfitted (94.6 % off) under a verdict of 0.67 %.
///
/// [`Network::with_dof_factors`]: crate::network::Network::with_dof_factors
pub fn fit_in_dof_units(
    data: &FrequencyResponse,
    params: &FitParams,
    factors: &[f64],
) -> Result<FitReport, IdentifyError> {
    let n = data.dof_count();
    if factors.len() != n || factors.iter().any(|f| !(f.is_finite() && *f > 0.0)) {
        return Err(IdentifyError::InvalidParams(format!(
            "DOF factors {factors:?}: expected {n} finite positive numbers"
        )));
    }
    let unscale = |i: usize, j: usize| 1.0 / (factors[i] * factors[j]);
    let scaled = FrequencyResponse {
        added_mass: data
            .added_mass
            .iter()
            .map(|m| DMatrix::from_fn(n, n, |i, j| m[(i, j)] * unscale(i, j)))
            .collect(),
        added_mass_inf: DMatrix::from_fn(n, n, |i, j| data.added_mass_inf[(i, j)] * unscale(i, j)),
        ..data.clone()
    };
    let scaled_params = FitParams {
        noise: params.noise.as_ref().map(|m| {
            DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| {
                m[(i, j)] * unscale(i.min(n - 1), j.min(n - 1))
            })
        }),
        ..params.clone()
    };
    let mut report = fit(&scaled, &scaled_params)?;
    report.network = report
        .network
        .with_dof_factors(factors)
        .map_err(|e| IdentifyError::InvalidData(format!("the fitted network: {e}")))?;
    let rescale = |m: &DMatrix<f64>| DMatrix::from_fn(n, n, |i, j| m[(i, j)] / unscale(i, j));
    report.error_scale = rescale(&report.error_scale);
    report.max_error = rescale(&report.max_error);
    report.rms_error = rescale(&report.rms_error);
    let largest = factors.iter().fold(0.0, |a: f64, f| a.max(*f));
    report.added_mass_inf_adjustment *= largest * largest;
    check_written_network(&mut report, data)?;
    Ok(report)
}

/// Makes the report's errors and verdict those of the network as written: its file text is
/// read back (refused, naming the limit, if a number exceeds what a network file holds) and
/// its response compared with `data` at the report's band frequencies, in the report's norm
/// (each entry's largest error over `error_scale`). A non-finite error is never within the
/// tolerance.
pub(crate) fn check_written_network(
    report: &mut FitReport,
    data: &FrequencyResponse,
) -> Result<(), IdentifyError> {
    let written = Network::from_xml_str(&report.network.to_xml_string(), "the fitted network")
        .map_err(|e| {
            IdentifyError::NotWritable(match e {
                NetworkError::File { message, .. } => message,
                other => other.to_string(),
            })
        })?;
    let n = data.dof_count();
    let (lo, hi) = report.band;
    let mut max = DMatrix::<f64>::zeros(n, n);
    let mut sum = DMatrix::<f64>::zeros(n, n);
    let mut count = 0usize;
    for (w, a) in data.omega.iter().zip(&data.added_mass) {
        if *w < lo || *w > hi {
            continue;
        }
        let h = written.added_mass_tf(*w);
        for k in 0..n * n {
            let e = (h[k] - a[k]).norm();
            max[k] = problem::nan_max(max[k], e);
            sum[k] += e * e;
        }
        count += 1;
    }
    if count == 0 {
        return Err(IdentifyError::InvalidBand(format!(
            "no frequency of the data lies in the fitted band {lo} .. {hi} rad/s"
        )));
    }
    report.max_relative_error = problem::relative_error(&max, &report.error_scale);
    report.tolerance_met = report.max_relative_error <= report.tolerance;
    report.max_error = max;
    report.rms_error = sum.map(|s| (s / count as f64).sqrt());
    report.states = written.state_count();
    report.aux_dofs = written.aux_dof_count();
    report.network = written;
    Ok(())
}

/// One DOF, no form given: the series chain, and with [`CoupledMethod::Rational`] the rational
/// path (a one-DOF coupled network with a substructure); if the chain misses the tolerance, the parallel bank too.
/// Among the fits that meet the tolerance the one with the fewest states wins (the chain on a
/// tie; the rational search stops below the states of a chain that meets it); if none does,
/// the smallest error. A failed alternative leaves the chain.
fn fit_one_dof_automatic(
    data: &FrequencyResponse,
    params: &FitParams,
) -> Result<FitReport, IdentifyError> {
    let chain = fit_form(data, params, NetworkForm::SeriesChain)?;
    let mut candidates = vec![chain];
    if params.coupled_method == CoupledMethod::Rational {
        // One state per pole for one DOF: against a chain that meets the tolerance, only
        // orders below its state count can win, so the search stops there.
        let max_order = match (candidates[0].tolerance_met, params.order) {
            (true, None) => params.max_order.min(candidates[0].states.saturating_sub(1)),
            _ => params.max_order,
        };
        let rational = FitParams {
            max_order,
            ..params.clone()
        };
        if max_order >= 1 {
            if let Ok(rational) = fit_form(data, &rational, NetworkForm::Coupled) {
                candidates.push(rational);
            }
        }
    }
    if !candidates[0].tolerance_met {
        if let Ok(bank) = fit_form(data, params, NetworkForm::ParallelBank) {
            candidates.push(bank);
        }
    }
    let describe = |r: &FitReport| {
        let what = if r.network.substructures.is_empty() {
            r.network.form.name().to_string()
        } else {
            "rational fit (a substructure)".to_string()
        };
        format!(
            "{what}: {} states, {:.3} %",
            r.states,
            100.0 * r.max_relative_error
        )
    };
    let summary: Vec<String> = candidates.iter().map(describe).collect();
    let best = if candidates.iter().any(|r| r.tolerance_met) {
        candidates
            .iter()
            .enumerate()
            .filter(|(_, r)| r.tolerance_met)
            .min_by_key(|(k, r)| (r.states, *k))
            .map(|(k, _)| k)
    } else {
        candidates
            .iter()
            .enumerate()
            .min_by(|(_, a), (_, b)| a.max_relative_error.total_cmp(&b.max_relative_error))
            .map(|(k, _)| k)
    }
    .expect("the chain is a candidate");
    let mut report = candidates.swap_remove(best);
    if best != 0 {
        report.notes.push(format!(
            "automatic form: {} is used (candidates: {})",
            describe(&report),
            summary.join("; ")
        ));
    }
    Ok(report)
}

/// Most DOFs a fit takes. Its cost grows faster than cubically with them (synthetic
/// diagonally dominant databases, 40 frequencies, CPU time: 5 DOFs 5.6 s, 10 DOFs 19 s, 20 DOFs
/// more than 288 s and unfinished); 12 DOFs, two rigid bodies, take about 40 s by
/// extrapolation (not measured).
pub const MAX_FIT_DOFS: usize = 12;

/// Fits a network of the given form.
fn fit_form(
    data: &FrequencyResponse,
    params: &FitParams,
    form: NetworkForm,
) -> Result<FitReport, IdentifyError> {
    data.validate()?;
    if data.dof_count() > MAX_FIT_DOFS {
        return Err(IdentifyError::InvalidData(format!(
            "{} DOFs; a fit takes at most {MAX_FIT_DOFS} (its cost grows faster than the cube \
             of the DOFs: 20 DOFs ran for more than 5 minutes); select the DOFs to fit",
            data.dof_count()
        )));
    }
    let tolerance = params.tolerance.unwrap_or(DEFAULT_TOLERANCE);
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(IdentifyError::InvalidParams(format!(
            "tolerance must be finite and > 0, got {tolerance}"
        )));
    }
    if params.max_order == 0 {
        return Err(IdentifyError::InvalidParams(
            "max_order must be >= 1".into(),
        ));
    }
    // Infinite: no bound below the band.
    if params.pole_range_below.is_nan() || params.pole_range_below < 1.0 {
        return Err(IdentifyError::InvalidParams(format!(
            "pole_range_below must be >= 1, got {}",
            params.pole_range_below
        )));
    }
    if let Some(order) = params.order {
        if order == 0 || order > params.max_order {
            return Err(IdentifyError::InvalidParams(format!(
                "order {order} is outside 1..={}",
                params.max_order
            )));
        }
    }
    if let Some(stages) = params.coupled_stages {
        if !(1..=4).contains(&stages) {
            return Err(IdentifyError::InvalidParams(format!(
                "coupled_stages must be 1 to 4, got {stages}"
            )));
        }
    }
    if form.is_single_dof() && data.dof_count() != 1 {
        return Err(IdentifyError::InvalidParams(format!(
            "form {form} fits one DOF but the data has {} (use FrequencyResponse::select, or \
             the coupled form)",
            data.dof_count()
        )));
    }
    let problem = Problem::new(data, params.band)?;
    let mut notes = Vec::new();
    // The search aims at the tolerance; the verdict takes the data's noise floor when larger.
    let verdict = match noise_floor(&problem, params.noise.as_ref())? {
        Some((floor, i, j)) if floor > tolerance => {
            notes.push(format!(
                "the data's own noise (reciprocity gap |A~_ij - A~_ji| / 2) reaches {:.3} % of \
                 sqrt(|A_ii A_jj|) at {}-{}, above the tolerance {:.3} %: the fit is judged \
                 against that noise floor (no network can be told apart from the data more \
                 finely; a finer mesh of the source gives cleaner data)",
                100.0 * floor,
                problem.dof_names[i],
                problem.dof_names[j],
                100.0 * tolerance
            ));
            floor
        }
        _ => tolerance,
    };
    if problem.omega.len() < FEW_POINTS {
        notes.push(format!(
            "only {} frequencies in the band: the network passes near them and between them \
             follows the lowest-order passive rational function that does (smooth, no \
             resonance the data does not show); a denser database would confirm it",
            problem.omega.len()
        ));
    }
    let rational = form == NetworkForm::Coupled
        && params.coupled_stages.is_none()
        && params.coupled_method == CoupledMethod::Rational;
    let (order, network, iterations) = if rational {
        match rational::fit_rational(&problem, data, params, tolerance) {
            Ok(outcome) => {
                notes.extend(outcome.notes);
                (outcome.order, outcome.network, outcome.iterations)
            }
            Err(e) => {
                notes.push(format!(
                    "the rational path failed ({e}); branch chains are used"
                ));
                problem.fit_coupled_network(params, tolerance)?
            }
        }
    } else if form == NetworkForm::Coupled {
        problem.fit_coupled_network(params, tolerance)?
    } else {
        problem.fit_single_dof(params, form, tolerance)?
    };
    // Every form keeps its networks within the rate limit; stated once for all of them.
    let rate = fastest_rate(&network);
    if rate > problem.rate_limit() {
        return Err(problem.over_fit_error(order, rate));
    }
    network.validate().map_err(|e| {
        IdentifyError::InvalidData(format!(
            "the fitted network is not valid ({e}); check the data"
        ))
    })?;
    let mut report = problem.report(network, order, verdict, iterations);
    report.notes = notes;
    Ok(report)
}

/// Fewer band points than this get a note on what the network assumes between them.
const FEW_POINTS: usize = 16;

/// The largest `noise_ij / sqrt(s_i s_j)` and its entry, if a noise is given.
fn noise_floor(
    problem: &Problem,
    noise: Option<&nalgebra::DMatrix<f64>>,
) -> Result<Option<(f64, usize, usize)>, IdentifyError> {
    let Some(noise) = noise else {
        return Ok(None);
    };
    let n = problem.n();
    if noise.shape() != (n, n) || !noise.iter().all(|x| x.is_finite() && *x >= 0.0) {
        return Err(IdentifyError::InvalidParams(format!(
            "noise must be a {n} x {n} matrix of finite values >= 0"
        )));
    }
    let mut worst = (0.0, 0, 0);
    for i in 0..n {
        for j in 0..n {
            let scale = problem::error_scale(&problem.scale, i, j);
            let floor = noise[(i, j)] / scale;
            if floor > worst.0 {
                worst = (floor, i.min(j), i.max(j));
            }
        }
    }
    Ok(Some(worst))
}
