//! `fmu-pack sweep|fit|pack NAME.1`: imported WAMIT databases on the command line (the
//! checked-in WAMIT v7.2 hemisphere, tests/data/wamit/), and clear errors.

use std::path::PathBuf;
use std::process::Command;

fn fmu_pack(args: &[&str]) -> (bool, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_fmu-pack"))
        .args(args)
        .output()
        .expect("run fmu-pack");
    (
        output.status.success(),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

fn sphere() -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/wamit/sphere.1")
        .display()
        .to_string()
}

#[test]
fn sweep_writes_the_whole_body_tables_of_the_database() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-database-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let excitation = dir.join("x.csv");
    let (ok, csv, err) = fmu_pack(&[
        "sweep",
        &sphere(),
        "--dofs",
        "surge,heave,pitch",
        "--excitation",
        excitation.to_str().unwrap(),
        "-o",
        "-",
    ]);
    assert!(ok, "{err}");
    assert!(csv.contains("# modes: surge heave pitch\n# convention: exp(+i omega t)\n# units: SI"));
    // 9 A_inf rows, then 9 per frequency, 7 frequencies.
    let rows: Vec<&str> = csv
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .collect();
    assert_eq!(rows.len(), 9 * 8);
    assert!(rows[..9].iter().all(|r| r.starts_with("inf,")));
    let x = std::fs::read_to_string(&excitation).unwrap();
    assert!(x.lines().any(|l| l.starts_with("omega,j,heading,re,im")));
    // One line on standard error says what was imported.
    assert!(
        err.contains("sphere: 3 DOFs (surge heave pitch), 7 frequencies"),
        "{err}"
    );
}

#[test]
fn fit_reports_and_draws_the_database() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-database-plots-{}", std::process::id()));
    let (ok, out, err) = fmu_pack(&[
        "fit",
        &sphere(),
        "--dofs",
        "heave",
        "--plots",
        dir.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(out.starts_with("database sphere: 1 DOFs (heave)"), "{out}");
    assert!(out.contains("largest error"), "{out}");
    let figure = std::fs::read_to_string(dir.join("fit-heave-heave.svg")).unwrap();
    assert!(figure.contains("database and network") && figure.contains("omega (rad/s)"));
}

#[test]
fn mistakes_are_named() {
    let cases: [(&[&str], &str); 6] = [
        (
            &["sweep", "nowhere/box.1", "-o", "-"],
            "nowhere/box.1: No such file",
        ),
        (
            &["sweep", &sphere(), "--panels", "64", "-o", "-"],
            "--panels does not apply to an imported database",
        ),
        (
            &["sweep", &sphere(), "--frequency-column", "kl", "-o", "-"],
            "--frequency-column 'kl': expected period, omega or hz",
        ),
        (
            &["sweep", &sphere(), "--length-scale=-2", "-o", "-"],
            "--length-scale -2: it must be finite and > 0 m",
        ),
        (
            &["sweep", &sphere(), "--dofs", "heave,wobble", "-o", "-"],
            "--dofs: 'wobble' is not a DOF",
        ),
        (
            &["sweep", "semicircle", "--length-scale", "2", "-o", "-"],
            "--length-scale applies to an imported database",
        ),
    ];
    for (args, expected) in cases {
        let (ok, _, err) = fmu_pack(args);
        assert!(!ok, "{args:?} succeeded");
        assert!(err.contains(expected), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}

#[test]
fn wamit_export_of_a_database_reads_back_to_the_same_table() {
    let dir = std::env::temp_dir().join(format!("hydrofmu-database-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let prefix = dir.join("again");
    let (ok, first, err) = fmu_pack(&[
        "sweep",
        &sphere(),
        "--wamit",
        prefix.to_str().unwrap(),
        "-o",
        "-",
    ]);
    assert!(ok, "{err}");
    for ext in ["1", "3", "hst"] {
        assert!(dir.join(format!("again.{ext}")).is_file(), "again.{ext}");
    }
    let (ok, second, err) = fmu_pack(&["sweep", dir.join("again.1").to_str().unwrap(), "-o", "-"]);
    assert!(ok, "{err}");
    // Every number equal to the 10 digits written (the header names another source).
    let rows = |t: &str| -> Vec<Vec<f64>> {
        t.lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("omega"))
            .map(|l| {
                l.split(',')
                    .map(|x| {
                        if x == "inf" {
                            f64::INFINITY
                        } else {
                            x.parse().unwrap()
                        }
                    })
                    .collect()
            })
            .collect()
    };
    let (a, b) = (rows(&first), rows(&second));
    assert_eq!(a.len(), b.len());
    let scale = a
        .iter()
        .flat_map(|r| r[3..].iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    for (r, s) in a.iter().zip(&b) {
        for (x, y) in r.iter().zip(s) {
            assert!(
                x == y || (x - y).abs() <= 1e-9 * x.abs().max(1e-9 * scale),
                "{r:?} {s:?}"
            );
        }
    }
    // A section has no whole-body tables to write.
    let (ok, _, err) = fmu_pack(&["sweep", "semicircle", "--wamit", "x", "-o", "-"]);
    assert!(
        !ok && err.contains("--wamit applies to ship files and imported databases"),
        "{err}"
    );
}
