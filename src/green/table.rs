//! Table of `Q(p) = e^{-p} Ei(p)` at about 1100 nodes in the first quadrant (inner log-polar
//! grid for `1 <= |p| < 8`, outer square grid up to `|p| = 40`) with Taylor steps from the
//! nearest node: `Q'(p) = 1/p - Q(p)` gives every derivative. Elsewhere `Q` is computed
//! directly; the lower half plane by conjugation.

use super::exp_integral::{exp, scaled_ei, scaled_ei_upper_given_exp, RECIPROCALS};
use num_complex::Complex64;

/// Inner log-polar grid: rings `rho_j = INNER_RHO_MIN * 1.15^j`, `j < INNER_RINGS`, and angles
/// `tan(theta_i / 2) = i / INNER_ANGLES`, `i <= INNER_ANGLES` (first quadrant).
const INNER_RHO_MIN: f64 = 1.0;
const INNER_RHO_MAX: f64 = 8.0;
const INNER_RING_RATIO: f64 = 1.15;
/// `ln(1.15)`, `ln(INNER_RHO_MIN)`.
const INNER_LN_RATIO: f64 = 0.139_761_942_375_158_63;
const INNER_LN_RHO_MIN: f64 = 0.0;
const INNER_RINGS: usize = 16;
const INNER_ANGLES: usize = 12;
const INNER_NODES: usize = INNER_RINGS * (INNER_ANGLES + 1);
/// Outer square grid `(i, j) * OUTER_SPACING`, `i, j < OUTER_SIDE`, used for
/// `INNER_RHO_MAX <= |p| < TABLE_RHO_MAX`.
const OUTER_SPACING: f64 = 1.2;
const OUTER_SIDE: usize = 35;
const OUTER_NODES: usize = OUTER_SIDE * OUTER_SIDE;
const TABLE_RHO_MAX: f64 = 40.0;
/// Taylor terms: they decay like `(|h|/|p0|)^n` and `|h|^n/n!`, below `1e-17` after 18 terms for
/// the steps of both grids (`|h| <= 0.9`, `|h|/|p0| <= 0.11`).
const TAYLOR_TERMS: usize = 18;

/// `Q` at the nodes of the inner and outer grids.
#[derive(Clone, Copy)]
pub(super) struct QTable {
    pub(super) inner: [Complex64; INNER_NODES],
    outer: [Complex64; OUTER_NODES],
}

impl QTable {
    pub(super) fn empty() -> Self {
        Self {
            inner: [Complex64::new(0.0, 0.0); INNER_NODES],
            outer: [Complex64::new(0.0, 0.0); OUTER_NODES],
        }
    }

    pub(super) fn new() -> Self {
        let mut table = Self::empty();
        for j in 0..INNER_RINGS {
            for i in 0..=INNER_ANGLES {
                let (p0, _) = inner_node(j, i);
                table.inner[j * (INNER_ANGLES + 1) + i] = scaled_ei(p0).q;
            }
        }
        for j in 0..OUTER_SIDE {
            for i in 0..OUTER_SIDE {
                let p0 = Complex64::new(i as f64 * OUTER_SPACING, j as f64 * OUTER_SPACING);
                // Only nodes nearest to some |p| in [INNER_RHO_MAX, TABLE_RHO_MAX) are used.
                let r = p0.norm_sqr().sqrt();
                if r > INNER_RHO_MAX - OUTER_SPACING && r < TABLE_RHO_MAX + OUTER_SPACING {
                    table.outer[j * OUTER_SIDE + i] = scaled_ei(p0).q;
                }
            }
        }
        table
    }

    /// `Q(p)` and `e^{-p}`.
    pub(super) fn q_and_exp(&self, p: Complex64) -> (Complex64, Complex64) {
        let lower = p.im.is_sign_negative();
        let pu = if lower { p.conj() } else { p };
        let (q, exp) = match self.taylor(pu) {
            Some(q) => (q, exp(-pu)),
            None => {
                let e = scaled_ei(pu);
                (e.q, e.exp)
            }
        };
        if lower {
            (q.conj(), exp.conj())
        } else {
            (q, exp)
        }
    }

    /// `Q(p)` for `Im p >= +0`, given `exp = e^{-p}` (as [`QTable::q_and_exp`]).
    pub(super) fn q_given_exp(&self, p: Complex64, exp: Complex64) -> Complex64 {
        self.taylor(p)
            .unwrap_or_else(|| scaled_ei_upper_given_exp(p, exp).q)
    }

    /// `Q(p)` by a Taylor step from the nearest node, `Im p >= +0`; `None` outside the table.
    fn taylor(&self, pu: Complex64) -> Option<Complex64> {
        let r2 = pu.norm_sqr();
        let node = if pu.re < 0.0 || r2 < INNER_RHO_MIN * INNER_RHO_MIN || r2.is_nan() {
            None // series is cheap inside, and p above the free surface is not tabulated
        } else if r2 < INNER_RHO_MAX * INNER_RHO_MAX {
            let rho = r2.sqrt();
            let j = ((0.5 * r2.ln() - INNER_LN_RHO_MIN) * (1.0 / INNER_LN_RATIO) + 0.5) as usize;
            let i = (pu.im / (rho + pu.re) * INNER_ANGLES as f64 + 0.5) as usize;
            let j = j.min(INNER_RINGS - 1);
            let (p0, w) = inner_node(j, i);
            Some((p0, w, self.inner[j * (INNER_ANGLES + 1) + i]))
        } else if r2 < TABLE_RHO_MAX * TABLE_RHO_MAX {
            let i = (pu.re / OUTER_SPACING + 0.5) as usize;
            let j = (pu.im / OUTER_SPACING + 0.5) as usize;
            let p0 = Complex64::new(i as f64 * OUTER_SPACING, j as f64 * OUTER_SPACING);
            Some((p0, p0.inv(), self.outer[j * OUTER_SIDE + i]))
        } else {
            None
        };
        node.map(|(p0, w, q0)| {
            // Q^(n+1) = -Q^(n) + (-1)^n n!/p0^{n+1}: with c_n = Q^(n) h^n/n!,
            // c_{n+1} = h/(n+1) (g^n/p0 - c_n), g = -h/p0; two steps per pass so that
            // the chain c_n -> c_{n+2} = alpha + beta c_n is one multiply-add.
            let h = pu - p0;
            let h2 = h * h;
            let g = -h * w;
            let mut gw = w; // g^n / p0
            let mut c = q0;
            let mut sum = q0;
            for n in (0..TAYLOR_TERMS).step_by(2) {
                let (r1, r2) = (RECIPROCALS[n + 1], RECIPROCALS[n + 2]);
                let gw1 = gw * g;
                let beta = h2 * (r1 * r2);
                let c1 = h * r1 * (gw - c);
                let c2 = h * r2 * gw1 - beta * gw + beta * c;
                sum += c1 + c2;
                // Both terms below 1e-17 (they decay geometrically here).
                if c1.l1_norm() + c2.l1_norm() <= 1e-17 * sum.l1_norm() {
                    break;
                }
                gw = gw1 * g;
                c = c2;
            }
            sum
        })
    }
}

/// Radii of the inner rings.
const INNER_RADII: [f64; INNER_RINGS] = {
    let mut r = [INNER_RHO_MIN; INNER_RINGS];
    let mut j = 1;
    while j < INNER_RINGS {
        r[j] = r[j - 1] * INNER_RING_RATIO;
        j += 1;
    }
    r
};

/// Inner node `(j, i)`: `p0` and `1/p0`, from `tan(theta/2) = t` without trigonometry.
fn inner_node(j: usize, i: usize) -> (Complex64, Complex64) {
    let rho = INNER_RADII[j];
    let t = i as f64 * (1.0 / INNER_ANGLES as f64);
    let d = 1.0 / (1.0 + t * t);
    let unit = Complex64::new((1.0 - t * t) * d, 2.0 * t * d);
    (rho * unit, unit.conj() * (1.0 / rho))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn table_taylor_matches_direct_evaluation() {
        // Dense sweep over the tabulated annulus (cell edges included) and its borders.
        let table = QTable::new();
        let mut worst: f64 = 0.0;
        for ir in 0..=400 {
            let rho = 0.45 * (41.0f64 / 0.45).powf(ir as f64 / 400.0);
            for it in 0..=90 {
                let theta = (it as f64 / 90.0 - 0.5) * PI; // fourth and first quadrant
                let p = Complex64::from_polar(rho, theta);
                let (q, exp) = table.q_and_exp(p);
                let e = scaled_ei(p);
                // Relative to |F| + |Q|: Q = i pi e^{-p} - F has zeros (those of Ei).
                let err = (q - e.q).norm() / (e.q.norm() + e.f.norm());
                worst = worst.max(err);
                assert!(err < 5e-15, "p = {p}: {q} vs {} ({err:e})", e.q);
                assert!((exp - e.exp).norm() <= 1e-15 * e.exp.norm());
            }
        }
        assert!(worst > 0.0);
    }
}
