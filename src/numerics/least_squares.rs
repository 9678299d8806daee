//! Nonlinear least squares `min_x |r(x)|^2` by Levenberg-Marquardt with Marquardt's diagonal
//! scaling. Each iteration solves
//!
//! ```text
//! (J^T J + lambda D) dx = -J^T r,   D = diag(max(J^T J_ii, 1e-9 max_i J^T J_ii)),
//! ```
//!
//! by Cholesky, accepts `x + dx` (clamped to `[-bound, bound]` per parameter) if the cost
//! falls (then `lambda /= 3`, at least 1e-12), else raises `lambda` (x4; x10 if the matrix is
//! not positive definite) until 1e12. Starts at `lambda = 1e-3`. Deterministic.

use nalgebra::{DMatrix, DVector};

/// A nonlinear least-squares problem `min |r(x)|^2`.
pub trait LeastSquares {
    /// Number of residuals.
    fn residual_count(&self) -> usize;
    /// Residuals at `x`, and the Jacobian `dr/dx` (residuals x parameters) if asked.
    fn evaluate(&self, x: &DVector<f64>, r: &mut DVector<f64>, jacobian: Option<&mut DMatrix<f64>>);
}

/// Why [`levenberg_marquardt`] stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Termination {
    /// The cost at the start is not finite; `x` is the (clamped) start.
    NonFiniteStart,
    /// The iteration limit was reached.
    MaxIterations,
    /// The Jacobian is zero: no direction lowers the cost.
    ZeroJacobian,
    /// The gradient `J^T r` is at most 1e-15 of the cost: a stationary point.
    Stationary,
    /// No damping up to `lambda = 1e12` gave a step that lowers the cost.
    NoDescent,
    /// Three accepted steps in a row each lowered the cost by less than 1e-9 (relative).
    Stalled,
    /// The last step changed no parameter by more than 1e-10.
    SmallStep,
    /// The cost fell below 1e-30: the residuals vanish.
    ZeroResidual,
}

/// Result of [`levenberg_marquardt`].
#[derive(Clone, Debug, PartialEq)]
pub struct LmResult {
    /// Parameters at the end.
    pub(crate) x: DVector<f64>,
    /// `|r(x)|^2` (infinite if the start is not finite).
    pub(crate) cost: f64,
    /// Iterations (Jacobian evaluations after the first).
    pub(crate) iterations: usize,
    /// Why the iteration stopped.
    pub(crate) termination: Termination,
}

/// Levenberg-Marquardt from `x0` (see the module docs), at most `max_iterations` iterations,
/// every parameter kept within `[-bound, bound]`.
pub fn levenberg_marquardt(
    problem: &dyn LeastSquares,
    x0: DVector<f64>,
    max_iterations: usize,
    bound: f64,
) -> LmResult {
    let np = x0.len();
    let nr = problem.residual_count();
    let clamp = |x: DVector<f64>| x.map(|v| v.clamp(-bound, bound));
    let mut x = clamp(x0);
    let mut r = DVector::zeros(nr);
    let mut jac = DMatrix::zeros(nr, np);
    problem.evaluate(&x, &mut r, Some(&mut jac));
    let mut cost = r.norm_squared();
    if !cost.is_finite() {
        return LmResult {
            x,
            cost: f64::INFINITY,
            iterations: 0,
            termination: Termination::NonFiniteStart,
        };
    }
    let mut lambda = 1e-3;
    let mut trial = DVector::zeros(nr);
    let mut iterations = 0;
    let mut slow = 0;
    let mut termination = Termination::MaxIterations;
    while iterations < max_iterations {
        iterations += 1;
        let jtj = jac.tr_mul(&jac);
        let grad = jac.tr_mul(&r);
        let diag_max = (0..np).map(|i| jtj[(i, i)]).fold(0.0, f64::max);
        if diag_max == 0.0 {
            termination = Termination::ZeroJacobian;
            break;
        }
        if grad.amax() <= 1e-15 * cost.max(1e-300) {
            termination = Termination::Stationary;
            break;
        }
        let mut accepted = None;
        while lambda < 1e12 {
            let mut a = jtj.clone();
            for i in 0..np {
                a[(i, i)] += lambda * jtj[(i, i)].max(1e-9 * diag_max);
            }
            let step = match a.cholesky() {
                Some(ch) => -ch.solve(&grad),
                None => {
                    lambda *= 10.0;
                    continue;
                }
            };
            let candidate = clamp(&x + &step);
            problem.evaluate(&candidate, &mut trial, None);
            let new_cost = trial.norm_squared();
            if new_cost.is_finite() && new_cost < cost {
                accepted = Some((candidate, new_cost, step.amax()));
                lambda = (lambda / 3.0).max(1e-12);
                break;
            }
            lambda *= 4.0;
        }
        let Some((candidate, new_cost, step_size)) = accepted else {
            termination = Termination::NoDescent;
            break;
        };
        let improvement = (cost - new_cost) / cost;
        x = candidate;
        cost = new_cost;
        problem.evaluate(&x, &mut r, Some(&mut jac));
        if improvement < 1e-9 {
            slow += 1;
        } else {
            slow = 0;
        }
        if slow >= 3 {
            termination = Termination::Stalled;
            break;
        }
        if step_size < 1e-10 {
            termination = Termination::SmallStep;
            break;
        }
        if cost < 1e-30 {
            termination = Termination::ZeroResidual;
            break;
        }
    }
    LmResult {
        x,
        cost,
        iterations,
        termination,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rosenbrock's function as least squares: `r = [10 (x2 - x1^2), 1 - x1]`, minimum 0 at
    /// (1, 1).
    struct Rosenbrock;

    impl LeastSquares for Rosenbrock {
        fn residual_count(&self) -> usize {
            2
        }

        fn evaluate(
            &self,
            x: &DVector<f64>,
            r: &mut DVector<f64>,
            jacobian: Option<&mut DMatrix<f64>>,
        ) {
            r[0] = 10.0 * (x[1] - x[0] * x[0]);
            r[1] = 1.0 - x[0];
            if let Some(j) = jacobian {
                j[(0, 0)] = -20.0 * x[0];
                j[(0, 1)] = 10.0;
                j[(1, 0)] = -1.0;
                j[(1, 1)] = 0.0;
            }
        }
    }

    /// `y = exp(a t) + b` at a few points, with data that the model cannot meet exactly.
    struct Exponential {
        t: Vec<f64>,
        y: Vec<f64>,
    }

    impl LeastSquares for Exponential {
        fn residual_count(&self) -> usize {
            self.t.len()
        }

        fn evaluate(
            &self,
            x: &DVector<f64>,
            r: &mut DVector<f64>,
            mut jacobian: Option<&mut DMatrix<f64>>,
        ) {
            for (i, (&t, &y)) in self.t.iter().zip(&self.y).enumerate() {
                let e = (x[0] * t).exp();
                r[i] = e + x[1] - y;
                if let Some(j) = jacobian.as_deref_mut() {
                    j[(i, 0)] = t * e;
                    j[(i, 1)] = 1.0;
                }
            }
        }
    }

    #[test]
    fn rosenbrock_reaches_its_minimum() {
        let start = DVector::from_vec(vec![-1.2, 1.0]);
        let result = levenberg_marquardt(&Rosenbrock, start, 200, 1e3);
        assert!((result.x[0] - 1.0).abs() < 1e-8, "{}", result.x);
        assert!((result.x[1] - 1.0).abs() < 1e-8, "{}", result.x);
        assert!(result.cost < 1e-20);
        assert_ne!(result.termination, Termination::MaxIterations);
        assert!(result.iterations < 200);
    }

    #[test]
    fn a_residual_minimum_ends_stationary_or_stalled() {
        let problem = Exponential {
            t: vec![0.0, 0.5, 1.0, 1.5, 2.0],
            y: vec![1.1, 1.5, 2.9, 4.2, 8.0],
        };
        let result = levenberg_marquardt(&problem, DVector::from_vec(vec![0.5, 0.0]), 500, 10.0);
        assert!(result.cost > 1e-3, "the data is not exactly an exponential");
        assert!(
            matches!(
                result.termination,
                Termination::Stationary
                    | Termination::Stalled
                    | Termination::SmallStep
                    | Termination::NoDescent
            ),
            "{:?}",
            result.termination
        );
        // The gradient vanishes at the minimum.
        let mut r = DVector::zeros(5);
        let mut j = DMatrix::zeros(5, 2);
        problem.evaluate(&result.x, &mut r, Some(&mut j));
        assert!(j.tr_mul(&r).amax() < 1e-6 * result.cost.max(1.0));
    }

    #[test]
    fn limits_and_bad_starts_are_reported() {
        let start = DVector::from_vec(vec![-1.2, 1.0]);
        let none = levenberg_marquardt(&Rosenbrock, start.clone(), 0, 1e3);
        assert_eq!(none.termination, Termination::MaxIterations);
        assert_eq!((none.iterations, none.x.clone()), (0, start.clone()));
        let one = levenberg_marquardt(&Rosenbrock, start, 1, 1e3);
        assert_eq!(one.termination, Termination::MaxIterations);
        assert_eq!(one.iterations, 1);

        let nan = levenberg_marquardt(&Rosenbrock, DVector::from_vec(vec![f64::NAN, 0.0]), 9, 1.0);
        assert_eq!(nan.termination, Termination::NonFiniteStart);
        assert_eq!(nan.cost, f64::INFINITY);

        // The start is clamped to the bound, and so is every step.
        let bounded = levenberg_marquardt(&Rosenbrock, DVector::from_vec(vec![5.0, 5.0]), 50, 0.5);
        assert!(bounded.x.amax() <= 0.5);
    }
}
