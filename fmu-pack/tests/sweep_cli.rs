//! `fmu-pack sweep` from the command line: the CSV of docs/DESIGN.md and clear errors.

mod common;
use common::fmu_pack;

#[test]
fn sweep_writes_the_coefficient_table() {
    let (ok, csv, err) = fmu_pack(&[
        "sweep",
        "semicircle",
        "--panels",
        "32",
        "--kr",
        "0.5:1:3",
        "--dofs",
        "sway,heave",
        "-o",
        "-",
    ]);
    assert!(ok, "{err}");
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("# hull: semicircle"));
    assert_eq!(lines.next(), Some("# H/R: 0"));
    assert_eq!(lines.next(), Some("# modes: sway heave"));
    assert_eq!(lines.next(), Some("# convention: exp(+i omega t)"));
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("kR"))
        .map(|l| l.split(',').collect())
        .collect();
    assert!(csv.lines().any(|l| l == "kR,i,j,re,im"));
    // A(0): sway-sway and the sway-heave pair are finite; heave-heave diverges and is left out.
    let zero: Vec<_> = rows.iter().filter(|r| r[0] == "0").collect();
    assert_eq!(zero.len(), 3, "{zero:?}");
    assert!(!zero.iter().any(|r| r[1] == "2" && r[2] == "2"));
    // 3 frequencies x 4 entries, and 4 A_inf rows.
    assert_eq!(
        rows.iter().filter(|r| r[0] != "0" && r[0] != "inf").count(),
        12
    );
    assert_eq!(rows.iter().filter(|r| r[0] == "inf").count(), 4);
    // Damping is positive on the diagonal: Im A~ <= 0.
    for r in rows
        .iter()
        .filter(|r| r[0] != "0" && r[0] != "inf" && r[1] == r[2])
    {
        assert!(r[4].parse::<f64>().unwrap() < 0.0, "{r:?}");
    }
}

#[test]
fn bad_parameters_get_clear_errors() {
    let cases: [(&[&str], &str); 6] = [
        (
            &["sweep", "semicircle", "--panels", "3", "-o", "-"],
            "at least 4",
        ),
        (&["sweep", "semicircle", "--kr", "0:1:10", "-o", "-"], "kR"),
        (&["sweep", "semicircle", "--kr", "-1:1:10", "-o", "-"], "kR"),
        (&["sweep", "circle", "--depth", "0.5", "-o", "-"], "H/R"),
        (
            &["sweep", "semicircle", "--dofs", "sway,pitch", "-o", "-"],
            "pitch",
        ),
        (&["sweep", "no/such/hull.xml", "-o", "-"], "neither"),
    ];
    for (args, expected) in cases {
        let (ok, _, err) = fmu_pack(args);
        assert!(!ok, "{args:?} should fail");
        assert!(
            err.contains(expected),
            "{args:?}: '{err}' lacks '{expected}'"
        );
    }
}

#[test]
fn sweep_writes_the_excitation_froude_krylov_and_hydrostatics_tables() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-sweep-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let (ok, _, err) = fmu_pack(&[
        "sweep",
        "semicircle",
        "--panels",
        "32",
        "--kr",
        "0.5:1:3",
        "--dofs",
        "sway,heave",
        "-o",
        &path("added_mass.csv"),
        "--excitation",
        &path("excitation.csv"),
        "--froude-krylov",
        &path("fk.csv"),
        "--hydrostatics",
        &path("hydrostatics.csv"),
    ]);
    assert!(ok, "{err}");
    assert!(err.contains("Haskind relation agrees to"), "{err}");
    let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap();
    let rows = |text: &str| -> Vec<Vec<String>> {
        text.lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("kR") && !l.starts_with("i,"))
            .map(|l| l.split(',').map(str::to_string).collect())
            .collect()
    };
    // (kR = 0 + 3 frequencies) x 2 headings x 2 DOFs in both force tables.
    for name in ["excitation.csv", "fk.csv"] {
        let text = read(name);
        assert!(text.lines().any(|l| l == "kR,j,heading,re,im"), "{name}");
        assert_eq!(rows(&text).len(), 16, "{name}");
    }
    // The total differs from its Froude-Krylov part at a wave frequency.
    let (total, fk) = (rows(&read("excitation.csv")), rows(&read("fk.csv")));
    assert_ne!(total[5][3], fk[5][3]);
    // Hydrostatics: heave-heave 2R, sway row 0.
    let c = rows(&read("hydrostatics.csv"));
    assert_eq!(c.len(), 4);
    assert!(
        (c[3][2].parse::<f64>().unwrap() - 2.0).abs() < 1e-12,
        "{c:?}"
    );
    assert_eq!(c[0][2], "0e0");
    std::fs::remove_dir_all(&dir).ok();
}

/// The files of a folder with their bytes, sorted by name.
fn folder_contents(dir: &std::path::Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|entry| {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            let bytes = if path.is_file() {
                std::fs::read(&path).unwrap()
            } else {
                b"(folder)".to_vec()
            };
            (name, bytes)
        })
        .collect();
    files.sort();
    files
}

/// A sweep whose later output cannot be written (the WAMIT prefix's `.3` is a folder; the
/// NetCDF file in `/proc`, where nothing can be created) leaves every earlier output as it was,
/// byte for byte, and no temporary file behind.
#[test]
fn a_failing_output_leaves_the_earlier_outputs_as_they_were() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-sweep-commit-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = |name: &str| dir.join(name).to_string_lossy().into_owned();
    for name in ["added_mass.csv", "hydrostatics.csv", "slice.1", "slice.hst"] {
        std::fs::write(dir.join(name), format!("earlier {name}\n")).unwrap();
    }
    std::fs::create_dir(dir.join("slice.3")).unwrap();
    let before = folder_contents(&dir);
    let sweep = |extra: &[&str]| {
        let mut args = vec![
            "sweep",
            "semicircle",
            "--panels",
            "16",
            "--levels",
            "1",
            "--kr",
            "0.5:1:2",
            "--dofs",
            "sway,heave",
        ];
        args.extend_from_slice(extra);
        fmu_pack(&args)
    };
    let outputs = [
        "-o",
        &path("added_mass.csv"),
        "--hydrostatics",
        &path("hydrostatics.csv"),
    ];
    let prefix = path("slice");
    let (ok, _, err) = sweep(&[&outputs[..], &["--wamit", &prefix]].concat());
    assert!(!ok);
    assert!(
        err.contains(&format!("cannot write {prefix}.3: it is a folder")),
        "{err}"
    );
    assert_eq!(folder_contents(&dir), before);
    if cfg!(target_os = "linux") {
        let (ok, _, err) = sweep(&[&outputs[..], &["--netcdf", "/proc/slice.nc"]].concat());
        assert!(!ok);
        assert!(err.contains("cannot write /proc/slice.nc"), "{err}");
        assert_eq!(folder_contents(&dir), before);
    }
    // Every output written: all replaced together, no temporary file left.
    std::fs::remove_dir(dir.join("slice.3")).unwrap();
    let (ok, _, err) = sweep(&[&outputs[..], &["--wamit", &prefix]].concat());
    assert!(ok, "{err}");
    let after = folder_contents(&dir);
    let names: Vec<&str> = after.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "added_mass.csv",
            "hydrostatics.csv",
            "slice.1",
            "slice.3",
            "slice.9",
            "slice.hst"
        ]
    );
    assert!(after
        .iter()
        .all(|(_, bytes)| !bytes.starts_with(b"earlier")));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn sweep_writes_the_drift_table_of_a_section_and_refuses_it_for_an_import_without_one() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-drift-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let drift = dir.join("drift.csv");
    let (ok, _, err) = fmu_pack(&[
        "sweep",
        "semicircle",
        "--panels",
        "32",
        "--kr",
        "0.5:2:3",
        "--dofs",
        "sway,heave,roll",
        "-o",
        "-",
        "--drift",
        drift.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&drift).unwrap();
    assert!(text.contains("\n# body: fixed; "), "{text}");
    assert!(text.contains("\nkR,j,heading,value\n"), "{text}");
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip_while(|l| *l != "kR,j,heading,value")
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    // 3 frequencies x 2 headings x 3 DOFs.
    assert_eq!(rows.len(), 18);
    // Headings 0 and 180 mirror each other on the symmetric section: sway changes sign,
    // heave keeps it (the coarse mesh is symmetric too, so to rounding).
    for row in rows.iter().filter(|r| r[2] == 0.0) {
        let mirror = rows
            .iter()
            .find(|m| m[0] == row[0] && m[1] == row[1] && m[2] == 180.0)
            .unwrap();
        let sign = if row[1] == 2.0 { 1.0 } else { -1.0 };
        assert!(
            (row[3] - sign * mirror[3]).abs() <= 1e-9,
            "{row:?} {mirror:?}"
        );
    }
    // Waves towards +x push a fixed section towards +x.
    assert!(rows
        .iter()
        .all(|r| r[1] != 1.0 || r[2] != 0.0 || r[3] > 0.0));
    let _ = std::fs::remove_dir_all(&dir);
    // A ship's drift is its strip theory's (fmu-pack/tests/ship_cli.rs); an import without
    // NAME.8 or NAME.9 has none.
    let sphere = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data/wamit/sphere.1");
    let (ok, _, err) = fmu_pack(&["sweep", sphere, "-o", "-", "--drift", "-"]);
    assert!(
        !ok && err.contains("--drift: sphere has no mean drift"),
        "{err}"
    );
}

#[test]
fn a_floating_section_gets_its_motion_and_drift_tables() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-rao-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (rao, drift) = (dir.join("rao.csv"), dir.join("drift.csv"));
    let (ok, _, err) = fmu_pack(&[
        "sweep",
        "semicircle",
        "--panels",
        "32",
        "--kr",
        "0.01:2:3",
        "--dofs",
        "sway,heave,roll",
        "-o",
        "-",
        "--mass",
        "displaced",
        "--cog",
        "0,-0.2",
        "--gyradius",
        "0.3",
        "--mooring",
        "sway=100",
        "--rao",
        rao.to_str().unwrap(),
        "--drift",
        drift.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let rao = std::fs::read_to_string(&rao).unwrap();
    assert!(
        rao.contains("\n# body: floating; mass 1610.0662349647678 kg/m, centre of gravity (0, -0.2) m, radius of gyration 0.3 m, external stiffness 1,1=100; rho 1025 kg/m^3"),
        "{rao}"
    );
    let rows = |text: &str, header: &str| -> Vec<Vec<f64>> {
        text.lines()
            .skip_while(|l| *l != header)
            .skip(1)
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect()
    };
    let motion = rows(&rao, "kR,j,heading,re,im");
    // 3 frequencies x 2 headings x 3 rigid DOFs; in long waves heave rides the elevation.
    assert_eq!(motion.len(), 18);
    let heave = &motion[1];
    assert_eq!((heave[0], heave[1], heave[2]), (0.01, 2.0, 0.0));
    assert!((heave[3].hypot(heave[4]) - 1.0).abs() < 1e-3, "{heave:?}");
    let drift = std::fs::read_to_string(&drift).unwrap();
    assert!(drift.contains("# body: floating; mass "), "{drift}");
    // Every DOF: 3 frequencies x 2 headings x 3 DOFs; the two methods' horizontal force in
    // the header.
    assert_eq!(rows(&drift, "kR,j,heading,value").len(), 18);
    assert!(
        drift.contains("\n# horizontal force, pressure integration - far field"),
        "{drift}"
    );
    let _ = std::fs::remove_dir_all(&dir);
    for (extra, message) in [
        (
            &["--rao", "-"][..],
            "a floating section needs --mass (or the hull file's <mass>",
        ),
        (
            &["--mass", "1e3", "--cog", "0", "--gyradius", "1"][..],
            "--cog '0': expected X,Y in m",
        ),
        (
            &[
                "--mass",
                "1e3",
                "--cog",
                "0,0",
                "--gyradius",
                "1",
                "--mooring",
                "cb1=3",
            ][..],
            "'cb1' is not a rigid DOF of the section (its rigid DOFs: sway heave roll)",
        ),
        (
            &["--mass", "-1", "--cog", "0,0", "--gyradius", "1"][..],
            "mass is -1: expected a finite mass > 0 kg/m",
        ),
    ] {
        let mut args = vec!["sweep", "semicircle", "--kr", "1:1:1", "-o", "-"];
        args.extend_from_slice(extra);
        let (ok, _, err) = fmu_pack(&args);
        assert!(!ok && err.contains(message), "{extra:?}: {err}");
    }
    let sphere = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data/wamit/sphere.1");
    let (ok, _, err) = fmu_pack(&["sweep", sphere, "-o", "-", "--mass", "1"]);
    assert!(
        !ok && err.contains("an imported database is not a section"),
        "{err}"
    );
}
