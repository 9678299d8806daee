//! The fixed 2D ship section of Sundsdal, Greco, Hanssen and Lugni (2025) in regular beam
//! waves: our exciting forces and mean drift in the flume's 1.0 m of water against its
//! measurements (`tests/data/sundsdal/scenario_A.csv`, processed from the public raw data, CC0),
//! at every frequency.

use hydrofmu::hull::Hull;
use hydrofmu::sweep::{self, SweepParams};
use hydrofmu::units::WaterDepth;

struct Row {
    xi: f64,
    h_over_lambda: f64,
    fy: f64,
    fz: f64,
    drift_y: f64,
    steepness: f64,
    drift_z: f64,
}

fn measurements() -> Vec<Row> {
    let text = include_str!("data/sundsdal/scenario_A.csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (xi, hl, fy, fz, dy, dz, ka) = (
        column("xi_B"),
        column("h_over_lambda"),
        column("Fy_amp"),
        column("Fz_amp"),
        column("Fy_mean_coef"),
        column("Fz_mean_coef"),
        column("steepness_ka"),
    );
    lines
        .map(|line| {
            let v: Vec<f64> = line
                .split(',')
                .map(|x| x.parse().unwrap_or(f64::NAN))
                .collect();
            Row {
                xi: v[xi],
                h_over_lambda: v[hl],
                fy: v[fy],
                fz: v[fz],
                drift_y: v[dy],
                drift_z: v[dz],
                steepness: v[ka],
            }
        })
        .collect()
}

/// The flume's water depth (m; the section's half-beam R is 0.2 m: h/R = 5): ours is solved in
/// it at every frequency. Waves below this steepness `k a` are linear (the data's README).
const FLUME_DEPTH: f64 = 1.0;
const STEEP: f64 = 0.1;
/// Below this depth-to-wavelength ratio (xi_B < 0.65) the fixed model's runs are single and
/// their mean sway force scatters: compared more loosely, and as a band.
const LONG_WAVES: f64 = 0.5;

/// `(Fy, Fz) / (rho g a B L)` and the mean `(Fy, Fz) / (rho g a^2 L / 2)` at each `xi_B = kR`.
fn ours(kr: &[f64], depth: WaterDepth) -> Vec<[f64; 4]> {
    let text = include_str!("../examples/hulls/sundsdal.xml");
    let hull = Hull::from_xml_str(text, "sundsdal.xml").unwrap();
    let params = SweepParams {
        kr: kr.to_vec(),
        depth,
        ..SweepParams::default()
    };
    let result = sweep::run(&hull, &params, &|_, _| {}).unwrap();
    result
        .excitation
        .iter()
        .map(|forces| {
            let mean = forces.drift.as_ref().unwrap().mean_drift();
            // X / (rho g a R) -> F / (rho g a B); D / (rho g) -> F / (rho g a^2 L / 2).
            [
                forces.direct[(0, 0)].norm() / 2.0,
                forces.direct[(1, 0)].norm() / 2.0,
                2.0 * mean[(0, 0)],
                2.0 * mean[(1, 0)],
            ]
        })
        .collect()
}

#[test]
fn exciting_forces_and_mean_sway_force_agree_with_the_flume_at_every_frequency() {
    let rows = measurements();
    let mut kr: Vec<f64> = rows.iter().map(|r| r.xi).collect();
    kr.dedup();
    let flume = ours(&kr, WaterDepth::Finite(FLUME_DEPTH));
    let deep = ours(&kr, WaterDepth::Infinite);
    let (mut long_measured, mut long_ours, mut long_count) = (0.0, 0.0, 0.0);
    let mut compared = 0;
    for row in &rows {
        let i = kr.iter().position(|k| *k == row.xi).unwrap();
        let [fy, fz, mean_y, mean_z] = flume[i];
        // The sign of the mean vertical force (down) at every frequency, ours and measured.
        assert!(mean_z < 0.0 && row.drift_z < 0.0, "xi {}", row.xi);
        if row.steepness >= STEEP {
            continue;
        }
        compared += 1;
        // Measured: within 2.9 % (xi_B 0.35, a single run; 1.5 % from xi_B 0.5 on);
        // repeatability 0.75 %, wave calibration 1.3 % rms.
        assert!(
            (fy / row.fy - 1.0).abs() <= 0.035,
            "xi {}: Fy {fy} {}",
            row.xi,
            row.fy
        );
        // Measured: ours 0.936 .. 1.007 of the flume's (its heave gain bias, README; deep
        // water gives 0.964 at xi_B 0.35, the depth takes the bias away there).
        let ratio = fz / row.fz;
        assert!(
            (0.92..=1.02).contains(&ratio),
            "xi {}: Fz ratio {ratio}",
            row.xi
        );
        let difference = (mean_y - row.drift_y).abs();
        if row.h_over_lambda >= LONG_WAVES {
            // Measured: within 0.062 (the repetitions scatter by up to 0.085).
            assert!(
                difference <= 0.08,
                "xi {}: mean Fy {mean_y} {}",
                row.xi,
                row.drift_y
            );
        } else {
            // Single runs, scattered both sides of ours (0.74 .. 0.99 measured where ours
            // rises smoothly from 0.84 to 0.92): measured 0.29 at most (xi_B 0.35), the band's
            // mean below.
            assert!(
                difference <= 0.32,
                "xi {}: mean Fy {mean_y} {}",
                row.xi,
                row.drift_y
            );
            long_measured += row.drift_y;
            long_ours += mean_y;
            long_count += 1.0;
        }
    }
    assert_eq!(compared, 15);
    // The long waves' mean: measured 0.861, ours 0.834 (deep water 0.816).
    let band = (long_measured - long_ours) / long_count;
    assert!(band.abs() <= 0.05, "long waves, mean Fy: {band}");
    // The depth's share at the longest wave (xi_B 0.35, h/lambda 0.29, kh 1.84): measured
    // Fy +2.6 %, Fz +4.5 %, mean Fy +0.036 over deep water; none from xi_B 1.0 (kh 5) on
    // for the sway force and its mean (below 0.3 %).
    let [deep_fy, deep_fz, deep_mean, _] = deep[0];
    let [fy, fz, mean, _] = flume[0];
    assert!(
        (0.02..=0.035).contains(&(fy / deep_fy - 1.0)),
        "{fy} {deep_fy}"
    );
    assert!(
        (0.035..=0.055).contains(&(fz / deep_fz - 1.0)),
        "{fz} {deep_fz}"
    );
    assert!(
        (0.025..=0.05).contains(&(mean - deep_mean)),
        "{mean} {deep_mean}"
    );
    for (i, xi) in kr.iter().enumerate().filter(|(_, xi)| **xi >= 1.0) {
        assert!((flume[i][0] / deep[i][0] - 1.0).abs() <= 3e-3, "xi {xi}");
        assert!((flume[i][2] - deep[i][2]).abs() <= 3e-3, "xi {xi}");
    }
}
