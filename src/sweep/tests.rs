//! Tests of the frequency sweep: grids, limits, tables and their bytes.

use super::*;

#[test]
fn log_grid_spans_its_bounds_and_rejects_bad_input() {
    let grid = log_grid(0.01, 10.0, 201).unwrap();
    assert_eq!(grid.len(), 201);
    assert_eq!((grid[0], grid[200]), (0.01, 10.0));
    assert!((grid[100] - 0.01f64.sqrt() * 10f64.sqrt()).abs() < 1e-12);
    assert!(grid.windows(2).all(|w| w[1] > w[0]));
    for (min, max, count) in [
        (0.0, 1.0, 10),
        (-1.0, 1.0, 10),
        (2.0, 1.0, 10),
        (1.0, 2.0, 0),
    ] {
        let err = log_grid(min, max, count).unwrap_err();
        assert!(err.to_string().contains("kR"), "{err}");
    }
}

#[test]
fn the_excitation_table_has_every_frequency_heading_and_dof() {
    let hull = Hull::semicircle(2.0).unwrap();
    let params = SweepParams {
        kr: vec![0.5, 1.5],
        panels: PanelParams {
            body_panels: 32,
            ..PanelParams::default()
        },
        ..SweepParams::default()
    };
    let result = run(&hull, &params, &|_, _| {}).unwrap();
    let mut text = Vec::new();
    result
        .write_excitation_csv(&mut text, ExcitationPart::Total)
        .unwrap();
    let text = String::from_utf8(text).unwrap();
    assert!(text.contains("# modes: sway heave roll cb1 cb2 cb3 cb4 cb5 cb6\n"));
    assert!(text.contains("# R: 2 m\n"));
    assert!(text.contains("# length exponents: 0 0 1 0 0 1 0 0 1\n"));
    let rows: Vec<Vec<&str>> = text
        .lines()
        .skip_while(|l| *l != "kR,j,heading,re,im")
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    // (the kR = 0 limit + 2 frequencies) x 2 headings x 9 DOFs.
    assert_eq!(rows.len(), 3 * 2 * 9);
    // Heave's long-wave limit: integral n_y ds / R^(1 + 0) = 2R / R = 2.
    let heave_limit: f64 = rows[1][3].parse().unwrap();
    assert!((heave_limit - 2.0).abs() < 1e-12);
    assert_eq!(rows[9][2], "180");
    // A frequency row reads back as the direct value over R^(1 + e_j) (roll: R^2).
    let row = &rows[2 * 9 + 1];
    assert_eq!((row[0], row[1], row[2]), ("5e-1", "2", "0"));
    let stored = result.excitation[0].direct[(1, 0)];
    assert_eq!(row[3].parse::<f64>().unwrap(), stored.re);
    assert_eq!(row[4].parse::<f64>().unwrap(), stored.im);
    // The wave model reads it back: same modes, radius, exponents and values.
    let table = crate::waves::ExcitationTable::from_csv_str(&text, "table").unwrap();
    assert_eq!(table.modes(), result.dof_names.as_slice());
    assert_eq!(table.radius(), 2.0);
    assert_eq!(table.length_exponents(), [0, 0, 1, 0, 0, 1, 0, 0, 1]);
    assert!(table.has_long_wave_rows());
    let heading = table.heading_index(180.0).unwrap();
    assert_eq!(
        table.value(5, heading, 2),
        Some(result.excitation[1].direct[(5, 1)])
    );
    // A selection keeps its DOFs' rows, in the order asked for.
    let picked = result.select_dofs(&["heave", "sway"]).unwrap();
    assert_eq!(picked.dof_names, ["heave", "sway"]);
    assert_eq!(
        picked.excitation[1].direct[(0, 1)],
        result.excitation[1].direct[(1, 1)]
    );
    assert_eq!(picked.added_mass[0][(0, 1)], result.added_mass[0][(1, 0)]);
    assert_eq!(
        picked.excitation_long_wave[0],
        result.excitation_long_wave[1]
    );
    assert_eq!(
        picked.excitation_long_wave[1],
        result.excitation_long_wave[0]
    );
    assert!(result.select_dofs(&["pitch"]).is_none());
    // The Froude-Krylov table is a different force in the same layout.
    let mut fk = Vec::new();
    result
        .write_excitation_csv(&mut fk, ExcitationPart::FroudeKrylov)
        .unwrap();
    let fk = String::from_utf8(fk).unwrap();
    assert_eq!(fk.lines().count(), text.lines().count() - 1);
    assert!(fk.contains("Froude-Krylov part"));
}

#[test]
fn normalized_difference_scales_by_the_diagonal_and_skips_empty_dofs() {
    let c = |re: f64| Complex64::new(re, 0.0);
    let reference = vec![DMatrix::from_row_slice(
        3,
        3,
        &[
            c(4.0),
            c(1.0),
            c(0.0),
            c(1.0),
            c(1.0),
            c(0.0),
            c(0.0),
            c(0.0),
            c(0.0),
        ],
    )];
    let mut perturbed = reference.clone();
    perturbed[0][(0, 1)] += c(0.02); // 0.02 / sqrt(4 * 1) = 0.01
    perturbed[0][(2, 2)] += c(1.0); // DOF 2 has no added mass: skipped
    let (error, k, entry) = max_normalized_difference(&perturbed, &reference);
    assert!((error - 0.01).abs() < 1e-15);
    assert_eq!((k, entry), (0, (0, 1)));
}

#[test]
fn one_failed_frequency_is_reported_and_the_others_survive() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let kr = [0.1, 0.2, 0.3, 0.4];
    let calls = AtomicUsize::new(0);
    let solve_at = |k: f64| {
        if k == 0.3 {
            Err(BemError::Singular {
                surface: FreeSurface::Wave { wavenumber: k },
                body_panels: 4,
                lid_panels: 0,
            })
        } else {
            Ok(RadiationSolution {
                added_mass: DMatrix::from_element(1, 1, Complex64::new(k, 0.0)),
                reciprocity_residual: 0.0,
                influence_time: Duration::ZERO,
                assembly_time: Duration::ZERO,
                factorization_time: Duration::ZERO,
                wave_forces: None,
            })
        }
    };
    let progress = |_: usize, total: usize| {
        calls.fetch_add(1, Ordering::Relaxed);
        assert_eq!(total, 4);
    };
    let solutions = solve_all(&pool, &kr, &solve_at, &progress);
    assert_eq!(calls.load(Ordering::Relaxed), 4);
    let kept: Vec<f64> = solutions.iter().map(|(k, _)| *k).collect();
    assert_eq!(kept, kr);
    assert!(solutions[2].1.is_err());
    assert!(solutions.iter().filter(|(_, s)| s.is_ok()).count() == 3);
}

#[test]
fn the_drift_table_is_nondimensional_and_mirrors_its_headings() {
    // The same section at R = 1 m and R = 50 m: the same table values (to rounding), the
    // rigid sway row the far field's, headings 0 and 180 mirrored (sway and roll change sign).
    let params = SweepParams {
        kr: vec![0.3, 1.0, 3.0],
        panels: PanelParams {
            body_panels: 32,
            ..PanelParams::default()
        },
        ..SweepParams::default()
    };
    let table = |radius: f64| {
        let result = run(&Hull::semicircle(radius).unwrap(), &params, &|_, _| {}).unwrap();
        let mut text = Vec::new();
        result.write_drift_csv(&mut text).unwrap();
        (result, String::from_utf8(text).unwrap())
    };
    let (result, text) = table(1.0);
    assert!(text.contains("# length exponents: 0 0 1 0 0 1 0 0 1\n"));
    let rows = |text: &str| -> Vec<Vec<f64>> {
        text.lines()
            .skip_while(|l| *l != "kR,j,heading,value")
            .skip(1)
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect()
    };
    let small = rows(&text);
    assert_eq!(small.len(), 3 * 2 * 9);
    let drift = result.excitation[1].drift.as_ref().unwrap();
    // kR 1, heading 0, sway: Maruo's far field.
    assert_eq!(small[2 * 9][3], drift.horizontal_far_field(0));
    for block in small.chunks(18) {
        let (h0, h180) = block.split_at(9);
        assert!((h0[0][3] + h180[0][3]).abs() <= 1e-12 * h0[0][3].abs());
        assert!((h0[1][3] - h180[1][3]).abs() <= 1e-12 * h0[1][3].abs());
        assert!((h0[2][3] + h180[2][3]).abs() <= 1e-12);
    }
    let large = rows(&table(50.0).1);
    for (a, b) in small.iter().zip(&large) {
        let scale = a[3].abs().max(1e-3);
        assert!((a[3] - b[3]).abs() <= 1e-9 * scale, "{a:?} {b:?}");
    }
}

fn small_sweep(depth: WaterDepth) -> SweepParams {
    SweepParams {
        kr: vec![0.5, 1.5],
        panels: PanelParams {
            body_panels: 32,
            ..PanelParams::default()
        },
        extrapolation_levels: 1,
        threads: 1,
        depth,
        ..SweepParams::default()
    }
}

fn table_text(result: &SweepResult, excitation: bool) -> String {
    let mut text = Vec::new();
    if excitation {
        result
            .write_excitation_csv(&mut text, ExcitationPart::Total)
            .unwrap();
    } else {
        result.write_csv(&mut text).unwrap();
    }
    String::from_utf8(text).unwrap()
}

#[test]
fn every_table_records_the_water_depth() {
    let hull = Hull::semicircle(2.0).unwrap();
    let deep = run(&hull, &small_sweep(WaterDepth::Infinite), &|_, _| {}).unwrap();
    let finite = run(&hull, &small_sweep(WaterDepth::Finite(5.0)), &|_, _| {}).unwrap();
    for excitation in [false, true] {
        let text = table_text(&deep, excitation);
        assert!(text.contains("# R: 2 m\n# depth: inf\n"), "{text}");
        let text = table_text(&finite, excitation);
        assert!(text.contains("# R: 2 m\n# depth: 2.5\n"), "{text}");
    }
    // The depth changes the coefficients; A(0) leaves heave-heave out as in deep water.
    let d = (deep.added_mass[0][(1, 1)] - finite.added_mass[0][(1, 1)]).norm();
    assert!(d > 1e-3 * deep.added_mass[0][(1, 1)].norm());
    assert!(finite.added_mass_zero[(1, 1)].is_none());
    assert!(finite.added_mass_zero[(0, 0)].is_some());
    // The drift table too, in either depth.
    for (result, line) in [(&deep, "# depth: inf\n"), (&finite, "# depth: 2.5\n")] {
        let mut text = Vec::new();
        result.write_drift_csv(&mut text).unwrap();
        let text = String::from_utf8(text).unwrap();
        assert!(
            text.contains(line) && text.contains("\nkR,j,heading,value\n"),
            "{text}"
        );
    }
}

#[test]
fn a_hull_on_the_bottom_and_a_bad_depth_are_refused_by_name() {
    let hull = Hull::semicircle(2.0).unwrap();
    for depth in [2.0, 1.5] {
        let error = small_sweep(WaterDepth::Finite(depth))
            .validate(&hull)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("bottom") && error.contains("keel"),
            "{error}"
        );
        assert!(error.contains(&format!("{depth}")), "{error}");
    }
    assert!(small_sweep(WaterDepth::Finite(2.01))
        .validate(&hull)
        .is_ok());
    for depth in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let error = small_sweep(WaterDepth::Finite(depth))
            .validate(&hull)
            .unwrap_err()
            .to_string();
        assert!(error.contains("finite and > 0"), "{error}");
    }
}
