//! The radiation force by direct convolution (Cummins), the classic alternative to the
//! equivalent network. Used as the baseline in the convolution benchmark
//! (`benches/convolution.rs`) and the performance report (`examples/performance/network.rs`),
//! which include this file by `#[path]`, and as an independent check of the network's
//! stepping (`tests/convolution.rs` runs the tests below); the FMU never uses it.
//!
//! With the network's state space (`z' = A z + B v`, `F = C z + D v`, see [`hydrofmu::realize`])
//! the force excluding `-A_inf q''` is
//!
//! ```text
//! F(t) = D v(t) + integral_0^t K(t - tau) v(tau) dtau,     K(t) = C exp(A t) B  (n x n)
//! ```
//!
//! `K` is the retardation function of the network (for an exact network of the panel data
//! it is the hull's own `K(t) = (2/pi) integral_0^inf b(omega) cos(omega t) domega`). On a
//! uniform step h the integral is taken by the trapezoidal rule over the last `history`
//! steps:
//!
//! ```text
//! F_k = D v_k + h sum_{j=0}^{L} w_j K(j h) v_(k-j),   w_0 = w_L = 1/2, else 1,  L = min(k, history)
//! ```
//!
//! Each step costs `(L + 1) n^2` multiply-adds and keeps `L + 1` past velocities; the
//! truncation error is the tail of `K` beyond `history h`, the quadrature error O(h^2).

use hydrofmu::discretize::{expm, DiscretizeError};
use hydrofmu::realize::StateSpace;
use nalgebra::{DMatrix, DVector};

/// The sampled retardation function and the velocity history of one convolution.
#[derive(Clone, Debug)]
pub struct ConvolutionForce {
    dofs: usize,
    step: f64,
    direct: DMatrix<f64>,
    /// `K(j h)` for j = 0..=history, each n x n column-major, concatenated.
    kernel: Vec<f64>,
    /// Past velocities, newest at `newest`, ring buffer of `history + 1` n-vectors.
    velocities: Vec<f64>,
    newest: usize,
    filled: usize,
}

impl ConvolutionForce {
    /// Samples `K(t) = C exp(A t) B` at `t = j h`, `j = 0..=history`.
    pub fn new(ss: &StateSpace, step: f64, history: usize) -> Result<Self, DiscretizeError> {
        if !(step.is_finite() && step > 0.0) {
            return Err(DiscretizeError::BadStepSize(step));
        }
        let n = ss.input_count();
        let phi = expm(&(&ss.a * step))?;
        let mut propagated = ss.b.clone();
        let mut kernel = Vec::with_capacity((history + 1) * n * n);
        for _ in 0..=history {
            let k = &ss.c * &propagated;
            kernel.extend_from_slice(k.as_slice());
            propagated = &phi * propagated;
        }
        Ok(ConvolutionForce {
            dofs: n,
            step,
            direct: ss.d.clone(),
            kernel,
            velocities: vec![0.0; (history + 1) * n],
            newest: 0,
            filled: 0,
        })
    }

    /// Number of past steps kept.
    pub fn history(&self) -> usize {
        self.velocities.len() / self.dofs.max(1) - 1
    }

    /// Records the velocity `v_k` of the next time point and writes `F_k` into `force`.
    /// Both must have one entry per DOF; otherwise nothing changes and an error is returned.
    pub fn push(
        &mut self,
        velocity: &DVector<f64>,
        force: &mut DVector<f64>,
    ) -> Result<(), DiscretizeError> {
        let n = self.dofs;
        if velocity.len() != n || force.len() != n {
            return Err(DiscretizeError::Dimensions(format!(
                "velocity has {} and force {} entries for {n} DOFs",
                velocity.len(),
                force.len()
            )));
        }
        let slots = self.history() + 1;
        self.newest = (self.newest + 1) % slots;
        self.velocities[self.newest * n..(self.newest + 1) * n]
            .copy_from_slice(velocity.as_slice());
        self.filled = (self.filled + 1).min(slots);
        force.gemv(1.0, &self.direct, velocity, 0.0);
        let last = self.filled - 1;
        for j in 0..=last {
            let weight = if j == 0 || j == last { 0.5 } else { 1.0 } * self.step;
            let slot = (self.newest + slots - j) % slots;
            let v = &self.velocities[slot * n..(slot + 1) * n];
            let k = &self.kernel[j * n * n..(j + 1) * n * n];
            for (col, vc) in v.iter().enumerate() {
                let scaled = weight * vc;
                for (f, kij) in force.iter_mut().zip(&k[col * n..(col + 1) * n]) {
                    *f += kij * scaled;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hydrofmu::discretize::discretize;
    use hydrofmu::network::{Branch, Network, NetworkForm, Stage};

    fn seed_state_space() -> StateSpace {
        let stage = |mass, stiffness, damping| Stage {
            mass,
            stiffness,
            damping,
        };
        Network {
            dof_names: vec!["sway".into()],
            added_mass_inf: DMatrix::from_element(1, 1, 0.1153),
            branches: vec![Branch {
                direction: DVector::from_element(1, 1.0),
                stages: vec![stage(0.5434, 0.2339, 0.9962), stage(0.1877, 0.5522, 0.2453)],
            }],
            substructures: Vec::new(),
            rho: 1.0,
            g: 1.0,
            form: NetworkForm::SeriesChain,
        }
        .state_space()
        .unwrap()
    }

    /// Network force for v(t) = sin(t), exact for the piecewise-linear input (first-order
    /// hold), sampled every `h`.
    fn network_force(ss: &StateSpace, h: f64, steps: usize) -> Vec<f64> {
        let d = discretize(&ss.a, &ss.b, h, true).unwrap();
        let mut z = DVector::zeros(ss.state_count());
        let mut out = Vec::with_capacity(steps + 1);
        for k in 0..=steps {
            let t = k as f64 * h;
            let v = DVector::from_element(1, t.sin());
            out.push(ss.force(&z, &v)[0]);
            let slope = DVector::from_element(1, ((t + h).sin() - t.sin()) / h);
            z = &d.phi * &z + &d.gamma0 * &v + d.gamma1.as_ref().unwrap() * slope;
        }
        out
    }

    fn convolution_force(ss: &StateSpace, h: f64, steps: usize) -> Vec<f64> {
        let mut conv = ConvolutionForce::new(ss, h, steps).unwrap();
        let mut f = DVector::zeros(1);
        (0..=steps)
            .map(|k| {
                conv.push(&DVector::from_element(1, (k as f64 * h).sin()), &mut f)
                    .unwrap();
                f[0]
            })
            .collect()
    }

    #[test]
    fn convolution_converges_to_the_network_at_second_order() {
        // Same input, two independent evaluations of one linear system: the difference is
        // the trapezoid's O(h^2) error (both use the piecewise-linear input).
        let ss = seed_state_space();
        let horizon = 20.0;
        let errors: Vec<f64> = [0.1, 0.05, 0.025]
            .iter()
            .map(|&h| {
                let steps = (horizon / h) as usize;
                let a = network_force(&ss, h, steps);
                let b = convolution_force(&ss, h, steps);
                a.iter()
                    .zip(&b)
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f64::max)
            })
            .collect();
        // Force amplitude is O(1) (unit velocity, O(1) network): 1e-3 at h = 0.025 s.
        assert!(errors[2] < 1e-3, "{errors:?}");
        for pair in errors.windows(2) {
            let order = (pair[0] / pair[1]).log2();
            assert!((1.8..2.3).contains(&order), "{errors:?}");
        }
    }

    #[test]
    fn kernel_at_zero_is_c_b_and_history_is_kept() {
        let ss = seed_state_space();
        let conv = ConvolutionForce::new(&ss, 0.01, 100).unwrap();
        assert_eq!(conv.history(), 100);
        let cb = &ss.c * &ss.b;
        assert!((conv.kernel[0] - cb[(0, 0)]).abs() < 1e-15);
        assert!(ConvolutionForce::new(&ss, 0.0, 10).is_err());
        // A velocity of the wrong size is refused and leaves the history as it was.
        let mut conv = conv;
        let mut f = DVector::zeros(1);
        assert!(conv.push(&DVector::zeros(2), &mut f).is_err());
        assert_eq!(conv.filled, 0);
    }
}
