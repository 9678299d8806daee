//! The water depth in the component: the tables' `# depth:` line, one depth for the excitation
//! and drift tables, the fixed parameter `depth`, and a sea that does not depend on it.

use super::drift_tests::TWO_DOF_DRIFT;
use super::tests::{TWO_DOF_EXCITATION, TWO_DOF_NETWORK};
use super::*;
use crate::fmu::description::{DescriptionInfo, FIXED_XML};
use crate::fmu::variables::{WaveParameter, VR_DEPTH};

/// `text` with `# depth: <value>` after its `# R:` line (R = 2 m in both two-DOF tables).
fn at_depth(text: &str, value: &str) -> String {
    text.replacen("# R: 2 m\n", &format!("# R: 2 m\n# depth: {value}\n"), 1)
}

fn resources(excitation: String, drift: Option<String>) -> Resources {
    Resources::new(TWO_DOF_NETWORK.into(), None, Resources::options_text(false))
        .unwrap()
        .with_excitation(Some(excitation))
        .with_drift(drift)
}

#[test]
fn the_tables_depth_line_is_read_and_deep_water_without_it() {
    let x = |text: &str| ExcitationTable::from_csv_str(text, "x.csv");
    let d = |text: &str| DriftTable::from_csv_str(text, "d.csv");
    assert_eq!(x(TWO_DOF_EXCITATION).unwrap().depth(), WaterDepth::Infinite);
    assert_eq!(d(TWO_DOF_DRIFT).unwrap().depth(), WaterDepth::Infinite);
    let deep = x(&at_depth(TWO_DOF_EXCITATION, "inf")).unwrap();
    assert_eq!(deep.depth(), WaterDepth::Infinite);
    assert_eq!(deep, x(TWO_DOF_EXCITATION).unwrap());
    // h/R = 2.5 with R = 2 m: h = 5 m.
    let finite = x(&at_depth(TWO_DOF_EXCITATION, "2.5")).unwrap();
    assert_eq!(finite.depth(), WaterDepth::Finite(5.0));
    assert_eq!(
        d(&at_depth(TWO_DOF_DRIFT, "2.5")).unwrap().depth(),
        WaterDepth::Finite(5.0)
    );
    // A depth line before the `# R:` line reads the same.
    let before = TWO_DOF_EXCITATION.replacen("# modes:", "# depth: 2.5\n# modes:", 1);
    assert_eq!(x(&before).unwrap().depth(), WaterDepth::Finite(5.0));
}

#[test]
fn a_bad_depth_line_is_refused_with_file_line_and_reason() {
    let x = |text: &str| {
        ExcitationTable::from_csv_str(text, "x.csv")
            .unwrap_err()
            .to_string()
    };
    for bad in ["0", "-1", "nan", "deep", "", "1e999"] {
        let e = x(&at_depth(TWO_DOF_EXCITATION, bad));
        assert!(e.starts_with("x.csv:4: `# depth:"), "{bad}: {e}");
    }
    let e = DriftTable::from_csv_str(&at_depth(TWO_DOF_DRIFT, "-2"), "d.csv")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("d.csv:4:") && e.contains("finite and > 0"),
        "{e}"
    );
    let twice = at_depth(&at_depth(TWO_DOF_EXCITATION, "2"), "2");
    assert!(x(&twice).contains("repeated `# depth:` line"));
    let late = format!("{TWO_DOF_EXCITATION}# depth: 2\n");
    assert!(x(&late).contains("header line after the column line"));
}

#[test]
fn excitation_and_drift_tables_of_different_depths_are_refused_naming_both() {
    for (x_depth, d_depth) in [("2.5", "inf"), ("inf", "3"), ("2.5", "3")] {
        let r = resources(
            at_depth(TWO_DOF_EXCITATION, x_depth),
            Some(at_depth(TWO_DOF_DRIFT, d_depth)),
        );
        let e = Model::from_resources(&r).unwrap_err().to_string();
        assert!(
            e.contains("resources/excitation.csv") && e.contains("resources/drift.csv"),
            "{e}"
        );
    }
    // Absent and `inf` are the same depth.
    let r = resources(
        TWO_DOF_EXCITATION.into(),
        Some(at_depth(TWO_DOF_DRIFT, "inf")),
    );
    assert_eq!(
        Model::from_resources(&r).unwrap().depth(),
        WaterDepth::Infinite
    );
    let r = resources(
        at_depth(TWO_DOF_EXCITATION, "2.5"),
        Some(at_depth(TWO_DOF_DRIFT, "2.5")),
    );
    assert_eq!(
        Model::from_resources(&r).unwrap().depth(),
        WaterDepth::Finite(5.0)
    );
}

#[test]
fn a_finite_depth_fmu_declares_depth_last_and_accepts_only_its_value() {
    let deep = Model::from_resources(&resources(TWO_DOF_EXCITATION.into(), None)).unwrap();
    let deep_layout = deep.layout().unwrap();
    assert_eq!(deep_layout.value_reference(Quantity::Depth), None);
    assert_eq!(deep_layout.quantity(VR_DEPTH), None);
    assert!(deep.check_depth(10.0).is_err());

    let mut m =
        Model::from_resources(&resources(at_depth(TWO_DOF_EXCITATION, "2.5"), None)).unwrap();
    let layout = m.layout().unwrap();
    // Declared after every other variable: no value reference or index moves.
    let last = layout.variables().last().unwrap();
    assert_eq!(
        (last.name.as_str(), last.value_reference),
        ("depth", VR_DEPTH)
    );
    assert_eq!(last.start, Some(5.0));
    assert_eq!(
        &layout.variables()[..layout.variables().len() - 1],
        deep_layout.variables()
    );
    assert_eq!(layout.quantity(VR_DEPTH), Some(Quantity::Depth));
    assert_eq!(m.value(Quantity::Depth).unwrap(), 5.0);
    m.set_value(Quantity::Depth, 5.0).unwrap();
    let e = m.set_value(Quantity::Depth, 7.0).unwrap_err().to_string();
    assert!(
        e.contains("depth = 7 m") && e.contains("depth = 5 m"),
        "{e}"
    );
    // The model description declares it with its start value, in FMI 2.0 and 3.0.
    let info = DescriptionInfo {
        model_identifier: "m".into(),
        guid: m.guid().into(),
        ..Default::default()
    };
    let two = layout.model_description(FIXED_XML, &info).unwrap();
    assert!(two.contains("name=\"depth\" valueReference=\"98\""));
    assert!(two.contains("<Real start=\"5.0\" unit=\"m\"/>"));
    let three = layout.model_description_fmi3(FIXED_XML, &info).unwrap();
    assert!(three.contains("name=\"depth\" valueReference=\"98\""));
    assert!(!deep_layout
        .model_description(FIXED_XML, &info)
        .unwrap()
        .contains("\"depth\""));
}

/// Every output after 200 steps of 0.1 s in a JONSWAP sea, as bits.
fn jonswap_record(excitation: String) -> Vec<u64> {
    let mut m = Model::from_resources(&resources(excitation, None)).unwrap();
    m.set_wave_integer(WaveParameter::Kind, 2).unwrap();
    m.set_wave_real(WaveParameter::Height, 2.0).unwrap();
    m.set_wave_real(WaveParameter::Period, 6.0).unwrap();
    m.set_start_time(0.0).unwrap();
    m.start_waves().unwrap();
    let mut bits = Vec::new();
    for k in 0..200 {
        m.set_value(Quantity::Velocity(0), (0.3 * k as f64).sin())
            .unwrap();
        m.step(m.time(), 0.1).unwrap();
        for q in [
            Quantity::Force(0),
            Quantity::Force(1),
            Quantity::WaveElevation,
        ] {
            bits.push(m.value(q).unwrap().to_bits());
        }
    }
    bits
}

#[test]
fn the_sea_depends_on_the_depth_only_through_the_tables() {
    // The elevation at x = 0 and the spectrum in omega do not involve k; the same tables
    // marked for another depth give the same record, bit for bit.
    let deep = jonswap_record(TWO_DOF_EXCITATION.into());
    let finite = jonswap_record(at_depth(TWO_DOF_EXCITATION, "2.5"));
    assert_eq!(deep, finite);
    assert!(deep.iter().any(|b| f64::from_bits(*b).abs() > 1.0));
}
