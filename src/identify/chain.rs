//! Dynamic mass of one series chain of stages and its derivatives with respect to the log
//! stage values, the recursion of [`crate::realize`] from the far end:
//!
//! ```text
//! G_(len+1) = 0,   M_j = m_j + G_(j+1),   Z_j = k_j + c_j s,   G_j = M_j Z_j / (Z_j + s^2 M_j),
//! ```
//!
//! `G(s) = G_1(s)`. The fitters work on `ln m, ln k, ln c`, bounded by [`LOG_BOUND`].

use num_complex::Complex64;

/// Bound on the log parameters (normalized units): keeps exp() finite.
pub(super) const LOG_BOUND: f64 = 35.0;

/// Dynamic mass `G(s)` of one chain with values `[m_1, k_1, c_1, m_2, ...]`, and if asked
/// `dG / d ln(value)` for every value (the chain recursion of [`crate::realize`]).
pub(super) fn chain_response(
    values: &[f64],
    s: Complex64,
    grad: Option<&mut [Complex64]>,
) -> Complex64 {
    let len = values.len() / 3;
    let s2 = s * s;
    let zero = Complex64::new(0.0, 0.0);
    let mut node = [zero; MAX_CHAIN];
    let mut spring = [zero; MAX_CHAIN];
    let mut denominator = [zero; MAX_CHAIN];
    let mut beyond = zero;
    for j in (0..len).rev() {
        node[j] = beyond + values[3 * j];
        spring[j] = Complex64::new(values[3 * j + 1], 0.0) + s * values[3 * j + 2];
        denominator[j] = spring[j] + s2 * node[j];
        beyond = node[j] * spring[j] / denominator[j];
    }
    if let Some(grad) = grad {
        let mut product = Complex64::new(1.0, 0.0);
        for j in 0..len {
            let d2 = denominator[j] * denominator[j];
            let d_node = spring[j] * spring[j] / d2;
            let d_spring = s2 * node[j] * node[j] / d2;
            grad[3 * j] = product * d_node * values[3 * j];
            grad[3 * j + 1] = product * d_spring * values[3 * j + 1];
            grad[3 * j + 2] = product * d_spring * s * values[3 * j + 2];
            product *= d_node;
        }
    }
    beyond
}

/// Longest chain the fitter builds.
pub(super) const MAX_CHAIN: usize = 16;
