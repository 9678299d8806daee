//! Tests of the drift table and of the sea's drift forces.

use super::*;
use crate::hull::Hull;
use crate::panels::PanelParams;
use crate::sweep::{self, SweepParams};

/// A small drift table: sway `0.5 kR / (1 + kR)` (heading 0; minus at 180), heave 0, roll
/// `0.1 kR` (heading 0; minus at 180), at kR 0.2, 0.5, 1, 2.
fn drift_text() -> String {
    let mut text = "# hull: synthetic\n# modes: sway heave roll\n# convention: exp(+i omega t)\n\
                    # R: 2 m\n# length exponents: 0 0 1\nkR,j,heading,value\n"
        .to_string();
    for kr in [0.2, 0.5, 1.0, 2.0] {
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
