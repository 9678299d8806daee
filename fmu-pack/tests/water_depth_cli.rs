//! `fmu-pack sweep --water-depth`: finite depth for sections, its table line, and clear
//! errors for a bad depth, a hull on the bottom and the drift.

mod common;
use common::fmu_pack;

fn sweep(extra: &[&str]) -> (bool, String, String) {
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
        "-o",
        "-",
    ];
    args.extend_from_slice(extra);
    fmu_pack(&args)
}

#[test]
fn the_table_carries_the_water_depth() {
    let (ok, csv, err) = sweep(&["--water-depth", "3"]);
    assert!(ok, "{err}");
    assert!(csv.lines().any(|l| l == "# depth: 3"), "{csv}");
    let (ok, csv, err) = sweep(&["--water-depth", "inf"]);
    assert!(ok, "{err}");
    assert!(csv.lines().any(|l| l == "# depth: inf"), "{csv}");
}

#[test]
fn bad_depths_are_refused_by_name() {
    for bad in ["0", "-2", "nan"] {
        let (ok, _, err) = sweep(&["--water-depth", bad]);
        assert!(!ok);
        assert!(
            err.contains("--water-depth") && err.contains("finite and > 0"),
            "{bad}: {err}"
        );
    }
    let (ok, _, err) = sweep(&["--water-depth", "0.9"]);
    assert!(!ok);
    assert!(err.contains("bottom") && err.contains("keel"), "{err}");
    let (ok, _, err) = sweep(&["--water-depth", "3", "--drift", "-"]);
    assert!(!ok);
    assert!(err.contains("deep water only"), "{err}");
}
