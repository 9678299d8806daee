//! Tests of the drift table and of the sea's drift forces.

use super::*;
use crate::hull::Hull;
use crate::panels::PanelParams;
use crate::sweep::{self, SweepParams};

const RHO: f64 = 1025.0;
const G: f64 = 9.81;

/// A small drift table: sway `0.5 kR / (1 + kR)` (heading 0; minus at 180), heave 0, roll
/// `0.1 kR` (heading 0; minus at 180), at kR 0.2, 0.5, 1, 2.
fn drift_text() -> String {
    drift_text_at(&[0.2, 0.5, 1.0, 2.0])
}

fn drift_text_at(kr_values: &[f64]) -> String {
    let mut text = "# hull: synthetic\n# modes: sway heave roll\n# convention: exp(+i omega t)\n\
                    # R: 2 m\n# length exponents: 0 0 1\nkR,j,heading,value\n"
        .to_string();
    for &kr in kr_values {
        for (heading, sign) in [(0.0, 1.0), (180.0, -1.0)] {
            let values = [sign * 0.5 * kr / (1.0 + kr), 0.0, sign * 0.1 * kr];
            for (j, v) in values.iter().enumerate() {
                text += &format!("{kr},{},{heading},{v:e}\n", j + 1);
            }
        }
    }
    text
}

#[test]
fn the_drift_table_interpolates_linearly_and_vanishes_towards_long_waves() {
    let table = DriftTable::from_csv_str(&drift_text(), "drift.csv").unwrap();
    assert_eq!(table.modes(), ["sway", "heave", "roll"]);
    assert_eq!(table.kr(), [0.0, 0.2, 0.5, 1.0, 2.0]);
    assert_eq!(table.headings(), [0.0, 180.0]);
    assert_eq!(table.heading_index(-180.0), Some(1));
    assert_eq!(table.heading_index(90.0), None);
    // At a node, between nodes, below the band (towards 0 at kR = 0), above it.
    assert_eq!(table.interpolate(0, 0, 1.0), Some(0.25));
    let between = 0.5 * (0.25 / 1.5 + 0.25);
    assert!((table.interpolate(0, 0, 0.75).unwrap() - between).abs() < 1e-15);
    let first = 0.5 * 0.2 / 1.2;
    assert!((table.interpolate(0, 1, 0.05).unwrap() + first / 4.0).abs() < 1e-15);
    assert_eq!(table.interpolate(0, 0, 0.0), Some(0.0));
    assert_eq!(
        table.interpolate(0, 0, 2.0 * (1.0 + 1e-13)),
        Some(0.5 * 2.0 / 3.0)
    );
    assert_eq!(table.interpolate(0, 0, 2.001), None);
    assert_eq!(table.interpolate(0, 0, f64::NAN), None);
    assert_eq!(table.interpolate(3, 0, 1.0), None);
    assert!(table.is_zero(1, 0) && !table.is_zero(0, 0) && !table.is_zero(2, 1));
    // rho g R^e_j: roll has one length exponent.
    assert_eq!(table.force_scale(0, 1000.0, 10.0), Some(1e4));
    assert_eq!(table.force_scale(2, 1000.0, 10.0), Some(2e4));
    assert_eq!(table.force_scale(3, 1000.0, 10.0), None);
}

#[test]
fn a_malformed_drift_table_is_refused_naming_its_line_and_field() {
    let text = drift_text();
    let refuse = |text: &str| {
        DriftTable::from_csv_str(text, "drift.csv")
            .unwrap_err()
            .to_string()
    };
    let message = refuse(&text.replace("1,2,0,0e0", "1,2,0,inf"));
    assert!(
        message.contains("drift.csv:") && message.contains("field `value`"),
        "{message}"
    );
    let message = refuse(&text.replace("1,2,0,0e0", "1,2,0,0e0,0"));
    assert!(
        message.contains("5 fields") && message.contains("(4 fields)"),
        "{message}"
    );
    let message = refuse(&text.replace("kR,j,heading,value", "kR,j,heading,re,im"));
    assert!(message.contains("kR,j,heading,value"), "{message}");
    let message = refuse(&text.replace("1,2,0,0e0\n", ""));
    assert!(message.contains("missing row kR = 1"), "{message}");
    let message = refuse(&text.replace("# R: 2 m\n", ""));
    assert!(message.contains("# R:"), "{message}");
    // Bounded before allocating: the row count, and the text's size.
    let big = " ".repeat(MAX_TABLE_BYTES + 1);
    assert!(refuse(&big).contains("64 MiB"));
    let mut headings = text.clone();
    for h in 0..=MAX_HEADINGS {
        headings += &format!("1,1,{},0\n", h + 1);
    }
    assert!(refuse(&headings).contains("field `heading`"));
}

#[test]
fn a_sweeps_drift_table_reads_back_its_values() {
    let params = SweepParams {
        kr: vec![0.4, 1.2],
        panels: PanelParams {
            body_panels: 32,
            ..PanelParams::default()
        },
        ..SweepParams::default()
    };
    let result = sweep::run(&Hull::semicircle(3.0).unwrap(), &params, &|_, _| {}).unwrap();
    let mut text = Vec::new();
    result.write_drift_csv(&mut text).unwrap();
    let text = String::from_utf8(text).unwrap();
    let table = DriftTable::from_csv_str(&text, "drift.csv").unwrap();
    assert_eq!(table.radius(), 3.0);
    assert_eq!(table.kr(), [0.0, 0.4, 1.2]);
    assert_eq!(table.modes().len(), 9);
    assert_eq!(table.length_exponents(), [0, 0, 1, 0, 0, 1, 0, 0, 1]);
    let mut compared = 0;
    for (k, forces) in result.excitation.iter().enumerate() {
        let values = forces.drift.as_ref().unwrap().mean_drift();
        for h in 0..2 {
            for j in 0..9 {
                let expected = values[(j, h)] / 3f64.powi(table.length_exponents()[j]);
                let read = table.value(j, h, k + 1).unwrap();
                assert!(
                    (read - expected).abs() <= 1e-15 * expected.abs(),
                    "{read} {expected}"
                );
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 2 * 2 * 9);
    // Sway drift is the far field's, not zero: the reader kept the signs by heading.
    assert!(table.value(0, 0, 2).unwrap() > 0.0 && table.value(0, 1, 2).unwrap() < 0.0);
}

/// The drift table over kR 0.2..5 on 60 nodes (a JONSWAP sea of Tp = 8 s at R = 2 m reaches
/// kR 4.5).
fn wide_table() -> DriftTable {
    let kr: Vec<f64> = (0..60).map(|i| 0.2 * 25f64.powf(i as f64 / 59.0)).collect();
    DriftTable::from_csv_str(&drift_text_at(&kr), "drift.csv").unwrap()
}

fn sea_with_drift(params: &WaveParams, mode: DriftMode) -> Sea {
    Sea::new(params, None, RHO, G, 0.0)
        .unwrap()
        .with_drift(params, &wide_table(), mode, RHO, G)
        .unwrap()
}

/// `D_j(omega)` in SI of the wide table at heading 0.
fn drift_si(j: usize, omega: f64) -> f64 {
    let table = wide_table();
    let kr = crate::units::kr_from_omega(omega, table.radius(), G);
    table.interpolate(j, 0, kr).unwrap() * table.force_scale(j, RHO, G).unwrap()
}

#[test]
fn a_regular_wave_drifts_by_a_squared_d_in_both_modes() {
    let params = WaveParams {
        kind: WaveKind::Regular,
        height: 3.0,
        period: 6.0,
        ..WaveParams::default()
    };
    let omega = 2.0 * std::f64::consts::PI / 6.0;
    let expected = [2.25 * drift_si(0, omega), 0.0, 2.25 * drift_si(2, omega)];
    assert!(expected[0] > 100.0 && expected[2] > 100.0);
    for mode in [DriftMode::Mean, DriftMode::Newman] {
        let sea = sea_with_drift(&params, mode);
        let mut scratch = sea.scratch();
        let mut forces = [f64::NAN; 4];
        for step in 0..2000 {
            sea.evaluate_drift(0.05 * step as f64, &mut scratch, &mut forces);
            for j in 0..3 {
                assert!(
                    (forces[j] - expected[j]).abs() <= 1e-12 * expected[0],
                    "{mode:?} j {j}: {} vs {}",
                    forces[j],
                    expected[j]
                );
            }
            assert_eq!(forces[3], 0.0);
        }
        assert_eq!(sea.mean_drift(0), expected[0]);
    }
    // Heading 180 mirrors sway; no drift: zeros.
    let mirrored = WaveParams {
        heading: 180.0,
        ..params.clone()
    };
    let sea = sea_with_drift(&mirrored, DriftMode::Mean);
    assert!((sea.mean_drift(0) + expected[0]).abs() <= 1e-12 * expected[0]);
    let sea = sea_with_drift(&params, DriftMode::Off);
    let mut forces = [1.0; 3];
    sea.evaluate_drift(1.0, &mut sea.scratch(), &mut forces);
    assert_eq!(forces, [0.0; 3]);
}

#[test]
fn the_drift_is_zero_before_the_start_and_ramps_as_r_squared() {
    let params = WaveParams {
        kind: WaveKind::Regular,
        height: 2.0,
        period: 7.0,
        ramp: 20.0,
        ..WaveParams::default()
    };
    let sea = Sea::new(&params, None, RHO, G, 5.0)
        .unwrap()
        .with_drift(&params, &wide_table(), DriftMode::Newman, RHO, G)
        .unwrap();
    let mut scratch = sea.scratch();
    let mut forces = [f64::NAN; 3];
    for time in [-10.0, 0.0, 4.999, 5.0] {
        sea.evaluate_drift(time, &mut scratch, &mut forces);
        assert_eq!(forces, [0.0; 3], "t = {time}");
    }
    sea.evaluate_drift(15.0, &mut scratch, &mut forces);
    let r = sea.ramp_factor(15.0);
    assert!((r - 0.5).abs() < 1e-15);
    assert!((forces[0] - r * r * sea.mean_drift(0)).abs() <= 1e-12 * sea.mean_drift(0));
}

/// Per batch, the time mean of the Newman sway drift and of its square, sampled every `dt`.
fn batch_moments(sea: &Sea, batches: usize, batch_steps: usize, dt: f64) -> Vec<(f64, f64)> {
    let mut scratch = sea.scratch();
    let mut forces = [0.0; 3];
    (0..batches)
        .map(|b| {
            let (mut sum, mut sum2) = (0.0, 0.0);
            for k in 0..batch_steps {
                let time = (b * batch_steps + k) as f64 * dt;
                sea.evaluate_drift(time, &mut scratch, &mut forces);
                sum += forces[0];
                sum2 += forces[0] * forces[0];
            }
            (sum / batch_steps as f64, sum2 / batch_steps as f64)
        })
        .collect()
}

/// The mean and the standard error of the mean of batch values.
fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let count = values.len() as f64;
    let mean = values.iter().sum::<f64>() / count;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (count - 1.0);
    (mean, (variance / count).sqrt())
}

#[test]
fn a_jonswap_records_mean_and_slow_drift_variance_are_newmans() {
    let params = WaveParams {
        kind: WaveKind::Jonswap,
        height: 4.0,
        period: 8.0,
        components: 64,
        seed: 7,
        ..WaveParams::default()
    };
    let sea = sea_with_drift(&params, DriftMode::Newman);
    let a = sea.amplitudes();
    let d: Vec<f64> = sea.frequencies().iter().map(|&w| drift_si(0, w)).collect();
    let mean: f64 = a.iter().zip(&d).map(|(a, d)| a * a * d).sum();
    assert!((sea.mean_drift(0) - mean).abs() <= 1e-12 * mean);
    // Variance of F - mean over time: sum over n != m of a_n^2 a_m^2 T_nm^2.
    let mut variance = 0.0;
    for n in 0..a.len() {
        for m in (0..a.len()).filter(|&m| m != n) {
            let t = 0.5 * (d[n] + d[m]);
            variance += (a[n] * a[m] * t).powi(2);
        }
    }
    // 40 batches of 4000 s sampled every 0.5 s.
    let moments = batch_moments(&sea, 40, 8000, 0.5);
    let means: Vec<f64> = moments.iter().map(|m| m.0).collect();
    let (record_mean, mean_error) = mean_and_error(&means);
    let variances: Vec<f64> = moments.iter().map(|m| m.1 - m.0 * m.0).collect();
    let (record_variance, variance_error) = mean_and_error(&variances);
    eprintln!(
        "mean drift: record {record_mean:.2} +- {mean_error:.2}, sum a_n^2 d_n {mean:.2}; \
         slow-drift variance: record {record_variance:.1} +- {variance_error:.1}, Newman \
         {variance:.1}"
    );
    assert!(mean_error < 0.02 * mean, "{mean_error} {mean}");
    assert!((record_mean - mean).abs() <= 3.0 * mean_error);
    // Within a batch the variance misses the periods longer than the batch: a small bias,
    // bounded here with the statistical error.
    assert!(
        variance_error < 0.05 * variance,
        "{variance_error} {variance}"
    );
    assert!(
        (record_variance - variance).abs() <= 3.0 * variance_error + 0.02 * variance,
        "{record_variance} {variance}"
    );
    // The mean mode gives the constant.
    let mean_sea = sea_with_drift(&params, DriftMode::Mean);
    let mut forces = [0.0; 3];
    mean_sea.evaluate_drift(123.0, &mut mean_sea.scratch(), &mut forces);
    assert_eq!(forces[0], mean_sea.mean_drift(0));
}

#[test]
fn the_mean_drift_over_seeds_is_twice_the_integral_of_s_times_d() {
    let (hs, tp, gamma) = (4.0, 8.0, 3.3);
    let wp = 2.0 * std::f64::consts::PI / tp;
    let (low, high) = (0.5 * wp, 6.0 * wp);
    let steps = 20_000;
    let h = (high - low) / steps as f64;
    let integrand = |w: f64| 2.0 * jonswap(w, hs, tp, gamma) * drift_si(0, w);
    let quadrature = h
        * (0.5 * (integrand(low) + integrand(high))
            + (1..steps)
                .map(|i| integrand(low + i as f64 * h))
                .sum::<f64>());
    let per_seed: Vec<f64> = (1..=24)
        .map(|seed| {
            let params = WaveParams {
                kind: WaveKind::Jonswap,
                height: hs,
                period: tp,
                gamma,
                components: 64,
                seed,
                ..WaveParams::default()
            };
            sea_with_drift(&params, DriftMode::Mean).mean_drift(0)
        })
        .collect();
    let (mean, error) = mean_and_error(&per_seed);
    eprintln!(
        "mean drift over 24 seeds: {mean:.3} +- {error:.3}; 2 int S D: {quadrature:.3}; one \
         seed's spread {:.3}",
        error * (per_seed.len() as f64).sqrt()
    );
    assert!(error < 0.01 * quadrature, "{error} {quadrature}");
    assert!((mean - quadrature).abs() <= 3.0 * error + 1e-6 * quadrature);
}

#[test]
fn the_drift_rate_is_the_derivative_of_the_drift() {
    let params = WaveParams {
        kind: WaveKind::Jonswap,
        height: 3.0,
        period: 9.0,
        components: 16,
        ramp: 30.0,
        ..WaveParams::default()
    };
    for mode in [DriftMode::Mean, DriftMode::Newman] {
        let sea = sea_with_drift(&params, mode);
        let (time, h) = (12.0, 1e-4);
        let mut rate = [0.0; 3];
        sea.evaluate_drift_rate(time, &mut rate);
        let (mut before, mut after) = ([0.0; 3], [0.0; 3]);
        sea.evaluate_drift(time - h, &mut sea.scratch(), &mut before);
        sea.evaluate_drift(time + h, &mut sea.scratch(), &mut after);
        for j in 0..3 {
            let difference = (after[j] - before[j]) / (2.0 * h);
            let scale = sea.mean_drift(j).abs().max(1.0);
            assert!(
                (rate[j] - difference).abs() <= 1e-6 * scale,
                "{mode:?} {j}: {} vs {difference}",
                rate[j]
            );
        }
        assert!(rate[0].abs() > 1.0, "{mode:?}: {}", rate[0]);
    }
}
