//! The library under hostile input: sizes past their limits are refused before anything is
//! allocated, and every number a sweep returns is finite (or the sweep fails saying where).

use hydrofmu::hull::Hull;
use hydrofmu::panels::{self, PanelParams};
use hydrofmu::sweep::{self, SweepParams};

/// A fast sweep at `kr`: 16 panels, no extrapolation, one thread.
fn quick(kr: Vec<f64>) -> SweepParams {
    SweepParams {
        kr,
        panels: PanelParams {
            body_panels: 16,
            ..PanelParams::default()
        },
        extrapolation_levels: 1,
        threads: 1,
        ..SweepParams::default()
    }
}

#[test]
fn grids_past_the_frequency_limit_are_refused_before_allocating() {
    for count in [100_000_000_000usize, usize::MAX] {
        let e = sweep::log_grid(0.1, 5.0, count).unwrap_err().to_string();
        assert!(e.contains("frequencies requested; at most 100000"), "{e}");
    }
    assert_eq!(sweep::log_grid(0.1, 5.0, 100_000).unwrap().len(), 100_000);
}

#[test]
fn sweep_sizes_past_their_limits_are_refused_before_any_work() {
    let hull = Hull::semicircle(1.0).unwrap();
    let base = quick(vec![0.5, 1.0]);
    let with_panels = |body_panels: usize, levels: usize| SweepParams {
        panels: PanelParams {
            body_panels,
            ..PanelParams::default()
        },
        extrapolation_levels: levels,
        ..base.clone()
    };
    let cases = [
        (
            with_panels(100_000_000, 1),
            "100000000 panels requested; at most 8192",
        ),
        (with_panels(usize::MAX, 1), "at most 8192"),
        (
            with_panels(8192, 13),
            "13 discretization levels requested; at most 12",
        ),
        (with_panels(128, 13), "at most 12"),
        (
            SweepParams {
                threads: 100_000_000,
                ..base.clone()
            },
            "100000000 worker threads requested; at most 1024",
        ),
        (
            quick(vec![0.5; 100_001]),
            "100001 frequencies requested; at most 100000",
        ),
        (quick(Vec::new()), "no frequency"),
    ];
    for (params, expected) in cases {
        // Refused before any work: no frequency reports progress.
        let progress = std::sync::atomic::AtomicUsize::new(0);
        let e = sweep::run(&hull, &params, &|_, _| {
            progress.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        })
        .unwrap_err()
        .to_string();
        assert!(e.contains(expected), "'{e}' lacks '{expected}'");
        assert_eq!(progress.into_inner(), 0, "{expected}: no work before");
    }
}

#[test]
fn a_table_past_its_entry_limit_is_refused() {
    // 256 DOFs (the hull limit) at 1000 frequencies: 65.5 million entries.
    let mut text =
        String::from("<hull name=\"many\" half_beam=\"1\">\n<circle radius=\"1\" depth=\"0\"/>\n");
    for k in 0..256 {
        text.push_str(&format!("<rigid name=\"d{k}\" kind=\"heave\"/>\n"));
    }
    text.push_str("</hull>\n");
    let hull = Hull::from_xml_str(&text, "many.xml").unwrap();
    let params = quick(sweep::log_grid(0.1, 5.0, 1000).unwrap());
    let progress = std::sync::atomic::AtomicUsize::new(0);
    let e = sweep::run(&hull, &params, &|_, _| {
        progress.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    })
    .unwrap_err()
    .to_string();
    assert!(
        e.contains(
            "65536000 added-mass table entries (frequencies x DOFs^2) requested; at most 20000000"
        ),
        "{e}"
    );
    assert_eq!(progress.into_inner(), 0, "no work before the refusal");
}

#[test]
fn a_lid_past_its_limit_is_refused_before_allocating() {
    let hull = Hull::semicircle(1.0).unwrap();
    for lid_density in [1e3, 1e300] {
        let params = PanelParams {
            lid_density,
            ..PanelParams::default()
        };
        let e = panels::discretize(&hull, &params).unwrap_err().to_string();
        assert!(e.contains("lid panels; at most 4096"), "{e}");
    }
    // The default lid of the largest mesh stays below the limit.
    let mesh = panels::discretize(
        &hull,
        &PanelParams {
            body_panels: 8192,
            ..PanelParams::default()
        },
    )
    .unwrap();
    assert!(mesh.lid.len() < 4096, "{}", mesh.lid.len());
}

#[test]
fn every_number_of_a_sweep_is_finite_or_the_sweep_fails() {
    let hull = Hull::semicircle(1.0).unwrap();
    // kR = 1e6: the panel method overflows; alone it leaves nothing, an error.
    let e = sweep::run(&hull, &quick(vec![1e6]), &|_, _| {})
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("the sweep's only frequency failed; kR = 1000000: "),
        "{e}"
    );
    let e = sweep::run(&hull, &quick(vec![1e6, 1e300]), &|_, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("all 2 frequencies of the sweep failed"), "{e}");
    // With a good frequency the bad one is a failure with its reason, the rest is finite.
    let result = sweep::run(&hull, &quick(vec![0.5, 1e6]), &|_, _| {}).unwrap();
    assert_eq!(result.kr, [0.5]);
    assert_eq!(result.failures.len(), 1);
    assert!(
        result.failures[0].1.contains("non-finite"),
        "{:?}",
        result.failures
    );
    let finite = |z: &num_complex::Complex64| z.re.is_finite() && z.im.is_finite();
    assert!(result.added_mass.iter().flatten().all(finite));
    assert!(result
        .excitation
        .iter()
        .all(|w| w.direct.iter().all(finite)));
    assert!(result.reciprocity_residual.iter().all(|r| r.is_finite()));
}

/// Before: a synthetic database of 20 DOFs (diagonally dominant, 40 frequencies) fitted for
/// more than 288 s of CPU time without finishing (10 DOFs: 19 s). Now more than
/// `MAX_FIT_DOFS` are refused before any work.
#[test]
fn a_fit_of_more_dofs_than_its_limit_is_refused_before_any_work() {
    use hydrofmu::identify::{self, FitParams, FrequencyResponse, MAX_FIT_DOFS};
    use nalgebra::DMatrix;
    use num_complex::Complex64;
    assert_eq!(MAX_FIT_DOFS, 12);
    let n = MAX_FIT_DOFS + 1;
    let omega = vec![0.5, 1.0, 2.0, 4.0];
    let response = FrequencyResponse {
        dof_names: (0..n).map(|i| format!("mode{i}")).collect(),
        added_mass: omega
            .iter()
            .map(|w| DMatrix::from_diagonal_element(n, n, Complex64::new(1.0 + 1.0 / w, -1.0 / w)))
            .collect(),
        omega,
        added_mass_inf: DMatrix::identity(n, n),
        rho: 1025.0,
        g: 9.81,
    };
    let e = identify::fit(&response, &FitParams::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("13 DOFs; a fit takes at most 12"), "{e}");
}

/// WAMIT's hemisphere (tests/data/wamit) with its `.1` file `edit`ed, imported at `ulen`.
fn hemisphere(
    tag: &str,
    ulen: f64,
    edit: impl Fn(&str) -> String,
) -> hydrofmu::identify::FrequencyResponse {
    use hydrofmu::database::import::{import, ImportParams};
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/wamit");
    let dir = std::env::temp_dir().join(format!("hydrofmu-hostile-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(data.join("sphere.1")).unwrap();
    let edited: Vec<String> = text.lines().map(&edit).collect();
    std::fs::write(dir.join("sphere.1"), edited.join("\n") + "\n").unwrap();
    let mut params = ImportParams::new();
    params.wamit.length_scale = ulen;
    let response = import(&dir.join("sphere.1"), &params).unwrap().response();
    let _ = std::fs::remove_dir_all(&dir);
    response
}

/// Before: at ULEN = 1e40 (largest entry 1.3e203 kg m^2) the fit returned order 0 with an
/// error of "0.000 %" (its errors overflowed to NaN, which the maximum skipped) and the
/// passivity check of that empty network panicked in nalgebra's Schur; at 1e-40 order 0 with
/// 64 %. Now refused before the fit, the range named.
#[test]
fn a_badly_scaled_database_is_refused_naming_the_representable_range() {
    use hydrofmu::identify::{self, FitParams, VALUE_RANGE};
    assert_eq!(VALUE_RANGE, (1e-50, 1e50));
    for ulen in [1e40, 1e-40] {
        let response = hemisphere("ulen", ulen, str::to_string);
        let e = identify::fit(&response, &FitParams::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("largest added mass entry") && e.contains("outside the range 1e-50 .. 1e50"),
            "{ulen}: {e}"
        );
    }
}

/// Before: periods of 1e300 and 1e-300 s (omega 6.3e-300 and 6.3e300 rad/s) kept nalgebra's
/// SVD in the vector fit iterating for ever (killed after 60 s). Now refused before the fit.
#[test]
fn frequencies_past_the_range_are_refused_before_the_fit() {
    use hydrofmu::identify::{self, FitParams, FrequencyResponse};
    let response = hemisphere("periods", 1.0, |line| {
        line.replacen(" 3.141593E+01 ", " 1.0E+300 ", 1)
            .replacen(" 2.617996E+00 ", " 1.0E-300 ", 1)
    });
    assert!(response.omega[0] < 1e-299 && response.omega[6] > 1e299);
    let e = identify::fit(&response, &FitParams::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("outside the range 1e-12 .. 1e12 rad/s"), "{e}");
    // Within the range but 1e13 apart.
    let mut spread = FrequencyResponse {
        omega: vec![1e-6, 1.0, 1e7],
        ..response.clone()
    };
    spread.added_mass.truncate(3);
    let e = identify::fit(&spread, &FitParams::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("a ratio above 1e12"), "{e}");
}
