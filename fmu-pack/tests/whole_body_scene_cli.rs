//! One scene for every source: a ship file and an imported database get `fit --form`, the
//! scene report on standard output and in the archive's `documentation/scene.txt`.

use std::path::{Path, PathBuf};

mod common;
use common::{fmu_pack, wamit_sphere as sphere};

fn barge() -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/ships/barge.xml")
        .display()
        .to_string()
}

fn entry(archive: &Path, name: &str) -> String {
    common::archive_member(archive, name).unwrap()
}

#[test]
fn fit_takes_the_coupled_form_for_several_dofs_of_a_database() {
    let (ok, out, err) = fmu_pack(&[
        "fit",
        &sphere(),
        "--dofs",
        "heave,surge",
        "--form",
        "coupled",
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("\nnetwork: coupled, order "), "{out}");
    // The fit in words, then the scene report with the DOFs left out.
    assert!(
        out.contains("\n\nDOFs modelled      heave surge\nDOFs left out      4 "),
        "{out}"
    );
    assert!(
        out.contains("\n  pitch      coupling to the modelled DOFs up to "),
        "{out}"
    );
    let (ok, json, err) = fmu_pack(&[
        "fit",
        &sphere(),
        "--dofs",
        "heave",
        "--form",
        "series_chain",
        "--json",
    ]);
    assert!(ok, "{err}");
    assert!(
        json.starts_with("{\"dofs\":[\"heave\"],\"form\":\"series_chain\""),
        "{json}"
    );
}

#[test]
fn one_dof_forms_are_refused_for_several_dofs_naming_the_count() {
    let (ok, _, err) = fmu_pack(&["fit", &sphere(), "--form", "parallel_bank"]);
    assert!(!ok);
    assert!(
        err.contains("--form parallel_bank: a one-DOF form, and the body has 6 DOFs to fit"),
        "{err}"
    );
    // A ship's is refused before its sweep.
    let (ok, _, err) = fmu_pack(&[
        "fit",
        &barge(),
        "--dofs",
        "heave,pitch",
        "--form",
        "series_chain",
    ]);
    assert!(!ok);
    assert!(err.contains("the body has 2 DOFs to fit"), "{err}");
    assert!(!err.contains("ship sweep"), "{err}");
    let (ok, _, err) = fmu_pack(&["fit", &sphere(), "--form", "ladder"]);
    assert!(
        !ok && err.contains("--form 'ladder': expected series_chain"),
        "{err}"
    );
}

#[test]
fn the_archive_of_a_database_holds_its_scene_report() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-body-scene-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let binary = common::stand_in_binary(&dir);
    let archive = dir.join("Sphere.fmu");
    let (ok, summary, err) = fmu_pack(&[
        "pack",
        &sphere(),
        "--dofs",
        "heave,surge",
        "--binary",
        binary.to_str().unwrap(),
        "-o",
        archive.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let scene = entry(&archive, "documentation/scene.txt");
    assert!(
        scene.starts_with("DOFs modelled      heave surge\n"),
        "{scene}"
    );
    assert!(scene.contains("\nerror in the band  "), "{scene}");
    assert!(
        scene.contains("\n\ndatabase sphere: 2 DOFs (heave surge)"),
        "{scene}"
    );
    assert!(scene.contains("\nlargest error "), "{scene}");
    // The summary shows the scene report under the fit's line.
    assert!(
        summary.contains("\n  scene\n    DOFs modelled      heave surge\n"),
        "{summary}"
    );
    let index = entry(&archive, "documentation/index.html");
    assert!(
        index.contains("<h2>Scene: what this FMU models and leaves out</h2>"),
        "{index}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
