//! An archive with a drift table: its resources, variables, GUID and description.

use super::*;
use crate::fmu::inspect::{inspect, read_entry};
use crate::panels::PanelParams;
use crate::sweep::{self, SweepParams};

const SEED: &str = include_str!("../../../examples/networks/seed_2dof.xml");

/// The semicircle (R = 1 m) section in sway, with its exciting force and, when asked, its
/// drift from a small sweep.
fn section(drift: bool) -> Body {
    let hull = Hull::semicircle(1.0)
        .unwrap()
        .select_dofs(&["sway", "roll"])
        .unwrap();
    let params = SweepParams {
        kr: vec![0.3, 1.0, 3.0],
        panels: PanelParams {
            body_panels: 32,
            ..PanelParams::default()
        },
        ..SweepParams::default()
    };
    let result = sweep::run(&hull, &params, &|_, _| {}).unwrap();
    let names = ["sway".to_string()];
    let body = Body::section(&hull)
        .with_sweep_excitation(&result, &names)
        .unwrap();
    if drift {
        body.with_sweep_drift(&result, &names).unwrap()
    } else {
        body
    }
}

fn build(body: Body, fmi: FmiVersion) -> Packed {
    let network = PackedNetwork::from_text(SEED.to_string(), "seed").unwrap();
    let mut archive = Archive::new(body, network, "M", b"\x7fELF fake".to_vec());
    archive.fmi = fmi;
    archive.build().unwrap()
}

/// `(name, valueReference)` of every variable of a model description.
fn references(description: &str) -> Vec<(String, String)> {
    let root = crate::xml::parse(description).unwrap();
    root.descendants()
        .filter_map(|e| {
            Some((
                e.attribute("name")?.to_string(),
                e.attribute("valueReference")?.to_string(),
            ))
        })
        .collect()
}

fn description(packed: &Packed) -> String {
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(packed.bytes.clone())).unwrap();
    read_entry(&mut zip, "modelDescription.xml")
        .unwrap()
        .unwrap()
}

#[test]
fn a_drift_table_adds_its_resource_and_two_variables_after_all_others() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-drift-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for fmi in [FmiVersion::V2, FmiVersion::V3] {
        let plain = build(section(false), fmi);
        let drift = build(section(true), fmi);
        assert_ne!(plain.guid, drift.guid);
        let (before, after) = (description(&plain), description(&drift));
        let (before, after) = (references(&before), references(&after));
        // Every variable keeps its value reference; force_drift.sway and wave.drift follow.
        assert_eq!(after.len(), before.len() + 2);
        assert_eq!(after[..before.len()], before[..]);
        let largest = before
            .iter()
            .map(|(_, vr)| vr.parse::<u32>().unwrap())
            .max()
            .unwrap();
        let names: Vec<&str> = after[before.len()..]
            .iter()
            .map(|(n, _)| n.as_str())
            .collect();
        assert_eq!(names, ["force_drift.sway", "wave.drift"]);
        for (_, vr) in &after[before.len()..] {
            assert!(vr.parse::<u32>().unwrap() > largest);
        }
        let text = description(&drift);
        match fmi {
            FmiVersion::V2 => assert!(text.contains("<Integer start=\"0\" min=\"0\" max=\"2\"/>")),
            FmiVersion::V3 => assert!(text.contains("<Int32 name=\"wave.drift\"")),
        }
        let path = dir.join(format!("drift-{}.fmu", fmi.platform()));
        drift.write(&path).unwrap();
        let found = inspect(&path).unwrap();
        assert!(found.drift && found.to_string().contains("drift "));
        assert!(found.entries.contains(&"resources/drift.csv".to_string()));
        assert_eq!(found.resources_guid, drift.guid);
        let plain_path = dir.join(format!("plain-{}.fmu", fmi.platform()));
        plain.write(&plain_path).unwrap();
        let found = inspect(&plain_path).unwrap();
        assert!(!found.drift && !found.to_string().contains("drift "));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_sweep_without_the_dofs_gives_no_drift_table() {
    let hull = Hull::semicircle(1.0).unwrap();
    let params = SweepParams {
        kr: vec![0.5, 1.0],
        panels: PanelParams {
            body_panels: 24,
            ..PanelParams::default()
        },
        ..SweepParams::default()
    };
    let result = sweep::run(&hull, &params, &|_, _| {}).unwrap();
    let err = Body::section(&hull)
        .with_sweep_drift(&result, &["surge".to_string()])
        .unwrap_err();
    assert!(err.to_string().contains("surge"), "{err}");
}
