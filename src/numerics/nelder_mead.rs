//! Derivative-free minimization of `f(x)`, `x` in R^n, by the Nelder-Mead simplex (standard
//! coefficients: reflection 1, expansion 2, contraction 1/2, shrink 1/2; Lagarias et al.
//! 1998). Deterministic. For small `n` and objectives that are cheap to evaluate but not
//! smooth (a largest error over a grid, a constrained solve inside). A non-finite value
//! counts as worse than every finite one.

/// The result of [`nelder_mead`]: the best point seen, its value and the evaluations used.
#[derive(Clone, Debug, PartialEq)]
pub struct Minimum {
    pub(crate) x: Vec<f64>,
    pub(crate) value: f64,
    pub(crate) evaluations: usize,
}

/// Minimizes `f` from `start` with a first simplex of `start` and `start + step e_i`, until
/// the simplex's values differ by at most `tolerance` (absolute) or `max_evaluations` are
/// spent.
pub fn nelder_mead(
    f: &mut dyn FnMut(&[f64]) -> f64,
    start: &[f64],
    step: f64,
    tolerance: f64,
    max_evaluations: usize,
) -> Minimum {
    let n = start.len();
    let mut evaluations = 0;
    let mut eval = |x: &[f64], evaluations: &mut usize| {
        *evaluations += 1;
        let v = f(x);
        if v.is_nan() {
            f64::INFINITY
        } else {
            v
        }
    };
    let mut simplex: Vec<(Vec<f64>, f64)> = Vec::with_capacity(n + 1);
    let v = eval(start, &mut evaluations);
    simplex.push((start.to_vec(), v));
    for i in 0..n {
        let mut x = start.to_vec();
        x[i] += step;
        let v = eval(&x, &mut evaluations);
        simplex.push((x, v));
    }
    let along = |from: &[f64], to: &[f64], t: f64| -> Vec<f64> {
        from.iter().zip(to).map(|(a, b)| a + t * (b - a)).collect()
    };
    while n > 0 && evaluations < max_evaluations {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (best, worst) = (simplex[0].1, simplex[n].1);
        if worst.is_finite() && worst - best <= tolerance {
            break;
        }
        let mut centroid = vec![0.0; n];
        for (x, _) in &simplex[..n] {
            for (c, v) in centroid.iter_mut().zip(x) {
                *c += v / n as f64;
            }
        }
        let reflected = along(&centroid, &simplex[n].0, -1.0);
        let fr = eval(&reflected, &mut evaluations);
        if fr < best {
            let expanded = along(&centroid, &simplex[n].0, -2.0);
            let fe = eval(&expanded, &mut evaluations);
            simplex[n] = if fe < fr {
                (expanded, fe)
            } else {
                (reflected, fr)
            };
        } else if fr < simplex[n - 1].1 {
            simplex[n] = (reflected, fr);
        } else {
            let (towards, ft) = if fr < worst {
                (reflected, fr)
            } else {
                (simplex[n].0.clone(), worst)
            };
            let contracted = along(&centroid, &towards, 0.5);
            let fc = eval(&contracted, &mut evaluations);
            if fc < ft {
                simplex[n] = (contracted, fc);
            } else {
                let best_x = simplex[0].0.clone();
                for vertex in simplex.iter_mut().skip(1) {
                    let x = along(&best_x, &vertex.0, 0.5);
                    let v = eval(&x, &mut evaluations);
                    *vertex = (x, v);
                }
            }
        }
    }
    let (x, value) = simplex
        .into_iter()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((start.to_vec(), f64::INFINITY));
    Minimum {
        x,
        value,
        evaluations,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_rosenbrock_minimum() {
        let mut f = |x: &[f64]| (1.0 - x[0]).powi(2) + 100.0 * (x[1] - x[0] * x[0]).powi(2);
        let m = nelder_mead(&mut f, &[-1.2, 1.0], 0.5, 1e-14, 2000);
        assert!(
            (m.x[0] - 1.0).abs() < 1e-4 && (m.x[1] - 1.0).abs() < 1e-4,
            "{m:?}"
        );
        assert!(m.evaluations <= 2000);
    }

    #[test]
    fn a_nonsmooth_maximum_and_an_infeasible_region() {
        // max |x_i - 0.3|, infinite where x_0 < 0: the minimum 0 at (0.3, 0.3).
        let mut f = |x: &[f64]| {
            if x[0] < 0.0 {
                f64::NAN
            } else {
                x.iter().map(|v| (v - 0.3).abs()).fold(0.0, f64::max)
            }
        };
        let m = nelder_mead(&mut f, &[1.0, -1.0], 0.25, 1e-10, 1000);
        assert!(m.value < 1e-5, "{m:?}");
    }

    #[test]
    fn stops_at_the_evaluation_budget() {
        let mut count = 0;
        let mut f = |x: &[f64]| {
            count += 1;
            x[0] * x[0] + x[1] * x[1] + x[2] * x[2]
        };
        let m = nelder_mead(&mut f, &[1.0, 2.0, 3.0], 1.0, 0.0, 25);
        assert!(m.evaluations <= 25 + 3, "{}", m.evaluations);
        assert_eq!(count, m.evaluations);
        assert!(m.value < 14.0);
    }
}
