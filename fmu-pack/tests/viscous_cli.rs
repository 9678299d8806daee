//! `fmu-pack pack --viscous`: the coefficients reach `resources/viscous.csv` and the model
//! description's start values; without the flag the archive is as before; bad values are
//! refused naming the option.

use hydrofmu::fmu::Quantity;
use hydrofmu::fmu::Resources;
use hydrofmu::model::Model;
use std::path::{Path, PathBuf};

mod common;
use common::fmu_pack;

fn entry(archive: &Path, name: &str) -> Option<String> {
    common::archive_member(archive, name)
}

fn network() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/networks/two-dof-sway-heave.xml")
        .display()
        .to_string()
}

fn pack(dir: &Path, name: &str, extra: &[&str]) -> (bool, PathBuf, String) {
    let archive = dir.join(name);
    let network = network();
    let mut args = vec![
        "pack",
        "semicircle",
        "--dofs",
        "sway,heave",
        "--network",
        network.as_str(),
        "-o",
        archive.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (ok, _, err) = fmu_pack(&args);
    (ok, archive, err)
}

#[test]
fn the_coefficients_are_packed_and_bad_ones_refused() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-viscous-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (ok, plain, err) = pack(&dir, "Plain.fmu", &[]);
    assert!(ok, "{err}");
    assert!(entry(&plain, "resources/viscous.csv").is_none());
    let description = entry(&plain, "modelDescription.xml").unwrap();
    assert!(!description.contains("current.speed") && !description.contains("kg/m2"));

    let flags = [
        "--viscous",
        "--damping-linear",
        "sway=120,heave=30,heave,sway=5,sway,heave=5",
        "--damping-quadratic",
        "sway=800",
    ];
    let (ok, damped, err) = pack(&dir, "Damped.fmu", &flags);
    assert!(ok, "{err}");
    let text = entry(&damped, "resources/viscous.csv").unwrap();
    let resources = Resources::new(
        entry(&damped, "resources/network.xml").unwrap(),
        entry(&damped, "resources/hull.xml"),
        entry(&damped, "resources/options.xml").unwrap(),
    )
    .unwrap()
    .with_viscous(Some(text));
    let mut model = Model::from_resources(&resources).unwrap();
    assert_eq!(model.value(Quantity::DampingLinear(0, 0)).unwrap(), 120.0);
    assert_eq!(model.value(Quantity::DampingLinear(1, 0)).unwrap(), 5.0);
    assert_eq!(model.value(Quantity::DampingQuadratic(0)).unwrap(), 800.0);
    // Heave not given: the semicircle's cross-flow drag estimate, 0.5 rho C_D B.
    let heave =
        hydrofmu::viscous::section_drag(&hydrofmu::hull::Hull::semicircle(1.0).unwrap(), 1025.0)
            .unwrap()[1]
            .quadratic;
    assert_eq!(model.value(Quantity::DampingQuadratic(1)).unwrap(), heave);
    let description = entry(&damped, "modelDescription.xml").unwrap();
    for name in [
        "current.speed",
        "current.heading",
        "force_viscous.sway",
        "damping_linear[2,1]",
        "damping_quadratic[1]",
        "<Unit name=\"kg/m2\">",
    ] {
        assert!(description.contains(name), "{name}");
    }
    assert!(description.contains("start=\"800.0\""));

    let bad = [
        (
            &["--viscous", "--damping-quadratic", "sway=-1"][..],
            "damping_quadratic[1]",
        ),
        (
            &["--viscous", "--damping-linear", "roll=1"][..],
            "'roll' is not a DOF",
        ),
        (
            &["--viscous", "--damping-linear", "sway,heave=9"][..],
            "positive semidefinite",
        ),
        (&["--damping-linear", "sway=1"][..], "--viscous"),
    ];
    for (flags, expected) in bad {
        let (ok, archive, err) = pack(&dir, "Bad.fmu", flags);
        assert!(!ok && err.contains(expected), "{flags:?}: {err}");
        assert!(!archive.exists());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
