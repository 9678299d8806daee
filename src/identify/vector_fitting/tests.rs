use super::*;

/// Parameters with `pairs` complex pairs and `real` real poles, over every frequency.
fn params(pairs: usize, real: usize) -> VectorFitParams {
    VectorFitParams {
        complex_pairs: pairs,
        real_poles: real,
        ..VectorFitParams::default()
    }
}

/// Largest modulus of a complex matrix.
fn largest(m: &DMatrix<Complex64>) -> f64 {
    m.iter().map(|x| x.norm()).fold(0.0, f64::max)
}

/// A 2-DOF response made by a known common-pole model (two pairs and one real pole, symmetric
/// residues) plus `A_inf`, on 80 log-spaced frequencies over 0.2 .. 20 rad/s.
fn synthetic() -> (FrequencyResponse, Vec<Complex64>, Vec<DMatrix<Complex64>>) {
    let poles = vec![
        Complex64::new(-0.3, 1.1),
        Complex64::new(-2.0, 6.0),
        Complex64::new(-0.8, 0.0),
    ];
    let residues = vec![
        DMatrix::from_row_slice(
            2,
            2,
            &[
                Complex64::new(3.0, -1.0),
                Complex64::new(0.5, 0.2),
                Complex64::new(0.5, 0.2),
                Complex64::new(1.0, 0.4),
            ],
        ),
        DMatrix::from_row_slice(
            2,
            2,
            &[
                Complex64::new(20.0, 5.0),
                Complex64::new(-4.0, 1.0),
                Complex64::new(-4.0, 1.0),
                Complex64::new(8.0, -3.0),
            ],
        ),
        DMatrix::from_row_slice(
            2,
            2,
            &[
                Complex64::new(2.0, 0.0),
                Complex64::new(0.7, 0.0),
                Complex64::new(0.7, 0.0),
                Complex64::new(1.5, 0.0),
            ],
        ),
    ];
    let model = RationalFit {
        poles: poles.clone(),
        residues: residues.clone(),
        dof_scales: DVector::from_element(2, 1.0),
        max_error: 0.0,
    };
    let omega: Vec<f64> = (0..80)
        .map(|k| 0.2 * 100f64.powf(k as f64 / 79.0))
        .collect();
    let added_mass_inf = DMatrix::from_row_slice(2, 2, &[10.0, 1.0, 1.0, 5.0]);
    let added_mass = omega
        .iter()
        .map(|&w| model.evaluate(w) + added_mass_inf.map(|x| Complex64::new(x, 0.0)))
        .collect();
    let response = FrequencyResponse {
        dof_names: vec!["a".into(), "b".into()],
        omega,
        added_mass,
        added_mass_inf,
        rho: 1.0,
        g: 1.0,
    };
    (response, poles, residues)
}

#[test]
fn a_common_pole_model_is_recovered_from_its_own_response() {
    let (response, poles, residues) = synthetic();
    let params = params(2, 1);
    let fit = vector_fit(&response, &params).unwrap();
    assert!(fit.max_error < 1e-10, "{}", fit.max_error);
    assert_eq!(fit.pole_count(), 5);
    for (p, r) in poles.iter().zip(&residues) {
        let (found, residue) = fit
            .poles
            .iter()
            .zip(&fit.residues)
            .min_by(|a, b| (a.0 - p).norm().total_cmp(&(b.0 - p).norm()))
            .unwrap();
        assert!((found - p).norm() < 1e-8 * p.norm(), "{found} vs {p}");
        assert!(
            largest(&(residue - r)) < 1e-7 * largest(r),
            "{residue} vs {r}"
        );
    }
    // Reconstruction off the grid, between the samples and beyond the band.
    let model = RationalFit {
        poles,
        residues,
        dof_scales: fit.dof_scales.clone(),
        max_error: 0.0,
    };
    for w in [0.05, 0.77, 3.3, 50.0] {
        assert!(largest(&(fit.evaluate(w) - model.evaluate(w))) < 1e-8);
    }
}

#[test]
fn the_fit_is_deterministic_and_its_poles_are_stable() {
    let (response, _, _) = synthetic();
    let params = params(1, 1);
    let a = vector_fit(&response, &params).unwrap();
    let b = vector_fit(&response, &params).unwrap();
    assert_eq!(a, b);
    assert!(a.poles.iter().all(|p| p.re < 0.0));
    // Too few poles: a real misfit, reported.
    assert!(a.max_error > 1e-3);
}

#[test]
fn bad_bands_and_orders_are_refused() {
    let (response, _, _) = synthetic();
    let none = VectorFitParams {
        complex_pairs: 0,
        real_poles: 0,
        ..VectorFitParams::default()
    };
    assert!(matches!(
        vector_fit(&response, &none),
        Err(IdentifyError::InvalidParams(_))
    ));
    let narrow = VectorFitParams {
        band: (1.0, 1.1),
        ..VectorFitParams::default()
    };
    assert!(matches!(
        vector_fit(&response, &narrow),
        Err(IdentifyError::InvalidBand(_))
    ));
}

#[test]
fn the_impedance_realization_reproduces_s_times_the_model() {
    let (response, _, _) = synthetic();
    let params = params(2, 1);
    let fit = vector_fit(&response, &params).unwrap();
    let [a, b, c, d] = fit.impedance_realization();
    assert_eq!(a.nrows(), 2 * 5);
    for w in [0.1, 1.0, 7.0] {
        let s = Complex64::new(0.0, w);
        let force = crate::realize::transfer_function(&a, &b, &c, &d, s);
        // F = -K v, K = s G.
        let expected = -(fit.evaluate(w) * s);
        assert!(largest(&(force - &expected)) < 1e-12 * largest(&expected));
    }
}

#[test]
fn enforcement_leaves_a_passive_fit_alone() {
    // The synthetic model: is its impedance passive? Either way, the enforced fit must pass the
    // check, and a model that already passes keeps the free residues (no round).
    let (response, _, _) = synthetic();
    let params = params(2, 1);
    let (fit, enforcement) = passive_vector_fit(&response, &params).unwrap();
    assert!(enforcement.passive, "{enforcement:?}");
    let free = vector_fit(&response, &params).unwrap();
    let free_report = free.passivity(1e-9);
    if free_report.passive {
        assert_eq!(enforcement.rounds, 0);
        assert!(fit.max_error < 1e-10);
    } else {
        assert!(enforcement.rounds > 0 && enforcement.samples > 0);
        assert!(fit.max_error >= free.max_error);
    }
}
