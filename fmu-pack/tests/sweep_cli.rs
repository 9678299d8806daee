//! `fmu-pack sweep` from the command line: the CSV of DESIGN.md and clear errors.

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
