//! One number of network states: `pack`'s summary, `inspect`, the archive's
//! `documentation/scene.txt` and the instance's log all give the length of the state vector
//! the FMU steps.

use hydrofmu::fmu::Resources;
use hydrofmu::model::Model;

mod common;
use common::fmu_pack;

/// The number after `label` on the first line that starts (after spaces) with it.
fn number_after(text: &str, label: &str) -> usize {
    let line = text
        .lines()
        .map(str::trim_start)
        .find(|l| l.starts_with(label))
        .unwrap_or_else(|| panic!("no '{label}' in\n{text}"));
    line[label.len()..].trim().parse().unwrap()
}

fn entry(archive: &std::path::Path, name: &str) -> String {
    common::archive_member(archive, name).unwrap()
}

#[test]
fn summary_inspect_scene_and_log_give_the_state_vector_length() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-states-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let archive = dir.join("Three.fmu");
    // Three DOFs: the fit has substructures with fewer springs than masses, so twice the
    // auxiliary DOFs is not the state count.
    let (ok, summary, err) = fmu_pack(&[
        "pack",
        "semicircle",
        "--dofs",
        "sway,heave,roll",
        "--panels",
        "16",
        "--kr",
        "0.05:5:12",
        "-o",
        archive.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let resources = Resources::new(
        entry(&archive, "resources/network.xml"),
        Some(entry(&archive, "resources/hull.xml")),
        entry(&archive, "resources/options.xml"),
    )
    .unwrap();
    let model = Model::from_resources(&resources).unwrap();
    let states = model.state().network.len();
    let network = hydrofmu::network::Network::from_xml_str(&resources.network_xml, "n").unwrap();
    assert_eq!(network.state_count(), states);
    assert_ne!(
        states,
        2 * network.aux_dof_count(),
        "not the case this test is for"
    );
    assert_eq!(model.network_states(), states);
    assert_eq!(
        number_after(&summary, "network states"),
        states,
        "{summary}"
    );
    let scene = entry(&archive, "documentation/scene.txt");
    assert_eq!(number_after(&scene, "network states"), states, "{scene}");
    let (ok, inspected, err) = fmu_pack(&["inspect", archive.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert_eq!(number_after(&inspected, "network states"), states);
    assert_eq!(
        inspected.matches("network states").count(),
        2,
        "once for the archive, once in its scene: {inspected}"
    );
    assert!(!inspected.contains("state size"), "{inspected}");
    let mut instance = hydrofmu::fmi::Instance::from_resources(c"log", &resources, true).unwrap();
    let log: Vec<String> = instance
        .take_messages()
        .into_iter()
        .map(|m| m.text)
        .collect();
    let expected = format!("{states} network states");
    assert!(log.iter().any(|l| l.ends_with(&expected)), "{log:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
