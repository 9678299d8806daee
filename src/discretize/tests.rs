//! Tests of the exact discretization: the exponential, ZOH and FOH steps, the block cache.

use super::*;
use nalgebra::DVector;

/// Schilder et al.'s 2-DOF network (hull held): z = [e1, e2, w1, w2].
fn seed_system() -> (DMatrix<f64>, DMatrix<f64>) {
    let (m1, k1, c1, m2, k2, c2) = (0.5434, 0.2339, 0.9962, 0.1877, 0.5522, 0.2453);
    let a = DMatrix::from_row_slice(
        4,
        4,
        &[
            0.0,
            0.0,
            -1.0,
            0.0,
            0.0,
            0.0,
            1.0,
            -1.0,
            k1 / m1,
            -k2 / m1,
            -(c1 + c2) / m1,
            c2 / m1,
            0.0,
            k2 / m2,
            c2 / m2,
            -c2 / m2,
        ],
    );
    let b = DMatrix::from_column_slice(4, 1, &[1.0, 0.0, c1 / m1, 0.0]);
    (a, b)
}

fn max_abs(m: &DMatrix<f64>) -> f64 {
    m.iter().fold(0.0, |acc, x| acc.max(x.abs()))
}

/// exp by an explicit Taylor series (only for small norms).
fn taylor(a: &DMatrix<f64>) -> DMatrix<f64> {
    let n = a.nrows();
    let mut term = DMatrix::<f64>::identity(n, n);
    let mut sum = term.clone();
    for k in 1..40 {
        term = &term * a / k as f64;
        sum += &term;
    }
    sum
}

#[test]
fn exponential_matches_taylor_series_for_small_steps() {
    let (a, _) = seed_system();
    for h in [1e-6, 1e-3, 0.05, 0.3, 1.0] {
        let e = expm(&(&a * h)).unwrap();
        let t = taylor(&(&a * h));
        // Taylor with 40 terms is exact to rounding for |A h| <= ~5.
        assert!(max_abs(&(e - &t)) < 1e-14 * max_abs(&t).max(1.0), "h = {h}");
    }
}

#[test]
fn exponential_matches_eigen_decomposition_for_long_steps() {
    // Symmetric negative definite A: exp(A h) = V exp(L h) V^T independently.
    let s = DMatrix::from_row_slice(3, 3, &[-2.0, 0.5, 0.1, 0.5, -1.0, 0.3, 0.1, 0.3, -0.7]);
    let eig = crate::numerics::symmetric_eigen(&s);
    for h in [1e-6, 1.0, 10.0, 100.0] {
        let e = expm(&(&s * h)).unwrap();
        let diag = DVector::from_iterator(3, eig.eigenvalues.iter().map(|l| (l * h).exp()));
        let reference =
            &eig.eigenvectors * DMatrix::from_diagonal(&diag) * eig.eigenvectors.transpose();
        // Relative to the largest entry; squaring loses ~log2(|A h|) bits at most.
        let scale = max_abs(&reference).max(1e-300);
        assert!(
            max_abs(&(e - &reference)) <= 1e-12 * scale,
            "h = {h}: {}",
            max_abs(&(expm(&(&s * h)).unwrap() - &reference)) / scale
        );
    }
}

#[test]
fn exponential_agrees_with_nalgebra_and_semigroup_property() {
    let (a, _) = seed_system();
    for h in [0.01, 3.0, 100.0] {
        let e = expm(&(&a * h)).unwrap();
        let other = (&a * h).exp();
        assert!(max_abs(&(&e - &other)) < 1e-10, "h = {h}");
        let half = expm(&(&a * (h / 2.0))).unwrap();
        assert!(max_abs(&(&half * &half - &e)) < 1e-12, "h = {h}");
    }
}

#[test]
fn input_blocks_match_closed_forms() {
    // A invertible: Gamma0 = A^-1 (Phi - I) B, Gamma1 = A^-2 (Phi - I - A h) B.
    let (a, b) = seed_system();
    let inv = a.clone().try_inverse().unwrap();
    let id = DMatrix::<f64>::identity(4, 4);
    for h in [0.01, 0.5, 7.0, 100.0] {
        let d = discretize(&a, &b, h, true).unwrap();
        let g0 = &inv * (&d.phi - &id) * &b;
        let g1 = &inv * &inv * (&d.phi - &id - &a * h) * &b;
        assert!(
            max_abs(&(&d.gamma0 - &g0)) < 1e-11 * max_abs(&g0).max(1.0),
            "h = {h}"
        );
        let g1_err = max_abs(&(d.gamma1.as_ref().unwrap() - &g1));
        assert!(g1_err < 1e-10 * max_abs(&g1).max(1.0), "h = {h}: {g1_err}");
    }
}

#[test]
fn input_blocks_match_series_for_tiny_steps() {
    // Gamma0 = sum A^k h^(k+1)/(k+1)! B, Gamma1 = sum A^k h^(k+2)/(k+2)! B.
    let (a, b) = seed_system();
    for h in [1e-6, 1e-4] {
        let d = discretize(&a, &b, h, true).unwrap();
        let mut g0 = DMatrix::<f64>::zeros(4, 1);
        let mut g1 = DMatrix::<f64>::zeros(4, 1);
        let mut power = b.clone();
        let mut fact0 = 1.0;
        let mut fact1 = 2.0;
        for k in 0..12 {
            fact0 *= (k + 1) as f64;
            if k > 0 {
                fact1 *= (k + 2) as f64;
            }
            g0 += &power * (h.powi(k + 1) / fact0);
            g1 += &power * (h.powi(k + 2) / fact1);
            power = &a * power;
        }
        // Relative accuracy near rounding even though the blocks are ~h and ~h^2.
        assert!(
            max_abs(&(&d.gamma0 - &g0)) < 1e-14 * max_abs(&g0),
            "h = {h}"
        );
        let g1_err = max_abs(&(d.gamma1.as_ref().unwrap() - &g1));
        assert!(g1_err < 1e-13 * max_abs(&g1), "h = {h}: {g1_err}");
    }
}

#[test]
fn step_responses_are_consistent_under_splitting() {
    // Two half steps with a ramp equal one full step (exactness of FOH).
    let (a, b) = seed_system();
    let z0 = DVector::from_vec(vec![0.1, -0.2, 0.3, 0.05]);
    let (u, du) = (0.7, -1.3);
    let h = 0.4;
    let full = discretize(&a, &b, h, true).unwrap();
    let half = discretize(&a, &b, h / 2.0, true).unwrap();
    let step = |d: &Discretization, z: &DVector<f64>, u: f64, du: f64| {
        &d.phi * z + d.gamma0.column(0) * u + d.gamma1.as_ref().unwrap().column(0) * du
    };
    let one = step(&full, &z0, u, du);
    let mid = step(&half, &z0, u, du);
    let two = step(&half, &mid, u + du * h / 2.0, du);
    assert!((one - two).amax() < 1e-14);
}

#[test]
fn linear_map_equals_the_dense_product_and_skips_exact_zeros() {
    let (a, _) = seed_system();
    let map = LinearMap::new(&a);
    assert_eq!(map.non_zeros(), a.iter().filter(|x| **x != 0.0).count());
    let x: Vec<f64> = (0..4).map(|k| (k as f64 * 0.7).sin()).collect();
    let mut y = vec![0.0; 4];
    map.apply(&x, &mut y);
    let dense = &a * DVector::from_column_slice(&x);
    for i in 0..4 {
        assert!((y[i] - dense[i]).abs() < 1e-15, "{i}");
    }
}

#[test]
fn bad_steps_are_rejected() {
    let (a, b) = seed_system();
    for h in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            discretize(&a, &b, h, false),
            Err(DiscretizeError::BadStepSize(_))
        ));
    }
    let wrong = DMatrix::<f64>::zeros(3, 1);
    assert!(matches!(
        discretize(&a, &wrong, 0.1, false),
        Err(DiscretizeError::Dimensions(_))
    ));
    let unstable = DMatrix::from_element(1, 1, 1.0);
    assert_eq!(expm(&(unstable * 1e6)), Err(DiscretizeError::NotFinite));
}

#[test]
fn cache_keeps_recent_steps() {
    let (a, b) = seed_system();
    let mut cache = BlockDiscretizationCache::new(
        &a,
        &b,
        &[vec![0, 1, 2, 3]],
        std::slice::from_ref(&(0..1)),
        &[1.0; 4],
    )
    .unwrap();
    let first = cache.get(0.01).unwrap().clone();
    let full = discretize(&a, &b, 0.01, true).unwrap();
    assert_eq!(first.phi, full.phi.transpose().as_slice());
    assert_eq!(cache.entries.len(), 1);
    for k in 1..=10 {
        cache.get(0.01 * k as f64).unwrap();
    }
    assert_eq!(
        cache.entries.len(),
        BlockDiscretizationCache::DEFAULT_CAPACITY
    );
    assert!(cache.get(-1.0).is_err());
}

#[test]
fn blocks_reproduce_the_whole_system_and_coupling_is_refused() {
    // Two copies of Schilder et al.'s chain, interleaved, each driven by its own input: the block
    // step must equal the full system's step (same exact discretization, to rounding).
    let (a1, b1) = seed_system();
    let order = [0usize, 5, 2, 7, 1, 3, 6, 4];
    let (block0, block1): (Vec<usize>, Vec<usize>) = (order[..4].to_vec(), order[4..].to_vec());
    let mut a = DMatrix::zeros(8, 8);
    let mut b = DMatrix::zeros(8, 2);
    for (j, states) in [&block0, &block1].iter().enumerate() {
        let scale = 1.0 + j as f64;
        for r in 0..4 {
            b[(states[r], j)] = b1[(r, 0)] * scale;
            for c in 0..4 {
                a[(states[r], states[c])] = a1[(r, c)] * scale;
            }
        }
    }
    let mut blocks =
        BlockDiscretizationCache::new(&a, &b, &[block0, block1], &[0..1, 1..2], &[1.0; 8]).unwrap();
    let full = discretize(&a, &b, 0.37, true).unwrap();
    let z = DVector::from_fn(8, |i, _| (i as f64 * 0.7).sin());
    let (u, du) = ([0.3, -1.2], [2.0, 0.5]);
    let mut next = vec![0.0; 8];
    blocks
        .get(0.37)
        .unwrap()
        .apply(z.as_slice(), &u, &du, &mut next);
    let expected = &full.phi * &z
        + &full.gamma0 * DVector::from_row_slice(&u)
        + full.gamma1.as_ref().unwrap() * DVector::from_row_slice(&du);
    for i in 0..8 {
        assert!((next[i] - expected[i]).abs() < 1e-14, "{i}");
    }
    // A coupling between the blocks, or a block missing a state, is refused.
    let mut coupled = a.clone();
    coupled[(0, 1)] = 1e-3;
    let halves = [vec![0, 5, 2, 7], vec![1, 3, 6, 4]];
    assert!(
        BlockDiscretizationCache::new(&coupled, &b, &halves, &[0..1, 1..2], &[1.0; 8]).is_err()
    );
    assert!(BlockDiscretizationCache::new(
        &a,
        &b,
        &[vec![0, 5, 2, 7], vec![1, 3, 6]],
        &[0..1, 1..2],
        &[1.0; 8]
    )
    .is_err());
    // An input in two blocks, or one driving the other block's states, is refused.
    assert!(BlockDiscretizationCache::new(&a, &b, &halves, &[0..2, 1..2], &[1.0; 8]).is_err());
    assert!(BlockDiscretizationCache::new(&a, &b, &halves, &[1..2, 0..1], &[1.0; 8]).is_err());
    assert!(blocks.get(0.0).is_err());
}

#[test]
fn a_block_with_several_inputs_steps_like_the_whole_system() {
    // Block 0: Schilder et al.'s chain driven by two inputs (columns 0 and 1), block 1: the same
    // chain scaled, driven by input 2.
    let (a1, b1) = seed_system();
    let mut a = DMatrix::zeros(8, 8);
    let mut b = DMatrix::zeros(8, 3);
    for r in 0..4 {
        b[(r, 0)] = b1[(r, 0)];
        b[(r, 1)] = (r as f64 + 1.0) * 0.3;
        b[(4 + r, 2)] = 2.0 * b1[(r, 0)];
        for c in 0..4 {
            a[(r, c)] = a1[(r, c)];
            a[(4 + r, 4 + c)] = 2.0 * a1[(r, c)];
        }
    }
    let mut blocks = BlockDiscretizationCache::new(
        &a,
        &b,
        &[vec![0, 1, 2, 3], vec![4, 5, 6, 7]],
        &[0..2, 2..3],
        &[1.0; 8],
    )
    .unwrap();
    assert_eq!(blocks.input_count(), 3);
    let full = discretize(&a, &b, 0.21, true).unwrap();
    let z = DVector::from_fn(8, |i, _| (i as f64 * 1.3).cos());
    let (u, du) = ([0.3, -1.2, 0.8], [2.0, 0.5, -0.4]);
    let mut next = vec![0.0; 8];
    blocks
        .get(0.21)
        .unwrap()
        .apply(z.as_slice(), &u, &du, &mut next);
    let expected = &full.phi * &z
        + &full.gamma0 * DVector::from_row_slice(&u)
        + full.gamma1.as_ref().unwrap() * DVector::from_row_slice(&du);
    for i in 0..8 {
        assert!((next[i] - expected[i]).abs() < 1e-14, "{i}");
    }
}
