//! Shared dynamics of the coupled form: groups of unit chains (first mass 1), their shapes
//! `g_p(s)` and derivatives with respect to the log parameters, and start values.

use nalgebra::DMatrix;
use num_complex::Complex64;

use crate::identify::chain::chain_response;
use crate::network::Stage;

/// Shared dynamics of the coupled form: `count` groups, each a chain of `stages` stages whose
/// first mass is 1 (normalized; the PSD weight carries the scale). Log parameters per group:
/// `[ln k_1, ln c_1]`, then `[ln m_j, ln k_j, ln c_j]` for every further stage.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct GroupSet {
    pub(super) stages: usize,
    pub(super) theta: Vec<f64>,
}

impl GroupSet {
    pub(super) fn params_per_group(&self) -> usize {
        3 * self.stages - 1
    }

    pub(super) fn count(&self) -> usize {
        self.theta.len() / self.params_per_group()
    }

    /// `[m, k, c]` values of group `p`'s chain.
    pub(super) fn values(&self, p: usize) -> Vec<f64> {
        let sp = self.params_per_group();
        let mut v = Vec::with_capacity(3 * self.stages);
        v.push(1.0);
        v.extend(self.theta[p * sp..(p + 1) * sp].iter().map(|t| t.exp()));
        v
    }

    pub(super) fn normalized_stages(&self, p: usize) -> Vec<Stage> {
        self.values(p)
            .chunks(3)
            .map(|c| Stage {
                mass: c[0],
                stiffness: c[1],
                damping: c[2],
            })
            .collect()
    }

    /// Dynamic mass of group `p`'s unit chain.
    pub(super) fn shape(&self, p: usize, s: Complex64) -> Complex64 {
        chain_response(&self.values(p), s, None)
    }

    /// Shapes (2N x P, rows `[Re; Im]` per frequency) and, if asked, their derivatives with
    /// respect to every parameter (2N x P sp).
    pub(super) fn basis(&self, nu: &[f64], derivatives: bool) -> (DMatrix<f64>, DMatrix<f64>) {
        let count = self.count();
        let sp = self.params_per_group();
        let mut g = DMatrix::zeros(2 * nu.len(), count);
        let mut d = DMatrix::zeros(if derivatives { 2 * nu.len() } else { 0 }, count * sp);
        let mut grad = vec![Complex64::new(0.0, 0.0); 3 * self.stages];
        for p in 0..count {
            let values = self.values(p);
            for (i, &v) in nu.iter().enumerate() {
                let s = Complex64::new(0.0, v);
                let value = if derivatives {
                    let value = chain_response(&values, s, Some(&mut grad));
                    for a in 0..sp {
                        d[(2 * i, p * sp + a)] = grad[a + 1].re;
                        d[(2 * i + 1, p * sp + a)] = grad[a + 1].im;
                    }
                    value
                } else {
                    chain_response(&values, s, None)
                };
                g[(2 * i, p)] = value.re;
                g[(2 * i + 1, p)] = value.im;
            }
        }
        (g, d)
    }

    /// Parameters of a fresh group at natural frequency `nu_n` and damping ratio `zeta`.
    pub(super) fn fresh_group(&self, nu_n: f64, zeta: f64) -> Vec<f64> {
        let mut theta = vec![(nu_n * nu_n).ln(), (2.0 * zeta * nu_n).ln()];
        let mut last = nu_n;
        for _ in 1..self.stages {
            let (m, w): (f64, f64) = (0.2, 2.0 * last);
            theta.extend([m.ln(), (m * w * w).ln(), (m * w).ln()]);
            last = w;
        }
        theta
    }

    pub(super) fn with_group(&self, nu_n: f64, zeta: f64) -> GroupSet {
        let mut theta = self.theta.clone();
        theta.extend(self.fresh_group(nu_n, zeta));
        GroupSet {
            stages: self.stages,
            theta,
        }
    }

    /// The same groups with one more (light) stage at the end of every chain.
    pub(super) fn with_extra_stage(&self) -> GroupSet {
        let sp = self.params_per_group();
        let mut theta = Vec::with_capacity(self.count() * (sp + 3));
        for p in 0..self.count() {
            theta.extend_from_slice(&self.theta[p * sp..(p + 1) * sp]);
            let values = self.values(p);
            let last = values.len() - 3;
            let w = 2.0 * (values[last + 1] / values[last]).sqrt();
            let m = 0.2 * values[last];
            theta.extend([m.ln(), (m * w * w).ln(), (m * w).ln()]);
        }
        GroupSet {
            stages: self.stages + 1,
            theta,
        }
    }
}
